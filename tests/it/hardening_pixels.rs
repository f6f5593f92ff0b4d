//! Issue 39, item 5: every pixel written is finite, and non-negative where it must be. Inputs
//! that would make one otherwise (factors outside glTF's ranges, a Radiance map at the
//! format's largest value, lights brighter than any sum can hold) are clamped at load with a
//! warning naming the key or counting the texels; the film is checked once more before it is
//! written.

use std::fs;
use std::path::Path;
use std::process::Output;

use serde_json::json;

use crate::common::{self, Gltf};

/// A floor quad and an upright quad in front of the camera, both with `material`, as a
/// `.gltf` with an embedded buffer written to `path`; `extensions_used` as the file declares.
fn two_quads(path: &Path, material: serde_json::Value, extensions_used: &[&str]) {
    let mut g = Gltf::default();
    #[rustfmt::skip]
    let p = g.floats("VEC3", &[
        -2.0, 0.0, -2.0, 2.0, 0.0, -2.0, 2.0, 0.0, 2.0, -2.0, 0.0, 2.0,
        -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.5, 0.0, -1.0, 1.5, 0.0,
    ]);
    let i = g.indices(&[0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7]);
    let rest = json!({
        "extensionsUsed": extensions_used,
        "materials": [material],
        "meshes": [{"primitives": [{"attributes": {"POSITION": p}, "indices": i, "material": 0}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    });
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        common::base64(&g.bin)
    );
    fs::write(path, serde_json::to_vec(&g.json(rest, Some(&uri))).unwrap()).unwrap();
}

/// A 16×8 Radiance map every texel of which is (255, 255, 255, 255): 1.7e38 per channel.
fn brightest_hdr(path: &Path) {
    let mut bytes = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8 +X 16\n".to_vec();
    bytes.extend(std::iter::repeat_n(255u8, 16 * 8 * 4));
    fs::write(path, bytes).unwrap();
}

fn render(model: &Path, map: &Path, out: &Path, extra: &[&str]) -> Output {
    common::bin()
        .arg("render")
        .arg(model)
        .arg("--env")
        .arg(map)
        .args([
            "--width", "48", "--height", "32", "--lights", "8", "--spp", "1",
        ])
        .args([
            "--frames",
            "0..1",
            "--no-report",
            "--ground",
            "none",
            "--out",
        ])
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

/// Every value of every channel of `exr` is finite; the beauty and alpha ≥ 0. Returns the
/// largest beauty value.
fn assert_finite_frame(exr: &Path) -> f32 {
    let frame = envshadow::output::exr::read_frame(exr).unwrap();
    let mut brightest = 0.0f32;
    for (name, values) in &frame.channels {
        let bad = values.iter().filter(|v| !v.is_finite()).count();
        assert_eq!(
            bad,
            0,
            "{}: channel {name}: {bad} non-finite values",
            exr.display()
        );
        if ["R", "G", "B", "A"].contains(&name.as_str()) {
            let negative = values.iter().filter(|v| **v < 0.0).count();
            assert_eq!(negative, 0, "channel {name}: {negative} negative values");
            brightest = values.iter().fold(brightest, |m, v| m.max(*v));
        }
    }
    brightest
}

/// Issue 39, item 5: `baseColorFactor [-5, 1e38, 0.5]`, `emissiveStrength 1e38` and a map
/// of (255,255,255,255) texels once wrote infinite pixels with exit 0. Now each is clamped
/// with a warning naming the key or counting the texels, and no value of the frame, float or
/// half, is infinite, NaN, or (in the beauty) negative.
#[test]
fn hostile_materials_and_maps_write_only_finite_pixels() {
    let tmp = tempfile::tempdir().unwrap();
    let model = tmp.path().join("hostile.gltf");
    two_quads(
        &model,
        json!({
            "pbrMetallicRoughness": {"baseColorFactor": [-5.0, 1e38, 0.5, 1.0], "roughnessFactor": -3.0},
            "emissiveFactor": [1.0, 1.0, 1.0],
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 1e38}},
        }),
        &["KHR_materials_emissive_strength"],
    );
    let map = tmp.path().join("brightest.hdr");
    brightest_hdr(&map);
    for half in ["--half=false", "--half=true"] {
        let out = tmp.path().join(half.trim_start_matches("--"));
        let o = render(&model, &map, &out, &[half]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{half}: {err}");
        for key in [
            "baseColorFactor[0] -5 clamped to 0",
            "baseColorFactor[1] 100000000000000000000000000000000000000 clamped to 1",
            "roughnessFactor -3 clamped to 0",
            "emissiveFactor × emissiveStrength",
            "128 texels brighter than 1e12 clamped to it",
        ] {
            assert!(err.contains(key), "{half}: no warning with {key:?}: {err}");
        }
        let brightest = assert_finite_frame(&out.join("frame_0000.exr"));
        assert!(
            brightest > 1e3,
            "{half}: the clamped inputs still shine: {brightest}"
        );
    }
}

/// Issue 39, item 5: a point light whose intensity is finite but whose sum with the others
/// would not be is clamped with a warning naming it.
#[test]
fn lights_too_bright_for_finite_sums_are_clamped_with_a_warning() {
    let tmp = tempfile::tempdir().unwrap();
    let model = tmp.path().join("lamp.gltf");
    two_quads(&model, json!({}), &["KHR_lights_punctual"]);
    let mut doc: serde_json::Value = serde_json::from_slice(&fs::read(&model).unwrap()).unwrap();
    doc["extensions"] = json!({"KHR_lights_punctual": {"lights": [
        {"type": "point", "intensity": 3e38, "name": "sun in a jar"}]}});
    doc["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!({"translation": [0.0, 1.0, 1.0], "extensions": {"KHR_lights_punctual": {"light": 0}}}));
    doc["scenes"][0]["nodes"] = json!([0, 1]);
    fs::write(&model, serde_json::to_vec(&doc).unwrap()).unwrap();
    let map = tmp.path().join("brightest.hdr");
    brightest_hdr(&map);
    let out = tmp.path().join("out");
    let o = render(&model, &map, &out, &["--scene-lights=true"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("light 0 ('sun in a jar'): intensity 300000000000000000000000000000000000000"),
        "{err}"
    );
    assert_finite_frame(&out.join("frame_0000.exr"));
}

/// The film's last guard: a non-finite or negative beauty value is clamped and counted, a
/// half channel is kept within half's range, a depth stays as it was.
#[test]
fn the_film_guard_clamps_and_counts_what_is_not_finite() {
    use envshadow::film::{Channel, Film, Holds};
    let mut film = Film::new(2, 2, Holds::default());
    film.set(Channel::R, 0, f32::NAN);
    film.set(Channel::G, 1, f32::INFINITY);
    film.set(Channel::B, 2, -1.0);
    film.set(Channel::R, 3, 1e6);
    film.set(Channel::Z, 3, 1e10);
    let mut full = film.clone();
    assert_eq!(full.guard_finite(false), 3);
    assert_eq!(full.beauty(0), [0.0, 0.0, 0.0]);
    assert_eq!(full.beauty(1), [0.0, f32::MAX, 0.0]);
    assert_eq!(full.beauty(2), [0.0, 0.0, 0.0]);
    assert_eq!(full.beauty(3), [1e6, 0.0, 0.0]);
    assert_eq!(film.guard_finite(true), 4);
    assert_eq!(film.beauty(1), [0.0, 65504.0, 0.0]);
    assert_eq!(film.beauty(3), [65504.0, 0.0, 0.0]);
    assert_eq!(film.get(Channel::Z, 3), 1e10, "depth is a float channel");
}
