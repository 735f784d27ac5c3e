//! Hand-made container files: every header case parses to the right shape and byte ranges,
//! plain formats decode exactly, and bad input is one error naming the file.

use std::path::Path;

use super::*;
use crate::texture::{Format, TextureOptions};

const NAME: &str = "made.tex";

/// A legacy or DX10 pixel format for [`dds`].
enum Pf {
    FourCc(&'static [u8; 4]),
    Masks {
        flags: u32,
        bits: u32,
        masks: [u32; 4],
    },
    Dx10 {
        dxgi: u32,
        dimension: u32,
        misc: u32,
        array: u32,
    },
}

/// A DDS header (and DX10 header) followed by `data`.
fn dds(w: u32, h: u32, depth: u32, mips: u32, caps2: u32, pf: Pf, data: &[u8]) -> Vec<u8> {
    let mut f = b"DDS ".to_vec();
    let mut hdr = [0u32; 31];
    hdr[0] = 124;
    hdr[1] = 0x1007 | 0x2_0000;
    hdr[2] = h;
    hdr[3] = w;
    hdr[5] = depth;
    hdr[6] = mips;
    hdr[18] = 32;
    let mut dx10 = None;
    match pf {
        Pf::FourCc(cc) => {
            hdr[19] = 0x4;
            hdr[20] = u32::from_le_bytes(*cc);
        }
        Pf::Masks { flags, bits, masks } => {
            hdr[19] = flags;
            hdr[21] = bits;
            hdr[22..26].copy_from_slice(&masks);
        }
        Pf::Dx10 {
            dxgi,
            dimension,
            misc,
            array,
        } => {
            hdr[19] = 0x4;
            hdr[20] = u32::from_le_bytes(*b"DX10");
            dx10 = Some([dxgi, dimension, misc, array, 0]);
        }
    }
    hdr[26] = 0x1000;
    hdr[27] = caps2;
    hdr.iter().for_each(|v| f.extend(v.to_le_bytes()));
    if let Some(x) = dx10 {
        x.iter().for_each(|v| f.extend(v.to_le_bytes()));
    }
    f.extend_from_slice(data);
    f
}

fn parse(bytes: Vec<u8>) -> Result<TextureFile> {
    TextureFile::from_bytes(bytes, Path::new(NAME), &Limits::default())
}

/// Asserts the error names the file and says `what`.
fn refused(bytes: Vec<u8>, what: &str) -> Error {
    let e = parse(bytes).expect_err("bad input must be refused");
    let s = e.to_string();
    assert!(s.contains(NAME) && s.contains(what), "{s}");
    assert!(!s.contains('\n'), "one line: {s}");
    e
}

/// `n` bytes counting up from `seed`.
fn ramp(n: usize, seed: u8) -> Vec<u8> {
    (0..n).map(|i| seed.wrapping_add(i as u8)).collect()
}

const CUBE: u32 = 0x200 | 0xfc00;
const RGB: u32 = 0x40;
const ALPHA: u32 = 0x1;
const BGRA_MASKS: [u32; 4] = [0xff_0000, 0xff00, 0xff, 0xff00_0000];

#[test]
fn dds_dxt1_mip_chain_has_the_block_sizes_of_each_level() {
    // 8x8: 2x2 blocks, then 1 block for 4x4, 2x2 and 1x1.
    let f = parse(dds(8, 8, 0, 4, 0, Pf::FourCc(b"DXT1"), &ramp(32 + 24, 0))).unwrap();
    assert_eq!(f.container(), Container::Dds);
    assert_eq!(f.format(), FileFormat::Block(BlockFormat::Bc1));
    assert_eq!((f.width(), f.height(), f.depth(), f.levels()), (8, 8, 1, 4));
    assert!(f.has_full_chain());
    let sizes: Vec<usize> = (0..4).map(|l| f.data(0, 0, l).unwrap().len()).collect();
    assert_eq!(sizes, [32, 8, 8, 8]);
    assert_eq!(f.data(0, 0, 1).unwrap()[0], 32);
    assert_eq!(f.texel_bytes(), 56);
    let e = f.data(0, 0, 4).unwrap_err().to_string();
    assert!(e.contains("level 4") && e.contains("0 to 3"), "{e}");
}

#[test]
fn dds_sizes_not_multiple_of_four_store_whole_blocks() {
    // 5x3 BC3: 2x1 blocks (32 bytes), then 2x1 → 1 block, 1x1 → 1 block.
    let f = parse(dds(5, 3, 0, 3, 0, Pf::FourCc(b"DXT5"), &ramp(64, 0))).unwrap();
    assert_eq!(f.level_size(1), (2, 1, 1));
    let sizes: Vec<usize> = (0..3).map(|l| f.data(0, 0, l).unwrap().len()).collect();
    assert_eq!(sizes, [32, 16, 16]);
    // 747x600, the DirectX sample's size: 187 x 150 blocks.
    let f = parse(dds(
        747,
        600,
        0,
        1,
        0,
        Pf::FourCc(b"DXT1"),
        &vec![0; 187 * 150 * 8],
    ))
    .unwrap();
    assert_eq!(f.data(0, 0, 0).unwrap().len(), 187 * 150 * 8);
}

#[test]
fn dds_cube_faces_follow_one_another_each_with_its_levels() {
    // BC1 4x4, 3 levels: 8 bytes each; face f, level l at (f·3 + l)·8.
    let data: Vec<u8> = (0..18u8).flat_map(|i| [i; 8]).collect();
    let f = parse(dds(4, 4, 0, 3, CUBE, Pf::FourCc(b"DXT1"), &data)).unwrap();
    assert_eq!((f.faces(), f.layers()), (6, 1));
    for face in 0..6 {
        for level in 0..3 {
            assert_eq!(
                f.data(0, face, level).unwrap(),
                [(face * 3 + level) as u8; 8]
            );
        }
    }
    let partial = dds(4, 4, 0, 1, 0x200 | 0x400, Pf::FourCc(b"DXT1"), &[0; 8]);
    refused(partial, "1 of its 6 faces");
}

#[test]
fn dds_dx10_arrays_cube_arrays_and_srgb() {
    // RGBA8 sRGB 2x2 array of 3 layers, 2 levels: 16 + 4 bytes a layer.
    let pf = Pf::Dx10 {
        dxgi: 29,
        dimension: 3,
        misc: 0,
        array: 3,
    };
    let f = parse(dds(2, 2, 0, 2, 0, pf, &ramp(60, 0))).unwrap();
    assert_eq!(f.color_space(), ColorSpace::Srgb);
    assert_eq!((f.layers(), f.faces(), f.levels()), (3, 1, 2));
    assert_eq!(f.decode_rgba8(2, 0, 0).unwrap(), ramp(16, 40));
    assert_eq!(f.decode_rgba8(1, 0, 1).unwrap(), ramp(4, 36));
    // A cube array of 2: 12 faces of BC7 4x4 (16 bytes).
    let pf = Pf::Dx10 {
        dxgi: 98,
        dimension: 3,
        misc: 4,
        array: 2,
    };
    let data: Vec<u8> = (0..12u8).flat_map(|i| [i; 16]).collect();
    let f = parse(dds(4, 4, 0, 1, 0, pf, &data)).unwrap();
    assert_eq!((f.layers(), f.faces()), (2, 6));
    assert_eq!(f.data(1, 2, 0).unwrap(), [8; 16]);
    assert_eq!(f.format().name(), "BC7");
}

#[test]
fn dds_volume_levels_halve_the_depth_too() {
    // BGRA8 4x4x4 with 3 levels: 256 + 32 + 4 bytes.
    let caps2 = 0x20_0000;
    let pf = Pf::Masks {
        flags: RGB | ALPHA,
        bits: 32,
        masks: BGRA_MASKS,
    };
    let f = parse(dds(4, 4, 4, 3, caps2, pf, &ramp(292, 0))).unwrap();
    assert_eq!(f.depth(), 4);
    assert_eq!(f.level_size(1), (2, 2, 2));
    let l1 = f.decode_rgba8(0, 0, 1).unwrap();
    assert_eq!(l1.len(), 2 * 2 * 2 * 4);
    assert_eq!(&l1[..4], &[2, 1, 0, 3]);
    // The same through the DX10 header (dimension 3D).
    let pf = Pf::Dx10 {
        dxgi: 87,
        dimension: 4,
        misc: 0,
        array: 1,
    };
    let f = parse(dds(4, 4, 4, 3, 0, pf, &ramp(292, 0))).unwrap();
    assert_eq!((f.depth(), f.format().name()), (4, "BGRA8"));
}

#[test]
fn dds_masks_name_the_8_bit_formats() {
    // (pixel-format flags, bits, masks, format, RGBA of texel bytes 1, 2, 3, 4)
    type Case = (u32, u32, [u32; 4], &'static str, [u8; 4]);
    let cases: [Case; 5] = [
        (RGB | ALPHA, 32, BGRA_MASKS, "BGRA8", [3, 2, 1, 4]),
        (
            RGB,
            32,
            [0xff_0000, 0xff00, 0xff, 0],
            "BGRX8",
            [3, 2, 1, 255],
        ),
        (
            RGB | ALPHA,
            32,
            [0xff, 0xff00, 0xff_0000, 0xff00_0000],
            "RGBA8",
            [1, 2, 3, 4],
        ),
        (RGB, 16, [0xff, 0xff00, 0, 0], "RG8", [1, 2, 0, 255]),
        (0x2_0000, 8, [0xff, 0, 0, 0], "L8", [1, 1, 1, 255]),
    ];
    for (flags, bits, masks, name, want) in cases {
        let bytes = (bits / 8) as usize;
        let pf = Pf::Masks { flags, bits, masks };
        let f = parse(dds(1, 1, 0, 1, 0, pf, &[1, 2, 3, 4][..bytes])).unwrap();
        assert_eq!(f.format().name(), name);
        assert_eq!(f.decode_rgba8(0, 0, 0).unwrap(), want, "{name}");
    }
    let pf = Pf::Masks {
        flags: RGB,
        bits: 16,
        masks: [0xf800, 0x7e0, 0x1f, 0],
    };
    refused(dds(1, 1, 0, 1, 0, pf, &[0; 2]), "16 bits with masks 0xf800");
}

#[test]
fn dds_float_formats_decode_to_their_values() {
    let one = 15u32 << 6;
    let texel = (one | (16 << 6) << 11 | (14 << 5) << 22).to_le_bytes();
    let pf = Pf::Dx10 {
        dxgi: 26,
        dimension: 3,
        misc: 0,
        array: 1,
    };
    let f = parse(dds(1, 1, 0, 1, 0, pf, &texel)).unwrap();
    assert_eq!(f.decode_f32(0, 0, 0).unwrap(), [1.0, 2.0, 0.5, 1.0]);
    let e = f.decode_rgba8(0, 0, 0).unwrap_err().to_string();
    assert!(e.contains(NAME) && e.contains("float"), "{e}");
    // RGB9E5 (DXGI 67) and the legacy D3DFMT_A32B32G32R32F (116) in the FourCC field.
    let pf = Pf::Dx10 {
        dxgi: 67,
        dimension: 3,
        misc: 0,
        array: 1,
    };
    let v = (24u32 << 27 | 3 | 5 << 9 | 7 << 18).to_le_bytes();
    let f = parse(dds(1, 1, 0, 1, 0, pf, &v)).unwrap();
    assert_eq!(f.decode_f32(0, 0, 0).unwrap(), [3.0, 5.0, 7.0, 1.0]);
    let texel: Vec<u8> = [0.25f32, -1.0, 8.0, 0.5]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let cc: &'static [u8; 4] = &[116, 0, 0, 0];
    let f = parse(dds(1, 1, 0, 1, 0, Pf::FourCc(cc), &texel)).unwrap();
    assert_eq!(f.decode_f32(0, 0, 0).unwrap(), [0.25, -1.0, 8.0, 0.5]);
}

#[test]
fn dds_bad_input_is_one_line_naming_the_file() {
    refused(b"DDS \x7c\0\0\0".to_vec(), "truncated");
    // One byte of level data missing.
    refused(
        dds(8, 8, 0, 1, 0, Pf::FourCc(b"DXT1"), &[0; 31]),
        "truncated",
    );
    refused(dds(4, 4, 0, 1, 0, Pf::FourCc(b"XYZW"), &[0; 8]), "'XYZW'");
    let pf = Pf::Dx10 {
        dxgi: 45,
        dimension: 3,
        misc: 0,
        array: 1,
    };
    refused(dds(4, 4, 0, 1, 0, pf, &[0; 64]), "DXGI format 45");
    refused(
        dds(0, 4, 0, 1, 0, Pf::FourCc(b"DXT1"), &[0; 8]),
        "zero side",
    );
    refused(dds(4, 4, 0, 9, 0, Pf::FourCc(b"DXT1"), &[0; 200]), "1 to 3");
    let mut bad_size = dds(4, 4, 0, 1, 0, Pf::FourCc(b"DXT1"), &[0; 8]);
    bad_size[4] = 100;
    refused(bad_size, "size of 100");
}

#[test]
fn declared_size_bombs_are_refused_before_allocation() {
    // 65535² with every level declared, in a file of 200 bytes: above the default limits…
    let bomb = dds(65535, 65535, 0, 16, 0, Pf::FourCc(b"DXT5"), &[0; 72]);
    let e = refused(bomb.clone(), "65535x65535");
    assert!(matches!(e, Error::Limits { .. }), "{e}");
    // …and with the limits raised to allow it, the data it declares is not there.
    let open = Limits::default()
        .with_max_dimension(65535)
        .with_max_bytes(u64::MAX / 2);
    let e = TextureFile::from_bytes(bomb, Path::new(NAME), &open).unwrap_err();
    assert!(e.to_string().contains("truncated"), "{e}");
    // A layer count that overflows every product: 2³² − 1 layers of 65535² BC7.
    let pf = Pf::Dx10 {
        dxgi: 98,
        dimension: 3,
        misc: 4,
        array: u32::MAX,
    };
    let e = TextureFile::from_bytes(
        dds(65535, 65535, 0, 16, 0, pf, &[0; 64]),
        Path::new(NAME),
        &open,
    )
    .unwrap_err();
    assert!(e.to_string().contains("truncated"), "{e}");
}

/// A KTX 1 file: header fields after the magic, each level's imageSize and bytes.
fn ktx1(fields: [u32; 13], levels: &[Vec<u8>], big: bool) -> Vec<u8> {
    let word = |v: u32| {
        if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    let mut f = KTX1_MAGIC.to_vec();
    f.extend(word(0x0403_0201));
    fields[1..].iter().for_each(|&v| f.extend(word(v)));
    for l in levels {
        f.extend_from_slice(l);
    }
    f
}

/// KTX 1 header fields (endianness first, ignored): glType, glTypeSize, glFormat,
/// glInternalFormat, glBaseInternalFormat, w, h, depth, elements, faces, mips, kvd bytes.
#[allow(clippy::too_many_arguments)]
fn ktx1_fields(
    internal: u32,
    gl_format: u32,
    w: u32,
    h: u32,
    elements: u32,
    faces: u32,
    mips: u32,
) -> [u32; 13] {
    [
        0, 0x1401, 1, gl_format, internal, gl_format, w, h, 0, elements, faces, mips, 0,
    ]
}

fn with_size(size: u32, data: &[u8]) -> Vec<u8> {
    let mut v = size.to_le_bytes().to_vec();
    v.extend_from_slice(data);
    v
}

#[test]
fn ktx1_cube_of_r11g11b10f_faces_each_sized_by_image_size() {
    // 2x2 faces of 16 bytes, 2 levels; imageSize is one face's for a non-array cube.
    let face = |f: u8, n: usize| -> Vec<u8> {
        (0..n)
            .flat_map(|_| ((15u32 << 6) * u32::from(f + 1)).to_le_bytes())
            .collect()
    };
    let l0: Vec<u8> = (0..6).flat_map(|f| face(f, 4)).collect();
    let l1: Vec<u8> = (0..6).flat_map(|f| face(f, 1)).collect();
    let fields = ktx1_fields(0x8c3a, 0x1907, 2, 2, 0, 6, 2);
    let f = parse(ktx1(
        fields,
        &[with_size(16, &l0), with_size(4, &l1)],
        false,
    ))
    .unwrap();
    assert_eq!(
        (f.container(), f.faces(), f.levels()),
        (Container::Ktx, 6, 2)
    );
    assert_eq!(f.format().name(), "R11G11B10F");
    for face in 0..6u32 {
        let want = super::plain::r11g11b10f((15u32 << 6) * (face + 1))[0];
        assert_eq!(f.decode_f32(0, face, 1).unwrap()[0], want);
        assert_eq!(f.data(0, face, 0).unwrap().len(), 16);
    }
    // A wrong imageSize is named.
    let e = parse(ktx1(
        fields,
        &[with_size(96, &l0), with_size(4, &l1)],
        false,
    ));
    let e = e.unwrap_err().to_string();
    assert!(
        e.contains("imageSize is 96") && e.contains("needs 16"),
        "{e}"
    );
}

#[test]
fn ktx1_big_endian_and_padded_rows_are_repacked() {
    // RGBA16F 1x1 big-endian: each half swapped.
    let halves = [0.5f32, 1.0, 2.0, 0.25].map(crate::texture::f32_to_f16);
    let texel: Vec<u8> = halves.iter().flat_map(|h| h.to_be_bytes()).collect();
    let mut level = 8u32.to_be_bytes().to_vec();
    level.extend(&texel);
    let fields = ktx1_fields(0x881a, 0x1908, 1, 1, 0, 1, 1);
    let f = parse(ktx1(fields, &[level], true)).unwrap();
    assert_eq!(f.decode_f32(0, 0, 0).unwrap(), [0.5, 1.0, 2.0, 0.25]);
    // R8 3x2: rows of 3 bytes padded to 4.
    let fields = ktx1_fields(0x8229, 0x1903, 3, 2, 0, 1, 1);
    let f = parse(ktx1(
        fields,
        &[with_size(8, &[1, 2, 3, 0, 4, 5, 6, 0])],
        false,
    ))
    .unwrap();
    let r: Vec<u8> = f
        .decode_rgba8(0, 0, 0)
        .unwrap()
        .chunks(4)
        .map(|t| t[0])
        .collect();
    assert_eq!(r, [1, 2, 3, 4, 5, 6]);
    // GL_RGBA8 given as GL_BGRA.
    let fields = ktx1_fields(0x8058, 0x80e1, 1, 1, 0, 1, 1);
    let f = parse(ktx1(fields, &[with_size(4, &[1, 2, 3, 4])], false)).unwrap();
    assert_eq!(f.decode_rgba8(0, 0, 0).unwrap(), [3, 2, 1, 4]);
}

#[test]
fn ktx1_arrays_size_the_whole_level_and_bad_input_is_named() {
    // A BC7 array of 2 layers 4x4: imageSize covers both.
    let fields = ktx1_fields(0x8e8d, 0, 4, 4, 2, 1, 1);
    let f = parse(ktx1(fields, &[with_size(32, &ramp(32, 0))], false)).unwrap();
    assert_eq!((f.layers(), f.color_space()), (2, ColorSpace::Srgb));
    assert_eq!(f.data(1, 0, 0).unwrap(), ramp(16, 16));
    refused(
        ktx1(fields, &[with_size(32, &ramp(20, 0))], false),
        "truncated",
    );
    let unknown = ktx1_fields(0x9274, 0, 4, 4, 0, 1, 1); // ETC2, not read
    refused(ktx1(unknown, &[with_size(8, &[0; 8])], false), "0x9274");
    let mut bad_endian = ktx1(fields, &[], false);
    bad_endian[12] = 9;
    refused(bad_endian, "endianness");
}

/// A zstd frame of raw blocks holding `data` (a valid frame any decoder reads).
fn zstd_raw(data: &[u8]) -> Vec<u8> {
    let mut f = 0xFD2F_B528u32.to_le_bytes().to_vec();
    f.push(0xa0); // single segment, 4-byte content size
    f.extend((data.len() as u32).to_le_bytes());
    let chunks: Vec<&[u8]> = data.chunks(1 << 16).collect();
    for (i, c) in chunks.iter().enumerate() {
        let last = u32::from(i + 1 == chunks.len());
        let header = last | (c.len() as u32) << 3;
        f.extend(&header.to_le_bytes()[..3]);
        f.extend_from_slice(c);
    }
    f
}

/// A KTX2 file: `vk` format, shape, scheme, and each level's stored bytes and uncompressed
/// length; `model` the descriptor's colour model.
#[allow(clippy::too_many_arguments)]
fn ktx2(
    vk: u32,
    w: u32,
    h: u32,
    layers: u32,
    faces: u32,
    scheme: u32,
    model: u8,
    levels: &[(Vec<u8>, u64)],
) -> Vec<u8> {
    let mut f = KTX2_MAGIC.to_vec();
    let n = levels.len() as u32;
    let index_end = 80 + 24 * levels.len();
    let dfd = index_end as u32;
    let dfd_len = 4 + 8 + 16;
    for v in [vk, 1, w, h, 0, layers, faces, n, scheme, dfd, dfd_len, 0, 0] {
        f.extend(v.to_le_bytes());
    }
    f.extend(0u64.to_le_bytes()); // sgd offset
    f.extend(0u64.to_le_bytes()); // sgd length
    let mut at = (index_end + dfd_len as usize) as u64;
    for (data, uncompressed) in levels {
        f.extend(at.to_le_bytes());
        f.extend((data.len() as u64).to_le_bytes());
        f.extend(uncompressed.to_le_bytes());
        at += data.len() as u64;
    }
    f.extend(dfd_len.to_le_bytes());
    f.extend(0u32.to_le_bytes()); // Khronos basic block
    f.extend(2u16.to_le_bytes());
    f.extend(24u16.to_le_bytes());
    f.extend([model, 1, 1, 0, 3, 3, 0, 0, 16, 0, 0, 0, 0, 0, 0, 0]);
    for (data, _) in levels {
        f.extend_from_slice(data);
    }
    f
}

#[test]
fn ktx2_plain_zstd_and_zlib_levels_decode_alike() {
    // RGBA8 sRGB 2x2, 2 levels.
    let (l0, l1) = (ramp(16, 0), ramp(4, 100));
    let plain = ktx2(43, 2, 2, 0, 1, 0, 1, &[(l0.clone(), 16), (l1.clone(), 4)]);
    let zstd = ktx2(
        43,
        2,
        2,
        0,
        1,
        2,
        1,
        &[(zstd_raw(&l0), 16), (zstd_raw(&l1), 4)],
    );
    let zlib_of = |d: &[u8]| {
        use std::io::Write as _;
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::best());
        z.write_all(d).unwrap();
        z.finish().unwrap()
    };
    let zlib = ktx2(
        43,
        2,
        2,
        0,
        1,
        3,
        1,
        &[(zlib_of(&l0), 16), (zlib_of(&l1), 4)],
    );
    for bytes in [plain, zstd, zlib] {
        let f = parse(bytes).unwrap();
        assert_eq!(
            (f.container(), f.color_space()),
            (Container::Ktx2, ColorSpace::Srgb)
        );
        assert_eq!(f.decode_rgba8(0, 0, 0).unwrap(), l0);
        assert_eq!(f.decode_rgba8(0, 0, 1).unwrap(), l1);
    }
    // A BC7 cube, 6 faces of one block each, zstd: faces in order inside the level.
    let faces: Vec<u8> = (0..6u8).flat_map(|i| [i; 16]).collect();
    let f = parse(ktx2(146, 4, 4, 0, 6, 2, 1, &[(zstd_raw(&faces), 96)])).unwrap();
    assert_eq!(f.faces(), 6);
    assert_eq!(f.data(0, 5, 0).unwrap(), [5; 16]);
}

#[test]
fn ktx2_bad_input_and_basis_are_named() {
    let l0 = ramp(16, 0);
    // The level index points past the end.
    let mut past = ktx2(37, 2, 2, 0, 1, 0, 1, &[(l0.clone(), 16)]);
    past[80..88].copy_from_slice(&10_000u64.to_le_bytes());
    refused(past, "level 0's data (offset 10000");
    // The index itself is cut off.
    let full = ktx2(37, 2, 2, 0, 1, 0, 1, &[(l0.clone(), 16)]);
    refused(full[..90].to_vec(), "level index");
    // A level of the wrong size, an inflated size that lies, corrupt zstd.
    refused(
        ktx2(37, 2, 2, 0, 1, 0, 1, &[(ramp(12, 0), 12)]),
        "holds 12 bytes",
    );
    refused(
        ktx2(37, 2, 2, 0, 1, 2, 1, &[(zstd_raw(&l0), 20)]),
        "holds 20 bytes",
    );
    refused(
        ktx2(37, 2, 2, 0, 1, 2, 1, &[(zstd_raw(&l0[..8]), 16)]),
        "inflates to 8",
    );
    refused(
        ktx2(37, 2, 2, 0, 1, 2, 1, &[(vec![1, 2, 3, 4, 5], 16)]),
        "corrupt",
    );
    refused(ktx2(4, 2, 2, 0, 1, 0, 1, &[(ramp(8, 0), 8)]), "VkFormat 4");
    // Basis Universal, told as ETC1S (BasisLZ) and UASTC (its colour model), with no real
    // Basis data: the transcoder refuses it, one line naming the codec.
    let e = refused(ktx2(0, 4, 4, 0, 1, 1, 163, &[(vec![0; 16], 0)]), "Basis");
    assert!(e
        .to_string()
        .contains("KTX2 Basis Universal (ETC1S) data is invalid"));
    let e = refused(
        ktx2(0, 4, 4, 0, 1, 2, 166, &[(zstd_raw(&[0; 16]), 16)]),
        "Basis",
    );
    assert!(e
        .to_string()
        .contains("KTX2 Basis Universal (UASTC) data is invalid"));
    // A descriptor block dimension of 255 (which the crate's parser panics on) is harmless.
    let mut dims = ktx2(37, 2, 2, 0, 1, 0, 1, &[(l0, 16)]);
    let model_at = 80 + 24 + 12;
    dims[model_at + 4] = 255;
    assert!(parse(dims).is_ok());
}

/// A DDS of 4x4 BGRA8 with `levels` levels, level `l` filled with opaque grey `40·(l + 1)`.
fn grey_levels(levels: u32) -> Vec<u8> {
    let data: Vec<u8> = (0..levels)
        .flat_map(|l| {
            let n = (4usize >> l).max(1);
            let g = 40 * (l as u8 + 1);
            [g, g, g, 255].repeat(n * n)
        })
        .collect();
    let pf = Pf::Masks {
        flags: RGB | ALPHA,
        bits: 32,
        masks: BGRA_MASKS,
    };
    dds(4, 4, 0, levels, 0, pf, &data)
}

#[test]
fn a_full_file_chain_is_kept_and_a_partial_one_rebuilt() {
    let options = TextureOptions::default();
    let full = parse(grey_levels(3)).unwrap();
    let t = texture_from_file(&full, ColorSpace::Linear, options).unwrap();
    assert_eq!((t.format(), t.levels().len()), (Format::Rgba8, 3));
    // Level 2 is the file's grey 120, not the average of level 0's 40.
    assert!((t.texel(2, 0, 0).x - 120.0 / 255.0).abs() < 1e-4);
    let partial = parse(grey_levels(2)).unwrap();
    let t = texture_from_file(&partial, ColorSpace::Linear, options).unwrap();
    assert_eq!(t.levels().len(), 3);
    assert!((t.texel(1, 0, 0).x - 40.0 / 255.0).abs() < 1e-4);
}

#[test]
fn cubes_become_cube_maps_and_only_cube_maps() {
    // BGRA8 2x2 cube, face f opaque grey 40·f.
    let data: Vec<u8> = (0..6u8)
        .flat_map(|f| [40 * f, 40 * f, 40 * f, 255].repeat(4))
        .collect();
    let pf = Pf::Masks {
        flags: RGB | ALPHA,
        bits: 32,
        masks: BGRA_MASKS,
    };
    let f = parse(dds(2, 2, 0, 1, CUBE, pf, &data)).unwrap();
    let cube = cube_from_file(&f, ColorSpace::Linear, TextureOptions::default()).unwrap();
    for (i, face) in cube.faces().iter().enumerate() {
        assert!((face.texel(0, 1, 1).y - (40 * i) as f32 / 255.0).abs() < 1e-4);
    }
    let e = texture_from_file(&f, ColorSpace::Srgb, TextureOptions::default()).unwrap_err();
    assert!(
        e.to_string()
            .contains("is a cube map; a 2D texture is needed"),
        "{e}"
    );
    let flat = parse(grey_levels(1)).unwrap();
    let e = cube_from_file(&flat, ColorSpace::Srgb, TextureOptions::default()).unwrap_err();
    assert!(
        e.to_string()
            .contains("a cube map (6 faces, 1 layer) is needed"),
        "{e}"
    );
}

#[test]
fn srgb_formats_keep_srgb_and_floats_stay_linear() {
    let pf = Pf::Dx10 {
        dxgi: 29,
        dimension: 3,
        misc: 0,
        array: 1,
    };
    let f = parse(dds(1, 1, 0, 1, 0, pf, &[128, 128, 128, 255])).unwrap();
    let t = texture_from_file(&f, ColorSpace::Linear, TextureOptions::default()).unwrap();
    assert_eq!(t.color_space(), ColorSpace::Srgb);
    let want = crate::color::srgb_to_linear(128.0 / 255.0);
    assert!((t.texel(0, 0, 0).x - want).abs() < 1e-4);
    let cc: &'static [u8; 4] = &[113, 0, 0, 0];
    let halves: Vec<u8> = [3.5f32, 0.0, 0.0, 1.0]
        .iter()
        .flat_map(|&v| crate::texture::f32_to_f16(v).to_le_bytes())
        .collect();
    let f = parse(dds(1, 1, 0, 1, 0, Pf::FourCc(cc), &halves)).unwrap();
    let t = texture_from_file(&f, ColorSpace::Srgb, TextureOptions::default()).unwrap();
    assert_eq!(
        (t.format(), t.color_space()),
        (Format::Rgba16F, ColorSpace::Linear)
    );
    assert_eq!(t.texel(0, 0, 0).x, 3.5);
}
