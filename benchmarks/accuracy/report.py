"""Tables and plots of the accuracy benchmark (used by run_all.py)."""

import csv
import math
import os
import platform

import numpy as np

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = {"linear fem": "tab:blue", "nonlinear fem": "tab:red",
           "mass tensor": "tab:green", "mass spring": "tab:orange"}


def machine():
    cpu = ""
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{cpu}, {os.cpu_count()} cores, {platform.system()} {platform.release()}"


def fmt(x, digits=3):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return f"{x:.{digits}g}"


def pareto(points):
    """Indices of the runs no other run beats in both time and error."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], math.inf
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def p90_distance(a, b):
    return float(np.percentile(np.linalg.norm(a - b, axis=1), 90))


def model_error_section(key, refs, linear_p2_rows, scene_rows, tightest):
    """Linear elasticity on the reference's discretisation against the
    reference, and the sweep's error split into model and discretisation."""
    lin = [r for r in linear_p2_rows if r["scene"] == key]
    if not lin:
        return []
    md = ["### Model error of linear elasticity", "",
          "Linear FEM's equations (`Material law = linear` of the nonlinear FEM model) solved "
          "on the reference's meshes with quadratic tetrahedra, against the reference on the "
          "same mesh: what linear FEM, and the MTM (the same equations), would still miss with "
          "no discretisation error.", "",
          "| mesh tets | setup s | solve s | status | median | 90% | 95% | max |",
          "|---:|---:|---:|---|---:|---:|---:|---:|"]
    by_level = {r["level"]: r for r in refs if r.get("values") is not None}
    for r in lin:
        stats = ""
        if r["values"] is not None and r["level"] in by_level:
            d = np.linalg.norm(r["values"] - by_level[r["level"]]["values"], axis=1)
            stats = (f"{fmt(float(np.median(d)))} | {fmt(float(np.percentile(d, 90)))} | "
                     f"{fmt(float(np.percentile(d, 95)))} | {fmt(float(d.max()))}")
        else:
            stats = " | | | "
        md.append(f"| {r['n_tets'] or r['level']} | {fmt(r['setup_s'])} | {fmt(r['solve_s'])} | "
                  f"{r['status']}{': ' + r['message'] if r['message'] else ''} | {stats} |")
    good = [r for r in lin if r["values"] is not None]
    if len(good) >= 2:
        md += ["", f"Change of the quadratic linear solution from {good[-2]['n_tets']} to "
               f"{good[-1]['n_tets']} tets: {fmt(p90_distance(good[-2]['values'], good[-1]['values']))}"
               " mm (90th percentile)."]
    if not good:
        return md + [""]
    limit = good[-1]["values"]
    md += ["", "Where the sweep's error comes from (90th percentile, mm, each model's tightest "
           "setting): the distance of P1 linear FEM and of the MTM to the quadratic linear "
           "solution is their discretisation (and, for the MTM, stopping) error; nonlinear "
           "FEM's error against the reference is its discretisation error. Model and "
           "discretisation error are vectors at each point: they add or partly cancel.", "",
           "| tets | linear FEM error | linear FEM to linear P2 | MTM error | MTM to linear P2 "
           "| nonlinear FEM error |", "|---:|---:|---:|---:|---:|---:|"]
    meshes = sorted({int(r["n_tets"]) for r in scene_rows})
    for n in meshes:
        cells = []
        for model, with_distance in (("linear fem", True), ("mass tensor", True),
                                     ("nonlinear fem", False)):
            run = [r for r in scene_rows if r["model"] == model and int(r["n_tets"]) == n
                   and r["setting"] == tightest[model] and r.get("values") is not None]
            if not run:
                cells += ["", ""] if with_distance else [""]
                continue
            cells.append(fmt(run[0]["err_p90"]))
            if with_distance:
                cells.append(fmt(p90_distance(run[0]["values"], limit)))
        md.append(f"| {n} | " + " | ".join(cells) + " |")
    md.append("")
    return md


def scene_sections(path):
    """The scene sections ('## title (`key`)' up to the next one or the plot)
    of an earlier report, by scene key."""
    sections, key = {}, None
    if not os.path.exists(path):
        return sections
    for line in open(path).read().split("\n"):
        if line.startswith("## ") and line.endswith("`)"):
            key = line[line.rindex("(`") + 2:-2]
            sections[key] = []
        elif line.startswith("![") or line.startswith("## "):
            key = None
        if key is not None:
            sections[key].append(line)
    return sections


def kept_prose(path, heading="## What the numbers show"):
    """The hand-written sections of an earlier report ('## What the numbers
    show' and '## Limits', up to the next '## ' heading): what the figures
    mean is written by hand and kept when the figures are re-made; re-read
    it against the new figures."""
    if not os.path.exists(path):
        return []
    kept, inside = [], False
    for line in open(path).read().split("\n"):
        if line.startswith("## "):
            inside = line in (heading, "## Limits")
        if inside:
            kept.append(line)
    return kept


def csv_rows(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def write_accuracy(results, command, scenes, rows, reference_rows, linear_p2_rows, tightest,
                   thresholds, models, run_lines, keep=()):
    """The report of SCENES, in their order. RUN_LINES holds each run scene's line
    on how it ran; the scenes whose keys are in KEEP were not run: they keep
    their section, rows and plot from the report already in RESULTS (or are
    left out if it has none)."""
    md_path = os.path.join(results, "accuracy_vs_time.md")
    csv_path = os.path.join(results, "accuracy_vs_time.csv")
    kept_sections = scene_sections(md_path)
    kept_rows = csv_rows(csv_path)
    all_scenes = [s for s in scenes if s["key"] not in keep or s["key"] in kept_sections]

    fields = ["scene", "model", "setting", "n_tets", "n_vertices", "setup_s", "solve_s",
              "total_s", "iterations", "err_median", "err_p90", "err_p95", "err_max",
              "status", "message"]
    plotted = []
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        for scene in all_scenes:
            key = scene["key"]
            if key in keep:
                mine = [r for r in kept_rows if r["scene"] == key]
                for r in mine:
                    if r["model"] in models and number(r["err_p90"]) is not None:
                        plotted.append(dict(scene=key, model=r["model"],
                                            total_s=number(r["total_s"]),
                                            err_p90=number(r["err_p90"])))
            else:
                mine = [r for r in reference_rows + linear_p2_rows + rows if r["scene"] == key]
                plotted += [r for r in rows if r["scene"] == key and "err_p90" in r]
            for r in mine:
                w.writerow(r)

    prose = kept_prose(md_path)
    md = ["# What accuracy costs in time", "",
          "Which model and setting reach a given accuracy (90th percentile of the error "
          "against a converged quadratic Neo-Hooke reference) in the least time, on the "
          "paper's cube with a 6 mm lift, a 16.7 mm lift and a 30 degree rotation.", "",
          f"Reproduce: `{command.strip()}` (about 2.4 hours of one core; `--jobs 2` runs two "
          "cases at once, `--scenes` a subset).", "",
          f"Measured on {machine()}; each scene's section names the commit its runs were "
          "built from.", "",
          "One softface process per case, on one thread (`Models/Threads = 1`; OpenBLAS "
          "and ML single-threaded). Times are softface's own setup and solve wall times of "
          "the model (mesh generation and file output excluded). Each scene's section says "
          "how it was run: the scenes can be run apart (`--scenes`), and with "
          "`--jobs 2` two cases run at once and share the machine's memory bandwidth.", "",
          "Errors are |u - u_ref| in mm at the free vertices of the coarsest mesh "
          "(every run evaluated there by its shape functions), against the reference: "
          "nonlinear FEM (compressible Neo-Hooke, the same Young's modulus and Poisson's "
          "ratio) with quadratic tetrahedra on the finest of its meshes, which are cube "
          "meshes graded towards the inner cube's faces (`Scene/Cube/Grading`: the spacing "
          "grows linearly from the inner cube's face planes to the outer faces by the factor "
          "given) and split mirror-symmetrically (`Scene/Cube/Mirror-symmetric split`), so "
          "that the symmetric plannings get symmetric answers. The sweep runs on softface's "
          "default uniform cube meshes (every box split along (1, 1, 1)). The linear models (linear "
          "FEM, MTM) therefore carry their model error as well as their discretisation "
          "error; the mass spring model is a different material altogether.", "",
          "Every run is in `accuracy_vs_time.csv`.", ""]

    for scene in all_scenes:
        key = scene["key"]
        if key in keep:
            md += kept_sections[key]
            continue
        md += [f"## {scene['title']} (`{key}`)", "", run_lines[key], ""]
        refs = [r for r in reference_rows if r["scene"] == key]
        scene_rows = [r for r in rows if r["scene"] == key and "err_p90" in r]
        md += ["### Reference", "",
               "| mesh tets | vertices | setting | DoFs | setup s | solve s | status |",
               "|---:|---:|---|---:|---:|---:|---|"]
        for r in refs:
            dofs = r.get("n_dofs", "")
            md.append(f"| {r['n_tets']} | {r['n_vertices']} | {r['setting']} | {dofs} | "
                      f"{fmt(r['setup_s'])} | "
                      f"{fmt(r['solve_s'])} | {r['status']}"
                      f"{' (used)' if r.get('used') else ''}"
                      f"{': ' + r['message'] if r['message'] else ''} |")
        good = [r for r in refs if r.get("values") is not None]
        if len(good) >= 2:
            md += ["", "Change of the reference between successive levels at the evaluation "
                   "points (mm):", "", "| from | to | median | 90% | 95% | max |",
                   "|---:|---:|---:|---:|---:|---:|"]
            for a, b in zip(good[:-1], good[1:]):
                d = np.linalg.norm(a["values"] - b["values"], axis=1)
                md.append(f"| {a['n_tets']} | {b['n_tets']} | {fmt(float(np.median(d)))} | "
                          f"{fmt(float(np.percentile(d, 90)))} | "
                          f"{fmt(float(np.percentile(d, 95)))} | {fmt(float(d.max()))} |")
            d = np.linalg.norm(good[-2]["values"] - good[-1]["values"], axis=1)
            change90 = float(np.percentile(d, 90))
            if scene_rows:
                smallest = min(r["err_p90"] for r in scene_rows)
                verdict = ("meets" if change90 <= 0.1 * smallest else "does NOT meet")
                md += ["", f"Convergence check (90th percentile): the last change, "
                       f"{fmt(change90)} mm, against a tenth of the smallest 90% error "
                       f"reported below ({fmt(smallest)} mm / 10 = {fmt(smallest / 10)} mm): "
                       f"the reference {verdict} the criterion. "
                       "Errors below about ten times that change are not resolved by this "
                       "reference."]
        md.append("")
        md += model_error_section(key, refs, linear_p2_rows, scene_rows, tightest)

        # Pareto table: cheapest setting per model and accuracy.
        md += ["### Cheapest setting reaching each accuracy (90th percentile)", "",
               "| model | " + " | ".join(f"<= {t} mm" for t in thresholds) + " |",
               "|---|" + "---|" * len(thresholds)]
        for model in models:
            cells = []
            runs = [r for r in scene_rows if r["model"] == model]
            for t in thresholds:
                ok = [r for r in runs if r["err_p90"] <= t]
                if not ok:
                    cells.append("not reached")
                    continue
                best = min(ok, key=lambda r: r["total_s"])
                cells.append(f"{fmt(best['total_s'])} s ({best['n_tets']} tets, "
                             f"{best['setting']}; p90 {fmt(best['err_p90'])})")
            md.append(f"| {model} | " + " | ".join(cells) + " |")
        failed = [r for r in rows if r["scene"] == key and r["status"] != "ok"]
        if failed:
            md += ["", "Runs that failed (left out of the tables):", ""]
            for r in failed:
                md.append(f"- {r['model']}, {r['n_tets'] or '?'} tets, {r['setting']}: "
                          f"{r['message']}")
        md += ["", "### Best error per model and mesh (any setting)", "",
               "| model | tets | setting | setup s | solve s | median | 90% | 95% | max |",
               "|---|---:|---|---:|---:|---:|---:|---:|---:|"]
        for model in models:
            by_mesh = {}
            for r in scene_rows:
                if r["model"] == model:
                    n = int(r["n_tets"])
                    if n not in by_mesh or r["err_p90"] < by_mesh[n]["err_p90"]:
                        by_mesh[n] = r
            for n in sorted(by_mesh):
                r = by_mesh[n]
                md.append(f"| {model} | {n} | {r['setting']} | {fmt(r['setup_s'])} | "
                          f"{fmt(r['solve_s'])} | {fmt(r['err_median'])} | "
                          f"{fmt(r['err_p90'])} | {fmt(r['err_p95'])} | {fmt(r['err_max'])} |")
        md.append("")

    md += ["![error against time](accuracy_vs_time.png)", "",
           "Plot: 90th-percentile error against setup + solve time, every run a marker, "
           "each model's Pareto front a line; dashed lines at the table's accuracies.", ""]
    md += prose
    with open(md_path, "w") as f:
        f.write("\n".join(md))

    fig, axes = plt.subplots(1, len(all_scenes), figsize=(5.5 * len(all_scenes), 4.6),
                             squeeze=False)
    for ax, scene in zip(axes[0], all_scenes):
        scene_rows = [r for r in plotted if r["scene"] == scene["key"]]
        for model in models:
            runs = [r for r in scene_rows if r["model"] == model]
            if not runs:
                continue
            pts = [(r["total_s"], r["err_p90"]) for r in runs]
            ax.scatter(*zip(*pts), s=14, alpha=0.45, color=COLOURS[model])
            front = [pts[i] for i in pareto(pts)]
            ax.plot(*zip(*front), "-o", ms=4, color=COLOURS[model], label=model)
        for t in thresholds:
            ax.axhline(t, color="grey", ls="--", lw=0.7)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("setup + solve time (s)")
        ax.set_ylabel("error, 90th percentile (mm)")
        ax.set_title(scene["title"])
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(results, "accuracy_vs_time.png"), dpi=110)


def write_precision(results, command, scenes, precision, keep=()):
    """The MTM precision study of SCENES, in their order: PRECISION holds the
    run ones; those whose keys are in KEEP keep their row and history from
    the report already in RESULTS (or are left out if it has none)."""
    md_path = os.path.join(results, "mtm_precision.md")
    csv_path = os.path.join(results, "mtm_precision.csv")
    old_md = open(md_path).read().split("\n") if os.path.exists(md_path) else []
    old_rows = csv_rows(csv_path)
    kept = {}
    for s in scenes:
        line = next((x for x in old_md if x.startswith(f"| {s['title']} |")), None)
        history = [[float(r[c]) for c in ("sweep", "precision_min_mm", "precision_mean_mm",
                                           "max_gradient_mm_per_sweep")]
                   for r in old_rows if r["scene"] == s["key"]]
        if s["key"] in keep and line is not None:
            kept[s["key"]] = dict(scene=s, line=line, ok=bool(history),
                                  tets=next((r["n_tets_target"] for r in old_rows
                                             if r["scene"] == s["key"]), ""),
                                  history=np.array(history) if history else None)
    precision = {s["key"]: kept.get(s["key"], precision.get(s["key"])) for s in scenes
                 if s["key"] in kept or s["key"] in precision}
    prose = kept_prose(md_path)
    md = ["# Precision of the mass tensor model (Mollemans et al. 2007, 2.3.5, Table 1, Fig. 1)", "",
          "How the mass tensor model's precision falls with its sweeps, and whether the "
          "paper's rule (G_max < 0.001 mm per sweep gives P_min < 0.3 mm) holds on the cube.", "",
          f"Reproduce: `{command.strip()}`.", "",
          f"Measured on {machine()}; the commit of each scene's runs is listed below the table "
          "(a scene run apart with `--scenes` keeps the others' rows from their last run).", "",
          "The MTM is swept with every free point updated in every sweep (Gauss-Seidel, no "
          "active set) until all gradients fall below 1e-5 mm per sweep; after every sweep "
          "softface measures the distance of each free point to the converged answer of the "
          "same equations (sparse direct solve): the largest is the paper's minimal "
          "precision P_min, the mean is P_mean; G_max is the largest gradient (mean step "
          "over the last 10 sweeps, mm per sweep).", "",
          "| scene | tets | vertices | sweeps to P_min < 0.3 mm | P_mean there (mm) | "
          "G_max there (mm/sweep) | sweeps to P_min < 0.1 mm | sweeps to G_max < 0.001 | "
          "P_min at G_max < 0.001 (mm) |",
          "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    rows = []
    for key, p in precision.items():
        if p["history"] is not None:
            for h in p["history"]:
                rows.append([key, p["tets"], int(h[0]), h[1], h[2], h[3]])
        if "line" in p:
            md.append(p["line"])
            continue
        if not p["ok"]:
            md.append(f"| {p['scene']['title']} | {p['tets']} | | failed: {p['message']} "
                      "| | | | | |")
            continue
        h = p["history"]
        sweep, pmin, pmean, gmax = h[:, 0], h[:, 1], h[:, 2], h[:, 3]

        def first(mask):
            idx = np.nonzero(mask)[0]
            return int(idx[0]) if len(idx) else None

        i03, i01 = first(pmin < 0.3), first(pmin < 0.1)
        # G_max is defined once every point has had a full window.
        ig = first((gmax < 1e-3) & (sweep >= 10))
        md.append(f"| {p['scene']['title']} | {p['tets']} | {p['vertices']} | "
                  f"{int(sweep[i03]) if i03 is not None else '-'} | "
                  f"{fmt(pmean[i03]) if i03 is not None else '-'} | "
                  f"{fmt(gmax[i03]) if i03 is not None else '-'} | "
                  f"{int(sweep[i01]) if i01 is not None else '-'} | "
                  f"{int(sweep[ig]) if ig is not None else '-'} | "
                  f"{fmt(pmin[ig]) if ig is not None else '-'} |")
    # Which run made each row: the rows of a scene run apart may come from another
    # version of softface than the others' (its defaults change the sweeps).
    sections = scene_sections(os.path.join(results, "accuracy_vs_time.md"))
    made = []
    for key, p in precision.items():
        line = next((x for x in sections.get(key, []) if x.startswith("Measured by")), None)
        if line:
            made.append(f"- {p['scene']['title']}: {line}")
    md += [""] + made if made else []
    md += ["", "![precision against sweeps](mtm_precision.png)", ""]
    md += prose or ["## What the numbers show", "",
                    "- The paper (five patients, Table 1) found P_min < 0.3 mm when G_max fell "
                    "below 0.001 and P_mean about 0.039 mm there.", ""]
    with open(md_path, "w") as f:
        f.write("\n".join(md))
    with open(csv_path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["scene", "n_tets_target", "sweep", "precision_min_mm",
                    "precision_mean_mm", "max_gradient_mm_per_sweep"])
        for r in rows:
            w.writerow([r[0], r[1], r[2], f"{r[3]:.6g}", f"{r[4]:.6g}", f"{r[5]:.6g}"])

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.3))
    for key, p in precision.items():
        if not p["ok"]:
            continue
        h = p["history"]
        # A kept row is marked: it may come from another version of softface.
        title = p["scene"]["title"] + (" (earlier run)" if key in keep else "")
        axes[0].semilogy(h[:, 0], h[:, 1], label=f"{title}: P_min")
        axes[0].semilogy(h[:, 0], h[:, 2], ls="--", label=f"{title}: P_mean")
        axes[1].loglog(h[10:, 3], h[10:, 1], label=title)
    axes[0].axhline(0.3, color="red", lw=0.8)
    axes[0].set_xlabel("sweep")
    axes[0].set_ylabel("precision (mm)")
    axes[0].legend(fontsize=7)
    axes[0].grid(True, which="both", alpha=0.3)
    axes[1].axhline(0.3, color="red", lw=0.8)
    axes[1].axvline(1e-3, color="grey", ls="--", lw=0.8)
    axes[1].invert_xaxis()
    axes[1].set_xlabel("G_max (mm per sweep)")
    axes[1].set_ylabel("P_min (mm)")
    axes[1].legend(fontsize=7)
    axes[1].grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(results, "mtm_precision.png"), dpi=110)
