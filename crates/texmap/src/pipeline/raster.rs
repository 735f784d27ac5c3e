//! Raster: one tile, its primitives in draw order, 2×2 quads at a time.
//!
//! For each primitive: edge functions at the first quad of its bounding box (clipped to the
//! tile), stepped incrementally (three `i64` additions per quad). A quad's four pixels (and
//! their MSAA samples) are tested together; uncovered quads cost only the edge tests. The
//! attribute planes are set up lazily, at the first covered quad, so the many small triangles
//! that cover no pixel centre in this tile cost no plane setup. Before the quad loop the edge
//! functions are checked at the corners of the rectangle the quads span: a triangle outside
//! one edge there is skipped, and one inside all three (a large triangle over the tile) skips
//! the per-quad edge tests. Depth is tested per sample
//! before shading; the shader runs once per pixel per triangle (at the pixel centre) and its
//! colour goes to every covered sample that passed. Covered quads wait in a `Batch` of up
//! to 8 (one primitive's, so disjoint; `batch.rs`) and are shaded together, which lets the
//! shader overlap their work. Colour and depth live in the tile buffer; the finished tile
//! goes to the target's rows with streaming stores.
//!
//! With one sample a pixel, a tile with two or more primitives of draws that test and write
//! depth, do not blend and keep every pixel they shade ([`super::DrawState::keeps_all`]), not
//! all in one plane (pieces of one flat surface cannot hide each other), is rasterized
//! twice: a depth pre-pass finds those primitives' nearest depth per pixel, then their quads
//! are shaded only where they reach it (`z ≤` that depth, besides `z <` the stored one), so
//! hidden surfaces cost no shading. The first fragment at the nearest depth is still the one
//! kept: the image is the single pass's, ties and discarding draws included. The pre-pass
//! keeps the quads it covers (`covered.rs`), and the shading pass reads them back instead of
//! walking those primitives' coverage a second time.
//!
//! MSAA sample positions are Direct3D's standard patterns (in 1/16 pixel from the centre),
//! exact in the 1/256-pixel fixed-point grid.

use glam::Vec4;

use super::batch::{Batch, Pending};
use super::bin::{Bins, TileRect};
use super::covered::{with_covered, Covered, CoveredQuad};
use super::framebuffer::{stream_fence, stream_fill, TileBuffer};
use super::interpolate::{depth_plane, Plane, Planes};
use super::quad_edges::{QuadEdges, QuadStep};
use super::setup::{Edges, EXTRA_VERTEX};
use super::transform::PostVertex;
use super::transform::ScreenCall;
use super::{FragmentShader, Prim, Target};

/// Direct3D's standard sample positions for 1, 2, 4, 8 and 16 samples, in 1/16 pixel from
/// the pixel centre (x right, y down). Any other count gets the 1-sample pattern.
#[must_use]
pub fn sample_positions(samples: u32) -> &'static [(i8, i8)] {
    match samples {
        2 => &[(4, 4), (-4, -4)],
        4 => &[(-2, -6), (6, -2), (-6, 2), (2, 6)],
        8 => &[
            (1, -3),
            (-1, 3),
            (5, 1),
            (-3, -5),
            (-5, 5),
            (-7, -1),
            (3, 7),
            (7, -7),
        ],
        16 => &[
            (1, 1),
            (-1, -3),
            (-3, 2),
            (4, -1),
            (-5, -2),
            (2, 5),
            (5, 3),
            (3, -5),
            (-2, 6),
            (0, -7),
            (-4, -6),
            (-6, 4),
            (-8, 0),
            (7, -4),
            (6, 7),
            (-7, -8),
        ],
        _ => &[(0, 0)],
    }
}

/// Everything the tile rasterizer reads.
pub struct RasterContext<'a> {
    pub calls: &'a [ScreenCall<'a>],
    pub extra: &'a [PostVertex],
    pub prims: &'a [Prim],
    pub shader: &'a dyn FragmentShader,
    pub target: &'a Target,
}

impl<'a> RasterContext<'a> {
    #[inline(always)]
    fn vertex(&self, call: &'a ScreenCall<'a>, r: u32) -> &'a PostVertex {
        if r & EXTRA_VERTEX != 0 {
            &self.extra[(r & !EXTRA_VERTEX) as usize]
        } else {
            &call.vertices[r as usize]
        }
    }
}

/// What a tile cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TileStats {
    pub pixels_shaded: u64,
    pub texture_samples: u64,
}

/// Rasterizes tile `t` into `rows` (its rows of the target, top first, each the tile's width),
/// using `buf` (any previous content is cleared first); returns the stats.
pub fn rasterize_tile(
    ctx: &RasterContext,
    bins: &Bins,
    t: usize,
    buf: &mut TileBuffer,
    rows: &mut [&mut [Vec4]],
) -> TileStats {
    let mut stats = TileStats::default();
    let rect = bins.tile_rect(t);
    let prims = bins.tile_prims(t);
    if prims.is_empty() {
        for row in rows.iter_mut() {
            stream_fill(row, ctx.target.clear_color);
        }
        stream_fence();
        return stats;
    }
    // Colour and depth live in the tile buffer (in cache) and go to the target's rows once,
    // with streaming stores.
    buf.clear(ctx.target.clear_color);
    let (color, depth, zmin) = (&mut buf.color[..], &mut buf.depth[..], &mut buf.zmin[..]);
    match buf.samples {
        1 => {
            // The depth pre-pass, when two primitives or more could hide each other.
            if could_hide(ctx, rect, prims) {
                zmin.fill(1.0);
                with_covered(|covered| {
                    let z = Depths {
                        zmin: &mut *zmin,
                        covered: Some(&mut *covered),
                    };
                    raster_prims::<1, true>(ctx, rect, prims, color, depth, z, &mut stats);
                    let z = Depths {
                        zmin,
                        covered: Some(covered),
                    };
                    raster_prims::<1, false>(ctx, rect, prims, color, depth, z, &mut stats);
                });
            } else {
                raster_prims::<1, false>(
                    ctx,
                    rect,
                    prims,
                    color,
                    depth,
                    Depths::none(),
                    &mut stats,
                );
            }
        }
        2 => raster_prims::<2, false>(ctx, rect, prims, color, depth, Depths::none(), &mut stats),
        4 => raster_prims::<4, false>(ctx, rect, prims, color, depth, Depths::none(), &mut stats),
        8 => raster_prims::<8, false>(ctx, rect, prims, color, depth, Depths::none(), &mut stats),
        _ => raster_prims::<16, false>(ctx, rect, prims, color, depth, Depths::none(), &mut stats),
    }
    for (ly, row) in rows.iter_mut().enumerate() {
        buf.resolve_row(ly, row);
    }
    stream_fence();
    stats
}

/// The sample count a target asks for, as the rasterizer runs it (1, 2, 4, 8 or 16).
#[must_use]
pub fn sample_count(target: &Target) -> usize {
    match target.samples {
        2 | 4 | 8 | 16 => target.samples as usize,
        _ => 1,
    }
}

/// Whether primitive `pi` takes part in the depth pre-pass: its draw tests and writes depth,
/// does not blend and keeps every pixel it shades ([`super::DrawState::keeps_all`]).
#[inline]
fn prepassed(ctx: &RasterContext, pi: u32) -> bool {
    let state = ctx.calls[ctx.prims[pi as usize].call as usize].state;
    state.keeps_all && state.depth_test && state.depth_write && !state.blend
}

/// The quads' extent of `prim` in tile `rect`, `(x0, y0, x1, y1)` (`x0`, `y0` even, ends
/// inclusive): its bounding box clipped to the tile; `None` when they do not meet.
#[inline]
fn quad_extent(prim: &Prim, rect: TileRect) -> Option<(i32, i32, i32, i32)> {
    let x0 = prim.bbox[0].max(rect.x0 as i32) & !1;
    let y0 = prim.bbox[1].max(rect.y0 as i32) & !1;
    let x1 = prim.bbox[2].min(rect.x1 as i32 - 1);
    let y1 = prim.bbox[3].min(rect.y1 as i32 - 1);
    (x0 <= x1 && y0 <= y1).then_some((x0, y0, x1, y1))
}

/// The least and greatest value of edge `k` over the rectangle of pixel centres `ext_x` ×
/// `ext_y` pixels from the edges' reference pixel (edges are linear: at its corners).
#[inline]
fn edge_range(edges: &Edges, k: usize, ext_x: i64, ext_y: i64) -> (i64, i64) {
    let (ax, ay) = (edges.dx[k] * ext_x, edges.dy[k] * ext_y);
    (
        edges.e[k] + ax.min(0) + ay.min(0),
        edges.e[k] + ax.max(0) + ay.max(0),
    )
}

/// Whether primitive `pi` may cover a pixel centre of tile `rect`: false when its box misses
/// the tile or one edge is negative at every pixel centre of its quads there (the walk's own
/// skip at one sample a pixel).
fn reaches(ctx: &RasterContext, rect: TileRect, pi: u32) -> bool {
    let prim = &ctx.prims[pi as usize];
    let Some((x0, y0, x1, y1)) = quad_extent(prim, rect) else {
        return false;
    };
    let call = &ctx.calls[prim.call as usize];
    let v = prim.v.map(|r| ctx.vertex(call, r));
    let edges = Edges::new(v, x0, y0);
    let (ext_x, ext_y) = ((x1 - x0) as i64 | 1, (y1 - y0) as i64 | 1);
    (0..3).all(|k| edge_range(&edges, k, ext_x, ext_y).1 >= 0)
}

/// Whether the pre-passed primitives of tile `rect` could hide one another: two of them at
/// least reach it, and not all lie in one plane. Primitives that only share the tile's box
/// cannot hide each other, nor can the pieces of one flat surface (a clipped polygon's fan,
/// a quad's two triangles), which meet only along their edges: a pre-pass over them would
/// spare no shading. (The image is the same either way: the pre-pass only skips the
/// shading of what ends up hidden.)
fn could_hide(ctx: &RasterContext, rect: TileRect, prims: &[u32]) -> bool {
    let mut first: Option<Plane> = None;
    for &pi in prims {
        if !(prepassed(ctx, pi) && reaches(ctx, rect, pi)) {
            continue;
        }
        let prim = &ctx.prims[pi as usize];
        let call = &ctx.calls[prim.call as usize];
        let v = prim.v.map(|r| ctx.vertex(call, r));
        let z = depth_plane(v, rect.x0 as i32, rect.y0 as i32);
        match first {
            None => first = Some(z),
            Some(f) if !same_plane(f, z) => return true,
            Some(_) => {}
        }
    }
    false
}

/// Whether depth planes `a` and `b` (relative to a tile's first pixel) agree over the tile
/// within a few units in the last place of a depth near 1: one plane, set up from two
/// triangles' vertices.
fn same_plane(a: Plane, b: Plane) -> bool {
    let t = super::bin::TILE as f32;
    (a.c - b.c).abs() + t * ((a.dx - b.dx).abs() + (a.dy - b.dy).abs()) <= 4.0e-6
}

/// The nearest depth per pixel of the pre-passed primitives (one sample a pixel, the depth
/// buffer's layout) and their covered quads, when this tile has a pre-pass.
struct Depths<'a> {
    zmin: &'a mut [f32],
    covered: Option<&'a mut Covered>,
}

impl Depths<'static> {
    /// No pre-pass.
    fn none() -> Self {
        Depths {
            zmin: &mut [],
            covered: None,
        }
    }
}

/// Rasterizes `prims` into the tile's samples: sample `s` of tile pixel `(x, y)` is at
/// `(y·TILE + x)·S + s` in `color` and `depth`. With `PRE` (one sample a pixel), only the
/// pre-passed primitives ([`prepassed`]) are walked: their nearest depths go to `z.zmin`,
/// their covered quads to `z.covered`. After it (`z.covered` given, not `PRE`), those
/// primitives' kept quads are shaded where they reach `z.zmin` (module docs), the others
/// walked as without a pre-pass. Compiled twice, for the CPU's level ([`crate::cpu`]).
#[inline(always)]
fn raster_prims_in<const S: usize, const PRE: bool>(
    ctx: &RasterContext,
    rect: TileRect,
    prims: &[u32],
    color: &mut [Vec4],
    depth: &mut [f32],
    z: Depths,
    stats: &mut TileStats,
) {
    let Depths { zmin, mut covered } = z;
    let positions = sample_positions(S as u32);
    let tile = super::bin::TILE as usize;
    let mut batch = Batch::new();
    // Set up in place at a primitive's first covered quad (`Planes::set`: no copy, no
    // clearing of the unused varyings' planes).
    let mut planes = Planes::empty();
    for &pi in prims {
        let prim = &ctx.prims[pi as usize];
        let call = &ctx.calls[prim.call as usize];
        let state = call.state;
        let nearest = covered.is_some() && prepassed(ctx, pi);
        if PRE && !nearest {
            continue;
        }
        // Spelled out: `prim.v.map(…)` was an out-of-line call per primitive and pass.
        let v = [
            ctx.vertex(call, prim.v[0]),
            ctx.vertex(call, prim.v[1]),
            ctx.vertex(call, prim.v[2]),
        ];
        if let Some(cov) = covered.as_deref_mut() {
            if PRE {
                cov.begin_prim();
            } else if nearest {
                let quads = cov.next_prim();
                let z = Kept { zmin, quads };
                shade_kept(
                    ctx,
                    rect,
                    prim,
                    v,
                    z,
                    color,
                    depth,
                    &mut planes,
                    &mut batch,
                    stats,
                );
                continue;
            }
        }
        let Some((x0, y0, x1, y1)) = quad_extent(prim, rect) else {
            continue;
        };
        let edges = Edges::new(v, x0, y0);
        // Per-sample edge offsets (none with one sample, at the pixel centre).
        let mut soff = [[0i64; 3]; S];
        for (s, &(ox, oy)) in positions.iter().enumerate().take(S).filter(|_| S > 1) {
            for k in 0..3 {
                soff[s][k] = edges.sample_offset(k, ox as i64 * 16, oy as i64 * 16);
            }
        }
        let step_x = edges.dx.map(|d| 2 * d);
        let step_y = edges.dy.map(|d| 2 * d);
        let pix = [
            [0, 0, 0],
            edges.dx,
            edges.dy,
            [
                edges.dx[0] + edges.dy[0],
                edges.dx[1] + edges.dy[1],
                edges.dx[2] + edges.dy[2],
            ],
        ];
        // Whole-rectangle tests at the corners of the quads' extent (edges are linear):
        // outside one edge everywhere → skip; inside all edges everywhere → no per-quad tests.
        let ext_x = (x1 - x0) as i64 | 1;
        let ext_y = (y1 - y0) as i64 | 1;
        let mut full = true;
        let mut outside = false;
        for k in 0..3 {
            let (lo, hi) = edge_range(&edges, k, ext_x, ext_y);
            let s_lo = soff.iter().map(|o| o[k]).min().unwrap_or(0);
            let s_hi = soff.iter().map(|o| o[k]).max().unwrap_or(0);
            full &= lo + s_lo >= 0;
            outside |= hi + s_hi < 0;
        }
        if outside {
            continue;
        }
        let all_samples = if S >= 32 { u32::MAX } else { (1u32 << S) - 1 };
        let mut have_planes = false;
        let mut zoff = [0.0f32; S];
        let mut row = edges.e;
        // One sample a pixel: the four pixels' tests at once (quad_edges.rs).
        let (quad_step_x, quad_step_y) = (QuadStep::new(step_x), QuadStep::new(step_y));
        let mut quad_row = QuadEdges::new(edges.e, edges.dx, edges.dy);
        let mut qy = y0;
        while qy <= y1 {
            let mut e = row;
            let mut quad_e = quad_row;
            let mut qx = x0;
            let valid_y = if qy + 1 < rect.y1 as i32 {
                0b1111
            } else {
                0b0011
            };
            while qx <= x1 {
                // Coverage of the four pixels' samples.
                let mut cov = [all_samples; 4];
                let mut pmask = 0b1111u8;
                if S == 1 && !full {
                    pmask = quad_e.covered();
                    cov = std::array::from_fn(|j| u32::from(pmask >> j) & 1);
                }
                for j in 0..4 {
                    if full || S == 1 {
                        break;
                    }
                    if j == 0 {
                        pmask = 0;
                    }
                    let p = [e[0] + pix[j][0], e[1] + pix[j][1], e[2] + pix[j][2]];
                    let mut c = 0u32;
                    for (s, o) in soff.iter().enumerate() {
                        if (p[0] + o[0]) | (p[1] + o[1]) | (p[2] + o[2]) >= 0 {
                            c |= 1 << s;
                        }
                    }
                    cov[j] = c;
                    pmask |= u8::from(c != 0) << j;
                }
                let valid_x = if qx + 1 < rect.x1 as i32 {
                    0b1111
                } else {
                    0b0101
                };
                pmask &= valid_x & valid_y;
                if pmask != 0 {
                    if !have_planes {
                        if PRE {
                            // The pre-pass needs only depth (the same plane either way).
                            planes.set_depth(v, rect.x0 as i32, rect.y0 as i32);
                        } else {
                            planes.set(
                                v,
                                state.varyings,
                                !prim.affine,
                                rect.x0 as i32,
                                rect.y0 as i32,
                            );
                        }
                        for (s, &(ox, oy)) in positions.iter().enumerate().take(S) {
                            zoff[s] = (planes.z.dx * ox as f32 + planes.z.dy * oy as f32) / 16.0;
                        }
                        have_planes = true;
                    }
                    let pl = &planes;
                    let fx = (qx - rect.x0 as i32) as f32;
                    let fy = (qy - rect.y0 as i32) as f32;
                    let lx = (qx - rect.x0 as i32) as usize;
                    let ly = (qy - rect.y0 as i32) as usize;
                    let z0 = pl.z.at(fx, fy);
                    let zp = [z0, z0 + pl.z.dx, z0 + pl.z.dy, z0 + pl.z.dx + pl.z.dy];
                    let mut pass = [0u32; 4];
                    let mut qmask = 0u8;
                    if PRE {
                        // Only the nearest depth, and the quad kept for the shading pass:
                        // nothing is shaded (qmask stays 0).
                        let i = ly * tile + lx;
                        let near =
                            Vec4::new(zmin[i], zmin[i + 1], zmin[i + tile], zmin[i + tile + 1]);
                        // Without a branch per pixel (which mispredicts): the pixels that
                        // are not nearer get their own value back.
                        let z4 = Vec4::from_array(zp);
                        let covered_px = glam::BVec4A::new(
                            pmask & 1 != 0,
                            pmask & 2 != 0,
                            pmask & 4 != 0,
                            pmask & 8 != 0,
                        );
                        let nearest = Vec4::select(z4.cmplt(near) & covered_px, z4, near);
                        zmin[i] = nearest.x;
                        zmin[i + 1] = nearest.y;
                        zmin[i + tile] = nearest.z;
                        zmin[i + tile + 1] = nearest.w;
                        if let Some(cov) = covered.as_deref_mut() {
                            cov.push(CoveredQuad {
                                zp,
                                lx: lx as u8,
                                ly: ly as u8,
                                mask: pmask,
                            });
                        }
                    } else if S == 1 {
                        // One sample: the quad's four depths compared at once (the sample
                        // offset is zero; the tile buffer holds whole quads, so the reads
                        // stay inside it at the tile's edges).
                        // (`pass` stays unset: with one sample the quad's mask says it.)
                        let i = ly * tile + lx;
                        let d = &depth[i..i + tile + 2];
                        let stored = Vec4::new(d[0], d[1], d[tile], d[tile + 1]);
                        let nearer = if state.depth_test {
                            Vec4::from_array(zp).cmplt(stored).bitmask() as u8
                        } else {
                            0b1111
                        };
                        qmask = pmask & nearer;
                    }
                    for j in 0..4 {
                        if S == 1 || pmask & (1 << j) == 0 {
                            continue;
                        }
                        let base = ((ly + (j >> 1)) * tile + lx + (j & 1)) * S;
                        let mut ok = 0u32;
                        for s in 0..S {
                            if cov[j] & (1 << s) != 0 {
                                let z = zp[j] + zoff[s];
                                if !state.depth_test || z < depth[base + s] {
                                    ok |= 1 << s;
                                }
                            }
                        }
                        pass[j] = ok;
                        qmask |= u8::from(ok != 0) << j;
                    }
                    if qmask != 0 {
                        let p = Pending { lx, ly, pass, zp };
                        if batch.push(prim, qmask, p, rect, pl) {
                            batch.flush::<S>(ctx, prim.call, &zoff, color, depth, stats);
                        }
                    }
                }
                for k in 0..3 {
                    e[k] += step_x[k];
                }
                quad_e.step(&quad_step_x);
                qx += 2;
            }
            for k in 0..3 {
                row[k] += step_y[k];
            }
            quad_row.step(&quad_step_y);
            qy += 2;
        }
        if !PRE {
            batch.flush::<S>(ctx, prim.call, &zoff, color, depth, stats);
        }
    }
}

crate::cpu::dispatch! {
    /// [`raster_prims_in`] at the CPU's level.
    #[inline(never)]
    fn raster_prims<const S: usize, const PRE: bool>(
        ctx: &RasterContext,
        rect: TileRect,
        prims: &[u32],
        color: &mut [Vec4],
        depth: &mut [f32],
        z: Depths,
        stats: &mut TileStats,
    ) => raster_prims_in, raster_prims_v3
}

/// A pre-passed primitive's covered quads and the tile's nearest depths.
struct Kept<'a> {
    zmin: &'a [f32],
    quads: &'a [CoveredQuad],
}

/// Shades the quads the pre-pass kept of `prim` (vertices `v`), one sample a pixel, where they
/// pass the depth test and reach the nearest depth: what walking the primitive again would
/// shade, quad for quad, in the same order and batches.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn shade_kept(
    ctx: &RasterContext,
    rect: TileRect,
    prim: &Prim,
    v: [&PostVertex; 3],
    kept: Kept,
    color: &mut [Vec4],
    depth: &mut [f32],
    planes: &mut Planes,
    batch: &mut Batch,
    stats: &mut TileStats,
) {
    let state = ctx.calls[prim.call as usize].state;
    let tile = super::bin::TILE as usize;
    let zmin = kept.zmin;
    let mut have_planes = false;
    let mut zoff = [0.0f32; 1];
    for q in kept.quads {
        let (lx, ly) = (usize::from(q.lx), usize::from(q.ly));
        let i = ly * tile + lx;
        let zp = Vec4::from_array(q.zp);
        let (d, z) = (&depth[i..i + tile + 2], &zmin[i..i + tile + 2]);
        let stored = Vec4::new(d[0], d[1], d[tile], d[tile + 1]);
        let nearer = if state.depth_test {
            zp.cmplt(stored).bitmask() as u8
        } else {
            0b1111
        };
        let near = Vec4::new(z[0], z[1], z[tile], z[tile + 1]);
        // Shaded only where nothing pre-passed lies nearer.
        let qmask = q.mask & nearer & zp.cmple(near).bitmask() as u8;
        if qmask == 0 {
            continue;
        }
        if !have_planes {
            // At the first quad shaded: the same planes as at the first covered quad.
            planes.set(
                v,
                state.varyings,
                !prim.affine,
                rect.x0 as i32,
                rect.y0 as i32,
            );
            zoff[0] = (planes.z.dx * 0.0 + planes.z.dy * 0.0) / 16.0;
            have_planes = true;
        }
        let p = Pending {
            lx,
            ly,
            pass: [0; 4],
            zp: q.zp,
        };
        if batch.push(prim, qmask, p, rect, planes) {
            batch.flush::<1>(ctx, prim.call, &zoff, color, depth, stats);
        }
    }
    batch.flush::<1>(ctx, prim.call, &zoff, color, depth, stats);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_of_one_plane_share_it_and_other_planes_do_not() {
        use super::super::transform::Viewport;
        use super::super::MAX_VARYINGS;
        use glam::{Mat4, Vec3};
        // A ground plane seen at a grazing angle (the peers' plane), split into a fan of
        // triangles, against the same fan lifted a hundredth of a unit or tilted a little.
        let vp = Viewport::new(1920, 1080);
        let proj = Mat4::perspective_rh_gl(60f32.to_radians(), 16.0 / 9.0, 0.05, 1000.0)
            * Mat4::look_at_rh(Vec3::Y, Vec3::new(0.0, 0.0, -50.0), Vec3::Y);
        let vertex = |p: Vec3| PostVertex::new(proj * p.extend(1.0), [0.0; MAX_VARYINGS], &vp);
        let fan = |lift: f32, tilt: f32| {
            let points = [
                (-3.0, -4.0),
                (3.0, -4.0),
                (4.0, -12.0),
                (0.0, -30.0),
                (-5.0, -9.0),
            ];
            points
                .iter()
                .map(|&(x, z)| vertex(Vec3::new(x, lift + tilt * x, z)))
                .collect::<Vec<_>>()
        };
        let (px, py) = (896, 576);
        let plane = |v: &[PostVertex], k: usize| depth_plane([&v[0], &v[k], &v[k + 1]], px, py);
        let flat = fan(0.0, 0.0);
        for k in 1..4 {
            assert!(same_plane(plane(&flat, 1), plane(&flat, k)), "piece {k}");
        }
        for other in [fan(0.01, 0.0), fan(0.0, 0.001)] {
            assert!(!same_plane(plane(&flat, 1), plane(&other, 1)));
        }
    }

    #[test]
    fn sample_patterns_have_the_right_counts_and_stay_inside_the_pixel() {
        for n in [1u32, 2, 4, 8, 16] {
            let p = sample_positions(n);
            assert_eq!(p.len(), n as usize);
            assert!(p
                .iter()
                .all(|&(x, y)| (-8..8).contains(&x) && (-8..8).contains(&y)));
        }
    }
}
