//! Basis Universal in KTX2 (ETC1S through BasisLZ, and UASTC, Zstandard-supercompressed or
//! not): transcoded when the file is read, by the pure-Rust `basisu` crate (a port of the
//! reference transcoder, byte for byte equal to it by its authors' conformance runs), to 8-bit
//! RGBA — the values the format's own decoder gives, with no second lossy step (transcoding
//! to BC7 would add one where UASTC is not exactly representable). The result is a plain
//! RGBA8 [`TextureFile`], so everything that reads texture files reads these too.
//!
//! The file's shape (size, levels, faces, layers) comes from the KTX2 header and is checked
//! against the limits before anything is transcoded; the colour space comes from the data
//! format descriptor's transfer function. The transcoder is new code reading untrusted data:
//! a panic inside it is caught and reported as invalid data, one line naming the file.

use std::ops::Range;
use std::path::Path;

use basisu::{DecodeFlags, TargetFormat, Transcoder};

use super::{Container, Desc, FileFormat, PlainFormat, TextureFile};
use crate::texture::load::Limits;
use crate::texture::ColorSpace;
use crate::{Error, Result};

/// Transcodes the Basis Universal KTX2 file `bytes` (its `kind`, "ETC1S" or "UASTC", for
/// messages) to an RGBA8 [`TextureFile`] of the header's shape, in `color_space`.
pub(super) fn transcode(
    bytes: &[u8],
    path: &Path,
    limits: &Limits,
    header: &ktx2::Header,
    color_space: ColorSpace,
    kind: &'static str,
) -> Result<TextureFile> {
    let invalid = |what: String| {
        Error::decode(
            path,
            format!("KTX2 Basis Universal ({kind}) data is invalid: {what}"),
        )
    };
    let desc = Desc {
        container: Container::Ktx2,
        format: FileFormat::Plain(PlainFormat::Rgba8),
        color_space,
        opaque: false,
        width: header.pixel_width,
        height: header.pixel_height.max(1),
        depth: header.pixel_depth.max(1),
        levels: header.level_count.max(1),
        faces: header.face_count.max(1),
        layers: header.layer_count.max(1),
    };
    // The decoded texels must fit in the memory budget (checked before any is made).
    desc.check(path, limits, limits.max_bytes)?;
    if desc.depth > 1 {
        return Err(Error::decode(
            path,
            "KTX2 Basis Universal volume textures are not read",
        ));
    }
    let run = std::panic::catch_unwind(|| -> Result<(Vec<u8>, Vec<Range<usize>>)> {
        let t = Transcoder::new(bytes).map_err(|e| invalid(format!("{e:?}")))?;
        if (t.base_dimensions(), t.level_count(), t.face_count().max(1))
            != ((desc.width, desc.height), desc.levels, desc.faces)
        {
            return Err(invalid(
                "its Basis data disagrees with the KTX2 header's size, levels or faces".into(),
            ));
        }
        let mut data = Vec::new();
        let mut images = Vec::new();
        for layer in 0..desc.layers {
            for face in 0..desc.faces {
                for level in 0..desc.levels {
                    let texels = t
                        .transcode_image(
                            level,
                            layer,
                            face,
                            TargetFormat::Rgba32,
                            DecodeFlags::NONE,
                        )
                        .map_err(|e| invalid(format!("level {level}: {e:?}")))?;
                    let (w, h, _) = desc.level_size(level);
                    if texels.len() != w as usize * h as usize * 4 {
                        return Err(invalid(format!("level {level} decoded to the wrong size")));
                    }
                    images.push(data.len()..data.len() + texels.len());
                    data.extend_from_slice(&texels);
                }
            }
        }
        Ok((data, images))
    });
    let (data, images) = match run {
        Ok(result) => result?,
        Err(_) => return Err(invalid("the transcoder failed on it".into())),
    };
    let mut file = TextureFile::new(path, desc, bytes.len() as u64, data, images);
    file.transcoded_from = Some(kind);
    Ok(file)
}
