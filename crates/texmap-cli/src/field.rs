//! The distance-field flags of `texmap render`: a scan's surface at a threshold
//! (`--surface T`: its exact distance field built on the fly), a mesh drawn as its distance
//! field (built at `--sdf-res`) when a look or a hypertexture asks for it, the surface's
//! look (`--solid`, `--bump`, `--surface-color`) and the hypertexture (`--hypertexture
//! PRESET`, `--ht key=value`). A distance-field file (`texmap sdf`'s output) takes them with
//! `--method surface|hypertexture`, or directly.

use std::path::Path;
use std::sync::Arc;

use clap::Args;
use glam::{Mat4, Vec3};
use texmap::scene::Scene;
use texmap::texture::procedural::Solid;
use texmap::volume::sdf::{hyper, smooth_field, Hypertexture, SCAN_SMOOTHING};
use texmap::volume::{Method, SceneVolume};
use texmap::Error;

/// Flags for distance fields: surfaces, solid textures, bumps, hypertexture.
#[derive(Args, Clone, Debug, Default)]
pub struct FieldArgs {
    /// A scan: draw the surface where values are at or above T (its exact Euclidean distance
    /// field is built first, as `texmap sdf --threshold T` builds it).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub surface: Option<f64>,
    /// A solid texture for a distance field's surface, carved from the block: marble, wood,
    /// granite, clouds, checker3d or bricks. A mesh is drawn as its distance field.
    #[arg(long)]
    pub solid: Option<String>,
    /// Bump a distance field's surface with the noise gradient, of this strength (0.2 when
    /// given without a value).
    #[arg(long, num_args = 0..=1, require_equals = true, default_missing_value = "0.2")]
    pub bump: Option<f32>,
    /// The bump noise's frequency per object size [default: 24].
    #[arg(long)]
    pub bump_frequency: Option<f32>,
    /// A distance field's surface colour r,g,b (linear) without --solid [default: 0.8,0.8,0.8].
    #[arg(long, value_parser = parse_color)]
    pub surface_color: Option<Vec3>,
    /// Hypertexture around a distance field's surface: fur, fire, smoke or melt. A mesh is
    /// drawn as its distance field.
    #[arg(long, value_name = "PRESET")]
    pub hypertexture: Option<String>,
    /// A hypertexture parameter, KEY=VALUE (repeatable): thickness, amplitude, frequency,
    /// octaves, noise, strands, softness, bias, gain, opacity, inner, outer, emission,
    /// shadows, rise, stretch, melt, core_displacement, core, step, tail, wide, time
    /// (`tail=off wide=off`: no extrapolation of a ray's last 5 % of opacity and single
    /// steps throughout, a reference render).
    #[arg(long = "ht", value_name = "KEY=VALUE")]
    pub ht: Vec<String>,
    /// Voxels along the largest side of a mesh's distance field [default: 128].
    #[arg(long)]
    pub sdf_res: Option<u32>,
    /// With --frames and an animated hypertexture (fire, smoke, melt): frames advance time
    /// only, the camera stays (frame k at time (k−1)/(N−1)).
    #[arg(long)]
    pub still: bool,
}

fn parse_color(s: &str) -> Result<Vec3, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| {
            x.trim()
                .parse::<f32>()
                .map_err(|_| format!("\"{x}\" is not a number"))
        })
        .collect::<Result<_, _>>()?;
    match v[..] {
        [r, g, b] if [r, g, b].iter().all(|c| c.is_finite() && *c >= 0.0) => Ok(Vec3::new(r, g, b)),
        _ => Err("expected three numbers r,g,b ≥ 0".into()),
    }
}

impl FieldArgs {
    /// The look and hypertexture flags given.
    pub fn given_look_flags(&self) -> Vec<&'static str> {
        [
            ("--solid", self.solid.is_some()),
            ("--bump", self.bump.is_some()),
            ("--bump-frequency", self.bump_frequency.is_some()),
            ("--surface-color", self.surface_color.is_some()),
            ("--hypertexture", self.hypertexture.is_some()),
            ("--ht", !self.ht.is_empty()),
        ]
        .into_iter()
        .filter_map(|(f, g)| g.then_some(f))
        .collect()
    }

    /// True when a mesh is to be drawn as its distance field.
    pub fn wants_field(&self) -> bool {
        !self.given_look_flags().is_empty()
    }

    /// The scan at `path` as the distance field of its values ≥ `threshold`.
    pub fn scan_surface(
        &self,
        path: &Path,
        threshold: f64,
        max_memory: u64,
        ignore_orientation: bool,
    ) -> Result<SceneVolume, Error> {
        let (field, _, _) = crate::sdf::scan_to_field(path, threshold, max_memory)?;
        // The mask's staircase rounded off (see `smooth_field`).
        let vol = smooth_field(&field, SCAN_SMOOTHING)
            .to_volume()
            .map_err(|e| Error::parameter(format!("{}: {e}", path.display())))?;
        let mut sv = SceneVolume::new(vol, path);
        if ignore_orientation {
            sv.place(Mat4::IDENTITY, true)?;
        }
        sv.method = Method::Surface;
        Ok(sv)
    }

    /// The meshes of `scene` (from `path`) as one distance field, at `--sdf-res`; the meshes
    /// are taken out of the scene (the field draws them).
    pub fn mesh_surface(
        &self,
        scene: &mut Scene,
        path: &Path,
        max_memory: u64,
    ) -> Result<SceneVolume, Error> {
        let tris = scene.world_triangles();
        let (field, _) =
            crate::sdf::mesh_to_field(path, &tris, self.sdf_res.unwrap_or(128), 0.1, max_memory)?;
        let vol = field
            .to_volume()
            .map_err(|e| Error::parameter(format!("{}: {e}", path.display())))?;
        // Framed as the mesh would be (from its front), not as a scan.
        if scene.camera.is_none() {
            scene.camera = Some(scene.framing_camera(60.0));
        }
        scene.meshes.clear();
        let mut sv = SceneVolume::new(vol, path);
        sv.method = Method::Surface;
        Ok(sv)
    }

    /// Gives `sv` the `--hypertexture` preset before the volume flags are checked (so that
    /// `--method hypertexture` finds one); [`Self::apply`] then lays the rest.
    pub fn preset_hypertexture(&self, sv: &mut SceneVolume) {
        if let Some(h) = self.hypertexture.as_deref().and_then(Hypertexture::preset) {
            sv.hypertexture = Some(h);
        }
    }

    /// Lays the look and hypertexture flags over a volume; they need a distance field.
    pub fn apply(&self, sv: &mut SceneVolume) -> Result<(), Error> {
        let given = self.given_look_flags();
        if given.is_empty() {
            return Ok(());
        }
        if self.hypertexture.is_some() {
            sv.method = Method::Hypertexture;
        }
        if !sv.method.is_distance_field() {
            return Err(Error::parameter(format!(
                "{} apply to a distance field's surface (give --surface T for a scan, or \
                 --method surface)",
                given.join(", ")
            )));
        }
        if let Some(name) = &self.solid {
            sv.look.solid = Some(Solid::named(name).ok_or_else(|| {
                Error::parameter(format!(
                    "--solid {name:?} is not marble, wood, granite, clouds, checker3d or bricks"
                ))
            })?);
        }
        if let Some(b) = self.bump {
            sv.look.bump = b;
        }
        if let Some(f) = self.bump_frequency {
            sv.look.bump_frequency = f;
        }
        if let Some(c) = self.surface_color {
            sv.look.color = c;
        }
        if let Some(p) = &self.hypertexture {
            sv.hypertexture = Some(Hypertexture::preset(p).ok_or_else(|| {
                Error::parameter(format!(
                    "--hypertexture {p:?} is not {}",
                    hyper::PRESETS.join(", ")
                ))
            })?);
        }
        if !self.ht.is_empty() {
            let h = sv.hypertexture.as_mut().ok_or_else(|| {
                Error::parameter("--ht sets a hypertexture's parameters: give --hypertexture")
            })?;
            for kv in &self.ht {
                let (k, v) = kv
                    .split_once('=')
                    .ok_or_else(|| Error::parameter(format!("--ht {kv:?} is not KEY=VALUE")))?;
                h.set(k.trim(), v)?;
            }
        }
        sv.validate()
    }
}

/// The volumes for frame `k` (1-based) of `n`: animated hypertextures at time (k−1)/(n−1)
/// when there are several frames, otherwise as given.
pub fn volumes_at(volumes: &[SceneVolume], k: u32, n: u32) -> Option<Vec<SceneVolume>> {
    if n <= 1 || !volumes.iter().any(animated) {
        return None;
    }
    let time = (k.max(1) - 1) as f32 / (n - 1) as f32;
    Some(
        volumes
            .iter()
            .map(|v| {
                let mut v = SceneVolume {
                    volume: Arc::clone(&v.volume),
                    ..v.clone()
                };
                if let Some(h) = &mut v.hypertexture {
                    h.time = time;
                }
                v
            })
            .collect(),
    )
}

/// True for a volume drawn with a hypertexture that changes with time.
pub fn animated(v: &SceneVolume) -> bool {
    v.method == Method::Hypertexture && v.hypertexture.as_ref().is_some_and(|h| h.animated())
}

/// How a distance field is drawn, for `texmap info` and `--stats`: the surface's look and
/// the hypertexture with its parameters.
pub fn describe(v: &SceneVolume) -> String {
    let l = &v.look;
    let mut out = match &l.solid {
        Some(s) => format!("surface {}", format!("{s:?}").to_lowercase()),
        None => format!(
            "surface colour ({}, {}, {})",
            l.color.x, l.color.y, l.color.z
        ),
    };
    if l.bump > 0.0 {
        out += &format!(", bump {} at frequency {}", l.bump, l.bump_frequency);
    }
    out += if v.params.lights.is_empty() {
        ", headlight"
    } else {
        ", scene lights"
    };
    if let (Method::Hypertexture, Some(h)) = (v.method, &v.hypertexture) {
        out += &format!(
            "; hypertexture {} (thickness {}, amplitude {}, frequency {}, octaves {}, {:?}{}, \
             softness {}, bias {}, gain {}, opacity {}, emission {}, shadows {}, rise {}, \
             melt {}, time {}, step {}, tail {}, wide {})",
            h.preset,
            h.thickness,
            h.amplitude,
            h.frequency,
            h.octaves,
            h.noise,
            if h.strands { " strands" } else { "" },
            h.softness,
            h.bias,
            h.gain,
            h.opacity,
            h.emission,
            h.shadows,
            h.rise,
            h.melt,
            h.time,
            h.step,
            h.tail,
            h.wide
        );
    }
    out
}
