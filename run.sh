#!/usr/bin/env bash
# Quick start: ./run.sh [scene.prm]
# Installs missing Debian packages (as root; otherwise prints the command), configures a Release
# build, builds, and runs softface on the scene (default: prm/default.prm).
set -euo pipefail
cd "$(dirname "$0")"
source scripts/bootstrap.sh
softface_ensure_packages
softface_build
exec ./build/softface "${1:-prm/default.prm}"
