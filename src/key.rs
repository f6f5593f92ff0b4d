//! The settings' keys, typed: a setting that code names (a method's `reads`, the settings
//! record, `envshadow methods`) is a [`Key`], so a renamed or removed setting is a compile error.
//!
//! The list of every setting lives here ([`settings_list!`]), below every module that names a
//! setting: the methods read keys, and the settings' own module sits above the methods (its
//! values are methods and flood rules). The list is tokens only — its types, defaults and
//! checks are resolved in `settings.rs`, where `settings!` turns it into the settings'
//! structs and [`Key`]'s methods (its name in a spec's table, its flag, its table,
//! [`Key::ALL`]) — so one entry makes both the setting and its key.

/// Every setting, declared once: its table, its name in the table (the spec key), its
/// type and default, its [`Key`], its flag, its `--help` (the doc comment) and its check.
/// `settings_list!(m)` hands the list to macro `m`: `settings.rs`'s `settings!` makes the
/// settings' structs from it, [`key_enum!`] the [`Key`]s. The types, defaults and checks are
/// names resolved where `settings!` expands them (`settings.rs`), so this module imports
/// nothing.
///
/// A new setting is one entry here (and, for a method setting, its field in `Params` and its
/// [`Key`] in the `reads` of the orders or flood rules that read it).
macro_rules! settings_list {
    ($then:ident) => {
        $then! {
            /// How the environment becomes lights (`[lights]`).
            ["lights"] Lights, LightsLayer, LightsSweep {
                /// Number of directional lights the environment is reduced to (default 200).
                count: usize = 200, key Count,
                    flag "lights" [short = 'n', alias = "count", value_name = "N"],
                    check any;
                /// Light sampler: sis (structured importance sampling, the default) or median-cut.
                sampler: Sampler = Sampler::Sis, key Sampler,
                    flag "sampler" [value_name = "NAME"], check any;
                /// Light the scene with the lights its glTF file places (KHR_lights_punctual:
                /// directional, point and spot) besides the map's (default true); false ignores them.
                scene_lights: bool = true, key SceneLights,
                    flag "scene-lights" [value_name = "BOOL", num_args = 0..=1, require_equals = true,
                        default_missing_value = "true"], check any;
            }

            /// How frames are rendered (`[render]`).
            ["render"] Render, RenderLayer, RenderSweep {
                /// Image width in pixels (default 640).
                width: u32 = 640, key Width, flag "width" [value_name = "W"], check any;
                /// Image height in pixels (default 480).
                height: u32 = 480, key Height, flag "height" [value_name = "H"], check any;
                /// Samples per pixel, a square from 1 to 64 (default 1: the pixel centre; a model
                /// render, `envshadow render model.glb`, uses 4): a k×k stratified, jittered pattern
                /// warped through --filter. Shadows are predicted
                /// between samples as between pixels. Above 1, textures are filtered (mip-mapped) to
                /// what each sample covers; at 1 they are point-sampled, as they always were.
                spp: u32 = 1, key Spp, flag "spp" [value_name = "N"], check check_spp;
                /// Pixel filter, importance-sampled (each sample counts once; its support may reach
                /// into the neighbouring pixels): blackman-harris (the default, Cycles' own: smooth
                /// edges with no visible ringing), gaussian, triangle or box. With --spp 1 the one
                /// sample is the pixel centre whatever the filter.
                filter: Filter = Filter::BlackmanHarris, key Filter,
                    flag "filter" [value_name = "NAME"], check any;
                /// Filter width in pixels, its full support (0, the default: box 1, triangle 2,
                /// gaussian and blackman-harris 1.5).
                filter_width: f32 = 0.0, key FilterWidth,
                    flag "filter-width" [value_name = "PX"], check check_filter_width;
                /// How often a pixel's samples are shaded, with --spp above 1: pixel (the default):
                /// the samples of a pixel that see the same surface (material, normal within 2.6°)
                /// share one evaluation of each light at their mean normal, each keeping its own
                /// shadows; sample: every sample shades every light it sees (docs/samples.md).
                shading_rate: ShadingRate = ShadingRate::Pixel, key ShadingRate,
                    flag "shading-rate" [value_name = "RATE"], check any;
                /// Specular lobes too narrow for the lights (low roughness: the lights would show as
                /// dots) reflect the environment prefiltered per roughness, weighted by the lobe's
                /// visible lights (default true); false: the lights alone at every roughness, the
                /// exact sum over them (docs/materials.md).
                glossy_env: bool = true, key GlossyEnv,
                    flag "glossy-env" [value_name = "BOOL", num_args = 0..=1, require_equals = true,
                        default_missing_value = "true"], check any;
                /// Shadow terminator offset (default false): true lifts a shadow ray's point onto
                /// the smooth surface the vertex normals describe and receives light down to that
                /// surface's horizon (Hanika, "Hacking the Shadow Terminator", 2021), so a low-poly
                /// model's lit side ends in a smooth terminator instead of its facets' steps. Off
                /// by default: it also brightens creases of detailed meshes (0.15–1.6 % on the
                /// corpus, BENCHMARKS.md).
                terminator_offset: bool = false, key TerminatorOffset,
                    flag "terminator-offset" [value_name = "BOOL", num_args = 0..=1,
                        require_equals = true, default_missing_value = "true"], check any;
                /// Shadow method (default grid-nowarp-uncertainty; `envshadow methods` lists them all).
                method: Method = Method::DEFAULT, key Method,
                    flag "method" [value_name = "METHOD", alias = "methods"], check any;
                /// Also trace every shadow query and record the method's mistakes: stats.csv gains
                /// wrong pairs, error rate and image error; the EXR gains a `wrong` layer. Default
                /// false.
                validate: bool = false, key Validate,
                    flag "validate" [value_name = "BOOL", num_args = 0..=1, require_equals = true,
                        default_missing_value = "true"], check any;
                /// Grid methods: coarse grid spacing, a power of two from 2 to 256 (default 16).
                h0: u32 = Params::DEFAULT.h0, key H0, flag "h0" [value_name = "N"], check check_h0;
                /// Uncertainty methods: trace a light when fewer voters than this have it above their
                /// horizon, 1–4 (default 3).
                min_voters: u32 = Params::DEFAULT.min_voters, key MinVoters,
                    flag "min-voters" [value_name = "K"], check check_min_voters;
                /// Uncertainty methods: which neighbour lights a flooding trace also traces — `all`
                /// untraced ones; `contrary`: only those predicted opposite to the traced answer, about
                /// a third fewer rays with more wrong pairs; `contrary-finest`: `contrary` at the
                /// grid's finest level, whose wrong pairs mislead no coarser pixel, and `all` above it,
                /// about a fifth fewer rays than `all` for a few percent more wrong pairs; `adaptive`:
                /// `all` where a voter's flooding caught a wrong prediction, `contrary` elsewhere;
                /// `auto` (the default): `all` for a frame with cut-out (alpha MASK or BLEND)
                /// triangles, whose holes contrary flooding misses, `contrary-finest` otherwise
                /// (docs/methods.md).
                flood_to: FloodTo = Params::DEFAULT.flood_to, key FloodTo,
                    flag "flood-to" [value_name = "RULE"], check any;
                /// Grid methods with --spp above 1: at the finest level, whose voters lie one sample
                /// apart inside a pixel, take a light on which three of four voters agree from them
                /// instead of tracing it (default false): a sixth fewer rays on the corpus at 4 spp,
                /// but five times the wrong pairs where shadows are finer than a pixel (cut-outs, thin
                /// parts) and several times the image error (docs/samples.md).
                pixel_majority: bool = Params::DEFAULT.pixel_majority, key PixelMajority,
                    flag "pixel-majority" [value_name = "BOOL", num_args = 0..=1, require_equals = true,
                        default_missing_value = "true"], check any;
                /// Uncertainty methods: predict a light only if every valid voter (at least
                /// --min-voters of them) has it above its horizon; default false (BENCHMARKS.md,
                /// issue 23).
                all_voters: bool = Params::DEFAULT.all_voters, key AllVoters,
                    flag "all-voters" [value_name = "BOOL", num_args = 0..=1, require_equals = true,
                        default_missing_value = "true"], check any;
                /// Uncertainty methods: where a voter's flooding caught a wrong prediction, trace a
                /// light fewer than K voters have above their horizon (default 4; 0: --min-voters
                /// everywhere): more tracing where shadows are finer than the voters' spacing, thin
                /// and busy models (BENCHMARKS.md, issue 23).
                busy_voters: u32 = Params::DEFAULT.busy_voters, key BusyVoters,
                    flag "busy-voters" [value_name = "K"], check check_busy_voters;
                /// Uncertainty methods: a pixel whose voters leave at least this share of its lights
                /// (percent) to trace traces all of them, in full packets from its point, and is exact
                /// (default 40; 0: off): on the corpus, half the wrong pairs of cut-out models for
                /// about the same rays (BENCHMARKS.md, issue 23).
                trace_all_share: u32 = Params::DEFAULT.trace_all_share, key TraceAllShare,
                    flag "trace-all-share" [value_name = "PERCENT"],
                    check check_percent;
                /// Uncertainty and boundary methods: a neighbour votes only if it lies on the pixel's
                /// surface (its normal within about 37° of the pixel's, its point within about 17° of
                /// the pixel's tangent plane); default false (BENCHMARKS.md, issue 23).
                surface_voters: bool = Params::DEFAULT.surface_voters, key SurfaceVoters,
                    flag "surface-voters" [value_name = "BOOL", num_args = 0..=1, require_equals = true,
                        default_missing_value = "true"], check any;
                /// Scanline methods: block size at which the scan restarts, at least 8 (default 64).
                scan_block: u32 = Params::DEFAULT.scan_block, key ScanBlock,
                    flag "scan-block" [value_name = "N"], check check_scan_block;
                /// Uncertainty methods: let every pixel whose surface point the previous frame saw use
                /// the previous frame's pixels there as voters (camera orbit: reprojection; object
                /// spin: votes pulled through the turn). Default false; see docs/temporal.md.
                temporal: bool = false, key Temporal,
                    flag "temporal" [value_name = "BOOL", num_args = 0..=1, require_equals = true,
                        default_missing_value = "true"], check any;
                /// With --temporal: frames 0, N, 2N, … are predicted from their own pixels and restart
                /// the chain (0, the default: 16 for a camera orbit, 4 for a spinning object). A run
                /// starting between key frames first renders, without writing, the frames back to the
                /// key frame before it.
                keyframe: u32 = 0, key Keyframe, flag "keyframe" [value_name = "N"], check check_keyframe;
                /// What rays that leave the scene see: environment (the default: the map, as it
                /// lights the scene), transparent (alpha 0: the EXR's RGBA is premultiplied, the PNG
                /// has straight alpha), color (--background-color) or blurred (the map blurred by
                /// --background-blur). The lights always come from the map.
                background: Background = Background::Environment, key Background,
                    flag "background" [value_name = "KIND"], check any;
                /// With --background color: the colour, linear RGB (default 0.18,0.18,0.18).
                background_color: Rgb = Rgb([0.18; 3]), key BackgroundColor,
                    flag "background-color" [value_name = "R,G,B"], check check_rgb;
                /// With --background blurred: the blur's standard deviation in degrees, 1 to 90
                /// (default 10).
                background_blur: f32 = 10.0, key BackgroundBlur,
                    flag "background-blur" [value_name = "DEGREES"], check check_blur;
                /// Exposure of the PNG previews, a multiplier applied before the view transform (the
                /// EXR keeps linear radiance; default 1).
                exposure: f32 = 1.0, key Exposure, flag "exposure" [value_name = "X"], check check_finite;
                /// View transform of the PNG previews, after the exposure: agx (the default,
                /// Blender's AgX: highlights roll off and desaturate), hable (John Hable's filmic
                /// curve, not Blender's Filmic) or standard (the sRGB curve, clipped at 1). The
                /// EXR stays linear.
                view: View = View::Agx, key View, flag "view" [value_name = "NAME"], check any;
                /// Tile size in pixels: 0 (the whole frame is one tile) or at least 8 (default 64).
                tile: u32 = 64, key Tile, flag "tile" [value_name = "N"], check check_tile;
                /// Worker threads (0, the default: one per core).
                threads: usize = 0, key Threads, flag "threads" [value_name = "N"], check any;
            }

            /// How the environment map is placed (`[environment]`, beside its `builtin` or `file`).
            ["environment"] EnvSettings, EnvLayer, EnvSweep {
                /// Turn the environment (its lights and the background) about the up axis,
                /// degrees (default 0): +90 moves what was seen along +Z to be seen along +X.
                rotation: f32 = 0.0, key EnvRotation,
                    flag "env-rotation" [value_name = "DEGREES", allow_negative_numbers = true],
                    check check_finite;
                /// Scale the environment's radiance, its lights and the background alike, at
                /// least 0 (default 1; a model's turntable under the built-in sky has 0.25).
                intensity: f32 = 1.0, key EnvIntensity,
                    flag "env-intensity" [value_name = "X", allow_negative_numbers = true],
                    check check_intensity;
            }

            /// Where the camera stands (`[camera]`, beside its `target`, `up` and `position`).
            ["camera"] CameraSettings, CameraLayer, CameraSweep {
                /// Camera distance from its target, in scene units (0, the default: auto-framed, the
                /// model filling at most nine tenths of the frame at every angle of its turn).
                distance: f32 = 0.0, key Distance,
                    flag "distance" [value_name = "D", allow_negative_numbers = true],
                    check check_distance;
                /// Camera elevation above the horizon, degrees, -90 to 90 (default 25).
                elevation: f32 = 25.0, key Elevation,
                    flag "elevation" [value_name = "DEGREES", allow_negative_numbers = true],
                    check check_elevation;
                /// Camera azimuth about the target, degrees from +Z towards +X (default 20); an
                /// orbit starts there.
                azimuth: f32 = 20.0, key Azimuth,
                    flag "azimuth" [value_name = "DEGREES", allow_negative_numbers = true],
                    check check_finite;
                /// Vertical field of view, degrees, between 0 and 180 (default 40).
                vfov: f32 = 40.0, key Vfov, flag "vfov" [alias = "fov", value_name = "DEGREES",
                    allow_negative_numbers = true],
                    check check_vfov;
                /// Look through the glTF file's first perspective camera (its position, direction
                /// and field of view) instead of placing one by distance, elevation and azimuth
                /// (default false); an orbit turns it about the point it looks at.
                from_file: bool = false, key FromFile,
                    flag "gltf-camera" [value_name = "BOOL", num_args = 0..=1, require_equals = true,
                        default_missing_value = "true"], check any;
            }

            /// What is done to the loaded scene (`[scene]`, beside the file it comes from).
            ["scene"] SceneSettings, SceneLayer, SceneSweep {
                /// The file's up axis: y (glTF's, the default) or z (the scene, its cameras included,
                /// is turned so that +Z points up, before anything else reads it).
                up: Up = Up::Y, key Up, flag "up" [value_name = "AXIS"], check any;
                /// A ground below the model: auto (the default: when the scene has no surface the model
                /// stands on), none, or always. The ground is a disc at the model's lowest point, 32
                /// bounding-sphere radii wide, diffuse grey (albedo 0.5) or, over a transparent
                /// background or with --shadow-catcher, a shadow catcher.
                ground: Ground = Ground::Auto, key Ground, flag "ground" [value_name = "WHEN"], check any;
                /// Make the added ground a shadow catcher over any background (it always is over a
                /// transparent one): it shows only the shadows on it. Default false.
                shadow_catcher: bool = false, key ShadowCatcher,
                    flag "shadow-catcher" [value_name = "BOOL", num_args = 0..=1, require_equals = true,
                        default_missing_value = "true"], check any;
                /// A folder a glTF file's external buffers and images may also be read from (default
                /// none: only files inside the model's own folder, after following symbolic links,
                /// are read; a URI leading elsewhere is refused). Relative to the working directory.
                allow_folder: AllowedFolder = AllowedFolder::NONE, key AllowFolder,
                    flag "allow-folder" [value_name = "DIR"], check any;
                /// The glTF file's animation to play: its name, its index from 0, first (the default:
                /// the file's first animation, when it has one) or none (the rest pose: skins and
                /// default morph weights still applied). Plays with the turntable or a still camera.
                animation: Choice = Choice::First, key Animation,
                    flag "animation" [value_name = "NAME|INDEX"], check any;
                /// Seconds into the animation at frame 0: frame N shows the moment N ÷ fps + this
                /// (default 0).
                animation_start: f32 = 0.0, key AnimationStart,
                    flag "animation-start" [value_name = "SECONDS", allow_negative_numbers = true],
                    check check_finite;
                /// What frames past the animation's end show: loop (the default: it starts over),
                /// hold (its last pose) or stop (such frames are refused, naming the last one that
                /// is not).
                animation_end: AfterEnd = AfterEnd::Loop, key AnimationEnd,
                    flag "animation-end" [value_name = "WHAT"], check any;
            }

            /// Where a render's files go (`[output]`).
            ["output"] Output, OutputLayer, OutputSweep {
                /// Output folder, relative to the working directory (default `out`, or a spec's
                /// `[output] dir`; a model render, `envshadow render model.glb`, writes to
                /// out/<model name>).
                dir: PathBuf = PathBuf::from("out"), key Dir, flag "out" [value_name = "DIR"], check any;
                /// Write the EXR's channels as 16-bit half floats where they suffice (beauty, normal,
                /// albedo, fractions; ray counts, wrong pairs and depth stay 32-bit): about a third of
                /// the size. Default false.
                half: bool = false, key Half,
                    flag "half" [value_name = "BOOL", num_args = 0..=1, require_equals = true,
                        default_missing_value = "true"], check any;
                /// Frames per second of the animation, stored exactly as a rational: the EXR's
                /// `framesPerSecond`, the video's rate (default 24). A whole number, N/D
                /// (30000/1001), or the NTSC decimals 23.976, 29.97, 59.94, which are n·1000/1001.
                fps: FrameRate = FrameRate::whole(24), key Fps, flag "fps" [value_name = "FPS"],
                    check check_fps;
                /// Frame file names, Blender's way: the run of # is the frame number, zero-padded
                /// to its length (turntable_#### → turntable_0001.exr and .png); without #, four
                /// digits are appended. A file name, not a path: no / \ or %. Default `frame_####`.
                output_pattern: Pattern = Pattern::default(), key OutputPattern,
                    flag "output-pattern" [value_name = "PATTERN"], check any;
                /// Number of the first frame in the file names and the EXR's `envshadow/frame`: a
                /// frame's number is this plus its index (--frames counts from 0 whatever it is).
                /// --frame-start 1 numbers frames from 1, as Blender does. Default 0.
                frame_start: u32 = 0, key FrameStart, flag "frame-start" [value_name = "N"],
                    check check_frame_start;
                /// How the EXR's channels are named: envshadow (the default: `R G B A`, `Z`, `N.X`,
                /// `albedo.R`, `shadow.rays`, …) or blender (Blender's multilayer names, which its
                /// compositor opens as a render of its own: `ViewLayer.Combined.R`,
                /// `ViewLayer.Depth.Z`, `ViewLayer.Normal.X`, `ViewLayer.DiffCol.R` for the albedo,
                /// ours as `ViewLayer.ShadowRays.X`, …).
                exr_layout: ExrLayout = ExrLayout::Envshadow, key ExrLayout,
                    flag "exr-layout" [value_name = "LAYOUT"], check any;
                /// Cryptomatte ID mattes in the EXR, objects and materials by name (Psyop's
                /// specification, which Nuke and Blender read: CryptoObject00–02 and
                /// CryptoMaterial00–02, six ranks each, the manifests in the header). Default false.
                cryptomatte: bool = false, key Cryptomatte,
                    flag "cryptomatte" [value_name = "BOOL", num_args = 0..=1, require_equals = true,
                        default_missing_value = "true"], check any;
                /// At the end of a render, encode the frames' PNGs into DIR/video.mp4 (H.264) with
                /// the system's ffmpeg, as `envshadow video DIR` does. Default false.
                video: bool = false, key Video,
                    flag "video" [value_name = "BOOL", num_args = 0..=1, require_equals = true,
                        default_missing_value = "true"], check any;
            }
        }
    };
}
pub(crate) use settings_list;

/// Makes [`Key`] from [`settings_list!`]: one variant per setting, documented as its setting.
macro_rules! key_enum {
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
        /// One setting of a spec's tables (`[lights]`, `[render]`, `[environment]`, `[camera]`,
        /// `[scene]`, `[output]`).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum Key {
            $($(
                $(#[doc = $doc])*
                $key,
            )*)*
        }
    };
}

settings_list!(key_enum);
