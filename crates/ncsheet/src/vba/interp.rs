//! The interpreter: walks statements, keeps variables in call frames, and evaluates every
//! expression with the one evaluator ([`Ctx`]), to which it is both the `Env` (cells, through
//! the workbook) and the `Host` (variables and macro-only nodes); that bridge is `host.rs`,
//! and what variables hold is `value.rs`.
//!
//! It is reentrant through the evaluator — a Function called inside an expression runs its
//! statements while that expression is being evaluated — so its state sits in cells
//! (`RefCell`), each borrowed only for a moment. A failure inside a host node cannot unwind
//! through the evaluator: it is parked in `pending`, later host nodes do nothing, and the
//! statement that started the evaluation raises it.

use std::cell::{Cell, RefCell};
use std::rc::Rc;

use crate::eval::coerce::{compare, to_bool, to_number};
use crate::eval::dates::DateSystem;
use crate::eval::evaluator::binary;
use crate::eval::functions::vba::errors;
use crate::eval::{Ctx, Operand, Value, XlError};
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::{Expr, ExprKind, SheetId};
use crate::workbook::{Input, Workbook, WorkbookError};

use super::ast::*;
use super::classes::Instance;
use super::collections::Handle;
use super::host::is_nothing;
use super::parser::Lines;
use super::typing::Declared;
use super::value::{array_var, convert, default_value, input_text, print_text, range_var, Obj, Slot, Slots, Var};
use super::{ErrorKind, MacroError, Printed, RunOptions, RunOutput};

/// The array items a copy moves for the price of one statement ([`Interp::count_copy`]).
/// Measured in release (benches/README.md): a statement costs about 0.57 µs of CPU, copying an
/// item of a two-dimensional `ReDim Preserve` 23 ns; at 64 items a statement a loop of them
/// ran 2.6 times the time its statement count stood for, and passed 30 s within the limit.
pub(super) const ITEMS_PER_STATEMENT: u64 = 16;

/// The text and array work that counts as one statement ([`Interp::tick`]), in the units the
/// evaluator reports it in ([`crate::eval::Host::work`]: an item made or read, or 16 bytes of
/// text made or read). Measured in release against a statement's 0.57 µs of CPU
/// (benches/README.md): a unit of `Split` (its items) costs 180 ns, of `InStr` 96 ns, of
/// `Replace` 67 ns, of a comparison 34 ns, of a cell `WorksheetFunction.Sum` reads 24 ns;
/// four units a statement keep the dearest within the time the limit stands for.
pub(super) const WORK_PER_STATEMENT: u64 = 4;

/// The statements a trapped error counts for besides the statement that raised it
/// ([`Interp::trap`]): measured in release, a raise handled by `On Error Resume Next` or a
/// handler costs about 1.25 µs, two statements' time (0.57 µs each), and a loop of them ran
/// 21–37 s before the limit stopped it; three keep it within the time the limit stands for.
pub(super) const TRAPPED_ERROR_STATEMENTS: u64 = 3;

/// Runs the entry procedure that `options` chooses.
pub fn run(
    module: &Module,
    wb: &mut Workbook,
    source: &str,
    file: &str,
    options: &RunOptions,
) -> Result<RunOutput, MacroError> {
    if wb.sheet_len() == 0 {
        // A workbook always has a sheet for Range and Cells to mean, as in Excel.
        wb.add_sheet("Sheet1").expect("the first sheet");
    }
    let sheet_named = |name: &str| wb.sheet_id(name).ok_or_else(|| format!("the workbook has no sheet named {name}"));
    let home = match &options.document {
        Some(super::Document::Sheet(name)) => Some(sheet_named(name).map_err(|m| usage(file, m))?),
        _ => None,
    };
    // A sheet's button is clicked on that sheet: it is the active one, unless --sheet says.
    let active = match &options.sheet {
        Some(name) => sheet_named(name).map_err(|m| usage(file, m))?,
        None => home.unwrap_or(wb.active_sheet()),
    };
    let code_sheets = options
        .code_names
        .iter()
        .filter_map(|(code, sheet)| Some((code.to_ascii_lowercase(), wb.sheet_id(sheet)?)))
        .collect();
    let saved: Vec<(SheetId, Vec<Rect>, Pos)> = options
        .active_cells
        .iter()
        .filter_map(|(sheet, pos)| Some((wb.sheet_id(sheet)?, saved_selection(options, sheet, *pos), *pos)))
        .collect();
    let cursors = saved.iter().map(|(sheet, areas, pos)| (*sheet, (area_of(areas, *pos), *pos))).collect();
    let selected_areas = saved
        .into_iter()
        .filter(|(_, areas, _)| areas.len() > 1)
        .map(|(sheet, areas, _)| (sheet, areas.into()))
        .collect();
    let entry = entry(module, options).map_err(|m| usage(file, m))?;
    let stem = std::path::Path::new(file).file_stem().and_then(|s| s.to_str()).unwrap_or("MACRO");
    // The workbook's own functions, called from cells while the macro runs, see the look
    // it gives the cells (`Range.Text` in a function shows the format the macro set).
    let looks = Rc::new(RefCell::new(super::formats::Looks::new(wb, &options.looks)));
    super::udf::share_looks(wb, &looks);
    let shared = Shared::new(source);
    let mut it = Interp::new(module, options, source, &shared, Book::Mut(wb), None);
    it.looks = looks;
    it.active.set(active);
    it.home = home;
    it.code_sheets = code_sheets;
    *it.cursors.get_mut() = cursors;
    *it.selected_areas.get_mut() = selected_areas;
    *it.out.get_mut() = RunOutput::new(&stem.to_ascii_uppercase(), options.machine);
    let result = it.start(entry);
    it.flush_line();
    // The sheet the macro activated (Activate, Sheets.Add) is the one the saved file opens on.
    if it.active.get() != active {
        if let Ok(mut book) = it.book_mut() {
            book.set_active_sheet(it.active.get());
        }
    }
    let looks = it.looks.borrow().finish(&it.wb.borrow());
    let mut output = it.out.into_inner();
    output.looks = looks;
    output.removed = it.files.borrow().removed();
    output.statements = it.steps.get();
    output.files = it.files.into_inner().into_written();
    match result {
        Ok(()) => Ok(output),
        Err(fault) => Err(it_error(source, file, fault, output)),
    }
}

/// What the runs of one program share, worked out once for it rather than at each call of a
/// workbook's function from a cell (a short call spent half its time asking the system where
/// the thread's stack ends, which for the main thread reads /proc/self/maps, and most of the
/// rest going over the whole project's source).
pub struct Shared {
    /// Where the source's lines start.
    lines: Rc<Lines>,
    /// The source may hold a Single or a Currency ([`Interp::narrow_numbers`]).
    narrow_numbers: bool,
    /// The bounds of the stack of the thread the calls run on, once a call has read them:
    /// the holder (`udf.rs`, not `Send`) stays on the thread that made it.
    stack: Cell<Option<(usize, usize)>>,
    /// The module-level variables and constants as the project's declarations leave them,
    /// once the first call of a recalculation has run them: each later call starts from these
    /// tables instead of running every declaration again (20,000 `Const` lines and 2,000
    /// cells calling a Function of their module ran 40 million declarations, 49 s).
    declared: RefCell<ModuleState>,
}

/// The module-level state of a program's calls from cells ([`Shared`]).
#[derive(Default)]
enum ModuleState {
    /// Not declared in this recalculation yet.
    #[default]
    Undeclared,
    /// As the declarations left it: a call borrows the tables and gives them back with the
    /// variables it changed put back as they were ([`Interp::restore_globals`]).
    Declared(Vec<Slots>),
    /// The declarations failed, and how: every call fails alike.
    Failed(Fault),
    /// A call has the tables: a call nested in it (a cell it reads computing through the
    /// program) runs the declarations for itself.
    Lent,
}

impl Shared {
    pub fn new(source: &str) -> Shared {
        Shared {
            lines: Rc::new(Lines::new(source)),
            narrow_numbers: super::typing::names_single_or_currency(source),
            stack: Cell::new(None),
            declared: RefCell::new(ModuleState::Undeclared),
        }
    }

    /// Lets the next call run the module-level declarations again (a new recalculation).
    pub fn forget_declarations(&self) {
        *self.declared.borrow_mut() = ModuleState::Undeclared;
    }
}

/// Calls Function `proc` of `module` from a cell of `wb` on `args` (a workbook's own function,
/// `udf.rs`): cells are read through `cells`, and any write to the workbook is an error.
/// `shared` is the program's, made from `source`.
#[allow(clippy::too_many_arguments)]
pub fn call_function(
    module: &Module,
    wb: &Workbook,
    cells: &dyn crate::eval::Env,
    (source, shared): (&str, &Shared),
    file: &str,
    options: &RunOptions,
    (proc, caller): (usize, (SheetId, Pos)),
    args: Vec<Var>,
    looks: Rc<RefCell<super::formats::Looks>>,
) -> (Result<Value, MacroError>, u64) {
    let mut it = Interp::new(module, options, source, shared, Book::Read(wb), Some(cells));
    it.looks = looks;
    it.active.set(caller.0);
    it.caller = Some(caller);
    let result = it.call_with_module_state(shared, proc, args);
    shared.stack.set(it.stack_low.get());
    let steps = it.steps.get();
    let output = it.out.into_inner();
    (result.map_err(|fault| it_error(source, file, fault, output)), steps)
}

/// The workbook a run sees: its own to change (a macro), or only to read (a function called
/// from a cell, which Excel does not let change any cell).
pub enum Book<'w> {
    Mut(&'w mut Workbook),
    Read(&'w Workbook),
}

impl std::ops::Deref for Book<'_> {
    type Target = Workbook;
    fn deref(&self) -> &Workbook {
        match self {
            Book::Mut(wb) => wb,
            Book::Read(wb) => wb,
        }
    }
}

fn it_error(source: &str, file: &str, fault: Fault, output: RunOutput) -> MacroError {
    let lines = Lines::new(source);
    MacroError {
        kind: fault.kind,
        file: file.to_string(),
        span: fault.span,
        message: fault.message,
        source_line: fault.span.map_or(String::new(), |s| lines.text(source, s.line).to_string()),
        trace: fault.trace,
        output: Box::new(output),
    }
}

/// A compile error found as the statement runs: it stops the run, and no handler traps it.
fn compile_error(message: String, span: Span) -> Fault {
    Fault { kind: ErrorKind::Syntax, code: 0, message, span: Some(span), trace: Vec::new(), source: None }
}

fn usage(file: &str, message: String) -> MacroError {
    MacroError {
        kind: ErrorKind::Usage,
        file: file.to_string(),
        span: None,
        message,
        source_line: String::new(),
        trace: Vec::new(),
        output: Box::new(RunOutput::new("", crate::nc::Machine::Lathe)),
    }
}

/// The procedure to run: `--sub NAME`, else `Main`, else the first Sub that needs no arguments.
fn entry(module: &Module, options: &RunOptions) -> Result<usize, String> {
    let subs: Vec<&str> = module.procs.iter().filter(|p| p.kind == ProcKind::Sub).map(|p| &*p.name).collect();
    if let Some(name) = &options.sub {
        return module.proc(name).ok_or_else(|| format!("no Sub named {name} (the module has: {})", subs.join(", ")));
    }
    if let Some(main) = module.proc("Main").filter(|&i| module.procs[i].kind == ProcKind::Sub) {
        return Ok(main);
    }
    // A class module's Subs need an object: none is a macro to run.
    let of_class = |p: &Proc| module.parts.get(p.part).is_some_and(|m| m.class);
    let plain = module
        .procs
        .iter()
        .position(|p| p.kind == ProcKind::Sub && p.params.iter().all(|q| q.optional) && !of_class(p));
    plain.ok_or_else(|| match subs.as_slice() {
        [] => "the module has no Sub to run".to_string(),
        _ => format!("which Sub? pass --sub NAME (the module has: {})", subs.join(", ")),
    })
}

/// A runtime failure before it is rendered: message, place (filled in by the statement when
/// the failing part did not know it) and the procedures that were running.
#[derive(Clone, Debug)]
pub struct Fault {
    pub kind: ErrorKind,
    /// VBA's error number, for `Err.Number` (0: the one its message implies).
    pub code: u32,
    pub message: String,
    pub span: Option<Span>,
    pub trace: Vec<String>,
    /// `Err.Raise n, source`: what `Err.Source` says once it is trapped (`None`: the project).
    pub source: Option<String>,
}

pub type Run<T> = Result<T, Fault>;

/// How a statement ends: on to the next, or out of a loop, a procedure or the macro.
#[derive(Debug)]
enum Flow {
    Next,
    Exit(ExitKind),
    GoTo(Rc<str>),
    End,
    /// `Return` of a GoSub.
    Return,
    /// A `Resume` of the running error handler.
    Resume(Resume),
    /// Out of the procedure: a handler or GoSub ran to its end.
    Leave,
    /// An error handler whose label is inside a block that was running when the error came
    /// (the loop, If or With around the failing statement) ran to that block's end: the
    /// block, further up, goes on as from its end (a loop steps and goes round).
    BlockEnd(*const Block),
}

/// What a trapped error makes the failing block do.
enum Trap {
    /// Go on after the failing statement.
    Next,
    /// Run the failing statement again.
    Retry,
    Flow(Flow),
}

/// `Err`: the last trapped error.
#[derive(Clone, Debug, Default)]
pub struct ErrState {
    pub number: u32,
    pub description: String,
    /// "Source property": what raised the error, `Err.Raise`'s source or the project's name.
    pub source: String,
    /// `Erl`: the line number of the last numbered line at or before the error in its
    /// procedure, 0 where none is ("Erl function" of the VBA reference; [MS-VBAL] 6.1.2.3.1.x).
    pub line: u32,
}

pub(super) struct Frame {
    pub(super) proc: usize,
    pub(super) vars: Slots,
    /// The running With blocks' objects, by their body: `None` where a GoTo or an error
    /// handler went into the With without running its With statement.
    with: Vec<(*const Block, Option<Obj>)>,
    /// The blocks running now, outermost first (for an error handler inside one of them).
    running: Vec<*const Block>,
    call_site: Option<Span>,
    on_error: OnError,
    /// The `On Error GoTo` handler is running: an error now goes to the caller.
    handling: bool,
    /// Optional Variant parameters without a default that the call left out (IsMissing).
    pub(super) missing: Vec<Rc<str>>,
    /// The object a class module's procedure runs for (`Me`): its variables are the
    /// procedure's module-level ones.
    pub(super) me: Option<Instance>,
}

impl Frame {
    /// The running With blocks' objects, to change in place (a Range following an insert).
    pub(super) fn with_objects(&mut self) -> impl Iterator<Item = &mut Obj> {
        self.with.iter_mut().filter_map(|(_, obj)| obj.as_mut())
    }
}

/// The key of the Static variables of a procedure running for `me`: the object's address,
/// 0 for a standard module's procedure ("Static statement": "In class modules, variables
/// declared with the Static statement retain their value in each class instance").
fn static_owner(me: Option<&Instance>) -> usize {
    me.map_or(0, |m| Rc::as_ptr(&m.0) as usize)
}

/// What a Let to an object variable goes through (`Interp::object_let`).
enum ObjectLet {
    Cells(Obj),
    Instance(Instance),
    Nothing,
}

/// What a call of a class module's procedure brings besides its arguments: the object it
/// runs for, and the value a Property Let or Set assigns (its last parameter).
#[derive(Default)]
pub(super) struct Call {
    pub me: Option<Instance>,
    pub value: Option<Var>,
    /// The caller's local arrays moved into ByRef parameters (the parameter's index, the
    /// caller's variable), given back even when the call fails ([`Interp::lend_array`]).
    pub lent: Vec<(usize, Rc<str>)>,
}

pub struct Interp<'m, 'w> {
    pub module: &'m Module,
    pub options: &'m RunOptions,
    source: &'m str,
    lines: Rc<Lines>,
    pub wb: RefCell<Book<'w>>,
    /// Where cells are read when a cell's formula called the function: the workbook, or the
    /// recalculation's probe, which notes what is read (cycles are found through it).
    pub cells: Option<&'w dyn crate::eval::Env>,
    /// The cell whose formula called the function (`Application.Caller`).
    pub caller: Option<(SheetId, Pos)>,
    /// The module-level variables and constants, one table per module of the project (its
    /// place in `Module::parts`): VBA gives each module its own ("Understanding scope and
    /// visibility"), so `Private Const NAME` in two modules are two constants.
    pub(super) globals: RefCell<Vec<Slots>>,
    /// The module-level variables are borrowed from the program's calls from cells
    /// ([`Shared`]): each is kept as it was before the call first reaches it to change it
    /// (`changed`, by its module and place), and put back after the call.
    noting_changes: Cell<bool>,
    changed: RefCell<crate::workbook::FxMap<(usize, usize), Slot>>,
    /// How many variables each module's table held as declared.
    declared_lengths: RefCell<Vec<usize>>,
    /// The module whose module-level declarations run while no procedure does.
    declaring: Cell<usize>,
    pub(super) frames: RefCell<Vec<Frame>>,
    pub out: RefCell<RunOutput>,
    /// A `Debug.Print` line left open by a trailing `;` or `,`.
    line: RefCell<Option<String>>,
    pub nc: RefCell<super::nc::NcState>,
    steps: Cell<u64>,
    /// Text and array work the evaluator reported ([`crate::eval::Host::work`]) not yet
    /// counted as statements, and the statements it has counted in all.
    work: Cell<u64>,
    work_steps: Cell<u64>,
    /// Static variables between calls, by procedure, the object a class module's procedure
    /// runs for ([`static_owner`], 0 for none) and name in ASCII lower case. `None` while a
    /// call of the procedure holds the variable (`Interp::statics`).
    pub(super) kept: RefCell<std::collections::HashMap<(usize, usize, String), Option<Slot>>>,
    /// The objects whose Static variables `kept` holds, by address: an object made later at
    /// the address of one that is gone starts with none of them.
    static_owners: RefCell<std::collections::HashMap<usize, std::rc::Weak<super::classes::Object>>>,
    pub(super) pending: RefCell<Option<Fault>>,
    /// The Decimals whose digits no double gives back, kept beside their doubles
    /// (`typing/decimal.rs`).
    pub(super) decimals: RefCell<super::typing::KeptDecimals>,
    /// An `End` statement ran: every procedure stops.
    pub(super) ended: Cell<bool>,
    pub active: Cell<SheetId>,
    /// `Application.ReferenceStyle` (`xlA1` 1, `xlR1C1` -4150): how Excel's window shows
    /// formulas. `.Formula` stays A1 and `.FormulaR1C1` R1C1 whatever it is, as in Excel.
    pub(super) reference_style: Cell<i32>,
    /// The harmless settings the macro wrote (`Application.StatusBar = "…"`), by object and
    /// member: a read gives them back, as Excel's does (`unmodelled.rs`).
    pub(super) harmless_settings: RefCell<std::collections::HashMap<String, Value>>,
    /// How many of [`RunOptions::answers`] the macro's dialogs took (`dialogs.rs`).
    pub(super) answered: Cell<usize>,
    /// The sheet of the document module the code is in: what unqualified `Range`, `Cells`
    /// and `[B3]` mean there, and `Me`.
    pub home: Option<SheetId>,
    /// The sheets' code names (lower case): `Sheet1.Range("A1")`.
    pub code_sheets: Vec<(String, SheetId)>,
    /// Each sheet's selection and active cell, once the file or the macro set one (else A1).
    pub cursors: RefCell<std::collections::HashMap<SheetId, (Rect, Pos)>>,
    /// A sheet's selection of several areas as the file saved it (`sqref="A1:B2 D4:E5"`),
    /// until the macro selects on that sheet: `Selection` is then all of them; `cursors`
    /// holds the area of the active cell.
    pub(super) selected_areas: RefCell<std::collections::HashMap<SheetId, Rc<[Rect]>>>,
    /// The range the last `Copy` without a destination took, for `PasteSpecial`.
    pub(super) clipboard: RefCell<Option<(SheetId, Rect)>>,
    /// The sheets `ws.Protect` protected in this run (`sheet_ops.rs`).
    pub(super) protections: RefCell<std::collections::HashMap<SheetId, super::sheet_ops::SheetProtection>>,
    /// Each worksheet's `Sort` object: its fields, range and header until `Apply` (`sort.rs`).
    pub(super) sorts: RefCell<std::collections::HashMap<SheetId, super::sort::SheetSort>>,
    /// The last `Range.Find`'s conditions, which FindNext continues and a later Find's left-out
    /// settings take (`replace.rs`).
    pub(super) find_conditions: RefCell<super::replace::FindConditions>,
    /// The array a class's Function last returned, with its bounds (`classes.rs`).
    pub(super) method_array: RefCell<Option<super::value::VArray>>,
    /// How the sheets' cells look (number formats, styles, widths), `formats.rs`: shared by a
    /// macro with the workbook's functions its writes recompute.
    pub(super) looks: Rc<RefCell<super::formats::Looks>>,
    /// Explanations the last evaluation left (why a value is an error).
    notes: RefCell<Vec<String>>,
    /// Bytes of `Debug.Print` and `MsgBox` output so far, against [`RunOptions::max_output`].
    output_bytes: Cell<u64>,
    /// Bytes stores brought since the variables were last measured (`budget.rs`).
    pub(super) charged: Cell<u64>,
    pub err: RefCell<ErrState>,
    /// GoSubs now running without their Return, across the running procedures.
    gosubs: Cell<usize>,
    /// The lowest address of this thread's stack and its size, read at the first check
    /// ([`stack_bounds`]).
    stack_low: Cell<Option<(usize, usize)>>,
    /// The files the macro wrote and those it has open (`files.rs`).
    pub(super) files: RefCell<super::files::Files>,
    /// The nodes (calls, items of arrays, Collections and Dictionaries) whose last value was
    /// a number of a type a Variant keeps (a Date, a Variant Function's Integer …): a Variant
    /// keeps its type through them ([MS-VBAL] 2.1.1.1), which the static typing of
    /// `typing.rs` cannot see.
    pub(super) node_types: RefCell<crate::workbook::FxMap<u32, Declared>>,
    /// The type of the number the last call, item or element gave (for `node_types`);
    /// `Variant` when it gave none of a kept type.
    pub(super) gave: Cell<Declared>,
    /// The types of the numbers a call passes to its parameters, by position, for the next
    /// `bind_and_run` (a Double's is left out).
    arg_types: RefCell<Vec<(usize, Declared)>>,
    /// The operations (by their first operand's address) whose last result, held in a
    /// Variant, widened past the type their operands gave it (`x * x` of the Integer 200 is
    /// a Long): what an enclosing operation, or the variable it goes to, takes it as
    /// ([`Interp::note_widening`]).
    pub(super) widened: RefCell<crate::workbook::FxMap<usize, Declared>>,
    /// The types of the running statement's operations, each worked out once (`typing.rs`).
    pub(super) types_known: super::typing::TypesKnown,
    /// The LongLongs past 2^53 kept beside their doubles (`longlong.rs`).
    pub(super) exact: RefCell<super::longlong::Exact>,
    /// The last IIf call: its condition's address and start, and the branch (1 or 2) it
    /// chose, whose type the Variant it gives holds (`TypeName(IIf(True, 1, 2.5))`).
    pub(super) iif_branch: Cell<(usize, usize, usize)>,
    /// The module may hold a Single or a Currency, whose operations are computed in their
    /// types ([`super::typing::names_single_or_currency`]).
    pub(super) narrow_numbers: bool,
}

impl<'m, 'w> Interp<'m, 'w> {
    fn new(
        module: &'m Module,
        options: &'m RunOptions,
        source: &'m str,
        shared: &Shared,
        wb: Book<'w>,
        cells: Option<&'w dyn crate::eval::Env>,
    ) -> Interp<'m, 'w> {
        Interp {
            module,
            options,
            source,
            lines: Rc::clone(&shared.lines),
            wb: RefCell::new(wb),
            cells,
            caller: None,
            globals: RefCell::new((0..module.parts.len().max(1)).map(|_| Slots::default()).collect()),
            noting_changes: Cell::new(false),
            changed: RefCell::default(),
            declared_lengths: RefCell::default(),
            declaring: Cell::new(0),
            frames: RefCell::new(Vec::new()),
            out: RefCell::new(RunOutput::new("MACRO", options.machine)),
            line: RefCell::new(None),
            nc: RefCell::new(super::nc::NcState::default()),
            steps: Cell::new(0),
            work: Cell::new(0),
            work_steps: Cell::new(0),
            kept: RefCell::new(std::collections::HashMap::new()),
            static_owners: RefCell::new(std::collections::HashMap::new()),
            pending: RefCell::new(None),
            ended: Cell::new(false),
            active: Cell::new(0),
            reference_style: Cell::new(XL_A1),
            harmless_settings: RefCell::new(std::collections::HashMap::new()),
            answered: Cell::new(0),
            home: None,
            code_sheets: Vec::new(),
            cursors: RefCell::new(std::collections::HashMap::new()),
            selected_areas: RefCell::default(),
            clipboard: RefCell::new(None),
            protections: RefCell::new(std::collections::HashMap::new()),
            sorts: RefCell::new(std::collections::HashMap::new()),
            find_conditions: RefCell::default(),
            method_array: RefCell::new(None),
            looks: Rc::new(RefCell::new(super::formats::Looks::default())),
            notes: RefCell::new(Vec::new()),
            output_bytes: Cell::new(0),
            charged: Cell::new(0),
            err: RefCell::new(ErrState::default()),
            gosubs: Cell::new(0),
            stack_low: Cell::new(shared.stack.get()),
            files: RefCell::new(super::files::Files::default()),
            node_types: RefCell::default(),
            gave: Cell::new(Declared::Variant),
            arg_types: RefCell::new(Vec::new()),
            widened: RefCell::default(),
            decimals: RefCell::default(),
            types_known: Default::default(),
            exact: RefCell::default(),
            iif_branch: Cell::new((0, 0, 0)),
            narrow_numbers: shared.narrow_numbers,
        }
    }
}

/// XlReferenceStyle's values.
pub(super) const XL_A1: i32 = 1;
pub(super) const XL_R1C1: i32 = -4150;

impl Interp<'_, '_> {
    /// The workbook, to change: refused inside a function a cell called.
    pub fn book_mut(&self) -> Run<std::cell::RefMut<'_, Workbook>> {
        std::cell::RefMut::filter_map(self.wb.borrow_mut(), |book| match book {
            Book::Mut(wb) => Some(&mut **wb),
            Book::Read(_) => None,
        })
        // Excel ends such a function at that line, #VALUE! in its cell, whatever its `On Error`
        // says ("Description of limitations of custom functions in Excel", KB 170787).
        .map_err(|_| self.unsupported_here("a function called from a cell cannot change cells (Excel does not let it)"))
    }

    /// Calls Function `proc` from a cell, starting from the module-level state the program's
    /// first call of this recalculation declared (`shared`), or declaring it here and keeping
    /// it for the calls after this one. Each call starts from the state as declared: the
    /// variables it changes are put back after it, so that no cell's value depends on the
    /// order the cells are computed in. A failure of the declarations is kept too, unless a
    /// limit (which depends on what the call had left) made it.
    fn call_with_module_state(&self, shared: &Shared, proc: usize, args: Vec<Var>) -> Run<Value> {
        let state = std::mem::replace(&mut *shared.declared.borrow_mut(), ModuleState::Lent);
        match state {
            ModuleState::Declared(tables) => *self.globals.borrow_mut() = tables,
            ModuleState::Failed(fault) => {
                *shared.declared.borrow_mut() = ModuleState::Failed(fault.clone());
                return Err(fault);
            }
            ModuleState::Undeclared => {
                if let Err(fault) = self.declare_module_level() {
                    *shared.declared.borrow_mut() = match fault.kind {
                        ErrorKind::Limit => ModuleState::Undeclared,
                        _ => ModuleState::Failed(fault.clone()),
                    };
                    return Err(fault);
                }
            }
            ModuleState::Lent => {
                *shared.declared.borrow_mut() = ModuleState::Lent;
                self.declare_module_level()?;
                return self.call_from_formula(proc, args);
            }
        }
        *self.declared_lengths.borrow_mut() = self.globals.borrow().iter().map(Slots::len).collect();
        self.noting_changes.set(true);
        let result = self.call_from_formula(proc, args);
        *shared.declared.borrow_mut() = match self.restore_globals() {
            Some(tables) => ModuleState::Declared(tables),
            None => ModuleState::Undeclared,
        };
        result
    }

    /// The module-level tables with every variable the call changed put back as declared
    /// ([`Interp::note_change`]); `None` when a table gained a variable, which only the
    /// declarations add (the next call declares them again rather than trust them).
    fn restore_globals(&self) -> Option<Vec<Slots>> {
        self.noting_changes.set(false);
        let mut tables = std::mem::take(&mut *self.globals.borrow_mut());
        for ((part, at), slot) in self.changed.borrow_mut().drain() {
            tables[part].put_at(at, slot);
        }
        let same = tables.iter().map(Slots::len).eq(self.declared_lengths.borrow().iter().copied());
        same.then_some(tables)
    }

    /// Calls Function `proc` with the arguments a formula gave it (a cell's call, or
    /// `Evaluate("F(2)")`): a ParamArray packed, too many or too few refused by name.
    pub(super) fn call_from_formula(&self, proc: usize, args: Vec<Var>) -> Run<Value> {
        let p = &self.module.procs[proc];
        let args = super::param_array::pack_cell_args(p, args);
        if args.len() > p.params.len() {
            return Err(self.fault(format!("Function {} takes at most {} arguments", p.name, p.params.len())));
        }
        if let Some(missing) = p.params.iter().skip(args.len()).find(|q| !q.optional) {
            return Err(self.fault(format!("Function {} needs {}", p.name, missing.name)));
        }
        let mut bound = Vec::with_capacity(args.len());
        for (i, arg) in args.into_iter().enumerate() {
            bound.push((i, self.range_as_declared(arg, p.params[i].ty.as_ref())?));
        }
        self.invoke(proc, bound, None)
    }

    /// A cell's range given to a parameter declared as a number, text or boolean is the
    /// range's value (VBA reads its default member); a range of several cells does not fit.
    fn range_as_declared(&self, arg: Var, ty: Option<&Ty>) -> Run<Var> {
        match (arg, ty) {
            (
                Var::Obj(Obj::Range(sheet, rect)),
                Some(Ty::Whole(_) | Ty::Number(_) | Ty::String | Ty::FixedString(_) | Ty::Boolean),
            ) => {
                if rect.rows() != 1 || rect.cols() != 1 {
                    return Err(
                        self.fault("a range of several cells given where one value is declared (type mismatch)")
                    );
                }
                Ok(Var::Value(self.ctx().rect_value(sheet, rect).unwrap_single()))
            }
            (arg, _) => Ok(arg),
        }
    }

    /// Runs every module's module-level declarations, each into its module's own table.
    fn declare_module_level(&self) -> Run<()> {
        for g in &self.module.globals {
            self.declaring.set(self.module.part_at_line(g.span.line));
            self.exec(g)?;
        }
        Ok(())
    }

    fn start(&self, entry: usize) -> Run<()> {
        self.declare_module_level()?;
        let proc = &self.module.procs[entry];
        let mut bound = Vec::new();
        for (name, text) in &self.options.args {
            let Some(i) = proc.params.iter().position(|p| p.name.eq_ignore_ascii_case(name)) else {
                let names: Vec<&str> = proc.params.iter().map(|p| &*p.name).collect();
                return Err(self.plain_fault(
                    ErrorKind::Usage,
                    format!("{} {} has no parameter {name} (it has: {})", proc.kind, proc.name, names.join(", ")),
                ));
            };
            let value = match Input::parse(text, DateSystem::From1900) {
                Input::Empty => Value::Blank,
                Input::Value(v) => v,
                Input::Formula(f) => Value::text(f),
            };
            bound.push((i, Var::Value(value)));
        }
        for (i, p) in proc.params.iter().enumerate() {
            if !p.optional && !bound.iter().any(|(j, _)| *j == i) {
                return Err(self.plain_fault(
                    ErrorKind::Usage,
                    format!("{} {} needs {}: pass --arg {}=VALUE", proc.kind, proc.name, p.name, p.name),
                ));
            }
        }
        self.invoke(entry, bound, None)?;
        if !self.ended.get() {
            self.release_module_variables()?;
        }
        Ok(())
    }

    /// The end of a run is the end of its program: the objects the module's variables and
    /// the procedures' Static variables still hold are let go, in the order declared, each
    /// object's Class_Terminate running as its last reference goes ("Initialize, Terminate
    /// events"). Not after `End`, which removes them without it (the same page).
    fn release_module_variables(&self) -> Run<()> {
        let globals = self.globals.borrow();
        let names: Vec<(usize, Rc<str>)> =
            globals.iter().enumerate().flat_map(|(part, g)| g.iter().map(move |s| (part, s.name.clone()))).collect();
        drop(globals);
        for (part, name) in names {
            let var = self.globals.borrow_mut()[part].get_mut(&name).map(|s| s.replace(Var::Value(Value::Blank)));
            if let Some(var) = var {
                self.release(&var)?;
            }
        }
        let mut statics: Vec<_> = self.kept.borrow_mut().drain().collect();
        statics.sort_by(|a, b| a.0.cmp(&b.0));
        for slot in statics.iter().filter_map(|(_, slot)| slot.as_ref()) {
            self.release(slot.var())?;
        }
        Ok(())
    }

    // ---- faults ----------------------------------------------------------------------

    fn plain_fault(&self, kind: ErrorKind, message: String) -> Fault {
        Fault { kind, code: 0, message, span: None, trace: Vec::new(), source: None }
    }

    /// A runtime failure here, with the procedures now running.
    pub fn fault(&self, message: impl Into<String>) -> Fault {
        let frames = self.frames.borrow();
        let trace = frames
            .iter()
            .rev()
            // A new object's declarations run in a frame of no procedure.
            .filter_map(|f| {
                let p = self.module.procs.get(f.proc)?;
                Some(match f.call_site {
                    Some(s) => format!("in {} {} (called at {s})", p.kind, p.name),
                    None => format!("in {} {}", p.kind, p.name),
                })
            })
            .collect();
        Fault { kind: ErrorKind::Runtime, code: 0, message: message.into(), span: None, trace, source: None }
    }

    pub fn fault_at(&self, span: Span, message: impl Into<String>) -> Fault {
        Fault { span: Some(span), ..self.fault(message) }
    }

    /// The workbook's refusal `e` as a fault at `span` (the statement's when `None`), its VBA
    /// number carried from the refusal's kind, not read from its words ([`workbook_error_number`]).
    pub(super) fn workbook_fault(&self, span: Option<Span>, e: &WorkbookError) -> Fault {
        let fault = self.fault(one_line(e));
        Fault { span: span.or(fault.span), code: workbook_error_number(e), ..fault }
    }

    /// The place of an expression (its first character).
    pub fn expr_span(&self, e: &Expr) -> Span {
        self.lines.span(self.source, e.span.start as usize)
    }

    /// The source text between two byte offsets (empty where they do not fall in it).
    pub(super) fn source_between(&self, start: u32, end: u32) -> &str {
        self.source.get(start as usize..end as usize).unwrap_or("")
    }

    /// The source of `start..end` to quote in a message, or `instead` when there is none or
    /// it is too long to read in one line (over 60 characters).
    pub(super) fn quoted_source<'a>(&'a self, start: u32, end: u32, instead: &'a str) -> &'a str {
        let text = self.source_between(start, end).trim();
        if text.is_empty() || text.chars().count() > 60 {
            instead
        } else {
            text
        }
    }

    /// The statements and loop turns run so far.
    pub(super) fn steps_run(&self) -> u64 {
        self.steps.get()
    }

    /// Counts one statement or loop turn against the limit, with the text and array work the
    /// statements before it did.
    fn tick(&self, span: Span) -> Run<()> {
        let before = self.steps.get();
        let n = before.saturating_add(1).saturating_add(self.work_as_statements());
        self.steps.set(n);
        if n > self.options.max_statements {
            let limit = self.options.max_statements;
            let hint = self.options.raise_hint("raise the limit with --max-statements");
            let why = if self.work_steps.get() > n / 2 {
                format!(
                    "text and array work counts too, each {WORK_PER_STATEMENT} items or {} characters \
                     made or read as a statement",
                    WORK_PER_STATEMENT * 16
                )
            } else {
                "an endless loop?".to_string()
            };
            let mut f = self.fault_at(span, format!("the statement limit ({limit}) is reached: {why} ({hint})"));
            f.kind = ErrorKind::Limit;
            return Err(f);
        }
        // The clock costs ~25 ns a reading: read it every 16 steps, a statement stopping at
        // most 15 statements late.
        let Some(deadline) = self.options.deadline else { return Ok(()) };
        if n / 16 != before / 16 && std::time::Instant::now() > deadline.at {
            let limit = deadline.seconds;
            let mut f = self.fault_at(
                span,
                format!("the command ran past its --timeout of {limit} s after {n} statements: statements too costly, or too many?"),
            );
            f.kind = ErrorKind::Limit;
            return Err(f);
        }
        Ok(())
    }

    /// The statements the text and array work reported since the last one is worth
    /// ([`WORK_PER_STATEMENT`]), the rest kept for the next.
    fn work_as_statements(&self) -> u64 {
        let work = self.work.get();
        if work < WORK_PER_STATEMENT {
            return 0;
        }
        self.work.set(work % WORK_PER_STATEMENT);
        let statements = work / WORK_PER_STATEMENT;
        self.work_steps.set(self.work_steps.get().saturating_add(statements));
        statements
    }

    /// Takes text and array work the evaluator reported ([`crate::eval::Host::work`]).
    pub(super) fn add_work(&self, units: u64) {
        self.work.set(self.work.get().saturating_add(units));
    }

    /// Counts the copy of `items` array items against the statement limit, a statement per
    /// [`ITEMS_PER_STATEMENT`]: a copy that grows with the array (`ReDim Preserve` of a
    /// two-dimensional array, which cannot grow in place; an array given back converted to its
    /// caller's type) costs its size each time, and a loop of them ran for minutes within the
    /// memory budget while counting one statement a turn.
    pub(super) fn count_copy(&self, items: usize, span: Span) -> Run<()> {
        let n = self.steps.get().saturating_add(items as u64 / ITEMS_PER_STATEMENT);
        self.steps.set(n);
        if n <= self.options.max_statements {
            return Ok(());
        }
        let limit = self.options.max_statements;
        let hint = self.options.raise_hint("raise the limit with --max-statements");
        let message = format!(
            "the statement limit ({limit}) is reached: arrays copied {items} items here, and each \
             {ITEMS_PER_STATEMENT} items copied count as a statement ({hint})"
        );
        let mut f = self.fault_at(span, message);
        f.kind = ErrorKind::Limit;
        Err(f)
    }

    // ---- evaluation ------------------------------------------------------------------

    pub fn ctx(&self) -> Ctx<'_> {
        Ctx::new(self, self.unqualified_sheet(), Pos::new(0, 0)).with_host(self)
    }

    /// The sheet `Range`, `Cells` and `[B3]` mean without a sheet before them: the document
    /// module's own sheet, else the active one.
    pub fn unqualified_sheet(&self) -> SheetId {
        self.home.unwrap_or(self.active.get())
    }

    /// A sheet's selection and active cell (A1 until something selects).
    pub fn cursor(&self, sheet: SheetId) -> (Rect, Pos) {
        let origin = Pos::new(0, 0);
        self.cursors.borrow().get(&sheet).copied().unwrap_or((Rect::cell(origin), origin))
    }

    /// Takes the failure a host node parked during an evaluation.
    pub fn take_pending(&self) -> Run<()> {
        match self.pending.borrow_mut().take() {
            Some(f) => Err(f),
            None => Ok(()),
        }
    }

    /// Evaluates an expression to a value (a 1×1 array is its item).
    pub fn eval(&self, e: &Expr) -> Run<Value> {
        let mut ctx = self.ctx();
        let v = crate::eval::evaluator::no_lambda(ctx.eval(e)).unwrap_single();
        self.take_pending()?;
        *self.notes.borrow_mut() = ctx.notes.into_iter().map(|n| n.message).collect();
        Ok(v)
    }

    /// What an error value means, with the notes functions left about it.
    fn describe_error(&self, what: &str, v: &Value, err: XlError) -> String {
        let notes = self.notes.borrow();
        let why = match v {
            Value::Text(t) => format!(" (\"{t}\" is not a number)"),
            _ if !notes.is_empty() => format!(" ({})", notes.join("; ")),
            _ => String::new(),
        };
        format!("{what} is {err}{why}")
    }

    /// A number, or a failure that names `what` and points at the expression.
    pub fn number(&self, e: &Expr, what: &str) -> Run<f64> {
        let v = self.eval(e)?;
        self.number_of(&v, what).map_err(|m| self.fault_at(self.expr_span(e), m))
    }

    pub fn number_of(&self, v: &Value, what: &str) -> Result<f64, String> {
        if let Value::Array(_) = v {
            return Err(format!("{what} is an array, not a number"));
        }
        if let Value::Null = v {
            return Err(format!("{what} is Null: {}", super::value::INVALID_USE_OF_NULL));
        }
        // A VBA Date counts days as the 1900 system does, whatever the workbook's.
        to_number(v, DateSystem::From1900).map_err(|err| self.describe_error(what, v, err))
    }

    pub fn truth(&self, e: &Expr, what: &str) -> Run<bool> {
        let v = self.eval(e)?;
        // "any expression containing a Null is itself Null and, therefore, False" (IsNull function).
        if let Value::Null = v {
            return Ok(false);
        }
        to_bool(&v).map_err(|err| self.fault_at(self.expr_span(e), self.describe_error(what, &v, err)))
    }

    /// Whole-number indexes, rounded as VBA rounds them.
    pub fn index(&self, e: &Expr, what: &str) -> Run<i64> {
        // `a(, 2)`: only a Range's row may be left out (`Range("B2:D6")(, 3)`); an array's
        // index is VBA's "Argument not optional" (error 449), never the 0 a blank gives.
        if e.kind == ExprKind::Missing {
            let mut fault = self.vba_fault(449, &format!("{what} is left out"));
            fault.span = Some(self.expr_span(e));
            return Err(fault);
        }
        let n = self.number(e, what)?.round_ties_even();
        // VBA's indexes are Longs: 1E+300 is an overflow, not the largest integer.
        if !(i32::MIN as f64..=i32::MAX as f64).contains(&n) {
            let n = crate::eval::format::number_format::general(n);
            let message = format!("{what} {n} is outside a Long (-2147483648 to 2147483647): overflow");
            return Err(self.fault_at(self.expr_span(e), message));
        }
        Ok(n as i64)
    }

    // ---- variables -------------------------------------------------------------------

    /// The object `.X` means: the innermost With's. A With a GoTo or an error handler went
    /// into has none: error 91 ("Object variable or With block variable not set (Error 91)":
    /// "The target of a GoTo statement is inside a With block"), not an outer With's object.
    pub fn with_object(&self, span: Span) -> Run<Obj> {
        let innermost = self.frames.borrow().last().and_then(|f| f.with.last().map(|(_, o)| o.clone()));
        match innermost {
            Some(Some(object)) => Ok(object),
            Some(None) => {
                let why = "a GoTo or an error handler went into the With block without running its With statement";
                let mut fault = self.vba_fault(91, why);
                fault.span = Some(span);
                Err(fault)
            }
            None => Err(self.fault_at(span, "a name starting with . needs a With block around it")),
        }
    }

    /// A copy of what the variable `name` holds (current procedure first, then module); a
    /// variable declared `As New` holding Nothing gets its new object first.
    pub fn lookup(&self, name: &str) -> Option<Var> {
        match self.lookup_slot(name, |s| (s.var().clone(), s.new))? {
            (var, Some((class, span))) if is_nothing(&var) => Some(self.instantiate(name, class, span)),
            (var, _) => Some(var),
        }
    }

    /// `f` of what the variable `name` holds, without copying it (`lookup` copies an array's
    /// description, seven references, at every read of an item): `f` runs while the
    /// variables are borrowed, so it must only look. A variable declared `As New` holding
    /// Nothing gets its object first, as [`Interp::lookup`] does.
    pub(super) fn peek<T>(&self, name: &str, f: impl FnOnce(&Var) -> T) -> Option<T> {
        let mut f = Some(f);
        let seen = self.lookup_slot(name, |s| match s.new {
            Some(_) if is_nothing(s.var()) => None,
            _ => f.take().map(|f| f(s.var())),
        })?;
        match (seen, f) {
            (Some(t), _) => Some(t),
            (None, Some(f)) => self.lookup(name).map(|var| f(&var)),
            (None, None) => None,
        }
    }

    /// The slot `name` means where the running procedure is, by [MS-VBAL] 5.6.10 (simple
    /// name expressions): its local, else its object's variable (a class module's), else
    /// its own module's module-level one, else the one another module declares Public.
    /// `Module2.Rate` (the parser's qualified name) is Module2's.
    fn lookup_slot<T>(&self, name: &str, f: impl FnOnce(&Slot) -> T) -> Option<T> {
        let frames = self.frames.borrow();
        let local = frames.last().and_then(|fr| fr.vars.get(name));
        if let Some(s) = local {
            return Some(f(s));
        }
        if let Some(me) = frames.last().and_then(|fr| fr.me.as_ref()) {
            if let Some(s) = me.0.fields.borrow().get(name) {
                return Some(f(s));
            }
        }
        let own = self.running_part(&frames);
        drop(frames);
        let globals = self.globals.borrow();
        if let Some(s) = globals.get(own).and_then(|g| g.get(name)) {
            return Some(f(s));
        }
        let (part, bare) = self.other_module_of(name)?;
        globals.get(part)?.get(bare).map(f)
    }

    /// The module whose procedure is running (or whose declarations are): the first place
    /// after the procedure's own where a name is looked for. A class's field declarations
    /// run in a frame of no procedure: they see only Public names.
    fn running_part(&self, frames: &[Frame]) -> usize {
        match frames.last() {
            Some(frame) => self.module.procs.get(frame.proc).map_or(usize::MAX, |p| p.part),
            None => self.declaring.get(),
        }
    }

    /// The `Option Base`/`Option Compare` of the module whose code runs. While the frames are
    /// being changed (never while an expression is computed) the first module's.
    pub(super) fn running_options(&self) -> super::ast::ModuleOptions {
        match self.frames.try_borrow() {
            Ok(frames) => self.module.options_of(self.running_part(&frames)),
            Err(_) => self.module.options_of(0),
        }
    }

    /// A module-level name the running module does not declare: `Module2.Rate`, qualified
    /// by the parser, in the module named; else in the module declaring it Public.
    fn other_module_of<'n>(&self, name: &'n str) -> Option<(usize, &'n str)> {
        if let Some((module, bare)) = name.split_once('.') {
            let part = self.module.parts.iter().position(|p| p.name.eq_ignore_ascii_case(module))?;
            return Some((part, bare));
        }
        self.module.public_part(name).map(|part| (part, name))
    }

    /// Auto-instantiation ([MS-VBAL] 5.2.3.1.4, "Variable Declarations": a variable declared
    /// `As New` that holds Nothing when it is used gets a new object of its class first, so
    /// `x Is Nothing` is never True and `Set x = Nothing` only lets its object go). A failure
    /// making it (its Class_Initialize) is parked for the statement to raise.
    fn instantiate(&self, name: &str, class: Made, span: Span) -> Var {
        match self.new_object(class, span) {
            Ok(object) => {
                self.with_slot(name, |s| s.replace(object.clone()));
                object
            }
            Err(fault) => {
                self.park(fault);
                Var::Obj(Obj::Value(Value::Blank))
            }
        }
    }

    /// Changes a variable in place; `None` when there is no such variable.
    pub(super) fn with_slot<T>(&self, name: &str, f: impl FnOnce(&mut Slot) -> T) -> Option<T> {
        let mut frames = self.frames.borrow_mut();
        if let Some(s) = frames.last_mut().and_then(|fr| fr.vars.get_mut(name)) {
            return Some(f(s));
        }
        let me = frames.last().and_then(|fr| fr.me.clone());
        let own = self.running_part(&frames);
        drop(frames);
        if let Some(me) = me {
            if let Some(s) = me.0.fields.borrow_mut().get_mut(name) {
                return Some(f(s));
            }
        }
        let mut globals = self.globals.borrow_mut();
        if self.noting_changes.get() {
            self.note_change(&globals, own, name);
        }
        if let Some(s) = globals.get_mut(own).and_then(|g| g.get_mut(name)) {
            return Some(f(s));
        }
        let (part, bare) = self.other_module_of(name)?;
        globals.get_mut(part)?.get_mut(bare).map(f)
    }

    /// Keeps module variable `name`, as [`Interp::with_slot`] finds it from module `own`, as
    /// it is before the call first reaches it to change it, to put back after the call: a
    /// copy of one variable, its array's items shared until one is changed. Not inlined: the
    /// frames of the procedures that change variables stay as small as without it.
    #[inline(never)]
    fn note_change(&self, globals: &[Slots], own: usize, name: &str) {
        let found = match globals.get(own).and_then(|g| g.position_of(name)) {
            Some(at) => Some((own, at)),
            None => {
                self.other_module_of(name).and_then(|(part, bare)| Some((part, globals.get(part)?.position_of(bare)?)))
            }
        };
        if let Some((part, at)) = found {
            self.changed.borrow_mut().entry((part, at)).or_insert_with(|| globals[part].at(at).clone());
        }
    }

    /// In a call from a cell, keeps module variable `name` before a write to one of its items
    /// ([`Interp::note_change`]), so that the write sees its items shared with the kept copy
    /// and counts their copy as any copy on write is counted: each call's first write to a
    /// module-level array copies it whole, and 2,000 cells writing into an array of a million
    /// items copied 2 billion items counting one statement a cell.
    #[inline(never)]
    pub(super) fn note_item_write(&self, name: &str) {
        if !self.noting_changes.get() {
            return;
        }
        let frames = self.frames.borrow();
        if frames.last().is_some_and(|fr| fr.vars.get(name).is_some()) {
            return;
        }
        if frames.last().and_then(|fr| fr.me.as_ref()).is_some_and(|me| me.0.fields.borrow().get(name).is_some()) {
            return;
        }
        let own = self.running_part(&frames);
        drop(frames);
        self.note_change(&self.globals.borrow(), own, name);
    }

    /// Declares a variable in the running procedure (or the module, before any runs).
    fn declare(&self, slot: Slot) {
        let mut frames = self.frames.borrow_mut();
        match frames.last_mut() {
            Some(f) => f.vars.push(slot),
            None => self.globals.borrow_mut()[self.declaring.get()].push(slot),
        }
    }

    fn has_local(&self, name: &str) -> bool {
        let frames = self.frames.borrow();
        match frames.last() {
            Some(f) => f.vars.get(name).is_some(),
            None => self.globals.borrow()[self.declaring.get()].get(name).is_some(),
        }
    }

    /// Assigns a variable, converting to its declared type; an undeclared one is created.
    pub fn set_var(&self, name: &Rc<str>, var: Var, span: Span) -> Run<()> {
        self.set_var_holding(name, var, Declared::Variant, span)
    }

    /// [`Interp::set_var`], a Variant given a number noting its type `held` (an Integer …).
    fn set_var_holding(&self, name: &Rc<str>, var: Var, held: Declared, span: Span) -> Run<()> {
        self.charge(super::budget::brought(&var), span)?;
        let result = self.with_slot(name, |slot| {
            if slot.constant {
                return Err(format!("{} is a constant", slot.name));
            }
            let new = match (&var, slot.var()) {
                // An array variable takes a whole array, its items converted to its type.
                (Var::Array(a), Var::Array(_)) => {
                    let typed = super::arrays::typed_items(a.clone(), slot.ty.as_ref(), &slot.name)?;
                    // Converted to the variable's type, the items are a copy.
                    if !Rc::ptr_eq(&typed.data, &a.data) {
                        self.owe(super::budget::copy_bytes(&typed.data));
                    }
                    Var::Array(typed)
                }
                _ => convert(var.clone(), slot.ty.as_ref(), &slot.name)?,
            };
            let old = slot.replace(new);
            slot.set_holds(held);
            Ok(old)
        });
        match result {
            // The object the variable held may have lost its last reference.
            Some(r) => self.release(&r.map_err(|m| self.fault_at(span, m))?),
            None => {
                let mut slot = Slot::new(name.clone(), var, None);
                slot.set_holds(held);
                self.declare(slot);
                Ok(())
            }
        }
    }

    /// What an expression is as something a variable can hold: a value, an array, or an
    /// object (a range stays a range for `Set` and `For Each`).
    pub fn var_of(&self, e: &Expr, as_object: bool) -> Run<Var> {
        match &e.kind {
            ExprKind::Paren(inner) => self.var_of(inner, as_object),
            ExprKind::Name(n) => match self.lookup(n) {
                Some(Var::Obj(Obj::Range(sheet, rect))) if !as_object => {
                    Ok(range_var(self.ctx().rect_value(sheet, rect)))
                }
                // `x = obj` without Set: the value of obj's default member.
                Some(Var::Obj(Obj::Instance(object))) if !as_object => self.default_value(&object),
                Some(var) => Ok(var),
                None => Ok(Var::Value(Value::Blank)),
            },
            ExprKind::Host(id) => match self.array_with_objects(e) {
                Some(array) => array,
                None => self.noting_date(*id, || self.host_var(e, *id, as_object)),
            },
            _ => match self.array_with_objects(e) {
                Some(array) => array,
                None => self.operand_var(e, as_object),
            },
        }
    }

    /// Runs `give`, which evaluates the node `id`, noting the type of the number it gave
    /// ([`Interp::node_types`]).
    pub(super) fn noting_date<T>(&self, id: u32, give: impl FnOnce() -> T) -> T {
        self.gave.set(Declared::Variant);
        self.forget_given_long_long();
        let given = give();
        self.note_node_long_long(id);
        // The flag is the last call's or item's, which is this node's own only for these.
        let own = match &self.module.nodes[id as usize] {
            Node::Call { .. } | Node::Element { .. } | Node::Index { .. } => true,
            // `Cells(r, c).Value` of a cell formatted as a date or as currency (`formats.rs`).
            Node::Path(path) => path.links.last().is_some_and(|l| {
                ["item", "filedatetime", "value", "keys", "items"].iter().any(|n| l.name.eq_ignore_ascii_case(n))
            }),
            _ => false,
        };
        let gave = self.gave.get();
        if own && gave != Declared::Variant {
            self.node_types.borrow_mut().insert(id, gave);
        } else if !self.node_types.borrow().is_empty() {
            self.node_types.borrow_mut().remove(&id);
        }
        given
    }

    /// Notes whether the item or element being read holds a Date (for [`Interp::node_types`]).
    pub(super) fn gave_date(&self, date: bool) {
        self.gave.set(if date { Declared::Date } else { Declared::Variant });
    }

    /// Whether `e` is a member path (`Sheets.Add …`, `ws.Copy`), which may end at an object.
    fn is_member_path(&self, e: &Expr) -> bool {
        matches!(&e.kind, ExprKind::Host(id) if matches!(self.module.nodes[*id as usize], Node::Path(_)))
    }

    /// [`Interp::var_of`] of the node `id`, the expression `e`.
    fn host_var(&self, e: &Expr, id: u32, as_object: bool) -> Run<Var> {
        match &e.kind {
            ExprKind::Host(_) if matches!(self.module.nodes[id as usize], Node::New { .. }) => {
                let Node::New { class, span } = &self.module.nodes[id as usize] else { unreachable!() };
                self.new_object(*class, *span)
            }
            // `Nothing` is an object reference to no object wherever it goes: a Dictionary's
            // item, an argument, a Variant (TypeName "Nothing", IsObject True).
            ExprKind::Host(_) if matches!(self.module.nodes[id as usize], Node::Nothing) => {
                Ok(Var::Obj(Obj::Value(Value::Blank)))
            }
            // `Set x = a(1)`, `a(1) Is Nothing`, `With a(1)`: an array's item that is an object.
            ExprKind::Host(_) if self.array_object(id).is_some() => {
                let (var, index, span) = self.array_object(id).expect("an array's item");
                self.array_item(&var, index, span)
            }
            ExprKind::Host(_) if matches!(self.module.nodes[id as usize], Node::Index { .. }) => {
                let Node::Index { base, index, span } = &self.module.nodes[id as usize] else { unreachable!() };
                self.indexed_var(base, index, *span)
            }
            // `Set ws = sl(j)` of `Set sl = ActiveWorkbook.Worksheets`: the collection's Item.
            ExprKind::Host(_) if as_object && self.is_collection_element(id) => {
                self.collection_element(id).expect("an item of a collection")
            }
            // `Set x = bag(1)`, `TypeName(bag(1))`: what an object's default member gives.
            ExprKind::Host(_) if self.instance_element(id).is_some() => {
                let (object, index, span) = self.instance_element(id).expect("an object's item");
                let args: Vec<Arg> = index.iter().map(|e| Arg { name: None, value: e.clone() }).collect();
                let got = super::classes::obj_var(self.default_member(&mut self.ctx(), &object, &args, span)?);
                match got {
                    Var::Obj(Obj::Instance(inner)) if !as_object => self.default_value(&inner),
                    other => Ok(other),
                }
            }
            // `k = d.Keys`: the keys with their types.
            ExprKind::Host(_) if !as_object && self.is_keys_member(e) => {
                let Node::Path(path) = &self.module.nodes[id as usize] else { unreachable!() };
                self.keys_var(path)
            }
            ExprKind::Host(_) if self.store_element(id).is_some() => {
                let (h, index, span) = self.store_element(id).expect("a Collection's item");
                let key = self.store_key(&mut self.ctx(), index, span)?;
                self.store_item(&h, &key, span)
            }
            // `Set m = matches(0)`: a MatchCollection's default member (`regexp.rs`).
            ExprKind::Host(_) if self.regex_element(id).is_some() => {
                let (r, index, span) = self.regex_element(id).expect("a MatchCollection's item");
                self.regex_element_item(&r, index, span)
            }
            // `p = MakePoint(1, 2)`, `Set o = MakeObject()`: what the Function's name holds.
            ExprKind::Host(_) if self.returns_record(id) || (as_object && self.is_call(id)) => {
                let Node::Call { proc, args, span } = &self.module.nodes[id as usize] else { unreachable!() };
                self.call_record(*proc, args, *span)
            }
            // `c = Coeffs(x)`: the array a Function returns keeps its bounds and dimensions, as
            // its name held it ([MS-VBAL] 5.3.1.5: the function's result is its variable's value).
            ExprKind::Host(_) if !as_object && self.is_call(id) => {
                let Node::Call { proc, args, span } = &self.module.nodes[id as usize] else { unreachable!() };
                let (value, frame) = self.call_frame(&mut self.ctx(), *proc, args, *span, Call::default())?;
                let name = &self.module.procs[*proc].name;
                if let Some(array @ Var::Array(_)) = frame.vars.get(name).map(|s| s.var()) {
                    return Ok(array.clone());
                }
                self.no_record_result(*proc, &frame)?;
                Ok(array_var(value, self.option_base()))
            }
            ExprKind::Host(_) if as_object => {
                if let Node::Path(path) = &self.module.nodes[id as usize] {
                    let mut ctx = self.ctx();
                    let obj = self.path(&mut ctx, path);
                    self.take_pending()?;
                    return Ok(Var::Obj(obj?));
                }
                // `Set o = A(1)(2).Owner`: the object a member of an item gives.
                if let Node::Members { base, path } = &self.module.nodes[id as usize] {
                    let obj = self.members_of(&mut self.ctx(), base, path);
                    self.take_pending()?;
                    return Ok(Var::Obj(obj?));
                }
                self.operand_var(e, as_object)
            }
            _ => self.operand_var(e, as_object),
        }
    }

    /// `….Value` or `….Value2` (of a Range: no other object has an array Value).
    fn is_value_member(&self, e: &Expr) -> bool {
        let ExprKind::Host(id) = &e.kind else { return false };
        let Node::Path(path) = &self.module.nodes[*id as usize] else { return false };
        (path.links.len() > 1 || path.with)
            && path.links.last().is_some_and(|l| {
                l.args.is_none() && (l.name.eq_ignore_ascii_case("value") || l.name.eq_ignore_ascii_case("value2"))
            })
    }

    /// The Collection or Dictionary the variable `name` holds, if it holds one.
    pub(super) fn store_named(&self, name: &str) -> Option<Handle> {
        let store = self.peek(name, |held| match held {
            Var::Obj(Obj::Store(h)) => Some(h.clone()),
            _ => None,
        });
        store.flatten()
    }

    /// The node is `bag(i)` of a variable holding an object of a class.
    fn instance_element(&self, id: u32) -> Option<(Instance, &[Expr], Span)> {
        let Node::Element { var, index, span } = &self.module.nodes[id as usize] else { return None };
        match self.peek(var, |held| matches!(held, Var::Obj(Obj::Instance(_))))? {
            true => match self.lookup(var) {
                Some(Var::Obj(Obj::Instance(object))) => Some((object, index.as_slice(), *span)),
                _ => None,
            },
            false => None,
        }
    }

    /// The node is `c(i)` of a variable holding a Collection or a Dictionary.
    fn store_element(&self, id: u32) -> Option<(Handle, &[Expr], Span)> {
        let Node::Element { var, index, span } = &self.module.nodes[id as usize] else { return None };
        self.store_named(var).map(|h| (h, index.as_slice(), *span))
    }

    /// `….Keys` or `….Items` (a Dictionary's: no other object has them).
    pub(super) fn is_keys_member(&self, e: &Expr) -> bool {
        let ExprKind::Host(id) = &e.kind else { return false };
        let Node::Path(path) = &self.module.nodes[*id as usize] else { return false };
        (path.links.len() > 1 || path.with)
            && path.links.last().is_some_and(|l| {
                l.args.as_ref().is_none_or(|a| a.is_empty())
                    && (l.name.eq_ignore_ascii_case("keys") || l.name.eq_ignore_ascii_case("items"))
            })
    }

    fn is_call(&self, id: u32) -> bool {
        matches!(self.module.nodes[id as usize], Node::Call { .. })
    }

    /// The node is a call of a Function declared `As` a Type.
    fn returns_record(&self, id: u32) -> bool {
        match &self.module.nodes[id as usize] {
            Node::Call { proc, .. } => matches!(self.module.procs[*proc].ty, Some(Ty::Record(_))),
            _ => false,
        }
    }

    fn operand_var(&self, e: &Expr, as_object: bool) -> Run<Var> {
        let mut ctx = self.ctx();
        let operand = ctx.operand(e);
        self.take_pending()?;
        Ok(match operand {
            Operand::Ref(sheet, rect) if as_object => Var::Obj(Obj::Range(sheet, rect)),
            Operand::Ref(sheet, rect) => range_var(ctx.rect_value(sheet, rect)),
            // `Range("A1:C1").Value`: a range's values are two-dimensional, one row too.
            Operand::Value(v) if self.is_value_member(e) => range_var(v),
            // `d.Keys`, `d.Items`: zero-based whatever the Option Base ("Keys method").
            Operand::Value(Value::Array(a)) if self.is_keys_member(e) => Var::Array(super::value::VArray::row(a, 0)),
            Operand::Value(v) => match self.array_of_call(e, &v).or_else(|| self.method_result(&v)) {
                Some(var) => var,
                None => array_var(v, self.option_base()),
            },
            // A Range of several areas (`Set u = Union(a, b)`), an object; its value is its
            // first area's, as Excel reads a multiple selection's Value.
            Operand::Areas(areas) => match super::areas::areas_object(&areas) {
                Some(Obj::Areas(sheet, rects)) if !as_object => range_var(ctx.rect_value(sheet, rects[0])),
                Some(obj) => Var::Obj(obj),
                // Areas of several sheets are no one range: the #VALUE! a cell shows.
                None => array_var(ctx.deref(Operand::Areas(areas)), self.option_base()),
            },
        })
    }

    // ---- procedures ------------------------------------------------------------------

    /// Calls a procedure with arguments from expressions; ByRef arguments that are plain
    /// variables are copied back when it returns.
    pub fn call(&self, ctx: &mut Ctx, proc: usize, args: &[Arg], span: Span) -> Run<Value> {
        let (value, frame) = self.call_frame(ctx, proc, args, span, Call::default())?;
        self.no_record_result(proc, &frame)?;
        Ok(value)
    }

    /// A call of a Function that returns a `Type` (`p = MakePoint(1, 2)`): the record its
    /// name holds when it returns.
    pub fn call_record(&self, proc: usize, args: &[Arg], span: Span) -> Run<Var> {
        let (_, frame) = self.call_frame(&mut self.ctx(), proc, args, span, Call::default())?;
        let name = &self.module.procs[proc].name;
        Ok(frame.vars.get(name).map_or(Var::Value(Value::Blank), |s| s.var().clone()))
    }

    /// A Type value can be assigned to a variable of that Type, not used as a value.
    fn no_record_result(&self, proc: usize, frame: &Frame) -> Run<()> {
        let p = &self.module.procs[proc];
        if p.kind == ProcKind::Function && matches!(frame.vars.get(&p.name).map(|s| s.var()), Some(Var::Record(..))) {
            let why = "returns a Type value: assign it to a variable of that Type (p = MakePoint(…))";
            return Err(self.fault(format!("Function {} {why}", p.name)));
        }
        Ok(())
    }

    pub(super) fn call_frame(
        &self,
        ctx: &mut Ctx,
        proc: usize,
        args: &[Arg],
        span: Span,
        call: Call,
    ) -> Run<(Value, Frame)> {
        let p = &self.module.procs[proc];
        let mut bound = Vec::new();
        let mut back = Vec::new();
        let mut types = Vec::new();
        let mut items_back = Vec::new();
        let mut lent = Vec::new();
        let (args, param_array) = super::param_array::split_args(p, args);
        let mut long_longs = super::longlong::ExactArgs::default();
        for (i, a) in args.iter().enumerate() {
            let index = match &a.name {
                Some(n) => p.params.iter().position(|q| q.name.eq_ignore_ascii_case(n)).expect("checked by the parser"),
                None => i,
            };
            if a.value.kind == ExprKind::Missing {
                continue;
            }
            if let (true, ExprKind::Name(caller_var)) = (p.params[index].by_ref, &a.value.kind) {
                if self.lendable(caller_var, args) {
                    // Taken once every argument is evaluated: `Sort a, LBound(a)` reads it.
                    lent.push((index, caller_var.clone()));
                    continue;
                }
                back.push((index, caller_var.clone()));
            } else if let Some(item) = self.item_reference(&a.value).filter(|_| p.params[index].by_ref) {
                // Read at the indexes just evaluated: an index that calls a function runs once.
                let (array, at) = item?;
                let var = self.item_argument(&a.value, &array, &at)?;
                types.extend(self.number_type(&a.value, &var).map(|ty| (index, ty)));
                items_back.push((index, (array, at)));
                bound.push((index, var));
                continue;
            }
            // `F(G(x))`: G's array passes with the bounds G gave it ([MS-VBAL] 2.2).
            if let Some(var) = self.call_argument(&a.value) {
                let var = var?;
                types.extend(self.number_type(&a.value, &var).map(|ty| (index, ty)));
                bound.push((index, var));
                continue;
            }
            if let ExprKind::Name(n) = &a.value.kind {
                if let Some(record @ Var::Record(..)) = self.lookup(n) {
                    bound.push((index, record));
                    continue;
                }
            }
            if let Some(var) = self.object_argument(ctx, &a.value, p.params[index].ty.as_ref(), (index, &mut types))? {
                bound.push((index, var));
                continue;
            }
            let var = match ctx.operand(&a.value) {
                Operand::Ref(sheet, rect) => Var::Obj(Obj::Range(sheet, rect)),
                Operand::Value(v) => match &a.value.kind {
                    // A number keeps its type in a Variant parameter ([MS-VBAL] 5.3.1.11).
                    _ if matches!(v, Value::Number(_)) => {
                        self.note_long_long_arg(&mut long_longs, index, &a.value, &v);
                        match self.value_type(&a.value, &v) {
                            Declared::Double => {}
                            ty => types.push((index, ty)),
                        }
                        Var::Value(v)
                    }
                    ExprKind::Name(n) => self.lookup(n).unwrap_or(Var::Value(v)),
                    _ => self.array_of_call(&a.value, &v).unwrap_or_else(|| array_var(v, self.option_base())),
                },
                Operand::Areas(areas) => match super::areas::areas_object(&areas) {
                    Some(obj) => Var::Obj(obj),
                    None => array_var(ctx.deref(Operand::Areas(areas)), self.option_base()),
                },
            };
            self.take_pending()?;
            bound.push((index, var));
        }
        if let Some(rest) = param_array {
            bound.push((p.params.len() - 1, self.param_array_arg(ctx, rest)?));
        }
        for (index, caller_var) in &lent {
            bound.push((*index, self.lend_array(caller_var)));
        }
        if let Some(value) = call.value {
            bound.push((p.params.len() - 1, value));
        }
        *self.arg_types.borrow_mut() = types;
        self.pass_long_long_args(long_longs);
        let called = self.invoke_frame(proc, bound, Some(span), Call { me: call.me, value: None, lent });
        self.arg_types.borrow_mut().clear();
        let (result, frame) = called?;
        for (index, caller_var) in back {
            // A constant passed ByRef is passed as a copy, as in VBA.
            if self.with_slot(&caller_var, |s| s.constant) == Some(true) {
                continue;
            }
            let name = &p.params[index].name;
            if let Some(slot) = frame.vars.get(name) {
                self.set_var(&caller_var, slot.var().clone(), span)?;
                // A number given back through a ByRef Variant keeps its type (a Date, an Integer …).
                self.with_slot(&caller_var, |s| s.set_holds(slot.holds));
                if let Some(k) = slot.exact() {
                    self.with_slot(&caller_var, |s| s.set_exact(k));
                }
                if let Some(d) = slot.decimal() {
                    self.with_slot(&caller_var, |s| s.set_decimal(d));
                }
            }
        }
        for (index, (array, at)) in items_back {
            if let Some(slot) = frame.vars.get(&p.params[index].name) {
                self.give_back_item(&array, &at, slot.var().clone(), slot.holds == Declared::Date, span)?;
            }
        }
        // A Variant Function assigned a Date returns a Date, assigned an Integer an Integer.
        self.gave.set(frame.vars.get(&p.name).map_or(Declared::Variant, |s| s.holds));
        self.returning_long_long(frame.vars.get(&p.name).and_then(|s| s.exact()));
        self.returning_decimal(frame.vars.get(&p.name).and_then(|s| s.decimal()));
        Ok((result, frame))
    }

    /// An argument that [`Interp::object_arg`] reads (an object, a Range, a member path's
    /// value) as the parameter of type `ty` takes it; a number it gave notes its type for the
    /// parameter at `index` (`F(Cells(r, c).Value)` of a date-formatted cell passes a Date).
    /// Its own frame: it runs in every call's argument loop ([`Interp::call_frame`]).
    #[inline(never)]
    fn object_argument(
        &self,
        ctx: &mut Ctx,
        e: &Expr,
        ty: Option<&Ty>,
        (index, types): (usize, &mut Vec<(usize, Declared)>),
    ) -> Run<Option<Var>> {
        let Some(object) = self.object_arg(ctx, e)? else { return Ok(None) };
        let var = self.object_to_param(object, ty)?;
        types.extend(self.number_type(e, &var).map(|ty| (index, ty)));
        Ok(Some(var))
    }

    /// A local array of the calling procedure passed ByRef (`HeapSort Arr`), moved into the
    /// parameter rather than copied: [MS-VBAL] 5.3.1.11 passes a reference to the variable,
    /// so the callee's writes are the caller's, and a call costs the same whatever the
    /// array's size (a copy per call made a sort that calls per item cubic). Only a local of
    /// the running procedure, named once among the arguments, is lent: no other code can
    /// reach it while the call runs.
    #[inline(never)]
    fn lendable(&self, caller_var: &Rc<str>, args: &[Arg]) -> bool {
        let an_array = {
            let frames = self.frames.borrow();
            let slot = frames.last().and_then(|f| f.vars.get(caller_var));
            slot.is_some_and(|s| !s.constant && matches!(s.var(), Var::Array(_)))
        };
        // Only an array's name is looked for among the arguments: looking for every name
        // made a call of 60,000 variables quadratic.
        let named = |a: &Arg| matches!(&a.value.kind, ExprKind::Name(n) if n.eq_ignore_ascii_case(caller_var));
        an_array && args.iter().filter(|a| named(a)).count() == 1
    }

    /// Takes a [`Interp::lendable`] array out of the caller's variable for the call.
    fn lend_array(&self, caller_var: &Rc<str>) -> Var {
        self.with_slot(caller_var, |s| s.replace(Var::Value(Value::Blank))).unwrap_or(Var::Value(Value::Blank))
    }

    /// Gives the lent arrays back to the caller (whose frame is the running one again) from
    /// the ended call's `frame`, whether the call ended well or not (VBA's caller sees what
    /// the callee wrote before an error). An array of the caller's declared type goes back
    /// as it is; anything else is assigned as a ByRef parameter's value is.
    fn give_back_lent(&self, p: &Proc, frame: &mut Frame, lent: &[(usize, Rc<str>)], ended_well: bool) -> Run<()> {
        for (index, caller_var) in lent {
            let Some(slot) = frame.vars.get_mut(&p.params[*index].name) else { continue };
            let (var, callee_ty) = (slot.replace(Var::Value(Value::Blank)), slot.ty.clone());
            let mut copied = 0;
            let given = match var {
                // Items that do not convert to the caller's type leave the caller its array
                // as the callee left it, and the error: never an Empty where the array was.
                Var::Array(a) => self
                    .with_slot(caller_var, |s| {
                        let lent_items = Rc::as_ptr(&a.data);
                        let typed = match s.ty == callee_ty {
                            true => Ok(a),
                            false => super::arrays::typed_items(a.clone(), s.ty.as_ref(), &s.name).map_err(|m| (a, m)),
                        };
                        let (back, outcome) = match typed {
                            Ok(t) => (t, Ok(())),
                            Err((a, m)) => (a, Err(m)),
                        };
                        // Converted to the caller's type, the items are a copy.
                        if !std::ptr::eq(Rc::as_ptr(&back.data), lent_items) {
                            copied = back.data.data.len();
                        }
                        drop(s.replace(Var::Array(back)));
                        outcome
                    })
                    .map(|r| r.map_err(|m| self.fault(m))),
                other => Some(self.set_var(caller_var, other, p.span)),
            };
            // The copy is charged as any other: its memory, and its work as ReDim Preserve's.
            if copied > 0 {
                self.owe((copied * std::mem::size_of::<Value>()) as u64);
                self.count_copy(copied, p.span)?;
            }
            if let (true, Some(Err(fault))) = (ended_well, given) {
                return Err(fault);
            }
        }
        Ok(())
    }

    fn invoke(&self, proc: usize, bound: Vec<(usize, Var)>, call_site: Option<Span>) -> Run<Value> {
        let (value, frame) = self.invoke_frame(proc, bound, call_site, Call::default())?;
        self.no_record_result(proc, &frame)?;
        Ok(value)
    }

    /// Why a call of `p` cannot start here: `--max-depth` procedures already running, or
    /// less than [`Interp::stack_reserve`] of the native stack left. Each level of `--max-depth` is
    /// given 64 KiB of stack, but one procedure's body may take far more (255 nested blocks
    /// around a call nested in 120 function calls took 600 KiB a level and overflowed the
    /// stack at 10,000 levels): past the reserve it is VBA's error 28, "Out of stack space",
    /// trappable as VBA's is.
    fn call_refused(&self, p: &Proc) -> Option<Fault> {
        let depth = self.frames.borrow().len();
        if depth >= self.options.max_depth {
            let limit = self.options.max_depth;
            let hint = self.options.raise_hint("raise the limit with --max-depth");
            let mut f = self.fault(format!(
                "calls nest deeper than the limit ({limit}) calling {} {}: endless recursion? ({hint})",
                p.kind, p.name
            ));
            f.kind = ErrorKind::Limit;
            return Some(f);
        }
        if self.stack_short() {
            let why = format_args!(
                "calls nest {depth} deep calling {} {}, less than {} KiB of the thread's stack left",
                p.kind,
                p.name,
                self.stack_reserve() >> 10
            );
            let mut f = self.fault(errors::message(28, why));
            f.code = 28;
            return Some(f);
        }
        None
    }

    pub(super) fn invoke_frame(
        &self,
        proc: usize,
        bound: Vec<(usize, Var)>,
        call_site: Option<Span>,
        call: Call,
    ) -> Run<(Value, Frame)> {
        let p = &self.module.procs[proc];
        // A class's procedure calling another of its own runs for the same object.
        let me = call.me.or_else(|| self.me().filter(|_| self.same_class(proc)));
        // Read in the caller's frame, before the callee's is pushed.
        let typed: Vec<usize> = (call.lent.iter())
            .filter(|(i, caller_var)| self.with_slot(caller_var, |s| s.ty == p.params[*i].ty) == Some(true))
            .map(|(i, _)| *i)
            .collect();
        if let Some(f) = self.call_refused(p) {
            // The lent arrays were never bound: straight back to the caller.
            for (var, (_, caller_var)) in lent_args(bound, &call.lent) {
                self.with_slot(&caller_var, |s| s.replace(var));
            }
            return Err(f);
        }
        self.frames.borrow_mut().push(Frame {
            proc,
            vars: Slots::default(),
            with: Vec::new(),
            running: Vec::new(),
            call_site,
            on_error: OnError::Off,
            handling: false,
            missing: Vec::new(),
            me,
        });
        let mut bound = bound;
        let result = self.bind_and_run(p, &mut bound, &typed);
        let mut frame = self.frames.borrow_mut().pop().expect("the frame pushed above");
        self.keep_statics(&frame);
        // A binding that failed (`S 40000, a` to `n As Integer`) left the lent arrays after
        // it unbound: straight back to the caller, as with the depth limit above.
        for (var, (_, caller_var)) in lent_args(bound, &call.lent) {
            self.with_slot(&caller_var, |s| s.replace(var));
        }
        self.give_back_lent(p, &mut frame, &call.lent, result.is_ok())?;
        result?;
        self.release_locals(p, &frame)?;
        let value = match p.kind {
            ProcKind::Function => match frame.vars.get(&p.name).map(|s| s.var()) {
                Some(Var::Value(v)) => v.clone(),
                Some(Var::Array(a)) => Value::Array(a.data.clone()),
                Some(Var::Obj(Obj::Value(v))) => v.clone(),
                Some(Var::Obj(Obj::Range(s, r))) => self.ctx().rect_value(*s, *r).unwrap_single(),
                // The caller takes it from the frame (`call_record`) or refuses it.
                _ => Value::Blank,
            },
            ProcKind::Sub => Value::Blank,
        };
        Ok((value, frame))
    }

    /// Binds the arguments and runs the body; the parameters in `typed` hold an array lent
    /// by a caller's variable of the parameter's own type, whose items need no converting.
    /// The arguments not bound when a binding fails are left in `bound` (an array argument
    /// whose items do not convert too), for a lent array to go back to its caller.
    fn bind_and_run(&self, p: &Proc, bound: &mut Vec<(usize, Var)>, typed: &[usize]) -> Run<()> {
        let types = self.take_arg_types();
        let long_longs = self.take_long_long_args();
        by_parameter(bound);
        for (i, param) in p.params.iter().enumerate() {
            let var = match bound_argument(bound, i) {
                Some(var) => var,
                None => match &param.default {
                    Some(d) => Var::Value(self.eval(d)?),
                    None => {
                        if matches!(param.ty, None | Some(Ty::Variant)) {
                            self.mark_missing(&param.name);
                        }
                        self.default_var(param.ty.as_ref())?
                    }
                },
            };
            let var = match param.array {
                true if typed.contains(&i) => var,
                // A clone shares the items until they are converted, which copies them anyway.
                true => super::arrays::array_param(var.clone(), param).map_err(|m| {
                    bound.push((i, var));
                    self.fault(m)
                })?,
                false => match super::longlong::long_long_param(&long_longs, i, param.ty.as_ref()) {
                    Some(whole) => whole,
                    None => {
                        // `F(r.Cells(1))` to `s As String`: a cell gives its value, as Let does.
                        let var = self.range_as_declared(var, param.ty.as_ref())?;
                        let var = self.string_param_text(var, param.ty.as_ref(), argument_type(&types, i));
                        convert(var, param.ty.as_ref(), &param.name).map_err(|m| self.fault(m))?
                    }
                },
            };
            let mut slot = Slot::new(param.name.clone(), var, param.ty.clone());
            // A Variant parameter given a Date holds a Date, given an Integer an Integer
            // ([MS-VBAL] 5.3.1.11: the argument's value is bound as it is, its value type with it).
            slot.set_holds(argument_type(&types, i));
            self.long_long_arg(&long_longs, i, &mut slot);
            self.declare(slot);
        }
        if p.kind == ProcKind::Function {
            let var = self.default_var(p.ty.as_ref())?;
            self.declare(Slot::new(p.name.clone(), var, p.ty.clone()));
        }
        match self.block(&p.body)? {
            Flow::GoTo(label) => Err(self.fault(format!("GoTo {label}: no such label"))),
            Flow::Return => Err(self.vba_fault(3, "Return belongs in a subroutine a GoSub runs")),
            Flow::Resume(_) => Err(self.vba_fault(20, "Resume belongs in an On Error GoTo handler")),
            Flow::End => {
                self.ended.set(true);
                Ok(())
            }
            _ => Ok(()),
        }
    }

    /// `var`, an argument holding a number of the type `held`, as a String parameter takes
    /// it ([`Interp::held_type_text`]: `Show CSng(1 / 3)` gives `t As String` "0.3333333");
    /// as it is for any other parameter.
    #[inline(never)]
    fn string_param_text(&self, var: Var, ty: Option<&Ty>, held: Declared) -> Var {
        match (&var, ty) {
            // A LongLong's every digit, where a double's text has fifteen (1.23456789012346E+15).
            (Var::Value(Value::Number(n)), Some(Ty::String | Ty::FixedString(_))) => {
                let digits = || super::longlong::long_long_digits(*n).filter(|_| held == Declared::LongLong);
                digits().or_else(|| self.held_type_text(held, *n)).map_or(var, |t| Var::Value(Value::text(t)))
            }
            _ => var,
        }
    }

    /// The types the caller noted of the arguments ([MS-VBAL] 5.3.1.11), ordered by parameter
    /// (stably: the first noted of a parameter first) for [`argument_type`] to search.
    #[inline(never)]
    fn take_arg_types(&self) -> Vec<(usize, Declared)> {
        let mut types = std::mem::take(&mut *self.arg_types.borrow_mut());
        types.sort_by_key(|&(i, _)| i);
        types
    }

    /// Whether the running procedure and `proc` are of one class module.
    fn same_class(&self, proc: usize) -> bool {
        let Some(running) = self.frames.borrow().last().map(|f| f.proc) else { return false };
        self.module.procs.get(running).is_some_and(|r| r.part == self.module.procs[proc].part)
    }

    /// A procedure's own variables are gone when it ends: an object only they held is
    /// terminated (not the Function's result, nor what a ByRef parameter gives back).
    #[inline(never)]
    fn release_locals(&self, p: &Proc, frame: &Frame) -> Run<()> {
        for (k, slot) in frame.vars.iter().enumerate() {
            // The parameters are the first slots, in order: a slot is looked for among them
            // only when it is not its own place's (a call of 60,000 parameters was quadratic).
            let by_ref = |q: &Param| q.by_ref && q.name.eq_ignore_ascii_case(&slot.name);
            let kept = (p.kind == ProcKind::Function && slot.name.eq_ignore_ascii_case(&p.name))
                || match p.params.get(k).filter(|q| q.name.eq_ignore_ascii_case(&slot.name)) {
                    Some(q) => q.by_ref,
                    None => p.params.iter().any(by_ref),
                };
            if !kept {
                self.release(slot.var())?;
            }
        }
        Ok(())
    }

    /// Runs a class module's declarations for a new object: the variables they declare
    /// become the object's own.
    pub(super) fn declare_fields(&self, object: &Instance, declarations: &[Stmt]) -> Run<()> {
        // `Dim child As New Node` in class Node makes one object inside the other without end.
        if self.frames.borrow().len() >= self.options.max_depth {
            let limit = self.options.max_depth;
            let mut f = self.fault(format!(
                "objects made by their own class's declarations (Dim … As New) nest deeper than the limit ({limit})"
            ));
            f.kind = ErrorKind::Limit;
            return Err(f);
        }
        self.frames.borrow_mut().push(Frame {
            proc: usize::MAX,
            vars: Slots::default(),
            with: Vec::new(),
            running: Vec::new(),
            call_site: None,
            on_error: OnError::Off,
            handling: false,
            missing: Vec::new(),
            me: None,
        });
        let result = declarations.iter().try_for_each(|d| self.exec(d).map(|_| ()));
        let frame = self.frames.borrow_mut().pop().expect("the frame pushed above");
        *object.0.fields.borrow_mut() = frame.vars;
        result
    }

    // ---- statements ------------------------------------------------------------------

    fn block(&self, block: &Block) -> Run<Flow> {
        self.block_from(block, 0)
    }

    fn block_from(&self, block: &Block, start: usize) -> Run<Flow> {
        self.block_entering(block, start, None)
    }

    /// Runs `block` from statement `start`, going into that statement at label `entering`
    /// when a GoTo names a label inside it; noted as running meanwhile, for an error handler
    /// that runs to its end ([`Flow::BlockEnd`]).
    fn block_entering(&self, block: &Block, start: usize, entering: Option<Rc<str>>) -> Run<Flow> {
        self.frame_mut(|f| f.running.push(block));
        let flow = self.block_steps(block, start, entering);
        self.frame_mut(|f| f.running.pop());
        match flow {
            Ok(Flow::BlockEnd(end)) if std::ptr::eq(end, block) => Ok(Flow::Next),
            other => other,
        }
    }

    fn block_steps(&self, block: &Block, start: usize, mut entering: Option<Rc<str>>) -> Run<Flow> {
        let mut i = start;
        while i < block.stmts.len() {
            let run = match entering.take() {
                Some(label) => self.enter_at(&block.stmts[i], &label),
                None => self.exec(&block.stmts[i]),
            };
            let flow = match run {
                Ok(flow) => flow,
                Err(fault) => match self.trap(fault)? {
                    Trap::Next => {
                        i += 1;
                        continue;
                    }
                    Trap::Retry => continue,
                    Trap::Flow(flow) => flow,
                },
            };
            match flow {
                Flow::Next => i += 1,
                Flow::GoTo(label) => match (block.label(&label), block.nested_label(&label)) {
                    (Some(target), _) => i = target,
                    (None, Some(holder)) => {
                        i = holder;
                        entering = Some(label);
                    }
                    (None, None) => return Ok(Flow::GoTo(label)),
                },
                other => return Ok(other),
            }
        }
        Ok(Flow::Next)
    }

    /// A GoTo into `stmt` at `label`, a label of one of its blocks ("GoTo statement": any
    /// line label of the procedure): that block runs from the label, then the statement goes
    /// on as from the block's end: an If or Select Case is done, a Do loop tests its
    /// condition and goes round, a For loop has no counter to step: VBA's error 92, "For loop
    /// not initialized" ("For loop not initialized (Error 92)": "You jumped into the middle
    /// of a For...Next loop"). Inside a With no With object is set: `.X` there is error 91
    /// ("Object variable or With block variable not set (Error 91)": "The target of a GoTo
    /// statement is inside a With block"). A block running further up (an error handler's
    /// label inside the loop, If or With around the failing statement) is that block itself:
    /// its With object, and at its end it goes on up there ([`Flow::BlockEnd`]).
    fn enter_at(&self, stmt: &Stmt, label: &Rc<str>) -> Run<Flow> {
        self.tick(stmt.span)?;
        let flow = match &stmt.kind {
            StmtKind::Do { test, at_end, body } => match self.run_into(&[body], label)? {
                Flow::Next => {
                    let ended = match test.as_ref().filter(|_| *at_end) {
                        Some(t) => self.truth(&t.cond, "the loop condition")? == t.until,
                        None => false,
                    };
                    if ended {
                        Flow::Next
                    } else {
                        self.do_loop(test.as_ref(), *at_end, body, stmt.span)?
                    }
                }
                Flow::Exit(ExitKind::Do) => Flow::Next,
                other => other,
            },
            StmtKind::For { body, .. } | StmtKind::ForEach { body, .. } => match self.run_into(&[body], label)? {
                Flow::Exit(ExitKind::For) => Flow::Next,
                Flow::Next => {
                    let why = "a GoTo went into the For loop, whose Next has no counter to step";
                    return Err(self.at_stmt(self.vba_fault(92, why), stmt));
                }
                other => other,
            },
            StmtKind::With { body, .. } => {
                let object = self.running_with(body);
                self.frame_mut(|f| f.with.push((body, object)));
                let flow = self.run_into(&[body], label);
                self.frame_mut(|f| f.with.pop());
                flow?
            }
            kind => self.run_into(&super::parser::inner_blocks(kind), label)?,
        };
        Ok(if self.ended.get() { Flow::End } else { flow })
    }

    /// Runs the one of `blocks` that holds `label`, from the label.
    fn run_into(&self, blocks: &[&Block], label: &Rc<str>) -> Run<Flow> {
        for &block in blocks {
            let flow = if let Some(at) = block.label(label) {
                self.block_from(block, at)?
            } else if let Some(holder) = block.nested_label(label) {
                self.block_entering(block, holder, Some(label.clone()))?
            } else {
                continue;
            };
            let running = self.frame_flag(|f| f.running.contains(&(block as *const Block)));
            return Ok(match flow {
                Flow::Next if running => Flow::BlockEnd(block),
                other => other,
            });
        }
        // The block that noted the label holds it: not reached.
        Ok(Flow::GoTo(label.clone()))
    }

    /// `fault` placed at `stmt` when the failing part did not know its place.
    fn at_stmt(&self, mut fault: Fault, stmt: &Stmt) -> Fault {
        fault.span.get_or_insert(stmt.span);
        fault
    }

    fn exec(&self, stmt: &Stmt) -> Run<Flow> {
        self.tick(stmt.span)?;
        let flow = self.exec_kind(stmt).map_err(|mut f| {
            f.span.get_or_insert(stmt.span);
            f
        })?;
        // `End` in a procedure called from this statement's expression stops everything.
        Ok(if self.ended.get() { Flow::End } else { flow })
    }

    fn exec_kind(&self, stmt: &Stmt) -> Run<Flow> {
        match &stmt.kind {
            StmtKind::Dim(vars) => self.dim(vars, false, false)?,
            StmtKind::Static(vars) => self.statics(vars)?,
            StmtKind::ReDim { preserve, vars } => self.dim(vars, true, *preserve)?,
            StmtKind::Const(items) => {
                for (name, ty, e) in items {
                    if !self.has_local(name) {
                        let var = self.constant_value(name, ty.as_ref(), e)?;
                        let mut slot = Slot::new(name.clone(), var, ty.clone());
                        self.constant_long_long(&mut slot, e);
                        slot.constant = true;
                        self.declare(slot);
                    }
                }
            }
            StmtKind::Assign { target, value, set } => self.assign(target, value, *set, stmt.span)?,
            // A method called as a statement drops its result, an object too ([MS-VBAL]
            // 5.4.2.1: a call statement's return value is discarded), as `Sheets.Add After:=…`.
            StmtKind::Call(e) if self.is_member_path(e) => {
                self.var_of(e, true)?;
            }
            StmtKind::Call(e) => {
                self.eval(e)?;
            }
            StmtKind::Print(items) => self.print(items)?,
            StmtKind::If { arms, otherwise } => return self.if_stmt(arms, otherwise.as_ref()),
            StmtKind::Select { subject, cases, otherwise } => return self.select(subject, cases, otherwise.as_ref()),
            StmtKind::For { var, from, to, step, body } => {
                return self.for_loop(var, from, to, step.as_ref(), body, stmt.span)
            }
            StmtKind::ForEach { var, group, body } => return self.for_each(var, group, body, stmt.span),
            StmtKind::Do { test, at_end, body } => return self.do_loop(test.as_ref(), *at_end, body, stmt.span),
            StmtKind::With { object, body } => {
                let obj = match self.var_of(object, true)? {
                    Var::Obj(o) => o,
                    Var::Value(v) => Obj::Value(v),
                    Var::Array(a) => Obj::Value(Value::Array(a.data)),
                    Var::Record(..) => match &object.kind {
                        ExprKind::Name(n) => Obj::Record(n.clone(), Vec::new()),
                        // `With pts(i)`: the item itself, so `.x = 1` changes it.
                        ExprKind::Host(id) if self.array_object(*id).is_some() => {
                            let (var, index, span) = self.array_object(*id).expect("an array's item");
                            match self.record_item(&var, index, span)? {
                                Some(k) => Obj::Record(var, vec![k]),
                                None => return Err(self.fault_at(span, "With needs the Type variable itself")),
                            }
                        }
                        _ => return Err(self.fault_at(self.expr_span(object), "With needs the Type variable itself")),
                    },
                };
                self.frame_mut(|f| f.with.push((body, Some(obj))));
                let flow = self.block(body);
                self.frame_mut(|f| f.with.pop());
                return flow;
            }
            StmtKind::Exit(kind) => return Ok(Flow::Exit(*kind)),
            StmtKind::GoTo(label) => return Ok(Flow::GoTo(label.clone())),
            StmtKind::GoSub(label) => return self.gosub(label),
            StmtKind::Return => return self.return_from_gosub(),
            StmtKind::OnError(mode) => self.on_error(mode),
            StmtKind::Resume(kind) => {
                if !self.frame_flag(|f| f.handling) {
                    // "Resume without error (Error 20)": trappable like any run-time error.
                    return Err(self.vba_fault(20, "Resume belongs in an On Error GoTo handler"));
                }
                return Ok(Flow::Resume(kind.clone()));
            }
            StmtKind::End => return Ok(Flow::End),
            StmtKind::Stop => return Err(self.stop(stmt.span)),
            StmtKind::Error(number) => return Err(self.error_statement(number)),
            StmtKind::Randomize(seed) => self.randomize(seed.as_ref())?,
            StmtKind::Erase(names) => self.erase(names, stmt.span)?,
            StmtKind::File(f) => self.file_stmt(f, stmt.span)?,
            StmtKind::CompileError(message) => return Err(compile_error(message.to_string(), stmt.span)),
        }
        Ok(Flow::Next)
    }

    /// A constant's value converted to its declared type ([MS-VBAL] 5.2.3.2, "Const
    /// Declarations": the value is let-coerced to the declared type), so `Const C As Integer
    /// = 2.5` is 2 and `Const X As Integer = 40000` an Overflow (error 6).
    fn constant_value(&self, name: &str, ty: Option<&Ty>, e: &Expr) -> Run<Var> {
        let var = Var::Value(self.eval(e)?);
        convert(var, ty, name).map_err(|m| {
            let mut fault = self.fault_at(self.expr_span(e), m);
            if fault.message.contains("(run-time error 6)") {
                fault.code = 6;
            }
            fault
        })
    }

    /// A new variable of a type: a Type's fields each at their own default, a record within
    /// the limits on its values and nesting.
    pub(super) fn default_var(&self, ty: Option<&Ty>) -> Run<Var> {
        if let Some(Ty::Record(i)) = ty {
            self.record_within_limits(*i)?;
        }
        self.default_fields(ty)
    }

    /// [`Self::default_var`] once its record is known to be within the limits.
    fn default_fields(&self, ty: Option<&Ty>) -> Run<Var> {
        Ok(match ty {
            Some(Ty::Record(i)) => {
                let def = &self.module.types[*i];
                let mut fields = Vec::with_capacity(def.fields.len());
                for ((_, t), bounds) in def.fields.iter().zip(&def.bounds) {
                    fields.push(match bounds {
                        // `x(1 To 100) As Double`: the field is an array of its type's defaults.
                        Some(b) if !b.is_empty() => {
                            let dims = self.array_dims(b, self.expr_span(&b[0].1))?;
                            Var::Array(self.array_with(&dims, Some(t))?)
                        }
                        // `v() As Double`: a dynamic array without bounds until ReDim.
                        Some(_) => Var::Array(
                            super::arrays::unallocated(Some(t)).unwrap_or_else(super::arrays::without_bounds),
                        ),
                        None => self.default_fields(Some(t))?,
                    });
                }
                Var::Record(*i, fields)
            }
            // An object variable starts as Nothing ([MS-VBAL] 5.2.3.1.3).
            Some(Ty::Object) => Var::Obj(Obj::Value(Value::Blank)),
            other => Var::Value(default_value(other)),
        })
    }

    /// The field a record path names, from the variable it starts at.
    pub fn record_field(&self, name: &str, path: &[usize]) -> Option<Var> {
        let mut var = self.lookup(name)?;
        for &i in path {
            var = match var {
                Var::Record(_, mut fields) => fields.swap_remove(i),
                // An item of an array of a Type, by its row-major position.
                Var::Array(a) => a.item(i),
                _ => return None,
            };
        }
        Some(var)
    }

    /// Writes a field of a Type variable, converted to the field's type.
    pub fn set_record_field(&self, name: &str, path: &[usize], value: Var, span: Span) -> Run<()> {
        let module = self.module;
        self.copy_records_if_shared(name, path, span)?;
        // The items of a field's array copied because the array was shared (each record of
        // `Dim t(1 To n) As T` starts with the one default array): charged to the memory
        // budget, which a loop writing into each record's array passed unseen until it aborted.
        let mut copied = 0;
        let result = self.with_slot(name, |slot| {
            let mut var = slot.var_mut();
            let mut ty = None;
            for (n, &i) in path.iter().enumerate() {
                var = match var {
                    Var::Record(t, fields) => {
                        ty = Some(&module.types[*t].fields[i]);
                        &mut fields[i]
                    }
                    Var::Array(super::value::VArray { records: Some(records), .. }) => &mut Rc::make_mut(records)[i],
                    // `p.x(3) = 2`: the item of a field that is an array of values, as it holds them.
                    Var::Array(a) if n + 1 == path.len() => {
                        let (field, field_ty) = ty.expect("an array field");
                        let given = super::budget::padding_bytes(&Var::Value(Value::Blank), &value);
                        let v = match convert(value, Some(field_ty), field)? {
                            Var::Value(v) => {
                                if let Some(arrays) = a.arrays.as_mut().filter(|held| held.contains_key(&i)) {
                                    Rc::make_mut(arrays).remove(&i);
                                }
                                v
                            }
                            // `A(1).Arr(2) = Array(1, 2)`: an item of a Variant array holds an
                            // array with its bounds ([MS-VBAL] 2.2).
                            Var::Array(inner) if matches!(field_ty, Ty::Variant) => {
                                let items = Value::Array(inner.data.clone());
                                Rc::make_mut(a.arrays.get_or_insert_with(Default::default)).insert(i, inner);
                                items
                            }
                            _ => return Err(format!("{field}(…) holds a value, not an object or an array")),
                        };
                        if Rc::strong_count(&a.data) > 1 {
                            copied = super::budget::copy_bytes(&a.data);
                        }
                        let stored = super::budget::padding_bytes(&Var::Value(Value::Blank), &Var::Value(v.clone()));
                        copied += stored.saturating_sub(given);
                        Rc::make_mut(&mut a.data).data[i] = v;
                        return Ok(());
                    }
                    _ => return Err("not a Type value".to_string()),
                };
            }
            let (field, field_ty) = ty.expect("a field");
            let given = value.clone();
            *var = convert(value, Some(field_ty), field)?;
            copied += super::budget::padding_bytes(&given, var);
            Ok(())
        });
        result.expect("a record variable").map_err(|m| self.fault_at(span, m))?;
        self.charge(copied, span)
    }

    // ---- errors and GoSub ---------------------------------------------------------------

    fn frame_flag(&self, f: impl FnOnce(&Frame) -> bool) -> bool {
        self.frames.borrow().last().is_some_and(f)
    }

    fn frame_mut<T>(&self, f: impl FnOnce(&mut Frame) -> T) {
        if let Some(frame) = self.frames.borrow_mut().last_mut() {
            f(frame);
        }
    }

    /// The object of the With whose body is `body`, when that With is running.
    fn running_with(&self, body: &Block) -> Option<Obj> {
        let frames = self.frames.borrow();
        let with = &frames.last()?.with;
        with.iter().rev().find(|(b, _)| std::ptr::eq(*b, body)).and_then(|(_, o)| o.clone())
    }

    fn on_error(&self, mode: &OnError) {
        let mut frames = self.frames.borrow_mut();
        let frame = frames.last_mut().expect("a running procedure");
        match mode {
            OnError::Reset => frame.handling = false,
            other => frame.on_error = other.clone(),
        }
        *self.err.borrow_mut() = ErrState::default();
    }

    /// `GoSub label`: the subroutine runs nested in this statement until its `Return`. A
    /// GoSub that never returns nests deeper at each call; past [`GOSUB_MAX_DEPTH`] it is
    /// VBA's error 28, "Out of stack space" (VBA's reference, "Out of stack space (Error
    /// 28)"), before the native stack runs out. The blocks between two GoSubs (`If`, `For`,
    /// `With` … around the inner one) nest native frames too, so the stack left is measured
    /// as well: a GoSub is refused with less than [`Interp::stack_reserve`] of it (800 GoSubs each
    /// inside an `If` overflowed an 8 MiB stack before the count was reached).
    fn gosub(&self, label: &str) -> Run<Flow> {
        let depth = self.gosubs.get();
        // Half a reserve more than a handler needs: error 28 is handled at this depth (the
        // handler runs in the procedure the GoSubs nest in), so it must find its reserve.
        let kept = self.stack_reserve() * 3 / 2;
        let short = self.stack_left().is_some_and(|left| left < kept);
        if depth >= GOSUB_MAX_DEPTH || short {
            let why = if short {
                format!(", less than {} KiB of the thread's stack left", kept >> 10)
            } else {
                String::new()
            };
            let mut f = self.fault(errors::message(28, format_args!("GoSubs nest {depth} deep without a Return{why}")));
            f.code = 28;
            return Err(f);
        }
        self.gosubs.set(depth + 1);
        let flow = self.run_from_label(label);
        self.gosubs.set(depth);
        Ok(match flow? {
            Flow::Return => Flow::Next,
            other => other,
        })
    }

    /// The native stack left below this frame, where the system says where the thread's
    /// stack ends (read once: a macro runs on one thread).
    fn stack_left(&self) -> Option<usize> {
        let (low, _) = match self.stack_low.get() {
            Some(bounds) => bounds,
            None => {
                let bounds = stack_bounds()?;
                self.stack_low.set(Some(bounds));
                bounds
            }
        };
        Some(stack_address().saturating_sub(low))
    }

    /// The stack a call, GoSub or handler must leave for what runs inside it: [`STACK_RESERVE`],
    /// or a quarter of a smaller thread's stack (a library caller's 2 MiB thread keeps room
    /// for its default 100 levels of recursion, as before the reserve was checked at calls).
    fn stack_reserve(&self) -> usize {
        self.stack_low.get().map_or(STACK_RESERVE, |(_, size)| STACK_RESERVE.min(size / 4))
    }

    /// Whether less than [`Interp::stack_reserve`] of the native stack is left.
    fn stack_short(&self) -> bool {
        self.stack_left().is_some_and(|left| left < self.stack_reserve())
    }

    /// Runs the procedure's body from a label: a GoSub's subroutine or an error handler.
    /// Running off the end of the body leaves the procedure. A handler's label may be inside
    /// a loop, If, Select or With ("On Error statement": any line label of the procedure):
    /// the blocks around it are entered as a GoTo enters them, while the failing statement
    /// waits below for the handler's `Resume` or `Resume Next` ([MS-VBAL] 5.4.4.2).
    fn run_from_label(&self, label: &str) -> Run<Flow> {
        let proc = self.frames.borrow().last().expect("a running procedure").proc;
        let body = &self.module.procs[proc].body;
        let flow = match body.label(label) {
            Some(start) => self.block_from(body, start)?,
            None => {
                let holder = body.nested_label(label).expect("the parser checked the label");
                self.block_entering(body, holder, Some(label.into()))?
            }
        };
        Ok(match flow {
            Flow::Next => Flow::Leave,
            other => other,
        })
    }

    /// `Return`: back to the statement after the GoSub that ran this subroutine. With no GoSub
    /// running it is run-time error 3 at the Return itself, which `On Error` traps as any other
    /// ("Return without GoSub (Error 3)": "A Return statement does not have a corresponding
    /// GoSub statement"; "GoSub...Return statement").
    #[inline(never)]
    fn return_from_gosub(&self) -> Run<Flow> {
        if self.gosubs.get() == 0 {
            return Err(self.vba_fault(3, "Return belongs in a subroutine a GoSub runs"));
        }
        Ok(Flow::Return)
    }

    /// VBA's run-time error `number` (its message from the one table), raised here.
    fn vba_fault(&self, number: u32, why: &str) -> Fault {
        let mut f = self.fault(errors::message(number, why));
        f.code = number;
        f
    }

    /// `Err` after `fault` trapped in the running procedure, with the line number before it.
    fn err_state_here(&self, fault: &Fault) -> ErrState {
        let proc = self.frames.borrow().last().map(|f| f.proc);
        let numbers = proc.map_or(&[][..], |p| &self.module.procs[p].line_numbers[..]);
        let line = fault.span.map_or(0, |s| numbers.iter().take_while(|(l, _)| *l <= s.line).last().map_or(0, |n| n.1));
        ErrState { line, ..err_state(fault) }
    }

    /// An error under `On Error`: what the failing block does next; the fault itself when
    /// nothing traps it (no handler, the handler already running, or a limit that stops the
    /// macro whatever it says).
    fn trap(&self, fault: Fault) -> Run<Trap> {
        let (mode, handling) = match self.frames.borrow().last() {
            Some(f) => (f.on_error.clone(), f.handling),
            None => return Err(fault),
        };
        let untrappable = [super::library::STOP, super::files::REFUSED, super::unmodelled::NOT_MODELLED];
        if fault.kind != ErrorKind::Runtime || untrappable.contains(&fault.code) || self.ended.get() {
            return Err(fault);
        }
        // Counted here, checked at the next statement: the handler's or the one after.
        self.steps.set(self.steps.get().saturating_add(TRAPPED_ERROR_STATEMENTS));
        let label = match mode {
            OnError::ResumeNext => {
                *self.err.borrow_mut() = self.err_state_here(&fault);
                return Ok(Trap::Next);
            }
            OnError::GoTo(label) if !handling => label,
            _ => return Err(fault),
        };
        *self.err.borrow_mut() = self.err_state_here(&fault);
        self.set_handling(true);
        self.handler_stack_check(fault.span)?;
        let flow = self.run_from_label(&label)?;
        if let Flow::Resume(_) = flow {
            self.set_handling(false);
            *self.err.borrow_mut() = ErrState::default();
        }
        Ok(match flow {
            Flow::Resume(Resume::Retry) => Trap::Retry,
            Flow::Resume(Resume::Next) => Trap::Next,
            Flow::Resume(Resume::Label(l)) => Trap::Flow(Flow::GoTo(l)),
            other => Trap::Flow(other),
        })
    }

    /// A handler runs nested in the failing statement, and `On Error GoTo -1` lets the next
    /// error run it again, deeper: refused as VBA's error 28, "Out of stack space", with
    /// less than [`Interp::stack_reserve`] of the native stack left, before it runs out; at the
    /// failing statement's place.
    fn handler_stack_check(&self, failing: Option<Span>) -> Run<()> {
        if !self.stack_short() {
            return Ok(());
        }
        let why =
            format!("error handlers nest with less than {} KiB of the thread's stack left", self.stack_reserve() >> 10);
        let mut fault = self.vba_fault(28, &why);
        fault.span = failing;
        Err(fault)
    }

    fn set_handling(&self, on: bool) {
        if let Some(f) = self.frames.borrow_mut().last_mut() {
            f.handling = on;
        }
    }

    fn dim(&self, vars: &[VarDecl], redim: bool, preserve: bool) -> Run<()> {
        for d in vars {
            if let Some(field) = &d.field {
                self.redim_field(d, field, preserve)?;
                continue;
            }
            if !redim && self.has_local(&d.name) {
                // VBA's Dim is a declaration, not an action: running it again keeps the value.
                continue;
            }
            let var = match &d.bounds {
                Some(bounds) if !bounds.is_empty() => {
                    // `Dim a() As Double` … `ReDim a(3)`: the items keep the declared type.
                    let declared = || self.with_slot(&d.name, |s| s.ty.clone()).flatten();
                    let ty = d.ty.clone().or_else(|| redim.then(declared).flatten());
                    let dims = self.array_dims(bounds, d.span)?;
                    if preserve {
                        let refusal = |slot: &mut Slot| match slot.var() {
                            Var::Array(old) => super::arrays::preserve_refusal(old, &dims),
                            _ => None,
                        };
                        if let Some(why) = self.with_slot(&d.name, refusal).flatten() {
                            return Err(self.subscript_fault(d.span, &d.name, why));
                        }
                    }
                    if preserve && self.grown_in_place(&d.name, &dims, ty.as_ref(), d.span)? {
                        continue;
                    }
                    let mut array = self.array_with(&dims, ty.as_ref())?;
                    if preserve {
                        if let Some(Var::Array(old)) = self.lookup(&d.name) {
                            self.count_copy(old.data.data.len(), d.span)?;
                            super::arrays::preserve_items(&old, &mut array);
                        }
                    }
                    Var::Array(array)
                }
                // `Dim x As New Class1` makes no object yet: the first use does.
                _ if d.new.is_some() => Var::Obj(Obj::Value(Value::Blank)),
                Some(_) if !redim => match super::arrays::unallocated(d.ty.as_ref()) {
                    Some(array) => Var::Array(array),
                    // `Dim a() As Variant`: an array too, without bounds until ReDim, which
                    // Erase leaves as it is ("Erase statement": a dynamic array's storage is
                    // freed) and IsArray finds True.
                    None if matches!(d.ty, None | Some(Ty::Variant)) => Var::Array(super::arrays::without_bounds()),
                    None => self.default_var(d.ty.as_ref())?,
                },
                _ => self.default_var(d.ty.as_ref())?,
            };
            self.charge(super::budget::brought(&var), d.span)?;
            if redim {
                // The objects only the old items held go (ReDim Preserve kept them).
                if let Some(old) = self.with_slot(&d.name, |s| s.replace(var.clone())) {
                    self.release(&old)?;
                    continue;
                }
            }
            let new = d.new.map(|class| (class, d.span));
            let mut slot = Slot::new(d.name.clone(), var, d.ty.clone());
            slot.new = new;
            slot.fixed = !redim && d.bounds.as_ref().is_some_and(|b| !b.is_empty());
            self.declare(slot);
        }
        Ok(())
    }

    /// `ReDim [Preserve] p.v(n)`, `ReDim p.inner.v(n)`: new bounds for the dynamic array field
    /// `v` of the Type variable `p`, or of a Type field of it ("ReDim statement"; a field
    /// declared with its bounds keeps them).
    fn redim_field(&self, d: &VarDecl, field: &str, preserve: bool) -> Run<()> {
        let (mut t, mut path) = self.redim_field_owner(d, field)?;
        let names: Vec<&str> = field.split('.').collect();
        for (n, name) in names.iter().enumerate() {
            let def = &self.module.types[t];
            let no_field = || format!("ReDim {}.{field}: {} has no field {name}", d.name, def.name);
            let i = def.field(name).ok_or_else(|| self.fault_at(d.span, no_field()))?;
            path.push(i);
            match &def.fields[i].1 {
                Ty::Record(inner) if n + 1 < names.len() && def.bounds[i].is_none() => t = *inner,
                _ if n + 1 < names.len() => {
                    let why = format!("ReDim {}.{field}: {}.{name} is no Type value", d.name, def.name);
                    return Err(self.fault_at(d.span, why));
                }
                _ => {}
            }
        }
        let def = &self.module.types[t];
        let i = *path.last().expect("a field");
        if !def.bounds[i].as_ref().is_some_and(|b| b.is_empty()) {
            let last = names.last().expect("a field");
            let why = format!("ReDim {}.{field}: {last} is no dynamic array field of {}", d.name, def.name);
            return Err(self.fault_at(d.span, why));
        }
        let dims = self.array_dims(d.bounds.as_deref().unwrap_or_default(), d.span)?;
        let mut array = self.array_with(&dims, Some(&def.fields[i].1))?;
        if let (true, Some(Var::Array(old))) = (preserve, self.record_field(&d.name, &path)) {
            if let Some(why) = super::arrays::preserve_refusal(&old, &dims) {
                return Err(self.subscript_fault(d.span, &format!("{}.{field}", d.name), why));
            }
            super::arrays::preserve_items(&old, &mut array);
        }
        let array = Var::Array(array);
        self.charge(super::budget::brought(&array), d.span)?;
        self.copy_records_if_shared(&d.name, &path, d.span)?;
        self.with_slot(&d.name, |slot| {
            let mut var = slot.var_mut();
            for &i in &path {
                var = match var {
                    Var::Record(_, fields) => &mut fields[i],
                    // `ReDim pts(i).v(n)`: the item of the array of a Type, by its position.
                    Var::Array(super::value::VArray { records: Some(records), .. }) => &mut Rc::make_mut(records)[i],
                    _ => return,
                };
            }
            *var = array;
        });
        Ok(())
    }

    /// The Type whose field `ReDim d.field(…)` sizes and the path to that Type's value: the
    /// variable itself (`ReDim p.v(n)`), or an item of an array of the Type, by its
    /// row-major position (`ReDim pts(i).v(n)`, "ReDim statement": any dynamic array).
    fn redim_field_owner(&self, d: &VarDecl, field: &str) -> Run<(usize, Vec<usize>)> {
        let not_type = || self.fault_at(d.span, format!("ReDim {}.{field}: {} is not a Type variable", d.name, d.name));
        match (&d.item, self.lookup(&d.name)) {
            (None, Some(Var::Record(t, _))) => Ok((t, Vec::new())),
            (Some(index), Some(Var::Array(_))) => {
                let Some(Some(Ty::Record(t))) = self.with_slot(&d.name, |s| s.ty.clone()) else {
                    return Err(not_type());
                };
                let k = self.record_item(&d.name, index, d.span)?.ok_or_else(not_type)?;
                Ok((t, vec![k]))
            }
            _ => Err(not_type()),
        }
    }

    /// `Static`: the variable the procedure's last call left, or a new one. It is moved
    /// into the call, not copied, so that a text the call grows (`s = s & x`, `append.rs`)
    /// grows in place: a copy shared with the one kept made every call copy the whole text.
    fn statics(&self, vars: &[VarDecl]) -> Run<()> {
        let (proc, me) = {
            let frames = self.frames.borrow();
            let frame = frames.last().expect("Static runs in a procedure");
            (frame.proc, frame.me.clone())
        };
        let owner = self.claim_static_owner(me.as_ref())?;
        for d in vars {
            if self.has_local(&d.name) {
                continue;
            }
            let key = (proc, owner, d.name.to_ascii_lowercase());
            let taken = self.kept.borrow_mut().get_mut(&key).map(Option::take);
            match taken.map(|slot| slot.or_else(|| self.outer_static(proc, owner, &d.name))) {
                Some(Some(slot)) => self.declare(slot),
                _ => {
                    self.dim(std::slice::from_ref(d), false, false)?;
                    self.kept.borrow_mut().insert(key, None);
                }
            }
        }
        Ok(())
    }

    /// The Static variable `name` as the nearest call of `proc` for the same object further
    /// out holds it: a recursive call shares its procedure's Static variables ("Static
    /// statement": they keep their values as long as the module runs, one for the procedure,
    /// not per call; in a class module one for each object).
    fn outer_static(&self, proc: usize, owner: usize, name: &str) -> Option<Slot> {
        let frames = self.frames.borrow();
        let same = |f: &&Frame| f.proc == proc && static_owner(f.me.as_ref()) == owner && f.vars.get(name).is_some();
        let outer = frames.iter().rev().skip(1).find(same);
        outer.and_then(|f| f.vars.get(name).cloned())
    }

    /// [`static_owner`] of `me`, the Static variables kept for an object that is gone and
    /// whose address `me` has now let go first.
    fn claim_static_owner(&self, me: Option<&Instance>) -> Run<usize> {
        let Some(me) = me else { return Ok(0) };
        let owner = static_owner(Some(me));
        let known = self.static_owners.borrow().get(&owner).and_then(std::rc::Weak::upgrade);
        if known.is_some_and(|o| Rc::ptr_eq(&o, &me.0)) {
            return Ok(owner);
        }
        self.static_owners.borrow_mut().insert(owner, Rc::downgrade(&me.0));
        let stale: Vec<Option<Slot>> = {
            let mut kept = self.kept.borrow_mut();
            let keys: Vec<_> = kept.keys().filter(|k| k.1 == owner).cloned().collect();
            keys.iter().filter_map(|k| kept.remove(k)).collect()
        };
        for slot in stale.iter().flatten() {
            self.release(slot.var())?;
        }
        Ok(owner)
    }

    /// Keeps the Static variables of a frame that is being left: for the call of the same
    /// procedure further out that holds them (recursion), else for the next call.
    fn keep_statics(&self, frame: &Frame) {
        let mut kept = self.kept.borrow_mut();
        if kept.is_empty() {
            return;
        }
        let mut frames = self.frames.borrow_mut();
        let owner = static_owner(frame.me.as_ref());
        for s in frame.vars.iter() {
            let Some(entry) = kept.get_mut(&(frame.proc, owner, s.name.to_ascii_lowercase())) else { continue };
            let outer = frames.iter_mut().rev().find(|f| {
                f.proc == frame.proc && static_owner(f.me.as_ref()) == owner && f.vars.get(&s.name).is_some()
            });
            match outer.and_then(|f| f.vars.get_mut(&s.name)) {
                Some(held) => *held = s.clone(),
                None => *entry = Some(s.clone()),
            }
        }
    }

    fn assign(&self, target: &Target, value: &Expr, set: bool, span: Span) -> Run<()> {
        match target {
            // `s = s & …` appends to the text in place (`append.rs`).
            Target::Var(name) if !set && self.append_in_place(name, value, span)? => Ok(()),
            // `Mid(s, i, 1) = x` replaces characters in place (`append.rs`).
            Target::Var(name) if !set && self.mid_in_place(name, value)? => Ok(()),
            Target::Var(name) if !set && self.declared_object(name) => match self.object_let(name) {
                Some(through) => self.let_through_object(name, through, value, span),
                None => self.let_var(name, value, set, span),
            },
            Target::Var(name) => self.let_var(name, value, set, span),
            Target::Element(name, index) => {
                if self.peek(name, |held| matches!(held, Var::Obj(Obj::Instance(_)))) == Some(true) {
                    return self.let_default_item(name, index, value, span);
                }
                if let Some(h) = self.store_named(name) {
                    let key = self.store_key(&mut self.ctx(), index, span)?;
                    let item = if set { self.item_var(value)? } else { self.var_of(value, false)? };
                    self.refuse_long_long_past_double(value, &item, super::collections::STORE_ITEM)?;
                    // The item keeps the type its number has (a Date, an Integer), as `d.Add` keeps it.
                    let held = if set { super::typing::Declared::Variant } else { self.item_held(value, &item) };
                    self.set_store_item(&h, &key, item, span)?;
                    return self.mark_store_held(&h, Some(&key.value), held, span);
                }
                if !set && self.holds_records(name) {
                    return self.set_record_element(name, index, value, span);
                }
                if set {
                    let item = self.item_var(value)?;
                    return self.set_object_element(name, index, item, span);
                }
                // `a(i) = a(i) & …` appends to the item's text in place (`append.rs`).
                if self.append_item_in_place(name, index, value, span)? {
                    return Ok(());
                }
                let v = match self.item_given(value)? {
                    Ok(array) => return self.set_array_element(name, index, array, span),
                    Err(v) => v,
                };
                // The item keeps the type of the number it is given, as a Variant does.
                let held = match &v {
                    Value::Number(_) => self.value_type(value, &v),
                    _ => Declared::Variant,
                };
                // A LongLong past 2^53 keeps its integer in the array (`longlong.rs`).
                self.note_item_long_long(value, &v);
                self.refuse_kept_decimal(value, &v, "an array item")?;
                self.set_element_holding(name, index, v, held, span)
            }
            Target::Node(id) if self.is_nested_item(*id) => self.set_nested_item(*id, value, set, span),
            Target::Node(id) if self.is_field_nested_item(*id) => self.set_field_nested_item(*id, value, set, span),
            Target::Node(id) => self.assign_node(*id, value),
        }
    }

    /// Whether `name` is declared as an object (`As Range`, `As Object`, a class …).
    fn declared_object(&self, name: &str) -> bool {
        self.with_slot(name, |s| matches!(s.ty, Some(Ty::Object))) == Some(true)
    }

    /// What a Let to an object variable goes through ([MS-VBAL] 5.4.3.8, Let statement: the
    /// object's default member takes the value): the cells it holds, its class instance, or
    /// its Nothing, which has no member to take a value. `None` for the other objects, which
    /// the value replaces.
    fn object_let(&self, name: &str) -> Option<ObjectLet> {
        match self.lookup(name)? {
            Var::Obj(cells @ (Obj::Range(..) | Obj::Lines(..))) => Some(ObjectLet::Cells(cells)),
            Var::Obj(Obj::Instance(object)) => Some(ObjectLet::Instance(object)),
            Var::Obj(Obj::Value(Value::Blank)) => Some(ObjectLet::Nothing),
            _ => None,
        }
    }

    /// `r = v` without Set, `r` declared as an object: `Dim r As Range: Set r = Range("A1"): r
    /// = 5` writes 5 into A1 and `r` still holds A1; an object of a class gives the value to
    /// its default member; Nothing is VBA's error 91 ("Object variable or With block variable
    /// not set").
    fn let_through_object(&self, name: &str, through: ObjectLet, value: &Expr, span: Span) -> Run<()> {
        match through {
            ObjectLet::Cells(cells) => {
                let v = self.sheet_value(value)?;
                self.write_default(cells, &v, span)
            }
            ObjectLet::Instance(object) => self.set_default_member(&mut self.ctx(), &object, &[], value, span),
            ObjectLet::Nothing => {
                let why = format!(
                    "{name} holds Nothing: no default member takes the value (Set {name} = … gives it an object)"
                );
                let mut fault = self.vba_fault(91, &why);
                fault.span = Some(span);
                Err(fault)
            }
        }
    }

    /// `bag(i) = value`, `Set bag(i) = obj` of a variable holding an object of a class: its
    /// default member, given the indexes as arguments.
    fn let_default_item(&self, name: &str, index: &[Expr], value: &Expr, span: Span) -> Run<()> {
        let Some(Var::Obj(Obj::Instance(object))) = self.lookup(name) else { unreachable!("checked by peek") };
        let args: Vec<Arg> = index.iter().map(|e| Arg { name: None, value: e.clone() }).collect();
        self.set_default_member(&mut self.ctx(), &object, &args, value, span)
    }

    /// `x = value`, `Set x = value` of a variable the value replaces.
    fn let_var(&self, name: &Rc<str>, value: &Expr, set: bool, span: Span) -> Run<()> {
        let var = super::regexp::let_value(self.var_of(value, set)?, set);
        // A Variant keeps the type of the number it is given ([MS-VBAL] 2.1.1.1: an
        // Integer for `x = 5`, a Date for a Date); known once evaluated (an item's, a
        // Variant Function's).
        let held = match &var {
            Var::Value(v @ Value::Number(_)) if !set => self.value_type(value, v),
            _ => Declared::Variant,
        };
        if set && matches!(var, Var::Value(ref v) if !v.is_blank()) {
            return Err(self.fault_at(self.expr_span(value), "Set needs an object (a Range, a Worksheet, …)"));
        }
        // `Set x = Nothing`: an object variable without an object (TypeName "Nothing",
        // IsObject True), where an unassigned Variant is Empty.
        let var = match var {
            Var::Value(Value::Blank) if set => Var::Obj(Obj::Value(Value::Blank)),
            // A String given a Date, a Single, a LongLong… holds the text its type writes
            // (5.5.1.2.4), not its day count or a Double's fifteen digits.
            Var::Value(v @ Value::Number(_)) if written_apart(held) => self.string_var_text(name, value, v),
            other => other,
        };
        // A LongLong past 2^53 keeps its integer ([MS-VBAL] 5.6.9.3, `longlong.rs`).
        if let Var::Value(v @ Value::Number(_)) = &var {
            if self.assign_long_long(name, value, v, held) {
                return Ok(());
            }
        }
        self.set_var_holding(name, var, held, span)
    }

    /// The number `v` that `value` gave as the variable `name` takes it: its
    /// [`Interp::let_text`] for a String variable, as it is for any other.
    #[inline(never)]
    fn string_var_text(&self, name: &str, value: &Expr, v: Value) -> Var {
        let string = |s: &mut Slot| matches!(s.ty, Some(Ty::String | Ty::FixedString(_)));
        let text = match self.with_slot(name, string) {
            Some(true) => self.let_text(value, &v),
            _ => None,
        };
        Var::Value(text.map_or(v, Value::text))
    }

    fn print(&self, items: &[PrintItem]) -> Run<()> {
        let left_open = self.line.borrow_mut().take();
        let was_open = left_open.is_some();
        let mut line = left_open.unwrap_or_default();
        let kept = line.len();
        let printed = self.print_items(items, &mut line);
        if printed.is_err() && was_open {
            // What an earlier `Debug.Print …;` left open is still written at the end.
            line.truncate(kept);
            *self.line.borrow_mut() = Some(line);
        }
        printed
    }

    /// Appends `items` to `line`, and writes it unless a `;` or `,` leaves it open.
    fn print_items(&self, items: &[PrintItem], line: &mut String) -> Run<()> {
        let mut open = false;
        for item in items {
            open = false;
            match item {
                PrintItem::Value(e) => {
                    let v = self.eval(e)?;
                    if let Value::Array(_) = v {
                        return Err(self.fault_at(self.expr_span(e), "Debug.Print prints values, not arrays"));
                    }
                    // VBA's Print leaves room for a sign before a number and a space after it;
                    // a Date is its text ("Print # statement"); a Single its seven digits.
                    let single = self.as_single(e, &v);
                    let v = single.map_or(v, Value::Number);
                    // A LongLong shows its every digit (`longlong.rs`).
                    let long_long = self.printed_long_long(e, &v);
                    let number = |n: f64| crate::eval::functions::vba::vba_number_shown(n, single.is_some());
                    match (self.as_date(e, &v), &v) {
                        (Some(date), _) => line.push_str(&super::value::date_text(date)),
                        (None, _) if long_long.is_some() => line.push_str(&long_long.unwrap_or_default()),
                        (None, Value::Number(n)) if *n >= 0.0 => line.push_str(&format!(" {} ", number(*n))),
                        (None, Value::Number(n)) => line.push_str(&format!("{} ", number(*n))),
                        // An error value prints as `Print #` writes it: `Error 2042`.
                        (None, Value::Error(_)) => line.push_str(&super::files::print_form(&v)),
                        _ => line.push_str(&print_text(&v)),
                    }
                }
                PrintItem::Join => open = true,
                PrintItem::Zone => {
                    let width = line.chars().count();
                    line.push_str(&" ".repeat(14 - width % 14));
                    open = true;
                }
            }
        }
        // A line left open by `;` counts too: `Debug.Print s;` in a loop grows one line.
        self.within_output_limit(line.len())?;
        if open {
            *self.line.borrow_mut() = Some(std::mem::take(line));
        } else {
            self.emit(Printed::Line(line));
        }
        Ok(())
    }

    fn flush_line(&self) {
        if let Some(line) = self.line.borrow_mut().take() {
            self.emit(Printed::Line(&line));
        }
    }

    /// Refuses output that would take the run past [`RunOptions::max_output`].
    pub fn within_output_limit(&self, more: usize) -> Run<()> {
        let limit = self.options.max_output;
        if self.output_bytes.get().saturating_add(more as u64) > limit {
            let hint = self.options.raise_hint("raise it with --max-output");
            let mut f = self.fault(format!(
                "the macro's output (Debug.Print and MsgBox) passes the limit of {limit} bytes ({hint})"
            ));
            f.kind = ErrorKind::Limit;
            return Err(f);
        }
        Ok(())
    }

    /// Hands a finished line to the sink as it happens, or keeps it in the run's output.
    pub fn emit(&self, printed: Printed) {
        let (Printed::Line(text) | Printed::Message(text)) = printed;
        self.output_bytes.set(self.output_bytes.get() + text.len() as u64 + 1);
        match (&self.options.sink, printed) {
            (Some(sink), _) => (sink.0)(printed),
            (None, Printed::Line(t)) => self.out.borrow_mut().printed.push(t.to_string()),
            (None, Printed::Message(t)) => self.out.borrow_mut().messages.push(t.to_string()),
        }
    }

    fn if_stmt(&self, arms: &[(Expr, Block)], otherwise: Option<&Block>) -> Run<Flow> {
        for (cond, body) in arms {
            match self.opening_condition(cond, "the If condition")? {
                Ok(Some(true) | None) => return self.block(body),
                Ok(Some(false)) => {}
                Err(flow) => return Ok(flow),
            }
        }
        match otherwise {
            Some(b) => self.block(b),
            None => Ok(Flow::Next),
        }
    }

    fn select(&self, subject: &Expr, cases: &[Case], otherwise: Option<&Block>) -> Run<Flow> {
        let s = self.eval(subject)?;
        // Every Case compares Null with Null: no Case holds.
        if let Value::Null = s {
            return otherwise.map_or(Ok(Flow::Next), |b| self.block(b));
        }
        if let Some(err) = s.as_error() {
            return Err(self.fault_at(self.expr_span(subject), self.describe_error("the Select Case value", &s, err)));
        }
        for case in cases {
            for test in &case.tests {
                if self.case_matches((subject, &s), test)? {
                    return self.block(&case.body);
                }
            }
        }
        match otherwise {
            Some(b) => self.block(b),
            None => Ok(Flow::Next),
        }
    }

    fn case_matches(&self, (subject, s): (&Expr, &Value), test: &CaseTest) -> Run<bool> {
        // Texts under Option Compare, LongLongs on their integers ([MS-VBAL] 5.4.2.10 compares
        // as `=` and `<=` do).
        let order = |e: &Expr, v: &Value| self.long_long_order((subject, e), (s, v)).or_else(|| self.vba_order(s, v));
        let cmp = |e: &Expr| -> Run<std::cmp::Ordering> {
            let v = self.eval(e)?;
            order(e, &v)
                .map_or_else(|| compare(s, &v), Ok)
                .map_err(|err| self.fault_at(self.expr_span(e), self.describe_error("the Case value", &v, err)))
        };
        Ok(match test {
            CaseTest::Value(e) => cmp(e)?.is_eq(),
            CaseTest::Range(lo, hi) => cmp(lo)?.is_ge() && cmp(hi)?.is_le(),
            CaseTest::Is(op, e) => {
                let v = self.eval(e)?;
                match order(e, &v) {
                    Some(ord) => crate::eval::evaluator::comparison_holds(*op, ord),
                    None => to_bool(&binary(*op, s, &v, DateSystem::From1900)).unwrap_or(false),
                }
            }
        })
    }

    fn for_loop(
        &self,
        var: &Rc<str>,
        from: &Expr,
        to: &Expr,
        step: Option<&Expr>,
        body: &Block,
        span: Span,
    ) -> Run<Flow> {
        let start = self.number(from, "the For start")?;
        let end = self.number(to, "the For end")?;
        let (step_value, step_ty) = match step {
            Some(e) => {
                let step = self.number(e, "the For step")?;
                (step, self.value_type(e, &Value::Number(step)))
            }
            None => (1.0, Declared::Integer),
        };
        let steps = step.map(|e| (e, step_value));
        let mut counting = match self.long_long_for_bounds(var, (from, start), (to, end), steps) {
            Some((first, last, step)) => {
                self.set_long_long_counter(var, first);
                Counting::LongLong { last, step }
            }
            None => {
                // A Variant counter holds the start's type, then that of counter + step
                // ([MS-VBAL] 5.4.2.3: it is Let-assigned the start value, then its value plus
                // the step).
                let held = self.value_type(from, &Value::Number(start));
                self.set_var_holding(var, Var::Value(Value::Number(start)), held, span)?;
                Counting::Double { end, step: step_value, step_ty, held }
            }
        };
        loop {
            if self.counter_past_end(var, &counting, span)? {
                return Ok(Flow::Next);
            }
            self.tick(span)?;
            match self.block(body)? {
                Flow::Next => {}
                Flow::Exit(ExitKind::For) => return Ok(Flow::Next),
                other => return Ok(other),
            }
            self.step_counter(var, &mut counting, span)?;
        }
    }

    /// Whether the For counter `var` has passed the loop's end.
    fn counter_past_end(&self, var: &Rc<str>, counting: &Counting, span: Span) -> Run<bool> {
        match *counting {
            Counting::Double { end, step, .. } => {
                let v = match self.peek(var, |held| self.counter_number(var, held)).flatten() {
                    Some(read) => read.map_err(|m| self.fault_at(span, m))?,
                    None => return Err(self.fault_at(span, format!("the For variable {var} no longer holds a number"))),
                };
                Ok((step >= 0.0 && v > end) || (step < 0.0 && v < end))
            }
            Counting::LongLong { last, step } => {
                let Some(i) = self.long_long_counter(var) else {
                    return Err(self.fault_at(span, format!("the For variable {var} no longer holds a whole number")));
                };
                Ok((step >= 0 && i > last) || (step < 0 && i < last))
            }
        }
    }

    /// The number a For counter holds (`None` when it holds no value).
    fn counter_number(&self, var: &str, held: &Var) -> Option<Result<f64, String>> {
        match held {
            Var::Value(v) => Some(self.number_of(v, var)),
            _ => None,
        }
    }

    /// The For counter `var` plus its step, as the loop's next value.
    fn step_counter(&self, var: &Rc<str>, counting: &mut Counting, span: Span) -> Run<()> {
        match counting {
            Counting::Double { step, step_ty, held, .. } => {
                let v = self.peek(var, |held| match held {
                    Var::Value(v) => to_number(v, DateSystem::From1900).unwrap_or(f64::NAN),
                    _ => f64::NAN,
                });
                let v = v.unwrap_or(f64::NAN);
                *held = super::typing::sum_held(*held, *step_ty, v + *step);
                self.set_var_holding(var, Var::Value(Value::Number(v + *step)), *held, span)
            }
            Counting::LongLong { step, .. } => {
                let Some(next) = self.long_long_counter(var).and_then(|i| i.checked_add(*step)) else {
                    return Err(self.overflow_fault(
                        span,
                        format!(
                            "the For variable {var} plus its step {step} passes a LongLong's range (-2^63 to 2^63 - 1)"
                        ),
                    ));
                };
                self.set_long_long_counter(var, next);
                Ok(())
            }
        }
    }

    /// The items `For Each` takes from `r.Rows` or `r.Columns`: each row (or column) of the
    /// range as a range as wide (tall) as it ("Range.Rows property": the collection of the rows
    /// of the range). Whole columns stop at the last used row, as a range's cells do.
    fn lines_of(&self, sheet: SheetId, rect: Rect, rows: bool) -> Vec<Var> {
        let used = self.ctx().clip_to_used(sheet, rect);
        let line = |i: u32| match rows {
            true => Rect { first: Pos::new(i, rect.first.col), last: Pos::new(i, rect.last.col) },
            false => Rect { first: Pos::new(rect.first.row, i), last: Pos::new(rect.last.row, i) },
        };
        let span = if rows { used.first.row..=used.last.row } else { used.first.col..=used.last.col };
        span.map(|i| Var::Obj(Obj::Range(sheet, line(i)))).collect()
    }

    fn for_each(&self, var: &Rc<str>, group: &Expr, body: &Block, span: Span) -> Run<Flow> {
        // VBA goes through an array or a collection with a Variant (or an object) only: an
        // Integer `m` would round each item ("For Each control variable must be Variant or
        // Object", a compile error in VBA, which no handler traps).
        let ty = self.with_slot(var, |s| s.ty.clone()).flatten();
        if ty.is_some_and(|t| !matches!(t, Ty::Variant | Ty::Object)) {
            let message = format!(
                "For Each control variable must be Variant or Object: {var} is declared otherwise (Dim {var} As Variant)"
            );
            return Err(compile_error(message, span));
        }
        // The type of the number each item holds, which the element variable keeps (a Date,
        // the Integer 1 of `Array(1, 2.5)`; [MS-VBAL] 5.4.2.4: it is let-assigned each
        // element, which keeps its Variant subtype).
        let mut held: Vec<Declared> = Vec::new();
        let items: Vec<Var> = match self.enumerated(self.var_of(group, true)?, group)? {
            Var::Obj(Obj::Range(sheet, rect)) => {
                let rect = self.ctx().clip_to_used(sheet, rect);
                let mut cells = Vec::new();
                for row in rect.first.row..=rect.last.row {
                    for col in rect.first.col..=rect.last.col {
                        cells.push(Var::Obj(Obj::Range(sheet, Rect::cell(Pos::new(row, col)))));
                    }
                }
                cells
            }
            Var::Obj(Obj::Areas(sheet, areas)) => self.area_cells(sheet, &areas),
            Var::Obj(Obj::AreaList(sheet, areas)) => areas.iter().map(|a| Var::Obj(Obj::Range(sheet, *a))).collect(),
            Var::Obj(Obj::Sheets) => self.wb.borrow().tab_order().iter().map(|&s| Var::Obj(Obj::Sheet(s))).collect(),
            Var::Obj(Obj::Lines(sheet, rect, rows)) => self.lines_of(sheet, rect, rows),
            Var::Obj(Obj::Hyperlinks(sheet, within)) => self.hyperlinks_each(sheet, within),
            Var::Obj(Obj::Table(t)) => match self.tables_each(&t, self.expr_span(group))? {
                Some(items) => items,
                None => {
                    return Err(
                        self.fault_at(self.expr_span(group), format!("For Each cannot go through a {}", t.class()))
                    )
                }
            },
            Var::Array(a) => {
                // An array of a declared type: each item is of that type.
                let typed = match &group.kind {
                    ExprKind::Name(n) => self.with_slot(n, |s| Declared::of_ty(s.ty.as_ref())),
                    _ => None,
                };
                held = match typed.filter(|ty| *ty != Declared::Variant) {
                    Some(ty) => vec![ty; a.data.data.len()],
                    None => a.memory_order().into_iter().map(|k| a.held(k)).collect(),
                };
                a.items()
            }
            // A Collection's items, a Dictionary's keys ("For Each...Next statement").
            Var::Obj(Obj::Store(h)) => {
                held = h.each_held();
                h.each()
            }
            Var::Obj(Obj::Value(Value::Array(a))) => a.data.iter().cloned().map(Var::Value).collect(),
            Var::Obj(Obj::Regex(r)) if r.each().is_some() => r.each().unwrap_or_default(),
            Var::Obj(other) => {
                return Err(
                    self.fault_at(self.expr_span(group), format!("For Each cannot go through {}", other.describe()))
                )
            }
            Var::Value(v) => {
                let shown = print_text(&v);
                return Err(
                    self.fault_at(self.expr_span(group), format!("For Each needs a range or an array, not {shown}"))
                );
            }
            Var::Record(..) => {
                return Err(self.fault_at(self.expr_span(group), "For Each needs a range or an array, not a Type value"))
            }
        };
        // The items are gathered before the first turn: a loop that leaves at its first item
        // (`For Each x In a: Exit For` over 9 million) copied them all, each turn uncounted.
        self.count_copy(items.len(), span)?;
        for (k, item) in items.into_iter().enumerate() {
            self.tick(span)?;
            let ty = held.get(k).copied().unwrap_or(Declared::Variant);
            self.set_var_holding(var, item, ty, span)?;
            match self.block(body)? {
                Flow::Next => {}
                Flow::Exit(ExitKind::For) => return Ok(Flow::Next),
                other => return Ok(other),
            }
        }
        Ok(Flow::Next)
    }

    /// The condition of an If, ElseIf, `Do While|Until` or `While`: `Ok(None)` when it failed
    /// and `Resume Next` trapped it, `Err(flow)` when the handler left elsewhere. Resume Next
    /// goes on with the next statement, which is the first of the block: the block runs, as in
    /// VBA and in LibreOffice's VBA mode (tests/vba_libreoffice.rs).
    fn opening_condition(&self, cond: &Expr, what: &str) -> Run<Result<Option<bool>, Flow>> {
        loop {
            match self.truth(cond, what) {
                Ok(holds) => return Ok(Ok(Some(holds))),
                Err(fault) => match self.trap(fault)? {
                    Trap::Next => return Ok(Ok(None)),
                    Trap::Retry => continue,
                    Trap::Flow(flow) => return Ok(Err(flow)),
                },
            }
        }
    }

    fn do_loop(&self, test: Option<&LoopTest>, at_end: bool, body: &Block, span: Span) -> Run<Flow> {
        // At the end the statement after `Loop While c` is the one after the loop: a failing
        // condition that the handler resumes leaves the loop, as the trapping block does.
        let holds = |t: &LoopTest| -> Run<bool> { Ok(self.truth(&t.cond, "the loop condition")? != t.until) };
        loop {
            self.tick(span)?;
            if let Some(t) = test.filter(|_| !at_end) {
                match self.opening_condition(&t.cond, "the loop condition")? {
                    Ok(Some(holds)) if holds == t.until => return Ok(Flow::Next),
                    Ok(_) => {}
                    Err(flow) => return Ok(flow),
                }
            }
            match self.block(body)? {
                Flow::Next => {}
                Flow::Exit(ExitKind::Do) => return Ok(Flow::Next),
                other => return Ok(other),
            }
            if let Some(t) = test.filter(|_| at_end) {
                if !holds(t)? {
                    return Ok(Flow::Next);
                }
            }
        }
    }

    // ---- cells -----------------------------------------------------------------------

    /// Writes a value into every cell of a range as if typed (VBA's `Range.Value =`): text
    /// starting with `=` becomes a formula, `"12"` a number; an array fills item by item.
    pub fn write_range(&self, sheet: SheetId, rect: Rect, v: &Value) -> Run<()> {
        let cells = rect.rows() as u64 * rect.cols() as u64;
        if cells > MAX_WRITE {
            return Err(self
                .beyond_limit(None, format!("writing {cells} cells at once is more than a macro may ({MAX_WRITE})")));
        }
        self.refuse_protected(sheet)?;
        let mut wb = self.book_mut()?;
        let item_at = |pos: Pos| match v {
            Value::Array(a) => {
                a.broadcast_get((pos.row - rect.first.row) as usize, (pos.col - rect.first.col) as usize)
            }
            other => other.clone(),
        };
        // A blank written where no cell is makes none.
        let filled = |pos| !input_text(&item_at(pos)).is_empty();
        wb.room_for_filled(sheet, rect, filled).map_err(|e| self.workbook_fault(None, &e))?;
        for row in rect.first.row..=rect.last.row {
            for col in rect.first.col..=rect.last.col {
                let pos = Pos::new(row, col);
                wb.set_input_deferred(sheet, pos, &input_text(&item_at(pos)))
                    .map_err(|e| self.workbook_fault(None, &e))?;
            }
        }
        wb.recalculate_rect(sheet, rect);
        Ok(())
    }
}

/// The deepest GoSubs nest without a Return (each level is a few native stack frames: the
/// limit leaves room for them on a 2 MiB thread with procedures and expressions running).
pub const GOSUB_MAX_DEPTH: usize = 1000;

/// The native stack a GoSub leaves for what runs inside it: a statement's expressions at
/// their nesting limits fit in it (docs/limits.md: both formula limits hold on 2 MiB).
const STACK_RESERVE: usize = 1 << 20;

/// The lowest address of the running thread's stack and its size (glibc's `pthread_getattr_np`, which
/// knows the main thread's too), or `None` where the system does not say.
fn stack_bounds() -> Option<(usize, usize)> {
    // SAFETY: `attr` is initialised by pthread_getattr_np before it is read, and destroyed
    // once; the out-pointers are valid locals.
    unsafe {
        let mut attr: libc::pthread_attr_t = std::mem::zeroed();
        if libc::pthread_getattr_np(libc::pthread_self(), &mut attr) != 0 {
            return None;
        }
        let mut addr: *mut libc::c_void = std::ptr::null_mut();
        let mut size: libc::size_t = 0;
        let read = libc::pthread_attr_getstack(&attr, &mut addr, &mut size) == 0;
        libc::pthread_attr_destroy(&mut attr);
        (read && !addr.is_null()).then_some((addr as usize, size))
    }
}

/// The address of a local of this frame: where the native stack stands (it grows down).
#[inline(never)]
fn stack_address() -> usize {
    let marker = 0u8;
    std::hint::black_box(&marker) as *const u8 as usize
}

/// The most cells one assignment writes (a whole sheet is 17 billion).
const MAX_WRITE: u64 = 10_000_000;

/// A workbook error on one line (a formula's parse error with its column, not a caret).
pub fn one_line(e: &WorkbookError) -> String {
    match e {
        WorkbookError::Parse { place, text, error } => {
            format!("{place}: {text}: column {}: {}", error.column(text), error.message)
        }
        other => other.to_string(),
    }
}

/// The VBA number of the workbook's refusal `e`: a write, paste or sort past the workbook's
/// cells, or a sheet past its sheets, is Excel's number for a Range write it cannot do
/// (Microsoft KB 832136: a range's value Excel cannot take is "Run-time error 1004"), the
/// message naming the cell kept as the description; any other is ncsheet's own (0: error 5
/// once trapped).
fn workbook_error_number(e: &WorkbookError) -> u32 {
    match e {
        WorkbookError::TooManyCells(_) | WorkbookError::TooManySheets => 1004,
        _ => 0,
    }
}

/// `Err` after a trapped failure: its VBA number, given or read from the kind of failure the
/// message names, and the message as the description.
fn err_state(fault: &Fault) -> ErrState {
    let m = fault.message.as_str();
    let number = match fault.code {
        0 if m.contains("#DIV/0!") => 11,
        0 if m.contains("overflow") => 6,
        0 if m.contains("Invalid use of Null") => 94,
        0 if m.contains("type mismatch") || m.contains("not a number") => 13,
        0 if m.contains("out of range") || m.contains("subscript") => 9,
        0 => 5,
        n => n,
    };
    let description = err_description(fault, number);
    // "Raise method": a source not given is the programmatic ID of the project, Excel's
    // "VBAProject", as for the errors VBA raises itself.
    let source = fault.source.clone().unwrap_or_else(|| "VBAProject".into());
    ErrState { number, description, source, line: 0 }
}

/// `Err.Description` of a trapped fault numbered `number`: the description before the number
/// (VBA's errors and Excel's own, as "Cannot run the macro"); VBA's message for the number
/// ("Trappable errors") when the message only ends with it or the number was read from the
/// kind of failure; the message itself for `Err.Raise`'s description and ncsheet's own
/// failures (numbered 5).
fn err_description(fault: &Fault, number: u32) -> String {
    let m = fault.message.as_str();
    let marker = format!(" (run-time error {number}): ");
    match m.split_once(&marker) {
        Some((vba, _)) if fault.code != 0 => return vba.to_string(),
        _ => {}
    }
    let defined = errors::description(number) != errors::APPLICATION_DEFINED;
    let numbered_at_end = fault.code != 0 && m.ends_with(&format!("(run-time error {number})"));
    let inferred = fault.code == 0 && number != 5;
    if defined && (numbered_at_end || inferred) {
        errors::description(number).to_string()
    } else {
        fault.message.clone()
    }
}

/// The arguments of `bound` that are lent arrays, each with its entry of `lent`.
/// Orders the bound arguments by parameter, the first parameter's last, for
/// [`bound_argument`] to take each in turn: finding each parameter's argument among all made
/// a call of 60,000 arguments quadratic.
#[inline(never)]
fn by_parameter(bound: &mut [(usize, Var)]) {
    bound.sort_by_key(|b| std::cmp::Reverse(b.0));
}

/// The argument bound to parameter `i`, taken out of `bound` ([`by_parameter`]'s order).
#[inline(never)]
fn bound_argument(bound: &mut Vec<(usize, Var)>, i: usize) -> Option<Var> {
    if bound.last().is_some_and(|(j, _)| *j == i) {
        return bound.pop().map(|(_, var)| var);
    }
    let k = bound.iter().position(|(j, _)| *j == i)?;
    Some(bound.remove(k).1)
}

/// Whether a number held as `held` is written as a String otherwise than a Double is
/// ([`Interp::let_text`]).
fn written_apart(held: Declared) -> bool {
    matches!(held, Declared::Date | Declared::Single | Declared::Currency | Declared::LongLong | Declared::Decimal)
}

/// The type the argument of parameter `i` holds (`types` ordered by parameter, as
/// [`Interp::take_arg_types`] gives them), Variant when not noted.
#[inline(never)]
fn argument_type(types: &[(usize, Declared)], i: usize) -> Declared {
    let k = types.partition_point(|(j, _)| *j < i);
    types.get(k).filter(|(j, _)| *j == i).map_or(Declared::Variant, |&(_, ty)| ty)
}

fn lent_args(bound: Vec<(usize, Var)>, lent: &[(usize, Rc<str>)]) -> Vec<(Var, (usize, Rc<str>))> {
    let mut out = Vec::new();
    for (index, var) in bound {
        if let Some(entry) = lent.iter().find(|(i, _)| *i == index) {
            out.push((var, entry.clone()));
        }
    }
    out
}

/// How a For loop's counter moves to its end ([MS-VBAL] 5.4.2.3): on doubles, the type the
/// counter holds following counter + step; or, for a LongLong counter whose start or end no
/// double holds exactly, on its integer (`longlong.rs`), where a double's `+ 1` past 2^53
/// would leave it where it is.
enum Counting {
    Double { end: f64, step: f64, step_ty: Declared, held: Declared },
    LongLong { last: i64, step: i64 },
}

/// The selection `sheet` starts with, area by area: the ranges the file saved when one holds
/// the active cell (Excel keeps the active cell inside the selection) and they are no more
/// than a Range holds ([`super::areas::MAX_AREAS`]), else the active cell alone.
fn saved_selection(options: &RunOptions, sheet: &str, active: Pos) -> Vec<Rect> {
    let saved = options.selections.iter().find(|(name, _)| name == sheet).map(|(_, areas)| areas);
    let fits = |areas: &&Vec<Rect>| areas.len() <= super::areas::MAX_AREAS && areas.iter().any(|r| r.contains(active));
    saved.filter(fits).cloned().unwrap_or_else(|| vec![Rect::cell(active)])
}

/// The area of a selection that holds the active cell `active`.
fn area_of(areas: &[Rect], active: Pos) -> Rect {
    areas.iter().copied().find(|r| r.contains(active)).unwrap_or(Rect::cell(active))
}
