//! Image comparison metrics: PSNR, RMSE and SSIM over 8-bit RGB images, optionally masked.
//!
//! Definitions follow `../shared/peers/metrics.py` (scikit-image's defaults) so figures from
//! `texmap compare` and from the peers' script agree: data range 255; SSIM with a 7×7 uniform
//! window, sample covariance, K1 = 0.01, K2 = 0.03, averaged over channels, then over the
//! (masked) pixels, with the window's border of 3 pixels reflected like scipy's filters.

/// Comparison of two images.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comparison {
    /// Peak signal-to-noise ratio in dB (infinite for identical images).
    pub psnr_db: f64,
    /// Root mean squared error in 8-bit units.
    pub rmse: f64,
    /// Mean structural similarity.
    pub ssim: f64,
    /// Pixels compared.
    pub pixels: usize,
}

/// Compares two `w`×`h` RGB8 images over the pixels where `mask` (if any) is true.
///
/// # Panics
/// If the buffers are not `w·h·3` bytes or the mask not `w·h` long.
#[must_use]
pub fn compare_rgb8(a: &[u8], b: &[u8], w: usize, h: usize, mask: Option<&[bool]>) -> Comparison {
    assert_eq!(a.len(), w * h * 3);
    assert_eq!(b.len(), w * h * 3);
    let inside = |i: usize| mask.is_none_or(|m| m[i]);
    let mut se = 0.0f64;
    let mut n = 0usize;
    for i in 0..w * h {
        if inside(i) {
            for c in 0..3 {
                let d = a[i * 3 + c] as f64 - b[i * 3 + c] as f64;
                se += d * d;
            }
            n += 1;
        }
    }
    let mse = if n > 0 { se / (n * 3) as f64 } else { 0.0 };
    let psnr_db = if mse > 0.0 {
        10.0 * (255.0f64 * 255.0 / mse).log10()
    } else {
        f64::INFINITY
    };
    let map = ssim_map(a, b, w, h);
    let (mut s, mut k) = (0.0, 0usize);
    for (i, v) in map.iter().enumerate() {
        if inside(i) {
            s += v;
            k += 1;
        }
    }
    Comparison {
        psnr_db,
        rmse: mse.sqrt(),
        ssim: if k > 0 { s / k as f64 } else { 1.0 },
        pixels: n,
    }
}

/// Per-pixel SSIM averaged over the three channels.
fn ssim_map(a: &[u8], b: &[u8], w: usize, h: usize) -> Vec<f64> {
    const R: isize = 3;
    let np = 49.0f64;
    let cov_norm = np / (np - 1.0);
    let (c1, c2) = ((0.01f64 * 255.0).powi(2), (0.03f64 * 255.0).powi(2));
    // scipy's "reflect" mode: (d c b a | a b c d | d c b a).
    let reflect = |i: isize, n: usize| -> usize {
        let n = n as isize;
        let mut i = i;
        loop {
            if i < 0 {
                i = -i - 1;
            } else if i >= n {
                i = 2 * n - i - 1;
            } else {
                return i as usize;
            }
        }
    };
    let mut out = vec![0.0; w * h];
    for c in 0..3 {
        // Box means of x, y, x², y², xy by separable sums.
        let fields: [Box<dyn Fn(usize) -> f64>; 5] = [
            Box::new(|i| a[i * 3 + c] as f64),
            Box::new(|i| b[i * 3 + c] as f64),
            Box::new(|i| (a[i * 3 + c] as f64).powi(2)),
            Box::new(|i| (b[i * 3 + c] as f64).powi(2)),
            Box::new(|i| a[i * 3 + c] as f64 * b[i * 3 + c] as f64),
        ];
        let means: Vec<Vec<f64>> = fields
            .iter()
            .map(|f| {
                let mut rows = vec![0.0; w * h];
                for y in 0..h {
                    for x in 0..w {
                        rows[y * w + x] = (-R..=R)
                            .map(|d| f(y * w + reflect(x as isize + d, w)))
                            .sum();
                    }
                }
                let mut m = vec![0.0; w * h];
                for y in 0..h {
                    for x in 0..w {
                        m[y * w + x] = (-R..=R)
                            .map(|d| rows[reflect(y as isize + d, h) * w + x])
                            .sum::<f64>()
                            / np;
                    }
                }
                m
            })
            .collect();
        for i in 0..w * h {
            let (ux, uy) = (means[0][i], means[1][i]);
            let vx = cov_norm * (means[2][i] - ux * ux);
            let vy = cov_norm * (means[3][i] - uy * uy);
            let vxy = cov_norm * (means[4][i] - ux * uy);
            let s = ((2.0 * ux * uy + c1) * (2.0 * vxy + c2))
                / ((ux * ux + uy * uy + c1) * (vx + vy + c2));
            out[i] += s / 3.0;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_are_perfect() {
        let a: Vec<u8> = (0..16 * 12 * 3).map(|i| (i * 31 % 256) as u8).collect();
        let c = compare_rgb8(&a, &a, 16, 12, None);
        assert!(c.psnr_db.is_infinite());
        assert_eq!(c.rmse, 0.0);
        assert!((c.ssim - 1.0).abs() < 1e-12);
    }

    #[test]
    fn constant_offset_has_known_psnr() {
        let a = vec![100u8; 8 * 8 * 3];
        let b = vec![110u8; 8 * 8 * 3];
        let c = compare_rgb8(&a, &b, 8, 8, None);
        assert!((c.rmse - 10.0).abs() < 1e-12);
        assert!((c.psnr_db - 20.0 * (25.5f64).log10()).abs() < 1e-9);
    }

    #[test]
    fn mask_restricts_the_pixels() {
        let a = vec![0u8; 4 * 4 * 3];
        let mut b = a.clone();
        b[0] = 255;
        let mut mask = vec![true; 16];
        mask[0] = false;
        let c = compare_rgb8(&a, &b, 4, 4, Some(&mask));
        assert_eq!(c.rmse, 0.0);
        assert_eq!(c.pixels, 15);
    }
}
