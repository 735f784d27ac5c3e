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
//! to 16 and are shaded together, which lets the shader overlap their work (`batch.rs`: with
//! one sample a pixel, consecutive primitives of a draw share a batch, a quad over a waiting
//! quad's pixel flushing it first; with more, a batch is one primitive's). Colour and depth
//! live in the tile buffer; the finished tile goes to the target's rows with streaming
//! stores.
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
//! Without a pre-pass, a tile whose first primitive to reach it covers every pixel of it,
//! opaque, writing depth below the clear depth (`tile_plan.rs`), is not cleared: that
//! primitive is drawn without the depth test, and its colours and depths replace whatever the
//! thread's tile buffer held (the plane's and large triangles' tiles; 4 % of the nearest
//! plane's instructions were the clear and the depth reads).
//!
//! MSAA sample positions are Direct3D's standard patterns (in 1/16 pixel from the centre),
//! exact in the 1/256-pixel fixed-point grid.

use glam::Vec4;

use super::batch::{Batch, Pending};
use super::bin::{Bins, TileRect};
use super::covered::{with_covered, Covered, CoveredQuad};
use super::framebuffer::{stream_fence, stream_fill, TileBuffer};
use super::interpolate::Planes;
use super::quad_edges::{QuadEdges, QuadStep};
use super::setup::{Edges, EXTRA_VERTEX};
use super::tile_plan::{could_hide, edge_range, owner, prepassed, quad_extent};
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
    pub(super) fn vertex(&self, call: &'a ScreenCall<'a>, r: u32) -> &'a PostVertex {
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
    let hide = buf.samples == 1 && could_hide(ctx, rect, prims);
    let owned = if buf.samples == 1 && !hide {
        owner(ctx, rect, prims)
    } else {
        None
    };
    if owned.is_none() {
        buf.clear(ctx.target.clear_color);
    }
    let (color, depth, zmin) = (&mut buf.color[..], &mut buf.depth[..], &mut buf.zmin[..]);
    match buf.samples {
        1 => {
            // The depth pre-pass, when two primitives or more could hide each other.
            if hide {
                zmin.fill(1.0);
                with_covered(|covered| {
                    let z = Depths {
                        zmin: &mut *zmin,
                        covered: Some(&mut *covered),
                        owned: None,
                    };
                    raster_prims::<1, true>(ctx, rect, prims, color, depth, z, &mut stats);
                    let z = Depths {
                        zmin,
                        covered: Some(covered),
                        owned: None,
                    };
                    raster_prims::<1, false>(ctx, rect, prims, color, depth, z, &mut stats);
                });
            } else {
                let z = Depths::owned(owned);
                raster_prims::<1, false>(ctx, rect, prims, color, depth, z, &mut stats);
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

/// The nearest depth per pixel of the pre-passed primitives (one sample a pixel, the depth
/// buffer's layout) and their covered quads, when this tile has a pre-pass.
struct Depths<'a> {
    zmin: &'a mut [f32],
    covered: Option<&'a mut Covered>,
    /// Without a pre-pass, the position of the primitive that owns the tile
    /// ([`owner`]): drawn without the depth test, which the tile's depths, not cleared,
    /// cannot answer.
    owned: Option<usize>,
}

impl Depths<'static> {
    /// No pre-pass.
    fn none() -> Self {
        Depths {
            zmin: &mut [],
            covered: None,
            owned: None,
        }
    }

    /// No pre-pass; the primitive at position `n` owns the tile.
    fn owned(n: Option<usize>) -> Self {
        Depths {
            owned: n,
            ..Depths::none()
        }
    }
}

/// Rasterizes `prims` into the tile's samples: sample `s` of tile pixel `(x, y)` is at
/// `(y·TILE + x)·S + s` in `color` and `depth`. With `PRE` (one sample a pixel), only the
/// pre-passed primitives ([`prepassed`]) are walked: their nearest depths go to `z.zmin`,
/// their covered quads to `z.covered`. After it (`z.covered` given, not `PRE`), those
/// primitives' kept quads are shaded where they reach `z.zmin` (module docs), the others
/// walked as without a pre-pass. With `z.owned` (one sample a pixel, no pre-pass), the
/// primitive at that position owns the tile ([`owner`]): its quads skip the depth test.
/// Compiled twice, for the CPU's level ([`crate::cpu`]).
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
    let Depths {
        zmin,
        mut covered,
        owned,
    } = z;
    let positions = sample_positions(S as u32);
    let tile = super::bin::TILE as usize;
    let mut batch = Batch::new();
    // The sample offsets a batch left waiting across primitives is flushed with: none is
    // read (with one sample a pixel a depth is the pixel's; with more, each primitive's
    // batch is flushed at its end, with its offsets).
    let no_offsets = [0.0f32; S];
    // Set up in place at a primitive's first covered quad (`Planes::set`: no copy, no
    // clearing of the unused varyings' planes).
    let mut planes = Planes::empty();
    for (n, &pi) in prims.iter().enumerate() {
        let prim = &ctx.prims[pi as usize];
        let call = &ctx.calls[prim.call as usize];
        let state = call.state;
        let depth_test = state.depth_test && owned != Some(n);
        // The tile's depths stay in the tile (only colour is resolved): the last primitive
        // walked writes depths nothing reads, and, not testing either (an owned tile's),
        // needs none.
        let write_depth = state.depth_write && n + 1 < prims.len();
        let need_z = PRE || S > 1 || depth_test || write_depth;
        let nearest = covered.is_some() && prepassed(ctx, pi);
        if PRE && !nearest {
            continue;
        }
        // A batch holds one draw's quads.
        if !PRE && batch.call().is_some_and(|c| c != prim.call) {
            batch.flush::<S>(ctx, &no_offsets, (&mut *color, &mut *depth), stats);
        }
        if !PRE {
            batch.begin_prim(prim.call);
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
                    (color, depth, write_depth),
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
        // Each quad's depth test, varyings and batch: `pmask` the covered pixels, `cov` their
        // samples (kept apart from the edge walk below, so that a rectangle inside every
        // edge is walked without stepping them; a macro, as a closure it was a call a quad).
        macro_rules! visit {
            ($qx:expr, $qy:expr, $valid_y:expr, $pmask:expr, $cov:expr) => {{
                let (qx, qy, valid_y, mut pmask, cov): (i32, i32, u8, u8, &[u32; 4]) =
                    ($qx, $qy, $valid_y, $pmask, $cov);
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
                    let zp = if need_z {
                        let z0 = pl.z.at(fx, fy);
                        [z0, z0 + pl.z.dx, z0 + pl.z.dy, z0 + pl.z.dx + pl.z.dy]
                    } else {
                        [0.0; 4]
                    };
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
                        // stay inside it at the tile's edges), after the waiting quads'
                        // writes to its pixels.
                        // (`pass` stays unset: with one sample the quad's mask says it.)
                        if batch.waits_on(lx, ly, pmask) {
                            batch.flush::<S>(ctx, &zoff, (&mut *color, &mut *depth), stats);
                        }
                        let nearer = if depth_test {
                            let i = ly * tile + lx;
                            let d = &depth[i..i + tile + 2];
                            let stored = Vec4::new(d[0], d[1], d[tile], d[tile + 1]);
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
                        let p = Pending {
                            lx: lx as u32,
                            ly: ly as u32,
                            pass,
                            zp,
                            write_depth,
                        };
                        if batch.push(prim, qmask, p, rect, pl) {
                            batch.flush::<S>(ctx, &zoff, (&mut *color, &mut *depth), stats);
                        }
                    }
                }
            }};
        }
        let mut qy = y0;
        while qy <= y1 {
            let valid_y = if qy + 1 < rect.y1 as i32 {
                0b1111
            } else {
                0b0011
            };
            if S == 1 && full {
                // Inside every edge: no tests, and no edges to step.
                let mut qx = x0;
                while qx <= x1 {
                    visit!(qx, qy, valid_y, 0b1111, &[all_samples; 4]);
                    qx += 2;
                }
            } else {
                let mut e = row;
                let mut quad_e = quad_row;
                let mut qx = x0;
                while qx <= x1 {
                    // Coverage of the four pixels' samples.
                    let mut cov = [all_samples; 4];
                    let mut pmask = 0b1111u8;
                    // (One sample a pixel here is a rectangle not inside every edge.)
                    if S == 1 {
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
                    visit!(qx, qy, valid_y, pmask, &cov);
                    for k in 0..3 {
                        e[k] += step_x[k];
                    }
                    quad_e.step(&quad_step_x);
                    qx += 2;
                }
            }
            for k in 0..3 {
                row[k] += step_y[k];
            }
            quad_row.step(&quad_step_y);
            qy += 2;
        }
        if !PRE && S > 1 {
            // Each sample's depth offset is the primitive's own.
            batch.flush::<S>(ctx, &zoff, (&mut *color, &mut *depth), stats);
        }
    }
    if !PRE {
        batch.flush::<S>(ctx, &no_offsets, (color, depth), stats);
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
/// shade, quad for quad, in the same order and batches (left waiting in `batch`).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn shade_kept(
    ctx: &RasterContext,
    rect: TileRect,
    prim: &Prim,
    v: [&PostVertex; 3],
    kept: Kept,
    (color, depth, write_depth): (&mut [Vec4], &mut [f32], bool),
    planes: &mut Planes,
    batch: &mut Batch,
    stats: &mut TileStats,
) {
    let state = ctx.calls[prim.call as usize].state;
    let tile = super::bin::TILE as usize;
    let zmin = kept.zmin;
    let mut have_planes = false;
    for q in kept.quads {
        let (lx, ly) = (usize::from(q.lx), usize::from(q.ly));
        // The waiting quads' writes to this quad's pixels first.
        if batch.waits_on(lx, ly, q.mask) {
            batch.flush::<1>(ctx, &[0.0], (&mut *color, &mut *depth), stats);
        }
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
            have_planes = true;
        }
        let p = Pending {
            lx: lx as u32,
            ly: ly as u32,
            pass: [0; 4],
            zp: q.zp,
            write_depth,
        };
        if batch.push(prim, qmask, p, rect, planes) {
            batch.flush::<1>(ctx, &[0.0], (&mut *color, &mut *depth), stats);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
