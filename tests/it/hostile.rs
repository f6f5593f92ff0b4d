//! Hostile and broken inputs through the binary: every kind gives exit code 2, one line on
//! stderr naming the file and the problem, no panic, and no output file.

use crate::common::{self, Failures};

use std::ffi::OsString;
use std::fs;
use std::path::{Path, PathBuf};

use serde_json::{Value, json};

/// Runs `envshadow ARGS` and checks a bad-input failure naming each of `needles`.
fn expect_refused(kind: &str, args: &[OsString], needles: &[&str], out: &Path) {
    let o = common::bin().args(args).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{kind}: stderr {err}");
    assert!(!err.contains("panicked"), "{kind}: {err}");
    let line = common::error_line(&err);
    for n in needles {
        assert!(
            line.to_lowercase().contains(&n.to_lowercase()),
            "{kind}: {n:?} not in {err}"
        );
    }
    assert!(
        common::file_names(out).is_empty(),
        "{kind}: left {:?}",
        common::file_names(out)
    );
}

/// A valid one-primitive glTF (two triangles sharing an edge, normals, u16 indices) in one
/// `data:` buffer: positions at 0 (48 bytes), normals at 48 (48), indices at 96 (12).
fn quad_gltf() -> Value {
    let mut b = Vec::new();
    for v in [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ] {
        v.iter().for_each(|c| b.extend_from_slice(&c.to_le_bytes()));
    }
    for _ in 0..4 {
        [0.0f32, 0.0, 1.0]
            .iter()
            .for_each(|c| b.extend_from_slice(&c.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}
        ]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 12}
        ],
        "buffers": [{"byteLength": 108,
                     "uri": format!("data:application/octet-stream;base64,{}", common::base64(&b))}]
    })
}

/// Bytes of a glTF like [`quad_gltf`] with `edit` applied to its JSON and `bytes` (its buffer)
/// changed by `poke`.
fn edited_gltf(edit: impl Fn(&mut Value), poke: impl Fn(&mut Vec<u8>)) -> Vec<u8> {
    let mut doc = quad_gltf();
    let uri = doc["buffers"][0]["uri"].as_str().unwrap().to_string();
    let payload = uri.split_once(";base64,").unwrap().1;
    let mut bytes = decode64(payload);
    poke(&mut bytes);
    doc["buffers"][0]["uri"] = json!(format!(
        "data:application/octet-stream;base64,{}",
        common::base64(&bytes)
    ));
    edit(&mut doc);
    serde_json::to_vec_pretty(&doc).unwrap()
}

fn decode64(s: &str) -> Vec<u8> {
    let mut out = Vec::new();
    let (mut acc, mut bits) = (0u32, 0);
    for c in s.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => continue,
        };
        acc = (acc << 6) | u32::from(v);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    out
}

fn write_exr(path: &Path, w: usize, h: usize, f: impl Fn(usize, usize) -> f32 + Sync) {
    use exr::prelude::*;
    let layer = SpecificChannels::rgb(|Vec2(x, y)| (f(x, y), 0.5f32, 0.25f32));
    Image::from_channels((w, h), layer)
        .write()
        .to_file(path)
        .unwrap();
}

fn write_hdr(path: &Path, w: usize, h: usize) {
    let pixels: Vec<image::Rgb<f32>> = (0..w * h)
        .map(|i| image::Rgb([1.0 + i as f32, 0.5, 0.25]))
        .collect();
    let mut bytes = Vec::new();
    image::codecs::hdr::HdrEncoder::new(&mut bytes)
        .encode(&pixels, w, h)
        .unwrap();
    fs::write(path, bytes).unwrap();
}

/// The table of broken inputs: each kind is a case of `failures`, so every kind that is not
/// refused properly is listed, not only the first.
struct Case {
    dir: PathBuf,
    out: PathBuf,
    count: usize,
    failures: Failures,
}

impl Case {
    /// Cases whose files go in `dir` and whose renders write to `dir/out`.
    fn new(dir: &Path) -> Case {
        Case {
            dir: dir.to_path_buf(),
            out: dir.join("out"),
            count: 0,
            failures: Failures::new(),
        }
    }

    fn spec(&self, name: &str, body: &str) -> PathBuf {
        let p = self.dir.join(name);
        fs::write(
            &p,
            format!(
                "[output]\ndir = \"{}\"\n{body}\n[lights]\ncount = 8\n",
                self.out.display()
            ),
        )
        .unwrap();
        p
    }

    fn render(&mut self, kind: &str, spec: &Path, flags: &[&str], needles: &[&str]) {
        let mut args = vec![OsString::from("render"), spec.as_os_str().to_owned()];
        args.extend(flags.iter().map(OsString::from));
        args.push("--no-report".into());
        let out = &self.out;
        self.failures
            .case(kind, || expect_refused(kind, &args, needles, out));
        self.count += 1;
    }

    /// A scene file with `bytes` is refused with a message naming it and each of `needles`.
    fn scene(&mut self, kind: &str, name: &str, bytes: &[u8], needles: &[&str]) {
        let file = self.dir.join(name);
        fs::write(&file, bytes).unwrap();
        let spec = self.spec(
            &format!("{name}.toml"),
            &format!(
                "[scene]\nfile = \"{}\"\n[render]\nwidth = 16\nheight = 16\n",
                file.display()
            ),
        );
        let mut all = vec![name];
        all.extend_from_slice(needles);
        self.render(kind, &spec, &[], &all);
    }

    /// An environment map file with `bytes` (or already written) is refused likewise.
    fn map(&mut self, kind: &str, name: &str, bytes: Option<&[u8]>, needles: &[&str]) {
        let file = self.dir.join(name);
        if let Some(b) = bytes {
            fs::write(&file, b).unwrap();
        }
        let spec = self.spec(
            &format!("{name}.toml"),
            &format!(
                "[scene]\nbuiltin = \"shapes\"\n[environment]\nfile = \"{}\"\n[render]\nwidth = 16\nheight = 16\n",
                file.display()
            ),
        );
        let mut all = vec![name];
        all.extend_from_slice(needles);
        self.render(kind, &spec, &[], &all);
    }
}

#[test]
fn every_kind_of_broken_input_is_refused_with_one_located_line() {
    let tmp = tempfile::tempdir().unwrap();
    let mut c = Case::new(tmp.path());

    // The control: the unedited file renders.
    let good = c.dir.join("good.gltf");
    fs::write(&good, edited_gltf(|_| {}, |_| {})).unwrap();
    let spec = c.spec(
        "good.toml",
        &format!(
            "[scene]\nfile = \"{}\"\n[render]\nwidth = 16\nheight = 16\n",
            good.display()
        ),
    );
    let o = common::bin()
        .arg("render")
        .arg(&spec)
        .args(["--no-report", "-q", "--out"])
        .arg(c.dir.join("good-out"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    // glTF and GLB.
    let glb = fs::read(common::asset("bunny_res4.glb")).unwrap();
    c.scene(
        "truncated GLB",
        "half.glb",
        &glb[..glb.len() / 2],
        &["truncated GLB"],
    );
    let mut bad_magic = glb.clone();
    bad_magic[12..16].copy_from_slice(b"XXXX");
    c.scene(
        "GLB with a broken chunk",
        "chunk.glb",
        &bad_magic,
        &["not a valid glTF"],
    );
    c.scene(
        "wrong accessor count",
        "count.gltf",
        &edited_gltf(|d| d["accessors"][1]["count"] = json!(3), |_| {}),
        &[
            "mesh 0 primitive 0",
            "accessor 1 (NORMAL) has 3 elements but accessor 0 (POSITION) has 4",
        ],
    );
    c.scene(
        "index out of range",
        "index.gltf",
        &edited_gltf(|_| {}, |b| b[100..102].copy_from_slice(&9u16.to_le_bytes())),
        &["mesh 0 primitive 0", "accessor 2", "index 9 out of range"],
    );
    c.scene(
        "missing external buffer",
        "nobuffer.gltf",
        &edited_gltf(|d| d["buffers"][0]["uri"] = json!("absent.bin"), |_| {}),
        &["buffer 0", "absent.bin"],
    );
    c.scene(
        "NaN position",
        "nan.gltf",
        &edited_gltf(
            |_| {},
            |b| b[16..20].copy_from_slice(&f32::NAN.to_le_bytes()),
        ),
        &[
            "mesh 0 primitive 0",
            "accessor 0 (POSITION)",
            "vertex 1 is not finite",
        ],
    );
    c.scene(
        "only non-triangle primitives",
        "lines.gltf",
        &edited_gltf(
            |d| d["meshes"][0]["primitives"][0]["mode"] = json!(1),
            |_| {},
        ),
        &["no triangles", "mesh 0 primitive 0: mode Lines"],
    );
    c.scene(
        "only zero-area triangles",
        "flat.gltf",
        &edited_gltf(
            |_| {},
            |b| {
                for v in 0..4 {
                    b[v * 12 + 4..v * 12 + 8].copy_from_slice(&0f32.to_le_bytes());
                }
            },
        ),
        &["no triangles", "2 zero-area triangles skipped"],
    );
    c.scene(
        "POSITION accessor out of range",
        "posref.gltf",
        &edited_gltf(
            |d| d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(7),
            |_| {},
        ),
        &["mesh 0 primitive 0", "accessor 7"],
    );
    c.scene(
        "buffer view outside its buffer",
        "view.gltf",
        &edited_gltf(|d| d["bufferViews"][1]["byteOffset"] = json!(100), |_| {}),
        &["mesh 0 primitive 0", "accessor 1", "outside its buffer"],
    );
    c.scene(
        "byteStride smaller than the element",
        "stride.gltf",
        &edited_gltf(|d| d["bufferViews"][0]["byteStride"] = json!(4), |_| {}),
        &["accessor 0", "byteStride"],
    );
    c.scene(
        "node cycle",
        "cycle.gltf",
        &edited_gltf(
            |d| d["nodes"] = json!([{"mesh": 0, "children": [1]}, {"children": [0]}]),
            |_| {},
        ),
        &["node 0", "reached twice"],
    );
    c.scene(
        "absurd accessor count",
        "huge.gltf",
        &edited_gltf(
            |d| d["accessors"][0]["count"] = json!(4_000_000_000u64),
            |_| {},
        ),
        &["mesh 0 primitive 0", "accessor 0", "count 4000000000"],
    );
    c.scene(
        "undecodable texture",
        "texture.gltf",
        &edited_gltf(
            |d| {
                d["materials"] =
                    json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]);
                d["textures"] = json!([{"source": 0}]);
                d["images"] = json!([{"uri": "data:image/png;base64,iVBORw0KGgoAAAA="}]);
                d["meshes"][0]["primitives"][0]["material"] = json!(0);
            },
            |_| {},
        ),
        &["material 0: image 0", "cannot decode"],
    );

    // Environment maps.
    let exr = c.dir.join("whole.exr");
    write_exr(&exr, 64, 32, |x, _| x as f32);
    let bytes = fs::read(&exr).unwrap();
    c.map(
        "truncated EXR",
        "cut.exr",
        Some(&bytes[..bytes.len() * 2 / 3]),
        &["OpenEXR"],
    );
    write_exr(&c.dir.join("nan.exr"), 8, 4, |x, y| {
        if (x, y) == (5, 1) { f32::NAN } else { 1.0 }
    });
    c.map("NaN texel", "nan.exr", None, &["texel (5, 1)", "NaN"]);
    write_exr(&c.dir.join("neg.exr"), 8, 4, |x, y| {
        if (x, y) == (2, 3) { -2.0 } else { 1.0 }
    });
    c.map(
        "negative texel",
        "neg.exr",
        None,
        &["texel (2, 3)", "negative"],
    );
    c.map(
        "HDR with a bad header",
        "header.hdr",
        Some(b"#?NOTRADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 2\n"),
        &["not a valid Radiance HDR"],
    );
    c.map(
        "HDR declaring an absurd size",
        "vast.hdr",
        Some(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 100000\n\x01\x02\x03\x04"),
        &["100000×100000", "too large"],
    );
    let hdr = c.dir.join("whole.hdr");
    write_hdr(&hdr, 32, 16);
    let bytes = fs::read(&hdr).unwrap();
    c.map(
        "truncated HDR pixels",
        "cut.hdr",
        Some(&bytes[..bytes.len() / 2]),
        &["Radiance HDR"],
    );
    c.map(
        "unsupported map format",
        "map.png",
        Some(b"\x89PNG"),
        &["unsupported environment map format"],
    );

    // Animation specs and flags.
    let p = c.spec(
        "type.toml",
        "[scene]\nbuiltin = \"shapes\"\n[render]\nwidth = \"wide\"",
    );
    c.render(
        "TOML wrong type",
        &p,
        &[],
        &["type.toml", "line 6", "width = \"wide\"", "invalid type"],
    );
    let p = c.spec(
        "key.toml",
        "[scene]\nbuiltin = \"shapes\"\n[camera]\nfov = 30.0",
    );
    c.render(
        "TOML unknown key",
        &p,
        &[],
        &["key.toml", "line 6", "unknown field `fov`"],
    );
    let p = c.spec("syntax.toml", "[scene\nbuiltin = \"shapes\"");
    c.render("TOML syntax", &p, &[], &["syntax.toml", "line 3"]);
    let p = c.spec("ok.toml", "[scene]\nbuiltin = \"shapes\"");
    c.render(
        "absurd resolution",
        &p,
        &["--width", "100000", "--height", "100000"],
        &["ok.toml", "100000x100000", "would need about", "TB"],
    );
    c.render(
        "a million lights",
        &p,
        &["--lights", "1000000"],
        &["ok.toml", "1000000 lights", "would need about", "GB"],
    );
    c.render(
        "memory estimate over the budget",
        &p,
        &[
            "--width", "16000", "--height", "4000", "--lights", "4000", "--tile", "0",
        ],
        &["ok.toml", "would need about", "GB of memory"],
    );
    let p = c.spec(
        "frames.toml",
        "[scene]\nbuiltin = \"shapes\"\n[motion]\nframes = 0",
    );
    c.render("zero frames", &p, &[], &["frames.toml", "frames = 0"]);
    let p = c.spec(
        "vfov.toml",
        "[scene]\nbuiltin = \"shapes\"\n[camera]\nvfov = 500.0",
    );
    c.render("field of view", &p, &[], &["vfov.toml", "vfov = 500"]);
    let p = c.spec(
        "flood.toml",
        "[scene]\nbuiltin = \"shapes\"\n[render]\nflood_to = \"some\"",
    );
    c.render(
        "unknown flood rule",
        &p,
        &[],
        &[
            "flood.toml",
            "[render] flood_to",
            "\"some\"",
            "all, contrary-finest, contrary, adaptive or auto",
        ],
    );
    c.render(
        "unknown flood rule flag",
        &c.dir.join("ok.toml"),
        &["--flood-to", "most"],
        &[
            "--flood-to",
            "most",
            "all, contrary-finest, contrary, adaptive or auto",
        ],
    );

    assert!(c.count >= 20, "{} kinds", c.count);
    c.failures.assert_none();
}

/// Issue 20, item 7: a NaN or infinite number anywhere in a spec, an `up` of zero length or
/// along the view (at any frame of the orbit), is refused with its key named and exit 2 —
/// before lights.json or a frame is written. A NaN pivot used to panic inside the BVH build;
/// a NaN camera rendered empty frames with exit 0.
#[test]
fn non_finite_numbers_and_a_degenerate_camera_are_refused_before_any_file() {
    let tmp = tempfile::tempdir().unwrap();
    let mut c = Case::new(tmp.path());
    let scene = "[scene]\nbuiltin = \"shapes\"\n[render]\nwidth = 16\nheight = 16\n";
    let cases: [(&str, &str, &[&str]); 11] = [
        (
            "NaN pivot",
            "[motion]\nkind = \"spin\"\nframes = 2\npivot = [nan, 0.0, 0.0]",
            &["[motion] pivot", "not finite"],
        ),
        (
            "infinite pivot",
            "[motion]\nkind = \"spin\"\nframes = 2\npivot = [0.0, inf, 0.0]",
            &["[motion] pivot", "inf", "not finite"],
        ),
        (
            "NaN camera position",
            "[camera]\nposition = [nan, 1.0, 1.0]",
            &["[camera] position", "not finite"],
        ),
        (
            "infinite camera target",
            "[camera]\ntarget = [0.0, -inf, 0.0]",
            &["[camera] target", "not finite"],
        ),
        (
            "NaN up",
            "[camera]\nup = [0.0, nan, 0.0]",
            &["[camera] up", "not finite"],
        ),
        (
            "zero up",
            "[camera]\nup = [0.0, 0.0, 0.0]",
            &["[camera] up", "no direction"],
        ),
        (
            "up along the view",
            "[camera]\nelevation = 90.0",
            &["[camera] up", "parallel to the view direction", "frame 0"],
        ),
        (
            "up along the view at the orbit's second frame",
            "[camera]\nup = [1.0, 0.0, 0.0]\nelevation = 0.0\nazimuth = 0.0\n\
             [motion]\nframes = 4\ndegrees_per_frame = 90.0",
            &["[camera] up", "parallel to the view direction", "frame 1"],
        ),
        (
            "infinite turn",
            "[motion]\nframes = 4\nturn_degrees = inf",
            &["[motion] turn_degrees", "not a finite number"],
        ),
        (
            "NaN map rotation",
            "[environment]\nbuiltin = \"sky\"\nrotation = nan",
            &["[environment] rotation", "not a finite number"],
        ),
        (
            "NaN elevation",
            "[camera]\nelevation = nan",
            &["[camera] elevation", "not a finite number"],
        ),
    ];
    for (i, (kind, body, needles)) in cases.iter().enumerate() {
        let name = format!("case{i}.toml");
        let spec = c.spec(&name, &format!("{scene}{body}"));
        let mut all = vec![name.as_str()];
        all.extend_from_slice(needles);
        c.render(kind, &spec, &[], &all);
    }
    c.failures.assert_none();
}

#[test]
fn non_triangle_primitives_and_zero_area_triangles_are_skipped_with_warnings() {
    let tmp = tempfile::tempdir().unwrap();
    // A second primitive of points beside the quad, and one of the quad's triangles collapsed.
    let bytes = edited_gltf(
        |d| {
            let mut points = d["meshes"][0]["primitives"][0].clone();
            points["mode"] = json!(0);
            d["meshes"][0]["primitives"]
                .as_array_mut()
                .unwrap()
                .push(points);
        },
        // Vertex 3 onto the diagonal from vertex 0 to 2: triangle (0, 2, 3) has no area.
        |b| {
            b[36..40].copy_from_slice(&0.5f32.to_le_bytes());
            b[40..44].copy_from_slice(&0.5f32.to_le_bytes());
        },
    );
    let file = tmp.path().join("mixed.gltf");
    fs::write(&file, bytes).unwrap();
    let spec = tmp.path().join("mixed.toml");
    fs::write(
        &spec,
        format!(
            "[scene]\nfile = \"{}\"\n[render]\nwidth = 16\nheight = 16\n[lights]\ncount = 8\n[output]\ndir = \"{}\"\n",
            file.display(),
            tmp.path().join("out").display()
        ),
    )
    .unwrap();
    let render = |extra: &[&str]| {
        let o = common::bin()
            .arg("render")
            .arg(&spec)
            .arg("--no-report")
            .args(extra)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{err}");
        err
    };
    let err = render(&[]);
    assert!(
        err.contains("warning: ") && err.contains("mixed.gltf: mesh 0 primitive 1: mode Points"),
        "{err}"
    );
    assert!(
        err.contains("mesh 0 primitive 0: 1 zero-area triangles skipped"),
        "{err}"
    );
    assert!(tmp.path().join("out/frame_0000.exr").exists());
    // -q prints errors only (issue 22, item 7).
    assert_eq!(render(&["-q"]), "");
}
