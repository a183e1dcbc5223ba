#!/usr/bin/python3
"""CalculiX peer of softface's `linear fem` on a make_mesh.py cube (approach borrowed from
benchmarks/calculix/make_case.py, but reading the existing .msh instead of meshing).

usage: calculix_case.py prepare MESH.msh DIR [--nlgeom]
                                               writes DIR/case.inp (+ DIR/nodes.npy), prints JSON
       calculix_case.py collect DIR OUT.csv    reads DIR/case.dat, writes x,y,z,ux,uy,uz, prints JSON
The driver runs `ccx -i case` in DIR between the two (static, C3D4, default SPOOLES). With
--nlgeom the step is geometrically nonlinear: *ELASTIC is then St. Venant-Kirchhoff. CalculiX's
automatic incrementation starts at a tenth of the load; residual and correction tolerances 1e-9
(as benchmarks/calculix/make_case.py).

Conditions: nodes of physical surface 1 ("fixed"): u = 0; nodes of physical volume 2 ("bone",
including its surface): u = (0, 0, 6). E = 3000, nu = 0.46 (the displacements do not depend on E).
"""
import sys, os, json, time
import numpy as np

E, NU, UZ = 3000.0, 0.46, 6.0


def nset(f, name, tags):
    f.write(f"*NSET,NSET={name}\n")
    for k in range(0, len(tags), 16):
        f.write(",".join(str(v) for v in tags[k:k + 16]) + "\n")


def prepare(msh, out, nlgeom=False):
    import gmsh
    t0 = time.perf_counter()
    os.makedirs(out, exist_ok=True)
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.open(msh)
    ntags, coords, _ = gmsh.model.mesh.getNodes()
    coords = coords.reshape(-1, 3)
    o = np.argsort(ntags)
    ntags, coords = ntags[o], coords[o]
    et, _, en = gmsh.model.mesh.getElements(3)
    assert list(et) == [4], f"only linear tetrahedra expected, got gmsh types {et}"
    tets = en[0].reshape(-1, 4)
    # Only nodes of tetrahedra: gmsh can leave a stray node in a volume that no element uses
    # (one in cube_h2.88.msh); softface and dolfinx drop such nodes too.
    used = np.isin(ntags, tets)
    ntags, coords = ntags[used], coords[used]
    fixed = set(int(v) for v in gmsh.model.mesh.getNodesForPhysicalGroup(2, 1)[0])
    bone = np.array(sorted(set(int(v) for v in gmsh.model.mesh.getNodesForPhysicalGroup(3, 2)[0])))
    gmsh.finalize()
    fixed = np.array(sorted(fixed - set(bone.tolist())))
    with open(os.path.join(out, "case.inp"), "w") as f:
        f.write("*NODE,NSET=NALL\n")
        f.writelines("%d,%.12g,%.12g,%.12g\n" % (t, *x) for t, x in zip(ntags, coords))
        f.write("*ELEMENT,TYPE=C3D4,ELSET=EALL\n")
        f.writelines("%d,%d,%d,%d,%d\n" % (i + 1, *e) for i, e in enumerate(tets))
        nset(f, "NFIX", fixed)
        nset(f, "NBONE", bone)
        f.write("*MATERIAL,NAME=TISSUE\n*ELASTIC\n%.6e,%.4f\n" % (E, NU))
        f.write("*SOLID SECTION,ELSET=EALL,MATERIAL=TISSUE\n")
        if nlgeom:
            f.write("*STEP,NLGEOM,INC=1000\n*STATIC\n0.1,1.\n"
                    "*CONTROLS,PARAMETERS=FIELD\n1.e-9,1.e-9,,,,,,\n")
        else:
            f.write("*STEP\n*STATIC\n")
        f.write("*BOUNDARY\nNFIX,1,3,0.\nNBONE,1,2,0.\nNBONE,3,3,%g\n" % UZ)
        # .dat has 7 significant digits (.frd only 6): read displacements from there.
        f.write("*NODE PRINT,NSET=NALL\nU\n*END STEP\n")
    np.save(os.path.join(out, "nodes.npy"), np.hstack([ntags[:, None].astype(float), coords]))
    return dict(n_nodes=len(ntags), n_tets=len(tets), n_fixed=len(fixed), n_bone=len(bone),
                prepare_s=time.perf_counter() - t0)


def collect(out, csv):
    """Last displacement block of case.dat -> CSV in node order."""
    lines = open(os.path.join(out, "case.dat")).read().splitlines()
    s = [i for i, l in enumerate(lines) if l.strip().startswith("displacements (vx,vy,vz)")][-1] + 1
    disp = {}
    for l in lines[s:]:
        p = l.split()
        if not p:
            if disp:
                break
            continue
        disp[int(p[0])] = [float(v) for v in p[1:4]]
    nodes = np.load(os.path.join(out, "nodes.npy"))
    U = np.array([disp[int(t)] for t in nodes[:, 0]])
    np.savetxt(csv, np.hstack([nodes[:, 1:], U]), delimiter=",", header="x,y,z,ux,uy,uz",
               comments="", fmt="%.12g")
    return dict(n_nodes=len(U), max_u=float(np.abs(U).max()))


if __name__ == "__main__":
    cmd, a, b = sys.argv[1:4]
    print(json.dumps(prepare(a, b, "--nlgeom" in sys.argv[4:]) if cmd == "prepare" else
                     collect(a, b)))
