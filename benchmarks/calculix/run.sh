#!/usr/bin/env bash
# softface's nonlinear FEM against CalculiX NLGEOM on the same gmsh meshes and conditions,
# measured side by side: for each case in cases/*.json, make_case.py meshes the cube with gmsh,
# writes and runs the CalculiX input (St. Venant-Kirchhoff: *ELASTIC with NLGEOM, residual and
# correction tolerances 1e-9, 2 OpenMP threads), then softface solves the same problem
# (St. Venant-Kirchhoff, one thread) with each of its nonlinear solvers. Writes
# doc/results/calculix_nonlinear.{md,csv}.
#
#   benchmarks/calculix/run.sh [case.json ...]
#
# Needs Debian's calculix-ccx, gmsh, python3-gmsh and python3-numpy; skips with a message
# when one is missing.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
softface=${SOFTFACE:-$root/build/softface}
results=$root/doc/results
work=$root/build/benchmarks/calculix
[ -x "$softface" ] || { echo "build softface first (./run.sh or ./test.sh)"; exit 1; }
if ! command -v ccx > /dev/null || ! /usr/bin/python3 -c "import gmsh, numpy" 2> /dev/null; then
  echo "skipped: needs the Debian packages calculix-ccx python3-gmsh python3-numpy"
  echo "  (apt-get install calculix-ccx python3-gmsh python3-numpy)"
  exit 0
fi
cases=("$@")
[ ${#cases[@]} -eq 0 ] && cases=("$here"/cases/*.json)
mkdir -p "$work" "$results"
start=$(date +%s)
i=0
for case in "${cases[@]}"; do
  i=$((i + 1))
  name=$(basename "$case" .json)
  out=$work/$name
  echo "[$i/${#cases[@]}] $name: gmsh + CalculiX NLGEOM (elapsed $(( $(date +%s) - start )) s)"
  /usr/bin/python3 "$here/make_case.py" "$case" "$out" > "$out.make_case.log" 2>&1 || {
    echo "  make_case.py failed: see $out.make_case.log"; continue; }
  for solver in "cg amg" "direct"; do
    echo "  softface nonlinear fem, $solver (elapsed $(( $(date +%s) - start )) s)"
    tag=${solver// /_}
    /usr/bin/python3 "$here/softface_scene.py" "$case" "$out/mesh.msh" "$solver" "$out/softface_$tag" \
      > "$out/softface_$tag.prm"
    /usr/bin/time -f "%e" -o "$out/softface_$tag.wall" "$softface" "$out/softface_$tag.prm" \
      > "$out/softface_$tag.log" 2>&1 || true
  done
done
/usr/bin/python3 "$here/report.py" "$work" "$results" "$0 $*" "${cases[@]}"
echo "wrote $results/calculix_nonlinear.md, calculix_nonlinear.csv"
