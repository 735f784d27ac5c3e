//! Where a mesh or a volume sits in the world: `scale` (a number or per axis), then `rotate`
//! (degrees about x, then y, then z), then `translate`; or a column-major 4×4 `matrix`
//! (glTF's order) instead of all three. Both ways at once is an error: which would win is
//! not obvious, so neither does.

use glam::{EulerRot, Mat4, Quat, Vec3};

use super::spec::ScaleSpec;

/// Object → world from a table's `translate`, `rotate` and `scale`, or its `matrix`; the
/// error is the table's problem, for the caller to prefix.
pub(super) fn placement(
    translate: Option<[f32; 3]>,
    rotate: Option<[f32; 3]>,
    scale: Option<&ScaleSpec>,
    matrix: Option<[f32; 16]>,
) -> Result<Mat4, String> {
    let m = if let Some(m) = matrix {
        if translate.is_some() || rotate.is_some() || scale.is_some() {
            return Err("give `matrix` or `translate`/`rotate`/`scale`, not both".into());
        }
        Mat4::from_cols_array(&m)
    } else {
        let scale = match scale {
            Some(ScaleSpec::Uniform(s)) => Vec3::splat(*s),
            Some(ScaleSpec::Axes(a)) => Vec3::from(*a),
            None => Vec3::ONE,
        };
        let r = rotate.unwrap_or_default().map(f32::to_radians);
        Mat4::from_scale_rotation_translation(
            scale,
            Quat::from_euler(EulerRot::ZYX, r[2], r[1], r[0]),
            Vec3::from(translate.unwrap_or_default()),
        )
    };
    if !m.is_finite() {
        return Err("the placement has a non-finite number".into());
    }
    Ok(m)
}
