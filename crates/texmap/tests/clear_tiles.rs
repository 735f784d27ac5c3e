//! The frame's note of its clear tiles (`Pixels::take_clear_tiles`): a draw into pixels that
//! an earlier draw of the same size and clear colour left holding the clear colour alone in a
//! tile does not write that tile again when it is empty again; the pixels are what a draw into
//! fresh ones gives, frame after frame, and a mutable borrow of them forgets the note.

mod common;

use common::Uv;
use glam::{Vec2, Vec4};
use texmap::pipeline::{
    self, ClipVertex, DrawCall, DrawState, Interpolation, Target, MAX_VARYINGS,
};
use texmap::pixels::Pixels;

/// A triangle over the clip-space box `lo`–`hi` (x right, y up), its uv the corners'.
fn triangle(lo: Vec2, hi: Vec2) -> Vec<ClipVertex> {
    [
        (lo, Vec2::ZERO),
        (Vec2::new(hi.x, lo.y), Vec2::X),
        (hi, Vec2::ONE),
    ]
    .map(|(p, uv)| {
        let mut varyings = [0.0; MAX_VARYINGS];
        varyings[..2].copy_from_slice(&uv.to_array());
        ClipVertex {
            clip: p.extend(0.5).extend(1.0),
            varyings,
        }
    })
    .to_vec()
}

fn target(w: u32, h: u32, clear: Vec4) -> Target {
    Target {
        width: w,
        height: h,
        samples: 1,
        clear_color: clear,
        interpolation: Interpolation::Perspective,
        depth_sort: false,
    }
}

/// Draws `verts` (none: an empty frame) into `into`.
fn draw_into(verts: &[ClipVertex], t: &Target, into: &mut Pixels) {
    let indices = [0, 1, 2];
    let verts = verts.to_vec();
    let call = DrawCall {
        vertices: &verts,
        indices: if verts.is_empty() { &[] } else { &indices },
        state: DrawState {
            cull: pipeline::CullMode::None,
            ..Default::default()
        },
    };
    pipeline::draw_into(&[call], &Uv, t, into);
}

/// Frames whose triangle moves, leaves, comes back, under two clear colours and two sizes,
/// drawn one after another into one buffer: each frame's pixels are a fresh buffer's.
#[test]
fn frames_drawn_into_one_buffer_are_frames_drawn_into_fresh_ones() {
    let (c0, c1) = (Vec4::new(0.1, 0.2, 0.3, 1.0), Vec4::new(0.0, 0.0, 0.5, 0.5));
    let left = triangle(Vec2::new(-0.9, -0.8), Vec2::new(-0.2, 0.7));
    let right = triangle(Vec2::new(0.3, -0.9), Vec2::new(0.95, 0.1));
    let frames: [(&[ClipVertex], u32, u32, Vec4); 8] = [
        (&left, 200, 150, c0),
        (&right, 200, 150, c0),
        (&right, 200, 150, c0),
        (&[], 200, 150, c0),
        (&left, 200, 150, c0),
        (&left, 200, 150, c1),
        (&left, 130, 90, c1),
        (&[], 130, 90, c1),
    ];
    let mut reused = Pixels::default();
    for (k, &(verts, w, h, clear)) in frames.iter().enumerate() {
        let t = target(w, h, clear);
        draw_into(verts, &t, &mut reused);
        let mut fresh = Pixels::default();
        draw_into(verts, &t, &mut fresh);
        assert!(*reused == *fresh, "frame {k}: the reused buffer differs");
    }
}

/// A tile noted clear is not written by the next draw when it is empty again: a pixel changed
/// in it (the note put back by hand) stays changed, while a tile the triangle covers is drawn
/// again; a mutable borrow alone forgets the note, and the next draw writes every tile.
#[test]
fn tiles_noted_clear_are_not_written_again() {
    let clear = Vec4::new(0.1, 0.2, 0.3, 1.0);
    let t = target(200, 150, clear);
    // Over the bottom right: the top-left tile (tile 0, 64 × 64 pixels) stays empty.
    let tri = triangle(Vec2::new(0.3, -0.95), Vec2::new(0.95, -0.2));
    let mut px = Pixels::default();
    draw_into(&tri, &t, &mut px);
    let drawn = px.to_vec();
    let covered = 140 * 200 + 180;
    assert_ne!(
        drawn[covered], clear,
        "the triangle covers pixel (180, 140)"
    );
    let note = px.take_clear_tiles().expect("a draw leaves its note");
    assert!(note.tiles[0], "tile 0 holds the clear colour alone");
    assert!(
        !note.tiles.iter().all(|&c| c),
        "the triangle's tiles are not clear"
    );
    assert_eq!((note.width, note.height), (200, 150));

    let marker = Vec4::new(9.0, 8.0, 7.0, 6.0);
    px[0] = marker;
    px[covered] = marker;
    assert!(
        px.take_clear_tiles().is_none(),
        "a mutable borrow forgets the note"
    );
    px.set_clear_tiles(note);
    draw_into(&tri, &t, &mut px);
    assert_eq!(
        px[0], marker,
        "tile 0, noted clear and empty again, is not written"
    );
    assert_eq!(px[covered], drawn[covered], "a covered tile is drawn again");

    // Without the note (a mutable borrow since the draw), every tile is written.
    px[0] = marker;
    draw_into(&tri, &t, &mut px);
    assert_eq!(px.to_vec(), drawn);
}
