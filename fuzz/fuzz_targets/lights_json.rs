//! The lights JSON reader, then the O(1) cell lookup of the lights it rebuilt.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

#[path = "../src/exercise.rs"]
mod exercise;

fuzz_target!(|data: &[u8]| {
    let _ = exercise::lights_json(data, Path::new("fuzz/lights.json"));
});
