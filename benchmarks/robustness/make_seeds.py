#!/usr/bin/python3
"""Write the fuzzer's mesh seeds (tests/data/mesh_seeds/box41.msh, box22.msh, box.vtk).

    /usr/bin/python3 make_seeds.py        (needs Debian's python3-gmsh)

[0,80]^3 with a conforming "bone" box [30,50]^3, h = 25 mm: a few hundred tetrahedra, so that
every fuzz case runs in about a second. gmsh 4.1 and 2.2 ASCII (physical volume 1 tissue,
2 bone; physical surface 1 the six outer faces), and legacy VTK written here from the same
mesh (CELL_DATA MaterialID 1/2, as deal.II's GridIn reads it).
"""
import os
import sys

import gmsh

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    out = os.path.join(HERE, "..", "..", "tests", "data", "mesh_seeds")
    os.makedirs(out, exist_ok=True)
    gmsh.initialize(["-nopopup"])
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    occ = gmsh.model.occ
    box = occ.addBox(0, 0, 0, 80, 80, 80)
    inner = occ.addBox(30, 30, 30, 20, 20, 20)
    occ.fragment([(3, box)], [(3, inner)])
    occ.synchronize()
    vols = [t for _, t in gmsh.model.getEntities(3)]
    bone = [t for t in vols
            if max(abs(a - b) for a, b in zip(gmsh.model.getBoundingBox(3, t),
                                              (30, 30, 30, 50, 50, 50))) < 1e-6]
    tissue = [t for t in vols if t not in bone]
    outer = [s for _, s in gmsh.model.getEntities(2)
             if any(abs(c) < 1e-6 or abs(c - 80) < 1e-6
                    for c in gmsh.model.getBoundingBox(2, s)[:3])
             and gmsh.model.getBoundingBox(2, s) is not None]
    outer = [s for s in outer if not any(
        abs(a - b) < 1e-6 for a, b in zip(gmsh.model.getBoundingBox(2, s), (30,) * 3))]
    gmsh.model.addPhysicalGroup(3, tissue, 1)
    gmsh.model.addPhysicalGroup(3, bone, 2)
    gmsh.model.addPhysicalGroup(2, outer, 1)
    for key, val in (("Mesh.CharacteristicLengthMin", 25), ("Mesh.CharacteristicLengthMax", 25),
                     ("Mesh.CharacteristicLengthFromPoints", 0), ("Mesh.Algorithm3D", 1),
                     ("Mesh.RandomSeed", 1)):
        gmsh.option.setNumber(key, val)
    gmsh.model.mesh.generate(3)
    gmsh.option.setNumber("Mesh.Binary", 0)
    gmsh.option.setNumber("Mesh.SaveAll", 0)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.write(os.path.join(out, "box41.msh"))
    gmsh.option.setNumber("Mesh.MshFileVersion", 2.2)
    gmsh.write(os.path.join(out, "box22.msh"))

    tags, xyz, _ = gmsh.model.mesh.getNodes()
    index = {int(t): i for i, t in enumerate(tags)}
    cells = []
    for material, volumes in ((1, tissue), (2, bone)):
        for v in volumes:
            types, _, nodes = gmsh.model.mesh.getElements(3, v)
            for t, n in zip(types, nodes):
                assert t == 4, "tetrahedra only"
                for k in range(0, len(n), 4):
                    cells.append((material, [index[int(x)] for x in n[k:k + 4]]))
    gmsh.finalize()
    with open(os.path.join(out, "box.vtk"), "w") as f:
        f.write("# vtk DataFile Version 3.0\nfuzz seed: box with a bone box\nASCII\n"
                "DATASET UNSTRUCTURED_GRID\nPOINTS %d double\n" % len(tags))
        for i in range(len(tags)):
            f.write("%.9g %.9g %.9g\n" % tuple(xyz[3 * i:3 * i + 3]))
        f.write("CELLS %d %d\n" % (len(cells), 5 * len(cells)))
        for _, c in cells:
            f.write("4 %d %d %d %d\n" % tuple(c))
        f.write("CELL_TYPES %d\n" % len(cells) + "10\n" * len(cells))
        f.write("CELL_DATA %d\nSCALARS MaterialID int 1\nLOOKUP_TABLE default\n" % len(cells))
        f.writelines("%d\n" % m for m, _ in cells)
    print("seeds: %d vertices, %d tetrahedra" % (len(tags), len(cells)))


if __name__ == "__main__":
    sys.exit(main())
