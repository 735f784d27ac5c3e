//! A material's computed sources: the colour from a solid pattern (`procedural`), from an
//! image through a per-pixel projection (`projected`) or from a 3D texture over an
//! object-space box (`solid_texture`, baked from a pattern or read from a scan) — at most one
//! of the three, since each multiplies the base colour and two would be ambiguous — and solid
//! patterns on the roughness and bump channels.
//!
//! 3D textures filter with OpenGL's filters only (nearest, bilinear, trilinear): there is no
//! anisotropic, EWA or summed-area path for them.

use std::path::Path;

use glam::Vec3;

use super::sampler::{filter_or_wrap_error, parse_wrap, Spellings};
use super::spec::{MaterialSpec, SolidTextureSpec};
use super::textures::slot;
use crate::geometry::Projection;
use crate::scene::texture_cache::TextureCache;
use crate::shading::{Procedural, SolidChannel, SolidMap};
use crate::texture::procedural::Solid;
use crate::texture::{ColorSpace, Filter, Sampler, Wrap};
use crate::{Error, Result};

/// The colour source of `m` (`procedural`, `projected` or `solid_texture`), if it has one.
pub(super) fn colour_source(
    dir: &Path,
    m: &MaterialSpec,
    textures: &mut TextureCache,
) -> Result<Option<Procedural>> {
    let colour_sources = [
        m.procedural.is_some(),
        m.projected.is_some(),
        m.solid_texture.is_some(),
    ];
    if colour_sources.iter().filter(|&&x| x).count() > 1 {
        return Err(Error::parameter(
            "a material takes one of `procedural`, `projected` and `solid_texture`",
        ));
    }
    Ok(match (&m.procedural, &m.projected) {
        (Some(p), _) => {
            let solid = pattern(&p.pattern)?;
            Some(Procedural::Solid {
                colors: p
                    .colors
                    .map_or(solid.default_colors(), |c| c.map(Vec3::from)),
                solid,
                antialias: p.antialias,
            })
        }
        (None, Some(p)) => {
            let mut projection = Projection::parse(&p.projection).ok_or_else(|| {
                Error::parameter(format!(
                    "projection {:?}: expected planar-x, planar-y, planar-z, cylindrical, spherical, cube or bounding-sphere",
                    p.projection
                ))
            })?;
            if let Projection::BoundingSphere { center } = &mut projection {
                // NaN: resolved to the mesh's bounding-box centre when drawn.
                *center = p.center.map_or(Vec3::NAN, Vec3::from);
            }
            slot(
                dir,
                "projected.texture",
                &p.texture,
                ColorSpace::Srgb,
                textures,
            )?
            .map(|slot| Procedural::Projected { slot, projection })
        }
        (None, None) => match &m.solid_texture {
            Some(t) => Some(solid_texture(dir, t, &textures.volumes)?),
            None => None,
        },
    })
}

/// The solid textures of `m` on the roughness and bump channels, in that order.
pub(super) fn solid_maps(m: &MaterialSpec) -> Result<Vec<SolidMap>> {
    let mut maps = Vec::new();
    if let Some(r) = &m.roughness_procedural {
        if !r.range.iter().all(|v| (0.0..=1.0).contains(v)) {
            return Err(Error::parameter(format!(
                "roughness_procedural: range {:?} is not within [0, 1]",
                r.range
            )));
        }
        maps.push(SolidMap {
            solid: pattern(&r.pattern)?,
            channel: SolidChannel::Roughness { range: r.range },
            antialias: r.antialias,
        });
    }
    if let Some(b) = &m.bump_procedural {
        if !b.scale.is_finite() {
            return Err(Error::parameter("bump_procedural: scale must be a number"));
        }
        maps.push(SolidMap {
            solid: pattern(&b.pattern)?,
            channel: SolidChannel::Bump { scale: b.scale },
            antialias: b.antialias,
        });
    }
    Ok(maps)
}

fn pattern(name: &str) -> Result<Solid> {
    Solid::named(name).ok_or_else(|| {
        Error::parameter(format!(
            "pattern {name:?}: expected marble, wood, granite, clouds, checker3d or bricks"
        ))
    })
}

/// A `solid_texture` table → [`Procedural::Texture3D`].
fn solid_texture(
    dir: &Path,
    t: &SolidTextureSpec,
    volumes: &crate::volume::VolumeOptions,
) -> Result<Procedural> {
    let (min, max) = (Vec3::from(t.min), Vec3::from(t.max));
    if !(min.is_finite() && max.is_finite() && max.cmpgt(min).all()) {
        return Err(Error::parameter(format!(
            "solid_texture: the box {min}..{max} must have every max above its min"
        )));
    }
    let (texture, default_colors) = match (&t.bake, &t.file) {
        (Some(name), None) => {
            let solid = pattern(name)?;
            let size = t.size.unwrap_or(64);
            let tex = solid.bake(size, min.as_dvec3(), max.as_dvec3())?;
            (tex, solid.default_colors())
        }
        (None, Some(file)) => {
            if t.size.is_some() {
                return Err(Error::parameter(
                    "solid_texture: `size` is for `bake`, not `file`",
                ));
            }
            let path = dir.join(file);
            let vol = crate::volume::load_volume_with(&path, None, volumes)?;
            (vol.texture().clone(), [Vec3::ZERO, Vec3::ONE])
        }
        _ => {
            return Err(Error::parameter(
                "solid_texture: give either `bake = \"pattern\"` or `file = \"volume\"`",
            ))
        }
    };
    // 3D textures filter with OpenGL's filters only (no anisotropic, EWA or SAT path).
    let filter = match t.filter.as_deref() {
        None => Filter::TRILINEAR,
        Some(f) => match Filter::parse(f) {
            Ok(f @ Filter::Gl { .. }) => f,
            _ => {
                return Err(filter_or_wrap_error(
                    "solid_texture: filter",
                    f,
                    Spellings::GlFilter,
                ))
            }
        },
    };
    let wrap = t
        .wrap
        .as_deref()
        .map(|w| parse_wrap("solid_texture: wrap", w))
        .transpose()?
        .unwrap_or(Wrap::Repeat);
    Ok(Procedural::Texture3D {
        texture: std::sync::Arc::new(texture),
        sampler: Sampler::new(filter, wrap),
        min,
        max,
        colors: t.colors.map_or(default_colors, |c| c.map(Vec3::from)),
    })
}
