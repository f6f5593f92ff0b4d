//! The settings' keys, typed: a setting that code names (a method's `reads`, the settings
//! record, `envshadow methods`) is a [`Key`], so a renamed or removed setting is a compile error.
//!
//! Only the variants live here, below every module that names a setting (the methods read
//! them, and the settings' own module sits above the methods: its values are methods and
//! flood rules). What a key spells and where it belongs (its name in a spec's table, its flag,
//! its table, [`Key::ALL`]) come from the one declaration of each setting in `settings.rs`,
//! whose `settings!` list implements them; that list's exhaustive matches make a variant
//! without a setting, or a setting without a variant, a compile error.

/// One setting of a spec's tables (`[lights]`, `[render]`, `[scene]`, `[output]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Key {
    // [lights]
    Count,
    Sampler,
    SceneLights,
    // [render]
    Width,
    Height,
    Spp,
    Filter,
    FilterWidth,
    GlossyEnv,
    Method,
    Validate,
    H0,
    MinVoters,
    FloodTo,
    PixelMajority,
    AllVoters,
    BusyVoters,
    TraceAllShare,
    SurfaceVoters,
    ScanBlock,
    Temporal,
    Keyframe,
    Background,
    BackgroundColor,
    BackgroundBlur,
    Exposure,
    View,
    Tile,
    Threads,
    // [scene]
    Up,
    Ground,
    ShadowCatcher,
    // [output]
    Dir,
    Half,
    Fps,
    Video,
}
