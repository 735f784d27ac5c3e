//! Parallax mapping in the fragment stage: each pixel's texture coordinates moved to where
//! its view ray meets the height field, before any map is read, so every map of the material
//! (base colour, normal, bump, …) is read at the shifted uv.
//!
//! The per-pixel frame needs no mesh tangents: the uv's gradient along the surface comes from
//! the screen derivatives of the position and of the uv (the surface-gradient rule of
//! `shading/bump.rs`), `∇u = (R1·∂u/∂x + R2·∂u/∂y)/det` with `R1 = σy × N`, `R2 = N × σx`,
//! `det = σx·R1`. With `V` the unit vector to the eye (per pixel, perspective-correct) and
//! `Vt = V − N(N·V)` its part along the surface, a point of the height field `z` object units
//! above the mesh that the ray sees at the pixel lies at `P + Vt·z/(N·V)`, so its uv is
//! `uv + (∇u·Vt, ∇v·Vt)·z/(N·V)`.
//!
//! - Offset: `z = scale·(h(uv) − base)`, the shift without the `1/(N·V)` (offset limiting).
//! - Occlusion: layers from `z = scale·(1 − base)` down to `−scale·base`, `n` steps with `n`
//!   lerped from `max_steps` (grazing) to `min_steps` (head-on) by `|N·V|`, but no more than
//!   the pixel footprints the ray crosses in uv plus one (a distant pixel's filtered heights
//!   hold nothing between); the first layer below the height field and the one before it
//!   bound the hit, refined by the secant.
//!
//! Every height read goes through the sampling engine with the pixel's own footprint (its
//! uv derivatives before the shift), four pixels of a quad at a time, bilinear on the mip
//! level the footprint picks (one level per read: the search's reads are most of its cost). The shifted uvs are
//! written into a copy of the quad; later reads take their derivatives from the shifted
//! values across the quad, as a GPU's would.

use glam::{Vec2, Vec3, Vec4};

use super::draw::DrawInfo;
use super::maps::MapRead;
use crate::pipeline::{Quad, BATCH};
use crate::shading::relief::{Parallax, ParallaxMode};
use crate::shading::{Light, Lighting, Viewer};
use crate::texture::{Filter, MagFilter, MinFilter};

/// Grazing views are traced as if `N·V` were at least this (the shift grows as `1/(N·V)`).
const MIN_COS: f32 = 0.05;

/// A draw's parallax mapping, resolved.
#[derive(Clone, Copy)]
pub(super) struct ParallaxRead<'a> {
    /// The height map; its `scale` is the relief in world units (object scale included).
    pub map: MapRead<'a>,
    pub mode: ParallaxMode,
    pub base: f32,
    pub min_steps: u32,
    pub max_steps: u32,
    /// Self-shadowing towards the lights.
    pub shadows: bool,
}

impl<'a> ParallaxRead<'a> {
    /// `map` read for the search bilinearly on the level its footprint picks
    /// (`GL_LINEAR_MIPMAP_NEAREST`, whatever the map's filter: the search reads the map up to
    /// `max_steps + 1` times per pixel, so one level per read halves its cost).
    pub fn new(p: &Parallax, mut map: MapRead<'a>) -> Self {
        map.sampler.filter = Filter::Gl {
            mag: MagFilter::Linear,
            min: MinFilter::LinearMipmapNearest,
        };
        ParallaxRead {
            map,
            mode: p.mode,
            base: p.base,
            min_steps: p.min_steps.max(1),
            max_steps: p.max_steps.max(p.min_steps.max(1)),
            shadows: p.shadows,
        }
    }
}

impl DrawInfo<'_> {
    /// `quad` with its height map's uv set moved by parallax mapping (the quad itself when the
    /// draw has no parallax or no per-pixel normal and position).
    pub(super) fn parallax_quad(&self, quad: &Quad, viewer: Viewer) -> Quad {
        let (Some(p), Some(ns), Some(ps)) =
            (&self.parallax, self.layout.normal, self.layout.position)
        else {
            return *quad;
        };
        let uv = p.map.uv;
        let [u, v] = uv.lanes(quad);
        let (dx, dy) = (uv.ddx(quad), uv.ddy(quad));
        let (dp_dx, dp_dy) = (ps.ddx3(quad), ps.ddy3(quad));
        let back = self.material.double_sided && !quad.front_facing;
        let footprint = Vec2::from_array(dx)
            .length()
            .max(Vec2::from_array(dy).length());
        // Per pixel: the raw uv moved per world unit of height along the ray, and the steps.
        let mut per_z = [Vec2::ZERO; 4];
        let mut steps = [0u32; 4];
        let mut mask = quad.mask;
        for j in 0..4 {
            if quad.mask & (1 << j) == 0 {
                continue;
            }
            let mut n = ns.pixel3(quad, j).normalize_or_zero();
            if back {
                n = -n;
            }
            let view = viewer.towards(ps.pixel3(quad, j));
            let r1 = dp_dy.cross(n);
            let r2 = n.cross(dp_dx);
            let det = dp_dx.dot(r1);
            let cos = view.dot(n);
            if !(det.abs() > f32::MIN_POSITIVE && det.is_finite()) || n == Vec3::ZERO || cos <= 0.0
            {
                mask &= !(1 << j);
                continue;
            }
            let grad_u = (r1 * dx[0] + r2 * dy[0]) / det;
            let grad_v = (r1 * dx[1] + r2 * dy[1]) / det;
            let vt = view - n * cos;
            let vt = match p.mode {
                ParallaxMode::Offset => vt,
                ParallaxMode::Occlusion => vt / cos.max(MIN_COS),
            };
            per_z[j] = Vec2::new(grad_u.dot(vt), grad_v.dot(vt));
            let t = cos.clamp(0.0, 1.0);
            let n_steps = p.max_steps as f32 + (p.min_steps as f32 - p.max_steps as f32) * t;
            // Never finer than the footprint: the ray's uv travel through the relief over
            // the pixel's uv footprint, plus one (heights read at that footprint hold no
            // detail between).
            let travel = per_z[j].length() * p.map.scale.abs();
            let crossed = (travel / footprint).ceil() + 1.0;
            let n_steps = if crossed.is_finite() {
                n_steps.min(crossed.max(2.0))
            } else {
                n_steps
            };
            steps[j] = (n_steps.round() as u32).clamp(1, p.max_steps);
        }
        if mask == 0 {
            return *quad;
        }
        let scale = p.map.scale;
        let z_of = |h: f32| scale * (h - p.base);
        let mut z_hit = [0.0f32; 4];
        match p.mode {
            ParallaxMode::Offset => {
                let h = p.map.read_raw(quad, u, v, mask);
                for j in 0..4 {
                    z_hit[j] = z_of(h[j].x);
                }
            }
            ParallaxMode::Occlusion => {
                // The four lanes in vectors; the read skips finished lanes.
                let top = scale * (1.0 - p.base);
                let inv = Vec4::from_array(steps.map(|n| scale / n.max(1) as f32));
                let (pzx, pzy) = (
                    Vec4::from_array(per_z.map(|p| p.x)),
                    Vec4::from_array(per_z.map(|p| p.y)),
                );
                let mut prev = [(top, 0.0f32); 4];
                let mut active = mask;
                let heights = p.map.raw_reader(quad);
                let most = steps.iter().copied().max().unwrap_or(0);
                for i in 0..=most {
                    let z = Vec4::splat(top) - inv * i as f32;
                    let h = heights.read(u + pzx * z, v + pzy * z, active);
                    let hv = Vec4::new(h[0].x, h[1].x, h[2].x, h[3].x);
                    let gap = (z - (hv - Vec4::splat(p.base)) * scale).to_array();
                    let z = z.to_array();
                    for j in 0..4 {
                        if active & (1 << j) == 0 {
                            continue;
                        }
                        if gap[j] <= 0.0 || i >= steps[j] {
                            // The ray is at or below the height field: secant between the
                            // previous layer (above it) and this one.
                            let (pz, pgap) = prev[j];
                            z_hit[j] = if i == 0 || gap[j] > 0.0 {
                                z[j]
                            } else {
                                pz + (z[j] - pz) * (pgap / (pgap - gap[j]))
                            };
                            active &= !(1 << j);
                        } else {
                            prev[j] = (z[j], gap[j]);
                        }
                    }
                    if active == 0 {
                        break;
                    }
                }
            }
        }
        let mut out = *quad;
        let mut nu = u;
        let mut nv = v;
        for j in 0..4 {
            if mask & (1 << j) != 0 {
                nu[j] += per_z[j].x * z_hit[j];
                nv[j] += per_z[j].y * z_hit[j];
            }
        }
        uv.set_lanes(&mut out, [nu, nv]);
        out
    }
}

/// The most lights parallax self-shadowing scales: a scene with more is lit without it.
pub(super) const SELF_SHADOW_LIGHTS: usize = 8;

/// Of the height field's relief, the height standing above the ray to a light that shadows
/// fully (the shadow's softness): 10%.
const SHADOW_SOFTNESS: f32 = 0.1;

/// What parallax self-shadowing lets through: per light (in the frame's order) and pixel of
/// a quad, the fraction of the light that reaches the point the view ray met.
pub(super) struct SelfShadow {
    pub lit: [Vec4; SELF_SHADOW_LIGHTS],
    pub count: usize,
}

/// A light that lights nothing: the filler of a self-shadowed pixel's light buffer.
const NO_LIGHT: Light = Light::Directional {
    direction: Vec3::Y,
    color: Vec3::ZERO,
};

/// The light buffer [`self_shadowed`] fills: only a quad with self-shadowing gets one.
#[inline]
pub(super) fn light_buffer(ss: Option<&SelfShadow>) -> Option<[Light; SELF_SHADOW_LIGHTS]> {
    ss.map(|_| [NO_LIGHT; SELF_SHADOW_LIGHTS])
}

/// `base` at pixel `j` of a quad under parallax self-shadowing `ss` (its lights scaled in
/// `buf`, from [`light_buffer`]), or `base` itself without.
#[inline]
pub(super) fn self_shadowed<'c>(
    ss: Option<&SelfShadow>,
    base: Lighting<'c>,
    j: usize,
    buf: &'c mut Option<[Light; SELF_SHADOW_LIGHTS]>,
) -> Lighting<'c> {
    match (ss, buf) {
        (Some(ss), Some(buf)) => Lighting {
            lights: ss.lights(base.lights, j, buf),
            ..base
        },
        _ => base,
    }
}

impl SelfShadow {
    /// `lights` at pixel `j`, each scaled by what the relief lets through, in `buf`.
    #[inline]
    pub fn lights<'b>(
        &self,
        lights: &[Light],
        j: usize,
        buf: &'b mut [Light; SELF_SHADOW_LIGHTS],
    ) -> &'b [Light] {
        for (i, (b, l)) in buf.iter_mut().zip(lights).take(self.count).enumerate() {
            *b = l.scaled(self.lit[i][j]);
        }
        &buf[..self.count]
    }
}

impl DrawInfo<'_> {
    /// Parallax self-shadowing of `quad` (already moved by [`DrawInfo::parallax_quad`]) under
    /// `lights`: from the point each pixel's view ray met, at height `z0`, a march of up to
    /// 16 steps towards each light through the relief (its uv travel per unit of height from
    /// the same surface gradient as the view ray's), reading the height map with the pixel's
    /// footprint. A step where the height field stands `a` above the ray shadows by
    /// `a / (0.1·scale) · (1 − t)` (`t` the fraction of the way out of the relief: farther
    /// occluders soften the shadow); the light gets 1 minus the largest, and nothing where it
    /// is below the mesh's surface. `None` when the draw has no self-shadowing, there is no
    /// light, or more than [`SELF_SHADOW_LIGHTS`].
    ///
    /// The surface frame and the reads' footprints come from the quad as rasterized
    /// (`quad`), the starting uvs from its moved copy (`moved`): the moved uvs' derivatives
    /// jump where the search crosses a step of the relief, and would scatter the march.
    pub(super) fn parallax_self_shadow(
        &self,
        quad: &Quad,
        moved: &Quad,
        lights: &[Light],
    ) -> Option<SelfShadow> {
        let p = self.parallax.as_ref().filter(|p| p.shadows)?;
        if lights.is_empty() || lights.len() > SELF_SHADOW_LIGHTS {
            return None;
        }
        let (ns, ps) = (self.layout.normal?, self.layout.position?);
        let uv = p.map.uv;
        let [u, v] = uv.lanes(moved);
        let (dx, dy) = (uv.ddx(quad), uv.ddy(quad));
        let (dp_dx, dp_dy) = (ps.ddx3(quad), ps.ddy3(quad));
        let back = self.material.double_sided && !quad.front_facing;
        let scale = p.map.scale;
        let top = scale * (1.0 - p.base);
        let heights = p.map.raw_reader(quad);
        let h0 = heights.read(u, v, quad.mask);
        let z0: [f32; 4] = std::array::from_fn(|j| scale * (h0[j].x - p.base));
        let steps = p.max_steps.clamp(4, 16);
        let soft = 1.0 / (SHADOW_SOFTNESS * scale.abs()).max(f32::MIN_POSITIVE);
        let mut out = SelfShadow {
            lit: [Vec4::ONE; SELF_SHADOW_LIGHTS],
            count: lights.len(),
        };
        for (i, light) in lights.iter().enumerate() {
            let mut per_z = [Vec2::ZERO; 4];
            let mut lit = [1.0f32; 4];
            let mut mask = 0u8;
            for j in 0..4 {
                if quad.mask & (1 << j) == 0 {
                    continue;
                }
                let mut n = ns.pixel3(quad, j).normalize_or_zero();
                if back {
                    n = -n;
                }
                let Some((l, _)) = light.incidence(ps.pixel3(quad, j)) else {
                    continue;
                };
                let cos = n.dot(l);
                if cos <= 0.0 {
                    // Below the mesh's own surface: the relief stands in the way.
                    lit[j] = 0.0;
                    continue;
                }
                let r1 = dp_dy.cross(n);
                let r2 = n.cross(dp_dx);
                let det = dp_dx.dot(r1);
                if !(det.abs() > f32::MIN_POSITIVE && det.is_finite()) || z0[j] >= top {
                    continue;
                }
                let grad_u = (r1 * dx[0] + r2 * dy[0]) / det;
                let grad_v = (r1 * dx[1] + r2 * dy[1]) / det;
                let lt = (l - n * cos) / cos.max(MIN_COS);
                per_z[j] = Vec2::new(grad_u.dot(lt), grad_v.dot(lt));
                mask |= 1 << j;
            }
            let mut shadow = [0.0f32; 4];
            for k in 1..=steps {
                if mask == 0 {
                    break;
                }
                let t = k as f32 / steps as f32;
                let z: [f32; 4] = std::array::from_fn(|j| z0[j] + (top - z0[j]) * t);
                let du = Vec4::from_array(std::array::from_fn(|j| per_z[j].x * (z[j] - z0[j])));
                let dv = Vec4::from_array(std::array::from_fn(|j| per_z[j].y * (z[j] - z0[j])));
                let h = heights.read(u + du, v + dv, mask);
                for j in 0..4 {
                    if mask & (1 << j) == 0 {
                        continue;
                    }
                    let above = scale * (h[j].x - p.base) - z[j];
                    if above > 0.0 {
                        shadow[j] = shadow[j].max(above * soft * (1.0 - t));
                        if shadow[j] >= 1.0 {
                            mask &= !(1 << j);
                        }
                    }
                }
            }
            for j in 0..4 {
                lit[j] *= 1.0 - shadow[j].min(1.0);
            }
            out.lit[i] = Vec4::from_array(lit);
        }
        Some(out)
    }
}

/// The quads of a batch, each moved by the draw's parallax into `buf` when it has one.
pub(super) fn shifted<'q>(
    d: &DrawInfo,
    quads: &'q [Quad],
    viewer: Viewer,
    buf: Option<&'q mut [Quad; BATCH]>,
) -> &'q [Quad] {
    let Some(buf) = buf.filter(|_| d.parallax.is_some()) else {
        return quads;
    };
    for (b, q) in buf.iter_mut().zip(quads) {
        *b = d.parallax_quad(q, viewer);
    }
    &buf[..quads.len()]
}
