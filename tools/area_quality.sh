#!/usr/bin/env bash
# The area level against the GL extension's: PSNR (dB) of aniso5, aniso6 and aniso5-area on
# the grazing-angle plane, against the box-filtered ground truth, for the peers' checker and
# noise and the photographs of ../shared/assets/textures/photos.
#
#   bash tools/area_quality.sh [OUT_DIR] [FILTER...]   (needs bash ../shared/peers/setup.sh once)
#
# 640x360, linear-light mode (ground_truth.py --srgb), PSNR over the plane's pixels
# (--mask-out), as tools/plane_quality.sh measures. Prints a Markdown table.
set -euo pipefail
cd "$(dirname "$0")/.."
P=${PEERS:-../shared/peers}
PY=$P/.venv/bin/python
PHOTOS=${PHOTOS:-../shared/assets/textures/photos}
OUT=${1:-target/area-quality}
shift $(( $# > 0 ? 1 : 0 ))
FILTERS=("$@")
[ ${#FILTERS[@]} -gt 0 ] || FILTERS=(aniso5 aniso6 aniso5-area)
mkdir -p "$OUT"
cargo build --release --quiet
TEXMAP=target/release/texmap
textures=("$P/data/checker.png" "$P/data/noise.png")
for f in grass.png coffee.png camera.png rocket.jpg gravel.png brick.png; do
    [ -f "$PHOTOS/$f" ] && textures+=("$PHOTOS/$f")
done
header="| texture"
for f in "${FILTERS[@]}"; do header="$header | $f"; done
echo "$header |"
echo "|---$(printf '|---%.0s' "${FILTERS[@]}")|"
for tex in "${textures[@]}"; do
    t=$(basename "$tex")
    [ -f "$OUT/gt_$t.png" ] || "$PY" "$P/ground_truth.py" --texture "$tex" --srgb --size 640x360 \
        -o "$OUT/gt_$t.png" --mask-out "$OUT/mask_$t.png" >/dev/null
    row="| $t"
    for f in "${FILTERS[@]}"; do
        "$TEXMAP" render builtin:plane --texture "$tex" --filter "$f" --size 640x360 \
            -o "$OUT/texmap_${t}_$f.png" --quiet
        psnr=$("$PY" "$P/metrics.py" "$OUT/texmap_${t}_$f.png" "$OUT/gt_$t.png" --mask "$OUT/mask_$t.png" \
            | "$PY" -c 'import json,sys; print("%.2f" % json.load(sys.stdin)["masked"]["psnr_db"])')
        row="$row | $psnr"
    done
    echo "$row |"
done
