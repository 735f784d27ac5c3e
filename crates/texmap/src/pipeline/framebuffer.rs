//! Framebuffer: a tile's colour and depth samples, blending, the MSAA resolve, and the SSAA
//! box filter.
//!
//! Colour is premultiplied linear RGBA. Opaque writes replace; blended writes use
//! premultiplied "over": `dst = src + (1 − src.a)·dst`. The MSAA resolve and the SSAA
//! downsample are plain averages in linear light.

use glam::Vec4;

use super::bin::TILE;
use crate::pixels::Pixels;

/// The colour and depth samples of one tile, in local arrays.
///
/// Sample `s` of local pixel `(x, y)` is at index `(y·TILE + x)·samples + s`.
#[derive(Clone, Debug)]
pub struct TileBuffer {
    pub samples: usize,
    pub color: Vec<Vec4>,
    pub depth: Vec<f32>,
    /// The depth pre-pass's nearest depths (one a pixel; `raster.rs`).
    pub zmin: Vec<f32>,
}

impl TileBuffer {
    /// A tile cleared to `clear` and depth 1.
    #[must_use]
    pub fn new(samples: usize, clear: Vec4) -> Self {
        let n = (TILE * TILE) as usize * samples;
        TileBuffer {
            samples,
            color: vec![clear; n],
            depth: vec![1.0; n],
            zmin: vec![1.0; (TILE * TILE) as usize],
        }
    }

    /// Runs `f` with this thread's tile buffer of `samples` samples a pixel (made on first
    /// use, and again when the count changes; kept across frames, so that a frame's tiles
    /// allocate nothing). `f` clears it as it needs: its contents are the last tile's.
    pub fn with_thread_buffer<R>(samples: usize, f: impl FnOnce(&mut TileBuffer) -> R) -> R {
        thread_local! {
            static BUFFER: std::cell::RefCell<Option<TileBuffer>> =
                const { std::cell::RefCell::new(None) };
        }
        BUFFER.with(|b| {
            let mut b = b.borrow_mut();
            if b.as_ref().is_none_or(|b| b.samples != samples) {
                *b = Some(TileBuffer::new(samples, Vec4::ZERO));
            }
            f(b.as_mut().expect("set above"))
        })
    }

    /// Clears every sample to `clear` and depth 1.
    pub fn clear(&mut self, clear: Vec4) {
        self.color.fill(clear);
        self.depth.fill(1.0);
    }

    /// Resolves local row `y` (the first `out.len()` pixels) into `out`: the average of each
    /// pixel's samples.
    #[inline]
    pub fn resolve_row(&self, y: usize, out: &mut [Vec4]) {
        let s = self.samples;
        let base = y * TILE as usize * s;
        if s == 1 {
            stream_copy(out, &self.color[base..base + out.len()]);
            return;
        }
        let inv = 1.0 / s as f32;
        for (x, o) in out.iter_mut().enumerate() {
            let i = base + x * s;
            *o = self.color[i..i + s].iter().copied().sum::<Vec4>() * inv;
        }
    }

    /// Writes `src` to sample index `i`, blending or replacing.
    #[inline(always)]
    pub fn write(&mut self, i: usize, src: Vec4, blend: bool) {
        over(&mut self.color[i], src, blend);
    }
}

/// A one-sample tile's colours, where [`super::FragmentShader::shade_into_tile`] writes a
/// batch's quads: pixel `(x, y)` of the target at `(y − y0)·TILE + (x − x0)`.
pub struct TileColors<'a> {
    color: &'a mut [Vec4],
    x0: u32,
    y0: u32,
}

impl<'a> TileColors<'a> {
    /// The colours `color` (one sample a pixel, `TILE` wide) of the tile whose first pixel
    /// is `(x0, y0)`.
    pub(super) fn new(color: &'a mut [Vec4], x0: u32, y0: u32) -> Self {
        TileColors { color, x0, y0 }
    }

    /// Writes `colors` to the pixels of `quad` in `mask` (pixel `j` at `(quad.x + (j & 1),
    /// quad.y + (j >> 1))`), replacing what is there.
    ///
    /// # Panics
    /// If the quad is not in the tile.
    #[inline(always)]
    pub fn write(&mut self, quad: &super::Quad, mask: u8, colors: &[Vec4; 4]) {
        let tile = TILE as usize;
        let i = (quad.y - self.y0) as usize * tile + (quad.x - self.x0) as usize;
        let c = &mut self.color[i..i + tile + 2];
        if mask == 0b1111 {
            c[..2].copy_from_slice(&colors[..2]);
            c[tile..].copy_from_slice(&colors[2..]);
            return;
        }
        for (j, &v) in colors.iter().enumerate() {
            if mask & (1 << j) != 0 {
                c[(j >> 1) * tile + (j & 1)] = v;
            }
        }
    }
}

// `_mm_stream_ps` needs 16-byte aligned targets: glam's `Vec4` is an `__m128` on x86-64 (SSE2
// builds), so every element of a `[Vec4]` is. A glam built without SIMD would break this.
#[cfg(target_arch = "x86_64")]
const _: () = assert!(std::mem::align_of::<Vec4>() == 16 && std::mem::size_of::<Vec4>() == 16);

/// Copies `src` to `dst` (the same length) with streaming stores on x86-64: the frame's lines
/// are written whole without being read first (no read-for-ownership of a frame that is
/// about to be overwritten: a measurable share of a frame, see DESIGN.md). Call
/// [`stream_fence`] before another thread reads `dst`.
#[inline]
pub fn stream_copy(dst: &mut [Vec4], src: &[Vec4]) {
    assert_eq!(dst.len(), src.len(), "stream_copy: lengths differ");
    #[cfg(target_arch = "x86_64")]
    {
        // Four pixels (a cache line) a step, then the rest: pixel by pixel the loop was six
        // instructions a pixel, 1.2 % of the trilinear plane's instructions (the frame's
        // time did not change: the streaming stores wait on memory, not on the loop).
        let (mut d4, mut s4) = (dst.chunks_exact_mut(4), src.chunks_exact(4));
        for (d, s) in (&mut d4).zip(&mut s4) {
            for k in 0..4 {
                stream(&mut d[k], s[k]);
            }
        }
        for (d, s) in d4.into_remainder().iter_mut().zip(s4.remainder()) {
            stream(d, *s);
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    dst.copy_from_slice(src);
}

/// One streaming store of `v` to `d`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn stream(d: &mut Vec4, v: Vec4) {
    // SAFETY: SSE is part of x86_64; `Vec4` is 16-byte aligned on x86_64 (asserted at compile
    // time above), as `_mm_stream_ps` requires, and `d` is a valid, exclusive target.
    unsafe { std::arch::x86_64::_mm_stream_ps(std::ptr::from_mut(d).cast::<f32>(), v.into()) };
}

/// [`stream_copy`] of one value into every element of `dst`.
#[inline]
pub fn stream_fill(dst: &mut [Vec4], v: Vec4) {
    #[cfg(target_arch = "x86_64")]
    {
        // Four pixels a step, as `stream_copy`.
        let mut d4 = dst.chunks_exact_mut(4);
        for d in &mut d4 {
            for d in d {
                stream(d, v);
            }
        }
        for d in d4.into_remainder() {
            stream(d, v);
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    dst.fill(v);
}

/// Orders this thread's streaming stores before its later stores (so a thread that
/// synchronizes with it afterwards sees them).
#[inline]
pub fn stream_fence() {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: SSE is part of x86_64.
    unsafe {
        std::arch::x86_64::_mm_sfence();
    }
}

/// Writes `src` to `dst`: premultiplied "over" when blending, else replace.
#[inline(always)]
pub fn over(dst: &mut Vec4, src: Vec4, blend: bool) {
    *dst = if blend {
        src + *dst * (1.0 - src.w)
    } else {
        src
    };
}

/// Box-filters an image of `(w·n) × (h·n)` pixels down to `w × h` (SSAA resolve).
#[must_use]
pub fn downsample_box(src: Pixels, w: usize, h: usize, n: usize) -> Pixels {
    if n <= 1 {
        return src;
    }
    let sw = w * n;
    let inv = 1.0 / (n * n) as f32;
    let mut out = Pixels::zeroed(w * h);
    for (y, row) in out.chunks_exact_mut(w).enumerate() {
        for (x, o) in row.iter_mut().enumerate() {
            let mut sum = Vec4::ZERO;
            for sy in 0..n {
                let base = (y * n + sy) * sw + x * n;
                for c in &src[base..base + n] {
                    sum += *c;
                }
            }
            *o = sum * inv;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn premultiplied_over() {
        let mut t = TileBuffer::new(1, Vec4::new(0.0, 0.0, 1.0, 1.0));
        t.write(0, Vec4::new(0.5, 0.0, 0.0, 0.5), true);
        assert_eq!(t.color[0], Vec4::new(0.5, 0.0, 0.5, 1.0));
        t.write(0, Vec4::new(0.0, 1.0, 0.0, 1.0), false);
        assert_eq!(t.color[0], Vec4::new(0.0, 1.0, 0.0, 1.0));
    }

    #[test]
    fn resolve_and_downsample_average() {
        let mut t = TileBuffer::new(4, Vec4::ZERO);
        t.color[0] = Vec4::ONE;
        let mut out = [Vec4::ZERO];
        t.resolve_row(0, &mut out);
        assert_eq!(out[0], Vec4::splat(0.25));
        let src = Pixels::from(vec![Vec4::ONE, Vec4::ZERO, Vec4::ZERO, Vec4::ZERO]);
        assert_eq!(downsample_box(src, 1, 1, 2)[0], Vec4::splat(0.25));
    }

    #[test]
    fn streaming_copies_and_fills_write_exactly_their_slice() {
        // Every length around the four-pixel steps, at every offset in a cache line: the
        // slice written, the pixels around it untouched.
        for len in 0..14 {
            for start in 0..4 {
                let src: Vec<Vec4> = (0..len).map(|i| Vec4::splat(i as f32 + 1.0)).collect();
                let mut buf = vec![Vec4::splat(-1.0); len + 8];
                stream_copy(&mut buf[start..start + len], &src);
                stream_fence();
                assert_eq!(&buf[start..start + len], &src[..], "copy {len} at {start}");
                let outside = buf[..start].iter().chain(&buf[start + len..]);
                assert!(outside.into_iter().all(|&p| p == Vec4::splat(-1.0)));
                let v = Vec4::new(0.25, 0.5, 0.75, 1.0);
                stream_fill(&mut buf[start..start + len], v);
                stream_fence();
                assert!(
                    buf[start..start + len].iter().all(|&p| p == v),
                    "fill {len}"
                );
                let outside = buf[..start].iter().chain(&buf[start + len..]);
                assert!(outside.into_iter().all(|&p| p == Vec4::splat(-1.0)));
            }
        }
    }
}
