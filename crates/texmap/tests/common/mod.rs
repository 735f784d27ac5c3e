//! What the integration tests share: golden-image comparison, the asset corpus's folder,
//! meshes made in code.
//!
//! Policy: an image matches its reference when its PSNR against it (8-bit sRGB, RGB) is at
//! least the test's stated threshold. On a mismatch the actual image and a difference image
//! are written to `target/golden-failures/`. `REPLACE=1` rewrites the references (review them
//! by eye before committing). A missing reference fails the test.

#![allow(dead_code)]

use std::path::PathBuf;

use glam::{Vec3, Vec4};
use texmap::metrics::compare_rgb8;
use texmap::pipeline::{FragmentShader, Quad};

/// A fragment shader writing varyings 0 and 1 as the colour, alpha 1.
pub struct Uv;

impl FragmentShader for Uv {
    fn shade(&self, _: u32, q: &Quad, out: &mut [Vec4; 4]) -> u8 {
        for (j, o) in out.iter_mut().enumerate() {
            let v = q.pixel(j);
            *o = Vec4::new(v[0], v[1], 0.0, 1.0);
        }
        q.mask
    }
}

/// The shared asset corpus (`../shared/assets`), or `None` after printing `SKIPPED` when it
/// is absent (tests over it then pass without running).
pub fn assets() -> Option<PathBuf> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/assets");
    if p.is_dir() {
        Some(p)
    } else {
        eprintln!("SKIPPED: the asset corpus {} is absent", p.display());
        None
    }
}

fn golden_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

/// Compares `rgb` (w×h RGB8) with `tests/golden/<name>.png` at `min_psnr` dB.
pub fn assert_golden(name: &str, w: u32, h: u32, rgb: &[u8], min_psnr: f64) {
    let path = golden_dir().join(format!("{name}.png"));
    if std::env::var_os("REPLACE").is_some() {
        std::fs::create_dir_all(golden_dir()).unwrap();
        image::RgbImage::from_raw(w, h, rgb.to_vec())
            .unwrap()
            .save(&path)
            .unwrap();
        eprintln!("REPLACED {}", path.display());
        return;
    }
    let reference = match image::open(&path) {
        Ok(img) => img.to_rgb8(),
        Err(e) => panic!(
            "{}: {e} (run with REPLACE=1 to create it, then review it)",
            path.display()
        ),
    };
    assert_eq!(
        reference.dimensions(),
        (w, h),
        "{name}: size differs from the reference"
    );
    let c = compare_rgb8(reference.as_raw(), rgb, w as usize, h as usize, None);
    if c.psnr_db < min_psnr {
        let out = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/golden-failures");
        std::fs::create_dir_all(&out).unwrap();
        image::RgbImage::from_raw(w, h, rgb.to_vec())
            .unwrap()
            .save(out.join(format!("{name}.actual.png")))
            .unwrap();
        let diff: Vec<u8> = rgb
            .iter()
            .zip(reference.as_raw())
            .map(|(a, b)| (a.abs_diff(*b) as u32 * 8).min(255) as u8)
            .collect();
        image::RgbImage::from_raw(w, h, diff)
            .unwrap()
            .save(out.join(format!("{name}.diff.png")))
            .unwrap();
        panic!(
            "{name}: PSNR {:.2} dB < {min_psnr} dB against {} (actual and diff in {})",
            c.psnr_db,
            path.display(),
            out.display()
        );
    }
}

/// Icosphere of radius 1 with `levels` subdivisions (20·4^levels triangles, outward CCW).
pub fn icosphere(levels: u32) -> (Vec<Vec3>, Vec<u32>) {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut v: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut cache = std::collections::HashMap::new();
        let mut mid = |a: u32, b: u32, v: &mut Vec<Vec3>| {
            *cache.entry((a.min(b), a.max(b))).or_insert_with(|| {
                v.push(((v[a as usize] + v[b as usize]) * 0.5).normalize());
                v.len() as u32 - 1
            })
        };
        let mut g = Vec::with_capacity(f.len() * 4);
        for [a, b, c] in f {
            let (ab, bc, ca) = (mid(a, b, &mut v), mid(b, c, &mut v), mid(c, a, &mut v));
            g.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = g;
    }
    (v, f.into_iter().flatten().collect())
}
