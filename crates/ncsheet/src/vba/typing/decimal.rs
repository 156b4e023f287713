//! VBA's Decimal ("Decimal data type": an integer of up to 29 digits scaled by a power of
//! ten, ±79,228,162,514,264,337,593,543,950,335) as far as ncsheet keeps it. A macro's
//! numbers are the one evaluator's doubles, so a Decimal is held as the double nearest to
//! it, and that double stands for the decimal its shortest text gives: every decimal of 15
//! significant digits, and most of 16 and 17. `+ - * /` of Decimals ([MS-VBAL] 5.6.9.3: the
//! operation's value type is Decimal, "/ operator": "Division involves a Decimal and any
//! other data type: A Decimal") are computed on those decimals exactly, the way real
//! modules use CDec "to prevent bit errors of reals" (CDec(32.675) * 100 is 3267.5, where
//! the doubles give 3267.4999999999995). A result whose digits the double cannot give back
//! is refused by name, untrappably: VBA would keep digits ncsheet cannot, and a handler that
//! falls back to Doubles would compute something else.

use crate::eval::Value;
use crate::formula::ast::{BinOp, Expr, ExprKind};

use super::super::interp::{Fault, Interp};
use super::Declared;

/// The largest Decimal ("Decimal data type": 79,228,162,514,264,337,593,543,950,335, 2^96 - 1).
const DECIMAL_END: i128 = 79_228_162_514_264_337_593_543_950_335;

/// The most digits a scaled integer may take while an operation is worked out: past them
/// the decimal is far beyond what a double gives back, and is refused.
const WORK_DIGITS: u32 = 36;

/// A decimal number, `digits` × 10^-`scale`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Dec {
    digits: i128,
    scale: i32,
}

/// A Decimal operation's exact result that no double holds, kept beside the nearest double the
/// operation gave: the operation is known by its first operand (`first`, its address) and the
/// double's `bits`; `withdrawable` when the refusal it parked is the statement's first fault.
#[derive(Clone, Copy, Debug)]
pub(in crate::vba) struct UnheldDecimal {
    first: usize,
    bits: u64,
    exact: Dec,
    withdrawable: bool,
}

impl Dec {
    /// The decimal written as `[-]digits[.digits][e[±]exponent]`, as Rust writes doubles.
    fn from_text(text: &str) -> Option<Dec> {
        let (mantissa, exponent) = match text.split_once(['e', 'E']) {
            Some((m, e)) => (m, e.parse::<i32>().ok()?),
            None => (text, 0),
        };
        let (negative, mantissa) = match mantissa.strip_prefix('-') {
            Some(rest) => (true, rest),
            None => (false, mantissa),
        };
        let (whole, fraction) = mantissa.split_once('.').unwrap_or((mantissa, ""));
        let mut digits: i128 = 0;
        for c in whole.bytes().chain(fraction.bytes()) {
            if !c.is_ascii_digit() {
                return None;
            }
            digits = digits.checked_mul(10)?.checked_add(i128::from(c - b'0'))?;
        }
        let scale = i32::try_from(fraction.len()).ok()? - exponent;
        Some(Dec { digits: if negative { -digits } else { digits }, scale }.normalized())
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

    /// The same decimal without trailing zeros after the point; a whole number at scale 0.
    fn normalized(self) -> Dec {
        let mut d = self;
        while d.scale > 0 && d.digits % 10 == 0 {
            d.digits /= 10;
            d.scale -= 1;
        }
        while d.scale < 0 {
            match d.digits.checked_mul(10) {
                Some(m) => {
                    d.digits = m;
                    d.scale += 1;
                }
                None => break,
            }
        }
        d
    }

    /// Both decimals at one scale, the finer one's.
    fn aligned(self, other: Dec) -> Option<(i128, i128, i32)> {
        let scale = self.scale.max(other.scale);
        let up = |d: Dec| d.digits.checked_mul(10_i128.checked_pow(u32::try_from(scale - d.scale).ok()?)?);
        Some((up(self)?, up(other)?, scale))
    }

    fn sum(self, other: Dec, negate_other: bool) -> Option<Dec> {
        let (a, b, scale) = self.aligned(other)?;
        let b = if negate_other { b.checked_neg()? } else { b };
        Some(Dec { digits: a.checked_add(b)?, scale }.normalized())
    }

    fn product(self, other: Dec) -> Option<Dec> {
        Some(Dec { digits: self.digits.checked_mul(other.digits)?, scale: self.scale + other.scale }.normalized())
    }

    /// The exact quotient, when it ends within [`WORK_DIGITS`] digits; `None` when it does
    /// not (1/3), which no double gives back either.
    fn quotient(self, other: Dec) -> Option<Dec> {
        if other.digits == 0 {
            return None;
        }
        let mut numerator = self.digits;
        for extra in 0..=WORK_DIGITS as i32 {
            if numerator % other.digits == 0 {
                let digits = numerator / other.digits;
                return Some(Dec { digits, scale: self.scale + extra - other.scale }.normalized());
            }
            numerator = numerator.checked_mul(10)?;
        }
        None
    }

    /// The whole part: the largest whole decimal not above it (`floor`, VBA's Int) or the
    /// decimal without its fraction (Fix).
    fn whole(self, floor: bool) -> Option<Dec> {
        if self.scale <= 0 {
            return Some(self);
        }
        let unit = 10_i128.checked_pow(u32::try_from(self.scale).ok()?)?;
        let digits = if floor { self.digits.div_euclid(unit) } else { self.digits / unit };
        Some(Dec { digits, scale: 0 }.normalized())
    }

    /// Whether the decimal is past a Decimal's range.
    fn past_range(self) -> bool {
        let mut whole = self.digits.unsigned_abs();
        for _ in 0..self.scale.max(0) {
            whole /= 10;
        }
        self.scale < 0 || whole > DECIMAL_END as u128
    }

    /// The decimal as VBA writes a Decimal: every digit, no exponent, no trailing zeros.
    pub(super) fn text(self) -> String {
        let digits = self.digits.unsigned_abs().to_string();
        let sign = if self.digits < 0 { "-" } else { "" };
        let scale = usize::try_from(self.scale).unwrap_or(0);
        if scale == 0 {
            return format!("{sign}{digits}");
        }
        let padded = format!("{digits:0>width$}", width = scale + 1);
        let (whole, fraction) = padded.split_at(padded.len() - scale);
        format!("{sign}{whole}.{fraction}")
    }

    /// The double that stands for the decimal, when its shortest text gives the decimal back.
    fn to_double(self) -> Option<f64> {
        let text = self.text();
        let n: f64 = text.parse().ok()?;
        (Dec::held(n)? == self).then_some(n)
    }
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
    /// operand is Let-coerced to the operation's type): a Double's 15 digits, a Single's 7.
    fn decimal_operand(&self, e: &Expr, n: f64) -> Option<Dec> {
        match self.held_operand(e) {
            ty if exact_in_decimal(ty) => Dec::held(n),
            Declared::Single => Dec::of_double(n, 7),
            _ => Dec::of_double(n, 15),
        }
    }

    /// `a op b` computed in Decimal: the exact result's double, Overflow (run-time error 6)
    /// past a Decimal's range, and an untrappable refusal where the double cannot hold the
    /// result's digits.
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
            Some(d) if d.past_range() => {
                let shown = self.quoted_source(a.span.start, b.span.end, "the operation");
                Err(self.overflow_fault(self.expr_span(a), format!("{shown} overflows: its result is past a Decimal")))
            }
            Some(d) => match d.to_double() {
                Some(n) => Ok(Value::Number(n)),
                None => Ok(self.unheld_decimal_result(a, b, d)),
            },
            None => Err(self.decimal_refused(a, b)),
        }
    }

    /// A Decimal result `d` of `a op b` within a Decimal's range whose digits no double holds:
    /// its refusal waits until the statement's expression is evaluated, and the nearest double
    /// goes on, so that `Int` or `Fix` of it, whose whole part a double may hold, takes the
    /// exact digits instead and withdraws the refusal ([`Interp::decimal_whole`]); anything
    /// else that reads it is refused as before.
    #[inline(never)]
    fn unheld_decimal_result(&self, a: &Expr, b: &Expr, d: Dec) -> Value {
        let nearest: f64 = d.text().parse().unwrap_or(f64::NAN);
        let withdrawable = self.pending.borrow().is_none();
        self.park(self.decimal_refused(a, b));
        let first = a as *const Expr as usize;
        self.unheld_decimal.set(Some(UnheldDecimal { first, bits: nearest.to_bits(), exact: d, withdrawable }));
        Value::Number(nearest)
    }

    /// `Int` (`floor`) or `Fix` of `v`, the value of `e`, when `e` is the Decimal operation
    /// that last gave a result no double holds ([`Interp::unheld_decimal_result`]) and its
    /// whole part is a double: that double, its waiting refusal withdrawn. `Int(CDec(10.5) *
    /// 10 ^ 20 + 0.5)` is 1050000000000000000000 ("Int, Fix functions"; the Decimal
    /// 1050000000000000000000.5 has 22 digits, which VBA keeps and a double does not).
    #[inline(never)]
    pub(in crate::vba) fn decimal_whole(&self, e: &Expr, v: &Value, floor: bool) -> Option<f64> {
        let unheld = self.unheld_decimal.get()?;
        let mut e = e;
        while let ExprKind::Paren(inner) = &e.kind {
            e = inner;
        }
        let ExprKind::Binary(_, a, _) = &e.kind else { return None };
        let Value::Number(n) = v else { return None };
        if &**a as *const Expr as usize != unheld.first || n.to_bits() != unheld.bits {
            return None;
        }
        let whole = unheld.exact.whole(floor)?.to_double()?;
        self.unheld_decimal.set(None);
        if unheld.withdrawable {
            self.pending.borrow_mut().take();
        }
        Some(whole)
    }

    /// The refusal of a Decimal result with more digits than ncsheet keeps: no `On Error`
    /// traps it (a handler falling back to Doubles would give other numbers).
    fn decimal_refused(&self, a: &Expr, b: &Expr) -> Fault {
        let shown = self.quoted_source(a.span.start, b.span.end, "the operation");
        self.unsupported(
            self.expr_span(a),
            format!(
                "{shown}: a Decimal result of more significant digits than ncsheet keeps (it holds a \
                 Decimal exactly up to the 15 to 17 digits a Double gives back; VBA keeps 28): \
                 CDbl(…) computes it in Double"
            ),
        )
    }

    /// The text VBA writes for `v`, the value of `e`, when it is held as a Decimal: its every
    /// digit ("Decimal data type"), where a Double shows 15 (CStr, Str, Print and `&` take it
    /// through `long_long_text`, Round rounds it); `None` for any other value.
    pub(in crate::vba) fn decimal_text(&self, e: &Expr, v: &Value) -> Option<String> {
        match v {
            Value::Number(n) if self.narrow_numbers && self.value_type(e, v) == Declared::Decimal => {
                Dec::held(*n).map(Dec::text)
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
        assert_eq!(dec("32.675").product(dec("100")), Some(dec("3267.5")));
        assert_eq!(dec("3268").quotient(dec("100")), Some(dec("32.68")));
        assert_eq!(dec("-9999999999999.25").product(dec("10")), Some(dec("-99999999999992.5")));
        assert_eq!(dec("0.1").sum(dec("0.2"), false), Some(dec("0.3")));
        assert_eq!(dec("1").quotient(dec("3")), None);
    }

    // VarDecFromR8 keeps 15 significant digits: 0.1 + 0.2 (0.30000000000000004) is 0.3.
    #[test]
    fn a_double_becomes_its_fifteen_digits() {
        assert_eq!(Dec::of_double(0.1 + 0.2, 15), Some(dec("0.3")));
        assert_eq!(Dec::of_double(32.675, 15), Some(dec("32.675")));
    }

    // Python's decimal, apart: Decimal("1050000000000000000000.5") floored is
    // 1050000000000000000000; Decimal("-2.5") floored -3, truncated -2.
    #[test]
    fn a_decimals_whole_part_is_exact() {
        assert_eq!(dec("1050000000000000000000.5").whole(true), Some(dec("1050000000000000000000")));
        assert_eq!(dec("-2.5").whole(true), Some(dec("-3")));
        assert_eq!(dec("-2.5").whole(false), Some(dec("-2")));
        assert_eq!(dec("0.500000000000000000105").whole(true), Some(dec("0")));
    }

    #[test]
    fn a_decimal_the_double_cannot_give_back_has_no_double() {
        assert_eq!(dec("0.1").to_double(), Some(0.1));
        assert_eq!(dec("1.00000000000000000001").to_double(), None);
        assert!(dec("79228162514264337593543950336").past_range());
        assert!(!dec("79228162514264337593543950335").past_range());
    }
}
