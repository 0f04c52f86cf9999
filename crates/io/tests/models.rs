//! Model loading: OBJ groups and MTL materials, glTF node hierarchies,
//! cameras, lights and materials, and meshes placed by scene files.

use crate::fixture;
use crate::{load_scene, parse_scene};
use gridrt_bbox::{Aabb, Real, Vec3};
use gridrt_io::{load_model, scene_from_model, Model};
use gridrt_tracer::{Geometry, Light, Material, Projection};

fn bounds_of(model: &Model, range: std::ops::Range<usize>) -> Aabb {
    model
        .triangles()
        .skip(range.start)
        .take(range.len())
        .flatten()
        .fold(Aabb::EMPTY, Aabb::grow)
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

fn assert_box(b: Aabb, min: [Real; 3], max: [Real; 3]) {
    assert!(
        close(b.min, Vec3::from_array(min)) && close(b.max, Vec3::from_array(max)),
        "{b:?} != {min:?}..{max:?}"
    );
}

#[test]
fn obj_groups_become_named_meshes_with_their_materials() {
    let m = load_model(&fixture("meshes/cube/cube.obj")).unwrap();
    assert_eq!(m.triangle_count(), 12);
    assert_eq!(m.meshes.len(), 6);
    let names: Vec<&str> = m.meshes.iter().map(|x| x.mesh.name.as_str()).collect();
    assert_eq!(names[0], "cube.obj:front cube");
    assert_eq!(names[2], "cube.obj:right cube");
    let mat_names: Vec<&str> = m.materials.iter().map(|x| x.name.as_str()).collect();
    assert_eq!(mat_names, ["white", "red", "green", "blue", "light"]);
    let right = m.meshes[2].material.unwrap();
    assert_eq!(m.materials[right].name, "red");
    assert!(
        matches!(m.materials[right].material, Material::Matte { color, .. } if color.x == 1.0 && color.y == 0.0)
    );
    assert_box(m.bounds(), [0.0; 3], [2.0; 3]);
}

#[test]
fn cornell_box_maps_mtl_materials() {
    let m = load_model(&fixture("meshes/cornell_box/CornellBox-Original.obj")).unwrap();
    assert_eq!(m.triangle_count(), 36);
    let get = |n: &str| &m.materials.iter().find(|x| x.name == n).unwrap().material;
    assert!(matches!(get("light"), Material::Emissive { strength, .. } if *strength == 17.0));
    assert!(matches!(get("leftWall"), Material::Matte { .. }));
    // Kd 0, Ks 0.725: a specular box.
    assert!(matches!(get("tallBox"), Material::Reflective { .. }));
}

#[test]
fn gltf_hierarchy_composes_node_transforms() {
    let m = load_model(&fixture("meshes/generated/hierarchy.gltf")).unwrap();
    assert_eq!(m.triangle_count(), 28);
    assert_eq!(m.meshes.len(), 5);
    // The cube hangs on two nodes: stored once, placed twice.
    let placed: Vec<_> = m.meshes[..2]
        .iter()
        .map(|mm| mm.placement.unwrap())
        .collect();
    assert!(std::sync::Arc::ptr_eq(&m.meshes[0].mesh, &m.meshes[1].mesh));
    // cube_child: arm · T(0,1,0) · S(0.5), arm = T(2,0,0) · Rz(90°).
    assert_box(
        bounds_of(&m, 0..12),
        [0.75, -0.25, -0.25],
        [1.25, 0.25, 0.25],
    );
    // mirrored: arm · T(0,-1,0) · S(-1,1,1).
    assert_box(bounds_of(&m, 12..24), [2.5, -0.5, -0.5], [3.5, 0.5, 0.5]);
    assert!(placed[0].determinant() > 0.0);
    assert!(placed[1].determinant() < 0.0);
    assert!(m.meshes[2..].iter().all(|mm| mm.placement.is_none()));
    // The non-indexed triangle, then the strip (2 triangles), then glass.
    let tris: Vec<[Vec3; 3]> = m.triangles().collect();
    assert!(close(tris[24][0], Vec3::new(-2.0, 0.0, 0.0)));
    assert!(close(tris[24][1], Vec3::new(-1.0, 0.0, 0.0)));
    assert_box(bounds_of(&m, 25..27), [0.0, 0.0, -2.0], [1.0, 1.0, -2.0]);
    assert_box(bounds_of(&m, 27..28), [0.0, 0.0, 2.0], [1.0, 1.0, 2.0]);
    // Points primitive skipped and reported; the spot light is a spot.
    assert!(
        m.warnings.iter().any(|w| w.contains("Points")),
        "{:?}",
        m.warnings
    );
    assert!(
        !m.warnings.iter().any(|w| w.contains("spot")),
        "{:?}",
        m.warnings
    );
}

#[test]
fn gltf_normals_follow_the_inverse_transpose_and_faces_stay_outward() {
    let m = load_model(&fixture("meshes/generated/hierarchy.gltf")).unwrap();
    // The shared cube, in its own space: normals agree with the winding
    // and point outward.
    let mesh = &m.meshes[0].mesh;
    assert_eq!(mesh.normals.len(), mesh.positions.len());
    let c = mesh
        .positions
        .iter()
        .copied()
        .fold(Vec3::ZERO, |a, b| a + b)
        / mesh.positions.len() as Real;
    for t in &mesh.triangles {
        let p: Vec<Vec3> = t.iter().map(|&k| mesh.positions[k as usize]).collect();
        let geo = (p[1] - p[0]).cross(p[2] - p[0]);
        let n = mesh.normals[t[0] as usize];
        assert!(geo.dot(n) > 0.0, "winding against normal {n}");
        assert!((p[0] - c).dot(n) > 0.0, "normal {n} points inward");
    }
    // Placed, normals follow the inverse transpose: the +x face of the
    // cube child points +y after the arm's Rz(90°); the mirror turns the
    // other copy's to -x, which the arm turns to -y (outward still: the
    // renderer keeps the front side by the same map).
    for (mm, want) in [(&m.meshes[0], Vec3::Y), (&m.meshes[1], -Vec3::Y)] {
        let normal = mm.placement.unwrap().inverse().transpose();
        let n = normal.transform_vector3(glam::DVec3::X).normalize();
        let n = Vec3::new(n.x as Real, n.y as Real, n.z as Real);
        assert!(close(n, want), "{n} vs {want}");
    }
}

#[test]
fn gltf_materials_cameras_and_lights() {
    let m = load_model(&fixture("meshes/generated/hierarchy.gltf")).unwrap();
    let kinds: Vec<&str> = m
        .materials
        .iter()
        .map(|x| match x.material {
            Material::Matte { .. } => "matte",
            Material::Phong { .. } => "phong",
            Material::Reflective { .. } => "reflective",
            Material::Dielectric { .. } => "dielectric",
            Material::Emissive { .. } => "emissive",
            Material::Conductor { .. } => "conductor",
            Material::RoughDielectric { .. } => "rough dielectric",
            Material::MetallicRoughness { .. } => "metallic-roughness",
        })
        .collect();
    // BLEND is the material's alpha mode (a simple transmission), not glass.
    // Every reflecting glTF material is the specification's BRDF.
    assert_eq!(
        kinds,
        [
            "metallic-roughness",
            "metallic-roughness",
            "emissive",
            "metallic-roughness"
        ]
    );
    assert!(matches!(
        m.materials[1].material,
        Material::MetallicRoughness { metallic, roughness, .. } if metallic == 1.0 && roughness == 0.05
    ));
    assert_eq!(
        m.materials[3].maps.alpha_mode,
        gridrt_tracer::texture::AlphaMode::Blend
    );
    assert!(m.materials[3].maps.alpha < 1.0);
    let cam = m.cameras.first().unwrap();
    assert!(close(cam.camera.eye, Vec3::new(0.0, 1.0, 8.0)));
    assert!(close(cam.camera.look_at, Vec3::new(0.0, 1.0, 7.0)));
    match cam.camera.projection {
        Projection::Perspective { vfov_deg } => {
            assert!((vfov_deg - 0.7f64.to_degrees() as Real).abs() < 1e-3)
        }
        other => panic!("{other:?}"),
    }
    assert!((cam.aspect.unwrap() - 1.3333).abs() < 1e-4);
    assert_eq!(m.lights.len(), 3);
    assert!(
        matches!(m.lights[0], Light::Directional { direction, .. } if close(direction, Vec3::Y))
    );
    assert!(
        matches!(m.lights[1], Light::Point { position, inverse_square: true, .. } if close(position, Vec3::new(2.0, 3.0, 2.0)))
    );
    // KHR_lights_punctual spot: outerConeAngle 0.6 rad, innerConeAngle
    // absent (0), shining along the node's −z.
    match m.lights[2] {
        Light::Spot {
            position,
            direction,
            inner_deg,
            outer_deg,
            inverse_square,
            ..
        } => {
            assert!(close(position, Vec3::new(-2.0, 3.0, 2.0)));
            assert!(close(direction, Vec3::NEG_Z));
            assert_eq!(inner_deg, 0.0);
            assert!((outer_deg - 0.6f32.to_degrees()).abs() < 1e-4);
            assert!(inverse_square);
        }
        ref other => panic!("{other:?}"),
    }
}

#[test]
fn gltf_and_glb_give_the_same_triangles() {
    for (a, b) in [
        (
            "meshes/generated/hierarchy.gltf",
            "meshes/generated/hierarchy.glb",
        ),
        ("meshes/gltf_box/Box.gltf", "meshes/gltf_box/Box.glb"),
    ] {
        let ta: Vec<_> = load_model(&fixture(a)).unwrap().triangles().collect();
        let tb: Vec<_> = load_model(&fixture(b)).unwrap().triangles().collect();
        assert_eq!(ta, tb, "{a} vs {b}");
    }
    let boxm = load_model(&fixture("meshes/gltf_box/Box.gltf")).unwrap();
    assert_eq!(boxm.triangle_count(), 12);
    assert_box(boxm.bounds(), [-0.5; 3], [0.5; 3]);
}

#[test]
fn one_mesh_on_two_nodes_is_instanced() {
    let m = load_model(&fixture("meshes/gltf_simple_meshes/SimpleMeshes.gltf")).unwrap();
    let t: Vec<_> = m.triangles().collect();
    assert_eq!(t.len(), 2);
    for (a, b) in t[0].iter().zip(&t[1]) {
        assert!(close(*b, *a + Vec3::X));
    }
}

#[test]
fn a_model_on_its_own_uses_its_camera_and_lights() {
    let s = scene_from_model(load_model(&fixture("meshes/generated/hierarchy.gltf")).unwrap());
    assert!(!s.framed_camera);
    assert_eq!(
        (s.scene.settings.width, s.scene.settings.height),
        (640, 480)
    );
    assert_eq!(s.scene.lights.len(), 3);
    // Without camera or lights: framed, with default lights.
    let s = load_scene(&fixture("meshes/cube/cube.obj")).unwrap();
    assert!(s.framed_camera);
    assert!(s
        .scene
        .lights
        .iter()
        .any(|l| matches!(l, Light::Directional { shadows: true, .. })));
    gridrt_tracer::Renderer::new(&s.scene, &Default::default()).unwrap();
}

#[test]
fn scene_meshes_take_transforms_and_material_overrides() {
    let text = r#"Scene(
        materials: { "glass": Dielectric(), "steel": Reflective(kr: 0.5) },
        objects: [
            Mesh(file: "meshes/cube/cube.obj", transform: [Translate((-1, -1, -1)), Scale(2), Translate((10, 0, 0))],
                 materials: { "red": "glass" }, material: "steel"),
            Mesh(file: "meshes/cube/cube.obj", transform: [Scale((-1, 1, 1))]),
        ],
    )"#;
    let s = parse_scene(text, &crate::fixtures().join("inline.ron")).unwrap();
    let sc = &s.scene;
    assert_eq!(sc.objects.len(), 12);
    // The file is named twice: both objects place one shared copy of each
    // of its meshes.
    let placed: Vec<_> = sc
        .objects
        .iter()
        .map(|o| match &o.geometry {
            Geometry::Instance { mesh, to_world } => (mesh, **to_world, o.material),
            other => panic!("{other:?}"),
        })
        .collect();
    for (a, b) in placed[..6].iter().zip(&placed[6..]) {
        assert!(std::sync::Arc::ptr_eq(a.0, b.0));
    }
    let world = |k: std::ops::Range<usize>| {
        placed[k]
            .iter()
            .flat_map(|(m, a, _)| m.positions.iter().map(|p| a.point(*p)))
            .fold(Aabb::EMPTY, Aabb::grow)
    };
    // First copy: (0..2)³ → (-1..1)³ → (-2..2)³ → x + 10.
    assert_box(world(0..6), [8.0, -2.0, -2.0], [12.0, 2.0, 2.0]);
    // "right cube" uses red → overridden to glass (id 0); the rest → steel (id 1).
    assert_eq!(placed[2].2, 0);
    assert!(placed[..6]
        .iter()
        .enumerate()
        .all(|(i, (_, _, id))| i == 2 || *id == 1));
    // Second copy: mirrored in x, file materials added under "cube.obj:<name>".
    assert_box(world(6..12), [-2.0, 0.0, 0.0], [0.0, 2.0, 2.0]);
    assert!(sc.materials.len() >= 4);
    // Under the mirror the front face (z = 2) still faces +z: normals map
    // by the inverse transpose, whatever the winding.
    let (front, a, _) = &placed[6];
    let p: Vec<Vec3> = front.triangles[0]
        .iter()
        .map(|&k| front.positions[k as usize])
        .collect();
    let n = a
        .inverse()
        .unwrap()
        .transpose_vector((p[1] - p[0]).cross(p[2] - p[0]));
    assert!(n.z > 0.0);
}

#[test]
fn obj_normals_quads_and_relative_indices() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("quad.obj");
    std::fs::write(
        &p,
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 2\n\
         o first\nf 1//1 2//1 3//1 4//1\n\
         o second\nf -4//-1 -2//-1 -1//-1\n",
    )
    .unwrap();
    let m = load_model(&p).unwrap();
    let names: Vec<&str> = m.meshes.iter().map(|x| x.mesh.name.as_str()).collect();
    assert_eq!(names, ["quad.obj:first", "quad.obj:second"]);
    let t: Vec<[Vec3; 3]> = m.triangles().collect();
    // The quad is fanned: (1 2 3), (1 3 4); then the relative face (1 3 4).
    let v = |x: Real, y: Real| Vec3::new(x, y, 0.0);
    assert_eq!(t[0], [v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0)]);
    assert_eq!(t[1], [v(0.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)]);
    assert_eq!(t[2], [v(0.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)]);
    // Normals are kept, one per vertex, and normalised.
    let mesh = &m.meshes[0].mesh;
    assert_eq!(mesh.normals.len(), mesh.positions.len());
    assert!(mesh.normals.iter().all(|n| close(*n, Vec3::Z)));
    // No material library: every mesh gets the default material.
    assert!(m.meshes.iter().all(|x| x.material.is_none()));
}

/// A model rendered on its own: a room (the Cornell box, open at the
/// front) is seen from inside and lit under its ceiling; an object (the
/// teapot) is framed from outside and stands on a ground plane; both get
/// 9 samples per pixel.
#[test]
fn rooms_are_seen_from_inside_and_objects_stand_on_the_ground() {
    let room = load_scene(&fixture("meshes/cornell_box/CornellBox-Original.obj")).unwrap();
    let b = load_model(&fixture("meshes/cornell_box/CornellBox-Original.obj"))
        .unwrap()
        .bounds();
    let eye = room.scene.camera.eye;
    assert!(b.contains(eye), "{eye} outside {b:?}");
    assert!(eye.z > b.centroid().z, "not at the open front: {eye}");
    assert!(room
        .scene
        .lights
        .iter()
        .any(|l| matches!(l, Light::Point { shadows: true, .. })));
    assert!(!room
        .scene
        .objects
        .iter()
        .any(|o| matches!(o.geometry, Geometry::Plane { .. })));
    let object = load_scene(&fixture("meshes/teapot/teapot.obj")).unwrap();
    let b = load_model(&fixture("meshes/teapot/teapot.obj"))
        .unwrap()
        .bounds();
    assert!(!b.contains(object.scene.camera.eye));
    let ground = object
        .scene
        .objects
        .iter()
        .find_map(|o| match o.geometry {
            Geometry::Plane { point, normal } => Some((point, normal)),
            _ => None,
        })
        .expect("a ground plane");
    assert_eq!(ground.1, Vec3::Y);
    assert!(ground.0.y < b.min.y && ground.0.y > b.min.y - 0.01 * b.extent().y);
    assert_eq!(object.scene.settings.spp, 9);
    assert_eq!(room.scene.settings.spp, 9);
}

#[test]
fn a_gltf_mesh_placed_once_reaches_the_scene_without_copies() {
    // One mesh on one node, with normals (so that nothing is recomputed):
    // the arrays the loader made are the scene's, moved, not copied.
    let m = load_model(&fixture("meshes/gltf_box/Box.glb")).unwrap();
    assert_eq!(m.meshes.len(), 1);
    let mm = &m.meshes[0];
    assert!(!mm.mesh.normals.is_empty() && mm.placement.is_none());
    assert_eq!(std::sync::Arc::strong_count(&mm.mesh), 1);
    let ptrs = (
        mm.mesh.positions.as_ptr(),
        mm.mesh.normals.as_ptr(),
        mm.mesh.triangles.as_ptr(),
    );
    let s = scene_from_model(m);
    let Some(Geometry::Mesh(mesh)) = s.scene.objects.first().map(|o| &o.geometry) else {
        panic!("the box is a mesh object");
    };
    assert_eq!(
        (
            mesh.positions.as_ptr(),
            mesh.normals.as_ptr(),
            mesh.triangles.as_ptr()
        ),
        ptrs
    );
}

#[test]
fn gltf_transmission_is_glass_of_its_ior_and_volume() {
    // One triangle drawn with each material in turn.
    let dir = tempfile::tempdir().unwrap();
    let bin: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    std::fs::write(dir.path().join("t.bin"), &bin).unwrap();
    let materials = [
        // Smooth glass of index 1.33 absorbing red: 0.5 left after 2 units.
        r#"{"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0},
            "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                           "KHR_materials_ior": {"ior": 1.33},
                           "KHR_materials_volume": {"attenuationColor": [0.5, 1, 1], "attenuationDistance": 2}}}"#,
        // Rough glass of the default index.
        r#"{"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0.4},
            "extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.9}}}"#,
        // Mostly opaque, a metal, and the legacy index 0: not glass / 1.5.
        r#"{"pbrMetallicRoughness": {"metallicFactor": 0},
            "extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.3}}}"#,
        r#"{"extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}}}"#,
        r#"{"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0},
            "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                           "KHR_materials_ior": {"ior": 0}}}"#,
    ];
    let prims: Vec<String> = (0..materials.len())
        .map(|i| format!(r#"{{"attributes": {{"POSITION": 0}}, "material": {i}}}"#))
        .collect();
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume"],
        "nodes": [{{"mesh": 0}}], "meshes": [{{"primitives": [{}]}}],
        "materials": [{}],
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
        "buffers": [{{"byteLength": 36, "uri": "t.bin"}}]}}"#,
        prims.join(", "),
        materials.join(", ")
    );
    let path = dir.path().join("t.gltf");
    std::fs::write(&path, json).unwrap();
    let m = load_model(&path).unwrap();
    let got: Vec<Material> = m.materials.iter().map(|x| x.material.clone()).collect();
    assert_eq!(got.len(), 5, "{got:?}");
    let Material::Dielectric { ior, tint } = got[0] else {
        panic!("{:?}", got[0]);
    };
    assert!((ior - 1.33).abs() < 1e-6);
    assert!(
        (tint.x - 0.5f32.sqrt()).abs() < 1e-6 && tint.y == 1.0,
        "{tint}"
    );
    assert!(matches!(
        got[1],
        Material::RoughDielectric { ior, tint, roughness }
            if ior == 1.5 && tint == gridrt_tracer::Rgb::ONE && roughness == 0.4
    ));
    assert!(matches!(got[2], Material::MetallicRoughness { .. }));
    assert!(matches!(got[3], Material::MetallicRoughness { .. }));
    assert!(matches!(got[4], Material::Dielectric { ior, .. } if ior == 1.5));
}
