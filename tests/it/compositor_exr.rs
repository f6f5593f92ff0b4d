//! EXR frames a compositor opens as its own: Blender's multilayer names (`--exr-layout
//! blender`), read back with OpenImageIO, and Cryptomatte (`--cryptomatte`), read back and
//! checked against the specification: coverages that add up to the alpha and the share of
//! samples that hit, a manifest that names every object and material, IDs that are the
//! manifest's hashes, and the same bytes whatever the tiles and threads.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

use envshadow::cryptomatte::{self, TYPES};
use envshadow::output::exr::{ReadFrame, read_frame};
use envshadow::scene::Scene;
use exr::meta::attribute::{AttributeValue, Text};

use crate::common;

const SHAPES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/anims/shapes-turntable.toml");

/// Renders frame 0 of `spec` at 32 × 24 and 4 samples into `dir/name` with `flags`; returns
/// the frame's EXR.
fn render(spec: &str, dir: &Path, name: &str, flags: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let o = common::bin()
        .arg("render")
        .arg(spec)
        .args([
            "--width", "32", "--height", "24", "--frames", "0", "--spp", "4",
        ])
        .args(["-q", "--no-report", "--out"])
        .arg(&out)
        .args(flags)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    out.join("frame_0000.exr")
}

fn text_attr(frame: &ReadFrame, name: &str) -> Option<String> {
    match frame.attributes.other.get(&Text::from(name)) {
        Some(AttributeValue::Text(t)) => Some(t.to_string()),
        _ => None,
    }
}

/// A type's manifest, read from the header under its key: name → ID bits.
fn manifest(frame: &ReadFrame, type_name: &str) -> BTreeMap<String, u32> {
    let key = cryptomatte::key(type_name);
    let attr = |a: &str| {
        text_attr(frame, &format!("cryptomatte/{key}/{a}"))
            .unwrap_or_else(|| panic!("no cryptomatte/{key}/{a} for {type_name}"))
    };
    assert_eq!(attr("name"), type_name);
    assert_eq!(attr("hash"), "MurmurHash3_32");
    assert_eq!(attr("conversion"), "uint32_to_float32");
    let json: BTreeMap<String, String> = serde_json::from_str(&attr("manifest")).unwrap();
    json.into_iter()
        .map(|(n, hex)| (n, u32::from_str_radix(&hex, 16).unwrap()))
        .collect()
}

/// `oiiotool --info -v` on a frame rendered with `--exr-layout blender` shows Blender's
/// multilayer names (the passes Blender has under its names, ours under our own), the
/// attribute Blender's multilayer files carry, and Cryptomatte under Blender's view layer.
#[test]
fn openimageio_reads_blenders_multilayer_names() {
    if !common::require_tools(
        common::this_test!(),
        &["oiiotool"],
        "apt-get install openimageio-tools",
    ) {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let exr = render(
        SHAPES,
        tmp.path(),
        "blender",
        &["--exr-layout", "blender", "--cryptomatte"],
    );
    let o = Command::new("oiiotool")
        .args(["--info", "-v"])
        .arg(&exr)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let info = String::from_utf8_lossy(&o.stdout);
    let list = info
        .lines()
        .find_map(|l| l.trim().strip_prefix("channel list:"))
        .unwrap_or_else(|| panic!("no channel list:\n{info}"));
    let channels: BTreeSet<&str> = list
        .split(',')
        .filter_map(|c| c.split_whitespace().next())
        .collect();
    let mut want = vec![
        "ViewLayer.Combined.R",
        "ViewLayer.Combined.G",
        "ViewLayer.Combined.B",
        "ViewLayer.Combined.A",
        "ViewLayer.Depth.Z",
        "ViewLayer.Normal.X",
        "ViewLayer.Normal.Y",
        "ViewLayer.Normal.Z",
        "ViewLayer.DiffCol.R",
        "ViewLayer.DiffCol.G",
        "ViewLayer.DiffCol.B",
        "ViewLayer.ShadowRays.X",
        "ViewLayer.ShadowVisible.X",
        "ViewLayer.ShadowCoverage.X",
    ];
    let crypto: Vec<String> = ["CryptoObject", "CryptoMaterial"]
        .iter()
        .flat_map(|t| {
            (0..3).flat_map(move |l| {
                "RGBA"
                    .chars()
                    .map(move |c| format!("ViewLayer.{t}0{l}.{c}"))
            })
        })
        .collect();
    want.extend(crypto.iter().map(String::as_str));
    let want: BTreeSet<&str> = want.into_iter().collect();
    assert_eq!(channels, want, "channel list: {list}");
    // Every channel is `<ViewLayer>.<Pass>.<Channel>`, as Blender splits them.
    for c in &channels {
        assert_eq!(c.split('.').count(), 3, "{c}");
    }
    assert!(
        info.contains("BlenderMultiChannel: \"Blender V2.55.1 and newer\""),
        "{info}"
    );
    for t in TYPES {
        let name = format!("ViewLayer.{t}");
        let line = format!("cryptomatte/{}/name: \"{name}\"", cryptomatte::key(&name));
        assert!(info.contains(&line), "{line} not in:\n{info}");
    }
    // Our own layout is unchanged: no Blender names, no Blender attribute.
    let ours = read_frame(&render(SHAPES, tmp.path(), "ours", &[])).unwrap();
    let names: Vec<&str> = ours.channels.iter().map(|c| c.0.as_str()).collect();
    assert!(
        names.contains(&"R") && names.contains(&"albedo.R"),
        "{names:?}"
    );
    assert!(
        !names
            .iter()
            .any(|n| n.contains("ViewLayer") || n.contains("Crypto"))
    );
    assert!(text_attr(&ours, "BlenderMultiChannel").is_none());
}

/// Checks one Cryptomatte frame against the scene it rendered: the manifests name every
/// object (named part) and material, their hashes are the names' IDs, every ID a pixel holds
/// is in its manifest, the ranks come in falling coverage, and each pixel's coverages add up
/// to the share of its samples that hit (and, over a transparent background, its alpha).
fn check_mattes(frame: &ReadFrame, scene: &Scene, failures: &mut common::Failures, label: &str) {
    let objects: BTreeSet<String> = scene
        .parts
        .iter()
        .enumerate()
        .map(|(i, p)| p.object_name(i))
        .collect();
    let materials: BTreeSet<String> = scene.materials.iter().map(|m| m.name.clone()).collect();
    for (t, names) in TYPES.iter().zip([&objects, &materials]) {
        let m = manifest(frame, t);
        for name in names {
            failures.check(m.contains_key(name), || {
                format!("{label}: {t}'s manifest lacks {name:?}: {m:?}")
            });
        }
        for (name, bits) in &m {
            failures.check_eq(*bits, cryptomatte::id(name).to_bits(), || {
                format!("{label}: {t} {name:?}'s hash")
            });
        }
        let known: BTreeSet<u32> = m.values().copied().collect();
        let ch = |layer: usize, c: char| {
            frame
                .channel(&format!("{t}0{layer}.{c}"))
                .unwrap_or_else(|| panic!("{label}: no {t}0{layer}.{c}"))
        };
        let hit = frame.channel("shadow.coverage").unwrap();
        let alpha = frame.channel("A").unwrap();
        let mut worst = 0f32;
        for i in 0..frame.width * frame.height {
            let mut sum = 0.0;
            let mut last = f32::INFINITY;
            for rank in 0..cryptomatte::RANKS {
                let (layer, [id_c, cov_c]) = (rank / 2, [['R', 'G'], ['B', 'A']][rank % 2]);
                let (id, cov) = (ch(layer, id_c)[i], ch(layer, cov_c)[i]);
                failures.check(cov <= last, || format!("{label}: {t} pixel {i} ranks"));
                last = cov;
                if cov > 0.0 {
                    failures.check(known.contains(&id.to_bits()), || {
                        format!(
                            "{label}: {t} pixel {i}: ID {:08x} not in the manifest",
                            id.to_bits()
                        )
                    });
                }
                sum += cov;
            }
            worst = worst.max((sum - hit[i]).abs()).max((sum - alpha[i]).abs());
        }
        failures.check(worst <= 1e-3, || {
            format!("{label}: {t}: coverages miss the hit share and alpha by {worst}")
        });
    }
}

/// The ID mattes of the built-in scene (its six objects and ground) and of a glTF file (its
/// nodes and materials), over a transparent background.
#[test]
fn cryptomatte_coverages_add_up_to_the_alpha_and_the_manifest_names_the_scene() {
    let tmp = tempfile::tempdir().unwrap();
    let mut failures = common::Failures::new();
    // The model itself (a model render), found wherever the assets are: a clean clone has
    // no assets/ beside anims/.
    let bunny_path = common::asset("bunny_on_plane.glb");
    let bunny = bunny_path.to_str().unwrap();
    let bunny_scene = Scene::load(&bunny_path).unwrap();
    for (label, spec, scene) in [
        ("shapes", SHAPES, Scene::shapes()),
        ("bunny", bunny, bunny_scene),
    ] {
        let exr = render(
            spec,
            tmp.path(),
            label,
            &[
                "--cryptomatte",
                "--background",
                "transparent",
                "--ground",
                "none",
            ],
        );
        let frame = read_frame(&exr).unwrap();
        failures.check(scene.parts.len() >= 2, || format!("{label}: parts"));
        check_mattes(&frame, &scene, &mut failures, label);
    }
    let shapes_objects = manifest(
        &read_frame(&tmp.path().join("shapes/frame_0000.exr")).unwrap(),
        "CryptoObject",
    );
    failures.check_eq(
        shapes_objects.keys().cloned().collect::<Vec<_>>(),
        [
            "box", "cone", "cylinder", "ground", "slab", "sphere", "torus",
        ]
        .map(String::from)
        .to_vec(),
        || "shapes' objects".into(),
    );
    failures.assert_none();
}

/// With Cryptomatte, a frame is the same bytes tiled or whole and on one thread or two.
#[test]
fn cryptomatte_frames_are_the_same_bytes_whatever_the_tiles_and_threads() {
    let tmp = tempfile::tempdir().unwrap();
    let bytes = |name: &str, flags: &[&str]| {
        let mut all = vec!["--cryptomatte"];
        all.extend_from_slice(flags);
        std::fs::read(render(SHAPES, tmp.path(), name, &all)).unwrap()
    };
    let whole = bytes("whole", &["--threads", "1"]);
    for (name, flags) in [
        ("tiled", &["--tile", "8", "--threads", "1"][..]),
        ("two-threads", &["--threads", "2"][..]),
        ("tiled-two-threads", &["--tile", "8", "--threads", "2"][..]),
    ] {
        assert!(bytes(name, flags) == whole, "{name}: other bytes");
    }
}
