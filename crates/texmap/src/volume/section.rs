//! Orthogonal slice views of a scan: one plane of voxels (axial, coronal or sagittal) drawn
//! flat, through the transfer function or a window/level — what a radiologist's viewer shows
//! beside the 3D rendering.
//!
//! Planes and orientation are chosen from the scan's placement in the world (the file's
//! orientation), not from its voxel order: the axial plane is the voxel axis nearest world z
//! held at `index`, the coronal the one nearest world y, the sagittal the one nearest world
//! x. On screen, world +x runs to the right in axial and coronal views and world +y in
//! sagittal ones; world +z is up in coronal and sagittal views and world +y in axial ones.
//! For a NIfTI file (RAS+: x to the patient's right, y anterior, z superior) that is the
//! neurological convention — the patient's right on the image's right — with the face up in
//! axial views and the head up otherwise.
//!
//! The plane's physical extent (voxel counts × spacing) is fitted into the image, aspect kept,
//! centred; voxels are read bilinearly within the plane (voxel centres at integers, as
//! everywhere in [`super`]). Outside the plane the image is transparent black.

use glam::{Mat4, Vec3, Vec4};

use super::grid::Volume;
use super::output::display_to_frame;
use super::transfer::TransferFunction;
use crate::frame::{Frame, FrameStats};
use crate::pixels::Pixels;
use crate::{Error, Result};

/// Which plane a [`render_section`] shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SectionAxis {
    /// Across world z (head to foot): seen from above.
    Axial,
    /// Across world y (front to back).
    Coronal,
    /// Across world x (left to right).
    Sagittal,
}

impl SectionAxis {
    /// Every axis with its name.
    pub const NAMES: [(&'static str, SectionAxis); 3] = [
        ("axial", SectionAxis::Axial),
        ("coronal", SectionAxis::Coronal),
        ("sagittal", SectionAxis::Sagittal),
    ];

    /// The world axes: across the plane, to the right, up.
    fn world_axes(self) -> (usize, usize, usize) {
        match self {
            SectionAxis::Axial => (2, 0, 1),
            SectionAxis::Coronal => (1, 0, 2),
            SectionAxis::Sagittal => (0, 1, 2),
        }
    }
}

/// How a section's values become colours.
#[derive(Clone, Debug, PartialEq)]
pub enum SectionLook {
    /// The transfer function's colour times its opacity, over black.
    Transfer(TransferFunction),
    /// Grey: `level − width/2` black to `level + width/2` white (display values).
    Window { level: f32, width: f32 },
}

impl SectionLook {
    /// A grey window over the scan's own values, as a radiology viewer opens a scan: from the
    /// 0.5th to the 99.5th percentile of its voxels (so a few outliers do not wash it out).
    #[must_use]
    pub fn auto_window(vol: &Volume) -> SectionLook {
        let mut bins = vec![0u64; 4096];
        for &q in vol.quantized() {
            bins[usize::from(q >> 4)] += 1;
        }
        let total: u64 = bins.iter().sum();
        let percentile = |p: u64| {
            let mut seen = 0u64;
            for (k, &n) in bins.iter().enumerate() {
                seen += n;
                if seen * 1000 >= total * p {
                    return vol.value_of((k as f32 + 0.5) * 16.0);
                }
            }
            vol.range().1
        };
        let (a, b) = (percentile(5), percentile(995));
        let (lo, hi) = if b > a { (a, b) } else { vol.range() };
        SectionLook::Window {
            level: 0.5 * (lo + hi),
            width: (hi - lo).max(f32::MIN_POSITIVE),
        }
    }
}

/// The voxel axes of `vol` that `axis` uses, with the signs that make them run right and up:
/// `(across, right, up)` each as (voxel axis, +1 or −1).
#[must_use]
pub fn section_axes(vol: &Volume, axis: SectionAxis) -> [(usize, f32); 3] {
    let m: Mat4 = vol.world_from_voxel();
    let dirs: [Vec3; 3] = [m.x_axis, m.y_axis, m.z_axis].map(|c| c.truncate().normalize_or_zero());
    let (across, right, up) = axis.world_axes();
    // Each world axis takes the voxel axis most aligned with it, across first.
    let mut taken = [false; 3];
    let mut pick = |world: usize| {
        let best = (0..3)
            .filter(|&a| !taken[a])
            .max_by(|&a, &b| dirs[a][world].abs().total_cmp(&dirs[b][world].abs()))
            .unwrap_or(0);
        taken[best] = true;
        let sign = if dirs[best][world] < 0.0 { -1.0 } else { 1.0 };
        (best, sign)
    };
    let a = pick(across);
    let r = pick(right);
    let u = pick(up);
    [a, r, u]
}

/// The plane `index` (a voxel index along the section's axis) of `vol`, `width × height`
/// pixels, coloured by `look` (see the module docs).
///
/// # Errors
/// [`Error::Parameter`] for an image size outside 1..=16384, an index outside the voxels of
/// that axis, or a window whose width is not positive.
pub fn render_section(
    vol: &Volume,
    axis: SectionAxis,
    index: u32,
    look: &SectionLook,
    width: u32,
    height: u32,
) -> Result<Frame> {
    if width == 0 || height == 0 || width > 16384 || height > 16384 {
        return Err(Error::parameter(format!(
            "image size {width}x{height} is out of range"
        )));
    }
    if let SectionLook::Window { level, width: w } = look {
        if !(w.is_finite() && *w > 0.0 && level.is_finite()) {
            return Err(Error::parameter(format!(
                "window width {w} must be positive and level {level} finite"
            )));
        }
    }
    let dims = vol.dims();
    let [(across, _), (right, rs), (up, us)] = section_axes(vol, axis);
    if index >= dims[across] {
        return Err(Error::parameter(format!(
            "index {index} is outside the {} voxels across the {} plane (0..={})",
            dims[across],
            SectionAxis::NAMES
                .iter()
                .find(|(_, a)| *a == axis)
                .map_or("", |(n, _)| n),
            dims[across] - 1
        )));
    }
    // The plane's physical size, fitted into the image.
    let spacing = vol.spacing();
    let (nr, nu) = (dims[right], dims[up]);
    let (ext_r, ext_u) = (
        (nr.max(2) - 1) as f32 * spacing[right],
        (nu.max(2) - 1) as f32 * spacing[up],
    );
    let px = (width as f32 / ext_r.max(1e-6)).min(height as f32 / ext_u.max(1e-6));
    let (w_img, h_img) = (ext_r * px, ext_u * px);
    let (x0, y0) = (0.5 * (width as f32 - w_img), 0.5 * (height as f32 - h_img));
    let value = |r: f32, u: f32| -> f32 {
        // Bilinear within the plane at voxel coordinates (r, u).
        let (r0, u0) = (r.floor(), u.floor());
        let (fr, fu) = (r - r0, u - u0);
        let clampi = |v: f32, n: u32| (v.max(0.0) as u32).min(n - 1);
        let at = |rr: u32, uu: u32| {
            let mut ijk = [0u32; 3];
            ijk[across] = index;
            ijk[right] = rr;
            ijk[up] = uu;
            vol.voxel(ijk[0], ijk[1], ijk[2])
        };
        let (ra, rb) = (clampi(r0, nr), clampi(r0 + 1.0, nr));
        let (ua, ub) = (clampi(u0, nu), clampi(u0 + 1.0, nu));
        let bottom = at(ra, ua) * (1.0 - fr) + at(rb, ua) * fr;
        let top = at(ra, ub) * (1.0 - fr) + at(rb, ub) * fr;
        bottom * (1.0 - fu) + top * fu
    };
    let mut color = Pixels::zeroed(width as usize * height as usize);
    for (y, row) in color.chunks_mut(width as usize).enumerate() {
        for (x, out) in row.iter_mut().enumerate() {
            // The pixel's centre in the plane's physical frame (right, up from its corner).
            let sx = (x as f32 + 0.5 - x0) / px;
            let sy = (h_img - (y as f32 + 0.5 - y0)) / px;
            if sx < 0.0 || sy < 0.0 || sx > ext_r || sy > ext_u {
                continue;
            }
            let mut r = sx / spacing[right];
            let mut u = sy / spacing[up];
            if rs < 0.0 {
                r = (nr - 1) as f32 - r;
            }
            if us < 0.0 {
                u = (nu - 1) as f32 - u;
            }
            let v = value(r, u);
            let display = match look {
                SectionLook::Transfer(tf) => {
                    let c = tf.eval(v);
                    (c.truncate() * c.w).extend(1.0)
                }
                SectionLook::Window { level, width } => {
                    let g = ((v - (level - 0.5 * width)) / width).clamp(0.0, 1.0);
                    Vec4::new(g, g, g, 1.0)
                }
            };
            *out = display_to_frame(display);
        }
    }
    Ok(Frame {
        width,
        height,
        color,
        stats: FrameStats::default(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_automatic_window_spans_the_bulk_of_the_values_not_the_outliers() {
        // 10,000 voxels from 0 to 99.99, 47 more at 0 and one outlier at 10,000.
        let mut v: Vec<f32> = (0..10_000).map(|i| i as f32 * 0.01).collect();
        v.push(10_000.0);
        v.extend([0.0; 47]);
        let vol = Volume::from_scalars([8, 8, 157], Mat4::IDENTITY, v).unwrap();
        let SectionLook::Window { level, width } = SectionLook::auto_window(&vol) else {
            panic!("not a window");
        };
        let (lo, hi) = (level - 0.5 * width, level + 0.5 * width);
        // The outlier's bins are 2.4 value units wide: the window is 0..100 within them.
        assert!(lo.abs() < 3.0 && (hi - 100.0).abs() < 3.0, "{lo} .. {hi}");
    }

    /// A 4 × 6 × 8 grid with value 100·i + 10·j + k, spacing 1, identity placement.
    fn grid() -> Volume {
        let (nx, ny, nz) = (4u32, 6u32, 8u32);
        let mut v = Vec::new();
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    v.push((100 * i + 10 * j + k) as f32);
                }
            }
        }
        Volume::from_scalars([nx, ny, nz], Mat4::IDENTITY, v).unwrap()
    }

    #[test]
    fn planes_follow_the_world_axes_and_their_signs() {
        let vol = grid();
        assert_eq!(
            section_axes(&vol, SectionAxis::Axial),
            [(2, 1.0), (0, 1.0), (1, 1.0)]
        );
        assert_eq!(
            section_axes(&vol, SectionAxis::Sagittal),
            [(0, 1.0), (1, 1.0), (2, 1.0)]
        );
        // A scan stored with y flipped (LPS-like rows): up still runs along world +y.
        let flipped = Volume::from_scalars(
            [4, 6, 8],
            Mat4::from_scale(Vec3::new(1.0, -1.0, 1.0)),
            vec![0.0; 4 * 6 * 8],
        )
        .unwrap();
        assert_eq!(section_axes(&flipped, SectionAxis::Axial)[2], (1, -1.0));
    }

    #[test]
    fn an_axial_section_shows_its_plane_right_and_up() {
        let vol = grid();
        // Window 0..400: grey = value / 400. The 4 × 6 plane fills a 30 × 50 image exactly
        // (3 × 5 mm at 10 pixels a mm).
        let look = SectionLook::Window {
            level: 200.0,
            width: 400.0,
        };
        let f = render_section(&vol, SectionAxis::Axial, 3, &look, 30, 50).unwrap();
        let grey = |x: usize, y: usize| crate::color::linear_to_srgb(f.color[y * 30 + x].x);
        // Bottom-left pixel centre: (0.05, 0.05) mm → value ≈ 100·0.05 + 10·0.05 + 3.
        let bl = grey(0, 49);
        assert!((bl - (3.0 + 5.5) / 400.0).abs() < 2e-3, "{bl}");
        // Top-right: (2.95, 4.95) → 295 + 49.5 + 3.
        let tr = grey(29, 0);
        assert!((tr - (295.0 + 49.5 + 3.0) / 400.0).abs() < 2e-3, "{tr}");
        // The index is checked.
        assert!(render_section(&vol, SectionAxis::Axial, 8, &look, 30, 50).is_err());
        assert!(render_section(&vol, SectionAxis::Sagittal, 3, &look, 30, 50).is_ok());
    }

    #[test]
    fn a_section_keeps_its_aspect_and_leaves_the_rest_transparent() {
        let vol = grid();
        let look = SectionLook::Window {
            level: 0.0,
            width: 1.0,
        };
        // 3 × 5 mm into 100 × 100: 60 × 100 pixels, centred; 20 columns empty each side.
        let f = render_section(&vol, SectionAxis::Axial, 0, &look, 100, 100).unwrap();
        assert_eq!(f.color[50 * 100 + 10], Vec4::ZERO);
        assert_eq!(f.color[50 * 100 + 89], Vec4::ZERO);
        assert!(f.color[50 * 100 + 50].w > 0.0);
    }
}
