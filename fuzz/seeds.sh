#!/usr/bin/env bash
# Fills corpus/<target>/ with seed inputs: small files from the repository and, when it is
# beside the repository, from ../shared/assets; plus a few made here. Safe to re-run.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/.." && pwd)
assets="$repo/../shared/assets"
c="$here/corpus"
mkdir -p "$c"/{gltf,glb,obj,toml,image,nifti,nrrd,raw,dds,ktx,ktx2}

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
seed dds $(small "$repo/crates/texmap/tests/fuzz_regressions/dds" "$assets/compressed" -iname '*.dds')
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
# Texture containers: DDS (legacy FourCC, masks, DX10; mips, cube, array, volume), KTX 1
# (little- and big-endian, cube, padded rows) and KTX2 (plain, zstd, zlib; cube).
def dds(w, h, depth, mips, caps2, pf, data, dx10=None):
    v = [0] * 31
    v[0], v[1], v[2], v[3], v[5], v[6] = 124, 0x21007, h, w, depth, mips
    v[18], v[19], v[20], v[21] = 32, pf[0], pf[1], pf[2]
    v[22:26] = pf[3]
    v[26], v[27] = 0x1000, caps2
    return b"DDS " + struct.pack("<31I", *v) + (struct.pack("<5I", *dx10) if dx10 else b"") + data
cc = lambda s: struct.unpack("<I", s)[0]
BGRA = (0x41, 0, 32, [0xFF0000, 0xFF00, 0xFF, 0xFF000000])
FOURCC = lambda s: (0x4, cc(s), 0, [0] * 4)
open(f"{c}/dds/dxt1_mips.dds", "wb").write(dds(8, 8, 0, 4, 0, FOURCC(b"DXT1"), bytes(range(56))))
open(f"{c}/dds/dxt5_5x3.dds", "wb").write(dds(5, 3, 0, 3, 0, FOURCC(b"DXT5"), bytes(64)))
open(f"{c}/dds/bgra_cube.dds", "wb").write(dds(2, 2, 0, 2, 0xFE00, BGRA, bytes(range(120))))
open(f"{c}/dds/bgra_volume.dds", "wb").write(dds(4, 4, 4, 3, 0x200000, BGRA, bytes(292)))
open(f"{c}/dds/bc7_array.dds", "wb").write(
    dds(4, 4, 0, 1, 0, FOURCC(b"DX10"), bytes(range(48)), [98, 3, 0, 3, 0]))
open(f"{c}/dds/r11g11b10.dds", "wb").write(
    dds(2, 2, 0, 2, 0, FOURCC(b"DX10"), struct.pack("<5I", *[15 << 6] * 5), [26, 3, 0, 1, 0]))
KTX1 = b"\xABKTX 11\xBB\r\n\x1A\n"
def ktx1(fields, levels, big=False):
    e = ">" if big else "<"
    out = KTX1 + struct.pack(e + "13I", 0x04030201, *fields)
    for data, size in levels:
        out += struct.pack(e + "I", size) + data
    return out
open(f"{c}/ktx/r11_cube.ktx", "wb").write(
    ktx1([0x8C3B, 4, 0x1907, 0x8C3A, 0x1907, 2, 2, 0, 0, 6, 2, 0],
         [(bytes(96), 16), (bytes(24), 4)]))
open(f"{c}/ktx/rgba16f_big.ktx", "wb").write(
    ktx1([0x140B, 2, 0x1908, 0x881A, 0x1908, 1, 1, 0, 0, 1, 1, 0],
         [(struct.pack(">4H", 0x3800, 0x3C00, 0x4000, 0x3400), 8)], big=True))
open(f"{c}/ktx/r8_padded.ktx", "wb").write(
    ktx1([0x1401, 1, 0x1903, 0x8229, 0x1903, 3, 2, 0, 0, 1, 1, 0], [(bytes(range(8)), 8)]))
open(f"{c}/ktx/bc1_mips.ktx", "wb").write(
    ktx1([0, 1, 0, 0x83F1, 0x1908, 4, 4, 0, 0, 1, 3, 0], [(bytes(8), 8)] * 3))
KTX2 = b"\xABKTX 20\xBB\r\n\x1A\n"
def zstd_raw(data):
    return (struct.pack("<IB", 0xFD2FB528, 0xA0) + struct.pack("<I", len(data))
            + struct.pack("<I", 1 | len(data) << 3)[:3] + data)
def ktx2(vk, w, h, faces, scheme, levels, model=1):
    index_end = 80 + 24 * len(levels)
    out = KTX2 + struct.pack("<13I", vk, 1, w, h, 0, 0, faces, len(levels), scheme,
                             index_end, 28, 0, 0) + struct.pack("<2Q", 0, 0)
    at = index_end + 28
    for data, size in levels:
        out += struct.pack("<3Q", at, len(data), size)
        at += len(data)
    out += struct.pack("<IIHH", 28, 0, 2, 24) + bytes([model, 1, 1, 0, 3, 3, 0, 0, 16] + [0] * 7)
    return out + b"".join(d for d, _ in levels)
open(f"{c}/ktx2/rgba8_mips.ktx2", "wb").write(ktx2(43, 2, 2, 1, 0, [(bytes(16), 16), (bytes(4), 4)]))
open(f"{c}/ktx2/zstd.ktx2", "wb").write(ktx2(37, 2, 2, 1, 2, [(zstd_raw(bytes(range(16))), 16)]))
open(f"{c}/ktx2/zlib.ktx2", "wb").write(ktx2(37, 2, 2, 1, 3, [(zlib.compress(bytes(16)), 16)]))
open(f"{c}/ktx2/bc7_cube.ktx2", "wb").write(ktx2(146, 4, 4, 6, 2, [(zstd_raw(bytes(96)), 96)]))
open(f"{c}/ktx2/uastc.ktx2", "wb").write(ktx2(0, 4, 4, 1, 2, [(zstd_raw(bytes(16)), 16)], model=166))
PY
for t in gltf glb obj toml image nifti nrrd raw dds ktx ktx2; do
  printf '%-6s %3d seeds\n' "$t" "$(ls "$c/$t" | wc -l)"
done
