//! Temporal coherence across frames (ALGORITHM.md §8 [ours], `--temporal`): the frame-level
//! side. The per-pixel prediction is [`crate::predict::temporal`].
//!
//! - **Carried data.** After a frame is rendered, every pixel's surface point and normal, its
//!   above-horizon and visible lights (and, for a spinning object, the lights at the edge of
//!   its shadow in light space) are kept for the whole frame in a [`Carried`]. The next frame
//!   reads it through a [`Prev`] and drops it when done: at most two carried frames per chain
//!   exist at once, whatever the animation's length.
//! - **Key frames.** Frames `0, K, 2K, …` (K = `keyframe`) are predicted from their own pixels
//!   only and start a new chain; the frames between read their predecessor. Chains are anchored
//!   to absolute frame numbers, so a job that starts inside a chain first renders (without
//!   writing) the frames back to the chain's key frame, and every frame written is the same
//!   whether the animation is rendered as one job or many. It also bounds how far a wrong
//!   prediction can travel in time.
//! - **Determinism.** A frame starts only after its predecessor is complete, so every tile
//!   reads the whole previous frame; a pixel's result is a pure function of the previous frame
//!   and its own frame, and tiles, threads and jobs do not change it.

use glam::{Mat3, Mat4, Vec3};

use crate::anim::{Animation, MotionKind};
use crate::camera::Camera;
use crate::frame::TileWork;
use crate::lights::LightSet;
use crate::predict::{Method, bits};
use crate::tile::Rect;

/// Default key-frame interval for `motion` (docs/temporal.md has the measurements): with a
/// camera orbit the wrong pairs fall along a chain (0.0045 % after one frame, 0.0015 % after
/// 15: bunny, 640×480, 200 lights), so chains are long; with a spinning object they grow
/// (0.034 % after one frame, 0.051 % after four, 0.07 % after eight), so the chain restarts
/// every 4 frames to stay within 0.05 %.
pub fn default_keyframe(motion: MotionKind) -> u32 {
    match motion {
        MotionKind::Spin => 4,
        MotionKind::Orbit | MotionKind::Still => 16,
    }
}

/// Longest allowed key-frame interval.
pub const MAX_KEYFRAME: u32 = 10_000;

/// Checks the temporal settings of an animation; the message names the setting.
pub fn check(anim: &Animation) -> Result<(), String> {
    if !(1..=MAX_KEYFRAME).contains(&anim.keyframe) {
        return Err(format!(
            "keyframe = {}: must be 1 to {MAX_KEYFRAME}",
            anim.keyframe
        ));
    }
    if anim.temporal
        && !matches!(
            anim.method,
            Method::GridNowarpUncertainty | Method::GridWarpUncertainty
        )
    {
        return Err(format!(
            "temporal prediction needs a grid uncertainty method (grid-nowarp-uncertainty or \
             grid-warp-uncertainty), not {}",
            anim.method
        ));
    }
    Ok(())
}

/// Whether `frame` starts a chain (is predicted from its own pixels only).
pub fn is_key(frame: usize, keyframe: u32) -> bool {
    frame % keyframe.max(1) as usize == 0
}

/// One chain of frames rendered in order, each reading its predecessor: the frames and
/// whether each is written (the others are rendered only to warm the chain up).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Chain {
    pub frames: Vec<(usize, bool)>,
}

/// The chains that render the frames of `todo` (sorted). Without temporal prediction every
/// frame is a chain of its own; with it, a chain runs from the key frame at or before its
/// first frame to its last frame, frames not in `todo` rendered but not written.
pub fn chains(todo: &[usize], temporal: bool, keyframe: u32) -> Vec<Chain> {
    if !temporal {
        return todo
            .iter()
            .map(|&f| Chain {
                frames: vec![(f, true)],
            })
            .collect();
    }
    let k = keyframe.max(1) as usize;
    let mut out: Vec<Chain> = Vec::new();
    let mut last_group = usize::MAX;
    for &f in todo {
        let group = f / k;
        if group != last_group {
            out.push(Chain {
                frames: (group * k..f).map(|g| (g, false)).collect(),
            });
            last_group = group;
        }
        let chain = out.last_mut().expect("a chain was just started");
        let next = chain.frames.last().map_or(group * k, |&(g, _)| g + 1);
        chain.frames.extend((next..f).map(|g| (g, false)));
        chain.frames.push((f, true));
    }
    out
}

/// A whole frame's visibility, kept for the next frame: per pixel, row-major over the frame.
pub struct Carried {
    pub frame: usize,
    width: u32,
    height: u32,
    words: usize,
    /// Bitset rows per pixel: above, visible, and with `edges` the light-space shadow edge.
    rows: usize,
    hit: Vec<bool>,
    /// World-space point and normal of the frame it was rendered in.
    p: Vec<Vec3>,
    n: Vec<Vec3>,
    bits: Vec<u64>,
}

/// The carried data of one tile's pixels, to be inserted into its frame's [`Carried`].
pub struct CarryPatch {
    rect: Rect,
    hit: Vec<bool>,
    p: Vec<Vec3>,
    n: Vec<Vec3>,
    bits: Vec<u64>,
}

impl Carried {
    /// Empty carried data for `frame`; `edges` also keeps light-space shadow edges.
    pub fn new(frame: usize, width: u32, height: u32, words: usize, edges: bool) -> Carried {
        let n = width as usize * height as usize;
        let rows = if edges { 3 } else { 2 };
        Carried {
            frame,
            width,
            height,
            words,
            rows,
            hit: vec![false; n],
            p: vec![Vec3::ZERO; n],
            n: vec![Vec3::ZERO; n],
            bits: vec![0; n * rows * words],
        }
    }

    /// Adds one tile's pixels.
    pub fn insert(&mut self, patch: &CarryPatch) {
        let r = patch.rect;
        let (w, rw) = (r.width() as usize, self.rows * self.words);
        for y in r.y0..r.y1 {
            let src = (y - r.y0) as usize * w;
            let dst = y as usize * self.width as usize + r.x0 as usize;
            self.hit[dst..dst + w].copy_from_slice(&patch.hit[src..src + w]);
            self.p[dst..dst + w].copy_from_slice(&patch.p[src..src + w]);
            self.n[dst..dst + w].copy_from_slice(&patch.n[src..src + w]);
            self.bits[dst * rw..(dst + w) * rw]
                .copy_from_slice(&patch.bits[src * rw..(src + w) * rw]);
        }
    }

    /// Word `m` of pixel `q`'s above, visible and edge bitsets (edge 0 when not kept).
    #[inline]
    pub fn word(&self, q: usize, m: usize) -> (u64, u64, u64) {
        let base = q * self.rows * self.words;
        let edge = if self.rows > 2 {
            self.bits[base + 2 * self.words + m]
        } else {
            0
        };
        (self.bits[base + m], self.bits[base + self.words + m], edge)
    }

    /// Whether the light-space shadow edges are kept (a spinning object).
    pub fn has_edges(&self) -> bool {
        self.rows > 2
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.hit.len() * (1 + 24) + self.bits.len() * 8
    }
}

impl CarryPatch {
    /// Records the tile's own pixels from `work` after the tile was rendered. With `edges`
    /// (a spinning object), also the edge lights: those whose visibility differs from an
    /// adjacent above-horizon light's.
    pub fn record(work: &TileWork, lights: &LightSet, edges: bool) -> CarryPatch {
        let t = work.tile;
        let w = work.words;
        let rows = if edges { 3 } else { 2 };
        let n = t.area();
        let mut patch = CarryPatch {
            rect: t,
            hit: Vec::with_capacity(n),
            p: Vec::with_capacity(n),
            n: Vec::with_capacity(n),
            bits: vec![0; n * rows * w],
        };
        let mut k = 0;
        for y in t.y0..t.y1 {
            for x in t.x0..t.x1 {
                let i = work.region.index(x, y);
                let s = work.surf[i];
                patch.hit.push(s.hit);
                patch.p.push(s.p);
                patch.n.push(s.n);
                let above = TileWork::row(&work.above, i, w);
                let vis = TileWork::row(&work.vis, i, w);
                let out = &mut patch.bits[k * rows * w..(k + 1) * rows * w];
                out[..w].copy_from_slice(above);
                out[w..2 * w].copy_from_slice(vis);
                if edges {
                    // Only blocked lights can sit at an edge or have a visible neighbour
                    // across one, so the loop runs over the (usually few) blocked lights.
                    // Both sides are marked: marking only the side the turn moves towards
                    // traced 2 % fewer rays with twice the wrong pairs (docs/temporal.md).
                    let (head, edge) = out.split_at_mut(2 * w);
                    for m in 0..w {
                        let mut blocked = head[m] & !head[w + m];
                        while blocked != 0 {
                            let j = m * 64 + blocked.trailing_zeros() as usize;
                            blocked &= blocked - 1;
                            for &a in lights.neighbors(j) {
                                let a = a as usize;
                                if bits::get(&head[..w], a) && bits::get(&head[w..2 * w], a) {
                                    bits::set(edge, j);
                                    bits::set(edge, a);
                                }
                            }
                        }
                    }
                }
                k += 1;
            }
        }
        patch
    }
}

/// What frame k reads of frame k − 1: its carried data and how to find a point in it.
pub struct Prev<'a> {
    carried: &'a Carried,
    /// Current world → the previous frame's world (the object's motion between the frames).
    to_prev: Mat4,
    to_prev_rot: Mat3,
    camera: Camera,
    /// The current camera's eye and the angle one pixel subtends (radians, vertically).
    eye: Vec3,
    pixel_angle: f32,
    /// Lights whose votes are pulled from another of the previous frame's lights (spin):
    /// (current light, previous light).
    remap: Vec<(u16, u16)>,
}

impl<'a> Prev<'a> {
    /// The view of `carried` (frame `frame − 1`) from `frame`, whose camera is `camera`.
    pub fn new(
        anim: &Animation,
        carried: &'a Carried,
        frame: usize,
        prev_camera: Camera,
        camera: &Camera,
        target: Vec3,
        lights: &LightSet,
    ) -> Prev<'a> {
        debug_assert_eq!(carried.frame + 1, frame);
        let now = anim
            .scene_transform(frame, target)
            .unwrap_or(Mat4::IDENTITY);
        let then = anim
            .scene_transform(carried.frame, target)
            .unwrap_or(Mat4::IDENTITY);
        let to_prev = then * now.inverse();
        let to_prev_rot = Mat3::from_mat4(to_prev);
        let mut remap = Vec::new();
        if anim.motion == MotionKind::Spin {
            for (j, l) in lights.lights.iter().enumerate() {
                // The object-space direction light j has now pointed along this world
                // direction in the previous frame.
                let m = lights.cell_of((to_prev_rot * l.dir).normalize()) as usize;
                if m != j {
                    remap.push((j as u16, m as u16));
                }
            }
        }
        Prev {
            carried,
            to_prev,
            to_prev_rot,
            camera: prev_camera,
            eye: camera.position,
            pixel_angle: 2.0 * (camera.vfov_deg.to_radians() * 0.5).tan() / camera.height as f32,
            remap,
        }
    }

    pub fn carried(&self) -> &Carried {
        self.carried
    }

    pub fn remap(&self) -> &[(u16, u16)] {
        &self.remap
    }

    /// The previous frame's pixels (up to four around the reprojected point) that saw the
    /// surface point of `s`: near it, on its tangent plane, with a similar normal.
    pub fn voters(&self, s: &crate::frame::Surface, out: &mut [usize; 4]) -> usize {
        let p = self.to_prev.transform_point3(s.p);
        let n = self.to_prev_rot * s.n;
        let Some((u, v)) = self.camera.project(p) else {
            return 0;
        };
        let (fx, fy) = ((u - 0.5).floor(), (v - 0.5).floor());
        let c = self.carried;
        if !(fx >= -1.0 && fy >= -1.0 && fx < c.width as f32 && fy < c.height as f32) {
            return 0;
        }
        // One pixel's footprint at the point's depth; grazing surfaces stretch it.
        let view = s.p - self.eye;
        let dist = view.length();
        let footprint = dist * self.pixel_angle;
        let cos = (s.n.dot(view) / dist).abs().max(0.25);
        let (near, plane) = (2.5 * footprint / cos, 0.5 * footprint);
        let mut k = 0;
        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let (x, y) = (fx as i64 + dx, fy as i64 + dy);
            if x < 0 || y < 0 || x >= c.width as i64 || y >= c.height as i64 {
                continue;
            }
            let q = y as usize * c.width as usize + x as usize;
            if !c.hit[q] {
                continue;
            }
            let d = c.p[q] - p;
            if d.length() <= near && n.dot(d).abs() <= plane && n.dot(c.n[q]) >= 0.8 {
                out[k] = q;
                k += 1;
            }
        }
        k
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chains_start_at_key_frames() {
        let one = |f: &[(usize, bool)]| Chain { frames: f.to_vec() };
        assert_eq!(
            chains(&[3, 4], false, 4),
            vec![one(&[(3, true)]), one(&[(4, true)])]
        );
        // 3 warms up from 0; 4 starts a chain of its own; 9 warms up from 8.
        assert_eq!(
            chains(&[3, 4, 5, 9], true, 4),
            vec![
                one(&[(0, false), (1, false), (2, false), (3, true)]),
                one(&[(4, true), (5, true)]),
                one(&[(8, false), (9, true)]),
            ]
        );
        // A resumed run with holes re-renders the frames between, unwritten.
        assert_eq!(
            chains(&[0, 3], true, 8),
            vec![one(&[(0, true), (1, false), (2, false), (3, true)])]
        );
        assert!(is_key(16, 16) && !is_key(17, 16) && is_key(0, 1));
    }
}
