//! A bounding volume hierarchy over triangles and the exact closest-triangle query.
//!
//! Build: a binary tree of axis-aligned boxes, split at the median centroid along the
//! longest side of the centroids' box, leaves of at most [`LEAF_SIZE`] triangles; nodes in
//! depth-first order (a node's left child follows it), triangles reordered to match, so a
//! leaf's triangles are contiguous. The median split is deterministic (same tree for the
//! same triangles), balanced (depth ⌈log₂(n / 4)⌉, so the query's fixed stack cannot
//! overflow) and builds in O(n log n).
//!
//! Query: depth first, the nearer child first, a node skipped when its box is farther than
//! the best triangle found so far. The caller may pass a first guess (the previous voxel's
//! triangle, see `mesh`), which prunes from the start.
//!
//! Point-to-triangle distance: the closest point by Voronoi regions (vertex, edge, face) of
//! Ericson, *Real-Time Collision Detection* (2005), §5.1.5; a triangle with no area falls back
//! to its three edges.

use glam::Vec3A;

/// The most triangles in a leaf.
pub(super) const LEAF_SIZE: usize = 4;

/// A triangle as the queries read it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Tri {
    pub a: Vec3A,
    pub b: Vec3A,
    pub c: Vec3A,
}

/// A node: its box; a leaf's triangles `start .. start + count`, or (`count` = 0) an
/// interior node whose children are the next node and node `start`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Node {
    pub lo: Vec3A,
    pub hi: Vec3A,
    pub start: u32,
    pub count: u32,
}

/// The hierarchy: nodes (root first) and the triangles in leaf order.
#[derive(Debug)]
pub(super) struct Bvh {
    pub nodes: Vec<Node>,
    pub tris: Vec<Tri>,
}

impl Bvh {
    /// Builds the tree over `tris` (at least one).
    pub fn build(tris: &[Tri]) -> Bvh {
        let mut items: Vec<(Vec3A, u32)> = tris
            .iter()
            .enumerate()
            .map(|(i, t)| ((t.a + t.b + t.c) / 3.0, i as u32))
            .collect();
        let mut nodes = Vec::with_capacity(2 * tris.len() / LEAF_SIZE + 1);
        build_node(tris, &mut items, 0, &mut nodes);
        let tris = items.iter().map(|&(_, i)| tris[i as usize]).collect();
        Bvh { nodes, tris }
    }

    /// The squared distance from `p` to the nearest triangle and that triangle's index (in
    /// leaf order), searching only for triangles nearer than `guess` = (squared distance,
    /// index) of a known triangle.
    pub fn closest(&self, p: Vec3A, guess: (f32, u32)) -> (f32, u32) {
        let (mut best, mut best_i) = guess;
        let mut stack = [0u32; 64];
        let mut top = 0;
        let mut node = 0usize;
        loop {
            let n = &self.nodes[node];
            if n.count > 0 {
                let s = n.start as usize;
                for (k, t) in self.tris[s..s + n.count as usize].iter().enumerate() {
                    let d = tri_dist2(p, t);
                    if d < best {
                        best = d;
                        best_i = (s + k) as u32;
                    }
                }
            } else {
                let (l, r) = (node + 1, n.start as usize);
                let dl = box_dist2(p, &self.nodes[l]);
                let dr = box_dist2(p, &self.nodes[r]);
                let (near, dn, far, df) = if dl <= dr {
                    (l, dl, r, dr)
                } else {
                    (r, dr, l, dl)
                };
                if dn < best {
                    if df < best {
                        stack[top] = far as u32;
                        top += 1;
                    }
                    node = near;
                    continue;
                }
            }
            // Next: the deepest pending node still nearer than the best.
            loop {
                if top == 0 {
                    return (best, best_i);
                }
                top -= 1;
                let cand = stack[top] as usize;
                if box_dist2(p, &self.nodes[cand]) < best {
                    node = cand;
                    break;
                }
            }
        }
    }
}

fn build_node(tris: &[Tri], items: &mut [(Vec3A, u32)], start: usize, nodes: &mut Vec<Node>) {
    let (mut lo, mut hi) = (Vec3A::splat(f32::INFINITY), Vec3A::splat(f32::NEG_INFINITY));
    let (mut clo, mut chi) = (lo, hi);
    for &(c, i) in items.iter() {
        let t = &tris[i as usize];
        lo = lo.min(t.a).min(t.b).min(t.c);
        hi = hi.max(t.a).max(t.b).max(t.c);
        clo = clo.min(c);
        chi = chi.max(c);
    }
    let me = nodes.len();
    nodes.push(Node {
        lo,
        hi,
        start: start as u32,
        count: items.len() as u32,
    });
    if items.len() <= LEAF_SIZE {
        return;
    }
    let ext = chi - clo;
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |a, b| {
        a.0[axis].total_cmp(&b.0[axis]).then(a.1.cmp(&b.1))
    });
    let (left, right) = items.split_at_mut(mid);
    build_node(tris, left, start, nodes);
    let r = nodes.len();
    build_node(tris, right, start + mid, nodes);
    nodes[me].start = r as u32;
    nodes[me].count = 0;
}

/// Squared distance from `p` to a node's box (0 inside).
#[inline]
fn box_dist2(p: Vec3A, n: &Node) -> f32 {
    let d = (n.lo - p).max(p - n.hi).max(Vec3A::ZERO);
    d.length_squared()
}

/// Squared distance from `p` to the segment `[a, b]`.
#[inline]
fn segment_dist2(p: Vec3A, a: Vec3A, b: Vec3A) -> f32 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).length_squared()
}

/// Squared distance from `p` to the triangle (Ericson's Voronoi-region walk).
#[inline]
pub(super) fn tri_dist2(p: Vec3A, t: &Tri) -> f32 {
    let (a, b, c) = (t.a, t.b, t.c);
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.length_squared();
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return bp.length_squared();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (ap - ab * v).length_squared();
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return cp.length_squared();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (ap - ac * w).length_squared();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (bp - (c - b) * w).length_squared();
    }
    let sum = va + vb + vc;
    if !(sum > 0.0) {
        // No area: the nearest point is on an edge.
        return segment_dist2(p, a, b)
            .min(segment_dist2(p, b, c))
            .min(segment_dist2(p, a, c));
    }
    // Inside the face: the distance to its plane.
    let n = ab.cross(ac);
    let h = ap.dot(n);
    h * h / n.length_squared()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> Tri {
        Tri {
            a: a.into(),
            b: b.into(),
            c: c.into(),
        }
    }

    /// Brute force over many points near a triangle: the minimum over a dense sampling of
    /// the triangle is never below the exact distance, and comes within the sampling step.
    #[test]
    fn triangle_distance_matches_dense_sampling() {
        let t = tri([0.0, 0.0, 0.0], [2.0, 0.2, 0.0], [0.5, 1.5, 0.3]);
        let n = 200;
        let mut samples = Vec::new();
        for i in 0..=n {
            for j in 0..=(n - i) {
                let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
                samples.push(t.a + (t.b - t.a) * u + (t.c - t.a) * v);
            }
        }
        let mut seed = 1u32;
        let mut rnd = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1u32 << 24) as f32 * 5.0 - 2.0
        };
        for _ in 0..200 {
            let p = Vec3A::new(rnd(), rnd(), rnd());
            let exact = tri_dist2(p, &t).sqrt();
            let brute = samples
                .iter()
                .map(|&s| (p - s).length())
                .fold(f32::INFINITY, f32::min);
            assert!(brute >= exact - 1e-5, "{p}: {brute} < {exact}");
            assert!(brute - exact < 0.02, "{p}: {brute} vs {exact}");
        }
    }

    #[test]
    fn degenerate_triangles_measure_to_their_edges() {
        let line = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]);
        assert!((tri_dist2(Vec3A::new(1.5, 1.0, 0.0), &line) - 1.0).abs() < 1e-6);
        assert!((tri_dist2(Vec3A::new(3.0, 0.0, 0.0), &line) - 1.0).abs() < 1e-6);
        let point = tri([1.0, 1.0, 1.0], [1.0, 1.0, 1.0], [1.0, 1.0, 1.0]);
        assert!((tri_dist2(Vec3A::ZERO, &point) - 3.0).abs() < 1e-6);
    }

    #[test]
    fn tree_query_equals_brute_force() {
        let mut seed = 7u32;
        let mut rnd = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        let tris: Vec<Tri> = (0..300)
            .map(|_| {
                let c = Vec3A::new(rnd(), rnd(), rnd()) * 4.0;
                let e = |r: &mut dyn FnMut() -> f32| Vec3A::new(r(), r(), r()) * 0.3;
                Tri {
                    a: c,
                    b: c + e(&mut rnd),
                    c: c + e(&mut rnd),
                }
            })
            .collect();
        let bvh = Bvh::build(&tris);
        for _ in 0..500 {
            let p = Vec3A::new(rnd(), rnd(), rnd()) * 6.0 - 1.0;
            let brute = tris
                .iter()
                .map(|t| tri_dist2(p, t))
                .fold(f32::INFINITY, f32::min);
            let (d, i) = bvh.closest(p, (f32::INFINITY, 0));
            assert_eq!(d, brute);
            assert_eq!(tri_dist2(p, &bvh.tris[i as usize]), d);
            // A first guess changes nothing but the work.
            assert_eq!(bvh.closest(p, (tri_dist2(p, &bvh.tris[3]), 3)).0, brute);
        }
    }
}
