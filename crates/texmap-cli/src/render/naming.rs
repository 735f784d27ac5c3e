//! Output names: `-o`'s pattern and its placeholders.
//!
//! - `{frame}`: the frame number, counted from 1, zero-padded to 4 digits (`0001`);
//!   `{frame:06}` pads to 6 (any width 1–9; a number wider than the width is written whole).
//! - `{scene}`: the input's file name up to its first dot (`Duck.glb` → `Duck`,
//!   `scan.nii.gz` → `scan`), or the built-in scene's name (`builtin:demo` → `demo`).
//!
//! Any other `{…}` is refused, so a mistyped placeholder cannot write every output to one
//! literal name.

use std::path::{Path, PathBuf};

use texmap::Error;

/// One piece of a pattern.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Piece {
    Text(String),
    Frame { width: usize },
    Scene,
}

/// A parsed `-o` pattern.
#[derive(Clone, Debug)]
pub struct NamePattern {
    raw: PathBuf,
    pieces: Vec<Piece>,
}

impl NamePattern {
    /// Parses `path`'s placeholders.
    ///
    /// # Errors
    /// [`Error::Parameter`]: an unknown placeholder, a bad width, an unclosed brace.
    pub fn parse(path: &Path) -> Result<NamePattern, Error> {
        let text = path.to_string_lossy();
        let bad = |what: &str| {
            Error::parameter(format!(
                "-o {text}: {what} (placeholders: {{frame}}, {{frame:06}}, {{scene}})"
            ))
        };
        let mut pieces = Vec::new();
        let mut rest: &str = &text;
        while let Some(open) = rest.find('{') {
            if open > 0 {
                pieces.push(Piece::Text(rest[..open].to_string()));
            }
            let close = rest[open..]
                .find('}')
                .ok_or_else(|| bad("a '{' is not closed"))?;
            let name = &rest[open + 1..open + close];
            pieces.push(match name {
                "frame" => Piece::Frame { width: 4 },
                "scene" => Piece::Scene,
                _ => match name.strip_prefix("frame:") {
                    Some(w) => {
                        let width: usize = w
                            .trim_start_matches('0')
                            .parse()
                            .ok()
                            .filter(|n| (1..=9).contains(n) && w.starts_with('0'))
                            .ok_or_else(|| bad(&format!("{{{name}}} needs a width 01–09")))?;
                        Piece::Frame { width }
                    }
                    None => return Err(bad(&format!("unknown placeholder {{{name}}}"))),
                },
            });
            rest = &rest[open + close + 1..];
        }
        if !rest.is_empty() {
            pieces.push(Piece::Text(rest.to_string()));
        }
        Ok(NamePattern {
            raw: path.to_path_buf(),
            pieces,
        })
    }

    /// The pattern as given.
    pub fn raw(&self) -> &Path {
        &self.raw
    }

    /// True when every frame gets its own name.
    pub fn has_frame(&self) -> bool {
        self.pieces.iter().any(|p| matches!(p, Piece::Frame { .. }))
    }

    /// True when every input gets its own name.
    pub fn has_scene(&self) -> bool {
        self.pieces.contains(&Piece::Scene)
    }

    /// The name of `scene`'s frame `frame` (1-based).
    pub fn fill(&self, scene: &str, frame: u32) -> PathBuf {
        let mut s = String::new();
        for p in &self.pieces {
            match p {
                Piece::Text(t) => s.push_str(t),
                Piece::Frame { width } => s.push_str(&format!("{frame:0width$}")),
                Piece::Scene => s.push_str(scene),
            }
        }
        PathBuf::from(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fill(p: &str, scene: &str, frame: u32) -> String {
        let n = NamePattern::parse(Path::new(p)).unwrap();
        n.fill(scene, frame).to_string_lossy().into_owned()
    }

    #[test]
    fn placeholders_are_filled() {
        assert_eq!(
            fill("out/{scene}_{frame}.png", "Duck", 7),
            "out/Duck_0007.png"
        );
        assert_eq!(fill("f{frame:06}.exr", "x", 42), "f000042.exr");
        assert_eq!(fill("f{frame:02}.exr", "x", 360), "f360.exr");
        assert_eq!(fill("plain.png", "x", 3), "plain.png");
        let n = NamePattern::parse(Path::new("{scene}.png")).unwrap();
        assert!(n.has_scene() && !n.has_frame());
    }

    #[test]
    fn unknown_placeholders_are_refused() {
        for bad in [
            "{frames}.png",
            "{frame:6}.png",
            "{frame:00}.png",
            "a{b.png",
            "{Scene}.png",
        ] {
            let e = NamePattern::parse(Path::new(bad)).unwrap_err().to_string();
            assert!(e.contains("-o") && e.contains("placeholders"), "{e}");
        }
    }
}
