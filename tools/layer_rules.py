#!/usr/bin/python3
"""Check the include direction between granhydro's layers.

Usage: tools/layer_rules.py [--root DIR]

Each folder of include/granhydro/ and source/ is a layer; a file may include
granhydro headers only from its own layer and the layers below it
(doc/developer.md, "Architecture"):

    base < physics < boundary < mesh < {convection, diffusion, io} < scene < driver < main.cc

convection, diffusion and io are side by side (none includes another), and nothing
below driver/ includes scene/: each layer takes its own settings struct.

A layer's internal headers (not installed) live beside its sources, e.g.
source/mesh/lattice.h, and are included with quotes ("lattice.h") only from the
same folder of source/: an installed header (include/granhydro/...) includes no
quoted header, and a source file includes only quoted headers of its own folder.
Prints every include that breaks the rules and exits with 1 if there is one.
"""
import argparse
import pathlib
import re
import sys

BELOW = {
    "base": set(),
    "physics": {"base"},
    "boundary": {"base", "physics"},
    "mesh": {"base", "physics", "boundary"},
    "convection": {"base", "physics", "boundary", "mesh"},
    "diffusion": {"base", "physics", "boundary", "mesh"},
    "io": {"base", "physics", "boundary", "mesh"},
    "scene": {"base", "physics", "boundary", "mesh", "convection", "diffusion", "io"},
    "driver": {"base", "physics", "boundary", "mesh", "convection", "diffusion", "io", "scene"},
}
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]granhydro/([A-Za-z_]+)/', re.M)
LOCAL = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.M)


def layer_of(path, root):
    parts = path.relative_to(root).parts
    if parts[0] == "include" and len(parts) > 3:
        return parts[2]
    if parts[0] == "source" and len(parts) > 2:
        return parts[1]
    return None  # source/main.cc: the top, may include anything


def local_include_errors(f, root):
    """quoted includes: none in installed headers; in source/, files of the same folder only"""
    bad = []
    text = f.read_text()
    installed = f.relative_to(root).parts[0] == "include"
    for m in LOCAL.finditer(text):
        line = text.count("\n", 0, m.start()) + 1
        target = (f.parent / m.group(1)).resolve()
        if installed:
            bad.append("%s:%d: an installed header includes \"%s\" (internal headers are not installed)" %
                       (f.relative_to(root), line, m.group(1)))
        elif target.parent != f.parent.resolve() or not target.exists():
            bad.append("%s:%d: \"%s\" is not an internal header of this folder" %
                       (f.relative_to(root), line, m.group(1)))
    return bad


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--root", default=pathlib.Path(__file__).resolve().parent.parent, type=pathlib.Path,
                   help="the checkout (default: the one of this script)")
    root = p.parse_args().root.resolve()
    files = sorted(f for d in ("include", "source") for f in (root / d).rglob("*") if f.suffix in (".h", ".cc"))
    bad = []
    for f in files:
        layer = layer_of(f, root)
        if layer is None:
            continue
        if layer not in BELOW:
            bad.append("%s: folder %r is not a known layer (add it to tools/layer_rules.py)" %
                       (f.relative_to(root), layer))
            continue
        for m in INCLUDE.finditer(f.read_text()):
            other = m.group(1)
            if other != layer and other not in BELOW[layer]:
                line = f.read_text().count("\n", 0, m.start()) + 1
                bad.append("%s:%d: %s/ includes %s/ (allowed: %s)" % (
                    f.relative_to(root), line, layer, other, ", ".join(sorted(BELOW[layer] | {layer}))))
        bad += local_include_errors(f, root)
    for b in bad:
        print(b)
    print("%d files, %d includes against the layer order" % (len(files), len(bad)))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
