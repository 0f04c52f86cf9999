//! glTF (JSON or GLB, by the first bytes) on arbitrary bytes: the input's
//! first part is the model, its second `b.bin`, a buffer it may name.
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let parts = common::parts(data, 2);
    let dir = common::scratch();
    let name = if parts[0].starts_with(b"glTF") {
        "m.glb"
    } else {
        "m.gltf"
    };
    let model = dir.join(name);
    if std::fs::write(&model, parts[0]).is_err()
        || std::fs::write(dir.join("b.bin"), parts.get(1).copied().unwrap_or(b"")).is_err()
    {
        return;
    }
    if let Ok(loaded) = gridrt_io::load_scene_in(&model, &common::sandbox()) {
        let _ = loaded.scene.objects.len();
    }
});
