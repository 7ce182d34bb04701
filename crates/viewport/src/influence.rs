//! Influence maps painted on the mesh: the paper's b_{c_i}(p) map (red: T_{c_i} fully applied,
//! blue: the join transformation fully applied), W_n(v, p) of one boundary vertex, and the
//! difference to a single-cage deformation (Fig. 7), with the numbers a legend needs.

use glam::Vec3;
use starcages_core::star::StarBinding;

use crate::colors;

/// Which map to paint.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum InfluenceMap {
    /// The plain studio mesh.
    #[default]
    None,
    /// b_{c}(p) (eq. 11) of one leaf cage (grey elsewhere), or of every cage.
    Boundary {
        /// The leaf cage, or `None` for all of them.
        cage: Option<usize>,
    },
    /// W_n(v, p) (eq. 4) of one boundary cage vertex.
    JoinWeight {
        /// The cage vertex.
        vertex: u32,
    },
    /// |S(p) − S_single(p)| relative to the bounding box diagonal (values from
    /// [`difference`]).
    Difference,
}

/// A map's values per mesh vertex in 0..1 (NaN: no value), with what the legend says.
#[derive(Debug, Clone, PartialEq)]
pub struct MapValues {
    /// Per welded mesh vertex.
    pub values: Vec<f32>,
    /// Legend title.
    pub title: String,
    /// What 0 and 1 stand for.
    pub range: (String, String),
}

/// The b map: 1 (red) where T is fully applied, 0 (blue) on borders.
pub fn boundary(binding: &StarBinding, cage: Option<usize>) -> MapValues {
    let values = binding
        .boundary_weight
        .iter()
        .zip(&binding.cage_of)
        .map(|(&b, &c)| match cage {
            Some(only) if c as usize != only => f32::NAN,
            _ => b,
        })
        .collect();
    MapValues {
        values,
        title: "b(p): cage vs join transformation".into(),
        range: ("0: join J".into(), "1: cage T".into()),
    }
}

/// The W_n(v, p) map of boundary vertex `vertex`.
pub fn join_weight(binding: &StarBinding, vertex: u32) -> MapValues {
    MapValues {
        values: binding.join_weights.of_vertex(vertex),
        title: format!("W(v{vertex}, p): join weight"),
        range: ("0".into(), "1".into()),
    }
}

/// Maximum and RMS distance between two deformations, relative to the bounding box diagonal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DifferenceStats {
    /// Largest distance / diagonal.
    pub max: f32,
    /// Root mean square distance / diagonal.
    pub rms: f32,
}

/// Differences up to this fraction of the bounding box diagonal are f32 round-off: the two
/// deformations are shown as identical.
pub const IDENTICAL: f32 = 1e-5;

/// The difference map between `a` (*Cages) and `b` (a single-cage deformation), scaled so the
/// largest difference is 1 (all zero when they are identical to [`IDENTICAL`]), with the
/// paper's max and RMS relative to the bounding box diagonal of `a`.
pub fn difference(a: &[Vec3], b: &[Vec3]) -> (MapValues, DifferenceStats) {
    let (lo, hi) = a.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let diagonal = (hi - lo).length().max(f32::MIN_POSITIVE);
    let distances: Vec<f32> = a
        .iter()
        .zip(b)
        .map(|(p, q)| p.distance(*q) / diagonal)
        .collect();
    let max = distances.iter().copied().fold(0.0, f32::max);
    let rms = (distances.iter().map(|d| d * d).sum::<f32>() / distances.len().max(1) as f32).sqrt();
    if max <= IDENTICAL {
        // At rest (or for any pose both reproduce) the difference is f32 round-off: say so
        // rather than stretch the noise to the full colour ramp.
        return (
            MapValues {
                values: vec![0.0; distances.len()],
                title: format!(
                    "difference to single cage: identical (within {IDENTICAL:.0e} of the \
                     diagonal); pose the cages to compare"
                ),
                range: ("0".into(), "0".into()),
            },
            DifferenceStats { max, rms },
        );
    }
    let scale = if max > 0.0 { 1.0 / max } else { 0.0 };
    let values = distances.iter().map(|d| d * scale).collect();
    (
        MapValues {
            values,
            title: format!("difference to single cage: max {max:.2e}, RMS {rms:.2e}"),
            range: ("0".into(), format!("{max:.2e} of the diagonal")),
        },
        DifferenceStats { max, rms },
    )
}

/// Per-vertex colours of a map (the studio colour for no map).
pub fn vertex_colors(values: Option<&[f32]>, count: usize) -> Vec<[u8; 4]> {
    match values {
        None => vec![colors::to_u8(colors::MESH); count],
        Some(v) => v.iter().map(|&x| colors::to_u8(colors::ramp(x))).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use starcages_core::BindControl;
    use starcages_core::generate::demo::demo_scene;

    #[test]
    fn a_multi_cage_b_map_has_both_ends_and_a_join_weight_map_peaks_on_its_border() {
        let scene = demo_scene("bar", 0.3).unwrap();
        let binding = StarBinding::bind_scene(&scene, &BindControl::default()).unwrap();
        let b = boundary(&binding, None);
        assert!(b.values.iter().any(|&x| x >= 0.999));
        assert!(b.values.iter().any(|&x| x <= 0.001));
        let left = boundary(&binding, Some(0));
        assert!(left.values.iter().any(|x| x.is_nan()));
        // A vertex of the middle border.
        let border = (0..scene.cages.vertices.len() as u32)
            .find(|&v| scene.cages.vertices[v as usize].x == 0.0)
            .unwrap();
        let w = join_weight(&binding, border);
        let max = w.values.iter().copied().fold(0.0, f32::max);
        assert!(max > 0.2 && max <= 1.0 + 1e-6, "{max}");
        let colours = vertex_colors(Some(&b.values), b.values.len());
        assert!(colours.contains(&colors::to_u8(colors::ramp(1.0))));
    }

    #[test]
    fn differences_are_relative_to_the_diagonal() {
        let a = vec![Vec3::ZERO, Vec3::new(3.0, 4.0, 0.0)];
        let b = vec![Vec3::new(0.5, 0.0, 0.0), Vec3::new(3.0, 4.0, 0.0)];
        let (map, stats) = difference(&a, &b);
        assert!((stats.max - 0.1).abs() < 1e-6);
        assert!((stats.rms - (0.005f32).sqrt()).abs() < 1e-6);
        assert_eq!(map.values, vec![1.0, 0.0]);
    }
}
