//! Composite mode: classify the samples of a ray and composite them front to back.
//!
//! Rules:
//! - `C += (1 − A)·α·c`, `A += (1 − A)·α`, with `α = 1 − (1 − a)^step` (opacity per unit
//!   length, VTK's unit distance 1, corrected in the table). A ray stops once
//!   `A ≥ early_termination`.
//! - The common case (post-classification, no gradient opacity, plain reads) runs
//!   [`cells`], specialised at compile time for shading on or off, which reads a cell's eight
//!   voxels (and normals) once per cell ([`CellCache`]); unshaded, it composites premultiplied
//!   table entries with one 4-wide multiply-add. Every other case runs [`general`], with the
//!   same samples.
//! - Shaded, [`cells`] blends the cell's eight normals in lanes (one `Vec4` per corner) and
//!   raises the specular term by inline squaring: the same bits as the scalar code, about a
//!   third of the shaded frame's instructions fewer with the lanes of `cell` and `bricks`.
//! - A variant of [`cells`] that kept four samples in flight (independent load → interpolate
//!   → table chains) measured no faster, so the simpler loop stays. With AVX2,
//!   [`super::composite_lanes`] (unshaded) and [`super::shaded_lanes`] (shaded by the
//!   headlight with a whole specular power) run instead: eight samples in lanes, the same
//!   bits. This loop runs for CPUs without AVX2, `TEXMAP_CPU=baseline` and scene lights.
//! - Pre-classification classifies the eight voxels and interpolates premultiplied colour;
//!   pre-integration classifies each segment between two samples from its table, and starts
//!   again (no segment) after a skipped brick.

use glam::{Vec3, Vec4};

use super::bricks::BrickCursor;
use super::cell::{blend_cell, corners_at, voxel_count, Cell, Locator, XPairs};
use super::marcher::{Marcher, Traced};
use super::normals::{direction_or_zero_lanes, normal_lanes, trilinear_normal};
use super::params::Classification;
use super::rays::RaySamples;
use super::transfer::gradient_factor;

/// The eight voxels of the last cell a ray read: at half-voxel steps about every other
/// sample stays in the same cell, and then skips the eight loads. Values and normals are
/// blended in lanes ([`XPairs`], [`normal_lanes`]), the same bits as the plain reads.
struct CellCache {
    /// The grid's cells (`None`: a side is zero, nothing to read).
    grid: Option<Locator>,
    /// The cell last read ([`Cell::index`], `usize::MAX` before the first).
    index: usize,
    corners: XPairs,
    /// The last sample's position inside the cell.
    frac: Vec3,
    /// The cell whose normals `normals` holds.
    normals_of: usize,
    normals: [Vec4; 8],
}

impl CellCache {
    fn new(dims: [u32; 3]) -> Self {
        CellCache {
            grid: (!dims.contains(&0)).then(|| Locator::new(dims)),
            index: usize::MAX,
            corners: XPairs::new([0.0; 8]),
            frac: Vec3::ZERO,
            normals_of: usize::MAX,
            normals: [Vec4::ZERO; 8],
        }
    }

    /// Trilinear level at `p`, equal to [`super::cell::trilinear`].
    #[inline(always)]
    fn value(&mut self, data: &[u16], dims: [u32; 3], p: Vec3) -> f32 {
        let Some(grid) = &self.grid else {
            return 0.0;
        };
        // The length check is done below, once per new cell.
        let cell = grid.locate(p);
        self.frac = cell.frac;
        if cell.index != self.index {
            if data.len() < voxel_count(dims) {
                return 0.0;
            }
            // SAFETY: `data` holds every voxel of the grid (checked above).
            self.corners = XPairs::new(unsafe { cell.corners(data, f32::from) });
            self.index = cell.index;
        }
        self.corners.blend(cell.frac)
    }

    /// The interpolated normal of the cell last passed to [`Self::value`], as
    /// [`trilinear_normal`] at that point.
    #[inline(always)]
    fn normal(&mut self, normals: &[[i8; 4]], dims: [u32; 3]) -> Vec3 {
        if self.normals_of != self.index {
            if normals.len() < voxel_count(dims) {
                return Vec3::ZERO;
            }
            let cell = Cell {
                index: self.index,
                strides: Cell::strides(dims),
                frac: self.frac,
            };
            // SAFETY: the cell was located on this grid (in `value`), and `normals` holds
            // every voxel of it (checked above).
            self.normals = unsafe { cell.corners(normals, normal_lanes) };
            self.normals_of = self.index;
        }
        direction_or_zero_lanes(blend_cell(&self.normals, self.frac))
    }
}

/// The common case: post-classification, no gradient opacity, plain reads; shaded from the
/// voxel `normals` along `light` when `SHADE`. One sample at a time.
pub(crate) fn cells<const SHADE: bool>(
    m: &Marcher,
    s: &RaySamples,
    light: Vec3,
    normals: &[[i8; 4]],
) -> Traced {
    let (mut rgb, mut a) = (Vec3::ZERO, 0.0f32);
    let (mut k, mut taken) = (0u32, 0u64);
    let stop = m.p.early_termination;
    let mut bricks = BrickCursor::new(s, &m.empty);
    let mut cell = CellCache::new(m.dims);
    let mut acc = Vec4::ZERO;
    while k < s.count {
        let q = s.at(k);
        if let Some(next) = bricks.skip(q, k) {
            k = next;
            continue;
        }
        taken += 1;
        let level = cell.value(m.data, m.dims, q);
        if !SHADE {
            acc += m.classify_premultiplied(level) * (1.0 - acc.w);
            if acc.w >= stop {
                break;
            }
            k += 1;
            continue;
        }
        let c = m.classify(level);
        if c.w > 0.0 {
            let col = m.shade(c.truncate(), cell.normal(normals, m.dims), light, q);
            let w = (1.0 - a) * c.w;
            rgb += col * w;
            a += w;
            if a >= stop {
                break;
            }
        }
        k += 1;
    }
    let color = if SHADE { rgb.extend(a) } else { acc };
    Traced {
        color,
        samples: taken,
    }
}

/// Every other composite case (pre-classification, pre-integration, gradient opacity, reads
/// through the texture engine), with the samples of [`cells`]; `dir` is the world ray's
/// direction (the light when there is no headlight).
pub(crate) fn general(m: &Marcher, s: &RaySamples, dir: Vec3) -> Traced {
    let mut rgb = Vec3::ZERO;
    let mut a = 0.0f32;
    let mut taken = 0u64;
    let shade = m.p.shade;
    let grad_op = !m.p.gradient_opacity.is_empty();
    let mut k = 0u32;
    let mut prev: Option<f32> = None;
    let mut bricks = BrickCursor::new(s, &m.empty);
    while k < s.count {
        let q = s.at(k);
        if let Some(next) = bricks.skip(q, k) {
            k = next;
            prev = None;
            continue;
        }
        taken += 1;
        let (c, alpha) = match m.p.classification {
            Classification::Post => {
                let c = m.classify(m.value(q));
                (c.truncate(), c.w)
            }
            Classification::Pre => pre_classified(m, q),
            Classification::PreIntegrated => {
                let v = m.value(q);
                let sf = prev.unwrap_or(v);
                prev = Some(v);
                let s = m
                    .pre_int
                    .as_ref()
                    .map_or(Vec4::ZERO, |p| p.get(m.vol.value_of(sf), m.vol.value_of(v)));
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
                let g = m.gradient(q);
                alpha *= gradient_factor(&m.p.gradient_opacity, g.length());
                if shade {
                    c = m.shade(c, g, m.headlight.unwrap_or(dir), q);
                }
            } else if let Some(nv) = m.normals {
                c = m.shade(
                    c,
                    trilinear_normal(nv, m.dims, q),
                    m.headlight.unwrap_or(dir),
                    q,
                );
            }
            let w = (1.0 - a) * alpha;
            rgb += c * w;
            a += w;
            if a >= m.p.early_termination {
                break;
            }
        }
        k += 1;
    }
    Traced {
        color: rgb.extend(a),
        samples: taken,
    }
}

/// Pre-classification: classify the eight voxels, interpolate premultiplied RGBA; straight
/// colour and opacity.
fn pre_classified(m: &Marcher, q: Vec3) -> (Vec3, f32) {
    let Some(cell) = corners_at(m.data, m.dims, q, f32::from) else {
        return (Vec3::ZERO, 0.0);
    };
    let f = cell.frac;
    let mut acc = Vec4::ZERO;
    for (corner, &level) in cell.values.iter().enumerate() {
        let (cx, cy, cz) = (corner & 1, (corner >> 1) & 1, corner >> 2);
        let c = m.classify(level);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::cell::trilinear;

    /// A `n³` grid of pseudo-random levels and normals (some zero, some disagreeing).
    fn grid(n: u32) -> (Vec<u16>, Vec<[i8; 4]>) {
        let mut r = crate::xorshift(0x2545_f491);
        let count = (n * n * n) as usize;
        let levels = (0..count).map(|_| r() as u16).collect();
        let normals = (0..count)
            .map(|_| {
                let v = r();
                if v.is_multiple_of(7) {
                    [0; 4]
                } else {
                    [(v >> 8) as i8, (v >> 16) as i8, (v >> 24) as i8, 0]
                }
            })
            .collect();
        (levels, normals)
    }

    #[test]
    fn cached_cells_in_lanes_give_the_bits_of_the_plain_reads() {
        let (n, dims) = (7, [7, 7, 7]);
        let (levels, normals) = grid(n);
        let mut cell = CellCache::new(dims);
        let mut s = 99u32;
        let mut r = move || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 8) as f32 / (1u32 << 24) as f32
        };
        for _ in 0..200 {
            // A ray across the box (and past it, clamped), at half-voxel steps.
            let o = Vec3::new(r(), r(), r()) * 8.0 - 0.5;
            let d = (Vec3::new(r(), r(), r()) - 0.5).normalize_or(Vec3::X) * 0.5;
            for k in 0..30 {
                let q = o + d * k as f32;
                let v = cell.value(&levels, dims, q);
                assert_eq!(v.to_bits(), trilinear(&levels, dims, q).to_bits(), "{q}");
                let g = cell.normal(&normals, dims);
                assert_eq!(g, trilinear_normal(&normals, dims, q), "{q}");
            }
        }
    }
}
