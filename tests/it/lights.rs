//! Lights: energy conservation, exact O(1) cell lookup, adjacency, determinism, JSON, errors.

use crate::common::{self, Failures};

use envshadow::envmap::EnvMap;
use envshadow::error::InputError;
use envshadow::lights::sis::{Thresholds, directions};
use envshadow::lights::{Light, LightSet, Sampler, read_json};
use glam::Vec3;
use std::sync::OnceLock;

fn map(name: &str) -> &'static EnvMap {
    static MAPS: OnceLock<Vec<(String, EnvMap)>> = OnceLock::new();
    let maps = MAPS.get_or_init(|| {
        [
            "grace.hdr",
            "studio_small_03_1k.hdr",
            "rooitou_park_1k.hdr",
            "KernerEnvLatLong.exr",
        ]
        .iter()
        .map(|n| (n.to_string(), EnvMap::load(&common::asset(n)).unwrap()))
        .chain([("sky".to_string(), EnvMap::builtin_sky())])
        .collect()
    });
    &maps.iter().find(|(n, _)| n == name).unwrap().1
}

/// splitmix64: a deterministic stream for random directions.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn dir(&mut self) -> Vec3 {
        let y = 1.0 - 2.0 * self.unit();
        let phi = std::f32::consts::TAU * self.unit();
        let r = (1.0 - y * y).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), y, r * phi.sin())
    }
}

fn check_energy(env: &EnvMap, set: &LightSet, what: &str) {
    let total = set.total_energy();
    let want = env.integral();
    for k in 0..3 {
        let rel = (total[k] - want[k]).abs() / want[k];
        assert!(
            rel < 1e-4,
            "{what}: channel {k}: {} vs {} ({rel})",
            total[k],
            want[k]
        );
    }
    let sa: f64 = set.lights.iter().map(|l| l.solid_angle as f64).sum();
    assert!(
        (sa - 4.0 * std::f64::consts::PI).abs() < 1e-3,
        "{what}: Σ solid angle {sa}"
    );
    assert!(set.lights.iter().all(|l| l.energy.min_element() >= 0.0));
}

#[test]
fn energy_is_conserved_for_every_map_and_sampler() {
    let cases: &[(&str, &[usize])] = &[
        ("grace.hdr", &[50, 200, 400]),
        ("studio_small_03_1k.hdr", &[50, 400]),
        ("rooitou_park_1k.hdr", &[200]),
        ("KernerEnvLatLong.exr", &[400]),
        ("sky", &[50, 200]),
    ];
    let mut failures = Failures::new();
    for &(name, ns) in cases {
        let env = map(name);
        for &n in ns {
            for s in [Sampler::Sis, Sampler::MedianCut] {
                let what = format!("{name} {s:?} n={n}");
                failures.case(&what, || {
                    let set = LightSet::build(env, n, s).unwrap();
                    assert_eq!(set.len(), n, "light count");
                    check_energy(env, &set, &what);
                    // No two lights coincide.
                    let mut d: Vec<[u32; 3]> = set
                        .lights
                        .iter()
                        .map(|l| l.dir.to_array().map(f32::to_bits))
                        .collect();
                    d.sort_unstable();
                    d.dedup();
                    assert_eq!(d.len(), n, "duplicate directions");
                });
            }
        }
    }
    failures.assert_none();
}

#[test]
fn rotated_map_conserves_energy_and_rotates_lights() {
    let env = map("grace.hdr");
    let rot = env.clone().with_rotation(90.0);
    let a = LightSet::build(env, 100, Sampler::Sis).unwrap();
    let b = LightSet::build(&rot, 100, Sampler::Sis).unwrap();
    check_energy(&rot, &b, "rotated");
    // The brightest light turns with the map: +90° takes (x, y, z) to (z, y, −x).
    let brightest = |s: &LightSet| {
        s.lights
            .iter()
            .max_by(|p, q| p.energy.y.total_cmp(&q.energy.y))
            .unwrap()
            .dir
    };
    let (da, db) = (brightest(&a), brightest(&b));
    assert!(
        (Vec3::new(da.z, da.y, -da.x) - db).length() < 0.05,
        "{da} → {db}"
    );
}

#[test]
fn cell_of_matches_brute_force() {
    let mut rng = Rng(0x5EED);
    let mut failures = Failures::new();
    for (name, n, s) in [
        ("rooitou_park_1k.hdr", 50, Sampler::Sis),
        ("rooitou_park_1k.hdr", 400, Sampler::MedianCut),
        ("studio_small_03_1k.hdr", 200, Sampler::Sis),
        ("grace.hdr", 400, Sampler::Sis),
        ("grace.hdr", 200, Sampler::MedianCut),
        ("sky", 50, Sampler::MedianCut),
    ] {
        failures.case(&format!("{name} {s:?} n={n}"), || {
            let set = LightSet::build(map(name), n, s).unwrap();
            let mut wrong = 0;
            for _ in 0..120_000 {
                let d = rng.dir();
                if set.cell_of(d) != set.cell_of_brute_force(d) {
                    wrong += 1;
                }
            }
            // Directions right next to each light (inside tiny cells of clustered lights).
            for l in &set.lights {
                for _ in 0..50 {
                    let d = (l.dir + 0.002 * rng.dir()).normalize();
                    if set.cell_of(d) != set.cell_of_brute_force(d) {
                        wrong += 1;
                    }
                }
            }
            assert_eq!(wrong, 0, "{name} {s:?} n={n}");
            // The shortcut for directions expected near light j: the same cell, whether the
            // direction is in j's inner cap, near its border, or in a neighbour's cell.
            for (j, l) in set.lights.iter().enumerate() {
                for scale in [0.0, 0.002, 0.01, 0.03, 0.1, 0.3] {
                    for _ in 0..20 {
                        let d = (l.dir + scale * rng.dir()).normalize();
                        assert_eq!(
                            set.cell_of_near(d, j),
                            set.cell_of_brute_force(d),
                            "{name} {s:?} n={n}: light {j}, {d}"
                        );
                    }
                }
            }
            // Each light is in its own cell, unless another light is so close that the f32 dot
            // products tie (median cut's several lights inside one sun texel).
            for (j, l) in set.lights.iter().enumerate() {
                let crowded = set
                    .lights
                    .iter()
                    .enumerate()
                    .any(|(k, o)| k != j && o.dir.dot(l.dir) > 1.0 - 1e-6);
                if !crowded {
                    assert_eq!(set.cell_of(l.dir), j as u32, "{name} light {j}");
                }
            }
        });
    }
    failures.assert_none();
}

/// A turning environment (`[motion] kind = "environment"`) turns the sampled lights rigidly:
/// each direction turned about +Y as `[environment] rotation` turns the map, energies and
/// solid angles kept, and `cell_of` still finds the nearest turned light.
#[test]
fn a_turned_light_set_turns_its_lights_and_their_cells() {
    let set = LightSet::build(map("rooitou_park_1k.hdr"), 200, Sampler::Sis).unwrap();
    let mut rng = Rng(0x7124);
    let mut failures = Failures::new();
    for degrees in [3.0f32, 90.0, -47.5, 360.0] {
        failures.case(&format!("{degrees}°"), || {
            let t = set.turned(degrees);
            let (s, c) = (degrees.to_radians().sin(), degrees.to_radians().cos());
            for (a, b) in set.lights.iter().zip(&t.lights) {
                // +90° takes what was seen along +Z to +X: (x, y, z) → (x c + z s, y, −x s + z c).
                let want = Vec3::new(
                    a.dir.x * c + a.dir.z * s,
                    a.dir.y,
                    -a.dir.x * s + a.dir.z * c,
                );
                assert!((b.dir - want).length() < 1e-5, "{} → {}", a.dir, b.dir);
                assert_eq!((a.energy, a.solid_angle), (b.energy, b.solid_angle));
            }
            let rotation = t.environment.as_ref().unwrap().rotation_deg;
            assert_eq!(
                rotation,
                set.environment.as_ref().unwrap().rotation_deg + degrees
            );
            // The nearest turned light, by brute force over the turned directions; a tie
            // within rounding may go either way.
            let mut wrong = 0;
            for _ in 0..20_000 {
                let d = rng.dir();
                let mut dots: Vec<(f32, usize)> = t
                    .lights
                    .iter()
                    .enumerate()
                    .map(|(j, l)| (l.dir.dot(d), j))
                    .collect();
                dots.sort_by(|p, q| q.0.total_cmp(&p.0));
                let got = t.cell_of(d) as usize;
                if got != dots[0].1 && dots[0].0 - dots[1].0 > 1e-5 {
                    wrong += 1;
                }
                assert_eq!(t.cell_of_near(d, got), got as u32);
            }
            assert_eq!(
                wrong, 0,
                "directions outside their nearest turned light's cell"
            );
            for (j, l) in t.lights.iter().enumerate() {
                assert_eq!(t.cell_of(l.dir), j as u32, "light {j}");
            }
            // Turns add up.
            let twice = set.turned(degrees / 2.0).turned(degrees / 2.0);
            for (a, b) in twice.lights.iter().zip(&t.lights) {
                assert!((a.dir - b.dir).length() < 1e-5);
            }
        });
    }
    failures.assert_none();
}

#[test]
fn cell_of_on_the_cube_edges_and_ties() {
    // Two lights symmetric about the plane z = 0: ties on it go to the lower index.
    let set = LightSet::from_lights(vec![
        Light {
            dir: Vec3::new(0.0, 0.0, -1.0),
            energy: Vec3::ONE,
            solid_angle: 0.0,
        },
        Light {
            dir: Vec3::new(0.0, 0.0, 1.0),
            energy: Vec3::ONE,
            solid_angle: 0.0,
        },
    ]);
    assert_eq!(set.cell_of(Vec3::X), 0);
    assert_eq!(set.cell_of(Vec3::Y), 0);
    assert_eq!(set.cell_of(Vec3::new(0.3, 0.1, 0.9).normalize()), 1);
    // Cube edges and corners for a real set.
    let set = LightSet::build(map("studio_small_03_1k.hdr"), 200, Sampler::Sis).unwrap();
    for x in [-1.0f32, 0.0, 1.0] {
        for y in [-1.0f32, 0.0, 1.0] {
            for z in [-1.0f32, 0.0, 1.0] {
                let d = Vec3::new(x, y, z);
                if d != Vec3::ZERO {
                    let d = d.normalize();
                    assert_eq!(set.cell_of(d), set.cell_of_brute_force(d), "{d}");
                }
            }
        }
    }
}

#[test]
fn adjacency_is_symmetric_and_plausible() {
    let mut failures = Failures::new();
    for (name, s) in [
        ("studio_small_03_1k.hdr", Sampler::Sis),
        ("rooitou_park_1k.hdr", Sampler::MedianCut),
        ("grace.hdr", Sampler::Sis),
    ] {
        failures.case(&format!("{name} {s:?}"), || {
            let set = LightSet::build(map(name), 200, s).unwrap();
            let mut total = 0;
            for j in 0..set.len() {
                let nb = set.neighbors(j);
                assert!(!nb.is_empty(), "{name}: light {j} has no neighbour");
                assert!(
                    nb.windows(2).all(|w| w[0] < w[1]),
                    "{name}: not sorted/deduped"
                );
                for &k in nb {
                    assert_ne!(k as usize, j, "{name}: self-loop at {j}");
                    assert!(
                        set.neighbors(k as usize).contains(&(j as u32)),
                        "{name}: {j}→{k} not symmetric"
                    );
                }
                // The bitset form lists the same lights.
                let mut from_bits = Vec::new();
                for (m, &word) in set.neighbor_bits(j).iter().enumerate() {
                    (0..64)
                        .filter(|b| word >> b & 1 == 1)
                        .for_each(|b| from_bits.push((m * 64 + b) as u32));
                }
                assert_eq!(from_bits, nb, "{name}: neighbour bits of {j}");
                total += nb.len();
            }
            let mean = total as f64 / set.len() as f64;
            assert!(
                (4.0..=8.0).contains(&mean),
                "{name} {s:?}: mean degree {mean}"
            );
        });
    }
    // Two lights are neighbours; one light has none.
    let two = LightSet::from_lights(vec![
        Light {
            dir: Vec3::X,
            energy: Vec3::ONE,
            solid_angle: 1.0,
        },
        Light {
            dir: Vec3::Y * 2.0,
            energy: Vec3::ONE,
            solid_angle: 1.0,
        },
    ]);
    failures.case("two lights", || {
        assert_eq!(two.neighbors(0), &[1]);
        assert_eq!(two.neighbors(1), &[0]);
        assert_eq!(two.lights[1].dir, Vec3::Y);
    });
    let one = LightSet::from_lights(vec![Light {
        dir: Vec3::Z,
        energy: Vec3::ONE,
        solid_angle: 1.0,
    }]);
    failures.case("one light", || {
        assert!(one.neighbors(0).is_empty());
        assert_eq!(one.cell_of(-Vec3::Z), 0);
        assert_eq!(one.cell_of_near(-Vec3::Z, 0), 0);
    });
    failures.assert_none();
}

/// The recorded light sets: `map lights sampler sha256`, the hash of [`light_set_bits`].
/// Building a set twice in one process cannot show that another host, compiler or release of
/// a dependency gives other bits; these were recorded once, so any drift fails here. A change
/// that means to move lights updates the table on purpose (the failure prints the new one).
/// Updated once: when the samplers' cosines and powers moved from the host's C library to the
/// pure-Rust `libm` (issue 20, item 10).
const LIGHT_SETS: &str = "\
KernerEnvLatLong.exr 200 Sis c8f0445514d477880bce09f0f5175064fd4ce5fa9b5821a86fcfb842b610e427
KernerEnvLatLong.exr 200 MedianCut ce7404aa741664e32d1269bae1244effefcc7444961ab49cc6400aea05b95b37
grace.hdr 50 Sis 182c82306015e88aa5285864773ee0b14ca9d779d23eefd3f990bee91b7ec6e3
grace.hdr 50 MedianCut 1f40e2da45ee3bae4cadf1ee4bec579aa28643e2542b94ccca114ac7f7ba325c
";

/// Every bit a render takes from a light set: each light's direction, energy and solid angle
/// as f32 bits, then each light's neighbour list (length first), all little-endian u32.
fn light_set_bits(set: &LightSet) -> Vec<u8> {
    let mut bytes = Vec::new();
    for l in &set.lights {
        for x in l
            .dir
            .to_array()
            .into_iter()
            .chain(l.energy.to_array())
            .chain([l.solid_angle])
        {
            bytes.extend_from_slice(&x.to_bits().to_le_bytes());
        }
    }
    for j in 0..set.len() {
        let nb = set.neighbors(j);
        bytes.extend_from_slice(&(nb.len() as u32).to_le_bytes());
        for &k in nb {
            bytes.extend_from_slice(&k.to_le_bytes());
        }
    }
    bytes
}

#[test]
fn light_sets_keep_their_recorded_bits() {
    use sha2::{Digest, Sha256};
    let mut got = String::new();
    for (name, n) in [("KernerEnvLatLong.exr", 200), ("grace.hdr", 50)] {
        for s in [Sampler::Sis, Sampler::MedianCut] {
            let set = LightSet::build(map(name), n, s).unwrap();
            let hash = Sha256::digest(light_set_bits(&set));
            got += &format!("{name} {n} {s:?} {hash:x}\n");
        }
    }
    let changed: Vec<&str> = got
        .lines()
        .filter(|l| !LIGHT_SETS.lines().any(|e| e == *l))
        .collect();
    assert!(
        changed.is_empty() && got.lines().count() == LIGHT_SETS.lines().count(),
        "light sets changed: {changed:?}\nthe new table:\n{got}"
    );
}

#[test]
fn sis_puts_lights_on_the_sun() {
    // rooitou_park: 65 % of the power in 16 texels around px (614, 226). SIS must put several
    // lights there, and the light holding the sun carries a large share of the energy.
    let env = map("rooitou_park_1k.hdr");
    let sun = env.texel_dir(614, 226);
    let set = LightSet::build(env, 200, Sampler::Sis).unwrap();
    let near = set
        .lights
        .iter()
        .filter(|l| l.dir.dot(sun) > (2.0f32).to_radians().cos())
        .count();
    assert!(near >= 3, "{near} lights near the sun");
    let j = set.cell_of(sun) as usize;
    assert!(set.lights[j].energy.y as f64 > 0.05 * env.integral()[1]);
}

#[test]
fn tiny_and_uniform_maps_work() {
    let env = EnvMap::from_texels(4, 2, vec![Vec3::ONE; 8], "white").unwrap();
    let mut failures = Failures::new();
    for s in [Sampler::Sis, Sampler::MedianCut] {
        for n in [1, 3, 50] {
            let what = format!("white {s:?} {n}");
            failures.case(&what, || {
                let set = LightSet::build(&env, n, s).unwrap();
                assert_eq!(set.len(), n);
                check_energy(&env, &set, &what);
            });
        }
    }
    let black = EnvMap::from_texels(16, 8, vec![Vec3::ZERO; 128], "black").unwrap();
    let set = LightSet::build(&black, 10, Sampler::Sis).unwrap();
    assert_eq!(set.len(), 10);
    assert_eq!(set.total_energy(), [0.0; 3]);
    let set = LightSet::build(&black, 10, Sampler::MedianCut).unwrap();
    assert_eq!(set.len(), 10);
    failures.assert_none();
}

#[test]
fn zero_lights_is_an_input_error() {
    let e = LightSet::build(map("grace.hdr"), 0, Sampler::Sis).expect_err("n = 0");
    assert!(e.downcast_ref::<InputError>().is_some());
    let t = format!("{e:#}");
    assert!(t.starts_with("lights:") && t.contains("at least 1"), "{t}");
}

#[test]
fn json_round_trip_and_errors() {
    let env = map("grace.hdr");
    let set = LightSet::build(env, 50, Sampler::MedianCut).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("lights.json");
    set.write_json(&p).unwrap();
    assert_eq!(temporaries(dir.path()), Vec::<String>::new());
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
    assert_eq!(v["sampler"], "median-cut");
    assert_eq!(v["count"], 50);
    assert_eq!(v["environment"]["width"], 256);
    assert!(
        v["environment"]["source"]
            .as_str()
            .unwrap()
            .ends_with("grace.hdr")
    );
    assert_eq!(v["lights"][3]["index"], 3);
    let back = read_json(&p).unwrap();
    assert_eq!(back.lights, set.lights);
    assert_eq!(back.sampler, Some(Sampler::MedianCut));
    assert_eq!(back.environment, set.environment);
    for j in 0..50 {
        assert_eq!(back.neighbors(j), set.neighbors(j));
    }

    let bad = |name: &str, text: &str, needle: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        let e = read_json(&p).expect_err(name);
        assert!(e.downcast_ref::<InputError>().is_some());
        let t = format!("{e:#}");
        assert!(t.contains(name) && t.contains(needle), "{t}");
    };
    bad("a.json", "{not json", "not valid JSON");
    bad(
        "b.json",
        r#"{"sampler":"sis","count":0,"lights":[]}"#,
        "count must be at least 1",
    );
    bad(
        "c.json",
        r#"{"sampler":"sis","count":1,"lights":[{"direction":[0,2,0],"energy":[1,1,1],"solid_angle":1}]}"#,
        "not a unit vector",
    );
    bad(
        "d.json",
        r#"{"sampler":"sis","count":1,"lights":[{"direction":[0,1,0],"energy":[1,-1,1],"solid_angle":1}]}"#,
        "negative energy",
    );
    bad(
        "e.json",
        r#"{"sampler":"sis","count":1,"lights":[{"direction":[0,1,0],"energy":[1,"x",1],"solid_angle":1}]}"#,
        "lights[0].energy[1]",
    );
    bad(
        "f.json",
        r#"{"sampler":"best","count":1,"lights":[]}"#,
        "unknown sampler \"best\"",
    );
    bad(
        "g.json",
        r#"{"sampler":"sis","count":2,"lights":[{"direction":[0,1,0],"energy":[1,1,1],"solid_angle":1}]}"#,
        "count is 2",
    );
    let e = read_json(&dir.path().join("missing.json")).expect_err("missing");
    assert!(format!("{e:#}").contains("missing.json: lights file not found"));
}

#[test]
fn cells_png_is_written() {
    let env = map("grace.hdr");
    let set = LightSet::build(env, 100, Sampler::Sis).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("cells.png");
    envshadow::lights::picture::cells_png(env, &set, &p).unwrap();
    let img = image::open(&p).unwrap().into_rgb8();
    assert_eq!((img.width(), img.height()), (1024, 512));
    let magenta = img.pixels().filter(|p| p.0 == [255, 0, 255]).count();
    assert!(magenta > 1000, "{magenta} border pixels");
    assert_eq!(temporaries(dir.path()), Vec::<String>::new());
}

/// Files in `dir` named like a temporary (`….tmp`).
fn temporaries(dir: &std::path::Path) -> Vec<String> {
    common::file_names(dir)
        .into_iter()
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

/// Issue 20, item 4: lights.json was written through one fixed temporary name, so two
/// writers of one folder starting at once (two renders, two attempts of a farm job) failed
/// with `cannot rename …/lights.json.tmp` about one time in ten. Sixteen threads writing it
/// twenty times each all succeed, and leave one whole file and no temporary.
#[test]
fn concurrent_writers_of_lights_json_never_share_a_temporary() {
    let set = LightSet::build(map("grace.hdr"), 50, Sampler::Sis).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("lights.json");
    let errors: Vec<String> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..16)
            .map(|_| s.spawn(|| (0..20).filter_map(|_| set.write_json(&p).err()).count()))
            .collect();
        handles
            .into_iter()
            .zip(0..)
            .filter_map(|(h, t)| {
                let n = h.join().unwrap();
                (n > 0).then(|| format!("thread {t}: {n} of 20 writes failed"))
            })
            .collect()
    });
    assert!(errors.is_empty(), "{}", errors.join("\n"));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
    assert_eq!(v["count"], 50);
    assert_eq!(temporaries(dir.path()), Vec::<String>::new());
}

/// RMS error of unshadowed diffuse irradiance E(n) = Σ_j E_j max(0, n·ω_j) from `n` SIS lights
/// placed with `th` (each carrying its Voronoi cell's luminance) against the map's `exact`
/// irradiance at `normals`, relative to the mean irradiance, in percent.
fn irradiance_error(
    env: &EnvMap,
    n: usize,
    th: Thresholds,
    normals: &[Vec3],
    exact: &[f64],
) -> f64 {
    let dirs = directions(env, n, th);
    let lights = dirs
        .iter()
        .map(|&d| Light {
            dir: d,
            energy: Vec3::ZERO,
            solid_angle: 0.0,
        })
        .collect();
    let set = LightSet::from_lights(lights);
    let mut e = vec![0.0f64; n];
    for y in 0..env.height {
        let dw = env.texel_solid_angle_f64(y);
        for x in 0..env.width {
            e[set.cell_of(env.texel_dir(x, y)) as usize] +=
                envshadow::envmap::luminance(env.texel(x, y)) as f64 * dw;
        }
    }
    let mean = exact.iter().sum::<f64>() / exact.len() as f64;
    let mut sq = 0.0;
    for (i, nn) in normals.iter().enumerate() {
        let approx: f64 = (0..n).map(|j| e[j] * nn.dot(dirs[j]).max(0.0) as f64).sum();
        sq += ((approx - exact[i]) / mean).powi(2);
    }
    100.0 * (sq / normals.len() as f64).sqrt()
}

/// The SIS layer thresholds (src/lights/sis.rs, [`Thresholds`], records these figures): the
/// default rule keeps the irradiance error of [`irradiance_error`] within a stated bound on
/// every shared map and the built-in sky at N = 50, 200 and 400 (measured at most 1.98, 0.52
/// and 0.36 %), and it is the better of the two rules over those fifteen cases: its summed
/// error is below the other rule's, which is why it is the default.
#[test]
fn sis_default_thresholds_are_accurate_and_the_better_rule() {
    let bound = |n: usize| match n {
        50 => 2.5,
        200 => 0.75,
        _ => 0.5,
    };
    let default = Thresholds::default();
    let other = if default == Thresholds::Sigma {
        Thresholds::MuPlusSigma
    } else {
        Thresholds::Sigma
    };
    let mut rng = Rng(7);
    let normals: Vec<Vec3> = (0..300).map(|_| rng.dir()).collect();
    let mut failures = Failures::new();
    let (mut sum_default, mut sum_other) = (0.0, 0.0);
    let mut table = String::new();
    for name in [
        "grace.hdr",
        "studio_small_03_1k.hdr",
        "rooitou_park_1k.hdr",
        "KernerEnvLatLong.exr",
        "sky",
    ] {
        let env = map(name);
        let exact: Vec<f64> = normals
            .iter()
            .map(|n| {
                let mut e = 0.0f64;
                for y in 0..env.height {
                    let dw = env.texel_solid_angle_f64(y);
                    for x in 0..env.width {
                        let c = n.dot(env.texel_dir(x, y)).max(0.0) as f64;
                        e += c * envshadow::envmap::luminance(env.texel(x, y)) as f64 * dw;
                    }
                }
                e
            })
            .collect();
        for n in [50, 200, 400] {
            let d = irradiance_error(env, n, default, &normals, &exact);
            let o = irradiance_error(env, n, other, &normals, &exact);
            table += &format!("{name:24} n={n:3}  {default:?}: {d:.4} %  {other:?}: {o:.4} %\n");
            failures.check(d <= bound(n), || {
                format!(
                    "{name} n={n}: {default:?} error {d:.4} % over the bound {} %",
                    bound(n)
                )
            });
            sum_default += d;
            sum_other += o;
        }
    }
    failures.check(sum_default < sum_other, || {
        format!(
            "the default {default:?} is not the better rule: summed error {sum_default:.4} % \
             against {sum_other:.4} % for {other:?}"
        )
    });
    if !failures.passed() {
        eprintln!("{table}");
    }
    failures.assert_none();
}
