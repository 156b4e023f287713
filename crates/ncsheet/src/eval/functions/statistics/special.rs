//! Special functions behind the statistical distributions: log-gamma, the regularized
//! incomplete gamma and beta functions, erf, and a monotone inverse. Pure numerics on `f64`,
//! written to about 1e-14 relative so that Excel's stored results (1e-9) are matched; the
//! continued fractions are the modified Lentz method.

use std::f64::consts::PI;

/// Converged: a continued fraction's factor within two units of the last place of 1 (its
/// rounding can leave it 1 + 2^-52 for good, which a tolerance of 1e-16 never accepted).
const EPS: f64 = 2.0 * f64::EPSILON;
const TINY: f64 = 1e-300;
const MAX_ITER: usize = 10_000;

/// The most the logarithm of a probability may be off from rounding before the probability
/// is not given: it is the result's relative error. A sum of logarithms of size S is off by
/// a few units of 2^-52 of S, so past parameters of about 10^8 (ln Γ(10^8) is 1.7·10^9)
/// the digits are noise: F.DIST(1,1E16,1E16,TRUE) was -795023, a probability.
const MAX_LOG_ERROR: f64 = 1e-6;

/// e^(Σ terms), the terms being logarithms (ln Γ values, a·ln x …) that nearly cancel: NaN
/// (`#NUM!`) when their size leaves the sum off by more than [`MAX_LOG_ERROR`], unless the
/// result is 0 (or past the largest double) whatever the error.
pub fn exp_of_sum(terms: &[f64]) -> f64 {
    let sum: f64 = terms.iter().sum();
    let error = terms.iter().map(|t| t.abs()).sum::<f64>() * 4.0 * f64::EPSILON;
    // An infinite term (ln 0, x² past the largest double) leaves e^sum what it always was.
    if error <= MAX_LOG_ERROR || !error.is_finite() || sum + error < -746.0 || sum - error > 710.0 {
        sum.exp()
    } else {
        f64::NAN
    }
}

/// Lanczos coefficients for g = 7, n = 9 (about 1e-15 relative over the positive reals).
const LANCZOS: [f64; 9] = [
    0.999_999_999_999_809_9,
    676.520_368_121_885_1,
    -1_259.139_216_722_402_8,
    771.323_428_777_653_1,
    -176.615_029_162_140_6,
    12.507_343_278_686_905,
    -0.138_571_095_265_720_12,
    9.984_369_578_019_572e-6,
    1.505_632_735_149_311_6e-7,
];

/// ln |Γ(x)| for x not a non-positive integer.
pub fn ln_gamma(x: f64) -> f64 {
    // Γ(1) = Γ(2) = 1 exactly, where the series leaves a residue of 1e-15.
    if x == 1.0 || x == 2.0 {
        return 0.0;
    }
    if x < 0.5 {
        // Reflection: Γ(x)Γ(1-x) = π / sin(πx).
        return (PI / (PI * x).sin().abs()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + 7.5;
    let series = LANCZOS[1..].iter().enumerate().fold(LANCZOS[0], |acc, (i, c)| acc + c / (x + i as f64 + 1.0));
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + series.ln()
}

/// Γ(x); exact products for small integers, where Excel's values are exact too.
pub fn gamma(x: f64) -> f64 {
    if x == x.floor() && x > 0.0 && x <= 171.0 {
        return (1..x as u32).fold(1.0, |acc, k| acc * f64::from(k));
    }
    if x < 0.5 {
        return PI / ((PI * x).sin() * gamma(1.0 - x));
    }
    ln_gamma(x).exp()
}

/// ln B(a, b).
pub fn ln_beta(a: f64, b: f64) -> f64 {
    ln_gamma(a) + ln_gamma(b) - ln_gamma(a + b)
}

/// From this shape on, P and Q come from Temme's uniform expansion: there its first two
/// terms are exact to far below a double's rounding (the next is of order a^-2.5), while the
/// series and the continued fraction need ever more steps and their e^(a ln x − x − ln Γ(a))
/// loses a digit per power of ten of a (POISSON.DIST(1E9,1E9,TRUE) was #NUM!).
const TEMME_FROM: f64 = 1e6;

/// The regularized lower incomplete gamma function P(a, x).
pub fn gamma_p(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if a >= TEMME_FROM {
        let (z, rest) = temme_gamma(a, x);
        // P = 1 − Q, with erfc(−z) = 2 − erfc(z) taken in exactly.
        return 0.5 * erfc(-z) - rest;
    }
    if x < a + 1.0 {
        gamma_series(a, x)
    } else {
        1.0 - gamma_fraction(a, x)
    }
}

/// The regularized upper incomplete gamma function Q(a, x) = 1 − P(a, x), accurate in the tail.
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    if a >= TEMME_FROM {
        let (z, rest) = temme_gamma(a, x);
        return 0.5 * erfc(z) + rest;
    }
    if x < a + 1.0 {
        1.0 - gamma_series(a, x)
    } else {
        gamma_fraction(a, x)
    }
}

/// Temme's uniform expansion of Q(a, x) = ½ erfc(z) + R (DLMF 8.12.3–8.12.9): with
/// λ = x/a, ½η² = λ − 1 − ln λ (η of the sign of λ − 1) and z = η√(a/2),
/// R = e^(−aη²/2)/√(2πa) · (c₀(η) + c₁(η)/a). Returns (z, R).
fn temme_gamma(a: f64, x: f64) -> (f64, f64) {
    // λ − 1 from the difference, exact for the whole numbers POISSON passes.
    let mu = (x - a) / a;
    let half_eta2 = -ln_1p_minus(mu);
    let eta = (2.0 * half_eta2).sqrt().copysign(mu);
    let (c0, c1) = if eta.abs() < 1e-3 {
        // Their Taylor series (DLMF 8.12.9's expansions): the closed forms below cancel near 0.
        (
            -1.0 / 3.0 + eta / 12.0 - 2.0 * eta * eta / 135.0 + eta.powi(3) / 864.0,
            -1.0 / 540.0 - eta / 288.0 + eta * eta / 378.0,
        )
    } else {
        (1.0 / mu - 1.0 / eta, 1.0 / eta.powi(3) - 1.0 / mu.powi(3) - 1.0 / (mu * mu) - 1.0 / (12.0 * mu))
    };
    let rest = (-a * half_eta2).exp() / (2.0 * PI * a).sqrt() * (c0 + c1 / a);
    (eta * (a / 2.0).sqrt(), rest)
}

/// ln(1 + μ) − μ, without the cancellation of the two near μ = 0: its series there.
fn ln_1p_minus(mu: f64) -> f64 {
    if mu.abs() > 0.1 {
        return mu.ln_1p() - mu;
    }
    // −μ²/2 + μ³/3 − μ⁴/4 …: 30 terms leave less than 0.1^30 of it.
    let (mut power, mut sum) = (mu * mu, 0.0);
    for k in 2..32 {
        let term = power / f64::from(k);
        sum += if k % 2 == 0 { -term } else { term };
        power *= mu;
    }
    sum
}

fn gamma_prefactor(a: f64, x: f64) -> f64 {
    exp_of_sum(&[a * x.ln(), -x, -ln_gamma(a)])
}

fn gamma_series(a: f64, x: f64) -> f64 {
    let mut term = 1.0 / a;
    let mut sum = term;
    let mut ap = a;
    for _ in 0..MAX_ITER {
        ap += 1.0;
        term *= x / ap;
        sum += term;
        if term.abs() < sum.abs() * EPS {
            return sum * gamma_prefactor(a, x);
        }
    }
    // Not converged (a beyond about 10^8): the partial sum is no answer.
    f64::NAN
}

fn gamma_fraction(a: f64, x: f64) -> f64 {
    let mut b = x + 1.0 - a;
    let mut c = 1.0 / TINY;
    let mut d = 1.0 / b;
    let mut h = d;
    for i in 1..MAX_ITER {
        let an = -(i as f64) * (i as f64 - a);
        b += 2.0;
        d = an * d + b;
        if d.abs() < TINY {
            d = TINY;
        }
        c = b + an / c;
        if c.abs() < TINY {
            c = TINY;
        }
        d = 1.0 / d;
        let delta = d * c;
        h *= delta;
        if (delta - 1.0).abs() < EPS {
            return gamma_prefactor(a, x) * h;
        }
    }
    f64::NAN
}

/// The regularized incomplete beta function I_x(a, b).
pub fn beta_i(x: f64, a: f64, b: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let front = exp_of_sum(&[a * x.ln(), b * (1.0 - x).ln(), -ln_gamma(a), -ln_gamma(b), ln_gamma(a + b)]);
    if x < (a + 1.0) / (a + b + 2.0) {
        front * beta_fraction(x, a, b) / a
    } else {
        1.0 - front * beta_fraction(1.0 - x, b, a) / b
    }
}

fn beta_fraction(x: f64, a: f64, b: f64) -> f64 {
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 - qab * x / qap;
    if d.abs() < TINY {
        d = TINY;
    }
    d = 1.0 / d;
    let mut h = d;
    for m in 1..MAX_ITER {
        let m = m as f64;
        let m2 = 2.0 * m;
        let aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 + aa * d;
        d = if d.abs() < TINY { 1.0 / TINY } else { 1.0 / d };
        c = 1.0 + aa / c;
        if c.abs() < TINY {
            c = TINY;
        }
        h *= d * c;
        let aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 + aa * d;
        d = if d.abs() < TINY { 1.0 / TINY } else { 1.0 / d };
        c = 1.0 + aa / c;
        if c.abs() < TINY {
            c = TINY;
        }
        let delta = d * c;
        h *= delta;
        if (delta - 1.0).abs() < EPS {
            return h;
        }
    }
    // Not converged (a and b beyond about 10^8): the partial fraction is no answer.
    f64::NAN
}

/// The error function.
pub fn erf(x: f64) -> f64 {
    if x.abs() < 0.5 {
        // The series, so that erf(x) ≈ 2x/√π keeps its relative accuracy near 0.
        return erf_series(x);
    }
    let p = gamma_p(0.5, x * x);
    if x < 0.0 {
        -p
    } else {
        p
    }
}

fn erf_series(x: f64) -> f64 {
    // erf x = 2/√π Σ (-1)^n x^(2n+1) / (n! (2n+1))
    let mut term = x;
    let mut sum = x;
    for n in 1..100 {
        let n = n as f64;
        term *= -x * x / n;
        let add = term / (2.0 * n + 1.0);
        sum += add;
        if add.abs() < sum.abs() * EPS {
            break;
        }
    }
    sum * 2.0 / PI.sqrt()
}

/// The complementary error function, accurate in the upper tail.
pub fn erfc(x: f64) -> f64 {
    if x < 0.5 {
        1.0 - erf(x)
    } else {
        gamma_q(0.5, x * x)
    }
}

/// The standard normal distribution function Φ(z).
pub fn norm_cdf(z: f64) -> f64 {
    0.5 * erfc(-z / std::f64::consts::SQRT_2)
}

/// The standard normal density.
pub fn norm_pdf(z: f64) -> f64 {
    (-0.5 * z * z).exp() / (2.0 * PI).sqrt()
}

/// Φ⁻¹(p) for 0 < p < 1: Acklam's rational start refined by Halley steps on [`norm_cdf`].
pub fn norm_inv(p: f64) -> f64 {
    let mut z = acklam(p);
    for _ in 0..3 {
        let e = norm_cdf(z) - p;
        let u = e * (2.0 * PI).sqrt() * (0.5 * z * z).exp();
        z -= u / (1.0 + z * u / 2.0);
    }
    z
}

fn acklam(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] =
        [7.784_695_709_041_462e-3, 3.224_671_290_700_398e-1, 2.445_134_137_142_996, 3.754_408_661_907_416];
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    if p < 0.024_25 {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - 0.024_25 {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}

/// The x in [lo, hi] where the increasing function `cdf` reaches `p`, by bisection to the
/// last bit (the distribution functions are cheap; robustness matters more than speed).
/// `hi` is doubled until it brackets `p`.
pub fn invert_increasing(p: f64, mut lo: f64, mut hi: f64, cdf: impl Fn(f64) -> f64) -> Option<f64> {
    // A cdf that cannot be computed there (NaN) compares false with everything, and the
    // search would settle on a bound as if it were the answer: NaN is the answer (#NUM!).
    let below = |x: f64| {
        let c = cdf(x);
        (!c.is_nan()).then_some(c < p)
    };
    let mut grow = 0;
    loop {
        match below(hi) {
            None => return Some(f64::NAN),
            Some(false) => break,
            Some(true) => {}
        }
        lo = hi;
        hi *= 2.0;
        grow += 1;
        if grow > 1100 || !hi.is_finite() {
            return None;
        }
    }
    for _ in 0..2000 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        match below(mid) {
            None => return Some(f64::NAN),
            Some(true) => lo = mid,
            Some(false) => hi = mid,
        }
    }
    Some(0.5 * (lo + hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    // Reference values: Abramowitz & Stegun tables and closed forms, not this code.
    #[test]
    fn gamma_matches_closed_forms() {
        assert!((gamma(0.5) - PI.sqrt()).abs() < 1e-14);
        assert_eq!(gamma(6.0), 120.0);
        assert!((ln_gamma(100.0) - 359.134_205_369_575_4).abs() < 1e-11);
    }

    #[test]
    fn erf_and_normal_match_tables() {
        assert!((erf(1.0) - 0.842_700_792_949_714_9).abs() < 1e-15);
        assert!((erfc(3.0) - 2.209_049_699_858_544e-5).abs() < 1e-19);
        assert!((norm_cdf(1.96) - 0.975_002_104_851_780).abs() < 1e-14);
        assert!((norm_inv(0.975) - 1.959_963_984_540_054).abs() < 1e-13);
    }

    #[test]
    fn incomplete_beta_matches_closed_forms() {
        // I_x(1, b) = 1 - (1-x)^b; I_x(a, 1) = x^a.
        assert!((beta_i(0.3, 1.0, 4.0) - (1.0 - 0.7f64.powi(4))).abs() < 1e-15);
        assert!((beta_i(0.6, 3.0, 1.0) - 0.216).abs() < 1e-15);
    }
}
