//! The texture transform: offset, rotation and scale on uv, as `KHR_texture_transform`.

use glam::{Mat2, Vec2};

use super::Footprint;

/// `uv' = T·R·S·uv`: scale, then rotate, then offset — `KHR_texture_transform`'s order.
///
/// With rotation r: `u' = sx·cos r·u + sy·sin r·v + ox`, `v' = −sx·sin r·u + sy·cos r·v + oy`
/// (the direction in which the TextureTransformTest model shows its green markers).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureTransform {
    pub offset: Vec2,
    /// Radians.
    pub rotation: f32,
    pub scale: Vec2,
}

impl Default for TextureTransform {
    fn default() -> Self {
        TextureTransform {
            offset: Vec2::ZERO,
            rotation: 0.0,
            scale: Vec2::ONE,
        }
    }
}

impl TextureTransform {
    /// The linear part (rotation·scale) as a matrix acting on column vectors.
    #[must_use]
    pub fn matrix(&self) -> Mat2 {
        let (s, c) = self.rotation.sin_cos();
        // Columns: the images of u and v.
        Mat2::from_cols(
            Vec2::new(c * self.scale.x, -s * self.scale.x),
            Vec2::new(s * self.scale.y, c * self.scale.y),
        )
    }

    /// Transforms a coordinate.
    #[must_use]
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        self.matrix() * uv + self.offset
    }

    /// Transforms a footprint: the coordinate fully, the derivatives by the linear part only.
    #[must_use]
    pub fn apply_footprint(&self, fp: &Footprint) -> Footprint {
        let m = self.matrix();
        Footprint {
            uv: m * fp.uv + self.offset,
            duv_dx: m * fp.duv_dx,
            duv_dy: m * fp.duv_dy,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_khr_texture_transform_formula() {
        let t = TextureTransform {
            offset: Vec2::new(0.1, 0.2),
            rotation: 0.3,
            scale: Vec2::new(2.0, 3.0),
        };
        let (u, v) = (0.4f32, 0.7f32);
        let (s, c) = 0.3f32.sin_cos();
        let want = Vec2::new(
            2.0 * c * u + 3.0 * s * v + 0.1,
            -2.0 * s * u + 3.0 * c * v + 0.2,
        );
        assert!((t.apply(Vec2::new(u, v)) - want).length() < 1e-6);
    }

    #[test]
    fn derivatives_ignore_offset() {
        let t = TextureTransform {
            offset: Vec2::new(5.0, 5.0),
            ..Default::default()
        };
        let fp = t.apply_footprint(&Footprint::new(Vec2::ZERO, Vec2::X, Vec2::Y));
        assert_eq!(fp.duv_dx, Vec2::X);
        assert_eq!(fp.uv, Vec2::splat(5.0));
    }
}
