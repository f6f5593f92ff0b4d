//! Issue 39: inputs that cannot reach outside their folder, outputs that cannot clobber what
//! is not a regular file, a cleanup that removes only our temporaries, names printed with
//! their control characters escaped.

use std::fs;
use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::{Value, json};

use crate::common::{self, Failures, Gltf};
use envshadow::error::InputError;
use envshadow::scene::Scene;

/// One triangle's buffer and the document around it (`rest` for [`Gltf::json`]).
fn triangle() -> (Gltf, Value) {
    let mut g = Gltf::default();
    let p = g.floats("VEC3", &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let i = g.indices(&[0, 1, 2]);
    let rest = json!({
        "meshes": [{"primitives": [{"attributes": {"POSITION": p}, "indices": i}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    });
    (g, rest)
}

/// Writes `dir/name.gltf`, whose one buffer is at `uri` (the bytes are not written).
fn model_with_buffer_uri(dir: &Path, name: &str, uri: &str) -> PathBuf {
    let (g, rest) = triangle();
    let path = dir.join(format!("{name}.gltf"));
    fs::write(&path, serde_json::to_vec(&g.json(rest, Some(uri))).unwrap()).unwrap();
    path
}

/// A model folder `root/a/b/model` holding `tri.bin` and `link.bin` (a symbolic link to
/// `root/outside/tri.bin`), and that outside copy: `(model folder, outside folder)`.
fn folders(root: &Path) -> (PathBuf, PathBuf) {
    let model = root.join("a/b/model");
    let outside = root.join("outside");
    fs::create_dir_all(&model).unwrap();
    fs::create_dir_all(&outside).unwrap();
    let (g, _) = triangle();
    fs::write(model.join("tri.bin"), &g.bin).unwrap();
    fs::write(outside.join("tri.bin"), &g.bin).unwrap();
    std::os::unix::fs::symlink(outside.join("tri.bin"), model.join("link.bin")).unwrap();
    (model, outside)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `envshadow render MODEL` at a tiny size, one frame, into `out`, with `extra` flags.
fn render_model(model: &Path, out: &Path, extra: &[&str]) -> Output {
    common::bin()
        .arg("render")
        .arg(model)
        .args(["--width", "32", "--height", "24", "--lights", "8"])
        .args(["--frames", "0..1", "--no-report", "-q", "--out"])
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

/// Issue 39, item 1: a buffer URI that leads outside the model's folder — up the tree,
/// absolute, as a `file:` URI, percent-encoded, through a link — is refused with an input
/// error naming the model and the URI, even where the file it names is a valid buffer; a
/// `..` that climbs out and back in is read.
#[test]
fn gltf_uris_leading_outside_the_model_folder_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let (model, outside) = folders(tmp.path());
    let outside_bin = outside.join("tri.bin").display().to_string();
    let file_uri = format!("file://{outside_bin}");
    let mut failures = Failures::new();
    for uri in [
        "../../../etc/passwd",
        "/etc/passwd",
        "file:///etc/passwd",
        "%2e%2e/%2e%2e/%2e%2e/outside/tri.bin",
        "../../../outside/tri.bin",
        outside_bin.as_str(),
        file_uri.as_str(),
        "link.bin",
    ] {
        let path = model_with_buffer_uri(&model, "m", uri);
        match Scene::load(&path) {
            Ok(_) => failures.check(false, || format!("{uri}: loaded")),
            Err(e) => {
                let input = e.chain().any(|c| c.downcast_ref::<InputError>().is_some());
                let text = format!("{e:#}");
                failures.check(
                    input
                        && text.contains("m.gltf")
                        && text.contains(&format!("'{uri}'"))
                        && text.contains("outside the model's folder"),
                    || format!("{uri}: {text}"),
                )
            }
        };
    }
    let back_in = model_with_buffer_uri(&model, "m", "../model/tri.bin");
    failures.check(Scene::load(&back_in).is_ok(), || {
        "../model/tri.bin: refused".into()
    });
    failures.assert_none();
}

/// Issue 39, item 1: `--allow-folder DIR` and `[scene] allow_folder` open one more folder;
/// without them the same model is refused with exit code 2, the URI named.
#[test]
fn an_allowed_folder_opens_to_a_models_uris() {
    let tmp = tempfile::tempdir().unwrap();
    let (model, outside) = folders(tmp.path());
    let path = model_with_buffer_uri(&model, "m", "../../../outside/tri.bin");
    let refused = render_model(&path, &tmp.path().join("out0"), &[]);
    assert_eq!(refused.status.code(), Some(2), "{}", stderr(&refused));
    let line = common::error_line(&stderr(&refused)).to_string();
    assert!(line.contains("'../../../outside/tri.bin'"), "{line}");
    assert!(line.contains("--allow-folder"), "{line}");
    let allowed = render_model(
        &path,
        &tmp.path().join("out1"),
        &["--allow-folder", &outside.display().to_string()],
    );
    assert!(allowed.status.success(), "{}", stderr(&allowed));
    assert!(tmp.path().join("out1/frame_0000.exr").exists());
    let spec = tmp.path().join("spec.toml");
    fs::write(
        &spec,
        format!(
            "[scene]\nfile = {:?}\nallow_folder = {:?}\n[lights]\ncount = 8\n[motion]\nframes = 1\n\
             [render]\nwidth = 32\nheight = 24\n[output]\ndir = {:?}\n",
            path.display().to_string(),
            outside.display().to_string(),
            tmp.path().join("out2").display().to_string(),
        ),
    )
    .unwrap();
    let o = common::bin()
        .arg("render")
        .arg(&spec)
        .args(["--no-report", "-q"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(tmp.path().join("out2/frame_0000.exr").exists());
}

/// `dir/anim.toml`: the shapes scene, 2 frames of 32 × 24 lit by 8 lights.
fn shapes_spec(dir: &Path) -> PathBuf {
    let spec = dir.join("anim.toml");
    fs::write(
        &spec,
        "[scene]\nbuiltin = \"shapes\"\n[lights]\ncount = 8\n[motion]\nframes = 2\n\
         [render]\nwidth = 32\nheight = 24\n",
    )
    .unwrap();
    spec
}

/// What stands at an output path, to check that it is still there after a refusal.
#[derive(Debug, PartialEq)]
enum Standing {
    Fifo,
    Device,
    Link(PathBuf),
}

fn standing(path: &Path) -> Option<Standing> {
    let ft = fs::symlink_metadata(path).ok()?.file_type();
    if ft.is_fifo() {
        Some(Standing::Fifo)
    } else if ft.is_char_device() {
        Some(Standing::Device)
    } else if ft.is_symlink() {
        Some(Standing::Link(fs::read_link(path).unwrap()))
    } else {
        None
    }
}

/// In `dir`: a FIFO, a symbolic link to `dir/elsewhere.txt`, and — run as root, which alone
/// may make one — a character device node (the numbers of `/dev/null`). Each with what should
/// stand there afterwards.
fn hostile_targets(dir: &Path) -> Vec<(PathBuf, Standing)> {
    fs::create_dir_all(dir).unwrap();
    let fifo = dir.join("fifo");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    assert!(made.is_ok_and(|s| s.success()), "mkfifo failed");
    let elsewhere = dir.join("elsewhere.txt");
    fs::write(&elsewhere, b"the user's file").unwrap();
    let link = dir.join("link");
    std::os::unix::fs::symlink(&elsewhere, &link).unwrap();
    let mut targets = vec![(fifo, Standing::Fifo), (link, Standing::Link(elsewhere))];
    let device = dir.join("null");
    let made = std::process::Command::new("mknod")
        .arg(&device)
        .args(["c", "1", "3"])
        .output();
    if made.is_ok_and(|o| o.status.success()) {
        targets.push((device, Standing::Device));
    } else {
        // Only root may make a device node: the FIFO and the link are still checked.
        common::notice(&format!(
            "{}: not root, no device node made; the FIFO and symbolic link cases ran",
            common::this_test!()
        ));
    }
    targets
}

/// Runs `command` (with the target appended) for each hostile target: exit code 2, the path
/// named on stderr, the target standing as it was and the file a link points to unchanged.
fn check_refused(
    failures: &mut Failures,
    label: &str,
    dir: &Path,
    command: impl Fn(&Path) -> Output,
) {
    for (target, want) in hostile_targets(dir) {
        let o = command(&target);
        let err = stderr(&o);
        failures.check(
            o.status.code() == Some(2) && err.contains(&target.display().to_string()),
            || format!("{label} {}: {:?} {err}", target.display(), o.status.code()),
        );
        let what = format!("{label} {}: left standing", target.display());
        failures.check_eq(standing(&target), Some(want), || what);
    }
    let elsewhere = fs::read(dir.join("elsewhere.txt")).unwrap();
    failures.check(elsewhere == b"the user's file", || {
        format!("{label}: the file a link points to was changed")
    });
}

/// Issue 39, item 2: `lights --json/--png`, `savings --out` and `video --out` refuse (exit 2,
/// the path named) to publish over a FIFO, a symbolic link or a device node, and leave each
/// as it was.
#[test]
fn outputs_never_replace_what_is_not_a_regular_file() {
    let tmp = tempfile::tempdir().unwrap();
    let mut failures = Failures::new();
    for flag in ["--json", "--png"] {
        let dir = tmp.path().join(format!("lights{flag}"));
        check_refused(&mut failures, &format!("lights {flag}"), &dir, |t| {
            common::bin()
                .args(["lights", "builtin:sky", "-n", "8", "-q", flag])
                .arg(t)
                .output()
                .unwrap()
        });
    }
    // Two renders of the same frames, with and without --temporal, for `savings` and `video`.
    let spec = shapes_spec(tmp.path());
    let (with, without) = (tmp.path().join("with"), tmp.path().join("without"));
    for (out, extra) in [(&with, Some("--temporal")), (&without, None)] {
        let o = common::bin()
            .arg("render")
            .arg(&spec)
            .args(["--no-report", "-q", "--out"])
            .arg(out)
            .args(extra)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
    }
    check_refused(&mut failures, "savings --out", &tmp.path().join("s"), |t| {
        common::bin()
            .arg("savings")
            .arg(&with)
            .arg("--without")
            .arg(&without)
            .args(["-q", "--out"])
            .arg(t)
            .output()
            .unwrap()
    });
    if common::require_tools(common::this_test!(), &["ffmpeg"], "apt-get install ffmpeg") {
        check_refused(&mut failures, "video --out", &tmp.path().join("v"), |t| {
            common::bin()
                .arg("video")
                .arg(&without)
                .args(["-q", "--out"])
                .arg(t)
                .output()
                .unwrap()
        });
    }
    failures.assert_none();
}

/// Issue 39, item 4 (3 of the brief): a render deleted a user's files in its output folder
/// whose names looked like our temporaries. Only names carrying our mark are removed.
#[test]
fn a_render_keeps_the_users_tmp_files() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    fs::create_dir_all(&out).unwrap();
    let users = ["thesis.docx.4242-1-deadbeef.tmp", "x.123.tmp"];
    for n in users {
        fs::write(out.join(n), n.as_bytes()).unwrap();
    }
    let spec = shapes_spec(tmp.path());
    let o = common::bin()
        .arg("render")
        .arg(&spec)
        .args(["--frames", "0..2", "--no-report", "-q", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.join("frame_0001.exr").exists(), "no frames written");
    for n in users {
        assert_eq!(
            fs::read(out.join(n)).ok().as_deref(),
            Some(n.as_bytes()),
            "{n}"
        );
    }
}

/// Issue 39, item 6 (4 of the brief): an image URI with an ANSI escape and a newline reaches
/// stderr escaped: no raw control character, and one error line (no forged second line).
#[test]
fn a_uri_with_control_characters_is_printed_escaped() {
    let tmp = tempfile::tempdir().unwrap();
    let (mut g, mut rest) = triangle();
    let uv = g.floats("VEC2", &[0.0, 0.0, 1.0, 0.0, 0.0, 1.0]);
    rest["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = json!(uv);
    rest["meshes"][0]["primitives"][0]["material"] = json!(0);
    rest["materials"] = json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]);
    rest["textures"] = json!([{"source": 0}]);
    rest["images"] = json!([{"uri": "tex\u{1b}[2J\u{1b}[31m\nerror: forged.png"}]);
    let model = g.write_gltf(tmp.path(), "m", rest);
    let o = render_model(&model, &tmp.path().join("out"), &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    let raw: Vec<char> = err
        .chars()
        .filter(|&c| c.is_control() && c != '\n')
        .collect();
    assert!(raw.is_empty(), "raw control characters {raw:?} in {err:?}");
    let line = common::error_line(&err);
    assert!(
        line.contains("tex\\u{1b}[2J\\u{1b}[31m\\nerror: forged.png"),
        "{line}"
    );
}

/// Issue 39, item 10 (5 of the brief): `plan` left a `.gltf`'s `.bin` and textures out of
/// `inputs.txt`, so a farm without a shared file system shipped a model that cannot load.
#[test]
fn plan_lists_every_file_a_gltf_references() {
    let tmp = tempfile::tempdir().unwrap();
    let (mut g, mut rest) = triangle();
    let uv = g.floats("VEC2", &[0.0, 0.0, 1.0, 0.0, 0.0, 1.0]);
    rest["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = json!(uv);
    rest["meshes"][0]["primitives"][0]["material"] = json!(0);
    rest["materials"] = json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]);
    rest["textures"] = json!([{"source": 0}]);
    rest["images"] = json!([{"uri": "tex%20ture.png"}]);
    let model_dir = tmp.path().join("model");
    fs::create_dir_all(&model_dir).unwrap();
    let model = g.write_gltf(&model_dir, "m", rest);
    fs::write(model_dir.join("tex ture.png"), b"not decoded by plan").unwrap();
    let spec = tmp.path().join("anim.toml");
    fs::write(
        &spec,
        format!(
            "[scene]\nfile = {:?}\n[motion]\nframes = 2\n",
            model.display().to_string()
        ),
    )
    .unwrap();
    let farm = tmp.path().join("farm");
    let o = common::bin()
        .arg("plan")
        .arg(&spec)
        .args(["--jobs", "2", "-q", "--out"])
        .arg(&farm)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let listed = fs::read_to_string(farm.join("inputs.txt")).unwrap();
    let listed: Vec<&str> = listed.lines().collect();
    for f in [
        &spec,
        &model,
        &model_dir.join("m.bin"),
        &model_dir.join("tex ture.png"),
    ] {
        let want = fs::canonicalize(f).unwrap().display().to_string();
        assert!(
            listed.contains(&want.as_str()),
            "{want} missing: {listed:?}"
        );
    }
    assert_eq!(listed.len(), 4, "{listed:?}");
}

/// Issue 39, item 6: a warning naming something from the file (an unsupported extension whose
/// name holds an ANSI escape and a newline) is kept and printed escaped.
#[test]
fn a_warning_with_control_characters_is_printed_escaped() {
    let tmp = tempfile::tempdir().unwrap();
    let (g, mut rest) = triangle();
    rest["extensionsUsed"] = json!(["EXT_\u{1b}[2Jevil\nwarning: forged"]);
    let model = g.write_gltf(tmp.path(), "m", rest);
    let scene = Scene::load(&model).unwrap();
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("EXT_\\u{1b}[2Jevil\\nwarning: forged")),
        "{:?}",
        scene.warnings
    );
    let o = common::bin()
        .arg("render")
        .arg(&model)
        .args(["--width", "32", "--height", "24", "--lights", "8"])
        .args(["--frames", "0..1", "--no-report", "--out"])
        .arg(tmp.path().join("out"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    let raw: Vec<char> = err
        .chars()
        .filter(|&c| c.is_control() && c != '\n' && c != '\r')
        .collect();
    assert!(raw.is_empty(), "raw control characters {raw:?} in {err:?}");
    assert!(
        !err.lines().any(|l| l.starts_with("warning: forged")),
        "{err}"
    );
    assert!(
        err.contains("EXT_\\u{1b}[2Jevil\\nwarning: forged"),
        "{err}"
    );
}

/// Two hosts agree on a render only when its every input agrees: a `.gltf` whose buffer
/// differs under the same name is another render (the farm's fingerprint hashed only the
/// `.gltf`), while the same files in another folder are the same render.
#[test]
fn farm_fingerprint_covers_a_gltfs_buffers_not_its_folder() {
    use envshadow::anim::{AnimFlags, Animation};
    use envshadow::farm::identity::settings_fingerprint;
    let root = tempfile::tempdir().unwrap();
    let fingerprint = |dir: &Path| {
        let spec = dir.join("spec.toml");
        let text = "[scene]\nfile = \"model.gltf\"\n[environment]\nbuiltin = \"sky\"\n";
        fs::write(&spec, text).unwrap();
        let anim = Animation::parse(text, &spec, &AnimFlags::default()).unwrap();
        settings_fingerprint(&anim).unwrap()
    };
    let (g, rest) = triangle();
    let (a, b) = (root.path().join("a"), root.path().join("b"));
    for dir in [&a, &b] {
        fs::create_dir_all(dir).unwrap();
        g.write_gltf(dir, "model", rest.clone());
    }
    assert_eq!(fingerprint(&a), fingerprint(&b), "same files, other folder");
    let mut bin = fs::read(b.join("model.bin")).unwrap();
    bin[12] ^= 0x40; // the second vertex's x
    fs::write(b.join("model.bin"), &bin).unwrap();
    assert_ne!(
        fingerprint(&a),
        fingerprint(&b),
        "another buffer under the same name"
    );
}
