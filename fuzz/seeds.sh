#!/usr/bin/env bash
# Fills corpus/<target>/ with seed inputs: small files from the repository and, when it is
# beside the repository, from ../shared/assets; plus a few made here. Safe to re-run.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/.." && pwd)
assets="$repo/../shared/assets"
c="$here/corpus"
mkdir -p "$c"/{gltf,glb,obj,toml,image,nifti,nrrd,raw}

# Files below 64 KiB only: big seeds slow every execution down.
small() { find "$@" -type f -size -64k 2>/dev/null || true; }
seed() { # target files...
  local t=$1; shift
  for f in "$@"; do cp -f "$f" "$c/$t/$(basename "$f")"; done
}

seed gltf $(small "$repo/crates/texmap/tests/fuzz_regressions/gltf" "$assets/gltf" -name '*.gltf')
seed glb $(small "$assets/gltf" -name '*.glb')
seed obj $(small "$repo/crates/texmap/tests/fuzz_regressions/obj" "$assets/obj" -name '*.obj')
seed toml $(small "$repo/scenes" -name '*.toml')
seed image $(small "$repo/crates/texmap/tests/golden" "$assets/textures" "$assets/env" "$assets/gltf" \
  \( -name '*.png' -o -name '*.jpg' -o -name '*.hdr' -o -name '*.exr' \))
seed nrrd $(small "$repo/scenes/volumes" "$repo/crates/texmap/tests/fuzz_regressions/nrrd" \
  \( -name '*.nrrd' -o -name '*.nhdr' \))

# An OBJ with its MTL after a `#MTL` line (the harness's convention), a detached NRRD with
# its data after `#DATA`, NIfTI-1 files (plain and gzipped), raw volumes, and small images in
# the formats no committed file has.
python3 - "$c" <<'PY'
import gzip, struct, sys, zlib
c = sys.argv[1]
open(f"{c}/obj/with_mtl.obj", "wb").write(
    b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nusemtl m\n"
    b"f 1/1/1 2/2/1 3/3/1\n#MTL\nnewmtl m\nKa 0.1 0.1 0.1\nKd 0.8 0.2 0.2\nKs 1 1 1\nNs 32\nd 0.5\nmap_Kd t.png\n")
open(f"{c}/nrrd/detached.nhdr", "wb").write(
    b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nspacings: 1 1 2\nencoding: raw\n"
    b"data file: d.raw\n\n#DATA" + bytes(range(64)))
open(f"{c}/nrrd/gzip.nrrd", "wb").write(
    b"NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 2\nendian: little\nencoding: gzip\n\n"
    + gzip.compress(struct.pack("<8h", *range(8))))
def nifti(dtype, bitpix, data):
    h = bytearray(352)
    struct.pack_into("<i", h, 0, 348)
    struct.pack_into("<8h", h, 40, 3, 4, 4, 4, 1, 1, 1, 1)
    struct.pack_into("<hh", h, 70, dtype, bitpix)
    struct.pack_into("<8f", h, 76, 1, 1, 1, 2, 0, 0, 0, 0)
    struct.pack_into("<f", h, 108, 352)
    struct.pack_into("<hh", h, 252, 1, 0)
    h[344:348] = b"n+1\0"
    return bytes(h) + data
open(f"{c}/nifti/u8.nii", "wb").write(nifti(2, 8, bytes(range(64))))
open(f"{c}/nifti/f32.nii", "wb").write(nifti(16, 32, struct.pack("<64f", *range(64))))
open(f"{c}/nifti/i16.nii.gz", "wb").write(gzip.compress(nifti(4, 16, struct.pack("<64h", *range(64)))))
open(f"{c}/raw/u8", "wb").write(bytes([3, 3, 3, 0]) + bytes(range(64)))
open(f"{c}/raw/f32be", "wb").write(bytes([1, 1, 1, 0x86]) + struct.pack(">8f", *range(8)))
# A 2×2 Radiance HDR (uncompressed scanlines) and a 2×2 binary PPM.
open(f"{c}/image/tiny.hdr", "wb").write(
    b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 2\n" + bytes([128, 64, 32, 129] * 4))
open(f"{c}/image/tiny.ppm", "wb").write(b"P6 2 2 255\n" + bytes(range(12)))
PY
for t in gltf glb obj toml image nifti nrrd raw; do
  printf '%-6s %3d seeds\n' "$t" "$(ls "$c/$t" | wc -l)"
done
