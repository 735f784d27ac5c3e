//! Bilinear and trilinear reads of a quad's four pixels on the default storage (16-bit
//! linear premultiplied texels, 4×4 tiles) in fixed point, with SSE2: the path that the
//! plain textured triangle takes, and so most of a frame's texels. Nearest reads share the
//! lane-wise addressing and return exactly the float path's values. The 8-bit storage
//! (`Storage::Rgba8`, RGBA8 in 4×4 tiles) is read the same way, each texel widened to 16-bit
//! linear as it is loaded: an sRGB code through a 256-entry table (the value the default
//! storage holds for it), a linear one as `c · 257`, colour times alpha unless opaque.
//!
//! A pixel's taps (four per level, at most eight) are summed as `Σ t·w` with `pmaddwd`:
//! - each texel enters as 15 bits (its 16-bit value shifted right once), two texels' channels
//!   interleaved in one register, so one `pmaddwd` multiplies and adds a pair of taps exactly
//!   into 32-bit lanes;
//! - the weights (bilinear × level) are rounded to 15 bits, and the last tap of each level takes
//!   what the others leave, so the weights of a read sum to exactly 32767 and a constant texture
//!   reads back its (15-bit) value.
//!
//! The float filters ([`super::bilinear`] on each level, blended) give the same value within
//! 1.6·10⁻⁴ (eight weights off by at most half a step of 1/32767, plus the dropped bit), about
//! half the smallest step an 8-bit sRGB output can show (3·10⁻⁴, at black). GPUs filter with
//! 8-bit weights; these are 15-bit. A pair of taps costs two loads, an interleave, a shift, a
//! multiply-add and an add, where the float filter converts, scales and interpolates each tap.
//!
//! The levels and their weights come from [`MipChoice::gl`] like every other OpenGL read;
//! a trilinear batch takes them straight from each quad's λ, the same operations without
//! the choice made (`trilinear.rs`).
//!
//! Anisotropic filtering's taps ([`read_probes`]) are such trilinear reads at several points
//! of a quad's major axis, all summed into the same 32-bit accumulators: each probe's share of
//! the 15-bit total is what the running sum of the probes' weights adds when rounded, so the
//! weights of all the taps still sum to exactly 32767. The probes and their weights depend on
//! the probe count alone, so they are made once per count ([`weights::ProbeSets`]).
//!
//! Only the repeat and clamp-to-edge wraps are handled here (indices by integer wrapping and
//! float clamps); other wraps, other formats and other targets return `None` and the float
//! filter serves.

use glam::Vec4;

use super::super::storage::{LevelRef, Rgba8Texels};
use super::super::{Format, Layout, MipChoice, Sampler, TexelFilter, Texture2D, Wrap};
use super::QuadCoords;

/// The largest 15-bit weight: a read's weights sum to it.
const ONE: i32 = 32767;

/// How a texture's texels enter the fixed-point sums. (One word: the RGBA8 widening is
/// the texture's own, lent. Held by value, its 17 bytes of fields and 7 of padding were
/// copied at every call that passes it, the padding by two overlapping moves.)
#[derive(Clone, Copy)]
enum Texels<'t> {
    /// 16-bit linear premultiplied ([`super::super::Storage::Linear16`]): loaded as they are.
    Linear16,
    /// RGBA8 ([`super::super::Storage::Rgba8`]): each channel widened to 16-bit linear (an sRGB
    /// code through a 256-entry table, a linear one as `c · 257`), colour times alpha unless
    /// the texture is opaque.
    Rgba8(&'t Rgba8Texels),
}

/// How these reads take `tex`'s texels through `s`, when they serve it: the default storage
/// or [`super::super::Storage::Rgba8`], tiled, repeat or clamp to edge on both axes.
#[inline]
fn texels_of<'t>(tex: &'t Texture2D, s: &Sampler) -> Option<Texels<'t>> {
    let wrap = |w: Wrap| matches!(w, Wrap::Repeat | Wrap::ClampToEdge);
    if tex.layout() != Layout::Tiled4x4 || !wrap(s.wrap_u) || !wrap(s.wrap_v) {
        return None;
    }
    if tex.storage_format() == Format::Rgba16Premultiplied {
        Some(Texels::Linear16)
    } else {
        tex.rgba8_texels().map(Texels::Rgba8)
    }
}

/// Whether these reads serve `tex` through `s` (see `texels_of`).
#[inline]
pub(super) fn serves(tex: &Texture2D, s: &Sampler) -> bool {
    texels_of(tex, s).is_some()
}

mod quads;
pub(super) use quads::{read_level_quads, read_quad, read_quads, LEVEL_QUADS};

mod prefetch;
pub(super) use prefetch::prefetch_quads;
#[cfg(target_arch = "x86_64")]
pub(super) use prefetch::prefetch_shared;

mod trilinear;
pub(super) use trilinear::read_trilinear;

mod weights;
pub(super) use weights::{Probe, ProbeSets, MAX_PROBES};

mod probed;
pub(super) use probed::ProbeReader;

/// The most textures [`read_quad_shared`] reads together.
pub(super) const MAX_SHARED: usize = 5;

/// Textures that [`read_quad_shared`] reads together through one sampler, checked once for
/// all the quads read: at most [`MAX_SHARED`], of one size, each served by these reads (how
/// each texture's texels enter the sums). It holds every level of the textures, each
/// texture's tiled texels looked up and checked when it was made (a draw makes it once for
/// all its quads), so the reads only index them.
pub(super) struct Shared<'a> {
    count: usize,
    texels: [Texels<'a>; MAX_SHARED],
    levels: Vec<SharedLevel<'a>>,
}

/// One level of every texture of a [`Shared`]: the first texture's view (whose size the
/// taps are computed for) and each texture's tiled texels, checked to be a level of that
/// size and tiling holding enough bytes.
struct SharedLevel<'a> {
    first: LevelRef<'a>,
    tiles_x: u32,
    data: [&'a [u8]; MAX_SHARED],
}

impl<'a> Shared<'a> {
    /// `texes` through `s`, when these reads serve them all together.
    ///
    /// # Panics
    /// If a texture's level is not of the first one's size and tiling, or not a tiled level
    /// of its texels (the sizes are checked; the tiling follows from them).
    #[inline]
    pub(super) fn new(texes: &[&'a Texture2D], s: &Sampler) -> Option<Self> {
        let first = *texes.first()?;
        if texes.len() > MAX_SHARED {
            return None;
        }
        let size = |t: &Texture2D| (t.width(), t.height(), t.levels().len());
        let mut texels = [Texels::Linear16; MAX_SHARED];
        for (slot, t) in texels.iter_mut().zip(texes) {
            if size(t) != size(first) {
                return None;
            }
            *slot = texels_of(t, s)?;
        }
        let levels = (0..first.levels().len())
            .map(|index| {
                let first = first.level(index);
                let mut data = [&[][..]; MAX_SHARED];
                let mut tiles_x = 0;
                for (k, (tex, &texels)) in texes.iter().zip(&texels).enumerate() {
                    let lv = tex.level(index);
                    assert!(
                        (lv.w, lv.h) == (first.w, first.h),
                        "shared levels differ in size"
                    );
                    let (d, tx) = lv.tiled_texels(bpp(texels));
                    if k == 0 {
                        tiles_x = tx;
                    }
                    assert_eq!(tx, tiles_x, "shared levels differ in tiling");
                    data[k] = d;
                }
                SharedLevel {
                    first,
                    tiles_x,
                    data,
                }
            })
            .collect();
        Some(Shared {
            count: texes.len(),
            texels,
            levels,
        })
    }

    /// How many textures are read together.
    #[inline]
    fn len(&self) -> usize {
        self.count
    }

    /// Level `index` of every texture.
    ///
    /// # Panics
    /// If the textures have no such level (a [`MipChoice`] names only levels they have).
    #[inline]
    fn level(&self, index: usize) -> &SharedLevel<'a> {
        &self.levels[index]
    }
}

impl Texels<'_> {
    /// Whether the AVX2 gathers read these texels in lanes (`avx2/gather.rs`): the 16-bit
    /// storage, and opaque RGBA8 texels with linear codes; the others are gathered as the
    /// SSE2 path gathers them.
    #[inline(always)]
    fn in_lanes(self) -> bool {
        match self {
            Texels::Linear16 => true,
            Texels::Rgba8(r) => r.opaque_linear(),
        }
    }
}

/// Bytes a texel of `texels` takes.
#[inline(always)]
fn bpp(texels: Texels) -> usize {
    match texels {
        Texels::Linear16 => 8,
        Texels::Rgba8(_) => 4,
    }
}

/// [`read_quad`] of the textures of `shared` at the same coordinates through the same
/// sampler, on the same levels: textures of one size, so one level's texel indices and
/// weights serve them all. They are computed once per level, and each texture's taps are
/// summed as [`read_quad`] sums them (the same values, bit for bit); `out[t]` gets texture
/// `t`'s reads. `false`, and nothing read, when the read is not bilinear.
///
/// # Panics
/// If `out` is shorter than the textures.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(super) fn read_quad_shared(
    shared: &Shared,
    s: &Sampler,
    choice: MipChoice,
    u: Vec4,
    v: Vec4,
    mask: u8,
    out: &mut [[Vec4; 4]],
) -> bool {
    assert!(out.len() >= shared.len());
    if choice.texels != TexelFilter::Linear {
        return false;
    }
    #[cfg(target_arch = "x86_64")]
    {
        sse2::linear_quad_shared(shared, s, choice, u, v, mask, out);
        true
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (shared, u, v, mask);
        false
    }
}

/// [`read_quad_shared`] of two quads (`coords[k]`, `choices[k]`, `masks[k]` into
/// `out[k]`) at once, their taps on each level computed together in AVX2 lanes: the same
/// values. `false`, and nothing read, unless the CPU has x86-64-v3 ([`crate::cpu::level`])
/// and both quads read bilinear texels on the same levels (most neighbours do).
#[inline]
pub(super) fn read_pair_shared(
    shared: &Shared,
    s: &Sampler,
    choices: [MipChoice; 2],
    coords: [&QuadCoords; 2],
    masks: [u8; 2],
    out: &mut [[[Vec4; 4]; MAX_SHARED]; 2],
) -> bool {
    let levels = |c: &MipChoice| (c.texels, c.level, c.blend.map(|b| b.level));
    let same =
        choices[0].texels == TexelFilter::Linear && levels(&choices[0]) == levels(&choices[1]);
    #[cfg(target_arch = "x86_64")]
    if same && crate::cpu::level() == crate::cpu::Level::V3 {
        // SAFETY: the CPU has x86-64-v3 (`cpu::level`); both quads read the same levels.
        unsafe { avx2::linear_pair_shared(shared, s, choices, coords, masks, out) };
        return true;
    }
    let _ = (same, shared, s, coords, masks, out);
    false
}

/// A quad's probes (anisotropic filtering in lanes): for each [`Probe`] of `probes`, a
/// fixed-point trilinear read on the levels `choice` names at `(u, v) + t·step` (one pixel per
/// lane), the reads summed with its 15-bit weight (the weights summing to `ONE`, as
/// [`weights::fixed`] makes them), every tap's 15-bit weight in one sum
/// (a constant texture reads back its value). Against the float filter: within 1.6·10⁻⁴ over
/// 20,000 random footprints of up to 16 taps (the property test of `filter/tests.rs`). Pixels
/// whose `mask` bit is clear are left zero. `None` when this texture or sampler is not one
/// this path handles, or `choice` reads nearest texels.
#[inline]
pub(super) fn read_probes(
    tex: &Texture2D,
    s: &Sampler,
    choice: MipChoice,
    uv: (Vec4, Vec4),
    step: glam::Vec2,
    probes: &[Probe],
    mask: u8,
) -> Option<[Vec4; 4]> {
    read_probes_inlined(tex, s, choice, uv, step, probes, mask)
}

/// [`read_probes`] inlined into its caller: anisotropic filtering's quads, so that the batch's
/// copy compiled for x86-64-v3 ([`crate::cpu`]) runs them at that level. (EWA's probes call
/// [`read_probes`]: inlined there they cost 1 % more instructions.)
#[inline(always)]
pub(super) fn read_probes_inlined(
    tex: &Texture2D,
    s: &Sampler,
    choice: MipChoice,
    (u, v): (Vec4, Vec4),
    step: glam::Vec2,
    probes: &[Probe],
    mask: u8,
) -> Option<[Vec4; 4]> {
    let texels = texels_of(tex, s)?;
    if choice.texels != TexelFilter::Linear {
        return None;
    }
    #[cfg(target_arch = "x86_64")]
    {
        let first = sse2::level_of(tex, texels, choice.level);
        let second = choice.blend.map(|b| sse2::level_of(tex, texels, b.level));
        Some(sse2::probes_on(
            &first,
            second.as_ref(),
            texels,
            s,
            choice,
            (u, v),
            step,
            probes,
            mask,
        ))
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (texels, u, v, step, probes, mask);
        None
    }
}

#[cfg(target_arch = "x86_64")]
mod sse2;

#[cfg(target_arch = "x86_64")]
mod avx2;
