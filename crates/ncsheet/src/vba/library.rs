//! VBA library statements and functions that need the interpreter, not only values:
//! `Stop`, `Randomize`, `Erase`, `Error n`, and `VarType` / `IsMissing`, which read a variable's
//! declaration ("VarType function", "IsMissing function", "Erase statement", "Randomize
//! statement", "Stop statement" in the Office VBA language reference).

use std::rc::Rc;

use crate::eval::functions::vba::{errors, var_type_of};
use pest::iterators::Pair;

use crate::eval::functions::Registry;
use crate::eval::{Array, Env, Operand, Value};
use crate::formula::ast::{BinOp, Expr, ExprKind};
use crate::formula::parse::{FunctionTable, Rule};

use super::ast::{Class, Inspect, Link, Node, Span, StmtKind, Target, Ty};
use super::interp::{Fault, Interp, Run};
use super::parser::{Build, Res};
use super::resolve::lower_bare;
use super::typing::Declared;
use super::value::{default_value, print_text, range_var, Obj, VArray, Var};

/// The error code of a `Stop`: no `On Error` traps it (VBA's Stop is no error but a pause).
pub(super) const STOP: u32 = u32::MAX;

/// vbArray, added to the items' VarType for an array.
const VB_ARRAY: f64 = 8192.0;
/// vbVariant: an untyped array's items.
const VB_VARIANT: f64 = 12.0;
/// vbError: what a left-out Optional Variant holds.
const VB_ERROR: f64 = 10.0;
/// vbObject: an object (a Collection, a Dictionary, a Range without a value, Nothing).
const VB_OBJECT: f64 = 9.0;

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

    /// `Randomize [seed]` ("Randomize statement"): reseeds VBA's generator, the workbook's
    /// (`Settings::vba_rnd`), from the number, or from `Timer` without one.
    pub(super) fn randomize(&self, seed: Option<&Expr>) -> Run<()> {
        match seed {
            Some(e) => {
                let v = self.eval(e)?;
                let number = crate::eval::coerce::to_number(&v, self.date_system())
                    .map_err(|err| self.fault_at(self.expr_span(e), format!("Randomize needs a number, not {err}")))?;
                self.wb.borrow().settings().vba_rnd.randomize(number);
            }
            None => {
                let now = self.now();
                let timer = ((now - now.floor()) * 86400.0) as f32;
                self.wb.borrow().settings().vba_rnd.randomize_from_timer(timer);
            }
        }
        Ok(())
    }

    /// `Error n` ([MS-VBAL] 5.4.4.3; "Error statement"): run-time error n, raised as VBA
    /// raises it: Err.Number n, Err.Description the Error function's message for n. n is
    /// passed as a Long, rounded half to even ([MS-VBAL] 5.5.1.2.1); one outside 1 to 65535
    /// is no error number ("Raise method"): error 5, Invalid procedure call or argument.
    pub(super) fn error_statement(&self, e: &Expr) -> Fault {
        let n = match self.number(e, "the Error statement's number") {
            Ok(n) => n.round_ties_even(),
            Err(fault) => return fault,
        };
        let (number, why) = match n {
            1.0..=65535.0 => (n as u32, "raised by the Error statement".to_string()),
            _ => (5, format!("Error {n}: an error number is from 1 to 65535")),
        };
        let mut fault = self.fault_at(self.expr_span(e), errors::message(number, why));
        fault.code = number;
        fault
    }

    /// `Erase a, b`: every item of a fixed-size array back to its type's default (0, "",
    /// False, Empty), its bounds kept; a dynamic array freed ("Erase statement": "Erase frees
    /// the memory used by dynamic arrays. Before your program can refer to the dynamic array
    /// again, it must redeclare the array variable's dimensions by using a ReDim statement").
    pub(super) fn erase(&self, names: &[Rc<str>], span: Span) -> Run<()> {
        for name in names {
            if self.free_dynamic_array(name)? {
                continue;
            }
            let ty = self.with_slot(name, |slot| slot.ty.clone()).flatten();
            let record = match ty {
                Some(Ty::Record(_)) => Some(self.default_var(ty.as_ref())?),
                _ => None,
            };
            let erased = self.with_slot(name, |slot| {
                let fill = default_value(slot.ty.as_ref());
                match slot.var_mut() {
                    Var::Array(a) => {
                        // Shared (`b = a`), the old items stay and the new ones are more memory.
                        if Rc::strong_count(&a.data) > 1 {
                            self.owe(super::budget::copy_bytes(&a.data));
                        }
                        a.data = Rc::new(Array::filled(a.data.rows, a.data.cols, fill));
                        // An array of objects holds Nothing again ("Erase statement"), an
                        // array of a Type the Type's defaults.
                        a.objects = None;
                        if let (Some(records), Some(record)) = (a.records.as_mut(), record) {
                            Rc::make_mut(records).fill(record);
                        }
                        true
                    }
                    _ => false,
                }
            });
            if erased != Some(true) {
                return Err(self.fault_at(span, format!("Erase {name}: {name} is not an array (type mismatch)")));
            }
            self.charge(0, span)?;
        }
        Ok(())
    }

    /// Frees `name` when it is a dynamic array (`Dim a() As Long` … `ReDim a(5)`): it goes
    /// back to an array without bounds, as its declaration left it, so that `UBound(a)` and
    /// `a(1)` are error 9 until the next ReDim. False for anything else, which Erase resets
    /// item by item. An array parameter is reset, not freed: the caller's array may be a
    /// fixed-size one, whose bounds VBA keeps.
    fn free_dynamic_array(&self, name: &str) -> Run<bool> {
        if self.is_parameter(name) {
            return Ok(false);
        }
        let freed = self.with_slot(name, |slot| {
            if slot.fixed || !matches!(slot.var(), Var::Array(a) if a.dims > 0) {
                return None;
            }
            let empty = super::arrays::unallocated(slot.ty.as_ref()).unwrap_or_else(super::arrays::without_bounds);
            Some(slot.replace(Var::Array(empty)))
        });
        match freed.flatten() {
            // The objects only the freed items held are terminated, as at ReDim.
            Some(old) => self.release(&old).map(|_| true),
            None => Ok(false),
        }
    }

    /// Whether `name` is a parameter of the running procedure.
    fn is_parameter(&self, name: &str) -> bool {
        let Some(proc) = self.frames.borrow().last().map(|f| f.proc) else { return false };
        self.module.procs.get(proc).is_some_and(|p| p.params.iter().any(|q| q.name.eq_ignore_ascii_case(name)))
    }

    /// `Application.Run "Proc", args…` ("Application.Run method (Excel)"): runs the project's
    /// Sub or Function named by the text (`"Module1.Proc"` and `"'Book.xlsm'!Proc"` name it
    /// too), its arguments passed by value; a Function's value is Run's. No such procedure is
    /// Excel's run-time error 1004, a wrong count of arguments VBA's 449 or 450.
    pub(super) fn application_run(&self, link: &Link) -> Run<Obj> {
        let args = link.args.as_deref().unwrap_or(&[]);
        let Some(first) = args.first() else {
            return Err(self.fault_at(link.span, "Application.Run needs the name of the procedure to run"));
        };
        let named = print_text(&self.eval(&first.value)?);
        let Some(proc) = self.run_target(&named) else {
            let mut fault = self.fault_at(
                link.span,
                format!("Application.Run: Cannot run the macro '{named}' (run-time error 1004): the project has no Sub or Function of that name"),
            );
            fault.code = 1004;
            return Err(fault);
        };
        let p = &self.module.procs[proc];
        let given = &args[1..];
        let required = p.params.iter().filter(|q| !q.optional).count();
        let wrong = if given.len() > p.params.len() {
            Some(450)
        } else if given.len() < required {
            Some(449)
        } else {
            None
        };
        if let Some(code) = wrong {
            let what = crate::eval::functions::vba::errors::description(code);
            let mut fault = self.fault_at(
                link.span,
                format!("Application.Run \"{named}\": {what} (run-time error {code}): {} takes {required} to {} arguments, given {}", p.name, p.params.len(), given.len()),
            );
            fault.code = code;
            return Err(fault);
        }
        let mut bound = Vec::new();
        for (i, a) in given.iter().enumerate() {
            if a.value.kind != ExprKind::Missing {
                bound.push((i, self.run_argument(&a.value)?));
            }
        }
        let (value, _) = self.invoke_frame(proc, bound, Some(link.span), Default::default())?;
        Ok(Obj::Value(value))
    }

    /// One argument of `Application.Run`, by value: an object as the object, anything else as
    /// what it reads (`.Arr(0)` the item, not the array holding it), as an ordinary call's
    /// ByVal argument.
    fn run_argument(&self, e: &Expr) -> Run<Var> {
        match self.object_arg(&mut self.ctx(), e)? {
            Some(object) => Ok(object),
            None => self.var_of(e, false),
        }
    }

    /// The procedure `Application.Run` names: by its name, after a workbook (`Book!`) and a
    /// module (`Module1.`) if given; never a class module's.
    pub(super) fn run_target(&self, named: &str) -> Option<usize> {
        let name = named.rsplit('!').next().unwrap_or(named).trim();
        let (module, name) = match name.rsplit_once('.') {
            Some((module, name)) => (Some(module), name),
            None => (None, name),
        };
        self.module.procs.iter().position(|p| {
            let part = &self.module.parts.get(p.part);
            p.name.eq_ignore_ascii_case(name)
                && p.property.is_none()
                && !part.is_some_and(|m| m.class)
                && module.is_none_or(|m| part.is_some_and(|part| part.name.eq_ignore_ascii_case(m)))
        })
    }

    /// Notes a parameter the call left out, for IsMissing.
    pub(super) fn mark_missing(&self, name: &Rc<str>) {
        if let Some(frame) = self.frames.borrow_mut().last_mut() {
            frame.missing.push(name.clone());
        }
    }

    /// Out of line: the evaluator's frame, which every nested call of a macro stacks, would
    /// otherwise hold the locals of every inspection (`IsEmpty`, `Len`, `TypeName` …).
    #[inline(never)]
    pub(super) fn inspect(&self, what: Inspect, arg: &Expr) -> Run<Value> {
        match what {
            Inspect::VarType => self.var_type(arg).map(Value::Number),
            Inspect::IsMissing => Ok(Value::Bool(self.is_missing(arg))),
            Inspect::TypeName => self.type_name(arg).map(Value::text),
            Inspect::IsObject => self.is_object(arg).map(Value::Bool),
            Inspect::IsDate => self.is_date(arg).map(Value::Bool),
            Inspect::IsEmpty => self.is_empty(arg).map(Value::Bool),
            Inspect::Len { bytes } => self.storage_len(arg, bytes, self.expr_span(arg)),
        }
    }

    /// `IsEmpty(x)` ("IsEmpty function": "IsEmpty returns True if the variable is
    /// uninitialized, or is explicitly set to Empty; otherwise, it returns False"): a Variant
    /// holding a Worksheet, a Collection or Nothing is set, so not empty, where reading it as
    /// a value stopped the macro; an object with a default member is read as that member's
    /// value, so `IsEmpty(cell)` of a Range is its cell's emptiness.
    fn is_empty(&self, arg: &Expr) -> Run<bool> {
        if self.is_empty_literal(arg) || self.is_nothing_literal(arg) {
            return Ok(self.is_empty_literal(arg));
        }
        let (var, named) = match &arg.kind {
            ExprKind::Name(name) => (self.lookup(name).unwrap_or(Var::Value(Value::Blank)), true),
            ExprKind::Host(_) | ExprKind::Paren(_) => (self.var_of(arg, true)?, false),
            _ => return Ok(self.eval(arg)?.is_blank()),
        };
        match var {
            Var::Value(v) => Ok(v.is_blank()),
            // An object variable Set to Nothing is set (to no object), so not empty; the same
            // holder read through a path is a member's value, Empty when the cell or the
            // regex group has none (`IsEmpty(Cells(6, 1).Value)`).
            Var::Obj(Obj::Value(Value::Blank)) => Ok(!named),
            Var::Obj(obj) if self.reads_as_value(&obj) => Ok(match self.operand_of(obj, self.expr_span(arg))? {
                Operand::Value(v) => v.is_blank(),
                Operand::Ref(sheet, rect) => self.ctx().rect_value(sheet, rect).is_blank(),
                _ => false,
            }),
            _ => Ok(false),
        }
    }

    /// An object that a value is read from: a value, a Range, Err, a class with a default
    /// member (what `operand_of` reads); a Worksheet, a Collection or Nothing has none.
    fn reads_as_value(&self, obj: &Obj) -> bool {
        match obj {
            Obj::Value(_) | Obj::Range(..) | Obj::Lines(..) | Obj::Areas(..) | Obj::Err | Obj::Unkept(_) => true,
            Obj::Regex(r) => r.default_value().is_some(),
            Obj::Instance(object) => self.has_default_member(object),
            _ => false,
        }
    }

    /// `IsDate(x)` ("IsDate function": "True if the expression is a date or is recognizable
    /// as a valid date or time"): a value held as a Date (a Date variable, `Now`, a cell
    /// formatted as a date), or text that reads as a date or time but not as a plain number
    /// (`IsDate("5")` is False, as `IsDate(5)` is).
    fn is_date(&self, arg: &Expr) -> Run<bool> {
        if self.type_name(arg)? == "Date" {
            return Ok(true);
        }
        Ok(match self.eval(arg)? {
            Value::Text(t) => {
                use crate::eval::functions::vba::{vba_number, vba_number_text};
                // Read whole, however short the answer (work: a unit per 16 bytes, `Ctx::charge_read`).
                self.add_work(t.len() as u64 / 16);
                vba_number_text(&t).is_none() && vba_number(&Value::Text(t)).is_ok()
            }
            _ => false,
        })
    }

    /// The constant `Nothing` as written (`TypeName(Nothing)`).
    fn is_nothing_literal(&self, arg: &Expr) -> bool {
        matches!(arg.kind, ExprKind::Host(id) if matches!(self.module.nodes[id as usize], Node::Nothing))
    }

    /// The constant `Empty` as written, or an argument left out: no value.
    fn is_empty_literal(&self, arg: &Expr) -> bool {
        arg.kind == ExprKind::Missing
            || matches!(arg.kind, ExprKind::Host(id) if matches!(self.module.nodes[id as usize], Node::Empty))
    }

    /// `TypeName(x)` ("TypeName function"): a typed variable's declared type, a Variant's
    /// content ("Empty", "Double", "String" …, "Nothing" for an object variable set to
    /// Nothing), an object's class ("Range", "Collection", "Dictionary" …), an array's item
    /// type followed by "()"; an expression of a declared type answers it ("Integer" for 5).
    fn type_name(&self, arg: &Expr) -> Run<String> {
        if self.is_nothing_literal(arg) {
            return Ok("Nothing".into());
        }
        if self.is_empty_literal(arg) {
            return Ok("Empty".into());
        }
        if let ExprKind::Name(name) = &arg.kind {
            // Using a variable declared `As New` makes its object first (auto-instantiation).
            self.lookup(name);
            if let Some((var, ty)) = self.with_slot(name, |s| (s.var().clone(), s.held_ty())) {
                return Ok(self.type_name_of(&var, ty.as_ref()));
            }
        }
        // A Type's array field: its items' declared type ("Double()", "Variant()").
        if let Some((array, items)) = self.array_field_items(arg)? {
            return Ok(self.type_name_of(&array, Some(&items)));
        }
        let var = self.var_of(arg, true)?;
        match &var {
            // A value answers its type, a number the type it is held with (`TypeName(x + 1)`),
            // a member's value too (`TypeName(c.Item(1))`; an object path's Empty is Nothing).
            Var::Value(v) | Var::Obj(Obj::Value(v))
                if matches!(var, Var::Value(_)) || !v.is_blank() || self.reads_cell_value(arg) =>
            {
                match self.value_type(arg, v) {
                    Declared::Variant => Ok(self.type_name_of(&Var::Value(v.clone()), None)),
                    held => Ok(held.name().into()),
                }
            }
            _ => Ok(self.type_name_of(&var, None)),
        }
    }

    /// `Cells(r, c).Value`, `.Value2`: an empty cell's value is Empty ("Value property":
    /// an empty cell returns Empty), never the Nothing of an object member left unset.
    fn reads_cell_value(&self, arg: &Expr) -> bool {
        let ExprKind::Host(id) = arg.kind else { return false };
        let Node::Path(path) = &self.module.nodes[id as usize] else { return false };
        path.links.last().is_some_and(|l| {
            l.args.is_none() && (l.name.eq_ignore_ascii_case("value") || l.name.eq_ignore_ascii_case("value2"))
        })
    }

    fn type_name_of(&self, var: &Var, ty: Option<&Ty>) -> String {
        match (var, ty) {
            (Var::Array(_), Some(Ty::Record(i))) => format!("{}()", self.module.types[*i].name),
            (Var::Array(a), ty) => format!("{}()", item_type(a, ty).name()),
            (Var::Record(i, _), _) => self.module.types[*i].name.to_string(),
            // "TypeName function": an object's class, a class module's name for its objects.
            (Var::Obj(Obj::Instance(object)), _) => self.module.classes[object.0.class].name.to_string(),
            (Var::Obj(obj), _) => object_type_name(obj).into(),
            (Var::Value(v), ty) => match Declared::of_ty(ty) {
                Declared::Variant => value_type_name(v),
                declared => declared.name(),
            }
            .into(),
        }
    }

    /// `TypeOf x Is ty` ([MS-VBAL] 5.6.7): True for an object whose class is `ty` (a library's
    /// prefix, `Excel.` or `Scripting.`, aside), a class module's object whose class implements
    /// `ty`, and any object for `Object`. Nothing and values are of no object type: False, as
    /// the "If...Then...Else statement" reference says ("True if objectname is of the object
    /// type specified by objecttype; otherwise it is False"), where MS-VBAL raises error 91.
    pub(super) fn is_of_type(&self, var: &Var, ty: &str) -> bool {
        let ty = ty.rsplit('.').next().unwrap_or(ty);
        let obj = match var {
            Var::Obj(Obj::Value(_)) | Var::Value(_) | Var::Array(_) | Var::Record(..) => return false,
            Var::Obj(obj) => obj,
        };
        if ty.eq_ignore_ascii_case("Object") {
            return true;
        }
        match obj {
            Obj::Instance(object) => {
                let class = &self.module.classes[object.0.class];
                class.name.eq_ignore_ascii_case(ty) || class.implements.iter().any(|i| i.eq_ignore_ascii_case(ty))
            }
            obj => object_type_name(obj).eq_ignore_ascii_case(ty),
        }
    }

    /// `IsObject(x)` ("IsObject function"): True for an object, Nothing included.
    fn is_object(&self, arg: &Expr) -> Run<bool> {
        if self.is_nothing_literal(arg) || self.is_empty_literal(arg) {
            return Ok(self.is_nothing_literal(arg));
        }
        let var = match &arg.kind {
            ExprKind::Name(name) => self.lookup(name).unwrap_or(Var::Value(Value::Blank)),
            ExprKind::Host(_) | ExprKind::Paren(_) => self.var_of(arg, true)?,
            _ => {
                self.eval(arg)?;
                return Ok(false);
            }
        };
        Ok(match var {
            Var::Obj(Obj::Value(v)) => v.is_blank(),
            Var::Obj(_) => true,
            _ => false,
        })
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
    /// Its own frame, off the expression evaluator's (which every nested call stacks).
    #[inline(never)]
    fn var_type(&self, arg: &Expr) -> Run<f64> {
        if self.is_nothing_literal(arg) {
            return Ok(VB_OBJECT);
        }
        if let ExprKind::Name(name) = &arg.kind {
            if self.is_missing(arg) {
                return Ok(VB_ERROR);
            }
            if let Some((var, ty)) = self.with_slot(name, |s| (s.var().clone(), s.held_ty())) {
                return self.var_type_of_var(&var, ty.as_ref());
            }
        }
        let var = self.var_type_operand(arg)?;
        // A value answers the type it is held with (`VarType(5)` vbInteger, `d + 1` of a
        // Date vbDate, an item or a call that gave a Date vbDate).
        match &var {
            Var::Value(v) => match self.value_type(arg, v).var_type() {
                Some(code) => Ok(code),
                None => self.var_type_of_var(&var, None),
            },
            _ => self.var_type_of_var(&var, None),
        }
    }

    /// What `VarType(arg)` asks about: a member path that gives a Range (`VarType(Cells(1, 1))`)
    /// stays the Range, whose cell's number format decides Date or Currency; an object with a
    /// default member answers for that member ("VarType function").
    fn var_type_operand(&self, arg: &Expr) -> Run<Var> {
        let path = matches!(arg.kind, ExprKind::Host(id) if matches!(self.module.nodes[id as usize], Node::Path(_)));
        Ok(match self.var_of(arg, path)? {
            range @ Var::Obj(Obj::Range(..)) => range,
            Var::Obj(Obj::Instance(object)) if path => self.default_value(&object)?,
            Var::Obj(Obj::Value(v)) if path => Var::Value(v),
            var => var,
        })
    }

    fn var_type_of_var(&self, var: &Var, ty: Option<&Ty>) -> Run<f64> {
        Ok(match var {
            Var::Array(a) => {
                VB_ARRAY + ty.and_then(declared_var_type).or_else(|| a.item_type.var_type()).unwrap_or(VB_VARIANT)
            }
            Var::Record(..) => 36.0,
            // A Range answers its default property's (Value's) type: a cell formatted as a
            // date gives a Date, as currency a Currency ("Range.Value property").
            Var::Obj(Obj::Range(sheet, rect)) => match range_var(self.ctx().rect_value(*sheet, *rect)) {
                Var::Value(v @ Value::Number(_)) => {
                    self.cell_value_type(*sheet, rect.first).var_type().unwrap_or_else(|| var_type_of(&v))
                }
                Var::Value(v) => var_type_of(&v),
                _ => VB_ARRAY + VB_VARIANT,
            },
            // An object variable set to Nothing.
            Var::Obj(Obj::Value(Value::Blank)) => VB_OBJECT,
            Var::Obj(Obj::Value(v)) => var_type_of(v),
            Var::Obj(_) => VB_OBJECT,
            Var::Value(v) => ty.and_then(declared_var_type).unwrap_or_else(|| var_type_of(v)),
        })
    }
}

impl Build<'_> {
    /// `LSet stringvar = string` and `RSet stringvar = string` ("LSet statement", "RSet
    /// statement"), read by the grammar as a call of LSet with the comparison `stringvar =
    /// string`: the assignment `stringvar = VBA.LSETSTATEMENT(stringvar, string)`; anything
    /// else after LSet is refused with the statement's form.
    pub(super) fn aligned_assignment(&self, pair: &Pair<Rule>, word: &str, statement: &Expr) -> Res<StmtKind> {
        let shown = if word == "lset" { "LSet" } else { "RSet" };
        let refused =
            || self.error_at(pair, format!("{shown}: {shown} stringvar = string, where stringvar is a variable"));
        let ExprKind::Binary(BinOp::Eq, target, value) = &statement.kind else { return Err(refused()) };
        let ExprKind::Name(var) = &target.kind else { return Err(refused()) };
        let name = if word == "lset" { "VBA.LSETSTATEMENT" } else { "VBA.RSETSTATEMENT" };
        if !self.is_var(var) {
            return Err(refused());
        }
        let info = Registry.lookup(name).ok_or_else(refused)?;
        let call = Expr::new(ExprKind::Call(info.id, vec![(**target).clone(), (**value).clone()]), statement.span);
        Ok(StmtKind::Assign { target: Target::Var(var.clone()), value: call, set: false })
    }

    /// `Mid(stringvar, start[, length]) = string` ("Mid statement"): the assignment
    /// `stringvar = <its text with the characters replaced>`, through the function table's
    /// `VBA.MIDSTATEMENT`; `None` for any other assignment.
    pub(super) fn mid_statement(&self, target: &Pair<Rule>, value: &Expr) -> Res<Option<StmtKind>> {
        // Only a target spelled `Mid(…)` is read twice.
        if !target.as_str().get(..3).is_some_and(|s| s.eq_ignore_ascii_case("mid")) {
            return Ok(None);
        }
        let path = self.path_syntax(target)?;
        let [link] = path.links.as_slice() else { return Ok(None) };
        let Some(args) = link.args.as_deref() else { return Ok(None) };
        let lower = lower_bare(&link.name);
        if path.with || lower != "mid" || self.is_var(&link.name) || self.proc_index(&link.name).is_some() {
            return Ok(None);
        }
        let var = match args.first().map(|a| &a.value.kind) {
            Some(ExprKind::Name(var)) if self.is_var(var) && (2..=3).contains(&args.len()) => var.clone(),
            _ => {
                return Err(self.error_at(
                    target,
                    "Mid statement: Mid(stringvar, start[, length]) = string, where stringvar is a variable",
                ))
            }
        };
        if args.iter().any(|a| a.name.is_some()) {
            return Err(
                self.error_at(target, "Mid statement: named arguments (x:=) are for the macro's own procedures")
            );
        }
        let Some(info) = Registry.lookup("VBA.MIDSTATEMENT") else { return Ok(None) };
        let mut exprs: Vec<Expr> = args.iter().map(|a| a.value.clone()).collect();
        if exprs.len() == 2 {
            exprs.push(Expr::new(ExprKind::Missing, value.span));
        }
        exprs.push(value.clone());
        let call = Expr::new(ExprKind::Call(info.id, exprs), value.span);
        Ok(Some(StmtKind::Assign { target: Target::Var(var), value: call, set: false }))
    }
}

/// What `Split(…)` and `Array(…)` give a variable: a one-dimensional array even of one
/// item or none, zero-based for Split ("Split function": "a zero-based, one-dimensional
/// array"), from Option Base for Array. `None` for any other expression.
impl Interp<'_, '_> {
    /// [`library_array`], with the types of the numbers among `Array(…)`'s items marked: each
    /// item is a Variant holding its value with its type ([MS-VBAL] 2.1.1.1, "Array function"),
    /// a Date as a Date and the literal 1 as an Integer (3.3.2).
    pub(super) fn array_of_call(&self, e: &Expr, v: &Value) -> Option<Var> {
        let base = if self.is_zero_based_array(e) { 0 } else { self.option_base() };
        let e = self.sheet_call_inner(e);
        let mut var = library_array(e, v, base)?;
        if let (ExprKind::Call(id, args), Var::Array(a)) = (&e.kind, &mut var) {
            if crate::eval::functions::spec(*id).name == "VBA.ARRAY" {
                for (k, arg) in args.iter().enumerate() {
                    let held = match a.data.data.get(k) {
                        Some(item) if self.as_date(arg, item).is_some() => super::typing::Declared::Date,
                        Some(item @ Value::Number(_)) => self.value_type(arg, item),
                        _ => super::typing::Declared::Variant,
                    };
                    a.mark_held(k, held);
                }
            }
        }
        Some(var)
    }
}

impl Interp<'_, '_> {
    /// Whether `e` is `VBA.Array(…)`, zero-based whatever the Option Base.
    fn is_zero_based_array(&self, e: &Expr) -> bool {
        matches!(&e.kind, ExprKind::Host(id) if matches!(self.module.nodes[*id as usize], Node::ZeroBasedArray { .. }))
    }

    /// `Array(…)` or `VBA.Array(…)` with an object among its arguments, as a Variant array
    /// holding the objects (`param_array.rs`); `None` for any other expression.
    pub(super) fn array_with_objects(&self, e: &Expr) -> Option<Run<Var>> {
        let lower = if self.is_zero_based_array(e) { 0 } else { self.option_base() };
        let ExprKind::Call(id, args) = &self.sheet_call_inner(e).kind else { return None };
        if crate::eval::functions::spec(*id).name != "VBA.ARRAY" {
            return None;
        }
        self.array_of_objects(args, lower)
    }
}

pub(super) fn library_array(e: &Expr, v: &Value, base: i64) -> Option<Var> {
    let ExprKind::Call(id, _) = &e.kind else { return None };
    let Value::Array(data) = v else { return None };
    let lower = match crate::eval::functions::spec(*id).name {
        // "StrConv function": vbFromUnicode's Byte array starts at 0 as a String's bytes do.
        "VBA.SPLIT" | "VBA.FILTER" | "VBA.STRCONV" => 0,
        "VBA.ARRAY" => base,
        name if name.starts_with("VBA.") => return None,
        // A worksheet function's one-row result (`Application.Transpose(column)`) comes to
        // VBA as a one-dimensional array from 1, whatever the Option Base, as Excel gives it.
        _ if data.rows == 1 && data.cols > 1 => 1,
        _ => return None,
    };
    let mut array = VArray::row(data.clone(), lower);
    // "Split function" and "Filter function" return arrays of strings: a `String()`.
    if matches!(crate::eval::functions::spec(*id).name, "VBA.SPLIT" | "VBA.FILTER") {
        array.item_type = super::typing::Declared::String;
    }
    Some(Var::Array(array))
}

/// The VarType number of a declared type (`None`: a Variant, which answers what it holds).
fn declared_var_type(ty: &Ty) -> Option<f64> {
    match ty {
        Ty::Whole(code) | Ty::Number(code) => Some(f64::from(*code)),
        Ty::String | Ty::FixedString(_) => Some(8.0),
        Ty::Boolean => Some(11.0),
        Ty::Record(_) => Some(36.0),
        // An object variable answers what it holds (Nothing 9, a Range its Value's type).
        Ty::Variant | Ty::Object => None,
    }
}

/// The type of the items of the array `a` held by a variable of type `ty`: the variable's
/// declared item type (`Dim a() As Long`), else the one the array keeps from where it was
/// made (a Variant holding a `Double()`, [`VArray::item_type`]).
fn item_type(a: &VArray, ty: Option<&Ty>) -> Declared {
    match Declared::of_ty(ty) {
        Declared::Variant => a.item_type,
        declared => declared,
    }
}

/// `TypeName` of what a Variant holds.
fn value_type_name(v: &Value) -> &'static str {
    match v {
        Value::Blank => "Empty",
        Value::Number(_) => "Double",
        Value::Text(_) => "String",
        Value::Bool(_) => "Boolean",
        Value::Error(_) => "Error",
        Value::Array(_) => "Variant()",
        Value::Lambda(_) => "Object",
        // VBA's Null ("TypeName function": "Null"), which no cell holds.
        #[allow(unreachable_patterns)]
        _ => "Null",
    }
}

/// `TypeName` of an object: its class as Excel and VBA name it.
fn object_type_name(obj: &Obj) -> &'static str {
    match obj {
        Obj::Value(Value::Blank) => "Nothing",
        Obj::Value(v) => value_type_name(v),
        Obj::Range(..) | Obj::Areas(..) | Obj::Lines(..) => "Range",
        Obj::AreaList(..) => "Areas",
        Obj::Look(_, _, super::formats::LookPart::Font) => "Font",
        Obj::Look(_, _, super::formats::LookPart::Interior) => "Interior",
        Obj::Sheet(_) => "Worksheet",
        Obj::Hyperlinks(..) => "Hyperlinks",
        Obj::Hyperlink(..) => "Hyperlink",
        Obj::Table(t) => t.class(),
        Obj::SheetGroup(_) => "Sheets",
        Obj::Sheets => "Sheets",
        Obj::Workbook => "Workbook",
        Obj::App => "Application",
        Obj::Err => "ErrObject",
        Obj::SheetFunctions => "WorksheetFunction",
        Obj::Store(h) => match h.class() {
            Class::Collection => "Collection",
            Class::Dictionary => "Dictionary",
            Class::ArrayList => "ArrayList",
        },
        Obj::SheetSort(_) => "Sort",
        Obj::SortFields(_) => "SortFields",
        Obj::Regex(r) => r.type_name(),
        #[allow(unreachable_patterns)]
        _ => "Object",
    }
}
