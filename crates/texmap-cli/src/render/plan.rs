//! A render's plan, made before anything is loaded: its inputs (SCENE arguments, folders,
//! `--list`), its frames (`--frames`, `--frame-range`), each output's name (`naming.rs`) and
//! the slice this process renders (`shard.rs`).
//!
//! The outputs are in one fixed order: the inputs as given (a folder's models sorted by
//! name, a list's lines in order), and within an input its frames in order. An output is one
//! frame where the name has `{frame}`; otherwise an input's one output holds all its frames
//! (an animation) or its only frame. Every problem the plan can see — a bad range or shard,
//! two outputs with one name, a folder without a model — is one line before any rendering.

use std::collections::HashMap;
use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};

use texmap::Error;

use super::args::RenderArgs;
use super::naming::NamePattern;
use super::shard::{self, Shard};
use crate::formats::OutputFormat;

/// The model files a folder given as SCENE contributes.
pub const FOLDER_EXTENSIONS: [&str; 4] = ["gltf", "glb", "obj", "toml"];

/// One input: what is handed to the loader, and its `{scene}` name.
#[derive(Clone, Debug)]
pub struct Input {
    pub name: String,
    pub stem: String,
}

/// One output: an input and the frames (1-based) it holds.
#[derive(Clone, Debug)]
pub struct Job {
    pub input: usize,
    pub frames: RangeInclusive<u32>,
    pub path: PathBuf,
}

/// What a `texmap render` call renders.
pub struct Plan {
    pub inputs: Vec<Input>,
    /// `--frames`: the turntable's frame count (frame k is turned by 360·(k−1)/N degrees).
    pub frames: u32,
    /// `--frame-range`, or every frame.
    pub range: RangeInclusive<u32>,
    pub pattern: NamePattern,
    /// One output per frame (`{frame}` in the name).
    pub per_frame: bool,
    pub shard: Shard,
}

impl Plan {
    /// The plan of `args`, whose output is `format`.
    ///
    /// # Errors
    /// [`Error::Parameter`] or [`Error::Io`], one line naming the flag or file.
    pub fn new(args: &RenderArgs, format: OutputFormat) -> Result<Plan, Error> {
        let frames = args.frames;
        let range = match &args.frame_range {
            Some(r) => parse_range(r, frames)?,
            None => 1..=frames,
        };
        let shard = shard::resolve(args.shard.as_deref(), args.shard_count, |k| {
            std::env::var(k).ok()
        })?;
        let inputs = inputs(&args.inputs, args.list.as_deref())?;
        let count = range.end() - range.start() + 1;
        let pattern = match &args.output {
            Some(p) => NamePattern::parse(p)?,
            None => {
                let ext = format.extension();
                let name = if count > 1 && !format.is_animated() {
                    format!("texmap-{{scene}}-{{frame}}.{ext}")
                } else {
                    format!("texmap-{{scene}}.{ext}")
                };
                NamePattern::parse(Path::new(&name))?
            }
        };
        let per_frame = pattern.has_frame();
        let raw = pattern.raw().display().to_string();
        if count > 1 && !per_frame && !format.is_animated() {
            return Err(Error::parameter(format!(
                "-o {raw}: {count} frames would all write this one file; put {{frame}} in the \
                 name (e.g. turn_{{frame}}.png) or write an animation (.gif, .apng)"
            )));
        }
        if inputs.len() > 1 && !pattern.has_scene() {
            return Err(Error::parameter(format!(
                "-o {raw}: {} inputs would all write the same name{}; put {{scene}} in it \
                 (e.g. out/{{scene}}.png)",
                inputs.len(),
                if per_frame { "s" } else { "" }
            )));
        }
        let mut seen: HashMap<PathBuf, &str> = HashMap::new();
        for input in &inputs {
            let name = pattern.fill(&input.stem, *range.start());
            if let Some(other) = seen.insert(name.clone(), &input.name) {
                return Err(Error::parameter(format!(
                    "-o {raw}: {other} and {} would both write {}",
                    input.name,
                    name.display()
                )));
            }
        }
        Ok(Plan {
            inputs,
            frames,
            range,
            pattern,
            per_frame,
            shard,
        })
    }

    /// Outputs per input.
    fn per_input(&self) -> u64 {
        if self.per_frame {
            u64::from(self.range.end() - self.range.start() + 1)
        } else {
            1
        }
    }

    /// Every output of the batch, all shards.
    pub fn total(&self) -> u64 {
        self.inputs.len() as u64 * self.per_input()
    }

    /// Output `j` of the batch.
    pub fn job(&self, j: u64) -> Job {
        let per = self.per_input();
        let input = (j / per) as usize;
        let frames = if self.per_frame {
            let k = self.range.start() + (j % per) as u32;
            k..=k
        } else {
            self.range.clone()
        };
        let path = self.pattern.fill(&self.inputs[input].stem, *frames.start());
        Job {
            input,
            frames,
            path,
        }
    }

    /// This shard's outputs, grouped by input (in order).
    pub fn shard_jobs(&self) -> Vec<(usize, Vec<Job>)> {
        let mut groups: Vec<(usize, Vec<Job>)> = Vec::new();
        for j in self.shard.range(self.total()) {
            let job = self.job(j);
            match groups.last_mut() {
                Some((i, jobs)) if *i == job.input => jobs.push(job),
                _ => groups.push((job.input, vec![job])),
            }
        }
        groups
    }
}

/// `A..B` (inclusive, 1-based) or `A` within `1..=frames`.
fn parse_range(s: &str, frames: u32) -> Result<RangeInclusive<u32>, Error> {
    let bad = |why: &str| Error::parameter(format!("--frame-range {s}: {why}"));
    let (a, b) = s.split_once("..").unwrap_or((s, s));
    let num = |t: &str| {
        t.trim()
            .parse::<u32>()
            .map_err(|_| bad("expected A..B, two frame numbers counted from 1 (e.g. 1..90)"))
    };
    let (a, b) = (num(a)?, num(b)?);
    if a == 0 {
        return Err(bad("frames are counted from 1"));
    }
    if a > b {
        return Err(bad("the first frame is after the last"));
    }
    if b > frames {
        return Err(bad(&format!(
            "--frames is {frames}, so the last frame is {frames}"
        )));
    }
    Ok(a..=b)
}

/// The `{scene}` name of an input.
pub(crate) fn stem(name: &str) -> String {
    if let Some(b) = name.strip_prefix("builtin:") {
        return b.to_string();
    }
    let path = Path::new(name);
    if crate::volume::is_volume_path(name) {
        return crate::volume::short_name(path);
    }
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into())
}

/// SCENE arguments (a folder: its models, sorted) and `--list`'s lines; `builtin:demo`
/// without either.
fn inputs(args: &[String], list: Option<&Path>) -> Result<Vec<Input>, Error> {
    let mut names: Vec<String> = args.to_vec();
    if let Some(list) = list {
        let text = std::fs::read(list).map_err(|e| {
            Error::parameter(format!("--list {}: cannot read it: {e}", list.display()))
        })?;
        let text = String::from_utf8(text).map_err(|_| {
            Error::parameter(format!("--list {}: is not UTF-8 text", list.display()))
        })?;
        let before = names.len();
        names.extend(
            text.lines()
                .map(str::trim)
                .filter(|l| !l.is_empty() && !l.starts_with('#'))
                .map(String::from),
        );
        if names.len() == before {
            return Err(Error::parameter(format!(
                "--list {}: names no input (one path a line; # starts a comment)",
                list.display()
            )));
        }
    }
    if names.is_empty() {
        names.push("builtin:demo".into());
    }
    let mut out = Vec::new();
    for name in names {
        if std::fs::metadata(&name).is_ok_and(|m| m.is_dir()) {
            let models = folder_models(Path::new(&name))?;
            out.extend(models.into_iter().map(|p| {
                let name = p.to_string_lossy().into_owned();
                Input {
                    stem: stem(&name),
                    name,
                }
            }));
        } else {
            out.push(Input {
                stem: stem(&name),
                name,
            });
        }
    }
    Ok(out)
}

/// A folder's model files (not its subfolders'), sorted by name.
fn folder_models(dir: &Path) -> Result<Vec<PathBuf>, Error> {
    let entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
    let mut models = Vec::new();
    for entry in entries {
        let path = entry.map_err(|e| Error::io(dir, e))?.path();
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        if ext.is_some_and(|e| FOLDER_EXTENSIONS.contains(&e.as_str())) && path.is_file() {
            models.push(path);
        }
    }
    if models.is_empty() {
        return Err(Error::parameter(format!(
            "{}: a folder with no model in it (.gltf, .glb, .obj, .toml)",
            dir.display()
        )));
    }
    models.sort();
    Ok(models)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_ranges_are_inclusive_and_within_the_frames() {
        assert_eq!(parse_range("1..90", 360).unwrap(), 1..=90);
        assert_eq!(parse_range("5", 10).unwrap(), 5..=5);
        for (s, why) in [
            ("9..2", "after"),
            ("0..3", "from 1"),
            ("1..11", "last frame is 10"),
            ("a..b", "expected"),
        ] {
            let e = parse_range(s, 10).unwrap_err().to_string();
            assert!(e.contains("--frame-range") && e.contains(why), "{e}");
        }
    }

    #[test]
    fn scene_names() {
        assert_eq!(stem("builtin:demo"), "demo");
        assert_eq!(stem("a/b/Duck.glb"), "Duck");
        assert_eq!(stem("scan.nii.gz"), "scan");
    }
}
