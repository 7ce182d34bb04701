//! `ln` and `atan2` in SIMD lanes, written against [`Lane`]'s primitives so that both backends
//! share them. Each costs one division; the polynomials are near-minimax fits (relative error
//! below 1e-17 in exact arithmetic) made by `scripts/fit_simd_polynomials.py`.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI, SQRT_2};

use super::Lane;

/// ln 2 with its low 21 bits cleared (so e · LN2_HI is exact for any f64 exponent e) …
const LN2_HI: f64 = 0.693_147_180_369_123_8;
/// … and the rest of ln 2.
const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;

/// atanh(s) / s = Σ z^k / (2k + 1) as a polynomial in z = s², for |s| ≤ (√2 − 1) / (√2 + 1).
const LN_POLY: [f64; 8] = [
    1.0,
    0.33333333333333826,
    0.19999999999650817,
    0.14285714380392664,
    0.11111098521383353,
    0.09091816188210201,
    0.07656255467088043,
    0.07404938778032384,
];

/// atan(r) / r as a polynomial in z = r², for |r| ≤ tan(π/8).
const ATAN_POLY: [f64; 12] = [
    1.0,
    -0.3333333333333312,
    0.19999999999941293,
    -0.14285714279286357,
    0.11111110746593866,
    -0.09090896854376548,
    0.07692046095886407,
    -0.06662960111411394,
    0.05846936137835164,
    -0.05035352889244637,
    0.0379713866776672,
    -0.01781187659908209,
];

/// tan(π/8) = √2 − 1.
const TAN_PI_8: f64 = SQRT_2 - 1.0;

/// Σ c_k z^k by Horner's rule.
#[inline(always)]
fn polynomial<L: Lane, const N: usize>(z: L, c: &[f64; N]) -> L {
    let mut acc = L::splat(c[N - 1]);
    for &k in c[..N - 1].iter().rev() {
        acc = acc.mul_add(z, L::splat(k));
    }
    acc
}

/// Natural logarithm of lanes that are positive, finite and normal; other lanes get a
/// meaningless value, so callers flag them first.
///
/// x = 2^e m with m in [√2/2, √2); ln x = e ln 2 + 2 atanh(s) with s = (m − 1) / (m + 1).
#[inline(always)]
pub(crate) fn ln<L: Lane>(x: L) -> L {
    let one = L::splat(1.0);
    let (e, m) = x.split_exponent();
    let high = m.gt(L::splat(SQRT_2));
    let m = L::select(high, m * L::splat(0.5), m);
    let e = L::select(high, e + one, e);
    let s = (m - one) / (m + one);
    let two_s = s + s;
    let series = two_s * polynomial(s * s, &LN_POLY);
    e.mul_add(L::splat(LN2_HI), e.mul_add(L::splat(LN2_LO), series))
}

/// atan2(y, x) for y, x ≥ 0: the angle in [0, π/2]; NaN where both are 0.
#[inline(always)]
pub(crate) fn atan2_nonnegative<L: Lane>(y: L, x: L) -> L {
    let (small, large) = (y.min(x), y.max(x));
    // t = small / large in [0, 1]; above tan(π/8), atan t = π/4 + atan((t − 1) / (t + 1)).
    let far = small.gt(large * L::splat(TAN_PI_8));
    let num = L::select(far, small - large, small);
    let den = L::select(far, small + large, large);
    let r = num / den;
    let offset = L::select(far, L::splat(FRAC_PI_4), L::zero());
    let angle = r.mul_add(polynomial(r * r, &ATAN_POLY), offset);
    // Swapped octant: atan(y / x) = π/2 − atan(x / y).
    L::select(y.gt(x), L::splat(FRAC_PI_2) - angle, angle)
}

/// atan2(y, x) in [−π, π], the quadrant from the signs of x and y (−0 counts as +0).
#[inline(always)]
pub(crate) fn atan2<L: Lane>(y: L, x: L) -> L {
    let zero = L::zero();
    let angle = atan2_nonnegative(y.abs(), x.abs());
    let angle = L::select(x.lt(zero), L::splat(PI) - angle, angle);
    L::select(y.lt(zero), -angle, angle)
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::super::{LANES, Lane, LaneKernel, run_every_backend};

    /// `ln` and `atan2` of four inputs on one backend.
    #[derive(Clone)]
    struct Eval {
        x: [f64; LANES],
        y: [f64; LANES],
    }

    impl LaneKernel for Eval {
        type Output = ([f64; LANES], [f64; LANES]);
        fn run<L: Lane>(self) -> Self::Output {
            let (x, y) = (L::from_array(self.x), L::from_array(self.y));
            (x.abs().ln().to_array(), y.atan2(x).to_array())
        }
    }

    fn check(x: [f64; LANES], y: [f64; LANES]) {
        for (backend, (ln, atan2)) in run_every_backend(Eval { x, y }) {
            for l in 0..LANES {
                let want = x[l].abs().ln();
                let err = (ln[l] - want).abs();
                assert!(
                    err <= 4.0 * f64::EPSILON * want.abs().max(1.0),
                    "{backend}: ln({}) = {} vs {want}",
                    x[l].abs(),
                    ln[l]
                );
                let want = y[l].atan2(x[l]);
                let err = (atan2[l] - want).abs();
                assert!(
                    err <= 4.0 * f64::EPSILON * want.abs().max(1e-300) || err <= 1e-300,
                    "{backend}: atan2({}, {}) = {} vs {want}",
                    y[l],
                    x[l],
                    atan2[l]
                );
            }
        }
    }

    #[test]
    fn exact_values_and_quadrants() {
        check([1.0, 2.0, 0.5, 1e300], [0.0, 2.0, -0.5, 1e-300]);
        check([-1.0, -2.0, 0.0, 3.0], [1.0, -2.0, 1.0, -4.0]);
        check(
            [f64::MIN_POSITIVE, 1.0 + 1e-15, 1.0 - 1e-15, 1e-10],
            [1e-10, 1e-20, -1e10, 3.0],
        );
        check(
            [0.0, -0.0, 7.0, -7.0],
            [-3.0, 5.0, 7.0 * (SQRT_2_MINUS_1), 7.0],
        );
    }

    const SQRT_2_MINUS_1: f64 = std::f64::consts::SQRT_2 - 1.0;

    #[test]
    fn both_zero_is_nan() {
        for (backend, (_, atan2)) in run_every_backend(Eval {
            x: [0.0; LANES],
            y: [0.0; LANES],
        }) {
            assert!(atan2.iter().all(|a| a.is_nan()), "{backend}: {atan2:?}");
        }
    }

    proptest! {
        #[test]
        fn agree_with_std_to_a_few_ulps(
            mant in proptest::array::uniform4(-1.0f64..1.0),
            expo in proptest::array::uniform4(-300i32..300),
            ys in proptest::array::uniform4(-1e6f64..1e6),
        ) {
            let x: [f64; LANES] = std::array::from_fn(|l| match mant[l] * 2f64.powi(expo[l]) {
                0.0 => 1.0,
                x => x,
            });
            check(x, ys);
            check(mant.map(|m| 1.0 + m * 1e-3), mant.map(|m| m * 1e-3));
        }
    }
}
