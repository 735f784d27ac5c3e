//! Ray marching a frame: one ray per pixel from the camera, in square tiles across rayon's
//! pool, each ray clipped to the volume's box (and stopped at the surfaces in front) and
//! handed to its mode's loop.
//!
//! Rules:
//! - The loop a frame's rays run ([`RayLoop`]) is chosen once per frame from the options;
//!   the per-ray work is the loop itself ([`super::composite`], [`super::intensity`],
//!   [`super::iso`]).
//! - Tiles are 16 × 16 pixels: a tile's rays stay in a narrow bundle of the volume, so their
//!   samples share cache lines, where a row of rays sweeps a whole slab.
//! - Tiles are written to the frame in a fixed order after all are done, so the image does
//!   not depend on the number of threads.
//! - Colours are composited as display values and converted once per pixel
//!   ([`super::output`]).

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use super::composite;
use super::composite_lanes::{self, LaneGrid};
use super::grid::Volume;
use super::intensity;
use super::iso;
use super::marcher::{Marcher, Traced};
use super::output::{check_request, display_to_frame};
use super::params::{Classification, MarchParams, Mode};
use super::rays::{clip_to_box, pixel_hash, CameraRays, RaySamples, VoxelRay};
use super::shaded_lanes::{self, ShadedGrid};
use super::transfer::TransferFunction;
use crate::camera::Camera;
use crate::frame::{Frame, FrameStats};
use crate::pixels::Pixels;
use crate::Result;

/// Pixels per tile side.
const TILE: usize = 16;

/// The loop every ray of a frame runs.
#[derive(Clone, Copy, Debug)]
enum RayLoop<'a> {
    /// Composite, post-classification, no gradient opacity, plain reads
    /// ([`composite::cells`]); shaded from these per-voxel normals when given.
    Cells { normals: Option<&'a [[i8; 4]]> },
    /// [`RayLoop::Cells`] unshaded, eight samples in AVX2 lanes
    /// ([`composite_lanes::cells`]) when the CPU has them and the grid fits.
    CellsInLanes(LaneGrid),
    /// [`RayLoop::Cells`] shaded by the headlight, eight samples in AVX2 lanes
    /// ([`shaded_lanes::cells`]) when the CPU has them, the grid fits and the specular power
    /// is whole.
    ShadedInLanes(ShadedGrid, &'a [[i8; 4]]),
    /// Any other composite case ([`composite::general`]).
    Composite,
    /// MIP or X-ray ([`intensity::project`]).
    Intensity,
    /// The iso-surface ([`iso::surface`]).
    Iso,
}

impl<'a> RayLoop<'a> {
    fn for_frame(m: &Marcher<'a>) -> Self {
        let p = m.p;
        match p.mode {
            Mode::Composite
                if p.classification == Classification::Post
                    && p.gradient_opacity.is_empty()
                    && !p.engine_sampling =>
            {
                match (m.normals, LaneGrid::new(m)) {
                    (None, Some(grid)) => RayLoop::CellsInLanes(grid),
                    (Some(nv), Some(grid)) => match ShadedGrid::new(grid, m, nv) {
                        Some(grid) => RayLoop::ShadedInLanes(grid, nv),
                        None => RayLoop::Cells { normals: Some(nv) },
                    },
                    (normals, None) => RayLoop::Cells { normals },
                }
            }
            Mode::Composite => RayLoop::Composite,
            Mode::Mip | Mode::Xray => RayLoop::Intensity,
            Mode::Iso => RayLoop::Iso,
        }
    }
}

/// One tile's pixels (row-major within the tile) and the samples its rays took.
struct TilePixels {
    color: Vec<Vec4>,
    samples: u64,
}

/// Renders `vol` classified by `tf`, seen by `camera`, into a `width × height` frame, in
/// rayon's current pool. `depth`, when given, holds per pixel (row-major, top row first) the
/// distance along the ray from the eye where the ray stops (a surface in front).
///
/// The image does not depend on the number of threads.
///
/// # Errors
/// [`crate::Error::Parameter`] for a bad camera, size, step, depth buffer length or
/// iso-value.
pub fn raymarch(
    vol: &Volume,
    tf: &TransferFunction,
    camera: &Camera,
    width: u32,
    height: u32,
    params: &MarchParams,
    depth: Option<&[f32]>,
) -> Result<Frame> {
    check_request(camera, width, height, params, depth)?;
    let (lo, hi) = vol.world_bounds();
    params.check_samples((hi - lo).length())?;
    let headlight = (camera.target - camera.eye).normalize();
    let m = Marcher::new(vol, tf, params, Some(headlight))?;
    let rays = RayLoop::for_frame(&m);
    let camera_rays = CameraRays::new(camera, width, height);
    let (color, samples) = tiled_frame(width, height, |x, y| {
        let (o, d) = camera_rays.ray(x as f32 + 0.5, y as f32 + 0.5);
        let t_max = depth.map_or(f32::INFINITY, |dd| dd[(y * width + x) as usize]);
        let j = if params.jitter { pixel_hash(x, y) } else { 0.0 };
        let traced = trace(&m, rays, o, d, t_max, j);
        (display_to_frame(traced.color), traced.samples)
    });
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

/// Every pixel of a `width × height` frame through `pixel(x, y)` (its colour and the
/// samples it took), in [`TILE`]-pixel square tiles across rayon's pool, written to the
/// frame in a fixed order: the result does not depend on the number of threads. Shared by
/// every per-pixel volume renderer (rays, distance-field surfaces, hypertexture).
pub(crate) fn tiled_frame(
    width: u32,
    height: u32,
    pixel: impl Fn(u32, u32) -> (Vec4, u64) + Sync,
) -> (Pixels, u64) {
    tiled_rows(width, height, |y, xs, color| {
        let mut samples = 0;
        for x in xs {
            let (c, n) = pixel(x, y);
            samples += n;
            color.push(c);
        }
        samples
    })
}

/// [`tiled_frame`] with each tile's row drawn by `row(y, xs, color)`: it pushes the colours
/// of pixels `xs` of row `y`, in order, onto `color` and returns the samples they took.
pub(crate) fn tiled_rows(
    width: u32,
    height: u32,
    row: impl Fn(u32, std::ops::Range<u32>, &mut Vec<Vec4>) -> u64 + Sync,
) -> (Pixels, u64) {
    let (w, h) = (width as usize, height as usize);
    let (tx, ty) = (w.div_ceil(TILE), h.div_ceil(TILE));
    let tiles: Vec<TilePixels> = (0..tx * ty)
        .into_par_iter()
        .map(|t| {
            let (x0, y0) = ((t % tx) * TILE, (t / tx) * TILE);
            let (x1, y1) = ((x0 + TILE).min(w), (y0 + TILE).min(h));
            let mut color = Vec::with_capacity((x1 - x0) * (y1 - y0));
            let mut samples = 0u64;
            for y in y0..y1 {
                samples += row(y as u32, x0 as u32..x1 as u32, &mut color);
            }
            TilePixels { color, samples }
        })
        .collect();
    let mut color = Pixels::zeroed(w * h);
    let mut samples = 0u64;
    for (t, tile) in tiles.iter().enumerate() {
        let (x0, y0) = ((t % tx) * TILE, (t / tx) * TILE);
        let tw = (x0 + TILE).min(w) - x0;
        for (r, row) in tile.color.chunks_exact(tw).enumerate() {
            color[(y0 + r) * w + x0..][..tw].copy_from_slice(row);
        }
        samples += tile.samples;
    }
    (color, samples)
}

/// One ray from `eye` along the unit `dir`, stopped at `t_max`, its samples offset by
/// `jitter` steps.
fn trace(m: &Marcher, rays: RayLoop, eye: Vec3, dir: Vec3, t_max: f32, jitter: f32) -> Traced {
    let ray = VoxelRay::new(&m.voxel_from_world, eye, dir);
    let Some(span) = clip_to_box(&ray, t_max, m.lo, m.hi) else {
        return Traced::NOTHING;
    };
    let step = m.p.step;
    match rays {
        RayLoop::Cells { normals } => {
            let s = RaySamples::by_reciprocal(ray, span, step, jitter);
            let light = m.headlight.unwrap_or(dir);
            match normals {
                Some(nv) => composite::cells::<true>(m, &s, light, nv),
                None => composite::cells::<false>(m, &s, light, &[]),
            }
        }
        RayLoop::CellsInLanes(grid) => composite_lanes::cells(
            m,
            &grid,
            &RaySamples::by_reciprocal(ray, span, step, jitter),
        ),
        RayLoop::ShadedInLanes(grid, nv) => shaded_lanes::cells(
            m,
            &grid,
            &RaySamples::by_reciprocal(ray, span, step, jitter),
            m.headlight.unwrap_or(dir),
            nv,
        ),
        RayLoop::Composite => composite::general(m, &RaySamples::new(ray, span, step, jitter), dir),
        RayLoop::Intensity => intensity::project(m, &RaySamples::new(ray, span, step, jitter)),
        RayLoop::Iso => iso::surface(m, &RaySamples::new(ray, span, step, jitter), dir),
    }
}
