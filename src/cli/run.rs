//! `ncsheet run`: a VBA-style macro on a workbook. Standard output carries only the NC program
//! (without `-o`), so `> p.ngc` is a program a control reads; what the macro prints
//! (`Debug.Print`), `MsgBox` and every message go to standard error.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use ncsheet::io::xlsx::Layout;
use ncsheet::nc::motion::{self, Rates};
use ncsheet::nc::{dialect, Block, Machine, Program};
use ncsheet::vba::project::{ModuleKind, ProjectModule};
use ncsheet::vba::{self, Document, ErrorKind, RunOptions, RunOutput};

use super::macro_files;
use super::output::emit;
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
/// Nc.Block, Nc.FeedPerRev/FeedPerMin, Nc.Spindle, Nc.Tool, Nc.Coolant. A macro runs no program and touches no file
/// outside --out-dir (its own files, written when it succeeds) and --in-file; it stops with its line and a
/// caret after --max-statements statements, --max-depth nested calls or the --timeout, or
/// at a string, array or output past --max-string, --max-array-items or --max-output.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The workbook the macro works on (.csv or .xlsx)
    pub workbook: PathBuf,
    /// The macro file (default: the macros stored in the workbook, an .xlsm)
    #[arg(value_name = "MACRO.bas")]
    pub macro_file: Option<PathBuf>,
    /// Another module of the macro's project, repeatable: a .bas standard module (its public
    /// procedures) or a .cls class module (`New Name` makes its objects)
    #[arg(long = "module", value_name = "FILE")]
    pub modules: Vec<PathBuf>,
    /// The ANSI code page the .bas and .cls files are in when they are not UTF-8: the VBA
    /// editor exports a module in the system's (1252 Western, 1251 Cyrillic, 932 Japanese, 936
    /// Simplified Chinese, 949 Korean, 950 Traditional Chinese; readable: 874, 932, 936, 949, 950,
    /// 1250-1258, 10000, 20866, 28591-28599, 65001); the macro's text files (Print #, Line
    /// Input #) are written and read in it too. Default: the workbook's own VBA project's;
    /// without one, a file with bytes past ASCII that is not UTF-8 is read in the code page its text is
    /// guessed to be in (said on stderr), or refused at its first such byte when none fits
    #[arg(long = "code-page", visible_alias = "codepage", value_name = "N",
          value_parser = super::macros::parse_code_page)]
    pub code_page: Option<u16>,
    /// The Sub to run (default: Main, or the first Sub without arguments); for the
    /// workbook's own macros also MODULE.SUB (Module1.Chamfer)
    #[arg(long, value_name = "NAME")]
    pub sub: Option<String>,
    /// A value for one of the Sub's parameters, read as a cell reads what is typed
    #[arg(long = "arg", value_name = "NAME=VALUE", value_parser = parse_arg)]
    pub args: Vec<(String, String)>,
    /// Write the NC program in this dialect. nc81: the same words as nc31, per the chamfer
    /// paper, which names NC81 beside NC31; no NC81 manual was available
    #[arg(long, default_value = "iso", ignore_case = true,
          value_parser = super::nc::dialect_parser(dialect::names()))]
    pub dialect: &'static dyn dialect::Dialect,
    /// How far (mm) the lines may lie from an arc on a control without circular
    /// interpolation (nc31, nc81), which gets each arc as lines (default 0.01)
    #[arg(long, value_name = "MM", value_parser = parse_arc_tol)]
    pub arc_tol: Option<f64>,
    /// The machine the program is for, until the macro sets Nc.Machine
    #[arg(long, value_enum, default_value_t)]
    pub machine: MachineKind,
    /// NC31 (and NC81): write each cycle the macro marks (Nc.Subprogram, Nc.Cycle …
    /// Nc.EndCycle, as sheets/cycles.bas does for L16, L17 and L13) once, as a subprogram with
    /// R parameters after M02 (with the subprograms it calls), and
    /// call it per use with its values (`L16 X40 W35 …`), as the cycles paper writes its
    /// cycles. The program is read back with its subprograms run and refused unless it moves
    /// as the unrolled one (docs/domain.md §2). Without it every cycle is written unrolled.
    #[arg(long)]
    pub subprograms: bool,
    /// Write the NC program here instead of standard output
    #[arg(short, long, value_name = "PROGRAM")]
    pub output: Option<PathBuf>,
    /// Save the workbook with the macro's changes (.csv or .xlsx; not the input file)
    #[arg(long, value_name = "OUT")]
    pub save: Option<PathBuf>,
    /// Replace a read-only or hard-linked PROGRAM or --save file
    #[arg(long)]
    pub force: bool,
    /// The one folder the macro's own files go in (Open … For Output/Append, Print #,
    /// Write #, FileSystemObject's CreateTextFile), each named plainly (program.nc); it may
    /// read the folder's files too. They are written when the macro runs to its end, and
    /// listed; without --out-dir and --in-file a file statement is refused
    #[arg(long, value_name = "DIR")]
    pub out_dir: Option<PathBuf>,
    /// A file the macro may read (Open … For Input, Line Input #, Input #, OpenTextFile),
    /// opened by its file name alone (--in-file data/points.csv: "points.csv"); repeatable
    #[arg(long = "in-file", value_name = "PATH")]
    pub in_files: Vec<PathBuf>,
    /// An answer to the macro's next dialog, repeatable, taken in the order the macro opens
    /// them: InputBox gets the text, Application.InputBox the text read as its Type asks (a
    /// number, TRUE/FALSE, a reference), GetOpenFilename and GetSaveAsFilename the file's name
    /// (a plain name in --out-dir, or an --in-file's). Past the last answer a dialog is
    /// cancelled: InputBox gives "", the others False. Without --input a dialog stops the run
    #[arg(long = "input", value_name = "TEXT")]
    pub inputs: Vec<String>,
    /// A folder the macro names by a fixed path (C:\Users\me\Desktop), mapped onto the --out-dir
    /// folder, repeatable: a file the macro names under it is that name in --out-dir, compared
    /// as Windows does (either case, / or \); a path going further (.., a deeper folder) is
    /// still refused. PREFIX=DIR names the folder too: it is --out-dir, or becomes it
    #[arg(long = "map-dir", value_name = "PREFIX[=DIR]")]
    pub map_dirs: Vec<String>,
    /// Stop the macro after this many statements (an endless loop, usually)
    #[arg(long, default_value_t = vba::DEFAULT_MAX_STATEMENTS)]
    pub max_statements: u64,
    /// The longest string the macro may make, in characters (VBA's "Out of string space")
    #[arg(long, value_name = "CHARS", default_value_t = vba::DEFAULT_MAX_STRING, value_parser = parse_max_string)]
    pub max_string: usize,
    /// The most items of one array (Dim, ReDim)
    #[arg(long, value_name = "N", default_value_t = vba::DEFAULT_MAX_ARRAY_ITEMS, value_parser = parse_max_array_items)]
    pub max_array_items: usize,
    /// The most Debug.Print and MsgBox output: 64M, 1G or bytes (default 64M)
    #[arg(long, value_name = "SIZE", value_parser = super::limits::parse_size)]
    pub max_output: Option<u64>,
    /// The most memory all the macro's strings and arrays may hold together: 1G, 512M or
    /// bytes (default 1G)
    #[arg(long, value_name = "SIZE", value_parser = super::limits::parse_size)]
    pub max_memory: Option<u64>,
    /// Stop the macro when calls nest deeper than this (endless recursion; at most 10000)
    #[arg(long, default_value_t = 100, value_parser = parse_max_depth)]
    pub max_depth: usize,
    /// The sheet Range and Cells mean (default: the active one, where the file opens)
    #[arg(long, value_name = "NAME")]
    pub sheet: Option<String>,
    #[command(flatten)]
    pub timeout: super::limits::TimeoutArg,
    #[command(flatten)]
    pub reading: super::WorkbookOptions,
}

/// The deepest `--max-depth`: each level reserves [`STACK_BYTES_PER_LEVEL`] of stack, and
/// 10,000 levels are 640 MiB (docs/limits.md).
const MAX_DEPTH_LIMIT: usize = 10_000;

fn parse_max_depth(text: &str) -> std::result::Result<usize, String> {
    match text.parse::<usize>() {
        Ok(n @ 1..=MAX_DEPTH_LIMIT) => Ok(n),
        _ => Err(format!(
            "'{text}' is not a depth from 1 to {MAX_DEPTH_LIMIT} (ncsheet's limit: each level reserves 64 KiB of stack)"
        )),
    }
}

/// The longest `--max-string`: 1 Gi characters (VBA's own limit is 2 Gi, more memory than
/// ncsheet allows itself).
const MAX_STRING_LIMIT: usize = 1 << 30;

fn parse_max_string(text: &str) -> std::result::Result<usize, String> {
    match text.parse::<usize>() {
        Ok(n @ 1..=MAX_STRING_LIMIT) => Ok(n),
        _ => Err(format!("'{text}' is not a number of characters from 1 to {MAX_STRING_LIMIT}")),
    }
}

/// The largest `--max-array-items`: 2^28 items (8 GiB of values at the least).
const MAX_ARRAY_ITEMS_LIMIT: usize = 1 << 28;

fn parse_max_array_items(text: &str) -> std::result::Result<usize, String> {
    match text.parse::<usize>() {
        Ok(n @ 1..=MAX_ARRAY_ITEMS_LIMIT) => Ok(n),
        _ => Err(format!("'{text}' is not a number of items from 1 to {MAX_ARRAY_ITEMS_LIMIT}")),
    }
}

fn parse_arc_tol(text: &str) -> std::result::Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("'{text}' is not a tolerance in mm above 0")),
    }
}

fn parse_arg(text: &str) -> std::result::Result<(String, String), String> {
    match text.split_once('=') {
        Some((name, value)) if !name.trim().is_empty() => Ok((name.trim().to_string(), value.to_string())),
        _ => Err(format!("'{text}' is not NAME=VALUE")),
    }
}

/// Deep recursion needs a deep stack: each nested macro call costs a few evaluator frames.
const STACK_BYTES_PER_LEVEL: usize = 64 * 1024;

pub fn run(args: RunArgs, delimiter: Option<u8>) -> Result<()> {
    let outputs: Vec<&std::path::Path> = args.output.iter().chain(&args.save).map(PathBuf::as_path).collect();
    let hint = "the program and the saved workbook go to new files";
    let mut inputs: Vec<&std::path::Path> = vec![&args.workbook];
    inputs.extend(args.macro_file.as_deref());
    inputs.extend(args.modules.iter().map(PathBuf::as_path));
    inputs.extend(args.in_files.iter().map(PathBuf::as_path));
    super::refuse_overwriting_inputs(&inputs, &outputs, hint)?;
    // The workbook's functions, recomputed by the macro's writes, nest on top of it.
    let levels = args.max_depth.saturating_add(ncsheet::vba::FUNCTION_MAX_DEPTH);
    let stack = (8 << 20).max(levels.saturating_mul(STACK_BYTES_PER_LEVEL));
    // The workbook is not Send, so it is loaded and used on the macro's own thread.
    let worker = std::thread::Builder::new().stack_size(stack).spawn(move || run_on_this_thread(args, delimiter));
    match worker {
        Ok(handle) => handle.join().unwrap_or_else(|_| Err(Error::User("the macro crashed".into()))),
        Err(e) => Err(Error::User(format!("cannot start the macro: {e}"))),
    }
}

fn run_on_this_thread(mut args: RunArgs, delimiter: Option<u8>) -> Result<()> {
    args.map_dirs = mapped_prefixes(&args.map_dirs, &mut args.out_dir)?;
    if args.subprograms && dialect::with_subprograms(args.dialect.name()).is_none() {
        return Err(Error::Usage(format!(
            "--subprograms writes NC31 subprograms: give --dialect nc31 or nc81 (the {} dialect gets the cycles \
             unrolled)",
            args.dialect.name()
        )));
    }
    let mut doc = ncsheet::document::Document::open_file(&args.workbook, &super::open_options(delimiter))?;
    // The project as the document read it when it opened: read once for the whole run.
    let project = super::macros::WorkbookProject { file: &args.workbook, read: doc.vba_project() };
    let code_page = module_code_page(&args, project);
    let (file, source, sub, document) = macro_source(&args, doc.layout(), project, code_page)?;
    let file = &file;
    let options = RunOptions {
        sub,
        args: super::locale::typed_args(doc.workbook(), &args.args)?,
        max_statements: args.max_statements,
        max_depth: args.max_depth,
        deadline: super::limits::deadline(),
        max_string: args.max_string,
        max_array_items: args.max_array_items,
        max_output: args.max_output.unwrap_or(vba::DEFAULT_MAX_OUTPUT),
        max_memory: args.max_memory.unwrap_or(vba::DEFAULT_MAX_MEMORY),
        sink: Some(vba::Sink(std::rc::Rc::new(write_printed))),
        document,
        sheet: args.sheet.clone(),
        dialect: Some(args.dialect),
        machine: match args.machine {
            MachineKind::Lathe => Machine::Lathe,
            MachineKind::Mill => Machine::Mill,
        },
        project: other_modules(&args, project, file, code_page)?,
        classes: class_modules(&args, project, code_page)?,
        workbook_name: args.workbook.file_name().and_then(|n| n.to_str()).map(str::to_string),
        code_page: code_page.or_else(|| guessed_code_page(&args)),
        files: macro_files::access(
            args.out_dir.as_deref(),
            &args.in_files,
            args.max_memory.unwrap_or(vba::DEFAULT_MAX_MEMORY),
        )?,
        answers: (!args.inputs.is_empty()).then(|| args.inputs.clone()),
        mapped_dirs: args.map_dirs.clone(),
        arc_tolerance: args.arc_tol,
        ..RunOptions::default()
    };
    let out = match doc.run_macro(&source, &file.display().to_string(), options) {
        Ok(out) => out,
        Err(e) => {
            // What the macro printed before it stopped is still the user's.
            print_output(&e.output)?;
            if let Some(note) = macro_files::not_written(&e.output) {
                eprintln!("ncsheet: {}: {note}", file.display());
            }
            return Err(match e.kind {
                ErrorKind::Usage => Error::Usage(e.to_string()),
                _ => Error::User(e.to_string()),
            });
        }
    };
    print_output(&out)?;
    note_unwritten_save(&out, args.save.is_some(), file);
    // Everything is computed before anything is written: a program that cannot be written
    // in the dialect, or a workbook that cannot be saved, leaves every file as it was.
    let mut files = Vec::new();
    let mut program = None;
    let mut summary = None;
    let mut out = out;
    out.program.arc_tolerance = args.arc_tol;
    if emits_program(&out.program) {
        let d = args.dialect;
        let text = if args.subprograms {
            if out.program.calls.is_empty() {
                eprintln!(
                    "ncsheet: {}: note: the macro marks no cycle (Nc.Cycle … Nc.EndCycle), so no subprogram is written",
                    file.display()
                );
            }
            dialect::with_subprograms(d.name()).unwrap_or(&dialect::NC31).render_with_subprograms(&out.program)
        } else {
            d.render(&out.program)
        };
        let text = text.map_err(|e| Error::User(format!("{}: {e}", file.display())))?;
        let written_to = args.output.as_ref().map_or("standard output".to_string(), |p| p.display().to_string());
        summary = Some(program_summary(&out.program, &text, d.name(), &written_to));
        match &args.output {
            Some(path) => files.push(ncsheet::io::Encoded::new(path, text.into_bytes())),
            None => program = Some(text),
        }
    } else if let Some(path) = &args.output {
        // A program file left from an earlier run would be taken for this run's program.
        let kept = if path.exists() { format!("{} is left as it was", path.display()) } else { "none written".into() };
        return Err(Error::User(format!(
            "{}: the macro emitted no NC block (no move), so there is no program: {kept}; nothing was saved",
            file.display()
        )));
    }
    let macro_outputs = macro_files::outputs(args.out_dir.as_deref(), &out)?;
    let mut inputs: Vec<&std::path::Path> = vec![&args.workbook];
    inputs.extend(args.macro_file.as_deref());
    inputs.extend(args.in_files.iter().map(PathBuf::as_path));
    let mut targets: Vec<&std::path::Path> = args.output.iter().chain(&args.save).map(PathBuf::as_path).collect();
    targets.extend(macro_outputs.iter().map(|f| f.path.as_path()));
    super::refuse_overwriting_inputs(&inputs, &targets, "the macro's files go to new files in --out-dir")?;
    let listed = macro_files::written(&macro_outputs);
    files.extend(macro_outputs);
    if let Some(save) = &args.save {
        files.push(doc.encode(save)?);
    }
    super::write_outputs(&files, false, args.force)?;
    for line in &listed {
        eprintln!("{line}");
    }
    for line in macro_files::remove_killed(args.out_dir.as_deref(), &out)? {
        eprintln!("{line}");
    }
    if let Some(text) = program {
        emit(&text, None, false)?;
    }
    match summary {
        Some(s) => eprintln!("{s}"),
        None if !listed.is_empty() => {}
        None => eprintln!("ncsheet: {}: note: no NC program: the macro emitted no NC block (no move)", file.display()),
    }
    Ok(())
}

/// Whether the macro emitted a program: at least one block a control acts on. Comments
/// alone (a macro that stopped after naming its program) are no program.
fn emits_program(program: &Program) -> bool {
    program.blocks.iter().any(|b| !matches!(b, Block::Comment(_)))
}

/// The machine the cycle-time estimate of [`program_summary`] assumes; `nc time` takes the
/// user's own.
pub(super) const SUMMARY_RATES: Rates = Rates { accel: 500.0, rapid: 5000.0 };

/// What a command wrote, for stderr: where, the dialect, the blocks, the tools and a cycle
/// time estimate at [`SUMMARY_RATES`] (or why there is none).
pub(super) fn program_summary(program: &Program, text: &str, dialect: &str, written_to: &str) -> String {
    let lines = text.lines().filter(|l| !l.trim().is_empty()).count();
    let moves =
        program.blocks.iter().filter(|b| matches!(b, Block::Rapid(_) | Block::Line { .. } | Block::Arc { .. })).count();
    let mut tools: Vec<String> = Vec::new();
    for b in &program.blocks {
        if let Block::Tool(t) = b {
            let t = format!("T{}", t.number);
            if !tools.contains(&t) {
                tools.push(t);
            }
        }
    }
    let tools = if tools.is_empty() { "no tool change".to_string() } else { format!("tool {}", tools.join(", ")) };
    let time = match motion::program_times(program, SUMMARY_RATES) {
        Ok(times) => {
            let total: f64 = times.iter().map(|t| t.time).sum();
            format!(
                "about {total:.1} s at {} mm/min rapid and {} mm/s² (nc time for your machine's)",
                SUMMARY_RATES.rapid, SUMMARY_RATES.accel
            )
        }
        Err(e) => format!("no time estimate ({})", e.message),
    };
    format!("wrote {written_to}: {dialect}, {lines} lines, {moves} moves, {tools}, {time}")
}

/// The code page the .bas and .cls files given are read in: --code-page, else the workbook's
/// own VBA project's (its PROJECTCODEPAGE record, as the VBA editor imports into it), else none,
/// and a file past ASCII that is not UTF-8 is refused at its first such byte.
/// The folder prefixes of `--map-dir PREFIX[=DIR]`. A DIR is the --out-dir folder, or becomes
/// it when there is none: the macro's files stay in one folder.
fn mapped_prefixes(specs: &[String], out_dir: &mut Option<PathBuf>) -> Result<Vec<String>> {
    let mut prefixes = Vec::new();
    for spec in specs {
        let (prefix, dir) = match spec.split_once('=') {
            Some((p, d)) => (p, Some(PathBuf::from(d))),
            None => (spec.as_str(), None),
        };
        if prefix.trim_end_matches(['/', '\\']).is_empty() {
            return Err(Error::Usage(format!(
                "--map-dir {spec}: name the folder the macro writes to (C:\\Users\\me\\out)"
            )));
        }
        match (dir, out_dir.as_ref()) {
            (None, None) => {
                return Err(Error::Usage(format!("--map-dir {spec}: the folder maps onto --out-dir DIR; give one")))
            }
            (Some(dir), None) => *out_dir = Some(dir),
            (Some(dir), Some(out)) if !same_folder(&dir, out) => {
                return Err(Error::Usage(format!(
                    "--map-dir {spec}: {} is not the --out-dir folder {}; a macro's files go in that one folder",
                    dir.display(),
                    out.display()
                )))
            }
            _ => {}
        }
        prefixes.push(prefix.to_string());
    }
    Ok(prefixes)
}

/// Whether two spellings name one folder (as the system resolves them, else as written).
fn same_folder(a: &std::path::Path, b: &std::path::Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

fn module_code_page(args: &RunArgs, project: super::macros::WorkbookProject) -> Option<u16> {
    args.code_page.or_else(|| project.read.and_then(|p| p.ok()).map(|p| p.code_page))
}

/// The code page the macro's own files were read in by a guess from their text, when neither
/// `--code-page` nor a project names one: the code page of the machine that wrote them, whose
/// `Print #` wrote its text files in it too.
fn guessed_code_page(args: &RunArgs) -> Option<u16> {
    let files: Vec<PathBuf> = args.macro_file.iter().chain(&args.modules).cloned().collect();
    super::macros::first_guessed_code_page(&files)
}

/// The macro's place (for messages), its source, the Sub to call and the document its module
/// belongs to: the .bas file given, or a module of the workbook's own VBA project.
fn macro_source(
    args: &RunArgs,
    layout: Option<&Layout>,
    project: super::macros::WorkbookProject,
    code_page: Option<u16>,
) -> Result<(PathBuf, String, Option<String>, Option<Document>)> {
    if let Some(file) = &args.macro_file {
        let source = super::macros::read_module_text(file, code_page)?;
        return Ok((file.clone(), source, args.sub.clone(), None));
    }
    let project = project.get()?;
    let (module, sub) = super::macros::pick_macro(project, args.sub.as_deref())?;
    let place = args.workbook.join(&module.name);
    let document = document_of(module, layout).map_err(|m| Error::User(format!("{}: {m}", place.display())))?;
    Ok((place, module.source.clone(), sub, document))
}

/// The project's other standard modules, whose public code the module run sees as VBA
/// compiles a project as one program (none for a .bas file given on its own).
fn other_modules(
    args: &RunArgs,
    project: super::macros::WorkbookProject,
    running: &std::path::Path,
    code_page: Option<u16>,
) -> Result<Vec<(String, String)>> {
    let mut modules = given_modules(args, ModuleKind::Standard, code_page)?;
    if args.macro_file.is_some() {
        return Ok(modules);
    }
    let project = project.get()?;
    let own = running.file_name().and_then(|n| n.to_str()).unwrap_or_default();
    let others = project.modules.iter().filter(|m| m.kind == ModuleKind::Standard && m.name != own);
    modules.extend(others.map(|m| (m.name.clone(), m.source.clone())));
    Ok(modules)
}

/// The project's class modules: the workbook's own (none for a .bas file given on its own)
/// and the .cls files given with --module.
fn class_modules(
    args: &RunArgs,
    project: super::macros::WorkbookProject,
    code_page: Option<u16>,
) -> Result<Vec<(String, String)>> {
    let mut classes = given_modules(args, ModuleKind::Class, code_page)?;
    if args.macro_file.is_none() {
        let project = project.get()?;
        let own = project.modules.iter().filter(|m| m.kind == ModuleKind::Class);
        classes.extend(own.map(|m| (m.name.clone(), m.source.clone())));
    }
    Ok(classes)
}

/// The --module files of one kind (a .cls file with a class header or named .cls is a class
/// module), by their `Attribute VB_Name` or file name.
fn given_modules(args: &RunArgs, kind: ModuleKind, code_page: Option<u16>) -> Result<Vec<(String, String)>> {
    let read = super::macros::read_modules(
        &args.modules,
        code_page,
        super::macros::Names { taken: Vec::new(), replaceable: &[] },
    )?;
    Ok(read.into_iter().filter(|m| m.kind == kind).map(|m| (m.name, m.source)).collect())
}

/// What a module of the project belongs to: nothing (a standard module), a sheet (its code
/// name is the module's name) or the workbook (`ThisWorkbook`). Class and UserForm modules
/// need an object or a form, which a run has not.
fn document_of(module: &ProjectModule, layout: Option<&Layout>) -> std::result::Result<Option<Document>, String> {
    if module.kind == ModuleKind::Standard {
        return Ok(None);
    }
    let named = |code: Option<&String>| code.is_some_and(|c| c.eq_ignore_ascii_case(&module.name));
    let workbook_code = layout.and_then(|l| l.workbook_code_name.as_ref());
    if named(workbook_code) || (workbook_code.is_none() && module.name.eq_ignore_ascii_case("ThisWorkbook")) {
        return Ok(Some(Document::Workbook));
    }
    let sheet = layout.into_iter().flat_map(|l| &l.sheets).find(|(_, s)| named(s.code_name.as_ref()));
    match sheet {
        Some((name, _)) => Ok(Some(Document::Sheet(name.clone()))),
        None => Err(format!(
            "{} is a class or UserForm module, not the module of a sheet or of the workbook: its code needs \
             an object or a form (a window), which a run has not; run a standard or a sheet module's macro",
            module.name
        )),
    }
}

/// What the macro prints goes to stderr as it happens (a line above `%` would stop a control
/// reading a redirected program); a closed stderr loses it, as `eprintln!` would not.
fn write_printed(printed: vba::Printed) {
    use std::io::Write;
    let (vba::Printed::Line(text) | vba::Printed::Message(text)) = printed;
    let _ = writeln!(std::io::stderr().lock(), "{text}");
}

/// What the macro printed and the sink did not take.
fn print_output(out: &RunOutput) -> Result<()> {
    for line in &out.printed {
        eprintln!("{line}");
    }
    for m in &out.messages {
        eprintln!("{m}");
    }
    Ok(())
}

/// A macro that called `ThisWorkbook.Save` expects its changes kept: they are with `--save`
/// (the workbook is written there at the end of the run); without it, the user is told.
fn note_unwritten_save(out: &ncsheet::vba::RunOutput, saved: bool, file: &std::path::Path) {
    if let (Some(line), false) = (out.saves.first(), saved) {
        eprintln!(
            "ncsheet: {}:{line}: note: Workbook.Save: the workbook is not written (ncsheet never writes the file it \
             opened); give --save OUT to keep the macro's changes",
            file.display()
        );
    }
}
