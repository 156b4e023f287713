//! `s = s & x`: appending to a text variable in place. A value's text is an `Rc<str>`, so
//! joining made a new text and copied the whole of `s` each time: a loop of 200,000 such
//! appends copied 2·10^10 bytes. Here the variable keeps its text in a buffer that doubles as
//! it grows (`value.rs`, `Slot::append`), so a loop of appends is linear, and the macro
//! string limit (`--max-string`) still stops it with its message.

use std::rc::Rc;

use crate::eval::Value;
use crate::formula::ast::{BinOp, Expr, ExprKind};

use super::ast::{Node, Span, Ty};
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
    /// Appends in place when `value` is `name & …` and `name` is a variable holding a text
    /// (a String or a Variant); `false` when the statement is to be run as any other.
    pub(super) fn append_in_place(&self, name: &Rc<str>, value: &Expr, span: Span) -> Run<bool> {
        let Some(pieces) = appended(name, value) else { return Ok(false) };
        if !self.unchanged_by(name, &pieces) {
            return Ok(false);
        }
        let plain_text = |s: &mut super::value::Slot| {
            let typed = matches!(s.ty, None | Some(Ty::Variant | Ty::String));
            if typed && !s.constant {
                s.text_units()
            } else {
                None
            }
        };
        let Some(units) = self.with_slot(name, plain_text).flatten() else { return Ok(false) };
        let mut ctx = self.ctx();
        let values: Vec<Value> = pieces.iter().map(|(_, right)| ctx.eval(right)).collect();
        // What `"" & a & b …` makes is what `s & a & b …` adds to `s`, as long as each
        // step is a text: a Null is "", a number or a Date is its text in both.
        let join = |ctx: &mut crate::eval::Ctx, start: Value| {
            let joined = pieces.iter().zip(&values);
            joined.fold(start, |acc, (&operands, b)| ctx.join_values(operands, acc, b.clone()))
        };
        let Value::Text(piece) = join(&mut ctx, Value::text("")) else {
            // An error, an array: joined to the variable's own value as the statement does.
            let own = self.with_slot(name, |s| s.var().clone());
            let start = match own {
                Some(super::value::Var::Value(v)) => v,
                _ => Value::Blank,
            };
            let v = join(&mut ctx, start);
            self.take_pending()?;
            return self.set_var(name, array_var(v, self.module.base), span).map(|()| true);
        };
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

    /// Whether evaluating the right operands of `pieces` leaves the variable `name` as it
    /// was: `s & a & b …` reads `s` first, and here `a`, `b` … are evaluated before `s` is
    /// appended to. So either they run none of the macro's procedures, or `name` is a
    /// variable of the running procedure that none of them names: a procedure they call
    /// cannot reach it then (it has its own variables, and a ByRef argument is a name), so
    /// `s = s & Cells(i, 1).Value`, `s = s & f(x)` and `s = s & d(k)` append in place too.
    fn unchanged_by(&self, name: &str, pieces: &[(&Expr, &Expr)]) -> bool {
        if pieces.iter().all(|(_, right)| self.reads_only(right)) {
            return true;
        }
        let local = self.frames.borrow().last().is_some_and(|f| f.vars.get(name).is_some());
        local && !pieces.iter().any(|(_, right)| self.names(right, name))
    }

    /// Whether `e` names the variable `name` anywhere (an argument of a call, an index, a
    /// member path's link).
    fn names(&self, e: &Expr, name: &str) -> bool {
        let mut found = false;
        e.visit(&mut |e| match &e.kind {
            ExprKind::Name(n) => found |= n.eq_ignore_ascii_case(name),
            ExprKind::Host(id) => found |= self.node_names(*id, name),
            _ => {}
        });
        found
    }

    fn node_names(&self, id: u32, name: &str) -> bool {
        let any = |es: &[Expr]| es.iter().any(|e| self.names(e, name));
        let args = |args: &[super::ast::Arg]| args.iter().any(|a| self.names(&a.value, name));
        match &self.module.nodes[id as usize] {
            Node::Call { args: a, .. } => args(a),
            Node::Path(path) => {
                path.links.iter().any(|l| l.name.eq_ignore_ascii_case(name) || l.args.as_deref().is_some_and(args))
            }
            Node::Element { var, index, .. } => var.eq_ignore_ascii_case(name) || any(index),
            Node::Bound { dim, .. } => dim.as_ref().is_some_and(|d| self.names(d, name)),
            Node::Is { object, other, .. } => {
                self.names(object, name) || other.as_ref().is_some_and(|o| self.names(o, name))
            }
            Node::TypeOf { object, .. } => self.names(object, name),
            Node::Inspect { arg, .. } => self.names(arg, name),
            Node::Index { base, index, .. } => self.names(base, name) || any(index),
            // Formula text reads no macro variable.
            Node::Evaluate { .. } | Node::Null | Node::New { .. } => false,
        }
    }

    /// Whether evaluating `e` only reads: it runs none of the macro's procedures (a Function
    /// or a Property could change the variable being appended to, which `s & …` reads first).
    fn reads_only(&self, e: &Expr) -> bool {
        match &e.kind {
            ExprKind::Number(_) | ExprKind::Text(_) | ExprKind::Bool(_) | ExprKind::Error(_) => true,
            ExprKind::Missing | ExprKind::Name(_) => true,
            ExprKind::Paren(inner) | ExprKind::Unary(_, inner) => self.reads_only(inner),
            ExprKind::Binary(_, a, b) => self.reads_only(a) && self.reads_only(b),
            ExprKind::Call(_, args) => args.iter().all(|a| self.reads_only(a)),
            ExprKind::Host(id) => match &self.module.nodes[*id as usize] {
                Node::Element { index, .. } => index.iter().all(|i| self.reads_only(i)),
                Node::Bound { dim, .. } => dim.as_ref().is_none_or(|d| self.reads_only(d)),
                _ => false,
            },
            _ => false,
        }
    }
}
