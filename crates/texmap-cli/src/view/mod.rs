//! `texmap view SCENE [render flags]`: a window drawing the CPU renderer live, with an orbit
//! camera, keys that switch each technique, an A/B split and screenshots.
//!
//! The scene is loaded and prepared by `texmap render`'s own code (`render::prepare`, with
//! the same flags and checks), so the first frame is `texmap render`'s image and `F12`
//! writes it through the same PNG writer. The camera is `camera.rs`, what the keys change
//! `look.rs`, the pixels drawn into the window `overlay.rs`, the event loop `window.rs`.
//!
//! The window is minifb's, built with its X11 backend only: it opens on `DISPLAY` (an X
//! server, XWayland or Xvfb). Without one the command says so in one line and exits 1.

mod camera;
mod look;
mod overlay;
mod window;

use std::path::Path;

use clap::Args;
use texmap::Error;

use crate::formats::OutputFormat;
use crate::render::{limits, RenderArgs, Switch};

/// The keys, as `--help` and the window's `h` show them.
pub const KEYS: &str = "\
Mouse: left drag orbits; right/middle (or shift+left) drag pans; wheel zooms.
Keys:
  arrows      orbit                  + / -     zoom in / out
  r, Home     reset the view         o         overlay on/off
  f           texture filter         s         shading (flat/gouraud/phong)
  i           interpolation          v         visibility (zbuffer/depth-sort)
  m           antialiasing (off/msaa 4/ssaa 2)
  e           environment on/off     h         this help
  1 shadows   2 normal maps   3 bump maps   4 parallax   5 displacement
  6 layers    7 light maps    8 toon        9 projectors 0 reflections
  b           A/B split (drag the divider); keys act on the side under
              the mouse
  F12         screenshot texmap-SCENE-N.png (no overlay: render's image)
  Escape      quit
A part the scene does not have is shown as n/a in the overlay.";

/// `texmap view`'s flags: the render's (output and batch flags aside) and the preview.
#[derive(Args)]
pub struct ViewArgs {
    #[command(flatten)]
    pub render: RenderArgs,
    /// Render at half the size in each direction while the camera moves, then refine
    /// [default: on].
    #[arg(long, value_enum, value_name = "on|off")]
    pub preview: Option<Switch>,
}

/// Refuses the render flags that write files or make batches: the viewer shows one scene.
fn check_flags(args: &RenderArgs) -> Result<(), Error> {
    if args.inputs.len() > 1 {
        return Err(Error::parameter(format!(
            "view shows one scene, not {} (texmap render takes a batch)",
            args.inputs.len()
        )));
    }
    let refused: Vec<&str> = [
        ("--list", args.list.is_some()),
        ("--alpha", args.alpha),
        ("--frames", args.frames != 1),
        ("--frame-range", args.frame_range.is_some()),
        ("--shard", args.shard.is_some()),
        ("--shard-count", args.shard_count.is_some()),
        ("--discard", args.discard),
    ]
    .into_iter()
    .chain(args.output_options())
    .filter_map(|(f, given)| given.then_some(f))
    .collect();
    if !refused.is_empty() {
        return Err(Error::parameter(format!(
            "{}: texmap view writes no image but F12's screenshots (use texmap render)",
            refused.join(", ")
        )));
    }
    Ok(())
}

/// The X11 display the window opens on.
///
/// # Errors
/// [`Error::Parameter`]: `DISPLAY` unset or empty.
fn display() -> Result<String, Error> {
    match std::env::var("DISPLAY") {
        Ok(d) if !d.is_empty() => Ok(d),
        _ => Err(Error::parameter(
            "view: no display (DISPLAY is not set): the viewer opens an X11 window (run it \
             in a desktop session, or under Xvfb)",
        )),
    }
}

/// `texmap view`.
pub fn run(args: ViewArgs) -> Result<(), Error> {
    let mut render = args.render;
    check_flags(&render)?;
    let name = render
        .inputs
        .first()
        .cloned()
        .unwrap_or_else(|| "builtin:demo".to_string());
    if Path::new(&name).is_dir() {
        return Err(Error::parameter(format!(
            "{name}: is a folder; view shows one scene (texmap render takes a folder)"
        )));
    }
    render.scene = Some(name);
    let threads = limits::frames_and_threads(1, render.threads)?;
    let display = display()?;
    let common = crate::render::Common::new(&render, OutputFormat::Png, threads)?;
    let preview = args.preview != Some(Switch::Off);
    window::run(&render, &common, &display, preview)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_keys_help_fits_a_640_pixel_window_and_names_every_key() {
        for line in KEYS.lines() {
            assert!(overlay::text_width(line) + 2 <= 640, "{line}");
        }
        for (c, _, _) in look::PARTS {
            assert!(KEYS.contains(&format!("{c} ")), "{c}");
        }
        for key in ["F12", "Escape", "Home", "A/B"] {
            assert!(KEYS.contains(key), "{key}");
        }
    }
}
