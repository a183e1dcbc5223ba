#!/usr/bin/env bash
# Re-planning: a phantom patient's scene (prm/patients/P1.prm, ~119k tetrahedra, its
# dense skin) swept over PLANS plans of the mandible's set-back, linear fem (cg amg) and mass
# tensor, once solving every plan and once from the response basis; then `softface serve` on the
# same scene with its page in headless Chromium (slider-to-face latency, a screenshot); writes
# doc/results/interactive.{md,csv,png} and interactive_page.png.
#
#   benchmarks/interactive/run.sh [--quick]   (--quick: prm/patient.prm, 8 plans; results in the
#                                              work dir)
#
# Env: SOFTFACE (default build/softface), INTERACTIVE_WORK (default /tmp/softface-interactive).
# The first run makes the patient's mesh (about 90 s); later runs reuse it. Needs Debian's
# /usr/bin/python3 with python3-matplotlib, chromium and web/node_modules (./test.sh installs both).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
softface=${SOFTFACE:-$root/build/softface}
work=${INTERACTIVE_WORK:-/tmp/softface-interactive}
results=$root/doc/results
[ -x "$softface" ] || { echo "no softface binary at $softface (build it or set SOFTFACE)"; exit 1; }
# The Debian packages and the page's npm packages, as ./run.sh and ./test.sh install them.
source "$root/scripts/bootstrap.sh"
softface_ensure_packages python3-matplotlib chromium
(cd "$root" && softface_web_packages)
scene=$root/prm/patients/P1.prm
quick=()
if [ "${1:-}" = "--quick" ]; then
  quick=(--quick); scene=$root/prm/patient.prm; results=$work/quick-results
fi
mkdir -p "$work" "$results"
/usr/bin/python3 "$here/run.py" "$(realpath "$softface")" "$scene" "$work" "$results" \
  "benchmarks/interactive/run.sh $*" "${quick[@]}"
