//! 3D textures (volumes, solid textures): nearest and trilinear, mipmapped.
//!
//! Voxels are stored row-major, x fastest, in any [`Format`]. Mip levels halve each axis
//! (`max(1, ⌊n/2⌋)`) with the same exact-area box as 2D levels, in linear light.
//!
//! Reads choose λ and their levels as 2D reads do ([`super::LodRule::lod3`],
//! [`MipChoice::gl`]); within a level a linear read is trilinear (eight voxels). Anisotropic,
//! EWA and summed-area filters have no 3D form here and read as trilinear between levels.

use glam::{Vec3, Vec4};

use super::filter::floor_index;
use super::format::{decode_table, with_codec, Codec};
use super::{ColorSpace, Filter, Footprint3, Format, MipChoice, Sampler, TexelFilter, BORDER};
use crate::{Error, Result};

#[derive(Clone, Debug)]
struct Level3 {
    dims: [u32; 3],
    data: Vec<u8>,
}

/// A 3D texture with its mip chain (level 0 first).
#[derive(Clone, Debug)]
pub struct Texture3D {
    format: Format,
    levels: Vec<Level3>,
    lut: &'static [f32],
}

impl Texture3D {
    /// Builds a 3D texture from voxels of `format`, x fastest, then y, then z.
    pub fn from_texels(
        dims: [u32; 3],
        format: Format,
        color_space: ColorSpace,
        texels: &[u8],
        mipmaps: bool,
    ) -> Result<Self> {
        if dims.contains(&0) {
            return Err(Error::parameter(format!(
                "3D texture size {dims:?} has a zero side"
            )));
        }
        let count = dims.iter().map(|&d| d as usize).product::<usize>();
        if texels.len() != count * format.bytes_per_texel() {
            return Err(Error::parameter(format!(
                "3D texture {dims:?} {format:?} needs {} bytes, got {}",
                count * format.bytes_per_texel(),
                texels.len()
            )));
        }
        let color_space = if format.is_unorm() {
            color_space
        } else {
            ColorSpace::Linear
        };
        let lut = decode_table(format, color_space);
        let mut tex = Texture3D {
            format,
            levels: vec![Level3 {
                dims,
                data: texels.to_vec(),
            }],
            lut,
        };
        if mipmaps {
            let mut cur: Vec<Vec4> =
                with_codec!(format, C => (0..count).map(|i| tex.voxel_at::<C>(0, i)).collect());
            let mut d = dims;
            while d.iter().any(|&n| n > 1) {
                let (nd, next) = reduce3(d, &cur);
                let bpp = format.bytes_per_texel();
                let mut bytes = vec![0u8; next.len() * bpp];
                for (i, c) in next.iter().enumerate() {
                    format.encode(
                        super::mip::unpremultiply(*c),
                        color_space,
                        &mut bytes[i * bpp..(i + 1) * bpp],
                    );
                }
                tex.levels.push(Level3 {
                    dims: nd,
                    data: bytes,
                });
                (d, cur) = (nd, next);
            }
        }
        Ok(tex)
    }

    /// Level-0 size.
    #[must_use]
    pub fn dims(&self) -> [u32; 3] {
        self.levels[0].dims
    }
    /// The voxel format.
    #[must_use]
    pub fn format(&self) -> Format {
        self.format
    }
    /// Number of mip levels.
    #[must_use]
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    #[inline(always)]
    fn voxel_at<C: Codec>(&self, level: usize, i: usize) -> Vec4 {
        let data = &self.levels[level].data;
        C::decode_premultiplied(&data[i * C::BPP..(i + 1) * C::BPP], self.lut)
    }

    /// Linear, premultiplied voxel `(x, y, z)` of `level` (in range).
    #[must_use]
    pub fn voxel(&self, level: usize, x: u32, y: u32, z: u32) -> Vec4 {
        let [w, h, _] = self.levels[level].dims;
        let i = ((z * h + y) * w + x) as usize;
        with_codec!(self.format, C => self.voxel_at::<C>(level, i))
    }
}

#[cfg(test)]
impl Texture3D {
    /// Overwrites every level's voxels with `f(level, x, y, z)` (linear, premultiplied; the
    /// texture must be linear): for tests that need levels unlike a box-filtered chain.
    pub(crate) fn replace_levels(&mut self, f: impl Fn(usize, u32, u32, u32) -> Vec4) {
        let bpp = self.format.bytes_per_texel();
        for (i, level) in self.levels.iter_mut().enumerate() {
            let [w, h, _] = level.dims;
            for (k, out) in level.data.chunks_exact_mut(bpp).enumerate() {
                let k = k as u32;
                let c = f(i, k % w, k / w % h, k / (w * h));
                self.format
                    .encode(super::mip::unpremultiply(c), ColorSpace::Linear, out);
            }
        }
    }
}

/// Exact-area box reduction of one 3D level (separable, axis by axis).
fn reduce3(d: [u32; 3], src: &[Vec4]) -> ([u32; 3], Vec<Vec4>) {
    let nd = d.map(|n| (n / 2).max(1));
    let mut cur = src.to_vec();
    let mut dims = d;
    for axis in 0..3 {
        let (n, m) = (dims[axis], nd[axis]);
        let mut next_dims = dims;
        next_dims[axis] = m;
        let stride: usize = dims[..axis].iter().map(|&v| v as usize).product();
        let outer: usize = dims[axis + 1..].iter().map(|&v| v as usize).product();
        let mut out = vec![Vec4::ZERO; stride * m as usize * outer];
        let scale = n as f64 / m as f64;
        for o in 0..outer {
            for i in 0..m as usize {
                let (lo, hi) = (i as f64 * scale, (i + 1) as f64 * scale);
                for j in lo.floor() as usize..(hi.ceil() as usize).min(n as usize) {
                    let w = ((hi.min(j as f64 + 1.0) - lo.max(j as f64)) / scale) as f32;
                    if w <= 0.0 {
                        continue;
                    }
                    for s in 0..stride {
                        out[(o * m as usize + i) * stride + s] +=
                            cur[(o * n as usize + j) * stride + s] * w;
                    }
                }
            }
        }
        cur = out;
        dims = next_dims;
    }
    (nd, cur)
}

/// Reads a 3D texture over a footprint: linear, premultiplied RGBA.
///
/// λ comes from the sampler's [`super::LodRule`] on the three-component derivatives, and
/// OpenGL filters choose their levels as in 2D ([`MipChoice::gl`]), a linear read being
/// trilinear within a level. Filters with no 3D form (anisotropic, EWA, summed-area) read as
/// trilinear between levels.
#[must_use]
pub fn sample_3d(tex: &Texture3D, sampler: &Sampler, fp: &Footprint3) -> Vec4 {
    with_codec!(tex.format, C => sample_3d_with::<C>(tex, sampler, fp))
}

fn sample_3d_with<C: Codec>(tex: &Texture3D, s: &Sampler, fp: &Footprint3) -> Vec4 {
    let size = Vec3::from_array(tex.dims().map(|v| v as f32));
    let (dx, dy) = (fp.duvw_dx * size, fp.duvw_dy * size);
    let lod = s.adjust_lod(s.lod_rule.lod3(dx, dy));
    let choice = match s.filter {
        Filter::Gl { mag, min } => MipChoice::gl(lod, tex.levels.len(), mag, min),
        Filter::Anisotropic { .. }
        | Filter::Ewa { .. }
        | Filter::EwaExact { .. }
        | Filter::SummedArea => MipChoice::trilinear(lod, tex.levels.len()),
    };
    let a = read_level3::<C>(tex, s, choice.level, choice.texels, fp.uvw);
    match choice.blend {
        Some(b) => a.lerp(
            read_level3::<C>(tex, s, b.level, choice.texels, fp.uvw),
            b.weight,
        ),
        None => a,
    }
}

/// Level `level` read at `p` with `texels`.
#[inline(always)]
fn read_level3<C: Codec>(
    tex: &Texture3D,
    s: &Sampler,
    level: usize,
    texels: TexelFilter,
    p: Vec3,
) -> Vec4 {
    match texels {
        TexelFilter::Nearest => nearest3::<C>(tex, s, level, p),
        TexelFilter::Linear => trilinear3::<C>(tex, s, level, p),
    }
}

#[inline(always)]
fn fetch3<C: Codec>(tex: &Texture3D, s: &Sampler, level: usize, x: i32, y: i32, z: i32) -> Vec4 {
    let [w, h, d] = tex.levels[level].dims.map(|v| v as i32);
    let (xi, yi, zi) = (
        s.wrap_u.index(x, w),
        s.wrap_v.index(y, h),
        s.wrap_w.index(z, d),
    );
    if xi == BORDER || yi == BORDER || zi == BORDER {
        return s.border;
    }
    tex.voxel_at::<C>(level, ((zi * h + yi) * w + xi) as usize)
}

fn nearest3<C: Codec>(tex: &Texture3D, s: &Sampler, level: usize, p: Vec3) -> Vec4 {
    let dims = Vec3::from_array(tex.levels[level].dims.map(|v| v as f32));
    let q = p * dims;
    fetch3::<C>(
        tex,
        s,
        level,
        floor_index(q.x),
        floor_index(q.y),
        floor_index(q.z),
    )
}

/// Trilinear interpolation of the eight voxels around `p` on one level.
#[inline]
pub(crate) fn trilinear3<C: Codec>(tex: &Texture3D, s: &Sampler, level: usize, p: Vec3) -> Vec4 {
    let dims = Vec3::from_array(tex.levels[level].dims.map(|v| v as f32));
    let q = p * dims - 0.5;
    let f = q.floor();
    let a = q - f;
    let (x, y, z) = (floor_index(f.x), floor_index(f.y), floor_index(f.z));
    // Saturating: a point far outside (a helper pixel's extrapolated one) floors to
    // `i32::MAX`, whose neighbour would overflow.
    let v = |dx: i32, dy: i32, dz: i32| {
        fetch3::<C>(
            tex,
            s,
            level,
            x.saturating_add(dx),
            y.saturating_add(dy),
            z.saturating_add(dz),
        )
    };
    let c00 = v(0, 0, 0).lerp(v(1, 0, 0), a.x);
    let c10 = v(0, 1, 0).lerp(v(1, 1, 0), a.x);
    let c01 = v(0, 0, 1).lerp(v(1, 0, 1), a.x);
    let c11 = v(0, 1, 1).lerp(v(1, 1, 1), a.x);
    c00.lerp(c10, a.y).lerp(c01.lerp(c11, a.y), a.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::Wrap;

    fn ramp(n: u32) -> Texture3D {
        let bytes: Vec<u8> = (0..n * n * n)
            .flat_map(|i| ((i % n) as f32 / (n - 1) as f32).to_le_bytes())
            .collect();
        Texture3D::from_texels([n, n, n], Format::R32F, ColorSpace::Linear, &bytes, true).unwrap()
    }

    #[test]
    fn trilinear_at_voxel_centres_returns_voxels() {
        let t = ramp(8);
        let s = Sampler::new(Filter::BILINEAR, Wrap::ClampToEdge);
        for x in 0..8 {
            let p = Vec3::new((x as f32 + 0.5) / 8.0, 0.3, 0.6);
            let v = sample_3d(&t, &s, &Footprint3::point(p));
            assert!((v.x - x as f32 / 7.0).abs() < 1e-6);
        }
    }

    #[test]
    fn a_point_far_outside_reads_without_overflow() {
        // Past `i32::MAX` texels once scaled: the floored index saturates, and its
        // neighbour must not overflow (clamped, the edge voxel; repeated, some voxel).
        let t = ramp(8);
        for wrap in [Wrap::ClampToEdge, Wrap::Repeat] {
            let s = Sampler::new(Filter::BILINEAR, wrap);
            for (x, edge) in [(1e12, 1.0), (-1e12, 0.0), (3e9, 1.0)] {
                let p = Vec3::new(x, 0.5, 0.5);
                let v = sample_3d(&t, &s, &Footprint3::point(p));
                assert!(v.is_finite(), "{wrap:?} {p}: {v}");
                if wrap == Wrap::ClampToEdge {
                    assert!((v.x - edge).abs() < 1e-6, "{p}: {v}");
                }
            }
        }
    }

    #[test]
    fn trilinear_is_linear_on_a_ramp() {
        let t = ramp(8);
        let s = Sampler::new(Filter::BILINEAR, Wrap::ClampToEdge);
        let v = sample_3d(&t, &s, &Footprint3::point(Vec3::new(0.5, 0.5, 0.5)));
        assert!((v.x - 0.5).abs() < 1e-6, "{v}");
    }

    #[test]
    fn mip_chain_of_a_cube_keeps_the_mean() {
        let t = ramp(8);
        assert_eq!(t.level_count(), 4);
        let v = t.voxel(3, 0, 0, 0);
        assert!((v.x - 0.5).abs() < 1e-6, "{v}");
    }

    #[test]
    fn nearest_reads_the_containing_voxel() {
        let t = ramp(4);
        let s = Sampler::new(Filter::NEAREST, Wrap::ClampToEdge);
        let v = sample_3d(&t, &s, &Footprint3::point(Vec3::new(0.3, 0.9, 0.1)));
        assert!((v.x - 1.0 / 3.0).abs() < 1e-6);
    }
}
