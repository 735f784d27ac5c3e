//! The environment in a frame's draws: which of its terms a draw's material takes
//! ([`EnvDraw`], attached once per draw), the per-pixel path that adds them with the reflected
//! and refracted directions' footprints, and the per-vertex and per-face form for Gouraud and
//! flat shading. The terms themselves are [`crate::shading::ibl`]'s.
//!
//! Footprints: a quad's four pixels each get their surface (after every map) and their
//! reflected direction `R = 2(N·V)N − V` (and refracted `T`); the directions' screen
//! derivatives are the differences across the quad (coarse, like the varyings': pixel 1 − 0
//! along x, 2 − 0 along y), so they carry the normal's and the view vector's change, normal
//! maps included. Gouraud and flat shading read along their vertex's or face's directions
//! with no footprint.

use glam::{Vec3, Vec4};

use super::behind;
use super::draw::{DrawInfo, LightingPath};
use super::fragment::SceneShader;
use super::layers::surface_colors;
use super::maps::MapRead;
use super::parallax::{light_buffer, self_shadowed, SelfShadow};
use super::reads::QuadReads;
use super::settings::Settings;
use crate::pipeline::Quad;
use crate::scene::Scene;
use crate::shading::ibl::{
    environment_terms, environment_terms_with, metallic_roughness_lit, point_rays, reflect,
    refract, EnvLight, EnvMaterial, EnvRays,
};
use crate::shading::{combine, Lighting, MapChannel, ShadingModel, Surface, Viewer};
use crate::texture::CubeFootprint;

/// What one draw takes from the frame's environment.
pub(super) struct EnvDraw<'a> {
    pub light: &'a EnvLight<'a>,
    pub material: EnvMaterial,
    /// The K_T (or transmission factor) map, per pixel in Phong shading.
    pub transmission_map: Option<MapRead<'a>>,
    /// Image-based light replaces the uniform ambient light.
    pub replaces_ambient: bool,
    /// Some pixel reads the refracted direction.
    pub refracts: bool,
}

/// Whether a frame's draws need the prefiltered irradiance, specular and sheen levels:
/// `(diffuse, specular, sheen)`.
pub(super) fn prefilters_needed(scene: &Scene, settings: &Settings) -> (bool, bool, bool) {
    let Some(env) = &scene.environment else {
        return (false, false, false);
    };
    if settings.unlit {
        return (false, false, false);
    }
    let (mut diffuse, mut specular, mut sheen) = (false, false, false);
    for mesh in &scene.meshes {
        let Some(m) = scene.materials.get(mesh.material) else {
            continue;
        };
        if m.unlit {
            continue;
        }
        let transmits = m.transmission > 0.0 || m.map(MapChannel::Transmission).is_some();
        match m.model {
            ShadingModel::MetallicRoughness => {
                diffuse |= env.ibl;
                specular |= env.ibl || (env.reflections && transmits);
                sheen |= env.ibl && m.lobes.sheen_color != glam::Vec3::ZERO;
            }
            ShadingModel::Phong => {
                diffuse |= env.ibl && m.ambient > 0.0;
                specular |=
                    env.reflections && (m.reflection > 0.0 || transmits) && m.roughness > 0.0;
            }
        }
    }
    (diffuse, specular, sheen)
}

/// Computes now the prefiltered forms of `scene`'s environment that frames rendered with
/// `settings` will read (otherwise the first frame does; they are cached in the
/// [`crate::scene::Environment`] either way). Returns whether anything was needed.
pub fn prefilter_environment(scene: &Scene, settings: &Settings) -> bool {
    let Some(env) = &scene.environment else {
        return false;
    };
    let (diffuse, specular, sheen) = prefilters_needed(scene, settings);
    let _ = EnvLight::new(env, diffuse, specular).with_sheen(sheen);
    diffuse || specular || sheen
}

impl<'a> DrawInfo<'a> {
    /// This draw with the environment's terms attached, when its material takes any: image-
    /// based light (every lit material, when on) or a reflection or transmission (when on).
    /// Per-pixel draws then carry the world position (for V) and leave the plain path.
    pub(super) fn with_environment(
        mut self,
        light: Option<&'a EnvLight<'a>>,
        settings: &Settings,
        uv_scale: f32,
    ) -> Self {
        let Some(light) = light else {
            return self;
        };
        let env = light.env;
        let m = self.material;
        if self.path == LightingPath::Unlit {
            return self;
        }
        let kt_map = m.map(MapChannel::Transmission);
        let transmits = env.reflections && (m.transmission > 0.0 || kt_map.is_some());
        let reflects = env.reflections && m.reflection > 0.0 && self.model == ShadingModel::Phong;
        let ambient = env.ibl && (self.model == ShadingModel::MetallicRoughness || m.ambient > 0.0);
        if !(ambient || reflects || transmits) {
            return self;
        }
        let per_pixel = self.path == LightingPath::PerPixel;
        if per_pixel && self.layout.position.is_none() {
            self.layout.position = Some(self.layout.add());
        }
        self.plain = false;
        let transmission_map = kt_map.filter(|_| per_pixel && transmits).map(|map| {
            MapRead::new(
                &map.slot,
                settings.textures.apply(map.slot.sampler),
                self.layout.uv_set(map.slot.tex_coord),
                uv_scale,
                map.scale,
            )
        });
        self.env = Some(EnvDraw {
            light,
            material: EnvMaterial {
                reflection: if reflects { m.reflection } else { 0.0 },
                transmission: if transmits { m.transmission } else { 0.0 },
                phong_roughness: m.roughness,
            },
            transmission_map,
            replaces_ambient: env.ibl,
            refracts: transmits,
        });
        if env.ibl {
            // Gouraud and flat occlusion removes the ambient part of D: the environment's
            // mean light stands for it.
            let mean = light.irradiance(Vec3::Y).max(light.irradiance(-Vec3::Y));
            self.ambient_d = mean
                * if self.model == ShadingModel::MetallicRoughness {
                    1.0 - m.metallic.clamp(0.0, 1.0)
                } else {
                    m.ambient
                };
        }
        self
    }

    /// The lighting the draw's own lights give (the uniform ambient left out when the
    /// environment replaces it).
    #[inline]
    fn env_lighting<'l>(&self, e: &EnvDraw, lighting: &Lighting<'l>) -> Lighting<'l> {
        if e.replaces_ambient {
            Lighting {
                ambient: Vec3::ZERO,
                ..*lighting
            }
        } else {
            *lighting
        }
    }

    /// The factors of a vertex or a face (toon shading for toon materials, as `lit_factors`),
    /// with the environment's terms along its own
    /// directions (no footprint) when the draw takes them.
    #[inline]
    pub(super) fn illuminate_vertex(
        &self,
        s: &Surface,
        lighting: &Lighting,
        viewer: Viewer,
    ) -> (Vec3, Vec3) {
        let Some(e) = &self.env else {
            return self.lit_factors(s, lighting, viewer);
        };
        let (d, sp) = self.lit_factors(s, &self.env_lighting(e, lighting), viewer);
        let (ed, es) = environment_terms(
            self.model,
            s,
            &e.material,
            viewer,
            &point_rays(s, viewer),
            e.light,
        );
        (d + ed, sp + es)
    }
}

impl SceneShader<'_> {
    /// The colours of one quad of a per-pixel draw that takes the environment (module docs).
    pub(super) fn shade_env(
        &self,
        d: &DrawInfo,
        e: &EnvDraw,
        quad: &Quad,
        reads: &QuadReads,
        out: &mut [Vec4; 4],
        self_shadow: Option<&SelfShadow>,
    ) -> u8 {
        let m = d.material;
        let mut kept = quad.mask;
        let back = m.double_sided && !quad.front_facing;
        let lighting = d.env_lighting(e, &self.lighting);
        let one_pass =
            d.model == ShadingModel::MetallicRoughness && m.toon.is_none() && e.replaces_ambient;
        // Parallax self-shadowing, as in the general path.
        let mut light_buf = light_buffer(self_shadow);
        let kt = e.transmission_map.as_ref().map(|t| t.quad(quad));
        // Every pixel's directions, helpers included: they give the derivatives. Helper
        // pixels (outside the triangle) give only their reflected and refracted directions:
        // their normal is all they take from the maps.
        let covered = |j: usize| quad.mask & (1 << j) != 0;
        let all = surface_colors(d, quad, reads);
        let colors: [Vec4; 4] =
            std::array::from_fn(|j| if covered(j) { all[j] } else { Vec4::ZERO });
        // A covered pixel's surface is written in place (a surface is a few hundred bytes:
        // building one then moving it copied it twice more); a helper pixel gets no surface,
        // only its normal and position, for its directions.
        let mut surfaces: [Option<Surface>; 4] = [None; 4];
        let mut reflected = [Vec3::ZERO; 4];
        let mut refracted = [Vec3::ZERO; 4];
        for j in 0..4 {
            let mut normal = d
                .layout
                .normal
                .map_or(d.surface.normal, |n| n.pixel3(quad, j).normalize_or_zero());
            let position = d
                .layout
                .position
                .map_or(d.surface.position, |p| p.pixel3(quad, j));
            let mut ior = d.surface.ior;
            if covered(j) || (reads.surface_maps() && d.solid_bump.is_some()) {
                let s = surfaces[j].insert(d.surface);
                s.normal = normal;
                s.position = position;
                if reads.surface_maps() {
                    d.apply_maps(reads, quad, j, colors[j], s);
                }
                if back {
                    s.normal = -s.normal;
                    s.clearcoat_normal = -s.clearcoat_normal;
                }
                (normal, ior) = (s.normal, s.ior);
            } else {
                if reads.surface_maps() {
                    normal = d.mapped_normal(reads, quad, j, normal);
                }
                if back {
                    normal = -normal;
                }
            }
            let v = self.viewer.towards(position);
            reflected[j] = reflect(normal, v);
            if e.refracts {
                refracted[j] = refract(normal, v, ior);
            }
        }
        // Map-free Phong: the draw's own lights at the four pixels in lanes (the same
        // factors as the per-pixel rule, bit for bit).
        let lanes = (d.model == ShadingModel::Phong
            && m.toon.is_none()
            && !reads.surface_maps()
            && self_shadow.is_none())
        .then(|| self.phong_lanes_with(d, quad, &lighting));
        let footprint = |dirs: &[Vec3; 4], j: usize| CubeFootprint {
            dir: dirs[j],
            ddir_dx: dirs[1] - dirs[0],
            ddir_dy: dirs[2] - dirs[0],
        };
        // The last irradiance read (a flat surface's pixels share it).
        let mut irradiance = None;
        for j in 0..4 {
            if quad.mask & (1 << j) == 0 {
                continue;
            }
            let Some(s) = &surfaces[j] else {
                continue;
            };
            let mut material = e.material;
            if let Some(k) = &kt {
                material.transmission *= k[j].x;
            }
            // The frame's other surfaces behind a transmitting metallic-roughness pixel, at
            // the point its refracted ray leaves it (behind.rs).
            let behind = self
                .behind
                .filter(|_| {
                    d.model == ShadingModel::MetallicRoughness && material.transmission > 0.0
                })
                .map(|b| {
                    let exit = s.position + refracted[j] * s.lobes.thickness;
                    b.read(exit, behind::lod(b.width(), s.roughness, s.ior))
                });
            let rays = EnvRays {
                reflected: footprint(&reflected, j),
                refracted: footprint(&refracted, j),
                behind,
            };
            // Metallic-roughness under image-based light: the lights and the environment
            // share one lobe (the same factors as the two calls below).
            let ((df, sp), (ed, es)) = if one_pass {
                let lit = self_shadowed(self_shadow, lighting, j, &mut light_buf);
                metallic_roughness_lit(s, &material, &lit, self.viewer, &rays, e.light)
            } else {
                let lit = match &lanes {
                    Some(q) => (q.d[j].truncate(), q.s[j].truncate()),
                    None => {
                        let lit = self_shadowed(self_shadow, lighting, j, &mut light_buf);
                        d.lit_factors(s, &lit, self.viewer)
                    }
                };
                let env = environment_terms_with(
                    d.model,
                    s,
                    &material,
                    self.viewer,
                    &rays,
                    e.light,
                    &mut irradiance,
                );
                (lit, env)
            };
            let (pd, ps) = self.projected(d, quad, s);
            let (mut df, sp) = (df + pd, sp + ps);
            if let Some(l) = d.light_factor(reads, j) {
                df *= l;
            }
            match combine(m.alpha_mode, colors[j], df + ed, sp + es) {
                Some(color) => out[j] = color,
                None => kept &= !(1 << j),
            }
        }
        kept
    }
}
