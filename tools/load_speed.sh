#!/usr/bin/env bash
# Scene loading: DamagedHelmet (five 2048² JPEG/PNG maps) loaded and made ready, then one
# 1920x1080 frame (--threads 2), with each storage (decoded, native, rgba8; STORAGES= to
# choose), against llvmpipe
# (gl_render.py, LP_NUM_THREADS=2) on the same model, alternating for ROUNDS rounds.
# Prints, for each texmap binary and storage, the medians over the rounds of setup_ms (load +
# setup, from --stats), the frame time, the wall time and the peak RSS (/usr/bin/time), and
# their ratios to llvmpipe's load_ms + setup_ms and peak RSS; each binary given is measured
# (an older build saved beside the current one gives an A/B in the same rounds).
#
#   bash tools/load_speed.sh [ROUNDS] [TEXMAP...]   (default 3 rounds of target/release/texmap)
#
# llvmpipe's script decodes only the base-colour image (one of the five); texmap decodes
# all five and builds their mip chains. Without ../shared/peers set up, its rows are left out.
set -euo pipefail
cd "$(dirname "$0")/.."
ROUNDS=${1:-3}
shift || true
A=../shared/assets
H=$A/gltf/DamagedHelmet/glTF-Binary/DamagedHelmet.glb
[ -f "$H" ] || { echo "SKIPPED: $H not present" >&2; exit 0; }
if [ $# -eq 0 ]; then
    cargo build --release --quiet
    set -- target/release/texmap
fi
P=${PEERS:-../shared/peers}
PY=$P/.venv/bin/python
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
: > "$OUT/rows"
for r in $(seq "$ROUNDS"); do
    for bin in "$@"; do
        for s in ${STORAGES:-decoded native rgba8}; do
            # A build that does not know a storage (an older one) skips it.
            "$bin" render --help | grep -q "$s" || continue
            /usr/bin/time -f '%e %M' -o "$OUT/time" "$bin" render "$H" --size 1920x1080 \
                --threads 2 --frames 1 --stats --quiet --texture-storage "$s" -o "$OUT/f.png" \
                > "$OUT/stats.json"
            python3 - "$OUT/stats.json" "$OUT/time" "$bin" "$s" "$r" >> "$OUT/rows" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
wall, kb = open(sys.argv[2]).read().split()[-2:]
print(sys.argv[3], sys.argv[4], sys.argv[5], j["setup_ms"], j["frame_ms"]["median"], wall, kb)
PY
        done
    done
    if [ -x "$PY" ]; then
        LP_NUM_THREADS=2 /usr/bin/time -f '%e %M' -o "$OUT/time" "$PY" $P/gl_render.py \
            --scene mesh --mesh "$H" --size 1920x1080 --threads 2 --frames 1 --json \
            -o "$OUT/p.png" > "$OUT/peer.json"
        python3 - "$OUT/peer.json" "$OUT/time" "$r" >> "$OUT/rows" <<'PY'
import json, sys
j = json.loads(open(sys.argv[1]).read().strip().splitlines()[-1])
wall, kb = open(sys.argv[2]).read().split()[-2:]
print("llvmpipe", "-", sys.argv[3], j["load_ms"] + j["setup_ms"], j["frame_ms"]["median"], wall, kb)
PY
    fi
done
uptime
python3 - "$OUT/rows" <<'PY'
import statistics, sys
rows = {}
for line in open(sys.argv[1]):
    name, storage, _, setup, frame, wall, kb = line.split()
    rows.setdefault((name, storage), []).append((float(setup), float(frame), float(wall), int(kb)))
med = lambda xs: statistics.median(xs)
peer = rows.get(("llvmpipe", "-"))
ps = med([r[0] for r in peer]) if peer else None
pk = med([r[3] for r in peer]) if peer else None
print("| binary | storage | load + setup ms (range) | / llvmpipe | frame ms | wall s | peak RSS MB (range) | / llvmpipe |")
print("|---|---|---|---|---|---|---|---|")
for (name, storage), rs in rows.items():
    s, f, w, k = (med([r[i] for r in rs]) for i in range(4))
    lo, hi = min(r[0] for r in rs), max(r[0] for r in rs)
    klo, khi = min(r[3] for r in rs) / 1024, max(r[3] for r in rs) / 1024
    rs_ = f"{s / ps:.2f}" if ps else "—"
    rk = f"{k / pk:.2f}" if pk else "—"
    print(f"| {name} | {storage} | {s:.0f} ({lo:.0f}–{hi:.0f}) | {rs_} | {f:.0f} | {w:.2f} "
          f"| {k / 1024:.0f} ({klo:.0f}–{khi:.0f}) | {rk} |")
print(f"rounds: {len(next(iter(rows.values())))}")
PY
