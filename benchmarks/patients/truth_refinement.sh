#!/usr/bin/env bash
# Is a phantom's post-operative truth converged? (the truth is
# quadratic Neo-Hooke "on a mesh refined to the accuracy benchmark's
# convergence criterion".) Makes one patient's truth (prm/patients/<P>_truth.prm)
# on meshes of 1, 2 and 4 times its target number of tetrahedra, everything
# else equal, and compares their post-operative skins point by point: the
# change from one level to the next against a tenth of the smallest 90%
# distance of a model to that truth (doc/results/patients_skin.csv), the
# criterion of the accuracy benchmark (doc/results/accuracy_vs_time.md).
# Writes doc/results/truth_refinement.md (+ .csv, .png).
#
#   benchmarks/patients/truth_refinement.sh          P4 (the smallest; about
#                                                    20 min on 2 cores)
#   benchmarks/patients/truth_refinement.sh P2       another patient
#   benchmarks/patients/truth_refinement.sh --report-only [P]
#
# Needs a built build/softface and Debian's python3-numpy, python3-matplotlib.
# Each level's run goes to build/benchmarks/truth_refinement/<P>_x<factor>/.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
work=build/benchmarks/truth_refinement
patient=P4
report_only=0
for a in "$@"; do
  case "$a" in
    --report-only) report_only=1 ;;
    P*) patient=$a ;;
    *) echo "usage: $0 [--report-only] [P<n>]"; exit 2 ;;
  esac
done
truth=prm/patients/${patient}_truth.prm
[ -f "$truth" ] || { echo "truth_refinement: no $truth"; exit 1; }
[ -x build/softface ] || { echo "truth_refinement: build/softface is missing; run ./test.sh or ./run.sh first"; exit 1; }
/usr/bin/python3 -c "import numpy, matplotlib" 2> /dev/null ||
  { echo "truth_refinement: needs python3-numpy and python3-matplotlib (apt-get install -y python3-numpy python3-matplotlib)"; exit 1; }

target=$(sed -n 's/^ *set Target number of tetrahedra *= *\([0-9]*\).*/\1/p' "$truth")
[ -n "$target" ] || { echo "truth_refinement: $truth sets no 'Target number of tetrahedra'"; exit 1; }
factors="1 2 4"
if [ $report_only -eq 0 ]; then
  for f in $factors; do
    out="$work/${patient}_x$f"
    rm -rf "$out"
    mkdir -p "$out"
    n=$(/usr/bin/python3 -c "print(round($target * $f))")
    sed -e "s|set Output directory = .*|set Output directory = $root/$out|" \
      -e "s|set Target number of tetrahedra = .*|set Target number of tetrahedra = $n|" \
      "$truth" > "$out/scene.prm"
    echo "truth_refinement: $patient x$f (target $n tetrahedra)"
    start=$(date +%s%N)
    # A level that fails is a result too: the report names it and why.
    /usr/bin/time -v build/softface "$out/scene.prm" > "$out/log.txt" 2> "$out/stderr.txt" ||
      echo "truth_refinement: $patient x$f failed, see $out/log.txt"
    end=$(date +%s%N)
    echo "$(( (end - start) / 1000000 ))" > "$out/wall_ms"
    grep -E "reference fem +[0-9]" "$out/log.txt" || true
  done
fi
/usr/bin/python3 benchmarks/patients/truth_refinement.py "$work" "$patient" $factors \
  --distances doc/results/patients_skin.csv --results doc/results \
  --command "benchmarks/patients/truth_refinement.sh $patient"
