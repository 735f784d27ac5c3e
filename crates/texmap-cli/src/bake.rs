//! `texmap bake PATTERN`: a procedural texture written to an image, on a plane or through the
//! inverse of a cylindrical or spherical projection (the texture a generated mapping needs to
//! show the solid pattern on the unit cylinder or sphere).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use glam::{DVec3, Vec3};
use rayon::prelude::*;
use texmap::frame::Frame;
use texmap::texture::procedural::Solid;
use texmap::Error;

use crate::formats::{OutputFormat, Picture, Store};

#[derive(Args)]
pub struct BakeArgs {
    /// marble | wood | granite | clouds | checker3d | bricks.
    pattern: String,
    /// Output image, its format from the extension: `.png` (8-bit sRGB; with --gray the
    /// values themselves), `.exr` (32-bit float, linear) or `.hdr` (Radiance, linear); `-` is
    /// stdout (PNG unless --format).
    #[arg(short = 'o', long = "output")]
    output: PathBuf,
    /// The output's format where its name does not say (`-`, a device, no extension).
    #[arg(long, value_enum)]
    format: Option<OutputFormat>,
    /// Image size, WxH.
    #[arg(long, default_value = "512x512", value_parser = crate::render::parse_size)]
    size: (u32, u32),
    /// Where the texture lives: a plane (z = --depth), or the unit cylinder or sphere (radius ½).
    #[arg(long, value_enum, default_value = "planar")]
    projection: BakeProjection,
    /// z of the plane for --projection planar.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    depth: f64,
    /// Object units per image side for --projection planar.
    #[arg(long, default_value_t = 1.0)]
    extent: f64,
    /// Write the pattern's value in [0, 1] as linear grey (for roughness or height maps).
    #[arg(long)]
    gray: bool,
    /// Leave the pattern unfiltered (all octaves; shows the aliasing the filter removes).
    #[arg(long)]
    no_antialias: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum BakeProjection {
    Planar,
    Cylindrical,
    Spherical,
}

impl BakeArgs {
    /// The object-space point behind texel centre `(u, v)` (glTF v, down the image).
    fn point(&self, u: f64, v: f64) -> DVec3 {
        use std::f64::consts::{PI, TAU};
        match self.projection {
            BakeProjection::Planar => {
                DVec3::new((u - 0.5) * self.extent, (0.5 - v) * self.extent, self.depth)
            }
            // Inverse of u = −θ/2π (mod 1): θ = −2πu; lecture v = y + ½, stored flipped.
            BakeProjection::Cylindrical => {
                let theta = -TAU * u;
                DVec3::new(0.5 * theta.cos(), 0.5 - v, 0.5 * theta.sin())
            }
            BakeProjection::Spherical => {
                let (theta, lat) = (-TAU * u, (0.5 - v) * PI);
                DVec3::new(lat.cos() * theta.cos(), lat.sin(), lat.cos() * theta.sin()) * 0.5
            }
        }
    }
}

pub fn run(args: BakeArgs) -> Result<(), Error> {
    let solid = Solid::named(&args.pattern).ok_or_else(|| {
        Error::parameter(format!(
            "{}: unknown pattern (marble, wood, granite, clouds, checker3d, bricks)",
            args.pattern
        ))
    })?;
    if args.extent.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
        || !args.extent.is_finite()
        || !args.depth.is_finite()
    {
        return Err(Error::parameter(
            "--extent must be positive and --depth finite",
        ));
    }
    let format = OutputFormat::for_output(&args.output, "-o", args.format)?;
    if !matches!(
        format,
        OutputFormat::Png | OutputFormat::Exr | OutputFormat::Hdr
    ) {
        return Err(Error::parameter(format!(
            "-o {}: texmap bake writes .png, .exr or .hdr, not {}",
            args.output.display(),
            format.name()
        )));
    }
    let (w, h) = args.size;
    // PNG rows are encoded as they are made (3 bytes a texel); the float formats hold the
    // linear texels (16 bytes) and what their encoder holds.
    let pixels = u64::from(w) * u64::from(h);
    let need = match format {
        OutputFormat::Png => pixels * 3,
        f => pixels * (16 + f.buffer_bytes_per_pixel()),
    };
    if need > texmap::files::DEFAULT_MAX_BYTES {
        return Err(Error::parameter(format!(
            "--size {w}x{h} as {} needs {} MiB, above the {} MiB budget",
            format.name(),
            need >> 20,
            texmap::files::DEFAULT_MAX_BYTES >> 20
        )));
    }
    let colors: [Vec3; 2] = solid.default_colors();
    // The linear value at texel (x, y).
    let texel = |x: u32, y: u32| -> Vec3 {
        let (u, v) = ((x as f64 + 0.5) / w as f64, (y as f64 + 0.5) / h as f64);
        let p = args.point(u, v);
        // Footprint: the distance to the neighbouring texel centres in object space.
        let extent = if args.no_antialias {
            DVec3::ZERO
        } else {
            let du = args.point(u + 1.0 / w as f64, v) - p;
            let dv = args.point(u, v + 1.0 / h as f64) - p;
            du.abs() + dv.abs()
        };
        if args.gray {
            Vec3::splat(solid.value(p, extent) as f32)
        } else {
            solid.color(p, extent, colors)
        }
    };
    if format == OutputFormat::Png {
        // Grey values are data (a roughness or height map): stored without sRGB.
        let encode = if args.gray {
            texmap::color::linear_to_unorm8
        } else {
            texmap::color::linear_to_srgb8
        };
        let mut rgb = vec![0u8; w as usize * h as usize * 3];
        rgb.par_chunks_mut(w as usize * 3)
            .enumerate()
            .for_each(|(y, row)| {
                for (x, px) in row.chunks_exact_mut(3).enumerate() {
                    let c = texel(x as u32, y as u32);
                    px.copy_from_slice(&[c.x, c.y, c.z].map(encode));
                }
            });
        let picture = Picture::Rgb8 {
            width: w,
            height: h,
            rgb: &rgb,
        };
        crate::output::write_image(&args.output, format, &picture)?;
    } else {
        let mut color = texmap::frame::Pixels::zeroed(w as usize * h as usize);
        color
            .par_chunks_mut(w as usize)
            .enumerate()
            .for_each(|(y, row)| {
                for (x, c) in row.iter_mut().enumerate() {
                    *c = texel(x as u32, y as u32).extend(1.0);
                }
            });
        let frame = Frame {
            width: w,
            height: h,
            color,
            ..Frame::default()
        };
        crate::output::write_image(&args.output, format, &Picture::Linear(&frame, Store::SRGB))?;
    }
    crate::output::stderr_line(&format!(
        "wrote {} ({w}x{h}, {})",
        args.output.display(),
        args.pattern
    ));
    Ok(())
}
