//! Ray marching: one ray per pixel from the camera, clipped to the volume's box, sampled at
//! a fixed step in world units and composited front to back.
//!
//! Rules:
//! - Samples sit at `t_entry + (k + j)·step`, `j ∈ [0, 1)` a hash of the pixel (jitter; 0 when
//!   off): the same pixel always gets the same offset, whatever the thread count.
//! - Composite: `C += (1 − A)·α·c`, `A += (1 − A)·α`, with `α = 1 − (1 − a)^step` (opacity per
//!   unit length, VTK's unit distance 1). Rays stop once `A ≥ early_termination`.
//! - Empty-space skipping: the box is cut into 8³-cell bricks with the min/max of their
//!   voxels; a brick whose whole value interval is transparent under the table is crossed in
//!   one jump to the first sample position past it (so skipping never moves samples).
//! - Values are read by trilinear interpolation from a plain `f32` copy of the field
//!   ([`super::Volume::value_at`]), which is tested equal to the texture engine's
//!   [`crate::texture::sample_3d`] (`value_at_engine`): the engine dispatches on the texel
//!   format and the wrap mode per read and computes a level of detail; measured by
//!   `examples/volume_sampling.rs`, 18 ns against 77 ns per read at random points of a 128³
//!   volume (one thread). `MarchParams::engine_sampling` selects the engine path.
//! - Shading interpolates per-voxel normals (built once per volume) instead of taking six
//!   extra trilinear reads per sample for central differences.
//! - The common case (post-classification, no gradient opacity) runs a loop specialised at
//!   compile time for shading on/off, reading a cell's eight voxels once per cell; unshaded,
//!   it composites premultiplied table entries with one 4-wide multiply-add.
//! - Colours are display values composited as VTK composites them; the frame stores
//!   `srgb_to_linear` of the result, so writing it as sRGB gives VTK's bytes.

use glam::{Mat3, Mat4, Vec3, Vec4};
use rayon::prelude::*;

use super::shade::VolumeLights;
use super::transfer::{gradient_factor, PreIntegrated, TransferFunction, TransferLut};
use super::{blend_cell, cell_corners, trilinear, Volume};
use crate::camera::{Camera, CameraProjection};
use crate::frame::{Frame, FrameStats};
use crate::shading::Light;
use crate::{Error, Result};

/// What a ray computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Mode {
    /// Direct volume rendering: classification and front-to-back compositing.
    #[default]
    Composite,
    /// Maximum intensity projection (grey, the value range mapped to [0, 1]).
    Mip,
    /// The first crossing of the iso-value, refined by bisection, shaded.
    Iso,
    /// The average value along the ray (grey, the value range mapped to [0, 1]).
    Xray,
}

/// Where classification happens relative to interpolation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Classification {
    /// Interpolate values, then classify (the default; sharpest).
    #[default]
    Post,
    /// Classify the eight voxels, then interpolate premultiplied colour and opacity.
    Pre,
    /// Classify each segment between two samples from a pre-integrated table.
    PreIntegrated,
}

/// Blinn-Phong coefficients (VTK's defaults in `vtk_volume.py`), for the headlight or the
/// scene's lights ([`MarchParams::lights`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lighting {
    pub ambient: f32,
    pub diffuse: f32,
    pub specular: f32,
    pub power: f32,
}

impl Default for Lighting {
    fn default() -> Self {
        Lighting {
            ambient: 0.2,
            diffuse: 0.7,
            specular: 0.2,
            power: 10.0,
        }
    }
}

/// How a volume is rendered.
#[derive(Clone, Debug, PartialEq)]
pub struct MarchParams {
    pub mode: Mode,
    /// Distance between samples along a ray, world units (> 0).
    pub step: f32,
    /// Blinn-Phong shading from central-difference gradients (composite mode).
    pub shade: bool,
    pub classification: Classification,
    pub lighting: Lighting,
    /// Lights for shading, world space (a scene's lights); empty: a white headlight along
    /// the view direction (see `volume::shade`).
    pub lights: Vec<Light>,
    /// Iso-value for [`Mode::Iso`] (default: the transfer function's first opaque value).
    pub iso: Option<f32>,
    /// Opacity × a piecewise-linear function of the gradient magnitude: `(g, factor)` points
    /// (the 2D transfer function); empty for none.
    pub gradient_opacity: Vec<(f32, f32)>,
    /// Jittered ray starts (hides wood-grain banding).
    pub jitter: bool,
    pub empty_space_skipping: bool,
    /// Stop a ray once its opacity reaches this (1 or more: never). Default 0.992: VTK's
    /// fixed-point mapper stops when the remaining opacity falls below 255/32768.
    pub early_termination: f32,
    /// Read values through the texture engine instead of the plain copy (slow; for checks).
    pub engine_sampling: bool,
}

impl Default for MarchParams {
    fn default() -> Self {
        MarchParams {
            mode: Mode::Composite,
            step: 0.5,
            shade: false,
            classification: Classification::Post,
            lighting: Lighting::default(),
            lights: Vec::new(),
            iso: None,
            gradient_opacity: Vec::new(),
            jitter: true,
            empty_space_skipping: true,
            early_termination: 0.992,
            engine_sampling: false,
        }
    }
}

/// Cells per brick side for empty-space skipping.
pub const BRICK: u32 = 8;

/// Min/max 16-bit level of the voxels of each brick (computed once per volume).
#[derive(Clone, Debug)]
pub struct Bricks {
    pub counts: [u32; 3],
    pub min_max: Vec<(f32, f32)>,
}

impl Bricks {
    /// Brick `b` covers cells `[8b, 8b + 8)`, i.e. voxels `8b ..= 8b + 8`.
    #[must_use]
    pub fn new(vol: &Volume) -> Self {
        let d = vol.dims();
        let cells = d.map(|n| (n - 1).max(1));
        let counts = cells.map(|c| c.div_ceil(BRICK));
        let data = vol.quantized();
        let (nx, ny) = (d[0] as usize, d[1] as usize);
        let slabs: Vec<Vec<(f32, f32)>> = (0..counts[2])
            .into_par_iter()
            .map(|bz| {
                let mut out =
                    vec![(f32::INFINITY, f32::NEG_INFINITY); (counts[0] * counts[1]) as usize];
                let z0 = bz * BRICK;
                let z1 = (z0 + BRICK).min(d[2] - 1);
                for z in z0..=z1 {
                    for y in 0..d[1] {
                        let by_lo = (y.saturating_sub(1) / BRICK).min(counts[1] - 1);
                        let by_hi = (y / BRICK).min(counts[1] - 1);
                        let row = &data[(z as usize * ny + y as usize) * nx..][..nx];
                        for (x, &v) in row.iter().enumerate() {
                            let v = f32::from(v);
                            let x = x as u32;
                            let bx_lo = (x.saturating_sub(1) / BRICK).min(counts[0] - 1);
                            let bx_hi = (x / BRICK).min(counts[0] - 1);
                            for by in by_lo..=by_hi {
                                for bx in bx_lo..=bx_hi {
                                    let m = &mut out[(by * counts[0] + bx) as usize];
                                    m.0 = m.0.min(v);
                                    m.1 = m.1.max(v);
                                }
                            }
                        }
                    }
                }
                out
            })
            .collect();
        Bricks {
            counts,
            min_max: slabs.concat(),
        }
    }
}

/// The eight voxels of the last cell a ray read: at half-voxel steps about every other
/// sample stays in the same cell, and then skips the eight loads (measured ~10% per sample).
struct CellCache {
    index: usize,
    corners: [f32; 8],
    frac: Vec3,
    normals_of: usize,
    normals: [Vec3; 8],
}

impl CellCache {
    fn new() -> Self {
        CellCache {
            index: usize::MAX,
            corners: [0.0; 8],
            frac: Vec3::ZERO,
            normals_of: usize::MAX,
            normals: [Vec3::ZERO; 8],
        }
    }

    /// The cell of `p` (clamped as [`trilinear`]): base index, strides, fractions.
    #[inline(always)]
    fn locate(dims: [u32; 3], p: Vec3) -> (usize, [usize; 3], Vec3) {
        // The length check is `value`'s, done once per new cell.
        super::trilinear_cell(dims, p, usize::MAX).unwrap_or((0, [0; 3], Vec3::ZERO))
    }

    /// Trilinear value at `p`, equal to [`trilinear`].
    #[inline(always)]
    fn value(&mut self, data: &[u16], dims: [u32; 3], p: Vec3) -> f32 {
        let (i, [sx, sy, sz], f) = Self::locate(dims, p);
        self.frac = f;
        if i != self.index {
            if data.len() < dims.iter().map(|&v| v as usize).product::<usize>() {
                return 0.0;
            }
            // SAFETY: as in `trilinear`: i + sx + sy + sz is a voxel of the grid, and `data`
            // holds every voxel (checked above).
            let g = |k: usize| f32::from(unsafe { *data.get_unchecked(k) });
            self.corners = cell_corners(i, [sx, sy, sz], g);
            self.index = i;
        }
        blend_cell(&self.corners, f)
    }

    /// The interpolated normal of the cell last passed to [`Self::value`], as
    /// [`trilinear_normal`] at that point.
    #[inline(always)]
    fn normal(&mut self, data: &[[i8; 4]], dims: [u32; 3]) -> Vec3 {
        let f = self.frac;
        if self.normals_of != self.index {
            let [nx, ny, nz] = dims;
            if data.len() < nx as usize * ny as usize * nz as usize {
                return Vec3::ZERO;
            }
            let (sx, sy, sz) = (
                usize::from(nx > 1),
                if ny > 1 { nx as usize } else { 0 },
                if nz > 1 { nx as usize * ny as usize } else { 0 },
            );
            let i = self.index;
            // SAFETY: `self.index` came from `locate` on the same grid (see `value`).
            let g = |k: usize| {
                let n = unsafe { *data.get_unchecked(k) };
                Vec3::new(f32::from(n[0]), f32::from(n[1]), f32::from(n[2]))
            };
            self.normals = cell_corners(i, [sx, sy, sz], g);
            self.normals_of = i;
        }
        direction_or_zero(blend_cell(&self.normals, f))
    }
}

/// Trilinear interpolation of per-voxel normals at voxel-space `p` (clamped): a direction
/// whose length falls below ½ where the normals disagree or are zero.
#[inline(always)]
pub(crate) fn trilinear_normal(data: &[[i8; 4]], dims: [u32; 3], p: Vec3) -> Vec3 {
    let Some((
        i,
        [sx, sy, sz],
        Vec3 {
            x: fx,
            y: fy,
            z: fz,
        },
    )) = super::trilinear_cell(dims, p, data.len())
    else {
        return Vec3::ZERO;
    };
    let g = |k: usize| {
        // SAFETY: as in `trilinear`: `trilinear_cell` makes the largest index i + sx + sy + sz a
        // voxel of the grid and checked that `data` holds every voxel.
        let n = unsafe { *data.get_unchecked(k) };
        Vec3::new(f32::from(n[0]), f32::from(n[1]), f32::from(n[2]))
    };
    let corners = cell_corners(i, [sx, sy, sz], g);
    direction_or_zero(blend_cell(&corners, Vec3::new(fx, fy, fz)))
}

/// An interpolated normal (×127) as a direction: below half length the neighbours disagree
/// (or are flat), so there is none.
#[inline(always)]
fn direction_or_zero(n127: Vec3) -> Vec3 {
    let v = n127 * (1.0 / 127.0);
    if v.length_squared() < 0.25 * 0.25 {
        Vec3::ZERO
    } else {
        v
    }
}

/// Per-voxel unit normals in world space ×127 (central differences through the spacing and
/// orientation; zero where the field is flat), x fastest.
#[must_use]
pub fn voxel_normals(vol: &Volume) -> Vec<[i8; 4]> {
    let d = vol.dims();
    let (nx, ny, nz) = (d[0] as usize, d[1] as usize, d[2] as usize);
    let data = vol.quantized();
    let m = Mat3::from_mat4(vol.world_from_voxel().inverse()).transpose();
    let slabs: Vec<Vec<[i8; 4]>> = (0..nz)
        .into_par_iter()
        .map(|z| {
            let mut out = Vec::with_capacity(nx * ny);
            let at = |x: usize, y: usize, z: usize| f32::from(data[(z * ny + y) * nx + x]);
            for y in 0..ny {
                for x in 0..nx {
                    let diff = |lo: usize, hi: usize, f: &dyn Fn(usize) -> f32| {
                        if hi > lo {
                            (f(hi) - f(lo)) / (hi - lo) as f32
                        } else {
                            0.0
                        }
                    };
                    let gx = diff(x.saturating_sub(1), (x + 1).min(nx - 1), &|i| at(i, y, z));
                    let gy = diff(y.saturating_sub(1), (y + 1).min(ny - 1), &|j| at(x, j, z));
                    let gz = diff(z.saturating_sub(1), (z + 1).min(nz - 1), &|k| at(x, y, k));
                    let g = m * Vec3::new(gx, gy, gz);
                    let len = g.length();
                    out.push(if len > 0.0 {
                        let n = g / len * 127.0;
                        [n.x.round() as i8, n.y.round() as i8, n.z.round() as i8, 0]
                    } else {
                        [0; 4]
                    });
                }
            }
            out
        })
        .collect();
    slabs.concat()
}

/// A per-pixel hash in [0, 1) (jitter): the same pixel always gets the same value.
#[inline]
#[must_use]
pub fn pixel_hash(x: u32, y: u32) -> f32 {
    let mut h = x.wrapping_mul(0x8da6_b343) ^ y.wrapping_mul(0xd816_3841) ^ 0x9e37_79b9;
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^= h >> 16;
    (h >> 8) as f32 / (1u32 << 24) as f32
}

/// A camera ray for pixel `(x, y)`: origin and unit direction in world space. Perspective
/// rays start at the eye; orthographic rays start on the plane through the eye perpendicular
/// to the view direction and all run along it.
#[inline]
#[must_use]
pub fn camera_ray(cam: &Camera, width: u32, height: u32, x: f32, y: f32) -> (Vec3, Vec3) {
    let f = (cam.target - cam.eye).normalize();
    let r = f.cross(cam.up).normalize();
    let u = r.cross(f);
    let aspect = width as f32 / height as f32;
    // Half the image height: at unit distance (perspective) or in world units (orthographic).
    let (th, ortho) = match cam.projection {
        CameraProjection::Perspective { fov_y_deg } => {
            ((fov_y_deg.to_radians() * 0.5).tan(), false)
        }
        CameraProjection::Orthographic { half_height } => (half_height, true),
    };
    let sx = (2.0 * x / width as f32 - 1.0) * th * aspect;
    let sy = (1.0 - 2.0 * y / height as f32) * th;
    if ortho {
        (cam.eye + r * sx + u * sy, f)
    } else {
        (cam.eye, (f + r * sx + u * sy).normalize())
    }
}

/// Everything a ray needs, prepared once per frame.
struct Ctx<'a> {
    vol: &'a Volume,
    data: &'a [u16],
    /// 16-bit level → table index.
    q_to_index: f32,
    /// Value of one level.
    value_step: f32,
    iso_q: f32,
    dims: [u32; 3],
    hi: Vec3,
    voxel_from_world: Mat4,
    world_from_voxel: Mat4,
    /// Transposed linear part of voxel_from_world: voxel gradient → world gradient.
    grad_to_world: Mat3,
    lut: TransferLut,
    /// The table premultiplied: `[r·a, g·a, b·a, a]`.
    lut_pm: Vec<Vec4>,
    pre_int: Option<PreIntegrated>,
    empty: Vec<bool>,
    brick_counts: [u32; 3],
    p: &'a MarchParams,
    iso_color: Vec3,
    range: (f32, f32),
    /// Per-voxel unit normals (world space, ×127) when shading without gradient opacity.
    normals: Option<&'a [[i8; 4]]>,
    /// The headlight's direction: the camera's view direction for every ray (as VTK's
    /// shading tables, which use the centre view direction); `None` uses each ray's own.
    /// Scene lights take it as the view direction.
    headlight: Option<Vec3>,
    lights: VolumeLights,
}

/// A depth buffer, if given, holds one distance per pixel (both methods check it).
pub(crate) fn check_depth(depth: Option<&[f32]>, width: u32, height: u32) -> Result<()> {
    match depth {
        Some(d) if d.len() != width as usize * height as usize => Err(Error::parameter(format!(
            "depth buffer has {} values for a {width}x{height} image",
            d.len()
        ))),
        _ => Ok(()),
    }
}

/// The checks both methods make: an image size in 1..=16384 and a positive, finite step.
pub(crate) fn check_frame(width: u32, height: u32, params: &MarchParams) -> Result<()> {
    if width == 0 || height == 0 || width > 16384 || height > 16384 {
        return Err(Error::parameter(format!(
            "image size {width}x{height} is out of range"
        )));
    }
    if !(params.step.is_finite() && params.step > 0.0) {
        return Err(Error::parameter(format!(
            "--step {} must be > 0",
            params.step
        )));
    }
    Ok(())
}

/// Renders `vol` classified by `tf`, seen by `camera`, into a `width × height` frame, in
/// rayon's current pool. `depth`, when given, holds per pixel (row-major, top row first) the
/// distance along the ray from the eye where the ray stops (a surface in front).
///
/// The image does not depend on the number of threads.
///
/// # Errors
/// [`Error::Parameter`] for a bad camera, size, step or depth buffer length.
pub fn raymarch(
    vol: &Volume,
    tf: &TransferFunction,
    camera: &Camera,
    width: u32,
    height: u32,
    params: &MarchParams,
    depth: Option<&[f32]>,
) -> Result<Frame> {
    camera.validate()?;
    check_frame(width, height, params)?;
    check_depth(depth, width, height)?;
    let mut ctx = Ctx::new(vol, tf, params)?;
    ctx.headlight = Some((camera.target - camera.eye).normalize());
    // Square tiles: a tile's rays stay in a narrow bundle of the volume, so their samples
    // share cache lines (rows of 512 rays sweep a whole slab).
    const TILE: usize = 16;
    let (w, h) = (width as usize, height as usize);
    let (tx, ty) = (w.div_ceil(TILE), h.div_ceil(TILE));
    let tiles: Vec<(Vec<Vec4>, u64)> = (0..tx * ty)
        .into_par_iter()
        .map(|t| {
            let (x0, y0) = ((t % tx) * TILE, (t / tx) * TILE);
            let (x1, y1) = ((x0 + TILE).min(w), (y0 + TILE).min(h));
            let mut out = Vec::with_capacity((x1 - x0) * (y1 - y0));
            let mut n = 0u64;
            for y in y0..y1 {
                for x in x0..x1 {
                    let (o, d) = camera_ray(camera, width, height, x as f32 + 0.5, y as f32 + 0.5);
                    let t_max = depth.map_or(f32::INFINITY, |dd| dd[y * w + x]);
                    let j = if params.jitter {
                        pixel_hash(x as u32, y as u32)
                    } else {
                        0.0
                    };
                    let (c, k) = ctx.march(o, d, t_max, j);
                    n += k;
                    out.push(to_frame(c));
                }
            }
            (out, n)
        })
        .collect();
    let mut color = vec![Vec4::ZERO; w * h];
    let mut samples = 0u64;
    for (t, (px, n)) in tiles.iter().enumerate() {
        let (x0, y0) = ((t % tx) * TILE, (t / tx) * TILE);
        let tw = (x0 + TILE).min(w) - x0;
        for (r, row) in px.chunks_exact(tw).enumerate() {
            color[(y0 + r) * w + x0..][..tw].copy_from_slice(row);
        }
        samples += n;
    }
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

/// Display-space premultiplied colour → the frame's linear premultiplied colour.
#[inline]
fn to_frame(c: Vec4) -> Vec4 {
    let f = |v: f32| crate::color::srgb_to_linear(v.clamp(0.0, 1.0));
    Vec4::new(f(c.x), f(c.y), f(c.z), c.w.clamp(0.0, 1.0))
}

/// The empty flags of every brick for a table (composite) or an iso-value.
fn empty_bricks(b: &Bricks, test: impl Fn(f32, f32) -> bool) -> Vec<bool> {
    b.min_max.iter().map(|&(lo, hi)| test(lo, hi)).collect()
}

impl<'a> Ctx<'a> {
    fn new(vol: &'a Volume, tf: &TransferFunction, p: &'a MarchParams) -> Result<Self> {
        let range = vol.range();
        let lut = TransferLut::new(tf, range, p.step);
        let pre_int = (p.classification == Classification::PreIntegrated
            && p.mode == Mode::Composite)
            .then(|| PreIntegrated::new(tf, range, p.step, 256));
        let iso = p
            .iso
            .or_else(|| tf.first_opaque_value())
            .unwrap_or(0.5 * (range.0 + range.1));
        if !iso.is_finite() {
            return Err(Error::parameter("--iso must be finite"));
        }
        let c = tf.eval(iso).truncate();
        let iso_color = if c.max_element() > 0.05 { c } else { Vec3::ONE };
        let voxel_from_world = vol.world_from_voxel().inverse();
        let value_step = vol.value_step();
        // Level differences → value differences → world gradient.
        let grad_to_world = Mat3::from_mat4(voxel_from_world).transpose() * value_step;
        let iso_q = if value_step > 0.0 {
            (iso - range.0) / value_step
        } else {
            0.0
        };
        let lo_v = range.0;
        let bricks = vol.bricks();
        let empty = if !p.empty_space_skipping {
            vec![false; bricks.min_max.len()]
        } else {
            match p.mode {
                Mode::Composite => empty_bricks(bricks, |lo, hi| {
                    // Pre-integrated segments may span a brick edge; the table of the
                    // brick's own values is still the right test for samples inside it.
                    lut.is_transparent(lo_v + lo * value_step, lo_v + hi * value_step)
                }),
                Mode::Iso => empty_bricks(bricks, |_, hi| hi < iso_q),
                Mode::Mip | Mode::Xray => vec![false; bricks.min_max.len()],
            }
        };
        let d = vol.dims();
        Ok(Ctx {
            vol,
            data: vol.quantized(),
            q_to_index: value_step * lut.scale,
            lut_pm: lut
                .table
                .iter()
                .map(|c| (c.truncate() * c.w).extend(c.w))
                .collect(),
            value_step,
            iso_q,
            dims: d,
            hi: Vec3::from_array(d.map(|n| (n - 1) as f32)),
            voxel_from_world,
            world_from_voxel: vol.world_from_voxel(),
            grad_to_world,
            lut,
            pre_int,
            empty,
            brick_counts: bricks.counts,
            p,
            iso_color,
            range,
            normals: (p.shade
                && p.gradient_opacity.is_empty()
                && p.mode == Mode::Composite
                && !p.engine_sampling)
                .then(|| vol.normals().as_slice()),
            headlight: None,
            lights: VolumeLights::new(p.lighting, &p.lights),
        })
    }

    /// The 16-bit level (fractional) at voxel-space `q`.
    #[inline(always)]
    fn value(&self, q: Vec3) -> f32 {
        if self.p.engine_sampling {
            self.vol.level_at_engine(q)
        } else {
            trilinear(self.data, self.dims, q)
        }
    }

    /// `[r, g, b, a_step]` of a level.
    #[inline(always)]
    fn classify(&self, q: f32) -> Vec4 {
        // `as u32`, not `as usize`: a float → u64 conversion is a long instruction sequence.
        let i = ((q * self.q_to_index + 0.5) as u32 as usize).min(self.lut.table.len() - 1);
        self.lut.table[i]
    }

    /// World-space gradient by central differences (one voxel each way).
    #[inline]
    fn gradient(&self, q: Vec3) -> Vec3 {
        let g = Vec3::new(
            self.value(q + Vec3::X) - self.value(q - Vec3::X),
            self.value(q + Vec3::Y) - self.value(q - Vec3::Y),
            self.value(q + Vec3::Z) - self.value(q - Vec3::Z),
        ) * 0.5;
        self.grad_to_world * g
    }

    /// Blinn-Phong of colour `c` with gradient `g` at voxel-space `q`, seen along `ray`: the
    /// headlight or the scene's lights ([`VolumeLights`]).
    #[inline(always)]
    fn shade(&self, c: Vec3, g: Vec3, ray: Vec3, q: Vec3) -> Vec3 {
        self.lights
            .shade(c, g, ray, || self.world_from_voxel.transform_point3(q))
    }

    /// The brick holding the trilinear cell of `q` (clamped as [`trilinear`] clamps).
    #[inline(always)]
    fn brick_of(&self, q: Vec3) -> (usize, [u32; 3]) {
        let c = |v: f32, n: u32, k: u32| {
            let i = (v.max(0.0) as u32).min(n.saturating_sub(2));
            (i / BRICK).min(k - 1)
        };
        let b = [
            c(q.x, self.dims[0], self.brick_counts[0]),
            c(q.y, self.dims[1], self.brick_counts[1]),
            c(q.z, self.dims[2], self.brick_counts[2]),
        ];
        (
            ((b[2] * self.brick_counts[1] + b[1]) * self.brick_counts[0] + b[0]) as usize,
            b,
        )
    }

    /// [`Self::brick_exit`] with the reciprocal direction (no divisions).
    #[inline]
    fn brick_exit_inv(&self, b: [u32; 3], o: Vec3, inv_d: Vec3) -> f32 {
        let lo = Vec3::new(b[0] as f32, b[1] as f32, b[2] as f32) * BRICK as f32;
        let hi = lo + BRICK as f32;
        let mut t = f32::INFINITY;
        for a in 0..3 {
            if inv_d[a].is_finite() {
                let edge = if inv_d[a] > 0.0 { hi[a] } else { lo[a] };
                t = t.min((edge - o[a]) * inv_d[a]);
            }
        }
        t
    }

    /// Ray parameter where the ray leaves brick `b` (voxel-space ray `o + d·t`).
    #[inline]
    fn brick_exit(&self, b: [u32; 3], o: Vec3, d: Vec3) -> f32 {
        let lo = Vec3::new(b[0] as f32, b[1] as f32, b[2] as f32) * BRICK as f32;
        let hi = lo + BRICK as f32;
        let mut t = f32::INFINITY;
        for a in 0..3 {
            if d[a] > 0.0 {
                t = t.min((hi[a] - o[a]) / d[a]);
            } else if d[a] < 0.0 {
                t = t.min((lo[a] - o[a]) / d[a]);
            }
        }
        t
    }

    /// One ray: display-space premultiplied colour and the number of samples taken.
    fn march(&self, eye: Vec3, dir: Vec3, t_max: f32, jitter: f32) -> (Vec4, u64) {
        let o = self.voxel_from_world.transform_point3(eye);
        let d = self.voxel_from_world.transform_vector3(dir);
        // Clip to the box [0, n − 1] (slabs).
        let Some((t0, t1)) = self.clip_box(o, d, t_max) else {
            return (Vec4::ZERO, 0);
        };
        match self.p.mode {
            Mode::Composite
                if self.p.classification == Classification::Post
                    && self.p.gradient_opacity.is_empty()
                    && !self.p.engine_sampling =>
            {
                let light = self.headlight.unwrap_or(dir);
                match self.normals {
                    Some(nv) => self.composite_cells::<true>(o, d, light, nv, t0, t1, jitter),
                    None => self.composite_cells::<false>(o, d, light, &[], t0, t1, jitter),
                }
            }
            Mode::Composite => self.composite(o, d, dir, t0, t1, jitter),
            Mode::Mip | Mode::Xray => self.project(o, d, t0, t1, jitter),
            Mode::Iso => self.isosurface(o, d, dir, t0, t1, jitter),
        }
    }

    /// Next sample index after the brick holding `q` is left, if that brick is empty.
    #[inline(always)]
    fn skip(&self, q: Vec3, o: Vec3, d: Vec3, t0: f32, jitter: f32, k: u32) -> Option<u32> {
        let (bi, b) = self.brick_of(q);
        if !self.empty[bi] {
            return None;
        }
        let t_exit = self.brick_exit(b, o, d);
        let step = self.p.step;
        let kk = ((t_exit - t0) / step - jitter - 1e-3).floor() + 1.0;
        Some((kk.max(0.0) as u32).max(k + 1))
    }

    /// The common case, specialised (mode tests hoisted out of the loop): post-classification,
    /// optional shading from the voxel normals, no gradient opacity; same samples as
    /// [`Self::composite`]. One sample at a time, the cell's voxels (and normals) read once
    /// per cell ([`CellCache`]). A variant that kept four samples in flight (independent
    /// load → interpolate → table chains) measured no faster on this machine, so the simpler
    /// loop stays.
    #[allow(clippy::too_many_arguments)]
    fn composite_cells<const SHADE: bool>(
        &self,
        o: Vec3,
        d: Vec3,
        light: Vec3,
        normals: &[[i8; 4]],
        t0: f32,
        t1: f32,
        jitter: f32,
    ) -> (Vec4, u64) {
        let step = self.p.step;
        let inv_step = 1.0 / step;
        let n = (((t1 - t0) * inv_step - jitter).floor().max(-1.0) as i64 + 1).max(0) as u32;
        let (mut rgb, mut a) = (Vec3::ZERO, 0.0f32);
        let (mut k, mut taken) = (0u32, 0u64);
        let stop = self.p.early_termination;
        let inv_d = d.recip();
        let mut k_check = if self.p.empty_space_skipping {
            0
        } else {
            u32::MAX
        };
        let mut cell = CellCache::new();
        let mut acc = Vec4::ZERO;
        while k < n {
            let t = t0 + (k as f32 + jitter) * step;
            let q = o + d * t;
            if k >= k_check {
                let (bi, b) = self.brick_of(q);
                let t_exit = self.brick_exit_inv(b, o, inv_d);
                let k_exit = ((((t_exit - t0) * inv_step - jitter - 1e-3).floor() + 1.0).max(0.0)
                    as u32)
                    .max(k + 1);
                if self.empty[bi] {
                    k = k_exit;
                    continue;
                }
                k_check = k_exit;
            }
            taken += 1;
            let level = cell.value(self.data, self.dims, q);
            if !SHADE {
                // Premultiplied entries: one 4-wide multiply-add per sample.
                let i =
                    ((level * self.q_to_index + 0.5) as u32 as usize).min(self.lut_pm.len() - 1);
                acc += self.lut_pm[i] * (1.0 - acc.w);
                if acc.w >= stop {
                    break;
                }
                k += 1;
                continue;
            }
            let c = self.classify(level);
            if c.w > 0.0 {
                let col = self.shade(c.truncate(), cell.normal(normals, self.dims), light, q);
                let w = (1.0 - a) * c.w;
                rgb += col * w;
                a += w;
                if a >= stop {
                    break;
                }
            }
            k += 1;
        }
        if !SHADE {
            return (acc, taken);
        }
        (rgb.extend(a), taken)
    }

    fn composite(&self, o: Vec3, d: Vec3, dir: Vec3, t0: f32, t1: f32, jitter: f32) -> (Vec4, u64) {
        let step = self.p.step;
        let n = ((t1 - t0) / step - jitter).floor().max(-1.0) as i64 + 1;
        let n = n.max(0) as u32;
        let mut rgb = Vec3::ZERO;
        let mut a = 0.0f32;
        let mut k = 0u32;
        let mut taken = 0u64;
        let shade = self.p.shade;
        let grad_op = !self.p.gradient_opacity.is_empty();
        let mut prev: Option<f32> = None;
        // The brick is looked up once per brick, not per sample: samples before `k_check`
        // lie in a brick already found non-empty.
        let mut k_check = if self.p.empty_space_skipping {
            0
        } else {
            u32::MAX
        };
        while k < n {
            let t = t0 + (k as f32 + jitter) * step;
            let q = o + d * t;
            if k >= k_check {
                let (bi, b) = self.brick_of(q);
                let t_exit = self.brick_exit(b, o, d);
                let k_exit = ((((t_exit - t0) / step - jitter - 1e-3).floor() + 1.0).max(0.0)
                    as u32)
                    .max(k + 1);
                if self.empty[bi] {
                    k = k_exit;
                    prev = None;
                    continue;
                }
                k_check = k_exit;
            }
            taken += 1;
            let (c, alpha) = match self.p.classification {
                Classification::Post => {
                    let c = self.classify(self.value(q));
                    (c.truncate(), c.w)
                }
                Classification::Pre => self.pre_classified(q),
                Classification::PreIntegrated => {
                    let v = self.value(q);
                    let sf = prev.unwrap_or(v);
                    prev = Some(v);
                    let (a, b) = (
                        self.range.0 + sf * self.value_step,
                        self.range.0 + v * self.value_step,
                    );
                    let s = self.pre_int.as_ref().map_or(Vec4::ZERO, |p| p.get(a, b));
                    if s.w > 0.0 {
                        (s.truncate() / s.w, s.w)
                    } else {
                        (Vec3::ZERO, 0.0)
                    }
                }
            };
            if alpha > 0.0 {
                let mut alpha = alpha;
                let mut c = c;
                if grad_op {
                    // Exact gradient: its magnitude drives the opacity.
                    let g = self.gradient(q);
                    alpha *= gradient_factor(&self.p.gradient_opacity, g.length());
                    if shade {
                        c = self.shade(c, g, self.headlight.unwrap_or(dir), q);
                    }
                } else if let Some(nv) = self.normals {
                    c = self.shade(
                        c,
                        trilinear_normal(nv, self.dims, q),
                        self.headlight.unwrap_or(dir),
                        q,
                    );
                }
                let w = (1.0 - a) * alpha;
                rgb += c * w;
                a += w;
                if a >= self.p.early_termination {
                    break;
                }
            }
            k += 1;
        }
        (rgb.extend(a), taken)
    }

    /// Pre-classification: classify the eight voxels, interpolate premultiplied RGBA.
    fn pre_classified(&self, q: Vec3) -> (Vec3, f32) {
        let [nx, ny, nz] = self.dims;
        let x = q.x.clamp(0.0, self.hi.x);
        let y = q.y.clamp(0.0, self.hi.y);
        let z = q.z.clamp(0.0, self.hi.z);
        let (ix, iy, iz) = (
            (x as u32).min(nx.saturating_sub(2)),
            (y as u32).min(ny.saturating_sub(2)),
            (z as u32).min(nz.saturating_sub(2)),
        );
        let f = Vec3::new(x - ix as f32, y - iy as f32, z - iz as f32);
        let mut acc = Vec4::ZERO;
        for corner in 0..8u32 {
            let (cx, cy, cz) = (corner & 1, (corner >> 1) & 1, corner >> 2);
            let (vx, vy, vz) = (
                (ix + cx).min(nx - 1),
                (iy + cy).min(ny - 1),
                (iz + cz).min(nz - 1),
            );
            let v = self.data[((vz * ny + vy) * nx + vx) as usize];
            let c = self.classify(f32::from(v));
            let w = (if cx == 1 { f.x } else { 1.0 - f.x })
                * (if cy == 1 { f.y } else { 1.0 - f.y })
                * (if cz == 1 { f.z } else { 1.0 - f.z });
            acc += (c.truncate() * c.w).extend(c.w) * w;
        }
        if acc.w > 0.0 {
            (acc.truncate() / acc.w, acc.w)
        } else {
            (Vec3::ZERO, 0.0)
        }
    }

    /// MIP and X-ray: the maximum or mean value along the ray, as grey.
    fn project(&self, o: Vec3, d: Vec3, t0: f32, t1: f32, jitter: f32) -> (Vec4, u64) {
        let step = self.p.step;
        let n = (((t1 - t0) / step - jitter).floor().max(-1.0) as i64 + 1).max(0) as u32;
        if n == 0 {
            return (Vec4::ZERO, 0);
        }
        let (mut mx, mut sum) = (f32::NEG_INFINITY, 0.0f64);
        for k in 0..n {
            let v = self.value(o + d * (t0 + (k as f32 + jitter) * step));
            mx = mx.max(v);
            sum += f64::from(v);
        }
        let v = if self.p.mode == Mode::Mip {
            mx
        } else {
            (sum / f64::from(n)) as f32
        };
        let g = (v / 65535.0).clamp(0.0, 1.0);
        (Vec4::new(g, g, g, 1.0), u64::from(n))
    }

    /// Isosurface: the first sample at or above the iso-value, bisected 10 times, shaded.
    fn isosurface(
        &self,
        o: Vec3,
        d: Vec3,
        dir: Vec3,
        t0: f32,
        t1: f32,
        jitter: f32,
    ) -> (Vec4, u64) {
        let (hit, taken) = self.iso_t(o, d, t0, t1, jitter);
        match hit {
            Some(t) => {
                let q = o + d * t;
                let g = self.gradient(q);
                (self.shade(self.iso_color, g, dir, q).extend(1.0), taken)
            }
            None => (Vec4::ZERO, taken),
        }
    }

    /// The ray parameter of the first crossing of the iso-value (from below), if any.
    fn iso_t(&self, o: Vec3, d: Vec3, t0: f32, t1: f32, jitter: f32) -> (Option<f32>, u64) {
        let step = self.p.step;
        let n = (((t1 - t0) / step - jitter).floor().max(-1.0) as i64 + 1).max(0) as u32;
        let mut k = 0u32;
        let mut taken = 0u64;
        let mut t_prev: Option<f32> = None;
        while k < n {
            let t = t0 + (k as f32 + jitter) * step;
            let q = o + d * t;
            if let Some(next) = self.skip(q, o, d, t0, jitter, k) {
                if t_prev.is_none() {
                    t_prev = Some(t);
                }
                k = next;
                continue;
            }
            taken += 1;
            if self.value(q) >= self.iso_q {
                let mut hit = t;
                if let Some(tp) = t_prev {
                    // Bisection: value(lo) < iso ≤ value(hi).
                    let (mut lo, mut hi) = (tp, t);
                    for _ in 0..10 {
                        let m = 0.5 * (lo + hi);
                        if self.value(o + d * m) >= self.iso_q {
                            hi = m;
                        } else {
                            lo = m;
                        }
                    }
                    hit = 0.5 * (lo + hi);
                    taken += 10;
                }
                return (Some(hit), taken);
            }
            t_prev = Some(t);
            k += 1;
        }
        (None, taken)
    }

    /// The box entry and exit parameters of a voxel-space ray, if it meets the box.
    fn clip_box(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<(f32, f32)> {
        let (mut t0, mut t1) = (0.0f32, t_max);
        for a in 0..3 {
            if d[a].abs() < 1e-12 {
                if o[a] < 0.0 || o[a] > self.hi[a] {
                    return None;
                }
                continue;
            }
            let inv = 1.0 / d[a];
            let (mut ta, mut tb) = (-o[a] * inv, (self.hi[a] - o[a]) * inv);
            if ta > tb {
                std::mem::swap(&mut ta, &mut tb);
            }
            t0 = t0.max(ta);
            t1 = t1.min(tb);
        }
        (t0 < t1).then_some((t0, t1))
    }
}

/// The distance along the world ray `origin + t·dir` (`dir` of unit length) to the
/// isosurface [`Mode::Iso`] would draw (`params.iso`, else the transfer function's first
/// opaque value), without jitter.
///
/// # Errors
/// [`Error::Parameter`] for a bad step or iso-value.
pub fn iso_hit(
    vol: &Volume,
    tf: &TransferFunction,
    origin: Vec3,
    dir: Vec3,
    params: &MarchParams,
) -> Result<Option<f32>> {
    if !(params.step.is_finite() && params.step > 0.0) {
        return Err(Error::parameter(format!(
            "--step {} must be > 0",
            params.step
        )));
    }
    let p = MarchParams {
        mode: Mode::Iso,
        ..params.clone()
    };
    let ctx = Ctx::new(vol, tf, &p)?;
    let o = ctx.voxel_from_world.transform_point3(origin);
    let d = ctx.voxel_from_world.transform_vector3(dir);
    Ok(ctx
        .clip_box(o, d, f32::INFINITY)
        .and_then(|(t0, t1)| ctx.iso_t(o, d, t0, t1, 0.0).0))
}

/// The distance along each pixel's ray at which `depth_ndc` (window depth in [0, 1], OpenGL
/// projection of `camera`, 1 = nothing) lies: the `depth` argument of [`raymarch`].
#[must_use]
pub fn ray_distances_from_depth(
    camera: &Camera,
    width: u32,
    height: u32,
    depth_window: &[f32],
) -> Vec<f32> {
    let (n, f) = (camera.near, camera.far);
    let fwd = (camera.target - camera.eye).normalize();
    let w = width as usize;
    let ortho = camera.projection.is_orthographic();
    depth_window
        .iter()
        .enumerate()
        .map(|(i, &z)| {
            if z >= 1.0 {
                return f32::INFINITY;
            }
            let zn = z * 2.0 - 1.0;
            // Distance along the view direction: GL's projections inverted.
            let view_z = if ortho {
                0.5 * (zn * (f - n) + f + n)
            } else {
                2.0 * n * f / (f + n - zn * (f - n))
            };
            let (_, d) = camera_ray(
                camera,
                width,
                height,
                (i % w) as f32 + 0.5,
                (i / w) as f32 + 0.5,
            );
            view_z / d.dot(fwd)
        })
        .collect()
}

#[cfg(test)]
mod depth_tests {
    use super::{camera_ray, ray_distances_from_depth};
    use crate::camera::{Camera, CameraProjection};
    use glam::Vec3;

    #[test]
    fn window_depth_converts_back_to_the_ray_distance() {
        let cam = Camera {
            eye: Vec3::new(1.0, 2.0, 30.0),
            target: Vec3::new(0.0, 0.0, 0.0),
            up: Vec3::Y,
            projection: CameraProjection::Perspective { fov_y_deg: 40.0 },
            near: 0.5,
            far: 200.0,
        };
        let (w, h) = (8u32, 6u32);
        let clip_from_world = cam.clip_from_view(w as f32 / h as f32) * cam.view_from_world();
        let mut window = Vec::new();
        let mut expected = Vec::new();
        for i in 0..(w * h) {
            let (o, d) = camera_ray(&cam, w, h, (i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
            let t = 10.0 + i as f32;
            let c = clip_from_world * (o + d * t).extend(1.0);
            window.push(c.z / c.w * 0.5 + 0.5);
            expected.push(t);
        }
        let got = ray_distances_from_depth(&cam, w, h, &window);
        for (g, e) in got.iter().zip(&expected) {
            assert!((g - e).abs() < 1e-2 * e, "{g} vs {e}");
        }
        assert!(ray_distances_from_depth(&cam, 1, 1, &[1.0])[0].is_infinite());
    }
}
