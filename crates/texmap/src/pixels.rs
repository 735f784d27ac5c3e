//! [`Pixels`]: a frame's colour, RGBA `f32` pixels whose first starts a 64-byte cache line.
//!
//! The rasterizer writes each finished tile's rows to the frame with streaming stores, whole
//! cache lines that bypass the caches. A `Vec<Vec4>` of a frame's size comes from the
//! allocator 16 bytes past a page boundary, so every 64-pixel tile row began and ended in
//! the middle of a line: two lines a row written in pieces, from two tiles at different
//! times, each piece a partial line the memory system has to merge. On a line boundary a
//! tile row is 16 whole lines (the 1080p plane's frames 1.03–1.05× faster; DESIGN.md's log).

use std::alloc::Layout;
use std::ops::{Deref, DerefMut};

use glam::Vec4;

/// Pixels a cache line holds.
const LINE: usize = 4;

/// A frame's pixels: a slice of [`Vec4`] (it dereferences to one) whose first element is
/// on a 64-byte boundary.
///
/// They are held in a `Vec<Vec4>` three pixels longer than asked, from the first of its
/// pixels on a line: a `Vec4`'s own 16-byte alignment is what the system allocator zeroes
/// for free (`calloc`: a frame's size is the system's fresh pages, which nothing writes until
/// the tiles write their pixels, in parallel), where a 64-byte alignment is allocated and
/// then zeroed on one thread (33 MB of stores, and their page faults, for a 1080p frame).
///
/// A draw into them (`pipeline::draw_into`) leaves a note of the tiles it filled with the
/// clear colour alone; the next draw of the same size and clear colour does not write such a
/// tile again when it is empty again ([`ClearTiles`]). Any mutable borrow of the pixels
/// forgets the note, so it never outlives what it describes.
#[derive(Default)]
pub struct Pixels {
    buf: Vec<Vec4>,
    /// The index in `buf` of the first pixel, the first on a line.
    start: usize,
    len: usize,
    /// The tiles known to hold the clear colour alone, since the last draw into them.
    clear: Option<Box<ClearTiles>>,
}

/// The tiles of a `width × height` frame that the draw into it filled with `color` alone (its
/// bits), tile `t` at `tiles[t]` (the rasterizer's tile order): what [`Pixels`] remembers of
/// its last draw.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ClearTiles {
    /// The frame's size in pixels.
    pub width: u32,
    pub height: u32,
    /// The clear colour's bits (`f32::to_bits` of its four channels).
    pub color: [u32; 4],
    /// Whether tile `t` holds the clear colour alone.
    pub tiles: Vec<bool>,
}

impl Pixels {
    /// `n` pixels of zero, straight from the allocator's zeroed memory.
    #[must_use]
    pub fn zeroed(n: usize) -> Self {
        if n == 0 {
            return Pixels::default();
        }
        let cap = n.checked_add(LINE - 1);
        let Some((cap, layout)) = cap.and_then(|c| Some((c, Layout::array::<Vec4>(c).ok()?)))
        else {
            // As `Vec` does for a capacity beyond the address space.
            panic!("{n} pixels: capacity overflow");
        };
        // SAFETY: the layout's size is not zero; zero bytes are `Vec4::ZERO`s; the memory
        // comes from the global allocator with the layout a `Vec<Vec4>` of capacity `cap`
        // frees it with.
        let buf = unsafe {
            let p = std::alloc::alloc_zeroed(layout).cast::<Vec4>();
            if p.is_null() {
                std::alloc::handle_alloc_error(layout);
            }
            Vec::from_raw_parts(p, cap, cap)
        };
        // `Vec4`s are 16-byte aligned: the first line boundary is at most three pixels on.
        let start = (buf.as_ptr() as usize).wrapping_neg() % 64 / 16;
        Pixels {
            buf,
            start,
            len: n,
            clear: None,
        }
    }

    /// The note of the tiles the last draw into these pixels left holding its clear colour
    /// alone, taken (none after any mutable borrow since that draw).
    pub fn take_clear_tiles(&mut self) -> Option<Box<ClearTiles>> {
        self.clear.take()
    }

    /// Notes that the tiles `clear` names hold its colour alone: for the draw that just
    /// wrote them (`pipeline::draw_into`).
    pub fn set_clear_tiles(&mut self, clear: Box<ClearTiles>) {
        self.clear = Some(clear);
    }

    /// `n` pixels of `c`.
    #[must_use]
    pub fn filled(n: usize, c: Vec4) -> Self {
        let mut p = Pixels::zeroed(n);
        p.fill(c);
        p
    }
}

impl Clone for Pixels {
    /// A copy on a line boundary of its own.
    fn clone(&self) -> Self {
        Pixels::from(&self[..])
    }
}

impl Deref for Pixels {
    type Target = [Vec4];

    #[inline(always)]
    fn deref(&self) -> &[Vec4] {
        // SAFETY: `buf` holds `start + len` pixels (`zeroed`; empty: 0 + 0), borrowed with
        // `self`.
        unsafe { std::slice::from_raw_parts(self.buf.as_ptr().add(self.start), self.len) }
    }
}

impl DerefMut for Pixels {
    #[inline(always)]
    fn deref_mut(&mut self) -> &mut [Vec4] {
        // Whatever is written through the borrow, the note of clear tiles no longer holds.
        self.clear = None;
        // SAFETY: as in `deref`, borrowed mutably with `self`.
        unsafe { std::slice::from_raw_parts_mut(self.buf.as_mut_ptr().add(self.start), self.len) }
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
            assert!(
                n == 0 || (q.as_ptr() as usize).is_multiple_of(64),
                "{n} pixels, cloned"
            );
            assert_eq!(Pixels::from(p.to_vec()), p);
            assert_eq!(p.iter().copied().collect::<Pixels>(), p);
        }
        assert!(Pixels::filled(7, Vec4::ONE).iter().all(|&c| c == Vec4::ONE));
    }
}
