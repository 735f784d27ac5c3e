//! Output formats and alpha: `.exr` holds the frame's linear float RGBA (read back with the
//! `image` crate and encoded to sRGB, it equals the PNG byte for byte), `.hdr` its colour to
//! RGBE precision, `--alpha` PNG straight alpha (0 where nothing is drawn, 255 inside,
//! fractional on antialiased edges, volumes' opacity), and an extension texmap does not
//! write is one line, exit 1, no file — checked before the scene is read.

mod common;

use common::texmap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use image::DynamicImage;
use texmap::color::{linear_to_srgb8, linear_to_unorm8, srgb_to_linear};

fn dir(test: &str) -> PathBuf {
    common::fresh_dir("out", test)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// An unlit orange sphere in the middle of a blue background (both linear).
fn sphere_scene(d: &Path) -> PathBuf {
    let p = d.join("sphere.toml");
    std::fs::write(
        &p,
        r#"
background = [0.2, 0.4, 0.8, 1.0]
[[cameras]]
eye = [0.0, 0.0, 4.0]
target = [0.0, 0.0, 0.0]
fov = 40
[materials.orange]
base_color = [0.8, 0.3, 0.05, 1.0]
unlit = true
[[meshes]]
primitive = "sphere"
radius = 0.8
segments = 48
rings = 24
material = "orange"
"#,
    )
    .unwrap();
    p
}

/// Renders `args` at 96×64 into `out`, which must then exist.
fn render(args: &[&str], out: &Path) {
    let mut v = vec!["render"];
    v.extend_from_slice(args);
    v.extend(["--size", "96x64", "--quiet", "-o", s(out)]);
    let r = texmap(&v);
    assert!(
        r.status.success(),
        "{v:?}: {}",
        String::from_utf8_lossy(&r.stderr)
    );
    assert!(out.exists(), "{v:?}: no {}", out.display());
}

/// An EXR or HDR file as float RGBA (alpha 1 where the file has none).
fn floats(p: &Path) -> (u32, u32, Vec<[f32; 4]>) {
    let img = image::open(p).unwrap();
    let kind = match &img {
        DynamicImage::ImageRgba32F(_) => "rgba32f",
        DynamicImage::ImageRgb32F(_) => "rgb32f",
        _ => "other",
    };
    assert_ne!(kind, "other", "{}: not float", p.display());
    let f = img.to_rgba32f();
    (f.width(), f.height(), f.pixels().map(|p| p.0).collect())
}

fn rgba8(p: &Path) -> (u32, u32, Vec<[u8; 4]>) {
    let img = image::open(p).unwrap();
    assert!(
        matches!(img, DynamicImage::ImageRgba8(_)),
        "{}: not RGBA8",
        p.display()
    );
    let i = img.to_rgba8();
    (i.width(), i.height(), i.pixels().map(|p| p.0).collect())
}

fn rgb8(p: &Path) -> Vec<[u8; 3]> {
    let img = image::open(p).unwrap();
    assert!(
        matches!(img, DynamicImage::ImageRgb8(_)),
        "{}: not RGB8",
        p.display()
    );
    img.to_rgb8().pixels().map(|p| p.0).collect()
}

/// Refused: exit 1, one line naming `needle`, no `out`.
fn assert_refused(r: &Output, needle: &str, out: &Path) {
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
    assert!(err.contains(needle), "names {needle}: {err}");
    assert!(!out.exists(), "no {} after a refusal", out.display());
}

#[test]
fn exr_holds_the_frames_linear_rgba() {
    let d = dir("exr");
    let scene = sphere_scene(&d);
    let (png, exr) = (d.join("a.png"), d.join("a.exr"));
    for (out, aa) in [(&png, "4"), (&exr, "4")] {
        render(&[s(&scene), "--msaa", aa], out);
    }
    let (w, h, f) = floats(&exr);
    assert_eq!((w, h), (96, 64));
    let p = rgb8(&png);
    // The same frame: its linear values, encoded here, are the PNG's bytes.
    let mut max_diff = 0;
    for (e, q) in f.iter().zip(&p) {
        for k in 0..3 {
            max_diff = max_diff.max(linear_to_srgb8(e[k]).abs_diff(q[k]));
        }
        // The background is drawn: opaque everywhere.
        assert_eq!(e[3], 1.0);
    }
    assert_eq!(max_diff, 0, "EXR encoded to sRGB against the PNG");
    // Linear values, not sRGB codes: the blue background is 0.4 linear in green.
    assert!((f[0][1] - 0.4).abs() < 1e-6, "{:?}", f[0]);

    // With --alpha: premultiplied, alpha fractional on the edges, and un-premultiplied it is
    // the RGBA PNG.
    let (png_a, exr_a) = (d.join("alpha.png"), d.join("alpha.exr"));
    render(&[s(&scene), "--msaa", "4", "--alpha"], &png_a);
    render(&[s(&scene), "--msaa", "4", "--alpha"], &exr_a);
    let (_, _, fa) = floats(&exr_a);
    let (_, _, pa) = rgba8(&png_a);
    let mut fractional = 0;
    for (e, q) in fa.iter().zip(&pa) {
        let a = e[3];
        assert!((0.0..=1.0).contains(&a));
        assert_eq!(linear_to_unorm8(a), q[3]);
        if a > 0.0 && a < 1.0 {
            fractional += 1;
        }
        for k in 0..3 {
            assert!(e[k] <= a + 1e-6, "premultiplied: {e:?}");
            let straight = if a > 0.0 {
                linear_to_srgb8(e[k] / a)
            } else {
                0
            };
            assert_eq!(straight, q[k], "{e:?} against {q:?}");
        }
    }
    assert!(fractional > 20, "{fractional} edge pixels");
}

#[test]
fn hdr_holds_the_colour_to_rgbe_precision() {
    let d = dir("hdr");
    let scene = sphere_scene(&d);
    let (exr, hdr) = (d.join("a.exr"), d.join("a.HDR"));
    render(&[s(&scene), "--ssaa", "2"], &exr);
    render(&[s(&scene), "--ssaa", "2"], &hdr);
    assert!(std::fs::read(&hdr).unwrap().starts_with(b"#?RADIANCE"));
    let (_, _, e) = floats(&exr);
    let (w, h, r) = floats(&hdr);
    assert_eq!((w, h), (96, 64));
    // RGBE: 8 bits of mantissa under the pixel's largest channel's exponent.
    let mut worst = 0.0f32;
    for (a, b) in e.iter().zip(&r) {
        let top = a[0].max(a[1]).max(a[2]);
        assert!(top > 0.0);
        for k in 0..3 {
            worst = worst.max((a[k] - b[k]).abs() / top);
        }
    }
    assert!(worst <= 0.01, "relative error {worst}");
}

#[test]
fn alpha_is_coverage_over_a_left_out_background() {
    let d = dir("alpha");
    let scene = sphere_scene(&d);
    let (plain, alpha) = (d.join("plain.png"), d.join("alpha.png"));
    for aa in [["--ssaa", "3"], ["--msaa", "8"]] {
        render(&[s(&scene), aa[0], aa[1]], &plain);
        render(&[s(&scene), aa[0], aa[1], "--alpha"], &alpha);
        let (w, h, a) = rgba8(&alpha);
        let p = rgb8(&plain);
        let at = |x: u32, y: u32| a[(y * w + x) as usize];
        for (x, y) in [(0, 0), (w - 1, 0), (0, h - 1), (w - 1, h - 1)] {
            assert_eq!(at(x, y), [0, 0, 0, 0], "{aa:?}: corner {x},{y}");
        }
        let centre = at(w / 2, h / 2);
        assert_eq!(centre[3], 255, "{aa:?}");
        assert_eq!(centre[..3], p[(h / 2 * w + w / 2) as usize], "{aa:?}");
        // Edge pixels: fractional alpha, and their straight colour laid over the background
        // in linear light gives the plain render back (within two codes).
        let bg = p[0].map(|c| srgb_to_linear(f32::from(c) / 255.0));
        let mut edge = 0;
        for (q, r) in a.iter().zip(&p) {
            if q[3] == 0 || q[3] == 255 {
                continue;
            }
            edge += 1;
            let k = f32::from(q[3]) / 255.0;
            for c in 0..3 {
                let over = srgb_to_linear(f32::from(q[c]) / 255.0) * k + bg[c] * (1.0 - k);
                let got = linear_to_srgb8(over);
                assert!(
                    got.abs_diff(r[c]) <= 2,
                    "{aa:?}: {q:?} over {bg:?} → {got}, not {r:?}"
                );
            }
        }
        assert!(edge > 20, "{aa:?}: {edge} fractional pixels");
    }
    // An environment's background is left out too (it still lights the scene).
    let demo = d.join("demo.png");
    render(&["builtin:demo", "--alpha", "--ssaa", "2"], &demo);
    let (w, h, a) = rgba8(&demo);
    assert_eq!(a[0], [0, 0, 0, 0], "the sky");
    assert_eq!(a[((h - 1) * w + w / 2) as usize][3], 255, "the floor");
    let lone = d.join("lone.png");
    // (its own panorama is in ../shared/assets; --env replaces it, so it is not read)
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let env_only = repo.join("scenes/reference/env.toml");
    let sky = repo.join("scenes/env/synthetic_sky.hdr");
    let r = texmap(&[
        "render",
        s(&env_only),
        "--env",
        s(&sky),
        "--alpha",
        "-o",
        s(&lone),
    ]);
    assert_refused(&r, "nothing to draw", &lone);
    // --background names the drawn one: the scene's colour, opaque again.
    let out = d.join("color.png");
    render(&[s(&scene), "--alpha", "--background", "color"], &out);
    let (_, _, a) = rgba8(&out);
    assert!(a.iter().all(|p| p[3] == 255));
}

#[test]
fn volumes_alpha_is_their_opacity() {
    let d = dir("volume");
    // A 16³ ball: 200 at the centre, 0 beyond radius 8 voxels.
    let mut b = Vec::new();
    for z in 0..16 {
        for y in 0..16 {
            for x in 0..16 {
                let r = ((x as f32 - 7.5).powi(2)
                    + (y as f32 - 7.5).powi(2)
                    + (z as f32 - 7.5).powi(2))
                .sqrt();
                b.push((200.0 * (1.0 - r / 8.0)).clamp(0.0, 200.0) as u8);
            }
        }
    }
    let ball = d.join("ball.raw");
    std::fs::write(&ball, b).unwrap();
    let flags = [
        s(&ball),
        "--dims",
        "16,16,16",
        "--tf",
        "0:1,1,1,0;40:1,1,1,0.08;200:1,1,1,0.08",
        "--no-jitter",
        "--alpha",
    ];
    let (png, exr) = (d.join("ball.png"), d.join("ball.exr"));
    render(&flags, &png);
    render(&flags, &exr);
    let (w, h, a) = rgba8(&png);
    let (_, _, f) = floats(&exr);
    assert_eq!(a[0], [0, 0, 0, 0]);
    let centre = (h / 2 * w + w / 2) as usize;
    // Semi-transparent through the middle: neither empty nor opaque.
    assert!(a[centre][3] > 10 && a[centre][3] < 250, "{:?}", a[centre]);
    for (q, e) in a.iter().zip(&f) {
        assert_eq!(q[3], linear_to_unorm8(e[3]));
    }
    // A scan's background is already transparent: --background none or color changes
    // nothing.
    let out = d.join("none.png");
    for (flags, needle) in [
        (&["--background", "none"][..], "--background none"),
        (
            &["--background", "color", "--alpha"][..],
            "--background color",
        ),
    ] {
        let mut v = vec!["render", s(&ball), "--dims", "16,16,16", "-o", s(&out)];
        v.extend_from_slice(flags);
        assert_refused(&texmap(&v), needle, &out);
    }
}

#[test]
fn unknown_extensions_and_contradictions_are_refused_before_loading() {
    let d = dir("refused");
    // The scene does not exist: the output's name is refused first.
    let missing = d.join("missing.gltf");
    // (.jpg was refused here until texmap wrote JPEG; .webp takes its place.)
    for name in ["x.webp", "x.tiff", "x.PNG.bak"] {
        let out = d.join(name);
        let r = texmap(&["render", s(&missing), "-o", s(&out)]);
        assert_refused(&r, name, &out);
        let r = texmap(&["bake", "marble", "--size", "8x8", "-o", s(&out)]);
        assert_refused(&r, name, &out);
    }
    let out = d.join("x.exr");
    let r = texmap(&["render", s(&missing), "--format", "png", "-o", s(&out)]);
    assert_refused(&r, "--format", &out);
    let out = d.join("x.hdr");
    let r = texmap(&["render", "builtin:sphere", "--alpha", "-o", s(&out)]);
    assert_refused(&r, "--alpha", &out);
    // compare's difference image is 8-bit false colour.
    let scene = sphere_scene(&d);
    let png = d.join("a.png");
    render(&[s(&scene)], &png);
    let diff = d.join("diff.exr");
    let r = texmap(&["compare", s(&png), s(&png), "--diff", s(&diff)]);
    assert_refused(&r, "--diff", &diff);
    // Background choices that change nothing, or show nothing.
    let out = d.join("bg.png");
    let r = texmap(&["render", s(&scene), "--background", "env", "-o", s(&out)]);
    assert_refused(&r, "--background env", &out);
    let r = texmap(&["render", s(&scene), "--background", "color", "-o", s(&out)]);
    assert_refused(&r, "--background color", &out);
    // The memory budget counts an EXR's encoding for a stream.
    let r = texmap(&[
        "render",
        "builtin:plane",
        "--size",
        "16384x16384",
        "--max-memory",
        "8G",
        "-o",
        s(&out).replace(".png", ".exr").as_str(),
    ]);
    assert_refused(&r, "--max-memory", &d.join("bg.exr"));
}

#[test]
fn stdout_frames_and_bake_write_every_format() {
    let d = dir("streams");
    let scene = sphere_scene(&d);
    // `-o -` is PNG unless --format says.
    let r = texmap(&["render", s(&scene), "--size", "32x16", "--quiet", "-o", "-"]);
    assert!(r.status.success());
    assert!(r.stdout.starts_with(b"\x89PNG"));
    let r = texmap(&[
        "render",
        s(&scene),
        "--size",
        "32x16",
        "--quiet",
        "--format",
        "exr",
        "-o",
        "-",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(r.stdout.starts_with(&[0x76, 0x2f, 0x31, 0x01]), "EXR magic");
    let img = image::load_from_memory(&r.stdout).unwrap();
    assert_eq!((img.width(), img.height()), (32, 16));
    // Every turntable frame in the format its name says.
    let pattern = d.join("turn_{frame}.exr");
    let r = texmap(&[
        "render",
        s(&scene),
        "--size",
        "32x16",
        "--frames",
        "2",
        "--quiet",
        "-o",
        s(&pattern),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    for k in ["0001", "0002"] {
        let (w, _, _) = floats(&d.join(format!("turn_{k}.exr")));
        assert_eq!(w, 32);
    }
    // A baked pattern: the EXR's linear values are the PNG's (sRGB colour; grey as data).
    for gray in [false, true] {
        let (png, exr) = (d.join("bake.png"), d.join("bake.exr"));
        for out in [&png, &exr] {
            let mut v = vec!["bake", "marble", "--size", "24x16", "-o", s(out)];
            if gray {
                v.push("--gray");
            }
            let r = texmap(&v);
            assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        }
        let (_, _, f) = floats(&exr);
        let p = rgb8(&png);
        for (e, q) in f.iter().zip(&p) {
            for k in 0..3 {
                let code = if gray {
                    linear_to_unorm8(e[k])
                } else {
                    linear_to_srgb8(e[k])
                };
                assert_eq!(code, q[k], "gray {gray}");
            }
        }
    }
}

#[cfg(unix)]
#[test]
fn an_exr_goes_through_a_fifo() {
    let d = dir("fifo");
    let fifo = d.join("pipe.exr");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        println!("skipped: mkfifo is not available");
        return;
    }
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(fifo).unwrap())
    };
    let scene = sphere_scene(&d);
    let r = texmap(&[
        "render",
        s(&scene),
        "--size",
        "32x16",
        "--quiet",
        "-o",
        s(&fifo),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let bytes = reader.join().unwrap();
    let img = image::load_from_memory(&bytes).unwrap();
    assert!(matches!(img, DynamicImage::ImageRgba32F(_)));
    // Written through, not replaced by a file.
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
}
