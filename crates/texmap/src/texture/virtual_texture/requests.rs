//! The feedback pass's page requests: one bit per page of every level, set from any thread
//! (a set, so the order threads set bits in does not matter), read and cleared between
//! passes.

use std::sync::atomic::{AtomicU64, Ordering};

use super::layout::{PageKey, PageLayout};

/// One bit per page, level by level.
#[derive(Debug)]
pub struct Requests {
    layout: PageLayout,
    /// Per level, row-major bits.
    bits: Vec<Vec<AtomicU64>>,
}

impl Requests {
    /// No page requested.
    #[must_use]
    pub fn new(layout: PageLayout) -> Self {
        let bits = (0..layout.levels())
            .map(|l| {
                let n = (layout.pages(l) as usize).pow(2);
                (0..n.div_ceil(64)).map(|_| AtomicU64::new(0)).collect()
            })
            .collect();
        Requests { layout, bits }
    }

    /// Requests page `key`.
    #[inline]
    pub fn add(&self, key: PageKey) {
        let i = (key.y * self.layout.pages(key.level) + key.x) as usize;
        let word = &self.bits[key.level as usize][i / 64];
        let bit = 1u64 << (i % 64);
        // Most requests repeat: read before writing keeps the line shared between threads.
        if word.load(Ordering::Relaxed) & bit == 0 {
            word.fetch_or(bit, Ordering::Relaxed);
        }
    }

    /// Every requested page, in key order (coarse levels first), and the set cleared.
    pub fn take(&self) -> Vec<PageKey> {
        let mut out = Vec::new();
        for level in (0..self.layout.levels()).rev() {
            let n = self.layout.pages(level);
            for (w, word) in self.bits[level as usize].iter().enumerate() {
                let mut bits = word.swap(0, Ordering::Relaxed);
                while bits != 0 {
                    let i = w as u32 * 64 + bits.trailing_zeros();
                    bits &= bits - 1;
                    out.push(PageKey {
                        level,
                        x: i % n,
                        y: i / n,
                    });
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_come_back_once_in_key_order_and_are_cleared() {
        let layout = PageLayout::new(10);
        let r = Requests::new(layout);
        let k = |level, x, y| PageKey { level, x, y };
        for key in [k(0, 7, 7), k(2, 1, 0), k(0, 0, 1), k(0, 7, 7), k(3, 0, 0)] {
            r.add(key);
        }
        assert_eq!(
            r.take(),
            vec![k(3, 0, 0), k(2, 1, 0), k(0, 0, 1), k(0, 7, 7)]
        );
        assert!(r.take().is_empty());
    }
}
