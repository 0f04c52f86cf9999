//! `Renderer::render_rows`: any set of rows, rendered alone, equals the same
//! rows of the full image bit for bit.

use crate::common::*;
use gridrt_tracer::{suffern, AccelKind, Framebuffer, RenderOptions, Renderer};
use std::sync::atomic::AtomicBool;

fn rows_of(full: &Framebuffer, rows: &[u32]) -> Vec<gridrt_tracer::Rgb> {
    let w = full.width as usize;
    rows.iter()
        .flat_map(|&y| {
            full.pixels[y as usize * w..(y as usize + 1) * w]
                .iter()
                .copied()
        })
        .collect()
}

fn check(r: &Renderer, rows: &[u32]) {
    let never = AtomicBool::new(false);
    let (full, fs) = r.render(&|_, _| {}, &never).unwrap();
    let (part, ps) = r.render_rows(rows, &|_, _| {}, &never).unwrap();
    assert_eq!((part.width, part.height), (full.width, rows.len() as u32));
    assert!(part.pixels == rows_of(&full, rows), "rows {rows:?} differ");
    let spp = fs.rays.camera / u64::from(full.width * full.height);
    assert_eq!(
        ps.rays.camera,
        u64::from(full.width) * rows.len() as u64 * spp
    );
}

#[test]
fn rows_equal_the_rows_of_the_full_render() {
    // Every effect, 2 samples per pixel (jittered), an odd size.
    let scene = kitchen_sink(37, 29);
    let every_3rd: Vec<u32> = (1..29).step_by(3).collect();
    let shuffled = [28, 0, 13, 13, 7, 27, 1];
    for accel in [AccelKind::Grid, AccelKind::Exhaustive] {
        for threads in [Some(1), Some(2)] {
            let r = Renderer::new(&scene, &opts(accel, threads)).unwrap();
            assert_eq!(r.size(), (37, 29));
            check(&r, &every_3rd);
            check(&r, &shuffled);
            check(&r, &(0..29).collect::<Vec<_>>());
            check(&r, &[]);
        }
    }
}

#[test]
fn benchmark_rows_spread_over_the_image() {
    let rows: Vec<u32> = (0..8).map(|i| 25 + 50 * i).collect();
    for accel in [AccelKind::Grid, AccelKind::Exhaustive] {
        let o = RenderOptions {
            accel,
            ..RenderOptions::default()
        };
        let r = suffern::renderer(2000, suffern::DEFAULT_SEED, &o).unwrap();
        check(&r, &rows);
    }
}

#[test]
#[should_panic(expected = "row 400 outside an image 400 rows high")]
fn a_row_below_the_image_panics() {
    let r = suffern::renderer(10, suffern::DEFAULT_SEED, &RenderOptions::default()).unwrap();
    let _ = r.render_rows(&[0, 400], &|_, _| {}, &AtomicBool::new(false));
}
