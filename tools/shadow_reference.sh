#!/usr/bin/env bash
# Shadow maps against a path tracer: renders ../shared/peers/mitsuba_ref.py's `shadow` scene
# (Mitsuba 3, direct light, hard shadows) and scenes/reference/shadow.toml through texmap at
# the same size, and prints the PSNR (8-bit sRGB, RGB) between them.
#
#   tools/shadow_reference.sh [WxH] [SPP] [texmap render flags…]
#       (default 256x256, 1024 spp; texmap renders with --ssaa 4 and the flags given)
#
# Mitsuba's image is cached in $CACHE (default /tmp/texmap-shadow-ref): it takes minutes.
# TEXMAP=path/to/texmap picks the binary (default: build and use target/debug/texmap).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
peers=${PEERS:-$root/../shared/peers}
py=$peers/.venv/bin/python
size=${1:-256x256}
spp=${2:-1024}
shift $(( $# < 2 ? $# : 2 ))
cache=${CACHE:-/tmp/texmap-shadow-ref}
if [ ! -x "$py" ]; then
  echo "SKIPPED: peer venv ($py) absent (bash ../shared/peers/setup.sh)"; exit 0
fi
if [ -z "${TEXMAP:-}" ]; then
  (cd "$root" && cargo build -q -p texmap-cli)
  TEXMAP=$root/target/debug/texmap
fi
mkdir -p "$cache"
ref=$cache/mitsuba-shadow-$size-$spp.png
if [ ! -f "$ref" ]; then
  "$py" "$peers/mitsuba_ref.py" shadow --size "$size" --spp "$spp" -o "$ref" >/dev/null
fi
ours=$cache/texmap-shadow-$size.png
"$TEXMAP" render "$root/scenes/reference/shadow.toml" --size "$size" --ssaa 4 --quiet -o "$ours" "$@"
"$py" "$peers/metrics.py" "$ref" "$ours" | "$py" -c '
import json, sys
d = json.load(sys.stdin)
print("shadow: PSNR %.2f dB, SSIM %.4f (Mitsuba %s spp vs texmap --ssaa 4)" % (d["psnr_db"], d["ssim"], sys.argv[1]))' "$spp"
