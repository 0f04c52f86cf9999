//! Shading normals of meshes: smooth by default for a model rendered on its
//! own, chosen per `Mesh` in a scene (`normals: File | Flat | Smooth(deg)`).

use crate::{fixture, parse_scene};
use gridrt_io::{load_model, scene_from_model};
use gridrt_tracer::{Geometry, Mesh, Scene};

fn meshes(s: &Scene) -> Vec<&Mesh> {
    s.objects
        .iter()
        .filter_map(|o| match &o.geometry {
            Geometry::Mesh(m) => Some(&**m),
            _ => None,
        })
        .collect()
}

#[test]
fn a_model_rendered_on_its_own_is_smooth() {
    // The teapot's file has no normals.
    let model = load_model(&fixture("meshes/teapot/teapot.obj")).unwrap();
    assert!(model.meshes.iter().all(|m| m.mesh.normals.is_empty()));
    let s = scene_from_model(model).scene;
    for m in meshes(&s) {
        assert_eq!(m.normals.len(), m.positions.len());
        assert!(m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4));
    }
}

fn scene_with(normals: &str, file: &str) -> gridrt_io::Result<gridrt_io::LoadedScene> {
    let ron = format!(
        r#"Scene(
            camera: Camera(eye: (0, 2, 9), look_at: (0, 1, 0)),
            objects: [Mesh(file: "{file}"{normals})],
        )"#
    );
    parse_scene(&ron, &fixture("scenes/x.ron"))
}

#[test]
fn scene_meshes_choose_their_normals() {
    let teapot = "../meshes/teapot/teapot.obj";
    let flat = scene_with("", teapot).unwrap();
    assert!(meshes(&flat.scene).iter().all(|m| m.normals.is_empty()));
    let smooth = scene_with(", normals: Smooth(45)", teapot).unwrap();
    assert!(meshes(&smooth.scene)
        .iter()
        .all(|m| m.normals.len() == m.positions.len()));
    // A crease of 0 keeps every facet flat: a normal per corner.
    let facets = scene_with(", normals: Smooth(0)", teapot).unwrap();
    let m = meshes(&facets.scene)[0];
    assert!(m.positions.len() > meshes(&smooth.scene)[0].positions.len());
    // Flat drops the file's own normals.
    let boxed = "../meshes/gltf_box/Box.glb";
    let file = scene_with("", boxed).unwrap();
    assert!(meshes(&file.scene).iter().all(|m| !m.normals.is_empty()));
    let flat = scene_with(", normals: Flat", boxed).unwrap();
    assert!(meshes(&flat.scene).iter().all(|m| m.normals.is_empty()));
}

#[test]
fn a_crease_out_of_range_names_the_place() {
    let e = scene_with(", normals: Smooth(200)", "../meshes/teapot/teapot.obj")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("fixtures/scenes/x.ron:3:") || e.contains("x.ron:3:"),
        "{e}"
    );
    assert!(e.contains("between 0 and 180 degrees"), "{e}");
}
