"""Finding the CSV files of a granhydro run (granhydro.output; tools/granhydro_output.py
re-exports it for the scripts in benchmarks/).

A run writes into its Output/Directory D, under its Output/Base name B (default
'solution'), so that several runs can share one directory:

    D/B.pvd, D/B_NNNN.pvtu, D/B_NNNN.*.vtu, D/B.checkpoint,
    D/B_profiles.csv, D/B_cross_section.csv, D/B_summary.csv, D/B_history.csv

Older runs wrote D/profiles.csv, D/cross_section.csv and D/summary.csv (without the
base name) and began profiles/cross-section CSVs with a '#' comment line; newer ones
begin with the header row. Readers should skip lines starting with '#' (read_rows).

    from granhydro.output import find_output_file
    path = find_output_file("output", "profiles")            # output/solution_profiles.csv
    path = find_output_file("output", "summary", base="run2")
    path = find_output_file("output/run2_profiles.csv", "profiles")   # a file: as given

The readers of the files' contents are in granhydro.readers.
"""
import glob
import os

KINDS = ("profiles", "cross_section", "summary", "history")
DEFAULT_BASE = "solution"


class OutputFileError(Exception):
    """No file, or no single file, of the asked kind (the message says which and why)."""


class SeveralRunsError(OutputFileError):
    """The directory holds the files of several base names and none was chosen."""


def _check_kind(kind):
    if kind not in KINDS:
        raise ValueError("granhydro.output: kind must be one of %s, not %r" % (", ".join(KINDS), kind))


def base_names(directory, kind):
    """The base names B of the runs that wrote DIRECTORY/B_<kind>.csv, sorted."""
    _check_kind(kind)
    suffix = "_%s.csv" % kind
    return sorted(os.path.basename(p)[:-len(suffix)]
                  for p in glob.glob(os.path.join(glob.escape(directory), "*" + suffix))
                  if os.path.isfile(p) and len(os.path.basename(p)) > len(suffix))


def find_output_file(path, kind, base=None, required=True):
    """The <kind>.csv file of a run; kind is 'profiles', 'cross_section', 'summary' or
    'history'.

    PATH is the CSV file itself (returned as it is) or an output directory. In a
    directory: BASE given -> PATH/BASE_<kind>.csv; otherwise the one PATH/*_<kind>.csv
    (an error listing the base names when there are several: pass base). For old
    output folders (no *_<kind>.csv at all) it falls back to PATH/<kind>.csv.
    Raises OutputFileError when nothing fits (or returns None if required=False),
    SeveralRunsError (an OutputFileError) for several base names without BASE.
    """
    _check_kind(kind)
    name = "%s.csv" % kind
    if os.path.isfile(path):
        return path
    if not os.path.isdir(path):
        if required:
            raise OutputFileError("no output directory or file %s" % path)
        return None
    bases = base_names(path, kind)
    if base is not None:
        f = os.path.join(path, "%s_%s" % (base, name))
        if os.path.isfile(f):
            return f
        old = os.path.join(path, name)
        if not bases and os.path.isfile(old):  # an output folder of an older run
            return old
        if not required:
            return None
        raise OutputFileError("no %s in %s%s" % (
            os.path.basename(f), path,
            " (it holds the %s of base name(s) %s)" % (name, ", ".join(bases)) if bases else ""))
    if len(bases) == 1:
        return os.path.join(path, "%s_%s" % (bases[0], name))
    if len(bases) > 1:
        raise SeveralRunsError("%s holds the *_%s of several runs: %s; choose one with --base NAME "
                              "(the scene's Output/Base name)" % (
                                  path, name, ", ".join("%s_%s" % (b, name) for b in bases)))
    old = os.path.join(path, name)
    if os.path.isfile(old):  # an output folder of an older run
        return old
    if required:
        raise OutputFileError("no *_%s (or %s) in %s" % (name, name, path))
    return None


def base_of(path):
    """The base name in the name of a file found by find_output_file (None for the
    un-prefixed names of older runs)."""
    name = os.path.basename(path)
    for kind in KINDS:
        suffix = "_%s.csv" % kind
        if name.endswith(suffix) and len(name) > len(suffix):
            return name[:-len(suffix)]
    return None


def add_base_option(parser):
    """The --base NAME option of the command-line tools that take an output directory."""
    parser.add_argument("--base", metavar="NAME", default=None,
                        help="the run's Output/Base name, when several runs share the output "
                             "directory (default: the only run there)")

