//! OpenGL's level choice, pinned: the rule alone on a table of λ, then every texture kind
//! (2D single, quad, batched and fixed-point reads, cube maps, 3D textures) giving the answers
//! the table gives on textures whose levels tell which levels and weights a read used.

use glam::{Vec2, Vec3, Vec4};

use super::{MipBlend, MipChoice, TexelFilter};
use crate::texture::{
    sample, sample_3d, sample_cube, sample_quad, sample_quads_lanes, ColorSpace, CubeFootprint,
    Filter, Footprint, Footprint3, Format, LodRule, MagFilter, MinFilter, QuadCoords, Sampler,
    Texture2D, Texture3D, TextureCube, TextureOptions, Wrap,
};

/// The six minification filters, in the order of the tables below.
const MINS: [MinFilter; 6] = [
    MinFilter::Nearest,
    MinFilter::Linear,
    MinFilter::NearestMipmapNearest,
    MinFilter::LinearMipmapNearest,
    MinFilter::NearestMipmapLinear,
    MinFilter::LinearMipmapLinear,
];

/// How each min filter reads texels within a level, in [`MINS`] order.
const MIN_TEXELS: [TexelFilter; 6] = [
    TexelFilter::Nearest,
    TexelFilter::Linear,
    TexelFilter::Nearest,
    TexelFilter::Linear,
    TexelFilter::Nearest,
    TexelFilter::Linear,
];

const MAGS: [MagFilter; 2] = [MagFilter::Nearest, MagFilter::Linear];

/// What a read at some λ takes, written out by hand from section 8.14 for a chain of four
/// levels (8, 4, 2, 1 texels a side).
#[derive(Clone, Copy, Debug)]
enum Reads {
    /// λ ≤ 0: level 0 with the magnification filter.
    Magnified,
    /// λ > 0: per min filter (in [`MINS`] order) the level read plus the weight of the next
    /// level blended in (`1.25` = level 1 weighted ¾, level 2 weighted ¼).
    Minified([f32; 6]),
}

/// Per λ > 0, per min filter in [`MINS`] order (NEAREST, LINEAR, NEAREST_MIPMAP_NEAREST,
/// LINEAR_MIPMAP_NEAREST, NEAREST_MIPMAP_LINEAR, LINEAR_MIPMAP_LINEAR): the level read plus
/// the weight of the next one, for four levels.
const TABLE: [(f32, [f32; 6]); 11] = [
    (0.25, [0.0, 0.0, 0.0, 0.0, 0.25, 0.25]),
    (0.5, [0.0, 0.0, 0.0, 0.0, 0.5, 0.5]),
    (0.75, [0.0, 0.0, 1.0, 1.0, 0.75, 0.75]),
    (1.0, [0.0, 0.0, 1.0, 1.0, 1.0, 1.0]),
    (1.25, [0.0, 0.0, 1.0, 1.0, 1.25, 1.25]),
    // ⌈λ + ½⌉ − 1: a half rounds down.
    (1.5, [0.0, 0.0, 1.0, 1.0, 1.5, 1.5]),
    (1.75, [0.0, 0.0, 2.0, 2.0, 1.75, 1.75]),
    (2.5, [0.0, 0.0, 2.0, 2.0, 2.5, 2.5]),
    (3.0, [0.0, 0.0, 3.0, 3.0, 3.0, 3.0]),
    // Beyond the last level: the last level alone.
    (3.5, [0.0, 0.0, 3.0, 3.0, 3.0, 3.0]),
    (6.0, [0.0, 0.0, 3.0, 3.0, 3.0, 3.0]),
];

/// The table's row at λ.
fn reads_at(lod: f32) -> Reads {
    if !(lod > 0.0) {
        return Reads::Magnified;
    }
    let row = TABLE.iter().find(|(l, _)| *l == lod);
    Reads::Minified(
        row.unwrap_or_else(|| panic!("no table row for λ = {lod}"))
            .1,
    )
}

#[test]
fn gl_choice_follows_the_table() {
    let lods = [
        f32::NAN,
        f32::NEG_INFINITY,
        -1.0,
        0.0,
        0.25,
        0.5,
        0.75,
        1.0,
        1.25,
        1.5,
        1.75,
        2.5,
        3.0,
        3.5,
        6.0,
    ];
    for lod in lods {
        for mag in MAGS {
            for (k, min) in MINS.into_iter().enumerate() {
                let got = MipChoice::gl(lod, 4, mag, min);
                let want = match reads_at(lod) {
                    Reads::Magnified => MipChoice {
                        level: 0,
                        blend: None,
                        texels: match mag {
                            MagFilter::Nearest => TexelFilter::Nearest,
                            MagFilter::Linear => TexelFilter::Linear,
                        },
                    },
                    Reads::Minified(levels) => {
                        let (level, weight) = (levels[k].floor(), levels[k].fract());
                        MipChoice {
                            level: level as usize,
                            blend: (weight > 0.0).then_some(MipBlend {
                                level: level as usize + 1,
                                weight,
                            }),
                            texels: MIN_TEXELS[k],
                        }
                    }
                };
                assert_eq!(got, want, "λ = {lod}, {mag:?}/{min:?}");
            }
        }
    }
}

#[test]
fn gl_choice_on_a_single_level_reads_level_zero() {
    for min in MINS {
        for lod in [0.25, 0.75, 1.5, 9.0] {
            let c = MipChoice::gl(lod, 1, MagFilter::Linear, min);
            assert_eq!((c.level, c.blend), (0, None), "{min:?} at {lod}");
        }
    }
}

#[test]
fn the_fixed_choice_is_the_rules_at_every_lod() {
    let lods = [
        f32::NAN,
        f32::NEG_INFINITY,
        -3.0,
        0.0,
        0.25,
        0.5,
        0.75,
        1.0,
        2.5,
        7.0,
        f32::INFINITY,
    ];
    let mut fixed_pairs = 0;
    for count in 1..=4 {
        for (&min, &min_texels) in MINS.iter().zip(&MIN_TEXELS) {
            for mag in MAGS {
                let mag_texels = match mag {
                    MagFilter::Nearest => TexelFilter::Nearest,
                    MagFilter::Linear => TexelFilter::Linear,
                };
                let level0 = count == 1 || matches!(min, MinFilter::Nearest | MinFilter::Linear);
                let fixed = MipChoice::fixed(count, mag, min);
                assert_eq!(fixed.is_some(), level0 && mag_texels == min_texels);
                if let Some(fixed) = fixed {
                    fixed_pairs += 1;
                    for lod in lods {
                        assert_eq!(MipChoice::gl(lod, count, mag, min), fixed, "{min:?} {lod}");
                    }
                }
            }
        }
    }
    // Level 0 only: two pairs on every chain; one level: all six min filters' matching pairs.
    assert_eq!(fixed_pairs, 2 * 3 + 6);
}

/// Level `level`'s texel `(x, y)` (and any z): red = the level (times `scale`), green a
/// checkerboard in x and y, so a read's red tells its levels and weights and its green tells
/// nearest (0 at the centre) from linear (½ at the centre, on levels of two texels or more).
fn level_texel(scale: f32, level: usize, x: u32, y: u32) -> Vec4 {
    Vec4::new(level as f32 * scale, ((x + y) % 2) as f32, 0.0, 1.0)
}

const N: u32 = 8;
const LAST: usize = 3;

fn float_2d() -> Texture2D {
    let mut t = Texture2D::from_fn(N, N, TextureOptions::default(), |_, _| Vec4::ZERO).unwrap();
    t.replace_levels(|l, x, y| level_texel(1.0, l, x, y));
    t
}

/// An 8-bit texture in the default storage: what the fixed-point quad reads serve. Red holds
/// the level over 3 to stay within [0, 1].
fn fixed_2d() -> Texture2D {
    let bytes = vec![0u8; (N * N * 4) as usize];
    let mut t = Texture2D::from_texels(
        N,
        N,
        Format::Rgba8,
        // sRGB: the default storage holds it in 16 bits (linear data it keeps in 8), which
        // `replace_levels` writes as linear values.
        ColorSpace::Srgb,
        &bytes,
        TextureOptions::default(),
    )
    .unwrap();
    t.replace_levels(|l, x, y| level_texel(1.0 / 3.0, l, x, y));
    t
}

fn cube() -> TextureCube {
    TextureCube::new(std::array::from_fn(|_| float_2d())).unwrap()
}

fn volume() -> Texture3D {
    let bytes = vec![0u8; (N * N * N) as usize * 16];
    let mut t =
        Texture3D::from_texels([N; 3], Format::Rgba32F, ColorSpace::Linear, &bytes, true).unwrap();
    t.replace_levels(|l, x, y, _| level_texel(1.0, l, x, y));
    t
}

/// A footprint setting: both derivatives `texels` long (along u and along v), and the
/// sampler's rule, bias and clamps.
#[derive(Clone, Copy, Debug)]
struct Setting {
    texels: f32,
    rule: LodRule,
    bias: f32,
    clamp: (f32, f32),
    /// The λ these make.
    lod: f32,
}

const OPEN: (f32, f32) = (-1000.0, 1000.0);

fn settings() -> Vec<Setting> {
    let s = |texels, rule, bias, clamp, lod| Setting {
        texels,
        rule,
        bias,
        clamp,
        lod,
    };
    use LodRule::{GlMax as Gl, RootSumSquares as Rss};
    vec![
        s(0.5, Gl, 0.0, OPEN, -1.0),
        s(1.0, Gl, 0.0, OPEN, 0.0),
        s(1.0, Gl, 0.25, OPEN, 0.25),
        // The sum rule: ½·log2(1 + 1).
        s(1.0, Rss, 0.0, OPEN, 0.5),
        s(2.0, Gl, -0.25, OPEN, 0.75),
        s(2.0, Gl, 0.0, OPEN, 1.0),
        s(2.0, Rss, 0.0, OPEN, 1.5),
        s(4.0, Gl, -0.25, OPEN, 1.75),
        s(4.0, Gl, 0.5, OPEN, 2.5),
        s(8.0, Gl, 0.0, OPEN, 3.0),
        s(8.0, Gl, 0.5, OPEN, 3.5),
        s(64.0, Gl, 0.0, OPEN, 6.0),
        // The clamps apply after the bias.
        s(4.0, Gl, 0.5, (0.0, 1.25), 1.25),
        s(0.5, Gl, 0.0, (1.5, 1000.0), 1.5),
        s(1.0, Gl, -2.0, (-0.5, 1000.0), -0.5),
        s(64.0, Gl, -10.0, (0.75, 2.5), 0.75),
    ]
}

/// The value a read with `mag`/`min` (index `k` in [`MINS`]) returns at `lod`, red in level
/// units.
fn expected(lod: f32, mag: MagFilter, k: usize) -> Vec4 {
    let (levels, texels) = match reads_at(lod) {
        Reads::Magnified => (
            0.0,
            match mag {
                MagFilter::Nearest => TexelFilter::Nearest,
                MagFilter::Linear => TexelFilter::Linear,
            },
        ),
        Reads::Minified(levels) => (levels[k], MIN_TEXELS[k]),
    };
    // A linear read at the centre averages a checkerboard; the 1×1 level has one texel (0).
    let green = |level: usize| {
        if texels == TexelFilter::Linear && level < LAST {
            0.5
        } else {
            0.0
        }
    };
    let (a, w) = (levels.floor() as usize, levels.fract());
    let g = if w > 0.0 {
        green(a) * (1.0 - w) + green(a + 1) * w
    } else {
        green(a)
    };
    Vec4::new(levels, g, 0.0, 1.0)
}

#[test]
fn gl_level_choice_is_the_same_for_2d_cube_and_3d_reads() {
    let (float_2d, fixed_2d, cube, volume) = (float_2d(), fixed_2d(), cube(), volume());
    assert_eq!(fixed_2d.storage_format(), Format::Rgba16Premultiplied);
    let (centre, n) = (Vec2::splat(0.5), N as f32);
    for set in settings() {
        let (dx, dy) = (
            Vec2::new(set.texels / n, 0.0),
            Vec2::new(0.0, set.texels / n),
        );
        for mag in MAGS {
            for (k, min) in MINS.into_iter().enumerate() {
                let s = Sampler::new(Filter::Gl { mag, min }, Wrap::ClampToEdge)
                    .with_lod_rule(set.rule)
                    .with_lod_bias(set.bias)
                    .with_lod_clamp(set.clamp.0, set.clamp.1);
                let want = expected(set.lod, mag, k);
                let check = |kind: &str, got: Vec4, tol: f32| {
                    assert!(
                        (got - want).abs().max_element() <= tol,
                        "{kind}, {mag:?}/{min:?}, {set:?}: got {got}, want {want}"
                    );
                };
                let fp = Footprint::new(centre, dx, dy);
                check("2D", sample(&float_2d, &s, &fp), 1e-6);
                let quad = sample_quad(&float_2d, &s, &[centre; 4], dx, dy, 0b1111);
                for (j, &got) in quad.iter().enumerate() {
                    check(&format!("2D quad pixel {j}"), got, 1e-6);
                }
                // Five quads: one full group of four for the four-lane λ, and one more.
                let coords = [QuadCoords {
                    u: Vec4::splat(0.5),
                    v: Vec4::splat(0.5),
                    duv_dx: dx,
                    duv_dy: dy,
                }; 5];
                let mut out = [[Vec4::ZERO; 4]; 5];
                sample_quads_lanes(&float_2d, &s, &coords, &[0b1111; 5], &mut out);
                for (i, quad) in out.iter().enumerate() {
                    for &got in quad {
                        check(&format!("2D batch quad {i}"), got, 1e-6);
                    }
                }
                // Fixed point: 15-bit weights, red scaled by 3.
                let quad = sample_quad(&fixed_2d, &s, &[centre; 4], dx, dy, 0b1111);
                for &got in &quad {
                    check("2D fixed point", got * Vec4::new(3.0, 1.0, 1.0, 1.0), 1e-3);
                }
                // Cube: the centre of +Z, whose face uv derivatives are half the direction's.
                let cfp = CubeFootprint {
                    dir: Vec3::Z,
                    ddir_dx: Vec3::new(2.0 * dx.x, 0.0, 0.0),
                    ddir_dy: Vec3::new(0.0, 2.0 * dy.y, 0.0),
                };
                check("cube", sample_cube(&cube, &s, &cfp), 1e-6);
                let fp3 = Footprint3 {
                    uvw: Vec3::splat(0.5),
                    duvw_dx: dx.extend(0.0),
                    duvw_dy: dy.extend(0.0),
                };
                check("3D", sample_3d(&volume, &s, &fp3), 1e-6);
            }
        }
    }
}
