//! Same inputs, same image, whatever the thread count: every scene kind (built-in meshes,
//! files, procedural and solid textures, volumes ray marched and sliced, each volume mode,
//! a volume with a mesh inside, depth sorting, multisampling) rendered with 1, 2 and 3
//! threads must give the same PNG bytes.

use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn render(args: &[&str], threads: usize, out: &Path) -> Vec<u8> {
    let o = Command::new(env!("CARGO_BIN_EXE_texmap"))
        .arg("render")
        .args(args)
        .args([
            "--size",
            "96x72",
            "--quiet",
            "--threads",
            &threads.to_string(),
        ])
        .arg("-o")
        .arg(out)
        .current_dir(repo())
        .output()
        .expect("run texmap");
    assert!(
        o.status.success(),
        "{args:?} --threads {threads}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    std::fs::read(out).unwrap()
}

#[test]
fn every_scene_kind_is_the_same_at_one_two_and_three_threads() {
    let d = std::env::temp_dir().join(format!("texmap-determinism-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let cases: &[&[&str]] = &[
        &["builtin:plane", "--filter", "ewa"],
        &["builtin:plane", "--filter", "aniso8"],
        &["builtin:plane", "--filter", "trilinear", "--msaa", "4"],
        &["builtin:sphere", "--shading", "phong", "--ssaa", "2"],
        &["builtin:demo"],
        &["builtin:marble"],
        &["scenes/shapes.toml", "--visibility", "depth-sort"],
        &["scenes/textures.toml"],
        &["scenes/channels.toml"],
        &["scenes/procedural.toml"],
        &["scenes/solid_texture3d.toml"],
        &["scenes/volume.toml"],
        &["scenes/volumes/cell.nrrd"],
        &["scenes/volumes/cell.nrrd", "--method", "slices"],
        &["scenes/volumes/cell.nrrd", "--mode", "mip"],
        &["scenes/volumes/cell.nrrd", "--mode", "iso"],
        &["scenes/volumes/cell.nrrd", "--classification", "preint"],
    ];
    for (i, args) in cases.iter().enumerate() {
        let out = d.join(format!("{i}.png"));
        let one = render(args, 1, &out);
        for threads in [2, 3] {
            assert!(
                render(args, threads, &out) == one,
                "{args:?}: --threads {threads} differs from --threads 1"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&d);
}
