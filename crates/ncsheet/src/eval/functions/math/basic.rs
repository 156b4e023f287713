//! Math and trigonometry. Angles in radians, as in Excel.

use std::rc::Rc;

use crate::eval::coerce::to_number;
use crate::eval::dates::DateSystem;
use crate::eval::format::number_format::round15;
use crate::eval::functions::api::{
    block, for_each_number, given, lift, lift_number1, lift_number2, number_or, number_result, power, sheet_sized,
    ArgSet, Ctx, FnSpec, MANY,
};
use crate::eval::value::{Array, Value, XlError, XlResult};
use crate::formula::ast::{Expr, ExprKind};

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value("ABS", 1, 1, abs, "ABS(number)", "Absolute value").biff(24),
    FnSpec::value("ACOS", 1, 1, acos, "ACOS(number)", "Arccosine in radians, 0 to pi; #NUM! outside -1..1").biff(99),
    FnSpec::value("ACOSH", 1, 1, acosh, "ACOSH(number)", "Inverse hyperbolic cosine; #NUM! below 1").biff(233),
    FnSpec::value("ACOT", 1, 1, acot, "ACOT(number)", "Arccotangent in radians, 0 to pi").future(),
    FnSpec::value("ACOTH", 1, 1, acoth, "ACOTH(number)", "Inverse hyperbolic cotangent; #NUM! for -1..1").future(),
    FnSpec::value("ASIN", 1, 1, asin, "ASIN(number)", "Arcsine in radians, -pi/2 to pi/2; #NUM! outside -1..1")
        .biff(98),
    FnSpec::value("ASINH", 1, 1, asinh, "ASINH(number)", "Inverse hyperbolic sine").biff(232),
    FnSpec::value("ATAN", 1, 1, atan, "ATAN(number)", "Arctangent in radians, -pi/2 to pi/2").biff(18),
    FnSpec::value(
        "ATAN2",
        2,
        2,
        atan2,
        "ATAN2(x, y)",
        "Angle of the point (x, y) in radians, -pi to pi; x before y as in Excel",
    )
    .biff(97),
    FnSpec::value("ATANH", 1, 1, atanh, "ATANH(number)", "Inverse hyperbolic tangent; #NUM! outside -1..1 (exclusive)")
        .biff(234),
    FnSpec::value(
        "CEILING",
        2,
        2,
        ceiling,
        "CEILING(number, significance)",
        "Rounds up to a multiple of significance (negative numbers toward zero)",
    )
    .biff(288),
    FnSpec::value(
        "CEILING.MATH",
        1,
        3,
        ceiling_math,
        "CEILING.MATH(number, [significance], [mode])",
        "Rounds up to a multiple of |significance|; mode<>0 rounds negatives away from zero",
    )
    .future(),
    FnSpec::value(
        "CEILING.PRECISE",
        1,
        2,
        ceiling_precise,
        "CEILING.PRECISE(number, [significance])",
        "Rounds up (toward +infinity) to a multiple of |significance|",
    )
    .future(),
    FnSpec::value("COS", 1, 1, cos, "COS(angle)", "Cosine of an angle in radians").biff(16),
    FnSpec::value("COSH", 1, 1, cosh, "COSH(number)", "Hyperbolic cosine").biff(230),
    FnSpec::value("COT", 1, 1, cot, "COT(angle)", "Cotangent of an angle in radians").future(),
    FnSpec::value("COTH", 1, 1, coth, "COTH(number)", "Hyperbolic cotangent").future(),
    FnSpec::value("CSC", 1, 1, csc, "CSC(angle)", "Cosecant of an angle in radians").future(),
    FnSpec::value("CSCH", 1, 1, csch, "CSCH(number)", "Hyperbolic cosecant").future(),
    FnSpec::value("DEGREES", 1, 1, degrees, "DEGREES(angle)", "Radians to degrees").biff(343),
    FnSpec::value("EXP", 1, 1, exp, "EXP(number)", "e raised to number").biff(21),
    FnSpec::value("EVEN", 1, 1, even, "EVEN(number)", "Rounds away from zero to an even integer").biff(279),
    FnSpec::value("FACT", 1, 1, fact, "FACT(number)", "Factorial of the integer part; #NUM! below 0 or above 170")
        .biff(184),
    FnSpec::value(
        "FLOOR",
        2,
        2,
        floor,
        "FLOOR(number, significance)",
        "Rounds down to a multiple of significance (negative numbers away from zero)",
    )
    .biff(285),
    FnSpec::value(
        "FLOOR.MATH",
        1,
        3,
        floor_math,
        "FLOOR.MATH(number, [significance], [mode])",
        "Rounds down to a multiple of |significance|; mode<>0 rounds negatives toward zero",
    )
    .future(),
    FnSpec::value(
        "FLOOR.PRECISE",
        1,
        2,
        floor_precise,
        "FLOOR.PRECISE(number, [significance])",
        "Rounds down (toward -infinity) to a multiple of |significance|",
    )
    .future(),
    FnSpec::value("INT", 1, 1, int, "INT(number)", "Rounds down to an integer (INT(-2.5) = -3)").biff(25),
    FnSpec::value(
        "ISO.CEILING",
        1,
        2,
        ceiling_precise,
        "ISO.CEILING(number, [significance])",
        "Same as CEILING.PRECISE",
    ),
    FnSpec::value("LN", 1, 1, ln, "LN(number)", "Natural logarithm; #NUM! for 0 and below").biff(22),
    FnSpec::value("LOG", 1, 2, log, "LOG(number, [base])", "Logarithm to base (10 when omitted)").biff(109),
    FnSpec::value("LOG10", 1, 1, log10, "LOG10(number)", "Base-10 logarithm").biff(23),
    FnSpec::value(
        "MOD",
        2,
        2,
        modulo,
        "MOD(number, divisor)",
        "Remainder with the sign of the divisor; #DIV/0! for divisor 0",
    )
    .biff(39),
    FnSpec::value(
        "MROUND",
        2,
        2,
        mround,
        "MROUND(number, multiple)",
        "Rounds half away from zero to a multiple; #NUM! when the signs differ",
    ),
    FnSpec::value("PI", 0, 0, pi, "PI()", "3.14159265358979").biff(19),
    FnSpec::value("ODD", 1, 1, odd, "ODD(number)", "Rounds away from zero to an odd integer").biff(298),
    FnSpec::value("POWER", 2, 2, power_fn, "POWER(number, power)", "number^power").biff(337),
    FnSpec::value(
        "PRODUCT",
        1,
        MANY,
        product,
        "PRODUCT(number1, [number2], ...)",
        "Multiplies numbers; text and booleans in ranges are skipped",
    )
    .biff(183)
    .range_args(ArgSet::ALL),
    FnSpec::value("QUOTIENT", 2, 2, quotient, "QUOTIENT(numerator, denominator)", "Integer part of a division"),
    FnSpec::value("RADIANS", 1, 1, radians, "RADIANS(angle)", "Degrees to radians").biff(342),
    FnSpec::value("ROUND", 2, 2, round, "ROUND(number, digits)", "Rounds half away from zero to digits decimals")
        .biff(27),
    FnSpec::value("ROUNDDOWN", 2, 2, rounddown, "ROUNDDOWN(number, digits)", "Rounds toward zero to digits decimals")
        .biff(213),
    FnSpec::value("ROUNDUP", 2, 2, roundup, "ROUNDUP(number, digits)", "Rounds away from zero to digits decimals")
        .biff(212),
    FnSpec::value("SEC", 1, 1, sec, "SEC(angle)", "Secant of an angle in radians").future(),
    FnSpec::value("SECH", 1, 1, sech, "SECH(number)", "Hyperbolic secant").future(),
    FnSpec::value(
        "SEQUENCE",
        1,
        4,
        sequence,
        "SEQUENCE(rows, [columns], [start], [step])",
        "Array of rows x columns numbers counting from start by step",
    )
    .future()
    .dynamic(),
    FnSpec::value("SIGN", 1, 1, sign, "SIGN(number)", "1, 0 or -1 by the sign of number").biff(26),
    FnSpec::value("SIN", 1, 1, sin, "SIN(angle)", "Sine of an angle in radians").biff(15),
    FnSpec::value("SINH", 1, 1, sinh, "SINH(number)", "Hyperbolic sine").biff(229),
    FnSpec::value("SQRT", 1, 1, sqrt, "SQRT(number)", "Square root; #NUM! for negative numbers").biff(20),
    FnSpec::value("SQRTPI", 1, 1, sqrtpi, "SQRTPI(number)", "Square root of number*pi; #NUM! for negative numbers"),
    FnSpec::value(
        "SUM",
        1,
        MANY,
        sum,
        "SUM(number1, [number2], ...)",
        "Adds numbers; text and booleans in ranges are skipped",
    )
    .biff(4)
    .range_args(ArgSet::ALL),
    FnSpec::value(
        "SUMPRODUCT",
        1,
        MANY,
        sumproduct,
        "SUMPRODUCT(array1, [array2], ...)",
        "Sum of the item-by-item products of same-sized arrays; non-numbers count as 0",
    )
    .biff(228)
    .array_args(ArgSet::ALL),
    FnSpec::value(
        "SUMSQ",
        1,
        MANY,
        sumsq,
        "SUMSQ(number1, [number2], ...)",
        "Sum of squares; text and booleans in ranges are skipped",
    )
    .biff(321)
    .range_args(ArgSet::ALL),
    FnSpec::value("TAN", 1, 1, tan, "TAN(angle)", "Tangent of an angle in radians").biff(17),
    FnSpec::value("TANH", 1, 1, tanh, "TANH(number)", "Hyperbolic tangent").biff(231),
    FnSpec::value("TRUNC", 1, 2, trunc, "TRUNC(number, [digits])", "Cuts off decimals beyond digits (0 when omitted)")
        .biff(197),
];

// ---- trigonometry -------------------------------------------------------------------------

/// Excel refuses sine, cosine and tangent of angles of 2^27 and beyond (#NUM!): so few
/// periods are left in a double there that the result would be noise.
fn trig_angle(x: f64) -> XlResult<f64> {
    if x.abs() >= 134_217_728.0 {
        Err(XlError::Num)
    } else {
        Ok(x)
    }
}

/// The arcsine and arccosine domain.
fn unit_interval(x: f64) -> XlResult<f64> {
    if (-1.0..=1.0).contains(&x) {
        Ok(x)
    } else {
        Err(XlError::Num)
    }
}

pub(crate) fn sin(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(trig_angle(x)?.sin()))
}

pub(crate) fn cos(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(trig_angle(x)?.cos()))
}

pub(crate) fn tan(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(trig_angle(x)?.tan()))
}

fn asin(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(unit_interval(x)?.asin()))
}

fn acos(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(unit_interval(x)?.acos()))
}

pub(crate) fn atan(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(x.atan()))
}

fn atan2(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number2(ctx, args, 0.0, |x, y| if x == 0.0 && y == 0.0 { Err(XlError::Div0) } else { Ok(y.atan2(x)) })
}

fn sinh(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(x.sinh()))
}

fn cosh(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(x.cosh()))
}

fn tanh(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(x.tanh()))
}

/// `1 / x` for the reciprocal functions: #DIV/0! where x is 0 (COT(0), CSCH(0)).
fn reciprocal(x: f64) -> XlResult<f64> {
    if x == 0.0 {
        Err(XlError::Div0)
    } else {
        Ok(1.0 / x)
    }
}

fn cot(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| reciprocal(trig_angle(x)?.tan()))
}

fn csc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| reciprocal(trig_angle(x)?.sin()))
}

fn sec(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| reciprocal(trig_angle(x)?.cos()))
}

fn acot(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(std::f64::consts::FRAC_PI_2 - x.atan()))
}

fn coth(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| reciprocal(x.tanh()))
}

fn csch(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| reciprocal(x.sinh()))
}

fn sech(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| reciprocal(x.cosh()))
}

fn asinh(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(x.asinh()))
}

fn acosh(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| if x < 1.0 { Err(XlError::Num) } else { Ok(x.acosh()) })
}

fn atanh(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| if x.abs() >= 1.0 { Err(XlError::Num) } else { Ok(x.atanh()) })
}

fn acoth(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| if x.abs() <= 1.0 { Err(XlError::Num) } else { Ok(0.5 * ((x + 1.0) / (x - 1.0)).ln()) })
}

fn degrees(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(x.to_degrees()))
}

fn radians(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(x.to_radians()))
}

fn pi(_: &mut Ctx, _: &[Expr]) -> XlResult<Value> {
    Ok(Value::Number(std::f64::consts::PI))
}

// ---- powers and logarithms ----------------------------------------------------------------

pub(crate) fn sqrt(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| if x < 0.0 { Err(XlError::Num) } else { Ok(x.sqrt()) })
}

fn sqrtpi(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| if x < 0.0 { Err(XlError::Num) } else { Ok((x * std::f64::consts::PI).sqrt()) })
}

fn power_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number2(ctx, args, 0.0, power)
}

pub(crate) fn exp(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(x.exp()))
}

/// Logarithms exist for positive numbers only.
fn positive(x: f64) -> XlResult<f64> {
    if x > 0.0 {
        Ok(x)
    } else {
        Err(XlError::Num)
    }
}

pub(crate) fn ln(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(positive(x)?.ln()))
}

fn log10(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(positive(x)?.log10()))
}

fn log(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number2(ctx, args, 10.0, |x, base| {
        let (x, base) = (positive(x)?, positive(base)?);
        if base == 1.0 {
            Err(XlError::Div0)
        } else if base == 10.0 {
            // log10 is exact on powers of ten, where ln(x)/ln(10) is not (LOG(1000) = 3).
            Ok(x.log10())
        } else {
            Ok(x.ln() / base.ln())
        }
    })
}

fn fact(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| {
        if x < 0.0 {
            return Err(XlError::Num);
        }
        // 170! is the largest factorial a double holds; beyond it the loop yields infinity,
        // which the lift reports as #NUM!.
        let n = x.trunc().min(171.0) as u32;
        Ok((2..=n).fold(1.0, |acc, k| acc * f64::from(k)))
    })
}

// ---- signs, integers and division ----------------------------------------------------------

pub(crate) fn abs(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(x.abs()))
}

pub(crate) fn sign(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| {
        Ok(if x > 0.0 {
            1.0
        } else if x < 0.0 {
            -1.0
        } else {
            0.0
        })
    })
}

fn even(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(((x.abs() / 2.0).ceil() * 2.0).copysign(x)))
}

fn odd(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| {
        let up = x.abs().ceil();
        let odd = if up % 2.0 == 0.0 { up + 1.0 } else { up };
        // ODD(0) is 1: zero rounds "away from zero" to the positive side.
        Ok(if x < 0.0 { -odd } else { odd })
    })
}

pub(crate) fn int(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(x.floor()))
}

fn modulo(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number2(ctx, args, 0.0, |n, d| {
        if d == 0.0 {
            return Err(XlError::Div0);
        }
        // n - d*INT(n/d), the remainder taking the divisor's sign (MOD(-3, 2) = 1). The
        // remainder of the division of two doubles is exact (IEEE fmod), where n - d*INT(n/d)
        // in doubles loses it for large n (MOD(1E+20, 7) = 2, not 0).
        let mut r = n % d;
        if r != 0.0 && (r < 0.0) != (d < 0.0) {
            r += d;
        }
        // A tiny remainder of the other sign rounds up to d; that remainder is 0.
        Ok(if r.abs() >= d.abs() { 0.0 } else { r })
    })
}

fn quotient(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_toolpak2(ctx, args, |n, d| if d == 0.0 { Err(XlError::Div0) } else { Ok((n / d).trunc()) })
}

/// A number argument of a function from Excel's old Analysis ToolPak (QUOTIENT, MROUND):
/// these refuse booleans (`QUOTIENT(TRUE, 1)` is #VALUE!) where built-ins read TRUE as 1.
pub(crate) fn toolpak_number(v: &Value, dates: DateSystem) -> XlResult<f64> {
    match v {
        Value::Bool(_) => Err(XlError::Value),
        v => to_number(v, dates),
    }
}

/// [`lift_number2`] for Analysis ToolPak functions.
fn lift_toolpak2(ctx: &mut Ctx, args: &[Expr], f: fn(f64, f64) -> XlResult<f64>) -> XlResult<Value> {
    let dates = ctx.dates();
    lift(ctx, args, &|v| {
        let (x, y) = (toolpak_number(&v[0], dates)?, toolpak_number(&v[1], dates)?);
        Ok(number_result(f(x, y)?))
    })
}

// ---- rounding -----------------------------------------------------------------------------

/// How the digits beyond the kept ones are dropped. Applied to the magnitude, so "up"
/// is away from zero and "down" toward zero, as Excel's ROUNDUP and ROUNDDOWN name them.
#[derive(Clone, Copy)]
enum Rounding {
    /// ROUND: halves go up (away from zero).
    HalfUp,
    Up,
    Down,
}

impl Rounding {
    fn apply(self, magnitude: f64) -> f64 {
        match self {
            Rounding::HalfUp => (magnitude + 0.5).floor(),
            Rounding::Up => magnitude.ceil(),
            Rounding::Down => magnitude.trunc(),
        }
    }
}

/// Rounds `x` to `digits` decimals (negative: to tens, hundreds, …), judged on the
/// 15-significant-digit values Excel shows, so that `ROUND(2.675, 2)` is 2.68 although
/// 2.675 is stored as 2.67499999….
fn round_to(x: f64, digits: f64, mode: Rounding) -> f64 {
    if !x.is_finite() || x == 0.0 {
        return x;
    }
    let digits = digits.trunc().clamp(-400.0, 400.0) as i32;
    let exact_scale = digits.unsigned_abs() as usize <= MAX_EXACT_POWER_OF_TEN;
    let scale = power_of_ten(digits.abs());
    let x15 = round15(x);
    let scaled = if digits >= 0 { x15 * scale } else { x15 / scale };
    if !scaled.is_finite() || scaled.abs() >= 1e15 {
        // Every significant digit is kept: nothing to round.
        return x;
    }
    let rounded = mode.apply(round15(scaled).abs());
    if rounded == 0.0 {
        return 0.0;
    }
    let rounded = rounded.copysign(x);
    let unscaled = if digits >= 0 { rounded / scale } else { rounded * scale };
    if exact_scale {
        // An integer below 10^15 and an exact power of ten: the one rounding of the quotient
        // or product is already the double nearest the decimal result.
        return unscaled;
    }
    // Past 10^22 the scale itself is rounded, and the quotient or product is off in its last
    // bits (ROUNDDOWN(1E+308,-300) was 9.99999990000001E+307): the result has at most 15
    // significant digits, so it is read back on them.
    crate::eval::format::number_format::round15(unscaled)
}

/// The largest k for which 10^k is a double exactly (2^53 > 5^22).
const MAX_EXACT_POWER_OF_TEN: usize = 22;

/// 10^k as the nearest double (`powi` multiplies, gathering an error of a few ulps by 10^300).
fn power_of_ten(k: i32) -> f64 {
    const EXACT: [f64; MAX_EXACT_POWER_OF_TEN + 1] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19,
        1e20, 1e21, 1e22,
    ];
    match EXACT.get(k.unsigned_abs() as usize) {
        Some(&p) if k >= 0 => p,
        // Text is the nearest double for the rest; ROUND's digits reach it only past 22.
        _ => format!("1e{k}").parse().unwrap_or(f64::INFINITY),
    }
}

/// Excel's ROUND: half away from zero, on the 15-significant-digit value.
pub fn round_half_away(x: f64, digits: i32) -> f64 {
    round_to(x, f64::from(digits), Rounding::HalfUp)
}

fn round(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    // `as` truncates the digits toward zero, as Excel does (ROUND(x, 1.9) keeps 1 digit).
    lift_number2(ctx, args, 0.0, |x, d| Ok(round_half_away(x, d as i32)))
}

fn roundup(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number2(ctx, args, 0.0, |x, d| Ok(round_to(x, d, Rounding::Up)))
}

fn rounddown(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number2(ctx, args, 0.0, |x, d| Ok(round_to(x, d, Rounding::Down)))
}

fn trunc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number2(ctx, args, 0.0, |x, d| Ok(round_to(x, d, Rounding::Down)))
}

/// `x / step` as Excel sees it before rounding to a multiple: on 15 significant digits, so
/// that `FLOOR(0.3, 0.1)` is 0.3 although 0.3/0.1 is 2.9999999999999996.
fn multiples(x: f64, step: f64) -> f64 {
    round15(x / step)
}

fn ceiling(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number2(ctx, args, 1.0, |x, s| {
        if s == 0.0 {
            return Ok(0.0);
        }
        // A negative significance only rounds negative numbers (away from zero).
        if x > 0.0 && s < 0.0 {
            return Err(XlError::Num);
        }
        Ok(multiples(x, s).ceil() * s)
    })
}

fn floor(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number2(ctx, args, 1.0, |x, s| {
        if x == 0.0 {
            return Ok(0.0);
        }
        if s == 0.0 {
            return Err(XlError::Div0);
        }
        if x > 0.0 && s < 0.0 {
            return Err(XlError::Num);
        }
        Ok(multiples(x, s).floor() * s)
    })
}

/// CEILING.MATH and FLOOR.MATH: the sign of significance is ignored (omitted: 1) and a
/// non-zero mode flips the direction for negative numbers.
fn math_rounding(ctx: &mut Ctx, args: &[Expr], up: bool) -> XlResult<Value> {
    let dates = ctx.dates();
    // Only an omitted significance is 1; an empty cell reads as 0 like any other number.
    let default_significance = given(args, 1).is_none();
    lift(ctx, args, &|v| {
        let x = to_number(&v[0], dates)?;
        let s = if default_significance { 1.0 } else { to_number(&v[1], dates)?.abs() };
        let mode = v.get(2).map_or(Ok(0.0), |m| to_number(m, dates))?;
        if s == 0.0 {
            return Ok(Value::Number(0.0));
        }
        let q = multiples(x, s);
        let toward_positive = up != (x < 0.0 && mode != 0.0);
        let q = if toward_positive { q.ceil() } else { q.floor() };
        Ok(number_result(q * s))
    })
}

/// CEILING.PRECISE and ISO.CEILING: CEILING.MATH without its mode argument.
fn ceiling_precise(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    math_rounding(ctx, args, true)
}

fn floor_precise(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    math_rounding(ctx, args, false)
}

fn ceiling_math(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    math_rounding(ctx, args, true)
}

fn floor_math(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    math_rounding(ctx, args, false)
}

fn mround(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    // Excel: MROUND(, 5) and MROUND(5, ) are #N/A, not a rounding of 0.
    if args.iter().any(|a| a.kind == ExprKind::Missing) {
        return Err(XlError::NA);
    }
    lift_toolpak2(ctx, args, |x, m| {
        if m == 0.0 {
            return Ok(0.0);
        }
        if x * m < 0.0 {
            return Err(XlError::Num);
        }
        if x == 0.0 {
            return Ok(0.0);
        }
        let q = mround_quotient(x / m);
        if q >= 2f64.powi(52) {
            // Every digit is a whole multiple already (and q + 0.5 would round to even).
            return Ok(x);
        }
        Ok((q + 0.5).floor() * m)
    })
}

/// MROUND's quotient rounded as Excel rounds it, to 14 decimal places, before its halves go
/// up. Excel's own results fit this and neither binary nor 15-digit rounding
/// (bettersolutions.com's MROUND page: MROUND(2.05,0.1) is 2.1 and MROUND(7.05,0.1) 7.1,
/// but MROUND(4.05,0.1) is 4.0 and MROUND(32.05,0.1) 32.0): the quotient
/// 20.4999999999999964 counts as a half, 40.4999999999999929 does not.
fn mround_quotient(q: f64) -> f64 {
    format!("{q:.14}").parse().unwrap_or(q)
}

// ---- aggregates ---------------------------------------------------------------------------

fn sum(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let mut total = 0.0;
    for_each_number(ctx, args, &mut |n| total += n)?;
    Ok(number_result(total))
}

fn sumsq(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let mut total = 0.0;
    for_each_number(ctx, args, &mut |n| total += n * n)?;
    Ok(number_result(total))
}

fn product(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let mut total: Option<f64> = None;
    for_each_number(ctx, args, &mut |n| total = Some(total.unwrap_or(1.0) * n))?;
    // No numbers at all is 0 in Excel, not the empty product 1.
    Ok(number_result(total.unwrap_or(0.0)))
}

/// SUMPRODUCT over the arrays' whole sizes: a whole row or column (`1:1+1`, a spill of one)
/// is its stored items and a tail of one value, and every item counts. The items beyond
/// those any array stores are the same term, counted once and multiplied by how often it
/// repeats, so the work follows the used area.
fn sumproduct(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let blocks = args.iter().map(|a| block(ctx, a)).collect::<XlResult<Vec<_>>>()?;
    let (rows, cols) = blocks[0].whole_size();
    if blocks.iter().any(|b| b.whole_size() != (rows, cols)) {
        return Err(XlError::Value);
    }
    let stored = blocks.iter().fold((0, 0), |(r, c), b| (r.max(b.rows), c.max(b.cols)));
    // Its products, for arrays bound outside MAP's LAMBDA and read at every call.
    ctx.charge(stored.0 * stored.1 * blocks.len());
    let mut total = 0.0;
    for r in 0..stored.0 {
        for c in 0..stored.1 {
            total += sumproduct_term(blocks.iter().map(|b| b.whole_get(r, c).expect("within the whole size")))?;
        }
    }
    let repeats = rows * cols - stored.0 * stored.1;
    if repeats > 0 {
        // Every array is shorter than the whole size here: each has a tail.
        let fills = blocks.iter().map(|b| &b.tail.as_ref().expect("a tail beyond the stored items").fill);
        total += sumproduct_term(fills)? * repeats as f64;
    }
    Ok(number_result(total))
}

/// One product of SUMPRODUCT: text, booleans and blanks are zeros; an error is the result.
fn sumproduct_term<'v>(items: impl Iterator<Item = &'v Value>) -> XlResult<f64> {
    let mut term = 1.0;
    for v in items {
        match v {
            Value::Number(n) => term *= n,
            Value::Error(e) => return Err(*e),
            _ => term = 0.0,
        }
    }
    Ok(term)
}

// ---- arrays -------------------------------------------------------------------------------

fn sequence(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let rows = number_or(ctx, args, 0, 1.0)?.trunc();
    let cols = number_or(ctx, args, 1, 1.0)?.trunc();
    let start = number_or(ctx, args, 2, 1.0)?;
    let step = number_or(ctx, args, 3, 1.0)?;
    if rows < 0.0 || cols < 0.0 {
        return Err(XlError::Value);
    }
    let (rows, cols) = sheet_sized(ctx, "SEQUENCE", rows, cols)?;
    // No row or no column (`SEQUENCE(0.3)`) is an empty array: #CALC!, as Excel 365 stores it.
    if rows == 0 || cols == 0 {
        return Err(XlError::Calc);
    }
    let data = (0..rows * cols).map(|i| number_result(start + step * i as f64)).collect();
    Ok(Value::Array(Rc::new(Array::new(rows, cols, data))))
}

#[cfg(test)]
mod tests {
    use crate::eval::testing::MapEnv;
    use crate::eval::testing::{err, n};
    use crate::eval::value::{Value, XlError};

    /// Evaluates each formula against no cells and checks the result.
    fn check(cases: &[(&str, Value)]) {
        let env = MapEnv::default();
        for (formula, expected) in cases {
            let got = env.eval(formula);
            match (&got, expected) {
                (Value::Number(a), Value::Number(b)) => {
                    assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{formula}: {a} vs {b}")
                }
                _ => assert_eq!(&got, expected, "{formula}"),
            }
        }
    }

    #[test]
    fn trigonometry_follows_excel() {
        check(&[
            ("=SIN(PI()/2)", n(1.0)),
            ("=COS(0)", n(1.0)),
            ("=TAN(PI()/4)", n(1.0)),
            ("=ASIN(1)", n(std::f64::consts::FRAC_PI_2)),
            ("=ACOS(2)", err(XlError::Num)),
            ("=ASIN(-1.5)", err(XlError::Num)),
            ("=ATAN2(1,1)", n(std::f64::consts::FRAC_PI_4)),
            ("=ATAN2(-1,0)", n(std::f64::consts::PI)),
            ("=ATAN2(0,0)", err(XlError::Div0)),
            ("=DEGREES(PI())", n(180.0)),
            ("=RADIANS(270)", n(4.71238898038469)),
            ("=SINH(0)", n(0.0)),
            ("=COSH(0)", n(1.0)),
            ("=TANH(0.5)", n(0.46211715726001)),
            ("=SIN(2^27)", err(XlError::Num)),
            ("=COT(0)", err(XlError::Div0)),
            ("=CSC(PI()/2)", n(1.0)),
            ("=SEC(0)", n(1.0)),
            ("=ACOT(0)", n(std::f64::consts::FRAC_PI_2)),
            ("=ACOSH(1)", n(0.0)),
            ("=ACOSH(0.5)", err(XlError::Num)),
            ("=ATANH(1)", err(XlError::Num)),
            ("=ASINH(0)", n(0.0)),
            ("=ACOTH(1)", err(XlError::Num)),
            ("=COTH(0)", err(XlError::Div0)),
            ("=SECH(0)", n(1.0)),
        ]);
    }

    #[test]
    fn powers_and_logarithms_follow_excel() {
        check(&[
            ("=SQRT(16)", n(4.0)),
            ("=SQRT(-1)", err(XlError::Num)),
            ("=SQRTPI(2)", n(2.5066282746310002)),
            ("=POWER(2,10)", n(1024.0)),
            ("=POWER(-8,1/3)", err(XlError::Num)),
            ("=POWER(0,-1)", err(XlError::Div0)),
            ("=EXP(1)", n(std::f64::consts::E)),
            ("=EXP(1000)", err(XlError::Num)),
            ("=LN(0)", err(XlError::Num)),
            ("=LN(EXP(2))", n(2.0)),
            ("=LOG(1000)", n(3.0)),
            ("=LOG(8,2)", n(3.0)),
            ("=LOG(0)", err(XlError::Num)),
            ("=LOG(10,1)", err(XlError::Div0)),
            ("=LOG10(0.001)", n(-3.0)),
            ("=FACT(5)", n(120.0)),
            ("=FACT(5.9)", n(120.0)),
            ("=FACT(0)", n(1.0)),
            ("=FACT(-1)", err(XlError::Num)),
            ("=FACT(171)", err(XlError::Num)),
        ]);
    }

    #[test]
    fn rounding_follows_excel() {
        check(&[
            ("=ROUND(2.5,0)", n(3.0)),
            ("=ROUND(-2.5,0)", n(-3.0)),
            ("=ROUND(2.675,2)", n(2.68)),
            ("=ROUND(1234.5678,-2)", n(1200.0)),
            ("=ROUNDUP(3.2,0)", n(4.0)),
            ("=ROUNDUP(-3.14159,1)", n(-3.2)),
            ("=ROUNDUP(31415.92654,-2)", n(31500.0)),
            ("=ROUNDDOWN(3.9,0)", n(3.0)),
            ("=ROUNDDOWN(-3.14159,1)", n(-3.1)),
            ("=TRUNC(8.9)", n(8.0)),
            ("=TRUNC(-8.9)", n(-8.0)),
            ("=TRUNC(2.71828,2)", n(2.71)),
            ("=INT(8.9)", n(8.0)),
            ("=INT(-8.9)", n(-9.0)),
            ("=CEILING(2.5,1)", n(3.0)),
            ("=CEILING(-2.5,2)", n(-2.0)),
            ("=CEILING(-2.5,-2)", n(-4.0)),
            ("=CEILING(2.5,-2)", err(XlError::Num)),
            ("=CEILING(1.5,0.1)", n(1.5)),
            ("=FLOOR(3.7,2)", n(2.0)),
            ("=FLOOR(-2.5,-2)", n(-2.0)),
            ("=FLOOR(-2.5,2)", n(-4.0)),
            ("=FLOOR(2.5,-2)", err(XlError::Num)),
            ("=FLOOR(0.3,0.1)", n(0.3)),
            ("=CEILING.MATH(24.3,5)", n(25.0)),
            ("=CEILING.MATH(6.7)", n(7.0)),
            ("=CEILING.MATH(-8.1,2)", n(-8.0)),
            ("=CEILING.MATH(-5.5,2,-1)", n(-6.0)),
            ("=FLOOR.MATH(24.3,5)", n(20.0)),
            ("=FLOOR.MATH(6.7)", n(6.0)),
            ("=FLOOR.MATH(-8.1,2)", n(-10.0)),
            ("=FLOOR.MATH(-5.5,2,-1)", n(-4.0)),
            ("=MROUND(10,3)", n(9.0)),
            ("=MROUND(-10,-3)", n(-9.0)),
            ("=MROUND(1.3,0.2)", n(1.4)),
            // Excel's results as bettersolutions.com's MROUND page lists them.
            ("=MROUND(1.05,0.1)", n(1.1)),
            ("=MROUND(2.05,0.1)", n(2.1)),
            ("=MROUND(3.05,0.1)", n(3.1)),
            ("=MROUND(4.05,0.1)", n(4.0)),
            ("=MROUND(5.05,0.1)", n(5.0)),
            ("=MROUND(6.05,0.1)", n(6.0)),
            ("=MROUND(7.05,0.1)", n(7.1)),
            ("=MROUND(8.05,0.1)", n(8.1)),
            ("=MROUND(31.05,0.1)", n(31.1)),
            ("=MROUND(32.05,0.1)", n(32.0)),
            ("=MROUND(1.05,0.2)", n(1.0)),
            ("=MROUND(0,-3)", n(0.0)),
            ("=MROUND(5,-2)", err(XlError::Num)),
            ("=MROUND(,5)", err(XlError::NA)),
            ("=QUOTIENT(TRUE,1)", err(XlError::Value)),
            ("=CEILING.PRECISE(4.3)", n(5.0)),
            ("=CEILING.PRECISE(-4.3)", n(-4.0)),
            ("=CEILING.PRECISE(4.3,-2)", n(6.0)),
            ("=ISO.CEILING(-4.3,2)", n(-4.0)),
            ("=FLOOR.PRECISE(-3.2,-1)", n(-4.0)),
            ("=FLOOR.PRECISE(3.2,-1)", n(3.0)),
            ("=EVEN(1.5)", n(2.0)),
            ("=EVEN(3)", n(4.0)),
            ("=EVEN(-1)", n(-2.0)),
            ("=ODD(1.5)", n(3.0)),
            ("=ODD(2)", n(3.0)),
            ("=ODD(-2)", n(-3.0)),
        ]);
    }

    #[test]
    fn signs_and_division_follow_excel() {
        check(&[
            ("=ABS(-2)", n(2.0)),
            ("=SIGN(-0.5)", n(-1.0)),
            ("=SIGN(0)", n(0.0)),
            ("=MOD(3,2)", n(1.0)),
            ("=MOD(-3,2)", n(1.0)),
            ("=MOD(3,-2)", n(-1.0)),
            ("=MOD(-3,-2)", n(-1.0)),
            ("=MOD(5,0)", err(XlError::Div0)),
            ("=QUOTIENT(5,2)", n(2.0)),
            ("=QUOTIENT(-10,3)", n(-3.0)),
            ("=QUOTIENT(1,0)", err(XlError::Div0)),
        ]);
    }

    #[test]
    fn aggregates_follow_excel() {
        let env = MapEnv::with(&[
            ("A1", n(1.0)),
            ("A2", Value::text("2")),
            ("A3", Value::Bool(true)),
            ("A4", n(3.0)),
            ("B1", n(4.0)),
            ("B2", n(5.0)),
            ("B3", n(6.0)),
            ("B4", Value::text("x")),
        ]);
        assert_eq!(env.eval("=SUM(1,\"2\",TRUE)"), n(4.0));
        assert_eq!(env.eval("=SUM(\"x\")"), err(XlError::Value));
        assert_eq!(env.eval("=SUM(A1:A4)"), n(4.0));
        assert_eq!(env.eval("=SUMSQ(A1:A4,2)"), n(14.0));
        assert_eq!(env.eval("=PRODUCT(A1:A4,2)"), n(6.0));
        assert_eq!(env.eval("=PRODUCT(C1:C3)"), n(0.0));
        assert_eq!(env.eval("=SUMPRODUCT(A1:A4,B1:B4)"), n(4.0));
        assert_eq!(env.eval("=SUMPRODUCT({1,2,3},{4,5,6})"), n(32.0));
        assert_eq!(env.eval("=SUMPRODUCT(A1:A4,B1:B3)"), err(XlError::Value));
        assert_eq!(env.eval("=SUMPRODUCT({1,2}*{3,4})"), n(11.0));
    }

    #[test]
    fn scalar_functions_lift_over_ranges() {
        let env = MapEnv::with(&[("A1", n(0.0)), ("A2", n(1.0)), ("A3", n(4.0))]);
        let Value::Array(a) = env.eval_at("=SQRT(A1:A3)", "C1").unwrap() else {
            panic!("SQRT of a range is an array");
        };
        assert_eq!((a.rows, a.cols), (3, 1));
        assert_eq!(a.data, vec![n(0.0), n(1.0), n(2.0)]);
        assert_eq!(env.eval("=SUM(ROUND(A1:A3/2,0))"), n(3.0));
    }

    #[test]
    fn sequence_spills_an_array() {
        let env = MapEnv::default();
        let Value::Array(a) = env.eval_at("=SEQUENCE(2,3,10,5)", "A1").unwrap() else {
            panic!("SEQUENCE is an array");
        };
        assert_eq!((a.rows, a.cols), (2, 3));
        assert_eq!(a.data[5], n(35.0));
        assert_eq!(env.eval("=SUM(SEQUENCE(10))"), n(55.0));
        // calc_tests/MATH_AND_TRIGONOMETRY/SEQUENCE.xlsx: nothing is #CALC!, less than nothing #VALUE!.
        assert_eq!(env.eval("=SEQUENCE(0,0)"), Value::Error(XlError::Calc));
        assert_eq!(env.eval("=SEQUENCE(0.3)"), Value::Error(XlError::Calc));
        assert_eq!(env.eval("=SEQUENCE(-1)"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=SUM(SEQUENCE(,3))"), n(6.0));
        assert_eq!(env.eval("=SEQUENCE(0)"), err(XlError::Calc));
    }
}
