"""Compare softface's nonlinear FEM with CalculiX NLGEOM: times side by side and the largest
nodal difference where both converged. Writes calculix_nonlinear.{md,csv}.

usage: /usr/bin/python3 report.py WORKDIR OUTDIR "command" CASE.json ...
"""
import csv
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "linear_fem"))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from report import cpu_name  # noqa: E402
import summary  # noqa: E402


def read_csv(path):
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    return {tuple(np.round(r[:3], 6)): r[3:] for r in data}


def main():
    work, outdir, command, cases = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    rows = []
    for case in cases:
        name = os.path.splitext(os.path.basename(case))[0]
        out = os.path.join(work, name)
        info_path = os.path.join(out, "case.json")
        if not os.path.exists(info_path):
            continue
        info = json.load(open(info_path))
        ccx_ok = info.get("ccx_nl_converged", False)
        for tag in ("cg_amg", "direct"):
            wall_file = os.path.join(out, f"softface_{tag}.wall")
            if not os.path.exists(wall_file):
                continue
            wall = float(open(wall_file).read().split()[-1])
            r = summary.row(os.path.join(out, f"softface_{tag}", "summary.csv"), "nonlinear fem")
            ok = r is not None and r["status"] == "ok"
            reason = (r["error"] if r else
                      f"no summary.csv (see softface_{tag}.log)")
            details = summary.details_text(r["details"]) if ok else ""
            diff = ""
            nodal = os.path.join(out, f"softface_{tag}", "displacements_nonlinear_fem.csv")
            ccx_csv = os.path.join(out, "calculix_nl_displacements.csv")
            if ok and ccx_ok and os.path.exists(nodal) and os.path.exists(ccx_csv):
                a, b = read_csv(nodal), read_csv(ccx_csv)
                common = set(a) & set(b)
                d = max(np.abs(a[k] - b[k]).max() for k in common)
                scale = max(np.abs(b[k]).max() for k in common)
                diff = f"{d / scale:.1e}"
            rows.append(dict(case=name, n_tets=info["n_tets"], n_vertices=info["n_nodes"],
                             calculix_s=info.get("ccx_nl_wall_s", ""),
                             calculix_converged=ccx_ok, softface_solver=tag.replace("_", " "),
                             softface_s=wall, softface_converged=ok,
                             speedup=f"{info.get('ccx_nl_wall_s', 0) / wall:.1f}" if wall else "",
                             max_relative_difference=diff, details=details or reason))
    with open(os.path.join(outdir, "calculix_nonlinear.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()) if rows else ["case"])
        w.writeheader()
        w.writerows(rows)
    md = ["# Nonlinear FEM: softface against CalculiX NLGEOM", ""]
    md.append("Whether softface's nonlinear FEM gives CalculiX's answer on the same meshes, and "
              "how long each takes.")
    md.append("")
    md.append(f"Reproduce: `{command.strip()}`.")
    md.append("")
    md.append(summary.measured_at(cpu_name()))
    md.append("")
    md.append("Same gmsh mesh, same conditions (outer faces fixed, inner 10 mm box moved), same "
              "material (St. Venant-Kirchhoff: CalculiX's *ELASTIC with NLGEOM; E = 3 kPa, "
              "Poisson's ratio 0.46). CalculiX 2.20 (Debian calculix-ccx): automatic "
              "incrementation from 10% of the load, residual and correction tolerances 1e-9, "
              "SPOOLES, 2 OpenMP threads. softface: Newton with line search and load-step "
              "cut-back, residual tolerance 1e-10, one thread. Times are whole-process wall "
              "times (input, solve, output) measured one after the other in one run; *speed-up* "
              "= CalculiX time / softface time. *max rel. diff.* = largest nodal difference over "
              "the largest CalculiX displacement, where both converged.")
    md.append("")
    md.append("| case | tets | CalculiX s | CalculiX converged | softface solver | softface s | "
              "softface converged | speed-up | max rel. diff. | softface details |")
    md.append("|---|---:|---:|---|---|---:|---|---:|---:|---|")
    for r in rows:
        md.append(f"| {r['case']} | {r['n_tets']} | {r['calculix_s']} | "
                  f"{'yes' if r['calculix_converged'] else 'no'} | {r['softface_solver']} | "
                  f"{r['softface_s']:.2f} | {'yes' if r['softface_converged'] else 'no'} | "
                  f"{r['speedup']} | {r['max_relative_difference']} | {r['details']} |")
    md.append("")
    md.append("## What the numbers show")
    md.append("")
    for r in rows:
        if r["calculix_converged"] and r["softface_converged"]:
            md.append(f"- {r['case']}, `{r['softface_solver']}`: the answers differ by "
                      f"{r['max_relative_difference']} of the largest displacement; CalculiX "
                      f"takes {r['speedup']} times softface's time.")
    md.append("")
    md.append("## Limits")
    md.append("")
    md.append("- One run per case; CalculiX on 2 threads, softface on one. No plot: four rows.")
    md.append("")
    with open(os.path.join(outdir, "calculix_nonlinear.md"), "w") as f:
        f.write("\n".join(md))


if __name__ == "__main__":
    main()
