//! [`phong`](super::phong) for the four pixels of a 2×2 quad at once, one pixel per `Vec4`
//! lane, under directional lights.
//!
//! The rasterizer hands quads whose varyings are structure of arrays (varying `k` of the four
//! pixels in one `Vec4`), so the normals and positions arrive in lanes and the lighting runs
//! in lanes with no gather. The rule and the order of operations are the per-pixel rule's, so
//! the two agree to rounding (tested). The factors leave as one vector per pixel (a 4×4
//! transpose): returning them as pairs of `Vec3` made 12-byte stores that were reloaded as
//! 16-byte vectors and stalled store forwarding (see DESIGN.md's decision log).

use glam::{Mat4, Vec3, Vec4};

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

/// The Phong factors of surface `s` at four pixels, under the directional lights of
/// `lighting` (other lights are skipped: callers take this path only when every light is
/// directional), each scaled by its shadow maps' visibility when it casts. `normal` holds the interpolated normals (renormalized here, zero stays
/// zero); `position` the world positions, read for the specular view vector of a point
/// viewer (the origin when `None`). The surface's own position and normal are not read, nor
/// its `ambient_color` (map-free surfaces have none).
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
    let ambient = lighting.ambient * (s.ambient * s.occlusion);
    let mut d = splat3(ambient);
    let mut sp = splat3(s.emissive);
    let specular = s.specular > 0.0;
    // The unit view vector per lane (only read for specular).
    let [vx, vy, vz] = match viewer {
        _ if !specular => [Vec4::ZERO; 3],
        Viewer::Direction(v) => splat3(v),
        Viewer::Point(eye) => {
            let [px, py, pz] = position.unwrap_or([Vec4::ZERO; 3]);
            let (x, y, z) = (
                Vec4::splat(eye.x) - px,
                Vec4::splat(eye.y) - py,
                Vec4::splat(eye.z) - pz,
            );
            let r = sqrt4(x * x + y * y + z * z).recip();
            let r = Vec4::select(r.cmplt(Vec4::INFINITY) & r.cmpgt(Vec4::ZERO), r, Vec4::ZERO);
            [x * r, y * r, z * r]
        }
    };
    for (i, light) in lighting.lights.iter().enumerate() {
        let Light::Directional {
            direction: l,
            color,
        } = *light
        else {
            continue;
        };
        let n_dot_l = nx * l.x + ny * l.y + nz * l.z;
        let facing = n_dot_l.cmpgt(Vec4::ZERO);
        let mut diffuse = Vec4::select(facing, n_dot_l * s.diffuse, Vec4::ZERO);
        // The light's share that gets past the shadow maps (positions are the origin when
        // `None`; callers pass them when there are shadows).
        let visible = lighting.shadows.map(|maps| {
            let p = position.unwrap_or([Vec4::ZERO; 3]);
            maps.visibility_quad(i, p, [nx, ny, nz], l, facing.bitmask())
        });
        if let Some(v) = visible {
            diffuse *= v;
        }
        for (c, dc) in d.iter_mut().enumerate() {
            *dc += diffuse * color[c];
        }
        if specular {
            // R·V with R = 2(N·L)N − L.
            let n_dot_v = nx * vx + ny * vy + nz * vz;
            let l_dot_v = vx * l.x + vy * l.y + vz * l.z;
            let r_dot_v = n_dot_l * 2.0 * n_dot_v - l_dot_v;
            let on = (facing & r_dot_v.cmpgt(Vec4::ZERO)).bitmask();
            let rv = r_dot_v.to_array();
            let mut lobe = Vec4::from_array(std::array::from_fn(|j| {
                if on & (1 << j) != 0 {
                    s.specular * rv[j].powf(s.shininess)
                } else {
                    0.0
                }
            }));
            if let Some(v) = visible {
                lobe *= v;
            }
            for (c, sc) in sp.iter_mut().enumerate() {
                *sc += lobe * (color[c] * s.specular_color[c]);
            }
        }
    }
    QuadFactors::from_lanes(d, sp)
}

#[inline(always)]
fn splat3(v: Vec3) -> Lanes3 {
    [Vec4::splat(v.x), Vec4::splat(v.y), Vec4::splat(v.z)]
}

/// Lane-wise square root (one `sqrtps`).
#[inline(always)]
fn sqrt4(v: Vec4) -> Vec4 {
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
    let m = Mat4::from_cols(c[0], c[1], c[2], Vec4::ZERO).transpose();
    [m.x_axis, m.y_axis, m.z_axis, m.w_axis]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::{phong, Material};

    #[test]
    fn quad_lighting_equals_the_per_pixel_rule() {
        let lights = [
            Light::Directional {
                direction: Vec3::new(0.3, 0.8, 0.5).normalize(),
                color: Vec3::new(1.0, 0.9, 0.8),
            },
            Light::Directional {
                direction: Vec3::new(-0.6, 0.2, 0.77).normalize(),
                color: Vec3::splat(0.5),
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
        // Unnormalized normals (one zero), positions spread out, some facing away.
        let normals = [
            Vec3::new(0.1, 2.0, 0.3),
            Vec3::new(-1.0, 0.2, 0.9),
            Vec3::ZERO,
            Vec3::new(0.2, -1.0, 0.1),
        ];
        let positions: [Vec3; 4] =
            std::array::from_fn(|j| Vec3::new(j as f32 - 1.5, 0.1 * j as f32, -2.0 + j as f32));
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
                    assert!(
                        (d - qd).abs().max_element() < 1e-5 && (sp - qs).abs().max_element() < 1e-5,
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
