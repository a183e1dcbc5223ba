"""Write the unit cube split into six tetrahedra (Kuhn) as VTK XML .vtu in
three encodings, following the VTK file-format specification independently of
softface's reader. Cell data "gmsh:physical": tetrahedra 7; the 12 boundary
triangles get 3 on the face z = 0 and 4 elsewhere.

The same cube is also written as a parallel writer would, in several <Piece>s
(cube6_pieces_*.vtu): each piece numbers its own points, so the points on the
interfaces between pieces appear once per piece. The pieces also carry what a
reader has to skip: a vertex and a line cell, an empty piece, and a ghost copy
of a tetrahedron of another piece (vtkGhostType 1, as VTK marks duplicates).

usage: /usr/bin/python3 make_vtu.py   (writes cube6_*.vtu here)
"""
import base64
import itertools
import struct
import zlib

points = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
index = {p: i for i, p in enumerate(points)}


def signed_volume(a, b, c, d):
    u = [b[i] - a[i] for i in range(3)]
    v = [c[i] - a[i] for i in range(3)]
    w = [d[i] - a[i] for i in range(3)]
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0])) / 6


tets = []
for path in itertools.permutations(range(3)):
    corner = [0, 0, 0]
    tet = [index[tuple(corner)]]
    for axis in path:
        corner[axis] += 1
        tet.append(index[tuple(corner)])
    if signed_volume(*[points[i] for i in tet]) < 0:
        tet[1], tet[2] = tet[2], tet[1]
    tets.append(tet)

# Boundary triangles: faces of the tetrahedra that lie in a cube face
# (triangles_of[t] lists those of tetrahedron t).
triangles, ids, triangles_of = [], [], []
for tet in tets:
    triangles_of.append([])
    for face in itertools.combinations(tet, 3):
        for axis in range(3):
            for value in (0, 1):
                if all(points[i][axis] == value for i in face):
                    triangles_of[-1].append(len(triangles))
                    triangles.append(list(face))
                    ids.append(3 if (axis == 2 and value == 0) else 4)
one_piece = {
    "points": points,
    "cells": tets + triangles,
    "types": [10] * len(tets) + [5] * len(triangles),
    "ids": [7] * len(tets) + ids,
}


def piece(tet_numbers, extra_cells=(), ghosts=()):
    """The tetrahedra tet_numbers with their boundary triangles, then
    extra_cells (VTK type, global point numbers) with id 9, then ghost copies
    of the tetrahedra ghosts. Points are numbered locally in order of first
    use, so that they differ from the global numbering."""
    cells, types, cell_ids = [], [], []
    for t in tet_numbers:
        cells.append(tets[t])
        types.append(10)
        cell_ids.append(7)
    for t in tet_numbers:
        for f in triangles_of[t]:
            cells.append(triangles[f])
            types.append(5)
            cell_ids.append(ids[f])
    for vtk_type, cell in extra_cells:
        cells.append(cell)
        types.append(vtk_type)
        cell_ids.append(9)
    for t in ghosts:
        cells.append(tets[t])
        types.append(10)
        cell_ids.append(7)
    local = {}
    for c in cells:
        for i in c:
            local.setdefault(i, len(local))
    return {
        "points": [points[i] for i in local],
        "cells": [[local[i] for i in c] for c in cells],
        "types": types,
        "ids": cell_ids,
        "ghost": [0] * (len(cells) - len(ghosts)) + [1] * len(ghosts),
    }


def arrays_of(p, point_type, index_type):
    """(section, name, vtk type, struct code, components, values) of piece p."""
    codes = {"Float64": "d", "Float32": "f", "Int64": "q", "Int32": "i"}
    arrays = [
        ("Points", "Points", point_type, codes[point_type], 3,
         [x for q in p["points"] for x in q]),
        ("Cells", "connectivity", index_type, codes[index_type], 1,
         [i for c in p["cells"] for i in c]),
        ("Cells", "offsets", index_type, codes[index_type], 1,
         list(itertools.accumulate(len(c) for c in p["cells"]))),
        ("Cells", "types", "UInt8", "B", 1, p["types"]),
        ("CellData", "gmsh:physical", "Int32", "i", 1, p["ids"]),
    ]
    if "ghost" in p:
        arrays.append(("CellData", "vtkGhostType", "UInt8", "B", 1, p["ghost"]))
    return arrays


def compress(data, hcode, block_size):
    """zlib blocks of block_size bytes (one block if None), VTK's header."""
    size = block_size or max(len(data), 1)
    blocks = [zlib.compress(data[i:i + size]) for i in range(0, len(data), size)]
    last = len(data) - (len(blocks) - 1) * size if blocks else 0
    head = struct.pack("<%d%s" % (3 + len(blocks), hcode), len(blocks),
                       len(data) if block_size is None else block_size, last,
                       *[len(b) for b in blocks])
    return head, b"".join(blocks)


def write(filename, encoding, compressed, header, pieces=(one_piece,),
          point_type="Float64", index_type="Int64", block_size=None):
    hcode = "Q" if header == "UInt64" else "I"
    appended = b""
    comp = ' compressor="vtkZLibDataCompressor"' if compressed else ""
    out = (f'<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" '
           f'byte_order="LittleEndian" header_type="{header}"{comp}>\n<UnstructuredGrid>\n')
    for p in pieces:
        body = {}
        for section, name, vtype, code, ncomp, values in arrays_of(p, point_type, index_type):
            data = struct.pack("<%d%s" % (len(values), code), *values)
            if compressed:
                payload = compress(data, hcode, block_size)
            else:
                payload = (struct.pack("<" + hcode, len(data)), data)
            attrs = f'type="{vtype}" Name="{name}" NumberOfComponents="{ncomp}"'
            if encoding == "ascii":
                text = " ".join(str(v) for v in values)
                xml = f'<DataArray {attrs} format="ascii">{text}</DataArray>'
            elif encoding == "binary":
                # header and data as two base64 streams, as VTK writes them
                text = (base64.b64encode(payload[0]) + base64.b64encode(payload[1])).decode()
                xml = f'<DataArray {attrs} format="binary">{text}</DataArray>'
            else:
                xml = f'<DataArray {attrs} format="appended" offset="{len(appended)}"/>'
                appended += payload[0] + payload[1]
            body.setdefault(section, []).append(xml)
        out += (f'<Piece NumberOfPoints="{len(p["points"])}" '
                f'NumberOfCells="{len(p["cells"])}">\n')
        for section in ("Points", "Cells", "CellData"):
            out += f"<{section}>\n" + "\n".join(body[section]) + f"\n</{section}>\n"
        out += "</Piece>\n"
    out += "</UnstructuredGrid>\n"
    raw = out.encode()
    if encoding == "appended":
        raw += b'<AppendedData encoding="raw">\n_' + appended + b"\n</AppendedData>\n"
    raw += b"</VTKFile>\n"
    with open(filename, "wb") as f:
        f.write(raw)


write("cube6_ascii.vtu", "ascii", False, "UInt32")
write("cube6_binary_zlib.vtu", "binary", True, "UInt64")
write("cube6_appended_raw.vtu", "appended", False, "UInt32")
write("cube6_appended_zlib.vtu", "appended", True, "UInt64")

# Three pieces of two tetrahedra each. In ascii with an empty piece, a vertex
# and a line cell, and piece 1 carrying a ghost copy of tetrahedron 0; appended
# raw + zlib in blocks of 32 bytes (several blocks per array, the last one
# partial) with 32-bit headers, Float32 points and Int32 indices.
empty = {"points": [], "cells": [], "types": [], "ids": [], "ghost": []}
write("cube6_pieces_ascii.vtu", "ascii", False, "UInt32",
      pieces=[piece([0, 1], extra_cells=[(1, [7])]),
              piece([2, 3], extra_cells=[(3, [0, 7])], ghosts=[0]),
              empty,
              piece([4, 5])])
write("cube6_pieces_appended_zlib.vtu", "appended", True, "UInt32",
      pieces=[piece([4, 5]), piece([0, 1]), piece([2, 3])],
      point_type="Float32", index_type="Int32", block_size=32)
