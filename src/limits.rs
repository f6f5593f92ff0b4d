//! Limits checked before work starts, so a hostile or mistaken input is refused with a message
//! instead of exhausting the host: frame size, light count, frames, input file sizes, triangles,
//! and an estimate of the memory a render would need.
//!
//! The limits are fixed numbers, not read from the host, so a farm refuses or accepts the same
//! jobs on every machine. The estimate covers the inputs too ([`Budget`]): the loaders count
//! what a scene or map will hold from its headers (instancing, texture and map sizes) and the
//! budget refuses it before anything large is read or decoded. Within the budget, the system is
//! asked for the whole estimate once, so a machine that cannot give it ends the run with an
//! error ([`NoMemory`], exit code 1) rather than an abort halfway through.

use std::fmt;
use std::io::Read;
use std::path::Path;

use crate::bail_input;
use crate::error::{Result, input_error};

/// Largest width or height.
pub const MAX_DIM: u32 = 16384;
/// Largest frame, in pixels.
pub const MAX_PIXELS: u64 = 64 << 20;
/// Most lights (visibility bitsets and per-pixel work grow with it).
pub const MAX_LIGHTS: usize = 4096;
/// Most frames in one animation.
pub const MAX_FRAMES: usize = 1_000_000;
/// Largest input file (scene, buffer, image, map, spec, lights JSON): 2 GB.
pub const MAX_FILE_BYTES: u64 = 2_000_000_000;
/// Most triangles in a scene (the BVH and per-triangle data take ~100 bytes each).
pub const MAX_TRIANGLES: usize = 1 << 26;
/// Most vertices in a scene.
pub const MAX_VERTICES: usize = 1 << 27;
/// Largest texture, in texels (12 bytes each once decoded, about 16 with its mip pyramid).
pub const MAX_TEXTURE_TEXELS: u64 = 1 << 26;
/// The memory a render may be expected to need: 16 GB.
pub const MAX_MEMORY_BYTES: u64 = 16_000_000_000;

/// Why `n` lights cannot be asked for, if they cannot.
pub fn lights_problem(n: usize) -> Option<String> {
    if n == 0 {
        Some("zero lights: the environment must be sampled into at least 1 light".into())
    } else if n > MAX_LIGHTS {
        Some(format!(
            "{n} lights requested; at most {MAX_LIGHTS} are allowed"
        ))
    } else {
        None
    }
}

/// Refuses a file larger than [`MAX_FILE_BYTES`], or one that is not a regular file (a device
/// such as `/dev/zero` reads forever, a FIFO blocks), before it is read. A missing file passes:
/// the reader that follows reports it in its own words.
pub fn check_file_size(path: &Path, what: &str) -> Result<()> {
    if let Ok(m) = std::fs::metadata(path) {
        if let Some(kind) = not_regular(&m) {
            bail_input!(path, "{what} is {kind}, not a regular file");
        }
        if m.len() > MAX_FILE_BYTES {
            bail_input!(
                path,
                "{what} is {} bytes; at most {MAX_FILE_BYTES} ({}) are read",
                m.len(),
                human_bytes(MAX_FILE_BYTES)
            );
        }
    }
    Ok(())
}

/// What a file that is not a regular file is, for messages; `None` for a regular file.
fn not_regular(m: &std::fs::Metadata) -> Option<&'static str> {
    let t = m.file_type();
    if t.is_file() {
        None
    } else if t.is_dir() {
        Some("a folder")
    } else {
        Some(special_kind(&t))
    }
}

/// A file that is neither a regular file nor a folder, as Unix tells them apart.
#[cfg(unix)]
fn special_kind(t: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if t.is_fifo() {
        "a FIFO"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "not a file"
    }
}

/// A file that is neither a regular file nor a folder: Windows metadata says no more of a
/// device (`NUL`, `CON`) or a pipe.
#[cfg(not(unix))]
fn special_kind(_: &std::fs::FileType) -> &'static str {
    "not a file"
}

/// Why [`read_regular`] read nothing.
#[derive(Debug)]
pub enum ReadError {
    /// A device, FIFO, socket or folder: never opened.
    NotRegular(&'static str),
    /// Larger than [`MAX_FILE_BYTES`].
    TooLarge(u64),
    /// The system's error (missing file, permission, I/O).
    Io(std::io::Error),
    /// The system refused the buffer for the file's bytes.
    NoMemory(NoMemory),
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReadError::NotRegular(kind) => write!(f, "{kind}, not a regular file"),
            ReadError::TooLarge(n) => write!(
                f,
                "{n} bytes; at most {MAX_FILE_BYTES} ({}) are read",
                human_bytes(MAX_FILE_BYTES)
            ),
            ReadError::Io(e) => write!(f, "{e}"),
            ReadError::NoMemory(e) => write!(f, "{e}"),
        }
    }
}

impl ReadError {
    /// The error for a file named `path` that was read as `what` (`scene file`, `buffer 0`):
    /// an input error naming both, but for a refused allocation, which is the machine's.
    pub fn into_error(self, path: &Path, what: &str) -> anyhow::Error {
        match self {
            ReadError::NoMemory(e) => {
                anyhow::Error::new(e).context(format!("{}: reading {what}", path.display()))
            }
            ReadError::Io(e) => input_error(path, format!("cannot read {what}: {e}")),
            e => input_error(path, format!("{what} is {e}")),
        }
    }
}

/// Reads a regular file whole, or its first `limit` bytes. The file is checked before it is
/// opened (a device or a FIFO would read forever or block, and is refused) and again once
/// open; the read is bounded by the size it had then, so a file that grows meanwhile cannot
/// make it run on, and its buffer is asked of the system first (a refusal is an error).
pub fn read_regular(path: &Path, limit: u64) -> std::result::Result<Vec<u8>, ReadError> {
    let check = |m: &std::fs::Metadata| match not_regular(m) {
        Some(kind) => Err(ReadError::NotRegular(kind)),
        None if m.len() > MAX_FILE_BYTES => Err(ReadError::TooLarge(m.len())),
        None => Ok(m.len()),
    };
    check(&std::fs::metadata(path).map_err(ReadError::Io)?)?;
    let file = std::fs::File::open(path).map_err(ReadError::Io)?;
    let len = check(&file.metadata().map_err(ReadError::Io)?)?.min(limit);
    let mut bytes = try_vec(len as usize, "a file's bytes").map_err(ReadError::NoMemory)?;
    file.take(len)
        .read_to_end(&mut bytes)
        .map_err(ReadError::Io)?;
    Ok(bytes)
}

/// The system refused memory: the machine's limit, not the input's fault (exit code 1). The
/// message gives what was asked and what for.
#[derive(Debug, Clone)]
pub struct NoMemory {
    pub bytes: u128,
    /// What the memory was for: `a file's bytes`, or the estimate's breakdown.
    pub what: String,
}

impl fmt::Display for NoMemory {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the system refused {} of memory for {}",
            human_bytes_u128(self.bytes),
            self.what
        )
    }
}

impl std::error::Error for NoMemory {}

/// An empty vector with room for `n` elements, or [`NoMemory`] if the system refuses it.
pub fn try_vec<T>(n: usize, what: &str) -> std::result::Result<Vec<T>, NoMemory> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| NoMemory {
        bytes: n as u128 * size_of::<T>() as u128,
        what: what.to_string(),
    })?;
    Ok(v)
}

/// `n` zero bytes, or [`NoMemory`]. Unlike `try_vec` then `resize`, the pages are not written:
/// a decoder that stops early (a truncated file) has touched only what it wrote.
pub fn try_zeroed(n: usize, what: &str) -> std::result::Result<Vec<u8>, NoMemory> {
    if n == 0 {
        return Ok(Vec::new());
    }
    let refused = || NoMemory {
        bytes: n as u128,
        what: what.to_string(),
    };
    let layout = std::alloc::Layout::array::<u8>(n).map_err(|_| refused())?;
    // SAFETY: `layout` has a non-zero size; a null pointer is the allocator's refusal. A
    // non-null one points to `n` zeroed bytes allocated by the global allocator with the layout
    // of a `Vec<u8>` of capacity `n`, which is what `from_raw_parts` needs, and zero is a valid
    // `u8`.
    unsafe {
        let p = std::alloc::alloc_zeroed(layout);
        if p.is_null() {
            return Err(refused());
        }
        Ok(Vec::from_raw_parts(p, n, n))
    }
}

/// What a render holds in memory, as far as it depends on the request.
#[derive(Clone, Copy, Debug)]
pub struct Request {
    pub width: u32,
    pub height: u32,
    pub lights: usize,
    /// Tile side (0: the whole frame is one tile).
    pub tile: u32,
    /// Worker threads (0: one per core).
    pub threads: usize,
    pub validate: bool,
    /// Samples per pixel (a square): the tile state is per sample.
    pub spp: u32,
}

/// Films alive at once: [`FRAMES_IN_FLIGHT`] rendering, and [`WRITES_IN_FLIGHT`] being
/// written (no frame waits in a queue: a finished frame goes to a free writer, its driver
/// waiting while none is), each counted twice: a frame being written holds its film and
/// about as much again in its encoder's copies (the EXR's channels, the preview's pixels,
/// the encoded files).
const FRAMES_ALIVE: u64 = (FRAMES_IN_FLIGHT + 2 * WRITES_IN_FLIGHT) as u64;
/// The widest halo a tile reads beyond its edges (the scanline block of 64, the grid's h0 ≤ 64).
const HALO: u64 = 64;

/// An upper estimate of the bytes a render needs beyond its inputs: the films of the frames
/// alive, each worker's per-sample tile state over the tile and its halo (surface, counts and
/// four light bitsets: above, visible, traced, and the shared lattice or blockers; the tile and
/// the halo are k times wider in samples at k × k samples per pixel), and the per-light tables. Computed in u128 so absurd requests do not overflow.
pub fn estimate_bytes(r: &Request) -> u128 {
    let (w, h) = (u128::from(r.width), u128::from(r.height));
    let pixels = w * h;
    let film_per_pixel: u128 = if r.validate { 36 } else { 20 } + if r.spp > 1 { 4 } else { 0 };
    let k = u128::from(r.spp.max(1)).isqrt();
    let samples = pixels * k * k;
    let films = pixels * film_per_pixel * u128::from(FRAMES_ALIVE);
    let words = (r.lights as u128).div_ceil(64);
    let state_per_pixel = 64 + 4 * words * 8;
    let threads = u128::from(worker_threads(r.threads));
    let tile_samples = if r.tile == 0 {
        // One tile: the whole frame on one thread.
        samples
    } else {
        let side = (u128::from(r.tile) + 2 * u128::from(HALO)) * k;
        (side * side).min(samples) * threads
    };
    let per_light = r.lights as u128 * 256;
    films + tile_samples * state_per_pixel + per_light
}

/// Worker threads of a render asking for `threads` (0: one per core).
fn worker_threads(threads: usize) -> u64 {
    if threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get()) as u64
    } else {
        threads as u64
    }
}

/// Refuses a request whose memory estimate exceeds [`MAX_MEMORY_BYTES`]; the message gives the
/// estimate and what drives it.
pub fn check_memory(source: impl AsRef<Path>, r: &Request) -> Result<()> {
    let need = estimate_bytes(r);
    if need > u128::from(MAX_MEMORY_BYTES) {
        bail_input!(
            source,
            "{}x{} at {} spp and {} lights would need about {} of memory (more than the {} allowed); use fewer pixels, samples or lights, or smaller tiles",
            r.width,
            r.height,
            r.spp,
            r.lights,
            human_bytes_u128(need),
            human_bytes(MAX_MEMORY_BYTES)
        );
    }
    Ok(())
}

/// Frames rendered at once (the coordinator's two chains in flight): with a spinning scene,
/// each holds its own posed copy of the scene and its BVH.
pub const FRAMES_IN_FLIGHT: usize = 2;

/// Frames written at once (the coordinator's writer threads, each encoding one frame on the
/// worker pool): several, so that writing keeps up with rendering on many cores, where a
/// frame renders in less time than one frame's PNG compression, which is one stream.
pub const WRITES_IN_FLIGHT: usize = 3;

/// Bytes per loaded vertex: position and normal (12 each), texture coordinates (8).
const SCENE_VERTEX: u128 = 32;
/// Bytes per vertex a file that animates, skins or morphs keeps for posing (`scene::rig`):
/// its position, normal and tangent in its mesh's space (40), eight joints and weights (48),
/// and one morph target's three displacements (36), rounded up.
pub const RIG_VERTEX: u64 = 128;
/// Bytes per loaded triangle: three indices and a material.
const SCENE_TRIANGLE: u128 = 16;
/// Bytes per triangle while a BVH is built, its triangle soup and the build's own arrays
/// included. Address space, not resident memory: the builder reserves room it may not touch
/// (its wide nodes, one per triangle), which still counts against an address-space limit or a
/// strict overcommit. 333 measured over 4.2 M triangles (271 resident), rounded up.
const BVH_TRIANGLE: u128 = 400;
/// Bytes per vertex while one primitive is read: its attributes as f64 and as f32, world
/// positions, smoothed and world normals (156).
const READ_VERTEX: u128 = 160;
/// Bytes per index while one primitive is read: as f64 and u32, and the triangles assembled
/// and kept (20).
const READ_INDEX: u128 = 24;
/// Bytes per texel of a decoded texture: linear RGB f32 and its mip pyramid (a third more).
const TEXTURE_TEXEL: u128 = 16;
/// Bytes per texel of a texture's alpha, when the image has an alpha channel: f32 and its mip
/// pyramid (a third more, rounded up).
const TEXTURE_ALPHA_TEXEL: u128 = 6;
/// Bytes per texel while a texture is decoded, beyond what it keeps: the decoder's pixels (up
/// to 16 for RGBA f32) and the rows of the pyramid's first halving (6).
const TEXTURE_DECODE_TEXEL: u128 = 24;
/// Bytes each thread of a render reserves: its stack, and the allocator's arena for it (glibc
/// reserves 64 MB of address space per arena).
const THREAD_BYTES: u128 = 72_000_000;
/// Threads beside the workers and the encoders (as many as the workers): the main thread,
/// the writers and a driver per frame in flight.
const OTHER_THREADS: u128 = 1 + (WRITES_IN_FLIGHT + FRAMES_IN_FLIGHT) as u128;
/// The process before it loads anything: the program and its libraries mapped, the main
/// thread's stack, the allocator's first heap (42 MB of address space measured), rounded up.
const PROCESS_BYTES: u128 = 64_000_000;
/// Bytes per texel of a map: linear RGB f32.
const MAP_TEXEL: u128 = 12;
/// Bytes per map texel beyond its own while it is decoded (the decoder's RGB f32) or reduced
/// to lights (luminance, solid angles, strata and owners: 20 measured with SIS).
const MAP_WORK_TEXEL: u128 = 24;

/// An upper estimate of the bytes a map of `texels` takes: its own texels, and its decoding or
/// reduction to lights beside them.
pub fn map_bytes(texels: u64) -> u128 {
    u128::from(texels) * (MAP_TEXEL + MAP_WORK_TEXEL)
}

/// What a scene file will hold once loaded, counted from its headers before its buffers are
/// read or its images decoded.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneSize {
    /// Vertices of every primitive instance: a mesh used by n nodes counts n times.
    pub vertices: u64,
    /// Triangles of every primitive instance, at most (degenerate ones are dropped later).
    pub triangles: u64,
    /// Meshes placed by nodes.
    pub instances: u64,
    /// The largest primitive instance read at once: vertices, and indices (its vertex count
    /// without an index accessor).
    pub largest_vertices: u64,
    pub largest_indices: u64,
    /// Bytes held while loading: the file, its buffers, encoded images.
    pub file_bytes: u64,
    /// Distinct images the materials use (each decoded once), their texels, and the largest.
    pub textures: u64,
    pub texels: u64,
    pub largest_texels: u64,
    /// Bytes of the optional vertex arrays (second texture coordinates, tangents, colours)
    /// over every vertex, when any primitive has them (then every vertex gets them).
    pub extra_vertex_bytes: u64,
    /// Texels of the decoded textures whose image has an alpha channel (kept beside the colour).
    pub alpha_texels: u64,
    /// Lights the file places (`KHR_lights_punctual`): each a bit of every sample's bitsets
    /// when they join the map's.
    pub lights: u64,
}

/// An upper estimate of a render's memory, by what holds it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Estimate {
    /// The loaded scene's arrays, and the posed copies a spin keeps of them.
    pub scene: u128,
    /// The BVHs alive at once.
    pub bvh: u128,
    pub textures: u128,
    pub map: u128,
    /// Films, per-worker tile state and light tables ([`estimate_bytes`]), the threads'
    /// stacks and allocator arenas, and the program itself.
    pub render: u128,
    /// Held only while loading: files and buffers, one primitive's arrays, one image's or
    /// the map's decoding, the map's reduction to lights (the largest of these).
    pub loading: u128,
}

impl Estimate {
    pub fn total(&self) -> u128 {
        self.scene + self.bvh + self.textures + self.map + self.render + self.loading
    }
}

/// The inputs counted so far against the memory budget of one render.
///
/// Loaders report what their file will hold as soon as its headers say
/// ([`Budget::scene`], [`Budget::map`]); each report checks the whole estimate against the
/// limit ([`MAX_MEMORY_BYTES`] unless set) and then asks the system for it once, so that a
/// render is refused before its large buffers exist, not halfway through them.
#[derive(Clone, Debug)]
pub struct Budget {
    limit: u64,
    render: u128,
    /// The render's request, if any: the scene's own lights are added to its lights.
    request: Option<Request>,
    /// Posed copies of the scene alive at once (a spin: one per frame in flight).
    posed: u64,
    /// BVHs alive at once: the still scene's, or each posed copy's.
    accels: u64,
    scene: SceneSize,
    map_texels: u64,
    map_file: u64,
    /// Bytes of the estimate the process holds before it loads anything (not asked for again).
    running: u128,
    /// The part of `render` that is the threads' own (stacks, per-thread tables), and their
    /// number: what the message blames when they are most of the estimate.
    thread_bytes: u128,
    threads: u128,
}

impl Default for Budget {
    /// Inputs alone: no frames, one BVH, no posed copy.
    fn default() -> Budget {
        Budget {
            limit: MAX_MEMORY_BYTES,
            render: 0,
            request: None,
            posed: 0,
            accels: 1,
            scene: SceneSize::default(),
            map_texels: 0,
            map_file: 0,
            running: 0,
            thread_bytes: 0,
            threads: 0,
        }
    }
}

impl Budget {
    /// A render's budget: its request, and `posed` frames whose scene is posed (and its BVH
    /// built) at once — 0 when the scene does not move, and one BVH serves every frame.
    pub fn new(request: &Request, posed: usize) -> Budget {
        // The workers, and as many encoders.
        let threads = 2 * u128::from(worker_threads(request.threads)) + OTHER_THREADS;
        Budget {
            render: estimate_bytes(request) + threads * THREAD_BYTES + PROCESS_BYTES,
            thread_bytes: threads * THREAD_BYTES,
            threads,
            request: Some(*request),
            running: PROCESS_BYTES,
            posed: posed as u64,
            accels: (posed as u64).max(1),
            ..Budget::default()
        }
    }

    /// The scene file animates its geometry: a render poses it every frame (whatever the
    /// motion), so each frame in flight holds a posed copy of the scene and its BVH, as a
    /// spin's frames do, and the run keeps one more BVH: the still triangles' hierarchy that
    /// every pose shares (`accel::Split`; counted whole, as if no triangle moved). Counted
    /// when the file is found to have animations, before its buffers are read; a budget with
    /// no render (a bare load) poses nothing.
    pub fn animated(&mut self) {
        if self.request.is_some() {
            self.posed = self.posed.max(FRAMES_IN_FLIGHT as u64);
            self.accels = self.accels.max(self.posed + 1);
        }
    }

    /// The same with another limit (tests, and the fuzz targets' smaller one).
    pub fn with_limit(mut self, bytes: u64) -> Budget {
        self.limit = bytes;
        self
    }

    /// The estimate of what has been counted so far.
    pub fn estimate(&self) -> Estimate {
        let s = &self.scene;
        let arrays = u128::from(s.vertices) * SCENE_VERTEX
            + u128::from(s.extra_vertex_bytes)
            + u128::from(s.triangles) * SCENE_TRIANGLE;
        let read = u128::from(s.largest_vertices) * READ_VERTEX
            + u128::from(s.largest_indices) * READ_INDEX;
        let decode = u128::from(s.largest_texels) * TEXTURE_DECODE_TEXEL;
        let scene_loading = u128::from(s.file_bytes) + read.max(decode);
        let map_loading = u128::from(self.map_file) + u128::from(self.map_texels) * MAP_WORK_TEXEL;
        Estimate {
            scene: arrays * (1 + u128::from(self.posed)),
            bvh: u128::from(s.triangles) * BVH_TRIANGLE * u128::from(self.accels),
            textures: u128::from(s.texels) * TEXTURE_TEXEL
                + u128::from(s.alpha_texels) * TEXTURE_ALPHA_TEXEL,
            map: u128::from(self.map_texels) * MAP_TEXEL,
            render: self.render + self.scene_lights_bytes(),
            loading: scene_loading.max(map_loading),
        }
    }

    /// What the scene file's lights add to the render's own estimate: their bits in every
    /// sample's bitsets and their per-light tables.
    fn scene_lights_bytes(&self) -> u128 {
        match self.request {
            Some(r) if self.scene.lights > 0 => {
                let more = Request {
                    lights: r.lights.saturating_add(self.scene.lights as usize),
                    ..r
                };
                estimate_bytes(&more) - estimate_bytes(&r)
            }
            _ => 0,
        }
    }

    /// Counts the scene file `source` as `size` (replacing what it was counted as before) and
    /// checks the estimate; `held` bytes of it are already allocated (read files, buffers).
    pub fn scene(&mut self, source: &Path, size: SceneSize, held: u64) -> Result<()> {
        self.scene = size;
        self.check(source, held)
    }

    /// Counts a map of `texels` whose file is `file_bytes` long without checking: the scene,
    /// loaded first, is then checked with the map it will be lit by.
    pub fn expect_map(&mut self, texels: u64, file_bytes: u64) {
        self.map_texels = texels;
        self.map_file = file_bytes;
    }

    /// Counts the map `source` (`texels`, its file `file_bytes` long and already read) and
    /// checks the estimate.
    pub fn map(&mut self, source: &Path, texels: u64, file_bytes: u64) -> Result<()> {
        self.expect_map(texels, file_bytes);
        self.check(source, file_bytes)
    }

    /// Refuses the estimate above the limit (an input error naming `source` and the estimate),
    /// then asks the system for it, less the `held` bytes already allocated, and gives it back:
    /// a machine that cannot give it refuses now ([`NoMemory`]), before any large buffer.
    fn check(&self, source: &Path, held: u64) -> Result<()> {
        let e = self.estimate();
        let total = e.total();
        if total > u128::from(self.limit) {
            // The threads' own memory is most of it: blame them, not the pixels.
            let advice = if 2 * self.thread_bytes > total {
                format!(
                    "{} threads (the workers and as many encoders) take {} of it, {} each: \
                     use fewer threads (--threads)",
                    self.threads,
                    human_bytes_u128(self.thread_bytes),
                    human_bytes_u128(THREAD_BYTES)
                )
            } else {
                "use fewer triangles or instances, smaller textures or maps, or fewer pixels, \
                 samples or lights"
                    .to_string()
            };
            bail_input!(
                source,
                "the render would need about {} of memory, more than the {} allowed ({}); {advice}",
                human_bytes_u128(total),
                human_bytes(self.limit),
                self.breakdown(&e)
            );
        }
        let ask = total.saturating_sub(u128::from(held) + self.running);
        let refused = || {
            let e = NoMemory {
                bytes: ask,
                what: format!("the render ({})", self.breakdown(&e)),
            };
            anyhow::Error::new(e).context(source.display().to_string())
        };
        let n = usize::try_from(ask).map_err(|_| refused())?;
        // Reserved and freed at once: untouched pages cost nothing, but an address-space limit
        // or the kernel's overcommit check refuses the whole at once, here.
        let probe: Vec<u8> = try_vec(n, "").map_err(|_| refused())?;
        drop(probe);
        Ok(())
    }

    /// `scene 1.1 GB (33.5 M triangles, 256 mesh instances), BVH 10.1 GB, …`: what drives the
    /// estimate, for messages; parts that are zero are left out.
    fn breakdown(&self, e: &Estimate) -> String {
        let s = &self.scene;
        let mut parts = Vec::new();
        if e.scene > 0 {
            let posed = if self.posed > 0 {
                format!(
                    ", and a posed copy for each of {} frames at once",
                    self.posed
                )
            } else {
                String::new()
            };
            let instances = match s.instances {
                1 => "1 mesh instance".to_string(),
                n => format!("{n} mesh instances"),
            };
            parts.push(format!(
                "scene {} ({} triangles in {instances}{posed})",
                human_bytes_u128(e.scene),
                human_count(s.triangles),
            ));
            parts.push(format!("BVH {}", human_bytes_u128(e.bvh)));
        }
        if e.textures > 0 {
            parts.push(format!(
                "textures {} ({} images, {} texels)",
                human_bytes_u128(e.textures),
                s.textures,
                human_count(s.texels)
            ));
        }
        if e.map > 0 {
            parts.push(format!(
                "map {} ({} texels)",
                human_bytes_u128(e.map),
                human_count(self.map_texels)
            ));
        }
        parts.push(format!("frames and threads {}", human_bytes_u128(e.render)));
        parts.push(format!("loading {}", human_bytes_u128(e.loading)));
        parts.join(", ")
    }
}

/// `33.5 M`, `12.0 k`, `512`: counts for messages.
fn human_count(n: u64) -> String {
    match n {
        0..1_000 => n.to_string(),
        1_000..1_000_000 => format!("{:.1} k", n as f64 / 1e3),
        1_000_000..1_000_000_000 => format!("{:.1} M", n as f64 / 1e6),
        _ => format!("{:.1} G", n as f64 / 1e9),
    }
}

/// `1.5 GB`, `12 MB`: decimal units, for messages.
pub fn human_bytes(n: u64) -> String {
    human_bytes_u128(u128::from(n))
}

pub fn human_bytes_u128(n: u128) -> String {
    const UNITS: [&str; 7] = ["bytes", "kB", "MB", "GB", "TB", "PB", "EB"];
    let mut v = n as f64;
    let mut u = 0;
    while v >= 1000.0 && u + 1 < UNITS.len() {
        v /= 1000.0;
        u += 1;
    }
    if u == 0 {
        format!("{n} bytes")
    } else {
        format!("{v:.1} {}", UNITS[u])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn req(width: u32, height: u32, lights: usize) -> Request {
        Request {
            width,
            height,
            lights,
            tile: 64,
            threads: 2,
            validate: false,
            spp: 1,
        }
    }

    #[test]
    fn ordinary_renders_fit_and_absurd_ones_do_not() {
        // The paper's frame: well under the budget (BENCHMARKS.md measures ~120 MB in all).
        assert!(estimate_bytes(&req(640, 480, 400)) < 100_000_000);
        assert!(check_memory("a.toml", &req(640, 480, 400)).is_ok());
        assert!(check_memory("a.toml", &req(100_000, 100_000, 200)).is_err());
        assert!(check_memory("a.toml", &req(640, 480, 1_000_000)).is_err());
        let mut whole = req(16384, 16384, 4096);
        whole.tile = 0;
        let e = check_memory("a.toml", &whole).unwrap_err().to_string();
        assert!(e.contains("would need about") && e.contains("GB"), "{e}");
    }

    #[test]
    fn samples_per_pixel_grow_the_tile_state_not_the_film() {
        let one = req(1920, 1080, 400);
        let sixteen = Request { spp: 16, ..one };
        let (a, b) = (estimate_bytes(&one), estimate_bytes(&sixteen));
        // Tiles and halos 4× wider in samples: the per-sample state grows 16×; the films
        // (every frame alive) only by the coverage channel.
        let alive = u128::from(FRAMES_ALIVE);
        let (films, per_light) = (1920 * 1080 * 20 * alive, 400 * 256);
        let coverage = 1920 * 1080 * 4 * alive;
        assert_eq!(
            b - films - coverage - per_light,
            16 * (a - films - per_light),
            "{a} → {b}"
        );
        // 1920×1080 at 16 spp and 400 lights fits well within the 2 GB the issue allows.
        assert!(b < 2_000_000_000, "{b}");
        // A whole-frame tile at 64 spp of a large frame is refused, naming the samples.
        let whole = Request {
            width: 8192,
            height: 8192,
            spp: 64,
            tile: 0,
            ..one
        };
        let e = check_memory("a.toml", &whole).unwrap_err().to_string();
        assert!(e.contains("64 spp"), "{e}");
    }

    /// A 131,072-triangle grid mesh (66,049 vertices) placed by `instances` nodes.
    fn instanced(instances: u64) -> SceneSize {
        SceneSize {
            vertices: 66_049 * instances,
            triangles: 131_072 * instances,
            instances,
            largest_vertices: 66_049,
            largest_indices: 393_216,
            file_bytes: 2_400_000,
            ..SceneSize::default()
        }
    }

    #[test]
    fn every_instance_counts_and_a_spin_counts_its_posed_copies() {
        let request = req(640, 480, 200);
        let (one, many) = (instanced(1), instanced(256));
        let still = |size: SceneSize| {
            let mut b = Budget::new(&request, 0);
            b.scene = size;
            b.estimate()
        };
        let (a, b) = (still(one), still(many));
        assert_eq!(b.scene, 256 * a.scene);
        assert_eq!(b.bvh, 256 * a.bvh);
        assert_eq!(a.render, b.render);
        // The bomb orbited: one BVH, 15 GB in all, inside the 16 GB.
        assert!((14e9..16e9).contains(&(b.total() as f64)), "{b:?}");
        // Spun, each of the two frames in flight poses the scene and builds its BVH.
        let mut spin = Budget::new(&request, 2);
        spin.scene = many;
        let s = spin.estimate();
        assert_eq!((s.scene, s.bvh), (3 * b.scene, 2 * b.bvh));
        assert!(s.total() > u128::from(MAX_MEMORY_BYTES), "{s:?}");
    }

    #[test]
    fn an_animated_file_counts_a_posed_copy_per_frame_in_flight() {
        let request = req(640, 480, 200);
        let mut still = Budget::new(&request, 0);
        still.scene = instanced(4);
        let mut animated = still.clone();
        animated.animated();
        let (a, b) = (still.estimate(), animated.estimate());
        let copies = FRAMES_IN_FLIGHT as u128;
        // A BVH per frame in flight, and the split one of the first pose that they share.
        assert_eq!(
            (b.scene, b.bvh),
            ((1 + copies) * a.scene, (copies + 1) * a.bvh)
        );
        // A spin already posing as many frames adds only that shared BVH.
        let mut spun = Budget::new(&request, FRAMES_IN_FLIGHT);
        spun.scene = instanced(4);
        let before = spun.estimate();
        spun.animated();
        let after = spun.estimate();
        assert_eq!((after.scene, after.bvh), (before.scene, before.bvh + a.bvh));
        // A bare load renders no frame.
        let mut bare = Budget::default();
        bare.animated();
        assert_eq!((bare.posed, bare.accels), (0, 1));
    }

    #[test]
    fn textures_and_maps_count_their_texels_and_their_decoding() {
        let mut b = Budget {
            scene: SceneSize {
                textures: 2,
                texels: 3 << 20,
                largest_texels: 2 << 20,
                ..SceneSize::default()
            },
            ..Budget::default()
        };
        b.expect_map(8 << 20, 1000);
        let e = b.estimate();
        assert_eq!(e.textures, (3 << 20) * TEXTURE_TEXEL);
        // An image with an alpha channel counts its alpha too.
        let mut cut = b.clone();
        cut.scene.alpha_texels = 1 << 20;
        let with_alpha = cut.estimate().textures;
        assert_eq!(with_alpha, e.textures + (1 << 20) * TEXTURE_ALPHA_TEXEL);
        // The optional vertex arrays (colours, tangents, a second UV set) count their bytes.
        let mut extra = b.clone();
        extra.scene.vertices = 1000;
        let without = extra.estimate().scene;
        extra.scene.extra_vertex_bytes = 1000 * 16;
        assert_eq!(extra.estimate().scene, without + 1000 * 16);
        assert_eq!(e.map, (8 << 20) * MAP_TEXEL);
        // Loading: the larger of decoding the largest image and decoding or sampling the map.
        let image = (2 << 20) * TEXTURE_DECODE_TEXEL;
        let map = 1000 + (8 << 20) * MAP_WORK_TEXEL;
        assert_eq!(e.loading, image.max(map));
        assert_eq!(map_bytes(8 << 20), (8 << 20) * (MAP_TEXEL + MAP_WORK_TEXEL));
    }

    #[test]
    fn over_the_limit_an_input_error_names_the_file_and_the_estimate() {
        let mut b = Budget::new(&req(640, 480, 200), 2);
        let e = b
            .scene(Path::new("bomb.gltf"), instanced(256), 0)
            .unwrap_err();
        assert_eq!(crate::error::exit_code(&e), crate::error::exit::BAD_INPUT);
        let msg = e.to_string();
        for needle in [
            "bomb.gltf: the render would need about",
            "more than the 16.0 GB allowed",
            "33.6 M triangles in 256 mesh instances",
            "a posed copy for each of 2 frames at once",
            "BVH 26.8 GB",
        ] {
            assert!(msg.contains(needle), "{needle:?} not in {msg}");
        }
        // A smaller limit refuses a smaller scene; the default one takes it.
        let small = instanced(4);
        assert!(
            Budget::default()
                .scene(Path::new("a.gltf"), small, 0)
                .is_ok()
        );
        let tight = Budget::default().with_limit(100_000_000);
        assert!(tight.clone().scene(Path::new("a.gltf"), small, 0).is_err());
    }

    #[test]
    fn a_refusal_by_the_system_is_the_machines_error_not_the_inputs() {
        // More than any address space: the system refuses when asked, whatever the budget.
        let mut b = Budget::default().with_limit(u64::MAX);
        let size = SceneSize {
            triangles: 1 << 50,
            instances: 1,
            ..SceneSize::default()
        };
        let e = b.scene(Path::new("vast.gltf"), size, 0).unwrap_err();
        assert_eq!(crate::error::exit_code(&e), crate::error::exit::INTERNAL);
        let msg = format!("{e:#}");
        assert!(msg.starts_with("vast.gltf: the system refused"), "{msg}");
        assert!(msg.contains("of memory for the render (scene"), "{msg}");
        assert!(e.downcast_ref::<NoMemory>().is_some());
    }

    #[test]
    fn only_regular_files_are_read_and_no_more_than_asked() {
        let dir = std::env::temp_dir().join(format!("envshadow-limits-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("ten.bin");
        std::fs::write(&file, b"0123456789").unwrap();
        assert_eq!(read_regular(&file, u64::MAX).unwrap(), b"0123456789");
        assert_eq!(read_regular(&file, 4).unwrap(), b"0123");
        let kind = |p: &Path| match read_regular(p, u64::MAX) {
            Err(ReadError::NotRegular(kind)) => kind,
            other => panic!("{}: {other:?}", p.display()),
        };
        assert_eq!(kind(Path::new("/dev/zero")), "a character device");
        assert_eq!(kind(&dir), "a folder");
        assert!(matches!(
            read_regular(&dir.join("absent"), 1),
            Err(ReadError::Io(_))
        ));
        let e = check_file_size(Path::new("/dev/zero"), "lights file").unwrap_err();
        assert!(
            e.to_string()
                .contains("/dev/zero: lights file is a character device, not a regular file"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn zeroed_buffers_are_zero_and_a_refusal_is_an_error() {
        let v = try_zeroed(1 << 20, "test").unwrap();
        assert!(v.len() == 1 << 20 && v.iter().all(|&b| b == 0));
        assert!(try_zeroed(0, "test").unwrap().is_empty());
        let e = try_zeroed(usize::MAX, "a test's buffer").unwrap_err();
        assert!(e.to_string().contains("for a test's buffer"), "{e}");
        assert!(try_vec::<u64>(usize::MAX / 4, "x").is_err());
    }

    #[test]
    fn human_units() {
        assert_eq!(human_bytes(12), "12 bytes");
        assert_eq!(human_bytes(1_500_000_000), "1.5 GB");
        assert_eq!(human_bytes(2 << 30), "2.1 GB");
    }
}
