#!/bin/sh
# One task of a Slurm job array renders one shard of a frame range into a shared folder.
#   sbatch --array=0-15 render-array.sh SCENE FRAMES SHARDS OUTPUT [relief render options]
# SHARDS is the array's task count. A task that was cancelled, pre-empted or failed is rerun
# as it is (sbatch --array=I ...): frames whose outputs all exist are skipped.
#SBATCH --job-name=relief
#SBATCH --cpus-per-task=1
#SBATCH --output=relief-%A_%a.log
set -eu
scene=$1 frames=$2 shards=$3 output=$4
shift 4
exec relief render "$scene" --frames "$frames" --shard "$SLURM_ARRAY_TASK_ID/$shards" \
  --threads "$SLURM_CPUS_PER_TASK" --skip-existing -o "$output" "$@"
