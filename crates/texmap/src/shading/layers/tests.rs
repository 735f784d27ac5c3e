//! The texture environment against the OpenGL 1.5 specification's tables, on constant
//! values: every mode and every base format, each expected value written from the table.

use glam::Vec4;

use super::{tex_env, BaseFormat as F, TexEnvMode as M};

const CF: Vec4 = Vec4::new(0.2, 0.4, 0.6, 0.5);
/// The texel: R (also L and I) 0.5, G 0.25, B 1, A 0.75.
const T: Vec4 = Vec4::new(0.5, 0.25, 1.0, 0.75);
const CC: Vec4 = Vec4::new(0.9, 0.1, 0.3, 0.6);

fn check(mode: M, format: F, want: [f32; 4]) {
    let got = tex_env(mode, format, CF, T, CC).expect("defined");
    let want = Vec4::from(want);
    assert!(
        (got - want).abs().max_element() < 1e-6,
        "{} {}: {got} ≠ {want}",
        mode.name(),
        format.name()
    );
}

#[test]
fn replace_table_3_22() {
    // ALPHA: Cf, At. LUMINANCE: Lt, Af. LA: Lt, At. INTENSITY: It, It. RGB: Ct, Af. RGBA: Ct, At.
    check(M::Replace, F::Alpha, [0.2, 0.4, 0.6, 0.75]);
    check(M::Replace, F::Luminance, [0.5, 0.5, 0.5, 0.5]);
    check(M::Replace, F::LuminanceAlpha, [0.5, 0.5, 0.5, 0.75]);
    check(M::Replace, F::Intensity, [0.5, 0.5, 0.5, 0.5]);
    check(M::Replace, F::Rgb, [0.5, 0.25, 1.0, 0.5]);
    check(M::Replace, F::Rgba, [0.5, 0.25, 1.0, 0.75]);
}

#[test]
fn modulate_table_3_22() {
    // ALPHA: Cf, Af·At. L: Cf·Lt, Af. LA: Cf·Lt, Af·At. I: Cf·It, Af·It. RGB: Cf·Ct, Af.
    // RGBA: Cf·Ct, Af·At.
    check(M::Modulate, F::Alpha, [0.2, 0.4, 0.6, 0.375]);
    check(M::Modulate, F::Luminance, [0.1, 0.2, 0.3, 0.5]);
    check(M::Modulate, F::LuminanceAlpha, [0.1, 0.2, 0.3, 0.375]);
    check(M::Modulate, F::Intensity, [0.1, 0.2, 0.3, 0.25]);
    check(M::Modulate, F::Rgb, [0.1, 0.1, 0.6, 0.5]);
    check(M::Modulate, F::Rgba, [0.1, 0.1, 0.6, 0.375]);
}

#[test]
fn decal_table_3_22() {
    // RGB: Ct, Af. RGBA: Cf·(1 − At) + Ct·At, Af. The others are undefined.
    check(M::Decal, F::Rgb, [0.5, 0.25, 1.0, 0.5]);
    check(
        M::Decal,
        F::Rgba,
        [
            0.2 * 0.25 + 0.5 * 0.75,
            0.4 * 0.25 + 0.25 * 0.75,
            0.6 * 0.25 + 0.75,
            0.5,
        ],
    );
    for f in [F::Alpha, F::Luminance, F::LuminanceAlpha, F::Intensity] {
        assert!(tex_env(M::Decal, f, CF, T, CC).is_none(), "{}", f.name());
    }
}

#[test]
fn blend_table_3_23() {
    // ALPHA: Cf, Af·At. L: Cf·(1 − Lt) + Cc·Lt, Af. LA: the same, Af·At.
    // I: Cf·(1 − It) + Cc·It, Af·(1 − It) + Ac·It. RGB: Cf·(1 − Ct) + Cc·Ct, Af. RGBA: …, Af·At.
    let l = [
        0.2 * 0.5 + 0.9 * 0.5,
        0.4 * 0.5 + 0.1 * 0.5,
        0.6 * 0.5 + 0.3 * 0.5,
    ];
    check(M::Blend, F::Alpha, [0.2, 0.4, 0.6, 0.375]);
    check(M::Blend, F::Luminance, [l[0], l[1], l[2], 0.5]);
    check(M::Blend, F::LuminanceAlpha, [l[0], l[1], l[2], 0.375]);
    check(
        M::Blend,
        F::Intensity,
        [l[0], l[1], l[2], 0.5 * 0.5 + 0.6 * 0.5],
    );
    let rgb = [0.2 * 0.5 + 0.9 * 0.5, 0.4 * 0.75 + 0.1 * 0.25, 0.3];
    check(M::Blend, F::Rgb, [rgb[0], rgb[1], rgb[2], 0.5]);
    check(M::Blend, F::Rgba, [rgb[0], rgb[1], rgb[2], 0.375]);
}

#[test]
fn add_table_3_23_clamps() {
    // ALPHA: Cf, Af·At. L: Cf + Lt, Af. LA: Cf + Lt, Af·At. I: Cf + It, Af + It.
    // RGB: Cf + Ct, Af. RGBA: Cf + Ct, Af·At. Clamped to [0, 1].
    check(M::Add, F::Alpha, [0.2, 0.4, 0.6, 0.375]);
    check(M::Add, F::Luminance, [0.7, 0.9, 1.0, 0.5]);
    check(M::Add, F::LuminanceAlpha, [0.7, 0.9, 1.0, 0.375]);
    check(M::Add, F::Intensity, [0.7, 0.9, 1.0, 1.0]);
    check(M::Add, F::Rgb, [0.7, 0.65, 1.0, 0.5]);
    check(M::Add, F::Rgba, [0.7, 0.65, 1.0, 0.375]);
}

#[test]
fn combine_interpolate_and_detail() {
    // INTERPOLATE: Arg0·Arg2 + Arg1·(1 − Arg2), Arg0 = texture, Arg1 = previous.
    let by_t = M::Interpolate { by_constant: false };
    let by_c = M::Interpolate { by_constant: true };
    check(
        by_t,
        F::Rgba,
        [
            0.5 * 0.75 + 0.2 * 0.25,
            0.25 * 0.75 + 0.4 * 0.25,
            0.75 + 0.6 * 0.25,
            0.5,
        ],
    );
    check(
        by_c,
        F::Rgba,
        [
            0.5 * 0.6 + 0.2 * 0.4,
            0.25 * 0.6 + 0.4 * 0.4,
            0.6 + 0.6 * 0.4,
            0.5,
        ],
    );
    // An RGB texture's alpha is 1: interpolating by it replaces.
    check(by_t, F::Rgb, [0.5, 0.25, 1.0, 0.5]);
    // Detail: 2·Cf·Ct, clamped; a grey 0.5 texel changes nothing.
    check(M::Detail, F::Rgb, [0.2, 0.2, 1.0, 0.5]);
    let grey = tex_env(M::Detail, F::Luminance, CF, Vec4::splat(0.5), CC).unwrap();
    assert!((grey - CF).abs().max_element() < 1e-7, "{grey}");
}

#[test]
fn names_round_trip() {
    for name in M::NAMES.split(", ") {
        assert_eq!(M::parse(name).map(M::name), Some(name));
    }
    for name in F::NAMES.split(", ") {
        assert_eq!(F::parse(name).map(F::name), Some(name));
    }
    assert!(M::parse("combine").is_none() && F::parse("bgr").is_none());
}
