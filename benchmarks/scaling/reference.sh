#!/usr/bin/env bash
# The quadratic reference model on one MPI rank and on two, the two also in a group of two whose
# member holds none of the scene's cells: peak memory per rank and time on the
# generated cube of about 100k and 300k tetrahedra (the reference's quadratic layout has about 8
# times the DoFs of the shared one), one thread per rank, once each; checks that the answers agree
# and writes doc/results/scaling_reference.{md,csv,png}.
#
#   benchmarks/scaling/reference.sh [--quick] [--sizes N,N,...]
#     --quick: 20k tetrahedra, results in the work dir
#     --sizes: the cube's requested tetrahedra (default 100000,300000); 100000,300000,600000 adds
#              about the largest one rank holds in 24 GB (its serial run peaks near 17 GB; over
#              an hour in all, and the two ranks at 600k need about 17 GB together)
#
# Env: SOFTFACE (default build/softface), SCALING_WORK (default /tmp/softface-scaling). About
# 16 minutes; needs mpiexec and Debian's /usr/bin/python3 with python3-numpy and
# python3-matplotlib. Run it on an otherwise idle machine.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
work=${SCALING_WORK:-/tmp/softface-scaling}/reference
results=$root/doc/results
name="reference scaling"
source "$here/prelude.sh"
options=()
arguments="$*"
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) options+=(--quick); results=$work/quick-results ;;
    --sizes)
      [[ "${2:-}" =~ ^[0-9]+(,[0-9]+)*$ ]] ||
        { echo "reference scaling: --sizes needs a list such as 100000,300000"; exit 2; }
      options+=(--sizes "$2"); shift ;;
    *) echo "reference scaling: unknown option '$1' (use --quick or --sizes N,N,...)"; exit 2 ;;
  esac
  shift
done
mkdir -p "$work" "$results"
/usr/bin/python3 "$here/reference.py" "$(realpath "$softface")" "$mpiexec" "$work" "$results" \
  "benchmarks/scaling/reference.sh $arguments" "${options[@]}"
