//! The secant method for one joint's scale: the ring's scale at which its region's volume is
//! its rest volume.

/// A region's volume change (as a share of its rest volume) below which its joint is left as
/// the mitre put it: a settled pose settled again does not move.
pub(super) const SETTLED: f64 = 1e-3;

/// The share the secant method stops at.
const SOLVED: f64 = 1e-4;

/// Evaluations of the region per joint and sweep, at most.
const MAX_EVALUATIONS: usize = 10;

/// The range of the ring's scale: a ring narrowed by more than 40 % pinches the limb; one
/// widened on the outer side is bounded by how far it stretches the surface (`mod.rs`,
/// `MAX_WIDENING_STRETCH`), which stops it within 4 times its radius on a mesh with vertices
/// near the joint (the CLI's box arm, with none, goes to 4); a region whose volume needs more
/// is left at the bound.
pub(super) const S_MIN: f64 = -0.4;
pub(super) const S_MAX: f64 = 4.0;

/// The least share of a region's volume change the ring's best scale must take back per unit
/// of scale for the ring to move at all (see [`solve`]): a widening by 0.8 must take back a
/// tenth of it.
const LEAST_TAKEN_BACK_PER_SCALE: f64 = 0.125;

/// What [`solve`] found: the scale, and the last one it evaluated (where the ring was left).
pub(super) struct Solved {
    pub(super) scale: f64,
    pub(super) last: f64,
}

/// The scale `s` at which `excess(s)` (the region's volume less its rest volume) vanishes, by
/// the secant method from 0 and `start` (a previous solution, when it widens or narrows as
/// this one must; else ±0.05) within [`S_MIN`, `S_MAX`]; 0 when the region is settled
/// already or when the best evaluated takes back less than [`LEAST_TAKEN_BACK_PER_SCALE`] of
/// the change per unit of scale, the best evaluated otherwise.
pub(super) fn solve(mut excess: impl FnMut(f64) -> f64, rest_volume: f64, start: f64) -> Solved {
    let e0 = excess(0.0);
    let size = rest_volume.abs();
    if !e0.is_finite() || e0.abs() <= SETTLED * size {
        return Solved {
            scale: 0.0,
            last: 0.0,
        };
    }
    // Lost volume (a change against the region's orientation): widen; gained: narrow.
    let widen = e0 * rest_volume < 0.0;
    let (mut s0, mut e_prev) = (0.0, e0);
    let mut s1 = match (widen, start) {
        (true, s) if s > 0.0 && s <= S_MAX => s,
        (false, s) if (S_MIN..0.0).contains(&s) => s,
        (true, _) => 0.05,
        (false, _) => -0.05,
    };
    let mut e1 = excess(s1);
    let mut best = (0.0, e0.abs());
    for _ in 2..MAX_EVALUATIONS {
        if e1.is_finite() && e1.abs() < best.1 {
            best = (s1, e1.abs());
        }
        if !e1.is_finite() || e1.abs() <= SOLVED * size {
            break;
        }
        let slope = (e1 - e_prev) / (s1 - s0);
        if !(slope.is_finite() && slope != 0.0) {
            break;
        }
        let s2 = (s1 - e1 / slope).clamp(S_MIN, S_MAX);
        if s2 == s1 {
            break;
        }
        (s0, e_prev, s1) = (s1, e1, s2);
        e1 = excess(s1);
    }
    if e1.is_finite() && e1.abs() < best.1 {
        best = (s1, e1.abs());
    }
    // The ring's whole range barely changes the region: its change lies elsewhere than at the
    // joint, and widening it to the bound only makes a lump (the bunny's head tilted 30°: its
    // region, most of the bunny, lost 0.5 %, of which a widening by 0.8 took back 4 % while
    // the ring moved out by 0.2 of the bunny's size into a spike).
    if e0.abs() - best.1 < LEAST_TAKEN_BACK_PER_SCALE * best.0.abs() * e0.abs() {
        best = (0.0, e0.abs());
    }
    Solved {
        scale: best.0,
        last: s1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_secant_method_finds_the_scale_of_a_cubic_volume() {
        // A region whose volume grows as (1 + s)³ and stands at 0.8 of its rest volume.
        let found = solve(|s| 0.8 * (1.0 + s).powi(3) - 1.0, 1.0, 0.0);
        let exact = 0.8f64.powf(-1.0 / 3.0) - 1.0;
        assert!(
            (found.scale - exact).abs() < 1e-3,
            "{} against {exact}",
            found.scale
        );
        // Started from a previous solution near it, the same answer.
        let warm = solve(|s| 0.8 * (1.0 + s).powi(3) - 1.0, 1.0, 0.07);
        assert!((warm.scale - exact).abs() < 1e-3);
        // A gain narrows the ring (s < 0).
        let gain = solve(|s| 1.3 * (1.0 + s).powi(3) - 1.0, 1.0, 0.0);
        assert!(gain.scale < 0.0);
    }

    #[test]
    fn a_settled_region_is_left_and_an_unreachable_one_stops_at_the_bound() {
        let settled = solve(|s| 1e-5 + s, 1.0, 0.0);
        assert_eq!((settled.scale, settled.last), (0.0, 0.0));
        // A region that would need the ring six times as wide: as far as it may go.
        let far = solve(|s| 0.005 * (1.0 + s).powi(3) - 1.0, 1.0, 0.0);
        assert_eq!(far.scale, S_MAX);
        // A negative orientation (a mesh wound inwards): the same scale.
        let inward = solve(|s| -(0.8 * (1.0 + s).powi(3) - 1.0), -1.0, 0.0);
        let outward = solve(|s| 0.8 * (1.0 + s).powi(3) - 1.0, 1.0, 0.0);
        assert!((inward.scale - outward.scale).abs() < 1e-9);
    }

    /// A region the ring's whole range barely changes (its loss lies elsewhere) leaves the
    /// ring where the mitre put it instead of widening it to the bound; one the bound helps
    /// enough still goes there.
    #[test]
    fn a_region_the_ring_barely_changes_is_left_at_the_mitre() {
        // 0.5 % lost, of which a widening by 0.8 takes back 4 % (the bunny's head) and the
        // bound a fifth.
        let insensitive = solve(|s| -0.005 + 0.000_25 * s, 1.0, 0.0);
        assert_eq!(insensitive.scale, 0.0);
        // Where the bound takes back four fifths of it, the ring goes to the bound.
        let helped = solve(|s| -0.005 + 0.001 * s, 1.0, 0.0);
        assert_eq!(helped.scale, S_MAX);
    }
}
