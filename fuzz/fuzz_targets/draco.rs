//! Draco streams straight into the decoder, as a `KHR_draco_mesh_compression` primitive's are
//! decoded: the first two bytes are the largest count its accessors declare (the decoder's
//! limits), the rest the stream.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

#[path = "../src/exercise.rs"]
mod exercise;

fuzz_target!(|data: &[u8]| {
    let _ = exercise::draco(data, Path::new("fuzz/mesh.gltf"));
});
