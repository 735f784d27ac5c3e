//! Filter invariants on tiny textures, with exact or stated tolerances.

use glam::{Vec2, Vec4};
use proptest::prelude::*;

use crate::texture::{
    sample, ColorSpace, Filter, Footprint, LodRule, MagFilter, MinFilter, Sampler, Texture2D,
    TextureOptions, Wrap,
};

const FILTERS: [&str; 10] = [
    "nearest",
    "bilinear",
    "trilinear",
    "aniso2",
    "aniso4",
    "aniso16",
    "ewa",
    "sat",
    "aniso8",
    "ewa-exact",
];
const WRAPS: [Wrap; 5] = [
    Wrap::Repeat,
    Wrap::MirroredRepeat,
    Wrap::ClampToEdge,
    Wrap::ClampToBorder,
    Wrap::MirrorClampToEdge,
];

fn all_gl_filters() -> Vec<Filter> {
    let mut v = Vec::new();
    for mag in [MagFilter::Nearest, MagFilter::Linear] {
        for min in [
            MinFilter::Nearest,
            MinFilter::Linear,
            MinFilter::NearestMipmapNearest,
            MinFilter::LinearMipmapNearest,
            MinFilter::NearestMipmapLinear,
            MinFilter::LinearMipmapLinear,
        ] {
            v.push(Filter::Gl { mag, min });
        }
    }
    v
}

fn every_filter() -> Vec<Filter> {
    let mut v = all_gl_filters();
    v.extend(FILTERS.iter().map(|f| Filter::parse(f).unwrap()));
    v
}

/// A 13×9 RGBA8 texture with values spread over [0, 255].
pub(super) fn noisy(w: u32, h: u32) -> Texture2D {
    let rgba: Vec<u8> = (0..w * h * 4)
        .map(|i| ((i * 97 + 13) % 256) as u8)
        .collect();
    Texture2D::from_rgba8(w, h, ColorSpace::Srgb, &rgba).unwrap()
}

/// A `w`×`h` texture held as 8-bit RGBA ([`crate::texture::Storage::Rgba8`]), values spread
/// over [0, 255]; alpha 255 everywhere when `opaque`.
fn noisy8(w: u32, h: u32, color_space: ColorSpace, opaque: bool) -> Texture2D {
    let rgba: Vec<u8> = (0..w * h * 4)
        .map(|i| {
            if opaque && i % 4 == 3 {
                255
            } else {
                ((i * 97 + 13) % 256) as u8
            }
        })
        .collect();
    let options = TextureOptions::default().with_storage(crate::texture::Storage::Rgba8);
    let tex = Texture2D::from_texels(
        w,
        h,
        crate::texture::Format::Rgba8,
        color_space,
        &rgba,
        options,
    )
    .unwrap();
    assert_eq!(tex.storage(), crate::texture::Storage::Rgba8);
    tex
}

fn close(a: Vec4, b: Vec4, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

#[test]
fn bilinear_at_texel_centres_returns_the_texels() {
    let tex = noisy(13, 9);
    let s = Sampler::new(Filter::BILINEAR, Wrap::Repeat);
    for y in 0..9 {
        for x in 0..13 {
            let uv = Vec2::new((x as f32 + 0.5) / 13.0, (y as f32 + 0.5) / 9.0);
            let got = sample(&tex, &s, &Footprint::point(uv));
            assert!(close(got, tex.texel(0, x, y), 1e-6), "({x},{y})");
        }
    }
}

#[test]
fn nearest_reads_the_texel_under_the_point() {
    let tex = noisy(4, 4);
    let s = Sampler::new(Filter::NEAREST, Wrap::Repeat);
    // u = 1.3 wraps to 0.3 → texel 1; v = −0.1 wraps to 0.9 → texel 3.
    let got = sample(&tex, &s, &Footprint::point(Vec2::new(1.3, -0.1)));
    assert_eq!(got, tex.texel(0, 1, 3));
}

#[test]
fn border_colour_outside_with_clamp_to_border() {
    let tex = noisy(4, 4);
    let mut s = Sampler::new(Filter::NEAREST, Wrap::ClampToBorder);
    s.border = Vec4::new(0.1, 0.2, 0.3, 1.0);
    assert_eq!(
        sample(&tex, &s, &Footprint::point(Vec2::new(-0.2, 0.5))),
        s.border
    );
    // Halfway between the edge texel centre and the border: the average.
    s.filter = Filter::BILINEAR;
    let got = sample(&tex, &s, &Footprint::point(Vec2::new(0.0, 0.125)));
    assert!(close(got, (tex.texel(0, 0, 0) + s.border) * 0.5, 1e-6));
}

#[test]
fn magnification_switches_at_lod_zero() {
    // Nearest mag, linear min: just below λ = 0 reads a texel, just above interpolates.
    let tex = noisy(8, 8);
    let s = Sampler::new(
        Filter::Gl {
            mag: MagFilter::Nearest,
            min: MinFilter::Linear,
        },
        Wrap::Repeat,
    );
    let uv = Vec2::new(0.5, 0.5);
    let d = |texels: f32| Footprint::new(uv, Vec2::new(texels / 8.0, 0.0), Vec2::ZERO);
    assert_eq!(sample(&tex, &s, &d(0.99)), tex.texel(0, 4, 4));
    let interp = sample(&tex, &s, &d(1.01));
    let s_lin = Sampler::new(Filter::BILINEAR, Wrap::Repeat);
    assert_eq!(interp, sample(&tex, &s_lin, &Footprint::point(uv)));
}

#[test]
fn nearest_mipmap_picks_the_rounded_level() {
    // Levels hold constants 0, 1, 2, 3 in red (built by hand via from_fn per level is not
    // possible, so test the level rule through a 1-texel footprint ladder on a checkerboard).
    let tex = Texture2D::from_fn(16, 16, TextureOptions::default(), |x, y| {
        Vec4::splat(((x + y) % 2) as f32)
    })
    .unwrap();
    let s = Sampler::new(
        Filter::Gl {
            mag: MagFilter::Linear,
            min: MinFilter::NearestMipmapNearest,
        },
        Wrap::Repeat,
    );
    // λ = 0.4 → level 0 (a texel of the checkerboard: 0 or 1); λ = 0.6 → level 1 (0.5).
    let uv = Vec2::new(0.5 / 16.0, 0.5 / 16.0);
    let fp = |lod: f32| Footprint::new(uv, Vec2::new(lod.exp2() / 16.0, 0.0), Vec2::ZERO);
    assert_eq!(sample(&tex, &s, &fp(0.4)).x, 0.0);
    assert!((sample(&tex, &s, &fp(0.6)).x - 0.5).abs() < 1e-6);
}

#[test]
fn lod_rules_bias_and_clamps() {
    let dx = Vec2::new(3.0, 4.0);
    let dy = Vec2::new(0.0, 12.0);
    // λ goes through `fast_log2` (within 3·10⁻⁵ of log2; halved here).
    assert!((LodRule::GlMax.lod(dx, dy) - 12f32.log2()).abs() < 5e-5);
    let rss = 0.5 * (9.0f32 + 16.0 + 144.0).log2();
    assert!((LodRule::RootSumSquares.lod(dx, dy) - rss).abs() < 5e-5);
    let s = Sampler::default()
        .with_lod_bias(1.0)
        .with_lod_clamp(0.5, 2.0);
    assert_eq!(s.adjust_lod(-3.0), 0.5);
    assert_eq!(s.adjust_lod(0.7), 1.7);
    assert_eq!(s.adjust_lod(9.0), 2.0);
}

#[test]
fn isotropic_footprint_makes_anisotropic_equal_trilinear() {
    let tex = noisy(32, 32);
    let fp = Footprint::new(
        Vec2::new(0.37, 0.61),
        Vec2::new(3.0 / 32.0, 0.0),
        Vec2::new(0.0, 3.0 / 32.0),
    );
    let tri = sample(&tex, &Sampler::new(Filter::TRILINEAR, Wrap::Repeat), &fp);
    let an = sample(&tex, &Sampler::new(Filter::aniso(16), Wrap::Repeat), &fp);
    assert!(close(tri, an, 1e-6), "{tri} vs {an}");
}

#[test]
fn ewa_with_a_tiny_round_footprint_is_close_to_bilinear() {
    // A smooth texture: the difference is the Gaussian's extra blur, small on smooth data.
    let tex = Texture2D::from_fn(64, 64, TextureOptions::default(), |x, y| {
        let (u, v) = (x as f32 / 64.0, y as f32 / 64.0);
        Vec4::new(
            0.5 + 0.5 * (std::f32::consts::TAU * u).sin(),
            0.5 + 0.5 * (std::f32::consts::TAU * v).cos(),
            u * v,
            1.0,
        )
    })
    .unwrap();
    let ewa = Sampler::new(
        Filter::Ewa {
            max_eccentricity: 16.0,
        },
        Wrap::Repeat,
    );
    let bil = Sampler::new(Filter::BILINEAR, Wrap::Repeat);
    for i in 0..50 {
        let uv = Vec2::new((i as f32 * 0.137) % 1.0, (i as f32 * 0.291) % 1.0);
        let d = 1.05 / 64.0;
        let a = sample(
            &tex,
            &ewa,
            &Footprint::new(uv, Vec2::new(d, 0.0), Vec2::new(0.0, d)),
        );
        let b = sample(&tex, &bil, &Footprint::point(uv));
        assert!(close(a, b, 0.02), "{uv}: {a} vs {b}");
    }
}

/// Brute-force box average of the piecewise-constant (nearest) texture over a rectangle.
fn brute_box(tex: &Texture2D, s: &Sampler, lo: Vec2, hi: Vec2) -> Vec4 {
    let (w, h) = (tex.width() as i32, tex.height() as i32);
    let mut sum = Vec4::ZERO;
    for y in lo.y.floor() as i32..hi.y.ceil() as i32 {
        let cy = (hi.y.min(y as f32 + 1.0) - lo.y.max(y as f32)).max(0.0);
        for x in lo.x.floor() as i32..hi.x.ceil() as i32 {
            let cx = (hi.x.min(x as f32 + 1.0) - lo.x.max(x as f32)).max(0.0);
            let (xi, yi) = (s.wrap_u.index(x, w), s.wrap_v.index(y, h));
            let t = if xi < 0 || yi < 0 {
                s.border
            } else {
                tex.texel(0, xi as u32, yi as u32)
            };
            sum += t * cx * cy;
        }
    }
    sum / ((hi.x - lo.x) * (hi.y - lo.y))
}

#[test]
fn summed_area_matches_brute_force_under_every_wrap() {
    let tex = noisy(13, 9);
    for wrap in WRAPS {
        let mut s = Sampler::new(Filter::SummedArea, wrap);
        s.border = Vec4::new(0.25, 0.5, 0.75, 1.0);
        for i in 0..40 {
            let c = Vec2::new(-1.3 + i as f32 * 0.093, 2.1 - i as f32 * 0.071);
            let d = Vec2::new(1.0 + (i % 7) as f32 * 3.3, 1.0 + (i % 5) as f32 * 2.1);
            let fp = Footprint::new(c, Vec2::new(d.x / 13.0, 0.0), Vec2::new(0.0, d.y / 9.0));
            let got = sample(&tex, &s, &fp);
            let centre = c * Vec2::new(13.0, 9.0);
            let want = brute_box(&tex, &s, centre - d * 0.5, centre + d * 0.5);
            // 16-bit quantization of the table: 1/65535 per texel, averaged.
            assert!(close(got, want, 2e-4), "{wrap:?} #{i}: {got} vs {want}");
        }
    }
}

#[test]
fn summed_area_is_exact_on_a_large_texture() {
    // 3000×3000 of a constant: the running sums reach 9M texels × 65535 ≫ 2^32, yet the
    // wrapping arithmetic returns the constant for every box.
    let n = 3000u32;
    let rgba = vec![200u8; (n * n * 4) as usize];
    let tex = Texture2D::from_texels(
        n,
        n,
        crate::texture::Format::Rgba8,
        ColorSpace::Linear,
        &rgba,
        TextureOptions::default(),
    )
    .unwrap();
    let s = Sampler::new(Filter::SummedArea, Wrap::Repeat);
    let want = tex.texel(0, 0, 0);
    for (c, d) in [(0.9, 40.0), (0.5, 250.0), (0.1, 2900.0)] {
        let fp = Footprint::new(
            Vec2::splat(c),
            Vec2::new(d / n as f32, 0.0),
            Vec2::new(0.0, 3.0 / n as f32),
        );
        let got = sample(&tex, &s, &fp);
        // Exact sums; what remains is the 16-bit quantization of the texel (≤ 0.5/65535).
        assert!(close(got, want, 1e-5), "{got} vs {want}");
    }
}

#[test]
fn float_textures_keep_values_above_one() {
    let tex = Texture2D::from_fn(8, 8, TextureOptions::default(), |_, _| {
        Vec4::new(7.5, 0.25, 3.0, 1.0)
    })
    .unwrap();
    for f in every_filter() {
        let s = Sampler::new(f, Wrap::Repeat);
        let fp = Footprint::new(
            Vec2::new(0.3, 0.4),
            Vec2::new(0.9, 0.1),
            Vec2::new(0.05, 0.2),
        );
        let got = sample(&tex, &s, &fp);
        assert!(
            close(got, Vec4::new(7.5, 0.25, 3.0, 1.0), 2e-3 * 7.5),
            "{f:?}: {got}"
        );
    }
}

fn footprint_strategy() -> impl Strategy<Value = Footprint> {
    (
        -3.0f32..3.0,
        -3.0f32..3.0,
        -2.0f32..2.0,
        -2.0f32..2.0,
        -2.0f32..2.0,
        -2.0f32..2.0,
        -8.0f32..2.0,
    )
        .prop_map(|(u, v, a, b, c, d, scale)| {
            let k = scale.exp2();
            Footprint::new(Vec2::new(u, v), Vec2::new(a, b) * k, Vec2::new(c, d) * k)
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn quad_sampling_equals_per_pixel_sampling(fp in footprint_strategy(), f in 0usize..22, w in 0usize..5) {
        let tex = noisy(13, 9);
        let s = Sampler::new(every_filter()[f], WRAPS[w]);
        let uvs = [fp.uv, fp.uv + Vec2::new(0.01, 0.0), fp.uv + Vec2::new(0.0, 0.02), fp.uv + Vec2::new(0.03, 0.01)];
        let quad = crate::texture::sample_quad(&tex, &s, &uvs, fp.duv_dx, fp.duv_dy, 0b1011);
        for j in 0..4 {
            let want = if j == 2 { Vec4::ZERO } else { sample(&tex, &s, &Footprint::new(uvs[j], fp.duv_dx, fp.duv_dy)) };
            // Linear GL reads of the default storage take the fixed-point path (`fixed16`),
            // within its stated bound of the float filter; the others are the same code.
            prop_assert!(close(quad[j], want, 1.6e-4), "{:?} pixel {}: {} vs {}", s.filter, j, quad[j], want);
        }
    }

    #[test]
    fn quad_sampling_of_8bit_storage_equals_per_pixel_sampling(fp in footprint_strategy(), f in 0usize..22, w in 0usize..5, srgb in any::<bool>(), opaque in any::<bool>()) {
        // The 8-bit storage's fixed-point reads (texels widened to 16-bit linear) against the
        // float filters on the same texels: within the same bound as the default storage's.
        let cs = if srgb { ColorSpace::Srgb } else { ColorSpace::Linear };
        let tex = noisy8(13, 9, cs, opaque);
        let s = Sampler::new(every_filter()[f], WRAPS[w]);
        let uvs = [fp.uv, fp.uv + Vec2::new(0.01, 0.0), fp.uv + Vec2::new(0.0, 0.02), fp.uv + Vec2::new(0.03, 0.01)];
        let quad = crate::texture::sample_quad(&tex, &s, &uvs, fp.duv_dx, fp.duv_dy, 0b1011);
        for j in 0..4 {
            let want = if j == 2 { Vec4::ZERO } else { sample(&tex, &s, &Footprint::new(uvs[j], fp.duv_dx, fp.duv_dy)) };
            prop_assert!(close(quad[j], want, 1.6e-4), "{:?} pixel {}: {} vs {}", s.filter, j, quad[j], want);
        }
    }

    #[test]
    fn batched_quads_equal_quads_read_one_by_one(fps in proptest::collection::vec(footprint_strategy(), 1..40), f in 0usize..22, w in 0usize..5, storage in 0usize..4, lod in 0usize..3, big in any::<bool>()) {
        // The default storage, or 8-bit RGBA (sRGB or linear, opaque or not); batches longer
        // than one chunk of level choices too; the sampler's λ as it is, biased, or biased
        // and clamped. 13×9, or 160×120: a first level over the 64 KiB above which batches
        // ask for their texels ahead (`fixed16/prefetch.rs`), in either storage.
        let (tw, th) = if big { (160, 120) } else { (13, 9) };
        let tex = match storage {
            0 => noisy(tw, th),
            k => noisy8(tw, th, if k == 1 { ColorSpace::Srgb } else { ColorSpace::Linear }, k != 3),
        };
        let mut s = Sampler::new(every_filter()[f], WRAPS[w]);
        (s.lod_bias, s.min_lod, s.max_lod) = [
            (s.lod_bias, s.min_lod, s.max_lod),
            (0.7, s.min_lod, s.max_lod),
            (-0.4, 0.5, 2.25),
        ][lod];
        let coords: Vec<crate::texture::QuadCoords> = fps
            .iter()
            .map(|fp| crate::texture::QuadCoords {
                u: Vec4::new(fp.uv.x, fp.uv.x + 0.01, fp.uv.x, fp.uv.x + 0.02),
                v: Vec4::new(fp.uv.y, fp.uv.y, fp.uv.y + 0.03, fp.uv.y + 0.01),
                duv_dx: fp.duv_dx,
                duv_dy: fp.duv_dy,
            })
            .collect();
        let masks: Vec<u8> = (0..coords.len()).map(|i| [0b1111, 0b0110, 0b1001][i % 3]).collect();
        let mut out = vec![[Vec4::ZERO; 4]; coords.len()];
        crate::texture::sample_quads_lanes(&tex, &s, &coords, &masks, &mut out);
        for ((c, &m), got) in coords.iter().zip(&masks).zip(&out) {
            let want = crate::texture::sample_quad_lanes(&tex, &s, (c.u, c.v), c.duv_dx, c.duv_dy, m);
            prop_assert_eq!(got, &want, "{:?}", s.filter);
        }
        // In two stages (levels and far texels first, the reads later; at most a staged
        // batch): the same values.
        let n = coords.len().min(crate::texture::QUADS_STAGED);
        let staged = crate::texture::StagedQuads::begin(&tex, &s, &coords[..n], &masks[..n]);
        let mut two = vec![[Vec4::splat(-1.0); 4]; n];
        staged.end(&tex, &s, &coords[..n], &masks[..n], &mut two);
        prop_assert_eq!(&two[..], &out[..n], "{:?} staged", s.filter);
    }

    #[test]
    fn shared_reads_equal_each_texture_read_on_its_own(fps in proptest::collection::vec(footprint_strategy(), 1..20), f in 0usize..22, w in 0usize..5, count in 1usize..8, mixed in any::<bool>(), opaque in any::<bool>()) {
        // Textures of one size (more than one group of them when `count` > 5), or with one of
        // another size (each then read on its own). Opaque ones all linear: groups of the
        // kinds the AVX2 reads gather together (16-bit and opaque linear 8-bit texels).
        let textures: Vec<Texture2D> = (0..count)
            .map(|k| {
                let width = if mixed && k == count - 1 { 17 } else { 13 };
                let rgba: Vec<u8> = (0..width * 9 * 4)
                    .map(|i| match i % 4 {
                        3 if opaque => 255,
                        _ => ((i * (97 + 2 * k as u32) + 13 * k as u32) % 256) as u8,
                    })
                    .collect();
                // Every third held as 8-bit RGBA, sRGB or linear: groups mixing the storages.
                let options = match k % 3 {
                    0 => TextureOptions::default(),
                    _ => TextureOptions::default().with_storage(crate::texture::Storage::Rgba8),
                };
                let cs = if k % 3 == 1 && !opaque { ColorSpace::Srgb } else { ColorSpace::Linear };
                Texture2D::from_texels(width, 9, crate::texture::Format::Rgba8, cs, &rgba, options).unwrap()
            })
            .collect();
        let refs: Vec<&Texture2D> = textures.iter().collect();
        let s = Sampler::new(every_filter()[f], WRAPS[w]);
        let coords: Vec<crate::texture::QuadCoords> = fps
            .iter()
            .map(|fp| crate::texture::QuadCoords {
                u: Vec4::new(fp.uv.x, fp.uv.x + 0.01, fp.uv.x, fp.uv.x + 0.02),
                v: Vec4::new(fp.uv.y, fp.uv.y, fp.uv.y + 0.03, fp.uv.y + 0.01),
                duv_dx: fp.duv_dx,
                duv_dy: fp.duv_dy,
            })
            .collect();
        let masks: Vec<u8> = (0..coords.len()).map(|i| [0b1111, 0b0110, 0b1001][i % 3]).collect();
        let mut got = vec![[Vec4::splat(-1.0); 4]; count * coords.len()];
        crate::texture::sample_quads_lanes_shared(&refs, &s, &coords, &masks, |t, i, v| {
            got[t * coords.len() + i] = v;
        });
        for (t, tex) in textures.iter().enumerate() {
            let mut want = vec![[Vec4::ZERO; 4]; coords.len()];
            crate::texture::sample_quads_lanes(tex, &s, &coords, &masks, &mut want);
            prop_assert_eq!(&got[t * coords.len()..(t + 1) * coords.len()], &want[..], "{:?} texture {}", s.filter, t);
        }
    }

    #[test]
    fn quad_sampling_of_a_constant_texture_reads_the_constant(fp in footprint_strategy(), f in 0usize..22, w in 0usize..5) {
        // Every 8-bit value: the fixed-point weights of a read sum to exactly one (the
        // default storage and the 8-bit one).
        for (c, storage) in [0u8, 1, 17, 128, 254, 255].into_iter().flat_map(|c| {
            [(c, crate::texture::Storage::Linear16), (c, crate::texture::Storage::Rgba8)]
        }) {
            let options = TextureOptions::default().with_storage(storage);
            let tex = Texture2D::from_texels(11, 6, crate::texture::Format::Rgba8, ColorSpace::Linear, &[c; 11 * 6 * 4], options).unwrap();
            let mut s = Sampler::new(every_filter()[f], WRAPS[w]);
            // Premultiplied: colour times alpha.
            let x = f32::from(c) / 255.0;
            let want = Vec4::new(x * x, x * x, x * x, x);
            s.border = want;
            let uvs = [fp.uv, fp.uv + Vec2::new(0.3, 0.0), fp.uv + Vec2::new(0.0, 0.7), fp.uv + Vec2::new(0.5, 0.5)];
            let quad = crate::texture::sample_quad(&tex, &s, &uvs, fp.duv_dx, fp.duv_dy, 0b1111);
            for q in quad {
                // 15 of the 16 stored bits survive: 1/32767.
                prop_assert!(close(q, want, 3.1e-5), "{:?} {:?} {}: {} vs {}", s.filter, s.wrap_u, c, q, want);
            }
        }
    }

    #[test]
    fn constant_texture_reads_the_constant(fp in footprint_strategy(), f in 0usize..22, w in 0usize..5) {
        let c = Vec4::new(0.2, 0.4, 0.6, 0.8);
        let tex = Texture2D::from_fn(11, 6, TextureOptions::default(), |_, _| c).unwrap();
        let mut s = Sampler::new(every_filter()[f], WRAPS[w]);
        s.border = c * Vec4::new(0.8, 0.8, 0.8, 1.0); // premultiplied, like every read
        let want = Vec4::new(c.x * c.w, c.y * c.w, c.z * c.w, c.w);
        s.border = want;
        let got = sample(&tex, &s, &fp);
        prop_assert!(close(got, want, 1e-4), "{:?} {:?}: {} vs {}", s.filter, s.wrap_u, got, want);
    }

    #[test]
    fn filtered_value_stays_within_the_texels_range(fp in footprint_strategy(), f in 0usize..22, w in 0usize..3) {
        let tex = noisy(13, 9);
        let s = Sampler::new(every_filter()[f], WRAPS[w]);
        let texels = tex.decode_level(0);
        let lo = texels.iter().fold(Vec4::splat(f32::MAX), |a, &b| a.min(b));
        let hi = texels.iter().fold(Vec4::splat(f32::MIN), |a, &b| a.max(b));
        let got = sample(&tex, &s, &fp);
        prop_assert!(got.cmpge(lo - 1e-4).all() && got.cmple(hi + 1e-4).all(), "{:?}: {} not in [{}, {}]", s.filter, got, lo, hi);
    }

    #[test]
    fn bilinear_stays_within_its_four_texels(u in 0.05f32..0.95, v in 0.05f32..0.95) {
        let tex = noisy(13, 9);
        let s = Sampler::new(Filter::BILINEAR, Wrap::ClampToEdge);
        let got = sample(&tex, &s, &Footprint::point(Vec2::new(u, v)));
        let (px, py) = (u * 13.0 - 0.5, v * 9.0 - 0.5);
        let (x0, y0) = (px.floor().max(0.0) as u32, py.floor().max(0.0) as u32);
        let ts: Vec<Vec4> = [(0, 0), (1, 0), (0, 1), (1, 1)]
            .iter()
            .map(|&(dx, dy)| tex.texel(0, (x0 + dx).min(12), (y0 + dy).min(8)))
            .collect();
        let lo = ts.iter().fold(Vec4::splat(f32::MAX), |a, &b| a.min(b));
        let hi = ts.iter().fold(Vec4::splat(f32::MIN), |a, &b| a.max(b));
        prop_assert!(got.cmpge(lo - 1e-6).all() && got.cmple(hi + 1e-6).all());
    }
}

/// Random footprints up to 64:1 anisotropy, at any angle, from magnification to past the
/// last level of a 64×48 texture.
fn anisotropic_footprint_strategy() -> impl Strategy<Value = Footprint> {
    (
        -2.0f32..2.0,
        -2.0f32..2.0,
        0.0f32..std::f32::consts::PI,
        -9.0f32..-1.0,
        0.0f32..6.0,
    )
        .prop_map(|(u, v, angle, log_minor, log_ratio)| {
            let minor = log_minor.exp2();
            let (s, c) = angle.sin_cos();
            Footprint::new(
                Vec2::new(u, v),
                Vec2::new(c, s) * minor * log_ratio.exp2(),
                Vec2::new(-s, c) * minor,
            )
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// Anisotropic filtering of a quad on the default storage (either level rule) takes the
    /// fixed-point taps in lanes (`anisotropic::sample_quad`); the float filter, one
    /// footprint at a time, is its reference: each tap within the fixed-point trilinear
    /// bound (1.6·10⁻⁴), so their mean too — far under 2/255.
    #[test]
    fn anisotropic_quads_in_lanes_equal_the_float_filter(fp in anisotropic_footprint_strategy(), n in 1u32..=16, w in 0usize..5, mask in 1u8..16, eight in any::<bool>(), area in any::<bool>()) {
        // The storages the lane path serves (with repeat and clamp to edge; the other wraps
        // take the float filter, and must agree all the same).
        let tex = if eight { noisy8(64, 48, ColorSpace::Srgb, false) } else { noisy(64, 48) };
        if !eight {
            prop_assert_eq!(tex.storage_format(), crate::texture::Format::Rgba16Premultiplied);
        }
        prop_assert_eq!(tex.layout(), crate::texture::Layout::Tiled4x4);
        let lod = if area { crate::texture::AnisoLod::Area } else { crate::texture::AnisoLod::Gl };
        let s = Sampler::new(Filter::Anisotropic { max_aniso: n, lod }, WRAPS[w]);
        let uvs = [fp.uv, fp.uv + Vec2::new(0.011, 0.0), fp.uv + Vec2::new(0.0, 0.013), fp.uv + Vec2::new(0.011, 0.013)];
        let quad = crate::texture::sample_quad(&tex, &s, &uvs, fp.duv_dx, fp.duv_dy, mask);
        for j in 0..4 {
            let want = if mask & (1 << j) == 0 {
                Vec4::ZERO
            } else {
                sample(&tex, &s, &Footprint::new(uvs[j], fp.duv_dx, fp.duv_dy))
            };
            prop_assert!(close(quad[j], want, 1.6e-4), "{} {:?} pixel {}: {} vs {}", s.filter.name(), s.wrap_u, j, quad[j], want);
        }
    }
}

/// Random EWA footprints: any angle, anisotropy up to 64:1 (past the eccentricity clamp),
/// from magnification to past the last level of a 64×48 texture, and coordinates some way
/// off the image.
fn ewa_footprint_strategy() -> impl Strategy<Value = Footprint> {
    (
        -4.0f32..4.0,
        -4.0f32..4.0,
        0.0f32..std::f32::consts::PI,
        -9.0f32..0.0,
        0.0f32..6.0,
    )
        .prop_map(|(u, v, angle, log_minor, log_ratio)| {
            let minor = log_minor.exp2();
            let (s, c) = angle.sin_cos();
            Footprint::new(
                Vec2::new(u, v),
                Vec2::new(c, s) * minor * log_ratio.exp2(),
                Vec2::new(-s, c) * minor,
            )
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// EWA of a quad in lanes (`ewa_lanes`) is the float filter read one pixel at a time,
    /// bit for bit (tolerance 0), on every wrap, storage and eccentricity clamp, with
    /// neighbours near and far (a wrap between the pixels) and any mask.
    #[test]
    fn ewa_quads_in_lanes_equal_the_float_filter_exactly(fp in ewa_footprint_strategy(), w in 0usize..5, mask in 1u8..16, spread in 0usize..3, ecc in 0usize..3, float in any::<bool>()) {
        let tex = if float {
            Texture2D::from_fn(37, 23, TextureOptions::default(), |x, y| {
                let h = (x * 7919 + y * 104_729) % 1000;
                Vec4::new(h as f32 / 999.0, (h % 17) as f32 / 16.0, 0.5, 1.0 - (h % 5) as f32 / 8.0)
            }).unwrap()
        } else {
            noisy(64, 48)
        };
        let max_eccentricity = [16.0, 4.0, 64.0][ecc];
        let mut s = Sampler::new(Filter::EwaExact { max_eccentricity }, WRAPS[w]);
        s.border = Vec4::new(0.1, 0.2, 0.3, 0.4);
        let step = [0.007, 0.05, 0.6][spread];
        let uvs = [fp.uv, fp.uv + Vec2::new(step, 0.0), fp.uv + Vec2::new(0.0, step * 1.3), fp.uv + Vec2::new(step, step * 1.3)];
        let quad = crate::texture::sample_quad(&tex, &s, &uvs, fp.duv_dx, fp.duv_dy, mask);
        for j in 0..4 {
            let want = if mask & (1 << j) == 0 {
                Vec4::ZERO
            } else {
                sample(&tex, &s, &Footprint::new(uvs[j], fp.duv_dx, fp.duv_dy))
            };
            prop_assert!(quad[j].to_array().map(f32::to_bits) == want.to_array().map(f32::to_bits), "{:?} pixel {}: {} vs {}", s.wrap_u, j, quad[j], want);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// `ewa`'s probes: at most 16, placed symmetrically about the centre inside (−1, 1), their
    /// weights positive, mirrored, and summing to 1.
    #[test]
    fn ewa_probe_weights_are_symmetric_and_sum_to_one(fp in ewa_footprint_strategy(), ecc in 0usize..3) {
        let tex = noisy(64, 48);
        let s = Sampler::new(Filter::Ewa { max_eccentricity: 16.0 }, Wrap::Repeat);
        let max_ecc = [16.0, 4.0, 64.0][ecc];
        if let super::ewa_probes::Plan::Probes { count, .. } = super::ewa_probes::plan(&tex, &s, &fp, max_ecc) {
            let probes = &super::ewa_probes::layout(count)[..count];
            prop_assert!((1..=super::ewa_probes::MAX_PROBES).contains(&count));
            let total: f32 = probes.iter().map(|p| p.1).sum();
            prop_assert!((total - 1.0).abs() < 1e-6, "{}", total);
            for (a, b) in probes.iter().zip(probes.iter().rev()) {
                prop_assert!(a.1 > 0.0 && a.0 > -1.0 && a.0 < 1.0, "{:?}", probes);
                prop_assert!((a.0 + b.0).abs() < 1e-6 && (a.1 - b.1).abs() < 1e-6, "{:?}", probes);
            }
        }
    }

    /// `ewa` of a quad on the default storage (fixed-point probes in lanes, or `ewa-exact`'s
    /// lanes for round footprints) against the float filter read one pixel at a time: within
    /// the fixed-point trilinear bound, on every wrap.
    #[test]
    fn ewa_quads_in_lanes_equal_the_float_filter(fp in ewa_footprint_strategy(), w in 0usize..5, mask in 1u8..16) {
        let tex = noisy(64, 48);
        let s = Sampler::new(Filter::Ewa { max_eccentricity: 16.0 }, WRAPS[w]);
        let uvs = [fp.uv, fp.uv + Vec2::new(0.011, 0.0), fp.uv + Vec2::new(0.0, 0.013), fp.uv + Vec2::new(0.011, 0.013)];
        let quad = crate::texture::sample_quad(&tex, &s, &uvs, fp.duv_dx, fp.duv_dy, mask);
        for j in 0..4 {
            let want = if mask & (1 << j) == 0 {
                Vec4::ZERO
            } else {
                sample(&tex, &s, &Footprint::new(uvs[j], fp.duv_dx, fp.duv_dy))
            };
            prop_assert!(close(quad[j], want, 1.6e-4), "{:?} pixel {}: {} vs {}", s.wrap_u, j, quad[j], want);
        }
    }
}

#[test]
fn ewa_reads_round_footprints_exactly() {
    // Below the probes' eccentricity (2:1) the two filters are one read, bit for bit (a
    // square texture: the ratio in texels is the one in uv).
    let tex = noisy(64, 64);
    let probes = Sampler::new(Filter::parse("ewa").unwrap(), Wrap::Repeat);
    let exact = Sampler::new(Filter::parse("ewa-exact").unwrap(), Wrap::Repeat);
    for i in 0..200 {
        let uv = Vec2::new((i as f32 * 0.137) % 1.0, (i as f32 * 0.291) % 1.0);
        let (angle, ratio, minor) = (
            i as f32 * 0.1,
            1.0 + (i % 10) as f32 / 10.0,
            0.02 + (i % 7) as f32 * 0.03,
        );
        let (s, c) = angle.sin_cos();
        let fp = Footprint::new(
            uv,
            Vec2::new(c, s) * minor * ratio,
            Vec2::new(-s, c) * minor,
        );
        let (a, b) = (sample(&tex, &probes, &fp), sample(&tex, &exact, &fp));
        assert_eq!(
            a.to_array().map(f32::to_bits),
            b.to_array().map(f32::to_bits),
            "{i}: {a} vs {b}"
        );
    }
}

/// `far_quads`' limit without a bias is the one its `exp2` gives.
#[test]
fn the_far_limit_without_a_bias_is_its_power_of_two() {
    use super::quads::{FAR_LIMIT, FAR_LOD};
    assert_eq!((2.0 * FAR_LOD).exp2(), FAR_LIMIT);
}

proptest! {
    /// The quads whose texels a bilinear read on level 0 asks for first are those whose λ,
    /// biased and clamped by the sampler, is over `FAR_LOD`: the logarithm-free test against
    /// λ itself (away from the boundary, where the two roundings may differ).
    #[test]
    fn far_quads_are_those_past_the_level_of_detail(
        d in prop::collection::vec((-0.05f32..0.05, -0.05f32..0.05, -0.05f32..0.05, -0.05f32..0.05), 1..16),
        bias in -2.0f32..2.0,
        min_lod in -1.0f32..3.0,
        span in 0.0f32..4.0,
        rss in any::<bool>(),
    ) {
        use super::quads::{far_quads, FAR_LOD};
        let tex = noisy(64, 48);
        let sampler = Sampler {
            lod_bias: bias,
            min_lod,
            max_lod: min_lod + span,
            lod_rule: if rss { LodRule::RootSumSquares } else { LodRule::GlMax },
            ..Sampler::new(Filter::parse("bilinear").unwrap(), Wrap::Repeat)
        };
        let coords: Vec<crate::texture::QuadCoords> = d
            .iter()
            .map(|&(a, b, c, e)| crate::texture::QuadCoords {
                duv_dx: Vec2::new(a, b),
                duv_dy: Vec2::new(c, e),
                ..Default::default()
            })
            .collect();
        let far = far_quads(&tex, &sampler, &coords);
        for (i, c) in coords.iter().enumerate() {
            let size = Vec2::new(64.0, 48.0);
            let (lx, ly) = ((c.duv_dx * size).length_squared(), (c.duv_dy * size).length_squared());
            let arg = if rss { lx + ly } else { lx.max(ly) };
            let lod = 0.5 * f64::from(arg).log2() as f32;
            let adjusted = sampler.adjust_lod(lod);
            if (adjusted - FAR_LOD).abs() > 1e-3 {
                prop_assert_eq!(far & (1 << i) != 0, adjusted > FAR_LOD, "quad {} λ {}", i, lod);
            }
        }
    }
}
