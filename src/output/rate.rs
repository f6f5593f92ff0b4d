//! Frame rates as the rationals video and EXR store (`framesPerSecond` is a rational; ffmpeg's
//! `-framerate` takes `N/D`): 24 is 24/1, and the NTSC rates written as decimals (23.976,
//! 29.97, 59.94, …) are the exact n·1000/1001 they stand for, not 2997/100.

use std::fmt;
use std::str::FromStr;

/// A frame rate, `num / den` in lowest terms.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FrameRate {
    pub num: u32,
    pub den: u32,
}

/// The whole rates whose NTSC variants (n·1000/1001) a decimal stands for: 23.976, 29.97,
/// 47.952, 59.94, 119.88.
const NTSC: [u32; 5] = [24, 30, 48, 60, 120];

/// How far a decimal may be from an NTSC rate and still name it (23.98 and 23.976 both name
/// 24000/1001).
const NTSC_TOLERANCE: f64 = 0.005;

impl FrameRate {
    /// `num / den` reduced; `None` for a zero denominator.
    pub fn new(num: u32, den: u32) -> Option<FrameRate> {
        if den == 0 {
            return None;
        }
        let g = gcd(num, den).max(1);
        Some(FrameRate {
            num: num / g,
            den: den / g,
        })
    }

    /// A whole rate.
    pub const fn whole(fps: u32) -> FrameRate {
        FrameRate { num: fps, den: 1 }
    }

    /// The rate in frames per second, for durations and messages.
    pub fn as_f64(self) -> f64 {
        f64::from(self.num) / f64::from(self.den)
    }

    /// A decimal rate: whole numbers exactly, the NTSC rates as n·1000/1001, others as the
    /// decimal fraction written (12.5 → 25/2).
    fn from_decimal(s: &str) -> Option<FrameRate> {
        let (whole, frac) = s.split_once('.').unwrap_or((s, ""));
        let digits = |t: &str| t.bytes().all(|b| b.is_ascii_digit());
        if whole.is_empty() || !digits(whole) || !digits(frac) || frac.len() > 6 {
            return None;
        }
        let frac = frac.trim_end_matches('0');
        let den = 10u64.pow(frac.len() as u32);
        let num = whole.parse::<u64>().ok()? * den + frac.parse::<u64>().unwrap_or(0);
        if den > 1 {
            let x = num as f64 / den as f64;
            if let Some(&n) = NTSC
                .iter()
                .find(|&&n| (x - f64::from(n) * 1000.0 / 1001.0).abs() <= NTSC_TOLERANCE)
            {
                return FrameRate::new(n * 1000, 1001);
            }
        }
        FrameRate::new(u32::try_from(num).ok()?, den as u32)
    }
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 { a } else { gcd(b, a % b) }
}

impl fmt::Display for FrameRate {
    /// `24` for a whole rate (as the settings record always wrote it), else `30000/1001`.
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        if self.den == 1 {
            write!(f, "{}", self.num)
        } else {
            write!(f, "{}/{}", self.num, self.den)
        }
    }
}

impl FromStr for FrameRate {
    type Err = String;

    /// `24`, `29.97` (the NTSC decimals are n·1000/1001) or `30000/1001`.
    fn from_str(s: &str) -> Result<FrameRate, String> {
        let s = s.trim();
        let rate = match s.split_once('/') {
            Some((n, d)) => match (n.trim().parse(), d.trim().parse()) {
                (Ok(n), Ok(d)) => FrameRate::new(n, d),
                _ => None,
            },
            None => FrameRate::from_decimal(s),
        };
        rate.ok_or_else(|| {
            format!("`{s}` is not a frame rate: write 24, 29.97 or 30000/1001 (num/den)")
        })
    }
}

impl serde::Serialize for FrameRate {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.to_string())
    }
}

impl<'de> serde::Deserialize<'de> for FrameRate {
    /// A number (`fps = 29.97`, as specs and older job manifests write it) or a string
    /// (`fps = "30000/1001"`).
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<FrameRate, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = FrameRate;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a frame rate: 24, 29.97 or \"30000/1001\"")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<FrameRate, E> {
                v.parse().map_err(E::custom)
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<FrameRate, E> {
                self.visit_str(&v.to_string())
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<FrameRate, E> {
                self.visit_str(&v.to_string())
            }
            // The shortest decimal that reads back as `v`: what the spec's author wrote.
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<FrameRate, E> {
                self.visit_str(&v.to_string())
            }
        }
        d.deserialize_any(Visitor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ntsc_decimals_are_the_rates_they_stand_for() {
        let mut failures = Vec::new();
        for (text, want) in [
            ("24", (24, 1)),
            ("24.0", (24, 1)),
            ("25", (25, 1)),
            ("23.976", (24000, 1001)),
            ("23.98", (24000, 1001)),
            ("29.97", (30000, 1001)),
            ("59.94", (60000, 1001)),
            ("119.88", (120000, 1001)),
            ("30000/1001", (30000, 1001)),
            ("60/2", (30, 1)),
            ("12.5", (25, 2)),
            (" 50 ", (50, 1)),
        ] {
            let got = text.parse::<FrameRate>().map(|r| (r.num, r.den));
            if got != Ok(want) {
                failures.push(format!("{text}: {got:?}"));
            }
        }
        for bad in ["", "x", "1/0", "-24", "24fps", "1e3", "/", ".5"] {
            if bad.parse::<FrameRate>().is_ok() {
                failures.push(format!("{bad} accepted"));
            }
        }
        assert!(failures.is_empty(), "{failures:?}");
        assert_eq!(
            FrameRate::new(30000, 1001).unwrap().to_string(),
            "30000/1001"
        );
        assert_eq!(FrameRate::whole(24).to_string(), "24");
    }

    #[test]
    fn specs_give_rates_as_numbers_or_strings() {
        #[derive(serde::Deserialize)]
        struct T {
            fps: FrameRate,
        }
        let rate = |text: &str| toml::from_str::<T>(text).map(|t| (t.fps.num, t.fps.den));
        assert_eq!(rate("fps = 29.97").unwrap(), (30000, 1001));
        assert_eq!(rate("fps = 24").unwrap(), (24, 1));
        assert_eq!(rate("fps = 24.0").unwrap(), (24, 1));
        assert_eq!(rate("fps = \"30000/1001\"").unwrap(), (30000, 1001));
        assert!(rate("fps = \"fast\"").is_err());
    }
}
