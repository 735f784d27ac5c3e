//! Which loader reads a file: the extension decides (case-insensitive), nothing else —
//! contents are never sniffed, so a file's name tells the user what texmap will do with it.

use std::path::Path;

use crate::{Error, Result};

/// The kinds of scene file texmap reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SceneFormat {
    /// `.gltf`, `.glb`.
    Gltf,
    /// `.obj` (with its `.mtl` files).
    Obj,
    /// `.toml`: a texmap scene.
    Toml,
}

impl SceneFormat {
    /// The format `path`'s extension names.
    ///
    /// # Errors
    /// [`Error::Unsupported`] naming the file when texmap reads no file with that extension.
    pub(crate) fn of(path: &Path) -> Result<SceneFormat> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        match ext.as_str() {
            "gltf" | "glb" => Ok(SceneFormat::Gltf),
            "obj" => Ok(SceneFormat::Obj),
            "toml" => Ok(SceneFormat::Toml),
            _ => Err(Error::Unsupported(format!(
                "{}: not a scene file texmap reads (.gltf, .glb, .obj, .toml)",
                path.display()
            ))),
        }
    }
}
