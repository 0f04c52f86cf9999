//! Wavefront OBJ and MTL through tobj.
//!
//! tobj reports errors without line numbers and panics on a few malformed
//! inputs (a colour with two components), so each file gets a validating
//! pass first that names the line of every problem it finds: unparsable or
//! non-finite numbers, face indices out of range (relative indices
//! included). Only then does tobj read it, triangulating polygons as fans.

use super::obj_textures;
use super::texture_load::TextureLoader;
use super::{check_normals, default_material, ModelMesh, NamedMaterial};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::sandbox::Sandbox;
use gridrt_bbox::{Real, Vec3};
use gridrt_tracer::{Material, Mesh, Rgb};
use std::cell::RefCell;
use std::io::Cursor;
use std::path::Path;

/// Reads an OBJ file (`bytes`, read from `real`, named `path` in messages)
/// and the MTL libraries it names, from the folders the sandbox allows a
/// model.
pub(crate) fn load(path: &Path, real: &Path, bytes: &[u8], sandbox: &Sandbox) -> Result<Model> {
    // OBJ is text: a NUL byte near the start means an image or a binary
    // mesh with the wrong extension, which would otherwise read as an OBJ
    // with no faces.
    if bytes[..bytes.len().min(8192)].contains(&0) {
        return Err(Error::obj(
            path,
            None,
            "the file is binary, not OBJ text (is it really an OBJ?)",
        ));
    }
    let text = String::from_utf8_lossy(strip_bom(bytes));
    let mut warnings = Vec::new();
    validate_obj(path, &text, &mut warnings)?;

    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mtl_error: RefCell<Option<Error>> = RefCell::new(None);
    let mtl_warnings: RefCell<Vec<String>> = RefCell::new(Vec::new());
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let loaded = tobj::load_obj_buf(&mut Cursor::new(text.as_bytes()), &options, |mtl| {
        if mtl_error.borrow().is_some() {
            return Err(tobj::LoadError::MaterialParseError);
        }
        if mtl.as_os_str().is_empty() {
            mtl_warnings.borrow_mut().push(format!(
                "{}: an `mtllib` line names no file; its materials use the default",
                path.display()
            ));
            return Err(tobj::LoadError::OpenFileFailed);
        }
        let shown = dir.join(mtl);
        match sandbox.resolve(real, Path::new(mtl), true) {
            Ok(file) => load_mtl(&shown, &file, sandbox, &mtl_error, &mtl_warnings),
            Err(e @ Error::Read { .. }) => {
                mtl_warnings.borrow_mut().push(format!(
                    "{e}; the materials of {} use the default",
                    path.display()
                ));
                Err(tobj::LoadError::OpenFileFailed)
            }
            Err(e) => {
                *mtl_error.borrow_mut() = Some(e);
                Err(tobj::LoadError::MaterialParseError)
            }
        }
    });
    if let Some(e) = mtl_error.into_inner() {
        return Err(e);
    }
    warnings.extend(mtl_warnings.into_inner());
    let (models, materials) = loaded.map_err(|e| {
        Error::obj(
            path,
            None,
            format!("{e}: the file is not a valid OBJ (tobj could not read it)"),
        )
    })?;
    let materials = materials.unwrap_or_else(|e| {
        warnings.push(format!(
            "{}: material library unusable ({e}); using the default material",
            path.display()
        ));
        Vec::new()
    });

    let mut meshes = Vec::with_capacity(models.len());
    let file_name = display_name(path);
    for (i, m) in models.iter().enumerate() {
        let mesh = convert_mesh(path, &file_name, i, m, &mut warnings)?;
        if mesh.triangles.is_empty() {
            continue;
        }
        let material = m.mesh.material_id.filter(|&id| id < materials.len());
        meshes.push(ModelMesh {
            mesh: std::sync::Arc::new(mesh),
            material,
            mirrored: false,
            placement: None,
        });
    }
    if meshes.is_empty() {
        return Err(Error::obj(
            path,
            None,
            "the file has no triangles: it needs `f` lines with at least three vertices",
        ));
    }
    let mut textures = TextureLoader::new(path, real, sandbox);
    let mut named = Vec::with_capacity(materials.len());
    for m in &materials {
        let maps = obj_textures::maps(m, &mut textures)?;
        // An emission or opacity map makes the colour and `d` factors of
        // the maps, not an emitter or glass.
        let mut plain = m.clone();
        if maps.emissive.is_some() {
            plain.emissive = None;
        }
        if maps.opacity.is_some() {
            plain.dissolve = None;
        }
        named.push(NamedMaterial {
            name: m.name.clone(),
            material: mtl_material(&plain),
            maps,
        });
    }
    Ok(Model {
        path: path.to_path_buf(),
        meshes,
        materials: named,
        textures: textures.list,
        cameras: Vec::new(),
        lights: Vec::new(),
        warnings,
    })
}

/// `bytes` without a UTF-8 byte-order mark.
pub(crate) fn strip_bom(bytes: &[u8]) -> &[u8] {
    bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes)
}

/// The file name for mesh names (`cube.obj`).
fn display_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// One tobj model as a tracer mesh.
#[allow(clippy::unnecessary_cast)] // tobj's numbers are f64 with the `f64` feature
fn convert_mesh(
    path: &Path,
    file_name: &str,
    index: usize,
    m: &tobj::Model,
    warnings: &mut Vec<String>,
) -> Result<Mesh> {
    let tm = &m.mesh;
    let positions: Vec<Vec3> = tm
        .positions
        .chunks_exact(3)
        .map(|c| Vec3::new(c[0] as Real, c[1] as Real, c[2] as Real))
        .collect();
    if let Some(k) = positions.iter().position(|p| !p.is_finite()) {
        return Err(Error::obj(
            path,
            None,
            format!("object \"{}\": vertex {k} is not finite", m.name),
        ));
    }
    let n = positions.len();
    let mut triangles = Vec::with_capacity(tm.indices.len() / 3);
    for t in tm.indices.chunks_exact(3) {
        if t.iter().any(|&i| i as usize >= n) {
            return Err(Error::obj(
                path,
                None,
                format!("object \"{}\": a face index is out of range", m.name),
            ));
        }
        triangles.push([t[0], t[1], t[2]]);
    }
    let normals = if tm.normals.len() == tm.positions.len() {
        tm.normals
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0] as Real, c[1] as Real, c[2] as Real))
            .collect()
    } else {
        Vec::new()
    };
    let uvs = if tm.texcoords.len() == 2 * n {
        tm.texcoords
            .chunks_exact(2)
            // OBJ's v grows upwards; texture space's downwards.
            .map(|c| glam::Vec2::new(c[0] as f32, 1.0 - c[1] as f32))
            .collect()
    } else {
        Vec::new()
    };
    let name = if m.name.is_empty() {
        format!("{file_name}:{index}")
    } else {
        format!("{file_name}:{}", m.name)
    };
    let mut mesh = Mesh {
        name,
        positions,
        normals,
        uvs,
        uvs1: Vec::new(),
        colors: Vec::new(),
        triangles,
    };
    check_normals(&mut mesh, warnings);
    Ok(mesh)
}

/// Parses `n` numbers after the keyword; `None` when there are fewer or one
/// does not parse.
fn numbers<'a>(words: &mut impl Iterator<Item = &'a str>, n: usize) -> Option<Vec<f64>> {
    let v: Vec<f64> = words.take(n).map_while(|w| w.parse().ok()).collect();
    (v.len() == n).then_some(v)
}

/// The validating pass over an OBJ file: names the line of every problem.
fn validate_obj(path: &Path, text: &str, warnings: &mut Vec<String>) -> Result<()> {
    let (mut nv, mut nvt, mut nvn) = (0usize, 0usize, 0usize);
    let mut skipped_elements = 0usize;
    for (i, line) in text.lines().enumerate() {
        let lineno = i + 1;
        let err = |msg: String| Error::obj(path, Some(lineno), msg);
        let mut words = line.split_whitespace();
        let Some(key) = words.next() else { continue };
        match key {
            "v" => {
                let c = numbers(&mut words, 3).ok_or_else(|| {
                    err(format!(
                        "a vertex needs three numbers `v x y z`, found `{}`",
                        line.trim()
                    ))
                })?;
                if c.iter().any(|x| !x.is_finite()) {
                    return Err(err(format!(
                        "vertex coordinate is not finite (NaN or infinity) in `{}`: fix or remove the vertex",
                        line.trim()
                    )));
                }
                let rest: Vec<&str> = words.collect();
                if rest.len() == 1 {
                    match rest[0].parse::<f64>() {
                        Ok(w) if w != 0.0 && w.is_finite() => {}
                        _ => {
                            return Err(err(format!(
                                "the vertex weight w must be a finite non-zero number, found `{}`",
                                rest[0]
                            )))
                        }
                    }
                } else if !rest.is_empty()
                    && (rest.len() != 3 || rest.iter().any(|w| w.parse::<f64>().is_err()))
                {
                    return Err(err(format!(
                        "a vertex is `v x y z`, `v x y z w` or `v x y z r g b`, found `{}`",
                        line.trim()
                    )));
                }
                nv += 1;
            }
            "vt" => {
                numbers(&mut words, 2).ok_or_else(|| {
                    err(format!(
                        "a texture coordinate needs two numbers `vt u v`, found `{}`",
                        line.trim()
                    ))
                })?;
                nvt += 1;
            }
            "vn" => {
                numbers(&mut words, 3).ok_or_else(|| {
                    err(format!(
                        "a normal needs three numbers `vn x y z`, found `{}`",
                        line.trim()
                    ))
                })?;
                nvn += 1;
            }
            "usemtl" if words.next().is_none() => {
                return Err(err(
                    "`usemtl` needs the name of a material from the `mtllib`".to_string(),
                ));
            }
            "f" | "l" => {
                let mut count = 0;
                for w in words {
                    check_vertex_ref(w, [nv, nvt, nvn]).map_err(&err)?;
                    count += 1;
                }
                if key == "l" || count < 3 {
                    skipped_elements += 1;
                }
            }
            _ => {}
        }
    }
    if skipped_elements > 0 {
        warnings.push(format!(
            "{}: skipped {skipped_elements} line element(s) or face(s) with fewer than 3 vertices",
            path.display()
        ));
    }
    Ok(())
}

/// Checks one `v`, `v/vt`, `v//vn` or `v/vt/vn` reference against the counts
/// defined so far (`counts` = vertices, texture coordinates, normals).
fn check_vertex_ref(word: &str, counts: [usize; 3]) -> std::result::Result<(), String> {
    const WHAT: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    const WHATS: [&str; 3] = ["vertices", "texture coordinates", "normals"];
    let parts: Vec<&str> = word.split('/').collect();
    if parts.len() > 3 || parts[0].is_empty() {
        return Err(format!(
            "bad face vertex `{word}`: use `v`, `v/vt`, `v//vn` or `v/vt/vn`"
        ));
    }
    for (k, p) in parts.iter().enumerate() {
        if p.is_empty() {
            continue;
        }
        let idx: i64 = p
            .parse()
            .map_err(|_| format!("bad face vertex `{word}`: `{p}` is not an integer index"))?;
        let n = counts[k] as u64;
        // unsigned_abs: -9223372036854775808 has no i64 negation.
        let ok = if idx != 0 {
            idx.unsigned_abs() <= n
        } else {
            return Err(format!(
                "face index 0 in `{word}`: OBJ indices start at 1 (or count back from -1)"
            ));
        };
        if !ok {
            return Err(format!(
                "face refers to {} {idx} in `{word}`, but only {n} {} are defined before this line",
                WHAT[k], WHATS[k]
            ));
        }
    }
    Ok(())
}

/// tobj's material loader: validates the MTL file (tobj panics on a colour
/// with two components), then lets tobj parse it. A missing library is a
/// warning (the meshes get the default material); a malformed one an error.
fn load_mtl(
    path: &Path,
    real: &Path,
    sandbox: &Sandbox,
    error: &RefCell<Option<Error>>,
    warnings: &RefCell<Vec<String>>,
) -> tobj::MTLLoadResult {
    let fail = Err(tobj::LoadError::MaterialParseError);
    let bytes = match sandbox.read(real) {
        Ok(b) => b,
        Err(e @ Error::Read { .. }) => {
            warnings.borrow_mut().push(format!(
                "{}; its materials use the default",
                e.renamed(real, path)
            ));
            return Err(tobj::LoadError::OpenFileFailed);
        }
        Err(e) => {
            *error.borrow_mut() = Some(e.renamed(real, path));
            return fail;
        }
    };
    let text = String::from_utf8_lossy(strip_bom(&bytes));
    match normalize_mtl(path, &text) {
        Ok(fixed) => tobj::load_mtl_buf(&mut Cursor::new(fixed.as_bytes())).inspect_err(|e| {
            *error.borrow_mut() = Some(Error::obj(
                path,
                None,
                format!("{e}: the material library is not valid MTL"),
            ));
        }),
        Err(e) => {
            *error.borrow_mut() = Some(e);
            fail
        }
    }
}

/// Checks every MTL line tobj would parse and expands one-component colours
/// (`Kd 0.5` means `Kd 0.5 0.5 0.5`), returning the text tobj should read.
fn normalize_mtl(path: &Path, text: &str) -> Result<String> {
    let mut out = String::with_capacity(text.len() + 64);
    for (i, line) in text.lines().enumerate() {
        let err = |msg: String| Error::obj(path, Some(i + 1), msg);
        let mut words = line.split_whitespace();
        let key = words.next().unwrap_or("");
        match key {
            "Ka" | "Kd" | "Ks" | "Ke" => {
                let vals: Vec<&str> = words.take_while(|w| !w.starts_with('#')).collect();
                let nums: Option<Vec<f64>> = vals.iter().map(|w| w.parse().ok()).collect();
                match nums {
                    Some(v)
                        if v.iter().all(|x| x.is_finite()) && (v.len() == 1 || v.len() >= 3) =>
                    {
                        if v.len() == 1 {
                            out.push_str(&format!("{key} {0} {0} {0}\n", v[0]));
                            continue;
                        }
                    }
                    _ => {
                        return Err(err(format!(
                            "`{key}` needs a colour `{key} r g b` of finite numbers, found `{}`",
                            line.trim()
                        )))
                    }
                }
            }
            "Ns" | "Ni" | "d" => match words.next().map(str::parse::<f64>) {
                Some(Ok(x)) if x.is_finite() => {}
                _ => {
                    return Err(err(format!(
                        "`{key}` needs one finite number, found `{}`",
                        line.trim()
                    )))
                }
            },
            "illum" if !matches!(words.next().map(str::parse::<u8>), Some(Ok(_))) => {
                return Err(err(format!(
                    "`illum` needs an illumination model 0 to 10, found `{}`",
                    line.trim()
                )));
            }
            // The maps gridrt uses stay when they name a file; others,
            // and bare ones (tobj rejects a bare `map_Kd`, which would lose
            // every material), are dropped.
            k if k.starts_with("map_")
                || matches!(k, "bump" | "disp" | "decal" | "refl" | "norm") =>
            {
                let used = matches!(
                    k,
                    "map_Kd" | "map_Ke" | "map_d" | "map_Bump" | "map_bump" | "bump" | "norm"
                );
                if !used || words.next().is_none() {
                    continue;
                }
            }
            "newmtl" if line.trim().len() <= "newmtl".len() => {
                return Err(err("`newmtl` needs a material name".to_string()));
            }
            _ => {}
        }
        out.push_str(line);
        out.push('\n');
    }
    Ok(out)
}

/// The largest component of a colour.
fn max3(c: [f32; 3]) -> f32 {
    c[0].max(c[1]).max(c[2])
}

/// Maps an MTL material to ours:
///
/// - `Ke` non-zero → Emissive (colour `Ke / max(Ke)`, strength `max(Ke)`);
/// - `d < 1`, or `illum` 4, 6 or 7 → Dielectric with `Ni` (1.5 when absent
///   or ≤ 1), tinted by `Tf` when given;
/// - `illum` 3 or 5, or `Ks` ≥ 0.5 and at least `Kd` → Reflective: the
///   mirror reflects `Ks`, the diffuse part is `Kd`;
/// - `Pr` (roughness) or `Pm` (metalness) given → MetallicRoughness with
///   base colour `Kd` (defaults: `Pr` 1, `Pm` 0);
/// - `Ks` non-zero → Phong with exponent `Ns` (the glossy lobe the path
///   tracer samples by cosine power);
/// - otherwise Matte with colour `Kd`.
#[allow(clippy::unnecessary_cast)] // tobj's numbers are f64 with the `f64` feature
pub(crate) fn mtl_material(m: &tobj::Material) -> Material {
    let clean = |c: Option<[_; 3]>, default: [f32; 3]| {
        let c = c.map_or(default, |c| c.map(|x| x as f32));
        c.map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 })
    };
    let kd = clean(m.diffuse, [0.8; 3]);
    let ks = clean(m.specular, [0.0; 3]);
    let ke = clean(m.emissive, [0.0; 3]);
    let ns = m
        .shininess
        .map(|x| x as f32)
        .filter(|x| x.is_finite())
        .unwrap_or(10.0)
        .clamp(1.0, 10_000.0);
    let d = m
        .dissolve
        .map(|x| x as f32)
        .filter(|x| x.is_finite())
        .unwrap_or(1.0);
    let illum = m.illumination_model.unwrap_or(2);
    let color = Rgb::from_array(kd);
    let max_ke = max3(ke);
    if max_ke > 0.0 {
        return Material::Emissive {
            color: Rgb::from_array(ke) / max_ke,
            strength: max_ke,
        };
    }
    if d < 1.0 || matches!(illum, 4 | 6 | 7) {
        let ior = m
            .optical_density
            .map(|x| x as f32)
            .filter(|x| x.is_finite() && *x > 1.0)
            .unwrap_or(1.5);
        let tint = m
            .unknown_param
            .get("Tf")
            .and_then(|s| {
                let v: Vec<f32> = s
                    .split_whitespace()
                    .filter_map(|w| w.parse().ok())
                    .collect();
                match v.as_slice() {
                    [g] => Some(Rgb::splat(*g)),
                    [r, g, b, ..] => Some(Rgb::new(*r, *g, *b)),
                    _ => None,
                }
            })
            .filter(|c| c.is_finite() && c.min_element() >= 0.0)
            .unwrap_or(Rgb::ONE);
        return Material::Dielectric { ior, tint };
    }
    // The PBR extension of MTL (`Pr` roughness, `Pm` metalness): glTF's
    // metallic-roughness BRDF with `Kd` as the base colour.
    let unit = |key: &str| {
        m.unknown_param
            .get(key)
            .and_then(|s| s.split_whitespace().next()?.parse::<f32>().ok())
            .filter(|x| x.is_finite())
            .map(|x| x.clamp(0.0, 1.0))
    };
    let (pr, pm) = (unit("Pr"), unit("Pm"));
    if pr.is_some() || pm.is_some() {
        return Material::MetallicRoughness {
            base: color.min(Rgb::ONE),
            metallic: pm.unwrap_or(0.0),
            roughness: pr.unwrap_or(1.0),
        };
    }
    let max_ks = max3(ks);
    if matches!(illum, 3 | 5) || (max_ks >= 0.5 && max_ks >= max3(kd)) {
        let kr = max_ks.max(if matches!(illum, 3 | 5) { 0.5 } else { 0.0 });
        let reflect = if max_ks > 0.0 {
            Rgb::from_array(ks) / max_ks
        } else {
            Rgb::ONE
        };
        return Material::Reflective {
            color,
            ka: 0.25,
            kd: 1.0,
            ks: 0.0,
            exp: ns,
            kr,
            reflect,
        };
    }
    if max_ks > 0.0 {
        return Material::Phong {
            color,
            ka: 0.25,
            kd: 1.0,
            ks: max_ks,
            exp: ns,
            specular: Rgb::from_array(ks) / max_ks,
        };
    }
    if m.diffuse.is_none() {
        return default_material();
    }
    Material::Matte {
        color,
        ka: 0.25,
        kd: 1.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(text: &str) -> std::result::Result<(), String> {
        validate_obj(Path::new("t.obj"), text, &mut Vec::new()).map_err(|e| e.to_string())
    }

    #[test]
    fn validation_names_lines() {
        assert!(check("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf -3 -2 -1\n").is_ok());
        let e = check("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n").unwrap_err();
        assert!(e.starts_with("t.obj:4: face refers to vertex 4"), "{e}");
        let e = check("v 0 0 0\nv 1 0 0\nf -3 1 2\n").unwrap_err();
        assert!(e.contains("t.obj:3:"), "{e}");
        let e = check("v 0 nan 0\n").unwrap_err();
        assert!(
            e.contains("t.obj:1: vertex coordinate is not finite"),
            "{e}"
        );
        let e = check("v 0 inf 0\n").unwrap_err();
        assert!(e.contains("not finite"), "{e}");
        let e = check("v 0 0\n").unwrap_err();
        assert!(e.contains("three numbers"), "{e}");
        let e = check("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n").unwrap_err();
        assert!(e.contains("start at 1"), "{e}");
        let e = check("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//2 3//1\n").unwrap_err();
        assert!(e.contains("normal 2"), "{e}");
    }

    #[test]
    fn mtl_colours_are_expanded_and_checked() {
        let p = Path::new("m.mtl");
        let fixed = normalize_mtl(p, "newmtl a\nKd 0.5\nKs 1 1 1 # c\n").unwrap();
        assert!(fixed.contains("Kd 0.5 0.5 0.5"), "{fixed}");
        let e = normalize_mtl(p, "newmtl a\nKd 1 1\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("m.mtl:2:"), "{e}");
        let e = normalize_mtl(p, "newmtl a\nNs x\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("m.mtl:2:"), "{e}");
    }

    #[test]
    fn mtl_mapping() {
        let base = tobj::Material {
            diffuse: Some([0.5, 0.5, 0.5]),
            ..Default::default()
        };
        assert!(matches!(mtl_material(&base), Material::Matte { .. }));
        let glass = tobj::Material {
            dissolve: Some(0.2),
            optical_density: Some(1.33),
            ..base.clone()
        };
        assert_eq!(
            mtl_material(&glass),
            Material::Dielectric {
                ior: 1.33,
                tint: Rgb::ONE
            }
        );
        let illum7 = tobj::Material {
            illumination_model: Some(7),
            ..base.clone()
        };
        assert!(matches!(mtl_material(&illum7), Material::Dielectric { ior, .. } if ior == 1.5));
        let mut pbr = base.clone();
        pbr.unknown_param.insert("Pr".into(), "0.25".into());
        pbr.unknown_param.insert("Pm".into(), "2".into());
        assert!(matches!(
            mtl_material(&pbr),
            Material::MetallicRoughness { metallic, roughness, .. } if metallic == 1.0 && roughness == 0.25
        ));
        let mirror = tobj::Material {
            illumination_model: Some(3),
            specular: Some([0.9, 0.9, 0.9]),
            ..base.clone()
        };
        assert!(matches!(mtl_material(&mirror), Material::Reflective { kr, .. } if kr == 0.9));
        let shiny = tobj::Material {
            specular: Some([0.3, 0.3, 0.3]),
            shininess: Some(50.0),
            ..base.clone()
        };
        assert!(matches!(mtl_material(&shiny), Material::Phong { exp, .. } if exp == 50.0));
        let lamp = tobj::Material {
            emissive: Some([17.0, 12.0, 4.0]),
            ..base
        };
        assert!(
            matches!(mtl_material(&lamp), Material::Emissive { strength, .. } if strength == 17.0)
        );
    }
}
