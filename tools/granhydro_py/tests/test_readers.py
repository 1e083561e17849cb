"""granhydro.readers on files written the way the solver writes them (solver_files.py)
and on the runs committed in doc/validation/."""
import math
import os

import numpy as np
import pytest

import solver_files as sf
from conftest import REPO
from granhydro import readers
from granhydro.output import OutputFileError

VALIDATION = os.path.join(REPO, "doc", "validation")


# ---------------------------------------------------------------- rows and summary
def test_read_rows_skips_comments_and_blank_lines(tmp_path):
    p = tmp_path / "a.csv"
    p.write_text("# written by an older run\ntime_s,x_m\n0,0.5\n\n0.1,0.5\n")
    assert readers.read_rows(str(p)) == [["time_s", "x_m"], ["0", "0.5"], ["0.1", "0.5"]]


def test_read_summary(tmp_path):
    d = str(tmp_path / "out")
    sf.write_summary(os.path.join(d, "run1_summary.csv"))
    s = readers.read_summary(d)  # the directory: its only *_summary.csv
    assert "key" not in s
    assert len(s) == len(sf.SUMMARY)
    assert s["status"] == "completed"
    assert s["cells"] == "400" and s["wall_seconds"] == "0.786747808"
    n = readers.read_summary(os.path.join(d, "run1_summary.csv"), numbers=True)
    assert n["status"] == "completed"
    assert n["steps"] == 3068.0 and n["min_dt"] == 2.961733689e-05
    assert n["musta_stages"] / n["flux_points"] == pytest.approx(2.013088, rel=1e-6)
    # the rows naming the run: words, the quoted one unquoted
    assert s["overrides"] == n["overrides"] == "Time/End time=0.2;Domain/Cells=20, 20"
    assert n["git_revision"] == "1234567" and n["version"] == "0.9.0"
    assert n["start_time"] == "2026-12-06T09:30:00Z"


def test_read_summary_of_a_running_and_of_a_missing_run(tmp_path):
    d = str(tmp_path)
    with open(os.path.join(d, "solution_summary.csv"), "w") as f:
        f.write("key,value\nstatus,running\n")  # write_running_summary
    assert readers.read_summary(d, base="solution") == {"status": "running"}
    with pytest.raises(OutputFileError):
        readers.read_summary(d, base="other")


def test_read_summary_of_the_committed_runs():
    s = readers.read_summary(os.path.join(VALIDATION, "sedimentation_column", "granhydro"), numbers=True)
    assert s["status"] == "completed"
    assert (s["dimension"], s["cells"], s["time"]) == (1, 100, 0.2)
    assert abs(s["mass_drift"]) < 1e-12
    b = readers.read_summary(os.path.join(VALIDATION, "bouncing_bed", "granhydro"))
    assert (b["dimension"], b["cells"]) == ("3", "600")


# ---------------------------------------------------------------- profiles
def column_field(t, x):
    """a settling layer: phi falls from 0.5 to 0.01 around a front that moves down"""
    front = 0.008 - 0.01 * t
    phi = 0.01 + 0.49 / (1 + math.exp((x - front) / 5e-4))
    return phi, (0.0, -0.1 * t), 1e-8 * (1 + x / 0.01)


def write_column(path, comment=False, old=False):
    ys = [(l + 0.5) * 1e-3 for l in range(10)]
    return sf.write_profiles(path, 2, 1, [0.0, 0.05, 0.1], ys, 1e-3, column_field, comment=comment, old=old)


def test_read_profiles(tmp_path):
    write_column(str(tmp_path / "solution_profiles.csv"))
    columns, times = readers.read_profiles(str(tmp_path))
    assert list(columns) == sf.profiles_header(2, 1).split(",")
    assert list(times) == [0.0, 0.05, 0.1]
    assert all(len(c) == 30 for c in columns.values())
    last = readers.select_time(columns, times[-1])
    assert len(last["y"]) == 10
    assert last["y"][0] == 0.0005 and last["y"][-1] == 0.0095
    phi, _, T = column_field(0.1, 0.0005)
    assert last["packing_fraction"][0] == pytest.approx(phi, rel=1e-9)
    assert last["temperature"][0] == pytest.approx(T, rel=1e-9)
    # T/m: both columns to 10 digits, so 1e-9 relative
    assert np.allclose(last["granular_temperature"], last["temperature"] / sf.GRAIN_MASS, rtol=1e-9)
    n = last["number_density"]
    assert np.allclose(last["number_flux_y"] / n, -0.01, rtol=1e-9)
    assert np.all(last["number_flux_x"] == 0)
    parts = sum(last[c] for c in ("kinetic_energy_density", "thermal_energy_density", "contact_energy_density"))
    assert np.allclose(parts, last["total_energy_density"], rtol=1e-15)
    by_time = readers.blocks(columns, times)
    assert list(by_time) == [0.0, 0.05, 0.1]
    assert np.array_equal(by_time[0.1]["packing_fraction"], last["packing_fraction"])


def test_read_profiles_of_an_older_run(tmp_path):
    """profiles.csv without the base name, beginning with a '#' line, old column names"""
    write_column(str(tmp_path / "profiles.csv"), comment=True, old=True)
    columns, times = readers.read_profiles(str(tmp_path), base="solution")
    assert len(times) == 3 and len(columns["time"]) == 30


def test_old_and_new_column_names_read_alike(tmp_path):
    """the same profiles and cross section written with the names of older runs (units in
    the names) and of now: read_profiles and read_cross_section give the same columns
    with the same values; the old files lack only granular_temperature"""
    old, new = write_column(str(tmp_path / "old_profiles.csv"), old=True), write_column(str(tmp_path / "new_profiles.csv"))
    assert open(old).readline().startswith("time_s,y_m,n_1/m3,n*u_x_1/(m2 s),")
    (co, to), (cn, tn) = readers.read_profiles(old), readers.read_profiles(new)
    assert list(to) == list(tn)
    assert list(co) == [c for c in cn if c != "granular_temperature"]
    assert list(co) == ["time", "y", "number_density", "number_flux_x", "number_flux_y", "total_energy_density",
                        "packing_fraction", "temperature", "kinetic_energy_density", "thermal_energy_density",
                        "contact_energy_density"]
    for name in co:
        assert np.array_equal(co[name], cn[name]), name  # the same digits in both files
    ys, zs = [0.5e-3, 1.5e-3], [1e-3, 3e-3, 5e-3]

    def field(t, y, z):
        return 0.3, t * z, 1e-9

    xo = sf.write_cross_section(str(tmp_path / "old_cross_section.csv"), [0.0, 0.5], ys, zs, field, old=True)
    xn = sf.write_cross_section(str(tmp_path / "new_cross_section.csv"), [0.0, 0.5], ys, zs, field)
    (co, _), (cn, _) = readers.read_cross_section(xo), readers.read_cross_section(xn)
    assert list(co) == [c for c in cn if c != "granular_temperature"]
    assert list(co)[:7] == ["time", "y", "z", "number_density", "velocity_x", "velocity_y", "velocity_z"]
    for name in co:
        assert np.array_equal(co[name], cn[name]), name


def test_column_names_of_older_runs():
    old = ["time_s", "z_m", "n_1/m3", "n*u_z_1/(m2 s)", "u_y_m/s", "temperature_J", "n*E_J/m3",
           "contact_energy_density_J/m3", "packing_fraction", "n_1/m3_se", "temperature_x_J_se", "phase"]
    assert [readers.column_name(c) for c in old] == [
        "time", "z", "number_density", "number_flux_z", "velocity_y", "temperature", "total_energy_density",
        "contact_energy_density", "packing_fraction", "number_density_se", "temperature_x_se", "phase"]
    # the names of now are kept, and every one is a Python identifier (numpy's and pandas'
    # attribute access, ParaView's Calculator)
    new = sf.profiles_header(3, 2).split(",") + sf.cross_section_header().split(",")
    assert all(readers.column_name(c) == c and c.isidentifier() for c in new)


def test_read_profiles_of_the_committed_run():
    """doc/validation keeps profiles.csv of an older run (names with units): read with the
    names of now"""
    columns, times = readers.read_profiles(os.path.join(VALIDATION, "sedimentation_column", "granhydro"))
    assert len(times) == 21 and times[0] == 0 and times[-1] == pytest.approx(0.2)
    first, last = readers.select_time(columns, times[0]), readers.select_time(columns, times[-1])
    assert len(first["x"]) == len(last["x"]) == 100
    assert first["packing_fraction"][0] == 0.1
    assert 0.62 < last["packing_fraction"][0] < 0.63  # the pile at the floor
    # a closed column: the mean number density (the grains) is kept to the 10 digits
    assert last["number_density"].mean() == pytest.approx(first["number_density"].mean(), rel=1e-9)


def test_read_columns_refuses_what_is_not_a_table(tmp_path):
    p = tmp_path / "x_summary.csv"
    p.write_text("key,value\nstatus,completed\n")
    with pytest.raises(ValueError, match="not time or time_s"):
        readers.read_columns(str(p))
    q = tmp_path / "cut_profiles.csv"
    q.write_text("time_s,x_m,n_1/m3\n0,0.5,1\n0,1.5\n")  # a run killed while writing
    with pytest.raises(ValueError, match="data row 3 has 2 values"):
        readers.read_profiles(str(q))
    e = tmp_path / "empty_profiles.csv"
    e.write_text("")
    with pytest.raises(ValueError, match="empty"):
        readers.read_profiles(str(e))


# ---------------------------------------------------------------- cross section, history
def test_read_cross_section(tmp_path):
    ys = [(i + 0.5) * 1e-3 for i in range(4)]
    zs = [(j + 0.5) * 2e-3 for j in range(3)]

    def field(t, y, z):
        return 0.5 - 10 * z, t * z * (1 + y * 100), 1e-9

    sf.write_cross_section(str(tmp_path / "chute_cross_section.csv"), [0.0, 0.5], ys, zs, field)
    columns, times = readers.read_cross_section(str(tmp_path), base="chute")
    assert list(times) == [0.0, 0.5]
    d = readers.select_time(columns, 0.5)
    assert len(d["y"]) == 12
    ux = d["velocity_x"].reshape(len(zs), len(ys))  # y fastest
    assert ux[2, 3] == pytest.approx(field(0.5, ys[3], zs[2])[1], rel=1e-9)
    assert d["packing_fraction"].reshape(3, 4)[:, 0] == pytest.approx([0.49, 0.47, 0.45], rel=1e-9)


def test_read_history(tmp_path):
    """a history as the solver writes it (source/driver/time_loop.cc: 17 digits, the
    integrator as a word, nan for the ideal gas's packing fraction), found in its folder"""
    header = sf.history_columns(2)
    rows = [[0.0, 0.0, 0, 1.5e-3, 0.0, -2.5e-7, 0.0, 1e-9, 0.0, 1e-9, 0.05, 0.01, float("nan"), 1e-9, 0.0,
             0, "none", 0, 0, 0, 0, 0, 0, 0],
            [0.01, 1e-3, 10, 1.5e-3, 0.0, -2.5e-6, 2.5e-6, 1e-9, 0.0, 2.5e-6 + 1e-9, 0.05, 0.0099999999999999985,
             float("nan"), 1e-9, 0.25, 2, "none", 10, 0, 0, 0, 0, 0, 0]]
    p = sf.write_history(str(tmp_path / "solution_history.csv"), header, rows)
    h = readers.read_history(str(tmp_path))
    assert list(h) == header
    assert list(h["time"]) == [0, 0.01]
    assert list(h["step"]) == [0, 10]
    assert h["centre_of_mass_y"][1] == 0.0099999999999999985  # 17 digits read back exactly
    assert list(h["integrator"]) == ["none", "none"]
    assert all(h["max_packing_fraction"] != h["max_packing_fraction"])  # nan
    assert h["total_energy"][1] == 2.5e-6 + 1e-9
    assert readers.read_history(p)["rejected_steps"][1] == 2
    q = tmp_path / "bad_history.csv"
    q.write_text("step,mass\n0,1\n")
    with pytest.raises(ValueError, match="not time or time"):
        readers.read_history(str(q))
    r = tmp_path / "short_history.csv"
    r.write_text("time,mass\n0\n")
    with pytest.raises(ValueError, match="has 1 values"):
        readers.read_history(str(r))
    w = tmp_path / "word_history.csv"
    w.write_text("time,mass\n0,heavy\n")
    with pytest.raises(ValueError, match="column mass"):
        readers.read_history(str(w))


# ---------------------------------------------------------------- parameter files
SCENE = """# a scene
set Dimension = 2
subsection Domain
  set Lower corner = 0, 0
  set Upper corner = 0.1, 0.2   # a comment
  set Cells = 10, \\
              20
end
subsection Initial state
  set Packing fraction = if(y < 0.1, 0.3, 0.01)
  subsection Constants
    set h = 0.1
  end
end
subsection Domain
  set Cells = 20, 40
end
"""


def test_read_parameters(tmp_path):
    p = tmp_path / "scene.prm"
    p.write_text(SCENE)
    params = readers.read_parameters(str(p))
    assert params == {
        "Dimension": "2",
        "Domain": {"Lower corner": "0, 0", "Upper corner": "0.1, 0.2", "Cells": "20, 40"},
        "Initial state": {"Packing fraction": "if(y < 0.1, 0.3, 0.01)", "Constants": {"h": "0.1"}}}
    flat = readers.flatten_parameters(params)
    assert flat["Initial state/Constants/h"] == "0.1"
    assert flat["Domain/Cells"] == "20, 40"  # the later 'set' wins


def test_read_parameters_continuation_line(tmp_path):
    """joined as deal.II joins them: stripped lines, the backslash removed"""
    p = tmp_path / "scene.prm"
    p.write_text(SCENE.replace("subsection Domain\n  set Cells = 20, 40\nend\n", ""))
    assert readers.read_parameters(str(p))["Domain"]["Cells"] == "10, 20"
    q = tmp_path / "bad.prm"
    q.write_text("set Dimension = \\\n  2\nsubsection Domain\n  set Cells \\\n  4\nend\n")
    with pytest.raises(readers.ParameterFileError, match="bad.prm:4: malformed 'set' line"):
        readers.read_parameters(str(q))  # the line where the statement begins


def write_prm(params, indent=""):
    """the inverse of read_parameters (for the round trip)"""
    lines = []
    for name, value in params.items():
        if isinstance(value, dict):
            lines += [indent + "subsection " + name] + write_prm(value, indent + "  ") + [indent + "end"]
        else:
            lines.append("%sset %s = %s" % (indent, name, value))
    return lines


def test_read_parameters_of_every_committed_scene(tmp_path):
    """every scene in parameters/ reads, and writing it back gives the same parameters"""
    scenes = []
    for root, _, files in os.walk(os.path.join(REPO, "parameters")):
        scenes += [os.path.join(root, f) for f in files if f.endswith(".prm")]
    assert len(scenes) > 20
    for s in scenes:
        params = readers.read_parameters(s)
        assert params, s
        out = tmp_path / "round_trip.prm"
        out.write_text("\n".join(write_prm(params)) + "\n")
        assert readers.read_parameters(str(out)) == params, s
    sod = readers.read_parameters(os.path.join(REPO, "parameters", "sod_1d.prm"))
    assert sod["Dimension"] == "1"


@pytest.mark.parametrize("text, message", [
    ("include other.prm\n", "scene.prm:1: 'include' is not supported"),
    ("set Dimension = 2\nend\n", "scene.prm:2: 'end' without subsection"),
    ("subsection Domain\n  set Cells = 4\n", "subsection 'Domain' is not closed"),
    ("subsection Domain\n  set Cells 4\nend\n", "scene.prm:2: malformed 'set' line"),
    ("subsection Domain\n  Cells = 4\nend\n", "scene.prm:2: cannot read 'Cells = 4'"),
    ("set Domain = 1\nsubsection Domain\nend\n", "'Domain' is an entry and a subsection"),
])
def test_read_parameters_refuses(tmp_path, text, message):
    p = tmp_path / "scene.prm"
    p.write_text(text)
    with pytest.raises(readers.ParameterFileError, match=message):
        readers.read_parameters(str(p))


# ---------------------------------------------------------------- checkpoint
def test_read_checkpoint(tmp_path):
    """two parts (two ranks) whose keys interleave, rows with the implicit step's
    history: the reader merges them in key order and keeps the state only"""
    nc = 4  # 2D: n, n u_x, n u_y, nE
    rank0 = [(k, [k + 0.25, -k, 2.0 * k, 1e-3 * k] + [99.0] * nc) for k in (8, 24, 40)]
    rank1 = [(k, [k + 0.25, -k, 2.0 * k, 1e-3 * k] + [99.0] * nc) for k in (16, 32)]
    p = sf.write_checkpoint(str(tmp_path / "solution.checkpoint"), 2, (5, 1, 1), (1e-3, 2e-6, 0.1), 12.5,
                            [rank0, rank1], nc, history=True)
    c = readers.read_checkpoint(p)
    assert readers.CHECKPOINT_HEADER.size == 240  # include/granhydro/io/checkpoint.h
    assert c["version"] == 6 and c["run_record"] == {} and c["step"] == 17
    assert c["dim"] == 2 and tuple(c["cells"]) == (5, 1, 1)
    assert (c["length"], c["mass"], c["velocity"], c["time_scaled"]) == (1e-3, 2e-6, 0.1, 12.5)
    assert list(c["key"]) == [8, 16, 24, 32, 40]
    assert c["U"].shape == (5, nc)
    assert list(c["U"][:, 0]) == [8.25, 16.25, 24.25, 32.25, 40.25]
    assert list(c["U"][:, 2]) == [16.0, 32.0, 48.0, 64.0, 80.0]


def test_read_checkpoint_run_record_and_v5(tmp_path):
    """format v6 carries the run record; format v5 (no record) is still read"""
    rows = [(k, [1.0 + k, 0.5, 2.0]) for k in (8, 16)]
    record = {"segments": 2.0, "rejected_steps": 3.0, "wall_seconds": 0.125}
    p = sf.write_checkpoint(str(tmp_path / "a.checkpoint"), 1, (2, 1, 1), (1e-3, 2e-6, 0.1), 1.5,
                            [rows], 3, record=record)
    c = readers.read_checkpoint(p)
    assert c["version"] == 6 and c["run_record"] == record
    q = sf.write_checkpoint(str(tmp_path / "b.checkpoint"), 1, (2, 1, 1), (1e-3, 2e-6, 0.1), 1.5,
                            [rows], 3, version=5)
    d = readers.read_checkpoint(q)
    assert d["version"] == 5 and d["run_record"] == {}
    assert list(d["U"][:, 0]) == list(c["U"][:, 0]) == [9.0, 17.0]


def test_read_checkpoint_refuses_another_format(tmp_path):
    p = tmp_path / "old.checkpoint"
    p.write_bytes(b"granhydro checkpoint v4\n" + bytes(300))
    with pytest.raises(ValueError, match="not a granhydro checkpoint"):
        readers.read_checkpoint(str(p))


# ---------------------------------------------------------------- DEM profiles (tools/dem)
def test_dem_profiles_of_an_older_version_and_of_now(tmp_path):
    """tools/dem/coarse_grain.py: the committed DEM profiles (doc/validation, names with
    units) read under the names coarse_grain.write_csv writes now, and a file with those
    names reads back the same"""
    import sys
    from conftest import TOOLS
    sys.path.insert(0, os.path.join(TOOLS, "dem"))
    import coarse_grain
    old = os.path.join(VALIDATION, "sedimentation_column", "dem", "dem_profiles.csv")
    keycol, dem = coarse_grain.read_csv(old)
    assert keycol == "time"
    header = [l for l in open(old) if not l.startswith("#")][0].strip().split(",")
    assert header[:3] == ["time_s", "x_m", "seeds"] and "n*u_x_1/(m2 s)_se" in header
    first = dem[min(dem)]
    assert list(first) == coarse_grain.csv_columns("x")
    # the same numbers under the names of now
    new = tmp_path / "dem_profiles.csv"
    with open(old) as f, open(new, "w") as g:
        lines = [l for l in f if not l.startswith("#")]
        g.write(",".join(coarse_grain.csv_columns("x")) + "\n" + "".join(lines[1:]))
    keycol_new, dem_new = coarse_grain.read_csv(str(new))
    assert keycol_new == "time" and list(dem_new) == list(dem)
    for k in dem:
        for c in first:
            assert np.array_equal(dem[k][c], dem_new[k][c], equal_nan=True), (k, c)
    _, phased = coarse_grain.read_csv(os.path.join(VALIDATION, "bouncing_bed", "dem", "dem_profiles.csv"))
    assert list(phased[min(phased)]) == coarse_grain.csv_columns("y", phase_bins=8)
