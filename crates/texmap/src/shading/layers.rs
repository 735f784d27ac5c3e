//! Texture layers (multitexturing) with OpenGL's texture-environment semantics.
//!
//! A material's layers are stages applied in order after its own colour: stage 0's incoming
//! colour `Cf` is the material's surface colour (base colour × base-colour texture ×
//! opacity × vertex colour × procedural colour), and each stage's output is the next one's
//! `Cf`. The result is the surface colour `C` that lighting then uses (`I = C·D + S`), so an
//! unlit render equals OpenGL's fixed-function pipeline with lighting off.
//!
//! Each stage combines `Cf`, the layer's texel `Ct` (read through the sampling engine with
//! its own uv set, transform and sampler) and the layer's constant `Cc` by
//! [`TexEnvMode`], per the texture's base internal format ([`BaseFormat`]) as in the
//! OpenGL 1.5 specification, §3.13, Tables 3.22 (REPLACE, MODULATE, DECAL) and 3.23 (BLEND,
//! ADD), and for `Interpolate` and `Detail`, GL_COMBINE (Table 3.24: INTERPOLATE is
//! `Arg0·Arg2 + Arg1·(1 − Arg2)`; MODULATE with RGB_SCALE 2). Values are linear light,
//! straight alpha; every stage's output is clamped to [0, 1] as OpenGL clamps it.

use std::sync::Arc;

use glam::{Vec3, Vec4};

use super::material::TextureSlot;

/// GL_TEXTURE_ENV_MODE, and the two GL_COMBINE functions texmap offers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TexEnvMode {
    /// GL_REPLACE.
    Replace,
    /// GL_MODULATE.
    Modulate,
    /// GL_DECAL (RGB and RGBA formats only; OpenGL leaves the others undefined).
    Decal,
    /// GL_BLEND with the environment colour `Cc` (the layer's constant).
    Blend,
    /// GL_ADD.
    Add,
    /// GL_COMBINE, COMBINE_RGB = INTERPOLATE: Arg0 = the texture's colour, Arg1 = the
    /// previous stage, Arg2 = the texture's alpha (`by_constant` false) or the constant's
    /// alpha; COMBINE_ALPHA = REPLACE with the previous stage's alpha.
    Interpolate {
        /// Arg2 is the constant's alpha instead of the texture's.
        by_constant: bool,
    },
    /// A detail map: GL_COMBINE, COMBINE_RGB = MODULATE of the previous stage and the
    /// texture with RGB_SCALE 2 (`2·Cf·Ct`: a texel of 0.5 leaves the colour as it is);
    /// COMBINE_ALPHA = REPLACE with the previous stage's alpha.
    Detail,
}

impl TexEnvMode {
    /// Every mode's scene-file name.
    pub const NAMES: &'static str =
        "replace, modulate, decal, blend, add, interpolate, interpolate-constant, detail";

    /// The mode named `name` (one of [`TexEnvMode::NAMES`]).
    #[must_use]
    pub fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "replace" => TexEnvMode::Replace,
            "modulate" => TexEnvMode::Modulate,
            "decal" => TexEnvMode::Decal,
            "blend" => TexEnvMode::Blend,
            "add" => TexEnvMode::Add,
            "interpolate" => TexEnvMode::Interpolate { by_constant: false },
            "interpolate-constant" => TexEnvMode::Interpolate { by_constant: true },
            "detail" => TexEnvMode::Detail,
            _ => return None,
        })
    }

    /// The scene-file name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            TexEnvMode::Replace => "replace",
            TexEnvMode::Modulate => "modulate",
            TexEnvMode::Decal => "decal",
            TexEnvMode::Blend => "blend",
            TexEnvMode::Add => "add",
            TexEnvMode::Interpolate { by_constant: false } => "interpolate",
            TexEnvMode::Interpolate { by_constant: true } => "interpolate-constant",
            TexEnvMode::Detail => "detail",
        }
    }
}

/// OpenGL's base internal format of a layer's texture: which of the texel's channels the
/// table reads (L = I = red).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BaseFormat {
    Alpha,
    Luminance,
    LuminanceAlpha,
    Intensity,
    Rgb,
    Rgba,
}

impl BaseFormat {
    /// Every format's scene-file name.
    pub const NAMES: &'static str = "alpha, luminance, luminance-alpha, intensity, rgb, rgba";

    /// The format named `name` (one of [`BaseFormat::NAMES`]).
    #[must_use]
    pub fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "alpha" => BaseFormat::Alpha,
            "luminance" => BaseFormat::Luminance,
            "luminance-alpha" => BaseFormat::LuminanceAlpha,
            "intensity" => BaseFormat::Intensity,
            "rgb" => BaseFormat::Rgb,
            "rgba" => BaseFormat::Rgba,
            _ => return None,
        })
    }

    /// The scene-file name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            BaseFormat::Alpha => "alpha",
            BaseFormat::Luminance => "luminance",
            BaseFormat::LuminanceAlpha => "luminance-alpha",
            BaseFormat::Intensity => "intensity",
            BaseFormat::Rgb => "rgb",
            BaseFormat::Rgba => "rgba",
        }
    }

    /// The texture source's colour and alpha (GL's Table 3.21 for the combiner's `TEXTURE`
    /// source): A → (0, 0, 0, A); L → (L, L, L, 1); LA → (L, L, L, A); I → (I, I, I, I);
    /// RGB → (R, G, B, 1); RGBA as read. `t` is straight.
    #[must_use]
    pub fn source(self, t: Vec4) -> (Vec3, f32) {
        match self {
            BaseFormat::Alpha => (Vec3::ZERO, t.w),
            BaseFormat::Luminance => (Vec3::splat(t.x), 1.0),
            BaseFormat::LuminanceAlpha => (Vec3::splat(t.x), t.w),
            BaseFormat::Intensity => (Vec3::splat(t.x), t.x),
            BaseFormat::Rgb => (t.truncate(), 1.0),
            BaseFormat::Rgba => (t.truncate(), t.w),
        }
    }
}

/// One texture layer of a material.
#[derive(Clone, Debug)]
pub struct TextureLayer {
    /// The image, its sampler, uv set (`tex_coord`), transform and scale.
    pub slot: TextureSlot,
    pub mode: TexEnvMode,
    pub format: BaseFormat,
    /// The environment colour `Cc` (BLEND) and the constant whose alpha INTERPOLATE may use:
    /// linear RGBA, straight alpha.
    pub constant: Vec4,
    /// Where the image came from (for `texmap info`).
    pub source: Arc<str>,
}

/// One stage: the straight colour `cf` (the previous stage's output) combined with the
/// straight texel `t` of format `format` and the constant `cc` by `mode`, clamped to
/// [0, 1]. `None` for DECAL on a format OpenGL leaves undefined (refused when a scene is
/// loaded).
#[must_use]
pub fn tex_env(mode: TexEnvMode, format: BaseFormat, cf: Vec4, t: Vec4, cc: Vec4) -> Option<Vec4> {
    use BaseFormat as F;
    let (c, a) = (cf.truncate(), cf.w);
    let (ct, at) = format.source(t);
    let lerp = |from: Vec3, to: Vec3, w: Vec3| from * (Vec3::ONE - w) + to * w;
    let (rgb, alpha) = match mode {
        TexEnvMode::Replace => match format {
            F::Alpha => (c, at),
            F::Luminance | F::Rgb => (ct, a),
            F::LuminanceAlpha | F::Rgba | F::Intensity => (ct, at),
        },
        TexEnvMode::Modulate => match format {
            F::Alpha => (c, a * at),
            _ => (c * ct, a * at),
        },
        TexEnvMode::Decal => match format {
            F::Rgb => (ct, a),
            F::Rgba => (lerp(c, ct, Vec3::splat(at)), a),
            _ => return None,
        },
        TexEnvMode::Blend => match format {
            F::Alpha => (c, a * at),
            F::Intensity => (lerp(c, cc.truncate(), ct), a * (1.0 - at) + cc.w * at),
            _ => (lerp(c, cc.truncate(), ct), a * at),
        },
        TexEnvMode::Add => match format {
            F::Alpha => (c, a * at),
            F::Intensity => (c + ct, a + at),
            _ => (c + ct, a * at),
        },
        TexEnvMode::Interpolate { by_constant } => {
            let w = if by_constant { cc.w } else { at };
            (ct * w + c * (1.0 - w), a)
        }
        TexEnvMode::Detail => (c * ct * 2.0, a),
    };
    Some(
        rgb.clamp(Vec3::ZERO, Vec3::ONE)
            .extend(alpha.clamp(0.0, 1.0)),
    )
}

#[cfg(test)]
mod tests;
