#!/usr/bin/env bash
# A clinical-size CT end to end: the phantom patient of prm/patient.prm
# acquired at 0.5 mm voxels (360 x 480 x 512, 88 million voxels, as a
# head CT's slices are) beside the same patient at 1 mm. The phantom's CT
# is made first and written as a NIfTI file; the timed run then starts as a
# user's does, from reading that file: segmentation and surfaces, bone
# parts, mesh and the four models' table. Time and peak memory per stage
# go to doc/results/clinical_size.md (+ .csv, .png).
#
#   benchmarks/patients/clinical_size.sh     (about 5 min on 2 cores)
#
# Needs a built build/softface and Debian's python3-numpy, python3-matplotlib.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
work=build/benchmarks/clinical_size
mkdir -p "$work"
[ -x build/softface ] || { echo "clinical_size: build/softface is missing; run ./test.sh first"; exit 1; }

for voxel in 1 0.5; do
  dir="$work/voxel_$voxel"
  rm -rf "$dir"
  mkdir -p "$dir"
  # The phantom's CT alone (not timed: a user's CT exists already).
  sed -e "s|set Output directory = .*|set Output directory = $root/$dir/phantom|" \
    -e "s|set Post-operative skin = .*|set Post-operative skin =|" \
    -e "s|set Seed                  = 0|set Seed                  = 0\n      set Voxel size = $voxel|" \
    prm/patient.prm > "$dir/phantom.prm"
  build/softface phantom "$dir/phantom.prm" > "$dir/phantom.log"
  # The timed run: the CT read from the file, every later stage made anew.
  sed -e "s|set Output directory = .*|set Output directory = $root/$dir/run|" \
    -e "s|set Post-operative skin = .*|set Post-operative skin =|" \
    -e "s|set Cut held by = cranium|set Cut held by = cranium\n    set CT volume = $root/$dir/phantom/patient/ct.nii.gz|" \
    prm/patient.prm > "$dir/run.prm"
  echo "clinical_size: $voxel mm voxels"
  /usr/bin/time -v build/softface "$dir/run.prm" > "$dir/run.log" 2> "$dir/time.txt"
done
/usr/bin/python3 benchmarks/patients/clinical_size.py "$work" doc/results
