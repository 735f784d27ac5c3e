//! [`phong`](super::phong) for the four pixels of a 2×2 quad at once, one pixel per `Vec4`
//! lane, under every kind of light.
//!
//! The rasterizer hands quads whose varyings are structure of arrays (varying `k` of the four
//! pixels in one `Vec4`), so the normals and positions arrive in lanes and the lighting runs
//! in lanes with no gather. The rule and the order of operations are the per-pixel rule's, so
//! the two agree to rounding (tested). The factors leave as one vector per pixel (a 4×4
//! transpose): returning them as pairs of `Vec3` made 12-byte stores that were reloaded as
//! 16-byte vectors and stalled store forwarding (see DESIGN.md's decision log).

use glam::{Mat4, Vec3, Vec4};

use super::wide::Lane;
use super::{Light, Lighting, Surface, Viewer};

/// Three lanes of a vector quantity: `x`, `y` and `z` of the four pixels.
pub type Lanes3 = [Vec4; 3];

/// The factors `I = C·D + S` of a quad's four pixels, one `Vec4` per pixel (fourth
/// component 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadFactors {
    pub d: [Vec4; 4],
    pub s: [Vec4; 4],
}

impl QuadFactors {
    /// D = 1, S = 0: unlit.
    pub const UNLIT: QuadFactors = QuadFactors {
        d: [Vec4::new(1.0, 1.0, 1.0, 0.0); 4],
        s: [Vec4::ZERO; 4],
    };

    /// D = 0, S = 0.
    pub const ZERO: QuadFactors = QuadFactors {
        d: [Vec4::ZERO; 4],
        s: [Vec4::ZERO; 4],
    };

    /// Factors given as lanes (R, G and B of the four pixels).
    #[inline(always)]
    #[must_use]
    pub fn from_lanes(d: Lanes3, s: Lanes3) -> Self {
        QuadFactors {
            d: lanes_to_pixels(d),
            s: lanes_to_pixels(s),
        }
    }
}

/// The Phong factors of surface `s` at four pixels, under every light of `lighting`
/// (directional, point and spot), each scaled by its shadow maps' visibility when it casts.
/// `normal` holds the interpolated normals (renormalized here, zero stays zero); `position`
/// the world positions, read by point and spot lights, shadow lookups and the specular view
/// vector of a point viewer (the origin when `None`). The surface's own position and normal
/// are not read, nor its `ambient_color` (map-free surfaces have none).
///
/// Every lane follows [`phong`](super::phong)'s operations in its order (the light's
/// incidence, `S_i·I_i` times the visibility, then times `K_D·(N·L)`; `R = 2(N·L)N − L`), so
/// the factors equal the per-pixel rule's bit for bit (tested).
#[inline(always)]
#[must_use]
pub fn phong_quad(
    s: &Surface,
    normal: Lanes3,
    position: Option<Lanes3>,
    lighting: &Lighting,
    viewer: Viewer,
) -> QuadFactors {
    let [mut nx, mut ny, mut nz] = normal;
    // normalize_or_zero, per lane.
    let rcp = sqrt4(nx * nx + ny * ny + nz * nz).recip();
    let ok = rcp.cmplt(Vec4::INFINITY) & rcp.cmpgt(Vec4::ZERO);
    let rcp = Vec4::select(ok, rcp, Vec4::ZERO);
    (nx, ny, nz) = (nx * rcp, ny * rcp, nz * rcp);
    let p = position.unwrap_or([Vec4::ZERO; 3]);
    let ambient = lighting.ambient * (s.ambient * s.occlusion);
    let mut d = splat3(ambient);
    let mut sp = splat3(s.emissive);
    let specular = s.specular > 0.0;
    // The unit view vector per lane (only read for specular).
    let [vx, vy, vz] = match viewer {
        _ if !specular => [Vec4::ZERO; 3],
        Viewer::Direction(v) => splat3(v),
        Viewer::Point(eye) => {
            let [px, py, pz] = p;
            normalize_or_zero([
                Vec4::splat(eye.x) - px,
                Vec4::splat(eye.y) - py,
                Vec4::splat(eye.z) - pz,
            ])
        }
    };
    for (i, light) in lighting.lights.iter().enumerate() {
        let Some(inc) = incidence(light, p) else {
            continue;
        };
        let [lx, ly, lz] = inc.l;
        let n_dot_l = nx * lx + ny * ly + nz * lz;
        let on = inc.reaches & n_dot_l.cmpgt(Vec4::ZERO).bitmask();
        if on == 0 {
            continue;
        }
        let mask = Vec4::mask_from_bits(on);
        // S_i·I_i per channel, times the share that gets past the shadow maps.
        let mut intensity = inc.intensity;
        if let Some(maps) = lighting.shadows {
            let v = maps.visibility_quad(i, p, [nx, ny, nz], inc.l, on);
            intensity = intensity.map(|c| c * v);
        }
        let kd = n_dot_l * s.diffuse;
        for (dc, ic) in d.iter_mut().zip(&intensity) {
            *dc = Vec4::select(mask, *dc + *ic * kd, *dc);
        }
        if specular {
            // R·V with R = 2(N·L)N − L.
            let k = n_dot_l * 2.0;
            let (rx, ry, rz) = (nx * k - lx, ny * k - ly, nz * k - lz);
            let r_dot_v = rx * vx + ry * vy + rz * vz;
            let lit = on & r_dot_v.cmpgt(Vec4::ZERO).bitmask();
            if lit == 0 {
                continue;
            }
            let rv = r_dot_v.to_array();
            let lobe = Vec4::from_array(std::array::from_fn(|j| {
                if lit & (1 << j) != 0 {
                    s.specular * rv[j].powf(s.shininess)
                } else {
                    0.0
                }
            }));
            let mask = Vec4::mask_from_bits(lit);
            for (c, (sc, ic)) in sp.iter_mut().zip(&intensity).enumerate() {
                *sc = Vec4::select(mask, *sc + *ic * s.specular_color[c] * lobe, *sc);
            }
        }
    }
    QuadFactors::from_lanes(d, sp)
}

/// What one light delivers at a quad's four points ([`Light::incidence`] in lanes; in
/// eight lanes, two quads' points).
pub(super) struct Incidence<L = Vec4> {
    /// The unit direction towards the light, per lane.
    pub l: [L; 3],
    /// `S·I` per channel.
    pub intensity: [L; 3],
    /// The lanes the light reaches (bit `j` for lane `j`).
    pub reaches: u32,
}

/// [`Light::incidence`] at four points (x, y and z lanes; eight for two quads), lane by lane
/// in its order of operations; `None` when it reaches none of them.
#[inline(always)]
pub(super) fn incidence<L: Lane>(light: &Light, p: [L; 3]) -> Option<Incidence<L>> {
    let splat = |c: Vec3| [L::splat(c.x), L::splat(c.y), L::splat(c.z)];
    match *light {
        Light::Directional { direction, color } => {
            let len2 = direction.length_squared();
            let l = if (len2 - 1.0).abs() < 1e-6 {
                direction
            } else {
                direction.try_normalize()?
            };
            Some(Incidence {
                l: splat(l),
                intensity: splat(color),
                reaches: (1 << (4 * L::QUADS)) - 1,
            })
        }
        Light::Point {
            position,
            color,
            range,
        } => {
            let (l, s, reaches) = point_falloff(position, p, range);
            Some(Incidence {
                l,
                intensity: [
                    L::splat(color.x) * s,
                    L::splat(color.y) * s,
                    L::splat(color.z) * s,
                ],
                reaches,
            })
            .filter(|_| reaches != 0)
        }
        Light::Spot {
            position,
            direction,
            color,
            inner_deg,
            outer_deg,
        } => {
            let (l, s, mut reaches) = point_falloff(position, p, None);
            let axis = direction.try_normalize()?;
            let cos_outer = outer_deg.to_radians().cos();
            let cos_inner = inner_deg.to_radians().cos();
            let scale = 1.0 / (cos_inner - cos_outer).max(1e-3);
            let [lx, ly, lz] = l;
            let cos =
                (-lx) * L::splat(axis.x) + (-ly) * L::splat(axis.y) + (-lz) * L::splat(axis.z);
            let cone =
                ((cos - L::splat(cos_outer)) * L::splat(scale)).clamp(L::splat(0.0), L::splat(1.0));
            reaches &= L::bitmask(cone.cmpgt(L::splat(0.0)));
            let k = s * cone * cone;
            Some(Incidence {
                l,
                intensity: [
                    L::splat(color.x) * k,
                    L::splat(color.y) * k,
                    L::splat(color.z) * k,
                ],
                reaches,
            })
            .filter(|_| reaches != 0)
        }
    }
}

/// The unit directions from four points towards `position`, the inverse-square falloff
/// (windowed by `range`) and the lanes it reaches, as the per-pixel rule's `point_falloff`.
#[inline(always)]
fn point_falloff<L: Lane>(position: Vec3, p: [L; 3], range: Option<f32>) -> ([L; 3], L, u32) {
    let [px, py, pz] = p;
    let (x, y, z) = (
        L::splat(position.x) - px,
        L::splat(position.y) - py,
        L::splat(position.z) - pz,
    );
    let d2 = x * x + y * y + z * z;
    let (zero, one) = (L::splat(0.0), L::splat(1.0));
    let mut reaches = L::bitmask(d2.cmpgt(zero) & d2.cmplt(L::splat(f32::INFINITY)));
    let d = d2.sqrt();
    let mut s = one / d2;
    if let Some(r) = range.filter(|r| *r > 0.0) {
        let x = (d / L::splat(r)).map(|v| v.powi(4));
        let w = (one - x).clamp(zero, one);
        s = s * (w * w);
    }
    reaches &= L::bitmask(s.cmpgt(zero));
    ([x / d, y / d, z / d], s, reaches)
}

/// `normalize_or_zero` of three lanes.
#[inline(always)]
#[must_use]
pub fn normalize_or_zero(v: Lanes3) -> Lanes3 {
    normalize_lanes(v)
}

/// [`normalize_or_zero`] on any lane type (two quads' lanes at once in eight).
#[inline(always)]
pub(crate) fn normalize_lanes<L: Lane>([x, y, z]: [L; 3]) -> [L; 3] {
    let r = (x * x + y * y + z * z).sqrt().recip();
    let zero = L::splat(0.0);
    let r = L::select(r.cmplt(L::splat(f32::INFINITY)) & r.cmpgt(zero), r, zero);
    [x * r, y * r, z * r]
}

#[inline(always)]
pub(crate) fn splat3(v: Vec3) -> Lanes3 {
    [Vec4::splat(v.x), Vec4::splat(v.y), Vec4::splat(v.z)]
}

/// Lane-wise square root (one `sqrtps`).
#[inline(always)]
#[must_use]
pub fn sqrt4(v: Vec4) -> Vec4 {
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY: SSE is part of x86_64.
        Vec4::from(unsafe { std::arch::x86_64::_mm_sqrt_ps(v.into()) })
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        Vec4::from_array(v.to_array().map(f32::sqrt))
    }
}

/// Three lanes (R, G and B, one pixel per lane) as one vector per pixel, its fourth component
/// zero: a 4×4 transpose (shuffles).
#[inline(always)]
#[must_use]
pub fn lanes_to_pixels(c: Lanes3) -> [Vec4; 4] {
    transpose([c[0], c[1], c[2], Vec4::ZERO])
}

/// Four vectors transposed (a 4×4 transpose, shuffles): four pixels' values (one `Vec4`
/// each) as lanes — x, y, z and w of the four pixels — or lanes back as pixels.
#[inline(always)]
#[must_use]
pub fn transpose(v: [Vec4; 4]) -> [Vec4; 4] {
    let m = Mat4::from_cols(v[0], v[1], v[2], v[3]).transpose();
    [m.x_axis, m.y_axis, m.z_axis, m.w_axis]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::{phong, Material};

    #[test]
    fn quad_lighting_equals_the_per_pixel_rule_under_every_light() {
        let lights = [
            Light::Directional {
                direction: Vec3::new(0.3, 0.8, 0.5).normalize(),
                color: Vec3::new(1.0, 0.9, 0.8),
            },
            Light::Directional {
                direction: Vec3::new(-0.6, 0.2, 0.77).normalize(),
                color: Vec3::splat(0.5),
            },
            Light::Point {
                position: Vec3::new(1.0, 3.0, 2.5),
                color: Vec3::new(8.0, 6.8, 4.8),
                range: Some(6.0),
            },
            Light::Point {
                position: Vec3::new(-2.0, 1.0, 0.5),
                color: Vec3::splat(2.0),
                range: None,
            },
            Light::Spot {
                position: Vec3::new(0.0, 4.0, 0.0),
                direction: Vec3::new(0.1, -1.0, 0.2).normalize(),
                color: Vec3::new(5.0, 5.0, 4.0),
                inner_deg: 20.0,
                outer_deg: 50.0,
            },
        ];
        let lighting = Lighting {
            lights: &lights,
            ambient: Vec3::new(0.3, 0.35, 0.4),
            shadows: None,
        };
        let material = Material {
            specular: 0.7,
            shininess: 24.0,
            emissive: Vec3::new(0.01, 0.02, 0.03),
            ..Default::default()
        };
        let mut surface = Surface::new(&material, Vec3::ZERO, Vec3::ZERO);
        surface.specular_color = Vec3::new(1.0, 0.5, 0.25);
        // Unnormalized normals (one zero), positions spread out (one outside the spot's
        // cone, one beyond the first point light's range), some facing away.
        let normals = [
            Vec3::new(0.1, 2.0, 0.3),
            Vec3::new(-1.0, 0.2, 0.9),
            Vec3::ZERO,
            Vec3::new(0.2, -1.0, 0.1),
        ];
        let positions = [
            Vec3::new(-4.0, 0.0, -5.0),
            Vec3::new(-0.5, 0.1, -1.0),
            Vec3::new(0.5, 0.2, 0.0),
            Vec3::new(1.5, 0.3, 1.0),
        ];
        let lanes = |v: &[Vec3; 4]| -> Lanes3 {
            std::array::from_fn(|c| Vec4::from_array(std::array::from_fn(|j| v[j][c])))
        };
        for viewer in [
            Viewer::Point(Vec3::new(0.5, 3.0, 4.0)),
            Viewer::Direction(Vec3::new(0.0, 0.6, 0.8)),
        ] {
            for back in [false, true] {
                let sign = if back { -1.0 } else { 1.0 };
                let n = lanes(&normals).map(|l| l * sign);
                let q = phong_quad(&surface, n, Some(lanes(&positions)), &lighting, viewer);
                for (j, n) in normals.iter().enumerate() {
                    let s = Surface {
                        position: positions[j],
                        normal: n.normalize_or_zero() * sign,
                        ..surface
                    };
                    let (d, sp) = phong(&s, &lighting, viewer);
                    let (qd, qs) = (q.d[j].truncate(), q.s[j].truncate());
                    // The same operations in the same order: equal, not just close.
                    assert!(
                        d == qd && sp == qs,
                        "pixel {j} {viewer:?} back {back}: {d} {sp} vs {qd} {qs}"
                    );
                }
            }
        }
    }

    #[test]
    fn lanes_to_pixels_transposes() {
        let c = [
            Vec4::new(1.0, 2.0, 3.0, 4.0),
            Vec4::new(5.0, 6.0, 7.0, 8.0),
            Vec4::new(9.0, 10.0, 11.0, 12.0),
        ];
        let p = lanes_to_pixels(c);
        assert_eq!(p[1], Vec4::new(2.0, 6.0, 10.0, 0.0));
        assert_eq!(p[3], Vec4::new(4.0, 8.0, 12.0, 0.0));
    }
}
