#!/usr/bin/env pvpython
"""Render a picture of a granhydro run with ParaView (run it with pvpython).

    xvfb-run -a pvpython tools/paraview_picture.py OUTPUT_DIR [--base NAME]
        [--field packing_fraction] [--times last | T1,T2,...] [--out FILE]
        [--range MIN,MAX] [--log] [--size W,H] [--title TEXT]

Needs ParaView's Python (Debian: apt-get install paraview python3-paraview xvfb;
python3-paraview is only a *recommended* package of paraview, and xvfb-run supplies
the X display Debian's pvpython wants).

It opens OUTPUT_DIR/<Base name>.pvd with ParaView's PVD reader, exactly as a user
would in the ParaView window, and colours the cells by one field (any array of the VTU
files: packing_fraction, temperature, granular_temperature, pressure,
velocity (its magnitude), ...; the unit in the colour bar's title comes from the
.pvtu file). In 1D and 2D the domain is seen from above (the
vertical direction up the picture); in 3D from an oblique angle, with the box's
outline. --times takes one or more simulated times in seconds (the nearest output
time is drawn; 'last', the default, is the final one); several times make a row of
panels with one shared colour scale, labelled with their times. The colour range is
the field's range over the panels unless --range is given; --log draws a logarithmic
scale (for temperatures that span decades).

The picture goes to OUTPUT_DIR/<Base name>_<field>.png unless --out is given.

Exit status: 0 when the picture is written, 2 when the input cannot be read (no PVD,
an unknown field, bad arguments).
"""
import argparse
import glob
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "granhydro_py"))  # tools/granhydro_py: import granhydro
from granhydro.output import OutputFileError, base_of, find_output_file  # noqa: E402


class InputError(Exception):
    """The output or an argument cannot be used (exit status 2)."""


def parse_pair(text, kind, name):
    try:
        a, b = (kind(v) for v in text.split(","))
    except ValueError:
        raise InputError("%s %r: expected two numbers separated by a comma" % (name, text))
    return a, b


def choose_times(available, wanted):
    """The output times nearest to each wanted time ('last': the final one)."""
    if not available:
        return [0.0]
    if wanted == "last":
        return [available[-1]]
    times = []
    for w in wanted.split(","):
        try:
            t = float(w)
        except ValueError:
            raise InputError("--times %r: expected 'last' or times in seconds separated by commas" % wanted)
        times.append(min(available, key=lambda a: abs(a - t)))
    return times


def units_of(pvd, field):
    """' [unit]' from the 'units' attribute granhydro writes on the .pvtu's arrays ('' if none)."""
    import xml.etree.ElementTree as ET
    try:
        files = [d.get("file") for d in ET.parse(pvd).getroot().iter("DataSet")]
        pvtu = os.path.join(os.path.dirname(pvd), files[0])
        for a in ET.parse(pvtu).getroot().iter("PDataArray"):
            if a.get("Name") == field and a.get("units"):
                return " [%s]" % a.get("units")
    except (ET.ParseError, OSError, IndexError, TypeError):
        pass
    return ""


def label_of_time(t):
    if t == 0:
        return "t = 0"
    if abs(t) < 1:
        return "t = %g ms" % round(t * 1e3, 6)
    return "t = %g s" % t


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=__doc__[__doc__.index("\n\n") + 2:])
    parser.add_argument("output_dir", help="the run's Output/Directory (or its .pvd file)")
    parser.add_argument("--base", help="Output/Base name when several runs share the directory")
    parser.add_argument("--field", default="packing_fraction", help="cell array to colour by")
    parser.add_argument("--times", default="last", help="'last' or simulated times [s], comma-separated")
    parser.add_argument("--out", help="picture file (.png)")
    parser.add_argument("--range", help="colour range MIN,MAX")
    parser.add_argument("--log", action="store_true", help="logarithmic colour scale")
    parser.add_argument("--size", help="picture size W,H in pixels (default: 900 high, 1D/2D panels shaped like the domain)")
    parser.add_argument("--title", help="title of the colour bar (default: the field and its unit)")
    args = parser.parse_args()
    try:
        out = render(args)
    except (InputError, OutputFileError) as e:
        print("paraview_picture: error: %s" % e, file=sys.stderr)
        return 2
    print("paraview_picture: wrote %s" % out)
    return 0


def render(args):
    from paraview import simple as pv
    import numpy as np

    pv._DisableFirstRenderCameraReset()  # the cameras below are set by hand

    if args.output_dir.endswith(".pvd"):
        pvd = args.output_dir
        directory = os.path.dirname(pvd) or "."
        base = os.path.basename(pvd)[:-4]
    else:
        directory = args.output_dir
        if args.base:
            base = args.base
        else:  # the one run in the directory (its summary names the base), else the one .pvd
            pvds = sorted(glob.glob(os.path.join(glob.escape(directory), "*.pvd")))
            summary = find_output_file(directory, "summary", required=False) if len(pvds) != 1 else None
            base = base_of(summary) if summary else (os.path.basename(pvds[0])[:-4] if pvds else "solution")
            if len(pvds) > 1 and not summary:
                raise InputError("%s holds several runs (%s): choose one with --base NAME" %
                                 (directory, ", ".join(os.path.basename(p) for p in pvds)))
        pvd = os.path.join(directory, base + ".pvd")
    if not os.path.isfile(pvd):
        raise InputError("no ParaView file %s (was Output/Write VTU = false?)" % pvd)
    out = args.out or os.path.join(directory, "%s_%s.png" % (base, args.field))

    reader = pv.PVDReader(FileName=os.path.abspath(pvd))
    reader.UpdatePipelineInformation()
    available = sorted(reader.TimestepValues) if reader.TimestepValues else []
    if not isinstance(available, list):
        available = [float(available)]
    times = choose_times(available, args.times)

    reader.UpdatePipeline(times[0])
    # granhydro writes each cell's value on the cell's own vertices (point data that is
    # constant in a cell: the pictures show the cells as they are); cell data as well
    association, data = "POINTS", reader.PointData
    if args.field not in data.keys() and args.field in reader.CellData.keys():
        association, data = "CELLS", reader.CellData
    if args.field not in data.keys():
        raise InputError("no array %r in %s (arrays: %s)" % (args.field, pvd, ", ".join(data.keys())))
    unit = units_of(pvd, args.field)
    info = data[args.field]
    components = info.GetNumberOfComponents()
    bounds = reader.GetDataInformation().GetBounds()
    extent = [bounds[2 * d + 1] - bounds[2 * d] for d in range(3)]
    dim = sum(1 for e in extent if e > 0)

    # the colour range over all panels
    lo, hi = np.inf, -np.inf
    for t in times:
        reader.UpdatePipeline(t)
        r = data[args.field].GetRange(-1 if components > 1 else 0)
        lo, hi = min(lo, r[0]), max(hi, r[1])
    if args.range:
        lo, hi = parse_pair(args.range, float, "--range")
    if args.log:
        if hi <= 0:
            raise InputError("--log: the field %s is not positive (range %g .. %g)" % (args.field, lo, hi))
        lo = max(lo, hi * 1e-12) if lo <= 0 else lo
    if hi <= lo:
        hi = lo + (abs(lo) if lo != 0 else 1.0) * 1e-6

    title = (args.title or (args.field if components == 1 else "|%s|" % args.field)) + unit
    # 1D/2D: the panel's shape follows the domain's (vertical direction up), unless --size
    # says otherwise; several times share the width
    across, up = (1, 0) if dim == 1 else (0, 1)
    if dim == 1:
        extent_across, extent_up = extent[0] / 20, extent[0]  # a column drawn as a bar
    else:
        extent_across, extent_up = extent[across], extent[up]
    if args.size:
        width, height = parse_pair(args.size, int, "--size")
    else:
        height = 900
        if dim == 3:
            width = 1200
        else:
            panel = min(1200, max(150, int(height * 1.15 * extent_across / extent_up) + 40))
            width = panel * len(times) + (180 if len(times) > 1 else 0)
    if width < 100 or height < 100 or width > 8000 or height > 8000:
        raise InputError("--size %d,%d: each side must be 100..8000 pixels" % (width, height))
    bar_width = 180 if len(times) > 1 else 0  # several panels: the colour bar in its own panel
    panel_width = max(100, (width - bar_width) // len(times))
    lut = pv.GetColorTransferFunction(args.field)
    lut.ApplyPreset("Viridis (matplotlib)", True)
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RescaleTransferFunction(lo, hi)
    if args.log:
        lut.UseLogScale = 1

    def view_of(size, t):
        view = pv.CreateRenderView()
        view.ViewSize = list(size)
        view.ViewTime = t
        view.Background = [1, 1, 1]
        try:  # ParaView >= 5.10 keeps the background in a palette unless told otherwise
            view.UseColorPaletteForBackground = 0
        except AttributeError:
            pass
        view.OrientationAxesVisibility = 0
        shown = pv.Show(reader, view)
        shown.Representation = "Surface"
        pv.ColorBy(shown, (association, args.field, "Magnitude") if components > 1 else (association, args.field))
        shown.LookupTable = lut
        lut.RescaleTransferFunction(lo, hi)  # ColorBy rescales to the data at hand
        if dim < 3:  # flat colours: a plane seen head-on is not shaded
            shown.Ambient = 1.0
            shown.Diffuse = 0.0
        else:  # faces told apart by a little shading, colours close to the bar's
            shown.Ambient = 0.4
            shown.Diffuse = 0.7
        return view, shown

    def show_bar(view, shown):
        shown.SetScalarBarVisibility(view, True)
        bar = pv.GetScalarBar(lut, view)
        bar.Title = title
        bar.ComponentTitle = ""
        bar.TitleColor = [0, 0, 0]
        bar.LabelColor = [0, 0, 0]
        bar.TitleFontSize = 16
        bar.LabelFontSize = 14
        bar.ScalarBarLength = 0.6
        bar.RangeLabelFormat = "%-#.3g"
        return bar

    def save(view, name, size):
        pv.Render(view)
        pv.SaveScreenshot(name, view, ImageResolution=list(size))
        pv.Delete(view)

    panels = []
    tmp = tempfile.mkdtemp(prefix="paraview_picture_")
    centre = [(bounds[2 * d] + bounds[2 * d + 1]) / 2 for d in range(3)]
    for k, t in enumerate(times):
        view, shown = view_of((panel_width, height), t)
        if len(times) == 1:
            show_bar(view, shown)
        if dim == 3:
            o = pv.Show(pv.Outline(Input=reader), view)
            o.DiffuseColor = [0, 0, 0]
            o.AmbientColor = [0, 0, 0]
            view.CameraFocalPoint = centre
            view.CameraPosition = [centre[0] + 1, centre[1] + 0.6, centre[2] + 1.6]
            view.CameraViewUp = [0, 1, 0]
            view.ResetCamera()
        else:
            view.InteractionMode = "2D"
            view.CameraFocalPoint = centre
            view.CameraPosition = [centre[0], centre[1], centre[2] + 1]
            view.CameraViewUp = [1, 0, 0] if dim == 1 else [0, 1, 0]
            view.ResetCamera()
            # fit the domain into the panel with a margin (room for the time label)
            aspect = panel_width / height
            view.CameraParallelScale = 0.55 * max(extent_up, extent_across / aspect) * 1.08
        text = pv.Text(Text=label_of_time(t))
        tv = pv.Show(text, view)
        tv.Color = [0, 0, 0]
        tv.FontSize = 16
        tv.WindowLocation = "Upper Center"
        name = os.path.join(tmp, "panel_%03d.png" % k)
        save(view, name, (panel_width, height))
        panels.append(name)
    if len(times) > 1:  # the shared colour bar
        view, shown = view_of((bar_width, height), times[-1])
        shown.Opacity = 0
        bar = show_bar(view, shown)
        bar.WindowLocation = "Any Location"
        bar.Position = [0.15, 0.2]
        name = os.path.join(tmp, "panel_bar.png")
        save(view, name, (bar_width, height))
        panels.append(name)

    if len(panels) == 1:
        os.replace(panels[0], out)
    else:  # one row of panels
        import matplotlib.image as mpimg
        images = [mpimg.imread(p) for p in panels]
        h = min(i.shape[0] for i in images)
        mpimg.imsave(out, np.concatenate([i[:h] for i in images], axis=1))
        for p in panels:
            os.remove(p)
    try:
        os.rmdir(tmp)
    except OSError:
        pass
    return out


if __name__ == "__main__":
    sys.exit(main())
