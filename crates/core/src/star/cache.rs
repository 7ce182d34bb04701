//! The binding cache's bytes: the compiled operator keyed by a hash of the mesh, the cages and
//! the settings, with a checksum of its content. A cache whose key or checksum does not match
//! is refused with a reason, never trusted. The file beside the scene (`SCENE.json.bind`) is
//! `starcages-io`'s.

use glam::Vec3;

use super::{BindStats, GreenDofs, JoinWeights, StarBinding, StarOperator};
use crate::scene::Scene;

/// 03: harmonic coordinates on grids centred on the cage (session 8); 04: a rest offset per row
/// (session 12). Older caches are rebuilt.
const MAGIC: &[u8; 8] = b"SCBIND04";

/// How far from 1 the stored (f32) weights of a row may sum: rounding of a few hundred f32
/// weights stays orders of magnitude below it.
const PARTITION_OF_UNITY_TOLERANCE: f64 = 1e-3;

/// FNV-1a, 64 bit: a stable hash (unlike `DefaultHasher`, fixed across Rust versions).
#[derive(Clone, Copy)]
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }

    fn bytes(mut self, bytes: &[u8]) -> Self {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
        self
    }
}

/// The key of a scene's binding: mesh (welded positions and triangles), cages and settings.
pub fn binding_key(scene: &Scene) -> u64 {
    let mut h = Fnv::new();
    for p in scene.mesh.welded_positions() {
        for c in p.to_array() {
            h = h.bytes(&c.to_le_bytes());
        }
    }
    for t in scene.mesh.welded_triangles() {
        for v in t {
            h = h.bytes(&v.to_le_bytes());
        }
    }
    // The cages' rest geometry, kinds and h values, and the settings, through their JSON form
    // (field order is fixed by the types; floats print exactly).
    let cages = serde_json::to_string(&scene.cages).unwrap_or_default();
    let settings = serde_json::to_string(&scene.settings).unwrap_or_default();
    h.bytes(cages.as_bytes()).bytes(settings.as_bytes()).0
}

/// The cache file's bytes for `binding` of `scene`: the magic `SCBIND03`, the scene's
/// [`binding_key`], an FNV-1a checksum of the payload, then the payload in little-endian 32-bit
/// words (counts, row starts, columns, f32 values, Green triangles, boundary weights, cage of
/// each row, join rows, join vertices, join weights).
pub fn encode_binding_cache(scene: &Scene, binding: &StarBinding) -> Vec<u8> {
    encode(binding_key(scene), binding)
}

/// Reads a cache file's bytes as the binding of `scene`, or says why it cannot be used: another
/// scene's key, a checksum mismatch, or (for a file whose checksum was forged) any count, index
/// or weight that does not fit the scene. Never panics and allocates no more than the bytes'
/// own size suggests.
pub fn decode_binding_cache(bytes: &[u8], scene: &Scene) -> Result<StarBinding, String> {
    let binding = decode(
        bytes,
        binding_key(scene),
        scene.cages.vertices.len(),
        scene.cages.leaves.len(),
    )?;
    if binding.operator.row_count() != scene.mesh.welded_positions().len() {
        return Err("it was written for another mesh".to_owned());
    }
    Ok(binding)
}

fn encode(key: u64, binding: &StarBinding) -> Vec<u8> {
    let (vertex_count, row_start, columns, values) = binding.operator.parts();
    let triangles = binding.operator.green_dofs().triangles();
    let mut payload = Vec::new();
    let mut put = |x: u32| payload.extend_from_slice(&x.to_le_bytes());
    let joins = &binding.join_weights;
    for n in [
        vertex_count,
        row_start.len(),
        columns.len(),
        triangles.len(),
        joins.vertex.len(),
    ] {
        put(n as u32);
    }
    row_start.iter().chain(columns).for_each(|&x| put(x));
    values.iter().for_each(|v| put(v.to_bits()));
    triangles.iter().flatten().for_each(|&x| put(x));
    binding
        .boundary_weight
        .iter()
        .for_each(|v| put(v.to_bits()));
    binding.cage_of.iter().for_each(|&x| put(x));
    joins
        .row_start
        .iter()
        .chain(&joins.vertex)
        .for_each(|&x| put(x));
    joins.weight.iter().for_each(|v| put(v.to_bits()));
    binding
        .operator
        .rest_offsets()
        .iter()
        .flat_map(|o| o.to_array())
        .for_each(|v| put(v.to_bits()));
    let mut out = Vec::with_capacity(payload.len() + 32);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&key.to_le_bytes());
    out.extend_from_slice(&Fnv::new().bytes(&payload).0.to_le_bytes());
    out.extend_from_slice(&payload);
    out
}

fn decode(
    bytes: &[u8],
    key: u64,
    cage_vertices: usize,
    leaf_count: usize,
) -> Result<StarBinding, String> {
    if bytes.len() < 24 || &bytes[..8] != MAGIC {
        return Err("not a StarCages binding cache (or an older format)".into());
    }
    let stored_key = u64::from_le_bytes(bytes[8..16].try_into().map_err(|_| "truncated")?);
    if stored_key != key {
        return Err("the mesh, cages or settings changed since it was written".into());
    }
    let checksum = u64::from_le_bytes(bytes[16..24].try_into().map_err(|_| "truncated")?);
    let payload = &bytes[24..];
    if Fnv::new().bytes(payload).0 != checksum {
        return Err("its content is corrupt (checksum mismatch)".into());
    }
    let words: Vec<u32> = payload
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    if !payload.len().is_multiple_of(4) || words.len() < 5 {
        return Err("truncated".into());
    }
    let [vertex_count, n_rows1, nnz, n_tris, n_joins] = [0, 1, 2, 3, 4].map(|i| words[i] as usize);
    if vertex_count != cage_vertices {
        return Err(format!(
            "it claims {vertex_count} cage vertices, the scene has {cage_vertices}"
        ));
    }
    let rows = n_rows1.checked_sub(1).ok_or("no rows")?;
    let expected = 5 + n_rows1 + 2 * nnz + 3 * n_tris + 2 * rows + n_rows1 + 2 * n_joins + 3 * rows;
    if words.len() != expected {
        return Err(format!(
            "truncated ({} words, {expected} expected)",
            words.len()
        ));
    }
    let mut at = 5;
    let mut take = |n: usize| {
        let slice = &words[at..at + n];
        at += n;
        slice
    };
    let row_start = take(n_rows1).to_vec();
    let columns = take(nnz).to_vec();
    let values: Vec<f32> = take(nnz).iter().map(|&b| f32::from_bits(b)).collect();
    let triangles: Vec<[u32; 3]> = take(3 * n_tris)
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let boundary_weight: Vec<f32> = take(rows).iter().map(|&b| f32::from_bits(b)).collect();
    let cage_of = take(rows).to_vec();
    let join_weights = JoinWeights {
        row_start: take(n_rows1).to_vec(),
        vertex: take(n_joins).to_vec(),
        weight: take(n_joins).iter().map(|&b| f32::from_bits(b)).collect(),
    };
    let rest_offset: Vec<Vec3> = take(3 * rows)
        .chunks_exact(3)
        .map(|o| {
            Vec3::new(
                f32::from_bits(o[0]),
                f32::from_bits(o[1]),
                f32::from_bits(o[2]),
            )
        })
        .collect();
    let join_rows_ok = join_weights.row_start.first() == Some(&0)
        && join_weights.row_start.windows(2).all(|w| w[0] <= w[1])
        && join_weights.row_start.last().map(|&l| l as usize) == Some(n_joins)
        && join_weights
            .vertex
            .iter()
            .all(|&v| (v as usize) < vertex_count);
    if !join_rows_ok || join_weights.weight.iter().any(|w| !w.is_finite()) {
        return Err("inconsistent join weights".into());
    }
    if boundary_weight.iter().any(|b| !(0.0..=1.0).contains(b)) {
        return Err("a boundary weight b is outside [0, 1]".into());
    }
    if cage_of.iter().any(|&c| c as usize >= leaf_count) {
        return Err(format!(
            "a mesh vertex names a leaf cage beyond the scene's {leaf_count}"
        ));
    }
    // Every row of *Cages reproduces translations: its cage-vertex weights sum to 1 (eqs. 1
    // and 2 for each coordinate type, kept by the blend of eq. 5). A forged file whose weights
    // would throw vertices anywhere (or to infinity) fails this.
    let unity = row_start.windows(2).all(|w| {
        let (a, b) = (w[0] as usize, w[1] as usize);
        let sum: f64 = columns
            .get(a..b)
            .into_iter()
            .flatten()
            .zip(values.get(a..b).into_iter().flatten())
            .filter(|(c, _)| (**c as usize) < vertex_count)
            .map(|(_, &v)| f64::from(v))
            .sum();
        (sum - 1.0).abs() <= PARTITION_OF_UNITY_TOLERANCE
    });
    if !unity {
        return Err("a row's weights do not sum to 1".into());
    }
    let operator = StarOperator::from_parts(
        vertex_count,
        GreenDofs::from_triangles(triangles),
        row_start,
        columns,
        values,
        rest_offset,
    )?;
    let stats = BindStats {
        operator_bytes: operator.byte_size(),
        transpose_bytes: operator.transpose_byte_size(),
        nonzeros: operator.nonzeros(),
        ..Default::default()
    };
    Ok(StarBinding {
        operator,
        boundary_weight,
        cage_of,
        join_weights,
        stats,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coords::BindControl;
    use crate::generate::demo::demo_scene;

    #[test]
    fn a_cache_claiming_another_vertex_count_is_refused_before_use() {
        let scene = demo_scene("bar", 0.2).unwrap();
        let binding = StarBinding::bind_scene(&scene, &BindControl::default()).unwrap();
        let key = binding_key(&scene);
        let bytes = encode(key, &binding);
        let count = scene.cages.vertices.len();
        assert!(decode(&bytes, key, count, scene.cages.leaves.len()).is_ok());
        // A well-formed cache (key and checksum right) for another vertex count than the scene's
        // (a crafted header claiming 0xFFFFFFF0 vertices, say) is not used.
        let error = decode(&bytes, key, 0xFFFF_FFF0, scene.cages.leaves.len())
            .err()
            .unwrap_or_default();
        assert!(error.contains("claims"), "{error}");
    }

    #[test]
    fn every_demo_reads_back_from_its_cache_bytes() {
        for (name, _) in crate::generate::demo::DEMOS {
            let scene = demo_scene(name, 0.2).unwrap();
            let binding = StarBinding::bind_scene(&scene, &BindControl::default()).unwrap();
            let read = decode_binding_cache(&encode_binding_cache(&scene, &binding), &scene);
            let read = read.unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(read.operator, binding.operator, "{name}");
        }
    }
}
