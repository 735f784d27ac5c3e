//! Transfer functions: scalar (and gradient magnitude) → colour and opacity.
//!
//! - [`TransferFunction`]: 1D piecewise linear through points `value:r,g,b,a`, clamped beyond
//!   the ends (VTK's default). Opacity is per unit length (VTK's `ScalarOpacityUnitDistance`
//!   = 1 world unit): a step of length `d` uses `1 − (1 − a)^d`.
//! - [`TransferFunction2D`]: a 1D function times an opacity ramp over gradient magnitude.
//! - [`TransferLut`]: a 1D function tabulated over the volume's value range for one step
//!   length (opacity corrected), the marcher's per-sample lookup.
//! - [`PreIntegrated`]: a table over (front, back) value pairs of a ray segment (Engel et al.
//!   2001), so features thinner than a step still show.
//!
//! Colours are display values composited as VTK composites them (see `output`).

use std::path::Path;

use glam::{Vec3, Vec4};

use crate::{Error, Result};

/// Presets: `ct-bone`, `synth`, `mri` are `vtk_volume.py`'s points exactly; `ct-muscle` is
/// 3D Slicer's CT-Muscle; `ct-skin` follows Slicer's CT-Skin (skin surface at −500 HU).
pub const PRESETS: &[(&str, &str)] = &[
    (
        "ct-bone",
        "-3024:0,0,0,0;-16.4458:0.729412,0.254902,0.301961,0;\
         641.385:0.905882,0.815686,0.552941,0.715686;3071:1,1,1,0.705882",
    ),
    (
        "ct-skin",
        "-3024:0,0,0,0;-1000:0.62,0.36,0.18,0;-500:0.88,0.6,0.29,0;\
         -499:0.88,0.6,0.29,1;3071:0.83,0.66,1,1",
    ),
    (
        "ct-muscle",
        "-3024:0,0,0,0;-155.407:0.54902,0.25098,0.14902,0;\
         217.641:0.882353,0.603922,0.290196,0.676471;419.736:1,0.937033,0.954531,0.833333;\
         3071:0.827451,0.658824,1,0.803922",
    ),
    (
        "synth",
        "0:0,0,0,0;45:0,0,0,0;60:0.8,0.45,0.3,0.02;100:0.9,0.6,0.4,0.04;\
         140:0.3,0.5,0.9,0.12;200:1,1,0.9,0.12;235:1,1,0.9,0.2;250:1,0.85,0.5,0.9",
    ),
    (
        "mri",
        "0:0,0,0,0;70:0,0,0,0;110:0.8,0.55,0.45,0.03;170:0.95,0.85,0.75,0.15;255:1,1,1,0.6",
    ),
];

/// A 1D piecewise-linear transfer function: value → straight-alpha RGBA.
#[derive(Clone, Debug, PartialEq)]
pub struct TransferFunction {
    /// `(value, rgba)` sorted by value, at least one point.
    points: Vec<(f32, Vec4)>,
}

impl TransferFunction {
    /// From points (sorted here; at least one).
    ///
    /// # Errors
    /// [`Error::Parameter`] when there is no point or a number is not finite.
    pub fn new(mut points: Vec<(f32, Vec4)>) -> Result<Self> {
        if points.is_empty() {
            return Err(Error::parameter("transfer function has no points"));
        }
        if points.iter().any(|(v, c)| !v.is_finite() || !c.is_finite()) {
            return Err(Error::parameter(
                "transfer function has a non-finite number",
            ));
        }
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        Ok(TransferFunction { points })
    }

    /// A preset by name (see [`PRESETS`]).
    #[must_use]
    pub fn preset(name: &str) -> Option<Self> {
        PRESETS
            .iter()
            .find(|(n, _)| *n == name)
            .and_then(|(_, s)| Self::parse(s).ok())
    }

    /// Parses `value:r,g,b,a;value:r,g,b,a;…` (`vtk_volume.py`'s syntax); newlines also
    /// separate points and `#` starts a comment.
    ///
    /// # Errors
    /// [`Error::Parameter`] naming the bad point.
    pub fn parse(s: &str) -> Result<Self> {
        Self::parse_points(s, Quote::Item)
    }

    /// The points of `s`; a bad point is named by its text (what the user typed) or, for a
    /// file's contents, by its line only: error messages never echo a file.
    fn parse_points(s: &str, quote: Quote) -> Result<Self> {
        let mut pts = Vec::new();
        for (n, line) in s.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("");
            for item in list_items(line) {
                let (v, [r, g, b, a]) = parse_point(item).ok_or_else(|| {
                    Error::parameter(match quote {
                        Quote::Item => {
                            format!("transfer function point \"{item}\" is not value:r,g,b,a")
                        }
                        Quote::Line => format!(
                            "line {}: a transfer function point is not value:r,g,b,a",
                            n + 1
                        ),
                    })
                })?;
                pts.push((v, Vec4::new(r, g, b, a)));
            }
        }
        Self::new(pts)
    }

    /// A preset name, a file holding points, or inline points, in that order.
    ///
    /// # Errors
    /// [`Error::Io`] for an unreadable file; [`Error::Parameter`] or [`Error::Decode`] for
    /// bad points.
    pub fn from_arg(s: &str) -> Result<Self> {
        Self::from_arg_in(s, Path::new(""))
    }

    /// [`Self::from_arg`] with a relative file name resolved from `dir` (a scene file's
    /// folder).
    ///
    /// # Errors
    /// As [`Self::from_arg`].
    pub fn from_arg_in(s: &str, dir: &Path) -> Result<Self> {
        if let Some(tf) = Self::preset(s) {
            return Ok(tf);
        }
        let joined = dir.join(s);
        let p = joined.as_path();
        if !s.contains(':') || p.is_file() {
            if !p.exists() {
                return Err(Error::parameter(format!(
                    "transfer function \"{s}\" is not a preset ({}), a file, or value:r,g,b,a points",
                    PRESETS.iter().map(|p| p.0).collect::<Vec<_>>().join(", ")
                )));
            }
            // Transfer functions are a few lines: 1 MiB is generous.
            let bytes = crate::files::read_bounded(p, 1 << 20)?;
            let text = String::from_utf8_lossy(&bytes);
            return Self::parse_points(&text, Quote::Line)
                .map_err(|e| Error::decode(p, e.to_string()));
        }
        Self::parse(s)
    }

    /// The points, sorted by value.
    #[must_use]
    pub fn points(&self) -> &[(f32, Vec4)] {
        &self.points
    }

    /// Straight-alpha RGBA at `v` (piecewise linear, clamped at the ends).
    #[must_use]
    pub fn eval(&self, v: f32) -> Vec4 {
        piecewise_linear(&self.points, v, Vec4::lerp).unwrap_or(Vec4::ZERO)
    }

    /// The lowest value with non-zero opacity (for iso-values and windows), if any.
    #[must_use]
    pub fn first_opaque_value(&self) -> Option<f32> {
        let p = &self.points;
        let i = p.iter().position(|q| q.1.w > 0.0)?;
        Some(if i == 0 { p[0].0 } else { p[i - 1].0 })
    }
}

/// How a parse error names a bad point.
#[derive(Clone, Copy)]
enum Quote {
    /// By its text (a command-line argument).
    Item,
    /// By its line (a file's contents).
    Line,
}

/// The non-blank items of a `;`-separated list, trimmed.
fn list_items(s: &str) -> impl Iterator<Item = &str> {
    s.split(';').map(str::trim).filter(|t| !t.is_empty())
}

/// One `key:n1,n2,…` point of a list: the key and exactly `N` numbers; `None` when it is
/// malformed.
fn parse_point<const N: usize>(item: &str) -> Option<(f32, [f32; N])> {
    let (key, rest) = item.split_once(':')?;
    let key = key.trim().parse().ok()?;
    let mut numbers = rest.split(',');
    let mut out = [0.0; N];
    for o in &mut out {
        *o = numbers.next()?.trim().parse().ok()?;
    }
    numbers.next().is_none().then_some((key, out))
}

/// Opacity corrected for a step of `step` unit lengths.
#[inline]
#[must_use]
pub fn correct_opacity(a: f32, step: f32) -> f32 {
    1.0 - (1.0 - a.clamp(0.0, 1.0)).powf(step)
}

/// A 2D transfer function: a 1D function of the value whose opacity is multiplied by a
/// piecewise-linear function of the gradient magnitude (world units⁻¹).
#[derive(Clone, Debug, PartialEq)]
pub struct TransferFunction2D {
    pub scalar: TransferFunction,
    /// `(gradient magnitude, opacity factor)` points, sorted.
    pub gradient: Vec<(f32, f32)>,
}

impl TransferFunction2D {
    /// Parses the gradient ramp `g:factor;g:factor;…`.
    ///
    /// # Errors
    /// [`Error::Parameter`] for a malformed point.
    pub fn parse_gradient(s: &str) -> Result<Vec<(f32, f32)>> {
        let mut pts = Vec::new();
        for item in list_items(s) {
            let (g, [f]) = parse_point(item)
                .filter(|(g, [f])| g.is_finite() && f.is_finite())
                .ok_or_else(|| {
                    Error::parameter(format!("gradient opacity point \"{item}\" is not g:factor"))
                })?;
            pts.push((g, f));
        }
        if pts.is_empty() {
            return Err(Error::parameter("gradient opacity has no points"));
        }
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        Ok(pts)
    }

    /// The opacity factor at gradient magnitude `g`.
    #[must_use]
    pub fn gradient_factor(&self, g: f32) -> f32 {
        gradient_factor(&self.gradient, g)
    }

    /// Straight-alpha RGBA at value `v` and gradient magnitude `g`.
    #[must_use]
    pub fn eval(&self, v: f32, g: f32) -> Vec4 {
        let c = self.scalar.eval(v);
        c.truncate().extend(c.w * self.gradient_factor(g))
    }
}

pub(crate) fn gradient_factor(p: &[(f32, f32)], g: f32) -> f32 {
    piecewise_linear(p, g, |a, b, t| a + (b - a) * t).unwrap_or(1.0)
}

/// The piecewise-linear function through `points` (sorted by x) at `x`, clamped at the ends;
/// `None` when there are no points.
fn piecewise_linear<T: Copy>(
    points: &[(f32, T)],
    x: f32,
    lerp: impl Fn(T, T, f32) -> T,
) -> Option<T> {
    let i = points.partition_point(|q| q.0 <= x);
    if i == 0 || i == points.len() {
        return points.get(i.saturating_sub(1)).map(|q| q.1);
    }
    let (a, b) = (points[i - 1], points[i]);
    let t = if b.0 > a.0 {
        (x - a.0) / (b.0 - a.0)
    } else {
        1.0
    };
    Some(lerp(a.1, b.1, t))
}

/// The nearest of `n` table entries for value `v`, the first at `lo` and `scale` entries per
/// value unit (clamped to the table).
#[inline(always)]
fn nearest_entry(v: f32, lo: f32, scale: f32, n: usize) -> usize {
    (((v - lo) * scale + 0.5).max(0.0) as usize).min(n - 1)
}

/// Number of entries of a [`TransferLut`].
pub const LUT_SIZE: usize = 4096;

/// A 1D transfer function tabulated over `[lo, hi]` for one step length: straight colour
/// and opacity already corrected for the step.
#[derive(Clone, Debug)]
pub struct TransferLut {
    pub lo: f32,
    /// Entries per value unit.
    pub scale: f32,
    /// `[r, g, b, a_step]`.
    pub table: Vec<Vec4>,
    /// `nonzero_prefix[i]` = entries with opacity > 0 among `table[..i]` (for empty-space
    /// tests over a value interval).
    nonzero_prefix: Vec<u32>,
}

impl TransferLut {
    /// Tabulates `tf` over `range` for a step of `step` world units.
    #[must_use]
    pub fn new(tf: &TransferFunction, range: (f32, f32), step: f32) -> Self {
        let (lo, hi) = range;
        let span = (hi - lo).max(1e-6);
        let n = LUT_SIZE;
        let scale = (n - 1) as f32 / span;
        let table: Vec<Vec4> = (0..n)
            .map(|i| {
                let v = lo + i as f32 / scale;
                let c = tf.eval(v);
                c.truncate().extend(correct_opacity(c.w, step))
            })
            .collect();
        let mut nonzero_prefix = Vec::with_capacity(n + 1);
        let mut acc = 0u32;
        nonzero_prefix.push(0);
        for c in &table {
            acc += u32::from(c.w > 0.0);
            nonzero_prefix.push(acc);
        }
        TransferLut {
            lo,
            scale,
            table,
            nonzero_prefix,
        }
    }

    /// Table index of value `v` (nearest entry, clamped).
    #[inline(always)]
    #[must_use]
    pub fn index(&self, v: f32) -> usize {
        nearest_entry(v, self.lo, self.scale, self.table.len())
    }

    /// `[r, g, b, a_step]` at value `v`.
    #[inline(always)]
    #[must_use]
    pub fn get(&self, v: f32) -> Vec4 {
        self.table[self.index(v)]
    }

    /// True when every value in `[a, b]` is transparent.
    #[must_use]
    pub fn is_transparent(&self, a: f32, b: f32) -> bool {
        let (i, j) = (self.index(a), self.index(b));
        self.nonzero_prefix[j + 1] == self.nonzero_prefix[i]
    }
}

/// Pre-integrated classification: for a ray segment of one step whose ends have values
/// `(sf, sb)`, the segment's premultiplied colour and opacity, from prefix integrals of the
/// extinction and emission (Engel, Kraus, Ertl 2001; self-attenuation inside the segment
/// neglected, as there).
#[derive(Clone, Debug)]
pub struct PreIntegrated {
    pub lo: f32,
    pub scale: f32,
    pub n: usize,
    /// `n × n`, row = front value, premultiplied `[r, g, b, a]`.
    pub table: Vec<Vec4>,
}

impl PreIntegrated {
    /// Builds the table over `range` with `n` bins for segments of `step` world units.
    #[must_use]
    pub fn new(tf: &TransferFunction, range: (f32, f32), step: f32, n: usize) -> Self {
        let n = n.max(2);
        let (lo, hi) = range;
        let span = (hi - lo).max(1e-6);
        let scale = (n - 1) as f32 / span;
        // Integrate over a fine grid between bins: extinction τ = −ln(1 − a) per unit length.
        const SUB: usize = 8;
        let fine = (n - 1) * SUB + 1;
        let mut tau_int = vec![0.0f64; fine];
        let mut col_int = vec![Vec3::ZERO.as_dvec3(); fine];
        let ext = |v: f32| {
            let c = tf.eval(v);
            let a = c.w.clamp(0.0, 0.999_999);
            (-(1.0 - a as f64).ln(), c.truncate().as_dvec3())
        };
        let dv = span as f64 / (fine - 1) as f64;
        let mut prev = ext(lo);
        for k in 1..fine {
            let cur = ext(lo + (k as f64 * dv) as f32);
            tau_int[k] = tau_int[k - 1] + 0.5 * (prev.0 + cur.0) * dv;
            col_int[k] = col_int[k - 1] + (prev.1 * prev.0 + cur.1 * cur.0) * 0.5 * dv;
            prev = cur;
        }
        let mut table = Vec::with_capacity(n * n);
        for f in 0..n {
            for b in 0..n {
                let (i, j) = (f * SUB, b * SUB);
                let c = if i == j {
                    let (t, col) = ext(lo + f as f32 / scale);
                    let a = 1.0 - (-t * step as f64).exp();
                    (col * a).extend(a)
                } else {
                    let ds = (j as f64 - i as f64) * dv;
                    let t = (tau_int[j] - tau_int[i]) / ds;
                    let col = (col_int[j] - col_int[i]) / ds;
                    let a = 1.0 - (-t * step as f64).exp();
                    // Colour weighted by extinction, normalised so a flat segment gives c·a.
                    let c = if t > 1e-12 { col / t * a } else { col * 0.0 };
                    c.extend(a)
                };
                table.push(c.as_vec4());
            }
        }
        PreIntegrated {
            lo,
            scale,
            n,
            table,
        }
    }

    /// Premultiplied RGBA of a segment from value `sf` to `sb`.
    #[inline(always)]
    #[must_use]
    pub fn get(&self, sf: f32, sb: f32) -> Vec4 {
        let idx = |v: f32| nearest_entry(v, self.lo, self.scale, self.n);
        self.table[idx(sf) * self.n + idx(sb)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn synth_preset_matches_vtk_volume_py() {
        let tf = TransferFunction::preset("synth").expect("preset");
        assert_eq!(tf.points().len(), 8);
        assert_eq!(tf.points()[7], (250.0, Vec4::new(1.0, 0.85, 0.5, 0.9)));
        // Halfway between 140 and 200: colour halfway, opacity 0.12.
        let c = tf.eval(170.0);
        assert!(
            (c - Vec4::new(0.65, 0.75, 0.9, 0.12)).abs().max_element() < 1e-6,
            "{c}"
        );
        // Clamped beyond the ends.
        assert_eq!(tf.eval(300.0), tf.eval(250.0));
        assert_eq!(tf.eval(-5.0), Vec4::ZERO);
    }

    /// Every preset's points, pinned: `ct-bone`, `synth` and `mri` as `vtk_volume.py`'s
    /// `PRESETS` (value, r, g, b, a); `ct-muscle` and `ct-skin` as texmap defines them (after
    /// 3D Slicer's CT-Muscle and CT-Skin). A changed point fails here (the peer's own file is compared in `tests/volume.rs` when present).
    #[test]
    fn preset_points_are_pinned() {
        let expected: &[(&str, &[[f32; 5]])] = &[
            (
                "ct-bone",
                &[
                    [-3024.0, 0.0, 0.0, 0.0, 0.0],
                    [-16.4458, 0.729412, 0.254902, 0.301961, 0.0],
                    [641.385, 0.905882, 0.815686, 0.552941, 0.715686],
                    [3071.0, 1.0, 1.0, 1.0, 0.705882],
                ],
            ),
            (
                "synth",
                &[
                    [0.0, 0.0, 0.0, 0.0, 0.0],
                    [45.0, 0.0, 0.0, 0.0, 0.0],
                    [60.0, 0.8, 0.45, 0.3, 0.02],
                    [100.0, 0.9, 0.6, 0.4, 0.04],
                    [140.0, 0.3, 0.5, 0.9, 0.12],
                    [200.0, 1.0, 1.0, 0.9, 0.12],
                    [235.0, 1.0, 1.0, 0.9, 0.2],
                    [250.0, 1.0, 0.85, 0.5, 0.9],
                ],
            ),
            (
                "mri",
                &[
                    [0.0, 0.0, 0.0, 0.0, 0.0],
                    [70.0, 0.0, 0.0, 0.0, 0.0],
                    [110.0, 0.8, 0.55, 0.45, 0.03],
                    [170.0, 0.95, 0.85, 0.75, 0.15],
                    [255.0, 1.0, 1.0, 1.0, 0.6],
                ],
            ),
            (
                "ct-muscle",
                &[
                    [-3024.0, 0.0, 0.0, 0.0, 0.0],
                    [-155.407, 0.54902, 0.25098, 0.14902, 0.0],
                    [217.641, 0.882353, 0.603922, 0.290196, 0.676471],
                    [419.736, 1.0, 0.937033, 0.954531, 0.833333],
                    [3071.0, 0.827451, 0.658824, 1.0, 0.803922],
                ],
            ),
            (
                "ct-skin",
                &[
                    [-3024.0, 0.0, 0.0, 0.0, 0.0],
                    [-1000.0, 0.62, 0.36, 0.18, 0.0],
                    [-500.0, 0.88, 0.6, 0.29, 0.0],
                    [-499.0, 0.88, 0.6, 0.29, 1.0],
                    [3071.0, 0.83, 0.66, 1.0, 1.0],
                ],
            ),
        ];
        assert_eq!(expected.len(), PRESETS.len(), "a preset is not pinned");
        for (name, points) in expected {
            let tf = TransferFunction::preset(name).expect("preset");
            let got: Vec<[f32; 5]> = tf
                .points()
                .iter()
                .map(|(v, c)| [*v, c.x, c.y, c.z, c.w])
                .collect();
            assert_eq!(&got[..], *points, "{name}");
        }
    }

    #[test]
    fn every_preset_parses() {
        for (name, _) in PRESETS {
            assert!(TransferFunction::preset(name).is_some(), "{name}");
        }
    }

    #[test]
    fn inline_syntax_errors_name_the_point() {
        let e = TransferFunction::parse("0:0,0,0,0;10:1,1,1").unwrap_err();
        assert!(e.to_string().contains("10:1,1,1"), "{e}");
        assert!(TransferFunction::parse("").is_err());
        assert!(TransferFunction::parse("x:1,1,1,1").is_err());
    }

    #[test]
    fn gradient_syntax_errors_name_the_point() {
        let g = TransferFunction2D::parse_gradient(" 50:1 ; 0:0 ;").unwrap();
        assert_eq!(g, vec![(0.0, 0.0), (50.0, 1.0)]);
        for bad in ["0:0;10:1,2", "0:0;10:", "0:0;x:1", "0:0;10:inf"] {
            let e = TransferFunction2D::parse_gradient(bad).unwrap_err();
            let item = bad.rsplit(';').next().unwrap();
            assert!(e.to_string().contains(item), "{bad}: {e}");
        }
        assert!(TransferFunction2D::parse_gradient(" ; ").is_err());
    }

    #[test]
    fn points_take_exactly_their_numbers() {
        assert_eq!(
            parse_point::<4>(" 3 : 1, 2 ,3,4"),
            Some((3.0, [1.0, 2.0, 3.0, 4.0]))
        );
        assert_eq!(parse_point::<4>("3:1,2,3"), None);
        assert_eq!(parse_point::<4>("3:1,2,3,4,"), None);
        assert_eq!(parse_point::<1>("3:1"), Some((3.0, [1.0])));
        assert_eq!(parse_point::<1>("3"), None);
    }

    #[test]
    fn opacity_correction_composes() {
        // Two half steps make one whole step.
        let a = 0.3;
        let h = correct_opacity(a, 0.5);
        assert!((1.0 - (1.0 - h) * (1.0 - h) - a).abs() < 1e-6);
    }

    #[test]
    fn lut_transparency_test_is_conservative() {
        let tf = TransferFunction::preset("synth").expect("preset");
        let lut = TransferLut::new(&tf, (0.0, 255.0), 0.5);
        assert!(lut.is_transparent(0.0, 44.0));
        assert!(!lut.is_transparent(0.0, 46.0));
        assert!(!lut.is_transparent(200.0, 210.0));
    }

    #[test]
    fn preintegrated_diagonal_equals_point_classification() {
        let tf = TransferFunction::preset("synth").expect("preset");
        let pi = PreIntegrated::new(&tf, (0.0, 255.0), 0.5, 256);
        let c = pi.get(170.0, 170.0);
        let a = correct_opacity(0.12, 0.5);
        assert!((c.w - a).abs() < 2e-3, "{c}");
        // A thin feature between the ends still shows: 0 → 255 crosses every opaque band.
        assert!(pi.get(0.0, 255.0).w > 0.0);
    }
}
