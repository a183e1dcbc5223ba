#!/usr/bin/env bash
# Quick start: ./test.sh [ctest arguments, e.g. -R peer]
#              ./test.sh --sanitize [ctest arguments]: a build with ASan and UBSan
#              (build-sanitize/) running the bad inputs and the fuzz sample.
# Same bootstrap as run.sh, then builds and runs the ctest suite on two cores.
set -euo pipefail
cd "$(dirname "$0")"
source scripts/bootstrap.sh
# Chromium for the browser test of softface serve (tests/serve_browser.sh); numpy and
# pydicom for the tests that write CT volumes and DICOM series themselves.
softface_ensure_packages chromium python3-numpy python3-pydicom
if [ "${1:-}" = "--sanitize" ]; then
  # AddressSanitizer and UndefinedBehaviorSanitizer on softface itself (not on
  # deal.II or its libraries), run on the bad inputs and the fuzz sample: what
  # reads user input must stay clean under them.
  shift
  export SOFTFACE_BUILD_DIR=build-sanitize SOFTFACE_BUILD_TARGET=softface
  softface_build -DSOFTFACE_SANITIZE=ON
  cd build-sanitize
  # Leaks at exit are the libraries' (MPI, Trilinos); any error ends the run.
  export ASAN_OPTIONS=detect_leaks=0:abort_on_error=0:halt_on_error=1
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  exec ctest --output-on-failure -j2 -R "bad_input/|fuzz_sample" "$@"
fi
softface_build
softface_web_packages
cd "${SOFTFACE_BUILD_DIR:-build}"
exec ctest --output-on-failure -j2 "$@"
