//! Directional lights from an environment map (ALGORITHM.md §1).
//!
//! A sampler ([`sis`] or [`median_cut`]) only places the N light directions. Everything else is
//! shared [ours]: the spherical Voronoi cell of light j is the set of directions closer to ω_j
//! than to any other light; every texel goes to `cell_of(texel direction)`, and light j gets
//! E_j = Σ L·Δω and solid_angle_j = Σ Δω over its texels. So ΣE_j is the map's integral exactly
//! (up to rounding), whatever the sampler did. The same `cell_of` answers the renderer's
//! "which light is this direction in" queries, and cells that share a border are neighbours.

mod json;
mod lookup;
pub mod median_cut;
pub mod picture;
pub mod punctual;
pub mod sis;
pub mod track;

use glam::Vec3;
use std::path::Path;

use crate::bail_input;
use crate::envmap::EnvMap;
use crate::error::Result;
use lookup::CellTable;

pub use json::{parse_json, read_json};
pub use punctual::{Cone, FileLight, PointLight};
pub use track::Tracks;

/// One directional light: the spherical Voronoi cell of `dir` with the map's radiance integrated over it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Unit direction towards the light (world space, environment rotation applied).
    pub dir: Vec3,
    /// E_j = ∫ over the cell of L(ω) dω, RGB.
    pub energy: Vec3,
    /// Solid angle of the cell, steradians.
    pub solid_angle: f32,
}

/// Which sampler places the light directions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Sampler {
    /// Structured importance sampling (Agarwal et al. 2003), the paper's choice.
    #[default]
    Sis,
    /// Median cut (Debevec 2005).
    MedianCut,
}

impl Sampler {
    /// The name used on the command line and in the lights JSON: `sis` or `median-cut`.
    pub fn name(self) -> &'static str {
        match self {
            Sampler::Sis => "sis",
            Sampler::MedianCut => "median-cut",
        }
    }
}

impl std::str::FromStr for Sampler {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Sampler, String> {
        match s {
            "sis" => Ok(Sampler::Sis),
            "median-cut" => Ok(Sampler::MedianCut),
            _ => Err(format!(
                "unknown sampler {s:?}; expected \"sis\" or \"median-cut\""
            )),
        }
    }
}

/// What the lights were sampled from, for the JSON and for logs.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvSummary {
    pub source: String,
    pub rotation_deg: f32,
    pub intensity: f32,
    pub width: usize,
    pub height: usize,
    /// ∫ L dω of the map, RGB.
    pub integral: [f64; 3],
}

impl EnvSummary {
    pub fn of(env: &EnvMap) -> EnvSummary {
        EnvSummary {
            source: env.source.clone(),
            rotation_deg: env.rotation_deg,
            intensity: env.intensity,
            width: env.width,
            height: env.height,
            integral: env.integral(),
        }
    }
}

/// N directional lights, their cells, an O(1) `cell_of` lookup and the cells' adjacency; and
/// the scene file's point and spot lights.
///
/// Every light has a bit in the visibility bitsets: the directional lights first (the map's,
/// then the scene file's: [`lights`](Self::lights)), then the point and spot lights
/// ([`points`](Self::points)). A file's directional light is a site of the cells like a map
/// light; a point or spot light has no cell (its direction differs from pixel to pixel) and no
/// neighbours.
#[derive(Clone, Debug)]
pub struct LightSet {
    /// The directional lights: the map's, then the scene file's.
    pub lights: Vec<Light>,
    /// The scene file's point and spot lights; point light k has bit `lights.len() + k`.
    pub points: Vec<PointLight>,
    /// The scene file's lights, in the file's node order, and where each went.
    pub from_file: Vec<FileLight>,
    /// The sampler that placed the lights; `None` for hand-placed ones ([`LightSet::from_lights`]).
    pub sampler: Option<Sampler>,
    /// The map they came from; `None` for hand-placed lights.
    pub environment: Option<EnvSummary>,
    /// Unit directions the cell table was built for: `lights[j].dir` before [`turned`]
    /// (`turn`) turned them.
    ///
    /// [`turned`]: LightSet::turned
    dirs: Vec<Vec3>,
    /// The turn about +Y applied to `lights` since the table was built: degrees, and its
    /// (sin, cos). A looked-up direction is turned back first.
    turn: Option<(f32, (f32, f32))>,
    table: CellTable,
    /// CSR adjacency: `adj_ids[adj_offsets[j]..adj_offsets[j + 1]]`, ascending.
    adj_offsets: Vec<u32>,
    adj_ids: Vec<u32>,
    /// The same adjacency as bitsets, `ceil(n / 64)` words per light: flooding adds a light's
    /// untraced neighbours with a few word operations instead of a branch per neighbour.
    adj_bits: Vec<u64>,
    /// Per light, the cosine of a cap around its direction that lies wholly inside its cell
    /// ([`cell_of_near`](Self::cell_of_near)'s shortcut); 2 where no cap is safe.
    inner_cos: Vec<f32>,
}

impl LightSet {
    /// Samples `n` lights from `env` with `sampler`. Deterministic. `n == 0` is an error.
    pub fn build(env: &EnvMap, n: usize, sampler: Sampler) -> Result<LightSet> {
        if n == 0 {
            bail_input!("lights", "the number of lights must be at least 1, got 0");
        }
        let dirs = match sampler {
            Sampler::Sis => sis::directions(env, n, sis::Thresholds::default()),
            Sampler::MedianCut => median_cut::directions(env, n),
        };
        debug_assert_eq!(dirs.len(), n);
        let lights = dirs
            .iter()
            .map(|&d| Light {
                dir: d.normalize(),
                energy: Vec3::ZERO,
                solid_angle: 0.0,
            })
            .collect();
        let mut set = LightSet::from_lights(lights);
        set.sampler = Some(sampler);
        set.environment = Some(EnvSummary::of(env));
        set.integrate(env);
        Ok(set)
    }

    /// Builds the set from given lights (directions normalised), e.g. one light for a test.
    /// Energies and solid angles are kept as given. An empty list gives an empty set whose
    /// `cell_of` must not be called.
    pub fn from_lights(mut lights: Vec<Light>) -> LightSet {
        for l in &mut lights {
            // Already-unit directions are kept bit for bit, so a JSON round trip is exact.
            if (l.dir.length_squared() - 1.0).abs() > 1e-6 {
                l.dir = l.dir.normalize_or(Vec3::Y);
            }
        }
        let dirs: Vec<Vec3> = lights.iter().map(|l| l.dir).collect();
        let mut set = LightSet {
            lights,
            points: Vec::new(),
            from_file: Vec::new(),
            sampler: None,
            environment: None,
            table: if dirs.is_empty() {
                CellTable::default()
            } else {
                CellTable::build(&dirs)
            },
            dirs,
            turn: None,
            adj_offsets: Vec::new(),
            adj_ids: Vec::new(),
            adj_bits: Vec::new(),
            inner_cos: Vec::new(),
        };
        set.build_adjacency();
        set.inner_cos = (0..set.dirs.len()).map(|j| set.inner_cap(j)).collect();
        set
    }

    /// Every light: directional, point and spot.
    pub fn len(&self) -> usize {
        self.lights.len() + self.points.len()
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// This set with the scene file's lights added [ours]: directional ones after the map's
    /// (energy colour × lux / 683, [`punctual`]), point and spot lights after those. The map
    /// lights keep the energies integrated over their own cells; the cell lookup and the
    /// adjacency are then rebuilt over every directional light, so a file's sun is a cell of
    /// its own for warping and flooding, and takes the directions nearest to it from its
    /// neighbours' cells for lookups only. More than [`crate::limits::MAX_LIGHTS`] lights in
    /// all is an input error naming `source`.
    pub fn with_scene_lights(
        self,
        scene: &[crate::scene::SceneLight],
        source: &Path,
    ) -> Result<LightSet> {
        if scene.is_empty() {
            return Ok(self);
        }
        let total = self.len() + scene.len();
        if total > crate::limits::MAX_LIGHTS {
            bail_input!(
                source,
                "{} lights of the scene file with {} from the map make {total}; at most {} are allowed",
                scene.len(),
                self.len(),
                crate::limits::MAX_LIGHTS
            );
        }
        let (mut lights, mut points) = (self.lights, self.points);
        // Where each went: a directional index, or a point index (its bit is counted once
        // every directional light is in).
        let old_directional = lights.len();
        let mut from_file: Vec<(FileLight, bool)> = self
            .from_file
            .into_iter()
            .map(|f| {
                let point = f.index >= old_directional;
                let index = if point {
                    f.index - old_directional
                } else {
                    f.index
                };
                (FileLight { index, ..f }, point)
            })
            .collect();
        for l in scene {
            let (index, point) = match punctual::convert(l) {
                punctual::Joined::Directional { dir, energy } => {
                    lights.push(Light {
                        dir,
                        energy,
                        solid_angle: 0.0,
                    });
                    (lights.len() - 1, false)
                }
                punctual::Joined::Point(p) => {
                    points.push(p);
                    (points.len() - 1, true)
                }
            };
            let cone = match l.kind {
                crate::scene::SceneLightKind::Spot { inner, outer } => Some((inner, outer)),
                _ => None,
            };
            let file = FileLight {
                name: l.name.clone(),
                kind: l.kind.name(),
                index,
                color: l.color,
                intensity: l.intensity,
                cone,
            };
            from_file.push((file, point));
        }
        let directional = lights.len();
        let from_file = from_file
            .into_iter()
            .map(|(f, point)| FileLight {
                index: if point {
                    directional + f.index
                } else {
                    f.index
                },
                ..f
            })
            .collect();
        let mut set = LightSet::from_lights(lights);
        set.points = points;
        set.from_file = from_file;
        set.sampler = self.sampler;
        set.environment = self.environment;
        set.adjacency_for_points();
        Ok(set)
    }

    /// The light whose cell contains unit direction `dir` (nearest light; ties to the lower index).
    /// O(1): a cube-map texel lookup and an exact argmax over its few candidates.
    #[inline]
    pub fn cell_of(&self, dir: Vec3) -> u32 {
        self.table.nearest(&self.dirs, self.unturn(dir))
    }

    /// `dir` in the frame the cell table was built in (the set's turn undone).
    #[inline]
    fn unturn(&self, dir: Vec3) -> Vec3 {
        match self.turn {
            None => dir,
            Some((_, (s, c))) => crate::envmap::rotate_y(dir, (-s, c)),
        }
    }

    /// The set turned about the up axis (+Y) by `degrees` beyond its own turn, in the sense
    /// of `[environment] rotation` (+90 moves what was seen along +Z to be seen along +X):
    /// the environment turning rigidly (`[motion] kind = "environment"`). Each direction is
    /// the sampled one turned by the total angle (libm's sine and cosine: the same bits on
    /// every host); energies and solid angles are kept, since the cells turn with their lights.
    /// `cell_of` turns the looked-up direction back and asks the table built for the sampled
    /// directions, so a direction falls in the cell its unturned direction fell in when the
    /// energies were integrated; the adjacency, which a rotation does not change, is kept.
    pub fn turned(&self, degrees: f32) -> LightSet {
        let total = self.turn.map_or(0.0, |t| t.0) + degrees;
        let sc = libm::sincosf(total.to_radians());
        let mut set = self.clone();
        for (l, &d) in set.lights.iter_mut().zip(&self.dirs) {
            l.dir = crate::envmap::rotate_y(d, sc);
        }
        set.turn = Some((total, sc));
        if let Some(e) = &mut set.environment {
            e.rotation_deg += degrees;
        }
        set
    }

    /// [`cell_of`](Self::cell_of) for a direction likely to lie near light `j`'s (a blocker of
    /// light j re-aimed from a neighbouring pixel): the same answer, without the table lookup
    /// when `dir` lies in a cap around light j so small that no other light can be as near.
    #[inline]
    pub fn cell_of_near(&self, dir: Vec3, j: usize) -> u32 {
        let dir = self.unturn(dir);
        if self.dirs[j].dot(dir) >= self.inner_cos[j] {
            j as u32
        } else {
            self.table.nearest(&self.dirs, dir)
        }
    }

    /// The nearest light by brute force over all lights (same rule as [`LightSet::cell_of`]);
    /// for tests and checks.
    pub fn cell_of_brute_force(&self, dir: Vec3) -> u32 {
        let dir = self.unturn(dir);
        let mut best = 0u32;
        let mut best_dot = f32::NEG_INFINITY;
        for (k, d) in self.dirs.iter().enumerate() {
            let dd = d.dot(dir);
            if dd > best_dot {
                best_dot = dd;
                best = k as u32;
            }
        }
        best
    }

    /// Lights whose cells share a border with light `j`'s cell (symmetric, ascending).
    pub fn neighbors(&self, j: usize) -> &[u32] {
        &self.adj_ids[self.adj_offsets[j] as usize..self.adj_offsets[j + 1] as usize]
    }

    /// [`neighbors`](Self::neighbors) of light `j` as a bitset of `ceil(len / 64)` words.
    pub fn neighbor_bits(&self, j: usize) -> &[u64] {
        let w = self.len().div_ceil(64);
        crate::bits::rows(&self.adj_bits, w).row(j)
    }

    /// Mean number of `cell_of` candidates per lookup-table texel.
    pub fn mean_lookup_candidates(&self) -> f64 {
        self.table.mean_candidates()
    }

    /// Sets every light's energy and solid angle from its Voronoi cell: the texels whose
    /// directions it is nearest to [ours]. f64 sums, so ΣE_j matches `env.integral()`.
    fn integrate(&mut self, env: &EnvMap) {
        let n = self.lights.len();
        let mut energy = vec![[0.0f64; 3]; n];
        let mut solid = vec![0.0f64; n];
        for y in 0..env.height {
            let dw = env.texel_solid_angle_f64(y);
            for x in 0..env.width {
                let j = self.cell_of(env.texel_dir(x, y)) as usize;
                let t = env.texel(x, y);
                energy[j][0] += t.x as f64 * dw;
                energy[j][1] += t.y as f64 * dw;
                energy[j][2] += t.z as f64 * dw;
                solid[j] += dw;
            }
        }
        for (j, l) in self.lights.iter_mut().enumerate() {
            l.energy = Vec3::new(
                energy[j][0] as f32,
                energy[j][1] as f32,
                energy[j][2] as f32,
            );
            l.solid_angle = solid[j] as f32;
        }
    }

    /// Cell adjacency by sampling [ours]: a fine lat-long grid over the whole sphere (wrapping
    /// in longitude) plus, around each light, a small gnomonic grid scaled to its nearest
    /// neighbour's distance, so tiny cells (a cluster of lights on a sun) are resolved too.
    /// Two samples next to each other in different cells make their lights candidate neighbours;
    /// each candidate pair is then checked exactly ([`LightSet::share_border`]), which drops the
    /// pairs that sampling finds across a Voronoi vertex (the mean degree is then 6 − 12/N, as
    /// Euler's formula wants for a spherical Voronoi diagram).
    /// A light whose neighbours were all missed gets its nearest other light.
    fn build_adjacency(&mut self) {
        let n = self.dirs.len();
        let mut pairs: Vec<(u32, u32)> = Vec::new();
        let add = |a: u32, b: u32, pairs: &mut Vec<(u32, u32)>| {
            if a != b {
                pairs.push((a.min(b), a.max(b)));
            }
        };
        if n >= 2 {
            // Global grid: about 8 samples across a typical cell.
            let h = (((n as f64).sqrt() * 40.0) as usize).clamp(256, 1024);
            let w = 2 * h;
            let mut prev_row = vec![0u32; w];
            let mut row = vec![0u32; w];
            for y in 0..h {
                for (x, cell) in row.iter_mut().enumerate() {
                    let uv =
                        glam::Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                    *cell = self.cell_of(crate::envmap::uv_to_dir(uv));
                }
                for x in 0..w {
                    add(row[x], row[(x + 1) % w], &mut pairs);
                    if y > 0 {
                        add(row[x], prev_row[x], &mut pairs);
                    }
                }
                std::mem::swap(&mut row, &mut prev_row);
            }
            // Local grids around each light.
            const L: usize = 24;
            let mut grid = vec![0u32; L * L];
            for j in 0..n {
                let d = self.dirs[j];
                let nearest = self.nearest_other(j);
                let angle = libm::acosf(d.dot(self.dirs[nearest as usize]).clamp(-1.0, 1.0));
                let half = libm::tanf((1.5 * angle).min(1.2));
                let (t1, t2) = d.any_orthonormal_pair();
                for gy in 0..L {
                    for gx in 0..L {
                        let a = ((gx as f32 + 0.5) / L as f32 * 2.0 - 1.0) * half;
                        let b = ((gy as f32 + 0.5) / L as f32 * 2.0 - 1.0) * half;
                        grid[gy * L + gx] = self.cell_of((d + a * t1 + b * t2).normalize());
                    }
                }
                for gy in 0..L {
                    for gx in 0..L {
                        let c = grid[gy * L + gx];
                        if gx + 1 < L {
                            add(c, grid[gy * L + gx + 1], &mut pairs);
                        }
                        if gy + 1 < L {
                            add(c, grid[(gy + 1) * L + gx], &mut pairs);
                        }
                    }
                }
            }
            pairs.sort_unstable();
            pairs.dedup();
            // Sampling can pair two cells that only come close near a Voronoi vertex; keep
            // only the pairs whose shared border really exists.
            pairs.retain(|&(a, b)| self.share_border(a as usize, b as usize));
            let mut has = vec![false; n];
            for &(a, b) in &pairs {
                has[a as usize] = true;
                has[b as usize] = true;
            }
            for (j, _) in has.iter().enumerate().filter(|(_, h)| !**h) {
                add(j as u32, self.nearest_other(j), &mut pairs);
            }
            pairs.sort_unstable();
            pairs.dedup();
        }
        let mut degree = vec![0u32; n + 1];
        for &(a, b) in &pairs {
            degree[a as usize] += 1;
            degree[b as usize] += 1;
        }
        let mut offsets = vec![0u32; n + 1];
        for j in 0..n {
            offsets[j + 1] = offsets[j] + degree[j];
        }
        let mut fill = offsets.clone();
        let mut ids = vec![0u32; offsets[n] as usize];
        for &(a, b) in &pairs {
            ids[fill[a as usize] as usize] = b;
            fill[a as usize] += 1;
            ids[fill[b as usize] as usize] = a;
            fill[b as usize] += 1;
        }
        for j in 0..n {
            ids[offsets[j] as usize..offsets[j + 1] as usize].sort_unstable();
        }
        self.adj_offsets = offsets;
        self.adj_ids = ids;
        self.adjacency_for_points();
    }

    /// Gives the point and spot lights (after the directional ones) no neighbours, and makes
    /// the adjacency bitsets as wide as every light's bitset.
    pub(super) fn adjacency_for_points(&mut self) {
        let (n, total) = (self.dirs.len(), self.len());
        self.adj_offsets.truncate(n + 1);
        let end = self.adj_offsets[n];
        self.adj_offsets.resize(total + 1, end);
        let w = total.div_ceil(64);
        let mut bits = vec![0u64; total * w];
        for j in 0..n {
            let ids = &self.adj_ids[self.adj_offsets[j] as usize..self.adj_offsets[j + 1] as usize];
            for &a in ids {
                bits[j * w + (a as usize >> 6)] |= 1 << (a & 63);
            }
        }
        self.adj_bits = bits;
    }

    /// Whether the cells of lights `a` and `b` share a border of positive length: some arc of
    /// their bisector great circle has no other light nearer. Every other light c cuts the
    /// circle to the half where (ω_a − ω_c)·p ≥ 0; the intersection of these half-circles is one
    /// arc (or empty). Coincident lights count as sharing a border.
    fn share_border(&self, a: usize, b: usize) -> bool {
        use std::f64::consts::{FRAC_PI_2, PI, TAU};
        let v = |d: Vec3| glam::DVec3::new(d.x as f64, d.y as f64, d.z as f64);
        let (da, db) = (v(self.dirs[a]), v(self.dirs[b]));
        let Some(m) = (da - db).try_normalize() else {
            return true;
        };
        let (e1, e2) = m.any_orthonormal_pair();
        let mut arc: Option<(f64, f64)> = None;
        for (c, &dc) in self.dirs.iter().enumerate() {
            if c == a || c == b {
                continue;
            }
            let g = da - v(dc);
            let (x, y) = (g.dot(e1), g.dot(e2));
            if libm::hypot(x, y) < 1e-12 {
                continue;
            }
            let phi = libm::atan2(y, x);
            arc = Some(match arc {
                None => (phi - FRAC_PI_2, phi + FRAC_PI_2),
                Some((lo, hi)) => {
                    let mid = 0.5 * (lo + hi);
                    let phi = phi + TAU * ((mid - phi) / TAU).round();
                    let (lo, hi) = (lo.max(phi - FRAC_PI_2), hi.min(phi + FRAC_PI_2));
                    if hi - lo <= 1e-7 {
                        return false;
                    }
                    debug_assert!(hi - lo <= PI + 1e-9);
                    (lo, hi)
                }
            });
        }
        true
    }

    /// Cosine of light `j`'s cap behind [`cell_of_near`](Self::cell_of_near). Within half the
    /// angle θ to the nearest other light a direction is strictly nearer to its own light than
    /// to any other; the cap keeps 0.45 θ, so the dot products `cell_of` compares differ by
    /// about 0.05 θ², far above f32 rounding for θ ≥ 0.01 rad (4096 lights lie about 0.05 rad
    /// apart; a near-tie for the nearest other light changes θ by rounding only). Closer lights
    /// get no cap (cosine 2: never taken); a single light owns the sphere (−2: always).
    fn inner_cap(&self, j: usize) -> f32 {
        if self.dirs.len() < 2 {
            return -2.0;
        }
        let (a, b) = (self.dirs[j], self.dirs[self.nearest_other(j) as usize]);
        let cos = a.x as f64 * b.x as f64 + a.y as f64 * b.y as f64 + a.z as f64 * b.z as f64;
        let theta = libm::acos(cos.clamp(-1.0, 1.0));
        if theta < 0.01 {
            2.0
        } else {
            libm::cos(0.45 * theta) as f32
        }
    }

    /// The light nearest to light `j` other than itself (ties to the lower index).
    fn nearest_other(&self, j: usize) -> u32 {
        let mut best = if j == 0 { 1 } else { 0 };
        let mut best_dot = f32::NEG_INFINITY;
        for (k, d) in self.dirs.iter().enumerate() {
            if k != j {
                let dd = d.dot(self.dirs[j]);
                if dd > best_dot {
                    best_dot = dd;
                    best = k;
                }
            }
        }
        best as u32
    }

    /// Sum of the lights' energies, f64.
    pub fn total_energy(&self) -> [f64; 3] {
        let mut s = [0.0f64; 3];
        for l in &self.lights {
            s[0] += l.energy.x as f64;
            s[1] += l.energy.y as f64;
            s[2] += l.energy.z as f64;
        }
        s
    }

    /// The set as JSON (format in [`json`]).
    pub fn to_json(&self) -> serde_json::Value {
        json::to_json(self)
    }

    /// Writes [`LightSet::to_json`] to `path` atomically ([`crate::output::write_atomic`]).
    pub fn write_json(&self, path: &Path) -> Result<()> {
        let text = serde_json::to_string_pretty(&self.to_json())?;
        crate::output::write_atomic(path, text.as_bytes())
    }
}
