//! Frame selections (`--frames LIST`): the text a command line gives and the set of frames it
//! names.
//!
//! A list is pieces joined by commas; each piece is one of
//!
//! | piece | frames | |
//! |---|---|---|
//! | `7` | 7 | one frame |
//! | `2-5` | 2, 3, 4, 5 | the end **included**, as Blender's `-f 1,3,5-10` and our `--tiles 0-4` |
//! | `2..5` | 2, 3, 4 | the end **excluded**, as a Rust range (the first form envshadow had) |
//! | `2..=5` | 2, 3, 4, 5 | the end included |
//!
//! and a range may end in `:STEP` (every STEP-th frame from its first): `1-10:3` is 1, 4, 7,
//! 10; `0..10:5` is 0, 5. Mixtures are fine (`1-3,7,10-20:5` is 1, 2, 3, 7, 10, 15, 20), order
//! and repeats do not matter: a selection is a set, rendered in frame order, each frame once.
//!
//! [ours] `A..B` keeps its meaning (end excluded) rather than Blender's (where `1..10` includes
//! 10): scripts and farm plans written with it stay right, and the dash is there for the
//! inclusive reading.

use std::fmt;
use std::ops::Range;

use serde::{Deserialize, Serialize};

use crate::limits::MAX_FRAMES;

/// The forms a piece may take, for messages.
const FORMS: &str = "a list is pieces joined by commas: N, A-B (B included), A..B (B excluded) \
                     or A..=B, a range optionally with :STEP";

/// A set of frame numbers, kept as sorted, disjoint, non-touching runs (end excluded): a
/// contiguous selection is one run however long it is.
#[derive(Clone, Default, PartialEq, Eq, Hash)]
pub struct FrameSet {
    runs: Vec<Range<usize>>,
}

impl FrameSet {
    /// The frames of `r` (end excluded).
    pub fn range(r: Range<usize>) -> FrameSet {
        let runs = if r.is_empty() { vec![] } else { vec![r] };
        FrameSet { runs }
    }

    /// The set of `frames`, in any order, repeats allowed.
    pub fn from_frames(frames: impl IntoIterator<Item = usize>) -> FrameSet {
        let mut v: Vec<usize> = frames.into_iter().collect();
        v.sort_unstable();
        v.dedup();
        let mut runs: Vec<Range<usize>> = Vec::new();
        for f in v {
            match runs.last_mut() {
                Some(r) if r.end == f => r.end = f + 1,
                _ => runs.push(f..f + 1),
            }
        }
        FrameSet { runs }
    }

    /// How many frames.
    pub fn len(&self) -> usize {
        self.runs.iter().map(|r| r.len()).sum()
    }

    pub fn is_empty(&self) -> bool {
        self.runs.is_empty()
    }

    pub fn contains(&self, frame: usize) -> bool {
        // The run that starts last at or before `frame`.
        let i = self.runs.partition_point(|r| r.start <= frame);
        i > 0 && self.runs[i - 1].contains(&frame)
    }

    /// The frames in increasing order.
    pub fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        self.runs.iter().flat_map(|r| r.clone())
    }

    pub fn first(&self) -> Option<usize> {
        self.runs.first().map(|r| r.start)
    }

    pub fn last(&self) -> Option<usize> {
        self.runs.last().map(|r| r.end - 1)
    }

    /// The one range these frames make, if they are contiguous (an empty set is `0..0`).
    pub fn as_range(&self) -> Option<Range<usize>> {
        match &self.runs[..] {
            [] => Some(0..0),
            [r] => Some(r.clone()),
            _ => None,
        }
    }

    /// The frames at or past `end`.
    pub fn at_or_after(&self, end: usize) -> FrameSet {
        FrameSet::from_frames(self.iter().filter(|&f| f >= end))
    }
}

impl IntoIterator for FrameSet {
    type Item = usize;
    type IntoIter = std::iter::Flatten<std::vec::IntoIter<Range<usize>>>;
    fn into_iter(self) -> Self::IntoIter {
        self.runs.into_iter().flatten()
    }
}

impl From<Range<usize>> for FrameSet {
    fn from(r: Range<usize>) -> FrameSet {
        FrameSet::range(r)
    }
}

/// The shortest list in the forms above that reads back to the same set, in the house's
/// reading of ranges: `0..8` (a run, end excluded), `5` (one frame), `1..11:3` (three or more
/// single frames evenly spaced); e.g. `0..4,7,10..21:5`. An empty set is `0..0`.
impl fmt::Display for FrameSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.runs.is_empty() {
            return f.write_str("0..0");
        }
        let mut pieces: Vec<String> = Vec::new();
        let mut i = 0;
        while i < self.runs.len() {
            let r = &self.runs[i];
            if r.len() > 1 {
                pieces.push(format!("{}..{}", r.start, r.end));
                i += 1;
                continue;
            }
            // Single frames evenly spaced: as many as follow with the same step.
            let mut j = i;
            while j + 1 < self.runs.len()
                && self.runs[j + 1].len() == 1
                && (j == i
                    || self.runs[j + 1].start - self.runs[j].start
                        == self.runs[i + 1].start - self.runs[i].start)
            {
                j += 1;
            }
            if j - i >= 2 {
                let step = self.runs[i + 1].start - r.start;
                pieces.push(format!("{}..{}:{step}", r.start, self.runs[j].start + 1));
                i = j + 1;
            } else {
                pieces.push(r.start.to_string());
                i += 1;
            }
        }
        f.write_str(&pieces.join(","))
    }
}

impl fmt::Debug for FrameSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "FrameSet({self})")
    }
}

impl std::str::FromStr for FrameSet {
    type Err = String;
    fn from_str(s: &str) -> Result<FrameSet, String> {
        let mut frames: Vec<Range<usize>> = Vec::new();
        let mut steps: Vec<(Range<usize>, usize)> = Vec::new();
        for piece in s.split(',') {
            let (r, step) = parse_piece(piece).map_err(|why| {
                if s.contains(',') {
                    format!("piece {:?}: {why}", piece.trim())
                } else {
                    why
                }
            })?;
            if step == 1 {
                frames.push(r);
            } else {
                steps.push((r, step));
            }
        }
        let mut all: Vec<usize> = Vec::new();
        for r in frames {
            all.extend(r);
        }
        for (r, step) in steps {
            all.extend(r.step_by(step));
        }
        Ok(FrameSet::from_frames(all))
    }
}

/// One piece: its frames as a range (end excluded) and its step (1 without `:STEP`).
fn parse_piece(piece: &str) -> Result<(Range<usize>, usize), String> {
    let text = piece.trim();
    if text.is_empty() {
        return Err(format!("an empty piece; {FORMS}"));
    }
    let (range, step) = match text.split_once(':') {
        Some((r, s)) => {
            let step = s
                .trim()
                .parse::<usize>()
                .ok()
                .filter(|&n| n > 0)
                .ok_or_else(|| format!("{:?} is not a step (a whole number from 1)", s.trim()))?;
            (r.trim(), Some(step))
        }
        None => (text, None),
    };
    let num = |t: &str| -> Result<usize, String> {
        let t = t.trim();
        let n = t
            .parse::<usize>()
            .map_err(|_| format!("{t:?} is not a frame number; {FORMS}"))?;
        if n >= MAX_FRAMES {
            return Err(format!(
                "frame {n} is past the limit of {MAX_FRAMES} frames"
            ));
        }
        Ok(n)
    };
    let (start, end, form) = if let Some((a, b)) = range.split_once("..=") {
        (num(a)?, num(b)? + 1, "..=")
    } else if let Some((a, b)) = range.split_once("..") {
        (num(a)?, num(b)?, "..")
    } else if let Some((a, b)) = range.split_once('-') {
        (num(a)?, num(b)? + 1, "-")
    } else {
        if step.is_some() {
            return Err(format!(
                "a step needs a range (e.g. 1-10:{}), not one frame",
                step.unwrap_or(1)
            ));
        }
        let a = num(range)?;
        (a, a + 1, "")
    };
    if end <= start {
        let why = if form == ".." && end == start {
            format!("is empty: the end of A..B is excluded (for {start} alone write {start})")
        } else {
            "runs backwards".to_string()
        };
        return Err(format!("{range:?} {why}"));
    }
    Ok((start..end, step.unwrap_or(1)))
}

/// Written as its text (`"0..8"`, `"1,3,5..9"`); read from the text or, as plans written
/// before frame lists had it, `{"start": 0, "end": 8}`.
impl Serialize for FrameSet {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.to_string())
    }
}

impl<'de> Deserialize<'de> for FrameSet {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<FrameSet, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Form {
            Text(String),
            Range { start: usize, end: usize },
        }
        match Form::deserialize(d)? {
            Form::Text(t) if t == "0..0" => Ok(FrameSet::default()),
            Form::Text(t) => t.parse().map_err(serde::de::Error::custom),
            Form::Range { start, end } => Ok(FrameSet::range(start..end)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(s: &str) -> Vec<usize> {
        s.parse::<FrameSet>()
            .unwrap_or_else(|e| panic!("{s:?}: {e}"))
            .iter()
            .collect()
    }

    fn refused(s: &str) -> String {
        s.parse::<FrameSet>()
            .map(|f| panic!("{s:?} parsed as {f}"))
            .unwrap_err()
    }

    #[test]
    fn every_form_names_its_frames() {
        assert_eq!(set("7"), [7]);
        assert_eq!(set("2..5"), [2, 3, 4]);
        assert_eq!(set("2..=5"), [2, 3, 4, 5]);
        assert_eq!(set("2-5"), [2, 3, 4, 5]);
        assert_eq!(set("1-10"), (1..=10).collect::<Vec<_>>());
        assert_eq!(set("1,5,9"), [1, 5, 9]);
        assert_eq!(set("1-10:2"), [1, 3, 5, 7, 9]);
        assert_eq!(set("1-10:3"), [1, 4, 7, 10]);
        assert_eq!(set("0..10:5"), [0, 5]);
        assert_eq!(set("0..=10:5"), [0, 5, 10]);
        assert_eq!(set("1-3,7,10-20:5"), [1, 2, 3, 7, 10, 15, 20]);
        // A set: order and repeats do not matter; spaces around pieces are allowed.
        assert_eq!(set("9, 1-3 ,2,1"), [1, 2, 3, 9]);
        assert_eq!(set("3-3"), [3]);
    }

    #[test]
    fn errors_name_the_bad_piece() {
        for (text, needles) in [
            (
                "1-3,x,5",
                &["piece \"x\"", "not a frame number", "A-B (B included)"][..],
            ),
            ("a..b", &["\"a\" is not a frame number"]),
            ("5..5", &["empty", "excluded", "write 5"]),
            ("5-2", &["\"5-2\" runs backwards"]),
            ("1,,2", &["empty piece"]),
            ("1,", &["empty piece"]),
            ("1-10:0", &["\"0\" is not a step"]),
            ("1-10:x", &["\"x\" is not a step"]),
            ("4:2", &["a step needs a range"]),
            ("-3", &["\"\" is not a frame number"]),
            ("0-2000000", &["2000000", "limit"]),
            ("0-3,8..2", &["piece \"8..2\"", "backwards"]),
        ] {
            let e = refused(text);
            for n in needles {
                assert!(e.contains(n), "{text:?}: {n:?} not in {e:?}");
            }
        }
    }

    #[test]
    fn the_text_reads_back_to_the_same_set() {
        for (text, shown) in [
            ("0..8", "0..8"),
            ("0-7", "0..8"),
            ("5", "5"),
            ("1,3", "1,3"),
            ("1-10:3", "1..11:3"),
            ("1-3,7,10-20:5", "1..4,7,10..21:5"),
            ("0,2,4,5,6", "0,2,4..7"),
            ("0,2,4,6,7", "0..5:2,6..8"),
        ] {
            let s: FrameSet = text.parse().unwrap();
            assert_eq!(s.to_string(), shown, "{text}");
            assert_eq!(s.to_string().parse::<FrameSet>().unwrap(), s, "{text}");
        }
        // Round trip through JSON, and the plans' older form.
        let s: FrameSet = "1,3,5-9".parse().unwrap();
        let json = serde_json::to_string(&s).unwrap();
        assert_eq!(serde_json::from_str::<FrameSet>(&json).unwrap(), s);
        let old: FrameSet = serde_json::from_str(r#"{"start": 2, "end": 6}"#).unwrap();
        assert_eq!(old, FrameSet::range(2..6));
        assert_eq!(FrameSet::default().to_string(), "0..0");
        let empty: FrameSet = serde_json::from_str("\"0..0\"").unwrap();
        assert!(empty.is_empty());
    }

    #[test]
    fn sets_answer_membership_length_and_ends() {
        let s: FrameSet = "1-3,7,10-20:5".parse().unwrap();
        assert_eq!(s.len(), 7);
        assert_eq!((s.first(), s.last()), (Some(1), Some(20)));
        for f in 0..25 {
            assert_eq!(s.contains(f), [1, 2, 3, 7, 10, 15, 20].contains(&f), "{f}");
        }
        assert_eq!(s.as_range(), None);
        assert_eq!(FrameSet::range(4..9).as_range(), Some(4..9));
        assert_eq!(s.at_or_after(8).iter().collect::<Vec<_>>(), [10, 15, 20]);
        assert_eq!(s.clone().into_iter().count(), 7);
    }
}
