#!/bin/bash
# The explanatory figures of the manual (doc/images/*.png): runs the cube
# benchmark (prm/default.prm) and the phantom patient (prm/patient.prm) in a
# work folder, then draws the figures from their outputs with
# doc/make_figures.py (Debian's numpy, matplotlib and VTK, hence
# /usr/bin/python3; no display needed). Run from anywhere, after a build:
#
#   doc/make_figures.sh [SOFTFACE] [WORK]
#
# SOFTFACE: the softface binary (default: build/softface of this repository).
# WORK: the work folder, kept afterwards; give the one of an earlier run to
# reuse the patient's stages and post-operative truth (its first run makes
# the truth: about 450 s more). Without it a temporary folder is used and
# removed at the end.
#
# Figures: cube_boundary_conditions, solution_view (cube); join_and_free_points,
# mesh_and_skin, closest_vs_corresponding, predicted_face (patient).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
softface=${1:-$repo/build/softface}
case $softface in /*) ;; *) softface=$(pwd)/$softface ;; esac
[ -x "$softface" ] || { echo "make_figures.sh: no softface binary at $softface" >&2; exit 1; }
if [ -n "${2:-}" ]; then
  mkdir -p "$2"
  work=$(cd "$2" && pwd)
else
  work=$(mktemp -d "${TMPDIR:-/tmp}/softface_figures.XXXXXX")
  trap 'rm -rf "$work"' EXIT
fi
start=$SECONDS
cd "$work"
# Outputs go to output/default and output/patient (paths relative to the
# working directory); the patient's work directory is output/patient/patient.
echo "make_figures.sh: softface prm/default.prm (log: $work/default.log)"
"$softface" "$repo/prm/default.prm" > default.log 2>&1 ||
  { tail -20 default.log; exit 1; }
echo "make_figures.sh: softface prm/patient.prm (log: $work/patient.log)"
# Exit code 1 also means a model reported a failure; the figures need only
# the files, checked by make_figures.py.
"$softface" "$repo/prm/patient.prm" > patient.log 2>&1 ||
  { echo "make_figures.sh: softface prm/patient.prm exited with $?" \
         "(see $work/patient.log)"; }
echo "make_figures.sh: scenes done in $((SECONDS - start)) s"
/usr/bin/python3 "$repo/doc/make_figures.py" --cube "$work/output/default" \
  --patient "$work/output/patient" --out "$repo/doc/images"
echo "make_figures.sh: done in $((SECONDS - start)) s"
