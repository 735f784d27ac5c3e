//! The bounds of one `texmap render`: the memory budget (`--max-memory`) that loading and the
//! frame must fit in, the most frames and threads, and the outputs that may not overwrite an
//! input. Each is checked before the work it bounds starts, with one line naming the flag.

use std::path::Path;

use texmap::Error;

/// The most turntable frames one command renders.
pub const MAX_FRAMES: u32 = 100_000;

/// Threads beyond this many per core are clamped (with a warning): they only add contention.
const THREADS_PER_CORE: usize = 4;

/// `--max-memory`: a byte count with an optional K, M, G or T suffix (powers of 1024).
pub fn parse_bytes(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let (digits, unit) = match t.char_indices().find(|(_, c)| !c.is_ascii_digit()) {
        Some((i, _)) => (&t[..i], t[i..].trim()),
        None => (t, ""),
    };
    let n: u64 = digits
        .parse()
        .map_err(|_| format!("expected a byte count such as 8G or 512M, got {s:?}"))?;
    let shift = match unit.to_ascii_uppercase().trim_end_matches('B') {
        "" => 0,
        "K" | "KI" => 10,
        "M" | "MI" => 20,
        "G" | "GI" => 30,
        "T" | "TI" => 40,
        _ => return Err(format!("unknown unit in {s:?} (K, M, G or T)")),
    };
    n.checked_mul(1 << shift)
        .filter(|&b| b > 0)
        .ok_or_else(|| format!("{s:?} is not a positive byte count"))
}

/// Refuses more frames than [`MAX_FRAMES`]; returns the threads to run (0: every core), a
/// request above [`THREADS_PER_CORE`] per core clamped with a warning.
pub fn frames_and_threads(frames: u32, threads: Option<usize>) -> Result<usize, Error> {
    if frames == 0 || frames > MAX_FRAMES {
        return Err(Error::parameter(format!(
            "--frames {frames} is outside 1..={MAX_FRAMES}"
        )));
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    Ok(match threads {
        None => 0,
        Some(0) => return Err(Error::parameter("--threads must be at least 1")),
        Some(t) if t > cores * THREADS_PER_CORE => {
            let max = cores * THREADS_PER_CORE;
            crate::output::stderr_line(&format!(
                "texmap: warning: --threads {t} is more than {THREADS_PER_CORE} per core on \
                 this machine's {cores}; using {max}"
            ));
            max
        }
        Some(t) => t,
    })
}

/// The buffers of a frame: the (supersampled) colour target, the resolved frame and what
/// the output's encoder holds besides ([`crate::formats::OutputFormat::buffer_bytes_per_pixel`]).
#[derive(Clone, Copy)]
pub struct FrameBuffers {
    pub width: u32,
    pub height: u32,
    pub ssaa: u32,
    pub output_bytes_per_pixel: u64,
}

impl FrameBuffers {
    /// Their bytes.
    pub fn bytes(&self) -> u64 {
        let pixels = u64::from(self.width) * u64::from(self.height);
        let samples = pixels * u64::from(self.ssaa) * u64::from(self.ssaa);
        let resolved = if self.ssaa > 1 { pixels * 16 } else { 0 };
        samples * 16 + resolved + pixels * self.output_bytes_per_pixel
    }
}

/// Refuses a frame whose buffers would not fit in `max_bytes`.
pub fn check_frame(frame: &FrameBuffers, max_bytes: u64) -> Result<(), Error> {
    let need = frame.bytes();
    if need > max_bytes {
        return Err(Error::parameter(format!(
            "--size {}x{} with --ssaa {} needs {} MiB of frame buffers, above \
             --max-memory {} MiB",
            frame.width,
            frame.height,
            frame.ssaa,
            need >> 20,
            max_bytes >> 20
        )));
    }
    Ok(())
}

/// Refuses shadow maps of `bytes` that would not fit in `max_bytes` next to the frame's
/// buffers; `source` names where their size came from.
pub fn check_shadow_maps(
    bytes: u64,
    source: &str,
    frame: &FrameBuffers,
    max_bytes: u64,
) -> Result<(), Error> {
    let frame_bytes = frame.bytes();
    if bytes.saturating_add(frame_bytes) > max_bytes {
        return Err(Error::parameter(format!(
            "{source}: the shadow maps need {} MiB, with the frame's {} MiB \
             above --max-memory {} MiB",
            bytes >> 20,
            frame_bytes >> 20,
            max_bytes >> 20
        )));
    }
    Ok(())
}

/// Refuses an output path that names one of the render's inputs.
pub fn check_output(output: &Path, inputs: &[&Path]) -> Result<(), Error> {
    if crate::output::is_an_input(output, inputs) {
        return Err(Error::parameter(format!(
            "-o {}: is an input of this render; it would be overwritten",
            output.display()
        )));
    }
    Ok(())
}

/// The process's peak resident memory so far in KiB (`VmHWM` of `/proc/self/status`), where
/// the system reports it (Linux).
pub fn peak_rss_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::OutputFormat;

    #[test]
    fn byte_counts_take_binary_suffixes() {
        assert_eq!(parse_bytes("4096"), Ok(4096));
        assert_eq!(parse_bytes("512M"), Ok(512 << 20));
        assert_eq!(parse_bytes("8G"), Ok(8 << 30));
        assert_eq!(parse_bytes("2GiB"), Ok(2 << 30));
        assert!(parse_bytes("0").is_err());
        assert!(parse_bytes("8X").is_err());
        assert!(parse_bytes("-1G").is_err());
        assert!(parse_bytes("99999999999T").is_err());
    }

    fn png(width: u32, height: u32) -> FrameBuffers {
        FrameBuffers {
            width,
            height,
            ssaa: 1,
            output_bytes_per_pixel: OutputFormat::Png.buffer_bytes_per_pixel(),
        }
    }

    #[test]
    fn frame_budget() {
        assert!(check_frame(&png(1920, 1080), 4 << 30).is_ok());
        // 16 bytes a pixel (a still PNG is encoded a band at a time): 4 GiB.
        let e = check_frame(&png(16384, 16384), (4 << 30) - 1)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("--size 16384x16384") && e.contains("--max-memory"),
            "{e}"
        );
        assert!(check_frame(&png(16384, 16384), 8 << 30).is_ok());
        // An EXR for a stream is encoded in memory: 33 bytes a pixel in all.
        let exr = FrameBuffers {
            output_bytes_per_pixel: OutputFormat::Exr.buffer_bytes_per_pixel(),
            ..png(16384, 16384)
        };
        assert!(check_frame(&exr, 8 << 30).is_err());
    }

    #[test]
    fn shadow_map_budget() {
        // A cube of six 4096² maps and its target: 640 MiB.
        let cube = 4096u64 * 4096 * (4 * 6 + 16);
        assert!(
            check_shadow_maps(cube, "--shadow-map-size 4096", &png(1920, 1080), 4 << 30).is_ok()
        );
        let e = check_shadow_maps(cube, "--shadow-map-size 4096", &png(1920, 1080), 512 << 20)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("--shadow-map-size 4096") && e.contains("--max-memory 512"),
            "{e}"
        );
    }
}
