//! Block-compressed storage ([`Storage::Compressed`]): a texture's levels kept as the BC
//! blocks of its file, each block decoded when a read first touches it.
//!
//! Decoded blocks live in a small cache per thread (rayon's workers each have their own, so
//! no read waits on another): 512 slots of 16 linear, premultiplied texels (256 bytes each,
//! 128 KiB a thread), direct-mapped by the block's position — 32 × 16 neighbouring blocks
//! (128 × 64 texels) of one level never evict each other — and tagged with the level's
//! process-unique id and the block's index, so a slot is never read for another texture,
//! even one allocated where a dropped one was. A block decodes to the same values the
//! decoded storages hold (the same decoder and colour-space tables), so the storage changes
//! memory and speed, not the image; the cache only changes when a block is decoded, so the
//! image is the same whatever the thread count.

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, Ordering};

use glam::Vec4;

use super::{check_chain, mip, BlockStore, Level, Storage, Texture2D, TextureOptions};
use crate::texture::compressed::{decode_block_f32, decode_block_rgba8, BlockFormat};
use crate::texture::format::{decode_table, ColorSpace, Format};
use crate::Result;

/// Slots in a thread's cache (a power of two: 32 × 16 blocks).
const SLOTS: usize = 512;

/// The next level id (0 marks an empty slot, so ids start at 1).
static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// The format a block format's texels decode to, which its levels without blocks are held in.
fn texel_format(format: BlockFormat) -> Format {
    match format {
        BlockFormat::Bc6hUnsigned | BlockFormat::Bc6hSigned => Format::Rgba16F,
        BlockFormat::Bc4Signed | BlockFormat::Bc5Signed => Format::Rgba32F,
        _ => Format::Rgba8,
    }
}

impl Texture2D {
    /// Builds a texture held as BC blocks ([`Storage::Compressed`]): `levels[i]` holds level
    /// `i`'s blocks, row-major (whole blocks at the edges). One level is level 0 alone, from
    /// which the options' chain is built and held as texels of [`Self::storage_format`]; more
    /// must be the full chain down to 1×1, all kept as blocks. `color_space` is that of the
    /// 8-bit formats' colour channels (BC6H and the signed formats are linear); with `opaque`
    /// every texel's alpha reads 1.
    ///
    /// # Errors
    /// [`crate::Error::Parameter`] for a zero side, a level of the wrong byte count, or a chain
    /// neither one level nor complete.
    pub fn from_blocks(
        width: u32,
        height: u32,
        format: BlockFormat,
        color_space: ColorSpace,
        levels: &[&[u8]],
        options: TextureOptions,
        opaque: bool,
    ) -> Result<Self> {
        let given = check_chain(width, height, levels, options, |w, h| {
            let bytes = usize::try_from(format.level_bytes(w, h)).unwrap_or(usize::MAX);
            (bytes, format.name().to_string())
        })?;
        let full = mip::level_count(width, height);
        let stored = texel_format(format);
        let color_space = if stored == Format::Rgba8 {
            color_space
        } else {
            ColorSpace::Linear
        };
        let mut tex = Texture2D {
            format: stored,
            stored,
            color_space,
            layout: options.layout,
            levels: Vec::with_capacity(full),
            lut: decode_table(stored, color_space),
            sat: std::sync::OnceLock::new(),
            blocks: Some(BlockStore { format, opaque }),
            rgba8: None,
        };
        for (i, bytes) in levels.iter().enumerate().take(given) {
            let (w, h) = ((width >> i).max(1), (height >> i).max(1));
            tex.levels.push(Level {
                width: w,
                height: h,
                tiles_x: w.div_ceil(4),
                data: bytes.to_vec(),
                block_id: Some(NEXT_ID.fetch_add(1, Ordering::Relaxed)),
            });
        }
        if options.mipmaps && given == 1 && full > 1 {
            let base = tex.decode_level(0);
            let mut chain = Vec::with_capacity(full - 1);
            mip::for_each_level(
                width,
                height,
                false,
                |x, y| base[(y * width + x) as usize],
                |w, h, t| chain.push(tex.store_linear(w, h, t)),
            );
            tex.levels.extend(chain);
        }
        Ok(tex)
    }

    /// The storage the texture is held in.
    #[must_use]
    pub fn storage(&self) -> Storage {
        if self.blocks.is_some() {
            Storage::Compressed
        } else if self.rgba8.is_some() {
            Storage::Rgba8
        } else if self.stored == Format::Rgba16Premultiplied && self.format != self.stored {
            Storage::Linear16
        } else {
            Storage::Native
        }
    }
}

/// One level held as blocks, as a read sees it.
#[derive(Clone, Copy)]
pub(crate) struct BlockRef {
    format: BlockFormat,
    id: u64,
    blocks_x: u32,
    opaque: bool,
}

impl BlockRef {
    pub(super) fn new(format: BlockFormat, id: u64, width: u32, opaque: bool) -> Self {
        BlockRef {
            format,
            id,
            blocks_x: width.div_ceil(4),
            opaque,
        }
    }

    /// Linear, premultiplied texel `(x, y)` (in range) of the level whose blocks are `data`.
    #[inline]
    pub fn texel(&self, data: &[u8], lut: &[f32], x: u32, y: u32) -> Vec4 {
        CACHE.with(|c| {
            let mut cache = c.borrow_mut();
            let slot = cache.fetch(self, data, lut, x >> 2, y >> 2);
            cache.texels[slot][((y & 3) * 4 + (x & 3)) as usize]
        })
    }

    /// The 2×2 texels with top-left `(x, y)` (all in range), as [`super::LevelRef::quad`]
    /// orders them.
    #[inline]
    pub fn quad(&self, data: &[u8], lut: &[f32], x: u32, y: u32) -> ((Vec4, Vec4), (Vec4, Vec4)) {
        CACHE.with(|c| {
            let mut cache = c.borrow_mut();
            if x & 3 != 3 && y & 3 != 3 {
                // The four texels share a block: one lookup.
                let slot = cache.fetch(self, data, lut, x >> 2, y >> 2);
                let t = &cache.texels[slot];
                let i = ((y & 3) * 4 + (x & 3)) as usize;
                return ((t[i], t[i + 1]), (t[i + 4], t[i + 5]));
            }
            let mut read = |x: u32, y: u32| {
                let slot = cache.fetch(self, data, lut, x >> 2, y >> 2);
                cache.texels[slot][((y & 3) * 4 + (x & 3)) as usize]
            };
            (
                (read(x, y), read(x + 1, y)),
                (read(x, y + 1), read(x + 1, y + 1)),
            )
        })
    }

    /// Block `(bx, by)` decoded to linear, premultiplied texels, row-major.
    fn decode(&self, data: &[u8], lut: &[f32], bx: u32, by: u32) -> [Vec4; 16] {
        let size = self.format.block_bytes();
        let start = (by as usize * self.blocks_x as usize + bx as usize) * size;
        let block = &data[start..start + size];
        let mut out = [Vec4::ZERO; 16];
        if texel_format(self.format) == Format::Rgba8 {
            let mut texels = [[0u8; 4]; 16];
            decode_block_rgba8(self.format, block, &mut texels);
            for (o, t) in out.iter_mut().zip(texels) {
                let a = if self.opaque {
                    1.0
                } else {
                    f32::from(t[3]) * (1.0 / 255.0)
                };
                let rgb =
                    glam::Vec3::new(lut[t[0] as usize], lut[t[1] as usize], lut[t[2] as usize]);
                *o = (rgb * a).extend(a);
            }
        } else {
            let mut texels = [[0f32; 4]; 16];
            decode_block_f32(self.format, block, &mut texels);
            for (o, t) in out.iter_mut().zip(texels) {
                let a = if self.opaque { 1.0 } else { t[3] };
                *o = (glam::Vec3::new(t[0], t[1], t[2]) * a).extend(a);
            }
        }
        out
    }
}

/// A thread's decoded blocks: fixed arrays, so the thread-local needs no lazy set-up and no
/// destructor (a read is a TLS offset, no heap pointer to follow).
struct Cache {
    /// Each slot's (level id, block index); id 0 is empty.
    tags: [(u64, u64); SLOTS],
    texels: [[Vec4; 16]; SLOTS],
}

impl Cache {
    const EMPTY: Cache = Cache {
        tags: [(0, 0); SLOTS],
        texels: [[Vec4::ZERO; 16]; SLOTS],
    };

    /// The slot holding block `(bx, by)` of `level`, decoding it there first if needed.
    #[inline]
    fn fetch(&mut self, level: &BlockRef, data: &[u8], lut: &[f32], bx: u32, by: u32) -> usize {
        let mix = (level.id.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 55) as usize;
        let slot = (((bx & 31) | ((by & 15) << 5)) as usize ^ mix) & (SLOTS - 1);
        let tag = (
            level.id,
            u64::from(by) * u64::from(level.blocks_x) + u64::from(bx),
        );
        if self.tags[slot] != tag {
            self.texels[slot] = level.decode(data, lut, bx, by);
            self.tags[slot] = tag;
        }
        slot
    }
}

thread_local! {
    static CACHE: RefCell<Cache> = const { RefCell::new(Cache::EMPTY) };
}

#[cfg(test)]
mod tests;
