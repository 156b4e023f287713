//! Math and trigonometry. Angles in radians, as in Excel.

use crate::eval::evaluator::{power, Ctx};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::ast::Expr;

use super::args::{for_each_number, lift_number1, lift_number2};
use super::{FnSpec, MANY};

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::value("ABS", 1, 1, abs, "ABS(number)", "Absolute value"),
    FnSpec::value("ATAN", 1, 1, atan, "ATAN(number)", "Arctangent in radians, -pi/2 to pi/2"),
    FnSpec::value(
        "ATAN2",
        2,
        2,
        atan2,
        "ATAN2(x, y)",
        "Angle of the point (x, y) in radians, -pi to pi; x before y as in Excel",
    ),
    FnSpec::value("COS", 1, 1, cos, "COS(angle)", "Cosine of an angle in radians"),
    FnSpec::value("DEGREES", 1, 1, degrees, "DEGREES(angle)", "Radians to degrees"),
    FnSpec::value("PI", 0, 0, pi, "PI()", "3.14159265358979"),
    FnSpec::value("POWER", 2, 2, power_fn, "POWER(number, power)", "number^power"),
    FnSpec::value("ROUND", 2, 2, round, "ROUND(number, digits)", "Rounds half away from zero to digits decimals"),
    FnSpec::value("SIN", 1, 1, sin, "SIN(angle)", "Sine of an angle in radians"),
    FnSpec::value("SQRT", 1, 1, sqrt, "SQRT(number)", "Square root; #NUM! for negative numbers"),
    FnSpec::value(
        "SUM",
        1,
        MANY,
        sum,
        "SUM(number1, [number2], ...)",
        "Adds numbers; text and booleans in ranges are skipped",
    ),
];

fn abs(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(x.abs()))
}

fn atan(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(x.atan()))
}

fn atan2(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number2(ctx, args, 0.0, |x, y| if x == 0.0 && y == 0.0 { Err(XlError::Div0) } else { Ok(y.atan2(x)) })
}

fn cos(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(x.cos()))
}

fn degrees(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(x.to_degrees()))
}

fn pi(_: &mut Ctx, _: &[Expr]) -> XlResult<Value> {
    Ok(Value::Number(std::f64::consts::PI))
}

fn power_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number2(ctx, args, 0.0, power)
}

fn round(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number2(ctx, args, 0.0, |x, d| Ok(round_half_away(x, d.trunc() as i32)))
}

/// Excel's ROUND: half away from zero, judged on the 15-significant-digit value so that
/// `ROUND(2.675, 2)` is 2.68 although 2.675 is stored as 2.67499999….
pub fn round_half_away(x: f64, digits: i32) -> f64 {
    if !x.is_finite() || x == 0.0 {
        return x;
    }
    let digits = digits.clamp(-308, 308);
    let x15 = crate::eval::number_format::round15(x);
    let scale = 10f64.powi(digits.abs());
    let scaled = if digits >= 0 { x15 * scale } else { x15 / scale };
    let rounded = crate::eval::number_format::round15(scaled).abs().add_half_floor() * x.signum();
    if digits >= 0 {
        rounded / scale
    } else {
        rounded * scale
    }
}

trait HalfUp {
    fn add_half_floor(self) -> f64;
}

impl HalfUp for f64 {
    fn add_half_floor(self) -> f64 {
        (self + 0.5).floor()
    }
}

fn sin(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| Ok(x.sin()))
}

fn sqrt(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    lift_number1(ctx, args, |x| if x < 0.0 { Err(XlError::Num) } else { Ok(x.sqrt()) })
}

fn sum(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let mut total = 0.0;
    for_each_number(ctx, args, &mut |n| total += n)?;
    Ok(crate::eval::evaluator::number_result(total))
}
