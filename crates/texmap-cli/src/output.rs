//! Writing what the command line produces: images atomically (a temporary file beside the
//! target, created exclusively, then a rename, so a failed or interrupted write never leaves
//! a partial file or clobbers the old one), and text to stdout and stderr without panicking.
//!
//! Images (in the formats of `formats.rs`): `-o -` writes to stdout; a FIFO or character
//! device (`/dev/null`) is written through, not replaced; a symbolic link is followed (the
//! file it names is replaced atomically, the link stays); a dangling link or a directory is
//! an error.
//!
//! Standard streams: a closed stdout (`texmap info … | head -1`) ends the program quietly
//! with success, as Unix filters expect of a reader that stopped reading; any other failure
//! to write it (a full device) is one line on stderr and exit 1. Lines for stderr are written
//! if they can be: with stderr gone there is nowhere left to report a failure.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use texmap::Error;

use crate::formats::{self, OutputFormat, Picture};

/// Where an image is written.
enum Target {
    /// `-`: standard output.
    Stdout,
    /// A FIFO or character device (`/dev/null`, a pipe someone reads): written through.
    Stream(PathBuf),
    /// A regular file (or none yet): a temporary file beside it, then a rename. A symbolic
    /// link is followed: the file it points at is replaced, the link stays.
    File(PathBuf),
}

fn target(path: &Path) -> Result<Target, Error> {
    if path.as_os_str() == "-" {
        return Ok(Target::Stdout);
    }
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err(Error::parameter(format!(
            "{}: is a directory, not an image file",
            path.display()
        ))),
        Ok(m) if !m.is_file() => Ok(Target::Stream(path.to_path_buf())),
        Ok(_) => Ok(Target::File(
            std::fs::canonicalize(path).map_err(|e| Error::io(path, e))?,
        )),
        Err(_) if std::fs::symlink_metadata(path).is_ok() => Err(Error::parameter(format!(
            "{}: is a symbolic link to nothing; give the file itself",
            path.display()
        ))),
        Err(_) => Ok(Target::File(path.to_path_buf())),
    }
}

/// Writes `picture` as `format` at `path`: atomically for a file, through for a FIFO or a
/// device, to stdout for `-` (see the module docs). A format that seeks in its output
/// (OpenEXR) is encoded in memory first when the target is a stream.
pub fn write_image(path: &Path, format: OutputFormat, picture: &Picture) -> Result<(), Error> {
    match Sink::open(path)? {
        Sink::File(mut file) => {
            let real = file.path.clone();
            formats::encode_seekable(&mut file.file, &real, format, picture)?;
            file.commit()
        }
        Sink::Stream(w, p) => write_stream(w, &p, format, picture),
    }
}

/// Writes `bytes` at `path` (a distance field's file): atomically for a file, through for a
/// FIFO or a device, to stdout for `-` (see the module docs).
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    use std::io::Write as _;
    match Sink::open(path)? {
        Sink::File(mut file) => {
            file.file
                .write_all(bytes)
                .map_err(|e| Error::io(&file.path, e))?;
            file.commit()
        }
        Sink::Stream(mut w, p) => w
            .write_all(bytes)
            .and_then(|()| w.flush())
            .map_err(|e| Error::io(&p, e)),
    }
}

/// Where an output's bytes go: a temporary file renamed into place by
/// [`AtomicFile::commit`], or a stream (stdout, a FIFO, a device) written through.
pub enum Sink {
    File(AtomicFile),
    Stream(Box<dyn std::io::Write>, PathBuf),
}

impl Sink {
    /// The sink for `path` (see the module docs).
    ///
    /// # Errors
    /// [`Error::Io`] or [`Error::Parameter`] naming `path`: a directory, a dangling link, a
    /// temporary file that cannot be created.
    pub fn open(path: &Path) -> Result<Sink, Error> {
        match target(path)? {
            Target::Stdout => Ok(Sink::Stream(
                Box::new(std::io::stdout().lock()),
                path.to_path_buf(),
            )),
            Target::Stream(p) => {
                let f = std::fs::OpenOptions::new()
                    .write(true)
                    .open(&p)
                    .map_err(|e| Error::io(&p, e))?;
                Ok(Sink::Stream(Box::new(f), p))
            }
            Target::File(p) => AtomicFile::create(&p).map(Sink::File),
        }
    }
}

/// A temporary file beside `path`, created exclusively (never through a file or link
/// planted at its name); renamed over `path` by [`AtomicFile::commit`], removed if dropped
/// before.
pub struct AtomicFile {
    pub file: std::fs::File,
    /// The output's (resolved) path.
    pub path: PathBuf,
    tmp: PathBuf,
    committed: bool,
}

impl AtomicFile {
    fn create(path: &Path) -> Result<AtomicFile, Error> {
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let name = path
            .file_name()
            .ok_or_else(|| Error::parameter(format!("{}: not a file name", path.display())))?;
        let tmp = dir.join(format!(
            ".{}.tmp-{}",
            name.to_string_lossy(),
            std::process::id()
        ));
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
            .map_err(|e| Error::io(&tmp, e))?;
        Ok(AtomicFile {
            file,
            path: path.to_path_buf(),
            tmp,
            committed: false,
        })
    }

    /// Syncs the file and renames it over the output.
    ///
    /// # Errors
    /// [`Error::Io`] naming the output (the temporary file is then removed).
    pub fn commit(mut self) -> Result<(), Error> {
        self.file.sync_all().map_err(|e| Error::io(&self.path, e))?;
        std::fs::rename(&self.tmp, &self.path).map_err(|e| Error::io(&self.path, e))?;
        self.committed = true;
        Ok(())
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// `picture` into a stream that cannot seek.
fn write_stream(
    mut w: impl std::io::Write,
    path: &Path,
    format: OutputFormat,
    picture: &Picture,
) -> Result<(), Error> {
    if !format.needs_seek() {
        return formats::encode_stream(w, path, format, picture);
    }
    let mut encoded = std::io::Cursor::new(Vec::new());
    formats::encode_seekable(&mut encoded, path, format, picture)?;
    w.write_all(encoded.get_ref())
        .and_then(|()| w.flush())
        .map_err(|e| Error::io(path, e))
}

/// True when `output` names the same existing file as one of `inputs` (which a write would
/// destroy).
pub fn is_an_input(output: &Path, inputs: &[&Path]) -> bool {
    let Ok(out) = std::fs::canonicalize(output) else {
        return false;
    };
    inputs
        .iter()
        .filter_map(|p| std::fs::canonicalize(p).ok())
        .any(|p| p == out)
}

/// Writes `text` to stdout (see the module docs for a closed pipe).
///
/// # Errors
/// [`Error::Io`] naming `stdout` when the write fails for another reason (a full device).
pub fn stdout(text: &str) -> Result<(), Error> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(e) => Err(Error::io("stdout", e)),
    }
}

/// Writes a line to stderr, if it can.
pub fn stderr_line(text: &str) {
    let _ = writeln!(std::io::stderr().lock(), "{text}");
}
