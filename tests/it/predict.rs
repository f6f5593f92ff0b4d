//! The prediction methods against brute force, and their independence from tiling and threads.

use crate::common::{self, Failures};

use envshadow::anim::{AnimFlags, Animation};
use envshadow::coordinator::thread_pool;
use envshadow::film::Counts;
use envshadow::film::{Channel, Film};
use envshadow::frame::render_frame;
use envshadow::inputs::Inputs;
use envshadow::key::Key;
use envshadow::predict::{FloodTo, Method, Params};
use envshadow::run::Silent;

/// A method with a flood rule.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Variant {
    method: Method,
    flood_to: FloodTo,
}

impl From<Method> for Variant {
    /// The method with the default flood rule.
    fn from(method: Method) -> Variant {
        Variant {
            method,
            flood_to: Params::DEFAULT.flood_to,
        }
    }
}

impl std::fmt::Display for Variant {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} --flood-to {}", self.method, self.flood_to)
    }
}

/// A small shapes frame under the built-in sky and a small bunny frame under grace.hdr.
fn scenes(width: u32, height: u32, lights: usize) -> Vec<(&'static str, Animation, Inputs)> {
    let shapes = common::animation(&format!(
        "[lights]\ncount = {lights}\n[camera]\ntarget = [0.0, 0.45, 0.0]\ndistance = 6.5\nelevation = 25.0\n\
         [motion]\nframes = 8\n[render]\nwidth = {width}\nheight = {height}\n"
    ));
    let bunny_text = format!(
        "[scene]\nfile = \"{}\"\n[environment]\nfile = \"{}\"\n[lights]\ncount = {lights}\n\
         [camera]\ntarget = [0.0, 0.075, 0.0]\ndistance = 0.45\nelevation = 25.0\n\
         [motion]\nframes = 8\n[render]\nwidth = {width}\nheight = {height}\n",
        common::asset("bunny_on_plane.glb").display(),
        common::asset("grace.hdr").display()
    );
    let bunny = Animation::parse(
        &bunny_text,
        std::path::Path::new("bunny.toml"),
        &AnimFlags::default(),
    )
    .unwrap();
    let si = Inputs::load(&shapes).unwrap();
    let bi = Inputs::load(&bunny).unwrap();
    vec![("shapes", shapes, si), ("bunny", bunny, bi)]
}

/// Every method, those that read the flood rule with each.
fn variants() -> Vec<Variant> {
    let mut v = Vec::new();
    for method in Method::all() {
        for flood_to in FloodTo::ALL {
            let flood_to = if method.reads(Key::FloodTo) {
                flood_to
            } else {
                Params::DEFAULT.flood_to
            };
            let variant = Variant { method, flood_to };
            if !v.contains(&variant) {
                v.push(variant);
            }
        }
    }
    v
}

fn render(
    anim: &Animation,
    inputs: &Inputs,
    v: impl Into<Variant>,
    tile: u32,
    threads: usize,
) -> (Film, Counts) {
    let v = v.into();
    let mut a = anim.clone();
    a.render.method = v.method;
    a.render.flood_to = v.flood_to;
    a.render.tile = tile;
    a.render.validate = true;
    let pool = thread_pool(threads).unwrap();
    let (film, stats) = pool
        .install(|| render_frame(&a, inputs, 1, None, &Silent))
        .unwrap();
    (film, stats.counts)
}

/// Stated bounds on wrong (pixel, light) pairs, in % of queries, for these small frames
/// (predictions are poorer at 160×120 than at 640×480: voters are further apart in the scene).
fn error_bound(v: Variant) -> f64 {
    match (v.method.name(), v.flood_to) {
        ("none", _) => f64::INFINITY,
        ("brute", _) => 0.0,
        ("grid-nowarp-uncertainty", FloodTo::All | FloodTo::ContraryFinest) => 0.15,
        ("grid-nowarp-uncertainty", FloodTo::Contrary) => 0.2,
        // Errors travel along the scan until a boundary trace catches them.
        ("scan-warp-boundary", _) => 2.5,
        // Every voter lies above or to the left: a shadow entering from below or the right is
        // predicted visible by all of them and never traced (BENCHMARKS.md, "A method the
        // paper did not list").
        ("scan-nowarp-uncertainty", _) => 1.5,
        _ => 0.5,
    }
}

// Each test is a table of cases (scene × variant, and tile × threads where they vary): every
// failing case is listed by its label at the end, not only the first.

#[test]
fn every_method_agrees_with_brute_force_within_its_stated_error() {
    let mut failures = Failures::new();
    for (name, anim, inputs) in scenes(160, 120, 100) {
        let (brute, bc) = render(&anim, &inputs, Method::BRUTE, 64, 0);
        failures.check_eq(bc.rays, bc.queries, || format!("{name} brute: rays"));
        for m in variants() {
            if m.method == Method::NONE {
                continue;
            }
            failures.case(&format!("{name} {m}"), || {
                let (film, c) = render(&anim, &inputs, m, 64, 0);
                assert_eq!(c.queries, bc.queries, "the same queries");
                // Where a method traced, it agrees with brute force exactly.
                assert_eq!(c.wrong_traced, 0, "wrong where traced");
                // The validation's reference image is the brute-force image.
                assert!(
                    film.layer(Channel::REFERENCE).unwrap()
                        == brute.layer(Channel::BEAUTY).unwrap(),
                    "the reference image is not the brute-force image"
                );
                let err = c.error_percent();
                assert!(err <= error_bound(m), "{err:.4} % wrong pairs");
                if m.method != Method::BRUTE {
                    let pct = c.percent_traced();
                    assert!(pct < 50.0, "traced {pct:.1} %");
                    assert!(c.rays > 0, "traced nothing");
                }
                // Pixels the method got entirely right match the brute-force image exactly.
                let wrong = film.plane(Channel::Wrong).unwrap();
                for (i, w) in wrong.iter().enumerate() {
                    if *w == 0.0 {
                        assert_eq!(film.beauty(i), brute.beauty(i), "pixel {i}");
                    }
                }
            });
        }
    }
    failures.assert_none();
}

#[test]
fn flooding_to_contrary_lights_saves_rays_only_where_it_can() {
    // Uncertainty methods: `contrary` < `contrary-finest` < `all` in rays (the scanline has no
    // levels: its `contrary-finest` is `all`); boundary methods trace the same under every
    // rule.
    let mut failures = Failures::new();
    for (name, mut anim, inputs) in scenes(160, 120, 100) {
        // The flood rules alone: busy voters ask for more voters where flooding caught a wrong
        // prediction, so under the scan (whose voters are the same pass's pixels) the flood
        // rule would also change the prediction's own queue.
        anim.render.busy_voters = 0;
        for m in Method::all() {
            failures.case(&format!("{name} {m}"), || {
                let all = Variant {
                    method: m,
                    flood_to: FloodTo::All,
                };
                let contrary = Variant {
                    method: m,
                    flood_to: FloodTo::Contrary,
                };
                let finest = Variant {
                    method: m,
                    flood_to: FloodTo::ContraryFinest,
                };
                let (fa, ca) = render(&anim, &inputs, all, 64, 0);
                let (fc, cc) = render(&anim, &inputs, contrary, 64, 0);
                let (ff, cf) = render(&anim, &inputs, finest, 64, 0);
                if m.reads(Key::FloodTo) && m.parts().0 == "grid" {
                    // Contrary at the finest level only: between the two.
                    assert!(
                        cc.rays < cf.rays && cf.rays * 10 < ca.rays * 9,
                        "{} rays, against {} (contrary) and {} (all)",
                        cf.rays,
                        cc.rays,
                        ca.rays
                    );
                    // The coarser levels (pixels with x and y even) flood to all, and read only
                    // coarser pixels: exactly the `all` rule's rays and visibility there.
                    for y in (0..fa.height).step_by(2) {
                        for x in (0..fa.width).step_by(2) {
                            let k = (y * fa.width + x) as usize;
                            assert!(
                                ff.plane(Channel::Rays).unwrap()[k]
                                    == fa.plane(Channel::Rays).unwrap()[k]
                                    && ff.plane(Channel::Visible).unwrap()[k]
                                        == fa.plane(Channel::Visible).unwrap()[k],
                                "({x}, {y}) differs from flooding to all"
                            );
                        }
                    }
                } else {
                    assert_eq!(cf, ca, "contrary-finest against all");
                    assert!(
                        ff.layer(Channel::BEAUTY).unwrap() == fa.layer(Channel::BEAUTY).unwrap()
                            && ff.plane(Channel::Rays).unwrap() == fa.plane(Channel::Rays).unwrap(),
                        "contrary-finest's frame differs from all's"
                    );
                }
                if m.reads(Key::FloodTo) {
                    // Uncertainty flooding: a smaller flood, at least a sixth fewer rays here.
                    assert!(
                        cc.rays * 6 < ca.rays * 5,
                        "{} rays against {}",
                        cc.rays,
                        ca.rays
                    );
                    // The saving is in the flood: the prediction's own queue stays about as
                    // large.
                    assert!(
                        ca.rays_flooded - cc.rays_flooded > ca.rays - cc.rays - ca.rays / 50,
                        "flooded {} against {}",
                        cc.rays_flooded,
                        ca.rays_flooded
                    );
                } else {
                    // Boundary flooding already queues what `contrary` leaves out: same traces.
                    assert_eq!(cc, ca, "contrary against all");
                    assert!(
                        fc.layer(Channel::BEAUTY).unwrap() == fa.layer(Channel::BEAUTY).unwrap()
                            && fc.plane(Channel::Rays).unwrap() == fa.plane(Channel::Rays).unwrap(),
                        "contrary's frame differs from all's"
                    );
                }
            });
        }
    }
    failures.assert_none();
}

#[test]
fn where_the_rays_go_adds_up_for_every_method() {
    let mut failures = Failures::new();
    for (name, anim, inputs) in scenes(160, 120, 100) {
        let h0 = anim.render.h0;
        let mut grid_every = None;
        let mut readers = Vec::new();
        for m in variants() {
            failures.case(&format!("{name} {m}"), || {
                let (film, c) = render(&anim, &inputs, m, 64, 0);
                assert!(
                    c.rays_every_light + c.rays_flooded <= c.rays,
                    "{} + {} of {} rays",
                    c.rays_every_light,
                    c.rays_flooded,
                    c.rays
                );
                assert!(
                    c.flood_fixes <= c.rays_flooded,
                    "more fixes than flooded rays"
                );
                match m.method {
                    Method::NONE => assert_eq!(c.rays + c.flood_fixes, 0, "none traced"),
                    Method::BRUTE => {
                        assert_eq!(c.rays_every_light, c.queries, "every light");
                        assert_eq!(c.rays_flooded + c.flood_fixes, 0, "brute flooded");
                    }
                    _ => {
                        // Every predicting method has voterless pixels (the coarse grid, each
                        // scan block's first pixel), queues lights from its prediction, and
                        // floods; on these small frames flooding always catches some wrong
                        // predictions.
                        assert!(
                            c.rays_every_light > 0 && c.rays_unsure() > 0,
                            "no every-light or no unsure rays"
                        );
                        assert!(c.flood_fixes > 0, "flooding caught nothing");
                    }
                }
                if m.method.parts().0 == "grid" {
                    // The coarse grid traces every light whatever the rules: the same rays in
                    // every grid method, at least those the rays layer shows on the coarse
                    // pixels.
                    let coarse: f32 = (0..film.height)
                        .step_by(h0 as usize)
                        .flat_map(|y| (0..film.width).step_by(h0 as usize).map(move |x| (x, y)))
                        .map(|(x, y)| {
                            film.plane(Channel::Rays).unwrap()[(y * film.width + x) as usize]
                        })
                        .sum();
                    assert!(
                        c.rays_every_light as f32 >= coarse && coarse > 0.0,
                        "every-light rays {} against {coarse} on the coarse pixels",
                        c.rays_every_light
                    );
                    // Rules that trace every light where the voters leave many uncertain
                    // (`--trace-all-share`) trace those pixels' rays on top.
                    if m.method.reads(Key::TraceAllShare) {
                        readers.push((m.to_string(), c.rays_every_light));
                    } else {
                        assert_eq!(
                            *grid_every.get_or_insert(c.rays_every_light),
                            c.rays_every_light,
                            "every-light rays depend on the rules"
                        );
                    }
                }
            });
        }
        let coarse = grid_every.unwrap_or(0);
        for (m, every) in readers {
            failures.case(&format!("{name} {m}"), || {
                assert!(
                    every > coarse,
                    "every-light rays {every}, the coarse grid's alone {coarse}: no pixel traced \
                     every light for its voters' uncertainty"
                );
            });
        }
    }
    failures.assert_none();
}

#[test]
fn tiles_and_threads_give_identical_pixels_and_counts_for_every_method() {
    let mut failures = Failures::new();
    for (name, anim, inputs) in scenes(128, 96, 48) {
        for m in variants() {
            let (reference, rc) = render(&anim, &inputs, m, 0, 1);
            failures.check_eq(rc.halo_pixels, 0, || {
                format!("{name} {m}: a whole-frame tile has no halo")
            });
            for threads in [1, 2] {
                for tile in [8, 16, 64, 0] {
                    failures.case(&format!("{name} {m} tile {tile} threads {threads}"), || {
                        let (film, c) = render(&anim, &inputs, m, tile, threads);
                        common::assert_same_film(&film, &reference);
                        assert_eq!(
                            common::without_halo(c),
                            common::without_halo(rc),
                            "counts differ"
                        );
                    });
                }
            }
        }
    }
    failures.assert_none();
}

#[test]
fn a_region_render_equals_the_same_pixels_of_the_full_frame() {
    use envshadow::tile::Rect;
    let mut failures = Failures::new();
    for (name, anim, inputs) in scenes(128, 96, 48) {
        for m in [
            "grid-nowarp-uncertainty",
            "grid-warp-boundary",
            "scan-warp-boundary",
            "scan-nowarp-uncertainty",
        ] {
            failures.case(&format!("{name} {m}"), || {
                let mut a = anim.clone();
                a.render.method = m.parse().unwrap();
                a.render.tile = 16;
                let (full, _) = render_frame(&a, &inputs, 1, None, &Silent).unwrap();
                let region = Rect::new(37, 21, 101, 66);
                let (part, _) = render_frame(&a, &inputs, 1, Some(region), &Silent).unwrap();
                for y in 0..96u32 {
                    for x in 0..128u32 {
                        let i = (y * 128 + x) as usize;
                        if region.contains(x, y) {
                            assert_eq!(part.beauty(i), full.beauty(i), "({x}, {y})");
                            assert_eq!(
                                part.plane(Channel::Rays).unwrap()[i],
                                full.plane(Channel::Rays).unwrap()[i],
                                "({x}, {y})"
                            );
                        } else {
                            assert_eq!(part.beauty(i), [0.0; 3], "({x}, {y}) outside the region");
                        }
                    }
                }
            });
        }
    }
    failures.assert_none();
}
