//! Textures from model files: MTL maps and glTF textures load, decode and
//! render; bad or out-of-bounds images are errors naming the file; the
//! textured models of `../shared/scenes` render in colour (skipped when
//! that folder is absent).

use crate::load_scene;
use gridrt_io::{load_model, write_framebuffer};
use gridrt_tracer::{render, Framebuffer, RenderOptions, Rgb};
use std::path::{Path, PathBuf};

/// A 2 × 1 PNG, red then green.
fn write_png(path: &Path) {
    let mut fb = Framebuffer::new(2, 1);
    fb.pixels = vec![Rgb::new(1.0, 0.0, 0.0), Rgb::new(0.0, 1.0, 0.0)];
    write_framebuffer(path, &fb).unwrap();
}

/// A unit quad facing +z with texture coordinates, its MTL naming `map`.
fn write_quad(dir: &Path, map: &str) -> PathBuf {
    std::fs::write(
        dir.join("quad.mtl"),
        format!("newmtl tex\nKd 1 1 1\n{map}\n"),
    )
    .unwrap();
    let obj = dir.join("quad.obj");
    std::fs::write(
        &obj,
        "mtllib quad.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl tex\nf 1/1 2/2 3/3 4/4\n",
    )
    .unwrap();
    obj
}

#[test]
fn an_obj_map_kd_colours_the_render() {
    let dir = tempfile::tempdir().unwrap();
    write_png(&dir.path().join("rg.png"));
    let obj = write_quad(dir.path(), "map_Kd -s 1 1 rg.png");
    let m = load_model(&obj).unwrap();
    assert_eq!(m.textures.len(), 1);
    assert!(m.materials[0].maps.base_color.is_some());
    let mut s = load_scene(&obj).unwrap();
    s.scene.settings.width = 32;
    s.scene.settings.height = 24;
    s.scene.settings.spp = 1;
    let (img, _) = render(&s.scene, &RenderOptions::default()).unwrap();
    // The quad's left half is red, its right half green.
    let reddish = img.pixels.iter().any(|p| p.x > 2.0 * p.y + 0.05);
    let greenish = img.pixels.iter().any(|p| p.y > 2.0 * p.x + 0.05);
    assert!(reddish && greenish);
}

#[test]
fn a_broken_image_names_the_file_and_the_material() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.png"), b"\x89PNG\r\n\x1a\n truncated").unwrap();
    let obj = write_quad(dir.path(), "map_Kd bad.png");
    let e = load_model(&obj).unwrap_err().to_string();
    assert!(e.contains("bad.png"), "{e}");
    assert!(e.contains("material \"tex\" map_Kd"), "{e}");
    let obj = write_quad(dir.path(), "map_Kd missing.png");
    let e = load_model(&obj).unwrap_err().to_string();
    assert!(e.contains("missing.png"), "{e}");
}

#[test]
fn an_image_outside_the_models_folder_is_denied() {
    let dir = tempfile::tempdir().unwrap();
    let inner = dir.path().join("model");
    std::fs::create_dir(&inner).unwrap();
    write_png(&dir.path().join("secret.png"));
    let obj = write_quad(&inner, "map_Kd ../secret.png");
    let e = load_model(&obj).unwrap_err();
    assert!(matches!(e, gridrt_io::Error::Denied { .. }), "{e}");
}

#[test]
fn a_map_d_makes_cut_outs() {
    let dir = tempfile::tempdir().unwrap();
    write_png(&dir.path().join("rg.png"));
    let obj = write_quad(dir.path(), "d 1\nmap_d rg.png");
    let m = load_model(&obj).unwrap();
    let maps = &m.materials[0].maps;
    assert!(maps.opacity.is_some());
    assert_eq!(
        maps.alpha_mode,
        gridrt_tracer::texture::AlphaMode::Mask { cutoff: 0.5 }
    );
}

/// The largest spread between colour channels over the image: 0 for grey.
fn colourfulness(img: &Framebuffer) -> f32 {
    img.pixels
        .iter()
        .map(|p| p.max_element() - p.min_element())
        .fold(0.0, f32::max)
}

/// The textured models of `../shared/scenes` load with their textures and
/// render in colour (their factors alone are white or grey).
#[test]
fn shared_textured_models_render_in_colour() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes");
    if !root.is_dir() {
        eprintln!("skipped: {} is absent", root.display());
        return;
    }
    for (file, textures) in [
        ("gltf_damaged_helmet/DamagedHelmet.glb", 4),
        ("gltf_avocado/Avocado.gltf", 3),
        ("gltf_duck/Duck.glb", 1),
        ("gltf_cesium_milk_truck/CesiumMilkTruck.glb", 1),
        ("gltf_box_textured/BoxTextured.gltf", 1),
    ] {
        let path = root.join(file);
        let m = load_model(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(m.textures.len() >= textures, "{file}: {}", m.textures.len());
        let mut s = load_scene(&path).unwrap();
        s.scene.settings.width = 48;
        s.scene.settings.height = 36;
        s.scene.settings.spp = 1;
        let (img, _) = render(&s.scene, &RenderOptions::default()).unwrap();
        let c = colourfulness(&img);
        // Without textures the same render is grey (or white): the test can fail.
        s.scene.textures = Default::default();
        let (plain, _) = render(&s.scene, &RenderOptions::default()).unwrap();
        assert!(
            c > 0.15 && c > colourfulness(&plain) + 0.1,
            "{file}: {c} vs {}",
            colourfulness(&plain)
        );
    }
}

#[test]
fn ply_vertex_colours_are_read_and_srgb_decoded() {
    let dir = tempfile::tempdir().unwrap();
    let ply = dir.path().join("c.ply");
    std::fs::write(
        &ply,
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n\
         element face 1\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 188 188 188\n3 0 1 2\n",
    )
    .unwrap();
    let m = load_model(&ply).unwrap();
    let c = &m.meshes[0].mesh.colors;
    assert_eq!(c.len(), 3);
    assert_eq!(c[0], Rgb::new(1.0, 0.0, 0.0));
    // sRGB 188 is linear 0.5.
    assert!((c[2].x - 0.5).abs() < 0.01, "{}", c[2]);
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
}

/// A glTF triangle with two texture-coordinate sets (set 0 along the
/// triangle, set 1 constant at u = 0.75: the PNG's green texel) and a
/// base-colour texture reading `set`, and, when `emissive`, an emissive
/// texture reading set 0.
fn write_two_set_gltf(dir: &Path, set: u32, emissive: bool) -> PathBuf {
    let emissive = if emissive {
        r#", "emissiveTexture": {"index": 0}"#
    } else {
        ""
    };
    write_png(&dir.join("rg.png"));
    let f = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let mut bin = f(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    bin.extend(f(&[0.0, 0.5, 1.0, 0.5, 0.0, 0.5]));
    bin.extend(f(&[0.75, 0.5, 0.75, 0.5, 0.75, 0.5]));
    std::fs::write(dir.join("t.bin"), &bin).unwrap();
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
        "nodes": [{{"mesh": 0}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1, "TEXCOORD_1": 2}}, "material": 0}}]}}],
        "materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0, "texCoord": {set}}}}}{emissive}}}],
        "textures": [{{"source": 0}}], "images": [{{"uri": "rg.png"}}],
        "accessors": [
            {{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
            {{"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}},
            {{"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 24}},
                        {{"buffer": 0, "byteOffset": 60, "byteLength": 24}}],
        "buffers": [{{"byteLength": 84, "uri": "t.bin"}}]}}"#
    );
    let path = dir.join("t.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

#[test]
fn gltf_textures_read_the_texcoord_set_they_name() {
    let dir = tempfile::tempdir().unwrap();
    let m = load_model(&write_two_set_gltf(dir.path(), 1, true)).unwrap();
    let mesh = &m.meshes[0].mesh;
    assert_eq!(mesh.uvs1, vec![glam::Vec2::new(0.75, 0.5); 3]);
    assert_eq!(mesh.uvs[1], glam::Vec2::new(1.0, 0.5));
    let maps = &m.materials[0].maps;
    assert_eq!(maps.base_color.map(|r| r.set), Some(1));
    assert_eq!(maps.emissive.map(|r| r.set), Some(0));
    // Textures on set 1 only: it is the mesh's one set.
    let m = load_model(&write_two_set_gltf(dir.path(), 1, false)).unwrap();
    assert_eq!(m.meshes[0].mesh.uvs, vec![glam::Vec2::new(0.75, 0.5); 3]);
    assert!(m.meshes[0].mesh.uvs1.is_empty());
    // Textures on set 0 only: the second set is not kept.
    let m = load_model(&write_two_set_gltf(dir.path(), 0, false)).unwrap();
    assert!(m.meshes[0].mesh.uvs1.is_empty());
    assert_eq!(m.materials[0].maps.base_color.map(|r| r.set), Some(0));
    // A set beyond 1 is read as set 0, with a warning.
    let m = load_model(&write_two_set_gltf(dir.path(), 3, false)).unwrap();
    assert!(
        m.warnings.iter().any(|w| w.contains("TEXCOORD_3")),
        "{:?}",
        m.warnings
    );
    assert_eq!(m.materials[0].maps.base_color.map(|r| r.set), Some(0));
}
