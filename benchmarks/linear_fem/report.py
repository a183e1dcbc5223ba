"""The linear FEM benchmark's cases (their summary.csv, read by column name) as
linear_fem.csv, a Markdown table and a PNG plot.

usage: /usr/bin/python3 report.py CASES.txt OUTDIR "command that ran it"
CASES.txt: one line per case, the solver and the case's output folder, tab-separated.
"""
import csv
import math
import os
import platform
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import summary  # noqa: E402

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def cpu_name():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def main():
    cases, outdir, command = sys.argv[1], sys.argv[2], sys.argv[3]
    columns = ["solver", "n_tets", "n_vertices", "n_free_dofs", "setup_s", "solve_s",
               "iterations", "max_displacement_mm", "peak_memory_mb", "phases"]
    rows = []
    for line in open(cases):
        solver, folder = line.rstrip("\n").split("\t")
        r = summary.row(os.path.join(folder, "summary.csv"), "linear fem")
        if r is None or r["status"] != "ok":
            print(f"{solver} in {folder}: no result" + (f" ({r['error']})" if r else ""))
            continue
        r["solver"] = solver
        r["peak_memory_mb"] = str(round(float(r["peak_memory_mb"])))
        r["phases"] = summary.phases_text(r["phases"])
        rows.append({k: r[k] for k in columns})
    with open(os.path.join(outdir, "linear_fem.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns)
        w.writeheader()
        w.writerows(rows)
    for r in rows:
        for k in ("n_tets", "n_vertices", "n_free_dofs", "iterations", "peak_memory_mb"):
            r[k] = int(r[k])
        for k in ("setup_s", "solve_s", "max_displacement_mm"):
            r[k] = float(r[k])
    solvers = sorted({r["solver"] for r in rows})

    def pick(solver, near):
        cands = [r for r in rows if r["solver"] == solver]
        return min(cands, key=lambda r: abs(math.log(r["n_tets"] / near))) if cands else None

    md = ["# Linear FEM on the paper's cube: solvers side by side", ""]
    md.append("What linear FEM's setup and solve cost with each solver (GMRES with Jacobi, CG with "
              "algebraic multigrid, sparse direct) from 35k to 511k tetrahedra, and whether CG + AMG "
              "meets the time and iteration targets at about 100k tetrahedra.")
    md.append("")
    md.append(f"Reproduce: `{command.strip()}`.")
    md.append("")
    md.append(summary.measured_at(cpu_name()) + " 1 MPI rank with 1 thread.")
    md.append("")
    md.append("The paper's benchmark (section 2.3.6): an 80 mm cube, border fixed, central 10 mm cube "
              "moved 6 mm up; P1 tetrahedra, Poisson's ratio 0.46, relative residual 1e-10 for the "
              "iterative solvers. One softface process per row. *setup* = sparsity + assembly + "
              "elimination of the join DoFs + preconditioner or factorisation; *solve* = right-hand "
              "side + solve for the planning (for `direct` this is the re-solve a new planning "
              "costs: the factorisation is reused). Peak memory is the process's VmHWM.")
    md.append("")
    md.append("| solver | tets | vertices | DoFs | free DoFs | setup s | solve s | total s | iterations | peak MB | max |u| mm |")
    md.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in sorted(rows, key=lambda r: (r["solver"], r["n_tets"])):
        md.append(f"| {r['solver']} | {r['n_tets']} | {r['n_vertices']} | {3 * r['n_vertices']} | "
                  f"{r['n_free_dofs']} | {r['setup_s']:.3f} | {r['solve_s']:.3f} | "
                  f"{r['setup_s'] + r['solve_s']:.3f} | {r['iterations']} | {r['peak_memory_mb']} | "
                  f"{r['max_displacement_mm']:.4f} |")
    md.append("")
    md.append("![time against tetrahedra](linear_fem.png)")
    md.append("")
    md.append("Phases (s) per run:")
    md.append("")
    for r in sorted(rows, key=lambda r: (r["solver"], r["n_tets"])):
        md.append(f"- {r['solver']}, {r['n_tets']} tets: {r['phases'].strip()}")
    md.append("")

    md.append("## What the numbers show: targets at about 100k tetrahedra")
    md.append("")
    amg = pick("cg amg", 1e5)
    direct = pick("direct", 1e5)
    if amg:
        t = amg["setup_s"] + amg["solve_s"]
        md.append(f"- `cg amg` setup + solve at {amg['n_tets']} tets: {t:.3f} s "
                  f"(target < 0.5 s: {'met' if t < 0.5 else 'not met'}).")
    if direct:
        md.append(f"- `direct` re-solve for a new planning at {direct['n_tets']} tets: "
                  f"{direct['solve_s']:.3f} s after a {direct['setup_s']:.2f} s setup "
                  f"(target < 0.05 s: {'met' if direct['solve_s'] < 0.05 else 'not met'}).")
    amg_rows = sorted((r for r in rows if r["solver"] == "cg amg"), key=lambda r: r["n_tets"])
    if len(amg_rows) >= 2:
        a, b = amg_rows[0], amg_rows[-1]
        growth = (b["iterations"] - a["iterations"]) / a["iterations"]
        md.append(f"- `cg amg` iterations from {a['n_tets']} to {b['n_tets']} tets: "
                  f"{a['iterations']} -> {b['iterations']} ({100 * growth:+.0f}%; target < +30%: "
                  f"{'met' if growth < 0.3 else 'not met'}).")
    md.append("- ML's settings, timed by hand on the gmsh cubes of `benchmarks/peers` (35k, 105k and 491k tetrahedra, 6 mm lift, `cg amg` to 1e-10, one thread, 3-4 interleaved runs each): a W-cycle with one sweep is 16-19% faster than the default (unsmoothed aggregation, threshold 0.02, V-cycle with 2 sweeps) on the 491k gmsh cube but inconclusive on the generated 511k cube, and no other setting is faster beyond the runs' spread; only the smoothed prolongator keeps the iterations nearly flat (21 -> 24 from 105k to 491k), at 1.2-1.3x the time; the W-cycles grow least among the cheap settings (28 -> 40 over 14 times the tetrahedra, against 28 -> 46). No setting makes the iterations flat and the solve cheaper at once.")
    md.append("")
    md.append("## Limits")
    md.append("")
    md.append("- One run per case on a shared machine: read differences of a few per cent as noise.")
    md.append("")
    with open(f"{outdir}/linear_fem.md", "w") as f:
        f.write("\n".join(md))

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for k, s in enumerate(solvers):
        rs = sorted((r for r in rows if r["solver"] == s), key=lambda r: r["n_tets"])
        n = [r["n_tets"] for r in rs]
        c = f"C{k}"
        ax1.loglog(n, [r["setup_s"] + r["solve_s"] for r in rs], "o-", color=c,
                   label=f"{s}: setup + solve")
        ax1.loglog(n, [r["solve_s"] for r in rs], "x--", color=c, label=f"{s}: solve (re-plan)")
        ax2.semilogx(n, [r["iterations"] for r in rs], "o-", color=c, label=s)
    ax1.set_xlabel("tetrahedra")
    ax1.set_ylabel("wall time [s]")
    ax1.set_title("Linear FEM, 6 mm cube")
    ax1.grid(True, which="both", alpha=0.3)
    ax1.legend(fontsize=7)
    ax2.set_xlabel("tetrahedra")
    ax2.set_ylabel("iterations")
    ax2.set_yscale("log")
    ax2.set_title("Solver iterations")
    ax2.grid(True, which="both", alpha=0.3)
    ax2.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(f"{outdir}/linear_fem.png", dpi=110)


if __name__ == "__main__":
    main()
