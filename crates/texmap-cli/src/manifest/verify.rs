//! `texmap manifest verify FILE…`: re-hashes every output the manifests name and checks
//! that the batch is whole.
//!
//! Checked: each line parses; each output exists with the bytes and SHA-256 its line
//! records; an output recorded twice (a resumed run) has one hash; and for each input and
//! settings, every frame of the recorded `frame_range` is held by exactly one output (none
//! missing, none twice). Relative output paths are read from `--root` (default: the current
//! folder), as the render that wrote them was run. One line per problem, a summary, and exit
//! 1 when there was any.

use std::collections::{BTreeMap, HashMap};
use std::path::PathBuf;

use clap::{Args, Subcommand};
use serde_json::Value;
use texmap::Error;

/// `texmap manifest`.
#[derive(Args)]
pub struct ManifestArgs {
    #[command(subcommand)]
    command: ManifestCommand,
}

#[derive(Subcommand)]
enum ManifestCommand {
    /// Re-hash every output the manifests list, and check that no frame is missing or twice.
    Verify(VerifyArgs),
}

#[derive(Args)]
struct VerifyArgs {
    /// Manifests written by `texmap render --manifest` (several: the shards' files).
    #[arg(required = true)]
    manifests: Vec<PathBuf>,
    /// The folder relative output paths are read from [default: the current folder].
    #[arg(long, value_name = "DIR")]
    root: Option<PathBuf>,
}

/// Runs `texmap manifest …`; `Ok(false)` when problems were found (each printed).
pub fn run(args: ManifestArgs) -> Result<bool, Error> {
    let ManifestCommand::Verify(args) = args.command;
    let mut problems = 0u64;
    let mut report = |m: String| {
        problems += 1;
        crate::output::stderr_line(&format!("texmap: manifest verify: {m}"));
    };
    // output → (sha256, where first recorded)
    let mut outputs: HashMap<String, (String, String)> = HashMap::new();
    // (input, settings) → frame → outputs holding it
    let mut coverage: BTreeMap<(String, String), BTreeMap<u32, Vec<String>>> = BTreeMap::new();
    let mut ranges: HashMap<(String, String), (u32, u32)> = HashMap::new();
    let mut lines = 0u64;
    for manifest in &args.manifests {
        let text = std::fs::read_to_string(manifest).map_err(|e| Error::io(manifest, e))?;
        for (n, line) in text.lines().enumerate() {
            let at = format!("{}:{}", manifest.display(), n + 1);
            if line.trim().is_empty() {
                continue;
            }
            lines += 1;
            let Ok(v) = serde_json::from_str::<Value>(line) else {
                report(format!("{at}: not a JSON line"));
                continue;
            };
            let (Some(output), Some(bytes), Some(sha)) = (
                v["output"].as_str(),
                v["bytes"].as_u64(),
                v["sha256"].as_str(),
            ) else {
                report(format!("{at}: lacks output, bytes or sha256"));
                continue;
            };
            if let Some((old, first)) = outputs.get(output) {
                if old != sha {
                    report(format!(
                        "{at}: {output} recorded with another SHA-256 at {first}"
                    ));
                }
                continue;
            }
            outputs.insert(output.to_string(), (sha.to_string(), at.clone()));
            let path = match &args.root {
                Some(root) => root.join(output),
                None => PathBuf::from(output),
            };
            match super::hash_file(&path) {
                Err(_) if !path.exists() => report(format!("{at}: {output} is missing")),
                Err(e) => report(format!("{at}: {e}")),
                Ok((b, _)) if b != bytes => report(format!(
                    "{at}: {output} has {b} bytes, the manifest says {bytes}"
                )),
                Ok((_, h)) if h != sha => report(format!(
                    "{at}: {output}: SHA-256 differs from the manifest's"
                )),
                Ok(_) => {}
            }
            let key = (
                v["input"].as_str().unwrap_or("").to_string(),
                v["settings"].to_string(),
            );
            if let (Some(a), Some(b)) = (v["frames"][0].as_u64(), v["frames"][1].as_u64()) {
                let frames = coverage.entry(key.clone()).or_default();
                for k in a..=b {
                    frames.entry(k as u32).or_default().push(output.to_string());
                }
            }
            let range = &v["settings"]["frame_range"];
            if let (Some(a), Some(b)) = (range[0].as_u64(), range[1].as_u64()) {
                ranges.insert(key, (a as u32, b as u32));
            }
        }
    }
    for (key, frames) in &coverage {
        let input = &key.0;
        for (k, holders) in frames {
            if holders.len() > 1 {
                report(format!(
                    "{input}: frame {k} is in {} outputs: {}",
                    holders.len(),
                    holders.join(", ")
                ));
            }
        }
        if let Some(&(a, b)) = ranges.get(key) {
            let missing: Vec<u32> = (a..=b).filter(|k| !frames.contains_key(k)).collect();
            if !missing.is_empty() {
                report(format!(
                    "{input}: {} of frames {a}..{b} missing (first: {})",
                    missing.len(),
                    missing
                        .iter()
                        .take(10)
                        .map(u32::to_string)
                        .collect::<Vec<_>>()
                        .join(", ")
                ));
            }
        }
    }
    crate::output::stdout(&format!(
        "verified {} outputs ({lines} lines, {} inputs) from {} manifest{}: {}\n",
        outputs.len(),
        coverage.len(),
        args.manifests.len(),
        if args.manifests.len() == 1 { "" } else { "s" },
        if problems == 0 {
            "all match".to_string()
        } else {
            format!("{problems} problem{}", if problems == 1 { "" } else { "s" })
        }
    ))?;
    Ok(problems == 0)
}
