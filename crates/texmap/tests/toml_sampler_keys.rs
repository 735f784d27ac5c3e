//! The TOML texture tables' `min_lod`, `max_lod` and `border` keys change what is drawn:
//! 64×64 texels of one-texel black and white stripes on a unit plane seen from straight above
//! (orthographic, unlit), rendered with and without each key. From mip level 1 on, the
//! stripes are grey.

use texmap::metrics::compare_rgb8;
use texmap::render::{render, Settings};
use texmap::scene::{load, LoadOptions};

const SIZE: u32 = 64;

/// Renders a scene whose unit plane shows the stripes with the texture keys `keys`, seen
/// from above by an orthographic camera `height` world units tall.
fn draw(name: &str, height: f32, keys: &str) -> Vec<u8> {
    let dir = std::env::temp_dir().join(format!("texmap-sampler-keys-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let stripes = dir.join(format!("{name}.png"));
    image::RgbImage::from_fn(64, 64, |x, _| {
        image::Rgb(if x % 2 == 0 { [255; 3] } else { [0; 3] })
    })
    .save(&stripes)
    .unwrap();
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(
        &scene,
        format!(
            r#"
[[cameras]]
eye = [0, 2, 0]
target = [0, 0, 0]
up = [0, 0, -1]
projection = "orthographic"
height = {height}
[materials.stripes]
unlit = true
[materials.stripes.base_color_texture]
file = "{name}.png"
{keys}
[[meshes]]
primitive = "plane"
material = "stripes"
"#
        ),
    )
    .unwrap();
    let loaded = load(&scene, &LoadOptions::default()).unwrap();
    let settings = Settings::new(SIZE, SIZE);
    render(&loaded.scene, &loaded.scene.camera.unwrap(), &settings)
        .unwrap()
        .to_srgb8()
}

/// PSNR of two renders, in dB.
fn psnr(a: &[u8], b: &[u8]) -> f64 {
    compare_rgb8(a, b, SIZE as usize, SIZE as usize, None).psnr_db
}

/// A difference far beyond noise: 20 dB is an RMS error of 25 levels of 255.
const DIFFERENT_DB: f64 = 20.0;

#[test]
fn max_lod_0_keeps_minified_stripes_at_their_finest_level() {
    // 3 texels a pixel: trilinear reads near level 1.6, where the stripes are grey.
    let mipmapped = draw("max_default", 3.0, "");
    let finest = draw("max_0", 3.0, "max_lod = 0");
    assert_eq!(draw("max_big", 3.0, "max_lod = 12"), mipmapped);
    let db = psnr(&mipmapped, &finest);
    assert!(db < DIFFERENT_DB, "max_lod = 0 vs default: {db:.1} dB");
}

#[test]
fn min_lod_blurs_magnified_stripes() {
    // 4 pixels a texel: magnified, the stripes are sharp.
    let sharp = draw("min_default", 0.25, "");
    let blurred = draw("min_2", 0.25, "min_lod = 2");
    assert_eq!(draw("min_low", 0.25, "min_lod = -4"), sharp);
    let db = psnr(&sharp, &blurred);
    assert!(db < DIFFERENT_DB, "min_lod = 2 vs default: {db:.1} dB");
}

#[test]
fn border_colours_the_plane_outside_the_image() {
    // uv 0..3 across the plane: eight ninths of it read the border.
    let keys = "wrap = \"border\"\ntransform = { scale = [3, 3] }";
    let black = draw("border_default", 1.0, keys);
    let red = draw("border_red", 1.0, &format!("{keys}\nborder = [1, 0, 0, 1]"));
    let db = psnr(&black, &red);
    assert!(db < DIFFERENT_DB, "border red vs default: {db:.1} dB");
    // The corner pixel (far outside the image) is the border's red, in sRGB.
    assert_eq!(&red[red.len() - 3..], [255, 0, 0]);
    assert_eq!(&black[black.len() - 3..], [0, 0, 0]);
}
