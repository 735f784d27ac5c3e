//! The lane types the quad shading rules run on: `Vec4` (a quad's four pixels) and, where the
//! CPU has AVX2, [`F32x8`] (two quads' eight pixels in one 256-bit vector).
//!
//! [`Lane`] names the operations the rules use ([`super::mr_lanes`], [`super::lanes`]), each
//! with `Vec4`'s meaning lane for lane: `F32x8`'s are the same IEEE operations and the same
//! compare predicates, selects and NaN rules on eight lanes, so a lane's value does not depend
//! on the type it was computed in (tested here on special and random values). Two quads
//! shaded as one `F32x8` give their `Vec4` colours bit for bit, in half the arithmetic
//! instructions.

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Sub};

use glam::{BVec4A, Vec4};

/// A vector of pixels' values, a whole number of quads (four lanes each) wide.
pub(crate) trait Lane:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// A lane-wise condition (all bits set or clear per lane).
    type Mask: Copy + BitAnd<Output = Self::Mask> + BitOr<Output = Self::Mask>;
    /// Quads held (lanes / 4).
    const QUADS: usize;
    fn splat(v: f32) -> Self;
    /// Quad `k`'s four lanes.
    fn quad(self, k: usize) -> Vec4;
    /// The vector whose quad `k` is `f(k)`.
    fn from_quads(f: impl FnMut(usize) -> Vec4) -> Self;
    /// `if mask { a } else { b }` per lane.
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self;
    fn cmpgt(self, rhs: Self) -> Self::Mask;
    fn cmplt(self, rhs: Self) -> Self::Mask;
    fn cmpne(self, rhs: Self) -> Self::Mask;
    /// `Vec4::max`'s rule (the right operand where either is NaN).
    fn max(self, rhs: Self) -> Self;
    /// `Vec4::min`'s rule.
    fn min(self, rhs: Self) -> Self;
    fn sqrt(self) -> Self;
    /// Lanes whose magnitude is below infinity.
    fn is_finite_mask(self) -> Self::Mask;
    /// `Vec4::signum`: ±1 by the sign bit, NaN kept.
    fn signum(self) -> Self;
    /// Bit `i` set where lane `i`'s condition holds.
    fn bitmask(mask: Self::Mask) -> u32;
    /// The condition whose lane `i` is bit `i` of `bits`.
    fn mask_from_bits(bits: u32) -> Self::Mask;

    /// `1 / self`, as `Vec4::recip`.
    #[inline(always)]
    fn recip(self) -> Self {
        Self::splat(1.0) / self
    }

    /// `Vec4::clamp`: `max` then `min`.
    #[inline(always)]
    fn clamp(self, lo: Self, hi: Self) -> Self {
        self.max(lo).min(hi)
    }

    /// Every lane through `f` (the lanes quad by quad).
    #[inline(always)]
    fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Self::from_quads(|k| Vec4::from_array(self.quad(k).to_array().map(&f)))
    }
}

impl Lane for Vec4 {
    type Mask = BVec4A;
    const QUADS: usize = 1;
    #[inline(always)]
    fn splat(v: f32) -> Self {
        Vec4::splat(v)
    }
    #[inline(always)]
    fn quad(self, _k: usize) -> Vec4 {
        self
    }
    #[inline(always)]
    fn from_quads(mut f: impl FnMut(usize) -> Vec4) -> Self {
        f(0)
    }
    #[inline(always)]
    fn select(mask: BVec4A, a: Self, b: Self) -> Self {
        Vec4::select(mask, a, b)
    }
    #[inline(always)]
    fn cmpgt(self, rhs: Self) -> BVec4A {
        Vec4::cmpgt(self, rhs)
    }
    #[inline(always)]
    fn cmplt(self, rhs: Self) -> BVec4A {
        Vec4::cmplt(self, rhs)
    }
    #[inline(always)]
    fn cmpne(self, rhs: Self) -> BVec4A {
        Vec4::cmpne(self, rhs)
    }
    #[inline(always)]
    fn max(self, rhs: Self) -> Self {
        Vec4::max(self, rhs)
    }
    #[inline(always)]
    fn min(self, rhs: Self) -> Self {
        Vec4::min(self, rhs)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        super::lanes::sqrt4(self)
    }
    #[inline(always)]
    fn is_finite_mask(self) -> BVec4A {
        Vec4::is_finite_mask(self)
    }
    #[inline(always)]
    fn signum(self) -> Self {
        Vec4::signum(self)
    }
    #[inline(always)]
    fn bitmask(mask: BVec4A) -> u32 {
        mask.bitmask()
    }
    #[inline(always)]
    fn mask_from_bits(bits: u32) -> BVec4A {
        BVec4A::new(bits & 1 != 0, bits & 2 != 0, bits & 4 != 0, bits & 8 != 0)
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use avx::F32x8;

/// The eight-lane type. Its operations are AVX instructions: a value is made and used only
/// in code compiled for x86-64-v3 that runs where [`crate::cpu::level`] is
/// [`crate::cpu::Level::V3`] (the callers check), where they inline as single instructions.
#[cfg(target_arch = "x86_64")]
mod avx {
    use std::arch::x86_64::{
        __m256, _mm256_add_ps, _mm256_and_ps, _mm256_andnot_ps, _mm256_blendv_ps,
        _mm256_castps128_ps256, _mm256_castps256_ps128, _mm256_castsi256_ps, _mm256_cmp_ps,
        _mm256_div_ps, _mm256_extractf128_ps, _mm256_insertf128_ps, _mm256_max_ps, _mm256_min_ps,
        _mm256_movemask_ps, _mm256_mul_ps, _mm256_or_ps, _mm256_set1_ps, _mm256_setr_epi32,
        _mm256_sqrt_ps, _mm256_sub_ps, _mm256_xor_ps, _CMP_GT_OS, _CMP_LT_OS, _CMP_NEQ_UQ,
        _CMP_UNORD_Q,
    };
    use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Sub};

    use glam::Vec4;

    use super::Lane;

    /// Two quads' values, quad 0 in the low four lanes.
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct F32x8(__m256);

    /// A condition on an [`F32x8`]'s lanes.
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct M32x8(__m256);

    impl F32x8 {
        /// Quad `lo` in the low four lanes, `hi` in the high four.
        #[inline(always)]
        pub(crate) fn join(lo: Vec4, hi: Vec4) -> F32x8 {
            // SAFETY: AVX is available where this runs (the module's rule).
            F32x8(unsafe {
                _mm256_insertf128_ps::<1>(_mm256_castps128_ps256(lo.into()), hi.into())
            })
        }

        /// The vector, for operations [`Lane`] does not name (a table's gathers).
        #[inline(always)]
        pub(crate) fn m256(self) -> __m256 {
            self.0
        }

        /// [`F32x8::m256`]'s inverse.
        #[inline(always)]
        pub(crate) fn from_m256(v: __m256) -> F32x8 {
            F32x8(v)
        }

        /// Two quads' four values a pixel (`lo[j]`, `hi[j]`: pixel `j`'s, as `Vec4`s) as
        /// lanes: value `c` of every pixel, quad `lo` in the low four lanes (the
        /// [`transpose`](super::super::lanes::transpose) of each, in 256-bit shuffles).
        #[inline(always)]
        pub(crate) fn transpose(lo: &[Vec4; 4], hi: &[Vec4; 4]) -> [F32x8; 4] {
            use std::arch::x86_64::{_mm256_shuffle_ps, _mm256_unpackhi_ps, _mm256_unpacklo_ps};
            let r = |j: usize| F32x8::join(lo[j], hi[j]).0;
            let (r0, r1, r2, r3) = (r(0), r(1), r(2), r(3));
            // SAFETY: AVX is available where this runs (the module's rule).
            unsafe {
                let t0 = _mm256_unpacklo_ps(r0, r1);
                let t1 = _mm256_unpacklo_ps(r2, r3);
                let t2 = _mm256_unpackhi_ps(r0, r1);
                let t3 = _mm256_unpackhi_ps(r2, r3);
                [
                    F32x8(_mm256_shuffle_ps::<0x44>(t0, t1)),
                    F32x8(_mm256_shuffle_ps::<0xEE>(t0, t1)),
                    F32x8(_mm256_shuffle_ps::<0x44>(t2, t3)),
                    F32x8(_mm256_shuffle_ps::<0xEE>(t2, t3)),
                ]
            }
        }
    }

    // SAFETY (every block below): AVX is available where these run (the module's rule).
    macro_rules! binary {
        ($trait:ident, $method:ident, $op:ident) => {
            impl $trait for F32x8 {
                type Output = F32x8;
                #[inline(always)]
                fn $method(self, rhs: F32x8) -> F32x8 {
                    F32x8(unsafe { $op(self.0, rhs.0) })
                }
            }
        };
    }
    binary!(Add, add, _mm256_add_ps);
    binary!(Sub, sub, _mm256_sub_ps);
    binary!(Mul, mul, _mm256_mul_ps);
    binary!(Div, div, _mm256_div_ps);

    impl Neg for F32x8 {
        type Output = F32x8;
        /// The sign bit flipped, as `Vec4`'s negation.
        #[inline(always)]
        fn neg(self) -> F32x8 {
            F32x8(unsafe { _mm256_xor_ps(_mm256_set1_ps(-0.0), self.0) })
        }
    }

    impl BitAnd for M32x8 {
        type Output = M32x8;
        #[inline(always)]
        fn bitand(self, rhs: M32x8) -> M32x8 {
            M32x8(unsafe { _mm256_and_ps(self.0, rhs.0) })
        }
    }

    impl BitOr for M32x8 {
        type Output = M32x8;
        #[inline(always)]
        fn bitor(self, rhs: M32x8) -> M32x8 {
            M32x8(unsafe { _mm256_or_ps(self.0, rhs.0) })
        }
    }

    impl Lane for F32x8 {
        type Mask = M32x8;
        const QUADS: usize = 2;
        #[inline(always)]
        fn splat(v: f32) -> Self {
            F32x8(unsafe { _mm256_set1_ps(v) })
        }
        #[inline(always)]
        fn quad(self, k: usize) -> Vec4 {
            unsafe {
                if k == 0 {
                    Vec4::from(_mm256_castps256_ps128(self.0))
                } else {
                    Vec4::from(_mm256_extractf128_ps::<1>(self.0))
                }
            }
        }
        #[inline(always)]
        fn from_quads(mut f: impl FnMut(usize) -> Vec4) -> Self {
            let (lo, hi) = (f(0), f(1));
            F32x8::join(lo, hi)
        }
        #[inline(always)]
        fn select(mask: M32x8, a: Self, b: Self) -> Self {
            F32x8(unsafe { _mm256_blendv_ps(b.0, a.0, mask.0) })
        }
        #[inline(always)]
        fn cmpgt(self, rhs: Self) -> M32x8 {
            M32x8(unsafe { _mm256_cmp_ps::<_CMP_GT_OS>(self.0, rhs.0) })
        }
        #[inline(always)]
        fn cmplt(self, rhs: Self) -> M32x8 {
            M32x8(unsafe { _mm256_cmp_ps::<_CMP_LT_OS>(self.0, rhs.0) })
        }
        #[inline(always)]
        fn cmpne(self, rhs: Self) -> M32x8 {
            M32x8(unsafe { _mm256_cmp_ps::<_CMP_NEQ_UQ>(self.0, rhs.0) })
        }
        #[inline(always)]
        fn max(self, rhs: Self) -> Self {
            F32x8(unsafe { _mm256_max_ps(self.0, rhs.0) })
        }
        #[inline(always)]
        fn min(self, rhs: Self) -> Self {
            F32x8(unsafe { _mm256_min_ps(self.0, rhs.0) })
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            F32x8(unsafe { _mm256_sqrt_ps(self.0) })
        }
        #[inline(always)]
        fn is_finite_mask(self) -> M32x8 {
            // |x| < ∞, |x| the sign bit cleared (as glam's `m128_abs`).
            unsafe {
                let abs = _mm256_andnot_ps(_mm256_set1_ps(-0.0), self.0);
                M32x8(_mm256_cmp_ps::<_CMP_LT_OS>(
                    abs,
                    _mm256_set1_ps(f32::INFINITY),
                ))
            }
        }
        #[inline(always)]
        fn signum(self) -> Self {
            unsafe {
                let sign = _mm256_and_ps(self.0, _mm256_set1_ps(-1.0));
                let result = _mm256_or_ps(sign, _mm256_set1_ps(1.0));
                let nan = _mm256_cmp_ps::<_CMP_UNORD_Q>(self.0, self.0);
                F32x8(_mm256_blendv_ps(result, self.0, nan))
            }
        }
        #[inline(always)]
        fn bitmask(mask: M32x8) -> u32 {
            unsafe { _mm256_movemask_ps(mask.0) as u32 }
        }
        #[inline(always)]
        fn mask_from_bits(bits: u32) -> M32x8 {
            // Each lane's bit moved to its sign bit and spread: all ones where set.
            unsafe {
                let lanes = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
                let b = std::arch::x86_64::_mm256_set1_epi32(bits as i32);
                let set = std::arch::x86_64::_mm256_cmpeq_epi32(
                    std::arch::x86_64::_mm256_and_si256(b, lanes),
                    lanes,
                );
                M32x8(_mm256_castsi256_ps(set))
            }
        }
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;

    /// Values of every kind: zeros of both signs, tiny, huge, infinite, NaN, and random ones.
    fn values() -> Vec<f32> {
        let mut v = vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            1e-40,
            f32::MAX,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
        ];
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..200 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            v.push(f32::from_bits((state >> 32) as u32));
            v.push((state >> 40) as f32 / (1u64 << 20) as f32 - 8.0);
        }
        v
    }

    fn same(a: Vec4, b: Vec4) -> bool {
        (0..4).all(|i| a[i].to_bits() == b[i].to_bits())
    }

    /// Every operation of `F32x8` gives, quad by quad, `Vec4`'s bits.
    #[test]
    fn eight_lanes_are_two_vec4s() {
        if !crate::cpu::available(crate::cpu::Level::V3) {
            eprintln!("skipped: this CPU has no AVX2");
            return;
        }
        // SAFETY: the CPU has AVX2 (checked above).
        unsafe { check() }
    }

    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
    fn check() {
        let v = values();
        let n = v.len();
        for k in 0..n {
            let at = |o: usize| Vec4::from_array(std::array::from_fn(|i| v[(k + o + i * 7) % n]));
            let (a0, a1, b0, b1) = (at(0), at(3), at(11), at(29));
            let a = F32x8::from_quads(|q| [a0, a1][q]);
            let b = F32x8::from_quads(|q| [b0, b1][q]);
            let check = |w: F32x8, f: &dyn Fn(Vec4, Vec4) -> Vec4, what: &str| {
                for (q, (x, y)) in [(a0, b0), (a1, b1)].into_iter().enumerate() {
                    assert!(same(w.quad(q), f(x, y)), "{what} of {x} and {y}");
                }
            };
            check(a + b, &|x, y| x + y, "sum");
            check(a - b, &|x, y| x - y, "difference");
            check(a * b, &|x, y| x * y, "product");
            check(a / b, &|x, y| x / y, "quotient");
            check(-a, &|x, _| -x, "negation");
            check(a.max(b), &|x, y| x.max(y), "max");
            check(a.min(b), &|x, y| x.min(y), "min");
            check(Lane::sqrt(a), &|x, _| Lane::sqrt(x), "sqrt");
            check(Lane::recip(a), &|x, _| x.recip(), "recip");
            check(Lane::signum(a), &|x, _| x.signum(), "signum");
            let (lo, hi) = ([a0, b0, a1, b1], [b1, a0, at(5), b0]);
            let t = F32x8::transpose(&lo, &hi);
            let (tlo, thi) = (
                super::super::lanes::transpose(lo),
                super::super::lanes::transpose(hi),
            );
            for c in 0..4 {
                assert!(
                    same(t[c].quad(0), tlo[c]) && same(t[c].quad(1), thi[c]),
                    "transpose"
                );
            }
            check(
                Lane::clamp(a, b, b + F32x8::splat(1.0)),
                &|x, y| x.clamp(y, y + Vec4::ONE),
                "clamp",
            );
            let masks = [
                (a.cmpgt(b), [a0.cmpgt(b0), a1.cmpgt(b1)]),
                (a.cmplt(b), [a0.cmplt(b0), a1.cmplt(b1)]),
                (a.cmpne(b), [a0.cmpne(b0), a1.cmpne(b1)]),
                (
                    a.is_finite_mask(),
                    [a0.is_finite_mask(), a1.is_finite_mask()],
                ),
                (
                    a.cmpgt(b) | a.cmpne(b),
                    [a0.cmpgt(b0) | a0.cmpne(b0), a1.cmpgt(b1) | a1.cmpne(b1)],
                ),
                (
                    a.cmpgt(b) & a.cmpne(b),
                    [a0.cmpgt(b0) & a0.cmpne(b0), a1.cmpgt(b1) & a1.cmpne(b1)],
                ),
            ];
            for (m, [m0, m1]) in masks {
                let bits = F32x8::bitmask(m);
                assert_eq!(bits, m0.bitmask() | m1.bitmask() << 4);
                let chosen = F32x8::select(m, a, b);
                assert!(same(chosen.quad(0), Vec4::select(m0, a0, b0)));
                assert!(same(chosen.quad(1), Vec4::select(m1, a1, b1)));
                assert_eq!(F32x8::bitmask(F32x8::mask_from_bits(bits)), bits);
            }
            let bits = (k * 37 % 256) as u32;
            assert_eq!(F32x8::bitmask(F32x8::mask_from_bits(bits)), bits);
            check(
                a.map(|x| x.powi(4)),
                &|x, _| Vec4::from_array(x.to_array().map(|x| x.powi(4))),
                "map",
            );
        }
    }
}
