#!/usr/bin/python3
"""Linear FEM ('cg amg') on the generated cube, serially and on two MPI ranks in groups of one and
of two (a group's member holds none of the scene's cells): peak memory of the largest
and the smallest rank, the phases, the whole process. Serial once, then the two groupings
interleaved REPEAT times (memory does not move from run to run; the times do: medians). Fails if
an answer differs from the serial one by more than 1e-8 relative.
With --point-models: the mass tensor and mass spring models instead (their members get the
tetrahedra from rank 0), compared with the serial answers to 1e-12 (the ranks sweep in the serial
order).

usage: groups.py SOFTFACE MPIEXEC WORK RESULTS "COMMAND" [--quick] [--point-models]
Writes RESULTS/scaling_groups.md, .csv, .png (scaling_groups_points.* with --point-models).
"""
import csv, os, re, statistics, sys

import softface_run

import numpy as np
import matplotlib
matplotlib.use("Agg")  # headless
import matplotlib.pyplot as plt  # noqa: E402

softface, mpiexec, work, results, command = sys.argv[1:6]
quick = "--quick" in sys.argv[6:]
points = "--point-models" in sys.argv[6:]
# Memory does not move from run to run: the point models' longer runs once.
N, REPEAT = (30000, 1) if quick else (2000000, 1 if points else 3)
MODELS = ["mass tensor", "mass spring"] if points else ["linear fem"]
WHAT = "the mass tensor and mass spring models" if points else "linear FEM (`cg amg`)"
STEM = "scaling_groups_points" if points else "scaling_groups"
TOLERANCE = 1e-12 if points else 1e-8
os.makedirs(work, exist_ok=True)
os.makedirs(results, exist_ok=True)
CASES = [("serial", 1, 1), ("2 ranks, groups of 1", 2, 1), ("2 ranks, groups of 2", 2, 2)]


def run(label, ranks, group, k):
    tag = f"{label.replace(' ', '_').replace(',', '')}_{k}"
    out_dir = os.path.join(work, tag)
    prm = os.path.join(work, tag + ".prm")
    scene = softface_run.cube_scene(N, MODELS, out_dir, nodal=True)
    scene = scene.replace("  set Threads = 1\n", f"  set Threads = 1\n  set Mesh group size = {group}\n"
                          "  subsection linear fem\n    set Solver = cg amg\n  end\n")
    with open(prm, "w") as f:
        f.write(scene)
    out, wall = softface_run.run(softface, mpiexec, prm, ranks, "group scaling")
    row = {"command s": wall}
    m = re.search(r"mesh generated cube: (\d+) tetrahedra, (\d+) vertices", out)
    row["tets"], row["vertices"] = int(m.group(1)), int(m.group(2))
    row.update(softface_run.phases(out, "linear fem"))
    for model in MODELS:
        row[model + " setup"], row[model + " solve"], _ = softface_run.table_row(out, model)
    row["process s"], row["peak MB"] = softface_run.process_figures(out)
    smallest = re.search(r"the smallest (\d+) MB", out)
    row["smallest peak MB"] = float(smallest.group(1)) if smallest else row["peak MB"]
    row["holds none"] = "members hold none of the scene's cells" in out
    row["u"] = np.concatenate([np.loadtxt(os.path.join(out_dir, "displacements_"
                                              + model.replace(" ", "_") + ".csv"),
                                              delimiter=",", skiprows=1)[:, 3:6]
                               for model in MODELS])
    return row


rows = {label: [] for label, _, _ in CASES}
rows["serial"].append(run("serial", 1, 1, 0))
print(f"serial: peak {rows['serial'][0]['peak MB']:.0f} MB, {rows['serial'][0]['process s']:.1f} s",
      flush=True)
for k in range(REPEAT):
    for label, ranks, group in CASES[1:]:
        r = run(label, ranks, group, k)
        rows[label].append(r)
        print(f"{label} ({k + 1}/{REPEAT}): peak {r['peak MB']:.0f} / {r['smallest peak MB']:.0f} MB "
              f"(largest / smallest rank), "
              + ("" if points else f"partition {r.get('partition', 0):.2f} s, ") +
              f"{r['process s']:.1f} s", flush=True)
u0 = rows["serial"][0]["u"]
difference = {}
for label, _, _ in CASES[1:]:
    difference[label] = max(np.abs(r["u"] - u0).max() / np.abs(u0).max() for r in rows[label])
    if difference[label] > TOLERANCE:
        sys.exit(f"group scaling: {label} differs from the serial answer by {difference[label]:.2e}")
if not all(r["holds none"] for r in rows["2 ranks, groups of 2"]):
    sys.exit("group scaling: with groups of 2 the members held the scene's cells")

FIGURES = [("peak memory, largest rank MB", "peak MB"),
           ("peak memory, smallest rank MB", "smallest peak MB")]
if points:
    FIGURES += [(f"{model} {phase} s", f"{model} {phase}")
                for model in MODELS for phase in ("setup", "solve")]
else:
    FIGURES += [("partition s", "partition"), ("assemble s", "assemble"),
                ("preconditioner s", "preconditioner"), ("solve s", "solve")]
FIGURES += [("whole process s", "process s")]


def median(label, key):
    return statistics.median(r.get(key, 0.0) for r in rows[label])


def cell(label, key):
    # The serial run has no partition: nothing to show.
    return f"{median(label, key):.4g}" if any(key in r for r in rows[label]) else ""


csv_rows = [[label] + [cell(c, key) for c, _, _ in CASES] for label, key in FIGURES]
with open(os.path.join(results, STEM + ".csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["figure"] + [c for c, _, _ in CASES])
    w.writerows(csv_rows)

fig, ax = plt.subplots(figsize=(6, 4))
x = np.arange(len(CASES))
ax.bar(x - 0.2, [median(c, "peak MB") for c, _, _ in CASES], 0.4, label="largest rank")
ax.bar(x + 0.2, [median(c, "smallest peak MB") for c, _, _ in CASES], 0.4, label="smallest rank")
ax.set_xticks(x, [c for c, _, _ in CASES], fontsize=8)
ax.set_ylabel("peak memory per rank, MB")
ax.set_title(f"{WHAT.replace('`', '')}, {rows['serial'][0]['tets']} tetrahedra", fontsize=9)
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(results, STEM + ".png"), dpi=110)

commit = softface_run.commit()
s, g1, g2 = (rows[c][0] for c, _, _ in CASES)
md = ["# Groups of MPI ranks whose members hold no scene cells"
      + (": the point models" if points else ""), "",
      "How much memory a rank saves when it holds no cell of the scene (an MPI group of two "
      "whose root makes the mesh), against a serial run and two ranks without groups, and "
      "whether the answers stay the serial ones.", "",
      f"Reproduce: `{command.strip()}`.", "",
      f"Measured at commit {commit or 'unknown'} on x86_64, {os.cpu_count()} cores.", "",
      f"The generated cube (6 mm lift), "
      f"{s['tets']} tetrahedra, {s['vertices']} vertices, {WHAT} alone, one "
      "thread per rank; serially once, then `mpiexec -n 2` with `Models/Mesh group size` 1 and 2 "
      + ("once each. " if REPEAT == 1 else f"interleaved, {REPEAT} times (medians). ")
      + ("With groups of 2 rank 0 reads or makes the mesh and sends rank 1 the arrays per vertex "
         "and DoF and the tetrahedra and their tissues (17 bytes a cell, for each model's "
         "`PointMesh`); rank 1 holds no cell of the scene (no fields are written, so no partition "
         "is made)" if points else
         "With groups of 2 rank 0 reads or makes the mesh "
         "and describes rank 1's part; rank 1 holds its part and the arrays per vertex and DoF "
         "rank 0 sent it, no cell of the scene")
      + ". Peak memory is each process's VmHWM as softface reports it. "
      f"CSV: [{STEM}.csv]({STEM}.csv).", "",
      "| | " + " | ".join(c for c, _, _ in CASES) + " |", "|---|---|---|---|"]
for row in csv_rows:
    md.append("| " + " | ".join(row) + " |")
md += ["", f"![memory]({STEM}.png)", "", "## What the numbers show", "",
       f"- Largest difference to the serial answer (relative): groups of 1 "
       f"{difference['2 ranks, groups of 1']:.1e}, groups of 2 {difference['2 ranks, groups of 2']:.1e}.",
       f"- The member's peak is {median('2 ranks, groups of 2', 'smallest peak MB') / median('serial', 'peak MB'):.3f} "
       f"of the serial run's and {median('2 ranks, groups of 2', 'smallest peak MB') / median('2 ranks, groups of 1', 'smallest peak MB'):.3f} "
       "of a rank's without groups; the root's stays near a rank's without groups, since it holds the "
       "scene and its own part."]
if points:
    md += ["- The member holds no triangulation or DoFs of the scene, but each point model's whole "
           "`PointMesh` (about 50 bytes a cell, reckoned from its arrays' lengths; one per model) "
           "and the vectors in serial numbering."]
md += [""]
with open(os.path.join(results, STEM + ".md"), "w") as f:
    f.write("\n".join(md) + "\n")
print(f"group scaling: wrote {os.path.join(results, STEM + '.md')}")
