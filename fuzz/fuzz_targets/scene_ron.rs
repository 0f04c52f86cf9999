//! The RON scene loader on arbitrary text: errors, never a panic, a hang
//! or unbounded memory. A second part of the input is written as `m.obj`,
//! which the scene may name.
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let parts = common::parts(data, 2);
    let dir = common::scratch();
    let _ = std::fs::write(dir.join("m.obj"), parts.get(1).copied().unwrap_or(b""));
    let Ok(text) = std::str::from_utf8(parts[0]) else {
        return;
    };
    let _ = gridrt_io::parse_scene_in(text, &dir.join("scene.ron"), &common::sandbox());
});
