//! Which leaf cages contain each mesh vertex (robust point-in-polyhedron by winding number,
//! pruned by bounding boxes, and for many points answered from each cage's [`CageLocator`]).

use glam::DVec3;
use rayon::prelude::*;

use super::cage_set::LocalCage;
use super::locator::{CageLocator, Location, exact};

/// Relative distance (to the cage's diagonal) under which a point is on a cage.
pub(crate) const ON_CAGE: f64 = 1e-9;

/// Where a point lies with respect to the leaf cages.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Containment {
    /// Cages containing the point strictly inside.
    pub inside: Vec<usize>,
    /// Cages on whose surface the point lies.
    pub on_surface: Vec<usize>,
}

impl Containment {
    /// Whether some cage contains the point (inside or on its surface).
    pub fn is_covered(&self) -> bool {
        !self.inside.is_empty() || !self.on_surface.is_empty()
    }
}

/// Containment of every point in the cages.
pub fn leaf_containment(cages: &[LocalCage], points: &[DVec3]) -> Vec<Containment> {
    let boxes: Vec<(DVec3, DVec3, f64)> = cages
        .iter()
        .map(|c| {
            let (lo, hi) = c.cage.bounds();
            let tol = ON_CAGE * c.cage.diagonal();
            (lo - DVec3::splat(tol), hi + DVec3::splat(tol), tol)
        })
        .collect();
    // A locator pays for itself once a cage has a few points per triangle to place.
    let locators: Vec<Option<CageLocator>> = cages
        .par_iter()
        .zip(&boxes)
        .map(|(c, &(lo, hi, tol))| {
            (points.len() >= 4 * c.cage.triangles().len()).then(|| {
                let in_box = points
                    .iter()
                    .filter(|p| p.cmpge(lo).all() && p.cmple(hi).all())
                    .count();
                CageLocator::for_points(&c.cage, tol, in_box)
            })
        })
        .collect();
    points
        .par_iter()
        .map(|&p| {
            let mut result = Containment::default();
            for (c, (cage, &(lo, hi, tol))) in cages.iter().zip(&boxes).enumerate() {
                if p.cmplt(lo).any() || p.cmpgt(hi).any() {
                    continue;
                }
                let location = match &locators[c] {
                    Some(locator) => locator.locate(p),
                    None => exact(&cage.cage, p, tol),
                };
                match location {
                    Location::OnSurface => result.on_surface.push(c),
                    Location::Inside => result.inside.push(c),
                    Location::Outside => {}
                }
            }
            result
        })
        .collect()
}
