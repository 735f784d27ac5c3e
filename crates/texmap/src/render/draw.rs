//! Per-draw compilation: a mesh, its material and the settings become a [`DrawInfo`] — which
//! lighting path the fragments take, the varying layout, every texture read resolved (sampler
//! with the user's overrides, uv transform folded into one affine map), the surface template
//! each lit pixel starts from, and whether the draw can take the plain path.
//!
//! Everything decided here is decided once per draw, so the per-pixel code branches only on
//! what the draw has (`Option`s), never on the material again.

use glam::{Mat3, Mat4, Vec3, Vec4};

use super::environment::EnvDraw;
use super::layers::LayerRead;
use super::maps::{MapRead, SharedReads};
use super::parallax::ParallaxRead;
use super::reads::Read;
use super::settings::{Settings, ShadingMode, Visibility};
use super::varyings::VaryingLayout;
use crate::geometry::Projection;
use crate::pipeline::{CullMode, DrawState};
use crate::scene::Mesh;
use crate::shading::lanes::{phong_quad, splat3, QuadFactors};
use crate::shading::{
    AlphaMode, Lighting, MapChannel, Material, Procedural, ShadingModel, SolidMap, Surface,
    TextureSlot, Viewer,
};
use crate::texture::Sampler;

/// Where a draw's lighting is evaluated, and so what its varyings carry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum LightingPath {
    /// No lighting: colour = base colour × texture × vertex colour.
    Unlit,
    /// Per pixel (Phong shading): the normal (and the position when needed) are interpolated.
    PerPixel,
    /// The factors D and S are interpolated: lit per vertex (Gouraud) or per face (flat).
    Interpolated,
}

/// A solid texture on the roughness or bump channel, resolved for a draw.
#[derive(Clone, Copy)]
pub(super) struct SolidRead<'a> {
    pub map: &'a SolidMap,
    /// Roughness: value 0 and value 1.
    pub range: [f32; 2],
    /// Bump: object-space gradient of the value → world-space gradient of the height
    /// (normal matrix × the transform's mean scale × the bump scale).
    pub world_from_gradient: Mat3,
}

/// The reads of glTF's extension maps ([`crate::shading::lobes`]), each `None` when the
/// draw has none.
#[derive(Clone, Copy, Default)]
pub(super) struct LobeMaps<'a> {
    pub specular_weight: Option<MapRead<'a>>,
    pub specular_color: Option<MapRead<'a>>,
    pub clearcoat: Option<MapRead<'a>>,
    pub clearcoat_roughness: Option<MapRead<'a>>,
    /// Read only with mesh tangents, as the base normal map.
    pub clearcoat_normal: Option<MapRead<'a>>,
    pub sheen_color: Option<MapRead<'a>>,
    pub sheen_roughness: Option<MapRead<'a>>,
    pub thickness: Option<MapRead<'a>>,
}

impl LobeMaps<'_> {
    /// True when the draw reads any of them.
    pub fn any(&self) -> bool {
        self.count() > 0
    }

    /// How many the draw reads.
    pub fn count(&self) -> u32 {
        [
            &self.specular_weight,
            &self.specular_color,
            &self.clearcoat,
            &self.clearcoat_roughness,
            &self.clearcoat_normal,
            &self.sheen_color,
            &self.sheen_roughness,
            &self.thickness,
        ]
        .iter()
        .filter(|m| m.is_some())
        .count() as u32
    }
}

/// Per-draw shading data.
pub(super) struct DrawInfo<'a> {
    pub material: &'a Material,
    pub path: LightingPath,
    pub model: ShadingModel,
    pub layout: VaryingLayout,
    /// The material's parameters without maps; each lit pixel starts from a copy.
    pub surface: Surface,
    /// Some map, solid texture or the metallic-roughness model changes the surface per pixel
    /// (or, in Gouraud and flat shading, an occlusion or emissive map adjusts the factors);
    /// false keeps the plain Lambert/Phong pixel free of their checks.
    pub surface_maps: bool,
    /// What occlusion removes from D in Gouraud and flat shading (per unit of 1 − O): the
    /// ambient part of D, K_A·I_AL (times 1 − metallic for metallic-roughness, whose Fresnel
    /// share of a few percent is left in).
    pub ambient_d: Vec3,
    /// Lit once per face (un-indexed vertices).
    pub flat: bool,
    /// Straight-alpha base colour, premultiplied.
    pub base: Vec4,
    pub texture: Option<MapRead<'a>>,
    /// Tangent-space normal map (Phong shading with mesh tangents only).
    pub normal_map: Option<MapRead<'a>>,
    /// Object-space normal map (Phong shading), and the normal matrix taking its normals to
    /// world space.
    pub normal_object_map: Option<MapRead<'a>>,
    pub normal_from_object: Mat3,
    /// Parallax mapping (Phong shading): every map read at the shifted uv.
    pub parallax: Option<ParallaxRead<'a>>,
    /// Ambient occlusion: scales the ambient term by 1 + strength·(R − 1).
    pub occlusion_map: Option<MapRead<'a>>,
    /// Emissive colour map: multiplies the material's emissive factor.
    pub emissive_map: Option<MapRead<'a>>,
    /// Metallic (B) and roughness (G), multiplying the factors (metallic-roughness materials,
    /// Phong shading).
    pub metal_rough_map: Option<MapRead<'a>>,
    /// Height map (Phong shading); its scale includes the transform's mean scale, so heights
    /// are in object units.
    pub bump_map: Option<MapRead<'a>>,
    /// OBJ `map_Ka`, `map_Ks`, `map_Ns` (Phong shading): the ambient term's colour, the
    /// specular tint, and a factor on the exponent.
    pub ambient_map: Option<MapRead<'a>>,
    pub specular_map: Option<MapRead<'a>>,
    pub shininess_map: Option<MapRead<'a>>,
    /// glTF's extension maps (metallic-roughness materials, Phong shading): specular weight
    /// and colour, clearcoat, its roughness and normal, sheen colour and roughness,
    /// thickness — each its own read (uv set, transform, footprint).
    pub lobe_maps: LobeMaps<'a>,
    /// OBJ `map_d`: opacity multiplying alpha (every mode), from the image's alpha channel
    /// when it has one, else from red (`alpha_from_w`).
    pub alpha_map: Option<MapRead<'a>>,
    pub alpha_from_w: bool,
    /// Solid textures on the roughness and bump channels (Phong shading).
    pub solid_roughness: Option<SolidRead<'a>>,
    pub solid_bump: Option<SolidRead<'a>>,
    /// The projected texture's read, with the command line's overrides applied.
    pub projected: Option<MapRead<'a>>,
    /// The projection, with an unset bounding-sphere centre resolved to the mesh's box centre.
    pub projection: Option<Projection>,
    /// A 3D solid texture's sampler, with the command line's overrides applied.
    pub sampler_3d: Option<Sampler>,
    pub mirrored: bool,
    /// An opaque draw whose colour is the base colour (times its texture) and whose lighting
    /// is the material's own, with no map, vertex colour or procedural texture: its quads take
    /// the plain path, the four pixels in lanes with no per-pixel branch.
    pub plain: bool,
    /// A per-pixel metallic-roughness draw with no coat or sheen, no extension maps and none
    /// of bump, object-space normal, parallax or solid maps, nor toon shading: its quads are
    /// lit in lanes (`mr_quad.rs`) unless the environment or projectors light it.
    pub mr_lanes: bool,
    /// Which of [`DrawInfo::shared_candidates`] are read together, at one set of
    /// coordinates, and the images they read (`maps::SharedReads`).
    pub shared: Option<SharedReads<'a>>,
    /// The occlusion map reads the metallic-roughness map's image the same way, apart from
    /// the shared reads (`MapRead::reads_same`): it takes that read's values.
    pub occlusion_from_mr: bool,
    /// The environment's terms, when the frame has an environment and the material takes
    /// them (`environment.rs`).
    pub env: Option<EnvDraw<'a>>,
    /// Texture layers, in order (`layers.rs`).
    pub layers: Vec<LayerRead<'a>>,
    /// The light map (any lighting path, unlit included), multiplying D.
    pub light_map: Option<MapRead<'a>>,
    /// The frame's projectors light this draw (`projectors.rs`): its position (and, in
    /// Gouraud shading, its normal) are interpolated for them.
    pub projectors: bool,
    /// A plain per-pixel draw lit the same at every pixel (one normal at every vertex, no
    /// specular, only directional lights, no shadows): its factors D and S for front and
    /// back faces, lit once here instead of per quad (`None`: lit per pixel).
    pub uniform_factors: Option<[QuadFactors; 2]>,
}

/// The factors of `surface` (front, back) when every vertex of `mesh` has the same normal,
/// lit by `lighting` (directional lights only, no shadows, no specular: the caller checks),
/// computed as [`phong_quad`] lights a quad whose interpolated normals are that normal.
fn uniform_factors(
    mesh: &Mesh,
    normal_from_object: Mat3,
    surface: &Surface,
    lighting: &Lighting,
) -> Option<[QuadFactors; 2]> {
    let first = *mesh.normals.first()?;
    let same = |n: &Vec3| n.to_array().map(f32::to_bits) == first.to_array().map(f32::to_bits);
    if !mesh.normals.iter().all(same) {
        return None;
    }
    let n = world_normal(normal_from_object, first);
    // Without specular the viewer is not read.
    let viewer = Viewer::Direction(Vec3::Z);
    let lit = |n: Vec3| phong_quad(surface, splat3(n), None, lighting, viewer);
    Some([lit(n), lit(-n)])
}

/// Object-space normal `n` in world space, unit (zero stays zero): what the vertex stage
/// interpolates.
pub(super) fn world_normal(normal_from_object: Mat3, n: Vec3) -> Vec3 {
    (normal_from_object * n).normalize_or_zero()
}

/// The normal matrix (inverse transpose) of `m`'s upper 3×3; `m`'s own for a singular one.
pub(super) fn normal_matrix(m: Mat4) -> Mat3 {
    let m3 = Mat3::from_mat4(m);
    let det = m3.determinant();
    if det.abs() > f32::MIN_POSITIVE && det.is_finite() {
        m3.inverse().transpose()
    } else {
        m3
    }
}

impl<'a> DrawInfo<'a> {
    /// Compiles `mesh` drawn with `material`; `uv_scale` multiplies every texture's
    /// coordinates (the scene's own scale).
    pub fn new(
        mesh: &Mesh,
        material: &'a Material,
        settings: &Settings,
        lighting: &Lighting,
        uv_scale: f32,
    ) -> Self {
        let has_normals = !mesh.normals.is_empty() && mesh.normals.len() == mesh.positions.len();
        let path = if settings.unlit || material.unlit {
            LightingPath::Unlit
        } else if (settings.shading == ShadingMode::Phong || material.toon.is_some()) && has_normals
        {
            // Toon shading is per pixel whatever the shading mode (its ramp is not linear).
            LightingPath::PerPixel
        } else {
            LightingPath::Interpolated
        };
        let flat = path == LightingPath::Interpolated
            && (settings.shading == ShadingMode::Flat || !has_normals);
        let model = material.model;
        let pbr = model == ShadingModel::MetallicRoughness;
        let per_pixel = path == LightingPath::PerPixel;
        let has_bump = material.map(MapChannel::Bump).is_some() || material.parallax.is_some();
        // Shadow lookups read the position too.
        let needs_position = per_pixel
            && (material.specular > 0.0
                || pbr
                || has_bump
                || lighting.needs_position()
                || lighting.shadows.is_some()
                || material.toon.is_some());

        // The varyings, in this order: uv 0, the lighting path's values (the per-pixel
        // normal aside), vertex colour, back factors, object point, uv 1, tangent, and last
        // the per-pixel normal (so a draw lit once can drop it: `with_uniform_lighting`).
        let mut layout = VaryingLayout::default();
        match path {
            LightingPath::Unlit => {}
            LightingPath::PerPixel if needs_position => layout.position = Some(layout.add()),
            LightingPath::PerPixel => {}
            LightingPath::Interpolated => layout.factors = Some(layout.add_factors()),
        }
        if !mesh.colors.is_empty() && mesh.colors.len() == mesh.positions.len() {
            layout.color = Some(layout.add());
        }
        if path == LightingPath::Interpolated && !flat && material.double_sided {
            layout.back_factors = Some(layout.add_factors());
        }
        let solid_maps = per_pixel && !material.solid_maps.is_empty();
        if material.procedural.is_some() || solid_maps {
            layout.object_position = Some(layout.add());
            layout.object_normal = Some(layout.add());
        }
        let uses_set1 = material
            .base_color_texture
            .iter()
            .map(|t| t.tex_coord)
            .chain(material.maps.iter().map(|m| m.slot.tex_coord))
            .chain(material.layers.iter().map(|l| l.slot.tex_coord))
            .any(|c| c == 1);
        if mesh.uvs1.len() == mesh.positions.len() && uses_set1 {
            layout.uv1 = Some(layout.add());
        }
        let has_tangents = mesh.tangents.len() == mesh.positions.len();
        if per_pixel
            && has_tangents
            && (material.map(MapChannel::Normal).is_some()
                || (pbr && material.map(MapChannel::ClearcoatNormal).is_some()))
        {
            layout.tangent = Some(layout.add());
        }
        if per_pixel {
            layout.normal = Some(layout.add());
        }

        let overrides = &settings.textures;
        let read = |slot: &'a TextureSlot, scale: f32| {
            MapRead::new(
                slot,
                overrides.apply(slot.sampler),
                layout.uv_set(slot.tex_coord),
                uv_scale,
                scale,
            )
        };
        let texture = material
            .base_color_texture
            .as_ref()
            .map(|slot| read(slot, 1.0));
        let map = |c: MapChannel| material.map(c).map(|m| read(&m.slot, m.scale));
        let normal_map = layout.tangent.and(map(MapChannel::Normal));
        let lit = path != LightingPath::Unlit;
        let occlusion_map = map(MapChannel::Occlusion).filter(|_| lit);
        let emissive_map = map(MapChannel::Emissive).filter(|_| lit);
        let world_from_object = Mat3::from_mat4(mesh.world_from_object);
        // Heights are in object units: scaled by the transform's mean scale (exact for
        // similarity transforms).
        let mean_scale = world_from_object.determinant().abs().cbrt();
        let mean_scale = if mean_scale.is_finite() && mean_scale > 0.0 {
            mean_scale
        } else {
            1.0
        };
        let metal_rough_map = (per_pixel && pbr)
            .then(|| map(MapChannel::MetallicRoughness))
            .flatten();
        let phong_map = |c: MapChannel| (per_pixel && !pbr).then(|| map(c)).flatten();
        let (ambient_map, specular_map, shininess_map) = (
            phong_map(MapChannel::Ambient),
            phong_map(MapChannel::Specular),
            phong_map(MapChannel::Shininess),
        );
        let lobe_map = |c: MapChannel| (per_pixel && pbr).then(|| map(c)).flatten();
        let lobe_maps = LobeMaps {
            specular_weight: lobe_map(MapChannel::SpecularWeight),
            specular_color: lobe_map(MapChannel::SpecularColor),
            clearcoat: lobe_map(MapChannel::Clearcoat),
            clearcoat_roughness: lobe_map(MapChannel::ClearcoatRoughness),
            clearcoat_normal: layout
                .tangent
                .and_then(|_| lobe_map(MapChannel::ClearcoatNormal)),
            sheen_color: lobe_map(MapChannel::SheenColor),
            sheen_roughness: lobe_map(MapChannel::SheenRoughness),
            thickness: lobe_map(MapChannel::Thickness),
        };
        let alpha_map = map(MapChannel::Alpha);
        let light_map = map(MapChannel::Light);
        let layers: Vec<LayerRead> = material
            .layers
            .iter()
            .map(|layer| LayerRead {
                read: read(&layer.slot, 1.0),
                layer,
            })
            .collect();
        let toon = per_pixel && material.toon.is_some();
        let alpha_from_w = alpha_map.is_some_and(|m| m.tex.format().has_alpha());
        let bump_map = if per_pixel {
            material
                .map(MapChannel::Bump)
                .map(|m| read(&m.slot, m.scale * mean_scale))
        } else {
            None
        };
        let normal_from_object = normal_matrix(mesh.world_from_object);
        let normal_object_map = per_pixel.then(|| map(MapChannel::NormalObject)).flatten();
        let parallax = material
            .parallax
            .as_deref()
            .filter(|_| per_pixel)
            .map(|p| ParallaxRead::new(p, read(&p.slot, p.scale * mean_scale)));
        let solid_roughness =
            material
                .solid_roughness()
                .filter(|_| per_pixel)
                .map(|(map, range)| SolidRead {
                    map,
                    range,
                    world_from_gradient: Mat3::IDENTITY,
                });
        let solid_bump = material
            .solid_bump()
            .filter(|_| per_pixel)
            .map(|(map, scale)| SolidRead {
                map,
                range: [0.0, 1.0],
                world_from_gradient: normal_from_object * (mean_scale * scale),
            });
        let (projected, projection, sampler_3d) = match &material.procedural {
            Some(Procedural::Projected { slot, projection }) => {
                let projection = match *projection {
                    Projection::BoundingSphere { center } if !center.is_finite() => {
                        Projection::BoundingSphere {
                            center: mesh.object_center(),
                        }
                    }
                    p => p,
                };
                (Some(read(slot, 1.0)), Some(projection), None)
            }
            Some(Procedural::Texture3D { sampler, .. }) => {
                (None, None, Some(overrides.apply(*sampler)))
            }
            _ => (None, None, None),
        };
        let b = material.base_color;
        let ambient_d = lighting.ambient
            * material.ambient
            * if pbr {
                1.0 - material.metallic.clamp(0.0, 1.0)
            } else {
                1.0
            };
        let surface_maps = occlusion_map.is_some()
            || emissive_map.is_some()
            || (per_pixel
                && (pbr
                    || ambient_map.is_some()
                    || specular_map.is_some()
                    || shininess_map.is_some()
                    || normal_map.is_some()
                    || normal_object_map.is_some()
                    || parallax.is_some()
                    || bump_map.is_some()
                    || solid_roughness.is_some()
                    || solid_bump.is_some()
                    || toon));
        let mr_lanes = per_pixel
            && pbr
            && !toon
            && !material.lobes.layered()
            && !lobe_maps.any()
            && normal_object_map.is_none()
            && bump_map.is_none()
            && parallax.is_none()
            && solid_roughness.is_none()
            && solid_bump.is_none();
        let mut surface = Surface::new(material, Vec3::ZERO, Vec3::ZERO);
        // KHR_materials_volume's thickness is in the mesh's object units.
        surface.lobes.thickness *= mean_scale;
        let mut draw = DrawInfo {
            material,
            path,
            model,
            layout,
            surface,
            surface_maps,
            ambient_d,
            flat,
            base: (b.truncate() * b.w).extend(b.w),
            texture,
            normal_map,
            normal_object_map,
            normal_from_object,
            parallax,
            occlusion_map,
            emissive_map,
            metal_rough_map,
            bump_map,
            ambient_map,
            specular_map,
            shininess_map,
            lobe_maps,
            alpha_map,
            alpha_from_w,
            solid_roughness,
            solid_bump,
            projected,
            projection,
            sampler_3d,
            mirrored: world_from_object.determinant() < 0.0,
            plain: !surface_maps
                && alpha_map.is_none()
                && layout.color.is_none()
                && material.procedural.is_none()
                && material.alpha_mode == AlphaMode::Opaque
                && layers.is_empty()
                && light_map.is_none()
                && model == ShadingModel::Phong,
            mr_lanes,
            shared: None,
            occlusion_from_mr: false,
            env: None,
            layers,
            light_map,
            projectors: false,
            uniform_factors: None,
        };
        draw.shared = SharedReads::new(&draw.shared_candidates());
        let shared = draw.shared.as_ref().map_or(0, |s| s.maps);
        draw.occlusion_from_mr = shared & (1 << 2) == 0
            && matches!((&draw.occlusion_map, &draw.metal_rough_map), (Some(o), Some(m)) if o.reads_same(m));
        draw
    }

    /// The draw lit once (`uniform_factors`) when it is plain, lit per pixel without the
    /// position, and every vertex of `mesh` has the same normal: its normal varyings, laid
    /// out last, are dropped (nothing reads them). Called after the decorations that may
    /// take a draw off the plain path (`with_environment`, `with_projectors`).
    #[must_use]
    pub fn with_uniform_lighting(mut self, mesh: &Mesh, lighting: &Lighting) -> Self {
        let per_pixel = self.path == LightingPath::PerPixel;
        if !(self.plain && per_pixel && self.layout.position.is_none()) {
            return self;
        }
        self.uniform_factors =
            uniform_factors(mesh, self.normal_from_object, &self.surface, lighting);
        if self.uniform_factors.is_some() {
            self.layout.drop_last_normal();
        }
        self
    }

    /// The read each of [`DrawInfo::shared_candidates`] makes, in its order (bit `k` of a
    /// [`SharedReads`] feed).
    pub(super) const SHARED_READS: [Read; 5] = [
        Read::Texels,
        Read::Normals,
        Read::Occlusion,
        Read::Emission,
        Read::MetalRough,
    ];

    /// The maps a draw may read together (`shared`): the base colour texture, the
    /// normal, occlusion, emissive and metallic-roughness maps.
    pub(super) fn shared_candidates(&self) -> [Option<&MapRead<'a>>; 5] {
        [
            self.texture.as_ref(),
            self.normal_map.as_ref(),
            self.occlusion_map.as_ref(),
            self.emissive_map.as_ref(),
            self.metal_rough_map.as_ref(),
        ]
    }

    /// The pipeline state of the draw.
    pub fn state(&self, settings: &Settings) -> DrawState {
        let blend = self.material.alpha_mode == AlphaMode::Blend;
        let zbuffer = settings.visibility == Visibility::ZBuffer;
        let reads = [
            &self.texture,
            &self.normal_map,
            &self.normal_object_map,
            &self.occlusion_map,
            &self.emissive_map,
            &self.metal_rough_map,
            &self.ambient_map,
            &self.specular_map,
            &self.shininess_map,
            &self.alpha_map,
            &self.projected,
            &self.light_map,
        ]
        .iter()
        .filter(|m| m.is_some())
        .count() as u32;
        DrawState {
            varyings: self.layout.count,
            cull: if self.material.double_sided {
                CullMode::None
            } else {
                settings.cull.unwrap_or(self.material.cull)
            },
            mirrored: self.mirrored,
            depth_test: zbuffer,
            depth_write: zbuffer && !blend,
            blend,
            // A bump map reads three times (at the pixel and one footprint along x and y).
            texture_reads: reads
                + self.lobe_maps.count()
                + 3 * u32::from(self.bump_map.is_some())
                + u32::from(self.parallax.is_some())
                + u32::from(self.sampler_3d.is_some())
                + u32::from(self.env.is_some())
                + self.layers.len() as u32,
            // Only the alpha test (`combine`) drops a shaded pixel.
            keeps_all: self.material.alpha_mode == AlphaMode::Opaque,
        }
    }
}
