//! A draw's primitives share the rasterizer's batches (one sample a pixel): the image must be
//! the one primitive-by-primitive drawing gives. The same triangles drawn as one draw (its
//! consecutive primitives' quads shaded in one batch) and as one draw a triangle (a batch
//! never holds two primitives) must give the same bits, with ties at equal depths (the first
//! triangle keeps the pixel), nearer and farther triangles over earlier ones, discarded
//! pixels, blending, the depth pre-pass on and off, and MSAA.

use glam::Vec4;
use texmap::pipeline::{
    self, ClipVertex, DrawCall, DrawState, FragmentShader, Interpolation, Quad, Target, TileColors,
};

/// Colours each pixel by its triangle (varying 0, constant over a triangle) and position;
/// with `discard`, triangles whose index is a multiple of 5 discard a pattern of pixels.
struct ByTriangle {
    discard: bool,
}
impl FragmentShader for ByTriangle {
    fn shade(&self, _: u32, q: &Quad, out: &mut [Vec4; 4]) -> u8 {
        let mut kept = q.mask;
        for (j, o) in out.iter_mut().enumerate() {
            let (x, y) = (q.x + (j as u32 & 1), q.y + (j as u32 >> 1));
            let t = q.varyings[0][j].round();
            *o = Vec4::new(t + 1.0, x as f32, y as f32, 0.75);
            if self.discard && (t as u32).is_multiple_of(5) && (x + 2 * y).is_multiple_of(3) {
                kept &= !(1 << j);
            }
        }
        kept
    }
}

/// [`ByTriangle`]'s colours (discarding nothing) written straight into the tile
/// (`FragmentShader::shade_into_tile`) rather than returned for the rasterizer to write.
struct IntoTile;
impl FragmentShader for IntoTile {
    fn shade(&self, draw: u32, q: &Quad, out: &mut [Vec4; 4]) -> u8 {
        ByTriangle { discard: false }.shade(draw, q, out)
    }

    fn shade_into_tile(
        &self,
        draw: u32,
        quads: &[Quad],
        scratch: &mut [[Vec4; 4]],
        tile: &mut TileColors,
    ) -> bool {
        for (q, o) in quads.iter().zip(scratch.iter_mut()) {
            let kept = self.shade(draw, q, o);
            assert_eq!(kept, q.mask, "IntoTile keeps every pixel");
            tile.write(q, q.mask, o);
        }
        true
    }
}

/// Small triangles over a `w × h` target in clip space: a grid of cells, two triangles each,
/// at depth 0.5; the same grid again, shifted by a third of a cell, at the same depth (ties
/// with the first) and, cell by cell, nearer or farther; then a tilted strip crossing both.
/// Each vertex carries its triangle's index as varying 0.
fn triangles() -> Vec<ClipVertex> {
    let mut out = Vec::new();
    let mut push = |corners: [(f32, f32, f32); 3]| {
        let t = (out.len() / 3) as f32;
        for (x, y, z) in corners {
            let mut varyings = [0.0; pipeline::MAX_VARYINGS];
            varyings[0] = t;
            out.push(ClipVertex {
                clip: Vec4::new(x, y, z, 1.0),
                varyings,
            });
        }
    };
    let (nx, ny) = (23, 17);
    for layer in 0..2 {
        let shift = layer as f32 / 3.0;
        for cy in 0..ny {
            for cx in 0..nx {
                let z = match (layer, (cx + cy) % 3) {
                    (0, _) | (1, 0) => 0.5,
                    (1, 1) => 0.3,
                    _ => 0.7,
                };
                let x0 = -0.95 + 1.9 * (cx as f32 + shift) / nx as f32;
                let y0 = -0.95 + 1.9 * (cy as f32 + shift) / ny as f32;
                let (x1, y1) = (x0 + 1.9 / nx as f32, y0 + 1.9 / ny as f32);
                push([(x0, y0, z), (x1, y0, z), (x1, y1, z)]);
                push([(x0, y0, z), (x1, y1, z), (x0, y1, z)]);
            }
        }
    }
    for k in 0..40 {
        let x = -0.9 + 1.8 * k as f32 / 40.0;
        let z = 0.2 + 0.6 * k as f32 / 40.0;
        push([(x, -0.9, z), (x + 0.06, -0.9, z), (x + 0.03, 0.9, 0.5)]);
    }
    out
}

/// The colours of `calls` (each a range of the triangles) drawn with `state`.
fn draw(
    vertices: &Vec<ClipVertex>,
    calls: &[std::ops::Range<u32>],
    state: DrawState,
    samples: u32,
) -> Vec<u32> {
    // Draws that keep all their pixels (the pre-pass's condition) discard none.
    let shader = ByTriangle {
        discard: !state.keeps_all,
    };
    draw_with(vertices, calls, state, samples, &shader)
}

/// [`draw`] with `shader`.
fn draw_with(
    vertices: &Vec<ClipVertex>,
    calls: &[std::ops::Range<u32>],
    state: DrawState,
    samples: u32,
    shader: &dyn FragmentShader,
) -> Vec<u32> {
    let indices: Vec<u32> = (0..vertices.len() as u32).collect();
    let calls: Vec<DrawCall> = calls
        .iter()
        .map(|r| DrawCall {
            vertices,
            indices: &indices[r.start as usize..r.end as usize],
            state,
        })
        .collect();
    let target = Target {
        width: 150,
        height: 110,
        samples,
        clear_color: Vec4::new(0.1, 0.2, 0.3, 1.0),
        interpolation: Interpolation::Perspective,
        depth_sort: false,
    };
    let (color, _) = pipeline::draw(&calls, shader, &target);
    color
        .iter()
        .flat_map(|v| v.to_array().map(f32::to_bits))
        .collect()
}

#[test]
fn a_draws_primitives_sharing_batches_draw_what_one_at_a_time_draws() {
    let vertices = triangles();
    let n = vertices.len() as u32;
    // One draw of every triangle (a range in a list of one).
    let one_draw = std::iter::once(0..n).collect::<Vec<_>>();
    let each: Vec<_> = (0..n / 3).map(|t| 3 * t..3 * t + 3).collect();
    for samples in [1, 4] {
        for (blend, keeps_all, depth_write) in [
            (false, false, true),
            (false, true, true),
            (true, false, true),
            (false, false, false),
        ] {
            let state = DrawState {
                varyings: 1,
                blend,
                keeps_all,
                depth_write,
                ..Default::default()
            };
            let shared = draw(&vertices, &one_draw, state, samples);
            let alone = draw(&vertices, &each, state, samples);
            let case = format!("{samples} samples, blend {blend}, keeps_all {keeps_all}");
            assert!(
                shared == alone,
                "{case}, depth_write {depth_write}: images differ"
            );
            // Both layers and the strip show.
            let firsts: std::collections::BTreeSet<u32> = shared
                .chunks(4)
                .map(|c| f32::from_bits(c[0]) as u32)
                .collect();
            assert!(
                firsts.len() > 500,
                "{case}: {} triangles show",
                firsts.len()
            );
        }
    }
}

/// A shader that writes its colours straight into the tile (`shade_into_tile`) draws what
/// the rasterizer's writes of the same colours draw: the quads at their pixels, partly
/// covered ones at their covered pixels only, the depths of those that write them (the
/// overlapping layers and the strip test them), one draw or one draw a triangle, with the
/// depth pre-pass and without. (Blended draws and MSAA never take it.)
#[test]
fn colours_written_into_the_tile_are_those_the_rasterizer_writes() {
    let vertices = triangles();
    let n = vertices.len() as u32;
    let one_draw = std::iter::once(0..n).collect::<Vec<_>>();
    let each: Vec<_> = (0..n / 3).map(|t| 3 * t..3 * t + 3).collect();
    for calls in [&one_draw, &each] {
        for (keeps_all, depth_write) in [(false, true), (true, true), (false, false)] {
            let state = DrawState {
                varyings: 1,
                keeps_all,
                depth_write,
                ..Default::default()
            };
            let returned = draw_with(&vertices, calls, state, 1, &ByTriangle { discard: false });
            let written = draw_with(&vertices, calls, state, 1, &IntoTile);
            assert!(
                returned == written,
                "{} draws, keeps_all {keeps_all}, depth_write {depth_write}: images differ",
                calls.len()
            );
        }
    }
}
