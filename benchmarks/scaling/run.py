#!/usr/bin/python3
"""Strong scaling, one MPI rank against two (issue 20): linear FEM (cg amg) on the generated cube
(6 mm lift) of about 500k and 2M tetrahedra, one thread per rank, serial and `mpiexec -n 2`
interleaved, REPS repetitions; per phase the median time and the ratio one rank / two ranks.

usage: run.py SOFTFACE MPIEXEC WORK RESULTS "COMMAND" [--quick]
Writes RESULTS/scaling.md, scaling.csv, scaling.png. Fails if the two ranks' displacement differs
from the serial one by more than 1e-8 relative (both CG to 1e-10).
"""
import csv, os, re, subprocess, sys, time
from statistics import median

import numpy as np
import matplotlib
matplotlib.use("Agg")  # headless
import matplotlib.pyplot as plt  # noqa: E402

softface, mpiexec, work, results, command = sys.argv[1:6]
quick = "--quick" in sys.argv[6:]
REPS = 1 if quick else 3
SIZES = [30000] if quick else [500000, 2000000]
os.makedirs(work, exist_ok=True)
os.makedirs(results, exist_ok=True)
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")

SCENE = """subsection Scene
  set Mesh source = cube
  subsection Cube
    set Target number of tetrahedra = {n}
  end
end
subsection Models
  set Models  = linear fem
  set Threads = 1
end
subsection Output
  set Output directory          = {out}
  set Write VTU                 = false
  set Write nodal displacements = {nodal}
end
"""


def run(n, ranks, rep):
    tag = f"n{n}_r{ranks}"
    out_dir = os.path.join(work, tag)
    prm = os.path.join(work, tag + ".prm")
    with open(prm, "w") as f:
        # The answers are compared on the first repetition only.
        f.write(SCENE.format(n=n, out=out_dir, nodal="true" if rep == 0 else "false"))
    cmd = [softface, prm] if ranks == 1 else [mpiexec, "-n", str(ranks), softface, prm]
    start = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - start
    if p.returncode != 0:
        sys.exit(f"scaling: {' '.join(cmd)} failed:\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    out = p.stdout
    row = {"tets requested": n, "ranks": ranks, "rep": rep + 1, "command s": wall}
    m = re.search(r"mesh generated cube: (\d+) tetrahedra, (\d+) vertices, \d+ free DoFs \(([\d.]+) s\)", out)
    row["tets"], row["vertices"], row["scene s"] = int(m.group(1)), int(m.group(2)), float(m.group(3))
    phases = re.search(r"^linear fem phases \(s\):(.*)$", out, re.M).group(1)
    for name, value in re.findall(r"([a-zA-Z][a-zA-Z ()]*?) ([\d.]+)(?=\s|$)", phases):
        row[name.strip()] = float(value)
    row["iterations"] = int(re.search(r"^ *linear fem +\d+ +\d+ +\d+ +[\d.]+ +[\d.]+ +(\d+)", out, re.M).group(1))
    row["process s"] = float(re.search(r"Wall time ([\d.]+) s", out).group(1))
    row["peak MB per rank"] = float(re.search(r"peak memory (\d+) MB", out).group(1))
    if rep == 0:
        with open(os.path.join(out_dir, "displacements_linear_fem.csv")) as f:
            row["u"] = np.loadtxt(f, delimiter=",", skiprows=1)[:, 3:6]
    return row


rows = []
for n in SIZES:
    for rep in range(REPS):
        for ranks in (1, 2):
            r = run(n, ranks, rep)
            rows.append(r)
            print(f"{n} tets, rep {rep + 1}, {ranks} rank(s): {r['command s']:.1f} s, "
                  f"CG {r['iterations']}", flush=True)

# The serial run's phases (sparsity, assemble, eliminate join DoFs, preconditioner, solve)
# against the distributed one's (partition, assemble, preconditioner, solve).
PHASES = [("scene (mesh, join points; every rank)", ["scene s"], ["scene s"]),
          ("partition (layout on the ranks)", [], ["partition"]),
          ("assembly (sparsity, matrix, joins)", ["sparsity", "assemble", "eliminate join DoFs"],
           ["assemble"]),
          ("AMG setup", ["preconditioner"], ["preconditioner"]),
          ("CG solve", ["solve"], ["solve"]),
          ("assembly + AMG + CG", ["sparsity", "assemble", "eliminate join DoFs",
                                   "preconditioner", "solve"],
           ["assemble", "preconditioner", "solve"]),
          ("whole process", ["process s"], ["process s"])]


def med(n, ranks, keys):
    vals = [sum(r.get(k, 0.0) for k in keys) for r in rows if r["tets requested"] == n and r["ranks"] == ranks]
    return median(vals) if keys else 0.0


table, csv_rows = [], []
for n in SIZES:
    serial = [r for r in rows if r["tets requested"] == n and r["ranks"] == 1]
    two = [r for r in rows if r["tets requested"] == n and r["ranks"] == 2]
    u1 = serial[0]["u"]
    u2 = two[0]["u"]
    diff = np.abs(u2 - u1).max() / np.abs(u1).max()
    if diff > 1e-8:
        sys.exit(f"scaling: at {n} tetrahedra two ranks differ from one by {diff:.2e} relative")
    for label, k1, k2 in PHASES:
        t1, t2 = med(n, 1, k1), med(n, 2, k2)
        csv_rows.append([serial[0]["tets"], label, f"{t1:.4g}", f"{t2:.4g}",
                         f"{t1 / t2:.3g}" if t1 > 0 and t2 > 0 else ""])
    table.append(dict(n=n, tets=serial[0]["tets"], vertices=serial[0]["vertices"], diff=diff,
                      it1=sorted({r["iterations"] for r in serial}),
                      it2=sorted({r["iterations"] for r in two}),
                      mem1=median(r["peak MB per rank"] for r in serial),
                      mem2=median(r["peak MB per rank"] for r in two)))

with open(os.path.join(results, "scaling.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["tets", "phase", "1 rank s", "2 ranks s", "1 / 2"])
    w.writerows(csv_rows)

fig, axes = plt.subplots(1, len(SIZES), figsize=(5.5 * len(SIZES), 4.2), squeeze=False)
for ax, t in zip(axes[0], table):
    labels = [p[0].split(" (")[0] for p in PHASES]
    t1 = [med(t["n"], 1, p[1]) for p in PHASES]
    t2 = [med(t["n"], 2, p[2]) for p in PHASES]
    x = np.arange(len(labels))
    ax.bar(x - 0.2, t1, 0.4, label="1 rank")
    ax.bar(x + 0.2, t2, 0.4, label="2 ranks")
    ax.set_xticks(x)
    ax.set_xticklabels(labels, rotation=30, ha="right", fontsize=8)
    ax.set_ylabel("s (median)")
    ax.set_title(f"linear FEM, {t['tets']} tetrahedra")
    ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(results, "scaling.png"), dpi=110)

try:
    commit = subprocess.run(["git", "-C", os.path.dirname(os.path.abspath(__file__)), "rev-parse",
                             "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
except OSError:
    commit = ""
md = ["# Strong scaling: one MPI rank against two (linear FEM)", "",
      f"Made by `{command}`" + (f" at commit {commit}" if commit else "") +
      f" on x86_64 / {os.cpu_count()} cores: the generated cube (6 mm lift), "
      f"linear FEM `cg amg` to 1e-10, one thread per rank (`Models/Threads = 1`), serial and "
      f"`mpiexec -n 2` interleaved, {REPS} repetition(s), medians; times from softface's own phase "
      "report (the slowest rank's), whole process from its wall-time line. Every rank builds the "
      "whole scene (a serial step of issue 20's design so far); CSV: [scaling.csv](scaling.csv).", ""]
for t in table:
    md += [f"## {t['tets']} tetrahedra, {t['vertices']} vertices", "",
           f"CG iterations: 1 rank {t['it1']}, 2 ranks {t['it2']}; peak memory per rank "
           f"{t['mem1']:.0f} MB (1 rank), {t['mem2']:.0f} MB (2 ranks, the larger); the two "
           f"answers differ by {t['diff']:.1e} relative.", "",
           "| phase | 1 rank s | 2 ranks s | 1 / 2 |", "|---|---|---|---|"]
    for row in csv_rows:
        if row[0] == t["tets"]:
            md.append(f"| {row[1]} | {row[2]} | {row[3]} | {row[4]} |")
    md.append("")
md += ["![scaling](scaling.png)", ""]
with open(os.path.join(results, "scaling.md"), "w") as f:
    f.write("\n".join(md) + "\n")
print(f"scaling: wrote {os.path.join(results, 'scaling.md')}")
