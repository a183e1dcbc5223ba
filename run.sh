#!/usr/bin/env bash
# Quick start: ./run.sh [scene.prm]        run a scene (default: prm/default.prm)
#              ./run.sh serve scene.prm  the interactive planning page (softface serve)
# Installs missing Debian packages (as root; otherwise prints the command) and the page's npm
# packages, configures a Release build, builds, and runs softface.
set -euo pipefail
cd "$(dirname "$0")"
source scripts/bootstrap.sh
softface_ensure_packages
softface_build
softface_web_packages
if [ $# -eq 0 ]; then
  set -- prm/default.prm
fi
exec ./build/softface "$@"
