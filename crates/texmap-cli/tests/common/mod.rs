//! What the command-line tests share: running the `texmap` binary and a fresh scratch folder.

#![allow(dead_code)]

use std::path::PathBuf;
use std::process::{Command, Output};

/// Runs the `texmap` binary built for these tests with `args`.
pub fn texmap(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_texmap"))
        .args(args)
        .output()
        .expect("the texmap binary runs")
}

/// An empty folder `texmap-<suite>-<pid>-<name>` in the system's temporary folder (emptied
/// first if a previous run left it).
pub fn fresh_dir(suite: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("texmap-{suite}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}
