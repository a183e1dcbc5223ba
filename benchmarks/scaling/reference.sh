#!/usr/bin/env bash
# The quadratic reference model on one MPI rank and on two (issue 20): peak memory per rank and
# time on the generated cube of about 100k and 300k tetrahedra (the reference's quadratic layout
# has about 8 times the DoFs of the shared one), one thread per rank, once each; checks that the
# two answers agree and writes doc/results/scaling_reference.{md,csv,png}.
#
#   benchmarks/scaling/reference.sh [--quick]      (--quick: 20k tetrahedra, results in the work dir)
#
# Env: SOFTFACE (default build/softface), SCALING_WORK (default /tmp/softface-scaling). About
# 11 minutes; needs mpiexec and Debian's /usr/bin/python3 with python3-numpy and
# python3-matplotlib. Run it on an otherwise idle machine.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
work=${SCALING_WORK:-/tmp/softface-scaling}/reference
results=$root/doc/results
name="reference scaling"
source "$here/prelude.sh"
quick=()
for option in "$@"; do
  case "$option" in
    --quick) quick+=(--quick); results=$work/quick-results ;;
    *) echo "reference scaling: unknown option '$option' (use --quick)"; exit 2 ;;
  esac
done
mkdir -p "$work" "$results"
/usr/bin/python3 "$here/reference.py" "$(realpath "$softface")" "$mpiexec" "$work" "$results" \
  "benchmarks/scaling/reference.sh $*" "${quick[@]}"
