//! Writing a frame as 8-bit sRGB: ns per pixel of [`Frame::to_srgb8`]'s encoding, one thread
//! (`cargo bench --bench encode`): the scalar encoder's loop (`srgb8`), and the rows as the
//! frame encodes them (`encode_srgb8`, `encode_srgba8`: in AVX2 lanes on x86-64-v3, the scalar
//! loop elsewhere or with `TEXMAP_CPU=baseline`). The pixels are a rendered frame's kind of values: smooth
//! shading with texture detail, a share of black background and a few highlights over 1.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use glam::Vec4;
use texmap::color::{encode_srgb8, encode_srgba8, Srgb8Encoder};

const W: usize = 1920;
const H: usize = 64;

fn pixels() -> Vec<Vec4> {
    let mut state = 0x9e37_79b9_u32;
    let mut rnd = move || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state as f32 / u32::MAX as f32
    };
    (0..W * H)
        .map(|i| {
            let (x, y) = ((i % W) as f32 / W as f32, (i / W) as f32 / H as f32);
            if x < 0.2 {
                return Vec4::new(0.0, 0.0, 0.0, 1.0);
            }
            let shade = 0.05 + 0.9 * x * (0.5 + 0.5 * y);
            let detail = 0.6 + 0.5 * rnd();
            let c = shade * detail;
            Vec4::new(c, c * 0.8, c * 0.6 + 0.02, 1.0)
        })
        .collect()
}

fn encode(c: &mut Criterion) {
    let px = pixels();
    let mut g = c.benchmark_group("encode");
    g.throughput(Throughput::Elements(px.len() as u64));
    g.bench_function("srgb8", |b| {
        let e = Srgb8Encoder::new();
        let mut out = vec![0u8; px.len() * 3];
        b.iter(|| {
            for (o, c) in out.chunks_exact_mut(3).zip(black_box(&px)) {
                o.copy_from_slice(&[e.encode(c.x), e.encode(c.y), e.encode(c.z)]);
            }
            black_box(&out);
        });
    });
    g.bench_function("encode_srgb8", |b| {
        let mut out = vec![0u8; px.len() * 3];
        b.iter(|| {
            encode_srgb8(black_box(&px), &mut out);
            black_box(&out);
        });
    });
    g.bench_function("encode_srgba8", |b| {
        let mut out = vec![0u8; px.len() * 4];
        b.iter(|| {
            encode_srgba8(black_box(&px), &mut out);
            black_box(&out);
        });
    });
    g.finish();
}

criterion_group!(benches, encode);
criterion_main!(benches);
