#!/usr/bin/python3
"""Compare two runs of the accuracy study, row by row, at the precision the
report prints (3 significant digits): which figures reproduced and which did
not. A re-run must reproduce every figure or explain the change.

usage: compare.py OLD.csv NEW.csv [--scenes KEY,...]

OLD.csv and NEW.csv are accuracy_vs_time.csv files (for example
`git show REV:doc/results/accuracy_vs_time.csv > old.csv`). Rows are matched
by scene, model, setting and mesh size. For each scene it prints how many rows
reproduced every figure, then each row that did not, with the figures that
changed (old -> new). Times are compared apart: they depend on the machine's
load, so the line per scene gives the median ratio new / old of setup + solve.
"""

import argparse
import csv
import statistics
import sys

FIGURES = ["n_vertices", "iterations", "err_median", "err_p90", "err_p95", "err_max", "status"]


def printed(text):
    """A value as the report prints it: numbers to 3 significant digits."""
    try:
        return f"{float(text):.3g}"
    except ValueError:
        return text


def key(row):
    return (row["scene"], row["model"], row["setting"], row["n_tets"])


def read(path, scenes):
    with open(path, newline="") as f:
        rows = [r for r in csv.DictReader(f) if not scenes or r["scene"] in scenes]
    return {key(r): r for r in rows}


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("--scenes", default="", help="comma-separated scene keys (default all)")
    args = parser.parse_args()
    scenes = [s for s in args.scenes.split(",") if s]
    old, new = read(args.old, scenes), read(args.new, scenes)
    if not new:
        sys.exit(f"{args.new}: no rows" + (f" of {args.scenes}" if scenes else ""))

    for scene in dict.fromkeys(k[0] for k in list(old) + list(new)):
        keys = [k for k in new if k[0] == scene]
        only_old = [k for k in old if k[0] == scene and k not in new]
        same, changed, ratios = 0, [], []
        for k in keys:
            if k not in old:
                changed.append((k, ["new row"]))
                continue
            o, n = old[k], new[k]
            diffs = [f"{f} {printed(o[f])} -> {printed(n[f])}" for f in FIGURES
                     if printed(o.get(f, "")) != printed(n.get(f, ""))]
            try:
                ratios.append(float(n["total_s"]) / float(o["total_s"]))
            except (ValueError, ZeroDivisionError):
                pass
            if diffs:
                changed.append((k, diffs))
            else:
                same += 1
        time = (f"; setup + solve new / old: median {statistics.median(ratios):.2f} "
                f"(min {min(ratios):.2f}, max {max(ratios):.2f})" if ratios else "")
        print(f"{scene}: {same} of {len(keys)} rows reproduced every figure{time}")
        for k, diffs in changed:
            print(f"  {k[1]}, {k[3]} tets, {k[2]}: " + "; ".join(diffs))
        for k in only_old:
            print(f"  {k[1]}, {k[3]} tets, {k[2]}: not in the new run")


if __name__ == "__main__":
    main()
