#!/usr/bin/python3
"""The patients benchmark's skin part (the paper's 3.4-3.6): how far each
model's predicted skin is from the post-operative skin, and what the
volume/surface mapping costs.

Called by report.py: reads WORK_DIR/P<n>/skin.csv (and, for the pictures,
the predicted skins, skin_postoperative.ply and the distance CSVs); returns
the Markdown sections and writes RESULTS_DIR/patients_skin.csv,
patients_exact.csv and the PNGs patients_skin_percentiles.png (Fig. 9),
patients_exact.png, patients/P<n>_distance.png (Fig. 10) and
patients/P<n>_partners.png (Fig. 6).
"""
import csv
import os

import numpy as np
import matplotlib
matplotlib.use("Agg")  # headless
import matplotlib.pyplot as plt  # noqa: E402

import render  # noqa: E402  (benchmarks/patients/render.py)
import partners_figure  # noqa: E402
import summary  # noqa: E402  (benchmarks/summary.py, on report.py's path)

MODELS = ["linear fem", "mass tensor", "mass spring", "nonlinear fem"]
SEED_NAMES = {"linear fem": "FEM", "mass tensor": "MTM", "mass spring": "MSM",
              "nonlinear fem": "NFEM"}
# The paper's Table 3: 50/90/95 % percentiles (mm) averaged over its 10
# patients, real post-operative CTs.
SEED_TABLE3 = {"linear fem": (0.60, 1.51, 1.78), "mass tensor": (0.60, 1.48, 1.75),
               "mass spring": (0.64, 1.67, 1.95),
               "nonlinear fem": (0.63, 1.71, 2.05)}
# The paper's Table 4 (ms, Pentium 4): inverse distance A, B; shape functions
# A, B.
SEED_TABLE4 = {"P1": (187, 547, 3813, 1141), "P2": (63, 109, 859, 219),
               "P3": (78, 157, 1188, 344), "P4": (125, 281, 2203, 688),
               "P5": (141, 297, 2094, 625), "P6": (109, 281, 2172, 594),
               "P7": (172, 500, 3532, 1000), "P8": (140, 312, 3016, 625),
               "P9": (156, 454, 3156, 1047), "P10": (94, 109, 1094, 250)}
METHODS = {"shape functions": "sf", "inverse distance": "idw"}


def read_skin_csv(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def value(row, key):
    v = row.get(key, "") if row else ""
    return float(v) if v not in ("", None) else None


def fmt(x, digits=3):
    return "-" if x is None else f"{x:.{digits}g}"


def distance_picture(patient_dir, out_png, title):
    """Fig. 10: the MTM's predicted skin (shape functions) coloured by its
    signed closest-point distance to the post-operative skin, -3..3 mm, and
    (with exact correspondences) by its exact distance, 0..3 mm; front and
    right profile."""
    ply = os.path.join(patient_dir, "skin_mass_tensor_sf.ply")
    dist = os.path.join(patient_dir, "skin_mass_tensor_sf_distance.csv")
    if not (os.path.exists(ply) and os.path.exists(dist)):
        return False
    verts, tris = render.read_ply(ply)
    with open(dist) as f:
        header = f.readline().strip().split(",")
    table = np.loadtxt(dist, delimiter=",", skiprows=1, ndmin=2)
    maps = [(table[:, 0], "RdBu_r", (-3, 3),
             "signed closest-point distance (mm)")]
    if "exact distance mm" in header:
        maps.append((table[:, header.index("exact distance mm")], "magma_r",
                     (0, 3), "exact distance (mm)"))
    normals = render.vertex_normals(verts, tris)
    lo, hi = verts.min(0) - [2.0, 2.0, 2.0], verts.max(0) + 2.0
    mm_per_px = np.ptp(verts[:, 2]) / 500
    fig, axes = plt.subplots(len(maps), 2, figsize=(9, 5.6 * len(maps)),
                             dpi=100, squeeze=False)
    for row, (d, cmap_name, (vmin, vmax), label) in zip(axes, maps):
        cmap = plt.get_cmap(cmap_name)
        for ax, view in zip(row, render.VIEWS):
            right, toward = (np.array(a, float) for a in render.VIEWS[view])
            up = np.array([0.0, 0.0, 1.0])
            light = toward + 0.4 * up - 0.3 * right
            light /= np.linalg.norm(light)
            u, v = verts @ right, verts @ up
            umin = min(lo @ right, hi @ right)
            umax = max(lo @ right, hi @ right)
            width = int(np.ceil((umax - umin) / mm_per_px)) + 1
            height = int(np.ceil((hi[2] - lo[2]) / mm_per_px)) + 1
            xy = np.stack([(u - umin) / mm_per_px, (hi[2] - v) / mm_per_px],
                          1)
            depth = -(verts @ toward)
            shade, mask = render.rasterise(xy, depth, 0.35 + 0.65 *
                                           np.abs(normals @ light), tris,
                                           height, width)
            value_img, _ = render.rasterise(xy, depth,
                                            np.clip(d, vmin, vmax), tris,
                                            height, width)
            rgb = cmap((value_img - vmin) / (vmax - vmin))[..., :3] * \
                shade[..., None]
            rgb = np.where(mask[..., None], rgb, 1.0)
            ax.imshow(rgb, extent=(umin, umax, lo[2], hi[2]))
            ax.set_title(view)
            ax.set_axis_off()
        sm = plt.cm.ScalarMappable(cmap=cmap,
                                   norm=plt.Normalize(vmin, vmax))
        fig.colorbar(sm, ax=row, shrink=0.7, label=label)
    fig.suptitle(title)
    fig.savefig(out_png)
    plt.close(fig)
    return True


def truth_error(results):
    """The truth's own error at its 1x mesh (p90 of the skin's motion, mm),
    by Richardson extrapolation of truth_refinement.sh's 1x/2x/4x sequence:
    with changes c1 (1x to 2x) and c2 (2x to 4x) falling by r = c1 / c2 per
    doubling, the 1x truth is c1 r / (r - 1) from the limit. None without
    the sequence or if it does not converge (r <= 1)."""
    refinement = os.path.join(results, "truth_refinement.csv")
    if not os.path.exists(refinement):
        return None
    with open(refinement, newline="") as f:
        rows = list(csv.DictReader(f))
    if len(rows) < 2:
        return None
    c1, c2 = float(rows[-2]["p90 mm"]), float(rows[-1]["p90 mm"])
    r = c1 / c2 if c2 > 0 else 0.
    if r <= 1.:
        return None
    return dict(patient=rows[-1]["patient"], c1=c1, c2=c2, rate=r,
                error=c1 * r / (r - 1.))


def conclusions(data, row_of, results):
    """The paper's conclusions (3.6) held against these numbers: the 90 %
    percentile of each model against linear FEM's, patient by patient, in
    the paper's metric (distances to TPS-RPM correspondences) and the exact
    one. In the paper's metric a difference counts only where it exceeds both
    the truth's own error and that metric's error (how far its p90 lies from
    the exact one); in the exact metric, where it exceeds the truth's."""
    def p90(p, m, key):
        return value(row_of(p, m, "shape functions"), key)

    def against_fem(m, key):
        return [p90(p, m, key) - p90(p, "linear fem", key) for p in data
                if p90(p, m, key) is not None and
                p90(p, "linear fem", key) is not None]

    seed_key, exact_key = "correspondence p90 mm", "exact p90 mm"
    metric_errors = [abs(p90(p, m, seed_key) - p90(p, m, exact_key))
                     for p in data for m in MODELS
                     if p90(p, m, seed_key) is not None and
                     p90(p, m, exact_key) is not None]
    metric_error = max(metric_errors) if metric_errors else None
    truth = truth_error(results)
    truth_floor = truth["error"] if truth else None
    seed_floor = max([x for x in (metric_error, truth_floor)
                      if x is not None], default=None)

    md = ["### The paper's conclusions against these numbers\n",
          "The 90 % percentile of each model's distances minus linear FEM's, "
          "patient by patient (mm): mean, smallest, largest, and on how many "
          "patients the difference exceeds what can be resolved; in the "
          "paper's metric (TPS-RPM correspondences) and the exact one.\n"]
    resolution = "**What these truths and these metrics resolve.**"
    if truth:
        resolution += (
            f" Refining {truth['patient']}'s truth twice changed its skin by "
            f"{truth['c1']:.3g} and then {truth['c2']:.3g} mm (p90; "
            "[truth_refinement.md](truth_refinement.md)): "
            f"{truth['rate']:.2f}x less per doubling, so by Richardson "
            "extrapolation the truths used here (1x) are about "
            f"{truth['error']:.2g} mm (p90) from their converged answer.")
    if metric_errors:
        resolution += (f" The paper's metric's p90 lies up to "
                       f"{metric_error:.2g} mm from the exact p90 (median "
                       f"{np.median(metric_errors):.2g} mm over the patients "
                       "and models).")
    if seed_floor is not None:
        resolution += (f" A difference between two models counts only beyond "
                       f"{seed_floor:.2g} mm in the paper's metric")
        resolution += (f" and beyond {truth_floor:.2g} mm in the exact one."
                       if truth_floor is not None else ".")
    md.append(resolution + "\n")

    def verdict(d, claim, floor):
        """claim: 'equal', 'worse' or 'not better' than linear FEM."""
        if not d:
            return "no data"
        if floor is None:
            return "not judged (no estimate of the error)"
        worse = sum(x > floor for x in d)
        better = sum(x < -floor for x in d)
        counts = (f"worse beyond {floor:.2g} mm on {worse}, better on "
                  f"{better} of {len(d)}")
        if claim == "equal":
            return (counts + ": **not contradicted**, equality finer than "
                    f"{floor:.2g} mm cannot be confirmed"
                    if worse == better == 0 else
                    counts + ": **contradicted**")
        if claim == "worse":
            return counts + (": **confirmed**" if worse == len(d) else
                             ": **refuted**" if better == len(d) else
                             ": **not resolved**")
        return counts + (": **consistent**" if better == 0 else
                         ": **refuted** on those patients")

    def span(d):
        return (f"{np.mean(d):+.3f} mm (from {min(d):+.3f} to {max(d):+.3f})"
                if d else "-")

    for m, claim, text in (
            ("mass tensor", "equal", "The MTM is as accurate as the FEM"),
            ("mass spring", "worse", "The MSM is less accurate"),
            ("nonlinear fem", "not better",
             "The nonlinear FEM is no better than the linear FEM")):
        seed, exact = against_fem(m, seed_key), against_fem(m, exact_key)
        if not seed and not exact:
            continue
        md.append(f"- *{text}*. The paper's metric: {span(seed)}, "
                  f"{verdict(seed, claim, seed_floor)}. Exact: {span(exact)}, "
                  f"{verdict(exact, claim, truth_floor)}.")
    md.append("")
    if truth_floor is not None:
        md.append("The truth is a Neo-Hooke model, the nonlinear FEM's law; "
                  "a difference in the nonlinear FEM's favour says as much "
                  "about that as about the paper's real faces.\n")
    return md


def exact_against_closest(data, row_of, results):
    """Closest-point distances against exact correspondences (the truth moved
    the same skin points): per model, the percentiles of both and how much
    the closest point underestimates, averaged over the patients; per patient
    and model; and a plot."""
    keys = ("p50", "p90", "p95")

    def pair(p, m):
        r = row_of(p, m, "shape functions")
        closest = [value(r, f"{k} mm") for k in keys]
        exact = [value(r, f"exact {k} mm") for k in keys]
        if None in closest or None in exact:
            return None
        return np.array(closest), np.array(exact)

    def tps_rpm(p, m):
        r = row_of(p, m, "shape functions")
        v = [value(r, f"correspondence {k} mm") for k in keys]
        return None if None in v else np.array(v)

    pairs = {(p, m): pair(p, m) for p in data for m in MODELS}
    pairs = {k: v for k, v in pairs.items() if v is not None}
    if not pairs:
        return []
    md = ["### How right each metric is: closest points, TPS-RPM and exact "
          "correspondences\n",
          "The truth moved the same skin points as every model, so each "
          "predicted point's true post-operative position is known: the "
          "exact distance is |predicted - true|. A closest point on the "
          "post-operative skin is never farther than the true partner, so "
          "closest-point distances underestimate; the paper says so (3.5.1, "
          "after Chabanas et al. 2004) without a figure. Shape-function "
          "mapping; 50 / 90 / 95 % percentiles (mm), mean over the "
          "patients; *closest / exact*: the closest-point percentile as a "
          "fraction of the exact one; *TPS-RPM*: the distances to the "
          "corresponding points the paper's metric finds (every measured "
          "point matched to the post-operative surface by the TPS-RPM "
          "variant, doc/skin.md).\n",
          "| model | closest 50 / 90 / 95 % | exact 50 / 90 / 95 % | closest "
          "/ exact, 50 / 90 / 95 % | TPS-RPM 50 / 90 / 95 % | TPS-RPM / "
          "exact, 50 / 90 / 95 % | patients |",
          "|---|---|---|---|---|---|---|"]
    csv_rows = []
    for m in MODELS:
        these = [v for (p, mm), v in pairs.items() if mm == m]
        if not these:
            continue
        closest = np.mean([c for c, _ in these], axis=0)
        exact = np.mean([e for _, e in these], axis=0)
        ratio = np.mean([c / e for c, e in these], axis=0)
        rpm = [(tps_rpm(p, mm), v[1]) for (p, mm), v in pairs.items()
               if mm == m]
        rpm = [(t, e) for t, e in rpm if t is not None]
        rpm_cell = (" / ".join(f"{x:.2f}" for x in
                               np.mean([t for t, _ in rpm], axis=0))
                    if rpm else "-")
        rpm_ratio = (" / ".join(f"{x:.2f}" for x in
                                np.mean([t / e for t, e in rpm], axis=0))
                     if rpm else "-")
        md.append(f"| {SEED_NAMES[m]} ({m}) | "
                  + " / ".join(f"{x:.2f}" for x in closest) + " | "
                  + " / ".join(f"{x:.2f}" for x in exact) + " | "
                  + " / ".join(f"{x:.2f}" for x in ratio)
                  + f" | {rpm_cell} | {rpm_ratio} | {len(these)} |")
    md.append("")
    closest90 = [c[1] / e[1] for c, e in pairs.values()]
    rpm90 = [tps_rpm(p, m)[1] / v[1][1] for (p, m), v in pairs.items()
             if tps_rpm(p, m) is not None]
    md.append(f"At the 90 % percentile, over every patient and model, closest "
              f"points give {min(closest90):.2f} to {max(closest90):.2f} of "
              f"the exact distance (median {np.median(closest90):.2f}): the "
              "paper's claim that they underestimate, measured."
              + (f" The TPS-RPM variant gives {min(rpm90):.2f} to "
                 f"{max(rpm90):.2f} (median {np.median(rpm90):.2f})."
                 if rpm90 else "") + "\n")
    md.append("Each patient (90 % percentile, mm: closest / TPS-RPM / "
              "exact):\n")
    md.append("| patient | " + " | ".join(MODELS) + " |")
    md.append("|---|" + "---|" * len(MODELS))
    for p in data:
        cells = []
        for m in MODELS:
            v = pairs.get((p, m))
            t = tps_rpm(p, m)
            cells.append("-" if v is None else
                         f"{v[0][1]:.2f} / "
                         f"{'-' if t is None else f'{t[1]:.2f}'} / "
                         f"{v[1][1]:.2f}")
            if v is not None:
                csv_rows.append(dict(
                    patient=p, model=m,
                    **{f"closest {k} mm": f"{c:.6g}"
                       for k, c in zip(keys, v[0])},
                    **{f"TPS-RPM {k} mm": "" if t is None else f"{x:.6g}"
                       for k, x in zip(keys, t if t is not None else keys)},
                    **{f"exact {k} mm": f"{e:.6g}"
                       for k, e in zip(keys, v[1])}))
        md.append(f"| {p} | " + " | ".join(cells) + " |")
    md.append("")
    summary.write_rows(os.path.join(results, "patients_exact.csv"), csv_rows)
    md.append("CSV: [patients_exact.csv](patients_exact.csv).\n")

    fig, axes = plt.subplots(1, len(MODELS), figsize=(14, 3.8), sharey=True)
    for ax, m in zip(axes, MODELS):
        these = [(p, v) for (p, mm), v in pairs.items() if mm == m]
        for k, (p, (c, e)) in enumerate(these):
            ax.plot(e[1], c[1], "o", color="C0",
                    label="closest point" if k == 0 else None)
            t = tps_rpm(p, m)
            if t is not None:
                ax.plot(e[1], t[1], "s", color="C1", markerfacecolor="none",
                        label="TPS-RPM" if k == 0 else None)
            ax.annotate(p, (e[1], c[1]), fontsize=7)
        top = max([v[1][1] for _, v in these] + [1e-3]) * 1.1
        ax.plot([0, top], [0, top], "k--", linewidth=0.8,
                label="equal to exact")
        ax.set_title(SEED_NAMES[m])
        ax.set_xlabel("exact 90 % (mm)")
    axes[0].set_ylabel("90 % in the metric (mm)")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(results, "patients_exact.png"))
    plt.close(fig)
    md.append("![closest against exact](patients_exact.png)\n")
    return md


def partners_section(work, results, patients):
    """The paper's Fig. 6 for the first patient that has the files: six lip
    points of linear FEM's prediction and their three partners."""
    for p in patients:
        png = os.path.join("patients", f"{p}_partners.png")
        rows = partners_figure.partners_picture(
            os.path.join(work, p), os.path.join(results, png),
            f"{p}, linear FEM: a predicted point (black) and its partners on "
            "the post-operative skin")
        if rows is None:
            continue
        md = ["### Fig. 6: closest, corresponding and true partners\n",
              f"Six points of {p}'s lips as linear FEM predicts them (shape-"
              "function mapping; the front-most points of the midsagittal "
              "profile between z = -50 and -10 mm, evenly spaced in height), "
              "each with its closest point on the post-operative skin, its "
              "corresponding point by the TPS-RPM variant and its true "
              "post-operative position; drawn in the sagittal plane (the "
              "distances in the legends are in 3D; a partner off the plane "
              "is drawn where it projects). Lines: where the plane through "
              "the point cuts the post-operative skin (grey) and the "
              "predicted skin (light blue).\n",
              f"![partners]({png})\n",
              "| z (mm) | closest (mm) | TPS-RPM (mm) | exact (mm) |",
              "|---|---|---|---|"]
        for r in rows:
            md.append(f"| {r['z']:.1f} | {r['closest point']:.3f} | "
                      f"{r['TPS-RPM']:.3f} | {r['exact']:.3f} |")
        md.append("")
        return md
    return []


def sections(work, results, patients):
    """The Markdown lines of the skin sections; writes their CSV and PNGs."""
    data = {p: read_skin_csv(os.path.join(work, p, "skin.csv"))
            for p in patients}
    data = {p: rows for p, rows in data.items() if rows}
    if not data:
        return []
    # Patients run without a post-operative skin (run.sh --no-truth) or
    # whose truth failed have no distances.
    without = [p for p in patients
               if p not in data or not any(r.get("p50 mm") for r in data[p])]
    data = {p: rows for p, rows in data.items() if p not in without}

    def row_of(p, model, method):
        for r in data[p]:
            if r["model"] == model and r["mapping"] == method:
                return r
        return None

    csv_rows = []
    for p, rows in data.items():
        for r in rows:
            csv_rows.append(dict(patient=p, **r))
    summary.write_rows(os.path.join(results, "patients_skin.csv"), csv_rows)

    md = ["## The predicted skins against the post-operative skins\n",
          "Every model's displacement is mapped onto the dense skin surface "
          "of the CT (the paper's 3.4) and measured against the post-operative skin "
          "over the skin points within reach of the tetrahedral mesh (the "
          "simulated region of the face) in three ways: signed closest-point "
          "distances (negative: the prediction lies behind it), distances to "
          "the corresponding points of the paper's TPS-RPM variant, and exact "
          "distances to each point's true post-operative position. CSV: "
          "[patients_skin.csv](patients_skin.csv).\n",
          "**What these distances measure.** The phantoms have no "
          "post-operative CT. Their post-operative skin is made by a model "
          "richer than the ones it judges: `reference fem` (quadratic "
          "tetrahedra, compressible Neo-Hooke), skin, fat and muscle with "
          "their own moduli (15, 3, 6 kPa), driven by the planned bone "
          "motions plus a known rigid error per moved segment (0.7 mm and "
          "0.6 degrees in random directions; the paper's 3.2: the residual mismatch "
          "between plan and surgery), on the patient's own tetrahedral mesh "
          "(its truth scene `prm/patients/P<n>_truth.prm` meshes it again "
          "with the same parameters and Mesh_3 seed; the two mesh.vtu files are "
          "identical) with quadratic elements; whether that mesh is fine "
          "enough: `truth_refinement.md`. "
          "A distance to it is what the predicting models leave out (the "
          "planning error, tissue layers, large strain, discretisation), "
          "not the distance to a real patient; the paper's numbers come from "
          "real post-operative CTs.\n"]

    if without:
        md.append("**Patients without distances:** " + ", ".join(without) +
                  ". They ran without their post-operative truth "
                  "(`run.sh --no-truth`); their predictions are in "
                  "Table 2.\n")

    # Table 3 analogue, in the three metrics.
    md.append("### Table 3: percentiles averaged over the patients\n")
    md.append("Shape-function mapping; mean over the patients where the model "
              "ran, of the 50/90/95 % percentiles (mm) of the distance to the "
              "post-operative skin in three metrics: *closest*, |signed "
              "closest-point distance|; *TPS-RPM*, the distance to the "
              "corresponding point the paper's metric finds (3.5.1: every "
              "measured point matched to the post-operative surface by the "
              "TPS-RPM variant, doc/skin.md); *exact*, the distance to the "
              "point's true post-operative position (the truth moved the same "
              "skin points). The paper's figures are in its metric, on real "
              "patients.\n")
    md.append("| model | T50 paper | closest | TPS-RPM | exact | T90 paper | "
              "closest | TPS-RPM | exact | T95 paper | closest | TPS-RPM | "
              "exact | patients |")
    md.append("|---" * 14 + "|")
    for m in MODELS:
        keys = [f"{metric}{k} mm" for k in ("p50", "p90", "p95")
                for metric in ("", "correspondence ", "exact ")]
        vals = [[value(row_of(p, m, "shape functions"), k) for k in keys]
                for p in data]
        vals = [[np.nan if x is None else x for x in v] for v in vals
                if v[0] is not None]
        mean = np.nanmean(vals, axis=0) if vals else [np.nan] * 9
        s = SEED_TABLE3[m]
        cells = []
        for j in range(3):
            cells.append(f"{s[j]:.2f}")
            cells += [fmt(x) if np.isfinite(x) else "-"
                      for x in mean[3 * j:3 * j + 3]]
        md.append(f"| {SEED_NAMES[m]} ({m}) | " + " | ".join(cells) +
                  f" | {len(vals)} |")
    md.append("")
    md += conclusions(data, row_of, results)
    md += exact_against_closest(data, row_of, results)
    md += partners_section(work, results, list(data))

    # Fig. 9 analogue: per patient and model.
    md.append("### Fig. 9: each patient and model\n")
    md.append("50 / 90 / 95 % percentiles of |distance| and the mean signed "
              "distance (mm), shape-function mapping.\n")
    md.append("| patient | " + " | ".join(MODELS) + " |")
    md.append("|---|" + "---|" * len(MODELS))
    for p in data:
        cells = []
        for m in MODELS:
            r = row_of(p, m, "shape functions")
            if r is None or value(r, "p50 mm") is None:
                cells.append("failed")
            else:
                cells.append(f"{value(r, 'p50 mm'):.2f} / "
                             f"{value(r, 'p90 mm'):.2f} / "
                             f"{value(r, 'p95 mm'):.2f} "
                             f"({value(r, 'mean mm'):+.2f})")
        md.append(f"| {p} | " + " | ".join(cells) + " |")
    md.append("")
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2), sharey=False)
    x = np.arange(len(data))
    for ax, key, label in zip(axes, ("p50 mm", "p90 mm", "p95 mm"),
                              ("50 %", "90 %", "95 %")):
        for k, m in enumerate(MODELS):
            ys = [value(row_of(p, m, "shape functions"), key) for p in data]
            ys = [np.nan if y is None else y for y in ys]
            ax.bar(x + (k - 1.5) * 0.2, ys, 0.2, label=SEED_NAMES[m])
        ax.set_xticks(x)
        ax.set_xticklabels(list(data))
        ax.set_title(f"{label} percentile of |distance|")
        ax.set_ylabel("mm")
    axes[0].legend()
    fig.tight_layout()
    fig.savefig(os.path.join(results, "patients_skin_percentiles.png"))
    plt.close(fig)
    md.append("![percentiles per patient](patients_skin_percentiles.png)\n")

    # Fig. 10 analogue.
    md.append("### Fig. 10: distance maps (mass tensor model)\n")
    md.append("The predicted skin (shape-function mapping) coloured by its "
              "signed closest-point distance to the post-operative skin "
              "(above) and by the distance to each point's true "
              "post-operative position (below).\n")
    pictures = []
    for p in data:
        png = os.path.join("patients", f"{p}_distance.png")
        if distance_picture(os.path.join(work, p),
                            os.path.join(results, png),
                            f"{p}: mass tensor model"):
            pictures.append(f"![{p} distance map]({png})")
    md += pictures + [""]

    # Fig. 11 analogue.
    md.append("### Fig. 11: the two mappings (mass tensor model)\n")
    md.append("| patient | shape functions 50 / 90 / 95 % | inverse distance "
              "50 / 90 / 95 % | points the inverse distance mapping left "
              "unmoved |")
    md.append("|---|---|---|---|")
    diffs = []
    for p in data:
        sf = row_of(p, "mass tensor", "shape functions")
        idw = row_of(p, "mass tensor", "inverse distance")
        if sf is None or idw is None or value(sf, "p50 mm") is None:
            continue
        cell = [f"{value(r, 'p50 mm'):.2f} / {value(r, 'p90 mm'):.2f} / "
                f"{value(r, 'p95 mm'):.2f}" for r in (sf, idw)]
        diffs.append([value(idw, k) - value(sf, k)
                      for k in ("p50 mm", "p90 mm", "p95 mm")])
        md.append(f"| {p} | {cell[0]} | {cell[1]} | "
                  f"{idw.get('unmoved points', '-')} |")
    if diffs:
        d = np.mean(np.abs(diffs), axis=0)
        md.append("")
        md.append(f"Mean |inverse distance - shape functions| over the "
                  f"patients: {d[0]:.3f} / {d[1]:.3f} / {d[2]:.3f} mm "
                  f"(50 / 90 / 95 %); the paper found under 0.05 mm for all "
                  f"three.")
    md.append("")

    # Table 4 analogue.
    md.append("### Table 4: what the mapping costs\n")
    md.append("Step A (initialisation, once per scene) and step B (the "
              "update, on every prediction) of both mappings, ms; the paper's "
              "on a Pentium 4 (2007), ours on this machine, one core. Skin "
              "points: the dense skin of the CT (the paper's skins are not "
              "given).\n")
    md.append("| patient | skin points | mapped | IDW A paper | ours | IDW B "
              "paper | ours | SF A paper | ours | SF B paper | ours |")
    md.append("|---|---|---|---|---|---|---|---|---|---|---|")
    for p in data:
        sf = row_of(p, "mass tensor", "shape functions") or \
            row_of(p, "linear fem", "shape functions")
        idw = row_of(p, "mass tensor", "inverse distance") or \
            row_of(p, "linear fem", "inverse distance")
        if sf is None or idw is None:
            continue
        s = SEED_TABLE4[p]
        md.append(
            f"| {p} | {sf['skin points']} | {sf['mapped points']} | {s[0]} | "
            f"{1000 * value(idw, 'step A s'):.0f} | {s[1]} | "
            f"{1000 * value(idw, 'step B s'):.1f} | {s[2]} | "
            f"{1000 * value(sf, 'step A s'):.0f} | {s[3]} | "
            f"{1000 * value(sf, 'step B s'):.1f} |")
    md.append("")
    return md
