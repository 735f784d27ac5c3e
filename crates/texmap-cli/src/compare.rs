//! `texmap compare A.png B.png [--diff out.png] [--mask M.png]`.

use std::path::{Path, PathBuf};

use clap::Args;
use texmap::metrics::compare_rgb8;
use texmap::Error;

use crate::formats::{OutputFormat, Picture};

#[derive(Args)]
pub struct CompareArgs {
    /// First image.
    a: PathBuf,
    /// Second image (same size).
    b: PathBuf,
    /// Write a false-colour difference image here (blue = equal, red = 32 levels or more
    /// apart): an 8-bit PNG, whatever the name, so only `.png`, a name without an extension
    /// or `-` is taken.
    #[arg(long)]
    diff: Option<PathBuf>,
    /// Compare only where this greyscale mask is non-zero.
    #[arg(long)]
    mask: Option<PathBuf>,
    /// Print JSON instead of text.
    #[arg(long)]
    json: bool,
}

fn load_rgb8(path: &Path) -> Result<image::RgbImage, Error> {
    let img = texmap::texture::load::decode_image(path, &texmap::texture::load::Limits::default())?;
    Ok(img.to_rgb8())
}

pub fn run(args: CompareArgs) -> Result<(), Error> {
    // Before anything is read: the difference image is display colour, PNG only.
    if let Some(out) = &args.diff {
        let format = OutputFormat::for_output(out, "--diff", None)?;
        if format != OutputFormat::Png {
            return Err(Error::parameter(format!(
                "--diff {}: the difference image is 8-bit false colour, written as PNG only, \
                 not {}",
                out.display(),
                format.name()
            )));
        }
    }
    let a = load_rgb8(&args.a)?;
    let b = load_rgb8(&args.b)?;
    if a.dimensions() != b.dimensions() {
        return Err(Error::parameter(format!(
            "{}: {}x{} does not match {}: {}x{}",
            args.a.display(),
            a.width(),
            a.height(),
            args.b.display(),
            b.width(),
            b.height()
        )));
    }
    let (w, h) = a.dimensions();
    let mask = match &args.mask {
        Some(p) => {
            let m = texmap::texture::load::decode_image(p, &Default::default())?.to_luma8();
            if m.dimensions() != (w, h) {
                return Err(Error::parameter(format!(
                    "{}: mask size differs from the images",
                    p.display()
                )));
            }
            Some(m.pixels().map(|p| p.0[0] > 0).collect::<Vec<_>>())
        }
        None => None,
    };
    let c = compare_rgb8(
        a.as_raw(),
        b.as_raw(),
        w as usize,
        h as usize,
        mask.as_deref(),
    );
    if args.json {
        crate::output::stdout(&format!(
            "{}\n",
            serde_json::json!({"a": args.a, "b": args.b, "psnr_db": c.psnr_db, "rmse": c.rmse, "ssim": c.ssim, "pixels": c.pixels})
        ))?;
    } else {
        crate::output::stdout(&format!(
            "PSNR {:.3} dB  RMSE {:.4}  SSIM {:.5}  ({} pixels)\n",
            c.psnr_db, c.rmse, c.ssim, c.pixels
        ))?;
    }
    if let Some(out) = &args.diff {
        let mut rgb = Vec::with_capacity((w * h * 3) as usize);
        for (pa, pb) in a.pixels().zip(b.pixels()) {
            let d = (0..3)
                .map(|i| (pa.0[i] as i32 - pb.0[i] as i32).abs())
                .max()
                .unwrap_or(0);
            rgb.extend(false_colour((d as f32 / 32.0).min(1.0)));
        }
        let picture = Picture::Rgb8 {
            width: w,
            height: h,
            rgb: &rgb,
        };
        crate::output::write_image(out, OutputFormat::Png, &picture)?;
    }
    Ok(())
}

/// Blue → cyan → green → yellow → red for t in [0, 1].
fn false_colour(t: f32) -> [u8; 3] {
    let stops = [
        [0.0, 0.0, 0.5],
        [0.0, 0.8, 1.0],
        [0.0, 0.9, 0.0],
        [1.0, 0.9, 0.0],
        [1.0, 0.0, 0.0],
    ];
    let x = t * 4.0;
    let i = (x.floor() as usize).min(3);
    let f = x - i as f32;
    std::array::from_fn(|k| ((stops[i][k] * (1.0 - f) + stops[i + 1][k] * f) * 255.0 + 0.5) as u8)
}
