#!/usr/bin/python3
"""A two-tissue copy of a peer cube mesh: every "tissue" tetrahedron (physical volume 1) whose
centroid lies at x >= X_SPLIT becomes physical volume 3; the "bone" (2) and the "fixed" faces (1)
stay. Vertices and tetrahedra are the same as the input's, so results on both meshes compare
vertex by vertex. Written as gmsh 2.2 (physical and elementary tag per element).

usage: /usr/bin/python3 two_tissue_mesh.py IN.msh OUT.msh [X_SPLIT (default 40)]
Needs Debian's python3-gmsh and python3-numpy.
"""
import sys
import gmsh
import numpy as np

source, target = sys.argv[1], sys.argv[2]
x_split = float(sys.argv[3]) if len(sys.argv) > 3 else 40.0

gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.open(source)
node_tags, coordinates, _ = gmsh.model.mesh.getNodes()
position = dict(zip(node_tags, coordinates.reshape(-1, 3)))


def elements(dim, physical):
    """(element type, node tags per element) of every entity in a physical group."""
    blocks = []
    for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, physical):
        types, _, nodes = gmsh.model.mesh.getElements(dim, entity)
        for t, n in zip(types, nodes):
            blocks.append((int(t), np.asarray(n, dtype=np.int64).reshape(-1, 3 if dim == 2 else 4)))
    return blocks


lines, counts = [], {1: 0, 2: 0, 3: 0}
for element_type, nodes in elements(2, 1):
    for n in nodes:
        lines.append((element_type, 1, n))
for physical in (1, 2):
    for element_type, nodes in elements(3, physical):
        for n in nodes:
            tag = physical
            if physical == 1 and np.mean([position[k][0] for k in n]) >= x_split:
                tag = 3
            counts[tag] += 1
            lines.append((element_type, tag, n))
gmsh.finalize()

with open(target, "w") as out:
    out.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n")
    out.write('$PhysicalNames\n4\n2 1 "fixed"\n3 1 "tissue"\n3 2 "bone"\n3 3 "tissue x>=%g"\n'
              "$EndPhysicalNames\n" % x_split)
    out.write("$Nodes\n%d\n" % len(node_tags))
    for tag in sorted(position):
        x = position[tag]
        out.write("%d %.17g %.17g %.17g\n" % (tag, x[0], x[1], x[2]))
    out.write("$EndNodes\n$Elements\n%d\n" % len(lines))
    for number, (element_type, tag, n) in enumerate(lines, 1):
        out.write("%d %d 2 %d %d %s\n" % (number, element_type, tag, tag, " ".join(map(str, n))))
    out.write("$EndElements\n")
print("tetrahedra: tissue %d, tissue x >= %g %d, bone %d" % (counts[1], x_split, counts[3], counts[2]))
