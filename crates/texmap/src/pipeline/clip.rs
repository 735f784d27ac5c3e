//! Clip: Sutherland–Hodgman clipping of a polygon in homogeneous clip space.
//!
//! Planes, each written `d(c) ≥ 0` inside: near `z + w`, far `w − z`, and the guard band
//! `g·w ± x`, `g·w ± y`. Only the planes some vertex is outside of are applied. Attributes are
//! interpolated linearly in clip space, which is correct before the perspective divide.
//!
//! A new vertex is always computed from the inside end of the edge towards the outside end,
//! so the two triangles sharing an edge create bit-identical vertices: clipping keeps the mesh
//! watertight.

use glam::Vec4;

use super::transform::{outcode, ClipVertex, Viewport};

/// Most vertices a triangle clipped by six planes can have.
pub const MAX_POLYGON: usize = 9;

impl ClipVertex {
    #[inline]
    fn lerp(&self, other: &ClipVertex, t: f32, n: usize) -> ClipVertex {
        let mut varyings = self.varyings;
        for (a, b) in varyings[..n].iter_mut().zip(&other.varyings[..n]) {
            *a += (b - *a) * t;
        }
        ClipVertex {
            clip: self.clip + (other.clip - self.clip) * t,
            varyings,
        }
    }
}

/// A convex polygon in clip space.
#[derive(Clone, Copy, Debug)]
pub struct ClipPolygon {
    pub len: usize,
    pub verts: [ClipVertex; MAX_POLYGON],
}

impl ClipPolygon {
    /// A triangle.
    #[must_use]
    pub fn triangle(v: [ClipVertex; 3]) -> Self {
        let mut verts = [v[0]; MAX_POLYGON];
        verts[..3].copy_from_slice(&v);
        ClipPolygon { len: 3, verts }
    }

    /// The polygon's vertices.
    #[must_use]
    pub fn vertices(&self) -> &[ClipVertex] {
        &self.verts[..self.len]
    }
}

#[inline]
fn distance(plane: u8, c: Vec4, vp: &Viewport) -> f32 {
    let (gx, gy) = (vp.guard_x as f32, vp.guard_y as f32);
    match plane {
        outcode::NEAR => c.z + c.w,
        outcode::FAR => c.w - c.z,
        outcode::GUARD_LEFT => c.x + gx * c.w,
        outcode::GUARD_RIGHT => gx * c.w - c.x,
        outcode::GUARD_BOTTOM => c.y + gy * c.w,
        _ => gy * c.w - c.y,
    }
}

/// Clips `poly` in place against every plane in `planes` (outcode bits), interpolating the
/// first `n` varyings. The result may be empty (`len < 3`).
pub fn clip_polygon(poly: &mut ClipPolygon, planes: u8, vp: &Viewport, n: usize) {
    const ORDER: [u8; 6] = [
        outcode::NEAR,
        outcode::FAR,
        outcode::GUARD_LEFT,
        outcode::GUARD_RIGHT,
        outcode::GUARD_BOTTOM,
        outcode::GUARD_TOP,
    ];
    let mut out = *poly;
    for plane in ORDER {
        if planes & plane == 0 || poly.len < 3 {
            continue;
        }
        let src = &poly.verts[..poly.len];
        let mut d = [0.0f32; MAX_POLYGON];
        for (di, v) in d.iter_mut().zip(src) {
            *di = distance(plane, v.clip, vp);
        }
        out.len = 0;
        for i in 0..src.len() {
            let j = if i + 1 == src.len() { 0 } else { i + 1 };
            let (a, b) = (&src[i], &src[j]);
            let (da, db) = (d[i], d[j]);
            let a_in = da >= 0.0;
            if a_in && out.len < MAX_POLYGON {
                out.verts[out.len] = *a;
                out.len += 1;
            }
            if a_in != (db >= 0.0) && out.len < MAX_POLYGON {
                // From the inside end, so shared edges give identical vertices.
                let v = if a_in {
                    a.lerp(b, da / (da - db), n)
                } else {
                    b.lerp(a, db / (db - da), n)
                };
                out.verts[out.len] = v;
                out.len += 1;
            }
        }
        std::mem::swap(poly, &mut out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::MAX_VARYINGS;

    fn v(x: f32, y: f32, z: f32, w: f32) -> ClipVertex {
        ClipVertex {
            clip: Vec4::new(x, y, z, w),
            varyings: [x; MAX_VARYINGS],
        }
    }

    #[test]
    fn clipped_vertices_lie_in_the_frustum() {
        let vp = Viewport::new(100, 100);
        // One vertex behind the camera, one beyond far.
        let mut p = ClipPolygon::triangle([
            v(0.0, 0.0, -3.0, -1.0),
            v(0.5, 0.2, 0.0, 1.0),
            v(-0.5, 0.4, 5.0, 2.0),
        ]);
        clip_polygon(&mut p, outcode::NEAR | outcode::FAR, &vp, 1);
        assert!(p.len >= 3);
        for q in p.vertices() {
            let c = q.clip;
            assert!(c.z >= -c.w - 1e-5 && c.z <= c.w + 1e-5, "{c}");
            assert!(c.w > 0.0);
            assert!(
                (q.varyings[0] - c.x).abs() < 1e-5,
                "attributes follow the position"
            );
        }
    }

    #[test]
    fn shared_edges_clip_to_identical_vertices() {
        let vp = Viewport::new(100, 100);
        let (a, b) = (v(0.0, 0.0, -3.0, -1.0), v(0.5, 0.2, 0.0, 1.0));
        let mut p = ClipPolygon::triangle([a, b, v(-0.5, 0.4, 0.0, 1.0)]);
        let mut q = ClipPolygon::triangle([b, a, v(0.5, -0.4, 0.0, 1.0)]);
        clip_polygon(&mut p, outcode::NEAR, &vp, 1);
        clip_polygon(&mut q, outcode::NEAR, &vp, 1);
        let new_p: Vec<Vec4> = p.vertices().iter().map(|v| v.clip).collect();
        assert!(q
            .vertices()
            .iter()
            .any(|v| new_p.contains(&v.clip) && v.clip != b.clip));
    }

    #[test]
    fn everything_behind_is_removed() {
        let vp = Viewport::new(100, 100);
        let mut p = ClipPolygon::triangle([
            v(0.0, 0.0, -3.0, -1.0),
            v(1.0, 0.0, -3.0, -1.0),
            v(0.0, 1.0, -3.0, -1.0),
        ]);
        clip_polygon(&mut p, outcode::NEAR, &vp, 1);
        assert!(p.len < 3);
    }
}
