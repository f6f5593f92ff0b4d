//! A measurement sweep: the configurations a measuring command (`bench`, `table`) renders
//! one frame of. The light layers (counts × samplers), the combinations of the swept render
//! settings ([`Variant`]s, each distinct render once), the heading's settings that every row
//! shares, and the scene each light layer loads.

use std::fmt;
use std::path::Path;

use crate::anim::{AnimFlags, Animation, EnvSource, MaterialFlags};
use crate::error::{Result, input_error};
use crate::inputs::Inputs;
use crate::key::Key;
use crate::predict::Method;
use crate::settings::{
    LightsLayer, LightsSweep, RenderLayer, RenderSweep, Source, check_applies, method_specific,
};

/// The light counts a measuring command renders when none are given.
pub const DEFAULT_LIGHTS: [usize; 4] = [50, 100, 200, 400];

/// Settings a one-frame measurement cannot use: it writes no files and reads no previous
/// frame.
const NOT_MEASURED: [Key; 3] = [Key::Temporal, Key::Keyframe, Key::Exposure];

/// One combination of a sweep's render settings (beyond light counts and thread counts): the
/// settings it gives, its method, and its name in a table's rows.
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    pub layer: RenderLayer,
    pub method: Method,
    /// The method, then the flag of each swept setting that differs from the spec's:
    /// `grid-nowarp-uncertainty --flood-to contrary`.
    pub label: String,
}

impl fmt::Display for Variant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.label)
    }
}

/// The combinations of `sweep` (its thread counts apart) over the render settings of `base`,
/// with `methods` when the sweep gives none. A method-specific setting is dropped from the
/// combinations whose method does not read it (those render the same whatever its value),
/// so each distinct render is measured once; a swept setting no swept method reads, or one a
/// one-frame measurement cannot use, is refused.
pub fn variants(base: &Animation, sweep: &RenderSweep, methods: &[Method]) -> Result<Vec<Variant>> {
    sweep.check()?;
    let mut sweep = sweep.clone();
    sweep.threads.clear();
    if sweep.method.is_empty() {
        sweep.method = methods.to_vec();
    }
    for (key, _) in sweep.swept_keys() {
        if NOT_MEASURED.contains(&key) {
            return Err(input_error(
                format!("--{}", key.flag()),
                "does not apply to a measurement of one frame (no previous frame, no files)",
            ));
        }
    }
    let spec = base.render.layer();
    let several: Vec<Key> = sweep
        .swept_keys()
        .into_iter()
        .filter(|&(_, n)| n > 1)
        .map(|(key, _)| key)
        .collect();
    let mut out: Vec<Variant> = Vec::new();
    for mut layer in sweep.layers() {
        check_applies(&layer, Source::Flags, &sweep.method)?;
        let method = layer.method.unwrap_or(base.render.method);
        for (key, _) in layer.given_keys() {
            if method_specific(key) && !method.reads(key) {
                layer.clear(key);
            }
        }
        // The method, then each setting swept over several values that this combination
        // gives otherwise than the spec (the settings swept over one value are the heading's).
        let mut label = method.to_string();
        let spec = spec.given_keys();
        for (key, shown) in layer.given_keys() {
            let was = spec.iter().find(|g| g.0 == key).map(|g| &g.1);
            if key != Key::Method && several.contains(&key) && was != Some(&shown) {
                label.push_str(&format!(" --{} {shown}", key.flag()));
            }
        }
        let v = Variant {
            layer,
            method,
            label,
        };
        if !out.contains(&v) {
            out.push(v);
        }
    }
    Ok(out)
}

/// The settings a sweep gives one value, for a table's heading (", h0 8, min_voters 2";
/// empty when none): the rows do not name them.
pub fn tuning(sweep: &RenderSweep) -> String {
    let one = sweep
        .layers()
        .into_iter()
        .next()
        .unwrap_or_default()
        .given_keys();
    let mut s = String::new();
    for (key, n) in sweep.swept_keys() {
        if n == 1 && ![Key::Method, Key::Threads, Key::Width, Key::Height].contains(&key) {
            let shown = one.iter().find(|g| g.0 == key).map(|g| g.1.as_str());
            s.push_str(&format!(", {} {}", key.name(), shown.unwrap_or_default()));
        }
    }
    s
}

/// The animation `spec` with the inputs of one light layer (count, sampler) loaded.
pub fn load(
    spec: &Path,
    lights: &LightsLayer,
    material: &MaterialFlags,
) -> Result<(Animation, Inputs)> {
    load_scene(spec, None, lights, material)
}

/// [`load`] for a spec or a glTF model (an auto-framed turntable,
/// [`Animation::of_model`]), lit by `env` when given (`sky`: the built-in sky).
pub fn load_scene(
    scene: &Path,
    env: Option<&Path>,
    lights: &LightsLayer,
    material: &MaterialFlags,
) -> Result<(Animation, Inputs)> {
    let flags = AnimFlags {
        lights: lights.clone(),
        material: material.clone(),
        ..Default::default()
    };
    let mut anim = if crate::anim::is_model(scene) {
        Animation::of_model(scene, None, &flags)?
    } else {
        Animation::load(scene, &flags)?
    };
    if let Some(env) = env {
        anim.env = if env == Path::new("sky") {
            EnvSource::Sky
        } else {
            EnvSource::File(env.to_path_buf())
        };
    }
    let inputs = Inputs::load(&anim)?;
    Ok((anim, inputs))
}

/// The light layers of a sweep: its counts (default [`DEFAULT_LIGHTS`]) × its samplers.
pub fn light_layers(sweep: &LightsSweep) -> Result<Vec<LightsLayer>> {
    let mut sweep = sweep.clone();
    if sweep.count.is_empty() {
        sweep.count = DEFAULT_LIGHTS.to_vec();
    }
    sweep.check()?;
    Ok(sweep.layers())
}
