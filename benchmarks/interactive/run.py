#!/usr/bin/python3
"""Re-planning with and without the response basis, one process each, same scene.

usage: run.py SOFTFACE SCENE WORK RESULTS "COMMAND" [--quick]

The scene (a patient's .prm, included) gets a sweep of the mandible's set-back (the chin's motion
as the scene plans it), linear fem (cg amg) and mass tensor, its dense skin mapped by shape
functions and no post-operative skin. Run 'never' solves every plan after one setup; run 'always'
builds each model's basis (12 solves per moved segment) and combines. Per model: setup, basis,
one solve (median over the plans of 'never'), re-plan = combination + skin step B (medians over
the plans of 'always'), the basis's memory, and the largest difference between the two runs'
displacements over all plans (linear fem: must be below 1e-6 of the largest displacement, or
the run fails; mass tensor: its stop criterion's, reported).
Then `softface serve` on the same scene and its page in headless Chromium (MOVES slider moves):
the slider-to-face latency and a screenshot.
Writes RESULTS/interactive.md, interactive.csv, interactive.png, interactive_page.png.
"""
import csv, json, os, re, signal, subprocess, sys, time
from statistics import median

softface, scene, work, results, command = sys.argv[1:6]
quick = "--quick" in sys.argv[6:]
PLANS = 8 if quick else 32
MOVES = 10 if quick else 30
MODELS = ["linear fem", "mass tensor"]
MOVED = 2  # the scene's moved segments: mandible and chin
out_dir = os.path.join(work, "out")


def write_scene(basis):
    prm = os.path.join(work, f"sweep_{basis}.prm")
    with open(prm, "w") as f:
        f.write(f"""include {scene}
subsection Planning
  set Response basis = {basis}
  subsection Sweep
    set Segment  = mandible
    set Quantity = translation y
    set From     = -2
    set To       = -10
    set Steps    = {PLANS}
  end
end
subsection Models
  set Models = {", ".join(MODELS)}
  set Threads = 1
  subsection linear fem
    set Solver = cg amg
  end
end
subsection Skin
  set Mapping             = shape functions
  set Post-operative skin =
end
subsection Output
  set Output directory          = {out_dir}
  set Write VTU                 = false
  set Write nodal displacements = true
end
""")
    return prm


def read_rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def displacement(label):
    name = "".join(c if c.isalnum() or c in ".-+" else "_" for c in label)
    while "__" in name:
        name = name.replace("__", "_")
    with open(os.path.join(out_dir, f"displacements_{name}.csv")) as f:
        return [tuple(map(float, l.split(",")[3:6])) for l in list(f)[1:]]


runs = {}
for basis in ["never", "always"]:
    prm = write_scene(basis)
    start = time.perf_counter()
    log = subprocess.run([softface, prm], capture_output=True, text=True)
    wall = time.perf_counter() - start
    with open(os.path.join(work, f"sweep_{basis}.log"), "w") as f:
        f.write(log.stdout + log.stderr)
    if log.returncode != 0:
        sys.exit(f"softface failed on {prm} (see {work}/sweep_{basis}.log)")
    summary = read_rows(os.path.join(out_dir, "summary.csv"))
    skin = read_rows(os.path.join(out_dir, "skin.csv"))
    u = {(r["model"], r["plan"]): displacement(f'{r["model"]}, {r["plan"]}') for r in summary}
    runs[basis] = {"summary": summary, "skin": skin, "u": u, "wall": wall}

# The page in headless Chromium: softface serve on the same scene, MOVES slider moves, each
# waited for until the face is redrawn (web/test/serve_browser.mjs).
root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
serve_prm = os.path.join(work, "serve.prm")
with open(serve_prm, "w") as f:
    f.write(f"""include {scene}
subsection Models
  set Models = {", ".join(MODELS)}
  set Threads = 1
end
subsection Skin
  set Mapping             = shape functions
  set Post-operative skin =
end
subsection Serve
  set Port = 0
end
subsection Output
  set Output directory = {out_dir}
  set Write VTU        = false
end
""")
serve_log = open(os.path.join(work, "serve.log"), "w+")
server = subprocess.Popen([softface, "serve", serve_prm], stdout=serve_log, stderr=subprocess.STDOUT)
url = None
for _ in range(6000):
    serve_log.seek(0)
    found = re.search(r"http://[0-9.]+:[0-9]+/", serve_log.read())
    if found:
        url = found.group(0)
        break
    if server.poll() is not None:
        break
    time.sleep(0.1)
if url is None:
    server.kill()
    sys.exit(f"softface serve did not start (see {work}/serve.log)")
screenshot = os.path.join(results, "interactive_page.png")
browser = subprocess.run(["node", os.path.join(root, "web", "test", "serve_browser.mjs"), url,
                          screenshot, str(MOVES)], capture_output=True, text=True)
server.send_signal(signal.SIGINT)
server.wait()
if browser.returncode != 0:
    sys.exit("the page failed in Chromium:\n" + browser.stdout + browser.stderr)
page = json.loads(browser.stdout.strip().splitlines()[-1])

n_tets = int(runs["never"]["summary"][0]["n_tets"])
rows = []
for model in MODELS:
    never = [r for r in runs["never"]["summary"] if r["model"] == model]
    always = [r for r in runs["always"]["summary"] if r["model"] == model]
    skin = [r for r in runs["always"]["skin"] if r["model"].startswith(model + ",")]
    details = dict(d.split("=", 1) for d in always[0]["details"].split(";") if "=" in d)
    solve = median(float(r["solve_s"]) for r in never)
    basis = float(always[0]["basis_s"])
    combination = median(float(r["solve_s"]) for r in always)
    step_b = median(float(r["step B s"]) for r in skin)
    largest = max(max(abs(c) for p in runs["never"]["u"][(model, r["plan"])] for c in p)
                  for r in never)
    diff = max(max(abs(a - b) for p, q in zip(runs["never"]["u"][(model, r["plan"])],
                                               runs["always"]["u"][(model, r["plan"])])
                   for a, b in zip(p, q)) for r in never)
    rows.append({"model": model, "tets": n_tets, "plans": len(never),
                 "setup_s": float(never[0]["setup_s"]), "solve_s": solve,
                 "basis_s": basis, "basis_memory_mb": float(details["basis memory"].split()[0]),
                 "combination_ms": 1e3 * combination, "skin_step_b_ms": 1e3 * step_b,
                 "replan_ms": 1e3 * (combination + step_b),
                 "skin_points": int(skin[0]["skin points"]),
                 "max_displacement_mm": largest, "max_difference_mm": diff})
    if model == "linear fem" and not diff <= 1e-6 * largest:
        sys.exit(f"linear fem: the combination differs from the solve by {diff} mm")

with open(os.path.join(results, "interactive.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)

scene_name = os.path.relpath(scene, os.path.join(os.path.dirname(__file__), "..", ".."))
commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                        text=True, cwd=os.path.dirname(os.path.abspath(__file__))).stdout.strip()
md = [f"# Re-planning: a plan in milliseconds\n",
      "What a re-plan costs once a response basis is built, against solving each plan, how exact "
      "the basis's combination is, and how fast the browser page redraws the face.\n",
      f"Reproduce: `{command.strip()}` (about 7 min).\n",
      f"Measured at commit {commit} on {os.cpu_count()} cores, one thread.\n",
      f"Scene: "
      f"`{scene_name}` ({n_tets} tetrahedra, its dense skin of {rows[0]['skin_points']} points "
      f"mapped by shape functions), swept over {PLANS} plans of the mandible's set-back "
      f"(translation y from -2 to -10 mm; the chin as planned). Two processes: one solves every "
      f"plan after one setup, the other builds each model's response basis (12 solves per moved "
      f"segment: 2 segments, 24 solves) and computes every plan as its combination. Medians over "
      f"the plans.\n",
      "| model | setup s | one solve s | basis s | basis / solve per segment | basis / (setup + solve) "
      "per segment | basis MB | combination ms | skin step B ms | re-plan ms | re-plan speed-up | "
      "max difference mm (of max u mm) |",
      "|---|---|---|---|---|---|---|---|---|---|---|---|"]
for r in rows:
    md.append(f"| {r['model']} | {r['setup_s']:.3g} | {r['solve_s']:.3g} | {r['basis_s']:.3g} | "
              f"{r['basis_s'] / r['solve_s'] / MOVED:.3g} | "
              f"{r['basis_s'] / (r['setup_s'] + r['solve_s']) / MOVED:.3g} | {r['basis_memory_mb']:.3g} | "
              f"{r['combination_ms']:.3g} | {r['skin_step_b_ms']:.3g} | {r['replan_ms']:.3g} | "
              f"{(r['solve_s'] * 1e3 + r['skin_step_b_ms']) / r['replan_ms']:.3g} | "
              f"{r['max_difference_mm']:.2g} ({r['max_displacement_mm']:.3g}) |")
md.append("")
md.append("*one solve*: a plan's solve after the model's setup (for linear fem with its ML "
          "preconditioner built once). *basis / solve per segment*: the basis's cost in such "
          "solves, per moved segment (12 solves each); *basis / (setup + solve) per segment*: in "
          "whole solves of a plan from scratch, as a user without the basis pays them (target: "
          "under 10 per moved segment). *re-plan*: the combination of the "
          "responses plus mapping the displacement onto the skin (target: under 5 ms). *re-plan "
          "speed-up*: (one solve + step B) / re-plan. *max difference*: between the two runs' "
          "displacements over every vertex and plan; linear fem's is its CG tolerance's, the mass "
          "tensor model's that of its stop criterion (each response stops on its own).")
md.append(f"\nCSV: [interactive.csv](interactive.csv). Whole processes: {runs['never']['wall']:.1f} s "
          f"solving every plan, {runs['always']['wall']:.1f} s with the bases (both include the "
          f"scene's set-up and the skin's step A).\n")
md.append("![re-plan times](interactive.png)\n")
md.append("## What the numbers show\n")
for r in rows:
    per_solve = r['basis_s'] / r['solve_s']
    md.append(f"- {r['model']}: a re-plan costs {r['replan_ms']:.3g} ms, "
              f"{(r['solve_s'] * 1e3 + r['skin_step_b_ms']) / r['replan_ms']:.3g}x less than a solve "
              f"after setup; the basis ({r['basis_s']:.3g} s, {r['basis_memory_mb']:.3g} MB) pays for "
              f"itself after about {per_solve:.0f} plans; the combination differs from the solve by "
              f"{r['max_difference_mm']:.2g} mm.")
md.append("- Linear FEM's combination is exact to its CG tolerance; the mass tensor model's is as "
          "precise as its stop, since each response stops on the model's own criterion.\n")
md.append(f"## In the browser\n\n`softface serve` on the same scene, its page in headless Chromium "
          f"(Debian's, software WebGL: SwiftShader, 1100 x 700 pixels), driven by "
          f"`web/test/serve_browser.mjs`: {page['replans']} moves of the mandible's sliders, each "
          f"waited for until the frame with the new face was drawn. Slider to redrawn face: median "
          f"**{page['median_latency_ms']:.0f} ms**, largest {page['max_latency_ms']:.0f} ms "
          f"(target: a median under 50 ms). The time is the page's: from the slider's input event "
          f"to the animation frame after the face's {rows[0]['skin_points']} points were updated "
          f"and drawn (the server's part is the re-plan above).\n")
md.append("![the page](interactive_page.png)\n")
md.append("## Limits\n")
md.append("- One scene and one sweep of plans; the browser's time is software WebGL in headless "
          "Chromium, not a graphics card.\n")
with open(os.path.join(results, "interactive.md"), "w") as f:
    f.write("\n".join(md))

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
fig, ax = plt.subplots(figsize=(7, 3.5))
labels = [r["model"] for r in rows]
x = range(len(rows))
ax.bar([i - 0.2 for i in x], [1e3 * r["solve_s"] + r["skin_step_b_ms"] for r in rows], 0.4,
       label="solve + step B")
ax.bar([i + 0.2 for i in x], [r["replan_ms"] for r in rows], 0.4,
       label="combination + step B")
ax.set_yscale("log")
ax.set_xticks(list(x))
ax.set_xticklabels(labels)
ax.set_ylabel("ms per plan")
ax.axhline(5, color="gray", ls="--", lw=0.8)
ax.legend()
ax.set_title(f"Re-plan on {n_tets} tetrahedra, one thread")
fig.tight_layout()
fig.savefig(os.path.join(results, "interactive.png"), dpi=120)
print("\n".join(md))
