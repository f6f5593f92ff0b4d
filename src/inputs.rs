//! An animation's inputs, loaded once per run: the scene as the spec asks for it, the map, its
//! lights and the backdrop; the still scene's BVH and the glossy prefilter, each made once by
//! the first frame that needs it.

use std::borrow::Cow;
use std::path::Path;
use std::sync::OnceLock;

use anyhow::Context;

use crate::accel::{Accel, Split};
use glam::Mat4;

use crate::anim::{Animation, EnvSource, MotionKind, SceneSource};
use crate::background::Backdrop;
use crate::envmap::EnvMap;
use crate::error::Result;
use crate::glossy::Glossy;
use crate::lights::LightSet;
use crate::scene::playback::clip_time;
use crate::scene::{Model, Scene};

/// An animation's inputs, loaded once per run.
pub struct Inputs {
    /// The scene as the spec asks for it: stood up, its catchers marked, a ground added
    /// ([`Animation::prepare_scene`]).
    pub scene: Scene,
    pub env: EnvMap,
    pub lights: LightSet,
    /// What rays that leave the scene see.
    pub backdrop: Backdrop,
    /// The BVH of the unposed scene, built by the first frame that needs it: frames whose
    /// geometry does not move (orbit turntables, still cameras) share one build per run.
    still: OnceLock<Accel>,
    /// The posed scene split into the triangles the played animation moves and the others,
    /// whose hierarchy the first posed frame builds and every pose shares ([`Split`]).
    split: OnceLock<Split>,
    /// The prefiltered environment, made by the first frame that needs it: only when some
    /// material is glossier than the lights resolve (see [`Glossy`]).
    glossy: OnceLock<Option<Glossy>>,
    /// The file's animation this run plays (`[scene] animation`), if any.
    pub playing: Option<Playing>,
}

/// The animation a run plays and how a frame's moment in it is found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Playing {
    /// Its index in the file's list.
    pub clip: usize,
    /// Its length, seconds.
    pub duration: f64,
    /// Whether it moves any vertex (an animation may move only a camera or an empty node).
    pub deforms: bool,
}

impl Inputs {
    /// Inputs from parts already loaded.
    pub fn new(scene: Scene, env: EnvMap, lights: LightSet) -> Inputs {
        Inputs {
            scene,
            env,
            lights,
            backdrop: Backdrop::Environment,
            still: OnceLock::new(),
            split: OnceLock::new(),
            glossy: OnceLock::new(),
            playing: None,
        }
    }

    /// The moment of the played animation `frame` shows, as (clip, seconds into it): None
    /// when no animation plays; an error naming the frame past the end under
    /// `animation_end = stop`.
    pub fn clip_at(&self, anim: &Animation, frame: usize) -> Result<Option<(usize, f64)>> {
        let Some(p) = self.playing else {
            return Ok(None);
        };
        let settings = &anim.scene_settings;
        let time = frame_time(anim, frame);
        match clip_time(time, p.duration, settings.animation_end) {
            Some(t) => Ok(Some((p.clip, t))),
            None => crate::bail_input!(
                &anim.spec_path,
                "frame {frame} is at {time:.4} s, past the end of the animation ({:.4} s long; \
                 [scene] animation_end = stop, --animation-end stop): the last frame it covers is {}",
                p.duration,
                last_frame(anim, p.duration)
            ),
        }
    }

    /// The triangles the played animation may move (those of the primitives it poses), as
    /// ranges of the scene's: none when no animation plays or it moves no vertex. Between two
    /// frames, only these are compared ([`crate::moved::Moved`]).
    pub fn animated_triangles(&self) -> Vec<std::ops::Range<usize>> {
        let (Some(p), Some(rig)) = (self.playing, &self.scene.rig) else {
            return Vec::new();
        };
        if !p.deforms {
            return Vec::new();
        }
        let data = &rig.data;
        data.moved_primitives(p.clip)
            .iter()
            .zip(&data.primitives)
            .filter(|(m, _)| **m)
            .map(|(_, prim)| prim.triangles.clone())
            .collect()
    }

    /// The scene `frame` shows, when it is not the still scene: the played animation's pose
    /// at the frame's moment, then the spin `spin` (`[motion] kind = "spin"`).
    pub fn posed(
        &self,
        anim: &Animation,
        frame: usize,
        spin: Option<Mat4>,
    ) -> Result<Option<Scene>> {
        let clip = self.clip_at(anim, frame)?;
        let posed = match (clip, &self.scene.rig) {
            (Some((c, t)), Some(rig)) => Some(rig.posed(&self.scene, c, t)),
            _ => None,
        };
        Ok(match (posed, spin) {
            (None, None) => None,
            (Some(s), None) => Some(s),
            (Some(mut s), Some(m)) => {
                s.transform(m);
                Some(s)
            }
            (None, Some(m)) => Some(self.scene.transformed(m)),
        })
    }

    /// The BVH of `posed`, the scene a frame shows ([`posed`](Self::posed)), `spun` when a
    /// spin moved it. A pose of the played animation shares the hierarchy of the triangles the
    /// animation does not move with every other pose and rebuilds only the moving ones'
    /// (issue 41); a spin moves every triangle, so a spun frame's BVH is built whole.
    pub fn posed_accel(&self, posed: &Scene, spun: bool) -> Accel {
        let cut_out = posed.cut_out_triangles();
        if spun {
            return Accel::build_with_cutouts(&posed.positions, &posed.triangles, &cut_out);
        }
        let split = built(&self.split, || {
            let mut moving = vec![false; posed.triangle_count()];
            for r in self.animated_triangles() {
                moving[r].fill(true);
            }
            Split::new(&posed.positions, &posed.triangles, &cut_out, &moving)
        });
        split.accel(&posed.positions, &posed.triangles, &cut_out)
    }

    /// The environment prefiltered for glossy lobes, if any material may need it: one whose
    /// roughness factor (its texture can only lower it) is below what the map's lights
    /// resolve where they are sparsest.
    pub fn glossy(&self) -> Option<&Glossy> {
        built(&self.glossy, || {
            let bound = Glossy::roughness_bound(&self.lights);
            let needed = self
                .scene
                .materials
                .iter()
                .any(|m| m.model == Model::MetallicRoughness && m.roughness < bound);
            needed.then(|| Glossy::build(&self.env, &self.lights))
        })
        .as_ref()
    }

    /// These inputs with rays that leave the scene seeing `backdrop`.
    pub fn with_backdrop(self, backdrop: Backdrop) -> Inputs {
        Inputs { backdrop, ..self }
    }

    /// The lights of `frame`: the sampled set, turned by the environment's turn at that frame
    /// (`[motion] kind = "environment"`).
    pub fn lights_at(&self, anim: &Animation, frame: usize) -> Cow<'_, LightSet> {
        match anim.motion.environment_degrees(frame) {
            None => Cow::Borrowed(&self.lights),
            Some(degrees) => Cow::Owned(self.lights.turned(degrees)),
        }
    }

    /// The unposed scene's BVH, built once.
    pub fn still_accel(&self) -> &Accel {
        built(&self.still, || self.scene.accel())
    }

    /// Loads the scene and environment and samples the lights. Each file is counted against
    /// the render's memory budget from its headers before it is decoded; the map's header is
    /// read first, so the scene is checked with what will light it.
    pub fn load(anim: &Animation) -> Result<Inputs> {
        let mut budget = anim.budget();
        if let EnvSource::File(p) = &anim.env
            && let Some((texels, bytes)) = EnvMap::declared_size(p)
        {
            budget.expect_map(texels, bytes);
        }
        let scene = match &anim.scene {
            SceneSource::Shapes => Scene::shapes(),
            SceneSource::File(p) => {
                Scene::load_allowing(p, &mut budget, &anim.scene_settings.allow_folder)
                    .with_context(|| format!("while loading {}", anim.spec_path.display()))?
            }
        };
        let scene = anim.prepare_model(scene)?;
        let playing = playing(anim, &scene)?;
        let mut scene = match playing {
            Some(p) => with_framing(anim, scene, p),
            None => scene,
        };
        // After the framing: a ground lies under every pose, not the rest pose only.
        anim.add_ground(&mut scene);
        // A spin poses the scene every frame: refused here if that could overflow (found by
        // fuzzing the posed scene: tests/data/fuzz/posed_scene/huge-pivot).
        for s in anim.motion.segments() {
            if s.kind != MotionKind::Spin {
                continue;
            }
            let pivot = match s.pivot {
                Some(p) => scene.to_local(p),
                None => anim.camera(&scene, 0)?.target,
            };
            if let Some(why) = scene.turn_problem(pivot) {
                crate::bail_input!(&anim.spec_path, "[motion] kind = \"spin\": {why}");
            }
        }
        let env = match &anim.env {
            EnvSource::Sky => EnvMap::builtin_sky(),
            EnvSource::File(p) => EnvMap::load_within(p, &mut budget)
                .with_context(|| format!("while loading {}", anim.spec_path.display()))?,
        };
        let env = env
            .with_rotation(anim.env_rotation_deg)
            .with_intensity(anim.env_intensity)?;
        let mut lights = LightSet::build(&env, anim.lights.count, anim.lights.sampler)?;
        if anim.lights.scene_lights {
            lights = lights.with_scene_lights(&scene.lights, Path::new(&scene.source))?;
        }
        let r = &anim.render;
        let backdrop = Backdrop::new(r.background, r.background_color, r.background_blur, &env)?;
        let mut inputs = Inputs::new(scene, env, lights).with_backdrop(backdrop);
        inputs.playing = playing;
        // Refused before any frame renders: a frame past the end under `stop`.
        for frame in anim.frames.iter() {
            inputs.clip_at(anim, frame)?;
        }
        Ok(inputs)
    }
}

/// Most frames whose poses the framing samples: a longer animation is sampled at this many
/// frames spread evenly over it (the same ones in every process, whatever it renders).
const FRAMING_SAMPLES: usize = 240;

/// `scene` with the points the model reaches over the animation's frames (all of them, not
/// only those this run renders: every process frames alike), so that the camera frames the
/// union of the poses ([`Scene::framing`]).
fn with_framing(anim: &Animation, mut scene: Scene, playing: Playing) -> Scene {
    let Some(rig) = scene.rig.clone() else {
        return scene;
    };
    let n = anim.frame_count.max(1);
    let frames: Vec<usize> = if n <= FRAMING_SAMPLES {
        (0..n).collect()
    } else {
        (0..FRAMING_SAMPLES)
            .map(|k| k * (n - 1) / (FRAMING_SAMPLES - 1))
            .collect()
    };
    let settings = &anim.scene_settings;
    let times: Vec<f64> = frames
        .into_iter()
        .filter_map(|f| {
            clip_time(
                frame_time(anim, f),
                playing.duration,
                settings.animation_end,
            )
        })
        .collect();
    let reach = rig.reach(&scene, playing.clip, &times);
    scene.framing = Some(reach.into());
    scene
}

/// The seconds frame `frame` shows: `frame ÷ fps + [scene] animation_start`.
pub fn frame_time(anim: &Animation, frame: usize) -> f64 {
    let fps = anim.output.fps;
    frame as f64 * f64::from(fps.den) / f64::from(fps.num)
        + f64::from(anim.scene_settings.animation_start)
}

/// The last frame whose moment lies within an animation `duration` seconds long.
fn last_frame(anim: &Animation, duration: f64) -> String {
    let fps = anim.output.fps;
    let span = duration - f64::from(anim.scene_settings.animation_start);
    if span < 0.0 {
        return "none".to_string();
    }
    // The largest frame with frame·den/num ≤ span, by exact steps from the estimate.
    let mut f = (span * f64::from(fps.num) / f64::from(fps.den)).floor() as usize;
    while f > 0 && frame_time(anim, f) > duration {
        f -= 1;
    }
    while frame_time(anim, f + 1) <= duration {
        f += 1;
    }
    f.to_string()
}

/// The animation `[scene] animation` picks in `scene`'s file, checked.
fn playing(anim: &Animation, scene: &Scene) -> Result<Option<Playing>> {
    let choice = &anim.scene_settings.animation;
    let clips = scene.rig.as_ref().map_or(&[][..], |r| r.clips());
    let picked = choice.pick(clips).map_err(|why| {
        crate::error::input_error(
            &anim.spec_path,
            format!(
                "[scene] animation = {choice} (--animation): {} has {why}",
                scene.source
            ),
        )
    })?;
    Ok(picked.map(|clip| Playing {
        clip,
        duration: clips[clip].duration,
        deforms: scene
            .rig
            .as_ref()
            .is_some_and(|r| r.data.moved_primitives(clip).contains(&true)),
    }))
}

/// What became of the scene file's lights, for the user: lit by them, or ignored.
pub fn scene_lights_note(anim: &Animation, scene: &Scene) -> Option<String> {
    if scene.lights.is_empty() {
        return None;
    }
    let names: Vec<String> = scene
        .lights
        .iter()
        .map(|l| format!("{} '{}'", l.kind.name(), l.name))
        .collect();
    let n = scene.lights.len();
    let (lights, join) = if n == 1 {
        ("light", "joins")
    } else {
        ("lights", "join")
    };
    Some(if anim.lights.scene_lights {
        format!(
            "the scene file's {n} {lights} {join} the map's: {}",
            names.join(", ")
        )
    } else {
        format!(
            "the scene file's {n} {lights} ignored ([lights] scene_lights = false): {}",
            names.join(", ")
        )
    })
}

/// The value of `cell`, built by `build` if no frame has yet. Not `OnceLock::get_or_init`: the
/// builds run on the render pool (a BVH, the glossy prefilter), and a worker waiting inside
/// them for its parallel parts steals another frame's job, which then asks for the same cell
/// and waits on the very initialisation it sits on — a deadlock (two frames in flight on the
/// animated fox, `animation_farm::a_farm_run_of_an_animated_model_equals_one_process`). So the
/// build runs outside the cell: two frames that ask at once may both build (the same value
/// from the same inputs, bit for bit), and the first to finish is kept.
fn built<T>(cell: &OnceLock<T>, build: impl FnOnce() -> T) -> &T {
    if let Some(v) = cell.get() {
        return v;
    }
    let _ = cell.set(build());
    cell.get().expect("set just above")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A build that, waiting on the pool, runs another frame's job asking for the same cell
    /// (as a BVH or prefilter build does when it steals work): with `OnceLock::get_or_init`
    /// the inner request waits forever on the outer build; `built` finishes, and both
    /// requests see one value.
    #[test]
    fn a_build_that_runs_another_frames_request_for_the_same_value_does_not_deadlock() {
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .unwrap();
            let cell: OnceLock<u32> = OnceLock::new();
            let (outer, inner) = pool.install(|| {
                rayon::join(
                    || {
                        *built(&cell, || {
                            // The other half of the join, queued on this worker, runs here.
                            let _ = rayon::yield_now();
                            7
                        })
                    },
                    || *built(&cell, || 7),
                )
            });
            let _ = tx.send((outer, inner, cell.get().copied()));
        });
        let got = rx
            .recv_timeout(std::time::Duration::from_secs(60))
            .expect("the two requests deadlocked");
        assert_eq!(got, (7, 7, Some(7)));
    }
}
