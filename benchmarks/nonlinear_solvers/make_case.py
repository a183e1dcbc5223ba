#!/usr/bin/python3
"""Build one nonlinear-solver measurement case: gmsh mesh, softface scenes, CalculiX NLGEOM run.

    /usr/bin/python3 make_case.py cases/NAME.json [OUTDIR] [--no-ccx | --parse-only]

OUTDIR defaults to /tmp/nl/NAME. --no-ccx (or --mesh-only) writes the mesh and inputs but does not
run CalculiX; --parse-only re-reads the outputs of an earlier CalculiX run in OUTDIR. The mesh is
remade every time (gmsh is deterministic for a given case and gmsh version). The case description (JSON) holds

    box          [LX, LY, LZ]            outer box [0,LX]x[0,LY]x[0,LZ] (mm)
    inner_min, inner_max                 the "bone" box, meshed conformingly inside the outer box
    h                                    target edge length (mm) of the tetrahedra
    fixed_faces  subset of x0,x1,y0,y1,z0,z1   outer faces held (u = 0); the others are free
    rotation     {"axis": [..], "angle_deg": a}   rotation about the axis through the inner box's
                                         centre c, right-handed, degrees
    translation  [tx, ty, tz]            applied after the rotation: x -> R (x - c) + c + t
    E_MPa, nu                            0.003 N/mm^2 (= 3000 Pa) and 0.46 unless given
    calculix     optional {"initial": 0.1, "minimum": 1e-5, "max_increments": 400,
                           "tolerance": 1e-9, "timeout_s": 1800, "threads": 1}
                                         (tolerance null: CalculiX's default field controls)

Writes into OUTDIR:
    mesh.msh                   gmsh 4.1, physical volumes 1 tissue / 2 bone, physical surface 1 fixed
                               (deal.II's GridIn: material ids 1/2, boundary id 1)
    scene.prm                  softface, 'nonlinear fem' St. Venant-Kirchhoff
    scene_neo_hooke.prm        softface, 'nonlinear fem' compressible Neo-Hooke
    scene_reference.prm        softface, 'reference fem' (P2) Neo-Hooke
    mesh.inc, ccx_nl.inp       CalculiX input (C3D4, *ELASTIC under NLGEOM = St. Venant-Kirchhoff)
    ccx_nl.sta, ccx_nl.cvg, ccx_nl.log   CalculiX's increment and iteration logs
    ccx_nl.dat                 CalculiX's displacements at every converged increment
    calculix_nl_displacements.csv        x,y,z,ux,uy,uz at the last converged increment
    calculix_nl_displacements_LOAD.csv   the same at every converged increment (LOAD: %.7f)
    calculix_nl_increments.csv           load, min det F over the tetrahedra, tetrahedra inverted,
                               per converged increment
    result.json                case, mesh counts, prescribed motion, CalculiX outcome:
                               load reached, increments, cut-backs, iterations, wall time,
                               min volume ratio det(F) over the tetrahedra of the final state,
                               and per converged increment (the last load with none inverted)
    tet_rows.npy               the tetrahedra as 0-based rows of the CSV (for volume ratios)
"""
import json
import math
import os
import re
import subprocess
import sys
import time

import numpy as np

FACES = ("x0", "x1", "y0", "y1", "z0", "z1")


def rotation_matrix(axis, angle_deg):
    """Rodrigues: right-handed rotation by angle_deg about the unit vector along axis."""
    a = np.asarray(axis, float)
    a = a / np.linalg.norm(a)
    th = math.radians(angle_deg)
    K = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    return np.eye(3) + math.sin(th) * K + (1.0 - math.cos(th)) * (K @ K)


def load_case(path):
    case = json.load(open(path))
    case.setdefault("name", os.path.splitext(os.path.basename(path))[0])
    case.setdefault("E_MPa", 0.003)
    case.setdefault("nu", 0.46)
    case.setdefault("rotation", {"axis": [0, 0, 1], "angle_deg": 0.0})
    case.setdefault("translation", [0.0, 0.0, 0.0])
    ccx = {"initial": 0.1, "minimum": 1e-5, "max_increments": 400, "tolerance": 1e-9,
           "timeout_s": 1800, "threads": 1}
    ccx.update(case.get("calculix", {}))
    case["calculix"] = ccx
    for f in case["fixed_faces"]:
        assert f in FACES, f"unknown face {f}"
    lo, hi = np.array(case["inner_min"], float), np.array(case["inner_max"], float)
    assert np.all(lo > 0) and np.all(hi < np.array(case["box"], float)) and np.all(lo < hi), \
        "the inner box must lie strictly inside the outer box"
    return case


# ---------------------------------------------------------------------------------------------
# mesh
# ---------------------------------------------------------------------------------------------
def build_mesh(case, out):
    """Mesh with gmsh; return node tags, coordinates (sorted by tag), tets (node tags, tissue
    first then bone), the tag set of fixed-face nodes and the number of bone tets."""
    import gmsh

    L = np.array(case["box"], float)
    lo, hi = np.array(case["inner_min"], float), np.array(case["inner_max"], float)
    h = float(case["h"])
    gmsh.initialize(["-nopopup"])
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.model.add(case["name"])
        occ = gmsh.model.occ
        box = occ.addBox(0, 0, 0, *L)
        inner = occ.addBox(*lo, *(hi - lo))
        # Fragmenting makes the two volumes share the inner box's faces (a conforming mesh).
        occ.fragment([(3, box)], [(3, inner)])
        occ.synchronize()

        # The bone is the volume whose bounding box is the inner box (a centroid test fails
        # for a centred inner box: the shell's centroid lies in it too).
        vols = [t for _, t in gmsh.model.getEntities(3)]
        bone_vols = [t for t in vols
                     if np.allclose(gmsh.model.getBoundingBox(3, t), [*lo, *hi], atol=1e-6 * L.max())]
        tissue_vols = [t for t in vols if t not in bone_vols]
        assert len(bone_vols) == 1 and len(tissue_vols) == 1, (bone_vols, tissue_vols)

        tol = 1e-6 * L.max()
        fixed_surfs = []
        for _, s in gmsh.model.getEntities(2):
            bb = np.array(gmsh.model.getBoundingBox(2, s))
            for name in case["fixed_faces"]:
                d, side = "xyz".index(name[0]), name[1]
                v = 0.0 if side == "0" else L[d]
                if abs(bb[d] - v) < tol and abs(bb[d + 3] - v) < tol:
                    fixed_surfs.append(s)
        assert len(fixed_surfs) == len(case["fixed_faces"]), fixed_surfs

        gmsh.model.addPhysicalGroup(3, tissue_vols, 1)
        gmsh.model.setPhysicalName(3, 1, "tissue")
        gmsh.model.addPhysicalGroup(3, bone_vols, 2)
        gmsh.model.setPhysicalName(3, 2, "bone")
        gmsh.model.addPhysicalGroup(2, fixed_surfs, 1)
        gmsh.model.setPhysicalName(2, 1, "fixed")

        # A uniform size field; Delaunay 3D, then gmsh's default tet optimisation.
        for key, val in (("Mesh.CharacteristicLengthMin", h), ("Mesh.CharacteristicLengthMax", h),
                         ("Mesh.CharacteristicLengthFromPoints", 0),
                         ("Mesh.CharacteristicLengthExtendFromBoundary", 0),
                         ("Mesh.CharacteristicLengthFromCurvature", 0),
                         ("Mesh.Algorithm", 6), ("Mesh.Algorithm3D", 1),
                         ("Mesh.Optimize", 1), ("Mesh.RandomSeed", case.get("mesh_seed", 1))):
            gmsh.option.setNumber(key, val)
        gmsh.model.mesh.generate(3)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.option.setNumber("Mesh.Binary", 0)
        gmsh.option.setNumber("Mesh.SaveAll", 0)
        gmsh.write(os.path.join(out, "mesh.msh"))

        tags, xyz, _ = gmsh.model.mesh.getNodes()
        order = np.argsort(tags)
        tags, xyz = tags[order].astype(np.int64), xyz.reshape(-1, 3)[order]

        def tets_of(vol_list):
            blocks = []
            for v in vol_list:
                types, _, nodes = gmsh.model.mesh.getElements(3, v)
                for ty, nd in zip(types, nodes):
                    assert ty == 4, f"element type {ty} is not a 4-node tetrahedron"
                    blocks.append(np.asarray(nd, np.int64).reshape(-1, 4))
            return np.vstack(blocks)

        tissue_tets, bone_tets = tets_of(tissue_vols), tets_of(bone_vols)
        fixed_nodes = set()
        for s in fixed_surfs:
            nt, _, _ = gmsh.model.mesh.getNodes(2, s, includeBoundary=True)
            fixed_nodes.update(int(t) for t in nt)
    finally:
        gmsh.finalize()
    tets = np.vstack([tissue_tets, bone_tets])
    return tags, xyz, tets, fixed_nodes, len(bone_tets)


# ---------------------------------------------------------------------------------------------
# softface scenes
# ---------------------------------------------------------------------------------------------
SCENE = """# {name}: made by benchmarks/nonlinear_solvers/make_case.py ({variant})
subsection Scene
  set Mesh source   = file
  set Mesh file     = mesh.msh
  set Bone segments = fixed, bone
  subsection Segment fixed
    set Boundary ids = 1
    set Material ids =
  end
  subsection Segment bone
    set Boundary ids =
    set Material ids = 2
  end
end
subsection Material
  set Young's modulus = {E_Pa:.10g}
  set Poisson's ratio = {nu:.10g}
end
subsection Planning
  set Moved segments = bone
  subsection Motion bone
    set Translation     = {t}
    set Rotation axis   = {axis}
    set Rotation angle  = {angle:.12g}
    set Rotation centre = {centre}
  end
end
subsection Models
  set Models = {model}
  subsection {model}
    set Material law = {law}
    set Solver       = cg amg
  end
end
subsection Output
  set Output directory          = {outdir}
  set Reference model           = {model}
  set Write VTU                 = false
  set Write nodal displacements = true
end
"""


def vec(v):
    return ", ".join("%.12g" % x for x in v)


def write_scenes(case, out, centre, axis):
    variants = {"scene.prm": ("nonlinear fem", "st venant-kirchhoff", "softface_svk"),
                "scene_neo_hooke.prm": ("nonlinear fem", "neo-hooke", "softface_neo_hooke"),
                "scene_reference.prm": ("reference fem", "neo-hooke", "softface_reference")}
    for fname, (model, law, sub) in variants.items():
        with open(os.path.join(out, fname), "w") as f:
            f.write(SCENE.format(name=case["name"], variant=f"{model}, {law}",
                                 E_Pa=case["E_MPa"] * 1e6, nu=case["nu"],
                                 t=vec(case["translation"]), axis=vec(axis),
                                 angle=float(case["rotation"]["angle_deg"]), centre=vec(centre),
                                 model=model, law=law, outdir=os.path.join(out, sub)))
    return list(variants)


# ---------------------------------------------------------------------------------------------
# CalculiX
# ---------------------------------------------------------------------------------------------
def write_calculix(case, out, tags, xyz, tets, fixed, moved, u_bone):
    ccx = case["calculix"]
    with open(os.path.join(out, "mesh.inc"), "w") as f:
        f.write("*NODE,NSET=NALL\n")
        f.writelines("%d,%.12g,%.12g,%.12g\n" % (t, *p) for t, p in zip(tags, xyz))
        f.write("*ELEMENT,TYPE=C3D4,ELSET=EALL\n")
        f.writelines("%d,%d,%d,%d,%d\n" % (i + 1, *e) for i, e in enumerate(tets))
        for name, nodes in (("NFIX", fixed), ("NBONE", moved)):
            f.write(f"*NSET,NSET={name}\n")
            for k in range(0, len(nodes), 16):
                f.write(",".join(str(int(v)) for v in nodes[k:k + 16]) + "\n")
    with open(os.path.join(out, "ccx_nl.inp"), "w") as f:
        f.write("** %s: St. Venant-Kirchhoff (*ELASTIC with NLGEOM), prescribed bone motion\n"
                % case["name"])
        f.write("*INCLUDE,INPUT=mesh.inc\n")
        f.write("*MATERIAL,NAME=TISSUE\n*ELASTIC\n%.8e,%.6f\n" % (case["E_MPa"], case["nu"]))
        f.write("*SOLID SECTION,ELSET=EALL,MATERIAL=TISSUE\n")
        f.write("*STEP,NLGEOM,INC=%d\n" % ccx["max_increments"])
        # initial increment, step time, minimum and maximum increment
        f.write("*STATIC\n%g,1.,%g,1.\n" % (ccx["initial"], ccx["minimum"]))
        # residual (R_n^alpha) and correction (C_n^alpha) tolerances tightened, so a converged
        # increment is converged as tightly as softface's Newton
        if ccx["tolerance"] is not None:  # null: CalculiX's default controls
            f.write("*CONTROLS,PARAMETERS=FIELD\n%g,%g,,,,,,\n"
                    % (ccx["tolerance"], ccx["tolerance"]))
        f.write("*BOUNDARY\nNFIX,1,3,0.\n")
        for t, u in zip(moved, u_bone):
            for d in range(3):
                f.write("%d,%d,%d,%.12g\n" % (t, d + 1, d + 1, u[d]))
        f.write("*NODE PRINT,NSET=NALL\nU\n*END STEP\n")


def parse_sta(path):
    """Every attempt of an increment: list of (inc, attempt, converged, iterations, total time).
    CalculiX marks an attempt that did not converge (and was cut back) with a U after ATT."""
    rows = []
    if os.path.exists(path):
        for line in open(path):
            p = line.split()
            if len(p) == 7 and p[0].isdigit():
                rows.append((int(p[1]), int(p[2].rstrip("U")), not p[2].endswith("U"),
                             int(p[3]), float(p[4])))
    return rows


def parse_cvg(path):
    """Every Newton iteration CalculiX tried: list of (inc, attempt, iteration)."""
    rows = []
    if os.path.exists(path):
        for line in open(path):
            p = line.split()
            if len(p) >= 5 and all(x.isdigit() for x in p[:4]):
                rows.append((int(p[1]), int(p[2]), int(p[3])))
    return rows


def dat_blocks(path):
    """Every displacement block of the .dat file (one per converged increment), in order:
    yields (time, {node: (ux,uy,uz)})."""
    head = re.compile(r"^\s*displacements \(vx,vy,vz\) for set NALL and time\s+(\S+)")
    current, t_cur = None, None
    with open(path) as f:
        for line in f:
            m = head.match(line)
            if m:
                if current:
                    yield t_cur, current
                current, t_cur = {}, float(m.group(1))
                continue
            if current is not None:
                p = line.split()
                if len(p) == 4:
                    current[int(p[0])] = (float(p[1]), float(p[2]), float(p[3]))
    if current:
        yield t_cur, current


def write_displacements(path, xyz, U):
    """x,y,z,ux,uy,uz per node, in gmsh node order (CalculiX's .dat has 7 significant digits)."""
    with open(path, "w") as f:
        f.write("x,y,z,ux,uy,uz\n")
        f.writelines("%.12g,%.12g,%.12g,%.7e,%.7e,%.7e\n" % (*p, *u) for p, u in zip(xyz, U))


def volume_ratios(X, U, tets_idx):
    """det F per tetrahedron: deformed over reference signed volume."""
    def signed(P):
        a, b, c, d = (P[tets_idx[:, k]] for k in range(4))
        return np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a))
    return signed(X + U) / signed(X)


def run_calculix(case, out):
    ccx = case["calculix"]
    for ext in ("sta", "cvg", "dat", "frd", "12d"):
        p = os.path.join(out, "ccx_nl." + ext)
        if os.path.exists(p):
            os.remove(p)
    env = dict(os.environ, OMP_NUM_THREADS=str(ccx["threads"]),
               CCX_NPROC_EQUATION_SOLVER=str(ccx["threads"]))
    t0 = time.time()
    timed_out = False
    with open(os.path.join(out, "ccx_nl.log"), "w") as log:
        try:
            proc = subprocess.run(["ccx", "-i", "ccx_nl"], cwd=out, stdout=log,
                                  stderr=subprocess.STDOUT, env=env, timeout=ccx["timeout_s"])
            rc = proc.returncode
        except subprocess.TimeoutExpired:
            rc, timed_out = None, True
    return {"wall_s": round(time.time() - t0, 2), "threads": ccx["threads"], "return_code": rc,
            "timed_out": timed_out}


def parse_calculix(out, run, tags, xyz, tets):
    """What CalculiX reached, from its .sta, .cvg, .log and .dat (kept in OUTDIR)."""
    timed_out = run["timed_out"]
    logtext = open(os.path.join(out, "ccx_nl.log")).read()
    attempts = parse_sta(os.path.join(out, "ccx_nl.sta"))
    sta = [r for r in attempts if r[2]]  # converged increments
    cvg = parse_cvg(os.path.join(out, "ccx_nl.cvg"))
    load = sta[-1][4] if sta else 0.0
    finished = "Job finished" in logtext and not timed_out
    errors = [l.strip() for l in logtext.splitlines() if "*ERROR" in l]
    res = {
        "status": "ok" if finished and abs(load - 1.0) < 1e-9 else "failed",
        "load_reached": load,
        "converged_increments": len(sta),
        # attempts that did not converge, each followed by a smaller increment (or the end)
        "cutbacks": sum(1 for r in attempts if not r[2]),
        "iterations": len(cvg),
        "iterations_converged_increments": sum(r[3] for r in sta),
        **run,
        "errors": errors[-3:],
        "attempts": [{"inc": r[0], "attempt": r[1], "converged": r[2], "iterations": r[3],
                      "total_time": r[4]} for r in attempts],
    }
    dat = os.path.join(out, "ccx_nl.dat")
    if sta and os.path.exists(dat):
        index = np.searchsorted(tags, tets)
        history = []  # (load, min volume ratio, tetrahedra inverted) per converged increment
        for t_dat, disp in dat_blocks(dat):
            U = np.array([disp[int(t)] for t in tags])
            J = volume_ratios(xyz, U, index)
            history.append([t_dat, float(J.min()), int((J <= 0).sum())])
            write_displacements(os.path.join(out, "calculix_nl_displacements_%.7f.csv" % t_dat),
                                xyz, U)
        with open(os.path.join(out, "calculix_nl_increments.csv"), "w") as f:
            f.write("load,min_volume_ratio,n_inverted\n")
            f.writelines("%.7f,%.6g,%d\n" % tuple(h) for h in history)
        res["dat_time"] = t_dat
        res["volume_ratio_history"] = history
        valid = [h[0] for h in history if h[2] == 0]
        # how far CalculiX got with no tetrahedron inverted (softface refuses any inverted one)
        res["last_load_without_inversion"] = valid[-1] if valid else 0.0
        first_bad = [h[0] for h in history if h[2] > 0]
        res["first_load_with_inversion"] = first_bad[0] if first_bad else None
        write_displacements(os.path.join(out, "calculix_nl_displacements.csv"), xyz, U)
        k = int(np.argmin(J))
        res.update({
            "max_displacement_mm": float(np.linalg.norm(U, axis=1).max()),
            "min_volume_ratio": float(J.min()),
            "n_inverted": int((J <= 0).sum()),
            "n_volume_ratio_below_0.1": int((J < 0.1).sum()),
            "min_volume_ratio_element": k + 1,
            "min_volume_ratio_centroid": [round(float(v), 3) for v in xyz[index[k]].mean(axis=0)],
        })
    return res


# ---------------------------------------------------------------------------------------------
def main(argv):
    args = [a for a in argv[1:] if not a.startswith("--")]
    flags = {a for a in argv[1:] if a.startswith("--")}
    if not args:
        sys.exit(__doc__)
    case = load_case(args[0])
    out = os.path.abspath(args[1] if len(args) > 1 else os.path.join("/tmp/nl", case["name"]))
    os.makedirs(out, exist_ok=True)
    json.dump(case, open(os.path.join(out, "case_input.json"), "w"), indent=1)

    lo, hi = np.array(case["inner_min"], float), np.array(case["inner_max"], float)
    centre = 0.5 * (lo + hi)
    axis = np.array(case["rotation"]["axis"], float)
    axis /= np.linalg.norm(axis)
    R = rotation_matrix(axis, case["rotation"]["angle_deg"])
    t = np.array(case["translation"], float)

    t0 = time.time()
    tags, xyz, tets, fixed_set, n_bone_tets = build_mesh(case, out)
    mesh_s = time.time() - t0
    tol = 1e-6 * float(np.max(case["box"]))
    in_bone = np.all((xyz >= lo - tol) & (xyz <= hi + tol), axis=1)
    moved = tags[in_bone]
    fixed = np.array(sorted(fixed_set - set(moved.tolist())), np.int64)
    u_bone = (xyz[in_bone] - centre) @ R.T + centre + t - xyz[in_bone]
    # The bone nodes are exactly the vertices of the bone tets (softface's join points).
    assert set(np.unique(tets[len(tets) - n_bone_tets:]).tolist()) == set(moved.tolist())

    # corners of the inner box: the largest displacement of the rigid motion is at one of them
    corners = np.array([[a, b, c] for a in (lo[0], hi[0]) for b in (lo[1], hi[1])
                        for c in (lo[2], hi[2])])
    u_corners = (corners - centre) @ R.T + centre + t - corners
    moved_box = corners + u_corners
    info = {
        "case": case,
        "outdir": out,
        "n_nodes": int(len(tags)),
        "n_tets": int(len(tets)),
        "n_bone_tets": int(n_bone_tets),
        "n_fixed_nodes": int(len(fixed)),
        "n_bone_nodes": int(len(moved)),
        "mesh_s": round(mesh_s, 2),
        "rotation_centre": centre.tolist(),
        "max_prescribed_displacement_mm": float(np.linalg.norm(u_corners, axis=1).max()),
        "moved_inner_box_bounds": [moved_box.min(axis=0).round(3).tolist(),
                                   moved_box.max(axis=0).round(3).tolist()],
        "softface_scenes": write_scenes(case, out, centre, axis),
    }
    write_calculix(case, out, tags, xyz, tets, fixed, moved, u_bone)
    # tetrahedra as 0-based rows of calculix_nl_displacements.csv, for volume-ratio checks
    np.save(os.path.join(out, "tet_rows.npy"), np.searchsorted(tags, tets).astype(np.int32))
    old = {}
    if os.path.exists(os.path.join(out, "result.json")):
        old = json.load(open(os.path.join(out, "result.json")))
        if old.get("n_tets") != info["n_tets"]:
            old = {}
    if "--mesh-only" not in flags and "--no-ccx" not in flags and "--parse-only" not in flags:
        run = run_calculix(case, out)
        info["calculix"] = parse_calculix(out, run, tags, xyz, tets)
    elif "--parse-only" in flags and "calculix" in old:
        keep = ("wall_s", "threads", "return_code", "timed_out")
        info["calculix"] = parse_calculix(out, {k: old["calculix"][k] for k in keep},
                                          tags, xyz, tets)
    elif "calculix" in old:
        info["calculix"] = old["calculix"]
    if "softface" in old:
        info["softface"] = old["softface"]
    json.dump(info, open(os.path.join(out, "result.json"), "w"), indent=1)
    brief = {k: v for k, v in info.items() if k not in ("case", "softface_scenes")}
    if "calculix" in brief:
        brief["calculix"] = {k: v for k, v in brief["calculix"].items()
                            if k not in ("attempts", "volume_ratio_history")}
    print(json.dumps(brief))


if __name__ == "__main__":
    main(sys.argv)
