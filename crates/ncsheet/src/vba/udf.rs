//! The workbook's own functions: the public Functions of an .xlsm's standard modules, callable
//! from its cells as Excel calls them (`=myFunc(A1)`, `=Module1.myFunc(A1)`, any case). Each
//! call runs in a fresh interpreter under the run limits, reading cells and never writing
//! them; a failure is the cell's `#VALUE!`. Each call starts from the module-level variables
//! and constants as the project's declarations leave them, declared once per recalculation
//! (`interp::Shared`): what one call changes in them, the next does not see. Private
//! Functions, Subs and the code of sheet, workbook and class modules are not callable
//! (`#NAME?`), as in Excel.

use std::rc::Rc;

use std::cell::{Cell, RefCell};
use std::time::{Duration, Instant};

use crate::eval::settings::FunctionLimits;
use crate::eval::{Env, Note, Operand, UserCall, Value, XlError};
use crate::workbook::{UserFunctions, Workbook};

use super::ast::{Module, ProcKind};
use super::formats::Looks;
use super::project::{ModuleKind, ProjectModule, VbaProject};
use super::value::{array_var, Obj, Var};
use super::{interp, Deadline, MacroError, RunOptions};

/// The deepest a function called from a cell may be allowed to nest its calls
/// (`FunctionLimits::max_depth` in the settings is held to it): it may run inside a macro already deep (a
/// macro's write recalculates the cells), whose stack must hold both.
pub const FUNCTION_MAX_DEPTH: usize = 32;

/// The most modules of a project the parser leaves out for what it finds in them when read
/// with the others' code (a name none declares, a procedure defined twice) before it gives up
/// on the rest: each costs a parse of the whole project again.
const MAX_BROKEN_MODULES: usize = 8;

/// The project's standard and class modules parsed once, together, as VBA compiles a project
/// as one program: each module's Private names its own, the Public ones everybody's.
struct Program {
    module: Rc<Module>,
    /// The modules' code joined, the first's first (what `module`'s places point into).
    source: String,
    /// The first module's name: the others' places are named by `module.parts`.
    first: String,
    /// What its calls share, worked out once.
    shared: interp::Shared,
}

/// A public Function of a standard module, callable from a cell.
struct Function {
    module: Rc<str>,
    proc: usize,
    /// Its body calls `Application.Volatile`.
    volatile: bool,
}

/// The public Functions of a VBA project's standard modules, as a workbook's own functions.
pub struct WorkbookFunctions {
    program: Option<Program>,
    /// The callable Functions by lower-case name, in the order of their modules.
    functions: std::collections::HashMap<Box<str>, Vec<Function>>,
    options: RunOptions,
    /// Statements the calls of the current recalculation ran, against
    /// the settings' `FunctionLimits::statements_per_recalculation`.
    spent: Cell<u64>,
    /// When the current recalculation began, for `FunctionLimits::seconds_per_recalculation`.
    began: Cell<Instant>,
    /// How the cells look (`Range.Text`, `NumberFormat`): the file's, then the look of the
    /// macro running or last run on the workbook, which its calls share ([`share_looks`]).
    looks: RefCell<Rc<RefCell<Looks>>>,
}

/// Gives the workbook's own functions, when `wb` has them, the look `looks` of a macro that
/// starts: the cells they recompute while it runs show the formats it sets, as in Excel,
/// and so do later calls, the document keeping that look.
pub(super) fn share_looks(wb: &Workbook, looks: &Rc<RefCell<Looks>>) {
    let ours = wb.user_functions().and_then(|f| f.as_any().downcast_ref::<WorkbookFunctions>());
    if let Some(functions) = ours {
        *functions.looks.borrow_mut() = Rc::clone(looks);
    }
}

/// Installs the functions of `project` into `wb` (recomputing the cells that call them), each
/// call under the limits of `options`. Returns the modules that do not parse: their functions
/// stay `#NAME?`. Calls nest at most [`FUNCTION_MAX_DEPTH`] deep.
pub fn install_functions(wb: &mut Workbook, project: &VbaProject, options: RunOptions) -> Vec<MacroError> {
    let (functions, errors) = WorkbookFunctions::new(project, wb, options);
    if functions.program.is_some() {
        wb.set_user_functions(Rc::new(functions));
    }
    errors
}

/// Makes the public Functions of the macro about to run, and of the modules given with it,
/// callable from the workbook's cells while it runs, as Excel calls the Functions of the
/// project a macro is in: `Range("D1").Formula = "=Coalesce(A1, B1)"` computes through the
/// module's `Coalesce`. A workbook that has functions of its own (an .xlsm's) keeps them; a
/// project without a public Function installs nothing. `module` is the run's own tree of
/// the project (`joined`: its source, the macro's module first), not parsed again.
pub(super) fn install_run_functions(
    wb: &mut Workbook,
    own: &str,
    (module, joined): (&Rc<Module>, &str),
    options: &RunOptions,
) {
    if wb.user_functions().is_some() || options.document.is_some() {
        return;
    }
    let program = Program {
        module: Rc::clone(module),
        source: joined.to_string(),
        first: own.to_string(),
        shared: interp::Shared::new(joined),
    };
    let functions = callable_functions(&program);
    if !functions.is_empty() {
        wb.set_user_functions(Rc::new(WorkbookFunctions::with(Some(program), functions, wb, options.clone())));
    }
}

impl WorkbookFunctions {
    pub fn new(project: &VbaProject, wb: &Workbook, options: RunOptions) -> (WorkbookFunctions, Vec<MacroError>) {
        let (program, errors) = parse_project(&project.modules, wb, &options);
        let functions = program.as_ref().map(callable_functions).unwrap_or_default();
        (WorkbookFunctions::with(program, functions, wb, options), errors)
    }

    /// `functions` of `program` (parsed), called under `options`.
    fn with(program: Option<Program>, functions: Callable, wb: &Workbook, options: RunOptions) -> WorkbookFunctions {
        // The look is built once here; the options each module keeps need not carry it.
        let looks = RefCell::new(Rc::new(RefCell::new(Looks::new(wb, &options.looks))));
        // A cell's call has no command options to raise its limits: its messages say so.
        let options = RunOptions { looks: Vec::new(), limits_from: super::LimitsFrom::CellFunction, ..options };
        WorkbookFunctions { program, functions, options, spent: Cell::new(0), began: Cell::new(Instant::now()), looks }
    }

    /// The Function a cell's call of `name` means.
    fn find(&self, name: &str) -> Option<&Function> {
        let name = strip_prefix(name, "_xludf.");
        let (module, function) = match name.rsplit_once('.') {
            Some((m, f)) => (Some(m), f),
            None => (None, name),
        };
        let same_name = self.functions.get(function.to_ascii_lowercase().as_str())?;
        same_name.iter().find(|f| module.is_none_or(|n| n.eq_ignore_ascii_case(&f.module)))
    }

    /// When the calls of the current recalculation must stop, by the settings' time for one
    /// recalculation, or the command's `--timeout` if sooner.
    fn deadline(&self, limits: FunctionLimits) -> Option<Deadline> {
        let own = limits.seconds_per_recalculation.and_then(|seconds| {
            let at = self.began.get().checked_add(Duration::try_from_secs_f64(seconds).ok()?)?;
            Some(Deadline { at, seconds })
        });
        match (self.options.deadline, own) {
            (Some(a), Some(b)) => Some(if a.at <= b.at { a } else { b }),
            (a, b) => a.or(b),
        }
    }
}

impl UserFunctions for WorkbookFunctions {
    fn volatile(&self, name: &str) -> Option<bool> {
        self.find(name).map(|f| f.volatile)
    }

    fn begin_recalculation(&self) {
        self.spent.set(0);
        self.began.set(Instant::now());
        if let Some(program) = &self.program {
            program.shared.forget_declarations();
        }
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn call(&self, wb: &Workbook, cells: &dyn Env, call: &UserCall) -> Result<Value, Note> {
        let (Some(f), Some(program)) = (self.find(call.name), self.program.as_ref()) else {
            return Ok(Value::Error(XlError::Name));
        };
        let proc = f.proc;
        let function = format!("{}.{}", f.module, program.module.procs[proc].name);
        let limits = wb.settings().functions;
        let left = limits.statements_per_recalculation.saturating_sub(self.spent.get());
        if left == 0 {
            let message = format!(
                "{function} was not called: the workbook's VBA functions ran the {} statements one recalculation \
                 allows them (docs/limits.md)",
                limits.statements_per_recalculation
            );
            return Err(Note { error: XlError::Value, message });
        }
        let deadline = self.deadline(limits);
        if let Some(past) = deadline.filter(|d| Instant::now() > d.at) {
            let message = format!(
                "{function} was not called: the workbook's VBA functions ran past the --timeout of {} s one \
                 recalculation allows them (docs/limits.md)",
                past.seconds
            );
            return Err(Note { error: XlError::Value, message });
        }
        let mut options = self.options.clone();
        options.deadline = deadline;
        // The command's own limit (`RunOptions`) and the document's, whichever is less.
        options.max_statements = self.options.max_statements.min(limits.statements_per_call).min(left);
        options.max_depth = limits.max_depth.min(FUNCTION_MAX_DEPTH);
        let caller = call.caller;
        let args = formula_arguments(call.args, &function, || wb.cell_name(caller.0, caller.1))?;
        let looks = Rc::clone(&self.looks.borrow());
        let (module, source) = (&program.module, (program.source.as_str(), &program.shared));
        let (result, steps) =
            interp::call_function(module, wb, cells, source, &program.first, &options, (proc, caller), args, looks);
        // A call stopped at its limit counted the statement it stopped at too.
        self.spent.set(self.spent.get().saturating_add(steps.min(options.max_statements)));
        match result {
            Ok(Value::Blank) => Ok(Value::Number(0.0)),
            Ok(v) => Ok(v),
            Err(mut e) => {
                // A place in another module is named by that module and its own line.
                super::relocate(&mut e, &module.parts);
                Err(Note { error: XlError::Value, message: e.to_string() })
            }
        }
    }
}

/// A formula's arguments as the VBA Function `function` receives them: a reference as its
/// Range, an array from 1 as a range's (`=Terp(3, {1,2,4})`: the module's Option Base governs
/// only the arrays VBA itself makes), a union of areas on one sheet (`=Total((A1:A3,C1:C3))`)
/// as one Range of those areas. Areas on several sheets (a 3-D reference, `=Total(Sheet1:Sheet2!A1)`)
/// is refused, naming the calling cell (`cell`) and the argument: no Range holds it, and
/// handing over its first area alone would compute a wrong value without a word.
pub(super) fn formula_arguments(
    args: &[Operand],
    function: &str,
    cell: impl FnOnce() -> String,
) -> Result<Vec<Var>, Note> {
    let mut vars = Vec::with_capacity(args.len());
    for (index, arg) in args.iter().enumerate() {
        vars.push(match arg {
            Operand::Ref(s, r) => Var::Obj(Obj::Range(*s, *r)),
            Operand::Value(v) => array_var(v.clone(), 1),
            Operand::Areas(areas) => match super::areas::areas_object(areas) {
                Some(obj) => Var::Obj(obj),
                None => {
                    let message = format!(
                        "{}: {function} was not called: its argument {} is a union of areas on several sheets, \
                         which no VBA Range holds; pass each sheet's cells as a separate argument",
                        cell(),
                        index + 1
                    );
                    return Err(Note { error: XlError::Value, message });
                }
            },
        });
    }
    Ok(vars)
}

/// Parses the standard and class modules of `modules` once, together. A module that does not
/// parse is left out, with its error, and the others parsed again without it: each module
/// read alone by the grammar first (linear in the project's size, and it names a module cut
/// short, not the one joined after it), then, at most [`MAX_BROKEN_MODULES`] times, the
/// module the whole names. Past that the rest is not parsed, each module given an error
/// saying why.
fn parse_project(modules: &[ProjectModule], wb: &Workbook, options: &RunOptions) -> (Option<Program>, Vec<MacroError>) {
    let of_kind = |kind| modules.iter().filter(|m| m.kind == kind).collect::<Vec<_>>();
    let (mut standard, mut classes) = (of_kind(ModuleKind::Standard), of_kind(ModuleKind::Class));
    let mut errors = Vec::new();
    let mut screened = false;
    let mut broken = 0;
    while let Some((first, others)) = standard.split_first() {
        let e = match parse_program(first, others, &classes, wb, options) {
            Ok(program) => return (Some(program), errors),
            Err(e) => e,
        };
        if !screened {
            screened = true;
            let before = errors.len();
            standard.retain(|m| super::grammar_error(&m.source, &m.name).map(|e| errors.push(e)).is_none());
            if errors.len() > before {
                continue;
            }
        }
        broken += 1;
        let name = e.file.clone();
        errors.push(e);
        let count = standard.len() + classes.len();
        standard.retain(|m| m.name != name);
        classes.retain(|m| m.name != name);
        if standard.len() + classes.len() == count {
            break;
        }
        if broken == MAX_BROKEN_MODULES {
            errors.extend(standard.iter().map(|m| given_up(m, broken)));
            break;
        }
    }
    (None, errors)
}

/// Module `first` parsed with the code of `others` and `classes` after it.
fn parse_program(
    first: &ProjectModule,
    others: &[&ProjectModule],
    classes: &[&ProjectModule],
    wb: &Workbook,
    options: &RunOptions,
) -> Result<Program, MacroError> {
    let code = |m: &&ProjectModule| (m.name.clone(), m.source.clone());
    let project = others.iter().map(code).collect();
    let options = RunOptions { project, classes: classes.iter().map(code).collect(), ..options.clone() };
    let (module, joined) = super::parse_joined(&first.source, &first.name, wb, &options)?;
    let source = joined.unwrap_or_else(|| first.source.clone());
    let shared = interp::Shared::new(&source);
    Ok(Program { module: Rc::new(module), source, first: first.name.clone(), shared })
}

/// Why module `m` was not parsed: `broken` of the project's modules did not parse.
fn given_up(m: &ProjectModule, broken: usize) -> MacroError {
    MacroError {
        kind: super::ErrorKind::Syntax,
        file: m.name.clone(),
        span: None,
        message: format!(
            "not parsed: {broken} modules of the project do not parse, the most left out before the rest is \
             given up (docs/limits.md)"
        ),
        source_line: String::new(),
        trace: Vec::new(),
        output: Box::new(super::RunOutput::new("", crate::nc::Machine::Lathe)),
    }
}

/// Functions callable from cells, by lower-case name.
type Callable = std::collections::HashMap<Box<str>, Vec<Function>>;

/// The public Functions of the standard modules of `program`, by lower-case name. Volatile:
/// the body calls `Application.Volatile` (without `False`).
fn callable_functions(program: &Program) -> Callable {
    let module = &program.module;
    let lines: Vec<&str> = program.source.lines().collect();
    let mut starts: Vec<usize> = module.procs.iter().map(|p| p.span.line as usize).collect();
    starts.sort_unstable();
    let first: Rc<str> = program.first.as_str().into();
    let mut functions: std::collections::HashMap<Box<str>, Vec<Function>> = Default::default();
    for (proc, p) in module.procs.iter().enumerate() {
        let part = module.parts.get(p.part);
        if p.kind != ProcKind::Function || !p.public || part.is_some_and(|m| m.class) {
            continue;
        }
        let line = p.span.line as usize;
        let end = starts.get(starts.partition_point(|&s| s <= line)).copied().unwrap_or(lines.len() + 1);
        let body = lines.get(line.saturating_sub(1)..(end - 1).min(lines.len())).unwrap_or(&[]);
        let volatile = body.iter().any(|l| marks_volatile(l));
        let name = part.map_or_else(|| Rc::clone(&first), |m| Rc::clone(&m.name));
        functions.entry(p.name.to_ascii_lowercase().into()).or_default().push(Function {
            module: name,
            proc,
            volatile,
        });
    }
    functions
}

/// Whether a line of code says `Application.Volatile` (or `Application.Volatile True`).
fn marks_volatile(line: &str) -> bool {
    let code = line.split('\'').next().unwrap_or("").to_ascii_lowercase();
    let Some(at) = code.find("application.volatile") else { return false };
    !code[at + "application.volatile".len()..].trim_start().starts_with("false")
}

fn strip_prefix<'a>(name: &'a str, prefix: &str) -> &'a str {
    match name.get(..prefix.len()) {
        Some(p) if p.eq_ignore_ascii_case(prefix) => &name[prefix.len()..],
        _ => name,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn application_volatile_marks_a_function_volatile_unless_false() {
        assert!(marks_volatile("    Application.Volatile"));
        assert!(marks_volatile("application.volatile True"));
        assert!(!marks_volatile("    Application.Volatile False"));
        assert!(!marks_volatile("    ' Application.Volatile"));
        assert!(!marks_volatile("    x = 1"));
    }
}
