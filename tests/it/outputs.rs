//! What a frame's files hold for a compositor and a viewer (issue 22): the EXR's named
//! channels, passes and header — read back by our reader and by OpenImageIO's `iinfo` and
//! `oiiotool` (on CI a failure when missing, elsewhere SKIPPED) —, half floats, and the PNG's
//! view transform.

use crate::common;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use envshadow::film::BACKGROUND_DEPTH;
use envshadow::output::exr::read_frame;
use envshadow::view::View;
use glam::{Mat4, Vec3, Vec4};

/// The default animation.
const SPEC: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/anims/shapes-turntable.toml");

/// Renders frames of the default animation, small, into `dir/name` with `flags`.
fn render(dir: &Path, name: &str, flags: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let o = common::bin()
        .arg("render")
        .arg(SPEC)
        .args([
            "--width",
            "96",
            "--height",
            "72",
            "--lights",
            "50",
            "-q",
            "--no-report",
        ])
        .arg("--out")
        .arg(&out)
        .args(flags)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    out
}

/// A row-vector matrix as OpenEXR stores it (`p' = p·M`, row by row), as glam's
/// column-vector matrix.
fn exr_matrix(m: &[f32; 16]) -> Mat4 {
    Mat4::from_cols_array(m)
}

/// The passes agree with the scene: at one sample per pixel, each pixel's depth, put back
/// through the header's `worldToNDC`, is a point of the surface its albedo names — the
/// ground (y = 0, normal +Y) or the red sphere (centre (0, 0.5, 0), radius 0.5, normal
/// outwards) — and background pixels carry the documented values.
#[test]
fn depth_normal_and_albedo_passes_agree_with_the_scene_and_the_camera_matrices() {
    let tmp = tempfile::tempdir().unwrap();
    let out = render(tmp.path(), "passes", &["--frames", "5", "--spp", "1"]);
    let path = out.join("frame_0005.exr");
    let f = read_frame(&path).unwrap();
    let ch = |n: &str| f.channel(n).unwrap_or_else(|| panic!("no channel {n}"));
    let (z, nx, ny, nz) = (ch("Z"), ch("N.X"), ch("N.Y"), ch("N.Z"));
    let (ar, ag, ab) = (ch("albedo.R"), ch("albedo.G"), ch("albedo.B"));
    let attrs = &f.attributes;
    let to_ndc = exr_matrix(&attrs.world_to_normalized_device.expect("worldToNDC"));
    let to_camera = exr_matrix(&attrs.world_to_camera.expect("worldToCamera"));
    let from_ndc = to_ndc.inverse();
    let (w, h) = (f.width, f.height);
    let (mut ground, mut sphere, mut background) = (0, 0, 0);
    let mut failures = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let n = Vec3::new(nx[i], ny[i], nz[i]);
            let albedo = Vec3::new(ar[i], ag[i], ab[i]);
            if z[i] == BACKGROUND_DEPTH {
                background += 1;
                if n != Vec3::ZERO || albedo != Vec3::ZERO {
                    failures.push(format!("background ({x}, {y}): N {n}, albedo {albedo}"));
                }
                continue;
            }
            // NDC of the pixel centre at depth z: (x_ndc·w, y_ndc·w, 1, w) with w = z.
            let d = z[i];
            let ndc = Vec4::new(
                (x as f32 + 0.5) / w as f32 * d,
                (y as f32 + 0.5) / h as f32 * d,
                1.0,
                d,
            );
            let p = from_ndc * ndc;
            let p = p.truncate() / p.w;
            // The camera-space depth of that point is z again.
            let cz = (to_camera * p.extend(1.0)).z;
            if (cz - d).abs() > 1e-3 * d {
                failures.push(format!("({x}, {y}): depth {d}, camera z {cz}"));
            }
            if (n.length() - 1.0).abs() > 1e-3 {
                failures.push(format!("({x}, {y}): |N| = {}", n.length()));
            }
            if (albedo - Vec3::splat(0.5)).abs().max_element() < 1e-6 {
                ground += 1;
                if p.y.abs() > 2e-3 || (n - Vec3::Y).length() > 1e-4 {
                    failures.push(format!("ground ({x}, {y}): P {p}, N {n}"));
                }
            } else if (albedo - Vec3::new(0.75, 0.18, 0.15)).abs().max_element() < 1e-6 {
                sphere += 1;
                let c = Vec3::new(0.0, 0.5, 0.0);
                let r = (p - c).length();
                if (r - 0.5).abs() > 0.01 || (n - (p - c) / r).length() > 0.05 {
                    failures.push(format!("sphere ({x}, {y}): |P - c| = {r}, N {n}"));
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} pixels: {:?}",
        failures.len(),
        &failures[..failures.len().min(10)]
    );
    assert!(
        ground > 1000 && sphere > 50 && background > 100,
        "ground {ground}, sphere {sphere}, background {background}"
    );
}

/// With several samples, N and albedo are means with background samples counting 0 (so
/// they fade with the coverage at silhouettes), and Z is the nearest sample's depth.
#[test]
fn passes_at_several_samples_are_means_and_the_nearest_depth() {
    let tmp = tempfile::tempdir().unwrap();
    let out = render(tmp.path(), "spp", &["--frames", "5", "--spp", "4"]);
    let f = read_frame(&out.join("frame_0005.exr")).unwrap();
    let ch = |n: &str| f.channel(n).unwrap();
    let (z, cov) = (ch("Z"), ch("shadow.coverage"));
    let (nx, ny, nz) = (ch("N.X"), ch("N.Y"), ch("N.Z"));
    let mut edges = 0;
    for i in 0..z.len() {
        let n = Vec3::new(nx[i], ny[i], nz[i]).length();
        if cov[i] == 0.0 {
            assert_eq!((z[i], n), (BACKGROUND_DEPTH, 0.0), "pixel {i}");
        } else {
            assert!(z[i] < 100.0, "pixel {i}: coverage {}, Z {}", cov[i], z[i]);
            // A mean of unit normals (some of them 0) is no longer than the coverage.
            assert!(
                n <= cov[i] + 1e-4,
                "pixel {i}: |N| {n} > coverage {}",
                cov[i]
            );
            if cov[i] < 1.0 {
                edges += 1;
            }
        }
    }
    assert!(edges > 20, "only {edges} silhouette pixels");
}

/// `--half`: the beauty and the passes that allow it are half floats, counts and depth stay
/// 32-bit; the file is smaller and the values those of the float file, rounded.
#[test]
fn half_float_exrs_keep_counts_and_depth_exact() {
    use exr::prelude::*;
    let tmp = tempfile::tempdir().unwrap();
    let full = render(tmp.path(), "float", &["--frames", "1", "--validate"]);
    let half = render(
        tmp.path(),
        "half",
        &["--frames", "1", "--validate", "--half"],
    );
    let (fp, hp) = (full.join("frame_0001.exr"), half.join("frame_0001.exr"));
    let image = read_all_flat_layers_from_file(&hp).unwrap();
    let layer = &image.layer_data[0];
    let mut seen = Vec::new();
    for c in layer.channel_data.list.iter() {
        let name = c.name.to_string();
        let want_f32 = matches!(name.as_str(), "Z" | "shadow.rays" | "shadow.wrong");
        let is_f32 = matches!(c.sample_data, FlatSamples::F32(_));
        let is_f16 = matches!(c.sample_data, FlatSamples::F16(_));
        assert!(
            if want_f32 { is_f32 } else { is_f16 },
            "{name}: float {is_f32}, half {is_f16}"
        );
        seen.push(name);
    }
    assert!(seen.len() >= 13, "{seen:?}");
    let (a, b) = (read_frame(&fp).unwrap(), read_frame(&hp).unwrap());
    for (name, va) in &a.channels {
        let vb = b.channel(name).unwrap();
        for (x, y) in va.iter().zip(vb) {
            let ok = if matches!(name.as_str(), "Z" | "shadow.rays" | "shadow.wrong") {
                x == y
            } else {
                (x - y).abs() <= x.abs() * 1e-3 + 1e-4
            };
            assert!(ok, "{name}: {x} as half {y}");
        }
    }
    let (sf, sh) = (
        fs::metadata(&fp).unwrap().len(),
        fs::metadata(&hp).unwrap().len(),
    );
    assert!(sh * 10 < sf * 7, "half {sh} bytes, float {sf}");
}

/// The PNG is the EXR's beauty through the chosen view after the exposure, and the default
/// view is AgX.
#[test]
fn the_png_is_the_exr_through_the_view() {
    let tmp = tempfile::tempdir().unwrap();
    for (view, flags) in [
        (View::Agx, vec![]),
        (
            View::Standard,
            vec!["--view", "standard", "--exposure", "2"],
        ),
        (View::Hable, vec!["--view", "hable"]),
    ] {
        let mut args = vec!["--frames", "2"];
        args.extend(flags.iter().copied());
        let out = render(tmp.path(), view.name(), &args);
        let exposure = if view == View::Standard { 2.0 } else { 1.0 };
        let f = read_frame(&out.join("frame_0002.exr")).unwrap();
        let (r, g, b) = (
            f.channel("R").unwrap(),
            f.channel("G").unwrap(),
            f.channel("B").unwrap(),
        );
        let png = image::open(out.join("frame_0002.png")).unwrap().to_rgb8();
        for (i, p) in png.pixels().enumerate() {
            assert_eq!(
                p.0,
                view.to_8bit([r[i], g[i], b[i]], exposure),
                "{view}: pixel {i}"
            );
        }
        let settings = fs::read_to_string(out.join("settings.txt")).unwrap();
        assert!(
            settings.contains(&format!("[render] view = {}", view.name())),
            "{settings}"
        );
    }
    // A view that does not exist is refused, naming the flag.
    let o = common::bin()
        .arg("render")
        .arg(SPEC)
        .args(["--view", "aces", "--out"])
        .arg(tmp.path().join("bad"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("aces") && err.contains("standard, hable or agx"),
        "{err}"
    );
    // The old name of Hable's curve is refused with a pointer to its new one: it promised
    // Blender's Filmic, which it is not.
    let o = common::bin()
        .arg("render")
        .arg(SPEC)
        .args(["--view", "filmic", "--out"])
        .arg(tmp.path().join("old"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("hable") && err.contains("not Blender's Filmic"),
        "{err}"
    );
}

/// OpenImageIO, an independent reader, lists the named channels and the header's
/// attributes, and extracts the Blender-style layers by name.
#[test]
fn openimageio_reads_the_named_channels_and_attributes() {
    if !common::require_tools(
        common::this_test!(),
        &["iinfo", "oiiotool"],
        "apt-get install openimageio-tools",
    ) {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let out = render(
        tmp.path(),
        "oiio",
        &[
            "--frames",
            "3",
            "--spp",
            "4",
            "--validate",
            "--half",
            "--fps",
            "25",
        ],
    );
    let exr = out.join("frame_0003.exr");
    let o = Command::new("iinfo").arg("-v").arg(&exr).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let info = String::from_utf8_lossy(&o.stdout);
    let list = info
        .lines()
        .find_map(|l| l.trim().strip_prefix("channel list:"))
        .unwrap_or_else(|| panic!("no channel list:\n{info}"));
    for ch in [
        "R",
        "G",
        "B",
        "Z",
        "N.X",
        "N.Y",
        "N.Z",
        "albedo.R",
        "albedo.G",
        "albedo.B",
        "shadow.rays",
        "shadow.visible",
        "shadow.wrong",
        "shadow.coverage",
    ] {
        assert!(
            list.split(',')
                .any(|c| c.trim().split(' ').next() == Some(ch)),
            "{ch} not in {list}"
        );
    }
    for attr in [
        "worldToCamera:",
        "worldToNDC:",
        "framesPerSecond: 25/1",
        "software: \"envshadow ",
        "envshadow/frame: 3",
        "envshadow/render.method: \"grid-nowarp-uncertainty\"",
        "envshadow/render.spp: \"4\"",
        "envshadow/output.half: \"true\"",
        "envshadow/stats.rays_traced: ",
        "envshadow/stats.psnr_db: ",
        "chromaticities: 0.64, 0.33, 0.3, 0.6, 0.15, 0.06, 0.3127, 0.329",
    ] {
        assert!(info.contains(attr), "{attr} not in:\n{info}");
    }
    // Nothing that changes from run to run or with the tiles.
    for absent in [
        "seconds",
        "halo",
        "envshadow/render.threads",
        "envshadow/render.tile",
    ] {
        assert!(!info.contains(absent), "{absent} in:\n{info}");
    }
    // The layers come out by name, as a compositor asks for them.
    let normals = tmp.path().join("normals.exr");
    let o = Command::new("oiiotool")
        .arg(&exr)
        .args(["--ch", "N.X,N.Y,N.Z", "-o"])
        .arg(&normals)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let n = read_frame(&normals).unwrap();
    let names: Vec<&str> = n.channels.iter().map(|c| c.0.as_str()).collect();
    assert_eq!(names.len(), 3, "{names:?}");
    let ours = read_frame(&exr).unwrap();
    for name in ["N.X", "N.Y", "N.Z"] {
        assert_eq!(n.channel(name), ours.channel(name), "{name}");
    }
}

/// `ffprobe`'s answer for one stream entry of `video`.
fn probe(video: &Path, entries: &str) -> String {
    let o = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args([
            "-show_entries",
            entries,
            "-of",
            "default=noprint_wrappers=1",
        ])
        .arg(video)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// `envshadow video DIR` encodes every frame PNG into an H.264 MP4 that ffprobe reads with
/// the right frame count, size (odd sizes padded to even), rate (the render's `--fps`) and
/// pixel format, and rebuilds the report to show it; `--video` does the same at the end of
/// a render.
#[test]
fn video_encodes_every_frame_at_the_renders_frame_rate() {
    if !common::require_tools(
        common::this_test!(),
        &["ffmpeg", "ffprobe"],
        "apt-get install ffmpeg",
    ) {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("odd");
    let o = common::bin()
        .arg("render")
        .arg(SPEC)
        .args([
            "--width", "97", "--height", "73", "--lights", "20", "--frames", "0..7",
        ])
        .args(["--fps", "25", "-q", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = common::bin().arg("video").arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let said = String::from_utf8_lossy(&o.stdout);
    assert!(
        said.contains("7 frames") && said.contains("25 fps"),
        "{said}"
    );
    let video = out.join("video.mp4");
    let info = probe(
        &video,
        "stream=codec_name,pix_fmt,width,height,r_frame_rate,nb_read_frames",
    );
    for want in [
        "codec_name=h264",
        "pix_fmt=yuv420p",
        "width=98",
        "height=74",
        "r_frame_rate=25/1",
        "nb_read_frames=7",
    ] {
        assert!(info.lines().any(|l| l == want), "{want} not in:\n{info}");
    }
    // faststart: the index (moov) comes before the media data (mdat).
    let bytes = fs::read(&video).unwrap();
    let at = |tag: &[u8]| bytes.windows(4).position(|w| w == tag).unwrap();
    assert!(at(b"moov") < at(b"mdat"), "the index is not at the front");
    // No temporary left, and the report now shows the video instead of the GIF.
    let names = common::file_names(&out);
    assert!(!names.iter().any(|n| n.ends_with(".tmp")), "{names:?}");
    let html = fs::read_to_string(out.join("report.html")).unwrap();
    assert!(
        html.contains("<video") && html.contains("src=\"video.mp4\""),
        "no video in the report"
    );
    assert!(
        !html.contains("turntable.gif"),
        "the report still shows the GIF"
    );

    // --video: the render encodes it at the end.
    let out2 = tmp.path().join("flag");
    let o = common::bin()
        .arg("render")
        .arg(SPEC)
        .args([
            "--width", "64", "--height", "48", "--lights", "20", "--frames", "0..3",
        ])
        .args(["--video", "-q", "--no-report", "--out"])
        .arg(&out2)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let info = probe(
        &out2.join("video.mp4"),
        "stream=nb_read_frames,r_frame_rate",
    );
    assert!(
        info.contains("nb_read_frames=3") && info.contains("r_frame_rate=24/1"),
        "{info}"
    );

    // A farm: `plan --video` records it, the jobs render no video, `assemble` encodes the
    // assembled frames at the plan's rate.
    let farm = tmp.path().join("farm");
    let small = [
        "--width", "64", "--height", "48", "--lights", "20", "--frames", "0-3",
    ];
    let o = common::bin()
        .arg("plan")
        .arg(SPEC)
        .args(small)
        .args([
            "--fps", "30", "--video", "--jobs", "2", "--by", "frames", "-q", "--out",
        ])
        .arg(&farm)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for k in 0..2 {
        let o = common::bin()
            .arg("render")
            .arg(SPEC)
            .args(small)
            .args([
                "--fps", "30", "--video", "--of", "2", "--by", "frames", "-q", "--out",
            ])
            .arg(&farm)
            .args(["--job", &k.to_string()])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    assert!(!farm.join("video.mp4").exists(), "a job wrote the video");
    let o = common::bin()
        .args(["assemble", "--no-report"])
        .arg(&farm)
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && said.contains("video: "), "{said}");
    let info = probe(
        &farm.join("video.mp4"),
        "stream=nb_read_frames,r_frame_rate",
    );
    assert!(
        info.contains("nb_read_frames=4") && info.contains("r_frame_rate=30/1"),
        "{info}"
    );
}

/// Without ffmpeg, `envshadow video` and `render --video` stop with exit code 2 and say what
/// to install — the render before rendering anything — and write no video.
#[test]
fn video_without_ffmpeg_says_what_to_install() {
    let tmp = tempfile::tempdir().unwrap();
    let out = render(tmp.path(), "noffmpeg", &["--frames", "0..2"]);
    let empty = tmp.path().join("empty-path");
    fs::create_dir(&empty).unwrap();
    let o = common::bin()
        .env("PATH", &empty)
        .arg("video")
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("apt-get install ffmpeg") && err.contains("does not download"),
        "{err}"
    );
    assert!(!out.join("video.mp4").exists());
    let out2 = tmp.path().join("render-video");
    let o = common::bin()
        .env("PATH", &empty)
        .arg("render")
        .arg(SPEC)
        .args(["--frames", "0", "--video", "--out"])
        .arg(&out2)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("apt-get install ffmpeg"), "{err}");
    assert!(!out2.exists(), "the render started without ffmpeg");
}
