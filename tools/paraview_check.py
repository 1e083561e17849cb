#!/usr/bin/env pvpython
"""Check what a ParaView user sees in the output of a granhydro run (run it with pvpython).

    xvfb-run -a pvpython tools/paraview_check.py OUTPUT_DIR [--base NAME]
        [--scene FILE [-p "Section/Name=value" ...] | --expected-mass M] [--ranks N]

(xvfb-run -a only supplies the X display that Debian's pvpython wants; nothing is
rendered.) Needs ParaView's Python (Debian: apt-get install paraview python3-paraview
xvfb; python3-paraview is only a *recommended* package of paraview).

What it does, all through ParaView's own readers and filters (paraview.simple):

 1. opens OUTPUT_DIR/B.pvd with the PVD reader and goes to its last time step (checks
    that the dataset's TIME field equals that time);
 2. checks that the point-data arrays have plain names (packing_fraction,
    number_density, mass_density, velocity (3 components), temperature,
    granular_temperature, pressure, kinetic_/thermal_/contact_/total_energy_density,
    mpi_rank, refinement_level,
    uniform_stencil) and that the .pvtu carries their SI units in 'units' attributes;
 3. Calculator (point data, double result) with expressions on the plain names:
    'mass_density/number_density' must equal the grain mass m at every point, and
    'mass_density*mag(velocity)' must equal the same product computed with numpy
    from the fetched arrays. m comes from --scene (Material/Material density rho_s,
    Material/Grain diameter sigma: m = rho_s pi sigma^3/6, the solver's formula) or,
    without --scene, from number_density/mass_density of the first point;
 4. IntegrateVariables on the data as loaded: the integral of mass_density is the total
    mass in kg. This is exact for granhydro's output: the fields are cell values (DG0)
    written on each cell's own vertices (no vertex is shared between cells), so the
    trilinear interpolation inside a cell is the constant cell value;
 5. compares that mass with the solver's own total mass (below) to 1e-6 relative;
 6. checks the rank count: mpi_rank takes exactly the values 0..R-1 (R from --ranks,
    else 'ranks' in B_summary.csv, else the number of pieces of the .pvtu), and piece
    k of the .pvtu holds only mpi_rank = k;
 7. applies Clean to Grid and integrates again, and prints by how much the mass
    changes. Clean to Grid merges the coincident vertices of neighbouring cells and
    keeps a single value per merged vertex, so the cell values are no longer constant
    inside a cell and the integral is no longer the mass: users must integrate the data
    as loaded, never after Clean to Grid. This is reported, never a failure.

The solver's total mass (the reference of step 5), route chosen: the profiles CSV.
B_profiles.csv holds, for each output time, the average number density n_l (column
'number_density', 'n_1/m3' in older runs) over every layer l of the finest lattice along the profile direction; the
solver averages with cell-volume weights, so sum_l n_l * (V / N_layers) is the exact
number of grains in a box domain of volume V, also on an adaptive mesh. The total mass
is m * V * mean_l(n_l) at the block whose time equals the last PVD time. V is the box
of --scene (Domain/Lower and Upper corner) or, without --scene, the dataset's bounds.
The route needs a box domain whose every layer holds fluid cells (it checks that the
layers are evenly spaced and fill the box, and that ParaView's integrated volume is
the box volume); for a domain read from a 'Mesh file' pass --expected-mass M instead.
The profile values have 10 significant digits, ample for the 1e-6 comparison.
Without --scene, m is the Float32 ratio of the first point and enters both masses, so
the comparison then checks the integration (geometry and n) but not m itself: pass
--scene for a check of m too.
Also reported: the mass at the first output time from the profiles (with --scene and
a constant initial packing fraction phi0, also the exact phi0 rho_s V) and the
summary's mass_drift; in a closed box (walls and periodic boundaries) the solver keeps
the mass to round-off (drift ~1e-15), so the first and last profile blocks agree to the
10 digits of the CSV (checked to 1e-9 when the summary's drift is below 1e-12).

Tolerance: the VTU fields and point coordinates are written as Float32 (about 7
significant digits, relative rounding 6e-8), so every comparison between ParaView's
numbers and the solver's double-precision numbers uses 1e-6 relative; a failure at
that level is a real error, not round-off.

Exit status: 0 when every check passes, 1 when a check fails, 2 when the input cannot
be read (no PVD, no profiles, bad arguments).
"""
import argparse
import glob
import math
import os
import re
import sys
import time
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "granhydro_py"))  # tools/granhydro_py: import granhydro
from granhydro import readers  # noqa: E402
from granhydro.output import OutputFileError, find_output_file  # noqa: E402

TOL = 1e-6  # Float32 VTU data: relative rounding 6e-8; see the docstring

EXPECTED_ARRAYS = {  # plain name -> (components, SI unit in the .pvtu or None: no units attribute)
    "packing_fraction": (1, ""),
    "number_density": (1, "1/m^3"),
    "mass_density": (1, "kg/m^3"),
    "velocity": (3, "m/s"),
    "temperature": (1, "J"),
    "granular_temperature": (1, "m^2/s^2"),
    "pressure": (1, "Pa"),
    "kinetic_energy_density": (1, "J/m^3"),
    "thermal_energy_density": (1, "J/m^3"),
    "contact_energy_density": (1, "J/m^3"),
    "total_energy_density": (1, "J/m^3"),
    "mpi_rank": (1, None),
    "refinement_level": (1, None),
    "uniform_stencil": (1, None),
}


class InputError(Exception):
    """The output or the scene cannot be read (exit status 2)."""


class Report:
    def __init__(self):
        self.failures = []

    def check(self, ok, name, detail):
        print("  %s  %-34s %s" % ("PASS" if ok else "FAIL", name, detail))
        if not ok:
            self.failures.append(name)
        return ok

    def info(self, name, detail):
        print("  info  %-34s %s" % (name, detail))


def rel(a, b):
    return abs(a - b) / abs(b) if b != 0 else (0.0 if a == 0 else math.inf)


# ---------------------------------------------------------------- scene (.prm) file
def scene_values(path, overrides):
    """{'Section/Name': value} of a deal.II parameter file (granhydro.readers.read_parameters:
    subsection/set/end, '#' comments, '\\' continuation lines, no 'include'), then the
    -p "Section/Name=value" overrides."""
    try:
        values = readers.flatten_parameters(readers.read_parameters(path))
    except OSError as e:
        raise InputError("cannot read the scene %s: %s" % (path, e))
    except readers.ParameterFileError as e:
        raise InputError("cannot read the scene: %s" % e)
    for o in overrides:
        if "=" not in o:
            raise InputError("-p %r: expected \"Section/Name=value\"" % o)
        name, value = o.split("=", 1)
        values["/".join(w.strip() for w in name.split("/"))] = value.strip()
    return values


def scene_numbers(path, overrides):
    """grain mass, box (lower, upper) or None, constant initial phi or None"""
    prm = scene_values(path, overrides)
    dim = int(prm.get("Dimension", "2"))
    sigma = float(prm.get("Material/Grain diameter", "1e-3"))  # the solver's defaults
    rho_s = float(prm.get("Material/Material density", "2600"))
    m = rho_s * math.pi * sigma ** 3 / 6.0  # Scene::grain_mass()
    box = None
    if not prm.get("Domain/Mesh file", "").strip():
        lo = [float(v) for v in prm.get("Domain/Lower corner", "0, 0, 0").split(",")][:dim]
        hi = [float(v) for v in prm.get("Domain/Upper corner", "0.1, 0.1, 0.1").split(",")][:dim]
        box = (lo, hi)
    try:
        phi0 = float(prm.get("Initial state/Packing fraction", "0.01"))
    except ValueError:
        phi0 = None  # an expression: no closed-form initial mass
    return dict(dim=dim, m=m, rho_s=rho_s, sigma=sigma, box=box, phi0=phi0)


# ---------------------------------------------------------------- solver's CSV files
def profile_blocks(path):
    """(axis letter, {time: [(position, n), ...]}) of a B_profiles.csv"""
    try:
        columns, _ = readers.read_profiles(path)
    except ValueError as e:
        raise InputError("not a granhydro profiles CSV: %s" % e)
    header = list(columns)
    if len(header) < 3 or header[2] != "number_density":  # read_profiles: older runs' n_1/m3 too
        raise InputError("%s: not a granhydro profiles CSV (header %r)" % (path, header))
    axis = header[1][0]
    blocks = {}
    for t, x, n in zip(*(columns[c].tolist() for c in header[:3])):
        blocks.setdefault(t, []).append((x, n))
    return axis, blocks


def block_at(blocks, t):
    for tb in blocks:
        if abs(tb - t) <= 1e-9 * max(abs(t), 1e-300) or tb == t:
            return tb, sorted(blocks[tb])
    raise InputError("the profiles CSV has no block at t = %r s (it has %s)" % (t, sorted(blocks)))


def run_summary(directory, base):
    path = find_output_file(directory, "summary", base=base, required=False)
    if path is None:
        return {}
    return readers.read_summary(path)


# ---------------------------------------------------------------- ParaView helpers
def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("output_dir")
    ap.add_argument("--base", metavar="NAME", default=None,
                    help="Output/Base name of the run (default: the only *.pvd in OUTPUT_DIR)")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--expected-mass", type=float, metavar="M",
                   help="the total mass [kg] to compare with (instead of the profiles CSV)")
    g.add_argument("--scene", metavar="FILE", help="the run's scene (.prm): grain mass and box")
    ap.add_argument("-p", "--set", dest="overrides", action="append", default=[],
                    metavar="Section/Name=value", help="an override the run used (with --scene)")
    ap.add_argument("--ranks", type=int, default=None,
                    help="expected number of MPI ranks (default: 'ranks' in B_summary.csv)")
    args = ap.parse_args()
    if args.overrides and not args.scene:
        ap.error("-p needs --scene")
    start = time.time()
    try:
        failures = run(args)
    except (InputError, OutputFileError) as e:
        print("paraview_check: error: %s" % e)
        return 2
    print("wall time %.1f s" % (time.time() - start))
    if failures:
        print("paraview_check: FAILED: %s" % ", ".join(failures))
        return 1
    print("paraview_check: all checks passed")
    return 0


def run(args):
    from paraview import servermanager as sm
    from paraview import simple as pv
    from paraview.vtk.util.numpy_support import vtk_to_numpy
    import numpy as np

    d = args.output_dir
    base = args.base
    if not os.path.isdir(d):
        raise InputError("no output directory %s" % d)
    if base is None:
        pvds = sorted(glob.glob(os.path.join(glob.escape(d), "*.pvd")))
        if len(pvds) != 1:
            raise InputError("%s holds %s; choose one with --base NAME" % (
                d, ", ".join(map(os.path.basename, pvds)) if pvds else "no *.pvd"))
        base = os.path.basename(pvds[0])[:-4]
    pvd = os.path.join(d, base + ".pvd")
    if not os.path.isfile(pvd):
        raise InputError("no %s" % pvd)
    scene = scene_numbers(args.scene, args.overrides) if args.scene else None
    summary = run_summary(d, base)
    R = Report()

    print("paraview_check: ParaView %s (VTK %s), %s" % (
        sm.vtkSMProxyManager.GetParaViewSourceVersion().replace("paraview version ", ""),
        __import__("vtk").vtkVersion.GetVTKVersion(), pvd))

    # 1. the PVD reader at the last time step -------------------------------------
    reader = pv.PVDReader(FileName=pvd)
    times = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
    t_last = times[-1]
    anim = pv.GetAnimationScene()
    anim.UpdateAnimationUsingDataTimeSteps()
    anim.AnimationTime = t_last

    def fetch(proxy, t):
        proxy.UpdatePipeline(t)
        return sm.Fetch(proxy)

    data = fetch(reader, t_last)
    tf = data.GetFieldData().GetArray("TIME")
    t_data = float(tf.GetValue(0)) if tf is not None else None
    R.check(t_data is not None and rel(t_data, t_last) <= TOL if t_last else t_data == 0,
            "last time step", "%d time steps, last t = %.9g s, dataset TIME = %s, %d cells, %d points"
            % (len(times), t_last, t_data, data.GetNumberOfCells(), data.GetNumberOfPoints()))

    # 2. plain array names and units ----------------------------------------------
    pd = data.GetPointData()
    names = [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())]
    missing = [a for a, (nc, _) in EXPECTED_ARRAYS.items()
               if pd.GetArray(a) is None or pd.GetArray(a).GetNumberOfComponents() != nc]
    R.check(not missing and all(re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", n) for n in names),
            "plain array names", "point data: %s%s" % (", ".join(names),
                                                        "; missing/wrong: %s" % missing if missing else ""))
    types = sorted({pd.GetArray(n).GetDataTypeAsString() for n in names})
    R.info("array type", "%s (hence the 1e-6 relative tolerance)" % "/".join(types))
    pvtu_files = re.findall(r'file="([^"]+)"', open(pvd).read())
    pvtu = os.path.join(d, pvtu_files[-1]) if pvtu_files else None
    units, pieces = {}, []
    if pvtu and os.path.isfile(pvtu):
        root = ET.parse(pvtu).getroot()
        for a in root.iter("PDataArray"):
            if a.get("Name"):
                units[a.get("Name")] = a.get("units")
        pieces = [p.get("Source") for p in root.iter("Piece")]
    bad_units = {a: units.get(a) for a, (_, u) in EXPECTED_ARRAYS.items() if units.get(a) != u}
    R.check(not bad_units, "units attributes (.pvtu)",
            "%s%s" % (", ".join("%s [%s]" % (a, units[a]) for a in units if units[a]),
                      "; wrong: %s" % bad_units if bad_units else ""))

    # 3. Calculator on plain names ------------------------------------------------
    rho = vtk_to_numpy(pd.GetArray("mass_density")).astype(float)
    n = vtk_to_numpy(pd.GetArray("number_density")).astype(float)
    vel = vtk_to_numpy(pd.GetArray("velocity")).astype(float)
    if scene:
        m, m_from = scene["m"], "scene: rho_s pi sigma^3/6 = %.6g pi (%.6g)^3/6" % (scene["rho_s"], scene["sigma"])
    else:
        m, m_from = rho[0] / n[0], "mass_density/number_density of the first point (Float32)"
    calc_m = pv.Calculator(Input=reader, AttributeType="Point Data", ResultArrayName="grain_mass",
                           ResultArrayType="Double", Function="mass_density/number_density")
    calc_p = pv.Calculator(Input=calc_m, AttributeType="Point Data", ResultArrayName="momentum_magnitude",
                           ResultArrayType="Double", Function="mass_density*mag(velocity)")
    cdata = fetch(calc_p, t_last)
    cm = cdata.GetPointData().GetArray("grain_mass")
    cp = cdata.GetPointData().GetArray("momentum_magnitude")
    if cm is None or cp is None:
        R.check(False, "Calculator", "no result array (an expression on plain names failed)")
    else:
        cm, cp = vtk_to_numpy(cm), vtk_to_numpy(cp)
        err_m = float(np.max(np.abs(cm - m)) / m)
        R.check(err_m <= TOL, "Calculator mass_density/number_density",
                "= grain mass %.9g kg at all %d points: max rel. error %.2e (m from %s)"
                % (m, len(cm), err_m, m_from))
        ref = rho * np.linalg.norm(vel, axis=1)
        scale = np.maximum(np.abs(ref), 1e-6 * float(np.max(np.abs(ref))) or 1e-300)
        err_p = float(np.max(np.abs(cp - ref) / scale))
        R.check(err_p <= TOL and float(np.max(np.abs(ref))) > 0, "Calculator mass_density*mag(velocity)",
                "max %.6g kg/(m^2 s), max rel. error vs numpy %.2e" % (float(np.max(cp)), err_p))
    if pd.GetArray("granular_temperature") is not None and pd.GetArray("temperature") is not None:
        # T/m [m^2/s^2] against the temperature [J] over the grain mass, point by point
        T = vtk_to_numpy(pd.GetArray("temperature")).astype(float)
        Tm = vtk_to_numpy(pd.GetArray("granular_temperature")).astype(float)
        err_t = float(np.max(np.abs(Tm * m - T) / np.maximum(np.abs(T), 1e-300)))
        R.check(err_t <= TOL, "granular_temperature = T/m", "max rel. error %.2e (m from %s)" % (err_t, m_from))

    # 4. IntegrateVariables on the data as loaded ----------------------------------
    def integrate(src, t):
        out = fetch(pv.IntegrateVariables(Input=src), t)
        vol = None
        for key in ("Volume", "Area", "Length"):
            if out.GetCellData().GetArray(key) is not None:
                vol = float(out.GetCellData().GetArray(key).GetValue(0))
                break
        return float(out.GetPointData().GetArray("mass_density").GetValue(0)), vol

    M_pv, V_pv = integrate(calc_p, t_last)
    M_pv0, _ = integrate(reader, times[0])
    b = data.GetBounds()
    dim = scene["dim"] if scene else (3 if b[5] > b[4] else 2 if b[3] > b[2] else 1)
    if scene and scene["box"]:
        lo, hi = scene["box"]
        V_box, box_from = math.prod(h - l for l, h in zip(lo, hi)), "scene box"
    else:
        lo, hi = [b[2 * i] for i in range(dim)], [b[2 * i + 1] for i in range(dim)]
        V_box, box_from = math.prod(h - l for l, h in zip(lo, hi)), "dataset bounds"
    R.info("ParaView IntegrateVariables", "mass %.9g kg at t = %.9g s (%.9g kg at t = %.9g s); volume %.9g m^%d"
           % (M_pv, t_last, M_pv0, times[0], V_pv, dim))

    # 5. the solver's mass ----------------------------------------------------------
    if args.expected_mass is not None:
        M_ref, ref_from = args.expected_mass, "--expected-mass"
    else:
        prof = find_output_file(d, "profiles", base=base)
        axis, blocks = profile_blocks(prof)
        k = "xyz".index(axis)
        tb, layers = block_at(blocks, t_last)
        pos = [p for p, _ in layers]
        h = (hi[k] - lo[k]) / len(layers)
        even = all(abs(p - (lo[k] + (i + 0.5) * h)) <= 1e-6 * h for i, p in enumerate(pos))
        full = rel(V_pv, V_box) <= TOL
        if not R.check(even and full, "profile layers fill the box",
                       "%d layers along %s, spacing %.6g m, %s volume %.9g m^%d vs ParaView's %.9g"
                       % (len(layers), axis, h, box_from, V_box, dim, V_pv)):
            print("        (not a box filled with cells: pass --expected-mass M)")
        mass_of = lambda ls: m * V_box * sum(v for _, v in ls) / len(ls)
        M_ref, ref_from = mass_of(layers), "%s at t = %.9g s: m V mean(n_layer)" % (os.path.basename(prof), tb)
        t0b, layers0 = block_at(blocks, times[0])
        M_ref0 = mass_of(layers0)
        R.check(rel(M_pv0, M_ref0) <= TOL, "mass at the first output time",
                "ParaView %.9g kg, profiles %.10g kg, rel. diff %.2e (t = %.9g s)"
                % (M_pv0, M_ref0, rel(M_pv0, M_ref0), t0b))
        drift = summary.get("mass_drift")
        if drift is not None and float(drift) < 1e-12:
            R.check(rel(M_ref, M_ref0) <= 1e-9, "solver mass conservation",
                    "summary mass_drift %s; profiles: first %.10g kg, last %.10g kg, rel. diff %.2e "
                    "(10-digit CSV)" % (drift, M_ref0, M_ref, rel(M_ref, M_ref0)))
        else:
            R.info("solver mass conservation", "summary mass_drift %s (open boundaries or no summary): "
                   "not checked" % drift)
        if scene and scene["phi0"] is not None and scene["box"] and times[0] == 0:
            M_exact = scene["phi0"] * scene["rho_s"] * V_box
            R.check(rel(M_ref0, M_exact) <= 1e-9, "initial mass phi0 rho_s V",
                    "%.10g kg (phi0 = %g) vs profiles %.10g kg, rel. diff %.2e"
                    % (M_exact, scene["phi0"], M_ref0, rel(M_ref0, M_exact)))
    R.check(rel(M_pv, M_ref) <= TOL, "total mass ParaView vs solver",
            "ParaView %.9g kg, solver %.10g kg (%s), rel. diff %.2e (tolerance %g, Float32 VTU)"
            % (M_pv, M_ref, ref_from, rel(M_pv, M_ref), TOL))

    # 6. MPI ranks ----------------------------------------------------------------
    ranks = args.ranks or (int(summary["ranks"]) if "ranks" in summary else len(pieces))
    got = sorted({int(v) for v in np.unique(vtk_to_numpy(pd.GetArray("mpi_rank")))})
    per_piece = []
    for i, src in enumerate(pieces):
        pr = pv.XMLUnstructuredGridReader(FileName=os.path.join(d, src))
        pdat = fetch(pr, t_last)
        vals = np.unique(vtk_to_numpy(pdat.GetPointData().GetArray("mpi_rank")))
        per_piece.append((i, [int(v) for v in vals], pdat.GetNumberOfCells()))
        pv.Delete(pr)
    pieces_ok = all(v == [i] for i, v, _ in per_piece)
    R.check(got == list(range(ranks)) and len(pieces) == ranks and pieces_ok, "mpi_rank values",
            "%s (expected 0..%d; %d pieces: %s)" % (got, ranks - 1, len(pieces),
                                                     ", ".join("piece %d: rank %s, %d cells" % p for p in per_piece)))

    # 7. Clean to Grid changes the integral (documentation, never a failure) --------
    clean = pv.CleantoGrid(Input=reader)
    cdat = fetch(clean, t_last)
    M_clean, _ = integrate(clean, t_last)
    crho = vtk_to_numpy(cdat.GetPointData().GetArray("mass_density"))
    kept = float(np.mean(np.isin(crho, vtk_to_numpy(pd.GetArray("mass_density")))))
    R.info("Clean to Grid", "points %d -> %d; integral of mass_density %.9g kg, %+.3e relative to the "
           "data as loaded (%.0f%% of the merged points carry one cell's value unchanged): do not "
           "apply it before Integrate Variables"
           % (data.GetNumberOfPoints(), cdat.GetNumberOfPoints(), M_clean, (M_clean - M_pv) / M_pv, 100 * kept))
    return R.failures


if __name__ == "__main__":
    sys.exit(main())
