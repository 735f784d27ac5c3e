//! Renders the grazing-angle plane analytically — exact ray/plane intersection and exact uv
//! derivatives per pixel — through each texture filter, so filter quality can be measured
//! apart from the rasterizer. Same scene conventions as `builtin:plane` and the peers.
//!
//! ```sh
//! cargo run --release --example plane_filters -- TEXTURE.png OUT_DIR [WxH [FILTER,FILTER...]]
//! ```
//! writes `OUT_DIR/<filter>.png` for every filter and prints ms per frame for each.

use std::path::PathBuf;
use std::time::Instant;

use glam::{DVec3, Vec2, Vec4};
use rayon::prelude::*;
use texmap::texture::{
    load::load_texture, load::Limits, sample, ColorSpace, Filter, Footprint, Sampler, Wrap,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 3 {
        return Err("usage: plane_filters TEXTURE.png OUT_DIR [WxH]".into());
    }
    let tex = load_texture(
        &PathBuf::from(&args[1]),
        ColorSpace::Srgb,
        &Limits::default(),
    )?;
    let out = PathBuf::from(&args[2]);
    std::fs::create_dir_all(&out)?;
    let (w, h) = match args.get(3) {
        Some(s) => {
            let (a, b) = s.split_once('x').ok_or("size is WxH")?;
            (a.parse::<u32>()?, b.parse::<u32>()?)
        }
        None => (640, 360),
    };
    // Camera: eye (0,1,0), target (0,0,−50), fov 60°; pixel rows from the top.
    let eye = DVec3::new(0.0, 1.0, 0.0);
    let f = (DVec3::new(0.0, 0.0, -50.0) - eye).normalize();
    let r = f.cross(DVec3::Y).normalize();
    let u = r.cross(f);
    let ty = (30f64).to_radians().tan();
    let tx = ty * w as f64 / h as f64;
    let (dx, dy) = (r * tx * 2.0 / w as f64, -u * ty * 2.0 / h as f64);
    let d0 = f - r * tx + u * ty;
    let uv_scale = 64.0;
    let light = 0.2 + 0.8 * DVec3::new(0.3, 0.8, 0.5).normalize().y as f32;
    let footprint = |px: u32, py: u32| -> Option<Footprint> {
        let d = d0 + dx * (px as f64 + 0.5) + dy * (py as f64 + 0.5);
        if d.y >= 0.0 {
            return None;
        }
        let t = -eye.y / d.y;
        let p = eye + d * t;
        if p.x.abs() > 100.0 || p.z.abs() > 100.0 {
            return None;
        }
        // ∂P/∂x = t·DX + (∂t/∂x)·d with ∂t/∂x = −t·DX.y/d.y (likewise for y).
        let dp = |dd: DVec3| dd * t + d * (-t * dd.y / d.y);
        let to_uv = |q: DVec3| {
            Vec2::new(
                (q.x / 200.0 * uv_scale) as f32,
                (q.z / 200.0 * uv_scale) as f32,
            )
        };
        let uv = Vec2::new(
            ((p.x + 100.0) / 200.0 * uv_scale) as f32,
            ((p.z + 100.0) / 200.0 * uv_scale) as f32,
        );
        Some(Footprint::new(uv, to_uv(dp(dx)), to_uv(dp(dy))))
    };
    let all = "nearest,bilinear,trilinear,aniso2,aniso4,aniso8,aniso16,ewa,sat".to_string();
    for name in args.get(4).unwrap_or(&all).split(',') {
        let sampler = Sampler::new(Filter::parse(name)?, Wrap::Repeat);
        let start = Instant::now();
        let rows: Vec<Vec<u8>> = (0..h)
            .into_par_iter()
            .map(|py| {
                let mut row = Vec::with_capacity(w as usize * 3);
                for px in 0..w {
                    let c = footprint(px, py)
                        .map_or(Vec4::ZERO, |fp| sample(&tex, &sampler, &fp) * light);
                    row.extend([c.x, c.y, c.z].map(texmap::color::linear_to_srgb8));
                }
                row
            })
            .collect();
        let ms = start.elapsed().as_secs_f64() * 1e3;
        let img = image::RgbImage::from_raw(w, h, rows.concat()).ok_or("image size")?;
        img.save(out.join(format!("{name}.png")))?;
        println!("{name:10} {ms:8.1} ms");
    }
    Ok(())
}
