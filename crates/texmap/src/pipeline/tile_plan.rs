//! How a tile is drawn, decided once per tile before its quads are walked: with a depth
//! pre-pass (its primitives could hide one another), owned by one primitive (it writes every
//! pixel before any other does: the tile is not cleared), or cleared and drawn in order; and
//! the tests on a primitive's box and edges over a tile these decisions and the walk share.

use super::bin::TileRect;
use super::interpolate::{depth_plane, Plane};
use super::raster::RasterContext;
use super::setup::Edges;
use super::Prim;

/// Whether primitive `pi` takes part in the depth pre-pass: its draw tests and writes depth,
/// does not blend and keeps every pixel it shades ([`super::DrawState::keeps_all`]).
#[inline]
pub(super) fn prepassed(ctx: &RasterContext, pi: u32) -> bool {
    let state = ctx.calls[ctx.prims[pi as usize].call as usize].state;
    state.keeps_all && state.depth_test && state.depth_write && !state.blend
}

/// The position in `prims` of the primitive that owns tile `rect` (one sample a pixel), if
/// one does: the first that reaches the tile ([`reaches`]: those before it draw nothing
/// there), when it [`owns`] it. Such a tile is not cleared, and its owner is drawn without
/// the depth test (`raster.rs`'s `Depths::owned`).
pub(super) fn owner(ctx: &RasterContext, rect: TileRect, prims: &[u32]) -> Option<usize> {
    let first = prims.iter().position(|&pi| reaches(ctx, rect, pi))?;
    owns(ctx, rect, prims[first]).then_some(first)
}

/// Whether primitive `pi`, drawn first into tile `rect`, writes every pixel of it with the
/// colour and depth that a cleared tile would have given: it covers every pixel centre of the
/// tile, its draw does not blend, keeps every pixel it shades and writes depth, and its depth
/// is below the clear depth (1) with a margin over the whole tile, so its depth test could not
/// fail.
pub(super) fn owns(ctx: &RasterContext, rect: TileRect, pi: u32) -> bool {
    let prim = &ctx.prims[pi as usize];
    let call = &ctx.calls[prim.call as usize];
    let state = call.state;
    let (x1, y1) = (rect.x1 as i32 - 1, rect.y1 as i32 - 1);
    let (x0, y0) = (rect.x0 as i32, rect.y0 as i32);
    let boxed =
        prim.bbox[0] <= x0 && prim.bbox[1] <= y0 && prim.bbox[2] >= x1 && prim.bbox[3] >= y1;
    if !(boxed && state.keeps_all && state.depth_write && !state.blend) {
        return false;
    }
    let v = prim.v.map(|r| ctx.vertex(call, r));
    let edges = Edges::new(v, x0, y0);
    let (ext_x, ext_y) = ((x1 - x0) as i64, (y1 - y0) as i64);
    if !(0..3).all(|k| edge_range(&edges, k, ext_x, ext_y).0 >= 0) {
        return false;
    }
    // The depth plane's greatest value at the tile's pixel centres (it is linear: at a
    // corner), with a margin far above the rounding of the per-pixel depths.
    let z = depth_plane(v, x0, y0);
    let zmax = z.c + (z.dx * (x1 - x0) as f32).max(0.0) + (z.dy * (y1 - y0) as f32).max(0.0);
    !state.depth_test || zmax < 1.0 - 1.0e-4
}

/// The quads' extent of `prim` in tile `rect`, `(x0, y0, x1, y1)` (`x0`, `y0` even, ends
/// inclusive): its bounding box clipped to the tile; `None` when they do not meet.
#[inline]
pub(super) fn quad_extent(prim: &Prim, rect: TileRect) -> Option<(i32, i32, i32, i32)> {
    let x0 = prim.bbox[0].max(rect.x0 as i32) & !1;
    let y0 = prim.bbox[1].max(rect.y0 as i32) & !1;
    let x1 = prim.bbox[2].min(rect.x1 as i32 - 1);
    let y1 = prim.bbox[3].min(rect.y1 as i32 - 1);
    (x0 <= x1 && y0 <= y1).then_some((x0, y0, x1, y1))
}

/// The least and greatest value of edge `k` over the rectangle of pixel centres `ext_x` ×
/// `ext_y` pixels from the edges' reference pixel (edges are linear: at its corners).
#[inline]
pub(super) fn edge_range(edges: &Edges, k: usize, ext_x: i64, ext_y: i64) -> (i64, i64) {
    let (ax, ay) = (edges.dx[k] * ext_x, edges.dy[k] * ext_y);
    (
        edges.e[k] + ax.min(0) + ay.min(0),
        edges.e[k] + ax.max(0) + ay.max(0),
    )
}

/// Whether primitive `pi` may cover a pixel centre of tile `rect`: false when its box misses
/// the tile or one edge is negative at every pixel centre of its quads there (the walk's own
/// skip at one sample a pixel).
pub(super) fn reaches(ctx: &RasterContext, rect: TileRect, pi: u32) -> bool {
    let prim = &ctx.prims[pi as usize];
    let Some((x0, y0, x1, y1)) = quad_extent(prim, rect) else {
        return false;
    };
    let call = &ctx.calls[prim.call as usize];
    let v = prim.v.map(|r| ctx.vertex(call, r));
    let edges = Edges::new(v, x0, y0);
    let (ext_x, ext_y) = ((x1 - x0) as i64 | 1, (y1 - y0) as i64 | 1);
    (0..3).all(|k| edge_range(&edges, k, ext_x, ext_y).1 >= 0)
}

/// Whether the pre-passed primitives of tile `rect` could hide one another: two of them at
/// least reach it, and not all lie in one plane. Primitives that only share the tile's box
/// cannot hide each other, nor can the pieces of one flat surface (a clipped polygon's fan,
/// a quad's two triangles), which meet only along their edges: a pre-pass over them would
/// spare no shading. (The image is the same either way: the pre-pass only skips the
/// shading of what ends up hidden.)
pub(super) fn could_hide(ctx: &RasterContext, rect: TileRect, prims: &[u32]) -> bool {
    let mut first: Option<Plane> = None;
    for &pi in prims {
        if !(prepassed(ctx, pi) && reaches(ctx, rect, pi)) {
            continue;
        }
        let prim = &ctx.prims[pi as usize];
        let call = &ctx.calls[prim.call as usize];
        let v = prim.v.map(|r| ctx.vertex(call, r));
        let z = depth_plane(v, rect.x0 as i32, rect.y0 as i32);
        match first {
            None => first = Some(z),
            Some(f) if !same_plane(f, z) => return true,
            Some(_) => {}
        }
    }
    false
}

/// Whether depth planes `a` and `b` (relative to a tile's first pixel) agree over the tile
/// within a few units in the last place of a depth near 1: one plane, set up from two
/// triangles' vertices.
pub(super) fn same_plane(a: Plane, b: Plane) -> bool {
    let t = super::bin::TILE as f32;
    (a.c - b.c).abs() + t * ((a.dx - b.dx).abs() + (a.dy - b.dy).abs()) <= 4.0e-6
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_of_one_plane_share_it_and_other_planes_do_not() {
        use super::super::transform::{PostVertex, Viewport};
        use super::super::MAX_VARYINGS;
        use glam::{Mat4, Vec3};
        // A ground plane seen at a grazing angle (the peers' plane), split into a fan of
        // triangles, against the same fan lifted a hundredth of a unit or tilted a little.
        let vp = Viewport::new(1920, 1080);
        let proj = Mat4::perspective_rh_gl(60f32.to_radians(), 16.0 / 9.0, 0.05, 1000.0)
            * Mat4::look_at_rh(Vec3::Y, Vec3::new(0.0, 0.0, -50.0), Vec3::Y);
        let vertex = |p: Vec3| PostVertex::new(proj * p.extend(1.0), [0.0; MAX_VARYINGS], &vp);
        let fan = |lift: f32, tilt: f32| {
            let points = [
                (-3.0, -4.0),
                (3.0, -4.0),
                (4.0, -12.0),
                (0.0, -30.0),
                (-5.0, -9.0),
            ];
            points
                .iter()
                .map(|&(x, z)| vertex(Vec3::new(x, lift + tilt * x, z)))
                .collect::<Vec<_>>()
        };
        let (px, py) = (896, 576);
        let plane = |v: &[PostVertex], k: usize| depth_plane([&v[0], &v[k], &v[k + 1]], px, py);
        let flat = fan(0.0, 0.0);
        for k in 1..4 {
            assert!(same_plane(plane(&flat, 1), plane(&flat, k)), "piece {k}");
        }
        for other in [fan(0.01, 0.0), fan(0.0, 0.001)] {
            assert!(!same_plane(plane(&flat, 1), plane(&other, 1)));
        }
    }
}
