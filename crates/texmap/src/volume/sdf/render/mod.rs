//! Drawing a distance field: its surface by sphere tracing, and a hypertexture around it by
//! ray marching the shell, one ray per pixel in the volume renderer's tiles.
//!
//! Rules:
//! - Sphere tracing (Hart 1996): outside the reach `R` of the material (0 for a plain
//!   surface) a ray advances by `0.9 · (d − R)` (at least 1/50 voxel), `d` the trilinear
//!   distance. This is the empty-space skipping: the field itself says how far the next
//!   thing is. The trilinear field of a distance field is close to 1-Lipschitz; the 0.9
//!   leaves room, and any crossing a step jumps into is still found by the sign change.
//! - Inside the reach the ray takes fixed steps of `step` shells (jittered per pixel like
//!   the volume rays), compositing the hypertexture's density front to back, until the
//!   opacity reaches the early stop or the core surface is crossed.
//! - From the hypertexture's `tail` opacity (0.95 by default) the rest of the material is
//!   extrapolated: the last sample repeated until the early stop, when that takes at most
//!   [`TAIL_STEPS`] steps (measured: 52 dB on smoke against marching on, 10 % fewer
//!   samples; README). `tail` 1 (`off`) marches every sample: a reference render.
//! - From the hypertexture's `wide` opacity (0.7 by default) a sample stands for two steps:
//!   the march takes every second grid point and composites `1 − (1 − a)²`, the sample's
//!   material over both. What lies behind is seen through at most 30 % of the light, so the
//!   coarser steps weigh little (measured on smoke: README). `wide` 1 (`off`) keeps single
//!   steps: with `tail` off, a reference render.
//! - A crossing (distance from > 0 to ≤ 0) is placed inside the last step to 1/100 voxel
//!   (at most 16 reads) by false position from the distances at its two ends (Illinois),
//!   by bisection where the first end's is not known, and shaded with the normal from
//!   central differences (±½ voxel) of the trilinear field. (Bisection's reads depend each
//!   on the last: a shell step of 2 voxels took 8; false position takes 2–3.)
//! - A material's march ([`kind::PLAIN`]) starts with its way in: the sphere-traced steps
//!   to the reach of two neighbouring rays, a step of each in turn ([`approach`]); each
//!   ray's march resumes where its way in stopped (the same steps, the same image).
//! - A material's samples read the noise lattice at the ray's own lattice coordinates,
//!   `o + v·t` ([`Tracer::lattice_ray`]), not the sample's world point carried through
//!   the texture transform.
//! - The melted core (melt, core displacement) is sphere-traced with a Lipschitz bound:
//!   far from it through the empty balls of a lattice of its exact distance ([`warp`]),
//!   near it by the noises themselves, in steps of at least ¼ voxel; its crossing is placed
//!   by false position ([`melted`]). Where the core is all there is to find (no material,
//!   or a light's depth map) a loop of its own traces it ([`Tracer::march_melted`]).
//! - Colours are linear and premultiplied, as meshes' are (not the display values of
//!   transfer functions): the frame holds them as they are.
//! - The image does not depend on the number of threads (per-pixel work, fixed tile order).

mod approach;
mod medium;
mod melted;
#[cfg(test)]
mod tests;
mod warp;

use glam::{Vec3, Vec3A, Vec4};

use super::super::grid::Volume;
use super::super::output::check_request;
use super::super::params::MarchParams;
use super::super::raymarch::{tiled_frame, tiled_rows};
use super::super::rays::{clip_to_box, pixel_hash, CameraRays, VoxelRay};
use super::super::shade::VolumeLights;
use super::hyper::Hypertexture;
use super::look::{texture_from_world, SurfaceLook};
use super::noise_cache::{NoiseCache, POINTS_PER_CELL};
use super::reader::{FieldReader, LazyGradient};
use crate::camera::{Camera, CameraProjection};
use crate::frame::{Frame, FrameStats};
use crate::shading::shadow::ShadowMaps;
use crate::Result;
use approach::Start;
use kind::flag;
use warp::Warp;

/// Most steps one ray takes.
const MAX_STEPS: u32 = 8192;
/// Most bisections that place a crossing; they stop once the interval is under 1/100 voxel.
const BISECTIONS: u32 = 16;
/// The least step of the melted core's sphere tracing, voxels.
const WARPED_STEP: f32 = 0.25;
/// Entries of the density shaping table (bias and gain of `u ∈ [0, 1]`).
const SHAPE_LUT: usize = 1024;
/// The march's specialisations, [`Tracer::march`]'s `K`: [`kind::GENERIC`] reads every
/// flag at run time; [`kind::PLAIN`] marks a material without melt, core displacement or
/// self-shadowing, with skipping on and not a depth-only trace, and then [`kind::STRANDS`],
/// [`kind::GLOW`] and [`kind::LATTICE`] say which of those it has. Each preset of the
/// command line gets a loop of its own without the others' branches (the same operations
/// in the same order, so the same bits).
pub(super) mod kind {
    pub const GENERIC: u8 = 0;
    pub const PLAIN: u8 = 1;
    pub const STRANDS: u8 = 2;
    pub const GLOW: u8 = 4;
    pub const LATTICE: u8 = 8;
    /// The presets' kinds.
    pub const FUR: u8 = PLAIN | STRANDS;
    pub const FIRE: u8 = PLAIN | GLOW | LATTICE;
    pub const SMOKE: u8 = PLAIN | LATTICE;

    /// `runtime` for the generic march, else what `K`'s `bit` says.
    #[inline(always)]
    pub fn flag<const K: u8>(bit: u8, runtime: bool) -> bool {
        if K & PLAIN == 0 {
            runtime
        } else {
            K & bit != 0
        }
    }
}

/// Most steps [`Tracer::tail`] stands for (beyond them the ray marches on).
const TAIL_STEPS: f32 = 12.0;

/// Everything the rays of one frame share.
pub(super) struct Tracer<'a> {
    field: FieldReader<'a>,
    /// The lights' shadow maps, looked up where the surface and the material are lit.
    shadows: Option<&'a ShadowMaps>,
    /// Rays find the core surface only (its distance), unshaded: a light's depth map.
    pub(super) depth_only: bool,
    look: &'a SurfaceLook,
    hyper: Option<&'a Hypertexture>,
    lights: VolumeLights,
    has_lights: bool,
    light_list: &'a [crate::shading::Light],
    texture_from_world: glam::Mat4,
    world_from_voxel: glam::Mat4,
    /// The object's size (its box's largest side), world.
    size: f32,
    /// The box's lowest point along the screen's up, world.
    base: f32,
    /// The screen's up, world (unit).
    up: Vec3,
    /// Shell thickness, world.
    shell: f32,
    /// Reach of material and displaced core beyond the surface, world (∞: no skipping).
    reach: f32,
    /// How fast the core distance may change (1 for the plain field).
    lipschitz: f32,
    /// Step inside the reach, world.
    step: f32,
    /// The octaves' weights summed (the fBm's largest value over [`NOISE_BOUND`]).
    noise_weight: f32,
    /// Bias and gain of the density ramp, tabulated.
    shape: Vec<f32>,
    /// The opacity of one shell step at each entry of `shape`: `1 − exp(−opacity·D·step/T)`.
    alpha: Vec<f32>,
    /// Pixel footprint: texture units per unit of distance (perspective) and constant.
    footprint: (f32, f32),
    early: f32,
    /// The opacity from which the material's rest is extrapolated ([`Self::tail`]); at
    /// `early` or above: never.
    tail_from: f32,
    /// The opacity from which a sample stands for two steps (+∞: never).
    wide_from: f32,
    jitter: bool,
    /// The frame's noise on a lattice, read by the shell's samples (material without
    /// strands; `None`: evaluated directly).
    noise_cache: Option<NoiseCache>,
    /// The melted core's distance on a lattice (`None`: no melt and no core displacement).
    warp: Option<Warp>,
    /// The core surface is melted or displaced (not the field's zero set).
    warped: bool,
    /// The march's specialisation ([`kind`]) when the trace is not depth-only.
    kind: u8,
}

/// Renders the distance field `vol` (world distances, negative inside) as a surface with
/// `look`, and with the hypertexture `hyper` around it when given, seen by `camera`, into a
/// `width × height` frame, in rayon's current pool. `depth`, when given, holds per pixel the
/// ray distance where rays stop (surfaces in front), as [`raymarch`](super::super::raymarch())'s.
/// From `params` it reads the lights and reflectance, jitter, empty-space skipping and the
/// early stop.
///
/// # Errors
/// [`crate::Error::Parameter`] for a bad camera, size, depth buffer, look or hypertexture,
/// or a field with an axis over 2^24 voxels (more than its reads take).
#[allow(clippy::too_many_arguments)]
pub fn render_distance_field(
    vol: &Volume,
    camera: &Camera,
    width: u32,
    height: u32,
    params: &MarchParams,
    look: &SurfaceLook,
    hyper: Option<&Hypertexture>,
    depth: Option<&[f32]>,
) -> Result<Frame> {
    render_distance_field_shadowed(vol, camera, width, height, params, look, hyper, depth, None)
}

/// [`render_distance_field`] with the scene lights' shadow maps (`shadows`, made for
/// `params.lights` in their order, as [`crate::render::shadow_maps_with_fields`] makes
/// them): the surface and the lit material receive the shadows of whatever the maps hold.
///
/// # Errors
/// As [`render_distance_field`].
#[allow(clippy::too_many_arguments)]
pub fn render_distance_field_shadowed(
    vol: &Volume,
    camera: &Camera,
    width: u32,
    height: u32,
    params: &MarchParams,
    look: &SurfaceLook,
    hyper: Option<&Hypertexture>,
    depth: Option<&[f32]>,
    shadows: Option<&ShadowMaps>,
) -> Result<Frame> {
    check_request(camera, width, height, params, depth)?;
    super::reader::check_axes(vol)?;
    look.validate()?;
    if let Some(h) = hyper {
        h.validate()?;
    }
    let mut tr = Tracer::new(vol, camera, height, params, look, hyper);
    tr.shadows = shadows.filter(|m| !m.is_empty());
    let rays = CameraRays::new(camera, width, height);
    let ray = |x: u32, y: u32| {
        let (o, d) = rays.ray(x as f32 + 0.5, y as f32 + 0.5);
        let t_max = depth.map_or(f32::INFINITY, |dd| dd[(y * width + x) as usize]);
        (o, d, t_max)
    };
    let (color, samples) = match tr.melted_warp() {
        // The melted core alone: two neighbouring rays marched in turn.
        Some(w) => tiled_rows(width, height, |y, xs, color| {
            let mut n = 0;
            let mut x = xs.start;
            while x + 1 < xs.end {
                let [a, b] = tr.march_melted_pair(w, [ray(x, y), ray(x + 1, y)]);
                color.extend([a.0, b.0]);
                n += a.1 + b.1;
                x += 2;
            }
            if x < xs.end {
                let (o, d, t_max) = ray(x, y);
                let (c, k, _) = tr.march_melted(w, o, d, t_max);
                color.push(c);
                n += k;
            }
            n
        }),
        // A material's march: the rays' ways in two at a time.
        None if tr.kind & kind::PLAIN != 0 => tiled_rows(width, height, |y, xs, color| {
            tr.trace_row(y, xs, color, ray)
        }),
        None => tiled_frame(width, height, |x, y| {
            let (o, d, t_max) = ray(x, y);
            let j = if tr.jitter { pixel_hash(x, y) } else { 0.0 };
            let (c, n, _) = tr.trace(o, d, t_max, j);
            (c, n)
        }),
    };
    Ok(Frame {
        width,
        height,
        color,
        stats: FrameStats {
            texture_samples: samples,
            ..Default::default()
        },
    })
}

impl<'a> Tracer<'a> {
    /// The rays' shared state for `vol` seen by `camera` in an image `height` pixels high
    /// (the pixel footprint; the camera's up is the melt's and the flames' up).
    pub(super) fn new(
        vol: &'a Volume,
        camera: &Camera,
        height: u32,
        params: &'a MarchParams,
        look: &'a SurfaceLook,
        hyper: Option<&'a Hypertexture>,
    ) -> Tracer<'a> {
        let field = FieldReader::new(vol);
        let (lo, hi) = vol.world_bounds();
        let size = (hi - lo).max_element().max(1e-12);
        let shell = hyper.map_or(0.0, |h| h.thickness * size);
        let reach = match hyper {
            _ if !params.empty_space_skipping => f32::INFINITY,
            None => 0.0,
            Some(h) => {
                (h.amplitude + h.core_displacement) * shell + h.melt * h.time.abs() * 2.5 * size
            }
        };
        // A bound on how fast the melted, displaced core distance changes (its Lipschitz
        // constant, in practice): sphere tracing it steps by e / lipschitz.
        let lipschitz = hyper.map_or(1.0, |h| {
            1.0 + 2.0 * h.melt * h.time.abs()
                + 2.0 * h.core_displacement * h.thickness * h.frequency
        });
        let step = hyper.map_or(field.voxel * 0.5, |h| h.step * shell);
        let shape = match hyper {
            Some(h) => (0..=SHAPE_LUT)
                .map(|i| h.shape(i as f32 / SHAPE_LUT as f32))
                .collect(),
            None => Vec::new(),
        };
        let alpha = match hyper {
            Some(h) => shape
                .iter()
                .map(|&dens| 1.0 - (-h.opacity * dens * step / shell).exp())
                .collect(),
            None => Vec::new(),
        };
        let footprint = match camera.projection {
            CameraProjection::Perspective { fov_y_deg } => (
                2.0 * (fov_y_deg.to_radians() * 0.5).tan() / height as f32 / size,
                0.0,
            ),
            CameraProjection::Orthographic { half_height } => {
                (0.0, 2.0 * half_height / height as f32 / size)
            }
        };
        let up = camera.up.try_normalize().unwrap_or(Vec3::Y);
        let texture_from_world = texture_from_world(lo, hi);
        let noise_cache = hyper
            .filter(|h| h.amplitude > 0.0 && h.opacity > 0.0 && !h.strands)
            .and_then(|h| {
                // The finest octave's lattice cell, squeezed along the up by `stretch`: along
                // texture axis `i` (world's, scaled) the stretched noise changes at
                // `|e_i + (stretch − 1)·u_i·u| = √(1 + (stretch² − 1)·u_i²)` times its rate.
                let finest = 2f32.powi(h.octaves.clamp(1.0, 32.0).ceil() as i32 - 1);
                let rate = (Vec3::ONE + (h.stretch * h.stretch - 1.0) * up * up).max(Vec3::ZERO);
                let density = POINTS_PER_CELL * h.frequency * finest * rate.map(f32::sqrt);
                NoiseCache::new(
                    texture_from_world.transform_point3(lo),
                    texture_from_world.transform_point3(hi),
                    density,
                )
            });
        // The core surface is melted or displaced (not the field's zero set).
        let warped = hyper.is_some_and(|h| h.melt != 0.0 || h.core_displacement != 0.0);
        let warp = warped
            .then(|| Warp::new(field.hi, &vol.world_from_voxel()))
            .flatten();
        let kind = match hyper {
            Some(h)
                if params.empty_space_skipping
                    && h.amplitude > 0.0
                    && h.opacity > 0.0
                    && !warped
                    && (!h.shadows || params.lights.is_empty()) =>
            {
                let on = |bit: u8, set: bool| if set { bit } else { 0 };
                kind::PLAIN
                    | on(kind::STRANDS, h.strands)
                    | on(kind::GLOW, h.emission > 0.0)
                    | on(kind::LATTICE, noise_cache.is_some())
            }
            _ => kind::GENERIC,
        };
        Tracer {
            shadows: None,
            depth_only: false,
            field,
            look,
            hyper,
            lights: VolumeLights::new(params.reflectance, &params.lights),
            has_lights: !params.lights.is_empty(),
            light_list: &params.lights,
            texture_from_world,
            world_from_voxel: vol.world_from_voxel(),
            size,
            base: vol
                .world_corners()
                .iter()
                .map(|c| c.dot(up))
                .fold(f32::INFINITY, f32::min),
            up,
            shell,
            reach,
            lipschitz,
            step,
            noise_weight: hyper.map_or(0.0, Hypertexture::octave_weight),
            shape,
            alpha,
            footprint,
            early: params.early_termination,
            tail_from: hyper.map_or(params.early_termination, |h| {
                h.tail.min(params.early_termination)
            }),
            wide_from: hyper.map_or(f32::INFINITY, |h| {
                if h.wide < 1.0 {
                    h.wide
                } else {
                    f32::INFINITY
                }
            }),
            jitter: params.jitter,
            noise_cache,
            warp,
            warped,
            kind,
        }
    }
}

impl Tracer<'_> {
    /// One ray: its colour (linear, premultiplied), the field reads it took and the ray
    /// distance of the core surface where it met it (+∞ where it did not). With
    /// `depth_only` the material is left out and nothing is shaded.
    #[inline(never)]
    pub(super) fn trace(&self, eye: Vec3, dir: Vec3, t_max: f32, jitter: f32) -> (Vec4, u64, f32) {
        if let Some(w) = self.melted_warp() {
            return self.march_melted(w, eye, dir, t_max);
        }
        self.trace_from(eye, dir, t_max, jitter, None)
    }

    /// [`Self::trace`] resuming from `start` when given (a plain kind's approach).
    #[inline(always)]
    fn trace_from(
        &self,
        eye: Vec3,
        dir: Vec3,
        t_max: f32,
        jitter: f32,
        start: Option<Start>,
    ) -> (Vec4, u64, f32) {
        match if self.depth_only {
            kind::GENERIC
        } else {
            self.kind
        } {
            kind::FUR => self.march::<{ kind::FUR }>(eye, dir, t_max, jitter, start),
            kind::FIRE => self.march::<{ kind::FIRE }>(eye, dir, t_max, jitter, start),
            kind::SMOKE => self.march::<{ kind::SMOKE }>(eye, dir, t_max, jitter, start),
            _ => self.march::<{ kind::GENERIC }>(eye, dir, t_max, jitter, start),
        }
    }

    /// [`Self::trace`] specialised as `K` says ([`kind`]; the tracer's flags agree with it),
    /// a function of its own so each loop gets its own registers.
    /// From `start`, when given, it resumes where the ray's approach left it.
    #[inline(never)]
    fn march<const K: u8>(
        &self,
        eye: Vec3,
        dir: Vec3,
        t_max: f32,
        jitter: f32,
        start: Option<Start>,
    ) -> (Vec4, u64, f32) {
        let plain = K & kind::PLAIN != 0;
        let ray = VoxelRay::new(&self.field.voxel_from_world, eye, dir);
        let core = self.hyper.is_none_or(|h| h.core);
        let Some(span) = clip_to_box(&ray, t_max, Vec3::ZERO, self.field.hi)
            .filter(|_| core || !self.depth_only)
        else {
            return (Vec4::ZERO, 0, f32::INFINITY);
        };
        let mut acc = Vec4::ZERO;
        let mut reads = 0u64;
        let mut t = span.t0;
        let mut t_prev: Option<f32> = None;
        // The core distance at `t_prev` where the melted core's tracing read it.
        let mut e_prev: Option<f32> = None;
        let mut jittered = false;
        let min_step = self.field.voxel * 0.05;
        let warped_step = self.field.voxel * WARPED_STEP;
        let mut at_end = false;
        // Only the material reads the gradient; sphere-traced steps read the distance alone.
        let medium = plain || !self.depth_only && self.has_material();
        // The melted core's lattice and flag (none for a plain march).
        let warp = if plain { None } else { self.warp.as_ref() };
        let warped_core = !plain && self.warped();
        let mut in_reach = false;
        let mut hit_t = f32::INFINITY;
        let lattice = if flag::<K>(kind::LATTICE, true) {
            self.lattice_ray(eye, dir)
        } else {
            None
        };
        let mut first = 0;
        if let Some(s) = start {
            (t, t_prev, e_prev, at_end, reads, first) =
                (s.t, s.t_prev, s.e_prev, s.at_end, s.reads, s.steps);
        }
        for _ in first..MAX_STEPS {
            if t > span.t1 {
                // The last sample sits on the span's end, so a crossing just before a stop
                // (a surface in front, the box's far side) is still found.
                if at_end || t_prev.is_none_or(|tp| tp >= span.t1) {
                    break;
                }
                t = span.t1;
                at_end = true;
            }
            let q = ray.at(t);
            let p = eye + dir * t;
            if let Some(w) = warp.filter(|_| !medium && self.reach.is_finite()) {
                // Through the melted core's empty balls, without reading the field.
                if let Some(b) = w.ball_step(
                    p.into(),
                    q.into(),
                    dir.into(),
                    warped_step,
                    self.lipschitz,
                    |c| self.core_distance(c),
                ) {
                    t_prev = Some(t);
                    e_prev = Some(b.lower);
                    t += b.advance;
                    continue;
                }
            }
            if warp.is_some() && !medium && self.reach.is_finite() {
                // Near the melted core: its own distance (the plain field's says nothing).
                let e = self.core_step_distance(p);
                reads += 1;
                if e <= 0.0 {
                    let n;
                    (hit_t, acc, n) = self.core_crossing(eye, dir, (t_prev, e_prev), (t, e));
                    reads += n;
                    break;
                }
                t_prev = Some(t);
                e_prev = Some(e);
                t += (e * 0.9 / self.lipschitz).max(warped_step);
                continue;
            }
            let (mut d, mut g) = if in_reach {
                self.field.distance_and_lazy_gradient(q)
            } else {
                (self.field.distance(q), LazyGradient::zero(&self.field))
            };
            reads += 1;
            if d > self.reach {
                // Sphere tracing to the reach.
                in_reach = false;
                t_prev = Some(t);
                // (The plain core's distance is the field's; the melted core's is not known.)
                e_prev = (!warped_core).then_some(d);
                // Inside a shell, stepping less than a shell step gains nothing.
                let least = if self.reach > 0.0 {
                    self.step
                } else {
                    min_step
                };
                t += ((d - self.reach) * 0.9).max(least);
                continue;
            }
            if medium && !in_reach {
                in_reach = true;
                (d, g) = self.field.distance_and_lazy_gradient(q);
            }
            if !medium && self.reach.is_finite() {
                // No material: sphere tracing of the (melted, displaced) core itself.
                let warped = warped_core;
                let e = if warped {
                    self.core_step_distance(p)
                } else {
                    d
                };
                if e <= 0.0 {
                    let prev = (t_prev, e_prev);
                    let n;
                    (hit_t, acc, n) = self.core_crossing(eye, dir, prev, (t, e));
                    reads += n;
                    break;
                }
                t_prev = Some(t);
                e_prev = Some(e);
                // The melted core: steps not below `warped_step`, a crossing placed by false position.
                let least = if warped { warped_step } else { min_step };
                t += (e * 0.9 / self.lipschitz).max(least);
                continue;
            }
            if !jittered && medium {
                // The first step into the reach starts the pixel's jittered sample grid.
                jittered = true;
                if jitter > 0.0 {
                    t_prev = Some(t);
                    e_prev = (!warped_core).then_some(d);
                    t += jitter * self.step;
                    continue;
                }
            }
            let e = if warped_core {
                self.core_distance(p)
            } else {
                d
            };
            if core && e <= 0.0 {
                let (c, n);
                (hit_t, c, n) = self.core_crossing(eye, dir, (t_prev, e_prev), (t, e));
                reads += n;
                acc += c * (1.0 - acc.w);
                break;
            }
            if let Some(h) = self.hyper {
                let lat = lattice.map(|(o, v)| o + v * t);
                let (c, a, n) = self.material::<K>(h, p, d, || g.gradient(), dir, lat);
                reads += n;
                // From `wide` on, the sample stands for two steps (the module's rules).
                let wide = acc.w >= self.wide_from;
                if a > 0.0 {
                    let aw = if wide { a * (2.0 - a) } else { a };
                    acc += (c * aw).extend(aw) * (1.0 - acc.w);
                    if acc.w >= self.early {
                        break;
                    }
                    if acc.w >= self.tail_from {
                        if let Some(done) = self.tail(acc, c, a) {
                            acc = done;
                            break;
                        }
                    }
                }
                t_prev = Some(t);
                e_prev = Some(e);
                t += if wide { self.step * 2.0 } else { self.step };
            } else {
                // A plain surface without skipping: fixed half-voxel steps.
                t_prev = Some(t);
                e_prev = Some(e);
                t += self.step;
            }
        }
        (acc, reads, hit_t)
    }

    /// The melted core's lattice when the core is all a ray can find (no material, or a
    /// depth-only trace): such rays take [`Self::march_melted`].
    #[inline(always)]
    fn melted_warp(&self) -> Option<&Warp> {
        self.warp
            .as_ref()
            .filter(|_| self.reach.is_finite() && (self.depth_only || !self.has_material()))
    }

    /// The ray `eye + dir·t` in the noise lattice's coordinates, `(at 0, per unit t)`, where
    /// the frame has a lattice.
    #[inline(always)]
    fn lattice_ray(&self, eye: Vec3, dir: Vec3) -> Option<(Vec3A, Vec3A)> {
        let c = self.noise_cache.as_ref()?;
        Some((
            c.lattice_point(self.texture_from_world.transform_point3(eye)),
            c.lattice_vector(self.texture_from_world.transform_vector3(dir)),
        ))
    }

    /// True when the hypertexture has material (amplitude and opacity above 0).
    #[inline(always)]
    fn has_material(&self) -> bool {
        self.hyper
            .is_some_and(|h| h.amplitude > 0.0 && h.opacity > 0.0)
    }

    /// The rest of a ray whose material has reached opacity `acc.w` (below the early stop)
    /// at a sample of colour `c` and step opacity `a`, extrapolated: that sample repeated
    /// until the opacity reaches the early stop, as the march would end there if the material
    /// stayed as it is. `None` when that takes more than [`TAIL_STEPS`] steps (the ray
    /// marches on).
    #[inline(never)]
    fn tail(&self, acc: Vec4, c: Vec3, a: f32) -> Option<Vec4> {
        let left = 1.0 - acc.w;
        // The least k with left·(1 − a)^k ≤ 1 − early.
        let k = if a >= 1.0 {
            1.0
        } else {
            (((1.0 - self.early) / left).ln() / (1.0 - a).ln())
                .ceil()
                .max(1.0)
        };
        if !(k <= TAIL_STEPS) {
            return None;
        }
        let rest = left * (1.0 - a).max(0.0).powi(k as i32);
        Some((acc.truncate() + c * (left - rest)).extend(1.0 - rest))
    }

    /// The core's crossing between the last step (`t_prev`, with its core distance `e_prev`
    /// when one was read) and `t`, where the distance `e` is ≤ 0: false position when both
    /// distances are known, else bisection (the first step: `t` itself). Returns the hit's
    /// distance along the ray, its shaded colour (zero when only depth is asked) and the
    /// field reads taken.
    fn core_crossing(
        &self,
        eye: Vec3,
        dir: Vec3,
        (t_prev, e_prev): (Option<f32>, Option<f32>),
        (t, e): (f32, f32),
    ) -> (f32, Vec4, u64) {
        let (hit, n) = match (t_prev, e_prev) {
            (Some(tp), Some(ep)) => self.false_position(eye, dir, (tp, ep), (t, e)),
            (Some(tp), _) => self.bisect(eye, dir, tp, t),
            (None, _) => (t, 0),
        };
        if self.depth_only {
            return (hit, Vec4::ZERO, 0);
        }
        (
            hit,
            self.shade_core(eye + dir * hit, dir, hit),
            u64::from(n) + 6,
        )
    }

    /// The core surface at world point `p`, reached at ray distance `t`: opaque, shaded.
    fn shade_core(&self, p: Vec3, dir: Vec3, t: f32) -> Vec4 {
        let q = self.field.voxel_from_world.transform_point3(p);
        let g = if self.warped() {
            self.field.central_gradient(q, |v| {
                self.core_distance(self.world_from_voxel.transform_point3(v))
            })
        } else {
            self.field.central_gradient(q, |v| self.field.distance(v))
        };
        let n = g.try_normalize().unwrap_or(-dir);
        // The material moves with the melt: its texture is read where it came from.
        let pt = match self.hyper {
            Some(h) => p + self.sag(h, p),
            None => p,
        };
        let n = self.look.bumped(&self.texture_from_world, pt, n);
        let width = self.footprint.0 * t + self.footprint.1;
        let c = self.look.color_at(&self.texture_from_world, pt, width);
        self.lit(c, n, dir, p).extend(1.0)
    }

    /// Colour `c` with normal (or gradient) `n` at world point `p` lit by the volume's
    /// lights, in the shadow maps' shadows when there are maps.
    #[inline(always)]
    fn lit(&self, c: Vec3, n: Vec3, dir: Vec3, p: Vec3) -> Vec3 {
        match self.shadows {
            None => self.lights.shade(c, n, dir, || p),
            Some(maps) => self.lights.shade_shadowed(
                c,
                n,
                dir,
                || p,
                |i, p, n, l| maps.visibility(i, p, n, l),
            ),
        }
    }
}
