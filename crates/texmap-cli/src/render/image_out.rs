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

use std::path::PathBuf;

use glam::Vec4;
use texmap::render::Frame;
use texmap::scene::Scene;
use texmap::shading::ibl::Background;
use texmap::Error;

use super::args::{BackgroundArg, RenderArgs};
use crate::formats::{OutputFormat, Picture, Png8};

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

/// Where and how every frame of a render is written.
pub(super) struct ImageOut {
    /// `-o`, or `texmap-SCENE.EXT`; `{frame}` in it is the frame number.
    pub path: PathBuf,
    pub format: OutputFormat,
    png: Png8,
}

impl ImageOut {
    /// The output of `args` in `format` (from [`output_format`]); `short` is the default
    /// name's stem.
    pub fn new(args: &RenderArgs, format: OutputFormat, short: &str) -> Self {
        let path = args
            .output
            .clone()
            .unwrap_or_else(|| PathBuf::from(format!("texmap-{short}.{}", format.extension())));
        let png = if args.alpha {
            Png8::SrgbAlpha
        } else {
            Png8::Srgb
        };
        ImageOut { path, format, png }
    }

    /// True when the name writes every frame (`{frame}`).
    pub fn per_frame(&self) -> bool {
        self.path.to_string_lossy().contains("{frame}")
    }

    /// Writes `frame`, number `k` where the name has `{frame}`.
    pub fn write(&self, frame: &Frame, k: u32) -> Result<(), Error> {
        let path = if self.per_frame() {
            PathBuf::from(
                self.path
                    .to_string_lossy()
                    .replace("{frame}", &format!("{k:04}")),
            )
        } else {
            self.path.clone()
        };
        crate::output::write_image(&path, self.format, &Picture::Linear(frame, self.png))
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
