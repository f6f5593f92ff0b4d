//! A glTF animation: channels that move nodes (translation, rotation, scale) or set a mesh's
//! morph-target weights, each sampled over its key times by `STEP`, `LINEAR` (slerp for
//! rotations) or `CUBICSPLINE`, exactly as the glTF 2.0 specification's appendix C defines
//! them. Sampled in f64: the file's f32 keys lose nothing on the way to a node's matrix.

use glam::DQuat;

/// How a sampler fills the time between its keys.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// The earlier key's value, until the next key.
    Step,
    /// Linear between neighbouring keys (spherical linear for rotations).
    Linear,
    /// Cubic Hermite between neighbouring keys, with each key's in- and out-tangents.
    CubicSpline,
}

/// What a channel moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Path {
    Translation,
    Rotation,
    Scale,
    /// The morph-target weights of the node's mesh.
    Weights,
}

/// One channel: a sampler (key times and values) driving one property of one node.
#[derive(Clone, Debug)]
pub struct Channel {
    pub node: usize,
    pub path: Path,
    pub interpolation: Interpolation,
    /// Key times, seconds, strictly increasing (checked at load).
    pub times: Vec<f64>,
    /// Values per key, `width` each (3 for translation and scale, 4 for a rotation's
    /// x, y, z, w, the target count for weights); for `CUBICSPLINE` three such groups per key:
    /// in-tangent, value, out-tangent.
    pub values: Vec<f64>,
    /// Components of one value.
    pub width: usize,
}

/// A named animation: its channels and its length (the last key time of any of them).
#[derive(Clone, Debug)]
pub struct Clip {
    /// The file's name for it, if any.
    pub name: Option<String>,
    pub channels: Vec<Channel>,
    /// Seconds, from 0 to the last key of any channel.
    pub duration: f64,
}

impl Channel {
    /// The channel's value at time `t` (seconds), `width` components written to `out`. Before
    /// the first key it holds the first value, after the last the last (the spec's clamp).
    pub fn sample(&self, t: f64, out: &mut [f64]) {
        let w = self.width;
        let keys = self.times.len();
        let cubic = self.interpolation == Interpolation::CubicSpline;
        // The value of key k (the middle group of a cubic key).
        let value = |k: usize| -> &[f64] {
            let at = if cubic { (3 * k + 1) * w } else { k * w };
            &self.values[at..at + w]
        };
        if keys == 0 {
            return;
        }
        if t <= self.times[0] || keys == 1 {
            out[..w].copy_from_slice(value(0));
            return self.finish(out);
        }
        if t >= self.times[keys - 1] {
            out[..w].copy_from_slice(value(keys - 1));
            return self.finish(out);
        }
        // The key interval holding t: times[k] ≤ t < times[k + 1].
        let k = self.times.partition_point(|&x| x <= t) - 1;
        let (t0, t1) = (self.times[k], self.times[k + 1]);
        let td = t1 - t0;
        let s = (t - t0) / td;
        match self.interpolation {
            Interpolation::Step => out[..w].copy_from_slice(value(k)),
            Interpolation::Linear if self.path == Path::Rotation => {
                let q = slerp(quat(value(k)), quat(value(k + 1)), s);
                out[..4].copy_from_slice(&q.to_array());
            }
            Interpolation::Linear => {
                let (a, b) = (value(k), value(k + 1));
                for c in 0..w {
                    out[c] = a[c] + s * (b[c] - a[c]);
                }
            }
            Interpolation::CubicSpline => {
                // Appendix C: p(s) = (2s³ − 3s² + 1)v_k + td(s³ − 2s² + s)b_k
                //                  + (−2s³ + 3s²)v_k+1 + td(s³ − s²)a_k+1.
                let group = |k: usize, g: usize| &self.values[(3 * k + g) * w..(3 * k + g + 1) * w];
                let (v0, b0) = (group(k, 1), group(k, 2));
                let (a1, v1) = (group(k + 1, 0), group(k + 1, 1));
                let (s2, s3) = (s * s, s * s * s);
                let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
                let h10 = td * (s3 - 2.0 * s2 + s);
                let h01 = -2.0 * s3 + 3.0 * s2;
                let h11 = td * (s3 - s2);
                for c in 0..w {
                    out[c] = h00 * v0[c] + h10 * b0[c] + h01 * v1[c] + h11 * a1[c];
                }
            }
        }
        self.finish(out);
    }

    /// A rotation leaves as a unit quaternion (a cubic spline's or a key's may not be one).
    fn finish(&self, out: &mut [f64]) {
        if self.path == Path::Rotation {
            let q = quat(&out[..4]);
            let q = if q.length_squared() > 0.0 {
                q.normalize()
            } else {
                DQuat::IDENTITY
            };
            out[..4].copy_from_slice(&q.to_array());
        }
    }
}

/// A quaternion from x, y, z, w.
pub fn quat(v: &[f64]) -> DQuat {
    DQuat::from_xyzw(v[0], v[1], v[2], v[3])
}

/// Spherical linear interpolation from `a` to `b` along the shorter arc (appendix C's slerp:
/// `b` negated when the two lie more than 90° apart), linear where they nearly coincide.
pub fn slerp(a: DQuat, b: DQuat, s: f64) -> DQuat {
    let mut d = a.dot(b);
    let b = if d < 0.0 {
        d = -d;
        -b
    } else {
        b
    };
    if d > 1.0 - 1e-12 {
        // Too close for the angle's sine: the straight line is the arc.
        return a + (b - a) * s;
    }
    let angle = libm::acos(d.min(1.0));
    let sin = libm::sin(angle);
    let wa = libm::sin((1.0 - s) * angle) / sin;
    let wb = libm::sin(s * angle) / sin;
    a * wa + b * wb
}

impl Clip {
    /// The name to show for clip `index`: its own, else `animation N`.
    pub fn label(&self, index: usize) -> String {
        self.name
            .clone()
            .unwrap_or_else(|| format!("animation {index}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel(path: Path, interpolation: Interpolation, times: &[f64], values: &[f64]) -> Channel {
        let width = match path {
            Path::Rotation => 4,
            Path::Weights => 1,
            _ => 3,
        };
        Channel {
            node: 0,
            path,
            interpolation,
            times: times.to_vec(),
            values: values.to_vec(),
            width,
        }
    }

    #[test]
    fn step_holds_the_earlier_key_until_the_next() {
        let c = channel(
            Path::Weights,
            Interpolation::Step,
            &[0.0, 1.0, 2.0],
            &[0.0, 5.0, 7.0],
        );
        let mut out = [0.0];
        for (t, want) in [(-1.0, 0.0), (0.5, 0.0), (1.0, 5.0), (1.99, 5.0), (3.0, 7.0)] {
            c.sample(t, &mut out);
            assert_eq!(out[0], want, "t = {t}");
        }
    }

    #[test]
    fn linear_rotation_takes_the_short_way_at_constant_speed() {
        // 0° to 270° about +Z written as the far-side quaternion: the short way is −90°.
        let a = DQuat::IDENTITY;
        let b = DQuat::from_rotation_z(270f64.to_radians());
        let c = channel(
            Path::Rotation,
            Interpolation::Linear,
            &[0.0, 1.0],
            &[a.to_array(), b.to_array()].concat(),
        );
        let mut out = [0.0; 4];
        c.sample(0.5, &mut out);
        let q = quat(&out);
        let want = DQuat::from_rotation_z((-45f64).to_radians());
        assert!(q.dot(want).abs() > 1.0 - 1e-12, "{q:?} vs {want:?}");
    }

    #[test]
    fn cubic_spline_is_the_hermite_curve_of_its_tangents() {
        // Keys 0 → 1 over 2 s with out-tangent 3 and in-tangent −1 (per second).
        let values = [0.0, 0.0, 3.0, -1.0, 1.0, 0.0];
        let c = channel(
            Path::Weights,
            Interpolation::CubicSpline,
            &[1.0, 3.0],
            &values,
        );
        let mut out = [0.0];
        let s: f64 = 0.25;
        c.sample(1.5, &mut out);
        let td = 2.0;
        // v0 = 0, b0 = 3, v1 = 1, a1 = −1.
        let (v0, b0, v1, a1) = (0.0, 3.0, 1.0, -1.0);
        let (s2, s3) = (s * s, s * s * s);
        let want = (2.0 * s3 - 3.0 * s2 + 1.0) * v0
            + td * (s3 - 2.0 * s2 + s) * b0
            + (-2.0 * s3 + 3.0 * s2) * v1
            + td * (s3 - s2) * a1;
        assert!((out[0] - want).abs() < 1e-15, "{} vs {want}", out[0]);
        // The keys themselves, and the clamp past them.
        c.sample(3.0, &mut out);
        assert_eq!(out[0], 1.0);
        c.sample(0.0, &mut out);
        assert_eq!(out[0], 0.0);
    }
}
