//! The texture sampling engine: storage, mip chains, wrap modes and filters.
//!
//! Every texture read in texmap goes through [`sample`] (2D, with [`sample_quad`] and
//! [`sample_quads_lanes`] for the rasterizer's quads), [`sample_cube`] or [`sample_3d`], which
//! take the pixel's footprint and return linear, premultiplied RGBA.
//!
//! A read runs the same steps whatever the texture kind: the footprint's derivatives give λ
//! ([`LodRule`], `footprint.rs`), the sampler's bias and clamps adjust it ([`Sampler`]),
//! OpenGL filters choose their levels from it ([`MipChoice`], `lod.rs`, written once for every
//! kind), and the filter reads those levels (`filter/`, `cube.rs`, `texture3d.rs`). Nothing
//! here knows the pipeline: the module uses only `color`, the crate's `Error`, `glam` and,
//! to decode files, `image`.

pub mod compressed;
pub mod container;
mod cube;
pub mod environment;
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
pub mod virtual_texture;
mod wrap;

pub use cube::{sample_cube, CubeFace, TextureCube};
pub use environment::{load_environment, EnvironmentKind, EnvironmentMap};
pub use filter::{
    quad_mip_choice, sample, sample_batch, sample_lanes, sample_quad, sample_quad_lanes,
    sample_quad_lanes_at, sample_quads_lanes, sample_quads_lanes_shared, QuadCoords, SharedQuads,
    StagedQuads, QUADS_STAGED,
};
pub use footprint::{
    CubeFootprint, CubeFootprintLanes, Footprint, Footprint3, FootprintLanes, LodRule,
};
pub use format::{f16_to_f32, f32_to_f16, ColorSpace, Format};
pub use lod::{MipBlend, MipChoice, TexelFilter};
pub use mip::level_count;
pub use sampler::{AnisoLod, Filter, MagFilter, MinFilter, Sampler, UnknownName};
pub use storage::{Layout, Level, Storage, Texture2D, TextureOptions};
pub use texture3d::{sample_3d, Texture3D};
pub use transform::TextureTransform;
pub use virtual_texture::VirtualTexture;
pub use wrap::{Wrap, BORDER};
