//! The surface-relief flags of `texmap render`: `--normal-maps`, `--bump-maps`,
//! `--parallax`, `--displacement` with `--displace-level` / `--displace-edge`, laid over the
//! scene's materials; each is refused where the scene has nothing for it to act on. The
//! displacement itself runs here, once per input, after the camera is chosen (an `edge_px`
//! tessellation is measured in the output's pixels).

use clap::{Args, ValueEnum};
use texmap::camera::Camera;
use texmap::scene::displace::{displace_scene, DisplaceOptions, DisplaceView};
use texmap::scene::{Material, Scene};
use texmap::shading::relief::{ParallaxMode, Tessellation, MAX_DISPLACEMENT_LEVEL};
use texmap::shading::MapChannel;
use texmap::shading::TextureSlot;
use texmap::Error;

use super::args::Switch;

/// `--parallax`'s values.
#[derive(Clone, Copy, PartialEq, Eq, Debug, ValueEnum)]
pub(crate) enum ParallaxArg {
    Off,
    Offset,
    Occlusion,
}

/// Flags that switch the surface-relief techniques of a scene's materials.
#[derive(Args, Clone, Default)]
pub struct ReliefArgs {
    /// Normal maps (tangent- and object-space) of the scene's materials [default: on].
    #[arg(long, value_enum, value_name = "on|off")]
    pub(crate) normal_maps: Option<Switch>,
    /// Bump (height) maps of the scene's materials [default: on].
    #[arg(long, value_enum, value_name = "on|off")]
    pub(crate) bump_maps: Option<Switch>,
    /// Parallax mapping of the materials that have it: off, offset (with offset limiting) or
    /// occlusion (parallax occlusion mapping) [default: each material's mode].
    #[arg(long, value_enum, value_name = "off|offset|occlusion")]
    pub(crate) parallax: Option<ParallaxArg>,
    /// Parallax self-shadowing towards the lights, for every material with parallax mapping
    /// [default: each material's `shadows`].
    #[arg(long, value_enum, value_name = "on|off")]
    pub(crate) parallax_shadows: Option<Switch>,
    /// Displacement mapping of the materials that have it (meshes tessellated and moved by
    /// the height map at load) [default: on].
    #[arg(long, value_enum, value_name = "on|off")]
    pub(crate) displacement: Option<Switch>,
    /// Tessellate displaced meshes uniformly: each edge in 2^N segments (replaces the
    /// materials' level or edge_px).
    #[arg(long, value_name = "N", conflicts_with = "displace_edge")]
    pub(crate) displace_level: Option<u32>,
    /// Tessellate displaced meshes until their longest edge spans at most PX output pixels.
    #[arg(long, value_name = "PX")]
    pub(crate) displace_edge: Option<f32>,
}

fn has_channel(scene: &Scene, channels: &[MapChannel]) -> bool {
    scene
        .materials
        .iter()
        .any(|m| m.maps.iter().any(|map| channels.contains(&map.channel)))
}

/// Lays the normal-map, bump and parallax flags over the materials (before the camera).
///
/// # Errors
/// A flag given for a scene without what it switches.
pub(super) fn apply_maps(r: &ReliefArgs, name: &str, scene: &mut Scene) -> Result<(), Error> {
    let switches = [
        (
            "--normal-maps",
            r.normal_maps,
            &[MapChannel::Normal, MapChannel::NormalObject][..],
            "normal map",
        ),
        (
            "--bump-maps",
            r.bump_maps,
            &[MapChannel::Bump][..],
            "bump map",
        ),
    ];
    for (flag, switch, channels, what) in switches {
        let Some(s) = switch else { continue };
        if !has_channel(scene, channels) {
            return Err(Error::parameter(format!(
                "{flag}: no material of {name} has a {what}"
            )));
        }
        if s == Switch::Off {
            for m in &mut scene.materials {
                m.maps.retain(|map| !channels.contains(&map.channel));
            }
        }
    }
    if let Some(p) = r.parallax {
        if !scene.materials.iter().any(|m| m.parallax.is_some()) {
            return Err(Error::parameter(format!(
                "--parallax: no material of {name} has parallax mapping"
            )));
        }
        for m in &mut scene.materials {
            match p {
                ParallaxArg::Off => m.parallax = None,
                ParallaxArg::Offset => {
                    if let Some(x) = m.parallax.as_mut() {
                        x.mode = ParallaxMode::Offset;
                    }
                }
                ParallaxArg::Occlusion => {
                    if let Some(x) = m.parallax.as_mut() {
                        x.mode = ParallaxMode::Occlusion;
                    }
                }
            }
        }
    }
    if let Some(on) = r.parallax_shadows {
        let on = on == Switch::On;
        let parallax: Vec<&mut Material> = scene
            .materials
            .iter_mut()
            .filter(|m| m.parallax.is_some())
            .collect();
        if parallax.is_empty() {
            return Err(Error::parameter(format!(
                "--parallax-shadows: no material of {name} has parallax mapping"
            )));
        }
        if parallax
            .iter()
            .all(|m| m.parallax.as_ref().is_some_and(|p| p.shadows == on))
        {
            return Err(Error::parameter(format!(
                "--parallax-shadows: every parallax material of {name} is already {}",
                if on {
                    "self-shadowed"
                } else {
                    "without self-shadowing"
                }
            )));
        }
        for m in parallax {
            if let Some(p) = m.parallax.as_mut() {
                p.shadows = on;
            }
        }
    }
    let displacement_flags = [
        ("--displacement", r.displacement.is_some()),
        ("--displace-level", r.displace_level.is_some()),
        ("--displace-edge", r.displace_edge.is_some()),
    ];
    let given: Vec<&str> = displacement_flags
        .iter()
        .filter_map(|(f, g)| g.then_some(*f))
        .collect();
    if !given.is_empty() && !scene.materials.iter().any(|m| m.displacement.is_some()) {
        return Err(Error::parameter(format!(
            "{}: no material of {name} has displacement mapping",
            given.join(", ")
        )));
    }
    if r.displacement == Some(Switch::Off)
        && (r.displace_level.is_some() || r.displace_edge.is_some())
    {
        return Err(Error::parameter(
            "--displace-level and --displace-edge need --displacement on",
        ));
    }
    if let Some(l) = r.displace_level {
        if l > MAX_DISPLACEMENT_LEVEL {
            return Err(Error::parameter(format!(
                "--displace-level {l} is more than {MAX_DISPLACEMENT_LEVEL}"
            )));
        }
    }
    if let Some(e) = r.displace_edge {
        if !(e.is_finite() && e >= 0.5) {
            return Err(Error::parameter(format!(
                "--displace-edge {e} must be at least 0.5 pixels"
            )));
        }
    }
    Ok(())
}

/// Tessellates and displaces the meshes whose materials have displacement (unless
/// `--displacement off`), measuring `edge_px` in the `size` frame seen by `camera`.
///
/// # Errors
/// The triangle budget exceeded (one line naming the scene and the count).
pub(super) fn displace(
    r: &ReliefArgs,
    name: &str,
    scene: &mut Scene,
    camera: &Camera,
    size: (u32, u32),
) -> Result<(), Error> {
    if r.displacement == Some(Switch::Off) {
        for m in &mut scene.materials {
            m.displacement = None;
        }
        return Ok(());
    }
    if !scene.materials.iter().any(|m| m.displacement.is_some()) {
        return Ok(());
    }
    let aspect = size.0 as f32 / size.1.max(1) as f32;
    let view = DisplaceView {
        clip_from_world: camera.clip_from_view(aspect) * camera.view_from_world(),
        width: size.0,
        height: size.1,
    };
    let options = DisplaceOptions {
        tessellation: r
            .displace_level
            .map(Tessellation::Level)
            .or(r.displace_edge.map(Tessellation::EdgePixels)),
        max_triangles: 0,
    };
    displace_scene(scene, &options, Some(&view))
        .map(|_| ())
        .map_err(|e| match e {
            Error::Parameter(m) => Error::parameter(format!("{name}: {m}")),
            other => other,
        })
}

/// `texmap info`'s words for a material's parallax and displacement.
pub(crate) fn describe(m: &Material) -> Vec<String> {
    let size = |s: &TextureSlot| format!("{}x{}", s.texture.width(), s.texture.height());
    let mut out = Vec::new();
    if let Some(p) = &m.parallax {
        out.push(format!(
            "parallax {} {} scale {} base {} steps {}..{}{}",
            p.mode.name(),
            size(&p.slot),
            p.scale,
            p.base,
            p.min_steps,
            p.max_steps,
            if p.shadows { ", self-shadowed" } else { "" }
        ));
    }
    if let Some(d) = &m.displacement {
        let t = match d.tessellation {
            Tessellation::Level(l) => format!("level {l}"),
            Tessellation::EdgePixels(e) => format!("edge {e} px"),
        };
        out.push(format!(
            "displacement {} scale {} base {} {t}",
            size(&d.slot),
            d.scale,
            d.base
        ));
    }
    out
}
