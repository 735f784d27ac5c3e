//! Filters: how a footprint on a texture becomes one linear, premultiplied RGBA value.
//!
//! Every filter is generic over the texel [`Codec`], and [`sample`] picks the codec once per
//! call (or once per batch in [`sample_batch`]), so the per-texel loops are compiled per format
//! with no format branch inside — the split of static and dynamic sampler state that llvmpipe
//! makes with generated code.

pub(crate) mod anisotropic;
pub(crate) mod ewa;
mod ewa_lanes;
mod ewa_probes;
mod fixed16;
mod quads;
pub(crate) mod summed_area;

pub use quads::{
    sample_quads_lanes, sample_quads_lanes_shared, QuadCoords, SharedQuads, StagedQuads,
    QUADS_STAGED,
};

use glam::{Vec2, Vec4};

use super::format::{with_texture_codec, Codec};
use super::storage::LevelRef;
use super::{
    Filter, Footprint, FootprintLanes, MagFilter, MinFilter, MipChoice, Sampler, TexelFilter,
    Texture2D, Wrap, BORDER,
};

/// Reads `texture` through `sampler` over `footprint`: linear, premultiplied RGBA.
///
/// ```
/// use texmap::texture::{sample, ColorSpace, Footprint, Sampler, Texture2D};
/// use glam::{Vec2, Vec4};
/// let white = Texture2D::from_rgba8(2, 2, ColorSpace::Srgb, &[255; 16]).unwrap();
/// let c = sample(&white, &Sampler::default(), &Footprint::point(Vec2::new(0.3, 0.7)));
/// assert!((c - Vec4::ONE).abs().max_element() < 1e-6);
/// ```
#[must_use]
pub fn sample(texture: &Texture2D, sampler: &Sampler, footprint: &Footprint) -> Vec4 {
    with_texture_codec!(texture, C => sample_with::<C>(texture, sampler, footprint))
}

/// [`sample`] over many footprints: the format and filter are dispatched once.
///
/// # Panics
/// If `out` is shorter than `footprints`.
pub fn sample_batch(
    texture: &Texture2D,
    sampler: &Sampler,
    footprints: &[Footprint],
    out: &mut [Vec4],
) {
    assert!(
        out.len() >= footprints.len(),
        "output shorter than the footprints"
    );
    with_texture_codec!(texture, C => {
        for (fp, o) in footprints.iter().zip(out.iter_mut()) {
            *o = sample_with::<C>(texture, sampler, fp);
        }
    })
}

/// [`sample`] of four footprints, each with its own derivatives (one pixel per lane): the
/// same values as four calls (lane `j` is `sample` of `fp.footprint(j)`), with the format and
/// filter dispatched once and, for OpenGL filters, λ four at a time ([`LodRule::lod4`]) and the
/// float filters' reads. Lanes whose bit in `mask` is clear are skipped (left zero).
///
/// [`LodRule::lod4`]: super::LodRule::lod4
#[must_use]
pub fn sample_lanes(
    texture: &Texture2D,
    sampler: &Sampler,
    fp: &FootprintLanes,
    mask: u8,
) -> [Vec4; 4] {
    let Filter::Gl { mag, min } = sampler.filter else {
        return with_texture_codec!(texture, C => std::array::from_fn(|j| {
            if mask & (1 << j) == 0 {
                return Vec4::ZERO;
            }
            sample_with::<C>(texture, sampler, &fp.footprint(j))
        }));
    };
    // λ as `gl` computes it (texel derivatives of level 0), four lanes at once.
    let (w, h) = (texture.width() as f32, texture.height() as f32);
    let lod = sampler
        .lod_rule
        .lod4(fp.dudx * w, fp.dvdx * h, fp.dudy * w, fp.dvdy * h);
    let levels = texture.levels().len();
    let lod = lod.to_array().map(|l| sampler.adjust_lod(l));
    // Every lane read magnified with a bilinear filter (a background's common case): one
    // level, the texel coordinates four at a time.
    let magnified = (0..4).all(|j| mask & (1 << j) == 0 || !(lod[j] > 0.0));
    with_texture_codec!(texture, C => {
        if magnified && mag == MagFilter::Linear {
            bilinear_lanes::<C>(&texture.level(0), sampler, fp.u, fp.v, mask)
        } else {
            let mut out = [Vec4::ZERO; 4];
            for (j, o) in out.iter_mut().enumerate() {
                if mask & (1 << j) != 0 {
                    let choice = MipChoice::gl(lod[j], levels, mag, min);
                    *o = read_choice::<C>(texture, sampler, Vec2::new(fp.u[j], fp.v[j]), choice);
                }
            }
            out
        }
    })
}

/// [`bilinear`] at four points of one level (one pixel per lane, any wraps): the texel
/// coordinates and weights four at a time by the same operations, so the same values; a
/// lane whose 2×2 texels are not all inside the level takes [`bilinear`] itself.
#[inline(always)]
fn bilinear_lanes<C: Codec>(lv: &LevelRef, s: &Sampler, u: Vec4, v: Vec4, mask: u8) -> [Vec4; 4] {
    // `prewrap`, then `bilinear`'s coordinates.
    let fract = |t: Vec4| t - t.floor();
    let pu = if s.wrap_u == Wrap::Repeat {
        fract(u)
    } else {
        u
    };
    let pv = if s.wrap_v == Wrap::Repeat {
        fract(v)
    } else {
        v
    };
    let px = pu * lv.w as f32 - 0.5;
    let py = pv * lv.h as f32 - 0.5;
    let (fx, fy) = (px.floor(), py.floor());
    let (ax, ay) = ((px - fx).to_array(), (py - fy).to_array());
    // Integral floats: truncation is `floor_index` wherever the result is in range (out of
    // range or NaN gives i32::MIN, which is not inside, and `bilinear` decides).
    let (x0, y0) = (truncate4(fx), truncate4(fy));
    let mut out = [Vec4::ZERO; 4];
    for (j, o) in out.iter_mut().enumerate() {
        if mask & (1 << j) == 0 {
            continue;
        }
        let (x, y) = (x0[j], y0[j]);
        *o = if x >= 0 && y >= 0 && x < lv.w - 1 && y < lv.h - 1 {
            let (top, bottom) = lv.quad::<C>(x, y);
            top.0
                .lerp(top.1, ax[j])
                .lerp(bottom.0.lerp(bottom.1, ax[j]), ay[j])
        } else {
            bilinear::<C>(lv, s, Vec2::new(u[j], v[j]))
        };
    }
    out
}

/// [`sample`] for the four pixels of a 2×2 quad, which share their derivatives (as the
/// rasterizer computes them, once per quad): the format is dispatched and, for OpenGL filters,
/// the level of detail and mip levels chosen once for the quad, as GPUs do. Pixels whose bit in
/// `mask` is clear are skipped (left zero).
#[must_use]
pub fn sample_quad(
    texture: &Texture2D,
    sampler: &Sampler,
    uvs: &[Vec2; 4],
    duv_dx: Vec2,
    duv_dy: Vec2,
    mask: u8,
) -> [Vec4; 4] {
    let u = Vec4::from_array(uvs.map(|uv| uv.x));
    let v = Vec4::from_array(uvs.map(|uv| uv.y));
    sample_quad_lanes(texture, sampler, (u, v), duv_dx, duv_dy, mask)
}

/// [`sample_quad`] with the four pixels' coordinates in lanes: `u` and `v` hold pixel `j`'s
/// in lane `j`.
#[must_use]
pub fn sample_quad_lanes(
    texture: &Texture2D,
    sampler: &Sampler,
    uv: (Vec4, Vec4),
    duv_dx: Vec2,
    duv_dy: Vec2,
    mask: u8,
) -> [Vec4; 4] {
    let Filter::Gl { mag, min } = sampler.filter else {
        if let Filter::Anisotropic { max_aniso, lod } = sampler.filter {
            // The default storage's taps in lanes, in fixed point.
            let aniso = anisotropic::Aniso { max_aniso, lod };
            let quad = anisotropic::sample_quad(texture, sampler, uv, duv_dx, duv_dy, mask, aniso);
            if let Some(quad) = quad {
                return quad;
            }
        }
        if let Filter::Ewa { max_eccentricity } = sampler.filter {
            // The quad's plan once; its probes in lanes, in fixed point.
            let quad = ewa_probes::sample_quad(
                texture,
                sampler,
                uv,
                duv_dx,
                duv_dy,
                mask,
                max_eccentricity,
            );
            if let Some(quad) = quad {
                return quad;
            }
        }
        if let Filter::EwaExact { max_eccentricity } = sampler.filter {
            // The quad's ellipse once, its texels read once for the four pixels.
            return with_texture_codec!(texture, C => ewa_lanes::sample_quad::<C>(
                texture, sampler, uv, duv_dx, duv_dy, mask, max_eccentricity
            ));
        }
        return with_texture_codec!(texture, C => {
            std::array::from_fn(|j| {
                if mask & (1 << j) == 0 {
                    return Vec4::ZERO;
                }
                let fp = Footprint::new(Vec2::new(uv.0[j], uv.1[j]), duv_dx, duv_dy);
                sample_with::<C>(texture, sampler, &fp)
            })
        });
    };
    // OpenGL filtering: λ depends on the derivatives only, so it is the same for the four
    // pixels — one level choice per quad, as GPUs make it.
    let size = Vec2::new(texture.width() as f32, texture.height() as f32);
    let lod = sampler.adjust_lod(sampler.lod_rule.lod(duv_dx * size, duv_dy * size));
    let choice = MipChoice::gl(lod, texture.levels().len(), mag, min);
    gl_read(texture, sampler, uv, choice, mask)
}

/// The level choice [`sample_quad_lanes`] makes for a quad with derivatives `duv_dx`,
/// `duv_dy` under an OpenGL filter (`None` for the others): made once, it serves reads of the
/// same footprint at other coordinates ([`sample_quad_lanes_at`]).
#[must_use]
pub fn quad_mip_choice(
    texture: &Texture2D,
    sampler: &Sampler,
    duv_dx: Vec2,
    duv_dy: Vec2,
) -> Option<MipChoice> {
    let Filter::Gl { mag, min } = sampler.filter else {
        return None;
    };
    let size = Vec2::new(texture.width() as f32, texture.height() as f32);
    let lod = sampler.adjust_lod(sampler.lod_rule.lod(duv_dx * size, duv_dy * size));
    Some(MipChoice::gl(lod, texture.levels().len(), mag, min))
}

/// [`sample_quad_lanes`] on a level choice made before ([`quad_mip_choice`]): what a search
/// reading one footprint at many coordinates (parallax occlusion mapping) calls per step.
#[inline]
#[must_use]
pub fn sample_quad_lanes_at(
    texture: &Texture2D,
    sampler: &Sampler,
    uv: (Vec4, Vec4),
    choice: MipChoice,
    mask: u8,
) -> [Vec4; 4] {
    gl_read(texture, sampler, uv, choice, mask)
}

/// A quad's OpenGL reads on the chosen levels: the default storage's fast path
/// ([`fixed16::read_quad`]) when it serves, else the float filters for the format.
#[inline]
fn gl_read(
    texture: &Texture2D,
    sampler: &Sampler,
    uv: (Vec4, Vec4),
    choice: MipChoice,
    mask: u8,
) -> [Vec4; 4] {
    fixed16::read_quad(texture, sampler, choice, uv.0, uv.1, mask).unwrap_or_else(
        || with_texture_codec!(texture, C => gl_quad::<C>(texture, sampler, uv, choice, mask)),
    )
}

/// OpenGL filtering of a quad's four pixels on the levels `choice` names.
fn gl_quad<C: Codec>(
    tex: &Texture2D,
    s: &Sampler,
    (u, v): (Vec4, Vec4),
    choice: MipChoice,
    mask: u8,
) -> [Vec4; 4] {
    let read = |level: usize| {
        let lv = tex.level(level);
        match choice.texels {
            TexelFilter::Linear => bilinear_quad::<C>(&lv, s, u, v, mask),
            TexelFilter::Nearest => std::array::from_fn(|j| {
                if mask & (1 << j) != 0 {
                    nearest::<C>(&lv, s, Vec2::new(u[j], v[j]))
                } else {
                    Vec4::ZERO
                }
            }),
        }
    };
    let a = read(choice.level);
    match choice.blend {
        Some(b) => {
            let (b, f) = (read(b.level), b.weight);
            std::array::from_fn(|j| a[j].lerp(b[j], f))
        }
        None => a,
    }
}

/// [`bilinear`] for the four pixels of a quad on one level, the coordinates in lanes. With
/// repeat on both axes (the common case) the texel coordinates and weights are computed four
/// at a time, then each pixel reads its 2×2 texels (wrapped by a select at the edges); other
/// wraps take [`bilinear`] per pixel.
#[inline(always)]
fn bilinear_quad<C: Codec>(lv: &LevelRef, s: &Sampler, u: Vec4, v: Vec4, mask: u8) -> [Vec4; 4] {
    let mut out = [Vec4::ZERO; 4];
    if s.wrap_u != Wrap::Repeat || s.wrap_v != Wrap::Repeat {
        for (j, o) in out.iter_mut().enumerate() {
            if mask & (1 << j) != 0 {
                *o = bilinear::<C>(lv, s, Vec2::new(u[j], v[j]));
            }
        }
        return out;
    }
    // Brought into [0, 1] (1 only by rounding), so x0 ∈ [−1, w − 1] and wrapping is a select.
    let px = (u - u.floor()) * lv.w as f32 - 0.5;
    let py = (v - v.floor()) * lv.h as f32 - 0.5;
    let (fx, fy) = (px.floor(), py.floor());
    let (ax, ay) = ((px - fx).to_array(), (py - fy).to_array());
    let (x0, y0) = (truncate4(fx), truncate4(fy));
    for (j, o) in out.iter_mut().enumerate() {
        if mask & (1 << j) == 0 {
            continue;
        }
        let (x, y) = (x0[j], y0[j]);
        let ((t00, t10), (t01, t11)) = if x >= 0 && y >= 0 && x < lv.w - 1 && y < lv.h - 1 {
            lv.quad::<C>(x, y)
        } else {
            let (x, y) = (x.clamp(-1, lv.w - 1), y.clamp(-1, lv.h - 1));
            let ((xa, xb), (ya, yb)) = (repeat_pair(x, lv.w), repeat_pair(y, lv.h));
            let t = |x, y| lv.texel::<C>(x, y);
            ((t(xa, ya), t(xb, ya)), (t(xa, yb), t(xb, yb)))
        };
        *o = t00.lerp(t10, ax[j]).lerp(t01.lerp(t11, ax[j]), ay[j]);
    }
    out
}

/// Four floats to `i32`, truncating; NaN and out-of-range lanes give `i32::MIN` on x86-64
/// (callers range-check the result).
#[inline(always)]
pub(crate) fn truncate4(v: Vec4) -> [i32; 4] {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{__m128i, _mm_cvttps_epi32};
        // SAFETY: SSE2 is part of x86_64; `__m128i` and `[i32; 4]` have the same size and
        // every bit pattern is valid for both.
        unsafe { std::mem::transmute::<__m128i, [i32; 4]>(_mm_cvttps_epi32(v.into())) }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        v.to_array().map(|x| x as i32)
    }
}

/// Four `i32`s as floats (`i as f32` lane by lane, the same values) in one conversion.
#[inline(always)]
pub(crate) fn float4(i: [i32; 4]) -> Vec4 {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{__m128i, _mm_cvtepi32_ps};
        // SAFETY: SSE2 is part of x86_64; `[i32; 4]` and `__m128i` have the same size and
        // every bit pattern is valid for both.
        Vec4::from(unsafe { _mm_cvtepi32_ps(std::mem::transmute::<[i32; 4], __m128i>(i)) })
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        Vec4::from_array(i.map(|i| i as f32))
    }
}

// Inlined into each entry point (as the compiler chose before the OpenGL read became
// `read_choice`): as a call it cost anisotropic filtering 0.6% more instructions.
#[inline(always)]
fn sample_with<C: Codec>(tex: &Texture2D, s: &Sampler, fp: &Footprint) -> Vec4 {
    match s.filter {
        Filter::Gl { mag, min } => gl::<C>(tex, s, fp, mag, min),
        Filter::Anisotropic { max_aniso, lod } => {
            anisotropic::sample::<C>(tex, s, fp, anisotropic::Aniso { max_aniso, lod })
        }
        Filter::Ewa { max_eccentricity } => ewa_probes::sample::<C>(tex, s, fp, max_eccentricity),
        Filter::EwaExact { max_eccentricity } => ewa::sample::<C>(tex, s, fp, max_eccentricity),
        Filter::SummedArea => summed_area::sample::<C>(tex, s, fp),
    }
}

/// The footprint's derivatives in texels of level 0.
#[inline(always)]
pub(crate) fn texel_derivatives(tex: &Texture2D, fp: &Footprint) -> (Vec2, Vec2) {
    let size = Vec2::new(tex.width() as f32, tex.height() as f32);
    (fp.duv_dx * size, fp.duv_dy * size)
}

/// A float to a texel index: `as` saturates, and NaN reads index 0.
#[inline(always)]
pub(crate) fn floor_index(v: f32) -> i32 {
    v.floor() as i32
}

/// Texel `(x, y)` of `lv`, wrapped by the sampler; the border colour where it says so.
#[inline(always)]
pub(crate) fn fetch<C: Codec>(lv: &LevelRef, s: &Sampler, x: i32, y: i32) -> Vec4 {
    let (xi, yi) = (s.wrap_u.index(x, lv.w), s.wrap_v.index(y, lv.h));
    if xi == BORDER || yi == BORDER {
        s.border
    } else {
        lv.texel::<C>(xi, yi)
    }
}

/// `uv` with repeating axes brought into [0, 1), so texel indices stay near the image and the
/// wrap needs no division (and large coordinates keep their fractional precision).
#[inline(always)]
pub(crate) fn prewrap(s: &Sampler, uv: Vec2) -> Vec2 {
    let fract = |v: f32| v - v.floor();
    Vec2::new(
        if s.wrap_u == Wrap::Repeat {
            fract(uv.x)
        } else {
            uv.x
        },
        if s.wrap_v == Wrap::Repeat {
            fract(uv.y)
        } else {
            uv.y
        },
    )
}

/// The nearest texel to `uv` on `lv`.
#[inline(always)]
pub(crate) fn nearest<C: Codec>(lv: &LevelRef, s: &Sampler, uv: Vec2) -> Vec4 {
    let uv = prewrap(s, uv);
    let x = floor_index(uv.x * lv.w as f32);
    let y = floor_index(uv.y * lv.h as f32);
    fetch::<C>(lv, s, x, y)
}

/// Bilinear interpolation of the four texels around `uv` on `lv`.
#[inline(always)]
pub(crate) fn bilinear<C: Codec>(lv: &LevelRef, s: &Sampler, uv: Vec2) -> Vec4 {
    let uv = prewrap(s, uv);
    let px = uv.x * lv.w as f32 - 0.5;
    let py = uv.y * lv.h as f32 - 0.5;
    let (fx, fy) = (px.floor(), py.floor());
    let (ax, ay) = (px - fx, py - fy);
    let (x0, y0) = (floor_index(fx), floor_index(fy));
    // Interior fast path: all four texels inside the level, no wrapping or border to decide.
    if x0 >= 0 && y0 >= 0 && x0 < lv.w - 1 && y0 < lv.h - 1 {
        let (top, bottom) = lv.quad::<C>(x0, y0);
        return top.0.lerp(top.1, ax).lerp(bottom.0.lerp(bottom.1, ax), ay);
    }
    // Repeat on both axes (the common case off the interior): prewrap put x0 in [−1, w − 1],
    // so wrapping is a select, not a division.
    if s.wrap_u == Wrap::Repeat
        && s.wrap_v == Wrap::Repeat
        && x0 >= -1
        && y0 >= -1
        && x0 < lv.w
        && y0 < lv.h
    {
        let ((xa, xb), (ya, yb)) = (repeat_pair(x0, lv.w), repeat_pair(y0, lv.h));
        let t = |x, y| lv.texel::<C>(x, y);
        return t(xa, ya)
            .lerp(t(xb, ya), ax)
            .lerp(t(xa, yb).lerp(t(xb, yb), ax), ay);
    }
    let (xa, xb) = (
        s.wrap_u.index(x0, lv.w),
        s.wrap_u.index(x0.wrapping_add(1), lv.w),
    );
    let (ya, yb) = (
        s.wrap_v.index(y0, lv.h),
        s.wrap_v.index(y0.wrapping_add(1), lv.h),
    );
    let t = |x: i32, y: i32| {
        if x == BORDER || y == BORDER {
            s.border
        } else {
            lv.texel::<C>(x, y)
        }
    };
    let top = t(xa, ya).lerp(t(xb, ya), ax);
    let bottom = t(xa, yb).lerp(t(xb, yb), ax);
    top.lerp(bottom, ay)
}

/// The two texel indices a bilinear tap at `i ∈ [−1, n − 1]` reads on a repeating axis of
/// `n` texels: `i` and `i + 1`, wrapped by a select (no division).
#[inline(always)]
fn repeat_pair(i: i32, n: i32) -> (i32, i32) {
    (
        if i < 0 { n - 1 } else { i },
        if i + 1 >= n { 0 } else { i + 1 },
    )
}

/// Bilinear on the two levels around `lod`, blended (the minification half of trilinear).
#[inline(always)]
pub(crate) fn trilinear_at<C: Codec>(tex: &Texture2D, s: &Sampler, uv: Vec2, lod: f32) -> Vec4 {
    read_choice::<C>(tex, s, uv, MipChoice::trilinear(lod, tex.levels().len()))
}

/// The levels `choice` names, read at `uv` and blended. A function, not a closure passed to
/// [`MipChoice::read`]: as a closure the compiler left each level's read out of line, which
/// cost anisotropic filtering measurably (DESIGN.md's decision log).
#[inline(always)]
fn read_choice<C: Codec>(tex: &Texture2D, s: &Sampler, uv: Vec2, choice: MipChoice) -> Vec4 {
    let a = read_level::<C>(tex, s, uv, choice.level, choice.texels);
    match choice.blend {
        Some(b) => a.lerp(
            read_level::<C>(tex, s, uv, b.level, choice.texels),
            b.weight,
        ),
        None => a,
    }
}

/// Level `level` read at `uv` with `texels`.
#[inline(always)]
fn read_level<C: Codec>(
    tex: &Texture2D,
    s: &Sampler,
    uv: Vec2,
    level: usize,
    texels: TexelFilter,
) -> Vec4 {
    let lv = tex.level(level);
    match texels {
        TexelFilter::Nearest => nearest::<C>(&lv, s, uv),
        TexelFilter::Linear => bilinear::<C>(&lv, s, uv),
    }
}

/// OpenGL's filtering: λ from the footprint, the levels from [`MipChoice::gl`].
fn gl<C: Codec>(
    tex: &Texture2D,
    s: &Sampler,
    fp: &Footprint,
    mag: MagFilter,
    min: MinFilter,
) -> Vec4 {
    let (dx, dy) = texel_derivatives(tex, fp);
    let lod = s.adjust_lod(s.lod_rule.lod(dx, dy));
    read_choice::<C>(
        tex,
        s,
        fp.uv,
        MipChoice::gl(lod, tex.levels().len(), mag, min),
    )
}

/// The ellipse a footprint's derivatives describe (texel units of level 0): the unit major
/// direction and the two semi-axis lengths, from the eigen-decomposition of J·Jᵀ.
#[inline]
pub(crate) fn ellipse_axes(dx: Vec2, dy: Vec2) -> (Vec2, f32, f32) {
    let a = dx.x * dx.x + dy.x * dy.x;
    let b = dx.x * dx.y + dy.x * dy.y;
    let c = dx.y * dx.y + dy.y * dy.y;
    let mean = 0.5 * (a + c);
    let d = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    let (l1, l2) = (mean + d, (mean - d).max(0.0));
    // Eigenvector of l1: pick the better-conditioned of the two forms.
    let v = if (a - c).abs() + b.abs() < 1e-20 {
        Vec2::X
    } else if a >= c {
        Vec2::new(l1 - c, b)
    } else {
        Vec2::new(b, l1 - a)
    };
    (v.normalize_or(Vec2::X), l1.sqrt(), l2.sqrt())
}

/// [`ellipse_axes`] of up to four quads' footprints at once, one per lane (lane `k` for
/// `coords[k]`'s derivatives scaled to texels by `size`, as [`texel_derivatives`] scales
/// them; lanes past `coords` zero derivatives): `[dir_x, dir_y, major, minor]`, the same
/// operations lane by lane, so the same values (the callers' plans are tested equal).
#[inline(always)]
pub(crate) fn ellipse_axes4(size: Vec2, coords: &[QuadCoords]) -> [Vec4; 4] {
    let lane = |f: &dyn Fn(&QuadCoords) -> f32| {
        Vec4::from_array(std::array::from_fn(|k| coords.get(k).map_or(0.0, f)))
    };
    let (dxx, dxy) = (
        lane(&|c| c.duv_dx.x) * size.x,
        lane(&|c| c.duv_dx.y) * size.y,
    );
    let (dyx, dyy) = (
        lane(&|c| c.duv_dy.x) * size.x,
        lane(&|c| c.duv_dy.y) * size.y,
    );
    let a = dxx * dxx + dyx * dyx;
    let b = dxx * dxy + dyx * dyy;
    let c = dxy * dxy + dyy * dyy;
    let mean = 0.5 * (a + c);
    let d = sqrt4(0.25 * (a - c) * (a - c) + b * b);
    let (l1, l2) = (mean + d, (mean - d).max(Vec4::ZERO));
    // The eigenvector of l1, the better-conditioned form (x = 1 where there is none).
    let round = ((a - c).abs() + b.abs()).cmplt(Vec4::splat(1e-20));
    let wide = a.cmpge(c);
    let vx = Vec4::select(round, Vec4::ONE, Vec4::select(wide, l1 - c, b));
    let vy = Vec4::select(round, Vec4::ZERO, Vec4::select(wide, b, l1 - a));
    // `normalize_or(Vec2::X)`: times the reciprocal length where it is finite and positive.
    let rcp = Vec4::ONE / sqrt4(vx * vx + vy * vy);
    let normal = rcp.abs().cmplt(Vec4::INFINITY) & rcp.cmpgt(Vec4::ZERO);
    let dir_x = Vec4::select(normal, vx * rcp, Vec4::ONE);
    let dir_y = Vec4::select(normal, vy * rcp, Vec4::ZERO);
    [dir_x, dir_y, sqrt4(l1), sqrt4(l2)]
}

/// The square root of each lane (correctly rounded, as `f32::sqrt`).
#[inline(always)]
fn sqrt4(v: Vec4) -> Vec4 {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: SSE is part of x86_64.
    unsafe {
        Vec4::from(std::arch::x86_64::_mm_sqrt_ps(v.into()))
    }
    #[cfg(not(target_arch = "x86_64"))]
    Vec4::from_array(v.to_array().map(f32::sqrt))
}

#[cfg(test)]
mod plan_checks;
#[cfg(test)]
mod tests;
