//! What the viewer draws into its window's pixels: frames (sRGB, nearest-upscaled from a
//! preview), the A/B divider, and text in an 8×8 bitmap font (`font8x8`'s basic Latin) on
//! a darkened band so it reads over any image.
//!
//! Pixels are `0x00RRGGBB`, rows top first: the window's format.

use texmap::render::Frame;

/// Height of a text line in pixels (8 for the glyphs, 2 of spacing).
pub const LINE: usize = 10;

/// A window's pixels.
pub struct Canvas<'a> {
    pub pixels: &'a mut [u32],
    pub width: usize,
    pub height: usize,
}

impl Canvas<'_> {
    /// Copies the columns `x0..x1` of `frame`, stretched to the canvas (nearest: a preview
    /// rendered smaller fills the window).
    pub fn blit(&mut self, frame: &Frame, x0: usize, x1: usize) {
        let (fw, fh) = (frame.width as usize, frame.height as usize);
        if fw == 0 || fh == 0 {
            return;
        }
        let rgb = frame.to_srgb8();
        for y in 0..self.height {
            let sy = y * fh / self.height;
            for x in x0..x1.min(self.width) {
                let sx = x * fw / self.width;
                let i = 3 * (sy * fw + sx);
                self.pixels[y * self.width + x] =
                    u32::from(rgb[i]) << 16 | u32::from(rgb[i + 1]) << 8 | u32::from(rgb[i + 2]);
            }
        }
    }

    /// A vertical line at `x`, two pixels wide.
    pub fn divider(&mut self, x: usize) {
        for y in 0..self.height {
            for dx in 0..2 {
                if let Some(p) = self.pixels.get_mut(y * self.width + x + dx) {
                    if x + dx < self.width {
                        *p = if (y / 4) % 2 == 0 {
                            0xFF_FF_FF
                        } else {
                            0x20_20_20
                        };
                    }
                }
            }
        }
    }

    /// `lines` from `(x, y)`, each on a darkened band as wide as its text; characters
    /// outside printable ASCII show as `?`; what falls outside the canvas is cut.
    pub fn text(&mut self, x: usize, y: usize, lines: &[String]) {
        for (k, line) in lines.iter().enumerate() {
            let top = y + k * LINE;
            let chars = line.chars().count();
            self.darken(x, top, 8 * chars + 4, LINE);
            for (c, ch) in line.chars().enumerate() {
                self.glyph(x + 2 + 8 * c, top + 1, ch);
            }
        }
    }

    fn darken(&mut self, x: usize, y: usize, w: usize, h: usize) {
        for yy in y..(y + h).min(self.height) {
            for xx in x..(x + w).min(self.width) {
                let p = &mut self.pixels[yy * self.width + xx];
                *p = (*p >> 2) & 0x3F_3F_3F;
            }
        }
    }

    fn glyph(&mut self, x: usize, y: usize, ch: char) {
        let code = if (' '..='~').contains(&ch) { ch } else { '?' };
        let rows = font8x8::legacy::BASIC_LEGACY[code as usize];
        for (dy, bits) in rows.iter().enumerate() {
            for dx in 0..8 {
                // Bit 0 is the leftmost pixel.
                if bits & (1 << dx) != 0 && x + dx < self.width && y + dy < self.height {
                    self.pixels[(y + dy) * self.width + x + dx] = 0xFF_FF_FF;
                }
            }
        }
    }
}

/// The width in pixels of `text` drawn by [`Canvas::text`].
#[must_use]
pub fn text_width(text: &str) -> usize {
    8 * text.chars().count() + 4
}

#[cfg(test)]
mod tests {
    use glam::Vec4;

    use super::*;

    #[test]
    fn text_lights_the_glyphs_pixels_and_darkens_its_band() {
        let mut pixels = vec![0x80_80_80; 40 * 12];
        let mut c = Canvas {
            pixels: &mut pixels,
            width: 40,
            height: 12,
        };
        c.text(0, 0, &["I".to_string()]);
        let white = pixels.iter().filter(|&&p| p == 0xFF_FF_FF).count();
        let dark = pixels.iter().filter(|&&p| p == 0x20_20_20).count();
        // The glyph's lit pixels, the rest of its 12×10 band darkened, the rest untouched.
        let lit: u32 = font8x8::legacy::BASIC_LEGACY['I' as usize]
            .iter()
            .map(|r| r.count_ones())
            .sum();
        assert_eq!(white, lit as usize);
        assert_eq!(white + dark, 12 * LINE);
        assert_eq!(text_width("I"), 12);
    }

    #[test]
    fn a_preview_fills_the_canvas_and_a_half_copies_only_its_columns() {
        let frame = Frame {
            width: 2,
            height: 1,
            color: vec![Vec4::new(1.0, 0.0, 0.0, 1.0), Vec4::new(0.0, 0.0, 1.0, 1.0)].into(),
            ..Frame::default()
        };
        let mut pixels = vec![7; 8 * 2];
        let mut c = Canvas {
            pixels: &mut pixels,
            width: 8,
            height: 2,
        };
        c.blit(&frame, 0, 6);
        assert_eq!(
            &pixels[..8],
            &[0xFF_00_00, 0xFF_00_00, 0xFF_00_00, 0xFF_00_00, 0xFF, 0xFF, 7, 7]
        );
        assert_eq!(pixels[8..14], pixels[..6]);
    }
}
