//! Class modules ([MS-VBAL] 5.2.4.1 class modules, 5.3.1.4 property declarations): `New
//! Class1` makes an object holding its own copy of the module's variables; its public Subs,
//! Functions and `Property Get|Let|Set` are the object's members, run with `Me` the object.
//! Objects are shared by `Set` (two names, one object) and compared by `Is`;
//! `Class_Initialize` runs when one is made, `Class_Terminate` when the last variable
//! holding it lets it go (set to another object or Nothing, or a procedure's variable when
//! the procedure ends). VBA's errors: 91 for a member of Nothing, 438 for a member the class
//! has not.

use std::cell::RefCell;
use std::fmt;
use std::rc::Rc;

use crate::eval::functions::vba::errors;
use crate::eval::{Ctx, Operand, Value};
use crate::formula::ast::{Expr, ExprKind};

use super::ast::{
    Arg, ClassDef, Link, Made, Node, Part, ProcKind, PropertyKind, Span, SpecialMembers, Stmt, StmtKind, Ty, VarDecl,
};
use super::collections::{var_obj, Handle};
use super::interp::{Call, Fault, Frame, Interp, Run};
use super::value::{array_var, convert, range_var, Obj, Slots, Var};

/// What one object costs the memory budget besides its variables' values.
pub(super) const OBJECT_BYTES: u64 = 64;

/// What an object of a class module costs the memory budget besides its variables' values:
/// its own block and its variables' slots as allocated. A fixed [`OBJECT_BYTES`] counted 64
/// bytes where an object of ten Double fields took 8 KiB, and a loop making objects ran past
/// the budget to the abort at the memory cap.
pub(super) fn object_bytes(object: &Object) -> u64 {
    let block = std::mem::size_of::<Object>() + 2 * std::mem::size_of::<usize>();
    (block as u64).saturating_add(object.fields.borrow().own_bytes())
}

/// "Trappable errors": VBA's numbers and texts for objects.
const NOT_SET: (u32, &str) = (91, errors::description(91));
const NO_MEMBER: (u32, &str) = (438, errors::description(438));

/// An object of a class module, shared by every variable set to it.
#[derive(Clone)]
pub struct Instance(pub Rc<Object>);

/// What an object holds: its class and its own variables.
pub struct Object {
    /// The class module, by its index in `Module::classes`.
    pub class: usize,
    pub fields: RefCell<Slots>,
}

impl PartialEq for Instance {
    fn eq(&self, other: &Instance) -> bool {
        Rc::ptr_eq(&self.0, &other.0)
    }
}

/// The class only: an object's variables may lead back to itself.
impl fmt::Debug for Instance {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Instance(class {})", self.0.class)
    }
}

impl Instance {
    /// Its variables' values (for the memory budget).
    pub fn field_vars(&self) -> Vec<Var> {
        self.0.fields.borrow().iter().map(|s| s.var().clone()).collect()
    }
}

/// Objects held in variables are let go one after another, not each inside the one holding
/// it: a linked list of a million objects does not take the native stack.
impl Drop for Object {
    fn drop(&mut self) {
        let fields = std::mem::take(self.fields.get_mut());
        let vars = fields.iter().map(|s| s.var().clone()).collect();
        drop(fields);
        let_go(vars);
    }
}

/// Drops what `pending` holds, what it alone holds taken out first (an explicit stack
/// instead of nested drops): the fields of objects, the items of Collections and
/// Dictionaries, and the items of arrays, whose arrays, objects and records are let go the
/// same way. A chain a million deep of any of them (`a = Array(a)` in a loop, a Collection
/// holding an array holding the next) does not take the native stack with it.
pub(super) fn let_go(mut pending: Vec<Var>) {
    let mut arrays: Vec<Rc<crate::eval::Array>> = Vec::new();
    loop {
        if let Some(array) = arrays.pop() {
            if let Ok(mut array) = Rc::try_unwrap(array) {
                arrays.extend(array.data.drain(..).filter_map(|item| match item {
                    crate::eval::Value::Array(inner) => Some(inner),
                    _ => None,
                }));
            }
            continue;
        }
        let Some(var) = pending.pop() else { break };
        match var {
            Var::Obj(Obj::Instance(o)) => {
                if let Ok(object) = Rc::try_unwrap(o.0) {
                    let fields = object.fields.take();
                    pending.extend(fields.iter().map(|s| s.var().clone()));
                }
            }
            Var::Obj(Obj::Store(h)) => {
                if let Ok(store) = Rc::try_unwrap(h.0) {
                    pending.extend(store.into_inner().take_items());
                }
            }
            Var::Record(_, fields) => pending.extend(fields),
            Var::Array(a) => {
                let (data, parts) = a.into_parts();
                arrays.push(data);
                pending.extend(parts);
            }
            Var::Value(crate::eval::Value::Array(data)) => arrays.push(data),
            _ => {}
        }
    }
}

/// What a member gave as a variable holds it: a value, or an object.
pub(super) fn obj_var(obj: Obj) -> Var {
    match obj {
        Obj::Value(v) => Var::Value(v),
        other => Var::Obj(other),
    }
}

/// The class modules among a project's parts, in order (`Made::Object(i)`).
pub(super) fn class_defs(parts: &[Part]) -> Vec<ClassDef> {
    let classes = parts.iter().enumerate().filter(|(_, p)| p.class);
    classes
        .map(|(i, p)| ClassDef {
            name: p.name.clone(),
            part: i,
            fields: Vec::new(),
            public: Vec::new(),
            implements: Vec::new(),
        })
        .collect()
}

/// Whether a class module's source gives it a default instance: `Attribute VB_PredeclaredId
/// = True`, which the VBA editor keeps in the module's stored source and in an exported .cls
/// (a UserForm's is always True; a class's is False unless the file was edited).
pub(super) fn has_predeclared_id(source: &str) -> bool {
    attributes(source).any(|(name, value)| {
        name.eq_ignore_ascii_case("vb_predeclaredid") && (value.eq_ignore_ascii_case("true") || value == "-1")
    })
}

/// The `Attribute <name> = <value>` lines of a module's source, each name and value trimmed.
fn attributes(source: &str) -> impl Iterator<Item = (&str, &str)> {
    source.lines().filter_map(|line| {
        let line = line.trim();
        let keyword = line.get(..10).filter(|w| w.eq_ignore_ascii_case("attribute "))?;
        let (name, value) = line[keyword.len()..].split_once('=')?;
        Some((name.trim(), value.trim()))
    })
}

/// A class module's default member and enumerator, from the `Attribute <Member>.VB_UserMemId
/// = 0` (DISPID_VALUE) and `= -4` (DISPID_NEWENUM) lines the VBA editor keeps in the module's
/// stored source and in an exported .cls ([MS-OVBA] 2.3.4.3's module source keeps them; the
/// numbers are COM's dispatch ids, which VBA's `obj(…)` and `For Each` use).
pub(super) fn special_members(source: &str) -> SpecialMembers {
    let mut special = SpecialMembers::default();
    for (member, id) in attributes(source).filter_map(user_mem_id) {
        match id {
            0 => special.default = Some(member.into()),
            -4 => special.enumerator = Some(member.into()),
            _ => {}
        }
    }
    special
}

/// `Attribute Item.VB_UserMemId = 0`: the member and its id.
fn user_mem_id<'a>((name, value): (&'a str, &str)) -> Option<(&'a str, i64)> {
    let (member, attribute) = name.split_once('.')?;
    let id = value.parse().ok()?;
    attribute.trim().eq_ignore_ascii_case("vb_usermemid").then_some((member.trim(), id))
}

/// The default instances of the project's predeclared classes (by name and class): each a
/// Public variable of the module run first, declared `As New` its class, so that `Point.Create`
/// makes the object at its first use and every module reaches the one object for the whole
/// run ([MS-VBAL] 5.2.4.1.2, "Default Instance Variables": a variable "with module extent as
/// if declared in a <module-variable-declaration> containing an <as-autoobject>", named
/// after the class).
pub(super) fn default_instances(parts: &[Part]) -> Vec<(Rc<str>, Made)> {
    let classes = parts.iter().filter(|p| p.class).enumerate();
    classes.filter(|(_, p)| p.predeclared).map(|(i, p)| (p.name.clone(), Made::Object(i))).collect()
}

/// [`default_instances`] as module-level declarations of the first module (line 1 is in it).
pub(super) fn default_instance_declarations(parts: &[Part]) -> Vec<Stmt> {
    let span = Span { line: 1, col: 1 };
    let declare = |(name, made): (Rc<str>, Made)| VarDecl {
        name,
        ty: Some(Ty::Object),
        bounds: None,
        new: Some(made),
        span,
        field: None,
        item: None,
    };
    let vars: Vec<VarDecl> = default_instances(parts).into_iter().map(declare).collect();
    if vars.is_empty() {
        return Vec::new();
    }
    vec![Stmt { kind: StmtKind::Dim(vars), span }]
}

impl Interp<'_, '_> {
    fn object_error(&self, span: Span, (code, text): (u32, &str), what: &str) -> Fault {
        let mut fault = self.fault_at(span, format!("{what}: {text} (run-time error {code})"));
        fault.code = code;
        fault
    }

    /// `x.Member` where `x` holds Nothing (or was never set): VBA's error 91.
    pub(super) fn not_set(&self, link: &Link) -> Fault {
        self.object_error(link.span, NOT_SET, &link.name)
    }

    /// A new object of `class`: a Collection, a Dictionary or an object of a class module,
    /// its variables declared and its `Class_Initialize` run.
    pub(super) fn new_object(&self, made: Made, span: Span) -> Run<Var> {
        let class = match made {
            Made::Store(class) => return Ok(Var::Obj(Obj::Store(Handle::new(class)))),
            Made::Object(class) => class,
            Made::RegExp => {
                self.charge(OBJECT_BYTES, span)?;
                return Ok(Var::Obj(Obj::Regex(super::regexp::RegexObj::new_regexp())));
            }
        };
        let object = Instance(Rc::new(Object { class, fields: RefCell::new(Slots::default()) }));
        self.declare_fields(&object, &self.module.classes[class].fields)?;
        // Charged once its fields are declared: what they take is known then, held to the
        // slots it has (a Vec grown slot by slot kept room for twice as many).
        object.0.fields.borrow_mut().shrink_to_fit();
        self.charge(object_bytes(&object.0), span)?;
        if let Some(proc) = self.class_proc(class, "Class_Initialize", None) {
            self.run_event(proc, &object, span)?;
        }
        Ok(Var::Obj(Obj::Instance(object)))
    }

    /// A procedure of the class by name: a Sub, a Function or a Property Get (`write`
    /// `None`), or the Property Let or Set that assigns.
    fn class_proc(&self, class: usize, name: &str, write: Option<PropertyKind>) -> Option<usize> {
        let part = self.module.classes[class].part;
        self.module.procs.iter().position(|p| {
            p.part == part
                && p.name.eq_ignore_ascii_case(name)
                && match write {
                    None => matches!(p.property, None | Some(PropertyKind::Get)),
                    Some(kind) => p.property == Some(kind),
                }
        })
    }

    /// A member other code may call: declared without `Private`, or the procedure that
    /// implements an interface's member ("Implements statement": `Private Function
    /// IShape_Area()` is what `shape.Area` runs for an object of a class that `Implements
    /// IShape`, reached through a variable of any declared type here).
    fn public_proc(&self, class: usize, name: &str, write: Option<PropertyKind>) -> Option<usize> {
        let public = self.class_proc(class, name, write).filter(|&p| self.module.procs[p].public);
        public.or_else(|| {
            let interfaces = self.module.classes[class].implements.iter();
            interfaces.filter_map(|i| self.class_proc(class, &format!("{i}_{name}"), write)).next()
        })
    }

    fn run_event(&self, proc: usize, object: &Instance, span: Span) -> Run<()> {
        let call = Call { me: Some(object.clone()), value: None, lent: Vec::new() };
        self.invoke_frame(proc, Vec::new(), Some(span), call).map(|_| ())
    }

    /// Runs `Class_Terminate` of an object `var` held, when nothing else holds it: the last
    /// reference is going. The objects it alone held go with it, and so do those a
    /// Collection or a Dictionary alone held ("Terminate event": when "all references to an
    /// instance" are removed), one after another: a long chain does not take the stack.
    pub(super) fn release(&self, var: &Var) -> Run<()> {
        let mut pending = Vec::new();
        self.release_one(var, &mut pending)?;
        self.release_all(pending)
    }

    /// Lets go of vars that nothing else will hold (taken out of their holder).
    pub(super) fn release_all(&self, pending: Vec<Var>) -> Run<()> {
        // The usual case, a value replaced by a value: nothing to let go.
        if pending.is_empty() {
            return Ok(());
        }
        // In the order held: the first item of a Collection goes first.
        let mut pending: Vec<Var> = pending.into_iter().rev().collect();
        while let Some(var) = pending.pop() {
            self.release_one(&var, &mut pending)?;
        }
        Ok(())
    }

    /// Terminates `var`'s object if this is its last reference, adding what it held to `pending`.
    fn release_one(&self, var: &Var, pending: &mut Vec<Var>) -> Run<()> {
        match var {
            Var::Obj(object) => self.release_obj(object, pending)?,
            // An array's objects go with it when nothing else holds its items.
            Var::Array(a) => {
                if let Some(objects) = a.objects.as_ref().filter(|o| Rc::strong_count(o) == 1) {
                    let mut places: Vec<&usize> = objects.keys().collect();
                    places.sort_unstable();
                    for k in places {
                        self.release_obj(&objects[k], pending)?;
                    }
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// `release_one` of an object held where `object` is.
    fn release_obj(&self, object: &Obj, pending: &mut Vec<Var>) -> Run<()> {
        match object {
            Obj::Instance(object) if Rc::strong_count(&object.0) == 1 => {
                if let Some(proc) = self.class_proc(object.0.class, "Class_Terminate", None) {
                    self.run_event(proc, object, self.module.procs[proc].span)?;
                }
                // Class_Terminate may have handed `Me` to someone: then it lives on.
                if Rc::strong_count(&object.0) == 1 {
                    let fields = object.0.fields.take();
                    pending.extend(fields.iter().map(|s| s.var().clone()));
                }
            }
            Obj::Store(h) if Rc::strong_count(&h.0) == 1 => pending.extend(h.0.borrow_mut().take_items()),
            _ => {}
        }
        Ok(())
    }

    /// `obj.Member(args)` read or called: a public Sub, Function or Property Get of the
    /// class, else a public variable of the object.
    pub(super) fn instance_member(&self, ctx: &mut Ctx, object: &Instance, link: &Link) -> Run<Obj> {
        let class = object.0.class;
        if let Some(proc) = self.public_proc(class, &link.name, None) {
            let args = link.args.as_deref().unwrap_or(&[]);
            // `obj.Items(1)` of a member without parameters: the arguments index what it gives.
            let p = &self.module.procs[proc];
            let (own, then) = match p.params.is_empty() && p.kind == ProcKind::Function {
                true if !args.is_empty() => (&[][..], Some(args)),
                _ => (args, None),
            };
            let result = self.call_method(ctx, object, proc, own, None, link.span)?;
            if let Some(args) = then {
                return self.indexed(ctx, result, args, link);
            }
            if let Var::Array(a) = &result {
                *self.method_array.borrow_mut() = Some(a.clone());
            }
            return Ok(var_obj(result));
        }
        let Some(var) = self.public_field(object, &link.name) else { return Err(self.no_such_member(object, link)) };
        match link.args.as_deref() {
            None => Ok(var_obj(var)),
            Some(args) => self.indexed(ctx, var, args, link),
        }
    }

    /// `held(args)`, what a member without parameters gave indexed by the arguments after it:
    /// an item of an array, of a Collection or a Dictionary (their default member, Item:
    /// "Collection object", "Dictionary object"), or an object's default member ([MS-VBAL]
    /// 5.6.13.1: an index expression on an object is a call of its default member).
    fn indexed(&self, ctx: &mut Ctx, held: Var, args: &[Arg], link: &Link) -> Run<Obj> {
        match held {
            Var::Array(a) => {
                let mut at = Vec::new();
                for arg in args {
                    at.push(self.index(&arg.value, "an array index")?);
                }
                let k =
                    self.element_at(&a, &at).map_err(|m| self.fault_at(link.span, format!("{}: {m}", link.name)))?;
                // The item as the array holds it: an object stays one (`this.Parts(1).Name`).
                Ok(var_obj(a.item(k)))
            }
            Var::Obj(Obj::Store(h)) => {
                let index: Vec<Expr> = args.iter().map(|a| a.value.clone()).collect();
                let key = self.store_key(ctx, &index, link.span)?;
                self.store_item(&h, &key, link.span).map(var_obj)
            }
            Var::Obj(Obj::Instance(inner)) => self.default_member(ctx, &inner, args, link.span),
            _ => Err(self.fault_at(link.span, format!("{} is a variable of the object, not an array", link.name))),
        }
    }

    /// The members VBA reaches without their names in `object`'s class.
    fn special(&self, object: &Instance) -> &SpecialMembers {
        &self.module.parts[self.module.classes[object.0.class].part].special
    }

    /// `obj(args)` read: the class's default member called with the arguments (`Attribute
    /// Item.VB_UserMemId = 0`). A class without one: VBA's error 438.
    pub(super) fn default_member(&self, ctx: &mut Ctx, object: &Instance, args: &[Arg], span: Span) -> Run<Obj> {
        let link = self.default_link(object, args, span)?;
        self.instance_member(ctx, object, &link)
    }

    /// `obj(args) = value`, `Set obj(args) = value` and `obj = value` of an object variable:
    /// the default member's Property Let or Set, or its public variable ([MS-VBAL] 5.4.3.8).
    pub(super) fn set_default_member(
        &self,
        ctx: &mut Ctx,
        object: &Instance,
        args: &[Arg],
        value: &Expr,
        span: Span,
    ) -> Run<()> {
        let link = self.default_link(object, args, span)?;
        self.set_instance_member(ctx, object, &link, value)
    }

    /// What `For Each x In obj` goes through: for an object of a class with an enumerator
    /// (`Attribute NewEnum.VB_UserMemId = -4`), what that member gives (usually a Collection's
    /// `[_NewEnum]`); anything else is itself.
    pub(super) fn enumerated(&self, group: Var, e: &Expr) -> Run<Var> {
        let Var::Obj(Obj::Instance(object)) = &group else { return Ok(group) };
        let Some(name) = self.special(object).enumerator.clone() else { return Ok(group) };
        let link = Link { name, args: None, span: self.expr_span(e) };
        self.instance_member(&mut self.ctx(), object, &link).map(obj_var)
    }

    /// An object given to a parameter of a value type (`ByVal x As Double`): its default
    /// member's value, as a Let would give it ([MS-VBAL] 5.3.1.11: the argument is let-coerced
    /// to the parameter's declared type). Other arguments pass as they are.
    pub(super) fn object_to_param(&self, arg: Var, ty: Option<&Ty>) -> Run<Var> {
        match (&arg, ty) {
            (Var::Obj(Obj::Instance(object)), Some(t)) if !matches!(t, Ty::Variant | Ty::Object | Ty::Record(_)) => {
                self.default_value(object)
            }
            _ => Ok(arg),
        }
    }

    pub(super) fn has_default_member(&self, object: &Instance) -> bool {
        self.special(object).default.is_some()
    }

    /// `object` where a value is wanted, of a class with a default member: that member's value.
    pub(super) fn instance_operand(&self, object: &Instance) -> Run<Operand> {
        match self.default_value(object)? {
            Var::Value(v) | Var::Obj(Obj::Value(v)) => Ok(Operand::Value(v)),
            Var::Array(a) => Ok(Operand::Value(Value::Array(a.data))),
            Var::Obj(Obj::Range(sheet, rect)) => Ok(Operand::Ref(sheet, rect)),
            Var::Obj(other) => Err(self.fault(format!("{} is not a value", other.describe()))),
            Var::Record(..) => Err(self.fault("a Type value is not a value: use its fields")),
        }
    }

    fn default_link(&self, object: &Instance, args: &[Arg], span: Span) -> Run<Link> {
        let Some(name) = self.special(object).default.clone() else {
            let class = &self.module.classes[object.0.class].name;
            let what = format!("{class} has no default member (Attribute <Member>.VB_UserMemId = 0)");
            return Err(self.object_error(span, NO_MEMBER, &what));
        };
        Ok(Link { name, args: (!args.is_empty()).then(|| args.to_vec()), span })
    }

    /// The value of an object read where a value is wanted (`x = obj`, `Debug.Print obj`, `obj
    /// + 1`): its default member without arguments, recursively while that gives an object
    /// ([MS-VBAL] 5.5.1.2, Let-coercion of an object: its default member's value).
    /// An object of a class without a default member is itself, and so is one met again on the
    /// way (a default member giving `Me`).
    pub(super) fn default_value(&self, object: &Instance) -> Run<Var> {
        let mut object = object.clone();
        let mut met = std::collections::HashSet::new();
        loop {
            let special = self.special(&object).default.clone();
            let Some(name) = special.filter(|_| met.insert(Rc::as_ptr(&object.0))) else {
                return Ok(Var::Obj(Obj::Instance(object)));
            };
            let got = match self.public_proc(object.0.class, &name, None) {
                Some(proc) => {
                    self.default_takes_no_arguments(proc)?;
                    let call = Call { me: Some(object.clone()), value: None, lent: Vec::new() };
                    let (result, frame) = self.invoke_frame(proc, Vec::new(), None, call)?;
                    self.returned(proc, result, &frame)
                }
                None => self.public_field(&object, &name).unwrap_or(Var::Value(Value::Blank)),
            };
            match got {
                Var::Obj(Obj::Instance(inner)) => object = inner,
                other => return Ok(other),
            }
        }
    }

    /// `x = bag` of a class whose default member needs an index: VBA's error 450.
    fn default_takes_no_arguments(&self, proc: usize) -> Run<()> {
        let p = &self.module.procs[proc];
        let Some(needed) = p.params.iter().find(|q| !q.optional && !q.param_array) else { return Ok(()) };
        let what =
            format!("{}.{} (the default member) needs its argument {}", self.class_name(p.part), p.name, needed.name);
        let mut fault = self.fault(format!("{what}: {} (run-time error 450)", errors::description(450)));
        fault.code = 450;
        Err(fault)
    }

    fn no_such_member(&self, object: &Instance, link: &Link) -> Fault {
        let class = &self.module.classes[object.0.class].name;
        self.object_error(link.span, NO_MEMBER, &format!("{class}.{}", link.name))
    }

    /// A variable of the object that other code may read (declared `Public`).
    fn public_field(&self, object: &Instance, name: &str) -> Option<Var> {
        let def = &self.module.classes[object.0.class];
        if !def.public.iter().any(|p| p.eq_ignore_ascii_case(name)) {
            return None;
        }
        object.0.fields.borrow().get(name).map(|s| s.var().clone())
    }

    /// `obj.Member = value` and `Set obj.Member = value`: its Property Let or Set (a Set when
    /// the value is an object and the class has both), else a public variable of the object.
    pub(super) fn set_instance_member(&self, ctx: &mut Ctx, object: &Instance, link: &Link, value: &Expr) -> Run<()> {
        let class = object.0.class;
        let name = &link.name;
        let args = link.args.as_deref().unwrap_or(&[]);
        let (lets, sets) = (
            self.public_proc(class, name, Some(PropertyKind::Let)),
            self.public_proc(class, name, Some(PropertyKind::Set)),
        );
        let (proc, var) = match (lets, sets) {
            (Some(let_), None) => (let_, self.var_of(value, false)?),
            (None, Some(set)) => (set, self.item_var(value)?),
            (Some(let_), Some(set)) => match self.item_var(value)? {
                object @ Var::Obj(Obj::Instance(_) | Obj::Store(_)) => (set, object),
                Var::Obj(Obj::Range(sheet, rect)) => (let_, range_var(self.ctx().rect_value(sheet, rect))),
                other => (let_, other),
            },
            (None, None) => return self.set_field(object, link, value),
        };
        self.call_method(ctx, object, proc, args, Some(var), link.span).map(|_| ())
    }

    /// `obj.Field = value`: a public variable of the object, converted to its type.
    fn set_field(&self, object: &Instance, link: &Link, value: &Expr) -> Run<()> {
        let name = &link.name;
        let args = link.args.as_deref().unwrap_or(&[]);
        if self.public_field(object, name).is_none() {
            return Err(self.no_such_member(object, link));
        }
        if !args.is_empty() {
            return self.set_field_item(object, link, args, value);
        }
        // `Set o.Field = obj` keeps the object; a range assigned without Set is its values.
        let var = match self.item_var(value)? {
            Var::Obj(Obj::Range(sheet, rect)) => range_var(self.ctx().rect_value(sheet, rect)),
            other => other,
        };
        self.charge(super::budget::brought(&var), link.span)?;
        let old = {
            let mut fields = object.0.fields.borrow_mut();
            let slot = fields.get_mut(name).expect("a public variable");
            let given = var.clone();
            let new = convert(var, slot.ty.as_ref(), &slot.name).map_err(|m| self.fault_at(link.span, m))?;
            self.owe(super::budget::padding_bytes(&given, &new));
            slot.replace(new)
        };
        self.release(&old)?;
        self.charge(0, link.span)
    }

    /// `obj.Field(i) = value`: an item of a public array variable of the object, converted
    /// to the array's item type ([MS-VBAL] 5.4.3.8: the member access names the variable, the
    /// index its element).
    fn set_field_item(&self, object: &Instance, link: &Link, args: &[Arg], value: &Expr) -> Run<()> {
        let item = self.item_var(value)?;
        let date = matches!(&item, Var::Value(v) if self.as_date(value, v).is_some());
        let at = args.iter().map(|a| self.index(&a.value, "an array index")).collect::<Run<Vec<i64>>>()?;
        let put = {
            let mut fields = object.0.fields.borrow_mut();
            let slot = fields.get_mut(&link.name).expect("a public variable");
            let own = slot.name.clone();
            let variant = matches!(slot.ty, None | Some(Ty::Variant));
            let item = match item {
                Var::Value(v) => convert(Var::Value(v), slot.ty.as_ref(), &own).map_err(|m| (13, m)),
                other if variant => Ok(other),
                _ => Err((13, format!("{own}: an array of a declared type holds values (type mismatch)"))),
            };
            match (item, slot.var_mut()) {
                (Ok(item), Var::Array(a)) => self.put_nested(a, &own, &[at], item, date && variant),
                (Err(e), _) => Err(e),
                (Ok(_), _) => Err((13, format!("Type mismatch (run-time error 13): {own} is not an array"))),
            }
        };
        match put {
            Ok(old) => old.map_or(Ok(()), |o| self.release(&Var::Obj(o))),
            Err((code, m)) => {
                let mut f = self.fault_at(link.span, m);
                f.code = code;
                Err(f)
            }
        }
    }

    /// Calls a member procedure for `object`, the arguments checked first (the parser does
    /// not know the class of a variable); `value` is a Property Let's or Set's last argument.
    fn call_method(
        &self,
        ctx: &mut Ctx,
        object: &Instance,
        proc: usize,
        args: &[Arg],
        value: Option<Var>,
        span: Span,
    ) -> Run<Var> {
        self.check_member_args(proc, args, value.is_some(), span)?;
        let call = Call { me: Some(object.clone()), value, lent: Vec::new() };
        let (result, frame) = self.call_frame(ctx, proc, args, span, call)?;
        Ok(self.returned(proc, result, &frame))
    }

    /// What a member procedure gave: a Function's or Property Get's variable of its name as it
    /// holds it (an object, an array with its bounds), a Sub's nothing.
    fn returned(&self, proc: usize, result: Value, frame: &Frame) -> Var {
        let p = &self.module.procs[proc];
        match p.kind {
            ProcKind::Function => frame.vars.get(&p.name).map_or(Var::Value(result), |s| s.var().clone()),
            ProcKind::Sub => Var::Value(Value::Blank),
        }
    }

    /// `a = obj.Items(1)`: the array a class's Function just returned, with its bounds, when
    /// `v` is that array (a Function's array keeps its bounds, [MS-VBAL] 5.3.1.5).
    pub(super) fn method_result(&self, v: &Value) -> Option<Var> {
        let Value::Array(data) = v else { return None };
        let kept = self.method_array.borrow_mut().take()?;
        Rc::ptr_eq(&kept.data, data).then_some(Var::Array(kept))
    }

    /// What the parser checks of a call of the module's own procedure, checked at run time.
    fn check_member_args(&self, proc: usize, args: &[Arg], value: bool, span: Span) -> Run<()> {
        let p = &self.module.procs[proc];
        let params = p.params.len().saturating_sub(usize::from(value));
        if value && p.params.is_empty() {
            return Err(self.fault_at(span, format!("Property {} has no parameter for the value", p.name)));
        }
        let wrong = |m: String| Err(self.fault_at(span, m));
        if args.len() > params && !super::param_array::has_param_array(p) {
            return wrong(format!(
                "{}.{} takes at most {params} arguments, not {}",
                self.class_name(p.part),
                p.name,
                args.len()
            ));
        }
        for (i, a) in args.iter().enumerate() {
            match &a.name {
                Some(n) if !p.params[..params].iter().any(|q| q.name.eq_ignore_ascii_case(n)) => {
                    return wrong(format!("{} has no parameter {n}", p.name))
                }
                None if args[..i].iter().any(|b| b.name.is_some()) => {
                    return wrong("a positional argument cannot follow a named one".into())
                }
                _ => {}
            }
        }
        let given = |i: usize, name: &str| {
            args.get(i).is_some_and(|a| a.name.is_none() && a.value.kind != ExprKind::Missing)
                || args.iter().any(|a| a.name.as_deref().is_some_and(|n| n.eq_ignore_ascii_case(name)))
        };
        let required = p.params[..params].iter().enumerate().filter(|(_, q)| !q.optional && !q.param_array);
        if let Some((_, q)) = required.into_iter().find(|(i, q)| !given(*i, &q.name)) {
            return wrong(format!("{}: argument {} is not optional", p.name, q.name));
        }
        Ok(())
    }

    fn class_name(&self, part: usize) -> &str {
        self.module.parts.get(part).map_or("the object", |p| &p.name)
    }

    /// An argument that is an object, passed as the object: a variable holding one, `Me`,
    /// `obj.Child`, `New Class1`. `None` for the other arguments (values, ranges, arrays).
    pub(super) fn object_arg(&self, ctx: &mut Ctx, e: &Expr) -> Run<Option<Var>> {
        match &e.kind {
            // A variable holding an object passes the object: a Worksheet, a Workbook, a
            // TextStream, Nothing … ([MS-VBAL] 5.3.1.11: an argument of an object is a reference
            // to it). A Range passes as the range the evaluator reads.
            ExprKind::Name(n) => {
                Ok(self.lookup(n).filter(|v| matches!(v, Var::Obj(o) if !matches!(o, Obj::Range(..)))))
            }
            ExprKind::Host(id) => match &self.module.nodes[*id as usize] {
                Node::New { class, span } => self.new_object(*class, *span).map(Some),
                // An object parameter given Nothing holds no object (TypeName "Nothing").
                Node::Nothing => Ok(Some(Var::Obj(Obj::Value(Value::Blank)))),
                // `J(z(1))`: an item of a Collection or Dictionary that is an object passes it.
                Node::Element { var, index, span } if self.store_named(var).is_some() => {
                    let store = self.store_named(var).expect("checked by the guard");
                    let key = self.store_key(ctx, index, *span)?;
                    Ok(Some(self.store_item(&store, &key, *span)?).filter(|v| matches!(v, Var::Obj(_))))
                }
                Node::Element { var, index, span } if self.array_object(*id).is_some() => {
                    // An item that is an array passes with its bounds ([MS-VBAL] 2.2).
                    Ok(Some(self.array_item(var, index, *span)?).filter(|v| matches!(v, Var::Obj(_) | Var::Array(_))))
                }
                Node::Path(path) => {
                    // Noted: `F(Cells(r, c).Value)` of a date-formatted cell passes a Date.
                    let object = self.noting_date(*id, || self.path(ctx, path));
                    self.take_pending()?;
                    Ok(Some(match object? {
                        // `hasKey(Worksheets, "Data")`: the collection of sheets passes as an object.
                        o @ (Obj::Instance(_)
                        | Obj::Store(_)
                        | Obj::Sheet(_)
                        | Obj::Sheets
                        | Obj::Workbook
                        | Obj::Files(_)) => Var::Obj(o),
                        other => match self.operand_of(other, path.span)? {
                            crate::eval::Operand::Ref(sheet, rect) => Var::Obj(Obj::Range(sheet, rect)),
                            operand => array_var(ctx.deref(operand), self.option_base()),
                        },
                    }))
                }
                _ => Ok(None),
            },
            _ => Ok(None),
        }
    }

    /// `Me` in a class module's procedure: the object it runs for.
    pub(super) fn me(&self) -> Option<Instance> {
        self.frames.borrow().last().and_then(|f| f.me.clone())
    }
}
