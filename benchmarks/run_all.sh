#!/usr/bin/env bash
# What accuracy costs in time: every model's error against a
# converged quadratic reference and its setup and solve time, for the cube
# benchmark with a 6 mm lift, a 16.7 mm lift and a 30 degree rotation, plus
# the paper's MTM precision study. Shows "case i of N, elapsed, estimate".
#
#   benchmarks/run_all.sh           full run (2.4 to 5 hours of one core in
#                                   2026-11, most of it the references), writes
#                                   doc/results/accuracy_vs_time.{md,csv,png}
#                                   and doc/results/mtm_precision.{md,csv,png}
#   benchmarks/run_all.sh --quick   coarser meshes, fewer settings (under 5
#                                   minutes), writes build/benchmarks/accuracy/quick/results/
#   benchmarks/run_all.sh --scenes cube_6mm,rotation_30deg   only these scenes;
#                                   the reports keep the other scenes' results
#   benchmarks/run_all.sh --jobs 2  two cases at once, each on one thread (the
#                                   times then share the memory bandwidth; each
#                                   scene's section states the load)
#   benchmarks/run_all.sh --resume  run only cases whose .prm changed or that did
#                                   not finish; reuse the other outputs
#   benchmarks/run_all.sh --report-only   rewrite the reports from an earlier
#                                   run's outputs in build/benchmarks/accuracy/
#
# Builds softface first if needed (like ./run.sh). Needs /usr/bin/python3 with
# python3-numpy and python3-matplotlib (installed here if missing).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/bootstrap.sh
softface_ensure_packages python3-numpy python3-matplotlib
if [ ! -x build/softface ]; then
  softface_build
else
  cmake --build build -j2 --target softface > /dev/null
fi
exec /usr/bin/python3 benchmarks/accuracy/run_all.py "$@"
