//! Texture containers end to end: every DDS, KTX and KTX2 file of the shared corpus
//! (`../shared/assets`, skipped with a message when absent) parses to the shape its
//! SOURCES.md line gives; cube map files make the same environment as their faces written out
//! and loaded through the folder loader; the file's own mip chain is kept.

mod common;

use common::assets;
use std::path::{Path, PathBuf};

use glam::{Vec3, Vec4};
use texmap::metrics::compare_rgb8;
use texmap::texture::container::{read_texture_file, Container, FileFormat, PlainFormat};
use texmap::texture::environment::equirect_direction;
use texmap::texture::load::{load_texture, Limits};
use texmap::texture::{
    load_environment, ColorSpace, CubeFootprint, EnvironmentKind, EnvironmentMap, Filter, Sampler,
    Wrap,
};

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("texmap-containers-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// Where images for a look by eye are written.
fn look_dir() -> PathBuf {
    let d = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/container-looks");
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn every_container_of_the_corpus_parses_to_its_declared_shape() {
    let Some(root) = assets() else { return };
    use texmap::texture::compressed::BlockFormat as B;
    let bc = FileFormat::Block;
    // (file, container, format, width, height, levels, faces, sRGB)
    let cases = [
        (
            "compressed/directx_sdk_samples/LobbyCube.dds",
            Container::Dds,
            bc(B::Bc1),
            256,
            256,
            1,
            6,
            false,
        ),
        (
            "compressed/directx_sdk_samples/MarbleClouds.dds",
            Container::Dds,
            bc(B::Bc3),
            512,
            512,
            1,
            1,
            false,
        ),
        (
            "compressed/directx_sdk_samples/RifleStock1Bump.dds",
            Container::Dds,
            bc(B::Bc1),
            747,
            600,
            10,
            1,
            false,
        ),
        (
            "compressed/directx_sdk_samples/gr_trans_b.dds",
            Container::Dds,
            bc(B::Bc3),
            256,
            256,
            1,
            1,
            false,
        ),
        (
            "compressed/directx_sdk_samples/seafloor.dds",
            Container::Dds,
            bc(B::Bc1),
            256,
            256,
            9,
            1,
            false,
        ),
        (
            "compressed/xbox_atg_fastblockcompress/alpha_offline_bc3.DDS",
            Container::Dds,
            bc(B::Bc3),
            1024,
            1024,
            11,
            1,
            false,
        ),
        (
            "compressed/xbox_atg_fastblockcompress/opaque_512.dds",
            Container::Dds,
            FileFormat::Plain(PlainFormat::Bgrx8),
            512,
            512,
            10,
            1,
            false,
        ),
        (
            "compressed/xbox_atg_fastblockcompress/opaque_512_offline_bc1.DDS",
            Container::Dds,
            bc(B::Bc1),
            512,
            512,
            10,
            1,
            false,
        ),
        (
            "compressed/xbox_atg_fastblockcompress/opaque_512_offline_bc7.dds",
            Container::Dds,
            bc(B::Bc7),
            512,
            512,
            10,
            1,
            false,
        ),
        (
            "compressed/bevy_ktx2/Ryfjallet_cubemap_bc7.ktx2",
            Container::Ktx2,
            bc(B::Bc7),
            512,
            512,
            1,
            6,
            true,
        ),
        (
            "env/cube/open3d_ktx1/park_skybox.ktx",
            Container::Ktx,
            FileFormat::Plain(PlainFormat::R11G11B10F),
            256,
            256,
            1,
            6,
            false,
        ),
    ];
    for (name, container, format, w, h, levels, faces, srgb) in cases {
        let f = read_texture_file(&root.join(name), &Limits::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let got = (
            f.container(),
            f.format(),
            f.width(),
            f.height(),
            f.levels(),
            f.faces(),
        );
        assert_eq!(got, (container, format, w, h, levels, faces), "{name}");
        assert_eq!(f.color_space() == ColorSpace::Srgb, srgb, "{name}");
        assert_eq!((f.layers(), f.depth()), (1, 1), "{name}");
        // Every image is as long as its level's size says.
        for face in 0..f.faces() {
            for level in 0..f.levels() {
                let (lw, lh, _) = f.level_size(level);
                let want = format.image_bytes(lw, lh);
                assert_eq!(f.data(0, face, level).unwrap().len() as u64, want, "{name}");
            }
        }
        eprintln!(
            "{name}: {} {} {w}x{h}, {levels} levels, {faces} faces, {} bytes of texels",
            f.container().name(),
            f.format().name(),
            f.texel_bytes()
        );
    }
}

/// AnisotropyBarnLamp's Basis Universal (UASTC, zstd) textures transcode to RGBA8 in the
/// colour space their descriptor names; the texels agree with the other road the transcoder
/// offers — UASTC to BC7, decoded by texmap's own BC7 decoder — within BC7's re-encoding
/// loss; a truncated or damaged file is one error naming it, never a panic.
#[test]
fn basis_universal_ktx2_transcodes_to_rgba8() {
    use texmap::texture::compressed::{decode_level_rgba8, BlockFormat};
    let Some(root) = assets() else { return };
    let dir = root.join("gltf/AnisotropyBarnLamp/glTF-KTX2-Basisu");
    for (name, space) in [
        ("AnisotropyBarnLamp_basecolor.ktx2", ColorSpace::Srgb),
        ("AnisotropyBarnLamp_normalbump.ktx2", ColorSpace::Linear),
        (
            "AnisotropyBarnLamp_occlusionroughnessmetal.ktx2",
            ColorSpace::Linear,
        ),
    ] {
        let path = dir.join(name);
        let f = read_texture_file(&path, &Limits::default()).unwrap();
        assert_eq!(f.transcoded_from(), Some("UASTC"), "{name}");
        assert_eq!(f.format(), FileFormat::Plain(PlainFormat::Rgba8), "{name}");
        assert_eq!(f.color_space(), space, "{name}");
        let (w, h) = (f.width(), f.height());
        let rgba = f.decode_rgba8(0, 0, 0).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let t = basisu::Transcoder::new(&bytes).unwrap();
        let bc7 = t
            .transcode(0, basisu::TargetFormat::Bc7Rgba, basisu::DecodeFlags::NONE)
            .unwrap();
        let via_bc7 = decode_level_rgba8(BlockFormat::Bc7, &bc7, w, h).unwrap();
        let rgb = |b: &[u8]| -> Vec<u8> { b.chunks(4).flat_map(|t| [t[0], t[1], t[2]]).collect() };
        let c = compare_rgb8(&rgb(&rgba), &rgb(&via_bc7), w as usize, h as usize, None);
        eprintln!(
            "{name}: RGBA32 against BC7 decoded by texmap: {:.2} dB",
            c.psnr_db
        );
        assert!(c.psnr_db >= 40.0, "{name}: {:.2} dB", c.psnr_db);
    }
    // Damaged copies of the smallest file: cut short, or bytes overwritten in its payload.
    let path = dir.join("AnisotropyBarnLamp_normalbump.ktx2");
    let bytes = std::fs::read(&path).unwrap();
    let damaged = std::env::temp_dir().join(format!("texmap-basis-{}.ktx2", std::process::id()));
    let mut cases: Vec<Vec<u8>> = [200, 1000, bytes.len() / 2, bytes.len() - 1]
        .iter()
        .map(|&n| bytes[..n].to_vec())
        .collect();
    for at in [bytes.len() / 3, bytes.len() / 2, bytes.len() - 100] {
        let mut b = bytes.clone();
        b[at..at + 64].iter_mut().for_each(|x| *x = !*x);
        cases.push(b);
    }
    for case in cases {
        std::fs::write(&damaged, &case).unwrap();
        // Ok is allowed for a payload damage the format cannot see; a panic is not.
        if let Err(e) = read_texture_file(&damaged, &Limits::default()) {
            let e = e.to_string();
            assert!(e.contains("texmap-basis-"), "{e}");
            assert_eq!(e.lines().count(), 1, "{e}");
        }
    }
    let _ = std::fs::remove_file(&damaged);
}

#[test]
fn opaque_512_loads_with_its_own_mip_chain() {
    let Some(root) = assets() else { return };
    let path = root.join("compressed/xbox_atg_fastblockcompress/opaque_512.dds");
    let file = read_texture_file(&path, &Limits::default()).unwrap();
    let t = load_texture(&path, ColorSpace::Linear, &Limits::default()).unwrap();
    assert_eq!(t.levels().len(), 10);
    // Level 4 (32x32) is the file's: its texels equal the file's bytes, swizzled from BGRX.
    let bytes = file.data(0, 0, 4).unwrap();
    for (x, y) in [(0u32, 0u32), (13, 7), (31, 31)] {
        let at = ((y * 32 + x) * 4) as usize;
        let want = Vec4::new(
            bytes[at + 2] as f32 / 255.0,
            bytes[at + 1] as f32 / 255.0,
            bytes[at] as f32 / 255.0,
            1.0,
        );
        let got = t.texel(4, x, y);
        assert!(
            (got - want).abs().max_element() < 1e-4,
            "({x}, {y}): {got} vs {want}"
        );
    }
}

/// An environment seen along every pixel of a 2:1 panorama, as sRGB8 RGB.
fn panorama(env: &EnvironmentMap, w: u32) -> Vec<u8> {
    let h = w / 2;
    let s = Sampler::new(Filter::BILINEAR, Wrap::ClampToEdge);
    let mut rgb = Vec::with_capacity((w * h * 3) as usize);
    for y in 0..h {
        for x in 0..w {
            let d = equirect_direction((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
            let c = env.sample(
                &s,
                &CubeFootprint {
                    dir: d,
                    ..Default::default()
                },
            );
            rgb.extend(c.truncate().to_array().map(texmap::color::linear_to_srgb8));
        }
    }
    rgb
}

/// The six faces of a cube map file written as images (`ext`: "exr" keeps floats, "png"
/// 8-bit) in a folder, for the faces loader.
fn faces_folder(path: &Path, ext: &str) -> PathBuf {
    let file = read_texture_file(path, &Limits::default()).unwrap();
    let dir = scratch(&format!(
        "{}-faces",
        path.file_stem().unwrap().to_string_lossy()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let (w, h) = (file.width(), file.height());
    for (face, name) in texmap::texture::environment::FACE_NAMES.iter().enumerate() {
        let out = dir.join(format!("{name}.{ext}"));
        if file.format().is_float() {
            let f = file.decode_f32(0, face as u32, 0).unwrap();
            let img = image::Rgba32FImage::from_raw(w, h, f).unwrap();
            image::DynamicImage::ImageRgba32F(img)
                .to_rgb32f()
                .save(&out)
                .unwrap();
        } else {
            let b = file.decode_rgba8(0, face as u32, 0).unwrap();
            image::RgbaImage::from_raw(w, h, b)
                .unwrap()
                .save(&out)
                .unwrap();
        }
    }
    dir
}

/// A cube map file and its faces written out make the same environment (≥ 40 dB over a
/// panorama), and the panorama is written for a look by eye.
fn cube_file_matches_its_faces(path: &Path, ext: &str) {
    let env = load_environment(path, None, &Limits::default()).unwrap();
    assert_eq!(env.kind(), EnvironmentKind::Faces);
    let folder = load_environment(&faces_folder(path, ext), None, &Limits::default()).unwrap();
    let (a, b) = (panorama(&env, 256), panorama(&folder, 256));
    let c = compare_rgb8(&a, &b, 256, 128, None);
    let stem = path.file_stem().unwrap().to_string_lossy().to_string();
    image::RgbImage::from_raw(256, 128, a)
        .unwrap()
        .save(look_dir().join(format!("{stem}_panorama.png")))
        .unwrap();
    eprintln!("{stem}: cube file vs its faces: PSNR {:.2} dB", c.psnr_db);
    assert!(c.psnr_db >= 40.0, "{stem}: {:.2} dB", c.psnr_db);
}

#[test]
fn park_skybox_ktx1_is_the_cube_of_its_faces() {
    let Some(root) = assets() else { return };
    let path = root.join("env/cube/open3d_ktx1/park_skybox.ktx");
    cube_file_matches_its_faces(&path, "exr");
    // Upright (as the panorama written for a look shows): sky in the upper quarter of the
    // panorama, bluer than the lower quarter's ground of yellow leaves.
    let env = load_environment(&path, None, &Limits::default()).unwrap();
    let rgb = panorama(&env, 256);
    let blue_share = |rows: std::ops::Range<usize>| {
        let (mut b, mut all) = (0.0, 0.0);
        for t in rgb[rows.start * 256 * 3..rows.end * 256 * 3].chunks(3) {
            b += f64::from(t[2]);
            all += f64::from(t[0]) + f64::from(t[1]) + f64::from(t[2]);
        }
        b / all
    };
    let (top, bottom) = (blue_share(0..32), blue_share(96..128));
    eprintln!("park skybox: blue share {top:.3} above, {bottom:.3} below");
    assert!(
        top > bottom + 0.05,
        "blue share {top:.3} above, {bottom:.3} below"
    );
}

#[test]
fn lobby_cube_dds_is_the_cube_of_its_faces() {
    let Some(root) = assets() else { return };
    cube_file_matches_its_faces(
        &root.join("compressed/directx_sdk_samples/LobbyCube.dds"),
        "png",
    );
}

#[test]
fn ktx2_bc7_cube_decodes_six_different_faces() {
    let Some(root) = assets() else { return };
    let path = root.join("compressed/bevy_ktx2/Ryfjallet_cubemap_bc7.ktx2");
    let file = read_texture_file(&path, &Limits::default()).unwrap();
    let faces: Vec<Vec<u8>> = (0..6)
        .map(|f| file.decode_rgba8(0, f, 0).unwrap())
        .collect();
    for (i, a) in faces.iter().enumerate() {
        assert_eq!(a.len(), 512 * 512 * 4);
        for b in &faces[i + 1..] {
            let rgb = |v: &[u8]| {
                v.chunks(4)
                    .flat_map(|t| [t[0], t[1], t[2]])
                    .collect::<Vec<u8>>()
            };
            let c = compare_rgb8(&rgb(a), &rgb(b), 512, 512, None);
            assert!(c.psnr_db < 30.0, "faces too alike: {:.2} dB", c.psnr_db);
        }
    }
    cube_file_matches_its_faces(&path, "png");
}

#[test]
fn bc1_and_bc7_of_opaque_512_are_close_to_their_source() {
    let Some(root) = assets() else { return };
    let dir = root.join("compressed/xbox_atg_fastblockcompress");
    let rgb = |name: &str, level: u32| {
        let f = read_texture_file(&dir.join(name), &Limits::default()).unwrap();
        let b = f.decode_rgba8(0, 0, level).unwrap();
        b.chunks(4)
            .flat_map(|t| [t[0], t[1], t[2]])
            .collect::<Vec<u8>>()
    };
    for (name, min_db) in [
        ("opaque_512_offline_bc1.DDS", 30.0),
        ("opaque_512_offline_bc7.dds", 38.0),
    ] {
        for level in [0, 3] {
            let n = (512 >> level) as usize;
            let c = compare_rgb8(&rgb(name, level), &rgb("opaque_512.dds", level), n, n, None);
            eprintln!(
                "{name} level {level} vs opaque_512.dds: PSNR {:.2} dB",
                c.psnr_db
            );
            assert!(
                c.psnr_db >= min_db,
                "{name} level {level}: {:.2} dB",
                c.psnr_db
            );
        }
    }
}

/// A BGRA8 cube map DDS of `n`² faces, each texel the colour of its direction.
fn direction_cube_dds(n: u32) -> Vec<u8> {
    let mut f = b"DDS ".to_vec();
    let mut hdr = [0u32; 31];
    (hdr[0], hdr[1], hdr[2], hdr[3], hdr[6]) = (124, 0x1007, n, n, 1);
    (hdr[18], hdr[19], hdr[21]) = (32, 0x41, 32);
    hdr[22..26].copy_from_slice(&[0xff_0000, 0xff00, 0xff, 0xff00_0000]);
    (hdr[26], hdr[27]) = (0x1008, 0xfe00);
    hdr.iter().for_each(|v| f.extend(v.to_le_bytes()));
    for face in texmap::texture::CubeFace::ALL {
        for y in 0..n {
            for x in 0..n {
                let sc = 2.0 * (x as f32 + 0.5) / n as f32 - 1.0;
                let tc = 2.0 * (y as f32 + 0.5) / n as f32 - 1.0;
                let g = face.direction_through(sc, tc).normalize();
                // Read mirrored in x (the environment convention).
                let c = (Vec3::new(-g.x, g.y, g.z) * 0.5 + Vec3::splat(0.5)) * 255.0;
                f.extend([c.z as u8, c.y as u8, c.x as u8, 255]);
            }
        }
    }
    f
}

#[test]
fn a_dds_cube_reads_the_directions_it_was_painted_with() {
    let path = scratch("directions.dds");
    std::fs::write(&path, direction_cube_dds(32)).unwrap();
    let env = load_environment(&path, None, &Limits::default()).unwrap();
    let s = Sampler::new(Filter::BILINEAR, Wrap::ClampToEdge);
    for d in [
        Vec3::X,
        Vec3::NEG_Y,
        Vec3::new(0.3, 0.5, -0.8),
        Vec3::new(-0.6, 0.1, 0.7),
    ] {
        let got = env.sample(
            &s,
            &CubeFootprint {
                dir: d,
                ..Default::default()
            },
        );
        let want = d.normalize() * 0.5 + Vec3::splat(0.5);
        // Texels are sRGB-encoded colour: compare encoded values.
        let enc = got.truncate().to_array().map(texmap::color::linear_to_srgb);
        let err = (Vec3::from(enc) - want).abs().max_element();
        assert!(err < 0.03, "{d}: {enc:?} vs {want}");
    }
    cube_file_matches_its_faces(&path, "png");
    // Asked for as another layout, it is refused by name.
    let e = load_environment(&path, Some(EnvironmentKind::Equirect), &Limits::default());
    let e = e.unwrap_err().to_string();
    assert!(
        e.contains("directions.dds") && e.contains("cube map"),
        "{e}"
    );
}
