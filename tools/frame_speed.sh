#!/usr/bin/env bash
# Median ms per 1920x1080 frame, texmap next to Mesa's llvmpipe, measured in one run:
# builtin:plane with each filter and builtin:sphere (199,200 triangles), 2 threads, a
# FRAMES-frame turntable each, ROUNDS rounds in which the renderers take turns (the order
# reversed every other round). The ratios are medians of the rounds' own ratios.
#
# llvmpipe runs twice a round: as gl_render.py draws by default (an RGBA8 texture filtered
# as its sRGB codes are, into an 8-bit framebuffer) and with --srgb (an SRGB8_ALPHA8
# texture and an sRGB framebuffer: texels decoded to linear light before they are
# filtered, as texmap filters them). The second draws the image texmap draws.
#
# texmap runs twice a round too: with --discard, its frames back to back as gl_render.py
# times llvmpipe's (which reads back and writes only the last), and writing a PNG after each
# frame (its encoding and file between the frames, not in their times, but in the caches the
# next frame finds).
#
# FRAMES defaults to 60: on the 2-core VM the first 10–15 frames of either renderer run up to
# twice as slow as the rest (a start-up phase of the machine, not of a renderer: llvmpipe's
# frames after its warm-up show it too), and a 20-frame median falls in or out of it from run
# to run.
#
#   bash tools/frame_speed.sh [FRAMES] [ROUNDS]   (needs bash ../shared/peers/setup.sh once)
#
# CASES="bilinear trilinear sphere" (any of the plane's filters below, and `sphere`) runs
# only those cases, in that order (more rounds of one case in the same time).
set -euo pipefail
cd "$(dirname "$0")/.."
P=${PEERS:-../shared/peers}
PY=$P/.venv/bin/python
N=${1:-60}
ROUNDS=${2:-3}
ALL="nearest bilinear trilinear aniso4 aniso16 aniso6 aniso5-area ewa sat sphere"
CASES=${CASES:-$ALL}
for c in $CASES; do
    case " $ALL " in
    *" $c "*) ;;
    *) echo "frame_speed.sh: unknown case '$c' in CASES (one of: $ALL)" >&2; exit 2 ;;
    esac
done
cargo build --release --quiet
TEXMAP=target/release/texmap
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
median() { "$PY" -c 'import json,sys; d=json.load(sys.stdin); print("%.2f" % d["frame_ms"]["median"])'; }
# One case: its name, texmap's arguments, then `--` and gl_render.py's (none: texmap alone).
# Prints "name texmap texmap_writing gl gl_srgb" for each round (— where llvmpipe does not run).
run() {
    local name=$1; shift
    local targs=() gargs=()
    while [ $# -gt 0 ] && [ "$1" != "--" ]; do targs+=("$1"); shift; done
    [ $# -gt 0 ] && shift
    gargs=("$@")
    for r in $(seq 1 "$ROUNDS"); do
        local order="texmap gl texw gls"
        [ $((r % 2)) -eq 0 ] && order="gls texw gl texmap"
        local t="—" w="—" g="—" s="—"
        for who in $order; do
            case $who in
            texmap) t=$("$TEXMAP" render "${targs[@]}" --size 1920x1080 --threads 2 --frames "$N" \
                        --stats --discard | median) ;;
            texw) w=$("$TEXMAP" render "${targs[@]}" --size 1920x1080 --threads 2 --frames "$N" \
                        --stats -o "$OUT/t_{frame}.png" | median) ;;
            gl) [ ${#gargs[@]} -gt 0 ] && g=$(LP_NUM_THREADS=2 "$PY" "$P/gl_render.py" "${gargs[@]}" \
                        --size 1920x1080 --threads 2 --frames "$N" --json -o "$OUT/g.png" | median) ;;
            gls) [ ${#gargs[@]} -gt 0 ] && s=$(LP_NUM_THREADS=2 "$PY" "$P/gl_render.py" "${gargs[@]}" \
                        --srgb --size 1920x1080 --threads 2 --frames "$N" --json -o "$OUT/s.png" | median) ;;
            esac
        done
        echo "$name $t $w $g $s"
    done
}
{
    for c in $CASES; do
        case $c in
        # The filters llvmpipe has too.
        nearest | bilinear | trilinear | aniso4 | aniso16)
            run "plane|$c" builtin:plane --filter "$c" -- --filter "$c" ;;
        aniso6 | aniso5-area | ewa | sat)
            run "plane|$c" builtin:plane --filter "$c" ;;
        sphere)
            run "sphere|trilinear" builtin:sphere --texture "$P/data/noise.png" \
                -- --scene mesh --mesh "$P/data/sphere.obj" --filter trilinear ;;
        esac
    done
} > "$OUT/rounds.txt"
"$PY" - "$OUT/rounds.txt" <<'PY'
import statistics, sys
rows = {}
for line in open(sys.argv[1]):
    name, t, w, g, s = line.split()
    rows.setdefault(name, []).append((t, g, s, w))
def med(xs):
    xs = [float(x) for x in xs if x != "—"]
    return "%.1f" % statistics.median(xs) if xs else "—"
def ratio(rounds, k, mine=0):
    rs = [float(r[mine]) / float(r[k]) for r in rounds if r[k] != "—"]
    if not rs:
        return "—"
    return "%.2f (%.2f–%.2f)" % (statistics.median(rs), min(rs), max(rs))
print("| scene | filter | texmap ms | llvmpipe ms | texmap / llvmpipe | llvmpipe --srgb ms "
      "| texmap / llvmpipe --srgb | texmap writing each frame ms | … / llvmpipe |")
print("|---|---|---|---|---|---|---|---|---|")
for name, rounds in rows.items():
    scene, filt = name.split("|")
    scene = "sphere (199,200 tris)" if scene == "sphere" else scene
    print(f"| {scene} | {filt} | {med(r[0] for r in rounds)} | {med(r[1] for r in rounds)} | "
          f"{ratio(rounds, 1)} | {med(r[2] for r in rounds)} | {ratio(rounds, 2)} | "
          f"{med(r[3] for r in rounds)} | {ratio(rounds, 1, 3)} |")
PY
