//! The surface-detail switches (`--layers`, `--light-maps`, `--toon`) act on a scene that has
//! the technique, or are refused with one line naming the flag and no output; bad scene
//! files are refused with one line naming the file, exit 1, no output; `texmap info` lists
//! layers, light maps and toon shading. The scene and its images are generated here.

mod common;

use common::texmap;
use std::path::{Path, PathBuf};
use std::process::Output;

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("texmap-detail-cli-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A scene with every technique: a floor with two layers and a light map on uv set 1, a
/// toon sphere with an outline.
fn write_scene(d: &Path) -> PathBuf {
    image::RgbImage::from_fn(16, 16, |x, y| {
        image::Rgb([(x * 16) as u8, (y * 16) as u8, 200])
    })
    .save(d.join("base.png"))
    .unwrap();
    image::RgbaImage::from_fn(16, 16, |x, _| {
        image::Rgba([250, 200, 20, if x % 4 < 2 { 255 } else { 0 }])
    })
    .save(d.join("decal.png"))
    .unwrap();
    image::RgbImage::from_fn(16, 16, |x, y| {
        let v = 60 + ((x * 7 + y * 13) % 16) as u8 * 8;
        image::Rgb([v, v, v])
    })
    .save(d.join("detail.png"))
    .unwrap();
    image::RgbImage::from_fn(16, 16, |x, y| {
        let v = (x + y) as u8 * 8;
        image::Rgb([v, v, 255 - v])
    })
    .save(d.join("light.png"))
    .unwrap();
    let toml = r#"
[[cameras]]
eye = [0.0, 2.0, 3.0]
target = [0.0, 0.0, 0.0]

[materials.floor]
[materials.floor.base_color_texture]
file = "base.png"
[[materials.floor.layers]]
mode = "decal"
texture = { file = "decal.png", uv_scale = 2 }
[[materials.floor.layers]]
mode = "detail"
texture = { file = "detail.png", uv_scale = 8 }
[materials.floor.light_map]
file = "light.png"
scale = 1.5

[materials.ball]
base_color = [0.8, 0.3, 0.2, 1.0]
[materials.ball.toon]
bands = 3
outline = [0.0, 0.0, 0.0]
outline_width = 2.0

[[meshes]]
primitive = "plane"
size = 4
material = "floor"
texgen = { projection = "planar-y", set = 1 }

[[meshes]]
primitive = "sphere"
radius = 0.6
material = "ball"
translate = [0.0, 0.6, 0.0]
"#;
    let path = d.join("detail.toml");
    std::fs::write(&path, toml).unwrap();
    path
}

fn render(scene: &str, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "render",
        scene,
        "--size",
        "96x64",
        "--quiet",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    texmap(&args)
}

fn rgb(path: &Path) -> image::RgbImage {
    image::open(path).unwrap().to_rgb8()
}

#[test]
fn each_switch_changes_the_image_or_is_refused() {
    let d = dir();
    let scene = write_scene(&d);
    let scene = scene.to_str().unwrap();
    let plain = d.join("plain.png");
    let o = render(scene, &plain, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let reference = rgb(&plain);
    for (k, flag) in [
        &["--layers", "off"][..],
        &["--light-maps", "off"],
        &["--toon", "off"],
        &["--toon", "on"],
    ]
    .iter()
    .enumerate()
    {
        let out = d.join(format!("flag-{k}.png"));
        let o = render(scene, &out, flag);
        assert!(
            o.status.success(),
            "{flag:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        // --toon on also gives the floor bands; the others drop a technique.
        assert_ne!(rgb(&out), reference, "{flag:?} changed nothing");
    }
    // `on` is each technique's default where the scene has it: the same image.
    for flag in [&["--layers", "on"][..], &["--light-maps", "on"]] {
        let out = d.join("on.png");
        let o = render(scene, &out, flag);
        assert!(o.status.success());
        assert_eq!(rgb(&out), reference, "{flag:?}");
    }
    // Refused where there is nothing to switch.
    for (scene, flag) in [
        ("builtin:demo", &["--layers", "off"][..]),
        ("builtin:demo", &["--light-maps", "off"]),
        ("builtin:demo", &["--toon", "off"]),
        (scene, &["--toon", "on", "--unlit"]),
    ] {
        let out = d.join("refused.png");
        let _ = std::fs::remove_file(&out);
        let o = render(scene, &out, flag);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{scene} {flag:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{flag:?}: {err}");
        assert!(err.contains(flag[0]), "{flag:?}: {err}");
        assert!(!out.exists(), "{flag:?}: no output on refusal");
    }
    // --toon on acts on a scene without toon materials.
    let a = d.join("demo.png");
    let b = d.join("demo-toon.png");
    assert!(render("builtin:demo", &a, &[]).status.success());
    assert!(render("builtin:demo", &b, &["--toon", "on"])
        .status
        .success());
    assert_ne!(rgb(&a), rgb(&b));
}

#[test]
fn bad_scene_files_are_one_line_exit_1_no_output() {
    let d = dir().join("bad");
    std::fs::create_dir_all(&d).unwrap();
    let scene = write_scene(&d);
    let text = std::fs::read_to_string(&scene).unwrap();
    for (name, from, to, want) in [
        (
            "missing",
            "file = \"decal.png\"",
            "file = \"gone.png\"",
            "gone.png",
        ),
        (
            "no-uv1",
            "texgen = { projection = \"planar-y\", set = 1 }",
            "",
            "light_map reads uv set 1",
        ),
        ("mode", "mode = \"decal\"", "mode = \"sum\"", "mode \"sum\""),
    ] {
        let path = d.join(format!("{name}.toml"));
        std::fs::write(&path, text.replace(from, to)).unwrap();
        let out = d.join(format!("{name}.png"));
        let o = render(path.to_str().unwrap(), &out, &[]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{name}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{name}: {err}");
        assert!(err.contains(want), "{name}: {err}");
        assert!(!out.exists(), "{name}: no output");
    }
}

#[test]
fn info_lists_layers_light_map_and_toon() {
    let d = dir().join("info");
    std::fs::create_dir_all(&d).unwrap();
    let scene = write_scene(&d);
    let o = texmap(&["info", scene.to_str().unwrap()]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    for want in [
        "layer 0: decal (rgba) decal.png 16x16 uv0",
        "layer 1: detail (rgb) detail.png 16x16 uv0 scale 8",
        "light map: 16x16 uv1, intensity 1.5",
        "toon: ramp bands 3, outline (0, 0, 0) 2 px",
    ] {
        assert!(text.contains(want), "{want:?} not in:\n{text}");
    }
}

#[test]
fn the_same_bytes_whatever_the_thread_count() {
    let d = dir().join("threads");
    std::fs::create_dir_all(&d).unwrap();
    let scene = write_scene(&d);
    let scene = scene.to_str().unwrap();
    let (a, b) = (d.join("t1.png"), d.join("t3.png"));
    assert!(render(scene, &a, &["--threads", "1"]).status.success());
    assert!(render(scene, &b, &["--threads", "3"]).status.success());
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
}
