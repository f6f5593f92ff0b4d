//! Which of a file's animations a render plays, and the moment of it each frame shows:
//! `[scene] animation` (`--animation`), `animation_start` (`--animation-start`) and
//! `animation_end` (`--animation-end`).
//!
//! A frame's time is `frame ÷ fps + start` seconds (fps the output's exact rational rate);
//! past the animation's end it loops (the default), holds the last pose, or is refused.

use super::clip::Clip;

/// `[scene] animation`: which animation plays.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Choice {
    /// The file's first animation, when it has one (the default).
    #[default]
    First,
    /// None: the file's rest pose (its skins and default morph weights still applied).
    None,
    /// The animation at this index in the file's list.
    Index(usize),
    /// The animation of this name.
    Name(String),
}

impl std::str::FromStr for Choice {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Choice, String> {
        Ok(match s {
            "" => {
                return Err(
                    "an empty animation name (expected a name, an index, first or none)".into(),
                );
            }
            "first" => Choice::First,
            "none" => Choice::None,
            _ => match s.parse::<usize>() {
                Ok(i) => Choice::Index(i),
                Err(_) => Choice::Name(s.to_string()),
            },
        })
    }
}

impl std::fmt::Display for Choice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Choice::First => f.write_str("first"),
            Choice::None => f.write_str("none"),
            Choice::Index(i) => write!(f, "{i}"),
            Choice::Name(n) => f.write_str(n),
        }
    }
}

impl<'de> serde::Deserialize<'de> for Choice {
    /// A spec may write an index as a number (`animation = 2`) or any choice as a string.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        #[derive(serde::Deserialize)]
        #[serde(untagged)]
        enum Raw {
            Index(usize),
            Text(String),
        }
        match Raw::deserialize(d)? {
            Raw::Index(i) => Ok(Choice::Index(i)),
            Raw::Text(s) => s.parse().map_err(serde::de::Error::custom),
        }
    }
}

impl Choice {
    /// The clip this choice names among `clips`: None for `none` or a file without
    /// animations (under `first`); an error naming the file's animations when it names none.
    pub fn pick(&self, clips: &[Clip]) -> std::result::Result<Option<usize>, String> {
        let names = || {
            if clips.is_empty() {
                "it has none".to_string()
            } else {
                let list: Vec<String> = clips
                    .iter()
                    .enumerate()
                    .map(|(i, c)| format!("{i}: {}", c.label(i)))
                    .collect();
                format!("its animations: {}", list.join(", "))
            }
        };
        match self {
            Choice::First => Ok((!clips.is_empty()).then_some(0)),
            Choice::None => Ok(None),
            Choice::Index(i) if *i < clips.len() => Ok(Some(*i)),
            Choice::Index(i) => Err(format!("no animation {i} ({})", names())),
            Choice::Name(n) => match clips.iter().position(|c| c.name.as_deref() == Some(n)) {
                Some(i) => Ok(Some(i)),
                None => Err(format!("no animation named {n:?} ({})", names())),
            },
        }
    }
}

/// `[scene] animation_end`: what frames past the animation's end show.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AfterEnd {
    /// Start over: the time wraps around the animation's length (the default).
    #[default]
    Loop,
    /// Keep the last pose.
    Hold,
    /// Refuse to render them (a frame whose time is past the end is an error).
    Stop,
}

impl std::str::FromStr for AfterEnd {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<AfterEnd, String> {
        match s {
            "loop" => Ok(AfterEnd::Loop),
            "hold" => Ok(AfterEnd::Hold),
            "stop" => Ok(AfterEnd::Stop),
            _ => Err(format!(
                "unknown animation end {s:?} (expected loop, hold or stop)"
            )),
        }
    }
}

impl std::fmt::Display for AfterEnd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            AfterEnd::Loop => "loop",
            AfterEnd::Hold => "hold",
            AfterEnd::Stop => "stop",
        })
    }
}

/// The time (seconds) of a clip `duration` long to show at `time` (the frame's
/// `frame ÷ fps + start`): wrapped, held, or None past the end under `stop`. Before 0 the
/// clip holds its first pose (a negative start).
pub fn clip_time(time: f64, duration: f64, after: AfterEnd) -> Option<f64> {
    if time <= duration {
        return Some(time.max(0.0));
    }
    match after {
        AfterEnd::Hold => Some(duration),
        AfterEnd::Stop => None,
        // A clip of no length is one pose.
        AfterEnd::Loop if duration <= 0.0 => Some(0.0),
        AfterEnd::Loop => Some(time % duration),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn past_the_end_loops_holds_or_stops() {
        assert_eq!(clip_time(2.5, 2.0, AfterEnd::Loop), Some(0.5));
        assert_eq!(clip_time(2.5, 2.0, AfterEnd::Hold), Some(2.0));
        assert_eq!(clip_time(2.5, 2.0, AfterEnd::Stop), None);
        // The end itself is inside, under every choice.
        for a in [AfterEnd::Loop, AfterEnd::Hold, AfterEnd::Stop] {
            assert_eq!(clip_time(2.0, 2.0, a), Some(2.0));
        }
        assert_eq!(clip_time(-1.0, 2.0, AfterEnd::Stop), Some(0.0));
    }

    #[test]
    fn a_choice_names_its_clip_or_says_what_there_is() {
        let clips = vec![
            Clip {
                name: Some("Walk".into()),
                channels: vec![],
                duration: 1.0,
            },
            Clip {
                name: None,
                channels: vec![],
                duration: 1.0,
            },
        ];
        assert_eq!("Walk".parse::<Choice>().unwrap().pick(&clips), Ok(Some(0)));
        assert_eq!("1".parse::<Choice>().unwrap().pick(&clips), Ok(Some(1)));
        assert_eq!(Choice::None.pick(&clips), Ok(None));
        assert_eq!(Choice::First.pick(&[]), Ok(None));
        let e = "Run".parse::<Choice>().unwrap().pick(&clips).unwrap_err();
        assert!(e.contains("0: Walk, 1: animation 1"), "{e}");
    }
}
