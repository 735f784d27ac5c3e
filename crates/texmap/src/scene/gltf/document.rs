//! One glTF document → [`Loaded`]: the JSON (or GLB) is parsed by the `gltf` crate without
//! validation, extensions are checked (a required one texmap does not read is an error, an
//! optional one a warning), then validated, its buffers read (`buffers`), and the
//! [`Loader`] builds materials, then the node hierarchy's meshes, cameras and lights.

use std::path::Path;

use glam::{Mat4, Vec3, Vec4};
use gltf::{Document, Gltf};

use super::buffers::{read_buffers, Accessors};
use super::cameras::{finish_cameras, FileCamera};
use super::lights::{default_light, AMBIENT_LIGHT};
use crate::scene::asset::{AssetInfo, LoadOptions, Loaded};
use crate::scene::files::read_bounded;
use crate::scene::texture_cache::TextureCache;
use crate::scene::Scene;
use crate::{Error, Result};

/// Extensions texmap reads; a file that requires any other is refused.
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_texture_transform",
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_unlit",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_variants",
    "KHR_materials_specular",
    "KHR_materials_clearcoat",
    "KHR_materials_sheen",
    "KHR_materials_volume",
    "KHR_mesh_quantization",
    "MSFT_texture_dds",
    "KHR_texture_basisu",
];

/// Loads a `.gltf` or `.glb` file.
///
/// # Errors
/// An [`Error`] naming the file (the glTF file or a buffer or image it names) and the
/// problem, one line.
pub fn load(path: &Path, options: &LoadOptions) -> Result<Loaded> {
    let bytes = read_bounded(path, options.max_buffer_bytes)?;
    check_glb_header(&bytes).map_err(|m| Error::decode(path, m))?;
    let Gltf { document, blob } = Gltf::from_slice_without_validation(&bytes)
        .map_err(|e| Error::decode(path, gltf_message(&e)))?;
    drop(bytes);
    let mut warnings = Vec::new();
    let mut root = document.into_json();
    for ext in &root.extensions_required {
        if !SUPPORTED_EXTENSIONS.contains(&ext.as_str()) {
            return Err(Error::Unsupported(format!(
                "{}: requires the extension {ext}, which texmap does not support",
                path.display()
            )));
        }
    }
    for ext in &root.extensions_used {
        if !SUPPORTED_EXTENSIONS.contains(&ext.as_str()) {
            warnings.push(format!(
                "{}: uses the optional extension {ext}, which texmap ignores",
                path.display()
            ));
        }
    }
    // Validation refuses required extensions the gltf crate does not know; we checked them.
    root.extensions_required
        .retain(|e| gltf::json::extensions::ENABLED_EXTENSIONS.contains(&e.as_str()));
    precheck(&root).map_err(|m| Error::decode(path, m))?;
    let document = Document::from_json(root).map_err(|e| Error::decode(path, gltf_message(&e)))?;
    let variant_names = super::variants::names(&document);
    let variant = options
        .variant
        .as_deref()
        .map(|name| super::variants::resolve(path, &variant_names, name))
        .transpose()?;
    let buffers = read_buffers(path, &document, blob, options)?;
    let mut loader = Loader {
        path,
        doc: &document,
        acc: Accessors {
            path,
            buffers: &buffers,
            max_bytes: options.max_buffer_bytes,
        },
        textures: TextureCache::new(options),
        options,
        warnings,
        scene: Scene {
            ambient_light: Vec3::splat(AMBIENT_LIGHT),
            background: Vec4::new(0.0, 0.0, 0.0, 1.0),
            ..Default::default()
        },
        info: AssetInfo {
            format: "glTF 2.0".into(),
            variants: variant_names,
            variant: options.variant.clone().filter(|_| variant.is_some()),
            ..Default::default()
        },
        variant,
        cameras: Vec::new(),
        node_world: Vec::new(),
        visits: 0,
    };
    loader.prefetch_images();
    loader.load_materials()?;
    loader.node_world = loader.node_world_matrices()?;
    loader.load_nodes()?;
    Ok(loader.finish())
}

fn gltf_message(e: &gltf::Error) -> String {
    match e {
        gltf::Error::Validation(errors) => {
            let first: Vec<String> = errors
                .iter()
                .take(3)
                .map(|(p, e)| format!("{p}: {e}"))
                .collect();
            format!("invalid glTF: {}", first.join("; "))
        }
        gltf::Error::Binary(gltf::binary::Error::Length {
            length,
            length_read,
        }) => format!(
            "truncated GLB: the header announces {length} bytes, only {length_read} could be read"
        ),
        gltf::Error::Binary(b) => format!("invalid GLB: {b}"),
        gltf::Error::Deserialize(d) => format!("invalid glTF JSON: {d}"),
        other => format!("invalid glTF: {other}"),
    }
}

/// The state of one glTF load: the document and its buffers, what has been built so far,
/// and the texture cache. Each stage of the load is a method in the file of its purpose.
pub(super) struct Loader<'a> {
    pub(super) path: &'a Path,
    pub(super) doc: &'a Document,
    pub(super) acc: Accessors<'a>,
    pub(super) textures: TextureCache,
    pub(super) options: &'a LoadOptions,
    pub(super) warnings: Vec<String>,
    pub(super) scene: Scene,
    pub(super) info: AssetInfo,
    pub(super) cameras: Vec<FileCamera>,
    /// World matrices of every node, by index (skins read their joints' from here).
    pub(super) node_world: Vec<Mat4>,
    /// Nodes visited so far (bounded: see `nodes`).
    pub(super) visits: usize,
    /// The chosen material variant's index (`variants`).
    pub(super) variant: Option<usize>,
}

impl Loader<'_> {
    /// The default light when the file has none, far planes for cameras without one, and
    /// the texture cache's records: the [`Loaded`] result.
    fn finish(mut self) -> Loaded {
        if self.scene.lights.is_empty() {
            self.info.default_light = true;
            self.scene.lights.push(default_light());
        }
        let cameras = finish_cameras(&self.cameras, &self.scene);
        self.scene.camera = cameras.first().copied();
        self.warnings.append(&mut self.textures.warnings);
        self.info.textures = std::mem::take(&mut self.textures.infos);
        Loaded {
            scene: self.scene,
            cameras,
            info: self.info,
            volumes: Vec::new(),
            warnings: self.warnings,
        }
    }
}

/// What the gltf crate assumes and would panic on instead of reporting: checked here, on the
/// JSON, before it is validated or read. A primitive's accessors must exist (validation
/// indexes `POSITION`'s unchecked); an image needs a `uri`, or a `bufferView` with a
/// `mimeType`; a camera's `type` needs its own object.
/// A binary glTF's 12-byte header must count itself: the gltf crate subtracts 12 from the
/// declared length unchecked (a panic in debug builds, a wrapped length otherwise).
fn check_glb_header(bytes: &[u8]) -> std::result::Result<(), String> {
    if bytes.len() < 12 || &bytes[..4] != b"glTF" {
        return Ok(()); // JSON, or too short for the crate to read a header: it says so.
    }
    let length = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]);
    if length < 12 {
        return Err(format!(
            "the GLB header declares a length of {length} bytes, less than the header itself"
        ));
    }
    Ok(())
}

fn precheck(root: &gltf::json::Root) -> std::result::Result<(), String> {
    use gltf::json::camera::Type;
    use gltf::json::validation::Checked;
    let accessors = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let targets = prim
                .targets
                .iter()
                .flatten()
                .flat_map(|t| [t.positions, t.normals, t.tangents].into_iter().flatten());
            let bad = prim
                .attributes
                .values()
                .copied()
                .chain(prim.indices)
                .chain(targets)
                .find(|a| a.value() >= accessors);
            if let Some(a) = bad {
                return Err(format!(
                    "meshes[{m}].primitives[{p}] uses accessor {} but the file has {accessors}",
                    a.value()
                ));
            }
        }
    }
    for (i, img) in root.images.iter().enumerate() {
        match (&img.uri, img.buffer_view, &img.mime_type) {
            (Some(_), _, _) | (None, Some(_), Some(_)) => {}
            (None, Some(_), None) => {
                return Err(format!(
                    "images[{i}] has a bufferView but no mimeType (the glTF specification requires one)"
                ))
            }
            (None, None, _) => return Err(format!("images[{i}] has neither a uri nor a bufferView")),
        }
    }
    for (i, cam) in root.cameras.iter().enumerate() {
        let ok = match cam.type_ {
            Checked::Valid(Type::Perspective) => cam.perspective.is_some(),
            Checked::Valid(Type::Orthographic) => cam.orthographic.is_some(),
            Checked::Invalid => true,
        };
        if !ok {
            return Err(format!(
                "cameras[{i}]: its type has no matching perspective or orthographic object"
            ));
        }
    }
    Ok(())
}
