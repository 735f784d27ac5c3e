//! Texture container files: DDS, KTX 1 and KTX2, parsed into a [`TextureFile`] that knows
//! where each image (array layer × cube face × mip level) lies and decodes it.
//!
//! Rules every container follows:
//! - Sizes first: the header's size, levels, faces and layers are checked against the
//!   [`Limits`] and the size of every level is computed (checked `u64` arithmetic) and
//!   compared with the bytes the file holds *before* anything is allocated from them, so a
//!   header declaring 65535×65535 texels in a small file is one error line, not an
//!   allocation.
//! - Levels follow OpenGL's sizes, `max(1, ⌊n/2ⁱ⌋)` per axis; block formats store whole 4×4
//!   blocks at the edges of sizes that are not multiples of 4 ([`BlockFormat::level_bytes`]).
//! - Cube faces are in the files' order +X, −X, +Y, −Y, +Z, −Z, which is
//!   [`super::CubeFace::ALL`]'s, with rows top first as OpenGL uploads them (DDS, KTX and
//!   KTX2 all store cube faces so), so a face is a [`super::TextureCube`] face as it is.
//! - Colour space: an `_SRGB` format is sRGB ([`TextureFile::color_space`]); every other
//!   8-bit format says nothing, and the loaders decode it in the colour space the caller
//!   asks for (sRGB for colour, linear for data), as they do a PNG; float formats are linear.
//!
//! `dds.rs`, `ktx.rs` and `ktx2.rs` read the headers; `plain.rs` decodes the uncompressed
//! formats; `texture.rs` turns a file into a [`super::Texture2D`] or [`super::TextureCube`];
//! block formats decode through [`super::compressed`].

mod basis;
mod dds;
mod ktx;
mod ktx2;
mod plain;
#[cfg(test)]
mod tests;
mod texture;

use std::ops::Range;
use std::path::{Path, PathBuf};

use super::compressed::{self, BlockFormat};
use super::load::Limits;
use super::ColorSpace;
use crate::{Error, Result};

pub use plain::PlainFormat;
pub(crate) use texture::texture_from_file_with;
pub use texture::{cube_from_file, flat_image, texture_from_file};

/// The container a file is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Container {
    /// DirectDraw Surface (legacy FourCC and pixel-mask headers, and the DX10 header).
    Dds,
    /// Khronos KTX 1.
    Ktx,
    /// Khronos KTX 2.
    Ktx2,
}

const KTX1_MAGIC: [u8; 12] = *b"\xABKTX 11\xBB\r\n\x1A\n";
const KTX2_MAGIC: [u8; 12] = *b"\xABKTX 20\xBB\r\n\x1A\n";

impl Container {
    /// The container whose magic bytes `head` (the file's first 12 bytes or more) starts with.
    #[must_use]
    pub fn sniff(head: &[u8]) -> Option<Container> {
        if head.starts_with(b"DDS ") {
            Some(Container::Dds)
        } else if head.starts_with(&KTX1_MAGIC) {
            Some(Container::Ktx)
        } else if head.starts_with(&KTX2_MAGIC) {
            Some(Container::Ktx2)
        } else {
            None
        }
    }

    /// The container of the file at `path`, from its first bytes (`None` for another file, or
    /// one that cannot be read: the image decoders report that).
    #[must_use]
    pub fn of_file(path: &Path) -> Option<Container> {
        use std::io::Read as _;
        if crate::files::check_regular(path).is_err() {
            return None;
        }
        let mut head = [0u8; 12];
        let mut f = std::fs::File::open(path).ok()?;
        let mut n = 0;
        while n < head.len() {
            match f.read(&mut head[n..]) {
                Ok(0) | Err(_) => break,
                Ok(k) => n += k,
            }
        }
        Container::sniff(&head[..n])
    }

    /// The container's name ("DDS", "KTX", "KTX2").
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Container::Dds => "DDS",
            Container::Ktx => "KTX",
            Container::Ktx2 => "KTX2",
        }
    }
}

/// How a file's texels are stored: in 4×4 blocks, or one texel after another.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FileFormat {
    /// A block-compressed format (BC1–BC7, BC6H).
    Block(BlockFormat),
    /// An uncompressed format.
    Plain(PlainFormat),
}

impl FileFormat {
    /// The format's name ("BC7", "R11G11B10F", …).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            FileFormat::Block(b) => b.name(),
            FileFormat::Plain(p) => p.name(),
        }
    }

    /// True when texels decode to floats beyond 8 bits (BC6H, half and float formats): read
    /// them with [`TextureFile::decode_f32`].
    #[must_use]
    pub const fn is_float(self) -> bool {
        match self {
            FileFormat::Block(b) => b.is_float(),
            FileFormat::Plain(p) => p.is_float(),
        }
    }

    /// True for the signed-normalised formats (BC4 and BC5 signed), whose values reach −1.
    #[must_use]
    pub const fn is_signed(self) -> bool {
        matches!(
            self,
            FileFormat::Block(BlockFormat::Bc4Signed | BlockFormat::Bc5Signed)
        )
    }

    /// Bytes of one `width`×`height` image (one depth slice) in this format.
    #[must_use]
    pub const fn image_bytes(self, width: u32, height: u32) -> u64 {
        match self {
            FileFormat::Block(b) => b.level_bytes(width, height),
            FileFormat::Plain(p) => width as u64 * height as u64 * p.bytes_per_texel() as u64,
        }
    }
}

/// What a header declares: the format and the shape of the texture.
#[derive(Clone, Copy, Debug)]
struct Desc {
    container: Container,
    format: FileFormat,
    color_space: ColorSpace,
    /// The format stores no alpha (BC1 in its "RGB" variants): decoded alpha is 1.
    opaque: bool,
    width: u32,
    height: u32,
    depth: u32,
    levels: u32,
    faces: u32,
    layers: u32,
}

impl Desc {
    /// Width, height and depth of `level`.
    fn level_size(&self, level: u32) -> (u32, u32, u32) {
        let at = |n: u32| n.checked_shr(level).unwrap_or(0).max(1);
        (at(self.width), at(self.height), at(self.depth))
    }

    /// Bytes of one layer's face at `level`, every depth slice.
    fn image_bytes(&self, level: u32) -> u64 {
        let (w, h, d) = self.level_size(level);
        self.format.image_bytes(w, h) * u64::from(d)
    }

    /// Bytes of every image of `level` (all layers and faces); `None` on overflow.
    fn level_bytes(&self, level: u32) -> Option<u64> {
        self.image_bytes(level)
            .checked_mul(u64::from(self.layers))?
            .checked_mul(u64::from(self.faces))
    }

    /// Bytes of every image of every level; `None` on overflow.
    fn total_bytes(&self) -> Option<u64> {
        (0..self.levels).try_fold(0u64, |sum, l| sum.checked_add(self.level_bytes(l)?))
    }

    /// Refuses a shape that is empty, inconsistent or above `limits`, and a file whose texel
    /// data (`available` bytes) is shorter than the shape needs: all before any allocation.
    fn check(&self, path: &Path, limits: &Limits, available: u64) -> Result<()> {
        let c = self.container.name();
        let (w, h, d) = (self.width, self.height, self.depth);
        if w == 0 || h == 0 || d == 0 {
            return Err(Error::decode(
                path,
                format!("{c} header declares a size of {w}x{h}x{d}, with a zero side"),
            ));
        }
        if self.faces != 1 && self.faces != 6 {
            return Err(Error::decode(
                path,
                format!(
                    "{c} header declares {} faces; a texture has 1, a cube map 6",
                    self.faces
                ),
            ));
        }
        if self.faces == 6 && (w != h || d != 1) {
            return Err(Error::decode(
                path,
                format!("{c} cube map of {w}x{h}x{d}: cube faces are square and flat"),
            ));
        }
        if self.layers == 0 {
            return Err(Error::decode(path, format!("{c} header declares 0 layers")));
        }
        let max_depth = limits.max_width.max(limits.max_height);
        if w > limits.max_width || h > limits.max_height || d > max_depth {
            return Err(Error::limits(
                path,
                format!(
                    "texture is {w}x{h}x{d}, above the limit of {}x{}x{max_depth}",
                    limits.max_width, limits.max_height
                ),
            ));
        }
        let chain = super::level_count(w.max(d), h) as u32;
        if self.levels == 0 || self.levels > chain {
            return Err(Error::decode(
                path,
                format!(
                    "{c} header declares {} mip levels; a {w}x{h}x{d} texture has 1 to {chain}",
                    self.levels
                ),
            ));
        }
        // The widest texel an image decodes to: 4 × f32.
        let decoded = u64::from(w) * u64::from(h) * u64::from(d) * 16;
        if decoded > limits.max_bytes {
            return Err(Error::limits(
                path,
                format!(
                    "texture is {w}x{h}x{d}: up to {} MiB decoded per image, above the limit of \
                     {} MiB",
                    decoded >> 20,
                    limits.max_bytes >> 20
                ),
            ));
        }
        let total = self.total_bytes().filter(|&t| t <= available);
        let Some(_) = total else {
            return Err(Error::decode(
                path,
                format!(
                    "{c} file is truncated: {} layer(s) x {} face(s) x {} level(s) of {w}x{h}x{d} \
                     {} need {} bytes of texel data, the file holds {available}",
                    self.layers,
                    self.faces,
                    self.levels,
                    self.format.name(),
                    self.total_bytes()
                        .map_or("more than 2^64".to_string(), |t| t.to_string()),
                ),
            ));
        };
        Ok(())
    }
}

/// A texture container file, parsed: its format and shape, and where each image lies.
///
/// An image is one array layer's cube face at one mip level, every depth slice of a volume
/// texture included (slice after slice). Images are addressed `(layer, face, level)`; for a
/// plain 2D texture all three are 0.
#[derive(Clone, Debug)]
pub struct TextureFile {
    path: PathBuf,
    desc: Desc,
    file_bytes: u64,
    data: Vec<u8>,
    /// Byte ranges into `data`, at `(layer · faces + face) · levels + level`.
    images: Vec<Range<usize>>,
    /// For a Basis Universal file, its codec ("ETC1S", "UASTC"): `data` is then the
    /// transcoded texels.
    transcoded_from: Option<&'static str>,
}

/// Reads and parses the texture container at `path` (DDS, KTX or KTX2, told by its magic
/// bytes), within `limits` (the file is read up to `limits.max_bytes`).
///
/// # Errors
/// One line naming the file: unreadable, not a container, truncated, a size or level count
/// that does not match the data, an unknown or unsupported format, above `limits`.
pub fn read_texture_file(path: &Path, limits: &Limits) -> Result<TextureFile> {
    let bytes = crate::files::read_bounded(path, limits.max_bytes)?;
    TextureFile::from_bytes(bytes, path, limits)
}

impl TextureFile {
    /// Parses a container held in memory (`name` is used in messages).
    ///
    /// # Errors
    /// As [`read_texture_file`].
    pub fn from_bytes(bytes: Vec<u8>, name: &Path, limits: &Limits) -> Result<TextureFile> {
        match Container::sniff(&bytes) {
            Some(Container::Dds) => dds::parse(bytes, name, limits),
            Some(Container::Ktx) => ktx::parse(bytes, name, limits),
            Some(Container::Ktx2) => ktx2::parse(bytes, name, limits),
            None => Err(Error::decode(
                name,
                "not a texture container (DDS, KTX or KTX2): its magic bytes are none of theirs",
            )),
        }
    }

    /// Assembles a parsed file: `images` are in `(layer, face, level)` order.
    fn new(
        path: &Path,
        desc: Desc,
        file_bytes: u64,
        data: Vec<u8>,
        images: Vec<Range<usize>>,
    ) -> Self {
        debug_assert_eq!(
            images.len() as u64,
            u64::from(desc.layers * desc.faces * desc.levels)
        );
        TextureFile {
            path: path.to_path_buf(),
            desc,
            file_bytes,
            data,
            images,
            transcoded_from: None,
        }
    }

    /// For a Basis Universal KTX2 file, its codec ("ETC1S" or "UASTC"), which was transcoded
    /// to the RGBA8 texels this file holds; `None` for every other file.
    #[must_use]
    pub fn transcoded_from(&self) -> Option<&'static str> {
        self.transcoded_from
    }

    /// The file's path (or the name given to [`TextureFile::from_bytes`]).
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }
    /// The container.
    #[must_use]
    pub fn container(&self) -> Container {
        self.desc.container
    }
    /// The texel format.
    #[must_use]
    pub fn format(&self) -> FileFormat {
        self.desc.format
    }
    /// [`ColorSpace::Srgb`] for an `_SRGB` format, else [`ColorSpace::Linear`] (which, for an
    /// 8-bit format, means the file does not say: see the module docs).
    #[must_use]
    pub fn color_space(&self) -> ColorSpace {
        self.desc.color_space
    }
    /// Width of level 0.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.desc.width
    }
    /// Height of level 0.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.desc.height
    }
    /// Depth of level 0 (1 unless a volume texture).
    #[must_use]
    pub fn depth(&self) -> u32 {
        self.desc.depth
    }
    /// Number of mip levels stored.
    #[must_use]
    pub fn levels(&self) -> u32 {
        self.desc.levels
    }
    /// Number of faces: 6 for a cube map, else 1.
    #[must_use]
    pub fn faces(&self) -> u32 {
        self.desc.faces
    }
    /// Number of array layers (1 unless an array texture).
    #[must_use]
    pub fn layers(&self) -> u32 {
        self.desc.layers
    }
    /// Size of the file in bytes.
    #[must_use]
    pub fn file_bytes(&self) -> u64 {
        self.file_bytes
    }
    /// Width, height and depth of `level` (OpenGL's sizes; 1 past the last level).
    #[must_use]
    pub fn level_size(&self, level: u32) -> (u32, u32, u32) {
        self.desc.level_size(level)
    }
    /// True when the levels stored are a full chain down to 1×1.
    #[must_use]
    pub fn has_full_chain(&self) -> bool {
        let (w, h, d) = (self.desc.width, self.desc.height, self.desc.depth);
        self.desc.levels as usize == super::level_count(w.max(d), h)
    }
    /// Bytes of texel data of every image, as stored (after supercompression is undone).
    #[must_use]
    pub fn texel_bytes(&self) -> u64 {
        self.images.iter().map(|r| r.len() as u64).sum()
    }
    /// Bytes every image takes decoded: 4 a texel (RGBA8), 16 for float formats (RGBA f32).
    #[must_use]
    pub fn decoded_bytes(&self) -> u64 {
        let per = if self.desc.format.is_float() { 16 } else { 4 };
        (0..self.desc.levels)
            .map(|l| {
                let (w, h, d) = self.desc.level_size(l);
                u64::from(w) * u64::from(h) * u64::from(d) * per
            })
            .sum::<u64>()
            * u64::from(self.desc.layers * self.desc.faces)
    }

    /// Refuses an image address outside the file, naming the valid ranges.
    fn index(&self, layer: u32, face: u32, level: u32) -> Result<usize> {
        let d = &self.desc;
        let out_of = |what: &str, given: u32, count: u32| {
            Error::parameter(format!(
                "{}: {what} {given} is out of range: the file has {count} {what}{} (0 to {})",
                self.path.display(),
                if count == 1 { "" } else { "s" },
                count - 1
            ))
        };
        if layer >= d.layers {
            return Err(out_of("layer", layer, d.layers));
        }
        if face >= d.faces {
            return Err(out_of("face", face, d.faces));
        }
        if level >= d.levels {
            return Err(out_of("level", level, d.levels));
        }
        Ok(((layer * d.faces + face) * d.levels + level) as usize)
    }

    /// The stored bytes of one image: `layer`'s `face` at `level`, every depth slice.
    ///
    /// # Errors
    /// [`Error::Parameter`] naming the valid range when an index is out of it.
    pub fn data(&self, layer: u32, face: u32, level: u32) -> Result<&[u8]> {
        let i = self.index(layer, face, level)?;
        Ok(&self.data[self.images[i].clone()])
    }

    /// One image decoded to RGBA8, row-major, depth slices one after another
    /// (`w·h·d·4` bytes): the values the format's rules give, no colour conversion (an sRGB
    /// format's bytes stay encoded). R8 reads `(r, 0, 0, 255)`, RG8 `(r, g, 0, 255)`.
    ///
    /// # Errors
    /// Out-of-range indices as [`TextureFile::data`]; [`Error::Unsupported`] for a float
    /// format (read it with [`TextureFile::decode_f32`]).
    pub fn decode_rgba8(&self, layer: u32, face: u32, level: u32) -> Result<Vec<u8>> {
        let bytes = self.data(layer, face, level)?;
        if self.desc.format.is_float() {
            return Err(Error::Unsupported(format!(
                "{}: {} is a float format; it decodes to floats, not 8-bit values",
                self.path.display(),
                self.desc.format.name()
            )));
        }
        let (w, h, d) = self.desc.level_size(level);
        let mut out = match self.desc.format {
            FileFormat::Plain(p) => plain::decode_rgba8(p, bytes),
            FileFormat::Block(b) => {
                let per = b.level_bytes(w, h) as usize;
                let mut out = Vec::with_capacity(w as usize * h as usize * d as usize * 4);
                for slice in bytes.chunks_exact(per) {
                    let decoded = compressed::decode_level_rgba8(b, slice, w, h)
                        .map_err(|e| self.decode_error(e))?;
                    out.extend_from_slice(&decoded);
                }
                out
            }
        };
        if self.desc.opaque {
            out.chunks_exact_mut(4).for_each(|t| t[3] = 255);
        }
        Ok(out)
    }

    /// One image decoded to RGBA `f32` (4 floats a texel, row-major, depth slices one after
    /// another): float formats as stored, 8-bit unorm values `v/255` (no colour conversion),
    /// signed formats by the snorm rule; alpha 1 where the format has none.
    ///
    /// # Errors
    /// Out-of-range indices as [`TextureFile::data`].
    pub fn decode_f32(&self, layer: u32, face: u32, level: u32) -> Result<Vec<f32>> {
        let bytes = self.data(layer, face, level)?;
        let (w, h, d) = self.desc.level_size(level);
        let mut out = match self.desc.format {
            FileFormat::Plain(p) => plain::decode_f32(p, bytes),
            FileFormat::Block(b) => {
                let per = b.level_bytes(w, h) as usize;
                let mut out = Vec::with_capacity(w as usize * h as usize * d as usize * 4);
                for slice in bytes.chunks_exact(per) {
                    let decoded = compressed::decode_level_f32(b, slice, w, h)
                        .map_err(|e| self.decode_error(e))?;
                    out.extend_from_slice(&decoded);
                }
                out
            }
        };
        if self.desc.opaque {
            out.chunks_exact_mut(4).for_each(|t| t[3] = 1.0);
        }
        Ok(out)
    }

    /// A decoder's error, naming this file.
    fn decode_error(&self, e: Error) -> Error {
        match e {
            Error::Unsupported(m) | Error::Parameter(m) => Error::decode(&self.path, m),
            other => other,
        }
    }
}

/// Reads a little-endian `u32` at `at` (the caller has checked the length).
fn le32(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

/// The byte ranges of images stored one after another from `start`, layer by layer, face by
/// face, level by level (DDS's order, and KTX2's inside a level): `images` in
/// `(layer, face, level)` order. The caller has checked that they fit.
fn contiguous_images(desc: &Desc, start: usize) -> Vec<Range<usize>> {
    let mut images = Vec::with_capacity((desc.layers * desc.faces * desc.levels) as usize);
    let mut at = start;
    for _ in 0..desc.layers * desc.faces {
        for level in 0..desc.levels {
            let n = desc.image_bytes(level) as usize;
            images.push(at..at + n);
            at += n;
        }
    }
    images
}
