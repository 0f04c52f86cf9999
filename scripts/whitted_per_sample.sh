#!/usr/bin/env bash
# Time per sample of today's renderer against the Whitted-only tracer it
# grew from (commit 7de69c6, before area lights, textures, samplers and the
# path tracer), on scenes without the new effects. Both render the same
# scene files at the same size and samples on one thread; runs alternate
# A, B, A, B... and the median user CPU time of each is compared.
#
#   bash scripts/whitted_per_sample.sh [RUNS]     (default 7; needs git, a clone with history)
#
# Builds the old commit in a temporary worktree (a few minutes the first
# time; it is kept in target/whitted-baseline for later runs).
set -euo pipefail
runs=${1:-7}
base=7de69c6
root=$(git rev-parse --show-toplevel)
cd "$root"
old=target/whitted-baseline
if [ ! -x "$old/target/release/gridrt" ]; then
    rm -rf "$old"
    git worktree prune
    git worktree add --detach "$old" "$base" >/dev/null
    (cd "$old" && CARGO_TARGET_DIR="$root/$old/target" cargo build --release -q)
fi
cargo build --release -q
new=target/release/gridrt
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# The user CPU seconds of one run of the command given.
user_time() {
    local t
    t=$( { /usr/bin/env TIMEFORMAT=%U bash -c "time $* >/dev/null 2>&1" ; } 2>&1 )
    echo "$t"
}

median() { sort -g | awk '{a[NR]=$1} END {print (NR%2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }

printf '%-14s %10s %10s %8s\n' scene "now s" "Whitted s" ratio
for scene in phong shadows mirror_glass; do
    args="--spp 16 --width 640 --threads 1"
    : >"$tmp/a"
    : >"$tmp/b"
    for _ in $(seq "$runs"); do
        user_time "$new render fixtures/scenes/$scene.ron $args -o $tmp/a.png" >>"$tmp/a"
        user_time "$old/target/release/gridrt render $old/fixtures/scenes/$scene.ron $args -o $tmp/b.png" >>"$tmp/b"
    done
    a=$(median <"$tmp/a")
    b=$(median <"$tmp/b")
    printf '%-14s %10.3f %10.3f %8.3f\n' "$scene" "$a" "$b" "$(echo "$a / $b" | bc -l)"
done
