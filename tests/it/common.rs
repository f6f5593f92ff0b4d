//! Helpers shared by the integration tests: where the assets are, small scenes, the binary,
//! tool-gated tests ([`require_tools`]) and tables of cases ([`Failures`]).

use std::io::Write as _;
use std::path::{Path, PathBuf};

use serde_json::{Value, json};

/// The folder with the shared test assets (bunny glTF, HDR maps): `$ENVSHADOW_ASSETS`, else
/// `assets/` in the repo (filled by scripts/fetch-assets.sh), else `../shared/assets`.
pub fn assets_dir() -> PathBuf {
    if let Ok(dir) = std::env::var("ENVSHADOW_ASSETS") {
        return PathBuf::from(dir);
    }
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    for candidate in [root.join("assets"), root.join("../shared/assets")] {
        if candidate.join("bunny_on_plane.glb").exists() {
            return candidate;
        }
    }
    panic!(
        "test assets not found: set ENVSHADOW_ASSETS, run scripts/fetch-assets.sh, or keep ../shared/assets beside the repo"
    );
}

/// One asset by file name.
pub fn asset(name: &str) -> PathBuf {
    let p = assets_dir().join(name);
    assert!(p.exists(), "missing test asset {}", p.display());
    p
}

use envshadow::anim::{AnimFlags, Animation};
use envshadow::film::Channel;
use envshadow::scene::{Material, Scene};
use glam::{Vec2, Vec3};

/// Appends a square of side `size` in the plane y = `y`, facing +Y, to `scene`.
pub fn add_plane(scene: &mut Scene, size: f32, y: f32, material: u32) {
    let h = size / 2.0;
    let base = scene.positions.len() as u32;
    for (x, z) in [(-h, -h), (h, -h), (h, h), (-h, h)] {
        scene.positions.push(Vec3::new(x, y, z));
        scene.normals.push(Vec3::Y);
        scene.uvs.push(Vec2::ZERO);
    }
    // Counter-clockwise seen from +Y.
    scene.triangles.push([base, base + 3, base + 2]);
    scene.triangles.push([base, base + 2, base + 1]);
    scene.tri_material.extend([material; 2]);
}

/// Appends a finely tessellated UV sphere with smooth normals.
pub fn add_sphere(
    scene: &mut Scene,
    centre: Vec3,
    r: f32,
    rings: u32,
    segments: u32,
    material: u32,
) {
    let base = scene.positions.len() as u32;
    for i in 0..=rings {
        let theta = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..=segments {
            let phi = std::f32::consts::TAU * j as f32 / segments as f32;
            let n = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            scene.positions.push(centre + n * r);
            scene.normals.push(n);
            scene.uvs.push(Vec2::ZERO);
        }
    }
    let row = segments + 1;
    for i in 0..rings {
        for j in 0..segments {
            let a = base + i * row + j;
            let b = a + row;
            // Outward-facing winding.
            scene.triangles.push([a, a + 1, b]);
            scene.triangles.push([a + 1, b + 1, b]);
            scene.tri_material.extend([material; 2]);
        }
    }
}

/// A scene with the given grey albedos as materials 0, 1, ….
pub fn scene_with_materials(albedos: &[f32]) -> Scene {
    Scene {
        materials: albedos
            .iter()
            .enumerate()
            .map(|(i, &a)| Material::lambert(&format!("m{i}"), Vec3::splat(a)))
            .collect(),
        source: "test".into(),
        ..Default::default()
    }
}

/// A lit point (`x`, 0, `z`) of a ground in the plane y = 0, facing up, its shadow
/// rays leaving from just above it (off by a bound on a hit point's rounding there).
pub fn ground_surface(x: f32, z: f32) -> envshadow::context::Surface {
    let p = Vec3::new(x, 0.0, z);
    envshadow::context::Surface {
        p,
        origin: envshadow::offset::offset_origin(p, Vec3::splat(1e-6), Vec3::Y),
        n: Vec3::Y,
        ng: Vec3::Y,
        albedo: Vec3::ONE,
        dir: -Vec3::Y,
        hit: true,
        ..Default::default()
    }
}

/// An animation from spec text (with `[scene] builtin = "shapes"` prepended) for tests that
/// supply their own inputs.
pub fn animation(body: &str) -> Animation {
    let text = format!("[scene]\nbuiltin = \"shapes\"\n{body}");
    Animation::parse(
        &text,
        std::path::Path::new("test.toml"),
        &AnimFlags::default(),
    )
    .expect("test spec parses")
}

/// Worker threads of a render spawned through [`bin`] that does not ask for its own: the tests
/// run in parallel, and a render on every core each would oversubscribe the machine. Frames do
/// not depend on the thread count, so no output changes.
const SPAWNED_THREADS: &str = "2";

/// The envshadow binary built for these tests. Its renders run on [`SPAWNED_THREADS`] workers
/// unless the test passes `--threads` or the caller set `RAYON_NUM_THREADS` (which rayon
/// reads for `--threads 0`, the default).
pub fn bin() -> std::process::Command {
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_envshadow"));
    if std::env::var_os("RAYON_NUM_THREADS").is_none() {
        c.env("RAYON_NUM_THREADS", SPAWNED_THREADS);
    }
    c
}

/// The one line of a refusal on stderr: it starts with `error: ` and is the only line, unless
/// clap wrote it (a flag's value its parser refused), which adds clap's usage and hints below.
#[track_caller]
pub fn error_line(err: &str) -> &str {
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert!(
        lines.first().is_some_and(|l| l.starts_with("error: ")),
        "no error line: {err}"
    );
    if !err.contains("For more information, try '--help'.") {
        assert_eq!(lines.len(), 1, "one line expected: {err}");
    }
    lines[0]
}

/// Whether this is CI's run: `.ci/run` runs with `CI=true` and installs every tool the tests
/// need, so there a missing tool is a failure, never a skip. The one spelling of that check.
pub fn on_ci() -> bool {
    std::env::var("CI").as_deref() == Ok("true")
}

/// One line on the process's real stderr. libtest captures only what the print macros write,
/// so this line is seen even when the test passes: a skipped check must not look like a pass.
pub fn notice(line: &str) {
    let _ = writeln!(std::io::stderr(), "{line}");
}

/// The name of the test whose body this is in, as libtest prints it (`farm::farm_over_ssh_…`),
/// for the notices of [`require_tools`] (a name typed by hand drifts when a test is renamed).
macro_rules! this_test {
    () => {{
        fn here() {}
        fn name_of<T>(_: T) -> &'static str {
            std::any::type_name::<T>()
        }
        let path = name_of(here);
        let path = path.strip_suffix("::here").unwrap_or(path);
        // Without the crate's own name (`it::`).
        path.split_once("::").map_or(path, |(_, rest)| rest)
    }};
}
pub(crate) use this_test;

/// Whether every tool is installed: a name is looked up on `PATH`, an absolute path taken as
/// it is. Missing on CI: panics naming them. Missing elsewhere: says `SKIPPED test: …` with
/// [`notice`] and returns false, and the caller returns.
pub fn require_tools(test: &str, tools: &[&str], install: &str) -> bool {
    let missing: Vec<&str> = tools.iter().copied().filter(|t| !installed(t)).collect();
    if missing.is_empty() {
        return true;
    }
    let missing = missing.join(", ");
    assert!(
        !on_ci(),
        "{test}: {missing} not installed, but CI must run this test: .ci/run installs them ({install})"
    );
    notice(&format!(
        "SKIPPED {test}: {missing} not installed (install: {install})"
    ));
    false
}

fn installed(tool: &str) -> bool {
    use std::os::unix::fs::PermissionsExt;
    let executable = |p: &Path| {
        std::fs::metadata(p).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
    };
    if Path::new(tool).is_absolute() {
        return executable(Path::new(tool));
    }
    std::env::var_os("PATH")
        .is_some_and(|path| std::env::split_paths(&path).any(|dir| executable(&dir.join(tool))))
}

/// The failures of a table of cases, collected so that one failing case does not hide the
/// others: [`Failures::assert_none`] panics once at the end, listing every failing case by its
/// label. It also fails when nothing was checked (an empty table would pass silently), and
/// dropping it unasserted panics, so a forgotten `assert_none` cannot pass either.
#[derive(Default)]
pub struct Failures {
    failed: Vec<String>,
    checks: usize,
    asserted: bool,
}

impl Failures {
    pub fn new() -> Failures {
        Failures::default()
    }

    /// Records `what()` unless `ok`; returns `ok` (a case can skip what depends on it).
    pub fn check(&mut self, ok: bool, what: impl FnOnce() -> String) -> bool {
        self.checks += 1;
        if !ok {
            self.failed.push(what());
        }
        ok
    }

    /// Records `what()` with both values unless `got == want`.
    pub fn check_eq<T: PartialEq + std::fmt::Debug>(
        &mut self,
        got: T,
        want: T,
        what: impl FnOnce() -> String,
    ) -> bool {
        let ok = got == want;
        self.check(ok, || format!("{}: got {got:?}, expected {want:?}", what()))
    }

    /// Whether every check so far passed.
    pub fn passed(&self) -> bool {
        self.failed.is_empty()
    }

    /// Runs one case written with plain assertions: its panic, if any, is recorded under
    /// `label` and the table goes on with the next case.
    pub fn case(&mut self, label: &str, case: impl FnOnce()) {
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(case));
        self.check(result.is_ok(), || {
            let payload = result.err().unwrap();
            let message = payload
                .downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| payload.downcast_ref::<&str>().copied())
                .unwrap_or("(a panic without a message)");
            format!("{label}: {message}")
        });
    }

    /// Panics listing every failure, or if nothing was checked.
    #[track_caller]
    pub fn assert_none(mut self) {
        self.asserted = true;
        assert!(
            self.checks > 0,
            "no case was checked: an empty table cannot fail"
        );
        assert!(
            self.failed.is_empty(),
            "{} of {} checks failed:\n  {}",
            self.failed.len(),
            self.checks,
            // A multi-line message (assert_eq!'s) stays indented under its case.
            self.failed
                .iter()
                .map(|f| f.replace('\n', "\n    "))
                .collect::<Vec<_>>()
                .join("\n  ")
        );
    }
}

impl Drop for Failures {
    fn drop(&mut self) {
        if !self.asserted && !std::thread::panicking() {
            panic!("Failures dropped without assert_none: its failures were never reported");
        }
    }
}

/// A CSV file with a header row, each row as (column name → value): tests read columns by
/// name, so a column added or moved does not silently shift what they compare.
pub fn csv_by_name(path: &Path) -> Vec<std::collections::BTreeMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            assert_eq!(cells.len(), header.len(), "{}: {l}", path.display());
            header
                .iter()
                .zip(cells)
                .map(|(h, c)| (h.trim().to_string(), c.trim().to_string()))
                .collect()
        })
        .collect()
}

/// Panics, naming the layer, unless `film` equals `want` bit for bit in every layer: beauty,
/// the `rays`, `visible` and `wrong` AOVs, coverage and the brute-force reference.
pub fn assert_same_film(film: &envshadow::film::Film, want: &envshadow::film::Film) {
    assert!(
        film.layer(Channel::BEAUTY).unwrap() == want.layer(Channel::BEAUTY).unwrap(),
        "beauty differs"
    );
    assert!(
        film.plane(Channel::Rays).unwrap() == want.plane(Channel::Rays).unwrap(),
        "rays AOV differs"
    );
    assert!(
        film.plane(Channel::Visible).unwrap() == want.plane(Channel::Visible).unwrap(),
        "visible AOV differs"
    );
    assert!(
        film.plane(Channel::Wrong) == want.plane(Channel::Wrong),
        "wrong AOV differs"
    );
    assert!(
        film.plane(Channel::Coverage) == want.plane(Channel::Coverage),
        "coverage differs"
    );
    assert!(
        film.layer(Channel::REFERENCE) == want.layer(Channel::REFERENCE),
        "reference differs"
    );
}

/// `c` without the halo's work, the one count that depends on the tiles.
pub fn without_halo(c: envshadow::film::Counts) -> envshadow::film::Counts {
    envshadow::film::Counts {
        halo_pixels: 0,
        halo_rays: 0,
        ..c
    }
}

/// A binary PLY file's bytes, where its header ends, and the header.
pub fn read_ply(path: &Path) -> (Vec<u8>, usize, String) {
    let ply = std::fs::read(path).unwrap();
    let end = ply.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let header = String::from_utf8_lossy(&ply[..end]).into_owned();
    (ply, end, header)
}

/// The names in `dir`, sorted (none when it does not exist).
pub fn file_names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// Standard base64 with padding, for `data:` URIs in generated glTF files.
pub fn base64(data: &[u8]) -> String {
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

// ---------------------------------------------------------------------------------------------
// A small glTF writer: accessors go into one binary buffer, written as `.gltf` + `.bin`, as
// `.gltf` with a `data:` URI, or as `.glb` (scene loading, scales, the truck of temporal).

#[derive(Clone, Default)]
pub struct Gltf {
    pub bin: Vec<u8>,
    pub views: Vec<Value>,
    pub accessors: Vec<Value>,
}

impl Gltf {
    pub fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()}));
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    /// A float accessor of `type_` ("VEC2", "VEC3", "VEC4") over `data`.
    pub fn floats(&mut self, type_: &str, data: &[f32]) -> usize {
        let n = match type_ {
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" => 4,
            _ => 1,
        };
        let bytes: Vec<u8> = data.iter().flat_map(|f| f.to_le_bytes()).collect();
        let view = self.view(&bytes);
        let mut acc = json!({"bufferView": view, "componentType": 5126, "count": data.len() / n, "type": type_});
        if type_ == "VEC3" {
            // glTF requires min/max on POSITION (f32::min skips NaN); harmless on others.
            let mut lo = [f32::INFINITY; 3];
            let mut hi = [f32::NEG_INFINITY; 3];
            for c in data.chunks(3) {
                for k in 0..3 {
                    lo[k] = lo[k].min(c[k]);
                    hi[k] = hi[k].max(c[k]);
                }
            }
            acc["min"] = json!(lo);
            acc["max"] = json!(hi);
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }

    pub fn indices(&mut self, data: &[u32]) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|i| i.to_le_bytes()).collect();
        let view = self.view(&bytes);
        self.accessors.push(json!({"bufferView": view, "componentType": 5125, "count": data.len(), "type": "SCALAR"}));
        self.accessors.len() - 1
    }

    /// The document: `rest` (meshes, nodes, scenes, …) plus buffers, views and accessors.
    pub fn json(&self, rest: Value, buffer_uri: Option<&str>) -> Value {
        let mut doc = rest;
        doc["asset"] = json!({"version": "2.0"});
        let mut buffer = json!({"byteLength": self.bin.len()});
        if let Some(uri) = buffer_uri {
            buffer["uri"] = json!(uri);
        }
        doc["buffers"] = json!([buffer]);
        doc["bufferViews"] = json!(self.views);
        doc["accessors"] = json!(self.accessors);
        doc
    }

    /// Writes `name.gltf` + `name.bin` into `dir`.
    pub fn write_gltf(&self, dir: &Path, name: &str, rest: Value) -> PathBuf {
        let bin_name = format!("{name}.bin");
        std::fs::write(dir.join(&bin_name), &self.bin).unwrap();
        let path = dir.join(format!("{name}.gltf"));
        let doc = self.json(rest, Some(&bin_name));
        std::fs::write(&path, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
        path
    }

    /// Writes `name.gltf` with the buffer inline as a base64 `data:` URI.
    pub fn write_gltf_data_uri(&self, dir: &Path, name: &str, rest: Value) -> PathBuf {
        let uri = format!("data:application/octet-stream;base64,{}", base64(&self.bin));
        let path = dir.join(format!("{name}.gltf"));
        let doc = self.json(rest, Some(&uri));
        std::fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
        path
    }

    /// Writes `name.glb` into `dir`.
    pub fn write_glb(&self, dir: &Path, name: &str, rest: Value) -> PathBuf {
        let mut json = serde_json::to_vec(&self.json(rest, None)).unwrap();
        while !json.len().is_multiple_of(4) {
            json.push(b' ');
        }
        let mut bin = self.bin.clone();
        while !bin.len().is_multiple_of(4) {
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
        let path = dir.join(format!("{name}.glb"));
        std::fs::write(&path, out).unwrap();
        path
    }
}
