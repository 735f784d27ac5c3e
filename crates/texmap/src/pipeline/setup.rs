//! Setup: primitive assembly (reject, clip, cull, orient, bound) and, per tile, the edge
//! functions of a triangle.
//!
//! Edge function of the edge a→b at p, in 1/256-pixel units (exact `i64`):
//! `E(p) = (b.x − a.x)(p.y − a.y) − (b.y − a.y)(p.x − a.x)`. Triangles are reordered so that
//! `E ≥ 0` inside for all three edges. Top-left rule (y down): a sample exactly on an edge is
//! inside only if the edge is a *top* edge (horizontal, `dx > 0`) or a *left* edge (`dy < 0`);
//! the others get a bias of −1. Adjacent triangles evaluate a shared edge with opposite
//! signs, exactly, so each sample belongs to exactly one of them.

use super::clip::{clip_polygon, ClipPolygon};
use super::transform::{outcode, view_sides, PostVertex, Viewport};
use super::transform::{ClipVertex, ScreenCall};
use super::{CullMode, Interpolation, SUBPIXEL_BITS};

/// Set in [`Prim::v`] when the vertex lives in the pool of vertices made by clipping and
/// subdivision rather than in the draw call's vertex buffer.
pub const EXTRA_VERTEX: u32 = 1 << 31;

/// Most split steps of one triangle in [`Interpolation::Subdivide`] (each splits one piece
/// into two to four). A safety net against absurd geometry: pieces left when it runs out are
/// drawn as they are, and only then may neighbours' shared edges disagree.
pub const MAX_SUBDIVISION: u32 = 1 << 16;

/// A triangle ready for binning and rasterization.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prim {
    /// Vertex references, ordered so the edge functions are positive inside.
    pub v: [u32; 3],
    /// Index of the draw call.
    pub call: u32,
    /// Covered pixel range, inclusive, clamped to the target: x0, y0, x1, y1.
    pub bbox: [i32; 4],
    /// The farthest window depth of the three vertices (painter's sort key).
    pub sort_depth: f32,
    pub front_facing: bool,
    /// Interpolate attributes screen-linearly.
    pub affine: bool,
}

/// Assembles triangle `idx` of `call`: rejects, clips, culls and (in subdivide mode) splits it,
/// appending the resulting [`Prim`]s and any new vertices (referenced with
/// [`EXTRA_VERTEX`] | index into `extra`).
pub fn assemble_triangle(
    call: &ScreenCall,
    call_index: u32,
    idx: [u32; 3],
    vp: &Viewport,
    interpolation: Interpolation,
    prims: &mut Vec<Prim>,
    extra: &mut Vec<PostVertex>,
) {
    let verts = &call.vertices;
    let (Some(a), Some(b), Some(c)) = (
        verts.get(idx[0] as usize),
        verts.get(idx[1] as usize),
        verts.get(idx[2] as usize),
    ) else {
        return;
    };
    let codes = [a.outcode, b.outcode, c.outcode];
    if codes.contains(&u8::MAX) {
        return;
    }
    // Trivially outside one plane of the view volume.
    let near_far = outcode::NEAR | outcode::FAR;
    if codes[0] & codes[1] & codes[2] & near_far != 0
        || view_sides(a.clip) & view_sides(b.clip) & view_sides(c.clip) != 0
    {
        return;
    }
    let cx = Assembly {
        call,
        call_index,
        vp,
        interpolation,
    };
    let any = (codes[0] | codes[1] | codes[2]) & outcode::CLIP;
    if any == 0 {
        cx.emit_or_split(idx, [a, b, c], prims, extra);
        return;
    }
    let n = call.state.varyings;
    let cv = |v: &PostVertex| ClipVertex {
        clip: v.clip,
        varyings: v.varyings,
    };
    let mut poly = ClipPolygon::triangle([cv(a), cv(b), cv(c)]);
    clip_polygon(&mut poly, any, vp, n);
    if poly.len < 3 {
        return;
    }
    let base = extra.len() as u32;
    for v in poly.vertices() {
        extra.push(PostVertex::new_clipped(v.clip, v.varyings, vp));
    }
    for k in 1..poly.len - 1 {
        let r = [base, base + k as u32, base + k as u32 + 1];
        let pv = [
            extra[r[0] as usize],
            extra[r[1] as usize],
            extra[r[2] as usize],
        ];
        if pv.iter().any(|v| v.outcode == u8::MAX) {
            continue;
        }
        let pv = [&pv[0], &pv[1], &pv[2]];
        cx.emit_or_split(r.map(|i| i | EXTRA_VERTEX), pv, prims, extra);
    }
}

/// What assembling one triangle needs to know of its draw and the frame.
struct Assembly<'a> {
    call: &'a ScreenCall<'a>,
    call_index: u32,
    vp: &'a Viewport,
    interpolation: Interpolation,
}

impl Assembly<'_> {
    fn emit_or_split(
        &self,
        r: [u32; 3],
        v: [&PostVertex; 3],
        prims: &mut Vec<Prim>,
        extra: &mut Vec<PostVertex>,
    ) {
        // Referenced, not copied: a vertex is some 140 bytes and most triangles are emitted
        // as they are.
        let Interpolation::Subdivide { max_error_px } = self.interpolation else {
            self.emit(r, v, self.interpolation == Interpolation::Affine, prims);
            return;
        };
        let v = v.map(|v| *v);
        // Every edge decides alone whether and where it splits (`split_point` reads only its
        // two ends, in a canonical order), so the triangles on either side of an edge split
        // it at the same points: no T-junctions. Breadth first, so a budget that runs out
        // leaves the pieces evenly refined.
        let n = self.call.state.varyings;
        let mut queue = std::collections::VecDeque::from([(r, v)]);
        let mut budget = MAX_SUBDIVISION;
        while let Some((r, v)) = queue.pop_front() {
            // Pieces entirely outside one side of the view cover no pixel.
            if view_sides(v[0].clip) & view_sides(v[1].clip) & view_sides(v[2].clip) != 0 {
                continue;
            }
            let split: [Option<PostVertex>; 3] = if budget == 0 {
                [None; 3]
            } else {
                std::array::from_fn(|k| {
                    split_point(&v[k], &v[(k + 1) % 3], max_error_px, n, self.vp)
                })
            };
            let count = split.iter().flatten().count();
            if count == 0 {
                self.emit(r, [&v[0], &v[1], &v[2]], true, prims);
                continue;
            }
            budget -= 1;
            // Vertex k, its reference, and the midpoint of edge k (from vertex k to k + 1).
            let mut mid = [(0u32, v[0]); 3];
            for k in 0..3 {
                if let Some(m) = split[k] {
                    mid[k] = (extra.len() as u32 | EXTRA_VERTEX, m);
                    extra.push(m);
                }
            }
            let vert = |k: usize| (r[k % 3], v[k % 3]);
            let mut piece = |p: [(u32, PostVertex); 3]| {
                queue.push_back((p.map(|x| x.0), p.map(|x| x.1)));
            };
            // The pieces keep the triangle's orientation.
            match count {
                1 => {
                    // Edge k (a → b) split at m: (a, m, c), (m, b, c).
                    let k = (0..3).find(|&k| split[k].is_some()).unwrap_or(0);
                    let (a, b, c, m) = (vert(k), vert(k + 1), vert(k + 2), mid[k]);
                    piece([a, m, c]);
                    piece([m, b, c]);
                }
                2 => {
                    // Edge k (c → a) whole; a → b split at m0, b → c at m1: the corner
                    // (m0, b, m1) and the quad (a, m0, m1, c) cut along its shorter diagonal
                    // (an edge inside this piece, so either choice is crack-free).
                    let k = (0..3).find(|&k| split[k].is_none()).unwrap_or(0);
                    let (c, a, b) = (vert(k), vert(k + 1), vert(k + 2));
                    let (m0, m1) = (mid[(k + 1) % 3], mid[(k + 2) % 3]);
                    piece([m0, b, m1]);
                    if screen_dist2(&a.1, &m1.1) <= screen_dist2(&m0.1, &c.1) {
                        piece([a, m0, m1]);
                        piece([a, m1, c]);
                    } else {
                        piece([a, m0, c]);
                        piece([m0, m1, c]);
                    }
                }
                _ => {
                    let (a, b, c) = (vert(0), vert(1), vert(2));
                    let (m0, m1, m2) = (mid[0], mid[1], mid[2]);
                    piece([a, m0, m2]);
                    piece([m0, b, m1]);
                    piece([m2, m1, c]);
                    piece([m0, m1, m2]);
                }
            }
        }
    }

    #[inline]
    fn emit(&self, r: [u32; 3], v: [&PostVertex; 3], affine: bool, prims: &mut Vec<Prim>) {
        let (x0, y0) = (v[0].sx as i64, v[0].sy as i64);
        let (x1, y1) = (v[1].sx as i64, v[1].sy as i64);
        let (x2, y2) = (v[2].sx as i64, v[2].sy as i64);
        let area2 = (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0);
        if area2 == 0 {
            return;
        }
        // Screen y points down, so counter-clockwise in NDC has a negative area here.
        let front_facing = (area2 < 0) != self.call.state.mirrored;
        match self.call.state.cull {
            CullMode::Back if !front_facing => return,
            CullMode::Front if front_facing => return,
            _ => {}
        }
        let vr = if area2 < 0 { [r[0], r[2], r[1]] } else { r };
        let (w, h) = (self.vp.width as i32, self.vp.height as i32);
        let s = SUBPIXEL_BITS;
        let bx0 = ((x0.min(x1).min(x2) >> s) as i32).max(0);
        let by0 = ((y0.min(y1).min(y2) >> s) as i32).max(0);
        let bx1 = ((x0.max(x1).max(x2) >> s) as i32).min(w - 1);
        let by1 = ((y0.max(y1).max(y2) >> s) as i32).min(h - 1);
        if bx0 > bx1 || by0 > by1 {
            return;
        }
        prims.push(Prim {
            v: vr,
            call: self.call_index,
            bbox: [bx0, by0, bx1, by1],
            sort_depth: v[0].z.max(v[1].z).max(v[2].z),
            front_facing,
            affine,
        });
    }
}

/// The affine error of edge a–b in pixels: the screen distance between where the edge
/// midpoint's attributes belong and where affine interpolation puts them,
/// `|w_a − w_b| / (2(w_a + w_b)) · length`. Symmetric in a and b, bit for bit.
fn edge_error_px(a: &PostVertex, b: &PostVertex) -> f32 {
    let (wa, wb) = (a.clip.w, b.clip.w);
    let dx = (b.sx - a.sx) as f32 / 256.0;
    let dy = (b.sy - a.sy) as f32 / 256.0;
    let len = (dx * dx + dy * dy).sqrt();
    (wa - wb).abs() / (2.0 * (wa + wb)) * len
}

/// Where edge a–b splits, if its affine error exceeds `max_error_px`: the point that projects
/// to the screen midpoint. Computed from the two ends in a canonical order (by clip
/// coordinates), so both triangles sharing the edge get the same position, bit for bit.
fn split_point(
    a: &PostVertex,
    b: &PostVertex,
    max_error_px: f32,
    n: usize,
    vp: &Viewport,
) -> Option<PostVertex> {
    if !(edge_error_px(a, b) > max_error_px) {
        return None;
    }
    let key = |v: &PostVertex| v.clip.to_array().map(f32::to_bits);
    let (lo, hi) = if key(a) <= key(b) { (a, b) } else { (b, a) };
    let m = midpoint(lo, hi, n, vp);
    (m.outcode != u8::MAX).then_some(m)
}

/// The point of edge a–b that projects to the screen midpoint: clip-space parameter
/// `t = w_a / (w_a + w_b)`.
fn midpoint(a: &PostVertex, b: &PostVertex, n: usize, vp: &Viewport) -> PostVertex {
    let t = a.clip.w / (a.clip.w + b.clip.w);
    let mut varyings = a.varyings;
    for (x, y) in varyings[..n].iter_mut().zip(&b.varyings[..n]) {
        *x += (y - *x) * t;
    }
    PostVertex::new_clipped(a.clip + (b.clip - a.clip) * t, varyings, vp)
}

/// Squared screen distance in 1/256 pixels (for choosing a diagonal).
fn screen_dist2(a: &PostVertex, b: &PostVertex) -> i64 {
    let (dx, dy) = ((b.sx - a.sx) as i64, (b.sy - a.sy) as i64);
    dx * dx + dy * dy
}

/// A triangle's three edge functions, evaluated at the centre of a reference pixel.
#[derive(Clone, Copy, Debug)]
pub struct Edges {
    /// `E_k` at the reference pixel centre, top-left bias included (inside ⇔ ≥ 0).
    pub e: [i64; 3],
    /// Change of `E_k` for one pixel to the right.
    pub dx: [i64; 3],
    /// Change of `E_k` for one pixel down.
    pub dy: [i64; 3],
}

impl Edges {
    /// Edge functions of the (positively oriented) triangle `v`, at the centre of pixel
    /// `(px, py)`. Edge `k` is opposite vertex `k`.
    #[must_use]
    pub fn new(v: [&PostVertex; 3], px: i32, py: i32) -> Self {
        let one = 1i64 << SUBPIXEL_BITS;
        let cx = px as i64 * one + one / 2;
        let cy = py as i64 * one + one / 2;
        let mut out = Edges {
            e: [0; 3],
            dx: [0; 3],
            dy: [0; 3],
        };
        for k in 0..3 {
            let a = v[(k + 1) % 3];
            let b = v[(k + 2) % 3];
            let (ax, ay) = (a.sx as i64, a.sy as i64);
            let (ex, ey) = (b.sx as i64 - ax, b.sy as i64 - ay);
            let top_left = (ey == 0 && ex > 0) || ey < 0;
            out.e[k] = ex * (cy - ay) - ey * (cx - ax) - i64::from(!top_left);
            out.dx[k] = -ey * one;
            out.dy[k] = ex * one;
        }
        out
    }

    /// `E_k` at an offset in 1/256 pixel from the reference sample position, per pixel step.
    #[inline]
    #[must_use]
    pub fn sample_offset(&self, k: usize, ox: i64, oy: i64) -> i64 {
        (self.dx[k] * ox + self.dy[k] * oy) >> SUBPIXEL_BITS
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::{DrawState, MAX_VARYINGS};
    use glam::Vec4;

    fn pv(x: f32, y: f32, vp: &Viewport) -> PostVertex {
        PostVertex::new(Vec4::new(x, y, 0.0, 1.0), [0.0; MAX_VARYINGS], vp)
    }

    fn assemble(verts: &[PostVertex], cull: CullMode, vp: &Viewport) -> Vec<Prim> {
        let call = ScreenCall {
            vertices: verts.to_vec(),
            indices: &[0, 1, 2],
            state: DrawState {
                cull,
                ..Default::default()
            },
        };
        let (mut prims, mut extra) = (Vec::new(), Vec::new());
        assemble_triangle(
            &call,
            0,
            [0, 1, 2],
            vp,
            Interpolation::Perspective,
            &mut prims,
            &mut extra,
        );
        prims
    }

    #[test]
    fn counter_clockwise_is_front_and_back_culling_removes_the_other() {
        let vp = Viewport::new(64, 64);
        let ccw = [pv(-0.5, -0.5, &vp), pv(0.5, -0.5, &vp), pv(0.0, 0.5, &vp)];
        let cw = [ccw[0], ccw[2], ccw[1]];
        let p = assemble(&ccw, CullMode::None, &vp);
        assert!(p[0].front_facing);
        assert_eq!(assemble(&ccw, CullMode::Back, &vp).len(), 1);
        assert_eq!(assemble(&cw, CullMode::Back, &vp).len(), 0);
        assert_eq!(assemble(&cw, CullMode::Front, &vp).len(), 1);
    }

    #[test]
    fn degenerate_and_nan_triangles_are_skipped() {
        let vp = Viewport::new(64, 64);
        let line = [pv(-0.5, -0.5, &vp), pv(0.5, 0.5, &vp), pv(0.0, 0.0, &vp)];
        assert!(assemble(&line, CullMode::None, &vp).is_empty());
        let nan = [pv(f32::NAN, 0.0, &vp), pv(0.5, 0.5, &vp), pv(0.0, 0.5, &vp)];
        assert!(assemble(&nan, CullMode::None, &vp).is_empty());
    }

    #[test]
    fn edges_are_positive_inside_and_opposite_on_shared_edges() {
        let vp = Viewport::new(64, 64);
        let q = [
            pv(-0.5, -0.5, &vp),
            pv(0.5, -0.5, &vp),
            pv(0.5, 0.5, &vp),
            pv(-0.5, 0.5, &vp),
        ];
        let p = assemble(&q[..3], CullMode::None, &vp);
        let t = p[0].v.map(|i| &q[i as usize]);
        let e = Edges::new(t, 40, 40);
        assert!(e.e.iter().all(|&x| x >= 0), "{:?}", e.e);
    }
}
