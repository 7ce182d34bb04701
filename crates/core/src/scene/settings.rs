//! Scene-wide settings: default h, the smoothing function f_h, the join-cage coordinate
//! policy, what to do with mesh vertices outside every cage, and the HC discretisation.

use serde::{Deserialize, Serialize};

use crate::coords::HarmonicSettings;
use crate::coords::lanes::{self, LANES, Lane, LaneKernel};

/// The paper's three smoothing functions f_h (section 3.1), all with f_h(0) = f'_h(0) = 0,
/// f_h(x) = 1 for x ≥ h and f'_h ≥ 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Smoothing {
    /// f_h(x) = ½ sin(π(x/h − ½)) + ½ (the paper's images use this one).
    #[default]
    Sine,
    /// f_h(x) = −2(x/h)³ + 3(x/h)².
    Cubic,
    /// f_h(x) = −8(x/h)⁵ + 20(x/h)⁴ − 18(x/h)³ + 7(x/h)².
    Quintic,
}

impl Smoothing {
    /// f_h(x), clamped: 0 for x ≤ 0 and 1 for x ≥ h (docs/math.md, reading 3).
    pub fn eval(self, x: f64, h: f64) -> f64 {
        if x <= 0.0 {
            return 0.0;
        }
        if x >= h {
            return 1.0;
        }
        let t = x / h;
        match self {
            Self::Sine => 0.5 * sin_within_half_turn(std::f64::consts::PI * (t - 0.5)) + 0.5,
            Self::Cubic => t * t * (3.0 - 2.0 * t),
            Self::Quintic => t * t * (7.0 + t * (-18.0 + t * (20.0 - 8.0 * t))),
        }
    }
}

impl Smoothing {
    /// f_1(x) of every x in place (h = 1, as Ω's factors in eqs. 6 and 8 use it): the same
    /// values as [`Smoothing::eval`], computed without branches so the loop runs in SIMD lanes
    /// (the factors of Ω are most of a bind's row assembly).
    pub fn eval_unit_in_place(self, xs: &mut [f64]) {
        // Each kind's loop separately: the match stays outside the lanes.
        fn each(xs: &mut [f64], f: impl Fn(f64) -> f64) {
            for x in xs {
                let t = x.clamp(0.0, 1.0);
                let y = f(t);
                *x = if *x <= 0.0 {
                    0.0
                } else if *x >= 1.0 {
                    1.0
                } else {
                    y
                };
            }
        }
        match self {
            Self::Sine => {
                let remainder = lanes::run_kernel(SineInPlace(xs));
                each(remainder, |t| {
                    0.5 * sin_within_half_turn(std::f64::consts::PI * (t - 0.5)) + 0.5
                });
            }
            Self::Cubic => each(xs, |t| t * t * (3.0 - 2.0 * t)),
            Self::Quintic => each(xs, |t| t * t * (7.0 + t * (-18.0 + t * (20.0 - 8.0 * t)))),
        }
    }
}

/// f_1 (sine) of every x in place, [`LANES`] at a time in the best SIMD lanes this CPU has
/// (AVX2 where it reports it: the portable build's `wide` lanes are SSE2, two instructions
/// per operation), with the same operations in the same order as [`Smoothing::eval`], so the
/// same values. Returns the last `len % LANES` values, left for the scalar loop.
struct SineInPlace<'a>(&'a mut [f64]);

impl<'a> LaneKernel for SineInPlace<'a> {
    type Output = &'a mut [f64];

    #[inline(always)]
    fn run<L: Lane>(self) -> &'a mut [f64] {
        let mut chunks = self.0.chunks_exact_mut(LANES);
        for c in &mut chunks {
            let y = sine_unit_lanes(L::from_array([c[0], c[1], c[2], c[3]]));
            c.copy_from_slice(&y.to_array());
        }
        chunks.into_remainder()
    }
}

/// f_1 (sine) of each lane, clamped as [`Smoothing::eval`] clamps, with the same operations in
/// the same order as `eval` (so the same values, bit for bit).
#[inline(always)]
fn sine_unit_lanes<L: Lane>(x: L) -> L {
    let (zero, one, half) = (L::splat(0.0), L::splat(1.0), L::splat(0.5));
    let (pi, minus_one) = (L::splat(std::f64::consts::PI), L::splat(-1.0));
    let t = x.max(zero).min(one);
    let u = pi * (t - half);
    let u2 = u * u;
    // A loop, not a `fold` closure: closures are compiled without the kernel's target
    // features, and their lane operations become calls.
    let mut series = zero;
    for &k in &SINE_COEFFICIENTS {
        series = series * u2 + L::splat(k);
    }
    let sine = (u * (series * u2 + one)).max(minus_one).min(one);
    let y = half * sine + half;
    let y = L::select(x.le(zero), zero, y);
    let y = L::select(x.ge(one), one, y);
    // NaN stays NaN, as in `eval` (no comparison holds for it).
    L::select(!x.le(x), x, y)
}

/// Π_k f_1(x_k · s_k) (sine) over `x` and `scale` (all 1 where `scale` is `None`), in the
/// four running products of [`product_of`]: a lane per product, the last `len % LANES`
/// factors left for the caller. Returns the four lane products and where the rest starts.
/// Neither the arguments nor the factors are written out: eq. 6's and eq. 8's products were
/// half of an auto rig's bind as separate passes over a buffer.
struct SineProduct<'a> {
    x: &'a [f64],
    scale: Option<&'a [f64]>,
}

impl LaneKernel for SineProduct<'_> {
    type Output = ([f64; LANES], usize);

    #[inline(always)]
    fn run<L: Lane>(self) -> ([f64; LANES], usize) {
        // Loops, not closures: the kernel must be one function for `#[target_feature]`.
        let whole = self.x.len() - self.x.len() % LANES;
        let mut product = L::splat(1.0);
        match self.scale {
            Some(scale) => {
                for (x, s) in self.x[..whole]
                    .chunks_exact(LANES)
                    .zip(scale.chunks_exact(LANES))
                {
                    let x = L::from_array([x[0], x[1], x[2], x[3]]);
                    let s = L::from_array([s[0], s[1], s[2], s[3]]);
                    product = product * sine_unit_lanes(x * s);
                }
            }
            None => {
                for x in self.x[..whole].chunks_exact(LANES) {
                    product = product * sine_unit_lanes(L::from_array([x[0], x[1], x[2], x[3]]));
                }
            }
        }
        (product.to_array(), whole)
    }
}

impl Smoothing {
    /// Π_k f_1(x_k): the same value, bit for bit, as [`Smoothing::eval_unit_in_place`] then
    /// [`product_of`], in one pass with nothing written out (Ω's products, eqs. 6 and 8).
    pub(crate) fn product_of_unit(self, xs: &[f64]) -> f64 {
        self.product_of_unit_scaled(xs, None)
    }

    /// Π_k f_1(x_k), leaving out first the x_k ≥ 1 (whose factor is exactly 1): the value of
    /// [`Smoothing::product_of_unit`] to rounding (the factors left are multiplied in another
    /// grouping), `xs` reordered and shortened. Most of Ω's factors in a blend zone are 1.
    pub(crate) fn product_of_unit_below_one(self, xs: &mut Vec<f64>) -> f64 {
        let mut kept = 0;
        for k in 0..xs.len() {
            let x = xs[k];
            xs[kept] = x;
            // Branch-free; NaN is kept (its product stays NaN).
            kept += usize::from(x < 1.0 || x.is_nan());
        }
        xs.truncate(kept);
        self.product_of_unit(xs)
    }

    /// Π_k f_1(x_k · s_k) (`scale` as long as `xs`): the same value, bit for bit, as the
    /// products x_k · s_k through [`Smoothing::product_of_unit`] (eq. 6's factors of an
    /// interior vertex, d(t, p) / d(t, u) with 1 / d(t, u) stored).
    pub(crate) fn product_of_unit_scaled(self, xs: &[f64], scale: Option<&[f64]>) -> f64 {
        let argument = |k: usize| scale.map_or(xs[k], |s| xs[k] * s[k]);
        match self {
            Self::Sine => {
                let (lanes, rest_from) = lanes::run_kernel(SineProduct { x: xs, scale });
                let rest: f64 = (rest_from..xs.len())
                    .map(|k| self.eval(argument(k), 1.0))
                    .product();
                (lanes[0] * lanes[1]) * (lanes[2] * lanes[3]) * rest
            }
            Self::Cubic | Self::Quintic => {
                let mut lanes = [1.0; LANES];
                let whole = xs.len() - xs.len() % LANES;
                for k in 0..whole {
                    lanes[k % LANES] *= self.eval(argument(k), 1.0);
                }
                let rest: f64 = (whole..xs.len())
                    .map(|k| self.eval(argument(k), 1.0))
                    .product();
                (lanes[0] * lanes[1]) * (lanes[2] * lanes[3]) * rest
            }
        }
    }
}

/// The product of `xs` in four independent running products (the one chain of
/// multiplications, each waiting on the last, was the bound): the order
/// [`Smoothing::product_of_unit`] multiplies in, which the tests check it against.
#[cfg(test)]
fn product_of(xs: &[f64]) -> f64 {
    let mut lanes = [1.0; 4];
    let mut chunks = xs.chunks_exact(4);
    for c in &mut chunks {
        for (lane, &x) in lanes.iter_mut().zip(c) {
            *lane *= x;
        }
    }
    let rest: f64 = chunks.remainder().iter().product();
    (lanes[0] * lanes[1]) * (lanes[2] * lanes[3]) * rest
}

/// sin x for |x| ≤ π/2 by its Taylor series through x²¹ (the first term left out is below
/// 2e-18 there): f_h is evaluated for every far face of every join cage at every point of a
/// bind, where libm's sin, with its range reduction, was a fifth of the bind's time.
fn sin_within_half_turn(x: f64) -> f64 {
    let x2 = x * x;
    // Plain multiply-adds: `mul_add` is a libm call where the build does not target FMA.
    let series = SINE_COEFFICIENTS.iter().fold(0.0, |acc, &c| acc * x2 + c);
    // Rounding may pass ±1 by an ulp near ±π/2; f_h must stay within [0, 1].
    (x * (series * x2 + 1.0)).clamp(-1.0, 1.0)
}

/// (−1)^k / (2k + 1)!, k = 10 … 1, in Horner order over x²: sin x = x (1 + x² series).
const SINE_COEFFICIENTS: [f64; 10] = [
    1.0 / 51_090_942_171_709_440_000.0,
    -1.0 / 121_645_100_408_832_000.0,
    1.0 / 355_687_428_096_000.0,
    -1.0 / 1_307_674_368_000.0,
    1.0 / 6_227_020_800.0,
    -1.0 / 39_916_800.0,
    1.0 / 362_880.0,
    -1.0 / 5_040.0,
    1.0 / 120.0,
    -1.0 / 6.0,
];

/// Coordinates used for join cages (section 3.1; Fig. 10).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum JoinPolicy {
    /// HC where the join cage is concave, MVC where it is convex.
    Auto,
    /// Always Mean Value Coordinates: the paper's default join transformation (section 4) and
    /// ours (docs/math.md, "Join cages default to mean value coordinates").
    #[default]
    Mvc,
    /// Always Harmonic Coordinates.
    Hc,
    /// Always Green Coordinates.
    Gc,
}

/// What happens to mesh vertices that lie outside every leaf cage.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OutsidePolicy {
    /// They are an error (the default): the scene does not validate.
    #[default]
    Error,
    /// They follow the nearest leaf cage: through its coordinates where those are defined
    /// outside (MVC, GC), rigidly otherwise.
    Nearest,
}

/// Scene-wide settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct SceneSettings {
    /// h of cages that set none, in (0, 1].
    pub default_h: f64,
    /// The smoothing function f_h.
    pub smoothing: Smoothing,
    /// Join-cage coordinates.
    pub join_coordinates: JoinPolicy,
    /// Mesh vertices outside every leaf cage.
    pub outside: OutsidePolicy,
    /// Harmonic coordinates' grid and solver.
    pub harmonic: HarmonicSettings,
}

impl Default for SceneSettings {
    fn default() -> Self {
        Self {
            default_h: 0.5,
            smoothing: Smoothing::default(),
            join_coordinates: JoinPolicy::default(),
            outside: OutsidePolicy::default(),
            harmonic: HarmonicSettings::default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smoothing_functions_meet_the_papers_conditions() {
        for f in [Smoothing::Sine, Smoothing::Cubic, Smoothing::Quintic] {
            for h in [0.2, 0.5, 1.0] {
                assert_eq!(f.eval(0.0, h), 0.0);
                assert!((f.eval(h, h) - 1.0).abs() < 1e-12);
                assert_eq!(f.eval(-0.3, h), 0.0);
                assert_eq!(f.eval(1.5, h), 1.0);
                let eps = 1e-6;
                // f'(0) = 0 and f'(h) = 0 (C1 at both ends), monotone in between.
                // Difference quotients at the ends vanish like eps (the derivatives are 0).
                assert!(f.eval(eps, h) / eps < 1e-3, "{f:?} f'(0)");
                assert!((1.0 - f.eval(h - eps, h)) / eps < 1e-3, "{f:?} f'(h)");
                let mut previous = 0.0;
                for k in 1..=100 {
                    let v = f.eval(h * k as f64 / 100.0, h);
                    assert!(v >= previous - 1e-15, "{f:?} not monotone");
                    previous = v;
                }
            }
        }
    }

    /// Arguments of f_1 for the bit-for-bit tests: `count` across [−0.25, 1.25], then the
    /// clamps, just inside them, and NaN.
    fn factor_samples(count: usize) -> Vec<f64> {
        let mut xs: Vec<f64> = (0..count)
            .map(|k| -0.25 + 1.5 * k as f64 / count as f64)
            .collect();
        xs.extend([
            0.0,
            -0.0,
            1.0,
            1e-300,
            1.0 - f64::EPSILON,
            f64::NAN,
            2.0,
            -3.0,
        ]);
        xs
    }

    /// Each of `values` is `smoothing.eval`'s value at the matching `xs`, bit for bit.
    fn assert_eval_bits(smoothing: Smoothing, xs: &[f64], values: &[f64], what: &str) {
        assert_eq!(values.len(), xs.len(), "{what}");
        for (&x, &y) in xs.iter().zip(values) {
            let expected = smoothing.eval(x, 1.0);
            assert!(
                y.to_bits() == expected.to_bits() || (y.is_nan() && expected.is_nan()),
                "{what} at {x}: {y} against {expected}"
            );
        }
    }

    /// The in-place batch gives `eval`'s values bit for bit (lanes and the scalar remainder),
    /// at the clamps, just inside them, and NaN.
    #[test]
    fn the_batch_of_factors_is_eval_bit_for_bit() {
        let xs = factor_samples(4002);
        for smoothing in [Smoothing::Sine, Smoothing::Cubic, Smoothing::Quintic] {
            let mut batch = xs.clone();
            smoothing.eval_unit_in_place(&mut batch);
            assert_eval_bits(smoothing, &xs, &batch, &format!("{smoothing:?}"));
        }
        assert_eq!(product_of(&[2.0, 3.0, 0.5, 4.0, 5.0, 0.1]), 6.0);
        assert_eq!(product_of(&[]), 1.0);
    }

    /// The fused product is the batch then [`product_of`], bit for bit, at every length (the
    /// lanes' remainder included), with and without scales, for each smoothing function.
    #[test]
    fn the_fused_product_is_the_batch_then_the_product_bit_for_bit() {
        // Arguments in (0, 1.2): a zero or NaN factor would hide every other one.
        let xs: Vec<f64> = (0..45)
            .map(|k| 0.02 + (k as f64 * 0.618_034).fract() * 1.2)
            .collect();
        let scale: Vec<f64> = (0..xs.len()).map(|k| 0.7 + 0.01 * k as f64).collect();
        for smoothing in [Smoothing::Sine, Smoothing::Cubic, Smoothing::Quintic] {
            for len in 0..xs.len() {
                let xs = &xs[..len];
                let mut batch = xs.to_vec();
                smoothing.eval_unit_in_place(&mut batch);
                let expected = product_of(&batch);
                assert!(len < 8 || (expected > 0.0 && expected < 0.5), "{expected}");
                let fused = smoothing.product_of_unit(xs);
                assert_eq!(fused.to_bits(), expected.to_bits(), "{smoothing:?}, {len}");
                let mut batch: Vec<f64> = xs.iter().zip(&scale).map(|(x, s)| x * s).collect();
                smoothing.eval_unit_in_place(&mut batch);
                let expected = product_of(&batch);
                let fused = smoothing.product_of_unit_scaled(xs, Some(&scale[..len]));
                assert_eq!(
                    fused.to_bits(),
                    expected.to_bits(),
                    "{smoothing:?} scaled, {len}"
                );
            }
        }
    }

    /// Leaving out the arguments at or past 1 changes the product by rounding only, and keeps
    /// a NaN (a filter on `x < 1` alone would drop it).
    #[test]
    fn leaving_out_the_factors_of_one_keeps_the_product() {
        let xs: Vec<f64> = (0..90)
            .map(|k| 0.3 + (k as f64 * 0.618_034).fract() * 1.4)
            .collect();
        assert!(xs.iter().filter(|&&x| x >= 1.0).count() > 10);
        for smoothing in [Smoothing::Sine, Smoothing::Cubic, Smoothing::Quintic] {
            let all = smoothing.product_of_unit(&xs);
            let mut kept = xs.clone();
            let below = smoothing.product_of_unit_below_one(&mut kept);
            assert!(kept.len() < xs.len() && kept.iter().all(|&x| x < 1.0));
            assert!((below - all).abs() <= 1e-14 * all.abs(), "{smoothing:?}");
            let mut with_nan = xs.clone();
            with_nan.push(f64::NAN);
            assert!(smoothing.product_of_unit_below_one(&mut with_nan).is_nan());
        }
    }

    /// The sine's SIMD lanes give `eval`'s values bit for bit under every backend this CPU
    /// has (the portable `wide` lanes and AVX2), not only the one `run_kernel` picks.
    #[test]
    fn the_sine_lanes_are_eval_bit_for_bit_under_every_backend() {
        #[derive(Clone)]
        struct Owned(Vec<f64>);
        impl LaneKernel for Owned {
            type Output = Vec<f64>;
            #[inline(always)]
            fn run<L: Lane>(mut self) -> Vec<f64> {
                let left = SineInPlace(&mut self.0).run::<L>().len();
                self.0.truncate(self.0.len() - left);
                self.0
            }
        }
        let xs = factor_samples(4000); // 4008 values: no scalar remainder
        let runs = crate::coords::lanes::run_every_backend(Owned(xs.clone()));
        assert!(!runs.is_empty());
        for (backend, values) in runs {
            assert_eval_bits(Smoothing::Sine, &xs, &values, backend);
        }
    }

    #[test]
    fn the_sine_series_is_libms_sine_to_rounding() {
        let half_turn = std::f64::consts::FRAC_PI_2;
        for k in 0..=20_000 {
            let x = -half_turn + 2.0 * half_turn * k as f64 / 20_000.0;
            let error = (sin_within_half_turn(x) - x.sin()).abs();
            assert!(error <= 4.0 * f64::EPSILON, "x = {x}: {error:e}");
        }
        // Odd, and exact at the ends of the range.
        assert_eq!(sin_within_half_turn(0.0), 0.0);
        assert!((sin_within_half_turn(half_turn) - 1.0).abs() <= f64::EPSILON);
    }
}
