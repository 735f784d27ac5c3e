//! Noise throughput: ns per `noise3`, per noise with gradient, and per 6-octave fBm and
//! marble evaluation (`cargo bench --bench procedural`).

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use glam::DVec3;
use texmap::texture::procedural::perlin::{fbm, noise3, noise3_with_gradient};
use texmap::texture::procedural::Solid;

const N: usize = 4096;

fn points() -> Vec<DVec3> {
    (0..N)
        .map(|i| {
            let t = i as f64;
            DVec3::new(
                t * 0.0371 + 0.5,
                (t * 0.6180339) % 37.0,
                (t * 0.41421) % 11.0 - 5.0,
            )
        })
        .collect()
}

fn noise(c: &mut Criterion) {
    let pts = points();
    let mut g = c.benchmark_group("perlin");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("noise3", |b| {
        b.iter(|| pts.iter().map(|p| noise3(p.x, p.y, p.z)).sum::<f64>())
    });
    g.bench_function("noise3_with_gradient", |b| {
        b.iter(|| {
            pts.iter()
                .map(|p| noise3_with_gradient(p.x, p.y, p.z).1.x)
                .sum::<f64>()
        })
    });
    g.bench_function("fbm6", |b| {
        b.iter(|| pts.iter().map(|&p| fbm(p, 6.0, 2.0, 0.5)).sum::<f64>())
    });
    let marble = Solid::named("marble").unwrap();
    g.bench_function("marble", |b| {
        b.iter(|| {
            pts.iter()
                .map(|&p| marble.value(black_box(p), DVec3::splat(1e-3)))
                .sum::<f64>()
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(2));
    targets = noise
}
criterion_main!(benches);
