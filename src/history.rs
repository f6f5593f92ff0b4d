//! What a frame keeps for the next one (`--temporal`, ALGORITHM.md §8 [ours]): every pixel's
//! surface point and normal and its above-horizon and visible lights ([`Carried`], assembled
//! from the tiles' [`CarryPatch`]es), and how the next frame finds the previous pixels that
//! saw its surface points ([`Prev`]). Key frames and chains, and the per-pixel temporal
//! prediction, are built on these by the modules above.

use glam::{Mat3, Mat4, Vec3};

use crate::bits;
use crate::buffers::TileBuffers;
use crate::camera::Camera;
use crate::context::Surface;
use crate::lights::{LightSet, Tracks};
use crate::moved::Moved;
use crate::tile::Rect;

/// Which lights a frame marks for the next one as *edge lights*: lights a shadow edge may
/// cross before the next frame, because the lights turn relative to the scene.
pub enum Edges {
    /// None (the lights keep their place relative to the scene: orbit, still).
    None,
    /// A spinning object: lights whose visibility differs from an adjacent above-horizon
    /// light's.
    Adjacent,
    /// A turning environment: lights whose path over the next frame's turn ([`Tracks`]) meets
    /// above-horizon cells of both visibilities (a shadow edge lies across or just ahead of it).
    Track(Tracks),
}

impl Edges {
    /// Whether edge lights are kept at all.
    pub fn kept(&self) -> bool {
        !matches!(self, Edges::None)
    }
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
    /// The frame's vertex positions, kept when a file's animation posed it, so the next
    /// frame finds what moved ([`Moved`]); empty otherwise.
    positions: Vec<Vec3>,
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
            positions: Vec::new(),
        }
    }

    /// Keeps the frame's vertex positions (a pose of the file's animation) for the next frame.
    pub fn keep_positions(&mut self, positions: &[Vec3]) {
        self.positions = positions.to_vec();
    }

    /// The frame's vertex positions, if kept ([`keep_positions`](Self::keep_positions)).
    pub fn positions(&self) -> Option<&[Vec3]> {
        (!self.positions.is_empty()).then_some(&self.positions[..])
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

    /// The surface point pixel `q` saw (world space of its frame).
    #[inline]
    pub fn point(&self, q: usize) -> Vec3 {
        self.p[q]
    }

    /// Whether the light-space shadow edges are kept (a spinning object).
    pub fn has_edges(&self) -> bool {
        self.rows > 2
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.hit.len() * (1 + 24) + self.bits.len() * 8 + self.positions.len() * 12
    }
}

impl CarryPatch {
    /// Records the tile's own pixels from `bufs` after the tile was rendered, each by one of
    /// its k × k samples (`bufs` addresses samples): the one in stratum (k/2, k/2), nearest the
    /// centre, so the carried frame keeps the memory of one sample per pixel whatever the
    /// samples per pixel. With `edges`, also the edge lights ([`Edges`]).
    pub fn record(bufs: &TileBuffers, lights: &LightSet, edges: &Edges, k: u32) -> CarryPatch {
        let st = bufs.tile;
        let t = Rect::new(st.x0 / k, st.y0 / k, st.x1 / k, st.y1 / k);
        let w = bufs.words;
        let rows = if edges.kept() { 3 } else { 2 };
        let n = t.area();
        let mut patch = CarryPatch {
            rect: t,
            hit: Vec::with_capacity(n),
            p: Vec::with_capacity(n),
            n: Vec::with_capacity(n),
            bits: vec![0; n * rows * w],
        };
        let mut c = 0;
        for y in t.y0..t.y1 {
            for x in t.x0..t.x1 {
                let i = bufs.region.index(x * k + k / 2, y * k + k / 2);
                let s = bufs.surf[i];
                patch.hit.push(s.hit);
                patch.p.push(s.p);
                patch.n.push(s.n);
                let above = bits::rows(&bufs.above, w).row(i);
                let vis = bits::rows(&bufs.vis, w).row(i);
                let out = bits::rows_mut(&mut patch.bits, rows * w).into_row(c);
                out[..w].copy_from_slice(above);
                out[w..2 * w].copy_from_slice(vis);
                if let Edges::Track(tracks) = edges {
                    track_edges(out, w, tracks);
                } else if edges.kept() {
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
                c += 1;
            }
        }
        patch
    }
}

/// Marks in `out`'s edge row (after the above and visible rows, `w` words each) the lights
/// whose corridor ([`Tracks`]) meets both a visible light and a blocked or below-horizon one:
/// a shadow edge (or the horizon, beyond which the previous frame knows nothing) lies across
/// or just ahead of its way.
fn track_edges(out: &mut [u64], w: usize, tracks: &Tracks) {
    let (head, edge) = out.split_at_mut(2 * w);
    let (above, vis) = head.split_at(w);
    edge.fill(0);
    for j in 0..tracks.len() {
        let (mut lit, mut dark) = (false, false);
        for &c in tracks.cells(j) {
            let c = c as usize;
            if bits::get(above, c) && bits::get(vis, c) {
                lit = true;
            } else {
                dark = true;
            }
        }
        if lit && dark {
            bits::set(edge, j);
        }
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
    /// The sine of the largest angle between a light's direction carried into the previous
    /// frame and the previous light its votes come from (spin; 0 for an orbit): lights this
    /// close to a pixel's tangent plane are at its horizon edge.
    grazing: f32,
    /// What a file's animation moved since the previous frame: its visibility does not
    /// predict a ray that may cross it.
    moved: Option<&'a Moved>,
}

impl<'a> Prev<'a> {
    /// The view of `carried` (the frame before the current one) from the current frame, whose
    /// camera is `camera`: `to_prev` carries a current world point into the previous frame's
    /// world (the object's motion between them), `prev_camera` saw the previous frame, and
    /// `remap` lists the lights whose votes come from another previous light (spin).
    pub fn new(
        carried: &'a Carried,
        to_prev: Mat4,
        prev_camera: Camera,
        camera: &Camera,
        remap: Vec<(u16, u16)>,
    ) -> Prev<'a> {
        Prev {
            carried,
            to_prev,
            to_prev_rot: Mat3::from_mat4(to_prev),
            camera: prev_camera,
            eye: camera.position,
            pixel_angle: 2.0 * libm::tanf(camera.vfov_deg.to_radians() * 0.5)
                / camera.height as f32,
            remap,
            grazing: 0.0,
            moved: None,
        }
    }

    /// This view with what the file's animation moved since the previous frame.
    pub fn with_moved(self, moved: Option<&'a Moved>) -> Prev<'a> {
        Prev { moved, ..self }
    }

    /// What the file's animation moved since the previous frame, if anything.
    pub fn moved(&self) -> Option<&'a Moved> {
        self.moved
    }

    /// This view with `grazing` (see [`grazing`](Self::grazing)).
    pub fn with_grazing(self, grazing: f32) -> Prev<'a> {
        Prev { grazing, ..self }
    }

    /// The sine of the elevation above a pixel's tangent plane below which a light's votes
    /// (pulled through a spin's turn) may come from the other side of a grazing shadow.
    pub fn grazing(&self) -> f32 {
        self.grazing
    }

    /// The previous frame's pixel (x, y) as a row-major index if it saw surface point `p` (bit
    /// for bit: the same ray through the same scene): what a turning environment's frame reads
    /// (scene and camera still, so each pixel's previous self saw its surface point).
    #[inline]
    pub fn same_point(&self, x: u32, y: u32, p: Vec3) -> Option<usize> {
        let c = self.carried;
        let q = y as usize * c.width as usize + x as usize;
        (x < c.width && y < c.height && c.hit[q] && c.p[q] == p).then_some(q)
    }

    pub fn carried(&self) -> &Carried {
        self.carried
    }

    pub fn remap(&self) -> &[(u16, u16)] {
        &self.remap
    }

    /// How far from `s`'s point the previous frame's voters may lie, and off its tangent plane:
    /// 2.5 and 0.5 pixel footprints at the point's depth (grazing surfaces stretch the first).
    #[inline]
    fn reach(&self, s: &Surface) -> (f32, f32) {
        let view = s.p - self.eye;
        let dist = view.length();
        let footprint = dist * self.pixel_angle;
        let cos = (s.n.dot(view) / dist).abs().max(0.25);
        (2.5 * footprint / cos, 0.5 * footprint)
    }

    /// The previous frame's pixels (up to four around the reprojected point) that saw the
    /// surface point of `s`: near it, on its tangent plane, with a similar normal.
    pub fn voters(&self, s: &Surface, out: &mut [usize; 4]) -> usize {
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
        let (near, plane) = self.reach(s);
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
    use crate::predict::testkit::{
        DOWN, Frame, R, UP, at, buffers, carried_ground, ground_point, list, set_of, star,
    };

    /// The star's lights above a ground point's horizon (all but DOWN), and those the roof
    /// leaves visible from the origin.
    fn up() -> Vec<usize> {
        (0..DOWN).collect()
    }
    const LIT: [usize; 4] = [UP, R[2], R[3], R[4]];

    /// A carried word's rows as light lists: (above, visible, edge).
    fn rows(c: &Carried, q: usize) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
        let (mut a, mut v, mut e) = (vec![], vec![], vec![]);
        for m in 0..c.words {
            let (wa, wv, we) = c.word(q, m);
            a.push(wa);
            v.push(wv);
            e.push(we);
        }
        (list(&a), list(&v), list(&e))
    }

    #[test]
    fn a_frame_keeps_each_tiles_pixels_where_the_frame_has_them() {
        let frame = Frame::new(&star());
        let ctx = frame.ctx();
        let w = ctx.words();
        // Two tiles of one row, 3 + 2 pixels, recorded apart and inserted in either order.
        let surfaces: Vec<_> = (0..5).map(|k| at(Vec3::new(k as f32, 0.0, 0.0))).collect();
        let (mut bufs, _) = buffers(&ctx, &surfaces);
        for q in 0..5 {
            bits::rows_mut(&mut bufs.above, w)
                .row_mut(q)
                .copy_from_slice(&set_of(w, &up()));
            bits::rows_mut(&mut bufs.vis, w)
                .row_mut(q)
                .copy_from_slice(&set_of(w, &[q]));
        }
        let mut carried = Carried::new(7, 5, 1, w, false);
        for tile in [Rect::new(3, 0, 5, 1), Rect::new(0, 0, 3, 1)] {
            bufs.tile = tile;
            carried.insert(&CarryPatch::record(&bufs, ctx.lights, &Edges::None, 1));
        }
        assert_eq!(carried.frame, 7);
        assert!(!carried.has_edges());
        for (q, s) in surfaces.iter().enumerate() {
            assert_eq!(rows(&carried, q), (up(), vec![q], vec![]), "pixel {q}");
            assert_eq!(carried.p[q], s.p);
            assert!(carried.hit[q]);
        }
    }

    #[test]
    fn a_pixel_keeps_its_middle_sample_whatever_the_samples_per_pixel() {
        let frame = Frame::new(&star());
        let ctx = frame.ctx();
        let w = ctx.words();
        // One pixel of 3 × 3 samples in a one-row region of 9: sample (1, 1) of the pixel is
        // stratum 4 when the row holds the 3 × 3 lattice row by row.
        let region = Rect::frame(3, 3);
        let mut bufs = TileBuffers::default();
        bufs.prepare(&ctx, region, region);
        for q in 0..9 {
            bufs.surf[q] = at(Vec3::new(q as f32, 0.0, 0.0));
            bits::rows_mut(&mut bufs.above, w)
                .row_mut(q)
                .copy_from_slice(&set_of(w, &up()));
            bits::rows_mut(&mut bufs.vis, w)
                .row_mut(q)
                .copy_from_slice(&set_of(w, &[q % 7]));
        }
        let mut carried = Carried::new(0, 1, 1, w, false);
        carried.insert(&CarryPatch::record(&bufs, ctx.lights, &Edges::None, 3));
        assert_eq!(rows(&carried, 0).1, [4]);
        assert_eq!(carried.p[0], Vec3::new(4.0, 0.0, 0.0));
    }

    #[test]
    fn a_spin_marks_both_sides_of_every_shadow_edge_between_adjacent_lights() {
        let frame = Frame::new(&star());
        let ctx = frame.ctx();
        let carried = carried_ground(&ctx, &Edges::Adjacent, |_, _| Some((up(), LIT.to_vec())));
        assert!(carried.has_edges());
        // Blocked R0, R1, R5 each border a visible light (UP; R2; R4): those pairs are edges.
        // R3 borders only visible lights, and DOWN is below the horizon.
        let (_, vis, edge) = rows(&carried, 0);
        assert_eq!(vis, LIT);
        assert_eq!(edge, [UP, R[0], R[1], R[2], R[4], R[5]]);
    }

    #[test]
    fn the_previous_frame_finds_the_pixels_that_saw_a_point_and_no_others() {
        let frame = Frame::new(&star());
        let ctx = frame.ctx();
        let carried = carried_ground(&ctx, &Edges::None, |x, _| {
            (x != 6).then(|| (up(), LIT.to_vec()))
        });
        let cam = ctx.camera;
        let prev = Prev::new(&carried, Mat4::IDENTITY, cam, &cam, Vec::new());
        let index = |x: u32, y: u32| (y * cam.width + x) as usize;
        // A quarter pixel past (3, 3)'s centre: the four pixels around it saw its plane.
        let s = at(ground_point(&ctx, 3, 3, (0.25, 0.25)));
        let mut out = [0; 4];
        let n = prev.voters(&s, &mut out);
        assert_eq!(
            out[..n],
            [index(3, 3), index(4, 3), index(3, 4), index(4, 4)]
        );
        // Column 6 saw nothing: only column 5 votes there.
        let s = at(ground_point(&ctx, 5, 2, (0.25, 0.25)));
        let n = prev.voters(&s, &mut out);
        assert_eq!(out[..n], [index(5, 2), index(5, 3)]);
        // A point off the plane, or one facing another way, is not what they saw.
        let lifted = at(ground_point(&ctx, 3, 3, (0.25, 0.25)) + Vec3::Y);
        assert_eq!(prev.voters(&lifted, &mut out), 0);
        let turned = Surface {
            n: Vec3::X,
            ..at(ground_point(&ctx, 3, 3, (0.25, 0.25)))
        };
        assert_eq!(prev.voters(&turned, &mut out), 0);
        // The object moved a metre between the frames: carried back, the point is found again.
        let moved = Mat4::from_translation(Vec3::new(0.0, 0.0, -1.0));
        let prev = Prev::new(&carried, moved, cam, &cam, Vec::new());
        let s = at(ground_point(&ctx, 3, 3, (0.25, 0.25)) + Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(prev.voters(&s, &mut out), 4);
        // In place, only the bit-identical point is the pixel's previous self.
        let p = ground_point(&ctx, 2, 5, (0.0, 0.0));
        assert_eq!(prev.same_point(2, 5, p), Some(index(2, 5)));
        assert_eq!(prev.same_point(2, 5, p + Vec3::splat(1e-6)), None);
        assert_eq!(
            prev.same_point(6, 5, ground_point(&ctx, 6, 5, (0.0, 0.0))),
            None
        );
        assert_eq!(prev.same_point(cam.width, 0, p), None);
    }
}
