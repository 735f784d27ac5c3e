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
# Real models and scans from the shared corpus, when it is present.
a=../shared/assets
if [ -d "$a" ]; then
  "$t" render "$a/gltf/DamagedHelmet/glTF-Binary/DamagedHelmet.glb" \
    --env "$a/env/equirect/venice_sunset_1k.hdr" --size 320x180 --ssaa 2 -q -o docs/gallery/helmet.png
  "$t" render "$a/gltf/AnisotropyBarnLamp/glTF-KTX2-Basisu/AnisotropyBarnLamp.gltf" \
    --env "$a/env/equirect/venice_sunset_1k.hdr" --background color \
    --eye -0.42,-0.09,0.18 --target 0,-0.07,0.11 --size 280x300 --ssaa 2 -q \
    -o docs/gallery/barn_lamp.png
  "$t" render "$a/volumes/tooth_ct/tooth.nhdr" --shade --size 320x180 -q -o docs/gallery/tooth_ct.png
  mni="$a/volumes/mni152_t1/mni_icbm152_t1_tal_nlin_sym_09a_converted.nii.gz"
  "$t" render "$mni" --shade --size 320x180 -q -o docs/gallery/mni_mri.png
  "$t" render "$mni" --slice sagittal --window 255 --level 128 --size 320x180 -q \
    -o docs/gallery/mni_sagittal.png
else
  echo "../shared/assets is absent: the real models' images are kept as they are" >&2
fi
ls -l docs/gallery
