//! Issue 39, item 8: the files users have. gltfpack's quantized and meshopt-compressed
//! meshes, Draco meshes, unlit and spec-gloss materials and KTX2 textures with a PNG fallback
//! render; broken Draco and meshopt streams, KTX2 without a fallback and glTF 1.0 are refused
//! with the cause first; a PLY, OBJ, Blender file or web
//! page given as a model or a spec is named as what it is. The files are made by
//! tests/data/formats/make.py.

use std::path::{Path, PathBuf};
use std::process::Output;

use crate::common::{self, Failures};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/formats")
        .join(name)
}

fn render(model: &Path, out: &Path) -> Output {
    common::bin()
        .arg("render")
        .arg(model)
        .args([
            "--width", "64", "--height", "48", "--lights", "16", "--spp", "1",
        ])
        .args(["--frames", "0..1", "--no-report", "--out"])
        .arg(out)
        .output()
        .unwrap()
}

/// The beauty of a render of `model` (exit 0 asserted), and its stderr.
fn beauty(model: &str, out: &Path) -> (Vec<f32>, String) {
    let o = render(&data(model), out);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{model}: {err}");
    let frame = envshadow::output::exr::read_frame(&out.join("frame_0000.exr")).unwrap();
    let mut rgb = Vec::new();
    for c in ["R", "G", "B"] {
        rgb.extend_from_slice(frame.channel(c).unwrap());
    }
    (rgb, err)
}

/// Relative RMSE of `a` against `b` (over `b`'s mean).
fn relative_rmse(a: &[f32], b: &[f32]) -> f64 {
    let n = b.len() as f64;
    let mse: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| f64::from(x - y).powi(2))
        .sum::<f64>()
        / n;
    let mean: f64 = b.iter().map(|&v| f64::from(v)).sum::<f64>() / n;
    mse.sqrt() / mean
}

/// Issue 39, item 8: a cube as gltfpack writes it (KHR_mesh_quantization required: unsigned
/// short positions placed by the node, padded normalized byte normals, normalized short UVs)
/// and as Blender writes it with Draco compression (KHR_draco_mesh_compression required),
/// as gltfpack writes it with meshopt compression (EXT_meshopt_compression required),
/// and a cube with a KTX2 texture whose PNG fallback is the texture's source, render like
/// their plain twins (relative RMSE ≤ 0.1 %); the quantized, Draco and meshopt cubes were
/// refused.
#[test]
fn quantized_meshes_and_ktx2_fallbacks_render_like_their_plain_twins() {
    let tmp = tempfile::tempdir().unwrap();
    let (plain, _) = beauty("cube.gltf", &tmp.path().join("plain"));
    let (quantized, _) = beauty("cube-quantized.gltf", &tmp.path().join("quantized"));
    let e = relative_rmse(&quantized, &plain);
    assert!(e <= 1e-3, "quantized cube: relative RMSE {e}");
    let (draco, _) = beauty("cube-draco.gltf", &tmp.path().join("draco"));
    let e = relative_rmse(&draco, &plain);
    assert!(e <= 1e-3, "Draco cube: relative RMSE {e}");
    // gltfpack's meshopt streams: float attributes (`-c -noq`), and quantized ones with the
    // octahedral filter on the normals (`-cc`); both were refused.
    for file in ["cube-meshopt.glb", "cube-meshopt-filters.glb"] {
        let (meshopt, _) = beauty(file, &tmp.path().join(file));
        let e = relative_rmse(&meshopt, &plain);
        assert!(e <= 1e-3, "{file}: relative RMSE {e}");
    }
    let (fallback, _) = beauty("cube-ktx2-fallback.gltf", &tmp.path().join("ktx2"));
    let (png, _) = beauty("cube-png.gltf", &tmp.path().join("png"));
    let e = relative_rmse(&fallback, &png);
    assert!(e <= 1e-3, "KTX2 with a PNG fallback: relative RMSE {e}");
    let e = relative_rmse(&png, &plain);
    assert!(
        e > 1e-2,
        "the red texture is read: relative RMSE {e} to the brown cube"
    );
}

/// Issue 39, item 8: a required `KHR_materials_unlit` renders its base colour as the file's
/// viewer shows it, unshaded: every cube pixel the same colour, whatever the face.
/// `KHR_materials_pbrSpecularGlossiness` is converted, with a warning saying so.
#[test]
fn unlit_and_spec_gloss_materials_render() {
    let tmp = tempfile::tempdir().unwrap();
    let (unlit, _) = beauty("cube-unlit.gltf", &tmp.path().join("unlit"));
    let n = unlit.len() / 3;
    // Pixels whose colour is the base colour's hue (green well above red and blue): the
    // cube, with the same value on every face.
    let greens: Vec<[f32; 3]> = (0..n)
        .map(|i| [unlit[i], unlit[n + i], unlit[2 * n + i]])
        .filter(|p| p[1] > 2.0 * p[0] && p[1] > 2.0 * p[2])
        .collect();
    assert!(
        greens.len() > n / 10,
        "{} green pixels of {n}",
        greens.len()
    );
    for p in &greens {
        assert!(
            (p[1] - 0.9).abs() < 0.02 && (p[0] - 0.2).abs() < 0.02,
            "{p:?}"
        );
    }
    let (_, err) = beauty("cube-specgloss.gltf", &tmp.path().join("sg"));
    assert!(
        err.contains("KHR_materials_pbrSpecularGlossiness converted to metallic-roughness"),
        "{err}"
    );
}

/// Issue 39, item 8: a spec-gloss material's glossiness is its glossinessFactor times the
/// specularGlossinessTexture's alpha, so roughness = 1 − factor × A where the texture is
/// sampled (it was 1 − factor, the texture's alpha ignored); without the texture, 1 − factor.
#[test]
fn spec_gloss_roughness_reads_the_glossiness_texture_alpha() {
    let tmp = tempfile::tempdir().unwrap();
    // 2 × 2 texels of one colour, alpha (glossiness) 64 / 255.
    let img = image::RgbaImage::from_pixel(2, 2, image::Rgba([10, 10, 10, 64]));
    img.save(tmp.path().join("gloss.png")).unwrap();
    let text = std::fs::read_to_string(data("cube-specgloss.gltf")).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    let sg = &mut doc["materials"][0]["extensions"]["KHR_materials_pbrSpecularGlossiness"];
    sg["glossinessFactor"] = serde_json::json!(0.8);
    let plain = tmp.path().join("plain.gltf");
    std::fs::write(&plain, doc.to_string()).unwrap();
    let sg = &mut doc["materials"][0]["extensions"]["KHR_materials_pbrSpecularGlossiness"];
    sg["specularGlossinessTexture"] = serde_json::json!({"index": 0});
    doc["textures"] = serde_json::json!([{"source": 0}]);
    doc["images"] = serde_json::json!([{"uri": "gloss.png"}]);
    let textured = tmp.path().join("textured.gltf");
    std::fs::write(&textured, doc.to_string()).unwrap();
    let roughness = |model: &Path| {
        let scene = envshadow::scene::Scene::load(model).unwrap();
        let tri = (0..scene.triangles.len())
            .find(|&t| scene.materials[scene.tri_material[t] as usize].name != "ground")
            .unwrap();
        scene
            .material_at(tri, (0.25, 0.25), 0.0, glam::Vec3::Y)
            .sample
            .roughness
    };
    let r = roughness(&plain);
    assert!((r - 0.2).abs() < 1e-5, "without the texture: {r}");
    let r = roughness(&textured);
    let want = 1.0 - 0.8 * 64.0 / 255.0;
    assert!(
        (r - want).abs() < 1e-3,
        "with the texture: {r}, want {want}"
    );
}

/// Issue 39, item 8: what the renderer cannot read is refused in one line that names the
/// extension (or the version, or the format) before anything else and says how to convert
/// the file; another format given as a model or a spec is named by its content.
#[test]
fn unreadable_files_are_refused_naming_the_cause_first() {
    let tmp = tempfile::tempdir().unwrap();
    let mut failures = Failures::new();
    for (file, cause, advice) in [
        (
            "cube-draco-broken.gltf",
            "KHR_draco_mesh_compression: mesh 0 primitive 0: cannot decode the Draco stream",
            "Draco",
        ),
        (
            "cube-meshopt-broken.glb",
            "EXT_meshopt_compression: bufferView 0: cannot decode the stream",
            "gltfpack -i in.glb -o out.glb",
        ),
        (
            "cube-ktx2-only.gltf",
            "KHR_texture_basisu: texture 0's image 0 'red_ktx' is a KTX2/Basis Universal texture with no PNG or JPEG fallback",
            "re-export the model with PNG or JPEG textures",
        ),
        (
            "duck-1.0.gltf",
            "glTF 1.0 is not supported (asset.version \"1.0\")",
            "gltf-pipeline",
        ),
        (
            "page.glb",
            "not a glTF file (starts with '<!DOCTYPE'): an HTML page",
            "envshadow reads glTF 2.0 (.gltf/.glb)",
        ),
        (
            "bunny.ply",
            "a PLY file, not an animation spec",
            "reads glTF 2.0",
        ),
        (
            "cube.obj",
            "a Wavefront OBJ file, not an animation spec",
            "reads glTF 2.0",
        ),
        (
            "scene.blend",
            "a Blender file (.blend), not an animation spec",
            "reads glTF 2.0",
        ),
    ] {
        let o = render(&data(file), &tmp.path().join(file));
        let err = String::from_utf8_lossy(&o.stderr);
        let line = common::error_line(&err);
        let first = line.rsplit(&format!("{file}: ")).next().unwrap_or("");
        let ok = o.status.code() == Some(2) && first.starts_with(cause) && line.contains(advice);
        failures.check(ok, || format!("{file}: exit {:?}: {err}", o.status.code()));
    }
    failures.assert_none();
}
