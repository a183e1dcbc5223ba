#!/usr/bin/env bash
# Linear FEM (cg amg), mass tensor and mass spring side by side in one softface
# run per mesh, on the paper's 6 mm cube at about 30k, 100k, 200k and 500k
# tetrahedra. Writes doc/results/cube_models.{md,csv,png}.
#
#   benchmarks/cube_models/run.sh [--quick]     (--quick: 30k and 100k only)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
softface=${SOFTFACE:-$root/build/softface}
results=$root/doc/results
work=$root/build/benchmarks/cube_models
[ -x "$softface" ] || { echo "build softface first (./run.sh or ./test.sh)"; exit 1; }

sizes="30000 100000 200000 500000"
# --quick writes its (coarse) results beside its runs, not over doc/results.
[ "${1:-}" = "--quick" ] && sizes="30000 100000" && results=$work/quick-results

mkdir -p "$work" "$results"
folders=()
n=$(echo $sizes | wc -w); i=0; start=$(date +%s)
for tets in $sizes; do
  i=$((i + 1))
  echo "[$i/$n] $tets tetrahedra (elapsed $(( $(date +%s) - start )) s)"
  sed -e "s/@TETS@/$tets/" -e "s|@OUTPUT@|$work/$tets|" "$here/cube.prm.in" > "$work/$tets.prm"
  "$softface" "$work/$tets.prm" > "$work/$tets.log" 2>&1 || echo "  (a model failed: see $work/$tets.log)"
  folders+=("$work/$tets")
done
# report.py joins the runs' summary.csv (read by column name) into cube_models.csv.
/usr/bin/python3 "$here/report.py" "$results" "$0 $*" "${folders[@]}"
echo "wrote $results/cube_models.md, cube_models.csv, cube_models.png"
