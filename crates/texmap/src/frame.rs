//! A rendered image: linear premultiplied colour and what it cost.

use glam::Vec4;

use crate::color::linear_to_srgb8;

/// What a frame cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameStats {
    pub triangles_submitted: u64,
    /// Triangles rasterized: after rejection, culling, clipping (a clipped triangle may become
    /// several) and subdivision.
    pub triangles_after_clip: u64,
    /// Fragment shader invocations (pixels × triangles, at the supersampled size).
    pub pixels_shaded: u64,
    pub texture_samples: u64,
}

/// A rendered image.
#[derive(Clone, Debug, Default)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// Linear, premultiplied RGBA, row-major, top row first.
    pub color: Vec<Vec4>,
    pub stats: FrameStats,
}

impl Frame {
    /// RGB8 rows, sRGB-encoded (the premultiplied colour, i.e. composited over black).
    #[must_use]
    pub fn to_srgb8(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.color.len() * 3);
        for c in &self.color {
            out.extend([c.x, c.y, c.z].map(linear_to_srgb8));
        }
        out
    }
}
