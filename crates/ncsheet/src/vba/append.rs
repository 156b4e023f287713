//! `s = s & x`: appending to a text variable in place. A value's text is an `Rc<str>`, so
//! joining made a new text and copied the whole of `s` each time: a loop of 200,000 such
//! appends copied 2·10^10 bytes. Here the variable keeps its text in a buffer that doubles as
//! it grows (`value.rs`, `Slot::append`), so a loop of appends is linear, and the macro
//! string limit (`--max-string`) still stops it with its message.

use std::rc::Rc;

use crate::eval::{Operand, Value};
use crate::formula::ast::{BinOp, Expr, ExprKind};

use super::ast::{Span, Ty};
use super::interp::{Interp, Run};
use super::value::{array_var, Var};

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
            return self.set_var(name, array_var(v, self.option_base()), span).map(|()| true);
        };
        // The buffer is shared no more: the append below writes to it in place.
        drop(before);
        let piece_units = self.admit_piece(&mut ctx, &piece, units, span)?;
        self.with_slot(name, |s| {
            s.append(&piece, piece_units);
            s.holds = super::typing::Declared::Variant;
        });
        Ok(true)
    }
}

/// The item read by the first operand of `a(…) & x & …` when it names the array `name`: its
/// indexes and the operands joined to it, as [`appended`] gives them.
type ItemAppend<'e> = (&'e [Expr], Vec<(&'e Expr, &'e Expr)>);

impl Interp<'_, '_> {
    /// `a(i) = a(i) & x & …` appends to the item's text in place, as `s = s & …` does to a
    /// variable's (`Slot::item_units`): only when both `a(i)` name the same item by indexes
    /// that only read variables, the array holds values of a text type (a String or a
    /// Variant) and the item a text; `false` runs the statement as written. The operands
    /// after `a(i)` are evaluated first; should they change the array or an index, the
    /// item's text from before is joined to them and stored as the statement does.
    pub(super) fn append_item_in_place(&self, name: &Rc<str>, index: &[Expr], value: &Expr, span: Span) -> Run<bool> {
        let Some((read, pieces)) = self.item_appended(name, value) else { return Ok(false) };
        if read.len() != index.len() || !read.iter().chain(index).all(|e| self.reads_variables_only(e)) {
            return Ok(false);
        }
        let (Some(at), Some(target)) = (self.plain_indexes(read), self.plain_indexes(index)) else { return Ok(false) };
        if at != target {
            return Ok(false);
        }
        let position = |s: &mut super::value::Slot| s.with_array(|a| self.element_at(a, &at).ok()).flatten();
        let Some(k) = self.with_slot(name, position).flatten() else { return Ok(false) };
        // Made the array's own first when it is shared (`b = a`), as `a(i) = v` does.
        let shared = |s: &mut super::value::Slot| match s.growing_item() {
            Some(_) => Some(0),
            None => s.with_array(|a| match Rc::strong_count(&a.data) {
                1 => 0,
                _ => super::budget::copy_bytes(&a.data),
            }),
        };
        let copied = self.with_slot(name, shared).flatten().unwrap_or(0);
        let ready = |s: &mut super::value::Slot| {
            let typed = matches!(s.ty, None | Some(Ty::Variant | Ty::String));
            if !typed || s.constant {
                return None;
            }
            let units = s.item_units(k)?;
            Some((units, s.written(), s.growing_item()?.1))
        };
        if self.with_slot(name, |s| s.growing_item().map(|g| g.0)).flatten() != Some(k) {
            self.charge(copied, span)?;
        }
        let Some((units, written, before)) = self.with_slot(name, ready).flatten() else { return Ok(false) };
        let mut ctx = self.ctx();
        let values: Vec<Value> = pieces.iter().map(|(_, right)| ctx.eval(right)).collect();
        let join = |ctx: &mut crate::eval::Ctx, start: Value| {
            let joined = pieces.iter().zip(&values);
            joined.fold(start, |acc, (&operands, b)| ctx.join_values(operands, acc, b.clone()))
        };
        let unchanged = self.with_slot(name, |s| s.written()) == Some(written)
            && self.pending.borrow().is_none()
            && self.plain_indexes(index) == Some(target);
        let joined_text = match join(&mut ctx, Value::text("")) {
            Value::Text(piece) if unchanged => Some(piece),
            _ => None,
        };
        let Some(piece) = joined_text else {
            // Joined to the item's text from before and stored as `a(i) = v` stores.
            let v = join(&mut ctx, Value::text(before.as_str()));
            self.take_pending()?;
            return self.set_element_holding(name, index, v, super::typing::Declared::Variant, span).map(|()| true);
        };
        drop(before);
        let piece_units = self.admit_piece(&mut ctx, &piece, units, span)?;
        self.with_slot(name, |s| s.append(&piece, piece_units));
        Ok(true)
    }

    /// The UTF-16 units of `piece`, about to be appended to a text of `units`: past the
    /// text limit the run stops (at the pending error taken here), and its bytes are
    /// charged to the memory budget.
    fn admit_piece(&self, ctx: &mut crate::eval::Ctx, piece: &str, units: usize, span: Span) -> Run<usize> {
        let piece_units = piece.encode_utf16().count();
        if units.saturating_add(piece_units) > ctx.text_limit() {
            ctx.text_over_limit();
        }
        self.take_pending()?;
        self.charge(piece.len() as u64, span)?;
        Ok(piece_units)
    }

    /// The indexes and operands of `value` when it is `name(…) & x & …`.
    fn item_appended<'e>(&'e self, name: &str, value: &'e Expr) -> Option<ItemAppend<'e>> {
        let mut pieces = Vec::new();
        let mut e = value;
        while let ExprKind::Binary(BinOp::Concat, left, right) = &e.kind {
            pieces.push((&**left, &**right));
            e = left;
        }
        let ExprKind::Host(id) = &e.kind else { return None };
        let super::ast::Node::Element { var, index, .. } = &self.module.nodes[*id as usize] else { return None };
        if pieces.is_empty() || !var.eq_ignore_ascii_case(name) {
            return None;
        }
        pieces.reverse();
        Some((index, pieces))
    }

    /// The whole-number indexes (rounded as VBA rounds them) that `index`, reading variables
    /// only, gives; `None` for anything else, which the statement as written then reports
    /// (a failure evaluating them is let go: it has no effect and recurs there).
    fn plain_indexes(&self, index: &[Expr]) -> Option<Vec<i64>> {
        let mut ctx = self.ctx();
        let mut at = Vec::with_capacity(index.len());
        for e in index {
            let v = ctx.eval(e);
            if self.pending.borrow_mut().take().is_some() {
                return None;
            }
            match v {
                Value::Number(n) if (i32::MIN as f64..=i32::MAX as f64).contains(&n.round_ties_even()) => {
                    at.push(n.round_ties_even() as i64)
                }
                _ => return None,
            }
        }
        Some(at)
    }

    /// `a(i)` read from an array whose item grows in place (`append_item_in_place`), without
    /// putting the item's text back into the array: the item growing is a copy of its text,
    /// any other item as it is. `None` when `name` holds no such array.
    pub(super) fn growing_element(
        &self,
        ctx: &mut crate::eval::Ctx,
        name: &str,
        index: &[Expr],
        span: Span,
    ) -> Option<Run<Operand>> {
        self.with_slot(name, |s| s.growing_item().map(|_| ())).flatten()?;
        Some(self.read_growing_element(ctx, name, index, span))
    }

    fn read_growing_element(&self, ctx: &mut crate::eval::Ctx, name: &str, index: &[Expr], span: Span) -> Run<Operand> {
        let mut at = Vec::with_capacity(index.len());
        for e in index {
            let v = ctx.eval(e);
            self.take_pending()?;
            let n = self.number_of(&v, "the index").map_err(|m| self.fault_at(self.expr_span(e), m))?;
            at.push(n.round_ties_even() as i64);
        }
        let read = |s: &mut super::value::Slot| {
            let growing = s.growing_item();
            s.with_array(|a| {
                let k = self.element_at(a, &at)?;
                let item = match (growing, a.item(k)) {
                    (Some((g, text)), _) if g == k => Ok(Value::text(text.as_str())),
                    (_, Var::Obj(o)) => Err(o),
                    _ => Ok(a.data.data[k].clone()),
                };
                Ok((item, a.held(k)))
            })
        };
        let found = self.with_slot(name, read).flatten();
        let Some(found) = found else { return Err(self.fault_at(span, format!("{name} is not an array"))) };
        let (item, held) = found.map_err(|m: String| self.fault_at(span, format!("{name}: {m}")))?;
        self.gave.set(held);
        match item {
            Ok(v) => Ok(Operand::Value(v)),
            Err(object) => self.operand_of(object, span),
        }
    }
}
