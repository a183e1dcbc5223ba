#!/usr/bin/env bash
# The patients benchmark as independent jobs of one Slurm batch: an array task per
# patient (its truth, then its four models: `run.sh --no-report P<n>`), then one job that writes
# the report once every task has ended well (afterok). Writes the two batch scripts into
# build/benchmarks/patients/slurm/ and submits them with sbatch, or, without sbatch (or with
# --dry-run), prints them and the commands that would submit them.
#
#   benchmarks/patients/slurm.sh [--dry-run] [--cpus N] [--mem SIZE] [--time HH:MM:SS]
#                                [--partition NAME] [P1 ... P10]
#
# Defaults: all ten patients, 2 CPUs, 16G (P8's truth peaks at 10.7 GB), 02:00:00 per task.
# The tasks share the repository's build/ and doc/results/ folders, so the repository must sit
# on a file system every node sees. Not run on a cluster yet: checked with --dry-run and a
# stand-in sbatch on one machine.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
cpus=2
mem=16G
time_limit=02:00:00
partition=""
dry_run=0
patients=()
usage="usage: $0 [--dry-run] [--cpus N] [--mem SIZE] [--time HH:MM:SS] [--partition NAME] [P1 ... P10]"
while [ $# -gt 0 ]; do
  case "$1" in
    --cpus | --mem | --time | --partition)
      [ $# -ge 2 ] || { echo "slurm: $1 needs a value"; echo "$usage"; exit 2; } ;;
  esac
  case "$1" in
    --dry-run) dry_run=1 ;;
    --cpus) cpus=$2; shift ;;
    --mem) mem=$2; shift ;;
    --time) time_limit=$2; shift ;;
    --partition) partition=$2; shift ;;
    P*) patients+=("$1") ;;
    *) echo "$usage"; exit 2 ;;
  esac
  shift
done
[ ${#patients[@]} -eq 0 ] && patients=(P1 P2 P3 P4 P5 P6 P7 P8 P9 P10)
[[ "$cpus" =~ ^[1-9][0-9]*$ ]] || { echo "slurm: --cpus takes a positive number (got '$cpus')"; exit 2; }
for p in "${patients[@]}"; do
  [ -f "prm/patients/$p.prm" ] || { echo "slurm: no patient $p (prm/patients/$p.prm)"; exit 2; }
done
[ -x build/softface ] || { echo "slurm: build/softface is missing; build it first (./test.sh or ./run.sh)"; exit 1; }

dir=build/benchmarks/patients/slurm
mkdir -p "$dir"
part_line=""
[ -n "$partition" ] && part_line="#SBATCH --partition=$partition"

cat > "$dir/patients.sbatch" <<EOF
#!/bin/bash
#SBATCH --job-name=softface-patients
#SBATCH --array=0-$(( ${#patients[@]} - 1 ))
#SBATCH --ntasks=1
#SBATCH --cpus-per-task=$cpus
#SBATCH --mem=$mem
#SBATCH --time=$time_limit
#SBATCH --output=$root/$dir/%x-%a.out
$part_line
patients=(${patients[*]})
cd "$root"
export DEAL_II_NUM_THREADS=\${SLURM_CPUS_PER_TASK:-$cpus}
benchmarks/patients/run.sh --no-report "\${patients[\$SLURM_ARRAY_TASK_ID]}"
EOF

cat > "$dir/report.sbatch" <<EOF
#!/bin/bash
#SBATCH --job-name=softface-patients-report
#SBATCH --ntasks=1
#SBATCH --cpus-per-task=1
#SBATCH --mem=4G
#SBATCH --time=00:20:00
#SBATCH --output=$root/$dir/%x.out
$part_line
cd "$root"
benchmarks/patients/run.sh --report-only
EOF

if [ $dry_run -eq 1 ] || ! command -v sbatch > /dev/null; then
  [ $dry_run -eq 1 ] || echo "slurm: no sbatch here; the scripts and the commands that would submit them:"
  for f in patients.sbatch report.sbatch; do echo "--- $dir/$f"; cat "$dir/$f"; done
  echo "--- submit with:"
  echo "  id=\$(sbatch --parsable $dir/patients.sbatch)"
  echo "  sbatch --dependency=afterok:\$id $dir/report.sbatch"
  exit 0
fi
id=$(sbatch --parsable "$dir/patients.sbatch")
report=$(sbatch --parsable --dependency="afterok:$id" "$dir/report.sbatch")
echo "slurm: submitted the patients as array job $id (${#patients[@]} tasks) and the report as job $report"
