"""Write the unit cube split into six tetrahedra (Kuhn) as VTK XML .vtu in
three encodings, following the VTK file-format specification independently of
softface's reader. Cell data "gmsh:physical": tetrahedra 7; the 12 boundary
triangles get 3 on the face z = 0 and 4 elsewhere.

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

# Boundary triangles: faces of the tetrahedra that lie in a cube face.
triangles, ids = [], []
for tet in tets:
    for face in itertools.combinations(tet, 3):
        for axis in range(3):
            for value in (0, 1):
                if all(points[i][axis] == value for i in face):
                    triangles.append(list(face))
                    ids.append(3 if (axis == 2 and value == 0) else 4)
cells = tets + triangles
cell_ids = [7] * len(tets) + ids
connectivity = [i for c in cells for i in c]
offsets = list(itertools.accumulate(len(c) for c in cells))
types = [10] * len(tets) + [5] * len(triangles)

arrays = [  # (section, name, vtk type, struct code, components, values)
    ("Points", "Points", "Float64", "d", 3, [x for p in points for x in p]),
    ("Cells", "connectivity", "Int64", "q", 1, connectivity),
    ("Cells", "offsets", "Int64", "q", 1, offsets),
    ("Cells", "types", "UInt8", "B", 1, types),
    ("CellData", "gmsh:physical", "Int32", "i", 1, cell_ids),
]


def write(filename, encoding, compressed, header):
    hcode = "Q" if header == "UInt64" else "I"
    appended = b""
    body = {}
    for section, name, vtype, code, ncomp, values in arrays:
        data = struct.pack("<%d%s" % (len(values), code), *values)
        if compressed:
            block = zlib.compress(data)
            head = struct.pack("<4" + hcode, 1, len(data), len(data), len(block))
            payload = (head, block)
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
    comp = ' compressor="vtkZLibDataCompressor"' if compressed else ""
    out = (f'<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" '
           f'byte_order="LittleEndian" header_type="{header}"{comp}>\n<UnstructuredGrid>\n'
           f'<Piece NumberOfPoints="{len(points)}" NumberOfCells="{len(cells)}">\n')
    for section in ("Points", "Cells", "CellData"):
        out += f"<{section}>\n" + "\n".join(body[section]) + f"\n</{section}>\n"
    out += "</Piece>\n</UnstructuredGrid>\n"
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
