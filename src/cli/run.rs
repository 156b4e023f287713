//! `ncsheet run`: a VBA-style macro on a workbook. Standard output carries only the NC program
//! (without `-o`), so `> p.ngc` is a program a control reads; what the macro prints
//! (`Debug.Print`), `MsgBox` and every message go to standard error.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use ncsheet::nc::{dialect, Machine};
use ncsheet::vba::{self, ErrorKind, RunOptions, RunOutput};

use super::cam::emit;
use super::report::{Error, Result};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum MachineKind {
    /// Z along the spindle, X a diameter, arcs in the ZX plane (G18)
    #[default]
    Lathe,
    /// X, Y, Z, arcs in the XY plane (G17)
    Mill,
}

/// Run a macro (.bas) on a workbook: it reads and writes cells and emits NC blocks.
///
/// The macro language is VBA as an Excel user writes it (Sub/Function, Dim, If/Select/For/Do,
/// GoTo labels, Range("B3").Value, Cells(r, c), [B3], every sheet function) plus an `Nc`
/// object for the program: Nc.Rapid, Nc.Line, Nc.ArcCW/ArcCCW, Nc.Dwell, Nc.Comment,
/// Nc.Block. A macro can touch no file and run no program; it stops with its line and a
/// caret after --max-statements statements or --max-depth nested calls.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The workbook the macro works on (.csv or .xlsx)
    pub workbook: PathBuf,
    /// The macro file
    #[arg(value_name = "MACRO.bas")]
    pub macro_file: PathBuf,
    /// The Sub to run (default: Main, or the first Sub without arguments)
    #[arg(long, value_name = "NAME")]
    pub sub: Option<String>,
    /// A value for one of the Sub's parameters, read as a cell reads what is typed
    #[arg(long = "arg", value_name = "NAME=VALUE", value_parser = parse_arg)]
    pub args: Vec<(String, String)>,
    /// Write the NC program in this dialect: iso, linuxcnc, sinumerik, heidenhain, nc31
    #[arg(long, default_value = "iso")]
    pub dialect: String,
    /// The machine the program is for, until the macro sets Nc.Machine
    #[arg(long, value_enum, default_value_t)]
    pub machine: MachineKind,
    /// Write the NC program here instead of standard output
    #[arg(short, long, value_name = "PROGRAM")]
    pub output: Option<PathBuf>,
    /// Save the workbook with the macro's changes (.csv or .xlsx; not the input file)
    #[arg(long, value_name = "OUT")]
    pub save: Option<PathBuf>,
    /// Stop the macro after this many statements (an endless loop, usually)
    #[arg(long, default_value_t = 10_000_000)]
    pub max_statements: u64,
    /// Stop the macro when calls nest deeper than this (endless recursion)
    #[arg(long, default_value_t = 100)]
    pub max_depth: usize,
    /// The sheet Range and Cells mean (default: the first)
    #[arg(long, value_name = "NAME")]
    pub sheet: Option<String>,
}

fn parse_arg(text: &str) -> std::result::Result<(String, String), String> {
    match text.split_once('=') {
        Some((name, value)) if !name.trim().is_empty() => Ok((name.trim().to_string(), value.to_string())),
        _ => Err(format!("'{text}' is not NAME=VALUE")),
    }
}

/// Deep recursion needs a deep stack: each nested macro call costs a few evaluator frames.
const STACK_BYTES_PER_LEVEL: usize = 64 * 1024;

pub fn run(args: RunArgs) -> Result<()> {
    if let Some(save) = &args.save {
        super::refuse_overwriting_input(&args.workbook, save, "save the changed workbook elsewhere")?;
    }
    let names = dialect::names().join(", ");
    let d = dialect::by_name(&args.dialect)
        .ok_or_else(|| Error::Usage(format!("unknown dialect '{}' (known: {names})", args.dialect)))?;
    let stack = (8 << 20).max(args.max_depth.saturating_mul(STACK_BYTES_PER_LEVEL));
    // The workbook is not Send, so it is loaded and used on the macro's own thread.
    let dialect_name = d.name();
    let worker = std::thread::Builder::new().stack_size(stack).spawn(move || run_on_this_thread(args, dialect_name));
    match worker {
        Ok(handle) => handle.join().unwrap_or_else(|_| Err(Error::User("the macro crashed".into()))),
        Err(e) => Err(Error::User(format!("cannot start the macro: {e}"))),
    }
}

fn run_on_this_thread(args: RunArgs, dialect_name: &'static str) -> Result<()> {
    let mut wb = ncsheet::io::load(&args.workbook)?;
    let formulas_before = if args.save.is_some() { formula_cells(&wb) } else { Vec::new() };
    let file = &args.macro_file;
    let source =
        std::fs::read_to_string(file).map_err(|e| Error::User(format!("{}: cannot read: {e}", file.display())))?;
    let options = RunOptions {
        sub: args.sub.clone(),
        args: args.args.clone(),
        max_statements: args.max_statements,
        max_depth: args.max_depth,
        sheet: args.sheet.clone(),
        dialect: Some(dialect_name.to_string()),
        machine: match args.machine {
            MachineKind::Lathe => Machine::Lathe,
            MachineKind::Mill => Machine::Mill,
        },
    };
    let out = match vba::run(&mut wb, &source, &file.display().to_string(), &options) {
        Ok(out) => out,
        Err(e) => {
            // What the macro printed before it stopped is still the user's.
            print_output(&e.output)?;
            return Err(match e.kind {
                ErrorKind::Usage => Error::Usage(e.to_string()),
                _ => Error::User(e.to_string()),
            });
        }
    };
    print_output(&out)?;
    if out.has_program() {
        let d = dialect::by_name(dialect_name).expect("dialect checked before");
        let text = d.render(&out.program).map_err(|e| Error::User(format!("{}: {e}", file.display())))?;
        emit(&text, args.output.as_deref())?;
    }
    if let Some(save) = &args.save {
        ncsheet::io::save(&wb, save)?;
        say_replaced_formulas(&wb, &formulas_before, save);
    }
    Ok(())
}

fn formula_cells(wb: &ncsheet::workbook::Workbook) -> Vec<(u16, ncsheet::formula::address::Pos)> {
    (0..wb.sheet_len() as u16)
        .flat_map(|s| wb.values(s).into_iter().filter(move |(p, _)| wb.is_formula(s, *p)).map(move |(p, _)| (s, p)))
        .collect()
}

/// A macro writing `Range(…).Value` over a formula cell leaves a constant there: the saved
/// workbook no longer recomputes that cell, which the user must hear.
fn say_replaced_formulas(
    wb: &ncsheet::workbook::Workbook,
    before: &[(u16, ncsheet::formula::address::Pos)],
    save: &std::path::Path,
) {
    let replaced: Vec<String> =
        before.iter().filter(|(s, p)| !wb.is_formula(*s, *p)).map(|&(s, p)| wb.cell_name(s, p)).collect();
    if replaced.is_empty() {
        return;
    }
    let shown = replaced.iter().take(8).cloned().collect::<Vec<_>>().join(", ");
    let more = if replaced.len() > 8 { format!(" and {} more", replaced.len() - 8) } else { String::new() };
    eprintln!(
        "ncsheet: {}: note: the macro wrote values over {} formula cells, saved as constants: {shown}{more}",
        save.display(),
        replaced.len()
    );
}

/// What the macro printed goes to stderr: a line above `%` would stop a control reading a
/// redirected program.
fn print_output(out: &RunOutput) -> Result<()> {
    for line in &out.printed {
        eprintln!("{line}");
    }
    for m in &out.messages {
        eprintln!("{m}");
    }
    Ok(())
}
