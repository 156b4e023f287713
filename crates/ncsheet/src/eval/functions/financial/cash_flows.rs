//! Financial functions: annuities (PV FV PMT NPER RATE IPMT PPMT CUMIPMT CUMPRINC ISPMT),
//! cash flows (NPV IRR MIRR XNPV XIRR FVSCHEDULE), depreciation (SLN SYD DB DDB VDB), rates
//! (EFFECT NOMINAL PDURATION RRI), dollar fractions and treasury bills. Signs follow
//! Excel: money paid out is negative. IRR, RATE and XIRR iterate as Excel documents
//! (Newton's method from the guess, 0.1 by default) and give #NUM! when they do not converge.

use crate::eval::functions::api::{
    block, check, finite, number, number_or, numbers, scalar_numbers, whole_numbers, ArgSet, Ctx, FnSpec, Scalars, MANY,
};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::Expr;

use crate::eval::coerce::to_number;
use crate::eval::functions::math::basic::toolpak_number;

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value("PV", 3, 5, pv, "PV(rate, nper, pmt, [fv], [type])", "Present value of an annuity").biff(56),
    FnSpec::value("FV", 3, 5, fv, "FV(rate, nper, pmt, [pv], [type])", "Future value of an annuity").biff(57),
    FnSpec::value("PMT", 3, 5, pmt, "PMT(rate, nper, pv, [fv], [type])", "Payment per period of an annuity").biff(59),
    FnSpec::value("NPER", 3, 5, nper, "NPER(rate, pmt, pv, [fv], [type])", "Number of periods of an annuity").biff(58),
    FnSpec::value(
        "RATE",
        3,
        6,
        rate,
        "RATE(nper, pmt, pv, [fv], [type], [guess])",
        "Interest rate per period of an annuity (Newton's method from guess, 0.1)",
    )
    .biff(60),
    FnSpec::value("IPMT", 4, 6, ipmt, "IPMT(rate, per, nper, pv, [fv], [type])", "Interest part of payment per")
        .biff(167),
    FnSpec::value("PPMT", 4, 6, ppmt, "PPMT(rate, per, nper, pv, [fv], [type])", "Principal part of payment per")
        .biff(168),
    FnSpec::value(
        "CUMIPMT",
        6,
        6,
        cumipmt,
        "CUMIPMT(rate, nper, pv, start_period, end_period, type)",
        "Interest paid between two periods",
    ),
    FnSpec::value(
        "CUMPRINC",
        6,
        6,
        cumprinc,
        "CUMPRINC(rate, nper, pv, start_period, end_period, type)",
        "Principal paid between two periods",
    ),
    FnSpec::value("ISPMT", 4, 4, ispmt, "ISPMT(rate, per, nper, pv)", "Interest of period per with even principal")
        .biff(350),
    FnSpec::value("NPV", 2, MANY, npv, "NPV(rate, value1, …)", "Net present value of payments at period ends")
        .biff(11)
        .range_args(ArgSet::from(1)),
    FnSpec::value("IRR", 1, 2, irr, "IRR(values, [guess])", "Internal rate of return of periodic cash flows")
        .biff(62)
        .range_args(ArgSet::only(0)),
    FnSpec::value("MIRR", 3, 3, mirr, "MIRR(values, finance_rate, reinvest_rate)", "Modified internal rate of return")
        .biff(61)
        .range_args(ArgSet::only(0)),
    FnSpec::value("XNPV", 3, 3, xnpv, "XNPV(rate, values, dates)", "Net present value of dated cash flows")
        .range_args(ArgSet::from(1)),
    FnSpec::value("XIRR", 2, 3, xirr, "XIRR(values, dates, [guess])", "Internal rate of return of dated cash flows")
        .range_args(ArgSet::ALL),
    FnSpec::value(
        "FVSCHEDULE",
        2,
        2,
        fvschedule,
        "FVSCHEDULE(principal, schedule)",
        "principal compounded by each rate of schedule",
    )
    .array_args(ArgSet::only(1)),
    FnSpec::value("SLN", 3, 3, sln, "SLN(cost, salvage, life)", "Straight-line depreciation per period").biff(142),
    FnSpec::value("SYD", 4, 4, syd, "SYD(cost, salvage, life, per)", "Sum-of-years'-digits depreciation").biff(143),
    FnSpec::value("DB", 4, 5, db, "DB(cost, salvage, life, period, [month])", "Fixed-declining-balance depreciation")
        .biff(247),
    FnSpec::value(
        "DDB",
        4,
        5,
        ddb,
        "DDB(cost, salvage, life, period, [factor])",
        "Double- (or factor-) declining-balance depreciation",
    )
    .biff(144),
    FnSpec::value(
        "VDB",
        5,
        7,
        vdb,
        "VDB(cost, salvage, life, start_period, end_period, [factor], [no_switch])",
        "Declining-balance depreciation between two periods, switching to straight line",
    )
    .biff(222),
    FnSpec::value("EFFECT", 2, 2, effect, "EFFECT(nominal_rate, npery)", "Effective annual rate"),
    FnSpec::value("NOMINAL", 2, 2, nominal, "NOMINAL(effect_rate, npery)", "Nominal annual rate"),
    FnSpec::value("PDURATION", 3, 3, pduration, "PDURATION(rate, pv, fv)", "Periods for pv to grow to fv").future(),
    FnSpec::value("RRI", 3, 3, rri, "RRI(nper, pv, fv)", "Rate per period for pv to grow to fv").future(),
    FnSpec::value(
        "DOLLARDE",
        2,
        2,
        dollarde,
        "DOLLARDE(fractional_dollar, fraction)",
        "A price written in fractions (1.02 with fraction 16 = 1 2/16) as a decimal",
    ),
    FnSpec::value(
        "DOLLARFR",
        2,
        2,
        dollarfr,
        "DOLLARFR(decimal_dollar, fraction)",
        "A decimal price written in fractions of fraction",
    ),
    FnSpec::value(
        "TBILLPRICE",
        3,
        3,
        tbillprice,
        "TBILLPRICE(settlement, maturity, discount)",
        "Price per 100 face value of a treasury bill",
    ),
    FnSpec::value("TBILLYIELD", 3, 3, tbillyield, "TBILLYIELD(settlement, maturity, pr)", "Yield of a treasury bill"),
    FnSpec::value(
        "TBILLEQ",
        3,
        3,
        tbilleq,
        "TBILLEQ(settlement, maturity, discount)",
        "Bond-equivalent yield of a treasury bill",
    ),
];

/// The annuity type argument: 0 (payments at period ends) or anything else (beginnings).
fn payment_type(a: Scalars, i: usize) -> XlResult<f64> {
    Ok(if a.num_or(i, 0.0)? != 0.0 { 1.0 } else { 0.0 })
}

fn pv_of(rate: f64, nper: f64, pmt: f64, fv: f64, kind: f64) -> f64 {
    if rate == 0.0 {
        return -(fv + pmt * nper);
    }
    let growth = (1.0 + rate).powf(nper);
    if growth.is_infinite() {
        // Divided through by the growth: PV(1000,1000,1) is −0.001 (LibreOffice), not ∞/∞.
        let shrink = growth_inverse(rate, nper);
        return -(fv * shrink + pmt * (1.0 + rate * kind) * (1.0 - shrink) / rate);
    }
    -(fv + pmt * (1.0 + rate * kind) * (growth - 1.0) / rate) / growth
}

/// 1 / (1 + rate)^nper where the growth itself is past the doubles: through ln(1 + rate), so
/// that it is the (tiny, perhaps 0) number it is rather than 1/∞ after an overflow.
fn growth_inverse(rate: f64, nper: f64) -> f64 {
    (-nper * rate.ln_1p()).exp()
}

fn fv_of(rate: f64, nper: f64, pmt: f64, pv: f64, kind: f64) -> f64 {
    if rate == 0.0 {
        return -(pv + pmt * nper);
    }
    let growth = (1.0 + rate).powf(nper);
    -(pv * growth + pmt * (1.0 + rate * kind) * (growth - 1.0) / rate)
}

fn pmt_of(rate: f64, nper: f64, pv: f64, fv: f64, kind: f64) -> f64 {
    if rate == 0.0 {
        return -(pv + fv) / nper;
    }
    let growth = (1.0 + rate).powf(nper);
    if growth.is_infinite() {
        // Divided through by the growth: a loan at 100 % over 2,000 periods pays its interest,
        // PMT(1,2000,1000) = −1000 (exact arithmetic), where ∞/∞ was #NUM!; CUMIPMT, IPMT and
        // PPMT read their payment here.
        let shrink = growth_inverse(rate, nper);
        return -(fv * shrink + pv) * (rate / ((1.0 + rate * kind) * (1.0 - shrink)));
    }
    -(fv + pv * growth) * rate / ((1.0 + rate * kind) * (growth - 1.0))
}

/// At a rate of −1 the growth (1+rate)^nper is 0 (or 0 to a negative power, infinite):
/// Excel's division by it is #DIV/0!.
fn no_zero_growth(rate: f64, nper: f64, divides: bool) -> XlResult<()> {
    check(rate != -1.0 || !(divides || nper < 0.0), XlError::Div0)
}

fn pv(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (rate, nper) = (a.num(0)?, a.num(1)?);
        let (pmt, fv, kind) = (a.num(2)?, a.num_or(3, 0.0)?, payment_type(a, 4)?);
        no_zero_growth(rate, nper, true)?;
        finite(pv_of(rate, nper, pmt, fv, kind))
    })
}

fn fv(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (rate, nper) = (a.num(0)?, a.num(1)?);
        let (pmt, pv, kind) = (a.num(2)?, a.num_or(3, 0.0)?, payment_type(a, 4)?);
        no_zero_growth(rate, nper, false)?;
        finite(fv_of(rate, nper, pmt, pv, kind))
    })
}

fn pmt(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (rate, nper) = (a.num(0)?, a.num(1)?);
        // Excel refuses a rate of −1 or below (no sensible loan shrinks that fast).
        check(nper != 0.0 && rate > -1.0, XlError::Num)?;
        finite(pmt_of(rate, nper, a.num(2)?, a.num_or(3, 0.0)?, payment_type(a, 4)?))
    })
}

fn nper(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (rate, pmt, pv, fv, kind) = (a.num(0)?, a.num(1)?, a.num(2)?, a.num_or(3, 0.0)?, payment_type(a, 4)?);
        if rate == 0.0 {
            check(pmt != 0.0, XlError::Num)?;
            return finite(-(pv + fv) / pmt);
        }
        // ln of the ratio (pmt(1 + rate·kind) - fv·rate) / (pv·rate + pmt(1 + rate·kind)),
        // taken as ln(1 + its difference from 1): at a rate of 1E-300 the ratio rounded to 1
        // and NPER(1E-300,-1,1000) was 0 periods instead of 1000.
        let change = -rate * (fv + pv) / (pv * rate + pmt * (1.0 + rate * kind));
        check(change > -1.0, XlError::Num)?;
        finite(change.ln_1p() / rate.ln_1p())
    })
}

fn rate(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (nper, pmt, pv, fv, kind) = (a.num(0)?, a.num(1)?, a.num(2)?, a.num_or(3, 0.0)?, payment_type(a, 4)?);
        let guess = a.num_or(5, 0.1)?;
        check(nper > 0.0, XlError::Num)?;
        // The balance after nper periods at rate r: zero at the rate sought.
        let balance = |r: f64| {
            if r == 0.0 {
                pv + pmt * nper + fv
            } else {
                let growth = (1.0 + r).powf(nper);
                pv * growth + pmt * (1.0 + r * kind) * (growth - 1.0) / r + fv
            }
        };
        newton(&balance, guess, 50, 1e-10).map(Value::Number)
    })
}

/// A root of `f` by Newton's method with a numeric derivative, from `guess`: at most
/// `iterations` steps, done when a step is below `tolerance`; #NUM! otherwise.
fn newton(f: &impl Fn(f64) -> f64, guess: f64, iterations: usize, tolerance: f64) -> XlResult<f64> {
    let mut x = guess;
    for _ in 0..iterations {
        let y = f(x);
        let h = 1e-7 * x.abs().max(1e-3);
        let slope = (f(x + h) - f(x - h)) / (2.0 * h);
        check(slope != 0.0 && slope.is_finite() && y.is_finite(), XlError::Num)?;
        let step = y / slope;
        x -= step;
        if step.abs() <= tolerance * x.abs().max(1.0) {
            check(x.is_finite() && x > -1.0, XlError::Num)?;
            return Ok(x);
        }
    }
    Err(XlError::Num)
}

/// The interest part of payment `per` (1-based).
fn ipmt_of(rate: f64, per: f64, nper: f64, pv: f64, fv: f64, kind: f64) -> f64 {
    let pmt = pmt_of(rate, nper, pv, fv, kind);
    let balance = if per == 1.0 {
        if kind == 1.0 {
            0.0
        } else {
            -pv
        }
    } else {
        // Paid in advance, the balance before `per` is one payment less than after per − 2.
        let periods = if kind == 1.0 { per - 2.0 } else { per - 1.0 };
        let after = balance_after(rate, periods, nper, pv, fv).unwrap_or_else(|| fv_of(rate, periods, pmt, pv, kind));
        if kind == 1.0 {
            after - pmt
        } else {
            after
        }
    };
    balance * rate
}

/// What is owed after `m` of the `n` payments of a loan of `pv` leaving `fv`, with the sign
/// FV gives it: −pv·(gⁿ − gᵐ)/(gⁿ − 1) + fv·(gᵐ − 1)/(gⁿ − 1), g = 1 + rate, each ratio
/// written with exponents of at most 0 through expm1. FV's own form, pv·gᵐ + pmt·(gᵐ − 1)/rate,
/// subtracts two numbers near pv·gᵐ: at 1E-4 over 3E6 periods they pass 1E+46 and the
/// interest of payment 1E6 (−0.1) came out 0. `None` where the forms do not hold (a rate of 0
/// or at most −1) or overflow, for FV's form.
fn balance_after(rate: f64, m: f64, n: f64, pv: f64, fv: f64) -> Option<f64> {
    if rate == 0.0 || rate <= -1.0 {
        return None;
    }
    let ln_g = rate.ln_1p();
    let left = ((m - n) * ln_g).exp_m1() / (-n * ln_g).exp_m1();
    let grown = if fv == 0.0 {
        0.0
    } else if n * ln_g > 1.0 {
        ((m - n) * ln_g).exp() * (-m * ln_g).exp_m1() / (-n * ln_g).exp_m1()
    } else {
        (m * ln_g).exp_m1() / (n * ln_g).exp_m1()
    };
    Some(-pv * left + fv * grown).filter(|b| b.is_finite())
}

fn ipmt(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (rate, per, nper, pv) = (a.num(0)?, a.num(1)?, a.num(2)?, a.num(3)?);
        let (fv, kind) = (a.num_or(4, 0.0)?, payment_type(a, 5)?);
        check(per >= 1.0 && per < nper + 1.0, XlError::Num)?;
        finite(ipmt_of(rate, per, nper, pv, fv, kind))
    })
}

fn ppmt(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (rate, per, nper, pv) = (a.num(0)?, a.num(1)?, a.num(2)?, a.num(3)?);
        let (fv, kind) = (a.num_or(4, 0.0)?, payment_type(a, 5)?);
        check(per >= 1.0 && per < nper + 1.0, XlError::Num)?;
        finite(ppmt_of(rate, per, nper, pv, fv, kind))
    })
}

/// The principal part of payment `per` (1-based), PMT − IPMT worked out by hand: with
/// g = 1 + rate, −rate·(pv + fv)·g^(per−1−kind)/(gⁿ − 1), the first payment in advance being
/// all principal. Taken as that difference it lost every digit on a long loan:
/// PPMT(1E-4,1E6,3E6,1000) was 0 (about −1.4E-88) and PPMT(1E-4,3E6,3E6,1000) −219902325.66
/// (about −0.1). The power and gⁿ − 1 go through exp and expm1 with exponents of at most 0,
/// so neither overflows nor cancels; rate is divided first, so a tiny rate does not overflow.
fn ppmt_of(rate: f64, per: f64, nper: f64, pv: f64, fv: f64, kind: f64) -> f64 {
    if kind == 1.0 && per == 1.0 {
        return pmt_of(rate, nper, pv, fv, kind);
    }
    if rate == 0.0 || rate <= -1.0 {
        return pmt_of(rate, nper, pv, fv, kind) - ipmt_of(rate, per, nper, pv, fv, kind);
    }
    let (ln_g, k) = (rate.ln_1p(), per - 1.0 - kind);
    let share = if nper * ln_g > 0.0 {
        rate / -(-nper * ln_g).exp_m1() * ((k - nper) * ln_g).exp()
    } else {
        rate / (nper * ln_g).exp_m1() * (k * ln_g).exp()
    };
    -(pv + fv) * share
}

/// The most periods a function sums one by one. CUMIPMT, CUMPRINC and DB sum longer spans
/// as geometric series (below it they step as Excel does, to its last digit); VDB, whose
/// switch to straight line has no closed form, is #NUM! past it with a note (docs/limits.md).
const MAX_PERIODS: f64 = 1e6;

/// CUMIPMT and CUMPRINC: Excel reads the periods as whole ones (the start rounded up, the
/// end down) and nper as given; booleans are #VALUE! (Analysis ToolPak functions).
fn cumulative(ctx: &mut Ctx, args: &[Expr], principal: bool) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let number = |i| toolpak_number(a.value(i), a.1);
        let (rate, nper, pv) = (number(0)?, number(1)?, number(2)?);
        let (start, end, kind) = (number(3)?.ceil(), number(4)?.trunc(), number(5)?);
        check(rate > 0.0 && nper > 0.0 && pv > 0.0, XlError::Num)?;
        check(start >= 1.0 && end >= start && end <= nper && (kind == 0.0 || kind == 1.0), XlError::Num)?;
        let stepped = end - start <= MAX_PERIODS;
        let repaid = if stepped {
            principal_paid(rate, nper, pv, start, end, kind)
        } else {
            principal_paid_in_closed_form(rate, nper, pv, start, end, kind)
        };
        if principal {
            return finite(repaid);
        }
        if stepped {
            return finite(whole_numbers(start, end).map(|per| ipmt_of(rate, per, nper, pv, 0.0, kind)).sum());
        }
        // Every payment is interest and principal: the interest is what the principal leaves.
        finite((end - start + 1.0) * pmt_of(rate, nper, pv, 0.0, kind) - repaid)
    })
}

/// The principal repaid by payments `start` to `end` of a loan of `pv` (no future value),
/// each payment's share as PPMT's [`ppmt_of`] (not payment minus interest, whose difference
/// loses every digit when the rate is high). Its powers stay finite where (1+rate)^nper
/// overflows: CUMPRINC(0.001,2E6,1000,2E6,2E6,0) was #NUM! (about −0.999).
fn principal_paid(rate: f64, nper: f64, pv: f64, start: f64, end: f64, kind: f64) -> f64 {
    whole_numbers(start, end).map(|per| ppmt_of(rate, per, nper, pv, 0.0, kind)).sum()
}

/// [`principal_paid`] as the sum of its geometric series, for spans too long to step
/// through: with g = 1 + rate, a = start − 1 − kind and c payments,
/// −pv·rate/(gⁿ − 1) · gᵃ(gᶜ − 1)/rate = −pv · (g^(a+c−n) − g^(a−n)) / (1 − g⁻ⁿ),
/// written with powers of at most 1 (a + c ≤ n), which neither overflow nor cancel.
fn principal_paid_in_closed_form(rate: f64, nper: f64, pv: f64, start: f64, end: f64, kind: f64) -> f64 {
    let (mut sum, mut start) = (0.0, start);
    if kind == 1.0 && start == 1.0 {
        sum = pmt_of(rate, nper, pv, 0.0, 1.0);
        start = 2.0;
    }
    let (ln_g, a, c) = (rate.ln_1p(), start - 1.0 - kind, end - start + 1.0);
    let powers = if c * ln_g < 1.0 {
        // A short or slow series: its two powers are close, and expm1 keeps their difference.
        ((a - nper) * ln_g).exp() * (c * ln_g).exp_m1()
    } else {
        ((a + c - nper) * ln_g).exp() - ((a - nper) * ln_g).exp()
    };
    sum - pv * powers / -(-nper * ln_g).exp_m1()
}

fn cumipmt(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    cumulative(ctx, args, false)
}

fn cumprinc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    cumulative(ctx, args, true)
}

fn ispmt(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (rate, per, nper, pv) = (a.num(0)?, a.num(1)?, a.num(2)?, a.num(3)?);
        check(nper != 0.0, XlError::Div0)?;
        finite(pv * rate * (per / nper - 1.0))
    })
}

fn npv_of(rate: f64, values: &[f64]) -> f64 {
    values.iter().enumerate().map(|(i, v)| v / (1.0 + rate).powi(i as i32 + 1)).sum()
}

fn npv(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let rate = numbers(ctx, &args[..1])?.first().copied().unwrap_or(0.0);
    check(rate != -1.0, XlError::Div0)?;
    let values = numbers(ctx, &args[1..])?;
    finite(npv_of(rate, &values))
}

/// The numbers of a range or array argument, in order; other items skipped, errors kept.
fn cash_flows(ctx: &mut Ctx, e: &Expr) -> XlResult<Vec<f64>> {
    numbers(ctx, std::slice::from_ref(e))
}

/// The guess of IRR and XIRR: 0.1 when omitted; a number above −1, else #VALUE!.
fn guess_arg(ctx: &mut Ctx, args: &[Expr], i: usize) -> XlResult<f64> {
    let guess = number_or(ctx, args, i, 0.1)?;
    check(guess > -1.0, XlError::Value)?;
    Ok(guess)
}

fn irr(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let values = cash_flows(ctx, &args[0])?;
    let guess = guess_arg(ctx, args, 1)?;
    check(values.iter().any(|v| *v > 0.0) && values.iter().any(|v| *v < 0.0), XlError::Num)?;
    let f = |r: f64| values.iter().enumerate().map(|(i, v)| v / (1.0 + r).powi(i as i32)).sum::<f64>();
    let slope =
        |r: f64| values.iter().enumerate().map(|(i, v)| -(i as f64) * v / (1.0 + r).powi(i as i32 + 1)).sum::<f64>();
    solve_rate(f, slope, guess).map(Value::Number)
}

/// A rate above −1 where `f` is zero: Newton's method from `guess` (as Excel iterates), and
/// where that fails (it overshoots below −1 or wanders off) the root whose sign change is
/// nearest the guess on a grid of rates from just above −1 to 1000, bisected to the last
/// digit. #NUM! when there is none.
fn solve_rate(f: impl Fn(f64) -> f64, slope: impl Fn(f64) -> f64, guess: f64) -> XlResult<f64> {
    if let Some(r) = newton_exact(&f, &slope, guess) {
        return Ok(r);
    }
    let grid = rate_grid();
    let nearest = grid
        .windows(2)
        .filter(|w| f(w[0]).signum() * f(w[1]).signum() <= 0.0 && f(w[0]).is_finite() && f(w[1]).is_finite())
        .min_by(|a, b| distance(a, guess).total_cmp(&distance(b, guess)));
    let [mut lo, mut hi] = match nearest {
        Some(w) => [w[0], w[1]],
        None => return Err(XlError::Num),
    };
    let lo_sign = f(lo).signum();
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if f(mid).signum() == lo_sign {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(if f(lo).abs() <= f(hi).abs() { lo } else { hi })
}

/// Newton's method with the exact slope, from `guess`: the rate once a step is below the
/// last digits (or f is exactly 0), `None` when it leaves the rates above −1 or does not
/// settle in 100 steps.
fn newton_exact(f: &impl Fn(f64) -> f64, slope: &impl Fn(f64) -> f64, guess: f64) -> Option<f64> {
    let mut x = guess;
    for _ in 0..100 {
        let (y, dy) = (f(x), slope(x));
        if y == 0.0 {
            return Some(x);
        }
        // An overflowed value or slope (flows near 1E308) makes the step 0 or NaN, which
        // would pass for convergence at the guess: the grid search takes over instead.
        if !(y.is_finite() && dy.is_finite()) {
            return None;
        }
        let step = y / dy;
        if !step.is_finite() {
            return None;
        }
        x -= step;
        if !(x > -1.0 && x.is_finite()) {
            return None;
        }
        if step.abs() <= 1e-13 * x.abs().max(1e-6) {
            return Some(x);
        }
    }
    None
}

/// How far the bracket `w` lies from `x`.
fn distance(w: &[f64], x: f64) -> f64 {
    if (w[0]..=w[1]).contains(&x) {
        0.0
    } else {
        (w[0] - x).abs().min((w[1] - x).abs())
    }
}

/// Rates to look for a sign change between: dense near −1, where the discount factors
/// explode, then every 0.05 to 1, then coarser to 1000.
fn rate_grid() -> Vec<f64> {
    let mut grid: Vec<f64> = (1..=8).rev().map(|k| -1.0 + 10f64.powi(-k)).collect();
    grid.extend((-18..=20).map(|k| f64::from(k) * 0.05));
    grid.extend([1.5, 2.0, 3.0, 5.0, 10.0, 20.0, 50.0, 100.0, 1000.0]);
    grid
}

/// MIRR: the negative flows discounted at the finance rate to the start, the positive ones
/// compounded at the reinvestment rate to the end (a finance rate of −1 discounts nothing
/// at the start). No negative flow is #DIV/0!; no positive one gives −1.
fn mirr(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let values = cash_flows(ctx, &args[0])?;
    let finance = number(ctx, &args[1])?;
    let reinvest = number(ctx, &args[2])?;
    let n = values.len();
    check(n > 1, XlError::Div0)?;
    let mut paid = 0.0;
    let mut earned = 0.0;
    for (i, v) in values.iter().enumerate() {
        if *v < 0.0 {
            paid += if i == 0 { *v } else { v / (1.0 + finance).powi(i as i32) };
        } else {
            earned += v * (1.0 + reinvest).powi((n - 1 - i) as i32);
        }
    }
    check(paid != 0.0 && paid.is_finite(), XlError::Div0)?;
    finite((-earned / paid).powf(1.0 / (n - 1) as f64) - 1.0)
}

/// Dated cash flows: as many dates as values, dates whole days from 0 on, none before the
/// first. A blank value is #NUM! for XNPV and 0 for XIRR; a text or boolean value #NUM! for
/// XNPV and #VALUE! for XIRR (Excel's choices).
fn dated_flows(ctx: &mut Ctx, values: &Expr, dates: &Expr, strict: bool) -> XlResult<(Vec<f64>, Vec<f64>)> {
    let (system, locale) = (ctx.dates(), ctx.locale());
    let not_number = if strict { XlError::Num } else { XlError::Value };
    let values: Vec<f64> = block(ctx, values)?
        .data
        .iter()
        .map(|v| match v {
            Value::Number(n) => Ok(*n),
            Value::Blank if !strict => Ok(0.0),
            Value::Blank => Err(XlError::Num),
            Value::Error(e) => Err(*e),
            _ => Err(not_number),
        })
        .collect::<XlResult<_>>()?;
    let dates: Vec<f64> = block(ctx, dates)?
        .data
        .iter()
        .map(|v| match v {
            Value::Error(e) => Err(*e),
            // Date text read in the locale (`"12.03.2025"` in de-DE).
            v => Ok(to_number(&locale.numbers_for_arithmetic(v.clone(), system), system)?.trunc()),
        })
        .collect::<XlResult<_>>()?;
    check(values.len() == dates.len() && !values.is_empty(), XlError::Num)?;
    check(dates.iter().all(|d| *d >= dates[0] && *d >= 0.0), XlError::Num)?;
    Ok((values, dates))
}

fn xnpv_of(rate: f64, values: &[f64], dates: &[f64]) -> f64 {
    values.iter().zip(dates).map(|(v, d)| v / (1.0 + rate).powf((d - dates[0]) / 365.0)).sum()
}

fn xnpv(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let rate = number(ctx, &args[0])?;
    let (values, dates) = dated_flows(ctx, &args[1], &args[2], true)?;
    check(rate >= 0.0, XlError::Num)?;
    finite(xnpv_of(rate, &values, &dates))
}

fn xirr(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let (values, dates) = dated_flows(ctx, &args[0], &args[1], false)?;
    let guess = guess_arg(ctx, args, 2)?;
    check(values.iter().any(|v| *v > 0.0) && values.iter().any(|v| *v < 0.0), XlError::Num)?;
    let slope = |r: f64| {
        let years = dates.iter().map(|d| (d - dates[0]) / 365.0);
        values.iter().zip(years).map(|(v, t)| -t * v / (1.0 + r).powf(t + 1.0)).sum::<f64>()
    };
    solve_rate(|r| xnpv_of(r, &values, &dates), slope, guess).map(Value::Number)
}

fn fvschedule(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let principal = numbers(ctx, &args[..1])?.first().copied().unwrap_or(0.0);
    let schedule = block(ctx, &args[1])?;
    let mut value = principal;
    for r in &schedule.data {
        value *= 1.0
            + match r {
                Value::Number(n) => *n,
                Value::Blank => 0.0,
                Value::Error(e) => return Err(*e),
                _ => return Err(XlError::Value),
            };
    }
    finite(value)
}

fn sln(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let life = a.num(2)?;
        check(life != 0.0, XlError::Div0)?;
        finite((a.num(0)? - a.num(1)?) / life)
    })
}

fn syd(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (cost, salvage, life, per) = (a.num(0)?, a.num(1)?, a.num(2)?, a.num(3)?);
        check(life > 0.0 && per > 0.0 && per <= life, XlError::Num)?;
        // Divided in two steps: life × (life + 1) overflows past a life of 1E154.
        finite((cost - salvage) * 2.0 * ((life - per + 1.0) / life) / (life + 1.0))
    })
}

fn db(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (cost, salvage, life, period) = (a.num(0)?, a.num(1)?, a.num(2)?, a.num(3)?.trunc());
        let month = a.num_or(4, 12.0)?.trunc();
        check(cost >= 0.0 && salvage >= 0.0 && life > 0.0 && period > 0.0, XlError::Num)?;
        check((1.0..=12.0).contains(&month) && period <= life + 1.0, XlError::Num)?;
        check(month < 12.0 || period <= life, XlError::Num)?;
        if cost == 0.0 {
            return Ok(Value::Number(0.0));
        }
        // Excel rounds the rate to three decimals.
        let rate = ((1.0 - (salvage / cost).powf(1.0 / life)) * 1000.0).round() / 1000.0;
        let first = cost * rate * month / 12.0;
        if period == 1.0 {
            return finite(first);
        }
        // What is left of the cost before `period`: stepped as Excel does, or past
        // MAX_PERIODS as the geometric series it is (each period takes `rate` of what is left).
        let left = if period <= MAX_PERIODS {
            let mut total = first;
            for _ in whole_numbers(2.0, period - 1.0) {
                total += (cost - total) * rate;
            }
            cost - total
        } else {
            (cost - first) * (1.0 - rate).powf(period - 2.0)
        };
        // The period after the life holds the months the first one lacked.
        finite(if period == life + 1.0 { left * rate * (12.0 - month) / 12.0 } else { left * rate })
    })
}

fn ddb(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (cost, salvage, life, period) = (a.num(0)?, a.num(1)?, a.num(2)?, a.num(3)?);
        let factor = a.num_or(4, 2.0)?;
        check(cost >= 0.0 && salvage >= 0.0 && life > 0.0 && period > 0.0 && factor > 0.0, XlError::Num)?;
        check(period <= life, XlError::Num)?;
        finite(ddb_of(cost, salvage, life, period, factor))
    })
}

/// Declining-balance depreciation of `period` (1-based), never below the salvage.
fn ddb_of(cost: f64, salvage: f64, life: f64, period: f64, factor: f64) -> f64 {
    let mut rate = factor / life;
    let before = if rate >= 1.0 {
        rate = 1.0;
        if period == 1.0 {
            cost
        } else {
            0.0
        }
    } else {
        worth_after(cost, rate, period - 1.0)
    };
    let after = worth_after(cost, rate, period);
    // before − after, written as before × rate: at a life of 1E16 the two worths agree to
    // the last digit and their difference cancelled to 0.
    let depreciation = if after < salvage { before - salvage } else { before * rate };
    depreciation.max(0.0)
}

/// What is left of `cost` after `periods` periods losing `rate` (< 1) of it each:
/// cost × (1 − rate)^periods, through ln(1 − rate) so a rate below a double's resolution
/// near 1 (a life past 2^53) is not rounded.
fn worth_after(cost: f64, rate: f64, periods: f64) -> f64 {
    cost * (periods * (-rate).ln_1p()).exp()
}

/// VDB: the declining-balance depreciation from `start` to `end` (fractions of periods
/// prorated), switching to straight line on what is left once that is larger unless
/// `no_switch`.
fn vdb(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let over = std::cell::Cell::new(false);
    let result = scalar_numbers(ctx, args, &|a| {
        let (cost, salvage, life, start, end) = (a.num(0)?, a.num(1)?, a.num(2)?, a.num(3)?, a.num(4)?);
        let factor = a.num_or(5, 2.0)?;
        let no_switch = if a.given(6) { crate::eval::coerce::to_bool(a.value(6))? } else { false };
        check(start >= 0.0 && end >= start && end <= life && cost >= 0.0 && salvage <= cost, XlError::Num)?;
        check(factor > 0.0 && life > 0.0, XlError::Num)?;
        let (first, last) = (start.floor(), end.ceil());
        // The work is the periods stepped, not the life: VDB(1000,0,1E7,0,10) is ten periods
        // (it was #NUM! for its life of 1E+7, which Excel computes).
        let stepped = if no_switch { last - first } else { last };
        if stepped > MAX_PERIODS {
            over.set(true);
            return Err(XlError::Num);
        }
        if no_switch {
            let mut total = 0.0;
            let mut period = first + 1.0;
            while period <= last {
                let mut part = ddb_of(cost, salvage, life, period, factor);
                if period == first + 1.0 {
                    part *= end.min(first + 1.0) - start;
                } else if period == last {
                    part *= end + 1.0 - last;
                }
                total += part;
                period += 1.0;
            }
            return finite(total);
        }
        // Whole periods from `first` to `last`, less the fractions outside start..end.
        let mut outside = 0.0;
        if start > first {
            let value = cost - switching_ddb(cost, salvage, life, life, first, factor);
            outside += (start - first) * switching_ddb(value, salvage, life, life - first, 1.0, factor);
        }
        if end < last {
            let value = cost - switching_ddb(cost, salvage, life, life, last - 1.0, factor);
            outside += (last - end) * switching_ddb(value, salvage, life, life - last + 1.0, 1.0, factor);
        }
        let value = cost - switching_ddb(cost, salvage, life, life, first, factor);
        finite(switching_ddb(value, salvage, life, life - first, last - first, factor) - outside)
    });
    if over.get() {
        let note = format!("VDB steps through the periods up to its end one by one: more than ncsheet's limit of {MAX_PERIODS} periods");
        ctx.explain(XlError::Num, note);
    }
    result
}

/// The depreciation over the first `periods` periods of an asset worth `cost` with
/// `remaining` periods of life left: declining balance until straight line over the
/// remaining life gives more, straight line from then on.
fn switching_ddb(cost: f64, salvage: f64, life: f64, remaining: f64, periods: f64, factor: f64) -> f64 {
    let last = periods.ceil();
    let (mut total, mut left, mut straight, mut switched) = (0.0, cost - salvage, 0.0, false);
    let mut period = 1.0;
    while period <= last {
        let mut part = if switched {
            straight
        } else {
            let declining = ddb_of(cost, salvage, life, period, factor);
            straight = left / (remaining - (period - 1.0));
            if straight > declining {
                switched = true;
                straight
            } else {
                left -= declining;
                declining
            }
        };
        if period == last {
            part *= periods + 1.0 - last;
        }
        total += part;
        period += 1.0;
    }
    total
}

fn effect(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (nominal, npery) = (toolpak_number(a.value(0), a.1)?, toolpak_number(a.value(1), a.1)?.trunc());
        check(nominal > 0.0 && npery >= 1.0, XlError::Num)?;
        finite((1.0 + nominal / npery).powf(npery) - 1.0)
    })
}

fn nominal(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (effect, npery) = (toolpak_number(a.value(0), a.1)?, toolpak_number(a.value(1), a.1)?.trunc());
        check(effect > 0.0 && npery >= 1.0, XlError::Num)?;
        // Excel's formula in doubles, as Excel computes it: its stored values match it to the
        // last bit (IronCalc corpus NOMINAL_EFFECT.xlsx), and at 1E+15 periods it keeps only
        // the digits the power has (NOMINAL(1E300,1E15) is 690.78077, exactly 690.77553).
        finite(((1.0 + effect).powf(1.0 / npery) - 1.0) * npery)
    })
}

fn pduration(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (rate, pv, fv) = (a.num(0)?, a.num(1)?, a.num(2)?);
        check(rate > 0.0 && pv > 0.0 && fv > 0.0, XlError::Num)?;
        finite((fv.ln() - pv.ln()) / rate.ln_1p())
    })
}

fn rri(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let (nper, pv, fv) = (a.num(0)?, a.num(1)?, a.num(2)?);
        check(nper > 0.0 && pv != 0.0, XlError::Num)?;
        finite((fv / pv).powf(1.0 / nper) - 1.0)
    })
}

/// The fraction argument of DOLLARDE and DOLLARFR, and the power of ten above it.
fn fraction(a: Scalars) -> XlResult<(f64, f64)> {
    let f = toolpak_number(a.value(1), a.1)?.trunc();
    check(f >= 0.0, XlError::Num)?;
    check(f != 0.0, XlError::Div0)?;
    Ok((f, 10f64.powf(f.log10().ceil())))
}

fn dollarde(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let x = toolpak_number(a.value(0), a.1)?;
        let (f, scale) = fraction(a)?;
        finite(x.trunc() + x.fract() * scale / f)
    })
}

fn dollarfr(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let x = toolpak_number(a.value(0), a.1)?;
        let (f, scale) = fraction(a)?;
        finite(x.trunc() + x.fract() * f / scale)
    })
}

/// Settlement and maturity of a treasury bill (whole days), the days between them: at
/// most a year, maturity after settlement.
fn bill_days(a: Scalars) -> XlResult<f64> {
    let (settlement, maturity) = (toolpak_number(a.value(0), a.1)?.trunc(), toolpak_number(a.value(1), a.1)?.trunc());
    check(settlement >= 0.0 && maturity > settlement, XlError::Num)?;
    let (y, m, d) = crate::eval::dates::ymd_from_serial(a.1, settlement as i64);
    let year_later = crate::eval::dates::serial_from_ymd(a.1, y + 1, i64::from(m), i64::from(d)) as f64;
    check(maturity <= year_later, XlError::Num)?;
    Ok(maturity - settlement)
}

fn tbillprice(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let days = bill_days(a)?;
        let discount = toolpak_number(a.value(2), a.1)?;
        check(discount > 0.0, XlError::Num)?;
        let price = 100.0 * (1.0 - discount * days / 360.0);
        check(price > 0.0, XlError::Num)?;
        finite(price)
    })
}

fn tbillyield(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let days = bill_days(a)?;
        let price = toolpak_number(a.value(2), a.1)?;
        check(price > 0.0, XlError::Num)?;
        finite((100.0 - price) / price * 360.0 / days)
    })
}

fn tbilleq(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar_numbers(ctx, args, &|a| {
        let days = bill_days(a)?;
        let discount = toolpak_number(a.value(2), a.1)?;
        check(discount > 0.0, XlError::Num)?;
        if days <= 182.0 {
            return finite(365.0 * discount / (360.0 - discount * days));
        }
        // Past half a year the bond equivalent compounds once: solve the quadratic.
        let price = 100.0 * (1.0 - discount * days / 360.0);
        check(price > 0.0, XlError::Num)?;
        // A bill of 366 days (over a February 29) counts the year as 366 days.
        let t = days / if days > 365.0 { 366.0 } else { 365.0 };
        finite((-t + (t * t - (2.0 * t - 1.0) * (1.0 - 100.0 / price)).sqrt()) / (t - 0.5))
    })
}

#[cfg(test)]
mod tests {
    use crate::eval::testing::MapEnv;
    use crate::eval::value::{Value, XlError};

    /// VDB has no cell in Excel's corpus: these are LibreOffice Calc 7's values (and
    /// Microsoft's documented examples, 480, 315 and 396.306…, among them).
    #[test]
    fn vdb_as_libreoffice() {
        let env = MapEnv::with(&[]);
        for (formula, want) in [
            ("=VDB(2400,300,10,0,1)", 480.0),
            ("=VDB(2400,300,10,0,0.875,1.5)", 315.0),
            ("=VDB(2400,300,10,6,10,2,TRUE)", 329.1456),
            ("=VDB(2400,300,10,6,10)", 329.1456),
            ("=VDB(2400,300,10*12,6,18)", 396.306053264752),
            ("=VDB(2400,300,10,1.5,3.25)", 560.64),
            ("=VDB(2400,300,10,0,10,3)", 2100.0),
            ("=VDB(1000,0,5,0,5,1,FALSE)", 1000.0),
            ("=VDB(1000,100,5,2.5,4.2,2,TRUE)", 164.32),
        ] {
            match env.eval(formula) {
                Value::Number(got) => {
                    assert!((got - want).abs() <= 1e-9 * want, "{formula}: {got}, LibreOffice {want}")
                }
                other => panic!("{formula}: {other:?}"),
            }
        }
        // The last: too many periods to sum, refused at once rather than computed for minutes.
        for formula in ["=VDB(2400,300,10,11,12)", "=VDB(2400,300,10,2,1)", "=VDB(-1,0,5,0,1)", "=VDB(1,0,1E12,0,1E12)"]
        {
            assert_eq!(env.eval(formula), Value::Error(XlError::Num), "{formula}");
        }
    }

    /// Depreciation at lives past a double's resolution (issue 30). DDB's closed form is
    /// cost × (1 − f/life)^(period−1) × f/life; at life = period = 1E16, f = 2 that is
    /// 1000 × e^−2 × 2E−16 (the power is e^((1E16−1)·ln(1−2E−16)) = e^−2 to 1E−16). The two
    /// worths subtracted agreed to the last digit and gave 0. SYD at life 1E200 is
    /// 2·cost/life = 2E−197, where life × (life + 1) overflowed and gave 0. Microsoft's
    /// examples for DDB (2400, 300, 10 years) keep their values.
    #[test]
    fn depreciation_at_huge_lives() {
        let env = MapEnv::with(&[]);
        for (formula, want) in [
            ("=DDB(1000,1,1E16,1E16)", 1000.0 * (-2f64).exp() * 2e-16),
            ("=SYD(1000,0,1E200,1)", 2e-197),
            ("=DDB(2400,300,3650,1)", 1.315068493150685),
            ("=DDB(2400,300,120,1)", 40.0),
            ("=DDB(2400,300,10,1,2)", 480.0),
            ("=DDB(2400,300,10,2,1.5)", 306.0),
            ("=DDB(2400,300,10,10)", 22.1225472),
        ] {
            match env.eval(formula) {
                Value::Number(got) => assert!((got - want).abs() <= 1e-9 * want, "{formula}: {got}, want {want}"),
                other => panic!("{formula}: {other:?}"),
            }
        }
    }
}
