//! Tests of the TOML loader as a whole: files written to a scratch folder and loaded.

use std::path::PathBuf;

use glam::{Vec3, Vec4};

use super::load;
use crate::camera::CameraProjection;
use crate::geometry::Projection;
use crate::scene::{LoadOptions, ShadingModel};
use crate::texture::procedural::Solid;

fn write(name: &str, body: &str) -> PathBuf {
    crate::scene::test_file("toml", name, body)
}

#[test]
fn primitives_materials_lights_and_camera() {
    let p = write(
        "ok.toml",
        r#"
background = [0.1, 0.1, 0.1, 1]
[[cameras]]
eye = [0, 2, 5]
target = [0, 0, 0]
[[lights]]
type = "point"
position = [0, 3, 0]
intensity = 10
[materials.red]
base_color = [1, 0, 0, 1]
[[meshes]]
primitive = "torus"
material = "red"
translate = [1, 0, 0]
[[meshes]]
primitive = "plane"
size = 10
"#,
    );
    let l = load(&p, &LoadOptions::default()).unwrap();
    assert_eq!(l.scene.meshes.len(), 2);
    assert_eq!(l.scene.meshes[0].material, 0);
    assert_eq!(l.scene.meshes[1].material, 1);
    assert_eq!(l.scene.lights.len(), 1);
    assert!(l.scene.camera.is_some());
    assert_eq!(l.scene.meshes[0].world_from_object.w_axis.x, 1.0);
}

#[test]
fn pbr_model_and_solid_roughness_and_bump_channels() {
    let p = write(
        "pbr.toml",
        r#"
[materials.stone]
model = "pbr"
metallic = 0.25
roughness_procedural = { pattern = "granite", range = [0.3, 0.9] }
bump_procedural = { pattern = "marble", scale = 0.05, antialias = false }
[materials.plain]
roughness = 0.5
"#,
    );
    let l = load(&p, &LoadOptions::default()).unwrap();
    let (plain, stone) = (&l.scene.materials[0], &l.scene.materials[1]);
    assert_eq!(plain.model, ShadingModel::Phong);
    assert!(plain.solid_maps.is_empty());
    assert_eq!(stone.model, ShadingModel::MetallicRoughness);
    assert_eq!(stone.metallic, 0.25);
    let (r, range) = stone.solid_roughness().unwrap();
    assert_eq!(range, [0.3, 0.9]);
    assert_eq!(r.solid, Solid::named("granite").unwrap());
    assert!(r.antialias);
    let (b, scale) = stone.solid_bump().unwrap();
    assert_eq!(scale, 0.05);
    assert!(!b.antialias);
}

#[test]
fn bad_model_and_solid_channel_keys_are_errors() {
    for (name, body, needle) in [
        ("m.toml", "[materials.a]\nmodel = \"blinn\"\n", "blinn"),
        (
            "r.toml",
            "[materials.a]\nroughness_procedural = { pattern = \"granite\", colors = [[0,0,0],[1,1,1]] }\n",
            "colors",
        ),
        (
            "b.toml",
            "[materials.a]\nbump_procedural = { pattern = \"lava\" }\n",
            "lava",
        ),
        (
            "r2.toml",
            "[materials.a]\nroughness_procedural = { pattern = \"wood\", range = [0, 2] }\n",
            "range",
        ),
    ] {
        let p = write(name, body);
        let e = load(&p, &LoadOptions::default()).unwrap_err().to_string();
        assert!(e.contains(needle), "{name}: {e}");
    }
}

#[test]
fn orthographic_cameras_take_a_height() {
    let cam = |body: &str| {
        let p = write(
            "cam.toml",
            &format!("[[cameras]]\neye = [0, 0, 5]\ntarget = [0, 0, 0]\n{body}"),
        );
        load(&p, &LoadOptions::default()).map(|l| l.scene.camera.unwrap().projection)
    };
    assert_eq!(
        cam("projection = \"orthographic\"\nheight = 4\nnear = 0\n").unwrap(),
        CameraProjection::Orthographic { half_height: 2.0 }
    );
    assert_eq!(
        cam("fov = 45\n").unwrap(),
        CameraProjection::Perspective { fov_y_deg: 45.0 }
    );
    for (bad, says) in [
        ("projection = \"orthographic\"\n", "needs `height`"),
        (
            "projection = \"orthographic\"\nheight = 4\nfov = 30\n",
            "`fov`",
        ),
        ("height = 4\n", "`height`"),
        ("projection = \"fisheye\"\n", "fisheye"),
        ("projection = \"orthographic\"\nheight = -1\n", "height"),
    ] {
        let e = cam(bad).unwrap_err().to_string();
        assert!(e.contains("cam.toml") && e.contains(says), "{bad}: {e}");
    }
}

#[test]
fn texgen_writes_a_uv_set_from_the_projection() {
    let p = write(
        "texgen.toml",
        r#"
[[meshes]]
primitive = "sphere"
texgen = { projection = "spherical" }
[[meshes]]
primitive = "cube"
texgen = { projection = "cube", set = 1 }
"#,
    );
    let l = load(&p, &LoadOptions::default()).unwrap();
    let (sphere, cube) = (&l.scene.meshes[0], &l.scene.meshes[1]);
    assert_eq!(sphere.uvs.len(), sphere.positions.len());
    // Off the seam copies, each vertex's uv is the projection of its position.
    let mut matched = 0;
    for (p, uv) in sphere.positions.iter().zip(&sphere.uvs) {
        let want = Projection::Spherical.map(*p, Vec3::Y);
        if (want - *uv).abs().max_element() < 1e-5 {
            matched += 1;
        }
    }
    assert!(matched * 10 >= sphere.uvs.len() * 9, "{matched}");
    assert!(sphere
        .indices
        .iter()
        .all(|&i| (i as usize) < sphere.positions.len()));
    assert_eq!(cube.uvs1.len(), cube.positions.len());
    for (k, e) in [
        ("texgen = { projection = \"conic\" }", "conic"),
        ("texgen = { projection = \"cube\", set = 2 }", "set 2"),
    ] {
        let p = write(
            "bad_texgen.toml",
            &format!("[[meshes]]\nprimitive = \"cube\"\n{k}\n"),
        );
        let msg = load(&p, &LoadOptions::default()).unwrap_err().to_string();
        assert!(msg.contains(e) && msg.contains("meshes[0]"), "{msg}");
    }
}

#[test]
fn unknown_key_names_the_line() {
    let p = write("bad.toml", "[[meshes]]\nprimitive = \"cube\"\ncolour = 3\n");
    let e = load(&p, &LoadOptions::default()).unwrap_err().to_string();
    assert!(
        e.contains("bad.toml") && e.contains("line 3") && e.contains("colour"),
        "{e}"
    );
}

#[test]
fn unknown_material_and_primitive_are_errors() {
    let p = write(
        "bad2.toml",
        "[[meshes]]\nprimitive = \"cube\"\nmaterial = \"nope\"\n",
    );
    assert!(load(&p, &LoadOptions::default())
        .unwrap_err()
        .to_string()
        .contains("nope"));
    let p = write("bad3.toml", "[[meshes]]\nprimitive = \"blob\"\n");
    assert!(load(&p, &LoadOptions::default())
        .unwrap_err()
        .to_string()
        .contains("blob"));
}

/// A 2×2 grey PNG beside the test's scene files.
fn png(name: &str) {
    let mut bytes = Vec::new();
    image::RgbaImage::from_pixel(2, 2, image::Rgba([128, 128, 128, 255]))
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .unwrap();
    crate::scene::test_file("toml", name, bytes);
}

#[test]
fn lod_clamps_and_border_reach_the_sampler() {
    png("grey_ok.png");
    let p = write(
        "sampler_keys.toml",
        r#"
[materials.a.base_color_texture]
file = "grey_ok.png"
wrap_u = "border"
min_lod = 0.5
max_lod = 2
border = [1, 0.5, 0, 0.5]
[materials.b.base_color_texture]
file = "grey_ok.png"
"#,
    );
    let l = load(&p, &LoadOptions::default()).unwrap();
    let s = l.scene.materials[0]
        .base_color_texture
        .as_ref()
        .unwrap()
        .sampler;
    assert_eq!((s.min_lod, s.max_lod), (0.5, 2.0));
    // Straight alpha in the file, premultiplied in the sampler.
    assert_eq!(s.border, Vec4::new(0.5, 0.25, 0.0, 0.5));
    let d = l.scene.materials[1]
        .base_color_texture
        .as_ref()
        .unwrap()
        .sampler;
    let default = crate::texture::Sampler::default();
    assert_eq!(
        (d.min_lod, d.max_lod, d.border),
        (default.min_lod, default.max_lod, default.border)
    );
}

#[test]
fn bad_lod_clamps_and_borders_name_the_file_and_key() {
    png("grey_bad.png");
    for (keys, says) in [
        ("min_lod = 3\nmax_lod = 1", "min_lod 3 is above max_lod 1"),
        ("min_lod = 2000", "min_lod 2000 is above max_lod 1000"),
        ("min_lod = nan", "min_lod NaN is not a finite number"),
        ("max_lod = inf", "max_lod inf is not a finite number"),
        ("max_lod = -inf", "max_lod -inf is not a finite number"),
        (
            "wrap = \"border\"\nborder = [1, 0, 0, 2]",
            "border [1.0, 0.0, 0.0, 2.0]",
        ),
        ("wrap = \"border\"\nborder = [-1, 0, 0, 1]", "border [-1.0"),
        ("wrap = \"border\"\nborder = [nan, 0, 0, 1]", "border [NaN"),
        ("wrap = \"clamp\"\nborder = [1, 0, 0, 1]", "no axis does"),
        ("border = [1, 0, 0, 1]", "no axis does"),
        ("wrap = \"border\"\nborder = [1, 0, 0]", "line 4"),
        (
            "wrap_v = \"edge\"",
            "wrap_v \"edge\": expected one of: repeat",
        ),
    ] {
        let p = write(
            "bad_sampler_keys.toml",
            &format!("[materials.wood.maps.normal]\nfile = \"grey_bad.png\"\n{keys}\n"),
        );
        let e = load(&p, &LoadOptions::default()).unwrap_err().to_string();
        assert!(
            e.contains("bad_sampler_keys.toml") && e.contains(says) && !e.contains('\n'),
            "{keys}: {e}"
        );
        if !says.starts_with("line") {
            assert!(e.contains("materials.wood: maps.normal: "), "{keys}: {e}");
        }
    }
}
