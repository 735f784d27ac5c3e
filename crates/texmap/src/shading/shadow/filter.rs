//! The filters a lookup runs over a map — one texel, percentage-closer boxes, a Poisson disc,
//! and percentage-closer soft shadows — each returning the lit fraction in [0, 1].
//!
//! Every compare is `receiver depth − bias ≤ map depth` at one texel, with the receiver's
//! depth taken on its tangent plane at that texel's centre ([`Receiver::du`], `dv`), so a
//! wide kernel on a sloped receiver does not compare against texels the surface itself
//! covers nearer the light. PCF is bilinear (GL's `sampler2DShadow` with `LINEAR`, each tap
//! four compares weighted by the position inside the texel) and the N×N box of taps one
//! texel apart reads an (N+1)² window once with separable weights. The Poisson discs are
//! fixed (no per-pixel rotation, so the image is a function of the position alone); PCSS
//! (Fernando 2005) searches a disc for blockers, estimates the penumbra from their mean depth
//! and the light's size, and filters a disc of that radius.

use glam::Vec4;

use super::map::{Receiver, ShadowMap};
use super::{LightExtent, ShadowFilter};

/// 16 points of a Poisson disc in the unit disc (best-candidate, minimum distance 0.44,
/// centred), for the Poisson filter and the PCSS blocker search.
const POISSON_16: [[f32; 2]; 16] = [
    [-0.0299, -0.0038],
    [0.3099, 0.3627],
    [0.3837, -0.3184],
    [-0.5135, 0.0677],
    [0.0078, -0.5438],
    [-0.1192, 0.5451],
    [-0.4189, -0.4047],
    [0.6376, 0.0478],
    [0.3526, -0.8312],
    [0.8738, 0.4272],
    [0.9069, -0.3546],
    [0.2829, 0.9358],
    [-0.9143, 0.3748],
    [-0.9499, -0.2861],
    [-0.4185, 0.9018],
    [-0.3911, -0.9204],
];

/// 32 points of a Poisson disc (minimum distance 0.28, centred), for the PCSS filter.
const POISSON_32: [[f32; 2]; 32] = [
    [0.0322, -0.0878],
    [-0.2599, 0.0386],
    [0.2667, 0.1464],
    [-0.0719, 0.3400],
    [0.0480, -0.4205],
    [-0.3700, 0.3405],
    [-0.4910, -0.1795],
    [0.2140, 0.4779],
    [0.3690, -0.3839],
    [-0.1906, -0.5645],
    [-0.6011, 0.0918],
    [0.6294, 0.1268],
    [0.6380, -0.1870],
    [0.5339, 0.4099],
    [-0.4901, -0.4640],
    [-0.2468, 0.6374],
    [0.1754, -0.6745],
    [0.0139, 0.7680],
    [-0.8581, -0.2600],
    [-0.6162, 0.6584],
    [-0.3512, -0.8495],
    [-0.9265, 0.0892],
    [-0.8562, 0.4118],
    [-0.6893, -0.6726],
    [0.7925, -0.5533],
    [-0.3084, 0.9279],
    [0.0175, -0.9811],
    [0.9448, -0.2767],
    [0.5869, -0.7916],
    [0.3561, 0.9266],
    [0.7571, 0.6487],
    [0.9519, 0.3063],
];

/// Radius of the Poisson filter's disc, texels (its taps cover about the 5×5 box's area).
pub const POISSON_RADIUS: f32 = 2.5;

/// The largest PCSS blocker search and filter radius, texels.
pub const MAX_PCSS_RADIUS: f32 = 24.0;

/// The smallest PCSS filter radius, texels (where a blocker touches the receiver).
pub const MIN_PCSS_RADIUS: f32 = 1.0;

impl LightExtent {
    /// The half-width in map texels of the penumbra a blocker at depth `blocker` casts on
    /// the receiver (similar triangles between the light, the blocker and the receiver).
    #[inline]
    fn penumbra(self, r: &Receiver, blocker: f32) -> f32 {
        let gap = (r.depth - blocker).max(0.0);
        match self {
            LightExtent::Angle { tan_half } => gap * tan_half / r.texel,
            LightExtent::Radius { radius } => radius * gap / (blocker.max(1e-6) * r.texel),
        }
    }
}

/// The lit fraction at receiver `r` of `map` with `filter`, the receiver's depth lowered by
/// `bias` (world units); `extent` sizes PCSS penumbrae.
#[inline]
pub(super) fn lit_fraction(
    map: &ShadowMap,
    r: &Receiver,
    bias: f32,
    filter: ShadowFilter,
    extent: LightExtent,
) -> f32 {
    match filter {
        ShadowFilter::Hard => lit(map, r, bias, r.u.floor() as i32, r.v.floor() as i32),
        ShadowFilter::Pcf3 => pcf3(map, r, bias),
        ShadowFilter::Pcf5 => pcf_box::<5>(map, r, bias),
        ShadowFilter::Poisson => disc(map, r, bias, &POISSON_16, POISSON_RADIUS),
        ShadowFilter::Pcss => pcss(map, r, bias, extent),
    }
}

/// The receiver's plane depth at the centre of texel `(i, j)`, lowered by `bias`.
#[inline(always)]
fn plane_depth(r: &Receiver, bias: f32, i: i32, j: i32) -> f32 {
    r.depth - bias + r.du * (i as f32 + 0.5 - r.u) + r.dv * (j as f32 + 0.5 - r.v)
}

/// 1 when texel `(i, j)` does not hide the receiver, else 0.
#[inline(always)]
fn lit(map: &ShadowMap, r: &Receiver, bias: f32, i: i32, j: i32) -> f32 {
    if plane_depth(r, bias, i, j) <= map.depth_at(i, j) {
        1.0
    } else {
        0.0
    }
}

/// A bilinear tap at texel coordinates `(x, y)`: the four nearest texels' compares weighted
/// by the position between their centres.
#[inline(always)]
fn bilinear(map: &ShadowMap, r: &Receiver, bias: f32, x: f32, y: f32) -> f32 {
    let (fx, fy) = (x - 0.5, y - 0.5);
    let (i, j) = (fx.floor(), fy.floor());
    let (a, b) = (fx - i, fy - j);
    let (i, j) = (i as i32, j as i32);
    let top = lit(map, r, bias, i, j) * (1.0 - a) + lit(map, r, bias, i + 1, j) * a;
    let bottom = lit(map, r, bias, i, j + 1) * (1.0 - a) + lit(map, r, bias, i + 1, j + 1) * a;
    top * (1.0 - b) + bottom * b
}

/// N×N bilinear taps one texel apart centred on the receiver: the (N+1)² texels around it,
/// weighted `1 − f, 1, …, 1, f` along each axis (`f` the position inside the texel), over N².
#[inline(always)]
fn pcf_box<const N: usize>(map: &ShadowMap, r: &Receiver, bias: f32) -> f32 {
    let (fx, fy) = (r.u - 0.5, r.v - 0.5);
    let (ix, iy) = (fx.floor(), fy.floor());
    let (a, b) = (fx - ix, fy - iy);
    let k = (N as i32 - 1) / 2;
    let (i0, j0) = (ix as i32 - k, iy as i32 - k);
    let weight = |t: usize, f: f32| {
        if t == 0 {
            1.0 - f
        } else if t == N {
            f
        } else {
            1.0
        }
    };
    let mut sum = 0.0;
    for y in 0..=N {
        let mut row = 0.0;
        for x in 0..=N {
            row += weight(x, a) * lit(map, r, bias, i0 + x as i32, j0 + y as i32);
        }
        sum += weight(y, b) * row;
    }
    sum / (N * N) as f32
}

/// [`pcf_box`] for N = 3 in lanes: each of the window's four rows is one load of four texels
/// compared with the receiver plane's four depths at once (the window inside the map; at its
/// edges, the clamped scalar box).
#[inline(always)]
fn pcf3(map: &ShadowMap, r: &Receiver, bias: f32) -> f32 {
    let (fx, fy) = (r.u - 0.5, r.v - 0.5);
    let (ix, iy) = (fx.floor(), fy.floor());
    let (a, b) = (fx - ix, fy - iy);
    let (i0, j0) = (ix as i32 - 1, iy as i32 - 1);
    let n = map.size as i32;
    if !(i0 >= 0 && j0 >= 0 && i0 + 4 <= n && j0 + 4 <= n) {
        return pcf_box::<3>(map, r, bias);
    }
    // The plane's depth at the centre of texel (i0, j0): (i0 + ½) − u = −1 − a.
    let corner = r.depth - bias - r.du * (1.0 + a) - r.dv * (1.0 + b);
    let mut plane = Vec4::splat(corner) + Vec4::new(0.0, 1.0, 2.0, 3.0) * r.du;
    let step = Vec4::splat(r.dv);
    let wx = Vec4::new(1.0 - a, 1.0, 1.0, a);
    let wy = [1.0 - b, 1.0, 1.0, b];
    let (i0, j0) = (i0 as usize, j0 as usize);
    // The tiles may tell every compare at once: the same sum as the loop's, without a read.
    match window_known(map, (i0, j0), corner, r.du, r.dv) {
        Some(true) => {
            let all = wx.element_sum();
            let mut sum = 0.0;
            for wy in wy {
                sum += wy * all;
            }
            return sum * (1.0 / 9.0);
        }
        Some(false) => return 0.0,
        None => {}
    }
    let mut sum = 0.0;
    for (y, wy) in wy.iter().enumerate() {
        let texels = map.four_at(i0, j0 + y);
        let lit = Vec4::select(plane.cmple(texels), wx, Vec4::ZERO);
        sum += wy * lit.element_sum();
        plane += step;
    }
    sum * (1.0 / 9.0)
}

/// Whether the receiver plane (`corner` at the centre of texel `at`, `du` and `dv` per
/// texel) passes the compare at every texel of the 4×4 window from `at` (`Some(true)`) or
/// at none (`Some(false)`), as far as the map's tiles tell; `None` when they do not.
///
/// Lit: for each tile the window touches, the plane's greatest depth over the window is at
/// most the tile's least depth, or its greatest height over the tile's fitted plane is at
/// least `below` under it. Shadowed: the plane's least depth is beyond every tile's greatest.
/// Each bound keeps a margin of 10⁻⁵ of the magnitudes involved, far above the rounding of
/// the loop's plane depths, so a known window gives the loop's answer exactly.
#[inline(always)]
fn window_known(
    map: &ShadowMap,
    at: (usize, usize),
    corner: f32,
    du: f32,
    dv: f32,
) -> Option<bool> {
    let reach = 3.0 * (du.abs() + dv.abs());
    let m1 = (corner.abs() + reach) * 1e-5;
    let (near, far) = (corner + reach + m1, corner - reach - m1);
    let (lit, dark) = map.fold_tiles(at, 4, (true, true), |(lit, dark), t, x, y| {
        let lit = lit
            && (near <= t.lo || {
                // The window's greatest height over the tile's plane.
                let g = corner - (t.c + t.a * x + t.b * y)
                    + 3.0 * ((du - t.a).max(0.0) + (dv - t.b).max(0.0));
                let m2 = (corner.abs() + reach + t.c.abs() + 12.0 * (t.a.abs() + t.b.abs())) * 1e-5;
                g + t.below + m2 <= 0.0
            });
        (lit, dark && far > t.hi)
    })?;
    if lit {
        Some(true)
    } else if dark {
        Some(false)
    } else {
        None
    }
}

/// The mean of bilinear taps at the points of `disc` scaled to `radius` texels.
#[inline]
fn disc(map: &ShadowMap, r: &Receiver, bias: f32, disc: &[[f32; 2]], radius: f32) -> f32 {
    let sum: f32 = disc
        .iter()
        .map(|[x, y]| bilinear(map, r, bias, r.u + radius * x, r.v + radius * y))
        .sum();
    sum / disc.len() as f32
}

/// Percentage-closer soft shadows: the mean depth of the blockers in the disc where the
/// nearest possible blocker (at the map's near plane) would cast its penumbra, then a disc
/// filter as wide as the penumbra those blockers cast; 1 where there is no blocker.
fn pcss(map: &ShadowMap, r: &Receiver, bias: f32, extent: LightExtent) -> f32 {
    let search = extent
        .penumbra(r, map.near)
        .clamp(MIN_PCSS_RADIUS, MAX_PCSS_RADIUS);
    let (mut sum, mut count) = (0.0f32, 0u32);
    for [x, y] in POISSON_16 {
        let i = (r.u + search * x).floor() as i32;
        let j = (r.v + search * y).floor() as i32;
        let z = map.depth_at(i, j);
        if z < plane_depth(r, bias, i, j) {
            sum += z;
            count += 1;
        }
    }
    if count == 0 {
        return 1.0;
    }
    let radius = extent
        .penumbra(r, sum / count as f32)
        .clamp(MIN_PCSS_RADIUS, MAX_PCSS_RADIUS);
    disc(map, r, bias, &POISSON_32, radius)
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Vec2, Vec3};

    use super::super::map::MapView;
    use super::*;

    /// A 16² map over [−8, 8]² seen from above, caster depth `z` where `covered(i, j)`.
    fn map(covered: impl Fn(i32, i32) -> bool, z: f32) -> ShadowMap {
        let n = 16;
        let mut m = ShadowMap {
            view_from_world: Mat4::look_at_rh(Vec3::new(0.0, 10.0, 0.0), Vec3::ZERO, -Vec3::Z),
            view: MapView::Orthographic {
                min: Vec2::splat(-8.0),
                max: Vec2::splat(8.0),
            },
            near: 0.0,
            far: 20.0,
            size: n,
            depth: Vec::new(),
            tiles: Vec::new(),
        };
        m.set_rows((0..n * n).map(|k| {
            if covered((k % n) as i32, (k / n) as i32) {
                z
            } else {
                f32::INFINITY
            }
        }));
        m
    }

    fn at(m: &ShadowMap, x: f32, z: f32) -> Receiver {
        m.locate(Vec3::new(x, 0.0, z), Vec3::Y).unwrap()
    }

    const FILTERS: [ShadowFilter; 5] = [
        ShadowFilter::Hard,
        ShadowFilter::Pcf3,
        ShadowFilter::Pcf5,
        ShadowFilter::Poisson,
        ShadowFilter::Pcss,
    ];
    const SUN: LightExtent = LightExtent::Angle { tan_half: 0.05 };

    #[test]
    fn every_filter_is_lit_in_the_open_and_dark_under_a_wide_blocker() {
        let open = map(|_, _| false, 5.0);
        let under = map(|_, _| true, 5.0);
        for f in FILTERS {
            let r = at(&open, 0.3, 0.2);
            assert_eq!(lit_fraction(&open, &r, 0.01, f, SUN), 1.0, "{f:?}");
            let r = at(&under, 0.3, 0.2);
            assert_eq!(lit_fraction(&under, &r, 0.01, f, SUN), 0.0, "{f:?}");
        }
    }

    #[test]
    fn a_receiver_at_the_caster_depth_lights_itself_within_the_bias() {
        // The floor itself in the map (depth 10): with a small bias every filter says lit.
        let floor = map(|_, _| true, 10.0);
        for f in FILTERS {
            let r = at(&floor, 0.37, -1.2);
            assert_eq!(lit_fraction(&floor, &r, 1e-3, f, SUN), 1.0, "{f:?}");
        }
    }

    #[test]
    fn pcf_crosses_an_edge_linearly() {
        // Blocker over the left half (x < 0 ⇔ i < 8): PCF 3×3 goes from 0 to 1 over three
        // texels, 0.5 on the edge, and the box filter is monotonic in between.
        let m = map(|i, _| i < 8, 5.0);
        let f = |x: f32| lit_fraction(&m, &at(&m, x, 0.5), 0.01, ShadowFilter::Pcf3, SUN);
        assert!((f(0.0) - 0.5).abs() < 1e-5, "{}", f(0.0));
        assert_eq!((f(-1.5), f(1.5)), (0.0, 1.0));
        let mut last = 0.0;
        for k in 0..=30 {
            let v = f(-1.5 + 0.1 * k as f32);
            assert!(v + 1e-6 >= last, "{k}: {v} < {last}");
            last = v;
        }
        // PCF 5×5 is wider: still partly dark 1.5 texels from the edge.
        let g = lit_fraction(&m, &at(&m, 1.5, 0.5), 0.01, ShadowFilter::Pcf5, SUN);
        assert!(g > 0.7 && g < 1.0, "{g}");
    }

    #[test]
    fn pcf3_in_lanes_equals_the_scalar_box() {
        // A ragged blocker at mixed depths, receivers on a sloped plane, inside the map and
        // at its edges (where the clamped box takes over).
        let m = map(|i, j| (i * 7 + j * 3) % 5 < 2, 9.9);
        let n = Vec3::new(0.3, 1.0, -0.2).normalize();
        for k in 0..200 {
            let (x, z) = (
                -8.0 + 0.08 * k as f32,
                -7.9 + 0.079 * ((k * 37) % 200) as f32,
            );
            let r = m.locate(Vec3::new(x, 0.1 * x, z), n).unwrap();
            let lanes = pcf3(&m, &r, 0.05);
            let scalar = pcf_box::<3>(&m, &r, 0.05);
            assert!((lanes - scalar).abs() < 1e-5, "{k}: {lanes} vs {scalar}");
        }
    }

    #[test]
    fn the_tiles_give_pcf3_the_same_fractions_as_reading_every_window() {
        // A floor seen at a slope casting on itself (its own depths in the map: the tiles'
        // fitted planes know it lit), a blocker over part of it (the blocks under it known
        // shadowed) and ragged edges; receivers on the floor's plane.
        let (ka, kb) = (0.3f32, -0.2f32);
        let floor_y = |x: f32, z: f32| ka * x + kb * z;
        let mut m = map(|_, _| false, 0.0);
        let n = 16;
        m.set_rows((0..n * n).map(|k| {
            let (i, j) = ((k % n) as f32, (k / n) as f32);
            let (x, z) = (i + 0.5 - 8.0, j + 0.5 - 8.0);
            if (3.0..7.0).contains(&i) && j < 9.0 {
                2.0
            } else {
                10.0 - floor_y(x, z)
            }
        }));
        let mut bare = m.clone();
        bare.tiles.clear();
        let normal = Vec3::new(-ka, 1.0, -kb).normalize();
        let (mut known, mut total) = (0, 0);
        for k in 0..400 {
            // Inside the map by more than the window (pcf3 reads it; no clamped box).
            let (x, z) = (
                -6.0 + 0.03 * k as f32,
                -5.9 + 0.0295 * ((k * 53) % 400) as f32,
            );
            let p = Vec3::new(x, floor_y(x, z), z);
            let r = m.locate(p, normal).unwrap();
            for bias in [0.0, 0.05, 0.3] {
                let with = pcf3(&m, &r, bias);
                let without = pcf3(&bare, &r, bias);
                assert_eq!(
                    with.to_bits(),
                    without.to_bits(),
                    "{k}: {with} vs {without}"
                );
                let (fx, fy) = (r.u - 0.5, r.v - 0.5);
                let (i0, j0) = (fx.floor() as usize - 1, fy.floor() as usize - 1);
                let corner = r.depth
                    - bias
                    - r.du * (1.0 + fx - fx.floor())
                    - r.dv * (1.0 + fy - fy.floor());
                known += usize::from(window_known(&m, (i0, j0), corner, r.du, r.dv).is_some());
                total += 1;
            }
        }
        // Many windows are known (the floor's own depths lie on its plane; with no bias the
        // receiver touches it and the margin leaves the window to be read).
        assert!(known * 5 > total, "{known} of {total}");
    }

    #[test]
    fn pcss_penumbrae_widen_with_the_gap_to_the_blocker() {
        // The same edge, a blocker near the receiver (depth 9.5) and far above it (depth 1).
        let near = map(|i, _| i < 8, 9.5);
        let far = map(|i, _| i < 8, 1.0);
        let wide = LightExtent::Angle { tan_half: 0.3 };
        let pcss =
            |m: &ShadowMap, x: f32| lit_fraction(m, &at(m, x, 0.5), 0.01, ShadowFilter::Pcss, wide);
        // Two texels out, a contact shadow is already lit; a high blocker's is not.
        assert!(pcss(&near, 2.0) > 0.99, "{}", pcss(&near, 2.0));
        let soft = pcss(&far, 2.0);
        assert!(soft > 0.5 && soft < 0.95, "{soft}");
    }
}
