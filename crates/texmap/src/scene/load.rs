//! The entry point [`load`]: a scene file goes to the loader its extension names
//! ([`super::gltf`], [`super::obj`], [`super::toml`]), and nothing else happens here.
//!
//! Safety rules, the same for every format (enforced by the loaders' shared file helpers):
//! - A reference inside an asset (a glTF URI, an MTL or texture path in an OBJ) resolves from
//!   the asset's folder and may not leave it (`..` above it, an absolute path, a symbolic
//!   link pointing out) unless [`LoadOptions::allow_outside_paths`] is set.
//! - Nothing is fetched over the network: `http:` / `https:` (and any other scheme but
//!   `data:`) are errors.
//! - Files, buffers and data URIs are bounded by [`LoadOptions::max_buffer_bytes`]; images by
//!   the texture [`Limits`](crate::texture::load::Limits).
//! - Triangles with a non-finite vertex (NaN, ±∞) cannot be drawn: they are dropped, with a
//!   warning naming the file and how many.
//! - A TOML scene is written by the user, like a command line: its own paths may point
//!   anywhere (relative ones resolve from the scene file's folder); the assets it names still
//!   follow the rules above inside their own folders.

use std::path::Path;

use super::asset::{LoadOptions, Loaded};
use super::format::SceneFormat;
use crate::Result;

/// Loads a `.gltf`, `.glb`, `.obj` or `.toml` scene file.
///
/// # Errors
/// An [`Error`](crate::Error) naming the file (the scene file or the asset it references) and
/// the problem.
pub fn load(path: &Path, options: &LoadOptions) -> Result<Loaded> {
    let mut loaded = match SceneFormat::of(path)? {
        SceneFormat::Gltf => super::gltf::load(path, options),
        SceneFormat::Obj => super::obj::load(path, options),
        SceneFormat::Toml => super::toml::load(path, options),
    }?;
    let dropped = loaded.scene.drop_unusable_triangles();
    if dropped > 0 {
        loaded.warnings.push(format!(
            "{}: {dropped} triangle{} with a non-finite position not drawn",
            path.display(),
            if dropped == 1 { "" } else { "s" }
        ));
    }
    Ok(loaded)
}
