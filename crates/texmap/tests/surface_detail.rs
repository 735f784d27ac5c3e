//! Surface detail rendered: texture layers through a whole frame against OpenGL's
//! texture-environment tables on constant textures (every mode and format), light maps
//! multiplying the diffuse factor, bad scene files refused, and golden images of the
//! technique scenes under `scenes/` (PSNR ≥ 40 dB against `tests/golden/`, reviewed by eye).
//!
//! `../shared/peers/gl_render.py` draws one texture per surface (no multitexturing), so the
//! combine modes are checked here against the specification's tables, not against llvmpipe.

mod common;

use std::path::{Path, PathBuf};

use glam::Vec4;
use texmap::render::{render, Settings};
use texmap::shading::layers::{tex_env, BaseFormat, TexEnvMode};

const MIN_PSNR: f64 = 40.0;

fn dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("texmap-detail-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// An 8×8 image of one colour (RGBA8, or RGB8 when `alpha` is `None`).
fn constant_png(path: &Path, rgb: [u8; 3], alpha: Option<u8>) {
    match alpha {
        Some(a) => image::RgbaImage::from_pixel(8, 8, image::Rgba([rgb[0], rgb[1], rgb[2], a]))
            .save(path)
            .unwrap(),
        None => image::RgbImage::from_pixel(8, 8, image::Rgb(rgb))
            .save(path)
            .unwrap(),
    }
}

/// A square plane seen from above, filling the frame, transparent background; `material`
/// is the body of `[materials.m]` and its sub-tables.
fn plane_scene(d: &Path, name: &str, material: &str, mesh_extra: &str) -> PathBuf {
    let toml = format!(
        "background = [0.0, 0.0, 0.0, 0.0]\n\
         [[cameras]]\neye = [0.0, 2.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, -1.0]\nfov = 40\n\
         [materials.m]\n{material}\n\
         [[meshes]]\nprimitive = \"plane\"\nsize = 4\nmaterial = \"m\"\n{mesh_extra}\n"
    );
    let path = d.join(format!("{name}.toml"));
    std::fs::write(&path, toml).unwrap();
    path
}

/// The centre pixel of `scene` (linear, premultiplied).
fn centre(scene: &Path) -> Vec4 {
    let loaded = texmap::scene::load(scene, &Default::default())
        .unwrap_or_else(|e| panic!("{}: {e}", scene.display()));
    let camera = loaded.scene.camera.unwrap();
    let frame = render(&loaded.scene, &camera, &Settings::new(16, 16)).unwrap();
    frame.color[8 * 16 + 8]
}

#[test]
fn every_mode_and_format_matches_the_gl_tables_through_a_frame() {
    let d = dir("table");
    // The texture: linear 8-bit R 128, G 64, B 255, A 192 (or no alpha).
    constant_png(&d.join("rgba.png"), [128, 64, 255], Some(192));
    constant_png(&d.join("rgb.png"), [128, 64, 255], None);
    let base = Vec4::new(0.2, 0.4, 0.6, 0.5);
    let cc = Vec4::new(0.9, 0.1, 0.3, 0.6);
    let t = |a: f32| Vec4::new(128.0 / 255.0, 64.0 / 255.0, 1.0, a);
    let mut checked = 0;
    for mode in TexEnvMode::NAMES.split(", ") {
        for format in BaseFormat::NAMES.split(", ") {
            let m = TexEnvMode::parse(mode).unwrap();
            let f = BaseFormat::parse(format).unwrap();
            if m == TexEnvMode::Decal && !matches!(f, BaseFormat::Rgb | BaseFormat::Rgba) {
                continue;
            }
            for (file, alpha) in [("rgba.png", 192.0 / 255.0), ("rgb.png", 1.0)] {
                let material = format!(
                    "unlit = true\nalpha_mode = \"blend\"\nbase_color = [0.2, 0.4, 0.6, 0.5]\n\
                     [[materials.m.layers]]\nmode = \"{mode}\"\nformat = \"{format}\"\n\
                     constant = [0.9, 0.1, 0.3, 0.6]\n\
                     texture = {{ file = \"{file}\", color_space = \"linear\" }}\n"
                );
                let scene = plane_scene(&d, &format!("{mode}-{format}-{file}"), &material, "");
                let got = centre(&scene);
                let want = tex_env(m, f, base, t(alpha), cc).unwrap();
                // The frame holds premultiplied colour over transparent black.
                let want = (want.truncate() * want.w).extend(want.w);
                assert!(
                    (got - want).abs().max_element() < 2e-3,
                    "{mode} {format} {file}: {got} ≠ {want}"
                );
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 2 * (8 * 6 - 4));
}

#[test]
fn stages_apply_in_order() {
    // Replace by an opaque red, then modulate by a grey 0.5: 0.5 red; the other order: red.
    let d = dir("order");
    constant_png(&d.join("red.png"), [255, 0, 0], None);
    constant_png(&d.join("grey.png"), [128, 128, 128], None);
    let layer = |mode: &str, file: &str| {
        format!(
            "[[materials.m.layers]]\nmode = \"{mode}\"\n\
             texture = {{ file = \"{file}\", color_space = \"linear\" }}\n"
        )
    };
    let a = plane_scene(
        &d,
        "a",
        &format!(
            "unlit = true\n{}{}",
            layer("replace", "red.png"),
            layer("modulate", "grey.png")
        ),
        "",
    );
    let b = plane_scene(
        &d,
        "b",
        &format!(
            "unlit = true\n{}{}",
            layer("modulate", "grey.png"),
            layer("replace", "red.png")
        ),
        "",
    );
    let (a, b) = (centre(&a), centre(&b));
    assert!((a.x - 128.0 / 255.0).abs() < 2e-3 && a.y == 0.0, "{a}");
    assert!((b.x - 1.0).abs() < 2e-3 && b.y == 0.0, "{b}");
}

#[test]
fn a_detail_map_of_mid_grey_changes_nothing() {
    let d = dir("detail");
    constant_png(&d.join("grey.png"), [128, 128, 128], None);
    let plain = plane_scene(
        &d,
        "plain",
        "unlit = true\nbase_color = [0.3, 0.5, 0.7, 1.0]",
        "",
    );
    let detail = plane_scene(
        &d,
        "detail",
        "unlit = true\nbase_color = [0.3, 0.5, 0.7, 1.0]\n\
         [[materials.m.layers]]\nmode = \"detail\"\ntexture = { file = \"grey.png\", uv_scale = 16 }\n",
        "",
    );
    let (a, b) = (centre(&plain), centre(&detail));
    // 2·(128/255) = 1.0039: within 0.4% of the colour.
    assert!((a - b).abs().max_element() < 0.004, "{a} {b}");
}

#[test]
fn a_light_map_multiplies_the_diffuse_factor_on_uv_set_1() {
    let d = dir("lightmap");
    constant_png(&d.join("light.png"), [102, 102, 102], None);
    let texgen = "texgen = { projection = \"planar-y\", set = 1 }";
    // Unlit: D = 1, so C·L·intensity = 0.5 · 0.4 · 2 = 0.4.
    let unlit = plane_scene(
        &d,
        "unlit",
        "unlit = true\nbase_color = [0.5, 0.5, 0.5, 1.0]\n\
         [materials.m.light_map]\nfile = \"light.png\"\ncolor_space = \"linear\"\nscale = 2.0\n",
        texgen,
    );
    let got = centre(&unlit);
    assert!((got.x - 0.4).abs() < 2e-3, "{got}");
    // Lit: the light map scales D (ambient + diffuse) and leaves the specular term.
    let lit = |name: &str, map: bool| {
        let mut m = String::from("base_color = [0.5, 0.5, 0.5, 1.0]\nspecular = 0.0\n");
        if map {
            m += "[materials.m.light_map]\nfile = \"light.png\"\ncolor_space = \"linear\"\nscale = 2.0\n";
        }
        centre(&plane_scene(&d, name, &m, texgen))
    };
    let (without, with) = (lit("lit-a", false), lit("lit-b", true));
    assert!(
        (with.x - without.x * 0.8).abs() < 3e-3,
        "{with} vs {without}"
    );
}

/// The scene file's error, one line.
fn load_error(path: &Path) -> String {
    match texmap::scene::load(path, &Default::default()) {
        Ok(_) => panic!("{} loaded", path.display()),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_surface_detail_is_refused_naming_the_file_and_table() {
    let d = dir("bad");
    constant_png(&d.join("ok.png"), [128, 128, 128], None);
    let cases: [(&str, &str, &str, &str); 7] = [
        (
            "missing",
            "[[materials.m.layers]]\nmode = \"modulate\"\ntexture = { file = \"nope.png\" }\n",
            "",
            "nope.png",
        ),
        (
            "mode",
            "[[materials.m.layers]]\nmode = \"combine\"\ntexture = { file = \"ok.png\" }\n",
            "",
            "materials.m: layers[0]: mode \"combine\"",
        ),
        (
            "decal",
            "[[materials.m.layers]]\nmode = \"decal\"\nformat = \"luminance\"\ntexture = { file = \"ok.png\" }\n",
            "",
            "decal is undefined for format luminance",
        ),
        (
            "constant",
            "[[materials.m.layers]]\nmode = \"blend\"\ntexture = { file = \"ok.png\" }\n",
            "",
            "mode blend needs a constant",
        ),
        (
            "uv1",
            "[materials.m.light_map]\nfile = \"ok.png\"\n",
            "",
            "light_map reads uv set 1, which the mesh does not have",
        ),
        (
            "layer-uv1",
            "[[materials.m.layers]]\nmode = \"add\"\ntexture = { file = \"ok.png\", tex_coord = 1 }\n",
            "",
            "layers[0] reads uv set 1",
        ),
        (
            "toon",
            "[materials.m.toon]\nbands = 3\nramp = { file = \"ok.png\" }\n",
            "",
            "toon: both bands and ramp",
        ),
    ];
    for (name, material, mesh, want) in cases {
        let path = plane_scene(&d, name, material, mesh);
        let err = load_error(&path);
        assert!(err.contains(want), "{name}: {err}");
        assert_eq!(err.lines().count(), 1, "{name}: {err}");
        if name != "missing" {
            assert!(err.contains(&format!("{name}.toml")), "{name}: {err}");
        }
    }
    // Nine layers: at most eight.
    let nine =
        "[[materials.m.layers]]\nmode = \"add\"\ntexture = { file = \"ok.png\" }\n".repeat(9);
    let err = load_error(&plane_scene(&d, "nine", &nine, ""));
    assert!(err.contains("9 layers: at most 8"), "{err}");
}

fn golden_scene(name: &str) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    if !root.join("../shared/assets/textures/photos").is_dir() {
        eprintln!("SKIPPED: the asset corpus ../shared/assets is absent");
        return;
    }
    let loaded = texmap::scene::load(
        &root.join(format!("scenes/{name}.toml")),
        &Default::default(),
    )
    .unwrap();
    let camera = loaded.scene.camera.unwrap();
    let settings = Settings::new(320, 180).with_ssaa(2);
    let img = render(&loaded.scene, &camera, &settings)
        .unwrap()
        .to_srgb8();
    common::assert_golden(&format!("scene_{name}"), 320, 180, &img, MIN_PSNR);
}

#[test]
fn golden_multitexture() {
    golden_scene("multitexture");
}

#[test]
fn golden_detail() {
    golden_scene("detail");
}

#[test]
fn golden_lightmap() {
    golden_scene("lightmap");
}

#[test]
fn golden_toon() {
    golden_scene("toon");
}
