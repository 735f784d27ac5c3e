//! OpenGL's level choice: which mip levels a read takes at level of detail λ, with what
//! weights, and whether it reads texels nearest or linearly (section 8.14 of the GL 4.6 core
//! specification).
//!
//! This is the one place the rule is written: 2D reads (single footprints, quads and batches
//! of quads, the fixed-point path included), cube maps and 3D textures all ask
//! [`MipChoice::gl`] and then read the levels it names, each in its own way. λ comes in with
//! the sampler's bias and clamps applied ([`super::Sampler::adjust_lod`]).
//!
//! The rule, for `q` the last level:
//! - λ ≤ 0 (and NaN, from a degenerate footprint) magnifies: level 0 with the magnification
//!   filter.
//! - `NEAREST` and `LINEAR` minify on level 0 only.
//! - `*_MIPMAP_NEAREST` read one level: 0 while λ ≤ ½, else ⌈λ + ½⌉ − 1, at most `q`.
//! - `*_MIPMAP_LINEAR` blend levels ⌊λ⌋ and ⌊λ⌋ + 1 by the fraction of λ, λ clamped to `q`
//!   (a whole λ, and λ ≥ `q`, read one level).
//!
//! The choice is a small `Copy` value the hot quad path computes once per quad: keep
//! [`MipChoice::gl`] branch-light and inlined (it feeds every pixel of a trilinear frame).

use glam::Vec4;

use super::{MagFilter, MinFilter};

/// How the texels of one level are read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TexelFilter {
    /// The texel containing the point (`GL_NEAREST`).
    Nearest,
    /// Interpolated between the texels around the point: bilinear on 2D levels and cube
    /// faces, trilinear on 3D levels (`GL_LINEAR`).
    Linear,
}

/// The second level of a two-level read and its weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MipBlend {
    /// The level blended in (the first level + 1).
    pub level: usize,
    /// Its weight in (0, 1): the read is `first.lerp(second, weight)`.
    pub weight: f32,
}

/// The levels a read takes and how it reads them: [`MipChoice::gl`]'s answer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MipChoice {
    /// The level read, or the first of the two blended.
    pub level: usize,
    /// The second level and its weight, when two levels are blended.
    pub blend: Option<MipBlend>,
    /// How texels are read within each level.
    pub texels: TexelFilter,
}

impl MipChoice {
    /// Level 0, nearest texels.
    pub const LEVEL0: MipChoice = MipChoice {
        level: 0,
        blend: None,
        texels: TexelFilter::Nearest,
    };

    /// [`MipChoice::gl`]'s choice for every λ, when λ cannot change it: the magnification
    /// and minification filters read texels alike and minification reads level 0 only
    /// (`NEAREST` or `LINEAR`, or a chain of one level). `None` otherwise.
    #[inline(always)]
    #[must_use]
    pub fn fixed(level_count: usize, mag: MagFilter, min: MinFilter) -> Option<MipChoice> {
        let min_texels = match min {
            MinFilter::Nearest
            | MinFilter::NearestMipmapNearest
            | MinFilter::NearestMipmapLinear => TexelFilter::Nearest,
            _ => TexelFilter::Linear,
        };
        let mag_texels = match mag {
            MagFilter::Nearest => TexelFilter::Nearest,
            MagFilter::Linear => TexelFilter::Linear,
        };
        let level0 = level_count <= 1 || matches!(min, MinFilter::Nearest | MinFilter::Linear);
        (level0 && min_texels == mag_texels).then_some(MipChoice {
            level: 0,
            blend: None,
            texels: min_texels,
        })
    }

    /// OpenGL's choice at level of detail `lod` (bias and clamps applied) on a chain of
    /// `level_count` levels (at least one) for the filter pair `mag`/`min`.
    #[inline(always)]
    #[must_use]
    pub fn gl(lod: f32, level_count: usize, mag: MagFilter, min: MinFilter) -> MipChoice {
        let one = |level, texels| MipChoice {
            level,
            blend: None,
            texels,
        };
        // λ ≤ 0 (or NaN from a degenerate footprint) magnifies.
        if !(lod > 0.0) {
            return one(
                0,
                match mag {
                    MagFilter::Nearest => TexelFilter::Nearest,
                    MagFilter::Linear => TexelFilter::Linear,
                },
            );
        }
        let last = level_count - 1;
        let nearest_level = || {
            if lod <= 0.5 {
                0
            } else {
                (((lod + 0.5).ceil() as usize) - 1).min(last)
            }
        };
        let between = |texels| {
            let l = lod.min(last as f32);
            let d = l.floor();
            let f = l - d;
            MipChoice {
                level: d as usize,
                blend: (f > 0.0).then_some(MipBlend {
                    level: d as usize + 1,
                    weight: f,
                }),
                texels,
            }
        };
        match min {
            MinFilter::Nearest => one(0, TexelFilter::Nearest),
            MinFilter::Linear => one(0, TexelFilter::Linear),
            MinFilter::NearestMipmapNearest => one(nearest_level(), TexelFilter::Nearest),
            MinFilter::LinearMipmapNearest => one(nearest_level(), TexelFilter::Linear),
            MinFilter::NearestMipmapLinear => between(TexelFilter::Nearest),
            MinFilter::LinearMipmapLinear => between(TexelFilter::Linear),
        }
    }

    /// Trilinear's choice (`GL_LINEAR` / `GL_LINEAR_MIPMAP_LINEAR`): what anisotropic taps
    /// read, and what filters with no form of their own on a texture kind fall back to.
    #[inline(always)]
    #[must_use]
    pub fn trilinear(lod: f32, level_count: usize) -> MipChoice {
        MipChoice::gl(
            lod,
            level_count,
            MagFilter::Linear,
            MinFilter::LinearMipmapLinear,
        )
    }

    /// The chosen read: `read(level)`, blended with `read(second)` by its weight when two
    /// levels are chosen.
    #[inline(always)]
    #[must_use]
    pub fn read(self, mut read: impl FnMut(usize) -> Vec4) -> Vec4 {
        let a = read(self.level);
        match self.blend {
            Some(b) => a.lerp(read(b.level), b.weight),
            None => a,
        }
    }
}

#[cfg(test)]
mod tests;
