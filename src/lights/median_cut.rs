//! Median cut (Debevec 2005) as the second sampler: only the light directions; energies come
//! from the Voronoi cells (see [`super`]).
//!
//! A region is a rectangle of texels with a number of lights k. While k > 1 it is split across
//! its longer side, measured in angle (a row's width is scaled by cos latitude), so that the
//! energy (luminance · Δω) on each side is proportional to the lights it gets (⌊k/2⌋ and ⌈k/2⌉),
//! which lets N be any number, not only a power of two. A region of one texel that still has
//! k > 1 lights (a very bright texel, e.g. a sun) gets them on a small ring inside the texel,
//! so no two lights coincide (their cells may hold no texel centre: zero energy).
//! Each light sits at its region's energy centroid: the normalised mean direction weighted by
//! luminance · Δω (the solid-angle centroid for a black region).

use glam::{Vec2, Vec3};

use crate::envmap::{EnvMap, luminance};

struct Region {
    x0: usize,
    x1: usize,
    y0: usize,
    y1: usize,
    k: usize,
}

/// `n` unit light directions for `env` (world space, rotation applied).
pub fn directions(env: &EnvMap, n: usize) -> Vec<Vec3> {
    let (w, h) = (env.width, env.height);
    let dw: Vec<f64> = (0..h).map(|y| env.texel_solid_angle_f64(y)).collect();
    let weight: Vec<f64> = (0..w * h)
        .map(|t| luminance(env.texels[t]).max(0.0) as f64 * dw[t / w])
        .collect();
    let mut out = Vec::with_capacity(n);
    let mut stack = vec![Region {
        x0: 0,
        x1: w,
        y0: 0,
        y1: h,
        k: n,
    }];
    // Depth-first, lower half first: a fixed order, so the output order is deterministic.
    while let Some(r) = stack.pop() {
        if r.k == 1 {
            out.push(centroid(env, &r, &weight, &dw));
            continue;
        }
        let (rw, rh) = (r.x1 - r.x0, r.y1 - r.y0);
        if rw == 1 && rh == 1 {
            out.extend(ring_in_texel(env, r.x0, r.y0, r.k));
            continue;
        }
        // Angular extents: width at the region's middle latitude.
        let mid_lat = std::f64::consts::PI * (0.5 - (r.y0 + r.y1) as f64 / (2.0 * h as f64));
        let ang_w = rw as f64 / w as f64 * std::f64::consts::TAU * libm::cos(mid_lat);
        let ang_h = rh as f64 / h as f64 * std::f64::consts::PI;
        let split_x = rh == 1 || (rw > 1 && ang_w >= ang_h);
        let k_lo = r.k / 2;
        let k_hi = r.k - k_lo;
        // Energy per column or per row of the region; solid angle if the region is black.
        let lines: Vec<f64> = if split_x {
            (r.x0..r.x1)
                .map(|x| (r.y0..r.y1).map(|y| weight[y * w + x]).sum())
                .collect()
        } else {
            (r.y0..r.y1)
                .map(|y| (r.x0..r.x1).map(|x| weight[y * w + x]).sum())
                .collect()
        };
        let mut total: f64 = lines.iter().sum();
        let lines = if total > 0.0 {
            lines
        } else if split_x {
            vec![1.0; rw]
        } else {
            (r.y0..r.y1).map(|y| dw[y]).collect()
        };
        if total <= 0.0 {
            total = lines.iter().sum();
        }
        let goal = total * k_lo as f64 / r.k as f64;
        // The cut s (lines [0, s) below) with cumulative energy closest to the goal, 1 ≤ s < len.
        let mut best = 1;
        let mut best_err = f64::INFINITY;
        let mut cum = 0.0;
        for (s, l) in lines.iter().enumerate().take(lines.len() - 1) {
            cum += l;
            let err = (cum - goal).abs();
            if err < best_err {
                best_err = err;
                best = s + 1;
            }
        }
        let (lo, hi) = if split_x {
            (
                Region {
                    x1: r.x0 + best,
                    k: k_lo,
                    ..r
                },
                Region {
                    x0: r.x0 + best,
                    k: k_hi,
                    ..r
                },
            )
        } else {
            (
                Region {
                    y1: r.y0 + best,
                    k: k_lo,
                    ..r
                },
                Region {
                    y0: r.y0 + best,
                    k: k_hi,
                    ..r
                },
            )
        };
        stack.push(hi);
        stack.push(lo);
    }
    out
}

/// Normalised mean direction of a region weighted by luminance · Δω, or by Δω if it is black;
/// its brightest (or first) texel if the mean vanishes (a whole sphere of uniform light).
fn centroid(env: &EnvMap, r: &Region, weight: &[f64], dw: &[f64]) -> Vec3 {
    let w = env.width;
    let total: f64 = (r.y0..r.y1)
        .flat_map(|y| (r.x0..r.x1).map(move |x| (x, y)))
        .map(|(x, y)| weight[y * w + x])
        .sum();
    let mut acc = [0.0f64; 3];
    let mut mass = 0.0f64;
    let (mut bx, mut by, mut bw) = (r.x0, r.y0, -1.0f64);
    for y in r.y0..r.y1 {
        for x in r.x0..r.x1 {
            let m = if total > 0.0 {
                weight[y * w + x]
            } else {
                dw[y]
            };
            if m > bw {
                (bx, by, bw) = (x, y, m);
            }
            let d = env.texel_dir(x, y);
            acc[0] += m * d.x as f64;
            acc[1] += m * d.y as f64;
            acc[2] += m * d.z as f64;
            mass += m;
        }
    }
    let len = (acc[0] * acc[0] + acc[1] * acc[1] + acc[2] * acc[2]).sqrt();
    if mass > 0.0 && len > 1e-6 * mass {
        Vec3::new(
            (acc[0] / len) as f32,
            (acc[1] / len) as f32,
            (acc[2] / len) as f32,
        )
    } else {
        env.texel_dir(bx, by)
    }
}

/// `k` distinct directions inside texel (x, y): a ring around its centre at a quarter texel.
fn ring_in_texel(env: &EnvMap, x: usize, y: usize, k: usize) -> Vec<Vec3> {
    let (w, h) = (env.width as f32, env.height as f32);
    (0..k)
        .map(|i| {
            let a = std::f32::consts::TAU * i as f32 / k as f32;
            let uv = Vec2::new(
                (x as f32 + 0.5 + 0.25 * libm::cosf(a)) / w,
                (y as f32 + 0.5 + 0.25 * libm::sinf(a)) / h,
            );
            env.to_world(crate::envmap::uv_to_dir(uv))
        })
        .collect()
}
