"""Small output files written the way granhydro writes them, for the tests.

The headers and number formats follow the solver: source/io/output.cc (profiles and
cross section: 10 significant digits, the energy densities with all 17; old=True: the
header of older runs, units in the names and no granular_temperature),
source/io/summary_csv.cc and source/driver/run_summary.cc (summary: 'key,value', 10
digits), include/granhydro/io/checkpoint.h (checkpoint formats v6 and v5).
"""
import math
import os
import struct

AXES = "xyz"
GRAIN_VOLUME = math.pi * 1e-9 / 6  # d = 1 mm
GRAIN_MASS = 2600 * GRAIN_VOLUME


def g10(v):
    """C++ 'out << std::setprecision(10) << v'"""
    return "%.10g" % v


def g17(v):
    """the energy densities: setprecision(max_digits10)"""
    return "%.17g" % v


def profiles_header(dim, pd, old=False):
    if old:
        return ("time_s,%s_m,n_1/m3," % AXES[pd] + ",".join("n*u_%s_1/(m2 s)" % AXES[d] for d in range(dim))
                + ",total_energy_density_J/m3,packing_fraction,temperature_J,kinetic_energy_density_J/m3,"
                  "thermal_energy_density_J/m3,contact_energy_density_J/m3")
    return ("time,%s,number_density," % AXES[pd] + ",".join("number_flux_%s" % AXES[d] for d in range(dim))
            + ",total_energy_density,packing_fraction,temperature,granular_temperature,kinetic_energy_density,"
              "thermal_energy_density,contact_energy_density")


def layer(phi, velocity, T, old=False):
    """the columns after the coordinate of one layer: n, n u_d, nE, phi, T, T/m (not in
    old files), parts of nE"""
    n = phi / GRAIN_VOLUME
    kinetic = 0.5 * n * GRAIN_MASS * sum(u * u for u in velocity)
    thermal = 1.5 * n * T
    return ([g10(n)] + [g10(n * u) for u in velocity] + [g17(kinetic + thermal), g10(phi), g10(T)]
            + ([] if old else [g10(T / GRAIN_MASS)]) + [g17(kinetic), g17(thermal), g17(0.0)])


def write_profiles(path, dim, pd, times, lower, h, field, comment=False, old=False):
    """B_profiles.csv with one block of layers per time; field(t, coordinate) ->
    (phi, velocity (dim values), T). comment: begin with a '#' line (older runs); old:
    the columns of older runs."""
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    with open(path, "w") as f:
        if comment:
            f.write("# granhydro profiles (an older run)\n")
        f.write(profiles_header(dim, pd, old) + "\n")
        for t in times:
            for l in range(len(lower)):
                x = lower[l]
                f.write(",".join([g10(t), g10(x)] + layer(*field(t, x), old=old)) + "\n")
    return path


def cross_section_header(old=False):
    """the header of a cross section along x"""
    if old:
        return ("time_s,y_m,z_m,n_1/m3,u_x_m/s,u_y_m/s,u_z_m/s,packing_fraction,temperature_J,"
                "total_energy_density_J/m3,kinetic_energy_density_J/m3,thermal_energy_density_J/m3,"
                "contact_energy_density_J/m3")
    return ("time,y,z,number_density,velocity_x,velocity_y,velocity_z,packing_fraction,temperature,"
            "granular_temperature,total_energy_density,kinetic_energy_density,thermal_energy_density,"
            "contact_energy_density")


def write_cross_section(path, times, ys, zs, field, old=False):
    """B_cross_section.csv of a 3D run along x: the y coordinate fastest; field(t, y, z)
    -> (phi, u_x, T). old: the columns of older runs."""
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    with open(path, "w") as f:
        f.write(cross_section_header(old) + "\n")
        for t in times:
            for z in zs:
                for y in ys:
                    phi, ux, T = field(t, y, z)
                    n = phi / GRAIN_VOLUME
                    ke, th = 0.5 * n * GRAIN_MASS * ux * ux, 1.5 * n * T
                    f.write(",".join([g10(t), g10(y), g10(z), g10(n), g10(ux), "0", "0", g10(phi), g10(T)]
                                     + ([] if old else [g10(T / GRAIN_MASS)])
                                     + [g17(ke + th), g17(ke), g17(th), g17(0.0)]) + "\n")
    return path


SUMMARY = [("status", "completed"), ("dimension", 2), ("cells", 400), ("max_cells", 400),
           ("ranks", 1), ("time", 0.2), ("steps", 3068), ("rejected_steps", 0),
           ("wall_seconds", 0.786747808), ("min_dt", 2.961733689e-05), ("mass_drift", 2.883304625e-14),
           ("flux_points", 935664), ("musta_stages", 1883574), ("friction_dissipation_J", 0.002542259529),
           ("version", "0.9.0"), ("git_revision", "1234567"), ("scene", "parameters/blast_2d.prm"),
           ("overrides", '"Time/End time=0.2;Domain/Cells=20, 20"'),  # quoted: it holds a comma
           ("start_time", "2026-12-06T09:30:00Z")]


def write_summary(path, entries=SUMMARY):
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    with open(path, "w") as f:
        f.write("key,value\n")
        for k, v in entries:
            f.write("%s,%s\n" % (k, g10(v) if isinstance(v, float) else v))
    return path


MAGIC = b"granhydro checkpoint v6\n"
MAGIC_V5 = b"granhydro checkpoint v5\n"
HEADER = struct.Struct("=ii3Q3d3d4d3Q16si4x5i4x2d4dd")
RUN_RECORD = 4096  # format v6: the run record after the v5 header
PART = struct.Struct("<QQqqQ")


def write_checkpoint(path, dim, cells, units, time_scaled, parts, n_components, history=False,
                     record=None, version=6):
    """A checkpoint of format v6 (or v5); parts: one list of (key, values) per writing
    rank, each sorted by key; values: n_components numbers (and as many more with
    history); record: the run record {key: value} (v6). The checksums are written as 0
    (granhydro.readers does not verify them)."""
    n_values = 2 * n_components if history else n_components
    n_cells = sum(len(p) for p in parts)
    header = HEADER.pack(dim, n_components, *cells, 0, 0, 0, 1, 1, 1, *units, time_scaled,
                         17, n_cells, 3, b"granular", n_values,
                         0, 1 if history else 0, 0, 0, 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    if version == 6:
        text = "".join("%s %.17g\n" % kv for kv in (record or {}).items()).encode()
        header += text + bytes(RUN_RECORD - len(text))
    magic = MAGIC if version == 6 else MAGIC_V5
    row = struct.Struct("<q%dd" % n_values)
    offset = len(magic) + len(header) + 8 + len(parts) * PART.size + 8
    table, body = b"", b""
    for p in parts:
        table += PART.pack(offset, len(p), p[0][0] if p else -1, p[-1][0] if p else -1, 0)
        for key, values in p:
            body += row.pack(key, *values)
        offset += len(p) * row.size
    with open(path, "wb") as f:
        f.write(magic + header + struct.pack("<Q", len(parts)) + table + struct.pack("<Q", 0) + body)
    return path


def history_columns(dim):
    """The header of B_history.csv of a dim-D run (source/driver/time_loop.cc)."""
    ax = "xyz"[:dim]
    return (["time", "dt", "step", "mass"] + ["momentum_%s" % a for a in ax] +
            ["%s_energy" % p for p in ("kinetic", "thermal", "contact", "total")] +
            ["centre_of_mass_%s" % a for a in ax] +
            ["max_packing_fraction", "min_temperature", "max_speed", "rejected_steps", "integrator",
             "convective_steps", "diffusion_steps", "rkl2_steps", "rkl2_stages", "implicit_steps",
             "newton_iterations", "gmres_iterations"])


def write_history(path, header, rows):
    """B_history.csv as the solver writes it: numbers with 17 significant digits (nan as
    'nan'), counts as integers, words as they are."""
    def cell(v):
        if isinstance(v, float):
            return "nan" if v != v else "%.17g" % v
        return str(v)
    with open(path, "w") as f:
        f.write(",".join(header) + "\n")
        for r in rows:
            f.write(",".join(cell(v) for v in r) + "\n")
    return path
