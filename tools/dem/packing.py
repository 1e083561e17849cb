"""Initial grain positions and velocities for a layered granhydro initial state.

Grain counts per layer: the scene's packing fraction phi(h) is averaged over each
profile bin (Gauss-Legendre, 8 points), times the bin volume over the grain volume;
the counts are rounded cumulatively so that the total is the rounded integral.
Every grain's centre lies inside its bin (and at least a radius from walls).

Placement, per bin:
  * phi_bin <= rsa_max (default 0.30): random sequential addition (RSA): uniform
    random trial centres in the bin, rejected on overlap with any grain already
    placed, up to 500 trials per grain;
  * denser bins, and any grain RSA could not place: a uniform random centre in the
    bin, overlaps allowed; then all grains are relaxed by pairwise push-apart
    iterations (each overlapping pair is moved apart by its overlap plus 1e-3 d,
    half to each grain; centres stay in their bins and clear of the walls) until no
    pair is closer than d. RSA itself jams at phi ~ 0.38 (and becomes slow well
    before), so dense layers (the bouncing bed's phi = 0.5) come from the relaxation:
    a random, not an equilibrium hard-sphere structure (no fluid-like pair
    correlations are built), which the DEM forgets within a few collision times.
Velocities: Maxwellian, mean the scene's velocity (plus the container velocity
ds/dt(0) for a vibrated scene: the scene's velocity is in the container frame),
variance T/m per component at the grain's height. Spin: zero.
"""

import numpy as np


def gauss_bin_average(f, edges, npts=8):
    xg, wg = np.polynomial.legendre.leggauss(npts)
    a, b = edges[:-1], edges[1:]
    pts = 0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * xg[None, :]
    vals = f(pts.ravel()).reshape(pts.shape)
    return 0.5 * (vals * wg[None, :]).sum(axis=1)


def bin_counts(phi_bin, bin_volume, grain_volume):
    c = np.cumsum(phi_bin * bin_volume / grain_volume)
    r = np.rint(np.concatenate([[0.0], c])).astype(int)
    return np.diff(r)


def find_pairs(pos, lo, hi, periodic, cutoff):
    """All pairs i < j closer than cutoff (minimum image in periodic directions).
    Returns I, J, displacement pos[J] - pos[I] (minimum image), distance."""
    n = len(pos)
    if n < 2:
        e = np.zeros(0, int)
        return e, e, np.zeros((0, 3)), np.zeros(0)
    L = hi - lo
    nc = np.maximum(1, np.floor(L / cutoff).astype(int))
    cell = np.clip(np.floor((pos - lo) / L * nc).astype(int), 0, nc - 1)
    key = (cell[:, 0] * nc[1] + cell[:, 1]) * nc[2] + cell[:, 2]
    order = np.argsort(key, kind="stable")
    ncell = int(nc.prod())
    count = np.bincount(key, minlength=ncell)
    start = np.concatenate([[0], np.cumsum(count)[:-1]])
    Is, Js = [], []
    offs = np.array([(a, b, c) for a in (-1, 0, 1) for b in (-1, 0, 1) for c in (-1, 0, 1)])
    for o in offs:
        nb = cell + o
        ok = np.ones(n, bool)
        for d in range(3):
            if periodic[d]:
                nb[:, d] %= nc[d]
            else:
                ok &= (nb[:, d] >= 0) & (nb[:, d] < nc[d])
        nkey = (nb[:, 0] * nc[1] + nb[:, 1]) * nc[2] + nb[:, 2]
        idx = np.nonzero(ok)[0]
        if len(idx) == 0:
            continue
        nkey = nkey[idx]
        cnt = count[nkey]
        I = np.repeat(idx, cnt)
        first = np.repeat(start[nkey], cnt)
        within = np.arange(len(I)) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        J = order[first + within]
        m = I < J
        Is.append(I[m])
        Js.append(J[m])
    I = np.concatenate(Is)
    J = np.concatenate(Js)
    # the same neighbour cell can be reached by two offsets when a direction has < 3 cells
    u = np.unique(I.astype(np.int64) * n + J)
    I, J = (u // n).astype(int), (u % n).astype(int)
    dx = pos[J] - pos[I]
    for d in range(3):
        if periodic[d]:
            dx[:, d] -= L[d] * np.rint(dx[:, d] / L[d])
    r = np.sqrt((dx * dx).sum(axis=1))
    m = r < cutoff
    return I[m], J[m], dx[m], r[m]


class Box:
    """The DEM box at t = 0 (container frame): lo, hi (3,), periodic (3 bools)."""

    def __init__(self, lo, hi, periodic):
        self.lo = np.asarray(lo, float)
        self.hi = np.asarray(hi, float)
        self.periodic = list(periodic)


def place(rng, box, pd, edges, counts, d, rsa_max, phi_bin, log=print):
    """Grain centres (N, 3) with counts[i] centres in bin i along direction pd."""
    R = 0.5 * d
    lo = box.lo.copy()
    hi = box.hi.copy()
    clo, chi = lo.copy(), hi.copy()  # allowed centre ranges (walls: a radius inside)
    for k in range(3):
        if not box.periodic[k]:
            clo[k] += R
            chi[k] -= R
    N = int(counts.sum())
    pos = np.zeros((N, 3))
    wlo = np.zeros(N)
    whi = np.zeros(N)
    # per-grain window along pd
    k = 0
    for i, c in enumerate(counts):
        a = max(edges[i], clo[pd])
        b = min(edges[i + 1], chi[pd])
        if c > 0 and b < a:
            raise ValueError("bin %d [%g, %g] cannot hold a grain centre clear of the wall" % (i, edges[i], edges[i + 1]))
        wlo[k:k + c] = a
        whi[k:k + c] = b
        k += c
    L = hi - lo
    # RSA on a hash grid
    cs = d
    nc = np.maximum(1, np.floor(L / cs).astype(int))
    grid = {}

    def cell_of(p):
        return tuple(np.clip(np.floor((p - lo) / L * nc).astype(int), 0, nc - 1))

    def overlaps(p):
        c = cell_of(p)
        for a in (-1, 0, 1):
            for b in (-1, 0, 1):
                for e in (-1, 0, 1):
                    q = [c[0] + a, c[1] + b, c[2] + e]
                    ok = True
                    for m in range(3):
                        if box.periodic[m]:
                            q[m] %= nc[m]
                        elif q[m] < 0 or q[m] >= nc[m]:
                            ok = False
                    if not ok:
                        continue
                    for j in grid.get(tuple(q), ()):
                        dx = pos[j] - p
                        for m in range(3):
                            if box.periodic[m]:
                                dx[m] -= L[m] * round(dx[m] / L[m])
                        if dx @ dx < d * d:
                            return True
        return False

    placed = np.zeros(N, bool)
    k = 0
    n_rsa = 0
    for i, c in enumerate(counts):
        if phi_bin[i] <= rsa_max:
            for g in range(k, k + c):
                for _ in range(500):
                    p = clo + rng.random(3) * (chi - clo)
                    p[pd] = wlo[g] + rng.random() * (whi[g] - wlo[g])
                    if not overlaps(p):
                        pos[g] = p
                        placed[g] = True
                        grid.setdefault(cell_of(p), []).append(g)
                        n_rsa += 1
                        break
        k += c
    rest = np.nonzero(~placed)[0]
    for g in rest:
        p = clo + rng.random(3) * (chi - clo)
        p[pd] = wlo[g] + rng.random() * (whi[g] - wlo[g])
        pos[g] = p
    info = {"grains": N, "rsa_placed": n_rsa, "relaxed_from_random": int(len(rest)),
            "relaxation_iterations": 0}
    if len(rest):
        it = relax(pos, box, clo, chi, pd, wlo, whi, d, log=log)
        info["relaxation_iterations"] = it
    return pos, info


def relax(pos, box, clo, chi, pd, wlo, whi, d, max_iter=20000, log=print):
    target = d * (1 + 1e-3)
    L = box.hi - box.lo
    for it in range(1, max_iter + 1):
        I, J, dx, r = find_pairs(pos, box.lo, box.hi, box.periodic, d)
        if len(I) == 0:
            return it - 1
        r = np.maximum(r, 1e-12 * d)
        push = (0.5 * (target - r) / r)[:, None] * dx
        disp = np.zeros_like(pos)
        np.add.at(disp, J, push)
        np.add.at(disp, I, -push)
        pos += disp
        for k in range(3):
            if box.periodic[k]:
                pos[:, k] = box.lo[k] + np.mod(pos[:, k] - box.lo[k], L[k])
            elif k != pd:
                np.clip(pos[:, k], clo[k], chi[k], out=pos[:, k])
        np.clip(pos[:, pd], wlo, whi, out=pos[:, pd])
        if it % 500 == 0:
            log("  relaxation: iteration %d, %d overlapping pairs, largest overlap %.3g d"
                % (it, len(I), (d - r.min()) / d))
    raise RuntimeError("the overlap removal did not converge in %d iterations: the layers are "
                       "too dense for a random packing (phi close to or above ~0.6?)" % max_iter)


def maxwellian(rng, scene, pos, frame_velocity):
    m = scene.grain_mass
    pd = scene.profile_direction
    lat = [0.5 * (scene.lower[k] + scene.upper[k]) for k in range(3)]
    h = pos[:, pd]
    xyz = [np.full_like(h, lat[k]) for k in range(3)]
    xyz[pd] = h
    T = scene.temp_expr(*xyz)
    if np.any(T < 0):
        raise ValueError("negative initial temperature")
    u = np.stack([e(*xyz) for e in scene.vel_expr], axis=1)
    v = u + np.sqrt(T / m)[:, None] * rng.standard_normal(pos.shape)
    v[:, scene.vib_direction] += frame_velocity
    return v
