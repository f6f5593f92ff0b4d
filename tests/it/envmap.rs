//! Environment maps: the pinned lat-long convention, rotation, solid angles, integrals, errors.

use crate::common::{self, Failures};

use envshadow::envmap::{EnvMap, dir_to_uv, uv_to_dir};
use envshadow::error::InputError;
use glam::{Vec2, Vec3};
use std::path::Path;

fn err_text(r: envshadow::error::Result<EnvMap>) -> String {
    let e = r.expect_err("expected an error");
    assert!(
        e.chain().any(|c| c.downcast_ref::<InputError>().is_some()),
        "not an InputError: {e:#}"
    );
    format!("{e:#}")
}

/// The OpenEXR sample `OrientationLatLong.exr` draws, at each horizontal axis, a dark-red corner:
/// one line up towards +Y and one along the equator, from ±X towards +Z and from ±Z towards +X
/// (seen in a PNG preview); the poles are dark red. White/blue text is everywhere else.
#[test]
fn orientation_pattern_pins_the_convention() {
    let m = EnvMap::load(&common::asset("OrientationLatLong.exr")).unwrap();
    assert_eq!((m.width, m.height), (1024, 512));
    let dark = |d: Vec3| m.radiance(d.normalize()).y < 0.1;
    let light = |d: Vec3| m.radiance(d.normalize()).y > 0.5;
    let cases = [
        (Vec3::X, Vec3::Z),
        (-Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X),
        (-Vec3::Z, Vec3::X),
    ];
    for (axis, towards) in cases {
        let e = 0.06;
        assert!(dark(axis + e * towards), "{axis}: line towards {towards}");
        assert!(
            light(axis - e * towards),
            "{axis}: no line away from {towards}"
        );
        assert!(
            m.radiance((axis + e * Vec3::Y).normalize()).y < 0.3,
            "{axis}: line up"
        );
        assert!(light(axis - e * Vec3::Y), "{axis}: nothing below");
    }
    for pole in [Vec3::Y, -Vec3::Y] {
        let c = m.radiance(pole);
        assert!(c.x > 0.05 && c.y < 0.02 && c.z < 0.02, "{pole}: {c}");
    }
}

#[test]
fn uv_convention_points_and_round_trip() {
    let close = |a: Vec2, b: Vec2| (a - b).abs().max_element() < 1e-5;
    assert!(close(dir_to_uv(Vec3::Z), Vec2::new(0.5, 0.5)));
    assert!(close(dir_to_uv(Vec3::X), Vec2::new(0.25, 0.5)));
    assert!(close(dir_to_uv(-Vec3::X), Vec2::new(0.75, 0.5)));
    assert!(dir_to_uv(Vec3::Y).y.abs() < 1e-6);
    assert!((dir_to_uv(-Vec3::Y).y - 1.0).abs() < 1e-6);
    let u = dir_to_uv(-Vec3::Z).x;
    assert!(
        !(1e-6..=1.0 - 1e-6).contains(&u),
        "−Z at the seam, got u = {u}"
    );
    assert!((uv_to_dir(Vec2::new(0.25, 0.5)) - Vec3::X).length() < 1e-6);
    for i in 0..50 {
        for j in 1..50 {
            let uv = Vec2::new((i as f32 + 0.3) / 50.0, j as f32 / 50.0);
            let back = dir_to_uv(uv_to_dir(uv));
            assert!(close(uv, back), "{uv} -> {back}");
        }
    }
}

#[test]
fn texel_dirs_follow_the_convention() {
    let m = EnvMap::from_texels(8, 4, vec![Vec3::ONE; 32], "test").unwrap();
    // Texel (3, 1) is just left of the centre column (+Z) and above the equator.
    let d = m.texel_dir(3, 1);
    assert!(d.z > 0.0 && d.x > 0.0 && d.y > 0.0, "{d}");
    assert!((dir_to_uv(d) - Vec2::new(3.5 / 8.0, 1.5 / 4.0)).length() < 1e-6);
}

#[test]
fn rotation_moves_plus_z_content_to_plus_x() {
    let m = EnvMap::load(&common::asset("grace.hdr")).unwrap();
    let r = m.clone().with_rotation(90.0);
    assert!(
        (r.radiance(Vec3::X) - m.radiance(Vec3::Z)).length()
            < 1e-4 * (1.0 + m.radiance(Vec3::Z).length())
    );
    // Any direction: rotated map at R_y(θ)·d equals the original at d.
    let mut failures = Failures::new();
    for deg in [90.0f32, -30.0, 200.0] {
        failures.case(&format!("{deg}°"), || {
            let r = m.clone().with_rotation(deg);
            let (s, c) = deg.to_radians().sin_cos();
            for i in 0..200 {
                let d = uv_to_dir(Vec2::new(
                    (i as f32 * 0.618).fract(),
                    (i as f32 + 0.5) / 200.0,
                ));
                let rd = Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
                let a = m.radiance(d);
                let b = r.radiance(rd);
                assert!(
                    (a - b).length() <= 1e-3 * (1.0 + a.length()),
                    "{deg}° {d}: {a} vs {b}"
                );
            }
            // texel_dir carries the rotation too.
            let t = r.texel_dir(17, 40);
            let u = m.texel_dir(17, 40);
            assert!((t - Vec3::new(c * u.x + s * u.z, u.y, -s * u.x + c * u.z)).length() < 1e-5);
            // The integral does not change.
            let (a, b) = (m.integral(), r.integral());
            assert!((a[0] - b[0]).abs() < 1e-9 * a[0]);
        });
    }
    failures.assert_none();
}

#[test]
fn solid_angles_sum_to_four_pi() {
    let mut failures = Failures::new();
    for (w, h) in [(8, 4), (256, 128), (1024, 512), (100, 37)] {
        let m = EnvMap::from_texels(w, h, vec![Vec3::ZERO; w * h], "t").unwrap();
        let s: f64 = (0..h)
            .map(|y| m.texel_solid_angle(y) as f64 * w as f64)
            .sum();
        failures.check((s - 4.0 * std::f64::consts::PI).abs() < 1e-4, || {
            format!("{w}×{h}: Σ {s}")
        });
        // Symmetric about the equator, largest there.
        failures.check(
            (m.texel_solid_angle(0) - m.texel_solid_angle(h - 1)).abs() < 1e-7,
            || format!("{w}×{h}: not symmetric about the equator"),
        );
        failures.check(m.texel_solid_angle(h / 2) > m.texel_solid_angle(0), || {
            format!("{w}×{h}: not largest at the equator")
        });
    }
    failures.assert_none();
}

#[test]
fn known_radiance_integrates_exactly() {
    // Uniform radiance L: ∫ = 4πL. Upper hemisphere only: 2πL.
    let (w, h) = (64, 32);
    let m = EnvMap::from_texels(w, h, vec![Vec3::new(1.0, 2.0, 0.5); w * h], "uniform").unwrap();
    let i = m.integral();
    let fp = 4.0 * std::f64::consts::PI;
    assert!(
        (i[0] - fp).abs() < 1e-9
            && (i[1] - 2.0 * fp).abs() < 1e-9
            && (i[2] - 0.5 * fp).abs() < 1e-9
    );
    let texels = (0..w * h)
        .map(|t| if t / w < h / 2 { Vec3::ONE } else { Vec3::ZERO })
        .collect();
    let up = EnvMap::from_texels(w, h, texels, "sky only").unwrap();
    assert!((up.integral()[0] - fp / 2.0).abs() < 1e-9);
    // Intensity scales it.
    let s = m.with_intensity(3.0).unwrap();
    assert!((s.integral()[0] - 3.0 * fp).abs() < 1e-6);
    assert_eq!(s.intensity, 3.0);
}

#[test]
fn shared_maps_load() {
    let mut failures = Failures::new();
    for (name, w, h) in [
        ("grace.hdr", 256, 128),
        ("studio_small_03_1k.hdr", 1024, 512),
        ("rooitou_park_1k.hdr", 1024, 512),
        ("KernerEnvLatLong.exr", 1024, 512),
    ] {
        failures.case(name, || {
            let m = EnvMap::load(&common::asset(name)).unwrap();
            assert_eq!((m.width, m.height), (w, h), "size");
            assert!(m.integral()[1] > 0.0, "black");
        });
    }
    // Peak of rooitou_park is documented at px (614, 226), 6.5e4.
    let m = EnvMap::load(&common::asset("rooitou_park_1k.hdr")).unwrap();
    let peak = (0..m.texels.len()).max_by(|&a, &b| {
        envshadow::envmap::luminance(m.texels[a])
            .total_cmp(&envshadow::envmap::luminance(m.texels[b]))
    });
    failures.check_eq(peak.map(|p| (p % 1024, p / 1024)), Some((614, 226)), || {
        "rooitou_park_1k.hdr: the peak".to_string()
    });
    failures.assert_none();
}

#[test]
fn builtin_sky_is_valid_and_sunny() {
    let m = EnvMap::builtin_sky();
    assert_eq!(m.source, "builtin:sky");
    assert!(
        m.texels
            .iter()
            .all(|t| t.is_finite() && t.min_element() >= 0.0)
    );
    // The ground is dim but not black; the sun dominates.
    assert!(m.radiance(-Vec3::Y).min_element() > 0.0);
    let (mut max, mut arg) = (0.0f32, 0);
    for (i, t) in m.texels.iter().enumerate() {
        if t.y > max {
            max = t.y;
            arg = i;
        }
    }
    let d = m.texel_dir(arg % m.width, arg / m.width);
    assert!(d.x > 0.0 && d.y > 0.4 && d.z > 0.0, "sun at {d}");
    assert!(max > 1000.0 * m.radiance(Vec3::Y).y);
    // Deterministic.
    let again = EnvMap::builtin_sky();
    assert!(
        m.texels
            .iter()
            .zip(&again.texels)
            .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits))
    );
}

#[test]
fn missing_file_is_named() {
    let t = err_text(EnvMap::load(Path::new("/nonexistent/sky.hdr")));
    assert!(
        t.contains("/nonexistent/sky.hdr") && t.contains("not found"),
        "{t}"
    );
}

#[test]
fn wrong_extension_is_named() {
    let t = err_text(EnvMap::load(Path::new("/work/shared/assets/bunny.glb")));
    assert!(t.contains("bunny.glb") && t.contains("'.glb'"), "{t}");
    let t = err_text(EnvMap::load(Path::new("/tmp/noext")));
    assert!(t.contains("noext") && t.contains("extension"), "{t}");
}

#[test]
fn upper_case_extension_loads() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("GRACE.HDR");
    std::fs::copy(common::asset("grace.hdr"), &p).unwrap();
    assert_eq!(EnvMap::load(&p).unwrap().width, 256);
}

#[test]
fn truncated_exr_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = std::fs::read(common::asset("KernerEnvLatLong.exr")).unwrap();
    let p = dir.path().join("half.exr");
    std::fs::write(&p, &bytes[..bytes.len() / 2]).unwrap();
    let t = err_text(EnvMap::load(&p));
    assert!(
        t.contains("half.exr") && t.to_lowercase().contains("exr"),
        "{t}"
    );
}

#[test]
fn bad_hdr_header_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("bad.hdr");
    std::fs::write(&p, b"#?NOTRADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 2\n").unwrap();
    let t = err_text(EnvMap::load(&p));
    assert!(t.contains("bad.hdr") && t.contains("Radiance HDR"), "{t}");
    // A valid header with missing pixels.
    let p = dir.path().join("short.hdr");
    std::fs::write(
        &p,
        b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 4\n\x01\x01",
    )
    .unwrap();
    let t = err_text(EnvMap::load(&p));
    assert!(t.contains("short.hdr"), "{t}");
}

#[test]
fn bad_texels_in_memory_are_named() {
    let mut t = vec![Vec3::ONE; 8 * 4];
    t[2 * 8 + 5] = Vec3::new(1.0, f32::NAN, 0.0);
    let e = err_text(EnvMap::from_texels(8, 4, t, "mem.hdr"));
    assert!(
        e.contains("mem.hdr") && e.contains("texel (5, 2)") && e.contains("NaN"),
        "{e}"
    );
    let mut t = vec![Vec3::ONE; 8 * 4];
    t[7] = Vec3::new(1.0, 1.0, -0.5);
    let e = err_text(EnvMap::from_texels(8, 4, t, "mem.hdr"));
    assert!(
        e.contains("texel (7, 0)") && e.contains("negative") && e.contains("-0.5"),
        "{e}"
    );
    let mut t = vec![Vec3::ONE; 8 * 4];
    t[0] = Vec3::splat(f32::INFINITY);
    let e = err_text(EnvMap::from_texels(8, 4, t, "mem.hdr"));
    assert!(e.contains("texel (0, 0)") && e.contains("infinite"), "{e}");
    let e = err_text(EnvMap::from_texels(0, 4, vec![], "empty"));
    assert!(e.contains("empty") && e.contains("zero size"), "{e}");
    let e = err_text(EnvMap::from_texels(1 << 15, 1 << 14, vec![], "huge"));
    assert!(e.contains("huge") && e.contains("too large"), "{e}");
    let e = err_text(EnvMap::from_texels(4, 4, vec![Vec3::ONE; 3], "short"));
    assert!(e.contains("short") && e.contains("3 texels"), "{e}");
}

#[test]
fn nan_texel_in_exr_file_is_named() {
    use exr::prelude::*;
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("nan.exr");
    write_rgb_file(&p, 8, 4, |x, y| {
        if (x, y) == (3, 2) {
            (f32::NAN, 0.0f32, 0.0f32)
        } else {
            (1.0, 1.0, 1.0)
        }
    })
    .unwrap();
    let e = err_text(EnvMap::load(&p));
    assert!(
        e.contains("nan.exr") && e.contains("texel (3, 2)") && e.contains("NaN"),
        "{e}"
    );
    // Negative, and an RGB file without alpha that is otherwise fine.
    let p = dir.path().join("neg.exr");
    write_rgb_file(&p, 8, 4, |x, _| {
        (1.0f32, if x == 6 { -2.0f32 } else { 0.5 }, 0.0f32)
    })
    .unwrap();
    let e = err_text(EnvMap::load(&p));
    assert!(
        e.contains("neg.exr") && e.contains("texel (6, 0)") && e.contains("negative"),
        "{e}"
    );
    let p = dir.path().join("ok.exr");
    write_rgb_file(&p, 8, 4, |x, y| (x as f32, y as f32, 0.25f32)).unwrap();
    let m = EnvMap::load(&p).unwrap();
    assert_eq!(m.texel(5, 3), Vec3::new(5.0, 3.0, 0.25));
}

#[test]
fn bad_intensity_is_refused() {
    let m = EnvMap::builtin_sky();
    let mut failures = Failures::new();
    for s in [f32::NAN, -1.0, f32::INFINITY] {
        failures.case(&format!("intensity {s}"), || {
            let e = m.clone().with_intensity(s).expect_err("refused");
            let t = format!("{e:#}");
            assert!(t.starts_with("intensity:"), "{t}");
        });
    }
    failures.assert_none();
}

/// Issue 20, item 6: a map's size is read from its header alone, so the scene is checked against
/// the memory budget with the map it will be lit by, before either is decoded.
#[test]
fn the_declared_size_comes_from_the_header() {
    for name in [
        "OrientationLatLong.exr",
        "grace.hdr",
        "KernerEnvLatLong.exr",
    ] {
        let p = common::asset(name);
        let m = EnvMap::load(&p).unwrap();
        let len = std::fs::metadata(&p).unwrap().len();
        assert_eq!(
            EnvMap::declared_size(&p),
            Some(((m.width * m.height) as u64, len)),
            "{name}"
        );
    }
    let dir = tempfile::tempdir().unwrap();
    // Only a header: 16384 × 8192 declared, no pixels.
    let p = dir.path().join("header.hdr");
    let header = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 16384\n";
    std::fs::write(&p, header).unwrap();
    assert_eq!(
        EnvMap::declared_size(&p),
        Some((16384 * 8192, header.len() as u64))
    );
    // What cannot be read gives nothing (the load reports it): a broken header, a missing file,
    // a device.
    std::fs::write(dir.path().join("broken.hdr"), b"#?NOTRADIANCE\n").unwrap();
    for p in [
        dir.path().join("broken.hdr"),
        dir.path().join("absent.exr"),
        Path::new("/dev/zero").to_path_buf(),
    ] {
        assert_eq!(EnvMap::declared_size(&p), None, "{}", p.display());
    }
}
