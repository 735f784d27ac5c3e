//! `--texture-storage decoded|native|compressed|rgba8` (render and info) and TOML `storage`: a
//! hand-made BC1 DDS (built here) renders the same held compressed as decoded, a PNG the same
//! held as 8-bit RGBA, `info` shows what each storage holds, and the flag is refused where no
//! image file is read.

mod common;

use common::texmap;
use std::path::{Path, PathBuf};
use std::process::Output;

fn dir(name: &str) -> PathBuf {
    common::fresh_dir("storage", name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A `n`×`n` BC1 ("DXT1") DDS with its full mip chain of pseudo-random blocks; returns the
/// bytes of its blocks (every level).
fn write_bc1_dds(path: &Path, n: u32) -> usize {
    let levels = 32 - n.leading_zeros();
    let mut hdr = [0u32; 31];
    // size, flags (caps, height, width, pixel format, mip count, linear size), height, width.
    (hdr[0], hdr[1], hdr[2], hdr[3], hdr[6]) = (124, 0x2_1007, n, n, levels);
    // The pixel format: size 32, DDPF_FOURCC, "DXT1".
    (hdr[18], hdr[19], hdr[20]) = (32, 0x4, u32::from_le_bytes(*b"DXT1"));
    (hdr[26], hdr[27]) = (0x40_1008, 0);
    let mut f = b"DDS ".to_vec();
    hdr.iter().for_each(|v| f.extend(v.to_le_bytes()));
    let mut x = 12_345u32;
    let mut blocks = 0;
    for l in 0..levels {
        let side = (n >> l).max(1).div_ceil(4) as usize;
        for _ in 0..side * side * 8 {
            x = x.wrapping_mul(1_103_515_245).wrapping_add(12_345);
            f.push((x >> 16) as u8);
        }
        blocks += side * side * 8;
    }
    std::fs::write(path, f).unwrap();
    blocks
}

fn psnr(a: &Path, b: &Path) -> f64 {
    let (a, b) = (
        image::open(a).unwrap().to_rgb8(),
        image::open(b).unwrap().to_rgb8(),
    );
    let (w, h) = a.dimensions();
    texmap::metrics::compare_rgb8(a.as_raw(), b.as_raw(), w as usize, h as usize, None).psnr_db
}

fn ok(r: &Output) -> String {
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    String::from_utf8_lossy(&r.stdout).into_owned()
}

/// Exit 1, one line on stderr containing every needle.
fn refused(r: &Output, needles: &[&str]) {
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
    for n in needles {
        assert!(err.contains(n), "{n:?} in {err}");
    }
}

#[test]
fn every_storage_renders_a_block_compressed_texture_alike() {
    let d = dir("render");
    let dds = d.join("bc1.dds");
    write_bc1_dds(&dds, 64);
    let render = |storage: &str, filter: &str| {
        let out = d.join(format!("plane-{storage}-{filter}.png"));
        ok(&texmap(&[
            "render",
            "builtin:plane",
            "--size",
            "96x64",
            "--uv-scale",
            "4",
            "--filter",
            filter,
            "--texture",
            s(&dds),
            "--texture-storage",
            storage,
            "--quiet",
            "-o",
            s(&out),
        ]));
        out
    };
    for filter in ["trilinear", "aniso8", "ewa"] {
        let decoded = render("decoded", filter);
        // The same decoder and tables: only decoded's 16-bit rounding can differ.
        for storage in ["native", "compressed"] {
            let p = psnr(&decoded, &render(storage, filter));
            assert!(p >= 50.0, "{storage} {filter}: {p:.1} dB from decoded");
        }
    }
}

#[test]
fn the_8bit_storage_renders_an_image_file_as_the_default_does() {
    // An sRGB PNG of pseudo-random texels: held as 8-bit RGBA, it reads within the 8-bit
    // rounding of the default storage's 16-bit linear texels under every filter family.
    let d = dir("rgba8");
    let png = d.join("noise.png");
    let mut x = 99u32;
    let img = image::RgbImage::from_fn(64, 64, |_, _| {
        let mut c = [0u8; 3];
        for v in &mut c {
            x = x.wrapping_mul(1_103_515_245).wrapping_add(12_345);
            *v = (x >> 16) as u8;
        }
        image::Rgb(c)
    });
    img.save(&png).unwrap();
    let render = |storage: &str, filter: &str| {
        let out = d.join(format!("plane-{storage}-{filter}.png"));
        ok(&texmap(&[
            "render",
            "builtin:plane",
            "--size",
            "96x64",
            "--uv-scale",
            "4",
            "--filter",
            filter,
            "--texture",
            s(&png),
            "--texture-storage",
            storage,
            "--quiet",
            "-o",
            s(&out),
        ]));
        out
    };
    for filter in ["nearest", "trilinear", "aniso8", "ewa"] {
        let p = psnr(&render("decoded", filter), &render("rgba8", filter));
        assert!(p >= 45.0, "rgba8 {filter}: {p:.1} dB from decoded");
    }
    let text = ok(&texmap(&["info", s(&png), "--texture-storage", "rgba8"]));
    assert!(text.contains("held rgba8:"), "{text}");
}

#[test]
fn info_shows_what_each_storage_holds() {
    let d = dir("info");
    let dds = d.join("bc1.dds");
    let blocks = write_bc1_dds(&dds, 64);
    // The texture file alone: its memory held compressed is its blocks.
    let text = ok(&texmap(&[
        "info",
        s(&dds),
        "--texture-storage",
        "compressed",
    ]));
    assert!(
        text.contains(&format!("held compressed (BC1): {blocks} bytes")),
        "{text}"
    );
    let text = ok(&texmap(&["info", s(&dds), "--texture-storage", "native"]));
    // 64² + 32² + … + 1 texels of 4 bytes (tiles pad the levels under 4×4).
    assert!(text.contains("held native:"), "{text}");
    // A scene's texture: an OBJ material's map_Kd, under each storage.
    std::fs::write(d.join("m.mtl"), "newmtl m\nKd 1 1 1\nmap_Kd bc1.dds\n").unwrap();
    let obj = d.join("tri.obj");
    std::fs::write(
        &obj,
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n",
    )
    .unwrap();
    let text = ok(&texmap(&["info", s(&obj)]));
    assert!(text.contains("held decoded,"), "{text}");
    let text = ok(&texmap(&[
        "info",
        s(&obj),
        "--texture-storage",
        "compressed",
    ]));
    assert!(
        text.contains(&format!("held compressed (BC1), {blocks} bytes")),
        "{text}"
    );
    // The render takes the same flag and draws.
    let out = d.join("tri.png");
    ok(&texmap(&[
        "render",
        s(&obj),
        "--size",
        "32x24",
        "--texture-storage",
        "compressed",
        "--quiet",
        "-o",
        s(&out),
    ]));
    assert!(out.exists());
}

#[test]
fn toml_textures_choose_their_storage() {
    let d = dir("toml");
    let dds = d.join("bc1.dds");
    let blocks = write_bc1_dds(&dds, 32);
    let scene = |storage: &str| {
        format!(
            "[[cameras]]\neye = [0.0, 2.0, 3.0]\ntarget = [0.0, 0.0, 0.0]\n\n\
             [materials.m.base_color_texture]\nfile = \"bc1.dds\"\nstorage = \"{storage}\"\n\n\
             [[meshes]]\nprimitive = \"plane\"\nmaterial = \"m\"\n"
        )
    };
    let toml = d.join("s.toml");
    std::fs::write(&toml, scene("compressed")).unwrap();
    let text = ok(&texmap(&["info", s(&toml)]));
    assert!(
        text.contains(&format!("held compressed (BC1), {blocks} bytes")),
        "{text}"
    );
    let out = d.join("s.png");
    ok(&texmap(&[
        "render",
        s(&toml),
        "--size",
        "32x24",
        "--quiet",
        "-o",
        s(&out),
    ]));
    std::fs::write(&toml, scene("zip")).unwrap();
    let out = d.join("bad.png");
    let r = texmap(&["render", s(&toml), "--size", "32x24", "-o", s(&out)]);
    refused(
        &r,
        &["s.toml", "storage \"zip\"", "decoded, native, compressed"],
    );
    assert!(!out.exists());
}

#[test]
fn the_flag_is_refused_where_no_image_file_is_read() {
    let d = dir("refused");
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let shapes = repo.join("scenes/shapes.toml");
    let cell = repo.join("scenes/volumes/cell.nrrd");
    for scene in ["builtin:plane", "builtin:demo", s(&shapes), s(&cell)] {
        let out = d.join("x.png");
        let r = texmap(&[
            "render",
            scene,
            "--size",
            "16x16",
            "--texture-storage",
            "native",
            "-o",
            s(&out),
        ]);
        refused(&r, &["--texture-storage"]);
        assert!(!out.exists(), "{scene}: no output");
    }
    // A value off the list: clap's error, exit 2, naming the values.
    let r = texmap(&["render", "--texture-storage", "bc9"]);
    assert_eq!(r.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&r.stderr).contains("decoded, native, compressed"));
}
