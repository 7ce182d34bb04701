//! The AVX2 + FMA backend (x86-64), chosen at run time by [`Avx2Token::detect`].
//!
//! # Safety
//!
//! This is the crate's one use of `unsafe`. The intrinsics below need AVX2 and FMA, which
//! the portable build does not assume. They are sound because [`Avx2`] values only ever exist
//! inside a kernel run by [`Avx2Token::run`], and an [`Avx2Token`] can only be made by
//! [`Avx2Token::detect`], after the CPU has reported both features. Every operation is
//! `#[inline(always)]`, so the whole kernel is compiled inside `run_avx2`, whose
//! `#[target_feature]` lets the intrinsics inline into plain vector instructions.
#![allow(unsafe_code)]

use std::arch::x86_64::*;
use std::ops::{Add, AddAssign, BitAnd, BitOr, Div, Mul, Neg, Not, Sub, SubAssign};

use super::{LANES, Lane, LaneKernel};

/// Proof that this CPU has AVX2 and FMA.
#[derive(Debug, Clone, Copy)]
pub(super) struct Avx2Token(());

impl Avx2Token {
    /// The token, if the CPU has AVX2 and FMA (the check is cached by `std`).
    pub(super) fn detect() -> Option<Self> {
        (is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma")).then_some(Self(()))
    }

    /// Runs `kernel` with [`Avx2`] lanes.
    pub(super) fn run<K: LaneKernel>(self, kernel: K) -> K::Output {
        // SAFETY: the token exists, so the CPU has AVX2 and FMA (see `detect`).
        unsafe { run_avx2(kernel) }
    }
}

/// The kernel compiled with AVX2 and FMA enabled.
#[target_feature(enable = "avx2,fma")]
unsafe fn run_avx2<K: LaneKernel>(kernel: K) -> K::Output {
    kernel.run::<Avx2>()
}

/// Four f64 in one AVX register.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx2(__m256d);

/// A comparison result: all bits set in the lanes where it holds.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx2Mask(__m256d);

macro_rules! binary_op {
    ($trait:ident, $method:ident, $intrinsic:ident) => {
        impl $trait for Avx2 {
            type Output = Self;
            #[inline(always)]
            fn $method(self, o: Self) -> Self {
                // SAFETY: see the module documentation.
                Self(unsafe { $intrinsic(self.0, o.0) })
            }
        }
    };
}
binary_op!(Add, add, _mm256_add_pd);
binary_op!(Sub, sub, _mm256_sub_pd);
binary_op!(Mul, mul, _mm256_mul_pd);
binary_op!(Div, div, _mm256_div_pd);

impl AddAssign for Avx2 {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl SubAssign for Avx2 {
    #[inline(always)]
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}

impl Neg for Avx2 {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        // SAFETY: see the module documentation.
        Self(unsafe { _mm256_xor_pd(self.0, _mm256_set1_pd(-0.0)) })
    }
}

macro_rules! mask_op {
    ($trait:ident, $method:ident, $intrinsic:ident) => {
        impl $trait for Avx2Mask {
            type Output = Self;
            #[inline(always)]
            fn $method(self, o: Self) -> Self {
                // SAFETY: see the module documentation.
                Self(unsafe { $intrinsic(self.0, o.0) })
            }
        }
    };
}
mask_op!(BitAnd, bitand, _mm256_and_pd);
mask_op!(BitOr, bitor, _mm256_or_pd);

impl Not for Avx2Mask {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        // SAFETY: see the module documentation.
        Self(unsafe { _mm256_xor_pd(self.0, _mm256_castsi256_pd(_mm256_set1_epi64x(-1))) })
    }
}

/// A comparison with predicate `P` (ordered, quiet: false where either side is NaN).
#[inline(always)]
fn compare<const P: i32>(a: Avx2, b: Avx2) -> Avx2Mask {
    // SAFETY: see the module documentation.
    Avx2Mask(unsafe { _mm256_cmp_pd::<P>(a.0, b.0) })
}

impl Lane for Avx2 {
    type Mask = Avx2Mask;

    #[inline(always)]
    fn splat(x: f64) -> Self {
        // SAFETY: see the module documentation.
        Self(unsafe { _mm256_set1_pd(x) })
    }
    #[inline(always)]
    fn from_array(a: [f64; LANES]) -> Self {
        // SAFETY: see the module documentation; the load reads the four f64 of `a`.
        Self(unsafe { _mm256_loadu_pd(a.as_ptr()) })
    }
    #[inline(always)]
    fn to_array(self) -> [f64; LANES] {
        let mut out = [0.0; LANES];
        // SAFETY: see the module documentation; the store writes the four f64 of `out`.
        unsafe { _mm256_storeu_pd(out.as_mut_ptr(), self.0) };
        out
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        // SAFETY: see the module documentation.
        Self(unsafe { _mm256_fmadd_pd(self.0, a.0, b.0) })
    }
    #[inline(always)]
    fn mul_sub(self, a: Self, b: Self) -> Self {
        // SAFETY: see the module documentation.
        Self(unsafe { _mm256_fmsub_pd(self.0, a.0, b.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: see the module documentation.
        Self(unsafe { _mm256_sqrt_pd(self.0) })
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: see the module documentation.
        Self(unsafe { _mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0) })
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        // SAFETY: see the module documentation.
        Self(unsafe { _mm256_min_pd(self.0, o.0) })
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        // SAFETY: see the module documentation.
        Self(unsafe { _mm256_max_pd(self.0, o.0) })
    }
    #[inline(always)]
    fn lt(self, o: Self) -> Avx2Mask {
        compare::<_CMP_LT_OQ>(self, o)
    }
    #[inline(always)]
    fn le(self, o: Self) -> Avx2Mask {
        compare::<_CMP_LE_OQ>(self, o)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> Avx2Mask {
        compare::<_CMP_GT_OQ>(self, o)
    }
    #[inline(always)]
    fn ge(self, o: Self) -> Avx2Mask {
        compare::<_CMP_GE_OQ>(self, o)
    }
    #[inline(always)]
    fn select(mask: Avx2Mask, a: Self, b: Self) -> Self {
        // SAFETY: see the module documentation.
        Self(unsafe { _mm256_blendv_pd(b.0, a.0, mask.0) })
    }
    #[inline(always)]
    fn bitmask(mask: Avx2Mask) -> u32 {
        // SAFETY: see the module documentation.
        (unsafe { _mm256_movemask_pd(mask.0) }) as u32
    }
    #[inline(always)]
    fn split_exponent(self) -> (Self, Self) {
        // SAFETY: see the module documentation.
        unsafe {
            let bits = _mm256_castpd_si256(self.0);
            // The biased exponent as a float: OR it into the mantissa of 2^52, subtract 2^52.
            let two52 = _mm256_set1_pd(4_503_599_627_370_496.0);
            let biased = _mm256_castsi256_pd(_mm256_or_si256(
                _mm256_srli_epi64::<52>(bits),
                _mm256_castpd_si256(two52),
            ));
            let exponent = _mm256_sub_pd(biased, _mm256_set1_pd(4_503_599_627_370_496.0 + 1023.0));
            let mantissa = _mm256_castsi256_pd(_mm256_or_si256(
                _mm256_and_si256(bits, _mm256_set1_epi64x(0x000F_FFFF_FFFF_FFFF)),
                _mm256_set1_epi64x(0x3FF0_0000_0000_0000),
            ));
            (Self(exponent), Self(mantissa))
        }
    }
}
