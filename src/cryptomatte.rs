//! Cryptomatte (Psyop's published specification, version 1.1.0): ID mattes a compositor
//! picks objects and materials with. Each name is hashed with MurmurHash3_x86_32 (seed 0),
//! the hash turned into a float by clamping its exponent to [1, 254] (no NaN, infinity or
//! denormal); a pixel's samples are ranked by the coverage of each ID they saw, and the
//! ranks are written as `{type}00.R` = ID rank 0, `.G` = its coverage, `.B` = ID rank 1,
//! `.A` = its coverage, then `{type}01`, `{type}02` ([`RANKS`] ranks in all). The header
//! names each type under `cryptomatte/<key>/…`, `<key>` the first 7 hex digits of the type
//! name's hash: `name`, `hash` = `MurmurHash3_32`, `conversion` = `uint32_to_float32` and
//! the `manifest`, `{"name":"8 hex digits of the float's bits"}`.
//!
//! [`Ids`] is a scene's IDs: its objects (named glTF nodes, else their meshes) and its
//! materials, hashed once per run; the tile driver looks a sample's up by its triangle and
//! material and ranks a pixel's samples with [`Ranking`], which never allocates per pixel.

use std::ops::Range;

/// The ranks kept per type: three EXR layers of two ranks, the specification's suggested
/// default.
pub const RANKS: usize = 6;

/// The two types envshadow writes, by their specification names.
pub const TYPES: [&str; 2] = ["CryptoObject", "CryptoMaterial"];

/// MurmurHash3_x86_32 (Austin Appleby's, public domain) of `bytes` with `seed`.
pub fn murmur3_32(bytes: &[u8], seed: u32) -> u32 {
    const C1: u32 = 0xcc9e_2d51;
    const C2: u32 = 0x1b87_3593;
    let mix = |mut k: u32| {
        k = k.wrapping_mul(C1);
        k = k.rotate_left(15);
        k.wrapping_mul(C2)
    };
    let mut h = seed;
    let mut blocks = bytes.chunks_exact(4);
    for b in &mut blocks {
        h ^= mix(u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        h = h.rotate_left(13);
        h = h.wrapping_mul(5).wrapping_add(0xe654_6b64);
    }
    let tail = blocks.remainder();
    if !tail.is_empty() {
        let mut k = 0u32;
        for (i, &b) in tail.iter().enumerate() {
            k |= (b as u32) << (8 * i);
        }
        h ^= mix(k);
    }
    h ^= bytes.len() as u32;
    h ^= h >> 16;
    h = h.wrapping_mul(0x85eb_ca6b);
    h ^= h >> 13;
    h = h.wrapping_mul(0xc2b2_ae35);
    h ^ (h >> 16)
}

/// A hash as the float the pixels hold (`uint32_to_float32`): its bits, the exponent clamped
/// to [1, 254] so that no ID is zero (no object), a denormal, infinite or NaN.
pub fn hash_to_float(hash: u32) -> f32 {
    let exponent = ((hash >> 23) & 0xff).clamp(1, 254);
    f32::from_bits((hash & 0x807f_ffff) | (exponent << 23))
}

/// The ID of `name`: its hash as a float.
pub fn id(name: &str) -> f32 {
    hash_to_float(murmur3_32(name.as_bytes(), 0))
}

/// The metadata key of a type named `name` (`CryptoObject`, or `ViewLayer.CryptoObject` in
/// Blender's layout): the first 7 hex digits of its hash, as Blender makes it.
pub fn key(name: &str) -> String {
    format!("{:08x}", murmur3_32(name.as_bytes(), 0))[..7].to_string()
}

/// A type's manifest: `{"name":"hex"}`, names in sorted order (so the same scene always gives
/// the same header), each with the 8 hex digits of its ID's bits.
pub fn manifest(names: &[String]) -> String {
    let map: std::collections::BTreeMap<&str, String> = names
        .iter()
        .map(|n| (n.as_str(), format!("{:08x}", id(n).to_bits())))
        .collect();
    serde_json::to_string(&map).expect("a map of strings serialises")
}

/// A scene's IDs: each object's and material's name and ID, and which object each triangle
/// belongs to.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Ids {
    /// Distinct object names, sorted, and their IDs (one name may stand for several parts: the
    /// specification combines what shares a name).
    pub objects: Vec<String>,
    object_ids: Vec<f32>,
    /// Material names, one per scene material (a name may repeat), and their IDs.
    pub materials: Vec<String>,
    material_ids: Vec<f32>,
    /// Triangle ranges and their object's index, sorted by start and disjoint.
    ranges: Vec<(Range<usize>, u32)>,
}

impl Ids {
    /// The IDs of a scene whose objects are `objects` (a name and its triangles; triangles in
    /// none belong to [`UNNAMED`]) and whose materials are named `materials` (by index).
    pub fn new(objects: &[(String, Range<usize>)], materials: &[String]) -> Ids {
        let mut names: Vec<String> = objects.iter().map(|(n, _)| n.clone()).collect();
        names.push(UNNAMED.to_string());
        names.sort();
        names.dedup();
        let index = |n: &str| names.binary_search_by(|m| m.as_str().cmp(n)).unwrap() as u32;
        let mut ranges: Vec<(Range<usize>, u32)> = objects
            .iter()
            .filter(|(_, r)| !r.is_empty())
            .map(|(n, r)| (r.clone(), index(n)))
            .collect();
        ranges.sort_by_key(|(r, _)| r.start);
        Ids {
            object_ids: names.iter().map(|n| id(n)).collect(),
            objects: names,
            material_ids: materials.iter().map(|n| id(n)).collect(),
            materials: materials.to_vec(),
            ranges,
        }
    }

    /// The object names the manifest lists: every object a triangle belongs to ([`UNNAMED`]
    /// only if some triangle is in no named part).
    fn listed_objects(&self, triangles: usize) -> Vec<String> {
        let covered: usize = self.ranges.iter().map(|(r, _)| r.len()).sum();
        let mut used: Vec<bool> = vec![false; self.objects.len()];
        for (_, o) in &self.ranges {
            used[*o as usize] = true;
        }
        if covered < triangles {
            used[self.unnamed() as usize] = true;
        }
        self.objects
            .iter()
            .zip(used)
            .filter(|(_, u)| *u)
            .map(|(n, _)| n.clone())
            .collect()
    }

    fn unnamed(&self) -> u32 {
        self.objects.iter().position(|n| n == UNNAMED).unwrap() as u32
    }

    /// The ID of the object triangle `tri` belongs to.
    #[inline]
    pub fn object_id(&self, tri: u32) -> f32 {
        let tri = tri as usize;
        let k = self.ranges.partition_point(|(r, _)| r.start <= tri);
        let o = match k.checked_sub(1).map(|k| &self.ranges[k]) {
            Some((r, o)) if r.contains(&tri) => *o,
            _ => self.unnamed(),
        };
        self.object_ids[o as usize]
    }

    /// The ID of material `m`.
    #[inline]
    pub fn material_id(&self, m: u32) -> f32 {
        self.material_ids[m as usize]
    }

    /// The manifests of [`TYPES`] for a scene of `triangles` triangles: the objects some
    /// triangle belongs to, and every material.
    pub fn manifests(&self, triangles: usize) -> [String; 2] {
        let mut materials = self.materials.clone();
        materials.sort();
        materials.dedup();
        [
            manifest(&self.listed_objects(triangles)),
            manifest(&materials),
        ]
    }
}

/// The name of the triangles no named part holds (shapes made in code, merged scenes).
pub const UNNAMED: &str = "unnamed";

/// One pixel's IDs and their weights, gathered sample by sample and ranked: a buffer kept
/// across pixels (sized once for the samples per pixel), so ranking allocates nothing.
#[derive(Clone, Debug, Default)]
pub struct Ranking {
    seen: Vec<(f32, f32)>,
}

impl Ranking {
    /// An empty ranking for pixels of up to `samples` samples.
    pub fn new(samples: usize) -> Ranking {
        Ranking {
            seen: Vec::with_capacity(samples),
        }
    }

    /// Starts a pixel.
    #[inline]
    pub fn clear(&mut self) {
        self.seen.clear();
    }

    /// Adds `weight` to `id`.
    #[inline]
    pub fn add(&mut self, id: f32, weight: f32) {
        match self
            .seen
            .iter_mut()
            .find(|(i, _)| i.to_bits() == id.to_bits())
        {
            Some((_, w)) => *w += weight,
            None => self.seen.push((id, weight)),
        }
    }

    /// The pixel's ranks, highest coverage first (ties by the ID's bits, so the order never
    /// depends on the samples' order), as (ID, coverage); 0 past the IDs seen.
    pub fn ranks(&mut self) -> [(f32, f32); RANKS] {
        self.seen.sort_unstable_by(|a, b| {
            b.1.total_cmp(&a.1)
                .then_with(|| a.0.to_bits().cmp(&b.0.to_bits()))
        });
        let mut out = [(0.0, 0.0); RANKS];
        for (o, s) in out.iter_mut().zip(&self.seen) {
            *o = *s;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// MurmurHash3_x86_32's published values (the reference implementation's, as the `mmh3`
    /// and `murmurhash3` packages test them).
    #[test]
    fn murmur3_matches_its_published_values() {
        assert_eq!(murmur3_32(b"", 0), 0);
        assert_eq!(murmur3_32(b"", 1), 0x514e_28b7);
        assert_eq!(murmur3_32(b"", 0xffff_ffff), 0x81f1_6f39);
        assert_eq!(murmur3_32(b"\0\0\0\0", 0), 0x2362_f9de);
        assert_eq!(murmur3_32(b"hello", 0), 0x248b_fa47);
        assert_eq!(murmur3_32(b"Hello, world!", 1234), 0xfaf6_cdb3);
        assert_eq!(
            murmur3_32(b"The quick brown fox jumps over the lazy dog", 0),
            0x2e4f_f723
        );
    }

    /// The specification's example manifest: "bunny" is 13851a76, "default" 42c9679f and
    /// "bunny_porcelain_mat" b24b26d4.
    #[test]
    fn names_hash_to_the_specifications_example_ids() {
        assert_eq!(id("bunny").to_bits(), 0x1385_1a76);
        assert_eq!(id("default").to_bits(), 0x42c9_679f);
        assert_eq!(id("bunny_porcelain_mat").to_bits(), 0xb24b_26d4);
        assert_eq!(
            manifest(&["default".into(), "bunny".into()]),
            r#"{"bunny":"13851a76","default":"42c9679f"}"#
        );
    }

    /// The exponent is clamped: no ID is zero, denormal, infinite or NaN; other bits pass.
    #[test]
    fn hashes_become_finite_normal_floats() {
        for h in [
            0u32,
            0x0000_0001,
            0x807f_ffff,
            0x7f80_0000,
            0xffff_ffff,
            0x3f80_0000,
        ] {
            let f = hash_to_float(h);
            assert!(f.is_normal(), "{h:08x} → {f}");
            assert_eq!(f.to_bits() & 0x807f_ffff, h & 0x807f_ffff);
        }
        assert_eq!(hash_to_float(0x3f80_0000), 1.0);
        assert_eq!(hash_to_float(0).to_bits(), 0x0080_0000);
        assert_eq!(hash_to_float(0xffff_ffff).to_bits(), 0xff7f_ffff);
    }

    /// Blender's metadata key: the first 7 hex digits of the type name's hash.
    #[test]
    fn a_types_key_is_seven_hex_digits_of_its_hash() {
        let k = key("CryptoObject");
        assert_eq!(k.len(), 7);
        assert_eq!(
            k,
            format!("{:08x}", murmur3_32(b"CryptoObject", 0))[..7].to_string()
        );
    }

    /// A triangle's object is the part holding it; others are `unnamed`; the manifest lists
    /// only objects some triangle belongs to, and every material once.
    #[test]
    fn triangles_find_their_objects() {
        let ids = Ids::new(
            &[
                ("b".into(), 10..20),
                ("a".into(), 0..5),
                ("b".into(), 30..31),
            ],
            &["m".into(), "m".into(), "n".into()],
        );
        assert_eq!(ids.object_id(0), id("a"));
        assert_eq!(ids.object_id(4), id("a"));
        assert_eq!(ids.object_id(5), id(UNNAMED));
        assert_eq!(ids.object_id(19), id("b"));
        assert_eq!(ids.object_id(30), id("b"));
        assert_eq!(ids.object_id(31), id(UNNAMED));
        assert_eq!(ids.material_id(2), id("n"));
        let [objects, materials] = ids.manifests(31);
        assert!(objects.contains("\"a\"") && objects.contains("\"unnamed\""));
        assert_eq!(materials, manifest(&["m".into(), "n".into()]));
        let whole = Ids::new(&[("a".into(), 0..5)], &[]);
        assert!(!whole.manifests(5)[0].contains(UNNAMED));
    }

    /// Ranks: by coverage, ties by ID, zeros past the IDs seen, whatever the samples' order.
    #[test]
    fn ranks_sort_by_coverage_then_id() {
        let mut r = Ranking::new(8);
        for (id, w) in [(2.0, 0.25), (1.0, 0.25), (3.0, 0.25), (1.0, 0.125)] {
            r.add(id, w);
        }
        let ranks = r.ranks();
        assert_eq!(ranks[0], (1.0, 0.375));
        assert_eq!(ranks[1], (2.0, 0.25));
        assert_eq!(ranks[2], (3.0, 0.25));
        assert_eq!(ranks[3], (0.0, 0.0));
        r.clear();
        assert_eq!(r.ranks(), [(0.0, 0.0); RANKS]);
    }
}
