#!/usr/bin/python3
"""What accuracy costs in time: every model's error against a converged
reference and its time, side by side (issue 5). Called by
benchmarks/run_all.sh, which builds softface first.

For each scene (the seed's cube with a 6 mm lift, a 16.7 mm lift, and a
30 degree rotation of the inner cube):
  1. evaluation points: the free vertices of the coarsest mesh;
  2. the reference: 'reference fem' (Neo-Hooke on quadratic tetrahedra) on
     graded cube meshes (grid spacing growing sixfold from the inner cube's
     face planes to the outer faces: the inner cube's edges and corners make
     the displacement singular, and uniform refinement converges too slowly
     there) with the mirror-symmetric split (on the default split along
     (1, 1, 1) the symmetric 16.7 mm lift moves the point 7 mm above the
     inner cube up to 2 mm sideways), evaluated at those points by its shape functions; its
     convergence is the change between the two finest levels;
  3. linear elasticity's model error: linear FEM's equations solved with
     the reference's discretisation ('Material law = linear', quadratic
     tetrahedra, the two finest reference meshes), compared with the
     reference on the same mesh; it also gives the limit P1 linear FEM
     converges to, which splits the linear models' error into model and
     discretisation error;
  4. the sweep: every model at every mesh level and accuracy setting, one
     softface process per case, timed by softface (setup and solve) and
     evaluated at the same points;
  5. error statistics (median, 90%, 95%, max of |u - u_ref| in mm), Pareto
     tables and a plot.
Then the MTM precision study (seed 2.3.5) on the same three scenes.

Writes accuracy_vs_time.{md,csv,png} and mtm_precision.{md,csv,png} to
doc/results/ (the quick mode to build/benchmarks/accuracy/quick/results/).
"""

import argparse
import csv
import os
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import report  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import summary  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HERE = os.path.join(ROOT, "benchmarks", "accuracy")
SOFTFACE = os.environ.get("SOFTFACE", os.path.join(ROOT, "build", "softface"))

# The seed's cube: outer faces held, the inner cube [35, 45]^3 is the bone.
EDGE, INNER_LOW, INNER_HIGH = 80.0, 35.0, 45.0

SCENES = [
    dict(key="cube_6mm", title="cube, 6 mm lift", translation="0, 0, 6",
         axis="0, 0, 1", angle=0),
    dict(key="cube_16.7mm", title="cube, 16.7 mm lift", translation="0, 0, 16.7",
         axis="0, 0, 1", angle=0),
    dict(key="rotation_30deg", title="inner cube rotated 30 deg about x",
         translation="0, 0, 0", axis="1, 0, 0", angle=30),
]

MODELS = ["linear fem", "nonlinear fem", "mass tensor", "mass spring"]
THRESHOLDS = [1.0, 0.5, 0.3, 0.1]  # mm, at the 90th percentile

FULL = dict(
    meshes=[10000, 30000, 100000, 300000],
    # Per scene, as fine as the criterion (last change <= a tenth of the
    # smallest 90% error) needed and the machine allowed: the rotation
    # changed 0.015 mm from 30k to 100k, too much, so it has a 300k level.
    # The 6 mm lift's 300k level stalled in its second Newton iteration
    # with the whole lift in one load step (CG over 14 minutes, also with ML
    # rebuilt during the solve); in quarters it converges (since CG stops on
    # negative curvature, also in one step: 12.7 min). The 16.7 mm lift
    # changed 0.049 mm from 30k to 100k (a tenth of its smallest error:
    # 0.046), so it has a 300k level too, also started in quarters (its 100k
    # level cut back from 1 to 0.25 anyway): 51 min, 10.2 GB, change 0.040
    # mm against 0.049.
    reference_meshes={"cube_6mm": [10000, 30000, 100000, 300000],
                      "cube_16.7mm": [10000, 30000, 100000, 300000],
                      "rotation_30deg": [10000, 30000, 100000, 300000]},
    reference_grading=6,
    settings={
        "linear fem": [("Relative tolerance", v) for v in ("1e-2", "1e-4", "1e-8")],
        "nonlinear fem": [("Residual tolerance", v) for v in ("1e-2", "1e-4", "1e-8")],
        "mass tensor": [(("Stop gradient threshold", t), ("Gradient window", w))
                        for t in ("1e-2", "1e-3", "1e-4") for w in ("3", "10")],
        "mass spring": [("Stop threshold", v) for v in ("1e-2", "1e-3", "1e-4")],
    },
    precision_mesh=100000,
)
QUICK = dict(
    meshes=[3000, 10000],
    reference_meshes=[3000, 10000],
    reference_grading=6,
    settings={
        "linear fem": [("Relative tolerance", v) for v in ("1e-2", "1e-8")],
        "nonlinear fem": [("Residual tolerance", v) for v in ("1e-2", "1e-8")],
        "mass tensor": [(("Stop gradient threshold", t), ("Gradient window", "10"))
                        for t in ("1e-2", "1e-3", "1e-4")],
        "mass spring": [("Stop threshold", v) for v in ("1e-2", "1e-3")],
    },
    precision_mesh=10000,
)

# Fixed settings of each model (the swept knob is added to them).
BASE_SETTINGS = {
    "linear fem": [("Solver", "cg amg")],
    "nonlinear fem": [("Material law", "neo-hooke"), ("Solver", "cg amg")],
    "mass tensor": [],
    "mass spring": [],
}
REFERENCE_SETTINGS = [("Material law", "neo-hooke"), ("Solver", "cg amg"),
                      ("Polynomial degree", "2"), ("Residual tolerance", "1e-9")]
REFERENCE_MODEL = "reference fem"
# Linear elasticity on the reference's discretisation (its model error).
LINEAR_P2_SETTINGS = [("Material law", "linear")] + REFERENCE_SETTINGS[1:]
# Added for single reference levels (scene, tets).
REFERENCE_EXTRA_SETTINGS = {("cube_6mm", 300000): [("Initial load increment", "0.25")],
                            ("cube_16.7mm", 300000): [("Initial load increment", "0.25")]}

# Rough relative cost per tetrahedron, only for the progress estimate.
COST = {"linear fem": 1, "nonlinear fem": 4, "mass tensor": 1,
        "mass spring": 3, "reference": 100, "model error": 20, "points": 1,
        "precision": 2}


def reference_meshes(config, key):
    """The reference's mesh levels: one list for all scenes or one per scene."""
    levels = config["reference_meshes"]
    return levels[key] if isinstance(levels, dict) else levels


def knob_pairs(setting):
    """A setting is one (name, value) pair or a tuple of them."""
    return list(setting) if isinstance(setting[0], tuple) else [setting]


def knob_text(setting):
    return ", ".join(f"{n.lower()} {v}" for n, v in knob_pairs(setting))


def file_name_of(model):
    return model.replace(" ", "_")


# False with --report-only: the parameter files then stay what the runs used.
WRITE_PRMS = True


def write_prm(path, scene, model, tets, settings, output, points="", nodal=False,
              grading=1, symmetric=False):
    text = open(os.path.join(HERE, "scene.prm.in")).read()
    lines = "\n".join(f"    set {n} = {v}" for n, v in settings)
    for key, value in {"@TETS@": str(tets), "@GRADING@": str(grading),
                       "@SYMMETRIC@": "true" if symmetric else "false",
                       "@TRANSLATION@": scene["translation"],
                       "@AXIS@": scene["axis"], "@ANGLE@": str(scene["angle"]),
                       "@MODEL@": model, "@SETTINGS@": lines, "@OUTPUT@": output,
                       "@POINTS@": points, "@NODAL@": "true" if nodal else "false"}.items():
        text = text.replace(key, value)
    unchanged = os.path.exists(path) and open(path).read() == text
    if not unchanged and WRITE_PRMS:
        with open(path, "w") as f:
            f.write(text)
    return unchanged


def read_values(path):
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return data[:, :3], data[:, 3:6]


def error_statistics(values, reference):
    d = np.linalg.norm(values - reference, axis=1)
    return dict(err_median=float(np.median(d)), err_p90=float(np.percentile(d, 90)),
                err_p95=float(np.percentile(d, 95)), err_max=float(d.max()))


class Progress:
    def __init__(self, total_cost):
        self.total, self.done, self.start, self.i, self.n = total_cost, 0., time.time(), 0, 0

    def step(self, label, cost):
        self.i += 1
        elapsed = time.time() - self.start
        estimate = ""
        if self.done > 0:
            remaining = elapsed / self.done * (self.total - self.done)
            estimate = f", about {remaining / 60:.1f} min left"
        print(f"[{self.i}/{self.n}] {label} (elapsed {elapsed / 60:.1f} min{estimate})",
              flush=True)
        self.done += cost


def run_finished(output):
    """Did the run of a case write its summary (softface writes it last)?"""
    return bool(summary.read(os.path.join(output, "summary.csv")))


def run_softface(prm, output, report_only=False):
    """Run one case (its log goes to OUTPUT.log), or with report_only take an
    earlier run's; returns (ok, error). The outcome is read from the case's
    summary.csv; a run that wrote none stopped on its input, whose one-line
    error is the last line of its log."""
    log = output + ".log"
    if not report_only:
        # The machine's load as the case starts: 1 is this run alone.
        with open(output + ".load", "w") as f:
            f.write(f"{os.getloadavg()[0]:.2f}\n")
    if report_only:
        if not os.path.exists(log):
            sys.exit(f"--report-only: no earlier run of {prm} (missing {log})")
    else:
        with open(log, "w") as out:
            subprocess.run([SOFTFACE, prm], stdout=out, stderr=subprocess.STDOUT)
    rows = summary.read(os.path.join(output, "summary.csv"))
    if not rows:
        lines = [line for line in open(log) if line.startswith("softface: error:")]
        return False, lines[-1][len("softface: error:"):].strip() if lines else "no summary.csv"
    failed = [r for r in rows if r["status"] != "ok"]
    return not failed, "; ".join(r["error"] for r in failed)


def load_text(work):
    """The machine's 1-minute load average as the cases started (this run
    alone makes it about 1; other work on the machine adds to it)."""
    loads = []
    for folder, _, files in os.walk(work):
        for name in files:
            if name.endswith(".load"):
                loads.append(float(open(os.path.join(folder, name)).read()))
    if not loads:
        return ""
    return (f" The machine's load average (1 minute) as the {len(loads)} cases started: "
            f"median {np.median(loads):.2f}, maximum {max(loads):.2f} (this run alone is "
            "about 1 on 2 cores; more means other work shared the machine).")


def summary_row(output, model):
    row = summary.row(os.path.join(output, "summary.csv"), model)
    return row if row is not None and row["status"] == "ok" else None


def free_points(points):
    """Vertices that are no join point: not on the outer faces and not in
    the closed inner (bone) cube."""
    tol = 1e-9 * EDGE
    on_outer = np.any((points < tol) | (points > EDGE - tol), axis=1)
    in_bone = np.all((points > INNER_LOW - tol) & (points < INNER_HIGH + tol), axis=1)
    return points[~on_outer & ~in_bone]


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true",
                        help="coarser meshes and fewer settings (under 5 minutes)")
    parser.add_argument("--scenes", default="",
                        help="comma-separated scene keys to run (default: all)")
    parser.add_argument("--report-only", action="store_true",
                        help="no softface runs: rewrite the reports from the outputs an "
                        "earlier run left in build/benchmarks/accuracy/")
    parser.add_argument("--resume", action="store_true",
                        help="run only the cases whose parameter file changed or whose "
                        "earlier run did not finish; reuse the others' outputs")
    args = parser.parse_args()
    config = QUICK if args.quick else FULL
    work = os.path.join(ROOT, "build", "benchmarks", "accuracy",
                        "quick" if args.quick else "full")
    results = (os.path.join(work, "results") if args.quick
               else os.path.join(ROOT, "doc", "results"))
    os.makedirs(results, exist_ok=True)
    scenes = [s for s in SCENES if not args.scenes or s["key"] in args.scenes.split(",")]
    command = "benchmarks/run_all.sh" + (" --quick" if args.quick else "")

    # Every case, in order: points, references (finest last), linear P2 on
    # the two finest reference meshes, sweep, precision.
    cases = []
    for scene in scenes:
        cases.append(dict(scene=scene, kind="points", model="linear fem",
                          tets=config["meshes"][0], settings=BASE_SETTINGS["linear fem"]))
        levels = reference_meshes(config, scene["key"])
        for tets in levels:
            cases.append(dict(scene=scene, kind="reference", model=REFERENCE_MODEL,
                              tets=tets, settings=REFERENCE_SETTINGS +
                              REFERENCE_EXTRA_SETTINGS.get((scene["key"], tets), [])))
        for tets in levels[-2:]:
            cases.append(dict(scene=scene, kind="model error", model=REFERENCE_MODEL,
                              tets=tets, settings=LINEAR_P2_SETTINGS))
        for model in MODELS:
            for tets in config["meshes"]:
                for setting in config["settings"][model]:
                    cases.append(dict(scene=scene, kind="sweep", model=model, tets=tets,
                                      setting=setting,
                                      settings=BASE_SETTINGS[model] + knob_pairs(setting)))
        cases.append(dict(scene=scene, kind="precision", model="mass tensor",
                          tets=config["precision_mesh"]))
    progress = Progress(sum(c["tets"] * COST[c["model"] if c["kind"] == "sweep" else c["kind"]]
                            for c in cases))
    progress.n = len(cases)
    # Each model's tightest setting: the one that shows its discretisation.
    tightest = {model: knob_text(config["settings"][model][-1]) for model in MODELS}

    global WRITE_PRMS
    WRITE_PRMS = not args.report_only

    def reuse(unchanged, output):
        """Read an earlier run's outputs instead of running the case?"""
        if args.report_only and not unchanged:
            sys.exit(f"--report-only: {output}.prm is not what this configuration "
                     "would run; run without --report-only (or with --resume)")
        return args.report_only or (args.resume and unchanged and run_finished(output))

    rows, reference_rows, linear_p2_rows, precision = [], [], [], {}
    points_file, reference_values = {}, {}
    for case in cases:
        scene, key = case["scene"], case["scene"]["key"]
        kind, model, tets = case["kind"], case["model"], case["tets"]
        folder = os.path.join(work, key)
        os.makedirs(folder, exist_ok=True)
        name = f"{kind}_{file_name_of(model)}_{tets}"
        if kind == "reference":
            name = f"{kind}_graded{config['reference_grading']}_{tets}"
        if kind == "model error":
            name = f"linear_p2_graded{config['reference_grading']}_{tets}"
        if kind == "sweep":
            name += "_" + "_".join(v for _, v in knob_pairs(case["setting"]))
        output = os.path.join(folder, name)
        prm = output + ".prm"
        label = f"{key}: {kind} {model}, {tets} tets"
        if kind == "model error":
            label = f"{key}: model error, linear elasticity on quadratic tetrahedra, {tets} tets"
        if kind == "sweep":
            label += ", " + knob_text(case["setting"])
        progress.step(label, tets * COST[model if kind == "sweep" else kind])

        if kind == "points":
            unchanged = write_prm(prm, scene, model, tets, case["settings"], output,
                                  nodal=True)
            ok, message = run_softface(prm, output, reuse(unchanged, output))
            if not ok:
                sys.exit(f"the evaluation-point run failed: {message} (log {output}.log)")
            points, _ = read_values(os.path.join(output, "displacements_linear_fem.csv"))
            points = free_points(points)
            points_file[key] = os.path.join(folder, "evaluation_points.csv")
            np.savetxt(points_file[key], points, delimiter=",", header="x,y,z",
                       comments="", fmt="%.12g")
            print(f"    {len(points)} evaluation points (free vertices of the "
                  f"{tets}-tetrahedron mesh)", flush=True)
            continue

        if kind == "precision":
            history = output + "_history.csv"
            settings = [("Stop gradient threshold", "1e-5"), ("Active set", "false"),
                        ("Maximum sweeps", "100000"), ("Precision history file", history)]
            unchanged = write_prm(prm, scene, model, tets, settings, output)
            ok, message = run_softface(prm, output, reuse(unchanged, output))
            row = summary_row(output, model)
            precision[key] = dict(scene=scene, tets=tets, ok=ok, message=message,
                                  vertices=row["n_vertices"] if row else "",
                                  history=np.loadtxt(history, delimiter=",", skiprows=1,
                                                     ndmin=2) if ok else None)
            # A scene is complete: write what is done so far.
            finished = [sc for sc in scenes if sc["key"] in precision]
            report.write_accuracy(results, command, finished, rows, reference_rows,
                                  linear_p2_rows, tightest, THRESHOLDS, MODELS,
                                  time.time() - progress.start, load_text(work))
            report.write_precision(results, command, precision)
            continue

        unchanged = write_prm(prm, scene, model, tets, case["settings"], output,
                  points=points_file[key],
                  grading=config["reference_grading"] if kind != "sweep" else 1,
                  symmetric=(kind != "sweep"))
        ok, message = run_softface(prm, output, reuse(unchanged, output))
        row = summary_row(output, model)
        values_path = os.path.join(output, f"evaluation_{file_name_of(model)}.csv")
        entry = dict(scene=key, model={"sweep": model, "reference": "reference (P2 neo-hooke)",
                                       "model error": "linear elasticity (P2)"}[kind],
                     setting=(knob_text(case["setting"]) if kind == "sweep" else
                              f"degree 2, grading {config['reference_grading']}"),
                     level=tets,
                     n_tets=row["n_tets"] if row else "", n_vertices=row["n_vertices"] if row else "",
                     setup_s=float(row["setup_s"]) if row else float("nan"),
                     solve_s=float(row["solve_s"]) if row else float("nan"),
                     iterations=row["iterations"] if row else "",
                     status="ok" if ok and row else "failed", message=message)
        entry["total_s"] = entry["setup_s"] + entry["solve_s"]
        if kind == "model error":
            entry["values"] = read_values(values_path)[1] if ok and row else None
            linear_p2_rows.append(entry)
            if entry["values"] is None:
                print(f"    failed: {message}", flush=True)
            continue
        if kind == "reference":
            entry["n_dofs"] = row["n_dofs"] if row else ""
            entry["values"] = read_values(values_path)[1] if ok and row else None
            reference_rows.append(entry)
            if entry["values"] is None:
                print(f"    reference failed: {message}", flush=True)
            if tets == reference_meshes(config, key)[-1]:
                # The finest reference that converged scores the sweep.
                done = [r for r in reference_rows if r["scene"] == key and r["values"] is not None]
                if done:
                    reference_values[key] = done[-1]["values"]
                    for r in done:
                        r["used"] = r is done[-1]
            continue
        if ok and row and key in reference_values:
            entry["values"] = read_values(values_path)[1]
            entry.update(error_statistics(entry["values"], reference_values[key]))
        elif ok and row:
            entry["message"] = "no converged reference"
        rows.append(entry)
        if "err_p90" in entry:
            print(f"    {entry['total_s']:.3f} s, error p90 {entry['err_p90']:.3f} mm, "
                  f"max {entry['err_max']:.3f} mm", flush=True)
        elif not ok:
            print(f"    failed: {message}", flush=True)

    # The reports state how long the runs took, also when rewritten later.
    info = os.path.join(work, "run_time_s.txt")
    earlier = float(open(info).read()) if os.path.exists(info) else float("nan")
    if args.report_only:
        elapsed = earlier
    else:
        # A resumed run adds its time to the run it completes.
        elapsed = time.time() - progress.start
        if args.resume and earlier == earlier:
            elapsed += earlier
        with open(info, "w") as f:
            f.write(f"{elapsed:.1f}\n")
    report.write_accuracy(results, command, scenes, rows, reference_rows, linear_p2_rows,
                          tightest, THRESHOLDS, MODELS, elapsed, load_text(work))
    report.write_precision(results, command, precision)
    print(f"done in {elapsed / 60:.1f} min; results in {results}/ "
          "(accuracy_vs_time.md/.csv/.png, mtm_precision.md/.csv/.png)", flush=True)


if __name__ == "__main__":
    main()
