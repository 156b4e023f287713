//! `s = s & x`: appending to a text variable in place. A value's text is an `Rc<str>`, so
//! joining made a new text and copied the whole of `s` each time: a loop of 200,000 such
//! appends copied 2·10^10 bytes. Here the variable keeps its text in a buffer that doubles as
//! it grows (`value.rs`, `Slot::append`), so a loop of appends is linear, and the macro
//! string limit (`--max-string`) still stops it with its message.

use std::rc::Rc;

use crate::eval::Value;
use crate::formula::ast::{BinOp, Expr, ExprKind};

use super::ast::{Span, Ty};
use super::interp::{Interp, Run};
use super::value::array_var;

/// The operands of `&` a statement `name = name & a & b …` joins to the variable, each with
/// the left operand it is joined to (for a Date's text, `Host::arithmetic`), in the order
/// they are evaluated; `None` for any other expression.
fn appended<'e>(name: &str, value: &'e Expr) -> Option<Vec<(&'e Expr, &'e Expr)>> {
    let mut pieces = Vec::new();
    let mut e = value;
    while let ExprKind::Binary(BinOp::Concat, left, right) = &e.kind {
        pieces.push((&**left, &**right));
        e = left;
    }
    let ExprKind::Name(first) = &e.kind else { return None };
    if pieces.is_empty() || !first.eq_ignore_ascii_case(name) {
        return None;
    }
    pieces.reverse();
    Some(pieces)
}

impl Interp<'_, '_> {
    /// `Mid(s, start[, length]) = text` (the Mid statement, which the parser makes
    /// `s = VBA.MIDSTATEMENT(s, start, length, text)`) done in the buffer of an ASCII text
    /// growing in place: the statement made the whole text anew, so a loop replacing one
    /// character at a time copied it at every turn. Only when the arguments run no macro code
    /// (they are evaluated again should the statement run as written) and are a whole start,
    /// a whole length of 0 or more or none, and a text; `false` runs the statement as written.
    pub(super) fn mid_in_place(&self, name: &Rc<str>, value: &Expr) -> Run<bool> {
        let ExprKind::Call(id, args) = &value.kind else { return Ok(false) };
        if crate::eval::functions::spec(*id).name != "VBA.MIDSTATEMENT" {
            return Ok(false);
        }
        let [Expr { kind: ExprKind::Name(var), .. }, start, length, with] = args.as_slice() else { return Ok(false) };
        if !var.eq_ignore_ascii_case(name) || ![start, length, with].iter().all(|e| self.reads_variables_only(e)) {
            return Ok(false);
        }
        let mut ctx = self.ctx();
        let (Value::Number(start), Value::Text(with)) = (ctx.eval(start), ctx.eval(with)) else { return Ok(false) };
        let length = match &length.kind {
            ExprKind::Missing => None,
            _ => match ctx.eval(length) {
                Value::Number(l) if l >= 0.0 && l.fract() == 0.0 => Some(l.min(u32::MAX as f64) as usize),
                _ => return Ok(false),
            },
        };
        if start < 1.0 || start.fract() != 0.0 || start > u32::MAX as f64 {
            return Ok(false);
        }
        let replace = |s: &mut super::value::Slot| {
            let typed = matches!(s.ty, None | Some(Ty::Variant | Ty::String));
            typed && !s.constant && s.text_units().is_some() && s.replace_ascii(start as usize - 1, length, &with)
        };
        Ok(self.with_slot(name, replace) == Some(true))
    }

    /// Whether `e` only reads variables and calls the library's functions that give the same
    /// value when called again: no procedure of the macro's, no member path (a Property, a
    /// cell), no name that is not a variable (a Function called without parentheses), no
    /// volatile function (`Rnd` would advance twice should the statement run as written).
    fn reads_variables_only(&self, e: &Expr) -> bool {
        let mut plain = true;
        e.visit(&mut |e| match &e.kind {
            ExprKind::Host(_) => plain = false,
            ExprKind::Call(id, _) if crate::eval::functions::spec(*id).volatile => plain = false,
            ExprKind::Name(n) => plain &= self.with_slot(n, |_| ()).is_some(),
            _ => {}
        });
        plain
    }

    /// Appends in place when `value` is `name & …` and `name` is a variable holding a text
    /// (a String or a Variant); `false` when the statement is to be run as any other.
    ///
    /// `s & a & b …` reads `s` first; here `a`, `b` … are evaluated first (a Function, a
    /// Property, `Cells(i, 1)`), with the text of `s` kept shared, not copied. Should they
    /// change `s` (a module variable or a class's field a Function writes, an argument passed
    /// ByRef), the text `s` held before is joined to them and assigned as the statement does;
    /// else they are appended to the buffer in place.
    pub(super) fn append_in_place(&self, name: &Rc<str>, value: &Expr, span: Span) -> Run<bool> {
        let Some(pieces) = appended(name, value) else { return Ok(false) };
        let ready = |s: &mut super::value::Slot| {
            let typed = matches!(s.ty, None | Some(Ty::Variant | Ty::String));
            if typed && !s.constant {
                let units = s.text_units()?;
                Some((units, s.written(), s.growing_text()))
            } else {
                None
            }
        };
        let Some((units, written, before)) = self.with_slot(name, ready).flatten() else { return Ok(false) };
        let mut ctx = self.ctx();
        let values: Vec<Value> = pieces.iter().map(|(_, right)| ctx.eval(right)).collect();
        // What `"" & a & b …` makes is what `s & a & b …` adds to `s`, as long as each
        // step is a text: a Null is "", a number or a Date is its text in both.
        let join = |ctx: &mut crate::eval::Ctx, start: Value| {
            let joined = pieces.iter().zip(&values);
            joined.fold(start, |acc, (&operands, b)| ctx.join_values(operands, acc, b.clone()))
        };
        let unchanged = self.with_slot(name, |s| s.written()) == Some(written);
        let joined_text = match join(&mut ctx, Value::text("")) {
            Value::Text(piece) if unchanged => Some(piece),
            _ => None,
        };
        let Some(piece) = joined_text else {
            // The right side changed `s`, or made an error or an array: joined to the text
            // `s` held before, as the statement does.
            let start = before.map_or(Value::Blank, |text| Value::text(text.as_str()));
            let v = join(&mut ctx, start);
            self.take_pending()?;
            return self.set_var(name, array_var(v, self.module.base), span).map(|()| true);
        };
        // The buffer is shared no more: the append below writes to it in place.
        drop(before);
        let piece_units = piece.encode_utf16().count();
        if units.saturating_add(piece_units) > ctx.text_limit() {
            ctx.text_over_limit();
        }
        self.take_pending()?;
        self.charge(piece.len() as u64, span)?;
        self.with_slot(name, |s| {
            s.append(&piece, piece_units);
            s.holds = super::typing::Declared::Variant;
        });
        Ok(true)
    }
}
