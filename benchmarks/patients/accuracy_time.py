#!/usr/bin/python3
"""What accuracy costs in time, on the phantom patients: each model's exact
distance to the post-operative skin (90 % percentile over the measured skin
points; the truth moved the same skin points, so every predicted point's
true position is known) against its time (setup + solve), over mesh sizes
(a factor times the patient's target number of tetrahedra) and, for the
point models, stop thresholds.

  benchmarks/patients/accuracy_time.py                 all ten, factors
                                                        0.5, 1, 2
  benchmarks/patients/accuracy_time.py --patients P2 P4 --factors 0.5,1
  benchmarks/patients/accuracy_time.py --report-only

Needs the truths that benchmarks/patients/run.sh makes (reused, never made
here) and a built build/softface. A case whose output folder holds the same
scene is not run again. Each patient's CT and segmentation are made once
(build/benchmarks/patients_accuracy/<P>/stages); each size meshes again.
Writes doc/results/patients_accuracy.{md,csv,png} and
patients_accuracy_each.png.
"""
import argparse
import csv
import os
import platform
import re
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "benchmarks"))
import summary  # noqa: E402

SOFTFACE = os.path.join(ROOT, "build", "softface")
WORK = os.path.join(ROOT, "build", "benchmarks", "patients_accuracy")
TRUTHS = os.path.join(ROOT, "build", "benchmarks", "patients")
RESULTS = os.path.join(ROOT, "doc", "results")
PATIENTS = [f"P{i}" for i in range(1, 11)]
MODELS = ["linear fem", "mass tensor", "mass spring", "nonlinear fem"]
POINT_MODELS = ["mass tensor", "mass spring"]
DEFAULT_THRESHOLD = 0.001  # the scenes' (and the paper's) stop threshold


def scene_text(patient, factor, threshold, models, truth):
    """The patient's scene at FACTOR times its target size, the point
    models stopping at THRESHOLD, measured against TRUTH."""
    text = open(os.path.join(ROOT, "prm", "patients", f"{patient}.prm")).read()
    target = int(re.search(r"set Target number of tetrahedra\s*=\s*(\d+)",
                           text).group(1))
    text = re.sub(r"(set Target number of tetrahedra\s*=\s*)\d+",
                  lambda m: m.group(1) + str(round(factor * target)), text)
    text = re.sub(r"set Post-operative skin\s*=.*",
                  f"set Post-operative skin = {truth}", text)
    text = re.sub(r"set Models\s*=.*", "set Models = " + ", ".join(models),
                  text)
    stages = os.path.join(WORK, patient, "stages")
    text += "\n".join([
        "", "subsection Scene", "  subsection Patient",
        f"    set Work directory = {stages}", "  end", "end",
        "subsection Models",
        "  subsection mass tensor",
        f"    set Stop gradient threshold = {threshold}", "  end",
        "  subsection mass spring", f"    set Stop threshold = {threshold}",
        "  end", "end",
        "subsection Skin", "  set Mapping = shape functions",
        "  set Correspondences = false", "end",
        "subsection Output", "  set Write VTU = false", "end", ""])
    return target, text


def cases(patients, factors, thresholds):
    for p in patients:
        for f in factors:
            yield p, f, DEFAULT_THRESHOLD, MODELS
            for t in thresholds:
                if t != DEFAULT_THRESHOLD:
                    yield p, f, t, POINT_MODELS


def folder(p, f, t):
    return os.path.join(WORK, p, f"x{f:g}_stop{t:g}")


def run(p, f, t, models):
    truth = os.path.join(TRUTHS, f"{p}_truth", "scene.prm")
    if not os.path.exists(truth):
        sys.exit(f"accuracy_time: no truth for {p} ({truth}); run "
                 f"benchmarks/patients/run.sh {p} first")
    out = folder(p, f, t)
    os.makedirs(out, exist_ok=True)
    _, text = scene_text(p, f, t, models, truth)
    text = re.sub(r"set Output directory\s*=.*",
                  f"set Output directory = {out}", text)
    prm = os.path.join(out, "scene.prm")
    done = os.path.join(out, "input.prm")
    if (os.path.exists(done) and open(done).read() == text and
            os.path.exists(os.path.join(out, "skin.csv"))):
        return "reused"
    with open(prm, "w") as f_out:
        f_out.write(text)
    start = time.time()
    with open(os.path.join(out, "log.txt"), "w") as log:
        code = subprocess.call([SOFTFACE, prm], stdout=log,
                               stderr=subprocess.STDOUT)
    return f"exit {code} in {time.time() - start:.0f} s"


def failures(patients, factors, thresholds):
    """(patient, factor, threshold, model, reason) of every model that ran
    and failed."""
    out = []
    for p, f, t, models in cases(patients, factors, thresholds):
        for r in summary.read(os.path.join(folder(p, f, t), "summary.csv")):
            if r["model"] in models and r["status"] != "ok":
                out.append((p, f, t, r["model"], r["error"]))
    return out


def collect(patients, factors, thresholds):
    rows = []
    for p, f, t, models in cases(patients, factors, thresholds):
        out = folder(p, f, t)
        skin_path = os.path.join(out, "skin.csv")
        if not os.path.exists(skin_path):
            continue
        with open(skin_path, newline="") as fin:
            skin = {r["model"]: r for r in csv.DictReader(fin)}
        for r in summary.read(os.path.join(out, "summary.csv")):
            if r["model"] not in models or r["status"] != "ok":
                continue
            s = skin.get(r["model"])
            if s is None or not s.get("exact p90 mm"):
                continue
            rows.append(dict(
                patient=p, factor=f, model=r["model"],
                stop_threshold=t if r["model"] in POINT_MODELS else "",
                tets=int(r["n_tets"]),
                seconds=float(r["setup_s"]) + float(r["solve_s"]),
                exact_p50_mm=float(s["exact p50 mm"]),
                exact_p90_mm=float(s["exact p90 mm"]),
                exact_p95_mm=float(s["exact p95 mm"]),
                closest_p90_mm=float(s["p90 mm"])))
    return rows


def label(r):
    return (f"{r['model']}, stop {r['stop_threshold']:g}"
            if r["stop_threshold"] != "" else r["model"])


def report(rows, command, patients, failed=()):
    if not rows:
        sys.exit("accuracy_time: no results to report")
    summary.write_rows(os.path.join(RESULTS, "patients_accuracy.csv"), rows)
    ran = sorted({r["patient"] for r in rows}, key=lambda p: int(p[1:]))
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short",
                             "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    md = ["# What accuracy costs in time, on the phantom patients\n",
          "What each model's accuracy against the post-operative truth "
          "costs in time on the ten phantom patients, over mesh sizes and "
          "the point models' stop thresholds.\n",
          f"Reproduce: `{command}` (about 36 min).\n",
          f"Measured at commit {commit} on {platform.machine()}, "
          f"{os.cpu_count()} cores.\n",
          "Each model's exact distance to the post-operative skin (the 90 % percentile "
          "over the measured skin points of |predicted - true|: the truth "
          "moved the same skin points, doc/skin.md) against its time "
          "(setup + solve, s), on meshes of a factor times each patient's "
          "target number of tetrahedra, the mass tensor and mass spring "
          "models also with other stop thresholds (mm per sweep; the "
          "scenes use 0.001). Shape-function mapping. Truths: "
          "`benchmarks/patients/run.sh` (their own error: "
          "[truth_refinement.md](truth_refinement.md)). Patients: "
          + ", ".join(ran) + ".\n",
          "## Mean over the patients\n",
          "| model | factor | tets (mean) | time s (mean) | exact p50 mm | "
          "exact p90 mm | exact p95 mm | closest p90 mm | patients |",
          "|---|---|---|---|---|---|---|---|---|"]
    groups = {}
    for r in rows:
        groups.setdefault((label(r), r["factor"]), []).append(r)
    order = sorted(groups, key=lambda k: (
        MODELS.index(groups[k][0]["model"]), k[0], k[1]))
    for key in order:
        g = groups[key]
        md.append(f"| {key[0]} | {key[1]:g} | "
                  f"{np.mean([r['tets'] for r in g]):.0f} | "
                  f"{np.mean([r['seconds'] for r in g]):.3g} | "
                  f"{np.mean([r['exact_p50_mm'] for r in g]):.3f} | "
                  f"{np.mean([r['exact_p90_mm'] for r in g]):.3f} | "
                  f"{np.mean([r['exact_p95_mm'] for r in g]):.3f} | "
                  f"{np.mean([r['closest_p90_mm'] for r in g]):.3f} | "
                  f"{len(g)} |")
    md.append("")
    md.append("![exact p90 against time, mean over the patients]"
              "(patients_accuracy.png)\n")
    md.append("Each patient:\n")
    md.append("![exact p90 against time, each patient]"
              "(patients_accuracy_each.png)\n")
    md.append("## What the numbers show\n")
    # Per model: its most accurate setting, and the cheapest one within
    # 0.05 mm of it (means over the patients where all of the model's
    # settings ran).
    md.append("What each model's accuracy costs (means of the table above):\n")
    for model in MODELS:
        these = [(k, groups[k]) for k in order if groups[k][0]["model"] == model]
        if not these:
            continue
        p90 = {k: np.mean([r["exact_p90_mm"] for r in g]) for k, g in these}
        secs = {k: np.mean([r["seconds"] for r in g]) for k, g in these}
        best = min(p90, key=p90.get)
        cheap = min((k for k in p90 if p90[k] <= p90[best] + 0.05),
                    key=secs.get)
        md.append(f"- {model}: most accurate {best[0]} at factor {best[1]:g}, "
                  f"exact p90 {p90[best]:.3f} mm in {secs[best]:.3g} s; "
                  f"within 0.05 mm of it for the least time: {cheap[0]} at "
                  f"factor {cheap[1]:g}, {p90[cheap]:.3f} mm in "
                  f"{secs[cheap]:.3g} s.")
    # How much the mesh moves each model's p90 (the scenes' threshold).
    moved = []
    for lab in dict.fromkeys(k[0] for k in order):
        g = [k for k in order if k[0] == lab]
        r0 = groups[g[0]][0]
        if len(g) < 2 or r0["stop_threshold"] not in ("", DEFAULT_THRESHOLD):
            continue
        means = [np.mean([r["exact_p90_mm"] for r in groups[k]]) for k in g]
        moved.append(abs(means[0] - means[-1]))
    if moved:
        md.append(f"- From the coarsest to the finest mesh the mean exact p90 of each "
                  f"model (at the scenes' stop threshold) moves by {min(moved):.2f}-"
                  f"{max(moved):.2f} mm, no more than the truth's own estimated error "
                  "(about 0.3 mm, [truth_refinement.md](truth_refinement.md)).")
    md.append("")
    if failed:
        md.append("Runs that failed (left out of the means above; their "
                  "reason, from `summary.csv`):\n")
        for p, f, t, model, reason in failed:
            md.append(f"- {p}, factor {f:g}, {model}"
                      + (f", stop {t:g}" if model in POINT_MODELS else "")
                      + f": {reason}")
        md.append("")
    md.append("CSV (every patient, model, size and threshold): "
              "[patients_accuracy.csv](patients_accuracy.csv).\n")
    md.append("## Limits\n")
    md.append("- The truths are model-made (quadratic Neo-Hooke, the nonlinear FEM's "
              "own law) and about 0.3 mm (p90) from their converged answer: "
              "differences below that are not resolved. The patients are "
              "phantoms, not the paper's CT scans.\n")
    with open(os.path.join(RESULTS, "patients_accuracy.md"), "w") as f:
        f.write("\n".join(md))
    figures(rows, groups, ran)


def figures(rows, groups, patients):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    colours = {m: f"C{i}" for i, m in enumerate(MODELS)}
    markers = {"": "o", 0.01: "v", 0.001: "o", 0.0001: "^"}

    def draw(ax, these):
        for key in sorted({label(r) for r in these}):
            g = sorted([r for r in these if label(r) == key],
                       key=lambda r: r["factor"])
            model = g[0]["model"]
            ax.plot([r["seconds"] for r in g],
                    [r["exact_p90_mm"] for r in g], "-",
                    marker=markers.get(g[0]["stop_threshold"], "s"),
                    color=colours[model], label=key, lw=1, ms=4)
        ax.set_xscale("log")
        ax.grid(True, which="both", lw=0.3)

    fig, ax = plt.subplots(figsize=(7.5, 5))
    means = []
    for (key, factor), g in groups.items():
        means.append(dict(model=g[0]["model"],
                          stop_threshold=g[0]["stop_threshold"],
                          factor=factor,
                          seconds=np.mean([r["seconds"] for r in g]),
                          exact_p90_mm=np.mean([r["exact_p90_mm"]
                                                for r in g])))
    draw(ax, means)
    ax.set_xlabel("time, setup + solve (s), mean over the patients")
    ax.set_ylabel("exact 90 % distance (mm), mean over the patients")
    ax.set_title("each line: mesh factors " +
                 ", ".join(f"{f:g}" for f in sorted({r['factor']
                                                     for r in rows})))
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, "patients_accuracy.png"), dpi=110)
    plt.close(fig)

    cols = 5
    n_rows = (len(patients) + cols - 1) // cols
    fig, axes = plt.subplots(n_rows, cols, figsize=(3.2 * cols, 3 * n_rows),
                             squeeze=False)
    for ax, p in zip(axes.ravel(), patients):
        draw(ax, [r for r in rows if r["patient"] == p])
        ax.set_title(p, fontsize=9)
        ax.tick_params(labelsize=7)
    for ax in axes.ravel()[len(patients):]:
        ax.set_axis_off()
    axes[0][0].legend(fontsize=5)
    fig.supxlabel("time, setup + solve (s)")
    fig.supylabel("exact 90 % distance (mm)")
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, "patients_accuracy_each.png"), dpi=100)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--patients", nargs="+", default=PATIENTS)
    parser.add_argument("--factors", default="0.5,1,2")
    parser.add_argument("--thresholds", default="0.01,0.001,0.0001")
    parser.add_argument("--report-only", action="store_true")
    args = parser.parse_args()
    factors = [float(x) for x in args.factors.split(",")]
    thresholds = [float(x) for x in args.thresholds.split(",")]
    for p in args.patients:
        if p not in PATIENTS:
            sys.exit(f"accuracy_time: no patient {p} (P1 ... P10)")
    if not args.report_only:
        if not os.access(SOFTFACE, os.X_OK):
            sys.exit("accuracy_time: build/softface is missing; run ./test.sh "
                     "or ./run.sh first")
        todo = list(cases(args.patients, factors, thresholds))
        for k, (p, f, t, models) in enumerate(todo, 1):
            outcome = run(p, f, t, models)
            print(f"accuracy_time: [{k}/{len(todo)}] {p}, factor {f:g}, "
                  f"stop {t:g} ({', '.join(models)}): {outcome}", flush=True)
    command = "benchmarks/patients/accuracy_time.py " + " ".join(
        a for a in sys.argv[1:] if a != "--report-only")
    if args.report_only:
        command = command.strip() + "`, the report rewritten by `--report-only"
    report(collect(args.patients, factors, thresholds), command.strip(),
           args.patients, failures(args.patients, factors, thresholds))
    print("accuracy_time: wrote doc/results/patients_accuracy.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
