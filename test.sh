#!/usr/bin/env bash
# Quick start: ./test.sh [ctest arguments, e.g. -R peer]
# Same bootstrap as run.sh, then builds and runs the ctest suite on two cores.
set -euo pipefail
cd "$(dirname "$0")"
source scripts/bootstrap.sh
softface_ensure_packages
softface_build
cd "${SOFTFACE_BUILD_DIR:-build}"
exec ctest --output-on-failure -j2 "$@"
