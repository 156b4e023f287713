//! Where VBA's operators differ from the formula language's, which computes them first
//! ([`crate::eval::evaluator::Host::arithmetic`] hands each result here): text compared
//! under the module's `Option Compare` ([MS-VBAL] 5.2.1.4; Binary, the default, by code
//! units with case, Text without case), a String against a number of a declared type
//! converted to Double ([MS-VBAL] 5.6.9.5), and `Like` under `Option Compare Text`; and an
//! operation that fails raises VBA's run-time error (division by zero 11, a text that is no
//! number 13, a result past a Double 6) where a formula gives an error value.

use std::cmp::Ordering;

use crate::eval::coerce::to_number;
use crate::eval::dates::DateSystem;
use crate::eval::evaluator::comparison_holds;
use crate::eval::functions::vba::{errors, like, vba_text};
use crate::eval::{Value, XlError};
use crate::formula::ast::{BinOp, Expr};

use super::interp::{Fault, Interp};
use super::typing::Declared;

/// VBA's "Type mismatch" ("Trappable errors").
pub(super) const TYPE_MISMATCH: (u32, &str) = (13, errors::description(13));

/// VBA's "Division by zero" and "Overflow" ("Trappable errors").
const DIVISION_BY_ZERO: (u32, &str) = (11, errors::description(11));
const OVERFLOW: (u32, &str) = (6, errors::description(6));
const INVALID_CALL: (u32, &str) = (5, errors::description(5));

/// Whether `op` is one of the relational operators `= <> < > <= >=`.
fn relational(op: BinOp) -> bool {
    matches!(op, BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge)
}

/// Two texts in the order of `Option Compare`: Binary by UTF-16 code units, as VBA's
/// Strings hold them; Text the same with case folded.
pub(super) fn text_order(x: &str, y: &str, text_compare: bool) -> Ordering {
    if text_compare {
        x.to_lowercase().encode_utf16().cmp(y.to_lowercase().encode_utf16())
    } else {
        x.encode_utf16().cmp(y.encode_utf16())
    }
}

/// `0 ^ 0`, which the sheet's `^` makes #NUM!, where VBA's is 1: the "^ operator" page names
/// no exception for it, and 1 is what IEEE 754's pow and LibreOffice's VBA mode give; `None`
/// for any other operation.
pub(super) fn zero_to_the_zero(op: BinOp, (a, b): (&Value, &Value)) -> Option<Value> {
    (op == BinOp::Pow && is_zero(a) && is_zero(b)).then_some(Value::Number(1.0))
}

/// Zero, or Empty or a text read as zero (the dividend of `0 / 0`).
fn is_zero(v: &Value) -> bool {
    crate::eval::functions::vba::vba_number(v).is_ok_and(|n| n == 0.0)
}

/// A number below zero, or a text read as one (the base of a `^` with no real value).
fn is_negative(v: &Value) -> bool {
    crate::eval::functions::vba::vba_number(v).is_ok_and(|n| n < 0.0)
}

impl Interp<'_, '_> {
    /// The run-time error `op` raises where it gave the error value `result` ([MS-VBAL]
    /// 5.6.9.3: `/`, `\` and `Mod` by zero are error 11, a String operand that is no number
    /// or an error value (as `CVErr` makes) 13, a result past a Double's range 6); `None`
    /// for a comparison, `&` and `Like`, and where an array's items keep their errors.
    pub(super) fn raised_error(
        &self,
        op: BinOp,
        (ea, eb): (&Expr, &Expr),
        (a, b): (&Value, &Value),
        result: &Value,
    ) -> Option<Fault> {
        let Value::Error(err) = result else { return None };
        let plain = |v: &Value| !matches!(v, Value::Error(_) | Value::Null | Value::Array(_) | Value::Lambda(_));
        // An error value (`CVErr`, an error cell's value) is no number: arithmetic on it is a
        // Type mismatch ([MS-VBAL] 5.6.9.3, the operands are let-coerced to numbers).
        let error_operand = matches!(a, Value::Error(_)) || matches!(b, Value::Error(_));
        let computed = !relational(op) && !matches!(op, BinOp::Concat | BinOp::Like);
        if !computed || (!error_operand && (!plain(a) || !plain(b))) {
            return None;
        }
        let (code, name) = match (op, err) {
            _ if error_operand => TYPE_MISMATCH,
            // `0 / 0` is Overflow, not Division by zero: it has no value, not an infinite one.
            // Microsoft's Knowledge Base Q42473, "'Overflow' Error Might Be the Result of 0/0",
            // says so of its BASIC (`(b# - c#) / (b# - c#)`), and VBA raises error 6 there; a
            // nonzero number over 0, and `\` and `Mod` by 0, stay error 11.
            (BinOp::Div, XlError::Div0) if is_zero(a) => OVERFLOW,
            (BinOp::Div | BinOp::IntDiv | BinOp::Mod, XlError::Div0) => DIVISION_BY_ZERO,
            // "^ operator": "a number can be negative only if exponent is an integer value";
            // VBA raises Invalid procedure call for `(-8) ^ (1 / 3)`, and for `0 ^ -1`, which
            // has no value either, where the sheet gives #NUM! and #DIV/0!.
            (BinOp::Pow, XlError::Div0) => INVALID_CALL,
            (BinOp::Pow, XlError::Num) if is_negative(a) => INVALID_CALL,
            (_, XlError::Value) => TYPE_MISMATCH,
            (_, XlError::Num) => OVERFLOW,
            _ => return None,
        };
        let shown = self.quoted_source(ea.span.start, eb.span.end, "the operation");
        let mut fault = self.fault_at(self.expr_span(ea), format!("{name} (run-time error {code}): {shown}"));
        fault.code = code;
        Some(fault)
    }

    /// Type mismatch (run-time error 13) of `a & b` with an error value (`CVErr`, an error
    /// cell's value) as an operand: `&` let-coerces each operand to String ([MS-VBAL] 5.6.9.4)
    /// and an Error let-coerced to any type but Variant is run-time error 13 ([MS-VBAL]
    /// 5.5.1.2, "Let-coercion from Error"), where a formula's `&` would give the error value.
    pub(super) fn concat_error(&self, (ea, eb): (&Expr, &Expr), (a, b): (&Value, &Value)) -> Option<Fault> {
        let error = |v: &Value| matches!(v, Value::Error(_));
        if !error(a) && !error(b) {
            return None;
        }
        let shown = self.quoted_source(ea.span.start, eb.span.end, "the operation");
        let (code, name) = TYPE_MISMATCH;
        let mut fault =
            self.fault_at(self.expr_span(ea), format!("{name} (run-time error {code}): {shown} joins an error value"));
        fault.code = code;
        Some(fault)
    }

    /// Type mismatch (run-time error 13) of an operator with an array operand (a several-cell
    /// `Range`'s value, a Variant holding an array): VBA's arithmetic, comparison and logical
    /// operators are defined on single values ([MS-VBAL] 5.6.9.3-5.6.9.8: numbers, dates,
    /// strings, Booleans, Empty, Null; "Type mismatch (Error 13)": "An object was passed to a
    /// procedure that is expecting a single property or value"), where a formula's `+` works
    /// item by item. So `Range("A1:A2") < -100` fails, as it does in Excel, instead of giving
    /// an array whose first item an `If` would then read.
    /// The fault is parked here, so the caller's frame on every operator holds no `Fault`
    /// (tests/vba_errors.rs: 100 nested calls in a 2 MB thread).
    #[inline(never)]
    pub(super) fn refused_array_operand(&self, op: BinOp, (ea, eb): (&Expr, &Expr), (a, b): (&Value, &Value)) -> bool {
        let array = |v: &Value| matches!(v, Value::Array(_));
        if matches!(op, BinOp::Range | BinOp::Intersect | BinOp::Union) || !array(a) && !array(b) {
            return false;
        }
        let shown = self.quoted_source(ea.span.start, eb.span.end, "the operation");
        let (code, name) = TYPE_MISMATCH;
        let at = self.expr_span(if array(a) { ea } else { eb });
        let mut fault = self.fault_at(at, format!("{name} (run-time error {code}): {shown} has an array operand"));
        fault.code = code;
        self.park(fault);
        true
    }

    /// Type mismatch (run-time error 13) of `-operand` on an array (its `result` an array):
    /// negation is defined on single values as the binary operators are ([MS-VBAL] 5.6.9.3.1;
    /// see [`Interp::refused_array_operand`]). The fault is parked here, out of the caller's
    /// frame.
    #[inline(never)]
    pub(super) fn refused_array_negation(&self, operand: &Expr, result: &Value) -> bool {
        if !matches!(result, Value::Array(_)) {
            return false;
        }
        let shown = self.quoted_source(operand.span.start, operand.span.end, "the operand");
        let (code, name) = TYPE_MISMATCH;
        let mut fault =
            self.fault_at(self.expr_span(operand), format!("{name} (run-time error {code}): -{shown} is an array"));
        fault.code = code;
        self.park(fault);
        true
    }

    /// Type mismatch (run-time error 13) of `-operand`, which gave the error value `result`:
    /// the operand was a text that is no number or an error value ([MS-VBAL] 5.6.9.3.1, the
    /// operand is let-coerced to a number).
    pub(super) fn negation_mismatch(&self, operand: &Expr, result: &Value) -> Option<Fault> {
        let Value::Error(_) = result else { return None };
        let shown = self.quoted_source(operand.span.start, operand.span.end, "the operand");
        let (code, name) = TYPE_MISMATCH;
        let mut fault =
            self.fault_at(self.expr_span(operand), format!("{name} (run-time error {code}): -{shown} is no number"));
        fault.code = code;
        Some(fault)
    }

    /// `Option Compare Text` is in force in the module whose code is running ([MS-VBAL]
    /// 5.2.1.4: the directive applies to its own module).
    pub(super) fn text_compare(&self) -> bool {
        self.running_options().text_compare
    }

    /// The lower bound of an array dimensioned without one in the module whose code is
    /// running: its `Option Base` ([MS-VBAL] 5.2.1.2), not another module's.
    pub(super) fn option_base(&self) -> i64 {
        self.running_options().base
    }

    /// The order of two values where VBA's differs from a formula's ([MS-VBAL] 5.6.9.5):
    /// texts (and Empty, which is "" against a text) under `Option Compare`; numbers exactly,
    /// as Doubles compare (`0.1 + 0.2 = 0.3` is False), not to a cell's 15 digits; a Boolean
    /// as the number it is (True -1, False 0) against a number or a Boolean; `None` where the
    /// formula's order holds (a Variant text against a Variant number, the number first).
    pub(super) fn vba_order(&self, a: &Value, b: &Value) -> Option<Ordering> {
        let text_compare = self.text_compare();
        let exact = |x: f64, y: f64| Some(x.partial_cmp(&y).unwrap_or(Ordering::Equal));
        match (a, b) {
            (Value::Number(x), Value::Number(y)) => exact(*x, *y),
            (Value::Bool(p), Value::Number(y)) => exact(boolean_number(*p), *y),
            (Value::Number(x), Value::Bool(q)) => exact(*x, boolean_number(*q)),
            (Value::Bool(p), Value::Bool(q)) => exact(boolean_number(*p), boolean_number(*q)),
            (Value::Text(x), Value::Text(y)) => Some(text_order(x, y, text_compare)),
            (Value::Text(x), Value::Blank) => Some(text_order(x, "", text_compare)),
            (Value::Blank, Value::Text(y)) => Some(text_order("", y, text_compare)),
            _ => None,
        }
    }

    /// `a Like b` where VBA's differs from the formula's: under `Option Compare Text`, and
    /// for an operand whose type writes it otherwise than a Double, let-coerced to String as
    /// its type writes it ([MS-VBAL] 5.6.9.5.7 takes both as Strings, [`Interp::let_text`]:
    /// `CSng(1 / 3) Like "0.3333333"` is True).
    #[inline(never)]
    fn vba_like(&self, (ea, eb): (&Expr, &Expr), (a, b): (&Value, &Value)) -> Option<Result<Value, Fault>> {
        let (ta, tb) = (self.let_text(ea, a), self.let_text(eb, b));
        if ta.is_none() && tb.is_none() {
            return self.text_compare().then(|| Ok(like_ignoring_case(a, b)));
        }
        let (a, b) = (ta.map_or_else(|| a.clone(), Value::text), tb.map_or_else(|| b.clone(), Value::text));
        Some(Ok(match self.text_compare() {
            true => like_ignoring_case(&a, &b),
            false => like(&a, &b),
        }))
    }

    /// The result of the relational operator or `Like` `op` on `values`, the values of
    /// `operands`, where VBA's differs from the formula's; `None` where it does not. A text
    /// against a number ("Comparison operators" in the Office VBA reference): a declared
    /// String against a Variant number compares as texts; against a number of a numeric
    /// type the text is made a Double (Type mismatch when it is no number); two Variants
    /// put the number (a Boolean too) first.
    pub(super) fn vba_comparison(
        &self,
        op: BinOp,
        (ea, eb): (&Expr, &Expr),
        (a, b): (&Value, &Value),
    ) -> Option<Result<Value, Fault>> {
        if op == BinOp::Like {
            return self.vba_like((ea, eb), (a, b));
        }
        if !relational(op) {
            return None;
        }
        if let Some(ord) = self.vba_order(a, b) {
            return Some(Ok(Value::Bool(comparison_holds(op, ord))));
        }
        // A Boolean against a text compares as its number, a String "True" or "False" as
        // the Boolean it converts to ("CBool", [MS-VBAL] 5.5.1.2.2).
        let (text, number, text_expr, number_expr) = match (a, b) {
            (Value::Text(t), Value::Number(n)) => (t, *n, ea, eb),
            (Value::Number(n), Value::Text(t)) => (t, *n, eb, ea),
            (Value::Text(t), Value::Bool(p)) => (t, boolean_number(*p), ea, eb),
            (Value::Bool(p), Value::Text(t)) => (t, boolean_number(*p), eb, ea),
            _ => return None,
        };
        let boolean = matches!(a, Value::Bool(_)) || matches!(b, Value::Bool(_));
        let text_variant = self.declared_type(text_expr) == Declared::Variant;
        match (text_variant, self.declared_type(number_expr) == Declared::Variant) {
            // Two Variants: the number is less ("Comparison operators": "one expression is
            // numeric and the other is a string: the numeric expression is less than the
            // string expression", the numeric types Byte, Boolean, Integer …), a Boolean too,
            // where a formula puts TRUE after every text.
            (true, true) => {
                let ord = if matches!(a, Value::Text(_)) { Ordering::Greater } else { Ordering::Less };
                return Some(Ok(Value::Bool(comparison_holds(op, ord))));
            }
            // A String against a Variant holding a number: the number's text is compared,
            // as its type writes it (a Single's seven digits, a Date's date: [`Interp::let_text`]).
            (false, true) => {
                let shown = if boolean {
                    vba_text(&Value::Bool(number != 0.0)).ok()?
                } else {
                    let value = Value::Number(number);
                    match self.let_text(number_expr, &value) {
                        Some(text) => text.into(),
                        None => vba_text(&value).ok()?,
                    }
                };
                let ord = if matches!(a, Value::Text(_)) {
                    text_order(text, &shown, self.text_compare())
                } else {
                    text_order(&shown, text, self.text_compare())
                };
                return Some(Ok(Value::Bool(comparison_holds(op, ord))));
            }
            _ => {}
        }
        let spelled_boolean = match text.trim() {
            t if boolean && t.eq_ignore_ascii_case("true") => Some(-1.0),
            t if boolean && t.eq_ignore_ascii_case("false") => Some(0.0),
            _ => None,
        };
        let Some(converted) =
            spelled_boolean.or_else(|| to_number(&Value::Text(text.clone()), DateSystem::From1900).ok())
        else {
            let (code, name) = TYPE_MISMATCH;
            let mut fault = self.fault_at(
                self.expr_span(text_expr),
                format!("{name} (run-time error {code}): \"{text}\" is compared with a number and is no number"),
            );
            fault.code = code;
            return Some(Err(fault));
        };
        let (x, y) = if matches!(a, Value::Text(_)) { (converted, number) } else { (number, converted) };
        Some(Ok(Value::Bool(comparison_holds(op, x.partial_cmp(&y).unwrap_or(Ordering::Equal)))))
    }
}

/// A Boolean as a number ([MS-VBAL] 5.5.1.2.1: True is -1, False 0).
fn boolean_number(b: bool) -> f64 {
    if b {
        -1.0
    } else {
        0.0
    }
}

/// `text Like pattern` under `Option Compare Text`: case does not count ("Like operator").
fn like_ignoring_case(text: &Value, pattern: &Value) -> Value {
    let folded = |v: &Value| match v {
        Value::Text(t) => Value::text(t.to_lowercase()),
        other => other.clone(),
    };
    match like(&folded(text), &folded(pattern)) {
        Value::Error(XlError::Value) => like(text, pattern),
        v => v,
    }
}
