//! What goes wrong, said once: the command's [`Error`] (rendered by `main` after `ncsheet: `)
//! and the problems of a sheet's cells (printed on stderr while the command goes on).
//!
//! Messages are built from the inside out with [`prepend`], which keeps a formula's caret
//! line under the right character however much context is put in front of it.

use std::fmt;
use std::io;

use ncsheet::eval::{Env, Value, XlError};
use ncsheet::formula::ast::{ExprKind, SheetId, SheetRef};
use ncsheet::formula::{ParseError, Pos};
use ncsheet::workbook::Workbook;

/// Why a command failed.
#[derive(Debug)]
pub enum Error {
    /// Bad input: a missing or malformed file, a formula that does not parse, a cell off the
    /// sheet. Exit code 1.
    User(String),
    /// Arguments that do not fit together (beyond what clap checks). Exit code 2.
    Usage(String),
    /// Writing the output failed; a closed pipe (`ncsheet eval … | head`) is not reported.
    Output(io::Error),
}

impl Error {
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::User(_) | Error::Output(_) => 1,
            Error::Usage(_) => 2,
        }
    }

    pub fn is_broken_pipe(&self) -> bool {
        matches!(self, Error::Output(e) if e.kind() == io::ErrorKind::BrokenPipe)
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::User(m) | Error::Usage(m) => f.write_str(m),
            Error::Output(e) => write!(f, "cannot write the output: {e}"),
        }
    }
}

impl From<io::Error> for Error {
    fn from(e: io::Error) -> Error {
        Error::Output(e)
    }
}

impl From<ncsheet::io::Error> for Error {
    fn from(e: ncsheet::io::Error) -> Error {
        Error::User(e.to_string())
    }
}

pub type Result<T> = std::result::Result<T, Error>;

/// `context` before the first line of `message`; later lines are indented by its width, so
/// that a caret line stays under the formula it points into.
pub fn prepend(context: &str, message: &str) -> String {
    let indent = " ".repeat(context.chars().count());
    let mut out = String::with_capacity(context.len() + message.len());
    for (i, line) in message.split('\n').enumerate() {
        if i == 0 {
            out.push_str(context);
        } else {
            out.push('\n');
            out.push_str(&indent);
        }
        out.push_str(line);
    }
    out
}

/// One thing to tell a user about a cell: `Sheet1!B2: =1+*2` with a caret line.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct CellProblem {
    pub sheet: SheetId,
    pub row: u32,
    pub col: u32,
    pub message: String,
}

impl CellProblem {
    /// `Sheet1!B2: message`, indented for carets.
    pub fn render(&self, wb: &Workbook) -> String {
        prepend(&format!("{}: ", wb.cell_name(self.sheet, Pos::new(self.row, self.col))), &self.message)
    }
}

/// Everything wrong in a workbook: the workbook's own list (formulas that do not parse,
/// circular references, notes functions left) and the reasons behind `#NAME?` and `#REF!`
/// that it does not list (unknown functions, names and sheets).
pub fn problems(wb: &Workbook) -> Vec<CellProblem> {
    let mut out: Vec<CellProblem> = wb
        .problems()
        .into_iter()
        .map(|p| CellProblem { sheet: p.sheet, row: p.pos.row, col: p.pos.col, message: p.message })
        .collect();
    for sheet in 0..wb.sheet_len() as SheetId {
        for (pos, value) in wb.values(sheet) {
            if matches!(value, Value::Error(XlError::Name | XlError::Ref)) {
                out.extend(unknowns(wb, sheet, pos));
            }
        }
    }
    out.sort();
    out.dedup();
    out
}

/// Unknown functions, names and sheets in the formula of one cell, each with a caret.
pub fn unknowns(wb: &Workbook, sheet: SheetId, pos: Pos) -> Vec<CellProblem> {
    let mut out = Vec::new();
    if !wb.is_formula(sheet, pos) {
        return out;
    }
    let Some(text) = wb.formula(sheet, pos) else { return out };
    let Ok(expr) = wb.parse_at(&text, sheet, pos) else { return out };
    let local = local_names(&expr);
    let is_local = |name: &str| local.iter().any(|l| l.eq_ignore_ascii_case(name));
    expr.visit(&mut |e| {
        let message = match &e.kind {
            ExprKind::UnknownCall(name, _) if is_local(name) => return,
            ExprKind::UnknownCall(name, _) => format!("unknown function {name} (see `ncsheet functions`)"),
            ExprKind::Name(name) if is_local(name) => return,
            ExprKind::Name(name) if Env::defined_name(wb, name, sheet).is_none() => format!("unknown name {name}"),
            ExprKind::Ref(r) => match &r.sheet {
                SheetRef::Missing(name) => format!("no sheet named '{name}'"),
                _ => return,
            },
            _ => return,
        };
        let caret = ParseError { offset: e.span.start as usize, message };
        out.push(CellProblem { sheet, row: pos.row, col: pos.col, message: caret.render(&text) });
    });
    out
}

/// The names a formula binds itself: LET's names and LAMBDA's parameters. They are not
/// unknown, whatever the workbook defines.
fn local_names(expr: &ncsheet::formula::ast::Expr) -> Vec<std::rc::Rc<str>> {
    let mut names = Vec::new();
    expr.visit(&mut |e| {
        let ExprKind::Call(id, args) = &e.kind else { return };
        let bound: Vec<&ncsheet::formula::ast::Expr> = match ncsheet::eval::functions::spec(*id).name {
            "LET" => args.iter().step_by(2).take(args.len() / 2).collect(),
            "LAMBDA" => args.iter().take(args.len().saturating_sub(1)).collect(),
            _ => return,
        };
        names.extend(bound.into_iter().filter_map(|a| match &a.kind {
            ExprKind::Name(n) => Some(n.clone()),
            _ => None,
        }));
    });
    names
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn continuation_lines_are_indented_by_the_context() {
        assert_eq!(prepend("a.csv: ", "=1+*2\n   ^ here"), "a.csv: =1+*2\n          ^ here");
        assert_eq!(prepend("x: ", "one line"), "x: one line");
    }
}
