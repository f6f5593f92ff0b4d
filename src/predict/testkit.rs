//! Hand-built frames for the prediction's unit tests: lights whose adjacency is known by
//! construction, and a blocker whose shadow rays have known answers from a surface point
//! under it.

use glam::{Vec2, Vec3};

use super::correct::At;
use super::flood::FloodTo;
use super::scratch::Scratch;
use crate::accel::Accel;
use crate::bits;
use crate::buffers::TileBuffers;
use crate::camera::Camera;
use crate::context::{FrameContext, Surface};
use crate::envmap::EnvMap;
use crate::history::{Carried, CarryPatch, Edges};
use crate::lights::{Light, LightSet};
use crate::scene::{Material, Scene};
use crate::tile::Rect;

/// The star: light `UP` straight up, `R[k]` a ring of six at 45° elevation and azimuth 60k°
/// (from +X towards +Z), `DOWN` straight down. UP borders every ring light, each ring light
/// its two ring neighbours, UP and DOWN; DOWN borders every ring light.
pub const UP: usize = 0;
pub const R: [usize; 6] = [1, 2, 3, 4, 5, 6];
pub const DOWN: usize = 7;

/// The star's directions, in light order.
pub fn star() -> Vec<Vec3> {
    let mut d = vec![Vec3::Y];
    for k in 0..6 {
        let a = (60.0 * k as f32).to_radians();
        d.push(Vec3::new(libm::cosf(a), 1.0, libm::sinf(a)).normalize());
    }
    d.push(Vec3::NEG_Y);
    d
}

/// `n` directions spread evenly over the sphere (a Fibonacci spiral).
pub fn spiral(n: usize) -> Vec<Vec3> {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..n)
        .map(|k| {
            let y = 1.0 - 2.0 * (k as f32 + 0.5) / n as f32;
            let r = (1.0 - y * y).sqrt();
            let a = golden * k as f32;
            Vec3::new(r * libm::cosf(a), y, r * libm::sinf(a))
        })
        .collect()
}

/// How the tests' pixels are decided: flooding to the contrary neighbours, keeping nothing, a
/// pixel apart from its voters.
pub const CONTRARY: At = At {
    flood_to: FloodTo::Contrary,
    keep_blockers: false,
    keep_predicted: false,
    majority: false,
    inside: false,
};

/// The surface point the tests decide: the origin, facing +Y, under [`Frame::new`]'s roof.
pub fn origin() -> Surface {
    Surface {
        p: Vec3::ZERO,
        n: Vec3::Y,
        ng: Vec3::Y,
        origin: crate::offset::offset_origin(Vec3::ZERO, Vec3::ZERO, Vec3::Y),
        albedo: Vec3::splat(0.5),
        dir: Vec3::NEG_Y,
        hit: true,
        catcher: false,
        ..Surface::default()
    }
}

/// A surface point at `p` facing +Y.
pub fn at(p: Vec3) -> Surface {
    let err = p.abs() * crate::offset::gamma(7);
    Surface {
        p,
        origin: crate::offset::offset_origin(p, err, Vec3::Y),
        ..origin()
    }
}

/// A frame with its own scene, BVH, lights and map; [`Frame::ctx`] borrows them.
pub struct Frame {
    scene: Scene,
    accel: Accel,
    lights: LightSet,
    env: EnvMap,
}

impl Frame {
    /// Lights in `dirs` and a roof: the square y = 1, x in [0.2, 10], z in [-10, 10]. From the
    /// origin it blocks the star's R[0], R[1] and R[5] and no other star light.
    pub fn new(dirs: &[Vec3]) -> Frame {
        let mut scene = Scene {
            materials: vec![Material::default_grey()],
            source: "test".into(),
            ..Default::default()
        };
        for (x, z) in [(0.2, -10.0), (10.0, -10.0), (10.0, 10.0), (0.2, 10.0)] {
            scene.positions.push(Vec3::new(x, 1.0, z));
            scene.normals.push(Vec3::NEG_Y);
            scene.uvs.push(Vec2::ZERO);
        }
        scene.triangles = vec![[0, 1, 2], [0, 2, 3]];
        scene.tri_material = vec![0, 0];
        let accel = scene.accel();
        let lights = LightSet::from_lights(
            dirs.iter()
                .map(|&dir| Light {
                    dir,
                    energy: Vec3::ONE,
                    solid_angle: 1.0,
                })
                .collect(),
        );
        Frame {
            scene,
            accel,
            lights,
            env: EnvMap::builtin_sky(),
        }
    }

    pub fn ctx(&self) -> FrameContext<'_> {
        let camera = Camera::look_at(Vec3::new(0.0, 5.0, 5.0), Vec3::ZERO, Vec3::Y, 40.0, 8, 8);
        FrameContext::new(&self.scene, &self.accel, camera, &self.lights, &self.env)
    }
}

/// A bitset of `words` words with `lights` set.
pub fn set_of(words: usize, lights: &[usize]) -> Vec<u64> {
    let mut b = vec![0; words];
    for &j in lights {
        bits::set(&mut b, j);
    }
    b
}

/// The bits of `a` not in `b`: a pixel's predicted-visible lights, from its above-horizon and
/// predicted-blocked ones.
pub fn and_not(a: &[u64], b: &[u64]) -> Vec<u64> {
    a.iter().zip(b).map(|(a, b)| a & !b).collect()
}

/// The set bits of `b`, ascending.
pub fn list(b: &[u64]) -> Vec<usize> {
    let mut v = Vec::new();
    bits::for_each(b, |j| v.push(j));
    v
}

/// Buffers for a one-row region holding `surfaces` (nothing above any horizon yet), and a
/// scratch sized for the frame's lights.
pub fn buffers(ctx: &FrameContext, surfaces: &[Surface]) -> (TileBuffers, Scratch) {
    let region = Rect::frame(surfaces.len() as u32, 1);
    let mut bufs = TileBuffers::default();
    bufs.prepare(ctx, region, region);
    bufs.surf.copy_from_slice(surfaces);
    let mut sc = Scratch::default();
    sc.prepare(ctx.light_count());
    (bufs, sc)
}

/// Where the primary ray through the point `(dx, dy)` pixels from the centre of pixel (x, y) of
/// the frame's camera meets the ground plane y = 0 (under [`Frame::new`]'s roof).
pub fn ground_point(ctx: &FrameContext, x: u32, y: u32, (dx, dy): (f32, f32)) -> Vec3 {
    let eye = ctx.camera.position;
    let dir = ctx.camera.ray_dir_at(x, y, dx, dy);
    eye + dir * (-eye.y / dir.y)
}

/// What a previous frame that saw the ground plane through the frame's camera keeps: pixel
/// (x, y) hit the ground at its centre, facing +Y, with `lights(x, y)` its (above-horizon,
/// visible) lights, or saw nothing where that is `None`; `edges` the edge lights it keeps.
pub fn carried_ground(
    ctx: &FrameContext,
    edges: &Edges,
    lights: impl Fn(u32, u32) -> Option<(Vec<usize>, Vec<usize>)>,
) -> Carried {
    let (width, height) = (ctx.camera.width, ctx.camera.height);
    let frame = Rect::frame(width, height);
    let w = ctx.words();
    let mut bufs = TileBuffers::default();
    bufs.prepare(ctx, frame, frame);
    for y in 0..height {
        for x in 0..width {
            let i = frame.index(x, y);
            let Some((above, vis)) = lights(x, y) else {
                bufs.surf[i] = Surface::default();
                continue;
            };
            bufs.surf[i] = at(ground_point(ctx, x, y, (0.0, 0.0)));
            bits::rows_mut(&mut bufs.above, w)
                .row_mut(i)
                .copy_from_slice(&set_of(w, &above));
            bits::rows_mut(&mut bufs.vis, w)
                .row_mut(i)
                .copy_from_slice(&set_of(w, &vis));
        }
    }
    let patch = CarryPatch::record(&bufs, ctx.lights, edges, 1);
    let mut carried = Carried::new(0, width, height, w, edges.kept());
    carried.insert(&patch);
    carried
}

/// The fixture is what the tests built on it assume.
#[test]
fn the_star_borders_as_drawn_and_the_roof_blocks_three_lights() {
    let frame = Frame::new(&star());
    let ctx = frame.ctx();
    let ring = |k: usize| R[k % 6];
    let mut want: Vec<Vec<u32>> = vec![R.iter().map(|&r| r as u32).collect()];
    for k in 0..6 {
        let mut n = vec![
            UP as u32,
            ring(k + 1) as u32,
            ring(k + 5) as u32,
            DOWN as u32,
        ];
        n.sort_unstable();
        want.push(n);
    }
    want.push(R.iter().map(|&r| r as u32).collect());
    for (j, n) in want.iter().enumerate() {
        assert_eq!(ctx.lights.neighbors(j), &n[..], "neighbours of light {j}");
    }
    let visible: Vec<usize> = (0..DOWN).filter(|&j| ctx.trace(&origin(), j)).collect();
    assert_eq!(visible, [UP, R[2], R[3], R[4]]);
}
