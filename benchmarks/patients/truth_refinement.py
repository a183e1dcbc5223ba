#!/usr/bin/python3
"""The report of truth_refinement.sh: one patient's post-operative truth on
meshes of several sizes, compared point by point on the dense skin.

Usage: truth_refinement.py WORK PATIENT FACTOR... --distances CSV
       --results DIR --command TEXT

Reads WORK/<PATIENT>_x<factor>/{skin_preoperative.ply,
skin_reference_fem.ply, summary.csv, wall_ms, stderr.txt}; writes
DIR/truth_refinement.md, .csv and .png. The change of a level is the 50/90/95%
percentile and maximum of |x_finer - x_coarser| over the skin points that the
truth moves on both meshes (a point out of reach of a mesh keeps its
pre-operative place there). The criterion is the accuracy benchmark's: the
last change at most a tenth of the smallest 90% distance (p90 of |d|) of a
model to the truth of this patient.
"""
import argparse
import csv
import os
import sys

import numpy as np
import matplotlib
matplotlib.use("Agg")  # headless
import matplotlib.pyplot as plt  # noqa: E402

import render  # noqa: E402  (benchmarks/patients/render.py: read_ply)


def summary(directory):
    with open(os.path.join(directory, "summary.csv"), newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["model"] == "reference fem"]
    if not rows:
        sys.exit(f"truth_refinement: {directory}: no reference fem row in "
                 "its summary.csv")
    return rows[0]


def peak_mb(directory):
    with open(os.path.join(directory, "stderr.txt")) as f:
        for line in f:
            if "Maximum resident set size" in line:
                return int(line.split()[-1]) / 1024.0
    return None


def smallest_p90(path, patient):
    if not os.path.exists(path):
        return None, None
    best = (None, None)
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            if r["patient"] == patient and r.get("p90 mm"):
                v = float(r["p90 mm"])
                if best[0] is None or v < best[0]:
                    best = (v, f"{r['model']}, {r['mapping']}")
    return best


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("work")
    parser.add_argument("patient")
    parser.add_argument("factors", nargs="+")
    parser.add_argument("--distances", required=True)
    parser.add_argument("--results", required=True)
    parser.add_argument("--command", required=True)
    a = parser.parse_args()

    levels, failed = [], []
    for factor in a.factors:
        d = os.path.join(a.work, f"{a.patient}_x{factor}")
        s = summary(d)
        if s["status"] != "ok":
            failed.append((factor, int(s["n_tets"]), s["error"]))
            continue
        pre = render.read_ply(os.path.join(d, "skin_preoperative.ply"))[0]
        post = render.read_ply(os.path.join(d, "skin_reference_fem.ply"))[0]
        with open(os.path.join(d, "wall_ms")) as f:
            wall = int(f.read()) / 1000.0
        levels.append(dict(factor=factor, tets=int(s["n_tets"]),
                           dofs=int(s["n_dofs"]), solve=float(s["solve_s"]),
                           setup=float(s["setup_s"]), wall=wall,
                           peak=peak_mb(d), pre=pre, post=post,
                           umax=float(s["max_displacement_mm"]),
                           details=s["details"]))
    if len(levels) < 2:
        sys.exit("truth_refinement: fewer than two levels succeeded: "
                 + "; ".join(f"x{f}: {e}" for f, _, e in failed))
    for lv in levels[1:]:
        if lv["pre"].shape != levels[0]["pre"].shape or \
                np.abs(lv["pre"] - levels[0]["pre"]).max() > 1e-4:
            sys.exit("truth_refinement: the levels' pre-operative skins "
                     "differ; they must come from the same CT")

    rows = []
    changes = []
    for coarse, fine in zip(levels, levels[1:]):
        moved = ((np.linalg.norm(coarse["post"] - coarse["pre"], axis=1) > 0) &
                 (np.linalg.norm(fine["post"] - fine["pre"], axis=1) > 0))
        diff = np.linalg.norm(fine["post"] - coarse["post"], axis=1)[moved]
        changes.append(np.sort(diff))
        p50, p90, p95 = np.percentile(diff, [50, 90, 95])
        rows.append(dict(coarse=coarse, fine=fine, points=int(moved.sum()),
                         p50=p50, p90=p90, p95=p95, max=diff.max()))

    bound, bound_of = smallest_p90(a.distances, a.patient)
    criterion = None if bound is None else bound / 10.0
    last = rows[-1]["p90"]
    os.makedirs(a.results, exist_ok=True)
    base = os.path.join(a.results, "truth_refinement")

    with open(base + ".csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["patient", "coarse factor", "coarse tets", "fine factor",
                    "fine tets", "points", "p50 mm", "p90 mm", "p95 mm",
                    "max mm"])
        for r in rows:
            w.writerow([a.patient, r["coarse"]["factor"], r["coarse"]["tets"],
                        r["fine"]["factor"], r["fine"]["tets"], r["points"],
                        f"{r['p50']:.6g}", f"{r['p90']:.6g}",
                        f"{r['p95']:.6g}", f"{r['max']:.6g}"])

    fig, ax = plt.subplots(figsize=(7, 4.2))
    for r, c in zip(rows, changes):
        ax.plot(c, np.linspace(0, 1, len(c)),
                label=f"{r['coarse']['tets']} -> {r['fine']['tets']} "
                      "tetrahedra")
    if criterion is not None:
        ax.axvline(criterion, color="k", ls="--",
                   label=f"a tenth of the smallest p90 distance "
                         f"({criterion:.3g} mm)")
    ax.axhline(0.9, color="0.6", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("change of the post-operative skin point (mm)")
    ax.set_ylabel("fraction of skin points")
    ax.set_title(f"{a.patient}: the truth (quadratic Neo-Hooke) refined")
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(base + ".png", dpi=110)

    import subprocess
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True,
                            cwd=os.path.dirname(os.path.abspath(__file__))
                            ).stdout.strip()
    out = [f"# Is the post-operative truth converged? ({a.patient})", "",
           "Whether a phantom's post-operative truth (the model-made skin the "
           "patients benchmark measures every model against) has converged "
           "with its mesh, and so how small a difference between two models "
           "it can resolve.", "",
           f"Reproduce: `{a.command.strip()}` (about 25 min).", "",
           f"Measured at commit {commit} on x86_64, {os.cpu_count()} cores.",
           "",
           f"The truth scene `prm/patients/{a.patient}_truth.prm` (quadratic "
           "compressible Neo-Hooke, skin, fat and muscle, the planning plus "
           "its known error) run on meshes of "
           + ", ".join(f"{lv['factor']}" for lv in levels) +
           " times its target number of tetrahedra, everything else equal. "
           "The change of a level is |x_finer - x_coarser| of each dense "
           "skin point that both truths move (the skin of the CT is the same "
           "at every level). CSV: [truth_refinement.csv](truth_refinement.csv).",
           "", "| factor | tets | DoFs | setup s | solve s | run s | peak MB "
           "| max |u| mm | Newton |", "|---|---|---|---|---|---|---|---|---|"]
    for lv in levels:
        out.append(f"| {lv['factor']} | {lv['tets']} | {lv['dofs']} | "
                   f"{lv['setup']:.3g} | {lv['solve']:.3g} | {lv['wall']:.3g} "
                   f"| {lv['peak']:.0f} | {lv['umax']:.4g} | "
                   f"{lv['details'].replace(';', ', ')} |")
    for factor, tets, error in failed:
        out.append(f"| {factor} | {tets} | failed: {error} |||||||")
    out += ["", "| from | to | points | p50 mm | p90 mm | p95 mm | max mm |",
            "|---|---|---|---|---|---|---|"]
    for r in rows:
        out.append(f"| {r['coarse']['tets']} | {r['fine']['tets']} | "
                   f"{r['points']} | {r['p50']:.3g} | {r['p90']:.3g} | "
                   f"{r['p95']:.3g} | {r['max']:.3g} |")
    out += ["", "![truth refinement](truth_refinement.png)", "",
            "## What the numbers show", ""]
    if len(rows) >= 2 and rows[-1]["p90"] > 0:
        r0, r1 = rows[-2]["p90"], rows[-1]["p90"]
        rate = r0 / r1
        out.append(f"- The change falls {rate:.2f}x per doubling (p90 {r0:.3g}, then "
                   f"{r1:.3g} mm), so by Richardson extrapolation the factor-1 "
                   f"truth lies about {r0 * rate / (rate - 1):.2g} mm (p90) from "
                   "the answer its equations converge to.\n")
    if criterion is None:
        out.append(f"No model distances for {a.patient} in "
                   f"`{a.distances}`: run `benchmarks/patients/run.sh "
                   f"{a.patient}` for the criterion.")
    else:
        met = last <= criterion
        tets = levels[-2]["tets"]
        out.append(
            f"- **Criterion** (the accuracy benchmark's: the last change at "
            f"most a tenth of the smallest 90% distance reported): the last "
            f"change's p90 is {last:.3g} mm against {criterion:.3g} mm (a "
            f"tenth of {bound:.3g} mm, {bound_of}): "
            + (f"**met**. The benchmark's truth ({tets} tetrahedra at factor "
               f"1) differs from the finer one by less than a tenth of the "
               f"distances it judges."
               if met else
               f"**not met**: the truth's own discretisation moves its skin "
               f"by more than a tenth of the smallest distance it judges; "
               f"differences between models smaller than about "
               f"{10 * last:.2g} mm are not resolved by it."))
    if criterion is not None and last > criterion and len(rows) >= 2 \
            and rows[-2]["p90"] > last:
        # An extrapolation, labelled so: the change falls by the last
        # ratio per doubling; memory grows with the DoFs.
        rate = rows[-2]["p90"] / last
        with open("/proc/meminfo") as f:
            machine_gb = int(f.readline().split()[1]) / 1024 ** 2
        doublings = int(np.ceil(np.log(last / criterion) / np.log(rate)))
        finest = levels[-1]
        out.append(
            "\n## Limits\n\n- **Extrapolated (a model, not a measurement):** the change fell "
            f"by {rate:.2f}x from one doubling to the next; at that rate it "
            f"falls below the criterion after {doublings} more doubling(s), at "
            f"a mesh of about {finest['tets'] * 2 ** doublings:.3g} tetrahedra "
            f"(factor {float(finest['factor']) * 2 ** doublings:g}) whose "
            f"truth would need about "
            f"{finest['peak'] * 2 ** doublings / 1024:.0f} GB if memory keeps "
            f"growing with the DoFs (this machine has {machine_gb:.0f} GB).")
    with open(base + ".md", "w") as f:
        f.write("\n".join(out) + "\n")
    print(f"truth_refinement: wrote {base}.md (last change p90 {last:.3g} mm"
          + ("" if criterion is None else f", criterion {criterion:.3g} mm")
          + ")")


if __name__ == "__main__":
    main()
