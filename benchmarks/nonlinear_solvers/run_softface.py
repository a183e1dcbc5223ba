#!/usr/bin/python3
"""Run softface's scenes of a case made by make_case.py and record how far each got.

    /usr/bin/python3 run_softface.py CASE_DIR [VARIANT ...] [--softface PATH] [--timeout S]

VARIANT is svk (scene.prm: 'nonlinear fem', St. Venant-Kirchhoff), neo_hooke
(scene_neo_hooke.prm) or reference (scene_reference.prm: 'reference fem', P2 Neo-Hooke); default
svk neo_hooke. Each run's stdout+stderr goes to CASE_DIR/softface_<variant>.log, its outputs to
CASE_DIR/softface_<variant>/, and what it reached to result.json under "softface" -> variant:

    status            ok / failed / timeout
    load_reached      1 when ok, else the error's "Last converged load"
    load_steps, cutbacks          converged load steps and halved (failed) steps
    newton_iterations             total over all steps (summary.csv; ok runs only)
    newton_iterations_converged   Newton iterations of the converged steps (progress lines)
    failed_steps      [load tried, reason] of every cut-back, in order
    error             the message softface stopped with
    wall_s            the process's wall time; setup_s / solve_s from summary.csv (ok runs)
    diff_to_calculix_max_mm / _mean_mm   |u_softface - u_CalculiX| over the vertices, when
                      both reached the full load (SVK: the same equations; Neo-Hooke: another law)
    min_volume_ratio  det F over the tetrahedra of softface's final state (ok P1 runs)

Runs one softface process at a time (softface computes on one thread).
"""
import csv
import json
import os
import re
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_SOFTFACE = os.path.join(HERE, "..", "..", "build", "softface")
SCENES = {"svk": "scene.prm", "neo_hooke": "scene_neo_hooke.prm", "reference": "scene_reference.prm"}
NUM = r"(\d+(?:\.\d*)?(?:[eE][+-]?\d+)?)"
STEP = re.compile(r"^\s*load step (\d+): load " + NUM + r", (\d+) Newton iterations")
FAIL = re.compile(r"^\s*load " + NUM + r" failed \((.*)\), cutting back\s*$")
LAST = re.compile(r"Last converged load: (\d+(?:\.\d*)?(?:[eE][+-]?\d+)?)")


def read_csv(path):
    return np.loadtxt(path, delimiter=",", skiprows=1)


def run(case_dir, variant, softface, timeout, scene=None, tag=None):
    """Run softface on CASE_DIR/SCENE (default: the variant's scene). TAG (default: the variant)
    names the log and the output folder, which the scene must name as CASE_DIR/softface_TAG."""
    scene = scene or SCENES[variant]
    tag = tag or variant
    outdir = os.path.join(case_dir, "softface_" + tag)
    log_path = os.path.join(case_dir, "softface_%s.log" % tag)
    summary = os.path.join(outdir, "summary.csv")
    if os.path.exists(summary):
        os.remove(summary)
    t0 = time.time()
    status = None
    with open(log_path, "w") as log:
        try:
            proc = subprocess.run([softface, scene], cwd=case_dir, stdout=log,
                                  stderr=subprocess.STDOUT, timeout=timeout)
            rc = proc.returncode
        except subprocess.TimeoutExpired:
            rc, status = None, "timeout"
    wall = time.time() - t0
    text = open(log_path).read()
    steps = [(int(m.group(1)), float(m.group(2)), int(m.group(3)))
             for m in map(STEP.match, text.splitlines()) if m]
    fails = [[float(m.group(1)), m.group(2)] for m in map(FAIL.match, text.splitlines()) if m]
    res = {"scene": scene, "return_code": rc, "wall_s": round(wall, 2),
           "load_steps": len(steps), "cutbacks": len(fails),
           "newton_iterations_converged": sum(s[2] for s in steps),
           "load_per_step": [s[1] for s in steps], "failed_steps": fails}
    errors = [l for l in text.splitlines() if "error" in l.lower() and "softface" in l]
    row = None
    if os.path.exists(summary):
        with open(summary) as f:
            rows = list(csv.DictReader(f))
        row = rows[0] if rows else None
    if status is None:
        status = "ok" if rc == 0 and row is not None and row["status"] == "ok" else "failed"
    res["status"] = status
    m = LAST.search(text)
    if status == "ok":
        res["load_reached"] = 1.0
    elif m:
        res["load_reached"] = float(m.group(1))
    else:
        res["load_reached"] = steps[-1][1] if steps else 0.0
    if row is not None:
        for key in ("n_tets", "n_vertices", "n_free_dofs", "setup_s", "solve_s", "iterations",
                    "max_displacement_mm", "peak_memory_mb"):
            if row.get(key, "") != "":
                res[key] = float(row[key])
        if status == "ok":
            res["newton_iterations"] = int(float(row["iterations"]))
        res["details"] = row.get("details", "")
        if row.get("error"):
            res["error"] = row["error"]
    if "error" not in res and errors:
        res["error"] = errors[-1]
    if status == "failed" and "error" in res:
        # the reason of the last failed step, as printed in the error
        m = re.search(r"of the planning: (.*?) \(relative residual", res["error"])
        if m:
            res["reason"] = m.group(1)
    disp = os.path.join(outdir, "displacements_%s.csv" % row["model"].replace(" ", "_")) \
        if row is not None else None
    if status == "ok" and disp and os.path.exists(disp):
        ours = read_csv(disp)
        X, U = ours[:, :3], ours[:, 3:]
        if os.path.exists(os.path.join(case_dir, "tet_rows.npy")):
            # vertices by coordinates -> gmsh node order (mesh.inc / CalculiX CSV order)
            ref = read_csv(os.path.join(case_dir, "calculix_nl_displacements.csv"))
            key = lambda P: [tuple(np.round(p, 6)) for p in P]
            pos = {k: i for i, k in enumerate(key(X))}
            perm = np.array([pos[k] for k in key(ref[:, :3])])
            U_g = U[perm]
            idx = np.load(os.path.join(case_dir, "tet_rows.npy"))
            Xr = ref[:, :3]

            def signed(P):
                a, b, c, d = (P[idx[:, k]] for k in range(4))
                return np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a))
            J = signed(Xr + U_g) / signed(Xr)
            if variant != "reference":
                # P1: det F is constant per cell. For P2 the vertex values alone do not give it
                # (a curved cell's straight-sided interpolant can fold where det F > 0).
                res["min_volume_ratio"] = float(J.min())
            result = json.load(open(os.path.join(case_dir, "result.json")))
            ccx = result.get("calculix", {})
            if ccx.get("status") == "ok":
                d = np.linalg.norm(U_g - ref[:, 3:], axis=1)
                res["diff_to_calculix_max_mm"] = float(d.max())
                res["diff_to_calculix_mean_mm"] = float(d.mean())
    return res


def main(argv):
    args, softface, timeout = [], DEFAULT_SOFTFACE, 3600
    it = iter(argv[1:])
    for a in it:
        if a == "--softface":
            softface = os.path.abspath(next(it))
        elif a == "--timeout":
            timeout = float(next(it))
        else:
            args.append(a)
    if not args:
        sys.exit(__doc__)
    if not os.access(softface, os.X_OK):
        sys.exit("run_softface.py: %s is not an executable (build softface first)" % softface)
    case_dir = os.path.abspath(args[0])
    variants = args[1:] or ["svk", "neo_hooke"]
    for v in variants:
        res = run(case_dir, v, softface, timeout)
        path = os.path.join(case_dir, "result.json")
        result = json.load(open(path))  # re-read: make_case.py may have written meanwhile
        result.setdefault("softface", {})[v] = res
        json.dump(result, open(path, "w"), indent=1)
        brief = {k: res[k] for k in ("status", "load_reached", "load_steps", "cutbacks",
                                     "newton_iterations_converged", "wall_s") if k in res}
        for k in ("newton_iterations", "solve_s", "reason", "min_volume_ratio",
                  "diff_to_calculix_max_mm"):
            if k in res:
                brief[k] = res[k]
        print(os.path.basename(case_dir), v, json.dumps(brief), flush=True)


if __name__ == "__main__":
    main(sys.argv)
