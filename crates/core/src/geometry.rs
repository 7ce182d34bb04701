//! Small geometric primitives shared by the coordinate systems and the cage checks.

use glam::{DMat3, DVec3};

/// Signed solid angle of triangle `(a, b, c)` seen from the origin (the three arguments are
/// positions relative to the viewpoint), Van Oosterom & Strackee (1983):
/// `tan(Ω/2) = det(a, b, c) / (|a||b||c| + (a·b)|c| + (b·c)|a| + (c·a)|b|)`.
/// Positive when the origin lies behind the triangle, on the side opposite to its normal
/// `(b − a) × (c − a)`: for an outward-oriented closed cage the sum over its faces is 4π inside.
pub fn solid_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let det = a.dot(b.cross(c));
    let denom = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    2.0 * det.atan2(denom)
}

/// Closest point of triangle `(a, b, c)` to `p`, with its barycentric coordinates
/// (Ericson, *Real-Time Collision Detection*, 5.1.5).
pub fn closest_point_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> (DVec3, [f64; 3]) {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, [1.0, 0.0, 0.0]);
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, [0.0, 1.0, 0.0]);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + ab * v, [1.0 - v, v, 0.0]);
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, [0.0, 0.0, 1.0]);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + ac * w, [1.0 - w, 0.0, w]);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * w, [0.0, 1.0 - w, w]);
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    (a + ab * v + ac * w, [1.0 - v - w, v, w])
}

/// Twice the vector area of triangle `(a, b, c)`: `(b − a) × (c − a)`.
pub fn triangle_area_vector(a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    (b - a).cross(c - a)
}

/// The parameter t > 0 where the ray `origin + t·direction` crosses triangle (a, b, c)
/// (Möller and Trumbore), or `None` when it misses or runs parallel to the triangle.
pub fn ray_triangle(origin: DVec3, direction: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Option<f64> {
    let (e1, e2) = (b - a, c - a);
    let p = direction.cross(e2);
    let det = e1.dot(p);
    if det.abs() <= f64::EPSILON * e1.length() * e2.length() * direction.length() {
        return None;
    }
    let s = origin - a;
    let u = s.dot(p) / det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = direction.dot(q) / det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) / det;
    (t > 0.0).then_some(t)
}

/// Whether segment `p`–`q` meets triangle `t`, its ends and the triangle's edges included
/// (a segment lying in the triangle's plane does not).
pub fn segment_meets_triangle(p: DVec3, q: DVec3, t: [DVec3; 3]) -> bool {
    ray_triangle(p, q - p, t[0], t[1], t[2]).is_some_and(|u| u <= 1.0)
        || ray_triangle(q, p - q, t[0], t[1], t[2]).is_some_and(|u| u <= 1.0)
}

/// The generalised winding number of a triangle mesh at `p` (Jacobson et al. 2013): the sum of
/// the triangles' signed solid angles over 4π; 1 inside a closed outward mesh, 0 outside, and a
/// graceful value in between near holes. Corners outside `positions` count as at `p`.
pub fn winding_number(positions: &[DVec3], triangles: &[[u32; 3]], p: DVec3) -> f64 {
    let at = |v: u32| positions.get(v as usize).map_or(DVec3::ZERO, |q| *q - p);
    let total: f64 = triangles
        .iter()
        .map(|&[a, b, c]| solid_angle(at(a), at(b), at(c)))
        .sum();
    total / (4.0 * std::f64::consts::PI)
}

/// Whether the cells set in `mask` (of a 2×2×2 block of grid cells, bit c = x + 2y + 4z) are
/// connected through shared faces (cells differing in one bit). The empty set is connected.
/// A set of grid cells and its complement are both face-connected in every block exactly when
/// the set's surface is a manifold (no two cells meeting only along an edge or at a corner).
pub(crate) fn block_face_connected(mask: u8) -> bool {
    let Some(first) = (0..8).find(|&c| mask & (1 << c) != 0) else {
        return true;
    };
    let mut seen = 1u8 << first;
    let mut stack = vec![first];
    while let Some(c) = stack.pop() {
        for bit in [1, 2, 4] {
            let n = c ^ bit;
            if mask & (1 << n) != 0 && seen & (1 << n) == 0 {
                seen |= 1 << n;
                stack.push(n);
            }
        }
    }
    seen == mask
}

/// The scatter of `points` about `centre`: the sum of the outer products `d dᵀ` of their
/// offsets `d` (their covariance times their count). Its eigenvectors are the points' spreads:
/// the largest along their longest, the least across their best-fitting plane.
pub fn scatter_about(points: impl IntoIterator<Item = DVec3>, centre: DVec3) -> DMat3 {
    points.into_iter().fold(DMat3::ZERO, |sum, p| {
        let d = p - centre;
        sum + DMat3::from_cols(d * d.x, d * d.y, d * d.z)
    })
}

/// The eigenvector of the symmetric positive semi-definite `m` with the largest eigenvalue
/// (by power iteration from its longest column), pointing to where its largest coordinate
/// grows, and that eigenvalue; None where `m` is (nearly) zero.
pub fn dominant_eigenvector(m: DMat3) -> Option<(DVec3, f64)> {
    let columns = [m.x_axis, m.y_axis, m.z_axis];
    let scale = columns.iter().map(|c| c.length()).fold(0.0, f64::max);
    if !scale.is_finite() || scale <= 1e-12 {
        return None;
    }
    let mut v = columns
        .into_iter()
        .max_by(|a, b| a.length().total_cmp(&b.length()))?
        .normalize_or_zero();
    for _ in 0..100 {
        let next = (m * v).normalize_or_zero();
        if next == DVec3::ZERO {
            return None;
        }
        v = next;
    }
    let largest = (0..3)
        .max_by(|&a, &b| v[a].abs().total_cmp(&v[b].abs()))
        .unwrap_or(0);
    if v[largest] < 0.0 {
        v = -v;
    }
    let value = v.dot(m * v);
    (value > 1e-12 * scale).then_some((v, value))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scatter_of_points_on_a_line_spreads_along_it_only() {
        let on_x = [-2.0, 0.0, 2.0].map(|x| DVec3::new(x, 1.0, 3.0));
        let scatter = scatter_about(on_x, DVec3::new(0.0, 1.0, 3.0));
        assert_eq!(scatter.x_axis, DVec3::new(8.0, 0.0, 0.0));
        assert_eq!(scatter.y_axis, DVec3::ZERO);
        assert_eq!(scatter.z_axis, DVec3::ZERO);
        // About another centre the offsets' products across the line appear.
        assert!(scatter_about(on_x, DVec3::ZERO).y_axis.y > 0.0);
    }

    #[test]
    fn closest_point_regions() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        let (q, w) = closest_point_on_triangle(DVec3::new(0.2, 0.2, 1.0), a, b, c);
        assert!((q - DVec3::new(0.2, 0.2, 0.0)).length() < 1e-15);
        assert!((w[0] - 0.6).abs() < 1e-15);
        let (q, w) = closest_point_on_triangle(DVec3::new(-1.0, -1.0, 0.0), a, b, c);
        assert_eq!(q, a);
        assert_eq!(w, [1.0, 0.0, 0.0]);
        let (q, _) = closest_point_on_triangle(DVec3::new(1.0, 1.0, 0.0), a, b, c);
        assert!((q - DVec3::new(0.5, 0.5, 0.0)).length() < 1e-15);
    }

    #[test]
    fn solid_angle_of_octant_triangle_is_half_pi() {
        // The triangle X, Y, Z seen from the origin covers one octant: 4π / 8.
        let omega = solid_angle(DVec3::X, DVec3::Y, DVec3::Z);
        assert!((omega - std::f64::consts::FRAC_PI_2).abs() < 1e-14);
    }
}
