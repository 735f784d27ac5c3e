//! [`Pixels`]: a frame's colour, RGBA `f32` pixels whose first starts a 64-byte cache line.
//!
//! The rasterizer writes each finished tile's rows to the frame with streaming stores, whole
//! cache lines that bypass the caches. A `Vec<Vec4>` of a frame's size comes from the
//! allocator 16 bytes past a page boundary, so every 64-pixel tile row began and ended in
//! the middle of a line: two lines a row written in pieces, from two tiles at different
//! times, each piece a partial line the memory system has to merge. On a line boundary a
//! tile row is 16 whole lines (the 1080p plane's frames 1.03–1.05× faster; DESIGN.md's log).

use std::ops::{Deref, DerefMut};

use glam::Vec4;

/// Four pixels: one 64-byte line, on its boundary.
#[derive(Clone, Copy)]
#[repr(C, align(64))]
struct Line([Vec4; 4]);

const _: () = assert!(std::mem::size_of::<Line>() == 64 && std::mem::align_of::<Line>() == 64);

/// A frame's pixels: a slice of [`Vec4`] (it dereferences to one) whose first element is
/// on a 64-byte boundary; the last line's unused lanes are zero.
#[derive(Clone, Default)]
pub struct Pixels {
    lines: Vec<Line>,
    len: usize,
}

impl Pixels {
    /// `n` pixels of zero, straight from the allocator's zeroed memory: for a frame's size the
    /// system's fresh pages, which nothing writes until the tiles write their pixels, in
    /// parallel (a 1080p frame written with zeros first took 33 MB of stores, and its page
    /// faults, on one thread).
    #[must_use]
    pub fn zeroed(n: usize) -> Self {
        let lines = n.div_ceil(4);
        let layout = match std::alloc::Layout::array::<Line>(lines) {
            Ok(layout) if layout.size() > 0 => layout,
            Ok(_) => return Pixels::default(),
            // As `Vec` does for a capacity beyond the address space.
            Err(_) => panic!("{n} pixels: capacity overflow"),
        };
        // SAFETY: the layout's size is not zero; zero bytes are four `Vec4::ZERO`s, a valid
        // `Line`; the memory comes from the global allocator with the layout a `Vec<Line>`
        // of capacity `lines` frees it with.
        let lines = unsafe {
            let p = std::alloc::alloc_zeroed(layout).cast::<Line>();
            if p.is_null() {
                std::alloc::handle_alloc_error(layout);
            }
            Vec::from_raw_parts(p, lines, lines)
        };
        Pixels { lines, len: n }
    }

    /// `n` pixels of `c`.
    #[must_use]
    pub fn filled(n: usize, c: Vec4) -> Self {
        let mut p = Pixels::zeroed(n);
        p.fill(c);
        p
    }
}

impl Deref for Pixels {
    type Target = [Vec4];

    #[inline(always)]
    fn deref(&self) -> &[Vec4] {
        // SAFETY: the lines hold at least `len` pixels, contiguous (`Line` is four `Vec4`s
        // with no padding), borrowed with `self`.
        unsafe { std::slice::from_raw_parts(self.lines.as_ptr().cast::<Vec4>(), self.len) }
    }
}

impl DerefMut for Pixels {
    #[inline(always)]
    fn deref_mut(&mut self) -> &mut [Vec4] {
        // SAFETY: as in `deref`, borrowed mutably with `self`.
        unsafe { std::slice::from_raw_parts_mut(self.lines.as_mut_ptr().cast::<Vec4>(), self.len) }
    }
}

impl<'a> IntoIterator for &'a Pixels {
    type Item = &'a Vec4;
    type IntoIter = std::slice::Iter<'a, Vec4>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl<'a> IntoIterator for &'a mut Pixels {
    type Item = &'a mut Vec4;
    type IntoIter = std::slice::IterMut<'a, Vec4>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter_mut()
    }
}

impl From<&[Vec4]> for Pixels {
    fn from(src: &[Vec4]) -> Self {
        let mut p = Pixels::zeroed(src.len());
        p.copy_from_slice(src);
        p
    }
}

impl From<Vec<Vec4>> for Pixels {
    /// A copy of `src` on a line boundary.
    fn from(src: Vec<Vec4>) -> Self {
        Pixels::from(&src[..])
    }
}

impl FromIterator<Vec4> for Pixels {
    /// The pixels collected into a `Vec`, then copied onto a line boundary.
    fn from_iter<I: IntoIterator<Item = Vec4>>(iter: I) -> Self {
        Pixels::from(iter.into_iter().collect::<Vec<Vec4>>())
    }
}

impl PartialEq for Pixels {
    fn eq(&self, other: &Self) -> bool {
        **self == **other
    }
}

impl PartialEq<Vec<Vec4>> for Pixels {
    fn eq(&self, other: &Vec<Vec4>) -> bool {
        **self == other[..]
    }
}

impl PartialEq<Pixels> for Vec<Vec4> {
    fn eq(&self, other: &Pixels) -> bool {
        self[..] == **other
    }
}

impl std::fmt::Debug for Pixels {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixels_start_on_a_line_hold_their_length_and_start_zero() {
        for n in [0usize, 1, 3, 4, 5, 1000, 1 << 20, 1920 * 1080] {
            let mut p = Pixels::zeroed(n);
            assert_eq!(p.len(), n);
            assert!(p.iter().all(|&c| c == Vec4::ZERO), "{n}");
            if n > 0 {
                assert_eq!(p.as_ptr() as usize % 64, 0, "{n} pixels");
            }
            for (i, c) in p.iter_mut().enumerate() {
                *c = Vec4::splat(i as f32);
            }
            let q = p.clone();
            assert_eq!(q, p);
            assert_eq!(Pixels::from(p.to_vec()), p);
            assert_eq!(p.iter().copied().collect::<Pixels>(), p);
        }
        assert!(Pixels::filled(7, Vec4::ONE).iter().all(|&c| c == Vec4::ONE));
    }
}
