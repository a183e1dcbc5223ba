#!/usr/bin/python3
"""Print the cases' result.json files as one markdown table.

    /usr/bin/python3 table.py [CASE_DIR ...]      (default: /tmp/nl/<name> for cases/*.json)
"""
import glob
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def fmt_load(x):
    return "-" if x is None else ("%.1f%%" % (100 * x))


def main(argv):
    dirs = argv[1:] or [os.path.join("/tmp/nl", os.path.splitext(os.path.basename(p))[0])
                        for p in sorted(glob.glob(os.path.join(HERE, "cases", "*.json")))]
    print("| case | tets | max prescribed u (mm) | CalculiX load / last load uninverted | "
          "cut-backs | iterations | time (s) | min det F |")
    print("|---|---|---|---|---|---|---|---|")
    rows = []
    for d in dirs:
        path = os.path.join(d, "result.json")
        if not os.path.exists(path):
            continue
        r = json.load(open(path))
        c = r.get("calculix", {})
        print("| %s | %d | %.2f | %s / %s | %s | %s | %s | %s |" % (
            r["case"]["name"], r["n_tets"], r["max_prescribed_displacement_mm"],
            fmt_load(c.get("load_reached")), fmt_load(c.get("last_load_without_inversion")),
            c.get("cutbacks", "-"), c.get("iterations", "-"), c.get("wall_s", "-"),
            "%.3f (%d inverted)" % (c["min_volume_ratio"], c["n_inverted"])
            if "min_volume_ratio" in c else "-"))
        rows.append(r)
    print()
    print("| case | softface model | load reached | load steps | cut-backs | Newton iterations "
          "(total / converged steps) | wall s | min det F | where it stopped |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        for v, s in r.get("softface", {}).items():
            print("| %s | %s | %s | %d | %d | %s / %d | %.1f | %s | %s |" % (
                r["case"]["name"], v, fmt_load(s["load_reached"]), s["load_steps"],
                s["cutbacks"], s.get("newton_iterations", "-"),
                s["newton_iterations_converged"], s["wall_s"],
                "%.3f" % s["min_volume_ratio"] if "min_volume_ratio" in s else "-",
                s.get("reason", "")))


if __name__ == "__main__":
    main(sys.argv)
