#!/usr/bin/env python3
"""
Generate tests/data/gd99_reference.csv from an independent Python
implementation of the Garzo-Dufty formulas, gd99_reference.py (written apart
from the C++ code, from the same equations: doc/physics.md section 7; it is
not part of this repository), loaded with importlib from its path -- nothing
is copied. Standard library only. The committed CSV is what the unit test
reads; this script is only needed to regenerate it.

Usage:  python3 make_gd99_reference.py [path/to/gd99_reference.py] [output.csv]
Defaults: $GD99_REFERENCE for the reference, and gd99_reference.csv next
to this script.

Rows (column "kind"):
  table        the 18 (phi, eps) states of doc/physics.md section 7, all values
               from gd99_reference.gd99();
  extra        further gd99() states: eps = 0.5 (mu* < 0 in dense states,
               doc/physics.md P5), states on the pole branch close to phi_max and
               on the linear continuation beyond phi_max (doc/physics.md 2, guard);
  closed_form  doc/physics.md 3.7: eps = 1 Enskog closed forms for eta*, kappa*,
               gamma* (evaluated here from the closed-form expressions, with
               the reference chi), and the dilute inelastic limit phi = 0
               (chi = 1) with the Brey et al. forms of kappa* and mu*; SI
               columns are "nan" for phi = 0 (n = 0).

Every number is written with 17 significant digits.
"""

import importlib.util
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REF = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("GD99_REFERENCE")
if not REF or not os.path.isfile(REF):
    sys.exit("make_gd99_reference: give the path of gd99_reference.py as the first argument "
             "or in $GD99_REFERENCE")
OUT = sys.argv[2] if len(sys.argv) > 2 else os.path.join(HERE, "gd99_reference.csv")

spec = importlib.util.spec_from_file_location("gd99_reference", REF)
ref = importlib.util.module_from_spec(spec)
spec.loader.exec_module(ref)

SIGMA, RHO_S, T = 1.0e-3, 2600.0, 1.0e-8       # doc/physics.md section 7
PI = math.pi

COLUMNS = ["kind", "phi", "eps", "sigma", "rho_s", "T",
           "c_star", "chi", "dchi_dphi", "Z", "dZ_dphi",
           "eta_star", "gamma_star", "kappa_star", "mu_star", "zeta_star", "zeta_U_full",
           "p", "eta", "gamma", "kappa", "mu", "zeta", "c"]


def fmt(x):
    if isinstance(x, str):
        return x
    if x != x:
        return "nan"
    return "%.16e" % x      # 17 significant digits


def row_from_gd99(kind, phi, eps):
    r = ref.gd99(phi, T, eps, SIGMA, RHO_S, with_zeta_u=True)
    dZ = 2.0 * (1.0 + eps) * (r["chi"] + phi * r["dchi"])
    return dict(kind=kind, phi=phi, eps=eps, sigma=SIGMA, rho_s=RHO_S, T=T,
                c_star=r["c_star"], chi=r["chi"], dchi_dphi=r["dchi"], Z=r["Z"], dZ_dphi=dZ,
                eta_star=r["eta_star"], gamma_star=r["gamma_star"], kappa_star=r["kappa_star"],
                mu_star=r["mu_star"], zeta_star=r["zeta_star"], zeta_U_full=r["zeta_U"],
                p=r["p"], eta=r["eta"], gamma=r["gamma"], kappa=r["kappa"], mu=r["mu"],
                zeta=r["zeta"], c=r["c_sound"])


def row_enskog_closed(phi):
    """doc/physics.md 3.7, eps = 1 (c* = 0, zeta = mu = 0)."""
    row = row_from_gd99("closed_form", phi, 1.0)
    chi = row["chi"]
    row["eta_star"] = (1.0 + 1.6 * phi * chi) ** 2 / chi + 768.0 / (25.0 * PI) * phi ** 2 * chi
    row["kappa_star"] = (1.0 + 2.4 * phi * chi) ** 2 / chi + 512.0 / (25.0 * PI) * phi ** 2 * chi
    row["gamma_star"] = 256.0 / (5.0 * PI) * phi ** 2 * chi
    row["Z"] = 1.0 + 4.0 * phi * chi
    row["mu_star"] = row["zeta_star"] = row["zeta_U_full"] = 0.0
    return row


def row_dilute_inelastic(eps):
    """doc/physics.md 3.7, phi = 0 (chi = 1): Brey et al. forms of kappa*, mu*."""
    a = eps
    cs = ref.c_star(a)
    chi, dchi = ref.chi_torquato(0.0)          # 1, 5/2
    zeta = 5.0 / 12.0 * (1.0 - a * a) * (1.0 + 3.0 * cs / 32.0)
    nu_eta = (1.0 - 0.25 * (1.0 - a) ** 2) * (1.0 - cs / 64.0)
    nu_kap = (1.0 + a) / 3.0 * (1.0 + 33.0 / 16.0 * (1.0 - a) + (19.0 - 3.0 * a) / 1024.0 * cs)
    kappa = 2.0 / 3.0 * (1.0 + cs) / (nu_kap - 2.0 * zeta)
    mu = 2.0 * zeta * (kappa + cs / (3.0 * zeta)) / (2.0 * nu_kap - 3.0 * zeta)
    nan = float("nan")
    return dict(kind="closed_form", phi=0.0, eps=eps, sigma=SIGMA, rho_s=RHO_S, T=T,
                c_star=cs, chi=chi, dchi_dphi=dchi, Z=1.0, dZ_dphi=2.0 * (1.0 + a) * chi,
                eta_star=1.0 / (nu_eta - 0.5 * zeta), gamma_star=0.0, kappa_star=kappa,
                mu_star=mu, zeta_star=zeta, zeta_U_full=0.0,
                p=nan, eta=nan, gamma=nan, kappa=nan, mu=nan, zeta=nan, c=nan)


def main():
    rows = []
    for phi in (0.01, 0.1, 0.3, 0.5, 0.6, 0.63):          # doc/physics.md section 7
        for eps in (1.0, 0.9, 0.7):
            rows.append(row_from_gd99("table", phi, eps))
    for phi in (1e-8, 0.05, 0.2, 0.45, 0.49, 0.55, 0.62, 0.635, 0.6385, 0.639):
        for eps in (0.5, 0.8, 0.99):
            rows.append(row_from_gd99("extra", phi, eps))
    # on the linear continuation beyond phi_max (guard); the gd99() formulas
    # only see chi and dchi, so they hold there unchanged
    for phi in (0.6392, 0.6395, 0.64, 0.65):
        for eps in (1.0, 0.9, 0.7, 0.5):
            rows.append(row_from_gd99("extra", phi, eps))
    for phi in (1e-8, 0.01, 0.1, 0.3, 0.5, 0.6, 0.63, 0.6395):
        rows.append(row_enskog_closed(phi))
    for eps in (0.5, 0.7, 0.9, 0.99):
        rows.append(row_dilute_inelastic(eps))

    with open(OUT, "w") as f:
        f.write("# generated by tests/data/make_gd99_reference.py from %s -- do not edit\n"
                % os.path.basename(REF))
        f.write("# sigma [m], rho_s [kg/m^3], T [J]; SI: p [Pa], eta, gamma [Pa s], "
                "kappa [1/(m s)], mu [J m^2/s], zeta [1/s], c [m/s]\n")
        f.write(",".join(COLUMNS) + "\n")
        for r in rows:
            f.write(",".join(fmt(r[c]) for c in COLUMNS) + "\n")
    print("wrote %d rows to %s" % (len(rows), OUT))


if __name__ == "__main__":
    main()
