//! OBJ and its MTL library on arbitrary bytes: the input's first part is
//! `m.obj`, its second `m.mtl`, its third `t.png` (a texture an MTL
//! `map_Kd t.png` has decoded by the image loader).
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let parts = common::parts(data, 3);
    let dir = common::scratch();
    let obj = dir.join("m.obj");
    if std::fs::write(&obj, parts[0]).is_err()
        || std::fs::write(dir.join("m.mtl"), parts.get(1).copied().unwrap_or(b"")).is_err()
        || std::fs::write(dir.join("t.png"), parts.get(2).copied().unwrap_or(b"")).is_err()
    {
        return;
    }
    if let Ok(model) = gridrt_io::load_model_in(&obj, &common::sandbox()) {
        // A loaded model is well formed: its triangles index its vertices.
        let _ = model.triangles().count();
        let _ = model.bounds();
    }
});
