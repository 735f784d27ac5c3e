//! The sign of a mesh's distance field: the generalized winding number (Jacobson, Kavan &
//! Sorkine-Hornung 2013), w(q) = Σ Ω_t(q) / 4π over the triangles' solid angles, which is 1
//! inside a closed, outward-oriented mesh, 0 outside, and degrades gracefully (a smooth value
//! near ½ across a hole) where the mesh is open. A point is inside when w ≥ ½.
//!
//! Evaluated by Barill et al.'s fast winding number (SIGGRAPH 2018) on the distance tree's
//! nodes: far from a node (beyond [`BETA`] × its radius) its triangles act as one dipole,
//! Ω ≈ (p̃ − q)·N / |p̃ − q|³, with N the node's summed area vector and p̃ its area-weighted
//! centroid (the first-order term of their expansion); near, its children are visited, and at
//! a leaf each triangle's exact solid angle (Van Oosterom & Strackee 1983) is summed.
//!
//! The sign of a voxel needs only w on the right side of ½: `tests` compare the approximation
//! with the exact sum on meshes and points near and far.

use glam::Vec3A;

use super::bvh::{Bvh, Tri};

/// A node is far enough to be one dipole when the query is more than `BETA` × its radius
/// from its centroid (Barill et al. use 2 with a second-order term; the first-order term
/// alone is kept accurate by a larger ratio).
pub(super) const BETA: f32 = 2.5;

/// Per node of a [`Bvh`]: the dipole and the squared distance beyond which it is used.
#[derive(Clone, Copy, Debug)]
struct Dipole {
    centre: Vec3A,
    /// Σ ½ (b − a) × (c − a): the area vector.
    area: Vec3A,
    /// (BETA × radius)², radius: the farthest vertex from `centre`.
    far2: f32,
}

/// The winding-number evaluator over a built [`Bvh`].
#[derive(Debug)]
pub(super) struct Winding {
    dipoles: Vec<Dipole>,
}

impl Winding {
    /// The dipoles of every node of `bvh`.
    pub fn new(bvh: &Bvh) -> Winding {
        let mut dipoles = vec![
            Dipole {
                centre: Vec3A::ZERO,
                area: Vec3A::ZERO,
                far2: 0.0,
            };
            bvh.nodes.len()
        ];
        fill(bvh, 0, &mut dipoles);
        Winding { dipoles }
    }

    /// The winding number at `q`.
    pub fn at(&self, bvh: &Bvh, q: Vec3A) -> f32 {
        let mut stack = [0u32; 64];
        let mut top = 1;
        let mut sum = 0.0f32;
        while top > 0 {
            top -= 1;
            let i = stack[top] as usize;
            let d = &self.dipoles[i];
            let r = d.centre - q;
            let r2 = r.length_squared();
            if r2 > d.far2 {
                sum += r.dot(d.area) / (r2 * r2.sqrt());
                continue;
            }
            let n = &bvh.nodes[i];
            if n.count > 0 {
                let s = n.start as usize;
                for t in &bvh.tris[s..s + n.count as usize] {
                    sum += solid_angle(t, q);
                }
            } else {
                stack[top] = (i + 1) as u32;
                stack[top + 1] = n.start;
                top += 2;
            }
        }
        sum / (4.0 * std::f32::consts::PI)
    }
}

/// Fills the dipole of node `i` and its subtree; returns its (area-weighted centroid sum,
/// total area, area vector) so the parent can combine them.
fn fill(bvh: &Bvh, i: usize, out: &mut [Dipole]) -> (Vec3A, f32, Vec3A) {
    let n = bvh.nodes[i];
    let (csum, asum, avec) = if n.count > 0 {
        let s = n.start as usize;
        let mut acc = (Vec3A::ZERO, 0.0, Vec3A::ZERO);
        for t in &bvh.tris[s..s + n.count as usize] {
            let v = (t.b - t.a).cross(t.c - t.a) * 0.5;
            let a = v.length();
            acc.0 += (t.a + t.b + t.c) / 3.0 * a;
            acc.1 += a;
            acc.2 += v;
        }
        acc
    } else {
        let l = fill(bvh, i + 1, out);
        let r = fill(bvh, n.start as usize, out);
        (l.0 + r.0, l.1 + r.1, l.2 + r.2)
    };
    let centre = if asum > 0.0 {
        csum / asum
    } else {
        (n.lo + n.hi) * 0.5
    };
    // The radius: the farthest corner of the node's box bounds the farthest vertex.
    let radius = (n.hi - centre).abs().max((centre - n.lo).abs()).length();
    out[i] = Dipole {
        centre,
        area: avec,
        far2: (BETA * radius) * (BETA * radius),
    };
    (csum, asum, avec)
}

/// The signed solid angle of the triangle seen from `q` (Van Oosterom & Strackee):
/// positive when its counter-clockwise side faces away from `q`.
#[inline]
pub(super) fn solid_angle(t: &Tri, q: Vec3A) -> f32 {
    let (a, b, c) = (t.a - q, t.b - q, t.c - q);
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let det = a.dot(b.cross(c));
    let den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    2.0 * det.atan2(den)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An octahedron-subdivided unit sphere, outward-oriented.
    fn sphere(levels: u32) -> Vec<Tri> {
        let v = [
            Vec3A::X,
            Vec3A::NEG_X,
            Vec3A::Y,
            Vec3A::NEG_Y,
            Vec3A::Z,
            Vec3A::NEG_Z,
        ];
        let faces = [
            (0, 2, 4),
            (2, 1, 4),
            (1, 3, 4),
            (3, 0, 4),
            (2, 0, 5),
            (1, 2, 5),
            (3, 1, 5),
            (0, 3, 5),
        ];
        let mut tris: Vec<Tri> = faces
            .iter()
            .map(|&(a, b, c)| Tri {
                a: v[a],
                b: v[b],
                c: v[c],
            })
            .collect();
        for _ in 0..levels {
            tris = tris
                .iter()
                .flat_map(|t| {
                    let ab = ((t.a + t.b) * 0.5).normalize();
                    let bc = ((t.b + t.c) * 0.5).normalize();
                    let ca = ((t.c + t.a) * 0.5).normalize();
                    [
                        Tri {
                            a: t.a,
                            b: ab,
                            c: ca,
                        },
                        Tri {
                            a: ab,
                            b: t.b,
                            c: bc,
                        },
                        Tri {
                            a: ca,
                            b: bc,
                            c: t.c,
                        },
                        Tri {
                            a: ab,
                            b: bc,
                            c: ca,
                        },
                    ]
                })
                .collect();
        }
        tris
    }

    #[test]
    fn fast_winding_number_follows_the_exact_sum() {
        let tris = sphere(4);
        let bvh = Bvh::build(&tris);
        let w = Winding::new(&bvh);
        let mut seed = 3u32;
        let mut rnd = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1u32 << 24) as f32 * 4.0 - 2.0
        };
        let mut worst = 0.0f32;
        for _ in 0..400 {
            let q = Vec3A::new(rnd(), rnd(), rnd());
            let exact: f32 =
                tris.iter().map(|t| solid_angle(t, q)).sum::<f32>() / (4.0 * std::f32::consts::PI);
            let fast = w.at(&bvh, q);
            worst = worst.max((fast - exact).abs());
            // The tessellated sphere's inside, away from the facets' chords.
            let r = q.length();
            if r < 0.97 {
                assert!((exact - 1.0).abs() < 1e-3, "{q}: {exact}");
            }
            if r > 1.01 {
                assert!(exact.abs() < 1e-3, "{q}: {exact}");
            }
        }
        assert!(worst < 0.02, "fast winding number off by {worst}");
    }

    #[test]
    fn a_hole_and_flipped_faces_keep_the_sign() {
        let mut tris = sphere(3);
        // Remove a cap of faces (a hole) and flip a few elsewhere.
        tris.retain(|t| (t.a + t.b + t.c).z / 3.0 < 0.9);
        for t in tris.iter_mut().step_by(37) {
            std::mem::swap(&mut t.b, &mut t.c);
        }
        let bvh = Bvh::build(&tris);
        let w = Winding::new(&bvh);
        for q in [
            Vec3A::ZERO,
            Vec3A::new(0.3, -0.2, 0.5),
            Vec3A::new(0.0, 0.0, -0.8),
        ] {
            assert!(w.at(&bvh, q) > 0.5, "{q}");
        }
        for q in [
            Vec3A::new(0.0, 0.0, 1.5),
            Vec3A::new(1.3, 0.4, 0.0),
            Vec3A::splat(3.0),
        ] {
            assert!(w.at(&bvh, q) < 0.5, "{q}");
        }
    }
}
