//! glTF / GLB loading from bytes, with a folder holding the external buffers and images a
//! fuzzed file may refer to (and links out of it); a scene that loads is also put in a BVH
//! and traced.
#![no_main]

use std::path::PathBuf;
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;

/// The model's folder ([`envshadow_fuzz_files::model_folder`]): external buffers and images,
/// links pointing in and out, a file just outside.
fn folder() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let root = std::env::temp_dir().join(format!("envshadow-fuzz-gltf-{}", std::process::id()));
        envshadow_fuzz_files::model_folder(&root)
    })
}

#[path = "../src/files.rs"]
mod envshadow_fuzz_files;

#[path = "../src/exercise.rs"]
mod exercise;

fuzz_target!(|data: &[u8]| {
    let _ = exercise::gltf(data, &folder().join("fuzz.gltf"));
});
