#!/usr/bin/env bash
# Peer conformance for glTF: renders every model of ../shared/assets/gltf as unlit base colour
# through texmap and through ../shared/peers/gl_render.py (same framing camera, size and
# filter) and prints the PSNR / SSIM between them as a Markdown table.
#
#   tools/peer_gltf.sh [WxH]          (default 640x480; images go to $OUT, default /tmp/texmap-peer)
#
# Two runs per model: `--filter trilinear` (every sampler's filter overridden, as the issue
# asks) and the file's own samplers. TEXMAP=path/to/texmap picks the binary (default: build
# and use target/debug/texmap).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
assets=${ASSETS:-$root/../shared/assets/gltf}
peers=${PEERS:-$root/../shared/peers}
py=$peers/.venv/bin/python
size=${1:-640x480}
out=${OUT:-/tmp/texmap-peer}
mkdir -p "$out"
if [ -z "${TEXMAP:-}" ]; then
  (cd "$root" && cargo build -q -p texmap-cli)
  TEXMAP=$root/target/debug/texmap
fi
if [ ! -d "$assets" ] || [ ! -x "$py" ]; then
  echo "SKIPPED: corpus ($assets) or peer venv ($py) absent"; exit 0
fi
echo "| model | PSNR trilinear (dB) | SSIM trilinear | PSNR file samplers (dB) | SSIM file samplers |"
echo "|---|---:|---:|---:|---:|"
for f in "$assets"/*/glTF*/*.gl[tb]*; do
  name=$(basename "${f%.*}")
  row="| $name"
  for mode in trilinear sampler; do
    flag=(); [ "$mode" = trilinear ] && flag=(--filter trilinear)
    "$py" "$peers/gl_render.py" --scene mesh --mesh "$f" --unlit --srgb --size "$size" "${flag[@]}" \
      -o "$out/$name-$mode-peer.png" > "$out/$name-$mode-peer.json" 2> "$out/$name-$mode-peer.err"
    "$TEXMAP" render "$f" --unlit --auto-camera --size "$size" "${flag[@]}" --quiet \
      -o "$out/$name-$mode-texmap.png" 2> "$out/$name-$mode-texmap.err"
    m=$("$TEXMAP" compare "$out/$name-$mode-peer.png" "$out/$name-$mode-texmap.png" --diff "$out/$name-$mode-diff.png")
    psnr=$(echo "$m" | awk '{print $2}'); ssim=$(echo "$m" | awk '{print $7}')
    row="$row | $psnr | $ssim"
  done
  echo "$row |"
done
