//! Issue 40: a plain render into a folder that already holds complete frames of the same
//! render said nothing before overwriting them; it now says, once, how many it renders again
//! and that `--resume` would skip them.

use std::path::Path;

use crate::common;

/// A 2-frame, 48×32 shapes turntable of 20 lights into `out`, `extra` flags added: its
/// stderr lines that mention `--resume`.
fn render(dir: &Path, extra: &[&str]) -> Vec<String> {
    let spec = dir.join("anim.toml");
    std::fs::write(
        &spec,
        "[scene]\nbuiltin = \"shapes\"\n[lights]\ncount = 20\n[motion]\nframes = 2\n\
         [render]\nwidth = 48\nheight = 32\n",
    )
    .unwrap();
    let out = common::bin()
        .arg("render")
        .arg(&spec)
        .arg("--out")
        .arg(dir.join("out"))
        .arg("--no-report")
        .args(extra)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{extra:?}: {err}");
    err.lines()
        .filter(|l| l.contains("--resume"))
        .map(str::to_string)
        .collect()
}

#[test]
fn a_plain_render_over_complete_frames_says_resume_would_skip_them() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    assert_eq!(render(dir, &[]), Vec::<String>::new(), "an empty folder");
    let again = render(dir, &[]);
    assert_eq!(
        again,
        [
            "2 complete frames of this render already here will be rendered again and \
          overwritten; --resume would skip them"
        ],
    );
    let one = render(dir, &["--frames", "1"]);
    assert_eq!(one.len(), 1, "{one:?}");
    assert!(
        one[0].starts_with("1 complete frame of this render"),
        "{one:?}"
    );
    // --resume skips them: no note, only its own per-frame lines.
    let resumed = render(dir, &["--resume"]);
    assert!(
        resumed.iter().all(|l| l.contains("skipped (--resume)")) && resumed.len() == 2,
        "{resumed:?}"
    );
    // Frames of other settings are not this render's: they are replaced without a note.
    assert_eq!(render(dir, &["--lights", "24"]), Vec::<String>::new());
    // -q: no notes, where one would be.
    assert_eq!(render(dir, &["--lights", "24"]).len(), 1);
    assert_eq!(render(dir, &["--lights", "24", "-q"]), Vec::<String>::new());
}
