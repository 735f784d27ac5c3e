#!/usr/bin/env bash
# Renders the README's gallery (docs/gallery/*.png) with the release build.
#   bash tools/gallery.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q
t=target/release/texmap
mkdir -p docs/gallery
"$t" render --size 320x180 --ssaa 2 -q -o docs/gallery/demo.png
for s in environment reflect refract ibl transmission shadows projector multitexture detail lightmap toon; do
  "$t" render "scenes/$s.toml" --size 320x180 --ssaa 2 -q -o "docs/gallery/$s.png"
done
for s in parallax displacement normal bump; do
  "$t" render "scenes/$s.toml" --size 320x180 --ssaa 2 -q -o "docs/gallery/$s.png"
done
ls -l docs/gallery
