"""Readers of the files a granhydro run writes, and of its scene files: one of each.

    from granhydro import readers
    summary = readers.read_summary("output")                # {'status': 'completed', 'cells': '100', ...}
    columns, times = readers.read_profiles("output")        # {'time': array, 'y': array, ...}, times
    last = readers.select_time(columns, times[-1])          # the rows of the last output time
    scene = readers.read_parameters("parameters/sod_1d.prm")   # {'Dimension': '1', 'Domain': {...}}

The readers of a run's CSV files take the file itself or the output directory, with
base=NAME when several runs share the directory (granhydro.output.find_output_file).

  file                      reader              content (written by)
  B_summary.csv             read_summary        'key,value' rows (source/io/summary_csv.cc,
                                                source/driver/run_summary.cc)
  B_profiles.csv            read_profiles       time, <axis>, number_density, number_flux_<d> per
                                                direction, total_energy_density, packing_fraction,
                                                temperature, granular_temperature, kinetic_/
                                                thermal_/contact_energy_density; one block of rows
                                                (one per layer) per output time (source/io/output.cc)
  B_cross_section.csv       read_cross_section  time, <a>, <b>, number_density, velocity_x/_y/_z,
                                                packing_fraction, temperature, granular_temperature,
                                                energy densities; 3D runs with Output/Cross-section
                                                direction; one block per output time, <a> fastest
  B_history.csv             read_history        time, dt, step, mass, momentum, energies, centre
                                                of mass, extremes and the run's counts; one row
                                                per history time (source/driver/run_history.cc)
  B.checkpoint              read_checkpoint     binary, format v6 or v5 (include/granhydro/io/
                                                checkpoint.h): header, run record and the cells'
                                                values in double precision
  scene (.prm)              read_parameters     deal.II ParameterHandler text: subsection/set/end

The profiles and cross-section columns are named like the VTU fields, in SI units
(doc/user-guide.md, "Profiles and cross-sections"). Older runs named them with their unit
('time_s', 'y_m', 'n_1/m3', 'n*u_y_1/(m2 s)', 'u_x_m/s', 'temperature_J',
'total_energy_density_J/m3', or 'n*E_J/m3' before the energy split) and had no
granular_temperature: read_profiles and read_cross_section return the names of now
(column_name), so a script reads old and new folders alike. Older runs also began these
files with a '#' comment line; every reader skips lines starting with '#' and blank lines. The readers that return arrays
import numpy when called (python3-numpy); the others need only the standard library.
"""
import csv
import re
import struct

from .output import find_output_file


# ---------------------------------------------------------------- CSV files of a run
# the profiles' and cross-section's column names of older runs (the unit in the name) ->
# the names of now, the VTU fields' (source/io/output.cc); see column_name
OLD_COLUMN_NAMES = {"time_s": "time", "n_1/m3": "number_density", "temperature_J": "temperature",
                    "n*E_J/m3": "total_energy_density"}
OLD_COLUMN_PATTERNS = [(re.compile(r"([xyz])_m"), r"\1"),                        # coordinates
                       (re.compile(r"n\*u_([xyz])_1/\(m2 s\)"), r"number_flux_\1"),
                       (re.compile(r"u_([xyz])_m/s"), r"velocity_\1"),
                       (re.compile(r"(\w+_energy_density)_J/m3"), r"\1"),
                       (re.compile(r"temperature_([xyz])_J"), r"temperature_\1")]  # DEM profiles


def column_name(name):
    """The name of now of a profiles or cross-section column named NAME by an older run
    ('temperature_J' -> 'temperature', 'n*u_y_1/(m2 s)' -> 'number_flux_y', 'y_m' -> 'y');
    a name of now, or any other, is returned as it is. The suffix '_se' (the standard
    error columns of tools/dem/coarse_grain.py) is kept: 'n_1/m3_se' -> 'number_density_se'."""
    if name.endswith("_se"):
        return column_name(name[:-3]) + "_se"
    if name in OLD_COLUMN_NAMES:
        return OLD_COLUMN_NAMES[name]
    for pattern, new in OLD_COLUMN_PATTERNS:
        if pattern.fullmatch(name):
            return pattern.sub(new, name)
    return name


def renamed(columns):
    """{column_name(name): array} of columns from read_columns, in the same order."""
    return {column_name(name): c for name, c in columns.items()}


def read_rows(path):
    """The rows of a granhydro CSV file (lists of strings), header first, without
    comment lines ('#', written by older runs) and blank lines."""
    with open(path, newline="") as f:
        return [r for r in csv.reader(l for l in f if not l.startswith("#")) if r]


def read_columns(path):
    """(columns, times) of a granhydro table whose first column is time (time_s in older
    runs): columns maps each header name, as in the file and in its order, to a numpy
    array of that column over all rows; times are the distinct values of the first
    column, ascending. ValueError for an empty file, a first column other than time or
    time_s, a row of the wrong length or a value that is not a number."""
    import numpy as np
    rows = read_rows(path)
    if not rows:
        raise ValueError("%s is empty" % path)
    header = rows[0]
    if header[0] not in ("time", "time_s"):
        raise ValueError("%s: the first column is %r, not time or time_s (not a granhydro table?)"
                         % (path, header[0]))
    values = []
    for k, r in enumerate(rows[1:], 2):
        if len(r) != len(header):
            raise ValueError("%s: data row %d has %d values, the header %d columns" % (path, k, len(r), len(header)))
        try:
            values.append([float(v) for v in r])
        except ValueError as e:
            raise ValueError("%s: data row %d: %s" % (path, k, e))
    data = np.array(values, dtype=float).reshape(len(values), len(header))
    columns = {name: data[:, i] for i, name in enumerate(header)}
    return columns, np.unique(data[:, 0])


def select_time(columns, t):
    """The rows of columns (from read_columns) at time == t exactly (t one of the times
    read_columns returned), as {name: array}; the time column is 'time', or 'time_s' as
    read_columns gives it for an older file."""
    rows = columns["time" if "time" in columns else "time_s"] == t
    return {name: c[rows] for name, c in columns.items()}


def blocks(columns, times):
    """{time: {name: array}}: the rows of every output time (select_time for each)."""
    return {float(t): select_time(columns, t) for t in times}


def read_profiles(path, base=None):
    """(columns, times) of a run's B_profiles.csv (PATH: the file or the output
    directory; BASE: the run's Output/Base name); see read_columns. The columns have the
    names of now also for an older run's file (column_name). The second column is the
    profile coordinate (x, y or z)."""
    columns, times = read_columns(find_output_file(path, "profiles", base))
    return renamed(columns), times


def read_cross_section(path, base=None):
    """(columns, times) of a run's B_cross_section.csv; see read_columns and
    read_profiles (names of now). Columns 2 and 3 are the two coordinates across the
    section direction (the first of them varies fastest within a block)."""
    columns, times = read_columns(find_output_file(path, "cross_section", base))
    return renamed(columns), times


# the columns of B_history.csv that hold words, not numbers
HISTORY_WORDS = ("integrator",)


def read_history(path, base=None):
    """{column: array} of a run's B_history.csv (PATH: the file or the output directory;
    BASE: the run's Output/Base name), columns in the file's order: numbers as float
    arrays ('nan' where a value does not apply, e.g. max_packing_fraction of the ideal
    gas), the word columns of HISTORY_WORDS as str arrays.

    The file (source/driver/run_history.cc, doc/user-guide.md "Output"): a header row,
    time first, then one row per history time (Output/History interval), in step
    order: time, dt, step, mass, momentum_<d> per direction,
    kinetic_/thermal_/contact_/total_energy, centre_of_mass_<d> per direction,
    max_packing_fraction, min_temperature, max_speed (SI units: s, kg, kg m/s, J, m, J,
    m/s), and the counts of the whole run so far: rejected_steps, integrator,
    convective_steps, diffusion_steps, rkl2_steps, rkl2_stages, implicit_steps,
    newton_iterations, gmres_iterations. In 1D and 2D the extensive values are per
    m^(3 - dim) of the unresolved extent. Lines starting with '#' are skipped.
    ValueError for an empty file, a first column other than time, a row of the wrong
    length or a value that is not a number."""
    import numpy as np
    path = find_output_file(path, "history", base)
    rows = read_rows(path)
    if not rows:
        raise ValueError("%s is empty" % path)
    header = rows[0]
    if header[0] not in ("time", "time_s"):
        raise ValueError("%s: the first column is %r, not time or time_s (not a granhydro history?)" %
                         (path, header[0]))
    for k, r in enumerate(rows[1:], 2):
        if len(r) != len(header):
            raise ValueError("%s: data row %d has %d values, the header %d columns" % (path, k, len(r), len(header)))
    columns = {}
    for i, name in enumerate(header):
        values = [r[i] for r in rows[1:]]
        if name in HISTORY_WORDS:
            columns[name] = np.array(values, dtype=str)
            continue
        try:
            columns[name] = np.array([float(v) for v in values], dtype=float)
        except ValueError as e:
            raise ValueError("%s: column %s: %s" % (path, name, e))
    return columns


# the rows that name the run: words even where they look like numbers (a commit 1234567)
SUMMARY_WORDS = ("status", "version", "git_revision", "scene", "overrides", "start_time")


def read_summary(path, base=None, numbers=False):
    """{key: value} of a run's B_summary.csv ('key,value' header, then one 'key,value'
    row per entry, a value with a comma in double quotes; PATH: the file or the output
    directory). Values are strings, or with numbers=True floats where they parse as
    numbers (the rows of SUMMARY_WORDS stay strings). A run that is still going has
    'status,running' and the rows that name the run."""
    summary = {}
    for row in read_rows(find_output_file(path, "summary", base)):
        if len(row) < 2 or row[0] == "key":
            continue
        value = ",".join(row[1:])
        if numbers and row[0] not in SUMMARY_WORDS:
            try:
                value = float(value)
            except ValueError:
                pass
        summary[row[0]] = value
    return summary


# ---------------------------------------------------------------- scene files
class ParameterFileError(ValueError):
    """A line of a parameter file that read_parameters cannot read (the message names
    the file and line)."""


def read_parameters(path):
    """A deal.II parameter file (a granhydro scene) as a nested dict: {'Dimension': '2',
    'Domain': {'Cells': '100, 50', ...}, ...}; values are the strings after '=' (a later
    'set' of the same entry wins, a subsection opened twice is merged).

    Lines are joined as deal.II's ParameterHandler::parse_input joins them: each line is
    stripped, and one ending in '\\' is continued by the next without the backslash; then
    '#' starts a comment. Not supported (ParameterFileError): 'include' lines (only the
    one file is read) and anything but subsection/set/end; also an 'end' without
    subsection, an unclosed subsection, a name that is both an entry and a subsection.
    The line number in a message is the line where the statement begins."""
    statements = []  # (line number, the joined line)
    with open(path) as f:
        joined, start = "", None
        for lineno, raw in enumerate(f, 1):
            line = raw.strip()
            start = lineno if start is None else start
            if line.endswith("\\"):
                joined += line[:-1]
                continue
            statements.append((start, joined + line))
            joined, start = "", None
        if start is not None:  # the last line ends in a backslash
            statements.append((start, joined))
    root = {}
    stack, names = [root], []

    def error(lineno, what):
        return ParameterFileError("%s:%d: %s" % (path, lineno, what))

    for lineno, text in statements:
        line = text.split("#", 1)[0].strip()
        if not line:
            continue
        words = line.split(None, 1)
        key = words[0]
        if key == "subsection":
            if len(words) < 2:
                raise error(lineno, "'subsection' without a name")
            name = words[1].strip()
            sub = stack[-1].setdefault(name, {})
            if not isinstance(sub, dict):
                raise error(lineno, "'%s' is an entry and a subsection" % name)
            stack.append(sub)
            names.append(name)
        elif key == "end":
            if not names:
                raise error(lineno, "'end' without subsection")
            stack.pop()
            names.pop()
        elif key == "set":
            m = re.match(r"set\s+(.+?)\s*=\s*(.*)$", line)
            if not m:
                raise error(lineno, "malformed 'set' line")
            name = m.group(1).strip()
            if isinstance(stack[-1].get(name), dict):
                raise error(lineno, "'%s' is an entry and a subsection" % name)
            stack[-1][name] = m.group(2).strip()
        elif key == "include":
            raise error(lineno, "'include' is not supported (granhydro.readers reads one file)")
        else:
            raise error(lineno, "cannot read '%s'" % line)
    if names:
        raise ParameterFileError("%s: subsection '%s' is not closed" % (path, names[-1]))
    return root


def flatten_parameters(params, prefix=""):
    """{'Section/Sub/Name': value} of a nested dict from read_parameters."""
    flat = {}
    for name, value in params.items():
        if isinstance(value, dict):
            flat.update(flatten_parameters(value, prefix + name + "/"))
        else:
            flat[prefix + name] = value
    return flat


# ---------------------------------------------------------------- checkpoint (binary)
CHECKPOINT_MAGIC = b"granhydro checkpoint v6\n"  # keys: fine-lattice key * 8 + level
CHECKPOINT_MAGIC_V5 = b"granhydro checkpoint v5\n"
# io::CheckpointHeader (include/granhydro/io/checkpoint.h) with x86-64 alignment: dims,
# cells, corners, units, time, step/n_cells/outputs, model, n_values, the implicit
# step's history (5 int32 + padding, t, dt, N[4]), the convective time owed; 240 bytes
# (format v5); format v6 appends the run record, 4096 bytes of "key value" lines
CHECKPOINT_HEADER = struct.Struct("=ii3Q3d3d4d3Q16si4x5i4x2d4dd")
CHECKPOINT_RUN_RECORD = 4096
# then the part count and the part table: offset, rows, first key, last key, checksum
CHECKPOINT_PART = struct.Struct("<QQqqQ")


def read_checkpoint(path):
    """Checkpoint of write_checkpoint (source/driver/simulation_checkpoint.cc): header and
    the cells of every part (one per writing rank) sorted by lattice key, conservative
    variables in the file's scaled units (double precision).

    Returns {'dim', 'cells' (3 counts), 'time_scaled', 'length', 'mass', 'velocity' (the
    scaled units), 'step', 'version' (5 or 6), 'run_record' ({key: float}: the counts of
    the run up to the checkpoint, summed over its segments; empty in format v5), 'key'
    (int64 array), 'U' (array, one row of n_components values per cell)}. Formats v5
    and v6; the checksums and key ranges are not verified (the solver's reader,
    source/io/checkpoint_read.cc, does that)."""
    import numpy as np
    with open(path, "rb") as f:
        data = f.read()
    if data.startswith(CHECKPOINT_MAGIC):
        version = 6
    elif data.startswith(CHECKPOINT_MAGIC_V5):
        version = 5
    else:
        raise ValueError("%s is not a granhydro checkpoint (format v5 or v6)" % path)
    o = len(CHECKPOINT_MAGIC)
    h = CHECKPOINT_HEADER.unpack_from(data, o)
    o += CHECKPOINT_HEADER.size
    record = {}
    if version == 6:
        text = data[o:o + CHECKPOINT_RUN_RECORD].split(b"\0", 1)[0].decode()
        for line in text.splitlines():
            key, value = line.split()
            record[key] = float(value)
        o += CHECKPOINT_RUN_RECORD
    dim, nc = h[0], h[1]
    cells = h[2:5]
    length, mass, velocity, t = h[11], h[12], h[13], h[14]
    n_values = h[19]  # nc, or 2 nc when the implicit step's history is stored
    n_parts = struct.unpack_from("<Q", data, o)[0]
    parts = [CHECKPOINT_PART.unpack_from(data, o + 8 + p * CHECKPOINT_PART.size) for p in range(n_parts)]
    rec = np.dtype([("key", "<i8"), ("u", "<f8", (n_values,))])
    rows = np.concatenate([np.frombuffer(data, dtype=rec, count=n, offset=off) for off, n, _, _, _ in parts])
    rows = rows[np.argsort(rows["key"], kind="stable")]
    return {"dim": dim, "cells": cells, "time_scaled": t, "length": length, "mass": mass,
            "velocity": velocity, "step": h[15], "version": version, "run_record": record,
            "key": rows["key"], "U": rows["u"][:, :nc]}
