//! Tiled versus row-major texel layout: walks a 2048² sRGB RGBA8 texture with trilinear
//! footprints in three directions (across rows, down columns, diagonally) and prints ns per
//! sample. Run it under `valgrind --tool=cachegrind --cache-sim=yes` for cache-miss counts
//! that do not depend on the machine's load.
//!
//! ```sh
//! cargo run --release --example layout_walk -- tiled|row-major
//! ```

use std::time::Instant;

use glam::{Vec2, Vec4};
use texmap::texture::{
    sample_batch, ColorSpace, Filter, Footprint, Format, Layout, Sampler, Texture2D,
    TextureOptions, Wrap,
};

fn main() {
    let layout = match std::env::args().nth(1).as_deref() {
        Some("row-major") => Layout::RowMajor,
        _ => Layout::Tiled4x4,
    };
    const N: u32 = 2048;
    let mut s = 0x1234_5678u32;
    let rgba: Vec<u8> = (0..N * N * 4)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            (s >> 24) as u8
        })
        .collect();
    let options = TextureOptions::default().with_layout(layout);
    let tex =
        Texture2D::from_texels(N, N, Format::Rgba8, ColorSpace::Srgb, &rgba, options).unwrap();
    let sampler = Sampler::new(Filter::TRILINEAR, Wrap::Repeat);
    // 256×256 pixels, 1.5 texels per pixel, in three orientations.
    let grid = 256u32;
    let mut out = vec![Vec4::ZERO; (grid * grid) as usize];
    for (name, dx, dy) in [
        ("across", Vec2::new(1.5, 0.0), Vec2::new(0.0, 1.5)),
        ("down", Vec2::new(0.0, 1.5), Vec2::new(1.5, 0.0)),
        ("diagonal", Vec2::new(1.06, 1.06), Vec2::new(-1.06, 1.06)),
    ] {
        let (dx, dy) = (dx / N as f32, dy / N as f32);
        let fps: Vec<Footprint> = (0..grid * grid)
            .map(|i| {
                let (x, y) = ((i % grid) as f32, (i / grid) as f32);
                Footprint::new(Vec2::new(0.3, 0.2) + dx * x + dy * y, dx, dy)
            })
            .collect();
        let start = Instant::now();
        let reps = 5;
        for _ in 0..reps {
            sample_batch(&tex, &sampler, &fps, &mut out);
        }
        let ns = start.elapsed().as_nanos() as f64 / (reps * fps.len()) as f64;
        println!("{layout:?} {name:9} {ns:6.1} ns/sample");
    }
}
