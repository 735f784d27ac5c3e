#!/usr/bin/env bash
# Per-output overhead of a batch: 100 small glTF models (copies of ../shared/assets'
# BoxTextured.glb) rendered at 320x180 by one `texmap render FOLDER` call against 100
# single-file calls, alternating, ROUNDS rounds (default 3); prints files/s both ways and the
# medians. Usage: tools/batch_speed.sh [path/to/texmap] [rounds]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
texmap=${1:-$here/target/release/texmap}
rounds=${2:-3}
model=$here/../shared/assets/gltf/BoxTextured/glTF-Binary/BoxTextured.glb
[ -f "$model" ] || { echo "SKIPPED: $model not found"; exit 0; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/models"
for i in $(seq -w 1 100); do cp "$model" "$work/models/box$i.glb"; done
now() { date +%s.%N; }
batch=() single=()
for r in $(seq 1 "$rounds"); do
    rm -rf "$work/a" "$work/b"; mkdir -p "$work/a" "$work/b"
    t0=$(now)
    "$texmap" render "$work/models" --size 320x180 --threads 2 --quiet -o "$work/a/{scene}.png"
    t1=$(now)
    for f in "$work"/models/*.glb; do
        "$texmap" render "$f" --size 320x180 --threads 2 --quiet -o "$work/b/$(basename "$f" .glb).png"
    done
    t2=$(now)
    cmp -s <(cd "$work/a" && cat ./*.png) <(cd "$work/b" && cat ./*.png) || { echo "outputs differ"; exit 1; }
    b=$(echo "100 / ($t1 - $t0)" | bc -l); s=$(echo "100 / ($t2 - $t1)" | bc -l)
    printf 'round %d: batch %.1f files/s, single calls %.1f files/s\n' "$r" "$b" "$s"
    batch+=("$b"); single+=("$s")
done
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR%2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }
mb=$(median "${batch[@]}"); ms=$(median "${single[@]}")
printf 'median: batch %.1f files/s, single calls %.1f files/s, ratio %.2fx\n' "$mb" "$ms" "$(echo "$mb / $ms" | bc -l)"
