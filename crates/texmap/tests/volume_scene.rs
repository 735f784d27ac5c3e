//! Volumes beyond a single scan: presets against the peer's own file, scene lights on a
//! synthetic volume, volumes in TOML scenes (placement, transfer function, options, errors)
//! and the example scene's golden image.
//!
//! Tolerances, stated once:
//! - Presets: the same numbers as `vtk_volume.py` (exact, as parsed from both texts).
//! - Golden images ≥ 40 dB PSNR (`tests/common`, `REPLACE=1` rewrites them).

mod common;

use std::path::{Path, PathBuf};

use texmap::volume::transfer::PRESETS;
use texmap::volume::TransferFunction;

/// The string literals of `vtk_volume.py`'s `PRESETS = { "name": "…" "…", … }` (adjacent
/// literals concatenated, `#` comments skipped).
fn python_presets(src: &str) -> Vec<(String, String)> {
    let start = src.find("PRESETS = {").expect("PRESETS in vtk_volume.py") + 11;
    let mut out: Vec<(String, String)> = Vec::new();
    let mut strings: Vec<String> = Vec::new();
    let mut key: Option<String> = None;
    let mut chars = src[start..].chars();
    while let Some(c) = chars.next() {
        match c {
            '#' => {
                for c in chars.by_ref() {
                    if c == '\n' {
                        break;
                    }
                }
            }
            '"' => strings.push(chars.by_ref().take_while(|&c| c != '"').collect()),
            ':' => key = strings.pop(),
            ',' | '}' => {
                if let Some(k) = key.take() {
                    out.push((k, strings.concat()));
                }
                strings.clear();
                if c == '}' {
                    break;
                }
            }
            _ => {}
        }
    }
    out
}

#[test]
fn presets_use_the_points_of_vtk_volume_py() {
    let peer = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/peers/vtk_volume.py");
    let Ok(src) = std::fs::read_to_string(&peer) else {
        eprintln!("SKIPPED: {} is absent", peer.display());
        return;
    };
    let theirs = python_presets(&src);
    assert!(theirs.len() >= 3, "parsed {theirs:?}");
    for (name, points) in &theirs {
        let Some(ours) = TransferFunction::preset(name) else {
            panic!("vtk_volume.py has a preset {name:?} that texmap lacks");
        };
        let peer_tf = TransferFunction::parse(points).expect("the peer's points parse");
        assert_eq!(ours.points(), peer_tf.points(), "{name}");
    }
    // The five presets texmap promises.
    for name in ["ct-bone", "ct-skin", "ct-muscle", "mri", "synth"] {
        assert!(PRESETS.iter().any(|p| p.0 == name), "{name}");
    }
}

#[allow(dead_code)]
fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

// ---- Scene lights ----------------------------------------------------------------------------

use glam::{Mat4, Vec3};
use texmap::render::Frame;
use texmap::scene::Light;
use texmap::volume::{raymarch, render_slices, MarchParams, Volume};

/// A ball: 200 at the centre of a 48³ grid falling linearly to 0 at radius 24 voxels.
fn ball() -> Volume {
    let n = 48u32;
    let c = (n - 1) as f32 * 0.5;
    let mut v = Vec::new();
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let r = Vec3::new(x as f32 - c, y as f32 - c, z as f32 - c).length();
                v.push((200.0 * (1.0 - r / 24.0)).max(0.0));
            }
        }
    }
    Volume::from_scalars([n; 3], Mat4::IDENTITY, v).unwrap()
}

/// Nearly opaque white from 110 up: a surface of radius ≈ 11 voxels.
fn ball_tf() -> TransferFunction {
    TransferFunction::parse("0:1,1,1,0;100:1,1,1,0;110:1,1,1,0.8;200:1,1,1,1").unwrap()
}

/// Mean of the colour channels over the left and the right half of the image.
fn halves(f: &Frame) -> (f64, f64) {
    let (mut l, mut r) = (0.0f64, 0.0f64);
    for (i, c) in f.color.iter().enumerate() {
        let v = f64::from(c.x + c.y + c.z);
        if (i as u32 % f.width) < f.width / 2 {
            l += v;
        } else {
            r += v;
        }
    }
    (l, r)
}

#[test]
fn a_light_from_plus_x_brightens_the_plus_x_side() {
    let vol = ball();
    let tf = ball_tf();
    // vtk_volume.py's camera: along +y, z up, so +x is the right of the image.
    let cam = vol.vtk_camera(1.6, 0.0);
    let light = |x: f32| Light::Directional {
        direction: Vec3::new(x, 0.0, 0.0),
        color: Vec3::ONE,
    };
    let params = |lights: Vec<Light>| MarchParams {
        shade: true,
        jitter: false,
        lights,
        ..MarchParams::default()
    };
    for slices in [false, true] {
        let draw = |p: &MarchParams| {
            if slices {
                render_slices(&vol, &tf, &cam, 64, 64, p).unwrap()
            } else {
                raymarch(&vol, &tf, &cam, 64, 64, p, None).unwrap()
            }
        };
        let (hl, hr) = halves(&draw(&params(Vec::new())));
        let (pl, pr) = halves(&draw(&params(vec![light(1.0)])));
        let (ml, mr) = halves(&draw(&params(vec![light(-1.0)])));
        let what = if slices { "slices" } else { "rays" };
        // The headlight lights both halves alike; a light from +x the right one, from −x the left.
        assert!(
            (hl - hr).abs() < 0.02 * (hl + hr),
            "{what} headlight: {hl} vs {hr}"
        );
        assert!(pr > 1.5 * pl, "{what} light from +x: left {pl}, right {pr}");
        assert!(ml > 1.5 * mr, "{what} light from −x: left {ml}, right {mr}");
        // Mirror images of each other.
        assert!((pr - ml).abs() < 0.02 * pr, "{what}: {pr} vs {ml}");
    }
}
