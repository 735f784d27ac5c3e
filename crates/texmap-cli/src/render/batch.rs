//! The batch: every output of this shard (`plan.rs`), input by input — each input loaded and
//! set up once for all its frames — with `--skip-existing`, the manifest, the signals and a
//! summary.
//!
//! A failure on one input (a bad file, an error while rendering or writing) is reported on
//! its own line and the next input is rendered; the exit is 1 at the end, after a summary
//! line naming how many failed. With a single input the error is the command's, as always:
//! one line, exit 1. SIGINT or SIGTERM stop the batch after the output being written (see
//! `signals.rs`): the exit is 128 + the signal's number, after a line saying how far it got.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use texmap::render::Frame;
use texmap::Error;

use super::args::RenderArgs;
use super::complete::is_complete;
use super::image_out::{self, ImageOut};
use super::plan::{Job, Plan};
use super::shard::Shard;
use super::{limits, prepare, Common};
use crate::manifest::{hash_file, Manifest};
use crate::progress::Progress;
use crate::signals::Stop;

/// What a batch did.
#[derive(Default)]
struct Tally {
    written: u64,
    /// Outputs rendered and not written (`--discard`).
    rendered: u64,
    skipped: u64,
    failed: Vec<String>,
}

/// Runs `texmap render`.
pub fn run(mut args: RenderArgs) -> Result<ExitCode, Error> {
    let threads = limits::frames_and_threads(args.frames, args.threads)?;
    if args.discard {
        check_discard(&args)?;
    }
    if let Some(out) = &args.output {
        let mut inputs: Vec<&Path> = args.inputs.iter().map(Path::new).collect();
        inputs.extend(inputs_of(&args));
        limits::check_output(out, &inputs)?;
    }
    let format = image_out::output_format(&args)?;
    let plan = Plan::new(&args, format)?;
    if args.output.as_deref() == Some(Path::new("-")) {
        for (flag, given) in [
            ("--manifest", args.manifest.is_some()),
            ("--skip-existing", args.skip_existing),
        ] {
            if given {
                return Err(Error::parameter(format!("{flag}: -o - writes no file")));
            }
        }
    }
    let groups = plan.shard_jobs();
    let outputs: u64 = groups.iter().map(|(_, jobs)| jobs.len() as u64).sum();
    let frames_todo: u64 = groups
        .iter()
        .flat_map(|(_, jobs)| jobs)
        .map(|j| u64::from(j.frames.end() - j.frames.start() + 1))
        .sum();
    let common = Common::new(&args, format, threads)?;
    let image = ImageOut::new(&args, format);
    let batch = plan.inputs.len() > 1 || plan.shard != Shard::ALL || args.skip_existing;
    // A single frame keeps the default handlers: Ctrl-C ends it at once, leaving no file.
    let stop = if frames_todo > 1 {
        Stop::install()?
    } else {
        Stop::never()
    };
    let mut manifest = args.manifest.as_deref().map(Manifest::open).transpose()?;
    let recorded = match (&manifest, args.skip_existing) {
        (Some(m), true) => m.recorded(),
        _ => Default::default(),
    };
    let settings = settings_json(&args, &plan, format);
    let progress = Progress::new(frames_todo.min(u64::from(u32::MAX)) as u32, args.quiet);
    progress.message("rendering");
    let mut tally = Tally::default();
    let mut frame = Frame::default();
    for (input_index, jobs) in &groups {
        if stop.asked().is_some() {
            break;
        }
        let input = &plan.inputs[*input_index];
        args.scene = Some(input.name.clone());
        let mut todo: Vec<&Job> = Vec::new();
        for job in jobs {
            let count = job.frames.end() - job.frames.start() + 1;
            if args.skip_existing
                && is_complete(
                    &job.path,
                    format,
                    args.size,
                    if format.is_animated() { count } else { 1 },
                )
            {
                tally.skipped += 1;
                progress.advance(u64::from(count));
                let key = job.path.to_string_lossy();
                if let Some(m) = manifest
                    .as_mut()
                    .filter(|_| !recorded.contains(key.as_ref()))
                {
                    // Finished by a run killed before its manifest line: recorded now.
                    let line = line_json(&plan, job, &settings, None)?;
                    m.append(&line)?;
                }
            } else {
                todo.push(job);
            }
        }
        if todo.is_empty() {
            continue;
        }
        let result = render_input(
            &args,
            &common,
            &image,
            &plan,
            &todo,
            &settings,
            &mut manifest,
            &stop,
            &progress,
            &mut frame,
            &mut tally,
        );
        if let Err(e) = result {
            if plan.inputs.len() == 1 {
                progress.finish();
                return Err(e);
            }
            progress.suspend(|| crate::output::stderr_line(&format!("texmap: {e}")));
            tally.failed.push(input.name.clone());
        }
    }
    progress.finish();
    let shard = if plan.shard == Shard::ALL {
        String::new()
    } else {
        format!("shard {}: ", plan.shard.label())
    };
    if let Some((name, number)) = stop.asked() {
        crate::output::stderr_line(&format!(
            "texmap: stopped by {name}: {shard}{} of {outputs} outputs written, {} skipped, \
             the rest not started (every written file and manifest line is whole; run again \
             with --skip-existing to finish)",
            tally.written, tally.skipped
        ));
        return Ok(ExitCode::from((128 + number).clamp(1, 255) as u8));
    }
    let summary = format!(
        "{shard}{outputs} output{} of {} input{}: {} written, {} skipped (complete), {}{} input{} \
         failed",
        if outputs == 1 { "" } else { "s" },
        plan.inputs.len(),
        if plan.inputs.len() == 1 { "" } else { "s" },
        tally.written,
        tally.skipped,
        if args.discard {
            format!("{} rendered and discarded, ", tally.rendered)
        } else {
            String::new()
        },
        tally.failed.len(),
        if tally.failed.len() == 1 { "" } else { "s" },
    );
    if !tally.failed.is_empty() {
        crate::output::stderr_line(&format!("texmap: {summary}: {}", tally.failed.join(", ")));
        return Ok(ExitCode::FAILURE);
    }
    if batch && !args.quiet {
        crate::output::stderr_line(&format!("texmap: {summary}"));
    }
    Ok(ExitCode::SUCCESS)
}

/// Renders one input's outputs `jobs`, each written and recorded before the next starts.
#[allow(clippy::too_many_arguments)]
fn render_input(
    args: &RenderArgs,
    common: &Common,
    image: &ImageOut,
    plan: &Plan,
    jobs: &[&Job],
    settings: &serde_json::Value,
    manifest: &mut Option<Manifest>,
    stop: &Stop,
    progress: &Progress,
    frame: &mut Frame,
    tally: &mut Tally,
) -> Result<(), Error> {
    if !args.discard {
        for job in jobs {
            limits::check_output(&job.path, &inputs_of(args))?;
        }
    }
    let prepared = prepare(args, common)?;
    let mut times = Vec::new();
    let mut last_path = PathBuf::new();
    for job in jobs {
        if stop.asked().is_some() {
            break;
        }
        if args.discard {
            // The frames back to back, nothing between them.
            for k in job.frames.clone() {
                if stop.asked().is_some() {
                    break;
                }
                let t = Instant::now();
                prepared.render(&common.pool, k, plan.frames, frame)?;
                times.push(t.elapsed().as_secs_f64() * 1e3);
                progress.advance(1);
            }
            tally.rendered += 1;
            continue;
        }
        let start = Instant::now();
        if image.format.is_animated() {
            let count = job.frames.end() - job.frames.start() + 1;
            let sink = crate::output::Sink::open(&job.path)?;
            let fps = args.fps.unwrap_or(25);
            let size = args.size;
            match sink {
                crate::output::Sink::File(mut file) => {
                    let real = file.path.clone();
                    let mut w = std::io::BufWriter::new(&mut file.file);
                    let mut anim = crate::animation::Animation::new(
                        &mut w,
                        &real,
                        image.format,
                        image.store,
                        count,
                        fps,
                        size,
                    )?;
                    for k in job.frames.clone() {
                        if stop.asked().is_some() {
                            // The temporary file is removed: nothing half-written stays.
                            return Ok(());
                        }
                        let t = Instant::now();
                        prepared.render(&common.pool, k, plan.frames, frame)?;
                        times.push(t.elapsed().as_secs_f64() * 1e3);
                        anim.push(frame)?;
                        progress.advance(1);
                    }
                    anim.finish()?;
                    std::io::Write::flush(&mut w).map_err(|e| Error::io(&real, e))?;
                    drop(w);
                    file.commit()?;
                }
                crate::output::Sink::Stream(mut w, p) => {
                    let mut anim = crate::animation::Animation::new(
                        &mut w,
                        &p,
                        image.format,
                        image.store,
                        count,
                        fps,
                        size,
                    )?;
                    for k in job.frames.clone() {
                        let t = Instant::now();
                        prepared.render(&common.pool, k, plan.frames, frame)?;
                        times.push(t.elapsed().as_secs_f64() * 1e3);
                        anim.push(frame)?;
                        progress.advance(1);
                    }
                    anim.finish()?;
                    std::io::Write::flush(&mut w).map_err(|e| Error::io(&p, e))?;
                }
            }
        } else {
            let k = *job.frames.start();
            prepared.render(&common.pool, k, plan.frames, frame)?;
            times.push(start.elapsed().as_secs_f64() * 1e3);
            image.write(&job.path, frame)?;
            progress.advance(1);
        }
        let ms = start.elapsed().as_secs_f64() * 1e3;
        tally.written += 1;
        if let Some(m) = manifest.as_mut() {
            m.append(&line_json(plan, job, settings, Some(ms))?)?;
        }
        last_path.clone_from(&job.path);
    }
    if times.is_empty() {
        return Ok(());
    }
    let shown = if plan.per_frame && jobs.len() > 1 {
        let stem = &plan.inputs[jobs[0].input].stem;
        PathBuf::from(
            plan.pattern
                .raw()
                .to_string_lossy()
                .replace("{scene}", stem),
        )
    } else {
        last_path
    };
    let shown = (!args.discard).then_some(shown.as_path());
    if args.stats {
        let json = prepared.stats(args, common, &times, frame, shown);
        crate::output::stdout(&format!("{json}\n"))?;
    } else if !args.quiet {
        let (_, median, _) = super::spread(&times);
        progress.suspend(|| {
            let (w, h, n) = (frame.width, frame.height, times.len());
            let frames = format!("{n} frame{}", if n == 1 { "" } else { "s" });
            crate::output::stderr_line(&match shown {
                Some(p) => format!(
                    "wrote {} ({w}x{h}, {frames}, median {median:.1} ms/frame)",
                    p.display()
                ),
                None => format!(
                    "rendered {frames} ({w}x{h}, median {median:.1} ms/frame), wrote nothing \
                     (--discard)"
                ),
            })
        });
    }
    Ok(())
}

/// `--discard` writes nothing: the options that say how or where an output is written are
/// refused with it, rather than left without effect.
fn check_discard(args: &RenderArgs) -> Result<(), Error> {
    for (flag, given) in args.output_options() {
        if given {
            return Err(Error::parameter(format!(
                "{flag}: --discard writes no image (leave out one or the other)"
            )));
        }
    }
    Ok(())
}

/// The files the render of `args.scene` reads, which no output may overwrite.
fn inputs_of(args: &RenderArgs) -> Vec<&Path> {
    let mut inputs: Vec<&Path> = args.scene.iter().map(Path::new).collect();
    inputs.extend(args.texture.as_deref());
    inputs.extend(args.env.as_deref());
    inputs.extend(args.volume.meshes.iter().map(PathBuf::as_path));
    inputs
}

/// What makes an output's bytes, for the manifest (the same for every output of a batch).
fn settings_json(
    args: &RenderArgs,
    plan: &Plan,
    format: crate::formats::OutputFormat,
) -> serde_json::Value {
    serde_json::json!({
        "size": [args.size.0, args.size.1],
        "frames": plan.frames,
        "frame_range": [plan.range.start(), plan.range.end()],
        "format": format.extension(),
        "alpha": args.alpha,
        "bit_depth": args.bit_depth,
        "quality": args.quality,
        "fps": if format.is_animated() { Some(args.fps.unwrap_or(25)) } else { None },
        "msaa": args.msaa.unwrap_or(1),
        "ssaa": args.ssaa.unwrap_or(1),
        "filter": args.filter.map(texmap::texture::Filter::name),
        "texture": args.texture,
        "env": args.env,
    })
}

/// The manifest line of `job`'s output, hashed from the file now in place.
fn line_json(
    plan: &Plan,
    job: &Job,
    settings: &serde_json::Value,
    ms: Option<f64>,
) -> Result<serde_json::Value, Error> {
    let (bytes, sha256) = hash_file(&job.path)?;
    let frame = (job.frames.start() == job.frames.end()).then_some(*job.frames.start());
    Ok(serde_json::json!({
        "output": job.path,
        "input": plan.inputs[job.input].name,
        "frame": frame,
        "frames": [job.frames.start(), job.frames.end()],
        "shard": plan.shard.label(),
        "settings": settings,
        "bytes": bytes,
        "sha256": sha256,
        "ms": ms.map(|t| (t * 100.0).round() / 100.0),
        "texmap": env!("CARGO_PKG_VERSION"),
    }))
}
