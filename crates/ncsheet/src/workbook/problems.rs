//! What a user should hear about a workbook's cells, as data: formulas that do not parse,
//! unknown functions, names and sheets, circular references, and the notes functions left
//! for their error values. Each [`Problem`] says its kind and, where it is in a formula, the
//! formula's text and the span in it, so that a front end renders it without parsing again.

use crate::eval::functions::{bound_names, Registry};
use crate::eval::{Env, Value, XlError};
use crate::formula::address::Pos;
use crate::formula::ast::{Expr, ExprKind, SheetId, SheetRef, Span};
use crate::formula::parse::ParseError;
use crate::formula::print::{print_locating, quote_sheet_name};

use super::Workbook;

/// Something wrong with a cell that a user should be told about.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    pub sheet: SheetId,
    pub pos: Pos,
    pub kind: ProblemKind,
    /// The formula `span` points into, with its `=` (as typed when it did not parse, else as
    /// the workbook prints it); empty for a problem of the cell as a whole.
    pub text: String,
    /// The bytes of `text` at fault (empty at a parse error's place).
    pub span: Option<Span>,
}

/// What is wrong.
#[derive(Clone, Debug, PartialEq)]
pub enum ProblemKind {
    /// The formula does not parse; the parser's message.
    Parse(String),
    UnknownFunction(String),
    UnknownName(String),
    MissingSheet(String),
    /// The cells of a circular reference, as `Sheet1!A1` names, starting with this one.
    Cycle(Vec<String>),
    /// The cycle starting at this cell stopped iterating at ncsheet's work budget after
    /// `rounds` of the `asked` rounds (`cycles::MAX_ITERATION_EVALUATIONS`).
    IterationCut {
        cells: usize,
        rounds: u32,
        asked: u32,
        limit: u64,
    },
    /// Why a function returned this error value.
    Note {
        error: XlError,
        message: String,
    },
}

impl Problem {
    /// The problem in words, without its place.
    pub fn message(&self) -> String {
        match &self.kind {
            ProblemKind::Parse(message) => message.clone(),
            ProblemKind::UnknownFunction(name) => format!("unknown function {name} (see `ncsheet functions`)"),
            ProblemKind::UnknownName(name) => format!("unknown name {name}"),
            ProblemKind::MissingSheet(name) => format!("no sheet named '{name}'"),
            ProblemKind::Cycle(cells) => format!("circular reference: {}", cycle_path(cells)),
            ProblemKind::Note { error, message } => format!("{error}: {message}"),
            ProblemKind::IterationCut { cells, rounds, asked, limit } => format!(
                "the iteration of this cycle of {cells} {} stopped after {rounds} of its {asked} rounds: \
                 ncsheet's limit of {limit} cell evaluations for the iterating cycles of one recalculation (rounds × \
                 cells, all cycles together, the work inside a cell counted too: {} array items made or read, \
                 or a LAMBDA call, as one evaluation) was reached before no value moved by more than the \
                 maximum change; the values are those of round {rounds}",
                if *cells == 1 { "cell" } else { "cells" },
                super::cycles::ITEMS_PER_EVALUATION
            ),
        }
    }

    /// The message, under the formula with a caret at the place when it is in one.
    pub fn render(&self) -> String {
        match self.span {
            Some(span) => ParseError { offset: span.start as usize, message: self.message() }.render(&self.text),
            None => self.message(),
        }
    }

    pub(super) fn parse(sheet: SheetId, pos: Pos, text: &str, error: &ParseError) -> Problem {
        let span = Some(Span { start: error.offset as u32, end: error.offset as u32 });
        Problem { sheet, pos, kind: ProblemKind::Parse(error.message.clone()), text: text.to_string(), span }
    }
}

/// The most cells a circular reference's message names: a cycle through a column of a
/// million cells was one line of 18.8 MB. Past it the first and last cells are named and
/// the count of those between.
const CYCLE_CELLS_NAMED: usize = 12;

/// `A1 -> B1 -> A1`, or for a long cycle `A1 -> … -> A9 -> (4,990 more cells) -> B5000`.
fn cycle_path(cells: &[String]) -> String {
    if cells.len() <= CYCLE_CELLS_NAMED {
        return cells.join(" -> ");
    }
    let (head, tail) = (CYCLE_CELLS_NAMED - 3, 3);
    let between = cells.len() - head - tail;
    format!(
        "{} -> ({between} more cells) -> {} ({} cells in all)",
        cells[..head].join(" -> "),
        cells[cells.len() - tail..].join(" -> "),
        cells.len()
    )
}

/// The rendering, without the cell's place.
impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.render())
    }
}

impl std::error::Error for Problem {}

impl Workbook {
    /// Everything a user should hear about, sorted by place: formulas that do not parse,
    /// the unknown functions, names and sheets behind a `#NAME?` or `#REF!`, circular
    /// references, and explanations functions gave for error values.
    pub fn problems(&self) -> Vec<Problem> {
        let mut out = Vec::new();
        for (&id, (text, err)) in &self.bad_inputs {
            let c = &self.cells[id as usize];
            out.push(Problem::parse(c.sheet, c.pos, text, err));
        }
        for cycle in self.cycles.iter() {
            out.push(self.cycle_problem(cycle));
        }
        for (&id, cut) in &self.iteration_cuts {
            let (sheet, pos) = (self.cells[id as usize].sheet, self.cells[id as usize].pos);
            let kind =
                ProblemKind::IterationCut { cells: cut.cells, rounds: cut.rounds, asked: cut.asked, limit: cut.limit };
            out.push(Problem { sheet, pos, kind, text: String::new(), span: None });
        }
        for &id in self.notes.keys() {
            out.extend(self.note_problems(id));
        }
        for sheet in 0..self.sheets.len() as SheetId {
            for (pos, value) in self.values(sheet) {
                if matches!(value, Value::Error(XlError::Name | XlError::Ref)) {
                    out.extend(self.unknowns(sheet, pos));
                }
            }
        }
        sort_by_place(&mut out);
        out
    }

    pub(super) fn cycle_problem(&self, cycle: &[u32]) -> Problem {
        let cell = |id: u32| &self.cells[id as usize];
        let names = cycle.iter().map(|&id| self.cell_name(cell(id).sheet, cell(id).pos)).collect();
        let first = cell(cycle[0]);
        Problem { sheet: first.sheet, pos: first.pos, kind: ProblemKind::Cycle(names), text: String::new(), span: None }
    }

    pub(super) fn note_problems(&self, id: u32) -> Vec<Problem> {
        let c = &self.cells[id as usize];
        let notes = self.notes.get(&id).map_or(&[][..], |n| &n[..]);
        notes
            .iter()
            .map(|n| Problem {
                sheet: c.sheet,
                pos: c.pos,
                kind: ProblemKind::Note { error: n.error, message: n.message.clone() },
                text: String::new(),
                span: None,
            })
            .collect()
    }

    /// Unknown functions, names and sheets in the formula of one cell, each with its span in
    /// the formula as printed.
    pub(super) fn unknowns(&self, sheet: SheetId, pos: Pos) -> Vec<Problem> {
        // Which names are unknown does not depend on the numbers: the shared tree tells.
        let Some(shared) = self.shared_formula_at(sheet, pos) else { return Vec::new() };
        let local = bound_names(&shared.expr);
        let unknown = |e: &Expr| -> Option<ProblemKind> {
            let is_local = |name: &str| local.iter().any(|l| l.eq_ignore_ascii_case(name));
            match &e.kind {
                ExprKind::UnknownCall(name, _) if !is_local(name) && !self.has_user_function(name) => {
                    Some(ProblemKind::UnknownFunction(name.to_string()))
                }
                ExprKind::Name(name) if !is_local(name) && Env::defined_name(self, name, sheet).is_none() => {
                    Some(ProblemKind::UnknownName(name.to_string()))
                }
                ExprKind::Ref(r) => match &r.sheet {
                    SheetRef::Missing(name) => Some(ProblemKind::MissingSheet(name.to_string())),
                    _ => None,
                },
                // `Data!Length`: a name of that sheet (or a workbook name) that is not defined.
                ExprKind::SheetName(SheetRef::Id(id), name) if Env::defined_name(self, name, *id).is_none() => {
                    let sheet_name = self.sheets.get(*id as usize).map_or("#REF", |s| s.name.as_str());
                    Some(ProblemKind::UnknownName(format!("{}!{name}", quote_sheet_name(sheet_name))))
                }
                ExprKind::SheetName(SheetRef::Current, name) if Env::defined_name(self, name, sheet).is_none() => {
                    Some(ProblemKind::UnknownName(name.to_string()))
                }
                ExprKind::SheetName(SheetRef::Missing(sheet_name), _) => {
                    Some(ProblemKind::MissingSheet(sheet_name.to_string()))
                }
                _ => None,
            }
        };
        let mut any = false;
        shared.expr.visit(&mut |e| any |= unknown(e).is_some());
        let Some(tree) = self.formula_tree(sheet, pos).filter(|_| any) else { return Vec::new() };
        let mut found = Vec::new();
        let sheets = |id: SheetId| self.sheets.get(id as usize).map_or_else(|| "#REF".into(), |s| s.name.clone());
        let printed = print_locating(&tree, pos, &Registry, &sheets, &mut |e, span| {
            if let Some(kind) = unknown(e) {
                // The printed text gets its `=` in front.
                found.push((kind, Span { start: span.start + 1, end: span.end + 1 }));
            }
        });
        let text = format!("={printed}");
        let problem = |(kind, span)| Problem { sheet, pos, kind, text: text.clone(), span: Some(span) };
        let mut out: Vec<Problem> = found.into_iter().map(problem).collect();
        out.sort_by_key(|p| p.span.map(|s| s.start));
        out
    }
}

/// Sorts by sheet, row, column and rendering, and drops repeats.
pub(super) fn sort_by_place(problems: &mut Vec<Problem>) {
    problems.sort_by_cached_key(|p| (p.sheet, p.pos.row, p.pos.col, p.render()));
    problems.dedup();
}
