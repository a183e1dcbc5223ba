#!/usr/bin/python3
"""The paper's cube benchmark (Fig. 2) meshed by gmsh: the box [0,80]^3 mm with the inner box
[35,45]^3 mm meshed conformingly, P1 tetrahedra of size H.

Physical groups: volume 1 "tissue", volume 2 "bone" (the inner box), surface 1 "fixed" (the six
outer faces). softface, FEniCSx and CalculiX all read the same file.

usage: make_mesh.py H OUT.msh [--offcentre]
       (H = 4.3: about 30k tetrahedra, 2.88: 98k, 1.68: 486k)

--offcentre: the harder geometry of the nonlinear solver cases instead: the bone box [20,35]x[30,45]x[40,55] mm and
only the four side faces x = 0, 80 and y = 0, 80 in "fixed" (top and bottom traction free).
"""
import sys
import gmsh

H, OUT = float(sys.argv[1]), sys.argv[2]
OFFCENTRE = "--offcentre" in sys.argv[3:]
L = 80.0
LO, HI = ([20.0, 30.0, 40.0], [35.0, 45.0, 55.0]) if OFFCENTRE else ([35.0] * 3, [45.0] * 3)
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("cube")
occ = gmsh.model.occ
outer = occ.addBox(0, 0, 0, L, L, L)
inner = occ.addBox(*LO, *(h - l for l, h in zip(LO, HI)))
occ.fragment([(3, outer)], [(3, inner)])
occ.synchronize()
volumes = [t for (d, t) in gmsh.model.getEntities(3)]
tissue = max(volumes, key=lambda t: occ.getMass(3, t))
bone = [t for t in volumes if t != tissue][0]
outer_faces = []
for (d, t) in gmsh.model.getEntities(2):
    x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(2, t)
    for lo, hi, z in ((x0, x1, False), (y0, y1, False), (z0, z1, True)):
        if (abs(lo) < 1e-6 and abs(hi) < 1e-6 or abs(lo - L) < 1e-6 and abs(hi - L) < 1e-6) \
                and not (OFFCENTRE and z):
            outer_faces.append(t)
assert len(outer_faces) == (4 if OFFCENTRE else 6), outer_faces
gmsh.model.addPhysicalGroup(3, [tissue], 1)
gmsh.model.setPhysicalName(3, 1, "tissue")
gmsh.model.addPhysicalGroup(3, [bone], 2)
gmsh.model.setPhysicalName(3, 2, "bone")
gmsh.model.addPhysicalGroup(2, outer_faces, 1)
gmsh.model.setPhysicalName(2, 1, "fixed")
gmsh.option.setNumber("Mesh.CharacteristicLengthMin", H)
gmsh.option.setNumber("Mesh.CharacteristicLengthMax", H)
gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
gmsh.option.setNumber("Mesh.Binary", 0)
gmsh.model.mesh.generate(3)
gmsh.write(OUT)
types, tags, _ = gmsh.model.mesh.getElements(3)
print(f"{OUT}: {sum(len(t) for t in tags)} tetrahedra, "
      f"{len(gmsh.model.mesh.getNodes()[0])} nodes")
gmsh.finalize()
