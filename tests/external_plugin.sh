#!/usr/bin/env bash
# A plugin from outside the tree: install softface from BUILD_DIR into
# WORK_DIR/install, build tests/external_plugin/ against it (its CMakeLists.txt
# is what a user writes), run the installed softface on a scene that loads the
# plugin's library, and compare what the plugin wrote with
# tests/external_plugin/expected.output: linear FEM's and the mass tensor model's mean
# and largest free motion, which agree to the model's stop threshold.
# Usage: external_plugin.sh BUILD_DIR WORK_DIR NUMDIFF
set -euo pipefail
source_dir=$(cd "$(dirname "$0")" && pwd)
build=$1
work=$2
numdiff=$3
rm -rf "$work"
mkdir -p "$work"
step()
{
  local log=$1
  shift
  "$@" > "$work/$log" 2>&1 || {
    cat "$work/$log"
    echo "external_plugin: '$*' failed (log above)"
    exit 1
  }
}
step install.log cmake --install "$build" --prefix "$work/install"
step configure.log cmake -S "$source_dir/external_plugin" -B "$work/plugin" \
  -DCMAKE_BUILD_TYPE=Release -Dsoftface_DIR="$work/install/lib/cmake/softface"
step build.log cmake --build "$work/plugin"
cp "$source_dir/external_plugin/free_motion.prm" "$work/plugin/"
cd "$work/plugin"
step run.log "$work/install/bin/softface" free_motion.prm
grep -q "free_motion.csv" "$work/run.log" || {
  cat "$work/run.log"
  echo "external_plugin: the closing line does not list free_motion.csv"
  exit 1
}
# The figures, rounded to what the stop threshold keeps stable.
/usr/bin/python3 - output/free_motion.csv > result <<'PYTHON'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for row in rows:
    print(f"{row['model']}: mean {float(row['mean_mm']):.5f} mm, "
          f"largest {float(row['max_mm']):.5f} mm")
PYTHON
cat result
"$numdiff" -q -a 2e-5 -r 1e-6 result "$source_dir/external_plugin/expected.output" > /dev/null || {
  diff result "$source_dir/external_plugin/expected.output" || true
  echo "external_plugin: the figures differ from tests/external_plugin/expected.output"
  exit 1
}
