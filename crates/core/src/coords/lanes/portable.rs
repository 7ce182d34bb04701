//! The portable backend: `wide::f64x4`, whose instruction set is fixed when the crate is
//! compiled (SSE2 on a default x86-64 build, NEON on aarch64).

use wide::{f64x4, u64x4};

use super::{LANES, Lane};

/// Name of this backend in reports.
pub(super) const NAME: &str = if cfg!(target_arch = "x86_64") {
    "sse2"
} else {
    "portable"
};

/// Portable lanes.
pub(crate) type Portable = f64x4;

impl Lane for f64x4 {
    type Mask = f64x4;

    #[inline(always)]
    fn splat(x: f64) -> Self {
        f64x4::splat(x)
    }
    #[inline(always)]
    fn from_array(a: [f64; LANES]) -> Self {
        f64x4::from(a)
    }
    #[inline(always)]
    fn to_array(self) -> [f64; LANES] {
        f64x4::to_array(self)
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        // Not f64x4::mul_add: without FMA in the build it is the same two roundings, and
        // this keeps the portable results independent of the build's target features.
        self * a + b
    }
    #[inline(always)]
    fn mul_sub(self, a: Self, b: Self) -> Self {
        self * a - b
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64x4::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f64x4::abs(self)
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        f64x4::fast_min(self, o)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        f64x4::fast_max(self, o)
    }
    #[inline(always)]
    fn lt(self, o: Self) -> Self::Mask {
        f64x4::simd_lt(self, o)
    }
    #[inline(always)]
    fn le(self, o: Self) -> Self::Mask {
        f64x4::simd_le(self, o)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> Self::Mask {
        f64x4::simd_gt(self, o)
    }
    #[inline(always)]
    fn ge(self, o: Self) -> Self::Mask {
        f64x4::simd_ge(self, o)
    }
    #[inline(always)]
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self {
        <f64x4 as wide::Select<f64x4>>::select(mask, a, b)
    }
    #[inline(always)]
    fn bitmask(mask: Self::Mask) -> u32 {
        mask.to_bitmask()
    }
    #[inline(always)]
    fn split_exponent(self) -> (Self, Self) {
        let bits: u64x4 = self.to_bits();
        // The biased exponent as a float: OR it into the mantissa of 2^52, subtract 2^52.
        let two52 = f64x4::splat(4_503_599_627_370_496.0);
        let biased = f64x4::from_bits((bits >> 52) | two52.to_bits());
        let exponent = biased - (two52 + f64x4::splat(1023.0));
        let mantissa = f64x4::from_bits(
            (bits & u64x4::splat(0x000F_FFFF_FFFF_FFFF)) | u64x4::splat(0x3FF0_0000_0000_0000),
        );
        (exponent, mantissa)
    }
}
