//! OpenEXR environment maps from bytes, then light sampling of what decodes.
#![no_main]

use std::path::Path;

use envshadow::envmap::EnvMap;
use libfuzzer_sys::fuzz_target;

mod envmap_common;

fuzz_target!(|data: &[u8]| {
    if let Ok(env) = EnvMap::decode(data, Path::new("fuzz/map.exr")) {
        envmap_common::exercise(env);
    }
});
