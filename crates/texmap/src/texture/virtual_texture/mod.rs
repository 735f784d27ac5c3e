//! Virtual texturing: a texture far larger than memory, read through a page table per mip
//! level from a fixed-size cache of resident pages.
//!
//! - **Pages** (`layout.rs`): level `l` is cut into pages of 128² texels, each held with a
//!   4-texel border copied from its neighbours (as the texture wraps), 136² RGBA16F in all,
//!   so nearest, bilinear, trilinear and anisotropic taps read one page and never cross its
//!   edge; the existing filters read it as a small [`Texture2D`] (`source.rs`).
//! - **Source** ([`PageSource`]): any texel of any level, the box average of level 0's
//!   (`pattern.rs`: the procedural quadtree, exact at every level).
//! - **Cache** (`cache.rs`): a page table per level over `budget / page bytes` slots, least
//!   recently used pages evicted, the tail (the levels of ≤ 128 texels, one page each)
//!   pinned: the finest coarser level resident always exists.
//! - **Feedback** (`requests.rs`, `sample.rs`): the frame driver (`render`) first draws
//!   the frame at half its size with the textures in feedback mode: each read
//!   records the pages its levels need over its footprint (λ corrected for the smaller
//!   frame) instead of reading. [`VirtualTexture::update`] then loads what was asked (coarse
//!   levels first, pages made in parallel, in an order that does not depend on threads) and
//!   the frame is drawn; a read whose page is not resident falls back to the finest coarser
//!   level that is.
//!
//! The resident set is fixed while a frame is drawn, so the image does not depend on the
//! number of threads.

mod cache;
pub mod layout;
pub mod pattern;
mod requests;
mod sample;
mod source;

use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError, RwLock};

use rayon::prelude::*;

use self::cache::PageCache;
pub use self::layout::{PageKey, PageLayout, PAGE_BORDER, PAGE_BYTES, PAGE_SIDE, PAGE_TEXELS};
pub use self::pattern::QuadtreePattern;
use self::requests::Requests;
pub use self::source::PageSource;
use super::{Filter, Sampler, Texture2D, TextureOptions, Wrap};
use crate::frame::VirtualPageStats;
use crate::{Error, Result};

/// Slots a budget must hold beyond the pinned tail: a trilinear read's two pages and room
/// to turn.
pub const MIN_FREE_PAGES: u64 = 4;
/// The largest side [`VirtualTexture::resident_texture`] builds whole (4096²: 256 MiB of
/// RGBA32F at level 0).
pub const MAX_RESIDENT_SIDE: u32 = 4096;

/// A texture read a page at a time (module docs).
#[derive(Debug)]
pub struct VirtualTexture {
    layout: PageLayout,
    source: Arc<dyn PageSource>,
    wraps: (Wrap, Wrap),
    budget: AtomicU64,
    cache: RwLock<PageCache<Texture2D>>,
    requests: Requests,
    /// In a feedback pass: the f32 bits of how many frame pixels a feedback pixel spans on a
    /// side (0: not in feedback).
    feedback: AtomicU32,
    fallbacks: AtomicU64,
    totals: Mutex<VirtualPageStats>,
}

impl VirtualTexture {
    /// A virtual texture of `side`² texels (a power of two from 128 to 131,072) whose pages
    /// `source` makes, wrapping as `wraps` says (repeat or clamp on each axis), with a cache
    /// of `budget` bytes.
    ///
    /// # Errors
    /// [`Error::Parameter`] for another side or wrap, or a budget below
    /// [`VirtualTexture::min_budget`].
    pub fn new(
        source: Arc<dyn PageSource>,
        side: u32,
        wraps: (Wrap, Wrap),
        budget: u64,
    ) -> Result<Self> {
        let log2 = side.trailing_zeros();
        if !side.is_power_of_two()
            || !(layout::MIN_SIDE_LOG2..=layout::MAX_SIDE_LOG2).contains(&log2)
        {
            return Err(Error::parameter(format!(
                "virtual texture size {side} is not a power of two from {} to {}",
                1u32 << layout::MIN_SIDE_LOG2,
                1u32 << layout::MAX_SIDE_LOG2
            )));
        }
        for w in [wraps.0, wraps.1] {
            if !matches!(w, Wrap::Repeat | Wrap::ClampToEdge) {
                return Err(Error::parameter(format!(
                    "virtual textures wrap repeat or clamp (their pages' borders are made so), not {}",
                    w.name()
                )));
            }
        }
        let layout = PageLayout::new(log2);
        let vt = VirtualTexture {
            layout,
            source,
            wraps,
            budget: AtomicU64::new(0),
            cache: RwLock::new(PageCache::new(layout, 0)),
            requests: Requests::new(layout),
            feedback: AtomicU32::new(0),
            fallbacks: AtomicU64::new(0),
            totals: Mutex::new(VirtualPageStats::default()),
        };
        vt.set_budget(budget)?;
        Ok(vt)
    }

    /// The quadtree pattern ([`QuadtreePattern`]) as a virtual texture.
    ///
    /// # Errors
    /// As [`VirtualTexture::new`].
    pub fn quadtree(side: u32, seed: u64, wraps: (Wrap, Wrap), budget: u64) -> Result<Self> {
        let log2 = side.trailing_zeros().min(layout::MAX_SIDE_LOG2);
        Self::new(
            Arc::new(QuadtreePattern::new(log2, seed)),
            side,
            wraps,
            budget,
        )
    }

    /// The smallest budget for a `side`² texture: its pinned tail and
    /// [`MIN_FREE_PAGES`] more pages.
    #[must_use]
    pub fn min_budget(layout: &PageLayout) -> u64 {
        (layout.tail().count() as u64 + MIN_FREE_PAGES) * PAGE_BYTES
    }

    /// Empties the cache and gives it `budget` bytes (the tail made again, pinned).
    ///
    /// # Errors
    /// [`Error::Parameter`] when `budget` cannot hold the tail and [`MIN_FREE_PAGES`] more.
    pub fn set_budget(&self, budget: u64) -> Result<()> {
        let min = Self::min_budget(&self.layout);
        if budget < min {
            let mib = |b: u64| b as f64 / (1u64 << 20) as f64;
            return Err(Error::parameter(format!(
                "virtual texture budget {:.2} MiB is too small: the {} coarsest levels of the {}² texture take {} pages of {} KiB, and reads need {} more; give at least {:.2} MiB",
                mib(budget),
                self.layout.tail().count(),
                self.side(),
                self.layout.tail().count(),
                PAGE_BYTES / 1024,
                MIN_FREE_PAGES,
                mib(min)
            )));
        }
        let capacity = usize::try_from(budget / PAGE_BYTES).unwrap_or(usize::MAX);
        // A budget above every page is every page.
        let capacity =
            capacity.min(usize::try_from(self.layout.total_pages()).unwrap_or(usize::MAX));
        let tail: Vec<PageKey> = self.layout.tail().collect();
        let pages = self.make_pages(&tail)?;
        let mut cache = PageCache::new(self.layout, capacity);
        for (key, page) in tail.into_iter().zip(pages) {
            cache.insert(key, page, true);
        }
        *self.cache.write().unwrap_or_else(PoisonError::into_inner) = cache;
        self.budget.store(budget, Ordering::Relaxed);
        Ok(())
    }

    /// Pages of `keys`, made in parallel (each a pure function of its key).
    fn make_pages(&self, keys: &[PageKey]) -> Result<Vec<Texture2D>> {
        keys.par_iter()
            .map(|&k| source::build_page(&*self.source, &self.layout, k, self.wraps))
            .collect()
    }

    /// Texels on a side of level 0.
    #[must_use]
    pub fn side(&self) -> u32 {
        self.layout.side()
    }

    /// The levels and pages.
    #[must_use]
    pub fn layout(&self) -> PageLayout {
        self.layout
    }

    /// What the texels are.
    #[must_use]
    pub fn describe(&self) -> String {
        self.source.describe()
    }

    /// The wrap modes along u and v.
    #[must_use]
    pub fn wraps(&self) -> (Wrap, Wrap) {
        self.wraps
    }

    /// The cache's budget in bytes.
    #[must_use]
    pub fn budget(&self) -> u64 {
        self.budget.load(Ordering::Relaxed)
    }

    /// Pages the cache holds at most, and holds now.
    #[must_use]
    pub fn slots(&self) -> (usize, usize) {
        let c = self.cache.read().unwrap_or_else(PoisonError::into_inner);
        (c.capacity(), c.resident())
    }

    /// Whether `sampler` can read this texture: an OpenGL filter or anisotropic (EWA and
    /// summed-area tables read whole levels), and the texture's own wrap modes (its pages'
    /// borders are made with them).
    ///
    /// # Errors
    /// [`Error::Unsupported`] naming what is not.
    pub fn check_sampler(&self, sampler: &Sampler) -> Result<()> {
        if matches!(
            sampler.filter,
            Filter::Ewa { .. } | Filter::EwaExact { .. } | Filter::SummedArea
        ) {
            return Err(Error::Unsupported(format!(
                "virtual textures are read with the OpenGL filters or anisoN, not {} (it reads whole levels)",
                sampler.filter.name()
            )));
        }
        if (sampler.wrap_u, sampler.wrap_v) != self.wraps {
            return Err(Error::Unsupported(format!(
                "this virtual texture wraps {}/{} (its pages' borders are made so), not {}/{}",
                self.wraps.0.name(),
                self.wraps.1.name(),
                sampler.wrap_u.name(),
                sampler.wrap_v.name()
            )));
        }
        Ok(())
    }

    /// Starts a feedback pass: reads record the pages they need and return no colour. A
    /// feedback pixel spans `scale` frame pixels on a side (λ is lowered by `log2(scale)`).
    pub fn begin_feedback(&self, scale: f32) {
        self.feedback
            .store(scale.max(1.0).to_bits(), Ordering::Relaxed);
    }

    /// Ends the feedback pass and brings in the pages it asked for (evicting least recently
    /// used ones beyond the budget); returns what moved.
    ///
    /// # Errors
    /// None in practice: a page of a valid layout always builds.
    pub fn update(&self) -> Result<VirtualPageStats> {
        self.feedback.store(0, Ordering::Relaxed);
        self.fallbacks.store(0, Ordering::Relaxed);
        let requested = self.requests.take();
        let mut cache = self.cache.write().unwrap_or_else(PoisonError::into_inner);
        let plan = cache.plan(&requested);
        for &k in &plan.evict {
            cache.evict(k);
        }
        let pages = self.make_pages(&plan.load)?;
        for (&k, page) in plan.load.iter().zip(pages) {
            cache.insert(k, page, false);
        }
        let stats = VirtualPageStats {
            requested: requested.len() as u64,
            loaded: plan.load.len() as u64,
            evicted: plan.evict.len() as u64,
            over_budget: plan.over_budget as u64,
            resident: cache.resident() as u64,
            fallback_reads: 0,
        };
        let mut totals = self.totals.lock().unwrap_or_else(PoisonError::into_inner);
        totals.requested += stats.requested;
        totals.loaded += stats.loaded;
        totals.evicted += stats.evicted;
        totals.over_budget += stats.over_budget;
        totals.resident = stats.resident;
        Ok(stats)
    }

    /// Reads since the last [`VirtualTexture::update`] that fell back to a coarser level.
    #[must_use]
    pub fn fallback_reads(&self) -> u64 {
        self.fallbacks.load(Ordering::Relaxed)
    }

    /// Every update's counts summed (resident: the last).
    #[must_use]
    pub fn totals(&self) -> VirtualPageStats {
        *self.totals.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The finest level of the tail (128² texels) and its chain as an ordinary
    /// [`Texture2D`]: what a reader that knows nothing of pages is given.
    ///
    /// # Errors
    /// None in practice (the side is valid).
    pub fn coarse_texture(&self) -> Result<Texture2D> {
        let level = self.layout.tail_start();
        let side = self.layout.level_side(level);
        Texture2D::from_fn(side, side, TextureOptions::default(), |x, y| {
            self.source.texel(level, x, y)
        })
    }

    /// The whole texture as an ordinary [`Texture2D`] (RGBA32F level 0 from the source, the
    /// chain box-filtered as every texture's is): what a virtual read is compared with.
    ///
    /// # Errors
    /// [`Error::Parameter`] above [`MAX_RESIDENT_SIDE`].
    pub fn resident_texture(&self) -> Result<Texture2D> {
        let side = self.side();
        if side > MAX_RESIDENT_SIDE {
            return Err(Error::parameter(format!(
                "a {side}² virtual texture is too large to hold whole (at most {MAX_RESIDENT_SIDE}²)"
            )));
        }
        Texture2D::from_fn(side, side, TextureOptions::default(), |x, y| {
            self.source.texel(0, x, y)
        })
    }
}
