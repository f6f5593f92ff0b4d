//! glTF / GLB loading from bytes, with a folder holding the external buffers and images a
//! fuzzed file may refer to; a scene that loads is also put in a BVH and traced.
#![no_main]

use std::path::PathBuf;
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;

/// A folder with `buffer.bin` (a small triangle's positions and indices) and `texture.png`,
/// the names the seed files use.
fn folder() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("envshadow-fuzz-gltf-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("buffer.bin"),
            envshadow_fuzz_files::triangle_buffer(),
        )
        .unwrap();
        std::fs::write(dir.join("texture.png"), envshadow_fuzz_files::texture_png()).unwrap();
        dir
    })
}

#[path = "../src/files.rs"]
mod envshadow_fuzz_files;

#[path = "../src/exercise.rs"]
mod exercise;

fuzz_target!(|data: &[u8]| {
    let _ = exercise::gltf(data, &folder().join("fuzz.gltf"));
});
