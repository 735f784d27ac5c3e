//! glTF 2.0 (`.gltf` with external or data-URI buffers and images, `.glb`).
//!
//! The JSON is parsed by the `gltf` crate without its importer: buffers and images are read
//! here, so the folder rule, size bounds and texmap's own image decoder (limits, colour
//! spaces) apply. Accessors are read by [`Accessors`], bounds-checked, in any component type
//! (`normalized`, `byteStride`, sparse, no bufferView = zeros), so `KHR_mesh_quantization` is
//! supported too.
//!
//! Conventions match `gl_render.py`'s glTF path (see `../shared/peers/README.md`): the default
//! scene (else scene 0, else every root node), nodes depth-first in document order, strips and
//! fans converted to lists, skins posed in the rest pose with the joints' node transforms,
//! morph targets at their default weights, base colour = factor × texture × COLOR_0, base
//! colour and emissive textures sRGB and the others linear, samplers straight to our GL
//! filters and wraps (undefined = trilinear, repeat), `KHR_texture_transform` as
//! [`TextureTransform`].
//!
//! Lighting: glTF has no ambient light, and its models are shown in image-based light, which
//! texmap does not have; a uniform environment stands in for it. `I_AL` is 1.5, so with
//! every loader's K_A = 0.2 the environment is 0.3: enough for metals, which reflect nothing
//! else but their highlights, to show their colour, little enough for the light to model
//! the shapes. Without lights in the file, the peer's direction (0.3, 0.8, 0.5) is used with
//! colour 0.7, so a rough white dielectric facing it reflects 0.3 + 0.7·(1 − F) ≈ 0.97, as
//! the peer's 0.2 + 0.8 reaches 1 (chosen by eye against the models' screenshots among
//! environment/light splits 0.2/1, 0.3/0.7, 0.5/0.5 and 0.8/0.5).
//!
//! Materials use the metallic-roughness model (`ShadingModel::MetallicRoughness`) unless
//! `KHR_materials_unlit`; the default material (for primitives without one) is glTF's:
//! white, metallic 1, roughness 1. `KHR_lights_punctual` intensities (lux for directional
//! lights, candela for point and spot lights) are divided by π: texmap's light units are
//! those of the Phong model (see `shading::pbr`), so a file's lights give the image the
//! glTF sample viewer gives without exposure or tone mapping.

use std::path::Path;
use std::sync::Arc;

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;
use gltf::{Document, Gltf, Semantic};

use super::asset::{AssetInfo, LoadOptions, Loaded};
use super::files::{decode_data_uri, percent_decode, read_bounded, resolve_reference};
use super::texture_cache::{ImageSource, TextureCache};
use super::{
    tangents, AlphaMode, Camera, CameraProjection, Light, Material, Mesh, Scene, ShadingModel,
    TextureSlot,
};
use crate::shading::{MapChannel, MaterialMap};
use crate::texture::{Filter, MagFilter, MinFilter, Sampler, Texture2D, TextureTransform, Wrap};
use crate::{Error, Result};

/// Extensions texmap reads; a file that requires any other is refused.
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_texture_transform",
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_unlit",
    "KHR_mesh_quantization",
];

/// The largest node depth followed (a guard against cycles in a malformed file).
const MAX_NODE_DEPTH: usize = 256;
/// The most node visits (a DAG can make a small file describe a huge scene).
const MAX_NODE_VISITS: usize = 1 << 20;

/// Loads a `.gltf` or `.glb` file.
pub fn load(path: &Path, options: &LoadOptions) -> Result<Loaded> {
    let bytes = read_bounded(path, options.max_buffer_bytes)?;
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
    let document = Document::from_json(root).map_err(|e| Error::decode(path, gltf_message(&e)))?;
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
        allow_outside: options.allow_outside_paths,
        max_bytes: options.max_buffer_bytes,
        warnings,
        scene: Scene {
            ambient_light: Vec3::splat(AMBIENT_LIGHT),
            background: Vec4::new(0.0, 0.0, 0.0, 1.0),
            ..Default::default()
        },
        info: AssetInfo {
            format: "glTF 2.0".into(),
            ..Default::default()
        },
        cameras: Vec::new(),
        node_world: Vec::new(),
        visits: 0,
    };
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

fn read_buffers(
    path: &Path,
    doc: &Document,
    mut blob: Option<Vec<u8>>,
    options: &LoadOptions,
) -> Result<Vec<Vec<u8>>> {
    let mut out = Vec::new();
    let mut total = 0u64;
    for b in doc.buffers() {
        let data = match b.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                Error::decode(
                    path,
                    format!(
                        "buffer {} refers to the GLB binary chunk, which is missing",
                        b.index()
                    ),
                )
            })?,
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                decode_data_uri(path, uri, options.max_buffer_bytes)?.1
            }
            gltf::buffer::Source::Uri(uri) => {
                let p = resolve_reference(path, &percent_decode(uri), options.allow_outside_paths)?;
                read_bounded(&p, options.max_buffer_bytes)?
            }
        };
        if data.len() < b.length() {
            return Err(Error::decode(
                path,
                format!(
                    "buffer {} holds {} bytes, fewer than its byteLength {} (truncated?)",
                    b.index(),
                    data.len(),
                    b.length()
                ),
            ));
        }
        total += data.len() as u64;
        if total > options.max_buffer_bytes {
            return Err(Error::limits(
                path,
                format!(
                    "buffers exceed the limit of {} bytes",
                    options.max_buffer_bytes
                ),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// Bounds-checked accessor reads.
struct Accessors<'a> {
    path: &'a Path,
    buffers: &'a [Vec<u8>],
    max_bytes: u64,
}

fn component(b: &[u8], ty: DataType, normalized: bool) -> f64 {
    match ty {
        DataType::I8 => {
            let v = f64::from(b[0] as i8);
            if normalized {
                (v / 127.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U8 => {
            let v = f64::from(b[0]);
            if normalized {
                v / 255.0
            } else {
                v
            }
        }
        DataType::I16 => {
            let v = f64::from(i16::from_le_bytes([b[0], b[1]]));
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U16 => {
            let v = f64::from(u16::from_le_bytes([b[0], b[1]]));
            if normalized {
                v / 65535.0
            } else {
                v
            }
        }
        DataType::U32 => {
            let v = f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
            if normalized {
                v / f64::from(u32::MAX)
            } else {
                v
            }
        }
        DataType::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
    }
}

impl Accessors<'_> {
    fn err(&self, msg: String) -> Error {
        Error::decode(self.path, msg)
    }

    /// The bytes of a buffer view.
    fn view_bytes(&self, view: &gltf::buffer::View) -> Result<&[u8]> {
        let buf = &self.buffers[view.buffer().index()];
        view.offset()
            .checked_add(view.length())
            .filter(|&end| end <= buf.len())
            .map(|end| &buf[view.offset()..end])
            .ok_or_else(|| {
                self.err(format!(
                    "bufferView {} reaches past the end of buffer {}",
                    view.index(),
                    view.buffer().index()
                ))
            })
    }

    /// Every component of `acc` as f64 (`count × components`), and the component count.
    fn read(&self, acc: &gltf::Accessor) -> Result<(Vec<f64>, usize)> {
        let n = acc.dimensions().multiplicity();
        let count = acc.count();
        let ty = acc.data_type();
        let csize = ty.size();
        let elem = n * csize;
        let norm = acc.normalized();
        let total = (count as u64).saturating_mul(n as u64);
        if total.saturating_mul(8) > self.max_bytes {
            return Err(Error::limits(
                self.path,
                format!(
                    "accessor {} has {count} elements, above the size limit",
                    acc.index()
                ),
            ));
        }
        if matches!(acc.dimensions(), Dimensions::Mat2 | Dimensions::Mat3) && csize < 4 {
            return Err(Error::Unsupported(format!(
                "{}: accessor {}: padded small-component matrices are not read",
                self.path.display(),
                acc.index()
            )));
        }
        let mut out = vec![0.0f64; count * n];
        if let Some(view) = acc.view() {
            let data = self.view_bytes(&view)?;
            let stride = view.stride().unwrap_or(elem);
            if stride < elem {
                return Err(self.err(format!(
                    "bufferView {} has byteStride {stride}, smaller than accessor {}'s element",
                    view.index(),
                    acc.index()
                )));
            }
            if count > 0 {
                let end = (stride as u64)
                    .checked_mul(count as u64 - 1)
                    .and_then(|v| v.checked_add((acc.offset() + elem) as u64));
                if end.is_none_or(|e| e > data.len() as u64) {
                    return Err(self.err(format!(
                        "accessor {} reaches past the end of bufferView {}",
                        acc.index(),
                        view.index()
                    )));
                }
            }
            for e in 0..count {
                let base = acc.offset() + e * stride;
                for c in 0..n {
                    out[e * n + c] = component(&data[base + c * csize..], ty, norm);
                }
            }
        }
        if let Some(sparse) = acc.sparse() {
            let k = sparse.count();
            let idx = sparse.indices();
            let isize = idx.index_type().size();
            let ibytes = self.view_bytes(&idx.view())?;
            let vbytes = self.view_bytes(&sparse.values().view())?;
            let ioff = idx.offset();
            let voff = sparse.values().offset();
            if ioff + k * isize > ibytes.len() || voff + k * elem > vbytes.len() {
                return Err(self.err(format!(
                    "sparse accessor {} reaches past the end of its bufferViews",
                    acc.index()
                )));
            }
            for s in 0..k {
                let b = &ibytes[ioff + s * isize..];
                let i = match isize {
                    1 => b[0] as usize,
                    2 => u16::from_le_bytes([b[0], b[1]]) as usize,
                    _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize,
                };
                if i >= count {
                    return Err(self.err(format!(
                        "sparse accessor {} writes element {i} of {count}",
                        acc.index()
                    )));
                }
                for c in 0..n {
                    out[i * n + c] = component(&vbytes[voff + s * elem + c * csize..], ty, norm);
                }
            }
        }
        Ok((out, n))
    }

    fn read_vec<const N: usize>(&self, acc: &gltf::Accessor, what: &str) -> Result<Vec<[f32; N]>> {
        let (v, n) = self.read(acc)?;
        if n < N {
            return Err(self.err(format!(
                "accessor {} ({what}) has {n} components, expected {N}",
                acc.index()
            )));
        }
        Ok(v.chunks_exact(n)
            .map(|c| std::array::from_fn(|i| c[i] as f32))
            .collect())
    }
}

struct Loader<'a> {
    path: &'a Path,
    doc: &'a Document,
    acc: Accessors<'a>,
    textures: TextureCache,
    allow_outside: bool,
    max_bytes: u64,
    warnings: Vec<String>,
    scene: Scene,
    info: AssetInfo,
    cameras: Vec<(Camera, Option<f32>)>,
    node_world: Vec<Mat4>,
    visits: usize,
}

/// `I_AL` of glTF scenes (module docs).
const AMBIENT_LIGHT: f32 = 1.5;

/// The colour of the default directional light of glTF scenes without lights.
const DEFAULT_SUN: f32 = 0.7;

fn mat4(m: [[f32; 4]; 4]) -> Mat4 {
    Mat4::from_cols_array_2d(&m)
}

impl Loader<'_> {
    fn finish(mut self) -> Loaded {
        if self.scene.lights.is_empty() {
            self.info.default_light = true;
            self.scene.lights.push(Light::Directional {
                direction: Vec3::new(0.3, 0.8, 0.5).normalize(),
                color: Vec3::splat(DEFAULT_SUN),
            });
        }
        // Cameras without a far plane: enclose the scene.
        let (lo, hi) = self.scene.bounds();
        let (c, r) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
        let cameras: Vec<Camera> = self
            .cameras
            .iter()
            .map(|(cam, zfar)| {
                let far =
                    zfar.unwrap_or_else(|| (cam.eye.distance(c) + 2.0 * r).max(cam.near * 1e3));
                Camera {
                    far: far.max(cam.near * 1.0001),
                    ..*cam
                }
            })
            .collect();
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

    fn load_materials(&mut self) -> Result<()> {
        let doc = self.doc;
        for m in doc.materials() {
            let mat = self.material(&m)?;
            self.scene.materials.push(mat);
            self.info.material_names.push(
                m.name()
                    .map(str::to_string)
                    .unwrap_or_else(|| format!("material {}", m.index().unwrap_or(0))),
            );
        }
        // glTF's default material, for primitives without one: every property at its default.
        self.scene.materials.push(Material {
            model: ShadingModel::MetallicRoughness,
            metallic: 1.0,
            roughness: 1.0,
            ..Default::default()
        });
        self.info.material_names.push("(default)".into());
        Ok(())
    }

    fn material(&mut self, m: &gltf::Material) -> Result<Material> {
        let pbr = m.pbr_metallic_roughness();
        let mut mat = Material {
            base_color: Vec4::from(pbr.base_color_factor()),
            metallic: pbr.metallic_factor(),
            roughness: pbr.roughness_factor(),
            double_sided: m.double_sided(),
            unlit: m.unlit(),
            model: if m.unlit() {
                ShadingModel::Phong
            } else {
                ShadingModel::MetallicRoughness
            },
            alpha_mode: match m.alpha_mode() {
                gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
                gltf::material::AlphaMode::Mask => AlphaMode::Mask(m.alpha_cutoff().unwrap_or(0.5)),
                gltf::material::AlphaMode::Blend => AlphaMode::Blend,
            },
            emissive: Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0),
            ..Default::default()
        };
        if let Some(info) = pbr.base_color_texture() {
            mat.base_color_texture = self.slot(
                &info.texture(),
                info.tex_coord(),
                info.texture_transform(),
                true,
                mat.alpha_mode == AlphaMode::Opaque,
            )?;
        }
        if let Some(info) = pbr.metallic_roughness_texture() {
            self.push_map(
                &mut mat,
                MapChannel::MetallicRoughness,
                &info.texture(),
                info.tex_coord(),
                info.texture_transform(),
                1.0,
            )?;
        }
        if let Some(n) = m.normal_texture() {
            self.push_map(
                &mut mat,
                MapChannel::Normal,
                &n.texture(),
                n.tex_coord(),
                None,
                n.scale(),
            )?;
            // The crate exposes KHR_texture_transform on `textureInfo` only; normal and
            // occlusion textures carry it too, read from their raw extension object.
            apply_raw_transform(&mut mat, MapChannel::Normal, n.extension_value(TRANSFORM));
        }
        if let Some(o) = m.occlusion_texture() {
            self.push_map(
                &mut mat,
                MapChannel::Occlusion,
                &o.texture(),
                o.tex_coord(),
                None,
                o.strength(),
            )?;
            apply_raw_transform(
                &mut mat,
                MapChannel::Occlusion,
                o.extension_value(TRANSFORM),
            );
        }
        if let Some(info) = m.emissive_texture() {
            self.push_map(
                &mut mat,
                MapChannel::Emissive,
                &info.texture(),
                info.tex_coord(),
                info.texture_transform(),
                1.0,
            )?;
        }
        Ok(mat)
    }

    fn push_map(
        &mut self,
        mat: &mut Material,
        channel: MapChannel,
        tex: &gltf::Texture,
        tex_coord: u32,
        transform: Option<gltf::texture::TextureTransform>,
        scale: f32,
    ) -> Result<()> {
        if let Some(slot) = self.slot(tex, tex_coord, transform, channel.is_color(), false)? {
            mat.maps.push(MaterialMap {
                channel,
                slot,
                scale,
            });
        }
        Ok(())
    }

    fn slot(
        &mut self,
        tex: &gltf::Texture,
        tex_coord: u32,
        transform: Option<gltf::texture::TextureTransform>,
        srgb: bool,
        opaque: bool,
    ) -> Result<Option<TextureSlot>> {
        let Some(texture) = self.image(&tex.source(), srgb, opaque)? else {
            return Ok(None);
        };
        let mut slot = TextureSlot::new(texture, sampler(&tex.sampler()));
        slot.tex_coord = tex_coord;
        if let Some(t) = transform {
            slot.transform = TextureTransform {
                offset: Vec2::from(t.offset()),
                rotation: t.rotation(),
                scale: Vec2::from(t.scale()),
            };
            if let Some(tc) = t.tex_coord() {
                slot.tex_coord = tc;
            }
        }
        if slot.tex_coord > 1 {
            self.warnings.push(format!(
                "{}: texture {} reads TEXCOORD_{}; texmap reads sets 0 and 1 only (uv = 0)",
                self.path.display(),
                tex.index(),
                slot.tex_coord
            ));
        }
        Ok(Some(slot))
    }

    fn image(
        &mut self,
        img: &gltf::Image,
        srgb: bool,
        opaque: bool,
    ) -> Result<Option<Arc<Texture2D>>> {
        let key = format!("image{}", img.index());
        let unsupported = |mime: Option<&str>| {
            matches!(mime, Some("image/ktx2" | "image/webp" | "image/vnd-ms.dds"))
        };
        match img.source() {
            gltf::image::Source::View { view, mime_type } => {
                let name = format!(
                    "{} (image {}, {mime_type})",
                    self.path.display(),
                    img.index()
                );
                if unsupported(Some(mime_type)) {
                    return self.skip_image(name);
                }
                let bytes = self.acc.view_bytes(&view)?;
                self.textures
                    .get(&key, ImageSource::Bytes { name, bytes }, srgb, opaque)
            }
            gltf::image::Source::Uri { uri, mime_type } if uri.starts_with("data:") => {
                let (mime, bytes) = decode_data_uri(self.path, uri, self.max_bytes)?;
                let name = format!("{} (image {}, data URI)", self.path.display(), img.index());
                if unsupported(mime.as_deref().or(mime_type)) {
                    return self.skip_image(name);
                }
                self.textures.get(
                    &key,
                    ImageSource::Bytes {
                        name,
                        bytes: &bytes,
                    },
                    srgb,
                    opaque,
                )
            }
            gltf::image::Source::Uri { uri, mime_type } => {
                let p = resolve_reference(self.path, &percent_decode(uri), self.allow_outside)?;
                if unsupported(mime_type) {
                    return self.skip_image(p.display().to_string());
                }
                self.textures.get(&key, ImageSource::File(p), srgb, opaque)
            }
        }
    }

    fn skip_image(&mut self, name: String) -> Result<Option<Arc<Texture2D>>> {
        self.warnings.push(format!(
            "{name}: image format not decoded by texmap; the texture is left out"
        ));
        Ok(None)
    }

    /// World matrices of every node (parents found over the whole document).
    fn node_world_matrices(&self) -> Result<Vec<Mat4>> {
        let n = self.doc.nodes().len();
        let mut parent = vec![usize::MAX; n];
        for node in self.doc.nodes() {
            for c in node.children() {
                parent[c.index()] = node.index();
            }
        }
        let local: Vec<Mat4> = self
            .doc
            .nodes()
            .map(|n| mat4(n.transform().matrix()))
            .collect();
        let mut world = vec![Mat4::IDENTITY; n];
        for i in 0..n {
            let mut m = local[i];
            let mut p = parent[i];
            let mut depth = 0;
            while p != usize::MAX {
                m = local[p] * m;
                p = parent[p];
                depth += 1;
                if depth > MAX_NODE_DEPTH {
                    return Err(Error::decode(
                        self.path,
                        "the node hierarchy is deeper than 256 levels or has a cycle",
                    ));
                }
            }
            world[i] = m;
        }
        Ok(world)
    }

    fn load_nodes(&mut self) -> Result<()> {
        let doc = self.doc;
        let roots: Vec<gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
            Some(s) => s.nodes().collect(),
            None => {
                let mut is_child = vec![false; doc.nodes().len()];
                for node in doc.nodes() {
                    for c in node.children() {
                        is_child[c.index()] = true;
                    }
                }
                doc.nodes().filter(|n| !is_child[n.index()]).collect()
            }
        };
        for node in roots {
            self.visit(&node, Mat4::IDENTITY, 0)?;
        }
        Ok(())
    }

    fn visit(&mut self, node: &gltf::Node, parent: Mat4, depth: usize) -> Result<()> {
        self.visits += 1;
        if depth > MAX_NODE_DEPTH || self.visits > MAX_NODE_VISITS {
            return Err(Error::decode(
                self.path,
                "the node hierarchy is too deep or too large (a cycle?)",
            ));
        }
        let world = parent * mat4(node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            let weights = node
                .weights()
                .or_else(|| mesh.weights())
                .unwrap_or(&[])
                .to_vec();
            for prim in mesh.primitives() {
                let name = format!(
                    "{}/{}",
                    mesh.name()
                        .map(str::to_string)
                        .unwrap_or_else(|| format!("mesh {}", mesh.index())),
                    prim.index()
                );
                if let Some(m) = self.primitive(node, &prim, world, &weights, &name)? {
                    self.scene.meshes.push(m);
                    self.info.mesh_names.push(name);
                }
            }
        }
        if let Some(cam) = node.camera() {
            let eye = world.transform_point3(Vec3::ZERO);
            let fwd = world.transform_vector3(-Vec3::Z).normalize_or(-Vec3::Z);
            let up = world.transform_vector3(Vec3::Y).normalize_or(Vec3::Y);
            // The image's aspect sets the horizontal extent (yfov / ymag are kept, a file's
            // aspectRatio / xmag are not), so nothing is stretched.
            let (projection, near, zfar) = match cam.projection() {
                gltf::camera::Projection::Perspective(p) => (
                    CameraProjection::Perspective {
                        fov_y_deg: p.yfov().to_degrees(),
                    },
                    p.znear(),
                    p.zfar(),
                ),
                gltf::camera::Projection::Orthographic(o) => (
                    CameraProjection::Orthographic {
                        half_height: o.ymag().abs(),
                    },
                    o.znear(),
                    Some(o.zfar()),
                ),
            };
            self.cameras.push((
                Camera {
                    eye,
                    target: eye + fwd,
                    up,
                    projection,
                    near,
                    far: zfar.unwrap_or(f32::INFINITY),
                },
                zfar,
            ));
        }
        if let Some(light) = node.light() {
            // Lux and candela to texmap's units (module docs).
            let color = Vec3::from(light.color()) * (light.intensity() / std::f32::consts::PI);
            let position = world.transform_point3(Vec3::ZERO);
            let dir = world.transform_vector3(-Vec3::Z).normalize_or(-Vec3::Z);
            self.scene.lights.push(match light.kind() {
                gltf::khr_lights_punctual::Kind::Directional => Light::Directional {
                    direction: -dir,
                    color,
                },
                gltf::khr_lights_punctual::Kind::Point => Light::Point {
                    position,
                    color,
                    range: light.range(),
                },
                gltf::khr_lights_punctual::Kind::Spot {
                    inner_cone_angle,
                    outer_cone_angle,
                } => Light::Spot {
                    position,
                    direction: dir,
                    color,
                    inner_deg: inner_cone_angle.to_degrees(),
                    outer_deg: outer_cone_angle.to_degrees(),
                },
            });
        }
        for child in node.children() {
            self.visit(&child, world, depth + 1)?;
        }
        Ok(())
    }

    fn primitive(
        &mut self,
        node: &gltf::Node,
        prim: &gltf::Primitive,
        world: Mat4,
        weights: &[f32],
        name: &str,
    ) -> Result<Option<Mesh>> {
        let skip = |this: &mut Self, why: &str| {
            this.warnings.push(format!(
                "{}: primitive {name} skipped: {why}",
                this.path.display()
            ));
            Ok(None)
        };
        let mode = prim.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            return skip(self, "points and lines are not drawn");
        }
        let Some(pos_acc) = prim.get(&Semantic::Positions) else {
            return skip(self, "it has no POSITION");
        };
        let mut positions: Vec<Vec3> = self
            .acc
            .read_vec::<3>(&pos_acc, "POSITION")?
            .into_iter()
            .map(Vec3::from)
            .collect();
        let nv = positions.len();
        let attr = |this: &Self, sem: Semantic, what: &str| -> Result<Option<(Vec<f64>, usize)>> {
            let Some(a) = prim.get(&sem) else {
                return Ok(None);
            };
            let (v, n) = this.acc.read(&a)?;
            if a.count() != nv {
                return Err(Error::decode(
                    this.path,
                    format!(
                        "primitive {name}: {what} has {} elements but POSITION has {nv}",
                        a.count()
                    ),
                ));
            }
            Ok(Some((v, n)))
        };
        let vec3s = |v: (Vec<f64>, usize)| -> Vec<Vec3> {
            v.0.chunks_exact(v.1.max(1))
                .map(|c| {
                    Vec3::new(
                        c[0] as f32,
                        c.get(1).copied().unwrap_or(0.0) as f32,
                        c.get(2).copied().unwrap_or(0.0) as f32,
                    )
                })
                .collect()
        };
        let vec2s = |v: (Vec<f64>, usize)| -> Vec<Vec2> {
            v.0.chunks_exact(v.1.max(1))
                .map(|c| Vec2::new(c[0] as f32, c.get(1).copied().unwrap_or(0.0) as f32))
                .collect()
        };
        let mut normals = attr(self, Semantic::Normals, "NORMAL")?
            .map(vec3s)
            .unwrap_or_default();
        let uvs = attr(self, Semantic::TexCoords(0), "TEXCOORD_0")?
            .map(vec2s)
            .unwrap_or_default();
        let uvs1 = attr(self, Semantic::TexCoords(1), "TEXCOORD_1")?
            .map(vec2s)
            .unwrap_or_default();
        // VEC3 or VEC4; a missing fourth component is 1 (colour alpha, tangent handedness).
        let vec4s = |(v, n): (Vec<f64>, usize)| -> Vec<Vec4> {
            v.chunks_exact(n.max(1))
                .map(|c| {
                    let at = |i: usize, d: f64| c.get(i).copied().unwrap_or(d) as f32;
                    Vec4::new(
                        at(0, 0.0),
                        at(1, 0.0),
                        at(2, 0.0),
                        if n == 4 { at(3, 1.0) } else { 1.0 },
                    )
                })
                .collect()
        };
        let colors: Vec<Vec4> = attr(self, Semantic::Colors(0), "COLOR_0")?
            .map(vec4s)
            .unwrap_or_default();
        let mut tangents: Vec<Vec4> = attr(self, Semantic::Tangents, "TANGENT")?
            .map(vec4s)
            .unwrap_or_default();

        // Morph targets at their default weights.
        for (t, target) in prim.morph_targets().enumerate() {
            let w = weights.get(t).copied().unwrap_or(0.0);
            if w == 0.0 {
                continue;
            }
            if let Some(a) = target.positions() {
                let d = self.acc.read_vec::<3>(&a, "morph POSITION")?;
                for (p, d) in positions.iter_mut().zip(d) {
                    *p += w * Vec3::from(d);
                }
            }
            if let Some(a) = target.normals() {
                let d = self.acc.read_vec::<3>(&a, "morph NORMAL")?;
                for (n, d) in normals.iter_mut().zip(d) {
                    *n += w * Vec3::from(d);
                }
            }
        }

        // Skins in the rest pose: the mesh node's own transform is ignored.
        let mut world_from_object = world;
        if let Some(skin) = node.skin() {
            self.skin(
                &skin,
                prim,
                &mut positions,
                &mut normals,
                &mut tangents,
                name,
            )?;
            world_from_object = Mat4::IDENTITY;
        }

        let list: Vec<u32> = match prim.indices() {
            Some(a) => {
                let (v, _) = self.acc.read(&a)?;
                let mut out = Vec::with_capacity(v.len());
                for x in v {
                    if x >= nv as f64 {
                        return Err(Error::decode(
                            self.path,
                            format!("primitive {name}: index {x} is out of range ({nv} vertices)"),
                        ));
                    }
                    out.push(x as u32);
                }
                out
            }
            None => (0..nv as u32).collect(),
        };
        let indices = to_triangle_list(mode, &list);
        for n in &mut normals {
            *n = n.normalize_or_zero();
        }
        let material = prim
            .material()
            .index()
            .unwrap_or(self.scene.materials.len() - 1);
        let mut mesh = Mesh {
            positions,
            normals,
            uvs,
            uvs1,
            colors,
            tangents,
            indices,
            material,
            world_from_object,
        };
        if mesh.tangents.is_empty() {
            if let Some(map) = self.scene.materials[material].map(MapChannel::Normal) {
                let set = map.slot.tex_coord;
                if !tangents::generate(&mut mesh, set) {
                    self.warnings.push(format!(
                        "{}: primitive {name}: tangents could not be generated (no normals or uvs)",
                        self.path.display()
                    ));
                }
            }
        }
        Ok(Some(mesh))
    }

    fn skin(
        &mut self,
        skin: &gltf::Skin,
        prim: &gltf::Primitive,
        positions: &mut [Vec3],
        normals: &mut [Vec3],
        tangents: &mut [Vec4],
        name: &str,
    ) -> Result<()> {
        let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
        let ibm: Vec<Mat4> = match skin.inverse_bind_matrices() {
            Some(a) => {
                let (v, n) = self.acc.read(&a)?;
                if n != 16 || v.len() / 16 < joints.len() {
                    return Err(Error::decode(
                        self.path,
                        format!(
                            "skin {}: inverseBindMatrices has too few matrices",
                            skin.index()
                        ),
                    ));
                }
                v.chunks_exact(16)
                    .map(|c| Mat4::from_cols_array(&std::array::from_fn(|i| c[i] as f32)))
                    .collect()
            }
            None => vec![Mat4::IDENTITY; joints.len()],
        };
        let joint_mats: Vec<Mat4> = joints
            .iter()
            .zip(&ibm)
            .map(|(&j, &ib)| self.node_world[j] * ib)
            .collect();
        let nv = positions.len();
        let mut blended = vec![Mat4::ZERO; nv];
        let mut any = false;
        for set in 0..2 {
            let (Some(ja), Some(wa)) = (
                prim.get(&Semantic::Joints(set)),
                prim.get(&Semantic::Weights(set)),
            ) else {
                continue;
            };
            let (jv, jn) = self.acc.read(&ja)?;
            let (wv, wn) = self.acc.read(&wa)?;
            if ja.count() != nv || wa.count() != nv || jn != 4 || wn != 4 {
                return Err(Error::decode(
                    self.path,
                    format!("primitive {name}: JOINTS_{set}/WEIGHTS_{set} do not match POSITION"),
                ));
            }
            for v in 0..nv {
                for k in 0..4 {
                    let w = wv[v * 4 + k] as f32;
                    if w == 0.0 {
                        continue;
                    }
                    let j = jv[v * 4 + k] as usize;
                    let m = joint_mats.get(j).ok_or_else(|| {
                        Error::decode(
                            self.path,
                            format!("primitive {name}: joint {j} is out of range"),
                        )
                    })?;
                    blended[v] += *m * w;
                    any = true;
                }
            }
        }
        if !any {
            return Ok(());
        }
        for v in 0..nv {
            let m = blended[v];
            positions[v] = m.transform_point3(positions[v]);
            let m3 = Mat3::from_mat4(m);
            if let Some(n) = normals.get_mut(v) {
                let nm = if m3.determinant().abs() > f32::MIN_POSITIVE {
                    m3.inverse().transpose()
                } else {
                    m3
                };
                *n = nm * *n;
            }
            if let Some(t) = tangents.get_mut(v) {
                *t = (m3 * t.truncate()).normalize_or_zero().extend(t.w);
            }
        }
        Ok(())
    }
}

/// Converts a strip or fan index sequence to a triangle list (glTF's vertex orders).
fn to_triangle_list(mode: Mode, v: &[u32]) -> Vec<u32> {
    match mode {
        Mode::TriangleStrip => (0..v.len().saturating_sub(2))
            .flat_map(|i| {
                if i % 2 == 0 {
                    [v[i], v[i + 1], v[i + 2]]
                } else {
                    [v[i], v[i + 2], v[i + 1]]
                }
            })
            .collect(),
        Mode::TriangleFan => (1..v.len().saturating_sub(1))
            .flat_map(|i| [v[i], v[i + 1], v[0]])
            .collect(),
        _ => v[..v.len() / 3 * 3].to_vec(),
    }
}

/// glTF sampler → texmap sampler (undefined filters are trilinear, undefined wraps repeat).
fn sampler(s: &gltf::texture::Sampler) -> Sampler {
    use gltf::texture::{MagFilter as GM, MinFilter as Gm, WrappingMode as W};
    let mag = match s.mag_filter() {
        Some(GM::Nearest) => MagFilter::Nearest,
        _ => MagFilter::Linear,
    };
    let min = match s.min_filter() {
        Some(Gm::Nearest) => MinFilter::Nearest,
        Some(Gm::Linear) => MinFilter::Linear,
        Some(Gm::NearestMipmapNearest) => MinFilter::NearestMipmapNearest,
        Some(Gm::LinearMipmapNearest) => MinFilter::LinearMipmapNearest,
        Some(Gm::NearestMipmapLinear) => MinFilter::NearestMipmapLinear,
        Some(Gm::LinearMipmapLinear) | None => MinFilter::LinearMipmapLinear,
    };
    let wrap = |w: W| match w {
        W::ClampToEdge => Wrap::ClampToEdge,
        W::MirroredRepeat => Wrap::MirroredRepeat,
        W::Repeat => Wrap::Repeat,
    };
    let mut out = Sampler::new(Filter::Gl { mag, min }, Wrap::Repeat);
    out.wrap_u = wrap(s.wrap_s());
    out.wrap_v = wrap(s.wrap_t());
    out
}

const TRANSFORM: &str = "KHR_texture_transform";

/// Sets the transform (and uv set override) of the last map of `mat`, if it feeds `channel`,
/// from a raw `KHR_texture_transform` object: `offset`, `rotation`, `scale`, `texCoord`, each
/// optional; malformed members keep their defaults.
fn apply_raw_transform(mat: &mut Material, channel: MapChannel, value: Option<&gltf::json::Value>) {
    let (Some(value), Some(map)) = (value, mat.maps.last_mut()) else {
        return;
    };
    if map.channel != channel {
        return;
    }
    let pair = |key: &str, default: Vec2| {
        value
            .get(key)
            .and_then(|v| v.as_array())
            .and_then(|a| {
                Some(Vec2::new(
                    a.first()?.as_f64()? as f32,
                    a.get(1)?.as_f64()? as f32,
                ))
            })
            .filter(|v| v.is_finite())
            .unwrap_or(default)
    };
    map.slot.transform = TextureTransform {
        offset: pair("offset", Vec2::ZERO),
        rotation: value
            .get("rotation")
            .and_then(|v| v.as_f64())
            .map(|r| r as f32)
            .filter(|r| r.is_finite())
            .unwrap_or(0.0),
        scale: pair("scale", Vec2::ONE),
    };
    if let Some(tc) = value.get("texCoord").and_then(|v| v.as_u64()) {
        map.slot.tex_coord = u32::try_from(tc).unwrap_or(u32::MAX);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_become_lists() {
        assert_eq!(
            to_triangle_list(Mode::TriangleStrip, &[0, 1, 2, 3]),
            [0, 1, 2, 1, 3, 2]
        );
        assert_eq!(
            to_triangle_list(Mode::TriangleFan, &[0, 1, 2, 3]),
            [1, 2, 0, 2, 3, 0]
        );
        assert_eq!(to_triangle_list(Mode::Triangles, &[0, 1, 2, 3]), [0, 1, 2]);
    }

    /// A data-URI glTF: a non-indexed strip, a sparse POSITION, u8-normalized COLOR_0, and a
    /// base-colour texture whose KHR_texture_transform reads TEXCOORD_1.
    #[test]
    fn data_uris_strips_sparse_colors_and_texcoord_override() {
        use base64::Engine;
        let mut b: Vec<u8> = Vec::new();
        for p in [
            [0.0f32, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ] {
            p.iter().for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
        }
        b.extend_from_slice(&[
            255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128,
        ]);
        for uv in [[0.0f32, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]] {
            uv.iter()
                .for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
        }
        b.extend_from_slice(&[3, 0, 0, 0]);
        [2.0f32, 2.0, 0.0]
            .iter()
            .for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
        assert_eq!(b.len(), 112);
        let enc = |x: &[u8]| base64::engine::general_purpose::STANDARD.encode(x);
        let mut png = Vec::new();
        image::RgbaImage::from_pixel(2, 2, image::Rgba([9, 9, 9, 255]))
            .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .unwrap();
        let json = format!(
            r#"{{"asset": {{"version": "2.0"}}, "extensionsUsed": ["KHR_texture_transform"],
  "nodes": [{{"mesh": 0, "translation": [0, 0, -1]}}],
  "meshes": [{{"primitives": [{{"mode": 5, "material": 0,
     "attributes": {{"POSITION": 0, "COLOR_0": 1, "TEXCOORD_1": 2}}}}]}}],
  "materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0,
     "extensions": {{"KHR_texture_transform": {{"texCoord": 1, "scale": [2, 2]}}}}}}}},
     "normalTexture": {{"index": 0, "scale": 0.5,
       "extensions": {{"KHR_texture_transform": {{"offset": [0.25, 0.5], "rotation": 0.5}}}}}},
     "occlusionTexture": {{"index": 0,
       "extensions": {{"KHR_texture_transform": {{"texCoord": 1, "scale": [3, 4]}}}}}}}}],
  "textures": [{{"source": 0}}],
  "images": [{{"uri": "data:image/png;base64,{}"}}],
  "buffers": [{{"byteLength": 112, "uri": "data:application/octet-stream;base64,{}"}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 16}},
                  {{"buffer": 0, "byteOffset": 64, "byteLength": 32}}, {{"buffer": 0, "byteOffset": 96, "byteLength": 4}},
                  {{"buffer": 0, "byteOffset": 100, "byteLength": 12}}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [2, 2, 0],
      "sparse": {{"count": 1, "indices": {{"bufferView": 3, "componentType": 5121}}, "values": {{"bufferView": 4}}}}}},
    {{"bufferView": 1, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC4"}},
    {{"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}}]}}"#,
            enc(&png),
            enc(&b)
        );
        let p = crate::scene::test_file("gltf", "data.gltf", json);
        let l = load(&p, &LoadOptions::default()).unwrap();
        let m = &l.scene.meshes[0];
        assert_eq!(m.indices, [0, 1, 2, 1, 3, 2]);
        assert_eq!(m.positions[3], Vec3::new(2.0, 2.0, 0.0));
        assert_eq!(m.colors[3], Vec4::new(1.0, 1.0, 1.0, 128.0 / 255.0));
        assert_eq!(m.uvs1.len(), 4);
        assert!(m.uvs.is_empty());
        assert_eq!(m.world_from_object.w_axis.z, -1.0);
        let slot = l.scene.materials[0].base_color_texture.as_ref().unwrap();
        assert_eq!(slot.tex_coord, 1);
        assert_eq!(slot.transform.scale, Vec2::splat(2.0));
        // Normal and occlusion textures carry their own transforms.
        let mat = &l.scene.materials[0];
        let normal = mat.map(MapChannel::Normal).unwrap();
        assert_eq!(normal.scale, 0.5);
        assert_eq!(normal.slot.transform.offset, Vec2::new(0.25, 0.5));
        assert_eq!(normal.slot.transform.rotation, 0.5);
        assert_eq!(normal.slot.transform.scale, Vec2::ONE);
        assert_eq!(normal.slot.tex_coord, 0);
        let occlusion = mat.map(MapChannel::Occlusion).unwrap();
        assert_eq!(occlusion.slot.transform.scale, Vec2::new(3.0, 4.0));
        assert_eq!(occlusion.slot.tex_coord, 1);
        // One image, decoded twice: as sRGB colour and as linear data.
        assert_eq!(l.info.textures.len(), 2);
        // glTF materials are metallic-roughness, the default one a white rough metal.
        let (mat, default) = (&l.scene.materials[0], l.scene.materials.last().unwrap());
        assert_eq!(mat.model, ShadingModel::MetallicRoughness);
        assert_eq!((mat.metallic, mat.roughness), (1.0, 1.0));
        assert_eq!(default.model, ShadingModel::MetallicRoughness);
        assert_eq!((default.metallic, default.roughness), (1.0, 1.0));
    }

    #[test]
    fn punctual_light_intensities_are_divided_by_pi() {
        let json = r#"{"asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_unlit"],
  "extensions": {"KHR_lights_punctual": {"lights": [
    {"type": "directional", "color": [1, 0.5, 0.25], "intensity": 6.283185307179586},
    {"type": "point", "intensity": 31.41592653589793}]}},
  "materials": [{"extensions": {"KHR_materials_unlit": {}}}],
  "nodes": [{"extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"translation": [0, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 1}}}]}"#;
        let p = crate::scene::test_file("gltf", "lights.gltf", json);
        let l = load(&p, &LoadOptions::default()).unwrap();
        match l.scene.lights[..] {
            [Light::Directional { direction, color }, Light::Point {
                position,
                color: point,
                ..
            }] => {
                assert!((color - Vec3::new(2.0, 1.0, 0.5)).abs().max_element() < 1e-6);
                assert!((direction - Vec3::Z).length() < 1e-6, "{direction}");
                assert!((point - Vec3::splat(10.0)).abs().max_element() < 1e-5);
                assert_eq!(position, Vec3::new(0.0, 2.0, 0.0));
            }
            ref other => panic!("{other:?}"),
        }
        // KHR_materials_unlit keeps the Phong model (and ignores lights).
        assert!(l.scene.materials[0].unlit);
        assert_eq!(l.scene.materials[0].model, ShadingModel::Phong);
    }

    #[test]
    fn normalized_components() {
        assert_eq!(component(&[255], DataType::U8, true), 1.0);
        assert_eq!(component(&[0x80], DataType::I8, true), -1.0);
        assert_eq!(component(&[0xff, 0x7f], DataType::I16, true), 1.0);
        assert_eq!(component(&[7], DataType::U8, false), 7.0);
    }
}
