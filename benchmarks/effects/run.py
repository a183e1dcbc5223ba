"""What each effect changes and what it costs; see run.sh.

Every (scene, configuration, model) runs in its own softface process, the
repetitions interleaved so that a slow minute of a shared machine hits every
configuration alike. Times are softface's own setup and solve times from
summary.csv, memory the process's peak (one model per process). What an effect
changes is measured against the same scene and model without effects: the
largest and the 90th-percentile difference of the displacement over the skin's
vertices (patient: the mesh's boundary id 1) or, on the cube, whose outer
faces are held, over its free vertices.
"""
import argparse
import csv
import os
import re
import statistics
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "benchmarks"))
import summary  # noqa: E402

WORK = os.path.join(ROOT, "build", "benchmarks", "effects")
RESULTS = os.path.join(ROOT, "doc", "results")
MODELS = ["linear fem", "mass tensor", "mass spring", "nonlinear fem"]

SCENES = {
    "cube": {
        "prm": "prm/default.prm",
        "heterogeneous": """subsection Scene
  subsection Cube
    set Upper tissue material id = 3
  end
end
""",
        "tissue": "1: 3000, 3: 12000",
        # The cube's base slides on its support; a slit in the mid-plane
        # from the face x = 0 to x = 30, short of the bone.
        "contact": "set Segment = fixed\n    set Region = -1, 81, -1, 81, -1, 1",
        "lips": "set Slit point = 40, 40, 40\n    set Region = -1, 30, -1, 81, 39, 41",
    },
    "patient": {
        "prm": "prm/patient.prm",
        "heterogeneous": "",
        "tissue": "1: 15000, 2: 3000, 3: 6000",
        # The upper lip slides on the front of the maxilla (its contact
        # faces in front of y = -60); the mouth slit at the occlusal plane
        # z = -22 (between the maxilla, down to z = -20, and the mandible,
        # up to z = -24, at x = 0), from the skin back to y = -66, in front
        # of the teeth.
        "contact": "set Segment = maxilla\n    set Region = -25, 25, -80, -60, -20, 0",
        "lips": "set Slit point = 0, -80, -22\n    set Region = -25, 25, -110, -66, -26, -18",
    },
}
CONFIGS = ["none", "heterogeneous tissue", "gravity", "sliding contact",
           "separated lips", "all four"]
ALL_FOUR = ["heterogeneous tissue", "gravity", "sliding contact", "separated lips"]


def file_name(model):
    return model.replace(" ", "_")


def scene_text(scene, config, model, output, current):
    spec = SCENES[scene]
    text = open(os.path.join(ROOT, spec["prm"])).read()
    # The skin mapping and its truth are not effects, and the
    # baseline has neither: left out, so that time and memory compare alike.
    text = re.sub(r"\nsubsection Skin\n.*?\nend\n", "\n", text, flags=re.S)
    text += f"""
subsection Output
  set Output directory = {output}
  set Write VTU = false
  set Write nodal displacements = true
end
subsection Models
  set Models = {model}
end
"""
    if scene == "patient":
        text += f"""subsection Scene
  subsection Patient
    set Work directory = {os.path.join(WORK, "patient_stages")}
  end
end
"""
        if current:
            text += """subsection Skin
  set Skin surface = none
end
"""
    effects = ALL_FOUR if config == "all four" else \
        ([] if config == "none" else [config])
    if "heterogeneous tissue" in effects:
        text += spec["heterogeneous"]
    if effects:
        text += f"""subsection Effects
  set Effects = {", ".join(effects)}
  subsection heterogeneous tissue
    set Young's moduli = {spec["tissue"]}
  end
  subsection gravity
    set Gravity = 0, 0, -9.81
    set Density = 1000
  end
  subsection sliding contact
    {spec["contact"]}
  end
  subsection separated lips
    {spec["lips"]}
  end
end
"""
    return text


def run_case(binary, scene, config, model, repetition):
    tag = "baseline" if binary != default_binary() else "current"
    out = os.path.join(WORK, scene, config.replace(" ", "_"), tag,
                       file_name(model), str(repetition))
    os.makedirs(out, exist_ok=True)
    prm = os.path.join(out, "scene.prm")
    with open(prm, "w") as f:
        f.write(scene_text(scene, config, model, out, tag == "current"))
    start = time.time()
    with open(os.path.join(out, "log.txt"), "w") as log:
        rc = subprocess.call([binary, prm], stdout=log, stderr=subprocess.STDOUT,
                             cwd=ROOT)
    wall = time.time() - start
    row = summary.row(os.path.join(out, "summary.csv"), model) or {}
    return {
        "scene": scene, "config": config, "binary": tag, "model": model,
        "repetition": repetition, "exit_code": rc, "wall_s": wall,
        "status": row.get("status", "no summary"),
        "setup_s": float(row.get("setup_s", "nan") or "nan"),
        "solve_s": float(row.get("solve_s", "nan") or "nan"),
        "peak_memory_mb": float(row.get("peak_memory_mb", "nan") or "nan"),
        "output": out,
    }


def default_binary():
    return os.path.join(ROOT, "build", "softface")


def skin_points(scene):
    """Coordinates of the vertices a difference is measured on, as a set of
    rounded tuples (None: every free vertex)."""
    if scene != "patient":
        return None
    msh = os.path.join(WORK, "patient_stages", "mesh.msh")
    nodes, skin = {}, set()
    with open(msh) as f:
        lines = iter(f)
        for line in lines:
            if line.startswith("$Nodes"):
                for _ in range(int(next(lines))):
                    i, x, y, z = next(lines).split()
                    nodes[i] = (float(x), float(y), float(z))
            if line.startswith("$Elements"):
                for _ in range(int(next(lines))):
                    e = next(lines).split()
                    if e[1] == "2" and e[3] == "1":
                        skin.update(e[-3:])
    return {tuple(round(c, 4) for c in nodes[i]) for i in skin}


def displacements(output, model):
    data = np.loadtxt(os.path.join(output, f"displacements_{file_name(model)}.csv"),
                      delimiter=",", skiprows=1, ndmin=2)
    return data[:, :3], data[:, 3:]


def differences(rows, scene, config, model, points):
    def output_of(c):
        for r in rows:
            if (r["scene"], r["config"], r["model"], r["binary"], r["repetition"]) == \
                    (scene, c, model, "current", 0) and r["status"] == "ok":
                return r["output"]
        return None
    on, off = output_of(config), output_of("none")
    if on is None or off is None:
        return None
    x, u_on = displacements(on, model)
    x_off, u_off = displacements(off, model)
    # A slit's copies of vertices come after the mesh's own ones.
    x, u_on = x[:len(x_off)], u_on[:len(x_off)]
    assert np.allclose(x, x_off), "vertex order changed"
    d = np.linalg.norm(u_on - u_off, axis=1)
    if points is None:
        # The cube: its free vertices, off the held outer faces and outside
        # the inner cube (the bone).
        on_face = np.any(np.isclose(x, 0) | np.isclose(x, 80), axis=1)
        in_bone = np.all((x > 35 - 1e-9) & (x < 45 + 1e-9), axis=1)
        mask = ~on_face & ~in_bone
    else:
        mask = np.array([tuple(round(c, 4) for c in p) in points for p in x])
    d = d[mask]
    return {"n": int(mask.sum()), "max": float(d.max()), "p90": float(np.percentile(d, 90))}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repetitions", type=int, default=3)
    parser.add_argument("--baseline", default="",
                        help="a softface built without the effect machinery")
    parser.add_argument("--baseline-name", default="",
                        help="what the baseline is, for the report (e.g. a commit)")
    parser.add_argument("--scenes", default="cube,patient")
    parser.add_argument("--report-only", action="store_true")
    args = parser.parse_args()
    scenes = args.scenes.split(",")
    table = os.path.join(WORK, "runs.csv")
    os.makedirs(WORK, exist_ok=True)

    command_file = os.path.join(WORK, "command.txt")
    if not args.report_only:
        with open(command_file, "w") as f:
            f.write(" ".join(a for a in sys.argv[1:]) + "\n")
        rows = []
        cases = [(default_binary(), s, c, m) for s in scenes for c in CONFIGS for m in MODELS]
        if args.baseline:
            cases += [(os.path.abspath(args.baseline), s, "none", m)
                      for s in scenes for m in MODELS]
        total, start = len(cases) * args.repetitions, time.time()
        done = 0
        for repetition in range(args.repetitions):
            for binary, s, c, m in cases:
                rows.append(run_case(binary, s, c, m, repetition))
                done += 1
                elapsed = time.time() - start
                print(f"[{done}/{total}] {s}, {c}, {m}"
                      f"{' (baseline)' if binary != default_binary() else ''}: "
                      f"{rows[-1]['status']} (elapsed {elapsed / 60:.1f} min, about "
                      f"{elapsed / done * (total - done) / 60:.1f} min left)", flush=True)
        with open(table, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            w.writeheader()
            w.writerows(rows)
    with open(table, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in ("setup_s", "solve_s", "peak_memory_mb", "wall_s"):
            r[k] = float(r[k])
        r["repetition"] = int(r["repetition"])
    arguments = open(command_file).read().strip() if os.path.exists(command_file) else ""
    report(rows, sorted({r["scene"] for r in rows}, key=list(SCENES).index),
           arguments, args.baseline_name)


def report(rows, scenes, arguments, baseline_name):
    def runs(scene, config, model, binary="current"):
        return [r for r in rows if (r["scene"], r["config"], r["model"], r["binary"]) ==
                (scene, config, model, binary) and r["status"] == "ok"]

    def time_of(r):
        return r["setup_s"] + r["solve_s"]

    out_csv = []
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True, cwd=os.path.dirname(os.path.abspath(__file__))
                            ).stdout.strip()
    md = ["# Effects: what each changes and what it costs",
          "",
          "What heterogeneous tissue, gravity, sliding contact and separated lips change in "
          "each model's answer on the cube and on the phantom patient, what they cost in time "
          "and memory, and whether an empty Effects section costs anything.",
          "",
          f"Reproduce: `{('benchmarks/effects/run.sh ' + arguments).strip()}` (about 7 min).",
          "",
          f"Measured at commit {commit}"
          + (f" against a baseline build of {baseline_name} (without the effects)"
             if baseline_name else "") + f", {os.cpu_count()} cores.",
          "", "![what each effect changes and costs](effects.png)", ""] + [
          "Every model in its own softface process; times are softface's setup + solve "
          "(median of the repetitions, min-max in brackets), memory the process's peak. "
          "Differences are to the same scene and model without effects: over the skin's "
          "vertices (patient) or the free vertices (cube, whose outer faces are held). "
          "Cube: `prm/default.prm` (35k tetrahedra, inner cube lifted 6 mm), a second "
          "tissue of 12 kPa above the mid-plane (3 kPa below). Patient: `prm/patient.prm` "
          "(the phantom, six bone segments moved), tissues 15/3/6 kPa (skin/fat/muscle). "
          "Gravity: 9.81 m/s^2 along -z (upright), 1000 kg/m^3. Sliding contact "
          "(bilateral): cube, its base (z = 0) slides on the fixed support; patient, "
          "the upper lip on the front of the maxilla (contact faces in x -25..25, "
          "y -80..-60, z -20..0). Separated lips: cube, a slit in the mid-plane from "
          "x = 0 to x = 30; patient, the mouth slit at z = -22 from the skin back to "
          "y = -66, x -25..25. 'all four': every effect at once.",
          ""]
    for scene in scenes:
        points = skin_points(scene)
        md += [f"## {scene}", "",
               "| model | effects | time s | time / none | peak MB | max diff mm | 90% diff mm |",
               "|---|---|---|---|---|---|---|"]
        for model in MODELS:
            base = runs(scene, "none", model)
            base_t = statistics.median(time_of(r) for r in base) if base else float("nan")
            for config in CONFIGS:
                rs = runs(scene, config, model)
                failed = [r for r in rows if (r["scene"], r["config"], r["model"], r["binary"])
                          == (scene, config, model, "current") and r["status"] != "ok"]
                if not rs:
                    md.append(f"| {model} | {config} | failed ({failed[0]['status'] if failed else 'not run'}) | | | | |")
                    continue
                ts = [time_of(r) for r in rs]
                t = statistics.median(ts)
                mem = statistics.median(r["peak_memory_mb"] for r in rs)
                diff = differences(rows, scene, config, model, points) if config != "none" else None
                md.append(f"| {model} | {config} | {t:.3f} ({min(ts):.3f}-{max(ts):.3f}) | "
                          f"{t / base_t:.2f} | {mem:.0f} | "
                          f"{diff['max']:.3f} | {diff['p90']:.3f} |" if diff else
                          f"| {model} | {config} | {t:.3f} ({min(ts):.3f}-{max(ts):.3f}) | "
                          f"{t / base_t:.2f} | {mem:.0f} | | |")
                out_csv.append({"scene": scene, "model": model, "effects": config,
                                "binary": "current", "runs": len(rs),
                                "time_median_s": t, "time_min_s": min(ts), "time_max_s": max(ts),
                                "peak_memory_mb": mem,
                                "max_diff_mm": diff["max"] if diff else "",
                                "p90_diff_mm": diff["p90"] if diff else "",
                                "diff_vertices": diff["n"] if diff else ""})
        md.append("")
        baseline = [r for r in rows if r["scene"] == scene and r["binary"] == "baseline"]
        if baseline:
            md += [f"Zero cost on the {scene}: Effects empty in this build against a build "
                   "without the effect machinery (baseline), same scene, interleaved. A ratio "
                   "inside the spread of the repetitions is noise.", "",
                   "| model | baseline time s | this build s | ratio | baseline MB | this build MB |",
                   "|---|---|---|---|---|---|"]
            for model in MODELS:
                b, c = runs(scene, "none", model, "baseline"), runs(scene, "none", model)
                if not b or not c:
                    continue
                bt, ct = [time_of(r) for r in b], [time_of(r) for r in c]
                md.append(f"| {model} | {statistics.median(bt):.3f} ({min(bt):.3f}-{max(bt):.3f}) | "
                          f"{statistics.median(ct):.3f} ({min(ct):.3f}-{max(ct):.3f}) | "
                          f"{statistics.median(ct) / statistics.median(bt):.3f} | "
                          f"{statistics.median(r['peak_memory_mb'] for r in b):.0f} | "
                          f"{statistics.median(r['peak_memory_mb'] for r in c):.0f} |")
                out_csv.append({"scene": scene, "model": model, "effects": "none",
                                "binary": "baseline", "runs": len(b),
                                "time_median_s": statistics.median(bt), "time_min_s": min(bt),
                                "time_max_s": max(bt),
                                "peak_memory_mb": statistics.median(r["peak_memory_mb"] for r in b),
                                "max_diff_mm": "", "p90_diff_mm": "", "diff_vertices": ""})
            md.append("")
    # What the numbers show, written by hand below its heading, stays.
    notes_heading = "## What the numbers show"
    path = os.path.join(RESULTS, "effects.md")
    notes = ""
    if os.path.exists(path):
        old = open(path).read()
        if notes_heading in old:
            notes = old[old.index(notes_heading):]
    with open(path, "w") as f:
        f.write("\n".join(md) + "\n" + ("\n" + notes if notes else ""))
    with open(os.path.join(RESULTS, "effects.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(out_csv[0].keys()))
        w.writeheader()
        w.writerows(out_csv)
    plot(out_csv, scenes)
    print("effects: wrote doc/results/effects.md, effects.csv, effects.png")


def plot(out_csv, scenes):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(scenes), figsize=(6 * len(scenes), 4), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        width = 0.8 / len(CONFIGS)
        for k, config in enumerate(CONFIGS):
            values = []
            for model in MODELS:
                r = next((r for r in out_csv if r["scene"] == scene and r["model"] == model
                          and r["effects"] == config and r["binary"] == "current"), None)
                values.append(r["time_median_s"] if r else 0.)
            ax.bar(np.arange(len(MODELS)) + (k - 1.5) * width, values, width, label=config)
        ax.set_xticks(np.arange(len(MODELS)))
        ax.set_xticklabels(MODELS)
        ax.set_ylabel("setup + solve (s), median")
        ax.set_title(scene)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, "effects.png"), dpi=110)


if __name__ == "__main__":
    main()
