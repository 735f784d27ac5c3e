//! The viewer of the lighting model: where the unit vector `V` towards the eye comes from.

use glam::Vec3;

/// Where a surface point is seen from.
///
/// A perspective camera's viewer is its eye, so `V = normalize(eye − p)` changes across the
/// surface; an orthographic camera's rays are parallel, so `V` is the same direction (towards
/// the camera) at every point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Viewer {
    /// The eye of a perspective camera.
    Point(Vec3),
    /// The unit direction towards an orthographic camera.
    Direction(Vec3),
}

impl Viewer {
    /// The unit vector `V` from `p` towards the viewer (zero if `p` is the eye).
    #[inline]
    #[must_use]
    pub fn towards(self, p: Vec3) -> Vec3 {
        match self {
            Viewer::Point(eye) => (eye - p).normalize_or_zero(),
            Viewer::Direction(d) => d,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_viewer_varies_and_a_direction_viewer_does_not() {
        let eye = Viewer::Point(Vec3::new(0.0, 0.0, 5.0));
        assert_eq!(eye.towards(Vec3::ZERO), Vec3::Z);
        assert_eq!(eye.towards(Vec3::new(0.0, 0.0, 6.0)), -Vec3::Z);
        assert_eq!(eye.towards(Vec3::new(0.0, 0.0, 5.0)), Vec3::ZERO);
        let dir = Viewer::Direction(Vec3::Z);
        assert_eq!(dir.towards(Vec3::ZERO), Vec3::Z);
        assert_eq!(dir.towards(Vec3::new(3.0, -2.0, 100.0)), Vec3::Z);
    }
}
