//! Filling a level in place: each row made in a scratch row and put into the level's layout
//! (tiled or row-major), bands of four rows in parallel (rayon), with no row-major copy of the
//! level in between.
//! Every texel is a function of its position alone, so the bytes are the same whatever the
//! thread count.

use glam::Vec4;
use rayon::prelude::*;

use super::linear16::premultiplied16_row;
use super::{mip, texel_index, Bands, Layout, Level, Texture2D};
use crate::texture::format::{with_codec, Codec, CodecRgba8, ColorSpace, Format};

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
        self.fill_rows(width, height, |y, row| {
            for (x, texel) in (0..).zip(row.chunks_exact_mut(bpp)) {
                f(x, y, texel);
            }
        })
    }

    /// A `width`×`height` level of the stored format whose row `y` is made by `row(y,
    /// bytes)` (the row's texels in order) and then put in its layout ([`place_row`]): bands
    /// of four rows in parallel, each band's rows made in one scratch row.
    pub(super) fn fill_rows(
        &self,
        width: u32,
        height: u32,
        row: impl Fn(u32, &mut [u8]) + Sync,
    ) -> Level {
        let bpp = self.stored.bytes_per_texel();
        let Bands { tiles_x, band, len } = Bands::of(self.layout, width, height);
        let mut data = vec![0u8; len * bpp];
        let layout = self.layout;
        data.par_chunks_mut(band * bpp)
            .enumerate()
            .for_each(|(b, chunk)| {
                let mut bytes = vec![0u8; width as usize * bpp];
                for r in 0..4 {
                    let y = (4 * b + r) as u32;
                    if y >= height {
                        break;
                    }
                    row(y, &mut bytes);
                    place_row(layout, chunk, r, bpp, &bytes);
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
            return self.fill_rows(width, height, |y, out| {
                let w = width as usize;
                premultiplied16_row(&texels[y as usize * w..(y as usize + 1) * w], out);
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
            // channel is the code's linear value rounded to 16 bits: a table of them, shifted
            // to each channel's place in the little-endian texel.
            let q16 = |v: f32| u64::from((v.clamp(0.0, 1.0) * 65535.0 + 0.5) as u16);
            let q: [u64; 256] = std::array::from_fn(|c| q16(lut[c]));
            let opaque = u64::from(u16::MAX) << 48;
            return self.fill_rows(width, height, |y, out| {
                let row = &texels[at(0, y)..at(0, y + 1)];
                for (o, t) in out.chunks_exact_mut(8).zip(row.chunks_exact(3)) {
                    let c = q[usize::from(t[0])]
                        | q[usize::from(t[1])] << 16
                        | q[usize::from(t[2])] << 32;
                    o.copy_from_slice(&(c | opaque).to_le_bytes());
                }
            });
        }
        if format == Format::Rgb8 && self.stored == Format::Rgba8 {
            // The codes kept, alpha 255.
            if self.layout == Layout::Tiled4x4 {
                return tiled_8bit(width, height, |y, row| {
                    let src = &texels[at(0, y as u32)..at(0, y as u32 + 1)];
                    // Four texels (a tile's row) at a time, then the partial tile's.
                    let whole = src.len() / 12 * 12;
                    for (tile, t) in src[..whole].chunks_exact(12).enumerate() {
                        row.put_four(
                            tile,
                            [
                                t[0], t[1], t[2], 255, t[3], t[4], t[5], 255, t[6], t[7], t[8],
                                255, t[9], t[10], t[11], 255,
                            ],
                        );
                    }
                    for (x, t) in src[whole..].chunks_exact(3).enumerate() {
                        row.put(whole / 3 + x, [t[0], t[1], t[2], 255]);
                    }
                });
            }
            return self.fill_level(width, height, |x, y, out| {
                out[..3].copy_from_slice(&texels[at(x, y)..at(x, y) + 3]);
                out[3] = 255;
            });
        }
        let (stored, cs) = (self.stored, self.color_space);
        with_codec!(format, C => self.fill_level(width, height, |x, y, out| {
            let c = C::decode_premultiplied(&texels[at(x, y)..at(x, y) + bpp], lut);
            stored.encode(mip::unpremultiply(c), cs, out);
        }))
    }

    /// Every level below level 0 (given as row-major texels of `format`, decoded with `lut`),
    /// built in linear light and stored as each is made. The default storage of 8-bit colour
    /// with sides multiples of four makes levels 1 and 2 together in strips
    /// ([`Texture2D::first_two_levels`]); the same bytes.
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
        with_codec!(format, C => {
            let read = |x: u32, y: u32| {
                let i = (y * width + x) as usize * bpp;
                C::decode_premultiplied(&texels[i..i + bpp], lut)
            };
            let store = |w, h, t: &[Vec4]| self.store_linear(w, h, t);
            if self.stored == Format::Rgba16Premultiplied && format.is_unorm()
                && width.is_multiple_of(4) && height.is_multiple_of(4)
            {
                // Levels 1 and 2 together, level 1 never held whole in floats.
                let (level1, level2) = self.first_two_levels(width, height, read);
                let (w2, h2) = (width / 4, height / 4);
                levels.push(level1);
                levels.push(store(w2, h2, &level2));
                mip::for_each_level(
                    w2,
                    h2,
                    true,
                    |x, y| level2[(y * w2 + x) as usize],
                    |w, h, t| levels.push(store(w, h, t)),
                );
            } else {
                mip::for_each_level(width, height, format.is_unorm(), read, |w, h, t| {
                    levels.push(store(w, h, t));
                });
            }
        });
        levels
    }

    /// The chain of an 8-bit texture ([`super::Storage::Rgba8`], level 0 stored): each level
    /// from the stored one above it, its texels decoded to linear premultiplied floats,
    /// averaged over the area each new texel covers (the weights and order of
    /// `mip::for_each_level`) and encoded back to 8 bits, written straight into the new
    /// level's layout: no float copy of any level.
    pub(super) fn chain_8bit(&mut self) {
        let (stored, cs, lut, layout) = (self.stored, self.color_space, self.lut, self.layout);
        debug_assert_eq!(stored, Format::Rgba8);
        loop {
            let prev = self.levels.last().expect("level 0 is stored first");
            let (w, h) = (prev.width, prev.height);
            if w <= 1 && h <= 1 {
                return;
            }
            let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
            if let Some(level) = self.halve_opaque_8bit(prev) {
                self.levels.push(level);
                continue;
            }
            let columns: Vec<Vec<(u32, f32)>> =
                (0..nw).map(|x| mip::coverage(x, w, nw).collect()).collect();
            let rows: Vec<Vec<(u32, f32)>> =
                (0..nh).map(|y| mip::coverage(y, h, nh).collect()).collect();
            let (data, tiles_x) = (&prev.data, prev.tiles_x);
            let read = |x: u32, y: u32| {
                let i = texel_index(layout, tiles_x, w, x, y) * 4;
                CodecRgba8::decode_premultiplied(&data[i..i + 4], lut)
            };
            let level = self.fill_level(nw, nh, |x, y, out| {
                let mut c = Vec4::ZERO;
                for &(j, wy) in &rows[y as usize] {
                    let r: Vec4 = columns[x as usize]
                        .iter()
                        .map(|&(i, wx)| read(i, j) * wx)
                        .sum();
                    c += r * wy;
                }
                stored.encode(mip::unpremultiply(c), cs, out);
            });
            self.levels.push(level);
        }
    }

    /// The next level of an opaque 8-bit level with both sides even, each texel the 2×2
    /// above it in integers: the codes widened to 16-bit linear as the fixed-point reads
    /// widen them (sRGB through the 256-entry table, linear as `c · 257`), the four summed,
    /// rounded to 16 bits and encoded through a 65,536-entry table. The float path's box
    /// with its sum rounded to 16 bits first: a code can differ from it by one where the
    /// mean falls within 2⁻¹⁷ of a rounding threshold. `None` for other levels.
    fn halve_opaque_8bit(&self, prev: &Level) -> Option<Level> {
        let texels = self.rgba8.filter(|t| t.opaque)?;
        let (w, h) = (prev.width, prev.height);
        if w % 2 != 0 || h % 2 != 0 || self.layout != Layout::Tiled4x4 {
            return None;
        }
        let linear: [u16; 256];
        let widen = match texels.srgb {
            Some(table) => table,
            None => {
                linear = std::array::from_fn(|c| c as u16 * 257);
                &linear
            }
        };
        let encode = encode16(self.color_space);
        let (data, row) = (&prev.data, prev.tiles_x as usize * 16);
        // Two texels side by side from an even column: the next in memory (same tile row).
        let pair = |i: usize| {
            let b: [u8; 8] = data[4 * i..4 * i + 8].try_into().expect("8 bytes");
            u64::from_le_bytes(b)
        };
        Some(tiled_8bit(w / 2, h / 2, |y, out| {
            let start = |y: usize| (y >> 2) * row + ((y & 3) << 2);
            let (r0, r1) = (start(2 * y), start(2 * y + 1));
            for x in 0..(w / 2) as usize {
                // Column 2x of the level above: tile x / 2, place 2·(x mod 2) in it.
                let c = ((x >> 1) << 4) + ((x & 1) << 1);
                let (top, bottom) = (pair(r0 + c), pair(r1 + c));
                let channel = |shift: u32| {
                    let code = |v: u64, s: u32| u32::from(widen[usize::from((v >> s) as u8)]);
                    let sum = code(top, shift)
                        + code(top, shift + 32)
                        + code(bottom, shift)
                        + code(bottom, shift + 32);
                    encode[usize::from(((sum + 2) >> 2) as u16)]
                };
                out.put(x, [channel(0), channel(8), channel(16), 255]);
            }
        }))
    }
}

/// Puts row `r` of a band of four rows (`chunk`, in `layout`) in place from its texels' bytes
/// in order, `bpp` bytes a texel.
#[inline]
pub(super) fn place_row(layout: Layout, chunk: &mut [u8], r: usize, bpp: usize, texels: &[u8]) {
    match layout {
        Layout::RowMajor => {
            let n = texels.len();
            chunk[r * n..(r + 1) * n].copy_from_slice(texels);
        }
        // Each tile's row of four texels to its place in the tile: a band holds its tiles one
        // after another, 16 texels each, row `r` of a tile at texel `4r` in it.
        Layout::Tiled4x4 => {
            for (t, four) in texels.chunks(4 * bpp).enumerate() {
                let o = (16 * t + 4 * r) * bpp;
                chunk[o..o + four.len()].copy_from_slice(four);
            }
        }
    }
}

/// A tiled `width`×`height` level of 4-byte texels whose row `y` is written by `f(y, put)`,
/// `put(x, texel)` storing texel `(x, y)`; bands of four rows in parallel, as
/// [`Texture2D::fill_level`] makes them, without its call and index arithmetic per texel.
fn tiled_8bit(width: u32, height: u32, f: impl Fn(usize, &mut RowOut) + Sync) -> Level {
    let tiles_x = width.div_ceil(4);
    let band = tiles_x as usize * 16 * 4;
    let mut data = vec![0u8; band * height.div_ceil(4) as usize];
    data.par_chunks_mut(band)
        .enumerate()
        .for_each(|(b, chunk)| {
            for r in 0..4 {
                let y = b * 4 + r;
                if y >= height as usize {
                    break;
                }
                f(y, &mut RowOut { chunk, r });
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

/// One row of a band of 4×4 tiles of 4-byte texels, as [`tiled_8bit`] hands it out.
struct RowOut<'a> {
    chunk: &'a mut [u8],
    /// The row's place in its band.
    r: usize,
}

impl RowOut<'_> {
    /// Stores texel `x` of the row.
    #[inline(always)]
    fn put(&mut self, x: usize, texel: [u8; 4]) {
        let o = (((x >> 2) << 4) + (self.r << 2) + (x & 3)) * 4;
        self.chunk[o..o + 4].copy_from_slice(&texel);
    }

    /// Stores texels `4·tile` to `4·tile + 3` of the row (one tile's row).
    #[inline(always)]
    fn put_four(&mut self, tile: usize, texels: [u8; 16]) {
        let o = ((tile << 4) + (self.r << 2)) * 4;
        self.chunk[o..o + 16].copy_from_slice(&texels);
    }
}

/// The 8-bit code of each 16-bit linear value `v` in `color_space` (`Format::encode` of
/// `v / 65535`).
fn encode16(color_space: ColorSpace) -> &'static [u8; 65536] {
    use std::sync::OnceLock;
    static SRGB: OnceLock<Box<[u8; 65536]>> = OnceLock::new();
    static LINEAR: OnceLock<Box<[u8; 65536]>> = OnceLock::new();
    let (cell, srgb) = match color_space {
        ColorSpace::Srgb => (&SRGB, true),
        ColorSpace::Linear => (&LINEAR, false),
    };
    cell.get_or_init(|| {
        let encoder = crate::color::Srgb8Encoder::new();
        (0..=u16::MAX)
            .map(|v| {
                let v = f32::from(v) / 65535.0;
                if srgb {
                    encoder.encode(v)
                } else {
                    crate::color::linear_to_unorm8(v)
                }
            })
            .collect::<Box<[u8]>>()
            .try_into()
            .expect("65,536 codes")
    })
}
