"""The paper's precision study of the mass tensor model (2.3.5, Table 1,
Fig. 1) on the phantom patients.

Called by report.py: reads WORK_DIR/P<n>/precision_<factor>/history.csv
(written by run.sh: the MTM alone, every free point in every sweep, to
gradients of 1e-5 mm per sweep; after each sweep the largest and mean
distance of a free point to the converged answer of the same equations and
the largest gradient); returns the Markdown section and writes
RESULTS_DIR/patients_precision.csv and patients_precision.png.
"""
import os

import numpy as np

import summary  # benchmarks/summary.py (report.py puts it on the path)

# Relaxation factors run.sh runs: the paper's plain update and the default.
FACTORS = [("1", "1 (paper)"), ("auto", "auto (1.8, default)")]
# The paper's Table 1 (five patients): P_min < 0.3 mm once G_max < 0.001
# mm per sweep, with P_mean about 0.039 mm there.
SEED_GRADIENT = 0.001
SEED_PRECISION = 0.3


def history(work, patient, factor):
    path = os.path.join(work, patient, f"precision_{factor}", "history.csv")
    if not os.path.exists(path):
        return None
    h = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return h if len(h) else None


def first(h, column, below):
    """The first row of history H whose COLUMN is below BELOW, or None."""
    rows = np.nonzero(h[:, column] < below)[0]
    return h[rows[0]] if len(rows) else None


def fmt(x, digits=3):
    return "-" if x is None else f"{x:.{digits}g}"


def sections(work, results, patients):
    found = {(p, f): history(work, p, f) for p in patients for f, _ in FACTORS}
    if not any(h is not None for h in found.values()):
        return []
    md = ["## Precision of the mass tensor model (the paper's Table 1, Fig. 1)\n",
          "The paper's precision study on each patient's mesh and planning: the mass "
          "tensor model alone, every free point updated in every sweep (Gauss-Seidel, "
          "no active set) until every gradient is below 1e-5 mm per sweep; after each "
          "sweep the largest (P_min, the paper's minimal precision) and mean (P_mean) "
          "distance of a free point to the converged answer of the same equations "
          "(sparse direct solve), and the largest gradient G_max (mean step of a "
          "point over its last 10 sweeps, mm per sweep). With the paper's plain "
          "update (relaxation factor 1) and softface's default over-relaxation. The "
          "paper (five real patients) found P_min < 0.3 mm once G_max < 0.001 mm per "
          "sweep, with P_mean about 0.039 mm there.\n",
          "| patient | relaxation | sweeps to P_min < 0.3 mm | P_mean there (mm) | "
          "G_max there (mm/sweep) | sweeps to G_max < 0.001 | P_min there (mm) | "
          "P_mean there (mm) | sweeps to G_max < 1e-5 |",
          "|---" * 9 + "|"]
    rows = []
    for p in patients:
        for f, label in FACTORS:
            h = found[(p, f)]
            if h is None:
                md.append(f"| {p} | {label} | failed or not run | | | | | | |")
                continue
            a = first(h, 1, SEED_PRECISION)
            b = first(h, 3, SEED_GRADIENT)
            row = dict(patient=p, relaxation_factor=f,
                       sweeps_to_precision=int(a[0]) if a is not None else "",
                       precision_mean_there_mm=a[2] if a is not None else "",
                       max_gradient_there=a[3] if a is not None else "",
                       sweeps_to_gradient=int(b[0]) if b is not None else "",
                       precision_min_at_gradient_mm=b[1] if b is not None else "",
                       precision_mean_at_gradient_mm=b[2] if b is not None else "",
                       sweeps=int(h[-1, 0]))
            rows.append(row)
            md.append(f"| {p} | {label} | {row['sweeps_to_precision'] or '-'} | "
                      f"{fmt(a[2] if a is not None else None)} | "
                      f"{fmt(a[3] if a is not None else None)} | "
                      f"{row['sweeps_to_gradient'] or '-'} | "
                      f"{fmt(b[1] if b is not None else None)} | "
                      f"{fmt(b[2] if b is not None else None)} | {row['sweeps']} |")
    md.append("")
    if rows:
        summary.write_rows(os.path.join(results, "patients_precision.csv"), rows)
        md.append("CSV: [patients_precision.csv](patients_precision.csv).\n")
        md += seed_claim(rows)
    shown = next((p for p in patients
                  if all(found[(p, f)] is not None for f, _ in FACTORS)), None)
    if shown is not None:
        figure(found, shown, os.path.join(results, "patients_precision.png"))
        md.append(f"Fig. 1 of the paper for {shown}: P_min, P_mean and G_max against "
                  "the sweeps, both relaxation factors.\n")
        md.append("![precision against sweeps](patients_precision.png)\n")
    return md


def seed_claim(rows):
    """Whether the paper's rule (G_max < 0.001 means P_min < 0.3 mm) held."""
    out = []
    for f, label in FACTORS:
        at = [r for r in rows if r["relaxation_factor"] == f
              and r["precision_min_at_gradient_mm"] != ""]
        if not at:
            continue
        worst = max(at, key=lambda r: r["precision_min_at_gradient_mm"])
        held = sum(r["precision_min_at_gradient_mm"] < SEED_PRECISION for r in at)
        means = [r["precision_mean_at_gradient_mm"] for r in at]
        out.append(f"- Relaxation factor {label}: when G_max first fell below 0.001 mm "
                   f"per sweep, P_min was below 0.3 mm on {held} of {len(at)} patients "
                   f"(largest {worst['precision_min_at_gradient_mm']:.3g} mm, "
                   f"{worst['patient']}); P_mean there {min(means):.3g} to "
                   f"{max(means):.3g} mm (the paper: about 0.039).")
    out.append("")
    return out


def figure(found, patient, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    for ax, (f, label) in zip(axes, FACTORS):
        h = found[(patient, f)]
        ax.semilogy(h[:, 0], h[:, 1], label="P_min (largest distance, mm)")
        ax.semilogy(h[:, 0], h[:, 2], label="P_mean (mean distance, mm)")
        ax.semilogy(h[:, 0], h[:, 3], label="G_max (mm per sweep)")
        ax.axhline(SEED_PRECISION, color="grey", lw=0.8, ls="--")
        ax.axhline(SEED_GRADIENT, color="grey", lw=0.8, ls=":")
        ax.set_xlabel("sweep")
        ax.set_title(f"{patient}, relaxation factor {label}")
        ax.grid(True, which="both", lw=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)
