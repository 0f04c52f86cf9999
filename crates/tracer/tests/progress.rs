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
