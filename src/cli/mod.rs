//! The command line: clap types, whose doc comments are the help text, and one function per
//! subcommand. The only layer that prints; `main` renders a failed command's [`Error`] once
//! and picks the exit code (0 success, 1 bad input, 2 bad usage).

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use clap::{ArgGroup, Args, Parser, Subcommand};
use ncsheet::document::{Document, OpenOptions};
use ncsheet::eval::functions::REGISTRY;
use ncsheet::formula::address::Pos;
use ncsheet::formula::ast::SheetId;
use ncsheet::io::{Content, Export, ExportOptions};
use ncsheet::workbook::Workbook;

mod ballpath;
mod cam;
mod help;
mod hints;
mod info;
mod limits;
pub mod locale;
mod macro_files;
mod macros;
mod nc;
mod nc_check;
mod nc_plot;
mod output;
mod post;
mod repl;
pub mod report;
mod run;
mod serve;
mod show;
mod target;

use output::{OutputFormat, Selection, Shown};
use report::{prepend, Error, Result};
use target::{parse_assignment, parse_target, Assignment, Target};

/// A spreadsheet formula engine for CNC programming: compute, edit and export sheets.
///
/// A csv file is one sheet named Sheet1. A field starting with `=` is a formula; anything
/// else is read as a spreadsheet reads it (number, TRUE/FALSE, error like #N/A, or text; a
/// leading ' forces text).
#[derive(Debug, Parser)]
#[command(name = "ncsheet", version, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

impl Cli {
    /// Reads the command line, with the commands listed in their groups in `ncsheet --help`.
    pub fn try_parse_grouped() -> std::result::Result<Cli, clap::Error> {
        use clap::{CommandFactory, FromArgMatches};
        let command = help::grouped(Cli::command());
        Cli::from_arg_matches(&command.try_get_matches()?)
    }
}

/// How the commands that read workbooks read them: the csv separator, the locale, and the
/// limits on what a file may make ncsheet hold.
#[derive(Debug, Default, Args)]
#[command(next_help_heading = "Reading workbooks")]
pub struct WorkbookOptions {
    /// The field separator of csv files read, and of a csv saved from a workbook: `,`, `;` or
    /// `tab` (default: detected from the first lines; a csv keeps its own). With `;` numbers
    /// have a decimal comma (0,8) and formulas `;` between arguments (=ROUND(A1*0,5;2)), as
    /// spreadsheets in such locales write them
    #[arg(long, value_name = "CHAR", value_parser = parse_delimiter)]
    pub delimiter: Option<u8>,
    /// The locale numbers, dates and formulas are typed and shown in, and text is read as
    /// numbers in while formulas compute, as that locale's Excel does: en-US, de-DE, fr-FR,
    /// et-EE, uk-UA, sk-SK, sr-RS, hu-HU (default: LC_ALL, LC_NUMERIC or LANG; en-US when
    /// none names one). Files stay as Excel stores them
    #[arg(long, value_name = "TAG", value_parser = locale::parse_locale)]
    pub locale: Option<ncsheet::eval::Locale>,
    #[command(flatten)]
    pub limits: limits::ReadLimitArgs,
}

fn parse_delimiter(text: &str) -> std::result::Result<u8, String> {
    match text {
        "," => Ok(b','),
        ";" => Ok(b';'),
        "tab" | "\\t" | "\t" => Ok(b'\t'),
        other => Err(format!("'{other}' is not a csv delimiter ncsheet writes: use ',', ';' or tab")),
    }
}

#[derive(Debug, Subcommand)]
pub enum Command {
    Eval(EvalArgs),
    Set(SetArgs),
    Export(ExportArgs),
    Repl(ReplArgs),
    Functions(FunctionsArgs),
    Cam(cam::CamArgs),
    Arcfit(cam::ArcfitArgs),
    // Boxed: the run command's options are by far the largest (clippy::large_enum_variant).
    Run(Box<run::RunArgs>),
    Ballpath(ballpath::BallpathArgs),
    Macros(macros::MacrosArgs),
    Show(show::ShowArgs),
    Info(info::InfoArgs),
    Nc(nc::NcArgs),
    Post(post::PostArgs),
    Serve(serve::ServeArgs),
}

/// Compute a sheet and print its values (all of it, or the cells and ranges named).
///
/// Cells whose formula is broken hold an error value (#NAME?, #REF!, #CIRC!, …) and are
/// explained on stderr, e.g. `ncsheet: parts.csv: Sheet1!B2: =1+*2` with a caret under the
/// fault; the other cells compute and print, and the exit code stays 0, because an error
/// value is a value. A file that cannot be read is exit code 1.
#[derive(Debug, Args)]
pub struct EvalArgs {
    /// The workbook (.csv, .xlsx, .xlsm)
    pub file: PathBuf,
    /// Cells, ranges or defined names to print: B3, A1:D20, Sheet1!B3, XA (default: the
    /// whole sheet)
    #[arg(value_name = "CELL|RANGE", value_parser = parse_target)]
    pub cells: Vec<Target>,
    /// The sheet to print (default: the active one, where the file opens)
    #[arg(long, value_name = "NAME")]
    pub sheet: Option<String>,
    /// How to print the values
    #[arg(long, value_enum, default_value_t)]
    pub format: OutputFormat,
    /// Instead of the values, list every cell whose recomputed value differs from the one
    /// Excel stored in the file (.xlsx), with both values; exit code 1 when any differs
    #[arg(long, conflicts_with = "cells")]
    pub check: bool,
    /// Numbers in full precision instead of as the cell's number format shows them
    #[arg(long)]
    pub raw: bool,
    /// Show formulas (as typed) instead of their values; constants as they are
    #[arg(long)]
    pub formulas: bool,
    /// Fit tables in this many columns: the columns that do not fit come below, in further
    /// tables; numbers keep every digit (default: the terminal's width; no limit when the
    /// output is not a terminal)
    #[arg(long, value_name = "N")]
    pub width: Option<usize>,
    #[command(flatten)]
    pub timeout: limits::TimeoutArg,
    #[command(flatten)]
    pub reading: WorkbookOptions,
}

/// Set cells, recalculate and save the workbook.
///
/// Each CELL=INPUT is typed into the cell as into a spreadsheet: `B3=45`, `B3==A1*2` (a
/// formula), `B3=` (empties it). Quote it for the shell: 'B3==A1*2'. A formula that does not
/// parse is refused and nothing is written. The save goes to a temporary file renamed over
/// the target, so the target is never left half-written; the input file is only replaced
/// with --in-place.
#[derive(Debug, Args)]
#[command(group(ArgGroup::new("destination").required(true).args(["output", "in_place"])))]
pub struct SetArgs {
    /// The workbook (.csv, .xlsx, .xlsm)
    pub file: PathBuf,
    /// What to type into which cell (or defined name: alpha=30)
    #[arg(value_name = "CELL=INPUT", required = true, value_parser = parse_assignment)]
    pub assignments: Vec<Assignment>,
    /// Write the result here (must not be FILE; see --in-place)
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// Replace FILE with the result
    #[arg(long)]
    pub in_place: bool,
    /// Replace a read-only or hard-linked target, and with --in-place a workbook whose save
    /// loses something (what is lost is said first)
    #[arg(long)]
    pub force: bool,
    /// The sheet of cells named without one (default: the active one, where the file opens)
    #[arg(long, value_name = "NAME")]
    pub sheet: Option<String>,
    #[command(flatten)]
    pub timeout: limits::TimeoutArg,
    #[command(flatten)]
    pub reading: WorkbookOptions,
}

/// Write a sheet's values (or formulas) to a csv file.
///
/// The csv is a table of the sheet from A1 (or of --range) to its last used row and column,
/// quoted per RFC 4180. Values are written as their cells' number formats show them (15
/// significant digits without one; --raw: in full). Text that a
/// spreadsheet could run as a formula (starting with = + - @) or read as something else
/// (12, TRUE, #N/A) is written with a leading ', which spreadsheets show as text and ncsheet
/// reads back as the original text. With --formulas, each cell is written as typed: formulas
/// as =… text, so the file loads back as the same sheet.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The workbook (.csv, .xlsx, .xlsm)
    pub file: PathBuf,
    /// The csv file to write (must not be FILE)
    #[arg(short, long, value_name = "OUT.csv")]
    pub output: PathBuf,
    /// Only these cells, e.g. A1:D20, Sheet1!A1:D20 or a defined name
    #[arg(long, value_name = "RANGE", value_parser = parse_target)]
    pub range: Option<Target>,
    /// Write formulas as =… text instead of their values
    #[arg(long)]
    pub formulas: bool,
    /// Numbers in full precision instead of as the cell's number format shows them
    #[arg(long)]
    pub raw: bool,
    /// The field separator of the csv written: `,`, `;` (numbers then get a decimal comma)
    /// or `tab` (default: the input csv's, else --delimiter's, else `,`)
    #[arg(long, value_name = "CHAR", value_parser = parse_delimiter)]
    pub output_delimiter: Option<u8>,
    /// The sheet to write (default: the active one, where the file opens)
    #[arg(long, value_name = "NAME")]
    pub sheet: Option<String>,
    /// Replace a read-only or hard-linked OUT
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub timeout: limits::TimeoutArg,
    #[command(flatten)]
    pub reading: WorkbookOptions,
}

/// Edit a workbook interactively: CELL=INPUT, CELL or RANGE, save PATH, quit.
///
/// With a terminal there is a prompt and line editing; piped input is read line by line
/// without a prompt. Values print on stdout, problems on stderr. Piped, the exit code is 1
/// when any command failed.
#[derive(Debug, Args)]
pub struct ReplArgs {
    /// The workbook (.csv, .xlsx, .xlsm)
    pub file: PathBuf,
    /// Print time_s=<seconds> to stderr after each command
    #[arg(long)]
    pub timings: bool,
    /// The sheet of cells named without one (default: the active one, where the file opens)
    #[arg(long, value_name = "NAME")]
    pub sheet: Option<String>,
    #[command(flatten)]
    pub timeout: limits::TimeoutArg,
    #[command(flatten)]
    pub reading: WorkbookOptions,
}

/// List every sheet function with its signature and a one-line summary.
#[derive(Debug, Args)]
pub struct FunctionsArgs {
    /// Only functions whose name contains one of these (case-insensitive): `functions TAN`
    #[arg(value_name = "NAME")]
    pub filter: Vec<String>,
}

impl Command {
    /// How this command reads workbooks, when it reads any.
    fn reading(&self) -> Option<&WorkbookOptions> {
        match self {
            Command::Eval(args) => Some(&args.reading),
            Command::Set(args) => Some(&args.reading),
            Command::Export(args) => Some(&args.reading),
            Command::Repl(args) => Some(&args.reading),
            Command::Run(args) => Some(&args.reading),
            Command::Show(args) => Some(&args.reading),
            Command::Info(args) => Some(&args.reading),
            Command::Serve(args) => Some(&args.reading),
            _ => None,
        }
    }

    /// The `--timeout` of this command, when it does work a timeout could stop (listing the
    /// functions does not).
    fn timeout(&self) -> Option<&limits::TimeoutArg> {
        match self {
            Command::Eval(args) => Some(&args.timeout),
            Command::Set(args) => Some(&args.timeout),
            Command::Export(args) => Some(&args.timeout),
            Command::Repl(args) => Some(&args.timeout),
            Command::Functions(_) => None,
            Command::Cam(args) => Some(&args.timeout),
            Command::Arcfit(args) => Some(&args.timeout),
            Command::Run(args) => Some(&args.timeout),
            Command::Ballpath(args) => Some(&args.timeout),
            Command::Macros(args) => Some(&args.timeout),
            Command::Show(args) => Some(&args.timeout),
            Command::Info(args) => Some(&args.timeout),
            Command::Nc(args) => Some(&args.timeout),
            Command::Post(args) => Some(&args.timeout),
            // The server bounds each request by it (`serve::run`), never its own life.
            Command::Serve(_) => None,
        }
    }

    /// The limits on the files this command reads: a workbook's, or the macros command's.
    fn read_limits(&self) -> Option<&limits::ReadLimitArgs> {
        match self {
            Command::Macros(args) => Some(&args.limits),
            _ => self.reading().map(|reading| &reading.limits),
        }
    }
}

pub fn run(cli: Cli) -> Result<()> {
    if let Some(timeout) = cli.command.timeout() {
        timeout.apply();
    }
    cli.command.read_limits().unwrap_or(&limits::ReadLimitArgs::default()).apply();
    let reading = cli.command.reading();
    locale::apply(reading.and_then(|r| r.locale));
    let delimiter = reading.and_then(|r| r.delimiter);
    match cli.command {
        Command::Eval(args) => eval(args, delimiter),
        Command::Set(args) => set(args, delimiter),
        Command::Export(args) => export(args, delimiter),
        Command::Repl(args) => repl(args, delimiter),
        Command::Functions(args) => functions(args),
        Command::Cam(args) => cam::cam(args),
        Command::Arcfit(args) => cam::arcfit(args),
        Command::Run(args) => run::run(*args, delimiter),
        Command::Ballpath(args) => ballpath::run(args),
        Command::Macros(args) => macros::run(args),
        Command::Show(args) => show::run(args, delimiter),
        Command::Info(args) => info::run(args, delimiter),
        Command::Nc(args) => nc::run(args),
        Command::Post(args) => post::run(args),
        Command::Serve(args) => serve::run(args, delimiter),
    }
}

fn eval(args: EvalArgs, delimiter: Option<u8>) -> Result<()> {
    let doc = open(&args.file, delimiter)?;
    if args.check {
        return check(&args.file, &doc);
    }
    let wb = doc.workbook();
    let sheet = default_sheet(wb, &args.file, args.sheet.as_deref())?;
    let selections = args.cells.iter().map(|t| locate(wb, &args.file, t, sheet)).collect::<Result<Vec<_>>>()?;
    let shown = Shown {
        layout: doc.layout(),
        raw: args.raw,
        formulas: args.formulas,
        width: args.width.or_else(output::terminal_width),
        parsed: Default::default(),
    };
    refuse_huge_prints(wb, sheet, &selections)?;
    let mut out = BufWriter::new(io::stdout().lock());
    if selections.is_empty() {
        output::print_sheet(&mut out, wb, sheet, args.format, &shown)?;
    } else {
        output::print_selections(&mut out, wb, sheet, &selections, args.format, &shown)?;
    }
    out.flush()?;
    report_problems(&args.file, wb);
    Ok(())
}

/// The most cells `eval` prints at once: a printed range is held whole before it is laid
/// out, blanks included, so `A1:XFD1048576` (17 billion cells) must be refused, not tried.
const MAX_PRINTED_CELLS: u64 = 10_000_000;

fn refuse_huge_prints(wb: &Workbook, sheet: SheetId, selections: &[Selection]) -> Result<()> {
    let whole = wb.used_rect(sheet).map(|used| ncsheet::formula::address::Rect::new(Pos::new(0, 0), used.last));
    let rects: Vec<_> =
        if selections.is_empty() { whole.into_iter().collect() } else { selections.iter().map(|s| s.rect).collect() };
    let cells: u64 = rects.iter().map(|r| r.rows() as u64 * r.cols() as u64).sum();
    if cells <= MAX_PRINTED_CELLS {
        return Ok(());
    }
    let what = match rects.as_slice() {
        [one] => format!("{one} is {cells} cells"),
        _ => format!("the ranges are {cells} cells"),
    };
    Err(Error::User(format!(
        "{what}, more than the {MAX_PRINTED_CELLS} ncsheet prints at once; name a smaller range (blank cells print too)"
    )))
}

fn set(args: SetArgs, delimiter: Option<u8>) -> Result<()> {
    let out_path = match (&args.output, args.in_place) {
        (Some(out), false) => {
            let hint = "write elsewhere with -o, or replace it with --in-place";
            refuse_overwriting_inputs(&[&args.file], &[out], hint)?;
            out.clone()
        }
        (None, true) => args.file.clone(),
        // clap's argument group makes exactly one of them required.
        _ => return Err(Error::Usage("give either -o OUT or --in-place".into())),
    };
    let lock = if args.in_place { lock_for_edit(&args.file)? } else { None };
    let mut doc = open(&args.file, delimiter)?;
    let wb = doc.workbook_mut();
    let sheet = default_sheet(wb, &args.file, args.sheet.as_deref())?;
    let mut done = Vec::new();
    for a in &args.assignments {
        let (cell_sheet, pos) = locate_cell(wb, &args.file, &a.target, sheet)?;
        let input = wb.typed_input(&a.input).map_err(|why| {
            Error::User(format!(
                "{}: {}: {why}; nothing was written",
                args.file.display(),
                wb.cell_name(cell_sheet, pos)
            ))
        })?;
        // The one edit path of every front end (`Workbook::set_input`): it recalculates what
        // depends on the cell and, on a table's header, renames the column as Excel does.
        let input = input.into_owned();
        wb.set_input(cell_sheet, pos, &input).map_err(|p| in_file(&args.file, Error::User(report::render(wb, &p))))?;
        if let Some(doubt) = hints::doubt_about(wb, cell_sheet, pos, &input) {
            eprintln!("ncsheet: {}: {}: warning: {doubt}", args.file.display(), wb.cell_name(cell_sheet, pos));
        }
        done.push((cell_sheet, pos, a.input.clone()));
    }
    // A date or time typed in the locale shows as Excel shows it (the cell's format).
    let formats: Vec<Option<&str>> = done.iter().map(|(s, p, typed)| doc.typed_into(*s, *p, typed)).collect();
    report_problems(&args.file, doc.workbook());
    let encoded = doc.encode(&out_path)?;
    if let Some(lock) = &lock {
        lock.unchanged().map_err(|e| Error::User(format!("{}: {e}", args.file.display())))?;
    }
    write_outputs(&[encoded], args.in_place, args.force)?;
    drop(lock);
    let wb = doc.workbook();
    // What was done, on stderr: stdout stays empty for scripts.
    let locale = wb.settings().locale;
    for ((cell_sheet, pos, _), code) in done.into_iter().zip(formats) {
        let value = match wb.value(cell_sheet, pos) {
            ncsheet::eval::Value::Number(n) => locale.shown_number(n, code, wb.date_system()),
            v => locale.shown_value(&v),
        };
        eprintln!("{} = {value}", wb.cell_name(cell_sheet, pos));
    }
    eprintln!("saved {}", out_path.display());
    Ok(())
}

/// Holds `file` for an in-place edit until it is saved (see `EditLock`): other edits of it
/// wait, and a change by a program that does not lock is refused at the save. A file that
/// cannot be opened is left for the reading to report.
fn lock_for_edit(file: &Path) -> Result<Option<ncsheet::io::atomic::EditLock>> {
    match ncsheet::io::atomic::EditLock::acquire(file) {
        Ok(lock) => Ok(Some(lock)),
        Err(e) if e.kind() == io::ErrorKind::NotFound || e.kind() == io::ErrorKind::PermissionDenied => Ok(None),
        Err(e) => Err(Error::User(format!("{}: cannot lock it for --in-place: {e}", file.display()))),
    }
}

/// Reads a workbook (a csv with `--delimiter`'s separator, if given) and tells the user
/// what the import left out.
fn open(file: &Path, delimiter: Option<u8>) -> Result<Document> {
    let doc = Document::open_file(file, &open_options(delimiter))?;
    for note in doc.notes() {
        eprintln!("ncsheet: {}: note: {note}", file.display());
    }
    if let Some(said) = locale::csv_reading(&doc, delimiter) {
        eprintln!("ncsheet: {}: note: {said}", file.display());
    }
    Ok(doc)
}

/// How every command opens a workbook: the workbook's own functions run under `--timeout`.
pub(crate) fn open_options(delimiter: Option<u8>) -> OpenOptions {
    let functions = ncsheet::vba::RunOptions { deadline: limits::deadline(), ..Default::default() };
    let locale = locale::in_force().locale;
    // Under en-US the default settings hold: no second recalculation at opening.
    let settings = (!locale.is_canonical()).then(|| {
        let mut settings = ncsheet::eval::Settings::default();
        settings.locale = locale;
        settings
    });
    OpenOptions {
        csv_delimiter: delimiter,
        functions,
        settings,
        read_limits: limits::read_limits(),
        ..OpenOptions::default()
    }
}

/// Whose values a workbook stores, as `eval --check` names them, and, when they are not
/// Excel's, why.
fn stored_by(doc: &Document) -> (String, Option<String>) {
    let full_calc = doc.layout().is_some_and(|l| l.calculation.full_calc_on_load);
    match doc.written_by() {
        Some(ncsheet::io::xlsx::WRITTEN_BY) => (
            "the values ncsheet stored in it".into(),
            Some("ncsheet wrote this file, so its stored values are not Excel's".into()),
        ),
        _ if full_calc => (
            "the values stored in it".into(),
            Some(
                "the file asks to be recalculated when opened (fullCalcOnLoad, as ncsheet's save of an edited \
                 workbook does), so its stored values are not Excel's results"
                    .into(),
            ),
        ),
        Some(app) if app.contains("Excel") && !app.contains("Compatible") => ("Excel".into(), None),
        Some(app) => {
            let name = app.split('/').next().unwrap_or(app).trim();
            (
                format!("the values {name} stored in it"),
                Some(format!("{name} saved this file, so its stored values are not Excel's")),
            )
        }
        None => {
            ("the values stored in it".into(), Some("the file does not name the program that stored its values".into()))
        }
    }
}

/// `eval --check`: every cell where ncsheet and Excel's stored value disagree.
fn check(file: &Path, doc: &Document) -> Result<()> {
    let wb = doc.workbook();
    let differences = ncsheet::io::xlsx::compare_cached(wb, doc.cached());
    // A file another program saved caches that program's results: agreeing with them says
    // nothing of Excel.
    let (whose, not_excel) = stored_by(doc);
    let stored = if not_excel.is_some() { "stored" } else { "Excel" };
    let mut out = BufWriter::new(io::stdout().lock());
    for d in &differences {
        let formula = d.formula.as_deref().unwrap_or("");
        let volatile = if d.volatile { " (volatile: expected to differ)" } else { "" };
        writeln!(
            out,
            "{}: {formula}: {stored} {}, ncsheet {}{volatile}",
            wb.cell_name(d.sheet, d.pos),
            show(&d.excel),
            show(&d.ncsheet)
        )?;
    }
    out.flush()?;
    let compared = doc.cached().len();
    if doc.layout().is_none() {
        eprintln!("ncsheet: {}: a csv file stores no computed values to check against", file.display());
        return Ok(());
    }
    let real = differences.iter().filter(|d| !d.volatile).count();
    let agree = compared - differences.len();
    eprintln!("ncsheet: {}: {agree} of {compared} stored values agree with {whose}", file.display());
    if let Some(why) = not_excel {
        eprintln!("ncsheet: {}: note: {why}", file.display());
    }
    if real > 0 {
        return Err(Error::User(format!("{}: {real} cells differ from {whose}", file.display())));
    }
    Ok(())
}

/// A value for a message: text quoted, so that "12" and 12 read apart.
fn show(v: &ncsheet::eval::Value) -> String {
    match v {
        ncsheet::eval::Value::Text(t) => format!("{t:?}"),
        ncsheet::eval::Value::Blank => "(blank)".into(),
        other => other.to_string(),
    }
}

fn export(args: ExportArgs, delimiter: Option<u8>) -> Result<()> {
    refuse_overwriting_inputs(&[&args.file], &[&args.output], "an export cannot replace its input; write elsewhere")?;
    let doc = open(&args.file, delimiter)?;
    let wb = doc.workbook();
    let mut sheet = default_sheet(wb, &args.file, args.sheet.as_deref())?;
    let mut range = None;
    if let Some(t) = &args.range {
        let selection = locate(wb, &args.file, t, sheet)?;
        (sheet, range) = (selection.sheet, Some(selection.rect));
    }
    let content = if args.formulas { Content::Formulas } else { Content::Values };
    let what = Export { sheet, range, content };
    report_problems(&args.file, wb);
    let read_with = match doc.origin() {
        ncsheet::io::Origin::Csv(original) => Some(original.delimiter()),
        _ => None,
    };
    // A decimal-comma locale's Excel writes `;` and decimal commas.
    let by_locale = (!wb.settings().locale.is_canonical()).then_some(b';');
    let delimiter = args.output_delimiter.or(read_with).or(delimiter).or(by_locale);
    let options = ExportOptions { delimiter, layout: doc.layout(), raw: args.raw };
    let encoded = ncsheet::io::encode_export_with(wb, &args.output, &what, &options)?;
    write_outputs(&[encoded], false, args.force)
}

fn repl(args: ReplArgs, delimiter: Option<u8>) -> Result<()> {
    let opened = open(&args.file, delimiter)?.into_opened();
    let sheet = default_sheet(&opened.workbook, &args.file, args.sheet.as_deref())?;
    report_problems(&args.file, &opened.workbook);
    repl::run(&args.file, opened, sheet, args.timings, delimiter)
}

fn functions(args: FunctionsArgs) -> Result<()> {
    let wanted = |name: &str| {
        args.filter.is_empty()
            || args.filter.iter().any(|f| name.to_ascii_uppercase().contains(&f.to_ascii_uppercase()))
    };
    let mut specs: Vec<_> = REGISTRY.iter().filter(|f| wanted(f.name)).collect();
    if specs.is_empty() {
        return Err(Error::User(format!("no function name contains {}", args.filter.join(" or "))));
    }
    specs.sort_by_key(|f| f.name);
    let width = specs.iter().map(|f| f.signature.chars().count()).max().unwrap_or(0);
    let mut out = BufWriter::new(io::stdout().lock());
    for f in specs {
        writeln!(out, "{:width$}  {}", f.signature, f.summary)?;
    }
    out.flush()?;
    Ok(())
}

/// Prints the problems of the workbook's cells on stderr: `ncsheet: FILE: Sheet1!B2: …`.
fn report_problems(file: &Path, wb: &Workbook) {
    let context = format!("ncsheet: {}: ", file.display());
    report::print_capped(&context, wb, wb.problems(), locale::foreign_numbers(wb));
}

fn in_file(file: &Path, e: Error) -> Error {
    match e {
        Error::User(m) => Error::User(prepend(&format!("{}: ", file.display()), &m)),
        e => e,
    }
}

/// `--sheet NAME`, or the active sheet (the one the file opens on, as in Excel).
fn default_sheet(wb: &Workbook, file: &Path, name: Option<&str>) -> Result<SheetId> {
    match name {
        Some(name) => sheet_named(wb, file, name),
        None => Ok(wb.active_sheet()),
    }
}

fn target_sheet(wb: &Workbook, file: &Path, target: &Target, default: SheetId) -> Result<SheetId> {
    match &target.sheet {
        Some(name) => sheet_named(wb, file, name),
        None => Ok(default),
    }
}

/// Where a cell argument points: its sheet and rectangle, a defined name resolved.
pub(crate) fn locate(wb: &Workbook, file: &Path, target: &Target, default: SheetId) -> Result<Selection> {
    let sheet = target_sheet(wb, file, target, default)?;
    let Some(name) = &target.name else { return Ok(Selection { sheet, rect: target.rect, label: None }) };
    let scopes = sheets_scoping(wb, name);
    let seen_from = match (wb.name_reference(name, sheet), scopes.as_slice()) {
        (Some(found), _) => Some(found),
        // A name only one other sheet defines means that sheet's (chamfer.xlsx: alpha of Outer).
        (None, [only]) if target.sheet.is_none() => wb.name_reference(name, *only),
        (None, [_, _, ..]) if target.sheet.is_none() => {
            let names = wb.sheet_names();
            let listed: Vec<&str> = scopes.iter().map(|s| names[*s as usize].as_str()).collect();
            let first = listed[0];
            return Err(Error::User(format!(
                "{}: {name} is defined for each of the sheets {} apart: say which, as {first}!{name} or --sheet {first}",
                file.display(),
                listed.join(", ")
            )));
        }
        _ => None,
    };
    match seen_from {
        Some((sheet, rect)) => Ok(Selection { sheet, rect, label: Some(name.clone()) }),
        None => {
            let mut known = wb.names().into_iter().map(|(n, _, _)| n).collect::<Vec<_>>();
            known.dedup();
            let known = if known.is_empty() {
                "it has no defined names".to_string()
            } else {
                format!("it has: {}", known.join(", "))
            };
            let what = if wb.names().iter().any(|(n, _, _)| n.eq_ignore_ascii_case(name)) {
                format!("the name {name} is not a cell or range")
            } else if let Some(past) = past_the_sheet(name) {
                format!("{name} is {past}, and no defined name either ({known})")
            } else {
                format!("no cell, range or defined name {name} ({known})")
            };
            Err(Error::User(format!("{}: {what}", file.display())))
        }
    }
}

/// Why a name shaped like a cell address (letters, then digits) is none: its column is past
/// XFD or its row past 1,048,576, Excel's last.
fn past_the_sheet(name: &str) -> Option<String> {
    let split = name.find(|c: char| c.is_ascii_digit())?;
    let (letters, digits) = name.split_at(split);
    let shaped = !letters.is_empty() && letters.chars().all(|c| c.is_ascii_alphabetic());
    if !shaped || !digits.chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    if letters.len() > 3 || letters.to_ascii_uppercase().as_str() > "XFD" && letters.len() == 3 {
        return Some("past the last column, XFD".to_string());
    }
    let row: u64 = digits.parse().unwrap_or(u64::MAX);
    (row == 0 || row > 1_048_576).then(|| "past the last row, 1048576".to_string())
}

/// The sheets that define `name` for themselves only, in sheet order.
fn sheets_scoping(wb: &Workbook, name: &str) -> Vec<SheetId> {
    let mut scopes: Vec<SheetId> =
        wb.names().into_iter().filter(|(n, _, _)| n.eq_ignore_ascii_case(name)).filter_map(|(_, _, s)| s).collect();
    scopes.sort_unstable();
    scopes.dedup();
    scopes
}

/// Like [`locate`], for one cell: a name must point at a single cell.
pub(crate) fn locate_cell(wb: &Workbook, file: &Path, target: &Target, default: SheetId) -> Result<(SheetId, Pos)> {
    let s = locate(wb, file, target, default)?;
    if !s.rect.is_cell() {
        let name = s.label.unwrap_or_default();
        return Err(Error::User(format!("{}: {name} is the range {}, not one cell", file.display(), s.rect)));
    }
    Ok((s.sheet, s.rect.first))
}

fn sheet_named(wb: &Workbook, file: &Path, name: &str) -> Result<SheetId> {
    wb.sheet_id(name).ok_or_else(|| {
        let names = wb.tab_names().join(", ");
        Error::User(format!("{}: no sheet named '{name}' (it has: {names})", file.display()))
    })
}

/// Refuses to write over an input: an output that is one of the inputs (the same file
/// however it is reached: another spelling, a symbolic link, a hard link), or that is
/// another output of the same command.
pub(crate) fn refuse_overwriting_inputs(inputs: &[&Path], outputs: &[&Path], hint: &str) -> Result<()> {
    for (i, out) in outputs.iter().enumerate() {
        if let Some(input) = inputs.iter().find(|input| same_file(input, out)) {
            return Err(Error::Usage(format!(
                "refusing to overwrite the input file {}{}: {hint}",
                input.display(),
                if input == out { String::new() } else { format!(" (reached as {})", out.display()) }
            )));
        }
        if let Some(other) = outputs[..i].iter().find(|o| same_file(o, out)) {
            return Err(Error::Usage(format!("{} and {} are the same file", other.display(), out.display())));
        }
    }
    Ok(())
}

/// Whether two paths name the same file: by device and inode when both exist (symbolic
/// links followed), else by their spelling.
fn same_file(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
        (Err(_), Err(_)) => a == b,
        _ => false,
    }
}

/// Writes each computed output, after checking that every target can be replaced, so that
/// one refused target leaves all of them as they were. What the outputs cannot keep of the
/// original is said first; replacing an input with losses needs --force.
pub(crate) fn write_outputs(files: &[ncsheet::io::Encoded], in_place: bool, force: bool) -> Result<()> {
    let options = ncsheet::io::atomic::Options { force };
    for f in files {
        for loss in &f.losses {
            eprintln!("ncsheet: {}: not kept: {loss}", f.path.display());
        }
    }
    if in_place && !force && files.iter().any(|f| !f.losses.is_empty()) {
        return Err(Error::User(
            "nothing was written: replacing the file would lose what is listed above (--force writes it anyway, \
             or write elsewhere with -o)"
                .into(),
        ));
    }
    for f in files {
        ncsheet::io::atomic::check(&f.path, options)
            .map_err(|e| Error::User(format!("{}: cannot write: {e}", f.path.display())))?;
    }
    for f in files {
        let _wait = if in_place { None } else { wait_for_edits_of(&f.path) };
        f.write(options)?;
    }
    Ok(())
}

/// Waits for another ncsheet's `--in-place` edit of `path` to finish (its `EditLock` held from
/// its read to its rename) and holds the file until this save's rename: a save landing between
/// that edit's check and its rename was replaced by the edit, both printing "saved" (a
/// `set -o` beside a `set --in-place` of one file lost the `-o` one time in three). A new
/// file, or one that cannot be read, has no edit to wait for.
fn wait_for_edits_of(path: &Path) -> Option<ncsheet::io::atomic::EditLock> {
    ncsheet::io::atomic::EditLock::acquire(path).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn the_command_line_definition_is_consistent() {
        Cli::command().debug_assert();
    }
}
