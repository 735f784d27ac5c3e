//! Materials: what a surface is made of — the Phong coefficients and the glTF
//! metallic-roughness factors, the base colour and its texture, procedural colour sources,
//! the other texture maps by channel, solid textures on channels, alpha and sidedness.

use std::sync::Arc;

use glam::{Vec3, Vec4};

use crate::geometry::Projection;
use crate::texture::procedural::Solid;
use crate::texture::{Sampler, Texture2D, Texture3D, TextureTransform, VirtualTexture};

/// A texture bound to a material: the image, how it is read, and the uv transform.
///
/// The uv used for sampling is `transform.apply(uv) · uv_scale`.
#[derive(Clone, Debug)]
pub struct TextureSlot {
    pub texture: Arc<Texture2D>,
    pub sampler: Sampler,
    pub transform: TextureTransform,
    pub uv_scale: f32,
    /// Which texture coordinate set the slot reads: 0 (`Mesh::uvs`) or 1 (`Mesh::uvs1`).
    pub tex_coord: u32,
    /// Set when the slot reads a virtual texture: reads go through its page table, and
    /// `texture` holds its coarsest page-sized level (what readers that know nothing of
    /// pages see).
    pub virtual_texture: Option<Arc<VirtualTexture>>,
}

impl TextureSlot {
    /// A slot with the identity transform and a uv scale of 1.
    #[must_use]
    pub fn new(texture: Arc<Texture2D>, sampler: Sampler) -> Self {
        TextureSlot {
            texture,
            sampler,
            transform: TextureTransform::default(),
            uv_scale: 1.0,
            tex_coord: 0,
            virtual_texture: None,
        }
    }
}

/// A colour computed from the surface point rather than read through the mesh's UVs. It
/// multiplies the base colour (and the base-colour texture, if any), like a texture.
#[derive(Clone, Debug)]
pub enum Procedural {
    /// A solid texture evaluated at the object-space position: the object looks carved from
    /// the block, and the pattern moves with it. With `antialias`, the pattern is box-filtered
    /// over the pixel's footprint (|∂P/∂x| + |∂P/∂y|); without, it is point-sampled.
    Solid {
        solid: Solid,
        /// Linear RGB for pattern values 0 and 1.
        colors: [Vec3; 2],
        antialias: bool,
    },
    /// An image texture whose coordinates a projection generates per pixel from the
    /// object-space position (and normal, for cube faces and cylinder caps), with analytic
    /// derivatives for the footprint — no seam where u wraps. A bounding-sphere projection
    /// whose centre is not finite (NaN) is centred on each mesh's bounding box.
    Projected {
        slot: TextureSlot,
        projection: Projection,
    },
    /// A 3D texture (the texture engine's [`Texture3D`]) as a solid texture: the object-space
    /// box `[min, max]` maps onto the texture's unit cube, `uvw = (P − min)/(max − min)`, read
    /// through `sampler` over the pixel's footprint (∂uvw/∂x, ∂uvw/∂y from the position's
    /// derivatives: trilinear with mip levels, as [`crate::texture::sample_3d`]). The red
    /// channel (a scan's value, a baked pattern) is mapped through `colors` (0 → first,
    /// 1 → second); the ramp is linear, so filtering the values equals filtering the colours.
    Texture3D {
        texture: Arc<Texture3D>,
        sampler: Sampler,
        min: Vec3,
        max: Vec3,
        colors: [Vec3; 2],
    },
}

/// How a material's alpha is used (glTF's `alphaMode`).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum AlphaMode {
    /// Alpha is ignored and written as 1.
    #[default]
    Opaque,
    /// Fragments with alpha below the cutoff are discarded; the others are opaque.
    Mask(f32),
    /// Premultiplied "over" blending, drawn after every opaque surface, back to front.
    Blend,
}

/// Which reflection model lights a material.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ShadingModel {
    /// The Phong model of the module docs: K_A, K_D, K_S and the exponent n.
    #[default]
    Phong,
    /// glTF's metallic-roughness BRDF ([`super::pbr`]): base colour, metallic and roughness (K_A
    /// still scales the ambient term; K_D, K_S and n are not used).
    MetallicRoughness,
}

/// A solid texture feeding a material channel other than the colour, evaluated at the
/// object-space position like [`Procedural::Solid`], with the same footprint filtering.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidMap {
    pub solid: Solid,
    pub channel: SolidChannel,
    /// Filter the pattern (and its gradient) over the pixel's footprint.
    pub antialias: bool,
}

/// What a [`SolidMap`] feeds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SolidChannel {
    /// Roughness = `range[0] + (range[1] − range[0])·value`, replacing the factor. Phong
    /// materials take it as the exponent `n = 2/α² − 2` (α = roughness², at least 1).
    Roughness { range: [f32; 2] },
    /// A height field `scale·value` in object units: the normal is tilted by the pattern's
    /// analytic gradient projected onto the surface.
    Bump { scale: f32 },
}

/// A surface's appearance: Phong coefficients, base colour and its texture.
#[derive(Clone, Debug)]
pub struct Material {
    /// The reflection model (Phong by default; glTF materials are metallic-roughness).
    pub model: ShadingModel,
    /// Linear RGBA, straight (not premultiplied) alpha.
    pub base_color: Vec4,
    pub base_color_texture: Option<TextureSlot>,
    /// K_A: the fraction of the ambient light reflected.
    pub ambient: f32,
    /// K_D: the diffuse reflection coefficient.
    pub diffuse: f32,
    /// K_S: the specular reflection coefficient.
    pub specular: f32,
    /// n: the Phong exponent.
    pub shininess: f32,
    /// I_E: linear light emitted by the surface.
    pub emissive: Vec3,
    /// When true, the colour is the surface colour `C` and lights are ignored.
    pub unlit: bool,
    /// When false, back faces may be culled (see `render::CullMode`); when true their normal
    /// is flipped towards the viewer before lighting.
    pub double_sided: bool,
    /// The faces a single-sided material culls when the render settings leave it to the
    /// scene: back faces for glTF's single-sided materials (its specification's rule), none
    /// by default (OBJ, TOML unless the material's `cull` key says).
    pub cull: crate::pipeline::CullMode,
    pub alpha_mode: AlphaMode,
    /// A procedural colour (solid texture or projected image), multiplying the base colour.
    pub procedural: Option<Procedural>,
    /// glTF's metallic factor (0 = dielectric), for metallic-roughness shading.
    pub metallic: f32,
    /// glTF's roughness factor (α = roughness²).
    pub roughness: f32,
    /// Texture maps other than the base colour (normal, occlusion, emissive, …), each with
    /// its channel and scale. The renderer reads the channels it implements.
    pub maps: Vec<MaterialMap>,
    /// Solid textures on channels other than the colour (roughness, bump height).
    pub solid_maps: Vec<SolidMap>,
    /// K_R: the Phong model's reflected environment `K_R·I_R` (0 = none; see
    /// [`super::ibl`]).
    pub reflection: f32,
    /// K_T: the Phong model's transmitted environment `K_T·I_T`, or glTF's
    /// `KHR_materials_transmission` factor for metallic-roughness materials (0 = opaque).
    pub transmission: f32,
    /// Index of refraction (`KHR_materials_ior`; 1.5, f0 = 0.04): refraction and the
    /// dielectric Fresnel.
    pub ior: f32,
    /// glTF's material extensions over the metallic-roughness model (specular, clearcoat,
    /// sheen, volume: [`super::lobes`]); the default changes nothing.
    pub lobes: super::lobes::Lobes,
    /// Texture layers applied in order after the surface colour, with OpenGL's
    /// texture-environment modes ([`super::layers`]).
    pub layers: Vec<super::layers::TextureLayer>,
    /// Toon shading in place of the reflection model ([`super::toon`]).
    pub toon: Option<super::toon::Toon>,
    /// Parallax mapping from a height map (`super::relief`).
    pub parallax: Option<Box<super::relief::Parallax>>,
    /// Displacement mapping: the meshes tessellated and moved by a height map at load.
    pub displacement: Option<Box<super::relief::Displacement>>,
}

/// What a [`MaterialMap`] feeds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MapChannel {
    /// glTF metallic (B) and roughness (G), linear.
    MetallicRoughness,
    /// Tangent-space normal map, linear; `scale` scales its x and y.
    Normal,
    /// Object-space normal map, linear: `2·rgb − 1` is the object-space normal, taken to
    /// world space by the normal matrix (needs no tangents); `scale` is unused.
    NormalObject,
    /// Ambient occlusion (R), linear; `scale` is the strength.
    Occlusion,
    /// Emissive colour, sRGB; multiplies `Material::emissive`.
    Emissive,
    /// OBJ `map_Ka`: ambient colour, sRGB.
    Ambient,
    /// OBJ `map_Ks`: specular colour, sRGB.
    Specular,
    /// OBJ `map_Ns`: specular exponent (R), linear.
    Shininess,
    /// OBJ `map_d`: opacity (R, or alpha when present), linear.
    Alpha,
    /// OBJ `bump`/`map_bump`: a height field, linear; `scale` is `-bm`.
    Bump,
    /// Transmission (R), linear: multiplies K_T or the transmission factor
    /// (`KHR_materials_transmission`'s texture).
    Transmission,
    /// A light map: baked irradiance (RGB, sRGB-encoded unless the file is float), read on
    /// uv set 1 by default; times `scale` (the intensity), it multiplies the diffuse factor
    /// D (`I = C·D·L + S`), lit or unlit.
    Light,
    /// `KHR_materials_specular`'s `specularTexture` (A), linear: multiplies the factor.
    SpecularWeight,
    /// `specularColorTexture`, sRGB: multiplies the specular colour.
    SpecularColor,
    /// `KHR_materials_clearcoat`'s `clearcoatTexture` (R), linear.
    Clearcoat,
    /// `clearcoatRoughnessTexture` (G), linear.
    ClearcoatRoughness,
    /// `clearcoatNormalTexture`: the coat's tangent-space normal map; `scale` as `Normal`.
    ClearcoatNormal,
    /// `KHR_materials_sheen`'s `sheenColorTexture`, sRGB.
    SheenColor,
    /// `sheenRoughnessTexture` (A), linear.
    SheenRoughness,
    /// `KHR_materials_volume`'s `thicknessTexture` (G), linear.
    Thickness,
}

impl MapChannel {
    /// The lower-case name used in scene files and by `texmap info`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            MapChannel::MetallicRoughness => "metallic_roughness",
            MapChannel::Normal => "normal",
            MapChannel::NormalObject => "normal_object",
            MapChannel::Occlusion => "occlusion",
            MapChannel::Emissive => "emissive",
            MapChannel::Ambient => "ambient",
            MapChannel::Specular => "specular",
            MapChannel::Shininess => "shininess",
            MapChannel::Alpha => "alpha",
            MapChannel::Bump => "bump",
            MapChannel::Transmission => "transmission",
            MapChannel::Light => "light",
            MapChannel::SpecularWeight => "specular_weight",
            MapChannel::SpecularColor => "specular_color",
            MapChannel::Clearcoat => "clearcoat",
            MapChannel::ClearcoatRoughness => "clearcoat_roughness",
            MapChannel::ClearcoatNormal => "clearcoat_normal",
            MapChannel::SheenColor => "sheen_color",
            MapChannel::SheenRoughness => "sheen_roughness",
            MapChannel::Thickness => "thickness",
        }
    }

    /// True for channels that hold colour (decoded from sRGB); the others hold linear data.
    #[must_use]
    pub fn is_color(self) -> bool {
        matches!(
            self,
            MapChannel::Emissive
                | MapChannel::Ambient
                | MapChannel::Specular
                | MapChannel::Light
                | MapChannel::SpecularColor
                | MapChannel::SheenColor
        )
    }
}

/// A texture map of a material other than the base colour.
#[derive(Clone, Debug)]
pub struct MaterialMap {
    pub channel: MapChannel,
    pub slot: TextureSlot,
    /// Normal scale, occlusion strength or bump multiplier (1 otherwise).
    pub scale: f32,
}

impl Material {
    /// The first map feeding `channel`, if any.
    #[must_use]
    pub fn map(&self, channel: MapChannel) -> Option<&MaterialMap> {
        self.maps.iter().find(|m| m.channel == channel)
    }

    /// The first solid texture on the roughness channel and its range, if any.
    #[must_use]
    pub fn solid_roughness(&self) -> Option<(&SolidMap, [f32; 2])> {
        self.solid_maps.iter().find_map(|m| match m.channel {
            SolidChannel::Roughness { range } => Some((m, range)),
            SolidChannel::Bump { .. } => None,
        })
    }

    /// The first solid texture on the bump channel and its scale, if any.
    #[must_use]
    pub fn solid_bump(&self) -> Option<(&SolidMap, f32)> {
        self.solid_maps.iter().find_map(|m| match m.channel {
            SolidChannel::Bump { scale } => Some((m, scale)),
            SolidChannel::Roughness { .. } => None,
        })
    }
}

impl Default for Material {
    /// White, K_A 0.2, K_D 0.8, no specular, opaque, single-sided.
    fn default() -> Self {
        Material {
            base_color: Vec4::ONE,
            base_color_texture: None,
            ambient: 0.2,
            diffuse: 0.8,
            specular: 0.0,
            shininess: 32.0,
            emissive: Vec3::ZERO,
            unlit: false,
            double_sided: false,
            cull: crate::pipeline::CullMode::None,
            alpha_mode: AlphaMode::Opaque,
            procedural: None,
            metallic: 0.0,
            roughness: 1.0,
            maps: Vec::new(),
            solid_maps: Vec::new(),
            model: ShadingModel::Phong,
            reflection: 0.0,
            transmission: 0.0,
            ior: 1.5,
            lobes: super::lobes::Lobes::default(),
            layers: Vec::new(),
            toon: None,
            parallax: None,
            displacement: None,
        }
    }
}
