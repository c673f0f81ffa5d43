#!/bin/bash
# A Slurm job array that runs a benchmark sweep in 16 shards: task i runs the
# jobs k (surface x algebra, in order) with k % 16 == i and writes its own
# report. Submit it, then merge the reports once every task has ended:
#
#   mkdir -p bench logs
#   jid=$(sbatch --parsable examples/batch/slurm-bench.sh)
#   sbatch --dependency=afterany:$jid --wrap \
#       "isotrace bench --merge 'bench/part-*.json' --json bench.json --markdown bench.md"
#
# The merge refuses reports of different settings or isotrace versions. Ask
# for one kind of node (--constraint, --partition): timings from different
# devices do not compare, and the merge warns when it sees more than one.
#SBATCH --job-name=isotrace-bench
#SBATCH --array=0-15
#SBATCH --cpus-per-task=2
#SBATCH --mem=4G
#SBATCH --time=01:00:00
#SBATCH --exclusive
#SBATCH --output=logs/%x-%A_%a.out
set -euo pipefail

# The sweep. Defaults for a real run; the simulation sets tiny values.
ISOTRACE=${ISOTRACE:-isotrace}
SURFACES=${SURFACES:---suite knoll}
SIZE=${SIZE:-1024}
REPEAT=${REPEAT:-5}
OUT=${OUT:-bench}

export NODEVICE_SELECT=1
# SURFACES is split into words on purpose: names, or --suite NAME.
# shellcheck disable=SC2086
exec "$ISOTRACE" bench $SURFACES --algebra ia,raa,auto --size "$SIZE" --repeat "$REPEAT" \
    --shard auto --json "$OUT/part-$SLURM_ARRAY_TASK_ID.json"
