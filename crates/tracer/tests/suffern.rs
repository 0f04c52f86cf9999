//! Suffern's benchmark scene: pixels hit match the Embree peer exactly.

use gridrt_tracer::suffern::{self, REFERENCE_PIXELS_HIT};
use gridrt_tracer::{AccelKind, RenderOptions, Renderer};

fn reference(n: usize) -> u64 {
    REFERENCE_PIXELS_HIT.iter().find(|r| r.0 == n).unwrap().1
}

#[test]
fn pixels_hit_match_the_reference_small() {
    for n in [10, 100, 1000] {
        let scene = suffern::scene(n);
        let r = Renderer::new(&scene, &RenderOptions::default()).unwrap();
        assert_eq!(r.count_camera_hits(), reference(n), "N = {n}");
        let (img, stats) = r.render(&|_, _| {}, &Default::default()).unwrap();
        crate::common::assert_finite(&img);
        assert_eq!(stats.pixels_hit, reference(n), "N = {n}");
        assert_eq!(stats.rays.total(), 160_000);
        assert_eq!(stats.plan.max_depth, 0);
        assert!(!stats.plan.shadows);
    }
    let exhaustive = RenderOptions {
        accel: AccelKind::Exhaustive,
        ..RenderOptions::default()
    };
    let r = Renderer::new(&suffern::scene(100), &exhaustive).unwrap();
    assert_eq!(r.count_camera_hits(), reference(100));
}

#[test]
fn pixels_hit_match_the_reference_10k() {
    let r = suffern::renderer(10_000, suffern::DEFAULT_SEED, &RenderOptions::default()).unwrap();
    assert_eq!(r.count_camera_hits(), reference(10_000));
}
