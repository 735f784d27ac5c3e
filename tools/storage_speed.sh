#!/usr/bin/env bash
# Texture storage, each way: frame time and peak memory of the same render with
# --texture-storage decoded, native, compressed and rgba8, the four alternating for ROUNDS rounds
# (1920x1080, --threads 2, FRAMES turntable frames each); prints the median over the rounds
# of each run's median frame time (--stats) and of its peak RSS (/usr/bin/time), and the
# ratios to decoded. With ../shared/peers set up, the DamagedHelmet rows are followed by
# llvmpipe's peak RSS on the same model in the same rounds (gl_render.py, LP_NUM_THREADS=2).
#
#   bash tools/storage_speed.sh [ROUNDS] [FRAMES]        (default 3 rounds of 3 frames)
#
# Cases (when ../shared/assets is present): the plane textured with the Xbox sample's BC1
# and BC7 DDS files (512², full chains), trilinear; DamagedHelmet (five 2048² JPEG/PNG maps:
# compressed holds them as native, since they are not block-compressed).
set -euo pipefail
cd "$(dirname "$0")/.."
ROUNDS=${1:-3}
FRAMES=${2:-3}
A=../shared/assets
[ -d "$A" ] || { echo "SKIPPED: $A not present" >&2; exit 0; }
cargo build --release --quiet
TEXMAP=target/release/texmap
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
P=${PEERS:-../shared/peers}
PY=$P/.venv/bin/python
common=(--size 1920x1080 --threads 2 --frames "$FRAMES" --stats --quiet -o "$OUT/f{frame}.png")
X=$A/compressed/xbox_atg_fastblockcompress
H=$A/gltf/DamagedHelmet/glTF-Binary/DamagedHelmet.glb
cases=(
    "plane, BC1 512²|builtin:plane --texture $X/opaque_512_offline_bc1.DDS --filter trilinear"
    "plane, BC7 512²|builtin:plane --texture $X/opaque_512_offline_bc7.dds --filter trilinear"
    "plane, brick.png (512², 8-bit)|builtin:plane --texture $A/textures/photos/brick.png --filter trilinear"
    "DamagedHelmet|$H"
)
# One run: "frame_ms peak_kB".
run() {
    # shellcheck disable=SC2086
    /usr/bin/time -f '%M' -o "$OUT/rss" "$TEXMAP" render $1 "${common[@]}" --texture-storage "$2" \
        > "$OUT/stats.json"
    ms=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["frame_ms"]["median"])' \
        "$OUT/stats.json")
    echo "$ms $(tail -1 "$OUT/rss")"
}
peer() {
    LP_NUM_THREADS=2 /usr/bin/time -f '%M' -o "$OUT/rss" "$PY" $P/gl_render.py --scene mesh \
        --mesh "$H" --size 1920x1080 --threads 2 --frames "$FRAMES" -o "$OUT/p.png" > /dev/null
    tail -1 "$OUT/rss"
}

echo "| case | storage | frame ms (range) | / decoded | peak RSS MB (range) | / decoded |"
echo "|---|---|---|---|---|---|"
for c in "${cases[@]}"; do
    IFS='|' read -r name args <<< "$c"
    declare -A ms=() kb=()
    peer_kb=()
    for _ in $(seq "$ROUNDS"); do
        for s in decoded native compressed rgba8; do
            read -r t m < <(run "$args" "$s")
            ms[$s]="${ms[$s]:-} $t"
            kb[$s]="${kb[$s]:-} $m"
        done
        if [ "$name" = DamagedHelmet ] && [ -x "$PY" ]; then
            peer_kb+=("$(peer)")
        fi
    done
    python3 - "$name" "${ms[decoded]}" "${kb[decoded]}" "${ms[native]}" "${kb[native]}" \
        "${ms[compressed]}" "${kb[compressed]}" "${ms[rgba8]}" "${kb[rgba8]}" "${peer_kb[*]:-}" <<'PY'
import statistics as st, sys
name, rest = sys.argv[1], sys.argv[2:]
rows = {}
for i, s in enumerate(["decoded", "native", "compressed", "rgba8"]):
    t = [float(x) for x in rest[2 * i].split()]
    m = [float(x) / 1024 for x in rest[2 * i + 1].split()]
    rows[s] = (t, m)
t0, m0 = st.median(rows["decoded"][0]), st.median(rows["decoded"][1])
for s, (t, m) in rows.items():
    print(f"| {name} | {s} | {st.median(t):.1f} ({min(t):.1f}–{max(t):.1f}) | "
          f"{st.median(t) / t0:.2f} | {st.median(m):.0f} ({min(m):.0f}–{max(m):.0f}) | "
          f"{st.median(m) / m0:.2f} |")
if rest[8].strip():
    p = [float(x) / 1024 for x in rest[8].split()]
    print(f"| {name} | llvmpipe (gl_render.py) | — | — | {st.median(p):.0f} "
          f"({min(p):.0f}–{max(p):.0f}) | {st.median(p) / m0:.2f} |")
PY
    unset ms kb
done
