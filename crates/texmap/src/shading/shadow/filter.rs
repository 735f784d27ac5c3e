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

use super::map::{Receiver, Receivers, ShadowMap, BLOCK};
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
    let at = (i0 as usize, j0 as usize);
    // The tiles may tell every compare at once: the same sum as the loop's, without a read.
    match window_known(map, at, corner, r.du, r.dv) {
        Some(true) => known_lit(a, b),
        Some(false) => 0.0,
        None => read_window(map, at, corner, (r.du, r.dv), (a, b)),
    }
}

/// The PCF 3×3 sum of a window every compare of which passes (`a`, `b` the position inside
/// the texel): exactly what [`read_window`] adds up there.
#[inline(always)]
fn known_lit(a: f32, b: f32) -> f32 {
    let all = Vec4::new(1.0 - a, 1.0, 1.0, a).element_sum();
    let mut sum = 0.0;
    for wy in [1.0 - b, 1.0, 1.0, b] {
        sum += wy * all;
    }
    sum * (1.0 / 9.0)
}

/// The PCF 3×3 sum over the 4×4 window from texel `at` (inside the map), the receiver plane
/// `corner` at its first texel's centre and `(du, dv)` per texel, `(a, b)` the position inside
/// the texel.
#[inline(always)]
fn read_window(
    map: &ShadowMap,
    (i0, j0): (usize, usize),
    corner: f32,
    (du, dv): (f32, f32),
    (a, b): (f32, f32),
) -> f32 {
    let mut plane = Vec4::splat(corner) + Vec4::new(0.0, 1.0, 2.0, 3.0) * du;
    let step = Vec4::splat(dv);
    let wx = Vec4::new(1.0 - a, 1.0, 1.0, a);
    let wy = [1.0 - b, 1.0, 1.0, b];
    let mut sum = 0.0;
    for (y, wy) in wy.iter().enumerate() {
        let texels = map.four_at(i0, j0 + y);
        let lit = Vec4::select(plane.cmple(texels), wx, Vec4::ZERO);
        sum += wy * lit.element_sum();
        plane += step;
    }
    sum * (1.0 / 9.0)
}

/// The most blocks [`pcf3_quad`] tests in lanes; a quad whose windows spread wider (a map
/// seen from far, several texels a pixel) is filtered pixel by pixel.
const QUAD_BLOCKS: usize = 9;

/// [`pcf3`] at a quad's four receivers `r` (receiver depths lowered by `bias`), for the lanes
/// set in `todo` (the others get 1). The tiles' test of [`window_known`] runs in lanes, once
/// per block the four windows touch, each lane over its own window's blocks in that
/// function's order of operations, so each lane is known exactly when its pixel's window is
/// and every fraction equals [`pcf3`]'s bit for bit (tested). Lanes left open read their
/// window; windows at the map's edges take the clamped box, as in [`pcf3`].
#[inline]
pub(super) fn pcf3_quad(map: &ShadowMap, r: &Receivers, bias: Vec4, todo: u32) -> Vec4 {
    let mut out = [1.0f32; 4];
    if todo == 0 {
        return Vec4::ONE;
    }
    let half = Vec4::splat(0.5);
    let (fx, fy) = (r.u - half, r.v - half);
    let (ix, iy) = (fx.floor(), fy.floor());
    let (a, b) = (fx - ix, fy - iy);
    // In pcf3's order of operations, lane by lane.
    let corner = r.depth - bias - r.du * (Vec4::ONE + a) - r.dv * (Vec4::ONE + b);
    let (ix, iy) = (ix.to_array(), iy.to_array());
    let n = map.size as i32;
    let mut at = [(0usize, 0usize); 4];
    let mut inside = 0u32;
    for j in 0..4 {
        if todo & (1 << j) == 0 {
            continue;
        }
        let (i0, j0) = (ix[j] as i32 - 1, iy[j] as i32 - 1);
        if i0 >= 0 && j0 >= 0 && i0 + 4 <= n && j0 + 4 <= n {
            at[j] = (i0 as usize, j0 as usize);
            inside |= 1 << j;
        } else {
            out[j] = pcf_box::<3>(map, &r.lane(j), bias[j]);
        }
    }
    let (lit, dark) = quad_known(map, &at, inside, corner, r.du, r.dv).unwrap_or((0, 0));
    let (a4, b4, c4) = (a.to_array(), b.to_array(), corner.to_array());
    let (du, dv) = (r.du.to_array(), r.dv.to_array());
    for j in 0..4 {
        if inside & (1 << j) == 0 {
            continue;
        }
        out[j] = if lit & (1 << j) != 0 {
            known_lit(a4[j], b4[j])
        } else if dark & (1 << j) != 0 {
            0.0
        } else {
            read_window(map, at[j], c4[j], (du[j], dv[j]), (a4[j], b4[j]))
        };
    }
    Vec4::from_array(out)
}

/// [`window_known`] for the windows from `at` of the lanes in `lanes`, in lanes: the lanes
/// known lit and those known shadowed, as bits; `None` without tiles or when the windows
/// touch more than [`QUAD_BLOCKS`] blocks (then every lane is tested alone).
#[inline(always)]
fn quad_known(
    map: &ShadowMap,
    at: &[(usize, usize); 4],
    lanes: u32,
    corner: Vec4,
    du: Vec4,
    dv: Vec4,
) -> Option<(u32, u32)> {
    if map.tiles.is_empty() || lanes == 0 {
        return None;
    }
    // Each lane's blocks: columns bx0..=bx1, rows by0..=by1.
    let mut span = [(usize::MAX, 0usize, usize::MAX, 0usize); 4];
    let (mut x0, mut x1, mut y0, mut y1) = (usize::MAX, 0, usize::MAX, 0);
    for j in 0..4 {
        if lanes & (1 << j) != 0 {
            let (i, k) = at[j];
            span[j] = (i / BLOCK, (i + 3) / BLOCK, k / BLOCK, (k + 3) / BLOCK);
            x0 = x0.min(span[j].0);
            x1 = x1.max(span[j].1);
            y0 = y0.min(span[j].2);
            y1 = y1.max(span[j].3);
        }
    }
    if (x1 - x0 + 1) * (y1 - y0 + 1) > QUAD_BLOCKS {
        return None;
    }
    let three = Vec4::splat(3.0);
    let reach = three * (du.abs() + dv.abs());
    let m1 = (corner.abs() + reach) * 1e-5;
    let (near, far) = (corner + reach + m1, corner - reach - m1);
    let m0 = corner.abs() + reach;
    let ci = Vec4::from_array(at.map(|(i, _)| i as f32));
    let cj = Vec4::from_array(at.map(|(_, k)| k as f32));
    let blocks = (map.size as usize).div_ceil(BLOCK);
    let (mut lit, mut dark) = (lanes, lanes);
    for by in y0..=y1 {
        for bx in x0..=x1 {
            let mut touch = 0u32;
            for (j, &(sx0, sx1, sy0, sy1)) in span.iter().enumerate() {
                if (sx0..=sx1).contains(&bx) && (sy0..=sy1).contains(&by) {
                    touch |= 1 << j;
                }
            }
            if touch & (lit | dark) == 0 {
                continue;
            }
            let t = &map.tiles[by * blocks + bx];
            // As window_known, lane-wise (x, y from the block's first texel).
            let x = ci - Vec4::splat((bx * BLOCK) as f32);
            let y = cj - Vec4::splat((by * BLOCK) as f32);
            let (ta, tb) = (Vec4::splat(t.a), Vec4::splat(t.b));
            let g = corner - (Vec4::splat(t.c) + ta * x + tb * y)
                + three * ((du - ta).max(Vec4::ZERO) + (dv - tb).max(Vec4::ZERO));
            let m2 =
                (m0 + Vec4::splat(t.c.abs()) + Vec4::splat(12.0 * (t.a.abs() + t.b.abs()))) * 1e-5;
            let on_plane = (g + Vec4::splat(t.below) + m2).cmple(Vec4::ZERO);
            let lit_t = (near.cmple(Vec4::splat(t.lo)) | on_plane).bitmask();
            let dark_t = far.cmpgt(Vec4::splat(t.hi)).bitmask();
            lit &= lit_t | !touch;
            dark &= dark_t | !touch;
        }
    }
    // Lit wins, as in window_known.
    Some((lit, dark & !lit))
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

    /// A 16² map of a floor seen at a slope (y = 0.3·x − 0.2·z) casting on itself, a blocker
    /// over part of it: the map, the same without its tiles, the floor's height and normal.
    fn sloped_floor() -> (ShadowMap, ShadowMap, impl Fn(f32, f32) -> f32, Vec3) {
        let (ka, kb) = (0.3f32, -0.2f32);
        let floor_y = move |x: f32, z: f32| ka * x + kb * z;
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
        (m, bare, floor_y, Vec3::new(-ka, 1.0, -kb).normalize())
    }

    #[test]
    fn the_tiles_give_pcf3_the_same_fractions_as_reading_every_window() {
        // A floor seen at a slope casting on itself (its own depths in the map: the tiles'
        // fitted planes know it lit), a blocker over part of it (the blocks under it known
        // shadowed) and ragged edges; receivers on the floor's plane.
        let (m, bare, floor_y, normal) = sloped_floor();
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
    fn pcf3_in_quads_equals_pcf3_pixel_by_pixel() {
        // The sloped floor casting on itself with a blocker over part of it (known lit,
        // known shadowed and read windows), quads of four receivers a little apart or
        // spread over many blocks, inside the map and over its edges, some lanes skipped.
        let (m, bare, floor_y, normal) = sloped_floor();
        let (mut known, mut total) = (0, 0);
        for k in 0..600 {
            let (x, z) = (
                -8.0 + 0.0267 * k as f32,
                -7.9 + 0.0263 * ((k * 53) % 600) as f32,
            );
            let spread = [0.4, 1.3, 6.0][k % 3];
            let mut r = [Receiver {
                u: 0.0,
                v: 0.0,
                depth: 0.0,
                du: 0.0,
                dv: 0.0,
                texel: 0.0,
            }; 4];
            for (j, r) in r.iter_mut().enumerate() {
                let (x, z) = (x + spread * (j % 2) as f32, z + spread * (j / 2) as f32);
                *r = m.locate(Vec3::new(x, floor_y(x, z), z), normal).unwrap();
            }
            let lanes = |f: fn(&Receiver) -> f32| Vec4::from_array(r.map(|r| f(&r)));
            let quad = Receivers {
                u: lanes(|r| r.u),
                v: lanes(|r| r.v),
                depth: lanes(|r| r.depth),
                du: lanes(|r| r.du),
                dv: lanes(|r| r.dv),
                texel: lanes(|r| r.texel),
            };
            for (bias, todo) in [(0.0, 0b1111), (0.05, 0b1011), (0.3, 0b0110)] {
                let b = Vec4::new(bias, bias * 0.9, bias * 1.1, bias);
                for map in [&m, &bare] {
                    let got = pcf3_quad(map, &quad, b, todo);
                    for j in 0..4 {
                        let want = if todo & (1 << j) == 0 {
                            1.0
                        } else {
                            pcf3(map, &r[j], b[j])
                        };
                        assert_eq!(got[j].to_bits(), want.to_bits(), "{k} lane {j}");
                    }
                }
                let (fx, fy) = (quad.u - Vec4::splat(0.5), quad.v - Vec4::splat(0.5));
                let corner = quad.depth
                    - b
                    - quad.du * (Vec4::ONE + fx - fx.floor())
                    - quad.dv * (Vec4::ONE + fy - fy.floor());
                let at = std::array::from_fn(|j| {
                    let (i, k) = (fx[j].floor() as i64 - 1, fy[j].floor() as i64 - 1);
                    (i.clamp(0, 12) as usize, k.clamp(0, 12) as usize)
                });
                if let Some((lit, dark)) = quad_known(&m, &at, todo, corner, quad.du, quad.dv) {
                    known += (lit | dark).count_ones();
                }
                total += todo.count_ones();
            }
        }
        // The quads' test decides many windows (as the per-pixel one does).
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
