//! Probability distributions: the .DIST and .INV families of NORM, NORM.S, LOGNORM, BINOM,
//! POISSON, EXPON, GAMMA, BETA, T, F, CHISQ, HYPGEOM, WEIBULL and NEGBINOM with their
//! pre-2010 names, GAMMA and GAMMALN, CONFIDENCE, FISHER, GAUSS, PHI and STANDARDIZE.
//! Every argument is lifted over arrays; Excel's checks give `#NUM!` for a parameter out of
//! its domain. The numerics are in `special.rs`.

use std::cell::Cell;

use crate::eval::coerce::{to_bool, to_number};
use crate::eval::dates::DateSystem;
use crate::eval::functions::api::{lift, number_result, Ctx, FnSpec};
use crate::eval::functions::scalar::{steps_between, whole_numbers, MAX_STEPS};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::Expr;

use crate::eval::functions::statistics::special::{
    beta_i, exp_of_sum, gamma, gamma_p, gamma_q, invert_increasing, ln_beta, ln_gamma, norm_cdf, norm_inv, norm_pdf,
};

type Body = fn(&[f64]) -> XlResult<f64>;

/// Evaluates the arguments, lifts over arrays and calls `f` with them as numbers.
fn numeric(ctx: &mut Ctx, args: &[Expr], f: Body) -> XlResult<Value> {
    numeric_with(ctx, args, &f)
}

/// [`numeric`] for a body that captures (a flag for the note a limit leaves).
fn numeric_with(ctx: &mut Ctx, args: &[Expr], f: &dyn Fn(&[f64]) -> XlResult<f64>) -> XlResult<Value> {
    let dates = ctx.dates();
    lift(ctx, args, &|v| {
        let x: Vec<f64> = v.iter().map(|x| number_or_flag(x, dates)).collect::<XlResult<_>>()?;
        Ok(number_result(f(&x)?))
    })
}

/// A number argument; the cumulative flags also take the text "TRUE" or "FALSE", as in Excel.
fn number_or_flag(v: &Value, dates: DateSystem) -> XlResult<f64> {
    to_number(v, dates).or_else(|e| match v {
        Value::Text(_) => to_bool(v).map(f64::from).map_err(|_| e),
        _ => Err(e),
    })
}

macro_rules! numeric_fns {
    ($($name:ident => $body:expr;)*) => {
        $(fn $name(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
            numeric(ctx, args, $body)
        })*
    };
}

/// `Err(#NUM!)` unless `ok`.
fn domain(ok: bool) -> XlResult<()> {
    if ok {
        Ok(())
    } else {
        Err(XlError::Num)
    }
}

/// A probability strictly inside (0, 1).
fn open_probability(p: f64) -> XlResult<()> {
    domain(p > 0.0 && p < 1.0)
}

fn finite(x: f64) -> XlResult<f64> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(XlError::Num)
    }
}

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "BETA.DIST",
        4,
        6,
        beta_dist,
        "BETA.DIST(x, alpha, beta, cumulative, [A], [B])",
        "Beta distribution on [A, B] (0 to 1 by default)",
    )
    .future(),
    FnSpec::value(
        "BETA.INV",
        3,
        5,
        beta_inv,
        "BETA.INV(probability, alpha, beta, [A], [B])",
        "Inverse of the cumulative beta distribution",
    )
    .future(),
    FnSpec::value(
        "BETADIST",
        3,
        5,
        betadist,
        "BETADIST(x, alpha, beta, [A], [B])",
        "Cumulative beta distribution (BETA.DIST)",
    )
    .biff(270),
    FnSpec::value(
        "BETAINV",
        3,
        5,
        beta_inv,
        "BETAINV(probability, alpha, beta, [A], [B])",
        "Inverse beta distribution (BETA.INV)",
    )
    .biff(272),
    FnSpec::value(
        "BINOM.DIST",
        4,
        4,
        binom_dist,
        "BINOM.DIST(successes, trials, probability, cumulative)",
        "Binomial distribution",
    )
    .future(),
    FnSpec::value(
        "BINOM.DIST.RANGE",
        3,
        4,
        binom_dist_range,
        "BINOM.DIST.RANGE(trials, probability, successes, [successes2])",
        "Probability of between successes and successes2 successes",
    )
    .future(),
    FnSpec::value(
        "BINOM.INV",
        3,
        3,
        binom_inv,
        "BINOM.INV(trials, probability, alpha)",
        "Smallest number of successes whose cumulative binomial probability reaches alpha",
    )
    .future(),
    FnSpec::value(
        "BINOMDIST",
        4,
        4,
        binom_dist,
        "BINOMDIST(successes, trials, probability, cumulative)",
        "Binomial distribution (BINOM.DIST)",
    )
    .biff(273),
    FnSpec::value(
        "CHIDIST",
        2,
        2,
        chisq_dist_rt,
        "CHIDIST(x, degrees)",
        "Right tail of the chi-squared distribution (CHISQ.DIST.RT)",
    )
    .biff(274),
    FnSpec::value(
        "CHIINV",
        2,
        2,
        chisq_inv_rt,
        "CHIINV(probability, degrees)",
        "Inverse right tail of the chi-squared distribution (CHISQ.INV.RT)",
    )
    .biff(275),
    FnSpec::value("CHISQ.DIST", 3, 3, chisq_dist, "CHISQ.DIST(x, degrees, cumulative)", "Chi-squared distribution")
        .future(),
    FnSpec::value(
        "CHISQ.DIST.RT",
        2,
        2,
        chisq_dist_rt,
        "CHISQ.DIST.RT(x, degrees)",
        "Right tail of the chi-squared distribution",
    )
    .future(),
    FnSpec::value(
        "CHISQ.INV",
        2,
        2,
        chisq_inv,
        "CHISQ.INV(probability, degrees)",
        "Inverse of the cumulative chi-squared distribution",
    )
    .future(),
    FnSpec::value(
        "CHISQ.INV.RT",
        2,
        2,
        chisq_inv_rt,
        "CHISQ.INV.RT(probability, degrees)",
        "Inverse of the right tail of the chi-squared distribution",
    )
    .future(),
    FnSpec::value(
        "CONFIDENCE",
        3,
        3,
        confidence_norm,
        "CONFIDENCE(alpha, standard_dev, size)",
        "Half-width of a normal confidence interval (CONFIDENCE.NORM)",
    )
    .biff(277),
    FnSpec::value(
        "CONFIDENCE.NORM",
        3,
        3,
        confidence_norm,
        "CONFIDENCE.NORM(alpha, standard_dev, size)",
        "Half-width of a confidence interval for a mean, normal distribution",
    )
    .future(),
    FnSpec::value(
        "CONFIDENCE.T",
        3,
        3,
        confidence_t,
        "CONFIDENCE.T(alpha, standard_dev, size)",
        "Half-width of a confidence interval for a mean, Student's t distribution",
    )
    .future(),
    FnSpec::value(
        "CRITBINOM",
        3,
        3,
        binom_inv,
        "CRITBINOM(trials, probability, alpha)",
        "Inverse binomial distribution (BINOM.INV)",
    )
    .biff(278),
    FnSpec::value("EXPON.DIST", 3, 3, expon_dist, "EXPON.DIST(x, lambda, cumulative)", "Exponential distribution")
        .future(),
    FnSpec::value(
        "EXPONDIST",
        3,
        3,
        expon_dist,
        "EXPONDIST(x, lambda, cumulative)",
        "Exponential distribution (EXPON.DIST)",
    )
    .biff(280),
    FnSpec::value("F.DIST", 4, 4, f_dist, "F.DIST(x, degrees1, degrees2, cumulative)", "F distribution").future(),
    FnSpec::value("F.DIST.RT", 3, 3, f_dist_rt, "F.DIST.RT(x, degrees1, degrees2)", "Right tail of the F distribution")
        .future(),
    FnSpec::value(
        "F.INV",
        3,
        3,
        f_inv,
        "F.INV(probability, degrees1, degrees2)",
        "Inverse of the cumulative F distribution",
    )
    .future(),
    FnSpec::value(
        "F.INV.RT",
        3,
        3,
        f_inv_rt,
        "F.INV.RT(probability, degrees1, degrees2)",
        "Inverse of the right tail of the F distribution",
    )
    .future(),
    FnSpec::value(
        "FDIST",
        3,
        3,
        f_dist_rt,
        "FDIST(x, degrees1, degrees2)",
        "Right tail of the F distribution (F.DIST.RT)",
    )
    .biff(281),
    FnSpec::value(
        "FINV",
        3,
        3,
        f_inv_rt,
        "FINV(probability, degrees1, degrees2)",
        "Inverse right tail of the F distribution (F.INV.RT)",
    )
    .biff(282),
    FnSpec::value("FISHER", 1, 1, fisher, "FISHER(x)", "Fisher transformation, atanh(x)").biff(283),
    FnSpec::value("FISHERINV", 1, 1, fisher_inv, "FISHERINV(y)", "Inverse Fisher transformation, tanh(y)").biff(284),
    FnSpec::value("GAMMA", 1, 1, gamma_fn, "GAMMA(number)", "The gamma function").future(),
    FnSpec::value("GAMMA.DIST", 4, 4, gamma_dist, "GAMMA.DIST(x, alpha, beta, cumulative)", "Gamma distribution")
        .future(),
    FnSpec::value(
        "GAMMA.INV",
        3,
        3,
        gamma_inv,
        "GAMMA.INV(probability, alpha, beta)",
        "Inverse of the cumulative gamma distribution",
    )
    .future(),
    FnSpec::value(
        "GAMMADIST",
        4,
        4,
        gamma_dist,
        "GAMMADIST(x, alpha, beta, cumulative)",
        "Gamma distribution (GAMMA.DIST)",
    )
    .biff(286),
    FnSpec::value(
        "GAMMAINV",
        3,
        3,
        gamma_inv,
        "GAMMAINV(probability, alpha, beta)",
        "Inverse gamma distribution (GAMMA.INV)",
    )
    .biff(287),
    FnSpec::value("GAMMALN", 1, 1, gammaln, "GAMMALN(x)", "Natural logarithm of the gamma function").biff(271),
    FnSpec::value("GAMMALN.PRECISE", 1, 1, gammaln, "GAMMALN.PRECISE(x)", "Natural logarithm of the gamma function")
        .future(),
    FnSpec::value("GAUSS", 1, 1, gauss, "GAUSS(z)", "Probability that a standard normal lies between the mean and z")
        .future(),
    FnSpec::value(
        "HYPGEOM.DIST",
        5,
        5,
        hypgeom_dist,
        "HYPGEOM.DIST(sample_s, number_sample, population_s, number_pop, cumulative)",
        "Hypergeometric distribution",
    )
    .future(),
    FnSpec::value(
        "HYPGEOMDIST",
        4,
        4,
        hypgeomdist,
        "HYPGEOMDIST(sample_s, number_sample, population_s, number_pop)",
        "Hypergeometric probability (HYPGEOM.DIST, not cumulative)",
    )
    .biff(289),
    FnSpec::value(
        "LOGINV",
        3,
        3,
        lognorm_inv,
        "LOGINV(probability, mean, standard_dev)",
        "Inverse lognormal distribution (LOGNORM.INV)",
    )
    .biff(291),
    FnSpec::value(
        "LOGNORM.DIST",
        4,
        4,
        lognorm_dist,
        "LOGNORM.DIST(x, mean, standard_dev, cumulative)",
        "Lognormal distribution",
    )
    .future(),
    FnSpec::value(
        "LOGNORM.INV",
        3,
        3,
        lognorm_inv,
        "LOGNORM.INV(probability, mean, standard_dev)",
        "Inverse of the cumulative lognormal distribution",
    )
    .future(),
    FnSpec::value(
        "LOGNORMDIST",
        3,
        3,
        lognormdist,
        "LOGNORMDIST(x, mean, standard_dev)",
        "Cumulative lognormal distribution (LOGNORM.DIST)",
    )
    .biff(290),
    FnSpec::value(
        "NEGBINOM.DIST",
        4,
        4,
        negbinom_dist,
        "NEGBINOM.DIST(number_f, number_s, probability_s, cumulative)",
        "Negative binomial distribution",
    )
    .future(),
    FnSpec::value(
        "NEGBINOMDIST",
        3,
        3,
        negbinomdist,
        "NEGBINOMDIST(number_f, number_s, probability_s)",
        "Negative binomial probability (NEGBINOM.DIST, not cumulative)",
    )
    .biff(292),
    FnSpec::value("NORM.DIST", 4, 4, norm_dist, "NORM.DIST(x, mean, standard_dev, cumulative)", "Normal distribution")
        .future(),
    FnSpec::value(
        "NORM.INV",
        3,
        3,
        norm_inv_fn,
        "NORM.INV(probability, mean, standard_dev)",
        "Inverse of the cumulative normal distribution",
    )
    .future(),
    FnSpec::value("NORM.S.DIST", 2, 2, norm_s_dist, "NORM.S.DIST(z, cumulative)", "Standard normal distribution")
        .future(),
    FnSpec::value(
        "NORM.S.INV",
        1,
        1,
        norm_s_inv,
        "NORM.S.INV(probability)",
        "Inverse of the cumulative standard normal distribution",
    )
    .future(),
    FnSpec::value(
        "NORMDIST",
        4,
        4,
        norm_dist,
        "NORMDIST(x, mean, standard_dev, cumulative)",
        "Normal distribution (NORM.DIST)",
    )
    .biff(293),
    FnSpec::value(
        "NORMINV",
        3,
        3,
        norm_inv_fn,
        "NORMINV(probability, mean, standard_dev)",
        "Inverse normal distribution (NORM.INV)",
    )
    .biff(295),
    FnSpec::value(
        "NORMSDIST",
        1,
        1,
        normsdist,
        "NORMSDIST(z)",
        "Cumulative standard normal distribution (NORM.S.DIST)",
    )
    .biff(294),
    FnSpec::value(
        "NORMSINV",
        1,
        1,
        norm_s_inv,
        "NORMSINV(probability)",
        "Inverse standard normal distribution (NORM.S.INV)",
    )
    .biff(296),
    FnSpec::value("PHI", 1, 1, phi, "PHI(x)", "Standard normal density").future(),
    FnSpec::value("POISSON", 3, 3, poisson_dist, "POISSON(x, mean, cumulative)", "Poisson distribution (POISSON.DIST)")
        .biff(300),
    FnSpec::value("POISSON.DIST", 3, 3, poisson_dist, "POISSON.DIST(x, mean, cumulative)", "Poisson distribution")
        .future(),
    FnSpec::value("STANDARDIZE", 3, 3, standardize, "STANDARDIZE(x, mean, standard_dev)", "(x - mean) / standard_dev")
        .biff(297),
    FnSpec::value("T.DIST", 3, 3, t_dist, "T.DIST(x, degrees, cumulative)", "Student's t distribution (left tail)")
        .future(),
    FnSpec::value("T.DIST.2T", 2, 2, t_dist_2t, "T.DIST.2T(x, degrees)", "Two-tailed Student's t distribution")
        .future(),
    FnSpec::value("T.DIST.RT", 2, 2, t_dist_rt, "T.DIST.RT(x, degrees)", "Right tail of Student's t distribution")
        .future(),
    FnSpec::value(
        "T.INV",
        2,
        2,
        t_inv,
        "T.INV(probability, degrees)",
        "Inverse of the left tail of Student's t distribution",
    )
    .future(),
    FnSpec::value(
        "T.INV.2T",
        2,
        2,
        t_inv_2t,
        "T.INV.2T(probability, degrees)",
        "Inverse of the two-tailed Student's t distribution",
    )
    .future(),
    FnSpec::value(
        "TDIST",
        3,
        3,
        tdist,
        "TDIST(x, degrees, tails)",
        "One- or two-tailed Student's t distribution (T.DIST.RT, T.DIST.2T)",
    )
    .biff(301),
    FnSpec::value("TINV", 2, 2, t_inv_2t, "TINV(probability, degrees)", "Inverse two-tailed t distribution (T.INV.2T)")
        .biff(332),
    FnSpec::value(
        "WEIBULL",
        4,
        4,
        weibull_dist,
        "WEIBULL(x, alpha, beta, cumulative)",
        "Weibull distribution (WEIBULL.DIST)",
    )
    .biff(302),
    FnSpec::value(
        "WEIBULL.DIST",
        4,
        4,
        weibull_dist,
        "WEIBULL.DIST(x, alpha, beta, cumulative)",
        "Weibull distribution",
    )
    .future(),
];

numeric_fns! {
    norm_dist => |a| normal(a[0], a[1], a[2], a[3] != 0.0);
    norm_s_dist => |a| normal(a[0], 0.0, 1.0, a[1] != 0.0);
    normsdist => |a| normal(a[0], 0.0, 1.0, true);
    norm_inv_fn => |a| {
        open_probability(a[0])?;
        domain(a[2] > 0.0)?;
        Ok(a[1] + a[2] * norm_inv(a[0]))
    };
    norm_s_inv => |a| {
        open_probability(a[0])?;
        Ok(norm_inv(a[0]))
    };
    lognorm_dist => |a| lognormal(a[0], a[1], a[2], a[3] != 0.0);
    lognormdist => |a| lognormal(a[0], a[1], a[2], true);
    lognorm_inv => |a| {
        open_probability(a[0])?;
        domain(a[2] > 0.0)?;
        Ok((a[1] + a[2] * norm_inv(a[0])).exp())
    };
    phi => |a| Ok(norm_pdf(a[0]));
    gauss => |a| Ok(norm_cdf(a[0]) - 0.5);
    standardize => |a| {
        domain(a[2] > 0.0)?;
        Ok((a[0] - a[1]) / a[2])
    };
    fisher => |a| {
        domain(a[0].abs() < 1.0)?;
        // Excel's formula, ½ ln((1+x)/(1−x)), whose rounding near 0 its stored values show
        // (FISHER(1E-10) is 1.00000008264037E-10 there, not atanh's 1E-10).
        Ok(0.5 * ((1.0 + a[0]) / (1.0 - a[0])).ln())
    };
    fisher_inv => |a| Ok(a[0].tanh());
    gamma_fn => |a| {
        domain(!(a[0] <= 0.0 && a[0] == a[0].floor()))?;
        finite(gamma(a[0]))
    };
    gammaln => |a| {
        domain(a[0] > 0.0)?;
        Ok(ln_gamma(a[0]))
    };
    binom_dist => |a| binomial(a[0].trunc(), a[1].trunc(), a[2], a[3] != 0.0);
    binom_dist_range => binomial_range;
    binom_inv => binomial_inverse;
    poisson_dist => |a| {
        domain(a[0] >= 0.0)?;
        poisson(a[0].trunc(), a[1], a[2] != 0.0)
    };
    expon_dist => |a| {
        let (x, lambda) = (a[0], a[1]);
        domain(x >= 0.0 && lambda > 0.0)?;
        Ok(if a[2] != 0.0 { -(-lambda * x).exp_m1() } else { lambda * (-lambda * x).exp() })
    };
    gamma_dist => |a| gamma_distribution(a[0], a[1], a[2], a[3] != 0.0);
    gamma_inv => |a| {
        let (p, alpha, beta) = (a[0], a[1], a[2]);
        domain((0.0..1.0).contains(&p) && alpha > 0.0 && beta > 0.0)?;
        if p == 0.0 {
            return Ok(0.0);
        }
        // Solved for the standard variable x/β: searching x itself, x/β underflowed first
        // and the search settled where it did (β × the smallest double, 2.47E-24 for β = 1E+300),
        // where the quantile is below every double.
        let standard = invert(p, 0.0, alpha, |y| gamma_p(alpha, y))?;
        Ok(if standard < f64::MIN_POSITIVE { 0.0 } else { standard * beta })
    };
    chisq_dist => |a| {
        let (x, df) = (a[0], a[1].trunc());
        domain(x >= 0.0 && (1.0..=1e10).contains(&df))?;
        gamma_distribution(x, df / 2.0, 2.0, a[2] != 0.0)
    };
    chisq_dist_rt => |a| {
        let (x, df) = (a[0], a[1].trunc());
        domain(x >= 0.0 && (1.0..=1e10).contains(&df))?;
        Ok(gamma_q(df / 2.0, x / 2.0))
    };
    chisq_inv => |a| {
        let (p, df) = (a[0], a[1].trunc());
        domain((0.0..1.0).contains(&p) && (1.0..=1e10).contains(&df))?;
        if p == 0.0 {
            return Ok(0.0);
        }
        invert(p, 0.0, df, |x| gamma_p(df / 2.0, x / 2.0))
    };
    chisq_inv_rt => |a| {
        let (p, df) = (a[0], a[1].trunc());
        domain(p > 0.0 && p <= 1.0 && (1.0..=1e10).contains(&df))?;
        if p == 1.0 {
            return Ok(0.0);
        }
        invert(-p, 0.0, df, |x| -gamma_q(df / 2.0, x / 2.0))
    };
    beta_dist => |a| {
        let (lo, hi) = (a.get(4).copied().unwrap_or(0.0), a.get(5).copied().unwrap_or(1.0));
        beta_distribution(a[0], a[1], a[2], a[3] != 0.0, lo, hi)
    };
    betadist => |a| {
        let (lo, hi) = (a.get(3).copied().unwrap_or(0.0), a.get(4).copied().unwrap_or(1.0));
        beta_distribution(a[0], a[1], a[2], true, lo, hi)
    };
    beta_inv => |a| {
        let (p, alpha, beta) = (a[0], a[1], a[2]);
        let (lo, hi) = (a.get(3).copied().unwrap_or(0.0), a.get(4).copied().unwrap_or(1.0));
        domain(p > 0.0 && p < 1.0 && alpha > 0.0 && beta > 0.0 && lo < hi)?;
        // Above the median, solve for 1 - x on the mirrored distribution: 1 - p is exact
        // there, and x near 1 keeps its digits.
        let x = if p <= 0.5 {
            bisect(p, 0.0, 1.0, |x| beta_i(x, alpha, beta))
        } else {
            1.0 - bisect(1.0 - p, 0.0, 1.0, |y| beta_i(y, beta, alpha))
        };
        Ok(lo + x * (hi - lo))
    };
    t_dist => |a| {
        let (x, df) = (a[0], a[1].trunc());
        domain(df >= 1.0)?;
        if a[2] != 0.0 {
            let tail = t_tail(x.abs(), df);
            Ok(if x < 0.0 { tail } else { 1.0 - tail })
        } else {
            Ok(t_density(x, df))
        }
    };
    t_dist_rt => |a| {
        let (x, df) = (a[0], a[1].trunc());
        domain(df >= 1.0)?;
        let tail = t_tail(x.abs(), df);
        Ok(if x < 0.0 { 1.0 - tail } else { tail })
    };
    t_dist_2t => |a| {
        let (x, df) = (a[0], a[1].trunc());
        domain(x >= 0.0 && df >= 1.0)?;
        Ok(2.0 * t_tail(x, df))
    };
    tdist => |a| {
        let (x, df, tails) = (a[0], a[1].trunc(), a[2].trunc());
        domain(x >= 0.0 && df >= 1.0 && (tails == 1.0 || tails == 2.0))?;
        Ok(tails * t_tail(x, df))
    };
    t_inv => |a| {
        let (p, df) = (a[0], a[1].trunc());
        open_probability(p)?;
        domain(df >= 1.0)?;
        let t = t_upper_quantile(2.0 * p.min(1.0 - p), df)?;
        Ok(if p < 0.5 { -t } else { t })
    };
    t_inv_2t => |a| {
        let (p, df) = (a[0], a[1].trunc());
        domain(p > 0.0 && p <= 1.0 && df >= 1.0)?;
        t_upper_quantile(p, df)
    };
    f_dist => |a| {
        let (x, d1, d2) = (a[0], a[1].trunc(), a[2].trunc());
        domain(x >= 0.0 && d1 >= 1.0 && d2 >= 1.0)?;
        Ok(if a[3] != 0.0 { f_cdf(x, d1, d2) } else { f_density(x, d1, d2) })
    };
    f_dist_rt => |a| {
        let (x, d1, d2) = (a[0], a[1].trunc(), a[2].trunc());
        domain(x >= 0.0 && d1 >= 1.0 && d2 >= 1.0)?;
        Ok(f_right_tail(x, d1, d2))
    };
    f_inv => |a| {
        let (p, d1, d2) = (a[0], a[1].trunc(), a[2].trunc());
        domain((0.0..1.0).contains(&p) && d1 >= 1.0 && d2 >= 1.0)?;
        if p == 0.0 {
            return Ok(0.0);
        }
        invert(p, 0.0, 1.0, |x| f_cdf(x, d1, d2))
    };
    f_inv_rt => |a| {
        let (p, d1, d2) = (a[0], a[1].trunc(), a[2].trunc());
        domain(p > 0.0 && p <= 1.0 && d1 >= 1.0 && d2 >= 1.0)?;
        if p == 1.0 {
            return Ok(0.0);
        }
        invert(-p, 0.0, 1.0, |x| -f_right_tail(x, d1, d2))
    };
    hypgeomdist => |a| hypergeometric(a, false, &Cell::new(false));
    negbinom_dist => |a| negative_binomial(a[0].trunc(), a[1].trunc(), a[2], a[3] != 0.0);
    negbinomdist => |a| negative_binomial(a[0].trunc(), a[1].trunc(), a[2], false);
    weibull_dist => |a| {
        let (x, alpha, beta) = (a[0], a[1], a[2]);
        domain(x >= 0.0 && alpha > 0.0 && beta > 0.0)?;
        let z = (x / beta).powf(alpha);
        Ok(if a[3] != 0.0 { -(-z).exp_m1() } else { alpha / beta * (x / beta).powf(alpha - 1.0) * (-z).exp() })
    };
    confidence_norm => |a| {
        let (alpha, sd, n) = (a[0], a[1], a[2].trunc());
        open_probability(alpha)?;
        domain(sd > 0.0 && n >= 1.0)?;
        Ok(norm_inv(1.0 - alpha / 2.0) * sd / n.sqrt())
    };
    confidence_t => |a| {
        let (alpha, sd, n) = (a[0], a[1], a[2].trunc());
        open_probability(alpha)?;
        domain(sd > 0.0 && n >= 1.0)?;
        if n == 1.0 {
            return Err(XlError::Div0);
        }
        Ok(t_upper_quantile(alpha, n - 1.0)? * sd / n.sqrt())
    };
}

fn normal(x: f64, mean: f64, sd: f64, cumulative: bool) -> XlResult<f64> {
    domain(sd > 0.0)?;
    let z = (x - mean) / sd;
    Ok(if cumulative { norm_cdf(z) } else { norm_pdf(z) / sd })
}

fn lognormal(x: f64, mean: f64, sd: f64, cumulative: bool) -> XlResult<f64> {
    domain(x > 0.0 && sd > 0.0)?;
    let z = (x.ln() - mean) / sd;
    Ok(if cumulative { norm_cdf(z) } else { norm_pdf(z) / (sd * x) })
}

/// ln C(n, k) as its three ln Γ terms, for [`exp_of_sum`] to add and judge.
fn ln_choose(n: f64, k: f64) -> [f64; 3] {
    [ln_gamma(n + 1.0), -ln_gamma(k + 1.0), -ln_gamma(n - k + 1.0)]
}

/// C(n, k) as a product while it is exact in a double, else through ln Γ.
fn choose(n: f64, k: f64) -> f64 {
    let k = k.min(n - k);
    if k < 0.0 {
        return 0.0;
    }
    if n <= 1000.0 {
        let mut c = 1.0;
        for i in 0..k as u32 {
            c = c * (n - f64::from(i)) / f64::from(i + 1);
        }
        return c.round();
    }
    exp_of_sum(&ln_choose(n, k))
}

fn binomial_pmf(k: f64, n: f64, p: f64) -> f64 {
    if p == 0.0 {
        return if k == 0.0 { 1.0 } else { 0.0 };
    }
    if p == 1.0 {
        return if k == n { 1.0 } else { 0.0 };
    }
    if n <= 1000.0 {
        return choose(n, k) * p.powf(k) * (1.0 - p).powf(n - k);
    }
    let [a, b, c] = ln_choose(n, k);
    exp_of_sum(&[a, b, c, k * p.ln(), (n - k) * (-p).ln_1p()])
}

fn binomial(k: f64, n: f64, p: f64, cumulative: bool) -> XlResult<f64> {
    domain(k >= 0.0 && k <= n && n < 2f64.powi(53) && (0.0..=1.0).contains(&p))?;
    if !cumulative {
        return Ok(binomial_pmf(k, n, p));
    }
    Ok(binomial_sum(0.0, k, n, p))
}

/// P(lo ≤ X ≤ hi) for X binomial: a sum of terms, as Excel computes it.
fn binomial_sum(lo: f64, hi: f64, n: f64, p: f64) -> f64 {
    if hi - lo > 10_000.0 {
        let below_hi = if hi >= n { 1.0 } else { binomial_cdf(hi, n, p) };
        let below_lo = if lo <= 0.0 { 0.0 } else { binomial_cdf(lo - 1.0, n, p) };
        return below_hi - below_lo;
    }
    let sum: f64 = whole_numbers(lo, hi).map(|k| binomial_pmf(k, n, p)).sum();
    // Rounding may carry the sum a hair past 1; a term that could not be computed (NaN,
    // ln Γ of a count past 1E+307) stays NaN, for #NUM!, where `f64::min` made it 1.
    if sum > 1.0 {
        1.0
    } else {
        sum
    }
}

fn binomial_range(a: &[f64]) -> XlResult<f64> {
    let (n, p, s) = (a[0].trunc(), a[1], a[2].trunc());
    let s2 = a.get(3).map_or(s, |x| x.trunc());
    domain(n >= 0.0 && (0.0..=1.0).contains(&p) && s >= 0.0 && s <= n && s2 >= s && s2 <= n)?;
    Ok(binomial_sum(s, s2, n, p))
}

/// P(X ≤ k) for X binomial(n, p), k < n: the incomplete beta function, or past what it
/// resolves (n p q beyond about 10^8) the normal law, whose error is far below the beta
/// function's rounding there.
fn binomial_cdf(k: f64, n: f64, p: f64) -> f64 {
    let exact = 1.0 - beta_i(p, k + 1.0, n - k);
    if exact.is_nan() {
        binomial_cdf_edgeworth(k, n, p)
    } else {
        exact
    }
}

/// P(X ≤ k) for X binomial(n, p) by the normal law with the continuity correction and the
/// first Edgeworth term (the skewness's): Φ(z) − φ(z)·γ(z² − 1)/6, z = (k + ½ − np)/σ,
/// γ = (1 − 2p)/σ. Its error is of order 1/(npq): for the n the beta function cannot
/// resolve, below 10^-8.
fn binomial_cdf_edgeworth(k: f64, n: f64, p: f64) -> f64 {
    let sigma = (n * p * (1.0 - p)).sqrt();
    // The mean taken off first: past 2^53 a half added to k is rounded away.
    let z = ((k - n * p) + 0.5) / sigma;
    let skew = (1.0 - 2.0 * p) / sigma;
    (norm_cdf(z) - norm_pdf(z) * skew * (z * z - 1.0) / 6.0).clamp(0.0, 1.0)
}

fn binomial_inverse(a: &[f64]) -> XlResult<f64> {
    let (n, p, alpha) = (a[0].trunc(), a[1], a[2]);
    domain(n >= 0.0 && n < 2f64.powi(53) && p > 0.0 && p < 1.0 && alpha > 0.0 && alpha < 1.0)?;
    if n > 10_000.0 {
        // Summing term by term would take n steps (BINOM.INV(1E+15,…)): bisect the
        // cumulative probability instead, which only grows with k.
        let (mut lo, mut hi) = (0.0, n);
        while lo < hi {
            let mid = ((lo + hi) / 2.0).floor();
            let below = binomial_sum(0.0, mid, n, p);
            if below >= alpha {
                hi = mid;
            } else {
                lo = mid + 1.0;
            }
        }
        return Ok(lo);
    }
    let mut sum = 0.0;
    for k in whole_numbers(0.0, n - 1.0) {
        sum += binomial_pmf(k, n, p);
        if sum >= alpha {
            return Ok(k);
        }
    }
    Ok(n)
}

fn poisson(x: f64, mean: f64, cumulative: bool) -> XlResult<f64> {
    domain(x >= 0.0 && mean >= 0.0)?;
    if mean == 0.0 {
        return Ok(if x == 0.0 || cumulative { 1.0 } else { 0.0 });
    }
    if cumulative {
        Ok(gamma_q(x + 1.0, mean))
    } else {
        Ok(exp_of_sum(&[x * mean.ln(), -mean, -ln_gamma(x + 1.0)]))
    }
}

fn gamma_distribution(x: f64, alpha: f64, beta: f64, cumulative: bool) -> XlResult<f64> {
    domain(x >= 0.0 && alpha > 0.0 && beta > 0.0)?;
    if cumulative {
        return Ok(gamma_p(alpha, x / beta));
    }
    if x == 0.0 {
        return match alpha {
            a if a < 1.0 => Err(XlError::Num),
            1.0 => Ok(1.0 / beta),
            _ => Ok(0.0),
        };
    }
    Ok(exp_of_sum(&[(alpha - 1.0) * x.ln(), -x / beta, -ln_gamma(alpha), -alpha * beta.ln()]))
}

fn beta_distribution(x: f64, alpha: f64, beta: f64, cumulative: bool, lo: f64, hi: f64) -> XlResult<f64> {
    domain(alpha > 0.0 && beta > 0.0 && lo < hi && x >= lo && x <= hi)?;
    let y = (x - lo) / (hi - lo);
    if cumulative {
        return Ok(beta_i(y, alpha, beta));
    }
    if (y == 0.0 && alpha < 1.0) || (y == 1.0 && beta < 1.0) {
        return Err(XlError::Num);
    }
    let (y_term, rest_term) = ((alpha - 1.0) * y.ln(), (beta - 1.0) * (-y).ln_1p());
    let ln_b = [-ln_gamma(alpha), -ln_gamma(beta), ln_gamma(alpha + beta)];
    Ok(exp_of_sum(&[y_term, rest_term, ln_b[0], ln_b[1], ln_b[2]]) / (hi - lo))
}

/// P(T > t) for t ≥ 0. Where df / (df + t²) is near 1 it is taken as one minus its
/// complement t² / (df + t²), which keeps its digits (df = 1E+16 rounded it to 1: a
/// probability of 0.5 for every t).
fn t_tail(t: f64, df: f64) -> f64 {
    let x = df / (df + t * t);
    if x < 0.5 {
        0.5 * beta_i(x, df / 2.0, 0.5)
    } else {
        0.5 * (1.0 - beta_i(t * t / (df + t * t), 0.5, df / 2.0))
    }
}

fn t_density(t: f64, df: f64) -> f64 {
    let ln = ln_gamma((df + 1.0) / 2.0)
        - ln_gamma(df / 2.0)
        - 0.5 * (df * std::f64::consts::PI).ln()
        - (df + 1.0) / 2.0 * (t * t / df).ln_1p();
    ln.exp()
}

/// The t ≥ 0 whose two-tailed probability is `p`.
fn t_upper_quantile(p: f64, df: f64) -> XlResult<f64> {
    if p >= 1.0 {
        return Ok(0.0);
    }
    // One degree of freedom is Cauchy's distribution, whose two tails beyond t hold
    // 1 - 2·atan(t)/π: t = cot(πp/2), exact where the search below cannot go (its t² overflows
    // past 1.34E+154, where p is below about 1E-154).
    if df == 1.0 {
        return Ok(1.0 / (std::f64::consts::FRAC_PI_2 * p).tan());
    }
    let t = invert(-p, 0.0, 1.0, |t| -2.0 * t_tail(t, df))?;
    // Where t² overflows the tail reads 0: a t found there is that edge, not the quantile.
    if (t * t).is_infinite() {
        return Err(XlError::Num);
    }
    Ok(t)
}

fn f_cdf(x: f64, d1: f64, d2: f64) -> f64 {
    beta_i(d1 * x / (d1 * x + d2), d1 / 2.0, d2 / 2.0)
}

fn f_right_tail(x: f64, d1: f64, d2: f64) -> f64 {
    beta_i(d2 / (d2 + d1 * x), d2 / 2.0, d1 / 2.0)
}

fn f_density(x: f64, d1: f64, d2: f64) -> f64 {
    if x == 0.0 {
        return if d1 == 2.0 { 1.0 } else { 0.0 };
    }
    let ln = 0.5 * (d1 * (d1 * x).ln() + d2 * d2.ln() - (d1 + d2) * (d1 * x + d2).ln())
        - x.ln()
        - ln_beta(d1 / 2.0, d2 / 2.0);
    ln.exp()
}

fn hypgeom_dist(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let over = Cell::new(false);
    let result = numeric_with(ctx, args, &|a| hypergeometric(a, a[4] != 0.0, &over));
    if over.get() {
        let note = format!(
            "HYPGEOM.DIST sums the probabilities that count one by one: more than ncsheet's limit of {MAX_STEPS} terms"
        );
        ctx.explain(XlError::Num, note);
    }
    result
}

#[cfg(test)]
thread_local! {
    /// Hypergeometric terms computed: counted for a test, which bounds a sum's work by this
    /// count rather than by a clock.
    static TERMS: Cell<u64> = const { Cell::new(0) };
}

/// The hypergeometric law; `over` is set when the cumulative sum needs more than MAX_STEPS
/// terms that count.
fn hypergeometric(a: &[f64], cumulative: bool, over: &Cell<bool>) -> XlResult<f64> {
    let (k, n, big_k, big_n) = (a[0].trunc(), a[1].trunc(), a[2].trunc(), a[3].trunc());
    domain(k >= 0.0 && n > 0.0 && big_k > 0.0 && big_n > 0.0)?;
    domain(n <= big_n && big_k <= big_n && k <= n && k <= big_k && n - k <= big_n - big_k)?;
    let pmf = |j: f64| {
        #[cfg(test)]
        TERMS.with(|c| c.set(c.get() + 1));
        let ([a, b, c], [d, e, f], [g, h, i]) =
            (ln_choose(big_k, j), ln_choose(big_n - big_k, n - j), ln_choose(big_n, n));
        exp_of_sum(&[a, b, c, d, e, f, -g, -h, -i])
    };
    if !cumulative {
        return Ok(pmf(k));
    }
    // A few terms up to k are summed whole. Past that only the terms near the mode count:
    // the side of k away from it is summed until what is left cannot change the result
    // (HYPGEOM.DIST(2E7,1E8,1E8,1E9,TRUE), 3,500 deviations above the mean, is 1, and
    // HYPGEOM.DIST(1E7,2E7,2E7,1E15,TRUE) no longer steps through 1E7 terms of 0). Where
    // even that is too long, the terms up to k, else one minus those above it; past
    // MAX_STEPS of both it is #NUM! with a note (docs/limits.md).
    let (first, last) = ((n - (big_n - big_k)).max(0.0), n.min(big_k));
    let (below, above) = (steps_between(first, k), steps_between(k + 1.0, last));
    let mode = ((n + 1.0) * (big_k + 1.0) / (big_n + 2.0)).floor();
    let near_the_mode = || {
        if k < mode {
            falling_sum(k, -1.0, first, &pmf, true)
        } else {
            falling_sum(k + 1.0, 1.0, last, &pmf, false).map(|above| 1.0 - above)
        }
    };
    let sum = if below <= 10_000.0 {
        whole_numbers(first, k).map(pmf).sum::<f64>()
    } else if let Some(sum) = near_the_mode() {
        sum
    } else if below <= MAX_STEPS {
        whole_numbers(first, k).map(pmf).sum::<f64>()
    } else if above <= MAX_STEPS {
        1.0 - whole_numbers(k + 1.0, last).map(pmf).sum::<f64>()
    } else {
        over.set(true);
        return Err(XlError::Num);
    };
    Ok(sum.clamp(0.0, 1.0))
}

/// Σ pmf(j) for j = from, from + step, … up to `bound`, where the terms fall from the first on
/// (a log-concave law away from its mode: each ratio to the term before is no larger than the
/// last one, so what is left is at most term · r / (1 − r)). Stops once that is below 2^-56
/// of the sum (`relative`) or of 1; `None` past [`MAX_STEPS`] terms.
fn falling_sum(from: f64, step: f64, bound: f64, pmf: &dyn Fn(f64) -> f64, relative: bool) -> Option<f64> {
    let (mut sum, mut before, mut j) = (0.0, f64::NAN, from);
    for _ in 0..MAX_STEPS as u64 {
        if (step > 0.0 && j > bound) || (step < 0.0 && j < bound) {
            return Some(sum);
        }
        let term = pmf(j);
        sum += term;
        let ratio = term / before;
        let left = term * ratio / (1.0 - ratio);
        let scale = if relative { sum } else { 1.0 };
        if term == 0.0 || term.is_nan() || (ratio < 1.0 && left <= scale * 2f64.powi(-56)) {
            return Some(sum);
        }
        before = term;
        j += step;
    }
    None
}

fn negative_binomial(f: f64, s: f64, p: f64, cumulative: bool) -> XlResult<f64> {
    domain(f >= 0.0 && s >= 1.0 && p > 0.0 && p < 1.0)?;
    if cumulative {
        // At least s successes in f + s trials: where the beta function cannot resolve it
        // (f and s past about 10^8), the binomial law's normal form (NEGBINOM.DIST(1E8,1E8,
        // 0.5,TRUE) was #NUM!; Excel gives 0.50003).
        let exact = beta_i(p, s, f + 1.0);
        if exact.is_nan() {
            // Past 2^53 trials `s - 1` and `f + s` are no longer whole numbers a double holds:
            // the law shifted by one success (NEGBINOM.DIST(1E16,1E16,0.5,TRUE) came out below
            // ½) would be noise, so it is #NUM!, as before the normal form.
            domain(f + s <= 2f64.powi(53))?;
            return Ok(1.0 - binomial_cdf_edgeworth(s - 1.0, f + s, p));
        }
        return Ok(exact);
    }
    Ok(choose(f + s - 1.0, s - 1.0) * p.powf(s) * (1.0 - p).powf(f))
}

/// Where the increasing `cdf` reaches `p`, searching up from `lo` with `hi` as a first bracket.
fn invert(p: f64, lo: f64, hi: f64, cdf: impl Fn(f64) -> f64) -> XlResult<f64> {
    invert_increasing(p, lo, hi, cdf).ok_or(XlError::NA)
}

/// Where the increasing `cdf` reaches `p` in the fixed bracket [lo, hi].
fn bisect(p: f64, lo: f64, hi: f64, cdf: impl Fn(f64) -> f64) -> f64 {
    invert_increasing(p, lo, hi, cdf).unwrap_or(hi)
}

#[cfg(test)]
mod tests {
    use crate::eval::testing::MapEnv;
    use crate::eval::value::Value;

    /// 2E7 drawn from 1E15 holding 2E7 marked: the mean is 0.4, so P(X ≤ 1E7) is 1 to every
    /// digit (P(X > 1E7) is below 0.4^1E7 by Markov's bound on the factorial moments). The
    /// 1E7 terms above k were each computed (nine ln Γ apiece, 80 s in a debug build) though
    /// every one is 0: the sum now starts beside k and stops at the first 0.
    #[test]
    fn a_hypergeometric_tail_of_zeros_is_not_stepped_through() {
        let env = MapEnv::default();
        let terms = || super::TERMS.with(std::cell::Cell::get);
        let before = terms();
        assert_eq!(env.eval("=HYPGEOM.DIST(1E7,2E7,2E7,1E15,TRUE)"), Value::Number(1.0));
        assert!(terms() - before < 10, "{} terms", terms() - before);
    }

    // Excel's documentation examples for each function, to the digits the page shows.
    #[test]
    fn documented_examples() {
        let close = |f: &str, want: f64, decimals: i32| {
            let Value::Number(got) = MapEnv::default().eval(f) else { panic!("{f} is not a number") };
            assert!((got - want).abs() <= 0.5 * 10f64.powi(-decimals), "{f}: {got} vs {want}");
        };
        close("NORM.DIST(42,40,1.5,TRUE)", 0.908_788_8, 7);
        close("NORM.INV(0.908789,40,1.5)", 42.000_002, 6);
        close("BINOM.DIST(6,10,0.5,FALSE)", 0.205_078_125, 9);
        close("T.DIST.2T(1.959999998,60)", 0.054_645, 6);
        close("CHISQ.DIST.RT(18.307,10)", 0.050_000_6, 7);
        close("BETA.DIST(2,8,10,TRUE,1,3)", 0.685_470_6, 7);
    }
}
