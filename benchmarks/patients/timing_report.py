"""Why the paper's timing claims do or do not hold on the phantom patients:
its Fig. 2 (the mass tensor model's gain over linear FEM about constant with
the mesh's size, the mass spring model's time near quadratic in it) and its
Table 4 (inverse distance mapping much faster than shape functions), taken
apart into what each solve repeats (CG iterations, sweeps, point updates and
their cost) and what step A of each mapping spends its time on.

Called by report.py: reads WORK_DIR/P<n>/summary.csv and skin.csv; returns
the Markdown section and writes RESULTS_DIR/patients_timing.csv and
patients_timing.png.
"""
import csv
import os

import numpy as np

import summary  # benchmarks/summary.py


def fit_exponent(x, y):
    """k of y ~ x^k by least squares in log-log, or None."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    keep = (x > 0) & (y > 0)
    if keep.sum() < 3:
        return None
    return float(np.polyfit(np.log(x[keep]), np.log(y[keep]), 1)[0])


def number(text):
    """The leading number of a details value ('25.1 MB' -> 25.1)."""
    try:
        return float(str(text).split()[0])
    except (ValueError, IndexError):
        return None


def solver_rows(work, patients):
    rows = []
    for p in patients:
        path = os.path.join(work, p, "summary.csv")
        runs = {r["model"]: r for r in summary.read(path)
                if r.get("status") == "ok"}
        lin, mtm, msm = (runs.get(m) for m in ("linear fem", "mass tensor",
                                                "mass spring"))
        if lin is None:
            continue
        row = dict(patient=p, tets=int(lin["n_tets"]),
                   free_dofs=int(lin["n_free_dofs"]),
                   fem_s=float(lin["setup_s"]) + float(lin["solve_s"]),
                   fem_cg_iterations=int(lin["iterations"]))
        for key, run in (("mtm", mtm), ("msm", msm)):
            if run is None:
                continue
            details = summary.pairs(run["details"])
            updates = number(details.get("point updates"))
            row[f"{key}_s"] = float(run["setup_s"]) + float(run["solve_s"])
            row[f"{key}_sweeps"] = int(run["iterations"])
            if updates:
                row[f"{key}_updates_per_point"] = updates / (row["free_dofs"] / 3)
                row[f"{key}_ns_per_update"] = (float(run["solve_s"]) * 1e9 /
                                               updates)
        rows.append(row)
    return rows


def mapping_rows(work, patients):
    rows = []
    for p in patients:
        path = os.path.join(work, p, "skin.csv")
        if not os.path.exists(path):
            continue
        with open(path, newline="") as f:
            skin = [r for r in csv.DictReader(f) if r["model"] == "mass tensor"]
        for r in skin:
            if not r.get("step A parts"):
                continue
            rows.append(dict(patient=p, mapping=r["mapping"],
                             skin_points=int(r["skin points"]),
                             mapped_points=int(r["mapped points"]),
                             step_a_s=float(r["step A s"]),
                             step_b_s=float(r["step B s"]),
                             weights_per_point=float(r["weights per point"]),
                             **{f"A: {n}": float(v) for n, v in
                                summary.pairs(r["step A parts"]).items()}))
    return rows


def fmt(x, digits=3):
    return "-" if x is None else f"{x:.{digits}g}"


def sections(work, results, patients):
    solvers = solver_rows(work, patients)
    mappings = mapping_rows(work, patients)
    if not solvers:
        return []
    md = ["## The paper's timing claims, taken apart\n",
          "The paper's Fig. 2 has the mass tensor model's gain over linear FEM "
          "about constant with the mesh's size and the mass spring model's "
          "time near quadratic in it; its Table 4 has the inverse distance "
          "mapping about 85 % faster than shape functions. What each time is "
          "made of, on the patients of this run (as in Table 2: "
          "setup + solve, s): linear FEM's CG iterations (AMG-preconditioned), "
          "the point models' sweeps and point updates per free point, and "
          "the cost of an update (solve time / updates).\n",
          "| patient | tets | FEM s | CG iterations | MTM s | MTM / FEM | "
          "MTM sweeps | updates per point | ns per update | MSM s | MSM / FEM "
          "| MSM sweeps | updates per point | ns per update |",
          "|---" * 14 + "|"]
    for r in solvers:
        def g(key, digits=3):
            return fmt(r.get(key), digits)
        mtm_ratio = r["mtm_s"] / r["fem_s"] if "mtm_s" in r else None
        msm_ratio = r["msm_s"] / r["fem_s"] if "msm_s" in r else None
        md.append(f"| {r['patient']} | {r['tets']} | {g('fem_s')} | "
                  f"{r['fem_cg_iterations']} | {g('mtm_s')} | "
                  f"{fmt(mtm_ratio, 2)} | {r.get('mtm_sweeps', '-')} | "
                  f"{g('mtm_updates_per_point')} | {g('mtm_ns_per_update')} | "
                  f"{g('msm_s')} | {fmt(msm_ratio, 2)} | "
                  f"{r.get('msm_sweeps', '-')} | {g('msm_updates_per_point')} | "
                  f"{g('msm_ns_per_update')} |")
    md.append("")
    tets = [r["tets"] for r in solvers]
    exponents = []
    for key, label in (("fem_s", "linear FEM time"),
                       ("fem_cg_iterations", "CG iterations"),
                       ("mtm_s", "MTM time"),
                       ("mtm_updates_per_point", "MTM updates per point"),
                       ("mtm_ns_per_update", "MTM ns per update"),
                       ("msm_s", "MSM time"),
                       ("msm_updates_per_point", "MSM updates per point"),
                       ("msm_ns_per_update", "MSM ns per update")):
        k = fit_exponent([r["tets"] for r in solvers if key in r],
                         [r[key] for r in solvers if key in r])
        if k is not None:
            exponents.append(f"{label} ~ tets^{k:.2f}")
    ratio = fit_exponent([r["tets"] for r in solvers if "mtm_s" in r],
                         [r["mtm_s"] / r["fem_s"] for r in solvers
                          if "mtm_s" in r])
    trend = ("" if ratio is None else
             f" The MTM / FEM time ratio ~ tets^{ratio:.2f}: " +
             ("about constant, as the paper found." if abs(ratio) < 0.1 else
              "it grows with the mesh, so the mass tensor model's gain over "
              "linear FEM shrinks (the paper: about constant)." if ratio > 0
              else "it falls with the mesh, so the mass tensor model's gain "
              "over linear FEM grows (the paper: about constant)."))
    md.append("Fitted over the patients (y ~ tets^k; the patients differ in "
              "their planning too, so these mix size with motion; "
              "cube_models.md varies the size alone): " +
              "; ".join(exponents) + "." + trend + " A point model's time is "
              "its updates per point times the points times the cost of an "
              "update; linear FEM's is its CG iterations times the cost of "
              f"one (here {len(tets)} patients of {min(tets)} to {max(tets)} "
              "tetrahedra).\n")
    keys = sorted({k for r in solvers for k in r},
                  key=lambda k: list(solvers[0]).index(k)
                  if k in solvers[0] else 99)
    summary.write_rows(os.path.join(results, "patients_timing.csv"), solvers,
                       keys)
    md.append("CSV: [patients_timing.csv](patients_timing.csv).\n")
    figure(solvers, os.path.join(results, "patients_timing.png"))
    md.append("![what the solves repeat against size](patients_timing.png)\n")

    if mappings:
        md += mapping_section(mappings, results)
    return md


def mapping_section(rows, results):
    md = ["### Step A of the two mappings, taken apart\n",
          "The paper's Table 4 times step A (initialisation) and step B "
          "(update) of each mapping as one figure each. softface's step A, "
          "part by part (s; mass tensor model's run, which maps the same "
          "skin as every model), with the mean number of weights per mapped "
          "point, which is what step B sums. Shape functions: `trees` (R-trees "
          "of the tetrahedra's boxes and of the mesh's skin triangles), "
          "`containing tetrahedra` (each skin point's, from the R-tree), "
          "`outside points` (a closest-point query on the mesh's skin for "
          "each point in no tetrahedron: whether it is within reach, and the "
          "tetrahedron it projects onto). Inverse distances: `skin tree`, "
          "`matching` (each skin vertex of the mesh to its closest skin "
          "point), `edges`, `reach` (a closest-point query on the mesh's "
          "skin for each unmatched point), `rings` (the connectivity rings "
          "of each point within reach). The skin is the whole head's; the "
          "mesh covers the face, so most skin points are out of reach and "
          "cost one closest-point query each in either method.\n"]
    for method in ("shape functions", "inverse distance"):
        these = [r for r in rows if r["mapping"] == method]
        if not these:
            continue
        parts = [k for k in these[0] if k.startswith("A: ")]
        md.append(f"**{method}**\n")
        md.append("| patient | skin points | step A s | " +
                  " | ".join(p[3:] + " s" for p in parts) +
                  " | weights per point | step B ms |")
        md.append("|---" * (5 + len(parts)) + "|")
        for r in these:
            md.append(f"| {r['patient']} | {r['skin_points']} | "
                      f"{r['step_a_s']:.3g} | " +
                      " | ".join(f"{r.get(p, 0):.3g}" for p in parts) +
                      f" | {r['weights_per_point']:.3g} | "
                      f"{1000 * r['step_b_s']:.3g} |")
        md.append("")
    sf = {r["patient"]: r for r in rows if r["mapping"] == "shape functions"}
    idw = {r["patient"]: r for r in rows if r["mapping"] == "inverse distance"}
    both = [p for p in sf if p in idw]
    if both:
        import skin_report
        seed = [skin_report.SEED_TABLE4[p] for p in both]
        seed_a = np.mean([s[0] / s[2] for s in seed])
        seed_b = np.mean([s[1] / s[3] for s in seed])
        a = np.mean([idw[p]["step_a_s"] / sf[p]["step_a_s"] for p in both])
        b = np.mean([idw[p]["step_b_s"] / sf[p]["step_b_s"] for p in both])

        def largest(these):
            shares = {}
            for r in these:
                for k in r:
                    if k.startswith("A: "):
                        shares.setdefault(k[3:], []).append(
                            r[k] / r["step_a_s"])
            name = max(shares, key=lambda k: np.mean(shares[k]))
            return name, 100 * np.mean(shares[name])

        sf_part, sf_share = largest([sf[p] for p in both])
        idw_part, idw_share = largest([idw[p] for p in both])
        md.append(f"Inverse distance against shape functions, mean over "
                  f"{len(both)} patients: step A {a:.2f}x, step B {b:.2f}x "
                  f"the time (the paper's Table 4: {seed_a:.2f}x and "
                  f"{seed_b:.2f}x on the same patients). Most of step A is "
                  f"'{sf_part}' for shape functions ({sf_share:.0f} %) and "
                  f"'{idw_part}' for inverse distances ({idw_share:.0f} %); "
                  "weights per mapped point: "
                  f"{np.mean([sf[p]['weights_per_point'] for p in both]):.2g}"
                  " and "
                  f"{np.mean([idw[p]['weights_per_point'] for p in both]):.2g}"
                  ".\n")
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    summary.write_rows(os.path.join(results, "patients_mapping_parts.csv"),
                       rows, keys)
    md.append("CSV: [patients_mapping_parts.csv]"
              "(patients_mapping_parts.csv).\n")
    return md


def figure(rows, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    tets = np.array([r["tets"] for r in rows])
    for key, label in (("fem_s", "linear FEM"), ("mtm_s", "MTM"),
                       ("msm_s", "MSM")):
        y = [r.get(key, np.nan) for r in rows]
        axes[0].loglog(tets, y, "o", label=label)
    axes[0].set_title("setup + solve (s)")
    for key, label in (("fem_cg_iterations", "CG iterations (FEM)"),
                       ("mtm_updates_per_point", "updates per point (MTM)"),
                       ("msm_updates_per_point", "updates per point (MSM)")):
        y = [r.get(key, np.nan) for r in rows]
        axes[1].loglog(tets, y, "o", label=label)
    axes[1].set_title("what each solve repeats")
    for key, label in (("mtm_ns_per_update", "MTM"),
                       ("msm_ns_per_update", "MSM")):
        y = [r.get(key, np.nan) for r in rows]
        axes[2].semilogx(tets, y, "o", label=label)
    axes[2].set_title("ns per point update")
    for ax in axes:
        ax.set_xlabel("tetrahedra")
        ax.legend(fontsize=8)
        ax.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)
