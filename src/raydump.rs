//! Shadow-ray dumps: a frame's triangles and the shadow rays a method traced, in one binary file,
//! so another tracer (benches/embree) can trace exactly the same rays as ours.
//!
//! The rays come from the recorder here ([`set_recording`], [`take_recorded`]): while it is on,
//! the frame's shadow-ray call sites (the frame context's `trace`, `trace_packet` and
//! `trace_blocker`) note every ray they hand to [`Accel`]; `envshadow bench` records one render
//! of a frame that way, then replays the rays alone. [`Accel`] itself knows nothing of it: one
//! set of queries, which frames and replays both call.
//!
//! Layout, little-endian: the 8 bytes `ESRAYS1\0`; u32 triangle count; u32 chunk size (rays
//! per work item when traced over threads, [`REPLAY_CHUNK`]); u64 ray count; per
//! triangle 9 f32 (three vertices); per ray 6 f32 (origin, unit direction; t in (0, ∞)).

use std::cell::RefCell;
use std::fs;
use std::io::{BufWriter, Read, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Context;
use glam::Vec3;

use crate::accel::{Accel, ShadowRay};
use crate::error::{Result, input_error};

const MAGIC: &[u8; 8] = b"ESRAYS1\0";

/// Rays per work item when a recorded ray list is traced again over a pool: small enough to
/// balance two threads, large enough that scheduling is noise. benches/embree uses the same.
pub const REPLAY_CHUNK: usize = 4096;

/// Whether shadow queries are being recorded (`envshadow bench --split`/`--dump-rays`). Off in
/// renders: the hook costs one relaxed load and a predictable branch per query.
static RECORDING: AtomicBool = AtomicBool::new(false);

thread_local! {
    /// The shadow rays this thread traced while recording, in order.
    static RECORDED: RefCell<Vec<ShadowRay>> = const { RefCell::new(Vec::new()) };
}

/// Notes the shadow ray from `origin` along `dir` when recording is on.
#[inline(always)]
pub fn record(origin: Vec3, dir: Vec3) {
    if RECORDING.load(Ordering::Relaxed) {
        RECORDED.with_borrow_mut(|v| v.push(ShadowRay { origin, dir }));
    }
}

/// Notes a packet of shadow rays from `origin` along `dirs`, in order, when recording is on.
#[inline(always)]
pub fn record_packet(origin: Vec3, dirs: &[Vec3]) {
    if RECORDING.load(Ordering::Relaxed) {
        RECORDED.with_borrow_mut(|v| v.extend(dirs.iter().map(|&dir| ShadowRay { origin, dir })));
    }
}

/// Starts or stops recording every shadow query (occlusion and blocker) on every thread.
pub fn set_recording(on: bool) {
    RECORDING.store(on, Ordering::SeqCst);
}

/// Takes the shadow rays the calling thread recorded.
pub fn take_recorded() -> Vec<ShadowRay> {
    RECORDED.with_borrow_mut(std::mem::take)
}

/// Writes the triangles of `accel` and `rays` to `path` (atomically).
pub fn write(path: &Path, accel: &Accel, rays: &[ShadowRay]) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    crate::output::write_atomic_with(path, |tmp| {
        let mut f = BufWriter::new(fs::File::create(tmp)?);
        f.write_all(MAGIC)?;
        f.write_all(&(accel.triangle_count() as u32).to_le_bytes())?;
        f.write_all(&(REPLAY_CHUNK as u32).to_le_bytes())?;
        f.write_all(&(rays.len() as u64).to_le_bytes())?;
        for t in accel.triangles() {
            for v in t {
                for c in v.to_array() {
                    f.write_all(&c.to_le_bytes())?;
                }
            }
        }
        for r in rays {
            for c in r.origin.to_array().into_iter().chain(r.dir.to_array()) {
                f.write_all(&c.to_le_bytes())?;
            }
        }
        f.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        Ok(())
    })
}

/// A dump read back: triangles and rays.
pub struct Dump {
    pub triangles: Vec<[Vec3; 3]>,
    pub rays: Vec<ShadowRay>,
}

/// Reads a dump written by [`write()`]; a malformed file is an input error naming it.
pub fn read(path: &Path) -> Result<Dump> {
    let mut bytes = Vec::new();
    fs::File::open(path)
        .and_then(|mut f| f.read_to_end(&mut bytes))
        .map_err(|e| input_error(path, format!("cannot read: {e}")))?;
    let bad = |what: &str| input_error(path, format!("not a ray dump: {what}"));
    if bytes.len() < 24 || &bytes[..8] != MAGIC {
        return Err(bad("wrong magic"));
    }
    let u32_at = |o: usize| u32::from_le_bytes(bytes[o..o + 4].try_into().unwrap()) as usize;
    let tris = u32_at(8);
    let rays = u64::from_le_bytes(bytes[16..24].try_into().unwrap()) as usize;
    let need = tris
        .checked_mul(36)
        .zip(rays.checked_mul(24))
        .and_then(|(a, b)| a.checked_add(b)?.checked_add(24));
    if need != Some(bytes.len()) {
        return Err(bad("its size does not match its counts"));
    }
    let f = |o: usize| f32::from_le_bytes(bytes[o..o + 4].try_into().unwrap());
    let v = |o: usize| Vec3::new(f(o), f(o + 4), f(o + 8));
    let triangles = (0..tris)
        .map(|i| {
            let o = 24 + 36 * i;
            [v(o), v(o + 12), v(o + 24)]
        })
        .collect();
    let base = 24 + 36 * tris;
    let rays = (0..rays)
        .map(|i| {
            let o = base + 24 * i;
            ShadowRay {
                origin: v(o),
                dir: v(o + 12),
            }
        })
        .collect();
    Ok(Dump { triangles, rays })
}
