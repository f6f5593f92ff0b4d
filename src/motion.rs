//! What moves from frame to frame: a spec's `[motion]` table, or a sequence of motions as an
//! array of `[[motion]]` tables (README.md, "Motion").
//!
//! ```toml
//! [[motion]]                    # frames 0–71: the model turns once
//! kind = "spin"
//! frames = 72                   # a count, or an inclusive range: frames = "0-71"
//! turn_degrees = 360.0
//! [[motion]]                    # frames 72–143: then the light turns once around it
//! kind = "environment"
//! frames = "72-143"
//! turn_degrees = 360.0
//! ```
//!
//! A segment turns by `degrees_per_frame` each frame, starting where the segments before it
//! left things [ours]: frame f of a segment that starts at frame s has turned (f − s)·d, and
//! the segment hands on the turn after its last frame, (end − s)·d, so a whole turn of 360°
//! over n frames leaves the model (or light, or camera) where it started and every step from
//! one frame to the next moves one thing by d. The object's spin, the camera's orbit and the
//! environment's turn are each summed over the segments of their kind up to the frame: every
//! frame's pose is a function of its number alone, so a frame rendered alone (a split job, a
//! farm host) is the frame the whole animation renders.

use std::ops::Range;
use std::path::Path;

use glam::{DVec3, Mat4, Vec3};
use serde::Deserialize;

use crate::bail_input;
use crate::error::Result;

/// What moves during a segment of the animation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionKind {
    /// The camera circles the target about the vertical axis; scene and environment fixed.
    Orbit,
    /// The scene turns about a vertical axis; camera and environment fixed.
    Spin,
    /// The environment (its lights and the background) turns about the up axis; scene and
    /// camera fixed.
    Environment,
    /// Nothing moves.
    Still,
}

impl MotionKind {
    /// The name a spec gives it.
    pub fn name(self) -> &'static str {
        match self {
            MotionKind::Orbit => "orbit",
            MotionKind::Spin => "spin",
            MotionKind::Environment => "environment",
            MotionKind::Still => "none",
        }
    }

    fn parse(s: &str) -> Option<MotionKind> {
        [
            MotionKind::Orbit,
            MotionKind::Spin,
            MotionKind::Environment,
            MotionKind::Still,
        ]
        .into_iter()
        .find(|k| k.name() == s)
    }

    /// Default key-frame interval (docs/temporal.md has the measurements): with a camera
    /// orbit the wrong pairs fall along a chain (0.0045 % after one frame, 0.0015 % after 15:
    /// bunny, 640×480, 200 lights), so chains are long; with a spinning object they grow
    /// (0.034 % after one frame, 0.051 % after four, 0.07 % after eight), so the chain
    /// restarts every 4 frames to stay within 0.05 %. A turning environment: see
    /// docs/temporal.md, "Environment rotation".
    pub fn default_keyframe(self) -> u32 {
        match self {
            MotionKind::Spin => 4,
            MotionKind::Environment => 8,
            MotionKind::Orbit | MotionKind::Still => 16,
        }
    }
}

/// One motion over a run of consecutive frames.
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    pub kind: MotionKind,
    /// Its frames (absolute frame numbers).
    pub frames: Range<usize>,
    /// The turn from one frame to the next, degrees (right-handed about +Y).
    pub degrees_per_frame: f32,
    /// Spin: the point the vertical axis passes through (default: the camera target).
    pub pivot: Option<Vec3>,
}

impl Segment {
    /// Frames of this segment's turn done by `frame`: none before it starts, all of them
    /// (its length) after it ends.
    fn elapsed(&self, frame: usize) -> Option<usize> {
        (frame >= self.frames.start).then(|| frame.min(self.frames.end) - self.frames.start)
    }
}

/// The animation's motion: segments covering frames 0.. without gaps or overlaps.
#[derive(Clone, Debug, PartialEq)]
pub struct Motion {
    segments: Vec<Segment>,
    /// Written as one `[motion]` table (errors and the settings record keep its old names).
    single: bool,
}

impl Motion {
    /// One motion over `frames` frames.
    pub fn single(kind: MotionKind, frames: usize, degrees_per_frame: f32) -> Motion {
        Motion {
            segments: vec![Segment {
                kind,
                frames: 0..frames,
                degrees_per_frame,
                pivot: None,
            }],
            single: true,
        }
    }

    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// Whether the spec wrote one `[motion]` table.
    pub fn is_single(&self) -> bool {
        self.single
    }

    /// Frames in the whole animation.
    pub fn frame_count(&self) -> usize {
        self.segments.last().map_or(0, |s| s.frames.end)
    }

    /// The segment `frame` belongs to (the last one for frames past the end).
    pub fn segment_at(&self, frame: usize) -> &Segment {
        let i = self.segments.partition_point(|s| s.frames.end <= frame);
        &self.segments[i.min(self.segments.len() - 1)]
    }

    /// What moves at `frame`.
    pub fn kind_at(&self, frame: usize) -> MotionKind {
        self.segment_at(frame).kind
    }

    /// Whether any segment has this kind.
    pub fn has(&self, kind: MotionKind) -> bool {
        self.segments.iter().any(|s| s.kind == kind)
    }

    /// The turn of `kind` done by `frame`, degrees, summed over its segments in order; `None`
    /// before the first segment of that kind (nothing of that kind has moved). One segment
    /// gives exactly `degrees_per_frame × frame`.
    fn turned(&self, kind: MotionKind, frame: usize) -> Option<f32> {
        self.segments
            .iter()
            .filter(|s| s.kind == kind)
            .filter_map(|s| Some(s.degrees_per_frame * s.elapsed(frame)? as f32))
            .reduce(|a, b| a + b)
    }

    /// The camera's orbit about the target at `frame`, degrees (`None`: no orbit yet).
    pub fn orbit_degrees(&self, frame: usize) -> Option<f32> {
        self.turned(MotionKind::Orbit, frame)
    }

    /// The environment's turn at `frame` beyond `[environment] rotation`, degrees, in the
    /// same sense (+90 moves what was seen along +Z to be seen along +X); `None`: it has not
    /// turned.
    pub fn environment_degrees(&self, frame: usize) -> Option<f32> {
        self.turned(MotionKind::Environment, frame)
    }

    /// The scene's world transform at `frame`: each spin segment that has started turns it
    /// about the vertical axis through its pivot (default `target`), later segments after
    /// earlier ones. `None` when no spin has started (the scene is where the file put it).
    /// `target` is in the scene's coordinates; the segments' world-space pivots are taken
    /// into them (they count from `origin`, [`crate::scene::Scene::origin`]).
    pub fn scene_transform(&self, frame: usize, target: Vec3, origin: DVec3) -> Option<Mat4> {
        self.segments
            .iter()
            .filter(|s| s.kind == MotionKind::Spin)
            .filter_map(|s| {
                let angle = (s.degrees_per_frame * s.elapsed(frame)? as f32).to_radians();
                let pivot = s
                    .pivot
                    .map_or(target, |p| (p.as_dvec3() - origin).as_vec3());
                Some(
                    Mat4::from_translation(pivot)
                        * Mat4::from_rotation_y(angle)
                        * Mat4::from_translation(-pivot),
                )
            })
            .reduce(|earlier, later| later * earlier)
    }

    /// The key frame that starts the temporal chain holding `frame`: chains restart at
    /// every segment's first frame (the motion, and what the prediction carries, changes
    /// there) and every `keyframe` frames from it, `keyframe` 0 meaning the segment kind's
    /// default. One segment from frame 0 gives the multiples of the interval.
    pub fn key_frame_of(&self, frame: usize, keyframe: u32) -> usize {
        let s = self.segment_at(frame);
        let k = self.interval(s, keyframe);
        s.frames.start + (frame - s.frames.start) / k * k
    }

    fn interval(&self, s: &Segment, keyframe: u32) -> usize {
        if keyframe > 0 {
            keyframe as usize
        } else {
            s.kind.default_keyframe() as usize
        }
    }

    /// Frames a job's range should start on so that it needs no warm-up (with temporal
    /// prediction): every key frame is a multiple of it. One segment: the key-frame interval;
    /// a sequence: the greatest common divisor of the segments' starts and intervals, at
    /// least 2 when a frame reads its predecessor (a job must then render whole frames).
    pub fn frame_alignment(&self, keyframe: u32) -> usize {
        let mut g = 0;
        let mut chained = false;
        for s in &self.segments {
            let k = self.interval(s, keyframe);
            chained |= k > 1;
            g = gcd(gcd(g, s.frames.start), k);
        }
        if self.single || !chained {
            g.max(1)
        } else {
            g.max(2)
        }
    }

    /// The settings record's lines: one table keeps its old keys, a sequence names each
    /// segment (`[[motion]] 2 kind`).
    pub fn record(&self, show: impl Fn(Vec3) -> String) -> Vec<(String, String)> {
        let mut lines = Vec::new();
        for (i, s) in self.segments.iter().enumerate() {
            let place = place(self.single, i);
            let mut put = |k: &str, v: String| lines.push((format!("{place} {k}"), v));
            put("kind", s.kind.name().into());
            if self.single {
                put("frames", s.frames.len().to_string());
            } else {
                put("frames", format!("{}-{}", s.frames.start, s.frames.end - 1));
            }
            put("degrees_per_frame", s.degrees_per_frame.to_string());
            put("pivot", s.pivot.map_or_else(|| "auto".into(), &show));
        }
        lines
    }

    /// Resolves the spec's motion; errors name `path` and the table and key.
    pub(crate) fn from_spec(spec: &MotionSpecs, path: &Path) -> Result<Motion> {
        let (list, single): (&[MotionSpec], bool) = match spec {
            MotionSpecs::One(m) => (std::slice::from_ref(m), true),
            MotionSpecs::Many(v) => (v, false),
        };
        if list.is_empty() {
            bail_input!(
                path,
                "motion = []: an empty list of motions (give one [motion] table or [[motion]] tables)"
            );
        }
        let mut segments: Vec<Segment> = Vec::with_capacity(list.len());
        for (i, m) in list.iter().enumerate() {
            let place = place(single, i);
            let Some(kind) = MotionKind::parse(&m.kind) else {
                bail_input!(
                    path,
                    "{place} kind = {:?}: expected \"orbit\", \"spin\", \"environment\" or \"none\"",
                    m.kind
                );
            };
            let start = segments.last().map_or(0, |s| s.frames.end);
            let frames = match &m.frames {
                FramesSpec::Count(n) => start..start.saturating_add(*n),
                FramesSpec::Range(text) => {
                    let Some(r) = parse_range(text) else {
                        bail_input!(
                            path,
                            "{place} frames = {text:?}: expected a frame count (72) or an inclusive range \"A-B\" (\"0-71\")"
                        );
                    };
                    if let Some(prev) = segments.last()
                        && r.start < start
                    {
                        bail_input!(
                            path,
                            "{place} frames = {text:?} overlaps {} (frames {}-{}): each frame belongs to one motion",
                            self::place(single, i - 1),
                            prev.frames.start,
                            prev.frames.end - 1
                        );
                    }
                    if r.start > start {
                        bail_input!(
                            path,
                            "{place} frames = {text:?} leaves frames {start}-{} without a motion ({}): the motions must follow one another from frame 0",
                            r.start - 1,
                            match i {
                                0 => "the animation starts at frame 0".to_string(),
                                _ => format!(
                                    "{} ends at frame {}",
                                    self::place(single, i - 1),
                                    start - 1
                                ),
                            }
                        );
                    }
                    r
                }
            };
            // One table's frame count is checked with the animation's limits.
            if !single && frames.is_empty() {
                bail_input!(path, "{place} frames = 0: a motion needs at least 1 frame");
            }
            if !single && frames.end > crate::limits::MAX_FRAMES {
                bail_input!(
                    path,
                    "{place} frames: the animation would have {} frames; at most {} are allowed",
                    frames.end,
                    crate::limits::MAX_FRAMES
                );
            }
            let n = frames.len();
            let degrees_per_frame = match (m.degrees_per_frame, m.turn_degrees) {
                (Some(_), Some(_)) => bail_input!(
                    path,
                    "{place} takes `degrees_per_frame` or `turn_degrees`, not both"
                ),
                (Some(d), None) if !d.is_finite() => {
                    bail_input!(
                        path,
                        "{place} degrees_per_frame = {d} is not a finite number"
                    )
                }
                (Some(d), None) => d,
                (None, Some(t)) if !t.is_finite() => {
                    bail_input!(path, "{place} turn_degrees = {t} is not a finite number")
                }
                (None, Some(t)) => t / n.max(1) as f32,
                (None, None) => 360.0 / n.max(1) as f32,
            };
            let pivot = m.pivot.map(Vec3::from_array);
            if let Some(p) = pivot {
                if !p.is_finite() {
                    bail_input!(
                        path,
                        "{place} pivot = [{}, {}, {}] is not finite",
                        p.x,
                        p.y,
                        p.z
                    );
                }
                // One table kept its pivot whatever the kind (older specs); a sequence says
                // which motion it belongs to.
                if !single && kind != MotionKind::Spin {
                    bail_input!(
                        path,
                        "{place} pivot applies only to kind = \"spin\" (this motion is {:?})",
                        kind.name()
                    );
                }
            }
            segments.push(Segment {
                kind,
                frames,
                degrees_per_frame,
                pivot,
            });
        }
        Ok(Motion { segments, single })
    }
}

impl MotionSpecs {
    /// One `[motion]` table's `frames` and `degrees_per_frame` replaced where given (the
    /// command line's `--frame-count`, `--degrees-per-frame`): a new frame count spreads the
    /// table's `turn_degrees` (default 360°) over the new frames unless a degrees per frame is
    /// given here or in the table. `Err(n)` for a sequence of `n` motions, whose frames are
    /// its motions'.
    pub(crate) fn set_single(
        &mut self,
        frames: Option<usize>,
        degrees_per_frame: Option<f32>,
    ) -> std::result::Result<(), usize> {
        let m = match self {
            MotionSpecs::One(m) => m,
            MotionSpecs::Many(_) if frames.is_none() && degrees_per_frame.is_none() => {
                return Ok(());
            }
            MotionSpecs::Many(v) => return Err(v.len()),
        };
        if let Some(n) = frames {
            m.frames = FramesSpec::Count(n);
        }
        if let Some(d) = degrees_per_frame {
            m.degrees_per_frame = Some(d);
            m.turn_degrees = None;
        }
        Ok(())
    }
}

impl Motion {
    /// The motion as a spec writes it (`render --write-spec`): one `[motion]` table, or the
    /// `[[motion]]` tables of a sequence, each with its frames, kind, degrees per frame and
    /// pivot, so that it reads back as this motion.
    pub fn spec_value(&self) -> toml::Value {
        let tables: Vec<toml::Value> = self
            .segments
            .iter()
            .map(|s| {
                let mut t = toml::Table::new();
                t.insert("kind".into(), toml::Value::String(s.kind.name().into()));
                let frames = if self.single {
                    toml::Value::Integer(s.frames.len() as i64)
                } else {
                    toml::Value::String(format!("{}-{}", s.frames.start, s.frames.end - 1))
                };
                t.insert("frames".into(), frames);
                let float = |x: f32| toml::Value::Float(crate::settings::spec_float(x));
                t.insert("degrees_per_frame".into(), float(s.degrees_per_frame));
                if let Some(p) = s.pivot {
                    let p = p.to_array().map(float).to_vec();
                    t.insert("pivot".into(), toml::Value::Array(p));
                }
                toml::Value::Table(t)
            })
            .collect();
        match &tables[..] {
            [one] if self.single => one.clone(),
            _ => toml::Value::Array(tables),
        }
    }
}

/// How errors and the settings record name segment `i`: `[motion]`, or `[[motion]] 2`
/// (counted from 1, as the file lists them).
fn place(single: bool, i: usize) -> String {
    if single {
        "[motion]".into()
    } else {
        format!("[[motion]] {}", i + 1)
    }
}

/// `A-B` (inclusive, Blender's way) or `A`.
fn parse_range(text: &str) -> Option<Range<usize>> {
    let num = |t: &str| t.trim().parse::<usize>().ok();
    let (a, b) = match text.split_once('-') {
        Some((a, b)) => (num(a)?, num(b)?),
        None => {
            let a = num(text)?;
            (a, a)
        }
    };
    if a > b {
        return None;
    }
    Some(a..b.checked_add(1)?)
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// One `[motion]` table as a spec writes it.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MotionSpec {
    #[serde(default = "default_kind")]
    kind: String,
    #[serde(default)]
    frames: FramesSpec,
    degrees_per_frame: Option<f32>,
    turn_degrees: Option<f32>,
    pivot: Option<[f32; 3]>,
}

impl Default for MotionSpec {
    fn default() -> Self {
        MotionSpec {
            kind: default_kind(),
            frames: FramesSpec::default(),
            degrees_per_frame: None,
            turn_degrees: None,
            pivot: None,
        }
    }
}

fn default_kind() -> String {
    "orbit".into()
}

/// `frames`: a count, or an inclusive range `"A-B"`.
#[derive(Debug, Clone, PartialEq)]
enum FramesSpec {
    Count(usize),
    Range(String),
}

impl Default for FramesSpec {
    fn default() -> Self {
        FramesSpec::Count(1)
    }
}

impl<'de> Deserialize<'de> for FramesSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = FramesSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a frame count (72) or an inclusive frame range (\"0-71\")")
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> std::result::Result<FramesSpec, E> {
                usize::try_from(v)
                    .map(FramesSpec::Count)
                    .map_err(|_| E::custom(format!("{v} frames is too many")))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> std::result::Result<FramesSpec, E> {
                match u64::try_from(v) {
                    Ok(v) => self.visit_u64(v),
                    Err(_) => Err(E::invalid_value(serde::de::Unexpected::Signed(v), &self)),
                }
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> std::result::Result<FramesSpec, E> {
                Ok(FramesSpec::Range(v.to_string()))
            }
        }
        d.deserialize_any(V)
    }
}

/// The spec's `motion`: one `[motion]` table or an array of `[[motion]]` tables.
#[derive(Debug, Clone)]
pub(crate) enum MotionSpecs {
    One(MotionSpec),
    Many(Vec<MotionSpec>),
}

impl Default for MotionSpecs {
    fn default() -> Self {
        MotionSpecs::One(MotionSpec::default())
    }
}

impl<'de> Deserialize<'de> for MotionSpecs {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        use serde::de::value::{MapAccessDeserializer, SeqAccessDeserializer};
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = MotionSpecs;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a [motion] table or [[motion]] tables")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> std::result::Result<MotionSpecs, A::Error> {
                MotionSpec::deserialize(MapAccessDeserializer::new(map)).map(MotionSpecs::One)
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                seq: A,
            ) -> std::result::Result<MotionSpecs, A::Error> {
                Vec::<MotionSpec>::deserialize(SeqAccessDeserializer::new(seq))
                    .map(MotionSpecs::Many)
            }
        }
        d.deserialize_any(V)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn motion(text: &str) -> Result<Motion> {
        #[derive(Deserialize)]
        struct S {
            motion: MotionSpecs,
        }
        let s: S = toml::from_str(text).map_err(|e| anyhow::anyhow!("{e}"))?;
        Motion::from_spec(&s.motion, Path::new("m.toml"))
    }

    const LOOKDEV: &str = "[[motion]]\nkind = \"spin\"\nframes = 72\nturn_degrees = 360.0\n\
                           [[motion]]\nkind = \"environment\"\nframes = \"72-143\"\n\
                           turn_degrees = 360.0\n";

    #[test]
    fn a_sequence_hands_each_turn_on_to_the_next_segment() {
        let m = motion(LOOKDEV).unwrap();
        assert_eq!(m.frame_count(), 144);
        assert_eq!(m.kind_at(71), MotionKind::Spin);
        assert_eq!(m.kind_at(72), MotionKind::Environment);
        // The spin is done (a whole turn) when the light starts turning.
        assert_eq!(m.environment_degrees(71), None);
        assert_eq!(m.environment_degrees(72), Some(0.0));
        assert_eq!(m.environment_degrees(73), Some(5.0));
        let t = |f| m.scene_transform(f, Vec3::ZERO, DVec3::ZERO).unwrap();
        assert!((t(1).transform_point3(Vec3::Z) - Vec3::new(0.0872, 0.0, 0.9962)).length() < 1e-3);
        assert!((t(72).transform_point3(Vec3::Z) - Vec3::Z).length() < 1e-5);
        assert_eq!(t(72), t(143), "the model stays where the spin left it");
        assert_eq!(m.orbit_degrees(100), None);
        // Chains restart where the motion changes.
        assert_eq!(m.key_frame_of(71, 0), 68);
        assert_eq!(m.key_frame_of(75, 0), 72);
        assert_eq!(m.key_frame_of(81, 0), 80);
        assert_eq!(m.key_frame_of(81, 6), 78);
        assert_eq!(m.frame_alignment(0), 4);
    }

    #[test]
    fn one_table_turns_as_before() {
        let m =
            motion("[motion]\nkind = \"spin\"\nframes = 120\ndegrees_per_frame = 3.0\n").unwrap();
        assert!(m.is_single());
        let p = Vec3::new(0.0, 0.075, 0.0);
        let angle = (3.0f32 * 7.0).to_radians();
        let old =
            Mat4::from_translation(p) * Mat4::from_rotation_y(angle) * Mat4::from_translation(-p);
        assert_eq!(m.scene_transform(7, p, DVec3::ZERO), Some(old));
        assert_eq!(m.key_frame_of(7, 4), 4);
        assert_eq!(m.frame_alignment(4), 4);
        assert_eq!(
            m.record(|v| format!("{v}"))[0],
            ("[motion] kind".to_string(), "spin".to_string())
        );
        let o = motion("[motion]\nframes = 4\n").unwrap();
        assert_eq!(o.orbit_degrees(3), Some(270.0));
    }

    #[test]
    fn bad_sequences_name_the_motion_and_key() {
        for (text, needle) in [
            (
                "[[motion]]\nframes = \"0-71\"\n[[motion]]\nframes = \"70-143\"\n",
                "m.toml: [[motion]] 2 frames = \"70-143\" overlaps [[motion]] 1 (frames 0-71)",
            ),
            (
                "[[motion]]\nframes = \"0-71\"\n[[motion]]\nframes = \"75-143\"\n",
                "m.toml: [[motion]] 2 frames = \"75-143\" leaves frames 72-74 without a motion",
            ),
            (
                "[[motion]]\nframes = \"1-71\"\n",
                "[[motion]] 1 frames = \"1-71\" leaves frames 0-0 without a motion",
            ),
            (
                "[[motion]]\nframes = 4\n[[motion]]\nkind = \"wobble\"\n",
                "[[motion]] 2 kind = \"wobble\": expected",
            ),
            (
                "[[motion]]\nframes = \"9-3\"\n",
                "[[motion]] 1 frames = \"9-3\": expected",
            ),
            ("[[motion]]\nframes = 0\n", "[[motion]] 1 frames = 0"),
            (
                "[[motion]]\nkind = \"orbit\"\npivot = [0.0, 0.0, 0.0]\n",
                "[[motion]] 1 pivot applies only to kind = \"spin\"",
            ),
            (
                "[[motion]]\nframes = 2\n[[motion]]\nturn_degrees = 1.0\ndegrees_per_frame = 1.0\n",
                "[[motion]] 2 takes `degrees_per_frame` or `turn_degrees`",
            ),
            ("motion = []\n", "empty list of motions"),
        ] {
            let e = motion(text).unwrap_err().to_string();
            assert!(e.contains(needle), "{text:?}: {e}");
        }
    }

    #[test]
    fn ranges_are_inclusive() {
        assert_eq!(parse_range("0-71"), Some(0..72));
        assert_eq!(parse_range(" 5 "), Some(5..6));
        assert_eq!(parse_range("3-2"), None);
        assert_eq!(parse_range("a-b"), None);
        assert_eq!(gcd(72, 4), 4);
    }
}
