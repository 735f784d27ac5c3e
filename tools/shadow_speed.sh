#!/usr/bin/env bash
# Cost of one shadowed light: scenes/reference/shadow.toml (one directional light) at
# 1920x1080, --threads 2, with a 2048² map and PCF 3×3 against the same frames without
# shadows. Runs alternate (unshadowed, shadowed) for ROUNDS rounds of FRAMES turntable frames
# each; prints the median frame time of each side, their ratio, and the map pass (drawn once
# per command, outside the frame times).
#
#   bash tools/shadow_speed.sh [ROUNDS] [FRAMES]        (default 5 rounds of 10 frames)
set -euo pipefail
cd "$(dirname "$0")/.."
ROUNDS=${1:-5}
FRAMES=${2:-10}
cargo build --release --quiet
TEXMAP=target/release/texmap
OUT=$(mktemp -d)
common=(render scenes/reference/shadow.toml --size 1920x1080 --threads 2 --frames "$FRAMES" --stats -o "$OUT/f_{frame}.png")
field() { python3 -c 'import json,sys; d=json.load(sys.stdin); print(d["frame_ms"]["median"], d["shadow_maps_ms"])'; }
off=(); on=(); maps=()
for _ in $(seq "$ROUNDS"); do
    read -r t _ < <("$TEXMAP" "${common[@]}" --shadows=false | field)
    off+=("$t")
    read -r t m < <("$TEXMAP" "${common[@]}" --shadow-map-size 2048 --shadow-filter pcf3 | field)
    on+=("$t"); maps+=("$m")
done
python3 - "${off[*]}" "${on[*]}" "${maps[*]}" <<'PY'
import statistics, sys
off, on, maps = ([float(x) for x in a.split()] for a in sys.argv[1:4])
mo, mn, mm = statistics.median(off), statistics.median(on), statistics.median(maps)
print(f"unshadowed frame: median {mo:.1f} ms over {len(off)} rounds ({', '.join(f'{x:.1f}' for x in off)})")
print(f"shadowed frame:   median {mn:.1f} ms over {len(on)} rounds ({', '.join(f'{x:.1f}' for x in on)})")
print(f"ratio (frames): {mn / mo:.2f}")
print(f"map pass (2048², once per command): median {mm:.1f} ms; one frame with its map: {(mn + mm) / mo:.2f}x")
PY
rm -rf "$OUT"
