//! Issue 20, item 6: memory is bounded by what the inputs hold. Each distinct image is decoded
//! once, however many materials and image entries use it. Only regular files are read: a device
//! such as `/dev/zero` would be read until memory ran out, a FIFO would block.
//!
//! The binary runs under `prlimit --as=4G`: a refusal there happened before any large
//! allocation.

use std::path::{Path, PathBuf};
use std::process::Output;

use envshadow::scene::Scene;
use serde_json::{Value, json};

use crate::common::{self, Failures};

/// The address-space limit the bombs run under.
const FOUR_GB: u64 = 4_000_000_000;

/// `envshadow render SPEC --no-report -q` under `prlimit --as=BYTES`. prlimit (util-linux) is
/// required: without it these tests fail rather than pass unchecked.
fn render_limited(spec: &Path, bytes: u64) -> Output {
    std::process::Command::new("prlimit")
        .arg(format!("--as={bytes}"))
        .arg(env!("CARGO_BIN_EXE_envshadow"))
        .arg("render")
        .arg(spec)
        .args(["--no-report", "-q"])
        .output()
        .expect("prlimit (util-linux) is needed to run the render under an address-space limit")
}

/// Checks a refusal: exit code `code`, one line on stderr naming each of `needles`, no panic
/// or abort, nothing written to `out`.
fn assert_refused(o: &Output, code: i32, needles: &[&str], out: &Path) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(code), "stderr: {err}");
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "one line expected: {err}");
    assert!(lines[0].starts_with("error: "), "{err}");
    for n in needles {
        assert!(err.contains(n), "{n:?} not in: {err}");
    }
    assert!(
        common::file_names(out).is_empty(),
        "left {:?}",
        common::file_names(out)
    );
}

/// A spec rendering `scene` (a file in `dir`, or the built-in shapes) under `map` (or the
/// built-in sky) into `dir/out`, small: 32 × 24 pixels, 8 lights; `extra` adds tables.
fn spec(dir: &Path, name: &str, scene: Option<&str>, map: Option<&str>, extra: &str) -> PathBuf {
    let scene = match scene {
        Some(f) => format!("file = \"{f}\""),
        None => "builtin = \"shapes\"".to_string(),
    };
    let map = map.map_or(String::new(), |f| {
        format!("[environment]\nfile = \"{f}\"\n")
    });
    let lights = if extra.contains("[lights]") {
        ""
    } else {
        "[lights]\ncount = 8\n"
    };
    let p = dir.join(format!("{name}.toml"));
    std::fs::write(
        &p,
        format!(
            "[scene]\n{scene}\n{map}[render]\nwidth = 32\nheight = 24\n[output]\ndir = \"{}\"\n{lights}{extra}",
            dir.join("out").display()
        ),
    )
    .unwrap();
    p
}

fn base64(data: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in data.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            s.push(if k <= c.len() {
                A[(n >> (18 - 6 * k) & 63) as usize] as char
            } else {
                '='
            });
        }
    }
    s
}

/// A glTF of `images.len()` textured quads, primitive k with material k, whose texture shows
/// image k (each a JSON image object: a `uri` or a `bufferView` into `views`, the bytes of
/// buffer views 3, 4, … appended to the geometry's buffer).
fn textured(images: Vec<Value>, views: &[&[u8]]) -> Vec<u8> {
    let mut bin = Vec::new();
    for v in [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ] {
        v.iter()
            .for_each(|c| bin.extend_from_slice(&c.to_le_bytes()));
    }
    for v in [[0.0f32, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]] {
        v.iter()
            .for_each(|c| bin.extend_from_slice(&c.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3, 0] {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    let mut buffer_views = vec![
        json!({"buffer": 0, "byteOffset": 0, "byteLength": 48}),
        json!({"buffer": 0, "byteOffset": 48, "byteLength": 32}),
        json!({"buffer": 0, "byteOffset": 80, "byteLength": 12}),
    ];
    for bytes in views {
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        buffer_views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()}));
        bin.extend_from_slice(bytes);
    }
    let n = images.len();
    let doc = json!({
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": (0..n).map(|k| json!({
            "attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": k
        })).collect::<Vec<_>>()}],
        "materials": (0..n).map(|k| json!({
            "pbrMetallicRoughness": {"baseColorTexture": {"index": k}}
        })).collect::<Vec<_>>(),
        "textures": (0..n).map(|k| json!({"source": k})).collect::<Vec<_>>(),
        "images": images,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ],
        "bufferViews": buffer_views,
        "buffers": [{"byteLength": bin.len(),
                     "uri": format!("data:application/octet-stream;base64,{}", base64(&bin))}]
    });
    serde_json::to_vec(&doc).unwrap()
}

/// A `w × h` RGB PNG of one colour, through the `image` crate's encoder (black compresses
/// about 1000:1, so 8192 × 8192 is a 200 kB file).
fn png(w: u32, h: u32, rgb: [u8; 3]) -> Vec<u8> {
    use image::ImageEncoder;
    let pixels: Vec<u8> = if rgb == [0; 3] {
        vec![0; w as usize * h as usize * 3]
    } else {
        rgb.repeat(w as usize * h as usize)
    };
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new_with_quality(
        &mut out,
        image::codecs::png::CompressionType::Fast,
        image::codecs::png::FilterType::NoFilter,
    )
    .write_image(&pixels, w, h, image::ExtendedColorType::Rgb8)
    .unwrap();
    out
}

#[test]
fn materials_sharing_an_image_decode_it_once() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let red = png(2, 2, [255, 0, 0]);
    let blue = png(2, 2, [0, 0, 255]);
    std::fs::write(dir.join("red.png"), &red).unwrap();
    std::fs::write(dir.join("copy of red.png"), &red).unwrap();
    std::fs::write(dir.join("blue.png"), &blue).unwrap();
    // Eight materials, eight image indices, two distinct images: the same file twice, a copy of
    // it, its bytes in a data: URI and in two buffer views; and a different one.
    let images = vec![
        json!({"uri": "red.png"}),
        json!({"uri": "red.png"}),
        json!({"uri": "copy%20of%20red.png"}),
        json!({"uri": format!("data:image/png;base64,{}", base64(&red))}),
        json!({"bufferView": 3, "mimeType": "image/png"}),
        json!({"bufferView": 4, "mimeType": "image/png"}),
        json!({"uri": "blue.png"}),
        json!({"uri": "red.png"}),
    ];
    let path = dir.join("shared.gltf");
    std::fs::write(&path, textured(images, &[&red, &red])).unwrap();
    let scene = Scene::load(&path).unwrap();
    assert_eq!(scene.textures.len(), 2, "two distinct images");
    let used: Vec<Option<usize>> = scene.materials.iter().map(|m| m.texture).collect();
    let red_t = used[0];
    assert_eq!(
        used,
        vec![red_t, red_t, red_t, red_t, red_t, red_t, used[6], red_t]
    );
    assert_ne!(used[6], red_t);
    let texel = |t: Option<usize>| scene.textures[t.unwrap()].texels()[0];
    assert_eq!(texel(red_t), glam::Vec3::new(1.0, 0.0, 0.0));
    assert_eq!(texel(used[6]), glam::Vec3::new(0.0, 0.0, 1.0));
}

#[test]
fn eight_materials_sharing_a_png_that_decodes_to_a_gigabyte_render_within_4_gb() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // 200 kB of PNG, 8192 × 8192 texels: about 1.1 GB once decoded with its pyramid. Eight
    // image indices name it; decoded once, it fits in 4 GB of address space with the render.
    let big = png(8192, 8192, [0; 3]);
    assert!(big.len() < 1_000_000, "{} bytes", big.len());
    std::fs::write(dir.join("big.png"), &big).unwrap();
    let images = (0..8).map(|_| json!({"uri": "big.png"})).collect();
    std::fs::write(dir.join("eight.gltf"), textured(images, &[])).unwrap();
    let s = spec(dir, "eight", Some("eight.gltf"), None, "");
    let o = render_limited(&s, FOUR_GB);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(dir.join("out/frame_0000.exr").exists());
}

/// Makes a FIFO at `path` with mkfifo(1) (coreutils; required).
fn mkfifo(path: &Path) {
    let ok = std::process::Command::new("mkfifo")
        .arg(path)
        .status()
        .expect("mkfifo (coreutils) is needed")
        .success();
    assert!(ok, "mkfifo {}", path.display());
}

/// Ends a thread writing to the FIFO `fifo`: while it waits for a reader, opens the FIFO for
/// reading without blocking (Linux's O_NONBLOCK), which lets it write and end.
fn release(fifo: &Path, writer: std::thread::JoinHandle<()>) {
    use std::os::unix::fs::OpenOptionsExt;
    const O_NONBLOCK: i32 = 0o4000;
    while !writer.is_finished() {
        let reader = std::fs::OpenOptions::new()
            .read(true)
            .custom_flags(O_NONBLOCK)
            .open(fifo);
        std::thread::sleep(std::time::Duration::from_millis(10));
        drop(reader);
    }
    writer.join().unwrap();
}

#[test]
fn devices_and_fifos_are_refused_unread() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let fifo = dir.join("fifo");
    mkfifo(&fifo);
    std::os::unix::fs::symlink("/dev/zero", dir.join("zero.hdr")).unwrap();
    std::os::unix::fs::symlink(&fifo, dir.join("fifo.hdr")).unwrap();
    std::os::unix::fs::symlink(&fifo, dir.join("fifo.gltf")).unwrap();
    // A triangle whose buffer (or texture) is a device or the FIFO.
    let buffer_at = |uri: &str| {
        json!({
            "asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                           "min": [0, 0, 0], "max": [1, 1, 0]}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}],
            "buffers": [{"byteLength": 36, "uri": uri}]
        })
    };
    std::fs::write(
        dir.join("zero.gltf"),
        buffer_at("file:///dev/zero").to_string(),
    )
    .unwrap();
    std::fs::write(dir.join("fifobuf.gltf"), buffer_at("fifo").to_string()).unwrap();
    std::fs::write(
        dir.join("fifoimage.gltf"),
        textured(vec![json!({"uri": "fifo"})], &[]),
    )
    .unwrap();
    std::fs::write(
        dir.join("zeroimage.gltf"),
        textured(vec![json!({"uri": "file:///dev/zero"})], &[]),
    )
    .unwrap();
    // (what, scene file, map file, what the message names)
    type Case<'a> = (&'a str, Option<&'a str>, Option<&'a str>, &'a [&'a str]);
    let cases: [Case; 7] = [
        (
            "/dev/zero as a buffer",
            Some("zero.gltf"),
            None,
            &[
                "zero.gltf",
                "buffer 0",
                "'/dev/zero' is a character device, not a regular file",
            ],
        ),
        (
            "a FIFO as a buffer",
            Some("fifobuf.gltf"),
            None,
            &["fifobuf.gltf", "buffer 0", "is a FIFO, not a regular file"],
        ),
        (
            "/dev/zero as an image",
            Some("zeroimage.gltf"),
            None,
            &[
                "zeroimage.gltf",
                "image 0",
                "is a character device, not a regular file",
            ],
        ),
        (
            "a FIFO as an image",
            Some("fifoimage.gltf"),
            None,
            &["fifoimage.gltf", "image 0", "is a FIFO, not a regular file"],
        ),
        (
            "a FIFO as the scene",
            Some("fifo.gltf"),
            None,
            &["fifo.gltf", "is a FIFO, not a regular file"],
        ),
        (
            "/dev/zero as the map",
            None,
            Some("zero.hdr"),
            &["zero.hdr", "is a character device, not a regular file"],
        ),
        (
            "a FIFO as the map",
            None,
            Some("fifo.hdr"),
            &["fifo.hdr", "is a FIFO, not a regular file"],
        ),
    ];
    let mut failures = Failures::new();
    for (kind, scene, map, needles) in cases {
        failures.case(kind, || {
            let s = spec(dir, "case", scene, map, "");
            // A reader that opened the FIFO would block until a writer came: one comes, so a
            // wrong reader reads and goes on (and the case fails) instead of hanging.
            let writer = {
                let fifo = fifo.clone();
                std::thread::spawn(move || {
                    let _ = std::fs::write(&fifo, [0u8; 64]);
                })
            };
            let o = render_limited(&s, FOUR_GB);
            release(&fifo, writer);
            assert_refused(&o, 2, needles, &dir.join("out"));
        });
    }
    // The spec itself.
    failures.case("a FIFO as the spec", || {
        let writer = {
            let fifo = fifo.clone();
            std::thread::spawn(move || {
                let _ = std::fs::write(&fifo, b"[scene]\nbuiltin = \"shapes\"\n");
            })
        };
        let o = common::bin()
            .arg("render")
            .arg(&fifo)
            .args(["--no-report", "-q", "--out"])
            .arg(dir.join("out"))
            .output()
            .unwrap();
        release(&fifo, writer);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains("is a FIFO, not a regular file"), "{err}");
    });
    failures.assert_none();
}
