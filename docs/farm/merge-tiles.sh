#!/usr/bin/env bash
# Merges the COUNT parts that render-tile.sh wrote to OUTDIR into IMAGE
# (.png or .exr). Fails, writing nothing, if a part is missing or foreign.
#   merge-tiles.sh OUTDIR COUNT IMAGE
set -euo pipefail
if [ "$#" -ne 3 ]; then
    echo "usage: $0 OUTDIR COUNT IMAGE" >&2
    exit 2
fi
outdir=$1 count=$2 image=$3
parts=()
for ((i = 0; i < count; i++)); do
    parts+=("$outdir/part-$i-of-$count.exr")
done
exec "${GRIDRT:-gridrt}" merge "${parts[@]}" -o "$image"
