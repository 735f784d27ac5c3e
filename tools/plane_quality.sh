#!/usr/bin/env bash
# Image quality of every texture filter on the grazing-angle plane, texmap next to Mesa's
# llvmpipe, against the box-filtered ground truth — all computed in one run.
#
#   bash tools/plane_quality.sh [OUT_DIR]        (needs bash ../shared/peers/setup.sh once)
#
# 640x360, checker.png and noise.png, linear-light mode (the peers' --srgb), PSNR/SSIM over
# the plane's pixels (ground_truth.py --mask-out). Prints a Markdown table.
set -euo pipefail
cd "$(dirname "$0")/.."
P=${PEERS:-../shared/peers}
PY=$P/.venv/bin/python
OUT=${1:-target/plane-quality}
mkdir -p "$OUT"
cargo build --release --quiet
TEXMAP=target/release/texmap
metric() { "$PY" "$P/metrics.py" "$1" "$2" --mask "$3" | "$PY" -c 'import json,sys; d=json.load(sys.stdin)["masked"]; print("%.2f / %.3f" % (d["psnr_db"], d["ssim"]))'; }
for t in checker noise; do
    [ -f "$OUT/gt_$t.png" ] || "$PY" "$P/ground_truth.py" --texture "$P/data/$t.png" --srgb --size 640x360 \
        -o "$OUT/gt_$t.png" --mask-out "$OUT/mask_$t.png" >/dev/null
done
echo "| filter | texmap checker | llvmpipe checker | texmap noise | llvmpipe noise |"
echo "|---|---|---|---|---|"
for f in nearest bilinear trilinear aniso2 aniso4 aniso6 aniso8 aniso16 aniso5-area aniso8-area ewa ewa-exact sat; do
    row="| $f"
    for t in checker noise; do
        "$TEXMAP" render builtin:plane --texture "$P/data/$t.png" --filter "$f" --size 640x360 \
            -o "$OUT/texmap_${t}_$f.png" --quiet
        ours=$(metric "$OUT/texmap_${t}_$f.png" "$OUT/gt_$t.png" "$OUT/mask_$t.png")
        case $f in
            ewa|ewa-exact|sat|aniso6|*-area) peer="—" ;;  # the peer offers 2, 4, 8 and 16
            *) "$PY" "$P/gl_render.py" --texture "$P/data/$t.png" --srgb --filter "$f" --size 640x360 \
                   -o "$OUT/gl_${t}_$f.png" >/dev/null
               peer=$(metric "$OUT/gl_${t}_$f.png" "$OUT/gt_$t.png" "$OUT/mask_$t.png") ;;
        esac
        row="$row | $ours | $peer"
    done
    echo "$row |"
done
