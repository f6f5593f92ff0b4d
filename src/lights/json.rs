//! The lights JSON: what was sampled from what, and every light's direction, energy and cell
//! solid angle.
//!
//! ```json
//! {"environment": {"source": "grace.hdr", "rotation_deg": 0, "intensity": 1,
//!                  "width": 256, "height": 128, "integral": [r, g, b]},
//!  "sampler": "sis", "count": 2,
//!  "lights": [{"index": 0, "direction": [x, y, z], "energy": [r, g, b], "solid_angle": s}, ...]}
//! ```
//! `environment` is `null` and `sampler` is `"given"` for hand-placed lights.
//!
//! The scene file's lights, when it has any, follow as `scene_lights`: each with its `name`,
//! `type` (`directional`, `point`, `spot`), `index` (its bit: directional lights are among
//! `lights` at that index, with their energy there; point and spot lights come after them),
//! `color` and `intensity` as in the file (`units`: `lux` or `cd`); point and spot lights also
//! with `position`, `radiant_intensity` (colour × cd / 683 per steradian, the map's units) and
//! `range` (`null` for none); spot lights with `axis`, `inner_cone_angle` and
//! `outer_cone_angle` (radians).

use glam::Vec3;
use serde_json::{Value, json};
use std::path::Path;

use super::{Cone, EnvSummary, FileLight, Light, LightSet, PointLight, Sampler};
use crate::bail_input;
use crate::error::Result;

pub(super) fn to_json(set: &LightSet) -> Value {
    let environment = match &set.environment {
        Some(e) => json!({
            "source": e.source,
            "rotation_deg": e.rotation_deg,
            "intensity": e.intensity,
            "width": e.width,
            "height": e.height,
            "integral": e.integral,
        }),
        None => Value::Null,
    };
    let lights: Vec<Value> = set
        .lights
        .iter()
        .enumerate()
        .map(|(i, l)| {
            json!({
                "index": i,
                "direction": [l.dir.x, l.dir.y, l.dir.z],
                "energy": [l.energy.x, l.energy.y, l.energy.z],
                "solid_angle": l.solid_angle,
            })
        })
        .collect();
    let mut out = json!({
        "environment": environment,
        "sampler": set.sampler.map_or("given", |s| s.name()),
        "count": set.lights.len(),
        "lights": lights,
    });
    if !set.from_file.is_empty() {
        let file: Vec<Value> = set.from_file.iter().map(|f| file_light(set, f)).collect();
        out["scene_lights"] = Value::Array(file);
    }
    out
}

fn file_light(set: &LightSet, f: &FileLight) -> Value {
    let v = |v: glam::Vec3| json!([v.x, v.y, v.z]);
    let directional = f.index < set.lights.len();
    let mut out = json!({
        "name": f.name,
        "type": f.kind,
        "index": f.index,
        "color": v(f.color),
        "intensity": f.intensity,
        "units": if directional { "lux" } else { "cd" },
    });
    if !directional {
        let p = &set.points[f.index - set.lights.len()];
        out["position"] = v(p.position);
        out["radiant_intensity"] = v(p.intensity);
        out["range"] = if p.range < f32::INFINITY {
            json!(p.range)
        } else {
            Value::Null
        };
        if let (Some(cone), Some((inner, outer))) = (&p.spot, f.cone) {
            out["axis"] = v(cone.axis);
            out["inner_cone_angle"] = json!(inner);
            out["outer_cone_angle"] = json!(outer);
        }
    }
    out
}

/// The `scene_lights` of a lights JSON (`count` directional lights listed), as the set's
/// file lights and point lights.
fn parse_file_lights(
    path: &Path,
    root: &Value,
    count: usize,
) -> Result<(Vec<FileLight>, Vec<PointLight>)> {
    let Some(items) = root.get("scene_lights") else {
        return Ok((Vec::new(), Vec::new()));
    };
    let Some(items) = items.as_array() else {
        bail_input!(path, "scene_lights: not an array");
    };
    if count + items.len() > crate::limits::MAX_LIGHTS {
        bail_input!(
            path,
            "{} lights in all; at most {} are allowed",
            count + items.len(),
            crate::limits::MAX_LIGHTS
        );
    }
    let (mut file, mut points) = (Vec::new(), Vec::new());
    for (i, item) in items.iter().enumerate() {
        let what = |k: &str| format!("scene_lights[{i}].{k}");
        let vec3 = |k: &str| -> Result<glam::Vec3> {
            let a = finite_array::<3>(path, item.get(k), &what(k))?;
            Ok(glam::Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32))
        };
        let name = match item.get("name").and_then(Value::as_str) {
            Some(n) => n.to_string(),
            None => bail_input!(path, "{}: missing or not a string", what("name")),
        };
        let kind = match item.get("type").and_then(Value::as_str) {
            Some("directional") => "directional",
            Some("point") => "point",
            Some("spot") => "spot",
            _ => bail_input!(
                path,
                "{}: expected \"directional\", \"point\" or \"spot\"",
                what("type")
            ),
        };
        let Some(index) = item.get("index").and_then(Value::as_u64) else {
            bail_input!(path, "{}: missing or not an integer", what("index"));
        };
        let index = index as usize;
        let color = vec3("color")?;
        let intensity = finite_number(path, item.get("intensity"), &what("intensity"))? as f32;
        let mut cone = None;
        if kind == "directional" {
            if index >= count {
                bail_input!(
                    path,
                    "{}: {index} is not one of the {count} lights",
                    what("index")
                );
            }
        } else {
            if index != count + points.len() {
                bail_input!(
                    path,
                    "{}: {index}, but the next point or spot light's is {}",
                    what("index"),
                    count + points.len()
                );
            }
            let range = match item.get("range") {
                None | Some(Value::Null) => f32::INFINITY,
                r => match r.and_then(Value::as_f64) {
                    Some(r) if r > 0.0 && r.is_finite() => r as f32,
                    _ => bail_input!(path, "{}: not a number > 0 or null", what("range")),
                },
            };
            let spot = if kind == "spot" {
                let inner = finite_number(
                    path,
                    item.get("inner_cone_angle"),
                    &what("inner_cone_angle"),
                )? as f32;
                let outer = finite_number(
                    path,
                    item.get("outer_cone_angle"),
                    &what("outer_cone_angle"),
                )? as f32;
                let axis = vec3("axis")?;
                cone = Some((inner, outer));
                Some(Cone::new(axis, inner, outer))
            } else {
                None
            };
            points.push(PointLight {
                position: vec3("position")?,
                intensity: vec3("radiant_intensity")?,
                range,
                spot,
            });
        }
        file.push(FileLight {
            name,
            kind,
            index,
            color,
            intensity,
            cone,
        });
    }
    Ok((file, points))
}

fn finite_array<const K: usize>(path: &Path, v: Option<&Value>, what: &str) -> Result<[f64; K]> {
    let Some(arr) = v.and_then(Value::as_array) else {
        bail_input!(path, "{what}: missing or not an array");
    };
    if arr.len() != K {
        bail_input!(path, "{what}: expected {K} numbers, found {}", arr.len());
    }
    let mut out = [0.0; K];
    for (k, x) in arr.iter().enumerate() {
        match x.as_f64() {
            Some(f) if f.is_finite() => out[k] = f,
            _ => bail_input!(path, "{what}[{k}]: not a finite number ({x})"),
        }
    }
    Ok(out)
}

fn finite_number(path: &Path, v: Option<&Value>, what: &str) -> Result<f64> {
    match v.and_then(Value::as_f64) {
        Some(f) if f.is_finite() => Ok(f),
        _ => bail_input!(path, "{what}: missing or not a finite number"),
    }
}

/// Reads a lights JSON written by [`LightSet::write_json`] and rebuilds the lookup and adjacency.
/// Energies and solid angles are taken from the file.
pub fn read_json(path: &Path) -> Result<LightSet> {
    crate::limits::check_file_size(path, "lights file")?;
    let text = match std::fs::read(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            bail_input!(path, "lights file not found")
        }
        Err(e) => bail_input!(path, "cannot read lights file: {e}"),
    };
    parse_json(&text, path)
}

/// Parses lights JSON from memory; `path` names it in errors.
pub fn parse_json(text: &[u8], path: &Path) -> Result<LightSet> {
    let root: Value = match serde_json::from_slice(text) {
        Ok(v) => v,
        Err(e) => bail_input!(path, "not valid JSON: {e}"),
    };
    let sampler = match root.get("sampler").and_then(Value::as_str) {
        Some("given") => None,
        Some(s) => match s.parse::<Sampler>() {
            Ok(s) => Some(s),
            Err(e) => bail_input!(path, "sampler: {e}"),
        },
        None => bail_input!(path, "sampler: missing or not a string"),
    };
    let environment = match root.get("environment") {
        None | Some(Value::Null) => None,
        Some(e) => {
            let source = match e.get("source").and_then(Value::as_str) {
                Some(s) => s.to_string(),
                None => bail_input!(path, "environment.source: missing or not a string"),
            };
            let size = |key: &str| -> Result<usize> {
                match e.get(key).and_then(Value::as_u64) {
                    Some(v) => Ok(v as usize),
                    None => bail_input!(path, "environment.{key}: missing or not an integer"),
                }
            };
            Some(EnvSummary {
                source,
                rotation_deg: finite_number(
                    path,
                    e.get("rotation_deg"),
                    "environment.rotation_deg",
                )? as f32,
                intensity: finite_number(path, e.get("intensity"), "environment.intensity")? as f32,
                width: size("width")?,
                height: size("height")?,
                integral: finite_array::<3>(path, e.get("integral"), "environment.integral")?,
            })
        }
    };
    let Some(items) = root.get("lights").and_then(Value::as_array) else {
        bail_input!(path, "lights: missing or not an array");
    };
    let count = match root.get("count").and_then(Value::as_u64) {
        Some(c) => c as usize,
        None => bail_input!(path, "count: missing or not an integer"),
    };
    if count == 0 {
        bail_input!(path, "count must be at least 1");
    }
    // Checked before the list is read: the lookup and adjacency grow with the light count.
    if count > crate::limits::MAX_LIGHTS {
        bail_input!(
            path,
            "count is {count}; at most {} lights are allowed",
            crate::limits::MAX_LIGHTS
        );
    }
    if count != items.len() {
        bail_input!(
            path,
            "count is {count} but {} lights are listed",
            items.len()
        );
    }
    let mut lights = Vec::with_capacity(count);
    for (i, item) in items.iter().enumerate() {
        let what = |k: &str| format!("lights[{i}].{k}");
        let d = finite_array::<3>(path, item.get("direction"), &what("direction"))?;
        let e = finite_array::<3>(path, item.get("energy"), &what("energy"))?;
        let s = finite_number(path, item.get("solid_angle"), &what("solid_angle"))?;
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if (len - 1.0).abs() > 1e-3 {
            bail_input!(
                path,
                "{}: not a unit vector (length {len})",
                what("direction")
            );
        }
        if e.iter().any(|&x| x < 0.0) {
            bail_input!(path, "{}: negative energy {:?}", what("energy"), e);
        }
        if s < 0.0 {
            bail_input!(path, "{}: negative solid angle {s}", what("solid_angle"));
        }
        lights.push(Light {
            dir: Vec3::new(d[0] as f32, d[1] as f32, d[2] as f32),
            energy: Vec3::new(e[0] as f32, e[1] as f32, e[2] as f32),
            solid_angle: s as f32,
        });
    }
    let (from_file, points) = parse_file_lights(path, &root, count)?;
    let mut set = LightSet::from_lights(lights);
    set.sampler = sampler;
    set.environment = environment;
    if !points.is_empty() || !from_file.is_empty() {
        set.points = points;
        set.from_file = from_file;
        set.adjacency_for_points();
    }
    Ok(set)
}
