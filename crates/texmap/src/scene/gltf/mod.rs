//! glTF 2.0 (`.gltf` with external or data-URI buffers and images, `.glb`).
//!
//! The JSON is parsed by the `gltf` crate without its importer: buffers and images are read
//! by texmap (`buffers`, `textures`), so the folder rule, size bounds and texmap's own image
//! decoder (limits, colour spaces) apply, and accessors are read bounds-checked in any
//! component type, so no accessor read can index out of bounds and `KHR_mesh_quantization`
//! is supported too.
//!
//! Conventions match `gl_render.py`'s glTF path (see `../shared/peers/README.md`): the default
//! scene (else scene 0, else every root node), nodes depth-first in document order, strips and
//! fans converted to lists, skins posed in the rest pose with the joints' node transforms,
//! morph targets at their default weights, base colour = factor × texture × COLOR_0, base
//! colour and emissive textures sRGB and the others linear, samplers straight to our GL
//! filters and wraps (undefined = trilinear, repeat), `KHR_texture_transform` as
//! [`TextureTransform`](crate::texture::TextureTransform).
//!
//! Lighting (`lights`): a uniform environment stands in for the image-based light glTF
//! models are made for, and `KHR_lights_punctual` intensities are divided by π into the
//! Phong model's light units. Materials (`materials`) use the metallic-roughness model
//! unless `KHR_materials_unlit`.
//!
//! Files: `document` (the file → [`Loaded`](crate::scene::Loaded), the loader's state),
//! `buffers` (buffers and accessors), `textures` (images, samplers, texture transforms),
//! `materials`, `extensions` (the material extensions read from raw JSON), `nodes` (the hierarchy), `mesh` (primitives), `skin`, `cameras`, `lights`,
//! `variants` (`KHR_materials_variants`).

mod buffers;
mod cameras;
mod document;
mod extensions;
mod lights;
mod materials;
mod mesh;
mod nodes;
mod packing;
mod skin;
mod textures;
mod variants;

#[cfg(test)]
mod tests;

pub use document::{load, SUPPORTED_EXTENSIONS};
