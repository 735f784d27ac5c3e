//! A chunk of shared reads planned before any of it is read: which neighbouring quads are
//! read as pairs ([`super::avx2::linear_pair_shared`]: both quads on the same levels, where
//! the CPU has x86-64-v3), and each pair's taps on its first level, made once. Planning asks
//! the cache for every quad's first-level texels in every texture (as
//! [`super::prefetch_shared`] asks for a single quad's), so it needs those taps anyway:
//! made before for the prefetch and again for the read, they were a third of the pairs'
//! taps.

use std::mem::MaybeUninit;

use super::Shared;
use crate::texture::{MipChoice, QuadCoords, Sampler, TexelFilter};

/// The most quads a [`SharedPlan`] plans.
pub(in super::super) const PLAN_QUADS: usize = 16;

/// The pairs of a chunk of at most [`PLAN_QUADS`] quads and their first-level taps
/// ([`SharedPlan::plan`]).
pub(in super::super) struct SharedPlan {
    /// Bit `k`: quads `k` and `k + 1` are read as a pair.
    pairs: u32,
    /// Pair `k`'s taps on its first level (written where bit `k` of `pairs` is set).
    #[cfg(target_arch = "x86_64")]
    taps: [MaybeUninit<[super::sse2::Taps; 2]>; PLAN_QUADS],
}

impl SharedPlan {
    /// A plan with no pairs.
    #[inline]
    pub(in super::super) fn new() -> Self {
        SharedPlan {
            pairs: 0,
            #[cfg(target_arch = "x86_64")]
            taps: [const { MaybeUninit::uninit() }; PLAN_QUADS],
        }
    }

    /// Plans the reads of `shared` at `coords` on the levels `choices` names (through `s`):
    /// neighbours paired from the first quad on as the reads pair them, each pair's taps on
    /// its first level made, and every quad's first-level texels asked for (a pair's from
    /// those taps, a single quad's by `prefetch_shared`). Nothing is read.
    ///
    /// # Panics
    /// If there are more than [`PLAN_QUADS`] quads, or fewer `choices` than `coords`.
    #[inline]
    pub(in super::super) fn plan(
        &mut self,
        shared: &Shared,
        s: &Sampler,
        coords: &[QuadCoords],
        choices: &[MipChoice],
    ) {
        let n = coords.len();
        assert!(n <= PLAN_QUADS && choices.len() >= n);
        self.pairs = 0;
        #[cfg(target_arch = "x86_64")]
        {
            let lanes = crate::cpu::level() == crate::cpu::Level::V3;
            let mut k = 0;
            while k < n {
                if lanes && k + 1 < n && pairable([choices[k], choices[k + 1]]) {
                    let (both, c) = ([choices[k], choices[k + 1]], [&coords[k], &coords[k + 1]]);
                    // SAFETY: the CPU has x86-64-v3 (`cpu::level`); both quads read bilinear
                    // texels on the same levels (`pairable`).
                    unsafe { super::avx2::plan_pair(shared, s, both, c, &mut self.taps[k]) };
                    self.pairs |= 1 << k;
                    k += 2;
                } else {
                    super::prefetch_shared(shared, s, choices[k], coords[k].u, coords[k].v);
                    k += 1;
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = (shared, s, choices);
    }

    /// Whether quads `k` and `k + 1` are read as a pair ([`SharedPlan::read_pair`]).
    #[inline(always)]
    pub(in super::super) fn pair(&self, k: usize) -> bool {
        k < PLAN_QUADS && self.pairs >> k & 1 != 0
    }

    /// [`super::read_quad_shared`] of the pair of quads `k` and `k + 1` (`coords[j]`,
    /// `choices[j]`, `masks[j]` into `out[j]`), of the textures of `shared` (the plan's or
    /// another group of textures of their size and tiling), their first-level taps the
    /// plan's: the same values.
    ///
    /// # Panics
    /// If quads `k` and `k + 1` are not a pair of the plan ([`SharedPlan::pair`]).
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub(in super::super) fn read_pair(
        &self,
        k: usize,
        shared: &Shared,
        s: &Sampler,
        choices: [MipChoice; 2],
        coords: [&QuadCoords; 2],
        masks: [u8; 2],
        out: &mut [[[glam::Vec4; 4]; super::MAX_SHARED]; 2],
    ) {
        assert!(self.pair(k));
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the plan paired these quads, so the CPU has x86-64-v3 and both read
        // bilinear texels on the same levels; pair `k`'s taps were written.
        unsafe {
            let first = self.taps[k].assume_init_ref();
            super::avx2::linear_pair_shared(shared, s, choices, coords, masks, first, out);
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = (shared, s, choices, coords, masks, out);
    }
}

/// Whether two neighbouring quads read bilinear texels on the same levels (most do): then
/// the AVX2 reads make their taps together.
#[inline(always)]
fn pairable(choices: [MipChoice; 2]) -> bool {
    let levels = |c: &MipChoice| (c.texels, c.level, c.blend.map(|b| b.level));
    choices[0].texels == TexelFilter::Linear && levels(&choices[0]) == levels(&choices[1])
}
