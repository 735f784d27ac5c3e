//! `texmap bake PATTERN`: a procedural texture written to an image, on a plane or through the
//! inverse of a cylindrical or spherical projection (the texture a generated mapping needs to
//! show the solid pattern on the unit cylinder or sphere).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use glam::{DVec3, Vec3};
use rayon::prelude::*;
use texmap::texture::procedural::Solid;
use texmap::Error;

#[derive(Args)]
pub struct BakeArgs {
    /// marble | wood | granite | clouds | checker3d | bricks.
    pattern: String,
    /// Output PNG.
    #[arg(short = 'o', long = "output")]
    output: PathBuf,
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
    let (w, h) = args.size;
    let colors: [Vec3; 2] = solid.default_colors();
    let rows: Vec<Vec<u8>> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut row = Vec::with_capacity(w as usize * 3);
            for x in 0..w {
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
                    let g = texmap::color::linear_to_unorm8(solid.value(p, extent) as f32);
                    row.extend([g, g, g]);
                } else {
                    let c = solid.color(p, extent, colors);
                    row.extend([c.x, c.y, c.z].map(texmap::color::linear_to_srgb8));
                }
            }
            row
        })
        .collect();
    crate::output::write_png_rgb8(&args.output, w, h, &rows.concat())?;
    crate::output::stderr_line(&format!(
        "wrote {} ({w}x{h}, {})",
        args.output.display(),
        args.pattern
    ));
    Ok(())
}
