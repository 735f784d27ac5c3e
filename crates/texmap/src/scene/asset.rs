//! What loading a scene file takes and gives: the [`LoadOptions`], the [`Loaded`] result and
//! the [`AssetInfo`] / [`TextureInfo`] that `texmap info` prints. Plain data, shared by every
//! loader; the rules that read files live in `files` and `texture_cache`.

use super::Scene;
use crate::camera::Camera;
use crate::texture::load::Limits;
use crate::texture::{ColorSpace, Format, Storage};

/// How scene files are read.
///
/// Options can grow, so the type is built from [`Default`] with one method per option (the
/// fields stay readable):
///
/// ```
/// use texmap::scene::LoadOptions;
///
/// let options = LoadOptions::default().allow_outside_paths(true).lenient(true);
/// assert!(options.allow_outside_paths && options.lenient);
/// assert_eq!(options.max_buffer_bytes, 1 << 30);
/// ```
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct LoadOptions {
    /// Let references leave the asset's folder (`..`, absolute paths).
    pub allow_outside_paths: bool,
    /// A missing or undecodable texture becomes a warning and a magenta placeholder.
    pub lenient: bool,
    /// Size limits for images.
    pub limits: Limits,
    /// Largest file, buffer or decoded data URI accepted, in bytes (default 1 GiB).
    pub max_buffer_bytes: u64,
    /// The most memory loading one volume may hold (default
    /// [`crate::files::DEFAULT_MAX_BYTES`]).
    pub max_volume_bytes: u64,
    /// Read a scene's environment image (default true); off for a caller that replaces the
    /// map (the command line's `--env`): the environment then holds a black placeholder.
    pub environment_image: bool,
    /// How image textures are held in memory unless a texture says otherwise (TOML
    /// `storage`; `--texture-storage`; default [`Storage::Linear16`], "decoded").
    pub texture_storage: Storage,
    /// A glTF file's material variant (`KHR_materials_variants`, `--variant NAME`): each
    /// primitive takes the material the variant maps it to; a name the file does not define
    /// is an error listing the ones it does. `None`: every primitive's own material.
    pub variant: Option<String>,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            allow_outside_paths: false,
            lenient: false,
            limits: Limits::default(),
            max_buffer_bytes: 1 << 30,
            max_volume_bytes: crate::files::DEFAULT_MAX_BYTES,
            environment_image: true,
            texture_storage: Storage::Linear16,
            variant: None,
        }
    }
}

impl LoadOptions {
    /// Sets [`LoadOptions::allow_outside_paths`] (`--allow-outside-paths`).
    #[must_use]
    pub fn allow_outside_paths(mut self, allow: bool) -> Self {
        self.allow_outside_paths = allow;
        self
    }

    /// Sets [`LoadOptions::variant`] (`--variant NAME`).
    #[must_use]
    pub fn variant(mut self, variant: Option<String>) -> Self {
        self.variant = variant;
        self
    }

    /// Sets [`LoadOptions::lenient`] (`--lenient`).
    #[must_use]
    pub fn lenient(mut self, lenient: bool) -> Self {
        self.lenient = lenient;
        self
    }

    /// Sets the image [`LoadOptions::limits`].
    #[must_use]
    pub fn limits(mut self, limits: Limits) -> Self {
        self.limits = limits;
        self
    }

    /// Sets [`LoadOptions::max_buffer_bytes`].
    #[must_use]
    pub fn max_buffer_bytes(mut self, bytes: u64) -> Self {
        self.max_buffer_bytes = bytes;
        self
    }

    /// One memory budget for everything a load holds at once (`--max-memory`): the largest
    /// file or buffer, decoded image and loaded volume.
    #[must_use]
    pub fn max_memory(mut self, bytes: u64) -> Self {
        self.max_buffer_bytes = bytes;
        self.limits.max_bytes = bytes;
        self.max_volume_bytes = bytes;
        self
    }

    /// How the volumes this load reads are read: the same folder rule, the volume budget.
    #[must_use]
    pub fn volume_options(&self) -> crate::volume::VolumeOptions {
        crate::volume::VolumeOptions::default()
            .allow_outside_paths(self.allow_outside_paths)
            .max_bytes(self.max_volume_bytes)
    }

    /// Sets [`LoadOptions::texture_storage`] (`--texture-storage`).
    #[must_use]
    pub fn texture_storage(mut self, storage: Storage) -> Self {
        self.texture_storage = storage;
        self
    }

    /// Sets [`LoadOptions::environment_image`].
    #[must_use]
    pub fn environment_image(mut self, read: bool) -> Self {
        self.environment_image = read;
        self
    }
}

/// A texture as `texmap info` lists it.
#[derive(Clone, Debug)]
pub struct TextureInfo {
    /// File name, or a description of where embedded data came from.
    pub name: String,
    pub width: u32,
    pub height: u32,
    pub format: Format,
    pub color_space: ColorSpace,
    /// How its texels are held, and their bytes (every level).
    pub storage: Storage,
    pub bytes: usize,
    /// The block format it is held in, for a block-compressed file kept compressed.
    pub block_format: Option<crate::texture::compressed::BlockFormat>,
    /// True for the magenta placeholder that stands for a missing texture (`--lenient`).
    pub placeholder: bool,
}

/// What a loaded file holds, beyond the renderable [`Scene`]: names and sources for `info`.
#[derive(Clone, Debug, Default)]
pub struct AssetInfo {
    /// "glTF", "OBJ", "TOML scene".
    pub format: String,
    /// One name per `Scene::meshes` entry.
    pub mesh_names: Vec<String>,
    /// One name per `Scene::materials` entry.
    pub material_names: Vec<String>,
    /// Every texture loaded, once each.
    pub textures: Vec<TextureInfo>,
    /// One name (the file) per [`Loaded::volumes`] entry.
    pub volumes: Vec<String>,
    /// True when the file defines no light and the loader added the peers' directional
    /// light (volumes then shade with a headlight instead).
    pub default_light: bool,
    /// glTF `KHR_materials_variants`: the variant names the file defines, in order.
    pub variants: Vec<String>,
    /// The variant the scene was loaded with, if any.
    pub variant: Option<String>,
}

/// A loaded scene file.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// What to render; `scene.camera` is the file's first camera, if any.
    pub scene: Scene,
    /// Every camera the file defines, in file order.
    pub cameras: Vec<Camera>,
    pub info: AssetInfo,
    /// Volumes placed in the scene (TOML `[[volumes]]`), with their transfer functions and
    /// rendering options; drawn by [`crate::render::render_with_volumes`].
    pub volumes: Vec<crate::volume::SceneVolume>,
    /// Problems that did not stop loading (unsupported optional extensions, skipped
    /// primitives, placeholders), one line each, for stderr.
    pub warnings: Vec<String>,
}
