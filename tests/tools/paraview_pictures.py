"""ctest tools.paraview: what a ParaView user sees of a granhydro run (run with pvpython
under xvfb-run; registered only where ParaView's Python is installed).

    xvfb-run -a pvpython tests/tools/paraview_pictures.py GRANHYDRO SOURCE_DIR WORKDIR

1. runs a small 2D granular box at rest (packing fraction 0.1 below y = 0.05 m, 0.3
   above, no gravity; two output times) on one rank;
2. tools/paraview_check.py on its output (ParaView's reader, Calculator and Integrate
   Variables against the solver's mass: its own checks and tolerances);
3. tools/paraview_picture.py at t = 0 with the colour range fixed to 0..0.4: the
   pixels at the centre of the lower and upper halves must have the colours of
   phi = 0.1 and 0.3 on ParaView's "Viridis (matplotlib)" map, i.e. the colours at
   0.25 and 0.75 of the range, read from ParaView's own lookup table. Tolerance 3 of
   255 per channel: the map is a 256-entry table (neighbouring entries differ by up to
   about 2 units) and the PNG rounds to whole units; a wrong time, a wrong range or a
   shaded surface shifts the colours by 20 or more (the faults this test found);
4. two times in one picture: the width is the sum of the panels and the colour bar.
Exit 0 when all hold, 1 otherwise.
"""
import os
import subprocess
import sys

from paraview import simple as pv
from paraview.vtk.util.numpy_support import vtk_to_numpy

exe, source, work = sys.argv[1:4]
os.makedirs(work, exist_ok=True)
os.chdir(work)
scene = """set Dimension = 2
subsection Domain
  set Lower corner = 0, 0
  set Upper corner = 0.1, 0.1
  set Cells = 10, 10
  set Boundary x- = slip wall
  set Boundary x+ = slip wall
  set Boundary y- = slip wall
  set Boundary y+ = slip wall
end
subsection Material
  set Model = granular
  set Grain diameter = 1e-3
  set Material density = 2600
  set Restitution coefficient = 0.9
end
subsection Initial state
  set Packing fraction = y < 0.05 ? 0.1 : 0.3
  set Temperature = 1e-8
  set Quadrature points = 1
end
subsection Time
  set End time = 1e-4
end
subsection Output
  set Directory = out
  set Interval = 5e-5
end
"""
with open("box.prm", "w") as f:
    f.write(scene)
failures = []


def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print("$ " + " ".join(cmd) + "\n" + p.stdout)
    return p.returncode


pvpython = sys.executable if "pvpython" in os.path.basename(sys.executable) else "pvpython"
if run([exe, "box.prm"]) != 0:
    sys.exit("granhydro failed")
if run([pvpython, os.path.join(source, "tools", "paraview_check.py"), "out", "--scene", "box.prm"]) != 0:
    failures.append("paraview_check")
picture = os.path.join(source, "tools", "paraview_picture.py")
if run([pvpython, picture, "out", "--times", "0", "--range", "0,0.4", "--size", "400,400", "--out", "one.png"]) != 0:
    sys.exit("paraview_picture failed")

reader = pv.PNGSeriesReader(FileNames=[os.path.abspath("one.png")])
image = pv.servermanager.Fetch(reader)
nx, ny, _ = image.GetDimensions()
pixels = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(ny, nx, -1)  # row 0 = bottom
lut = pv.GetColorTransferFunction("reference_map")
lut.ApplyPreset("Viridis (matplotlib)", True)
lut.RescaleTransferFunction(0.0, 0.4)
for phi, row in ((0.1, ny // 4), (0.3, 3 * ny // 4)):
    rgb = [0.0, 0.0, 0.0]
    lut.GetClientSideObject().GetColor(phi, rgb)
    want = [round(255 * c) for c in rgb]
    got = [int(v) for v in pixels[row, nx // 2, :3]]
    ok = max(abs(a - b) for a, b in zip(want, got)) <= 3
    print("phi = %.1f: pixel %s, map %s: %s" % (phi, got, want, "PASS" if ok else "FAIL"))
    if not ok:
        failures.append("colour of phi = %.1f" % phi)

if run([pvpython, picture, "out", "--times", "0,1e-4", "--size", "700,300", "--out", "two.png"]) != 0:
    sys.exit("paraview_picture (two times) failed")
reader2 = pv.PNGSeriesReader(FileNames=[os.path.abspath("two.png")])
dims = pv.servermanager.Fetch(reader2).GetDimensions()
# two panels of (700 - 180) // 2 = 260 pixels and the 180-pixel colour bar
ok = dims[0] == 2 * 260 + 180 and dims[1] == 300
print("two times: %d x %d pixels: %s" % (dims[0], dims[1], "PASS" if ok else "FAIL"))
if not ok:
    failures.append("size of the two-panel picture")
print("FAILED: " + ", ".join(failures) if failures else "all passed")
sys.exit(1 if failures else 0)
