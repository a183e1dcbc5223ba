#!/usr/bin/env bash
# softface `linear fem` (cg amg) and `nonlinear fem` (St. Venant-Kirchhoff) against FEniCSx (dolfinx)
# and CalculiX on the same gmsh cube meshes (~35k, ~105k, ~491k tetrahedra; CalculiX on the first
# two only), 3 interleaved repetitions, on one thread each and then on all cores. Checks that the
# displacements agree (fails if a peer differs by > 1e-4 mm) and writes
# doc/results/peers.{md,csv,png}. See README.md.
#
#   benchmarks/peers/run.sh [--quick] [--passes linear,linear-all,svk,svk-all] [--reps N]
#   (--quick: the 35k mesh once; results in the work dir)
#
# Env: SOFTFACE (default build/softface), PEERS_WORK (default /tmp/peerbench), LD_LIBRARY_PATH is
# passed through. Needs Debian's /usr/bin/python3 with python3-dolfinx, gmsh, scipy, matplotlib and
# calculix-ccx.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
softface=${SOFTFACE:-$root/build/softface}
work=${PEERS_WORK:-/tmp/peerbench}
results=$root/doc/results
[ -x "$softface" ] || { echo "no softface binary at $softface (build it or set SOFTFACE)"; exit 1; }
missing=()
command -v ccx > /dev/null || missing+=(calculix-ccx)
/usr/bin/python3 -c "import dolfinx" 2> /dev/null || missing+=(python3-dolfinx)
/usr/bin/python3 -c "import gmsh, scipy, matplotlib" 2> /dev/null ||
  missing+=(python3-gmsh python3-scipy python3-matplotlib)
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" = 0 ]; then
    apt-get install -y -qq "${missing[@]}"
  else
    echo "benchmarks/peers needs: sudo apt-get install ${missing[*]}"
    exit 1
  fi
fi

quick=()
more=()   # other options go to run.py (--passes, --reps)
for a in "$@"; do
  if [ "$a" = "--quick" ]; then quick=(--quick); results=$work/quick-results; else more+=("$a"); fi
done
mkdir -p "$work" "$results"

# The meshes (gmsh 4.1 ASCII), made once.
for h in 4.3 2.88 1.68; do
  [ -n "${quick[*]}" ] && [ "$h" != 4.3 ] && continue
  m=$work/cube_h$h.msh
  [ -s "$m" ] || /usr/bin/python3 "$here/make_mesh.py" "$h" "$m"
done

/usr/bin/python3 "$here/run.py" --softface "$(realpath "$softface")" --work "$work" \
  --results "$results" --command "benchmarks/peers/run.sh $*" "${quick[@]}" "${more[@]}"
echo "wrote $results/peers.md, peers.csv, peers.png"

# Cell and DoF order: every model on the gmsh cubes against the generated cube of the same size.
/usr/bin/python3 "$here/mesh_order.py" "$(realpath "$softface")" "$work" "$work/order" "$results" \
  "benchmarks/peers/run.sh $*" "${quick[@]}"
