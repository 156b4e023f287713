//! `ParamArray` ([MS-VBAL] 5.3.1.5, "Understanding parameter arrays"): a procedure's last
//! parameter `ParamArray args()` takes every argument from its position on, as one Variant
//! array, zero-based whatever the Option Base ("Option Base statement": "The base of an array
//! created with the ParamArray keyword is zero"), empty (LBound 0, UBound -1) when the call
//! gives none. The parser checks the declaration and the call (`parser.rs`, `resolve.rs`);
//! here the arguments become that array, for a call from code and from a cell.

use std::collections::HashMap;
use std::rc::Rc;

use crate::eval::{Array, Ctx, Operand, Value};
use crate::formula::ast::{Expr, ExprKind};

use super::ast::{Arg, Proc};
use super::interp::{Interp, Run};
use super::typing::Declared;
use super::value::{array_var, Obj, VArray, Var};

/// Whether `p`'s last parameter is a ParamArray.
pub(super) fn has_param_array(p: &Proc) -> bool {
    p.params.last().is_some_and(|q| q.param_array)
}

/// A call's arguments for `p`'s own parameters, and those its ParamArray takes (`None` when
/// it has none).
pub(super) fn split_args<'a>(p: &Proc, args: &'a [Arg]) -> (&'a [Arg], Option<&'a [Arg]>) {
    if !has_param_array(p) {
        return (args, None);
    }
    let fixed = (p.params.len() - 1).min(args.len());
    (&args[..fixed], Some(&args[fixed..]))
}

/// A cell's call of `p` (`=TEXTLIKE(A1, "x*", "y*")`): the arguments from the ParamArray's
/// position on, as its array. A call short of the parameters before it is left as it is,
/// for the binding to refuse.
pub(super) fn pack_cell_args(p: &Proc, mut args: Vec<Var>) -> Vec<Var> {
    let fixed = p.params.len().saturating_sub(1);
    if !has_param_array(p) || args.len() < fixed {
        return args;
    }
    let rest = args.split_off(fixed);
    let held = vec![Declared::Variant; rest.len()];
    args.push(Var::Array(zero_based(rest, held)));
    args
}

/// One-dimensional, from 0, each item as the argument gave it: a value, an object (a Range
/// stays a Range, as VBA passes it), an array.
fn zero_based(items: Vec<Var>, held: Vec<Declared>) -> VArray {
    let mut data = Vec::with_capacity(items.len());
    let mut objects = HashMap::new();
    let mut arrays = HashMap::new();
    for (k, item) in items.into_iter().enumerate() {
        match item {
            Var::Value(v) => data.push(v),
            Var::Obj(o) => {
                data.push(Value::Blank);
                objects.insert(k, o);
            }
            Var::Array(a) => {
                data.push(Value::Array(a.data.clone()));
                arrays.insert(k, a);
            }
            // The parser lets no Type through a ParamArray (a Variant cannot hold one).
            Var::Record(..) => data.push(Value::Blank),
        }
    }
    let cols = data.len();
    let mut array = VArray::row(Rc::new(Array { rows: 1, cols, data, tail: None }), 0);
    array.objects = (!objects.is_empty()).then(|| Rc::new(objects));
    array.arrays = (!arrays.is_empty()).then(|| Rc::new(arrays));
    for (k, ty) in held.into_iter().enumerate() {
        array.mark_held(k, ty);
    }
    array
}

impl Interp<'_, '_> {
    /// The ParamArray's array of a call from code: each argument evaluated in the caller, a
    /// number keeping its type (an Integer 1, a Date) as a Variant item does ([MS-VBAL] 2.1.1.1).
    pub(super) fn param_array_arg(&self, ctx: &mut Ctx, args: &[Arg]) -> Run<Var> {
        let values: Vec<&Expr> = args.iter().map(|a| &a.value).collect();
        self.variant_items(ctx, &values).map(Var::Array)
    }

    /// One-dimensional Variant items from 0, one per expression, each as a Variant holds it:
    /// an object as the reference, a number with its type, an array with its bounds.
    fn variant_items(&self, ctx: &mut Ctx, values: &[&Expr]) -> Run<VArray> {
        let mut items = Vec::with_capacity(values.len());
        let mut held = Vec::with_capacity(values.len());
        for value in values {
            let mut ty = Declared::Variant;
            // `zip(col(1, 2), col(3))`: a function's result is taken as it is, an object with it.
            if let Some(var) = self.call_argument(value) {
                let var = var?;
                if let Var::Value(v) = &var {
                    ty = self.variant_item_type(value, v);
                }
                items.push(var);
                held.push(ty);
                continue;
            }
            let var = match self.object_arg(ctx, value)? {
                Some(object) => object,
                None => match ctx.operand(value) {
                    Operand::Ref(sheet, rect) => Var::Obj(Obj::Range(sheet, rect)),
                    Operand::Value(v) => {
                        ty = self.variant_item_type(value, &v);
                        match &value.kind {
                            ExprKind::Name(n) => self.lookup(n).unwrap_or(Var::Value(v)),
                            _ => self.array_of_call(value, &v).unwrap_or_else(|| array_var(v, self.option_base())),
                        }
                    }
                    areas @ Operand::Areas(_) => array_var(ctx.deref(areas), self.option_base()),
                },
            };
            self.take_pending()?;
            items.push(var);
            held.push(ty);
        }
        Ok(zero_based(items, held))
    }

    /// The type a Variant item keeps of the value `value` gave: a Date, or a number's own type.
    fn variant_item_type(&self, value: &Expr, v: &Value) -> Declared {
        if self.as_date(value, v).is_some() {
            Declared::Date
        } else if matches!(v, Value::Number(_)) {
            self.value_type(value, v)
        } else {
            Declared::Variant
        }
    }

    /// `Array(c, 2)` where an argument is a variable holding an object (a Collection, an
    /// object of a class, a Worksheet), `New …` or a Function's call: a Variant array whose
    /// item holds the object reference, as a Variant does ("Array function": "a Variant containing an array";
    /// [MS-VBAL] 2.2), from `lower`. Likewise `Array(m, p)` where a variable holds an array:
    /// the item keeps that array's bounds (`Dim p(1 To 3)` stays 1 To 3, [MS-VBAL] 2.2: an
    /// array value carries its bounds), which the evaluator's Array, holding plain values,
    /// would lose. `None` when no argument is either: the evaluator's Array builds that one.
    pub(super) fn array_of_objects(&self, args: &[Expr], lower: i64) -> Option<Run<Var>> {
        let keeps_itself = |e: &Expr| match &e.kind {
            ExprKind::Name(n) => match self.lookup(n) {
                Some(Var::Obj(o)) => !matches!(o, Obj::Range(..) | Obj::Value(_)),
                Some(Var::Array(_)) => true,
                _ => false,
            },
            // `Array(Mk(1), 7)`: a Function's result, which may be an object or an array.
            ExprKind::Host(id) => {
                matches!(self.module.nodes[*id as usize], super::ast::Node::New { .. } | super::ast::Node::Call { .. })
            }
            _ => false,
        };
        if !args.iter().any(keeps_itself) {
            return None;
        }
        let values: Vec<&Expr> = args.iter().collect();
        Some(self.variant_items(&mut self.ctx(), &values).map(|mut array| {
            array.lower.1 = lower;
            Var::Array(array)
        }))
    }
}
