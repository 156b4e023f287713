//! Array variables: `Dim a(1 To 5)`, `ReDim Preserve`, `a(i)`, `a(i, j)`, `UBound`, `LBound`.
//! Items sit row-major in an [`Array`] with the lower bound of each dimension beside it; a
//! Range held in a variable answers `r(i)` and `r(i, j)` with its cells, as in VBA.

use std::rc::Rc;

use crate::eval::{Array, Ctx, Operand, Value};
use crate::formula::address::Rect;
use crate::formula::ast::Expr;

use super::ast::{Span, Ty};
use super::interp::{Interp, Run};
use super::value::{convert, default_value, Obj, VArray, Var};

impl Interp<'_, '_> {
    pub(super) fn new_array(&self, bounds: &[(Option<Expr>, Expr)], ty: Option<&Ty>, span: Span) -> Run<VArray> {
        if bounds.len() > 2 {
            return Err(self.fault_at(span, "arrays have one or two dimensions here"));
        }
        let mut dims = Vec::new();
        for (lower, upper) in bounds {
            let lo = match lower {
                Some(e) => self.index(e, "the lower bound")?,
                None => self.module.base,
            };
            let hi = self.index(upper, "the upper bound")?;
            if hi < lo {
                return Err(self.fault_at(span, format!("array bounds {lo} To {hi} are not a size")));
            }
            dims.push((lo, (hi - lo).saturating_add(1) as usize));
        }
        let items = dims.iter().fold(1usize, |n, d| n.saturating_mul(d.1));
        let limit = self.options.max_array_items;
        if items > limit {
            let mut f = self.fault_at(
                span,
                format!("an array of {items} items passes the limit of {limit} (ncsheet's limit; raise it with --max-array-items)"),
            );
            f.kind = super::ErrorKind::Limit;
            return Err(f);
        }
        let (rows, lower_row) = if dims.len() == 2 { (dims[0].1, dims[0].0) } else { (1, 1) };
        let (lower_col, cols) = *dims.last().expect("one dimension at least");
        let data = Rc::new(Array::filled(rows, cols, default_value(ty)));
        Ok(VArray { data, lower: (lower_row, lower_col), dims: dims.len() as u8 })
    }

    /// The row-major position of an element, or why there is none.
    pub(super) fn element_at(&self, a: &VArray, index: &[i64]) -> Result<usize, String> {
        let (row, col) = match (a.dims, index) {
            (1, [i]) => (0, i - a.lower.1),
            (2, [i, j]) => (i - a.lower.0, j - a.lower.1),
            (d, _) => {
                return Err(format!(
                    "the array has {d} dimension{}, not {}",
                    if d == 1 { "" } else { "s" },
                    index.len()
                ))
            }
        };
        if row < 0 || col < 0 || row as usize >= a.data.rows || col as usize >= a.data.cols {
            let shown: Vec<String> = index.iter().map(|i| i.to_string()).collect();
            return Err(format!("index ({}) is outside the array's bounds", shown.join(", ")));
        }
        Ok(row as usize * a.data.cols + col as usize)
    }

    pub fn element(&self, ctx: &mut Ctx, name: &str, index: &[Expr], span: Span) -> Run<Operand> {
        if let Some(Var::Obj(Obj::Store(h))) = self.lookup(name) {
            return self.store_operand(ctx, &h, index, span);
        }
        let mut at = Vec::new();
        for e in index {
            let v = ctx.eval(e);
            self.take_pending()?;
            let n = self.number_of(&v, "the index").map_err(|m| self.fault_at(self.expr_span(e), m))?;
            at.push(n.round_ties_even() as i64);
        }
        match self.lookup(name) {
            Some(Var::Array(a)) => {
                let k = self.element_at(&a, &at).map_err(|m| self.fault_at(span, format!("{name}: {m}")))?;
                Ok(Operand::Value(a.data.data[k].clone()))
            }
            Some(Var::Obj(Obj::Range(sheet, rect))) => {
                let cell = super::objects::item(rect, &at).map_err(|m| self.fault_at(span, format!("{name}: {m}")))?;
                Ok(Operand::Ref(sheet, Rect::cell(cell)))
            }
            _ => Err(self.fault_at(span, format!("{name} is not an array"))),
        }
    }

    pub(super) fn set_element(&self, name: &Rc<str>, index: &[Expr], v: Value, span: Span) -> Run<()> {
        let at = index.iter().map(|e| self.index(e, "the index")).collect::<Run<Vec<i64>>>()?;
        if let Some(Var::Obj(Obj::Range(sheet, rect))) = self.lookup(name) {
            let cell = super::objects::item(rect, &at).map_err(|m| self.fault_at(span, format!("{name}: {m}")))?;
            return self.write_range(sheet, Rect::cell(cell), &v);
        }
        // The item's text, and the whole array when it is shared and so copied first.
        let shared = match self.lookup(name) {
            Some(Var::Array(a)) if Rc::strong_count(&a.data) > 2 => super::budget::value_bytes(&Value::Array(a.data)),
            _ => 0,
        };
        self.charge(shared + super::budget::value_bytes(&v), span)?;
        let result = self.with_slot(name, |slot| {
            let ty = slot.ty.clone();
            let Var::Array(a) = &mut slot.var else { return Err(format!("{} is not an array", slot.name)) };
            let k = self.element_at(a, &at).map_err(|m| format!("{}: {m}", slot.name))?;
            let item = match convert(Var::Value(v.clone()), ty.as_ref(), &slot.name)? {
                Var::Value(item) => item,
                _ => return Err(format!("{}: an array item holds a value", slot.name)),
            };
            Rc::make_mut(&mut a.data).data[k] = item;
            Ok(())
        });
        match result {
            Some(r) => r.map_err(|m| self.fault_at(span, m)),
            None => Err(self.fault_at(span, format!("{name} is not an array (Dim {name}(…) first)"))),
        }
    }

    pub fn bound(&self, ctx: &mut Ctx, upper: bool, name: &str, dim: Option<&Expr>, span: Span) -> Run<Value> {
        let d = match dim {
            Some(e) => {
                let v = ctx.eval(e);
                self.take_pending()?;
                self.number_of(&v, "the dimension").map_err(|m| self.fault_at(span, m))? as i64
            }
            None => 1,
        };
        let Some(Var::Array(a)) = self.lookup(name) else {
            return Err(self.fault_at(span, format!("{name} is not an array")));
        };
        let (lower, len) = match (a.dims, d) {
            (1, 1) => (a.lower.1, a.data.cols),
            (2, 1) => (a.lower.0, a.data.rows),
            (2, 2) => (a.lower.1, a.data.cols),
            _ => return Err(self.fault_at(span, format!("{name} has no dimension {d}"))),
        };
        Ok(Value::Number(if upper { lower + len as i64 - 1 } else { lower } as f64))
    }
}

pub(super) fn preserve_items(old: &VArray, new: &mut VArray) {
    let data = Rc::make_mut(&mut new.data);
    for r in 0..old.data.rows.min(data.rows) {
        for c in 0..old.data.cols.min(data.cols) {
            data.data[r * data.cols + c] = old.data.get(r, c).clone();
        }
    }
}
