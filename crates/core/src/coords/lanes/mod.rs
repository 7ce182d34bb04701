//! Several points at a time in SIMD lanes, with the instruction set chosen at run time.
//!
//! The per-edge and per-face formulas of MVC and GC are evaluated for [`LANES`] points together
//! (four: measured faster than two on the SSE2 baseline despite the register pressure). A lane
//! that meets a special case (a point on the cage, in a face's plane, …) is flagged and
//! recomputed by the scalar routine, which handles every case exactly.
//!
//! The kernels are written once, generic over [`Lane`], and [`run_kernel`] instantiates them
//! for the best backend this CPU has:
//!
//! * [`portable`]: `wide::f64x4`, SSE2 on any x86-64 (NEON on Arm), what the build targets;
//! * `avx2` (x86-64 only): AVX2 registers with fused multiply-add, picked when the CPU reports
//!   both features, so a portable build still runs at AVX2 speed on machines that have it.
//!
//! `ln` and `atan2`, the only transcendental functions the kernels need, are ours
//! ([`math`]): one division each, shared by both backends.

#[cfg(target_arch = "x86_64")]
mod avx2;
pub(crate) mod math;
mod portable;

use std::fmt::Debug;
use std::ops::{Add, AddAssign, BitAnd, BitOr, Div, Mul, Neg, Not, Sub, SubAssign};

use glam::DVec3;

/// Points evaluated together.
pub(crate) const LANES: usize = 4;

/// Bits of every lane in a comparison mask.
pub(crate) const ALL_LANES: u32 = (1 << LANES) - 1;

/// One f64 per lane, [`LANES`] lanes: the operations the coordinate kernels need.
///
/// Every method is `#[inline(always)]` in the implementations, so that a kernel instantiated
/// inside a `#[target_feature]` function is compiled for that instruction set as a whole.
pub(crate) trait Lane:
    Copy
    + Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
{
    /// A lane-wise comparison result.
    type Mask: Copy
        + BitAnd<Output = Self::Mask>
        + BitOr<Output = Self::Mask>
        + Not<Output = Self::Mask>;

    /// The same value in every lane.
    fn splat(x: f64) -> Self;
    /// Lane `l` from `a[l]`.
    fn from_array(a: [f64; LANES]) -> Self;
    /// The lanes as an array.
    fn to_array(self) -> [f64; LANES];
    /// `self · a + b`, fused (one rounding) where the backend has FMA.
    fn mul_add(self, a: Self, b: Self) -> Self;
    /// `self · a − b`, fused (one rounding) where the backend has FMA.
    fn mul_sub(self, a: Self, b: Self) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// Lane-wise minimum.
    fn min(self, o: Self) -> Self;
    /// Lane-wise maximum.
    fn max(self, o: Self) -> Self;
    /// `self < o` (false where either is NaN).
    fn lt(self, o: Self) -> Self::Mask;
    /// `self <= o` (false where either is NaN).
    fn le(self, o: Self) -> Self::Mask;
    /// `self > o` (false where either is NaN).
    fn gt(self, o: Self) -> Self::Mask;
    /// `self >= o` (false where either is NaN).
    fn ge(self, o: Self) -> Self::Mask;
    /// `a` where `mask` is set, `b` elsewhere.
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self;
    /// Bit `l` set where lane `l` of `mask` is set.
    fn bitmask(mask: Self::Mask) -> u32;
    /// For a positive, finite, normal `self = 2^e m` with m in [1, 2): `(e, m)`.
    fn split_exponent(self) -> (Self, Self);

    /// Zero in every lane.
    #[inline(always)]
    fn zero() -> Self {
        Self::splat(0.0)
    }

    /// Natural logarithm of positive, finite, normal lanes ([`math::ln`]).
    #[inline(always)]
    fn ln(self) -> Self {
        math::ln(self)
    }

    /// `atan2(self, x)` in (−π, π] ([`math::atan2`]).
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        math::atan2(self, x)
    }
}

/// A computation generic over the lane backend, run by [`run_kernel`] with the best one.
pub(crate) trait LaneKernel {
    /// What the kernel returns.
    type Output;
    /// Runs the kernel with lanes `L`. Implementations must be `#[inline(always)]`, and so must
    /// everything they call that does lane arithmetic: it is compiled inside the caller's
    /// `#[target_feature]` function.
    fn run<L: Lane>(self) -> Self::Output;
}

/// Runs `kernel` with AVX2 + FMA lanes where this CPU has them, portable lanes otherwise.
pub(crate) fn run_kernel<K: LaneKernel>(kernel: K) -> K::Output {
    #[cfg(target_arch = "x86_64")]
    if let Some(token) = avx2_token() {
        return token.run(kernel);
    }
    kernel.run::<portable::Portable>()
}

/// Environment variable that, set to `portable`, keeps the kernels on the portable backend
/// (to measure it, or to rule the AVX2 path out when chasing a difference).
pub const SIMD_ENV: &str = "STARCAGES_SIMD";

/// The AVX2 token, unless the CPU lacks AVX2/FMA or [`SIMD_ENV`] asks for portable lanes.
#[cfg(target_arch = "x86_64")]
fn avx2_token() -> Option<avx2::Avx2Token> {
    static PORTABLE_ONLY: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let portable_only =
        *PORTABLE_ONLY.get_or_init(|| std::env::var(SIMD_ENV).is_ok_and(|v| v == "portable"));
    if portable_only {
        None
    } else {
        avx2::Avx2Token::detect()
    }
}

/// Runs `kernel` once with every backend this CPU supports, for tests that compare them.
#[cfg(test)]
pub(crate) fn run_every_backend<K: LaneKernel + Clone>(
    kernel: K,
) -> Vec<(&'static str, K::Output)> {
    let mut out = vec![("portable", kernel.clone().run::<portable::Portable>())];
    #[cfg(target_arch = "x86_64")]
    if let Some(token) = avx2::Avx2Token::detect() {
        out.push(("avx2", token.run(kernel)));
    }
    out
}

/// The SIMD backend the coordinate kernels use on this CPU ("avx2+fma", "sse2" or
/// "portable"), for reports.
pub fn lane_backend() -> &'static str {
    #[cfg(target_arch = "x86_64")]
    if avx2_token().is_some() {
        return "avx2+fma";
    }
    portable::NAME
}

/// A 3-vector per lane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Vec3Lanes<L> {
    pub x: L,
    pub y: L,
    pub z: L,
}

impl<L: Lane> Vec3Lanes<L> {
    /// `x − p` per lane: the same cage point seen from each lane's point.
    #[inline(always)]
    pub fn from_minus(x: DVec3, p: &[DVec3; LANES]) -> Self {
        Self {
            x: L::from_array(std::array::from_fn(|l| x.x - p[l].x)),
            y: L::from_array(std::array::from_fn(|l| x.y - p[l].y)),
            z: L::from_array(std::array::from_fn(|l| x.z - p[l].z)),
        }
    }

    /// Dot product, lane by lane.
    #[inline(always)]
    pub fn dot(&self, o: &Self) -> L {
        self.x.mul_add(o.x, self.y.mul_add(o.y, self.z * o.z))
    }

    /// Dot product with the same vector in every lane.
    #[inline(always)]
    pub fn dot_splat(&self, o: DVec3) -> L {
        self.x.mul_add(
            L::splat(o.x),
            self.y.mul_add(L::splat(o.y), self.z * L::splat(o.z)),
        )
    }

    /// Cross product, lane by lane.
    #[inline(always)]
    pub fn cross(&self, o: &Self) -> Self {
        Self {
            x: self.y.mul_sub(o.z, self.z * o.y),
            y: self.z.mul_sub(o.x, self.x * o.z),
            z: self.x.mul_sub(o.y, self.y * o.x),
        }
    }

    /// The opposite vector.
    #[inline(always)]
    pub fn neg(&self) -> Self {
        Self {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}
