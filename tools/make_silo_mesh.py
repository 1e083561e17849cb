#!/usr/bin/python3
"""Coarse hexahedral meshes for granhydro's 'Domain/Mesh file' (python3, standard library only).

A mesh is a set of occupied blocks of a lattice (congruent axis-aligned boxes, the only meshes
granhydro accepts) written as gmsh 2.2 ASCII (.msh) or ucd (.inp). Every boundary face gets a
physical tag = boundary id, which the scene maps to its 'Boundary x-' .. 'Boundary z+' entries:
0 = x-, 1 = x+, 2 = y-, 3 = y+, 4 = z-, 5 = z+ (the id names the entry; the face's direction
comes from the geometry).

Default output: meshes/silo_3d.msh, a flat-bottomed silo (quasi-2D slot silo) discharging
through a centred orifice into a short outlet channel (all lengths in m):

            x = 0                 x = 0.040
    y=0.068 +----------------------+        lid: id 3 (y+)
            |                      |
            |        bin           |        side walls: id 0 (x-), id 1 (x+)
            |   40 mm x 60 mm      |        front/back (z = 0, 0.010): id 4 (z-), id 5 (z+)
            |   10 mm deep (z)     |
    y=0.008 +--------+    +--------+        floor (faces up into the bin): id 3 (y+)
                     |    |                 outlet side walls: id 0 / id 1
                     |    |  outlet channel x in [0.016, 0.024], 8 mm tall, full depth
    y=0     .        +----+                 outlet bottom: id 2 (y-)  -> set it to outflow
                x=0.016  x=0.024

The orifice is the 8 mm x 10 mm opening of the floor at y = 8 mm. Coarse blocks are
4 mm (x) x 4 mm (y) x 5 mm (z): 10 x 17 x 2 lattice, 308 blocks; 'Mesh refinements' halves
them (2 refinements: 1 x 1 x 1.25 mm cells, 19712 cells).

Usage:
  tools/make_silo_mesh.py                       # meshes/silo_3d.msh
  tools/make_silo_mesh.py out.msh               # the silo, elsewhere
  tools/make_silo_mesh.py --box 2 out.msh       # test boxes with colorized ids (tests/data)
  tools/make_silo_mesh.py --box 3 out.msh
  tools/make_silo_mesh.py --box 2 out.inp
"""
import argparse
import os


def boundary_faces(blocks, dim):
    """(block, direction d, side 0/1) of every face without a neighbouring block."""
    occupied = set(blocks)
    for b in sorted(blocks):
        for d in range(dim):
            for side in (0, 1):
                n = list(b)
                n[d] += 1 if side else -1
                if tuple(n) not in occupied:
                    yield b, d, side


def corner(b, offsets):
    return tuple(b[k] + offsets[k] for k in range(len(b)))


# vertex orders (offsets from the block's lower corner)
HEX = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
QUAD2D = [(0, 0), (1, 0), (1, 1), (0, 1)]


def face_vertices(b, d, side, dim):
    """vertices of the face of block b normal to d on side, in cyclic order"""
    if dim == 2:
        t = 1 - d
        o0 = [0, 0]
        o0[d] = side
        o1 = list(o0)
        o1[t] = 1
        return [corner(b, o0), corner(b, o1)]
    a, c = [k for k in range(3) if k != d]
    out = []
    for (u, v) in [(0, 0), (1, 0), (1, 1), (0, 1)]:
        o = [0, 0, 0]
        o[d], o[a], o[c] = side, u, v
        out.append(corner(b, o))
    return out


def write_mesh(path, dim, blocks, lower, h, face_id):
    """blocks: lattice indices of the occupied blocks; face_id(block, d, side) -> boundary id"""
    cells = []
    # x fastest, like deal.II's GridGenerator: a box from a file gets the same coarse cell
    # order, hence the same p4est partition and DoF numbering as the generated box
    blocks = sorted(blocks, key=lambda b: b[::-1])
    for b in blocks:
        order = HEX if dim == 3 else QUAD2D
        cells.append([corner(b, o) for o in order])
    faces = [(face_vertices(b, d, s, dim), face_id(b, d, s)) for b, d, s in boundary_faces(blocks, dim)]
    nodes = {}
    for vs in cells:
        for v in vs:
            nodes.setdefault(v, len(nodes) + 1)

    def coords(v):
        x = [lower[k] + v[k] * h[k] for k in range(dim)] + [0.0] * (3 - dim)
        return " ".join(repr(float(c)) for c in x)  # repr: exact round trip

    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w") as f:
        if path.endswith(".msh"):
            f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(nodes))
            for v, i in nodes.items():
                f.write("%d %s\n" % (i, coords(v)))
            f.write("$EndNodes\n$Elements\n%d\n" % (len(faces) + len(cells)))
            k = 0
            ftype, ctype = (3, 5) if dim == 3 else (1, 3)
            for vs, bid in faces:  # physical tag = elementary tag = boundary id
                k += 1
                f.write("%d %d 2 %d %d %s\n" % (k, ftype, bid, bid, " ".join(str(nodes[v]) for v in vs)))
            for vs in cells:  # material id 0
                k += 1
                f.write("%d %d 2 0 100 %s\n" % (k, ctype, " ".join(str(nodes[v]) for v in vs)))
            f.write("$EndElements\n")
        elif path.endswith(".inp"):
            assert dim == 2, "ucd output is written for 2D meshes only"
            f.write("%d %d 0 0 0\n" % (len(nodes), len(faces) + len(cells)))
            for v, i in nodes.items():
                f.write("%d %s\n" % (i, coords(v)))
            k = 0
            for vs in cells:
                k += 1
                f.write("%d 0 quad %s\n" % (k, " ".join(str(nodes[v]) for v in vs)))
            for vs, bid in faces:
                k += 1
                f.write("%d %d line %s\n" % (k, bid, " ".join(str(nodes[v]) for v in vs)))
        else:
            raise SystemExit("unknown extension of " + path)


def silo(path):
    h = (0.004, 0.004, 0.005)
    nx, ny, nz = 10, 17, 2
    outlet_x = (4, 5)  # x in [16, 24) mm
    outlet_y = 2       # y in [0, 8) mm: outlet channel; bin above
    blocks = [(i, j, k) for i in range(nx) for j in range(ny) for k in range(nz)
              if j >= outlet_y or i in outlet_x]

    def face_id(b, d, side):
        if d == 0:
            return side        # side walls of bin and outlet: 0 (x-), 1 (x+)
        if d == 2:
            return 4 + side    # front/back: 4 (z-), 5 (z+)
        if side == 0 and b[1] == 0:
            return 2           # bottom of the outlet channel: y-, the outflow
        return 3               # lid and floor of the bin: y+

    write_mesh(path, 3, blocks, (0.0, 0.0, 0.0), h, face_id)
    print("wrote %s: %d blocks" % (path, len(blocks)))


def box(dim, path):
    """[0, 1] x [0, 0.75] (x [0, 0.5]) with colorized ids, dyadic coordinates (exact)"""
    n = (4, 3, 2)[:dim]
    h = (0.25,) * dim
    blocks = [(i, j) for i in range(n[0]) for j in range(n[1])] if dim == 2 else \
             [(i, j, k) for i in range(n[0]) for j in range(n[1]) for k in range(n[2])]
    write_mesh(path, dim, blocks, (0.0,) * dim, h, lambda b, d, s: 2 * d + s)
    print("wrote %s: %d blocks" % (path, len(blocks)))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("path", nargs="?", default=None,
                   help="the mesh file to write, .msh (gmsh 2.2) or .inp (ucd, 2D only); "
                        "default: meshes/silo_3d.msh of this checkout")
    p.add_argument("--box", type=int, choices=(2, 3), metavar="DIM",
                   help="write the test box of dimension DIM (2 or 3) with colorized ids to PATH "
                        "instead of the silo")
    a = p.parse_args()
    if a.box:
        if a.path is None:
            p.error("--box DIM needs the file to write: --box DIM PATH")
        box(a.box, a.path)
    else:
        root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        silo(a.path or os.path.join(root, "meshes", "silo_3d.msh"))


if __name__ == "__main__":
    main()
