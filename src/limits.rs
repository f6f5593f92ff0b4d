//! Limits checked before work starts, so a hostile or mistaken input is refused with a message
//! instead of exhausting the host: frame size, light count, frames, input file sizes, triangles,
//! and an estimate of the memory a render would need.
//!
//! The limits are fixed numbers, not read from the host, so a farm refuses or accepts the same
//! jobs on every machine.

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
    use std::os::unix::fs::FileTypeExt;
    let t = m.file_type();
    if t.is_file() {
        None
    } else if t.is_dir() {
        Some("a folder")
    } else if t.is_fifo() {
        Some("a FIFO")
    } else if t.is_char_device() {
        Some("a character device")
    } else if t.is_block_device() {
        Some("a block device")
    } else if t.is_socket() {
        Some("a socket")
    } else {
        Some("not a file")
    }
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

/// Frames alive at once: two rendering, two waiting in the writer's channel, one being written.
const FRAMES_ALIVE: u64 = 5;
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
    let threads = if r.threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get()) as u128
    } else {
        r.threads as u128
    };
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
        // (five frames alive) only by the coverage channel.
        let (films, per_light) = (1920 * 1080 * 20 * 5, 400 * 256);
        let coverage = 1920 * 1080 * 4 * 5;
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
