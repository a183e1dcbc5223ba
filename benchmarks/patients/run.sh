#!/usr/bin/env bash
# The ten phantom patients after the paper's Table 2 (Mollemans et al. 2007):
# builds each patient from its scene prm/patients/P<n>.prm (phantom CT ->
# segmentation -> surfaces -> bone parts -> tetrahedral mesh -> the four
# models), measures each predicted skin against the patient's post-operative
# truth (closest points, TPS-RPM correspondences and exact correspondences),
# runs the mass tensor model's precision study on the patient (the paper's Table 1,
# both relaxation factors) and writes doc/results/patients.md: the paper's
# Tables 1-4 and Figs. 1, 6, 9-11 side by side with ours, the paper's
# conclusions judged against the truth's and the metric's own error, and
# its timing claims taken apart (+ CSVs and PNGs, one picture per patient).
# What accuracy costs in time over mesh sizes and stop thresholds, on the
# same truths: benchmarks/patients/accuracy_time.py.
#
#   benchmarks/patients/run.sh            all ten (about 18 min on 2 cores,
#                                         plus about an hour for their truths
#                                         the first time and after any change
#                                         of softface's code)
#   benchmarks/patients/run.sh P4 P5      some of them
#   benchmarks/patients/run.sh --no-truth P8
#                                         without the post-operative truth
#                                         (Table 2 only: no skin distances)
#   benchmarks/patients/run.sh --report-only
#   benchmarks/patients/run.sh --no-report P4
#                                         run without writing the report (a
#                                         cluster's array task; see slurm.sh)
#
# Needs a built build/softface and Debian's python3-numpy, python3-matplotlib.
# Each patient's outputs (and its stage files, reused by a second run with
# unchanged parameters) go to build/benchmarks/patients/<name>/.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
work=build/benchmarks/patients
results=doc/results
mkdir -p "$work" "$results/patients"

if [ ! -x build/softface ]; then
  echo "patients: build/softface is missing; run ./test.sh or ./run.sh first"
  exit 1
fi
if ! /usr/bin/python3 -c "import numpy, matplotlib" 2> /dev/null; then
  echo "patients: needs python3-numpy and python3-matplotlib (apt-get install -y python3-numpy python3-matplotlib)"
  exit 1
fi

patients=()
report_only=0
no_truth=0
no_report=0
for a in "$@"; do
  case "$a" in
    --report-only) report_only=1 ;;
    --no-truth) no_truth=1 ;;
    --no-report) no_report=1 ;;
    P*) patients+=("$a") ;;
    *) echo "usage: $0 [--report-only] [--no-truth] [--no-report] [P1 ... P10]"; exit 2 ;;
  esac
done
[ ${#patients[@]} -eq 0 ] && patients=(P1 P2 P3 P4 P5 P6 P7 P8 P9 P10)
for p in "${patients[@]}"; do
  [ -f "prm/patients/$p.prm" ] && [ -f "prm/patients/${p}_truth.prm" ] ||
    { echo "patients: no patient $p (prm/patients/$p.prm and ${p}_truth.prm)"; exit 2; }
done

if [ $report_only -eq 0 ]; then
  for p in "${patients[@]}"; do
    out="$work/$p"
    rm -rf "$out"
    mkdir -p "$out"
    # The scene and its truth (the post-operative skin) with their output
    # folders redirected into the build tree; the truth's folder is kept, so
    # that an unchanged truth made by the same build is not made again.
    truth="$work/${p}_truth"
    mkdir -p "$truth"
    sed "s|set Output directory = .*|set Output directory = $root/$truth|" \
      "prm/patients/${p}_truth.prm" > "$truth/scene.tmp"
    cmp -s "$truth/scene.tmp" "$truth/scene.prm" || mv "$truth/scene.tmp" "$truth/scene.prm"
    rm -f "$truth/scene.tmp"
    post="$root/$truth/scene.prm"
    [ $no_truth -eq 1 ] && post=""
    sed -e "s|set Output directory = .*|set Output directory = $root/$out|" \
      -e "s|set Post-operative skin = .*|set Post-operative skin = $post|" \
      "prm/patients/$p.prm" > "$out/scene.prm"
    # The signed distances per skin point, for the distance maps.
    printf 'subsection Skin\n  set Write distances = true\nend\n' >> "$out/scene.prm"
    echo "patients: $p"
    start=$(date +%s%N)
    set +e
    /usr/bin/time -v build/softface "$out/scene.prm" > "$out/log.txt" 2> "$out/stderr.txt"
    code=$?
    set -e
    end=$(date +%s%N)
    echo "$code $(( (end - start) / 1000000 ))" > "$out/exit_code"  # exit code, wall ms
    grep -E "^ *(model|linear fem|mass tensor|mass spring|nonlinear fem) +[0-9m]" "$out/log.txt" || true
    grep "Maximum resident" "$out/stderr.txt" || true
    # The paper's precision study (2.3.5, Table 1, Fig. 1) on the patient: the
    # mass tensor model alone on the patient's mesh (its stage files reused),
    # every free point in every sweep until all gradients fall below 1e-5 mm
    # per sweep, the distance to the converged answer written after each
    # sweep; with the paper's plain update (factor 1) and the default
    # over-relaxation (auto).
    for factor in 1 auto; do
      run="$out/precision_$factor"
      mkdir -p "$run"
      sed -e "s|set Output directory = .*|set Output directory = $root/$run|" \
        -e "s|set Post-operative skin = .*|set Post-operative skin =|" \
        -e "s|set Models = .*|set Models = mass tensor|" \
        "prm/patients/$p.prm" > "$run/scene.prm"
      printf '%s\n' "subsection Scene" "  subsection Patient" \
        "    set Work directory = $root/$out/patient" "  end" "end" \
        "subsection Models" "  subsection mass tensor" \
        "    set Relaxation factor = $factor" "    set Active set = false" \
        "    set Stop gradient threshold = 1e-5" \
        "    set Precision history file = $root/$run/history.csv" "  end" "end" \
        "subsection Skin" "  set Skin surface = none" "end" \
        "subsection Output" "  set Write VTU = false" "end" >> "$run/scene.prm"
      if build/softface "$run/scene.prm" > "$run/log.txt" 2>&1; then
        echo "patients: $p: precision study, relaxation factor $factor: $(($(wc -l < "$run/history.csv") - 1)) sweeps"
      else
        echo "patients: $p: precision study, relaxation factor $factor failed (see $run/log.txt)"
      fi
    done
    /usr/bin/python3 benchmarks/patients/render.py "$out/patient/skin.ply" \
      "$out/patient/skull.ply" "$results/patients/$p.png" \
      --title "$p: $(grep -m1 '^# Phantom patient' "prm/patients/$p.prm" | sed 's/.*Table 2: //; s/,.*//')" ||
      echo "patients: $p: no image"
  done
fi

[ $no_report -eq 1 ] && exit 0
/usr/bin/python3 benchmarks/patients/report.py "$work" "$results"
