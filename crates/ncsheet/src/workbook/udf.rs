//! The workbook's own functions (user-defined functions: the VBA Functions of an .xlsm's
//! macros) as the workbook sees them: a provider that the macro layer implements and the
//! importer's caller installs. The evaluator reaches them through [`Env::call_user_function`]
//! for a call of a name that is no sheet function; their dependencies are their arguments'
//! references, as in Excel, and a provider's volatile function (`Application.Volatile`) makes
//! its cells recalculate at every edit.

use std::rc::Rc;

use crate::eval::{Env, Note, UserCall, Value, XlError};
use crate::formula::ast::{Expr, ExprKind};

use super::{Workbook, NO_FORMULA};

/// A workbook's own functions, callable from its cells.
pub trait UserFunctions {
    /// Whether a cell may call `name` (spelled as the formula does, `Module1.F` too), and if
    /// so whether it is volatile; `None` for no such function.
    fn volatile(&self, name: &str) -> Option<bool>;

    /// Makes the call, reading cells through `cells`. A failure inside the function is an
    /// error value with why (`#VALUE!`), never a change to `wb`.
    fn call(&self, wb: &Workbook, cells: &dyn Env, call: &UserCall) -> Result<Value, Note>;

    /// A recalculation starts: the budget all its calls share is full again.
    fn begin_recalculation(&self) {}

    /// The provider as itself, for the macro layer that made it to reach its own state (a
    /// running macro shares the cells' look with the functions it recomputes).
    fn as_any(&self) -> &dyn std::any::Any;
}

impl Workbook {
    /// The workbook's own functions, once installed.
    pub fn user_functions(&self) -> Option<&Rc<dyn UserFunctions>> {
        self.user_functions.as_ref()
    }

    /// Installs the workbook's own functions and recomputes the cells that call them (and
    /// what reads those): before, such a call was `#NAME?`.
    pub fn set_user_functions(&mut self, functions: Rc<dyn UserFunctions>) {
        self.user_functions = Some(functions);
        let mut calling = Vec::new();
        for id in 0..self.cells.len() as u32 {
            let formula = self.cells[id as usize].formula;
            if formula == NO_FORMULA {
                continue;
            }
            let Some(volatile) = self.calls_user_function(&self.formulas.get(formula).expr) else { continue };
            if volatile {
                self.volatile.insert(id);
            }
            // The #NAME? the unknown call gave is no calculation of the formula: in a
            // circular reference the cell has no last calculated value to keep (0).
            if self.cells[id as usize].value == Value::Error(XlError::Name) {
                self.cells[id as usize].value = Value::Blank;
            }
            calling.push(id);
        }
        self.recalculate_from(calling);
    }

    /// Whether a cell may call `name` as one of the workbook's own functions.
    pub fn has_user_function(&self, name: &str) -> bool {
        self.user_functions.as_ref().is_some_and(|f| f.volatile(name).is_some())
    }

    /// Whether `expr` calls one of the workbook's own functions, and if so whether one of
    /// them is volatile.
    pub(super) fn calls_user_function(&self, expr: &Expr) -> Option<bool> {
        let functions = self.user_functions.as_ref()?;
        let mut found = None;
        expr.visit(&mut |e| {
            if let ExprKind::UnknownCall(name, _) = &e.kind {
                if let Some(v) = functions.volatile(name) {
                    found = Some(found.unwrap_or(false) | v);
                }
            }
        });
        found
    }

    pub(super) fn call_user(&self, cells: &dyn Env, call: &UserCall) -> Option<Result<Value, Note>> {
        let functions = self.user_functions.as_ref()?;
        functions.volatile(call.name)?;
        Some(functions.call(self, cells, call))
    }
}
