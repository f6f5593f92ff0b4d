//! Shared by the two map targets: a map that decodes is reduced to lights by both samplers.

use envshadow::envmap::EnvMap;
use envshadow::lights::{LightSet, Sampler};
use glam::Vec3;

pub fn exercise(env: EnvMap) {
    // Sampling is linear in the texels; keep the executions fast.
    if env.width * env.height > 1 << 16 {
        return;
    }
    for sampler in [Sampler::Sis, Sampler::MedianCut] {
        for n in [1, 7, 32] {
            if let Ok(set) = LightSet::build(&env, n, sampler) {
                let _ = set.cell_of(Vec3::new(0.3, 0.5, -0.8).normalize());
            }
        }
    }
}
