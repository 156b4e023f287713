//! The workbook's own functions: the public Functions of an .xlsm's standard modules, callable
//! from its cells as Excel calls them (`=myFunc(A1)`, `=Module1.myFunc(A1)`, any case). Each
//! call runs in a fresh interpreter under the run limits, reading cells and never writing
//! them; a failure is the cell's `#VALUE!`. Private Functions, Subs and the code of sheet,
//! workbook and class modules are not callable (`#NAME?`), as in Excel.

use std::rc::Rc;

use std::cell::{Cell, RefCell};
use std::time::{Duration, Instant};

use crate::eval::settings::FunctionLimits;
use crate::eval::{Env, Note, Operand, UserCall, Value, XlError};
use crate::workbook::{UserFunctions, Workbook};

use super::ast::{Module, ProcKind};
use super::formats::Looks;
use super::project::{ModuleKind, VbaProject};
use super::value::{array_var, Obj, Var};
use super::{interp, parse_with, Deadline, MacroError, RunOptions};

/// The deepest a function called from a cell may be allowed to nest its calls
/// (`FunctionLimits::max_depth` in the settings is held to it): it may run inside a macro already deep (a
/// macro's write recalculates the cells), whose stack must hold both.
pub const FUNCTION_MAX_DEPTH: usize = 32;

/// The most source, in bytes, of a project whose modules are parsed with one another's code.
const MAX_JOINED: usize = 1 << 20;

/// One standard module, parsed once.
struct Parsed {
    name: String,
    source: String,
    module: Module,
    /// For each procedure: callable from a cell (a public Function), and volatile.
    callable: Vec<Option<bool>>,
}

/// The public Functions of a VBA project's standard modules, as a workbook's own functions.
pub struct WorkbookFunctions {
    modules: Vec<Parsed>,
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
    if !functions.modules.is_empty() {
        wb.set_user_functions(Rc::new(functions));
    }
    errors
}

/// Makes the public Functions of the macro about to run, and of the modules given with it,
/// callable from the workbook's cells while it runs, as Excel calls the Functions of the
/// project a macro is in: `Range("D1").Formula = "=Coalesce(A1, B1)"` computes through the
/// module's `Coalesce`. A workbook that has functions of its own (an .xlsm's) keeps them; a
/// project without a public Function installs nothing.
pub(super) fn install_run_functions(wb: &mut Workbook, own: &str, source: &str, options: &RunOptions) {
    if wb.user_functions().is_some() || options.document.is_some() {
        return;
    }
    let module = |name: &str, source: &str, kind| super::project::ProjectModule {
        name: name.to_string(),
        stream: name.to_string(),
        kind,
        source: source.to_string(),
    };
    let mut modules = vec![module(own, source, ModuleKind::Standard)];
    modules.extend(options.project.iter().map(|(n, s)| module(n, s, ModuleKind::Standard)));
    modules.extend(options.classes.iter().map(|(n, s)| module(n, s, ModuleKind::Class)));
    if !modules.iter().any(|m| !m.function_names().is_empty()) {
        return;
    }
    let project = VbaProject { code_page: 65001, modules, protection: None };
    let (functions, _) = WorkbookFunctions::new(&project, wb, options.clone());
    if functions.modules.iter().any(|m| m.callable.iter().any(Option::is_some)) {
        wb.set_user_functions(Rc::new(functions));
    }
}

impl WorkbookFunctions {
    pub fn new(project: &VbaProject, wb: &Workbook, options: RunOptions) -> (WorkbookFunctions, Vec<MacroError>) {
        // The look is built once here; the options each module keeps need not carry it.
        let looks = RefCell::new(Rc::new(RefCell::new(Looks::new(wb, &options.looks))));
        // A cell's call has no command options to raise its limits: its messages say so.
        let options = RunOptions { looks: Vec::new(), limits_from: super::LimitsFrom::CellFunction, ..options };
        let mut modules = Vec::new();
        let mut errors = Vec::new();
        let standard: Vec<_> = project.modules.iter().filter(|m| m.kind == ModuleKind::Standard).collect();
        let total: usize = standard.iter().map(|m| m.source.len()).sum();
        let classes: Vec<(String, String)> = (project.modules.iter().filter(|m| m.kind == ModuleKind::Class))
            .map(|m| (m.name.clone(), m.source.clone()))
            .collect();
        for m in &standard {
            // With the others' code after it, as VBA compiles a project as one program (not
            // for a project so large that parsing it once per module would be slow).
            let mut own = options.clone();
            if total + classes.iter().map(|c| c.1.len()).sum::<usize>() <= MAX_JOINED {
                own.project =
                    standard.iter().filter(|o| o.name != m.name).map(|o| (o.name.clone(), o.source.clone())).collect();
                own.classes = classes.clone();
            }
            let (joined, _) = super::join_project(&m.name, &m.source, &own.project, &own.classes);
            match parse_with(&m.source, &m.name, wb, &own) {
                Ok(module) => {
                    let source = joined.unwrap_or_else(|| m.source.clone());
                    let callable = callable(&module, &source, m.source.lines().count());
                    modules.push(Parsed { name: m.name.clone(), source, module, callable });
                }
                Err(e) => errors.push(e),
            }
        }
        (WorkbookFunctions { modules, options, spent: Cell::new(0), began: Cell::new(Instant::now()), looks }, errors)
    }

    /// The module and procedure a cell's call of `name` means, with its volatility.
    fn find(&self, name: &str) -> Option<(&Parsed, usize, bool)> {
        let name = strip_prefix(name, "_xludf.");
        let (module, function) = match name.rsplit_once('.') {
            Some((m, f)) => (Some(m), f),
            None => (None, name),
        };
        self.modules.iter().filter(|m| module.is_none_or(|n| n.eq_ignore_ascii_case(&m.name))).find_map(|m| {
            let i = m.module.proc(function)?;
            m.callable[i].map(|volatile| (m, i, volatile))
        })
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
        self.find(name).map(|(_, _, v)| v)
    }

    fn begin_recalculation(&self) {
        self.spent.set(0);
        self.began.set(Instant::now());
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }

    fn call(&self, wb: &Workbook, cells: &dyn Env, call: &UserCall) -> Result<Value, Note> {
        let Some((m, proc, _)) = self.find(call.name) else { return Ok(Value::Error(XlError::Name)) };
        let limits = wb.settings().functions;
        let left = limits.statements_per_recalculation.saturating_sub(self.spent.get());
        if left == 0 {
            let message = format!(
                "{}.{} was not called: the workbook's VBA functions ran the {} statements one recalculation \
                 allows them (docs/limits.md)",
                m.name, m.module.procs[proc].name, limits.statements_per_recalculation
            );
            return Err(Note { error: XlError::Value, message });
        }
        let deadline = self.deadline(limits);
        if let Some(past) = deadline.filter(|d| Instant::now() > d.at) {
            let message = format!(
                "{}.{} was not called: the workbook's VBA functions ran past the --timeout of {} s one \
                 recalculation allows them (docs/limits.md)",
                m.name, m.module.procs[proc].name, past.seconds
            );
            return Err(Note { error: XlError::Value, message });
        }
        let mut options = self.options.clone();
        options.deadline = deadline;
        // The command's own limit (`RunOptions`) and the document's, whichever is less.
        options.max_statements = self.options.max_statements.min(limits.statements_per_call).min(left);
        options.max_depth = limits.max_depth.min(FUNCTION_MAX_DEPTH);
        let caller = call.caller;
        let function = format!("{}.{}", m.name, m.module.procs[proc].name);
        let args = formula_arguments(call.args, &function, || wb.cell_name(caller.0, caller.1))?;
        let looks = Rc::clone(&self.looks.borrow());
        let (result, steps) =
            interp::call_function(&m.module, wb, cells, &m.source, &m.name, &options, (proc, caller), args, looks);
        // A call stopped at its limit counted the statement it stopped at too.
        self.spent.set(self.spent.get().saturating_add(steps.min(options.max_statements)));
        match result {
            Ok(Value::Blank) => Ok(Value::Number(0.0)),
            Ok(v) => Ok(v),
            Err(e) => Err(Note { error: XlError::Value, message: e.to_string() }),
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

/// For each procedure of `module`: `Some(volatile)` for a public Function of the module's
/// own first `own_lines` lines, else `None`. Volatile: its body calls `Application.Volatile`
/// (without `False`).
fn callable(module: &Module, source: &str, own_lines: usize) -> Vec<Option<bool>> {
    let lines: Vec<&str> = source.lines().collect();
    let mut starts: Vec<usize> = module.procs.iter().map(|p| p.span.line as usize).collect();
    starts.sort_unstable();
    module
        .procs
        .iter()
        .map(|p| {
            if p.kind != ProcKind::Function || !p.public || p.span.line as usize > own_lines {
                return None;
            }
            let first = p.span.line as usize;
            let end = starts.iter().copied().find(|&s| s > first).unwrap_or(lines.len() + 1);
            let body = lines.get(first.saturating_sub(1)..(end - 1).min(lines.len())).unwrap_or(&[]);
            Some(body.iter().any(|l| marks_volatile(l)))
        })
        .collect()
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
