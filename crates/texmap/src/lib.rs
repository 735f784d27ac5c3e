//! texmap: a texture-mapping renderer on the CPU.
//!
//! Conventions, stated once:
//! - Right-handed world, camera looking down −Z (OpenGL, glTF); column vectors; radians.
//! - Texture coordinates in glTF's convention: u to the right, v down the image rows, texel
//!   centres at `(i + 0.5) / width`.
//! - Colour in linear light, `f32`, premultiplied alpha inside the library; sRGB is decoded
//!   when texels are read and encoded once when an image is written.
//!
//! Every texture read goes through one entry point that knows the pixel's footprint:
//!
//! ```
//! use glam::{Vec2, Vec4};
//! use texmap::texture::{sample, ColorSpace, Filter, Footprint, Sampler, Texture2D, Wrap};
//!
//! // A 2×1 texture: black, white (sRGB-encoded).
//! let tex = Texture2D::from_rgba8(2, 1, ColorSpace::Srgb, &[0, 0, 0, 255, 255, 255, 255, 255])?;
//! let sampler = Sampler::new(Filter::BILINEAR, Wrap::ClampToEdge);
//! // Halfway between the two texel centres: the linear-light average, 0.5.
//! let c = sample(&tex, &sampler, &Footprint::point(Vec2::new(0.5, 0.5)));
//! assert!((c - Vec4::new(0.5, 0.5, 0.5, 1.0)).abs().max_element() < 1e-6);
//! # Ok::<(), texmap::Error>(())
//! ```

// The crate's two lint exceptions, stated once:
// `!(x > 0.0)` is how texmap spells "not positive, or NaN" on purpose: degenerate footprints
// and NaN inputs must take the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Hot loops index several parallel arrays (samples, lanes, channels) with one counter.
#![allow(clippy::needless_range_loop)]

pub mod camera;
pub mod color;
pub mod cpu;
mod error;
pub mod files;
pub mod frame;
pub mod geometry;
pub mod metrics;
pub mod pipeline;
pub mod pixels;
pub mod render;
pub mod scene;
pub mod shading;
pub mod texture;
pub mod volume;

pub use error::{Error, Result};

/// A xorshift32 generator from `seed` (not 0): the unit tests' pseudo-random grids, rays and
/// texture coordinates.
#[cfg(test)]
pub(crate) fn xorshift(mut seed: u32) -> impl FnMut() -> u32 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed
    }
}
