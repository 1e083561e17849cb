"""The command-line tools in tools/ and tools/dem/: --help, shebang, and the tools that
read a run's output on small runs written like the solver's (solver_files.py).

Every script runs in a fresh temporary working directory, with the interpreter running
the tests (/usr/bin/python3 under ctest), as CI and the docs call them:
python3 tools/X.py ...
"""
import math
import os
import subprocess
import sys

import pytest

import solver_files as sf
from conftest import REPO, TOOLS

SCRIPTS = ["chute_mu_i.py", "closure_sensitivity.py", "code_size.py", "compare_profiles.py", "cost_model.py",
           "explicit_baseline.py", "format_check.py", "fuzz_scenes.py", "layer_rules.py", "make_silo_mesh.py", "paraview_check.py",
           "paraview_picture.py", "plot_adaptive_sedimentation.py", "plot_chute.py",
           "plot_profiles.py", "work_precision.py", "dem/coarse_grain.py", "dem/compare.py",
           "dem/make_input.py", "dem/run_ensemble.py", "dem/stiffness_check.py"]
MODULES = ["granhydro_output.py", "dem/packing.py", "dem/scene.py"]  # imported, not run
SHEBANG = {"paraview_check.py": "#!/usr/bin/env pvpython", "paraview_picture.py": "#!/usr/bin/env pvpython"}  # needs ParaView's Python


def run(script, *args, cwd):
    env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1", MPLBACKEND="Agg")
    return subprocess.run([sys.executable, os.path.join(TOOLS, script)] + [str(a) for a in args], cwd=str(cwd),
                          env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=120)


def needs_matplotlib():
    return pytest.importorskip("matplotlib", reason="python3-matplotlib is not installed")


def test_the_list_of_scripts_is_complete():
    found = []
    for d in ("", "dem/"):
        for name in sorted(os.listdir(os.path.join(TOOLS, d or "."))):
            if name.endswith(".py"):
                found.append(d + name)
    assert sorted(found) == sorted(SCRIPTS + MODULES)
    for m in MODULES:
        with open(os.path.join(TOOLS, m)) as f:
            assert "__main__" not in f.read(), m + " has become a script: add it to SCRIPTS"


@pytest.mark.parametrize("script", SCRIPTS)
def test_help(script, tmp_path):
    """--help prints the usage, exits 0 and creates no file"""
    r = run(script, "--help", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("usage: "), r.stdout[:200]
    assert r.stderr == ""
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("script", SCRIPTS)
def test_shebang_and_executable(script):
    path = os.path.join(TOOLS, script)
    with open(path) as f:
        assert f.readline().rstrip("\n") == SHEBANG.get(script, "#!/usr/bin/python3")
    assert os.access(path, os.X_OK), script + " is not executable"


def test_make_silo_mesh_writes_the_committed_meshes(tmp_path):
    """the meshes in meshes/ and tests/data/ are this script's output, byte for byte"""
    for args, committed in ((["silo.msh"], "meshes/silo_3d.msh"), (["--box", 2, "box.msh"], "tests/data/box_2d.msh"),
                            (["--box", 3, "box3.msh"], "tests/data/box_3d.msh"),
                            (["--box", 2, "box.inp"], "tests/data/box_2d.inp")):
        r = run("make_silo_mesh.py", *args, cwd=tmp_path)
        assert r.returncode == 0, r.stderr
        with open(tmp_path / args[-1], "rb") as a, open(os.path.join(REPO, committed), "rb") as b:
            assert a.read() == b.read(), committed
    r = run("make_silo_mesh.py", "--box", 2, cwd=tmp_path)
    assert r.returncode == 2 and "--box DIM needs the file" in r.stderr


def test_code_size(tmp_path):
    (tmp_path / "include").mkdir()
    (tmp_path / "source").mkdir()
    body = "\n".join("  x += %d;" % i for i in range(12))
    (tmp_path / "source" / "a.cc").write_text("int f(int x)\n{\n%s\n  return x;\n}\n" % body)
    (tmp_path / "include" / "b.h").write_text("int g();\n")
    r = run("code_size.py", "--root", tmp_path, cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "      16  source/a.cc\n       1  include/b.h\n" in r.stdout  # 16 lines, the longest first
    assert "      15  f  (source/a.cc:2)" in r.stdout  # from its '{' to its '}'
    r = run("code_size.py", "1", "--limit-function", 10, "--root", tmp_path, cwd=tmp_path)
    assert r.returncode == 1
    assert "0 files and 1 functions above the limits" in r.stdout


# ---------------------------------------------------------------- tools reading a run
def chute_field(t, y):
    """a 6 mm layer at phi = 0.55 with a Bagnold-like down-slope velocity, gas above"""
    h = 0.006
    phi = 0.55 if y < h else 0.01
    return phi, (t * 0.3 * (1 - (1 - min(y, h) / h) ** 1.5), 0.0), 1e-9


def write_chute(directory, base="solution", times=(0.0, 0.5, 1.0)):
    ys = [(l + 0.5) * 5e-4 for l in range(20)]
    return sf.write_profiles(os.path.join(str(directory), base + "_profiles.csv"), 2, 1, times, ys, 5e-4,
                             chute_field)


def test_chute_mu_i(tmp_path):
    write_chute(tmp_path / "out")
    r = run("chute_mu_i.py", "out", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    # h = sum(phi) dy / phi_dense = (12 x 0.55 + 8 x 0.01) x 0.5 mm / 0.55
    h = (12 * 0.55 + 8 * 0.01) * 0.5 / 0.55
    assert "t = 1 s, slope 24 deg: layer depth h = %.2f mm (phi = 0.550)" % h in r.stdout
    u_top = 0.3 * (1 - (1 - 5.75 / 6) ** 1.5)  # the highest dense layer, y = 5.75 mm
    assert "surface speed: granhydro %.4g m/s" % u_top in r.stdout
    r = run("chute_mu_i.py", "out", "--slope", 20, "--time", 0.4, cwd=tmp_path)
    assert "chute at t = 0.5 s, slope 20 deg" in r.stdout
    assert "below the arrest angle: at rest" in r.stdout


def test_compare_profiles(tmp_path):
    """two runs sharing a folder (--base-a/--base-b); B's layers are denser by 0.01"""
    write_chute(tmp_path / "out", base="a")
    ys = [(l + 0.5) * 5e-4 for l in range(20)]

    def denser(t, y):
        phi, u, T = chute_field(t, y)
        return phi + 0.01, u, 2 * T

    sf.write_profiles(str(tmp_path / "out" / "b_profiles.csv"), 2, 1, (0.5, 1.0), ys, 5e-4, denser)
    r = run("compare_profiles.py", "out", "out", "--base-a", "a", "--base-b", "b", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[0].startswith("time_s, layers, max|dphi|")
    assert lines[1:] == ["0.5, 20, 0.01, 0.01, 0.55, 0.56, 0.5", "1, 20, 0.01, 0.01, 0.55, 0.56, 0.5"]
    r = run("compare_profiles.py", "out", "out", cwd=tmp_path)
    assert r.returncode == 1 and "choose one with --base NAME" in r.stderr


def test_plot_profiles(tmp_path):
    needs_matplotlib()
    write_chute(tmp_path / "out", base="run")
    r = run("plot_profiles.py", "out", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "plot_profiles: wrote out/run_profiles.png"
    with open(tmp_path / "out" / "run_profiles.png", "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    r = run("plot_profiles.py", "out", "--spacetime", "--out", "st.png", cwd=tmp_path)
    assert r.returncode == 0 and os.path.getsize(tmp_path / "st.png") > 1000
    r = run("plot_profiles.py", "nothing", cwd=tmp_path)
    assert r.returncode == 1 and "no output directory or file nothing" in r.stderr


def test_plot_chute(tmp_path):
    needs_matplotlib()
    ys = [(i + 0.5) * 1e-3 for i in range(8)]
    zs = [(j + 0.5) * 1e-3 for j in range(6)]
    sf.write_cross_section(str(tmp_path / "out" / "solution_cross_section.csv"), [0.0, 0.5], ys, zs,
                           lambda t, y, z: (0.5 * (1 - z / 0.006), t * z * (1 + math.sin(1e3 * y)), 1e-9))
    r = run("plot_chute.py", "out", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "plot_chute: wrote out/solution_chute.png"
    assert os.path.getsize(tmp_path / "out" / "solution_chute.png") > 1000
