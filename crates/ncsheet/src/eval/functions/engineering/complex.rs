//! Complex numbers as Excel keeps them: text such as "3+4i" or "-2.5j" (COMPLEX, IMREAL,
//! IMSUM, IMSIN …). Arithmetic is nalgebra's `Complex<f64>`; results are written back with
//! 15 significant digits and the suffix the arguments used.

use nalgebra::Complex;

use crate::eval::coerce::{parse_plain_number, to_text};
use crate::eval::format::number_format::general;
use crate::eval::functions::api::{check, scalar, ArgSet, Ctx, FnSpec, Scalars, MANY};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::Expr;

type C = Complex<f64>;

macro_rules! unary {
    ($name:literal, $f:ident, $summary:literal) => {
        FnSpec::value($name, 1, 1, $f, concat!($name, "(inumber)"), $summary)
    };
}

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value(
        "COMPLEX",
        2,
        3,
        complex,
        "COMPLEX(real_num, i_num, [suffix])",
        "The complex number real + i·imaginary as text (suffix \"i\" or \"j\")",
    ),
    FnSpec::value("IMREAL", 1, 1, imreal, "IMREAL(inumber)", "Real part of a complex number"),
    FnSpec::value("IMAGINARY", 1, 1, imaginary, "IMAGINARY(inumber)", "Imaginary part of a complex number"),
    FnSpec::value("IMABS", 1, 1, imabs, "IMABS(inumber)", "Modulus of a complex number"),
    FnSpec::value("IMARGUMENT", 1, 1, imargument, "IMARGUMENT(inumber)", "Angle of a complex number in radians"),
    unary!("IMCONJUGATE", imconjugate, "Complex conjugate"),
    FnSpec::value("IMSUM", 1, MANY, imsum, "IMSUM(inumber1, …)", "Sum of complex numbers").range_args(ArgSet::ALL),
    FnSpec::value("IMSUB", 2, 2, imsub, "IMSUB(inumber1, inumber2)", "Difference of two complex numbers"),
    FnSpec::value("IMPRODUCT", 1, MANY, improduct, "IMPRODUCT(inumber1, …)", "Product of complex numbers")
        .range_args(ArgSet::ALL),
    FnSpec::value("IMDIV", 2, 2, imdiv, "IMDIV(inumber1, inumber2)", "Quotient of two complex numbers"),
    FnSpec::value("IMPOWER", 2, 2, impower, "IMPOWER(inumber, number)", "A complex number to a real power"),
    unary!("IMSQRT", imsqrt, "Principal square root"),
    unary!("IMEXP", imexp, "e to a complex power"),
    unary!("IMLN", imln, "Natural logarithm"),
    unary!("IMLOG10", imlog10, "Base-10 logarithm"),
    unary!("IMLOG2", imlog2, "Base-2 logarithm"),
    unary!("IMSIN", imsin, "Sine"),
    unary!("IMCOS", imcos, "Cosine"),
    unary!("IMTAN", imtan, "Tangent").future(),
    unary!("IMSEC", imsec, "Secant").future(),
    unary!("IMCSC", imcsc, "Cosecant").future(),
    unary!("IMCOT", imcot, "Cotangent").future(),
    unary!("IMSINH", imsinh, "Hyperbolic sine").future(),
    unary!("IMCOSH", imcosh, "Hyperbolic cosine").future(),
    unary!("IMSECH", imsech, "Hyperbolic secant").future(),
    unary!("IMCSCH", imcsch, "Hyperbolic cosecant").future(),
];

/// A complex number and the suffix its text used ('i' when none).
#[derive(Clone, Copy)]
struct Parsed {
    z: C,
    suffix: Option<char>,
}

/// Excel's complex text: `a`, `bi`, `a+bi`, `a-bj`, `i`, `-i`; a number is its real part.
fn parse(v: &Value) -> XlResult<Parsed> {
    match v {
        Value::Number(n) => return Ok(Parsed { z: C::new(*n, 0.0), suffix: None }),
        Value::Bool(_) => return Err(XlError::Value),
        Value::Blank => return Ok(Parsed { z: C::new(0.0, 0.0), suffix: None }),
        _ => {}
    }
    let text = to_text(v)?;
    parse_text(&text).ok_or(XlError::Num)
}

fn parse_text(text: &str) -> Option<Parsed> {
    if text.is_empty() {
        return Some(Parsed { z: C::new(0.0, 0.0), suffix: None });
    }
    if let Some(re) = plain(text) {
        return Some(Parsed { z: C::new(re, 0.0), suffix: None });
    }
    let suffix = text.chars().last().filter(|c| *c == 'i' || *c == 'j')?;
    let body = &text[..text.len() - 1];
    // The imaginary part starts at the last sign that is not an exponent's.
    let bytes = body.as_bytes();
    let split = (1..bytes.len())
        .rev()
        .find(|&k| matches!(bytes[k], b'+' | b'-') && !matches!(bytes[k - 1], b'e' | b'E'))
        .unwrap_or(0);
    let (re_text, im_text) = body.split_at(split);
    let re = if re_text.is_empty() { 0.0 } else { plain(re_text)? };
    let im = match im_text {
        "" | "+" => 1.0,
        "-" => -1.0,
        t => plain(t)?,
    };
    Some(Parsed { z: C::new(re, im), suffix: Some(suffix) })
}

/// A plain decimal number (sign, digits, point, exponent), no spaces.
fn plain(text: &str) -> Option<f64> {
    let ok = !text.is_empty()
        && text.bytes().all(|b| b.is_ascii_digit() || matches!(b, b'+' | b'-' | b'.' | b'e' | b'E'))
        && text.bytes().any(|b| b.is_ascii_digit());
    if ok {
        parse_plain_number(text)
    } else {
        None
    }
}

/// The one suffix of several arguments: mixing `i` and `j` is #VALUE!.
fn common_suffix(parts: &[Parsed]) -> XlResult<char> {
    let mut suffix = None;
    for p in parts {
        match (suffix, p.suffix) {
            (Some(a), Some(b)) if a != b => return Err(XlError::Value),
            (None, Some(b)) => suffix = Some(b),
            _ => {}
        }
    }
    Ok(suffix.unwrap_or('i'))
}

/// Excel's text for a complex number.
fn format(z: C, suffix: char) -> XlResult<Value> {
    check(z.re.is_finite() && z.im.is_finite(), XlError::Num)?;
    let clean = |x: f64| if x == 0.0 { 0.0 } else { x };
    let (re, im) = (clean(z.re), clean(z.im));
    let mut out = String::new();
    if re != 0.0 || im == 0.0 {
        out.push_str(&general(re));
    }
    if im != 0.0 {
        if im > 0.0 && !out.is_empty() {
            out.push('+');
        }
        match im {
            1.0 => {}
            -1.0 => out.push('-'),
            _ => out.push_str(&general(im)),
        }
        out.push(suffix);
    }
    Ok(Value::text(out))
}

fn complex(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let re = number_only(a, 0)?;
        let im = number_only(a, 1)?;
        let suffix = if a.given(2) { a.text(2)? } else { "i".into() };
        let suffix = match &*suffix {
            "" | "i" => 'i',
            "j" => 'j',
            _ => return Err(XlError::Value),
        };
        format(C::new(re, im), suffix)
    })
}

/// A real argument; booleans are #VALUE!.
fn number_only(a: Scalars, i: usize) -> XlResult<f64> {
    match a.value(i) {
        Value::Bool(_) => Err(XlError::Value),
        _ => a.num(i),
    }
}

fn real_of(ctx: &mut Ctx, args: &[Expr], f: fn(C) -> XlResult<f64>) -> XlResult<Value> {
    scalar(ctx, args, &|a| Ok(Value::Number(f(parse(a.value(0))?.z)?)))
}

fn imreal(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    real_of(ctx, args, |z| Ok(z.re))
}

fn imaginary(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    real_of(ctx, args, |z| Ok(z.im))
}

fn imabs(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    real_of(ctx, args, |z| Ok(z.re.hypot(z.im)))
}

fn imargument(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    real_of(ctx, args, |z| {
        check(z.re != 0.0 || z.im != 0.0, XlError::Div0)?;
        Ok(z.im.atan2(z.re))
    })
}

/// A complex function of one complex number, the result in the argument's suffix.
fn map1(ctx: &mut Ctx, args: &[Expr], f: fn(C) -> XlResult<C>) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let p = parse(a.value(0))?;
        format(f(p.z)?, p.suffix.unwrap_or('i'))
    })
}

fn map2(ctx: &mut Ctx, args: &[Expr], f: fn(C, C) -> XlResult<C>) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let (p, q) = (parse(a.value(0))?, parse(a.value(1))?);
        format(f(p.z, q.z)?, common_suffix(&[p, q])?)
    })
}

/// Every complex number of the arguments, ranges and arrays item by item (a blank is 0).
fn fold(ctx: &mut Ctx, args: &[Expr], start: C, f: fn(C, C) -> C) -> XlResult<Value> {
    let mut parts = Vec::new();
    for arg in args {
        match ctx.eval(arg) {
            Value::Array(items) => {
                for v in &items.data {
                    parts.push(parse(v)?);
                }
            }
            Value::Error(e) => return Err(e),
            v => parts.push(parse(&v)?),
        }
    }
    let suffix = common_suffix(&parts)?;
    format(parts.iter().fold(start, |acc, p| f(acc, p.z)), suffix)
}

fn imsum(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    fold(ctx, args, C::new(0.0, 0.0), |a, b| a + b)
}

fn improduct(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    fold(ctx, args, C::new(1.0, 0.0), |a, b| a * b)
}

fn imsub(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map2(ctx, args, |a, b| Ok(a - b))
}

fn imdiv(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map2(ctx, args, |a, b| {
        check(b.re != 0.0 || b.im != 0.0, XlError::Num)?;
        Ok(a / b)
    })
}

fn impower(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    scalar(ctx, args, &|a| {
        let p = parse(a.value(0))?;
        let n = number_only(a, 1)?;
        let z = p.z;
        check(z.re != 0.0 || z.im != 0.0 || n > 0.0, XlError::Num)?;
        // In polar form, as Excel computes it: r^n (cos nθ + i sin nθ).
        let (r, theta) = (z.re.hypot(z.im), z.im.atan2(z.re));
        let rn = r.powf(n);
        format(C::new(rn * (n * theta).cos(), rn * (n * theta).sin()), p.suffix.unwrap_or('i'))
    })
}

fn nonzero(z: C) -> XlResult<C> {
    check(z.re != 0.0 || z.im != 0.0, XlError::Num)?;
    Ok(z)
}

fn imconjugate(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map1(ctx, args, |z| Ok(z.conj()))
}

fn imsqrt(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    // In polar form, as Excel computes it (so √-1 has Excel's tiny real part).
    map1(ctx, args, |z| {
        let (r, theta) = (z.re.hypot(z.im).sqrt(), z.im.atan2(z.re) / 2.0);
        Ok(C::new(r * theta.cos(), r * theta.sin()))
    })
}

fn imexp(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map1(ctx, args, |z| Ok(z.exp()))
}

fn imln(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map1(ctx, args, |z| Ok(nonzero(z)?.ln()))
}

fn imlog10(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map1(ctx, args, |z| Ok(nonzero(z)?.ln() / std::f64::consts::LN_10))
}

fn imlog2(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map1(ctx, args, |z| Ok(nonzero(z)?.ln() / std::f64::consts::LN_2))
}

fn imsin(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map1(ctx, args, |z| Ok(z.sin()))
}

fn imcos(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map1(ctx, args, |z| Ok(z.cos()))
}

fn imtan(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map1(ctx, args, |z| Ok(z.tan()))
}

fn inverse(z: C) -> XlResult<C> {
    Ok(C::new(1.0, 0.0) / nonzero(z)?)
}

fn imsec(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map1(ctx, args, |z| inverse(z.cos()))
}

fn imcsc(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map1(ctx, args, |z| inverse(z.sin()))
}

fn imcot(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map1(ctx, args, |z| inverse(z.tan()))
}

fn imsinh(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map1(ctx, args, |z| Ok(z.sinh()))
}

fn imcosh(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map1(ctx, args, |z| Ok(z.cosh()))
}

fn imsech(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map1(ctx, args, |z| inverse(z.cosh()))
}

fn imcsch(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    map1(ctx, args, |z| inverse(z.sinh()))
}
