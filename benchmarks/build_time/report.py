#!/usr/bin/env python3
"""The build-time table, CSV and plot (benchmarks/build_time/run.sh)."""
import csv
import os
import platform
import subprocess
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LABELS = {"plain": "-g, no precompiled headers",
          "default": "default: no -g, precompiled headers"}


def main(csv_file, results):
    rows = list(csv.DictReader(open(csv_file)))
    by = {r["configuration"]: r for r in rows}
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    cpu = "unknown CPU"
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    machine = f"{cpu}, {os.cpu_count()} cores, {platform.system()}"
    os.makedirs(results, exist_ok=True)
    with open(os.path.join(results, "build_time.csv"), "w") as f:
        f.write(open(csv_file).read())

    lines = ["# Build time: softface and its tests from nothing", "",
             "How long a newcomer waits for softface, its libraries and its "
             "test drivers built from nothing, with and without debug "
             "information and precompiled headers.", "",
             "Reproduce: `benchmarks/build_time/run.sh` (about 45 min on 2 "
             "cores: two builds from nothing).", "",
             "Measured at commit " + commit + " on " + machine + ".", "",
             "The same commit is built twice, one after the other, without "
             "ccache, with `cmake --build -j2` (the executable, the core and "
             "patient libraries, both test drivers).", "",
             "| configuration | wall s | user s | system s | build folder MB |",
             "|---|---|---|---|---|"]
    for name in ("plain", "default"):
        r = by[name]
        lines.append(f"| {LABELS[name]} | {float(r['wall_s']):.0f} | "
                     f"{float(r['user_s']):.0f} | {float(r['system_s']):.0f} |"
                     f" {r['build_folder_mb']} |")
    p, d = by["plain"], by["default"]
    cpu_p = float(p["user_s"]) + float(p["system_s"])
    cpu_d = float(d["user_s"]) + float(d["system_s"])
    lines += ["", "![build time](build_time.png)", "",
              "## What the numbers show", "",
              f"- The default configuration takes {float(d['wall_s']) / float(p['wall_s']):.2f}"
              f" of the plain one's wall time and {cpu_d / cpu_p:.2f} of its "
              "processor time; its build folder is "
              f"{float(d['build_folder_mb']) / float(p['build_folder_mb']):.2f} "
              "of the size.",
              "- Debug information is back with "
              "`-DSOFTFACE_DEBUG_INFO=ON` (for a debugger or perf's line "
              "numbers), the precompiled headers off with "
              "`-DSOFTFACE_PRECOMPILED_HEADERS=OFF`.", "",
              "## Limits", "",
              "- One build of each configuration on a shared 2-core machine; "
              "the wall times move with what else runs.", ""]
    open(os.path.join(results, "build_time.md"), "w").write("\n".join(lines))

    fig, ax = plt.subplots(figsize=(7, 2.6))
    names = ["plain", "default"]
    user = [float(by[n]["user_s"]) / 60 for n in names]
    system = [float(by[n]["system_s"]) / 60 for n in names]
    wall = [float(by[n]["wall_s"]) / 60 for n in names]
    y = range(len(names))
    ax.barh(y, user, label="user", color="#4477aa")
    ax.barh(y, system, left=user, label="system", color="#ccbb44")
    ax.scatter(wall, y, marker="|", s=400, color="black", label="wall")
    ax.set_yticks(list(y))
    ax.set_yticklabels([LABELS[n] for n in names])
    ax.set_xlabel("minutes (2 cores)")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(results, "build_time.png"), dpi=120)
    print("wrote", os.path.join(results, "build_time.md"))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
