//! Progress reports and cancellation.

use crate::common::*;
use gridrt_tracer::{Cancelled, RenderOptions, Renderer};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

#[test]
fn progress_reaches_the_total() {
    let scene = kitchen_sink(50, 35);
    for threads in [Some(1), Some(2)] {
        let r = Renderer::new(&scene, &opts(Default::default(), threads)).unwrap();
        let last = AtomicU64::new(0);
        let calls = AtomicU64::new(0);
        let (img, _) = r
            .render(
                &|done, total| {
                    assert_eq!(total, 50 * 35);
                    assert!(done <= total);
                    last.fetch_max(done, Ordering::Relaxed);
                    calls.fetch_add(1, Ordering::Relaxed);
                },
                &AtomicBool::new(false),
            )
            .unwrap();
        assert_finite(&img);
        assert_eq!(last.load(Ordering::Relaxed), 50 * 35);
        // One call per 16 × 16 tile.
        assert_eq!(calls.load(Ordering::Relaxed), 4 * 3);
    }
}

#[test]
fn cancel_stops_the_render() {
    let scene = kitchen_sink(64, 64);
    for threads in [Some(1), Some(2)] {
        let r = Renderer::new(&scene, &opts(Default::default(), threads)).unwrap();
        let cancel = AtomicBool::new(false);
        let calls = AtomicU64::new(0);
        let out = r.render(
            &|_, _| {
                calls.fetch_add(1, Ordering::Relaxed);
                cancel.store(true, Ordering::Relaxed);
            },
            &cancel,
        );
        assert_eq!(out.unwrap_err(), Cancelled);
        // Tiles already running may finish, the rest are skipped.
        assert!(calls.load(Ordering::Relaxed) < 16, "{calls:?}");
        // Raised before the start: nothing is rendered.
        let out = r.render(&|_, _| panic!("no tile should run"), &AtomicBool::new(true));
        assert!(out.is_err());
    }
    // The renderer is reusable after a cancelled render.
    let r = Renderer::new(&scene, &RenderOptions::default()).unwrap();
    let _ = r.render(&|_, _| {}, &AtomicBool::new(true));
    assert!(r.render(&|_, _| {}, &AtomicBool::new(false)).is_ok());
}

#[test]
fn live_image_follows_the_render_and_keeps_an_interrupted_one() {
    use gridrt_tracer::LiveImage;
    let scene = kitchen_sink(80, 48);
    for threads in [Some(1), Some(2)] {
        let r = Renderer::new(&scene, &opts(Default::default(), threads)).unwrap();
        let never = AtomicBool::new(false);
        let (full, stats) = r.render(&|_, _| {}, &never).unwrap();

        // Watched to the end: the same image, every tile done, every ray
        // counted.
        let live = LiveImage::new();
        assert!(live.snapshot().is_none());
        let (img, _) = r.render_live(&|_, _| {}, &never, &live).unwrap();
        assert_eq!(img, full);
        assert_eq!(live.snapshot().unwrap(), full);
        assert!(live.missing().is_empty());
        assert_eq!(live.tile_count(), 5 * 3);
        assert_eq!(live.rays(), stats.rays.total());
        // Counting rays only: the same image and count, no copy of it.
        let counter = LiveImage::rays_only();
        let (img, _) = r.render_live(&|_, _| {}, &never, &counter).unwrap();
        assert_eq!(img, full);
        assert_eq!(counter.rays(), stats.rays.total());
        assert!(counter.snapshot().is_none());
        // As 8-bit sRGB, tile by tile: each byte the code of its linear
        // channel, and the same rays.
        let counter = LiveImage::rays_only();
        let (png, _) = r.render_srgb8(&|_, _| {}, &never, &counter).unwrap();
        assert_eq!((png.width, png.height), (80, 48));
        let codes: Vec<u8> = full
            .pixels
            .iter()
            .flat_map(|p| [p.x, p.y, p.z].map(gridrt_tracer::srgb8))
            .collect();
        assert_eq!(png.bytes, codes);
        assert_eq!(png, gridrt_tracer::Srgb8Image::from_linear(&full));
        assert!(codes.iter().any(|&c| c > 0 && c < 255));
        assert_eq!(counter.rays(), stats.rays.total());

        // Cancelled after four tiles: what was done is kept, pixel for
        // pixel, and the missing tiles are exactly the black rest.
        let cancel = AtomicBool::new(false);
        let tiles = AtomicU64::new(0);
        let live = LiveImage::new();
        let out = r.render_live(
            &|_, _| {
                if tiles.fetch_add(1, Ordering::SeqCst) + 1 >= 4 {
                    cancel.store(true, Ordering::SeqCst);
                }
            },
            &cancel,
            &live,
        );
        assert!(matches!(out, Err(Cancelled)));
        let part = live.snapshot().unwrap();
        let missing = live.missing();
        assert!(!missing.is_empty() && missing.len() <= 15 - 4);
        let in_missing = |x: u32, y: u32| {
            missing
                .iter()
                .any(|m| (m.x0..m.x1).contains(&x) && (m.y0..m.y1).contains(&y))
        };
        for y in 0..48 {
            for x in 0..80 {
                if !in_missing(x, y) {
                    assert_eq!(part.get(x, y), full.get(x, y), "pixel ({x}, {y})");
                }
            }
        }
    }
}
