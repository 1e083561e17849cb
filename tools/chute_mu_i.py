#!/usr/bin/python3
"""Compare a steady chute flow with the mu(I) rheology of glass beads.

Reads the profiles (<Base name>_profiles.csv, profile direction normal to the base) of a
laterally uniform chute run such as parameters/frictional_chute.prm and compares the
down-slope velocity at the last output (or --time) with the Bagnold profile of the local
mu(I) rheology (Jop, Forterre & Pouliquen, Nature 441, 727 (2006)) for glass beads:

    mu(I) = mu_s + (mu_2 - mu_s) / (I_0 / I + 1),  mu_s = tan 20.9 deg, mu_2 = tan 32.76 deg,
    I_0 = 0.279;  steady uniform flow of depth h at slope theta:  I = I_theta with
    mu(I_theta) = tan theta, and
    u(z) = (2/3) I_theta sqrt(phi g cos theta) / d (h^1.5 - (h - z)^1.5),
    surface speed u_s = (2/3) I_theta sqrt(phi g cos theta) h^1.5 / d.

Below the arrest angle (tan theta <= mu_s) the layer is at rest. h is taken from the run:
the mass per area divided by phi * rho_s (phi = the mean packing fraction of the layers
with phi > 0.3); the surface speed of the run is its largest down-slope velocity among
those layers. Prints both speeds and their ratio; --plot draws the two profiles.

    /usr/bin/python3 tools/chute_mu_i.py OUTPUT_DIR [--base NAME] [--slope DEG]
        [--diameter 1e-3] [--time T] [--plot out.png]

Debian: apt-get install python3-numpy python3-matplotlib
"""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "granhydro_py"))  # tools/granhydro_py: import granhydro
from granhydro.output import OutputFileError, add_base_option, find_output_file  # noqa: E402
from granhydro.readers import read_profiles, select_time  # noqa: E402

MU_S, MU_2, I_0 = math.tan(math.radians(20.9)), math.tan(math.radians(32.76)), 0.279


def inertial_number(slope_deg):
    """I_theta of a steady uniform flow at the slope, 0 at or below the arrest angle."""
    t = math.tan(math.radians(slope_deg))
    if t <= MU_S:
        return 0.0
    if t >= MU_2:
        raise ValueError(f"slope {slope_deg} deg: tan theta >= mu_2, no steady mu(I) flow")
    return I_0 * (t - MU_S) / (MU_2 - t)


def bagnold(z, h, phi, slope_deg, d, g=9.81):
    i = inertial_number(slope_deg)
    c = (2.0 / 3.0) * i * math.sqrt(phi * g * math.cos(math.radians(slope_deg))) / d
    zz = np.clip(z, 0, h)
    return c * (h ** 1.5 - (h - zz) ** 1.5)


def layer(path, time):
    columns, times = read_profiles(path)
    t = times[-1] if time is None else times[np.argmin(abs(times - time))]
    blk = select_time(columns, t)

    def pick(*names):
        for n in names:
            if n in blk:
                return blk[n]
        raise KeyError(f"{path}: none of the columns {names}")

    z = pick("y", "z")  # the profile coordinate (read_profiles gives older runs' names as these)
    n = pick("number_density")
    nu = pick("number_flux_x")
    phi = pick("packing_fraction")
    return t, z, phi, nu / n


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("directory", help="the run's Output/Directory (or its profiles CSV)")
    add_base_option(p)
    p.add_argument("--slope", type=float, default=24.0, help="slope theta [degrees] (default 24)")
    p.add_argument("--diameter", type=float, default=1e-3, help="grain diameter d [m] (default 1e-3)")
    p.add_argument("--time", type=float, default=None, help="output time [s] (default: the last)")
    p.add_argument("--plot", default=None, help="PNG of the two velocity profiles")
    a = p.parse_args()
    try:
        path = find_output_file(a.directory, "profiles", a.base)
    except OutputFileError as e:
        sys.exit(f"chute_mu_i: {e}")
    t, z, phi, u = layer(path, a.time)
    dz = np.diff(z).mean()
    dense = phi > 0.3
    if not dense.any():
        sys.exit("chute_mu_i: no layer with phi > 0.3: is this a chute flow?")
    phi_b = phi[dense].mean()
    h = phi.sum() * dz / phi_b
    us_model = u[dense].max()
    us_ref = float(bagnold(np.array([h]), h, phi_b, a.slope, a.diameter)[0])
    ratio = us_model / us_ref if us_ref > 0 else float("inf")
    print(f"chute at t = {t:g} s, slope {a.slope:g} deg: layer depth h = {h * 1e3:.2f} mm "
          f"(phi = {phi_b:.3f}), I_theta = {inertial_number(a.slope):.4f}")
    print(f"surface speed: granhydro {us_model:.4g} m/s, mu(I) {us_ref:.4g} m/s"
          + (f", ratio {ratio:.3f}" if us_ref > 0 else " (below the arrest angle: at rest)"))
    if a.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(4.5, 4))
        ax.plot(u, z * 1e3, "o-", ms=3, label="granhydro")
        zz = np.linspace(0, h, 100)
        ax.plot(bagnold(zz, h, phi_b, a.slope, a.diameter), zz * 1e3, "k--", label="mu(I), Jop et al. 2006")
        ax.axhline(h * 1e3, color="0.7", lw=0.8)
        ax.set_xlabel("down-slope velocity [m/s]")
        ax.set_ylabel("height above the base [mm]")
        ax.set_title(f"frictional chute, {a.slope:g} deg, t = {t:g} s", fontsize=9)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(a.plot, dpi=120)
        print(f"plot: {a.plot}")


if __name__ == "__main__":
    main()
