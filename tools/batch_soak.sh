#!/usr/bin/env bash
# Soak: a 1,000-frame turntable at 320x180 in one process; peak RSS (/usr/bin/time -v's
# "Maximum resident set size") of the same render stopped at 100 frames (--frame-range 1..100)
# and run to 1,000. Usage: tools/batch_soak.sh [path/to/texmap] [scene]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
texmap=${1:-$here/target/release/texmap}
scene=${2:-$here/../shared/assets/gltf/Duck/glTF-Binary/Duck.glb}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for last in 100 1000; do
    rm -rf "$work/out"; mkdir -p "$work/out"
    /usr/bin/time -v "$texmap" render "$scene" --size 320x180 --frames 1000 \
        --frame-range "1..$last" --quiet -o "$work/out/{frame}.png" 2> "$work/time.txt"
    rss=$(awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}' "$work/time.txt")
    wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {print $2}' "$work/time.txt")
    echo "frames 1..$last: peak RSS $rss KiB, wall $wall, files $(ls "$work/out" | wc -l)"
done
