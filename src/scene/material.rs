//! Materials: the glTF 2.0 metallic-roughness model's parameters and textures, and what they
//! are at one surface point ([`Scene::material_at`]): base colour, metallic, roughness,
//! occlusion, emission, the dielectric specular (`KHR_materials_ior`, `KHR_materials_specular`)
//! and the normal-mapped shading normal. The BRDF that uses them is the `brdf` module's.

use glam::{Vec2, Vec3, Vec4, Vec4Swizzles};

use super::texture::Sampler;
use super::{AlphaMode, Scene};

/// The reflection model a material is shaded with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Model {
    /// glTF 2.0 metallic-roughness (its appendix B): Lambert diffuse for the dielectric part,
    /// GGX microfacet specular with Smith height-correlated masking and Schlick Fresnel,
    /// metals tinted by the base colour. Every glTF material.
    #[default]
    MetallicRoughness,
    /// Lambert only: `albedo / π`, no specular. The built-in `shapes` scene's materials, and
    /// every material under `[material] lambert = true` (`--lambert`).
    Lambert,
}

/// A 2-D affine map of texture coordinates (`KHR_texture_transform`): `uv' = M · (u, v, 1)`
/// with `M = translation × rotation × scale` as the extension defines it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    /// Rows of the 2 × 3 matrix: `u' = m[0] u + m[1] v + m[2]`, `v' = m[3] u + m[4] v + m[5]`.
    pub m: [f32; 6],
}

impl UvTransform {
    /// The extension's `offset`, `rotation` (radians, counter-clockwise in UV space as the
    /// extension draws it) and `scale`.
    pub fn new(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> UvTransform {
        let (s, c) = libm::sincosf(rotation);
        // translation × rotation × scale, with the extension's rotation matrix
        // [cos sin; −sin cos].
        UvTransform {
            m: [
                c * scale[0],
                s * scale[1],
                offset[0],
                -s * scale[0],
                c * scale[1],
                offset[1],
            ],
        }
    }

    #[inline]
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        let m = &self.m;
        Vec2::new(
            m[0] * uv.x + m[1] * uv.y + m[2],
            m[3] * uv.x + m[4] * uv.y + m[5],
        )
    }

    /// How much the map stretches lengths, as one number: `sqrt(|det|)` (a footprint in the
    /// file's coordinates times this is one in the transformed coordinates).
    pub fn scale(&self) -> f32 {
        let det = self.m[0] * self.m[4] - self.m[1] * self.m[3];
        libm::sqrtf(det.abs())
    }
}

/// One texture as a material uses it: which texture, read with which texture coordinate set
/// and transform, through which sampler.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureSlot {
    /// Index into [`Scene::textures`].
    pub texture: usize,
    /// `TEXCOORD_0` or `TEXCOORD_1` (after `KHR_texture_transform`'s `texCoord` override).
    pub tex_coord: u8,
    pub transform: Option<UvTransform>,
    pub sampler: Sampler,
}

impl TextureSlot {
    /// Texture `texture`, `TEXCOORD_0`, no transform, the default sampler.
    pub fn plain(texture: usize) -> TextureSlot {
        TextureSlot {
            texture,
            tex_coord: 0,
            transform: None,
            sampler: Sampler::default(),
        }
    }
}

/// A material: the glTF metallic-roughness parameters, each a factor times its texture.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The file's material name, or `material N`, or `default` for primitives without one.
    pub name: String,
    pub model: Model,
    /// Linear RGB base colour factor.
    pub base_color: Vec3,
    /// The base colour factor's alpha (coverage; the alpha modes use it with the texture's).
    pub base_alpha: f32,
    /// Base colour (sRGB) texture: RGB multiplies `base_color`, A `base_alpha`.
    pub base_color_texture: Option<TextureSlot>,
    /// How the base colour alpha covers the surface (glTF `alphaMode`, [`Scene::alpha`]).
    pub alpha_mode: AlphaMode,
    /// The base colour is `base_color` alone: the texture gives only its alpha, vertex colours
    /// are not used (a `[material] base_color` override).
    pub plain_base_color: bool,
    pub metallic: f32,
    /// Perceptual roughness: the GGX α is its square.
    pub roughness: f32,
    /// Linear; B scales `metallic`, G `roughness` (each unless an override took it).
    pub metallic_roughness_texture: Option<TextureSlot>,
    pub metallic_from_texture: bool,
    pub roughness_from_texture: bool,
    /// Tangent-space normal map (linear), its X and Y scaled by `normal_scale`.
    pub normal_texture: Option<TextureSlot>,
    pub normal_scale: f32,
    /// Linear; R is the occlusion, blended in by `occlusion_strength`.
    pub occlusion_texture: Option<TextureSlot>,
    pub occlusion_strength: f32,
    /// Linear RGB emission: the factor times `KHR_materials_emissive_strength`.
    pub emissive: Vec3,
    /// Emissive (sRGB) texture, multiplying `emissive`.
    pub emissive_texture: Option<TextureSlot>,
    /// Index of refraction of the dielectric part (`KHR_materials_ior`; 1.5: F0 = 0.04).
    pub ior: f32,
    /// `KHR_materials_specular`: the dielectric specular's strength (and F90) …
    pub specular: f32,
    /// … its texture (linear, A channel) …
    pub specular_texture: Option<TextureSlot>,
    /// … its F0 colour (linear) …
    pub specular_color: Vec3,
    /// … and that colour's texture (sRGB).
    pub specular_color_texture: Option<TextureSlot>,
    /// Spec-gloss (`KHR_materials_pbrSpecularGlossiness`): the specular colour texture's A
    /// (linear) is the glossiness, scaling `1 − roughness` (roughness = 1 − glossinessFactor ×
    /// A), unless an override took the roughness.
    pub glossiness_from_specular_texture: bool,
}

impl Default for Material {
    /// glTF's defaults for every field, with a 0.8 grey base colour (see
    /// [`default_grey`](Self::default_grey)).
    fn default() -> Material {
        Material {
            name: "default".to_string(),
            model: Model::MetallicRoughness,
            base_color: Vec3::splat(0.8),
            base_alpha: 1.0,
            base_color_texture: None,
            alpha_mode: AlphaMode::Opaque,
            plain_base_color: false,
            metallic: 0.0,
            roughness: 1.0,
            metallic_roughness_texture: None,
            metallic_from_texture: true,
            roughness_from_texture: true,
            normal_texture: None,
            normal_scale: 1.0,
            occlusion_texture: None,
            occlusion_strength: 1.0,
            emissive: Vec3::ZERO,
            emissive_texture: None,
            ior: 1.5,
            specular: 1.0,
            specular_texture: None,
            specular_color: Vec3::ONE,
            specular_color_texture: None,
            glossiness_from_specular_texture: false,
        }
    }
}

impl Material {
    /// The material given to primitives that have none: a 0.8 grey rough dielectric
    /// (metallic 0, roughness 1), untextured. [ours] glTF's own default material is metallic
    /// 1, a white rough metal that looks black under most maps; a primitive left without a
    /// material is more likely meant as plain grey, as Blender imports it.
    pub fn default_grey() -> Material {
        Material::default()
    }

    /// A Lambertian material of `albedo` (no specular), named `name`.
    pub fn lambert(name: &str, albedo: Vec3) -> Material {
        Material {
            name: name.to_string(),
            model: Model::Lambert,
            base_color: albedo,
            ..Material::default()
        }
    }

    /// Every texture slot the material has, with what it is for (in messages).
    pub fn slots(&self) -> [(&'static str, Option<TextureSlot>); 7] {
        [
            ("baseColorTexture", self.base_color_texture),
            ("metallicRoughnessTexture", self.metallic_roughness_texture),
            ("normalTexture", self.normal_texture),
            ("occlusionTexture", self.occlusion_texture),
            ("emissiveTexture", self.emissive_texture),
            ("specularTexture", self.specular_texture),
            ("specularColorTexture", self.specular_color_texture),
        ]
    }

    /// The slots as mutable references (merging scenes shifts their texture indices).
    pub fn slots_mut(&mut self) -> [&mut Option<TextureSlot>; 7] {
        [
            &mut self.base_color_texture,
            &mut self.metallic_roughness_texture,
            &mut self.normal_texture,
            &mut self.occlusion_texture,
            &mut self.emissive_texture,
            &mut self.specular_texture,
            &mut self.specular_color_texture,
        ]
    }
}

/// What a spec's `[material]` table, or `--clay` and `--lambert`, change in the scene's
/// materials: each key given replaces what the file says, for every material (or, under
/// `[material.named."NAME"]`, for the materials of that name).
#[derive(Clone, Debug, Default, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialOverride {
    /// Linear RGB base colour, replacing the factor, the texture's colour (its alpha stays)
    /// and vertex colours.
    pub base_color: Option<[f32; 3]>,
    /// Metallic in [0, 1], replacing the factor and the texture's B channel.
    pub metallic: Option<f32>,
    /// Perceptual roughness in [0, 1], replacing the factor and the texture's G channel.
    pub roughness: Option<f32>,
    /// Linear RGB emission, replacing the factor, its strength and its texture.
    pub emissive: Option<[f32; 3]>,
    /// `true`: Lambert only (no specular), as envshadow shaded before glTF materials.
    pub lambert: Option<bool>,
    /// `false`: no texture but the normal maps (and the base colour texture's alpha).
    pub textures: Option<bool>,
    /// `false`: no normal maps.
    pub normal_maps: Option<bool>,
    /// Overrides for the materials of one name, over those above (only at the top level).
    #[serde(default)]
    pub named: std::collections::BTreeMap<String, MaterialOverride>,
}

impl MaterialOverride {
    /// `--clay`: a mid-grey, half-rough dielectric without textures but normal maps, and
    /// without emission: the form alone, for lookdev turntables.
    pub fn clay() -> MaterialOverride {
        MaterialOverride {
            base_color: Some([0.5, 0.5, 0.5]),
            metallic: Some(0.0),
            roughness: Some(0.5),
            emissive: Some([0.0, 0.0, 0.0]),
            textures: Some(false),
            ..MaterialOverride::default()
        }
    }

    /// The keys given here over those of `base` (`named` merged, this one's entries winning).
    pub fn over(&self, base: &MaterialOverride) -> MaterialOverride {
        let mut named = base.named.clone();
        named.extend(self.named.clone());
        MaterialOverride {
            base_color: self.base_color.or(base.base_color),
            metallic: self.metallic.or(base.metallic),
            roughness: self.roughness.or(base.roughness),
            emissive: self.emissive.or(base.emissive),
            lambert: self.lambert.or(base.lambert),
            textures: self.textures.or(base.textures),
            normal_maps: self.normal_maps.or(base.normal_maps),
            named,
        }
    }

    /// Whether nothing is overridden.
    pub fn is_empty(&self) -> bool {
        *self == MaterialOverride::default()
    }

    /// Why the values given are out of range, naming the key (`base_color`, `named."x".roughness`).
    pub fn problem(&self) -> Option<String> {
        self.problem_at("")
    }

    fn problem_at(&self, prefix: &str) -> Option<String> {
        let unit = |v: f32| v.is_finite() && (0.0..=1.0).contains(&v);
        let colour = |c: [f32; 3]| c.iter().all(|v| v.is_finite() && *v >= 0.0);
        if let Some(c) = self.base_color
            && !c.iter().all(|&v| unit(v))
        {
            return Some(format!(
                "{prefix}base_color = {c:?}: each component must be in [0, 1]"
            ));
        }
        for (key, v) in [("metallic", self.metallic), ("roughness", self.roughness)] {
            if let Some(v) = v
                && !unit(v)
            {
                return Some(format!("{prefix}{key} = {v}: must be in [0, 1]"));
            }
        }
        if let Some(c) = self.emissive
            && !colour(c)
        {
            return Some(format!(
                "{prefix}emissive = {c:?}: each component must be finite and ≥ 0"
            ));
        }
        for (name, o) in &self.named {
            if !prefix.is_empty() || !o.named.is_empty() {
                return Some(format!(
                    "{prefix}named.{name:?}: named overrides do not nest"
                ));
            }
            if let Some(p) = o.problem_at(&format!("named.{name:?}.")) {
                return Some(p);
            }
        }
        None
    }

    /// The keys given, as `(key, value)` spelled as a spec writes them (`named."x".roughness`).
    pub fn given(&self) -> Vec<(String, String)> {
        let mut out = Vec::new();
        let c = |c: [f32; 3]| format!("[{}, {}, {}]", c[0], c[1], c[2]);
        if let Some(v) = self.base_color {
            out.push(("base_color".to_string(), c(v)));
        }
        if let Some(v) = self.metallic {
            out.push(("metallic".to_string(), v.to_string()));
        }
        if let Some(v) = self.roughness {
            out.push(("roughness".to_string(), v.to_string()));
        }
        if let Some(v) = self.emissive {
            out.push(("emissive".to_string(), c(v)));
        }
        for (key, v) in [
            ("lambert", self.lambert),
            ("textures", self.textures),
            ("normal_maps", self.normal_maps),
        ] {
            if let Some(v) = v {
                out.push((key.to_string(), v.to_string()));
            }
        }
        for (name, o) in &self.named {
            for (k, v) in o.given() {
                out.push((format!("named.{name:?}.{k}"), v));
            }
        }
        out
    }

    /// This override's keys applied to `m` (not `named`).
    fn apply_to(&self, m: &mut Material) {
        if let Some(c) = self.base_color {
            m.base_color = Vec3::from_array(c);
            m.plain_base_color = true;
        }
        if let Some(v) = self.metallic {
            m.metallic = v;
            m.metallic_from_texture = false;
        }
        if let Some(v) = self.roughness {
            m.roughness = v;
            m.roughness_from_texture = false;
        }
        if let Some(c) = self.emissive {
            m.emissive = Vec3::from_array(c);
            m.emissive_texture = None;
        }
        match self.lambert {
            Some(true) => m.model = Model::Lambert,
            Some(false) => m.model = Model::MetallicRoughness,
            None => {}
        }
        if self.textures == Some(false) {
            // The base colour texture stays for its alpha (cut-outs keep their shape).
            m.plain_base_color = true;
            m.metallic_roughness_texture = None;
            m.occlusion_texture = None;
            m.emissive_texture = None;
            m.specular_texture = None;
            m.specular_color_texture = None;
        }
        if self.normal_maps == Some(false) {
            m.normal_texture = None;
        }
    }

    /// Applies the overrides to `materials`: the top level's to every one, then the named
    /// ones' to theirs; `over` (the command line) last, over both. A name that no material
    /// has is an error naming the materials there are.
    pub fn apply(&self, over: &MaterialOverride, materials: &mut [Material]) -> Result<(), String> {
        for name in self.named.keys().chain(over.named.keys()) {
            if !materials.iter().any(|m| &m.name == name) {
                let names: Vec<String> =
                    materials.iter().map(|m| format!("{:?}", m.name)).collect();
                return Err(format!(
                    "named.{name:?}: no material has that name (the scene's: {})",
                    names.join(", ")
                ));
            }
        }
        for m in materials.iter_mut() {
            self.apply_to(m);
            if let Some(o) = self.named.get(&m.name) {
                o.apply_to(m);
            }
            over.apply_to(m);
            if let Some(o) = over.named.get(&m.name) {
                o.apply_to(m);
            }
        }
        Ok(())
    }
}

/// A material at one surface point, textures read: what shading needs beside the base colour
/// (the surface's albedo) and the shading normal. Flat and `Copy`: one per sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialSample {
    /// Lambert only (no specular term).
    pub lambert: bool,
    /// Base colour alpha (factor × texture × vertex colour).
    pub alpha: f32,
    pub metallic: f32,
    /// Perceptual roughness in [0, 1].
    pub roughness: f32,
    /// Environment-light occlusion in [0, 1] (1: none).
    pub occlusion: f32,
    /// Emitted radiance, linear RGB.
    pub emission: Vec3,
    /// The dielectric part's specular reflectance at normal incidence (RGB) and at grazing
    /// incidence: `((ior − 1)/(ior + 1))² × specular colour × specular`, and `specular`.
    pub f0: Vec3,
    pub f90: f32,
}

impl Default for MaterialSample {
    /// A Lambertian surface, nothing else.
    fn default() -> MaterialSample {
        MaterialSample {
            lambert: true,
            alpha: 1.0,
            metallic: 0.0,
            roughness: 1.0,
            occlusion: 1.0,
            emission: Vec3::ZERO,
            f0: Vec3::splat(0.04),
            f90: 1.0,
        }
    }
}

/// What [`Scene::material_at`] gives: the base colour (the surface's albedo), the rest of the
/// material, and the shading normal after the normal map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceMaterial {
    pub base_color: Vec3,
    pub sample: MaterialSample,
    pub normal: Vec3,
}

/// Most emitted radiance a material may have (its emissive factor times
/// `KHR_materials_emissive_strength`), and most a light's colour times intensity may reach.
/// [ours] far above any real emitter in a scene's units, far enough below f32's range that
/// sums over samples and lights stay finite.
pub const MAX_EMISSION: f32 = 1e6;

impl Material {
    /// Brings the factors into the ranges glTF gives them (base colour, metallic, roughness,
    /// occlusion strength, specular in [0, 1]; emission and specular colour ≥ 0, emission at
    /// most [`MAX_EMISSION`]; ior 0 or ≥ 1) and says, for each key it changed, what it was:
    /// a factor outside them makes negative or non-finite pixels.
    pub fn clamp_factors(&mut self) -> Vec<String> {
        let mut changed = Vec::new();
        // NaN becomes 0 (spec-gloss factors reach here unchecked).
        let within = |v: f32, most: f32| if v.is_nan() { 0.0 } else { v.clamp(0.0, most) };
        let mut unit = |key: &str, v: &mut f32| {
            let c = within(*v, 1.0);
            if c.to_bits() != v.to_bits() {
                changed.push(format!("{key} {v} clamped to {c}"));
                *v = c;
            }
        };
        let mut base = self.base_color.to_array();
        for (k, v) in base.iter_mut().enumerate() {
            unit(&format!("baseColorFactor[{k}]"), v);
        }
        self.base_color = Vec3::from_array(base);
        unit("baseColorFactor[3]", &mut self.base_alpha);
        unit("metallicFactor", &mut self.metallic);
        unit("roughnessFactor", &mut self.roughness);
        unit("occlusionTexture.strength", &mut self.occlusion_strength);
        unit("KHR_materials_specular.specularFactor", &mut self.specular);
        let mut colour = |key: &str, c: &mut Vec3, most: f32| {
            let d = Vec3::from_array(c.to_array().map(|v| within(v, most)));
            if d.to_array().map(f32::to_bits) != c.to_array().map(f32::to_bits) {
                changed.push(format!("{key} {c} clamped to {d}"));
                *c = d;
            }
        };
        colour(
            "emissiveFactor × emissiveStrength",
            &mut self.emissive,
            MAX_EMISSION,
        );
        colour(
            "KHR_materials_specular.specularColorFactor",
            &mut self.specular_color,
            MAX_EMISSION,
        );
        if self.ior < 1.0 && self.ior != 0.0 {
            changed.push(format!("KHR_materials_ior.ior {} raised to 1", self.ior));
            self.ior = 1.0;
        }
        changed
    }
}

/// The dielectric F0 of an index of refraction: `((ior − 1)/(ior + 1))²` (0.04 at 1.5).
pub fn ior_f0(ior: f32) -> f32 {
    let r = (ior - 1.0) / (ior + 1.0);
    r * r
}

impl Scene {
    /// Interpolated texture coordinates of set `set` (0 or 1) at barycentric `(u, v)` of
    /// triangle `tri`; set 1 where the scene has none reads set 0's.
    pub fn uv_of_set(&self, set: u8, tri: usize, bary: (f32, f32)) -> Vec2 {
        if set == 0 || self.uvs1.is_empty() {
            return self.uv(tri, bary);
        }
        let [i0, i1, i2] = self.triangles[tri].map(|i| i as usize);
        let (u, v) = bary;
        self.uvs1[i0] * (1.0 - u - v) + self.uvs1[i1] * u + self.uvs1[i2] * v
    }

    /// [`uv_density`](Self::uv_density) of texture coordinate set `set`.
    pub fn uv_density_of_set(&self, set: u8, tri: usize) -> f32 {
        if set == 0 || self.uvs1.is_empty() {
            return self.uv_density(tri);
        }
        let [a, b, c] = self.triangle(tri);
        let world = (b - a).cross(c - a).length();
        let [ta, tb, tc] = self.triangles[tri].map(|i| self.uvs1[i as usize]);
        let uv = (tb - ta).perp_dot(tc - ta).abs();
        let density = (uv / world).sqrt();
        if density.is_finite() { density } else { 0.0 }
    }

    /// Interpolated vertex colour (`COLOR_0`, linear RGBA) at barycentric `(u, v)` of triangle
    /// `tri`; white where the scene has none.
    pub fn vertex_color(&self, tri: usize, bary: (f32, f32)) -> Vec4 {
        if self.colors.is_empty() {
            return Vec4::ONE;
        }
        let [i0, i1, i2] = self.triangles[tri].map(|i| i as usize);
        let (u, v) = bary;
        self.colors[i0] * (1.0 - u - v) + self.colors[i1] * u + self.colors[i2] * v
    }

    /// Texture `slot` read at barycentric `bary` of `tri` over a footprint `footprint_world`
    /// wide on the surface (0: point-sampled), RGBA.
    fn read(&self, slot: &TextureSlot, tri: usize, bary: (f32, f32), footprint_world: f32) -> Vec4 {
        let Some(texture) = self.textures.get(slot.texture) else {
            return Vec4::ONE;
        };
        let mut footprint = 0.0;
        if footprint_world > 0.0 {
            footprint = footprint_world * self.uv_density_of_set(slot.tex_coord, tri);
            if let Some(t) = &slot.transform {
                footprint *= t.scale();
            }
        }
        texture.lookup(self.slot_uv(slot, tri, bary), footprint, &slot.sampler)
    }

    /// The texture coordinates `slot` reads at barycentric `bary` of `tri`: its set, then its
    /// transform.
    pub(super) fn slot_uv(&self, slot: &TextureSlot, tri: usize, bary: (f32, f32)) -> Vec2 {
        let uv = self.uv_of_set(slot.tex_coord, tri, bary);
        match &slot.transform {
            Some(t) => t.apply(uv),
            None => uv,
        }
    }

    /// The base colour (linear RGB, times the vertex colour) and its alpha at barycentric
    /// `bary` of triangle `tri`, the texture filtered over `footprint_world` (0: point-sampled).
    pub fn base_color_at(&self, tri: usize, bary: (f32, f32), footprint_world: f32) -> Vec4 {
        let m = &self.materials[self.tri_material[tri] as usize];
        let mut c = m.base_color.extend(m.base_alpha);
        if let Some(slot) = &m.base_color_texture {
            // With the default sampler, the colour is the bits textured albedos always had
            // (`Texture::lookup` is `sample_footprint` then).
            let t = self.read(slot, tri, bary, footprint_world);
            if m.plain_base_color {
                c.w *= t.w;
            } else {
                c = (c.xyz() * t.xyz()).extend(c.w * t.w);
            }
        }
        if !self.colors.is_empty() {
            // A plain base colour keeps the vertex colours' alpha (cut-outs keep their shape).
            let v = self.vertex_color(tri, bary);
            c = if m.plain_base_color {
                c.xyz().extend(c.w * v.w)
            } else {
                c * v
            };
        }
        c
    }

    /// Everything shading needs of the material at barycentric `bary` of triangle `tri`, its
    /// textures filtered over a footprint `footprint_world` wide on the surface (world units;
    /// 0: point-sampled): base colour, metallic, roughness, occlusion, emission, the dielectric
    /// specular, and the shading normal `n` (unit, interpolated) bent by the normal map.
    ///
    /// A normal map whose texel is the tangent-space +Z leaves `n` as it is, bit for bit;
    /// without tangents (no UVs to make them from) the normal map is not applied.
    pub fn material_at(
        &self,
        tri: usize,
        bary: (f32, f32),
        footprint_world: f32,
        n: Vec3,
    ) -> SurfaceMaterial {
        let m = &self.materials[self.tri_material[tri] as usize];
        let base = self.base_color_at(tri, bary, footprint_world);
        let read = |slot: &Option<TextureSlot>| {
            slot.as_ref()
                .map(|s| self.read(s, tri, bary, footprint_world))
        };
        let (mut metallic, mut roughness) = (m.metallic, m.roughness);
        if let Some(t) = read(&m.metallic_roughness_texture) {
            if m.metallic_from_texture {
                metallic *= t.z;
            }
            if m.roughness_from_texture {
                roughness *= t.y;
            }
        }
        let specular_color_texel = read(&m.specular_color_texture);
        if m.glossiness_from_specular_texture
            && m.roughness_from_texture
            && let Some(t) = specular_color_texel
        {
            roughness = 1.0 - (1.0 - roughness) * t.w;
        }
        let occlusion = match read(&m.occlusion_texture) {
            Some(t) => 1.0 + m.occlusion_strength * (t.x - 1.0),
            None => 1.0,
        };
        let mut emission = m.emissive;
        if let Some(t) = read(&m.emissive_texture) {
            emission *= t.xyz();
        }
        let mut specular = m.specular;
        if let Some(t) = read(&m.specular_texture) {
            specular *= t.w;
        }
        let mut specular_color = m.specular_color;
        if let Some(t) = specular_color_texel {
            specular_color *= t.xyz();
        }
        let f0 = (specular_color * ior_f0(m.ior)).min(Vec3::ONE) * specular;
        let mut normal = n;
        if let Some(slot) = &m.normal_texture
            && !self.tangents.is_empty()
        {
            let t = self.read(slot, tri, bary, footprint_world);
            normal = self.bend(tri, bary, n, t.xyz(), m.normal_scale);
        }
        SurfaceMaterial {
            base_color: base.xyz(),
            sample: MaterialSample {
                lambert: m.model == Model::Lambert,
                alpha: base.w,
                metallic: metallic.clamp(0.0, 1.0),
                roughness: roughness.clamp(0.0, 1.0),
                occlusion: occlusion.clamp(0.0, 1.0),
                emission,
                f0,
                f90: specular,
            },
            normal,
        }
    }

    /// The shading normal `n` bent by normal-map texel `texel` (linear, in [0, 1]) with its X
    /// and Y scaled by `scale`, in the tangent frame at barycentric `bary` of `tri`: the
    /// interpolated tangent made orthogonal to `n`, the bitangent `n × t` times the tangent's
    /// handedness. A tangent-space normal of (0, 0, z > 0) returns `n` itself.
    fn bend(&self, tri: usize, bary: (f32, f32), n: Vec3, texel: Vec3, scale: f32) -> Vec3 {
        let x = (texel.x * 2.0 - 1.0) * scale;
        let y = (texel.y * 2.0 - 1.0) * scale;
        let z = texel.z * 2.0 - 1.0;
        if x == 0.0 && y == 0.0 && z > 0.0 {
            return n;
        }
        let [i0, i1, i2] = self.triangles[tri].map(|i| i as usize);
        let (u, v) = bary;
        let t4 = self.tangents[i0] * (1.0 - u - v) + self.tangents[i1] * u + self.tangents[i2] * v;
        let t = t4.xyz();
        let t = (t - n * n.dot(t)).normalize_or_zero();
        if t == Vec3::ZERO {
            return n;
        }
        let sign = if self.tangents[i0].w < 0.0 { -1.0 } else { 1.0 };
        let b = n.cross(t) * sign;
        let bent = (t * x + b * y + n * z).normalize_or_zero();
        if bent == Vec3::ZERO || !bent.is_finite() {
            n
        } else {
            bent
        }
    }
}
