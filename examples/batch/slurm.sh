#!/bin/bash
# A Slurm job array that renders one animation in 16 shards: task i renders
# the frames k with k % 16 == i (isotrace reads i and the count from
# SLURM_ARRAY_TASK_ID, _MIN and _MAX). Submit it from the directory the
# frames go to:
#
#   mkdir -p frames logs && sbatch examples/batch/slurm.sh
#
# A task that is re-queued (node failure, time limit, `scontrol requeue`) or
# submitted again renders only the frames that are still missing
# (--skip-existing). When the array has ended:
#
#   isotrace manifest merge 'frames/*.manifest.json'
#
# lists the complete and the missing frames (exit code 1 if any is missing).
# scripts/simulate-array.sh runs this file as a 4-task array on one machine.
#SBATCH --job-name=isotrace-frames
#SBATCH --array=0-15
#SBATCH --cpus-per-task=2
#SBATCH --mem=4G
#SBATCH --time=02:00:00
#SBATCH --requeue
#SBATCH --output=logs/%x-%A_%a.out
set -euo pipefail

# The animation. Defaults for a real run; the simulation sets tiny values.
ISOTRACE=${ISOTRACE:-isotrace}
SURFACE=${SURFACE:-@water}
SIZE=${SIZE:-1920x1080}
FRAMES=${FRAMES:-960}
OUT=${OUT:-frames}

# Mesa's device-select layer warns on every start without this.
export NODEVICE_SELECT=1
exec "$ISOTRACE" render "$SURFACE" --size "$SIZE" --frames "$FRAMES" --t0 0 --t1 6.283 \
    -o "$OUT/f_%04d.png" --shard auto --skip-existing
