//! Wrap modes: what a texel index outside the image reads, per axis, with OpenGL semantics.

use super::UnknownName;

/// What a texel index outside `[0, n)` reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Wrap {
    /// The image tiles the plane (`GL_REPEAT`).
    #[default]
    Repeat,
    /// The image tiles the plane, every other copy mirrored (`GL_MIRRORED_REPEAT`).
    MirroredRepeat,
    /// Indices clamp to the edge texels (`GL_CLAMP_TO_EDGE`).
    ClampToEdge,
    /// Indices outside read the sampler's border colour (`GL_CLAMP_TO_BORDER`).
    ClampToBorder,
    /// Mirrored once about the origin, then clamped (`GL_MIRROR_CLAMP_TO_EDGE`).
    MirrorClampToEdge,
}

/// The index [`Wrap::index`] returns for "read the border colour".
pub const BORDER: i32 = -1;

impl Wrap {
    /// Maps texel index `i` on an axis of `n` texels to an index in `[0, n)`, or to [`BORDER`].
    #[inline(always)]
    #[must_use]
    pub fn index(self, i: i32, n: i32) -> i32 {
        match self {
            // In range is the common case: skip the division.
            Wrap::Repeat if (i as u32) < (n as u32) => i,
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::ClampToEdge => i.clamp(0, n - 1),
            Wrap::ClampToBorder => {
                if (0..n).contains(&i) {
                    i
                } else {
                    BORDER
                }
            }
            Wrap::MirroredRepeat => {
                let m = i.rem_euclid(2 * n);
                if m >= n {
                    2 * n - 1 - m
                } else {
                    m
                }
            }
            Wrap::MirrorClampToEdge => {
                let m = if i >= 0 { i } else { -1 - i };
                m.min(n - 1)
            }
        }
    }

    /// Every spelling [`Wrap::parse`] accepts, as `--help` text and error messages list them.
    pub const SPELLINGS: &'static str = "repeat, mirror, clamp, border, mirror-clamp \
        (or OpenGL's mirrored-repeat, clamp-to-edge, clamp-to-border, mirror-clamp-to-edge)";

    /// Each mode's short name and OpenGL's, in [`Wrap::SPELLINGS`] order.
    const NAMES: [(&'static str, &'static str, Wrap); 5] = [
        ("repeat", "repeat", Wrap::Repeat),
        ("mirror", "mirrored-repeat", Wrap::MirroredRepeat),
        ("clamp", "clamp-to-edge", Wrap::ClampToEdge),
        ("border", "clamp-to-border", Wrap::ClampToBorder),
        (
            "mirror-clamp",
            "mirror-clamp-to-edge",
            Wrap::MirrorClampToEdge,
        ),
    ];

    /// Parses one of [`Wrap::SPELLINGS`].
    ///
    /// ```
    /// use texmap::texture::Wrap;
    /// assert_eq!(Wrap::parse("mirror"), Ok(Wrap::MirroredRepeat));
    /// assert_eq!(Wrap::parse("clamp-to-edge"), Ok(Wrap::ClampToEdge));
    /// assert!(Wrap::parse("wrap").is_err());
    /// ```
    pub fn parse(s: &str) -> Result<Wrap, UnknownName> {
        Self::NAMES
            .iter()
            .find(|(short, gl, _)| *short == s || *gl == s)
            .map(|&(.., w)| w)
            .ok_or_else(|| UnknownName {
                given: s.to_string(),
                expected: Wrap::SPELLINGS,
            })
    }

    /// The short spelling of this mode (`mirror` for [`Wrap::MirroredRepeat`]), which
    /// [`Wrap::parse`] reads back.
    #[must_use]
    pub fn name(self) -> &'static str {
        Self::NAMES
            .iter()
            .find(|(.., w)| *w == self)
            .map(|&(short, ..)| short)
            .expect("every wrap mode has a name")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(w: Wrap, n: i32) -> Vec<i32> {
        (-5..8).map(|i| w.index(i, n)).collect()
    }

    #[test]
    fn repeat_on_three_texels() {
        assert_eq!(
            row(Wrap::Repeat, 3),
            [1, 2, 0, 1, 2, 0, 1, 2, 0, 1, 2, 0, 1]
        );
    }

    #[test]
    fn mirrored_repeat_on_three_texels() {
        // ... 2 1 0 | 0 1 2 | 2 1 0 | 0 1 ...
        assert_eq!(
            row(Wrap::MirroredRepeat, 3),
            [1, 2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0, 1]
        );
    }

    #[test]
    fn clamp_to_edge_on_three_texels() {
        assert_eq!(
            row(Wrap::ClampToEdge, 3),
            [0, 0, 0, 0, 0, 0, 1, 2, 2, 2, 2, 2, 2]
        );
    }

    #[test]
    fn clamp_to_border_on_three_texels() {
        let b = BORDER;
        assert_eq!(
            row(Wrap::ClampToBorder, 3),
            [b, b, b, b, b, 0, 1, 2, b, b, b, b, b]
        );
    }

    #[test]
    fn mirror_clamp_on_three_texels() {
        // -5..-1 mirror to 4..0, then clamp to 2.
        assert_eq!(
            row(Wrap::MirrorClampToEdge, 3),
            [2, 2, 2, 1, 0, 0, 1, 2, 2, 2, 2, 2, 2]
        );
    }

    #[test]
    fn every_name_parses_back_and_is_listed() {
        for (short, gl, w) in Wrap::NAMES {
            assert_eq!(Wrap::parse(short), Ok(w));
            assert_eq!(Wrap::parse(gl), Ok(w));
            assert_eq!(Wrap::parse(w.name()), Ok(w));
            assert!(Wrap::SPELLINGS.contains(short) && Wrap::SPELLINGS.contains(gl));
        }
        let e = Wrap::parse("tile").unwrap_err();
        assert_eq!(e.given, "tile");
        assert_eq!(
            e.to_string(),
            format!("expected one of: {}", Wrap::SPELLINGS)
        );
    }

    #[test]
    fn single_texel_axis() {
        for w in [
            Wrap::Repeat,
            Wrap::MirroredRepeat,
            Wrap::ClampToEdge,
            Wrap::MirrorClampToEdge,
        ] {
            assert!((-4..4).all(|i| w.index(i, 1) == 0), "{w:?}");
        }
    }
}
