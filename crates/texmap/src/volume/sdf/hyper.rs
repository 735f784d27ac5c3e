//! Hypertexture (Perlin & Hoffert 1989; Miller & Jones §6): a soft region of a given
//! thickness around a distance field's surface whose density is a function of the distance,
//! modulated by noise or turbulence and shaped by Perlin's bias and gain.
//!
//! The density at a point `p` whose (possibly melted) distance to the surface is `d`:
//! - `h = d / T` is the height in the shell (`T` = `thickness` × the object's size);
//! - `N` is fBm or turbulence at `frequency ×` the texture-space point (drifting along the
//!   screen's up by `rise × time`, squeezed along it by `stretch`), mapped to `[0, 1]`; with
//!   `strands` it is read at the nearest surface point `p − d·∇d`, constant along the
//!   normal, so it makes hairs;
//! - `u = (amplitude·N − h) / softness`: the material reaches `amplitude·N` shells out;
//! - `D = gain(g, bias(b, clamp(u, 0, 1)))`, extinction `opacity · D / T` per world unit.
//!
//! With `amplitude` 0 there is no material outside the surface (`u ≤ 0` there), and the
//! surface itself (the core) is drawn as [`super::SurfaceLook`] says: the plain surface.
//! `melt` moves the field down the screen by `melt × time ×` the height above the box's
//! bottom (in object sizes) × (1 + ½·noise): the object sags and drips as `time` runs from 0
//! to 1; `core_displacement` moves the core surface out by that many shells × noise.

use glam::Vec3;

use crate::texture::procedural::perlin::{bias, gain};
use crate::{Error, Result};

/// Which noise modulates the density.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoiseKind {
    /// fBm, mapped from about `[−1, 1]` to `[0, 1]`.
    Fbm,
    /// Perlin's turbulence (sum of |noise|), in about `[0, 1]`.
    Turbulence,
}

/// A hypertexture's parameters (see the module's rules for what each does).
#[derive(Clone, Debug, PartialEq)]
pub struct Hypertexture {
    /// The preset it started from (for listings).
    pub preset: String,
    /// Shell thickness `T`, a fraction of the object's size (its field box's largest side).
    pub thickness: f32,
    /// How far the material reaches, in shells, at noise 1 (0: the plain surface).
    pub amplitude: f32,
    /// Noise frequency per object size.
    pub frequency: f32,
    /// Noise octaves (fractional: the last fades in).
    pub octaves: f32,
    pub noise: NoiseKind,
    /// Noise read at the nearest surface point (hair along the normal).
    pub strands: bool,
    /// Width of the density ramp, in shells.
    pub softness: f32,
    /// Perlin's bias of the density (½: none).
    pub bias: f32,
    /// Perlin's gain of the density (½: none).
    pub gain: f32,
    /// Optical depth across one shell at density 1.
    pub opacity: f32,
    /// Colour deep in the material (density ramp 1), linear RGB.
    pub inner: Vec3,
    /// Colour at the material's fringe (ramp 0).
    pub outer: Vec3,
    /// 0: the material is lit (the volume shading); above 0 it glows, colour × emission.
    pub emission: f32,
    /// Self-shadowing towards each scene light (lit material only).
    pub shadows: bool,
    /// Noise drift up the screen per unit of time, in noise periods.
    pub rise: f32,
    /// Noise squeezed along the screen's up by this factor (flames: above 1).
    pub stretch: f32,
    /// Sag per unit of time (see the module's rules).
    pub melt: f32,
    /// The core surface pushed out by this many shells × noise.
    pub core_displacement: f32,
    /// Draw the object's surface under the material.
    pub core: bool,
    /// Sample distance inside the shell, in shells.
    pub step: f32,
    /// The opacity from which the rest of a ray's material is extrapolated (the last sample
    /// repeated to the early stop, when that is at most 12 steps); 1 (`off`): never, every
    /// sample marched, for reference renders.
    pub tail: f32,
    /// The opacity from which each sample stands for two steps (every second grid point
    /// marched, its opacity `1 − (1 − a)²`); 1 (`off`): never, for reference renders.
    pub wide: f32,
    /// Animation time, usually 0 to 1 over the frames.
    pub time: f32,
}

/// The preset names.
pub const PRESETS: [&str; 4] = ["fur", "fire", "smoke", "melt"];

/// The keys [`Hypertexture::set`] takes.
pub const KEYS: [&str; 23] = [
    "thickness",
    "amplitude",
    "frequency",
    "octaves",
    "noise",
    "strands",
    "softness",
    "bias",
    "gain",
    "opacity",
    "inner",
    "outer",
    "emission",
    "shadows",
    "rise",
    "stretch",
    "melt",
    "core_displacement",
    "core",
    "step",
    "tail",
    "wide",
    "time",
];

impl Hypertexture {
    /// A preset: `fur`, `fire`, `smoke` or `melt`.
    #[must_use]
    pub fn preset(name: &str) -> Option<Hypertexture> {
        let base = Hypertexture {
            preset: name.to_string(),
            thickness: 0.05,
            amplitude: 1.0,
            frequency: 8.0,
            octaves: 3.0,
            noise: NoiseKind::Fbm,
            strands: false,
            softness: 0.3,
            bias: 0.5,
            gain: 0.5,
            opacity: 8.0,
            inner: Vec3::splat(0.8),
            outer: Vec3::splat(0.8),
            emission: 0.0,
            shadows: false,
            rise: 0.0,
            stretch: 1.0,
            melt: 0.0,
            core_displacement: 0.0,
            core: true,
            step: 0.08,
            tail: 0.95,
            wide: 0.7,
            time: 0.0,
        };
        Some(match name {
            "fur" => Hypertexture {
                thickness: 0.035,
                amplitude: 1.0,
                frequency: 90.0,
                octaves: 1.0,
                noise: NoiseKind::Fbm,
                strands: true,
                softness: 0.15,
                bias: 0.7,
                gain: 0.7,
                opacity: 30.0,
                inner: Vec3::new(0.12, 0.07, 0.03),
                outer: Vec3::new(0.75, 0.55, 0.32),
                step: 0.06,
                ..base
            },
            "fire" => Hypertexture {
                thickness: 0.12,
                amplitude: 1.0,
                frequency: 7.0,
                octaves: 3.0,
                noise: NoiseKind::Turbulence,
                softness: 0.6,
                bias: 0.35,
                gain: 0.6,
                opacity: 3.0,
                inner: Vec3::new(1.0, 0.78, 0.25),
                outer: Vec3::new(0.7, 0.08, 0.0),
                emission: 2.0,
                rise: 3.0,
                stretch: 0.45,
                core: true,
                step: 0.15,
                ..base
            },
            "smoke" => Hypertexture {
                thickness: 0.15,
                amplitude: 1.0,
                frequency: 4.0,
                octaves: 3.0,
                noise: NoiseKind::Fbm,
                softness: 0.8,
                bias: 0.4,
                gain: 0.5,
                opacity: 2.5,
                inner: Vec3::splat(0.75),
                outer: Vec3::splat(0.55),
                shadows: true,
                rise: 1.0,
                core: false,
                step: 0.15,
                ..base
            },
            "melt" => Hypertexture {
                thickness: 0.1,
                amplitude: 0.0,
                frequency: 6.0,
                octaves: 2.0,
                noise: NoiseKind::Fbm,
                opacity: 0.0,
                melt: 0.6,
                core_displacement: 0.3,
                time: 0.5,
                step: 0.08,
                ..base
            },
            _ => return None,
        })
    }

    /// Sets one parameter from text (`--ht key=value`, a TOML key): numbers, `true`/`false`,
    /// `fbm`/`turbulence`, colours `r,g,b`; `tail` and `wide` also take `off` (1: never).
    ///
    /// # Errors
    /// [`Error::Parameter`] naming the key for an unknown key or a bad value.
    pub fn set(&mut self, key: &str, value: &str) -> Result<()> {
        let num = || -> Result<f32> {
            value
                .trim()
                .parse::<f32>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    Error::parameter(format!("hypertexture {key} = {value:?} is not a number"))
                })
        };
        let flag = || -> Result<bool> {
            match value.trim() {
                "true" | "on" | "1" => Ok(true),
                "false" | "off" | "0" => Ok(false),
                _ => Err(Error::parameter(format!(
                    "hypertexture {key} = {value:?} is not true or false"
                ))),
            }
        };
        let color = || -> Result<Vec3> {
            let v: Vec<f32> = value
                .split(',')
                .filter_map(|c| c.trim().parse().ok())
                .collect();
            match v[..] {
                [r, g, b] if [r, g, b].iter().all(|c| c.is_finite() && *c >= 0.0) => {
                    Ok(Vec3::new(r, g, b))
                }
                _ => Err(Error::parameter(format!(
                    "hypertexture {key} = {value:?} is not a colour r,g,b"
                ))),
            }
        };
        match key {
            "thickness" => self.thickness = num()?,
            "amplitude" => self.amplitude = num()?,
            "frequency" => self.frequency = num()?,
            "octaves" => self.octaves = num()?,
            "noise" => {
                self.noise = match value.trim() {
                    "fbm" => NoiseKind::Fbm,
                    "turbulence" => NoiseKind::Turbulence,
                    _ => {
                        return Err(Error::parameter(format!(
                            "hypertexture noise = {value:?} is not fbm or turbulence"
                        )))
                    }
                }
            }
            "strands" => self.strands = flag()?,
            "softness" => self.softness = num()?,
            "bias" => self.bias = num()?,
            "gain" => self.gain = num()?,
            "opacity" => self.opacity = num()?,
            "inner" => self.inner = color()?,
            "outer" => self.outer = color()?,
            "emission" => self.emission = num()?,
            "shadows" => self.shadows = flag()?,
            "rise" => self.rise = num()?,
            "stretch" => self.stretch = num()?,
            "melt" => self.melt = num()?,
            "core_displacement" => self.core_displacement = num()?,
            "core" => self.core = flag()?,
            "step" => self.step = num()?,
            "tail" => {
                self.tail = match value.trim() {
                    "off" | "false" => 1.0,
                    _ => num()?,
                }
            }
            "wide" => {
                self.wide = match value.trim() {
                    "off" | "false" => 1.0,
                    _ => num()?,
                }
            }
            "time" => self.time = num()?,
            _ => {
                return Err(Error::parameter(format!(
                    "hypertexture has no parameter {key:?} (it has {})",
                    KEYS.join(", ")
                )))
            }
        }
        Ok(())
    }

    /// Checks the ranges.
    ///
    /// # Errors
    /// [`Error::Parameter`] naming the first parameter out of range.
    pub fn validate(&self) -> Result<()> {
        let positive = [
            ("thickness", self.thickness),
            ("frequency", self.frequency),
            ("softness", self.softness),
            ("step", self.step),
            ("stretch", self.stretch),
        ];
        for (k, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::parameter(format!(
                    "hypertexture {k} = {v} must be > 0"
                )));
            }
        }
        let non_negative = [
            ("amplitude", self.amplitude),
            ("octaves", self.octaves),
            ("opacity", self.opacity),
            ("emission", self.emission),
            ("melt", self.melt),
            ("core_displacement", self.core_displacement),
        ];
        for (k, v) in non_negative {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::parameter(format!(
                    "hypertexture {k} = {v} must be ≥ 0"
                )));
            }
        }
        for (k, v) in [("bias", self.bias), ("gain", self.gain)] {
            if !(v > 0.0 && v < 1.0) {
                return Err(Error::parameter(format!(
                    "hypertexture {k} = {v} must be between 0 and 1"
                )));
            }
        }
        if !(self.tail > 0.0 && self.tail <= 1.0) {
            return Err(Error::parameter(format!(
                "hypertexture tail = {} must be in (0, 1] (1 or off: no extrapolation)",
                self.tail
            )));
        }
        if !(self.wide > 0.0 && self.wide <= 1.0) {
            return Err(Error::parameter(format!(
                "hypertexture wide = {} must be in (0, 1] (1 or off: single steps throughout)",
                self.wide
            )));
        }
        if self.octaves > 8.0 {
            return Err(Error::parameter("hypertexture octaves must be at most 8"));
        }
        if self.thickness > 1.0 {
            return Err(Error::parameter(
                "hypertexture thickness must be at most 1 (the object's size)",
            ));
        }
        if self.step < 0.005 {
            return Err(Error::parameter(
                "hypertexture step must be at least 0.005 shells",
            ));
        }
        if !(self.time.is_finite() && self.rise.is_finite()) {
            return Err(Error::parameter(
                "hypertexture time and rise must be finite",
            ));
        }
        Ok(())
    }

    /// True when the image changes with [`Self::time`].
    #[must_use]
    pub fn animated(&self) -> bool {
        self.rise != 0.0 || self.melt != 0.0
    }

    /// The sum of the weights `octaves3f` gives its octaves (gain ½, the last fractional):
    /// the largest the fBm can be, over the noise's own bound.
    pub(crate) fn octave_weight(&self) -> f32 {
        let octaves = self.octaves.clamp(0.0, 32.0);
        let whole = octaves.floor() as u32;
        let (mut sum, mut amp) = (0.0f32, 1.0f32);
        for i in 0..=whole {
            sum += if i < whole {
                amp
            } else {
                (octaves - whole as f32) * amp
            };
            amp *= 0.5;
        }
        sum
    }

    /// The density ramp `u` shaped by bias and gain: `D ∈ [0, 1]`.
    pub(crate) fn shape(&self, u: f32) -> f32 {
        let u = u.clamp(0.0, 1.0);
        if u == 0.0 || u == 1.0 {
            return u;
        }
        let mut v = f64::from(u);
        if self.bias != 0.5 {
            v = bias(f64::from(self.bias), v);
        }
        if self.gain != 0.5 {
            v = gain(f64::from(self.gain), v);
        }
        v as f32
    }
}
