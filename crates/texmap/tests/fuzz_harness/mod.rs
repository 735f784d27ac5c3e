//! The fuzz harness: one function per loader, each taking arbitrary bytes and exercising the
//! loader (and, for scenes that load, a tiny render) the way the command line does. None may
//! panic, hang or allocate without bound; an `Err` is the expected answer to bad input.
//!
//! Used by the coverage-guided fuzz targets in `fuzz/` (cargo-fuzz, nightly) and by
//! `tests/fuzz_regressions.rs`, which replays every input the fuzzers ever found a fault
//! with (committed under `tests/fuzz_regressions/<target>/`) on the stable toolchain.

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use texmap::render::framing::{choose_camera, CameraRequest};
use texmap::render::{render, Settings};
use texmap::scene::LoadOptions;
use texmap::texture::container::{cube_from_file, texture_from_file, TextureFile};
use texmap::texture::load::{decode_image_bytes, texture_from_image, Limits};
use texmap::texture::{ColorSpace, TextureOptions};
use texmap::volume::{load_volume_with, RawDesc, ScalarType, VolumeOptions};

/// Fuzzing budget: far below the defaults, so a bounded allocation stays cheap too.
const MAX_BYTES: u64 = 64 << 20;

/// A scratch directory of this process (inputs are written there, as the loaders read files).
fn scratch() -> PathBuf {
    let d = std::env::temp_dir().join(format!("texmap-fuzz-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&d);
    d
}

fn write(name: &str, data: &[u8]) -> PathBuf {
    let p = scratch().join(name);
    std::fs::write(&p, data).expect("scratch file");
    p
}

fn options() -> LoadOptions {
    LoadOptions::default().max_memory(MAX_BYTES).limits(
        Limits::default()
            .with_max_dimension(1024)
            .with_max_bytes(MAX_BYTES),
    )
}

/// Loads a scene file and, when it loads with few triangles, renders it at 8×8.
fn scene(path: &Path) {
    let Ok(loaded) = texmap::scene::load(path, &options()) else {
        return;
    };
    let scene = loaded.scene;
    if scene.triangle_count() == 0 || scene.triangle_count() > 20_000 {
        return;
    }
    let Ok(camera) = choose_camera(&scene, &loaded.volumes, &CameraRequest::default()) else {
        return;
    };
    let _ = render(&scene, &camera, &Settings::new(8, 8));
}

/// A glTF JSON document.
pub fn gltf(data: &[u8]) {
    scene(&write("f.gltf", data));
}

/// A binary glTF.
pub fn glb(data: &[u8]) {
    scene(&write("f.glb", data));
}

/// An OBJ file, and after a line `#MTL` the `m.mtl` it names (`mtllib m.mtl` is prepended).
pub fn obj(data: &[u8]) {
    let split = data.windows(5).position(|w| w == b"\n#MTL");
    let (obj, mtl) = match split {
        Some(i) => (&data[..i], &data[i + 5..]),
        None => (data, &b""[..]),
    };
    write("m.mtl", mtl);
    let mut body = b"mtllib m.mtl\n".to_vec();
    body.extend_from_slice(obj);
    scene(&write("f.obj", &body));
}

/// A TOML scene.
pub fn toml(data: &[u8]) {
    scene(&write("f.toml", data));
}

/// An image in any format texmap reads, made into a texture with its mip chain.
pub fn image(data: &[u8]) {
    let limits = Limits::default()
        .with_max_dimension(2048)
        .with_max_bytes(MAX_BYTES);
    if let Ok(img) = decode_image_bytes(data, Path::new("fuzz-image"), &limits) {
        let _ = texture_from_image(img, ColorSpace::Srgb, TextureOptions::default());
    }
}

/// A texture container (`magic` prepended unless the bytes start with it): parsed, then up to
/// 64 of its images decoded, and made into the texture or cube map it is.
fn container(data: &[u8], magic: &[u8], name: &str) {
    let mut bytes = Vec::with_capacity(data.len() + magic.len());
    if !data.starts_with(magic) {
        bytes.extend_from_slice(magic);
    }
    bytes.extend_from_slice(data);
    let limits = Limits::default()
        .with_max_dimension(2048)
        .with_max_bytes(MAX_BYTES);
    let Ok(file) = TextureFile::from_bytes(bytes, Path::new(name), &limits) else {
        return;
    };
    let mut decoded = 0;
    'all: for layer in 0..file.layers() {
        for face in 0..file.faces() {
            for level in 0..file.levels() {
                if decoded == 64 {
                    break 'all;
                }
                decoded += 1;
                if file.format().is_float() {
                    let _ = file.decode_f32(layer, face, level);
                } else {
                    let _ = file.decode_rgba8(layer, face, level);
                }
            }
        }
    }
    let _ = texture_from_file(&file, ColorSpace::Srgb, TextureOptions::default());
    let _ = cube_from_file(&file, ColorSpace::Srgb, TextureOptions::default());
}

/// A DDS file (`DDS ` prepended unless present).
pub fn dds(data: &[u8]) {
    container(data, b"DDS ", "f.dds");
}

/// A KTX 1 file (its magic prepended unless present).
pub fn ktx(data: &[u8]) {
    container(data, b"\xABKTX 11\xBB\r\n\x1A\n", "f.ktx");
}

/// A KTX2 file (its magic prepended unless present).
pub fn ktx2(data: &[u8]) {
    container(data, b"\xABKTX 20\xBB\r\n\x1A\n", "f.ktx2");
}

fn volume_options() -> VolumeOptions {
    VolumeOptions::default().max_bytes(MAX_BYTES)
}

/// A NIfTI-1 file (gzipped when the bytes start with the gzip magic).
pub fn nifti(data: &[u8]) {
    let name = if data.starts_with(&[0x1f, 0x8b]) {
        "f.nii.gz"
    } else {
        "f.nii"
    };
    let _ = load_volume_with(&write(name, data), None, &volume_options());
}

/// A NRRD file: attached, or a header `f.nhdr` and after a line `#DATA` the `d.raw` its
/// `data file` may name.
pub fn nrrd(data: &[u8]) {
    let split = data.windows(6).position(|w| w == b"\n#DATA");
    let path = match split {
        Some(i) => {
            write("d.raw", &data[i + 6..]);
            write("f.nhdr", &data[..i + 1])
        }
        None => write("f.nrrd", data),
    };
    let _ = load_volume_with(&path, None, &volume_options());
}

/// A raw volume: the first four bytes choose the grid (each axis 1..=32) and the voxel type,
/// the rest is the file.
pub fn raw(data: &[u8]) {
    if data.len() < 4 {
        return;
    }
    let dims = [data[0], data[1], data[2]].map(|d| u32::from(d % 32) + 1);
    let types = [
        ScalarType::U8,
        ScalarType::I8,
        ScalarType::U16,
        ScalarType::I16,
        ScalarType::U32,
        ScalarType::I32,
        ScalarType::F32,
        ScalarType::F64,
    ];
    let mut desc = RawDesc::new(dims, types[usize::from(data[3] % 8)], glam::Vec3::ONE);
    desc.big_endian = data[3] & 0x80 != 0;
    let _ = load_volume_with(&write("f.raw", &data[4..]), Some(&desc), &volume_options());
}

/// Every target by name, for the regression replay.
/// A fuzz target: bytes in, a clean load or a clean error out (a panic is the fault).
pub type Target = fn(&[u8]);

pub const TARGETS: [(&str, Target); 11] = [
    ("gltf", gltf),
    ("glb", glb),
    ("obj", obj),
    ("toml", toml),
    ("image", image),
    ("nifti", nifti),
    ("nrrd", nrrd),
    ("raw", raw),
    ("dds", dds),
    ("ktx", ktx),
    ("ktx2", ktx2),
];
