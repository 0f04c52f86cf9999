//! Ambient occlusion in scene files: `Ambient(.., occlusion: Occlusion(..))`
//! with its defaults, and bad values named with their place.

use crate::{fixture, parse_scene};
use gridrt_bbox::Real;
use gridrt_tracer::{Light, Occlusion};

fn ambient(light: &str) -> gridrt_io::Result<Light> {
    let src = format!("Scene(lights: [{light}], objects: [Sphere(center: (0, 0, 0), radius: 1)])");
    let s = parse_scene(&src, &fixture("scenes").join("x.ron"))?;
    Ok(s.scene.lights[0].clone())
}

fn occlusion(light: &str) -> Option<Occlusion> {
    match ambient(light).unwrap() {
        Light::Ambient { occlusion, .. } => occlusion,
        l => panic!("{l:?}"),
    }
}

#[test]
fn occlusion_is_off_by_default_and_has_suffern_defaults() {
    assert_eq!(occlusion("Ambient(intensity: 0.5)"), None);
    assert_eq!(
        occlusion("Ambient(intensity: 0.5, occlusion: Occlusion())"),
        Some(Occlusion {
            samples: 16,
            distance: Real::INFINITY,
            min_amount: 0.0
        })
    );
    assert_eq!(
        occlusion("Ambient(occlusion: (samples: 64, distance: 2.5, min_amount: 0.25))"),
        Some(Occlusion {
            samples: 64,
            distance: 2.5,
            min_amount: 0.25
        })
    );
}

#[test]
fn bad_occlusion_values_are_located_errors() {
    for (bad, says) in [
        ("samples: 0", "occlusion samples 0"),
        ("samples: 5000", "occlusion samples 5000"),
        ("distance: 0", "expected a number > 0"),
        ("distance: -1", "expected a number > 0"),
        ("min_amount: 2", "expected a number in [0, 1]"),
        ("radius: 2", "unknown field `radius`"),
    ] {
        let e = ambient(&format!("Ambient(occlusion: Occlusion({bad}))"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("x.ron:1:") && e.contains(says), "{bad}: {e}");
    }
}
