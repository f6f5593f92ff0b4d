//! The O(1) cell table behind [`super::LightSet::cell_of`]: a cube map whose texels each list
//! the few lights that can be nearest anywhere inside that texel (conservatively), stored flat.

use glam::Vec3;

/// Candidate lists per cube-map texel: 6 faces × `res` × `res`, CSR (offsets + ids).
#[derive(Clone, Debug, Default)]
pub(crate) struct CellTable {
    res: usize,
    /// `offsets[t]..offsets[t + 1]` indexes `ids` for cube texel `t`.
    offsets: Vec<u32>,
    /// Light ids, ascending within each texel (so ties go to the lower index).
    ids: Vec<u32>,
}

/// Cube face and texel of a direction: face = 2·axis + (negative), then (s, t) in [−1, 1] on it.
#[inline]
fn cube_texel(d: Vec3, res: usize) -> usize {
    let a = d.abs();
    let (face, s, t, m) = if a.x >= a.y && a.x >= a.z {
        (if d.x < 0.0 { 1 } else { 0 }, d.y, d.z, a.x)
    } else if a.y >= a.z {
        (if d.y < 0.0 { 3 } else { 2 }, d.z, d.x, a.y)
    } else {
        (if d.z < 0.0 { 5 } else { 4 }, d.x, d.y, a.z)
    };
    let r = res as f32;
    // `as usize` saturates (NaN → 0), so a degenerate direction still gives a valid texel.
    let i = (((s / m + 1.0) * 0.5 * r) as usize).min(res - 1);
    let j = (((t / m + 1.0) * 0.5 * r) as usize).min(res - 1);
    (face * res + j) * res + i
}

/// The (unnormalised) direction at face coordinates (s, t) ∈ [−1, 1]² of `face`.
fn face_point(face: usize, s: f64, t: f64) -> [f64; 3] {
    let sign = if face % 2 == 1 { -1.0 } else { 1.0 };
    match face / 2 {
        0 => [sign, s, t],
        1 => [t, sign, s],
        _ => [s, t, sign],
    }
}

fn normalized(p: [f64; 3]) -> [f64; 3] {
    let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    [p[0] / l, p[1] / l, p[2] / l]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl CellTable {
    /// Builds the table for unit directions `dirs` (at least one).
    pub(crate) fn build(dirs: &[Vec3]) -> CellTable {
        // ~1–3 candidates per texel for the typical spacing of N lights (≈ sqrt(4π/N) rad).
        let res = ((dirs.len() as f64).sqrt() * 3.0).clamp(8.0, 96.0) as usize;
        let lights: Vec<[f64; 3]> = dirs
            .iter()
            .map(|d| [d.x as f64, d.y as f64, d.z as f64])
            .collect();
        let mut offsets = Vec::with_capacity(6 * res * res + 1);
        let mut ids = Vec::new();
        offsets.push(0u32);
        let mut dots = vec![0.0f64; lights.len()];
        let step = 2.0 / res as f64;
        for face in 0..6 {
            for j in 0..res {
                for i in 0..res {
                    let (s0, t0) = (-1.0 + i as f64 * step, -1.0 + j as f64 * step);
                    let c = normalized(face_point(face, s0 + 0.5 * step, t0 + 0.5 * step));
                    // Angular radius of the texel: the farthest of its corners and edge midpoints.
                    let mut cos_alpha = 1.0f64;
                    for (a, b) in [
                        (0.0, 0.0),
                        (1.0, 0.0),
                        (0.0, 1.0),
                        (1.0, 1.0),
                        (0.5, 0.0),
                        (0.5, 1.0),
                        (0.0, 0.5),
                        (1.0, 0.5),
                    ] {
                        let p = normalized(face_point(face, s0 + a * step, t0 + b * step));
                        cos_alpha = cos_alpha.min(dot(c, p));
                    }
                    // Margin for the corner bound and for f32 rounding in `cube_texel` and in the
                    // dot products that `cell_of` compares.
                    let alpha = libm::acos(cos_alpha.clamp(-1.0, 1.0)) * 1.05 + 1e-5;
                    let mut best = f64::NEG_INFINITY;
                    for (k, l) in lights.iter().enumerate() {
                        dots[k] = dot(c, *l);
                        best = best.max(dots[k]);
                    }
                    // j can be nearest somewhere in the texel only if
                    // angle(c, ω_j) − α ≤ min_k angle(c, ω_k) + α.
                    let limit = libm::acos(best.clamp(-1.0, 1.0)) + 2.0 * alpha;
                    let cos_limit = if limit >= std::f64::consts::PI {
                        -2.0
                    } else {
                        libm::cos(limit)
                    };
                    for (k, &d) in dots.iter().enumerate() {
                        if d >= cos_limit {
                            ids.push(k as u32);
                        }
                    }
                    offsets.push(ids.len() as u32);
                }
            }
        }
        CellTable { res, offsets, ids }
    }

    /// The nearest of `dirs` to `d` (largest f32 dot product, ties to the lower index).
    #[inline]
    pub(crate) fn nearest(&self, dirs: &[Vec3], d: Vec3) -> u32 {
        let t = cube_texel(d, self.res);
        let cands = &self.ids[self.offsets[t] as usize..self.offsets[t + 1] as usize];
        let mut best = cands[0];
        let mut best_dot = dirs[best as usize].dot(d);
        for &k in &cands[1..] {
            let dd = dirs[k as usize].dot(d);
            if dd > best_dot {
                best_dot = dd;
                best = k;
            }
        }
        best
    }

    /// Mean number of candidates per cube texel (for tests and stats).
    pub(crate) fn mean_candidates(&self) -> f64 {
        self.ids.len() as f64 / (self.offsets.len() - 1) as f64
    }
}
