//! Cube maps: six square faces addressed by a direction, sampled seamlessly across edges.
//!
//! Faces follow OpenGL's order and orientation (+X, −X, +Y, −Y, +Z, −Z; table 8.19 of the GL
//! 4.6 specification), with the face's `(s, t)` used as our `uv` (t runs down the image rows).
//! Seamless filtering: a bilinear tap that falls off a face is turned back into a direction
//! through that texel's centre on the face's extended plane, and read from the face that
//! direction hits — so there is no seam at edges, at any level. Anisotropic taps are spread
//! along the direction's derivative and each tap is seamless too. EWA and summed-area filters
//! run on the centre's face with clamp-to-edge (a documented approximation near edges).
//!
//! λ comes from the face coordinates' derivatives (the quotient rule on the direction's) and
//! OpenGL filters choose their levels from it as 2D reads do ([`MipChoice::gl`]).

use glam::{Vec2, Vec3, Vec4};

use super::filter::anisotropic::{probe_count, probe_lod};
use super::filter::{ellipse_axes, floor_index};
use super::format::{with_texture_codec, Codec};
use super::{
    sample, CubeFootprint, Filter, Footprint, MipChoice, Sampler, TexelFilter, Texture2D, Wrap,
};
use crate::{Error, Result};

/// A face of a cube map, in OpenGL's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CubeFace {
    PosX,
    NegX,
    PosY,
    NegY,
    PosZ,
    NegZ,
}

impl CubeFace {
    /// All faces, in order.
    pub const ALL: [CubeFace; 6] = [
        CubeFace::PosX,
        CubeFace::NegX,
        CubeFace::PosY,
        CubeFace::NegY,
        CubeFace::PosZ,
        CubeFace::NegZ,
    ];

    /// The face a direction hits and its `(sc, tc, |ma|)` (OpenGL's table 8.19).
    #[inline]
    pub(crate) fn select(d: Vec3) -> (usize, f32, f32, f32) {
        let a = d.abs();
        if a.x >= a.y && a.x >= a.z {
            if d.x >= 0.0 {
                (0, -d.z, -d.y, a.x)
            } else {
                (1, d.z, -d.y, a.x)
            }
        } else if a.y >= a.z {
            if d.y >= 0.0 {
                (2, d.x, d.z, a.y)
            } else {
                (3, d.x, -d.z, a.y)
            }
        } else if d.z >= 0.0 {
            (4, d.x, -d.y, a.z)
        } else {
            (5, -d.x, -d.y, a.z)
        }
    }

    /// A vector's `(s, t, m)` on face `face`'s axes (the ones [`CubeFace::select`] uses for
    /// that face, `m` signed): for a derivative of a direction whose face is known.
    #[inline]
    pub(crate) fn axes(face: usize, d: Vec3) -> (f32, f32, f32) {
        match face {
            0 => (-d.z, -d.y, d.x),
            1 => (d.z, -d.y, -d.x),
            2 => (d.x, d.z, d.y),
            3 => (d.x, -d.z, -d.y),
            4 => (d.x, -d.y, d.z),
            _ => (-d.x, -d.y, -d.z),
        }
    }

    /// The direction (not normalised) through face coordinates `(sc, tc)` in [−1, 1] of
    /// this face (outside that range, on the face's extended plane).
    #[inline]
    #[must_use]
    pub fn direction_through(self, sc: f32, tc: f32) -> Vec3 {
        Self::direction(self as usize, sc, tc)
    }

    /// [`CubeFace::direction_through`] by the face's index in [`CubeFace::ALL`].
    #[inline]
    pub(crate) fn direction(face: usize, sc: f32, tc: f32) -> Vec3 {
        match face {
            0 => Vec3::new(1.0, -tc, -sc),
            1 => Vec3::new(-1.0, -tc, sc),
            2 => Vec3::new(sc, 1.0, tc),
            3 => Vec3::new(sc, -1.0, -tc),
            4 => Vec3::new(sc, -tc, 1.0),
            _ => Vec3::new(-sc, -tc, -1.0),
        }
    }
}

/// A cube map: six square faces of one size and format, each with its mip chain.
#[derive(Clone, Debug)]
pub struct TextureCube {
    faces: [Texture2D; 6],
}

impl TextureCube {
    /// Builds a cube map from six faces in [`CubeFace::ALL`] order.
    pub fn new(faces: [Texture2D; 6]) -> Result<Self> {
        let (w, f) = (faces[0].width(), faces[0].storage_format());
        let blocks = faces[0].block_format();
        for (i, t) in faces.iter().enumerate() {
            let same = t.storage_format() == f && t.block_format() == blocks;
            if t.width() != w || t.height() != w || !same {
                return Err(Error::parameter(format!(
                    "cube face {i} is {}x{} {:?}; every face must be {w}x{w} {f:?}",
                    t.width(),
                    t.height(),
                    t.storage_format()
                )));
            }
        }
        Ok(TextureCube { faces })
    }

    /// The faces in [`CubeFace::ALL`] order.
    #[must_use]
    pub fn faces(&self) -> &[Texture2D; 6] {
        &self.faces
    }

    /// Face size in texels.
    #[must_use]
    pub fn size(&self) -> u32 {
        self.faces[0].width()
    }

    /// The face and face uv a direction hits.
    #[must_use]
    pub fn face_uv(dir: Vec3) -> (CubeFace, Vec2) {
        let (f, sc, tc, ma) = CubeFace::select(dir);
        (
            CubeFace::ALL[f],
            Vec2::new(0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0)),
        )
    }
}

/// Reads a cube map along a direction footprint: linear, premultiplied RGBA.
#[must_use]
pub fn sample_cube(cube: &TextureCube, sampler: &Sampler, fp: &CubeFootprint) -> Vec4 {
    with_texture_codec!(&cube.faces[0], C => sample_cube_with::<C>(cube, sampler, fp))
}

/// The face footprint of a direction footprint (derivatives by the quotient rule).
fn face_footprint(fp: &CubeFootprint) -> (usize, Footprint) {
    let (f, sc, tc, ma) = CubeFace::select(fp.dir);
    let deriv = |dd: Vec3| {
        let (ds, dt, dm) = CubeFace::axes(f, dd);
        Vec2::new(
            (ds * ma - sc * dm) / (2.0 * ma * ma),
            (dt * ma - tc * dm) / (2.0 * ma * ma),
        )
    };
    let uv = Vec2::new(0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0));
    (f, Footprint::new(uv, deriv(fp.ddir_dx), deriv(fp.ddir_dy)))
}

fn sample_cube_with<C: Codec>(cube: &TextureCube, s: &Sampler, fp: &CubeFootprint) -> Vec4 {
    if !(fp.dir.length_squared() > 0.0) || !fp.dir.is_finite() {
        return Vec4::ZERO;
    }
    let (face, ffp) = face_footprint(fp);
    let n = cube.size() as f32;
    let (dx, dy) = (ffp.duv_dx * n, ffp.duv_dy * n);
    let levels = cube.faces[0].levels().len();
    match s.filter {
        Filter::Gl { mag, min } => {
            let lod = s.adjust_lod(s.lod_rule.lod(dx, dy));
            let choice = MipChoice::gl(lod, levels, mag, min);
            choice.read(|level| match choice.texels {
                TexelFilter::Nearest => nearest_cube::<C>(cube, face, ffp.uv, level),
                TexelFilter::Linear => bilinear_cube::<C>(cube, face, ffp.uv, level),
            })
        }
        Filter::Anisotropic { max_aniso, lod } => {
            let (_, major, minor) = ellipse_axes(dx, dy);
            let taps = probe_count(major, minor, max_aniso);
            let lod = s.adjust_lod(probe_lod(major, minor, taps, lod, f32::log2));
            if !(major > 1.0) {
                return bilinear_cube::<C>(cube, face, ffp.uv, 0);
            }
            // Taps along the longer direction derivative, each a seamless trilinear read.
            let axis = if dx.length_squared() >= dy.length_squared() {
                fp.ddir_dx
            } else {
                fp.ddir_dy
            };
            let choice = MipChoice::trilinear(lod, levels);
            let mut sum = Vec4::ZERO;
            for i in 0..taps as u32 {
                let t = (i as f32 + 0.5) / taps - 0.5;
                let (tf, tuv) = {
                    let (tf, sc, tc, ma) = CubeFace::select(fp.dir + axis * t);
                    (tf, Vec2::new(0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0)))
                };
                sum += choice.read(|level| bilinear_cube::<C>(cube, tf, tuv, level));
            }
            sum / taps
        }
        Filter::Ewa { .. } | Filter::EwaExact { .. } | Filter::SummedArea => {
            let clamped = s.with_wraps(Wrap::ClampToEdge, Wrap::ClampToEdge, s.wrap_w);
            sample(&cube.faces[face], &clamped, &ffp)
        }
    }
}

/// Texel `(x, y)` of `face` at `level`; off-face indices continue on the neighbouring face.
#[inline]
fn fetch_cube<C: Codec>(cube: &TextureCube, face: usize, level: usize, x: i32, y: i32) -> Vec4 {
    let lv = cube.faces[face].level(level);
    let n = lv.w;
    if (0..n).contains(&x) && (0..n).contains(&y) {
        return lv.texel::<C>(x, y);
    }
    // Re-project the texel centre on the extended plane onto the face it really lies on.
    let sc = 2.0 * (x as f32 + 0.5) / n as f32 - 1.0;
    let tc = 2.0 * (y as f32 + 0.5) / n as f32 - 1.0;
    let (f, s2, t2, ma) = CubeFace::select(CubeFace::direction(face, sc, tc));
    let nx = floor_index(0.5 * (s2 / ma + 1.0) * n as f32).clamp(0, n - 1);
    let ny = floor_index(0.5 * (t2 / ma + 1.0) * n as f32).clamp(0, n - 1);
    cube.faces[f].level(level).texel::<C>(nx, ny)
}

fn nearest_cube<C: Codec>(cube: &TextureCube, face: usize, uv: Vec2, level: usize) -> Vec4 {
    let lv = cube.faces[face].level(level);
    let x = floor_index(uv.x * lv.w as f32).clamp(0, lv.w - 1);
    let y = floor_index(uv.y * lv.h as f32).clamp(0, lv.h - 1);
    lv.texel::<C>(x, y)
}

fn bilinear_cube<C: Codec>(cube: &TextureCube, face: usize, uv: Vec2, level: usize) -> Vec4 {
    let n = cube.faces[face].level(level).w as f32;
    let (px, py) = (uv.x * n - 0.5, uv.y * n - 0.5);
    let (fx, fy) = (px.floor(), py.floor());
    let (ax, ay) = (px - fx, py - fy);
    let (x0, y0) = (floor_index(fx), floor_index(fy));
    let t = |x, y| fetch_cube::<C>(cube, face, level, x, y);
    let top = t(x0, y0).lerp(t(x0 + 1, y0), ax);
    let bottom = t(x0, y0 + 1).lerp(t(x0 + 1, y0 + 1), ax);
    top.lerp(bottom, ay)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::TextureOptions;

    fn solid_faces(n: u32) -> TextureCube {
        let colours = [
            Vec4::new(1.0, 0.0, 0.0, 1.0),
            Vec4::new(0.0, 1.0, 0.0, 1.0),
            Vec4::new(0.0, 0.0, 1.0, 1.0),
            Vec4::new(1.0, 1.0, 0.0, 1.0),
            Vec4::new(0.0, 1.0, 1.0, 1.0),
            Vec4::new(1.0, 0.0, 1.0, 1.0),
        ];
        TextureCube::new(
            colours.map(|c| Texture2D::from_fn(n, n, TextureOptions::default(), |_, _| c).unwrap()),
        )
        .unwrap()
    }

    #[test]
    fn axis_directions_pick_their_faces() {
        let cube = solid_faces(4);
        let s = Sampler::new(Filter::NEAREST, Wrap::ClampToEdge);
        let dirs = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
        for (i, d) in dirs.into_iter().enumerate() {
            let c = sample_cube(
                &cube,
                &s,
                &CubeFootprint {
                    dir: d,
                    ..Default::default()
                },
            );
            let want = cube.faces()[i].texel(0, 0, 0);
            assert_eq!(c, want, "face {i}");
        }
    }

    #[test]
    fn face_orientation_follows_gl() {
        // On +Z, s grows with +x and t grows with −y.
        let (f, uv) = TextureCube::face_uv(Vec3::new(0.5, 0.5, 1.0));
        assert_eq!(f, CubeFace::PosZ);
        assert!((uv - Vec2::new(0.75, 0.25)).length() < 1e-6);
        let (f, uv) = TextureCube::face_uv(Vec3::new(1.0, 0.0, 0.5));
        assert_eq!(f, CubeFace::PosX);
        assert!((uv - Vec2::new(0.25, 0.5)).length() < 1e-6);
    }

    #[test]
    fn bilinear_is_continuous_across_an_edge() {
        // Just either side of the +X/+Z edge the colours blend to the same value.
        let cube = solid_faces(8);
        let s = Sampler::new(Filter::BILINEAR, Wrap::ClampToEdge);
        let read = |d: Vec3| {
            sample_cube(
                &cube,
                &s,
                &CubeFootprint {
                    dir: d,
                    ..Default::default()
                },
            )
        };
        let a = read(Vec3::new(1.0, 0.1, 0.9999));
        let b = read(Vec3::new(0.9999, 0.1, 1.0));
        assert!((a - b).abs().max_element() < 1e-3, "{a} vs {b}");
        // And the value mixes both faces' colours.
        assert!(a.x > 0.2 && a.y > 0.2, "{a}");
    }

    #[test]
    fn constant_cube_reads_constant_under_every_filter() {
        let c = Vec4::new(0.3, 0.5, 0.7, 1.0);
        let cube = TextureCube::new(std::array::from_fn(|_| {
            Texture2D::from_fn(16, 16, TextureOptions::default(), |_, _| c).unwrap()
        }))
        .unwrap();
        for name in ["nearest", "bilinear", "trilinear", "aniso16", "ewa", "sat"] {
            let s = Sampler::new(Filter::parse(name).unwrap(), Wrap::ClampToEdge);
            for d in [Vec3::new(1.0, 0.99, -0.98), Vec3::new(0.2, -1.0, 0.3)] {
                let fp = CubeFootprint {
                    dir: d,
                    ddir_dx: Vec3::new(0.3, 0.0, 0.0),
                    ddir_dy: Vec3::new(0.0, 0.05, 0.0),
                };
                let v = sample_cube(&cube, &s, &fp);
                assert!((v - c).abs().max_element() < 1e-5, "{name}: {v}");
            }
        }
    }
}
