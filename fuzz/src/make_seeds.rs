//! Writes the seed corpora: `cargo run --release --bin make_seeds -- fuzz/seeds` (from the
//! repository root; it also reads `anims/` and, if present, the shared assets).

use std::io::Cursor;
use std::path::{Path, PathBuf};

use envshadow::envmap::EnvMap;
use envshadow::lights::{Light, LightSet, Sampler};
use glam::Vec3;
use image::ImageEncoder;

mod files;

fn write(dir: &Path, name: &str, bytes: &[u8]) {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join(name), bytes).unwrap();
}

fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                s.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

/// The JSON of a one-triangle glTF whose buffer is `uri` (None: the GLB chunk) and whose
/// texture is `image` (a JSON object: a uri or a bufferView).
fn gltf_json(uri: Option<&str>, image: &str, extra_views: &str, mode: u32) -> String {
    let buffer = match uri {
        Some(u) => format!(r#"{{"byteLength": 68, "uri": "{u}"}}"#),
        None => r#"{"byteLength": 68}"#.to_string(),
    };
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
 "nodes": [{{"children": [1], "rotation": [0, 0.7071068, 0, 0.7071068]}},
           {{"mesh": 0, "translation": [0, 1, 0], "scale": [2, 2, 2]}},
           {{"camera": 0, "translation": [0, 0, 5]}}],
 "cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.7, "znear": 0.1}}}}],
 "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 2}}, "indices": 1,
   "material": 0, "mode": {mode}}}]}}],
 "materials": [{{"pbrMetallicRoughness": {{"baseColorFactor": [0.8, 0.7, 0.6, 1],
   "baseColorTexture": {{"index": 0}}}}}}],
 "textures": [{{"source": 0}}], "images": [{image}],
 "accessors": [
  {{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
    "min": [0, 0, 0], "max": [1, 1, 0]}},
  {{"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}},
  {{"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"}},
  {{"componentType": 5126, "count": 3, "type": "VEC3",
    "sparse": {{"count": 1, "indices": {{"bufferView": 1, "componentType": 5123}},
               "values": {{"bufferView": 0}}}}}}],
 "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}},
                 {{"buffer": 0, "byteOffset": 36, "byteLength": 6}},
                 {{"buffer": 0, "byteOffset": 44, "byteLength": 24, "byteStride": 8}}{extra_views}],
 "buffers": [{buffer}]}}"#
    )
}

fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut json = json.as_bytes().to_vec();
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

fn gltf_seeds(dir: &Path, assets: &Path) {
    let buffer = files::triangle_buffer();
    let data_uri = format!("data:application/octet-stream;base64,{}", base64(&buffer));
    let png_uri = format!("data:image/png;base64,{}", base64(&files::texture_png()));
    write(
        dir,
        "external.gltf",
        gltf_json(Some("buffer.bin"), r#"{"uri": "texture.png"}"#, "", 4).as_bytes(),
    );
    write(
        dir,
        "embedded.gltf",
        gltf_json(
            Some(&data_uri),
            &format!(r#"{{"uri": "{png_uri}"}}"#),
            "",
            4,
        )
        .as_bytes(),
    );
    write(
        dir,
        "strip.gltf",
        gltf_json(Some(&data_uri), r#"{"uri": "texture.png"}"#, "", 5).as_bytes(),
    );
    write(
        dir,
        "fan.gltf",
        gltf_json(Some("buffer.bin"), r#"{"uri": "texture.png"}"#, "", 6).as_bytes(),
    );
    // GLB: the texture lives in the binary chunk after the triangle's 68 bytes.
    let (json, bin) = glb_with_png(&files::texture_png());
    write(dir, "triangle.glb", &glb(&json, &bin));
    if let Ok(b) = std::fs::read(assets.join("bunny_res4.glb")) {
        write(dir, "bunny_res4.glb", &b);
    }
    uri_seeds(dir);
    format_seeds(dir);
}

/// The triangle with its buffer and image named by each spelling URI resolution must refuse
/// or accept, in the folder `files::model_folder` writes (`fuzz.gltf` in `ROOT/model/`, a
/// triangle buffer at `ROOT/outside.bin`, links in and out): a parent folder plainly and
/// percent-encoded, an absolute path, `file://` URIs, a link out, another scheme; a link in,
/// a percent-encoded name and a path that leaves the folder and comes back.
/// tests/it/fuzz_regressions.rs checks which load.
fn uri_seeds(dir: &Path) {
    for (name, buffer, image) in [
        ("uri-parent.gltf", "../outside.bin", "texture.png"),
        (
            "uri-percent-parent.gltf",
            "%2e%2e/outside.bin",
            "texture.png",
        ),
        ("uri-absolute.gltf", "/etc/passwd", "texture.png"),
        ("uri-file-scheme.gltf", "file:///etc/passwd", "texture.png"),
        (
            "uri-file-host.gltf",
            "file://host/etc/passwd",
            "texture.png",
        ),
        ("uri-link-out.gltf", "outside-link.bin", "texture.png"),
        (
            "uri-http.gltf",
            "http://example.com/buffer.bin",
            "texture.png",
        ),
        (
            "uri-image-file-scheme.gltf",
            "buffer.bin",
            "file:///etc/passwd",
        ),
        (
            "uri-image-parent.gltf",
            "buffer.bin",
            "%2E%2E/%2E%2E/etc/passwd",
        ),
        ("uri-link-in.gltf", "inside-link.bin", "texture.png"),
        ("uri-percent-name.gltf", "%62uffer%2Ebin", "texture%2epng"),
        ("uri-back-in.gltf", "../model/buffer.bin", "./texture.png"),
    ] {
        let image = format!(r#"{{"uri": "{image}"}}"#);
        write(dir, name, gltf_json(Some(buffer), &image, "", 4).as_bytes());
    }
}

/// The format test files of issue 39 (tests/data/formats/: quantized, Draco, unlit,
/// spec-gloss, KTX2, meshopt, glTF 1.0, a page saved as GLB), as `issue39-NAME`.
fn format_seeds(dir: &Path) {
    let formats = Path::new("tests/data/formats");
    let entries = std::fs::read_dir(formats).expect("run from the repository root");
    for p in entries.map(|e| e.unwrap().path()) {
        if p.extension().is_some_and(|e| e == "gltf" || e == "glb") {
            let name = p.file_name().unwrap().to_str().unwrap();
            write(dir, &format!("issue39-{name}"), &std::fs::read(&p).unwrap());
        }
    }
}

/// The triangle's glTF JSON and binary chunk with `png` in the chunk after the triangle's
/// 68 bytes, as its texture.
fn glb_with_png(png: &[u8]) -> (String, Vec<u8>) {
    let mut bin = files::triangle_buffer();
    bin.extend_from_slice(png);
    let json = gltf_json(
        None,
        r#"{"bufferView": 3, "mimeType": "image/png"}"#,
        &format!(
            r#", {{"buffer": 0, "byteOffset": 68, "byteLength": {}}}"#,
            png.len()
        ),
        4,
    )
    .replace(
        r#""byteLength": 68}"#,
        &format!(r#""byteLength": {}}}"#, bin.len()),
    );
    (json, bin)
}

/// Seeds over libFuzzer's usual 64 kB, where images decode to hundreds of megabytes: a GLB
/// whose eight materials share one 4096 × 4096 PNG (about 100 kB) in its binary chunk. Named
/// `large-*`, not committed.
fn large_gltf_seeds(dir: &Path) {
    let side = 4096u32;
    let pixels: Vec<u8> = (0..side * side)
        .flat_map(|i| {
            let (x, y) = (i % side, i / side);
            [(x / 64) as u8, (y / 64) as u8, ((x ^ y) / 512) as u8]
        })
        .collect();
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(&pixels, side, side, image::ExtendedColorType::Rgb8)
        .unwrap();
    let (json, bin) = glb_with_png(&png);
    // Eight materials, each with its own texture and image entry, all the same bytes.
    let materials: Vec<String> = (0..8)
        .map(|k| format!(r#"{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": {k}}}}}}}"#))
        .collect();
    let primitives: Vec<String> = (0..8)
        .map(|k| format!(r#"{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 2}}, "indices": 1, "material": {k}}}"#))
        .collect();
    let json = json
        .replace(
            r#""textures": [{"source": 0}], "images": [{"bufferView": 3, "mimeType": "image/png"}]"#,
            &format!(
                r#""textures": [{}], "images": [{}]"#,
                (0..8).map(|k| format!(r#"{{"source": {k}}}"#)).collect::<Vec<_>>().join(", "),
                vec![r#"{"bufferView": 3, "mimeType": "image/png"}"#; 8].join(", ")
            ),
        )
        .replacen(
            r#""materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.7, 0.6, 1],
   "baseColorTexture": {"index": 0}}}]"#,
            &format!(r#""materials": [{}]"#, materials.join(", ")),
            1,
        )
        .replacen(
            r#""primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 2}, "indices": 1,
   "material": 0, "mode": 4}]"#,
            &format!(r#""primitives": [{}]"#, primitives.join(", ")),
            1,
        );
    write(dir, "large-shared-texture.glb", &glb(&json, &bin));
}

/// Maps over 64 kB: 4096 × 2048 texels, run-length coded (about 0.5 MB), and a 16384 × 16384
/// header whose file holds a tenth of its scanlines. Named `large-*`, not committed.
fn large_hdr_seeds(dir: &Path) {
    let scanlines = |w: usize, rows: usize| {
        let mut line = vec![2u8, 2, (w >> 8) as u8, w as u8];
        for value in [120u8, 130, 140, 129] {
            let mut left = w;
            while left > 0 {
                let n = left.min(127);
                line.extend_from_slice(&[128 + n as u8, value]);
                left -= n;
            }
        }
        line.repeat(rows)
    };
    for (name, w, h, rows) in [
        ("large-4096x2048.hdr", 4096, 2048, 2048),
        ("large-16384x16384-partial.hdr", 16384, 16384, 1638),
    ] {
        let mut out = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n").into_bytes();
        out.extend_from_slice(&scanlines(w, rows));
        write(dir, name, &out);
    }
}

fn exr_seeds(dir: &Path) {
    use exr::prelude::*;
    let compressions = [
        ("none", Compression::Uncompressed),
        ("rle", Compression::RLE),
        ("zip1", Compression::ZIP1),
        ("zip16", Compression::ZIP16),
        ("piz", Compression::PIZ),
        ("pxr24", Compression::PXR24),
        ("b44", Compression::B44),
        ("b44a", Compression::B44A),
    ];
    for (name, compression) in compressions {
        for (blocks_name, blocks) in [
            ("lines", Blocks::ScanLines),
            ("tiles", Blocks::Tiles(Vec2(4, 4))),
        ] {
            let encoding = Encoding {
                compression,
                blocks,
                line_order: LineOrder::Increasing,
            };
            let mut out = Cursor::new(Vec::new());
            if name.starts_with('b') || name == "piz" {
                // Half channels: what B44 and PIZ are made for.
                let pixels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
                    (
                        f16::from_f32(x as f32 * 0.25),
                        f16::from_f32(y as f32 * 0.5),
                        f16::from_f32(1.0),
                    )
                });
                let layer = Layer::new((8, 4), LayerAttributes::named("rgb"), encoding, pixels);
                Image::from_layer(layer)
                    .write()
                    .to_buffered(&mut out)
                    .unwrap();
            } else {
                let pixels = SpecificChannels::rgba(|Vec2(x, y): Vec2<usize>| {
                    (x as f32 * 0.25, y as f32 * 0.5, 2.0f32, 1.0f32)
                });
                let layer = Layer::new((8, 4), LayerAttributes::named("rgba"), encoding, pixels);
                Image::from_layer(layer)
                    .write()
                    .to_buffered(&mut out)
                    .unwrap();
            }
            write(dir, &format!("{name}_{blocks_name}.exr"), &out.into_inner());
        }
    }
}

fn hdr_seeds(dir: &Path, assets: &Path) {
    for (w, h) in [(4usize, 2usize), (16, 8), (40, 3)] {
        let pixels: Vec<image::Rgb<f32>> = (0..w * h)
            .map(|i| image::Rgb([i as f32 * 0.1, (i % 7) as f32, 0.5]))
            .collect();
        let mut out = Vec::new();
        image::codecs::hdr::HdrEncoder::new(&mut out)
            .encode(&pixels, w, h)
            .unwrap();
        write(dir, &format!("map_{w}x{h}.hdr"), &out);
    }
    if let Ok(b) = std::fs::read(assets.join("grace.hdr")) {
        write(dir, "grace.hdr", &b);
    }
}

fn lights_seeds(dir: &Path) {
    let sky = EnvMap::builtin_sky();
    let tmp = std::env::temp_dir().join(format!("envshadow-seeds-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let mut sets = Vec::new();
    for (n, sampler) in [
        (1, Sampler::Sis),
        (6, Sampler::Sis),
        (12, Sampler::MedianCut),
    ] {
        sets.push((
            format!("{}_{n}.json", sampler.name()),
            LightSet::build(&sky, n, sampler).unwrap(),
        ));
    }
    let given = LightSet::from_lights(vec![
        Light {
            dir: Vec3::Y,
            energy: Vec3::ONE,
            solid_angle: 1.0,
        },
        Light {
            dir: Vec3::new(0.6, 0.0, 0.8),
            energy: Vec3::new(0.5, 0.25, 0.0),
            solid_angle: 2.0,
        },
    ]);
    sets.push(("given_2.json".to_string(), given));
    for (name, set) in sets {
        let p = tmp.join(&name);
        set.write_json(&p).unwrap();
        write(dir, &name, &std::fs::read(&p).unwrap());
    }
    let _ = std::fs::remove_dir_all(&tmp);
}

/// Spinning specs for the posed scene: pivots near and far, turns small and large, one frame
/// and many.
fn posed_seeds(dir: &Path) {
    let specs = [
        (
            "spin.toml",
            "[motion]\nkind = \"spin\"\nframes = 12\ndegrees_per_frame = 3.0\n",
        ),
        (
            "pivot.toml",
            "[motion]\nkind = \"spin\"\nframes = 5\nturn_degrees = 270.0\npivot = [1.0, 0.5, -2.0]\n",
        ),
        (
            "far-pivot.toml",
            "[motion]\nkind = \"spin\"\nframes = 3\ndegrees_per_frame = 90.0\npivot = [1e6, 0.0, 1e6]\n",
        ),
        ("one-frame.toml", "[motion]\nkind = \"spin\"\nframes = 1\n"),
        (
            "camera.toml",
            "[camera]\nposition = [0.0, 2.0, 5.0]\ntarget = [0.3, 0.2, 0.0]\n[motion]\nkind = \"spin\"\nframes = 1000\ndegrees_per_frame = 17.5\n",
        ),
    ];
    for (name, body) in specs {
        write(
            dir,
            name,
            format!("[scene]\nbuiltin = \"shapes\"\n{body}").as_bytes(),
        );
    }
}

fn spec_seeds(dir: &Path) {
    for entry in std::fs::read_dir("anims").expect("run from the repository root") {
        let p = entry.unwrap().path();
        if p.extension().is_some_and(|e| e == "toml") {
            write(
                dir,
                p.file_name().unwrap().to_str().unwrap(),
                &std::fs::read(&p).unwrap(),
            );
        }
    }
    write(
        dir,
        "spin.toml",
        b"name = \"s\"\n[scene]\nbuiltin = \"shapes\"\n[camera]\nposition = [0.0, 2.0, 5.0]\ntarget = [0.0, 0.5, 0.0]\nup = [0.0, 1.0, 0.0]\n[motion]\nkind = \"spin\"\nframes = 12\ndegrees_per_frame = 3.0\npivot = [0.0, 0.0, 0.0]\n[render]\nwidth = 64\nheight = 48\nmethod = \"brute\"\nvalidate = true\ntile = 0\n",
    );
    write(
        dir,
        "file.toml",
        b"[scene]\nfile = \"scene.glb\"\n[environment]\nfile = \"map.hdr\"\nrotation = 90.0\nintensity = 2.0\n[lights]\ncount = 50\nsampler = \"median-cut\"\n[camera]\nfrom_file = true\n[motion]\nkind = \"none\"\n[output]\ndir = \"out/x\"\n",
    );
}

fn main() {
    let root = PathBuf::from(std::env::args().nth(1).unwrap_or("fuzz/seeds".into()));
    let assets = PathBuf::from(
        std::env::var("ENVSHADOW_ASSETS").unwrap_or_else(|_| "../shared/assets".into()),
    );
    spec_seeds(&root.join("anim_spec"));
    posed_seeds(&root.join("posed_scene"));
    gltf_seeds(&root.join("gltf"), &assets);
    large_gltf_seeds(&root.join("gltf"));
    exr_seeds(&root.join("envmap_exr"));
    hdr_seeds(&root.join("envmap_hdr"), &assets);
    large_hdr_seeds(&root.join("envmap_hdr"));
    lights_seeds(&root.join("lights_json"));
    println!("seeds written under {}", root.display());
}
