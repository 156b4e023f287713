//! Engineering: base conversions (BIN2DEC … HEX2OCT, ten-digit two's complement for
//! negatives, as Excel), bitwise functions on 48-bit whole numbers, DELTA, GESTEP and the
//! error function.

use crate::eval::coerce::to_text;
use crate::eval::functions::api::{check, finite, scalar, Ctx, FnSpec, Scalars};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::Expr;

use crate::eval::functions::text::more::to_radix;

macro_rules! conversion {
    ($name:literal, $f:ident, $from:expr, $to:expr, $sig:literal, $summary:literal) => {
        FnSpec::value($name, 1, 2, $f, $sig, $summary)
    };
}

pub const FUNCTIONS: &[FnSpec] = &[
    conversion!("BIN2DEC", bin2dec, 2, 10, "BIN2DEC(number)", "Binary text (10 digits, two's complement) as a number"),
    conversion!("BIN2HEX", bin2hex, 2, 16, "BIN2HEX(number, [places])", "Binary text as hexadecimal"),
    conversion!("BIN2OCT", bin2oct, 2, 8, "BIN2OCT(number, [places])", "Binary text as octal"),
    conversion!("DEC2BIN", dec2bin, 10, 2, "DEC2BIN(number, [places])", "-512..511 as binary text"),
    conversion!("DEC2HEX", dec2hex, 10, 16, "DEC2HEX(number, [places])", "A whole number as hexadecimal text"),
    conversion!("DEC2OCT", dec2oct, 10, 8, "DEC2OCT(number, [places])", "A whole number as octal text"),
    conversion!("HEX2BIN", hex2bin, 16, 2, "HEX2BIN(number, [places])", "Hexadecimal text as binary"),
    conversion!(
        "HEX2DEC",
        hex2dec,
        16,
        10,
        "HEX2DEC(number)",
        "Hexadecimal text (10 digits, two's complement) as a number"
    ),
    conversion!("HEX2OCT", hex2oct, 16, 8, "HEX2OCT(number, [places])", "Hexadecimal text as octal"),
    conversion!("OCT2BIN", oct2bin, 8, 2, "OCT2BIN(number, [places])", "Octal text as binary"),
    conversion!("OCT2DEC", oct2dec, 8, 10, "OCT2DEC(number)", "Octal text (10 digits, two's complement) as a number"),
    conversion!("OCT2HEX", oct2hex, 8, 16, "OCT2HEX(number, [places])", "Octal text as hexadecimal"),
    FnSpec::value("BITAND", 2, 2, bitand, "BITAND(number1, number2)", "Bitwise AND of whole numbers below 2^48")
        .future(),
    FnSpec::value("BITOR", 2, 2, bitor, "BITOR(number1, number2)", "Bitwise OR of whole numbers below 2^48").future(),
    FnSpec::value("BITXOR", 2, 2, bitxor, "BITXOR(number1, number2)", "Bitwise XOR of whole numbers below 2^48")
        .future(),
    FnSpec::value(
        "BITLSHIFT",
        2,
        2,
        bitlshift,
        "BITLSHIFT(number, shift_amount)",
        "number shifted left (right when negative); #NUM! past 2^48",
    )
    .future(),
    FnSpec::value(
        "BITRSHIFT",
        2,
        2,
        bitrshift,
        "BITRSHIFT(number, shift_amount)",
        "number shifted right (left when negative)",
    )
    .future(),
    FnSpec::value("DELTA", 1, 2, delta, "DELTA(number1, [number2])", "1 when the numbers are equal, else 0"),
    FnSpec::value("GESTEP", 1, 2, gestep, "GESTEP(number, [step])", "1 when number >= step (default 0), else 0"),
    FnSpec::value(
        "ERF",
        1,
        2,
        erf_fn,
        "ERF(lower_limit, [upper_limit])",
        "Error function, or its integral between the limits",
    ),
    FnSpec::value("ERF.PRECISE", 1, 1, erf_precise, "ERF.PRECISE(x)", "Error function").future(),
    FnSpec::value("ERFC", 1, 1, erfc_fn, "ERFC(x)", "Complementary error function 1-ERF(x)"),
    FnSpec::value("ERFC.PRECISE", 1, 1, erfc_fn, "ERFC.PRECISE(x)", "Complementary error function 1-ERF(x)").future(),
];

/// Excel's base conversions work on ten digits; the top digit's top bit is the sign.
const DIGITS: usize = 10;

/// The bits of a ten-digit number in `radix` (2, 8, 16).
fn bits(radix: u32) -> u32 {
    DIGITS as u32 * radix.trailing_zeros()
}

/// A number in `radix` read from text (or from a number typed as its digits).
fn read_radix(v: &Value, radix: u32) -> XlResult<i64> {
    let text = match v {
        Value::Bool(_) => return Err(XlError::Value),
        Value::Number(n) => {
            check(*n >= 0.0 && n.fract() == 0.0, XlError::Num)?;
            format!("{n}").into()
        }
        other => to_text(other)?,
    };
    check(text.chars().count() <= DIGITS, XlError::Num)?;
    let mut n: i64 = 0;
    for c in text.chars() {
        let d = c.to_digit(radix).ok_or(XlError::Num)?;
        n = n * i64::from(radix) + i64::from(d);
    }
    // Ten digits with the sign bit set are negative.
    let width = bits(radix);
    if text.chars().count() == DIGITS && n >> (width - 1) == 1 {
        n -= 1 << width;
    }
    Ok(n)
}

/// `n` as text in `radix`, negative numbers as ten digits of two's complement; `places`
/// pads a positive number with zeros.
fn write_radix(n: i64, radix: u32, places: Option<f64>) -> XlResult<Value> {
    let width = bits(radix);
    let limit = 1i64 << (width - 1);
    check((-limit..limit).contains(&n), XlError::Num)?;
    if n < 0 {
        return Ok(Value::text(to_radix((n + (1 << width)) as u64, u64::from(radix))));
    }
    let text = to_radix(n as u64, u64::from(radix));
    let Some(places) = places else { return Ok(Value::text(text)) };
    let places = places.trunc();
    check(places >= 1.0 && places <= DIGITS as f64 && places as usize >= text.len(), XlError::Num)?;
    Ok(Value::text(format!("{text:0>width$}", width = places as usize)))
}

/// The places argument: 1..10 when given (checked even where a negative number ignores it).
fn places(a: Scalars) -> XlResult<Option<f64>> {
    match a.value(1) {
        _ if !a.given(1) => Ok(None),
        Value::Bool(_) => Err(XlError::Value),
        _ => {
            let places = a.num(1)?.trunc();
            check((1.0..=DIGITS as f64).contains(&places), XlError::Num)?;
            Ok(Some(places))
        }
    }
}

fn convert(ctx: &mut Ctx, args: &[Expr], from: u32, to: u32) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let n = if from == 10 {
            let v = a.value(0);
            check(!matches!(v, Value::Bool(_)), XlError::Value)?;
            let x = a.num(0)?.trunc();
            check(x.abs() < 1e15, XlError::Num)?;
            x as i64
        } else {
            read_radix(a.value(0), from)?
        };
        if to == 10 {
            return Ok(Value::Number(n as f64));
        }
        let places = places(a)?;
        write_radix(n, to, places)
    })
}

macro_rules! conversions {
    ($($f:ident: $from:expr => $to:expr),*) => {
        $(fn $f(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
            convert(ctx, args, $from, $to)
        })*
    };
}

conversions!(bin2dec: 2 => 10, bin2hex: 2 => 16, bin2oct: 2 => 8, dec2bin: 10 => 2, dec2hex: 10 => 16,
    dec2oct: 10 => 8, hex2bin: 16 => 2, hex2dec: 16 => 10, hex2oct: 16 => 8, oct2bin: 8 => 2, oct2dec: 8 => 10,
    oct2hex: 8 => 16);

const BIT_LIMIT: f64 = 281474976710656.0; // 2^48

/// A whole number 0 ≤ n < 2^48, as the bit functions take.
fn bit_operand(a: Scalars, i: usize) -> XlResult<u64> {
    let n = a.num(i)?;
    check((0.0..BIT_LIMIT).contains(&n) && n.fract() == 0.0, XlError::Num)?;
    Ok(n as u64)
}

fn bitwise(ctx: &mut Ctx, args: &[Expr], op: fn(u64, u64) -> u64) -> XlResult<Value> {
    scalar(ctx, args, &|a| Ok(Value::Number(op(bit_operand(a, 0)?, bit_operand(a, 1)?) as f64)))
}

fn bitand(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    bitwise(ctx, args, |a, b| a & b)
}

fn bitor(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    bitwise(ctx, args, |a, b| a | b)
}

fn bitxor(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    bitwise(ctx, args, |a, b| a ^ b)
}

fn shift(ctx: &mut Ctx, args: &[Expr], direction: f64) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let n = bit_operand(a, 0)? as f64;
        let by = a.num(1)?.trunc() * direction;
        check(by.abs() <= 53.0, XlError::Num)?;
        let shifted = if by >= 0.0 { n * 2f64.powi(by as i32) } else { (n / 2f64.powi(-by as i32)).floor() };
        check(shifted < BIT_LIMIT, XlError::Num)?;
        Ok(Value::Number(shifted))
    })
}

fn bitlshift(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    shift(ctx, args, 1.0)
}

fn bitrshift(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    shift(ctx, args, -1.0)
}

/// A number argument as the Analysis ToolPak read it: a boolean is #VALUE!.
fn toolpak(a: Scalars, i: usize, default: f64) -> XlResult<f64> {
    match a.value(i) {
        Value::Bool(_) if a.given(i) => Err(XlError::Value),
        _ => a.num_or(i, default),
    }
}

fn delta(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| Ok(Value::Number(f64::from(toolpak(a, 0, 0.0)? == toolpak(a, 1, 0.0)?))))
}

fn gestep(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| Ok(Value::Number(f64::from(toolpak(a, 0, 0.0)? >= toolpak(a, 1, 0.0)?))))
}

fn erf_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let lower = toolpak(a, 0, 0.0)?;
        if !a.given(1) {
            return finite(erf(lower));
        }
        finite(erf(toolpak(a, 1, 0.0)?) - erf(lower))
    })
}

fn erf_precise(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| finite(erf(toolpak(a, 0, 0.0)?)))
}

fn erfc_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| finite(erfc(toolpak(a, 0, 0.0)?)))
}

const FRAC_2_SQRT_PI: f64 = std::f64::consts::FRAC_2_SQRT_PI;

/// The error function: a series of positive terms below 2.5 (no cancellation), 1-erfc above.
pub fn erf(x: f64) -> f64 {
    if x.is_nan() {
        return x;
    }
    if x.abs() >= 2.5 {
        return x.signum() * (1.0 - erfc(x.abs()));
    }
    // erf x = 2/√π e^{-x²} Σ 2ⁿ x^{2n+1} / (1·3·…·(2n+1))
    let mut term = x;
    let mut sum = x;
    let mut n = 0.0;
    while term.abs() > sum.abs() * 1e-17 {
        n += 1.0;
        term *= 2.0 * x * x / (2.0 * n + 1.0);
        sum += term;
    }
    FRAC_2_SQRT_PI * (-x * x).exp() * sum
}

/// The complementary error function: a continued fraction (Lentz) above 2.5.
pub fn erfc(x: f64) -> f64 {
    if x < 2.5 {
        return if x > -2.5 { 1.0 - erf(x) } else { 2.0 - erfc(-x) };
    }
    // erfc x = e^{-x²}/√π · 1/(x+ (1/2)/(x+ 1/(x+ (3/2)/(x+ …))))
    let tiny = 1e-300;
    let mut f = x;
    let mut c = x;
    let mut d = 0.0;
    for k in 1..500 {
        let a = f64::from(k) / 2.0;
        d = x + a * d;
        d = if d.abs() < tiny { 1.0 / tiny } else { 1.0 / d };
        c = x + a / c;
        if c.abs() < tiny {
            c = tiny;
        }
        let delta = c * d;
        f *= delta;
        if (delta - 1.0).abs() < 1e-16 {
            break;
        }
    }
    (-x * x).exp() / (std::f64::consts::PI.sqrt() * f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erf_matches_abramowitz_and_stegun_table_7_1() {
        // A&S table 7.1: erf(0.5) = 0.5204998778, erf(1) = 0.8427007929, erf(2) = 0.9953222650.
        for (x, want) in [(0.5, 0.5204998778), (1.0, 0.8427007929), (2.0, 0.9953222650)] {
            assert!((erf(x) - want).abs() < 1e-10, "erf({x}) = {}", erf(x));
        }
        // erfc(3) = 2.209049699858544e-5 (A&S 7.1.26's tables, to 10 digits).
        assert!((erfc(3.0) / 2.209049699858544e-5 - 1.0).abs() < 1e-9);
    }
}
