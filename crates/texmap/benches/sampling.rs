//! Sampling throughput: every filter on a 2048² sRGB RGBA8 texture, for magnification, 4:1
//! minification and 16:1 anisotropic footprints, plus the tiled-versus-row-major layout.
//!
//! Footprints come from a 64×64 pixel grid walking the texture as a rasterizer would (each
//! pixel's uv = origin + x·∂uv/∂x + y·∂uv/∂y), so cache behaviour is that of a real frame.
//!
//! `quads/*` reads the same grid as the rasterizer does: 2×2 quads sharing their derivatives,
//! eight quads per `sample_quads_lanes` call (the GL filters; for the others it reads
//! pixel by pixel).
//!
//! `cargo bench --bench sampling` (criterion reports time per batch of 4096 samples and
//! elements/s; ns/sample = time / 4096).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use glam::Vec2;
use texmap::texture::{
    sample_batch, sample_quads_lanes, ColorSpace, Filter, Footprint, Format, Layout, QuadCoords,
    Sampler, Texture2D, TextureOptions, Wrap,
};

const N: u32 = 2048;
const GRID: u32 = 64;

fn texture(layout: Layout) -> Texture2D {
    // A value-noise-like pattern: cheap to make, no flat runs.
    let mut rgba = vec![0u8; (N * N * 4) as usize];
    let mut s = 0x9e37_79b9u32;
    for b in rgba.iter_mut() {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        *b = (s >> 24) as u8;
    }
    Texture2D::from_texels(
        N,
        N,
        Format::Rgba8,
        ColorSpace::Srgb,
        &rgba,
        TextureOptions::default().with_layout(layout),
    )
    .unwrap()
}

/// A 64×64 grid of footprints with the given per-pixel derivatives (in texels).
fn grid(dx_texels: Vec2, dy_texels: Vec2) -> Vec<Footprint> {
    let (dx, dy) = (dx_texels / N as f32, dy_texels / N as f32);
    let origin = Vec2::new(0.123, 0.377);
    (0..GRID * GRID)
        .map(|i| {
            let (x, y) = ((i % GRID) as f32, (i / GRID) as f32);
            Footprint::new(origin + dx * x + dy * y, dx, dy)
        })
        .collect()
}

fn cases() -> Vec<(&'static str, Vec<Footprint>)> {
    let a = 0.4f32; // rotate the anisotropic footprint off the axes
    let major = Vec2::new(a.cos(), a.sin());
    let minor = Vec2::new(-a.sin(), a.cos());
    vec![
        ("magnify", grid(Vec2::new(0.5, 0.0), Vec2::new(0.0, 0.5))),
        ("minify4", grid(Vec2::new(4.0, 0.0), Vec2::new(0.0, 4.0))),
        ("aniso16", grid(major * 16.0, minor)),
    ]
}

fn filters(c: &mut Criterion) {
    let tex = texture(Layout::Tiled4x4);
    let mut out = vec![glam::Vec4::ZERO; (GRID * GRID) as usize];
    for (case, fps) in cases() {
        let mut g = c.benchmark_group(format!("sample/{case}"));
        g.throughput(Throughput::Elements(fps.len() as u64));
        for name in [
            "nearest",
            "bilinear",
            "trilinear",
            "aniso4",
            "aniso16",
            "ewa",
            "sat",
        ] {
            let s = Sampler::new(Filter::parse(name).unwrap(), Wrap::Repeat);
            g.bench_function(BenchmarkId::from_parameter(name), |b| {
                b.iter(|| sample_batch(&tex, &s, &fps, &mut out))
            });
        }
        g.finish();
    }
}

/// The grid's footprints as 2×2 quads (pixel j of a quad in lane j).
fn quads(fps: &[Footprint]) -> Vec<QuadCoords> {
    let g = GRID as usize;
    let mut out = Vec::new();
    for qy in (0..g).step_by(2) {
        for qx in (0..g).step_by(2) {
            let px = |j: usize| &fps[(qy + (j >> 1)) * g + qx + (j & 1)];
            out.push(QuadCoords {
                u: glam::Vec4::from_array(std::array::from_fn(|j| px(j).uv.x)),
                v: glam::Vec4::from_array(std::array::from_fn(|j| px(j).uv.y)),
                duv_dx: px(0).duv_dx,
                duv_dy: px(0).duv_dy,
            });
        }
    }
    out
}

fn quad_reads(c: &mut Criterion) {
    let tex = texture(Layout::Tiled4x4);
    for (case, fps) in cases() {
        let coords = quads(&fps);
        let masks = vec![0b1111u8; coords.len()];
        let mut out = vec![[glam::Vec4::ZERO; 4]; coords.len()];
        let mut g = c.benchmark_group(format!("quads/{case}"));
        g.throughput(Throughput::Elements(fps.len() as u64));
        for name in ["nearest", "bilinear", "trilinear"] {
            let s = Sampler::new(Filter::parse(name).unwrap(), Wrap::Repeat);
            g.bench_function(BenchmarkId::from_parameter(name), |b| {
                b.iter(|| {
                    for ((c, m), o) in coords.chunks(8).zip(masks.chunks(8)).zip(out.chunks_mut(8))
                    {
                        sample_quads_lanes(&tex, &s, c, m, o);
                    }
                })
            });
        }
        g.finish();
    }
}

fn layout(c: &mut Criterion) {
    let mut out = vec![glam::Vec4::ZERO; (GRID * GRID) as usize];
    // Footprints walking down the texture (v fastest), where row-major order hurts most.
    let down: Vec<Footprint> = grid(Vec2::new(0.0, 1.5), Vec2::new(1.5, 0.0));
    let mut g = c.benchmark_group("layout");
    g.throughput(Throughput::Elements(down.len() as u64));
    for layout in [Layout::Tiled4x4, Layout::RowMajor] {
        let tex = texture(layout);
        for name in ["bilinear", "trilinear", "aniso16"] {
            let s = Sampler::new(Filter::parse(name).unwrap(), Wrap::Repeat);
            g.bench_function(format!("{layout:?}/{name}"), |b| {
                b.iter(|| sample_batch(&tex, &s, &down, &mut out))
            });
        }
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(2));
    targets = filters, quad_reads, layout
}
criterion_main!(benches);
