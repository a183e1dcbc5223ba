#!/usr/bin/python3
"""The quadratic reference model (Neo-Hooke, cg amg) on one MPI rank and on two: the
generated cube (6 mm lift) at SIZES tetrahedra, one thread per rank, once each: serially, on two
ranks, and on two ranks in a group of two (`Mesh group size = 2`: only rank 0 makes the mesh, the
other rank holds none of the scene's cells); peak memory per rank (softface's own report: the
largest and the smallest rank's), the phases and the whole process. Fails if an answer on two
ranks differs from the serial one by more than 1e-8 relative (Newton to a residual of 1e-10).

usage: reference.py SOFTFACE MPIEXEC WORK RESULTS "COMMAND" [--quick] [--sizes N,N,...]
(--sizes: the cube's requested tetrahedra, default 100000,300000). Writes
RESULTS/scaling_reference.md, .csv, .png.
"""
import csv, os, re, sys

import softface_run

import numpy as np
import matplotlib
matplotlib.use("Agg")  # headless
import matplotlib.pyplot as plt  # noqa: E402

softface, mpiexec, work, results, command = sys.argv[1:6]
options = sys.argv[6:]
quick = "--quick" in options
SIZES = [20000] if quick else [100000, 300000]
if "--sizes" in options:
    SIZES = [int(n) for n in options[options.index("--sizes") + 1].split(",")]
os.makedirs(work, exist_ok=True)
os.makedirs(results, exist_ok=True)

# (ranks, mesh group size): serial, two ranks, two ranks whose second holds no cells.
CONFIGS = [(1, 1), (2, 1), (2, 2)]


def run(n, ranks, group):
    tag = f"n{n}_r{ranks}_g{group}"
    out_dir = os.path.join(work, tag)
    prm = os.path.join(work, tag + ".prm")
    with open(prm, "w") as f:
        f.write(softface_run.cube_scene(n, ["reference fem"], out_dir, nodal=True))
        f.write(f"subsection Models\n  set Mesh group size = {group}\nend\n")
    before = os.times()
    out, wall = softface_run.run(softface, mpiexec, prm, ranks, "reference scaling")
    after = os.times()
    # Other work beside a run moves its times (not its memory): the share of the run's wall time
    # x ranks its processes ran (MPI ranks spin while they wait, so 1 unless the cores were shared).
    row = {"n": n, "ranks": ranks, "command s": wall,
           "cpu share": (after.children_user - before.children_user + after.children_system -
                         before.children_system) / (wall * ranks)}
    m = re.search(r"mesh generated cube: (\d+) tetrahedra, (\d+) vertices", out)
    row["tets"], row["vertices"] = int(m.group(1)), int(m.group(2))
    row.update(softface_run.phases(out, "reference fem"))
    row["setup s"], row["solve s"], row["newton"] = softface_run.table_row(out, "reference fem")
    row["linear iterations"] = int(re.search(r"linear iterations (\d+)", out).group(1))
    row["process s"], row["peak MB"] = softface_run.process_figures(out)
    smallest = re.search(r"the smallest (\d+) MB", out)
    row["smallest peak MB"] = float(smallest.group(1)) if smallest else row["peak MB"]
    row["u"] = np.loadtxt(os.path.join(out_dir, "displacements_reference_fem.csv"),
                          delimiter=",", skiprows=1)[:, 3:6]
    return row


rows = {}
for n in SIZES:
    for config in CONFIGS:
        rows[(n,) + config] = r = run(n, *config)
        print(f"{n} tets, {config[0]} rank(s) in groups of {config[1]}: {r['process s']:.1f} s, "
              f"peak {r['peak MB']:.0f} MB (largest rank), {r['smallest peak MB']:.0f} MB "
              f"(smallest), Newton {r['newton']}, CG {r['linear iterations']}", flush=True)
    u1 = rows[n, 1, 1]["u"]
    for config in CONFIGS[1:]:
        difference = np.abs(rows[(n,) + config]["u"] - u1).max() / np.abs(u1).max()
        rows[(n,) + config]["difference"] = difference
        if difference > 1e-8:
            sys.exit(f"reference scaling: at {n} tetrahedra {config[0]} ranks in groups of "
                     f"{config[1]} differ from one by {difference:.2e}")

PHASES = [("peak memory per rank MB (the largest rank)", "peak MB"),
          ("peak memory per rank MB (the smallest rank)", "smallest peak MB"),
          ("layout s (on 2 ranks with the partition)", "layout"),
          ("matrix positions s", "matrix positions"),
          ("AMG setup s", "preconditioner"), ("assembly s", "assembly"),
          ("linear solves s", "linear solves"), ("Newton solve s", "solve s"),
          ("whole process s", "process s")]
def ratio(label, x, y):
    """Memory: the ranks' over the serial run's; time: the serial run's over the ranks'."""
    if not (x and y):
        return ""
    return f"{y / x:.3g}" if label.startswith("peak") else f"{x / y:.3g}"


csv_rows = []
for n in SIZES:
    a, b, c = (rows[(n,) + config] for config in CONFIGS)
    for label, key in PHASES:
        x, y, z = a.get(key, 0.0), b.get(key, 0.0), c.get(key, 0.0)
        csv_rows.append([a["tets"], label, f"{x:.4g}", f"{y:.4g}", f"{z:.4g}",
                         ratio(label, x, y), ratio(label, x, z)])
with open(os.path.join(results, "scaling_reference.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["tets", "phase", "1 rank", "2 ranks", "2 ranks in a group of 2",
                "2 ranks against 1 (memory 2 / 1, time 1 / 2)", "in a group of 2 against 1"])
    w.writerows(csv_rows)

fig, ax = plt.subplots(figsize=(6, 4))
tets = [rows[n, 1, 1]["tets"] for n in SIZES]
ax.plot(tets, [rows[n, 1, 1]["peak MB"] for n in SIZES], "o-", label="1 rank")
ax.plot(tets, [rows[n, 2, 1]["peak MB"] for n in SIZES], "s-", label="2 ranks (largest rank)")
ax.plot(tets, [rows[n, 2, 2]["peak MB"] for n in SIZES], "^-",
        label="2 ranks in a group of 2 (largest rank)")
ax.plot(tets, [rows[n, 2, 2]["smallest peak MB"] for n in SIZES], "v--",
        label="2 ranks in a group of 2 (the member)")
ax.plot(tets, [0.55 * rows[n, 1, 1]["peak MB"] for n in SIZES], "k:", label="0.55 x 1 rank (target)")
ax.set_xlabel("tetrahedra")
ax.set_ylabel("peak memory per rank, MB")
ax.set_title("quadratic reference (Neo-Hooke, cg amg)")
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(results, "scaling_reference.png"), dpi=110)

commit = softface_run.commit()
with open("/proc/meminfo") as f:
    MACHINE_MB = int(re.search(r"MemTotal:\s+(\d+) kB", f.read()).group(1)) / 1024
md = ["# The quadratic reference on one MPI rank and on two", "",
      "How much of the serial run's peak memory a rank needs for the quadratic reference model "
      "on two ranks (target: at most 0.55 at the largest size one rank can hold), with and "
      "without a group whose member holds no cells, and whether the answers stay the serial "
      "ones.", "",
      f"Reproduce: `{command.strip()}`.", "",
      f"Measured at commit {commit or 'unknown'} on x86_64, {os.cpu_count()} cores.", "",
      "The generated cube (6 mm lift), the reference model "
      "(quadratic tetrahedra, Neo-Hooke, `cg amg`, Newton to 1e-10), one thread per rank, serial "
      "and `mpiexec -n 2` (each rank holding the scene's mesh, and in a group of two, where only "
      "rank 0 makes the mesh and rank 1 holds none of its cells), once each (memory does not move "
      "from run to run; the times do). Peak memory is softface's own report. CSV: "
      "[scaling_reference.csv](scaling_reference.csv).", ""]
for n in SIZES:
    a, b, c = (rows[(n,) + config] for config in CONFIGS)
    md += [f"## {a['tets']} tetrahedra, {a['vertices']} vertices", "",
           f"- Two ranks against one: {b['difference']:.1e} relative, in a group of two "
           f"{c['difference']:.1e}; Newton iterations {a['newton']}, {b['newton']} and "
           f"{c['newton']}, CG iterations {a['linear iterations']}, {b['linear iterations']} and "
           f"{c['linear iterations']}.",
           f"- Peak memory per rank, the largest rank: {b['peak MB'] / a['peak MB']:.3f} of the "
           f"serial run's, in a group of two {c['peak MB'] / a['peak MB']:.3f} (the "
           f"target: at most 0.55); the member without cells {c['smallest peak MB'] / a['peak MB']:.3f}. "
           f"The serial run's peak is {100 * a['peak MB'] / MACHINE_MB:.0f} % of this machine's "
           "memory.",
           f"- CPU time over wall time x ranks: {a['cpu share']:.2f} (1 rank), "
           f"{b['cpu share']:.2f} and {c['cpu share']:.2f} (2 ranks); below 1, other work shared "
           "the cores and the times.",
           "",
           "| | 1 rank | 2 ranks | 2 ranks, group of 2 | 2 ranks against 1 (memory 2 / 1, time 1 / 2) "
           "| group of 2 against 1 |", "|---|---|---|---|---|---|"]
    for row in csv_rows:
        if row[0] == a["tets"]:
            md.append("| " + " | ".join(row[1:]) + " |")
    md.append("")
md += ["![memory](scaling_reference.png)", "", "## What the numbers show", "",
       "- On the ranks the reference's DoFs are its quadratic element's on the ranks' parts of the "
       "mesh (no rank builds it on the whole mesh); the tangent, its copy for ML and ML itself "
       "are shared out. Every rank still holds Newton's vectors whole (8 bytes per quadratic DoF "
       "each) and the scene's arrays per vertex; each rank outside a group, and the root of a "
       "group, holds the scene's mesh too.", "",
       "## Limits", "",
       "- Each configuration ran once: the memory does not move from run to run, the times do "
       "(the CPU share above says how much other work shared the cores).", ""]
with open(os.path.join(results, "scaling_reference.md"), "w") as f:
    f.write("\n".join(md) + "\n")
print(f"reference scaling: wrote {os.path.join(results, 'scaling_reference.md')}")
