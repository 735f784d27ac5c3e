//! What the render's image holds and where it goes: the output format (`-o`'s extension or
//! `--format`, chosen before anything is loaded), `--alpha`, and the background it leaves
//! out.
//!
//! Alpha is the frame's: the coverage of the surfaces (fractional on antialiased edges and
//! through blended materials), the volumes' accumulated opacity, and the background's where
//! one is drawn (an environment or the scene's colour is opaque). `--alpha` is for
//! compositing: the background is left out unless `--background` names one, and PNG keeps
//! alpha (RGBA, straight). Without it the background is drawn and PNG is the colour over
//! black (RGB). OpenEXR always holds the frame's RGBA, premultiplied; Radiance HDR holds the
//! colour over black and refuses `--alpha`.

use std::path::Path;

use glam::Vec4;
use texmap::render::Frame;
use texmap::scene::Scene;
use texmap::shading::ibl::Background;
use texmap::Error;

use super::args::{BackgroundArg, RenderArgs};
use crate::formats::{OutputFormat, Picture, Store};

/// The format of `args`' output (`-o`, else the default name's `.png`, or `--format`), and
/// `--alpha` checked against it.
///
/// # Errors
/// [`Error::Parameter`]: an extension texmap does not write, one that contradicts
/// `--format`, or `--alpha` with Radiance HDR.
pub(super) fn output_format(args: &RenderArgs) -> Result<OutputFormat, Error> {
    let format = match &args.output {
        Some(path) => OutputFormat::for_output(path, "-o", args.format)?,
        None => args.format.unwrap_or(OutputFormat::Png),
    };
    let name = || match &args.output {
        Some(p) => format!("{} ({})", format.name(), p.display()),
        None => format.name().to_string(),
    };
    if args.alpha && matches!(format, OutputFormat::Jpeg | OutputFormat::Gif) {
        return Err(Error::parameter(format!(
            "--alpha: {} keeps no alpha channel (write .png, .apng or .exr)",
            name()
        )));
    }
    match args.bit_depth {
        8 => {}
        16 if matches!(format, OutputFormat::Png | OutputFormat::Apng) => {}
        16 => {
            return Err(Error::parameter(format!(
                "--bit-depth 16: {} has 8 bits a channel (16 is for .png and .apng; .exr is \
                 float)",
                name()
            )))
        }
        n => {
            return Err(Error::parameter(format!(
                "--bit-depth {n}: expected 8 or 16"
            )))
        }
    }
    if let Some(q) = args.quality {
        if format != OutputFormat::Jpeg {
            return Err(Error::parameter(format!(
                "--quality: only JPEG has a quality, not {}",
                name()
            )));
        }
        if !(1..=100).contains(&q) {
            return Err(Error::parameter(format!(
                "--quality {q} is outside 1..=100"
            )));
        }
    }
    if let Some(fps) = args.fps {
        if !format.is_animated() {
            return Err(Error::parameter(format!(
                "--fps: {} is not an animation (write .gif or .apng)",
                name()
            )));
        }
        if !(1..=100).contains(&fps) {
            return Err(Error::parameter(format!("--fps {fps} is outside 1..=100")));
        }
    }
    if args.alpha && format == OutputFormat::Hdr {
        return Err(Error::parameter(format!(
            "--alpha: {} has no alpha channel (write .exr or .png)",
            match &args.output {
                Some(p) => format!("Radiance HDR ({})", p.display()),
                None => "Radiance HDR".to_string(),
            }
        )));
    }
    Ok(format)
}

/// How every output of a render is written.
pub(crate) struct ImageOut {
    pub format: OutputFormat,
    pub store: Store,
}

impl ImageOut {
    /// The outputs of `args` in `format` (from [`output_format`]).
    pub fn new(args: &RenderArgs, format: OutputFormat) -> Self {
        let store = Store {
            alpha: args.alpha,
            sixteen: args.bit_depth == 16,
            quality: args.quality.unwrap_or(Store::SRGB.quality),
        };
        ImageOut { format, store }
    }

    /// `frame` as the picture the format stores.
    pub fn picture<'a>(&self, frame: &'a Frame) -> Picture<'a> {
        Picture::Linear(frame, self.store)
    }

    /// Writes `frame` at `path` (atomically: see `output.rs`).
    pub fn write(&self, path: &Path, frame: &Frame) -> Result<(), Error> {
        crate::output::write_image(path, self.format, &self.picture(frame))
    }
}

/// `--background` (or `--alpha`'s default, none) laid over the scene: with an environment
/// its background becomes the one named; without one, `none` clears the scene's colour to
/// transparent black and `color` keeps it (which only `--alpha` would have left out).
///
/// # Errors
/// [`Error::Parameter`] naming the flag where it changes nothing or has nothing to show:
/// `env` without an environment; without one, `color` but with `--alpha` and a colour that
/// is not transparent black, `none` on a background already transparent; and a scene left with nothing to draw (an environment alone whose
/// background is left out).
pub(super) fn apply_background(
    args: &RenderArgs,
    scene: &mut Scene,
    has_volumes: bool,
) -> Result<(), Error> {
    let name = args.scene.as_deref().unwrap_or("builtin:demo");
    let Some(choice) = args
        .background
        .or(args.alpha.then_some(BackgroundArg::None))
    else {
        return Ok(());
    };
    let flag = if args.background.is_some() {
        "--background none"
    } else {
        "--alpha"
    };
    match (scene.environment.as_mut(), choice) {
        (Some(env), choice) => {
            env.background = match choice {
                BackgroundArg::Env => Background::Environment,
                BackgroundArg::Color => Background::Color,
                BackgroundArg::None => Background::None,
            };
        }
        (None, BackgroundArg::Env) => {
            return Err(Error::parameter(format!(
                "--background env: {name} has no environment (add --env FILE)"
            )));
        }
        (None, BackgroundArg::Color) if !args.alpha => {
            return Err(Error::parameter(format!(
                "--background color: {name} has no environment; its colour is already the \
                 background (only --alpha leaves it out)"
            )));
        }
        (None, BackgroundArg::Color) if scene.background == Vec4::ZERO => {
            return Err(Error::parameter(format!(
                "--background color: {name}'s background colour is transparent black, what \
                 --alpha leaves"
            )));
        }
        (None, BackgroundArg::Color) => {}
        (None, BackgroundArg::None) if scene.background == Vec4::ZERO => {
            // --alpha alone: nothing to clear, alpha is already the coverage.
            if args.background.is_some() {
                return Err(Error::parameter(format!(
                    "--background none: {name}'s background is already transparent"
                )));
            }
        }
        (None, BackgroundArg::None) => scene.background = Vec4::ZERO,
    }
    let env_only = scene.environment.is_some() && !has_volumes && !scene.any_triangle_has_area();
    if env_only && scene.environment.as_ref().map(|e| e.background) == Some(Background::None) {
        return Err(Error::parameter(format!(
            "{flag}: {name} has nothing to draw but its environment's background, which it \
             leaves out"
        )));
    }
    Ok(())
}
