//! EWA for a rasterizer quad's four pixels, bit-identical to [`super::ewa`] read one pixel at
//! a time.
//!
//! The four pixels share their derivatives, so their ellipse, levels and quadratic form
//! ([`ewa::plan`], [`ewa::Form`]) are computed once per quad; only the centres differ. Each
//! pixel's level is then walked row by row over the ellipse's span, not its bounding box, four
//! texels of a row in lanes (`r²` and the table indices), the texels of a row read by index
//! arithmetic (the row's part once, no wrap per texel) where the span needs no border.
//!
//! Bit-identical: every step is the scalar loop's operation on the same values (`r²` as
//! `a·x·x + b·x·y + cc·y·y`, the table's weight, the sums over the pixel's texels in row-major
//! order; Rust does not contract `a·b + c` into FMAs), and the span holds every texel of the
//! box the scalar loop accepts (`r² < 1`). Each row's span solves the quadratic in f64 for
//! `r² < 1 + δ`, δ a bound on the f32 evaluation's rounding over the box, and widens it by a
//! texel; on a tilted 16:1 ellipse the box is about ten times the ellipse. Boxes at most
//! [`NARROW`] texels wide are walked whole; coordinates too large for the margin take the
//! scalar loop.
//!
//! Measured (callgrind, the 640×360 plane, one thread, instructions in `draw_frame`): the
//! scalar loop 1,140 M; these four pixels' texels fetched once over the union of their
//! ellipses with the four weights in lanes 1,161 M (the neighbours' ellipses overlap by about
//! a third along each axis, so the union held ~2× one ellipse and every texel paid for four
//! weights); per pixel spans with four texels in lanes 881 M; with the rows' index
//! arithmetic 785 M.

use glam::{Vec2, Vec4};

use super::ewa::{self, Form, Plan};
use super::{bilinear, floor_index, Codec};
use crate::texture::storage::LevelRef;
use crate::texture::{Footprint, Sampler, Texture2D, Wrap, BORDER};

/// [`ewa::sample`] for a quad's four pixels (pixel `j` at `(u[j], v[j])`, the derivatives
/// shared); pixels whose bit in `mask` is clear are left zero. Out of line: inlined into
/// `sample_quad_lanes` it cost the anisotropic quads 0.9% more instructions.
#[inline(never)]
pub(crate) fn sample_quad<C: Codec>(
    tex: &Texture2D,
    s: &Sampler,
    (u, v): (Vec4, Vec4),
    duv_dx: Vec2,
    duv_dy: Vec2,
    mask: u8,
    max_ecc: f32,
) -> [Vec4; 4] {
    let fp = Footprint::new(Vec2::ZERO, duv_dx, duv_dy);
    let Plan::Ellipse {
        dir,
        major,
        minor,
        d,
        f,
        last,
    } = ewa::plan(tex, s, &fp, max_ecc)
    else {
        let lv = tex.level(0);
        return std::array::from_fn(|j| {
            if mask & (1 << j) == 0 {
                Vec4::ZERO
            } else {
                bilinear::<C>(&lv, s, Vec2::new(u[j], v[j]))
            }
        });
    };
    let a = level_quad::<C>(
        &tex.level(d as usize),
        s,
        (u, v),
        &Form::new(dir, major, minor, d),
        mask,
    );
    if f <= 0.0 || d >= last {
        a
    } else {
        let b = level_quad::<C>(
            &tex.level(d as usize + 1),
            s,
            (u, v),
            &Form::new(dir, major, minor, d + 1.0),
            mask,
        );
        std::array::from_fn(|j| a[j].lerp(b[j], f))
    }
}

/// Coordinates (texels) beyond which the span's one-texel margin no longer covers the
/// rounding of `x − px`; such pixels take the scalar loop.
const LARGE: f32 = (1 << 20) as f32;

/// Boxes at most this wide are walked whole: solving for a row's span costs more than the
/// texels it would skip.
const NARROW: i32 = 4;

/// [`ewa::ewa_level`] for the four pixels of a quad on one level.
#[inline(always)]
fn level_quad<C: Codec>(
    lv: &LevelRef,
    s: &Sampler,
    (u, v): (Vec4, Vec4),
    form: &Form,
    mask: u8,
) -> [Vec4; 4] {
    // The span's tolerance: δ bounds the f32 rounding of r² over the box (a few ulps of its
    // largest term), far above f64's own.
    let (ad, bd, cd) = (f64::from(form.a), f64::from(form.b), f64::from(form.cc));
    let (ex, ey) = (f64::from(form.ext_x) + 1.0, f64::from(form.ext_y) + 1.0);
    let k = 1.0 + ad.abs() * ex * ex + bd.abs() * ex * ey + cd.abs() * ey * ey;
    let limit = 1.0 + k * f64::from(f32::EPSILON) * 16.0;
    let spans = Spans { ad, bd, cd, limit };
    std::array::from_fn(|j| {
        if mask & (1 << j) == 0 {
            return Vec4::ZERO;
        }
        let uv = Vec2::new(u[j], v[j]);
        level_one::<C>(lv, s, uv, form, &spans)
            .unwrap_or_else(|| ewa::ewa_level::<C>(lv, s, uv, form))
    })
}

/// A level's quadratic form in f64 and the bound `limit` (1 + δ) its row spans solve for.
struct Spans {
    ad: f64,
    bd: f64,
    cd: f64,
    limit: f64,
}

/// [`ewa::ewa_level`] at `uv`, row by row over the ellipse's spans, four texels of a row in
/// lanes: the same texels, weights and sums in the same order. `None` for coordinates or
/// boxes too large for the spans' margin (the caller takes the scalar loop).
#[inline(always)]
fn level_one<C: Codec>(
    lv: &LevelRef,
    s: &Sampler,
    uv: Vec2,
    form: &Form,
    spans: &Spans,
) -> Option<Vec4> {
    let &Form {
        a,
        b,
        cc,
        ext_x,
        ext_y,
    } = form;
    let px = uv.x * lv.w as f32 - 0.5;
    let py = uv.y * lv.h as f32 - 0.5;
    if !(ext_x < LARGE && ext_y < LARGE && px.abs() < LARGE && py.abs() < LARGE) {
        return None;
    }
    let (x0, x1) = (floor_index(px - ext_x) + 1, floor_index(px + ext_x));
    let (y0, y1) = (floor_index(py - ext_y) + 1, floor_index(py + ext_y));
    let narrow = x1 - x0 < NARROW;
    let table = ewa::weights();
    let (av, bv) = (Vec4::splat(a), Vec4::splat(b));
    let steps = Vec4::new(0.0, 1.0, 2.0, 3.0);
    let mut sum = Vec4::ZERO;
    let mut total = 0.0;
    for y in y0..=y1 {
        let ty = y as f32 - py;
        // The row's span: the box's, or the ellipse's chord widened by a texel.
        let (lo, hi) = if narrow {
            (x0, x1)
        } else {
            let t = f64::from(ty);
            let (qb, qc) = (spans.bd * t, spans.cd * t * t - spans.limit);
            let disc = qb * qb - 4.0 * spans.ad * qc;
            if !(disc >= 0.0) {
                continue;
            }
            let (mid, half) = (-qb / (2.0 * spans.ad), disc.sqrt() / (2.0 * spans.ad));
            let p = f64::from(px);
            let (l, h) = ((p + mid - half).floor(), (p + mid + half).ceil());
            if l.is_finite() && h.is_finite() {
                ((l.max(f64::from(x0))) as i32, (h.min(f64::from(x1))) as i32)
            } else {
                (x0, x1)
            }
        };
        if lo > hi {
            continue;
        }
        let yi = s.wrap_v.index(y, lv.h);
        // The row's texels by index arithmetic when the span reads them without a border:
        // inside the level every wrap mode reads the index itself, and a repeating span
        // shorter than the level is the level's columns from `lo mod w` on, wrapped once.
        let shift = if lo >= 0 && hi < lv.w {
            Some(0)
        } else if s.wrap_u == Wrap::Repeat && hi - lo < lv.w {
            Some(lo.rem_euclid(lv.w) - lo)
        } else {
            None
        };
        let direct = shift.filter(|_| yi != BORDER && !C::BLOCKS);
        let row = if direct.is_some() {
            lv.row_start(yi)
        } else {
            0
        };
        let fetch = |x: i32| {
            if let Some(shift) = direct {
                let xi = x + shift;
                let xi = if xi >= lv.w { xi - lv.w } else { xi };
                return lv.texel_at::<C>(row + lv.column(xi));
            }
            let xi = s.wrap_u.index(x, lv.w);
            if xi == BORDER || yi == BORDER {
                s.border
            } else {
                lv.texel::<C>(xi, yi)
            }
        };
        // The same value as the scalar loop's `cc·ty·ty` at every texel of the row.
        let tyy = cc * ty * ty;
        let (tyv, tyyv) = (Vec4::splat(ty), Vec4::splat(tyy));
        let mut x = lo;
        while x <= hi {
            // Four texels' r² and weights in lanes; the texels added one by one, in order.
            let tx = (Vec4::splat(x as f32) + steps) - px;
            let r2 = av * tx * tx + bv * tx * tyv + tyyv;
            let inside = r2.cmplt(Vec4::ONE).bitmask();
            let idx = super::truncate4(
                (r2 * (ewa::TABLE_SIZE - 1) as f32)
                    .max(Vec4::ZERO)
                    .min(Vec4::splat((ewa::TABLE_SIZE - 1) as f32)),
            );
            // The lanes inside the ellipse and the span, lowest (leftmost) first.
            let mut bits = inside & (0b1111 >> (3 - (hi - x).min(3)));
            while bits != 0 {
                let k = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let w = table[idx[k] as usize & (ewa::TABLE_SIZE - 1)];
                sum += fetch(x + k as i32) * w;
                total += w;
            }
            x += 4;
        }
    }
    Some(if total > 0.0 {
        sum / total
    } else {
        bilinear::<C>(lv, s, uv)
    })
}
