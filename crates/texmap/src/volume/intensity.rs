//! MIP and X-ray modes: the maximum or the mean of the values along a ray, as grey (the value
//! range mapped to `[0, 1]`, opaque).
//!
//! Rules:
//! - Every sample of the span is read: no brick is skipped (a maximum or a mean depends on
//!   every value) and there is no early stop.
//! - The mean is summed in `f64`, so a long ray's sum keeps the precision of its last samples.

use glam::Vec4;

use super::marcher::{Marcher, Traced};
use super::params::Mode;
use super::rays::RaySamples;

/// The maximum ([`Mode::Mip`]) or the mean (otherwise) level along the ray, as grey.
pub(crate) fn project(m: &Marcher, s: &RaySamples) -> Traced {
    let n = s.count;
    if n == 0 {
        return Traced::NOTHING;
    }
    let (mut mx, mut sum) = (f32::NEG_INFINITY, 0.0f64);
    for k in 0..n {
        let v = m.value(s.at(k));
        mx = mx.max(v);
        sum += f64::from(v);
    }
    let v = if m.p.mode == Mode::Mip {
        mx
    } else {
        (sum / f64::from(n)) as f32
    };
    let g = (v / 65535.0).clamp(0.0, 1.0);
    Traced {
        color: Vec4::new(g, g, g, 1.0),
        samples: u64::from(n),
    }
}
