#!/usr/bin/env bash
# What each effect changes and what it costs: the paper's cube
# (prm/default.prm) and the phantom patient (prm/patient.prm) with Effects
# empty, each effect alone and both, every model in its own process (so that
# its peak memory is its own), repetitions interleaved. Writes
# doc/results/effects.md, effects.csv and effects.png.
#
#   benchmarks/effects/run.sh                      about 15 minutes
#   benchmarks/effects/run.sh --repetitions 5
#   benchmarks/effects/run.sh --baseline OLD/softface
#       also runs OLD (a softface built without the effect machinery, e.g.
#       from the commit before it) on the scenes without effects: the
#       zero-cost comparison
#   benchmarks/effects/run.sh --report-only        rewrite the reports
#
# Needs a built build/softface and Debian's python3-numpy, python3-matplotlib.
set -euo pipefail
cd "$(dirname "$0")/../.."
if [ ! -x build/softface ]; then
  echo "effects: build/softface is missing; run ./test.sh or ./run.sh first"
  exit 1
fi
if ! /usr/bin/python3 -c "import numpy, matplotlib" 2> /dev/null; then
  echo "effects: needs python3-numpy and python3-matplotlib (apt-get install -y python3-numpy python3-matplotlib)"
  exit 1
fi
exec /usr/bin/python3 benchmarks/effects/run.py "$@"
