//! VBA's Decimal ("Decimal data type": a 96-bit integer scaled by a power of ten, 0 to 28
//! places, ±79,228,162,514,264,337,593,543,950,335). A macro's numbers are the one evaluator's
//! doubles, so a Decimal is held as the double nearest to it; where that double's shortest text
//! is not the Decimal (more than 15 to 17 significant digits), the Decimal itself is kept
//! beside it ([`KeptDecimals`], a Variant's slot), as `longlong.rs` keeps LongLongs past 2^53.
//! `+ - * /` of Decimals ([MS-VBAL] 5.6.9.3: the operation's value type is Decimal, "/
//! operator": "Division involves a Decimal and any other data type: A Decimal") are computed on
//! the decimals exactly and fitted to 28 places and 96 bits, halves to even, the way real
//! modules use CDec "to prevent bit errors of reals" (CDec(32.675) * 100 is 3267.5, where the
//! doubles give 3267.4999999999995). The kept digits go on through a Variant variable, a
//! Function's result, CDec, CVar, Int, Fix, Abs, Round, the comparisons and every text (CStr,
//! Str, Print, `&`); anything reading a Double (Sqr, a cell, a Double variable) takes the
//! nearest double, as VBA converts; a Variant parameter takes the digits with the value. A
//! place that keeps a double alone (an array item, a Type's field) refuses such a Decimal by
//! name.

use std::cmp::Ordering;
use std::collections::HashMap;

use crate::eval::Value;
use crate::formula::ast::{BinOp, Expr, ExprKind, UnaryOp};

use super::super::interp::{Fault, Interp};
use super::Declared;

/// The largest Decimal ("Decimal data type": 79,228,162,514,264,337,593,543,950,335, 2^96 - 1).
const DECIMAL_END: u128 = 79_228_162_514_264_337_593_543_950_335;

/// The most places after the point a Decimal keeps ("Decimal data type": 0 through 28).
const MAX_SCALE: u32 = 28;

/// A Decimal: `mantissa` (below 2^96) × 10^-`scale`, negative or not; zero is never negative.
/// Trailing zeros after the point are dropped, which changes no value and no result: each
/// operation works out its exact result before it is fitted ([`fit`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(in crate::vba) struct Dec {
    negative: bool,
    mantissa: u128,
    scale: u32,
}

/// An unsigned integer of 320 bits, little-endian words: wide enough for an operation's exact
/// result before it is fitted to a Decimal (a product of two 96-bit mantissas, a sum aligned
/// to 28 places, a dividend scaled by up to 10^57).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Wide([u64; 5]);

impl Wide {
    fn of(n: u128) -> Wide {
        Wide([n as u64, (n >> 64) as u64, 0, 0, 0])
    }

    /// The number, where it fits in 128 bits.
    fn narrow(self) -> Option<u128> {
        self.0[2..].iter().all(|&w| w == 0).then(|| u128::from(self.0[0]) | u128::from(self.0[1]) << 64)
    }

    fn times(self, k: u64) -> Option<Wide> {
        let mut out = [0u64; 5];
        let mut carry = 0u128;
        for (o, &w) in out.iter_mut().zip(&self.0) {
            let p = u128::from(w) * u128::from(k) + carry;
            *o = p as u64;
            carry = p >> 64;
        }
        (carry == 0).then_some(Wide(out))
    }

    fn times_ten_to(self, k: u32) -> Option<Wide> {
        (0..k).try_fold(self, |w, _| w.times(10))
    }

    /// `a × b` for two numbers below 2^128: below 2^256, so it always fits.
    fn product(a: u128, b: u128) -> Wide {
        let (x, y) = ([a as u64, (a >> 64) as u64], [b as u64, (b >> 64) as u64]);
        let mut out = [0u64; 5];
        for (i, &xi) in x.iter().enumerate() {
            let mut carry = 0u128;
            for (j, &yj) in y.iter().enumerate() {
                let t = u128::from(xi) * u128::from(yj) + u128::from(out[i + j]) + carry;
                out[i + j] = t as u64;
                carry = t >> 64;
            }
            out[i + 2] = carry as u64;
        }
        Wide(out)
    }

    fn plus(self, other: Wide) -> Option<Wide> {
        let mut out = [0u64; 5];
        let mut carry = 0u128;
        for ((o, &a), &b) in out.iter_mut().zip(&self.0).zip(&other.0) {
            let t = u128::from(a) + u128::from(b) + carry;
            *o = t as u64;
            carry = t >> 64;
        }
        (carry == 0).then_some(Wide(out))
    }

    /// `self − other`, for `other` not above `self`.
    fn minus(self, other: Wide) -> Wide {
        let mut out = [0u64; 5];
        let mut borrow = false;
        for ((o, &a), &b) in out.iter_mut().zip(&self.0).zip(&other.0) {
            let (d, under) = a.overflowing_sub(b);
            let (d, under2) = d.overflowing_sub(u64::from(borrow));
            *o = d;
            borrow = under || under2;
        }
        Wide(out)
    }

    /// The quotient and remainder by a small divisor.
    fn divided_small(self, k: u64) -> (Wide, u64) {
        let mut out = [0u64; 5];
        let mut rest = 0u128;
        for i in (0..5).rev() {
            let cur = rest << 64 | u128::from(self.0[i]);
            out[i] = (cur / u128::from(k)) as u64;
            rest = cur % u128::from(k);
        }
        (Wide(out), rest as u64)
    }

    /// The quotient and remainder by `d`, non-zero and below 2^96, a bit at a time.
    fn divided(self, d: u128) -> (Wide, u128) {
        let mut out = [0u64; 5];
        let mut rest = 0u128;
        for bit in (0..320).rev() {
            rest = rest << 1 | u128::from((self.0[bit / 64] >> (bit % 64)) & 1);
            if rest >= d {
                rest -= d;
                out[bit / 64] |= 1 << (bit % 64);
            }
        }
        (Wide(out), rest)
    }
}

impl Ord for Wide {
    fn cmp(&self, other: &Wide) -> Ordering {
        self.0.iter().rev().cmp(other.0.iter().rev())
    }
}

impl PartialOrd for Wide {
    fn partial_cmp(&self, other: &Wide) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The Decimal nearest to `magnitude` × 10^-`scale` (negative or not): places dropped from the
/// right, rounded half to even, until it has at most 28 places and its mantissa fits 96 bits,
/// as VBA fits every Decimal result ("Decimal data type"; OLE Automation's VarDecAdd, VarDecMul
/// and VarDecDiv round the same way). `inexact` when digits past `magnitude` were dropped
/// already (a quotient's remainder). `None` when the whole part is past a Decimal (Overflow).
fn fit(negative: bool, magnitude: Wide, scale: u32, inexact: bool) -> Option<Dec> {
    let (mut magnitude, mut scale, mut sticky, mut dropped) = (magnitude, scale, inexact, 0u64);
    while scale > MAX_SCALE || magnitude.narrow().is_none_or(|m| m > DECIMAL_END) {
        if scale == 0 {
            return None;
        }
        sticky |= dropped != 0;
        (magnitude, dropped) = magnitude.divided_small(10);
        scale -= 1;
    }
    let mut mantissa = magnitude.narrow()?;
    if dropped > 5 || (dropped == 5 && (sticky || mantissa % 2 == 1)) {
        mantissa += 1;
        if mantissa > DECIMAL_END {
            // 2^96 itself: one more place goes (its last digit is 6, no tie).
            if scale == 0 {
                return None;
            }
            mantissa = mantissa / 10 + u128::from(mantissa % 10 >= 5);
            scale -= 1;
        }
    }
    Some(Dec { negative: negative && mantissa != 0, mantissa, scale }.normalized())
}

/// Why an operation of Decimals gave none.
#[derive(Debug, PartialEq, Eq)]
pub(in crate::vba) enum DecFault {
    /// Past ±79,228,162,514,264,337,593,543,950,335: Overflow (run-time error 6).
    Overflow,
    /// Division by zero (run-time error 11).
    ByZero,
}

impl Dec {
    /// The decimal written as `[-]digits[.digits][e[±]exponent]`, as Rust writes doubles and
    /// VBA reads a number's text; more digits than a Decimal keeps are rounded half to even.
    pub(in crate::vba) fn from_text(text: &str) -> Option<Dec> {
        let text = text.trim();
        let (mantissa, exponent) = match text.split_once(['e', 'E']) {
            Some((m, e)) => (m, e.strip_prefix('+').unwrap_or(e).parse::<i32>().ok()?),
            None => (text, 0),
        };
        let (negative, mantissa) = match mantissa.strip_prefix('-') {
            Some(rest) => (true, rest),
            None => (false, mantissa.strip_prefix('+').unwrap_or(mantissa)),
        };
        let (whole, fraction) = mantissa.split_once('.').unwrap_or((mantissa, ""));
        if whole.is_empty() && fraction.is_empty() {
            return None;
        }
        let mut digits = Wide::of(0);
        for c in whole.bytes().chain(fraction.bytes()) {
            if !c.is_ascii_digit() {
                return None;
            }
            digits = digits.times(10)?.plus(Wide::of(u128::from(c - b'0')))?;
        }
        let scale = i64::try_from(fraction.len()).ok()? - i64::from(exponent);
        if scale < 0 {
            let up = u32::try_from(-scale).ok()?;
            return fit(negative, digits.times_ten_to(up)?, 0, false);
        }
        fit(negative, digits, u32::try_from(scale).ok()?, false)
    }

    /// The decimal a Decimal-held double stands for: the shortest text that gives it back.
    pub(super) fn held(n: f64) -> Option<Dec> {
        n.is_finite().then(|| Dec::from_text(&format!("{n}")))?
    }

    /// A Double made a Decimal: its 15 significant digits, as OLE Automation's VarDecFromR8
    /// converts (`CDec(0.1 + 0.2)` is 0.3); a Single's 7 (VarDecFromR4).
    pub(super) fn of_double(n: f64, digits: usize) -> Option<Dec> {
        n.is_finite().then(|| Dec::from_text(&format!("{n:.*e}", digits - 1)))?
    }

    /// The same decimal without trailing zeros after the point.
    fn normalized(self) -> Dec {
        let mut d = self;
        while d.scale > 0 && d.mantissa.is_multiple_of(10) {
            d.mantissa /= 10;
            d.scale -= 1;
        }
        d
    }

    fn negated(self) -> Dec {
        Dec { negative: !self.negative && self.mantissa != 0, ..self }
    }

    fn abs(self) -> Dec {
        Dec { negative: false, ..self }
    }

    /// The mantissa at `scale` places (not below the decimal's own).
    fn at_scale(self, scale: u32) -> Option<Wide> {
        Wide::of(self.mantissa).times_ten_to(scale - self.scale)
    }

    /// `self + other`, or `self − other` where `negate_other`.
    fn sum(self, other: Dec, negate_other: bool) -> Result<Dec, DecFault> {
        let other = if negate_other { other.negated() } else { other };
        let scale = self.scale.max(other.scale);
        let (a, b) =
            (self.at_scale(scale).ok_or(DecFault::Overflow)?, other.at_scale(scale).ok_or(DecFault::Overflow)?);
        let (negative, magnitude) = match (self.negative == other.negative, a >= b) {
            (true, _) => (self.negative, a.plus(b).ok_or(DecFault::Overflow)?),
            (false, true) => (self.negative, a.minus(b)),
            (false, false) => (other.negative, b.minus(a)),
        };
        fit(negative, magnitude, scale, false).ok_or(DecFault::Overflow)
    }

    fn product(self, other: Dec) -> Result<Dec, DecFault> {
        let magnitude = Wide::product(self.mantissa, other.mantissa);
        fit(self.negative != other.negative, magnitude, self.scale + other.scale, false).ok_or(DecFault::Overflow)
    }

    /// The quotient, worked out to 29 places and fitted ([`fit`]): 1/3 is
    /// 0.3333333333333333333333333333, 10/3 3.3333333333333333333333333333.
    fn quotient(self, other: Dec) -> Result<Dec, DecFault> {
        if other.mantissa == 0 {
            return Err(DecFault::ByZero);
        }
        // self / other = (a / b) × 10^(other.scale − self.scale); the quotient at 29 places
        // is a × 10^(29 − self.scale + other.scale) / b.
        let up = MAX_SCALE + 1 - self.scale + other.scale;
        let dividend = Wide::of(self.mantissa).times_ten_to(up).ok_or(DecFault::Overflow)?;
        let (quotient, rest) = dividend.divided(other.mantissa);
        fit(self.negative != other.negative, quotient, MAX_SCALE + 1, rest != 0).ok_or(DecFault::Overflow)
    }

    /// The whole part: the largest whole decimal not above it (`floor`, VBA's Int) or the
    /// decimal without its fraction (Fix).
    fn whole(self, floor: bool) -> Dec {
        let unit = 10u128.pow(self.scale);
        let (mut mantissa, rest) = (self.mantissa / unit, self.mantissa % unit);
        if floor && self.negative && rest != 0 {
            mantissa += 1;
        }
        Dec { negative: self.negative && mantissa != 0, mantissa, scale: 0 }
    }

    /// Rounded to `places` places, halves to even ("Round function").
    fn rounded(self, places: u32) -> Dec {
        if self.scale <= places {
            return self;
        }
        let unit = 10u128.pow(self.scale - places);
        let (mut mantissa, rest) = (self.mantissa / unit, self.mantissa % unit);
        if rest * 2 > unit || (rest * 2 == unit && mantissa % 2 == 1) {
            mantissa += 1;
        }
        Dec { negative: self.negative && mantissa != 0, mantissa, scale: places }.normalized()
    }

    /// The decimal as VBA writes a Decimal: every digit, no exponent, no trailing zeros.
    pub(in crate::vba) fn text(self) -> String {
        let digits = self.mantissa.to_string();
        let sign = if self.negative { "-" } else { "" };
        let scale = self.scale as usize;
        if scale == 0 {
            return format!("{sign}{digits}");
        }
        let padded = format!("{digits:0>width$}", width = scale + 1);
        let (whole, fraction) = padded.split_at(padded.len() - scale);
        format!("{sign}{whole}.{fraction}")
    }

    /// The double nearest to the decimal (Rust reads a decimal text correctly rounded).
    fn nearest(self) -> f64 {
        self.text().parse().unwrap_or(f64::NAN)
    }

    /// The double that stands for the decimal, when its shortest text gives the decimal back.
    #[cfg(test)]
    fn to_double(self) -> Option<f64> {
        let n = self.nearest();
        (Dec::held(n)? == self).then_some(n)
    }
}

impl Ord for Dec {
    fn cmp(&self, other: &Dec) -> Ordering {
        let scale = self.scale.max(other.scale);
        // Both are below 2^96 × 10^28, which a Wide holds.
        let magnitudes = || (self.at_scale(scale).unwrap_or(Wide::of(0)), other.at_scale(scale).unwrap_or(Wide::of(0)));
        match (self.negative, other.negative) {
            (false, true) => Ordering::Greater,
            (true, false) => Ordering::Less,
            (false, false) => magnitudes().0.cmp(&magnitudes().1),
            (true, true) => magnitudes().1.cmp(&magnitudes().0),
        }
    }
}

impl PartialOrd for Dec {
    fn partial_cmp(&self, other: &Dec) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The Decimals a macro holds whose digits no double gives back, beside the nearest double
/// the one evaluator computes with, as `longlong.rs` keeps LongLongs past 2^53: each Decimal
/// operation's last such result (by the address of its first operand), each Function call
/// node's, and what the Function returning last gave. A variable keeps its own in its slot.
/// Each is used only where its nearest double is the value at hand.
#[derive(Debug, Default)]
pub(in crate::vba) struct KeptDecimals {
    ops: HashMap<usize, Dec>,
    nodes: HashMap<u32, Dec>,
    gave: Option<Dec>,
    /// Whether any Decimal was ever kept: until one is, nothing is looked up.
    seen: bool,
}

fn key(e: &Expr) -> usize {
    e as *const Expr as usize
}

/// Whether a number of the type `ty` becomes a Decimal digit for digit: a whole-number type,
/// a Currency's four places, or a Decimal held as the double that stands for it.
fn exact_in_decimal(ty: Declared) -> bool {
    matches!(
        ty,
        Declared::Decimal
            | Declared::Currency
            | Declared::Byte
            | Declared::Boolean
            | Declared::Integer
            | Declared::Long
            | Declared::LongLong
    )
}

impl Interp<'_, '_> {
    /// The decimal an operand of a Decimal operation stands for ([MS-VBAL] 5.6.9.3: each
    /// operand is Let-coerced to the operation's type): a Decimal's own digits (those kept
    /// beside its double, or the double's), a LongLong's or a Currency's every digit, a
    /// Double's 15 significant digits, a Single's 7.
    fn decimal_operand(&self, e: &Expr, n: f64) -> Option<Dec> {
        match self.held_operand(e) {
            Declared::Decimal => self.kept_decimal(e, n).or_else(|| Dec::held(n)),
            Declared::LongLong | Declared::Currency => {
                self.long_long_text(e, &Value::Number(n)).and_then(|t| Dec::from_text(&t)).or_else(|| Dec::held(n))
            }
            ty if exact_in_decimal(ty) => Dec::held(n),
            Declared::Single => Dec::of_double(n, 7),
            _ => Dec::of_double(n, 15),
        }
    }

    /// `a op b` computed in Decimal ("Decimal data type": a 96-bit integer scaled by a power of
    /// ten, 0 to 28 places): the result's nearest double, its every digit kept beside it where
    /// the double does not give them back ([`KeptDecimals`]); Overflow (run-time error 6) past
    /// a Decimal's range.
    #[inline(never)]
    pub(in crate::vba) fn decimal_result(
        &self,
        op: BinOp,
        (a, b): (&Expr, &Expr),
        (x, y): (f64, f64),
    ) -> Result<Value, Fault> {
        let (Some(left), Some(right)) = (self.decimal_operand(a, x), self.decimal_operand(b, y)) else {
            return Err(self.decimal_refused(a, b));
        };
        let exact = match op {
            BinOp::Add => left.sum(right, false),
            BinOp::Sub => left.sum(right, true),
            BinOp::Mul => left.product(right),
            _ => left.quotient(right),
        };
        match exact {
            Ok(d) => Ok(Value::Number(self.keep_decimal(a, d))),
            Err(DecFault::Overflow) => {
                let shown = self.quoted_source(a.span.start, b.span.end, "the operation");
                Err(self.overflow_fault(self.expr_span(a), format!("{shown} overflows: its result is past a Decimal")))
            }
            Err(DecFault::ByZero) => {
                let mut fault = self
                    .fault_at(self.expr_span(b), crate::eval::functions::vba::errors::message(11, "Division by zero"));
                fault.code = 11;
                Err(fault)
            }
        }
    }

    /// The nearest double to `d`, the result of the operation whose first operand is `first`,
    /// with `d` kept for it where that double does not give its digits back (and forgotten
    /// where it does: the operation gave another value before).
    fn keep_decimal(&self, first: &Expr, d: Dec) -> f64 {
        let n = d.nearest();
        let mut kept = self.decimals.borrow_mut();
        if Dec::held(n) == Some(d) {
            if kept.seen {
                kept.ops.remove(&key(first));
            }
        } else {
            kept.seen = true;
            kept.ops.insert(key(first), d);
        }
        n
    }

    /// The Decimal kept for `e` whose nearest double is `n`, its value; `None` where none is
    /// kept (the double is then the value's own).
    #[inline(never)]
    pub(in crate::vba) fn kept_decimal(&self, e: &Expr, n: f64) -> Option<Dec> {
        // A call (CDec of a text) gives its digits from its argument, kept or not.
        let looked_up = self.decimals.borrow().seen || matches!(e.kind, ExprKind::Call(..));
        let kept = match looked_up {
            true => self.kept_for(e).filter(|d| d.nearest().to_bits() == n.to_bits()),
            false => None,
        };
        kept.or_else(|| self.decimal_of_scaled(e, n))
    }

    /// `CDec(x)` of a LongLong or a Currency `x` whose digits its double `n` (CDec's too) does
    /// not give back: its every digit ([MS-VBAL] 5.5.1.2.1, a Let-coercion keeps the value).
    pub(in crate::vba) fn decimal_of_scaled(&self, e: &Expr, n: f64) -> Option<Dec> {
        let ExprKind::Call(id, args) = &e.kind else { return None };
        if crate::eval::functions::spec(*id).name != "VBA.CDEC" {
            return None;
        }
        let arg = args.first()?;
        if !matches!(self.held_operand(arg), Declared::LongLong | Declared::Currency) {
            return None;
        }
        let d = Dec::from_text(&self.long_long_text(arg, &Value::Number(n))?)?;
        (d.nearest().to_bits() == n.to_bits() && Dec::held(n) != Some(d)).then_some(d)
    }

    /// The Decimal last kept for the expression `e`, whatever its value now.
    fn kept_for(&self, e: &Expr) -> Option<Dec> {
        match &e.kind {
            ExprKind::Paren(inner) | ExprKind::Unary(UnaryOp::Plus, inner) => self.kept_for(inner),
            ExprKind::Unary(UnaryOp::Neg, inner) => self.kept_for(inner).map(Dec::negated),
            ExprKind::Name(name) => self.with_slot(name, |s| s.decimal()).flatten(),
            ExprKind::Binary(_, first, _) => self.decimals.borrow().ops.get(&key(first)).copied(),
            ExprKind::Host(id) => self.decimals.borrow().nodes.get(id).copied(),
            ExprKind::Call(id, args) => self.kept_call(crate::eval::functions::spec(*id).name, args),
            _ => None,
        }
    }

    /// The Decimal a VBA function gave from its Decimal argument's digits: CDec's and CVar's
    /// are the argument's ("Type conversion functions"), Int's and Fix's its whole part,
    /// Abs's its magnitude ("Abs function": the same type), Round's its digits rounded half
    /// to even to a number of places written as a literal ("Round function").
    fn kept_call(&self, name: &str, args: &[Expr]) -> Option<Dec> {
        let arg = args.first()?;
        match name {
            "VBA.CDEC" => match &arg.kind {
                ExprKind::Text(t) => Dec::from_text(t),
                _ => self.kept_for(arg),
            },
            "VBA.CVAR" => self.kept_for(arg),
            "VBA.INT" => self.kept_for(arg).map(|d| d.whole(true)),
            "VBA.FIX" => self.kept_for(arg).map(|d| d.whole(false)),
            "VBA.ABS" => self.kept_for(arg).map(Dec::abs),
            "VBA.ROUND" => {
                let places = match args.get(1).map(|p| &p.kind) {
                    None => 0.0,
                    Some(ExprKind::Number(p)) => *p,
                    Some(_) => return None,
                };
                (places >= 0.0).then_some(())?;
                self.kept_for(arg).map(|d| d.rounded(places.min(f64::from(MAX_SCALE)) as u32))
            }
            _ => None,
        }
    }

    /// `Int` (`floor`) or `Fix` of a Decimal `v`, the value of `e`, whose digits are kept
    /// beside its double ("Int, Fix functions": the whole part, of the argument's type):
    /// `Int(CDec(10.5) * 10 ^ 20 + 0.5)` is 1050000000000000000000, where the double nearest
    /// to the Decimal 1050000000000000000000.5 is itself whole. `None` for any other value.
    #[inline(never)]
    pub(in crate::vba) fn decimal_whole(&self, e: &Expr, v: &Value, floor: bool) -> Option<f64> {
        let Value::Number(n) = v else { return None };
        self.kept_decimal(e, *n).map(|d| d.whole(floor).nearest())
    }

    /// `name = value` where `value` gave the Decimal `v` whose digits are kept beside its
    /// double, for a Variant (the only variable that holds a Decimal, "Decimal data type"):
    /// the digits kept in the variable with the double. `false` (nothing done) for any other
    /// assignment, which converts as usual (a Double takes the nearest double).
    #[inline(never)]
    pub(in crate::vba) fn assign_decimal(&self, name: &str, value: &Expr, v: &Value) -> bool {
        let Value::Number(n) = v else { return false };
        let Some(d) = self.kept_decimal(value, *n) else { return false };
        self.decimals.borrow_mut().seen = true;
        self.with_slot(name, |slot| {
            let variant = matches!(Declared::of_ty(slot.ty.as_ref()), Declared::Variant);
            if slot.constant || !variant || !matches!(slot.var(), super::super::value::Var::Value(_)) {
                return false;
            }
            slot.replace(super::super::value::Var::Value(Value::Number(*n)));
            slot.set_holds(Declared::Decimal);
            slot.set_decimal(d);
            true
        }) == Some(true)
    }

    /// Refuses the Decimal `v`, the value of `e`, given to `place` (an argument, an array
    /// item, a Type's field, a Collection's item) where its digits are kept beside its double:
    /// ncsheet keeps them in a variable, an operation and a Function's result, and the place
    /// would take the nearest double, another number. No `On Error` traps it.
    #[inline(never)]
    pub(in crate::vba) fn refuse_kept_decimal(&self, e: &Expr, v: &Value, place: &str) -> Result<(), Fault> {
        let Value::Number(n) = v else { return Ok(()) };
        let Some(d) = self.kept_decimal(e, *n) else { return Ok(()) };
        let shown = self.quoted_source(e.span.start, e.span.end, "the value");
        Err(self.unsupported(
            self.expr_span(e),
            format!(
                "{shown} is the Decimal {}, whose digits no Double holds: ncsheet keeps them in a Variant \
                 variable, an operation or a Function's result, not in {place}; CDbl(…) passes its nearest Double",
                d.text()
            ),
        ))
    }

    /// The Decimal `v`, the value of `e`, stands for where its digits are kept beside its
    /// double; `None` for any other value.
    #[inline(never)]
    pub(in crate::vba) fn kept_decimal_of(&self, e: &Expr, v: &Value) -> Option<Dec> {
        let Value::Number(n) = v else { return None };
        self.kept_decimal(e, *n)
    }

    /// A parameter bound to an argument that gave the Decimal `d`: a Variant holds it, its
    /// digits kept ([MS-VBAL] 5.3.1.11: the argument's value is bound with its value type);
    /// a parameter of another type converted it already.
    #[inline(never)]
    pub(in crate::vba) fn bind_decimal(&self, d: Dec, slot: &mut super::super::value::Slot) {
        let variant = matches!(Declared::of_ty(slot.ty.as_ref()), Declared::Variant);
        let nearest = matches!(slot.var(), super::super::value::Var::Value(Value::Number(n)) if n.to_bits() == d.nearest().to_bits());
        if variant && nearest {
            slot.set_holds(Declared::Decimal);
            slot.set_decimal(d);
        }
    }

    /// Notes the Decimal the Function that is returning gave (its name's variable's).
    #[inline(never)]
    pub(in crate::vba) fn returning_decimal(&self, d: Option<Dec>) {
        if d.is_some() || self.decimals.borrow().gave.is_some() {
            self.decimals.borrow_mut().gave = d;
        }
    }

    /// After the node `id` gave its value: the Decimal a Function gave, kept for the node (and
    /// what an earlier call of it gave forgotten).
    #[inline(never)]
    pub(in crate::vba) fn note_node_decimal(&self, id: u32) {
        let mut kept = self.decimals.borrow_mut();
        if !kept.seen {
            return;
        }
        match kept.gave.take() {
            Some(d) => kept.nodes.insert(id, d),
            None => kept.nodes.remove(&id),
        };
    }

    /// How `a`'s value `x` orders against `b`'s `y` where one is a Decimal whose digits are
    /// kept beside its double: on their decimals ([MS-VBAL] 5.6.9.5: a comparison with a
    /// Decimal operand is a Decimal's). `None` for anything else (the doubles' order is the
    /// values').
    #[inline(never)]
    pub(in crate::vba) fn decimal_order(&self, (a, b): (&Expr, &Expr), (x, y): (&Value, &Value)) -> Option<Ordering> {
        if !self.decimals.borrow().seen {
            return None;
        }
        let (Value::Number(p), Value::Number(q)) = (x, y) else { return None };
        let (i, j) = (self.kept_decimal(a, *p), self.kept_decimal(b, *q));
        if i.is_none() && j.is_none() {
            return None;
        }
        let i = i.or_else(|| self.decimal_operand(a, *p))?;
        let j = j.or_else(|| self.decimal_operand(b, *q))?;
        Some(i.cmp(&j))
    }

    /// The refusal of a Decimal operand no Decimal stands for (a Double past a Decimal's range).
    fn decimal_refused(&self, a: &Expr, b: &Expr) -> Fault {
        let shown = self.quoted_source(a.span.start, b.span.end, "the operation");
        self.overflow_fault(self.expr_span(a), format!("{shown}: an operand is past a Decimal's range"))
    }

    /// The text VBA writes for `v`, the value of `e`, when it is held as a Decimal: its every
    /// digit ("Decimal data type"), where a Double shows 15 (CStr, Str, Print and `&` take it
    /// through `long_long_text`, Round rounds it); `None` for any other value.
    #[inline(never)]
    pub(in crate::vba) fn decimal_text(&self, e: &Expr, v: &Value) -> Option<String> {
        match v {
            Value::Number(n) if self.narrow_numbers && self.value_type(e, v) == Declared::Decimal => {
                self.kept_decimal(e, *n).or_else(|| Dec::held(*n)).map(Dec::text)
            }
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dec(text: &str) -> Dec {
        Dec::from_text(text).unwrap()
    }

    #[test]
    fn decimals_read_and_write_their_digits() {
        assert_eq!(dec("32.675").text(), "32.675");
        assert_eq!(dec("-0.0099").text(), "-0.0099");
        assert_eq!(dec("1.5e3").text(), "1500");
        assert_eq!(dec("100.100").text(), "100.1");
        assert_eq!(Dec::held(3267.5).unwrap().text(), "3267.5");
    }

    // Python's decimal module, computed apart: Decimal("32.675") * 100 == Decimal("3267.5"),
    // Decimal(3268) / 100 == Decimal("32.68"), Decimal("-9999999999999.25") * 10 ==
    // Decimal("-99999999999992.5"); float 32.675 * 100 is 3267.4999999999995.
    #[test]
    fn decimal_arithmetic_is_exact() {
        assert_eq!(dec("32.675").product(dec("100")), Ok(dec("3267.5")));
        assert_eq!(dec("3268").quotient(dec("100")), Ok(dec("32.68")));
        assert_eq!(dec("-9999999999999.25").product(dec("10")), Ok(dec("-99999999999992.5")));
        assert_eq!(dec("0.1").sum(dec("0.2"), false), Ok(dec("0.3")));
        assert_eq!(dec("0.1").sum(dec("0.3"), true), Ok(dec("-0.2")));
        assert_eq!(dec("1").quotient(dec("0")), Err(DecFault::ByZero));
    }

    // Microsoft's "Decimal data type": a 96-bit integer scaled by 10^0 to 10^28. Each result
    // rounded half to even to the most places whose integer fits 96 bits, computed apart by
    // /tmp/h1/s32/oracle.py (Python's decimal at 200 digits, then that rule): 1/3 is
    // 0.3333333333333333333333333333, 2/3 0.6666666666666666666666666667, 10/3
    // 3.3333333333333333333333333333 (29 digits: its integer is below 2^96), (1/3)·3
    // 0.9999999999999999999999999999, (1/3)+10 10.333333333333333333333333333, (1/3)·(1/3)
    // 0.1111111111111111111111111111, (1/7)·7 1.0000000000000000000000000003.
    #[test]
    fn decimal_results_keep_twenty_eight_places_and_ninety_six_bits() {
        let third = dec("1").quotient(dec("3")).unwrap();
        assert_eq!(third.text(), "0.3333333333333333333333333333");
        assert_eq!(dec("2").quotient(dec("3")).unwrap().text(), "0.6666666666666666666666666667");
        assert_eq!(dec("10").quotient(dec("3")).unwrap().text(), "3.3333333333333333333333333333");
        assert_eq!(third.product(dec("3")).unwrap().text(), "0.9999999999999999999999999999");
        assert_eq!(third.sum(dec("10"), false).unwrap().text(), "10.333333333333333333333333333");
        assert_eq!(third.product(third).unwrap().text(), "0.1111111111111111111111111111");
        let seventh = dec("1").quotient(dec("7")).unwrap();
        assert_eq!(seventh.product(dec("7")).unwrap().text(), "1.0000000000000000000000000003");
        assert_eq!(
            dec("1.0000000000000000000000000001").sum(dec("1"), true).unwrap().text(),
            "0.0000000000000000000000000001"
        );
        // 79,228,162,514,264,337,593,543,950,335 + 0.5 rounds to 2^96: Overflow.
        assert_eq!(dec("79228162514264337593543950335").sum(dec("0.5"), false), Err(DecFault::Overflow));
        assert_eq!(Dec::from_text("79228162514264337593543950336"), None);
        assert!(third < dec("0.3333333333333333333333333334") && dec("-1") < third.negated().abs());
    }

    // VarDecFromR8 keeps 15 significant digits: 0.1 + 0.2 (0.30000000000000004) is 0.3.
    #[test]
    fn a_double_becomes_its_fifteen_digits() {
        assert_eq!(Dec::of_double(0.1 + 0.2, 15), Some(dec("0.3")));
        assert_eq!(Dec::of_double(32.675, 15), Some(dec("32.675")));
    }

    // Python's decimal, apart: Decimal("1050000000000000000000.5") floored is
    // 1050000000000000000000; Decimal("-2.5") floored -3, truncated -2; rounded to 1 place
    // half to even 2.345 is 2.3 (2.35 to 1 place is 2.4, 2.25 is 2.2).
    #[test]
    fn a_decimals_whole_part_is_exact() {
        assert_eq!(dec("1050000000000000000000.5").whole(true), dec("1050000000000000000000"));
        assert_eq!(dec("-2.5").whole(true), dec("-3"));
        assert_eq!(dec("-2.5").whole(false), dec("-2"));
        assert_eq!(dec("0.500000000000000000105").whole(true), dec("0"));
        assert_eq!(dec("2.35").rounded(1), dec("2.4"));
        assert_eq!(dec("2.25").rounded(1), dec("2.2"));
    }

    #[test]
    fn a_decimal_the_double_cannot_give_back_has_no_double() {
        assert_eq!(dec("0.1").to_double(), Some(0.1));
        assert_eq!(dec("1.00000000000000000001").to_double(), None);
    }
}
