//! VBA library statements and functions that need the interpreter, not only values:
//! `Stop`, `Randomize`, `Erase`, and `VarType` / `IsMissing`, which read a variable's
//! declaration ("VarType function", "IsMissing function", "Erase statement", "Randomize
//! statement", "Stop statement" in the Office VBA language reference).

use std::rc::Rc;

use crate::eval::functions::vba::var_type_of;
use crate::eval::{Array, Env, Value};
use crate::formula::ast::{Expr, ExprKind};

use super::ast::{Inspect, Span, Ty};
use super::interp::{Fault, Interp, Run};
use super::value::{default_value, range_var, Obj, VArray, Var};

/// The error code of a `Stop`: no `On Error` traps it (VBA's Stop is no error but a pause).
pub(super) const STOP: u32 = u32::MAX;

/// vbArray, added to the items' VarType for an array.
const VB_ARRAY: f64 = 8192.0;
/// vbVariant: an untyped array's items.
const VB_VARIANT: f64 = 12.0;
/// vbError: what a left-out Optional Variant holds.
const VB_ERROR: f64 = 10.0;

impl Interp<'_, '_> {
    /// `Stop`: VBA would pause in its debugger; ncsheet has none, so the macro ends here.
    pub(super) fn stop(&self, span: Span) -> Fault {
        let line = self.module_line(span.line);
        let mut fault = self.fault_at(
            span,
            format!("Stop statement at line {line}: ncsheet has no debugger to pause in, so the macro stops here"),
        );
        fault.code = STOP;
        fault
    }

    /// The line within its own module of a line of the joined project source.
    fn module_line(&self, line: u32) -> u32 {
        match self.module.parts.iter().skip(1).rev().find(|p| p.first_line <= line) {
            Some(part) => line - (part.first_line - 1),
            None => line,
        }
    }

    /// `Randomize [seed]`: restarts the document's random sequence from the seed, or from
    /// the document's clock without one (VBA seeds from its system timer).
    pub(super) fn randomize(&self, seed: Option<&Expr>) -> Run<()> {
        let number = match seed {
            Some(e) => {
                let v = self.eval(e)?;
                crate::eval::coerce::to_number(&v, self.date_system())
                    .map_err(|err| self.fault_at(self.expr_span(e), format!("Randomize needs a number, not {err}")))?
            }
            None => self.now(),
        };
        // Zero would mean "from the system clock at the next draw": a seed never is.
        let seed = number.to_bits().max(1);
        self.wb.borrow().settings().seed_random(seed);
        Ok(())
    }

    /// `Erase a, b`: every item of each array back to its type's default (0, "", False,
    /// Empty); the bounds stay, as for VBA's fixed-size arrays.
    pub(super) fn erase(&self, names: &[Rc<str>], span: Span) -> Run<()> {
        for name in names {
            let erased = self.with_slot(name, |slot| match &mut slot.var {
                Var::Array(a) => {
                    let fill = default_value(slot.ty.as_ref());
                    a.data = Rc::new(Array::filled(a.data.rows, a.data.cols, fill));
                    true
                }
                _ => false,
            });
            if erased != Some(true) {
                return Err(self.fault_at(span, format!("Erase {name}: {name} is not an array (type mismatch)")));
            }
        }
        Ok(())
    }

    /// Notes a parameter the call left out, for IsMissing.
    pub(super) fn mark_missing(&self, name: &Rc<str>) {
        if let Some(frame) = self.frames.borrow_mut().last_mut() {
            frame.missing.push(name.clone());
        }
    }

    pub(super) fn inspect(&self, what: Inspect, arg: &Expr) -> Run<Value> {
        match what {
            Inspect::VarType => self.var_type(arg).map(Value::Number),
            Inspect::IsMissing => Ok(Value::Bool(self.is_missing(arg))),
        }
    }

    /// `IsMissing(param)`: an Optional Variant parameter without a default that the call
    /// left out (and the procedure has not assigned since).
    fn is_missing(&self, arg: &Expr) -> bool {
        let ExprKind::Name(name) = &arg.kind else { return false };
        let left_out =
            self.frames.borrow().last().is_some_and(|f| f.missing.iter().any(|m| m.eq_ignore_ascii_case(name)));
        left_out && matches!(self.lookup(name), Some(Var::Value(Value::Blank)))
    }

    /// `VarType(x)`: a typed variable answers its declared type, a Variant what it holds.
    fn var_type(&self, arg: &Expr) -> Run<f64> {
        if let ExprKind::Name(name) = &arg.kind {
            if self.is_missing(arg) {
                return Ok(VB_ERROR);
            }
            if let Some((var, ty)) = self.with_slot(name, |s| (s.var.clone(), s.ty.clone())) {
                return self.var_type_of_var(&var, ty.as_ref());
            }
        }
        let var = self.var_of(arg, false)?;
        self.var_type_of_var(&var, None)
    }

    fn var_type_of_var(&self, var: &Var, ty: Option<&Ty>) -> Run<f64> {
        Ok(match var {
            Var::Array(_) => VB_ARRAY + ty.and_then(declared_var_type).unwrap_or(VB_VARIANT),
            Var::Record(..) => 36.0,
            // A Range answers its default property's (Value's) type.
            Var::Obj(Obj::Range(sheet, rect)) => match range_var(self.ctx().rect_value(*sheet, *rect)) {
                Var::Value(v) => var_type_of(&v),
                _ => VB_ARRAY + VB_VARIANT,
            },
            Var::Obj(Obj::Value(v)) => var_type_of(v),
            Var::Obj(_) => 9.0,
            Var::Value(v) => ty.and_then(declared_var_type).unwrap_or_else(|| var_type_of(v)),
        })
    }
}

/// What `Split(…)` and `Array(…)` give a variable: a one-dimensional array even of one
/// item or none, zero-based for Split ("Split function": "a zero-based, one-dimensional
/// array"), from Option Base for Array. `None` for any other expression.
pub(super) fn library_array(e: &Expr, v: &Value, base: i64) -> Option<Var> {
    let ExprKind::Call(id, _) = &e.kind else { return None };
    let lower = match crate::eval::functions::spec(*id).name {
        "VBA.SPLIT" => 0,
        "VBA.ARRAY" => base,
        _ => return None,
    };
    let Value::Array(data) = v else { return None };
    Some(Var::Array(VArray { data: data.clone(), lower: (1, lower), dims: 1 }))
}

/// The VarType number of a declared type (`None`: a Variant, which answers what it holds).
fn declared_var_type(ty: &Ty) -> Option<f64> {
    match ty {
        Ty::Whole(code) | Ty::Number(code) => Some(f64::from(*code)),
        Ty::String => Some(8.0),
        Ty::Boolean => Some(11.0),
        Ty::Record(_) => Some(36.0),
        Ty::Variant => None,
    }
}
