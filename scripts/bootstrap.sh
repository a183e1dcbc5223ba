# Shared by run.sh and test.sh: install what is missing, configure and build.
# Sourced, not executed.

# Debian packages softface needs to build and test. OpenBLAS replaces the reference
# BLAS that the direct solver (CHOLMOD) would otherwise run on 30x slower; ccache is optional.
# The patient pipeline adds ITK (volumes, segmentation), VTK (surfaces), CGAL (Mesh_3),
# Eigen and nanoflann (ICP).
SOFTFACE_PACKAGES="cmake g++ make libdeal.ii-dev libsuitesparse-dev libopenblas0-pthread numdiff clang-format
  libinsighttoolkit5-dev libvtk9-dev libcgal-dev libeigen3-dev libnanoflann-dev"

softface_missing_packages()
{
  local missing=""
  for p in $SOFTFACE_PACKAGES "$@"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed"; then
      missing="$missing $p"
    fi
  done
  echo "$missing"
}

softface_ensure_packages()
{
  local missing
  missing=$(softface_missing_packages "$@")
  [ -z "$missing" ] && return 0
  if [ "$(id -u)" = "0" ]; then
    echo "softface: installing missing Debian packages (a few minutes for deal.II):$missing"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq $missing ccache > /dev/null ||
      apt-get install -y -qq $missing > /dev/null
  else
    echo "softface: missing Debian packages:$missing"
    echo "Install them with:"
    echo "  sudo apt-get update && sudo apt-get install -y$missing"
    exit 1
  fi
}

# softface serve's page: three.js (and, for the browser test, playwright-core) from the npm
# registry into web/node_modules, as web/package-lock.json pins them. Needs Node.js 20 (the
# machine's, or Debian's nodejs and npm); a failure is reported and the rest goes on (only
# 'softface serve' and the browser test need the page).
softface_web_packages()
{
  if [ -f web/node_modules/three/build/three.module.js ] &&
       [ -f web/node_modules/playwright-core/package.json ]; then
    return 0
  fi
  if ! command -v npm > /dev/null; then
    softface_ensure_packages nodejs npm
  fi
  echo "softface: installing the page's packages (npm ci in web/)"
  (cd web && npm ci --no-audit --no-fund > npm-ci.log 2>&1) || {
    cat web/npm-ci.log
    echo "softface: warning: 'npm ci' in web/ failed; softface serve's page and the browser test need it"
  }
}

# Configure (Release) and build in build/ with two jobs.
# softface_build [cmake options...]: configure (once) and build. With
# SOFTFACE_BUILD_TARGET set, only that target is built.
softface_build()
{
  local build_dir=${SOFTFACE_BUILD_DIR:-build}
  mkdir -p "$build_dir"
  if [ ! -f "$build_dir/CMakeCache.txt" ]; then
    echo "softface: configuring a Release build in $build_dir/"
    cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@" > "$build_dir/configure.log" 2>&1 || {
      cat "$build_dir/configure.log"
      echo "softface: cmake configuration failed (log above)"
      exit 1
    }
  fi
  echo "softface: building (2 jobs)"
  cmake --build "$build_dir" -j2 ${SOFTFACE_BUILD_TARGET:+--target "$SOFTFACE_BUILD_TARGET"} || {
    echo "softface: build failed"
    exit 1
  }
}
