//! The farm recipes of `docs/cluster/` run here as their engine would run them: the Slurm array
//! script once per task with Slurm's variables (the array read from its `#SBATCH --array`
//! line), the Kubernetes Indexed Job's command once per completion index (its count and
//! script read from the manifest), each with `texmap` on the PATH; then their verify steps.
//! Sizes are shrunk through the recipes' own variables; the frame counts stay.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn dir(name: &str) -> PathBuf {
    common::fresh_dir("recipes", name)
}

/// A folder holding `texmap` (a link to the binary under test), a scene and four models.
fn workspace(name: &str) -> (PathBuf, String) {
    let d = dir(name);
    let bin = d.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_texmap"), bin.join("texmap")).unwrap();
    let shapes = std::fs::read_to_string(repo().join("scenes/shapes.toml")).unwrap();
    std::fs::write(d.join("model.toml"), &shapes).unwrap();
    let models = d.join("models");
    std::fs::create_dir_all(&models).unwrap();
    for n in ["a", "b", "c", "d"] {
        std::fs::write(models.join(format!("{n}.toml")), &shapes).unwrap();
    }
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    (d, path)
}

fn count(d: &Path) -> usize {
    std::fs::read_dir(d).map_or(0, |r| r.count())
}

fn check_outputs(out: &Path) {
    assert_eq!(count(&out.join("turntable")), 360, "a 360-frame turntable");
    assert_eq!(count(&out.join("models")), 4, "one image per model");
}

#[test]
fn the_slurm_array_script_renders_and_verifies() {
    let script = repo().join("docs/cluster/slurm-render.sbatch");
    let text = std::fs::read_to_string(&script).unwrap();
    // The array as Slurm reads it: `#SBATCH --array=MIN-MAX`.
    let array = text
        .lines()
        .find_map(|l| l.strip_prefix("#SBATCH --array="))
        .expect("an --array line");
    let (min, max) = array.split_once('-').unwrap();
    let (min, max): (u32, u32) = (min.parse().unwrap(), max.trim().parse().unwrap());
    let (d, path) = workspace("slurm");
    let out = d.join("out");
    for id in min..=max {
        let r = Command::new("bash")
            .arg(&script)
            .current_dir(&d)
            .env("PATH", &path)
            .env("SCENE", "model.toml")
            .env("MODELS", "models")
            .env("OUT", &out)
            .env("SIZE", "32x24")
            .env("SLURM_ARRAY_TASK_ID", id.to_string())
            .env("SLURM_ARRAY_TASK_MIN", min.to_string())
            .env("SLURM_ARRAY_TASK_MAX", max.to_string())
            .env("SLURM_ARRAY_TASK_COUNT", (max - min + 1).to_string())
            .env("SLURM_CPUS_PER_TASK", "1")
            .env_remove("JOB_COMPLETION_INDEX")
            .output()
            .unwrap();
        assert!(
            r.status.success(),
            "task {id}: {}",
            String::from_utf8_lossy(&r.stderr)
        );
    }
    check_outputs(&out);
    let r = Command::new("bash")
        .arg(repo().join("docs/cluster/slurm-verify.sbatch"))
        .current_dir(&d)
        .env("PATH", &path)
        .env("OUT", &out)
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let stdout = String::from_utf8_lossy(&r.stdout);
    assert!(
        stdout.contains("verified 360 outputs") && stdout.contains("verified 4 outputs"),
        "{stdout}"
    );
}

/// The YAML block scalar after the line `- |` following `args:` in `doc`, dedented.
fn args_script(doc: &str) -> String {
    let lines: Vec<&str> = doc.lines().collect();
    let start = lines
        .iter()
        .position(|l| l.trim() == "- |")
        .expect("an args block scalar")
        + 1;
    let indent = lines[start].len() - lines[start].trim_start().len();
    lines[start..]
        .iter()
        .take_while(|l| l.trim().is_empty() || l.len() - l.trim_start().len() >= indent)
        .map(|l| l.get(indent..).unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// A `key: value` of `doc` (the first).
fn value<'a>(doc: &'a str, key: &str) -> Option<&'a str> {
    doc.lines()
        .find_map(|l| l.trim().strip_prefix(&format!("{key}:")))
        .map(str::trim)
}

#[test]
fn the_kubernetes_indexed_job_renders_and_verifies() {
    let text = std::fs::read_to_string(repo().join("docs/cluster/k8s-render.yaml")).unwrap();
    let docs: Vec<&str> = text.split("\n---\n").collect();
    let job = docs
        .iter()
        .find(|d| value(d, "completionMode") == Some("Indexed"))
        .expect("an Indexed Job");
    let completions: u32 = value(job, "completions").unwrap().parse().unwrap();
    let script = args_script(job);
    assert!(
        script.contains(&format!("--shard-count {completions}")),
        "--shard-count equals completions"
    );
    // The variables the script reads are the container's (the test gives smaller values).
    for v in ["SCENE", "MODELS", "OUT", "SIZE"] {
        assert!(script.contains(&format!("${v}")) && job.contains(&format!("- name: {v}")));
    }
    let (d, path) = workspace("k8s");
    let out = d.join("out");
    for index in 0..completions {
        let r = Command::new("sh")
            .args(["-c", &script])
            .current_dir(&d)
            .env("PATH", &path)
            .env("SCENE", "model.toml")
            .env("MODELS", "models")
            .env("OUT", &out)
            .env("SIZE", "32x24")
            .env("JOB_COMPLETION_INDEX", index.to_string())
            .env_remove("SLURM_ARRAY_TASK_ID")
            .output()
            .unwrap();
        assert!(
            r.status.success(),
            "index {index}: {}",
            String::from_utf8_lossy(&r.stderr)
        );
    }
    check_outputs(&out);
    let verify = docs
        .iter()
        .find(|d| d.contains("manifest verify"))
        .expect("a verify job");
    let r = Command::new("sh")
        .args(["-c", &args_script(verify)])
        .current_dir(&d)
        .env("PATH", &path)
        .env("OUT", &out)
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(String::from_utf8_lossy(&r.stdout).contains("verified 360 outputs"));
}
