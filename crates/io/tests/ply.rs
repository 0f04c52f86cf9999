//! PLY models: the same mesh written as ASCII and binary PLY (both byte
//! orders) loads exactly like its OBJ; a PLY in a scene's `Mesh`, and
//! `gridrt render`, `info` and `rays` on a `.ply`.

use crate::{fixture, gridrt, parse_scene};
use gridrt_bbox::{Real, Vec3};
use gridrt_io::{load_model, Model};
use gridrt_tracer::Geometry;

/// PLY encodings.
#[derive(Clone, Copy, Debug)]
pub enum Encoding {
    Ascii,
    Little,
    Big,
}

/// The scalar type that holds a `Real` exactly.
const REAL: &str = if std::mem::size_of::<Real>() == 8 {
    "double"
} else {
    "float"
};

/// One `Real` in a binary payload.
fn push_real(out: &mut Vec<u8>, x: Real, enc: Encoding) {
    match enc {
        Encoding::Little => out.extend_from_slice(&x.to_le_bytes()),
        Encoding::Big => out.extend_from_slice(&x.to_be_bytes()),
        Encoding::Ascii => out.extend_from_slice(format!("{x} ").as_bytes()),
    }
}

/// Writes the model's meshes as one PLY (positions, normals when every
/// mesh has them, triangles), each `Real` exactly.
pub fn to_ply(model: &Model, enc: Encoding) -> Vec<u8> {
    let positions: usize = model.meshes.iter().map(|m| m.mesh.positions.len()).sum();
    let normals = model
        .meshes
        .iter()
        .all(|m| m.mesh.normals.len() == m.mesh.positions.len());
    let format = match enc {
        Encoding::Ascii => "ascii",
        Encoding::Little => "binary_little_endian",
        Encoding::Big => "binary_big_endian",
    };
    let mut h = format!(
        "ply\nformat {format} 1.0\ncomment written by gridrt's tests\nelement vertex {positions}\n"
    );
    for p in ["x", "y", "z"] {
        h += &format!("property {REAL} {p}\n");
    }
    if normals {
        for p in ["nx", "ny", "nz"] {
            h += &format!("property {REAL} {p}\n");
        }
    }
    h += &format!(
        "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        model.triangle_count()
    );
    let mut out = h.into_bytes();
    for m in &model.meshes {
        for (k, p) in m.mesh.positions.iter().enumerate() {
            let mut v = p.to_array().to_vec();
            if normals {
                v.extend(m.mesh.normals[k].to_array());
            }
            for x in v {
                push_real(&mut out, x, enc);
            }
            if let Encoding::Ascii = enc {
                out.push(b'\n');
            }
        }
    }
    let mut base = 0i32;
    for m in &model.meshes {
        for t in &m.mesh.triangles {
            let idx = t.map(|i| base + i as i32);
            match enc {
                Encoding::Ascii => out
                    .extend_from_slice(format!("3 {} {} {}\n", idx[0], idx[1], idx[2]).as_bytes()),
                Encoding::Little => {
                    out.push(3);
                    idx.iter()
                        .for_each(|i| out.extend_from_slice(&i.to_le_bytes()));
                }
                Encoding::Big => {
                    out.push(3);
                    idx.iter()
                        .for_each(|i| out.extend_from_slice(&i.to_be_bytes()));
                }
            }
        }
        base += m.mesh.positions.len() as i32;
    }
    out
}

/// The model's triangles, corner by corner.
pub fn corners(m: &Model) -> Vec<[Vec3; 3]> {
    m.triangles().collect()
}

#[test]
fn teapot_as_ply_loads_like_its_obj_in_every_encoding() {
    let obj = load_model(&fixture("meshes/teapot/teapot.obj")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for enc in [Encoding::Ascii, Encoding::Little, Encoding::Big] {
        let path = dir.path().join(format!("teapot-{enc:?}.ply"));
        std::fs::write(&path, to_ply(&obj, enc)).unwrap();
        let ply = load_model(&path).unwrap();
        assert_eq!(ply.triangle_count(), 6_320, "{enc:?}");
        assert_eq!(corners(&ply), corners(&obj), "{enc:?}");
        assert!(ply.warnings.is_empty(), "{:?}", ply.warnings);
    }
}

#[test]
fn normals_in_the_file_are_kept() {
    let obj = load_model(&fixture("meshes/gltf_box/Box.glb")).unwrap();
    assert!(obj.meshes.iter().all(|m| !m.mesh.normals.is_empty()));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("box.ply");
    std::fs::write(&path, to_ply(&obj, Encoding::Little)).unwrap();
    let ply = load_model(&path).unwrap();
    let want: Vec<Vec3> = obj
        .meshes
        .iter()
        .flat_map(|m| m.mesh.normals.iter().copied())
        .collect();
    for (a, b) in ply.meshes[0].mesh.normals.iter().zip(&want) {
        assert!((*a - *b).length() < 1e-6, "{a} {b}");
    }
    assert_eq!(ply.meshes[0].mesh.normals.len(), want.len());
}

#[test]
fn a_ply_in_a_scene_mesh_with_a_transform_and_material() {
    let dir = tempfile::tempdir().unwrap();
    let obj = load_model(&fixture("meshes/generated/tri.obj")).unwrap();
    std::fs::write(dir.path().join("tri.ply"), to_ply(&obj, Encoding::Big)).unwrap();
    let ron = r#"Scene(
        camera: Camera(eye: (0, 0, 5), look_at: (0, 0, 0)),
        materials: { "red": Matte(color: (1, 0, 0)) },
        lights: [Ambient(intensity: 1)],
        objects: [Mesh(file: "tri.ply", material: "red", transform: [Translate((0, 0, 1))])],
    )"#;
    let s = parse_scene(ron, &dir.path().join("s.ron")).unwrap();
    let Geometry::Mesh(m) = &s.scene.objects[0].geometry else {
        panic!("not a mesh")
    };
    let moved: Vec<Vec3> = obj.meshes[0]
        .mesh
        .positions
        .iter()
        .map(|p| *p + Vec3::Z)
        .collect();
    assert_eq!(m.positions, moved);
}

#[test]
fn cli_renders_inspects_and_queries_a_ply() {
    let dir = tempfile::tempdir().unwrap();
    let obj = load_model(&fixture("meshes/generated/tri.obj")).unwrap();
    let ply = dir.path().join("tri.ply");
    std::fs::write(&ply, to_ply(&obj, Encoding::Little)).unwrap();
    let o = gridrt(
        &[
            "render", "tri.ply", "-o", "t.png", "--width", "24", "--height", "16", "--spp", "1",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(dir.path().join("t.png").is_file());
    let o = gridrt(&["info", "tri.ply"], dir.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The same rays answered from the PLY and from the OBJ.
    let rays = fixture("meshes/generated/tri_rays.csv");
    let expected =
        std::fs::read_to_string(fixture("meshes/generated/tri_rays.expected.csv")).unwrap();
    let o = gridrt(
        &["rays", "tri.ply", rays.to_str().unwrap(), "-o", "hits.csv"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let got = std::fs::read_to_string(dir.path().join("hits.csv")).unwrap();
    assert_eq!(got, expected);
}

#[test]
fn malformed_ply_fails_with_file_and_place() {
    let dir = tempfile::tempdir().unwrap();
    let obj = load_model(&fixture("meshes/generated/tri.obj")).unwrap();
    let mut bytes = to_ply(&obj, Encoding::Little);
    bytes.truncate(bytes.len() - 3);
    std::fs::write(dir.path().join("cut.ply"), &bytes).unwrap();
    let o = gridrt(&["info", "cut.ply"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.starts_with("error: cut.ply:"), "{err}");
    assert!(err.contains("face"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
}
