"""Report of benchmarks/patients/clinical_size.sh: time and peak memory per
stage of the phantom patient read from its CT at 1 mm and at 0.5 mm voxels.

    /usr/bin/python3 benchmarks/patients/clinical_size.py WORK RESULTS

WORK is the benchmark's work folder (voxel_1/, voxel_0.5/), RESULTS the
folder the table (clinical_size.md), CSV and PNG go to.
"""
import csv
import os
import platform
import re
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

work, results = sys.argv[1], sys.argv[2]
voxels = ["1", "0.5"]


def figures(path):
    """patient.csv: figure,value."""
    with open(path) as f:
        return {row["figure"]: row["value"] for row in csv.DictReader(f)}


def model_seconds(path):
    """Each model's setup and solve time (s) from summary.csv."""
    out = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            out[row["model"]] = float(row["setup_s"]) + float(row["solve_s"])
    return out


def time_v(path):
    text = open(path).read()
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", text).group(1)
    parts = [float(p) for p in wall.split(":")]
    seconds = sum(p * 60 ** i for i, p in enumerate(reversed(parts)))
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1))
    return seconds, rss / 1024.0 ** 2


rows = []
for v in voxels:
    d = os.path.join(work, f"voxel_{v}")
    f = figures(os.path.join(d, "run", "patient.csv"))
    models = model_seconds(os.path.join(d, "run", "summary.csv"))
    wall, peak = time_v(os.path.join(d, "time.txt"))
    stages = {
        "read CT": float(f["CT read s"]),
        "segmentation and surfaces": float(f["segmentation s"]),
        "bone parts": float(f["bone split s"]),
        "mesh": float(f["mesh s"]),
    }
    for m, s in models.items():
        stages[m] = s
    # The dense skin's mapping for each model and the output files.
    stages["skin mapping and files"] = wall - sum(stages.values())
    rows.append(dict(voxel=v, ct=f["CT voxels"], tets=f["tetrahedra"], stages=stages,
                     wall=wall, peak=peak))

names = list(rows[0]["stages"].keys())
with open(os.path.join(results, "clinical_size.csv"), "w", newline="") as out:
    w = csv.writer(out)
    w.writerow(["voxel mm", "CT voxels", "tetrahedra"] + [n + " s" for n in names] +
               ["wall s", "peak memory GB"])
    for r in rows:
        w.writerow([r["voxel"], r["ct"], r["tets"]] + [f"{r['stages'][n]:.2f}" for n in names] +
                   [f"{r['wall']:.1f}", f"{r['peak']:.2f}"])

fig, ax = plt.subplots(figsize=(8, 4))
left = [0.0] * len(rows)
for n in names:
    values = [r["stages"][n] for r in rows]
    ax.barh([f"{r['voxel']} mm\n{r['ct']}" for r in rows], values, left=left, label=n)
    left = [a + b for a, b in zip(left, values)]
for i, r in enumerate(rows):
    ax.text(r["wall"], i, f"  {r['wall']:.0f} s wall, {r['peak']:.1f} GB", va="center")
ax.set_xlabel("seconds (stages stacked; the text: the whole run)")
ax.set_xlim(0, max(r["wall"] for r in rows) * 1.5)
ax.legend(fontsize=8, loc="lower right")
ax.set_title("Phantom patient from its CT file to the four models' table")
fig.tight_layout()
fig.savefig(os.path.join(results, "clinical_size.png"), dpi=100)

commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                        text=True).stdout.strip()
cores = os.cpu_count()
lines = [
    "# A clinical-size CT end to end",
    "",
    "What a CT of clinical resolution (0.5 mm voxels) costs beside a 1 mm one, stage by stage, "
    "from the CT file to the four models' table, in time and peak memory.",
    "",
    "Reproduce: `benchmarks/patients/clinical_size.sh` (about 5 min).",
    "",
    f"Measured at commit {commit} on {platform.machine()}, {cores} cores.",
    "",
    "The phantom patient of `prm/patient.prm` (mandibular advancement and genioplasty, six "
    "bone segments, the four models) acquired at 1 mm and at 0.5 mm voxels, then run as a "
    "user's CT is: from reading the CT file (NIfTI) through segmentation and surfaces, bone "
    "parts and mesh to the four models' table. The phantom's own acquisition is not timed. "
    "CSV: [clinical_size.csv](clinical_size.csv).",
    "",
    "| voxels | CT | tetrahedra | " + " | ".join(names) + " | whole run | peak memory |",
    "|---|---|---|" + "---|" * len(names) + "---|---|",
]
for r in rows:
    lines.append(f"| {r['voxel']} mm | {r['ct']} | {r['tets']} | " +
                 " | ".join(f"{r['stages'][n]:.1f} s" for n in names) +
                 f" | {r['wall']:.1f} s | {r['peak']:.2f} GB |")
lines += [
    "",
    "Stage times as the run reports them (`patient.csv`, `summary.csv`); the whole run is the "
    "wall time of the process, its peak memory the largest resident set (`/usr/bin/time -v`); "
    "what the stages leave of it is the mapping of every model's answer onto the dense skin (both "
    "mappings) and the output files (skins, solution.vtu).",
    "",
    "![Stage times at 1 mm and 0.5 mm voxels](clinical_size.png)",
    "",
]
if len(rows) >= 2:
    a, b = rows[0], rows[-1]
    grown = sorted(names, key=lambda n: -b["stages"][n])[:2]
    lines += [
        "## What the numbers show",
        "",
        f"- At {b['voxel']} mm voxels the whole run takes {b['wall'] / a['wall']:.1f} times "
        f"as long as at {a['voxel']} mm ({b['wall']:.1f} s against {a['wall']:.1f} s) and "
        f"peaks at {b['peak']:.2f} GB against {a['peak']:.2f} GB.",
        "- The time goes to the stages whose work grows with the voxels (the dense skin comes from them): " +
        ", ".join(f"{n} {b['stages'][n]:.1f} s against {a['stages'][n]:.1f} s" for n in grown) +
        f". The mesh ({b['tets']} against {a['tets']} tetrahedra) and the four models cost "
        "about the same at both resolutions.",
        "",
        "## Limits",
        "",
        "- One run at each resolution on a phantom; the phantom's own acquisition is not timed.",
        "",
    ]
open(os.path.join(results, "clinical_size.md"), "w").write("\n".join(lines))
print("\n".join(lines))
