//! The `texmap` command line: it parses arguments and calls the library, nothing more.

mod animation;
mod bake;
mod compare;
mod convert;
mod detail_info;
mod field;
mod formats;
mod info;
mod manifest;
mod output;
mod progress;
mod render;
mod sdf;
mod section;
mod signals;
mod view;
mod volume;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// texmap: a texture-mapping renderer on the CPU.
#[derive(Parser)]
#[command(name = "texmap", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene (default: the embedded demo) to an image.
    Render(Box<render::RenderArgs>),
    /// Open a window drawing a scene live (the render's scenes and flags): orbit, pan, zoom,
    /// switch each technique, compare two settings side by side, take screenshots.
    #[command(after_help = view::KEYS)]
    View(Box<view::ViewArgs>),
    /// Write a procedural texture to an image (on a plane, or unwrapped from a cylinder or sphere).
    Bake(bake::BakeArgs),
    /// Compare two images: PSNR, RMSE and SSIM, and optionally a false-colour difference image.
    Compare(compare::CompareArgs),
    /// List what a model, scene or texture holds: meshes, triangles, materials, textures, cameras.
    Info(info::InfoArgs),
    /// Write one image of a texture (PNG, JPEG, TGA, BMP, HDR, EXR, DDS, KTX, KTX2) as PNG or EXR.
    Convert(convert::ConvertArgs),
    /// Check a batch's manifests: every output's bytes and SHA-256, no frame missing or twice.
    Manifest(manifest::verify::ManifestArgs),
    /// Build a signed distance field (negative inside) from a mesh or a thresholded scan, as
    /// NIfTI or NRRD.
    Sdf(sdf::SdfArgs),
}

fn main() -> ExitCode {
    // Before any thread starts: the allocator's thresholds (render/heap.rs).
    render::set_up_allocator();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render::run(*args).map(Some),
        Command::View(args) => view::run(*args).map(|()| None),
        Command::Manifest(args) => manifest::verify::run(args).map(|ok| {
            Some(if ok {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            })
        }),
        Command::Compare(args) => compare::run(args).map(|()| None),
        Command::Bake(args) => bake::run(args).map(|()| None),
        Command::Info(args) => info::run(args).map(|()| None),
        Command::Convert(args) => convert::run(args).map(|()| None),
        Command::Sdf(args) => sdf::run(args).map(|()| None),
    };
    match result {
        Ok(code) => code.unwrap_or(ExitCode::SUCCESS),
        Err(e) => {
            crate::output::stderr_line(&format!("texmap: {e}"));
            ExitCode::FAILURE
        }
    }
}
