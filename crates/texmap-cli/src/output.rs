//! Writing what the command line produces: images atomically (a temporary file beside the
//! target, created exclusively, then a rename, so a failed or interrupted write never leaves
//! a partial file or clobbers the old one), and text to stdout and stderr without panicking.
//!
//! Images (PNG, or OpenEXR for `texmap convert`): `-o -` writes the image to stdout; a FIFO or character device (`/dev/null`) is
//! written through, not replaced; a symbolic link is followed (the file it names is replaced
//! atomically, the link stays); a dangling link or a directory is an error.
//!
//! Standard streams: a closed stdout (`texmap info … | head -1`) ends the program quietly
//! with success, as Unix filters expect of a reader that stopped reading; any other failure
//! to write it (a full device) is one line on stderr and exit 1. Lines for stderr are written
//! if they can be: with stderr gone there is nowhere left to report a failure.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use image::ImageEncoder;
use texmap::Error;

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

/// The encoding of an image: PNG of 8-bit RGB or RGBA rows, or OpenEXR of `f32` RGBA.
#[derive(Clone, Copy)]
pub enum Image<'a> {
    /// 8-bit RGB rows.
    Rgb8(&'a [u8]),
    /// 8-bit RGBA rows (straight alpha).
    Rgba8(&'a [u8]),
    /// `f32` RGBA rows, linear (an OpenEXR file).
    Rgba32F(&'a [f32]),
}

/// Encodes `image` into `w`.
fn encode(
    w: impl std::io::Write,
    path: &Path,
    width: u32,
    height: u32,
    image: Image<'_>,
) -> Result<(), Error> {
    let image_error = |e: image::ImageError| match e {
        image::ImageError::IoError(e) => Error::io(path, e),
        e => Error::decode(path, e.to_string()),
    };
    let mut w = std::io::BufWriter::new(w);
    match image {
        Image::Rgb8(rgb) => image::codecs::png::PngEncoder::new(&mut w)
            .write_image(rgb, width, height, image::ExtendedColorType::Rgb8)
            .map_err(image_error)?,
        Image::Rgba8(rgba) => image::codecs::png::PngEncoder::new(&mut w)
            .write_image(rgba, width, height, image::ExtendedColorType::Rgba8)
            .map_err(image_error)?,
        Image::Rgba32F(texels) => {
            // The EXR encoder seeks: encode in memory, then write the bytes.
            let mut bytes = std::io::Cursor::new(Vec::new());
            let raw: Vec<u8> = texels.iter().flat_map(|v| v.to_ne_bytes()).collect();
            image::codecs::openexr::OpenExrEncoder::new(&mut bytes)
                .write_image(&raw, width, height, image::ExtendedColorType::Rgba32F)
                .map_err(image_error)?;
            w.write_all(bytes.get_ref())
                .map_err(|e| Error::io(path, e))?;
        }
    }
    w.flush().map_err(|e| Error::io(path, e))
}

/// Writes RGB8 rows as a PNG at `path`: atomically for a file, through for a FIFO or a
/// device, to stdout for `-`.
pub fn write_png_rgb8(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), Error> {
    write_image(path, width, height, Image::Rgb8(rgb))
}

/// Writes `image` at `path` as [`write_png_rgb8`] does (an EXR to `-` goes to stdout too).
pub fn write_image(path: &Path, width: u32, height: u32, image: Image<'_>) -> Result<(), Error> {
    let path = match target(path)? {
        Target::Stdout => return encode(std::io::stdout().lock(), path, width, height, image),
        Target::Stream(p) => {
            let f = std::fs::OpenOptions::new()
                .write(true)
                .open(&p)
                .map_err(|e| Error::io(&p, e))?;
            return encode(f, &p, width, height, image);
        }
        Target::File(p) => p,
    };
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
    // Created exclusively: never through a file or link planted at the temporary name.
    let file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)
        .map_err(|e| Error::io(&tmp, e))?;
    let result = (|| {
        let mut file = file;
        encode(&mut file, &path, width, height, image)?;
        file.sync_all().map_err(|e| Error::io(&path, e))?;
        std::fs::rename(&tmp, &path).map_err(|e| Error::io(&path, e))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
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
