//! Animated outputs, encoded frame by frame as they are rendered (no frame is held once
//! encoded): GIF through `image`'s encoder (a NeuQuant palette per frame, speed 10, looping
//! forever, the delay in hundredths of a second: `--fps 25` is 4/100 s) and APNG through the
//! `png` crate (8 or 16 bits a channel, RGB or RGBA with `--alpha`, the delay 1/fps exactly,
//! looping forever). A GIF keeps no alpha (its one transparent index cannot hold coverage),
//! so `--alpha` is refused for it before rendering (`render/image_out.rs`).

use std::io::Write;
use std::path::{Path, PathBuf};

use texmap::frame::Frame;
use texmap::Error;

use crate::formats::{png_error, OutputFormat, Store};

enum Encoder<W: Write> {
    Gif(Box<image::codecs::gif::GifEncoder<W>>),
    Apng(png::Writer<W>),
}

/// An animation being written.
pub struct Animation<W: Write> {
    encoder: Encoder<W>,
    path: PathBuf,
    store: Store,
    fps: u16,
    frames: u32,
    pushed: u32,
}

impl<W: Write> Animation<W> {
    /// An animation of `frames` frames of `size` at `fps` into `w` (`path` names it in
    /// errors).
    ///
    /// # Errors
    /// [`Error::Io`] or [`Error::Decode`] naming `path` when the header cannot be written.
    pub fn new(
        w: W,
        path: &Path,
        format: OutputFormat,
        store: Store,
        frames: u32,
        fps: u16,
        size: (u32, u32),
    ) -> Result<Animation<W>, Error> {
        let fps = fps.max(1);
        let encoder = match format {
            OutputFormat::Gif => {
                let mut g = image::codecs::gif::GifEncoder::new_with_speed(w, 10);
                g.set_repeat(image::codecs::gif::Repeat::Infinite)
                    .map_err(|e| Error::decode(path, e.to_string()))?;
                Encoder::Gif(Box::new(g))
            }
            _ => Encoder::Apng(apng_header(w, path, store, frames, fps, size)?),
        };
        Ok(Animation {
            encoder,
            path: path.to_path_buf(),
            store,
            fps,
            frames,
            pushed: 0,
        })
    }

    /// Encodes the next frame.
    ///
    /// # Errors
    /// [`Error::Io`] or [`Error::Decode`] naming the output; more frames than announced.
    pub fn push(&mut self, frame: &Frame) -> Result<(), Error> {
        if self.pushed == self.frames {
            return Err(Error::parameter(format!(
                "{}: more frames than the {} announced",
                self.path.display(),
                self.frames
            )));
        }
        let path = &self.path;
        match &mut self.encoder {
            Encoder::Gif(g) => {
                let rgb = frame.to_srgb8();
                let rgba: Vec<u8> = rgb
                    .chunks_exact(3)
                    .flat_map(|p| [p[0], p[1], p[2], 255])
                    .collect();
                let buffer = image::RgbaImage::from_raw(frame.width, frame.height, rgba)
                    .ok_or_else(|| Error::decode(path, "frame size"))?;
                let delay = image::Delay::from_numer_denom_ms(1000, u32::from(self.fps));
                g.encode_frame(image::Frame::from_parts(buffer, 0, 0, delay))
                    .map_err(|e| match e {
                        image::ImageError::IoError(e) => Error::io(path, e),
                        e => Error::decode(path, e.to_string()),
                    })?;
            }
            Encoder::Apng(w) => {
                w.write_image_data(&self.store.png_rows(frame, true))
                    .map_err(|e| png_error(path, e))?;
            }
        }
        self.pushed += 1;
        Ok(())
    }

    /// Ends the file (the GIF trailer, the APNG's end), once every frame was pushed.
    ///
    /// # Errors
    /// [`Error::Io`] naming the output; fewer frames than announced.
    pub fn finish(self) -> Result<(), Error> {
        if self.pushed != self.frames {
            return Err(Error::parameter(format!(
                "{}: {} of {} frames written",
                self.path.display(),
                self.pushed,
                self.frames
            )));
        }
        match self.encoder {
            // The trailer is written when the encoder is dropped.
            Encoder::Gif(g) => drop(g),
            Encoder::Apng(w) => w.finish().map_err(|e| png_error(&self.path, e))?,
        }
        Ok(())
    }
}

fn apng_header<W: Write>(
    w: W,
    path: &Path,
    store: Store,
    frames: u32,
    fps: u16,
    (width, height): (u32, u32),
) -> Result<png::Writer<W>, Error> {
    let mut e = store.png_encoder(w, (width, height));
    e.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    e.set_animated(frames, 0).map_err(|e| png_error(path, e))?;
    e.set_frame_delay(1, fps).map_err(|e| png_error(path, e))?;
    e.write_header().map_err(|e| png_error(path, e))
}
