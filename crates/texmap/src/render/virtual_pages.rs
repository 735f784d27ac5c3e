//! The frame driver's part for virtual textures: check how they are read, draw the
//! feedback pass at half the frame's size (each read records the pages it needs,
//! λ corrected for the smaller frame), bring the pages in, and count the fallbacks of the
//! frame drawn after.

use std::sync::Arc;

use super::settings::Settings;
use crate::frame::VirtualPageStats;
use crate::texture::{Sampler, VirtualTexture};
use crate::Result;

/// Feedback pixels span this many frame pixels on a side (when the frame is that large).
pub(super) const FEEDBACK_SCALE: u32 = 2;

/// Checks the samplers (with the settings' overrides), draws the feedback pass through
/// `draw` (given its settings) and updates every texture's cache; returns what moved.
///
/// # Errors
/// [`crate::Error::Unsupported`] for a filter or wrap a virtual texture cannot be read
/// with; `draw`'s errors.
pub(super) fn feedback(
    virtuals: &[(Arc<VirtualTexture>, Vec<Sampler>)],
    settings: &Settings,
    draw: impl FnOnce(&Settings) -> Result<()>,
) -> Result<VirtualPageStats> {
    for (vt, samplers) in virtuals {
        for s in samplers {
            vt.check_sampler(&settings.textures.apply(*s))?;
        }
    }
    // The frame's sample grid (supersampling included), halved on each side.
    let (w, h) = (
        settings.width * settings.ssaa,
        settings.height * settings.ssaa,
    );
    let (fw, fh) = (w.div_ceil(FEEDBACK_SCALE), h.div_ceil(FEEDBACK_SCALE));
    let mut fb = *settings;
    fb.width = fw;
    fb.height = fh;
    fb.ssaa = 1;
    fb.msaa = 1;
    let scale = w as f32 / fw as f32;
    for (vt, _) in virtuals {
        vt.begin_feedback(scale);
    }
    let drawn = draw(&fb);
    let mut stats = VirtualPageStats::default();
    for (vt, _) in virtuals {
        // Ends the feedback mode even when the pass failed.
        let moved = vt.update();
        stats = stats.plus(moved?);
    }
    drawn?;
    Ok(stats)
}

/// `stats` with the reads that fell back since the update.
pub(super) fn with_fallbacks(
    virtuals: &[(Arc<VirtualTexture>, Vec<Sampler>)],
    mut stats: VirtualPageStats,
) -> VirtualPageStats {
    stats.fallback_reads = virtuals.iter().map(|(vt, _)| vt.fallback_reads()).sum();
    stats
}
