#!/usr/bin/env bash
# Frame times of the relief techniques with and without them: 1920x1080, --threads 2,
# `texmap render --stats`, the variants of each scene alternated, ROUNDS rounds (default 3);
# prints the median frame_ms (and setup_ms, where displacement's tessellation runs) of each.
# Usage: tools/relief_speed.sh [ROUNDS]   (after cargo build --release)
set -euo pipefail
cd "$(dirname "$0")/.."
T=target/release/texmap
ROUNDS=${1:-3}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cases=(
  "parallax.toml|occlusion|--parallax occlusion"
  "parallax.toml|offset|--parallax offset"
  "parallax.toml|normal-map-only|--parallax off"
  "parallax.toml|no-maps|--parallax off --normal-maps off"
  "displacement.toml|displaced|--displacement on"
  "displacement.toml|smooth|--displacement off"
  "normal.toml|normal-maps|--normal-maps on"
  "normal.toml|no-normal-maps|--normal-maps off"
  "bump.toml|bump+normal|--bump-maps on"
  "bump.toml|no-bump|--bump-maps off"
)
for r in $(seq "$ROUNDS"); do
  for c in "${cases[@]}"; do
    IFS='|' read -r scene tag flags <<<"$c"
    # shellcheck disable=SC2086
    $T render "scenes/$scene" $flags --size 1920x1080 --threads 2 --stats --quiet \
      -o "$out/img.png" >>"$out/$scene.$tag.json"
  done
done
for c in "${cases[@]}"; do
  IFS='|' read -r scene tag _ <<<"$c"
  python3 - "$out/$scene.$tag.json" "$scene" "$tag" <<'PY'
import json, statistics, sys
runs = [json.loads(l) for l in open(sys.argv[1]) if l.startswith("{")]
f = statistics.median(r["frame_ms"]["median"] for r in runs)
s = statistics.median(r["setup_ms"] for r in runs)
print(f"{sys.argv[2]:18} {sys.argv[3]:16} frame {f:8.1f} ms  setup {s:8.1f} ms  triangles {runs[0]['triangles_submitted']}")
PY
done
