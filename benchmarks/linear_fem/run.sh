#!/usr/bin/env bash
# Linear FEM on the paper's cube at about 30k, 100k, 200k and 500k tetrahedra
# with each linear solver, one softface process per case (so that the peak
# memory is the case's own). Writes doc/results/linear_fem.{md,csv,png}.
#
#   benchmarks/linear_fem/run.sh [--quick]     (--quick: 30k and 100k only)
#
# Needs a built softface (./run.sh or ./test.sh builds it) and, for the plot,
# /usr/bin/python3 with Debian's python3-matplotlib.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
softface=${SOFTFACE:-$root/build/softface}
results=$root/doc/results
work=$root/build/benchmarks/linear_fem
[ -x "$softface" ] || { echo "build softface first (./run.sh or ./test.sh)"; exit 1; }

sizes="30000 100000 200000 500000"
# --quick writes its (coarse) results beside its runs, not over doc/results.
[ "${1:-}" = "--quick" ] && sizes="30000 100000" && results=$work/quick-results
solvers=("cg amg" "direct" "gmres jacobi")

mkdir -p "$work" "$results"
# One line per case: the solver and its output folder (report.py reads its summary.csv).
cases=$work/cases.txt
: > "$cases"
n_cases=$(( $(echo $sizes | wc -w) * ${#solvers[@]} ))
i=0
start=$(date +%s)
for tets in $sizes; do
  for solver in "${solvers[@]}"; do
    i=$((i + 1))
    tag="${tets}_${solver// /_}"
    sed -e "s/@TETS@/$tets/" -e "s/@SOLVER@/$solver/" -e "s|@OUTPUT@|$work/$tag|" \
      "$here/cube.prm.in" > "$work/$tag.prm"
    echo "[$i/$n_cases] $tets tetrahedra, $solver (elapsed $(( $(date +%s) - start )) s)"
    "$softface" "$work/$tag.prm" > "$work/$tag.log"
    printf '%s\t%s\n' "$solver" "$work/$tag" >> "$cases"
  done
done

/usr/bin/python3 "$here/report.py" "$cases" "$results" "$0 $*"
echo "wrote $results/linear_fem.md, linear_fem.csv, linear_fem.png"
