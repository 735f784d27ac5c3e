//! Transform: the vertex stage. Each draw's [`VertexShader`] makes its clip-space vertices
//! (model → world → view → clip and whatever varyings the material needs — the caller's
//! business), and this stage applies the perspective divide and the one viewport transform
//! of the frame to every vertex, recording which clip planes it is outside of.
//!
//! Viewport: `x_s = (x/w·½ + ½)·width`, `y_s = (½ − y/w·½)·height` (row 0 at the top),
//! `z_s = z/w·½ + ½`; the divide is in `f64` and x, y are rounded to 1/256 pixel.

use glam::{DVec4, Vec4};
use rayon::prelude::*;

use super::{DrawCall, DrawState, MAX_VARYINGS, SUBPIXEL_ONE};

/// Half-width of the guard band in pixels around the viewport centre. Triangles reaching
/// beyond it are clipped; inside it they are rasterized unclipped.
pub const GUARD_PX: f64 = 65536.0;

/// Outcode bits: outside the guard band on the left/right/bottom/top, near, far, the viewport
/// sides, and non-finite.
pub mod outcode {
    pub const GUARD_LEFT: u8 = 1;
    pub const GUARD_RIGHT: u8 = 2;
    pub const GUARD_BOTTOM: u8 = 4;
    pub const GUARD_TOP: u8 = 8;
    pub const NEAR: u8 = 16;
    pub const FAR: u8 = 32;
    /// Any guard, near or far plane: the triangle must be clipped.
    pub const CLIP: u8 = 63;
}

/// The size of the render target and the guard band factors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewport {
    pub width: u32,
    pub height: u32,
    /// Guard band in NDC units: the x (y) guard planes are `|x| ≤ guard_x·w`.
    pub guard_x: f64,
    pub guard_y: f64,
}

impl Viewport {
    /// A viewport covering a `width × height` target.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        Viewport {
            width,
            height,
            guard_x: GUARD_PX / (width.max(1) as f64 * 0.5),
            guard_y: GUARD_PX / (height.max(1) as f64 * 0.5),
        }
    }
}

/// A vertex as a vertex shader leaves it (and as clipping makes new ones): the clip-space
/// position and the varyings.
#[derive(Clone, Copy, Debug)]
pub struct ClipVertex {
    pub clip: Vec4,
    pub varyings: [f32; MAX_VARYINGS],
}

/// The programmable half of the vertex stage: vertex `i` of a draw, for `i` in
/// `0..vertex_count()`. Called once per vertex, in parallel.
pub trait VertexShader: Sync {
    fn vertex_count(&self) -> usize;
    fn vertex(&self, i: usize) -> ClipVertex;
}

/// Vertices already in clip space.
impl VertexShader for Vec<ClipVertex> {
    fn vertex_count(&self) -> usize {
        self.len()
    }
    #[inline]
    fn vertex(&self, i: usize) -> ClipVertex {
        self[i]
    }
}

/// A draw call after the vertex stage: its vertices on the screen.
pub struct ScreenCall<'a> {
    pub vertices: Vec<PostVertex>,
    pub indices: &'a [u32],
    pub state: DrawState,
}

/// Runs `call`'s vertex shader on every vertex (in parallel, rayon's current pool) and
/// projects each through `vp`.
#[must_use]
pub fn transform_call<'a>(call: &DrawCall<'a>, vp: &Viewport) -> ScreenCall<'a> {
    let shader = call.vertices;
    let vertices = (0..shader.vertex_count())
        .into_par_iter()
        .with_min_len(4096)
        .map(|i| {
            let v = shader.vertex(i);
            PostVertex::new(v.clip, v.varyings, vp)
        })
        .collect();
    ScreenCall {
        vertices,
        indices: call.indices,
        state: call.state,
    }
}

/// A vertex after the vertex shader and the viewport transform.
#[derive(Clone, Copy, Debug)]
pub struct PostVertex {
    pub clip: Vec4,
    pub varyings: [f32; MAX_VARYINGS],
    /// Screen position in 1/256 pixels (valid when `outcode & CLIP == 0`).
    pub sx: i32,
    pub sy: i32,
    /// Window depth in [0, 1].
    pub z: f32,
    pub inv_w: f32,
    /// Which planes the vertex is outside of ([`outcode`]); `u8::MAX` for a non-finite
    /// position.
    pub outcode: u8,
}

impl PostVertex {
    /// Projects a clip-space vertex.
    #[must_use]
    pub fn new(clip: Vec4, varyings: [f32; MAX_VARYINGS], vp: &Viewport) -> Self {
        let mut v = PostVertex {
            clip,
            varyings,
            sx: 0,
            sy: 0,
            z: 0.0,
            inv_w: 0.0,
            outcode: u8::MAX,
        };
        if !clip.is_finite() {
            return v;
        }
        let c = clip.as_dvec4();
        let code = outcodes(c, vp);
        if code & outcode::CLIP == 0 && !(c.w > 0.0) {
            // Only w = 0 with z = 0 gets here: no projection exists.
            return v;
        }
        v.outcode = code;
        if code & outcode::CLIP == 0 {
            let inv_w = 1.0 / c.w;
            let x = (c.x * inv_w * 0.5 + 0.5) * vp.width as f64;
            let y = (0.5 - c.y * inv_w * 0.5) * vp.height as f64;
            v.sx = (x * SUBPIXEL_ONE as f64).round() as i32;
            v.sy = (y * SUBPIXEL_ONE as f64).round() as i32;
            v.z = (c.z * inv_w * 0.5 + 0.5) as f32;
            v.inv_w = inv_w as f32;
        }
        v
    }
}

impl PostVertex {
    /// Projects a vertex made by clipping or subdivision: it is inside the clip volume up to
    /// rounding, so only a finite position with `w > 0` is required.
    #[must_use]
    pub fn new_clipped(clip: Vec4, varyings: [f32; MAX_VARYINGS], vp: &Viewport) -> Self {
        let mut v = PostVertex::new(clip, varyings, vp);
        if v.outcode != 0 && clip.is_finite() && clip.w > 0.0 {
            let c = clip.as_dvec4();
            let inv_w = 1.0 / c.w;
            let lim = (GUARD_PX + 4096.0) * SUBPIXEL_ONE as f64;
            let half = (vp.width as f64 * 0.5, vp.height as f64 * 0.5);
            let x = ((c.x * inv_w) * half.0 * SUBPIXEL_ONE as f64).clamp(-lim, lim);
            let y = ((c.y * inv_w) * half.1 * SUBPIXEL_ONE as f64).clamp(-lim, lim);
            v.sx = (half.0 * SUBPIXEL_ONE as f64 + x).round() as i32;
            v.sy = (half.1 * SUBPIXEL_ONE as f64 - y).round() as i32;
            v.z = ((c.z * inv_w * 0.5 + 0.5) as f32).clamp(0.0, 1.0);
            v.inv_w = inv_w as f32;
            v.outcode = 0;
        }
        v
    }
}

fn outcodes(c: DVec4, vp: &Viewport) -> u8 {
    use outcode::*;
    let mut code = 0;
    let (gx, gy) = (vp.guard_x * c.w, vp.guard_y * c.w);
    if c.x < -gx {
        code |= GUARD_LEFT;
    }
    if c.x > gx {
        code |= GUARD_RIGHT;
    }
    if c.y < -gy {
        code |= GUARD_BOTTOM;
    }
    if c.y > gy {
        code |= GUARD_TOP;
    }
    if c.z < -c.w {
        code |= NEAR;
    }
    if c.z > c.w {
        code |= FAR;
    }
    code
}

/// The outcode of a vertex against the viewport's own side planes, split per side, for
/// trivial rejection: bits 0–3 left/right/bottom/top.
#[inline]
#[must_use]
pub fn view_sides(c: Vec4) -> u8 {
    let mut code = 0;
    if c.x < -c.w {
        code |= 1;
    }
    if c.x > c.w {
        code |= 2;
    }
    if c.y < -c.w {
        code |= 4;
    }
    if c.y > c.w {
        code |= 8;
    }
    code
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ndc_corners_map_to_the_target_corners() {
        let vp = Viewport::new(640, 360);
        let v = PostVertex::new(Vec4::new(-2.0, 2.0, 0.0, 2.0), [0.0; MAX_VARYINGS], &vp);
        assert_eq!((v.sx, v.sy, v.outcode), (0, 0, 0));
        let v = PostVertex::new(Vec4::new(1.0, -1.0, 1.0, 1.0), [0.0; MAX_VARYINGS], &vp);
        assert_eq!((v.sx, v.sy), (640 * 256, 360 * 256));
        assert_eq!(v.z, 1.0);
    }

    #[test]
    fn behind_the_camera_is_outside_near() {
        let vp = Viewport::new(64, 64);
        let v = PostVertex::new(Vec4::new(0.0, 0.0, -1.5, -1.0), [0.0; MAX_VARYINGS], &vp);
        assert!(v.outcode & outcode::NEAR != 0);
        let v = PostVertex::new(Vec4::new(f32::NAN, 0.0, 0.0, 1.0), [0.0; MAX_VARYINGS], &vp);
        assert_eq!(v.outcode, u8::MAX);
    }
}
