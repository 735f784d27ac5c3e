//! Shadow maps: the visibility factor of the illumination model's `S_i` — how much of light
//! `i` reaches a surface point past the other surfaces.
//!
//! A light that casts has a depth map drawn from it (by `render`, through the pipeline:
//! orthographic and fitted to the scene for a directional light, perspective for a spot
//! light, a cube of six perspective faces for a point light or a spot wider than 120°).
//! [`ShadowMaps::visibility`] looks a point up:
//!
//! 1. the map that sees it (a cube: the face of the dominant axis of `p − light`);
//! 2. the point moved along its normal by `normal_offset` texels (normal offset);
//! 3. its texel coordinates, depth and tangent plane in the map ([`ShadowMap::locate`]);
//!    outside the map it is lit (nothing there was drawn);
//! 4. the receiver's depth lowered by `texel·(bias + slope_bias·tan θ)` (constant and
//!    slope-scaled bias, θ between N and L, tan θ at most [`MAX_SLOPE`]);
//! 5. the filter's lit fraction (`filter.rs`): one texel, PCF 3×3 or 5×5, a Poisson disc, or
//!    PCSS with the light's size.
//!
//! Biases are in texels — the world size of one map texel at the receiver — so they follow
//! the map's resolution and the scene's scale. Depths are linear (the view depth, world
//! units), and every filter compares each texel with the receiver's tangent plane at that
//! texel (receiver-plane depth), so planes do not shadow themselves however wide the kernel.
//!
//! Files: `map.rs` (one map and where a point falls in it), `filter.rs` (the filters), this
//! file (the parameters, a scene's casters, a frame's maps and the lookup).

mod filter;
mod map;

use glam::{Vec3, Vec4};

pub use filter::{MAX_PCSS_RADIUS, MIN_PCSS_RADIUS, POISSON_RADIUS};
pub use map::{MapView, Receiver, Receivers, ShadowMap, Tile, BLOCK, MAX_SLOPE};

use crate::texture::UnknownName;
use crate::{Error, Result};

/// The largest shadow map side accepted (a point light draws six maps of this side).
pub const MAX_SHADOW_MAP_SIZE: u32 = 4096;

/// How a lookup filters the map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ShadowFilter {
    /// One texel, one compare: hard, aliased edges.
    Hard,
    /// Percentage-closer filtering: 3×3 bilinear taps (16 texels).
    #[default]
    Pcf3,
    /// 5×5 bilinear taps (36 texels).
    Pcf5,
    /// 16 bilinear taps on a Poisson disc of [`POISSON_RADIUS`] texels.
    Poisson,
    /// Percentage-closer soft shadows: penumbrae from the blockers' depth and the light's
    /// size ([`ShadowParams::light_angle`], [`ShadowParams::light_radius`]).
    Pcss,
}

impl ShadowFilter {
    /// The names [`ShadowFilter::parse`] accepts.
    pub const SPELLINGS: &'static str = "hard, pcf3, pcf5, poisson, pcss";

    /// The filter named `s` (one of [`ShadowFilter::SPELLINGS`]).
    ///
    /// # Errors
    /// [`UnknownName`] quoting the list.
    pub fn parse(s: &str) -> std::result::Result<ShadowFilter, UnknownName> {
        Ok(match s {
            "hard" => ShadowFilter::Hard,
            "pcf3" => ShadowFilter::Pcf3,
            "pcf5" => ShadowFilter::Pcf5,
            "poisson" => ShadowFilter::Poisson,
            "pcss" => ShadowFilter::Pcss,
            _ => {
                return Err(UnknownName {
                    given: s.to_string(),
                    expected: Self::SPELLINGS,
                })
            }
        })
    }

    /// The filter's name, as [`ShadowFilter::parse`] reads it.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ShadowFilter::Hard => "hard",
            ShadowFilter::Pcf3 => "pcf3",
            ShadowFilter::Pcf5 => "pcf5",
            ShadowFilter::Poisson => "poisson",
            ShadowFilter::Pcss => "pcss",
        }
    }
}

/// How every casting light's map is made and read.
///
/// ```
/// use texmap::shading::shadow::{ShadowFilter, ShadowParams};
/// let p = ShadowParams::default().with_map_size(1024).with_filter(ShadowFilter::Pcss);
/// assert!(p.validate().is_ok());
/// assert!(p.with_map_size(0).validate().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct ShadowParams {
    /// Texels a side (each face of a cube), 1..=[`MAX_SHADOW_MAP_SIZE`].
    pub map_size: u32,
    pub filter: ShadowFilter,
    /// Constant bias, texels.
    pub bias: f32,
    /// Slope-scaled bias: texels per unit of tan θ (θ between the normal and the light).
    pub slope_bias: f32,
    /// Normal offset: the lookup point moves this many texels along the normal.
    pub normal_offset: f32,
    /// PCSS: the angular diameter of directional lights, degrees.
    pub light_angle: f32,
    /// PCSS: the radius of point and spot lights, world units.
    pub light_radius: f32,
}

impl Default for ShadowParams {
    /// 2048² maps, PCF 3×3, bias 0.5 texel, slope bias 1, normal offset 0.5 texel; PCSS
    /// with a 2° sun and lamps of radius 0.05.
    fn default() -> Self {
        ShadowParams {
            map_size: 2048,
            filter: ShadowFilter::Pcf3,
            bias: 0.5,
            slope_bias: 1.0,
            normal_offset: 0.5,
            light_angle: 2.0,
            light_radius: 0.05,
        }
    }
}

impl ShadowParams {
    #[must_use]
    pub fn with_map_size(mut self, texels: u32) -> Self {
        self.map_size = texels;
        self
    }
    #[must_use]
    pub fn with_filter(mut self, filter: ShadowFilter) -> Self {
        self.filter = filter;
        self
    }
    #[must_use]
    pub fn with_bias(mut self, texels: f32) -> Self {
        self.bias = texels;
        self
    }
    #[must_use]
    pub fn with_slope_bias(mut self, texels: f32) -> Self {
        self.slope_bias = texels;
        self
    }
    #[must_use]
    pub fn with_normal_offset(mut self, texels: f32) -> Self {
        self.normal_offset = texels;
        self
    }
    #[must_use]
    pub fn with_light_angle(mut self, degrees: f32) -> Self {
        self.light_angle = degrees;
        self
    }
    #[must_use]
    pub fn with_light_radius(mut self, radius: f32) -> Self {
        self.light_radius = radius;
        self
    }

    /// Checks the values: a map size in 1..=[`MAX_SHADOW_MAP_SIZE`], finite biases ≥ 0, a
    /// light angle in [0, 90) degrees and a finite radius ≥ 0.
    ///
    /// # Errors
    /// [`Error::Parameter`] naming the first bad value by its TOML key.
    pub fn validate(&self) -> Result<()> {
        if !(1..=MAX_SHADOW_MAP_SIZE).contains(&self.map_size) {
            return Err(Error::parameter(format!(
                "map_size {} is outside 1..={MAX_SHADOW_MAP_SIZE}",
                self.map_size
            )));
        }
        for (name, v) in [
            ("bias", self.bias),
            ("slope_bias", self.slope_bias),
            ("normal_offset", self.normal_offset),
            ("light_radius", self.light_radius),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::parameter(format!(
                    "{name} {v} must be finite and at least 0"
                )));
            }
        }
        if !(self.light_angle >= 0.0 && self.light_angle < 90.0) {
            return Err(Error::parameter(format!(
                "light_angle {} is outside [0, 90) degrees",
                self.light_angle
            )));
        }
        Ok(())
    }
}

/// Which of a scene's lights cast shadows, and how their maps are made and read.
///
/// ```
/// use texmap::shading::shadow::{ShadowParams, Shadows};
/// let s = Shadows::casting(vec![0]).with_params(ShadowParams::default().with_map_size(512));
/// assert!(s.casts(0) && !s.casts(1));
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct Shadows {
    /// Indices into the scene's lights (`Scene::lights`).
    pub lights: Vec<usize>,
    pub params: ShadowParams,
}

impl Shadows {
    /// Lights `lights` cast, with the default parameters.
    #[must_use]
    pub fn casting(lights: Vec<usize>) -> Self {
        Shadows {
            lights,
            params: ShadowParams::default(),
        }
    }
    #[must_use]
    pub fn with_params(mut self, params: ShadowParams) -> Self {
        self.params = params;
        self
    }
    /// Whether light `i` casts.
    #[must_use]
    pub fn casts(&self, i: usize) -> bool {
        self.lights.contains(&i)
    }
}

/// The maps of one casting light.
#[derive(Clone, Debug, PartialEq)]
pub enum LightMaps {
    /// A directional light's or a spot light's map.
    One(ShadowMap),
    /// A point light's (or a wide spot light's) six faces, in the order +x, −x, +y, −y, +z,
    /// −z: the dominant axis of `p − position` and its sign choose the face.
    Cube(Box<[ShadowMap; 6]>),
}

/// How large a light looks, for the penumbrae of PCSS.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightExtent {
    /// A directional light: tan of half its angular diameter.
    Angle { tan_half: f32 },
    /// A point or spot light: its radius in world units.
    Radius { radius: f32 },
}

/// One casting light of a frame: its maps, where it is and how large it looks.
#[derive(Clone, Debug, PartialEq)]
pub struct LightShadow {
    pub maps: LightMaps,
    /// The light's position (point and spot lights), or its unit direction towards the light
    /// (directional lights): a cube's faces are chosen around it, and the renderer checks
    /// the maps were made for the light it lights with.
    pub origin: Vec3,
    pub extent: LightExtent,
}

/// A frame's shadow maps: for each light the frame lights (in its order), its maps or
/// `None`, and the parameters lookups read.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShadowMaps {
    pub lights: Vec<Option<LightShadow>>,
    pub params: ShadowParams,
    /// For each of the scene's projectors (in order), its depth map when it casts
    /// ([`crate::shading::Projector::shadows`]); empty when none does.
    pub projectors: Vec<Option<LightShadow>>,
}

impl ShadowMaps {
    /// True when no light has a map (lighting then takes no shadow path).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.lights.iter().all(Option::is_none)
    }

    /// The fraction of light `i` (of the frame's list) that reaches world point `p` with
    /// unit normal `n`, `l` being the unit direction towards the light and `n·l > 0`: 1 for
    /// a light without maps.
    #[inline]
    #[must_use]
    pub fn visibility(&self, i: usize, p: Vec3, n: Vec3, l: Vec3) -> f32 {
        match self.lights.get(i) {
            Some(Some(shadow)) => self.lookup(shadow, p, n, l),
            _ => 1.0,
        }
    }

    /// The fraction of projector `k`'s light that reaches `p` (as [`ShadowMaps::visibility`]
    /// for the lights): 1 for a projector without a map.
    #[inline]
    #[must_use]
    pub fn projector_visibility(&self, k: usize, p: Vec3, n: Vec3, l: Vec3) -> f32 {
        match self.projectors.get(k) {
            Some(Some(shadow)) => self.lookup(shadow, p, n, l),
            _ => 1.0,
        }
    }

    /// [`ShadowMaps::visibility`] at a quad's four pixels, in lanes (`p`, `n` and `l` as x,
    /// y and z lanes): pixels whose bit in `facing` is clear (facing away from the light, or
    /// out of its reach) get 1 without a lookup. The steps up to the filter run in lanes, in
    /// the per-pixel lookup's order of operations (so each lane equals it bit for bit), the
    /// filters pixel by pixel.
    #[inline]
    #[must_use]
    pub fn visibility_quad(
        &self,
        i: usize,
        p: [Vec4; 3],
        n: [Vec4; 3],
        l: [Vec4; 3],
        facing: u32,
    ) -> Vec4 {
        let Some(Some(shadow)) = self.lights.get(i) else {
            return Vec4::ONE;
        };
        if facing & 0b1111 == 0 {
            return Vec4::ONE;
        }
        let lane = |v: [Vec4; 3], j: usize| Vec3::new(v[0][j], v[1][j], v[2][j]);
        let map = match &shadow.maps {
            LightMaps::One(m) => m,
            LightMaps::Cube(faces) => {
                let face = |j| cube_face(lane(p, j) - shadow.origin);
                let first = face(0);
                if (1..4).any(|j| face(j) != first) {
                    // The quad straddles two faces: each pixel alone.
                    return Vec4::from_array(std::array::from_fn(|j| {
                        if facing & (1 << j) == 0 {
                            1.0
                        } else {
                            self.lookup(shadow, lane(p, j), lane(n, j), lane(l, j))
                        }
                    }));
                }
                &faces[first]
            }
        };
        // A directional map covers only where shadows can fall: a quad wholly outside it
        // (by more than the normal offset can move it) is lit without the lookup's steps.
        if map.outside_quad(p, self.params.normal_offset + 1.0) {
            return Vec4::ONE;
        }
        let cos = (n[0] * l[0] + n[1] * l[1] + n[2] * l[2]).clamp(Vec4::splat(1e-6), Vec4::ONE);
        let sin = Vec4::from_array(
            (Vec4::ONE - cos * cos)
                .max(Vec4::ZERO)
                .to_array()
                .map(f32::sqrt),
        );
        let tan = (sin / cos).min(Vec4::splat(MAX_SLOPE));
        let k = map.texel_at_quad(p) * self.params.normal_offset;
        let moved = std::array::from_fn(|c| p[c] + n[c] * k);
        let r = map.locate_quad(moved, n);
        let bias = r.texel * (Vec4::splat(self.params.bias) + tan * self.params.slope_bias);
        let perspective = matches!(map.view, MapView::Perspective { .. });
        // The lanes that look the map up (the others are lit).
        let todo = (0..4).fold(0u32, |todo, j| {
            let behind = perspective && !(r.depth[j] > 0.0);
            if facing & (1 << j) == 0 || behind || map.outside(r.u[j], r.v[j]) {
                todo
            } else {
                todo | 1 << j
            }
        });
        if self.params.filter == ShadowFilter::Pcf3 {
            return filter::pcf3_quad(map, &r, bias, todo);
        }
        Vec4::from_array(std::array::from_fn(|j| {
            if todo & (1 << j) == 0 {
                1.0
            } else {
                filter::lit_fraction(map, &r.lane(j), bias[j], self.params.filter, shadow.extent)
            }
        }))
    }

    /// The lookup's steps (the module docs) for one casting light.
    #[inline]
    fn lookup(&self, shadow: &LightShadow, p: Vec3, n: Vec3, l: Vec3) -> f32 {
        let map = match &shadow.maps {
            LightMaps::One(m) => m,
            LightMaps::Cube(faces) => &faces[cube_face(p - shadow.origin)],
        };
        let cos = n.dot(l).clamp(1e-6, 1.0);
        let tan = ((1.0 - cos * cos).sqrt() / cos).min(MAX_SLOPE);
        let p = p + n * (self.params.normal_offset * map.texel_at(p));
        let Some(r) = map.locate(p, n).filter(|r| !map.outside(r.u, r.v)) else {
            return 1.0;
        };
        let bias = r.texel * (self.params.bias + self.params.slope_bias * tan);
        filter::lit_fraction(map, &r, bias, self.params.filter, shadow.extent)
    }
}

/// The cube face that sees direction `d`: 0..6 for +x, −x, +y, −y, +z, −z.
#[inline]
#[must_use]
pub fn cube_face(d: Vec3) -> usize {
    let a = d.abs();
    if a.x >= a.y && a.x >= a.z {
        usize::from(d.x < 0.0)
    } else if a.y >= a.z {
        2 + usize::from(d.y < 0.0)
    } else {
        4 + usize::from(d.z < 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filter_names_round_trip_and_unknown_ones_quote_the_list() {
        for f in [
            ShadowFilter::Hard,
            ShadowFilter::Pcf3,
            ShadowFilter::Pcf5,
            ShadowFilter::Poisson,
            ShadowFilter::Pcss,
        ] {
            assert_eq!(ShadowFilter::parse(f.name()).unwrap(), f);
            assert!(ShadowFilter::SPELLINGS.contains(f.name()));
        }
        let e = ShadowFilter::parse("pcf7").unwrap_err();
        assert!(e.to_string().contains(ShadowFilter::SPELLINGS));
    }

    #[test]
    fn params_refuse_bad_values_by_name() {
        let p = ShadowParams::default();
        assert!(p.validate().is_ok());
        for (bad, key) in [
            (p.with_map_size(0), "map_size"),
            (p.with_map_size(MAX_SHADOW_MAP_SIZE + 1), "map_size"),
            (p.with_bias(-1.0), "bias"),
            (p.with_slope_bias(f32::NAN), "slope_bias"),
            (p.with_normal_offset(f32::INFINITY), "normal_offset"),
            (p.with_light_angle(90.0), "light_angle"),
            (p.with_light_radius(-0.1), "light_radius"),
        ] {
            let e = bad.validate().unwrap_err().to_string();
            assert!(e.starts_with(key), "{e}");
        }
    }

    #[test]
    fn cube_faces_follow_the_dominant_axis() {
        assert_eq!(cube_face(Vec3::new(2.0, 1.0, -1.0)), 0);
        assert_eq!(cube_face(Vec3::new(-2.0, 1.0, -1.0)), 1);
        assert_eq!(cube_face(Vec3::new(0.1, 3.0, -1.0)), 2);
        assert_eq!(cube_face(Vec3::new(0.1, -3.0, -1.0)), 3);
        assert_eq!(cube_face(Vec3::new(0.1, 0.2, 1.0)), 4);
        assert_eq!(cube_face(Vec3::new(0.1, 0.2, -1.0)), 5);
    }

    #[test]
    fn a_light_without_maps_is_fully_visible() {
        let maps = ShadowMaps {
            lights: vec![None],
            params: ShadowParams::default(),
            projectors: vec![None],
        };
        assert!(maps.is_empty());
        assert_eq!(maps.visibility(0, Vec3::ZERO, Vec3::Y, Vec3::Y), 1.0);
        assert_eq!(
            maps.projector_visibility(0, Vec3::ZERO, Vec3::Y, Vec3::Y),
            1.0
        );
        assert_eq!(maps.visibility(3, Vec3::ZERO, Vec3::Y, Vec3::Y), 1.0);
    }
}
