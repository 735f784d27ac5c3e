//! The scene behind transmitting surfaces: `KHR_materials_transmission` seeing the frame's
//! other surfaces, as the Khronos sample viewer and Filament draw it.
//!
//! A frame with a transmitting metallic-roughness draw (under an environment) is drawn twice:
//! first without its transmitting and blended draws onto a transparent target — the opaque
//! scene, premultiplied, its alpha the surfaces' coverage — then whole. The first image and
//! its box-filtered chain ([`SceneBehind`]) are what a transmitting pixel sees: the point
//! where its refracted ray leaves the surface (`KHR_materials_volume`'s thickness along the
//! refracted direction; the pixel itself when thin-walled) is projected into the image and
//! read trilinearly at the level the sample viewer picks, `log2(width) · roughness ·
//! clamp(2·ior − 2, 0, 1)`: a rough surface blurs what is behind it. Where the image has no
//! surface (alpha 0) the environment along the refracted direction is seen, as before, so a
//! transmitting object alone in a scene is shaded exactly as without this pass.

use glam::{Mat4, Vec3, Vec4};
use rayon::prelude::*;

use crate::pixels::Pixels;

/// One level of the chain: `w × h` premultiplied linear RGBA, rows top to bottom.
struct Level {
    w: usize,
    h: usize,
    texels: Pixels,
}

/// The opaque scene's image and its chain, with the projection that made it.
pub(super) struct SceneBehind {
    levels: Vec<Level>,
    clip_from_world: Mat4,
}

impl SceneBehind {
    /// The chain of `color` (`w × h`, as drawn with `clip_from_world`): each level the 2×2
    /// box average of the one above (an odd last row or column repeated), down to 1×1.
    pub fn new(color: Pixels, w: usize, h: usize, clip_from_world: Mat4) -> Self {
        assert_eq!(color.len(), w * h, "the image is w × h");
        let mut levels = vec![Level {
            w,
            h,
            texels: color,
        }];
        while let Some(top) = levels.last().filter(|l| l.w > 1 || l.h > 1) {
            levels.push(halve(top));
        }
        SceneBehind {
            levels,
            clip_from_world,
        }
    }

    /// The width of the first level, in pixels.
    pub fn width(&self) -> usize {
        self.levels[0].w
    }

    /// What the opaque scene shows at world point `p` (premultiplied; alpha its coverage),
    /// read at level of detail `lod` (0 = the frame's pixels): zero for a point behind the
    /// camera; a point outside the frame reads its nearest edge.
    pub fn read(&self, p: Vec3, lod: f32) -> Vec4 {
        let c = self.clip_from_world * p.extend(1.0);
        if !(c.w > 0.0) || !c.is_finite() {
            return Vec4::ZERO;
        }
        // The pipeline's viewport: x right, y down, pixel centres at half-integers.
        let (u, v) = (c.x / c.w * 0.5 + 0.5, 0.5 - c.y / c.w * 0.5);
        let top = (self.levels.len() - 1) as f32;
        let lod = lod.clamp(0.0, top);
        let k = lod.floor();
        let t = lod - k;
        let k = k as usize;
        let a = bilinear(&self.levels[k], u, v);
        if t == 0.0 {
            return a;
        }
        a + (bilinear(&self.levels[k + 1], u, v) - a) * t
    }
}

/// The next level of `l`: 2×2 box averages, rows in parallel.
fn halve(l: &Level) -> Level {
    let (w, h) = (l.w.div_ceil(2), l.h.div_ceil(2));
    let mut texels = Pixels::zeroed(w * h);
    texels.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        let (y0, y1) = (2 * y, (2 * y + 1).min(l.h - 1));
        for (x, out) in row.iter_mut().enumerate() {
            let (x0, x1) = (2 * x, (2 * x + 1).min(l.w - 1));
            let at = |x: usize, y: usize| l.texels[y * l.w + x];
            *out = (at(x0, y0) + at(x1, y0) + at(x0, y1) + at(x1, y1)) * 0.25;
        }
    });
    Level { w, h, texels }
}

/// `l` at normalised coordinates `(u, v)`, bilinear, clamped to its edges.
fn bilinear(l: &Level, u: f32, v: f32) -> Vec4 {
    let x = (u * l.w as f32 - 0.5).clamp(0.0, (l.w - 1) as f32);
    let y = (v * l.h as f32 - 0.5).clamp(0.0, (l.h - 1) as f32);
    let (x0, y0) = (x.floor() as usize, y.floor() as usize);
    let (x1, y1) = ((x0 + 1).min(l.w - 1), (y0 + 1).min(l.h - 1));
    let (fx, fy) = (x - x0 as f32, y - y0 as f32);
    let at = |x: usize, y: usize| l.texels[y * l.w + x];
    let top = at(x0, y0) + (at(x1, y0) - at(x0, y0)) * fx;
    let bottom = at(x0, y1) + (at(x1, y1) - at(x0, y1)) * fx;
    top + (bottom - top) * fy
}

/// The level a transmitting surface of `roughness` and index of refraction `ior` reads the
/// scene behind it at, in an image `width` pixels wide (the Khronos sample viewer's rule).
pub(super) fn lod(width: usize, roughness: f32, ior: f32) -> f32 {
    (width.max(1) as f32).log2() * roughness.clamp(0.0, 1.0) * (2.0 * ior - 2.0).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ortho() -> Mat4 {
        // World x, y in [−1, 1] map to the whole frame.
        Mat4::orthographic_rh(-1.0, 1.0, -1.0, 1.0, 0.1, 10.0)
    }

    #[test]
    fn a_pixel_centre_reads_its_own_texel() {
        let (w, h) = (4, 2);
        let color: Pixels = (0..w * h).map(|i| Vec4::splat(i as f32)).collect();
        let b = SceneBehind::new(color, w, h, ortho());
        // Pixel (1, 0)'s centre: x = (1.5 / 4) · 2 − 1, y = 1 − (0.5 / 2) · 2.
        let p = Vec3::new(1.5 / 4.0 * 2.0 - 1.0, 1.0 - 0.5, -1.0);
        assert!((b.read(p, 0.0) - Vec4::splat(1.0)).abs().max_element() < 1e-5);
        let p = Vec3::new(3.5 / 4.0 * 2.0 - 1.0, 1.0 - 1.5, -1.0);
        assert!((b.read(p, 0.0) - Vec4::splat(7.0)).abs().max_element() < 1e-5);
    }

    #[test]
    fn the_chain_keeps_the_mean_and_ends_in_one_texel() {
        let (w, h) = (8, 4);
        let color: Pixels = (0..w * h).map(|i| Vec4::splat((i % 5) as f32)).collect();
        let mean = color.iter().copied().sum::<Vec4>() / (w * h) as f32;
        let b = SceneBehind::new(color, w, h, ortho());
        let last = b.levels.last().unwrap();
        assert_eq!((last.w, last.h), (1, 1));
        assert!((last.texels[0] - mean).abs().max_element() < 1e-5);
        // The top level is the mean anywhere in the frame.
        let top = (b.levels.len() - 1) as f32;
        assert!(
            (b.read(Vec3::new(0.3, -0.7, -1.0), top) - mean)
                .abs()
                .max_element()
                < 1e-5
        );
    }

    #[test]
    fn behind_the_camera_is_nothing_and_outside_reads_the_edge() {
        let color = vec![Vec4::ONE; 4];
        let b = SceneBehind::new(
            color.into(),
            2,
            2,
            Mat4::perspective_rh(1.0, 1.0, 0.1, 10.0),
        );
        assert_eq!(b.read(Vec3::new(0.0, 0.0, 1.0), 0.0), Vec4::ZERO);
        assert_eq!(b.read(Vec3::new(50.0, 0.0, -1.0), 0.0), Vec4::ONE);
    }

    #[test]
    fn smooth_or_index_one_surfaces_read_the_frame_sharp() {
        assert_eq!(lod(1024, 0.0, 1.5), 0.0);
        assert_eq!(lod(1024, 0.8, 1.0), 0.0);
        assert!((lod(1024, 0.5, 1.5) - 5.0).abs() < 1e-6);
    }
}
