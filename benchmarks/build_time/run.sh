#!/usr/bin/env bash
# What a newcomer waits for: softface, its libraries and its test drivers
# built from nothing (no ccache) on two cores, in two configurations of the
# same commit, one after the other in one run:
#   plain:   debug information (-g, as Debian's deal.II hands it on) and no
#            precompiled headers (-DSOFTFACE_DEBUG_INFO=ON
#            -DSOFTFACE_PRECOMPILED_HEADERS=OFF);
#   default: without -g, the common deal.II headers precompiled.
# Wall, user and system time of each build and the size of its build folder
# go to doc/results/build_time.{md,csv,png}.
#
# Usage (from the repository's root): benchmarks/build_time/run.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
work=$root/build/benchmarks/build_time
mkdir -p "$work"
export CCACHE_DISABLE=1
csv=$work/build_time.csv
echo "configuration,wall_s,user_s,system_s,build_folder_mb" > "$csv"
for configuration in plain default; do
  dir=$work/$configuration
  rm -rf "$dir"
  case $configuration in
    plain) options="-DSOFTFACE_DEBUG_INFO=ON -DSOFTFACE_PRECOMPILED_HEADERS=OFF" ;;
    default) options="" ;;
  esac
  echo "build_time: configuring and building '$configuration' in $dir"
  cmake -S "$root" -B "$dir" -DCMAKE_BUILD_TYPE=Release $options > "$work/$configuration.configure.log"
  /usr/bin/time -f "%e,%U,%S" -o "$work/$configuration.time" \
    cmake --build "$dir" -j2 > "$work/$configuration.build.log" 2>&1 || {
    tail -20 "$work/$configuration.build.log"
    echo "build_time: the '$configuration' build failed"
    exit 1
  }
  size=$(du -sm "$dir" | cut -f1)
  echo "$configuration,$(tail -1 "$work/$configuration.time"),$size" >> "$csv"
  tail -1 "$csv"
done
/usr/bin/python3 benchmarks/build_time/report.py "$csv" doc/results
