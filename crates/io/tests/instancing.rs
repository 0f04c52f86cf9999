//! Instancing from files: a mesh file named by several `Mesh` objects of a
//! scene, and a glTF mesh used by several nodes, are stored once and placed
//! by transforms.

use crate::parse_scene;
use gridrt_bbox::{Aabb, Vec3};
use gridrt_tracer::{Geometry, Mesh, Renderer};
use std::sync::Arc;

fn instances(s: &gridrt_tracer::Scene) -> Vec<(&Arc<Mesh>, gridrt_tracer::Affine)> {
    s.objects
        .iter()
        .filter_map(|o| match &o.geometry {
            Geometry::Instance { mesh, to_world } => Some((mesh, **to_world)),
            _ => None,
        })
        .collect()
}

#[test]
fn a_file_named_by_many_objects_is_loaded_once_and_shared() {
    let mut objects = String::new();
    for k in 0..40 {
        objects += &format!(
            "Mesh(file: \"meshes/cube/cube.obj\", transform: [Scale(0.5), Rotate(axis: (0, 1, 0), degrees: {}), Translate(({}, 0, {}))], material: \"m\"),\n",
            9 * k,
            k % 8,
            k / 8
        );
    }
    let text = format!(
        r#"Scene(
            materials: {{ "m": Matte(color: (0.8, 0.8, 0.8)) }},
            lights: [Directional(direction: (1, 2, 3))],
            objects: [
                {objects}
                Mesh(file: "meshes/teapot/teapot.obj"),
            ],
        )"#
    );
    let s = parse_scene(&text, &crate::fixtures().join("inline.ron")).unwrap();
    let placed = instances(&s.scene);
    // The cube file has six meshes (one per face group): 40 × 6 placements
    // of six shared meshes.
    assert_eq!(placed.len(), 240);
    let firsts: Vec<_> = placed[..6].iter().map(|(m, _)| Arc::as_ptr(m)).collect();
    for (k, (m, _)) in placed.iter().enumerate() {
        assert_eq!(Arc::as_ptr(m), firsts[k % 6], "placement {k}");
    }
    // The teapot, named once, is baked into world space as before.
    assert!(s
        .scene
        .objects
        .iter()
        .any(|o| matches!(&o.geometry, Geometry::Mesh(m) if m.triangles.len() > 1000)));
    // Placements land where the transforms put them: object 39 at (7, 0, 4).
    let b = placed[234..]
        .iter()
        .map(|(m, a)| a.bounds(&m.bounds()))
        .fold(Aabb::EMPTY, Aabb::union);
    let c = (b.min + b.max) * 0.5;
    assert!(
        (c - Vec3::new(7.5, 0.5, 4.5)).abs().max_element() < 0.3,
        "{c}"
    );
    let r = Renderer::new(&s.scene, &Default::default()).unwrap();
    assert_eq!(r.instancing().shared_meshes, 6);
    assert_eq!(r.instancing().instances, 240);
}

#[test]
fn different_normals_make_different_shared_meshes() {
    let text = r#"Scene(
        objects: [
            Mesh(file: "meshes/teapot/teapot.obj", normals: Flat),
            Mesh(file: "meshes/teapot/teapot.obj", normals: Flat, transform: [Translate((5, 0, 0))]),
            Mesh(file: "meshes/teapot/teapot.obj", normals: Smooth(60)),
            Mesh(file: "meshes/teapot/teapot.obj", normals: Smooth(60), transform: [Translate((-5, 0, 0))]),
        ],
    )"#;
    let s = parse_scene(text, &crate::fixtures().join("inline.ron")).unwrap();
    let placed = instances(&s.scene);
    assert_eq!(placed.len(), 4);
    assert!(Arc::ptr_eq(placed[0].0, placed[1].0));
    assert!(Arc::ptr_eq(placed[2].0, placed[3].0));
    assert!(placed[0].0.normals.is_empty());
    assert_eq!(placed[2].0.normals.len(), placed[2].0.positions.len());
}

#[test]
fn a_shared_file_under_a_singular_or_huge_transform_is_refused() {
    // A stretch and a shift each within range whose sum is not.
    let max = gridrt_bbox::math::to_f64(gridrt_bbox::Real::MAX);
    let overflow = format!(
        "Scale(({:e}, 1, 1)), Translate(({:e}, 0, 0))",
        0.1 * max,
        0.9 * max
    );
    for (t, want) in [
        (
            "Matrix(((1, 0, 0, 0), (0, 1, 0, 0), (1, 1, 0, 0), (0, 0, 0, 1)))",
            "singular",
        ),
        (overflow.as_str(), "non-finite"),
    ] {
        let text = format!(
            r#"Scene(objects: [
                Mesh(file: "meshes/cube/cube.obj"),
                Mesh(file: "meshes/cube/cube.obj", transform: [{t}]),
            ])"#
        );
        let e = parse_scene(&text, &crate::fixtures().join("inline.ron"))
            .unwrap_err()
            .to_string();
        assert!(e.contains(want) && e.contains("cube.obj"), "{e}");
        assert!(e.contains("objects[1]"), "{e}");
    }
}

/// A glTF file whose one mesh (a triangle) hangs on `nodes` nodes, side by
/// side along x.
fn gltf_with_nodes(dir: &std::path::Path, nodes: usize) -> std::path::PathBuf {
    let bin: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    std::fs::write(dir.join("t.bin"), &bin).unwrap();
    let list: Vec<String> = (0..nodes).map(|k| k.to_string()).collect();
    let node_json: Vec<String> = (0..nodes)
        .map(|k| format!(r#"{{"mesh": 0, "translation": [{}, 0, 0]}}"#, 2 * k))
        .collect();
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0,
        "scenes": [{{"nodes": [{}]}}], "nodes": [{}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
        "buffers": [{{"byteLength": 36, "uri": "t.bin"}}]}}"#,
        list.join(","),
        node_json.join(",")
    );
    let path = dir.join("t.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

#[test]
fn a_gltf_mesh_on_2000_nodes_is_stored_once() {
    let dir = tempfile::tempdir().unwrap();
    let m = gridrt_io::load_model(&gltf_with_nodes(dir.path(), 2000)).unwrap();
    assert_eq!(m.meshes.len(), 2000);
    assert!(m
        .meshes
        .iter()
        .all(|i| i.placement.is_some() && Arc::ptr_eq(&i.mesh, &m.meshes[0].mesh)));
    assert_eq!(m.triangle_count(), 2000);
    assert_eq!(m.primitive_count(), 1 + 2000);
    let b = m.bounds();
    assert!(
        (b.max.x - 3999.0).abs() < 1e-3 && b.min.x.abs() < 1e-6,
        "{b:?}"
    );
    let s = gridrt_io::scene_from_model(m);
    let r = Renderer::new(&s.scene, &Default::default()).unwrap();
    assert_eq!(r.instancing().shared_meshes, 1);
    assert_eq!(r.instancing().instances, 2000);
}

#[test]
fn a_gltf_mesh_on_one_node_is_baked() {
    let dir = tempfile::tempdir().unwrap();
    let m = gridrt_io::load_model(&gltf_with_nodes(dir.path(), 1)).unwrap();
    assert_eq!(m.meshes.len(), 1);
    assert!(m.meshes[0].placement.is_none());
}

#[test]
fn a_scene_places_a_files_instances_under_its_transform() {
    let dir = tempfile::tempdir().unwrap();
    gltf_with_nodes(dir.path(), 3);
    std::fs::write(
        dir.path().join("s.ron"),
        r#"Scene(objects: [Mesh(file: "t.gltf", transform: [Scale(2), Translate((0, 10, 0))])])"#,
    )
    .unwrap();
    let s = gridrt_io::load_scene(&dir.path().join("s.ron")).unwrap();
    let placed = instances(&s.scene);
    assert_eq!(placed.len(), 3);
    // The third node's triangle: x from 4 to 5, scaled by 2, moved up 10.
    let b = placed[2].1.bounds(&placed[2].0.bounds());
    assert!(
        (b.min - Vec3::new(8.0, 10.0, 0.0)).abs().max_element() < 1e-3,
        "{b:?}"
    );
    assert!(
        (b.max - Vec3::new(10.0, 12.0, 0.0)).abs().max_element() < 1e-3,
        "{b:?}"
    );
}
