//! Filling a level in place: each texel written straight into the level's layout (tiled or
//! row-major), bands of four rows in parallel (rayon), with no row-major copy in between.
//! Every texel is a function of its position alone, so the bytes are the same whatever the
//! thread count.

use glam::Vec4;
use rayon::prelude::*;

use super::{mip, Layout, Level, Texture2D};
use crate::texture::format::{with_codec, Format};

impl Texture2D {
    /// A `width`×`height` level of the stored format whose texel `(x, y)` is written by
    /// `f(x, y, bytes)`.
    pub(super) fn fill_level(
        &self,
        width: u32,
        height: u32,
        f: impl Fn(u32, u32, &mut [u8]) + Sync,
    ) -> Level {
        let bpp = self.stored.bytes_per_texel();
        let tiles_x = width.div_ceil(4);
        // Texels in a band of four rows (a row of tiles, padding included).
        let band = match self.layout {
            Layout::RowMajor => width as usize * 4,
            Layout::Tiled4x4 => tiles_x as usize * 16,
        };
        let bands = height.div_ceil(4) as usize;
        let len = match self.layout {
            Layout::RowMajor => (width * height) as usize,
            Layout::Tiled4x4 => band * bands,
        };
        let mut data = vec![0u8; len * bpp];
        let layout = self.layout;
        data.par_chunks_mut(band * bpp)
            .enumerate()
            .for_each(|(b, chunk)| {
                let start = b * band;
                for y in (b as u32 * 4)..(b as u32 * 4 + 4).min(height) {
                    for x in 0..width {
                        let i = super::texel_index(layout, tiles_x, width, x, y) - start;
                        f(x, y, &mut chunk[i * bpp..(i + 1) * bpp]);
                    }
                }
            });
        Level {
            width,
            height,
            tiles_x,
            data,
            block_id: None,
        }
    }

    /// A level of the stored format from row-major linear premultiplied texels.
    pub(super) fn store_linear(&self, width: u32, height: u32, texels: &[Vec4]) -> Level {
        let (stored, cs) = (self.stored, self.color_space);
        if stored == Format::Rgba16Premultiplied {
            // `Format::encode`'s arm for this format, inlined: the same values.
            return self.fill_level(width, height, |x, y, out| {
                let c = mip::unpremultiply(texels[(y * width + x) as usize]);
                let a = c.w.clamp(0.0, 1.0);
                let p = (c.truncate() * a).extend(a);
                for (o, v) in out.chunks_exact_mut(2).zip(p.to_array()) {
                    o.copy_from_slice(&((v.clamp(0.0, 1.0) * 65535.0 + 0.5) as u16).to_le_bytes());
                }
            });
        }
        self.fill_level(width, height, |x, y, out| {
            let c = texels[(y * width + x) as usize];
            stored.encode(mip::unpremultiply(c), cs, out);
        })
    }

    /// A level of the stored format from row-major texels given in `format` (decoded with
    /// `lut`): copied when the stored format is the given one, converted texel by texel
    /// otherwise (opaque RGB8 to 16-bit linear through a 256-entry table, the same values the
    /// float conversion gives).
    pub(super) fn store_given(
        &self,
        width: u32,
        height: u32,
        format: Format,
        lut: &[f32],
        texels: &[u8],
    ) -> Level {
        let bpp = format.bytes_per_texel();
        let at = move |x: u32, y: u32| (y * width + x) as usize * bpp;
        if format == self.stored {
            return self.fill_level(width, height, |x, y, out| {
                out.copy_from_slice(&texels[at(x, y)..at(x, y) + bpp]);
            });
        }
        if format == Format::Rgb8 && self.stored == Format::Rgba16Premultiplied {
            // Alpha 1: unpremultiplying and premultiplying again change nothing, so each
            // channel is the code's linear value rounded to 16 bits.
            let q: Vec<[u8; 2]> = lut
                .iter()
                .map(|v| ((v.clamp(0.0, 1.0) * 65535.0 + 0.5) as u16).to_le_bytes())
                .collect();
            return self.fill_level(width, height, |x, y, out| {
                let t = &texels[at(x, y)..at(x, y) + 3];
                out[0..2].copy_from_slice(&q[t[0] as usize]);
                out[2..4].copy_from_slice(&q[t[1] as usize]);
                out[4..6].copy_from_slice(&q[t[2] as usize]);
                out[6..8].copy_from_slice(&u16::MAX.to_le_bytes());
            });
        }
        let (stored, cs) = (self.stored, self.color_space);
        with_codec!(format, C => self.fill_level(width, height, |x, y, out| {
            let c = C::decode_premultiplied(&texels[at(x, y)..at(x, y) + bpp], lut);
            stored.encode(mip::unpremultiply(c), cs, out);
        }))
    }

    /// Every level below level 0 (given as row-major texels of `format`, decoded with `lut`),
    /// built in linear light and stored as each is made.
    pub(super) fn chain_from_given(
        &self,
        width: u32,
        height: u32,
        format: Format,
        lut: &[f32],
        texels: &[u8],
    ) -> Vec<Level> {
        let bpp = format.bytes_per_texel();
        let mut levels = Vec::new();
        with_codec!(format, C => mip::for_each_level(
            width,
            height,
            |x, y| {
                let i = (y * width + x) as usize * bpp;
                C::decode_premultiplied(&texels[i..i + bpp], lut)
            },
            |w, h, t| levels.push(self.store_linear(w, h, t)),
        ));
        levels
    }
}
