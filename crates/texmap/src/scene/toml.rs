//! TOML scene files: cameras, lights, materials with any texture channel, meshes from files
//! or built-in primitives, and volumes ([`super::toml_volume`]). The format is documented in
//! `docs/scenes.md`.
//!
//! Every table refuses unknown keys (a typo is an error naming the line), and relative paths
//! resolve from the scene file's folder. Meshes and volumes are placed alike: scale, rotate,
//! translate, or a matrix; a mesh may generate its texture coordinates (`texgen`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::{EulerRot, Mat4, Quat, Vec2, Vec3, Vec4};
use serde::Deserialize;

use super::load::{read_bounded, AssetInfo, ImageSource, LoadOptions, Loaded, TextureCache};
use super::primitives::Primitive;
use super::{
    AlphaMode, Camera, CameraProjection, Light, Material, Procedural, Scene, ShadingModel,
    SolidChannel, SolidMap, TextureSlot,
};
use crate::geometry::Projection;
use crate::shading::{MapChannel, MaterialMap};
use crate::texture::procedural::Solid;
use crate::texture::{Filter, Sampler, TextureTransform, Wrap};
use crate::{Error, Result};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    /// Linear RGBA.
    #[serde(default)]
    background: Option<[f32; 4]>,
    /// I_AL, linear RGB.
    #[serde(default)]
    ambient: Option<[f32; 3]>,
    #[serde(default)]
    cameras: Vec<CameraSpec>,
    #[serde(default)]
    lights: Vec<LightSpec>,
    #[serde(default)]
    materials: BTreeMap<String, MaterialSpec>,
    #[serde(default)]
    meshes: Vec<MeshSpec>,
    #[serde(default)]
    volumes: Vec<super::toml_volume::VolumeSpec>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraSpec {
    eye: [f32; 3],
    target: [f32; 3],
    #[serde(default = "up")]
    up: [f32; 3],
    /// "perspective" (default) or "orthographic".
    #[serde(default)]
    projection: Option<String>,
    /// Perspective: vertical field of view, degrees (default 60).
    #[serde(default)]
    fov: Option<f32>,
    /// Orthographic: the visible world height (required).
    #[serde(default)]
    height: Option<f32>,
    #[serde(default = "near")]
    near: f32,
    #[serde(default = "far")]
    far: f32,
}

fn up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}
fn near() -> f32 {
    0.05
}
fn far() -> f32 {
    1000.0
}
fn one() -> f32 {
    1.0
}
fn white() -> [f32; 3] {
    [1.0, 1.0, 1.0]
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, tag = "type", rename_all = "lowercase")]
enum LightSpec {
    Directional {
        /// Towards the light.
        direction: [f32; 3],
        #[serde(default = "white")]
        color: [f32; 3],
        #[serde(default = "one")]
        intensity: f32,
    },
    Point {
        position: [f32; 3],
        #[serde(default = "white")]
        color: [f32; 3],
        #[serde(default = "one")]
        intensity: f32,
        #[serde(default)]
        range: Option<f32>,
    },
    Spot {
        position: [f32; 3],
        /// Away from the light.
        direction: [f32; 3],
        #[serde(default = "white")]
        color: [f32; 3],
        #[serde(default = "one")]
        intensity: f32,
        #[serde(default)]
        inner_deg: f32,
        #[serde(default = "outer")]
        outer_deg: f32,
    },
}

fn outer() -> f32 {
    45.0
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct MaterialSpec {
    /// "phong" (default) or "pbr" (glTF metallic-roughness).
    model: Option<String>,
    base_color: Option<[f32; 4]>,
    ambient: Option<f32>,
    diffuse: Option<f32>,
    specular: Option<f32>,
    shininess: Option<f32>,
    emissive: Option<[f32; 3]>,
    metallic: Option<f32>,
    roughness: Option<f32>,
    #[serde(default)]
    unlit: bool,
    #[serde(default)]
    double_sided: bool,
    /// "opaque", "mask" or "blend".
    alpha_mode: Option<String>,
    alpha_cutoff: Option<f32>,
    base_color_texture: Option<TextureSpec>,
    #[serde(default)]
    maps: MapsSpec,
    /// A solid (procedural) texture multiplying the base colour.
    procedural: Option<ProceduralSpec>,
    /// An image whose coordinates a projection generates per pixel, multiplying the base colour.
    projected: Option<ProjectedSpec>,
    /// A 3D texture (baked from a pattern, or a volume file) as a solid texture.
    solid_texture: Option<SolidTextureSpec>,
    /// A solid texture on the roughness channel.
    roughness_procedural: Option<RoughnessProceduralSpec>,
    /// A solid texture on the bump (height) channel.
    bump_procedural: Option<BumpProceduralSpec>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RoughnessProceduralSpec {
    pattern: String,
    /// Roughness at pattern values 0 and 1 (default [0.2, 0.8]).
    #[serde(default = "roughness_range")]
    range: [f32; 2],
    #[serde(default = "yes")]
    antialias: bool,
}

fn roughness_range() -> [f32; 2] {
    [0.2, 0.8]
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BumpProceduralSpec {
    pattern: String,
    /// Height of pattern value 1, in object units (default 0.01).
    #[serde(default = "bump_scale")]
    scale: f32,
    #[serde(default = "yes")]
    antialias: bool,
}

fn bump_scale() -> f32 {
    0.01
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ProceduralSpec {
    /// marble | wood | granite | clouds | checker3d | bricks.
    pattern: String,
    /// Linear RGB for pattern values 0 and 1 (default: the pattern's own).
    colors: Option<[[f32; 3]; 2]>,
    /// Box-filter the pattern over the pixel footprint (default true).
    #[serde(default = "yes")]
    antialias: bool,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ProjectedSpec {
    /// planar-x | planar-y | planar-z | cylindrical | spherical | cube | bounding-sphere.
    projection: String,
    /// Centre for bounding-sphere, in object space (default: the mesh's bounding-box centre).
    center: Option<[f32; 3]>,
    texture: TextureSpec,
}

/// A 3D texture over an object-space box: baked from a pattern or read from a volume file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SolidTextureSpec {
    /// A pattern to bake (marble | wood | granite | clouds | checker3d | bricks) …
    bake: Option<String>,
    /// … at this many voxels a side (default 64) …
    size: Option<u32>,
    /// … or a volume file (.nii, .nii.gz, .nrrd, .nhdr; relative to the scene file), its value
    /// range mapped to 0..1.
    file: Option<PathBuf>,
    /// The object-space box the texture fills (default [-1, -1, -1] to [1, 1, 1]).
    #[serde(default = "minus_one")]
    min: [f32; 3],
    #[serde(default = "plus_one")]
    max: [f32; 3],
    /// Linear RGB for values 0 and 1 (default: the pattern's own, else black and white).
    colors: Option<[[f32; 3]; 2]>,
    /// nearest | bilinear | trilinear (default trilinear: mipmapped).
    filter: Option<String>,
    /// repeat | mirror | clamp | border | mirror-clamp (default repeat).
    wrap: Option<String>,
}

fn minus_one() -> [f32; 3] {
    [-1.0; 3]
}

fn plus_one() -> [f32; 3] {
    [1.0; 3]
}

fn yes() -> bool {
    true
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct MapsSpec {
    metallic_roughness: Option<TextureSpec>,
    normal: Option<TextureSpec>,
    occlusion: Option<TextureSpec>,
    emissive: Option<TextureSpec>,
    ambient: Option<TextureSpec>,
    specular: Option<TextureSpec>,
    shininess: Option<TextureSpec>,
    alpha: Option<TextureSpec>,
    bump: Option<TextureSpec>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TextureSpec {
    /// An image file (relative to the scene file).
    file: PathBuf,
    /// nearest | bilinear | trilinear | anisoN | ewa | sat (default trilinear).
    filter: Option<String>,
    /// repeat | mirror | clamp | border | mirror-clamp, both axes.
    wrap: Option<String>,
    wrap_u: Option<String>,
    wrap_v: Option<String>,
    /// "srgb" or "linear" (default: sRGB for colour channels, linear for data).
    color_space: Option<String>,
    #[serde(default)]
    transform: Option<TransformSpec>,
    #[serde(default = "one")]
    uv_scale: f32,
    #[serde(default)]
    tex_coord: u32,
    #[serde(default)]
    lod_bias: f32,
    /// Normal scale, occlusion strength or bump multiplier.
    #[serde(default = "one")]
    scale: f32,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TransformSpec {
    #[serde(default)]
    offset: [f32; 2],
    /// Degrees.
    #[serde(default)]
    rotation: f32,
    #[serde(default = "unit2")]
    scale: [f32; 2],
}

fn unit2() -> [f32; 2] {
    [1.0, 1.0]
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshSpec {
    /// A model file (.gltf, .glb, .obj), relative to the scene file.
    file: Option<PathBuf>,
    /// plane | cube | sphere | cylinder | cone | torus.
    primitive: Option<String>,
    /// A material name from `[materials]`; for files it replaces the file's materials.
    material: Option<String>,
    /// Primitive sizes (defaults: 1).
    size: Option<f32>,
    width: Option<f32>,
    depth: Option<f32>,
    radius: Option<f32>,
    height: Option<f32>,
    major_radius: Option<f32>,
    minor_radius: Option<f32>,
    segments: Option<u32>,
    rings: Option<u32>,
    divisions: Option<u32>,
    /// Object → world: scale, then rotate (degrees about x, y, z), then translate; or a
    /// column-major 4×4 `matrix` (glTF's order).
    translate: Option<[f32; 3]>,
    rotate: Option<[f32; 3]>,
    scale: Option<ScaleSpec>,
    matrix: Option<[f32; 16]>,
    /// Texture coordinates generated per vertex by a projection (replacing the mesh's own).
    texgen: Option<TexgenSpec>,
}

/// `texgen = { projection = "spherical", set = 0, center = [0, 0, 0] }` on a mesh.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TexgenSpec {
    /// planar-x | planar-y | planar-z | cylindrical | spherical | cube | bounding-sphere.
    projection: String,
    /// The uv set written: 0 (default) or 1; a channel reads it with its `tex_coord`.
    #[serde(default)]
    set: u32,
    /// Bounding-sphere centre in object space (default: the mesh's bounding-box centre).
    center: Option<[f32; 3]>,
}

/// Replaces uv set `t.set` of `mesh` with per-vertex coordinates from the projection (object
/// space); seam triangles get their own vertex copies, every other attribute follows them.
fn apply_texgen(mesh: &mut super::Mesh, t: &TexgenSpec) -> std::result::Result<(), String> {
    let mut projection = Projection::parse(&t.projection).ok_or_else(|| {
        format!(
            "texgen: projection {:?}: expected planar-x, planar-y, planar-z, cylindrical, spherical, cube or bounding-sphere",
            t.projection
        )
    })?;
    if t.set > 1 {
        return Err(format!("texgen: set {} is not 0 or 1", t.set));
    }
    if let Projection::BoundingSphere { center } = &mut projection {
        *center = t.center.map_or_else(|| mesh.object_center(), Vec3::from);
    }
    let (uvs, indices, remap) = crate::geometry::texgen::generate_uvs(
        &projection,
        &mesh.positions,
        &mesh.normals,
        &mesh.indices,
    );
    fn follow<T: Copy>(v: &mut Vec<T>, remap: &[u32], n: usize) {
        if v.len() == n {
            *v = remap.iter().map(|&i| v[i as usize]).collect();
        }
    }
    let n = mesh.positions.len();
    follow(&mut mesh.positions, &remap, n);
    follow(&mut mesh.normals, &remap, n);
    follow(&mut mesh.uvs, &remap, n);
    follow(&mut mesh.uvs1, &remap, n);
    follow(&mut mesh.colors, &remap, n);
    // Tangents follow set 0; they are regenerated when set 0 changes.
    if t.set == 0 {
        mesh.tangents.clear();
        mesh.uvs = uvs;
    } else {
        follow(&mut mesh.tangents, &remap, n);
        mesh.uvs1 = uvs;
    }
    mesh.indices = indices;
    Ok(())
}

#[derive(Deserialize)]
#[serde(untagged)]
pub(super) enum ScaleSpec {
    Uniform(f32),
    Axes([f32; 3]),
}

/// Loads a `.toml` scene file.
pub fn load(path: &Path, options: &LoadOptions) -> Result<Loaded> {
    let bytes = read_bounded(path, options.max_buffer_bytes)?;
    let text = String::from_utf8(bytes).map_err(|_| Error::decode(path, "not UTF-8 text"))?;
    let spec: SceneFile = ::toml::from_str(&text).map_err(|e| {
        let line = e
            .span()
            .map(|s| text.get(..s.start).unwrap_or(&text).matches('\n').count() + 1);
        let msg = e.message().replace('\n', " ");
        match line {
            Some(l) => Error::decode(path, format!("line {l}: {msg}")),
            None => Error::decode(path, msg),
        }
    })?;
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let err = |m: String| Error::decode(path, m);

    let mut scene = Scene {
        background: Vec4::from(spec.background.unwrap_or([0.0, 0.0, 0.0, 1.0])),
        ambient_light: Vec3::from(spec.ambient.unwrap_or([1.0; 3])),
        ..Default::default()
    };
    let mut info = AssetInfo {
        format: "TOML scene".into(),
        ..Default::default()
    };
    let mut warnings = Vec::new();
    let mut textures = TextureCache::new(options);

    let mut cameras = Vec::new();
    for (i, c) in spec.cameras.iter().enumerate() {
        let projection = match (c.projection.as_deref(), c.fov, c.height) {
            (None | Some("perspective"), fov, None) => CameraProjection::Perspective {
                fov_y_deg: fov.unwrap_or(60.0),
            },
            (Some("orthographic"), None, Some(height)) => CameraProjection::Orthographic {
                half_height: 0.5 * height,
            },
            (Some("orthographic"), None, None) => {
                return Err(err(format!(
                    "cameras[{i}]: an orthographic camera needs `height` (visible world height)"
                )))
            }
            (Some("orthographic"), Some(_), _) => {
                return Err(err(format!(
                "cameras[{i}]: `fov` is for perspective cameras; orthographic ones take `height`"
            )))
            }
            (None | Some("perspective"), _, Some(_)) => {
                return Err(err(format!(
                "cameras[{i}]: `height` is for orthographic cameras; perspective ones take `fov`"
            )))
            }
            (Some(other), _, _) => {
                return Err(err(format!(
                    "cameras[{i}]: projection {other:?} is not perspective or orthographic"
                )))
            }
        };
        let cam = Camera {
            eye: Vec3::from(c.eye),
            target: Vec3::from(c.target),
            up: Vec3::from(c.up),
            projection,
            near: c.near,
            far: c.far,
        };
        cam.validate()
            .map_err(|e| err(format!("cameras[{i}]: {e}")))?;
        cameras.push(cam);
    }
    scene.camera = cameras.first().copied();

    for l in &spec.lights {
        scene.lights.push(match *l {
            LightSpec::Directional {
                direction,
                color,
                intensity,
            } => Light::Directional {
                direction: Vec3::from(direction),
                color: Vec3::from(color) * intensity,
            },
            LightSpec::Point {
                position,
                color,
                intensity,
                range,
            } => Light::Point {
                position: Vec3::from(position),
                color: Vec3::from(color) * intensity,
                range,
            },
            LightSpec::Spot {
                position,
                direction,
                color,
                intensity,
                inner_deg,
                outer_deg,
            } => Light::Spot {
                position: Vec3::from(position),
                direction: Vec3::from(direction),
                color: Vec3::from(color) * intensity,
                inner_deg,
                outer_deg,
            },
        });
    }
    if scene.lights.is_empty() {
        scene.lights.push(Light::Directional {
            direction: Vec3::new(0.3, 0.8, 0.5).normalize(),
            color: Vec3::ONE,
        });
    }

    let mut material_index = BTreeMap::new();
    for (name, m) in &spec.materials {
        let mat = material(&dir, name, m, &mut textures).map_err(|e| match e {
            Error::Parameter(msg) => err(format!("materials.{name}: {msg}")),
            other => other,
        })?;
        material_index.insert(name.clone(), scene.materials.len());
        scene.materials.push(mat);
        info.material_names.push(name.clone());
    }
    let default_material = scene.materials.len();
    scene.materials.push(Material::default());
    info.material_names.push("(default)".into());

    for (i, m) in spec.meshes.iter().enumerate() {
        let transform = placement(m.translate, m.rotate, m.scale.as_ref(), m.matrix)
            .map_err(|e| err(format!("meshes[{i}]: {e}")))?;
        let named = match &m.material {
            Some(n) => Some(*material_index.get(n).ok_or_else(|| {
                err(format!(
                    "meshes[{i}]: no material named {n:?} in [materials]"
                ))
            })?),
            None => None,
        };
        match (&m.file, &m.primitive) {
            (Some(file), None) => {
                let full = dir.join(file);
                if full
                    .extension()
                    .and_then(|e| e.to_str())
                    .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
                {
                    return Err(err(format!(
                        "meshes[{i}]: a scene file cannot include another scene file"
                    )));
                }
                let sub = super::load(&full, options)?;
                let offset = scene.materials.len();
                for (k, mesh) in sub.scene.meshes.into_iter().enumerate() {
                    let mut mesh = mesh;
                    if let Some(t) = &m.texgen {
                        apply_texgen(&mut mesh, t).map_err(|e| err(format!("meshes[{i}]: {e}")))?;
                    }
                    mesh.world_from_object = transform * mesh.world_from_object;
                    mesh.material = named.unwrap_or(mesh.material + offset);
                    info.mesh_names.push(format!(
                        "{}: {}",
                        file.display(),
                        sub.info.mesh_names.get(k).map_or("", String::as_str)
                    ));
                    scene.meshes.push(mesh);
                }
                scene.materials.extend(sub.scene.materials);
                info.material_names.extend(
                    sub.info
                        .material_names
                        .into_iter()
                        .map(|n| format!("{}: {n}", file.display())),
                );
                info.textures.extend(sub.info.textures);
                warnings.extend(sub.warnings);
            }
            (None, Some(kind)) => {
                let p = primitive(kind, m).map_err(|e| err(format!("meshes[{i}]: {e}")))?;
                let mut mesh = p.mesh(named.unwrap_or(default_material));
                if let Some(t) = &m.texgen {
                    apply_texgen(&mut mesh, t).map_err(|e| err(format!("meshes[{i}]: {e}")))?;
                }
                mesh.world_from_object = transform;
                info.mesh_names.push(kind.clone());
                scene.meshes.push(mesh);
            }
            _ => {
                return Err(err(format!(
                    "meshes[{i}]: give exactly one of `file` and `primitive`"
                )))
            }
        }
    }
    // Volumes shade with the file's own lights, else with a headlight.
    let volume_lights: &[Light] = if spec.lights.is_empty() {
        &[]
    } else {
        &scene.lights
    };
    let mut volumes = Vec::new();
    for (i, v) in spec.volumes.iter().enumerate() {
        let transform = placement(v.translate, v.rotate, v.scale.as_ref(), v.matrix)
            .map_err(|e| err(format!("volumes[{i}]: {e}")))?;
        let sv =
            super::toml_volume::volume(&dir, v, transform, volume_lights).map_err(|e| match e {
                Error::Parameter(msg) | Error::Unsupported(msg) => {
                    err(format!("volumes[{i}]: {msg}"))
                }
                other => other,
            })?;
        info.volumes.push(sv.source.display().to_string());
        volumes.push(sv);
    }
    info.default_light = spec.lights.is_empty();
    for i in super::tangents::generate_where_needed(&mut scene.meshes, &scene.materials) {
        warnings.push(format!(
            "{}: mesh {i}: no tangents for its normal map (it lacks normals or uvs)",
            path.display()
        ));
    }
    warnings.append(&mut textures.warnings);
    info.textures.append(&mut textures.infos);
    Ok(Loaded {
        scene,
        cameras,
        info,
        volumes,
        warnings,
    })
}

/// Object → world from a table's `translate`, `rotate` (degrees about x, then y, then z) and
/// `scale` (applied first), or its column-major `matrix` (then none of the others).
fn placement(
    translate: Option<[f32; 3]>,
    rotate: Option<[f32; 3]>,
    scale: Option<&ScaleSpec>,
    matrix: Option<[f32; 16]>,
) -> std::result::Result<Mat4, String> {
    let m = if let Some(m) = matrix {
        if translate.is_some() || rotate.is_some() || scale.is_some() {
            return Err("give `matrix` or `translate`/`rotate`/`scale`, not both".into());
        }
        Mat4::from_cols_array(&m)
    } else {
        let scale = match scale {
            Some(ScaleSpec::Uniform(s)) => Vec3::splat(*s),
            Some(ScaleSpec::Axes(a)) => Vec3::from(*a),
            None => Vec3::ONE,
        };
        let r = rotate.unwrap_or_default().map(f32::to_radians);
        Mat4::from_scale_rotation_translation(
            scale,
            Quat::from_euler(EulerRot::ZYX, r[2], r[1], r[0]),
            Vec3::from(translate.unwrap_or_default()),
        )
    };
    if !m.is_finite() {
        return Err("the placement has a non-finite number".into());
    }
    Ok(m)
}

fn primitive(kind: &str, m: &MeshSpec) -> std::result::Result<Primitive, String> {
    let positive = |v: Option<f32>, d: f32, what: &str| {
        let v = v.unwrap_or(d);
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(format!("{what} must be a positive number"))
        }
    };
    let size = positive(m.size, 1.0, "size")?;
    Ok(match kind {
        "plane" => Primitive::Plane {
            width: positive(m.width, size, "width")?,
            depth: positive(m.depth, size, "depth")?,
            divisions: m.divisions.unwrap_or(1),
        },
        "cube" => Primitive::Cube { size },
        "sphere" => Primitive::Sphere {
            radius: positive(m.radius, 0.5 * size, "radius")?,
            segments: m.segments.unwrap_or(64),
            rings: m.rings.unwrap_or(33),
        },
        "cylinder" | "cone" => {
            let radius = positive(m.radius, 0.5 * size, "radius")?;
            let height = positive(m.height, size, "height")?;
            let segments = m.segments.unwrap_or(64);
            if kind == "cone" {
                Primitive::Cone {
                    radius,
                    height,
                    segments,
                }
            } else {
                Primitive::Cylinder {
                    radius,
                    height,
                    segments,
                }
            }
        }
        "torus" => Primitive::Torus {
            major: positive(m.major_radius, 0.375 * size, "major_radius")?,
            minor: positive(m.minor_radius, 0.125 * size, "minor_radius")?,
            segments: m.segments.unwrap_or(64),
            sides: m.rings.unwrap_or(24),
        },
        other => {
            return Err(format!(
                "unknown primitive {other:?} (plane, cube, sphere, cylinder, cone, torus)"
            ))
        }
    })
}

fn material(
    dir: &Path,
    _name: &str,
    m: &MaterialSpec,
    textures: &mut TextureCache,
) -> Result<Material> {
    let d = Material::default();
    let alpha_mode = match m.alpha_mode.as_deref() {
        None | Some("opaque") => AlphaMode::Opaque,
        Some("mask") => AlphaMode::Mask(m.alpha_cutoff.unwrap_or(0.5)),
        Some("blend") => AlphaMode::Blend,
        Some(other) => {
            return Err(Error::parameter(format!(
                "alpha_mode {other:?} is not opaque, mask or blend"
            )))
        }
    };
    let model = match m.model.as_deref() {
        None | Some("phong") => ShadingModel::Phong,
        Some("pbr") => ShadingModel::MetallicRoughness,
        Some(other) => {
            return Err(Error::parameter(format!(
                "model {other:?} is not phong or pbr"
            )))
        }
    };
    let mut mat = Material {
        model,
        base_color: m.base_color.map_or(d.base_color, Vec4::from),
        ambient: m.ambient.unwrap_or(d.ambient),
        diffuse: m.diffuse.unwrap_or(d.diffuse),
        specular: m.specular.unwrap_or(d.specular),
        shininess: m.shininess.unwrap_or(d.shininess),
        emissive: m.emissive.map_or(d.emissive, Vec3::from),
        metallic: m.metallic.unwrap_or(d.metallic),
        roughness: m.roughness.unwrap_or(d.roughness),
        unlit: m.unlit,
        double_sided: m.double_sided,
        alpha_mode,
        ..d
    };
    if let Some(t) = &m.base_color_texture {
        mat.base_color_texture = slot(dir, t, true, textures)?;
    }
    let colour_sources = [
        m.procedural.is_some(),
        m.projected.is_some(),
        m.solid_texture.is_some(),
    ];
    if colour_sources.iter().filter(|&&x| x).count() > 1 {
        return Err(Error::parameter(
            "a material takes one of `procedural`, `projected` and `solid_texture`",
        ));
    }
    mat.procedural = match (&m.procedural, &m.projected) {
        (Some(p), _) => {
            let solid = pattern(&p.pattern)?;
            Some(Procedural::Solid {
                colors: p
                    .colors
                    .map_or(solid.default_colors(), |c| c.map(Vec3::from)),
                solid,
                antialias: p.antialias,
            })
        }
        (None, Some(p)) => {
            let mut projection = Projection::parse(&p.projection).ok_or_else(|| {
                Error::parameter(format!(
                    "projection {:?}: expected planar-x, planar-y, planar-z, cylindrical, spherical, cube or bounding-sphere",
                    p.projection
                ))
            })?;
            if let Projection::BoundingSphere { center } = &mut projection {
                // NaN: resolved to the mesh's bounding-box centre when drawn.
                *center = p.center.map_or(Vec3::NAN, Vec3::from);
            }
            slot(dir, &p.texture, true, textures)?
                .map(|slot| Procedural::Projected { slot, projection })
        }
        (None, None) => match &m.solid_texture {
            Some(t) => Some(solid_texture(dir, t)?),
            None => None,
        },
    };
    if let Some(r) = &m.roughness_procedural {
        if !r.range.iter().all(|v| (0.0..=1.0).contains(v)) {
            return Err(Error::parameter(format!(
                "roughness_procedural: range {:?} is not within [0, 1]",
                r.range
            )));
        }
        mat.solid_maps.push(SolidMap {
            solid: pattern(&r.pattern)?,
            channel: SolidChannel::Roughness { range: r.range },
            antialias: r.antialias,
        });
    }
    if let Some(b) = &m.bump_procedural {
        if !b.scale.is_finite() {
            return Err(Error::parameter("bump_procedural: scale must be a number"));
        }
        mat.solid_maps.push(SolidMap {
            solid: pattern(&b.pattern)?,
            channel: SolidChannel::Bump { scale: b.scale },
            antialias: b.antialias,
        });
    }
    let maps = &m.maps;
    for (channel, spec) in [
        (MapChannel::MetallicRoughness, &maps.metallic_roughness),
        (MapChannel::Normal, &maps.normal),
        (MapChannel::Occlusion, &maps.occlusion),
        (MapChannel::Emissive, &maps.emissive),
        (MapChannel::Ambient, &maps.ambient),
        (MapChannel::Specular, &maps.specular),
        (MapChannel::Shininess, &maps.shininess),
        (MapChannel::Alpha, &maps.alpha),
        (MapChannel::Bump, &maps.bump),
    ] {
        if let Some(spec) = spec {
            if let Some(s) = slot(dir, spec, channel.is_color(), textures)? {
                mat.maps.push(MaterialMap {
                    channel,
                    slot: s,
                    scale: spec.scale,
                });
            }
        }
    }
    Ok(mat)
}

fn pattern(name: &str) -> Result<Solid> {
    Solid::named(name).ok_or_else(|| {
        Error::parameter(format!(
            "pattern {name:?}: expected marble, wood, granite, clouds, checker3d or bricks"
        ))
    })
}

fn parse_filter(f: &str) -> Result<Filter> {
    Filter::parse(f).ok().ok_or_else(|| {
        Error::parameter(format!(
            "filter {f:?}: expected nearest, bilinear, trilinear, aniso1..aniso16, ewa or sat"
        ))
    })
}

fn parse_wrap(w: &str) -> Result<Wrap> {
    Wrap::parse(w).ok().ok_or_else(|| {
        Error::parameter(format!(
            "wrap {w:?}: expected repeat, mirror, clamp, border or mirror-clamp"
        ))
    })
}

/// A `solid_texture` table → [`Procedural::Texture3D`].
fn solid_texture(dir: &Path, t: &SolidTextureSpec) -> Result<Procedural> {
    let (min, max) = (Vec3::from(t.min), Vec3::from(t.max));
    if !(min.is_finite() && max.is_finite() && max.cmpgt(min).all()) {
        return Err(Error::parameter(format!(
            "solid_texture: the box {min}..{max} must have every max above its min"
        )));
    }
    let (texture, default_colors) = match (&t.bake, &t.file) {
        (Some(name), None) => {
            let solid = pattern(name)?;
            let size = t.size.unwrap_or(64);
            let tex = solid.bake(size, min.as_dvec3(), max.as_dvec3())?;
            (tex, solid.default_colors())
        }
        (None, Some(file)) => {
            if t.size.is_some() {
                return Err(Error::parameter(
                    "solid_texture: `size` is for `bake`, not `file`",
                ));
            }
            let path = dir.join(file);
            let vol = crate::volume::load_volume(&path, None)?;
            (vol.texture().clone(), [Vec3::ZERO, Vec3::ONE])
        }
        _ => {
            return Err(Error::parameter(
                "solid_texture: give either `bake = \"pattern\"` or `file = \"volume\"`",
            ))
        }
    };
    // 3D textures filter with OpenGL's filters only (no anisotropic, EWA or SAT path).
    let filter = match t.filter.as_deref().map(parse_filter).transpose()? {
        None => Filter::TRILINEAR,
        Some(f @ Filter::Gl { .. }) => f,
        Some(_) => {
            return Err(Error::parameter(format!(
                "solid_texture: filter {:?}: expected nearest, bilinear or trilinear",
                t.filter.as_deref().unwrap_or_default()
            )))
        }
    };
    let wrap = t
        .wrap
        .as_deref()
        .map(parse_wrap)
        .transpose()?
        .unwrap_or(Wrap::Repeat);
    Ok(Procedural::Texture3D {
        texture: std::sync::Arc::new(texture),
        sampler: Sampler::new(filter, wrap),
        min,
        max,
        colors: t.colors.map_or(default_colors, |c| c.map(Vec3::from)),
    })
}

fn slot(
    dir: &Path,
    t: &TextureSpec,
    color: bool,
    textures: &mut TextureCache,
) -> Result<Option<TextureSlot>> {
    let filter = t
        .filter
        .as_deref()
        .map(parse_filter)
        .transpose()?
        .unwrap_or(Filter::TRILINEAR);
    let wrap = |w: Option<&str>, d: Wrap| -> Result<Wrap> {
        Ok(w.map(parse_wrap).transpose()?.unwrap_or(d))
    };
    let both = wrap(t.wrap.as_deref(), Wrap::Repeat)?;
    let srgb = match t.color_space.as_deref() {
        None => color,
        Some("srgb") => true,
        Some("linear") => false,
        Some(other) => {
            return Err(Error::parameter(format!(
                "color_space {other:?} is not srgb or linear"
            )))
        }
    };
    if t.tex_coord > 1 {
        return Err(Error::parameter(format!(
            "tex_coord {} is not 0 or 1",
            t.tex_coord
        )));
    }
    let file = dir.join(&t.file);
    let Some(tex) = textures.get(
        &file.to_string_lossy(),
        ImageSource::File(file.clone()),
        srgb,
        false,
    )?
    else {
        return Ok(None);
    };
    let mut sampler = Sampler::new(filter, both);
    sampler.wrap_u = wrap(t.wrap_u.as_deref(), both)?;
    sampler.wrap_v = wrap(t.wrap_v.as_deref(), both)?;
    sampler.lod_bias = t.lod_bias;
    let mut s = TextureSlot::new(tex, sampler);
    s.uv_scale = t.uv_scale;
    s.tex_coord = t.tex_coord;
    if let Some(tr) = &t.transform {
        s.transform = TextureTransform {
            offset: Vec2::from(tr.offset),
            rotation: tr.rotation.to_radians(),
            scale: Vec2::from(tr.scale),
        };
    }
    Ok(Some(s))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, body: &str) -> PathBuf {
        crate::scene::test_file("toml", name, body)
    }

    #[test]
    fn primitives_materials_lights_and_camera() {
        let p = write(
            "ok.toml",
            r#"
background = [0.1, 0.1, 0.1, 1]
[[cameras]]
eye = [0, 2, 5]
target = [0, 0, 0]
[[lights]]
type = "point"
position = [0, 3, 0]
intensity = 10
[materials.red]
base_color = [1, 0, 0, 1]
[[meshes]]
primitive = "torus"
material = "red"
translate = [1, 0, 0]
[[meshes]]
primitive = "plane"
size = 10
"#,
        );
        let l = load(&p, &LoadOptions::default()).unwrap();
        assert_eq!(l.scene.meshes.len(), 2);
        assert_eq!(l.scene.meshes[0].material, 0);
        assert_eq!(l.scene.meshes[1].material, 1);
        assert_eq!(l.scene.lights.len(), 1);
        assert!(l.scene.camera.is_some());
        assert_eq!(l.scene.meshes[0].world_from_object.w_axis.x, 1.0);
    }

    #[test]
    fn pbr_model_and_solid_roughness_and_bump_channels() {
        let p = write(
            "pbr.toml",
            r#"
[materials.stone]
model = "pbr"
metallic = 0.25
roughness_procedural = { pattern = "granite", range = [0.3, 0.9] }
bump_procedural = { pattern = "marble", scale = 0.05, antialias = false }
[materials.plain]
roughness = 0.5
"#,
        );
        let l = load(&p, &LoadOptions::default()).unwrap();
        let (plain, stone) = (&l.scene.materials[0], &l.scene.materials[1]);
        assert_eq!(plain.model, ShadingModel::Phong);
        assert!(plain.solid_maps.is_empty());
        assert_eq!(stone.model, ShadingModel::MetallicRoughness);
        assert_eq!(stone.metallic, 0.25);
        let (r, range) = stone.solid_roughness().unwrap();
        assert_eq!(range, [0.3, 0.9]);
        assert_eq!(r.solid, Solid::named("granite").unwrap());
        assert!(r.antialias);
        let (b, scale) = stone.solid_bump().unwrap();
        assert_eq!(scale, 0.05);
        assert!(!b.antialias);
    }

    #[test]
    fn bad_model_and_solid_channel_keys_are_errors() {
        for (name, body, needle) in [
            ("m.toml", "[materials.a]\nmodel = \"blinn\"\n", "blinn"),
            (
                "r.toml",
                "[materials.a]\nroughness_procedural = { pattern = \"granite\", colors = [[0,0,0],[1,1,1]] }\n",
                "colors",
            ),
            (
                "b.toml",
                "[materials.a]\nbump_procedural = { pattern = \"lava\" }\n",
                "lava",
            ),
            (
                "r2.toml",
                "[materials.a]\nroughness_procedural = { pattern = \"wood\", range = [0, 2] }\n",
                "range",
            ),
        ] {
            let p = write(name, body);
            let e = load(&p, &LoadOptions::default()).unwrap_err().to_string();
            assert!(e.contains(needle), "{name}: {e}");
        }
    }

    #[test]
    fn orthographic_cameras_take_a_height() {
        let cam = |body: &str| {
            let p = write(
                "cam.toml",
                &format!("[[cameras]]\neye = [0, 0, 5]\ntarget = [0, 0, 0]\n{body}"),
            );
            load(&p, &LoadOptions::default()).map(|l| l.scene.camera.unwrap().projection)
        };
        assert_eq!(
            cam("projection = \"orthographic\"\nheight = 4\nnear = 0\n").unwrap(),
            CameraProjection::Orthographic { half_height: 2.0 }
        );
        assert_eq!(
            cam("fov = 45\n").unwrap(),
            CameraProjection::Perspective { fov_y_deg: 45.0 }
        );
        for (bad, says) in [
            ("projection = \"orthographic\"\n", "needs `height`"),
            (
                "projection = \"orthographic\"\nheight = 4\nfov = 30\n",
                "`fov`",
            ),
            ("height = 4\n", "`height`"),
            ("projection = \"fisheye\"\n", "fisheye"),
            ("projection = \"orthographic\"\nheight = -1\n", "height"),
        ] {
            let e = cam(bad).unwrap_err().to_string();
            assert!(e.contains("cam.toml") && e.contains(says), "{bad}: {e}");
        }
    }

    #[test]
    fn texgen_writes_a_uv_set_from_the_projection() {
        let p = write(
            "texgen.toml",
            r#"
[[meshes]]
primitive = "sphere"
texgen = { projection = "spherical" }
[[meshes]]
primitive = "cube"
texgen = { projection = "cube", set = 1 }
"#,
        );
        let l = load(&p, &LoadOptions::default()).unwrap();
        let (sphere, cube) = (&l.scene.meshes[0], &l.scene.meshes[1]);
        assert_eq!(sphere.uvs.len(), sphere.positions.len());
        // Off the seam copies, each vertex's uv is the projection of its position.
        let mut matched = 0;
        for (p, uv) in sphere.positions.iter().zip(&sphere.uvs) {
            let want = Projection::Spherical.map(*p, Vec3::Y);
            if (want - *uv).abs().max_element() < 1e-5 {
                matched += 1;
            }
        }
        assert!(matched * 10 >= sphere.uvs.len() * 9, "{matched}");
        assert!(sphere
            .indices
            .iter()
            .all(|&i| (i as usize) < sphere.positions.len()));
        assert_eq!(cube.uvs1.len(), cube.positions.len());
        for (k, e) in [
            ("texgen = { projection = \"conic\" }", "conic"),
            ("texgen = { projection = \"cube\", set = 2 }", "set 2"),
        ] {
            let p = write(
                "bad_texgen.toml",
                &format!("[[meshes]]\nprimitive = \"cube\"\n{k}\n"),
            );
            let msg = load(&p, &LoadOptions::default()).unwrap_err().to_string();
            assert!(msg.contains(e) && msg.contains("meshes[0]"), "{msg}");
        }
    }

    #[test]
    fn unknown_key_names_the_line() {
        let p = write("bad.toml", "[[meshes]]\nprimitive = \"cube\"\ncolour = 3\n");
        let e = load(&p, &LoadOptions::default()).unwrap_err().to_string();
        assert!(
            e.contains("bad.toml") && e.contains("line 3") && e.contains("colour"),
            "{e}"
        );
    }

    #[test]
    fn unknown_material_and_primitive_are_errors() {
        let p = write(
            "bad2.toml",
            "[[meshes]]\nprimitive = \"cube\"\nmaterial = \"nope\"\n",
        );
        assert!(load(&p, &LoadOptions::default())
            .unwrap_err()
            .to_string()
            .contains("nope"));
        let p = write("bad3.toml", "[[meshes]]\nprimitive = \"blob\"\n");
        assert!(load(&p, &LoadOptions::default())
            .unwrap_err()
            .to_string()
            .contains("blob"));
    }
}
