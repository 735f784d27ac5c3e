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
        use std::arch::x86_64::_mm_stream_ps;
        for (d, s) in dst.iter_mut().zip(src) {
            // SAFETY: SSE is part of x86_64; `Vec4` is 16-byte aligned on x86_64 (asserted at
            // compile time above), as `_mm_stream_ps` requires, and `d` is a valid, exclusive
            // target.
            unsafe { _mm_stream_ps(std::ptr::from_mut(d).cast::<f32>(), (*s).into()) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    dst.copy_from_slice(src);
}

/// [`stream_copy`] of one value into every element of `dst`.
#[inline]
pub fn stream_fill(dst: &mut [Vec4], v: Vec4) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::_mm_stream_ps;
        for d in dst.iter_mut() {
            // SAFETY: as in `stream_copy`.
            unsafe { _mm_stream_ps(std::ptr::from_mut(d).cast::<f32>(), v.into()) };
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
}
