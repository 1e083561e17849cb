"""granhydro.output: finding a run's CSV files by output directory and base name."""
import argparse
import os
import sys

import pytest

from conftest import TOOLS
from granhydro import output
from granhydro.output import OutputFileError, SeveralRunsError, base_names, base_of, find_output_file


def touch(path):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    open(path, "w").close()
    return path


def test_one_run_in_the_directory(tmp_path):
    d = str(tmp_path)
    p = touch(os.path.join(d, "solution_profiles.csv"))
    touch(os.path.join(d, "solution_summary.csv"))
    assert find_output_file(d, "profiles") == p
    assert find_output_file(d, "profiles", base="solution") == p
    assert find_output_file(p, "profiles") == p  # a file: as given
    assert find_output_file(d, "summary").endswith("solution_summary.csv")
    assert find_output_file(d, "cross_section", required=False) is None
    with pytest.raises(OutputFileError, match="no \\*_cross_section.csv"):
        find_output_file(d, "cross_section")


def test_several_runs_need_a_base_name(tmp_path):
    d = str(tmp_path)
    touch(os.path.join(d, "adaptive_profiles.csv"))
    touch(os.path.join(d, "uniform_profiles.csv"))
    assert base_names(d, "profiles") == ["adaptive", "uniform"]
    with pytest.raises(SeveralRunsError, match="adaptive_profiles.csv, uniform_profiles.csv"):
        find_output_file(d, "profiles")
    assert find_output_file(d, "profiles", base="uniform") == os.path.join(d, "uniform_profiles.csv")
    with pytest.raises(OutputFileError, match="no other_profiles.csv .*adaptive, uniform"):
        find_output_file(d, "profiles", base="other")


def test_older_run_without_base_name(tmp_path):
    d = str(tmp_path)
    p = touch(os.path.join(d, "profiles.csv"))
    assert find_output_file(d, "profiles") == p
    assert find_output_file(d, "profiles", base="solution") == p
    assert base_of(p) is None
    assert base_of(os.path.join(d, "run2_cross_section.csv")) == "run2"


def test_missing_directory_and_bad_kind(tmp_path):
    with pytest.raises(OutputFileError, match="no output directory or file"):
        find_output_file(str(tmp_path / "nothing"), "summary")
    assert find_output_file(str(tmp_path / "nothing"), "summary", required=False) is None
    with pytest.raises(ValueError, match="kind must be one of"):
        find_output_file(str(tmp_path), "nonsense")


def test_base_option():
    p = argparse.ArgumentParser()
    output.add_base_option(p)
    assert p.parse_args(["--base", "run2"]).base == "run2"
    assert p.parse_args([]).base is None


def test_the_old_module_still_imports():
    """tools/granhydro_output.py (imported by benchmarks/*.sh) re-exports the package"""
    sys.path.insert(0, TOOLS)
    try:
        import granhydro_output
    finally:
        sys.path.remove(TOOLS)
    from granhydro import readers
    assert granhydro_output.find_output_file is output.find_output_file
    assert granhydro_output.OutputFileError is OutputFileError
    assert granhydro_output.read_rows is readers.read_rows
