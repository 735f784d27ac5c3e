//! Anisotropic filtering: trilinear taps spread along the footprint's major axis.
//!
//! The footprint's ellipse comes from the derivatives (its axes are the singular vectors of
//! the Jacobian, not just the longer derivative as in the GL extension's sketch). With the
//! major semi-axis σ₁ and minor σ₂ in texels, `N = min(⌈σ₁/σ₂⌉, max_aniso)` taps sit at the
//! centres of N equal segments of the major axis, each a trilinear read at λ = log2(σ₁/N), so
//! together they cover the footprint without gaps; when the ratio exceeds `max_aniso` the level
//! rises and the image blurs instead of aliasing, as the extension specifies.
//!
//! Two paths share that plan ([`plan`]): [`sample`] reads one footprint in float, for every
//! storage; [`sample_quad`] reads a rasterizer quad's four pixels (which share their
//! derivatives, so their tap count, level and axis) in lanes on the default 16-bit storage,
//! each tap a fixed-point trilinear read ([`super::fixed16::read_probes`]) — as many taps as the
//! quad's eccentricity needs, one for an isotropic footprint. A batch of quads plans four
//! quads at a time in lanes ([`quad_plans4`], the same plans) and reads them after: the
//! plans' square roots, divisions and logarithms no longer wait one after another between
//! the reads.

use glam::{Vec2, Vec4};

use std::sync::OnceLock;

use super::fixed16::{ProbeSets, MAX_PROBES};
use super::{
    bilinear, ellipse_axes, ellipse_axes4, fixed16, texel_derivatives, trilinear_at, Codec,
};
use crate::texture::{Footprint, MipChoice, QuadCoords, Sampler, Texture2D};

/// What a footprint's anisotropic read takes.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Plan {
    /// Magnification: one bilinear read of level 0.
    Bilinear,
    /// A degenerate (infinite) footprint: one trilinear read at this λ.
    Trilinear(f32),
    /// `taps` trilinear reads on the levels `choice` names, at the centres of equal segments
    /// of `axis_uv` (the major axis, end to end, in texture coordinates).
    Taps {
        choice: MipChoice,
        axis_uv: Vec2,
        taps: u32,
    },
}

/// The read a footprint with derivatives `duv_dx`, `duv_dy` takes.
#[inline(always)]
fn plan(tex: &Texture2D, s: &Sampler, fp: &Footprint, max_aniso: u32) -> Plan {
    let (dx, dy) = texel_derivatives(tex, fp);
    let (major_dir, major, minor) = ellipse_axes(dx, dy);
    let max_aniso = max_aniso.clamp(1, 16) as f32;
    let ratio = if minor > 0.0 {
        major / minor
    } else {
        f32::INFINITY
    };
    let n = ratio.ceil().clamp(1.0, max_aniso);
    let lod = s.adjust_lod(crate::texture::footprint::fast_log2(major / n));
    if !(major > 1.0) || !(lod > 0.0) && n == 1.0 {
        return Plan::Bilinear;
    }
    if !major.is_finite() {
        return Plan::Trilinear(lod);
    }
    let size = Vec2::new(tex.width() as f32, tex.height() as f32);
    Plan::Taps {
        // Every tap reads the same levels: chosen once.
        choice: MipChoice::trilinear(lod, tex.levels().len()),
        axis_uv: major_dir * major / size,
        taps: n as u32,
    }
}

/// The offset along the axis (in [−½, ½]) of tap `i` of `n`.
#[inline(always)]
fn offset(i: u32, n: f32) -> f32 {
    (i as f32 + 0.5) / n - 0.5
}

pub(crate) fn sample<C: Codec>(
    tex: &Texture2D,
    s: &Sampler,
    fp: &Footprint,
    max_aniso: u32,
) -> Vec4 {
    let (choice, axis_uv, taps) = match plan(tex, s, fp, max_aniso) {
        Plan::Bilinear => return bilinear::<C>(&tex.level(0), s, fp.uv),
        Plan::Trilinear(lod) => return trilinear_at::<C>(tex, s, fp.uv, lod),
        Plan::Taps {
            choice,
            axis_uv,
            taps,
        } => (choice, axis_uv, taps),
    };
    let n = taps as f32;
    let first = tex.level(choice.level);
    let second = choice.blend.map(|b| (tex.level(b.level), b.weight));
    let mut sum = Vec4::ZERO;
    for i in 0..taps {
        let uv = fp.uv + axis_uv * offset(i, n);
        let a = bilinear::<C>(&first, s, uv);
        sum += match second {
            Some((lv, weight)) => a.lerp(bilinear::<C>(&lv, s, uv), weight),
            None => a,
        };
    }
    sum / n
}

/// [`sample`] for a quad's four pixels (pixel `j` at `(u[j], v[j])`, the derivatives shared)
/// in lanes, in fixed point: `None` where [`fixed16`] does not serve the texture and sampler.
/// Pixels whose bit in `mask` is clear are left zero.
#[inline(always)]
pub(crate) fn sample_quad(
    tex: &Texture2D,
    s: &Sampler,
    uv: (Vec4, Vec4),
    duv_dx: Vec2,
    duv_dy: Vec2,
    mask: u8,
    max_aniso: u32,
) -> Option<[Vec4; 4]> {
    read_quad(
        tex,
        s,
        uv,
        &quad_plan(tex, s, duv_dx, duv_dy, max_aniso),
        mask,
    )
}

/// A quad's plan for [`read_quad`]: the levels its taps read, the major axis (end to end, in
/// texture coordinates) and the tap count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct QuadPlan {
    choice: MipChoice,
    axis_uv: Vec2,
    taps: u32,
}

impl QuadPlan {
    /// A placeholder, for arrays of plans.
    pub(crate) const NONE: QuadPlan = QuadPlan {
        choice: MipChoice::LEVEL0,
        axis_uv: Vec2::ZERO,
        taps: 1,
    };
}

/// The plan of a quad whose pixels share the derivatives `duv_dx`, `duv_dy` ([`sample_quad`]'s
/// first half: a batch plans every quad before it reads any, so the plans' chains of
/// dependent steps — square roots, divisions, a logarithm — overlap one another).
#[inline(always)]
pub(crate) fn quad_plan(
    tex: &Texture2D,
    s: &Sampler,
    duv_dx: Vec2,
    duv_dy: Vec2,
    max_aniso: u32,
) -> QuadPlan {
    let fp = Footprint::new(Vec2::ZERO, duv_dx, duv_dy);
    let (choice, axis_uv, taps) = match plan(tex, s, &fp, max_aniso) {
        Plan::Bilinear => (MipChoice::trilinear(0.0, 1), Vec2::ZERO, 1),
        Plan::Trilinear(lod) => (MipChoice::trilinear(lod, tex.levels().len()), Vec2::ZERO, 1),
        Plan::Taps {
            choice,
            axis_uv,
            taps,
        } => (choice, axis_uv, taps),
    };
    QuadPlan {
        choice,
        axis_uv,
        taps,
    }
}

/// [`quad_plan`] of up to four quads at once, one per lane (plan `k` for `coords[k]`; lanes
/// past `coords` plan zero derivatives): the ellipse's square roots, the ratio's and the
/// axis's divisions and λ's logarithm four at a time, the same operations lane by lane, so
/// the same plans (tested against `quad_plan`).
#[inline(always)]
pub(crate) fn quad_plans4(
    tex: &Texture2D,
    s: &Sampler,
    coords: &[QuadCoords],
    max_aniso: u32,
) -> [QuadPlan; 4] {
    let size = Vec2::new(tex.width() as f32, tex.height() as f32);
    let [dir_x, dir_y, major, minor] = ellipse_axes4(size, coords);
    // `plan`'s count and λ.
    let max_aniso = max_aniso.clamp(1, 16) as f32;
    let ratio = Vec4::select(minor.cmpgt(Vec4::ZERO), major / minor, Vec4::INFINITY);
    let n = ratio.ceil().to_array().map(|r| r.clamp(1.0, max_aniso));
    let n = Vec4::from_array(n);
    let lod = s.adjust_lod4(crate::texture::footprint::fast_log2_4(major / n));
    let (axis_x, axis_y) = (dir_x * major / size.x, dir_y * major / size.y);
    let levels = tex.levels().len();
    std::array::from_fn(|k| {
        let (major, n, lod) = (major[k], n[k], lod[k]);
        if !(major > 1.0) || !(lod > 0.0) && n == 1.0 {
            QuadPlan {
                choice: MipChoice::trilinear(0.0, 1),
                axis_uv: Vec2::ZERO,
                taps: 1,
            }
        } else if !major.is_finite() {
            QuadPlan {
                choice: MipChoice::trilinear(lod, levels),
                axis_uv: Vec2::ZERO,
                taps: 1,
            }
        } else {
            QuadPlan {
                choice: MipChoice::trilinear(lod, levels),
                axis_uv: Vec2::new(axis_x[k], axis_y[k]),
                taps: n as u32,
            }
        }
    })
}

/// [`sample_quad`]'s second half: the reads of quad `uv` as `plan` says.
#[inline(always)]
pub(crate) fn read_quad(
    tex: &Texture2D,
    s: &Sampler,
    uv: (Vec4, Vec4),
    plan: &QuadPlan,
    mask: u8,
) -> Option<[Vec4; 4]> {
    // The taps' places and 15-bit weights depend on their count alone: made once.
    static PROBES: OnceLock<ProbeSets> = OnceLock::new();
    let probes = PROBES.get_or_init(|| ProbeSets::new(layout));
    let taps = probes.get(plan.taps as usize);
    fixed16::read_probes_inlined(tex, s, plan.choice, uv, plan.axis_uv, taps, mask)
}

/// The places along the axis and the weights of `n` taps (the first `n` of the array), as
/// [`sample`] reads them.
fn layout(n: usize) -> [(f32, f32); MAX_PROBES] {
    let mut probes = [(0.0, 0.0); MAX_PROBES];
    let count = n as f32;
    for (i, p) in probes.iter_mut().enumerate().take(n) {
        *p = (offset(i as u32, count), 1.0 / count);
    }
    probes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::{Filter, Wrap};

    /// Four quads' plans at once are each quad's own plan, for derivatives of every kind:
    /// zero, tiny, huge, infinite, NaN, isotropic, degenerate along an axis, and many random
    /// ones, under biased and clamped samplers and every anisotropy limit's neighbourhood.
    #[test]
    fn four_plans_at_once_are_each_quads_plan() {
        for max_aniso in [1, 2, 6, 16, 40] {
            super::super::plan_checks::assert_four_plans_are_each_quads(
                Sampler::new(Filter::Anisotropic { max_aniso }, Wrap::Repeat),
                |tex, s, quads| quad_plans4(tex, s, quads, max_aniso),
                |tex, s, dx, dy| quad_plan(tex, s, dx, dy, max_aniso),
            );
        }
    }
}
