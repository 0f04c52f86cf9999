//! Meshes, scenes and rays are read at the build's precision: with the
//! `f64` feature an OBJ vertex `0.1` is the double nearest 0.1, not the
//! float, so a hit lands where the file says.

use gridrt_bbox::{Real, Vec3};
use gridrt_grid::{Exhaustive, Primitive};
use gridrt_io::{load_model, parse_rays, trace_rays};
use gridrt_tracer::Triangle;

#[test]
fn obj_vertices_and_ray_csv_keep_the_builds_precision() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("t.obj");
    std::fs::write(&obj, "v 0 0 0.1\nv 1 0 0.1\nv 0 1 0.1\nf 1 2 3\n").unwrap();
    let model = load_model(&obj).unwrap();
    let tris: Vec<Triangle> = model
        .triangles()
        .map(|[a, b, c]| Triangle::new(a, b, c))
        .collect();
    assert_eq!(
        tris[0].vertices()[0],
        Vec3::new(0.0, 0.0, "0.1".parse().unwrap())
    );
    assert!(tris[0].bounds(&()).min.z == "0.1".parse::<Real>().unwrap());
    let rays = parse_rays("0.25,0.25,1.0,0,0,-1\n", &dir.path().join("r.csv")).unwrap();
    assert_eq!(rays[0].ray.origin.x, "0.25".parse::<Real>().unwrap());
    let hits = trace_rays(&Exhaustive::new(tris), &rays);
    let t = hits[0].unwrap().t;
    // 1 − 0.1 in the build's precision: 0.9 in f64, not 0.8999999985.
    let one: Real = 1.0;
    assert_eq!(t, one - "0.1".parse::<Real>().unwrap());
}

/// RON numbers reach the scene at the build's precision: with `f64` a
/// sphere at 0.1 + 1e-12 is not rounded to the float nearest 0.1, and a
/// camera 10⁶ + 0.1 from the origin keeps its 0.1; a mesh's transform
/// and the ray CSV likewise.
#[test]
fn ron_scene_numbers_keep_the_builds_precision() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.ron");
    let text = "Scene(
        camera: Camera(eye: (1000000.1, 0.30000000000000004, 9), look_at: (0, 0, 0)),
        materials: { \"m\": Matte(color: (0.5, 0.5, 0.5)) },
        objects: [ Sphere(center: (0.100000000001, -7.1e-300, 123456789.123456789), radius: 0.7, material: \"m\") ],
    )";
    let loaded = crate::parse_scene(text, &path).unwrap();
    let p = |s: &str| s.parse::<Real>().unwrap();
    let cam = loaded.scene.camera;
    assert_eq!(
        cam.eye,
        Vec3::new(p("1000000.1"), p("0.30000000000000004"), 9.0)
    );
    let gridrt_tracer::Geometry::Sphere { center, radius } = loaded.scene.objects[0].geometry
    else {
        panic!("not a sphere: {:?}", loaded.scene.objects[0].geometry);
    };
    assert_eq!(center.x, p("0.100000000001"));
    assert_eq!(center.z, p("123456789.123456789"));
    assert_eq!(radius, p("0.7"));
    #[cfg(feature = "f64")]
    {
        // What an f32 detour would lose ("0.100000000001" read as f32).
        assert_ne!(center.x, f64::from(0.1f32));
        assert_ne!(cam.eye.x, f64::from(1000000.1f32));
        assert_eq!(center.y, -7.1e-300);
    }
}
