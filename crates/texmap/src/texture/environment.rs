//! Environment maps: the light arriving from every direction, stored as an equirectangular
//! panorama, a cube map or a sphere map, and read along a direction with its footprint.
//!
//! Direction convention (Mitsuba's, stated in `../shared/peers/mitsuba_ref.py`): a direction
//! `d = (x, y, z)` reads an equirectangular image at
//!
//! ```text
//! u = atan2(x, −z) / 2π  (wrapped to [0, 1))      v = acos(y) / π
//! ```
//!
//! so +z sees the panorama's centre column, −z its left and right edges (the seam), +x the
//! column at u = ¼, +y the top row. Columns are texel-centred (`(i + ½)/W`), as OpenGL's;
//! rows are Mitsuba's latitudes, row `i` at `θ = π·i/(H − 1)` (the first row is the north
//! pole, the last the south pole), so the remap `v' = (v·(H − 1) + ½)/H` puts them at
//! OpenGL's texel centres before the read.
//!
//! Every read carries its footprint ([`CubeFootprint`]: the direction and its screen
//! derivatives). The equirectangular footprint is the chain rule through atan2 and acos, so
//! the seam, where u jumps from 1 to 0, costs nothing: the derivative is continuous there and
//! u wraps with [`Wrap::Repeat`] (no line, `tests/environment.rs`). The sampler's filter
//! applies (trilinear by default); near the poles the footprint stretches along u, as the
//! panorama does.
//!
//! Cube maps read through [`sample_cube`] (seamless across faces). Their face images are
//! OpenGL's (a left-handed layout: each face as seen from inside the cube in a left-handed
//! world), so a world direction `(x, y, z)` reads the cube at `(−x, y, z)`, as three.js reads
//! its face images; the camera looking down −z then sees `negz` upright and unmirrored.
//! Crosses (`4:3` horizontal, `3:4` vertical) hold the same faces:
//!
//! ```text
//! horizontal     +Y                vertical       +Y
//!            −X  +Z  +X  −Z                   −X  +Z  +X
//!                −Y                               −Y
//!                                                 −Z (turned 180°)
//! ```
//!
//! Sphere maps are OpenGL's (`GL_SPHERE_MAP`): the picture of a mirror ball seen along −z, so
//! `+z` reads the centre and `−z` the rim: `m = 2·√(x² + y² + (z + 1)²)`, `u = x/m + ½`,
//! `v = ½ − y/m`.
//!
//! Files: an equirectangular image is 2:1 (HDR, EXR, PNG or any format [`load`] reads), a
//! cross 4:3 or 3:4, a sphere map 1:1; a folder holds six faces named `posx`, `negx`, `posy`,
//! `negy`, `posz`, `negz` (any image extension). A DDS, KTX or KTX2 cube map file gives its
//! six faces in its own order (+X, −X, +Y, −Y, +Z, −Z, rows top first as OpenGL uploads them,
//! which is this layout: `posx` … `negz` written out from it load as the same cube); a flat
//! 2D container file is an image like any other (level 0, the proportions above).
//!
//! [`load`]: super::load

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3, Vec4};
use image::DynamicImage;

use super::container::{cube_from_file, flat_image, read_texture_file, Container};
use super::load::{decode_image, texture_from_image, Limits};
use super::{
    sample, sample_cube, sample_lanes, ColorSpace, CubeFootprint, CubeFootprintLanes, Footprint,
    FootprintLanes, Sampler, TextureCube, TextureOptions, Wrap,
};
use super::{Texture2D, UnknownName};
use crate::{Error, Result};

/// How an environment image is laid out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EnvironmentKind {
    /// A 2:1 latitude-longitude panorama.
    Equirect,
    /// Six faces in one image: a 4:3 horizontal or a 3:4 vertical cross.
    Cross,
    /// Six face images in a folder (`posx` … `negz`).
    Faces,
    /// An OpenGL sphere map (1:1).
    Sphere,
}

impl EnvironmentKind {
    /// The names [`EnvironmentKind::parse`] accepts.
    pub const SPELLINGS: &'static str = "equirect, cross, faces, sphere";

    /// The kind named `s` (one of [`EnvironmentKind::SPELLINGS`]).
    ///
    /// # Errors
    /// [`UnknownName`] listing the names.
    pub fn parse(s: &str) -> std::result::Result<Self, UnknownName> {
        match s {
            "equirect" => Ok(EnvironmentKind::Equirect),
            "cross" => Ok(EnvironmentKind::Cross),
            "faces" => Ok(EnvironmentKind::Faces),
            "sphere" => Ok(EnvironmentKind::Sphere),
            _ => Err(UnknownName {
                given: s.to_string(),
                expected: Self::SPELLINGS,
            }),
        }
    }

    /// The kind's name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            EnvironmentKind::Equirect => "equirect",
            EnvironmentKind::Cross => "cross",
            EnvironmentKind::Faces => "faces",
            EnvironmentKind::Sphere => "sphere",
        }
    }
}

/// An environment map: radiance (linear RGB) by direction.
#[derive(Clone, Debug)]
pub enum EnvironmentMap {
    /// A latitude-longitude panorama (the module docs' convention).
    Equirect(Texture2D),
    /// Six faces in OpenGL's layout, from a cross or six images (read mirrored in x).
    Cube(Box<TextureCube>),
    /// An OpenGL sphere map.
    Sphere(Texture2D),
}

/// The sampler state an environment read uses: `sampler`'s filter and levels of detail,
/// with the wrap modes the map's layout needs (repeat around the panorama, clamp at its
/// poles and at a sphere map's rim).
#[must_use]
fn wrapped(sampler: &Sampler, u: Wrap, v: Wrap) -> Sampler {
    sampler.with_wraps(u, v, Wrap::ClampToEdge)
}

impl EnvironmentMap {
    /// Reads the map along `fp.dir` (any length) with its screen derivatives: linear RGBA,
    /// premultiplied (alpha 1 for opaque images).
    #[must_use]
    pub fn sample(&self, sampler: &Sampler, fp: &CubeFootprint) -> Vec4 {
        match self {
            EnvironmentMap::Equirect(t) => {
                let s = wrapped(sampler, Wrap::Repeat, Wrap::ClampToEdge);
                sample(t, &s, &equirect_footprint(fp, t.height()))
            }
            EnvironmentMap::Cube(c) => {
                let m = |v: Vec3| Vec3::new(-v.x, v.y, v.z);
                let mirrored = CubeFootprint {
                    dir: m(fp.dir),
                    ddir_dx: m(fp.ddir_dx),
                    ddir_dy: m(fp.ddir_dy),
                };
                sample_cube(c, sampler, &mirrored)
            }
            EnvironmentMap::Sphere(t) => {
                let s = wrapped(sampler, Wrap::ClampToEdge, Wrap::ClampToEdge);
                sample(t, &s, &sphere_map_footprint(fp))
            }
        }
    }

    /// [`EnvironmentMap::sample`] of four footprints (lanes whose bit in `mask` is clear are
    /// skipped, left zero): the same values, a panorama's footprints computed four at a time
    /// ([`equirect_footprint_lanes`]) and read through [`sample_lanes`].
    #[must_use]
    pub fn sample_lanes(&self, sampler: &Sampler, fp: &CubeFootprintLanes, mask: u8) -> [Vec4; 4] {
        if let EnvironmentMap::Equirect(t) = self {
            if let Some(uv) = equirect_footprint_lanes(fp, t.height()) {
                let s = wrapped(sampler, Wrap::Repeat, Wrap::ClampToEdge);
                return sample_lanes(t, &s, &uv, mask);
            }
        }
        let mut out = [Vec4::ZERO; 4];
        for (j, o) in out.iter_mut().enumerate() {
            if mask & (1 << j) != 0 {
                *o = self.sample(sampler, &fp.footprint(j));
            }
        }
        out
    }

    /// The layout's kind (a cube map reports [`EnvironmentKind::Faces`]).
    #[must_use]
    pub fn kind(&self) -> EnvironmentKind {
        match self {
            EnvironmentMap::Equirect(_) => EnvironmentKind::Equirect,
            EnvironmentMap::Cube(_) => EnvironmentKind::Faces,
            EnvironmentMap::Sphere(_) => EnvironmentKind::Sphere,
        }
    }

    /// Width and height of the image (a cube map: one face).
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        match self {
            EnvironmentMap::Equirect(t) | EnvironmentMap::Sphere(t) => (t.width(), t.height()),
            EnvironmentMap::Cube(c) => (c.size(), c.size()),
        }
    }

    /// The number of mip levels of the image (a cube map: of one face).
    #[must_use]
    pub fn levels(&self) -> usize {
        match self {
            EnvironmentMap::Equirect(t) | EnvironmentMap::Sphere(t) => t.levels().len(),
            EnvironmentMap::Cube(c) => c.faces()[0].levels().len(),
        }
    }

    /// Roughly how many texels of level 0 a steradian holds (for choosing how finely a
    /// derived map must sample it).
    #[must_use]
    pub fn texels_per_steradian(&self) -> f32 {
        let (w, h) = self.size();
        match self {
            EnvironmentMap::Equirect(_) => (w * h) as f32 / (2.0 * std::f32::consts::PI.powi(2)),
            EnvironmentMap::Cube(_) => 6.0 * (w * h) as f32 / (4.0 * std::f32::consts::PI),
            // The disc of a sphere map covers the sphere of directions.
            EnvironmentMap::Sphere(_) => {
                std::f32::consts::FRAC_PI_4 * (w * h) as f32 / (4.0 * std::f32::consts::PI)
            }
        }
    }
}

/// A direction and its derivative made unit length: `d̂ = d/|d|`,
/// `∂d̂ = (∂d − d̂(d̂·∂d))/|d|`.
#[inline]
fn unit_with_derivatives(fp: &CubeFootprint) -> (Vec3, Vec3, Vec3) {
    let len = fp.dir.length();
    if !(len > 0.0) || !len.is_finite() {
        return (Vec3::NEG_Z, Vec3::ZERO, Vec3::ZERO);
    }
    let d = fp.dir / len;
    let project = |dd: Vec3| (dd - d * d.dot(dd)) / len;
    (d, project(fp.ddir_dx), project(fp.ddir_dy))
}

/// The equirectangular coordinates of a unit direction (the module docs' convention, rows
/// at OpenGL's texel centres for level 0 of a panorama `height` rows tall).
#[inline]
#[must_use]
pub fn equirect_uv(d: Vec3, height: u32) -> Vec2 {
    let u = d.x.atan2(-d.z) * (0.5 / std::f32::consts::PI);
    let u = if u < 0.0 { u + 1.0 } else { u };
    let v = d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI;
    Vec2::new(u, row_remap(v, height))
}

/// Mitsuba's rows (`θ = π·i/(H − 1)`) at OpenGL's texel centres: `(v·(H − 1) + ½)/H`.
#[inline]
fn row_remap(v: f32, height: u32) -> f32 {
    let h = height.max(2) as f32;
    (v * (h - 1.0) + 0.5) / h
}

/// The unit direction an equirectangular `(u, v)` (the docs' `v`, before the row remap)
/// looks along: the inverse of [`equirect_uv`].
#[inline]
#[must_use]
pub fn equirect_direction(u: f32, v: f32) -> Vec3 {
    let (sin_t, cos_t) = (v * std::f32::consts::PI).sin_cos();
    let (sin_p, cos_p) = (u * std::f32::consts::TAU).sin_cos();
    Vec3::new(sin_p * sin_t, cos_t, -cos_p * sin_t)
}

/// The footprint on an equirectangular panorama of `height` rows: `uv` and its derivatives
/// by the chain rule, `∂u = (−z·∂x + x·∂z)/(2π(x² + z²))`, `∂v = −∂y/(π·√(x² + z²))` (times
/// the row remap's `(H − 1)/H`) — continuous across the seam, growing towards the poles.
#[must_use]
pub fn equirect_footprint(fp: &CubeFootprint, height: u32) -> Footprint {
    let (d, dx, dy) = unit_with_derivatives(fp);
    let uv = equirect_uv(d, height);
    let r2 = (d.x * d.x + d.z * d.z).max(1e-12);
    let r = r2.sqrt();
    let h = height.max(2) as f32;
    let row_scale = (h - 1.0) / h;
    let deriv = |dd: Vec3| {
        Vec2::new(
            (-d.z * dd.x + d.x * dd.z) / (std::f32::consts::TAU * r2),
            -dd.y / (std::f32::consts::PI * r) * row_scale,
        )
    };
    Footprint::new(uv, deriv(dx), deriv(dy))
}

/// [`equirect_footprint`] of four footprints, one per lane: the same operations in the same
/// order lane by lane (atan2 and acos by the same library calls per lane), so the same
/// values. `None` when a direction is zero or not finite (the scalar rule's special case).
#[must_use]
pub fn equirect_footprint_lanes(fp: &CubeFootprintLanes, height: u32) -> Option<FootprintLanes> {
    let [x, y, z] = fp.dir;
    // Unit direction and derivatives (`unit_with_derivatives`).
    let len = sqrt4(x * x + y * y + z * z);
    if !len.cmpgt(Vec4::ZERO).all() || !len.is_finite() {
        return None;
    }
    let (dx, dy, dz) = (x / len, y / len, z / len);
    let project = |[ddx, ddy, ddz]: [Vec4; 3]| {
        let dot = dx * ddx + dy * ddy + dz * ddz;
        (
            (ddx - dx * dot) / len,
            (ddy - dy * dot) / len,
            (ddz - dz * dot) / len,
        )
    };
    let (xx, xy, xz) = project(fp.ddir_dx);
    let (yx, yy, yz) = project(fp.ddir_dy);
    // `equirect_uv`, the library calls per lane.
    let u = Vec4::from_array(std::array::from_fn(|j| dx[j].atan2(-dz[j])))
        * (0.5 / std::f32::consts::PI);
    let u = Vec4::select(u.cmplt(Vec4::ZERO), u + 1.0, u);
    let v = Vec4::from_array(std::array::from_fn(|j| dy[j].clamp(-1.0, 1.0).acos()))
        / std::f32::consts::PI;
    let h = height.max(2) as f32;
    let v = (v * (h - 1.0) + 0.5) / h;
    // The chain rule (`equirect_footprint`).
    let r2 = (dx * dx + dz * dz).max(Vec4::splat(1e-12));
    let r = sqrt4(r2);
    let row_scale = (h - 1.0) / h;
    let du = |ddx: Vec4, ddz: Vec4| (-dz * ddx + dx * ddz) / (std::f32::consts::TAU * r2);
    let dv = |ddy: Vec4| -ddy / (std::f32::consts::PI * r) * row_scale;
    Some(FootprintLanes {
        u,
        v,
        dudx: du(xx, xz),
        dvdx: dv(xy),
        dudy: du(yx, yz),
        dvdy: dv(yy),
    })
}

/// Lane-wise square root (one `sqrtps`, correctly rounded as `f32::sqrt` is).
#[inline(always)]
fn sqrt4(v: Vec4) -> Vec4 {
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY: SSE is part of x86_64.
        Vec4::from(unsafe { std::arch::x86_64::_mm_sqrt_ps(v.into()) })
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        Vec4::from_array(v.to_array().map(f32::sqrt))
    }
}

/// The footprint on an OpenGL sphere map: `(u, v) = (x/m + ½, ½ − y/m)` with
/// `m = 2·√(x² + y² + (z + 1)²)`, and its derivatives by the chain rule.
#[must_use]
pub fn sphere_map_footprint(fp: &CubeFootprint) -> Footprint {
    let (d, dx, dy) = unit_with_derivatives(fp);
    let p = Vec3::new(d.x, d.y, d.z + 1.0);
    let m = (2.0 * p.length()).max(1e-4);
    let uv = Vec2::new(d.x / m + 0.5, 0.5 - d.y / m);
    let deriv = |dd: Vec3| {
        // ∂m = 4(p·∂p)/m, with ∂p = ∂d.
        let dm = 4.0 * p.dot(dd) / m;
        Vec2::new((dd.x - d.x * dm / m) / m, -(dd.y - d.y * dm / m) / m)
    };
    Footprint::new(uv, deriv(dx), deriv(dy))
}

/// The face names of a folder of six images, in [`super::CubeFace::ALL`] order.
pub const FACE_NAMES: [&str; 6] = ["posx", "negx", "posy", "negy", "posz", "negz"];

/// Loads an environment map: an image file (its layout `kind`, or else told by its
/// proportions: 2:1 equirectangular, 4:3 or 3:4 a cross, 1:1 a sphere map) or a folder of six
/// faces. 8- and 16-bit images hold sRGB colour; HDR and EXR linear radiance.
///
/// # Errors
/// One line naming the file or folder: missing, undecodable, above `limits`, proportions that
/// fit no layout (or not the one asked for), faces of different sizes, a container file that
/// is an array or volume texture.
pub fn load_environment(
    path: &Path,
    kind: Option<EnvironmentKind>,
    limits: &Limits,
) -> Result<EnvironmentMap> {
    let container = (!path.is_dir())
        .then(|| Container::of_file(path))
        .flatten()
        .map(|_| read_texture_file(path, limits))
        .transpose()?;
    if let Some(file) = container.as_ref().filter(|f| f.faces() == 6) {
        if kind.is_some_and(|k| k != EnvironmentKind::Faces) {
            return Err(Error::decode(
                path,
                format!(
                    "is a cube map; a {} environment is one flat image",
                    kind.map_or("", EnvironmentKind::name)
                ),
            ));
        }
        return cube_from_file(file, ColorSpace::Srgb, TextureOptions::default())
            .map(|c| EnvironmentMap::Cube(Box::new(c)));
    }
    if container.is_some() && kind == Some(EnvironmentKind::Faces) {
        return Err(Error::decode(
            path,
            "is one flat texture; a faces environment is a folder of six images or a cube map \
             file",
        ));
    }
    if path.is_dir() || kind == Some(EnvironmentKind::Faces) {
        if kind.is_some_and(|k| k != EnvironmentKind::Faces) {
            return Err(Error::decode(
                path,
                format!(
                    "is a folder; a {} environment is one image",
                    kind.map_or("", EnvironmentKind::name)
                ),
            ));
        }
        return load_faces(path, limits).map(|c| EnvironmentMap::Cube(Box::new(c)));
    }
    let img = match &container {
        Some(file) => flat_image(file)?,
        None => decode_image(path, limits)?,
    };
    let (w, h) = (img.width(), img.height());
    let kind = match kind {
        Some(k) => k,
        None if w == 2 * h => EnvironmentKind::Equirect,
        None if 3 * w == 4 * h || 4 * w == 3 * h => EnvironmentKind::Cross,
        None if w == h => EnvironmentKind::Sphere,
        None => {
            return Err(Error::decode(
                path,
                format!(
                    "is {w}x{h}: an environment image is 2:1 (equirectangular), 4:3 or 3:4 \
                     (a cross of six square faces) or 1:1 (a sphere map)"
                ),
            ))
        }
    };
    let texture = |img: DynamicImage| {
        texture_from_image(img, ColorSpace::Srgb, TextureOptions::default())
            .map_err(|e| Error::decode(path, e.to_string()))
    };
    match kind {
        EnvironmentKind::Equirect => {
            if w != 2 * h {
                return Err(Error::decode(
                    path,
                    format!("is {w}x{h}: an equirectangular panorama is twice as wide as tall"),
                ));
            }
            texture(img).map(EnvironmentMap::Equirect)
        }
        EnvironmentKind::Sphere => {
            if w != h {
                return Err(Error::decode(
                    path,
                    format!("is {w}x{h}: a sphere map is square"),
                ));
            }
            texture(img).map(EnvironmentMap::Sphere)
        }
        EnvironmentKind::Cross => {
            cube_from_cross(img, path).map(|c| EnvironmentMap::Cube(Box::new(c)))
        }
        EnvironmentKind::Faces => unreachable!("folders are handled above"),
    }
}

/// The six faces of a 4:3 horizontal or 3:4 vertical cross (the module docs' layouts).
fn cube_from_cross(img: DynamicImage, path: &Path) -> Result<TextureCube> {
    let (w, h) = (img.width(), img.height());
    let horizontal = 3 * w == 4 * h && w % 4 == 0;
    let vertical = 4 * w == 3 * h && w % 3 == 0;
    if !(horizontal || vertical) || w == 0 {
        return Err(Error::decode(
            path,
            format!(
                "is {w}x{h}: a cross is 4N x 3N (horizontal) or 3N x 4N (vertical) with square \
                 faces of N x N"
            ),
        ));
    }
    let n = if horizontal { w / 4 } else { w / 3 };
    // (column, row) of each face in CubeFace::ALL order.
    let cells: [(u32, u32); 6] = if horizontal {
        [(2, 1), (0, 1), (1, 0), (1, 2), (1, 1), (3, 1)]
    } else {
        [(2, 1), (0, 1), (1, 0), (1, 2), (1, 1), (1, 3)]
    };
    let mut faces = Vec::with_capacity(6);
    for (i, &(cx, cy)) in cells.iter().enumerate() {
        let mut face = img.crop_imm(cx * n, cy * n, n, n);
        if vertical && i == 5 {
            // The vertical cross unfolds −Z below −Y, upside down.
            face = face.rotate180();
        }
        faces.push(
            texture_from_image(face, ColorSpace::Srgb, TextureOptions::default())
                .map_err(|e| Error::decode(path, e.to_string()))?,
        );
    }
    let faces: [Texture2D; 6] = faces.try_into().expect("six faces");
    TextureCube::new(faces).map_err(|e| Error::decode(path, e.to_string()))
}

/// Six face images `posx` … `negz` (any extension [`super::load`] reads) from a folder.
fn load_faces(dir: &Path, limits: &Limits) -> Result<TextureCube> {
    let entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| Error::io(dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    let mut faces = Vec::with_capacity(6);
    for name in FACE_NAMES {
        let mut found: Vec<&PathBuf> = entries
            .iter()
            .filter(|p| {
                p.file_stem().and_then(|s| s.to_str()) == Some(name)
                    && p.extension().is_some_and(|e| {
                        matches!(
                            e.to_ascii_lowercase().to_str(),
                            Some("png" | "jpg" | "jpeg" | "tga" | "bmp" | "hdr" | "exr")
                        )
                    })
            })
            .collect();
        found.sort();
        let Some(file) = found.first() else {
            return Err(Error::decode(
                dir,
                format!(
                    "has no {name} image: a folder environment holds six faces named {}",
                    FACE_NAMES.join(", ")
                ),
            ));
        };
        let img = decode_image(file, limits)?;
        faces.push(
            texture_from_image(img, ColorSpace::Srgb, TextureOptions::default())
                .map_err(|e| Error::decode(file, e.to_string()))?,
        );
    }
    let faces: [Texture2D; 6] = faces.try_into().expect("six faces");
    TextureCube::new(faces).map_err(|e| Error::decode(dir, e.to_string()))
}

#[cfg(test)]
mod tests;
