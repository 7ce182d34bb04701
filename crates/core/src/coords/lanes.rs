//! Several points at a time in SIMD lanes (`wide` vectors).
//!
//! The per-edge and per-face formulas of MVC and GC are evaluated for [`LANES`] points together
//! (four: measured faster than two on the SSE2 baseline despite the register pressure). A
//! lane that meets a special case (a point on the cage, in a face's plane, …) is flagged and
//! recomputed by the scalar routine, which handles every case exactly.

use glam::DVec3;

/// One f64 per lane.
pub(crate) type Lane = wide::f64x4;

/// Points evaluated together.
pub(crate) const LANES: usize = 4;

/// Bits of every lane in a comparison mask.
pub(crate) const ALL_LANES: u32 = (1 << LANES) - 1;

/// A 3-vector per lane.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Vec3Lanes {
    pub x: Lane,
    pub y: Lane,
    pub z: Lane,
}

impl Vec3Lanes {
    /// `x − p` per lane: the same cage point seen from each lane's point.
    #[inline(always)]
    pub fn from_minus(x: DVec3, p: &[DVec3; LANES]) -> Self {
        Self {
            x: Lane::from(std::array::from_fn::<f64, LANES, _>(|l| x.x - p[l].x)),
            y: Lane::from(std::array::from_fn::<f64, LANES, _>(|l| x.y - p[l].y)),
            z: Lane::from(std::array::from_fn::<f64, LANES, _>(|l| x.z - p[l].z)),
        }
    }

    #[inline(always)]
    pub fn dot(&self, o: &Self) -> Lane {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Dot product with the same vector in every lane.
    #[inline(always)]
    pub fn dot_splat(&self, o: DVec3) -> Lane {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    #[inline(always)]
    pub fn cross(&self, o: &Self) -> Self {
        Self {
            x: self.y * o.z - self.z * o.y,
            y: self.z * o.x - self.x * o.z,
            z: self.x * o.y - self.y * o.x,
        }
    }

    #[inline(always)]
    pub fn scale(&self, s: Lane) -> Self {
        Self {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }

    #[inline(always)]
    pub fn neg(&self) -> Self {
        Self {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

/// Bit `l` set where lane `l` of the comparison mask is true.
#[inline(always)]
pub(crate) fn mask_bits(mask: Lane) -> u32 {
    mask.to_bitmask()
}
