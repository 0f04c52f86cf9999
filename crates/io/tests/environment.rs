//! Environment lights from scene files: the image is read through the
//! sandbox and decoded; bad images and names fail with the file named.

use crate::{fixture, load_scene, parse_scene};
use gridrt_tracer::Light;

#[test]
fn the_fixture_sky_loads_as_an_equirectangular_image() {
    let s = load_scene(&fixture("scenes/environment.ron")).unwrap();
    let Some(Light::Environment {
        image: Some(img), ..
    }) = s.scene.lights.first()
    else {
        panic!("{:?}", s.scene.lights);
    };
    assert_eq!((img.width, img.height), (64, 32));
    assert_eq!(img.pixels.len(), 64 * 32);
    // The top rows are sky (blue), the bottom rows ground (dark).
    let top = img.pixels[64 * 2 + 5];
    let bottom = img.pixels[64 * 30 + 5];
    assert!(top.z > top.x && top.z > 0.8, "{top}");
    assert!(bottom.z < 0.2, "{bottom}");
    // The sun is the brightest pixel by far.
    let max = img.pixels.iter().map(|p| p.x).fold(0.0, f32::max);
    assert!(max > 30.0, "{max}");
}

#[test]
fn bad_environment_images_name_the_file() {
    let dir = fixture("scenes");
    let scene = |image: &str| {
        format!(
            "Scene(lights: [Environment(image: \"{image}\")], objects: [Sphere(center: (0, 0, 0), radius: 1)])"
        )
    };
    // Not an image format for environments.
    let e = parse_scene(&scene("../env/make_sky.py"), &dir.join("x.ron"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("x.ron") && e.contains(".hdr"), "{e}");
    // Missing.
    let e = parse_scene(&scene("../env/nothing.hdr"), &dir.join("x.ron"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("nothing.hdr"), "{e}");
    // Not a Radiance file inside.
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("bad.hdr"), b"not an image").unwrap();
    let e = parse_scene(&scene("bad.hdr"), &tmp.path().join("x.ron"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("bad.hdr") && e.contains("lights[0]"), "{e}");
}

#[test]
fn an_environment_light_is_no_ignored_request_under_either_integrator() {
    let dir = fixture("scenes");
    for integrator in ["Whitted", "Path", "Auto"] {
        let text = format!(
            "Scene(settings: Settings(integrator: {integrator}), lights: [Point(position: (0, 5, 5), intensity: 10), Environment(color: (0.5, 0.6, 0.9))], objects: [Sphere(center: (0, 0, 0), radius: 1)])"
        );
        let s = parse_scene(&text, &dir.join("x.ron")).unwrap();
        assert!(s.warnings.is_empty(), "{integrator}: {:?}", s.warnings);
    }
}
