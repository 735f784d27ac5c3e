//! What a surface takes from the environment: the reflected and refracted directions, the
//! Fresnel blend and each illumination model's environment terms.

use glam::{Mat3, Vec2, Vec3, Vec3A, Vec4};

use super::super::{pbr, Surface, Viewer};
use super::{Environment, FaceSet, MirrorCube, LEVELS};
use crate::texture::{CubeFootprint, CubeFootprintLanes, Filter, Sampler};

/// The environment as one frame reads it: rotation, intensity and the prefiltered forms
/// resolved.
#[derive(Clone, Copy, Debug)]
pub struct EnvLight<'a> {
    pub env: &'a Environment,
    /// World → map directions (the inverse of the map's rotation).
    pub env_from_world: Mat3,
    /// The map is rotated (`env_from_world` is not the identity).
    pub rotated: bool,
    /// `None` unless image-based light is on and some draw needs it.
    pub irradiance: Option<&'a FaceSet>,
    pub specular: Option<&'a [FaceSet]>,
    /// The map as a trilinear cube, beside `specular` (the sharp end of rough reads).
    pub sharp: Option<&'a MirrorCube>,
    /// The Charlie-prefiltered levels, when some draw has a sheen (see
    /// [`EnvLight::with_sheen`]); without them a sheen takes the irradiance.
    pub sheen: Option<&'a [FaceSet]>,
    /// How the map itself is read: the environment's sampler, with any overrides of the
    /// frame laid over it (the wrap modes stay the layout's).
    pub sampler: Sampler,
}

impl<'a> EnvLight<'a> {
    /// `env` for a frame; `diffuse` and `specular` say which prefiltered forms the frame's
    /// draws read (computed now if not cached).
    #[must_use]
    pub fn new(env: &'a Environment, diffuse: bool, specular: bool) -> Self {
        EnvLight {
            env,
            env_from_world: Mat3::from_rotation_y(-env.rotation_deg.to_radians()),
            rotated: env.rotation_deg.rem_euclid(360.0) != 0.0,
            irradiance: diffuse.then(|| env.irradiance()),
            specular: specular.then(|| env.specular_levels()),
            sharp: specular.then(|| env.mirror_cube()),
            sheen: None,
            sampler: env.sampler,
        }
    }

    /// This light with the sheen levels resolved (computed now if not cached) when `on`.
    #[must_use]
    pub fn with_sheen(mut self, on: bool) -> Self {
        self.sheen = on.then(|| self.env.sheen_levels());
        self
    }

    /// A world direction in the map's frame (the identity unless the map is rotated).
    #[inline(always)]
    fn in_map_frame(&self, d: Vec3) -> Vec3 {
        if self.rotated {
            self.env_from_world * d
        } else {
            d
        }
    }

    /// `I_env(N)` (irradiance / π, times the intensity) for a world normal.
    #[inline]
    #[must_use]
    pub fn irradiance(&self, n: Vec3) -> Vec3 {
        self.irradiance_a(n).into()
    }

    /// [`EnvLight::irradiance`] as a SIMD vector.
    #[inline]
    #[must_use]
    pub fn irradiance_a(&self, n: Vec3) -> Vec3A {
        match self.irradiance {
            Some(f) => f.read(self.in_map_frame(n)) * self.env.intensity,
            None => Vec3A::ZERO,
        }
    }

    /// The light a sheen of roughness `r` reflects towards a viewer along the reflected
    /// direction `dir` (a world direction): the Charlie-prefiltered levels around `r`,
    /// interpolated linearly in `r` (the first level below `1/LEVELS`), times the intensity;
    /// without the levels, the irradiance about `normal`.
    #[inline]
    #[must_use]
    pub fn sheen_radiance(&self, dir: Vec3, normal: Vec3, r: f32) -> Vec3 {
        let Some(levels) = self.sheen else {
            return self.irradiance(normal);
        };
        let x = (r.clamp(0.0, 1.0) * LEVELS as f32 - 1.0).max(0.0);
        let k = (x as usize).min(LEVELS - 2);
        let t = (x - k as f32).min(1.0);
        let (a, b) = levels[k].read_pair(&levels[k + 1], self.in_map_frame(dir));
        (a.lerp(b, t) * self.env.intensity).into()
    }

    /// The map itself along a world-direction footprint (the background, mirror reflections),
    /// times the intensity: linear RGB.
    #[inline]
    #[must_use]
    pub fn mirror(&self, fp: &CubeFootprint) -> Vec3 {
        let local = CubeFootprint {
            dir: self.in_map_frame(fp.dir),
            ddir_dx: self.in_map_frame(fp.ddir_dx),
            ddir_dy: self.in_map_frame(fp.ddir_dy),
        };
        self.env.map.sample(&self.sampler, &local).truncate() * self.env.intensity
    }

    /// The environment seen through a GGX lobe of `roughness` around the world-direction
    /// footprint `fp` (its derivatives widen the lobe; module docs): the map itself at
    /// roughness 0, else the prefiltered levels.
    #[inline]
    #[must_use]
    pub fn radiance(&self, fp: &CubeFootprint, roughness: f32) -> Vec3 {
        self.radiance_a(fp, roughness).into()
    }

    /// [`EnvLight::radiance`] as a SIMD vector.
    #[inline]
    #[must_use]
    pub fn radiance_a(&self, fp: &CubeFootprint, roughness: f32) -> Vec3A {
        let roughness = roughness.clamp(0.0, 1.0);
        let Some(levels) = self.specular.filter(|_| roughness > 0.0) else {
            return self.mirror(fp).into();
        };
        // The footprint's angle (the direction is unit length), as a lobe of α = w/2.
        let w2 = fp.ddir_dx.length_squared().max(fp.ddir_dy.length_squared());
        let r2 = roughness * roughness;
        let a2 = r2 * r2 + 0.25 * w2;
        // The lobe's level: k = ⌊LEVELS·α²^¼⌋ (at most LEVELS − 1), found by comparing α²
        // with the levels' own (seven compares instead of two dependent square roots).
        let k = A2_AT[1..LEVELS].iter().filter(|&&t| a2 >= t).count();
        // The blend of levels k and k + 1 is linear in α² (not in roughness): GGX's tails
        // grow as α², so this weighting keeps the blurred light a lobe spreads as the lobe
        // of this roughness does (linear in roughness, a roughness-0.3 metal was 26% too
        // bright where a bright sky leaks into its reflection of the ground).
        let frac = ((a2.min(1.0) - A2_AT[k]) * INV_A2_STEP[k]).clamp(0.0, 1.0);
        let dir = self.in_map_frame(fp.dir);
        let intensity = self.env.intensity;
        // The reads and their blend in SIMD vectors (Vec3A), one conversion at the end.
        let c: Vec3A = if k == 0 {
            if let Some(sharp) = self
                .sharp
                .filter(|_| self.sampler.filter == Filter::TRILINEAR)
            {
                let local = CubeFootprint {
                    dir,
                    ddir_dx: self.in_map_frame(fp.ddir_dx),
                    ddir_dy: self.in_map_frame(fp.ddir_dy),
                };
                let (lower, (f, sc, tc)) = sharp.read(&self.sampler, &local);
                if frac <= 0.0 {
                    lower
                } else {
                    lower.lerp(levels[0].read_at(f, sc, tc), frac)
                }
            } else {
                let lower = Vec3A::from(self.mirror(fp));
                if frac <= 0.0 {
                    return lower;
                }
                return lower.lerp(levels[0].read(dir) * intensity, frac);
            }
        } else if frac <= 0.0 {
            levels[k - 1].read(dir)
        } else {
            let (lower, upper) = levels[k - 1].read_pair(&levels[k], dir);
            lower.lerp(upper, frac)
        };
        c * intensity
    }

    /// The background along a world-direction footprint: premultiplied RGBA, alpha 1.
    #[must_use]
    pub fn background(&self, fp: &CubeFootprint) -> Vec4 {
        self.mirror(fp).extend(1.0)
    }

    /// [`EnvLight::background`] of four footprints (lanes whose bit in `mask` is clear are
    /// left zero): the same values, the map read four at a time
    /// ([`crate::texture::EnvironmentMap::sample_lanes`]).
    #[must_use]
    pub fn background_lanes(&self, fp: &CubeFootprintLanes, mask: u8) -> [Vec4; 4] {
        let c = if self.rotated {
            // `in_map_frame` lane by lane: glam's `Mat3 * Vec3` order, x + y then + z.
            let m = &self.env_from_world;
            let turn = |[vx, vy, vz]: [Vec4; 3]| {
                std::array::from_fn(|c| {
                    Vec4::splat(m.x_axis[c]) * vx
                        + Vec4::splat(m.y_axis[c]) * vy
                        + Vec4::splat(m.z_axis[c]) * vz
                })
            };
            let local = CubeFootprintLanes {
                dir: turn(fp.dir),
                ddir_dx: turn(fp.ddir_dx),
                ddir_dy: turn(fp.ddir_dy),
            };
            self.env.map.sample_lanes(&self.sampler, &local, mask)
        } else {
            self.env.map.sample_lanes(&self.sampler, fp, mask)
        };
        let mut out = [Vec4::ZERO; 4];
        for (j, o) in out.iter_mut().enumerate() {
            if mask & (1 << j) != 0 {
                *o = (c[j].truncate() * self.env.intensity).extend(1.0);
            }
        }
        out
    }
}

/// α² at each prefiltered roughness `k/LEVELS` (`(k/8)⁴`), and the reciprocals of the steps
/// between neighbours: the blend weights of [`EnvLight::radiance`] without a division.
const A2_AT: [f32; LEVELS + 1] = {
    let mut t = [0.0; LEVELS + 1];
    let mut k = 0;
    while k <= LEVELS {
        let r = k as f32 / LEVELS as f32;
        t[k] = r * r * r * r;
        k += 1;
    }
    t
};
const INV_A2_STEP: [f32; LEVELS] = {
    let mut t = [0.0; LEVELS];
    let mut k = 0;
    while k < LEVELS {
        t[k] = 1.0 / (A2_AT[k + 1] - A2_AT[k]);
        k += 1;
    }
    t
};

/// The material's environment parameters beside its [`Surface`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvMaterial {
    /// K_R (Phong).
    pub reflection: f32,
    /// K_T (Phong) or `KHR_materials_transmission`'s factor (metallic-roughness), after its
    /// map.
    pub transmission: f32,
    /// The roughness the Phong reflection and transmission are read at.
    pub phong_roughness: f32,
}

/// Where a pixel looks into the environment: the reflected and refracted directions with
/// their screen derivatives.
#[derive(Clone, Copy, Debug, Default)]
pub struct EnvRays {
    pub reflected: CubeFootprint,
    pub refracted: CubeFootprint,
    /// What the frame's other surfaces show where the refracted ray leaves the surface
    /// (premultiplied, alpha their coverage), when the frame drew them first: seen through a
    /// transmitting metallic-roughness surface in front of the environment.
    pub behind: Option<Vec4>,
}

/// The unit reflection of the view direction: `R = 2(N·V)N − V`.
#[inline]
#[must_use]
pub fn reflect(n: Vec3, v: Vec3) -> Vec3 {
    n * (2.0 * n.dot(v)) - v
}

/// The direction of the ray from the eye (`−V`) refracted into the surface (`N` towards the
/// viewer, `ior` inside over outside): Snell's law; total internal reflection returns the
/// reflection.
#[inline]
#[must_use]
pub fn refract(n: Vec3, v: Vec3, ior: f32) -> Vec3 {
    let eta = 1.0 / ior.max(1e-3);
    let cos_i = n.dot(v).clamp(-1.0, 1.0);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if k < 0.0 {
        return reflect(n, v);
    }
    (-v * eta + n * (eta * cos_i - k.sqrt())).normalize_or_zero()
}

/// f0 of a dielectric of index of refraction `ior` in air: `((ior − 1)/(ior + 1))²`
/// ([`pbr::DIELECTRIC_F0`] exactly at 1.5).
#[inline]
#[must_use]
pub fn dielectric_f0(ior: f32) -> f32 {
    if ior == 1.5 {
        return pbr::DIELECTRIC_F0;
    }
    let r = (ior - 1.0) / (ior + 1.0);
    r * r
}

/// The factors `(D, S)` the environment adds at surface `s` seen by `viewer` (the lit colour
/// being `C·D + S`): the module docs' terms for `model`.
#[must_use]
pub fn environment_terms(
    model: crate::shading::ShadingModel,
    s: &Surface,
    m: &EnvMaterial,
    viewer: Viewer,
    rays: &EnvRays,
    light: &EnvLight,
) -> (Vec3, Vec3) {
    environment_terms_with(model, s, m, viewer, rays, light, &mut None)
}

/// [`environment_terms`] with the last irradiance a Phong surface read, `(normal, I_env)`:
/// reused when `s` has that normal, bit for bit (a flat surface's pixels read it once), and
/// replaced otherwise.
#[must_use]
pub fn environment_terms_with(
    model: crate::shading::ShadingModel,
    s: &Surface,
    m: &EnvMaterial,
    viewer: Viewer,
    rays: &EnvRays,
    light: &EnvLight,
    last: &mut Option<([u32; 3], Vec3)>,
) -> (Vec3, Vec3) {
    let env = light.env;
    let n = s.normal;
    let mut d = Vec3::ZERO;
    let mut sp = Vec3::ZERO;
    match model {
        crate::shading::ShadingModel::Phong => {
            let n_dot_v = n.dot(viewer.towards(s.position)).max(1e-4);
            if env.ibl {
                let key = n.to_array().map(f32::to_bits);
                let irradiance = match *last {
                    Some((k, i)) if k == key => i,
                    _ => {
                        let i = light.irradiance(n);
                        *last = Some((key, i));
                        i
                    }
                };
                let ambient = irradiance * (s.ambient * s.occlusion);
                match s.ambient_color {
                    None => d += ambient,
                    Some(a) => sp += ambient * a,
                }
            }
            if env.reflections && (m.reflection > 0.0 || m.transmission > 0.0) {
                let reflected = if m.reflection > 0.0 {
                    light.radiance(&rays.reflected, m.phong_roughness)
                } else {
                    Vec3::ZERO
                };
                if m.transmission > 0.0 {
                    let f = pbr::fresnel(Vec3::splat(dielectric_f0(s.ior)), n_dot_v).x;
                    let through = light.radiance(&rays.refracted, m.phong_roughness);
                    sp += reflected * (m.reflection * f) * s.specular_color;
                    d += through * (m.transmission * (1.0 - f));
                } else {
                    sp += reflected * m.reflection * s.specular_color;
                }
            }
        }
        crate::shading::ShadingModel::MetallicRoughness => {
            let lobe = pbr::MrLobe::new(s, viewer);
            (d, sp) = metallic_roughness_env(s, m, &lobe, rays, light);
            if s.lobes.layered() && env.ibl {
                return layered_env(s, lobe.v, lobe.n_dot_v, rays, light, (d, sp));
            }
        }
    }
    (d, sp)
}

/// The metallic-roughness factors of `s` under `lighting`'s lights and the environment in one
/// pass: `(lights, environment)`, each pair `(D, S)` exactly as [`pbr::metallic_roughness`]
/// and [`environment_terms`] give them (the lights' pair with the emission, no ambient term:
/// the caller's `lighting` has none, image-based light replacing it), the lobe they share
/// computed once.
#[inline]
#[must_use]
pub fn metallic_roughness_lit(
    s: &Surface,
    m: &EnvMaterial,
    lighting: &crate::shading::Lighting,
    viewer: Viewer,
    rays: &EnvRays,
    light: &EnvLight,
) -> ((Vec3, Vec3), (Vec3, Vec3)) {
    debug_assert!(lighting.ambient == Vec3::ZERO || s.ambient * s.occlusion == 0.0);
    if s.lobes.layered() {
        return (
            pbr::metallic_roughness(s, lighting, viewer),
            environment_terms(
                crate::shading::ShadingModel::MetallicRoughness,
                s,
                m,
                viewer,
                rays,
                light,
            ),
        );
    }
    let lobe = pbr::MrLobe::new(s, viewer);
    let lit = pbr::lights(s, lighting, &lobe, (Vec3::ZERO, s.emissive));
    (lit, metallic_roughness_env(s, m, &lobe, rays, light))
}

/// The metallic-roughness environment terms `(D, S)` of `s` with its `lobe` (no clearcoat or
/// sheen: [`layered_env`] lays them over).
#[inline(always)]
fn metallic_roughness_env(
    s: &Surface,
    m: &EnvMaterial,
    lobe: &pbr::MrLobe,
    rays: &EnvRays,
    light: &EnvLight,
) -> (Vec3, Vec3) {
    let env = light.env;
    // In SIMD vectors (Vec3A: the same operations in the same order, one instruction where
    // Vec3 takes three): this runs at every pixel of image-based light.
    let metallic = lobe.metallic;
    let roughness = s.roughness.clamp(0.0, 1.0);
    let e = Vec3A::from(lobe.albedo());
    let diffuse = (Vec3A::ONE - e) * (1.0 - metallic);
    let transmission = if env.reflections {
        m.transmission.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (mut da, mut sa) = (Vec3A::ZERO, Vec3A::ZERO);
    if env.ibl {
        // A metal (or a fully transmitting surface) has no diffuse lobe: its irradiance read
        // is skipped, not multiplied by zero.
        let kd = diffuse * (s.occlusion * (1.0 - transmission));
        if kd != Vec3A::ZERO {
            da += light.irradiance_a(s.normal) * kd;
        }
        sa += light.radiance_a(&rays.reflected, roughness) * e * s.occlusion;
    }
    if transmission > 0.0 {
        // KHR_materials_volume: Beer–Lambert through the thickness.
        let through = Vec3A::from(s.lobes.transmittance(s.lobes.thickness));
        let mut seen = light.radiance_a(&rays.refracted, roughness);
        if let Some(b) = rays.behind {
            // Surfaces over the environment (none there: the environment exactly).
            seen = Vec3A::from(b.truncate()) + seen * (1.0 - b.w);
        }
        da += seen * diffuse * through * transmission;
    }
    (da.into(), sa.into())
}

/// The clearcoat and sheen over the environment's base factors ([`pbr`]'s layering, the
/// [`crate::shading::lobes`] module docs): the coat reads the prefiltered environment along
/// its own reflected direction (with the base reflection's footprint) at its roughness; the
/// sheen takes the irradiance about the normal times its albedo.
fn layered_env(
    s: &Surface,
    v: Vec3,
    n_dot_v: f32,
    rays: &EnvRays,
    light: &EnvLight,
    (d, sp): (Vec3, Vec3),
) -> (Vec3, Vec3) {
    use crate::shading::lobes::{coat_share, sheen_scaling};
    let l = &s.lobes;
    let nc = if s.clearcoat_normal == Vec3::ZERO {
        s.normal
    } else {
        s.clearcoat_normal
    };
    let nc_dot_v = nc.dot(v).max(1e-4);
    let coat = coat_share(l.clearcoat, nc_dot_v);
    let k = sheen_scaling(l.sheen_color, l.sheen_roughness, n_dot_v);
    let mut under_coat = sp * k;
    if l.sheen_color != Vec3::ZERO {
        under_coat += light.sheen_radiance(reflect(s.normal, v), s.normal, l.sheen_roughness)
            * l.sheen_color
            * (crate::shading::sheen::albedo(n_dot_v, l.sheen_roughness) * s.occlusion);
    }
    let mut coat_sp = Vec3::ZERO;
    if l.clearcoat > 0.0 {
        let r = l.clearcoat_roughness.clamp(0.0, 1.0);
        let ab = pbr::specular_albedo(nc_dot_v, pbr::alpha(r).sqrt());
        let fp = CubeFootprint {
            dir: reflect(nc, v),
            ..rays.reflected
        };
        coat_sp = light.radiance(&fp, r)
            * (l.clearcoat * (pbr::DIELECTRIC_F0 * ab.x + ab.y) * s.occlusion);
    }
    let under = 1.0 - coat;
    (d * (k * under), under_coat * under + coat_sp)
}

/// Rays for a point with no neighbours (Gouraud vertices, flat faces): directions without
/// derivatives.
#[must_use]
pub fn point_rays(s: &Surface, viewer: Viewer) -> EnvRays {
    let v = viewer.towards(s.position);
    EnvRays {
        reflected: CubeFootprint {
            dir: reflect(s.normal, v),
            ..Default::default()
        },
        refracted: CubeFootprint {
            dir: refract(s.normal, v, s.ior),
            ..Default::default()
        },
        behind: None,
    }
}

/// The lobe-widening angle a footprint stands for, for tests and diagnostics: the longer of
/// the direction's two derivatives.
#[must_use]
pub fn footprint_angle(fp: &CubeFootprint) -> f32 {
    Vec2::new(fp.ddir_dx.length(), fp.ddir_dy.length()).max_element()
}
