//! Volumes beyond a single scan: presets against the peer's own file.
//!
//! Tolerances, stated once:
//! - Presets: the same numbers as `vtk_volume.py` (exact, as parsed from both texts).

use std::path::Path;

use texmap::volume::transfer::PRESETS;
use texmap::volume::TransferFunction;

/// The string literals of `vtk_volume.py`'s `PRESETS = { "name": "…" "…", … }` (adjacent
/// literals concatenated, `#` comments skipped).
fn python_presets(src: &str) -> Vec<(String, String)> {
    let start = src.find("PRESETS = {").expect("PRESETS in vtk_volume.py") + 11;
    let mut out: Vec<(String, String)> = Vec::new();
    let mut strings: Vec<String> = Vec::new();
    let mut key: Option<String> = None;
    let mut chars = src[start..].chars();
    while let Some(c) = chars.next() {
        match c {
            '#' => {
                for c in chars.by_ref() {
                    if c == '\n' {
                        break;
                    }
                }
            }
            '"' => strings.push(chars.by_ref().take_while(|&c| c != '"').collect()),
            ':' => key = strings.pop(),
            ',' | '}' => {
                if let Some(k) = key.take() {
                    out.push((k, strings.concat()));
                }
                strings.clear();
                if c == '}' {
                    break;
                }
            }
            _ => {}
        }
    }
    out
}

#[test]
fn presets_use_the_points_of_vtk_volume_py() {
    let peer = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/peers/vtk_volume.py");
    let Ok(src) = std::fs::read_to_string(&peer) else {
        eprintln!("SKIPPED: {} is absent", peer.display());
        return;
    };
    let theirs = python_presets(&src);
    assert!(theirs.len() >= 3, "parsed {theirs:?}");
    for (name, points) in &theirs {
        let Some(ours) = TransferFunction::preset(name) else {
            panic!("vtk_volume.py has a preset {name:?} that texmap lacks");
        };
        let peer_tf = TransferFunction::parse(points).expect("the peer's points parse");
        assert_eq!(ours.points(), peer_tf.points(), "{name}");
    }
    // The five presets texmap promises.
    for name in ["ct-bone", "ct-skin", "ct-muscle", "mri", "synth"] {
        assert!(PRESETS.iter().any(|p| p.0 == name), "{name}");
    }
}
