#!/usr/bin/env bash
# Renders tile INDEX of COUNT of a scene into OUTDIR/part-INDEX-of-COUNT.exr.
# The one command every recipe in docs/farm.md runs per task.
#   render-tile.sh SCENE INDEX COUNT OUTDIR [gridrt render options...]
# GRIDRT names the gridrt binary (default: gridrt on PATH).
set -euo pipefail
if [ "$#" -lt 4 ]; then
    echo "usage: $0 SCENE INDEX COUNT OUTDIR [gridrt render options...]" >&2
    exit 2
fi
scene=$1 index=$2 count=$3 outdir=$4
shift 4
mkdir -p "$outdir"
exec "${GRIDRT:-gridrt}" render "$scene" --tile "$index/$count" \
    -o "$outdir/part-$index-of-$count.exr" --quiet "$@"
