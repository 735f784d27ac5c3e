//! The footprint of a pixel in texture space: coordinates and their screen derivatives, and
//! the level of detail λ they make.
//!
//! Footprints carry derivatives wherever coordinates go, so every read can filter. λ is a
//! function of the derivatives alone ([`LodRule`], in texels of level 0; the same rule for 2D,
//! cube faces and 3D), so the four pixels of a quad share it; which levels a λ reads is
//! [`super::MipChoice`]'s rule.

use glam::{Vec2, Vec3, Vec4};

/// A pixel's footprint on a 2D texture: `uv` and its derivatives along the screen axes.
///
/// `uv` is in glTF's convention (u right, v down the image rows, one unit = the whole image).
/// A zero footprint (`duv_dx = duv_dy = 0`) is a point sample at the finest level.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Footprint {
    pub uv: Vec2,
    pub duv_dx: Vec2,
    pub duv_dy: Vec2,
}

impl Footprint {
    /// A footprint with derivatives.
    #[must_use]
    pub fn new(uv: Vec2, duv_dx: Vec2, duv_dy: Vec2) -> Self {
        Footprint { uv, duv_dx, duv_dy }
    }

    /// A point sample (no derivatives).
    #[must_use]
    pub fn point(uv: Vec2) -> Self {
        Footprint {
            uv,
            ..Default::default()
        }
    }
}

/// A footprint on a 3D texture.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Footprint3 {
    pub uvw: Vec3,
    pub duvw_dx: Vec3,
    pub duvw_dy: Vec3,
}

impl Footprint3 {
    /// A point sample (no derivatives).
    #[must_use]
    pub fn point(uvw: Vec3) -> Self {
        Footprint3 {
            uvw,
            ..Default::default()
        }
    }
}

/// A footprint on a cube map: a direction (need not be unit length) and its derivatives.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CubeFootprint {
    pub dir: Vec3,
    pub ddir_dx: Vec3,
    pub ddir_dy: Vec3,
}

/// Four [`CubeFootprint`]s in lanes, one pixel per lane: `dir[0]` holds the four `dir.x`,
/// `ddir_dx[1]` the four `ddir_dx.y`, and so on.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CubeFootprintLanes {
    pub dir: [Vec4; 3],
    pub ddir_dx: [Vec4; 3],
    pub ddir_dy: [Vec4; 3],
}

impl CubeFootprintLanes {
    /// Lane `j`'s footprint.
    #[inline]
    #[must_use]
    pub fn footprint(&self, j: usize) -> CubeFootprint {
        let v = |c: &[Vec4; 3]| Vec3::new(c[0][j], c[1][j], c[2][j]);
        CubeFootprint {
            dir: v(&self.dir),
            ddir_dx: v(&self.ddir_dx),
            ddir_dy: v(&self.ddir_dy),
        }
    }
}

/// Four [`Footprint`]s in lanes, one pixel per lane: `u` holds the four `uv.x`, `dudx` the
/// four `duv_dx.x`, and so on (each pixel its own derivatives).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FootprintLanes {
    pub u: Vec4,
    pub v: Vec4,
    pub dudx: Vec4,
    pub dvdx: Vec4,
    pub dudy: Vec4,
    pub dvdy: Vec4,
}

impl FootprintLanes {
    /// Lane `j`'s footprint.
    #[inline]
    #[must_use]
    pub fn footprint(&self, j: usize) -> Footprint {
        Footprint::new(
            Vec2::new(self.u[j], self.v[j]),
            Vec2::new(self.dudx[j], self.dvdx[j]),
            Vec2::new(self.dudy[j], self.dvdy[j]),
        )
    }
}

/// How the level of detail is computed from the derivatives, in texel units.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum LodRule {
    /// OpenGL's: λ = log2 of the longer of the two derivative vectors.
    #[default]
    GlMax,
    /// The article's: λ = ½·log2(Σ of the squared derivatives).
    RootSumSquares,
}

impl LodRule {
    /// λ for 2D derivatives already scaled to texels.
    #[inline]
    #[must_use]
    pub fn lod(self, dx: Vec2, dy: Vec2) -> f32 {
        let (lx, ly) = (dx.length_squared(), dy.length_squared());
        match self {
            LodRule::GlMax => 0.5 * fast_log2(lx.max(ly)),
            LodRule::RootSumSquares => 0.5 * fast_log2(lx + ly),
        }
    }

    /// λ for 3D derivatives already scaled to texels (texels of level 0 on each axis).
    ///
    /// The same rule as [`LodRule::lod`], with the exact `f32::log2` that 3D reads have
    /// always used: `fast_log2`'s error (up to 3·10⁻⁵) moves some solid-texture pixels by
    /// an 8-bit step.
    #[inline]
    #[must_use]
    pub fn lod3(self, dx: Vec3, dy: Vec3) -> f32 {
        let (lx, ly) = (dx.length_squared(), dy.length_squared());
        match self {
            LodRule::GlMax => 0.5 * lx.max(ly).log2(),
            LodRule::RootSumSquares => 0.5 * (lx + ly).log2(),
        }
    }
}

impl LodRule {
    /// [`LodRule::lod`] of four footprints at once, one per lane: `dxu` holds the four
    /// `dx.x`, and so on. The same operations lane by lane, so the same values. (Always
    /// inlined: a batch's λ are taken in a loop compiled for the CPU's level, which a call
    /// would leave for the baseline copy.)
    #[inline(always)]
    #[must_use]
    pub fn lod4(self, dxu: Vec4, dxv: Vec4, dyu: Vec4, dyv: Vec4) -> Vec4 {
        let (lx, ly) = (dxu * dxu + dxv * dxv, dyu * dyu + dyv * dyv);
        let arg = match self {
            LodRule::GlMax => lx.max(ly),
            LodRule::RootSumSquares => lx + ly,
        };
        fast_log2_4(arg) * 0.5
    }
}

/// [`fast_log2`] of four values, one per lane (SSE2 on x86-64; the scalar function per lane
/// elsewhere, and for any lane that is not a positive, finite normal number).
#[inline(always)]
#[must_use]
pub fn fast_log2_4(x: Vec4) -> Vec4 {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{
            _mm_and_si128, _mm_castps_si128, _mm_castsi128_ps, _mm_cmpgt_epi32, _mm_cvtepi32_ps,
            _mm_movemask_ps, _mm_or_si128, _mm_set1_epi32, _mm_setzero_si128, _mm_srli_epi32,
            _mm_sub_epi32,
        };
        // SAFETY: SSE2 is part of x86_64.
        let (e, m, special) = unsafe {
            let bits = _mm_castps_si128(x.into());
            let biased = _mm_and_si128(_mm_srli_epi32(bits, 23), _mm_set1_epi32(0xff));
            let e = _mm_cvtepi32_ps(_mm_sub_epi32(biased, _mm_set1_epi32(127)));
            let mant = _mm_or_si128(
                _mm_and_si128(bits, _mm_set1_epi32(0x007f_ffff)),
                _mm_set1_epi32(0x3f80_0000),
            );
            // Positive, finite, normal: bits in [0x0080_0000, 0x7f80_0000), so bits −
            // 0x0080_0000 in [0, 0x7f00_0000) as a signed number (a negative float's bits,
            // negative as i32, stay negative or wrap past 0x7f00_0000). The other lanes' bits,
            // one compare for the four (it was four scalar tests, 7 instructions a lane).
            let t = _mm_sub_epi32(bits, _mm_set1_epi32(0x0080_0000));
            let outside = _mm_or_si128(
                _mm_cmpgt_epi32(_mm_setzero_si128(), t),
                _mm_cmpgt_epi32(t, _mm_set1_epi32(0x7eff_ffff)),
            );
            (
                Vec4::from(e),
                Vec4::from(_mm_castsi128_ps(mant)) - 1.0,
                _mm_movemask_ps(_mm_castsi128_ps(outside)),
            )
        };
        let m2 = m * m;
        let lo = Vec4::splat(1.441_592_7) - m * 0.707_256_4;
        let mid = Vec4::splat(0.411_566_8) - m * 0.189_836_41;
        let p = (lo + mid * m2 + (m2 * m2) * 0.043_929_57) * m;
        let mut out = e + p;
        // Zero, negative, subnormal, infinite or NaN lanes: the scalar rule.
        if special != 0 {
            for k in (0..4).filter(|k| special & (1 << k) != 0) {
                out[k] = fast_log2(x[k]);
            }
        }
        out
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        Vec4::from_array(x.to_array().map(fast_log2))
    }
}

/// log2 for level-of-detail work: exponent bits plus a degree-5 polynomial on the mantissa,
/// within 3·10⁻⁵ of `f32::log2` and exact at powers of two (so λ = 0 stays magnification).
/// It replaces the libm call, a function call on the critical path of every level-of-detail
/// choice, with a few multiply-adds.
#[inline(always)]
#[must_use]
pub fn fast_log2(x: f32) -> f32 {
    if !(x > 0.0) || x.is_infinite() || !x.is_normal() {
        return x.log2();
    }
    let bits = x.to_bits();
    let e = ((bits >> 23) & 0xff) as i32 - 127;
    let m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000) - 1.0;
    // The polynomial by Estrin's scheme (three levels of dependent operations, not Horner's
    // five): it sits on the critical path of every level-of-detail choice.
    let m2 = m * m;
    let lo = 1.441_592_7 - 0.707_256_4 * m;
    let mid = 0.411_566_8 - 0.189_836_41 * m;
    let p = (lo + mid * m2 + 0.043_929_57 * (m2 * m2)) * m;
    e as f32 + p
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn fast_log2_is_exact_at_powers_of_two() {
        for e in -30..30 {
            assert_eq!(fast_log2((e as f32).exp2()), e as f32);
        }
        assert_eq!(fast_log2(0.0), f32::NEG_INFINITY);
        assert!(fast_log2(f32::NAN).is_nan());
    }

    proptest! {
        #[test]
        fn four_lane_lod_equals_the_scalar_rule(d in proptest::array::uniform16(-1e3f32..1e3), zero in 0usize..5) {
            let mut d = d;
            if zero < 4 {
                // A degenerate footprint in one lane (λ = −∞): the scalar rule's special case.
                for k in 0..4 { d[4 * k + zero] = 0.0; }
            }
            let lane = |k: usize| Vec4::new(d[4 * k], d[4 * k + 1], d[4 * k + 2], d[4 * k + 3]);
            for rule in [LodRule::GlMax, LodRule::RootSumSquares] {
                let four = rule.lod4(lane(0), lane(1), lane(2), lane(3));
                for i in 0..4 {
                    let one = rule.lod(Vec2::new(d[i], d[4 + i]), Vec2::new(d[8 + i], d[12 + i]));
                    prop_assert!(four[i] == one || (four[i].is_nan() && one.is_nan()), "{:?} lane {}: {} vs {}", rule, i, four[i], one);
                }
            }
        }

        #[test]
        fn fast_log2_4_is_the_scalar_function_lane_by_lane(bits in proptest::array::uniform4(any::<u32>()), pick in proptest::array::uniform4(0usize..16)) {
            // Any bits, or values of every kind: zeros, subnormals, the normal range's ends,
            // infinities, NaN, negatives.
            const KINDS: [f32; 12] = [
                0.0, -0.0, 1e-40, f32::MIN_POSITIVE, 1.0, 0.5, f32::MAX,
                f32::INFINITY, f32::NEG_INFINITY, f32::NAN, -1.0, -1e-40,
            ];
            let x: [f32; 4] = std::array::from_fn(|k| {
                KINDS.get(pick[k]).copied().unwrap_or(f32::from_bits(bits[k]))
            });
            let four = fast_log2_4(Vec4::from_array(x));
            for k in 0..4 {
                let one = fast_log2(x[k]);
                let same = four[k] == one || (four[k].is_nan() && one.is_nan());
                prop_assert!(same, "lane {}: {:e} gives {} vs {}", k, x[k], four[k], one);
            }
        }

        #[test]
        fn fast_log2_is_close(x in 1e-20f32..1e20) {
            prop_assert!((fast_log2(x) - x.log2()).abs() < 5e-5);
        }
    }
}
