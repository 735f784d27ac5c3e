//! Surface relief from a height map beyond bump mapping: parallax mapping (the texture
//! coordinates shifted along the view ray, so the surface seems to have depth) and
//! displacement mapping (the mesh tessellated and its vertices moved). Both read a height map
//! `h ∈ [0, 1]` (red channel, linear) whose surface lies `scale·(h − base)` object units along
//! the normal: `base = 0` raises the relief out of the mesh, `base = 1` carves it in.
//!
//! The renderer's parallax is `render/parallax.rs`; the tessellation and displacement,
//! `scene/displace.rs`.

use super::TextureSlot;

/// How parallax mapping finds the point the view ray sees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParallaxMode {
    /// Parallax mapping with offset limiting (Welsh 2004): one height read, the uv shifted by
    /// `height · V_tangent` (the view vector's part along the surface, not divided by `N·V`,
    /// so grazing views do not shift without bound).
    Offset,
    /// Parallax occlusion mapping: a linear search along the ray through the height layers
    /// (the step count lerped from `max_steps` at grazing views to `min_steps` head-on, by
    /// `|N·V|`), then the intersection refined between the last two steps (secant).
    Occlusion,
}

impl ParallaxMode {
    /// The name used in scene files, on the command line and by `texmap info`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ParallaxMode::Offset => "offset",
            ParallaxMode::Occlusion => "occlusion",
        }
    }
}

/// A material's parallax mapping: its height map and how it is traced.
#[derive(Clone, Debug)]
pub struct Parallax {
    /// The height map (red channel, linear), read through the sampling engine with each
    /// pixel's footprint.
    pub slot: TextureSlot,
    pub mode: ParallaxMode,
    /// Object units of relief for heights 0 → 1.
    pub scale: f32,
    /// The height value at the mesh's surface (0: relief raised, 1: carved in).
    pub base: f32,
    /// Occlusion: the steps head-on and at grazing views.
    pub min_steps: u32,
    pub max_steps: u32,
    /// Self-shadowing: each light's contribution scaled by how much of the height field
    /// stands between the point the view ray meets and the light (a march towards it,
    /// softened by the distance along it; `render/parallax.rs`).
    pub shadows: bool,
}

/// How finely a displaced mesh is tessellated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tessellation {
    /// Every triangle cut into `4^level` (each edge into `2^level` segments).
    Level(u32),
    /// Each mesh's edges cut so the longest projected edge is at most this many pixels (one
    /// segment count per mesh, decided from the camera and the frame's height).
    EdgePixels(f32),
}

/// A material's displacement mapping: the height map moving the vertices of its meshes.
#[derive(Clone, Debug)]
pub struct Displacement {
    /// The height map (red channel, linear).
    pub slot: TextureSlot,
    /// Object units of displacement for heights 0 → 1.
    pub scale: f32,
    /// The height value left in place (0: raised, 1: carved in).
    pub base: f32,
    pub tessellation: Tessellation,
}

/// The most steps a parallax occlusion search may take.
pub const MAX_PARALLAX_STEPS: u32 = 256;

impl Parallax {
    /// Checks the numbers: finite scale, base in [0, 1], `1 ≤ min_steps ≤ max_steps ≤`
    /// [`MAX_PARALLAX_STEPS`].
    ///
    /// # Errors
    /// A message naming the first bad value.
    pub fn validate(&self) -> Result<(), String> {
        check_relief(self.scale, self.base)?;
        if self.min_steps < 1 || self.min_steps > self.max_steps {
            return Err(format!(
                "min_steps {} must be at least 1 and at most max_steps {}",
                self.min_steps, self.max_steps
            ));
        }
        if self.max_steps > MAX_PARALLAX_STEPS {
            return Err(format!(
                "max_steps {} is more than {MAX_PARALLAX_STEPS}",
                self.max_steps
            ));
        }
        Ok(())
    }
}

impl Displacement {
    /// Checks the numbers: finite scale, base in [0, 1], a level of at most
    /// [`MAX_DISPLACEMENT_LEVEL`] or a positive edge length.
    ///
    /// # Errors
    /// A message naming the first bad value.
    pub fn validate(&self) -> Result<(), String> {
        check_relief(self.scale, self.base)?;
        match self.tessellation {
            Tessellation::Level(l) if l > MAX_DISPLACEMENT_LEVEL => {
                Err(format!("level {l} is more than {MAX_DISPLACEMENT_LEVEL}"))
            }
            Tessellation::EdgePixels(e) if !(e.is_finite() && e >= 0.5) => {
                Err(format!("edge_px {e} must be at least 0.5"))
            }
            _ => Ok(()),
        }
    }
}

/// The highest uniform tessellation level (each edge in 2^level segments).
pub const MAX_DISPLACEMENT_LEVEL: u32 = 10;

fn check_relief(scale: f32, base: f32) -> Result<(), String> {
    if !scale.is_finite() {
        return Err(format!("scale {scale} is not finite"));
    }
    if !(0.0..=1.0).contains(&base) {
        return Err(format!("base {base} is outside 0..=1"));
    }
    Ok(())
}
