"""Compatibility shim: the helpers that were here are now granhydro.output (finding a run's
CSV files) and granhydro.readers.read_rows, in the package tools/granhydro_py/granhydro.

Kept so that existing imports keep working (benchmarks/*.sh insert tools/ into sys.path
and import find_output_file from here). New code: import granhydro (doc/developer.md, "Tools").
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "granhydro_py"))  # import granhydro
from granhydro.output import (DEFAULT_BASE, KINDS, OutputFileError, SeveralRunsError,  # noqa: E402
                              add_base_option, base_names, base_of, find_output_file)
from granhydro.readers import read_rows  # noqa: E402

__all__ = ["DEFAULT_BASE", "KINDS", "OutputFileError", "SeveralRunsError", "add_base_option", "base_names",
           "base_of", "find_output_file", "read_rows"]
