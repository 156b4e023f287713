//! Array variables: `Dim a(1 To 5)`, `ReDim Preserve`, `a(i)`, `a(i, j, k)`, `UBound`, `LBound`,
//! up to VBA's 60 dimensions. Items sit row-major in an [`Array`] with the lower bound of each
//! dimension beside it (past two, [`VArray::shape`]); a
//! Range held in a variable answers `r(i)` and `r(i, j)` with its cells, as in VBA.

use std::rc::Rc;

use crate::eval::{Array, Ctx, Operand, Value};
use crate::formula::address::Rect;
use crate::formula::ast::{Expr, ExprKind, SheetId};

use super::ast::{Arg, Link, Node, Param, Span, Ty};
use super::interp::{Interp, Run};
use super::typing::Declared;
use super::value::{convert, default_value, Obj, VArray, Var};

impl Interp<'_, '_> {
    /// The (lower bound, length) of each dimension `bounds` give, within the item limit.
    pub(super) fn array_dims(&self, bounds: &[(Option<Expr>, Expr)], span: Span) -> Run<Vec<(i64, usize)>> {
        if bounds.len() > MAX_DIMENSIONS {
            // VBA's own limit ("Dim statement": "up to 60 dimensions"); VBA refuses more when
            // it compiles ("Too many dimensions").
            let n = bounds.len();
            return Err(
                self.fault_at(span, format!("Too many dimensions: {n} (an array has at most {MAX_DIMENSIONS})"))
            );
        }
        let mut dims = Vec::new();
        for (lower, upper) in bounds {
            let lo = match lower {
                Some(e) => self.index(e, "the lower bound")?,
                None => self.option_base(),
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
                format!(
                    "an array of {items} items passes the limit of {limit} (ncsheet's limit; {})",
                    self.options.raise_hint("raise it with --max-array-items")
                ),
            );
            f.kind = super::ErrorKind::Limit;
            return Err(f);
        }
        Ok(dims)
    }

    /// An array of `dims`, each item the default of `ty`; past two dimensions, `data`'s rows
    /// are every dimension but the last ([`VArray::shape`]).
    pub(super) fn array_with(&self, dims: &[(i64, usize)], ty: Option<&Ty>) -> Run<VArray> {
        let (rows, lower_row) = match dims {
            [_] => (1, 1),
            [first, .., _] => (dims[..dims.len() - 1].iter().map(|d| d.1).product(), first.0),
            [] => unreachable!("one dimension at least"),
        };
        let (lower_col, cols) = *dims.last().expect("one dimension at least");
        let data = Rc::new(Array::filled(rows, cols, default_value(ty)));
        // An array of a Type: each item a record of the Type's defaults.
        let records = match ty.filter(|t| matches!(t, Ty::Record(_))) {
            Some(t) => {
                let record = self.default_var(Some(t))?;
                self.records_within_limit(rows * cols, &record)?;
                Some(Rc::new(vec![record; rows * cols]))
            }
            None => None,
        };
        Ok(VArray {
            records,
            shape: (dims.len() > 2).then(|| Rc::from(dims)),
            item_type: Declared::of_ty(ty),
            ..VArray::plain(data, (lower_row, lower_col), dims.len() as u8)
        })
    }

    /// Refuses `count` copies of `record` past the item limit, counting each of its fields
    /// (those of a Type within it too; an array field is shared until written, and counts
    /// one): `Dim a(1 To 100000) As Big` of a Type of 1,000 Doubles is 10^8 values, which
    /// the limit on its 100,000 items let through to abort at the memory cap.
    fn records_within_limit(&self, count: usize, record: &Var) -> Run<()> {
        let fields = values_in(record);
        let items = count.saturating_mul(fields);
        let limit = self.options.max_array_items;
        if items <= limit {
            return Ok(());
        }
        let mut f = self.fault(format!(
            "an array of {count} records of {fields} fields each, {items} values, passes the limit of {limit} \
             items (ncsheet's limit; {})",
            self.options.raise_hint("raise it with --max-array-items")
        ));
        f.kind = super::ErrorKind::Limit;
        Err(f)
    }

    /// Refuses a record of Type `i` before any of it is made when its values (its fields,
    /// those of the Types and fixed arrays within it) pass the item limit or its Types nest
    /// deeper than [`MAX_RECORD_NESTING`]: a Type of two fields of a Type of two fields …, 39
    /// deep, is 2^39 Doubles, and a chain of 20,000 Types each holding the one before
    /// overflowed the stack; both aborted while the record was being made.
    #[inline(never)]
    pub(super) fn record_within_limits(&self, i: usize) -> Run<()> {
        let (values, _) = self.record_size((i, i), 0, &mut std::collections::HashMap::new())?;
        let limit = self.options.max_array_items;
        if values <= limit {
            return Ok(());
        }
        let mut f = self.fault(format!(
            "a {} holds {values} values (its fields, with the Types and arrays within them), more than the \
             limit of {limit} items (ncsheet's limit; {})",
            self.module.types[i].name,
            self.options.raise_hint("raise it with --max-array-items")
        ));
        f.kind = super::ErrorKind::Limit;
        Err(f)
    }

    /// The values a record of Type `i` holds and how deep its Types nest below it, each Type
    /// counted once however often it recurs (`sizes`), so the count takes a step per field;
    /// `top` is the Type of the record being made, which a refusal names.
    fn record_size(
        &self,
        (top, i): (usize, usize),
        depth: usize,
        sizes: &mut std::collections::HashMap<usize, (usize, usize)>,
    ) -> Run<(usize, usize)> {
        if let Some(&(values, below)) = sizes.get(&i) {
            return self.record_nesting_within_limit(top, depth + below).map(|_| (values, below));
        }
        self.record_nesting_within_limit(top, depth)?;
        let def = &self.module.types[i];
        let (mut values, mut below) = (0usize, 0usize);
        for ((_, t), bounds) in def.fields.iter().zip(&def.bounds) {
            let (each, nested) = match t {
                Ty::Record(inner) => self.record_size((top, *inner), depth + 1, sizes).map(|(v, b)| (v, b + 1))?,
                _ => (1, 0),
            };
            let items = match bounds {
                Some(b) if !b.is_empty() => {
                    self.array_dims(b, self.expr_span(&b[0].1))?.iter().fold(1usize, |n, d| n.saturating_mul(d.1))
                }
                _ => 1,
            };
            values = values.saturating_add(items.saturating_mul(each));
            below = below.max(nested);
        }
        sizes.insert(i, (values.max(1), below));
        Ok((values.max(1), below))
    }

    fn record_nesting_within_limit(&self, top: usize, depth: usize) -> Run<()> {
        if depth <= MAX_RECORD_NESTING {
            return Ok(());
        }
        let mut f = self.fault(format!(
            "a {} nests Types more than {MAX_RECORD_NESTING} deep (a field of a Type of a Type …; ncsheet's limit)",
            self.module.types[top].name
        ));
        f.kind = super::ErrorKind::Limit;
        Err(f)
    }

    /// The row-major position of an element, or why there is none.
    pub(super) fn element_at(&self, a: &VArray, index: &[i64]) -> Result<usize, String> {
        let (row, col) = match (a.dims, index) {
            (0, _) => return Err("the array has no bounds yet (ReDim gives them)".into()),
            // Saturating: an index near i64's ends (`a(-9.2E+18)`) is outside any bounds, not
            // an overflow.
            (1, [i]) => (0, i.saturating_sub(a.lower.1)),
            (2, [i, j]) => (i.saturating_sub(a.lower.0), j.saturating_sub(a.lower.1)),
            (d, _) if d > 2 && index.len() == d as usize => {
                let shape = a.shape.as_deref().expect("an array of three dimensions or more has its shape");
                return position_in(shape, index).ok_or_else(|| outside_bounds(index));
            }
            (d, _) => {
                return Err(format!(
                    "the array has {d} dimension{}, not {}",
                    if d == 1 { "" } else { "s" },
                    index.len()
                ))
            }
        };
        if row < 0 || col < 0 || row as usize >= a.data.rows || col as usize >= a.data.cols {
            return Err(outside_bounds(index));
        }
        Ok(row as usize * a.data.cols + col as usize)
    }

    pub fn element(&self, ctx: &mut Ctx, name: &str, index: &[Expr], span: Span) -> Run<Operand> {
        let plain = self.peek(name, |held| matches!(held, Var::Array(_))) == Some(true);
        // An item growing in place (`append.rs`) is read without making the array anew.
        if let Some(read) = self.growing_element(ctx, name, index, span) {
            return read;
        }
        if !plain {
            if let Some(h) = self.store_named(name) {
                return self.store_operand(ctx, &h, index, span);
            }
            if let Some(got) = self.collection_item_of(ctx, name, index, span) {
                return got;
            }
            if let Some(Var::Obj(Obj::Instance(object))) = self.lookup(name) {
                // `bag(2)`: the object's default member ([MS-VBAL] 5.6.13.1).
                let args: Vec<Arg> = index.iter().map(|e| Arg { name: None, value: e.clone() }).collect();
                let got = self.default_member(ctx, &object, &args, span)?;
                return self.operand_of(got, span);
            }
            if let Some(r) = self.regex_named(name) {
                return match self.regex_element_item(&r, index, span)? {
                    Var::Obj(o) => self.operand_of(o, span),
                    Var::Value(v) => Ok(Operand::Value(v)),
                    _ => unreachable!("a MatchCollection or SubMatches holds objects and values"),
                };
            }
        }
        let mut at = Vec::new();
        for e in index {
            let v = ctx.eval(e);
            self.take_pending()?;
            let n = self.number_of(&v, "the index").map_err(|m| self.fault_at(self.expr_span(e), m))?;
            at.push(n.round_ties_even() as i64);
        }
        // The usual item, a plain value, is read in place without copying the array's
        // description (the index may have changed the variable: it is looked at again).
        let read = self.peek(name, |held| match held {
            Var::Array(a) if a.records.is_none() && a.exact.is_none() && a.objects.is_none() => {
                Some(self.element_at(a, &at).map(|k| (a.data.data[k].clone(), a.held(k))))
            }
            _ => None,
        });
        if let Some(Some(read)) = read {
            let (value, held) = read.map_err(|m| self.subscript_error(span, name, m))?;
            self.gave.set(held);
            return Ok(Operand::Value(value));
        }
        match self.lookup(name) {
            Some(Var::Array(a)) => {
                let k = self.element_at(&a, &at).map_err(|m| self.subscript_error(span, name, m))?;
                if a.records.is_some() {
                    let why = "is a Type value: read its fields (pts(i).x) or assign it to a variable of the Type";
                    let mut f = self.fault_at(span, format!("Type mismatch (run-time error 13): {name}(…) {why}"));
                    f.code = 13;
                    return Err(f);
                }
                self.gave.set(a.held(k));
                // Its LongLong past 2^53 is the node's (`longlong.rs`).
                if let Some(long_long) = a.exact_item(k) {
                    self.returning_long_long(Some(long_long));
                }
                match a.item(k) {
                    Var::Obj(o) => self.operand_of(o, span),
                    _ => Ok(Operand::Value(a.data.data[k].clone())),
                }
            }
            Some(Var::Obj(Obj::Range(sheet, rect))) => {
                let cell = super::objects::item(rect, &at).map_err(|m| self.fault_at(span, format!("{name}: {m}")))?;
                Ok(Operand::Ref(sheet, Rect::cell(cell)))
            }
            _ => Err(self.fault_at(span, format!("{name} is not an array"))),
        }
    }

    /// `sl(j)` of a variable set to one of Excel's collections (`Set sl = ActiveWorkbook.Worksheets`,
    /// `r.Rows`, `r.Areas`): its default member, Item ([MS-VBAL] 5.6.13.1: an index
    /// expression on an object is a call of its default member; "Sheets.Item property",
    /// "Range.Item property"). `None` when the variable holds something else.
    #[inline(never)]
    fn collection_item_of(&self, ctx: &mut Ctx, name: &str, index: &[Expr], span: Span) -> Option<Run<Operand>> {
        let item = self.collection_item(ctx, name, index, span)?;
        Some(item.and_then(|item| self.operand_of(item, span)))
    }

    /// `Set ws = sl(j)`: the node `id` is an item of a variable set to one of Excel's
    /// collections, as an object ([`Interp::collection_item_of`]).
    #[inline(never)]
    pub(super) fn collection_element(&self, id: u32) -> Option<Run<Var>> {
        let Node::Element { var, index, span } = &self.module.nodes[id as usize] else { return None };
        let item = self.collection_item(&mut self.ctx(), var, index, *span)?;
        Some(item.map(Var::Obj))
    }

    /// Whether the node `id` is `sl(j)` of a variable set to one of Excel's collections.
    pub(super) fn is_collection_element(&self, id: u32) -> bool {
        matches!(&self.module.nodes[id as usize], Node::Element { var, .. } if self.holds_collection(var))
    }

    pub(super) fn holds_collection(&self, name: &str) -> bool {
        let is_collection = |held: &Var| {
            matches!(
                held,
                Var::Obj(Obj::Sheets | Obj::SheetGroup(_) | Obj::Lines(..) | Obj::AreaList(..) | Obj::Hyperlinks(..))
            )
        };
        self.peek(name, is_collection) == Some(true)
    }

    fn collection_item(&self, ctx: &mut Ctx, name: &str, index: &[Expr], span: Span) -> Option<Run<Obj>> {
        if !self.holds_collection(name) {
            return None;
        }
        let collection = self.lookup(name)?;
        let args: Vec<Arg> = index.iter().map(|e| Arg { name: None, value: e.clone() }).collect();
        Some(self.collection_member_item(ctx, collection, &args, span))
    }

    /// The collection's Item of the arguments, as `collection.Item(args)` reads it.
    #[inline(never)]
    pub(super) fn collection_member_item(&self, ctx: &mut Ctx, collection: Var, args: &[Arg], span: Span) -> Run<Obj> {
        let Var::Obj(collection) = collection else { unreachable!("a collection is an object") };
        let link = Link { name: "Item".into(), args: Some(args.to_vec()), span };
        let item = self.member(ctx, collection, &link);
        self.take_pending().and(item)
    }

    /// `r(i)` or `r(i, j)` of a Range an expression gave (`Range("A65536").End(xlUp)(2)`): its
    /// default member, Item, the cell counted from the range's first cell, which may lie past
    /// the range ("Range.Item property").
    #[inline(never)]
    fn range_item_var(&self, sheet: SheetId, rect: Rect, index: &[Expr], span: Span) -> Run<Var> {
        // `r(, j)`: the row left out is the range's first, as `r.Cells(, j)` (objects.rs).
        let row_left_out = |k: usize, e: &Expr| k == 0 && index.len() == 2 && e.kind == ExprKind::Missing;
        let at = index
            .iter()
            .enumerate()
            .map(|(k, e)| if row_left_out(k, e) { Ok(1) } else { self.index(e, "the index") })
            .collect::<Run<Vec<i64>>>()?;
        let cell = super::objects::item(rect, &at).map_err(|m| self.fault_at(span, format!("Range item: {m}")))?;
        Ok(Var::Obj(Obj::Range(sheet, Rect::cell(cell))))
    }

    /// The node is `a(i)` of a variable holding an array with objects or arrays among its items.
    pub(super) fn array_object(&self, id: u32) -> Option<(Rc<str>, &[Expr], Span)> {
        let Node::Element { var, index, span } = &self.module.nodes[id as usize] else { return None };
        let special = |held: &Var| matches!(held, Var::Array(a) if a.objects.is_some() || a.arrays.is_some() || a.records.is_some());
        (self.peek(var, special) == Some(true)).then(|| (var.clone(), index.as_slice(), *span))
    }

    /// `a(i)` as a variable holds it: its object, or its value.
    pub(super) fn array_item(&self, name: &str, index: &[Expr], span: Span) -> Run<Var> {
        let at = index.iter().map(|e| self.index(e, "the index")).collect::<Run<Vec<i64>>>()?;
        let Some(Var::Array(a)) = self.lookup(name) else {
            return Err(self.fault_at(span, format!("{name} is not an array")));
        };
        let k = self.element_at(&a, &at).map_err(|m| self.subscript_error(span, name, m))?;
        // A number keeps its type beside objects too (`TypeName(Array(c, 7)(1))`: Integer).
        self.gave.set(a.held(k));
        Ok(a.item(k))
    }

    /// The row-major position of `name(index)`, an item of an array of a Type: the first
    /// step of the path to its fields ([`Obj::Record`]), so `pts(i).x = 1` changes the item.
    pub(super) fn record_item(&self, name: &str, index: &[Expr], span: Span) -> Run<Option<usize>> {
        let Some(Var::Array(a)) = self.lookup(name).filter(|v| matches!(v, Var::Array(a) if a.records.is_some()))
        else {
            return Ok(None);
        };
        let at = index.iter().map(|e| self.index(e, "the index")).collect::<Run<Vec<i64>>>()?;
        self.element_at(&a, &at).map(Some).map_err(|m| self.subscript_error(span, name, m))
    }

    /// Whether `name` holds an array of a Type.
    pub(super) fn holds_records(&self, name: &str) -> bool {
        self.peek(name, |held| matches!(held, Var::Array(a) if a.records.is_some())) == Some(true)
    }

    /// `pts(i) = q`, `pts(i) = MakePoint(…)` ([MS-VBAL] 5.4.3.8: a Let of a UDT copies it): the
    /// item becomes a copy of a value of the array's Type; the value first, then the indexes.
    pub(super) fn set_record_element(&self, name: &Rc<str>, index: &[Expr], value: &Expr, span: Span) -> Run<()> {
        let record = self.var_of(value, false)?;
        self.set_record_item(name, index, record, span)
    }

    /// Puts `record` at `name(index)` in an array of a Type, converted to the array's Type.
    pub(super) fn set_record_item(&self, name: &Rc<str>, index: &[Expr], record: Var, span: Span) -> Run<()> {
        let at = index.iter().map(|e| self.index(e, "the index")).collect::<Run<Vec<i64>>>()?;
        self.charge(super::budget::brought(&record), span)?;
        // Any item: the write steps into the array itself only.
        self.copy_records_if_shared(name, &[0], span)?;
        let result = self.with_slot(name, |slot| {
            let (ty, own) = (slot.ty.clone(), slot.name.clone());
            let Var::Array(a) = slot.var_mut() else { return Err(format!("{own} is not an array")) };
            let k = self
                .element_at(a, &at)
                .map_err(|m| format!("Subscript out of range (run-time error 9): {own}: {m}"))?;
            let record = convert(record, ty.as_ref(), &format!("{own}(…)"))?;
            let records = a.records.as_mut().ok_or_else(|| format!("{own} is not an array of a Type"))?;
            Rc::make_mut(records)[k] = record;
            Ok(())
        });
        match result {
            Some(r) => r.map_err(|m| self.fault_at(span, m)),
            None => Err(self.fault_at(span, format!("{name} is not an array (Dim {name}(…) first)"))),
        }
    }

    /// The value a Range is given (`r.Value = value`): a sheet holds rows and columns, so an
    /// array variable of three dimensions or more is refused as a type mismatch, error 13,
    /// rather than written flattened.
    pub(super) fn sheet_value(&self, value: &Expr) -> Run<Value> {
        if let ExprKind::Name(n) = &value.kind {
            if let Some(Var::Array(a)) = self.lookup(n).filter(|v| matches!(v, Var::Array(a) if a.dims > 2)) {
                let why = format!(
                    "Type mismatch (run-time error 13): {n} has {} dimensions; a range's values have rows and columns only",
                    a.dims
                );
                let mut f = self.fault_at(self.expr_span(value), why);
                f.code = 13;
                return Err(f);
            }
        }
        self.eval(value)
    }

    /// What `name(i) = …` copies first when the array's items are shared with another
    /// variable (`b = a`, or the module's array as a call from a cell found it): the items,
    /// charged to the memory budget, and counted against the statement limit as any copy is
    /// ([`Interp::count_copy`]): `b = a: b(1) = i` in a loop copies `a` each turn.
    fn copy_if_shared(&self, name: &str, span: Span) -> Run<u64> {
        self.note_item_write(name);
        let shared = |held: &Var| match held {
            Var::Array(a) if Rc::strong_count(&a.data) > 1 => (a.data.data.len(), super::budget::copy_bytes(&a.data)),
            _ => (0, 0),
        };
        let (items, bytes) = self.peek(name, shared).unwrap_or((0, 0));
        if items > 0 {
            self.count_copy(items, span)?;
        }
        Ok(bytes)
    }

    /// What a write at `path` into `name` (an array of a Type, or a Type holding one, `pts(3).x
    /// = 1`, `b(1) = q`) copies first because the records it steps into are shared with another
    /// variable (`b = a`) or with the module's array as a call from a cell found it: counted
    /// against the statement limit and charged to the memory budget, as [`Interp::copy_if_shared`]
    /// does for an array of values (2,000 cells whose Function wrote `big(1).x = v` into a
    /// module-level array of a million records copied 2 billion records uncounted).
    #[inline(never)]
    pub(super) fn copy_records_if_shared(&self, name: &str, path: &[usize], span: Span) -> Run<()> {
        self.note_item_write(name);
        let items = self.peek(name, |held| records_copied(held, path)).unwrap_or(0);
        if items == 0 {
            return Ok(());
        }
        self.count_copy(items, span)?;
        self.charge((items * std::mem::size_of::<Var>()) as u64, span)
    }

    /// VBA's "Subscript out of range (Error 9)".
    fn subscript_error(&self, span: Span, name: &str, m: String) -> super::interp::Fault {
        self.subscript_fault(span, name, m)
    }

    /// VBA's "Subscript out of range (Error 9)" about `name`, for why `m`.
    pub(super) fn subscript_fault(&self, span: Span, name: &str, m: String) -> super::interp::Fault {
        let mut f = self.fault_at(span, format!("Subscript out of range (run-time error 9): {name}: {m}"));
        f.code = 9;
        f
    }

    /// `Set a(i) = obj` ([MS-VBAL] 5.4.3.9, "Set Statement"): the item holds the object (or
    /// Nothing), in an array of any declared item type that holds objects (Variant, Object
    /// or a class); an object only it held is let go.
    pub(super) fn set_object_element(&self, name: &Rc<str>, index: &[Expr], item: Var, span: Span) -> Run<()> {
        let at = index.iter().map(|e| self.index(e, "the index")).collect::<Run<Vec<i64>>>()?;
        let object = match item {
            Var::Obj(Obj::Value(Value::Blank)) | Var::Value(Value::Blank) => None,
            Var::Obj(Obj::Value(_)) | Var::Value(_) | Var::Array(_) | Var::Record(..) => {
                return Err(self.fault_at(span, "Set needs an object (a Range, a Worksheet, …)"))
            }
            Var::Obj(o) => Some(o),
        };
        self.charge(self.copy_if_shared(name, span)?, span)?;
        let result = self.with_slot(name, |slot| {
            if matches!(slot.ty, Some(ref t) if !matches!(t, Ty::Variant | Ty::Object)) {
                return Err(format!("{}: an array of values cannot hold an object (type mismatch)", slot.name));
            }
            let own = slot.name.clone();
            let Var::Array(a) = slot.var_mut() else { return Err(format!("{own} is not an array")) };
            let k = self.element_at(a, &at).map_err(|m| format!("{own}: {m}"))?;
            Rc::make_mut(&mut a.data).data[k] = Value::Blank;
            let objects = Rc::make_mut(a.objects.get_or_insert_with(Default::default));
            Ok(match object {
                Some(o) => objects.insert(k, o),
                None => objects.remove(&k),
            })
        });
        match result {
            Some(Ok(old)) => self.release(&old.map_or(Var::Value(Value::Blank), Var::Obj)),
            Some(Err(m)) => Err(self.fault_at(span, m)),
            None => Err(self.fault_at(span, format!("{name} is not an array (Dim {name}(…) first)"))),
        }
    }

    /// `a(i) = v`; `date`: `v` is a Date, which a Variant array's item keeps as one.
    pub(super) fn set_element(&self, name: &Rc<str>, index: &[Expr], v: Value, date: bool, span: Span) -> Run<()> {
        let held = if date { Declared::Date } else { Declared::Variant };
        self.set_element_holding(name, index, v, held, span)
    }

    /// `a(i) = v`, where `v` is a number of the type `held`: an item of a Variant array keeps
    /// it ("Variant data type": numeric data "is maintained in its original data type"), as a
    /// Variant variable does, so `v(0) = 5` holds the Integer 5.
    pub(super) fn set_element_holding(
        &self,
        name: &Rc<str>,
        index: &[Expr],
        v: Value,
        held: Declared,
        span: Span,
    ) -> Run<()> {
        // The LongLong past 2^53 the assignment gave, if any (`longlong.rs`).
        let long_long = self.take_item_long_long();
        let at = index.iter().map(|e| self.index(e, "the index")).collect::<Run<Vec<i64>>>()?;
        // Looked at in place: a copy of an array variable's description, to see that it is
        // not a Range, cost each write of an item seven reference counts.
        let range = |held: &Var| match held {
            Var::Obj(Obj::Range(sheet, rect)) => Some((*sheet, *rect)),
            _ => None,
        };
        if let Some((sheet, rect)) = self.peek(name, range).flatten() {
            let cell = super::objects::item(rect, &at).map_err(|m| self.fault_at(span, format!("{name}: {m}")))?;
            return self.write_range(sheet, Rect::cell(cell), &v);
        }
        // The item's text, and the array's items when it is shared and so copied first.
        self.charge(self.copy_if_shared(name, span)? + super::budget::value_bytes(&v), span)?;
        let result = self.with_slot(name, |slot| {
            let own = slot.name.clone();
            let declared = slot.ty.clone();
            let Var::Array(a) = slot.var_mut() else { return Err(format!("{own} is not an array")) };
            let ty = element_type(declared, a);
            let k = self.element_at(a, &at).map_err(|m| format!("{own}: {m}"))?;
            let given = Var::Value(v.clone());
            let item = match convert(given.clone(), ty.as_ref(), &own)? {
                Var::Value(item) => item,
                _ => return Err(format!("{own}: an array item holds a value")),
            };
            let padded = super::budget::padding_bytes(&given, &Var::Value(item.clone()));
            Rc::make_mut(&mut a.data).data[k] = item;
            if let Some(objects) = a.objects.as_mut().filter(|o| o.contains_key(&k)) {
                Rc::make_mut(objects).remove(&k);
            }
            if let Some(arrays) = a.arrays.as_mut().filter(|o| o.contains_key(&k)) {
                Rc::make_mut(arrays).remove(&k);
            }
            let number = matches!(a.data.data[k], Value::Number(_));
            let variant = matches!(ty, None | Some(Ty::Variant));
            a.mark_held(k, if number && variant { held } else { Declared::Variant });
            let typed = matches!(Declared::of_ty(ty.as_ref()), Declared::LongLong | Declared::Variant);
            a.keep_exact_item(k, long_long.filter(|&n| typed && a.data.data[k] == Value::Number(n as f64)));
            Ok(padded)
        });
        match result {
            Some(r) => self.charge(r.map_err(|m| self.fault_at(span, m))?, span),
            None => Err(self.fault_at(span, format!("{name} is not an array (Dim {name}(…) first)"))),
        }
    }

    /// What `a(i) = value` stores: an array with its own bounds ([MS-VBAL] 2.2), when `value`
    /// gives one — a variable's array, a Function's, another array's item — or else its value.
    pub(super) fn item_given(&self, value: &Expr) -> Run<Result<VArray, Value>> {
        let gives_array = match &value.kind {
            ExprKind::Name(n) => matches!(self.lookup(n), Some(Var::Array(_))),
            ExprKind::Host(id) => {
                matches!(self.module.nodes[*id as usize], Node::Call { .. } | Node::ZeroBasedArray { .. })
                    || self.array_object(*id).is_some()
            }
            // `a(i) = Array(3)`, `Split(s)`, `Filter(…)`: an array of one item is still an array.
            ExprKind::Call(id, _) => {
                matches!(crate::eval::functions::spec(*id).name, "VBA.ARRAY" | "VBA.SPLIT" | "VBA.FILTER")
            }
            _ => false,
        };
        if gives_array {
            match self.var_of(value, false)? {
                Var::Array(a) => return Ok(Ok(a)),
                Var::Value(v) => return Ok(Err(v)),
                // An object's default value, a Type's refusal: as any other assignment.
                _ => {}
            }
        }
        self.eval(value).map(Err)
    }

    /// `a(i) = b` where `b` is an array: the item holds it with its bounds, in an array of
    /// Variants (an array of a declared value type cannot hold an array: type mismatch).
    pub(super) fn set_array_element(&self, name: &Rc<str>, index: &[Expr], item: VArray, span: Span) -> Run<()> {
        let at = index.iter().map(|e| self.index(e, "the index")).collect::<Run<Vec<i64>>>()?;
        // The item's own array too: one a call made (`Array(Space(1E6), …)`) was counted nowhere.
        let brought = super::budget::array_brought(&item.data);
        self.charge(self.copy_if_shared(name, span)? + brought, span)?;
        let result = self.with_slot(name, |slot| {
            let own = slot.name.clone();
            if matches!(slot.ty, Some(ref t) if !matches!(t, Ty::Variant)) {
                return Err(format!("{own}: an array of a declared type cannot hold an array (type mismatch)"));
            }
            let Var::Array(a) = slot.var_mut() else { return Err(format!("{own} is not an array")) };
            let k = self.element_at(a, &at).map_err(|m| format!("{own}: {m}"))?;
            Rc::make_mut(&mut a.data).data[k] = Value::Array(item.data.clone());
            if let Some(objects) = a.objects.as_mut().filter(|o| o.contains_key(&k)) {
                Rc::make_mut(objects).remove(&k);
            }
            a.mark_date(k, false);
            Rc::make_mut(a.arrays.get_or_insert_with(Default::default)).insert(k, item);
            Ok(())
        });
        match result {
            Some(r) => r.map_err(|m| self.fault_at(span, m)),
            None => Err(self.fault_at(span, format!("{name} is not an array (Dim {name}(…) first)"))),
        }
    }

    /// An argument `a(i)` naming an item of an array variable: the array's name and the
    /// item's indexes, evaluated before the call, for a ByRef parameter to give the item
    /// back ([MS-VBAL] 5.3.1.11: a ByRef argument is a reference to the item itself).
    pub(super) fn item_reference(&self, e: &Expr) -> Option<Run<(Rc<str>, Vec<Expr>)>> {
        let ExprKind::Host(id) = &e.kind else { return None };
        let Node::Element { var, index, .. } = &self.module.nodes[*id as usize] else { return None };
        if !matches!(self.lookup(var), Some(Var::Array(_))) {
            return None;
        }
        let at = index
            .iter()
            .map(|i| Ok(Expr::new(ExprKind::Number(self.index(i, "the index")? as f64), i.span)))
            .collect::<Run<Vec<Expr>>>();
        Some(at.map(|at| (var.clone(), at)))
    }

    /// The item `name(at)` an argument `e` (an item reference) passes, `at` evaluated already.
    pub(super) fn item_argument(&self, e: &Expr, name: &str, at: &[Expr]) -> Run<Var> {
        let ExprKind::Host(id) = e.kind else { unreachable!("an item reference is a node") };
        let span = self.expr_span(e);
        self.noting_date(id, || {
            let at = at.iter().map(|e| self.index(e, "the index")).collect::<Run<Vec<i64>>>()?;
            let Some(Var::Array(a)) = self.lookup(name) else {
                return Err(self.fault_at(span, format!("{name} is not an array")));
            };
            let k = self.element_at(&a, &at).map_err(|m| self.subscript_error(span, name, m))?;
            self.gave.set(a.held(k));
            Ok(a.item(k))
        })
    }

    /// What an argument that calls the project's own Function gives, as the Function left it:
    /// an array with its bounds, an object, a Type value or a value.
    pub(super) fn call_argument(&self, e: &Expr) -> Option<Run<Var>> {
        let ExprKind::Host(id) = e.kind else { return None };
        let Node::Call { proc, args, span } = &self.module.nodes[id as usize] else { return None };
        let var = self.noting_date(id, || self.call_record(*proc, args, *span));
        Some(var.map(|var| match var {
            Var::Value(v @ Value::Array(_)) => super::value::array_var(v, self.option_base()),
            other => other,
        }))
    }

    /// The type a number argument `e` gave keeps in a Variant parameter ([MS-VBAL] 5.3.1.11),
    /// when it is not a Double.
    pub(super) fn number_type(&self, e: &Expr, var: &Var) -> Option<super::typing::Declared> {
        match var {
            Var::Value(v @ Value::Number(_)) => {
                Some(self.value_type(e, v)).filter(|ty| *ty != super::typing::Declared::Double)
            }
            _ => None,
        }
    }

    /// The item `name(at)` given what a ByRef parameter holds after the call: a value, an
    /// array with its bounds or an object (a Type is left as it was).
    pub(super) fn give_back_item(&self, name: &Rc<str>, at: &[Expr], var: Var, date: bool, span: Span) -> Run<()> {
        match var {
            Var::Array(a) => self.set_array_element(name, at, a, span),
            Var::Value(v) => self.set_element(name, at, v, date, span),
            object @ Var::Obj(_) => self.set_object_element(name, at, object, span),
            record @ Var::Record(..) if self.holds_records(name) => self.set_record_item(name, at, record, span),
            Var::Record(..) => Ok(()),
        }
    }

    pub fn bound(&self, ctx: &mut Ctx, upper: bool, of: &Expr, dim: Option<&Expr>, span: Span) -> Run<Value> {
        let d = match dim {
            Some(e) => {
                let v = ctx.eval(e);
                self.take_pending()?;
                self.number_of(&v, "the dimension").map_err(|m| self.fault_at(span, m))? as i64
            }
            None => 1,
        };
        // A variable's array, or the one a call, an item or a library function gives
        // (`UBound(Split(s, ","))`, `UBound(c(1))`), with its own bounds.
        let (name, array): (&str, Option<Var>) = match &of.kind {
            ExprKind::Name(n) => (n, self.lookup(n)),
            _ => match self.indexed_base(of)? {
                Var::Value(v @ Value::Array(_)) => ("the value", Some(super::value::array_var(v, self.option_base()))),
                other => ("the value", Some(other)),
            },
        };
        // A Variant holding no array is VBA's Type mismatch (run-time error 13), as indexing
        // one is; not error 5, which Microsoft's pages give for a bad argument value.
        let Some(Var::Array(a)) = array else {
            let mut f = self.fault_at(span, format!("Type mismatch (run-time error 13): {name} is not an array"));
            f.code = 13;
            return Err(f);
        };
        if a.dims == 0 {
            // A dynamic array before its first ReDim has no bounds ("UBound function": error 9).
            return Err(self.subscript_error(span, name, "it has no bounds yet (ReDim gives them)".into()));
        }
        // "LBound function": a dimension past the array's is "Subscript out of range" too.
        let bounds = a.bounds();
        let Some(&(lower, len)) = usize::try_from(d).ok().and_then(|d| d.checked_sub(1)).and_then(|d| bounds.get(d))
        else {
            let why = format!("it has no dimension {d} (it has {})", bounds.len());
            return Err(self.subscript_error(span, name, why));
        };
        Ok(Value::Number(if upper { lower + len as i64 - 1 } else { lower } as f64))
    }
}

/// Indexing what an expression gives: `d(k)(i)`, `c.Item(1)(2)`, `Split(s, ",")(0)`, `f()(2)`.
impl Interp<'_, '_> {
    /// `base(index)`: an item of the array, Collection or Dictionary `base` gives.
    pub(super) fn indexed_var(&self, base: &Expr, index: &[Expr], span: Span) -> Run<Var> {
        let whole = match self.indexed_base_or_item(base, index, span)? {
            Ok(item) => return Ok(item),
            Err(whole) => whole,
        };
        let whole = match whole {
            // An item added from a Range's values or a sheet function holds a plain array.
            Var::Value(v @ Value::Array(_)) => super::value::array_var(v, self.option_base()),
            other => other,
        };
        match whole {
            Var::Obj(Obj::Store(h)) => {
                let key = self.store_key(&mut self.ctx(), index, span)?;
                self.store_item(&h, &key, span)
            }
            Var::Obj(Obj::Regex(r)) => self.regex_element_item(&r, index, span),
            Var::Array(a) => {
                let at = index.iter().map(|e| self.index(e, "the index")).collect::<Run<Vec<i64>>>()?;
                let k = self.element_at(&a, &at).map_err(|m| {
                    let mut f = self.fault_at(span, format!("Subscript out of range (run-time error 9): {m}"));
                    f.code = 9;
                    f
                })?;
                self.gave.set(a.held(k));
                match a.item(k) {
                    held @ (Var::Obj(_) | Var::Array(_)) => Ok(held),
                    _ => Ok(super::value::array_var(a.data.data[k].clone(), self.option_base())),
                }
            }
            Var::Obj(Obj::Range(sheet, rect)) => self.range_item_var(sheet, rect, index, span),
            // "Range.Item property": the offsets are from the first area's top-left cell.
            Var::Obj(Obj::Areas(sheet, areas)) => self.range_item_var(sheet, areas[0], index, span),
            other => {
                let what = match other {
                    Var::Obj(o) => o.describe().to_string(),
                    Var::Record(..) => "a Type value".to_string(),
                    _ => "a value, not an array".to_string(),
                };
                let mut f = self.fault_at(span, format!("Type mismatch (run-time error 13): indexing {what}"));
                f.code = 13;
                Err(f)
            }
        }
    }

    /// `d.Items()(i)`: a Dictionary's one item, read alone (`Ok`); any other base whole, as
    /// [`Interp::indexed_base`] gives it, for the caller to index (`Err`).
    #[inline(never)]
    fn indexed_base_or_item(&self, base: &Expr, index: &[Expr], span: Span) -> Run<Result<Var, Var>> {
        if let (ExprKind::Host(id), [one]) = (&base.kind, index) {
            if self.is_keys_member(base) {
                let Node::Path(path) = &self.module.nodes[*id as usize] else { unreachable!() };
                return self.keys_or_item(path, Some((one, span)));
            }
        }
        self.indexed_base(base).map(Err)
    }

    /// What the indexed expression gives, arrays with their own bounds: a Function's result
    /// as it assigned it, a Collection's or a Dictionary's item as it was added.
    fn indexed_base(&self, base: &Expr) -> Run<Var> {
        let ExprKind::Host(id) = &base.kind else { return self.var_of(base, false) };
        match &self.module.nodes[*id as usize] {
            Node::Call { proc, args, span } => self.call_record(*proc, args, *span),
            // `d.Keys()(0)`: Keys and Items are zero-based, their items keep their types.
            Node::Path(path) if self.is_keys_member(base) => self.keys_var(path),
            Node::Path(path) => {
                let mut ctx = self.ctx();
                let last = path.links.last().filter(|l| l.name.eq_ignore_ascii_case("item") && l.args.is_some());
                if let (Some(link), true) = (last, path.links.len() > 1 || path.with) {
                    let owner = self.path_until(&mut ctx, path, path.links.len() - 1);
                    self.take_pending()?;
                    if let Obj::Store(h) = owner? {
                        let key = self.store_key(&mut ctx, &link_index(link), link.span)?;
                        return self.store_item(&h, &key, link.span);
                    }
                }
                if let Some(array) = self.array_field(&mut ctx, path)? {
                    return Ok(array);
                }
                let obj = self.path(&mut ctx, path);
                self.take_pending()?;
                match obj? {
                    o @ (Obj::Store(_) | Obj::Range(..)) => Ok(Var::Obj(o)),
                    Obj::Value(v) => Ok(super::value::array_var(v, self.option_base())),
                    other => Ok(Var::Obj(other)),
                }
            }
            _ => self.var_of(base, false),
        }
    }
}

impl Interp<'_, '_> {
    /// `p.x` or `pts(i).x` where the field is an array: the array with its own bounds
    /// (`UBound(p.x)` with `x(1 To 100)`), when the path starts at a Type variable.
    fn array_field(&self, ctx: &mut Ctx, path: &super::ast::Path) -> Run<Option<Var>> {
        Ok(self.typed_array_field(ctx, path)?.map(|(array, _)| array))
    }

    /// `TypeName(p.x)`: the array field `p.x` with its items' declared type ("Variant" for
    /// `x() As Variant`, "Double" for `x(1 To 3) As Double`); `None` for any other path.
    pub(super) fn array_field_items(&self, e: &Expr) -> Run<Option<(Var, Ty)>> {
        let ExprKind::Host(id) = &e.kind else { return Ok(None) };
        let Node::Path(path) = &self.module.nodes[*id as usize] else { return Ok(None) };
        self.typed_array_field(&mut self.ctx(), path)
    }

    /// [`Interp::array_field`] with the field's declared item type.
    fn typed_array_field(&self, ctx: &mut Ctx, path: &super::ast::Path) -> Run<Option<(Var, Ty)>> {
        let (Some(first), Some(last)) = (path.links.first(), path.links.last()) else { return Ok(None) };
        let at_record = match self.lookup(&first.name) {
            Some(Var::Record(..)) => true,
            Some(Var::Array(a)) => a.records.is_some(),
            _ => false,
        };
        if path.with || path.links.len() < 2 || last.args.is_some() || !at_record {
            return Ok(None);
        }
        let owner = self.path_until(ctx, path, path.links.len() - 1);
        self.take_pending()?;
        let Obj::Record(var, mut at) = owner? else { return Ok(None) };
        let Some(ty) = self.record_field(&var, &at).and_then(|r| match r {
            Var::Record(t, _) => Some(t),
            _ => None,
        }) else {
            return Ok(None);
        };
        let Some(i) = self.module.types[ty].field(&last.name) else { return Ok(None) };
        at.push(i);
        let items = self.module.types[ty].fields[i].1.clone();
        Ok(self.record_field(&var, &at).filter(|f| matches!(f, Var::Array(_))).map(|array| (array, items)))
    }
}

/// The type an item assigned to the array `a` takes: the variable's declared item type, or,
/// for a Variant holding a typed array (`v = a` with `Dim a() As Long`, `v = Split(…)`), the
/// array's own ([MS-VBAL] 5.4.3.1.2: the array keeps its declared type, so `v(0) = "7"`
/// stores the Long 7 and `v(0) = "abc"` is a type mismatch, error 13).
fn element_type(declared: Option<Ty>, a: &VArray) -> Option<Ty> {
    match Declared::of_ty(declared.as_ref()) {
        Declared::Variant => a.item_type.ty().or(declared),
        _ => declared,
    }
}

/// The records and their fields a write at `path` into `held` copies: every array of a Type
/// it steps into from the first shared one on (a copy of records shares the arrays their
/// fields hold, so those are copied in turn), each record counting its fields.
fn records_copied(held: &Var, path: &[usize]) -> usize {
    let (mut items, mut shared, mut at) = (0usize, false, held);
    for &i in path {
        at = match at {
            Var::Record(_, fields) => match fields.get(i) {
                Some(field) => field,
                None => break,
            },
            Var::Array(VArray { records: Some(records), .. }) => {
                shared |= Rc::strong_count(records) > 1;
                if shared {
                    let fields = match records.first() {
                        Some(Var::Record(_, fields)) => fields.len(),
                        _ => 0,
                    };
                    items = items.saturating_add(records.len().saturating_mul(1 + fields));
                }
                match records.get(i) {
                    Some(record) => record,
                    None => break,
                }
            }
            _ => break,
        };
    }
    items
}

/// A link's arguments as the index expressions of `c(i)`.
fn link_index(link: &Link) -> Vec<Expr> {
    link.args.iter().flatten().map(|a| a.value.clone()).collect()
}

pub(super) fn preserve_items(old: &VArray, new: &mut VArray) {
    let data = Rc::make_mut(&mut new.data);
    let mut objects = std::collections::HashMap::new();
    let mut held_types = std::collections::HashMap::new();
    let mut arrays = std::collections::HashMap::new();
    let mut exact = std::collections::HashMap::new();
    let mut records = new.records.take();
    for r in 0..old.data.rows.min(data.rows) {
        for c in 0..old.data.cols.min(data.cols) {
            data.data[r * data.cols + c] = old.data.get(r, c).clone();
            // A LongLong past 2^53 moves with its item (`longlong.rs`).
            if let Some(k) = old.exact_item(r * old.data.cols + c) {
                exact.insert(r * data.cols + c, k);
            }
            match old.item(r * old.data.cols + c) {
                Var::Obj(o) => _ = objects.insert(r * data.cols + c, o),
                Var::Array(a) => _ = arrays.insert(r * data.cols + c, a),
                record @ Var::Record(..) => {
                    if let Some(records) = records.as_mut() {
                        Rc::make_mut(records)[r * data.cols + c] = record;
                    }
                }
                _ => {}
            }
            match old.held(r * old.data.cols + c) {
                super::typing::Declared::Variant => {}
                held => _ = held_types.insert(r * data.cols + c, held),
            }
        }
    }
    new.objects = (!objects.is_empty()).then(|| Rc::new(objects));
    new.held_types = (!held_types.is_empty()).then(|| Rc::new(held_types));
    new.arrays = (!arrays.is_empty()).then(|| Rc::new(arrays));
    new.exact = (!exact.is_empty()).then(|| Rc::new(exact));
    new.records = records;
}

impl Interp<'_, '_> {
    /// `ReDim Preserve a(n)` growing a one-dimensional array from the same lower bound: its
    /// items grow in place, the vector's capacity doubling as needed, so that a loop growing an
    /// array one item at a time is linear (each ReDim used to copy every item: 2,000,000 steps
    /// ran for hours). Only the items added are charged to the memory budget. `false` for any
    /// other ReDim, which builds a new array.
    pub(super) fn grown_in_place(&self, name: &str, dims: &[(i64, usize)], ty: Option<&Ty>, span: Span) -> Run<bool> {
        let &[(lower, len)] = dims else { return Ok(false) };
        if matches!(ty, Some(Ty::Record(_))) {
            return Ok(false);
        }
        let grows = |var: &Var| {
            matches!(var, Var::Array(a) if a.dims == 1 && a.lower.1 == lower && a.data.rows == 1
                && a.data.cols <= len && a.data.tail.is_none())
        };
        // Taken out of its slot, the array's items are its own: growing them copies nothing
        // unless another variable shares them.
        let taken = self.with_slot(name, |slot| grows(slot.var()).then(|| slot.replace(Var::Value(Value::Blank))));
        let Some(Some(Var::Array(mut a))) = taken else { return Ok(false) };
        let added = len - a.data.cols;
        // Shared with a copy taken before (`b = a`), the items are copied first.
        let copied = if Rc::strong_count(&a.data) > 1 { super::budget::copy_bytes(&a.data) } else { 0 };
        let items = Rc::make_mut(&mut a.data);
        items.data.resize(len, default_value(ty));
        items.cols = len;
        self.with_slot(name, |slot| slot.replace(Var::Array(a)));
        self.charge(copied + (added * std::mem::size_of::<Value>()) as u64, span)?;
        Ok(true)
    }
}

/// Whether items of type `ty` are plain values a conversion gives (a number, a String, a
/// Boolean): not a Variant, an object or a `Type`.
/// The values a record holds, its records' fields counted one by one; any other variable is
/// one.
fn values_in(var: &Var) -> usize {
    match var {
        Var::Record(_, fields) => fields.iter().map(values_in).fold(0usize, usize::saturating_add).max(1),
        _ => 1,
    }
}

fn holds_values(ty: &Ty) -> bool {
    matches!(ty, Ty::Whole(_) | Ty::Number(_) | Ty::String | Ty::FixedString(_) | Ty::Boolean)
}

/// `Dim a() As Double` before its first `ReDim` or assignment: a dynamic array with no
/// bounds yet ([MS-VBAL] 5.2.3.1.3: an array variable declared without bounds is a resizable
/// array). `UBound` and an item of it are run-time error 9, as in VBA.
pub(super) fn unallocated(ty: Option<&Ty>) -> Option<VArray> {
    ty.filter(|t| holds_values(t) || matches!(t, Ty::Record(_))).map(|_| VArray {
        records: ty.filter(|t| matches!(t, Ty::Record(_))).map(|_| Rc::new(Vec::new())),
        item_type: Declared::of_ty(ty),
        ..VArray::plain(Rc::new(Array::filled(0, 0, Value::Blank)), (0, 0), 0)
    })
}

/// `Dim a() As Variant` before its first `ReDim`: an array of no dimensions yet.
pub(super) fn without_bounds() -> VArray {
    VArray { dims: 0, ..VArray::row(Rc::new(Array::filled(0, 0, Value::Blank)), 0) }
}

/// VBA's limit on an array's dimensions ("Dim statement": "up to 60 dimensions").
pub(super) const MAX_DIMENSIONS: usize = 60;

/// How deep Types may nest in a record (a field of a Type of a Type …): ncsheet's limit, as
/// for blocks, so that making, copying and dropping a record stays within the stack.
pub(super) const MAX_RECORD_NESTING: usize = 255;

/// The row-major position of `index` in an array of `shape` ((lower bound, length) per
/// dimension), or `None` when an index is outside its dimension.
fn position_in(shape: &[(i64, usize)], index: &[i64]) -> Option<usize> {
    let mut at = 0usize;
    for (&(lower, len), &i) in shape.iter().zip(index) {
        let offset = usize::try_from(i.checked_sub(lower)?).ok().filter(|&o| o < len)?;
        at = at * len + offset;
    }
    Some(at)
}

fn outside_bounds(index: &[i64]) -> String {
    let shown: Vec<String> = index.iter().map(|i| i.to_string()).collect();
    format!("index ({}) is outside the array's bounds", shown.join(", "))
}

/// Why `ReDim Preserve` cannot give `old` the bounds `dims`, if it cannot ("ReDim
/// statement": with Preserve "you can resize only the last array dimension and you can't
/// change the number of dimensions at all", and "changing the lower bound causes an
/// error"). A dynamic array with no bounds yet takes any.
pub(super) fn preserve_refusal(old: &VArray, dims: &[(i64, usize)]) -> Option<String> {
    let before = old.bounds();
    let (last, others) = before.split_last()?;
    if before.len() != dims.len() {
        return Some(format!(
            "ReDim Preserve cannot change the number of dimensions ({} to {})",
            before.len(),
            dims.len()
        ));
    }
    let (new_last, new_others) = dims.split_last().expect("as many dimensions");
    if others != new_others {
        return Some("ReDim Preserve may change only the last dimension".into());
    }
    (last.0 != new_last.0).then(|| "ReDim Preserve may change only the upper bound of the last dimension".into())
}

/// What a parameter declared with `()` (`Sub S(a() As Long)`) holds: the caller's whole
/// array, its items as the declared type holds them. A value that is no array does not
/// bind ([MS-VBAL] 5.3.1.5: such a parameter is an array; "Type mismatch: array or
/// user-defined type expected").
pub(super) fn array_param(var: Var, param: &Param) -> Result<Var, String> {
    match var {
        Var::Array(a) => Ok(Var::Array(typed_items(a, param.ty.as_ref(), &param.name)?)),
        _ => Err(format!("{} is an array parameter: its argument must be an array (type mismatch)", param.name)),
    }
}

/// An array assigned to an array variable of declared type `ty` (`h = F_Minverse(m)` with
/// `Dim h() As Double`, or one a ByRef parameter gives back): its items as that type holds
/// them, each converted as a Let of that type converts ([MS-VBAL] 5.4.3.8, "Let Statement";
/// 5.5.1.2, "Let-coercion").
pub(super) fn typed_items(mut a: VArray, ty: Option<&Ty>, name: &str) -> Result<VArray, String> {
    let Some(ty) = ty.filter(|t| holds_values(t)) else { return Ok(a) };
    if a.objects.is_some() {
        return Err(format!("{name} is an array of a declared type and cannot hold objects (type mismatch)"));
    }
    for item in Rc::make_mut(&mut a.data).data.iter_mut() {
        let Var::Value(v) = convert(Var::Value(std::mem::take(item)), Some(ty), name)? else {
            unreachable!("a value converts to a value")
        };
        *item = v;
    }
    a.held_types = None;
    a.item_type = Declared::of_ty(Some(ty));
    Ok(a)
}

/// Writing into an item of an item: `a(1)(2) = 7` where `a(1)` holds an array.
impl Interp<'_, '_> {
    /// The array variable and the index lists of `a(i)(j)…`, outermost first, when node `id`
    /// is such an item.
    fn nested_item(&self, id: u32) -> Option<(Rc<str>, Vec<&[Expr]>)> {
        let mut chain = Vec::new();
        let mut node = &self.module.nodes[id as usize];
        loop {
            match node {
                Node::Index { base, index, .. } => {
                    chain.push(index.as_slice());
                    let ExprKind::Host(inner) = base.kind else { return None };
                    node = &self.module.nodes[inner as usize];
                }
                Node::Element { var, index, .. } => {
                    chain.push(index.as_slice());
                    chain.reverse();
                    return Some((var.clone(), chain));
                }
                _ => return None,
            }
        }
    }

    pub(super) fn is_nested_item(&self, id: u32) -> bool {
        self.nested_item(id).is_some()
    }

    /// `a(i)(j) = v` / `Set a(i)(j) = obj`: the item of the array that `a(i)` holds, which
    /// is a part of `a` ([MS-VBAL] 2.2: an array item of a Variant holds the array value,
    /// and an index expression on it names its element as a variable, 5.6.13.1). The value
    /// is evaluated first, then the indexes left to right, as for `a(i) = v`.
    // Out of line: the statement executor is on every macro call's stack, and this
    // path's locals would widen each of its frames.
    #[inline(never)]
    pub(super) fn set_nested_item(&self, id: u32, value: &Expr, set: bool, span: Span) -> Run<()> {
        let (name, chain) = self.nested_item(id).expect("a nested item");
        if let Some(owner) = self.object_item_owner(&name, chain[0], span)? {
            return self.let_through_default_members(owner, &chain[1..], value, set, span);
        }
        let (item, date) = self.nested_value(value, set, span)?;
        let mut at = Vec::new();
        for index in &chain {
            at.push(index.iter().map(|e| self.index(e, "the index")).collect::<Run<Vec<i64>>>()?);
        }
        self.put_nested_in(&name, at, item, date, span)
    }

    /// What `name(i)` holds when it is an object, for `name(i)(j) = v`: the item of a
    /// Collection or a Dictionary `name` (their default member, Item), the default member of
    /// a class's object `name`, or an array's item holding an object. `None` for an array's
    /// value item, which the array path puts into.
    #[inline(never)]
    fn object_item_owner(&self, name: &str, index: &[Expr], span: Span) -> Run<Option<Var>> {
        let held = self.peek(name, |held| match held {
            Var::Obj(o @ (Obj::Store(_) | Obj::Instance(_))) => Some(Ok(Var::Obj(o.clone()))),
            Var::Array(a) if a.objects.as_ref().is_some_and(|o| !o.is_empty()) => Some(Err(a.clone())),
            _ => None,
        });
        match held.flatten() {
            Some(Ok(object)) => self.item_of(object, index, span).map(Some),
            Some(Err(array)) => {
                let at = index.iter().map(|e| self.index(e, "the index")).collect::<Run<Vec<i64>>>()?;
                let k = self.element_at(&array, &at).map_err(|m| self.subscript_error(span, name, m))?;
                Ok(Some(array.item(k)).filter(|item| matches!(item, Var::Obj(Obj::Store(_) | Obj::Instance(_)))))
            }
            None => Ok(None),
        }
    }

    /// `held(index)` read: a Collection's or a Dictionary's item, a class's default member, an
    /// array's item ([MS-VBAL] 5.6.13.1: an index expression on an object is a call of its
    /// default member).
    #[inline(never)]
    fn item_of(&self, held: Var, index: &[Expr], span: Span) -> Run<Var> {
        let mut ctx = self.ctx();
        match held {
            Var::Obj(Obj::Store(h)) => {
                let key = self.store_key(&mut ctx, index, span)?;
                self.store_item(&h, &key, span)
            }
            Var::Obj(Obj::Instance(object)) => {
                let args: Vec<Arg> = index.iter().map(|e| Arg { name: None, value: e.clone() }).collect();
                self.default_member(&mut ctx, &object, &args, span).map(super::classes::obj_var)
            }
            Var::Array(a) => {
                let at = index.iter().map(|e| self.index(e, "the index")).collect::<Run<Vec<i64>>>()?;
                let k = self.element_at(&a, &at).map_err(|m| self.subscript_error(span, "the array", m))?;
                Ok(a.item(k))
            }
            other => {
                let what = match &other {
                    Var::Obj(o) => o.describe(),
                    _ => "a value",
                };
                let mut f = self.fault_at(span, format!("Type mismatch (run-time error 13): indexing {what}"));
                f.code = 13;
                Err(f)
            }
        }
    }

    /// `dicts(0)("k") = v`, `c(1)(2) = v`, `d("a")("b") = v`: a Let (or Set) through the
    /// default member of the object an item holds, each index list but the last reading the
    /// default member on the way ([MS-VBAL] 5.4.3.8: the Let statement on an index expression
    /// whose target is an object assigns its default member; 5.6.13.1). An item that holds
    /// an array is a copy the Let would change and drop: refused, as before.
    #[inline(never)]
    fn let_through_default_members(
        &self,
        mut held: Var,
        lists: &[&[Expr]],
        value: &Expr,
        set: bool,
        span: Span,
    ) -> Run<()> {
        let Some((last, on_the_way)) = lists.split_last() else {
            return Err(self.fault_at(span, "an object's item is assigned through its default member with an index"));
        };
        for index in on_the_way {
            held = self.item_of(held, index, span)?;
        }
        match held {
            Var::Obj(Obj::Store(h)) => {
                let key = self.store_key(&mut self.ctx(), last, span)?;
                let (item, _) = self.nested_value(value, set, span)?;
                self.set_store_item(&h, &key, item, span)
            }
            Var::Obj(Obj::Instance(object)) => {
                let args: Vec<Arg> = last.iter().map(|e| Arg { name: None, value: e.clone() }).collect();
                self.set_default_member(&mut self.ctx(), &object, &args, value, span)
            }
            _ => Err(self.unsupported(
                span,
                "(…)(…) = …: the item reached holds a value, not an object; a Collection's or a Dictionary's item \
                 is given as a copy, which VBA changes and drops: take the item into a variable, change it and put \
                 it back",
            )),
        }
    }

    /// What `….(i)(j) = value` (or `Set … = value`) puts in the item, and whether it is a Date.
    fn nested_value(&self, value: &Expr, set: bool, span: Span) -> Run<(Var, bool)> {
        let item = match set {
            true => self.item_var(value)?,
            false => match self.item_given(value)? {
                Ok(array) => Var::Array(array),
                Err(v) => Var::Value(v),
            },
        };
        self.refuse_long_long_past_double(value, &item, "an item reached through another item")?;
        let date = matches!(&item, Var::Value(v) if !set && self.as_date(value, v).is_some());
        let item = match item {
            Var::Obj(Obj::Value(Value::Blank)) | Var::Value(Value::Blank) if set => Var::Obj(Obj::Value(Value::Blank)),
            Var::Value(_) | Var::Array(_) | Var::Obj(Obj::Value(_)) if set => {
                return Err(self.fault_at(span, "Set needs an object (a Range, a Worksheet, …)"))
            }
            Var::Record(..) => return Err(self.fault_at(span, "a Type value cannot be an item of a Variant's array")),
            other => other,
        };
        Ok((item, date))
    }

    /// [`Interp::set_nested_item`] once the value and the indexes are evaluated.
    fn put_nested_in(&self, name: &Rc<str>, at: Vec<Vec<i64>>, item: Var, date: bool, span: Span) -> Run<()> {
        let name = name.clone();
        match self.lookup(&name) {
            Some(Var::Array(_)) => {}
            Some(Var::Obj(Obj::Store(_))) => {
                return Err(self.unsupported(
                    span,
                    format!(
                        "{name}(…)(…) = …: a Collection's or a Dictionary's item is given as a copy, which VBA changes \
                         and drops; take the item into a variable, change it and put it back"
                    ),
                ))
            }
            _ => return Err(self.fault_at(span, format!("{name} is not an array (Dim {name}(…) first)"))),
        }
        self.charge_nested_item(&item, span)?;
        let result = self.with_slot(&name, |slot| {
            if matches!(slot.ty, Some(ref t) if !matches!(t, Ty::Variant)) {
                let why = "holds a value, not an array";
                return Err((13, format!("Type mismatch (run-time error 13): {}(…) {why}", slot.name)));
            }
            let own = slot.name.clone();
            let Var::Array(a) = slot.var_mut() else { return Err((13, format!("{own} is not an array"))) };
            self.put_nested(a, &own, &at, item, date)
        });
        self.nested_put_done(result, span, || format!("{name} is not an array (Dim {name}(…) first)"))?;
        // The copies of shared levels the put made.
        self.charge(0, span)
    }

    /// What an item put into a nested array brings, charged to the memory budget.
    fn charge_nested_item(&self, item: &Var, span: Span) -> Run<()> {
        let bytes = match item {
            Var::Value(v) => super::budget::value_bytes(v),
            Var::Array(a) => super::budget::array_brought(&a.data),
            _ => 0,
        };
        self.charge(bytes, span)
    }

    /// The end of a put into a nested array ([`Interp::put_nested`]) in the variable's slot:
    /// the object it replaced released, its error a fault at `span` with its number, and
    /// `missing`'s message where there was no such variable.
    fn nested_put_done(&self, result: Option<NestedPut>, span: Span, missing: impl FnOnce() -> String) -> Run<()> {
        match result {
            Some(Ok(old)) => old.map_or(Ok(()), |o| self.release(&Var::Obj(o))),
            Some(Err((code, m))) => {
                let mut f = self.fault_at(span, m);
                f.code = code;
                Err(f)
            }
            None => Err(self.fault_at(span, missing())),
        }
    }

    /// Puts `item` at `at` (one index list per level) in `a`, taking each inner array out
    /// while it changes so that only a shared one is copied. Gives the object it replaced.
    pub(super) fn put_nested(&self, a: &mut VArray, own: &str, at: &[Vec<i64>], item: Var, date: bool) -> NestedPut {
        let out_of_range = |m| (9, format!("Subscript out of range (run-time error 9): {own}: {m}"));
        let k = self.element_at(a, &at[0]).map_err(out_of_range)?;
        // Shared (`outer(1) = big` then `outer(1)(2) = 0`), this level's items are copied.
        if Rc::strong_count(&a.data) > 1 {
            self.owe(super::budget::copy_bytes(&a.data));
        }
        if at.len() > 1 {
            let held = a.arrays.as_mut().and_then(|arrays| Rc::make_mut(arrays).remove(&k));
            let taken = std::mem::take(&mut Rc::make_mut(&mut a.data).data[k]);
            let mut inner = match (held, super::value::array_var(taken.clone(), self.option_base())) {
                (Some(inner), _) => inner,
                (None, Var::Array(inner)) => inner,
                (None, _) => {
                    Rc::make_mut(&mut a.data).data[k] = taken;
                    return Err((13, format!("Type mismatch (run-time error 13): {own}(…) holds no array")));
                }
            };
            let old = self.put_nested(&mut inner, own, &at[1..], item, date);
            Rc::make_mut(&mut a.data).data[k] = Value::Array(inner.data.clone());
            Rc::make_mut(a.arrays.get_or_insert_with(Default::default)).insert(k, inner);
            return old;
        }
        let data = Rc::make_mut(&mut a.data);
        data.data[k] = match &item {
            Var::Value(v) => v.clone(),
            Var::Array(inner) => Value::Array(inner.data.clone()),
            _ => Value::Blank,
        };
        if let Some(arrays) = a.arrays.as_mut().filter(|o| o.contains_key(&k)) {
            Rc::make_mut(arrays).remove(&k);
        }
        a.mark_date(k, date);
        let old = a.objects.as_mut().and_then(|o| Rc::make_mut(o).remove(&k));
        match item {
            Var::Array(inner) => {
                Rc::make_mut(a.arrays.get_or_insert_with(Default::default)).insert(k, inner);
            }
            Var::Obj(Obj::Value(_)) | Var::Value(_) | Var::Record(..) => {}
            Var::Obj(o) => {
                Rc::make_mut(a.objects.get_or_insert_with(Default::default)).insert(k, o);
            }
        }
        Ok(old)
    }
}

/// The object an item held before, or the run-time error number and message.
type NestedPut = Result<Option<Obj>, (u32, String)>;

/// Writing through a Type's array field: `A(1).Arr(2)(3) = x`.
impl Interp<'_, '_> {
    /// The path `A(1).Arr(2)` (an array field of a Type variable or of an item of an array of
    /// a Type, indexed) and the index lists after it, outermost first, when node `id` is
    /// `A(1).Arr(2)(3)…`.
    fn field_nested_item(&self, id: u32) -> Option<(&super::ast::Path, Vec<&[Expr]>)> {
        let mut chain = Vec::new();
        let mut node = &self.module.nodes[id as usize];
        loop {
            match node {
                Node::Index { base, index, .. } => {
                    chain.push(index.as_slice());
                    let ExprKind::Host(inner) = base.kind else { return None };
                    node = &self.module.nodes[inner as usize];
                }
                Node::Path(path) if !chain.is_empty() && !path.with && path.links.len() > 1 => {
                    path.links.last()?.args.as_ref()?;
                    chain.reverse();
                    return Some((path, chain));
                }
                _ => return None,
            }
        }
    }

    pub(super) fn is_field_nested_item(&self, id: u32) -> bool {
        self.field_nested_item(id).is_some_and(|(path, _)| match self.lookup(&path.links[0].name) {
            Some(Var::Record(..)) => true,
            Some(Var::Array(a)) => a.records.is_some(),
            _ => false,
        })
    }

    /// `A(1).Arr(2)(3) = v`: the item of the array that item 2 of the array field `Arr` of
    /// `A(1)` holds, a part of `A` ([MS-VBAL] 5.6.13.1: an index expression on a variable's
    /// array names its element as a variable; 5.6.12: a member of a UDT value names its field).
    /// The value first, then the indexes left to right, as for `a(i)(j) = v`.
    pub(super) fn set_field_nested_item(&self, id: u32, value: &Expr, set: bool, span: Span) -> Run<()> {
        let (path, chain) = self.field_nested_item(id).expect("an item through a field");
        let (item, date) = self.nested_value(value, set, span)?;
        let field = path.links.last().expect("a field");
        let owner = self.path_until(&mut self.ctx(), path, path.links.len() - 1);
        self.take_pending()?;
        let not_field = || self.fault_at(span, format!("{} is no array field of a Type value", field.name));
        let Obj::Record(var, mut at) = owner? else { return Err(not_field()) };
        let Some(Var::Record(ty, _)) = self.record_field(&var, &at) else { return Err(not_field()) };
        at.push(self.module.types[ty].field(&field.name).ok_or_else(not_field)?);
        let mut lists =
            vec![link_index(field).iter().map(|e| self.index(e, "the index")).collect::<Run<Vec<i64>>>()?];
        for index in &chain {
            lists.push(index.iter().map(|e| self.index(e, "the index")).collect::<Run<Vec<i64>>>()?);
        }
        self.charge_nested_item(&item, span)?;
        self.copy_records_if_shared(&var, &at, span)?;
        let result = self.with_slot(&var, |slot| {
            let own: Rc<str> = format!("{}.{}", slot.name, field.name).into();
            let mut target = slot.var_mut();
            for &i in &at {
                target = match target {
                    Var::Record(_, fields) => &mut fields[i],
                    Var::Array(VArray { records: Some(records), .. }) => &mut Rc::make_mut(records)[i],
                    _ => {
                        return Err((
                            13,
                            format!("Type mismatch (run-time error 13): {own} is not a Type value's field"),
                        ))
                    }
                };
            }
            let Var::Array(a) = target else {
                return Err((13, format!("Type mismatch (run-time error 13): {own} is not an array")));
            };
            self.put_nested(a, &own, &lists, item, date)
        });
        self.nested_put_done(result, span, || format!("{var} is not a variable"))?;
        self.charge(0, span)
    }
}

/// An argument of a worksheet function: a one-dimensional array whose items are
/// one-dimensional arrays of one length reads as a two-dimensional array, row i the i-th
/// inner array, as Excel reads a VBA array of arrays (`Application.Transpose(Array(Array(1,
/// 2), Array(3, 4)))` is {1,3;2,4}). Inner arrays of different lengths are refused.
impl Interp<'_, '_> {
    pub(super) fn worksheet_function_argument(&self, ctx: &mut Ctx, arg: &Expr, span: Span) -> Run<Operand> {
        let operand = ctx.operand(arg);
        self.take_pending()?;
        let Operand::Value(Value::Array(outer)) = &operand else { return Ok(operand) };
        let inner: Vec<&Array> = outer
            .data
            .iter()
            .filter_map(|v| match v {
                Value::Array(a) => Some(&**a),
                _ => None,
            })
            .collect();
        if outer.rows != 1 || inner.is_empty() || inner.len() != outer.data.len() {
            return Ok(operand);
        }
        let width = inner[0].cols;
        if inner.iter().any(|a| a.rows != 1 || a.cols != width) {
            return Err(self.fault_at(
                span,
                "an array of arrays is a worksheet function's argument only when its arrays are rows of one length",
            ));
        }
        let data = inner.iter().flat_map(|a| a.data.iter().cloned()).collect();
        Ok(Operand::Value(Value::Array(Rc::new(Array::new(inner.len(), width, data)))))
    }
}
