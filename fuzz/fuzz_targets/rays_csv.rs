//! The rays CSV parser on arbitrary text; parsed rays answer queries
//! against one triangle without panicking.
#![no_main]

use gridrt_bbox::Vec3;
use gridrt_grid::{Exhaustive, Grid, GridConfig};
use gridrt_tracer::Triangle;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let Ok(rays) = gridrt_io::parse_rays(&text, std::path::Path::new("r.csv")) else {
        return;
    };
    let tri = || vec![Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y)];
    let grid = Grid::build(
        tri(),
        &GridConfig {
            parallel_build: false,
            ..GridConfig::default()
        },
    );
    let a = gridrt_io::trace_rays(&grid, &rays);
    let b = gridrt_io::trace_rays(&Exhaustive::new(tri()), &rays);
    assert_eq!(a, b);
    let _ = gridrt_io::format_hits(&a);
});
