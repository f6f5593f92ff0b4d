//! What the camera sees where its rays leave the scene (`[render] background`): the
//! environment (the default), nothing (transparent: alpha 0, for compositing), a flat colour,
//! or the environment blurred. The lights always come from the environment itself: the
//! background changes what is seen, not what lights the scene.
//!
//! The blurred background is a prefiltered low-resolution copy of the map, computed once per
//! run from the map alone (deterministic sums in a fixed order, `libm` maths): a Gaussian of
//! `background_blur` degrees (its standard deviation, as an angle on the sphere).

use std::fmt;

use glam::Vec3;

use crate::envmap::EnvMap;
use crate::error::Result;

/// `[render] background`: what rays that leave the scene see.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Background {
    /// The environment map, as it lights the scene.
    #[default]
    Environment,
    /// Nothing: alpha 0 (the beauty is premultiplied; see `crate::film::Film::alpha`).
    Transparent,
    /// `background_color`, opaque.
    Color,
    /// The environment blurred by `background_blur` degrees.
    Blurred,
}

impl std::str::FromStr for Background {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Background, String> {
        match s {
            "environment" => Ok(Background::Environment),
            "transparent" => Ok(Background::Transparent),
            "color" | "colour" => Ok(Background::Color),
            "blurred" => Ok(Background::Blurred),
            _ => Err(format!(
                "unknown background {s:?} (expected environment, transparent, color or blurred)"
            )),
        }
    }
}

impl fmt::Display for Background {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Background::Environment => "environment",
            Background::Transparent => "transparent",
            Background::Color => "color",
            Background::Blurred => "blurred",
        })
    }
}

/// A linear RGB colour as a setting: `[r, g, b]` in a spec, `r,g,b` on the command line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rgb(pub [f32; 3]);

impl std::str::FromStr for Rgb {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Rgb, String> {
        let v: Vec<f32> = s
            .trim_matches(['[', ']'])
            .split(',')
            .map(|t| t.trim().parse::<f32>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| format!("{s:?} is not a colour (expected three numbers r,g,b)"))?;
        match v[..] {
            [r, g, b] => Ok(Rgb([r, g, b])),
            _ => Err(format!(
                "{s:?} is not a colour (expected three numbers r,g,b)"
            )),
        }
    }
}

impl fmt::Display for Rgb {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [r, g, b] = self.0;
        write!(f, "[{r}, {g}, {b}]")
    }
}

impl<'de> serde::Deserialize<'de> for Rgb {
    /// A TOML array of three numbers, or the command line's `"r,g,b"`.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        #[derive(serde::Deserialize)]
        #[serde(untagged)]
        enum Either {
            Array([f32; 3]),
            Text(String),
        }
        match Either::deserialize(d)
            .map_err(|_| serde::de::Error::custom("expected a colour [r, g, b]"))?
        {
            Either::Array(a) => Ok(Rgb(a)),
            Either::Text(s) => s.parse().map_err(serde::de::Error::custom),
        }
    }
}

/// A colour setting's check: finite and not negative.
pub fn check_rgb(c: &Rgb) -> std::result::Result<(), String> {
    if c.0.iter().all(|v| v.is_finite() && *v >= 0.0) {
        Ok(())
    } else {
        Err("must be three finite numbers ≥ 0 (linear RGB)".into())
    }
}

/// The background of a run, resolved: what a camera ray that leaves the scene sees.
#[derive(Clone, Debug, Default)]
pub enum Backdrop {
    /// The map (looked up in the frame's `EnvMap`).
    #[default]
    Environment,
    Transparent,
    Color(Vec3),
    /// The prefiltered map, rotated as the map is.
    Blurred(EnvMap),
}

/// The background when none is given: the environment.
pub static ENVIRONMENT: Backdrop = Backdrop::Environment;

impl Backdrop {
    /// The backdrop `background` asks for over `env` (`color` and `blur_deg` for the colour
    /// and blurred backgrounds).
    pub fn new(
        background: Background,
        color: Rgb,
        blur_deg: f32,
        env: &EnvMap,
    ) -> Result<Backdrop> {
        Ok(match background {
            Background::Environment => Backdrop::Environment,
            Background::Transparent => Backdrop::Transparent,
            Background::Color => Backdrop::Color(Vec3::from_array(color.0)),
            Background::Blurred => Backdrop::Blurred(blurred(env, blur_deg)?),
        })
    }

    /// Whether rays that leave the scene see nothing (alpha 0).
    #[inline]
    pub fn is_transparent(&self) -> bool {
        matches!(self, Backdrop::Transparent)
    }

    /// Radiance seen along unit direction `dir` where nothing of the scene is in the way:
    /// zero over a transparent background (premultiplied: its alpha is 0).
    #[inline]
    pub fn radiance(&self, env: &EnvMap, dir: Vec3) -> Vec3 {
        match self {
            Backdrop::Environment => env.radiance(dir),
            Backdrop::Transparent => Vec3::ZERO,
            Backdrop::Color(c) => *c,
            Backdrop::Blurred(map) => map.radiance(dir),
        }
    }

    /// The alpha of what [`radiance`](Self::radiance) shows: 0 over a transparent background,
    /// else 1.
    #[inline]
    pub fn alpha(&self) -> f32 {
        if self.is_transparent() { 0.0 } else { 1.0 }
    }
}

/// The cells of a line of `n_dst` cells that cell `i` of the same line cut into `n_src` cells
/// overlaps, with the share of cell `i` each holds (exact: integer ends on a line of
/// `n_src × n_dst` units).
fn overlaps(i: usize, n_src: usize, n_dst: usize) -> impl Iterator<Item = (usize, f64)> {
    let (start, end) = (i * n_dst, (i + 1) * n_dst);
    (start / n_src..=(end - 1) / n_src).map(move |t| {
        let (lo, hi) = (start.max(t * n_src), end.min((t + 1) * n_src));
        (t, (hi - lo) as f64 / n_dst as f64)
    })
}

/// Rows of the blurred copy at most (its columns are twice as many): 1.9° texels, which a blur
/// of 4° or more resolves; a finer blur is as fine as these texels.
const MAX_BLUR_ROWS: usize = 96;

/// `env` blurred by a Gaussian of standard deviation `sigma_deg` degrees on the sphere
/// (weight `exp((cos θ − 1) / σ²)`, `θ` the angle between directions: `exp(−θ² / 2σ²)` for
/// small angles), at about two texels per σ, in the map's own frame and rotated as it is.
///
/// Two steps, each a sum in a fixed order: the map averaged by solid angle into the copy's
/// texels (a box filter: each texel of the map shared by overlap), then each texel of the copy the weighted mean of the copy's texels within 4σ in
/// latitude (weights below e⁻⁸ skipped).
pub fn blurred(env: &EnvMap, sigma_deg: f32) -> Result<EnvMap> {
    let sigma = sigma_deg.to_radians();
    let rows = ((std::f32::consts::TAU / sigma).ceil() as usize).clamp(8, MAX_BLUR_ROWS);
    let h = rows.min(env.height);
    let w = (2 * h).min(env.width);
    // Step 1: the map by solid angle into w × h texels, each source texel shared between the
    // copy's texels it overlaps (by length along each axis), so no light is lost or doubled.
    let mut sum = vec![[0.0f64; 3]; w * h];
    let mut weight = vec![0.0f64; w * h];
    for y in 0..env.height {
        let dw = env.texel_solid_angle_f64(y);
        for (ty, fy) in overlaps(y, env.height, h) {
            for x in 0..env.width {
                let c = env.texel(x, y);
                for (tx, fx) in overlaps(x, env.width, w) {
                    let (t, k) = (ty * w + tx, dw * fy * fx);
                    sum[t][0] += c.x as f64 * k;
                    sum[t][1] += c.y as f64 * k;
                    sum[t][2] += c.z as f64 * k;
                    weight[t] += k;
                }
            }
        }
    }
    let small: Vec<Vec3> = sum
        .iter()
        .zip(&weight)
        .map(|(s, &wt)| {
            let s = s.map(|v| (v / wt.max(f64::MIN_POSITIVE)) as f32);
            Vec3::from_array(s)
        })
        .collect();
    let grid = EnvMap::from_texels(w, h, small, &env.source)?;
    // Step 2: the Gaussian over the sphere.
    let dirs: Vec<Vec3> = (0..w * h)
        .map(|i| {
            let uv = glam::Vec2::new(
                ((i % w) as f32 + 0.5) / w as f32,
                ((i / w) as f32 + 0.5) / h as f32,
            );
            crate::envmap::uv_to_dir(uv)
        })
        .collect();
    let solid: Vec<f32> = (0..h).map(|y| grid.texel_solid_angle(y)).collect();
    let inv_var = 1.0 / (sigma * sigma);
    let reach = (4.0 * sigma / std::f32::consts::PI * h as f32).ceil() as usize + 1;
    let mut out = vec![Vec3::ZERO; w * h];
    for (o, texel) in out.iter_mut().enumerate() {
        let (d, oy) = (dirs[o], o / w);
        let (mut acc, mut total) = ([0.0f64; 3], 0.0f64);
        let rows = oy.saturating_sub(reach)..(oy + reach + 1).min(h);
        for (y, &dw) in solid.iter().enumerate().take(rows.end).skip(rows.start) {
            for x in 0..w {
                let i = y * w + x;
                let e = (d.dot(dirs[i]) - 1.0) * inv_var;
                if e < -8.0 {
                    continue;
                }
                let k = (libm::expf(e) * dw) as f64;
                let c = grid.texels[i];
                acc[0] += c.x as f64 * k;
                acc[1] += c.y as f64 * k;
                acc[2] += c.z as f64 * k;
                total += k;
            }
        }
        *texel = Vec3::from_array(acc.map(|v| (v / total.max(f64::MIN_POSITIVE)) as f32));
    }
    let source = format!("{} (blurred {sigma_deg}°)", env.source);
    Ok(EnvMap::from_texels(w, h, out, &source)?.with_rotation(env.rotation_deg))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_blurred_uniform_map_stays_uniform_and_a_blurred_sky_keeps_its_mean() {
        let uniform = EnvMap::from_texels(64, 32, vec![Vec3::splat(0.7); 64 * 32], "u").unwrap();
        let b = blurred(&uniform, 10.0).unwrap();
        for t in &b.texels {
            assert!((*t - Vec3::splat(0.7)).abs().max_element() < 1e-5, "{t}");
        }
        // The sun's energy spreads out: the blurred sky's brightest texel is far dimmer, its
        // integral about the same (a Gaussian on the sphere loses nothing).
        let sky = EnvMap::builtin_sky();
        let b = blurred(&sky, 10.0).unwrap();
        let peak = |m: &EnvMap| m.texels.iter().map(|t| t.x).fold(0.0, f32::max);
        assert!(peak(&b) < peak(&sky) / 50.0);
        let (i0, i1) = (sky.integral(), b.integral());
        for c in 0..3 {
            assert!((i1[c] / i0[c] - 1.0).abs() < 0.02, "{i0:?} {i1:?}");
        }
    }

    #[test]
    fn colours_read_as_arrays_and_as_flags() {
        assert_eq!("0.1,0.2,0.3".parse::<Rgb>().unwrap(), Rgb([0.1, 0.2, 0.3]));
        assert!("0.1,0.2".parse::<Rgb>().is_err());
        assert!(check_rgb(&Rgb([0.0, -1.0, 0.0])).is_err());
        assert!(check_rgb(&Rgb([f32::NAN, 0.0, 0.0])).is_err());
    }
}
