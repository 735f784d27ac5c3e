//! Loads the real images of the shared asset corpus (`../shared/assets`, present on CI) through
//! the texture engine: PNG, JPEG, Radiance HDR, OpenEXR and the six JPEG faces of a cube map.
//! Skipped, with a message, when the corpus is absent.

mod common;

use common::assets;

use glam::{Vec2, Vec3, Vec4};
use texmap::texture::load::{load_texture, Limits};
use texmap::texture::{
    sample, sample_cube, ColorSpace, CubeFootprint, Filter, Footprint, Format, Sampler,
    TextureCube, Wrap,
};

fn mean_of_last_level(t: &texmap::texture::Texture2D) -> Vec4 {
    let last = t.levels().len() - 1;
    t.decode_level(last)[0]
}

#[test]
fn photos_load_with_full_mip_chains() {
    let Some(root) = assets() else { return };
    let dir = root.join("textures/photos");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let t = load_texture(&path, ColorSpace::Srgb, &Limits::default()).unwrap();
        assert_eq!(
            t.levels().last().map(|l| (l.width(), l.height())),
            Some((1, 1)),
            "{}",
            path.display()
        );
        // The 1×1 level is the image mean: a plausible colour, opaque.
        let m = mean_of_last_level(&t);
        assert!(
            m.truncate().cmpgt(Vec3::splat(0.005)).all() && m.truncate().cmplt(Vec3::ONE).all(),
            "{}: {m}",
            path.display()
        );
        assert!((m.w - 1.0).abs() < 1e-6);
        // Every filter reads it without leaving the value range.
        for f in ["nearest", "trilinear", "aniso16", "ewa", "sat"] {
            let s = Sampler::new(Filter::parse(f).unwrap(), Wrap::Repeat);
            let c = sample(
                &t,
                &s,
                &Footprint::new(
                    Vec2::new(0.3, 0.6),
                    Vec2::new(0.05, 0.0),
                    Vec2::new(0.0, 0.002),
                ),
            );
            assert!(
                c.cmpge(Vec4::ZERO).all() && c.cmple(Vec4::ONE + 1e-5).all(),
                "{f} {}: {c}",
                path.display()
            );
        }
        n += 1;
    }
    assert!(n >= 5, "expected the photos in {}", dir.display());
}

#[test]
fn hdr_and_exr_load_as_linear_float() {
    let Some(root) = assets() else { return };
    let hdr = load_texture(
        &root.join("env/equirect/venice_sunset_1k.hdr"),
        ColorSpace::Srgb,
        &Limits::default(),
    )
    .unwrap();
    assert_eq!(hdr.format(), Format::Rgba32F);
    assert_eq!(hdr.color_space(), ColorSpace::Linear);
    // A sunset has texels brighter than 1.
    assert!(hdr.decode_level(0).iter().any(|c| c.max_element() > 1.0));
    let exr_path = root.join("env/equirect/blender_studiolight_forest.exr");
    match load_texture(&exr_path, ColorSpace::Linear, &Limits::default()) {
        Ok(t) => assert_eq!(t.format(), Format::Rgba32F),
        // DWAB compression: the exr crate does not decode it; the error must name the file.
        Err(e) => assert!(
            e.to_string().contains("blender_studiolight_forest.exr"),
            "{e}"
        ),
    }
}

#[test]
fn bridge_cube_map_is_seamless() {
    let Some(root) = assets() else { return };
    let dir = root.join("env/cube/Bridge2");
    let faces = ["posx", "negx", "posy", "negy", "posz", "negz"].map(|f| {
        load_texture(
            &dir.join(format!("{f}.jpg")),
            ColorSpace::Srgb,
            &Limits::default(),
        )
        .unwrap()
    });
    let cube = TextureCube::new(faces).unwrap();
    let s = Sampler::new(Filter::TRILINEAR, Wrap::ClampToEdge);
    // Straddle the +X/+Z edge: the two sides agree closely (no seam).
    for y in [-0.6f32, -0.2, 0.3, 0.7] {
        let read = |d: Vec3| {
            sample_cube(
                &cube,
                &s,
                &CubeFootprint {
                    dir: d,
                    ..Default::default()
                },
            )
        };
        let a = read(Vec3::new(1.0, y, 0.9995));
        let b = read(Vec3::new(0.9995, y, 1.0));
        assert!((a - b).abs().max_element() < 0.03, "y {y}: {a} vs {b}");
    }
}
