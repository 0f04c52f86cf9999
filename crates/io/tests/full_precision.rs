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
    assert!(tris[0].bounds().min.z == "0.1".parse::<Real>().unwrap());
    let rays = parse_rays("0.25,0.25,1.0,0,0,-1\n", &dir.path().join("r.csv")).unwrap();
    assert_eq!(rays[0].ray.origin.x, "0.25".parse::<Real>().unwrap());
    let hits = trace_rays(&Exhaustive::new(tris), &rays);
    let t = hits[0].unwrap().t;
    // 1 − 0.1 in the build's precision: 0.9 in f64, not 0.8999999985.
    let one: Real = 1.0;
    assert_eq!(t, one - "0.1".parse::<Real>().unwrap());
}
