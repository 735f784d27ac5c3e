//! The texture sampling engine: storage, mip chains, wrap modes and filters.
//!
//! Every texture read in texmap goes through [`sample`] (2D), [`sample_cube`] or
//! [`sample_3d`], which take the pixel's footprint and return linear, premultiplied RGBA.

mod cube;
pub(crate) mod filter;
pub(crate) mod footprint;
pub(crate) mod format;
pub mod load;
mod lod;
mod mip;
pub mod procedural;
mod sampler;
mod storage;
mod texture3d;
mod transform;
mod wrap;

pub use cube::{sample_cube, CubeFace, TextureCube};
pub use filter::{
    sample, sample_batch, sample_quad, sample_quad_lanes, sample_quads_lanes, QuadCoords,
};
pub use footprint::{CubeFootprint, Footprint, Footprint3, LodRule};
pub use format::{f16_to_f32, f32_to_f16, ColorSpace, Format};
pub use lod::{MipBlend, MipChoice, TexelFilter};
pub use mip::level_count;
pub use sampler::{Filter, MagFilter, MinFilter, Sampler, UnknownName};
pub use storage::{Layout, Level, Storage, Texture2D, TextureOptions};
pub use texture3d::{sample_3d, Texture3D};
pub use transform::TextureTransform;
pub use wrap::{Wrap, BORDER};
