//! Stanford PLY (ASCII, binary little and big endian) through ply-rs-bw.
//!
//! The `vertex` element gives positions (`x`, `y`, `z`), normals (`nx`,
//! `ny`, `nz`) and texture coordinates (`u`/`v`, `s`/`t`, `texture_u`/
//! `texture_v` or `texture_s`/`texture_t`) when present; the `face` element
//! gives polygons as a list `vertex_indices` (or `vertex_index`), fanned
//! into triangles. Other elements (edges, materials, range grids) and
//! other properties are read past. The header's counts are checked against
//! the file's size and the primitive budget before the payload is read, and
//! ply-rs-bw caps its preallocation, so a header that promises a billion
//! faces allocates nothing for them.

use super::{check_normals, ModelMesh};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::sandbox::Sandbox;
use gridrt_bbox::{Real, Vec3};
use gridrt_tracer::Mesh;
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{
    ElementDef, Encoding, Property, PropertyAccess, PropertyAccessResult, PropertyType, ScalarType,
};
use std::io::Cursor;
use std::path::Path;

/// One vertex as read: every attribute optional until checked.
#[derive(Clone, Copy, Debug, Default)]
struct PlyVertex {
    p: [Option<f64>; 3],
    n: [Option<f64>; 3],
    uv: [Option<f64>; 2],
    /// Colour in [0, 1], as stored (sRGB-encoded).
    c: [Option<f64>; 3],
}

impl PropertyAccess for PlyVertex {
    fn new() -> Self {
        Self::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        let slot = match name {
            "x" => &mut self.p[0],
            "y" => &mut self.p[1],
            "z" => &mut self.p[2],
            "nx" => &mut self.n[0],
            "ny" => &mut self.n[1],
            "nz" => &mut self.n[2],
            "u" | "s" | "texture_u" | "texture_s" => &mut self.uv[0],
            "v" | "t" | "texture_v" | "texture_t" => &mut self.uv[1],
            "red" | "green" | "blue" | "diffuse_red" | "diffuse_green" | "diffuse_blue" => {
                let k = match name.trim_start_matches("diffuse_") {
                    "red" => 0,
                    "green" => 1,
                    _ => 2,
                };
                // Integers span their type's range; floats are in [0, 1].
                let x = match property {
                    Property::UChar(v) => Some(f64::from(v) / 255.0),
                    Property::UShort(v) => Some(f64::from(v) / 65535.0),
                    Property::Float(v) => Some(f64::from(v)),
                    Property::Double(v) => Some(v),
                    ref other => scalar(other).map(|x| x / 255.0),
                };
                return match x {
                    Some(x) => {
                        self.c[k] = Some(if x.is_finite() {
                            x.clamp(0.0, 1.0)
                        } else {
                            0.0
                        });
                        PropertyAccessResult::Set
                    }
                    None => PropertyAccessResult::UnsupportedType,
                };
            }
            _ => return PropertyAccessResult::Ignored,
        };
        match scalar(&property) {
            Some(x) => {
                *slot = Some(x);
                PropertyAccessResult::Set
            }
            None => PropertyAccessResult::UnsupportedType,
        }
    }
}

/// One face as read: its vertex indices (signed, checked later).
#[derive(Clone, Debug, Default)]
struct PlyFace {
    indices: Vec<i64>,
}

impl PropertyAccess for PlyFace {
    fn new() -> Self {
        Self::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        if name != "vertex_indices" && name != "vertex_index" {
            return PropertyAccessResult::Ignored;
        }
        let v: Vec<i64> = match property {
            Property::ListChar(v) => v.into_iter().map(i64::from).collect(),
            Property::ListUChar(v) => v.into_iter().map(i64::from).collect(),
            Property::ListShort(v) => v.into_iter().map(i64::from).collect(),
            Property::ListUShort(v) => v.into_iter().map(i64::from).collect(),
            Property::ListInt(v) => v.into_iter().map(i64::from).collect(),
            Property::ListUInt(v) => v.into_iter().map(i64::from).collect(),
            _ => return PropertyAccessResult::UnsupportedType,
        };
        self.indices = v;
        PropertyAccessResult::Set
    }
}

/// An element gridrt does not use: read past, nothing kept.
#[derive(Clone, Copy, Debug, Default)]
struct Skipped;

impl PropertyAccess for Skipped {
    fn new() -> Self {
        Self
    }
}

/// A scalar property as f64; `None` for a list.
fn scalar(p: &Property) -> Option<f64> {
    Some(match *p {
        Property::Char(v) => f64::from(v),
        Property::UChar(v) => f64::from(v),
        Property::Short(v) => f64::from(v),
        Property::UShort(v) => f64::from(v),
        Property::Int(v) => f64::from(v),
        Property::UInt(v) => f64::from(v),
        Property::Float(v) => f64::from(v),
        Property::Double(v) => v,
        _ => return None,
    })
}

/// Size in bytes of a scalar type in a binary payload.
fn scalar_size(t: &ScalarType) -> u64 {
    match t {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

/// The fewest payload bytes one element can take: a binary scalar its size,
/// a list its count; an ASCII element at least one byte per property (a
/// digit or a separator).
fn min_element_bytes(e: &ElementDef, encoding: &Encoding) -> u64 {
    e.properties
        .values()
        .map(|p| match (encoding, &p.data_type) {
            (Encoding::Ascii, _) => 1,
            (_, PropertyType::Scalar(t)) => scalar_size(t),
            (_, PropertyType::List(count, _)) => scalar_size(count),
        })
        .sum()
}

/// The message of a ply-rs-bw error, its first line only (the crate adds
/// the offending text on further lines), and its place.
fn parse_error(path: &Path, element: Option<&str>, e: &ply_rs_bw::parser::ParseError) -> Error {
    let text = e.to_string();
    let msg = text
        .lines()
        .next()
        .unwrap_or("malformed PLY")
        .trim()
        .to_string();
    // "Line N: …" is the crate's own prefix; the place carries the line.
    let msg = match msg.split_once(": ") {
        Some((head, rest)) if head.starts_with("Line ") => rest.to_string(),
        _ => msg,
    };
    let place = match (e.line(), element) {
        (Some(l), Some(el)) => format!("line {l} (element `{el}`)"),
        (Some(l), None) => format!("line {l}"),
        (None, Some(el)) => format!("element `{el}`"),
        (None, None) => String::new(),
    };
    Error::ply(path, place, format!("{msg}: the file is not a valid PLY"))
}

/// Reads a PLY file (`bytes`, named `path` in messages). PLY names no
/// other file, so the sandbox only supplies the budgets.
pub(crate) fn load(path: &Path, bytes: &[u8], sandbox: &Sandbox) -> Result<Model> {
    if !bytes.starts_with(b"ply") {
        return Err(Error::ply(
            path,
            "line 1",
            "the file does not start with `ply`: it is not a PLY file",
        ));
    }
    let mut reader = Reader::new(Cursor::new(bytes));
    let header = Parser::<Skipped>::new()
        .read_header(&mut reader)
        .map_err(|e| parse_error(path, None, &e))?;
    let payload_bytes = bytes.len() as u64;
    let mut warnings = Vec::new();

    // Budgets and plausibility before any payload is read.
    let mut min_total = 0u64;
    for (name, e) in &header.elements {
        min_total = min_total.saturating_add(
            (e.count as u64).saturating_mul(min_element_bytes(e, &header.encoding)),
        );
        if min_total > payload_bytes {
            return Err(Error::ply(
                path,
                format!("element `{name}`"),
                format!(
                    "the header promises {} `{name}` elements, more than the file's {payload_bytes} bytes can hold: the file is truncated or its header is wrong",
                    e.count
                ),
            ));
        }
    }
    let Some(vdef) = header.elements.get("vertex") else {
        return Err(Error::ply(
            path,
            "header",
            "no `vertex` element: a PLY mesh needs `element vertex N` with properties x, y, z",
        ));
    };
    for axis in ["x", "y", "z"] {
        if !matches!(
            vdef.properties.get(axis).map(|p| &p.data_type),
            Some(PropertyType::Scalar(_))
        ) {
            return Err(Error::ply(
                path,
                "element `vertex`",
                format!("the vertices have no scalar property `{axis}`"),
            ));
        }
    }
    let fdef = header.elements.get("face");
    let faces_declared = fdef.map_or(0, |f| f.count as u64);
    if faces_declared > sandbox.limits.max_primitives {
        return Err(sandbox
            .limits
            .primitives_error(path, "element `face`", faces_declared));
    }

    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    for (name, def) in &header.elements {
        match name.as_str() {
            "vertex" => {
                vertices = Parser::<PlyVertex>::new()
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(|e| parse_error(path, Some(name), &e))?;
            }
            "face" => {
                faces = Parser::<PlyFace>::new()
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(|e| parse_error(path, Some(name), &e))?;
            }
            _ => {
                Parser::<Skipped>::new()
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(|e| parse_error(path, Some(name), &e))?;
            }
        }
    }
    let mesh = build_mesh(path, &vertices, &faces, sandbox, &mut warnings)?;
    Ok(Model {
        path: path.to_path_buf(),
        meshes: vec![ModelMesh {
            mesh: std::sync::Arc::new(mesh),
            material: None,
            mirrored: false,
            placement: None,
        }],
        materials: Vec::new(),
        cameras: Vec::new(),
        lights: Vec::new(),
        textures: Vec::new(),
        warnings,
    })
}

/// Checks the vertices and faces and fans the polygons into triangles.
fn build_mesh(
    path: &Path,
    vertices: &[PlyVertex],
    faces: &[PlyFace],
    sandbox: &Sandbox,
    warnings: &mut Vec<String>,
) -> Result<Mesh> {
    let mut positions = Vec::with_capacity(vertices.len());
    for (k, v) in vertices.iter().enumerate() {
        let [Some(x), Some(y), Some(z)] = v.p else {
            return Err(Error::ply(path, format!("vertex {k}"), "missing x, y or z"));
        };
        let p = Vec3::new(x as Real, y as Real, z as Real);
        if !p.is_finite() {
            return Err(Error::ply(
                path,
                format!("vertex {k}"),
                format!("the position ({x}, {y}, {z}) is not finite"),
            ));
        }
        positions.push(p);
    }
    let normals: Vec<Vec3> = vertices
        .iter()
        .map_while(|v| match v.n {
            [Some(x), Some(y), Some(z)] => Some(Vec3::new(x as Real, y as Real, z as Real)),
            _ => None,
        })
        .collect();
    // Vertex colours are sRGB-encoded, as images are: decoded to linear.
    let colors: Vec<gridrt_tracer::Rgb> = vertices
        .iter()
        .map_while(|v| match v.c {
            [Some(r), Some(g), Some(b)] => Some(gridrt_tracer::Rgb::from_array(
                [r, g, b].map(|x| gridrt_tracer::texture::srgb_to_linear(x as f32)),
            )),
            _ => None,
        })
        .collect();
    let colors = if colors.len() == vertices.len() {
        colors
    } else {
        Vec::new()
    };
    let uvs: Vec<glam::Vec2> = vertices
        .iter()
        .map_while(|v| match v.uv {
            // PLY's v grows upwards; texture space's downwards.
            [Some(u), Some(w)] => Some(glam::Vec2::new(u as f32, 1.0 - w as f32)),
            _ => None,
        })
        .collect();

    let n = positions.len() as i64;
    let mut triangles = Vec::with_capacity(faces.len());
    let mut short_faces = 0usize;
    for (f, face) in faces.iter().enumerate() {
        if let Some(&bad) = face.indices.iter().find(|&&i| i < 0 || i >= n) {
            return Err(Error::ply(
                path,
                format!("face {f}"),
                format!(
                    "vertex index {bad} is out of range: the file has {n} vertices (0 to {})",
                    n - 1
                ),
            ));
        }
        if face.indices.len() < 3 {
            short_faces += 1;
            continue;
        }
        // Indices are in 0..n, n ≤ u32::MAX + 1 by the element count's type.
        let idx = |k: usize| face.indices[k] as u32;
        for k in 1..face.indices.len() - 1 {
            triangles.push([idx(0), idx(k), idx(k + 1)]);
        }
        if triangles.len() as u64 > sandbox.limits.max_primitives {
            return Err(sandbox.limits.primitives_error(
                path,
                &format!("face {f}"),
                triangles.len() as u64,
            ));
        }
    }
    if short_faces > 0 {
        warnings.push(format!(
            "{}: {short_faces} faces with fewer than three vertices skipped",
            path.display()
        ));
    }
    if triangles.is_empty() {
        return Err(Error::ply(
            path,
            "element `face`",
            "the file has no triangles: it needs a `face` element with `vertex_indices` lists of three or more (a point cloud cannot be rendered)",
        ));
    }
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |s| s.to_string_lossy().into_owned(),
    );
    let mut mesh = Mesh {
        name,
        positions,
        normals,
        uvs,
        uvs1: Vec::new(),
        colors,
        triangles,
    };
    check_normals(&mut mesh, warnings);
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load_bytes(bytes: &[u8]) -> Result<Model> {
        load(Path::new("m.ply"), bytes, &Sandbox::working_directory())
    }

    const QUAD: &str = "ply\nformat ascii 1.0\ncomment a unit quad\nelement vertex 4\n\
        property float x\nproperty float y\nproperty float z\n\
        property float nx\nproperty float ny\nproperty float nz\n\
        property float u\nproperty float v\n\
        element face 1\nproperty list uchar int vertex_indices\nend_header\n\
        0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n4 0 1 2 3\n";

    #[test]
    fn an_ascii_quad_becomes_two_triangles_with_normals_and_uvs() {
        let m = load_bytes(QUAD.as_bytes()).unwrap();
        let mesh = &m.meshes[0].mesh;
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(mesh.normals, vec![Vec3::Z; 4]);
        assert_eq!(mesh.uvs[2], glam::Vec2::new(1.0, 0.0));
        assert_eq!(mesh.name, "m.ply");
        assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    }

    #[test]
    fn out_of_range_index_names_the_face() {
        let text = QUAD.replace("4 0 1 2 3", "4 0 1 2 9");
        let e = load_bytes(text.as_bytes()).unwrap_err().to_string();
        assert!(
            e.starts_with("m.ply: face 0: vertex index 9 is out of range"),
            "{e}"
        );
    }

    #[test]
    fn a_bad_number_names_the_line() {
        let text = QUAD.replace("1 1 0 0 0 1 1 1", "1 oops 0 0 0 1 1 1");
        let e = load_bytes(text.as_bytes()).unwrap_err().to_string();
        assert!(e.starts_with("m.ply: line 18 (element `vertex`)"), "{e}");
    }

    #[test]
    fn a_header_promising_more_than_the_file_holds_is_refused_first() {
        let text = QUAD.replace("element face 1", "element face 4000000000");
        let e = load_bytes(text.as_bytes()).unwrap_err().to_string();
        assert!(e.contains("more than the file's"), "{e}");
    }

    #[test]
    fn non_finite_vertices_and_missing_coordinates_are_errors() {
        let text = QUAD.replace("1 0 0 0 0 1 1 0", "1 nan 0 0 0 1 1 0");
        let e = load_bytes(text.as_bytes()).unwrap_err().to_string();
        assert!(e.contains("vertex 1") || e.contains("line"), "{e}");
        let text = QUAD.replace("property float z\n", "");
        let e = load_bytes(text.as_bytes()).unwrap_err().to_string();
        assert!(e.contains("no scalar property `z`"), "{e}");
        let e = load_bytes(b"solid stl\n").unwrap_err().to_string();
        assert!(e.contains("does not start with `ply`"), "{e}");
    }

    /// The fuzz target's seeds: ASCII, and binary in both byte orders with
    /// colours and an extra `edge` element.
    const SEEDS: [&[u8]; 3] = [
        include_bytes!("../../../../fuzz/seeds/ply/quad_ascii"),
        include_bytes!("../../../../fuzz/seeds/ply/tri_binary_le"),
        include_bytes!("../../../../fuzz/seeds/ply/tri_binary_be"),
    ];

    #[test]
    fn seeds_load_alike_in_every_encoding() {
        let a = load_bytes(SEEDS[0]).unwrap();
        assert_eq!(a.triangle_count(), 2);
        let le = load_bytes(SEEDS[1]).unwrap();
        let be = load_bytes(SEEDS[2]).unwrap();
        assert_eq!(le.meshes[0].mesh, be.meshes[0].mesh);
        assert_eq!(le.meshes[0].mesh.triangles, vec![[0, 1, 2]]);
        assert_eq!(le.meshes[0].mesh.positions[2], Vec3::Y);
        // The binary seeds' vertex colours are read (and sRGB-decoded).
        assert_eq!(le.meshes[0].mesh.colors.len(), 3);
        assert!(le.warnings.is_empty(), "{:?}", le.warnings);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig {
            cases: 256,
            rng_seed: proptest::test_runner::RngSeed::Fixed(28),
            failure_persistence: None,
            ..Default::default()
        })]

        /// Truncated or corrupted PLY files give a model or an error naming
        /// the file, never a panic; a model's triangles index its vertices.
        #[test]
        fn corrupted_files_never_panic(
            seed in 0usize..3,
            cut in proptest::prelude::any::<proptest::sample::Index>(),
            flips in proptest::collection::vec(
                (proptest::prelude::any::<proptest::sample::Index>(), proptest::prelude::any::<u8>()),
                0..6,
            ),
        ) {
            let mut bytes = SEEDS[seed].to_vec();
            for (at, b) in flips {
                let i = at.index(bytes.len());
                bytes[i] = b;
            }
            bytes.truncate(cut.index(bytes.len() + 1));
            match load_bytes(&bytes) {
                Ok(m) => {
                    let mesh = &m.meshes[0].mesh;
                    let n = mesh.positions.len() as u32;
                    proptest::prop_assert!(mesh.triangles.iter().flatten().all(|&i| i < n));
                }
                Err(e) => proptest::prop_assert!(e.to_string().starts_with("m.ply"), "{}", e),
            }
        }
    }
}
