//! envshadow: batch rendering of turntable animations of glTF scenes lit by HDR environment maps,
//! with shadows from every light, most of them predicted from coherence instead of traced
//! (Ben-Artzi, Ramamoorthi & Agrawala 2004).
//!
//! The pipeline, one module per stage:
//! - [`scene`] loads glTF or builds the `shapes` scene; [`envmap`] loads lat-long maps;
//!   [`lights`] reduces a map to N directional lights with O(1) cell lookup.
//! - [`accel`] wraps the BVH; [`camera`] makes primary rays.
//! - [`brdf`] is the glTF metallic-roughness BRDF; [`shade`] sums it over the visible lights
//!   (SIMD kernels); [`glossy`] prefilters the map for lobes too narrow for the lights.
//! - [`predict`] decides each (pixel, light) visibility: traced or predicted.
//! - [`background`] is what rays leaving the scene see; [`catcher`] shades the background's
//!   and shadow catchers' share of a pixel (its alpha too).
//! - [`tile`] splits a frame; [`context`] is the frame as its tiles see it (primary and shadow
//!   rays); [`driver`] renders one tile; [`frame`] renders one frame's tiles into a [`film`];
//!   [`inputs`] are loaded once per run; [`coordinator`] schedules frames and their temporal
//!   chains over threads and streams them to the writer ([`run`]'s `FrameSink`, e.g.
//!   [`frame_files`]).
//! - [`output`] writes EXR/PNG/CSV/JSON atomically; [`anim`] parses animation specs;
//!   [`report`] builds `report.html` from a finished render's folder.
//! - [`farm`] splits a run into jobs for many machines and assembles their outputs;
//!   [`temporal`] carries a frame's visibility to the next (`--temporal`); [`simd`] picks the
//!   AVX2 or SSE2 copy of the hot kernels at run time (same bits either way).

pub mod accel;
pub mod anim;
pub mod background;
pub mod bench;
pub mod bits;
pub mod blockers;
pub mod brdf;
pub mod buffers;
pub mod camera;
pub mod cancel;
pub mod catcher;
pub mod context;
pub mod coordinator;
pub mod cryptomatte;
pub mod driver;
pub mod envmap;
pub mod error;
pub mod export;
pub mod farm;
pub mod film;
pub mod folder;
pub mod frame;
pub mod frame_files;
pub mod frames;
pub mod glossy;
pub mod history;
pub mod inputs;
pub mod key;
pub mod lattice;
pub mod lights;
pub mod limits;
pub mod motion;
pub mod moved;
pub mod offset;
pub mod output;
pub mod paper;
pub mod plot;
pub mod predict;
pub mod radiance;
pub mod raydump;
pub mod reflection;
pub mod report;
pub mod run;
pub mod samples;
pub mod savings;
pub mod scene;
pub mod settings;
pub mod shade;
pub mod shading_rate;
pub mod simd;
pub mod sweep;
pub mod table;
pub mod temporal;
pub mod tile;
pub mod video;
pub mod view;
