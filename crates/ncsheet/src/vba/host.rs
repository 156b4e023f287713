//! The bridge to the one evaluator: the interpreter is its [`Env`] (cells, read through the
//! macro's workbook) and its [`Host`] (macro variables and the nodes only macros have).

use std::rc::Rc;

use crate::eval::evaluator::Host;
use crate::eval::{Array, Ctx, Env, Note, Operand, UserCall, Value, XlError};
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::{BinOp, Expr, ExprKind, SheetId};

use super::ast::{Inspect, Node, Path, Span};
use super::interp::{Fault, Interp, Run};
use super::typing::Declared;
use super::value::{Obj, VArray, Var};
use super::ErrorKind;

impl Env for Interp<'_, '_> {
    /// A function a formula of the macro calls (`Evaluate("Twice(2)")`, `[Twice(2)]`): a
    /// public Function of the macro's own code, as Excel's Evaluate calls the project's, else
    /// the workbook's (it was `#NAME?`, Error 2029, with no word why). A failed call is
    /// `#VALUE!` with its reason, as in a cell.
    fn call_user_function(&self, cells: &dyn Env, call: &UserCall) -> Option<Result<Value, Note>> {
        let Some(proc) = self.formula_function(call.name) else {
            return self.wb.borrow().call_user_function(cells, call);
        };
        let function = self.module.procs[proc].name.to_string();
        let args = match super::udf::formula_arguments(call.args, &function, || {
            self.wb.borrow().cell_name(call.caller.0, call.caller.1)
        }) {
            Ok(args) => args,
            Err(note) => return Some(Err(note)),
        };
        Some(self.call_from_formula(proc, args).map_err(|f| Note { error: XlError::Value, message: f.message }))
    }

    fn value(&self, sheet: SheetId, pos: Pos) -> Value {
        match self.cells {
            Some(cells) => cells.value(sheet, pos),
            None => self.wb.borrow().value(sheet, pos),
        }
    }

    fn for_each_value(&self, sheet: SheetId, rect: Rect, f: &mut dyn FnMut(Pos, &Value)) {
        // Collected first: `f` may run macro code that writes cells.
        let mut items = Vec::new();
        let mut keep = |p: Pos, v: &Value| items.push((p, v.clone()));
        match self.cells {
            Some(cells) => cells.for_each_value(sheet, rect, &mut keep),
            None => self.wb.borrow().for_each_value(sheet, rect, &mut keep),
        }
        // Each cell read is work (`WorksheetFunction.Sum` of a million cells in a loop).
        self.add_work(items.len() as u64);
        for (p, v) in items {
            f(p, &v);
        }
    }

    fn used_rect(&self, sheet: SheetId) -> Option<Rect> {
        match self.cells {
            Some(cells) => cells.used_rect(sheet),
            None => Env::used_rect(&**self.wb.borrow(), sheet),
        }
    }

    fn used_rect_for(&self, sheet: SheetId, rect: Rect) -> Option<Rect> {
        match self.cells {
            Some(cells) => cells.used_rect_for(sheet, rect),
            None => Env::used_rect_for(&**self.wb.borrow(), sheet, rect),
        }
    }

    fn defined_name(&self, name: &str, sheet: SheetId) -> Option<(Rc<Expr>, SheetId)> {
        self.wb.borrow().defined_name(name, sheet)
    }

    fn table_part(
        &self,
        r: &crate::formula::ast::TableRef,
        sheet: SheetId,
        pos: Pos,
    ) -> Result<(SheetId, Rect), crate::formula::ast::XlError> {
        self.wb.borrow().table_part(r, sheet, pos)
    }

    fn spill_rect(&self, sheet: SheetId, pos: Pos) -> Option<Rect> {
        match self.cells {
            Some(cells) => cells.spill_rect(sheet, pos),
            None => self.wb.borrow().spill_rect(sheet, pos),
        }
    }

    fn sheet_count(&self) -> usize {
        self.wb.borrow().sheet_count()
    }

    fn sheet_name(&self, sheet: SheetId) -> Option<String> {
        Env::sheet_name(&**self.wb.borrow(), sheet)
    }

    fn tab_position(&self, sheet: SheetId) -> usize {
        Env::tab_position(&**self.wb.borrow(), sheet)
    }

    fn sheets_spanned(&self, first: SheetId, last: SheetId) -> Vec<SheetId> {
        Env::sheets_spanned(&**self.wb.borrow(), first, last)
    }

    fn sheet_id(&self, name: &str) -> Option<SheetId> {
        self.wb.borrow().sheet_id(name)
    }

    fn formula_text(&self, sheet: SheetId, pos: Pos) -> Option<String> {
        self.wb.borrow().formula_text(sheet, pos)
    }

    fn is_subtotal(&self, sheet: SheetId, pos: Pos) -> bool {
        self.wb.borrow().is_subtotal(sheet, pos)
    }

    fn date_system(&self) -> crate::eval::dates::DateSystem {
        self.wb.borrow().date_system()
    }

    // A function called from a cell reads the calling workbook's clock and sequence.
    fn now(&self) -> f64 {
        match self.cells {
            Some(cells) => cells.now(),
            None => {
                let wb = self.wb.borrow();
                wb.settings().now(wb.date_system())
            }
        }
    }

    fn next_random(&self) -> f64 {
        match self.cells {
            Some(cells) => cells.next_random(),
            None => self.wb.borrow().settings().next_random(),
        }
    }

    fn vba_rnd(&self, n: f64) -> f64 {
        match self.cells {
            Some(cells) => cells.vba_rnd(n),
            None => self.wb.borrow().settings().vba_rnd.draw(n),
        }
    }

    // `Evaluate` and WorksheetFunction have the workbook's LAMBDA budget, as its cells do.
    fn lambda_work_limit(&self) -> u64 {
        match self.cells {
            Some(cells) => cells.lambda_work_limit(),
            None => self.wb.borrow().settings().lambda_work_limit(),
        }
    }

    fn locale(&self) -> crate::eval::Locale {
        match self.cells {
            Some(cells) => cells.locale(),
            None => {
                let wb = self.wb.borrow();
                wb.settings().locale_in_force(wb.date_system())
            }
        }
    }
}

impl Host for Interp<'_, '_> {
    fn variable(&self, name: &str) -> Option<Operand> {
        // A value or an array's items are read in place: copying the whole variable first
        // cost a sort's inner loop a fifth of its time.
        let plain = self.peek(name, |held| match held {
            Var::Value(v) | Var::Obj(Obj::Value(v)) => Some(Operand::Value(v.clone())),
            Var::Array(a) => Some(Operand::Value(Value::Array(a.data.clone()))),
            Var::Obj(Obj::Range(sheet, rect)) => Some(Operand::Ref(*sheet, *rect)),
            Var::Obj(Obj::Areas(sheet, areas)) => Some(super::areas::areas_operand(*sheet, areas)),
            _ => None,
        });
        if let Some(Some(operand)) = plain {
            return Some(operand);
        }
        Some(match self.lookup(name) {
            None => Operand::Value(Value::Blank),
            Some(Var::Value(v)) => Operand::Value(v),
            Some(Var::Array(a)) => Operand::Value(Value::Array(a.data)),
            Some(Var::Obj(Obj::Range(sheet, rect))) => Operand::Ref(sheet, rect),
            Some(Var::Obj(Obj::Value(v))) => Operand::Value(v),
            // A Match reads as its Value, its default property ("Match Object").
            Some(Var::Obj(Obj::Regex(r))) if r.default_value().is_some() => {
                Operand::Value(r.default_value().unwrap_or_default())
            }
            // An object of a class with a default member reads as that member's value.
            Some(Var::Obj(Obj::Instance(object))) if self.has_default_member(&object) => {
                self.instance_operand(&object).unwrap_or_else(|fault| {
                    self.park(fault);
                    Operand::Value(Value::Error(XlError::Value))
                })
            }
            Some(Var::Record(..)) => {
                self.park(self.fault(format!("{name} is a Type value: use its fields ({name}.Field)")));
                Operand::Value(Value::Error(XlError::Value))
            }
            Some(Var::Obj(other)) => {
                self.park(self.fault(format!("{name} is {}, not a value", other.describe())));
                Operand::Value(Value::Error(XlError::Value))
            }
        })
    }

    fn node(&self, ctx: &mut Ctx, id: u32) -> Operand {
        if self.pending.borrow().is_some() || self.ended.get() {
            return Operand::Value(Value::Error(XlError::Value));
        }
        // What the node gave is a Date or not until it is evaluated again.
        match self.noting_date(id, || self.node_operand(ctx, id)) {
            Ok(operand) => operand,
            Err(fault) => {
                self.park(fault);
                Operand::Value(Value::Error(XlError::Value))
            }
        }
    }

    fn text_limit(&self) -> usize {
        self.options.max_string
    }

    fn arithmetic(&self, op: BinOp, operands: (&Expr, &Expr), values: (&Value, &Value), result: Value) -> Value {
        self.forget_widening(operands.0);
        self.forget_exact(operands.0, [values.0, values.1, &result]);
        if self.refused_array_operand(op, operands, values) {
            return Value::Error(XlError::Value);
        }
        if op == BinOp::Concat {
            if let Some(fault) = self.concat_error(operands, values) {
                self.park(fault);
                return Value::Error(XlError::Value);
            }
            // The joined text is a copy of the left one (work counted for tests: `Work`).
            if let (Value::Text(left), Value::Text(_)) = (values.0, &result) {
                super::count(&super::TEXT_COPIED, left.len() as u64);
            }
            return self
                .concat_dates(operands, values)
                .or_else(|| self.concat_singles(operands, values))
                .or_else(|| self.concat_long_longs(operands, values))
                .or_else(|| concat_booleans(values))
                .or_else(|| concat_small_numbers(values))
                .unwrap_or(result);
        }
        if let Some(v) = self.long_long_comparison(op, operands, values) {
            return v;
        }
        match self.vba_comparison(op, operands, values) {
            Some(Ok(v)) => return v,
            Some(Err(fault)) => {
                self.park(fault);
                return Value::Error(XlError::Value);
            }
            None => {}
        }
        // "+ operator" (Office VBA reference): two Strings, or two Variants holding Strings,
        // are concatenated ("36" + Chr(34) is 36"), where a formula would add "1" + "2" to 3.
        if let (BinOp::Add, (Value::Text(a), Value::Text(b))) = (op, values) {
            return Value::text(format!("{a}{b}"));
        }
        // "+ operator": "One expression is an Empty Variant: Return the remaining expression
        // unchanged as result", so `Empty + "1"` is the String "1", not the number 1.
        if let (BinOp::Add, (Value::Blank, Value::Text(t)) | (Value::Text(t), Value::Blank)) = (op, values) {
            return Value::Text(t.clone());
        }
        let read = vba_operands(op, values, &result, self.date_system());
        let (values, result) = match &read {
            Some((a, b, computed)) => ((a, b), computed.clone()),
            None => (values, result),
        };
        let result = super::operators::zero_to_the_zero(op, values).unwrap_or(result);
        match self.long_long_arithmetic(op, operands, values, &result) {
            Some(Ok(v)) => return v,
            Some(Err(fault)) => {
                self.park(fault);
                return Value::Error(XlError::Num);
            }
            None => {}
        }
        match self.overflow(op, operands, values, &result).or_else(|| self.raised_error(op, operands, values, &result))
        {
            Some(fault) => {
                self.park(fault);
                Value::Error(XlError::Num)
            }
            None => match self.in_its_type(op, operands, values, result) {
                Ok(v) => v,
                Err(fault) => {
                    self.park(fault);
                    Value::Error(XlError::Num)
                }
            },
        }
    }

    fn shown_number(&self, e: &Expr, value: &Value) -> Option<f64> {
        self.as_single(e, value)
    }

    fn date_text(&self, e: &Expr, value: &Value) -> Option<String> {
        self.as_date(e, value).map(super::value::date_text)
    }

    fn long_long_text(&self, e: &Expr, value: &Value) -> Option<String> {
        self.long_long_text(e, value)
    }

    fn item_texts(&self, e: &Expr, items: &Rc<Array>) -> Option<Rc<Array>> {
        // The array a variable holds, known by its items being the very ones evaluated.
        let ExprKind::Name(name) = &e.kind else { return None };
        self.peek(name, |held| match held {
            Var::Array(a) if Rc::ptr_eq(&a.data, items) => self.items_written(a),
            _ => None,
        })
        .flatten()
    }

    fn decimal_whole(&self, e: &Expr, value: &Value, floor: bool) -> Option<f64> {
        self.decimal_whole(e, value, floor)
    }

    fn chose(&self, args: &[Expr], index: usize, value: &Value) {
        self.note_iif_branch(args, index, value);
        if let Some(condition) = args.first() {
            self.iif_branch.set((condition as *const Expr as usize, condition.span.start as usize, index));
        }
    }

    fn negation(&self, operand: &Expr, result: Value) -> Value {
        self.forget_widening(operand);
        self.forget_exact(operand, [&result; 3]);
        if self.refused_array_negation(operand, &result) {
            return Value::Error(XlError::Value);
        }
        match self.long_long_negation(operand, &result) {
            Some(Ok(v)) => return v,
            Some(Err(fault)) => {
                self.park(fault);
                return Value::Error(XlError::Num);
            }
            None => {}
        }
        match self.negation_mismatch(operand, &result).or_else(|| self.negation_overflow(operand, &result)) {
            Some(fault) => {
                self.park(fault);
                Value::Error(XlError::Num)
            }
            None => result,
        }
    }

    fn integer_bits(&self, e: &Expr, value: &Value) -> Option<u32> {
        self.integer_bits(e, value)
    }

    fn logical_not(&self, operand: &Expr, result: Value) -> Value {
        self.not_in_its_type(operand, result)
    }

    fn option_compare_text(&self) -> bool {
        self.text_compare()
    }

    fn work(&self, units: u64) {
        self.add_work(units);
    }

    fn may_run_code(&self, id: u32) -> bool {
        match &self.module.nodes[id as usize] {
            // `Len(t)`: its call runs code only where its argument does.
            Node::Inspect { what: Inspect::Len { .. }, arg, .. } => {
                let mut found = false;
                arg.visit(&mut |e| found |= matches!(e.kind, ExprKind::Host(id) if self.may_run_code(id)));
                found
            }
            _ => true,
        }
    }

    fn text_length(&self, name: &str) -> Option<usize> {
        self.with_slot(name, |s| s.growing_chars()).flatten()
    }

    fn growing_text(&self, name: &str) -> Option<Rc<String>> {
        self.with_slot(name, |s| s.growing_text()).flatten()
    }

    fn raise(&self, number: u32, message: &str) {
        let mut f = self.fault(message);
        f.code = number;
        self.park(f);
    }

    fn text_too_long(&self, limit: usize) {
        let hint = self.options.raise_hint("raise it with --max-string");
        let mut f =
            self.fault(format!("a string longer than {limit} characters (ncsheet's limit for macro strings; {hint})"));
        f.kind = ErrorKind::Limit;
        self.park(f);
    }

    fn array_item_limit(&self) -> usize {
        self.options.max_array_items
    }

    /// The same error as `Dim` and `ReDim` past the limit give (`Split` of a long text).
    fn array_too_large(&self, items: usize, limit: usize) {
        let why = if limit < self.options.max_array_items {
            "ncsheet's limit for an array a function makes".to_string()
        } else {
            format!("ncsheet's limit; {}", self.options.raise_hint("raise it with --max-array-items"))
        };
        let mut f = self.fault(format!("an array of {items} items passes the limit of {limit} ({why})"));
        f.kind = ErrorKind::Limit;
        self.park(f);
    }
}

/// `"on " & True` with a Boolean operand: VBA's "True"/"False" (the "& operator" converts it to
/// a String as CStr does), where the formula language's `&` would give "TRUE".
fn concat_booleans((x, y): (&Value, &Value)) -> Option<Value> {
    if !matches!(x, Value::Bool(_)) && !matches!(y, Value::Bool(_)) {
        return None;
    }
    let text = |v: &Value| match v {
        Value::Null => Some("".into()),
        v => crate::eval::functions::vba::vba_text(v).ok(),
    };
    Some(Value::text(format!("{}{}", text(x)?, text(y)?)))
}

/// `"1d2" + 0`, `"&H10" * 1`, `True + 1`: arithmetic let-coerces a String operand to a number
/// as CDbl reads it ([MS-VBAL] 5.6.9.3 and 5.5.1.2.1), a `D` exponent or an `&H`/`&O` literal
/// too, where the formula's reading gave `#VALUE!`, and a Boolean to -1 or 0 (5.5.1.2.1: True
/// is -1), where the formula's TRUE is 1: the operands read so and the result computed again.
/// `None` when no operand needed VBA's reading.
fn vba_operands(
    op: BinOp,
    (a, b): (&Value, &Value),
    result: &Value,
    dates: crate::eval::dates::DateSystem,
) -> Option<(Value, Value, Value)> {
    let arithmetic =
        matches!(op, BinOp::Pow | BinOp::Mul | BinOp::Div | BinOp::Add | BinOp::Sub | BinOp::Mod | BinOp::IntDiv);
    let boolean = matches!(a, Value::Bool(_)) || matches!(b, Value::Bool(_));
    if !arithmetic || !(boolean || matches!(result, Value::Error(XlError::Value))) {
        return None;
    }
    let read = |v: &Value| match v {
        Value::Text(t) => crate::eval::functions::vba::vba_number_text(t).map(Value::Number),
        Value::Bool(b) => Some(Value::Number(if *b { -1.0 } else { 0.0 })),
        other => Some(other.clone()),
    };
    let (a, b) = (read(a)?, read(b)?);
    let computed = crate::eval::evaluator::binary(op, &a, &b, dates);
    Some((a, b, computed))
}

/// `"x" & 1.5E-7`: VBA writes a number below 1E-04 in E notation (`1.5E-07`, its CStr),
/// where the formula's `&` writes `0.00000015`; everywhere else the two texts agree, and
/// this is `None`.
fn concat_small_numbers((x, y): (&Value, &Value)) -> Option<Value> {
    let small = |v: &Value| matches!(v, Value::Number(n) if *n != 0.0 && n.abs() < 1e-4);
    if !small(x) && !small(y) {
        return None;
    }
    let text = |v: &Value| match v {
        Value::Null => Some("".into()),
        v => crate::eval::functions::vba::vba_text(v).ok(),
    };
    Some(Value::text(format!("{}{}", text(x)?, text(y)?)))
}

/// What an object variable holds before `Set` or after `Set x = Nothing`: no object.
pub(super) fn is_nothing(var: &Var) -> bool {
    matches!(var, Var::Value(Value::Blank) | Var::Obj(Obj::Value(Value::Blank)))
}

impl Interp<'_, '_> {
    /// `"on " & d` with a Date operand: the date's text, not its day count ([MS-VBAL]
    /// 5.6.9.4, `&` let-coerces each operand to String). `None` when neither is a Date.
    fn concat_dates(&self, (a, b): (&Expr, &Expr), (x, y): (&Value, &Value)) -> Option<Value> {
        if !matches!(x, Value::Number(_)) && !matches!(y, Value::Number(_)) {
            return None;
        }
        let (dx, dy) = (self.as_date(a, x), self.as_date(b, y));
        if dx.is_none() && dy.is_none() {
            return None;
        }
        let text = |date: Option<f64>, v: &Value| match (date, v) {
            (Some(d), _) => Some(super::value::date_text(d)),
            (None, Value::Null) => Some(String::new()),
            (None, v) => crate::eval::functions::vba::vba_text(v).ok().map(|t| t.to_string()),
        };
        Some(Value::text(format!("{}{}", text(dx, x)?, text(dy, y)?)))
    }

    pub(super) fn park(&self, fault: Fault) {
        let mut pending = self.pending.borrow_mut();
        if pending.is_none() {
            *pending = Some(fault);
        }
    }

    fn node_operand(&self, ctx: &mut Ctx, id: u32) -> Run<Operand> {
        match &self.module.nodes[id as usize] {
            Node::Call { proc, args, span } => self.call(ctx, *proc, args, *span).map(Operand::Value),
            Node::Path(path) => {
                let obj = self.path(ctx, path)?;
                self.operand_of(obj, path.span)
            }
            Node::Element { var, index, span } => self.element(ctx, var, index, *span),
            Node::Bound { upper, of, dim, span } => {
                self.bound(ctx, *upper, of, dim.as_ref(), *span).map(Operand::Value)
            }
            Node::Evaluate { expr, .. } => Ok(Ctx::new(self, self.unqualified_sheet(), Pos::new(0, 0)).operand(expr)),
            Node::Is { object, other, .. } => {
                let object = self.var_of(object, true)?;
                let same = match other {
                    None => is_nothing(&object),
                    Some(other) => {
                        let other = self.var_of(other, true)?;
                        match (&object, &other) {
                            (Var::Obj(a), Var::Obj(b)) => a == b,
                            (a, b) => is_nothing(a) && is_nothing(b),
                        }
                    }
                };
                Ok(Operand::Value(Value::Bool(same)))
            }
            Node::TypeOf { object, ty, .. } => {
                let object = self.var_of(object, true)?;
                Ok(Operand::Value(Value::Bool(self.is_of_type(&object, ty))))
            }
            Node::Inspect { what, arg, .. } => self.inspect(*what, arg).map(Operand::Value),
            Node::Null => Ok(Operand::Value(Value::Null)),
            Node::Empty | Node::Nothing => Ok(Operand::Value(Value::Blank)),
            Node::SheetArg { arg, span } => self.worksheet_function_argument(ctx, arg, *span),
            Node::Members { base, path } => {
                let obj = self.members_of(ctx, base, path)?;
                self.operand_of(obj, path.span)
            }
            Node::Index { base, index, span } => match self.indexed_var(base, index, *span)? {
                Var::Obj(obj) => self.operand_of(obj, *span),
                Var::Value(v) => Ok(Operand::Value(v)),
                Var::Array(a) => Ok(Operand::Value(Value::Array(a.data))),
                Var::Record(..) => {
                    Err(self.fault_at(*span, "the item is a Type value: assign it to a variable of the Type"))
                }
            },
            Node::New { span, .. } => Err(self.fault_at(*span, "New makes an object: assign it with Set")),
            Node::SheetCall { call, name, span } => match ctx.operand(call) {
                Operand::Value(Value::Error(e)) => {
                    let why = format!("Unable to get the {name} property of the WorksheetFunction class ({e})");
                    Err(self.error_1004(*span, why))
                }
                other => Ok(other),
            },
            Node::ZeroBasedArray { call } => Ok(ctx.operand(call)),
            Node::Through { object, call } => self.call_through(ctx, object, call),
        }
    }

    /// [`Node::Through`]: the object whose Application is named, then the call. Its own
    /// function, so the frame of every node read holds none of this.
    #[inline(never)]
    fn call_through(&self, ctx: &mut Ctx, object: &Path, call: &Expr) -> Run<Operand> {
        let obj = self.path(ctx, object)?;
        self.alive(obj, object.span)?;
        Ok(ctx.operand(call))
    }

    /// The worksheet function's call a [`Node::SheetCall`] `e` makes (what its result is read
    /// as, `library.rs`); `e` itself for any other expression.
    pub(super) fn sheet_call_inner<'e>(&'e self, e: &'e Expr) -> &'e Expr {
        match &e.kind {
            crate::formula::ast::ExprKind::Host(id) => match &self.module.nodes[*id as usize] {
                Node::SheetCall { call, .. } | Node::ZeroBasedArray { call } => call,
                Node::Through { call, .. } => self.sheet_call_inner(call),
                _ => e,
            },
            _ => e,
        }
    }

    pub fn operand_of(&self, obj: Obj, span: Span) -> Run<Operand> {
        match obj {
            Obj::Value(v) => Ok(Operand::Value(v)),
            Obj::Range(sheet, rect) => Ok(Operand::Ref(sheet, rect)),
            // "Range.Rows property": a Range of the same cells, so `v = r.Rows` reads r's values.
            Obj::Lines(sheet, rect, _) => Ok(Operand::Ref(sheet, rect)),
            Obj::Areas(sheet, areas) => Ok(super::areas::areas_operand(sheet, &areas)),
            // `If Err Then`: Err's default member is its Number.
            Obj::Err => Ok(Operand::Value(Value::Number(self.err.borrow().number as f64))),
            // A Match reads as its default member, Value ("Match Object").
            Obj::Regex(r) if r.default_value().is_some() => Ok(Operand::Value(r.default_value().unwrap_or_default())),
            Obj::Unkept(what) => Err(self.unkept_read(&what, span)),
            Obj::Instance(object) if self.has_default_member(&object) => self.instance_operand(&object),
            other => Err(self.fault_at(span, format!("{} is not a value", other.describe()))),
        }
    }
}

impl Interp<'_, '_> {
    /// The public Function of the macro's code that a formula's call of `name` means
    /// (`Twice`, `Module1.Twice`), as `Application.Run` finds a procedure.
    fn formula_function(&self, name: &str) -> Option<usize> {
        let proc = self.run_target(name)?;
        let p = &self.module.procs[proc];
        (p.kind == super::ast::ProcKind::Function && p.public).then_some(proc)
    }
}

impl Interp<'_, '_> {
    /// The items of `a` with each number its type writes otherwise than a Double made that
    /// text ([MS-VBAL] 5.5.1.2.4, Let-coercion to String): a Single its seven digits, a Date
    /// its date, a Currency its four places, a LongLong every digit. An array keeps each
    /// item's type (its declared item type, or the type a Variant item holds), so
    /// `Join(v, ",")` of `v(0) = CSng(1 / 3)` is "0.3333333", as `CStr(v(0))` is. `None`
    /// where no item is such, without a look at the items when the array can hold none.
    fn items_written(&self, a: &VArray) -> Option<Rc<Array>> {
        let apart = |ty| matches!(ty, Declared::Single | Declared::Date | Declared::Currency | Declared::LongLong);
        if a.held_types.is_none() && a.exact.is_none() && !apart(a.item_type) {
            return None;
        }
        let mut written: Option<Vec<Value>> = None;
        for (k, item) in a.data.data.iter().enumerate() {
            let Value::Number(n) = *item else { continue };
            let held = a.held(k);
            let text = match a.exact_item(k) {
                // The integer kept past 2^53, while it still stands for the item's double.
                Some(whole) if whole as f64 == n => Some(whole.to_string()),
                _ if held == Declared::LongLong => super::longlong::long_long_digits(n),
                _ => self.held_type_text(held, n),
            };
            if let Some(text) = text {
                written.get_or_insert_with(|| a.data.data.clone())[k] = Value::text(text);
            }
        }
        let data = written?;
        Some(Rc::new(Array { rows: a.data.rows, cols: a.data.cols, data, tail: a.data.tail.clone() }))
    }
}
