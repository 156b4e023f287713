//! The macro language: VBA's statements (`Sub`, `Dim`, `If`, `For`, `GoTo`, …) around the
//! formula language's expressions, run against a [`Workbook`] and filling an NC [`Program`].
//!
//! `parser.rs` turns the source into [`ast::Module`] through the one pest parser
//! (grammar/formula.pest + grammar/macro.pest); `interp.rs` walks the statements and hands
//! every expression to the one evaluator, which reads macro variables and macro-only nodes
//! (`Range("B3").Value`, calls of the module's Functions) through its `Host` hook.
//!
//! **Architecture Invariant:** a macro cannot reach files, programs or the system: the
//! language has no such statement or object (`Open`, `Kill`, `Shell`, `CreateObject` are
//! refused by the parser), and this module touches neither files nor stdout; [`run`] returns
//! what the macro printed and emitted, and the CLI decides where it goes.

pub mod ast;
mod interp;
mod objects;
pub mod parser;

use std::fmt;

use crate::nc::{Machine, Program};
use crate::workbook::Workbook;

pub use ast::{Module, Span};

/// How to run a macro.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// The Sub (or Function) to run; `None` runs `Main`, or else the first Sub that needs no
    /// arguments.
    pub sub: Option<String>,
    /// Arguments for its parameters, by name, as typed (`"40"`, `"outer"`, `"TRUE"`): read
    /// as a cell reads what is typed into it.
    pub args: Vec<(String, String)>,
    /// Stops the macro after this many statements and loop turns (an endless loop, usually).
    pub max_statements: u64,
    /// Stops the macro when procedure calls nest deeper than this (endless recursion).
    pub max_depth: usize,
    /// The sheet `Range`, `Cells` and `[B3]` mean before a macro activates another; `None`
    /// is the first sheet.
    pub sheet: Option<String>,
    /// The dialect the program will be written in, as `Nc.Dialect` tells the macro (`""`
    /// when none was chosen). Rendering is the caller's: see [`RunOutput::program`].
    pub dialect: Option<String>,
    /// The machine of the program until the macro sets `Nc.Machine`.
    pub machine: Machine,
}

impl Default for RunOptions {
    fn default() -> RunOptions {
        RunOptions {
            sub: None,
            args: Vec::new(),
            max_statements: 10_000_000,
            max_depth: 100,
            sheet: None,
            dialect: None,
            machine: Machine::Lathe,
        }
    }
}

/// What a macro produced. Cell writes are already in the workbook.
#[derive(Clone, Debug, PartialEq)]
pub struct RunOutput {
    /// `Debug.Print` lines, for standard output.
    pub printed: Vec<String>,
    /// `MsgBox` texts, for standard error.
    pub messages: Vec<String>,
    /// The NC program the macro emitted with `Nc.*` (empty when it emitted none); write it
    /// with `nc::by_name(dialect)?.render(&program)`.
    pub program: Program,
}

impl RunOutput {
    fn new(name: &str, machine: Machine) -> RunOutput {
        RunOutput { printed: Vec::new(), messages: Vec::new(), program: Program::new(name, machine) }
    }

    pub fn has_program(&self) -> bool {
        !self.program.blocks.is_empty()
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// The source does not parse, or names something the language does not have.
    Syntax,
    /// A statement failed while running.
    Runtime,
    /// The statement or recursion limit stopped the macro.
    Limit,
    /// The run was asked for something the module does not have (`--sub`, `--arg`).
    Usage,
}

/// Why a macro did not run to its end: where (file, line, column, the source line for a
/// caret), what, and which procedures were running.
#[derive(Clone, Debug, PartialEq)]
pub struct MacroError {
    pub kind: ErrorKind,
    pub file: String,
    pub span: Option<Span>,
    pub message: String,
    /// The source line at `span`.
    pub source_line: String,
    /// Innermost first: `in Function Area (called at line 12, column 5)`, `in Sub Main`.
    pub trace: Vec<String>,
    /// What the macro printed and emitted before it stopped.
    pub output: Box<RunOutput>,
}

/// Renders as a compiler does:
///
/// ```text
/// chamfer.bas:14:13: error: Nc.Line: X is #DIV/0!
///    14 |     Nc.Line x / 0, z
///       |             ^
///   in Sub Cut (called at line 3, column 5)
///   in Sub Main
/// ```
impl fmt::Display for MacroError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = match self.kind {
            ErrorKind::Syntax => "syntax error",
            ErrorKind::Runtime | ErrorKind::Usage => "error",
            ErrorKind::Limit => "stopped",
        };
        let Some(span) = self.span else {
            return write!(f, "{}: {kind}: {}", self.file, self.message);
        };
        write!(f, "{}:{}:{}: {kind}: {}", self.file, span.line, span.col, self.message)?;
        let number = span.line.to_string();
        let pad = " ".repeat(number.len());
        // The caret lines up under tabs too: copy the line's own whitespace up to the column.
        let lead: String =
            self.source_line.chars().take(span.col as usize - 1).map(|c| if c == '\t' { '\t' } else { ' ' }).collect();
        write!(f, "\n {number} | {}\n {pad} | {lead}^", self.source_line)?;
        for t in &self.trace {
            write!(f, "\n  {t}")?;
        }
        Ok(())
    }
}

impl std::error::Error for MacroError {}

/// Parses a module without running it (for listing its Subs, or checking it). `workbook`
/// resolves sheet names in `[Sheet2!A1]` brackets.
pub fn parse(source: &str, file_name: &str, workbook: &Workbook) -> Result<Module, MacroError> {
    parser::parse_module(source, &|n| workbook.sheet_id(n)).map_err(|e| {
        let lines = parser::Lines::new(source);
        let span = lines.span(source, e.offset);
        MacroError {
            kind: ErrorKind::Syntax,
            file: file_name.to_string(),
            span: Some(span),
            message: e.message,
            source_line: lines.text(source, span.line).to_string(),
            trace: Vec::new(),
            output: Box::new(RunOutput::new("", Machine::Lathe)),
        }
    })
}

/// Runs a macro: parses `source` (named `file_name` in messages), runs the Sub chosen by
/// `options` against `workbook` (cell writes stay in it), and returns what the macro printed
/// and the NC program it emitted.
pub fn run(
    workbook: &mut Workbook,
    source: &str,
    file_name: &str,
    options: &RunOptions,
) -> Result<RunOutput, MacroError> {
    let module = parse(source, file_name, workbook)?;
    interp::run(&module, workbook, source, file_name, options)
}
