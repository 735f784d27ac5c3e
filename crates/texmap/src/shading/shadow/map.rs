//! One shadow map: the depth of the nearest caster seen from a light over a square grid of
//! texels, and where a receiving point falls in it ([`ShadowMap::locate`]).
//!
//! A map's view looks down its −z (a view matrix, rigid); depth is the view depth `−z` in
//! world units, linear for both kinds of view, so biases and penumbrae are lengths. Texel
//! `(i, j)` covers `[i, i + 1) × [j, j + 1)` in texel coordinates, `u` to the right and `v`
//! down the rows (as the rasterizer's pixels: the map is drawn through the pipeline, texel
//! centres at `+½`).

use glam::{Mat4, Vec2, Vec3, Vec4};

/// The side of the square blocks a map's texels are stored in.
pub const BLOCK: usize = 8;

/// The steepest receiver slope a lookup follows, in texels of depth per texel (tan θ; θ ≈ 83°):
/// beyond it a plane seen edge-on would ask for unbounded depths.
pub const MAX_SLOPE: f32 = 8.0;

/// How a map's texels see the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MapView {
    /// Parallel rays along −z (a directional light): the view-space rectangle `min..max`
    /// (x right, y up) covers the map.
    Orthographic { min: Vec2, max: Vec2 },
    /// Rays from the view's origin (a spot light, a point light's cube face): at depth `d`
    /// the square `|x|, |y| ≤ tan_half·d` covers the map.
    Perspective { tan_half: f32 },
}

/// A depth image seen from a light.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadowMap {
    /// The light's view (rigid: rotation and translation).
    pub view_from_world: Mat4,
    pub view: MapView,
    /// The depth range the pass draws (its near and far clip planes).
    pub near: f32,
    pub far: f32,
    /// Texels a side.
    pub size: u32,
    /// The depth of the nearest caster at each texel, +∞ where there is none, in blocks of
    /// [`BLOCK`]² texels (the blocks row-major, top row first, the texels inside a block
    /// too; [`ShadowMap::index`]), so a filter's window is a few cache lines of one page
    /// rather than rows a map's width apart. [`ShadowMap::set_rows`] fills it.
    pub depth: Vec<f32>,
    /// For each block (in the same order), what bounds its depths ([`Tile`]): so a filter's
    /// window, which touches one to four blocks, can be known lit or shadowed without reading
    /// it. Empty: unknown (every window is read). [`ShadowMap::set_rows`] and
    /// [`ShadowMap::refresh_tiles`] make them.
    pub tiles: Vec<Tile>,
}

/// What bounds the depths of one block: the least and greatest, and — when they are all
/// finite — the plane `c + a·x + b·y` fitted to them (least squares; `x`, `y` the texel's
/// column and row in the block) with `below`, how far the plane rises above the depths at
/// most (every depth ≥ plane − below). A receiver lying on a caster seen at a slope (a floor
/// in a sun's map) is surely lit where its own plane stays under the fitted one by more than
/// `below`, though the block's least depth is nearer the light than the receiver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tile {
    pub lo: f32,
    pub hi: f32,
    pub a: f32,
    pub b: f32,
    pub c: f32,
    /// +∞ when some depth is not finite (no plane).
    pub below: f32,
}

impl Tile {
    /// The bounds of one block's depths (`BLOCK²`, row by row).
    #[must_use]
    pub fn of(depths: &[f32]) -> Tile {
        let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
        let mut finite = true;
        // Sums for the least-squares plane: Σd, Σx·d, Σy·d.
        let (mut sd, mut sxd, mut syd) = (0.0f64, 0.0f64, 0.0f64);
        for (k, &d) in depths.iter().enumerate() {
            if d.is_nan() {
                (lo, hi) = (f32::NEG_INFINITY, f32::INFINITY);
            } else {
                lo = lo.min(d);
                hi = hi.max(d);
            }
            finite &= d.is_finite();
            let d = f64::from(d);
            sd += d;
            sxd += (k % BLOCK) as f64 * d;
            syd += (k / BLOCK) as f64 * d;
        }
        let none = Tile {
            lo,
            hi,
            a: 0.0,
            b: 0.0,
            c: 0.0,
            below: f32::INFINITY,
        };
        if !finite || depths.len() != BLOCK * BLOCK {
            return none;
        }
        // A full grid: x and y are independent, so each slope is its own regression.
        let side = BLOCK as f64;
        let mean = (side - 1.0) * 0.5;
        let var = side * side * (side * side - 1.0) / 12.0;
        let a = (sxd - mean * sd) / var;
        let b = (syd - mean * sd) / var;
        let c = sd / (side * side) - (a + b) * mean;
        let (a, b, c) = (a as f32, b as f32, c as f32);
        let below = depths.iter().enumerate().fold(0.0f32, |m, (k, &d)| {
            m.max(c + a * (k % BLOCK) as f32 + b * (k / BLOCK) as f32 - d)
        });
        if !below.is_finite() {
            return none;
        }
        Tile {
            a,
            b,
            c,
            below,
            ..none
        }
    }
}

/// Where a receiving point falls in a map, and the plane it lies on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Receiver {
    /// Texel coordinates (continuous).
    pub u: f32,
    pub v: f32,
    /// The point's depth.
    pub depth: f32,
    /// The depth change of the receiver's tangent plane per texel along `u` and `v`, so
    /// every texel a filter compares is compared with the plane's depth at that texel's
    /// centre (receiver-plane depth), not with the point's.
    pub du: f32,
    pub dv: f32,
    /// The world size of one texel at the point.
    pub texel: f32,
}

impl ShadowMap {
    /// The clip transform the depth pass draws with (OpenGL's conventions, square aspect).
    #[must_use]
    pub fn clip_from_world(&self) -> Mat4 {
        let projection = match self.view {
            MapView::Orthographic { min, max } => {
                Mat4::orthographic_rh_gl(min.x, max.x, min.y, max.y, self.near, self.far)
            }
            MapView::Perspective { tan_half } => {
                Mat4::perspective_rh_gl(2.0 * tan_half.atan(), 1.0, self.near, self.far)
            }
        };
        projection * self.view_from_world
    }

    /// The world size of a texel at world point `p`.
    #[inline]
    #[must_use]
    pub fn texel_at(&self, p: Vec3) -> f32 {
        match self.view {
            MapView::Orthographic { min, max } => (max - min).max_element() / self.size as f32,
            MapView::Perspective { tan_half } => {
                let depth = -self.view_from_world.transform_point3(p).z;
                depth.max(0.0) * 2.0 * tan_half / self.size as f32
            }
        }
    }

    /// Where world point `p` with unit normal `n` (facing the light) falls in the map, or
    /// `None` behind a perspective view's eye.
    #[inline]
    #[must_use]
    pub fn locate(&self, p: Vec3, n: Vec3) -> Option<Receiver> {
        let q = self.view_from_world.transform_point3(p);
        let nv = self.view_from_world.transform_vector3(n);
        let size = self.size as f32;
        let depth = -q.z;
        let r = match self.view {
            MapView::Orthographic { min, max } => {
                let t = (max - min) / size;
                // The plane n·Δ = 0 with Δ = (t.x·Δu, −t.y·Δv, −Δd).
                let facing = nv.z.max(1e-6);
                Receiver {
                    u: (q.x - min.x) / t.x,
                    v: (max.y - q.y) / t.y,
                    depth,
                    du: nv.x * t.x / facing,
                    dv: -nv.y * t.y / facing,
                    texel: t.max_element(),
                }
            }
            MapView::Perspective { tan_half } => {
                if !(depth > 0.0) {
                    return None;
                }
                // Ray slope per texel; the point is depth·(rx, ry, −1).
                let s = 2.0 * tan_half / size;
                let (rx, ry) = (q.x / depth, q.y / depth);
                // d(u, v) = c / −(n·r(u, v)) on the plane; its gradient at the point.
                let facing = (nv.z - nv.x * rx - nv.y * ry).max(1e-6);
                Receiver {
                    u: (rx + tan_half) / s,
                    v: (tan_half - ry) / s,
                    depth,
                    du: depth * nv.x * s / facing,
                    dv: -depth * nv.y * s / facing,
                    texel: depth * s,
                }
            }
        };
        let most = MAX_SLOPE * r.texel;
        Some(Receiver {
            du: r.du.clamp(-most, most),
            dv: r.dv.clamp(-most, most),
            ..r
        })
    }

    /// [`ShadowMap::locate`] at four points at once: `p` and `n` as x, y and z lanes. Lanes
    /// behind a perspective view's eye get a depth ≤ 0 (the caller skips them).
    #[inline]
    #[must_use]
    pub fn locate_quad(&self, p: [Vec4; 3], n: [Vec4; 3]) -> Receivers {
        let [qx, qy, qz] = transform_lanes(&self.view_from_world, p, 1.0);
        let [nx, ny, nz] = transform_lanes(&self.view_from_world, n, 0.0);
        let size = self.size as f32;
        let depth = -qz;
        let tiny = Vec4::splat(1e-6);
        let r = match self.view {
            MapView::Orthographic { min, max } => {
                let t = (max - min) / size;
                let facing = nz.max(tiny);
                Receivers {
                    u: (qx - Vec4::splat(min.x)) / t.x,
                    v: (Vec4::splat(max.y) - qy) / t.y,
                    depth,
                    du: nx * t.x / facing,
                    dv: -ny * t.y / facing,
                    texel: Vec4::splat(t.max_element()),
                }
            }
            MapView::Perspective { tan_half } => {
                let s = 2.0 * tan_half / size;
                let (rx, ry) = (qx / depth, qy / depth);
                let facing = (nz - nx * rx - ny * ry).max(tiny);
                // In `locate`'s order of operations: each lane equals it bit for bit.
                Receivers {
                    u: (rx + Vec4::splat(tan_half)) / s,
                    v: (Vec4::splat(tan_half) - ry) / s,
                    depth,
                    du: depth * nx * s / facing,
                    dv: -depth * ny * s / facing,
                    texel: depth * s,
                }
            }
        };
        let most = r.texel * MAX_SLOPE;
        Receivers {
            du: r.du.clamp(-most, most),
            dv: r.dv.clamp(-most, most),
            ..r
        }
    }

    /// [`ShadowMap::texel_at`] at four points (x, y and z lanes).
    #[inline]
    #[must_use]
    pub fn texel_at_quad(&self, p: [Vec4; 3]) -> Vec4 {
        match self.view {
            MapView::Orthographic { min, max } => {
                Vec4::splat((max - min).max_element() / self.size as f32)
            }
            MapView::Perspective { tan_half } => {
                let [_, _, z] = transform_lanes(&self.view_from_world, p, 1.0);
                (-z).max(Vec4::ZERO) * 2.0 * tan_half / self.size as f32
            }
        }
    }

    /// Whether texel coordinates `(u, v)` fall outside the map: nothing there was drawn, so
    /// lookups call the point lit (a directional map covers only where shadows can fall).
    #[inline(always)]
    #[must_use]
    pub fn outside(&self, u: f32, v: f32) -> bool {
        let size = self.size as f32;
        !(u >= 0.0 && v >= 0.0 && u <= size && v <= size)
    }

    /// Whether four points (x, y and z lanes) all fall more than `margin` texels outside an
    /// orthographic map (always false for a perspective one).
    #[inline]
    #[must_use]
    pub fn outside_quad(&self, p: [Vec4; 3], margin: f32) -> bool {
        let MapView::Orthographic { min, max } = self.view else {
            return false;
        };
        let [qx, qy, _] = transform_lanes(&self.view_from_world, p, 1.0);
        let t = (max - min) / self.size as f32;
        let (mx, my) = (margin * t.x, margin * t.y);
        let out = qx.cmplt(Vec4::splat(min.x - mx))
            | qx.cmpgt(Vec4::splat(max.x + mx))
            | qy.cmplt(Vec4::splat(min.y - my))
            | qy.cmpgt(Vec4::splat(max.y + my));
        out.all()
    }

    /// Where texel `(i, j)` (inside the map) is stored in [`ShadowMap::depth`].
    #[inline(always)]
    #[must_use]
    pub fn index(&self, i: usize, j: usize) -> usize {
        let blocks = (self.size as usize).div_ceil(BLOCK);
        ((j / BLOCK) * blocks + i / BLOCK) * BLOCK * BLOCK + (j % BLOCK) * BLOCK + i % BLOCK
    }

    /// Stores `rows` (`size²` depths, row-major, top row first) in the map's blocks; texels
    /// past `rows`' end are +∞.
    pub fn set_rows(&mut self, rows: impl IntoIterator<Item = f32>) {
        let n = self.size as usize;
        let side = n.div_ceil(BLOCK) * BLOCK;
        self.depth = vec![f32::INFINITY; side * side];
        for (k, d) in rows.into_iter().take(n * n).enumerate() {
            let at = self.index(k % n, k / n);
            self.depth[at] = d;
        }
        self.refresh_tiles();
    }

    /// Makes [`ShadowMap::tiles`] from the depths (after any change to them).
    pub fn refresh_tiles(&mut self) {
        let blocks = (self.size as usize).div_ceil(BLOCK);
        if self.depth.len() != blocks * blocks * BLOCK * BLOCK {
            self.tiles.clear();
            return;
        }
        self.tiles = self
            .depth
            .chunks_exact(BLOCK * BLOCK)
            .map(Tile::of)
            .collect();
    }

    /// Folds `f` over the tiles a window of `w × w` texels (`w` ≤ [`BLOCK`], inside the
    /// map) whose first texel is `(i, j)` touches — one to four — each with `(i, j)` from
    /// its block's first texel; `None` without tiles.
    #[inline(always)]
    pub fn fold_tiles<T>(
        &self,
        (i, j): (usize, usize),
        w: usize,
        init: T,
        mut f: impl FnMut(T, &Tile, f32, f32) -> T,
    ) -> Option<T> {
        if self.tiles.is_empty() {
            return None;
        }
        let blocks = (self.size as usize).div_ceil(BLOCK);
        let mut acc = init;
        for by in j / BLOCK..=(j + w - 1) / BLOCK {
            for bx in i / BLOCK..=(i + w - 1) / BLOCK {
                // Negative in the blocks to the right and below.
                let x = i as f32 - (bx * BLOCK) as f32;
                let y = j as f32 - (by * BLOCK) as f32;
                acc = f(acc, &self.tiles[by * blocks + bx], x, y);
            }
        }
        Some(acc)
    }

    /// The depth of texel `(i, j)`, clamped to the map's edges.
    #[inline(always)]
    #[must_use]
    pub fn depth_at(&self, i: i32, j: i32) -> f32 {
        let last = self.size as i32 - 1;
        let (i, j) = (i.clamp(0, last) as usize, j.clamp(0, last) as usize);
        self.depth[self.index(i, j)]
    }

    /// Texels `(i..i + 4, j)` (inside the map): one load when they share a block row.
    #[inline(always)]
    #[must_use]
    pub fn four_at(&self, i: usize, j: usize) -> Vec4 {
        let at = self.index(i, j);
        if i % BLOCK <= BLOCK - 4 {
            Vec4::from_slice(&self.depth[at..at + 4])
        } else {
            let first = BLOCK - i % BLOCK;
            let next = self.index(i + first, j);
            Vec4::from_array(std::array::from_fn(|k| {
                if k < first {
                    self.depth[at + k]
                } else {
                    self.depth[next + k - first]
                }
            }))
        }
    }
}

/// Four receivers in lanes ([`ShadowMap::locate_quad`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Receivers {
    pub u: Vec4,
    pub v: Vec4,
    pub depth: Vec4,
    pub du: Vec4,
    pub dv: Vec4,
    pub texel: Vec4,
}

impl Receivers {
    /// Lane `j`.
    #[inline(always)]
    #[must_use]
    pub fn lane(&self, j: usize) -> Receiver {
        Receiver {
            u: self.u[j],
            v: self.v[j],
            depth: self.depth[j],
            du: self.du[j],
            dv: self.dv[j],
            texel: self.texel[j],
        }
    }
}

/// `m` applied to four points (`w` = 1) or vectors (`w` = 0) given as x, y and z lanes.
#[inline(always)]
fn transform_lanes(m: &Mat4, v: [Vec4; 3], w: f32) -> [Vec4; 3] {
    let [x, y, z] = v;
    std::array::from_fn(|r| {
        let row = m.row(r);
        x * row.x + y * row.y + z * row.z + Vec4::splat(row.w * w)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ortho(size: u32) -> ShadowMap {
        ShadowMap {
            // Looking down −y from above the origin: view x = world x, view y = world −z.
            view_from_world: Mat4::look_at_rh(Vec3::new(0.0, 10.0, 0.0), Vec3::ZERO, -Vec3::Z),
            view: MapView::Orthographic {
                min: Vec2::splat(-2.0),
                max: Vec2::splat(2.0),
            },
            near: 0.0,
            far: 20.0,
            size,
            depth: vec![f32::INFINITY; (size.div_ceil(8) * 8).pow(2) as usize],
            tiles: Vec::new(),
        }
    }

    #[test]
    fn blocks_hold_every_texel_once() {
        // 13 is not a multiple of the block side: the last blocks are padded with +∞.
        let mut m = ortho(13);
        m.set_rows((0..169).map(|k| k as f32));
        assert_eq!(m.depth.len(), 16 * 16);
        for j in 0..13 {
            for i in 0..13 {
                assert_eq!(m.depth_at(i, j), (j * 13 + i) as f32);
            }
            for i in 0..=9usize {
                let four = m.four_at(i, j as usize);
                let want: [f32; 4] = std::array::from_fn(|k| (j as usize * 13 + i + k) as f32);
                assert_eq!(four.to_array(), want, "({i}, {j})");
            }
        }
        // Clamped to the edges.
        assert_eq!(m.depth_at(-3, 20), (12 * 13) as f32);
        assert_eq!(
            m.depth.iter().filter(|d| d.is_infinite()).count(),
            256 - 169
        );
    }

    #[test]
    fn an_orthographic_map_places_points_by_texel() {
        let m = ortho(4);
        // One texel is 1 unit; the world origin is the map's centre, 10 below the eye.
        let r = m.locate(Vec3::ZERO, Vec3::Y).unwrap();
        assert!(
            (r.u - 2.0).abs() < 1e-5 && (r.v - 2.0).abs() < 1e-5,
            "{r:?}"
        );
        assert!((r.depth - 10.0).abs() < 1e-5 && r.du.abs() < 1e-6 && r.dv.abs() < 1e-6);
        assert!((r.texel - 1.0).abs() < 1e-6);
        // +x is to the right, −z (the view's up) is up the rows.
        let r = m.locate(Vec3::new(1.5, 0.0, -1.5), Vec3::Y).unwrap();
        assert!(
            (r.u - 3.5).abs() < 1e-5 && (r.v - 0.5).abs() < 1e-5,
            "{r:?}"
        );
    }

    #[test]
    fn the_receiver_plane_gives_the_depth_of_neighbouring_texels() {
        let m = ortho(4);
        // A plane tilted about z: y = 0.5·x, its normal (−0.5, 1, 0) normalized. One texel
        // to the right (x + 1) it is 0.5 higher, so 0.5 nearer the light.
        let n = Vec3::new(-0.5, 1.0, 0.0).normalize();
        let r = m.locate(Vec3::ZERO, n).unwrap();
        assert!((r.du + 0.5).abs() < 1e-5 && r.dv.abs() < 1e-6, "{r:?}");
        let right = m.locate(Vec3::new(1.0, 0.5, 0.0), n).unwrap();
        assert!((right.depth - (r.depth + r.du)).abs() < 1e-5);
    }

    #[test]
    fn four_points_in_lanes_fall_where_each_falls_alone() {
        let persp = ShadowMap {
            view: MapView::Perspective { tan_half: 0.7 },
            ..ortho(64)
        };
        let points = [
            Vec3::new(0.3, 0.1, -0.2),
            Vec3::new(-1.2, 0.0, 1.7),
            Vec3::new(1.9, -0.4, 0.3),
            Vec3::new(0.0, 0.5, -1.1),
        ];
        let normals = [
            Vec3::Y,
            Vec3::new(0.2, 1.0, 0.1).normalize(),
            Vec3::new(-0.7, 0.3, 0.2).normalize(),
            Vec3::new(0.0, 0.05, 1.0).normalize(),
        ];
        let lanes = |v: [Vec3; 4]| -> [Vec4; 3] {
            std::array::from_fn(|c| Vec4::from_array(std::array::from_fn(|j| v[j][c])))
        };
        for m in [ortho(64), persp] {
            let q = m.locate_quad(lanes(points), lanes(normals));
            let t = m.texel_at_quad(lanes(points));
            for j in 0..4 {
                let (a, b) = (m.locate(points[j], normals[j]).unwrap(), q.lane(j));
                for (x, y) in [
                    (a.u, b.u),
                    (a.v, b.v),
                    (a.depth, b.depth),
                    (a.du, b.du),
                    (a.dv, b.dv),
                    (a.texel, b.texel),
                    (m.texel_at(points[j]), t[j]),
                ] {
                    assert!(
                        (x - y).abs() <= 1e-4 * x.abs().max(1.0),
                        "{j}: {a:?} vs {b:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_perspective_map_measures_depth_along_its_axis() {
        let m = ShadowMap {
            view_from_world: Mat4::look_at_rh(Vec3::new(0.0, 4.0, 0.0), Vec3::ZERO, -Vec3::Z),
            view: MapView::Perspective { tan_half: 1.0 },
            near: 0.1,
            far: 10.0,
            size: 8,
            depth: vec![f32::INFINITY; 64],
            tiles: Vec::new(),
        };
        let r = m.locate(Vec3::ZERO, Vec3::Y).unwrap();
        assert!(
            (r.u - 4.0).abs() < 1e-5 && (r.v - 4.0).abs() < 1e-5 && (r.depth - 4.0).abs() < 1e-5
        );
        // At depth 4 the map spans 8 units: a texel is 1.
        assert!((r.texel - 1.0).abs() < 1e-5 && (m.texel_at(Vec3::ZERO) - 1.0).abs() < 1e-5);
        // On the floor (facing the light) the depth stays 4 one texel to the right: the
        // gradient at the centre is zero; further out the ray meets the plane at the same depth.
        assert!(r.du.abs() < 1e-5, "{r:?}");
        let side = m.locate(Vec3::new(2.0, 0.0, 0.0), Vec3::Y).unwrap();
        assert!((side.u - 6.0).abs() < 1e-4 && (side.depth - 4.0).abs() < 1e-5);
        // Behind the eye: nothing.
        assert!(m.locate(Vec3::new(0.0, 5.0, 0.0), Vec3::Y).is_none());
        // The clip transform puts the same point at the same place.
        let c = m.clip_from_world() * Vec3::new(2.0, 0.0, 0.0).extend(1.0);
        let u = (c.x / c.w * 0.5 + 0.5) * 8.0;
        assert!((u - 6.0).abs() < 1e-4, "{u}");
    }
}
