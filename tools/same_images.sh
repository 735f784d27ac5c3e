#!/usr/bin/env bash
# Renders a fixed set of scenes and flag combinations with two texmap binaries and compares
# every pair: a refactoring must leave each image byte-identical (PSNR inf).
#
#   bash tools/same_images.sh OLD_TEXMAP NEW_TEXMAP [OUT_DIR]
#
# Scenes from ../shared/assets are included when the corpus is present. Prints one line per
# case (identical, or the PSNR) and exits 1 if any pair differs or either binary fails.
set -uo pipefail
cd "$(dirname "$0")/.."
OLD=$1 NEW=$2
OUT=${3:-$(mktemp -d)}
mkdir -p "$OUT/a" "$OUT/b"
A=../shared/assets
PD=../shared/peers/data
cases=(
    "demo|builtin:demo"
    "demo-gouraud|builtin:demo --shading gouraud"
    "demo-flat|builtin:demo --shading flat --msaa 4"
    "demo-ssaa|builtin:demo --ssaa 2 --size 320x180"
    "demo-depthsort|builtin:demo --visibility depth-sort --cull back"
    "demo-ortho|builtin:demo --ortho"
    "marble|builtin:marble"
    "sphere|builtin:sphere --tris 20000"
    "sphere-gouraud|builtin:sphere --tris 20000 --shading gouraud --filter aniso4"
    "shapes|scenes/shapes.toml"
    "procedural|scenes/procedural.toml"
    "channels|scenes/channels.toml"
    "textures|scenes/textures.toml"
    "solid3d|scenes/solid_texture3d.toml"
    "volume-toml|scenes/volume.toml --size 320x240"
    "cell|scenes/volumes/cell.nrrd --size 200x200"
)
for f in nearest bilinear trilinear aniso2 aniso16 ewa sat; do
    cases+=("plane-$f|builtin:plane --filter $f")
done
cases+=(
    "plane-affine|builtin:plane --interp affine"
    "plane-subdivide|builtin:plane --interp subdivide"
    "plane-mirror|builtin:plane --wrap mirror --uv-scale 16"
    "plane-bias|builtin:plane --lod-bias 1.5 --lod-rule rss"
)
if [ -d "$PD" ]; then
    cases+=("plane-checker|builtin:plane --texture $PD/checker.png --size 640x360")
fi
if [ -d "$A" ]; then
    for g in "$A"/gltf/*/glTF-Binary/*.glb "$A"/gltf/*/glTF/*.gltf; do
        [ -f "$g" ] || continue
        n=$(basename "$g"); n=${n%.*}
        cases+=("gltf-$n|$g --size 320x240")
    done
    cases+=(
        "gltf-unlit|$A/gltf/Duck/glTF-Binary/Duck.glb --unlit --auto-camera --size 320x240"
        "spot|$A/obj/spot/spot_triangulated.obj --size 320x240"
        "spider|$A/obj/spider/spider.obj --size 320x240"
        "tooth|$A/volumes/tooth_ct/tooth.nhdr --tf ct-bone --size 200x200"
        "tooth-slices|$A/volumes/tooth_ct/tooth.nhdr --tf ct-bone --method slices --size 200x200"
        "mni|$A/volumes/mni152_t1/mni_icbm152_t1_tal_nlin_sym_09a_converted.nii.gz --tf mri --shade --size 200x200"
    )
fi
fail=0
for c in "${cases[@]}"; do
    name=${c%%|*}
    # shellcheck disable=SC2086
    read -r -a args <<< "${c#*|}"
    if ! "$OLD" render "${args[@]}" --quiet -o "$OUT/a/$name.png" 2> "$OUT/a/$name.err"; then
        echo "$name: old binary failed: $(head -1 "$OUT/a/$name.err")"; fail=1; continue
    fi
    if ! "$NEW" render "${args[@]}" --quiet -o "$OUT/b/$name.png" 2> "$OUT/b/$name.err"; then
        echo "$name: new binary failed: $(head -1 "$OUT/b/$name.err")"; fail=1; continue
    fi
    if cmp -s "$OUT/a/$name.png" "$OUT/b/$name.png"; then
        echo "$name: identical"
    else
        echo "$name: DIFFERS, $("$NEW" compare "$OUT/a/$name.png" "$OUT/b/$name.png" | head -1)"
        fail=1
    fi
done
exit $fail
