//! The integration tests, as one test binary: cargo links one executable for all of them
//! instead of one per file (each linking the whole library again), and a module path names
//! each test (`cargo test --release --test it lights::`).
//!
//! Shared test data stays beside this folder: `tests/data/` and `tests/farm-hosts.sh`, found
//! from `CARGO_MANIFEST_DIR`.
//!
//! Tests may compute expected values with the host's maths (`f32::sin`, …, which clippy.toml
//! keeps out of the crate): they are compared within tolerances, never written as output.
#![allow(clippy::disallowed_methods)]

mod alpha;
mod animation_farm;
mod animation_playback;
mod bench_script;
mod chaos;
mod cli;
mod common;
mod compositing;
mod compositor_exr;
mod envmap;
mod export;
mod farm;
mod figures;
mod frames;
mod fuzz_regressions;
mod glossy;
mod golden;
mod hardening;
mod hardening_edges;
mod hardening_formats;
mod hardening_messages;
mod hardening_pixels;
mod help_drift;
mod hostile;
mod interrupt;
mod lights;
mod look;
mod materials;
mod maths;
mod memory;
mod motion;
mod names;
mod outputs;
mod predict;
mod punctual;
mod raydump;
mod render;
mod report;
mod rerender_note;
mod resume;
mod samples;
mod scale;
mod scene;
mod simd;
mod slurm;
mod temporal;
mod terminator;
mod truck;
mod writing;
