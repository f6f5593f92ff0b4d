//! Structured importance sampling (Agarwal, Ramamoorthi, Belongie & Jensen 2003), as outlined in
//! ALGORITHM.md §1: only the light directions; energies come from the Voronoi cells (see
//! [`super`]).
//!
//! 1. Luminance Y (Rec.709) and solid angle Δω per texel; solid-angle-weighted mean μ and
//!    standard deviation σ of Y over the sphere.
//! 2. Nested layers: layer 0 is the whole sphere [ours: so dim regions get lights too, otherwise
//!    they would only be covered by the huge cells of far-away lights]; layer i = 1..5 is
//!    {Y ≥ threshold_i} (see [`Thresholds`]). The connected components of a layer (4-connected,
//!    wrapping in longitude) are its strata; each stratum of layer i+1 lies inside one of layer i.
//! 3. Stratum C's sample count is N·Γ(C)/Γ(sphere) with Γ = (Σ_C Y·Δω)·min(Δω_C, 0.01 sr)^(1/4)
//!    [paper, via SIS]. Counts are inclusive (they count the samples of the strata nested inside),
//!    so the sphere gets exactly N. Γ is monotone under nesting, so the children's quotas fit in
//!    their parent's; integers come from largest-remainder rounding inside each parent (ties to
//!    the lower stratum index), capped by the stratum's texel count.
//! 4. Placement, brightest layer first: a stratum keeps the samples its nested strata placed and
//!    adds the rest by farthest-point selection (largest angular distance to the samples already in
//!    it) among its texel centres, starting from its brightest texel when it has none. Strata
//!    larger than [`MAX_CANDIDATES`] texels use a deterministic subset of roughly uniform density
//!    on the sphere (every s-th row, every s·round(1/cos lat)-th column) plus their brightest texel.
//!
//! Everything is sequential and seedless: the same map gives the same bits.

use glam::{Vec2, Vec3};

use crate::envmap::{EnvMap, luminance, uv_to_dir};

/// Farthest-point candidates per stratum at most (the cost is candidates × samples).
pub const MAX_CANDIDATES: usize = 32_768;
/// Number of layers above the base layer 0.
pub const LAYERS: usize = 5;

/// Where layers 1..5 start.
///
/// Measured, and asserted, by `lights::sis_default_thresholds_are_accurate_and_the_better_rule`
/// (tests/it/lights.rs): the RMS error of unshadowed diffuse
/// irradiance E(n) = Σ_j E_j max(0, n·ω_j) against the map's exact irradiance over 300 normals,
/// relative to the mean irradiance. On grace, rooitou_park and the built-in sky both rules give
/// identical lights (σ ≫ μ there). Where they differ, μ + i·σ was better in 4 of 5 cases
/// (studio_small_03 N=200: 0.52 % vs 0.66 %; Kerner N=50/200/400: 1.15/0.32/0.17 % vs
/// 1.70/0.33/0.20 %) and worse in one (studio N=400: 0.36 % vs 0.31 %), so it is the default.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Thresholds {
    /// {Y ≥ i·σ}, as written in the spec.
    Sigma,
    /// {Y ≥ μ + i·σ}: layer 1 starts above the mean.
    #[default]
    MuPlusSigma,
}

struct Stratum {
    layer: usize,
    /// Index (into the stratum list) of the enclosing stratum of the layer below; root: itself.
    parent: usize,
    texels: Vec<u32>,
    gamma: f64,
    count: usize,
    samples: Vec<Vec3>,
}

/// `n` unit light directions for `env` (world space, rotation applied).
pub fn directions(env: &EnvMap, n: usize, thresholds: Thresholds) -> Vec<Vec3> {
    let texels = Texels::new(env);
    let (mu, sigma) = texels.mean_and_sigma();
    let mut strata = strata(&texels, n, mu, sigma, thresholds);
    let children = children(&strata);
    share_counts(&mut strata, &children, n);
    place(env, &texels, &mut strata, &children, n)
}

/// Step 1's per-texel quantities of a map.
struct Texels {
    w: usize,
    h: usize,
    /// Luminance Y (Rec.709) per texel, negative values as 0.
    lum: Vec<f32>,
    /// Solid angle Δω of a texel, per row.
    dw: Vec<f64>,
}

impl Texels {
    fn new(env: &EnvMap) -> Texels {
        let (w, h) = (env.width, env.height);
        Texels {
            w,
            h,
            lum: env.texels.iter().map(|&t| luminance(t).max(0.0)).collect(),
            dw: (0..h).map(|y| env.texel_solid_angle_f64(y)).collect(),
        }
    }

    /// μ and σ of the luminance, weighted by solid angle.
    fn mean_and_sigma(&self) -> (f64, f64) {
        let (w, h, lum, dw) = (self.w, self.h, &self.lum, &self.dw);
        let (mut sum, mut area) = (0.0f64, 0.0f64);
        for y in 0..h {
            for x in 0..w {
                sum += lum[y * w + x] as f64 * dw[y];
            }
            area += dw[y] * w as f64;
        }
        let mu = sum / area;
        let mut var = 0.0f64;
        for y in 0..h {
            for x in 0..w {
                let d = lum[y * w + x] as f64 - mu;
                var += d * d * dw[y];
            }
        }
        (mu, (var / area).sqrt())
    }

    /// Γ of a stratum: (Σ Y·Δω)·min(Δω, 0.01 sr)^(1/4) over its texels.
    fn gamma(&self, texels: &[u32]) -> f64 {
        let (mut e, mut a) = (0.0f64, 0.0f64);
        for &t in texels {
            let y = t as usize / self.w;
            e += self.lum[t as usize] as f64 * self.dw[y];
            a += self.dw[y];
        }
        e * libm::pow(a.min(0.01), 0.25)
    }
}

/// Step 2: the strata, the root (the whole sphere, holding all `n` samples) first, then the
/// components of each layer, layer by layer.
fn strata(map: &Texels, n: usize, mu: f64, sigma: f64, thresholds: Thresholds) -> Vec<Stratum> {
    let all: Vec<u32> = (0..(map.w * map.h) as u32).collect();
    let mut strata = vec![Stratum {
        layer: 0,
        parent: 0,
        gamma: map.gamma(&all),
        texels: all,
        count: n,
        samples: Vec::new(),
    }];
    // owner[t]: the stratum of the current layer holding texel t (u32::MAX: none).
    let mut owner = vec![0u32; map.w * map.h];
    if sigma > 0.0 && strata[0].gamma > 0.0 {
        for layer in 1..=LAYERS {
            let threshold = match thresholds {
                Thresholds::Sigma => layer as f64 * sigma,
                Thresholds::MuPlusSigma => mu + layer as f64 * sigma,
            };
            owner = layer_strata(map, layer, threshold, &owner, &mut strata);
        }
    }
    strata
}

/// Appends the components of {Y ≥ `threshold`} to `strata` as the strata of `layer` (each
/// inside the stratum of the layer below that `owner` names); returns the new owners.
fn layer_strata(
    map: &Texels,
    layer: usize,
    threshold: f64,
    owner: &[u32],
    strata: &mut Vec<Stratum>,
) -> Vec<u32> {
    let (w, h, lum) = (map.w, map.h, &map.lum);
    let mut next = vec![u32::MAX; w * h];
    let mut stack = Vec::new();
    for start in 0..w * h {
        if next[start] != u32::MAX || (lum[start] as f64) < threshold || owner[start] == u32::MAX {
            continue;
        }
        let id = strata.len() as u32;
        let parent = owner[start] as usize;
        let mut texels = Vec::new();
        next[start] = id;
        stack.push(start);
        while let Some(t) = stack.pop() {
            texels.push(t as u32);
            let (x, y) = (t % w, t / w);
            let mut visit = |u: usize| {
                if next[u] == u32::MAX && lum[u] as f64 >= threshold {
                    next[u] = id;
                    stack.push(u);
                }
            };
            visit(y * w + (x + 1) % w);
            visit(y * w + (x + w - 1) % w);
            if y > 0 {
                visit(t - w);
            }
            if y + 1 < h {
                visit(t + w);
            }
        }
        texels.sort_unstable();
        strata.push(Stratum {
            layer,
            parent,
            gamma: map.gamma(&texels),
            texels,
            count: 0,
            samples: Vec::new(),
        });
    }
    next
}

/// Each stratum's children: the strata of the next layer nested inside it.
fn children(strata: &[Stratum]) -> Vec<Vec<usize>> {
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); strata.len()];
    for (i, s) in strata.iter().enumerate().skip(1) {
        children[s.parent].push(i);
    }
    children
}

/// Step 3: counts, top-down: each stratum shares its count among its children.
fn share_counts(strata: &mut [Stratum], children: &[Vec<usize>], n: usize) {
    let gamma_sphere = strata[0].gamma;
    for p in 0..strata.len() {
        let kids = &children[p];
        if kids.is_empty() || strata[p].count == 0 {
            continue;
        }
        let quotas: Vec<f64> = kids
            .iter()
            .map(|&k| n as f64 * strata[k].gamma / gamma_sphere)
            .collect();
        let total: f64 = quotas.iter().sum();
        if total <= 0.0 {
            continue;
        }
        let target = (strata[p].count as f64).min(total.round());
        let scaled: Vec<f64> = quotas.iter().map(|q| q * target / total).collect();
        let mut counts: Vec<usize> = scaled.iter().map(|q| q.floor() as usize).collect();
        let mut left = target as usize - counts.iter().sum::<usize>();
        let mut order: Vec<usize> = (0..kids.len()).collect();
        // Largest remainder first; ties to the lower stratum index (stable sort).
        order.sort_by(|&a, &b| {
            let ra = scaled[a] - scaled[a].floor();
            let rb = scaled[b] - scaled[b].floor();
            rb.total_cmp(&ra)
        });
        for &i in &order {
            if left == 0 {
                break;
            }
            counts[i] += 1;
            left -= 1;
        }
        for (i, &k) in kids.iter().enumerate() {
            strata[k].count = counts[i].min(strata[k].texels.len());
        }
    }
}

/// Step 4: placement, deepest layer first; strata of one layer are disjoint. Returns the root's
/// samples, at most `n`.
fn place(
    env: &EnvMap,
    map: &Texels,
    strata: &mut [Stratum],
    children: &[Vec<usize>],
    n: usize,
) -> Vec<Vec3> {
    let mut by_layer: Vec<usize> = (0..strata.len()).collect();
    by_layer.sort_by_key(|&i| std::cmp::Reverse(strata[i].layer));
    for &i in &by_layer {
        let mut inherited = Vec::new();
        for &k in &children[i] {
            inherited.append(&mut strata[k].samples);
        }
        let want = strata[i].count;
        let mut candidates = candidate_dirs(env, &strata[i].texels, &map.lum);
        if i == 0 && candidates.len() < 4 * n {
            // A tiny map has fewer texels than lights want: add an even spread of extra points.
            candidates.extend(fibonacci_sphere(4 * n));
        }
        strata[i].samples = farthest_points(&candidates, inherited, want);
    }
    let mut out = std::mem::take(&mut strata[0].samples);
    out.truncate(n);
    out
}

/// Texel-centre directions of a stratum: its brightest texel first, then all texels or, for a
/// large stratum, a subset of roughly uniform density on the sphere.
fn candidate_dirs(env: &EnvMap, texels: &[u32], lum: &[f32]) -> Vec<Vec3> {
    let w = env.width;
    let h = env.height;
    let mut brightest = texels[0];
    for &t in texels {
        if lum[t as usize] > lum[brightest as usize] {
            brightest = t;
        }
    }
    let dir = |t: u32| env.texel_dir(t as usize % w, t as usize / w);
    let mut out = vec![dir(brightest)];
    if texels.len() <= MAX_CANDIDATES {
        out.extend(texels.iter().filter(|&&t| t != brightest).map(|&t| dir(t)));
        return out;
    }
    // Column step per row so kept texels are spread evenly in solid angle.
    let col_step: Vec<usize> = (0..h)
        .map(|y| {
            let lat = std::f64::consts::PI * (0.5 - (y as f64 + 0.5) / h as f64);
            ((1.0 / libm::cos(lat)).round() as usize).clamp(1, w)
        })
        .collect();
    let mut s = 2usize;
    loop {
        let keep = |t: u32| {
            let (x, y) = (t as usize % w, t as usize / w);
            y % s == s / 2 && x % (s * col_step[y]) == 0
        };
        let count = texels.iter().filter(|&&t| keep(t)).count();
        if count <= MAX_CANDIDATES {
            out.extend(
                texels
                    .iter()
                    .filter(|&&t| keep(t) && t != brightest)
                    .map(|&t| dir(t)),
            );
            return out;
        }
        s += 1;
    }
}

/// Keeps `selected` and adds candidates until there are `want`, each time the candidate farthest
/// (in angle) from all selected; the first pick, if none is selected, is `candidates[0]`.
/// Ties go to the earlier candidate. Stops early if the candidates are used up.
fn farthest_points(candidates: &[Vec3], mut selected: Vec<Vec3>, want: usize) -> Vec<Vec3> {
    if selected.len() >= want || candidates.is_empty() {
        return selected;
    }
    // max_dot[c] = cos of the angle from candidate c to its nearest selected point.
    let mut max_dot = vec![-2.0f32; candidates.len()];
    for s in &selected {
        for (m, c) in max_dot.iter_mut().zip(candidates) {
            *m = m.max(c.dot(*s));
        }
    }
    while selected.len() < want {
        let pick = if selected.is_empty() {
            0
        } else {
            let mut best = 0;
            for (i, &m) in max_dot.iter().enumerate() {
                if m < max_dot[best] {
                    best = i;
                }
            }
            best
        };
        // Everything left coincides with a selected point.
        if max_dot[pick] >= 1.0 - 1e-7 {
            break;
        }
        let p = candidates[pick];
        selected.push(p);
        for (m, c) in max_dot.iter_mut().zip(candidates) {
            *m = m.max(c.dot(p));
        }
    }
    selected
}

/// `k` nearly evenly spread unit directions (a Fibonacci lattice).
fn fibonacci_sphere(k: usize) -> Vec<Vec3> {
    let golden = (5.0f64.sqrt() - 1.0) / 2.0;
    (0..k)
        .map(|i| {
            let v = (i as f64 + 0.5) / k as f64;
            let u = (i as f64 * golden).fract();
            // Uniform in y = 1 − 2v, so equal areas.
            let vv = libm::acos(1.0 - 2.0 * v) / std::f64::consts::PI;
            uv_to_dir(Vec2::new(u as f32, vv as f32))
        })
        .collect()
}
