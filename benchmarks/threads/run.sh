#!/usr/bin/env bash
# One thread against two: every model on the ~491k-tetrahedron gmsh cube of
# benchmarks/peers/make_mesh.py with Models/Threads = 1 and 2, interleaved, 3 repetitions; checks
# that the answers agree and writes doc/results/threads.{md,csv,png}.
#
#   benchmarks/threads/run.sh [--quick]   (--quick: the ~35k mesh once; results in the work dir)
#
# Env: SOFTFACE (default build/softface), THREADS_WORK (default /tmp/softface-threads). Needs
# Debian's /usr/bin/python3 with python3-gmsh and python3-matplotlib.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
softface=${SOFTFACE:-$root/build/softface}
work=${THREADS_WORK:-/tmp/softface-threads}
results=$root/doc/results
[ -x "$softface" ] || { echo "no softface binary at $softface (build it or set SOFTFACE)"; exit 1; }
# The Debian packages, as ./run.sh installs them.
source "$root/scripts/bootstrap.sh"
softface_ensure_packages python3-gmsh python3-matplotlib
h=1.68
quick=()
if [ "${1:-}" = "--quick" ]; then quick=(--quick); h=4.3; results=$work/quick-results; fi
mkdir -p "$work" "$results"
mesh=$work/cube_h$h.msh
[ -s "$mesh" ] || /usr/bin/python3 "$root/benchmarks/peers/make_mesh.py" "$h" "$mesh"
/usr/bin/python3 "$here/run.py" "$(realpath "$softface")" "$mesh" "$work" "$results" \
  "benchmarks/threads/run.sh $*" "${quick[@]}"
