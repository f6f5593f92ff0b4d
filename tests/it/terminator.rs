//! The shadow terminator (`[render] terminator_offset`): a coarse, smooth-shaded convex mesh
//! casts no shadow on itself, so wherever a lit point of it comes out darker than the frame
//! without shadows, its own neighbouring facets blocked rays its shading normal let through —
//! the faceted terminator. Hanika's offset lifts the rays' points onto the smooth surface.

use crate::common::{self, Gltf};
use envshadow::output::exr::read_frame;
use serde_json::json;
use std::path::Path;

/// An icosphere of unit radius: the icosahedron's 20 faces, each split into 4 per `levels`,
/// with every vertex's normal its direction from the centre (smooth shading).
fn icosphere(levels: u32) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut v: Vec<[f32; 3]> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .to_vec();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let unit = |p: [f32; 3]| {
        let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        p.map(|c| c / l)
    };
    for p in &mut v {
        *p = unit(*p);
    }
    for _ in 0..levels {
        let mut mids = std::collections::HashMap::new();
        let mut mid = |a: u32, b: u32, v: &mut Vec<[f32; 3]>| {
            *mids.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (v[a as usize], v[b as usize]);
                v.push(unit([p[0] + q[0], p[1] + q[1], p[2] + q[2]]));
                v.len() as u32 - 1
            })
        };
        let mut next = Vec::new();
        for [a, b, c] in f {
            let (ab, bc, ca) = (mid(a, b, &mut v), mid(b, c, &mut v), mid(c, a, &mut v));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = next;
    }
    (v, f)
}

/// Writes the icosphere as `name.glb` in `dir`, standing on y = 0.
fn write_icosphere(dir: &Path, levels: u32) -> std::path::PathBuf {
    let (v, f) = icosphere(levels);
    let mut g = Gltf::default();
    let pos: Vec<f32> = v.iter().flat_map(|p| [p[0], p[1] + 1.0, p[2]]).collect();
    let nrm: Vec<f32> = v.iter().flatten().copied().collect();
    let idx: Vec<u32> = f.iter().flatten().copied().collect();
    let (p, n, i) = (
        g.floats("VEC3", &pos),
        g.floats("VEC3", &nrm),
        g.indices(&idx),
    );
    g.write_glb(
        dir,
        &format!("icosphere-{}", f.len()),
        json!({
            "meshes": [{"primitives": [{"attributes": {"POSITION": p, "NORMAL": n}, "indices": i}]}],
            "nodes": [{"mesh": 0}],
            "scenes": [{"nodes": [0]}],
            "scene": 0,
        }),
    )
}

/// Renders `model` under the built-in sky with no ground (nothing but the sphere can cast a
/// shadow on it), Lambertian, 1 spp, and returns the beauty's R, G, B planes.
fn render(dir: &Path, model: &Path, method: &str, offset: bool) -> Vec<[f32; 3]> {
    let name = format!("{method}-{offset}");
    let spec = dir.join(format!("{name}.toml"));
    std::fs::write(
        &spec,
        format!(
            "name = \"{name}\"\n[scene]\nfile = {model:?}\nground = \"none\"\n\
             [environment]\nbuiltin = \"sky\"\n[lights]\ncount = 200\n\
             [camera]\ntarget = [0.0, 1.0, 0.0]\ndistance = 4.0\nelevation = 10.0\nazimuth = 60.0\nvfov = 40.0\n\
             [motion]\nkind = \"none\"\nframes = 1\n\
             [render]\nwidth = 96\nheight = 96\nmethod = \"{method}\"\nbackground = \"color\"\n\
             background_color = [0.0, 0.0, 0.0]\nterminator_offset = {offset}\n\
             [material]\nlambert = true\n[output]\ndir = {:?}\n",
            dir.join(&name)
        ),
    )
    .unwrap();
    let o = common::bin()
        .arg("render")
        .arg(&spec)
        .arg("-q")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let f = read_frame(&dir.join(&name).join("frame_0000.exr")).unwrap();
    let (r, g, b) = (
        f.channel("R").unwrap(),
        f.channel("G").unwrap(),
        f.channel("B").unwrap(),
    );
    (0..r.len()).map(|i| [r[i], g[i], b[i]]).collect()
}

/// The share of the sphere's pixels that exact shadows (brute force) make more than 1 %
/// darker than no shadows at all.
fn self_shadowed(exact: &[[f32; 3]], unshadowed: &[[f32; 3]]) -> f64 {
    let lum = |c: [f32; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    let on: Vec<usize> = (0..unshadowed.len())
        .filter(|&i| lum(unshadowed[i]) > 0.0)
        .collect();
    assert!(on.len() > 1000, "the sphere covers {} pixels", on.len());
    let dark = on
        .iter()
        .filter(|&&i| lum(exact[i]) < 0.99 * lum(unshadowed[i]))
        .count();
    dark as f64 / on.len() as f64
}

/// Faceted icospheres of 20 and 80 faces: without the offset their own facets shadow a band
/// of lit pixels (the terminator's steps); with it almost none.
#[test]
fn the_terminator_offset_removes_a_coarse_spheres_self_shadowing() {
    let tmp = tempfile::tempdir().unwrap();
    for levels in [0, 1] {
        let model = write_icosphere(tmp.path(), levels);
        let none = render(tmp.path(), &model, "none", true);
        let flat = self_shadowed(&render(tmp.path(), &model, "brute", false), &none);
        let lifted = self_shadowed(&render(tmp.path(), &model, "brute", true), &none);
        eprintln!(
            "{} faces: self-shadowed {flat:.4} flat, {lifted:.4} lifted",
            20 * 4u32.pow(levels)
        );
        assert!(
            flat > 0.005,
            "{levels}: the flat facets shadow only {flat} of the sphere"
        );
        assert!(
            lifted < 0.001,
            "{levels}: with the offset {lifted} of the sphere is still self-shadowed"
        );
    }
}
