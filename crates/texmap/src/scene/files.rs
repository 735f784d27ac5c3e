//! Where an asset's bytes may come from, and how many: whole-file reads bounded by
//! [`LoadOptions::max_buffer_bytes`](super::LoadOptions::max_buffer_bytes), the folder rule
//! for references inside an asset, and `data:` URIs.
//!
//! Rules (the safety rules of `docs/scenes.md`):
//! - A reference resolves from the asset's folder and may not leave it — lexically (`..`
//!   above the folder, an absolute path) nor through a symbolic link — unless outside paths
//!   are allowed; then it may go anywhere.
//! - `http:` / `https:` and every other URI scheme but `data:` are refused: texmap never
//!   fetches over the network.
//! - A file above the byte limit is refused before it is read, a `data:` URI before it is
//!   decoded (from its length: base64 holds 3 bytes in 4 characters).

use std::path::{Path, PathBuf};

use super::asset::LoadOptions;
use crate::{Error, Result};

/// Reads a whole regular file, refusing it when it is larger than `max_bytes`
/// ([`crate::files::read_bounded`]).
pub(crate) fn read_bounded(path: &Path, max_bytes: u64) -> Result<Vec<u8>> {
    crate::files::read_bounded(path, max_bytes)
}

/// Resolves a reference `rel` made by the asset `asset` (a file path, already decoded from
/// any URI escaping), enforcing the folder rule unless `options` allow outside paths.
pub(crate) fn resolve_reference(asset: &Path, rel: &str, options: &LoadOptions) -> Result<PathBuf> {
    let lower = rel.to_ascii_lowercase();
    if lower.starts_with("http:") || lower.starts_with("https:") {
        return Err(Error::Unsupported(format!(
            "{}: refers to {rel}: texmap never fetches over the network",
            asset.display()
        )));
    }
    if let Some((scheme, _)) = rel.split_once(':') {
        // A URI scheme (letters, then ':'), but not a Windows drive letter.
        if scheme.len() > 1
            && scheme
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "+.-".contains(c))
        {
            return Err(Error::Unsupported(format!(
                "{}: refers to {rel}: only relative paths and data: URIs are read",
                asset.display()
            )));
        }
    }
    crate::files::resolve_within(asset, rel, options.allow_outside_paths)
}

/// Decodes `%XX` escapes of a URI path.
pub(crate) fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' && i + 2 < b.len() {
            let hex = std::str::from_utf8(&b[i + 1..i + 3]).ok();
            if let Some(v) = hex.and_then(|h| u8::from_str_radix(h, 16).ok()) {
                out.push(v);
                i += 3;
                continue;
            }
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// A decoded `data:` URI.
pub(crate) struct DataUri {
    /// The media type the URI declares (`image/png`), if any.
    pub mime: Option<String>,
    pub bytes: Vec<u8>,
}

/// Decodes a `data:` URI's payload (base64 or percent-encoded), bounded by `max_bytes`.
pub(crate) fn decode_data_uri(asset: &Path, uri: &str, max_bytes: u64) -> Result<DataUri> {
    let rest = &uri[5..];
    let (header, payload) = rest
        .split_once(',')
        .ok_or_else(|| Error::decode(asset, "malformed data: URI (no comma)"))?;
    // Base64 yields 3 bytes per 4 characters.
    if (payload.len() as u64 / 4) * 3 > max_bytes {
        return Err(Error::limits(
            asset,
            format!("a data: URI holds more than the limit of {max_bytes} bytes"),
        ));
    }
    let mime = header
        .split(';')
        .next()
        .filter(|m| !m.is_empty())
        .map(str::to_string);
    let bytes = if header.ends_with(";base64") {
        use base64::Engine;
        base64::engine::general_purpose::STANDARD
            .decode(payload.trim())
            .map_err(|e| Error::decode(asset, format!("bad base64 in a data: URI: {e}")))?
    } else {
        percent_decode(payload).into_bytes()
    };
    Ok(DataUri { mime, bytes })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_stay_in_the_asset_folder() {
        let a = Path::new("/tmp/models/x.gltf");
        let inside = LoadOptions::default();
        let outside = LoadOptions::default().allow_outside_paths(true);
        assert!(resolve_reference(a, "tex/a.png", &inside).is_ok());
        assert!(resolve_reference(a, "tex/../a.png", &inside).is_ok());
        assert!(resolve_reference(a, "../a.png", &inside).is_err());
        assert!(resolve_reference(a, "tex/../../a.png", &inside).is_err());
        assert!(resolve_reference(a, "/etc/passwd", &inside).is_err());
        assert!(resolve_reference(a, "../a.png", &outside).is_ok());
        assert!(resolve_reference(a, "http://example.com/a.png", &outside).is_err());
        assert!(resolve_reference(a, "file:///etc/passwd", &outside).is_err());
    }

    #[test]
    fn percent_decoding() {
        assert_eq!(percent_decode("a%20b%2"), "a b%2");
        assert_eq!(percent_decode("%41%42"), "AB");
    }

    #[test]
    fn data_uris_decode_and_are_bounded() {
        let a = Path::new("x.gltf");
        let d = decode_data_uri(a, "data:application/octet-stream;base64,AAEC", 100).unwrap();
        assert_eq!(d.mime.as_deref(), Some("application/octet-stream"));
        assert_eq!(d.bytes, [0, 1, 2]);
        assert!(decode_data_uri(a, "data:;base64,AAECAAEC", 3).is_err());
    }
}
