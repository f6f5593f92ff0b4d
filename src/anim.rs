//! Animation specs: a TOML file in `anims/` says what to render; flags may override it.
//!
//! ```toml
//! [scene]
//! builtin = "shapes"            # or: file = "../assets/bunny_on_plane.glb"
//! up = "y"                      # the file's up axis: "y" (glTF's) or "z" (turned upright)
//! ground = "auto"               # a ground below the model: "auto" (when the scene has
//!                               # none), "none" or "always"
//! shadow_catcher = false        # the added ground shows only its shadows (it always does
//!                               # over a transparent background)
//! # catchers = ["Floor"]        # glTF nodes (or meshes) that are shadow catchers
//! animation = "first"           # the file's animation: a name, an index, "first" (the
//!                               # file's first, if any) or "none" (its rest pose)
//! animation_start = 0.0         # seconds into it at frame 0 (frame N: N ÷ fps + this)
//! animation_end = "loop"        # frames past its end: "loop", "hold" or "stop" (refused)
//! [environment]
//! builtin = "sky"               # or: file = "../assets/grace.hdr"
//! rotation = 0.0                # degrees about +Y
//! intensity = 1.0
//! [lights]
//! count = 100
//! sampler = "sis"               # or "median-cut"
//! scene_lights = true           # also the glTF file's own lights (KHR_lights_punctual)
//! [camera]
//! target = [0.0, 0.5, 0.0]      # default: the scene's bounding-box centre
//! distance = 7.0                # 0 or absent: auto-framed (the model fills at most 9/10)
//! elevation = 25.0              # degrees above the horizon
//! azimuth = 20.0                # degrees from +Z towards +X
//! vfov = 40.0                   # vertical field of view, degrees
//! # position = [x, y, z]        # instead of distance/elevation/azimuth
//! # from_file = true            # use the glTF file's first camera
//! # Each of rotation, intensity, distance, elevation, azimuth, vfov and from_file has its flag
//! # (--env-rotation, --env-intensity, --distance, …, --gltf-camera), and [motion]'s frames and
//! # degrees_per_frame theirs (--frame-count, --degrees-per-frame); `render --write-spec FILE`
//! # writes a render's resolved settings as a spec like this one.
//! [motion]
//! kind = "orbit"                # camera orbits the target; "spin": the scene turns;
//!                               # "environment": the lights and background turn; "none"
//! frames = 24
//! turn_degrees = 360.0          # the whole animation's turn; or degrees_per_frame = 3.0
//! # A sequence instead: [[motion]] tables, one per motion in order (src/motion.rs)
//! [render]
//! width = 320
//! height = 240
//! method = "grid-nowarp-uncertainty"   # `envshadow methods` lists them all
//! validate = false              # also trace every query; record mistakes in stats.csv
//! # Settings only some methods read (a setting the method does not read is refused):
//! h0 = 16                       # grid methods: coarse grid spacing (power of two)
//! min_voters = 3                # uncertainty methods: fewer voters with the light above
//!                               # their horizon → trace it
//! flood_to = "contrary-finest"  # uncertainty methods: or "all", or "contrary": flood only to
//!                               # lights predicted opposite (contrary-finest: so at the
//!                               # finest grid level only)
//! # scan_block = 64             # scanline methods: the scan restarts every scan_block pixels
//! temporal = false              # uncertainty methods: the previous frame votes too
//! # keyframe = 16               # with temporal: frames 0, 16, 32, … restart the chain
//!                               # (0, the default: 16 for orbit, 4 for spin, 8 for
//!                               # environment; docs/temporal.md)
//! background = "environment"   # or "transparent", "color", "blurred"
//! # background_color = [0.18, 0.18, 0.18]   # with "color": linear RGB
//! # background_blur = 10.0      # with "blurred": degrees
//! exposure = 1.0                # PNG preview exposure, before the view transform
//! view = "agx"                  # PNG view transform: "agx", "hable" or "standard"
//! tile = 64
//! threads = 0                   # 0: all cores
//! [output]
//! dir = "out/shapes"
//! half = false                  # half-float EXR channels (counts and depth stay float)
//! fps = 24.0                    # frame rate: the EXR's framesPerSecond, the video's
//!                               # (29.97 or "30000/1001": stored as 30000/1001)
//! # output_pattern = "turntable_####"   # frame names, Blender's #: turntable_0001.exr
//! # frame_start = 1             # the first frame's number (1: Blender's numbering)
//! video = false                 # encode DIR/video.mp4 with ffmpeg at the end
//! # [material]                  # overrides every material (docs/materials.md)
//! # base_color = [0.5, 0.5, 0.5]   # linear; replaces factor, texture colour, vertex colours
//! # roughness = 0.5 ; metallic = 0.0 ; emissive = [0, 0, 0]
//! # lambert = false             # true: diffuse only (no specular)
//! # textures = true             # false: no textures but normal maps (and base colour alpha)
//! # normal_maps = true          # false: no normal maps
//! # [material.named."Floor"]    # the same keys, for the materials of one name
//! # roughness = 0.9
//! ```
//! Input paths are relative to the spec file's folder; the output folder is relative to the
//! working directory. Unknown keys are errors.

use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};
use serde::Deserialize;

use crate::bail_input;
use crate::camera::Camera;
use crate::error::{Result, input_error};
use crate::frames::FrameSet;
use crate::key::Key;
use crate::motion::{Motion, MotionSpecs};
use crate::output::record::{SettingsRecord, file_sha256};
use crate::scene::{MaterialOverride, Scene};
use crate::settings::{
    CameraLayer, EnvLayer, Lights, LightsLayer, Output, OutputLayer, Render, RenderLayer,
    SceneLayer, SceneSettings, Source, check_applies,
};

/// Limits checked before any work starts (see [`crate::limits`]).
pub use crate::limits;

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct Spec {
    #[serde(default)]
    name: Option<String>,
    scene: SceneSpec,
    #[serde(default)]
    environment: EnvSpec,
    #[serde(default)]
    lights: LightsLayer,
    #[serde(default)]
    camera: CameraSpec,
    #[serde(default)]
    motion: MotionSpecs,
    #[serde(default)]
    render: RenderLayer,
    #[serde(default)]
    output: OutputLayer,
    #[serde(default)]
    material: MaterialOverride,
}

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneSpec {
    builtin: Option<String>,
    file: Option<PathBuf>,
    #[serde(default)]
    catchers: Vec<String>,
    // The settings of `SceneLayer` (`crate::settings`: their flags, defaults and checks), by
    // name; serde cannot flatten a layer into a table that refuses unknown keys.
    up: Option<crate::scene::Up>,
    ground: Option<crate::scene::ground::Ground>,
    shadow_catcher: Option<bool>,
    allow_folder: Option<crate::scene::AllowedFolder>,
    animation: Option<crate::scene::playback::Choice>,
    animation_start: Option<f32>,
    animation_end: Option<crate::scene::playback::AfterEnd>,
}

impl SceneSpec {
    /// The settings given in the spec's `[scene]`.
    fn layer(&self) -> SceneLayer {
        SceneLayer {
            up: self.up,
            ground: self.ground,
            shadow_catcher: self.shadow_catcher,
            allow_folder: self.allow_folder.clone(),
            animation: self.animation.clone(),
            animation_start: self.animation_start,
            animation_end: self.animation_end,
        }
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct EnvSpec {
    builtin: Option<String>,
    file: Option<PathBuf>,
    // The settings of `EnvLayer` (`crate::settings`), by name, as `SceneSpec`'s.
    rotation: Option<f32>,
    intensity: Option<f32>,
}

impl Default for EnvSpec {
    fn default() -> Self {
        EnvSpec {
            builtin: Some("sky".into()),
            file: None,
            rotation: None,
            intensity: None,
        }
    }
}

impl EnvSpec {
    /// The settings given in the spec's `[environment]`.
    fn layer(&self) -> EnvLayer {
        EnvLayer {
            rotation: self.rotation,
            intensity: self.intensity,
        }
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraSpec {
    target: Option<[f32; 3]>,
    #[serde(default = "default_up")]
    up: [f32; 3],
    position: Option<[f32; 3]>,
    // The settings of `CameraLayer` (`crate::settings`), by name, as `SceneSpec`'s.
    distance: Option<f32>,
    elevation: Option<f32>,
    azimuth: Option<f32>,
    vfov: Option<f32>,
    from_file: Option<bool>,
}

impl Default for CameraSpec {
    fn default() -> Self {
        CameraSpec {
            target: None,
            up: default_up(),
            position: None,
            distance: None,
            elevation: None,
            azimuth: None,
            vfov: None,
            from_file: None,
        }
    }
}

impl CameraSpec {
    /// The settings given in the spec's `[camera]`.
    fn layer(&self) -> CameraLayer {
        CameraLayer {
            distance: self.distance,
            elevation: self.elevation,
            azimuth: self.azimuth,
            vfov: self.vfov,
            from_file: self.from_file,
        }
    }
}

fn default_up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}
/// Where the scene comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneSource {
    Shapes,
    File(PathBuf),
}

/// Where the environment comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum EnvSource {
    Sky,
    File(PathBuf),
}

pub use crate::motion::MotionKind;

/// The share of the frame's half-width and half-height an auto-framed model fills at most
/// [ours]: a margin of a twentieth on each side, as a product turntable leaves.
const FRAME_FILL: f32 = 0.9;

/// Rim points sampled on each of the swept cylinder's two circles when framing it.
const FRAME_RIM: usize = 64;

/// The volume a model sweeps as it turns about a vertical line (a turntable's orbit or spin,
/// both about the vertical through the camera target): a cylinder about `axis` of `radius`,
/// from height `y.0` to `y.1`.
struct Swept {
    axis: Vec3,
    radius: f32,
    y: (f32, f32),
}

impl Swept {
    /// How far from `axis` (its point) a camera looking back along `back` (unit, from the
    /// target towards the camera) must stand for the whole cylinder to fill at most
    /// [`FRAME_FILL`] of its frame, whatever the turn — so the model stays in frame at every
    /// angle without the slack a bounding sphere leaves around flat or long models. A point at
    /// `o` from the target, seen from `d · back`, lies at depth `d − o·back` and must have
    /// `|o·right| ≤ depth · tan(hfov/2) · fill` (likewise up): the least `d` is the largest of
    /// `o·back + |o·right| / (tan · fill)` over the rims ([`FRAME_RIM`] points each, the
    /// circles' extremes within cos(π/64) of it, inside the margin). Scale-free, and never
    /// inside the cylinder's bounding sphere.
    fn framing_distance(&self, back: Vec3, up: Vec3, vfov_deg: f32, aspect: f32) -> f32 {
        let forward = -back;
        let right = forward.cross(up.normalize()).normalize_or_zero();
        let cam_up = right.cross(forward);
        let tan_v = libm::tanf(vfov_deg.to_radians() * 0.5) * FRAME_FILL;
        let tan_h = tan_v * aspect;
        let mut dist = 0.0f32;
        let mut reach = 0.0f32;
        for k in 0..FRAME_RIM {
            let a = std::f32::consts::TAU * k as f32 / FRAME_RIM as f32;
            let (sa, ca) = (libm::sinf(a), libm::cosf(a));
            for y in [self.y.0, self.y.1] {
                let o = Vec3::new(self.radius * ca, y - self.axis.y, self.radius * sa);
                let need = (o.dot(right).abs() / tan_h).max(o.dot(cam_up).abs() / tan_v);
                dist = dist.max(o.dot(back) + need);
                reach = reach.max(o.length());
            }
        }
        // A model with no extent still gets a camera some way off (any positive distance
        // frames a point).
        dist.max(reach * 1.05).max(f32::MIN_POSITIVE)
    }
}

/// How the camera is placed.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraRig {
    pub target: Option<Vec3>,
    pub distance: Option<f32>,
    pub elevation_deg: f32,
    pub azimuth_deg: f32,
    pub vfov_deg: f32,
    pub up: Vec3,
    pub position: Option<Vec3>,
    pub from_file: bool,
}

/// The settings of a command line that renders an animation: each given one overrides the
/// spec's (the binary flattens it into `render`, `plan`, `export`).
#[derive(Clone, Debug, Default, clap::Args)]
pub struct AnimFlags {
    /// Frames to render, from 0: a list of pieces joined by commas, each N, A-B (B included,
    /// as Blender's), A..B (B excluded), or A..=B, a range optionally with :STEP, e.g.
    /// `1-10`, `1,5,9`, `1-10:2`, `0..24`, `1-3,7,10-20:5`. Default: all of the animation.
    /// A model's turntable (no spec) grows to the last frame asked for at its 5° a frame
    /// (frame N is N×5° round, whatever the selection); --frame-count N instead spreads one
    /// turn over N frames. A spec's frames past its last are refused.
    #[arg(long, value_name = "LIST")]
    pub frames: Option<FrameSet>,
    /// Frames in the animation, over a single motion's `[motion] frames` (72 for a model's
    /// turntable): its turn (`turn_degrees`, default 360°) spreads over them unless
    /// --degrees-per-frame (or the spec's `degrees_per_frame`) says otherwise.
    #[arg(long, value_name = "N")]
    pub frame_count: Option<usize>,
    /// Degrees the motion turns from one frame to the next, over a single motion's
    /// `[motion] degrees_per_frame` or `turn_degrees` (a model's turntable: 5).
    #[arg(long, value_name = "DEGREES", allow_negative_numbers = true)]
    pub degrees_per_frame: Option<f32>,
    /// Light the scene with this lat-long map (.exr, .hdr; `builtin:sky` for the built-in
    /// sky) instead of the spec's `[environment]` map (a model's default: the built-in sky at
    /// intensity 0.25). Relative to the working directory.
    #[arg(long, value_name = "MAP")]
    pub env: Option<PathBuf>,
    #[command(flatten)]
    pub environment: EnvLayer,
    #[command(flatten)]
    pub camera: CameraLayer,
    #[command(flatten)]
    pub scene: SceneLayer,
    #[command(flatten)]
    pub lights: LightsLayer,
    #[command(flatten)]
    pub render: RenderLayer,
    #[command(flatten)]
    pub output: OutputLayer,
    #[command(flatten)]
    pub material: MaterialFlags,
}

/// Material overrides from the command line, over the spec's `[material]` table.
#[derive(Clone, Debug, Default, clap::Args)]
pub struct MaterialFlags {
    /// Lookdev: every material a grey clay — base colour 0.5, roughness 0.5, metallic 0, no
    /// emission, no textures but normal maps (docs/materials.md).
    #[arg(long)]
    pub clay: bool,
    /// Every material Lambertian (diffuse only, no specular), as envshadow shaded before glTF
    /// materials.
    #[arg(long)]
    pub lambert: bool,
}

impl MaterialFlags {
    /// The overrides these flags stand for.
    pub fn overrides(&self) -> MaterialOverride {
        let mut o = if self.clay {
            MaterialOverride::clay()
        } else {
            MaterialOverride::default()
        };
        if self.lambert {
            o.lambert = Some(true);
        }
        o
    }
}

impl AnimFlags {
    /// Refuses the settings given here that `command` does not read: they would change nothing
    /// it writes. The material flags, `--env`, `--frame-count`, `--degrees-per-frame` and the
    /// environment's and camera's settings are not refused: every command that takes them
    /// (render, plan, export) reads them.
    pub fn refuse_unread(&self, reads: &[Key], command: &str) -> Result<()> {
        if self.frames.is_some() {
            bail_input!("--frames", "does not apply to {command}");
        }
        let given = self
            .scene
            .given_keys()
            .into_iter()
            .chain(self.lights.given_keys())
            .chain(self.render.given_keys())
            .chain(self.output.given_keys());
        for (key, _) in given {
            if !reads.contains(&key) {
                bail_input!(format!("--{}", key.flag()), "does not apply to {command}");
            }
        }
        Ok(())
    }
}

/// A resolved animation: the spec with defaults filled in and flags applied.
#[derive(Clone, Debug)]
pub struct Animation {
    /// The spec file (or `builtin` for programmatic animations).
    pub spec_path: PathBuf,
    pub name: String,
    pub scene: SceneSource,
    /// `[scene]`: the up axis, the ground, whether the ground catches shadows.
    pub scene_settings: SceneSettings,
    /// `[scene] catchers`: the glTF nodes (or meshes) that are shadow catchers.
    pub catchers: Vec<String>,
    pub env: EnvSource,
    pub env_rotation_deg: f32,
    pub env_intensity: f32,
    pub camera: CameraRig,
    /// What moves, frame by frame: one motion or a sequence ([`Motion`]).
    pub motion: Motion,
    /// Frames in the whole animation.
    pub frame_count: usize,
    /// Frames this run renders (`--frames`).
    pub frames: FrameSet,
    /// `[lights]`: how many lights, by which sampler.
    pub lights: Lights,
    /// `[render]`: size, method and its parameters, validation, temporal prediction (its
    /// `keyframe` resolved for the motion), tiles, threads.
    pub render: Render,
    /// `[output]`: the output folder, the EXR's precision, the frame rate, the video.
    pub output: Output,
    /// `[material]`: the spec's material overrides …
    pub materials: MaterialOverride,
    /// … and the command line's (`--clay`, `--lambert`), applied over them.
    pub material_flags: MaterialOverride,
}

impl Animation {
    /// Reads and resolves a spec file with the command line's `flags` over it.
    pub fn load(path: &Path, flags: &AnimFlags) -> Result<Animation> {
        if is_model(path) {
            bail_input!(
                path,
                "is a glTF model, not an animation spec: `envshadow render {}` renders a default turntable of it, or name it in a spec's [scene] file",
                path.display()
            );
        }
        limits::check_file_size(path, "animation spec")?;
        let bytes = std::fs::read(path)
            .map_err(|e| input_error(path, format!("cannot read animation spec: {e}")))?;
        not_a_spec(path, &bytes)?;
        let text = String::from_utf8(bytes).map_err(|_| {
            input_error(path, "is not UTF-8 text: an animation spec is a TOML file")
        })?;
        Animation::parse(&text, path, flags)
    }

    /// Parses spec text; `path` names it in errors and anchors relative input paths. The
    /// settings given in `flags` win over the spec's, defaults fill the rest; every given
    /// value is checked where it came from, and a setting the chosen method does not read is
    /// refused.
    pub fn parse(text: &str, path: &Path, flags: &AnimFlags) -> Result<Animation> {
        Animation::parse_as(text, path, flags, false)
    }

    /// [`parse`](Self::parse); `grows`: frames asked for past the last lengthen a single
    /// motion at its degrees per frame (a model's turntable, whose frame count is ours).
    fn parse_as(text: &str, path: &Path, flags: &AnimFlags, grows: bool) -> Result<Animation> {
        let mut spec: Spec =
            toml::from_str(text).map_err(|e| input_error(path, toml_message(text, &e)))?;
        let base = path.parent().unwrap_or(Path::new("")).to_path_buf();
        let rel = |p: &Path| {
            if p.is_absolute() {
                p.to_path_buf()
            } else {
                base.join(p)
            }
        };

        let scene = match (&spec.scene.builtin, &spec.scene.file) {
            (Some(b), None) if b == "shapes" => SceneSource::Shapes,
            (Some(b), None) => bail_input!(
                path,
                "[scene] builtin = {b:?}: the only built-in scene is \"shapes\""
            ),
            (None, Some(f)) => SceneSource::File(rel(f)),
            _ => bail_input!(path, "[scene] needs exactly one of `builtin` or `file`"),
        };
        // `--env` replaces the spec's map (relative to the working directory, as flags are).
        let env = match (&spec.environment.builtin, &spec.environment.file) {
            _ if flags.env.as_deref() == Some(Path::new("builtin:sky")) => EnvSource::Sky,
            _ if flags.env.is_some() => EnvSource::File(flags.env.clone().unwrap_or_default()),
            (Some(b), None) if b == "sky" => EnvSource::Sky,
            (Some(b), None) => bail_input!(
                path,
                "[environment] builtin = {b:?}: the only built-in environment is \"sky\""
            ),
            (None, Some(f)) => EnvSource::File(rel(f)),
            (Some(_), Some(_)) => {
                bail_input!(path, "[environment] takes `builtin` or `file`, not both")
            }
            (None, None) => EnvSource::Sky,
        };
        let motion = motion_of(&mut spec.motion, path, flags, grows)?;
        let frame_count = motion.frame_count();
        let (spec_source, flags_source) = (Source::Spec(path), Source::Flags);
        let spec_scene = spec.scene.layer();
        spec_scene.check(spec_source)?;
        spec.lights.check(spec_source)?;
        spec.render.check(spec_source)?;
        spec.output.check(spec_source)?;
        let (spec_env, spec_camera) = (spec.environment.layer(), spec.camera.layer());
        spec_env.check(spec_source)?;
        spec_camera.check(spec_source)?;
        flags.environment.check(flags_source)?;
        flags.camera.check(flags_source)?;
        flags.scene.check(flags_source)?;
        flags.lights.check(flags_source)?;
        flags.render.check(flags_source)?;
        flags.output.check(flags_source)?;
        let given = flags.render.clone().over(spec.render.clone());
        let mut render = given.resolve();
        check_applies(&flags.render, flags_source, &[render.method])?;
        check_applies(&spec.render, spec_source, &[render.method])?;
        if given.keyframe.is_some() && !render.temporal {
            let message = "applies only with temporal prediction (--temporal)".to_string();
            let source = if flags.render.keyframe.is_some() {
                flags_source
            } else {
                spec_source
            };
            return Err(source.error(Render::TABLE, "keyframe", "keyframe", message));
        }
        if render.keyframe == 0 {
            render.keyframe = default_keyframe(&motion);
        }
        check_background(&given, &flags.render, path)?;
        if !spec.scene.catchers.is_empty() && scene == SceneSource::Shapes {
            bail_input!(
                path,
                "[scene] catchers names glTF nodes; the built-in shapes scene has none"
            );
        }
        let camera = camera_rig(&spec.camera, &flags.camera)?;
        let environment = flags.environment.clone().over(spec_env).resolve();
        let mut anim = Animation {
            spec_path: path.to_path_buf(),
            name: spec.name.clone().unwrap_or_else(|| {
                path.file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_else(|| "animation".into())
            }),
            scene,
            scene_settings: flags.scene.clone().over(spec_scene).resolve(),
            catchers: spec.scene.catchers.clone(),
            env,
            env_rotation_deg: environment.rotation,
            env_intensity: environment.intensity,
            camera,
            motion,
            frame_count,
            frames: FrameSet::range(0..frame_count),
            lights: flags.lights.clone().over(spec.lights).resolve(),
            render,
            output: flags.output.clone().over(spec.output).resolve(),
            materials: spec.material.clone(),
            material_flags: flags.material.overrides(),
        };
        if let Some(why) = anim.materials.problem() {
            bail_input!(path, "[material] {why}");
        }
        if let Some(r) = &flags.frames {
            let outside = r.at_or_after(anim.frame_count);
            if !outside.is_empty() {
                bail_input!(
                    "--frames",
                    "{r}: frame(s) {outside} are past the animation's last frame, {} (its {} \
                     frames are numbered from 0; --frame-count N makes it N frames long)",
                    anim.frame_count.saturating_sub(1),
                    anim.frame_count
                );
            }
            anim.frames = r.clone();
        }
        anim.validate(path)?;
        Ok(anim)
    }

    /// The default turntable of a model (`envshadow render model.glb`), `flags` over it: the
    /// camera orbits the model in [`MODEL_FRAMES`] frames, framed as a spec without `[camera]`
    /// target or distance frames it (the cylinder the model sweeps as it turns, 25° above the
    /// horizon, filling nine tenths of the frame); the
    /// built-in sky at a quarter of its intensity (as the default animation has it) or the
    /// map `env`; 200 lights; 640×480 at 4 samples per pixel; a ground if
    /// the model has none (`[scene] ground = "auto"`); frames in `out/<model's name>/`.
    pub fn of_model(model: &Path, env: Option<&Path>, flags: &AnimFlags) -> Result<Animation> {
        let env = env.or(flags.env.as_deref());
        let stem = model
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "model".into());
        let quote = |s: &str| toml::Value::String(s.to_string()).to_string();
        let absolute = |p: &Path| {
            std::path::absolute(p)
                .map_err(|e| input_error(p, format!("cannot resolve the path: {e}")))
        };
        let environment = match env {
            Some(map) if map != Path::new("builtin:sky") => {
                format!("file = {}", quote(&absolute(map)?.to_string_lossy()))
            }
            // The built-in sun is bright: at a quarter (as the default animation has it) a
            // white model does not clip at exposure 1.
            _ => "builtin = \"sky\"\nintensity = 0.25".to_string(),
        };
        let text = format!(
            "name = {name}\n[scene]\nfile = {file}\n[environment]\n{environment}\n\
             [lights]\ncount = 200\n[motion]\nkind = \"orbit\"\nframes = {MODEL_FRAMES}\n\
             [render]\nwidth = 640\nheight = 480\nspp = 4\n[output]\ndir = {dir}\n",
            name = quote(&stem),
            file = quote(&absolute(model)?.to_string_lossy()),
            dir = quote(&Path::new("out").join(&stem).to_string_lossy()),
        );
        Animation::parse_as(&text, model, flags, true)
    }

    /// The loaded `scene` as the spec asks for it: turned upright (`[scene] up`), its materials
    /// overridden (`[material]`, `--clay`, `--lambert`), its named
    /// catchers marked (`[scene] catchers`), and a ground added below the model where
    /// `[scene] ground` asks for one ([`Animation::add_ground`]).
    pub fn prepare_scene(&self, scene: Scene) -> Result<Scene> {
        let mut scene = self.prepare_model(scene)?;
        self.add_ground(&mut scene);
        Ok(scene)
    }

    /// [`Animation::prepare_scene`] short of the ground: what the model's poses (and so the
    /// ground under them) are found from.
    pub fn prepare_model(&self, scene: Scene) -> Result<Scene> {
        let settings = &self.scene_settings;
        let mut scene = scene.stood_up(settings.up);
        // The file's materials as `[material]` and --clay / --lambert say (before a ground of
        // ours joins them: it keeps its own look).
        self.materials
            .apply(&self.material_flags, &mut scene.materials)
            .map_err(|why| {
                input_error(
                    &self.spec_path,
                    format!("[material] {why} (in {})", scene.source),
                )
            })?;
        if let Err(name) = scene.mark_catchers(&self.catchers) {
            let names: Vec<String> = scene
                .parts
                .iter()
                .flat_map(|p| [p.node.clone(), p.mesh.clone()])
                .flatten()
                .collect();
            bail_input!(
                &self.spec_path,
                "[scene] catchers: {} has no node or mesh named {name:?} (its names: {})",
                scene.source,
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                }
            );
        }
        Ok(scene)
    }

    /// Adds a ground below the model where `[scene] ground` asks for one — a shadow catcher
    /// over a transparent background or with `shadow_catcher = true`, else diffuse grey. It
    /// lies under [`Scene::model_bounds`]: the union of the poses once the framing holds them.
    pub fn add_ground(&self, scene: &mut Scene) {
        use crate::scene::ground::{Ground, add_ground, has_ground};
        let settings = &self.scene_settings;
        let add = match settings.ground {
            Ground::None => false,
            Ground::Always => true,
            Ground::Auto => !has_ground(scene),
        };
        if add {
            let catcher = settings.shadow_catcher
                || self.render.background == crate::background::Background::Transparent;
            add_ground(scene, catcher);
        }
    }

    /// This animation with the render settings of `layer` (one combination of a measuring
    /// command's sweep) over its own: checked as flags, refused where the method does not read
    /// them, the limits checked again.
    pub fn with_render(&self, layer: &RenderLayer) -> Result<Animation> {
        layer.check(Source::Flags)?;
        let mut a = self.clone();
        a.render = layer.clone().over(self.render.layer()).resolve();
        check_applies(layer, Source::Flags, &[a.render.method])?;
        if a.render.keyframe == 0 {
            a.render.keyframe = default_keyframe(&a.motion);
        }
        a.validate(&self.spec_path)?;
        Ok(a)
    }

    /// What rendering this animation holds in memory, as far as its settings say.
    pub fn request(&self) -> limits::Request {
        let r = &self.render;
        limits::Request {
            width: r.width,
            height: r.height,
            lights: self.lights.count,
            tile: r.tile,
            threads: r.threads,
            validate: r.validate,
            spp: r.spp,
        }
    }

    /// The memory budget its inputs are loaded against: the request, and with a spin a posed
    /// copy of the scene (and its BVH) for each frame in flight.
    pub fn budget(&self) -> limits::Budget {
        let posed = if self.motion.has(MotionKind::Spin) {
            self.frames.len().min(limits::FRAMES_IN_FLIGHT)
        } else {
            0
        };
        limits::Budget::new(&self.request(), posed)
    }

    fn validate(&self, path: &Path) -> Result<()> {
        use limits::*;
        let (r, lights) = (&self.render, self.lights.count);
        let request = self.request();
        let need = human_bytes_u128(estimate_bytes(&request));
        if r.width == 0 || r.height == 0 || r.width > MAX_DIM || r.height > MAX_DIM {
            bail_input!(
                path,
                "resolution {}x{} is out of range: each side must be 1..={MAX_DIM} (it would need about {need} of memory)",
                r.width,
                r.height
            );
        }
        let px = r.width as u64 * r.height as u64;
        if px > MAX_PIXELS {
            bail_input!(
                path,
                "resolution {}x{} is {px} pixels; at most {MAX_PIXELS} are allowed (it would need about {need} of memory)",
                r.width,
                r.height
            );
        }
        if let Some(why) = lights_problem(lights) {
            if lights == 0 {
                bail_input!(path, "{why}");
            }
            bail_input!(
                path,
                "{why} (each pixel keeps a bit per light and traces up to one ray per light; it would need about {need} of memory)"
            );
        }
        check_memory(path, &request)?;
        if self.frame_count == 0 || self.frame_count > MAX_FRAMES {
            bail_input!(
                path,
                "[motion] frames = {}: must be 1..={MAX_FRAMES}",
                self.frame_count
            );
        }
        // Every number named by its key, before anything is loaded or written: a NaN or
        // infinite vector would otherwise reach the BVH build (a panic in obvhs) or render
        // empty frames with a NaN camera in stats.csv.
        let numbers = [
            ("[environment] rotation", self.env_rotation_deg),
            ("[environment] intensity", self.env_intensity),
            ("[camera] vfov", self.camera.vfov_deg),
            ("[camera] elevation", self.camera.elevation_deg),
            ("[camera] azimuth", self.camera.azimuth_deg),
        ];
        for (key, v) in numbers {
            if !v.is_finite() {
                bail_input!(path, "{key} = {v} is not a finite number");
            }
        }
        let vectors = [
            ("[camera] target", self.camera.target),
            ("[camera] position", self.camera.position),
            ("[camera] up", Some(self.camera.up)),
        ];
        for (key, v) in vectors {
            if let Some(v) = v
                && !v.is_finite()
            {
                bail_input!(path, "{key} = {} is not finite", show(v));
            }
        }
        if self.camera.up.length_squared() == 0.0 {
            bail_input!(path, "[camera] up = [0, 0, 0] has no direction");
        }
        // Intensity, field of view and distance are checked as settings, where they enter.
        Ok(())
    }

    /// Where spins turn, in `scene`'s coordinates: the default pivot (the camera's target at
    /// frame 0) and the scene's origin, from which a `[motion] pivot` (world space) is taken.
    pub fn pivot(&self, scene: &Scene) -> Result<Pivot> {
        Ok(Pivot {
            target: self.camera(scene, 0)?.target,
            origin: scene.origin,
        })
    }

    /// The scene's transform at `frame`: the spins done by then, each about the vertical axis
    /// through its pivot (from [`pivot`](Self::pivot)); `None` before any spin.
    pub fn scene_transform(&self, frame: usize, pivot: Pivot) -> Option<Mat4> {
        self.motion
            .scene_transform(frame, pivot.target, pivot.origin)
    }

    /// The key frame that starts the temporal chain holding `frame` (`--temporal`): frames
    /// `0, K, 2K, …` of each motion of the sequence, K the key-frame interval.
    pub fn key_frame_of(&self, frame: usize) -> usize {
        self.motion.key_frame_of(frame, self.render.keyframe)
    }

    /// Frames a job's range should start on so that every frame it writes is rendered as the
    /// whole animation would render it: with `temporal`, the key-frame interval (a job
    /// starting elsewhere first renders, without writing, the frames back to its key frame;
    /// a sequence of motions: [`Motion::frame_alignment`]).
    pub fn frame_alignment(&self) -> usize {
        if self.render.temporal {
            self.motion.frame_alignment(self.render.keyframe)
        } else {
            1
        }
    }

    /// The camera at `frame`. `scene` is the unposed scene (bounds and file camera).
    pub fn camera(&self, scene: &Scene, frame: usize) -> Result<Camera> {
        let rig = &self.camera;
        // The model, not the ground envshadow may have added under it.
        let (lo, hi) = scene.model_bounds();
        let centre = (lo + hi) * 0.5;
        // Scale-free: any positive radius frames the model (a floor in scene units would move
        // the camera of a model authored in micrometres).
        let radius = ((hi - lo) * 0.5).length().max(f32::MIN_POSITIVE);
        let (mut position, target, vfov) = if rig.from_file {
            let Some(c) = scene.camera else {
                // A camera the loader set aside says why (orthographic, a zero yfov).
                let why: Vec<&str> = scene
                    .warnings
                    .iter()
                    .filter(|w| w.contains(": camera "))
                    .map(|w| w.rsplit_once(": node ").map_or(w.as_str(), |(_, r)| r))
                    .collect();
                bail_input!(
                    &self.spec_path,
                    "[camera] from_file = true, but {} has no camera envshadow can use{}",
                    scene.source,
                    if why.is_empty() {
                        String::new()
                    } else {
                        format!(" (node {})", why.join("; node "))
                    }
                );
            };
            let dist = (centre - c.position).length().max(radius);
            (c.position, c.position + c.forward * dist, c.vfov_deg)
        } else {
            // The spec's positions are world space; the scene counts from its origin.
            let target = rig.target.map_or(centre, |t| scene.to_local(t));
            let position = match rig.position {
                Some(p) => scene.to_local(p),
                None => {
                    let (el, az) = (rig.elevation_deg.to_radians(), rig.azimuth_deg.to_radians());
                    let back = Vec3::new(
                        libm::cosf(el) * libm::sinf(az),
                        libm::sinf(el),
                        libm::cosf(el) * libm::cosf(az),
                    );
                    let dist = rig.distance.unwrap_or_else(|| {
                        let swept = Swept {
                            axis: target,
                            radius: scene.model_radius_about(target),
                            y: (lo.y, hi.y),
                        };
                        let aspect = self.render.width as f32 / self.render.height as f32;
                        swept.framing_distance(back, rig.up, rig.vfov_deg, aspect)
                    });
                    target + dist * back
                }
            };
            (position, target, rig.vfov_deg)
        };
        if let Some(degrees) = self.motion.orbit_degrees(frame) {
            let angle = degrees.to_radians();
            position = target + Mat4::from_rotation_y(angle).transform_vector3(position - target);
        }
        if !(position.is_finite() && target.is_finite()) {
            bail_input!(
                &self.spec_path,
                "the camera at frame {frame} is not finite (position {}, target {})",
                show(position),
                show(target)
            );
        }
        if !(target - position).normalize_or_zero().is_normalized() {
            bail_input!(&self.spec_path, "[camera] position and target coincide");
        }
        // look_at needs a right vector: `up` along the view leaves none.
        let forward = (target - position).normalize();
        if forward.cross(rig.up.normalize()).length() < 1e-4 {
            bail_input!(
                &self.spec_path,
                "[camera] up = {} is parallel to the view direction {} at frame {frame}",
                show(rig.up),
                show(forward)
            );
        }
        Ok(Camera::look_at(
            position,
            target,
            rig.up,
            vfov,
            self.render.width,
            self.render.height,
        ))
    }

    /// The settings that decide this animation's frames' bytes and `stats.csv` rows, as
    /// (`[table] key`, value) in spec order: what `render --resume` checks a folder against.
    /// The frames selected, the tile size, the thread count and the output folder change no
    /// pixel and are left out; input files are named by their content's SHA-256, so a moved spec still agrees.
    pub fn settings_record(&self) -> Result<SettingsRecord> {
        let mut lines: Vec<(String, String)> = Vec::new();
        let mut put = |k: &str, v: String| lines.push((k.to_string(), v));
        let file = |p: &Path| -> Result<String> {
            Ok(format!(
                "sha256:{}",
                file_sha256(p).map_err(|e| input_error(p, format!("{e:#}")))?
            ))
        };
        match &self.scene {
            SceneSource::Shapes => put("[scene] builtin", "shapes".into()),
            SceneSource::File(p) => put("[scene] file", file(p)?),
        }
        // [ours] Only what differs from the defaults, so folders rendered before these keys
        // existed (and which they would not change) still resume.
        let setting = |key: Key| format!("[{}] {}", key.table(), key.name());
        let defaults = SceneSettings::default().layer().given_keys();
        for (key, value) in self.scene_settings.layer().given_keys() {
            if !defaults.contains(&(key, value.clone())) {
                put(&setting(key), value);
            }
        }
        if !self.catchers.is_empty() {
            put("[scene] catchers", format!("{:?}", self.catchers));
        }
        match &self.env {
            EnvSource::Sky => put("[environment] builtin", "sky".into()),
            EnvSource::File(p) => put("[environment] file", file(p)?),
        }
        put("[environment] rotation", self.env_rotation_deg.to_string());
        put("[environment] intensity", self.env_intensity.to_string());
        let auto = |v: Option<String>| v.unwrap_or_else(|| "auto".into());
        let c = &self.camera;
        put("[camera] target", auto(c.target.map(show)));
        put("[camera] distance", auto(c.distance.map(|d| d.to_string())));
        put("[camera] elevation", c.elevation_deg.to_string());
        put("[camera] azimuth", c.azimuth_deg.to_string());
        put("[camera] vfov", c.vfov_deg.to_string());
        put("[camera] up", show(c.up));
        put("[camera] position", auto(c.position.map(show)));
        put("[camera] from_file", c.from_file.to_string());
        for (key, value) in self.motion.record(show) {
            put(&key, value);
        }
        for (key, value) in self.lights.layer().given_keys() {
            put(&setting(key), value);
        }
        let render_defaults = Render::default().layer().given_keys();
        for (key, value) in self.render.layer().given_keys() {
            // [ours] Tiles and threads change no pixel (tiled == untiled, bit for bit): a
            // resume may pick them for the machine it runs on. The background settings are
            // recorded when not the defaults, so folders from before them still resume.
            let background = matches!(
                key,
                Key::Background | Key::BackgroundColor | Key::BackgroundBlur
            );
            if background && render_defaults.contains(&(key, value.clone())) {
                continue;
            }
            if !matches!(key, Key::Threads | Key::Tile) {
                put(&setting(key), value);
            }
        }
        // Material overrides change pixels: the spec's, then the command line's.
        for (key, value) in self.materials.given() {
            put(&format!("[material] {key}"), value);
        }
        for (key, value) in self.material_flags.given() {
            put(&format!("[material] (command line) {key}"), value);
        }
        let output_defaults = Output::default().layer().given_keys();
        for (key, value) in self.output.layer().given_keys() {
            // The folder and the video change no frame's bytes. The names, the EXR layout and
            // Cryptomatte are recorded when not the defaults (folders from before them still
            // resume): readers of the folder find its frames by the names
            // (`FrameNames::of_folder`).
            let later = matches!(
                key,
                Key::OutputPattern | Key::FrameStart | Key::ExrLayout | Key::Cryptomatte
            );
            if later && output_defaults.contains(&(key, value.clone())) {
                continue;
            }
            if !matches!(key, Key::Dir | Key::Video) {
                put(&setting(key), value);
            }
        }
        Ok(SettingsRecord { lines })
    }
}

impl Animation {
    /// This animation as a spec (`render --write-spec`): every setting resolved, the command
    /// line's included, input files and the output folder by absolute path, so that the
    /// spec renders the same frames from any folder. `--frames` is a selection, not a
    /// setting: the spec renders every frame.
    pub fn spec_text(&self) -> Result<String> {
        use crate::settings::{CameraSettings, EnvSettings, spec_float};
        use toml::Value as V;
        let absolute = |p: &Path| -> Result<V> {
            let a = std::path::absolute(p)
                .map_err(|e| input_error(p, format!("cannot resolve the path: {e}")))?;
            Ok(V::String(a.to_string_lossy().into_owned()))
        };
        let float = |x: f32| V::Float(spec_float(x));
        let vector = |v: Vec3| V::Array(v.to_array().map(float).to_vec());
        let mut doc = toml::Table::new();
        doc.insert("name".into(), V::String(self.name.clone()));

        let mut scene = self.scene_settings.layer().spec_table();
        match &self.scene {
            SceneSource::Shapes => scene.insert("builtin".into(), V::String("shapes".into())),
            SceneSource::File(p) => scene.insert("file".into(), absolute(p)?),
        };
        if !self.catchers.is_empty() {
            let names = self.catchers.iter().map(|c| V::String(c.clone())).collect();
            scene.insert("catchers".into(), V::Array(names));
        }
        doc.insert("scene".into(), V::Table(scene));

        let environment = EnvSettings {
            rotation: self.env_rotation_deg,
            intensity: self.env_intensity,
        };
        let mut env = environment.layer().spec_table();
        match &self.env {
            EnvSource::Sky => env.insert("builtin".into(), V::String("sky".into())),
            EnvSource::File(p) => env.insert("file".into(), absolute(p)?),
        };
        doc.insert("environment".into(), V::Table(env));
        doc.insert("lights".into(), V::Table(self.lights.layer().spec_table()));

        let c = &self.camera;
        let placed = CameraSettings {
            distance: c.distance.unwrap_or(0.0),
            elevation: c.elevation_deg,
            azimuth: c.azimuth_deg,
            vfov: c.vfov_deg,
            from_file: c.from_file,
        };
        let mut camera = placed.layer().spec_table();
        camera.insert("up".into(), vector(c.up));
        if let Some(t) = c.target {
            camera.insert("target".into(), vector(t));
        }
        if let Some(p) = c.position {
            camera.insert("position".into(), vector(p));
        }
        doc.insert("camera".into(), V::Table(camera));
        doc.insert("motion".into(), self.motion.spec_value());
        doc.insert("render".into(), V::Table(self.spec_render().spec_table()));

        let mut output = self.output.layer().spec_table();
        output.insert("dir".into(), absolute(&self.output.dir)?);
        doc.insert("output".into(), V::Table(output));
        let materials = self.spec_materials()?;
        if !materials.is_empty() {
            doc.insert("material".into(), V::Table(materials));
        }
        let text = toml::to_string(&doc)
            .map_err(|e| input_error(&self.spec_path, format!("cannot write as a spec: {e}")))?;
        Ok(format!(
            "# Written by `envshadow render --write-spec`: the resolved settings of a render of\n\
             # {}; `envshadow render` this file renders the same frames.\n{text}",
            self.spec_path.display()
        ))
    }

    /// Writes [`spec_text`](Self::spec_text) to `path` (a temporary file, then renamed).
    pub fn write_spec(&self, path: &Path) -> Result<()> {
        let text = self.spec_text()?;
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)
                .map_err(|e| input_error(dir, format!("cannot create the folder: {e}")))?;
        }
        crate::output::write_atomic(path, text.as_bytes())
    }

    /// The `[render]` settings a spec gives: those the method reads, the key-frame interval
    /// with temporal prediction, the background's colour or blur with that background (a
    /// spec giving the others is refused).
    fn spec_render(&self) -> RenderLayer {
        use crate::background::Background;
        let r = &self.render;
        let mut layer = r.layer();
        for (key, _) in layer.clone().given_keys() {
            let unread = crate::settings::method_specific(key) && !r.method.reads(key);
            let off = match key {
                Key::Keyframe => !r.temporal,
                Key::BackgroundColor => r.background != Background::Color,
                Key::BackgroundBlur => r.background != Background::Blurred,
                _ => false,
            };
            if unread || off {
                layer.clear(key);
            }
        }
        layer
    }

    /// The `[material]` table that overrides the materials as the spec's `[material]` and
    /// the command line's `--clay`, `--lambert` do: those apply after the spec's named
    /// overrides, so they join each named table too.
    fn spec_materials(&self) -> Result<toml::Table> {
        let flags = &self.material_flags;
        let mut merged = flags.over(&self.materials);
        for o in merged.named.values_mut() {
            *o = flags.over(o);
        }
        let lines: String = merged
            .given()
            .into_iter()
            .map(|(key, value)| format!("{key} = {value}\n"))
            .collect();
        toml::from_str(&lines).map_err(|e| {
            input_error(
                &self.spec_path,
                format!("[material] cannot be written as a spec: {e}"),
            )
        })
    }
}

/// Refuses the background settings that the chosen background does not read: a colour
/// without `background = "color"`, a blur without `"blurred"` (they would change nothing).
fn check_background(given: &RenderLayer, flags: &RenderLayer, path: &Path) -> Result<()> {
    use crate::background::Background;
    let background = given.background.unwrap_or_default();
    for (key, flag, set, wants) in [
        (
            "background_color",
            "background-color",
            given.background_color.is_some(),
            Background::Color,
        ),
        (
            "background_blur",
            "background-blur",
            given.background_blur.is_some(),
            Background::Blurred,
        ),
    ] {
        if set && background != wants {
            let from_flag = match key {
                "background_color" => flags.background_color.is_some(),
                _ => flags.background_blur.is_some(),
            };
            let source = if from_flag {
                Source::Flags
            } else {
                Source::Spec(path)
            };
            let message =
                format!("applies only with background = \"{wants}\" (it is \"{background}\")");
            return Err(source.error(Render::TABLE, key, flag, message));
        }
    }
    Ok(())
}

/// A vector as a spec writes it: `[x, y, z]`.
fn show(v: Vec3) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}

/// Where an animation's spins turn ([`Animation::pivot`]), in the scene's coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pivot {
    /// The pivot of a spin that names none: the camera's target at frame 0.
    pub target: Vec3,
    /// The scene's origin ([`Scene::origin`]): a `[motion] pivot` is a world-space point.
    pub origin: glam::DVec3,
}

/// Frames of a model's default turntable ([`Animation::of_model`]): 5° per frame.
pub const MODEL_FRAMES: usize = 72;

/// Refuses a file whose content is not a TOML spec (a model, a mesh, a web page), naming
/// what it is rather than a TOML parser's line and column.
fn not_a_spec(path: &Path, bytes: &[u8]) -> Result<()> {
    use crate::scene::sniff::{Kind, kind, opening};
    let what = match kind(bytes) {
        Kind::Text => return Ok(()),
        Kind::Glb { .. } => "a glTF model (GLB)".to_string(),
        Kind::Json => "a JSON file (a .gltf model?)".to_string(),
        Kind::Other(what) => what.to_string(),
        Kind::Binary => format!("not text (starts with '{}')", opening(bytes)),
    };
    bail_input!(
        path,
        "{what}, not an animation spec: envshadow reads glTF 2.0 models (.gltf/.glb: \
         `envshadow render model.glb`) and TOML animation specs"
    )
}

/// Whether `path` names a glTF model (`.glb`, `.gltf`) rather than an animation spec.
pub fn is_model(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("glb") || e.eq_ignore_ascii_case("gltf"))
}

/// Default key-frame interval for `motion` ([`MotionKind::default_keyframe`]): one motion's
/// own; 0 for a sequence, whose motions each take their own default.
pub fn default_keyframe(motion: &Motion) -> u32 {
    if motion.is_single() {
        motion.segments()[0].kind.default_keyframe()
    } else {
        0
    }
}

/// The spec's motion with the command line's `--frame-count` and `--degrees-per-frame` over
/// its one `[motion]` table; `grows`: frames asked for (`--frames`) past the last lengthen
/// that table at its degrees per frame, so frame N is the same picture whatever is asked.
fn motion_of(
    specs: &mut crate::motion::MotionSpecs,
    path: &Path,
    flags: &AnimFlags,
    grows: bool,
) -> Result<Motion> {
    if let Some(n) = flags.frame_count
        && !(1..=limits::MAX_FRAMES).contains(&n)
    {
        return Err(input_error(
            "",
            format!(
                "--frame-count {n}: must be 1 to {} frames",
                limits::MAX_FRAMES
            ),
        ));
    }
    if let Some(d) = flags.degrees_per_frame
        && !d.is_finite()
    {
        return Err(input_error(
            "",
            format!("--degrees-per-frame {d}: is not a finite number"),
        ));
    }
    if let Err(n) = specs.set_single(flags.frame_count, flags.degrees_per_frame) {
        let flag = if flags.frame_count.is_some() {
            "--frame-count"
        } else {
            "--degrees-per-frame"
        };
        bail_input!(
            flag,
            "applies to one [motion] table; {} has a sequence of {n} [[motion]] tables (edit their frames there)",
            path.display()
        );
    }
    let motion = Motion::from_spec(specs, path)?;
    let last = flags.frames.as_ref().and_then(FrameSet::last);
    match last {
        Some(last) if grows && motion.is_single() && last >= motion.frame_count() => {
            let d = motion.segments()[0].degrees_per_frame;
            // The limit on frames is checked with the animation's (`validate`).
            let _ = specs.set_single(Some(last.saturating_add(1)), Some(d));
            Motion::from_spec(specs, path)
        }
        _ => Ok(motion),
    }
}

/// The camera as the spec's `[camera]` and the command line's camera flags place it. A flag
/// that places the camera by angles (--distance, --elevation, --azimuth) replaces the spec's
/// `position`; one the file's camera would ignore is refused.
fn camera_rig(spec: &CameraSpec, flags: &CameraLayer) -> Result<CameraRig> {
    let given = flags.clone().over(spec.layer());
    let c = given.resolve();
    let by_angles =
        flags.distance.is_some() || flags.elevation.is_some() || flags.azimuth.is_some();
    if c.from_file {
        for (key, _) in flags.given_keys() {
            if key != Key::FromFile {
                bail_input!(
                    format!("--{}", key.flag()),
                    "does not apply with the file's camera (--gltf-camera, [camera] from_file), which has its own"
                );
            }
        }
    }
    let v3 = |a: [f32; 3]| Vec3::from_array(a);
    Ok(CameraRig {
        target: spec.target.map(v3),
        distance: (c.distance > 0.0).then_some(c.distance),
        elevation_deg: c.elevation,
        azimuth_deg: c.azimuth,
        vfov_deg: c.vfov,
        up: v3(spec.up),
        position: spec.position.filter(|_| !by_angles).map(v3),
        from_file: c.from_file,
    })
}

/// A TOML error as one line, naming the table and key it is about where the position shows
/// them: `line 6, column 12: [render] flood_to: unknown flood rule "some"; … (at `…`)`.
fn toml_message(text: &str, e: &toml::de::Error) -> String {
    let folded = one_line(&e.to_string());
    let Some(span) = e.span() else {
        return folded;
    };
    let start = span.start.min(text.len());
    let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
    let line = text[line_start..].lines().next().unwrap_or("");
    let Some((key, _)) = line.split_once('=') else {
        return folded;
    };
    let key = key.trim();
    if key.is_empty() || key.contains(['[', '"', ' ']) {
        return folded;
    }
    let table = text[..line_start]
        .lines()
        .rev()
        .map(str::trim)
        .find(|l| l.starts_with('[') && l.ends_with(']'));
    let place = match table {
        Some(t) => format!("{t} {key}"),
        None => key.to_string(),
    };
    match folded.split_once(": ") {
        Some((position, rest)) => format!("{position}: {place}: {rest}"),
        None => format!("{place}: {folded}"),
    }
}

/// toml's messages span several lines (position, a source excerpt with a caret, the
/// explanation); fold them into one: `line 6, column 9: invalid type … (at `width = "wide"`)`.
fn one_line(msg: &str) -> String {
    let lines: Vec<&str> = msg
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    let position = lines
        .first()
        .map(|l| l.trim_start_matches("TOML parse error at ").to_string())
        .unwrap_or_default();
    let excerpt = lines.iter().find_map(|l| {
        let (num, rest) = l.split_once('|')?;
        (!num.trim().is_empty() && num.trim().chars().all(|c| c.is_ascii_digit()))
            .then(|| rest.trim().to_string())
    });
    let explanation = lines
        .iter()
        .skip(1)
        .filter(|l| {
            !l.starts_with('|')
                && l.split_once('|')
                    .is_none_or(|(n, _)| n.trim().parse::<u64>().is_err())
        })
        .copied()
        .collect::<Vec<_>>()
        .join(" ");
    match excerpt {
        Some(ex) if !ex.is_empty() => format!("{position}: {explanation} (at `{ex}`)"),
        _ => format!("{position}: {explanation}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn toml_errors_fold_into_one_line_with_position_and_key() {
        let err = Animation::parse(
            "[scene]\nbuiltin = \"shapes\"\n[render]\nwidth = \"wide\"\n",
            Path::new("a.toml"),
            &AnimFlags::default(),
        )
        .unwrap_err()
        .to_string();
        assert!(!err.contains('\n'), "{err}");
        assert!(err.starts_with("a.toml: line 4, column 9: "), "{err}");
        assert!(err.contains("[render] width: invalid type"), "{err}");
        assert!(err.contains("width = \"wide\""), "{err}");
        let err = Animation::parse(
            "[scene]\nbuiltin = \"shapes\"\n[render]\nwidht = 1\n",
            Path::new("b.toml"),
            &AnimFlags::default(),
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("widht") && err.contains("line 4"), "{err}");
    }

    #[test]
    fn the_spec_documented_above_parses() {
        let doc: String = include_str!("anim.rs")
            .lines()
            .filter_map(|l| l.strip_prefix("//!"))
            .map(|l| l.strip_prefix(' ').unwrap_or(l))
            .collect::<Vec<_>>()
            .join("\n");
        let toml = doc
            .split("```toml\n")
            .nth(1)
            .and_then(|t| t.split("```").next())
            .expect("the module doc has a toml block");
        let anim = Animation::parse(toml, Path::new("doc.toml"), &AnimFlags::default()).unwrap();
        assert_eq!((anim.render.width, anim.lights.count), (320, 100));
        assert!(anim.lights.scene_lights);
        let off = toml.replace("scene_lights = true", "scene_lights = false");
        let anim = Animation::parse(&off, Path::new("doc.toml"), &AnimFlags::default()).unwrap();
        assert!(!anim.lights.scene_lights);
    }

    #[test]
    fn orbit_turns_the_camera_and_spin_turns_the_scene() {
        let text = "[scene]\nbuiltin = \"shapes\"\n[camera]\ntarget = [0.0, 0.0, 0.0]\ndistance = 2.0\nelevation = 0.0\nazimuth = 0.0\n[motion]\nframes = 4\n";
        let anim = Animation::parse(text, Path::new("o.toml"), &AnimFlags::default()).unwrap();
        let scene = Scene::shapes();
        let c0 = anim.camera(&scene, 0).unwrap();
        assert!((c0.position - Vec3::new(0.0, 0.0, 2.0)).length() < 1e-5);
        // A quarter turn (90° per frame) about +Y takes +Z to +X.
        let c1 = anim.camera(&scene, 1).unwrap();
        assert!(
            (c1.position - Vec3::new(2.0, 0.0, 0.0)).length() < 1e-4,
            "{}",
            c1.position
        );
        assert!(
            anim.scene_transform(
                1,
                Pivot {
                    target: Vec3::ZERO,
                    origin: glam::DVec3::ZERO
                }
            )
            .is_none()
        );
        let spin = Animation::parse(
            &text.replace("frames = 4", "frames = 4\nkind = \"spin\""),
            Path::new("s.toml"),
            &AnimFlags::default(),
        )
        .unwrap();
        assert_eq!(spin.camera(&scene, 3).unwrap().position, c0.position);
        let m = spin
            .scene_transform(
                1,
                Pivot {
                    target: Vec3::ZERO,
                    origin: glam::DVec3::ZERO,
                },
            )
            .unwrap();
        assert!((m.transform_point3(Vec3::Z) - Vec3::X).length() < 1e-5);
    }
}
