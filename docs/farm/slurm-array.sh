#!/usr/bin/env bash
# A Slurm job array that renders one frame in tiles, one task per tile,
# then merges them in a dependent job. Submit from the repository root:
#   sbatch --array=0-15 docs/farm/slurm-array.sh scene.ron /shared/render/frame
#   sbatch --dependency=afterok:JOBID --wrap \
#       "docs/farm/merge-tiles.sh /shared/render/frame 16 /shared/render/frame.exr"
# The output folder must be on a file system every node sees.
#SBATCH --job-name=gridrt-tiles
#SBATCH --cpus-per-task=8
#SBATCH --output=gridrt-tile-%a.log
set -euo pipefail
scene=$1 outdir=$2
count=${SLURM_ARRAY_TASK_COUNT:?run as a job array}
exec docs/farm/render-tile.sh "$scene" "$SLURM_ARRAY_TASK_ID" "$count" "$outdir" \
    --threads "${SLURM_CPUS_PER_TASK:-1}"
