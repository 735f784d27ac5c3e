//! Reading input files safely: every loader (scenes, images, volumes, transfer functions)
//! reads through these rules.
//!
//! - Only regular files are read. A FIFO would block the reader forever and a device
//!   (`/dev/zero`) never ends, so both, and directories, are refused before they are opened.
//! - A file above its byte budget is refused from its size before it is read, and the read
//!   itself stops at the budget (a file that grows while it is read cannot exceed it).
//! - Decompression is bounded too: gzip data is inflated at most to its budget, checked as it
//!   goes, so a small file of zeros cannot expand into gigabytes.
//! - A reference made inside an asset (a glTF URI, an OBJ texture, an NRRD data file)
//!   resolves from the asset's folder and may not leave it — lexically (`..` above the folder,
//!   an absolute path) nor through a symbolic link — unless outside paths are allowed.

use std::io::Read;
use std::path::{Component, Path, PathBuf};

use crate::{Error, Result};

/// The memory budget of loading one input when the user sets none (`--max-memory`): 4 GiB.
pub const DEFAULT_MAX_BYTES: u64 = 4 << 30;

/// Refuses `path` unless it is a regular file (following symbolic links).
///
/// # Errors
/// [`Error::Io`] when it cannot be inspected; [`Error::Limits`] for a FIFO, device, socket or
/// directory.
pub fn check_regular(path: &Path) -> Result<()> {
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if meta.is_file() {
        return Ok(());
    }
    let kind = if meta.is_dir() {
        "a directory"
    } else {
        "not a regular file (a FIFO, device or socket)"
    };
    Err(Error::limits(
        path,
        format!("is {kind}; only files are read"),
    ))
}

/// Reads the whole regular file `path`, refusing it when it holds more than `max_bytes`.
///
/// # Errors
/// As [`check_regular`]; [`Error::Limits`] above the budget; [`Error::Io`] when reading fails.
pub fn read_bounded(path: &Path, max_bytes: u64) -> Result<Vec<u8>> {
    check_regular(path)?;
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    let too_big = |n: u64| {
        Error::limits(
            path,
            format!("file is {n} bytes, above the limit of {max_bytes}"),
        )
    };
    if meta.len() > max_bytes {
        return Err(too_big(meta.len()));
    }
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut out = Vec::with_capacity(meta.len() as usize);
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut out)
        .map_err(|e| Error::io(path, e))?;
    if out.len() as u64 > max_bytes {
        return Err(too_big(out.len() as u64));
    }
    Ok(out)
}

/// Inflates gzip `bytes` (read from `path`), refusing output above `max_bytes`.
///
/// # Errors
/// [`Error::Decode`] for corrupt or truncated data; [`Error::Limits`] above the budget.
pub fn gunzip_bounded(path: &Path, bytes: &[u8], max_bytes: u64) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(bytes)
        .take(max_bytes.saturating_add(1))
        .read_to_end(&mut out)
        .map_err(|e| {
            if e.kind() == std::io::ErrorKind::UnexpectedEof {
                Error::decode(path, "gzip data is truncated")
            } else {
                Error::decode(path, format!("gzip data is corrupt: {e}"))
            }
        })?;
    if out.len() as u64 > max_bytes {
        return Err(Error::limits(
            path,
            format!("gzip data inflates to more than {max_bytes} bytes"),
        ));
    }
    Ok(out)
}

/// The first `n` bytes (or fewer, if the data is shorter) of gzip `bytes` inflated: enough to
/// read a header and size what follows before inflating it all.
#[must_use]
pub fn gunzip_prefix(bytes: &[u8], n: usize) -> Vec<u8> {
    let mut out = Vec::with_capacity(n);
    let _ = flate2::read::MultiGzDecoder::new(bytes)
        .take(n as u64)
        .read_to_end(&mut out);
    out
}

/// The path a reference `rel` made by the file `asset` names: resolved from `asset`'s
/// folder, and refused when it leaves that folder unless `allow_outside`.
///
/// # Errors
/// [`Error::Parameter`] naming `asset` and `rel` when the reference leaves the folder.
pub fn resolve_within(asset: &Path, rel: &str, allow_outside: bool) -> Result<PathBuf> {
    let base = asset.parent().unwrap_or(Path::new(""));
    let rel_path = Path::new(rel);
    let joined = base.join(rel_path);
    if allow_outside {
        return Ok(joined);
    }
    let refused = || {
        Error::parameter(format!(
            "{}: refers to {rel}, outside the asset's folder (allow with --allow-outside-paths)",
            asset.display()
        ))
    };
    // Lexically: no absolute path, and `..` never climbs above the folder.
    let mut depth = 0i32;
    for c in rel_path.components() {
        match c {
            Component::Prefix(_) | Component::RootDir => return Err(refused()),
            Component::ParentDir => {
                depth -= 1;
                if depth < 0 {
                    return Err(refused());
                }
            }
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
        }
    }
    // Through symbolic links: the real file must be inside the real folder.
    if let (Ok(real), Ok(real_base)) = (
        joined.canonicalize(),
        if base.as_os_str().is_empty() {
            Path::new(".").canonicalize()
        } else {
            base.canonicalize()
        },
    ) {
        if !real.starts_with(&real_base) {
            return Err(refused());
        }
    }
    Ok(joined)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir() -> PathBuf {
        let d = std::env::temp_dir().join(format!("texmap-files-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn directories_and_devices_are_refused_before_they_are_read() {
        let d = dir();
        let e = read_bounded(&d, 1 << 20).unwrap_err().to_string();
        assert!(e.contains("directory"), "{e}");
        #[cfg(unix)]
        {
            let e = read_bounded(Path::new("/dev/zero"), 1 << 20)
                .unwrap_err()
                .to_string();
            assert!(e.contains("/dev/zero") && e.contains("regular"), "{e}");
        }
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_is_refused_without_blocking() {
        let p = dir().join("fifo");
        let _ = std::fs::remove_file(&p);
        let made = std::process::Command::new("mkfifo").arg(&p).status();
        if !made.is_ok_and(|s| s.success()) {
            eprintln!("SKIPPED: mkfifo is not available");
            return;
        }
        let e = read_bounded(&p, 1 << 20).unwrap_err().to_string();
        assert!(e.contains("FIFO"), "{e}");
    }

    #[test]
    fn files_above_the_budget_are_refused() {
        let p = dir().join("big.bin");
        std::fs::write(&p, [0u8; 100]).unwrap();
        assert_eq!(read_bounded(&p, 100).unwrap().len(), 100);
        let e = read_bounded(&p, 99).unwrap_err().to_string();
        assert!(e.contains("100 bytes") && e.contains("99"), "{e}");
    }

    #[test]
    fn gzip_bombs_stop_at_the_budget() {
        use std::io::Write as _;
        let mut z = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
        z.write_all(&vec![0u8; 10 << 20]).unwrap();
        let bytes = z.finish().unwrap();
        assert!(bytes.len() < 100_000);
        let p = Path::new("zeros.gz");
        assert_eq!(gunzip_bounded(p, &bytes, 10 << 20).unwrap().len(), 10 << 20);
        let e = gunzip_bounded(p, &bytes, 1 << 20).unwrap_err().to_string();
        assert!(e.contains("zeros.gz") && e.contains("1048576"), "{e}");
    }

    #[test]
    fn references_stay_in_the_folder() {
        let a = Path::new("models/a.gltf");
        assert!(resolve_within(a, "tex/x.png", false).is_ok());
        assert!(resolve_within(a, "../x.png", false).is_err());
        assert!(resolve_within(a, "/etc/passwd", false).is_err());
        assert!(resolve_within(a, "../x.png", true).is_ok());
    }
}
