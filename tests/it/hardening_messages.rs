//! Issue 39, item 11: messages that say what is wrong. Geometry too large is not "zero-area";
//! a model too far from the origin is refused, not drawn as a sliver; a camera the loader set
//! aside says why; too many threads blame the threads; an output folder that is a file is
//! named as one (exit 2); an EXR map without RGB lists the channels it has.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::{Value, json};

use crate::common::{self, Failures, Gltf};

/// A triangle placed by `node` (its `mesh` set here), with `extra` merged into the document,
/// as `dir/name.gltf` with an embedded buffer.
fn model(dir: &Path, name: &str, node: Value, extra: Value) -> PathBuf {
    let mut g = Gltf::default();
    let p = g.floats("VEC3", &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let i = g.indices(&[0, 1, 2]);
    let mut node = node;
    node["mesh"] = json!(0);
    let mut rest = json!({
        "meshes": [{"primitives": [{"attributes": {"POSITION": p}, "indices": i}]}],
        "nodes": [node],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    });
    for (k, v) in extra.as_object().unwrap() {
        rest[k] = v.clone();
    }
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        common::base64(&g.bin)
    );
    let path = dir.join(format!("{name}.gltf"));
    fs::write(
        &path,
        serde_json::to_vec(&g.json(rest, Some(&uri))).unwrap(),
    )
    .unwrap();
    path
}

fn render(model: &Path, out: &Path, extra: &[&str]) -> Output {
    common::bin()
        .arg("render")
        .arg(model)
        .args([
            "--width", "32", "--height", "24", "--lights", "8", "--spp", "1",
        ])
        .args(["--frames", "0..1", "--no-report", "-q", "--out"])
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

/// A Y-only EXR map, 8×4.
fn luminance_map(path: &Path) {
    use exr::prelude::*;
    let y = AnyChannel::new("Y", FlatSamples::F32(vec![1.0; 32]));
    let layer = Layer::new(
        (8, 4),
        LayerAttributes::default(),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(SmallVec::from_vec(vec![y])),
    );
    Image::from_layer(layer).write().to_file(path).unwrap();
}

/// Issue 39, item 11: each case's error line says what is wrong, and the misleading words it
/// used to say are gone; exit 2 (bad input) for each.
#[test]
fn misleading_messages_say_what_is_wrong() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let camera = |projection: Value| {
        json!({"cameras": [projection], "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.5, 0.5, 3.0]}],
               "scenes": [{"nodes": [0, 1]}]})
    };
    let a_file = dir.join("a-file");
    fs::write(&a_file, "not a folder").unwrap();
    let y_map = dir.join("y.exr");
    luminance_map(&y_map);
    let plain = model(dir, "plain", json!({}), json!({}));
    let cases: Vec<(&str, PathBuf, Vec<String>, &str, &str)> = vec![
        (
            "scaled by 1e30",
            model(dir, "huge", json!({"scale": [1e30, 1e30, 1e30]}), json!({})),
            vec![],
            "too large to render",
            "zero-area",
        ),
        (
            "at x = 1e20",
            model(
                dir,
                "far",
                json!({"translation": [1e20, 0.0, 0.0]}),
                json!({}),
            ),
            vec![],
            "the model lies 1e20 units from the origin but spans only",
            "\u{0}",
        ),
        (
            "orthographic camera",
            model(
                dir,
                "ortho",
                json!({}),
                camera(
                    json!({"type": "orthographic", "orthographic": {"xmag": 1.0, "ymag": 1.0, "znear": 0.1, "zfar": 10.0}}),
                ),
            ),
            vec!["--gltf-camera".into()],
            "camera 0 is orthographic",
            "\u{0}",
        ),
        (
            "yfov 0 camera",
            model(
                dir,
                "yfov0",
                json!({}),
                camera(json!({"type": "perspective", "perspective": {"yfov": 0.0, "znear": 0.1}})),
            ),
            vec!["--gltf-camera".into()],
            "camera 0: its yfov 0 rad is not between 0 and π",
            "\u{0}",
        ),
        (
            "100000 threads",
            plain.clone(),
            vec!["--threads".into(), "100000".into()],
            "use fewer threads (--threads)",
            "pixels, samples or lights",
        ),
        (
            "output folder a file",
            plain.clone(),
            vec![],
            "is a file, not a folder",
            "File exists",
        ),
        (
            "Y-only map",
            plain.clone(),
            vec!["--env".into(), y_map.display().to_string()],
            "no layer with R, G and B channels, which an environment map needs (found: Y)",
            "\u{0}",
        ),
    ];
    let mut failures = Failures::new();
    for (case, model, extra, says, not) in cases {
        let out = if case == "output folder a file" {
            a_file.join("sub")
        } else {
            dir.join(format!("out-{}", case.replace(' ', "-")))
        };
        let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
        let o = render(&model, &out, &extra);
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        let ok = o.status.code() == Some(2) && err.contains(says) && !err.contains(not);
        failures.check(ok, || format!("{case}: exit {:?}: {err}", o.status.code()));
    }
    failures.assert_none();
}

/// Issue 39, item 9: what the loader warned about (an ignored extension, an orthographic
/// camera set aside) is kept with the run, not only printed: in `settings.txt`, in each
/// frame's EXR header and in the report.
#[test]
fn loader_warnings_reach_the_settings_the_exr_header_and_the_report() {
    use exr::meta::attribute::{AttributeValue, Text};
    let tmp = tempfile::tempdir().unwrap();
    let model = model(
        tmp.path(),
        "warned",
        json!({}),
        json!({
            "extensionsUsed": ["EXT_made_up"],
            "cameras": [{"type": "orthographic", "orthographic": {"xmag": 1.0, "ymag": 1.0, "znear": 0.1, "zfar": 10.0}}],
            "nodes": [{"mesh": 0}, {"camera": 0}],
            "scenes": [{"nodes": [0, 1]}],
        }),
    );
    let out = tmp.path().join("out");
    let o = common::bin()
        .arg("render")
        .arg(&model)
        .args([
            "--width", "32", "--height", "24", "--lights", "8", "--spp", "1",
        ])
        .args(["--frames", "0..1", "-q", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let settings = fs::read_to_string(out.join("settings.txt")).unwrap();
    let report = fs::read_to_string(out.join("report.html")).unwrap();
    let frame = envshadow::output::exr::read_frame(&out.join("frame_0000.exr")).unwrap();
    let header: Vec<String> = ["envshadow/warnings.1", "envshadow/warnings.2"]
        .iter()
        .filter_map(|k| match frame.attributes.other.get(&Text::from(*k)) {
            Some(AttributeValue::Text(t)) => Some(t.to_string()),
            _ => None,
        })
        .collect();
    for said in [
        "camera 0 is orthographic",
        "extensions not supported (ignored): EXT_made_up",
    ] {
        assert!(
            settings
                .lines()
                .any(|l| l.starts_with("[warnings] ") && l.contains(said)),
            "settings.txt lacks {said:?}: {settings}"
        );
        assert!(
            header.iter().any(|h| h.contains(said)),
            "EXR header: {header:?}"
        );
        assert!(report.contains(said), "report.html lacks {said:?}");
    }
}
