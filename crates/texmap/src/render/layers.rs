//! Surface detail in a frame: a draw's texture layers (read through the sampling engine,
//! each with its own uv set, transform and sampler, then combined by OpenGL's texture
//! environment, [`crate::shading::layers`]), its light map (multiplying the diffuse factor)
//! and toon shading (the lighting and the outline).

use glam::{Vec3, Vec4};

use super::draw::DrawInfo;
use super::fragment::pixel_colors;
use super::maps::MapRead;
use super::reads::{QuadReads, Read};
use super::surface::straight;
use crate::pipeline::{Quad, BATCH};
use crate::shading::layers::{tex_env, TextureLayer};
use crate::shading::toon::{outline_weights, toon};
use crate::shading::{illuminate, Lighting, Surface, Viewer};

/// A texture layer resolved for a draw: its read and how it combines.
#[derive(Clone, Copy)]
pub(super) struct LayerRead<'a> {
    pub read: MapRead<'a>,
    pub layer: &'a TextureLayer,
}

impl LayerRead<'_> {
    /// The stage's output from the previous stage's premultiplied colour `prev` and the
    /// layer's premultiplied texel `t` (premultiplied too).
    #[inline]
    fn apply(&self, prev: Vec4, t: Vec4) -> Vec4 {
        let l = self.layer;
        let cf = straight(prev).extend(prev.w);
        let ct = straight(t).extend(t.w);
        // DECAL on a format OpenGL leaves undefined is refused when the scene is loaded.
        let out = tex_env(l.mode, l.format, cf, ct, l.constant).unwrap_or(cf);
        (out.truncate() * out.w).extend(out.w)
    }
}

/// The layers' reads of `quads` (of draw `d`), folded into each quad's `layered` colour:
/// the surface colour (its texture and opacity reads made) through every stage in order.
pub(super) fn fold_layers(d: &DrawInfo, quads: &[Quad], out: &mut [QuadReads]) {
    if d.layers.is_empty() {
        return;
    }
    let mut buf = [[Vec4::ZERO; 4]; BATCH];
    for (quads, out) in quads.chunks(BATCH).zip(out.chunks_mut(BATCH)) {
        let mut colors = [[Vec4::ZERO; 4]; BATCH];
        for ((c, o), q) in colors.iter_mut().zip(out.iter()).zip(quads) {
            *c = pixel_colors(d, q, o.get(Read::Texels), o.get(Read::Opacity));
        }
        for layer in &d.layers {
            layer.read.quads(quads, &mut buf[..quads.len()]);
            for (c, b) in colors.iter_mut().zip(&buf) {
                for j in 0..4 {
                    c[j] = layer.apply(c[j], b[j]);
                }
            }
        }
        for (o, c) in out.iter_mut().zip(colors) {
            o.set(Read::Layered, c);
        }
    }
}

/// A quad's premultiplied surface colours `C`: after the layers when the draw has any, else
/// [`pixel_colors`].
#[inline(always)]
pub(super) fn surface_colors(d: &DrawInfo, quad: &Quad, reads: &QuadReads) -> [Vec4; 4] {
    match reads.get(Read::Layered) {
        Some(c) => *c,
        None => pixel_colors(d, quad, reads.get(Read::Texels), reads.get(Read::Opacity)),
    }
}

impl DrawInfo<'_> {
    /// The factors `(D, S)` of surface `s`: toon shading for toon materials, else the
    /// material's model.
    #[inline]
    pub(super) fn lit_factors(
        &self,
        s: &Surface,
        lighting: &Lighting,
        viewer: Viewer,
    ) -> (Vec3, Vec3) {
        match &self.material.toon {
            Some(t) => toon(s, t, lighting, viewer),
            None => illuminate(self.model, s, lighting, viewer),
        }
    }

    /// The light map's factor on D at pixel `j` (its straight RGB times the intensity).
    #[inline]
    pub(super) fn light_factor(&self, reads: &QuadReads, j: usize) -> Option<Vec3> {
        let (texel, map) = (reads.get(Read::Light)?, self.light_map.as_ref()?);
        Some(straight(texel[j]) * map.scale)
    }

    /// The toon outline's weight at the quad's four pixels, when the draw has one (per-pixel
    /// lighting: the interpolated normals and positions give `|N·V|`).
    pub(super) fn outline(&self, quad: &Quad, viewer: Viewer) -> Option<([f32; 4], Vec3)> {
        let o = self.material.toon.as_ref()?.outline?;
        let normal = self.layout.normal?;
        let n_dot_v: [f32; 4] = std::array::from_fn(|j| {
            let n = normal.pixel3(quad, j).normalize_or_zero();
            let p = self
                .layout
                .position
                .map_or(Vec3::ZERO, |s| s.pixel3(quad, j));
            n.dot(viewer.towards(p))
        });
        Some((outline_weights(n_dot_v, o.width), o.color))
    }
}

/// Lays the outline over a quad's premultiplied colours (`weights` of `color`, opaque).
pub(super) fn apply_outline(out: &mut [Vec4; 4], weights: [f32; 4], color: Vec3) {
    for (o, w) in out.iter_mut().zip(weights) {
        if w > 0.0 {
            let a = o.w + (1.0 - o.w) * w;
            *o = (o.truncate() * (1.0 - w) + color * w).extend(a);
        }
    }
}
