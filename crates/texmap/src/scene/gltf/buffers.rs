//! A glTF file's binary data: its buffers (the GLB binary chunk, `data:` URIs or files
//! beside it, each bounded and following the folder rule) and bounds-checked accessor reads
//! in any component type (`normalized`, `byteStride`, sparse, no bufferView = zeros), so
//! `KHR_mesh_quantization` is read too. No read can index out of a buffer: every view and
//! accessor is checked against its buffer before it is read.

use std::path::Path;

use gltf::accessor::{DataType, Dimensions};
use gltf::Document;

use crate::scene::asset::LoadOptions;
use crate::scene::files::{decode_data_uri, percent_decode, read_bounded, resolve_reference};
use crate::{Error, Result};

/// Every buffer of `doc`, in index order, each at least its `byteLength` long.
pub(super) fn read_buffers(
    path: &Path,
    doc: &Document,
    mut blob: Option<Vec<u8>>,
    options: &LoadOptions,
) -> Result<Vec<Vec<u8>>> {
    let mut out = Vec::new();
    let mut total = 0u64;
    for b in doc.buffers() {
        let data = match b.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                Error::decode(
                    path,
                    format!(
                        "buffer {} refers to the GLB binary chunk, which is missing",
                        b.index()
                    ),
                )
            })?,
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                decode_data_uri(path, uri, options.max_buffer_bytes)?.bytes
            }
            gltf::buffer::Source::Uri(uri) => {
                let p = resolve_reference(path, &percent_decode(uri), options)?;
                read_bounded(&p, options.max_buffer_bytes)?
            }
        };
        if data.len() < b.length() {
            return Err(Error::decode(
                path,
                format!(
                    "buffer {} holds {} bytes, fewer than its byteLength {} (truncated?)",
                    b.index(),
                    data.len(),
                    b.length()
                ),
            ));
        }
        total += data.len() as u64;
        if total > options.max_buffer_bytes {
            return Err(Error::limits(
                path,
                format!(
                    "buffers exceed the limit of {} bytes",
                    options.max_buffer_bytes
                ),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// Bounds-checked accessor reads.
pub(super) struct Accessors<'a> {
    pub(super) path: &'a Path,
    pub(super) buffers: &'a [Vec<u8>],
    pub(super) max_bytes: u64,
}

fn component(b: &[u8], ty: DataType, normalized: bool) -> f64 {
    match ty {
        DataType::I8 => {
            let v = f64::from(b[0] as i8);
            if normalized {
                (v / 127.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U8 => {
            let v = f64::from(b[0]);
            if normalized {
                v / 255.0
            } else {
                v
            }
        }
        DataType::I16 => {
            let v = f64::from(i16::from_le_bytes([b[0], b[1]]));
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U16 => {
            let v = f64::from(u16::from_le_bytes([b[0], b[1]]));
            if normalized {
                v / 65535.0
            } else {
                v
            }
        }
        DataType::U32 => {
            let v = f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
            if normalized {
                v / f64::from(u32::MAX)
            } else {
                v
            }
        }
        DataType::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
    }
}

impl Accessors<'_> {
    fn err(&self, msg: String) -> Error {
        Error::decode(self.path, msg)
    }

    /// The bytes of a buffer view.
    pub(super) fn view_bytes(&self, view: &gltf::buffer::View) -> Result<&[u8]> {
        let buf = &self.buffers[view.buffer().index()];
        view.offset()
            .checked_add(view.length())
            .filter(|&end| end <= buf.len())
            .map(|end| &buf[view.offset()..end])
            .ok_or_else(|| {
                self.err(format!(
                    "bufferView {} reaches past the end of buffer {}",
                    view.index(),
                    view.buffer().index()
                ))
            })
    }

    /// Every component of `acc` as f64 (`count × components`), and the component count.
    pub(super) fn read(&self, acc: &gltf::Accessor) -> Result<(Vec<f64>, usize)> {
        let n = acc.dimensions().multiplicity();
        let count = acc.count();
        let ty = acc.data_type();
        let csize = ty.size();
        let elem = n * csize;
        let norm = acc.normalized();
        let total = (count as u64).saturating_mul(n as u64);
        if total.saturating_mul(8) > self.max_bytes {
            return Err(Error::limits(
                self.path,
                format!(
                    "accessor {} has {count} elements, above the size limit",
                    acc.index()
                ),
            ));
        }
        if matches!(acc.dimensions(), Dimensions::Mat2 | Dimensions::Mat3) && csize < 4 {
            return Err(Error::Unsupported(format!(
                "{}: accessor {}: padded small-component matrices are not read",
                self.path.display(),
                acc.index()
            )));
        }
        let mut out = vec![0.0f64; count * n];
        if let Some(view) = acc.view() {
            let data = self.view_bytes(&view)?;
            let stride = view.stride().unwrap_or(elem);
            if stride < elem {
                return Err(self.err(format!(
                    "bufferView {} has byteStride {stride}, smaller than accessor {}'s element",
                    view.index(),
                    acc.index()
                )));
            }
            if count > 0 {
                let end = (stride as u64)
                    .checked_mul(count as u64 - 1)
                    .and_then(|v| v.checked_add((acc.offset() + elem) as u64));
                if end.is_none_or(|e| e > data.len() as u64) {
                    return Err(self.err(format!(
                        "accessor {} reaches past the end of bufferView {}",
                        acc.index(),
                        view.index()
                    )));
                }
            }
            for e in 0..count {
                let base = acc.offset() + e * stride;
                for c in 0..n {
                    out[e * n + c] = component(&data[base + c * csize..], ty, norm);
                }
            }
        }
        if let Some(sparse) = acc.sparse() {
            let k = sparse.count();
            let idx = sparse.indices();
            let isize = idx.index_type().size();
            let ibytes = self.view_bytes(&idx.view())?;
            let vbytes = self.view_bytes(&sparse.values().view())?;
            let ioff = idx.offset();
            let voff = sparse.values().offset();
            if ioff + k * isize > ibytes.len() || voff + k * elem > vbytes.len() {
                return Err(self.err(format!(
                    "sparse accessor {} reaches past the end of its bufferViews",
                    acc.index()
                )));
            }
            for s in 0..k {
                let b = &ibytes[ioff + s * isize..];
                let i = match isize {
                    1 => b[0] as usize,
                    2 => u16::from_le_bytes([b[0], b[1]]) as usize,
                    _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize,
                };
                if i >= count {
                    return Err(self.err(format!(
                        "sparse accessor {} writes element {i} of {count}",
                        acc.index()
                    )));
                }
                for c in 0..n {
                    out[i * n + c] = component(&vbytes[voff + s * elem + c * csize..], ty, norm);
                }
            }
        }
        Ok((out, n))
    }

    pub(super) fn read_vec<const N: usize>(
        &self,
        acc: &gltf::Accessor,
        what: &str,
    ) -> Result<Vec<[f32; N]>> {
        let (v, n) = self.read(acc)?;
        if n < N {
            return Err(self.err(format!(
                "accessor {} ({what}) has {n} components, expected {N}",
                acc.index()
            )));
        }
        Ok(v.chunks_exact(n)
            .map(|c| std::array::from_fn(|i| c[i] as f32))
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalized_components() {
        assert_eq!(component(&[255], DataType::U8, true), 1.0);
        assert_eq!(component(&[0x80], DataType::I8, true), -1.0);
        assert_eq!(component(&[0xff, 0x7f], DataType::I16, true), 1.0);
        assert_eq!(component(&[7], DataType::U8, false), 7.0);
    }
}
