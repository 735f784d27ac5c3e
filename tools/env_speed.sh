#!/usr/bin/env bash
# Cost of each environment technique at 1920x1080, --threads 2: every scene rendered with
# and without its technique, the two runs alternating for ROUNDS rounds of FRAMES turntable
# frames each; prints the median over the rounds of each run's median frame time (--stats)
# and their ratio. The background is the scene's colour in both runs (--background color),
# so the ratio is the technique's own cost; the prefilter (env_prefilter_ms) runs once per
# command, outside the frame times, and is printed apart.
#
#   bash tools/env_speed.sh [ROUNDS] [FRAMES]        (default 5 rounds of 3 frames)
#
# Rows: reflection (scenes/reflect.toml, --reflections off), refraction (scenes/refract.toml,
# --reflections off), transmission (scenes/transmission.toml, --reflections off), image-based
# light (scenes/ibl.toml, --ibl off) and, when ../shared/assets is present, DamagedHelmet
# with --env venice_sunset_1k.hdr against the same model without an environment (the issue's
# "IBL ≤ 1.3× the uniform-ambient metallic-roughness frame").
set -euo pipefail
cd "$(dirname "$0")/.."
ROUNDS=${1:-5}
FRAMES=${2:-3}
cargo build --release --quiet
TEXMAP=target/release/texmap
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
A=../shared/assets
common=(--size 1920x1080 --threads 2 --frames "$FRAMES" --stats -o "$OUT/f_{frame}.png")
field() { python3 -c 'import json,sys; d=json.load(sys.stdin); print(d["frame_ms"]["median"], d.get("env_prefilter_ms", 0))'; }

rows=()
rows+=("reflection|scenes/reflect.toml --background color|scenes/reflect.toml --background color --reflections off")
rows+=("refraction|scenes/refract.toml --background color|scenes/refract.toml --background color --reflections off")
rows+=("transmission|scenes/transmission.toml --background color|scenes/transmission.toml --background color --reflections off")
rows+=("image-based light|scenes/ibl.toml --background color|scenes/ibl.toml --background color --ibl off")
H=$A/gltf/DamagedHelmet/glTF-Binary/DamagedHelmet.glb
if [ -f "$H" ]; then
    rows+=("DamagedHelmet IBL|$H --env $A/env/equirect/venice_sunset_1k.hdr --background color|$H")
else
    echo "(DamagedHelmet row skipped: $A not present)" >&2
fi

echo "| technique | with (ms) | without (ms) | ratio | prefilter (ms) |"
echo "|---|---|---|---|---|"
for row in "${rows[@]}"; do
    IFS='|' read -r name with without <<< "$row"
    on=(); off=(); pre=()
    for _ in $(seq "$ROUNDS"); do
        # shellcheck disable=SC2086
        read -r t p < <("$TEXMAP" render $with "${common[@]}" | field)
        on+=("$t"); pre+=("$p")
        # shellcheck disable=SC2086
        read -r t _ < <("$TEXMAP" render $without "${common[@]}" | field)
        off+=("$t")
    done
    python3 - "$name" "${on[*]}" "${off[*]}" "${pre[*]}" <<'PY'
import statistics, sys
name = sys.argv[1]
on, off, pre = ([float(x) for x in a.split()] for a in sys.argv[2:5])
mn, mf, mp = statistics.median(on), statistics.median(off), statistics.median(pre)
print(f"| {name} | {mn:.1f} ({min(on):.1f}–{max(on):.1f}) | {mf:.1f} ({min(off):.1f}–{max(off):.1f}) | {mn / mf:.2f} | {mp:.0f} |")
PY
done
