//! What the viewer's keys change: the frame's [`Look`] (filter, shading, interpolation,
//! visibility, antialiasing: laid over the render's settings, no reload) and the scene's
//! [`Parts`] (the texture applications and the environment: the render's own flags, so the
//! scene is prepared again by the render's code, whose checks refuse a part the scene does
//! not have).
//!
//! Every cycle starts from what the command line asked for, so with no key pressed the
//! viewer draws exactly `texmap render`'s frame.

use texmap::render::{Interpolation, Settings, ShadingMode, Visibility};
use texmap::texture::Filter;

use crate::render::relief::ParallaxArg;
use crate::render::{RenderArgs, Switch};

/// The filters `f` steps through after each texture's own: by the library's names.
pub const FILTERS: [&str; 7] = [
    "nearest",
    "bilinear",
    "trilinear",
    "aniso16",
    "aniso5-area",
    "ewa",
    "sat",
];

/// Antialiasing modes `m` steps through: `(msaa, ssaa)`.
pub const ANTIALIASING: [(u32, u32); 3] = [(1, 1), (4, 1), (1, 2)];

/// The per-frame settings the keys cycle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Look {
    /// `None`: each texture's own filter (or `--filter`'s, already in the settings).
    pub filter: Option<Filter>,
    pub shading: ShadingMode,
    pub interpolation: Interpolation,
    pub visibility: Visibility,
    pub msaa: u32,
    pub ssaa: u32,
    /// `--subdivide-error`: the error bound `i` uses when it reaches subdivision.
    pub subdivide_error: f32,
}

impl Look {
    /// The look of the render's `settings` (the user's flags).
    #[must_use]
    pub fn of(settings: &Settings, subdivide_error: f32) -> Look {
        Look {
            filter: settings.textures.filter,
            shading: settings.shading,
            interpolation: settings.interpolation,
            visibility: settings.visibility,
            msaa: settings.msaa,
            ssaa: settings.ssaa,
            subdivide_error,
        }
    }

    /// `settings` with this look laid over them.
    #[must_use]
    pub fn apply(&self, settings: &Settings) -> Settings {
        let mut s = *settings;
        s.textures.filter = self.filter;
        s.shading = self.shading;
        s.interpolation = self.interpolation;
        s.visibility = self.visibility;
        s.msaa = self.msaa;
        s.ssaa = self.ssaa;
        s
    }

    /// `f`: the next filter of [`FILTERS`], from each texture's own (a filter given that is
    /// not in the list goes on to the first).
    pub fn next_filter(&mut self) {
        let names = FILTERS.map(|n| Filter::parse(n).expect("the library's own filter names"));
        self.filter = match self.filter {
            None => Some(names[0]),
            Some(f) => match names.iter().position(|n| n.name() == f.name()) {
                Some(i) if i + 1 < names.len() => Some(names[i + 1]),
                Some(_) => None,
                None => Some(names[0]),
            },
        };
    }

    /// `s`: flat → Gouraud → Phong → flat.
    pub fn next_shading(&mut self) {
        self.shading = match self.shading {
            ShadingMode::Flat => ShadingMode::Gouraud,
            ShadingMode::Gouraud => ShadingMode::Phong,
            ShadingMode::Phong => ShadingMode::Flat,
        };
    }

    /// `i`: perspective → affine → subdivide → perspective.
    pub fn next_interpolation(&mut self) {
        self.interpolation = match self.interpolation {
            Interpolation::Perspective => Interpolation::Affine,
            Interpolation::Affine => Interpolation::Subdivide {
                max_error_px: self.subdivide_error,
            },
            Interpolation::Subdivide { .. } => Interpolation::Perspective,
        };
    }

    /// `v`: z-buffer ↔ depth sort.
    pub fn next_visibility(&mut self) {
        self.visibility = match self.visibility {
            Visibility::ZBuffer => Visibility::DepthSort,
            Visibility::DepthSort => Visibility::ZBuffer,
        };
    }

    /// `m`: off → MSAA 4 → SSAA 2 → off (a mode given on the command line that is not in
    /// [`ANTIALIASING`] goes on to the one after off).
    pub fn next_antialiasing(&mut self) {
        let i = ANTIALIASING
            .iter()
            .position(|&m| m == (self.msaa, self.ssaa))
            .map_or(1, |i| (i + 1) % ANTIALIASING.len());
        (self.msaa, self.ssaa) = ANTIALIASING[i];
    }

    /// The overlay's words for each setting.
    #[must_use]
    pub fn describe(&self) -> [(&'static str, String); 5] {
        [
            (
                "filter",
                self.filter.map_or_else(|| "own".to_string(), Filter::name),
            ),
            (
                "shading",
                match self.shading {
                    ShadingMode::Flat => "flat",
                    ShadingMode::Gouraud => "gouraud",
                    ShadingMode::Phong => "phong",
                }
                .to_string(),
            ),
            (
                "interp",
                match self.interpolation {
                    Interpolation::Perspective => "perspective".to_string(),
                    Interpolation::Affine => "affine".to_string(),
                    Interpolation::Subdivide { max_error_px } => {
                        format!("subdivide {max_error_px}px")
                    }
                },
            ),
            (
                "visibility",
                match self.visibility {
                    Visibility::ZBuffer => "zbuffer",
                    Visibility::DepthSort => "depth-sort",
                }
                .to_string(),
            ),
            (
                "aa",
                match (self.msaa, self.ssaa) {
                    (1, 1) => "off".to_string(),
                    (m, 1) => format!("msaa {m}"),
                    (1, s) => format!("ssaa {s}"),
                    (m, s) => format!("msaa {m} ssaa {s}"),
                },
            ),
        ]
    }
}

/// A texture application (or the environment) a number key switches.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Part {
    Shadows,
    NormalMaps,
    BumpMaps,
    Parallax,
    Displacement,
    Layers,
    LightMaps,
    Toon,
    Projectors,
    Reflections,
}

/// The number keys, in order `1`…`9`, `0`, with their parts and the render flag each sets.
pub const PARTS: [(char, Part, &str); 10] = [
    ('1', Part::Shadows, "shadows"),
    ('2', Part::NormalMaps, "normal-maps"),
    ('3', Part::BumpMaps, "bump-maps"),
    ('4', Part::Parallax, "parallax"),
    ('5', Part::Displacement, "displacement"),
    ('6', Part::Layers, "layers"),
    ('7', Part::LightMaps, "light-maps"),
    ('8', Part::Toon, "toon"),
    ('9', Part::Projectors, "projectors"),
    ('0', Part::Reflections, "reflections"),
];

/// Which parts are on: the key of a prepared scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Parts {
    on: [bool; PARTS.len()],
    /// The scene's environment (`e`).
    pub environment: bool,
}

fn on(s: Option<Switch>) -> bool {
    s != Some(Switch::Off)
}

impl Parts {
    /// The parts as `args` ask (a part not named is on: the scene's own).
    #[must_use]
    pub fn of(args: &RenderArgs) -> Parts {
        let r = &args.relief;
        let on = PARTS.map(|(_, part, _)| match part {
            Part::Shadows => args.shadows != Some(false),
            Part::NormalMaps => on(r.normal_maps),
            Part::BumpMaps => on(r.bump_maps),
            Part::Parallax => r.parallax != Some(ParallaxArg::Off),
            Part::Displacement => on(r.displacement),
            Part::Layers => on(args.layers),
            Part::LightMaps => on(args.light_maps),
            Part::Toon => on(args.toon),
            Part::Projectors => on(args.projectors),
            Part::Reflections => on(args.reflections),
        });
        Parts {
            on,
            environment: true,
        }
    }

    /// Whether `part` is on.
    #[must_use]
    pub fn is_on(&self, part: Part) -> bool {
        self.on[index(part)]
    }

    /// `part` switched.
    #[must_use]
    pub fn toggled(mut self, part: Part) -> Parts {
        self.on[index(part)] ^= true;
        self
    }

    /// `args` with the flag of every part that differs from `given` (the command line's
    /// parts) set to this state; the others are left as given.
    #[must_use]
    pub fn apply(&self, given: &Parts, args: &RenderArgs) -> RenderArgs {
        let mut a = args.clone();
        let switch = |on: bool| Some(if on { Switch::On } else { Switch::Off });
        for (i, (_, part, _)) in PARTS.iter().enumerate() {
            let on = self.on[i];
            if on == given.on[i] {
                continue;
            }
            match part {
                Part::Shadows => a.shadows = Some(on),
                Part::NormalMaps => a.relief.normal_maps = switch(on),
                Part::BumpMaps => a.relief.bump_maps = switch(on),
                Part::Parallax => {
                    a.relief.parallax = Some(if on {
                        ParallaxArg::Occlusion
                    } else {
                        ParallaxArg::Off
                    })
                }
                Part::Displacement => a.relief.displacement = switch(on),
                Part::Layers => a.layers = switch(on),
                Part::LightMaps => a.light_maps = switch(on),
                Part::Toon => a.toon = switch(on),
                Part::Projectors => a.projectors = switch(on),
                Part::Reflections => a.reflections = switch(on),
            }
        }
        a
    }
}

fn index(part: Part) -> usize {
    PARTS
        .iter()
        .position(|(_, p, _)| *p == part)
        .expect("every part has a key")
}

#[cfg(test)]
mod tests {
    use clap::{Args, FromArgMatches};

    use super::*;

    fn args(flags: &[&str]) -> RenderArgs {
        let cmd = RenderArgs::augment_args(clap::Command::new("view"));
        let m = cmd
            .try_get_matches_from(std::iter::once("view").chain(flags.iter().copied()))
            .unwrap();
        RenderArgs::from_arg_matches(&m).unwrap()
    }

    #[test]
    fn every_cycle_comes_back_to_where_it_started_after_visiting_each_mode() {
        let start = Look::of(&Settings::new(8, 8), 0.5);
        let mut l = start;
        let mut seen = Vec::new();
        for _ in 0..=FILTERS.len() {
            seen.push(l.describe()[0].1.clone());
            l.next_filter();
        }
        assert_eq!(l, start);
        assert_eq!(seen[0], "own");
        assert_eq!(seen[1..], FILTERS.map(|n| Filter::parse(n).unwrap().name()));
        for step in [
            Look::next_shading as fn(&mut Look),
            Look::next_interpolation,
            Look::next_visibility,
            Look::next_antialiasing,
        ] {
            let mut l = start;
            let mut n = 0;
            loop {
                step(&mut l);
                n += 1;
                assert_ne!(n, 5, "a cycle did not close");
                if l == start {
                    break;
                }
            }
            assert!(n >= 2);
        }
    }

    #[test]
    fn the_keys_reach_each_named_mode_in_order() {
        let mut l = Look::of(&Settings::new(8, 8), 0.25);
        l.next_shading();
        assert_eq!(l.shading, ShadingMode::Flat);
        l.next_shading();
        assert_eq!(l.shading, ShadingMode::Gouraud);
        l.next_interpolation();
        l.next_interpolation();
        assert_eq!(
            l.interpolation,
            Interpolation::Subdivide { max_error_px: 0.25 }
        );
        l.next_antialiasing();
        assert_eq!((l.msaa, l.ssaa), (4, 1));
        l.next_antialiasing();
        assert_eq!((l.msaa, l.ssaa), (1, 2));
        let s = l.apply(&Settings::new(8, 8));
        assert_eq!((s.shading, s.msaa, s.ssaa), (ShadingMode::Gouraud, 1, 2));
        // A mode from the command line outside the list goes on to the first after off.
        let mut l = Look::of(&Settings::new(8, 8).with_msaa(16), 0.5);
        l.next_antialiasing();
        assert_eq!((l.msaa, l.ssaa), (4, 1));
    }

    #[test]
    fn the_untouched_look_and_parts_give_back_the_command_lines_frame() {
        let a = args(&["--filter", "ewa", "--shadows=false", "--toon", "off"]);
        let given = Parts::of(&a);
        assert!(!given.is_on(Part::Shadows) && !given.is_on(Part::Toon));
        assert!(given.is_on(Part::NormalMaps));
        let same = given.apply(&given, &a);
        assert_eq!(same.shadows, Some(false));
        assert_eq!(same.relief.normal_maps, None);
        let settings = Settings::new(8, 8);
        let look = Look::of(&settings, 0.5);
        assert_eq!(look.apply(&settings), settings);
    }

    #[test]
    fn a_switched_part_sets_its_flag_and_switching_back_restores_the_given_one() {
        let a = args(&["--parallax", "off"]);
        let given = Parts::of(&a);
        for (_, part, _) in PARTS {
            let t = given.toggled(part);
            assert_ne!(t.is_on(part), given.is_on(part));
            let b = t.apply(&given, &a);
            let set = match part {
                Part::Shadows => b.shadows == Some(false),
                Part::NormalMaps => b.relief.normal_maps == Some(Switch::Off),
                Part::BumpMaps => b.relief.bump_maps == Some(Switch::Off),
                Part::Parallax => b.relief.parallax == Some(ParallaxArg::Occlusion),
                Part::Displacement => b.relief.displacement == Some(Switch::Off),
                Part::Layers => b.layers == Some(Switch::Off),
                Part::LightMaps => b.light_maps == Some(Switch::Off),
                Part::Toon => b.toon == Some(Switch::Off),
                Part::Projectors => b.projectors == Some(Switch::Off),
                Part::Reflections => b.reflections == Some(Switch::Off),
            };
            assert!(set, "{part:?}");
            let back = t.toggled(part);
            assert_eq!(back, given);
            let b = back.apply(&given, &a);
            assert_eq!(b.relief.parallax, Some(ParallaxArg::Off));
            assert_eq!(b.shadows, None);
        }
    }
}
