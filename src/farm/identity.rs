//! Build identity and settings fingerprints: what must agree between farm hosts and jobs for
//! their pixels to be the same bits.

use crate::anim::{Animation, EnvSource, SceneSource};
use crate::error::Result;
use crate::scene::Scene;

pub use crate::output::record::{file_sha256, sha256};

/// This build's identity: 16 hex digits of a SHA-256 that build.rs computes from what
/// decides the output bits — the crate's sources and lock file, the compiler, the target, the
/// profile and the flags — not of the executable's bytes, which also change with what does
/// not reach a pixel (`cargo test --release` links another file from the same source; see
/// build.rs). Two hosts with the same identity render the same bits.
pub const BUILD_ID: &str = env!("ENVSHADOW_BUILD_ID");

/// [`BUILD_ID`], as plans and manifests record it.
pub fn build_id() -> String {
    BUILD_ID.to_string()
}

/// The name of the machine this runs on, for job manifests: `$ENVSHADOW_HOST`, else the
/// sshlogin GNU parallel sent the job to (`$PARALLEL_SSHHOST`), else the system's host name
/// (`gethostname` on Unix, the computer name on Windows).
pub fn host_name() -> String {
    for var in ["ENVSHADOW_HOST", "PARALLEL_SSHHOST"] {
        if let Ok(v) = std::env::var(var)
            && !v.trim().is_empty()
        {
            return v.trim().to_string();
        }
    }
    let name = gethostname::gethostname()
        .to_string_lossy()
        .trim()
        .to_string();
    if name.is_empty() {
        "unknown".into()
    } else {
        name
    }
}

/// A fingerprint of everything that decides a frame's pixels: the resolved animation with the
/// run-only fields (frames, threads, output folder, the video, where the spec lies) blanked and input
/// files named by their content's hash, so hosts that hold the inputs at other paths agree.
pub fn settings_fingerprint(anim: &Animation) -> Result<String> {
    let mut a = anim.clone();
    a.spec_path = Default::default();
    a.frames = Default::default();
    a.render.threads = 0;
    a.output.dir = Default::default();
    a.output.video = false;
    // Where the allowed folder lies is the host's layout; the files it lets in are hashed below.
    a.scene_settings.allow_folder = Default::default();
    if let SceneSource::File(p) = &a.scene {
        // A .gltf's buffers and textures decide the pixels as much as the .gltf itself: a host
        // with another texture under the same name must not pass for the same render.
        let mut hashes = vec![file_sha256(p)?];
        for f in Scene::external_files(p, &anim.scene_settings.allow_folder)? {
            hashes.push(file_sha256(&f)?);
        }
        a.scene = SceneSource::File(format!("sha256:{}", hashes.join("+")).into());
    }
    if let EnvSource::File(p) = &a.env {
        a.env = EnvSource::File(format!("sha256:{}", file_sha256(p)?).into());
    }
    let mut id = sha256(format!("{a:?}").as_bytes());
    id.truncate(16);
    Ok(id)
}

/// The input files an animation reads (scene and map), besides the spec itself.
pub fn input_files(anim: &Animation) -> Vec<std::path::PathBuf> {
    let mut v = Vec::new();
    if let SceneSource::File(p) = &anim.scene {
        v.push(p.clone());
    }
    if let EnvSource::File(p) = &anim.env {
        v.push(p.clone());
    }
    v
}
