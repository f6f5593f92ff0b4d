//! Render settings, each declared once: its name in a spec's table, its flag, its type, its
//! default, what it means (the doc comment is the flag's `--help`) and its range check.
//!
//! [`settings!`] turns the one declaration list (`key.rs`'s `settings_list!`, where each
//! setting's `--help` is its doc comment) into three structs: the resolved settings
//! (`Render`), a *layer* of settings some of which are given (`RenderLayer`: a spec's
//! `[render]` table through serde, the command line through clap), and a *sweep* of values
//! per setting for the measuring commands (`RenderSweep`: `bench --lights 50,100 --h0 8,16`).
//! Layers merge flags over spec ([`RenderLayer::over`]), then defaults fill the rest
//! ([`RenderLayer::resolve`]). Each given value is checked once, where it enters, with an error
//! that names it as the user wrote it (`--h0 3: …` or `spec.toml: [render] h0 = 3: …`).
//!
//! The list also makes the settings' typed keys ([`Key`]: the variant in `key.rs`; name, flag,
//! table and [`Key::ALL`] here). A new setting is one entry in the list; the code that reads it
//! uses the resolved struct's field, and a method that reads it names its key in its order's
//! or rule's `reads`. A method setting's default is the
//! methods' own ([`Params::DEFAULT`]), which the list reads, and [`Render::params`] passes it
//! on.

use std::fmt::Debug;
use std::path::{Path, PathBuf};

use crate::background::{Background, Rgb, check_rgb};
use crate::error::{Result, input_error};
use crate::key::Key;
use crate::lights::Sampler;
use crate::output::exr::ExrLayout;
use crate::output::names::{FrameNames, Pattern};
use crate::output::rate::FrameRate;
use crate::predict::{FloodTo, Method, Params};
use crate::samples::{Filter, Samples};
use crate::scene::ground::Ground;
use crate::scene::playback::{AfterEnd, Choice};
use crate::scene::{AllowedFolder, Up};
use crate::shading_rate::ShadingRate;
use crate::view::View;

/// A setting's value as flags, specs and messages spell it.
pub trait Value: Clone + Debug + Send + Sync + 'static {
    fn show(&self) -> String;

    /// The value as a spec writes it (`render --write-spec`): read back, it is this value.
    fn toml(&self) -> toml::Value {
        toml::Value::String(self.show())
    }
}

macro_rules! value_by_display {
    ($($t:ty),*) => {$(
        impl Value for $t {
            fn show(&self) -> String {
                self.to_string()
            }
        }
    )*};
}

macro_rules! value_integer {
    ($($t:ty),*) => {$(
        impl Value for $t {
            fn show(&self) -> String {
                self.to_string()
            }

            fn toml(&self) -> toml::Value {
                toml::Value::Integer(i64::try_from(*self).unwrap_or(i64::MAX))
            }
        }
    )*};
}
value_integer!(u32, usize);

impl Value for bool {
    fn show(&self) -> String {
        self.to_string()
    }

    fn toml(&self) -> toml::Value {
        toml::Value::Boolean(*self)
    }
}

impl Value for f32 {
    fn show(&self) -> String {
        self.to_string()
    }

    fn toml(&self) -> toml::Value {
        toml::Value::Float(spec_float(*self))
    }
}

/// `x` as the f64 a spec writes: its shortest spelling (0.1, not 0.100000001…) when that
/// reads back as `x`, else its exact value.
pub fn spec_float(x: f32) -> f64 {
    let short: f64 = format!("{x:?}").parse().unwrap_or(x as f64);
    if short as f32 == x { short } else { x as f64 }
}

impl Value for Rgb {
    fn show(&self) -> String {
        self.to_string()
    }

    fn toml(&self) -> toml::Value {
        toml::Value::Array(
            self.0
                .iter()
                .map(|&c| toml::Value::Float(spec_float(c)))
                .collect(),
        )
    }
}

value_by_display!(
    Method,
    FloodTo,
    Filter,
    ShadingRate,
    Background,
    Ground,
    Up,
    View,
    FrameRate,
    Pattern,
    ExrLayout,
    AllowedFolder,
    Choice,
    AfterEnd
);

impl Value for Sampler {
    fn show(&self) -> String {
        self.name().to_string()
    }
}

impl Value for PathBuf {
    fn show(&self) -> String {
        self.display().to_string()
    }
}

/// Reads a value from a spec as its command-line spelling (one parser per type).
macro_rules! deserialize_by_from_str {
    ($($t:ty),*) => {$(
        impl<'de> serde::Deserialize<'de> for $t {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
                let s = String::deserialize(d)?;
                s.parse().map_err(serde::de::Error::custom)
            }
        }
    )*};
}
deserialize_by_from_str!(
    Method,
    FloodTo,
    Sampler,
    Filter,
    ShadingRate,
    Background,
    Ground,
    Up,
    View,
    Pattern,
    ExrLayout,
    AllowedFolder,
    AfterEnd
);

/// Where a layer of settings came from, so a message names a value as the user wrote it.
#[derive(Clone, Copy, Debug)]
pub enum Source<'a> {
    /// The spec file's table.
    Spec(&'a Path),
    /// The command line.
    Flags,
}

impl Source<'_> {
    /// An input error about setting `key` (spec) / `flag` (command line) of `table`.
    pub fn error(self, table: &str, key: &str, flag: &str, message: String) -> anyhow::Error {
        match self {
            Source::Spec(path) => input_error(path, format!("[{table}] {key} {message}")),
            Source::Flags => input_error("", format!("--{flag} {message}")),
        }
    }
}

/// A setting's check: `Err(why)` for a value out of range.
pub type Check<T> = fn(&T) -> std::result::Result<(), String>;

/// Makes every group of settings (one table of a spec each) from the list, and the [`Key`]s'
/// methods; see the module doc.
macro_rules! settings {
    ($(
        $(#[doc = $sdoc:literal])*
        [$table:literal] $name:ident, $layer:ident, $sweep:ident {
            $(
                $(#[doc = $doc:literal])*
                $field:ident: $ty:ty = $default:expr, key $key:ident,
                    flag $flag:literal [$($arg:tt)*], check $check:expr;
            )*
        }
    )*) => {
        $(
            settings_table! {
                $(#[doc = $sdoc])*
                [$table] $name, $layer, $sweep {
                    $(
                        $(#[doc = $doc])*
                        $field: $ty = $default, key $key, flag $flag [$($arg)*], check $check;
                    )*
                }
            }
        )*

        impl Key {
            /// Every setting, table by table, each table's in its list's order.
            pub const ALL: &'static [Key] = &[$($(Key::$key,)*)*];

            /// The setting's name in its spec table (`min_voters`).
            pub fn name(self) -> &'static str {
                match self {
                    $($(Key::$key => stringify!($field),)*)*
                }
            }

            /// The setting's command-line flag, without its dashes (`min-voters`).
            pub fn flag(self) -> &'static str {
                match self {
                    $($(Key::$key => $flag,)*)*
                }
            }

            /// The spec table the setting belongs to (`render`).
            pub fn table(self) -> &'static str {
                match self {
                    $($(Key::$key => $table,)*)*
                }
            }

            /// The setting whose spec name is `name`.
            pub fn from_name(name: &str) -> Option<Key> {
                Key::ALL.iter().copied().find(|k| k.name() == name)
            }
        }
    };
}

/// One table's structs and their methods, for [`settings!`].
macro_rules! settings_table {
    (
        $(#[doc = $sdoc:literal])*
        [$table:literal] $name:ident, $layer:ident, $sweep:ident {
            $(
                $(#[doc = $doc:literal])*
                $field:ident: $ty:ty = $default:expr, key $key:ident,
                    flag $flag:literal [$($arg:tt)*], check $check:expr;
            )*
        }
    ) => {
        $(#[doc = $sdoc])*
        #[derive(Clone, Debug, PartialEq)]
        pub struct $name {
            $( $(#[doc = $doc])* pub $field: $ty, )*
        }

        impl Default for $name {
            fn default() -> Self {
                $name { $( $field: $default, )* }
            }
        }

        impl $name {
            /// The spec table these settings come from.
            pub const TABLE: &'static str = $table;

            /// Every setting given: the base a later layer goes over.
            pub fn layer(&self) -> $layer {
                $layer { $( $field: Some(self.$field.clone()), )* }
            }
        }

        $(#[doc = $sdoc])*
        /// Some of them given (the spec's table, or the command line); see [`Self::resolve`].
        #[derive(Clone, Debug, Default, PartialEq, clap::Args, serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct $layer {
            $(
                $(#[doc = $doc])*
                #[arg(long = $flag, $($arg)*)]
                #[serde(default)]
                pub $field: Option<$ty>,
            )*
        }

        impl $layer {
            /// The settings given here over those of `base`.
            pub fn over(self, base: $layer) -> $layer {
                $layer { $( $field: self.$field.or(base.$field), )* }
            }

            /// The settings, with defaults for those not given.
            pub fn resolve(&self) -> $name {
                let d = $name::default();
                $name { $( $field: self.$field.clone().unwrap_or(d.$field), )* }
            }

            /// The given settings: each key, and its value as spelled.
            pub fn given_keys(&self) -> Vec<(Key, String)> {
                let mut v = Vec::new();
                $(
                    if let Some(x) = &self.$field {
                        v.push((Key::$key, Value::show(x)));
                    }
                )*
                v
            }

            /// The given settings as a spec's table writes them (`render --write-spec`).
            pub fn spec_table(&self) -> toml::Table {
                let mut t = toml::Table::new();
                $(
                    if let Some(x) = &self.$field {
                        t.insert(stringify!($field).to_string(), Value::toml(x));
                    }
                )*
                t
            }

            /// Forgets the setting `key`, if given.
            pub fn clear(&mut self, key: Key) {
                $( if key == Key::$key { self.$field = None; } )*
            }

            /// Checks every given value; the error names it as `source` spells it.
            pub fn check(&self, source: Source) -> Result<()> {
                $(
                    if let Some(x) = &self.$field {
                        let check: Check<$ty> = $check;
                        if let Err(why) = check(x) {
                            let shown = Value::show(x);
                            let message = match source {
                                Source::Spec(_) => format!("= {shown}: {why}"),
                                Source::Flags => format!("{shown}: {why}"),
                            };
                            return Err(source.error($table, stringify!($field), $flag, message));
                        }
                    }
                )*
                Ok(())
            }
        }

        $(#[doc = $sdoc])*
        /// Several values per setting, comma-separated: the measuring commands render every
        /// combination (see [`Self::layers`]).
        #[derive(Clone, Debug, Default, clap::Args)]
        pub struct $sweep {
            $(
                $(#[doc = $doc])*
                #[arg(long = $flag, value_delimiter = ',', $($arg)*)]
                pub $field: Vec<$ty>,
            )*
        }

        impl $sweep {
            /// Every combination of the values given, as layers (one empty layer when none
            /// is given); the first setting varies slowest.
            // A group of one setting updates no other field.
            #[allow(clippy::needless_update)]
            pub fn layers(&self) -> Vec<$layer> {
                let mut out = vec![$layer::default()];
                $(
                    if !self.$field.is_empty() {
                        out = out
                            .into_iter()
                            .flat_map(|l| {
                                self.$field.iter().map(move |x| $layer {
                                    $field: Some(x.clone()),
                                    ..l.clone()
                                })
                            })
                            .collect();
                    }
                )*
                out
            }

            /// The settings given a value list: each key, and how many values.
            pub fn swept_keys(&self) -> Vec<(Key, usize)> {
                let mut v = Vec::new();
                $(
                    if !self.$field.is_empty() {
                        v.push((Key::$key, self.$field.len()));
                    }
                )*
                v
            }

            /// Checks every given value; the error names the flag.
            pub fn check(&self) -> Result<()> {
                for layer in self.layers() {
                    layer.check(Source::Flags)?;
                }
                Ok(())
            }
        }
    };
}

fn any<T>(_: &T) -> std::result::Result<(), String> {
    Ok(())
}

fn check_spp(v: &u32) -> std::result::Result<(), String> {
    if (1..=8).any(|k| k * k == *v) {
        Ok(())
    } else {
        Err(
            "samples per pixel must be a square from 1 to 64 (1, 4, 9, 16, 25, 36, 49 or 64)"
                .into(),
        )
    }
}

fn check_filter_width(v: &f32) -> std::result::Result<(), String> {
    if v.is_finite() && (*v == 0.0 || (0.5..=8.0).contains(v)) {
        Ok(())
    } else {
        Err("must be 0 (the filter's default) or 0.5 to 8 pixels".into())
    }
}

fn check_h0(v: &u32) -> std::result::Result<(), String> {
    if (2..=256).contains(v) && v.is_power_of_two() {
        Ok(())
    } else {
        Err("the coarse grid spacing must be a power of two from 2 to 256".into())
    }
}

fn check_min_voters(v: &u32) -> std::result::Result<(), String> {
    if (1..=4).contains(v) {
        Ok(())
    } else {
        Err("must be 1 to 4 (a pixel has at most 4 voters)".into())
    }
}

fn check_busy_voters(v: &u32) -> std::result::Result<(), String> {
    if *v <= 4 {
        Ok(())
    } else {
        Err("must be 0 (off) to 4 (a pixel has at most 4 voters)".into())
    }
}

fn check_percent(v: &u32) -> std::result::Result<(), String> {
    if *v <= 100 {
        Ok(())
    } else {
        Err("must be a percentage, 0 (off) to 100".into())
    }
}

fn check_scan_block(v: &u32) -> std::result::Result<(), String> {
    if *v >= 8 {
        Ok(())
    } else {
        Err("must be at least 8".into())
    }
}

/// Longest allowed key-frame interval.
pub const MAX_KEYFRAME: u32 = 10_000;

fn check_keyframe(v: &u32) -> std::result::Result<(), String> {
    if *v <= MAX_KEYFRAME {
        Ok(())
    } else {
        Err(format!(
            "must be 0 (the motion's default) to {MAX_KEYFRAME}"
        ))
    }
}

fn check_tile(v: &u32) -> std::result::Result<(), String> {
    if *v == 0 || *v >= 8 {
        Ok(())
    } else {
        Err("the tile is too small: use 0 (whole frame) or at least 8".into())
    }
}

fn check_blur(v: &f32) -> std::result::Result<(), String> {
    if v.is_finite() && (1.0..=90.0).contains(v) {
        Ok(())
    } else {
        Err("must be 1 to 90 degrees".into())
    }
}

/// Highest frame rate: a turntable is watched, not sampled.
pub const MAX_FPS: f64 = 240.0;

fn check_fps(v: &FrameRate) -> std::result::Result<(), String> {
    if (1.0..=MAX_FPS).contains(&v.as_f64()) {
        Ok(())
    } else {
        Err(format!("must be a frame rate from 1 to {MAX_FPS}"))
    }
}

/// Highest start frame: Blender's own highest frame number.
pub const MAX_FRAME_START: u32 = 1_048_574;

fn check_frame_start(v: &u32) -> std::result::Result<(), String> {
    if *v <= MAX_FRAME_START {
        Ok(())
    } else {
        Err(format!(
            "must be 0 to {MAX_FRAME_START} (Blender's highest frame)"
        ))
    }
}

fn check_finite(v: &f32) -> std::result::Result<(), String> {
    if v.is_finite() {
        Ok(())
    } else {
        Err("is not a finite number".into())
    }
}

fn check_intensity(v: &f32) -> std::result::Result<(), String> {
    check_finite(v)?;
    if *v >= 0.0 {
        Ok(())
    } else {
        Err("must be ≥ 0".into())
    }
}

fn check_distance(v: &f32) -> std::result::Result<(), String> {
    check_finite(v)?;
    if *v >= 0.0 {
        Ok(())
    } else {
        Err("must be 0 (auto-framed) or a positive distance".into())
    }
}

fn check_elevation(v: &f32) -> std::result::Result<(), String> {
    check_finite(v)?;
    if (-90.0..=90.0).contains(v) {
        Ok(())
    } else {
        Err("must be -90 to 90 degrees".into())
    }
}

fn check_vfov(v: &f32) -> std::result::Result<(), String> {
    check_finite(v)?;
    if *v > 0.0 && *v < 180.0 {
        Ok(())
    } else {
        Err("must be between 0 and 180 degrees (both excluded)".into())
    }
}

crate::key::settings_list!(settings);

impl Render {
    /// The frame's tiles (the frame-anchored grid of `tile`), inside `region` if given.
    pub fn tiles(&self, region: Option<crate::tile::Rect>) -> Vec<crate::tile::Tile> {
        crate::tile::tiles(self.width, self.height, self.tile, region)
    }

    /// The pixels' sample pattern.
    pub fn samples(&self) -> Samples {
        Samples::new(self.spp, self.filter, self.filter_width)
    }

    /// The prediction methods' parameters.
    pub fn params(&self) -> Params {
        Params {
            h0: self.h0,
            min_voters: self.min_voters,
            flood_to: self.flood_to,
            scan_block: self.scan_block,
            pixel_majority: self.pixel_majority,
            surface_voters: self.surface_voters,
            all_voters: self.all_voters,
            busy_voters: self.busy_voters,
            trace_all_share: self.trace_all_share,
        }
    }
}

impl Output {
    /// How the frames' files are named (`output_pattern`, `frame_start`).
    pub fn frame_names(&self) -> FrameNames {
        FrameNames::new(self.output_pattern.clone(), self.frame_start as usize)
    }
}

/// Settings some method reads: one that the chosen method does not read is refused.
pub fn method_specific(key: Key) -> bool {
    Method::all().any(|m| m.reads(key))
}

/// Every setting some method reads, in [`Key::ALL`]'s order: what `envshadow methods` lists
/// per method.
pub fn method_settings() -> impl Iterator<Item = Key> {
    Key::ALL.iter().copied().filter(|&k| method_specific(k))
}

/// The methods that read `key`, for messages: `grid-warp-boundary, grid-nowarp-boundary, …`.
pub fn readers(key: Key) -> String {
    let v: Vec<&str> = Method::all()
        .filter(|m| m.reads(key))
        .map(Method::name)
        .collect();
    v.join(", ")
}

/// Refuses the method-specific settings of `layer` (from `source`) that none of `methods`
/// reads: they would change nothing.
pub fn check_applies(layer: &RenderLayer, source: Source, methods: &[Method]) -> Result<()> {
    for (key, shown) in layer.given_keys() {
        if method_specific(key) && !methods.iter().any(|m| m.reads(key)) {
            let names: Vec<&str> = methods.iter().map(|m| m.name()).collect();
            let message = format!(
                "{}{shown} does not apply to {}: only {} read it",
                if matches!(source, Source::Spec(_)) {
                    "= "
                } else {
                    ""
                },
                names.join(", "),
                readers(key)
            );
            return Err(source.error(Render::TABLE, key.name(), key.flag(), message));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_override_the_spec_and_defaults_fill_the_rest() {
        let spec = RenderLayer {
            width: Some(320),
            h0: Some(8),
            ..Default::default()
        };
        let flags = RenderLayer {
            width: Some(100),
            ..Default::default()
        };
        let r = flags.over(spec).resolve();
        assert_eq!((r.width, r.h0, r.height), (100, 8, 480));
    }

    #[test]
    fn a_sweep_renders_every_combination() {
        let sweep = RenderSweep {
            h0: vec![8, 16],
            flood_to: vec![FloodTo::All, FloodTo::Contrary],
            ..Default::default()
        };
        let layers = sweep.layers();
        assert_eq!(layers.len(), 4);
        assert_eq!(
            (layers[1].h0, layers[1].flood_to),
            (Some(8), Some(FloodTo::Contrary))
        );
        assert_eq!(
            RenderSweep::default().layers(),
            vec![RenderLayer::default()]
        );
    }

    #[test]
    fn a_bad_value_is_named_as_the_user_wrote_it() {
        let layer = RenderLayer {
            h0: Some(3),
            ..Default::default()
        };
        let flag = layer.check(Source::Flags).unwrap_err().to_string();
        assert!(flag.starts_with("--h0 3: "), "{flag}");
        let spec = layer
            .check(Source::Spec(Path::new("a.toml")))
            .unwrap_err()
            .to_string();
        assert!(spec.starts_with("a.toml: [render] h0 = 3: "), "{spec}");
    }

    #[test]
    fn a_setting_no_chosen_method_reads_is_refused() {
        let layer = RenderLayer {
            h0: Some(8),
            ..Default::default()
        };
        let err = check_applies(&layer, Source::Flags, &[Method::BRUTE])
            .unwrap_err()
            .to_string();
        assert!(err.contains("--h0 8 does not apply to brute"), "{err}");
        assert!(check_applies(&layer, Source::Flags, &[Method::BRUTE, Method::DEFAULT]).is_ok());
    }

    /// Issue 37: a method setting's default is written once, in `Params::DEFAULT`; the
    /// `[render]` defaults give the very same parameters.
    #[test]
    fn the_default_settings_give_the_default_params() {
        assert_eq!(RenderLayer::default().resolve().params(), Params::default());
        assert_eq!(Render::default().params(), Params::DEFAULT);
    }

    /// Whether `help` names `value` as the default: "default 16", "Default false.", "default
    /// `out`", "auto (the default: …)", "sis (…, the default)" or "0, the default".
    fn names_default(help: &str, value: &str) -> bool {
        // A list's value as the flag spells it ("[0.18, 0.18, 0.18]" is typed 0.18,0.18,0.18).
        let typed: String = value
            .chars()
            .filter(|c| !matches!(c, '[' | ']' | ' '))
            .collect();
        let lower = help.to_lowercase();
        // `s[at..at + len]` is a whole word or number (not 1 of 16, nor 0 of 0.5).
        let whole = |s: &str, at: usize, len: usize| {
            let before = s[..at].chars().next_back();
            let mut after = s[at + len..].chars();
            let end = match after.next() {
                None => true,
                Some('.') => !after.next().is_some_and(|c| c.is_ascii_digit()),
                Some(c) => !c.is_alphanumeric(),
            };
            end && !before.is_some_and(|c| c.is_alphanumeric() || c == '.')
        };
        [value, typed.as_str()].iter().any(|v| {
            let default = format!("default {v}");
            lower
                .match_indices(&default)
                .any(|(at, m)| whole(&lower, at, m.len()))
                || lower.contains(&format!("default `{v}`"))
                || help.match_indices(v).any(|(at, _)| {
                    if !whole(help, at, v.len()) {
                        return false;
                    }
                    let after = help[at + v.len()..].trim_start_matches('`');
                    let clause = match after.strip_prefix(" (") {
                        Some(paren) => paren.split(')').next().unwrap_or(""),
                        None => after,
                    };
                    let clause = clause.strip_prefix(", ").unwrap_or(clause);
                    (after.starts_with(" (") && clause.contains("the default"))
                        || clause.starts_with("the default")
                })
        })
    }

    /// Issue 37: `--help` said `--flood-to`'s default was `contrary-finest` after it became
    /// `auto`. Every setting's help names its default, the one `Default` gives.
    #[test]
    fn every_settings_help_names_its_real_default() {
        use clap::Args;
        let cmd = clap::Command::new("settings");
        let cmd = LightsLayer::augment_args(cmd);
        let cmd = RenderLayer::augment_args(cmd);
        let cmd = EnvLayer::augment_args(cmd);
        let cmd = CameraLayer::augment_args(cmd);
        let cmd = SceneLayer::augment_args(cmd);
        let cmd = OutputLayer::augment_args(cmd);
        let defaults = [
            Lights::default().layer().given_keys(),
            Render::default().layer().given_keys(),
            EnvSettings::default().layer().given_keys(),
            CameraSettings::default().layer().given_keys(),
            SceneSettings::default().layer().given_keys(),
            Output::default().layer().given_keys(),
        ]
        .concat();
        assert_eq!(defaults.len(), Key::ALL.len());
        let mut failures = Vec::new();
        for (key, value) in defaults {
            let arg = cmd
                .get_arguments()
                .find(|a| a.get_id() == key.name())
                .unwrap_or_else(|| panic!("no flag for {key:?}"));
            assert_eq!(arg.get_long(), Some(key.flag()));
            let help = arg.get_help().map(|h| h.to_string()).unwrap_or_default();
            if !names_default(&help, &value) {
                failures.push(format!("--{}: default {value}, help: {help}", key.flag()));
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
        assert!(names_default("x `auto` (the default), y", "auto"));
        assert!(!names_default("(default 16)", "1"));
        assert!(!names_default("(default 16)", "8"));
    }

    /// A key's name, flag and table are its setting's, and every key has one setting.
    #[test]
    fn keys_name_their_settings() {
        assert_eq!(Key::MinVoters.name(), "min_voters");
        assert_eq!(Key::MinVoters.flag(), "min-voters");
        assert_eq!(Key::MinVoters.table(), Render::TABLE);
        assert_eq!((Key::Dir.flag(), Key::Dir.table()), ("out", Output::TABLE));
        for &k in Key::ALL {
            assert_eq!(Key::from_name(k.name()), Some(k));
        }
        let mut names: Vec<&str> = Key::ALL.iter().map(|k| k.name()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), Key::ALL.len(), "two settings of one name");
        assert_eq!(Key::from_name("no_such_setting"), None);
    }

    /// Folder readers find a render's frame names by these settings' lines in its
    /// `settings.txt` (`FrameNames::from_record`).
    #[test]
    fn the_frame_names_lines_are_the_settings_keys() {
        use crate::output::names::{PATTERN_LINE, START_LINE};
        let line = |k: Key| format!("[{}] {}", k.table(), k.name());
        assert_eq!(line(Key::OutputPattern), PATTERN_LINE);
        assert_eq!(line(Key::FrameStart), START_LINE);
    }

    /// The settings the methods read, from their orders' and rules' `reads`.
    #[test]
    fn method_settings_are_those_some_method_reads() {
        let got: Vec<Key> = method_settings().collect();
        let want = [
            Key::H0,
            Key::MinVoters,
            Key::FloodTo,
            Key::PixelMajority,
            Key::AllVoters,
            Key::BusyVoters,
            Key::TraceAllShare,
            Key::SurfaceVoters,
            Key::ScanBlock,
            Key::Temporal,
            Key::Keyframe,
        ];
        assert_eq!(got, want);
        assert!(method_specific(Key::H0) && !method_specific(Key::Width));
    }
}
