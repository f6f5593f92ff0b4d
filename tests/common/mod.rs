//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

/// The folder with the shared test assets (bunny glTF, HDR maps): `$ENVSHADOW_ASSETS`, else
/// `assets/` in the repo (filled by scripts/fetch-assets.sh), else `../shared/assets`.
pub fn assets_dir() -> PathBuf {
    if let Ok(dir) = std::env::var("ENVSHADOW_ASSETS") {
        return PathBuf::from(dir);
    }
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    for candidate in [root.join("assets"), root.join("../shared/assets")] {
        if candidate.join("bunny_on_plane.glb").exists() {
            return candidate;
        }
    }
    panic!(
        "test assets not found: set ENVSHADOW_ASSETS, run scripts/fetch-assets.sh, or keep ../shared/assets beside the repo"
    );
}

/// One asset by file name.
pub fn asset(name: &str) -> PathBuf {
    let p = assets_dir().join(name);
    assert!(p.exists(), "missing test asset {}", p.display());
    p
}
