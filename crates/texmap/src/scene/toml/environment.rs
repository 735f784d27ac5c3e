//! `[environment]` → [`Environment`]: the map (an image whose layout `kind` names or its
//! proportions tell, or a folder of six faces; relative to the scene file), its rotation about
//! +y, intensity, background, whether it lights by IBL and is reflected, and its filter.
//! With [`LoadOptions::environment_image`] off (the command line's `--env`, which replaces the
//! map) the image is not read and a black placeholder stands in.

use std::path::Path;

use glam::Vec4;

use super::sampler::parse_filter;
use super::spec::EnvironmentSpec;
use crate::scene::asset::LoadOptions;
use crate::shading::ibl::{Background, Environment};
use crate::texture::environment::{load_environment, EnvironmentKind, EnvironmentMap};
use crate::texture::{Texture2D, TextureOptions};
use crate::{Error, Result};

/// The environment an `[environment]` table describes. `Error::Parameter` messages are the
/// table's problem, for the caller to prefix; the image's own errors name the image.
pub(super) fn environment(
    dir: &Path,
    e: &EnvironmentSpec,
    options: &LoadOptions,
) -> Result<Environment> {
    let kind = e
        .kind
        .as_deref()
        .map(|k| {
            EnvironmentKind::parse(k).map_err(|u| Error::parameter(format!("kind {k:?}: {u}")))
        })
        .transpose()?;
    let background = match e.background.as_deref() {
        None => Background::Environment,
        Some(b) => Background::parse(b).ok_or_else(|| {
            Error::parameter(format!(
                "background {b:?}: expected one of: {}",
                Background::SPELLINGS
            ))
        })?,
    };
    if !e.rotate.is_finite() {
        return Err(Error::parameter(format!(
            "rotate {} is not finite",
            e.rotate
        )));
    }
    if !(e.intensity.is_finite() && e.intensity >= 0.0) {
        return Err(Error::parameter(format!(
            "intensity {} must be finite and ≥ 0",
            e.intensity
        )));
    }
    let path = dir.join(&e.file);
    let map = if options.environment_image {
        load_environment(&path, kind, &options.limits)?
    } else {
        let black = Texture2D::from_fn(2, 1, TextureOptions::default(), |_, _| Vec4::W)?;
        EnvironmentMap::Equirect(black)
    };
    let mut env = Environment::new(map, path.display().to_string())
        .with_rotation_deg(e.rotate)
        .with_intensity(e.intensity)
        .with_background(background)
        .with_ibl(e.ibl)
        .with_reflections(e.reflections);
    if let Some(f) = &e.filter {
        let sampler = env.sampler.with_filter(parse_filter("filter", f)?);
        env = env.with_sampler(sampler);
    }
    Ok(env)
}
