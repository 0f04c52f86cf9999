//! PLY (ASCII and binary) on arbitrary bytes, as `m.ply`.
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let dir = common::scratch();
    let ply = dir.join("m.ply");
    if std::fs::write(&ply, data).is_err() {
        return;
    }
    if let Ok(model) = gridrt_io::load_model_in(&ply, &common::sandbox()) {
        // A loaded model is well formed: its triangles index its vertices.
        let _ = model.triangles().count();
        let _ = model.bounds();
    }
});
