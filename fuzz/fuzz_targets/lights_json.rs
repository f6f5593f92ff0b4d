//! The lights JSON reader, then the O(1) cell lookup of the lights it rebuilt.
#![no_main]

use std::path::Path;

use envshadow::lights::parse_json;
use glam::Vec3;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(set) = parse_json(data, Path::new("fuzz/lights.json")) {
        for d in [Vec3::X, Vec3::NEG_Y, Vec3::new(0.6, 0.0, 0.8)] {
            let _ = set.cell_of(d);
        }
    }
});
