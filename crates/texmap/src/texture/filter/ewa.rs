//! Heckbert's elliptical weighted average (EWA): `ewa-exact`, the reference that
//! [`super::ewa_probes`] (`ewa`) approximates.
//!
//! The footprint's ellipse (semi-axes along the derivatives' singular vectors) is convolved with a
//! reconstruction disc (a term added to the squared semi-axes, as Heckbert's thesis and pbrt add
//! 1), its eccentricity clamped so the minor axis is at least `major / e_max`, and every texel
//! inside is weighted by a Gaussian (`e^(−2r²) − e^(−2)`) read from a 128-entry table. The level
//! is chosen from the minor axis, and the two levels around it are blended.
//!
//! Radii: pbrt's choice (semi-axes = 1.0 × the derivatives, disc 1.0 texel²) blurs: on the
//! grazing plane at 640×360 it scored 28.4 dB (checker) and 31.9 dB (noise) against the
//! box-filtered ground truth. Semi-axes of 0.8 × the derivatives and a 0.5 texel² disc — a
//! Gaussian whose spread is closer to the pixel's box — scored 36.6 and 36.0 dB; those are the
//! constants below (measured with `examples/plane_filters.rs`).

use std::sync::OnceLock;

use glam::{Vec2, Vec4};

use super::{bilinear, ellipse_axes, fetch, floor_index, texel_derivatives, Codec};
use crate::texture::storage::LevelRef;
use crate::texture::{Footprint, Sampler, Texture2D};

pub(super) const TABLE_SIZE: usize = 128;
/// The ellipse's semi-axes as a multiple of the derivatives' singular values.
pub(super) const RADIUS: f32 = 0.8;
/// The reconstruction disc's squared radius in texels, added to the footprint's.
const RECONSTRUCTION: f32 = 0.5;
/// Gaussian falloff: weight = e^(−α r²) − e^(−α), r² ∈ [0, 1).
const ALPHA: f32 = 2.0;

pub(super) fn weights() -> &'static [f32; TABLE_SIZE] {
    static TABLE: OnceLock<[f32; TABLE_SIZE]> = OnceLock::new();
    TABLE.get_or_init(|| {
        let mut t = [0.0; TABLE_SIZE];
        for (i, w) in t.iter_mut().enumerate() {
            let r2 = i as f32 / (TABLE_SIZE - 1) as f32;
            *w = (-ALPHA * r2).exp() - (-ALPHA).exp();
        }
        t
    })
}

/// What a footprint's EWA read takes: shared by [`sample`] and the quad path in lanes
/// ([`super::ewa_lanes`]), which must choose exactly the same.
#[derive(Clone, Copy, Debug)]
pub(super) enum Plan {
    /// Magnification: one bilinear read of level 0.
    Bilinear,
    /// The ellipse (unit major direction, semi-axes in texels of level 0, eccentricity
    /// clamped) read on level `d`, blended with level `d + 1` by `f` unless `f ≤ 0` or `d` is
    /// the `last` level.
    Ellipse {
        dir: Vec2,
        major: f32,
        minor: f32,
        d: f32,
        f: f32,
        last: f32,
    },
}

/// The read a footprint with derivatives `duv_dx`, `duv_dy` takes (its `uv` is not used).
#[inline(always)]
pub(super) fn plan(tex: &Texture2D, s: &Sampler, fp: &Footprint, max_ecc: f32) -> Plan {
    let (dx, dy) = texel_derivatives(tex, fp);
    let (major_dir, major, mut minor) = ellipse_axes(dx, dy);
    if !(major > 1.0) || !major.is_finite() {
        // Magnification: the footprint is smaller than a texel.
        return Plan::Bilinear;
    }
    // Clamp ellipse eccentricity.
    let max_ecc = max_ecc.max(1.0);
    if minor * max_ecc < major {
        minor = major / max_ecc;
    }
    let last = (tex.levels().len() - 1) as f32;
    let lod = s
        .adjust_lod(crate::texture::footprint::fast_log2(minor))
        .clamp(0.0, last);
    let d = lod.floor();
    Plan::Ellipse {
        dir: major_dir,
        major,
        minor,
        d,
        f: lod - d,
        last,
    }
}

pub(crate) fn sample<C: Codec>(tex: &Texture2D, s: &Sampler, fp: &Footprint, max_ecc: f32) -> Vec4 {
    let Plan::Ellipse {
        dir,
        major,
        minor,
        d,
        f,
        last,
    } = plan(tex, s, fp, max_ecc)
    else {
        return bilinear::<C>(&tex.level(0), s, fp.uv);
    };
    let a = ewa_level::<C>(
        &tex.level(d as usize),
        s,
        fp.uv,
        &Form::new(dir, major, minor, d),
    );
    if f <= 0.0 || d >= last {
        a
    } else {
        a.lerp(
            ewa_level::<C>(
                &tex.level(d as usize + 1),
                s,
                fp.uv,
                &Form::new(dir, major, minor, d + 1.0),
            ),
            f,
        )
    }
}

/// The ellipse on one level as the quadratic form `r² = a·x² + b·x·y + cc·y²` of texel
/// offsets `(x, y)` from its centre, and the half-extents of its bounding box (`r² = 1`).
#[derive(Clone, Copy, Debug)]
pub(super) struct Form {
    pub a: f32,
    pub b: f32,
    pub cc: f32,
    pub ext_x: f32,
    pub ext_y: f32,
}

impl Form {
    /// The form of the ellipse with unit major direction `dir` and semi-axes `major`, `minor`
    /// (texels of level 0) on level `level`.
    #[inline(always)]
    pub(super) fn new(dir: Vec2, major: f32, minor: f32, level: f32) -> Form {
        let scale = (-level).exp2();
        // Semi-axes on this level, convolved with the one-texel reconstruction disc.
        let (r1, r2) = (RADIUS * major * scale, RADIUS * minor * scale);
        let (q1, q2) = (
            1.0 / (r1 * r1 + RECONSTRUCTION),
            1.0 / (r2 * r2 + RECONSTRUCTION),
        );
        let (c, sn) = (dir.x, dir.y);
        let a = q1 * c * c + q2 * sn * sn;
        let b = 2.0 * (q1 - q2) * c * sn;
        let cc = q1 * sn * sn + q2 * c * c;
        // Bounding box of the ellipse r² = 1.
        let det = 4.0 * a * cc - b * b;
        Form {
            a,
            b,
            cc,
            ext_x: (4.0 * cc / det).sqrt(),
            ext_y: (4.0 * a / det).sqrt(),
        }
    }
}

/// The weight of a texel at `r2 < 1` from the table.
#[inline(always)]
pub(super) fn weight(table: &[f32; TABLE_SIZE], r2: f32) -> f32 {
    table[((r2 * (TABLE_SIZE - 1) as f32) as usize).min(TABLE_SIZE - 1)]
}

/// The Gaussian-weighted average over the ellipse `form` centred at `uv` on one level.
pub(super) fn ewa_level<C: Codec>(lv: &LevelRef, s: &Sampler, uv: Vec2, form: &Form) -> Vec4 {
    let &Form {
        a,
        b,
        cc,
        ext_x,
        ext_y,
    } = form;
    let px = uv.x * lv.w as f32 - 0.5;
    let py = uv.y * lv.h as f32 - 0.5;
    let (x0, x1) = (floor_index(px - ext_x) + 1, floor_index(px + ext_x));
    let (y0, y1) = (floor_index(py - ext_y) + 1, floor_index(py + ext_y));
    let table = weights();
    let mut sum = Vec4::ZERO;
    let mut total = 0.0;
    for y in y0..=y1 {
        let ty = y as f32 - py;
        for x in x0..=x1 {
            let tx = x as f32 - px;
            let r2 = a * tx * tx + b * tx * ty + cc * ty * ty;
            if r2 < 1.0 {
                let w = weight(table, r2);
                sum += fetch::<C>(lv, s, x, y) * w;
                total += w;
            }
        }
    }
    if total > 0.0 {
        sum / total
    } else {
        bilinear::<C>(lv, s, uv)
    }
}
