#!/usr/bin/python3
"""The same scene's mesh on an idle and on a busy machine.

Runs the mesh stage of a patient scene (`softface mesh SCENE`: bone parts and
CGAL Mesh_3 with sliver perturbation and exudation) under five conditions, one
after the other: the machine idle (twice), three and seven processes spinning
beside it, and beside a compile of two jobs. The phantom CT and its
segmentation are made once and reused; only the mesh stage runs again. Each
run's mesh.vtu is compared by its md5 sum with the first idle run's.

  /usr/bin/python3 benchmarks/busy_machine/run.py
  /usr/bin/python3 benchmarks/busy_machine/run.py --sliver-bound 12 \\
      --sliver-bound 20 --softface "new=build/softface" \\
      --softface "old=/path/to/other/softface"

Each --sliver-bound (Scene/Patient/Mesh/Sliver bound; default: the scene's
own) is a case: a higher bound makes the optimisation run longer. Several
--softface NAME=PATH are run side by side (each condition for each binary
before the next condition). Writes doc/results/busy_machine.md (+ .csv and
.png; --name for another name): the table, the plot and a count of meshes per
case; a section headed "## What the numbers show" in the page, written by
hand, is kept. Needs Debian's python3-matplotlib and g++ (for the compile).
"""

import argparse
import csv
import hashlib
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

# A translation unit heavy enough to keep a compiler busy for a while (CGAL's
# 3D triangulations, header-only).
COMPILE_UNIT = r"""
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Regular_triangulation_3.h>
#include <vector>
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
int main()
{
  std::vector<K::Point_3> p{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  CGAL::Delaunay_triangulation_3<K> d(p.begin(), p.end());
  CGAL::Regular_triangulation_3<K> r;
  return int(d.number_of_vertices() + r.number_of_vertices());
}
"""

# The heading of the page's hand-written reading, kept when it is re-made.
NOTES = "## What the numbers show"

CONDITIONS = [("idle", "idle"), ("idle, again", "idle"),
              ("3 busy processes", "spin3"), ("7 busy processes", "spin7"),
              ("beside a two-job compile", "compile")]


class Load:
    """Processes that keep the cores busy while a run lasts."""

    def __init__(self, kind, scratch):
        self.kind, self.scratch, self.processes = kind, scratch, []

    def __enter__(self):
        if self.kind.startswith("spin"):
            for _ in range(int(self.kind[4:])):
                self.processes.append(subprocess.Popen(
                    [sys.executable, "-c", "while True: pass"]))
        elif self.kind == "compile":
            source = os.path.join(self.scratch, "load.cc")
            with open(source, "w") as f:
                f.write(COMPILE_UNIT)
            loop = ("while true; do g++ -std=c++17 -O2 -c %s -o /dev/null "
                    "2> /dev/null; done" % source)
            for _ in range(2):
                self.processes.append(subprocess.Popen(
                    ["bash", "-c", loop], start_new_session=True))
        if self.processes:
            time.sleep(1.)
        return self

    def __exit__(self, *args):
        for p in self.processes:
            try:
                if self.kind == "compile":
                    os.killpg(p.pid, 9)
                else:
                    p.kill()
            except ProcessLookupError:
                pass
            p.wait()


def figures(text):
    """The figures softface mesh prints, one '  name: value' a line."""
    out = {}
    for line in text.splitlines():
        if line.startswith("  ") and ": " in line:
            k, v = line.strip().split(": ", 1)
            out[k] = v
    return out


def md5(path):
    with open(path, "rb") as f:
        return hashlib.md5(f.read()).hexdigest()


def bound_label(bound):
    return "scene's" if bound is None else f"{bound:g}"


def prepare(binary, scene, bound, folder):
    """A scene that includes SCENE with its own work folder (and sliver
    bound), its CT and labels made once."""
    os.makedirs(folder)
    mesh = ("" if bound is None else
            f"    subsection Mesh\n      set Sliver bound = {bound:g}\n"
            "    end\n")
    prm = os.path.join(folder, "scene.prm")
    with open(prm, "w") as f:
        f.write(f"include {scene}\nsubsection Scene\n  subsection Patient\n"
                f"    set Work directory = {folder}\n{mesh}  end\nend\n")
    subprocess.run([binary, "segment", prm], check=True,
                   stdout=subprocess.DEVNULL)
    return prm


def run_mesh(binary, prm, kind, scratch):
    """The mesh stage alone under the load KIND: its figures and md5."""
    folder = os.path.dirname(prm)
    stamp = os.path.join(folder, "mesh.stamp")
    if os.path.exists(stamp):
        os.remove(stamp)
    with Load(kind, scratch):
        run = subprocess.run([binary, "mesh", prm], text=True,
                             capture_output=True)
    f = figures(run.stdout)
    ok = run.returncode == 0
    return {
        "exit code": run.returncode,
        "mesh stage s": f.get("mesh s", ""),
        "tetrahedra": f.get("tetrahedra", ""),
        "sliver perturbation": f.get("sliver perturbation", ""),
        "sliver exudation": f.get("sliver exudation", ""),
        "mesh.vtu md5": md5(os.path.join(folder, "mesh.vtu")) if ok else "",
        "error": "" if ok else run.stderr.strip()[-300:],
    }


def main():
    a = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    a.add_argument("--scene", default="prm/patient.prm")
    a.add_argument("--softface", action="append",
                   help="NAME=PATH of a softface binary (default: "
                   "'softface=build/softface'); repeat to compare")
    a.add_argument("--sliver-bound", type=float, action="append",
                   help="Scene/Patient/Mesh/Sliver bound of a case (degrees; "
                   "default: the scene's); repeat for several cases")
    a.add_argument("--out", default="doc/results")
    a.add_argument("--name", default="busy_machine")
    args = a.parse_args()
    os.chdir(ROOT)
    binaries = []
    for item in args.softface or ["softface=build/softface"]:
        name, _, path = item.partition("=")
        if not os.access(path, os.X_OK):
            sys.exit(f"busy_machine: {path} is not an executable softface")
        binaries.append((name, os.path.abspath(path)))
    if shutil.which("g++") is None:
        sys.exit("busy_machine: needs g++ for the compile load")
    try:
        import matplotlib  # noqa: F401 (the plot, after the runs)
    except ImportError:
        sys.exit("busy_machine: needs python3-matplotlib (apt-get install -y "
                 "python3-matplotlib)")
    bounds = args.sliver_bound or [None]
    scratch = tempfile.mkdtemp(prefix="softface_busy_")
    scene = os.path.abspath(args.scene)

    cases = []
    for bound in bounds:
        for name, binary in binaries:
            folder = os.path.join(scratch, f"case_{len(cases)}")
            cases.append((bound, name, binary,
                          prepare(binary, scene, bound, folder)))
    rows = []
    for bound in bounds:
        for label, kind in CONDITIONS:
            for b, name, binary, prm in cases:
                if b != bound:
                    continue
                print(f"busy_machine: sliver bound {bound_label(bound)}, "
                      f"{name}, {label}", flush=True)
                row = {"sliver bound": bound_label(bound), "softface": name,
                       "condition": label}
                row.update(run_mesh(binary, prm, kind, scratch))
                rows.append(row)
    for bound, name, _, _ in cases:
        mine = [r for r in rows if r["softface"] == name and
                r["sliver bound"] == bound_label(bound)]
        for r in mine:
            r["same mesh as the first idle run"] = (
                "yes" if r["mesh.vtu md5"] and
                r["mesh.vtu md5"] == mine[0]["mesh.vtu md5"] else "no")
    write(rows, args, binaries, bounds)
    shutil.rmtree(scratch, ignore_errors=True)


def write(rows, args, binaries, bounds):
    os.makedirs(args.out, exist_ok=True)
    base = os.path.join(args.out, args.name)
    with open(base + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    cpu = platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(l.split(":", 1)[1].strip() for l in f
                       if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    command = " ".join(
        ["/usr/bin/python3 benchmarks/busy_machine/run.py",
         f"--scene {args.scene}"] +
        [f"--sliver-bound {b:g}" for b in bounds if b is not None] +
        [f"--softface '{n}={os.path.relpath(p)}'" for n, p in binaries])
    cols = ["sliver bound", "softface", "condition", "mesh stage s",
            "tetrahedra", "sliver perturbation", "sliver exudation",
            "mesh.vtu md5", "same mesh as the first idle run"]
    md = ["# The same scene's mesh on an idle and on a busy machine", "",
          "Whether a patient scene makes the same mesh, bit for bit, on an idle "
          "machine and on a busy one.", "",
          f"Reproduce: `{command}`.", "",
          f"Measured at commit {commit} on {cpu}, {os.cpu_count()} cores; "
          "each binary of the table is named by the commit it was built from.",
          "",
          f"The mesh stage of `{args.scene}` (`softface mesh`: bone parts, "
          "CGAL Mesh_3, sliver perturbation and exudation) run under five "
          "conditions one after the other, its `mesh.vtu` compared by md5 "
          "sum with the first idle run's of the same case. The CT and "
          "labels are made once per case and reused. *mesh stage s* is "
          f"wall-clock time; the busy conditions share the {os.cpu_count()} "
          "cores with the load.", "",
          "| " + " | ".join(cols) + " |",
          "|" + "---|" * len(cols)]
    for r in rows:
        md.append("| " + " | ".join(
            str(r[c])[:10] if c == "mesh.vtu md5" else str(r[c])
            for c in cols) + " |")
    md += ["", f"![mesh stage time per condition]({args.name}.png)", "",
           "Runs that made the first idle run's mesh:", ""]
    for bound in bounds:
        for name, _ in binaries:
            mine = [r for r in rows if r["softface"] == name and
                    r["sliver bound"] == bound_label(bound)]
            same = sum(r["same mesh as the first idle run"] == "yes"
                       for r in mine)
            counts = sorted({r["tetrahedra"] for r in mine if r["tetrahedra"]})
            failed = sum(r["exit code"] != 0 for r in mine)
            md.append(f"- sliver bound {bound_label(bound)}, {name}: {same} "
                      f"of {len(mine)} runs made the first idle run's mesh "
                      f"(tetrahedra: {', '.join(counts) or 'none'}"
                      + (f"; {failed} ended with an error" if failed else "")
                      + ").")
    errors = [r for r in rows if r["error"]]
    if errors:
        md += ["", "Errors:", ""]
        md += [f"- sliver bound {r['sliver bound']}, {r['softface']}, "
               f"{r['condition']}: {r['error']}" for r in errors]
    # What the numbers show, written by hand below its heading, stays.
    notes = ""
    if os.path.exists(base + ".md"):
        with open(base + ".md") as f:
            old = f.read()
        if NOTES in old:
            notes = old[old.index(NOTES):]
    with open(base + ".md", "w") as f:
        f.write("\n".join(md) + "\n" + ("\n" + notes if notes else ""))
    plot(rows, base + ".png")
    print("busy_machine: wrote", base + ".md,", base + ".csv and",
          base + ".png")


def plot(rows, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    groups = list(dict.fromkeys((r["sliver bound"], r["softface"])
                                for r in rows))
    labels = [c for c, _ in CONDITIONS]
    fig, ax = plt.subplots(figsize=(9, 4))
    width = 0.8 / len(groups)
    for i, (bound, name) in enumerate(groups):
        rs = [r for r in rows if (r["sliver bound"], r["softface"]) ==
              (bound, name)]
        x = [k + i * width for k in range(len(rs))]
        t = [float(r["mesh stage s"] or 0) for r in rs]
        bars = ax.bar(x, t, width, label=f"{name}, sliver bound {bound}")
        for b, r in zip(bars, rs):
            same = r["same mesh as the first idle run"] == "yes"
            ax.text(b.get_x() + b.get_width() / 2, b.get_height(),
                    "same" if same else "other", ha="center", va="bottom",
                    fontsize=7, color="black" if same else "red",
                    rotation=90)
    top = max(float(r["mesh stage s"] or 0) for r in rows)
    ax.set_ylim(0, 1.2 * top)
    ax.set_xticks([k + 0.4 - width / 2 for k in range(len(labels))])
    ax.set_xticklabels(labels, fontsize=8)
    ax.set_ylabel("mesh stage (s, wall clock)")
    ax.set_title("Mesh stage time per condition; above each bar, whether its "
                 "mesh equals the first idle run's", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=120)


if __name__ == "__main__":
    main()
