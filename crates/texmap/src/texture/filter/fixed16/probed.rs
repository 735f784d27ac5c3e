//! Probed reads of a batch's quads (anisotropic filtering, `ewa`'s probes) on the fixed-point
//! path: [`super::read_probes`] quad after quad, with the texture's storage checked once
//! for the batch and each level looked up once while consecutive quads read it (neighbours
//! mostly take the same levels), so that a quad pays its probes' taps, not the storage's
//! bookkeeping.

use glam::{Vec2, Vec4};

use super::super::super::{MipChoice, Sampler, TexelFilter, Texture2D};
#[cfg(target_arch = "x86_64")]
use super::avx2;
#[cfg(target_arch = "x86_64")]
use super::prefetch::{prefetch_lanes, PREFETCH_BYTES};
#[cfg(target_arch = "x86_64")]
use super::sse2::{self, Level};
#[cfg(target_arch = "x86_64")]
use super::ONE;
use super::{texels_of, Probe, Texels};

/// A batch's reader of probed quads on one texture.
pub(in super::super) struct ProbeReader<'t> {
    tex: &'t Texture2D,
    texels: Texels<'t>,
    /// The levels last read first and second, with their indices.
    #[cfg(target_arch = "x86_64")]
    levels: [Option<(usize, Level<'t>)>; 2],
}

impl<'t> ProbeReader<'t> {
    /// A reader of `tex` through `s`: `None` where the fixed-point path does not serve them
    /// (as [`super::read_probes`] returns `None`).
    #[inline(always)]
    pub(in super::super) fn new(tex: &'t Texture2D, s: &Sampler) -> Option<Self> {
        let texels = texels_of(tex, s);
        #[cfg(not(target_arch = "x86_64"))]
        let texels: Option<Texels> = texels.and(None);
        Some(ProbeReader {
            tex,
            texels: texels?,
            #[cfg(target_arch = "x86_64")]
            levels: [None, None],
        })
    }

    /// Level `index` in `slot` (0 for a read's first level, 1 for its second), looked up
    /// when the slot holds another.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn level(&mut self, slot: usize, index: usize) -> Level<'t> {
        match self.levels[slot] {
            Some((held, level)) if held == index => level,
            _ => {
                let level = sse2::level_of(self.tex, self.texels, index);
                self.levels[slot] = Some((index, level));
                level
            }
        }
    }

    /// [`Self::level`]'s parts that the AVX2 reads use ([`avx2::Level`]), copied out of the
    /// slot rather than the whole level view.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn part(&mut self, slot: usize, index: usize) -> avx2::Level<'t> {
        if !matches!(self.levels[slot], Some((held, _)) if held == index) {
            self.levels[slot] = Some((index, sse2::level_of(self.tex, self.texels, index)));
        }
        let Some((_, (lv, data, tiles_x))) = &self.levels[slot] else {
            unreachable!("slot {slot} was just filled")
        };
        (avx2::size(lv), data, *tiles_x)
    }

    /// Asks the cache for quad `(u, v)`'s texels on `level`, the first level its plan reads
    /// (bilinear taps, as every probe reads), where that level is larger than
    /// [`PREFETCH_BYTES`]: each covered pixel's first bilinear tap at its own coordinates
    /// (the centre of its probes, which spread along an axis from there). Its last tap as
    /// well, as [`super::prefetch_quads`] asks for a quad's, made `aniso5-area`'s frame
    /// 1.02× and `ewa`'s 1.01× this (a line a pixel is enough; the four corners of the
    /// quad's taps instead were slower still). A batch asks for every quad's after planning
    /// them and before reading any (`quads.rs`). The level is the reader's slot 0, looked
    /// up only when the quad's is another (as for a read). Nothing is read or changed.
    #[inline(always)]
    pub(in super::super) fn prefetch(
        &mut self,
        s: &Sampler,
        level: usize,
        (u, v): (Vec4, Vec4),
        mask: u8,
    ) {
        #[cfg(target_arch = "x86_64")]
        {
            let (size, data, tiles_x) = self.part(0, level);
            if data.len() > PREFETCH_BYTES {
                let t = sse2::sized_taps(size, tiles_x, s, u, v, ONE);
                prefetch_lanes(data, sse2::bpp(self.texels), &[&t.offsets[0]], mask);
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = (s, level, u, v, mask);
    }

    /// [`super::read_probes`] of quad `(u, v)`: the same values. `choice` must read linear
    /// texels (every probed filter's does: `MipChoice::trilinear`; checked in debug builds),
    /// where `read_probes` would return `None` for a nearest one.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(in super::super) fn read(
        &mut self,
        s: &Sampler,
        choice: MipChoice,
        uv: (Vec4, Vec4),
        step: Vec2,
        probes: &[Probe],
        mask: u8,
    ) -> [Vec4; 4] {
        debug_assert_eq!(choice.texels, TexelFilter::Linear);
        #[cfg(target_arch = "x86_64")]
        {
            if crate::cpu::level() == crate::cpu::Level::V3 {
                // Inlined, with its intrinsics, where the batch runs at x86-64-v3 (the only
                // copy in which this branch runs).
                let first = self.part(0, choice.level);
                let second = choice.blend.map(|b| self.part(1, b.level));
                let fa = sse2::first_share(choice);
                // SAFETY: the CPU has x86-64-v3 (`cpu::level`).
                return unsafe {
                    avx2::probe_quad_inlined(
                        (first, second),
                        self.texels,
                        s,
                        fa,
                        uv,
                        step,
                        probes,
                        mask,
                    )
                };
            }
            let first = self.level(0, choice.level);
            let second = choice.blend.map(|b| self.level(1, b.level));
            sse2::probes_on(
                &first,
                second.as_ref(),
                self.texels,
                s,
                choice,
                uv,
                step,
                probes,
                mask,
            )
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = (s, choice, uv, step, probes, mask);
            unreachable!("no reader is made off x86_64 (`new`)")
        }
    }
}
