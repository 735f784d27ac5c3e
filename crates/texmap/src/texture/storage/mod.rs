//! Texture storage: 2D textures with their mip chains, in a cache-friendly tiled layout.
//!
//! By default 8-bit sRGB colour (RGB8, RGBA8) is stored decoded, as 16-bit linear
//! premultiplied RGBA ([`Storage::Linear16`], 8 bytes a texel): a read is one 8-byte load
//! and a conversion, where the native format costs a table lookup per channel and a multiply
//! by alpha. 16 bits in linear light hold every 8-bit sRGB value to within 8·10⁻⁶, and the mip
//! levels keep that precision instead of being rounded back to 8-bit sRGB. 8-bit linear data
//! keeps its own 8 bits (4 bytes a texel, as [`Storage::Rgba8`]): its codes widen exactly to
//! the 16-bit values, so 16 bits would only add precision to its mip levels (which GL holds
//! in 8 bits too) at twice the memory.
//! [`Storage::Native`] keeps the texels in their own [`Format`] (half the memory) and decodes
//! them when read.
//!
//! [`Storage::Compressed`] keeps a block-compressed file's levels as its BC blocks (BC1: half
//! a byte a texel) and decodes a block when a read first touches it, through a small cache
//! per thread (`blocks.rs`).
//!
//! Each level is stored in 4×4 tiles by default: one tile of RGBA8 is 64 bytes, one cache
//! line, so the 2×2 neighbourhood a bilinear tap reads usually sits in one line whatever the
//! direction the footprint walks. [`Layout::RowMajor`] is kept so the gain can be measured
//! (`cargo bench --bench sampling -- layout`).

use glam::Vec4;

use super::compressed::BlockFormat;
use super::format::{decode_table, with_codec, with_texture_codec, Codec, ColorSpace, Format};
use super::mip;
use crate::{Error, Result};

mod blocks;
mod fill;
mod linear16;

use blocks::BlockRef;

/// How the texels of a level are ordered in memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Layout {
    /// Rows one after another.
    RowMajor,
    /// 4×4 tiles, row-major inside a tile and tiles row-major in the level.
    #[default]
    Tiled4x4,
}

/// One level of a mip chain.
#[derive(Clone, Debug)]
pub struct Level {
    width: u32,
    height: u32,
    tiles_x: u32,
    data: Vec<u8>,
    /// For a level held as BC blocks (row-major blocks in `data`): its key in the block
    /// caches, unique in the process.
    block_id: Option<u64>,
}

impl Level {
    /// Width in texels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Height in texels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }
}

/// How texels are held in memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Storage {
    /// sRGB RGB8 and RGBA8 stored as [`Format::Rgba16Premultiplied`] (8 bytes a texel),
    /// decoded once at load; linear RGB8 and RGBA8 (data: normals, metallic-roughness,
    /// occlusion) as [`Storage::Rgba8`] holds them, since their codes widen exactly to the
    /// 16-bit values (`c · 257`) and only their mip levels would keep more bits; other
    /// formats as given.
    #[default]
    Linear16,
    /// Every format as given (an sRGB RGBA8 texel costs 4 bytes), decoded at each read; a
    /// block-compressed file's texels as 8-bit RGBA (or float for BC6H and the signed
    /// formats).
    Native,
    /// A block-compressed file's levels kept as its blocks, each decoded when a read first
    /// touches it through a small cache per thread; levels built from them, and images that
    /// are not block-compressed, as [`Storage::Native`].
    Compressed,
    /// RGB8 and RGBA8 stored as [`Format::Rgba8`] (4 bytes a texel, straight alpha) in their
    /// colour space (sRGB colour, linear data), the mip chain built in 8 bits (each level
    /// averaged in linear light from the one above, as `glGenerateMipmap` does on an sRGB8
    /// texture), and read through the same fixed-point quad path as [`Storage::Linear16`]
    /// (each texel widened to 16-bit linear, sRGB codes through a 256-entry table); other
    /// formats as given.
    Rgba8,
}

impl Storage {
    /// The names the CLI and TOML take, each with its storage.
    pub const NAMES: [(&'static str, Storage); 4] = [
        ("decoded", Storage::Linear16),
        ("native", Storage::Native),
        ("compressed", Storage::Compressed),
        ("rgba8", Storage::Rgba8),
    ];

    /// The storage called `name` (see [`Storage::NAMES`]).
    #[must_use]
    pub fn from_name(name: &str) -> Option<Storage> {
        Self::NAMES
            .iter()
            .find(|(n, _)| *n == name)
            .map(|&(_, s)| s)
    }

    /// The name of this storage (see [`Storage::NAMES`]).
    #[must_use]
    pub fn name(self) -> &'static str {
        Self::NAMES
            .iter()
            .find(|(_, s)| *s == self)
            .map_or("decoded", |&(n, _)| n)
    }
}

/// Options for building a texture from texels.
///
/// Built from [`TextureOptions::default`] and the `with_*` methods, so an option added later
/// breaks no caller (the type is `#[non_exhaustive]`); the fields stay public.
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
pub struct TextureOptions {
    /// Build the full mip chain down to 1×1 (default true).
    pub mipmaps: bool,
    /// Memory order of the texels (default tiled).
    pub layout: Layout,
    /// Memory format of the texels (default [`Storage::Linear16`]).
    pub storage: Storage,
}

impl Default for TextureOptions {
    fn default() -> Self {
        TextureOptions {
            mipmaps: true,
            layout: Layout::Tiled4x4,
            storage: Storage::Linear16,
        }
    }
}

impl TextureOptions {
    /// These options with (`true`) or without the mip chain.
    #[must_use]
    pub fn with_mipmaps(mut self, mipmaps: bool) -> Self {
        self.mipmaps = mipmaps;
        self
    }

    /// These options with the texels in `layout`.
    #[must_use]
    pub fn with_layout(mut self, layout: Layout) -> Self {
        self.layout = layout;
        self
    }

    /// These options with the texels held as `storage` says.
    #[must_use]
    pub fn with_storage(mut self, storage: Storage) -> Self {
        self.storage = storage;
        self
    }
}

/// A 2D texture: a format, a colour space and a mip chain (level 0 is the full image).
#[derive(Clone, Debug)]
pub struct Texture2D {
    /// The format the texels were given in.
    format: Format,
    /// The format they are held in (see [`Storage`]).
    stored: Format,
    color_space: ColorSpace,
    layout: Layout,
    levels: Vec<Level>,
    lut: &'static [f32],
    sat: std::sync::OnceLock<super::filter::summed_area::SummedAreaTables>,
    /// Set when the texture is held block-compressed ([`Storage::Compressed`]).
    blocks: Option<BlockStore>,
    /// Set when 8-bit colour is held as [`Storage::Rgba8`]: what the fixed-point reads need.
    rgba8: Option<Rgba8Texels>,
}

/// How the fixed-point reads widen a [`Storage::Rgba8`] texture's texels to 16-bit linear.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Rgba8Texels {
    /// The 16-bit linear value of each 8-bit sRGB code (the value [`Storage::Linear16`]
    /// stores for it); `None` for linear codes, which widen as `c · 257`.
    pub srgb: Option<&'static [u16; 256]>,
    /// The same values shifted right once (the 15 bits the fixed-point sums take).
    pub srgb15: Option<&'static [u16; 256]>,
    /// Every texel's alpha is 255 (an RGB8 source, or RGBA8 with no translucent texel):
    /// no premultiplication.
    pub opaque: bool,
}

impl Rgba8Texels {
    /// Opaque texels with linear codes (data maps: normals, metallic-roughness,
    /// occlusion): each channel widens as `c · 257`, nothing to look up or premultiply
    /// (the kind the AVX2 gathers read in lanes).
    #[inline(always)]
    pub fn opaque_linear(&self) -> bool {
        self.srgb15.is_none() && self.opaque
    }
}

/// The 16-bit linear value of each 8-bit sRGB code, rounded as [`Storage::Linear16`] stores it.
fn srgb_to_linear16() -> &'static [u16; 256] {
    static TABLE: std::sync::OnceLock<[u16; 256]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let lut = crate::color::lut8(ColorSpace::Srgb);
        std::array::from_fn(|c| (lut[c].clamp(0.0, 1.0) * 65535.0 + 0.5) as u16)
    })
}

/// [`srgb_to_linear16`] shifted right once.
fn srgb_to_linear15() -> &'static [u16; 256] {
    static TABLE: std::sync::OnceLock<[u16; 256]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| srgb_to_linear16().map(|v| v >> 1))
}

/// What a block-compressed texture's blocks are.
#[derive(Clone, Copy, Debug)]
struct BlockStore {
    format: BlockFormat,
    /// Alpha read as 1 (glTF's OPAQUE base colour).
    opaque: bool,
}

/// Checks a chain given level by level (`levels[i]` the bytes of level `i`): sides not zero,
/// one level or the full chain, each level `size(w, h).0` bytes (`.1` names the format in
/// messages). Returns how many levels are used (one without mipmaps).
fn check_chain(
    width: u32,
    height: u32,
    levels: &[&[u8]],
    options: TextureOptions,
    size: impl Fn(u32, u32) -> (usize, String),
) -> Result<usize> {
    if width == 0 || height == 0 {
        return Err(Error::parameter(format!(
            "texture size {width}x{height} has a zero side"
        )));
    }
    let full = mip::level_count(width, height);
    if levels.is_empty() || (levels.len() > 1 && levels.len() != full) {
        return Err(Error::parameter(format!(
            "texture {width}x{height} given {} levels; give 1 or the full chain of {full}",
            levels.len()
        )));
    }
    let given = if options.mipmaps { levels.len() } else { 1 };
    for (i, bytes) in levels.iter().enumerate().take(given) {
        let (w, h) = ((width >> i).max(1), (height >> i).max(1));
        let (expected, name) = size(w, h);
        if bytes.len() != expected {
            return Err(Error::parameter(format!(
                "texture level {i} of {w}x{h} {name} needs {expected} bytes, got {}",
                bytes.len()
            )));
        }
    }
    Ok(given)
}

/// A `width`×`height` level's bands of four rows in `layout`, as the parallel writers cut it:
/// tiles per row, texels a band holds (a row of tiles, padding included) and the level's
/// texel count (a row-major level's last band may be short).
#[derive(Clone, Copy)]
struct Bands {
    tiles_x: u32,
    band: usize,
    len: usize,
}

impl Bands {
    fn of(layout: Layout, width: u32, height: u32) -> Self {
        let tiles_x = width.div_ceil(4);
        let (band, len) = match layout {
            Layout::RowMajor => (width as usize * 4, (width * height) as usize),
            Layout::Tiled4x4 => {
                let band = tiles_x as usize * 16;
                (band, band * height.div_ceil(4) as usize)
            }
        };
        Bands { tiles_x, band, len }
    }
}

/// Size of a texel index within a level, and its memory offset.
#[inline(always)]
fn texel_index(layout: Layout, tiles_x: u32, width: u32, x: u32, y: u32) -> usize {
    match layout {
        Layout::RowMajor => (y * width + x) as usize,
        Layout::Tiled4x4 => {
            (((y >> 2) * tiles_x + (x >> 2)) * 16 + ((y & 3) << 2) + (x & 3)) as usize
        }
    }
}

impl Texture2D {
    /// Builds a texture from row-major texels of `format` (`width·height·bytes_per_texel`
    /// bytes), with the options' mip chain and layout.
    ///
    /// `color_space` is ignored for float formats, which are always linear.
    pub fn from_texels(
        width: u32,
        height: u32,
        format: Format,
        color_space: ColorSpace,
        texels: &[u8],
        options: TextureOptions,
    ) -> Result<Self> {
        Self::from_texel_levels(width, height, format, color_space, &[texels], options)
    }

    /// Builds a texture from its mip chain given level by level: `levels[i]` holds the
    /// row-major texels of level `i` (`max(1, ⌊width/2ⁱ⌋)` × `max(1, ⌊height/2ⁱ⌋)`). One
    /// level is level 0 alone, from which the options' chain is built; more must be the full
    /// chain down to 1×1, which is kept as given (with `options.mipmaps` off, only level 0).
    ///
    /// # Errors
    /// [`Error::Parameter`] for a zero side, a level of the wrong size, or a chain neither
    /// one level nor complete.
    pub fn from_texel_levels(
        width: u32,
        height: u32,
        format: Format,
        color_space: ColorSpace,
        levels: &[&[u8]],
        options: TextureOptions,
    ) -> Result<Self> {
        let given = check_chain(width, height, levels, options, |w, h| {
            (
                w as usize * h as usize * format.bytes_per_texel(),
                format!("{format:?}"),
            )
        })?;
        let color_space = if format.is_unorm() {
            color_space
        } else {
            ColorSpace::Linear
        };
        let lut_of = |f: Format| decode_table(f, color_space);
        let eight_bit = matches!(format, Format::Rgb8 | Format::Rgba8);
        let opaque = eight_bit
            && (format == Format::Rgb8
                || levels
                    .iter()
                    .take(given)
                    .all(|l| l.chunks_exact(4).all(|t| t[3] == 255)));
        // Linear 8-bit data widens exactly to the values 16 bits would hold (`c · 257`, read
        // by the same fixed-point path): the default storage keeps it in its own 8 bits.
        let as_rgba8 = eight_bit
            && match options.storage {
                Storage::Rgba8 => true,
                Storage::Linear16 => color_space == ColorSpace::Linear,
                Storage::Native | Storage::Compressed => false,
            };
        let stored = match (options.storage, format) {
            _ if as_rgba8 => Format::Rgba8,
            (Storage::Linear16, Format::Rgb8 | Format::Rgba8) => Format::Rgba16Premultiplied,
            _ => format,
        };
        let rgba8 = as_rgba8.then(|| Rgba8Texels {
            srgb: (color_space == ColorSpace::Srgb).then(srgb_to_linear16),
            srgb15: (color_space == ColorSpace::Srgb).then(srgb_to_linear15),
            opaque,
        });
        let mut tex = Texture2D {
            format,
            stored,
            color_space,
            layout: options.layout,
            levels: Vec::new(),
            lut: lut_of(stored),
            sat: std::sync::OnceLock::new(),
            blocks: None,
            rgba8,
        };
        // Each level written straight into its layout, converted texel by texel; the chain
        // is built from the given level 0 (never copied to floats) and each level stored as
        // it is made.
        let lut = lut_of(format);
        for (i, texels) in levels.iter().enumerate().take(given) {
            let (w, h) = ((width >> i).max(1), (height >> i).max(1));
            let level = tex.store_given(w, h, format, lut, texels);
            tex.levels.push(level);
        }
        if options.mipmaps && given == 1 {
            if tex.rgba8.is_some() {
                tex.chain_8bit();
            } else {
                let chain = tex.chain_from_given(width, height, format, lut, levels[0]);
                tex.levels.extend(chain);
            }
        }
        Ok(tex)
    }

    /// Overwrites every level's texels with `f(level, x, y)` (linear, premultiplied), in the
    /// stored format: for tests that need levels unlike a box-filtered chain.
    #[cfg(test)]
    pub(crate) fn replace_levels(&mut self, f: impl Fn(usize, u32, u32) -> Vec4) {
        for i in 0..self.levels.len() {
            let (w, h) = (self.levels[i].width, self.levels[i].height);
            let texels: Vec<Vec4> = (0..w * h).map(|k| f(i, k % w, k / w)).collect();
            self.levels[i] = self.store_linear(w, h, &texels);
        }
    }

    /// Builds an RGBA8 texture (full mip chain, tiled) from row-major RGBA bytes.
    pub fn from_rgba8(
        width: u32,
        height: u32,
        color_space: ColorSpace,
        rgba: &[u8],
    ) -> Result<Self> {
        Self::from_texels(
            width,
            height,
            Format::Rgba8,
            color_space,
            rgba,
            TextureOptions::default(),
        )
    }

    /// Builds a linear RGBA32F texture by evaluating `f` at every texel (tests and procedurals).
    pub fn from_fn(
        width: u32,
        height: u32,
        options: TextureOptions,
        f: impl Fn(u32, u32) -> Vec4,
    ) -> Result<Self> {
        let mut bytes = Vec::with_capacity(width as usize * height as usize * 16);
        for y in 0..height {
            for x in 0..width {
                for v in f(x, y).to_array() {
                    bytes.extend_from_slice(&v.to_le_bytes());
                }
            }
        }
        Self::from_texels(
            width,
            height,
            Format::Rgba32F,
            ColorSpace::Linear,
            &bytes,
            options,
        )
    }

    /// Level `i`'s texels, linear and premultiplied, row-major.
    #[must_use]
    pub fn decode_level(&self, i: usize) -> Vec<Vec4> {
        let view = self.level(i);
        with_texture_codec!(self, C => {
            let mut out = Vec::with_capacity((view.w * view.h) as usize);
            for y in 0..view.h {
                for x in 0..view.w {
                    out.push(view.texel::<C>(x, y));
                }
            }
            out
        })
    }

    /// The format the texels were given in.
    #[must_use]
    pub fn format(&self) -> Format {
        self.format
    }
    /// The format the texels are held in: [`Format::Rgba16Premultiplied`] for 8-bit sRGB
    /// colour with [`Storage::Linear16`], [`Format::Rgba8`] for 8-bit colour with
    /// [`Storage::Rgba8`] and 8-bit linear data with either, else [`Self::format`]. For a texture held
    /// block-compressed, the format its blocks decode to (and its levels without blocks are
    /// held in): see [`Self::block_format`].
    #[must_use]
    pub fn storage_format(&self) -> Format {
        self.stored
    }

    /// The block format the texture is held in, for [`Storage::Compressed`] textures made
    /// from block-compressed files (`None` otherwise).
    #[must_use]
    pub fn block_format(&self) -> Option<BlockFormat> {
        self.blocks.map(|b| b.format)
    }

    /// For a texture held as [`Storage::Rgba8`], how its texels widen to 16-bit linear.
    #[inline]
    pub(crate) fn rgba8_texels(&self) -> Option<&Rgba8Texels> {
        self.rgba8.as_ref()
    }
    /// The colour space the stored values are in.
    #[must_use]
    pub fn color_space(&self) -> ColorSpace {
        self.color_space
    }
    /// The memory layout of every level.
    #[must_use]
    pub fn layout(&self) -> Layout {
        self.layout
    }
    /// Width of level 0.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.levels[0].width
    }
    /// Height of level 0.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.levels[0].height
    }
    /// The mip chain, level 0 first.
    #[must_use]
    pub fn levels(&self) -> &[Level] {
        &self.levels
    }
    /// Bytes held by texels of every level (tile padding included).
    #[must_use]
    pub fn texel_bytes(&self) -> usize {
        self.levels.iter().map(|l| l.data.len()).sum()
    }

    /// A read view of level `i` (clamped to the last level).
    #[inline]
    pub(crate) fn level(&self, i: usize) -> LevelRef<'_> {
        let l = &self.levels[i.min(self.levels.len() - 1)];
        LevelRef {
            data: &l.data,
            w: l.width as i32,
            h: l.height as i32,
            tiles_x: l.tiles_x,
            layout: self.layout,
            lut: self.lut,
            blocks: match (self.blocks, l.block_id) {
                (Some(b), Some(id)) => Some(BlockRef::new(b.format, id, l.width, b.opaque)),
                _ => None,
            },
        }
    }

    /// Linear, premultiplied texel `(x, y)` of level `level` (no wrapping: in range or panics).
    #[must_use]
    pub fn texel(&self, level: usize, x: u32, y: u32) -> Vec4 {
        let view = self.level(level);
        with_texture_codec!(self, C => view.texel::<C>(x as i32, y as i32))
    }

    pub(crate) fn summed_area_tables(&self) -> &super::filter::summed_area::SummedAreaTables {
        self.sat
            .get_or_init(|| super::filter::summed_area::SummedAreaTables::build(self))
    }
}

/// A borrowed view of one level, what the filters read.
#[derive(Clone, Copy)]
pub(crate) struct LevelRef<'a> {
    data: &'a [u8],
    pub w: i32,
    pub h: i32,
    tiles_x: u32,
    layout: Layout,
    lut: &'a [f32],
    /// Set for a level held as blocks: read through the block cache when the codec is
    /// [`super::format::Blocks`].
    blocks: Option<BlockRef>,
}

impl<'a> LevelRef<'a> {
    /// The table its 8- and 16-bit codes decode through (the codecs' `lut`).
    #[inline(always)]
    pub(crate) fn lut(&self) -> &'a [f32] {
        self.lut
    }

    /// The 2×2 texels with top-left `(x, y)` (all in range): ((x,y), (x+1,y)), ((x,y+1), (x+1,y+1)).
    #[inline(always)]
    pub fn quad<C: Codec>(&self, x: i32, y: i32) -> ((Vec4, Vec4), (Vec4, Vec4)) {
        if C::BLOCKS {
            if let Some(b) = self.blocks {
                return b.quad(self.data, self.lut, x as u32, y as u32);
            }
        }
        let (i00, i10, i01, i11) = match self.layout {
            Layout::RowMajor => {
                let i = (y * self.w + x) as usize;
                let w = self.w as usize;
                (i, i + 1, i + w, i + w + 1)
            }
            Layout::Tiled4x4 => {
                let (x, y) = (x as u32, y as u32);
                let idx = |x: u32, y: u32| {
                    (((y >> 2) * self.tiles_x + (x >> 2)) * 16 + ((y & 3) << 2) + (x & 3)) as usize
                };
                let i00 = idx(x, y);
                // Inside one tile the neighbours are +1 and +4; across a tile edge, recompute.
                let i10 = if x & 3 != 3 { i00 + 1 } else { idx(x + 1, y) };
                let (i01, i11) = if y & 3 != 3 {
                    (i00 + 4, i10 + 4)
                } else {
                    (idx(x, y + 1), idx(x + 1, y + 1))
                };
                (i00, i10, i01, i11)
            }
        };
        // One bounds check for the four reads, at the largest index.
        let hi = i00.max(i10).max(i01).max(i11);
        let data = &self.data[..(hi + 1) * C::BPP];
        let read = |i: usize| {
            let b = i * C::BPP;
            // SAFETY: i ≤ hi, so b + BPP ≤ (hi + 1)·BPP = data.len() (checked by the slice).
            let bytes = unsafe { data.get_unchecked(b..b + C::BPP) };
            C::decode_premultiplied(bytes, self.lut)
        };
        ((read(i00), read(i10)), (read(i01), read(i11)))
    }

    /// The texels of a [`Layout::Tiled4x4`] level of `bpp`-byte texels and its tiles per
    /// row, checked to hold every tile (`tiles_x · ⌈h/4⌉ · 16` texels).
    ///
    /// # Panics
    /// If the level is not so laid out (callers check the texture's layout and format).
    #[inline]
    pub fn tiled_texels(&self, bpp: usize) -> (&'a [u8], u32) {
        let tiles = self.tiles_x as usize * (self.h as usize).div_ceil(4);
        assert!(
            self.layout == Layout::Tiled4x4 && self.data.len() >= tiles * 16 * bpp,
            "not a tiled level of {bpp}-byte texels"
        );
        (self.data, self.tiles_x)
    }

    /// The texel index of in-range `(0, y)`: with [`LevelRef::column`], a row's indices with
    /// the row's part computed once (`texel_index` split in two; the sum is the same index).
    #[inline(always)]
    pub fn row_start(&self, y: i32) -> usize {
        let y = y as u32;
        match self.layout {
            Layout::RowMajor => (y * self.w as u32) as usize,
            Layout::Tiled4x4 => ((y >> 2) * self.tiles_x * 16 + ((y & 3) << 2)) as usize,
        }
    }

    /// What in-range column `x` adds to a row's [`LevelRef::row_start`].
    #[inline(always)]
    pub fn column(&self, x: i32) -> usize {
        let x = x as u32;
        match self.layout {
            Layout::RowMajor => x as usize,
            Layout::Tiled4x4 => (((x >> 2) << 4) + (x & 3)) as usize,
        }
    }

    /// Linear, premultiplied texel at index `i` (`row_start + column`) of a level not held as
    /// blocks (callers check `C::BLOCKS`).
    #[inline(always)]
    pub fn texel_at<C: Codec>(&self, i: usize) -> Vec4 {
        let i = i * C::BPP;
        C::decode_premultiplied(&self.data[i..i + C::BPP], self.lut)
    }

    /// Linear, premultiplied texel at in-range `(x, y)`.
    #[inline(always)]
    pub fn texel<C: Codec>(&self, x: i32, y: i32) -> Vec4 {
        if C::BLOCKS {
            if let Some(b) = self.blocks {
                return b.texel(self.data, self.lut, x as u32, y as u32);
            }
        }
        let i = texel_index(self.layout, self.tiles_x, self.w as u32, x as u32, y as u32) * C::BPP;
        C::decode_premultiplied(&self.data[i..i + C::BPP], self.lut)
    }
}

#[cfg(test)]
mod tests;
