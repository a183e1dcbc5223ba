# What both scaling benchmarks (run.sh, reference.sh) need before they run, sourced with
# $root set and $name the benchmark's name for messages: the softface binary ($softface: SOFTFACE
# or build/softface), mpiexec ($mpiexec) and Debian's numpy and matplotlib.
softface=${SOFTFACE:-$root/build/softface}
[ -x "$softface" ] || { echo "no softface binary at $softface (build it or set SOFTFACE)"; exit 1; }
mpiexec=$(command -v mpiexec || command -v mpirun || true)
[ -n "$mpiexec" ] || { echo "$name: needs mpiexec (apt-get install -y openmpi-bin)"; exit 1; }
source "$root/scripts/bootstrap.sh"
softface_ensure_packages python3-numpy python3-matplotlib
