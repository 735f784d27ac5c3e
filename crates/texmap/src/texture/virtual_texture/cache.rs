//! The resident pages: a page table per level and a fixed number of slots, least recently
//! used pages evicted first, the tail pinned.
//!
//! A frame's update is planned ([`PageCache::plan`]) before anything moves: requested pages
//! already resident are touched; missing ones are taken in key order (coarse levels first)
//! while slots remain once the pinned tail and this frame's resident requests are counted;
//! the victims are the unpinned pages not requested this frame, oldest use first (ties by
//! key). The caller evicts them, makes the new pages (in parallel) and inserts them, so the
//! cache never holds more than its slots, and the result does not depend on timing.

use super::layout::{PageKey, PageLayout};

/// No page in this entry of a page table.
const EMPTY: u32 = u32::MAX;

/// A resident page.
#[derive(Debug)]
struct Entry<T> {
    key: PageKey,
    page: T,
    last_used: u64,
    pinned: bool,
}

/// What an update will do.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Plan {
    /// Pages to make and insert, in key order.
    pub load: Vec<PageKey>,
    /// Pages to evict first, oldest use first.
    pub evict: Vec<PageKey>,
    /// Requested pages already resident.
    pub hits: usize,
    /// Requested pages left out: the slots were full of this frame's pages.
    pub over_budget: usize,
}

/// Page tables (one per level) over a fixed number of slots.
#[derive(Debug)]
pub struct PageCache<T> {
    layout: PageLayout,
    /// Per level, row-major: the slot holding the page, or [`EMPTY`].
    tables: Vec<Vec<u32>>,
    slots: Vec<Option<Entry<T>>>,
    free: Vec<u32>,
    clock: u64,
}

impl<T> PageCache<T> {
    /// An empty cache of `capacity` slots over `layout`'s levels.
    #[must_use]
    pub fn new(layout: PageLayout, capacity: usize) -> Self {
        let tables = (0..layout.levels())
            .map(|l| vec![EMPTY; (layout.pages(l) as usize).pow(2)])
            .collect();
        PageCache {
            layout,
            tables,
            slots: (0..capacity).map(|_| None).collect(),
            free: (0..capacity as u32).rev().collect(),
            clock: 0,
        }
    }

    /// Slots in all.
    #[must_use]
    pub fn capacity(&self) -> usize {
        self.slots.len()
    }

    /// Pages resident now.
    #[must_use]
    pub fn resident(&self) -> usize {
        self.slots.len() - self.free.len()
    }

    fn entry_index(&self, key: PageKey) -> usize {
        let n = self.layout.pages(key.level);
        (key.y * n + key.x) as usize
    }

    /// The page `key` if it is resident.
    #[inline]
    #[must_use]
    pub fn get(&self, key: PageKey) -> Option<&T> {
        let slot = *self
            .tables
            .get(key.level as usize)?
            .get(self.entry_index(key))?;
        if slot == EMPTY {
            return None;
        }
        self.slots[slot as usize].as_ref().map(|e| &e.page)
    }

    /// When `key` was last requested (or loaded), if it is resident.
    #[cfg(test)]
    #[must_use]
    pub fn last_used(&self, key: PageKey) -> Option<u64> {
        let slot = self.tables[key.level as usize][self.entry_index(key)];
        (slot != EMPTY).then(|| self.slots[slot as usize].as_ref().map(|e| e.last_used))?
    }

    /// Every resident page's key.
    #[cfg(test)]
    pub fn keys(&self) -> impl Iterator<Item = PageKey> + '_ {
        self.slots.iter().flatten().map(|e| e.key)
    }

    /// Inserts `page` as `key`, pinned (never evicted) or not, used now.
    ///
    /// # Panics
    /// If no slot is free or `key` is already resident (a plan's evictions come first).
    pub fn insert(&mut self, key: PageKey, page: T, pinned: bool) {
        let index = self.entry_index(key);
        assert_eq!(
            self.tables[key.level as usize][index], EMPTY,
            "{key:?} inserted twice"
        );
        let slot = self.free.pop().expect("a free slot (evict first)");
        self.slots[slot as usize] = Some(Entry {
            key,
            page,
            last_used: self.clock,
            pinned,
        });
        self.tables[key.level as usize][index] = slot;
    }

    /// Drops `key`'s page, if resident and not pinned.
    pub fn evict(&mut self, key: PageKey) {
        let index = self.entry_index(key);
        let slot = self.tables[key.level as usize][index];
        if slot == EMPTY || self.slots[slot as usize].as_ref().is_some_and(|e| e.pinned) {
            return;
        }
        self.slots[slot as usize] = None;
        self.tables[key.level as usize][index] = EMPTY;
        self.free.push(slot);
    }

    /// Starts a frame: touches the requested pages that are resident and says which to
    /// load and which to evict. `requested` is sorted and without repeats.
    pub fn plan(&mut self, requested: &[PageKey]) -> Plan {
        self.clock += 1;
        let now = self.clock;
        let mut plan = Plan::default();
        let mut missing = Vec::new();
        for &key in requested {
            let slot = self.tables[key.level as usize][self.entry_index(key)];
            match self.slots.get_mut(slot as usize).and_then(Option::as_mut) {
                Some(e) => {
                    e.last_used = now;
                    plan.hits += 1;
                }
                None => missing.push(key),
            }
        }
        // Slots this frame cannot take back: the pinned ones and those just touched.
        let kept = self
            .slots
            .iter()
            .flatten()
            .filter(|e| e.pinned || e.last_used == now)
            .count();
        let room = self.capacity() - kept;
        plan.over_budget = missing.len().saturating_sub(room);
        missing.truncate(room);
        let need = (self.resident() + missing.len()).saturating_sub(self.capacity());
        let mut victims: Vec<(u64, PageKey)> = self
            .slots
            .iter()
            .flatten()
            .filter(|e| !e.pinned && e.last_used < now)
            .map(|e| (e.last_used, e.key))
            .collect();
        victims.sort_unstable();
        plan.evict = victims.into_iter().take(need).map(|(_, k)| k).collect();
        plan.load = missing;
        plan
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::collections::HashMap;

    fn key(level: u32, x: u32, y: u32) -> PageKey {
        PageKey { level, x, y }
    }

    /// Runs `plan`, evicts, inserts: one frame.
    fn frame(cache: &mut PageCache<PageKey>, requested: &[PageKey]) -> Plan {
        let mut r = requested.to_vec();
        r.sort();
        r.dedup();
        let plan = cache.plan(&r);
        for &k in &plan.evict {
            cache.evict(k);
        }
        for &k in &plan.load {
            cache.insert(k, k, false);
        }
        plan
    }

    #[test]
    fn the_least_recently_used_page_goes_first() {
        let mut c = PageCache::new(PageLayout::new(9), 3);
        frame(&mut c, &[key(0, 0, 0)]);
        frame(&mut c, &[key(0, 1, 0)]);
        frame(&mut c, &[key(0, 2, 0)]);
        frame(&mut c, &[key(0, 0, 0)]);
        let p = frame(&mut c, &[key(0, 3, 0)]);
        assert_eq!(p.evict, vec![key(0, 1, 0)]);
        assert!(c.get(key(0, 0, 0)).is_some() && c.get(key(0, 1, 0)).is_none());
    }

    #[test]
    fn pinned_pages_stay_and_coarse_requests_win() {
        let mut c = PageCache::new(PageLayout::new(9), 3);
        c.insert(key(2, 0, 0), key(2, 0, 0), true);
        let p = frame(&mut c, &[key(0, 0, 0), key(0, 1, 0), key(1, 0, 0)]);
        assert_eq!(p.load, vec![key(1, 0, 0), key(0, 0, 0)]);
        assert_eq!(p.over_budget, 1);
        let p = frame(&mut c, &[key(0, 3, 3), key(0, 2, 2), key(0, 1, 1)]);
        assert_eq!(p.evict.len(), 2);
        assert!(c.get(key(2, 0, 0)).is_some());
    }

    proptest! {
        /// Over any run of frames: never more pages than slots; pinned pages stay; every
        /// request that fits is resident after its frame; no evicted page was used more
        /// recently than a page kept.
        #[test]
        fn the_cache_keeps_its_invariants(
            capacity in 2usize..12,
            frames in prop::collection::vec(
                prop::collection::vec((0u32..3, 0u32..4, 0u32..4), 0..10), 1..25),
        ) {
            let layout = PageLayout::new(9);
            let mut c = PageCache::new(layout, capacity);
            let tail = key(3, 0, 0);
            c.insert(tail, tail, true);
            let mut used: HashMap<PageKey, u64> = HashMap::new();
            for (t, reqs) in frames.iter().enumerate() {
                let mut r: Vec<PageKey> = reqs
                    .iter()
                    .map(|&(l, x, y)| key(l, x % layout.pages(l), y % layout.pages(l)))
                    .collect();
                r.sort();
                r.dedup();
                let plan = frame(&mut c, &r);
                let now = t as u64 + 1;
                prop_assert!(c.resident() <= capacity);
                prop_assert!(c.get(tail).is_some());
                for k in &r {
                    if c.get(*k).is_some() {
                        used.insert(*k, now);
                    }
                }
                if r.len() < capacity {
                    prop_assert_eq!(plan.over_budget, 0);
                    for k in &r {
                        prop_assert!(c.get(*k).is_some(), "{:?} not resident", k);
                    }
                }
                let kept: Vec<u64> = c.keys().filter(|k| *k != tail).map(|k| used[&k]).collect();
                for (k, &t) in &used {
                    if c.get(*k).is_none() {
                        prop_assert!(kept.iter().all(|&u| u >= t), "evicted {:?} used at {}", k, t);
                    }
                }
                for k in c.keys().filter(|k| *k != tail) {
                    prop_assert_eq!(c.last_used(k), Some(used[&k]));
                }
            }
        }
    }
}
