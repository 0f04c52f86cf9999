//! `RandomSpheres`: Suffern's benchmark spheres, drawn by the tracer's
//! portable LCG so a scene file reproduces the benchmark (and the Embree
//! peer) exactly.

use crate::model::r64;
use gridrt_bbox::{Real, Vec3};
use gridrt_tracer::{suffern, SphereSet};

/// `count` spheres for `seed`, in the box `lo..hi`, with their random
/// colours: the set the scene's object holds, drawn once, straight into
/// its arrays.
///
/// In the default box `[−1, 1]³` the centres and radius are bit for bit
/// those of [`suffern::spheres`]. Another box maps the same centres
/// affinely into it, and the default radius (Suffern's: total volume 0.1)
/// is scaled by the cube root of the box's volume over 8, so the spheres
/// fill the same fraction of it.
pub(crate) fn spheres(
    count: u32,
    seed: u64,
    radius: Option<f64>,
    lo: [f64; 3],
    hi: [f64; 3],
) -> SphereSet {
    let unit = lo == [-1.0; 3] && hi == [1.0; 3];
    let volume_ratio = (0..3).map(|a| (hi[a] - lo[a]) / 2.0).product::<f64>();
    let r = radius.map(|r| r as Real);
    let mut set = suffern::sphere_set(count as usize, seed);
    for s in &mut set.spheres {
        if unit {
            s.radius = r.unwrap_or(s.radius);
        } else {
            let c = [s.center.x, s.center.y, s.center.z];
            let m = |a: usize| lo[a] + (r64(c[a]) + 1.0) * 0.5 * (hi[a] - lo[a]);
            s.center = Vec3::new(m(0) as Real, m(1) as Real, m(2) as Real);
            s.radius = r.unwrap_or((r64(s.radius) * volume_ratio.cbrt()) as Real);
        }
    }
    set
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_box_matches_the_benchmark_exactly() {
        let ours = spheres(100, 15, None, [-1.0; 3], [1.0; 3]);
        let theirs = suffern::spheres(100, 15);
        assert_eq!(ours.spheres.len(), 100);
        assert_eq!(ours.colors.len(), 100);
        for (k, (s, b)) in ours.spheres.iter().zip(&theirs).enumerate() {
            let c = ours.colors.get(k);
            assert_eq!((s.center, s.radius, c), (b.center, b.radius, Some(b.color)));
        }
    }

    #[test]
    fn other_boxes_scale_centres_and_radius() {
        let ours = spheres(50, 3, None, [0.0; 3], [4.0; 3]);
        let theirs = suffern::spheres(50, 3);
        for (a, b) in ours.spheres.iter().zip(&theirs) {
            assert!(a.center.min_element() >= 0.0 && a.center.max_element() <= 4.0);
            assert!((a.radius - 2.0 * b.radius).abs() < 1e-5);
        }
        let fixed = spheres(5, 3, Some(0.5), [0.0; 3], [4.0; 3]);
        assert!(fixed.spheres.iter().all(|s| s.radius == 0.5));
    }
}
