//! Radiance HDR environment maps from bytes, then light sampling of what decodes.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

#[path = "../src/exercise.rs"]
mod exercise;

fuzz_target!(|data: &[u8]| {
    let _ = exercise::envmap(data, Path::new("fuzz/map.hdr"));
});
