//! The macro syntax tree. Plain data: statements here, expressions as formula trees
//! ([`Expr`]) whose macro-only parts (member paths, calls of the module's procedures,
//! `[B3]`) are [`Node`]s in the module's table, referenced by `ExprKind::Host(index)`.
//! Variables are `ExprKind::Name`s, read through the evaluator's `Host::variable`.

use std::fmt;
use std::rc::Rc;

use crate::formula::ast::Expr;

/// A place in the macro source: 1-based line and column (in characters).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Span {
    pub line: u32,
    pub col: u32,
}

impl fmt::Display for Span {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}, column {}", self.line, self.col)
    }
}

/// A parsed `.bas` module.
#[derive(Debug, Default)]
pub struct Module {
    /// `Option Explicit` of the module run first; each module's own is in `options`.
    pub explicit: bool,
    /// `Option Base 1`: the lower bound of arrays dimensioned without one (the module run
    /// first's; each module's own is in `options`).
    pub base: i64,
    /// `Option Compare Text`: text compares without case ([MS-VBAL] 5.2.1.4; Binary, the
    /// default, by code units). The module run first's; each module's own is in `options`.
    pub text_compare: bool,
    /// Each module's `Option Base` and `Option Compare`, by its place in `parts`: a module
    /// directive applies to its own module only ([MS-VBAL] 5.2.1), so a project's modules
    /// may differ. Missing past the end: the defaults (Base 0, Compare Binary).
    pub options: Vec<ModuleOptions>,
    /// Module-level `Dim`/`Private`/`Public` variables and `Const`s, in order.
    pub globals: Vec<Stmt>,
    pub procs: Vec<Proc>,
    /// The module's `Type`s; `Ty::Record(i)` is `types[i]`.
    pub types: Vec<TypeDef>,
    /// The macro-only expression nodes; `ExprKind::Host(i)` is `nodes[i]`.
    pub nodes: Vec<Node>,
    /// The modules of the project whose code this source joins, the module run first
    /// (empty: one module alone).
    pub parts: Vec<Part>,
    /// The project's class modules (`Made::Object(i)` is `classes[i]`).
    pub classes: Vec<ClassDef>,
    /// The module-level names a standard module declares Public (variables, constants, Enum
    /// members), ASCII lower case, with that module's place in `parts`: where a procedure of
    /// another module finds one it does not declare itself ([MS-VBAL] 5.6.10). A name Public
    /// in several modules keeps the first; the parser refuses its unqualified use elsewhere.
    pub public_names: std::collections::HashMap<Box<str>, usize>,
}

/// One module's `Option Base`, `Option Compare` and `Option Explicit` directives ([MS-VBAL]
/// 5.2.1.2, 5.2.1.4, 5.2.1.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ModuleOptions {
    /// `Option Base 1`: the lower bound of arrays dimensioned without one.
    pub base: i64,
    /// `Option Compare Text`: text compares without case.
    pub text_compare: bool,
    /// `Option Explicit`: every variable the module uses must be declared (checked by the
    /// parser); another module of the project without it may still use undeclared ones.
    pub explicit: bool,
}

/// A class module: what each of its objects holds and which procedures are its members.
#[derive(Debug)]
pub struct ClassDef {
    pub name: Rc<str>,
    /// The module's place in `Module::parts`: its procedures are those of this part.
    pub part: usize,
    /// The module-level `Dim`/`Private`/`Public`/`Const` statements: each object's own variables.
    pub fields: Vec<Stmt>,
    /// The fields declared `Public` (ASCII lower case): the only ones other code reaches.
    pub public: Vec<String>,
    /// `Implements IShape`: the interfaces whose members its `IShape_Member` procedures are.
    pub implements: Vec<Rc<str>>,
}

/// One module of a project joined into one source: its name and the line it starts at.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Part {
    pub name: Rc<str>,
    pub first_line: u32,
    /// A class module: its procedures are members of its objects, not names of the project.
    pub class: bool,
    /// A class module with `Attribute VB_PredeclaredId = True` (as exported .cls files and
    /// UserForms carry): it has a default instance named after the class (`classes.rs`).
    pub predeclared: bool,
    /// A class module's members reached without their names (`classes.rs`).
    pub special: SpecialMembers,
}

/// The members of a class module that VBA reaches without naming them, as the editor keeps
/// them in the module's source (`Attribute Item.VB_UserMemId = 0` inside the procedure, or
/// after a public variable): the default member (DISPID 0: `obj(1)`, `x = obj`) and the
/// enumerator (DISPID_NEWENUM, -4: `For Each x In obj`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SpecialMembers {
    pub default: Option<Rc<str>>,
    pub enumerator: Option<Rc<str>>,
}

/// The module of a joined project (its place in `parts`, which are in the order of their
/// first lines) that source line `line` belongs to, found by bisection: a scan of the modules
/// for each item of a project of 2,000 modules went over 2,000 modules for each of its items.
pub fn part_of_line(parts: &[Part], line: u32) -> usize {
    super::count(&super::PARTS_SEARCHED, u64::from(usize::BITS - parts.len().leading_zeros()));
    parts.partition_point(|p| p.first_line <= line).saturating_sub(1)
}

impl Module {
    /// The `Option Base`/`Option Compare` of the module at `part` (its place in `parts`).
    pub fn options_of(&self, part: usize) -> ModuleOptions {
        self.options.get(part).copied().unwrap_or_default()
    }

    /// The `Option Base`/`Option Compare` of the module declaring procedure `proc`.
    pub fn options_of_proc(&self, proc: usize) -> ModuleOptions {
        self.procs
            .get(proc)
            .map_or(ModuleOptions { base: self.base, text_compare: self.text_compare, explicit: self.explicit }, |p| {
                self.options_of(p.part)
            })
    }

    /// A Sub or Function by name (any case).
    pub fn proc(&self, name: &str) -> Option<usize> {
        self.procs.iter().position(|p| p.name.eq_ignore_ascii_case(name))
    }

    /// The module of the project (its place in `parts`) the source line belongs to.
    pub fn part_at_line(&self, line: u32) -> usize {
        part_of_line(&self.parts, line)
    }

    /// The module declaring `name` Public at its level, if one does (any case).
    pub fn public_part(&self, name: &str) -> Option<usize> {
        match self.public_names.get(name) {
            Some(&part) => Some(part),
            None => self.public_names.get(name.to_ascii_lowercase().as_str()).copied(),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProcKind {
    Sub,
    Function,
}

impl fmt::Display for ProcKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ProcKind::Sub => "Sub",
            ProcKind::Function => "Function",
        })
    }
}

#[derive(Debug)]
pub struct Proc {
    pub name: Rc<str>,
    pub kind: ProcKind,
    pub params: Vec<Param>,
    /// `Function F() As Double`: the type of the result.
    pub ty: Option<Ty>,
    pub body: Block,
    pub span: Span,
    /// Not declared `Private`: a cell may call a public Function of a standard module.
    pub public: bool,
    /// The module of the project it is in (`Module::parts`; 0 for a module alone).
    pub part: usize,
    /// `Property Get|Let|Set`: a Get is a Function, a Let or Set a Sub taking the value last.
    pub property: Option<PropertyKind>,
    /// The body's line numbers (`30  x = 1 / 0`), each with the source line it labels, in
    /// source order: what `Erl` reads after an error.
    pub line_numbers: Box<[(u32, u32)]>,
}

/// The three kinds of property procedure ([MS-VBAL] 5.3.1.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PropertyKind {
    Get,
    Let,
    Set,
}

#[derive(Debug)]
pub struct Param {
    pub name: Rc<str>,
    /// VBA passes by reference unless `ByVal` says otherwise.
    pub by_ref: bool,
    pub optional: bool,
    pub default: Option<Expr>,
    pub ty: Option<Ty>,
    /// `a() As Long`: the parameter is an array of the declared type, not one value of it.
    pub array: bool,
    /// `ParamArray args()`: the last parameter, taking every argument from its position on
    /// as one Variant array ([MS-VBAL] 5.3.1.5).
    pub param_array: bool,
}

/// A declared type, as far as it changes what a variable holds.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Ty {
    /// Integer, Long, LongLong, Byte: whole numbers, halves rounded to even, by their
    /// VarType number (2 Integer, 3 Long, 17 Byte, 20 LongLong), which also sets their range.
    Whole(u8),
    /// Double, Single, Currency, Decimal and Date, by their VarType number (5, 4, 6, 14,
    /// [`DATE_VAR_TYPE`]); a Date holds its day count as the 1900 date system counts.
    Number(u8),
    String,
    /// `String * n`: a String always `n` characters long, padded with spaces or truncated
    /// on assignment ([MS-VBAL] 5.5.1.2, Let-coercion to String * length).
    FixedString(u32),
    Boolean,
    /// Variant: holds anything.
    Variant,
    /// An object type (Object, Range, Worksheet, Collection, a class module …): holds
    /// anything as a Variant does, but starts as Nothing, not Empty ([MS-VBAL] 5.2.3.1.3:
    /// an object variable's default value is Nothing).
    Object,
    /// A `Type` of the module, by index.
    Record(usize),
}

/// VarType's number for a Date (vbDate): `Ty::Number(DATE_VAR_TYPE)` is the Date type.
pub const DATE_VAR_TYPE: u8 = 7;

/// 2^63, one past a LongLong's top ("LongLong data type": -9,223,372,036,854,775,808 to
/// 9,223,372,036,854,775,807): a LongLong is at least -2^63 and below this. The values are
/// doubles, so the top itself reads as 2^63 and overflows: its largest whole double is 2^63 - 1024.
pub const LONG_LONG_END: f64 = 9_223_372_036_854_775_808.0;

/// An array's declared bounds, a dimension each: `(lower, upper)`, the lower one when given
/// (`Dim a(1 To 3, 5)`).
pub type Bounds = Vec<(Option<Expr>, Expr)>;

/// `Type Name … End Type`: its fields in order, with their types.
#[derive(Debug)]
pub struct TypeDef {
    pub name: Rc<str>,
    pub fields: Vec<(Rc<str>, Ty)>,
    /// The bounds of each field that is an array, by the field's index (`x(1 To 100) As
    /// Double`; none given for a dynamic one, `v() As Double`); `None` for the others.
    pub bounds: Vec<Option<Bounds>>,
}

impl TypeDef {
    pub fn field(&self, name: &str) -> Option<usize> {
        self.fields.iter().position(|(f, _)| f.eq_ignore_ascii_case(name))
    }
}

/// Statements in order, and where each label points (the index of the next statement).
#[derive(Debug, Default)]
pub struct Block {
    pub stmts: Vec<Stmt>,
    /// Label names in ASCII lower case: found in one step, so that neither a module of many
    /// labels nor a loop of `GoTo`s costs time in proportion to their number.
    labels: std::collections::HashMap<Box<str>, usize>,
    /// The labels inside the statements' own blocks (an If's arms, a loop's body …, at any
    /// depth), each with the index of the statement holding it: where a GoTo, an On Error
    /// GoTo or a Resume from outside that statement goes in ("GoTo statement": any line
    /// label of the procedure).
    nested: std::collections::HashMap<Box<str>, usize>,
}

impl Block {
    pub fn label(&self, name: &str) -> Option<usize> {
        self.labels.get(name.to_ascii_lowercase().as_str()).copied()
    }

    /// The statement holding label `name` in one of its own blocks, at any depth.
    pub fn nested_label(&self, name: &str) -> Option<usize> {
        self.nested.get(name.to_ascii_lowercase().as_str()).copied()
    }

    /// Notes that statement `at` holds `inner`, with its labels and those nested in it.
    pub fn note_nested(&mut self, at: usize, inner: &Block) {
        for name in inner.labels.keys().chain(inner.nested.keys()) {
            self.nested.entry(name.clone()).or_insert(at);
        }
    }

    /// Puts `stmt` first, every label still pointing at the statement it pointed at.
    pub fn prepend(&mut self, stmt: Stmt) {
        self.stmts.insert(0, stmt);
        for at in self.labels.values_mut().chain(self.nested.values_mut()) {
            *at += 1;
        }
    }

    /// Adds a label pointing at the next statement; false when the block has it already.
    pub fn add_label(&mut self, name: &str) -> bool {
        let at = self.stmts.len();
        match self.labels.entry(name.to_ascii_lowercase().into()) {
            std::collections::hash_map::Entry::Occupied(_) => false,
            std::collections::hash_map::Entry::Vacant(v) => {
                v.insert(at);
                true
            }
        }
    }
}

#[derive(Debug)]
pub struct Stmt {
    pub kind: StmtKind,
    pub span: Span,
}

#[derive(Debug)]
pub enum StmtKind {
    Dim(Vec<VarDecl>),
    /// `Static n`: a procedure's variable that keeps its value from one call to the next.
    Static(Vec<VarDecl>),
    ReDim {
        preserve: bool,
        vars: Vec<VarDecl>,
    },
    /// `Const C As Integer = 2.5`: each name, its declared type, and its value's expression.
    Const(Vec<(Rc<str>, Option<Ty>, Expr)>),
    /// `x = …`, `Range("B3").Value = …`, `Set r = …`.
    Assign {
        target: Target,
        value: Expr,
        set: bool,
    },
    /// A call statement or a method: evaluating the expression does the work.
    Call(Expr),
    Print(Vec<PrintItem>),
    If {
        arms: Vec<(Expr, Block)>,
        otherwise: Option<Block>,
    },
    Select {
        subject: Expr,
        cases: Vec<Case>,
        otherwise: Option<Block>,
    },
    For {
        var: Rc<str>,
        from: Expr,
        to: Expr,
        step: Option<Expr>,
        body: Block,
    },
    ForEach {
        var: Rc<str>,
        group: Expr,
        body: Block,
    },
    /// `Do [While|Until c] … Loop [While|Until c]` and `While c … Wend`.
    Do {
        test: Option<LoopTest>,
        at_end: bool,
        body: Block,
    },
    With {
        object: Expr,
        body: Block,
    },
    Exit(ExitKind),
    GoTo(Rc<str>),
    /// `GoSub label`: runs from the label up to `Return`, then goes on after the GoSub.
    GoSub(Rc<str>),
    Return,
    OnError(OnError),
    Resume(Resume),
    /// `End`: stops the macro.
    End,
    /// `Stop`: VBA suspends for its debugger; ncsheet has none and stops the macro there.
    Stop,
    /// `Randomize [seed]`: restarts the document's random sequence (from the clock without a seed).
    Randomize(Option<Expr>),
    /// `Error n`: raises run-time error n ([MS-VBAL] 5.4.4.3; "Error statement").
    Error(Expr),
    /// `Erase a, b`: every item of each array back to its type's default.
    Erase(Vec<Rc<str>>),
    /// `Open`, `Print #`, `Write #`, `Input #`, `Line Input #`, `Close` (`files.rs`).
    File(super::files::FileStmt),
    /// The procedure does not compile: running it stops the macro with this message, at
    /// the statement's place (a syntax error, which no `On Error` traps).
    CompileError(Rc<str>),
}

/// What a runtime error does in the procedure from an `On Error` statement on.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum OnError {
    /// `On Error GoTo label`: run the handler at the label (of the procedure's body, or of a
    /// block around the statement: then the handler runs in place).
    GoTo(Rc<str>),
    /// `On Error Resume Next`: go on with the next statement.
    ResumeNext,
    /// `On Error GoTo 0`: errors stop the procedure again.
    Off,
    /// `On Error GoTo -1`: the running handler is done; the next error may be handled again.
    Reset,
}

/// Where a handler goes back to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Resume {
    /// `Resume`: the statement that failed, again.
    Retry,
    /// `Resume Next`: the statement after it.
    Next,
    /// `Resume label`.
    Label(Rc<str>),
}

#[derive(Debug)]
pub struct VarDecl {
    pub name: Rc<str>,
    pub ty: Option<Ty>,
    /// `Dim a(1 To 5, 3)`: (lower, upper) per dimension, lower `None` for Option Base.
    pub bounds: Option<Bounds>,
    /// `Dim c As New Collection`: the object the variable starts with.
    pub new: Option<Made>,
    pub span: Span,
    /// `ReDim p.v(5)`: the array field of the Type variable `name` that ReDim sizes; the
    /// fields leading to it joined by dots for a field of a nested Type (`ReDim p.inner.v(5)`:
    /// `inner.v`).
    pub field: Option<Rc<str>>,
    /// `ReDim pts(i).v(5)`: the indexes of the item of the array of a Type `name` whose field
    /// ReDim sizes.
    pub item: Option<Vec<Expr>>,
}

/// The classes a macro can make objects of (`New Collection`, `CreateObject("Scripting.Dictionary")`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Class {
    Collection,
    Dictionary,
    /// .NET's `System.Collections.ArrayList` as VBA reaches it through COM (`array_list.rs`).
    ArrayList,
}

/// What `New` makes: a Collection or a Dictionary, or an object of a class module of the
/// project (by its index in `Module::classes`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Made {
    Store(Class),
    Object(usize),
    /// VBScript's RegExp (`regexp.rs`).
    RegExp,
}

#[derive(Debug)]
pub struct LoopTest {
    pub until: bool,
    pub cond: Expr,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExitKind {
    For,
    Do,
    Sub,
    Function,
}

#[derive(Debug)]
pub enum PrintItem {
    Value(Expr),
    /// `;`: no space.
    Join,
    /// `,`: to the next print zone.
    Zone,
}

#[derive(Debug)]
pub struct Case {
    pub tests: Vec<CaseTest>,
    pub body: Block,
}

#[derive(Debug)]
pub enum CaseTest {
    Value(Expr),
    Range(Expr, Expr),
    /// `Case Is >= 5`: the comparison as a binary operator applied to the subject.
    Is(crate::formula::ast::BinOp, Expr),
}

/// What an assignment writes.
#[derive(Debug)]
pub enum Target {
    /// A variable (or the function's result, by the function's name).
    Var(Rc<str>),
    /// `a(i, j)`: an element of an array variable.
    Element(Rc<str>, Vec<Expr>),
    /// A member path or `[B3]`: a node of the module (`Node::Path` or `Node::Evaluate`).
    Node(u32),
}

/// A macro-only expression node.
#[derive(Debug)]
pub enum Node {
    /// A call of the module's own Function or Sub.
    Call { proc: usize, args: Vec<Arg>, span: Span },
    /// `Range("B3").Value`, `Cells(i, 2)`, `Nc.Line x, z`, `ws.Name`, `.Value` in a With block.
    Path(Path),
    /// `a(i)`: an element of an array variable.
    Element { var: Rc<str>, index: Vec<Expr>, span: Span },
    /// `UBound(a, 1)`, `LBound(a)`, `UBound(Split(s, ","))`: the bounds of the array a
    /// variable holds, or of the one an expression gives (a Function's, an item's, Split's).
    Bound { upper: bool, of: Expr, dim: Option<Expr>, span: Span },
    /// `[B3]`, `[Sheet2!A1:C4]`, `[D]`: formula text evaluated as in a cell (no macro variables).
    Evaluate { expr: Expr, span: Span },
    /// `object Is Nothing` (`other` is `None`) or `object Is other`: the same object or not.
    Is { object: Expr, other: Option<Expr>, span: Span },
    /// `TypeOf object Is Type` ([MS-VBAL] 5.6.7): whether the object is of the type named
    /// (`Collection`, `Excel.Range`, a class module, an interface it implements, `Object`).
    TypeOf { object: Expr, ty: Rc<str>, span: Span },
    /// `VarType(x)`, `IsMissing(x)`, `TypeName(x)`, `IsObject(x)`: what a variable is, which its
    /// declaration tells.
    Inspect { what: Inspect, arg: Expr, span: Span },
    /// `d(k)(i)`, `Split(s)(0)`, `f()(2)`: what `base` gives (an array, a Collection, a
    /// Dictionary), indexed in the same expression.
    Index { base: Expr, index: Vec<Expr>, span: Span },
    /// `A(1)(2).Count`, `d("k")(0).Name`, `coll(1)(2).Add x`: the members of what `base`
    /// gives (an indexed item), followed as a path follows its links after its root
    /// ([MS-VBAL] 5.6.12 and 5.6.13: a member access or an index applies to any expression).
    Members { base: Expr, path: Path },
    /// VBA's `Null`.
    Null,
    /// The constant `Empty`: a given argument, not a left-out one (`f Empty`), which the
    /// formula tree's `Missing` would be.
    Empty,
    /// The constant `Nothing`: an object reference to no object, given as an argument
    /// (`dict.Add k, Nothing`, `Export Nothing`) or assigned with Set.
    Nothing,
    /// An argument of a worksheet function (`Application.Transpose(a)`): an array of arrays
    /// reads as a two-dimensional array, one row per inner array, as Excel reads one.
    SheetArg { arg: Expr, span: Span },
    /// `New Collection`, `CreateObject("Scripting.Dictionary")`: a new object of the class.
    New { class: Made, span: Span },
    /// `WorksheetFunction.Match(…)`: a worksheet function called through Excel's
    /// WorksheetFunction object, whose error result is raised as run-time error 1004 ("Unable
    /// to get the Match property of the WorksheetFunction class"), where `Application.Match(…)`
    /// returns the error value.
    SheetCall { call: Expr, name: Rc<str>, span: Span },
    /// `VBA.Array(…)`: Array qualified by its type library, an array from 0 whatever the
    /// Option Base ("Array function": the lower bound is Option Base's "unless Array is
    /// qualified with the name of the type library (for example VBA.Array)").
    ZeroBasedArray { call: Expr },
    /// `Sheets("Data").Application.WorksheetFunction.Max(…)`, `ws.Application.Max(…)`: a call
    /// of Application's own reached through the `Application` of another object, which is
    /// evaluated first for its errors (a sheet the workbook lacks is still error 9).
    Through { object: Path, call: Expr },
}

/// The questions [`Node::Inspect`] asks of a variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Inspect {
    VarType,
    IsMissing,
    /// `TypeName(x)`: the name of a variable's type or of what it holds.
    TypeName,
    /// `IsObject(x)`: an object (a Range, a Collection, Nothing …), not a value.
    IsObject,
    /// `IsDate(x)`: a Date, or text that reads as a date or time.
    IsDate,
    /// `IsEmpty(x)`: a Variant never given a value; an object without a value is not.
    IsEmpty,
    /// `Len(x)` (`LenB(x)` with `bytes`): a fixed-size variable's bytes, else the text's
    /// length; the node's expression is the function table's call (`storage_size.rs`).
    Len {
        bytes: bool,
    },
}

#[derive(Debug)]
pub struct Path {
    /// Starts with `.`: a member of the innermost With object.
    pub with: bool,
    pub links: Vec<Link>,
    pub span: Span,
}

/// One `Name(args)` of a member path.
#[derive(Debug)]
pub struct Link {
    pub name: Rc<str>,
    pub args: Option<Vec<Arg>>,
    pub span: Span,
}

#[derive(Clone, Debug)]
pub struct Arg {
    /// `x:=1`
    pub name: Option<Rc<str>>,
    /// `ExprKind::Missing` when left empty (`Nc.Line , -10`).
    pub value: Expr,
}
