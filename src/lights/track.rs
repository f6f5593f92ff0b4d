//! Where each light goes when the light set turns about the up axis (a turning environment,
//! `[motion] kind = "environment"`): the cells of the set before the turn that its path
//! crosses ([`Tracks`]). Temporal prediction reads a pixel's previous visibility at those
//! cells to tell whether a shadow edge lies across or just ahead of the light's path
//! (docs/temporal.md, "Environment rotation").

use std::f32::consts::FRAC_PI_2;

use glam::{Vec2, Vec3};

use super::LightSet;
use crate::envmap::rotate_y;

/// Step along a path, degrees: fine enough not to skip a cell of the densest sets we render
/// (4096 lights lie about 3° apart).
const STEP_DEG: f32 = 0.25;
/// How far past the turn a path is followed to find the cell after the one it ends in.
const REACH_DEG: f32 = 60.0;
/// The corridor around a path, as a share of the lights' mean spacing sqrt(4π/N) on each side
/// [ours]: a shadow edge crossing the path obliquely can leave the next cell's light on the
/// near side; a corridor of 0.3 spacing (±3° at 400 lights) took the bunny's relative image
/// error from up to 2.1 % to within 0.6 % over a chain of ten frames (docs/temporal.md).
const CORRIDOR: f32 = 0.3;
/// Cells kept per light (three paths cross a few each).
const MAX_CELLS: usize = 16;

/// For a turn of a light set by a fixed angle: per light j, the cells (lights of the set
/// before the turn) met by j's path and by two paths beside it (a corridor), from its
/// direction to where the turn ends and on to the next cell — what the previous frame knew
/// around the light's way, stored per light (CSR). A light whose turn crosses several small
/// cells (a cluster on a sun or a softbox) meets each of them along its path, so it needs no
/// special case: marking every light that leaves its own cell in one turn as an edge light
/// traced 72.5 % of the spatial method's rays instead of 55 % on studio_small_03 (bunny,
/// 640×480, 200 lights, 3° per frame) for no fewer wrong pairs (docs/temporal.md).
#[derive(Clone, Debug)]
pub struct Tracks {
    offsets: Vec<u32>,
    cells: Vec<u16>,
}

impl Tracks {
    /// The tracks of `set`'s lights turned by `degrees` about +Y (the sense of
    /// [`LightSet::turned`]). Deterministic (libm, fixed steps).
    pub fn new(set: &LightSet, degrees: f32) -> Tracks {
        let n = set.len();
        assert!(n <= 1 << 16, "light ids are u16 in tracks");
        let turn = degrees.abs();
        let sign = if degrees < 0.0 { -1.0 } else { 1.0 };
        let side = CORRIDOR * (4.0 * std::f32::consts::PI / n.max(1) as f32).sqrt();
        let mut offsets = Vec::with_capacity(n + 1);
        let mut cells: Vec<u16> = Vec::new();
        offsets.push(0u32);
        for l in &set.lights {
            let start = cells.len();
            let lat = libm::asinf(l.dir.y.clamp(-1.0, 1.0));
            let h = Vec2::new(l.dir.x, l.dir.z).normalize_or(Vec2::Y);
            for offset in [0.0, -side, side] {
                // The path itself, then the two beside it (the same longitude, `side` radians
                // nearer either pole).
                let d0 = if offset == 0.0 {
                    l.dir
                } else {
                    let la = (lat + offset).clamp(-FRAC_PI_2, FRAC_PI_2);
                    let (s, c) = libm::sincosf(la);
                    Vec3::new(c * h.x, s, c * h.y)
                };
                let cell_at =
                    |a: f32| set.cell_of(rotate_y(d0, libm::sincosf((sign * a).to_radians())));
                let mut push = |c: u32| {
                    if cells.len() - start < MAX_CELLS && !cells[start..].contains(&(c as u16)) {
                        cells.push(c as u16);
                    }
                };
                // Along the turn, and exactly at its end.
                let mut k = 0u32;
                let end = loop {
                    let a = (k as f32 * STEP_DEG).min(turn);
                    let c = cell_at(a);
                    push(c);
                    if a >= turn {
                        break c;
                    }
                    k += 1;
                };
                // Beyond it, up to the next cell.
                let mut k = 1u32;
                while k as f32 * STEP_DEG <= REACH_DEG {
                    let c = cell_at(turn + k as f32 * STEP_DEG);
                    if c != end {
                        push(c);
                        break;
                    }
                    k += 1;
                }
            }
            offsets.push(cells.len() as u32);
        }
        Tracks { offsets, cells }
    }

    /// Number of lights.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The cells light `j`'s corridor meets, its own first.
    #[inline]
    pub fn cells(&self, j: usize) -> &[u16] {
        &self.cells[self.offsets[j] as usize..self.offsets[j + 1] as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::Light;

    /// A ring of lights on the horizon 10° apart, each with a cell as wide as a 10° disc.
    fn ring() -> LightSet {
        let lights: Vec<Light> = (0..36)
            .map(|i| {
                let (s, c) = libm::sincosf((i as f32 * 10.0).to_radians());
                Light {
                    dir: Vec3::new(s, 0.0, c),
                    energy: Vec3::ONE,
                    solid_angle: 0.03,
                }
            })
            .collect();
        LightSet::from_lights(lights)
    }

    #[test]
    fn a_track_starts_in_its_own_cell_and_ends_past_the_next() {
        // A turn of 3° stays in the light's own cell (its border is 5° away) and the next
        // cell along is the next light's; a turn of 7° ends in the next light's cell and
        // brackets it with the one after. The ring's cells are long lunes from pole to pole,
        // so the corridor meets the same cells.
        let set = ring();
        let t = Tracks::new(&set, 3.0);
        assert_eq!(t.cells(0), &[0, 1]);
        assert_eq!(t.cells(35), &[35, 0]);
        let t = Tracks::new(&set, 7.0);
        assert_eq!(t.cells(0), &[0, 1, 2]);
        // The other way round.
        let t = Tracks::new(&set, -3.0);
        assert_eq!(t.cells(0), &[0, 35]);
    }
}
