//! Frame file names, by Blender's `#` convention: in the pattern `turntable_####` the run of
//! `#` is the frame number, zero-padded to the run's length (`turntable_0001.exr`); a pattern
//! without `#` has the number appended, four digits wide, as Blender does (`shot` →
//! `shot0001.png`). The number is the start frame plus the frame's index (`--frame-start 1`
//! numbers from 1, as Blender does). The default, `frame_####` from 0, is the names every
//! render folder had before patterns.
//!
//! Only the published frames are named so: a frame's record and the report's pictures keep
//! their index (`records/frame_0003.json`, the report's `thumb_0003.jpg`).

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// The settings record's lines that name the frames (absent: the defaults).
pub const PATTERN_LINE: &str = "[output] output_pattern";
pub const START_LINE: &str = "[output] frame_start";

/// Longest pattern: a file name, not a path.
const MAX_PATTERN: usize = 200;

/// A frame name pattern (`turntable_####`), as written and as its parts.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pattern {
    text: String,
    prefix: String,
    width: usize,
    suffix: String,
}

impl Default for Pattern {
    fn default() -> Self {
        "frame_####".parse().expect("the default pattern is one")
    }
}

impl fmt::Display for Pattern {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(&self.text)
    }
}

impl FromStr for Pattern {
    type Err = String;

    /// A file name with at most one run of `#`; no folder (`/`, `\`), no `%` (ffmpeg's
    /// sequence patterns read it as a format), no control characters.
    fn from_str(text: &str) -> Result<Pattern, String> {
        let bad = |why: &str| Err(format!("`{text}` is not a frame name pattern: {why}"));
        if text.is_empty() {
            return bad("it is empty (write e.g. turntable_####)");
        }
        if text.len() > MAX_PATTERN {
            return bad(&format!("longer than {MAX_PATTERN} bytes"));
        }
        if text.contains(['/', '\\']) {
            return bad("a name, not a path (give the folder with --out)");
        }
        if let Some(c) = text.chars().find(|&c| c == '%' || c.is_control()) {
            return bad(&format!(
                "{c:?} would break video tools' frame patterns (ffmpeg's %04d)"
            ));
        }
        if text == "." || text == ".." {
            return bad("not a file name");
        }
        let (prefix, width, suffix) = match text.find('#') {
            None => (text, 4, ""),
            Some(at) => {
                let run = text[at..].bytes().take_while(|&b| b == b'#').count();
                let suffix = &text[at + run..];
                if suffix.contains('#') {
                    return bad("one run of # is the frame number, and it has two");
                }
                (&text[..at], run, suffix)
            }
        };
        Ok(Pattern {
            text: text.to_string(),
            prefix: prefix.to_string(),
            width,
            suffix: suffix.to_string(),
        })
    }
}

/// How a render folder names its frames: the pattern and the number of frame 0.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FrameNames {
    pub pattern: Pattern,
    pub start: usize,
}

impl FrameNames {
    pub fn new(pattern: Pattern, start: usize) -> FrameNames {
        FrameNames { pattern, start }
    }

    /// The number frame `frame` (its index from 0) has in its file name and EXR header.
    pub fn number(&self, frame: usize) -> usize {
        self.start + frame
    }

    /// Frame `frame`'s file name: `turntable_0001.exr`.
    pub fn name(&self, frame: usize, ext: &str) -> String {
        let p = &self.pattern;
        let n = self.number(frame);
        format!("{}{n:0w$}{}.{ext}", p.prefix, p.suffix, w = p.width)
    }

    /// `DIR/turntable_0001.exr`.
    pub fn path(&self, dir: &Path, frame: usize, ext: &str) -> PathBuf {
        dir.join(self.name(frame, ext))
    }

    /// The frame index whose file `name` is (`None`: not one of these frames' names).
    pub fn frame_of(&self, name: &str, ext: &str) -> Option<usize> {
        let p = &self.pattern;
        let digits = name
            .strip_suffix(ext)?
            .strip_suffix('.')?
            .strip_prefix(p.prefix.as_str())?
            .strip_suffix(p.suffix.as_str())?;
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        let frame = digits.parse::<usize>().ok()?.checked_sub(self.start)?;
        // Only the name this frame is written under (not `frame_1.exr` beside `frame_0001`).
        (self.name(frame, ext) == name).then_some(frame)
    }

    /// The names for messages: `frame_NNNN.png`.
    pub fn shown(&self, ext: &str) -> String {
        let p = &self.pattern;
        format!("{}{}{}.{ext}", p.prefix, "N".repeat(p.width), p.suffix)
    }

    /// The names as ffmpeg's image sequence input reads them: `turntable_%04d.png` (with
    /// `-start_number` [`Self::start`]).
    pub fn ffmpeg_pattern(&self, ext: &str) -> String {
        let p = &self.pattern;
        format!("{}%0{}d{}.{ext}", p.prefix, p.width, p.suffix)
    }

    /// The names a settings record states (its `[output] output_pattern` and `frame_start`
    /// lines, written when not the defaults); a line that does not read is the default.
    pub fn from_record(lines: &[(String, String)]) -> FrameNames {
        let value = |key: &str| lines.iter().find(|(k, _)| k == key).map(|(_, v)| v);
        FrameNames {
            pattern: value(PATTERN_LINE)
                .and_then(|v| v.parse().ok())
                .unwrap_or_default(),
            start: value(START_LINE).and_then(|v| v.parse().ok()).unwrap_or(0),
        }
    }

    /// The names of the render folder `dir`, from its `settings.txt` (none: the defaults).
    pub fn of_folder(dir: &Path) -> FrameNames {
        match super::record::SettingsRecord::read(dir) {
            Ok(Some(r)) => FrameNames::from_record(&r.lines),
            _ => FrameNames::default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(pattern: &str, start: usize) -> FrameNames {
        FrameNames::new(pattern.parse().unwrap(), start)
    }

    #[test]
    fn hashes_are_the_zero_padded_frame_number_as_in_blender() {
        assert_eq!(FrameNames::default().name(3, "exr"), "frame_0003.exr");
        assert_eq!(
            names("turntable_####", 1).name(0, "png"),
            "turntable_0001.png"
        );
        assert_eq!(names("shot", 0).name(12, "exr"), "shot0012.exr");
        assert_eq!(names("a_##_b", 0).name(7, "exr"), "a_07_b.exr");
        assert_eq!(names("x#", 0).name(123, "exr"), "x123.exr");
        assert_eq!(names("v.2_###", 0).ffmpeg_pattern("png"), "v.2_%03d.png");
        assert_eq!(FrameNames::default().shown("png"), "frame_NNNN.png");
    }

    #[test]
    fn names_read_back_as_their_frames() {
        let n = names("turntable_####_beauty", 100);
        assert_eq!(n.frame_of(&n.name(5, "exr"), "exr"), Some(5));
        assert_eq!(n.frame_of("turntable_0099_beauty.exr", "exr"), None);
        assert_eq!(n.frame_of("turntable_105_beauty.exr", "exr"), None);
        assert_eq!(n.frame_of(&n.name(5, "exr"), "png"), None);
        assert_eq!(n.frame_of("frame_0105.exr", "exr"), None);
        let d = FrameNames::default();
        assert_eq!(d.frame_of("frame_12345.png", "png"), Some(12345));
    }

    #[test]
    fn patterns_that_are_paths_or_break_ffmpeg_are_refused() {
        for bad in [
            "",
            "a/b_##",
            "..\\x",
            "x_%04d",
            "a#b#",
            "tab\there",
            "..",
            &"x".repeat(201),
        ] {
            assert!(bad.parse::<Pattern>().is_err(), "{bad}");
        }
    }

    #[test]
    fn a_record_without_pattern_lines_names_frames_as_before() {
        assert_eq!(FrameNames::from_record(&[]), FrameNames::default());
        let lines = vec![
            (PATTERN_LINE.to_string(), "t_##".to_string()),
            (START_LINE.to_string(), "1".to_string()),
        ];
        assert_eq!(FrameNames::from_record(&lines), names("t_##", 1));
    }
}
