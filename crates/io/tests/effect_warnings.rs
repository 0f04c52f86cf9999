//! A scene file that asks for an effect its contents make impossible says
//! so, naming the file and the place; the fixture scenes ask for nothing
//! impossible.

use crate::{fixture, load_scene, parse_scene};

const SPHERE: &str = "Sphere(center: (0, 0, 0), radius: 1, material: \"m\")";

fn warnings(settings: &str, materials: &str, lights: &str, objects: &str) -> Vec<String> {
    let src = format!(
        "Scene(\n    settings: Settings({settings}),\n    materials: {{{materials}}},\n    lights: [{lights}],\n    objects: [{objects}],\n)"
    );
    parse_scene(&src, &fixture("scenes").join("x.ron"))
        .unwrap_or_else(|e| panic!("{e}"))
        .warnings
}

fn one(w: &[String], at: &str, says: &str) {
    assert!(
        w.len() == 1 && w[0].contains("x.ron") && w[0].contains(at) && w[0].contains(says),
        "expected `{at}` and `{says}` in {w:?}"
    );
}

const MATTE: &str = "\"m\": Matte(color: (0.5, 0.5, 0.5), ka: 0.2, kd: 0.8)";
const NO_KA: &str = "\"m\": Matte(color: (0.5, 0.5, 0.5), ka: 0, kd: 0.8)";
const POINT: &str = "Point(position: (0, 5, 5))";
const AO: &str = "Ambient(intensity: 0.5, occlusion: Occlusion(samples: 4))";

#[test]
fn a_scene_using_everything_it_asks_for_has_no_warnings() {
    let w = warnings("", MATTE, &format!("{AO}, {POINT}"), SPHERE);
    assert!(w.is_empty(), "{w:?}");
}

#[test]
fn occlusion_without_an_ambient_material_or_light_is_named() {
    let w = warnings("", NO_KA, &format!("{POINT}, {AO}"), SPHERE);
    one(&w, "lights[1]", "ka");
    let black = "Ambient(intensity: 0, occlusion: Occlusion())";
    let w = warnings("", MATTE, &format!("{black}, {POINT}"), SPHERE);
    one(&w, "lights[0]", "black ambient light");
}

#[test]
fn ambient_light_under_the_path_tracer_is_named() {
    let w = warnings("integrator: Path", MATTE, &format!("{POINT}, {AO}"), SPHERE);
    one(
        &w,
        "lights[1]",
        "path tracer does not use an Ambient light and its occlusion",
    );
}

#[test]
fn an_emissive_box_under_whitted_is_named_at_its_line() {
    let glow = format!("{MATTE}, \"glow\": Emissive(color: (1, 1, 1), strength: 2)");
    let objects = format!("{SPHERE},\n    Box(min: (2, 0, 0), max: (3, 1, 1), material: \"glow\")");
    let w = warnings("integrator: Whitted", &glow, POINT, &objects);
    one(&w, "x.ron:6:5: objects[1]", "emissive Box");
    let w = warnings("integrator: Path", &glow, POINT, &objects);
    assert!(w.is_empty(), "{w:?}");
}

#[test]
fn depth_zero_glass_and_an_unused_filter_are_named() {
    let glass = "\"m\": Dielectric(ior: 1.5)";
    let w = warnings("max_depth: 0", glass, POINT, SPHERE);
    one(&w, "settings.max_depth", "glass is black");
    let gauss = "filter: Gaussian(radius: 1.5, sigma: 0.5)";
    let w = warnings(gauss, MATTE, POINT, SPHERE);
    one(&w, "x.ron:2:5: settings.filter", "not used");
    let w = warnings(&format!("spp: 4, {gauss}"), MATTE, POINT, SPHERE);
    assert!(w.is_empty(), "{w:?}");
}

#[test]
fn fixture_scenes_ask_for_nothing_impossible() {
    let dir = fixture("scenes");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    files.sort();
    for f in files {
        let s = load_scene(&f).unwrap_or_else(|e| panic!("{e}"));
        let ignored = gridrt_tracer::ignored_effects(&s.scene);
        assert!(ignored.is_empty(), "{}: {ignored:?}", f.display());
    }
}
