//! One texture's reads on the fixed-point path: a quad ([`read_quad`]) and a batch of quads
//! ([`read_quads`], what [`super::super::sample_quads_lanes`] asks for).
//!
//! The batch checks once that the texture and sampler are ones this path serves, and keeps
//! the view of the level its nearest reads take while consecutive quads stay on it (most
//! do: a whole batch of a plane reads level 0): a quad pays its texel addresses and loads,
//! not the storage's bookkeeping.

use glam::Vec4;

use super::super::super::{MipChoice, Sampler, TexelFilter, Texture2D};
use super::super::QuadCoords;
#[cfg(target_arch = "x86_64")]
use super::sse2;
use super::{texels_of, Texels};

/// A quad's reads at `(u, v)` (one pixel per lane, pixels whose `mask` bit is clear left
/// zero) on the levels `choice` names: bilinear in fixed point for [`TexelFilter::Linear`],
/// else nearest — the same texels and values as the float path's `nearest` (its wrap of an
/// index that rounds up to the size, its index 0 for NaN), with the index arithmetic in
/// lanes. `None` when this texture or sampler is not one this path handles.
#[inline]
pub(in super::super) fn read_quad(
    tex: &Texture2D,
    s: &Sampler,
    choice: MipChoice,
    u: Vec4,
    v: Vec4,
    mask: u8,
) -> Option<[Vec4; 4]> {
    let texels = texels_of(tex, s)?;
    #[cfg(target_arch = "x86_64")]
    {
        Some(read_with(tex, texels, s, choice, u, v, mask))
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (texels, choice, u, v, mask);
        None
    }
}

/// [`read_quad`] of each quad of a batch: `out[i]` for `coords[i]`, `choices[i]` and
/// `masks[i]`, the same values quad for quad. `false`, and nothing read, when this texture or
/// sampler is not one this path handles.
///
/// # Panics
/// If `choices`, `masks` or `out` is shorter than `coords`.
#[inline(always)]
pub(in super::super) fn read_quads(
    tex: &Texture2D,
    s: &Sampler,
    coords: &[QuadCoords],
    choices: &[MipChoice],
    masks: &[u8],
    out: &mut [[Vec4; 4]],
) -> bool {
    let Some(texels) = texels_of(tex, s) else {
        return false;
    };
    assert!(choices.len() >= coords.len() && masks.len() >= coords.len());
    assert!(out.len() >= coords.len());
    #[cfg(target_arch = "x86_64")]
    {
        // The level the last nearest read took, and its view.
        let mut view = None;
        for (((c, &choice), &mask), o) in coords.iter().zip(choices).zip(masks).zip(out) {
            if choice.texels == TexelFilter::Nearest && choice.blend.is_none() {
                let lv = match view {
                    Some((level, lv)) if level == choice.level => lv,
                    _ => {
                        let lv = tex.level(choice.level);
                        view = Some((choice.level, lv));
                        lv
                    }
                };
                *o = sse2::nearest_level(lv, texels, s, c.u, c.v, mask);
            } else {
                *o = read_with(tex, texels, s, choice, c.u, c.v, mask);
            }
        }
        true
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (texels, coords, choices, masks, out);
        false
    }
}

/// [`read_quad`] once the texture's texels are known to be served (`texels`).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn read_with(
    tex: &Texture2D,
    texels: Texels,
    s: &Sampler,
    choice: MipChoice,
    u: Vec4,
    v: Vec4,
    mask: u8,
) -> [Vec4; 4] {
    if choice.texels == TexelFilter::Linear {
        return sse2::linear_quad(tex, texels, s, choice, u, v, mask);
    }
    let a = sse2::nearest_level(tex.level(choice.level), texels, s, u, v, mask);
    match choice.blend {
        Some(b) => {
            let (f, b) = (
                b.weight,
                sse2::nearest_level(tex.level(b.level), texels, s, u, v, mask),
            );
            std::array::from_fn(|j| a[j].lerp(b[j], f))
        }
        None => a,
    }
}
