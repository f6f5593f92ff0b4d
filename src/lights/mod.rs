//! Directional lights from an environment map (ALGORITHM.md §1).
//!
//! STUB: filled in by the lights helper.

use glam::Vec3;

use crate::envmap::EnvMap;
use crate::error::Result;

/// One directional light: the spherical Voronoi cell of `dir` with the map's radiance integrated over it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Unit direction towards the light (world space, environment rotation applied).
    pub dir: Vec3,
    /// E_j = ∫ over the cell of L(ω) dω, RGB.
    pub energy: Vec3,
    /// Solid angle of the cell, steradians.
    pub solid_angle: f32,
}

/// Which sampler places the light directions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Sampler {
    /// Structured importance sampling (Agarwal et al. 2003), the paper's choice.
    #[default]
    Sis,
    /// Median cut (Debevec 2005).
    MedianCut,
}

/// N directional lights, their cells, an O(1) `cell_of` lookup and the cells' adjacency.
#[derive(Clone, Debug)]
pub struct LightSet {
    pub lights: Vec<Light>,
}

impl LightSet {
    /// Samples `n` lights from `env` with `sampler`. Deterministic. `n == 0` is an error.
    pub fn build(_env: &EnvMap, _n: usize, _sampler: Sampler) -> Result<LightSet> {
        unimplemented!()
    }
    /// Builds the set from given lights (directions normalised), e.g. one light for a test.
    pub fn from_lights(_lights: Vec<Light>) -> LightSet {
        unimplemented!()
    }
    pub fn len(&self) -> usize {
        self.lights.len()
    }
    pub fn is_empty(&self) -> bool {
        self.lights.is_empty()
    }
    /// The light whose cell contains unit direction `dir` (nearest light; ties to the lower index).
    pub fn cell_of(&self, _dir: Vec3) -> u32 {
        unimplemented!()
    }
    /// Lights whose cells share a border with light `j`'s cell (symmetric).
    pub fn neighbors(&self, _j: usize) -> &[u32] {
        unimplemented!()
    }
}
