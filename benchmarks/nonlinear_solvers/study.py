#!/usr/bin/python3
"""Predictors, load paths and KINSOL against softface's Newton loop and CalculiX.

    /usr/bin/python3 study.py [CASE_DIR ...] [--softface PATH] [--baseline PATH]
                              [--baseline-name NAME] [--out DIR] [--timeout S]

CASE_DIR: cases made by make_case.py (default: /tmp/nl/<name> for cube30k_svk, offcentre_mild,
offcentre_hard). For each case and law (St. Venant-Kirchhoff: scene.prm; compressible
Neo-Hooke: scene_neo_hooke.prm) it runs softface once per variant

    Load path        = linear | rigid
    Predictor        = join only | tangent | secant
    Nonlinear solver = newton | kinsol

(12 variants, 'Indefinite tangent = cut back'; the defaults are rigid, tangent, newton), the
defaults with 'Indefinite tangent = lu' and 'lu and unstable', and, with --baseline, the same scene
on another softface build (the hand-written loop: linear path, the tangent predictor
taken whole). One process at a time, one thread each, interleaved by case so that machine
load falls on all variants alike. Writes DIR/nonlinear_solvers.{md,csv,png} (DIR defaults to
doc/results of this repository); findings.md beside this script is copied into the Markdown.
--render DIR re-writes the Markdown and the plot into --out from DIR's nonlinear_solvers.csv and
nonlinear_solvers_run.json (after editing findings.md), without running anything.
"""
import csv
import json
import os
import subprocess
import sys
import time

import numpy as np

import run_softface

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
LAWS = {"svk": ("St. Venant-Kirchhoff", "scene.prm"),
        "neo_hooke": ("Neo-Hooke", "scene_neo_hooke.prm")}
PATHS = ("linear", "rigid")
PREDICTORS = ("join only", "tangent", "secant")
CORRECTORS = ("newton", "kinsol")
DEFAULT = ("rigid", "tangent", "newton")
INDEFINITE = ("cut back", "lu", "lu and unstable")


def variants(baseline_name):
    out = []
    if baseline_name:
        out.append({"name": baseline_name, "baseline": True})
    for corrector in CORRECTORS:
        for path in PATHS:
            for predictor in PREDICTORS:
                out.append({"name": "%s, %s, %s" % (path, predictor, corrector),
                            "path": path, "predictor": predictor, "corrector": corrector})
    # The defaults with the other answers to an indefinite tangent.
    for indefinite in INDEFINITE[1:]:
        out.append({"name": "%s, %s, %s, %s" % (DEFAULT + (indefinite,)),
                    "path": DEFAULT[0], "predictor": DEFAULT[1], "corrector": DEFAULT[2],
                    "indefinite": indefinite})
    return out


def tag_of(law, variant):
    return "study_%s_%s" % (law, variant["name"].replace(", ", "-").replace(" ", "_"))


def write_scene(case_dir, law, variant):
    """The case's scene with the variant's options and its own output folder."""
    base = open(os.path.join(case_dir, LAWS[law][1])).read()
    tag = tag_of(law, variant)
    extra = ["", "# study.py: %s" % variant["name"]]
    if not variant.get("baseline"):
        extra += ["subsection Models", "  subsection nonlinear fem",
                  "    set Load path        = " + variant["path"],
                  "    set Predictor        = " + variant["predictor"],
                  "    set Nonlinear solver = " + variant["corrector"],
                  "    set Indefinite tangent = " + variant.get("indefinite", INDEFINITE[0]),
                  "  end", "end"]
    extra += ["subsection Output",
              "  set Output directory = " + os.path.join(case_dir, "softface_" + tag), "end", ""]
    name = tag + ".prm"
    with open(os.path.join(case_dir, name), "w") as f:
        f.write(base + "\n".join(extra))
    return name, tag


def details_of(res):
    """damped predictors / secant predictors refused, from summary.csv's details (ok runs)."""
    out = {}
    for item in res.get("details", "").split(";"):
        if ":" in item:
            k, v = item.split(":", 1)
        elif "=" in item:
            k, v = item.split("=", 1)
        else:
            continue
        k = k.strip()
        if k in ("damped predictors", "secant predictors refused"):
            out[k] = v.strip()
    return out


def fmt_load(x):
    return "-" if x is None else "%.1f %%" % (100 * x)


def main(argv):
    args, opts = [], {"--softface": run_softface.DEFAULT_SOFTFACE, "--baseline": None,
                      "--baseline-name": "before", "--out": os.path.join(ROOT, "doc", "results"),
                      "--timeout": "1800", "--render": None}
    it = iter(argv[1:])
    for a in it:
        if a in opts:
            opts[a] = next(it)
        elif a.startswith("--"):
            sys.exit(__doc__)
        else:
            args.append(a)
    if opts["--render"]:
        # Re-render the Markdown and the plot from an earlier run's CSV and run.json (after
        # editing findings.md).
        out = opts["--out"]
        rows = read_rows(os.path.join(opts["--render"], "nonlinear_solvers.csv"))
        run = json.load(open(os.path.join(opts["--render"], "nonlinear_solvers_run.json")))
        write_results(out, run["cases"], rows, run)
        return
    cases = [os.path.abspath(a) for a in args] or [
        os.path.join("/tmp/nl", n) for n in ("cube30k_svk", "offcentre_mild", "offcentre_hard")]
    for c in cases:
        if not os.path.exists(os.path.join(c, "result.json")):
            sys.exit("study.py: %s has no result.json: make the case first (make_case.py)" % c)
    baseline_name = opts["--baseline-name"] if opts["--baseline"] else None
    todo = variants(baseline_name)
    softface = os.path.abspath(opts["--softface"])
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    for binary in (softface, opts["--baseline"]):
        if binary and not os.access(binary, os.X_OK):
            sys.exit("study.py: %s is not an executable (build softface first)" % binary)
    binary_note = "%s, built %s" % (softface, time.strftime(
        "%Y-%m-%d %H:%M", time.localtime(os.path.getmtime(softface))))
    started = time.strftime("%Y-%m-%d %H:%M")
    load_before = os.getloadavg()
    rows = []
    n_runs, done = len(cases) * len(LAWS) * len(todo), 0
    t_start = time.time()
    # Interleaved: every variant of one case and law before the next.
    for case_dir in cases:
        info = json.load(open(os.path.join(case_dir, "result.json")))
        for law in LAWS:
            for v in todo:
                scene, tag = write_scene(case_dir, law, v)
                binary = os.path.abspath(opts["--baseline"]) if v.get("baseline") else softface
                res = run_softface.run(case_dir, law, binary, float(opts["--timeout"]),
                                       scene=scene, tag=tag)
                done += 1
                row = {"case": info["case"]["name"], "n_tets": info["n_tets"],
                       "law": LAWS[law][0], "variant": v["name"],
                       "default": (v.get("path"), v.get("predictor"), v.get("corrector"),
                                   v.get("indefinite", INDEFINITE[0])) == DEFAULT + INDEFINITE[:1],
                       "status": res["status"], "load_reached": res["load_reached"],
                       "load_steps": res["load_steps"], "cutbacks": res["cutbacks"],
                       "newton_iterations": res.get("newton_iterations",
                                                    res["newton_iterations_converged"]),
                       "wall_s": res["wall_s"], "solve_s": res.get("solve_s"),
                       "min_volume_ratio": res.get("min_volume_ratio"),
                       "diff_to_calculix_max_mm": res.get("diff_to_calculix_max_mm"),
                       "reason": res.get("reason", res.get("error", ""))
                       if res["status"] != "ok" else ""}
                row.update(details_of(res))
                rows.append(row)
                print("[%d/%d, %.0f s] %s %s %s: %s load %s, %d cut-backs, %s its, %.1f s" % (
                    done, n_runs, time.time() - t_start, row["case"], law, v["name"],
                    row["status"], fmt_load(row["load_reached"]), row["cutbacks"],
                    row["newton_iterations"], row["wall_s"]), flush=True)
    write_results(opts["--out"], cases, rows, {
        "command": "/usr/bin/python3 benchmarks/nonlinear_solvers/study.py " +
                   " ".join(argv[1:]),
        "commit": commit, "binary": binary_note, "started": started, "minutes": (time.time() - t_start) / 60,
        "load_before": load_before, "load_after": os.getloadavg()})


def read_rows(path):
    rows = []
    with open(path) as f:
        for r in csv.DictReader(f):
            for k in ("n_tets", "load_steps", "cutbacks"):
                r[k] = int(r[k])
            for k in ("load_reached", "wall_s", "solve_s", "min_volume_ratio",
                      "diff_to_calculix_max_mm"):
                r[k] = float(r[k]) if r[k] not in ("", None) else None
            r["default"] = r["default"] == "True"
            for k in ("damped predictors", "secant predictors refused"):
                if r.get(k) in ("", None):
                    r.pop(k, None)
            rows.append(r)
    return rows


def write_results(out, cases, rows, run):
    os.makedirs(out, exist_ok=True)
    run = dict(run, cases=cases)
    with open(os.path.join(out, "nonlinear_solvers_run.json"), "w") as f:
        json.dump(run, f, indent=1)
    keys = ["case", "n_tets", "law", "variant", "default", "status", "load_reached",
            "load_steps", "cutbacks", "newton_iterations", "wall_s", "solve_s",
            "min_volume_ratio", "diff_to_calculix_max_mm", "damped predictors",
            "secant predictors refused", "reason"]
    with open(os.path.join(out, "nonlinear_solvers.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow(r)

    md = ["# Nonlinear solvers: predictors, load paths and KINSOL against the hand loop and "
          "CalculiX", "",
          "How far St. Venant-Kirchhoff and Neo-Hooke solves get on hard cases with each load "
          "path, predictor and corrector (softface's Newton loop or KINSOL), against CalculiX "
          "NLGEOM on the same meshes, and what each costs.", "",
          "Reproduce: `%s` (%.0f minutes)." % (run["command"], run["minutes"]), "",
          "Measured at commit %s (%s) on 2 cores, one softface process at a time, one thread; "
          "load average %.1f before and %.1f after." % (
              run["commit"], run["binary"], run["load_before"][0], run["load_after"][0]), "",
          "Data: `nonlinear_solvers.csv`. The cases are made by "
          "`benchmarks/nonlinear_solvers/make_case.py` (README there).", "",
          "![load reached and Newton iterations per variant](nonlinear_solvers.png)", ""]
    findings = os.path.join(HERE, "findings.md")
    if os.path.exists(findings):
        md += [open(findings).read().rstrip(), ""]
    md += ["## CalculiX NLGEOM (St. Venant-Kirchhoff) on the same meshes", "",
           "From `make_case.py`'s run of CalculiX 2.20 (one thread; its wall time was measured "
           "then, not in this run).", "",
           "| case | tets | largest prescribed u (mm) | load reached | last load with no "
           "tetrahedron inverted | increments / cut-backs | iterations | wall s | min det F at "
           "its end |", "|---|---|---|---|---|---|---|---|---|"]
    for c in cases:
        r = json.load(open(os.path.join(c, "result.json")))
        x = r.get("calculix", {})
        md.append("| %s | %d | %.2f | %s | %s | %s / %s | %s | %s | %s |" % (
            r["case"]["name"], r["n_tets"], r["max_prescribed_displacement_mm"],
            fmt_load(x.get("load_reached")), fmt_load(x.get("last_load_without_inversion")),
            x.get("converged_increments", "-"), x.get("cutbacks", "-"),
            x.get("iterations", "-"), x.get("wall_s", "-"),
            "%.3f (%d inverted)" % (x["min_volume_ratio"], x["n_inverted"])
            if "min_volume_ratio" in x else "-"))
    md += ["", "## softface, every variant", "",
           "Variant = load path, predictor, corrector[, Indefinite tangent]; **bold** the defaults. Newton iterations: "
           "all of them when the run finished, else those of its converged load steps. min det F: "
           "the smallest volume ratio of the final state (finished P1 runs). |u - CalculiX|: the "
           "largest nodal difference to CalculiX's answer where both reached the whole planning "
           "(for Neo-Hooke another law: not a check of the solver).", ""]
    for case in dict.fromkeys(r["case"] for r in rows):
        for law in dict.fromkeys(r["law"] for r in rows):
            sel = [r for r in rows if r["case"] == case and r["law"] == law]
            if not sel:
                continue
            md += ["### %s, %s" % (case, law), "",
                   "| variant | load reached | load steps | cut-backs | Newton its | wall s | "
                   "solve s | min det F | max abs(u - CalculiX) mm | damped / secant refused | "
                   "stopped because |", "|---|---|---|---|---|---|---|---|---|---|---|"]
            for r in sel:
                name = "**%s**" % r["variant"] if r["default"] else r["variant"]
                reason = r["reason"]
                if len(reason) > 160:
                    reason = reason[:157] + "..."
                md.append("| %s | %s | %d | %d | %s | %.1f | %s | %s | %s | %s / %s | %s |" % (
                    name, fmt_load(r["load_reached"]), r["load_steps"], r["cutbacks"],
                    r["newton_iterations"], r["wall_s"],
                    "%.2f" % r["solve_s"] if r["solve_s"] is not None else "-",
                    "%.3f" % r["min_volume_ratio"] if r["min_volume_ratio"] is not None else "-",
                    "%.2g" % r["diff_to_calculix_max_mm"]
                    if r["diff_to_calculix_max_mm"] is not None else "-",
                    r.get("damped predictors", "-"), r.get("secant predictors refused", "-"),
                    reason.replace("|", "/")))
            md.append("")
    with open(os.path.join(out, "nonlinear_solvers.md"), "w") as f:
        f.write("\n".join(md))
    plot(out, cases, rows)


def plot(out, cases, rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    names = list(dict.fromkeys(r["variant"] for r in rows))
    case_names = list(dict.fromkeys(r["case"] for r in rows))
    fig, axes = plt.subplots(1, 2, figsize=(15, 6))
    width = 0.8 / len(case_names)
    y = np.arange(len(names))
    for panel, (law, what, label) in enumerate(
            [("St. Venant-Kirchhoff", "load_reached", "load reached (%)"),
             ("Neo-Hooke", "wall_s", "wall time (s), full load reached")]):
        ax = axes[panel]
        for k, case in enumerate(case_names):
            vals = []
            for n in names:
                r = [x for x in rows if x["case"] == case and x["law"] == law
                     and x["variant"] == n]
                v = r[0][what] if r else np.nan
                if what == "load_reached":
                    v = 100 * v
                elif r and r[0]["status"] != "ok":
                    v = np.nan
                vals.append(v)
            ax.barh(y + k * width, vals, width, label=case)
        if what == "load_reached":
            by_name = {json.load(open(os.path.join(c, "result.json")))["case"]["name"]: c
                       for c in cases}
            for k, case in enumerate(case_names):
                if case in by_name:
                    x = json.load(open(os.path.join(by_name[case], "result.json"))).get(
                        "calculix", {})
                    if "last_load_without_inversion" in x:
                        ax.axvline(100 * x["last_load_without_inversion"], ls="--",
                                   color="C%d" % k, lw=1)
            ax.set_title("St. Venant-Kirchhoff: load reached\n(dashed: CalculiX's last load "
                         "with no tetrahedron inverted)")
        else:
            ax.set_title("Neo-Hooke: wall time to the full load")
        ax.set_yticks(y + 0.4 - width / 2)
        ax.set_yticklabels(names if panel == 0 else [""] * len(names))
        ax.set_xlabel(label)
        ax.invert_yaxis()
        ax.grid(axis="x", alpha=0.3)
    axes[0].legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "nonlinear_solvers.png"), dpi=110)


if __name__ == "__main__":
    main(sys.argv)
