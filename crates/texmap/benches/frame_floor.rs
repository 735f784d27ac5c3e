//! The frame-write floor of issue 16's aim (the 1080p trilinear plane within 5× of it): the
//! time to write one 1920×1080 frame and its depth and nothing else, on two threads (each
//! writes half the rows), as `texmap render --threads 2` writes its frames
//! (`cargo bench --bench frame_floor`):
//!
//! - `rgba8_depth`: 8-bit RGBA colour and f32 depth (8 bytes a pixel), the floor as the
//!   issue states it;
//! - `rgba32f_depth`: texmap's own frame, f32 RGBA colour with the streaming stores the tiles
//!   are resolved with ([`stream_fill`]), and f32 depth (20 bytes a pixel).
//!
//! The buffers are written again and again, so this is the warm floor: no page faults, and
//! on a machine whose last-level cache holds the 16.6 MB of `rgba8_depth` that one is written
//! to the cache, not to memory.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::Vec4;
use texmap::pipeline::framebuffer::{stream_fence, stream_fill};

const W: usize = 1920;
const H: usize = 1080;

/// Writes each half of `a` and `b` on its own thread with `fill`.
fn halves<A: Send, B: Send>(a: &mut [A], b: &mut [B], fill: impl Fn(&mut [A], &mut [B]) + Sync) {
    let (a0, a1) = a.split_at_mut(a.len() / 2);
    let (b0, b1) = b.split_at_mut(b.len() / 2);
    std::thread::scope(|s| {
        s.spawn(|| fill(a0, b0));
        fill(a1, b1);
    });
}

fn floor(c: &mut Criterion) {
    let mut g = c.benchmark_group("frame_floor");
    g.throughput(Throughput::Elements((W * H) as u64));
    let mut depth = vec![0.0f32; W * H];
    let mut rgba8 = vec![[0u8; 4]; W * H];
    let mut k = 0u8;
    g.bench_function("rgba8_depth", |b| {
        b.iter(|| {
            k = k.wrapping_add(1);
            halves(&mut rgba8, &mut depth, |c, d| {
                c.fill([k; 4]);
                d.fill(f32::from(k));
            });
        });
    });
    let mut rgba32f = vec![Vec4::ZERO; W * H];
    g.bench_function("rgba32f_depth", |b| {
        b.iter(|| {
            k = k.wrapping_add(1);
            halves(&mut rgba32f, &mut depth, |c, d| {
                stream_fill(c, Vec4::splat(f32::from(k)));
                stream_fence();
                d.fill(f32::from(k));
            });
        });
    });
    g.finish();
}

criterion_group!(benches, floor);
criterion_main!(benches);
