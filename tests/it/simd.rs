//! Run-time SIMD dispatch must not change a bit: farm hosts with and without AVX2 render the
//! same frames. `ENVSHADOW_NO_AVX2` forces the SSE2 kernels, so one host can compare both.

use crate::common;

use std::fs;
use std::path::Path;

fn render(dir: &Path, name: &str, method: &str, no_avx2: bool) -> std::path::PathBuf {
    let out = dir.join(name);
    let spec = dir.join(format!("{name}.toml"));
    fs::write(
        &spec,
        format!(
            "[scene]\nbuiltin = \"shapes\"\n[lights]\ncount = 120\n[motion]\nframes = 2\n\
             [render]\nwidth = 96\nheight = 72\ntile = 16\nmethod = \"{method}\"\n\
             [output]\ndir = \"{}\"\n",
            out.display()
        ),
    )
    .unwrap();
    let mut cmd = common::bin();
    cmd.args(["render", "-q", "--no-report"]).arg(&spec);
    if no_avx2 {
        cmd.env("ENVSHADOW_NO_AVX2", "1");
    } else {
        cmd.env_remove("ENVSHADOW_NO_AVX2");
    }
    let o = cmd.output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    out
}

#[test]
fn avx2_and_sse2_kernels_write_identical_frames() {
    #[cfg(target_arch = "x86_64")]
    if !std::arch::is_x86_feature_detected!("avx2") {
        eprintln!("note: this CPU has no AVX2; both renders use the SSE2 kernels");
    }
    let dir = tempfile::tempdir().unwrap();
    for method in ["brute", "grid-nowarp-uncertainty", "grid-warp-boundary"] {
        let a = render(dir.path(), &format!("{method}-avx2"), method, false);
        let b = render(dir.path(), &format!("{method}-sse2"), method, true);
        for frame in ["frame_0000", "frame_0001"] {
            for ext in ["exr", "png"] {
                let file = format!("{frame}.{ext}");
                let (x, y) = (
                    fs::read(a.join(&file)).unwrap(),
                    fs::read(b.join(&file)).unwrap(),
                );
                assert!(
                    x == y,
                    "{method}: {file} differs between the AVX2 and SSE2 kernels"
                );
            }
        }
    }
}
