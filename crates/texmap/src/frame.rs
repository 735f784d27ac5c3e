//! A rendered image: linear premultiplied colour and what it cost.
//!
//! The colour is linear light, premultiplied by alpha; alpha is the coverage of what was
//! drawn (surfaces, their antialiased edges, blended layers, volumes' accumulated opacity,
//! and a background unless it was left out). The 8-bit encodings below are the two ways it
//! leaves as a display image: composited over black ([`Frame::to_srgb8`]), or with straight
//! alpha for compositing ([`Frame::to_srgba8`]).

use glam::Vec4;
use rayon::prelude::*;

use crate::color::{encode_srgb8, encode_srgba8};
pub use crate::pixels::Pixels;

/// Pixels per parallel task of the 8-bit encodings (the order of the bytes does not depend on
/// it: every pixel is encoded on its own).
const CHUNK: usize = 16 * 1024;

/// What a frame cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameStats {
    pub triangles_submitted: u64,
    /// Triangles rasterized: after rejection, culling, clipping (a clipped triangle may become
    /// several) and subdivision.
    pub triangles_after_clip: u64,
    /// Fragment shader invocations (pixels × triangles, at the supersampled size), the pass
    /// that draws what transmitting surfaces see included.
    pub pixels_shaded: u64,
    pub texture_samples: u64,
    /// Virtual textures' pages this frame (all zero without any).
    pub virtual_pages: VirtualPageStats,
}

/// What a frame's feedback pass asked of the virtual textures' caches, and what moved.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VirtualPageStats {
    /// Pages the feedback pass asked for.
    pub requested: u64,
    /// Pages made and brought in.
    pub loaded: u64,
    /// Pages dropped to make room (least recently used first).
    pub evicted: u64,
    /// Pages asked for but left out: the budget was full of this frame's pages.
    pub over_budget: u64,
    /// Pages resident after the update (the pinned coarsest levels included).
    pub resident: u64,
    /// Reads whose page was not resident and that read a coarser level.
    pub fallback_reads: u64,
}

impl VirtualPageStats {
    /// The counts of two textures together (`resident` summed too).
    #[must_use]
    pub fn plus(self, o: VirtualPageStats) -> VirtualPageStats {
        VirtualPageStats {
            requested: self.requested + o.requested,
            loaded: self.loaded + o.loaded,
            evicted: self.evicted + o.evicted,
            over_budget: self.over_budget + o.over_budget,
            resident: self.resident + o.resident,
            fallback_reads: self.fallback_reads + o.fallback_reads,
        }
    }
}

/// A rendered image.
#[derive(Clone, Debug, Default)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// Linear, premultiplied RGBA, row-major, top row first.
    pub color: Pixels,
    pub stats: FrameStats,
}

impl Frame {
    /// RGB8 rows, sRGB-encoded (the premultiplied colour, i.e. composited over black).
    #[must_use]
    pub fn to_srgb8(&self) -> Vec<u8> {
        srgb8(&self.color)
    }

    /// RGBA8 rows with straight (un-premultiplied) alpha, as PNG stores it: the colour is
    /// the sRGB code of `rgb / a` (exactly rounded, as [`Frame::to_srgb8`]), alpha the 8-bit
    /// code of `a` rounded to nearest; a pixel of alpha 0 is `(0, 0, 0, 0)`.
    ///
    /// Laying the result over black in linear light gives back [`Frame::to_srgb8`]'s colour
    /// (within the 8-bit rounding of alpha).
    ///
    /// ```
    /// use glam::Vec4;
    /// use texmap::frame::Frame;
    ///
    /// // Half of a white pixel covered, and an empty one.
    /// let frame = Frame {
    ///     width: 2,
    ///     height: 1,
    ///     color: vec![Vec4::new(0.5, 0.5, 0.5, 0.5), Vec4::ZERO].into(),
    ///     ..Frame::default()
    /// };
    /// assert_eq!(frame.to_srgba8(), [255, 255, 255, 128, 0, 0, 0, 0]);
    /// ```
    #[must_use]
    pub fn to_srgba8(&self) -> Vec<u8> {
        srgba8(&self.color)
    }
}

/// [`Frame::to_srgb8`] of some pixels (a band of a frame's rows, say).
#[must_use]
pub fn srgb8(color: &[Vec4]) -> Vec<u8> {
    let mut out = vec![0; color.len() * 3];
    out.par_chunks_mut(3 * CHUNK)
        .zip(color.par_chunks(CHUNK))
        .for_each(|(out, color)| encode_srgb8(color, out));
    out
}

/// [`Frame::to_srgba8`] of some pixels (a band of a frame's rows, say).
#[must_use]
pub fn srgba8(color: &[Vec4]) -> Vec<u8> {
    let mut out = vec![0; color.len() * 4];
    out.par_chunks_mut(4 * CHUNK)
        .zip(color.par_chunks(CHUNK))
        .for_each(|(out, color)| encode_srgba8(color, out));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::{linear_to_srgb8, srgb_to_linear};

    fn frame(color: Vec<Vec4>) -> Frame {
        Frame {
            width: color.len() as u32,
            height: 1,
            color: color.into(),
            ..Frame::default()
        }
    }

    #[test]
    fn opaque_pixels_have_the_same_colour_in_both_encodings() {
        let f = frame(vec![
            Vec4::new(0.2, 0.5, 1.0, 1.0),
            Vec4::new(0.0, 0.01, 0.3, 1.0),
        ]);
        let rgb = f.to_srgb8();
        let rgba = f.to_srgba8();
        for p in 0..2 {
            assert_eq!(rgb[3 * p..3 * p + 3], rgba[4 * p..4 * p + 3], "pixel {p}");
            assert_eq!(rgba[4 * p + 3], 255);
        }
    }

    #[test]
    fn straight_alpha_undoes_the_premultiplication() {
        // A red surface covering a quarter of the pixel, a blue one 0.9 of it.
        let f = frame(vec![
            Vec4::new(0.25, 0.0, 0.0, 0.25),
            Vec4::new(0.0, 0.0, 0.9 * 0.4, 0.9),
        ]);
        let rgba = f.to_srgba8();
        assert_eq!(rgba[..4], [255, 0, 0, 64]);
        assert_eq!(rgba[4 + 2], linear_to_srgb8(0.4));
        assert_eq!(rgba[4 + 3], 230);
        // Over black in linear light: within a code of the composited encoding.
        let rgb = f.to_srgb8();
        for p in 0..2 {
            for k in 0..3 {
                let a = f32::from(rgba[4 * p + 3]) / 255.0;
                let over = linear_to_srgb8(srgb_to_linear(f32::from(rgba[4 * p + k]) / 255.0) * a);
                assert!(over.abs_diff(rgb[3 * p + k]) <= 1, "pixel {p} channel {k}");
            }
        }
    }

    #[test]
    fn empty_and_non_finite_alpha_are_transparent_black() {
        let f = frame(vec![
            Vec4::ZERO,
            Vec4::new(0.3, 0.3, 0.3, 0.0),
            Vec4::new(0.3, 0.3, 0.3, f32::NAN),
        ]);
        assert_eq!(f.to_srgba8(), [0; 12]);
    }
}
