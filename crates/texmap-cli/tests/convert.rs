//! `texmap convert` and `texmap info` on texture files, and texture files where the renderer
//! takes textures (`--texture`, `--env`): hand-made DDS files (built here, not committed),
//! exact bytes out, every index out of range and every bad file one line, exit 1, no output.

mod common;

use common::texmap;
use std::path::{Path, PathBuf};
use std::process::Output;

fn dir(name: &str) -> PathBuf {
    common::fresh_dir("convert", name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A DDS header: `pf` is (flags, FourCC, bits, masks); `dx10` the DXGI header when given.
fn dds_header(
    w: u32,
    h: u32,
    depth: u32,
    mips: u32,
    caps2: u32,
    pf: (u32, [u8; 4], u32, [u32; 4]),
    dx10: Option<[u32; 5]>,
) -> Vec<u8> {
    let mut hdr = [0u32; 31];
    (hdr[0], hdr[1], hdr[2], hdr[3], hdr[5], hdr[6]) = (124, 0x2_1007, h, w, depth, mips);
    (hdr[18], hdr[19], hdr[20], hdr[21]) = (32, pf.0, u32::from_le_bytes(pf.1), pf.2);
    hdr[22..26].copy_from_slice(&pf.3);
    (hdr[26], hdr[27]) = (0x1000, caps2);
    let mut f = b"DDS ".to_vec();
    hdr.iter().for_each(|v| f.extend(v.to_le_bytes()));
    if let Some(x) = dx10 {
        x.iter().for_each(|v| f.extend(v.to_le_bytes()));
    }
    f
}

const BGRA: (u32, [u8; 4], u32, [u32; 4]) =
    (0x41, [0; 4], 32, [0xff_0000, 0xff00, 0xff, 0xff00_0000]);
const CUBE: u32 = 0xfe00;
const VOLUME: u32 = 0x20_0000;

/// Texel `i` of image `image` (BGRA bytes): distinct everywhere.
fn texel(image: u8, i: usize) -> [u8; 4] {
    [image.wrapping_mul(40), i as u8, 255 - i as u8, 128 + image]
}

/// A BGRA8 DDS of `w`x`h` (depth `depth`), `images` images of `levels` levels each, every
/// texel distinct; returns the file and each image's expected RGBA bytes.
fn bgra_dds(
    w: u32,
    h: u32,
    depth: u32,
    levels: u32,
    caps2: u32,
    images: u8,
) -> (Vec<u8>, Vec<Vec<u8>>) {
    let mut f = dds_header(w, h, depth, levels, caps2, BGRA, None);
    let mut rgba = Vec::new();
    let mut n = 0u8;
    for _ in 0..images {
        for l in 0..levels {
            let count = ((w >> l).max(1) * (h >> l).max(1) * (depth >> l).max(1)) as usize;
            let mut want = Vec::new();
            for i in 0..count {
                let t = texel(n, i);
                f.extend(t);
                want.extend([t[2], t[1], t[0], t[3]]);
            }
            rgba.push(want);
            n += 1;
        }
    }
    (f, rgba)
}

fn read_png(p: &Path) -> (u32, u32, Vec<u8>) {
    let img = image::open(p).unwrap().to_rgba8();
    (img.width(), img.height(), img.into_raw())
}

/// Asserts a failure: exit 1, one line on stderr with every needle, no output file.
fn assert_fails(out: &Output, needles: &[&str], output_file: &Path) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(
        stderr.trim().lines().count(),
        1,
        "one line expected: {stderr}"
    );
    for n in needles {
        assert!(stderr.contains(n), "{n:?} not in {stderr:?}");
    }
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        !output_file.exists(),
        "a failed run left {}",
        output_file.display()
    );
}

#[test]
fn every_level_converts_to_exactly_its_bytes() {
    let d = dir("levels");
    let (file, want) = bgra_dds(8, 4, 1, 4, 0, 1);
    let input = d.join("t.dds");
    std::fs::write(&input, file).unwrap();
    for level in 0..4u32 {
        let out = d.join(format!("l{level}.png"));
        let r = texmap(&["convert", s(&input), s(&out), "--level", &level.to_string()]);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let (w, h, rgba) = read_png(&out);
        assert_eq!((w, h), ((8 >> level).max(1), (4 >> level).max(1)));
        assert_eq!(rgba, want[level as usize], "level {level}");
    }
    // EXR: the same texels, sRGB decoded; alpha linear.
    let exr = d.join("l0.exr");
    assert!(texmap(&["convert", s(&input), s(&exr)]).status.success());
    let f = image::open(&exr).unwrap().to_rgba32f();
    let (p, q) = (&f.as_raw()[..4], &want[0][..4]);
    let srgb = |v: u8| texmap::color::srgb_to_linear(f32::from(v) / 255.0);
    assert!((p[0] - srgb(q[0])).abs() < 1e-6 && (p[3] - f32::from(q[3]) / 255.0).abs() < 1e-6);
    // `info` lists the shape and the bytes.
    let info = texmap(&["info", s(&input)]);
    let text = String::from_utf8_lossy(&info.stdout);
    for needle in [
        "DDS texture",
        "format BGRA8",
        "8x4",
        "4 mip levels (full chain)",
        "1 face",
        "1 layer",
        "8x4, 4x2, 2x1, 1x1",
        "decoded 172 (RGBA8)",
    ] {
        assert!(text.contains(needle), "{needle:?} not in {text}");
    }
}

#[test]
fn faces_by_number_and_by_name_and_slices_of_a_volume() {
    let d = dir("faces");
    let (file, want) = bgra_dds(4, 4, 1, 1, CUBE, 6);
    let input = d.join("cube.dds");
    std::fs::write(&input, file).unwrap();
    for (flag, face) in [("3", 3), ("-y", 3), ("+x", 0), ("-Z", 5)] {
        let out = d.join(format!("f{flag}.png"));
        let r = texmap(&["convert", s(&input), s(&out), "--face", flag]);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        assert_eq!(read_png(&out).2, want[face], "--face {flag}");
    }
    // A 4x4x4 volume, 2 levels: level 1 has 2 slices of 2x2.
    let (file, want) = bgra_dds(4, 4, 4, 2, VOLUME, 1);
    let input = d.join("volume.dds");
    std::fs::write(&input, file).unwrap();
    let out = d.join("z1.png");
    let r = texmap(&[
        "convert",
        s(&input),
        s(&out),
        "--level",
        "1",
        "--slice",
        "1",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(read_png(&out).2, want[1][16..]);
    let out = d.join("z2.png");
    let r = texmap(&[
        "convert",
        s(&input),
        s(&out),
        "--level",
        "1",
        "--slice",
        "2",
    ]);
    assert_fails(
        &r,
        &[
            "--slice 2 is out of range",
            "2 depth slices at this level (0 to 1)",
        ],
        &out,
    );
}

#[test]
fn out_of_range_indices_and_bad_outputs_list_what_is_valid() {
    let d = dir("ranges");
    let (file, _) = bgra_dds(4, 4, 1, 3, CUBE, 6);
    let input = d.join("cube.dds");
    std::fs::write(&input, file).unwrap();
    let out = d.join("x.png");
    let cases: [(&[&str], &[&str]); 5] = [
        (
            &["--level", "3"],
            &["--level 3 is out of range", "3 mip levels (0 to 2)"],
        ),
        (
            &["--face", "6"],
            &["--face 6 is out of range", "6 faces (0 to 5)"],
        ),
        (
            &["--face", "up"],
            &["--face up", "0 to 5", "+x, -x, +y, -y, +z, -z"],
        ),
        (
            &["--slice", "1"],
            &["--slice 1 is out of range", "1 layer (0 to 0)"],
        ),
        (&["--level", "-1"], &["-1"]),
    ];
    for (flags, needles) in cases {
        let mut args = vec!["convert", s(&input), s(&out)];
        args.extend_from_slice(flags);
        let r = texmap(&args);
        if flags[1] == "-1" {
            // clap refuses it (exit 2) before texmap runs.
            assert!(!r.status.success() && !out.exists());
            continue;
        }
        assert_fails(&r, needles, &out);
    }
    let jpg = d.join("x.jpg");
    assert_fails(
        &texmap(&["convert", s(&input), s(&jpg)]),
        &["x.jpg", ".png", ".exr"],
        &jpg,
    );
    // An image file has one level, one face, one layer.
    let png = d.join("in.png");
    image::RgbaImage::from_pixel(2, 2, image::Rgba([1, 2, 3, 4]))
        .save(&png)
        .unwrap();
    assert_fails(
        &texmap(&["convert", s(&png), s(&out), "--face", "+y"]),
        &["--face 2", "1 face (0 to 0)"],
        &out,
    );
    let r = texmap(&["convert", s(&png), s(&out)]);
    assert!(r.status.success());
    assert_eq!(read_png(&out).2, [1, 2, 3, 4].repeat(4));
    assert_fails(
        &texmap(&["convert", s(&png), s(&png)]),
        &["overwrite the input"],
        &d.join("none"),
    );
}

#[test]
fn bad_texture_files_are_one_line_exit_1_and_no_output() {
    let d = dir("bad");
    let out = d.join("x.png");
    let (good, _) = bgra_dds(8, 8, 1, 1, 0, 1);
    let dxt1 = (0x4, *b"DXT1", 0, [0; 4]);
    let dx10 = (0x4, *b"DX10", 0, [0; 4]);
    let mut bomb = dds_header(65535, 65535, 1, 16, 0, (0x4, *b"DXT5", 0, [0; 4]), None);
    bomb.extend([0; 64]);
    let mut unknown_dxgi = dds_header(4, 4, 1, 1, 0, dx10, Some([45, 3, 0, 1, 0]));
    unknown_dxgi.extend([0; 64]);
    let mut short_blocks = dds_header(8, 8, 1, 2, 0, dxt1, None);
    short_blocks.extend([0; 39]); // 32 + 8 bytes needed
    let mut zero = dds_header(0, 8, 1, 1, 0, dxt1, None);
    zero.extend([0; 8]);
    let cases: [(&str, Vec<u8>, &[&str]); 6] = [
        (
            "truncated.dds",
            good[..100].to_vec(),
            &["truncated.dds", "truncated"],
        ),
        (
            "cut.dds",
            good[..good.len() - 1].to_vec(),
            &["cut.dds", "truncated"],
        ),
        (
            "bomb.dds",
            bomb,
            &["bomb.dds", "65535x65535", "above the limit"],
        ),
        ("dxgi.dds", unknown_dxgi, &["dxgi.dds", "DXGI format 45"]),
        (
            "blocks.dds",
            short_blocks,
            &["blocks.dds", "truncated", "need 40 bytes"],
        ),
        ("zero.dds", zero, &["zero.dds", "zero side"]),
    ];
    for (name, bytes, needles) in cases {
        let input = d.join(name);
        std::fs::write(&input, bytes).unwrap();
        assert_fails(&texmap(&["convert", s(&input), s(&out)]), needles, &out);
        assert_fails(&texmap(&["info", s(&input)]), needles, &out);
        let r = texmap(&[
            "render",
            "builtin:plane",
            "--size",
            "16x16",
            "--texture",
            s(&input),
            "-o",
            s(&out),
        ]);
        assert_fails(&r, needles, &out);
    }
}

#[test]
fn dds_files_are_textures_and_environments_for_the_renderer() {
    let d = dir("render");
    let (tex, _) = bgra_dds(16, 16, 1, 5, 0, 1);
    let texture = d.join("t.dds");
    std::fs::write(&texture, tex).unwrap();
    let (cube, _) = bgra_dds(8, 8, 1, 1, CUBE, 6);
    let env = d.join("env.dds");
    std::fs::write(&env, cube).unwrap();
    let out = d.join("plane.png");
    let r = texmap(&[
        "render",
        "builtin:plane",
        "--size",
        "32x24",
        "--texture",
        s(&texture),
        "-o",
        s(&out),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(out.exists());
    let out = d.join("sphere.png");
    let r = texmap(&[
        "render",
        "builtin:sphere",
        "--size",
        "32x24",
        "--env",
        s(&env),
        "-o",
        s(&out),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    // A scene's texture: an OBJ material's map_Kd.
    std::fs::write(d.join("m.mtl"), "newmtl m\nKd 1 1 1\nmap_Kd t.dds\n").unwrap();
    let obj = d.join("tri.obj");
    std::fs::write(&obj, "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n").unwrap();
    let info = texmap(&["info", s(&obj)]);
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(
        text.contains("t.dds: 16x16, Rgba8"),
        "{text}{}",
        String::from_utf8_lossy(&info.stderr)
    );
    // A cube map where a 2D texture is needed is refused by name.
    let out = d.join("x.png");
    let r = texmap(&[
        "render",
        "builtin:plane",
        "--size",
        "16x16",
        "--texture",
        s(&env),
        "-o",
        s(&out),
    ]);
    assert_fails(
        &r,
        &["env.dds", "is a cube map; a 2D texture is needed"],
        &out,
    );
}
