//! Reads through the page table: the OpenGL filters and anisotropic taps, each level's read
//! on the page that holds it (the existing `nearest` and `bilinear` on the page, whose border
//! keeps the taps inside), falling back to the finest coarser level resident; in a feedback
//! pass, the pages a read would take are recorded instead.

use std::sync::atomic::Ordering;
use std::sync::PoisonError;

use glam::{Vec2, Vec4};

use super::cache::PageCache;
use super::layout::{PageKey, PAGE_BORDER};
use super::VirtualTexture;
use crate::texture::filter::anisotropic::{probe_count, probe_lod};
use crate::texture::filter::{bilinear, ellipse_axes, nearest};
use crate::texture::footprint::fast_log2;
use crate::texture::format::CodecRgba16F;
use crate::texture::{
    Filter, MinFilter, MipChoice, QuadCoords, Sampler, TexelFilter, Texture2D, Wrap,
};

/// How many pages a read may record on each side of a level (a footprint wider than this
/// reads a level whose texels are larger: only a clamped λ gets here).
const MAX_RECORDED_PAGES: i64 = 4;

/// The sampler pages are read with: their borders hold the neighbours, so clamping never
/// reaches past them.
fn page_sampler() -> Sampler {
    Sampler::new(Filter::BILINEAR, Wrap::ClampToEdge)
}

/// What a read needs for a frame: the levels `choice` names at the lod from the footprint,
/// and (for anisotropic reads) the taps.
#[derive(Clone, Copy)]
enum Plan {
    Gl(MipChoice),
    Aniso {
        choice: MipChoice,
        axis_uv: Vec2,
        taps: u32,
    },
}

/// Pixel `j`'s own derivatives: along x its row's difference, along y its column's. The
/// frame reads with the quad's coarse ones (the top row, the left column); a feedback quad
/// spans twice as many frame pixels as a frame quad, where perspective near the horizon
/// changes them severalfold between its rows, so a feedback read takes its own pixel's.
fn fine_derivatives(c: &QuadCoords, j: usize) -> (Vec2, Vec2) {
    let lane = |k: usize| Vec2::new(c.u[k], c.v[k]);
    let row = j & 2;
    let column = j & 1;
    let dx = lane(row + 1) - lane(row);
    let dy = lane(column + 2) - lane(column);
    if dx.is_finite() && dy.is_finite() {
        (dx, dy)
    } else {
        (c.duv_dx, c.duv_dy)
    }
}

impl VirtualTexture {
    /// [`crate::texture::sample`] on this texture: linear, premultiplied RGBA.
    #[must_use]
    pub fn sample(&self, sampler: &Sampler, uv: Vec2, duv_dx: Vec2, duv_dy: Vec2) -> Vec4 {
        let cache = self.cache.read().unwrap_or_else(PoisonError::into_inner);
        self.read(&cache, sampler, uv, duv_dx, duv_dy)
    }

    /// [`crate::texture::sample_quads_lanes`] on this texture: `out[i]` for `coords[i]`,
    /// pixels whose bit in `masks[i]` is clear left zero.
    ///
    /// # Panics
    /// If `masks` or `out` is shorter than `coords`.
    pub fn sample_quads_lanes(
        &self,
        sampler: &Sampler,
        coords: &[QuadCoords],
        masks: &[u8],
        out: &mut [[Vec4; 4]],
    ) {
        assert!(masks.len() >= coords.len() && out.len() >= coords.len());
        let cache = self.cache.read().unwrap_or_else(PoisonError::into_inner);
        let feedback = self.feedback.load(Ordering::Relaxed) != 0;
        for ((c, &mask), o) in coords.iter().zip(masks).zip(out.iter_mut()) {
            *o = std::array::from_fn(|j| {
                if mask & (1 << j) == 0 {
                    return Vec4::ZERO;
                }
                let uv = Vec2::new(c.u[j], c.v[j]);
                let (dx, dy) = if feedback {
                    fine_derivatives(c, j)
                } else {
                    (c.duv_dx, c.duv_dy)
                };
                self.read(&cache, sampler, uv, dx, dy)
            });
        }
    }

    /// One read (or, in a feedback pass, its requests).
    fn read(
        &self,
        cache: &PageCache<Texture2D>,
        s: &Sampler,
        uv: Vec2,
        duv_dx: Vec2,
        duv_dy: Vec2,
    ) -> Vec4 {
        let feedback = f32::from_bits(self.feedback.load(Ordering::Relaxed));
        let size = self.layout.side() as f32;
        let (dx, dy) = (duv_dx * size, duv_dy * size);
        // A feedback pixel spans `feedback` frame pixels: λ as the frame's pixels see it.
        let lod_shift = if feedback > 0.0 {
            fast_log2(feedback)
        } else {
            0.0
        };
        let levels = self.layout.levels() as usize;
        // λ of the read, for the feedback pass (−∞: a filter without mipmaps).
        let mut lod_read = f32::NEG_INFINITY;
        // How far the frame pixels' λ may be from the feedback pixel's: the derivatives are
        // differences over a wider step, and anisotropic taps' count changes in steps.
        let mut lod_slack = 1.0;
        let plan = match s.filter {
            Filter::Anisotropic { max_aniso, lod } => {
                let (dx, dy) = if feedback > 0.0 {
                    (dx / feedback, dy / feedback)
                } else {
                    (dx, dy)
                };
                let (major_dir, major, minor) = ellipse_axes(dx, dy);
                let n = probe_count(major, minor, max_aniso);
                let lod = s.adjust_lod(probe_lod(major, minor, n, lod, fast_log2));
                lod_read = lod;
                lod_slack = 1.0;
                if !(major > 1.0) || !(lod > 0.0) && n == 1.0 {
                    Plan::Gl(MipChoice {
                        level: 0,
                        blend: None,
                        texels: TexelFilter::Linear,
                    })
                } else if !major.is_finite() {
                    Plan::Gl(MipChoice::trilinear(lod, levels))
                } else {
                    Plan::Aniso {
                        choice: MipChoice::trilinear(lod, levels),
                        axis_uv: major_dir * major / size,
                        taps: n as u32,
                    }
                }
            }
            Filter::Gl { mag, min } => {
                let lod = s.adjust_lod(s.lod_rule.lod(dx, dy) - lod_shift);
                if !matches!(min, MinFilter::Nearest | MinFilter::Linear) {
                    lod_read = lod;
                }
                Plan::Gl(MipChoice::gl(lod, levels, mag, min))
            }
            // Refused before a frame (`check_sampler`); read as trilinear if asked anyway.
            Filter::Ewa { .. } | Filter::EwaExact { .. } | Filter::SummedArea => {
                let lod = s.adjust_lod(s.lod_rule.lod(dx, dy) - lod_shift);
                lod_read = lod;
                Plan::Gl(MipChoice::trilinear(lod, levels))
            }
        };
        if feedback > 0.0 {
            // The feedback pixel's footprint and one frame pixel's beyond it.
            let reach = 0.5 * (duv_dx.abs() + duv_dy.abs()) * (1.0 + 1.0 / feedback);
            // λ changes across the frame pixels a feedback pixel stands for: the levels
            // λ ± slack reads (level 0 alone for filters without mipmaps).
            let last = levels - 1;
            let floor = |l: f32| (l.clamp(0.0, last as f32).floor() as usize).min(last);
            let (lo, hi) = if lod_read == f32::NEG_INFINITY {
                (0, 0)
            } else {
                (
                    floor(lod_read - lod_slack),
                    (floor(lod_read + lod_slack) + 1).min(last),
                )
            };
            if std::env::var_os("VTDEBUG").is_some() && lo == 0 && s.filter != Filter::TRILINEAR {
                eprintln!("rec0 uv {uv} reach {reach} lod {lod_read} hi {hi}");
            }
            for level in lo..=hi {
                self.record(uv, reach, level as u32);
            }
            return Vec4::ZERO;
        }
        match plan {
            Plan::Gl(choice) => {
                choice.read(|level| self.read_level(cache, uv, level, choice.texels))
            }
            Plan::Aniso {
                choice,
                axis_uv,
                taps,
            } => {
                let n = taps as f32;
                let mut sum = Vec4::ZERO;
                for i in 0..taps {
                    let t = (i as f32 + 0.5) / n - 0.5;
                    let uv = uv + axis_uv * t;
                    sum +=
                        choice.read(|level| self.read_level(cache, uv, level, TexelFilter::Linear));
                }
                sum / n
            }
        }
    }

    /// Page `(level, px, py)` and `uv` in the page's own coordinates (border included).
    #[inline]
    fn locate(&self, uv: Vec2, level: u32) -> (PageKey, Vec2) {
        let n = self.layout.level_side(level) as f32;
        let span = self.layout.span(level);
        let pages = self.layout.pages(level) as i64;
        let side = (span + 2 * PAGE_BORDER) as f32;
        let axis = |u: f32, wrap: Wrap| -> (u32, f32) {
            let u = if wrap == Wrap::Repeat {
                u - u.floor()
            } else {
                u
            };
            let t = u * n;
            let p = ((t / span as f32).floor() as i64).clamp(0, pages - 1);
            let local = (t - (p as f32) * span as f32 + PAGE_BORDER as f32) / side;
            (p as u32, local)
        };
        let (x, lu) = axis(uv.x, self.wraps.0);
        let (y, lv) = axis(uv.y, self.wraps.1);
        (PageKey { level, x, y }, Vec2::new(lu, lv))
    }

    /// Level `level` read at `uv`, or the finest coarser level resident.
    #[inline]
    fn read_level(
        &self,
        cache: &PageCache<Texture2D>,
        uv: Vec2,
        level: usize,
        texels: TexelFilter,
    ) -> Vec4 {
        let mut level = level as u32;
        let mut fell_back = false;
        loop {
            let (key, local) = self.locate(uv, level);
            if let Some(page) = cache.get(key) {
                if fell_back {
                    self.fallbacks.fetch_add(1, Ordering::Relaxed);
                }
                let lv = page.level(0);
                let s = page_sampler();
                return match texels {
                    TexelFilter::Nearest => nearest::<CodecRgba16F>(&lv, &s, local),
                    TexelFilter::Linear => bilinear::<CodecRgba16F>(&lv, &s, local),
                };
            }
            if std::env::var_os("VTDEBUG").is_some() && !fell_back {
                eprintln!("miss {key:?} uv {uv}");
            }
            // The tail is pinned, so the last level is always resident.
            if level + 1 >= self.layout.levels() {
                return Vec4::ZERO;
            }
            level += 1;
            fell_back = true;
        }
    }

    /// Requests the pages of `level` under `uv ± reach`.
    fn record(&self, uv: Vec2, reach: Vec2, level: u32) {
        let level = level.min(self.layout.levels() - 1);
        let n = self.layout.level_side(level) as f32;
        let span = self.layout.span(level) as f32;
        let pages = i64::from(self.layout.pages(level));
        let range = |u: f32, r: f32, wrap: Wrap| -> (i64, i64) {
            let u = if wrap == Wrap::Repeat {
                u - u.floor()
            } else {
                u
            };
            let lo = ((u - r) * n / span).floor();
            let hi = ((u + r) * n / span).floor();
            let (lo, hi) = (lo.max(-1e9) as i64, hi.min(1e9) as i64);
            let centre = (u * n / span).floor().clamp(-1e9, 1e9) as i64;
            (
                lo.max(centre - MAX_RECORDED_PAGES / 2),
                hi.min(centre + MAX_RECORDED_PAGES / 2),
            )
        };
        let (x0, x1) = range(uv.x, reach.x, self.wraps.0);
        let (y0, y1) = range(uv.y, reach.y, self.wraps.1);
        let fix = |p: i64, wrap: Wrap| -> u32 {
            if wrap == Wrap::Repeat {
                p.rem_euclid(pages) as u32
            } else {
                p.clamp(0, pages - 1) as u32
            }
        };
        for py in y0..=y1 {
            for px in x0..=x1 {
                self.requests.add(PageKey {
                    level,
                    x: fix(px, self.wraps.0),
                    y: fix(py, self.wraps.1),
                });
            }
        }
    }
}
