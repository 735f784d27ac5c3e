#!/usr/bin/env bash
# Median ms per 1920x1080 frame, texmap next to Mesa's llvmpipe, measured in one run:
# builtin:plane with each filter and builtin:sphere (199,200 triangles), 2 threads, a
# 20-frame turntable each.
#
#   bash tools/frame_speed.sh [FRAMES]       (needs bash ../shared/peers/setup.sh once)
set -euo pipefail
cd "$(dirname "$0")/.."
P=${PEERS:-../shared/peers}
PY=$P/.venv/bin/python
N=${1:-20}
cargo build --release --quiet
TEXMAP=target/release/texmap
OUT=$(mktemp -d)
median() { "$PY" -c 'import json,sys; d=json.load(sys.stdin); print("%.1f" % d["frame_ms"]["median"])'; }
echo "| scene | filter | texmap ms | llvmpipe ms | ratio |"
echo "|---|---|---|---|---|"
run() { # scene filter texmap-args... -- gl-args...
    local scene=$1 filter=$2; shift 2
    local targs=() gargs=()
    while [ $# -gt 0 ] && [ "$1" != "--" ]; do targs+=("$1"); shift; done
    [ $# -gt 0 ] && shift
    gargs=("$@")
    ours=$("$TEXMAP" render "${targs[@]}" --size 1920x1080 --threads 2 --frames "$N" --stats -o "$OUT/t_{frame}.png" | median)
    if [ ${#gargs[@]} -gt 0 ]; then
        peer=$(LP_NUM_THREADS=2 "$PY" "$P/gl_render.py" "${gargs[@]}" --size 1920x1080 --threads 2 --frames "$N" --json -o "$OUT/g.png" | median)
        ratio=$("$PY" -c "print('%.2f' % ($ours / $peer))")
    else
        peer="—"; ratio="—"
    fi
    echo "| $scene | $filter | $ours | $peer | $ratio |"
}
for f in nearest bilinear trilinear aniso4 aniso16; do
    run plane "$f" builtin:plane --filter "$f" -- --filter "$f"
done
for f in ewa sat; do
    run plane "$f" builtin:plane --filter "$f"
done
run sphere trilinear builtin:sphere --texture "$P/data/noise.png" -- --scene mesh --mesh "$P/data/sphere.obj" --filter trilinear
rm -rf "$OUT"
