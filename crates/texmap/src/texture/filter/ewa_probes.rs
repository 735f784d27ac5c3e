//! `ewa`: [`super::ewa`]'s ellipse, read exactly where it is nearly round and by weighted
//! trilinear probes along its major axis where it is long (after Mavridis and Papaioannou,
//! "High-quality elliptical texture filtering on GPU", 2011).
//!
//! The ellipse and its eccentricity clamp are `ewa-exact`'s. Below [`EXACT_RATIO`] (major /
//! minor, after the clamp) the footprint holds few texels and is read by `ewa-exact` itself,
//! bit for bit. Longer footprints take `N = ⌈2·REACH·major / minor⌉` probes (at most
//! [`MAX_PROBES`]) at the centres of `N` equal segments of the major axis over ±`REACH`·major,
//! each a trilinear read at λ = log2(segment) — anisotropic filtering's layout — weighted
//! `1 − t²` (`t ∈ (−1, 1)` the probe's place along the axis), the weights normalised.
//!
//! Measured on the 640×360 plane (`tools/plane_quality.sh`, checker / noise dB against the
//! box-filtered ground truth; `ewa-exact` 36.64 / 35.90): probes everywhere with `ewa-exact`'s
//! Gaussian (`e^(−2t²) − e^(−2)`, reach 0.7) scored 34.79 / 35.35; flatter profiles
//! `e^(−αt²) − e^(−α)` scored better as α fell (α = 1: 34.95 / 36.12; α = 0.25, reach 0.6:
//! 35.71 / 36.78), up to the limit α → 0, `1 − t²` (reach 0.6: 36.2–36.3 checker), still
//! below `ewa-exact` on the checker. The probes lost in the near rows, whose round footprints
//! the exact filter reads as a Gaussian of the same width on both levels where a trilinear
//! probe's tent doubles between them; those footprints are also the exact filter's cheap ones.
//! Exact below 2: 36.22 / 36.78; below 3: 36.70 / 36.47 at 4.2× trilinear's instructions in
//! `draw_frame` (callgrind, one thread); below 4: 36.86 / 36.27 at 5.2×.
//!
//! The limit was 3 while only the checker and the noise decided. Over the eight textures of
//! `tools/area_quality.sh` (PSNR, limit 3 / 2.5 / 2): checker 36.71 / 36.44 / 36.24, noise
//! 36.47 / 36.69 / 36.78, grass 41.27 / 41.47 / 41.62, coffee 39.12 / 39.17 / 39.14, camera
//! 39.81 / 39.88 / 39.91, rocket 43.17 / 43.29 / 43.33, gravel 42.01 / 42.15 / 42.29, brick
//! 44.17 / 44.27 / 44.30: the probes score higher on every texture but the checker (whose
//! detail sits at the texel scale), and the mean rises (40.34 / 40.42 / 40.45) as the limit
//! falls, with 18 % fewer instructions at 2 (the 1080p plane's `draw_frame`: 888.7 → 730.1
//! M). The limit is 2 (checker / noise SSIM 0.959 / 0.988, as at 3).
//!
//! Two paths share the plan ([`plan`]): [`sample`] reads one footprint in float, for every
//! storage; [`sample_quad`] reads a quad's four pixels (which share their derivatives, so
//! their plan) on the default 16-bit storage, the probes in lanes in fixed point
//! ([`super::fixed16::read_probes`], as anisotropic filtering does), the exact reads by
//! [`super::ewa_lanes`]. A batch of quads plans four at a time in lanes ([`quad_plans4`],
//! the same plans) before it reads any, as anisotropic filtering's batches do.

use std::sync::OnceLock;

use glam::{Vec2, Vec4};

use super::fixed16::ProbeSets;
use super::{
    bilinear, ellipse_axes, ellipse_axes4, ewa, ewa_lanes, fixed16, texel_derivatives, Codec,
};
use crate::texture::format::with_texture_codec;
use crate::texture::{Footprint, MipChoice, QuadCoords, Sampler, Texture2D};

/// The most probes a footprint takes; longer footprints space them wider, a level coarser.
pub(super) use super::fixed16::MAX_PROBES;

/// Below this eccentricity (major / minor, clamped) a footprint is read exactly.
const EXACT_RATIO: f32 = 2.0;

/// The probes' reach along the major axis, as a multiple of the major semi-axis.
const REACH: f32 = 0.6;

/// What a footprint's read takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Plan {
    /// Magnification: one bilinear read of level 0.
    Bilinear,
    /// A nearly round footprint: `ewa-exact`'s read.
    Exact,
    /// `count` trilinear reads on the levels `choice` names, probe `i` at `uv + t·axis_uv`
    /// weighted `w` for `(t, w) = layout(count)[i]`.
    Probes {
        choice: MipChoice,
        axis_uv: Vec2,
        count: usize,
    },
}

/// The read a footprint with derivatives `duv_dx`, `duv_dy` takes (its `uv` is not used).
#[inline(always)]
pub(crate) fn plan(tex: &Texture2D, s: &Sampler, fp: &Footprint, max_ecc: f32) -> Plan {
    let (dx, dy) = texel_derivatives(tex, fp);
    let (dir, major, mut minor) = ellipse_axes(dx, dy);
    if !(major > 1.0) || !major.is_finite() {
        // Magnification: the footprint is smaller than a texel.
        return Plan::Bilinear;
    }
    // Clamp ellipse eccentricity.
    let max_ecc = max_ecc.max(1.0);
    if minor * max_ecc < major {
        minor = major / max_ecc;
    }
    if major < EXACT_RATIO * minor {
        return Plan::Exact;
    }
    // Probes at the centres of equal segments of the reach, at most a minor axis (or a
    // texel) apart.
    let reach = REACH * major;
    let n = (2.0 * reach / minor.max(1.0))
        .ceil()
        .clamp(1.0, MAX_PROBES as f32);
    let lod = s.adjust_lod(crate::texture::footprint::fast_log2(2.0 * reach / n));
    let size = Vec2::new(tex.width() as f32, tex.height() as f32);
    Plan::Probes {
        choice: MipChoice::trilinear(lod, tex.levels().len()),
        axis_uv: dir * reach / size,
        count: n as usize,
    }
}

/// The places `t` (in (−1, 1), symmetric about 0) and weights `w` (summing to 1) of `count`
/// probes, the first `count` of the array: the centres of equal segments, weighted by their
/// place along the axis.
pub(super) fn layout(count: usize) -> [(f32, f32); MAX_PROBES] {
    let n = count as f32;
    let mut probes = [(0.0, 0.0); MAX_PROBES];
    let mut total = 0.0;
    for (i, p) in probes.iter_mut().enumerate().take(count) {
        let t = (2 * i + 1) as f32 / n - 1.0;
        let w = 1.0 - t * t;
        *p = (t, w);
        total += w;
    }
    for p in probes.iter_mut().take(count) {
        p.1 /= total;
    }
    probes
}

/// One footprint in float.
pub(crate) fn sample<C: Codec>(tex: &Texture2D, s: &Sampler, fp: &Footprint, max_ecc: f32) -> Vec4 {
    let (choice, axis_uv, count) = match plan(tex, s, fp, max_ecc) {
        Plan::Bilinear => return bilinear::<C>(&tex.level(0), s, fp.uv),
        Plan::Exact => return ewa::sample::<C>(tex, s, fp, max_ecc),
        Plan::Probes {
            choice,
            axis_uv,
            count,
        } => (choice, axis_uv, count),
    };
    let probes = layout(count);
    let first = tex.level(choice.level);
    let second = choice.blend.map(|b| (tex.level(b.level), b.weight));
    let mut sum = Vec4::ZERO;
    for &(t, w) in &probes[..count] {
        let uv = fp.uv + axis_uv * t;
        let a = bilinear::<C>(&first, s, uv);
        sum += w * match second {
            Some((lv, weight)) => a.lerp(bilinear::<C>(&lv, s, uv), weight),
            None => a,
        };
    }
    sum
}

/// [`sample`] for a quad's four pixels (pixel `j` at `(u[j], v[j])`, the derivatives shared):
/// the probes in lanes in fixed point, `None` where [`fixed16`] does not serve the texture and
/// sampler (the caller reads each pixel with [`sample`]). Pixels whose bit in `mask` is clear
/// are left zero. Out of line, as [`ewa_lanes::sample_quad`].
#[inline(never)]
pub(crate) fn sample_quad(
    tex: &Texture2D,
    s: &Sampler,
    uv: (Vec4, Vec4),
    duv_dx: Vec2,
    duv_dy: Vec2,
    mask: u8,
    max_ecc: f32,
) -> Option<[Vec4; 4]> {
    let plan = quad_plan(tex, s, duv_dx, duv_dy, max_ecc);
    read_quad(tex, s, uv, (duv_dx, duv_dy), &plan, mask, max_ecc)
}

/// The plan of a quad whose pixels share the derivatives `duv_dx`, `duv_dy` ([`sample_quad`]'s
/// first half: a batch plans every quad before it reads any, so the plans' chains of
/// dependent steps overlap one another).
#[inline(always)]
pub(crate) fn quad_plan(
    tex: &Texture2D,
    s: &Sampler,
    duv_dx: Vec2,
    duv_dy: Vec2,
    max_ecc: f32,
) -> Plan {
    plan(tex, s, &Footprint::new(Vec2::ZERO, duv_dx, duv_dy), max_ecc)
}

/// [`quad_plan`] of up to four quads at once, one per lane (plan `k` for `coords[k]`): the
/// ellipse ([`ellipse_axes4`]), the clamp, the count's and λ's divisions and logarithm four
/// at a time, the same operations lane by lane, so the same plans (tested against
/// `quad_plan`).
#[inline(always)]
pub(crate) fn quad_plans4(
    tex: &Texture2D,
    s: &Sampler,
    coords: &[QuadCoords],
    max_ecc: f32,
) -> [Plan; 4] {
    let size = Vec2::new(tex.width() as f32, tex.height() as f32);
    let [dir_x, dir_y, major, minor] = ellipse_axes4(size, coords);
    // The eccentricity clamp.
    let max_ecc = Vec4::splat(max_ecc.max(1.0));
    let minor = Vec4::select((minor * max_ecc).cmplt(major), major / max_ecc, minor);
    let reach = REACH * major;
    let n = (2.0 * reach / minor.max(Vec4::ONE)).ceil().to_array();
    let n = Vec4::from_array(n.map(|n| n.clamp(1.0, MAX_PROBES as f32)));
    let lod = s.adjust_lod4(crate::texture::footprint::fast_log2_4(2.0 * reach / n));
    let (axis_x, axis_y) = (dir_x * reach / size.x, dir_y * reach / size.y);
    let levels = tex.levels().len();
    // A loop, not `array::from_fn` (whose closure was compiled on its own, at the baseline
    // level, as anisotropic filtering's `quad_plans4` says).
    let mut plans = [Plan::Bilinear; 4];
    for (k, plan) in plans.iter_mut().enumerate() {
        let major = major[k];
        *plan = if !(major > 1.0) || !major.is_finite() {
            Plan::Bilinear
        } else if major < EXACT_RATIO * minor[k] {
            Plan::Exact
        } else {
            Plan::Probes {
                choice: MipChoice::trilinear(lod[k], levels),
                axis_uv: Vec2::new(axis_x[k], axis_y[k]),
                count: n[k] as usize,
            }
        };
    }
    plans
}

/// [`sample_quad`]'s second half: the reads of quad `uv` (derivatives `duv`) as `plan` says.
#[inline(always)]
pub(crate) fn read_quad(
    tex: &Texture2D,
    s: &Sampler,
    uv: (Vec4, Vec4),
    (duv_dx, duv_dy): (Vec2, Vec2),
    plan: &Plan,
    mask: u8,
    max_ecc: f32,
) -> Option<[Vec4; 4]> {
    match *plan {
        Plan::Bilinear => fixed16::read_probes(
            tex,
            s,
            MipChoice::trilinear(0.0, 1),
            uv,
            Vec2::ZERO,
            &[fixed16::Probe::WHOLE],
            mask,
        ),
        Plan::Exact => Some(with_texture_codec!(tex, C => ewa_lanes::sample_quad::<C>(
            tex, s, uv, duv_dx, duv_dy, mask, max_ecc
        ))),
        Plan::Probes {
            choice,
            axis_uv,
            count,
        } => {
            let probes = probe_sets().get(count);
            fixed16::read_probes(tex, s, choice, uv, axis_uv, probes, mask)
        }
    }
}

/// [`read_quad`] by a batch's reader (`probes` from [`probe_sets`]): the same values.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn read_quad_with(
    reader: &mut fixed16::ProbeReader,
    tex: &Texture2D,
    s: &Sampler,
    uv: (Vec4, Vec4),
    (duv_dx, duv_dy): (Vec2, Vec2),
    plan: &Plan,
    probes: &ProbeSets,
    mask: u8,
    max_ecc: f32,
) -> [Vec4; 4] {
    match *plan {
        Plan::Bilinear => reader.read(
            s,
            MipChoice::trilinear(0.0, 1),
            uv,
            Vec2::ZERO,
            &[fixed16::Probe::WHOLE],
            mask,
        ),
        Plan::Exact => with_texture_codec!(tex, C => ewa_lanes::sample_quad::<C>(
            tex, s, uv, duv_dx, duv_dy, mask, max_ecc
        )),
        Plan::Probes {
            choice,
            axis_uv,
            count,
        } => reader.read(s, choice, uv, axis_uv, probes.get(count), mask),
    }
}

/// The probes' places and 15-bit weights of every count (they depend on the count alone):
/// made once.
pub(super) fn probe_sets() -> &'static ProbeSets {
    static PROBES: OnceLock<ProbeSets> = OnceLock::new();
    PROBES.get_or_init(|| ProbeSets::new(layout))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::{Filter, Wrap};

    /// Four quads' plans at once are each quad's own plan, for derivatives of every kind
    /// (zero, tiny, huge, infinite, NaN, round, long, random), under biased and clamped
    /// samplers and several eccentricity limits.
    #[test]
    fn four_plans_at_once_are_each_quads_plan() {
        for max_ecc in [0.5, 4.0, 16.0, 1000.0] {
            let filter = Filter::Ewa {
                max_eccentricity: max_ecc,
            };
            super::super::plan_checks::assert_four_plans_are_each_quads(
                Sampler::new(filter, Wrap::Repeat),
                |tex, s, quads| quad_plans4(tex, s, quads, max_ecc),
                |tex, s, dx, dy| quad_plan(tex, s, dx, dy, max_ecc),
            );
        }
    }
}
