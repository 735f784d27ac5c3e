//! The TOML scene format's tables as serde reads them: one type per table, every one
//! refusing keys it does not know (`deny_unknown_fields`, so a typo is an error naming its
//! line), with the defaults `docs/scenes.md` lists. Nothing here interprets a value; the
//! files beside this one turn these tables into scene data.

use std::collections::BTreeMap;
use std::path::PathBuf;

use serde::Deserialize;

/// The whole file: the top-level keys and the table arrays.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SceneFile {
    /// Linear RGBA.
    #[serde(default)]
    pub(super) background: Option<[f32; 4]>,
    /// I_AL, linear RGB.
    #[serde(default)]
    pub(super) ambient: Option<[f32; 3]>,
    #[serde(default)]
    pub(super) cameras: Vec<CameraSpec>,
    /// `lights = []` says no lights (without the key, the peers' light).
    #[serde(default)]
    pub(super) lights: Option<Vec<LightSpec>>,
    /// How the casting lights' shadow maps are made and read.
    #[serde(default)]
    pub(super) shadows: Option<ShadowsSpec>,
    /// The environment map: background, image-based light, reflections.
    #[serde(default)]
    pub(super) environment: Option<EnvironmentSpec>,
    #[serde(default)]
    pub(super) materials: BTreeMap<String, MaterialSpec>,
    #[serde(default)]
    pub(super) meshes: Vec<MeshSpec>,
    #[serde(default)]
    pub(super) volumes: Vec<VolumeSpec>,
    /// Slide projectors.
    #[serde(default)]
    pub(super) projectors: Vec<ProjectorSpec>,
}

/// A `[[projectors]]` entry: a slide projector.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ProjectorSpec {
    pub(super) position: [f32; 3],
    pub(super) target: [f32; 3],
    #[serde(default = "up")]
    pub(super) up: [f32; 3],
    /// Vertical field of view, degrees (default 30).
    #[serde(default = "projector_fov")]
    pub(super) fov: f32,
    /// Width over height (default: the image's).
    pub(super) aspect: Option<f32>,
    /// The slide: a texture table (sRGB unless it says; a transparent black border unless
    /// it names a wrap).
    pub(super) image: TextureSpec,
    #[serde(default = "white")]
    pub(super) color: [f32; 3],
    #[serde(default = "one")]
    pub(super) intensity: f32,
    /// Inverse-square falloff (default true).
    #[serde(default = "yes")]
    pub(super) falloff: bool,
    /// Occluded by its own depth map (default false).
    #[serde(default)]
    pub(super) shadows: bool,
}

fn projector_fov() -> f32 {
    30.0
}

/// A `[[cameras]]` entry.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraSpec {
    pub(super) eye: [f32; 3],
    pub(super) target: [f32; 3],
    #[serde(default = "up")]
    pub(super) up: [f32; 3],
    /// "perspective" (default) or "orthographic".
    #[serde(default)]
    pub(super) projection: Option<String>,
    /// Perspective: vertical field of view, degrees (default 60).
    #[serde(default)]
    pub(super) fov: Option<f32>,
    /// Orthographic: the visible world height (required).
    #[serde(default)]
    pub(super) height: Option<f32>,
    #[serde(default = "near")]
    pub(super) near: f32,
    #[serde(default = "far")]
    pub(super) far: f32,
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

/// The `[environment]` table.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct EnvironmentSpec {
    /// An image (equirectangular, cross or sphere map) or a folder of six faces, relative to
    /// the scene file.
    pub(super) file: PathBuf,
    /// equirect | cross | faces | sphere (default: from the image's proportions).
    pub(super) kind: Option<String>,
    /// Degrees about +y.
    #[serde(default)]
    pub(super) rotate: f32,
    #[serde(default = "one")]
    pub(super) intensity: f32,
    /// env | color | none (default env).
    pub(super) background: Option<String>,
    /// Image-based light in place of `ambient` (default true).
    #[serde(default = "yes")]
    pub(super) ibl: bool,
    /// Reflection and refraction terms (default true).
    #[serde(default = "yes")]
    pub(super) reflections: bool,
    /// How the map is read (default trilinear).
    pub(super) filter: Option<String>,
}

/// A `[[lights]]` entry, by its `type`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, tag = "type", rename_all = "lowercase")]
pub(super) enum LightSpec {
    Directional {
        /// Towards the light.
        direction: [f32; 3],
        #[serde(default = "white")]
        color: [f32; 3],
        #[serde(default = "one")]
        intensity: f32,
        /// Casts shadows (a shadow map).
        #[serde(default)]
        shadows: bool,
    },
    Point {
        position: [f32; 3],
        #[serde(default = "white")]
        color: [f32; 3],
        #[serde(default = "one")]
        intensity: f32,
        #[serde(default)]
        range: Option<f32>,
        #[serde(default)]
        shadows: bool,
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
        #[serde(default)]
        shadows: bool,
    },
}

impl LightSpec {
    /// Whether the light says it casts shadows.
    pub(super) fn casts(&self) -> bool {
        match *self {
            LightSpec::Directional { shadows, .. }
            | LightSpec::Point { shadows, .. }
            | LightSpec::Spot { shadows, .. } => shadows,
        }
    }
}

/// The `[shadows]` table: how every casting light's map is made and read (defaults: those
/// of `ShadowParams`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ShadowsSpec {
    /// Texels a side (each cube face for point lights).
    pub(super) map_size: Option<u32>,
    /// hard | pcf3 | pcf5 | poisson | pcss.
    pub(super) filter: Option<String>,
    /// Constant, slope-scaled and normal-offset bias, in texels.
    pub(super) bias: Option<f32>,
    pub(super) slope_bias: Option<f32>,
    pub(super) normal_offset: Option<f32>,
    /// PCSS: directional lights' angular diameter (degrees), point and spot lights' radius.
    pub(super) light_angle: Option<f32>,
    pub(super) light_radius: Option<f32>,
}

fn outer() -> f32 {
    45.0
}

/// A `[materials.NAME]` table.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct MaterialSpec {
    /// "phong" (default) or "pbr" (glTF metallic-roughness).
    pub(super) model: Option<String>,
    pub(super) base_color: Option<[f32; 4]>,
    pub(super) ambient: Option<f32>,
    pub(super) diffuse: Option<f32>,
    pub(super) specular: Option<f32>,
    pub(super) shininess: Option<f32>,
    pub(super) emissive: Option<[f32; 3]>,
    pub(super) metallic: Option<f32>,
    /// Metallic-roughness: the GGX roughness (default 1). Phong: how blurred the reflected
    /// and refracted environment is (default 0, a mirror).
    pub(super) roughness: Option<f32>,
    /// K_R: the reflected environment (Phong).
    pub(super) reflection: Option<f32>,
    /// K_T (Phong) or the transmission factor (pbr).
    pub(super) transmission: Option<f32>,
    /// Index of refraction (default 1.5).
    pub(super) ior: Option<f32>,
    #[serde(default)]
    pub(super) unlit: bool,
    #[serde(default)]
    pub(super) double_sided: bool,
    /// "none" (default), "back" or "front": the faces culled unless `--cull` says.
    pub(super) cull: Option<String>,
    /// "opaque", "mask" or "blend".
    pub(super) alpha_mode: Option<String>,
    pub(super) alpha_cutoff: Option<f32>,
    pub(super) base_color_texture: Option<TextureSpec>,
    /// A virtual texture as the base-colour texture (instead of `base_color_texture`).
    pub(super) virtual_texture: Option<VirtualTextureSpec>,
    #[serde(default)]
    pub(super) maps: MapsSpec,
    /// A solid (procedural) texture multiplying the base colour.
    pub(super) procedural: Option<ProceduralSpec>,
    /// An image whose coordinates a projection generates per pixel, multiplying the base colour.
    pub(super) projected: Option<ProjectedSpec>,
    /// A 3D texture (baked from a pattern, or a volume file) as a solid texture.
    pub(super) solid_texture: Option<SolidTextureSpec>,
    /// A solid texture on the roughness channel.
    pub(super) roughness_procedural: Option<RoughnessProceduralSpec>,
    /// A solid texture on the bump (height) channel.
    pub(super) bump_procedural: Option<BumpProceduralSpec>,
    /// Texture layers with OpenGL's texture-environment modes (`layers.rs`).
    #[serde(default)]
    pub(super) layers: Vec<super::layers::LayerSpec>,
    /// A light map: baked irradiance multiplying the diffuse factor.
    pub(super) light_map: Option<TextureSpec>,
    /// Toon shading: a ramp, an outline.
    pub(super) toon: Option<super::layers::ToonSpec>,
    /// Parallax mapping from a height map.
    pub(super) parallax: Option<super::relief::ParallaxSpec>,
    /// Displacement mapping from a height map.
    pub(super) displacement: Option<super::relief::DisplacementSpec>,
}

/// `roughness_procedural`: a solid texture on the roughness channel.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RoughnessProceduralSpec {
    pub(super) pattern: String,
    /// Roughness at pattern values 0 and 1 (default [0.2, 0.8]).
    #[serde(default = "roughness_range")]
    pub(super) range: [f32; 2],
    #[serde(default = "yes")]
    pub(super) antialias: bool,
}

fn roughness_range() -> [f32; 2] {
    [0.2, 0.8]
}

/// `bump_procedural`: a solid texture on the bump (height) channel.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BumpProceduralSpec {
    pub(super) pattern: String,
    /// Height of pattern value 1, in object units (default 0.01).
    #[serde(default = "bump_scale")]
    pub(super) scale: f32,
    #[serde(default = "yes")]
    pub(super) antialias: bool,
}

fn bump_scale() -> f32 {
    0.01
}

/// `procedural`: a solid texture multiplying the base colour.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ProceduralSpec {
    /// marble | wood | granite | clouds | checker3d | bricks.
    pub(super) pattern: String,
    /// Linear RGB for pattern values 0 and 1 (default: the pattern's own).
    pub(super) colors: Option<[[f32; 3]; 2]>,
    /// Box-filter the pattern over the pixel footprint (default true).
    #[serde(default = "yes")]
    pub(super) antialias: bool,
}

/// `projected`: an image read through a mapping generated per pixel.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ProjectedSpec {
    /// planar-x | planar-y | planar-z | cylindrical | spherical | cube | bounding-sphere.
    pub(super) projection: String,
    /// Centre for bounding-sphere, in object space (default: the mesh's bounding-box centre).
    pub(super) center: Option<[f32; 3]>,
    pub(super) texture: TextureSpec,
}

/// A 3D texture over an object-space box: baked from a pattern or read from a volume file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SolidTextureSpec {
    /// A pattern to bake (marble | wood | granite | clouds | checker3d | bricks) …
    pub(super) bake: Option<String>,
    /// … at this many voxels a side (default 64) …
    pub(super) size: Option<u32>,
    /// … or a volume file (.nii, .nii.gz, .nrrd, .nhdr; relative to the scene file), its value
    /// range mapped to 0..1.
    pub(super) file: Option<PathBuf>,
    /// The object-space box the texture fills (default [-1, -1, -1] to [1, 1, 1]).
    #[serde(default = "minus_one")]
    pub(super) min: [f32; 3],
    #[serde(default = "plus_one")]
    pub(super) max: [f32; 3],
    /// Linear RGB for values 0 and 1 (default: the pattern's own, else black and white).
    pub(super) colors: Option<[[f32; 3]; 2]>,
    /// nearest | bilinear | trilinear (default trilinear: mipmapped).
    pub(super) filter: Option<String>,
    /// repeat | mirror | clamp | border | mirror-clamp (default repeat).
    pub(super) wrap: Option<String>,
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

/// `[materials.NAME.maps]`: a texture table per channel beyond the base colour.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct MapsSpec {
    pub(super) metallic_roughness: Option<TextureSpec>,
    pub(super) normal: Option<TextureSpec>,
    /// An object-space normal map.
    pub(super) normal_object: Option<TextureSpec>,
    pub(super) occlusion: Option<TextureSpec>,
    pub(super) emissive: Option<TextureSpec>,
    pub(super) ambient: Option<TextureSpec>,
    pub(super) specular: Option<TextureSpec>,
    pub(super) shininess: Option<TextureSpec>,
    pub(super) alpha: Option<TextureSpec>,
    pub(super) bump: Option<TextureSpec>,
    pub(super) transmission: Option<TextureSpec>,
}

/// A texture table (every channel alike): the image, how it is sampled, which coordinates.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TextureSpec {
    /// An image file (relative to the scene file).
    pub(super) file: PathBuf,
    /// nearest | bilinear | trilinear | anisoN | ewa | ewa-exact | sat (default trilinear).
    pub(super) filter: Option<String>,
    /// repeat | mirror | clamp | border | mirror-clamp, both axes.
    pub(super) wrap: Option<String>,
    pub(super) wrap_u: Option<String>,
    pub(super) wrap_v: Option<String>,
    /// "srgb" or "linear" (default: sRGB for colour channels, linear for data).
    pub(super) color_space: Option<String>,
    #[serde(default)]
    pub(super) transform: Option<TransformSpec>,
    #[serde(default = "one")]
    pub(super) uv_scale: f32,
    /// 0 or 1 (default 0; a light map's default is 1).
    pub(super) tex_coord: Option<u32>,
    #[serde(default)]
    pub(super) lod_bias: f32,
    /// Clamps of the level of detail, after `lod_bias` (default: none); min ≤ max.
    pub(super) min_lod: Option<f32>,
    pub(super) max_lod: Option<f32>,
    /// Linear RGBA, straight alpha: the colour outside the image with `wrap = "border"`
    /// (default transparent black).
    pub(super) border: Option<[f32; 4]>,
    /// Normal scale, occlusion strength or bump multiplier.
    #[serde(default = "one")]
    pub(super) scale: f32,
    /// How the image is held in memory: decoded | native | compressed (default: the
    /// load's, `--texture-storage`).
    pub(super) storage: Option<String>,
}

/// A `virtual_texture` table: a texture too large to hold, read a page at a time.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct VirtualTextureSpec {
    /// The source: "quadtree" (the procedural pattern).
    pub(super) pattern: String,
    /// Texels on a side: a power of two from 128 to 131072.
    pub(super) size: u32,
    /// Chooses the pattern's colours (default 1).
    #[serde(default = "seed_one")]
    pub(super) seed: u64,
    /// An OpenGL filter or anisoN (default trilinear).
    pub(super) filter: Option<String>,
    /// repeat | clamp, both axes (default repeat).
    pub(super) wrap: Option<String>,
    #[serde(default = "one")]
    pub(super) uv_scale: f32,
    #[serde(default)]
    pub(super) lod_bias: f32,
    /// The resident page cache in MiB (default 64; `--vt-budget` replaces it).
    pub(super) budget_mib: Option<f64>,
    /// Hold the whole texture as an ordinary one instead (sides up to 4096): the same
    /// texels read without pages, for comparisons.
    #[serde(default)]
    pub(super) resident: bool,
}

fn seed_one() -> u64 {
    1
}

/// A texture table's `transform`, in `KHR_texture_transform`'s order.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TransformSpec {
    #[serde(default)]
    pub(super) offset: [f32; 2],
    /// Degrees.
    #[serde(default)]
    pub(super) rotation: f32,
    #[serde(default = "unit2")]
    pub(super) scale: [f32; 2],
}

fn unit2() -> [f32; 2] {
    [1.0, 1.0]
}

/// A `[[meshes]]` entry: a model file or a built-in primitive, placed in the world.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MeshSpec {
    /// A model file (.gltf, .glb, .obj), relative to the scene file.
    pub(super) file: Option<PathBuf>,
    /// A glTF file's material variant (`KHR_materials_variants`); the command line's
    /// `--variant` when absent.
    pub(super) variant: Option<String>,
    /// plane | cube | sphere | cylinder | cone | torus.
    pub(super) primitive: Option<String>,
    /// A material name from `[materials]`; for files it replaces the file's materials.
    pub(super) material: Option<String>,
    /// Primitive sizes (defaults: 1).
    pub(super) size: Option<f32>,
    pub(super) width: Option<f32>,
    pub(super) depth: Option<f32>,
    pub(super) radius: Option<f32>,
    pub(super) height: Option<f32>,
    pub(super) major_radius: Option<f32>,
    pub(super) minor_radius: Option<f32>,
    pub(super) segments: Option<u32>,
    pub(super) rings: Option<u32>,
    pub(super) divisions: Option<u32>,
    /// Object → world: scale, then rotate (degrees about x, y, z), then translate; or a
    /// column-major 4×4 `matrix` (glTF's order).
    pub(super) translate: Option<[f32; 3]>,
    pub(super) rotate: Option<[f32; 3]>,
    pub(super) scale: Option<ScaleSpec>,
    pub(super) matrix: Option<[f32; 16]>,
    /// Texture coordinates generated per vertex by a projection (replacing the mesh's own).
    pub(super) texgen: Option<TexgenSpec>,
}

/// `texgen = { projection = "spherical", set = 0, center = [0, 0, 0] }` on a mesh.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TexgenSpec {
    /// planar-x | planar-y | planar-z | cylindrical | spherical | cube | bounding-sphere.
    pub(super) projection: String,
    /// The uv set written: 0 (default) or 1; a channel reads it with its `tex_coord`.
    #[serde(default)]
    pub(super) set: u32,
    /// Bounding-sphere centre in object space (default: the mesh's bounding-box centre).
    pub(super) center: Option<[f32; 3]>,
}

/// `scale = 2` (uniform) or `scale = [x, y, z]`.
#[derive(Deserialize)]
#[serde(untagged)]
pub(super) enum ScaleSpec {
    Uniform(f32),
    Axes([f32; 3]),
}

/// A `[[volumes]]` entry: a scan, its placement, its transfer function and how it is drawn.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct VolumeSpec {
    /// `.nii`, `.nii.gz`, `.nrrd`, `.nhdr`, or a raw file described by `dims` and the keys
    /// after it (relative to the scene file).
    pub(super) file: PathBuf,
    /// Raw files: grid size, voxel type (default u8), spacing (default 1), byte order
    /// (default little) and bytes to skip before the voxels (default 0).
    pub(super) dims: Option<[u32; 3]>,
    pub(super) dtype: Option<String>,
    pub(super) spacing: Option<[f32; 3]>,
    pub(super) endian: Option<String>,
    pub(super) header_bytes: Option<u64>,
    /// Place the grid by its spacing alone, as `vtk_volume.py` does.
    #[serde(default)]
    pub(super) ignore_orientation: bool,
    /// World from the file's placement: scale, rotate (degrees about x, y, z), translate;
    /// or a column-major 4×4 `matrix`.
    pub(super) translate: Option<[f32; 3]>,
    pub(super) rotate: Option<[f32; 3]>,
    pub(super) scale: Option<ScaleSpec>,
    pub(super) matrix: Option<[f32; 16]>,
    /// A preset, `value:r,g,b,a;…` points, or a file of points (default `synth`).
    pub(super) tf: Option<String>,
    /// composite | mip | iso | xray.
    pub(super) mode: Option<String>,
    pub(super) iso: Option<f32>,
    /// Sample distance in world units (default 0.5).
    pub(super) step: Option<f32>,
    /// A crop box in voxel coordinates: x0, x1, y0, y1, z0, z1.
    pub(super) crop: Option<[f32; 6]>,
    #[serde(default)]
    pub(super) shade: bool,
    /// raymarch | slices.
    pub(super) method: Option<String>,
    /// post | pre | preint.
    pub(super) classification: Option<String>,
    /// `g:factor;…`.
    pub(super) gradient_opacity: Option<String>,
    #[serde(default = "yes")]
    pub(super) jitter: bool,
    #[serde(default = "yes")]
    pub(super) empty_space_skipping: bool,
    /// A scan drawn as its surface: inside is value ≥ threshold; its exact distance field is
    /// built (method `surface` unless given).
    pub(super) threshold: Option<f64>,
    /// `file` a mesh (.obj, .gltf, .glb): voxels along the largest side of its distance
    /// field (default 128).
    pub(super) sdf_res: Option<u32>,
    /// A distance field's surface: solid pattern, its two colours, bump strength and
    /// frequency, plain colour.
    pub(super) solid: Option<String>,
    pub(super) solid_colors: Option<[[f32; 3]; 2]>,
    pub(super) bump: Option<f32>,
    pub(super) bump_frequency: Option<f32>,
    pub(super) color: Option<[f32; 3]>,
    /// A hypertexture around a distance field's surface: `preset` and any parameter
    /// (method `hypertexture` unless given).
    pub(super) hypertexture: Option<toml::Table>,
}
