#!/usr/bin/env bash
# Groups of MPI ranks whose members hold none of the scene's cells: linear FEM ('cg amg')
# on the generated cube of about 2M tetrahedra, serially and on two ranks with 'Models/Mesh group
# size' 1 (every rank holds the scene) and 2 (rank 1 holds its part only), the two interleaved,
# 3 repetitions, one thread per rank; peak memory of the largest and the smallest rank, the
# phases and the whole process; checks that the answers agree and writes
# doc/results/scaling_groups.{md,csv,png} (about 5 minutes). With --point-models the mass
# tensor and mass spring models instead (doc/results/scaling_groups_points.*).
#
#   benchmarks/scaling/groups.sh [--quick] [--point-models]
#   (--quick: 30k tetrahedra once, results in the work dir)
#
# Env: SOFTFACE (default build/softface), SCALING_WORK (default /tmp/softface-scaling). Needs
# mpiexec and Debian's /usr/bin/python3 with python3-numpy and python3-matplotlib. Run it on an
# otherwise idle machine.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
work=${SCALING_WORK:-/tmp/softface-scaling}/groups
results=$root/doc/results
name="group scaling"
source "$here/prelude.sh"
options=()
for option in "$@"; do
  case "$option" in
    --quick) options+=(--quick); results=$work/quick-results ;;
    --point-models) options+=(--point-models) ;;
    *) echo "group scaling: unknown option '$option' (use --quick, --point-models)"; exit 2 ;;
  esac
done
mkdir -p "$work" "$results"
/usr/bin/python3 "$here/groups.py" "$(realpath "$softface")" "$mpiexec" "$work" "$results" \
  "benchmarks/scaling/groups.sh${*:+ $*}" "${options[@]}"
