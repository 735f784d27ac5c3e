//! Virtual texturing: a frame read through pages equals the same texture held whole, the
//! caches stay within their budgets, and the page counts are reported.

use std::sync::Arc;

use texmap::metrics::compare_rgb8;
use texmap::render::{render, Settings, TextureOverrides};
use texmap::scene::{builtin, Scene};
use texmap::texture::virtual_texture::{VirtualTexture, PAGE_BYTES};
use texmap::texture::{Filter, Sampler, Wrap};

/// The peers' grazing plane with `vt` on it, read through its pages, and the same plane
/// with the texture held whole.
fn scenes(vt: Arc<VirtualTexture>, uv_scale: f32, filter: Filter) -> (Scene, Scene) {
    let sampler = Sampler::new(filter, Wrap::Repeat);
    let whole = Arc::new(vt.resident_texture().unwrap());
    let resident = builtin::plane(Some(whole), uv_scale, sampler);
    let coarse = Arc::new(vt.coarse_texture().unwrap());
    let mut paged = builtin::plane(Some(coarse), uv_scale, sampler);
    for m in &mut paged.materials {
        if let Some(slot) = &mut m.base_color_texture {
            slot.virtual_texture = Some(vt.clone());
        }
    }
    (paged, resident)
}

fn psnr(a: &texmap::render::Frame, b: &texmap::render::Frame) -> f64 {
    let (w, h) = (a.width as usize, a.height as usize);
    compare_rgb8(&a.to_srgb8(), &b.to_srgb8(), w, h, None).psnr_db
}

#[test]
fn a_paged_frame_equals_the_texture_held_whole() {
    for filter in [Filter::TRILINEAR, Filter::aniso(8)] {
        let vt = Arc::new(
            VirtualTexture::quadtree(1024, 3, (Wrap::Repeat, Wrap::Repeat), 64 << 20).unwrap(),
        );
        let (paged, resident) = scenes(vt.clone(), 2.0, filter);
        let settings = Settings::new(256, 144);
        let cam = paged.camera.unwrap();
        let a = render(&paged, &cam, &settings).unwrap();
        let b = render(&resident, &cam, &settings).unwrap();
        let db = psnr(&a, &b);
        let s = a.stats.virtual_pages;
        eprintln!("{}: {db:.2} dB, {s:?}", filter.name());
        assert!(db >= 45.0, "{}: {db:.2} dB", filter.name());
        assert!(s.loaded > 0 && s.requested >= s.loaded);
        assert_eq!((s.evicted, s.over_budget), (0, 0));
        // A second frame of the same view asks for the same pages: all resident.
        let again = render(&paged, &cam, &settings).unwrap();
        assert_eq!(again.stats.virtual_pages.loaded, 0);
        assert_eq!(again.color, a.color);
    }
}

#[test]
fn a_small_budget_evicts_falls_back_and_stays_within_it() {
    let budget = 12 * PAGE_BYTES;
    let vt =
        Arc::new(VirtualTexture::quadtree(2048, 5, (Wrap::Repeat, Wrap::Repeat), budget).unwrap());
    let (paged, resident) = scenes(vt.clone(), 1.0, Filter::TRILINEAR);
    let settings = Settings::new(192, 108);
    let cam = paged.camera.unwrap();
    let a = render(&paged, &cam, &settings).unwrap();
    let s = a.stats.virtual_pages;
    assert!(s.over_budget > 0 && s.fallback_reads > 0, "{s:?}");
    assert_eq!(s.resident, 12);
    assert_eq!(vt.slots(), (12, 12));
    // Coarser where pages are missing, but the same picture.
    let b = render(&resident, &cam, &settings).unwrap();
    assert!(psnr(&a, &b) > 20.0);
    // Another view: pages move out, never beyond the budget.
    let turned = cam.orbit(1.0);
    let c = render(&paged, &turned, &settings).unwrap();
    assert!(
        c.stats.virtual_pages.evicted > 0,
        "{:?}",
        c.stats.virtual_pages
    );
    assert_eq!(vt.slots().1, 12);
    assert!(vt.totals().loaded >= s.loaded + c.stats.virtual_pages.loaded);
}

#[test]
fn budgets_below_the_coarsest_levels_and_whole_level_filters_are_refused() {
    let e = VirtualTexture::quadtree(65536, 1, (Wrap::Repeat, Wrap::Repeat), 1 << 20)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("too small") && e.contains("8 coarsest levels"),
        "{e}"
    );
    let e = VirtualTexture::quadtree(1000, 1, (Wrap::Repeat, Wrap::Repeat), 64 << 20)
        .unwrap_err()
        .to_string();
    assert!(e.contains("power of two"), "{e}");
    let e = VirtualTexture::quadtree(256, 1, (Wrap::MirroredRepeat, Wrap::Repeat), 64 << 20)
        .unwrap_err()
        .to_string();
    assert!(e.contains("repeat or clamp"), "{e}");

    let vt =
        Arc::new(VirtualTexture::quadtree(256, 1, (Wrap::Repeat, Wrap::Repeat), 4 << 20).unwrap());
    let (paged, _) = scenes(vt, 1.0, Filter::TRILINEAR);
    let mut overrides = TextureOverrides::default();
    overrides.filter = Some(Filter::SummedArea);
    let settings = Settings::new(32, 18).with_textures(overrides);
    let e = render(&paged, &paged.camera.unwrap(), &settings)
        .unwrap_err()
        .to_string();
    assert!(e.contains("not sat"), "{e}");
}

#[test]
fn the_image_does_not_depend_on_the_thread_count() {
    let frame = |threads| {
        let vt = Arc::new(
            VirtualTexture::quadtree(2048, 9, (Wrap::Repeat, Wrap::Repeat), 24 * PAGE_BYTES)
                .unwrap(),
        );
        let (paged, _) = scenes(vt, 4.0, Filter::TRILINEAR);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| render(&paged, &paged.camera.unwrap(), &Settings::new(160, 90)).unwrap())
    };
    let (a, b) = (frame(1), frame(3));
    assert_eq!(a.color, b.color);
    assert_eq!(a.stats.virtual_pages, b.stats.virtual_pages);
}
