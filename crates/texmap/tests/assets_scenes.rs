//! Every model of the shared corpus (`../shared/assets/gltf`, `../shared/assets/obj`) loads
//! and renders, and matches its golden image in `tests/golden/` (320×240, lit with the file's
//! lights or the peer's default light, the peers' framing camera, each texture's own sampler).
//!
//! Tolerance: PSNR ≥ 40 dB against the golden (8-bit sRGB, all pixels). A failure writes
//! `target/golden-diff/<name>.png` as expected | actual | ×8 difference. `REPLACE=1`
//! regenerates the goldens; review each by eye against the model's `screenshot/` before
//! committing. Without the corpus the test prints `SKIPPED` and passes.

mod common;

use common::assets;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use texmap::metrics::compare_rgb8;
use texmap::render::{render, Settings};
use texmap::scene::{load, LoadOptions, TextureSlot};
use texmap::texture::load::{load_texture, Limits};
use texmap::texture::{ColorSpace, Sampler};

const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;
const MIN_PSNR_DB: f64 = 40.0;

/// Files with one of `exts` in `dir`, down to `depth` folders below, sorted.
fn find(dir: &Path, depth: usize, exts: &[&str], out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<PathBuf> = rd.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() && depth > 0 {
            find(&p, depth - 1, exts, out);
        } else if p
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| exts.contains(&e.to_ascii_lowercase().as_str()))
        {
            out.push(p);
        }
    }
}

/// Every .gltf/.glb in the models' variant folders, and every .obj.
fn models(root: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    find(&root.join("gltf"), 2, &["gltf", "glb"], &mut out);
    find(&root.join("obj"), 1, &["obj"], &mut out);
    out
}

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

fn render_model(path: &Path) -> Vec<u8> {
    let loaded = load(path, &LoadOptions::default())
        .unwrap_or_else(|e| panic!("{} does not load: {e}", path.display()));
    let mut scene = loaded.scene;
    // Spot ships its texture without an MTL: bind it as the base colour, as the peers do
    // with --texture.
    let tex = path.with_file_name("spot_texture.png");
    if path
        .file_name()
        .is_some_and(|n| n == "spot_triangulated.obj")
        && tex.exists()
    {
        let t = Arc::new(load_texture(&tex, ColorSpace::Srgb, &Limits::default()).unwrap());
        for m in &mut scene.materials {
            m.base_color_texture = Some(TextureSlot::new(t.clone(), Sampler::default()));
        }
    }
    let camera = scene.framing_camera(60.0);
    let settings = Settings::new(WIDTH, HEIGHT);
    let frame = render(&scene, &camera, &settings)
        .unwrap_or_else(|e| panic!("{} does not render: {e}", path.display()));
    frame.to_srgb8()
}

fn name_of(path: &Path) -> String {
    path.file_stem().unwrap().to_string_lossy().into_owned()
}

#[test]
fn every_corpus_model_matches_its_golden() {
    let Some(root) = assets() else { return };
    let list = models(&root);
    assert!(
        list.len() >= 12,
        "expected the corpus's models, found {list:?}"
    );
    let replace = std::env::var_os("REPLACE").is_some();
    let mut failures = Vec::new();
    for path in &list {
        let name = name_of(path);
        let rgb = render_model(path);
        let golden = golden_dir().join(format!("{name}.png"));
        if replace {
            std::fs::create_dir_all(golden_dir()).unwrap();
            image::RgbImage::from_raw(WIDTH, HEIGHT, rgb)
                .unwrap()
                .save(&golden)
                .unwrap();
            eprintln!("wrote {}", golden.display());
            continue;
        }
        let Ok(expected) = image::open(&golden) else {
            failures.push(format!(
                "{name}: no golden {} (run with REPLACE=1)",
                golden.display()
            ));
            continue;
        };
        let expected = expected.to_rgb8();
        let c = compare_rgb8(
            expected.as_raw(),
            &rgb,
            WIDTH as usize,
            HEIGHT as usize,
            None,
        );
        eprintln!("{name}: PSNR {:.2} dB", c.psnr_db);
        if c.psnr_db < MIN_PSNR_DB {
            let diff_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/golden-diff");
            std::fs::create_dir_all(&diff_dir).unwrap();
            let mut side = image::RgbImage::new(WIDTH * 3, HEIGHT);
            for y in 0..HEIGHT {
                for x in 0..WIDTH {
                    let i = ((y * WIDTH + x) * 3) as usize;
                    let e = [
                        expected.as_raw()[i],
                        expected.as_raw()[i + 1],
                        expected.as_raw()[i + 2],
                    ];
                    let a = [rgb[i], rgb[i + 1], rgb[i + 2]];
                    let d = [0, 1, 2].map(|k| (e[k].abs_diff(a[k]) as u32 * 8).min(255) as u8);
                    side.put_pixel(x, y, image::Rgb(e));
                    side.put_pixel(x + WIDTH, y, image::Rgb(a));
                    side.put_pixel(x + 2 * WIDTH, y, image::Rgb(d));
                }
            }
            let p = diff_dir.join(format!("{name}.png"));
            side.save(&p).unwrap();
            failures.push(format!(
                "{name}: PSNR {:.2} dB < {MIN_PSNR_DB} (expected | actual | diff in {})",
                c.psnr_db,
                p.display()
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
