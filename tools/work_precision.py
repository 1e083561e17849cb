#!/usr/bin/python3
"""Work-precision study of granhydro's scheme choices: what accuracy costs in time.

Runs ladders of resolutions / time steps for several scheme choices on
reference problems with known answers, records error and cost per run, draws
error-vs-CPU-time diagrams and ranks the choices by the cost of reaching a
target error.

  /usr/bin/python3 tools/work_precision.py --granhydro build/granhydro --out study
  /usr/bin/python3 tools/work_precision.py --quick            # ~2 min smoke version
  /usr/bin/python3 tools/work_precision.py --report-only      # redraw from study/work_precision.csv
  /usr/bin/python3 tools/work_precision.py --self-test        # exact solutions vs published numbers

Problems (references in brackets):
  sod     1D Sod shock tube, ideal-gas (elastic dilute) limit, the physical data of
          parameters/sod_1d.prm with the end time at which it is Toro's nondimensional
          Sod problem at t = 0.2 (the problem of tests/verify/test_riemann.cc)
          [exact Riemann solution: cell averages of a Python port of tests/common/exact_riemann.h].
          L1 error of rho/rho_L per unit length.  Families: reconstruction x flux.
  vortex  2D isentropic vortex (Shu), periodic 10 x 10 box, advected by (1, 1) to t = 1
          (the 2D problem of tests/verify/test_order.cc, nonlinear flux, so the face quadrature
          matters) [exact: the translated vortex, cell averages by 6x6 Gauss points].
          L1 error of rho per unit area from the checkpoint.  Families: reconstruction x
          face quadrature.
  haff    Homogeneous cooling granular gas (1D periodic box of 2 cells, convection off,
          only the implicit source step) [Haff's law T0/(1 + zeta0(T0) t/2)^2, the exact
          solution of the code's own cooling ODE dT/dt = -zeta0(T) T with zeta0 ~ sqrt(T)].
          Relative error of T(t_end).  Families: diffusion-step integrators, ladder of
          'Numerics/Fixed time step'.
  column  parameters/sedimentation_column_1d.prm (granular, gravity, Johnson-Jackson
          closure) to a shorter end time [the finest Gauss-Legendre run of the ladder,
          restricted to each coarse mesh].  L1 error of the packing fraction per unit
          length.  Families: diffusion-step integrators, resolution ladder.

Cost: CPU seconds (user + system) of the granhydro process (differences of
resource.getrusage(RUSAGE_CHILDREN)), the fairer measure on a shared machine; it
includes the start-up (~0.3 s: MPI, scene, mesh), which is not subtracted (it varies
by as much as the coarsest runs' work); runs below --repeat-below seconds are repeated
and the smallest CPU time is kept.

Cross-checks: the Python exact Riemann solver reproduces tests/common/exact_riemann.h bit for
bit (p*, u*, cell averages of Sod, Lax, 123); the vortex error at 40^2 and 80^2 with
tests/verify/test_order.cc's time step reproduces its L1 errors to 4 digits; the Sod L1
errors at 200 cells reproduce `tests/test_riemann --study` for first order and MUSCL;
WENO3/WENO5 and MUSTA-4 differed by 1-10 % because their results then depended on the
internal units (doc/performance.md, "Work-precision study").
Meshes are uniform except in the sod2d problem, which compares uniform and adaptive
meshes.
"""
import argparse
import csv
import math
import os
import resource
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "granhydro_py"))  # tools/granhydro_py: import granhydro
from granhydro.output import find_output_file  # noqa: E402
from granhydro.readers import read_checkpoint, read_profiles, read_summary, select_time  # noqa: E402

# ---------------------------------------------------------------------------
# exact Riemann solver (port of tests/common/exact_riemann.h, Toro ch. 4)
# ---------------------------------------------------------------------------


class ExactRiemann:
    """Exact solution of the 1D Euler Riemann problem for an ideal gas.

    States are (rho, u, p).  Same algorithm as tests/common/exact_riemann.h: pressure
    functions, two-rarefaction formula or Newton from the PVRS / two-shock
    guess, sampling, vacuum generation, cell averages split at every wave.
    """

    def __init__(self, left, right, gamma):
        if not (gamma > 1 and math.isfinite(gamma)):
            raise ValueError("gamma must be > 1")
        for s, side in ((left, "left"), (right, "right")):
            if not (s[0] > 0 and s[2] > 0 and all(math.isfinite(v) for v in s)):
                raise ValueError("invalid %s state %r" % (side, s))
        self.L, self.R, self.g = tuple(left), tuple(right), gamma
        g = gamma
        self.cL = math.sqrt(g * left[2] / left[0])
        self.cR = math.sqrt(g * right[2] / right[0])
        self.vacuum = 2 / (g - 1) * (self.cL + self.cR) <= right[1] - left[1]
        if self.vacuum:
            self.p_star = self.rho_sL = self.rho_sR = 0.0
            self.u_star = float("nan")
            return
        self._solve_p_star()
        self.u_star = 0.5 * (left[1] + right[1]) + 0.5 * (
            self._f(self.p_star, self.R, self.cR)[0] - self._f(self.p_star, self.L, self.cL)[0])
        self.rho_sL = self._rho_star(self.L)
        self.rho_sR = self._rho_star(self.R)

    def _f(self, p, K, cK):
        g = self.g
        if p > K[2]:  # shock
            A, B = 2 / ((g + 1) * K[0]), (g - 1) / (g + 1) * K[2]
            q = math.sqrt(A / (p + B))
            return (p - K[2]) * q, q * (1 - 0.5 * (p - K[2]) / (p + B))
        r = (p / K[2]) ** ((g - 1) / (2 * g))  # rarefaction
        return 2 * cK / (g - 1) * (r - 1), r / (K[0] * cK) * (K[2] / p)

    def _solve_p_star(self):
        L, R, g = self.L, self.R, self.g
        du = R[1] - L[1]
        pmin, pmax = min(L[2], R[2]), max(L[2], R[2])
        eps = sys.float_info.epsilon
        if self._f(pmin, L, self.cL)[0] + self._f(pmin, R, self.cR)[0] + du >= 0:
            z = (g - 1) / (2 * g)  # two rarefactions: exact formula
            self.p_star = ((self.cL + self.cR - 0.5 * (g - 1) * du) /
                           (self.cL / L[2] ** z + self.cR / R[2] ** z)) ** (1 / z)
            return
        ppv = 0.5 * (L[2] + R[2]) - 0.125 * du * (L[0] + R[0]) * (self.cL + self.cR)
        if pmax / pmin <= 2 and pmin <= ppv <= pmax:
            p = ppv
        else:
            p0, G6 = max(ppv, pmin), (g - 1) / (g + 1)
            gL = math.sqrt(2 / ((g + 1) * L[0]) / (p0 + G6 * L[2]))
            gR = math.sqrt(2 / ((g + 1) * R[0]) / (p0 + G6 * R[2]))
            p = (gL * L[2] + gR * R[2] - du) / (gL + gR)
        p = max(p, pmin)
        for it in range(100):
            fL, dL = self._f(p, L, self.cL)
            fR, dR = self._f(p, R, self.cR)
            F = fL + fR + du
            if abs(F) <= 16 * eps * (abs(fL) + abs(fR) + abs(du)):
                break
            p_new = max(p - F / (dL + dR), pmin)
            change = 2 * abs(p_new - p) / (p_new + p)
            p = p_new
            if change < 1e-14:
                break
            if it == 99:
                raise RuntimeError("exact Riemann: Newton for p* did not converge")
        self.p_star = p

    def _rho_star(self, K):
        r, G6 = self.p_star / K[2], (self.g - 1) / (self.g + 1)
        if self.p_star > K[2]:
            return K[0] * (r + G6) / (G6 * r + 1)
        return K[0] * r ** (1 / self.g)

    def _sample_left(self, xi):
        G, L, cL = self.g, self.L, self.cL
        if not self.vacuum and self.p_star > L[2]:
            sL = L[1] - cL * math.sqrt((G + 1) / (2 * G) * self.p_star / L[2] + (G - 1) / (2 * G))
            return L if xi <= sL else (self.rho_sL, self.u_star, self.p_star)
        head = L[1] - cL
        tail = (L[1] + 2 * cL / (G - 1) if self.vacuum
                else self.u_star - cL * (self.p_star / L[2]) ** ((G - 1) / (2 * G)))
        if xi <= head:
            return L
        if xi >= tail:
            return (self.rho_sL, self.u_star, self.p_star)
        c = 2 / (G + 1) + (G - 1) / ((G + 1) * cL) * (L[1] - xi)
        return (L[0] * c ** (2 / (G - 1)), 2 / (G + 1) * (cL + 0.5 * (G - 1) * L[1] + xi),
                L[2] * c ** (2 * G / (G - 1)))

    def _sample_right(self, xi):
        G, R, cR = self.g, self.R, self.cR
        if not self.vacuum and self.p_star > R[2]:
            sR = R[1] + cR * math.sqrt((G + 1) / (2 * G) * self.p_star / R[2] + (G - 1) / (2 * G))
            return R if xi >= sR else (self.rho_sR, self.u_star, self.p_star)
        head = R[1] + cR
        tail = (R[1] - 2 * cR / (G - 1) if self.vacuum
                else self.u_star + cR * (self.p_star / R[2]) ** ((G - 1) / (2 * G)))
        if xi >= head:
            return R
        if xi <= tail:
            return (self.rho_sR, self.u_star, self.p_star)
        c = 2 / (G + 1) - (G - 1) / ((G + 1) * cR) * (R[1] - xi)
        return (R[0] * c ** (2 / (G - 1)), 2 / (G + 1) * (-cR + 0.5 * (G - 1) * R[1] + xi),
                R[2] * c ** (2 * G / (G - 1)))

    def sample(self, xi):
        """(rho, u, p) at xi = (x - x0)/t."""
        if self.vacuum:
            G = self.g
            sL = self.L[1] + 2 * self.cL / (G - 1)
            sR = self.R[1] - 2 * self.cR / (G - 1)
            if xi <= sL:
                return self._sample_left(xi)
            if xi >= sR:
                return self._sample_right(xi)
            return (0.0, xi, 0.0)
        return self._sample_left(xi) if xi <= self.u_star else self._sample_right(xi)

    def fans(self):
        G, z = self.g, (self.g - 1) / (2 * self.g)
        L, R = self.L, self.R
        r = []
        if self.vacuum or self.p_star <= L[2]:
            r.append((L[1] - self.cL, L[1] + 2 * self.cL / (G - 1) if self.vacuum
                      else self.u_star - self.cL * (self.p_star / L[2]) ** z))
        if self.vacuum or self.p_star <= R[2]:
            r.append((R[1] - 2 * self.cR / (G - 1) if self.vacuum
                      else self.u_star + self.cR * (self.p_star / R[2]) ** z, R[1] + self.cR))
        return r

    def wave_speeds(self):
        G, z = self.g, (self.g - 1) / (2 * self.g)
        s = [v for f in self.fans() for v in f]
        if self.vacuum:
            return s
        s.append(self.u_star)
        if self.p_star > self.L[2]:
            s.append(self.L[1] - self.cL * math.sqrt((G + 1) / (2 * G) * self.p_star / self.L[2] + z))
        if self.p_star > self.R[2]:
            s.append(self.R[1] + self.cR * math.sqrt((G + 1) / (2 * G) * self.p_star / self.R[2] + z))
        return s

    _XG = (0.0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640, 0.9061798459386640)
    _WG = (0.5688888888888889, 0.4786286704993665, 0.4786286704993665,
           0.2369268850561891, 0.2369268850561891)

    def cell_average(self, a, b, x0, t, n_sub=64):
        """Averages over [a, b] of (rho, rho u, E) at time t (discontinuity at x0)."""
        if not (b > a and t > 0 and n_sub > 0):
            raise ValueError("cell_average: need b > a, t > 0, n_sub > 0")
        pts = [a, b] + [x0 + s * t for s in self.wave_speeds() if a < x0 + s * t < b]
        pts.sort()
        fans = self.fans()
        g = self.g
        out = [0.0, 0.0, 0.0]
        for i in range(len(pts) - 1):
            if not pts[i + 1] > pts[i]:
                continue
            xm = (0.5 * (pts[i] + pts[i + 1]) - x0) / t
            fan = any(f[0] < xm < f[1] for f in fans)
            n = n_sub if fan else 1
            h = (pts[i + 1] - pts[i]) / n
            for k in range(n):
                m = pts[i] + (k + 0.5) * h
                for xq, wq in zip(self._XG, self._WG):
                    rho, u, p = self.sample((m + 0.5 * h * xq - x0) / t)
                    w = 0.5 * h * wq
                    out[0] += w * rho
                    out[1] += w * rho * u
                    out[2] += w * (p / (g - 1) + 0.5 * rho * u * u)
        return [v / (b - a) for v in out]


# ---------------------------------------------------------------------------
# physics needed by the references (doc/physics.md sections 2, 3)
# ---------------------------------------------------------------------------

def torquato_chi(phi, phi_f=0.49, phi_c=0.64, delta=1e-3):
    """Torquato's pair correlation at contact with the C1 guard (doc/physics.md 2)."""
    def pole(x):
        if x <= phi_f:
            return (1 - x / 2) / (1 - x) ** 3, (2.5 - x) / (1 - x) ** 4
        chi_f = (1 - phi_f / 2) / (1 - phi_f) ** 3
        return chi_f * (phi_c - phi_f) / (phi_c - x), chi_f * (phi_c - phi_f) / (phi_c - x) ** 2
    pmax = phi_c - delta
    if phi > pmax:
        c, dc = pole(pmax)
        return c + dc * (phi - pmax)
    return pole(phi)[0]


def haff_rates(phi, eps, T, sigma, rho_s):
    """(zeta0, nu0) [1/s] of Garzo-Dufty (1999), doc/physics.md 3.1-3.5."""
    m = rho_s * math.pi * sigma ** 3 / 6
    a = eps
    cstar = 32 * (1 - a) * (1 - 2 * a * a) / (81 - 17 * a + 30 * a * a * (1 - a))
    chi = torquato_chi(phi)
    zeta0 = 8 / math.sqrt(math.pi) * (1 - a * a) * (1 + 3 * cstar / 32) * phi * chi * math.sqrt(T / m) / sigma
    nu0 = 96 / 5 * (phi / sigma) * math.sqrt(T / (math.pi * m))
    return zeta0, nu0


def haff_temperature(T0, zeta0_T0, t):
    """Haff's law T0 / (1 + zeta0(T0) t / 2)^2 (doc/physics.md 6(a))."""
    return T0 / (1 + zeta0_T0 * t / 2) ** 2


# ---------------------------------------------------------------------------
# isentropic vortex (tests/verify/test_order.cc, 2D): box [0, 10]^2, advected by (1, 1)
# ---------------------------------------------------------------------------
VORTEX_L, VORTEX_BETA, VORTEX_GAMMA, VORTEX_T_END = 10.0, 5.0, 5.0 / 3.0, 1.0


def vortex_density(x, y, t):
    """Exact density of the periodic vortex (sum over the 3 x 3 nearest images, as
    tests/verify/test_order.cc; the overlap of images is below 1e-13).  numpy arrays in."""
    import numpy as np
    L, b, g = VORTEX_L, VORTEX_BETA, VORTEX_GAMMA
    dT = np.zeros_like(x)
    for i in (-1, 0, 1):
        for j in (-1, 0, 1):
            y0 = x - L / 2 - t + L * i
            y1 = y - L / 2 - t + L * j
            dT += -(g - 1) * b * b / (8 * g * math.pi ** 2) * np.exp(1 - (y0 * y0 + y1 * y1))
    # the exact solution is periodic: wrap the advected position into the box first
    return (1 + dT) ** (1 / (g - 1))


def vortex_cell_averages(N, t, nq=6):
    """Exact cell averages of the density on the N x N mesh (nq x nq Gauss points)."""
    import numpy as np
    xg, wg = np.polynomial.legendre.leggauss(nq)
    h = VORTEX_L / N
    c = (np.arange(N) + 0.5) * h
    avg = np.zeros((N, N))  # [j (y), i (x)]
    for a, wa in zip(xg, wg):
        for b, wb in zip(xg, wg):
            X = c[None, :] + 0.5 * h * a
            Y = c[:, None] + 0.5 * h * b
            # periodic: evaluate at the position moved back by the advection, wrapped
            Xw = np.mod(X - t, VORTEX_L) + t
            Yw = np.mod(Y - t, VORTEX_L) + t
            avg += 0.25 * wa * wb * vortex_density(Xw + 0 * Y, Yw + 0 * X, t)
    return avg


def vortex_expressions():
    """muParser expressions (x, y) for packing fraction, velocity and temperature of the
    vortex at t = 0 in units sigma = 1 m, m = 1 kg (rho_s = 6/pi), V0 = 1 m/s, where
    n = rho, T [J] = p/n and phi = pi/6 rho."""
    L, b, g = VORTEX_L, VORTEX_BETA, VORTEX_GAMMA
    f_terms, ux, uy, dT = [], [], [], []
    for i in (-1, 0, 1):
        for j in (-1, 0, 1):
            sx = "(x-%g)" % (L / 2 - L * i)
            sy = "(y-%g)" % (L / 2 - L * j)
            r2 = "(%s^2+%s^2)" % (sx, sy)
            f = "%.17g*exp(0.5*(1-%s))" % (b / (2 * math.pi), r2)
            ux.append("-%s*%s" % (f, sy))
            uy.append("%s*%s" % (f, sx))
            dT.append("%.17g*exp(1-%s)" % ((g - 1) * b * b / (8 * g * math.pi ** 2), r2))
    T = "(1-(" + "+".join(dT) + "))"
    phi = "%.17g*%s^%.17g" % (math.pi / 6, T, 1 / (g - 1))
    vel = "1+" + "+".join(ux) + "; 1+" + "+".join(uy)
    return phi, vel, T


# ---------------------------------------------------------------------------
# scenes
# ---------------------------------------------------------------------------
SIGMA, RHO_S = 1e-3, 2600.0
GRAIN_MASS = RHO_S * math.pi * SIGMA ** 3 / 6

# Sod: parameters/sod_1d.prm (phi 0.01 | 0.00125, T 1e-8 | 8e-9 J, 0.2 m) is Toro's Sod
# problem (1, 0, 1 | 0.125, 0, 0.1) in units rho_L, length 0.2 m and sqrt(p_L/rho_L) =
# sqrt(T_L/m); its end time is chosen as nondimensional t = 0.2 (tests/verify/test_riemann.cc).
SOD_LENGTH, SOD_PHI_L, SOD_T_L = 0.2, 0.01, 1e-8
SOD_T_END = 0.2 * SOD_LENGTH / math.sqrt(SOD_T_L / GRAIN_MASS)

# Haff: the densest, most inelastic case of tests/verify/test_haff.cc (phi 0.5, eps 0.7; zeta0(T0)
# t_end = 13); 1000 cells (all equal) so that the cost per step is measurable
HAFF_PHI, HAFF_EPS, HAFF_T0, HAFF_CELLS = 0.5, 0.7, 1e-8, 1000
HAFF_ZETA0, HAFF_NU0 = haff_rates(HAFF_PHI, HAFF_EPS, HAFF_T0, SIGMA, RHO_S)
HAFF_T_END = 10 / HAFF_NU0

COLUMN_T_END = 0.08  # the floor layer passes phi_min = 0.5 of the closure at ~0.07 s


def sod2d_scene(base, levels, rundir):
    """Sod (gamma 5/3, t = 0.2) along the diagonal of the unit square, units sigma = m = V0 =
    1 (rho = n): uniform base^2 (levels = 0) or adaptive base^2 + levels (jumps of n and p,
    refine 0.2, coarsen 0.05, buffer 1, every 4 steps; tests/verify/test_amr.cc's settings)."""
    return """# Sod along the diagonal (tests/verify/test_amr.cc sod 2), work-precision study
set Dimension = 2
subsection Domain
  set Lower corner = 0, 0
  set Upper corner = 1, 1
  set Cells = %d, %d
  set Boundary x- = outflow
  set Boundary x+ = outflow
  set Boundary y- = outflow
  set Boundary y+ = outflow
end
subsection Material
  set Model = ideal gas
  set Grain diameter = 1
  set Material density = %.17g
  set Adiabatic index = %.17g
end
subsection Initial state
  set Packing fraction = %.17g*(0.125 + 0.875*((x+y) < 1))
  set Temperature = 0.8 + 0.2*((x+y) < 1)
  set Velocity = 0; 0
  set Quadrature points = 3
end
subsection Numerics
  set Reference velocity = 1
end
subsection Adaptivity
  set Maximum level = %d
  set Refine threshold = 0.2
  set Coarsen threshold = 0.05
  set Buffer = 1
  set Interval = 4
end
subsection Time
  set End time = 0.2
end
""" % (base, base, 6 / math.pi, 5.0 / 3.0, math.pi / 6, levels) + output_block(rundir, False, True)


_SOD2D_EXACT = None


def sod2d_error(rundir, base, levels):
    """L1 density error per unit area against the exact solution along the diagonal (3x3
    Gauss averages per cell), and the number of cells at the end."""
    import numpy as np
    global _SOD2D_EXACT
    if _SOD2D_EXACT is None:
        _SOD2D_EXACT = ExactRiemann((1.0, 0.0, 1.0), (0.125, 0.0, 0.1), 5.0 / 3.0)
    c = read_checkpoint(os.path.join(rundir, "solution.checkpoint"))
    if abs(c["time_scaled"] - 0.2) > 1e-12:
        raise RuntimeError("checkpoint is not the end state (t = 0.2)")
    nf = base << levels
    key = c["key"]
    lev = key & 7
    fk = key >> 3
    i, j = fk % nf, fk // nf
    h = 1.0 / (base * (1 << lev))
    x0, y0 = i / nf, j / nf
    g = np.array([-math.sqrt(0.6), 0.0, math.sqrt(0.6)])
    w = np.array([5.0, 8.0, 5.0]) / 18.0
    xi0 = math.sqrt(2.0) / 2
    avg = np.zeros(len(key))  # exact cell averages
    for a in range(3):
        for b in range(3):
            x = x0 + h * (0.5 + 0.5 * g[a])
            y = y0 + h * (0.5 + 0.5 * g[b])
            xi = ((x + y) / math.sqrt(2.0) - xi0) / 0.2
            avg += w[a] * w[b] * np.array([_SOD2D_EXACT.sample(v)[0] for v in xi])
    return float(np.sum(np.abs(c["U"][:, 0] - avg) * h * h)), len(key)


def output_block(rundir, profiles, checkpoint):
    return ("subsection Output\n  set Directory = %s\n  set Interval = 0\n  set Write VTU = false\n"
            "  set Write profiles = %s\n  set Write checkpoint = %s\n  set Write summary = true\n"
            "  set Verbose = false\nend\n" % (rundir, str(profiles).lower(), str(checkpoint).lower()))


def sod_scene(cells, rec, flux, stages, rundir):
    return """# Sod (ideal-gas limit of parameters/sod_1d.prm), work-precision study
set Dimension = 1
subsection Domain
  set Lower corner = 0
  set Upper corner = %.17g
  set Cells = %d
  set Boundary x- = outflow
  set Boundary x+ = outflow
end
subsection Material
  set Model = ideal gas
  set Grain diameter = %g
  set Material density = %g
end
subsection Initial state
  set Packing fraction = if(x < %.17g, 0.01, 0.00125)
  set Velocity = 0
  set Temperature = if(x < %.17g, 1e-8, 8e-9)
  set Quadrature points = 1
end
subsection Numerics
  set Reconstruction = %s
  set Flux = %s
  set MUSTA maximum stages = %d
  set CFL number = 0.4
end
subsection Time
  set End time = %.17g
end
""" % (SOD_LENGTH, cells, SIGMA, RHO_S, SOD_LENGTH / 2, SOD_LENGTH / 2, rec, flux, stages,
       SOD_T_END) + output_block(rundir, True, False)


def vortex_scene(N, rec, quad, rundir):
    phi, vel, T = vortex_expressions()
    return """# 2D isentropic vortex (tests/verify/test_order.cc), units sigma = 1 m, m = 1 kg, V0 = 1 m/s
set Dimension = 2
subsection Domain
  set Lower corner = 0, 0
  set Upper corner = %g, %g
  set Cells = %d, %d
  set Boundary x- = periodic
  set Boundary x+ = periodic
  set Boundary y- = periodic
  set Boundary y+ = periodic
end
subsection Material
  set Model = ideal gas
  set Grain diameter = 1
  set Material density = %.17g
  set Adiabatic index = %.17g
end
subsection Initial state
  set Packing fraction = %s
  set Velocity = %s
  set Temperature = %s
  set Quadrature points = 6
end
subsection Numerics
  set Reconstruction = %s
  set Face quadrature = %s
  set Flux = musta
  set CFL number = 0.4
  set Reference velocity = 1
end
subsection Time
  set End time = %g
end
""" % (VORTEX_L, VORTEX_L, N, N, 6 / math.pi, VORTEX_GAMMA, phi, vel, T, rec, quad,
       VORTEX_T_END) + output_block(rundir, False, True)


def haff_scene(integrator, steps, rundir):
    return """# Haff's law: homogeneous cooling, 1D periodic, implicit source step only
set Dimension = 1
subsection Domain
  set Lower corner = 0
  set Upper corner = %g
  set Cells = %d
  set Boundary x- = periodic
  set Boundary x+ = periodic
end
subsection Material
  set Model = granular
  set Grain diameter = %g
  set Material density = %g
  set Restitution coefficient = %g
end
subsection Effects
  set Convection = false
end
subsection Initial state
  set Packing fraction = %g
  set Velocity = 0
  set Temperature = %g
  set Quadrature points = 1
end
subsection Numerics
  set Fixed time step = %.17g
end
subsection Diffusion step
  set Integrator = %s
  set Newton tolerance = 1e-13
end
subsection Time
  set End time = %.17g
end
""" % (HAFF_CELLS * SIGMA, HAFF_CELLS, SIGMA, RHO_S, HAFF_EPS, HAFF_PHI, HAFF_T0,
       HAFF_T_END / steps, integrator, HAFF_T_END) + output_block(rundir, False, True)


def column_scene(cells, integrator, rundir, repo):
    """parameters/sedimentation_column_1d.prm with another mesh, integrator, end time."""
    path = os.path.join(repo, "parameters", "sedimentation_column_1d.prm")
    out, skip = [], False
    with open(path) as f:
        for line in f:
            s = line.strip()
            if s == "subsection Output":
                skip = True
            if not skip:
                if s.startswith("set Cells"):
                    line = "  set Cells = %d\n" % cells
                elif s.startswith("set End time"):
                    line = "  set End time = %g\n" % COLUMN_T_END
                out.append(line)
            elif s == "end":
                skip = False
    return ("".join(out) + "subsection Diffusion step\n  set Integrator = %s\nend\n" % integrator +
            output_block(rundir, True, False))


# ---------------------------------------------------------------------------
# reading results
# ---------------------------------------------------------------------------

def read_last_profile(rundir):
    """Last block of the run's <Base name>_profiles.csv: (time, columns dict of lists)."""
    columns, times = read_profiles(rundir)
    last = select_time(columns, times[-1])
    return float(times[-1]), {h: c.tolist() for h, c in last.items()}


# ---------------------------------------------------------------------------
# errors against the references
# ---------------------------------------------------------------------------
_SOD_EXACT_CACHE = {}


def sod_exact_averages(cells):
    """Exact cell averages of rho/rho_L on `cells` cells of the unit interval at t = 0.2."""
    if cells not in _SOD_EXACT_CACHE:
        ex = ExactRiemann((1.0, 0.0, 1.0), (0.125, 0.0, 0.1), 5.0 / 3.0)
        h = 1.0 / cells
        _SOD_EXACT_CACHE[cells] = [ex.cell_average(i * h, (i + 1) * h, 0.5, 0.2)[0]
                                   for i in range(cells)]
    return _SOD_EXACT_CACHE[cells]


def sod_error(rundir, cells):
    t, prof = read_last_profile(rundir)
    if abs(t - SOD_T_END) > 1e-9 * SOD_T_END:
        raise RuntimeError("profiles end at t = %g s, not %g s" % (t, SOD_T_END))
    rho = [p / SOD_PHI_L for p in prof["packing_fraction"]]
    ex = sod_exact_averages(cells)
    return sum(abs(a - b) for a, b in zip(rho, ex)) / cells


def vortex_error(rundir, N):
    import numpy as np
    c = read_checkpoint(os.path.join(rundir, "solution.checkpoint"))
    if abs(c["time_scaled"] - VORTEX_T_END) > 1e-12 or tuple(c["cells"][:2]) != (N, N):
        raise RuntimeError("checkpoint is not the end state of the %d^2 run" % N)
    if not (c["length"] == 1 and c["mass"] == 1 and c["velocity"] == 1):
        raise RuntimeError("vortex checkpoint not in units sigma = m = V0 = 1")
    order = np.argsort(c["key"])
    rho = c["U"][order, 0].reshape(N, N)  # key = i + N j: rows are y
    return float(np.abs(rho - vortex_cell_averages(N, VORTEX_T_END)).mean())


def haff_error(rundir):
    import numpy as np
    c = read_checkpoint(os.path.join(rundir, "solution.checkpoint"))
    t = c["time_scaled"] * c["length"] / c["velocity"]
    if abs(t - HAFF_T_END) > 1e-9 * HAFF_T_END:
        raise RuntimeError("checkpoint at t = %g s, not %g s" % (t, HAFF_T_END))
    U = c["U"]
    # scaled units: T / (m V0^2) = (2/3) (E - |nu|^2 / (2 n)) / n
    T = (2.0 / 3.0) * (U[:, 2] - 0.5 * U[:, 1] ** 2 / U[:, 0]) / U[:, 0] * c["mass"] * c["velocity"] ** 2
    exact = haff_temperature(HAFF_T0, HAFF_ZETA0, HAFF_T_END)
    return float(np.max(np.abs(T - exact)) / exact)


def column_profile(rundir):
    t, prof = read_last_profile(rundir)
    if abs(t - COLUMN_T_END) > 1e-9:
        raise RuntimeError("profiles end at t = %g s, not %g s" % (t, COLUMN_T_END))
    return prof["packing_fraction"]


def restrict(fine, cells):
    r = len(fine) // cells
    if r * cells != len(fine):
        raise RuntimeError("reference mesh %d is not a multiple of %d" % (len(fine), cells))
    return [sum(fine[i * r:(i + 1) * r]) / r for i in range(cells)]


# ---------------------------------------------------------------------------
# running
# ---------------------------------------------------------------------------
FIELDS = ["problem", "family", "cells", "dt_s", "cfl", "error", "error_measure", "reference",
          "status", "cpu_seconds", "repeats", "wall_seconds_child",
          "wall_seconds_loop", "steps", "rejected_steps", "newton_iterations",
          "gmres_iterations", "newton_failures", "switches_to_midpoint", "explicit_substeps",
          "rkl2_steps", "rkl2_stages", "min_dt_s", "max_dt_s", "min_explicit_dt_s", "max_dt_over_explicit",
          "musta_stages_per_point", "first_order_fallbacks"]


class Runner:
    def __init__(self, exe, out, timeout, verbose=True):
        self.exe, self.out, self.timeout, self.verbose = exe, out, timeout, verbose
        self.startup = None

    def run(self, name, scene_text):
        """Runs one scene in out/runs/<name>; returns (status, cpu, wall, rundir)."""
        rundir = os.path.abspath(os.path.join(self.out, "runs", name))
        if os.path.isdir(rundir):
            shutil.rmtree(rundir)
        os.makedirs(rundir)
        scene_text = scene_text.replace("@RUNDIR@", rundir)
        prm = os.path.join(rundir, "scene.prm")
        with open(prm, "w") as f:
            f.write(scene_text)
        env = dict(os.environ, OMP_NUM_THREADS="1", DEAL_II_NUM_THREADS="1")
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        w0 = time.perf_counter()
        with open(os.path.join(rundir, "run.log"), "w") as log:
            try:
                p = subprocess.run([self.exe, prm], stdout=log, stderr=subprocess.STDOUT,
                                   cwd=rundir, env=env, timeout=self.timeout)
                status = "ok" if p.returncode == 0 else "failed (exit %d)" % p.returncode
            except subprocess.TimeoutExpired:
                status = "timeout (%g s)" % self.timeout
        wall = time.perf_counter() - w0
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (r1.ru_utime + r1.ru_stime) - (r0.ru_utime + r0.ru_stime)
        if status != "ok":
            with open(os.path.join(rundir, "run.log")) as f:
                tail = f.read().strip().splitlines()[-2:]
            status += ": " + " ".join(tail)[:300]
        return status, cpu, wall, rundir

    def measure_startup(self):
        """CPU seconds of a run that does nothing but start: MPI, scene, mesh, one
        step of a 10-cell ideal gas (the minimum of 5). Shown in the diagrams as the
        floor of every run's cost; not subtracted (on a shared machine it varies by
        +-0.05 s, as much as the whole work of the coarsest runs)."""
        best = float("inf")
        for k in range(5):
            text = sod_scene(10, "first order", "rusanov", 1, "@RUNDIR@").replace(
                "  set End time", "  set Maximum steps = 1\n  set End time")
            status, cpu, _, rundir = self.run("startup", text)
            if status != "ok":
                raise RuntimeError("%s does not run a scene: %s" % (self.exe, status))
            if find_output_file(rundir, "summary", required=False) is None:
                raise RuntimeError("%s wrote no *_summary.csv: is it granhydro (with "
                                   "Output/Write summary)?" % self.exe)
            best = min(best, cpu)
        self.startup = best
        return best


def summary_fields(s):
    g = lambda k: s.get(k, "")
    pts = s.get("flux_points", 0) or 0
    return {"wall_seconds_loop": g("wall_seconds"), "steps": int(g("steps") or 0),
            "rejected_steps": int(g("rejected_steps") or 0),
            "newton_iterations": int(g("newton_iterations") or 0),
            "gmres_iterations": int(g("gmres_iterations") or 0),
            "newton_failures": int(g("newton_failures") or 0),
            "switches_to_midpoint": int(g("switches_to_midpoint") or 0),
            "rkl2_steps": int(g("rkl2_steps") or 0), "rkl2_stages": int(g("rkl2_stages") or 0),
            "explicit_substeps": int(g("explicit_substeps") or 0),
            "min_dt_s": g("min_dt"), "max_dt_s": g("max_dt"),
            "min_explicit_dt_s": g("min_explicit_dt"),
            "max_dt_over_explicit": g("max_dt_over_explicit"),
            "musta_stages_per_point": (s.get("musta_stages", 0) / pts) if pts else "",
            "first_order_fallbacks": int(g("first_order_fallbacks") or 0)}


# ---------------------------------------------------------------------------
# the study: problems, families, ladders
# ---------------------------------------------------------------------------
INTEGRATORS = ["gauss-legendre", "implicit midpoint", "sdirk2", "rkl2", "cost-based", "automatic",
               "explicit euler"]


def study_plan(quick):
    """list of (problem, family, ladder value, scene builder args)."""
    plan = []
    # --- Sod: reconstruction x flux (MUSTA with 1 stage = FORCE, 2, 4 stages)
    fluxes = [("rusanov", "rusanov", 1), ("hll", "hll", 1), ("force", "musta", 1),
              ("musta-4", "musta", 4)]
    if quick:
        sod_cells = [100, 200, 400]
        fams = [("first order", "rusanov", "rusanov", 1), ("muscl", "hll", "hll", 1),
                ("weno5", "force", "musta", 1), ("weno5", "musta-4", "musta", 4)]
    else:
        sod_cells = [100, 200, 400, 800, 1600, 3200]
        fams = [(r, lab, f, s) for r in ["first order", "muscl", "weno3", "weno5"]
                for lab, f, s in fluxes]
        fams.append(("weno5", "musta-2", "musta", 2))
    for rec, lab, flux, st in fams:
        for c in sod_cells:
            plan.append(("sod", "%s + %s" % (rec, lab), c, ("sod", c, rec, flux, st)))
    # --- vortex: reconstruction x face quadrature (MUSTA-4 flux)
    if quick:
        vN = [16, 32, 64]
        vf = [("weno5", "gauss"), ("weno5", "midpoint"), ("muscl", "midpoint")]
    else:
        vN = [16, 32, 64, 128]
        vf = [("weno5", "gauss"), ("weno5", "midpoint"), ("weno3", "gauss"),
              ("weno3", "midpoint"), ("muscl", "gauss"), ("muscl", "midpoint"),
              ("first order", "midpoint")]
    for rec, q in vf:
        for N in vN:
            plan.append(("vortex", "%s + %s" % (rec, q), N, ("vortex", N, rec, q)))
    # --- Sod along the diagonal of the unit square: uniform vs adaptive mesh (WENO5 + Gauss
    # + MUSTA); ladder value = cells per direction at the finest level
    s2 = [32, 64, 128] if quick else [32, 64, 128, 256]
    for n in s2:
        plan.append(("sod2d", "uniform mesh", n, ("sod2d", n, 0)))
    for n in s2[1:]:
        plan.append(("sod2d", "adaptive, 2 levels", n, ("sod2d", n // 4, 2)))
        plan.append(("sod2d", "adaptive, 1 level", n, ("sod2d", n // 2, 1)))
    # --- Haff: integrators x fixed time step (steps per t_end)
    hsteps = [8, 32, 128] if quick else [4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048]
    for integ in INTEGRATORS:
        for s in hsteps:
            if integ == "explicit euler" and s < 8:
                continue  # zeta0 dt > 2: forward Euler drives T < 0 (halved, retried)
            plan.append(("haff", integ, s, ("haff", integ, s)))
    # --- sedimentation column: integrators x resolution; the finest Gauss-Legendre
    # run is the reference and runs first
    ccells = [25, 50, 100] if quick else [50, 100, 200, 400, 800]
    cref = 200 if quick else 3200
    plan.append(("column", "gauss-legendre", cref, ("column", cref, "gauss-legendre")))
    for integ in INTEGRATORS:
        for c in ccells:
            plan.append(("column", integ, c, ("column", c, integ)))
    return plan, cref


def build_scene(args, repo):
    kind = args[0]
    if kind == "sod":
        return sod_scene(args[1], args[2], args[3], args[4], "@RUNDIR@")
    if kind == "vortex":
        return vortex_scene(args[1], args[2], args[3], "@RUNDIR@")
    if kind == "haff":
        return haff_scene(args[1], args[2], "@RUNDIR@")
    if kind == "sod2d":
        return sod2d_scene(args[1], args[2], "@RUNDIR@")
    return column_scene(args[1], args[2], "@RUNDIR@", repo)


def slug(*parts):
    return "_".join(str(p).replace(" ", "-").replace("+", "").replace("--", "-") for p in parts)


def run_study(opts, repo):
    os.makedirs(opts.out, exist_ok=True)
    plan, cref = study_plan(opts.quick)
    plan = [p for p in plan if p[0] in opts.problems]
    runner = Runner(opts.granhydro, opts.out, opts.timeout)
    t_start = time.perf_counter()
    startup = runner.measure_startup()
    print("start-up CPU time of granhydro (one-step run): %.3f s" % startup,
          flush=True)
    csv_path = os.path.join(opts.out, "work_precision.csv")
    rows = []
    column_ref = None
    for k, (problem, family, value, args) in enumerate(plan):
        name = slug(problem, family, value)
        scene = build_scene(args, repo)
        status, cpu, wall, rundir = runner.run(name, scene)
        repeats = 1
        # cheap runs: CPU time on a shared machine is noisy at the 0.01-0.05 s level;
        # repeat them and keep the cheapest (the results are deterministic)
        while status == "ok" and cpu < opts.repeat_below and repeats < 3:
            st2, cpu2, wall2, _ = runner.run(name + "_repeat", scene)
            repeats += 1
            if st2 == "ok" and cpu2 < cpu:
                cpu, wall = cpu2, wall2
        shutil.rmtree(os.path.join(opts.out, "runs", name + "_repeat"), ignore_errors=True)
        row = {f: "" for f in FIELDS}
        row.update(problem=problem, family=family, status=status, cpu_seconds="%.4f" % cpu,
                   repeats=repeats,
                   wall_seconds_child="%.4f" % wall)
        if problem == "haff":
            row.update(cells=HAFF_CELLS, dt_s="%.6g" % (HAFF_T_END / value))
        else:
            row.update(cells=value * value if problem in ("vortex", "sod2d") else value, cfl=0.4)
        err = float("nan")
        try:
            if find_output_file(rundir, "summary", required=False):
                row.update(summary_fields(read_summary(rundir, numbers=True)))
            if status == "ok":
                if problem == "sod":
                    err = sod_error(rundir, value)
                    row.update(error_measure="L1(rho/rho_L) per unit length at t=0.2 (Toro units)",
                               reference="exact Riemann solution (cell averages)")
                elif problem == "vortex":
                    err = vortex_error(rundir, value)
                    row.update(error_measure="L1(rho) per unit area at t=1",
                               reference="exact translated vortex (6x6 Gauss cell averages)")
                elif problem == "sod2d":
                    err, ncells = sod2d_error(rundir, args[1], args[2])
                    row.update(cells=ncells,
                               error_measure="L1(rho) per unit area at t=0.2",
                               reference="exact Riemann solution along the diagonal (3x3 Gauss)")
                elif problem == "haff":
                    err = haff_error(rundir)
                    row.update(error_measure="max |T - T_Haff| / T_Haff at t_end = 10/nu0",
                               reference="Haff's law (exact for the code's cooling ODE)")
                else:
                    prof = column_profile(rundir)
                    if value == cref and family == "gauss-legendre" and column_ref is None:
                        column_ref = prof
                        row.update(status="reference", error_measure="",
                                   reference="this run is the reference")
                    else:
                        if column_ref is None:
                            raise RuntimeError("the reference run failed")
                        ref = restrict(column_ref, value)
                        err = sum(abs(a - b) for a, b in zip(prof, ref)) / value
                        row.update(error_measure="L1(phi) per unit height at t=%g s" % COLUMN_T_END,
                                   reference="gauss-legendre, %d cells (restricted)" % cref)
        except Exception as e:  # a result that cannot be read is a failed run
            row["status"] = "error: %s" % e
        row["error"] = "" if math.isnan(err) else "%.6e" % err
        rows.append(row)
        with open(csv_path, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=FIELDS)
            w.writeheader()
            w.writerows(rows)
        print("[%3d/%d] %-7s %-26s %6s  error %-12s cpu %7.2f s  %s" % (
            k + 1, len(plan), problem, family, value, row["error"] or "-", cpu,
            row["status"][:60]), flush=True)
        if not opts.keep_runs and row["status"] in ("ok", "reference"):
            for fn in os.listdir(rundir):
                if fn.endswith(".checkpoint"):
                    os.remove(os.path.join(rundir, fn))
    shutil.rmtree(os.path.join(opts.out, "runs", "startup"), ignore_errors=True)
    total = time.perf_counter() - t_start
    print("study: %d runs in %.0f s wall" % (len(rows), total), flush=True)
    return csv_path, total, startup


# ---------------------------------------------------------------------------
# diagrams and ranking
# ---------------------------------------------------------------------------
TITLES = {
    "sod": "Sod shock tube (1D, ideal-gas limit) vs exact Riemann solution",
    "vortex": "2D isentropic vortex (periodic, t = 1) vs exact solution",
    "sod2d": "Sod along the diagonal of the unit square (2D, t = 0.2): uniform vs adaptive mesh",
    "haff": "Haff's law (homogeneous cooling, phi 0.5, eps 0.7): integrators",
    "column": "1D sedimentation column (closure on, t = %g s) vs finest GL run" % COLUMN_T_END,
}
YLABEL = {
    "sod": "L1 error of rho/rho_L", "vortex": "L1 error of rho", "sod2d": "L1 error of rho",
    "haff": "relative error of T(t_end)", "column": "L1 error of packing fraction",
}
LADDER = {"sod": "cells", "vortex": "cells", "sod2d": "cells", "haff": "dt_s", "column": "cells"}


def load_rows(csv_path):
    with open(csv_path) as f:
        return list(csv.DictReader(f))


def families(rows, problem):
    """{family: [(cost, error, row)] in ladder order (coarse to fine)}, ok runs only."""
    fam = {}
    for r in rows:
        if r["problem"] != problem:
            continue
        fam.setdefault(r["family"], [])
        if r["status"] == "ok" and r["error"]:
            fam[r["family"]].append((float(r["cpu_seconds"]), float(r["error"]), r))
    lad = LADDER[problem]
    sign = -1 if lad == "dt_s" else 1
    for v in fam.values():
        v.sort(key=lambda t: sign * float(t[2][lad]))
    return fam


def cost_to_reach(curve, target):
    """CPU cost at which the family first reaches `target` along its ladder: log-log
    interpolation between the last run above and the first run at or below the
    target; None if never reached."""
    prev = None
    for cost, err, _ in curve:
        if err <= target:
            if prev is None or prev[1] <= target or err <= 0:
                return cost
            lc0, le0, lc1, le1 = math.log(prev[0]), math.log(prev[1]), math.log(cost), math.log(err)
            s = (math.log(target) - le0) / (le1 - le0)
            return math.exp(lc0 + s * (lc1 - lc0))
        prev = (cost, err)
    return None


def target_levels(fams, n=4):
    """Up to n round error levels (1, 2, 5 x 10^k) between the error every family
    reaches and the smallest error any family reaches, log-spaced."""
    curves = [c for c in fams.values() if c]
    if not curves:
        return []
    hi = min(max(e for _, e, _ in c) for c in curves)  # every family starts above
    hi = max(hi, sorted(min(e for _, e, _ in c) for c in curves)[len(curves) // 2])
    lo = min(min(e for _, e, _ in c) for c in curves)
    cands = [m * 10.0 ** k for k in range(-16, 3) for m in (1, 2, 5)]
    cands = [c for c in cands if lo * 1.0001 <= c <= hi]
    if len(cands) > n:
        idx = [round(i * (len(cands) - 1) / (n - 1)) for i in range(n)]
        cands = [cands[i] for i in sorted(set(idx))]
    return sorted(cands, reverse=True)


def plot_problem(rows, problem, out, startup=0.0):
    """Left: error vs CPU cost (the work-precision diagram); right: error vs the
    ladder parameter (cells or time step), which shows the orders."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fams = families(rows, problem)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 5.8), gridspec_kw={"width_ratios": [1.35, 1]})
    names = sorted(fams)
    cmap = plt.get_cmap("tab20" if len(names) > 10 else "tab10")
    markers = "osD^v<>pPX*h"
    lad = LADDER[problem]
    rec_color = {"first order": "tab:gray", "muscl": "tab:blue", "weno3": "tab:green",
                 "weno5": "tab:red"}
    flux_style = {"rusanov": (":", "v"), "hll": ("-.", "s"), "force": ("--", "o"),
                  "musta-4": ("-", "D"), "musta-2": ("-", "x")}
    integ_style = {"gauss-legendre": ("tab:green", "-", "D", 6), "automatic": ("black", ":", "o", 9),
                   "implicit midpoint": ("tab:blue", "-", "s", 6),
                   "explicit euler": ("tab:orange", "-", "^", 6),
                   "sdirk2": ("tab:red", "-", "v", 6), "rkl2": ("tab:purple", "-", "P", 6),
                   "cost-based": ("tab:brown", "--", "x", 8)}
    for i, name in enumerate(names):
        c = fams[name]
        if not c:
            continue
        style = dict(marker=markers[i % len(markers)], color=cmap(i % cmap.N), ms=5)
        ls = "-"
        if problem == "sod2d":
            style["color"] = {"uniform mesh": "black", "adaptive, 1 level": "tab:blue",
                              "adaptive, 2 levels": "tab:red"}.get(name, style["color"])
            ls = "--" if name == "uniform mesh" else "-"
        elif problem in ("sod", "vortex"):
            rec, var = name.split(" + ")
            style["color"] = rec_color.get(rec, style["color"])
            if problem == "sod":
                ls, style["marker"] = flux_style.get(var, ("-", "o"))
                if var == "musta-2":
                    style["color"] = "darkred"
            else:
                ls = "--" if var == "midpoint" else "-"
                style["marker"] = "o" if var == "midpoint" else "D"
        else:
            col, ls, mk, ms = integ_style.get(name, (style["color"], "-", "o", 5))
            style.update(color=col, marker=mk, ms=ms)
            if name == "automatic":  # identical to gauss-legendre unless Newton fails
                style.update(markerfacecolor="none")
        ax.loglog([p[0] for p in c], [p[1] for p in c], ls, label=name, **style)
        pts = sorted((float(p[2][lad]), p[1]) for p in c)
        bx.loglog([p[0] for p in pts], [p[1] for p in pts], ls, **style)
    if startup:
        ax.axvline(startup, color="k", lw=0.8, alpha=0.5)
        ax.text(startup, ax.get_ylim()[0], " start-up", rotation=90, va="bottom", fontsize=7,
                alpha=0.7)
    ax.set_xlabel("CPU seconds of the granhydro process (getrusage of the child)")
    ax.set_ylabel(YLABEL[problem])
    ax.set_title("work-precision: " + TITLES[problem], fontsize=9)
    bx.set_xlabel({"cells": "cells", "dt_s": "time step [s]"}[lad])
    bx.set_title("error vs %s" % ("cells" if lad == "cells" else "time step"), fontsize=9)
    for a in (ax, bx):
        a.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7 if len(names) > 8 else 8, ncol=2 if len(names) > 8 else 1)
    fig.tight_layout()
    path = os.path.join(out, "work_precision_%s.png" % problem)
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return path


def fmt(x, p=3):
    return "%.*g" % (p, x) if isinstance(x, float) else str(x)


def markdown(rows, out, info):
    startup = float(info.get("startup", 0) or 0)
    L = ["# Work-precision study", "",
         "Written by `tools/work_precision.py` (%s; %s runs, %s s of wall time on a shared "
         "2-core machine). Cost = CPU seconds (user + system) of the granhydro process, from "
         "getrusage(RUSAGE_CHILDREN); runs below 1 s were repeated up to 3 times and the "
         "smallest time kept. Every run includes the start-up (MPI, scene, mesh): a one-step "
         "run costs %.2f s, so costs below about %.1f s are start-up dominated and their "
         "ranking is a tie within noise (marked *). Meshes are uniform except in the 2D diagonal "
         "Sod problem, which compares uniform and adaptive meshes (same finest resolution)." % (
             info.get("mode", "?"), info.get("runs", "?"), info.get("wall", "?"), startup,
             2 * startup), ""]
    for problem in ["sod", "vortex", "sod2d", "haff", "column"]:
        fams = families(rows, problem)
        if not fams:
            continue
        prow = [r for r in rows if r["problem"] == problem]
        L += ["## %s" % TITLES[problem], ""]
        meas = next((r["error_measure"] for r in prow if r["error_measure"]), "")
        ref = next((r["reference"] for r in prow if r["reference"] and r["status"] == "ok"), "")
        mesh = ("uniform vs adaptive (p4est octree; 'adaptive, k levels' has the uniform "
                "mesh's finest resolution with Domain/Cells divided by 2^k; cells = at the end)"
                if problem == "sod2d" else "uniform")
        L += ["Error: %s. Reference: %s. Mesh: %s." % (meas, ref, mesh), "",
              "![%s](work_precision_%s.png)" % (problem, problem), ""]
        levels = target_levels(fams)
        if levels:
            L += ["Cheapest choice to reach each error level (CPU s, log-log interpolation "
                  "along each family's runs; '-' = not reached on this ladder):", ""]
            L += ["| error <= | 1st | 2nd | 3rd | not reached |", "| --- | --- | --- | --- | --- |"]
            for lev in levels:
                costs = [(cost_to_reach(c, lev), f) for f, c in fams.items()]
                ok = sorted((c, f) for c, f in costs if c is not None)
                miss = sorted(f for c, f in costs if c is None)
                tie = lambda c: "*" if c < 2 * startup else ""
                cells = ["%s (%s s%s)" % (f, fmt(c), tie(c)) for c, f in ok[:3]] + \
                    ["-"] * (3 - len(ok[:3]))
                L.append("| %s | %s | %s |" % (fmt(lev, 2), " | ".join(cells),
                                               ", ".join(miss) if miss else ""))
            L += [""]
            L += ["Full ranking at each level (CPU s):", ""]
            fnames = sorted(fams)
            L += ["| family | " + " | ".join("<= %s" % fmt(l, 2) for l in levels) + " |",
                  "| --- |" + " --- |" * len(levels)]
            for f in fnames:
                L.append("| %s | %s |" % (f, " | ".join(
                    (fmt(c) if c is not None else "-") for c in
                    (cost_to_reach(fams[f], l) for l in levels))))
            L += [""]
        lad = LADDER[problem]
        L += ["Raw numbers:", "",
              "| family | %s | error | CPU s | steps | max dt [s] | Newton | GMRES | "
              "expl. substeps | max dt / expl. limit | status |" % ("dt [s]" if lad == "dt_s" else "cells"),
              "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
        for r in prow:
            L.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                r["family"], r[lad], r["error"] or "-", r["cpu_seconds"], r["steps"],
                fmt(float(r["max_dt_s"])) if r["max_dt_s"] else "-", r["newton_iterations"], r["gmres_iterations"], r["explicit_substeps"],
                fmt(float(r["max_dt_over_explicit"])) if r["max_dt_over_explicit"] else "-",
                r["status"].replace("|", "/")))
        L += [""]
    path = os.path.join(out, "work_precision.md")
    with open(path, "w") as f:
        f.write("\n".join(L))
    return path


def report(out):
    csv_path = os.path.join(out, "work_precision.csv")
    rows = load_rows(csv_path)
    info = {}
    ip = os.path.join(out, "work_precision_info.csv")
    if os.path.exists(ip):
        with open(ip) as f:
            info = {r[0]: r[1] for r in csv.reader(f) if len(r) == 2}
    startup = float(info.get("startup", 0) or 0)
    pngs = [plot_problem(rows, p, out, startup) for p in ["sod", "vortex", "sod2d", "haff", "column"]
            if any(r["problem"] == p for r in rows)]
    md = markdown(rows, out, info)
    return pngs, md


# ---------------------------------------------------------------------------
# self-test of the references and the command line
# ---------------------------------------------------------------------------

def self_test():
    """The exact solutions against published numbers (doc/physics.md 6, Toro's tables)."""
    ok = True

    def check(what, got, want, rel):
        nonlocal ok
        good = abs(got - want) <= rel * abs(want)
        ok = ok and good
        print("  %s  %s = %.9g (expected %.9g)" % ("ok  " if good else "FAIL", what, got, want))
    s = ExactRiemann((1, 0, 1), (0.125, 0, 0.1), 5 / 3)
    check("Sod gamma 5/3 p*", s.p_star, 0.293945, 2e-6)
    check("Sod gamma 5/3 u*", s.u_star, 0.841195, 2e-6)
    check("Sod gamma 5/3 rho*_L", s.rho_sL, 0.479689, 2e-6)
    check("Sod gamma 5/3 rho*_R", s.rho_sR, 0.229806, 2e-6)
    s = ExactRiemann((1, 0, 1), (0.125, 0, 0.1), 1.4)
    check("Sod gamma 1.4 p* (Toro)", s.p_star, 0.30313, 2e-5)
    check("Sod gamma 1.4 u* (Toro)", s.u_star, 0.92745, 2e-5)
    s = ExactRiemann((1, 0, 1000), (1, 0, 0.01), 1.4)
    check("Toro test 3 p*", s.p_star, 460.894, 2e-6)
    s = ExactRiemann((5.99924, 19.5975, 460.894), (5.99242, -6.19633, 46.095), 1.4)
    check("Toro test 5 p* (table rounded)", s.p_star, 1691.64, 5e-6)
    # conservation of the cell averages: the total mass of Sod at t = 0.2 is 0.5625
    m = sum(sod_exact_averages(200)) / 200
    check("Sod mass of the cell averages", m, 0.5625, 1e-13)
    z, nu = haff_rates(0.1, 0.9, 1e-8, 1e-3, 2600)
    check("zeta0(phi 0.1, eps 0.9, T 1e-8 J)", z, 9.551937, 1e-6)
    check("Haff T(0.1 s)", haff_temperature(1e-8, z, 0.1), 4.580238e-9, 1e-6)
    check("Haff T(1 s)", haff_temperature(1e-8, z, 1.0), 2.997439e-10, 1e-6)
    check("chi(0.639) (guard)", torquato_chi(0.639), 853.744, 1e-6)
    return ok


def parse_args(argv, repo):
    p = argparse.ArgumentParser(
        prog="work_precision.py",
        description="Work-precision study of granhydro's scheme choices.")
    p.add_argument("--granhydro", default=os.path.join(repo, "build", "granhydro"),
                   help="the granhydro executable (default: build/granhydro of this checkout)")
    p.add_argument("--out", default="study", help="output directory (default: study)")
    p.add_argument("--quick", action="store_true", help="a ~2-minute smoke version")
    p.add_argument("--problems", default="sod,vortex,sod2d,haff,column",
                   help="comma-separated subset of sod, vortex, haff, column")
    p.add_argument("--timeout", type=float, default=900.0,
                   help="wall-clock limit per run in seconds (default 900)")
    p.add_argument("--repeat-below", type=float, default=None,
                   help="repeat runs cheaper than this many CPU seconds (up to 3 times in "
                        "all) and keep the smallest CPU time (default 1.0, with --quick 0; "
                        "0 = never)")
    p.add_argument("--keep-runs", action="store_true",
                   help="keep the checkpoints in OUT/runs (removed by default)")
    p.add_argument("--report-only", action="store_true",
                   help="no runs: redraw diagrams and table from OUT/work_precision.csv")
    p.add_argument("--self-test", action="store_true",
                   help="check the exact solutions against published numbers and exit")
    o = p.parse_args(argv)
    o.problems = [s.strip() for s in o.problems.split(",") if s.strip()]
    bad = [s for s in o.problems if s not in ("sod", "vortex", "sod2d", "haff", "column")]
    if bad or not o.problems:
        p.error("--problems: unknown problem(s) %s (allowed: sod, vortex, sod2d, haff, column)" %
                ", ".join(repr(b) for b in bad) if bad else "--problems: empty list")
    if o.repeat_below is None:
        o.repeat_below = 0.0 if o.quick else 1.0
    if not (o.repeat_below >= 0):
        p.error("--repeat-below must be >= 0")
    if not (o.timeout > 0):
        p.error("--timeout must be positive")
    if o.report_only:
        if not os.path.isfile(os.path.join(o.out, "work_precision.csv")):
            p.error("--report-only: %s has no work_precision.csv (run the study first)" % o.out)
    elif not o.self_test:
        if not os.path.isfile(o.granhydro):
            p.error("--granhydro: no such file '%s' (build it: cmake --build build --target "
                    "granhydro)" % o.granhydro)
        if not os.access(o.granhydro, os.X_OK):
            p.error("--granhydro: '%s' is not executable" % o.granhydro)
        o.granhydro = os.path.abspath(o.granhydro)
    if os.path.exists(o.out) and not os.path.isdir(o.out):
        p.error("--out: '%s' exists and is not a directory" % o.out)
    return o


def main(argv=None):
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    opts = parse_args(sys.argv[1:] if argv is None else argv, repo)
    if opts.self_test:
        return 0 if self_test() else 1
    try:
        import numpy  # noqa: F401
        import matplotlib  # noqa: F401
    except ImportError as e:
        print("work_precision.py: error: needs numpy and matplotlib (%s); use /usr/bin/python3 "
              "with python3-numpy and python3-matplotlib" % e, file=sys.stderr)
        return 2
    if not opts.report_only:
        if not self_test():
            print("work_precision.py: error: the exact solutions fail their self-test",
                  file=sys.stderr)
            return 1
        try:
            csv_path, total, startup = run_study(opts, repo)
        except RuntimeError as e:
            print("work_precision.py: error: %s" % e, file=sys.stderr)
            return 3
        rows = load_rows(csv_path)
        # the cheapest complete run bounds the start-up cost from above
        startup = min([startup] + [float(r["cpu_seconds"]) for r in rows if r["cpu_seconds"]])
        with open(os.path.join(opts.out, "work_precision_info.csv"), "w") as f:
            f.write("key,value\nmode,%s\nruns,%d\nwall,%.0f\nstartup,%.4f\n" % (
                "--quick" if opts.quick else "default", len(rows), total,
                startup))
    pngs, md = report(opts.out)
    print("wrote %s, %s" % (md, ", ".join(pngs)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
