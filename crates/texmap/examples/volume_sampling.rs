//! Times the two ways the ray marcher can read a volume: the plain 16-bit copy
//! (`Volume::value_at`) and the texture engine (`Volume::value_at_engine`, i.e. `sample_3d`),
//! over the same 4 million points of a 128³ volume, one thread.
//!
//! `cargo run --release -p texmap --example volume_sampling`

use std::time::Instant;

use glam::{Mat4, Vec3};
use texmap::volume::Volume;

fn main() -> texmap::Result<()> {
    let n = 128u32;
    let values: Vec<f32> = (0..n * n * n)
        .map(|i| ((i * 2_654_435_761u32) >> 24) as f32)
        .collect();
    let vol = Volume::from_scalars([n; 3], Mat4::IDENTITY, values)?;
    let mut s = 1u32;
    let pts: Vec<Vec3> = (0..4_000_000)
        .map(|_| {
            let mut r = || {
                s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (s >> 8) as f32 / (1u32 << 24) as f32 * (n - 1) as f32
            };
            Vec3::new(r(), r(), r())
        })
        .collect();
    for (name, engine) in [("plain u16 copy", false), ("texture engine", true)] {
        let t = Instant::now();
        let mut acc = 0.0f64;
        for &p in &pts {
            acc += f64::from(if engine {
                vol.value_at_engine(p)
            } else {
                vol.value_at(p)
            });
        }
        let ns = t.elapsed().as_secs_f64() * 1e9 / pts.len() as f64;
        println!("{name}: {ns:.1} ns per trilinear read (checksum {acc:.0})");
    }
    Ok(())
}
