//! Texture coordinate generation: planar, cylindrical, spherical, cube and bounding-sphere
//! projections of object-space positions, per vertex or per pixel.
//!
//! Conventions (the texture lecture's, `../shared/references/000_ed5bcbb59764aae3.txt`):
//! - cylindrical about +y: θ = atan2(P_z, P_x), u = −θ/2π when θ < 0 and 1 − θ/2π otherwise
//!   (u grows counter-clockwise seen from +y); on the unit cylinder (y in [−0.5, 0.5]) the
//!   lecture's v is P_y + 0.5; caps (faces whose normal is mostly ±y) are mapped as planes;
//! - spherical: u as for the cylinder, the lecture's v = asin(P_y / r)/π + 0.5 (latitude);
//! - cube: the face is chosen by the dominant axis of the normal, then mapped as a plane;
//! - bounding sphere: the direction of P from the object's centre, mapped as on the sphere —
//!   the lecture's "pretend the house is a sphere".
//!
//! The lecture's v points up; texmap's texture space is glTF's (v down the image rows), so the
//! stored v is `1 − v_lecture` and images appear upright.
//!
//! Per-pixel evaluation ([`Projection::map_footprint`]) differentiates the mapping
//! analytically (chain rule through atan2 and asin), so the derivatives are continuous across
//! the u = 1 → 0 seam and a pixel straddling it does not read the smallest mip level. Per-vertex
//! generation ([`generate_uvs`]) splits the triangles that cross the seam (their vertices on the
//! low side get u + 1), so interpolation does not run backwards through the whole texture.

use glam::{DVec3, Vec2, Vec3};

use crate::texture::Footprint;

/// An object-space axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    X,
    Y,
    Z,
}

/// A projection from object space to texture space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Orthographic along `axis` over the unit square centred on the origin.
    Planar { axis: Axis },
    /// About the +y axis, unit cylinder of height 1 centred on the origin.
    Cylindrical,
    /// Longitude and latitude about the origin.
    Spherical,
    /// Six planar maps, chosen by the normal's dominant axis.
    Cube,
    /// Spherical about `center` (the bounding sphere's centre).
    BoundingSphere { center: Vec3 },
}

/// u of the lecture's cylindrical/spherical longitude, and du for a displacement.
fn longitude(p: DVec3) -> f64 {
    let theta = p.z.atan2(p.x);
    let t = theta / std::f64::consts::TAU;
    if theta < 0.0 {
        -t
    } else {
        1.0 - t
    }
}

fn d_longitude(p: DVec3, dp: DVec3) -> f64 {
    let r2 = p.x * p.x + p.z * p.z;
    if r2 <= 1e-300 {
        return 0.0;
    }
    let dtheta = (p.x * dp.z - p.z * dp.x) / r2;
    -dtheta / std::f64::consts::TAU
}

fn latitude_v(p: DVec3) -> f64 {
    let r = p.length();
    if r <= 0.0 {
        return 0.5;
    }
    let v_lecture = (p.y / r).clamp(-1.0, 1.0).asin() / std::f64::consts::PI + 0.5;
    1.0 - v_lecture
}

fn d_latitude_v(p: DVec3, dp: DVec3) -> f64 {
    let r = p.length();
    if r <= 0.0 {
        return 0.0;
    }
    let s = p.y / r;
    let ds = (dp.y * r - p.y * p.dot(dp) / r) / (r * r);
    let c = (1.0 - s * s).max(1e-12).sqrt();
    -(ds / c) / std::f64::consts::PI
}

/// Planar map along `axis`: the two other coordinates, centred, v down.
fn planar(p: DVec3, axis: Axis) -> (f64, f64) {
    match axis {
        Axis::X => (0.5 - p.z, 0.5 - p.y),
        Axis::Y => (p.x + 0.5, p.z + 0.5),
        Axis::Z => (p.x + 0.5, 0.5 - p.y),
    }
}

fn planar_linear(dp: DVec3, axis: Axis) -> (f64, f64) {
    match axis {
        Axis::X => (-dp.z, -dp.y),
        Axis::Y => (dp.x, dp.z),
        Axis::Z => (dp.x, -dp.y),
    }
}

fn dominant_axis(n: Vec3) -> Axis {
    let a = n.abs();
    if a.x >= a.y && a.x >= a.z {
        Axis::X
    } else if a.y >= a.z {
        Axis::Y
    } else {
        Axis::Z
    }
}

impl Projection {
    /// Parses `planar-x|planar-y|planar-z|planar` (= z), `cylindrical`, `spherical`, `cube`,
    /// `bounding-sphere` (centred on the origin; callers set the centre).
    #[must_use]
    pub fn parse(s: &str) -> Option<Projection> {
        Some(match s {
            "planar" | "planar-z" => Projection::Planar { axis: Axis::Z },
            "planar-x" => Projection::Planar { axis: Axis::X },
            "planar-y" => Projection::Planar { axis: Axis::Y },
            "cylindrical" => Projection::Cylindrical,
            "spherical" => Projection::Spherical,
            "cube" => Projection::Cube,
            "bounding-sphere" => Projection::BoundingSphere { center: Vec3::ZERO },
            _ => return None,
        })
    }

    /// The chart a point uses: planar axis for planes, caps and cube faces; `None` for the
    /// round part of the cylinder and for spheres.
    fn chart(&self, n: Vec3) -> Option<Axis> {
        match *self {
            Projection::Planar { axis } => Some(axis),
            Projection::Cube => Some(dominant_axis(n)),
            Projection::Cylindrical if n.y.abs() > n.x.abs().max(n.z.abs()) => Some(Axis::Y),
            _ => None,
        }
    }

    fn centred(&self, p: Vec3) -> DVec3 {
        match *self {
            Projection::BoundingSphere { center } => (p - center).as_dvec3(),
            _ => p.as_dvec3(),
        }
    }

    /// Texture coordinates of object-space point `p` with normal `n` (the normal only picks
    /// cube faces and cylinder caps).
    #[must_use]
    pub fn map(&self, p: Vec3, n: Vec3) -> Vec2 {
        let q = self.centred(p);
        let (u, v) = match (self.chart(n), self) {
            (Some(axis), _) => planar(q, axis),
            (None, Projection::Cylindrical) => (longitude(q), 1.0 - (q.y + 0.5)),
            (None, _) => (longitude(q), latitude_v(q)),
        };
        Vec2::new(u as f32, v as f32)
    }

    /// The footprint at `p` given the screen derivatives of the object-space position.
    #[must_use]
    pub fn map_footprint(&self, p: Vec3, dp_dx: Vec3, dp_dy: Vec3, n: Vec3) -> Footprint {
        let q = self.centred(p);
        let d = |dp: Vec3| -> Vec2 {
            let dp = dp.as_dvec3();
            let (du, dv) = match (self.chart(n), self) {
                (Some(axis), _) => planar_linear(dp, axis),
                (None, Projection::Cylindrical) => (d_longitude(q, dp), -dp.y),
                (None, _) => (d_longitude(q, dp), d_latitude_v(q, dp)),
            };
            Vec2::new(du as f32, dv as f32)
        };
        Footprint::new(self.map(p, n), d(dp_dx), d(dp_dy))
    }

    /// True for projections with a u seam (u wraps from 1 to 0).
    #[must_use]
    pub fn has_seam(&self) -> bool {
        matches!(
            self,
            Projection::Cylindrical | Projection::Spherical | Projection::BoundingSphere { .. }
        )
    }
}

/// Per-vertex coordinates for an indexed triangle mesh. Triangles that cross the u seam get
/// their own copies of the vertices on the low side with u + 1 (and a pole vertex takes the
/// mean u of its triangle's other corners); the returned `remap[i]` is the original vertex of
/// vertex `i`, so callers copy the other attributes with it. Returns `(uvs, indices, remap)`.
#[must_use]
pub fn generate_uvs(
    projection: &Projection,
    positions: &[Vec3],
    normals: &[Vec3],
    indices: &[u32],
) -> (Vec<Vec2>, Vec<u32>, Vec<u32>) {
    let normal = |i: usize| normals.get(i).copied().unwrap_or(Vec3::Y);
    let mut uvs: Vec<Vec2> = positions
        .iter()
        .enumerate()
        .map(|(i, &p)| projection.map(p, normal(i)))
        .collect();
    let mut remap: Vec<u32> = (0..positions.len() as u32).collect();
    let mut out = indices.to_vec();
    if !projection.has_seam() {
        return (uvs, out, remap);
    }
    let is_pole = |i: usize| {
        let q = projection.centred(positions[i]);
        (q.x * q.x + q.z * q.z) < 1e-12 * q.length_squared().max(1e-30)
    };
    for tri in out.chunks_exact_mut(3) {
        if tri.iter().any(|&i| i as usize >= positions.len()) {
            continue;
        }
        let us: Vec<f32> = tri.iter().map(|&i| uvs[i as usize].x).collect();
        let poles: Vec<bool> = tri
            .iter()
            .map(|&i| is_pole(remap[i as usize] as usize))
            .collect();
        let live: Vec<f32> = us
            .iter()
            .zip(&poles)
            .filter(|(_, &p)| !p)
            .map(|(&u, _)| u)
            .collect();
        if live.is_empty() {
            continue;
        }
        let (lo, hi) = live
            .iter()
            .fold((f32::MAX, f32::MIN), |(a, b), &u| (a.min(u), b.max(u)));
        let crosses = hi - lo > 0.5;
        let shifted = |u: f32| if crosses && u < 0.5 { u + 1.0 } else { u };
        let mean_u = live.iter().map(|&u| shifted(u)).sum::<f32>() / live.len() as f32;
        for (k, idx) in tri.iter_mut().enumerate() {
            let old = uvs[*idx as usize];
            let new_u = if poles[k] { mean_u } else { shifted(old.x) };
            if new_u != old.x {
                uvs.push(Vec2::new(new_u, old.y));
                remap.push(remap[*idx as usize]);
                *idx = (uvs.len() - 1) as u32;
            }
        }
    }
    (uvs, out, remap)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cylindrical_u_follows_the_lecture() {
        let c = Projection::Cylindrical;
        let side = |x: f32, z: f32| c.map(Vec3::new(x, 0.0, z), Vec3::new(x, 0.0, z)).x;
        // θ = 0 at +x: u = 1 − 0 = 1 (the seam); θ = +90° at +z: u = 1 − ¼; θ = −90° at −z: u = ¼.
        assert!((side(1.0, 0.0) - 1.0).abs() < 1e-6);
        assert!((side(0.0, 1.0) - 0.75).abs() < 1e-6);
        assert!((side(0.0, -1.0) - 0.25).abs() < 1e-6);
        assert!((side(-1.0, 0.0) - 0.5).abs() < 1e-6);
        // Lecture v = P_y + 0.5, stored flipped (v down).
        let v = c.map(Vec3::new(1.0, 0.25, 0.0), Vec3::X).y;
        assert!((v - (1.0 - 0.75)).abs() < 1e-6);
    }

    #[test]
    fn cylinder_caps_are_planar() {
        let c = Projection::Cylindrical;
        let uv = c.map(Vec3::new(0.2, 0.5, -0.3), Vec3::Y);
        assert!((uv - Vec2::new(0.7, 0.2)).length() < 1e-6);
    }

    #[test]
    fn spherical_latitude() {
        let s = Projection::Spherical;
        let p = Vec3::new(0.0, 1.0, 1.0).normalize() * 3.0;
        let v_lecture = (45f32.to_radians() / std::f32::consts::PI) + 0.5;
        assert!((s.map(p, p).y - (1.0 - v_lecture)).abs() < 1e-6);
    }

    #[test]
    fn bounding_sphere_uses_the_direction_from_the_centre() {
        let c = Vec3::new(5.0, 1.0, -2.0);
        let b = Projection::BoundingSphere { center: c };
        let d = Vec3::new(0.3, -0.4, 0.5);
        assert!(
            (b.map(c + d * 7.0, Vec3::Y) - Projection::Spherical.map(d, Vec3::Y)).length() < 1e-6
        );
    }

    #[test]
    fn cube_picks_the_dominant_normal_axis() {
        let uv = Projection::Cube.map(Vec3::new(0.5, 0.1, 0.2), Vec3::X);
        assert!((uv - Vec2::new(0.3, 0.4)).length() < 1e-6);
    }

    #[test]
    fn derivatives_match_finite_differences_and_ignore_the_seam() {
        for proj in [Projection::Cylindrical, Projection::Spherical] {
            // Just beside the seam (θ slightly below 0 → u ≈ 0; slightly above → u ≈ 1).
            let p = Vec3::new(1.0, 0.2, -1e-4);
            let dp = Vec3::new(0.0, 0.0, 2e-4);
            let fp = proj.map_footprint(p, dp, Vec3::ZERO, p);
            // The finite difference wraps through the seam; the analytic one does not.
            let analytic = fp.duv_dx.x;
            assert!(analytic.abs() < 1e-3, "{proj:?}: {analytic}");
            let q = Vec3::new(0.6, 0.3, 0.7);
            let h = Vec3::new(1e-3, 2e-3, -1e-3);
            let fp = proj.map_footprint(q, h, Vec3::ZERO, q);
            let fd = proj.map(q + h * 0.5, q) - proj.map(q - h * 0.5, q);
            assert!(
                (fp.duv_dx - fd).length() < 1e-5,
                "{proj:?}: {} vs {fd}",
                fp.duv_dx
            );
        }
    }

    #[test]
    fn per_vertex_seam_triangles_are_split() {
        // A triangle straddling the +x seam: u ≈ 0.99 and u ≈ 0.01.
        let positions = [
            Vec3::new(1.0, 0.0, 0.06),
            Vec3::new(1.0, 0.0, -0.06),
            Vec3::new(1.0, 0.3, 0.0),
        ];
        let (uvs, idx, remap) =
            generate_uvs(&Projection::Cylindrical, &positions, &positions, &[0, 1, 2]);
        let us: Vec<f32> = idx.iter().map(|&i| uvs[i as usize].x).collect();
        let spread = us.iter().cloned().fold(f32::MIN, f32::max)
            - us.iter().cloned().fold(f32::MAX, f32::min);
        assert!(spread < 0.1, "{us:?}");
        assert_eq!(remap.len(), uvs.len());
    }
}
