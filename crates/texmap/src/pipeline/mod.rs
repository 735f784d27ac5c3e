//! The rasterization pipeline, stage by stage.
//!
//! ```text
//! transform   VertexShader → ClipVertex → PostVertex (fixed-point screen position, depth,
//!             1/w, outcodes): the vertex stage, one viewport for the frame
//! clip        homogeneous clipping against near, far and a guard band → convex polygon
//! setup       primitive assembly: culling, orientation, bounding box → Prim;
//!             per tile: edge functions and attribute planes
//! bin         Prims → per-tile lists (fixed order: the draw order)
//! raster      per tile: coverage (top-left rule), depth, 2×2 quads → FragmentShader, blending
//! interpolate attribute planes: perspective-correct (a/w and 1/w, divide per pixel) or affine
//! framebuffer tile colour/depth samples, blending, MSAA resolve, frame assembly, SSAA
//! ```
//!
//! Rules the stages share:
//! - Clip space is OpenGL's: NDC x, y, z in [−1, 1]. Window depth is `z_ndc·½ + ½` in [0, 1],
//!   stored as `f32` (24-bit mantissa: with near 0.05 and far 1000 it resolves about 6 mm at
//!   100 units); the test is `LESS`, the buffer cleared to 1.
//! - Screen space: x right, y down, row 0 at the top; pixel centres at (x + ½, y + ½).
//!   Vertex positions are snapped to [`SUBPIXEL_BITS`] = 8 fractional bits; edge functions are
//!   exact `i64` (positions stay within the guard band, |coordinate| < 2^17 pixels, so products
//!   stay below 2^53).
//! - Fill rule: top-left, so a closed mesh covers every pixel (sample) exactly once.
//! - Determinism: tiles are independent and each is drawn in primitive order, so the image does
//!   not depend on the thread count.
//!
//! The pipeline knows nothing of materials: a draw's [`VertexShader`] makes clip-space vertices
//! with up to [`MAX_VARYINGS`] floats each, the pipeline interpolates them and hands 2×2 quads
//! to a [`FragmentShader`].

mod batch;
pub mod bin;
pub mod clip;
mod covered;
pub mod framebuffer;
pub mod interpolate;
mod quad_edges;
pub mod raster;
pub mod setup;
mod tile_plan;
pub mod transform;

use crate::pixels::{ClearTiles, Pixels};
use glam::Vec4;
use rayon::prelude::*;

pub use batch::BATCH;
pub use bin::{bin_prims, Bins, TILE};
pub use clip::{clip_polygon, ClipPolygon};
pub use framebuffer::{downsample_box, TileBuffer, TileColors};
pub use interpolate::Planes;
pub use raster::{rasterize_tile, TileStats};
pub use setup::{assemble_triangle, Prim};
pub use transform::{transform_call, ClipVertex, PostVertex, ScreenCall, VertexShader, Viewport};

/// The number of floats a vertex can carry to the fragment shader: the largest draw `render`
/// makes, a double-sided Gouraud draw (uv, D and S for each side, vertex colour, a projected
/// texture's object position and normal, a second uv set). Quads carry all of them, so it is
/// kept as small as that draw allows (the cost of raising it is in DESIGN.md's decision log).
pub const MAX_VARYINGS: usize = 26;

/// Fractional bits of the fixed-point screen positions.
pub const SUBPIXEL_BITS: u32 = 8;

/// One pixel in fixed-point units.
pub const SUBPIXEL_ONE: i64 = 1 << SUBPIXEL_BITS;

/// Which faces are culled. The front face is counter-clockwise in normalized device
/// coordinates (OpenGL's default).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CullMode {
    #[default]
    None,
    Back,
    Front,
}

/// How attributes are interpolated across a triangle.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum Interpolation {
    /// Perspective-correct: interpolate `a/w` and `1/w` linearly in screen space, divide per
    /// pixel.
    #[default]
    Perspective,
    /// Screen-linear (affine) interpolation, as early software renderers did: textures swim.
    Affine,
    /// Affine interpolation on triangles split in screen space until every edge's affine
    /// error (the screen distance between where the edge midpoint's attributes are and where
    /// affine interpolation puts them) is below `max_error_px`: each edge over it is bisected
    /// at its screen midpoint, with perspective-correct attributes there, and the piece is cut
    /// into two, three or four. Whether and where an edge splits depends on the edge alone,
    /// so neighbours split shared edges identically: watertight, like the other modes (up to
    /// [`setup::MAX_SUBDIVISION`] steps per triangle).
    Subdivide { max_error_px: f32 },
}

/// Fixed-function state of one draw call.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawState {
    /// Number of varyings the vertices carry (≤ [`MAX_VARYINGS`]).
    pub varyings: usize,
    pub cull: CullMode,
    /// True when the transform from object to world mirrors (negative determinant): the
    /// winding of front faces flips.
    pub mirrored: bool,
    pub depth_test: bool,
    pub depth_write: bool,
    /// Premultiplied "over" blending instead of replacing the colour.
    pub blend: bool,
    /// Texture reads the shader makes per shaded pixel (statistics only).
    pub texture_reads: u32,
    /// The shader keeps every pixel it is given (no alpha test, no discard): with one
    /// sample a pixel, such opaque draws first find each pixel's nearest depth, and only
    /// the quads that reach it are shaded (`raster.rs`).
    pub keeps_all: bool,
}

impl Default for DrawState {
    fn default() -> Self {
        DrawState {
            varyings: 0,
            cull: CullMode::None,
            mirrored: false,
            depth_test: true,
            depth_write: true,
            blend: false,
            texture_reads: 0,
            keeps_all: false,
        }
    }
}

/// A draw call: its vertex shader, an index list (three per triangle) and its state.
#[derive(Clone, Copy)]
pub struct DrawCall<'a> {
    pub vertices: &'a dyn VertexShader,
    pub indices: &'a [u32],
    pub state: DrawState,
}

/// A 2×2 block of pixels handed to the fragment shader.
///
/// Pixel `j` of the quad is at `(x + (j & 1), y + (j >> 1))`. Every pixel has interpolated
/// varyings, also those outside the triangle (helper pixels), so derivatives are defined.
#[derive(Clone, Copy, Debug)]
pub struct Quad {
    pub x: u32,
    pub y: u32,
    /// Bit `j` set: pixel `j` is covered and passed the depth test.
    pub mask: u8,
    pub front_facing: bool,
    /// Varying `k` of the four pixels, one lane per pixel (structure of arrays, so a shader
    /// can work on the four pixels at once): `varyings[k][j]`.
    pub varyings: [Vec4; MAX_VARYINGS],
}

impl Quad {
    /// ∂/∂x of varying `i` (coarse: the quad's top row).
    #[inline]
    #[must_use]
    pub fn ddx(&self, i: usize) -> f32 {
        self.varyings[i].y - self.varyings[i].x
    }

    /// ∂/∂y of varying `i` (coarse: the quad's left column).
    #[inline]
    #[must_use]
    pub fn ddy(&self, i: usize) -> f32 {
        self.varyings[i].z - self.varyings[i].x
    }

    /// Pixel `j`'s varyings: `quad.pixel(j)[k]` is varying `k`.
    #[inline]
    #[must_use]
    pub fn pixel(&self, j: usize) -> PixelVaryings<'_> {
        PixelVaryings {
            varyings: &self.varyings,
            j,
        }
    }
}

/// One pixel's varyings of a [`Quad`], indexed by varying.
#[derive(Clone, Copy)]
pub struct PixelVaryings<'a> {
    varyings: &'a [Vec4; MAX_VARYINGS],
    j: usize,
}

impl std::ops::Index<usize> for PixelVaryings<'_> {
    type Output = f32;
    #[inline(always)]
    fn index(&self, k: usize) -> &f32 {
        &self.varyings[k][self.j]
    }
}

/// Colours the pixels of a quad.
pub trait FragmentShader: Sync {
    /// Writes premultiplied linear RGBA for the pixels in `quad.mask` (of draw `draw`) to
    /// `out`, and returns the pixels kept (a subset of `quad.mask`; clear a bit to discard).
    fn shade(&self, draw: u32, quad: &Quad, out: &mut [Vec4; 4]) -> u8;

    /// [`FragmentShader::shade`] for several quads of draw `draw` (disjoint pixels of one
    /// primitive): `out[i]` and `kept[i]` for `quads[i]`. The default shades them one by one;
    /// a shader may interleave their work.
    fn shade_batch(&self, draw: u32, quads: &[Quad], out: &mut [[Vec4; 4]], kept: &mut [u8]) {
        for ((quad, o), k) in quads.iter().zip(out.iter_mut()).zip(kept.iter_mut()) {
            *k = self.shade(draw, quad, o);
        }
    }

    /// [`FragmentShader::shade_batch`] of one-sample quads whose colours replace the
    /// tile's (no blending), written straight into `tile` instead of returned: a shader
    /// that keeps every pixel of each quad's mask for draw `draw` may do so and return
    /// true (one pass over the batch rather than a second to write it); `scratch` is at
    /// least `quads.len()` long. Whether it does must depend on the draw alone (a false
    /// answer is not asked again for the draw's other batches in a tile). The default
    /// returns false, and the quads are shaded and written as usual.
    fn shade_into_tile(
        &self,
        draw: u32,
        quads: &[Quad],
        scratch: &mut [[Vec4; 4]],
        tile: &mut TileColors,
    ) -> bool {
        let _ = (draw, quads, scratch, tile);
        false
    }
}

/// The render target of [`draw`].
#[derive(Clone, Copy, Debug)]
pub struct Target {
    pub width: u32,
    pub height: u32,
    /// MSAA samples per pixel: 1, 2, 4, 8 or 16.
    pub samples: u32,
    /// Premultiplied linear colour where nothing is drawn.
    pub clear_color: Vec4,
    pub interpolation: Interpolation,
    /// Painter's algorithm: draw everything back to front without the depth buffer.
    pub depth_sort: bool,
}

/// What a frame cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DrawStats {
    pub triangles_submitted: u64,
    pub triangles_after_clip: u64,
    pub pixels_shaded: u64,
    pub texture_samples: u64,
}

/// Runs the whole pipeline: shades and projects every call's vertices, assembles, clips and
/// sets up every triangle, bins them, rasterizes the tiles in parallel (rayon's current pool)
/// and resolves.
///
/// Returns the resolved colour, `width·height` premultiplied linear pixels, top row first.
/// Opaque draws are drawn in order, then blended draws in order (sorting them is the caller's
/// business, as on a GPU), each draw's triangles in index order; with `depth_sort`, every
/// triangle back to front by its farthest vertex instead.
pub fn draw(
    calls: &[DrawCall],
    shader: &dyn FragmentShader,
    target: &Target,
) -> (Pixels, DrawStats) {
    let mut color = Pixels::default();
    let stats = draw_into(calls, shader, target, &mut color);
    (color, stats)
}

/// [`draw`] into `color`, which is resized to `width·height` and overwritten: reusing one
/// buffer across frames spares the page faults of a fresh one (tens of megabytes at 1080p),
/// and the writes of the tiles that hold the clear colour already: an empty tile that the
/// last draw into `color` left holding the same clear colour alone, at the same size, is not
/// written again (the note `Pixels::take_clear_tiles` gives; a mutable borrow of `color`
/// forgets it). The pixels are those a fresh buffer would get.
pub fn draw_into(
    calls: &[DrawCall],
    shader: &dyn FragmentShader,
    target: &Target,
    color: &mut Pixels,
) -> DrawStats {
    // The frame's one viewport: the vertex stage and clipping both project through it.
    let viewport = Viewport::new(target.width, target.height);
    let screen: Vec<ScreenCall> = calls.iter().map(|c| transform_call(c, &viewport)).collect();
    let calls = &screen[..];
    let mut stats = DrawStats {
        triangles_submitted: calls.iter().map(|c| (c.indices.len() / 3) as u64).sum(),
        ..Default::default()
    };

    // Assemble in parallel over fixed chunks; concatenate in order.
    const CHUNK: usize = 4096;
    let jobs: Vec<(usize, usize)> = calls
        .iter()
        .enumerate()
        .flat_map(|(ci, c)| {
            let n = c.indices.len() / 3;
            (0..n.div_ceil(CHUNK)).map(move |k| (ci, k * CHUNK))
        })
        .collect();
    let parts: Vec<(Vec<Prim>, Vec<PostVertex>)> = jobs
        .par_iter()
        .map(|&(ci, start)| {
            let call = &calls[ci];
            let n = call.indices.len() / 3;
            let end = (start + CHUNK).min(n);
            let mut prims = Vec::with_capacity(end - start);
            let mut extra = Vec::new();
            for t in start..end {
                let idx = &call.indices[3 * t..3 * t + 3];
                assemble_triangle(
                    call,
                    ci as u32,
                    [idx[0], idx[1], idx[2]],
                    &viewport,
                    target.interpolation,
                    &mut prims,
                    &mut extra,
                );
            }
            (prims, extra)
        })
        .collect();
    let (prims, extra) = concat_parts(parts);
    stats.triangles_after_clip = prims.len() as u64;

    // Draw order: opaque, then blended, each in submission order; or the painter's sort.
    let mut order: Vec<u32> = Vec::with_capacity(prims.len());
    if target.depth_sort {
        order.extend(0..prims.len() as u32);
        order.sort_by(|a, b| {
            prims[*b as usize]
                .sort_depth
                .total_cmp(&prims[*a as usize].sort_depth)
        });
    } else {
        let blend = |i: &u32| calls[prims[*i as usize].call as usize].state.blend;
        order.extend((0..prims.len() as u32).filter(|i| !blend(i)));
        order.extend((0..prims.len() as u32).filter(blend));
    }

    let bins = bin_prims(&prims, &order, target.width, target.height);
    let ctx = raster::RasterContext {
        calls,
        extra: &extra,
        prims: &prims,
        shader,
        target,
    };
    // Tiles in parallel, each writing its own rows of the target: many more tasks than
    // threads, so the costly tiles (the floor at the horizon) balance out.
    let (w, h) = (target.width as usize, target.height as usize);
    let clear = ClearTiles {
        width: target.width,
        height: target.height,
        color: target.clear_color.to_array().map(f32::to_bits),
        tiles: (0..bins.tile_count())
            .map(|t| bins.tile_prims(t).is_empty())
            .collect(),
    };
    // The tiles the last draw into `color` left holding the clear colour alone, if it was of
    // this size and clear colour (taken before anything borrows the pixels mutably, which
    // forgets it).
    let known = color
        .take_clear_tiles()
        .filter(|k| (k.width, k.height, k.color) == (clear.width, clear.height, clear.color));
    if color.len() != w * h {
        // Every tile writes all its pixels: a new frame needs no clearing pass.
        *color = Pixels::zeroed(w * h);
    }
    // An empty tile that holds the clear colour already is not written again (the turntable's
    // background: on the 1080p plane, the sky's half of the frame).
    let unchanged = |t: usize| clear.tiles[t] && known.as_ref().is_some_and(|k| k.tiles[t]);
    // Each tile's rows of the target, tile after tile in one vector (a few allocations a
    // frame, not one a tile): a band of tiles' rows cut into their tiles' pieces, taken
    // tile by tile.
    let tile = TILE as usize;
    let mut rows: Vec<&mut [Vec4]> = Vec::with_capacity(bins.tile_count() * tile);
    let mut band_rows = Vec::with_capacity(tile);
    for band in color.chunks_mut(w * tile) {
        band_rows.extend(band.chunks_mut(w).map(|row| row.chunks_mut(tile)));
        for _ in 0..bins.tiles_x {
            rows.extend(band_rows.iter_mut().filter_map(Iterator::next));
        }
        band_rows.clear();
    }
    let mut tiles: Vec<&mut [&mut [Vec4]]> = Vec::with_capacity(bins.tile_count());
    let mut rest = &mut rows[..];
    for t in 0..bins.tile_count() {
        let r = bins.tile_rect(t);
        let count = (r.y1 - r.y0) as usize;
        let (mine, tail) = std::mem::take(&mut rest).split_at_mut(count);
        tiles.push(mine);
        rest = tail;
    }
    let samples = raster::sample_count(target);
    let tile_stats: Vec<TileStats> = tiles
        .into_par_iter()
        .enumerate()
        .map(|(t, rows)| {
            if unchanged(t) {
                return TileStats::default();
            }
            TileBuffer::with_thread_buffer(samples, |buf| {
                raster::rasterize_tile(&ctx, &bins, t, buf, rows)
            })
        })
        .collect();
    color.set_clear_tiles(Box::new(clear));
    for ts in tile_stats {
        stats.pixels_shaded += ts.pixels_shaded;
        stats.texture_samples += ts.texture_samples;
    }
    stats
}

/// The assembled chunks' primitives and extra vertices, each in one vector, in order; a
/// primitive's extra vertex references move by the extra vertices of the chunks before it.
/// The primitives are copied in parallel (tens of megabytes for a large mesh).
fn concat_parts(parts: Vec<(Vec<Prim>, Vec<PostVertex>)>) -> (Vec<Prim>, Vec<PostVertex>) {
    let mut bases = Vec::with_capacity(parts.len());
    let mut extra = Vec::with_capacity(parts.iter().map(|p| p.1.len()).sum());
    for (_, e) in &parts {
        bases.push(extra.len() as u32);
        extra.extend_from_slice(e);
    }
    let total = parts.iter().map(|p| p.0.len()).sum();
    let mut prims: Vec<Prim> = Vec::with_capacity(total);
    let mut pieces = Vec::with_capacity(parts.len());
    let mut rest = &mut prims.spare_capacity_mut()[..total];
    for (p, _) in &parts {
        let (piece, tail) = std::mem::take(&mut rest).split_at_mut(p.len());
        pieces.push(piece);
        rest = tail;
    }
    pieces
        .into_par_iter()
        .zip(parts.par_iter())
        .zip(bases.par_iter())
        .for_each(|((piece, (p, _)), &base)| {
            for (d, prim) in piece.iter_mut().zip(p) {
                let mut prim = *prim;
                if base > 0 {
                    for v in &mut prim.v {
                        if *v & setup::EXTRA_VERTEX != 0 {
                            *v += base;
                        }
                    }
                }
                d.write(prim);
            }
        });
    // SAFETY: the pieces cover the first `total` elements and each was written above.
    unsafe { prims.set_len(total) };
    (prims, extra)
}
