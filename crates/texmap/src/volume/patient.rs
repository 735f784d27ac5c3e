//! Which way a scan's patient faces: the anatomical frame a file states (NIfTI's world is
//! RAS+ by definition; a NRRD says so in its `space` field), kept as the anterior and
//! superior directions in voxel space so that they follow the volume wherever a scene
//! places it. The automatic framing reads them to show the face, head up.

use glam::{Mat4, Vec3};

/// An anatomical world frame: the direction each axis increases toward.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AnatomicalSpace {
    /// +x right, +y anterior, +z superior (NIfTI, NRRD `right-anterior-superior`).
    Ras,
    /// +x left, +y posterior, +z superior (DICOM, NRRD `left-posterior-superior`).
    Lps,
    /// +x left, +y anterior, +z superior (NRRD `left-anterior-superior`).
    Las,
}

impl AnatomicalSpace {
    /// The frame a NRRD `space` field names (long or short form), if it is an anatomical one.
    #[must_use]
    pub fn from_nrrd(space: &str) -> Option<Self> {
        match space.trim().to_ascii_lowercase().as_str() {
            "right-anterior-superior" | "ras" => Some(Self::Ras),
            "left-posterior-superior" | "lps" => Some(Self::Lps),
            "left-anterior-superior" | "las" => Some(Self::Las),
            _ => None,
        }
    }

    /// The world directions of the patient's front and top in this frame.
    #[must_use]
    pub fn anterior_superior(self) -> (Vec3, Vec3) {
        match self {
            Self::Ras | Self::Las => (Vec3::Y, Vec3::Z),
            Self::Lps => (-Vec3::Y, Vec3::Z),
        }
    }
}

/// The patient's front and top as voxel-space directions (unit length in voxel space).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatientAxes {
    anterior: Vec3,
    superior: Vec3,
}

impl PatientAxes {
    /// The axes of a file whose voxels are placed by `world_from_voxel` in `space`; `None`
    /// for a singular placement.
    #[must_use]
    pub fn new(space: AnatomicalSpace, world_from_voxel: Mat4) -> Option<Self> {
        if !world_from_voxel.is_finite() || world_from_voxel.determinant().abs() < 1e-12 {
            return None;
        }
        let voxel_from_world = world_from_voxel.inverse();
        let (a, s) = space.anterior_superior();
        Some(PatientAxes {
            anterior: voxel_from_world.transform_vector3(a).normalize_or_zero(),
            superior: voxel_from_world.transform_vector3(s).normalize_or_zero(),
        })
    }

    /// The front and top directions in the world of a volume placed by `world_from_voxel`
    /// (unit vectors; the top made perpendicular to the front).
    #[must_use]
    pub fn world(&self, world_from_voxel: Mat4) -> (Vec3, Vec3) {
        let a = world_from_voxel
            .transform_vector3(self.anterior)
            .normalize_or_zero();
        let s = world_from_voxel.transform_vector3(self.superior);
        let s = (s - a * s.dot(a)).normalize_or_zero();
        (a, s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ras_file_faces_plus_y_and_an_lps_file_minus_y_wherever_it_is_placed() {
        let m = Mat4::from_scale(Vec3::new(0.5, 0.7, 2.0));
        let ras = PatientAxes::new(AnatomicalSpace::Ras, m).unwrap();
        let (a, s) = ras.world(m);
        assert!((a - Vec3::Y).length() < 1e-6 && (s - Vec3::Z).length() < 1e-6);
        let lps = PatientAxes::new(AnatomicalSpace::Lps, m).unwrap();
        assert!((lps.world(m).0 + Vec3::Y).length() < 1e-6);
        // Placed by spacing alone after a flipped file matrix, the axes follow the voxels.
        let flipped = Mat4::from_scale(Vec3::new(0.5, -0.7, 2.0));
        let axes = PatientAxes::new(AnatomicalSpace::Ras, flipped).unwrap();
        let (a, _) = axes.world(Mat4::from_scale(Vec3::new(0.5, 0.7, 2.0)));
        assert!((a + Vec3::Y).length() < 1e-6, "{a}");
        // A scene's rotation turns them too.
        let turn = Mat4::from_rotation_z(std::f32::consts::FRAC_PI_2) * m;
        let (a, s) = ras.world(turn);
        assert!(
            (a + Vec3::X).length() < 1e-5 && (s - Vec3::Z).length() < 1e-5,
            "{a} {s}"
        );
        assert_eq!(
            AnatomicalSpace::from_nrrd("Left-Posterior-Superior"),
            Some(AnatomicalSpace::Lps)
        );
        assert_eq!(AnatomicalSpace::from_nrrd("3D-right-handed"), None);
    }
}
