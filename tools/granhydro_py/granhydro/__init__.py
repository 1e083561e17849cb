"""granhydro's Python tools: finding and reading the files a granhydro run writes.

    import sys; sys.path.insert(0, "<checkout>/tools/granhydro_py")   # or PYTHONPATH
    from granhydro import find_output_file, read_profiles, read_summary

Modules:
  granhydro.output   where a run's CSV files are (Output/Directory, Output/Base name),
                     the --base option of the command-line tools
  granhydro.readers  one reader of each file: summary, profiles, cross section,
                     history, checkpoint, scene (.prm)

The command-line tools are the scripts in tools/ and tools/dem/ (doc/developer.md,
"Tools"); the package's tests are in tools/granhydro_py/tests (ctest tools.python_package).
"""
from .output import (DEFAULT_BASE, KINDS, OutputFileError, SeveralRunsError, add_base_option,
                     base_names, base_of, find_output_file)
from .readers import (ParameterFileError, blocks, column_name, flatten_parameters, read_checkpoint,
                      read_columns, read_cross_section, read_history, read_parameters, read_profiles,
                      read_rows, read_summary, select_time)

__all__ = ["DEFAULT_BASE", "KINDS", "OutputFileError", "SeveralRunsError", "add_base_option", "base_names",
           "base_of", "find_output_file", "ParameterFileError", "blocks", "column_name", "flatten_parameters",
           "read_checkpoint", "read_columns", "read_cross_section", "read_history", "read_parameters",
           "read_profiles", "read_rows", "read_summary", "select_time"]
