//! A transfer function chosen from a scan's own values, for a scan rendered without one.
//!
//! - Values in Hounsfield units (air at −1000: the minimum at most −500 and the maximum at
//!   least 300) get the `ct-bone` preset.
//! - Anything else (MRI, microscopy, 8- and 16-bit data) is read from its histogram: Otsu's
//!   threshold `t` (the split of 256 bins that maximises the between-class variance) parts
//!   the background from the object, and `p` is the 99th percentile of the values above it.
//!   Below `t` everything is transparent; from `t` the opacity rises to 0.05 per unit length
//!   halfway to `p`, 0.25 at `p` and 0.6 at the maximum, in warm greys that lighten with the
//!   value — the object's surface first, its brightest parts showing through.

use glam::Vec4;

use super::grid::Volume;
use super::transfer::TransferFunction;

/// How the names of chosen transfer functions begin.
pub const CHOSEN_PREFIX: &str = "chosen: ";

/// The transfer function for `vol` (see the module docs) and a name for listings (beginning
/// with [`CHOSEN_PREFIX`]).
#[must_use]
pub fn transfer_for(vol: &Volume) -> (TransferFunction, String) {
    let (lo, hi) = vol.range();
    if lo <= -500.0 && hi >= 300.0 {
        if let Some(tf) = TransferFunction::preset("ct-bone") {
            return (tf, format!("{CHOSEN_PREFIX}ct-bone (Hounsfield units)"));
        }
    }
    let mut bins = [0u64; 256];
    for &q in vol.quantized() {
        bins[usize::from(q >> 8)] += 1;
    }
    let value = |bin: f32| lo + (hi - lo) * bin / 256.0;
    let t_bin = otsu(&bins);
    let t = value(t_bin as f32 + 1.0);
    // The 99th percentile of the bins above the threshold.
    let above: u64 = bins[t_bin + 1..].iter().sum();
    let mut seen = 0u64;
    let mut p_bin = 255;
    for (k, &n) in bins.iter().enumerate().skip(t_bin + 1) {
        seen += n;
        if above > 0 && seen * 100 >= above * 99 {
            p_bin = k;
            break;
        }
    }
    let p = value(p_bin as f32 + 1.0).max(t + (hi - t) * 0.5).min(hi);
    let mid = 0.5 * (t + p);
    let mut points = vec![
        (lo, Vec4::ZERO),
        (t, Vec4::new(0.55, 0.3, 0.25, 0.0)),
        (mid, Vec4::new(0.85, 0.55, 0.45, 0.05)),
        (p, Vec4::new(0.95, 0.85, 0.75, 0.25)),
        (hi, Vec4::new(1.0, 1.0, 1.0, 0.6)),
    ];
    // Values that coincide (a flat or two-valued scan) keep the first point of each.
    points.dedup_by(|b, a| b.0 <= a.0);
    let tf = TransferFunction::new(points).expect("finite, sorted points");
    (
        tf,
        format!("{CHOSEN_PREFIX}auto (histogram: threshold {t:.4}, 99th percentile {p:.4})"),
    )
}

/// Otsu's threshold over `bins`: the last bin of the lower class.
fn otsu(bins: &[u64; 256]) -> usize {
    let total: f64 = bins.iter().map(|&n| n as f64).sum();
    let sum: f64 = bins
        .iter()
        .enumerate()
        .map(|(k, &n)| k as f64 * n as f64)
        .sum();
    let (mut w0, mut sum0) = (0.0f64, 0.0f64);
    let (mut best, mut best_k) = (-1.0f64, 0usize);
    for (k, &n) in bins.iter().enumerate().take(255) {
        w0 += n as f64;
        sum0 += k as f64 * n as f64;
        let w1 = total - w0;
        if w0 == 0.0 || w1 == 0.0 {
            continue;
        }
        let (m0, m1) = (sum0 / w0, (sum - sum0) / w1);
        let between = w0 * w1 * (m0 - m1) * (m0 - m1);
        if between > best {
            (best, best_k) = (between, k);
        }
    }
    best_k
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;

    fn volume(values: impl Fn(u32) -> f32) -> Volume {
        let v = (0..16 * 16 * 16).map(values).collect();
        Volume::from_scalars([16; 3], Mat4::IDENTITY, v).unwrap()
    }

    #[test]
    fn hounsfield_units_get_the_ct_preset() {
        let ct = volume(|i| {
            if i % 3 == 0 {
                -1000.0
            } else {
                40.0 + (i % 700) as f32
            }
        });
        let (tf, name) = transfer_for(&ct);
        assert!(name.starts_with("chosen: ct-bone"), "{name}");
        assert_eq!(tf, TransferFunction::preset("ct-bone").unwrap());
    }

    #[test]
    fn a_two_class_scan_hides_its_background_and_shows_its_object() {
        // 70% background around 10, 30% object around 180 (8-bit units).
        let scan = volume(|i| {
            let jitter = (i * 7919 % 13) as f32;
            if i % 10 < 7 {
                5.0 + jitter
            } else {
                170.0 + jitter
            }
        });
        let (tf, name) = transfer_for(&scan);
        assert!(name.starts_with("chosen: auto"), "{name}");
        for v in [5.0, 12.0, 17.0] {
            assert_eq!(tf.eval(v).w, 0.0, "background {v}");
        }
        for v in [175.0, 182.0] {
            assert!(tf.eval(v).w > 0.0, "object {v}");
        }
        // The threshold lies between the classes.
        let first = tf.first_opaque_value().unwrap();
        assert!((17.0..=170.0).contains(&first), "{first}");
    }

    #[test]
    fn a_flat_scan_still_gets_a_valid_function() {
        let (tf, _) = transfer_for(&volume(|_| 7.0));
        assert!(tf.eval(7.0).is_finite());
    }
}
