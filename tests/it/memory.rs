//! Issue 20, item 6: memory is bounded by an estimate that covers the inputs. A scene's mesh
//! instances, its textures and the environment map are counted from their headers and refused
//! before anything large is read or decoded — over the 16 GB budget with exit code 2 and the
//! estimate, or, within it, by a system that cannot give that much with exit code 1 and the
//! estimate, never an abort. Each distinct image is decoded once; only regular files are read.
//!
//! The memory bombs are small files made here (a grid mesh's 2.4 MB buffer placed by 256 nodes,
//! PNG and HDR headers declaring huge sizes), and the binary runs under `prlimit --as=4G`: a
//! refusal there happened before any large allocation.

use std::path::{Path, PathBuf};
use std::process::Output;

use envshadow::anim::{AnimFlags, Animation, EnvSource, SceneSource};
use envshadow::envmap::EnvMap;
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

/// Writes `name.gltf` and `name.bin` in `dir`: a grid of `side × side` quads in the unit square
/// (2 side² triangles, (side + 1)² vertices, u32 indices) placed by `instances` nodes in a row.
fn instanced(dir: &Path, name: &str, side: u32, instances: usize) -> PathBuf {
    let mut bin = Vec::new();
    let n = side + 1;
    for j in 0..n {
        for i in 0..n {
            for c in [i as f32 / side as f32, 0.0, j as f32 / side as f32] {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    let positions = bin.len();
    for j in 0..side {
        for i in 0..side {
            let a = j * n + i;
            for v in [a, a + n, a + 1, a + 1, a + n, a + n + 1] {
                bin.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    std::fs::write(dir.join(format!("{name}.bin")), &bin).unwrap();
    let doc = json!({
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": (0..instances).collect::<Vec<_>>()}],
        "nodes": (0..instances)
            .map(|k| json!({"mesh": 0, "translation": [k as f32 * 1.1, 0.0, 0.0]}))
            .collect::<Vec<_>>(),
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n * n, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 0, 1]},
            {"bufferView": 1, "componentType": 5125, "count": 6 * side * side, "type": "SCALAR"}
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": positions},
            {"buffer": 0, "byteOffset": positions, "byteLength": bin.len() - positions}
        ],
        "buffers": [{"byteLength": bin.len(), "uri": format!("{name}.bin")}]
    });
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
    path
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
                     "uri": format!("data:application/octet-stream;base64,{}", common::base64(&bin))}]
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

/// The CRC-32 of PNG chunks (ISO 3309).
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// A PNG that is only a header: it declares `w × h` RGB texels and holds none (an empty IDAT).
fn png_header(w: u32, h: u32) -> Vec<u8> {
    let chunk = |kind: &[u8], data: &[u8]| {
        let mut c = (data.len() as u32).to_be_bytes().to_vec();
        let body = [kind, data].concat();
        c.extend_from_slice(&body);
        c.extend_from_slice(&crc32(&body).to_be_bytes());
        c
    };
    let mut ihdr = w.to_be_bytes().to_vec();
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
    [
        b"\x89PNG\r\n\x1a\n".to_vec(),
        chunk(b"IHDR", &ihdr),
        chunk(b"IDAT", &[]),
        chunk(b"IEND", &[]),
    ]
    .concat()
}

/// A Radiance HDR declaring `w × h` texels followed by `rows` run-length scanlines of one grey.
fn hdr(w: u32, h: u32, rows: u32) -> Vec<u8> {
    let mut out = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n").into_bytes();
    let mut line = vec![2, 2, (w >> 8) as u8, w as u8];
    for value in [128u8, 128, 128, 129] {
        let mut left = w;
        while left > 0 {
            let n = left.min(127);
            line.extend_from_slice(&[128 + n as u8, value]);
            left -= n;
        }
    }
    for _ in 0..rows {
        out.extend_from_slice(&line);
    }
    out
}

#[test]
fn a_mesh_instanced_past_the_budget_is_refused_before_its_buffer_is_read() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // One 131,072-triangle mesh (a 2.4 MB buffer) placed by 256 nodes: 33.6 M triangles. A
    // spin poses the scene and builds its BVH for each of the two frames in flight.
    instanced(dir, "instanced", 256, 256);
    let s = spec(
        dir,
        "spin",
        Some("instanced.gltf"),
        None,
        "[motion]\nkind = \"spin\"\nframes = 4\n",
    );
    let o = render_limited(&s, FOUR_GB);
    assert_refused(
        &o,
        2,
        &[
            "instanced.gltf",
            "the render would need about",
            "GB of memory, more than the 16.0 GB allowed",
            "33.6 M triangles in 256 mesh instances",
            "a posed copy for each of 2 frames",
            "BVH",
        ],
        &dir.join("out"),
    );
}

#[test]
fn a_mesh_instanced_past_what_the_system_gives_is_refused_by_it_not_aborted() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // The same 256 instances, the camera orbiting: one BVH, within the budget, but not within
    // 4 GB of address space. The system is asked for the estimate before anything is loaded.
    instanced(dir, "instanced", 256, 256);
    let s = spec(dir, "orbit", Some("instanced.gltf"), None, "");
    let o = render_limited(&s, FOUR_GB);
    assert_refused(
        &o,
        1,
        &[
            "instanced.gltf",
            "the system refused",
            "GB of memory for the render",
            "33.6 M triangles in 256 mesh instances",
            "BVH",
        ],
        &dir.join("out"),
    );
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
        json!({"uri": format!("data:image/png;base64,{}", common::base64(&red))}),
        json!({"bufferView": 3, "mimeType": "image/png"}),
        json!({"bufferView": 4, "mimeType": "image/png"}),
        json!({"uri": "blue.png"}),
        json!({"uri": "red.png"}),
    ];
    let path = dir.join("shared.gltf");
    std::fs::write(&path, textured(images, &[&red, &red])).unwrap();
    let scene = Scene::load(&path).unwrap();
    assert_eq!(scene.textures.len(), 2, "two distinct images");
    let used: Vec<Option<usize>> = scene
        .materials
        .iter()
        .map(|m| m.base_color_texture.map(|s| s.texture))
        .collect();
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

#[test]
fn images_declaring_huge_sizes_are_counted_before_any_is_decoded() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut failures = Failures::new();
    // PNG headers of about 8192 × 8192 texels each (sizes differ, so the files differ), with no
    // pixels at all: the estimate is made from the headers, before the first decode would
    // find the data missing.
    for (n, code, needles) in [
        // Eight: 8.6 GB of textures, within the budget but not within 4 GB.
        (
            8,
            1,
            [
                "the system refused",
                "textures 8.6 GB (8 images, 536.6 M texels)",
            ],
        ),
        // Sixteen: 17.2 GB, past the budget.
        (
            16,
            2,
            [
                "would need about",
                "textures 17.2 GB (16 images, 1.1 G texels)",
            ],
        ),
    ] {
        failures.case(&format!("{n} images"), || {
            let case = dir.join(format!("case{n}"));
            std::fs::create_dir(&case).unwrap();
            let images = (0..n)
                .map(|k| {
                    let name = format!("header{k}.png");
                    std::fs::write(case.join(&name), png_header(8192, 8192 - k)).unwrap();
                    json!({ "uri": name })
                })
                .collect();
            std::fs::write(case.join("headers.gltf"), textured(images, &[])).unwrap();
            let s = spec(&case, "headers", Some("headers.gltf"), None, "");
            let o = render_limited(&s, FOUR_GB);
            let mut all = vec!["headers.gltf"];
            all.extend(needles);
            assert_refused(&o, code, &all, &case.join("out"));
        });
    }
    failures.assert_none();
}

#[test]
fn a_16384_square_hdr_is_refused_before_its_pixels_are_allocated() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut failures = Failures::new();
    // One scanline of data: more texels than the file can hold, refused with the estimate.
    let tiny = hdr(16384, 16384, 1);
    std::fs::write(dir.join("tiny.hdr"), &tiny).unwrap();
    failures.case("one scanline", || {
        let s = spec(dir, "tiny", None, Some("tiny.hdr"), "");
        let o = render_limited(&s, FOUR_GB);
        assert_refused(
            &o,
            2,
            &[
                "tiny.hdr",
                "16384×16384 texels",
                "9.7 GB of memory to load",
                &format!("more than a {}-byte file can hold", tiny.len()),
            ],
            &dir.join("out"),
        );
    });
    // 400 scanlines (420 kB): a file that could hold the map, which would take 9.7 GB.
    std::fs::write(dir.join("part.hdr"), hdr(16384, 16384, 400)).unwrap();
    failures.case("400 scanlines", || {
        let s = spec(dir, "part", None, Some("part.hdr"), "");
        let o = render_limited(&s, FOUR_GB);
        assert_refused(
            &o,
            1,
            &[
                "part.hdr",
                "the system refused",
                "map 3.2 GB (268.4 M texels)",
            ],
            &dir.join("out"),
        );
    });
    failures.assert_none();
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
                "'file:///dev/zero' is a character device, not a regular file",
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
            if kind.starts_with("/dev/zero as a") {
                // A URI outside the model's folder is refused before it is opened: allow
                // /dev, so that the device itself is what the loader refuses.
                let text = std::fs::read_to_string(&s).unwrap();
                let text = text.replacen("[scene]\n", "[scene]\nallow_folder = \"/dev\"\n", 1);
                std::fs::write(&s, text).unwrap();
            }
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

/// The estimate `Inputs::load` makes for `spec`: its budget with the map's header and the
/// scene counted, as a render counts them.
fn estimate_of(spec: &Path) -> u64 {
    let anim = Animation::load(spec, &AnimFlags::default()).unwrap();
    let mut budget = anim.budget();
    if let EnvSource::File(p) = &anim.env {
        let (texels, bytes) = EnvMap::declared_size(p).unwrap();
        budget.expect_map(texels, bytes);
    }
    if let SceneSource::File(p) = &anim.scene {
        Scene::load_within(p, &mut budget).unwrap();
    }
    if let EnvSource::File(p) = &anim.env {
        EnvMap::load_within(p, &mut budget).unwrap();
    }
    budget.estimate().total() as u64
}

#[test]
fn the_estimate_bounds_the_address_space_a_render_takes() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // Each input kind at a size where its own memory dominates, rendered under an address-space
    // limit of its estimate: were the estimate short, an allocation would fail there (or the
    // process abort). A 2 MB mesh placed 16 times (2.1 M triangles), orbited and spun; a
    // 4096 × 4096 texture; a 4096 × 2048 map reduced to lights by both samplers.
    instanced(dir, "grid", 256, 16);
    std::fs::write(dir.join("t.png"), png(4096, 4096, [40, 80, 120])).unwrap();
    std::fs::write(
        dir.join("t.gltf"),
        textured(vec![json!({"uri": "t.png"})], &[]),
    )
    .unwrap();
    std::fs::write(dir.join("m.hdr"), hdr(4096, 2048, 2048)).unwrap();
    let spin = "[motion]\nkind = \"spin\"\nframes = 2\n";
    let median_cut = "[lights]\ncount = 8\nsampler = \"median-cut\"\n";
    let cases = [
        ("orbit", Some("grid.gltf"), None, ""),
        ("spin", Some("grid.gltf"), None, spin),
        ("texture", Some("t.gltf"), None, ""),
        ("map sis", None, Some("m.hdr"), ""),
        ("map median-cut", None, Some("m.hdr"), median_cut),
    ];
    let mut failures = Failures::new();
    for (kind, scene, map, extra) in cases {
        failures.case(kind, || {
            let _ = std::fs::remove_dir_all(dir.join("out"));
            let s = spec(dir, "bound", scene, map, extra);
            let estimate = estimate_of(&s);
            let o = render_limited(&s, estimate);
            assert!(
                o.status.success(),
                "estimate {estimate}: {}",
                String::from_utf8_lossy(&o.stderr)
            );
        });
    }
    failures.assert_none();
}
