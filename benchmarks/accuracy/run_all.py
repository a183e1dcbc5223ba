#!/usr/bin/python3
"""What accuracy costs in time: every model's error against a converged
reference and its time, side by side. Called by
benchmarks/run_all.sh, which builds softface first.

For each scene (the paper's cube with a 6 mm lift, a 16.7 mm lift, and a
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
Then the MTM precision study (Mollemans et al. 2007, 2.3.5) on the same three scenes.

Writes accuracy_vs_time.{md,csv,png} and mtm_precision.{md,csv,png} to
doc/results/ (the quick mode to build/benchmarks/accuracy/quick/results/).
"""

import argparse
import os
import subprocess
import sys
import threading
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import report  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import summary  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HERE = os.path.join(ROOT, "benchmarks", "accuracy")
SOFTFACE = os.environ.get("SOFTFACE", os.path.join(ROOT, "build", "softface"))

# The paper's cube: outer faces held, the inner cube [35, 45]^3 is the bone.
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
    """'case i of N, elapsed, estimate' from the cost of the cases finished."""

    def __init__(self, total_cost):
        self.total, self.done, self.start, self.i, self.n = total_cost, 0., time.time(), 0, 0

    def elapsed(self):
        return f"elapsed {(time.time() - self.start) / 60:.1f} min"

    def step(self, label):
        self.i += 1
        print(f"[{self.i}/{self.n}] {label} ({self.elapsed()})", flush=True)

    def finish(self, label, cost):
        self.done += cost
        estimate = ""
        if 0 < self.done < self.total:
            elapsed = time.time() - self.start
            remaining = elapsed / self.done * (self.total - self.done)
            estimate = f", about {remaining / 60:.1f} min left"
        print(f"    done: {label} ({self.elapsed()}{estimate})", flush=True)


def run_finished(output):
    """Did the run of a case write its summary (softface writes it last)?"""
    return bool(summary.read(os.path.join(output, "summary.csv")))


# How the runs of this invocation are recorded with each case: the command
# and the commit softface was built from (set by main()).
RUN_RECORD = ""
# The softface processes running now, so that an interrupted run can end them.
RUNNING, RUNNING_LOCK = set(), threading.Lock()


def run_softface(prm, output):
    """Run one case; its log goes to OUTPUT.log, the machine's load as it
    starts to OUTPUT.load, and its wall time with this invocation's command
    and commit to OUTPUT.wall."""
    with open(output + ".load", "w") as f:
        # The 1-minute load average: 1 is this run alone.
        f.write(f"{os.getloadavg()[0]:.2f}\n")
    start = time.time()
    with open(output + ".log", "w") as out:
        process = subprocess.Popen([SOFTFACE, prm], stdout=out, stderr=subprocess.STDOUT)
        with RUNNING_LOCK:
            RUNNING.add(process)
        try:
            process.wait()
        finally:
            with RUNNING_LOCK:
                RUNNING.discard(process)
    if process.returncode < 0:           # ended by a signal: no record of a finished run
        return
    with open(output + ".wall", "w") as f:
        f.write(f"{time.time() - start:.1f}\t{RUN_RECORD}\n")


def case_outcome(output):
    """(ok, error) of a case's run, from its summary.csv; a run that wrote
    none stopped on its input, whose one-line error is the last line of its
    log."""
    log = output + ".log"
    if not os.path.exists(log):
        sys.exit(f"no run of {output}.prm (missing {log}); run without --report-only")
    rows = summary.read(os.path.join(output, "summary.csv"))
    if not rows:
        lines = [line for line in open(log) if line.startswith("softface: error:")]
        return False, lines[-1][len("softface: error:"):].strip() if lines else "no summary.csv"
    failed = [r for r in rows if r["status"] != "ok"]
    return not failed, "; ".join(r["error"] for r in failed)


def run_text(scene_cases):
    """How a scene's cases ran, from the records their runs left (OUTPUT.wall
    and OUTPUT.load): their number and wall time, the commands and commits
    that ran them and the machine's 1-minute load average as each started (a
    run alone makes it about 1 on this 2-core machine; more means other work,
    or --jobs, shared it)."""
    loads, walls, records, last, missing = [], [], [], 0., 0
    for case in scene_cases:
        wall, load = case["output"] + ".wall", case["output"] + ".load"
        if not os.path.exists(wall):
            missing += 1
            continue
        fields = open(wall).read().rstrip("\n").split("\t")
        walls.append(float(fields[0]))
        record = fields[1] if len(fields) > 1 else "an earlier version of this benchmark"
        if record not in records:
            records.append(record)
        last = max(last, os.path.getmtime(wall))
        if os.path.exists(load):
            loads.append(float(open(load).read()))
    text = (f"Measured by {'; '.join(records) or '?'} on {report.machine()}: "
            f"{len(walls)} softface runs took {sum(walls) / 60:.1f} min of wall time in all")
    if missing:
        text += f" ({missing} cases have no record of their run)"
    if loads:
        text += (f"; the machine's load average (1 minute) as they started: median "
                 f"{np.median(loads):.2f}, maximum {max(loads):.2f} (one run alone is about 1)")
    return text + "."


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


def case_name(case, config):
    kind, model, tets = case["kind"], case["model"], case["tets"]
    name = f"{kind}_{file_name_of(model)}_{tets}"
    if kind == "reference":
        name = f"{kind}_graded{config['reference_grading']}_{tets}"
    if kind == "model error":
        name = f"linear_p2_graded{config['reference_grading']}_{tets}"
    if kind == "sweep":
        name += "_" + "_".join(v for _, v in knob_pairs(case["setting"]))
    return name


def case_label(case):
    key, kind, model, tets = case["scene"]["key"], case["kind"], case["model"], case["tets"]
    label = f"{key}: {kind} {model}, {tets} tets"
    if kind == "model error":
        label = f"{key}: model error, linear elasticity on quadratic tetrahedra, {tets} tets"
    if kind == "sweep":
        label += ", " + knob_text(case["setting"])
    return label


# Peak memory per tetrahedron, bytes (the 16.7 mm lift's 280k-tetrahedron
# reference took 10.2 GB), so that --jobs never runs two cases whose sum
# would not fit: a process killed for memory would count as a failed case.
MEMORY_PER_TET = {"reference": 40e3, "model error": 40e3, "precision": 10e3,
                  "nonlinear fem": 4e3}


def memory_estimate(case):
    kind = case["kind"]
    return case["tets"] * MEMORY_PER_TET.get(case["model"] if kind == "sweep" else kind, 2e3)


def memory_budget():
    """Bytes the cases may use together: 80% of the machine's memory."""
    for line in open("/proc/meminfo"):
        if line.startswith("MemTotal:"):
            return 0.8 * int(line.split()[1]) * 1024
    return float("inf")


def run_cases(todo, jobs, progress):
    """Run the cases of TODO (each a softface process on one thread), JOBS at a
    time. Each worker takes the most expensive waiting case whose memory
    estimate fits beside the running ones (a case runs alone if it fits with
    none), so the last to finish is a short one and two large references never
    share the machine. A failure of the driver or Ctrl-C ends the running
    processes and starts no other case."""
    pending = sorted(todo, key=lambda c: -c["cost"]) if jobs > 1 else list(todo)
    budget, state = memory_budget(), dict(used=0., running=0, error=None)
    cond = threading.Condition()

    def take():
        with cond:
            while True:
                if state["error"] is not None or not pending:
                    return None
                for case in pending:
                    need = memory_estimate(case)
                    if state["running"] == 0 or state["used"] + need <= budget:
                        pending.remove(case)
                        state["used"] += need
                        state["running"] += 1
                        return case
                cond.wait()

    def worker():
        while True:
            case = take()
            if case is None:
                return
            try:
                with cond:
                    progress.step(case["label"] + " started")
                run_softface(case["prm"], case["output"])
                if state["error"] is None:
                    ok, message = case_outcome(case["output"])
                    with cond:
                        progress.finish(case["label"] + ("" if ok else f": failed, {message}"),
                                        case["cost"])
            except BaseException as error:    # noqa: B902 (also SystemExit of case_outcome)
                with cond:
                    state["error"] = state["error"] or error
            finally:
                with cond:
                    state["used"] -= memory_estimate(case)
                    state["running"] -= 1
                    cond.notify_all()

    def stop(error):
        with cond:
            state["error"] = state["error"] or error
            cond.notify_all()
        with RUNNING_LOCK:
            for process in RUNNING:
                process.terminate()

    threads = [threading.Thread(target=worker, daemon=True) for _ in range(jobs)]
    for t in threads:
        t.start()
    try:
        for t in threads:
            while t.is_alive():
                t.join(timeout=1.)
                if state["error"] is not None:
                    stop(state["error"])
    except KeyboardInterrupt as interrupt:
        stop(interrupt)
        for t in threads:
            t.join()
    if state["error"] is not None:
        raise state["error"]


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true",
                        help="coarser meshes and fewer settings (under 5 minutes)")
    parser.add_argument("--scenes", default="",
                        help="comma-separated scene keys to run (default: all); the reports "
                        "keep the other scenes' sections, rows and plots from their last run")
    parser.add_argument("--jobs", type=int, default=1,
                        help="cases run at once, each on one thread (default 1; 2 uses both "
                        "cores of a 2-core machine: the times then share memory bandwidth, "
                        "and the reports state the load)")
    parser.add_argument("--report-only", action="store_true",
                        help="no softface runs: rewrite the reports from the outputs an "
                        "earlier run left in build/benchmarks/accuracy/")
    parser.add_argument("--resume", action="store_true",
                        help="run only the cases whose parameter file changed or whose "
                        "earlier run did not finish; reuse the others' outputs")
    args = parser.parse_args()
    if args.jobs < 1:
        sys.exit(f"--jobs {args.jobs}: give 1 or more")
    config = QUICK if args.quick else FULL
    work = os.path.join(ROOT, "build", "benchmarks", "accuracy",
                        "quick" if args.quick else "full")
    results = (os.path.join(work, "results") if args.quick
               else os.path.join(ROOT, "doc", "results"))
    os.makedirs(results, exist_ok=True)
    keys = [s["key"] for s in SCENES]
    chosen = [k for k in args.scenes.split(",") if k] if args.scenes else keys
    unknown = [k for k in chosen if k not in keys]
    if unknown:
        sys.exit(f"--scenes: unknown scene {', '.join(unknown)} (known: {', '.join(keys)})")
    scenes = [s for s in SCENES if s["key"] in chosen]
    command = ("benchmarks/run_all.sh" + (" --quick" if args.quick else "")
               + (f" --scenes {','.join(chosen)}" if args.scenes else "")
               + (f" --jobs {args.jobs}" if args.jobs > 1 else ""))
    global RUN_RECORD
    commit = subprocess.run(["git", "-C", ROOT, "describe", "--always", "--dirty"],
                            capture_output=True, text=True).stdout.strip() or "?"
    RUN_RECORD = f"`{command}` (softface at commit {commit})"

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

    # 1. Parameter files. The evaluation points of a scene are run here:
    # every other case of the scene names their file.
    points_file, todo = {}, []
    for case in cases:
        scene, key, kind = case["scene"], case["scene"]["key"], case["kind"]
        folder = os.path.join(work, key)
        os.makedirs(folder, exist_ok=True)
        output = os.path.join(folder, case_name(case, config))
        prm = output + ".prm"
        case.update(output=output, prm=prm, label=case_label(case),
                    cost=case["tets"] * COST[case["model"] if kind == "sweep" else kind])
        if kind == "points":
            unchanged = write_prm(prm, scene, case["model"], case["tets"], case["settings"],
                                  output, nodal=True)
            if not reuse(unchanged, output):
                run_softface(prm, output)
            ok, message = case_outcome(output)
            if not ok:
                sys.exit(f"the evaluation-point run failed: {message} (log {output}.log)")
            points, _ = read_values(os.path.join(output, "displacements_linear_fem.csv"))
            points = free_points(points)
            points_file[key] = os.path.join(folder, "evaluation_points.csv")
            np.savetxt(points_file[key], points, delimiter=",", header="x,y,z",
                       comments="", fmt="%.12g")
            print(f"{key}: {len(points)} evaluation points (free vertices of the "
                  f"{case['tets']}-tetrahedron mesh)", flush=True)
            continue
        if kind == "precision":
            case["history"] = output + "_history.csv"
            settings = [("Stop gradient threshold", "1e-5"), ("Active set", "false"),
                        ("Maximum sweeps", "100000"), ("Precision history file",
                                                       case["history"])]
            unchanged = write_prm(prm, scene, case["model"], case["tets"], settings, output)
        else:
            unchanged = write_prm(prm, scene, case["model"], case["tets"], case["settings"],
                                  output, points=points_file[key],
                                  grading=config["reference_grading"] if kind != "sweep" else 1,
                                  symmetric=(kind != "sweep"))
        if not reuse(unchanged, output):
            todo.append(case)

    # 2. The runs.
    progress = Progress(sum(c["cost"] for c in todo))
    progress.n = len(todo)
    if todo:
        print(f"{len(todo)} of {len(cases)} cases to run, {args.jobs} at a time", flush=True)
    run_cases(todo, args.jobs, progress)

    # 3. The reports, from the cases' outputs.
    rows, reference_rows, linear_p2_rows, precision = [], [], [], {}
    reference_values = {}
    for case in cases:
        key, kind, model, tets = case["scene"]["key"], case["kind"], case["model"], case["tets"]
        output = case["output"]
        if kind == "points":
            continue
        ok, message = case_outcome(output)
        row = summary_row(output, model)
        if kind == "precision":
            precision[key] = dict(scene=case["scene"], tets=tets, ok=ok, message=message,
                                  vertices=row["n_vertices"] if row else "",
                                  history=np.loadtxt(case["history"], delimiter=",",
                                                     skiprows=1, ndmin=2) if ok else None)
            continue
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
            continue
        if kind == "reference":
            entry["n_dofs"] = row["n_dofs"] if row else ""
            entry["values"] = read_values(values_path)[1] if ok and row else None
            reference_rows.append(entry)
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

    # What each scene's run cost, from its cases' records (also when resumed
    # or rewritten later), and whether its finest reference converged.
    runs = {}
    for scene in scenes:
        key = scene["key"]
        runs[key] = run_text([c for c in cases if c["scene"]["key"] == key
                              and c["kind"] != "points"])
        finest = reference_meshes(config, key)[-1]
        used = next((r for r in reference_rows if r["scene"] == key and r.get("used")), None)
        if used is not None and used["level"] != finest:
            warning = (f"The finest reference ({finest} tetrahedra) failed: this scene's errors "
                       f"are against the {used['level']}-tetrahedron one.")
            print(f"warning: {key}: {warning}", flush=True)
            runs[key] += f" **{warning}**"
    # A run of some scenes keeps the others' results (full mode only: the
    # quick results are a folder of their own).
    shown = scenes if args.quick else SCENES
    keep = {s["key"] for s in shown if s not in scenes}
    report.write_accuracy(results, command, shown, rows, reference_rows, linear_p2_rows,
                          tightest, THRESHOLDS, MODELS, runs, keep)
    report.write_precision(results, command, shown, precision, keep)
    print(f"done in {(time.time() - progress.start) / 60:.1f} min; results in {results}/ "
          "(accuracy_vs_time.md/.csv/.png, mtm_precision.md/.csv/.png)", flush=True)


if __name__ == "__main__":
    try:
        main()
    except KeyboardInterrupt:
        sys.exit("interrupted: the running cases were ended; --resume runs the rest and keeps "
                 "the finished ones")
