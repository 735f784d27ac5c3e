//! Built-in primitive meshes for scene files: plane, cube, sphere, cylinder, cone, torus.
//!
//! Each is centred at the origin with unit-ish size, has unit normals and uv in [0, 1] in
//! texmap's convention (v down the image), and counter-clockwise front faces pointing out.

use std::f32::consts::TAU;

use glam::{Mat4, Vec2, Vec3};

use super::builtin;
use super::Mesh;

/// A primitive shape and its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Primitive {
    /// A `width` × `depth` rectangle in the xz plane facing +y, `divisions` quads a side;
    /// u along +x, v along +z.
    Plane {
        width: f32,
        depth: f32,
        divisions: u32,
    },
    /// An axis-aligned cube of side `size`, each face with uv in [0, 1].
    Cube { size: f32 },
    /// A uv sphere; u around +y, v from the north pole (0) to the south pole (1).
    Sphere {
        radius: f32,
        segments: u32,
        rings: u32,
    },
    /// A capped cylinder along y; the side's u goes around, v top (0) to bottom (1).
    Cylinder {
        radius: f32,
        height: f32,
        segments: u32,
    },
    /// A capped cone along y, apex up.
    Cone {
        radius: f32,
        height: f32,
        segments: u32,
    },
    /// A torus around y: `major` radius of the ring, `minor` radius of the tube.
    Torus {
        major: f32,
        minor: f32,
        segments: u32,
        sides: u32,
    },
}

/// The largest segment count accepted (guards against absurd meshes from scene files).
pub const MAX_SEGMENTS: u32 = 4096;

/// The most vertices one primitive may have (a 2047² plane): a scene file asking for more is
/// refused before anything is allocated (at 36 bytes a vertex in the mesh and 136 in the
/// frame's vertex stage, about 0.7 GB).
pub const MAX_PRIMITIVE_VERTICES: u64 = 1 << 22;

impl Primitive {
    /// Builds the mesh with material `material`.
    #[must_use]
    pub fn mesh(&self, material: usize) -> Mesh {
        let seg = |s: u32| s.clamp(3, MAX_SEGMENTS) as usize;
        let mut m = match *self {
            Primitive::Plane {
                width,
                depth,
                divisions,
            } => plane(width, depth, divisions.clamp(1, MAX_SEGMENTS) as usize),
            Primitive::Cube { size } => {
                let mut m = builtin::cube(material, Mat4::IDENTITY);
                for p in &mut m.positions {
                    *p *= size;
                }
                m
            }
            Primitive::Sphere {
                radius,
                segments,
                rings,
            } => {
                let mut m = builtin::uv_sphere(seg(segments), seg(rings), material);
                for p in &mut m.positions {
                    *p *= radius;
                }
                m
            }
            Primitive::Cylinder {
                radius,
                height,
                segments,
            } => lathe(radius, radius, height, seg(segments)),
            Primitive::Cone {
                radius,
                height,
                segments,
            } => lathe(radius, 0.0, height, seg(segments)),
            Primitive::Torus {
                major,
                minor,
                segments,
                sides,
            } => torus(major, minor, seg(segments), seg(sides)),
        };
        m.material = material;
        fix_winding(&mut m);
        m
    }
}

fn plane(w: f32, d: f32, n: usize) -> Mesh {
    let mut m = Mesh::default();
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            m.positions
                .push(Vec3::new((u - 0.5) * w, 0.0, (v - 0.5) * d));
            m.normals.push(Vec3::Y);
            m.uvs.push(Vec2::new(u, v));
        }
    }
    grid_indices(&mut m.indices, n, n, 0);
    m
}

/// Quads of a (cols+1) × (rows+1) vertex grid starting at `base`.
fn grid_indices(out: &mut Vec<u32>, cols: usize, rows: usize, base: usize) {
    let w = cols + 1;
    for j in 0..rows {
        for i in 0..cols {
            let a = (base + j * w + i) as u32;
            let (b, c, d) = (a + 1, a + w as u32 + 1, a + w as u32);
            out.extend_from_slice(&[a, d, c, a, c, b]);
        }
    }
}

/// A surface of revolution from `r_bottom` at y = −h/2 to `r_top` at y = +h/2, with caps.
fn lathe(r_bottom: f32, r_top: f32, h: f32, n: usize) -> Mesh {
    let mut m = Mesh::default();
    let slope = (r_bottom - r_top) / h.max(f32::MIN_POSITIVE);
    for (row, (r, y)) in [(r_top, h * 0.5), (r_bottom, -h * 0.5)]
        .into_iter()
        .enumerate()
    {
        for i in 0..=n {
            let a = TAU * i as f32 / n as f32;
            let (s, c) = a.sin_cos();
            m.positions.push(Vec3::new(r * s, y, r * c));
            m.normals.push(Vec3::new(s, slope, c).normalize());
            m.uvs.push(Vec2::new(i as f32 / n as f32, row as f32));
        }
    }
    grid_indices(&mut m.indices, n, 1, 0);
    for (r, y, ny) in [(r_top, h * 0.5, 1.0f32), (r_bottom, -h * 0.5, -1.0)] {
        if r <= 0.0 {
            continue;
        }
        let centre = m.positions.len() as u32;
        m.positions.push(Vec3::new(0.0, y, 0.0));
        m.normals.push(Vec3::Y * ny);
        m.uvs.push(Vec2::splat(0.5));
        for i in 0..=n {
            let a = TAU * i as f32 / n as f32;
            let (s, c) = a.sin_cos();
            m.positions.push(Vec3::new(r * s, y, r * c));
            m.normals.push(Vec3::Y * ny);
            m.uvs.push(Vec2::new(0.5 + 0.5 * s, 0.5 + 0.5 * c));
        }
        for i in 0..n as u32 {
            m.indices
                .extend_from_slice(&[centre, centre + 1 + i, centre + 2 + i]);
        }
    }
    m
}

fn torus(big: f32, small: f32, n: usize, k: usize) -> Mesh {
    let mut m = Mesh::default();
    for j in 0..=k {
        let phi = TAU * j as f32 / k as f32;
        let (sp, cp) = phi.sin_cos();
        for i in 0..=n {
            let theta = TAU * i as f32 / n as f32;
            let (st, ct) = theta.sin_cos();
            let ring = big + small * cp;
            m.positions
                .push(Vec3::new(ring * st, small * sp, ring * ct));
            m.normals.push(Vec3::new(cp * st, sp, cp * ct));
            m.uvs
                .push(Vec2::new(i as f32 / n as f32, j as f32 / k as f32));
        }
    }
    grid_indices(&mut m.indices, n, k, 0);
    m
}

/// Makes every triangle counter-clockwise about its vertices' mean normal; drops degenerate
/// (zero-area) triangles.
fn fix_winding(m: &mut Mesh) {
    let mut out = Vec::with_capacity(m.indices.len());
    for t in m.indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| i as usize);
        let f = (m.positions[b] - m.positions[a]).cross(m.positions[c] - m.positions[a]);
        if f.length_squared() == 0.0 {
            continue;
        }
        let n = m.normals[a] + m.normals[b] + m.normals[c];
        if f.dot(n) < 0.0 {
            out.extend_from_slice(&[t[0], t[2], t[1]]);
        } else {
            out.extend_from_slice(t);
        }
    }
    m.indices = out;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all() -> Vec<Primitive> {
        vec![
            Primitive::Plane {
                width: 2.0,
                depth: 2.0,
                divisions: 2,
            },
            Primitive::Cube { size: 1.0 },
            Primitive::Sphere {
                radius: 1.0,
                segments: 16,
                rings: 8,
            },
            Primitive::Cylinder {
                radius: 0.5,
                height: 1.0,
                segments: 16,
            },
            Primitive::Cone {
                radius: 0.5,
                height: 1.0,
                segments: 16,
            },
            Primitive::Torus {
                major: 1.0,
                minor: 0.25,
                segments: 16,
                sides: 8,
            },
        ]
    }

    #[test]
    fn every_primitive_faces_out_with_unit_normals_and_uvs_in_range() {
        for p in all() {
            let m = p.mesh(3);
            assert_eq!(m.material, 3);
            assert!(m.triangle_count() > 0, "{p:?}");
            assert_eq!(m.normals.len(), m.positions.len());
            assert_eq!(m.uvs.len(), m.positions.len());
            for n in &m.normals {
                assert!((n.length() - 1.0).abs() < 1e-4, "{p:?}");
            }
            for uv in &m.uvs {
                assert!(uv.min_element() >= 0.0 && uv.max_element() <= 1.0, "{p:?}");
            }
            // A closed convex-ish solid's faces point away from its centre on average.
            if !matches!(p, Primitive::Plane { .. } | Primitive::Torus { .. }) {
                for t in m.indices.chunks_exact(3) {
                    let [a, b, c] = [t[0], t[1], t[2]].map(|i| m.positions[i as usize]);
                    let f = (b - a).cross(c - a);
                    assert!(f.dot((a + b + c) / 3.0) > 0.0, "{p:?}");
                }
            }
        }
    }
}
