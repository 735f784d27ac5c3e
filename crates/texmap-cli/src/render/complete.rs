//! `--skip-existing`: is an output already there and complete?
//!
//! Outputs are renamed into place only once written whole (`output.rs`), so a file under an
//! output's name was finished by texmap — unless something else wrote it, or it was cut
//! short afterwards. So a file counts as complete only when it decodes to the end, at the
//! render's `--size`, with every frame an animation should hold. Anything else (missing,
//! truncated, another size, undecodable) is rendered again.

use std::path::Path;

use image::AnimationDecoder;

use crate::formats::OutputFormat;

/// True when `path` holds a whole image of `format` at `size` with `frames` frames.
pub fn is_complete(path: &Path, format: OutputFormat, size: (u32, u32), frames: u32) -> bool {
    if !path.is_file() {
        return false;
    }
    let Ok(file) = std::fs::File::open(path) else {
        return false;
    };
    let reader = std::io::BufReader::new(file);
    match format {
        OutputFormat::Gif => {
            let Ok(decoder) = image::codecs::gif::GifDecoder::new(reader) else {
                return false;
            };
            whole_animation(decoder.into_frames(), size, frames)
        }
        OutputFormat::Apng => {
            let Ok(decoder) = image::codecs::png::PngDecoder::new(reader) else {
                return false;
            };
            match decoder.apng() {
                Ok(apng) => whole_animation(apng.into_frames(), size, frames),
                Err(_) => false,
            }
        }
        _ => {
            let Ok(reader) = image::ImageReader::new(reader).with_guessed_format() else {
                return false;
            };
            reader
                .decode()
                .is_ok_and(|img| (img.width(), img.height()) == size)
        }
    }
}

fn whole_animation(frames: image::Frames, size: (u32, u32), count: u32) -> bool {
    let mut n = 0u32;
    for f in frames {
        match f {
            Ok(f) if f.buffer().dimensions() == size => n += 1,
            _ => return false,
        }
    }
    n == count
}
