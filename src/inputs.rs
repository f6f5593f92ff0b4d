//! An animation's inputs, loaded once per run: the scene as the spec asks for it, the map, its
//! lights and the backdrop; the still scene's BVH and the glossy prefilter, each made once by
//! the first frame that needs it.

use std::borrow::Cow;
use std::path::Path;
use std::sync::OnceLock;

use anyhow::Context;

use crate::accel::Accel;
use crate::anim::{Animation, EnvSource, MotionKind, SceneSource};
use crate::background::Backdrop;
use crate::envmap::EnvMap;
use crate::error::Result;
use crate::glossy::Glossy;
use crate::lights::LightSet;
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
    /// The prefiltered environment, made by the first frame that needs it: only when some
    /// material is glossier than the lights resolve (see [`Glossy`]).
    glossy: OnceLock<Option<Glossy>>,
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
            glossy: OnceLock::new(),
        }
    }

    /// The environment prefiltered for glossy lobes, if any material may need it: one whose
    /// roughness factor (its texture can only lower it) is below what the map's lights
    /// resolve where they are sparsest.
    pub fn glossy(&self) -> Option<&Glossy> {
        self.glossy
            .get_or_init(|| {
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
        self.still.get_or_init(|| self.scene.accel())
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
        let scene = anim.prepare_scene(scene)?;
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
        Ok(Inputs::new(scene, env, lights).with_backdrop(backdrop))
    }
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
