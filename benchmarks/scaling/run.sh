#!/usr/bin/env bash
# Strong scaling, one MPI rank against two: linear FEM, the mass tensor and the mass
# spring model and nonlinear FEM on the generated cube of about 500k and 2M tetrahedra, serial
# and mpiexec -n 2 interleaved, 3 repetitions, one thread per rank; checks that the answers
# agree and writes doc/results/scaling.{md,csv,png}, with a model of 64 and 1024 ranks built from
# the figures (about 25 min).
#
#   benchmarks/scaling/run.sh [--quick] [--report-only]
#   (--quick: 30k tetrahedra once, results in the work dir; --report-only: the report again from
#   the last run's figures in the work dir)
#
# Env: SOFTFACE (default build/softface), SCALING_WORK (default /tmp/softface-scaling). Needs
# mpiexec (Open MPI, as deal.II's package brings it) and Debian's /usr/bin/python3 with
# python3-numpy and python3-matplotlib. Run it on an otherwise idle machine.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
work=${SCALING_WORK:-/tmp/softface-scaling}
results=$root/doc/results
name=scaling
source "$here/prelude.sh"
quick=()
for option in "$@"; do
  case "$option" in
    --quick) quick+=(--quick); results=$work/quick-results ;;
    --report-only) quick+=(--report-only) ;;
    *) echo "scaling: unknown option '$option' (use --quick, --report-only)"; exit 2 ;;
  esac
done
mkdir -p "$work" "$results"
/usr/bin/python3 "$here/run.py" "$(realpath "$softface")" "$mpiexec" "$work" "$results" \
  "benchmarks/scaling/run.sh $*" "${quick[@]}"
