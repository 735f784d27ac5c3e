//! The pipeline's modes, rendered: one golden image (PSNR ≥ 40 dB against
//! `tests/golden/pipeline_modes.png`, reviewed by eye) holding the embedded demo scene — a
//! textured floor to the horizon, a normal-mapped brick cube, marble spheres with highlights,
//! a blended glass pane — once per mode, so a change in any mode shows, and so the modes can be
//! compared side by side.
//!
//! Tiles, left to right and top to bottom (each 192×108):
//! 1. Phong shading, perspective-correct, z-buffer (the defaults)
//! 2. Gouraud shading
//! 3. flat shading
//! 4. unlit
//! 5. affine interpolation (the floor's texture swims)
//! 6. screen-space subdivision (affine inside, 1-pixel error bound)
//! 7. depth sort (painter's algorithm) instead of the z-buffer
//! 8. front-face culling (closed meshes show their insides; back-face culling leaves this
//!    scene unchanged)
//! 9. MSAA 4×
//! 10. MSAA 16×
//! 11. SSAA 2×2
//! 12. nearest filtering everywhere

mod common;

use texmap::render::{render, CullMode, Interpolation, Settings, ShadingMode, Visibility};
use texmap::scene::builtin;
use texmap::texture::{Filter, MagFilter, MinFilter};

const W: u32 = 192;
const H: u32 = 108;

fn modes() -> Vec<Settings> {
    let base = Settings::new(W, H);
    vec![
        base,
        base.with_shading(ShadingMode::Gouraud),
        base.with_shading(ShadingMode::Flat),
        base.with_unlit(true),
        base.with_interpolation(Interpolation::Affine),
        base.with_interpolation(Interpolation::Subdivide { max_error_px: 1.0 }),
        base.with_visibility(Visibility::DepthSort),
        base.with_cull(CullMode::Front),
        base.with_msaa(4),
        base.with_msaa(16),
        base.with_ssaa(2),
        base.with_textures(
            texmap::render::TextureOverrides::default().with_filter(Filter::Gl {
                mag: MagFilter::Nearest,
                min: MinFilter::Nearest,
            }),
        ),
    ]
}

#[test]
fn every_mode_renders_the_demo_scene_as_reviewed() {
    let scene = builtin::demo();
    let camera = scene.camera.expect("the demo has a camera");
    let modes = modes();
    let cols = 4usize;
    let rows = modes.len().div_ceil(cols);
    let (sw, sh) = (W as usize * cols, H as usize * rows);
    let mut sheet = vec![0u8; sw * sh * 3];
    let mut frames = Vec::new();
    for (i, s) in modes.iter().enumerate() {
        let frame = render(&scene, &camera, s).unwrap();
        let rgb = frame.to_srgb8();
        let (x0, y0) = ((i % cols) * W as usize, (i / cols) * H as usize);
        for y in 0..H as usize {
            let src = &rgb[y * W as usize * 3..][..W as usize * 3];
            sheet[((y0 + y) * sw + x0) * 3..][..W as usize * 3].copy_from_slice(src);
        }
        frames.push(rgb);
    }
    // Each mode changes the image, but none breaks it: every tile is close to the defaults'
    // and none is identical to them (flat-vs-Phong and the anti-aliasing modes differ least).
    for (i, rgb) in frames.iter().enumerate().skip(1) {
        let c = texmap::metrics::compare_rgb8(&frames[0], rgb, W as usize, H as usize, None);
        assert!(
            c.psnr_db > 10.0 && c.psnr_db < 80.0,
            "mode {}: PSNR {:.2} dB against the defaults",
            i + 1,
            c.psnr_db
        );
    }
    common::assert_golden("pipeline_modes", sw as u32, sh as u32, &sheet, 40.0);
}
