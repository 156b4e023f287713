//! VBA's LongLong ("LongLong data type": a signed 64-bit integer, -9,223,372,036,854,775,808
//! to 9,223,372,036,854,775,807) kept exact beside the double the one evaluator computes
//! with. A double holds every whole number up to 2^53; past it the interpreter keeps the
//! 64-bit integer each LongLong literal, operation, variable, argument and Function result
//! gave, so that `+ - * \ Mod` and the comparisons are the integer's ([MS-VBAL] 5.6.9.3),
//! a result past the type is Overflow (run-time error 6), and CStr, Str, Format, Print and
//! `&` show its every digit. A cell given a LongLong takes its nearest double, as Excel's
//! cells hold numbers. `/` and `^` make Doubles of their operands, and a Double beside a
//! LongLong makes the operation a Double's: both are the evaluator's double arithmetic.
//!
//! Each kept integer is checked against the double the evaluator holds for the same value
//! before it is used: one that no longer stands for that double is not that value's.

use std::collections::HashMap;

use crate::eval::evaluator::comparison_holds;
use crate::eval::Value;
use crate::formula::ast::{BinOp, Expr, ExprKind, UnaryOp};

use super::ast::LONG_LONG_END;
use super::interp::{Fault, Interp};
use super::typing::{binary_type, Dec, Declared, Typing};
use super::value::Var;

/// 2^53: every whole number of a smaller size is exact in a double, and none is kept.
const EXACT_IN_DOUBLE: f64 = 9_007_199_254_740_992.0;

/// 10^15: a whole number below it shows every digit in a double's 15 significant digits; a
/// LongLong from it up is shown from its integer.
const SHOWN_IN_FULL: f64 = 1e15;

/// The LongLongs kept beside the doubles that stand for them.
#[derive(Debug, Default)]
pub(super) struct Exact {
    /// The last result of each operation, by the address of its first operand (of a
    /// negation, its operand's), as [`Interp::widened`] notes operations.
    ops: HashMap<usize, i64>,
    /// The last value of each node (a Function's call), by its number: indexed, so that
    /// forgetting one, at every evaluation of a node once any kept one, costs no hashing.
    nodes: Vec<Option<i64>>,
    /// What the Function that returned last gave, until its node takes it.
    gave: Option<i64>,
    /// The exact values the call being bound passes, by parameter position.
    args: ExactArgs,
    /// The branch each IIf call chose, by the address of its condition, with the double it
    /// gave: noted only past 2^53 ([`Interp::note_iif_branch`]).
    iif: HashMap<usize, (usize, f64)>,
    /// What the value assigned to an array item (`a(i) = value`) gave, until the item takes it.
    item: Option<i64>,
}

fn key(e: &Expr) -> usize {
    e as *const Expr as usize
}

/// Whether a double may stand for a whole number it does not hold exactly.
fn inexact(n: f64) -> bool {
    n.abs() >= EXACT_IN_DOUBLE
}

/// The LongLong a whole double within the type's range is.
fn whole(n: f64) -> Option<i64> {
    (n.fract() == 0.0 && (-LONG_LONG_END..LONG_LONG_END).contains(&n)).then_some(n as i64)
}

/// The digits of the LongLong the whole double `n` is, as a String takes a LongLong
/// ([MS-VBAL] 5.5.1.2.4: every digit, where a Double's text has fifteen); `None` for a
/// double that is no LongLong.
pub(super) fn long_long_digits(n: f64) -> Option<String> {
    whole(n).map(|k| k.to_string())
}

/// What a call's arguments hold beyond their doubles, by parameter position: a LongLong
/// past 2^53, a Decimal whose digits no double gives back (`typing/decimal.rs`).
#[derive(Debug, Default)]
pub(super) struct ExactArgs {
    long_longs: Vec<(usize, i64)>,
    decimals: Vec<(usize, Dec)>,
}

impl ExactArgs {
    fn is_empty(&self) -> bool {
        self.long_longs.is_empty() && self.decimals.is_empty()
    }
}

/// The LongLong noted for the argument at parameter position `index`.
fn noted_for(noted: &ExactArgs, index: usize) -> Option<i64> {
    noted.long_longs.iter().find(|(i, _)| *i == index).map(|&(_, k)| k)
}

/// The argument at parameter position `index` as a LongLong parameter of type `ty` takes
/// it, where a LongLong was noted for it: already of the type and in its range, though its
/// nearest double may not be (2^63 - 512 and up round to 2^63, one past the top). A String
/// parameter takes a LongLong's or a Decimal's every digit ([MS-VBAL] 5.5.1.2.4, Let-coercion
/// to String), not its double's (9007199254740993 was "9007199254740992"). `None` for any
/// other parameter or argument, which converts as usual.
pub(super) fn long_long_param(noted: &ExactArgs, index: usize, ty: Option<&super::ast::Ty>) -> Option<Var> {
    if matches!(ty, Some(super::ast::Ty::String)) {
        let decimal = || noted.decimals.iter().find(|(i, _)| *i == index).map(|&(_, d)| d.text());
        let text = noted_for(noted, index).map(|k| k.to_string()).or_else(decimal)?;
        return Some(Var::Value(Value::text(text)));
    }
    if Declared::of_ty(ty) != Declared::LongLong {
        return None;
    }
    noted_for(noted, index).map(|k| Var::Value(Value::Number(k as f64)))
}

/// The LongLong a literal with the `^` type character writes ([MS-VBAL] 3.3.2):
/// `9007199254740993^`, or `&H…^` and `&O…^` as their 64 bits, the top one the sign.
fn literal(text: &str) -> Option<i64> {
    let digits = text.trim().strip_suffix('^')?;
    let Some(radix) = digits.strip_prefix('&') else { return digits.parse().ok() };
    let (digits, base) = match radix.as_bytes().first() {
        Some(b'h' | b'H') => (&radix[1..], 16),
        Some(b'o' | b'O') => (&radix[1..], 8),
        _ => (radix, 8),
    };
    u64::from_str_radix(digits, base).ok().map(|n| n as i64)
}

impl Interp<'_, '_> {
    /// The whole number `v`, the value of `e`, stands for: the LongLong kept for it where
    /// its double is past 2^53, else the double's own; `None` for no whole number.
    pub(super) fn exact_whole(&self, e: &Expr, v: &Value) -> Option<i64> {
        let Value::Number(n) = *v else { return None };
        if !inexact(n) {
            return whole(n);
        }
        let kept = match &e.kind {
            ExprKind::Paren(inner) | ExprKind::Unary(UnaryOp::Plus, inner) => return self.exact_whole(inner, v),
            ExprKind::Number(_) => literal(self.source_between(e.span.start, e.span.end)),
            ExprKind::Name(name) => self.with_slot(name, |s| s.exact()).flatten(),
            ExprKind::Binary(_, first, _) | ExprKind::Unary(UnaryOp::Neg, first) => {
                self.exact.borrow().ops.get(&key(first)).copied()
            }
            ExprKind::Host(id) => self.exact.borrow().nodes.get(*id as usize).copied().flatten(),
            ExprKind::Call(id, args) => self.exact_call(crate::eval::functions::spec(*id).name, args, n),
            _ => None,
        };
        kept.filter(|&k| k as f64 == n).or_else(|| whole(n))
    }

    /// The LongLong kept for `e`'s value `n` past 2^53, `None` where none is: the value is
    /// then its double's.
    fn kept_whole(&self, e: &Expr, n: f64) -> Option<i64> {
        self.exact_whole(e, &Value::Number(n)).filter(|&k| whole(n) != Some(k))
    }

    /// The LongLong a call of a VBA function gave as `n`, from its LongLong argument's
    /// integer: CLngLng's ("Type conversion functions"), Int's and Fix's (a whole number is
    /// its own, "Int, Fix functions"), Abs's ("Abs function": the same type), and the branch
    /// IIf chose ("IIf function": a Variant holding that branch's value). `None` for any
    /// other function, whose result is its double.
    fn exact_call(&self, name: &str, args: &[Expr], n: f64) -> Option<i64> {
        let arg = args.first()?;
        match name {
            "VBA.CLNGLNG" => match &arg.kind {
                ExprKind::Text(t) => t.trim().parse().ok(),
                _ => self.exact_whole(arg, &Value::Number(n)),
            },
            "VBA.INT" | "VBA.FIX" => self.exact_whole(arg, &Value::Number(n)),
            // The argument was `-n` or `n`; only the integer kept for the one it was is kept.
            "VBA.ABS" => self.kept_whole(arg, -n).or_else(|| self.kept_whole(arg, n)).and_then(i64::checked_abs),
            "VBA.IIF" => {
                let branch = self.iif_branch(args, n)?;
                self.exact_whole(branch, &Value::Number(n))
            }
            _ => None,
        }
    }

    /// The branch of the IIf call with arguments `args` that gave the value `n`, where it is
    /// past 2^53 and the call told which ([`Interp::note_iif_branch`]).
    fn iif_branch<'e>(&self, args: &'e [Expr], n: f64) -> Option<&'e Expr> {
        let (index, given) = *self.exact.borrow().iif.get(&key(args.first()?))?;
        (given.to_bits() == n.to_bits()).then(|| args.get(index)).flatten()
    }

    /// The branch the IIf call with arguments `args` chose last, where its value was past
    /// 2^53: its type is the call's (a Variant holding that branch's value). `None` for a
    /// call whose last value was below 2^53, or when no IIf gave one past it (one check).
    pub(super) fn iif_chosen<'e>(&self, args: &'e [Expr]) -> Option<&'e Expr> {
        let exact = self.exact.borrow();
        if exact.iif.is_empty() {
            return None;
        }
        let &(index, _) = exact.iif.get(&key(args.first()?))?;
        args.get(index)
    }

    /// Notes which branch (`index` into `args`) an IIf call chose, where its value is past
    /// 2^53 (its LongLong and type are that branch's), and forgets it when the call gives a
    /// smaller value. Costs nothing until an IIf gives a value past 2^53.
    pub(super) fn note_iif_branch(&self, args: &[Expr], index: usize, v: &Value) {
        let Some(first) = args.first() else { return };
        match v {
            Value::Number(n) if inexact(*n) => {
                self.exact.borrow_mut().iif.insert(key(first), (index, *n));
            }
            _ if !self.exact.borrow().iif.is_empty() => {
                self.exact.borrow_mut().iif.remove(&key(first));
            }
            _ => {}
        }
    }

    /// Refuses the LongLong `v`, the value of `e`, given to `place` (a Type's field, a
    /// Collection's or a Dictionary's item, an item reached through another item), where no
    /// double is its integer: such a place holds a double alone, and the nearest one is
    /// another number. Overflow (run-time error 6) naming the number, never the double in
    /// its stead; nothing to check below 2^53 or for a LongLong whose double is exact.
    pub(super) fn refuse_long_long_past_double(&self, e: &Expr, var: &Var, place: &str) -> Result<(), Fault> {
        let Var::Value(v @ Value::Number(n)) = var else { return Ok(()) };
        self.refuse_kept_decimal(e, v, place)?;
        let n = *n;
        if !inexact(n) {
            return Ok(());
        }
        let Some(k) = self.kept_long_long(e, v) else { return Ok(()) };
        if i128::from(k) == n as i128 {
            return Ok(());
        }
        let why = format!(
            "{place} cannot hold the LongLong {k} exactly: it keeps a double, and the nearest is {n:.0}; \
             ncsheet keeps a LongLong past 2^53 whole in a variable, an array item, a parameter, a constant \
             or a Function's result"
        );
        let mut fault = self.fault_at(self.expr_span(e), crate::eval::functions::vba::errors::message(6, why));
        fault.code = 6;
        Err(fault)
    }

    /// The LongLong `v`, the value of `e`, is when `e` is of that type and its double is
    /// not exact; `None` otherwise (the double is the value).
    fn kept_long_long(&self, e: &Expr, v: &Value) -> Option<i64> {
        match v {
            Value::Number(n) if inexact(*n) && self.value_type(e, v) == Declared::LongLong => self.exact_whole(e, v),
            _ => None,
        }
    }

    /// Forgets what the operation whose first operand is `first` gave: it is being computed
    /// again, on `numbers` (its operands and the evaluator's result). Only where one of them
    /// is past 2^53: a kept integer is read for a double past it alone, so a macro whose
    /// numbers stay below it (or came back below it) pays no table look-up per operation.
    pub(super) fn forget_exact(&self, first: &Expr, numbers: [&Value; 3]) {
        let past = numbers.iter().any(|v| matches!(v, Value::Number(n) if inexact(*n)));
        if past && !self.exact.borrow().ops.is_empty() {
            self.exact.borrow_mut().ops.remove(&key(first));
        }
    }

    /// `a op b` computed on 64-bit integers when its type is LongLong ([MS-VBAL] 5.6.9.3:
    /// two integral operands, one of them a LongLong) and a double would not hold it or an
    /// operand exactly; Overflow (run-time error 6) past the type. `\` truncates toward zero
    /// and `Mod`'s remainder has the dividend's sign (5.6.9.3.6, 5.6.9.3.7), their operands
    /// rounded to whole numbers half to even first. `None` where the double is exact, the
    /// type is another, or the operation divides by zero (error 11, raised as for any type).
    pub(super) fn long_long_arithmetic(
        &self,
        op: BinOp,
        (a, b): (&Expr, &Expr),
        (x, y): (&Value, &Value),
        result: &Value,
    ) -> Option<Result<Value, Fault>> {
        if !matches!(op, BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::IntDiv | BinOp::Mod) {
            return None;
        }
        let (Value::Number(n), Value::Number(p), Value::Number(q)) = (result, x, y) else { return None };
        if !inexact(*n) && !inexact(*p) && !inexact(*q) {
            return None;
        }
        let ty = self
            .widened_if_held(Typing::Held, a)
            .unwrap_or_else(|| binary_type(op, self.held_operand(a), self.held_operand(b)));
        if ty != Declared::LongLong {
            return None;
        }
        let dividing = matches!(op, BinOp::IntDiv | BinOp::Mod);
        let operand = |e: &Expr, v: &Value, d: f64| match self.exact_whole(e, v) {
            None if dividing => whole(d.round_ties_even()),
            exact => exact,
        };
        let (i, j) = (operand(a, x, *p)?, operand(b, y, *q)?);
        let exact = match op {
            BinOp::Add => i.checked_add(j),
            BinOp::Sub => i.checked_sub(j),
            BinOp::Mul => i.checked_mul(j),
            _ if j == 0 => return None,
            BinOp::IntDiv => i.checked_div(j),
            _ => Some(i.wrapping_rem(j)),
        };
        Some(match exact {
            Some(r) => {
                self.exact.borrow_mut().ops.insert(key(a), r);
                Ok(Value::Number(r as f64))
            }
            None => {
                let shown = self.quoted_source(a.span.start, b.span.end, "the operation");
                let exact = i128::from(i);
                let past = match op {
                    BinOp::Add => exact + i128::from(j),
                    BinOp::Sub => exact - i128::from(j),
                    BinOp::Mul => exact * i128::from(j),
                    _ => -exact,
                };
                Err(self.overflow_fault(
                    self.expr_span(a),
                    format!("{shown} overflows: its operands' types make it a LongLong (-2^63 to 2^63 - 1), which cannot hold {past}"),
                ))
            }
        })
    }

    /// `-operand` of a LongLong whose double is not exact, on its integer: the most negative
    /// LongLong has no positive (Overflow, run-time error 6, [MS-VBAL] 5.6.9.3.1).
    pub(super) fn long_long_negation(&self, operand: &Expr, result: &Value) -> Option<Result<Value, Fault>> {
        let Value::Number(n) = *result else { return None };
        if !inexact(n) || self.held_operand(operand) != Declared::LongLong {
            return None;
        }
        let i = self.exact_whole(operand, &Value::Number(-n))?;
        Some(match i.checked_neg() {
            Some(r) => {
                self.exact.borrow_mut().ops.insert(key(operand), r);
                Ok(Value::Number(r as f64))
            }
            None => {
                let shown = self.quoted_source(operand.span.start, operand.span.end, "the operand");
                Err(self.overflow_fault(
                    self.expr_span(operand),
                    format!("-{shown} overflows: a LongLong holds -2^63 to 2^63 - 1, not 2^63"),
                ))
            }
        })
    }

    /// `a op b` for a relational operator on two integral operands, one a LongLong past what a
    /// double holds exactly: their integers compared ([MS-VBAL] 5.6.9.5, the comparison is
    /// in the operands' effective value type). `None` for anything else.
    pub(super) fn long_long_comparison(
        &self,
        op: BinOp,
        (a, b): (&Expr, &Expr),
        (x, y): (&Value, &Value),
    ) -> Option<Value> {
        if !matches!(op, BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge) {
            return None;
        }
        let order = self.long_long_order((a, b), (x, y))?;
        Some(Value::Bool(comparison_holds(op, order)))
    }

    /// How `a`'s value `x` orders against `b`'s `y` when both are integral, one a LongLong past
    /// what a double holds exactly: on their integers. `None` for anything else (the doubles'
    /// order is the value's). Select Case compares with it as `=`, `<=` and `>=` do
    /// ([MS-VBAL] 5.4.2.10).
    pub(super) fn long_long_order(
        &self,
        (a, b): (&Expr, &Expr),
        (x, y): (&Value, &Value),
    ) -> Option<std::cmp::Ordering> {
        if let Some(order) = self.decimal_order((a, b), (x, y)) {
            return Some(order);
        }
        let (Value::Number(p), Value::Number(q)) = (x, y) else { return None };
        if !inexact(*p) && !inexact(*q) {
            return None;
        }
        let integral = |e: &Expr| {
            matches!(
                self.held_operand(e),
                Declared::Byte | Declared::Boolean | Declared::Integer | Declared::Long | Declared::LongLong
            )
        };
        if !integral(a) || !integral(b) {
            return None;
        }
        let (i, j) = (self.exact_whole(a, x)?, self.exact_whole(b, y)?);
        Some(i.cmp(&j))
    }

    /// The start, end and step of `For var = from To to Step step` as integers, where the
    /// counter is a LongLong and the start or the end is past what a double holds exactly:
    /// the counter then steps on its integer ([MS-VBAL] 5.4.2.3: it is assigned its value plus
    /// the step, a LongLong addition), where a double's `+ 1` would leave it where it was.
    /// `None` for any other loop, which counts in doubles.
    pub(super) fn long_long_for_bounds(
        &self,
        var: &str,
        (from, start): (&Expr, f64),
        (to, end): (&Expr, f64),
        step: Option<(&Expr, f64)>,
    ) -> Option<(i64, i64, i64)> {
        if !inexact(start) && !inexact(end) {
            return None;
        }
        let declared = self.with_slot(var, |s| Declared::of_ty(s.ty.as_ref()))?;
        let counter = match declared {
            Declared::Variant => self.value_type(from, &Value::Number(start)),
            other => other,
        };
        if counter != Declared::LongLong {
            return None;
        }
        let first = self.exact_whole(from, &Value::Number(start))?;
        let last = self.exact_whole(to, &Value::Number(end))?;
        let step = match step {
            Some((e, n)) => self.exact_whole(e, &Value::Number(n))?,
            None => 1,
        };
        Some((first, last, step))
    }

    /// The whole number the For counter `var` holds, its LongLong where it keeps one.
    pub(super) fn long_long_counter(&self, var: &str) -> Option<i64> {
        self.with_slot(var, |slot| match slot.var() {
            super::value::Var::Value(Value::Number(n)) => {
                slot.exact().filter(|&k| k as f64 == *n).or_else(|| whole(*n))
            }
            _ => None,
        })
        .flatten()
    }

    /// Sets the LongLong For counter `var` to `k`, its integer kept beside its double.
    pub(super) fn set_long_long_counter(&self, var: &str, k: i64) {
        self.with_slot(var, |slot| {
            slot.replace(super::value::Var::Value(Value::Number(k as f64)));
            slot.set_holds(Declared::LongLong);
            slot.set_exact(k);
        });
    }

    /// The digits a LongLong `v`, the value of `e`, shows as a String (CStr, Str, Format,
    /// Print, `&`, [MS-VBAL] 5.5.1.2.4: a number's decimal text): every one, where a
    /// double's 15 significant digits would round it or show an exponent; a Decimal's and a
    /// Currency's every digit too ("Decimal data type", `typing/decimal.rs`; "Currency data
    /// type", its integer of ten-thousandths), which Round rounds as they are written.
    /// `None` for any other value, shown as a double.
    pub(super) fn long_long_text(&self, e: &Expr, v: &Value) -> Option<String> {
        match v {
            Value::Number(n) if n.abs() >= SHOWN_IN_FULL && self.value_type(e, v) == Declared::LongLong => {
                self.exact_whole(e, v).map(|k| k.to_string())
            }
            _ => self.decimal_text(e, v).or_else(|| self.currency_text(e, v)),
        }
    }

    /// `a & b` with a LongLong operand shown in full ([`Interp::long_long_text`]).
    pub(super) fn concat_long_longs(&self, (a, b): (&Expr, &Expr), (x, y): (&Value, &Value)) -> Option<Value> {
        let (tx, ty) = (self.long_long_text(a, x), self.long_long_text(b, y));
        if tx.is_none() && ty.is_none() {
            return None;
        }
        let text = |kept: Option<String>, v: &Value| match (kept, v) {
            (Some(t), _) => Some(t),
            (None, Value::Null) => Some(String::new()),
            (None, v) => crate::eval::functions::vba::vba_text(v).ok().map(|t| t.to_string()),
        };
        Some(Value::text(format!("{}{}", text(tx, x)?, text(ty, y)?)))
    }

    /// `name = value` where `value` gave the LongLong `v` past what its double holds, for a
    /// variable declared LongLong or a Variant: the integer kept with its double, and the
    /// variable's type noted as `held`. `false` (nothing done) for any other assignment,
    /// which converts as usual.
    pub(super) fn assign_long_long(&self, name: &str, value: &Expr, v: &Value, held: Declared) -> bool {
        if held == Declared::Decimal && self.assign_decimal(name, value, v) {
            return true;
        }
        let Some(k) = self.kept_long_long(value, v) else { return false };
        self.with_slot(name, |slot| {
            let typed = matches!(Declared::of_ty(slot.ty.as_ref()), Declared::LongLong | Declared::Variant);
            if slot.constant || !typed || !matches!(slot.var(), super::value::Var::Value(_)) {
                return false;
            }
            slot.replace(super::value::Var::Value(Value::Number(k as f64)));
            slot.set_holds(held);
            slot.set_exact(k);
            true
        }) == Some(true)
    }

    /// Notes the LongLong past 2^53 that `value`, assigned to an array item, gave as `v`.
    pub(super) fn note_item_long_long(&self, value: &Expr, v: &Value) {
        let k = self.kept_long_long(value, v);
        if k.is_some() || self.exact.borrow().item.is_some() {
            self.exact.borrow_mut().item = k;
        }
    }

    /// The LongLong noted for the array item being assigned, forgotten for any later one.
    pub(super) fn take_item_long_long(&self) -> Option<i64> {
        let noted = self.exact.borrow().item.is_some();
        if noted {
            self.exact.borrow_mut().item.take()
        } else {
            None
        }
    }

    /// Notes in `noted` that the argument at parameter position `index`, the expression `e`,
    /// gave the LongLong `v` past what its double holds, or a Decimal whose digits its double
    /// does not give back, for the parameter it is bound to. The call keeps its own list
    /// until it is bound: an argument that calls a Function (`F(G(x), y)`) binds G's in between.
    pub(super) fn note_long_long_arg(&self, noted: &mut ExactArgs, index: usize, e: &Expr, v: &Value) {
        if let Some(d) = self.kept_decimal_of(e, v) {
            noted.decimals.push((index, d));
        }
        if let Some(k) = self.kept_long_long(e, v) {
            noted.long_longs.push((index, k));
        }
    }

    /// Hands the LongLongs a call's arguments gave to the binding of its parameters.
    pub(super) fn pass_long_long_args(&self, noted: ExactArgs) {
        if !noted.is_empty() || !self.exact.borrow().args.is_empty() {
            self.exact.borrow_mut().args = noted;
        }
    }

    /// The LongLongs handed to the parameters being bound, taken: no later call reads them.
    pub(super) fn take_long_long_args(&self) -> ExactArgs {
        if self.exact.borrow().args.is_empty() {
            return ExactArgs::default();
        }
        std::mem::take(&mut self.exact.borrow_mut().args)
    }

    /// The LongLong noted for the parameter at `index`, for its variable holding `var`
    /// (a LongLong or a Variant parameter: any other converted it); a Decimal for a Variant.
    pub(super) fn long_long_arg(&self, noted: &ExactArgs, index: usize, slot: &mut super::value::Slot) {
        if let Some(&(_, d)) = noted.decimals.iter().find(|(i, _)| *i == index) {
            self.bind_decimal(d, slot);
        }
        let Some(k) = noted_for(noted, index) else { return };
        let typed = matches!(Declared::of_ty(slot.ty.as_ref()), Declared::LongLong | Declared::Variant);
        if typed && matches!(slot.var(), Var::Value(Value::Number(n)) if *n == k as f64) {
            slot.set_exact(k);
        }
    }

    /// `Const name As LongLong = e` (or a Variant constant): the LongLong `e` gave kept with
    /// the constant's double, where that is not exact.
    pub(super) fn constant_long_long(&self, slot: &mut super::value::Slot, e: &Expr) {
        let super::value::Var::Value(v) = slot.var() else { return };
        let Some(k) = self.kept_long_long(e, v) else { return };
        let typed = matches!(Declared::of_ty(slot.ty.as_ref()), Declared::LongLong | Declared::Variant);
        if typed && matches!(v, Value::Number(n) if *n == k as f64) {
            slot.set_exact(k);
        }
    }

    /// Notes the LongLong the Function that is returning gave (its name's variable's).
    pub(super) fn returning_long_long(&self, k: Option<i64>) {
        self.exact.borrow_mut().gave = k;
    }

    /// Before the node `id` gives its value: what an earlier Function gave is not its.
    pub(super) fn forget_given_long_long(&self) {
        self.returning_decimal(None);
        if self.exact.borrow().gave.is_some() {
            self.exact.borrow_mut().gave = None;
        }
    }

    /// After the node `id` gave its value: the LongLong a Function gave, kept for the node.
    pub(super) fn note_node_long_long(&self, id: u32) {
        self.note_node_decimal(id);
        let mut exact = self.exact.borrow_mut();
        let id = id as usize;
        match exact.gave.take() {
            Some(k) => {
                if exact.nodes.len() <= id {
                    exact.nodes.resize(id + 1, None);
                }
                exact.nodes[id] = Some(k);
            }
            None => {
                if let Some(kept) = exact.nodes.get_mut(id) {
                    *kept = None;
                }
            }
        }
    }

    /// The text Debug.Print shows for a LongLong in full, its sign's room and trailing
    /// space as for any number ("Print # statement").
    pub(super) fn printed_long_long(&self, e: &Expr, v: &Value) -> Option<String> {
        let text = self.long_long_text(e, v)?;
        Some(if text.starts_with('-') { format!("{text} ") } else { format!(" {text} ") })
    }
}
