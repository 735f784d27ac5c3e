//! The manifest of a batch (`--manifest FILE`): one JSON line per output written, appended
//! as it is written, so a farm can merge the shards' files, check them (`verify.rs`) and see
//! what a preempted run finished.
//!
//! A line: `output` (the path as written, as given on the command line), `input`, `frame`
//! (1-based; `null` for an animation), `frames` (`[first, last]` the output holds), `shard`,
//! `settings` (size, turntable frames and range, format and what it keeps, sampling — what
//! makes the bytes), `bytes`, `sha256` (hex, of the file as renamed into place), `ms` (render
//! and write; `null` for a file found complete by `--skip-existing` that the manifest lacked)
//! and `texmap` (the version).
//!
//! Each line is one `write(2)` of the whole line on a descriptor opened with `O_APPEND`, so
//! processes appending to one manifest (on a local file system) never interleave within a
//! line, and a killed process leaves whole lines only.

pub mod verify;

use std::collections::HashSet;
use std::fs::File;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};
use texmap::Error;

/// An open manifest.
pub struct Manifest {
    file: File,
    path: PathBuf,
}

impl Manifest {
    /// Opens `path` for appending (created if missing).
    ///
    /// # Errors
    /// [`Error::Io`] naming it.
    pub fn open(path: &Path) -> Result<Manifest, Error> {
        let file = std::fs::OpenOptions::new()
            .append(true)
            .create(true)
            .open(path)
            .map_err(|e| Error::io(path, e))?;
        Ok(Manifest {
            file,
            path: path.to_path_buf(),
        })
    }

    /// The outputs its lines already name (lines that do not parse are left out).
    pub fn recorded(&self) -> HashSet<String> {
        let text = std::fs::read_to_string(&self.path).unwrap_or_default();
        text.lines()
            .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
            .filter_map(|v| v.get("output")?.as_str().map(String::from))
            .collect()
    }

    /// Appends `line` and a newline in one write.
    ///
    /// # Errors
    /// [`Error::Io`] naming the manifest, also when the system wrote less than the line.
    pub fn append(&mut self, line: &serde_json::Value) -> Result<(), Error> {
        let mut bytes = line.to_string().into_bytes();
        bytes.push(b'\n');
        match self.file.write(&bytes) {
            Ok(n) if n == bytes.len() => Ok(()),
            Ok(n) => Err(Error::io(
                &self.path,
                std::io::Error::other(format!("wrote {n} of a {}-byte line", bytes.len())),
            )),
            Err(e) => Err(Error::io(&self.path, e)),
        }
    }
}

/// A file's size and SHA-256 (lower-case hex).
///
/// # Errors
/// [`Error::Io`] naming it.
pub fn hash_file(path: &Path) -> Result<(u64, String), Error> {
    let mut file = File::open(path).map_err(|e| Error::io(path, e))?;
    let mut hasher = Sha256::new();
    let mut buf = vec![0u8; 1 << 16];
    let mut bytes = 0u64;
    loop {
        let n = file.read(&mut buf).map_err(|e| Error::io(path, e))?;
        if n == 0 {
            break;
        }
        hasher.update(&buf[..n]);
        bytes += n as u64;
    }
    let digest = hasher.finalize();
    let hex = digest.iter().map(|b| format!("{b:02x}")).collect();
    Ok((bytes, hex))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sha256_of_a_known_string() {
        let d = std::env::temp_dir().join(format!("texmap-manifest-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let f = d.join("abc");
        std::fs::write(&f, b"abc").unwrap();
        let (n, h) = hash_file(&f).unwrap();
        assert_eq!(n, 3);
        assert_eq!(
            h,
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        let m = d.join("m.jsonl");
        let _ = std::fs::remove_file(&m);
        let mut man = Manifest::open(&m).unwrap();
        man.append(&serde_json::json!({"output": "a.png"})).unwrap();
        man.append(&serde_json::json!({"output": "b.png"})).unwrap();
        assert_eq!(man.recorded().len(), 2);
        let text = std::fs::read_to_string(&m).unwrap();
        assert_eq!(text.lines().count(), 2);
        let _ = std::fs::remove_dir_all(&d);
    }
}
