#!/usr/bin/python3
"""The patients benchmark's report: the paper's Table 2 side by side with the
ten phantom patients (procedure, tetrahedra, largest soft-tissue motion, each
model's time), the patient pipeline's figures, and each patient's image.

Usage: report.py WORK_DIR RESULTS_DIR  (called by benchmarks/patients/run.sh)
Reads WORK_DIR/P<n>/{summary.csv, patient.csv, exit_code, stderr.txt} (and
what skin_report.py, precision_report.py and timing_report.py read); writes RESULTS_DIR/patients.md
and RESULTS_DIR/patients.csv.
"""
import csv
import os
import platform
import re
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import summary  # noqa: E402
import skin_report  # noqa: E402
import precision_report  # noqa: E402
import timing_report  # noqa: E402

# The paper's Table 2 (Mollemans et al. 2007): procedure, N_tetra, M_max (mm),
# T_FEM, T_MTM, T_MSM, T_NFEM (s) on a Pentium 4 with 1 GB; None where the
# paper gives no figure.
SEED = {
    "P1": ("MSB + G", 129955, 8.1, 24.7, 16.5, 68.35, 893.6),
    "P2": ("G + MxA", 74232, 9.5, 11.9, 7.6, 24.3, 233.4),
    "P3": ("MSB + MxA", 85213, 4.9, 16.8, 6.6, None, None),
    "P4": ("MA", 66286, 4.3, 13.7, 2.5, 10.99, 41.1),
    "P5": ("MA + G + MxA", 79716, 16.7, 19.2, 12.9, 47.6, 1885.2),
    "P6": ("MA + MxA", 79125, 6.3, 19.5, 5.4, 33.1, 913.5),
    "P7": ("MA + MxA", 75314, 9.6, 17.9, 9.9, 32.2, 1001.6),
    "P8": ("MA + G + MxA", 303745, 9.9, 104.1, 23.2, 94.3, 2712.3),
    "P9": ("MA + G + MxSB", 80654, 13.8, 11.5, 8.2, 42.3, 897.3),
    "P10": ("MA + G + MxA", 91925, 9.5, 17.9, 8.5, 34.6, 498.6),
}
MODELS = ["linear fem", "mass tensor", "mass spring", "nonlinear fem"]


def figures(path):
    if not os.path.exists(path):
        return {}
    with open(path, newline="") as f:
        return {r["figure"]: r["value"] for r in csv.DictReader(f)}


def fmt(x, digits=3):
    if x is None or x == "":
        return "-"
    return f"{float(x):.{digits}g}"


def commit():
    """The commit softface was built from (a suffix says the tree had
    uncommitted changes)."""
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    try:
        head = subprocess.run(["git", "-C", root, "rev-parse", "--short",
                               "HEAD"], capture_output=True, text=True,
                              check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", root, "status", "--porcelain",
                                "--untracked-files=no", "--", "source",
                                "include"], capture_output=True,
                               text=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "an unknown commit"
    return head + (" with local changes to source/ or include/" if dirty
                   else "")


def seconds(row):
    """A model's time as in the paper: setup + solve (s), or None."""
    if row is None or row["status"] != "ok":
        return None
    return float(row["setup_s"]) + float(row["solve_s"])


def main(work, results):
    rows = []
    for name in SEED:
        d = os.path.join(work, name)
        # A patient whose run was stopped has no exit code: not reported.
        if not os.path.exists(os.path.join(d, "exit_code")):
            continue
        runs = {m: summary.row(os.path.join(d, "summary.csv"), m)
                for m in MODELS}
        fig = figures(os.path.join(d, "patient.csv"))
        code, wall_ms = (open(os.path.join(d, "exit_code")).read().split()
                         + ["", ""])[:2]
        peak = ""
        stderr = os.path.join(d, "stderr.txt")
        if os.path.exists(stderr):
            m = re.search(r"Maximum resident set size \(kbytes\): (\d+)",
                          open(stderr).read())
            peak = f"{int(m.group(1)) / 1024:.0f}" if m else ""
        lin = runs["linear fem"]
        r = {"patient": name, "procedure": SEED[name][0],
             "seed_tets": SEED[name][1], "seed_m_max_mm": SEED[name][2],
             "tets": fig.get("tetrahedra", lin["n_tets"] if lin else ""),
             "m_max_mm": lin["max_displacement_mm"] if lin else "",
             "exit_code": code, "wall_s": float(wall_ms) / 1000
             if wall_ms else "", "peak_memory_mb": peak}
        for i, m in enumerate(MODELS):
            key = m.replace(" ", "_")
            r[f"seed_t_{key}_s"] = SEED[name][3 + i]
            r[f"t_{key}_s"] = seconds(runs[m])
            r[f"status_{key}"] = runs[m]["status"] if runs[m] else "missing"
            r[f"error_{key}"] = runs[m]["error"] if runs[m] else ""
            r[f"max_diff_{key}_mm"] = (runs[m]["max_diff_to_reference_mm"]
                                       if runs[m] else "")
            r[f"mean_diff_{key}_mm"] = (runs[m]["mean_diff_to_reference_mm"]
                                        if runs[m] else "")
            r[f"max_u_{key}_mm"] = (runs[m]["max_displacement_mm"]
                                    if runs[m] else "")
        for f in ["CT voxels", "phantom s", "segmentation s", "bone split s",
                  "mesh s", "skin vertices", "skull vertices",
                  "min dihedral deg", "worst radius ratio", "mesh volume cm3",
                  "soft tissue in region cm3", "mesh vertices",
                  "shared join points", "peak memory MB"]:
            r[f] = fig.get(f, "")
        rows.append(r)
    if not rows:
        print("patients: no results in", work)
        return 1

    summary.write_rows(os.path.join(results, "patients.csv"), rows)

    md = []
    md.append("# Ten phantom patients after the paper's Table 2\n")
    md.append("Whether every model runs on ten phantom patients made after "
              "the paper's Table 2, what each costs, how far each prediction "
              "lies from a model-made post-operative skin, and which of the "
              "paper's conclusions these numbers confirm and which they "
              "cannot resolve.\n")
    md.append("Reproduce: `benchmarks/patients/run.sh` (about 9 min, plus "
              "about an hour for the post-operative truths the first "
              "time).\n")
    md.append(f"Measured at commit {commit()} on {platform.machine()}, "
              f"{os.cpu_count()} cores.\n")
    md.append("Scenes `prm/patients/P1.prm` ... `P10.prm`, written by "
              "`benchmarks/patients/make_scenes.py`; figures from each "
              "run's `summary.csv` and `patient.csv`. CSV: "
              "[patients.csv](patients.csv).\n")
    # What the person who ran the benchmark says of this run (the machine's
    # load, patients run separately), from WORK_DIR/run_note.md.
    run_note = os.path.join(work, "run_note.md")
    if os.path.exists(run_note):
        md.append("**This run.** " + open(run_note).read().strip() + "\n")
    md.append("Each patient is a phantom head CT at 1 mm voxels "
              "(180 x 240 x 256), segmented, its skull cut by Le Fort I, "
              "bilateral sagittal split and genioplasty into six bone parts "
              "(cranium, maxilla, two rami, mandible, chin), the soft tissue "
              "below the eyes meshed by CGAL Mesh_3, and moved by the "
              "procedure's planning. The paper's patients were real; its "
              "times were measured on a Pentium 4 (2007), ours on this "
              "machine. Time = setup + solve, in seconds; M_max = the "
              "largest displacement of any soft-tissue vertex (linear "
              "FEM).\n")
    md.append("| patient | procedure | N_tetra paper | ours | M_max paper (mm) "
              "| ours | T_FEM paper | ours | T_MTM paper | ours | T_MSM paper | "
              "ours | T_NFEM paper | ours |")
    md.append("|---" * 14 + "|")

    def t(r, key):
        if r[f"status_{key}"] == "ok":
            return fmt(r[f"t_{key}_s"])
        return r[f"status_{key}"]

    keys = [m.replace(" ", "_") for m in MODELS]
    for r in rows:
        times = " | ".join(fmt(r["seed_t_" + k + "_s"]) + " | " + t(r, k)
                           for k in keys)
        md.append(
            f"| {r['patient']} | {r['procedure']} | {r['seed_tets']} | "
            f"{r['tets']} | {r['seed_m_max_mm']} | {fmt(r['m_max_mm'])} | "
            f"{times} |")
    md.append("")
    failed = [(r["patient"], m, r["error_" + m.replace(" ", "_")])
              for r in rows for m in MODELS
              if r["status_" + m.replace(" ", "_")] != "ok"]
    if failed:
        md.append("Models that failed (their reason, from `summary.csv`):\n")
        for p, m, e in failed:
            md.append(f"- {p}, {m}: {e}")
        md.append("")

    md.append("## Each model against linear FEM\n")
    md.append("Largest and mean difference of each model's displacement to "
              "linear FEM's over the free vertices (mm), and its largest "
              "displacement.\n")
    md.append("| patient | " + " | ".join(
        f"{m} max / mean | {m} max u" for m in MODELS[1:]) + " |")
    md.append("|---" * (1 + 2 * len(MODELS[1:])) + "|")
    for r in rows:
        cells = []
        for m in MODELS[1:]:
            k = m.replace(" ", "_")
            if r[f"status_{k}"] == "ok":
                cells.append(f"{fmt(r[f'max_diff_{k}_mm'])} / "
                             f"{fmt(r[f'mean_diff_{k}_mm'])}")
                cells.append(fmt(r[f"max_u_{k}_mm"]))
            else:
                cells += [r[f"status_{k}"], "-"]
        md.append(f"| {r['patient']} | " + " | ".join(cells) + " |")
    md.append("")

    md.append("## The patient pipeline\n")
    md.append("Seconds per stage (phantom acquisition; segmentation with the "
              "skin and skull surfaces; bone split; Mesh_3 with sliver "
              "perturbation and exudation), mesh quality, the meshed volume "
              "against the segmented soft tissue of the region, and the "
              "whole run (pipeline + four models) with its peak memory "
              "(`/usr/bin/time -v`).\n")
    md.append("| patient | phantom s | segmentation s | split s | mesh s | "
              "labels + surfaces + mesh s | tets | skin vertices | min "
              "dihedral deg | worst radius ratio | mesh / segmented cm^3 | "
              "vertices left free between parts | run s | peak MB |")
    md.append("|---" * 14 + "|")
    for r in rows:
        stages = sum(float(r[k]) for k in ["segmentation s", "bone split s",
                                           "mesh s"] if r[k] != "")
        md.append(
            f"| {r['patient']} | {fmt(r['phantom s'])} | "
            f"{fmt(r['segmentation s'])} | {fmt(r['bone split s'])} | "
            f"{fmt(r['mesh s'])} | {fmt(stages)} | {r['tets']} | "
            f"{r['skin vertices']} | {fmt(r['min dihedral deg'])} | "
            f"{fmt(r['worst radius ratio'])} | {fmt(r['mesh volume cm3'], 4)}"
            f" / {fmt(r['soft tissue in region cm3'], 4)} | "
            f"{r['shared join points']} | {fmt(r['wall_s'])} | "
            f"{r['peak_memory_mb']} |")
    md.append("")

    md += skin_report.sections(work, results, [r["patient"] for r in rows])
    md += precision_report.sections(work, results, [r["patient"] for r in rows])
    md += timing_report.sections(work, results, [r["patient"] for r in rows])

    md.append("## The patients\n")
    md.append("Skin and skull of each phantom (front and right profile), "
              "rendered from the `skin.ply` and `skull.ply` the segmentation "
              "wrote (`benchmarks/patients/render.py`).\n")
    for r in rows:
        png = f"patients/{r['patient']}.png"
        if os.path.exists(os.path.join(results, png)):
            md.append(f"### {r['patient']}: {r['procedure']}\n")
            md.append(f"![{r['patient']}]({png})\n")
    # What the numbers show and the limits, written by hand below their
    # heading, stay (re-read them against the new figures).
    notes_heading = "## What the numbers show"
    old_path = os.path.join(results, "patients.md")
    if os.path.exists(old_path):
        old = open(old_path).read()
        if notes_heading in old:
            md.append(old[old.index(notes_heading):].rstrip("\n") + "\n")
    with open(os.path.join(results, "patients.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("patients: wrote", os.path.join(results, "patients.md"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
