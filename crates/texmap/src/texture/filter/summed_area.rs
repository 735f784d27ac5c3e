//! Summed-area tables (Crow 1984): a box filter over the footprint's bounding rectangle in
//! constant time.
//!
//! Precision: each level keeps, per channel, the running sums of texels quantized to 16-bit
//! fixed point (linear, premultiplied; float textures are first scaled by their largest value)
//! in `u32` with wrapping arithmetic. A box sum is a signed combination of table entries, and
//! modular arithmetic gives it exactly whenever the true sum fits in 32 bits, i.e. for any box
//! of up to 65,536 texels — on any texture size, an 8k or 16k texture included (a plain `f32`
//! table loses whole texels beyond 2^24/255 ≈ 65k texels). Larger boxes are read from the
//! coarsest level that keeps the box under that bound, where the box covers the same region.
//! Memory: 16 bytes per texel, built lazily on first use.
//!
//! The rectangle's fractional edges are honoured (the texture is integrated as piecewise
//! constant), and wrap modes extend the table analytically, so a box may straddle the edge of
//! a repeating texture.

use glam::{Vec2, Vec4};

use super::{bilinear, texel_derivatives, Codec};
use crate::texture::{Footprint, Sampler, Texture2D, Wrap};

/// The largest box (in texels) whose sum fits in `u32` at 16-bit precision.
const MAX_BOX: f32 = 65_536.0;
const ONE: f32 = 65_535.0;

/// One table per mip level.
#[derive(Clone, Debug)]
pub(crate) struct SummedAreaTables {
    levels: Vec<Table>,
    /// Multiply a table sum by this to get linear values.
    unscale: f32,
}

#[derive(Clone, Debug)]
struct Table {
    w: u32,
    h: u32,
    /// `(w+1)·(h+1)` entries: `sums[y·(w+1) + x]` = Σ of texels `[0, x) × [0, y)`.
    sums: Vec<[u32; 4]>,
}

impl SummedAreaTables {
    pub(crate) fn build(tex: &Texture2D) -> Self {
        let decoded: Vec<Vec<Vec4>> = (0..tex.levels().len())
            .map(|l| tex.decode_level(l))
            .collect();
        let max = if tex.format().is_unorm() {
            1.0
        } else {
            decoded
                .iter()
                .flatten()
                .map(|c| c.max_element())
                .fold(0.0f32, f32::max)
                .max(1e-30)
        };
        let scale = ONE / max;
        let levels = tex
            .levels()
            .iter()
            .zip(&decoded)
            .map(|(l, texels)| {
                let (w, h) = (l.width(), l.height());
                let stride = (w + 1) as usize;
                let mut sums = vec![[0u32; 4]; stride * (h + 1) as usize];
                for y in 0..h as usize {
                    let mut row = [0u32; 4];
                    for x in 0..w as usize {
                        let c = texels[y * w as usize + x];
                        for (k, r) in row.iter_mut().enumerate() {
                            let q = (c[k].clamp(0.0, max) * scale + 0.5) as u32;
                            *r = r.wrapping_add(q);
                        }
                        let above = sums[y * stride + x + 1];
                        sums[(y + 1) * stride + x + 1] =
                            std::array::from_fn(|k| above[k].wrapping_add(row[k]));
                    }
                }
                Table { w, h, sums }
            })
            .collect();
        SummedAreaTables {
            levels,
            unscale: max / ONE,
        }
    }
}

/// A prefix position on one axis, extended past the texture by its wrap mode, as a sum of
/// `coef × prefix(index)` terms plus a count of positions that read the border colour.
#[derive(Default)]
struct Extended {
    terms: [(i64, u32); 3],
    len: usize,
    border: i64,
}

impl Extended {
    fn push(&mut self, coef: i64, index: i64) {
        if coef != 0 && index != 0 {
            self.terms[self.len] = (coef, index as u32);
            self.len += 1;
        }
    }

    /// Positions `[0, x)` (negative x: minus the positions `[x, 0)`) on an axis of `n` texels.
    fn new(x: i64, n: i64, wrap: Wrap) -> Extended {
        let mut e = Extended::default();
        match wrap {
            Wrap::Repeat => {
                let (q, r) = (x.div_euclid(n), x.rem_euclid(n));
                e.push(q, n);
                e.push(1, r);
            }
            Wrap::MirroredRepeat => {
                let (q, r) = (x.div_euclid(2 * n), x.rem_euclid(2 * n));
                e.push(2 * q, n);
                if r <= n {
                    e.push(1, r);
                } else {
                    e.push(2, n);
                    e.push(-1, 2 * n - r);
                }
            }
            Wrap::ClampToEdge => e.clamp(x, n, 1),
            Wrap::MirrorClampToEdge => {
                if x >= 0 {
                    e.clamp(x, n, 1)
                } else {
                    e.clamp(-x, n, -1)
                }
            }
            Wrap::ClampToBorder => {
                let inside = x.clamp(0, n);
                e.push(1, inside);
                e.border = x - inside;
            }
        }
        e
    }

    /// `sign ×` the clamp-to-edge prefix of `x` positions.
    fn clamp(&mut self, x: i64, n: i64, sign: i64) {
        if x < 0 {
            self.push(sign * x, 1);
        } else if x <= n {
            self.push(sign, x);
        } else {
            // The last texel repeats x − n more times: (x−n)·(prefix(n) − prefix(n−1)).
            self.push(sign * (1 + x - n), n);
            self.push(-sign * (x - n), n - 1);
        }
    }
}

impl Table {
    #[inline]
    fn at(&self, x: u32, y: u32) -> [u32; 4] {
        self.sums[(y * (self.w + 1) + x) as usize]
    }

    /// The extended prefix sum over positions `[0, x) × [0, y)` (exact mod 2^32), plus the
    /// number of those positions that read the border colour.
    fn prefix(&self, ex: &Extended, x: i64, ey: &Extended, y: i64) -> ([u32; 4], i64) {
        let mut acc = [0u32; 4];
        for &(cx, ix) in &ex.terms[..ex.len] {
            for &(cy, iy) in &ey.terms[..ey.len] {
                let k = (cx * cy) as u32;
                let v = self.at(ix, iy);
                for c in 0..4 {
                    acc[c] = acc[c].wrapping_add(v[c].wrapping_mul(k));
                }
            }
        }
        // Border positions: x's border columns times all of y's, and so on.
        (acc, ex.border * y + x * ey.border - ex.border * ey.border)
    }
}

/// The texel boundaries around `[a, b]` (up to four) and the spans between them, as
/// `(start index, end index, coverage weight)`.
struct Spans {
    points: [i64; 4],
    n_points: usize,
    spans: [(usize, usize, f32); 3],
    n_spans: usize,
}

fn spans(a: f32, b: f32) -> Spans {
    let (ai, bi) = (a.floor() as i64, b.floor() as i64);
    let mut s = Spans {
        points: [0; 4],
        n_points: 0,
        spans: [(0, 0, 0.0); 3],
        n_spans: 0,
    };
    let point = |s: &mut Spans, p: i64| {
        if s.n_points == 0 || s.points[s.n_points - 1] != p {
            s.points[s.n_points] = p;
            s.n_points += 1;
        }
        s.n_points - 1
    };
    let span = |s: &mut Spans, from: i64, to: i64, w: f32| {
        if w > 0.0 {
            let (i, j) = (point(s, from), point(s, to));
            s.spans[s.n_spans] = (i, j, w);
            s.n_spans += 1;
        }
    };
    if ai == bi {
        span(&mut s, ai, ai + 1, b - a);
    } else {
        span(&mut s, ai, ai + 1, 1.0 - (a - ai as f32));
        if bi > ai + 1 {
            span(&mut s, ai + 1, bi, 1.0);
        }
        span(&mut s, bi, bi + 1, b - bi as f32);
    }
    s
}

pub(crate) fn sample<C: Codec>(tex: &Texture2D, s: &Sampler, fp: &Footprint) -> Vec4 {
    let (dx, dy) = texel_derivatives(tex, fp);
    // Half extents of the footprint parallelogram's bounding rectangle, in level-0 texels.
    let half = 0.5 * (dx.abs() + dy.abs());
    if !(half.max_element() > 0.5) || !half.is_finite() || !fp.uv.is_finite() {
        return bilinear::<C>(&tex.level(0), s, fp.uv);
    }
    let tables = tex.summed_area_tables();
    // The finest level where the box stays under the exact-sum bound.
    let mut level = 0usize;
    let mut h = half;
    while (2.0 * h.x + 2.0) * (2.0 * h.y + 2.0) > MAX_BOX && level + 1 < tables.levels.len() {
        level += 1;
        h *= 0.5;
    }
    let t = &tables.levels[level];
    let size = Vec2::new(t.w as f32, t.h as f32);
    // At least one texel wide on each axis, so the box never point-samples.
    let h = h.max(Vec2::splat(0.5));
    let c = fp.uv * size;
    let (lo, hi) = (c - h, c + h);
    let (xs, ys) = (spans(lo.x, hi.x), spans(lo.y, hi.y));
    // The extended prefix sums at every pair of boundaries (at most 4 × 4), then each span
    // pair's box from its four corners.
    let mut ex: [Extended; 4] = Default::default();
    let mut ey: [Extended; 4] = Default::default();
    for (e, &x) in ex.iter_mut().zip(&xs.points[..xs.n_points]) {
        *e = Extended::new(x, t.w as i64, s.wrap_u);
    }
    for (e, &y) in ey.iter_mut().zip(&ys.points[..ys.n_points]) {
        *e = Extended::new(y, t.h as i64, s.wrap_v);
    }
    let mut corners = [[([0u32; 4], 0i64); 4]; 4];
    for (i, e) in ex[..xs.n_points].iter().enumerate() {
        for (j, f) in ey[..ys.n_points].iter().enumerate() {
            corners[i][j] = t.prefix(e, xs.points[i], f, ys.points[j]);
        }
    }
    let mut sum = Vec4::ZERO;
    let mut border = 0.0f32;
    for &(x0, x1, wx) in &xs.spans[..xs.n_spans] {
        for &(y0, y1, wy) in &ys.spans[..ys.n_spans] {
            let (a, b, c, d) = (
                corners[x1][y1],
                corners[x0][y1],
                corners[x1][y0],
                corners[x0][y0],
            );
            let v: [u32; 4] = std::array::from_fn(|k| {
                a.0[k]
                    .wrapping_sub(b.0[k])
                    .wrapping_sub(c.0[k])
                    .wrapping_add(d.0[k])
            });
            let w = wx * wy;
            sum += Vec4::new(v[0] as f32, v[1] as f32, v[2] as f32, v[3] as f32) * w;
            border += (a.1 - b.1 - c.1 + d.1) as f32 * w;
        }
    }
    let area = (hi.x - lo.x) * (hi.y - lo.y);
    (sum * tables.unscale + s.border * border) / area
}
