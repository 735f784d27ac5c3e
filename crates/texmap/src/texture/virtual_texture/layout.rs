//! Where pages sit: a virtual texture's levels, each cut into pages of 128² texels held with
//! a 4-texel border (136² in memory), and the keys that name them.
//!
//! Level `l` of a `2ᵏ`-texel square is `2ᵏ⁻ˡ` texels on a side and `⌈2ᵏ⁻ˡ/128⌉` pages. The
//! levels of 128 texels or fewer (the *tail*) are one page each, always resident: the
//! finest of them is where every fallback ends.

/// Texels of a level a page covers on each side (fewer on the tail's smaller levels).
pub const PAGE_TEXELS: u32 = 128;
/// Texels copied from the neighbouring pages on each side: bilinear needs 1, and 4 keeps
/// the page's texel rows 16-byte aligned in 4×4 tiles.
pub const PAGE_BORDER: u32 = 4;
/// A full page's side in memory.
pub const PAGE_SIDE: u32 = PAGE_TEXELS + 2 * PAGE_BORDER;
/// Bytes one page holds (RGBA16F, 8 bytes a texel); a cache slot is sized for it.
pub const PAGE_BYTES: u64 = (PAGE_SIDE * PAGE_SIDE) as u64 * 8;
/// The smallest virtual texture side (one page) and the largest (a page table of 1024² at
/// level 0, 4 MiB).
pub const MIN_SIDE_LOG2: u32 = 7;
pub const MAX_SIDE_LOG2: u32 = 17;

/// One page: its level and its column and row among that level's pages.
///
/// Keys order coarse levels first, then row-major: the order requests are served in, so
/// when the budget cannot hold them all the coarse pages (what others fall back to) win.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PageKey {
    pub level: u32,
    pub x: u32,
    pub y: u32,
}

impl PartialOrd for PageKey {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for PageKey {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        other
            .level
            .cmp(&self.level)
            .then(self.y.cmp(&other.y))
            .then(self.x.cmp(&other.x))
    }
}

/// The levels and pages of a square virtual texture of `2^side_log2` texels a side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PageLayout {
    side_log2: u32,
}

impl PageLayout {
    /// The layout of a `2^side_log2` square, `side_log2` in
    /// [`MIN_SIDE_LOG2`]`..=`[`MAX_SIDE_LOG2`] (checked by the caller).
    #[must_use]
    pub fn new(side_log2: u32) -> Self {
        debug_assert!((MIN_SIDE_LOG2..=MAX_SIDE_LOG2).contains(&side_log2));
        PageLayout { side_log2 }
    }

    /// Texels on a side of level 0.
    #[must_use]
    pub fn side(&self) -> u32 {
        1 << self.side_log2
    }

    /// Levels in the full chain, down to 1×1.
    #[must_use]
    pub fn levels(&self) -> u32 {
        self.side_log2 + 1
    }

    /// Texels on a side of level `level`.
    #[must_use]
    pub fn level_side(&self, level: u32) -> u32 {
        (self.side() >> level).max(1)
    }

    /// Texels of level `level` one page covers on a side.
    #[must_use]
    pub fn span(&self, level: u32) -> u32 {
        self.level_side(level).min(PAGE_TEXELS)
    }

    /// Pages on a side of level `level`.
    #[must_use]
    pub fn pages(&self, level: u32) -> u32 {
        self.level_side(level).div_ceil(PAGE_TEXELS)
    }

    /// The first level held in one page: it and every coarser level are the pinned tail.
    #[must_use]
    pub fn tail_start(&self) -> u32 {
        self.side_log2 - MIN_SIDE_LOG2
    }

    /// The tail's pages, finest first.
    pub fn tail(&self) -> impl Iterator<Item = PageKey> {
        (self.tail_start()..self.levels()).map(|level| PageKey { level, x: 0, y: 0 })
    }

    /// Every page of every level.
    #[must_use]
    pub fn total_pages(&self) -> u64 {
        (0..self.levels())
            .map(|l| u64::from(self.pages(l)).pow(2))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_65536_texture_has_17_levels_and_a_tail_of_8() {
        let l = PageLayout::new(16);
        assert_eq!((l.side(), l.levels(), l.tail_start()), (65536, 17, 9));
        assert_eq!(l.pages(0), 512);
        assert_eq!(l.pages(8), 2);
        assert_eq!((l.pages(9), l.span(9)), (1, 128));
        assert_eq!((l.pages(16), l.span(16)), (1, 1));
        assert_eq!(l.tail().count(), 8);
        assert_eq!(
            l.total_pages(),
            (0..9).map(|i| (512u64 >> i).pow(2)).sum::<u64>() + 8
        );
    }

    #[test]
    fn keys_order_coarse_levels_first_then_rows() {
        let k = |level, x, y| PageKey { level, x, y };
        let mut v = vec![k(0, 1, 0), k(2, 0, 0), k(0, 0, 1), k(0, 0, 0)];
        v.sort();
        assert_eq!(v, vec![k(2, 0, 0), k(0, 0, 0), k(0, 1, 0), k(0, 0, 1)]);
    }
}
