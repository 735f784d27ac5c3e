//! The surface-detail switches of `texmap render`: `--layers`, `--light-maps` and `--toon`
//! lay over the scene's materials. Each is refused, naming the scene, where it would change
//! nothing: `--layers` and `--light-maps` without a material that has them, `--toon off`
//! without a toon material, `--toon on` without a lit surface.

use texmap::scene::Scene;
use texmap::shading::toon::Toon;
use texmap::shading::{MapChannel, Material};
use texmap::Error;

use super::args::{RenderArgs, Switch};

/// The bands `--toon on` gives a material without its own toon table.
const DEFAULT_BANDS: u32 = 3;

/// Applies the switches to `scene` (its drawn materials), or refuses one that does nothing.
pub(super) fn apply(args: &RenderArgs, scene: &mut Scene) -> Result<(), Error> {
    let name = args.scene.as_deref().unwrap_or("builtin:demo");
    let used: Vec<usize> = {
        let mut v: Vec<usize> = scene.meshes.iter().map(|m| m.material).collect();
        v.sort_unstable();
        v.dedup();
        v.retain(|&i| i < scene.materials.len());
        v
    };
    let any =
        |scene: &Scene, f: &dyn Fn(&Material) -> bool| used.iter().any(|&i| f(&scene.materials[i]));
    if let Some(s) = args.layers {
        if !any(scene, &|m| !m.layers.is_empty()) {
            return Err(Error::parameter(format!(
                "--layers: no material of {name} has texture layers"
            )));
        }
        if s == Switch::Off {
            for &i in &used {
                scene.materials[i].layers.clear();
            }
        }
    }
    if let Some(s) = args.light_maps {
        if !any(scene, &|m| m.map(MapChannel::Light).is_some()) {
            return Err(Error::parameter(format!(
                "--light-maps: no material of {name} has a light map"
            )));
        }
        if s == Switch::Off {
            for &i in &used {
                scene.materials[i]
                    .maps
                    .retain(|m| m.channel != MapChannel::Light);
            }
        }
    }
    match args.toon {
        None => {}
        Some(Switch::Off) => {
            if !any(scene, &|m| m.toon.is_some()) {
                return Err(Error::parameter(format!(
                    "--toon off: no material of {name} is toon-shaded"
                )));
            }
            for &i in &used {
                scene.materials[i].toon = None;
            }
        }
        Some(Switch::On) => {
            if args.unlit || !any(scene, &|m| !m.unlit) {
                return Err(Error::parameter(format!(
                    "--toon on: {name} has no lit surface to shade"
                )));
            }
            for &i in &used {
                let m = &mut scene.materials[i];
                if !m.unlit && m.toon.is_none() {
                    m.toon = Some(Toon::bands(DEFAULT_BANDS, None));
                }
            }
        }
    }
    Ok(())
}
