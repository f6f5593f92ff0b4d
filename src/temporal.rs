//! Temporal coherence across frames (ALGORITHM.md §8 [ours], `--temporal`): the animation's
//! side. The per-pixel prediction is [`crate::predict::temporal`].
//!
//! - **Carried data.** After a frame is rendered, every pixel's surface point and normal, its
//!   above-horizon and visible lights (and, for a spinning object, the lights at the edge of
//!   its shadow in light space) are kept for the whole frame in a [`Carried`]. The next frame
//!   reads it through a [`Prev`] ([`link`] places it for the animation's motion and chooses
//!   the solver once per frame) and
//!   drops it when done: at most two carried frames per chain exist at once, whatever the
//!   animation's length.
//! - **Key frames.** Frames `0, K, 2K, …` (K = `keyframe`) are predicted from their own pixels
//!   only and start a new chain; the frames between read their predecessor. In a sequence of
//!   motions each motion's first frame is a key frame and K counts from it
//!   ([`crate::motion::Motion::key_frame_of`]). Chains are anchored to absolute frame numbers, so a job that starts inside a chain first renders (without
//!   writing) the frames back to the chain's key frame, and every frame written is the same
//!   whether the animation is rendered as one job or many. It also bounds how far a wrong
//!   prediction can travel in time.
//! - **Determinism.** A frame starts only after its predecessor is complete, so every tile
//!   reads the whole previous frame; a pixel's result is a pure function of the previous frame
//!   and its own frame, and tiles, threads and jobs do not change it.

use glam::{Mat3, Mat4};

use crate::anim::{Animation, MotionKind, Pivot};
use crate::camera::Camera;
use crate::history::{Carried, Edges, Prev};
use crate::lights::{LightSet, Tracks};
use crate::moved::Moved;
use crate::predict::{Link, Read};

/// Whether `frame` starts a chain (is predicted from its own pixels only).
pub fn is_key(frame: usize, keyframe: u32) -> bool {
    frame.is_multiple_of(keyframe.max(1) as usize)
}

/// One chain of frames rendered in order, each reading its predecessor: the frames and
/// whether each is written (the others are rendered only to warm the chain up).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Chain {
    pub frames: Vec<(usize, bool)>,
}

/// The chains that render the frames of `todo` (sorted). Without temporal prediction every
/// frame is a chain of its own; with it, a chain runs from the key frame at or before its
/// first frame (`key_of`: frame → the key frame starting its chain) to its last frame, frames
/// not in `todo` rendered but not written.
pub fn chains(todo: &[usize], temporal: bool, key_of: impl Fn(usize) -> usize) -> Vec<Chain> {
    if !temporal {
        return todo
            .iter()
            .map(|&f| Chain {
                frames: vec![(f, true)],
            })
            .collect();
    }
    let mut out: Vec<Chain> = Vec::new();
    let mut last_key = usize::MAX;
    for &f in todo {
        let key = key_of(f);
        if key != last_key {
            out.push(Chain {
                frames: (key..f).map(|g| (g, false)).collect(),
            });
            last_key = key;
        }
        let chain = out.last_mut().expect("a chain was just started");
        let next = chain.frames.last().map_or(key, |&(g, _)| g + 1);
        chain.frames.extend((next..f).map(|g| (g, false)));
        chain.frames.push((f, true));
    }
    out
}

/// Frame `frame` as its link in time sees it: its scene's pose (`posed`: the transform a
/// moving object has at this frame, about `pivot`), its camera and its lights.
pub struct Now<'b> {
    pub frame: usize,
    pub pivot: Pivot,
    pub posed: Option<Mat4>,
    pub camera: &'b Camera,
    pub lights: &'b LightSet,
}

/// The previous frame as the current one reads it: its carried data, and the camera and lights
/// it was rendered with.
pub struct Before<'a, 'b> {
    pub carried: &'a Carried,
    pub camera: Camera,
    pub lights: &'b LightSet,
    /// What a file's animation moved since (None: nothing did).
    pub moved: Option<&'a Moved>,
}

/// Frame `now`'s link in time, decided here once from the motion at that frame: what it reads
/// of `before` (if any) and with which solver, and, with `carry`, which edge lights it keeps
/// for the next frame.
///
/// - An orbit (or a still scene): the previous pixels around each point's reprojection vote;
///   no edge lights are kept (the lights keep their place relative to the scene).
/// - A spinning object: the same reprojection through the object's motion, each light's
///   votes pulled from the previous light whose cell holds its direction as the object saw it
///   then; the lights at a shadow edge between adjacent lights are kept.
/// - A turning environment: each pixel reads its own previous self (scene and camera still);
///   the lights whose path over the next turn meets both visibilities are kept
///   ([`Tracks`]).
pub fn link<'a>(
    anim: &Animation,
    now: &Now,
    before: Option<Before<'a, '_>>,
    carry: bool,
) -> Link<'a> {
    let segment = anim.motion.segment_at(now.frame);
    let keep = carry.then(|| match segment.kind {
        MotionKind::Environment => Edges::Track(Tracks::new(now.lights, segment.degrees_per_frame)),
        MotionKind::Spin => Edges::Adjacent,
        _ => Edges::None,
    });
    let read = before.map(|b| read(anim, now, segment.kind, b));
    Link::new(read, keep)
}

/// How frame `now` (moving as `kind`) reads `before`, the frame before it: the object's
/// motion between the two frames, and where the lights turn relative to the scene (a spinning
/// object) which previous light each light's votes come from.
fn read<'a>(anim: &Animation, now: &Now, kind: MotionKind, before: Before<'a, '_>) -> Read<'a> {
    let Before {
        carried,
        camera: prev_camera,
        lights: prev_lights,
        moved,
    } = before;
    debug_assert_eq!(carried.frame + 1, now.frame);
    let then = anim.scene_transform(carried.frame, now.pivot);
    // A scene posed alike in both frames (still, or left where an earlier spin put it) has
    // not moved: no rounding from a transform times its inverse.
    let to_prev = if now.posed == then {
        Mat4::IDENTITY
    } else {
        then.unwrap_or(Mat4::IDENTITY) * now.posed.unwrap_or(Mat4::IDENTITY).inverse()
    };
    // A turning environment: each pixel's previous self saw its point, and the lights'
    // paths were marked when it was recorded.
    if kind == MotionKind::Environment {
        return Read::InPlace(Prev::new(
            carried,
            to_prev,
            prev_camera,
            now.camera,
            Vec::new(),
        ));
    }
    let mut remap = Vec::new();
    // The cosine of the largest angle between the direction a light's votes are wanted for
    // and the direction of the previous light they come from (1: none, an orbit).
    let mut worst = 1.0f32;
    if kind == MotionKind::Spin {
        let rot = Mat3::from_mat4(to_prev);
        for (j, l) in now.lights.lights.iter().enumerate() {
            // The direction light j has now, in the previous frame's scene (turned back with
            // the object), fell in this previous light's cell.
            let wanted = (rot * l.dir).normalize();
            let m = prev_lights.cell_of(wanted) as usize;
            worst = worst.min(wanted.dot(prev_lights.lights[m].dir));
            if m != j {
                remap.push((j as u16, m as u16));
            }
        }
    }
    // [ours] Lights grazing the surface by less than that angle are voted on from a direction
    // that may lie on the other side of a grazing shadow (docs/temporal.md, "Flat panels").
    let grazing = libm::sqrtf((1.0 - worst * worst).max(0.0));
    let prev = Prev::new(carried, to_prev, prev_camera, now.camera, remap)
        .with_grazing(grazing)
        .with_moved(moved);
    Read::Reproject(prev)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chains_start_at_key_frames() {
        let one = |f: &[(usize, bool)]| Chain { frames: f.to_vec() };
        let k4 = |f: usize| f / 4 * 4;
        assert_eq!(
            chains(&[3, 4], false, k4),
            vec![one(&[(3, true)]), one(&[(4, true)])]
        );
        // 3 warms up from 0; 4 starts a chain of its own; 9 warms up from 8.
        assert_eq!(
            chains(&[3, 4, 5, 9], true, k4),
            vec![
                one(&[(0, false), (1, false), (2, false), (3, true)]),
                one(&[(4, true), (5, true)]),
                one(&[(8, false), (9, true)]),
            ]
        );
        // A resumed run with holes re-renders the frames between, unwritten.
        assert_eq!(
            chains(&[0, 3], true, |f| f / 8 * 8),
            vec![one(&[(0, true), (1, false), (2, false), (3, true)])]
        );
        assert!(is_key(16, 16) && !is_key(17, 16) && is_key(0, 1));
    }
}
