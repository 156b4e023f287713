//! The files a macro reads and writes (`Open`, `Print #`, `Write #`, `Input #`, `Line Input #`,
//! `Close`, `FreeFile`, `EOF`, `LOF`, `Dir`, `Kill`, `FileLen`, `FileDateTime`, `FileCopy`, and
//! Scripting's `FileSystemObject` with its
//! `TextStream`s), inside a sandbox the run is given ([`FileAccess`]: `ncsheet run --out-dir
//! DIR` and `--in-file PATH`).
//!
//! This module touches no file: the macro sees a table of files in memory. What it writes is
//! kept here and handed back in [`super::RunOutput::files`], for the front end to write when
//! the run succeeded (all or nothing), as are the folder's files it deleted
//! ([`super::RunOutput::removed`]); what it reads comes from the listed inputs' bytes or
//! from [`FileAccess::read_out_dir`], which the front end answers. A path is a plain file name
//! in the output folder or the name of a listed input: [`checked_name`] refuses every other
//! spelling (a folder part, `..`, an absolute path, a drive letter, UNC, a Windows device
//! name, an alternate data stream), and that refusal stops the macro (no `On Error` traps it).
//!
//! Formats are VBA's ("Print # statement", "Write # statement", "Input # statement", "Line
//! Input # statement" in the Office VBA language reference; [MS-VBAL] 5.4.5): `Print #`
//! writes numbers with a space before (for the sign) and after, `;` joins, `,` and `Tab` move
//! to the next 14-column print zone; `Write #` quotes strings, separates items with commas
//! and writes `#TRUE#`/`#FALSE#`; every line ends with CR LF. Text files are written and read
//! in the ANSI code page the project was written in ([`super::RunOptions::code_page`]; Windows-1252,
//! a Western Excel's, when none is known), as VBA writes them in the system's: a Chinese shop's
//! comments go out in GBK (`CreateTextFile(…, True)` writes UTF-16 with its byte-order mark). A
//! character the code page has not is refused, never replaced. Binary and Random files hold
//! their Strings in Windows-1252.

use std::collections::BTreeMap;
use std::fmt;
use std::rc::Rc;

use pest::iterators::Pair;

use crate::eval::functions::vba::{errors, wildcard_matches};
use crate::eval::{Ctx, Value, XlError};
use crate::formula::ast::Expr;
use crate::formula::parse::Rule;

use super::ast::{Link, Span, StmtKind, Target};
use super::interp::{Fault, Interp, Run};
use super::parser::{Build, Res};
use super::resolve::refusal;
use super::value::{print_text, Obj, Var};

/// What a run may read and write besides its workbook. The library never opens a file: the
/// front end gives the listed inputs' bytes and reads the output folder for it.
#[derive(Clone)]
pub struct FileAccess {
    /// The folder the macro writes its files in, as the user named it (for messages);
    /// `None`: the macro may only read.
    pub out_dir: Option<String>,
    /// The files the user listed for reading (`--in-file`): the name a macro opens each by
    /// (its file name) and its bytes.
    pub inputs: Vec<(String, Rc<[u8]>)>,
    /// Reads a file of the output folder by a name [`checked_name`] accepted: `Ok(None)` when
    /// there is none, `Err` why it cannot be read (a symbolic link, not a plain file, …).
    pub read_out_dir: Rc<FolderReader>,
    /// The names of the output folder's plain files (those [`checked_name`] accepts), for
    /// `Dir` and `Kill` with wildcards; `Err` why the folder cannot be listed.
    pub list_out_dir: Rc<FolderLister>,
    /// When a file of the output folder was last modified (`FileDateTime`), by a name
    /// [`checked_name`] accepted: `Ok(None)` when there is none, `Err` why it cannot be read.
    pub modified_out_dir: Rc<FolderClock>,
}

/// Reads a file of the output folder by name for the sandbox (see [`FileAccess::read_out_dir`]).
pub type FolderReader = dyn Fn(&str) -> Result<Option<Vec<u8>>, String>;

/// Lists the output folder's files for the sandbox (see [`FileAccess::list_out_dir`]).
pub type FolderLister = dyn Fn() -> Result<Vec<String>, String>;

/// When a file of the output folder was last modified (see [`FileAccess::modified_out_dir`]).
pub type FolderClock = dyn Fn(&str) -> Result<Option<std::time::SystemTime>, String>;

impl fmt::Debug for FileAccess {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let inputs: Vec<&str> = self.inputs.iter().map(|(n, _)| n.as_str()).collect();
        f.debug_struct("FileAccess").field("out_dir", &self.out_dir).field("inputs", &inputs).finish()
    }
}

/// The code of a sandbox refusal: no `On Error` traps it (the path must change, not be skipped).
pub(super) const REFUSED: u32 = u32::MAX - 1;

/// VBA's trappable file errors ("Trappable errors" in the VBA reference).
const BAD_NUMBER: (u32, &str) = (52, errors::description(52));
const NOT_FOUND: (u32, &str) = (53, errors::description(53));
const BAD_MODE: (u32, &str) = (54, errors::description(54));
const ALREADY_OPEN: (u32, &str) = (55, errors::description(55));
const EXISTS: (u32, &str) = (58, errors::description(58));
const PAST_END: (u32, &str) = (62, errors::description(62));
const TOO_MANY: (u32, &str) = (67, errors::description(67));
const ACCESS: (u32, &str) = (75, errors::description(75));
const INVALID_CALL: (u32, &str) = (5, errors::description(5));

/// What one TextStream or written file costs the memory budget besides its text.
const STREAM_BYTES: u64 = 64;

/// The width of a print zone ("Print # statement": `,` and `Tab` move to the next one).
const ZONE: usize = 14;

/// Why a path a macro names is not a plain file name of the sandbox, or `None` when it is.
/// Every spelling that could leave the folder on Linux or on Windows is refused.
pub fn checked_name(path: &str) -> Option<&'static str> {
    let bytes = path.as_bytes();
    let drive = bytes.len() >= 2 && bytes[0].is_ascii_alphabetic() && bytes[1] == b':';
    let stem = path.split('.').next().unwrap_or("").trim_end().to_ascii_uppercase();
    let device = matches!(stem.as_str(), "CON" | "PRN" | "AUX" | "NUL" | "CONIN$" | "CONOUT$" | "CLOCK$")
        || (stem.len() == 4
            && (stem.starts_with("COM") || stem.starts_with("LPT"))
            && stem.as_bytes()[3].is_ascii_digit());
    Some(if path.is_empty() {
        "a file needs a name"
    } else if path.chars().any(char::is_control) {
        "a control character in a file name"
    } else if path.starts_with("\\\\?\\") || path.starts_with("//?/") {
        // Win32's file namespace prefix: no name parsing at all, any length, any drive.
        "an extended-length path (\\\\?\\ prefix)"
    } else if path.starts_with("\\\\.\\") || path.starts_with("//./") {
        "a Windows device path (\\\\.\\ prefix)"
    } else if path.starts_with("\\\\") || path.starts_with("//") {
        "a network (UNC) path"
    } else if drive {
        "a drive letter"
    } else if path.starts_with('/') || path.starts_with('\\') {
        "an absolute path"
    } else if path == "." || path == ".." || path.split(['/', '\\']).any(|p| p == "..") {
        "\"..\" leaves the folder"
    } else if path.contains('\\') {
        "a backslash (a folder on Windows)"
    } else if path.contains('/') {
        "a folder part"
    } else if path.contains(':') {
        "a colon (an alternate data stream on Windows)"
    } else if device {
        "a Windows device name (CON, PRN, AUX, NUL, COM1…, LPT1…)"
    } else if path.contains(['<', '>', '"', '|', '?', '*']) {
        "a character Windows forbids in file names"
    } else if path.ends_with(['.', ' ']) {
        "a trailing dot or space (Windows drops it, naming another file)"
    } else if path.len() > 255 {
        "a name longer than 255 bytes"
    } else {
        return None;
    })
}

// ---- statements, as parsed -------------------------------------------------------------

/// A file statement ([MS-VBAL] 5.4.5).
#[derive(Debug)]
pub enum FileStmt {
    /// `Open path For mode As #n`.
    Open { path: Expr, mode: Mode, number: Expr, len: Option<Expr> },
    /// `Print #n, items`.
    Print { number: Expr, items: Vec<PrintPart> },
    /// `Write #n, items`: `open` when a separator ends the list (no line end).
    Write { number: Expr, items: Vec<Expr>, open: bool },
    /// `Line Input #n, var`.
    LineInput { number: Expr, target: Target },
    /// `Input #n, a, b`.
    Input { number: Expr, targets: Vec<Target> },
    /// `Close #1, #2`; no numbers: every file.
    Close(Vec<Expr>),
    /// `Put #n, [record], data` (`binary.rs`).
    Put { number: Expr, record: Option<Expr>, data: Expr },
    /// `Get #n, [record], var`.
    Get { number: Expr, record: Option<Expr>, target: Target },
    /// `Seek #n, position`.
    Seek { number: Expr, position: Expr },
}

/// What a file is open for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Input,
    Output,
    Append,
    Binary,
    Random,
}

#[derive(Debug)]
pub enum PrintPart {
    Value(Expr),
    /// `;`
    Join,
    /// `,`: the next print zone.
    Zone,
    /// `Spc(n)`: n spaces.
    Spc(Expr),
    /// `Tab(n)`: to column n; `Tab` alone: the next print zone.
    Tab(Option<Expr>),
}

fn kids<'i>(pair: &Pair<'i, Rule>) -> Vec<Pair<'i, Rule>> {
    pair.clone().into_inner().collect()
}

fn find_rule<'i>(pairs: &[Pair<'i, Rule>], rule: Rule) -> Option<Pair<'i, Rule>> {
    pairs.iter().find(|p| p.as_rule() == rule).cloned()
}

impl Build<'_> {
    /// A file statement: refused by name unless the run has files ([`FileAccess`]).
    pub(super) fn file_statement(&self, pair: &Pair<Rule>) -> Res<StmtKind> {
        let word = pair.as_str().split(|c: char| !c.is_alphabetic()).next().unwrap_or("");
        let Some(inner) = pair.clone().into_inner().next().filter(|_| self.files) else {
            return Err(self.error_at(pair, refusal(word)));
        };
        let k = kids(&inner);
        let stmt = match inner.as_rule() {
            Rule::open_stmt => self.open_statement(&k)?,
            Rule::print_file => {
                let mut items = Vec::new();
                for p in &k[2..] {
                    items.push(match p.as_rule() {
                        Rule::print_sep if p.as_str() == ";" => PrintPart::Join,
                        Rule::print_sep => PrintPart::Zone,
                        Rule::print_spc => PrintPart::Spc(self.expr(kids(p)[1].clone())?),
                        Rule::print_tab => match kids(p).get(1) {
                            Some(column) => PrintPart::Tab(Some(self.expr(column.clone())?)),
                            None => PrintPart::Tab(None),
                        },
                        _ => PrintPart::Value(self.expr(p.clone())?),
                    });
                }
                FileStmt::Print { number: self.expr(k[1].clone())?, items }
            }
            Rule::write_file => {
                let rest = &k[2..];
                let mut items = Vec::new();
                for p in rest.iter().filter(|p| p.as_rule() == Rule::vexpr) {
                    items.push(self.expr(p.clone())?);
                }
                let open = rest.last().is_some_and(|p| p.as_rule() == Rule::print_sep);
                FileStmt::Write { number: self.expr(k[1].clone())?, items, open }
            }
            Rule::line_input_file => {
                FileStmt::LineInput { number: self.expr(k[1].clone())?, target: self.input_target(&k[2])? }
            }
            Rule::input_file => {
                let mut targets = Vec::new();
                for p in &k[2..] {
                    targets.push(self.input_target(p)?);
                }
                FileStmt::Input { number: self.expr(k[1].clone())?, targets }
            }
            Rule::close_file => {
                let mut numbers = Vec::new();
                for p in &k[1..] {
                    numbers.push(self.file_number(p)?);
                }
                FileStmt::Close(numbers)
            }
            Rule::put_file | Rule::get_file => {
                let record = match find_rule(&k, Rule::record_number) {
                    Some(r) => Some(self.expr(kids(&r)[0].clone())?),
                    None => None,
                };
                let number = self.expr(k[1].clone())?;
                let last = k.last().expect("Put's data or Get's variable").clone();
                match inner.as_rule() {
                    Rule::put_file => FileStmt::Put { number, record, data: self.expr(last)? },
                    _ => FileStmt::Get { number, record, target: self.input_target(&last)? },
                }
            }
            Rule::seek_file => FileStmt::Seek { number: self.expr(k[1].clone())?, position: self.expr(k[2].clone())? },
            _ => {
                return Err(self.error_at(
                    pair,
                    format!(
                        "{word} #: not supported; a macro's files: Open … For Input, Output, Append, Binary or \
                         Random, Print #, Write #, Input #, Line Input #, Put #, Get #, Seek #, Close"
                    ),
                ))
            }
        };
        Ok(StmtKind::File(stmt))
    }

    /// `Open path For mode [Access …] [Lock …] As [#]n [Len = …]`.
    fn open_statement(&self, k: &[Pair<Rule>]) -> Res<FileStmt> {
        let mode = k.iter().find(|p| p.as_rule() == Rule::open_mode).expect("Open's mode");
        let mode = match mode.as_str().to_ascii_lowercase().as_str() {
            "input" => Mode::Input,
            "output" => Mode::Output,
            "append" => Mode::Append,
            "binary" => Mode::Binary,
            _ => Mode::Random,
        };
        let number = k.iter().find(|p| p.as_rule() == Rule::file_number).expect("Open's number");
        let len = match find_rule(k, Rule::open_len) {
            Some(l) => {
                Some(self.expr(kids(&l).into_iter().find(|p| p.as_rule() == Rule::vexpr).expect("Len's value"))?)
            }
            None => None,
        };
        Ok(FileStmt::Open { path: self.expr(k[1].clone())?, mode, number: self.file_number(number)?, len })
    }

    fn file_number(&self, pair: &Pair<Rule>) -> Res<Expr> {
        let e = kids(pair).into_iter().find(|p| p.as_rule() == Rule::vexpr).expect("a file number");
        self.expr(e)
    }

    /// What `Line Input #` and `Input #` read into: a variable or an array's item.
    fn input_target(&self, pair: &Pair<Rule>) -> Res<Target> {
        match self.target(pair.clone())? {
            Target::Node(_) => Err(self.error_at(pair, "Input # and Line Input # read into a variable")),
            target => Ok(target),
        }
    }
}

/// The names that reach files in expressions once the run has them: `FreeFile`, `EOF(n)`,
/// `LOF(n)` and `CreateObject("Scripting.FileSystemObject")`, resolved as paths that
/// [`Interp::file_root`] answers.
pub(super) fn is_file_function(lower: &str, link: &Link) -> bool {
    match lower {
        "freefile" | "eof" | "lof" | "loc" | "seek" | "kill" | "dir" | "filelen" | "filedatetime" | "filecopy"
        | "mkdir" | "rmdir" => true,
        "createobject" => matches!(
            link.args.as_deref(),
            Some([arg]) if matches!(&arg.value.kind,
                crate::formula::ast::ExprKind::Text(id) if id.eq_ignore_ascii_case("Scripting.FileSystemObject"))
        ),
        _ => false,
    }
}

// ---- the run's files ----------------------------------------------------------------------

/// A file object a macro holds: the FileSystemObject, or one of its TextStreams.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileObj {
    System,
    Stream(usize),
}

/// An open file: read from its text, or written into one of the run's written files.
#[derive(Debug)]
struct Channel {
    name: String,
    way: Way,
}

#[derive(Debug)]
enum Way {
    Read {
        text: Rc<str>,
        at: usize,
        bytes: usize,
    },
    Write {
        file: usize,
        /// The column the next character goes to (0-based), for print zones and `Tab`.
        column: usize,
        unicode: bool,
    },
}

/// The run's files: those written (name, bytes, in the order first opened) and those open.
#[derive(Debug, Default)]
pub(super) struct Files {
    pub(super) written: Vec<(String, Vec<u8>)>,
    /// Where each name (lowercase) is in `written`: a macro writing 200,000 files looked
    /// for each name among all before it (past 30 s).
    by_name: std::collections::HashMap<String, usize>,
    /// The places in `written` of the files `Kill` deleted. An entry never moves, because
    /// an open channel holds its place (`Way::Write`, `Place::Written`): a killed one stays,
    /// emptied, and is left out of the output and of `Dir`.
    killed: std::collections::HashSet<usize>,
    numbered: BTreeMap<i64, Channel>,
    /// The files open for Binary or Random (`binary.rs`), by number.
    pub(super) records: BTreeMap<i64, super::binary::Channel>,
    streams: Vec<Option<Channel>>,
    /// Files of the output folder the macro deleted (`Kill`): gone for the rest of the run,
    /// removed from the folder when the run succeeded.
    removed: Vec<String>,
    /// `Dir`'s matches not yet returned, for `Dir` without arguments; `None` before a
    /// `Dir(pattern)` and after the last match was returned.
    dir_left: Option<std::collections::VecDeque<String>>,
}

impl Files {
    /// Whether file number `n` is open for Input, Output or Append.
    pub(super) fn is_numbered(&self, n: i64) -> bool {
        self.numbered.contains_key(&n)
    }

    /// The files written, for [`super::RunOutput::files`].
    pub(super) fn into_written(self) -> Vec<(String, Vec<u8>)> {
        let killed = self.killed;
        self.written.into_iter().enumerate().filter(|(i, _)| !killed.contains(i)).map(|(_, file)| file).collect()
    }

    /// The files written and not killed, in the order first opened.
    fn live_written(&self) -> impl Iterator<Item = &(String, Vec<u8>)> {
        self.written.iter().enumerate().filter(|(i, _)| !self.killed.contains(i)).map(|(_, file)| file)
    }

    /// The files of the output folder the macro deleted, for [`super::RunOutput::removed`].
    pub(super) fn removed(&self) -> Vec<String> {
        self.removed.clone()
    }

    fn is_removed(&self, name: &str) -> bool {
        self.removed.iter().any(|n| n.eq_ignore_ascii_case(name))
    }

    /// The bytes the table holds, for the memory budget.
    pub(super) fn held_bytes(&self) -> u64 {
        let written: usize = self.live_written().map(|(n, b)| b.len() + n.len() + STREAM_BYTES as usize).sum();
        let read = |c: &Channel| match &c.way {
            Way::Read { text, .. } => text.len(),
            Way::Write { .. } => 0,
        };
        let reading: usize = self.numbered.values().chain(self.streams.iter().flatten()).map(read).sum();
        (written + reading) as u64 + self.streams.len() as u64 * STREAM_BYTES
    }

    fn written_index(&self, name: &str) -> Option<usize> {
        self.by_name.get(&name.to_ascii_lowercase()).copied()
    }

    /// Adds a file to those written; its index.
    fn add_written(&mut self, name: &str, bytes: Vec<u8>) -> usize {
        self.written.push((name.to_string(), bytes));
        self.by_name.insert(name.to_ascii_lowercase(), self.written.len() - 1);
        self.written.len() - 1
    }

    /// Forgets written file `i` (`Kill`): its name and bytes go, its place stays (see `killed`).
    fn remove_written(&mut self, i: usize) {
        let name = self.written[i].0.to_ascii_lowercase();
        if self.by_name.get(&name) == Some(&i) {
            self.by_name.remove(&name);
        }
        self.written[i].1 = Vec::new();
        self.killed.insert(i);
    }

    /// Whether a channel now writes the file `name`.
    fn writing(&self, name: &str) -> bool {
        let open = |c: &Channel| matches!(c.way, Way::Write { .. }) && c.name.eq_ignore_ascii_case(name);
        self.numbered.values().any(open) || self.streams.iter().flatten().any(open)
    }
}

/// A folder as `ThisWorkbook.Path` gives it: without a separator at its end ("Path
/// property (Excel)": the complete path to the workbook's folder), the root excepted.
/// The rest of `path` after one of the folders `run --map-dir` maps onto the --out-dir folder
/// (`D:\\cam\\out` for `D:\\cam\\out\\prog.nc`), compared as Windows compares them: letters
/// in either case, `/` or `\\` between the parts. The rest is then a sandbox name like any
/// other, so `..`, a deeper folder or a device name after the prefix is still refused.
fn mapped_name<'p>(prefixes: &[String], path: &'p str) -> Option<&'p str> {
    let same = |a: char, b: char| a.eq_ignore_ascii_case(&b) || (matches!(a, '/' | '\\') && matches!(b, '/' | '\\'));
    prefixes.iter().find_map(|prefix| {
        let prefix = prefix.trim_end_matches(['/', '\\']);
        let mut rest = path.char_indices();
        for p in prefix.chars() {
            let (_, c) = rest.next()?;
            if !same(p, c) {
                return None;
            }
        }
        let (at, separator) = rest.next()?;
        (!prefix.is_empty() && matches!(separator, '/' | '\\')).then(|| &path[at + 1..])
    })
}

fn folder_spelling(dir: &str) -> String {
    let trimmed = dir.trim_end_matches(['/', '\\']);
    if trimmed.is_empty() {
        dir.to_string()
    } else {
        trimmed.to_string()
    }
}

/// The parameters of a FileSystemObject's or a TextStream's method, in order, as Microsoft's
/// reference names them ("CreateTextFile method": filename, overwrite, unicode; "OpenTextFile
/// method": filename, iomode, create, format; …).
fn file_method_parameters(method: &str) -> &'static [&'static str] {
    match method {
        "createtextfile" => &["filename", "overwrite", "unicode"],
        "opentextfile" => &["filename", "iomode", "create", "format"],
        "buildpath" => &["path", "name"],
        "fileexists" | "folderexists" => &["filespec"],
        "getfilename" | "getbasename" | "getextensionname" | "getparentfoldername" | "getdrivename" => &["path"],
        "write" | "writeline" => &["string"],
        "writeblanklines" => &["lines"],
        _ => &[],
    }
}

/// The part of `path` a FileSystemObject method named `method` (lower case) gives.
fn path_text(method: &str, path: &str) -> String {
    use super::path_names::{base_name, drive_name, extension_name, file_name, parent_folder_name};
    let part = match method {
        "getfilename" => file_name(path),
        "getbasename" => base_name(path),
        "getextensionname" => extension_name(path),
        "getparentfoldername" => parent_folder_name(path),
        _ => drive_name(path),
    };
    part.to_string()
}

/// A value as `Print #` writes it: numbers with room for a sign before and a space after.
pub(super) fn print_form(v: &Value) -> String {
    match v {
        Value::Number(n) if *n >= 0.0 => format!(" {} ", print_text(v)),
        Value::Number(_) => format!("{} ", print_text(v)),
        Value::Error(e) => format!("Error {}", error_number(*e).map_or(e.as_str().to_string(), |n| n.to_string())),
        _ => print_text(v),
    }
}

/// A value as `Write #` writes it: strings quoted, numbers bare, `#TRUE#`, `#ERROR 2007#`,
/// `#NULL#` ("Write # statement": nothing for Empty, #NULL# for Null).
fn write_form(v: &Value) -> String {
    match v {
        Value::Blank => String::new(),
        Value::Null => "#NULL#".to_string(),
        Value::Text(t) => format!("\"{t}\""),
        Value::Bool(b) => if *b { "#TRUE#" } else { "#FALSE#" }.to_string(),
        Value::Error(e) => format!("#ERROR {}#", error_number(*e).map_or(e.as_str().to_string(), |n| n.to_string())),
        other => print_text(other),
    }
}

/// Excel's `xlErr…` number of an error value, as VBA's CVErr holds it.
pub(super) fn error_number(e: XlError) -> Option<u32> {
    Some(match e {
        XlError::Null => 2000,
        XlError::Div0 => 2007,
        XlError::Value => 2015,
        XlError::Ref => 2023,
        XlError::Name => 2029,
        XlError::Num => 2036,
        XlError::NA => 2042,
        _ => return None,
    })
}

/// Text in Windows-1252, VBA's ANSI code page, for a Binary or Random file; a character it
/// has not is refused.
pub(super) fn ansi_bytes(text: &str) -> Result<Vec<u8>, String> {
    encode(text, false, WESTERN).map_err(|c| {
        format!("the character {c:?} (U+{:04X}) has no place in Windows-1252, the code page VBA writes", c as u32)
    })
}

/// Bytes of a Binary or Random file as text (Windows-1252).
pub(super) fn ansi_text(bytes: &[u8]) -> Rc<str> {
    encoding_rs::WINDOWS_1252.decode_without_bom_handling(bytes).0.into()
}

/// A Western Excel's ANSI code page.
const WESTERN: u16 = 1252;

/// The encoding of the ANSI code page `code_page`, Windows-1252 for one ncsheet cannot write
/// (the project reader and `--code-page` refuse those before a macro runs).
fn ansi_encoding(code_page: u16) -> &'static encoding_rs::Encoding {
    super::project::encoding_for(code_page).unwrap_or(encoding_rs::WINDOWS_1252)
}

/// How messages name the code page `code_page`.
fn code_page_name(code_page: u16) -> String {
    match code_page {
        WESTERN => "Windows-1252".into(),
        n => format!("code page {n} ({})", ansi_encoding(n).name()),
    }
}

/// Text as the file holds it: in the ANSI code page `code_page`, or UTF-16LE for a Unicode
/// TextStream.
fn encode(text: &str, unicode: bool, code_page: u16) -> Result<Vec<u8>, char> {
    if unicode {
        return Ok(text.encode_utf16().flat_map(u16::to_le_bytes).collect());
    }
    let encoding = ansi_encoding(code_page);
    let (bytes, _, unmappable) = encoding.encode(text);
    if unmappable {
        let bad = text.chars().find(|c| encoding.encode(&c.to_string()).2).unwrap_or('?');
        return Err(bad);
    }
    Ok(bytes.into_owned())
}

/// A file's bytes as text: UTF-16 after its byte-order mark, else the ANSI code page `code_page`.
fn decode(bytes: &[u8], code_page: u16) -> Rc<str> {
    if let [0xFF, 0xFE, rest @ ..] = bytes {
        let units: Vec<u16> = rest.chunks_exact(2).map(|c| u16::from_le_bytes([c[0], c[1]])).collect();
        return String::from_utf16_lossy(&units).into();
    }
    ansi_encoding(code_page).decode_without_bom_handling(bytes).0.into()
}

/// The next line of `text` from `at`, and where the one after starts. `lf`: a lone LF ends a
/// line too (FileSystemObject's ReadLine); `Line Input #` ends lines at CR or CR LF only.
fn next_line(text: &str, at: usize, lf: bool) -> (&str, usize) {
    let rest = &text[at..];
    let end = rest.find(|c| c == '\r' || (lf && c == '\n')).unwrap_or(rest.len());
    let mut next = at + end;
    if rest[end..].starts_with("\r\n") {
        next += 2;
    } else if end < rest.len() {
        next += 1;
    }
    (&rest[..end], next)
}

/// One field of `Input #` from `at`: a quoted string, or text up to a comma or a line end
/// with spaces trimmed; and where the next field starts.
fn next_field(text: &str, at: usize) -> (Value, usize) {
    let rest = &text[at..];
    let lead = rest.len() - rest.trim_start_matches([' ', '\t']).len();
    let body = &rest[lead..];
    let (field, quoted, used) = match body.strip_prefix('"') {
        Some(inner) => {
            let close = inner.find('"').unwrap_or(inner.len());
            let after = &inner[(close + 1).min(inner.len())..];
            let skip = after.find([',', '\r', '\n']).unwrap_or(after.len());
            (&inner[..close], true, 1 + (close + 1).min(inner.len()) + skip)
        }
        None => {
            let end = body.find([',', '\r', '\n']).unwrap_or(body.len());
            (body[..end].trim_end(), false, end)
        }
    };
    let mut next = at + lead + used;
    if text[next..].starts_with("\r\n") {
        next += 2;
    } else if next < text.len() {
        next += 1;
    }
    let value = if quoted {
        Value::text(field)
    } else {
        match field.to_ascii_uppercase().as_str() {
            "" => Value::Blank,
            "#TRUE#" => Value::Bool(true),
            "#FALSE#" => Value::Bool(false),
            _ => match field.parse::<f64>() {
                Ok(n) if n.is_finite() => Value::Number(n),
                _ => Value::text(field),
            },
        }
    };
    (value, next)
}

impl Interp<'_, '_> {
    pub(super) fn file_error(&self, span: Span, (code, text): (u32, &str), what: String) -> Fault {
        let mut fault = self.fault_at(span, format!("{what}: {text} (run-time error {code})"));
        fault.code = code;
        fault
    }

    fn refused(&self, span: Span, message: String) -> Fault {
        let mut fault = self.fault_at(span, message);
        fault.code = REFUSED;
        fault
    }

    /// The refusal of `CreateObject("Scripting.FileSystemObject")` in a run given no files:
    /// untrappable, as skipping it would leave the macro writing its program nowhere.
    fn without_files(&self, link: &Link) -> Fault {
        let message = format!(
            "{}(\"Scripting.FileSystemObject\"): file access needs a folder: run with `ncsheet run --out-dir DIR` \
             (the macro's files are plain names inside DIR, written when it succeeds) or --in-file FILE to read \
             one; this run was given neither",
            link.name
        );
        self.refused(link.span, message)
    }

    /// The ANSI code page text files are in ([`super::RunOptions::code_page`]).
    fn code_page(&self) -> u16 {
        self.options.code_page.unwrap_or(WESTERN)
    }

    pub(super) fn access(&self) -> &super::FileAccess {
        self.options.files.as_ref().expect("file statements parse only when the run has files")
    }

    /// `ThisWorkbook.Path`: the --out-dir folder as the user named it, the one folder a
    /// macro has (a real macro joins it with a file name: `ThisWorkbook.Path & "\prog.nc"`).
    pub(super) fn workbook_path(&self, link: &Link) -> Run<Obj> {
        match self.options.files.as_ref().and_then(|f| f.out_dir.as_deref()) {
            Some(dir) => Ok(Obj::Value(Value::text(folder_spelling(dir)))),
            None => Err(self.unsupported(
                link.span,
                "ThisWorkbook.Path: a macro's folder is the one given with `ncsheet run --out-dir DIR`, and this run \
                 has none",
            )),
        }
    }

    /// The sandbox name of a path the macro gave, or the refusal naming it. A path in the
    /// --out-dir folder as `ThisWorkbook.Path` spells it is the file name after it.
    fn sandbox_name(&self, what: &str, path: &str, span: Span) -> Run<String> {
        self.sandbox_pattern(what, path, false, span)
    }

    /// [`Interp::sandbox_name`], or with `wild` a pattern of such names (`*.nc`, `O????`:
    /// `Dir` and `Kill` take Windows' wildcards).
    fn sandbox_pattern(&self, what: &str, path: &str, wild: bool, span: Span) -> Run<String> {
        let dir = self.access().out_dir.as_deref().map(folder_spelling);
        let inside = dir
            .and_then(|d| path.strip_prefix(d.as_str())?.strip_prefix(['\\', '/']).map(str::to_string))
            .or_else(|| mapped_name(&self.options.mapped_dirs, path).map(str::to_string));
        let name = inside.as_deref().unwrap_or(path);
        let checked = if wild { name.replace(['*', '?'], "_") } else { name.to_string() };
        match checked_name(&checked) {
            None => Ok(name.to_string()),
            Some(why) => {
                let folder = match &self.access().out_dir {
                    Some(dir) => format!("the --out-dir folder ({dir})"),
                    None => "the --out-dir folder".to_string(),
                };
                Err(self.refused(
                    span,
                    format!(
                        "{what} \"{path}\": refused: {why}; a macro's files are plain names (program.nc) inside \
                         {folder} or the files given with --in-file"
                    ),
                ))
            }
        }
    }

    /// The text of a file to read: written earlier in this run, a listed input, or in the
    /// output folder; `None` when there is none.
    fn read_text(&self, what: &str, name: &str, span: Span) -> Run<Option<(Rc<str>, usize)>> {
        let files = self.files.borrow();
        if files.writing(name) {
            return Err(self.file_error(span, ALREADY_OPEN, format!("{what} \"{name}\": it is open for writing")));
        }
        let bytes: Option<Vec<u8>> = match files.written_index(name) {
            Some(i) => Some(files.written[i].1.clone()),
            None => self.stored_bytes(what, name, span)?,
        };
        drop(files);
        let Some(bytes) = bytes else { return Ok(None) };
        let text = decode(&bytes, self.code_page());
        self.charge(text.len() as u64, span)?;
        Ok(Some((text, bytes.len())))
    }

    /// A listed input's bytes, or a file's of the output folder.
    fn stored_bytes(&self, what: &str, name: &str, span: Span) -> Run<Option<Vec<u8>>> {
        if self.files.borrow().is_removed(name) {
            return Ok(None);
        }
        let access = self.access();
        if let Some((_, bytes)) = access.inputs.iter().find(|(n, _)| n.eq_ignore_ascii_case(name)) {
            return Ok(Some(bytes.to_vec()));
        }
        if access.out_dir.is_none() {
            return Ok(None);
        }
        (access.read_out_dir)(name).map_err(|why| self.refused(span, format!("{what} \"{name}\": refused: {why}")))
    }

    /// Opens `name` for writing: a new empty file, or (appending) one that goes on from what
    /// the file holds. Returns the index of the written file.
    pub(super) fn open_for_writing(&self, what: &str, name: &str, append: bool, span: Span) -> Run<usize> {
        if self.access().out_dir.is_none() {
            return Err(self.refused(
                span,
                format!("{what} \"{name}\": refused: a macro writes files only inside a folder given with --out-dir"),
            ));
        }
        if self.access().inputs.iter().any(|(n, _)| n.eq_ignore_ascii_case(name)) {
            return Err(self.refused(
                span,
                format!("{what} \"{name}\": refused: it is an input (--in-file), which a run never writes over"),
            ));
        }
        if self.files.borrow().writing(name) {
            return Err(self.file_error(span, ALREADY_OPEN, format!("{what} \"{name}\"")));
        }
        let existing = self.files.borrow().written_index(name);
        let start = match (existing, append) {
            (Some(i), true) => std::mem::take(&mut self.files.borrow_mut().written[i].1),
            (None, true) => self.stored_bytes(what, name, span)?.unwrap_or_default(),
            _ => Vec::new(),
        };
        let entry = if existing.is_some() { 0 } else { STREAM_BYTES + name.len() as u64 };
        self.charge(start.len() as u64 + entry, span)?;
        let mut files = self.files.borrow_mut();
        // Written again after a Kill: the new file replaces the one deleted.
        files.removed.retain(|n| !n.eq_ignore_ascii_case(name));
        Ok(match existing {
            Some(i) => {
                files.written[i].1 = start;
                i
            }
            None => files.add_written(name, start),
        })
    }

    /// The column a written file's last line has reached.
    fn end_column(&self, file: usize) -> usize {
        let files = self.files.borrow();
        let bytes = &files.written[file].1;
        bytes.iter().rev().take_while(|&&b| b != b'\n').count()
    }

    // ---- statements ---------------------------------------------------------------------

    pub(super) fn file_stmt(&self, stmt: &FileStmt, span: Span) -> Run<()> {
        match stmt {
            FileStmt::Open { path, mode, number, len } => self.open(path, *mode, number, len.as_ref(), span),
            FileStmt::Put { number, record, data } => self.put_record(number, record.as_ref(), data, span),
            FileStmt::Get { number, record, target } => self.get_record(number, record.as_ref(), target, span),
            FileStmt::Seek { number, position } => self.seek_record(number, position, span),
            FileStmt::Print { number, items } => self.print_file(number, items, span),
            FileStmt::Write { number, items, open } => self.write_file(number, items, *open, span),
            FileStmt::LineInput { number, target } => {
                let n = self.file_no(number)?;
                let line = self.read_from(Channels::Numbered(n), span, |text, at| {
                    let (line, next) = next_line(text, at, false);
                    (Value::text(line), next)
                })?;
                self.store_input(target, line, span)
            }
            FileStmt::Input { number, targets } => {
                let n = self.file_no(number)?;
                for target in targets {
                    let value = self.read_from(Channels::Numbered(n), span, next_field)?;
                    self.store_input(target, value, span)?;
                }
                Ok(())
            }
            FileStmt::Close(numbers) => {
                if numbers.is_empty() {
                    self.files.borrow_mut().numbered.clear();
                    self.files.borrow_mut().records.clear();
                }
                for e in numbers {
                    let n = self.file_no(e)?;
                    self.files.borrow_mut().numbered.remove(&n);
                    self.files.borrow_mut().records.remove(&n);
                }
                Ok(())
            }
        }
    }

    /// A file number, 1 to 511 (VBA's range; `#` is optional).
    pub(super) fn file_no(&self, e: &Expr) -> Run<i64> {
        let n = self.index(e, "the file number")?;
        if !(1..=511).contains(&n) {
            return Err(self.file_error(self.expr_span(e), BAD_NUMBER, format!("file number {n}")));
        }
        Ok(n)
    }

    fn open(&self, path: &Expr, mode: Mode, number: &Expr, len: Option<&Expr>, span: Span) -> Run<()> {
        let v = self.eval(path)?;
        let shown = print_text(&v);
        let n = self.file_no(number)?;
        if self.files.borrow().numbered.contains_key(&n) || self.files.borrow().records.contains_key(&n) {
            return Err(self.file_error(span, ALREADY_OPEN, format!("Open … As #{n}")));
        }
        let name = self.sandbox_name("Open", &shown, span)?;
        let way = match mode {
            Mode::Binary | Mode::Random => return self.open_record_file(name, n, mode == Mode::Random, len, span),
            Mode::Input => {
                let Some((text, bytes)) = self.read_text("Open", &name, span)? else {
                    return Err(self.not_found("Open", &name, span));
                };
                Way::Read { text, at: 0, bytes }
            }
            Mode::Output | Mode::Append => {
                let file = self.open_for_writing("Open", &name, mode == Mode::Append, span)?;
                Way::Write { file, column: self.end_column(file), unicode: false }
            }
        };
        self.files.borrow_mut().numbered.insert(n, Channel { name, way });
        Ok(())
    }

    fn not_found(&self, what: &str, name: &str, span: Span) -> Fault {
        let folder = match &self.access().out_dir {
            Some(dir) => format!("in the --out-dir folder ({dir}) or "),
            None => String::new(),
        };
        self.file_error(span, NOT_FOUND, format!("{what} \"{name}\": no such file {folder}among the --in-file files"))
    }

    /// Appends text to an open file, counted in the memory budget.
    fn put_text(&self, channel: Channels, text: &str, span: Span) -> Run<()> {
        let (file, unicode, name) = self.writer(channel, span)?;
        let code_page = self.code_page();
        let bytes = encode(text, unicode, code_page).map_err(|c| {
            self.unsupported(
                span,
                format!(
                    "\"{name}\": the character {c:?} (U+{:04X}) has no place in {}, the code page VBA writes \
                     text files in (FileSystemObject's CreateTextFile(name, True, True) writes Unicode){}",
                    c as u32,
                    code_page_name(code_page),
                    if self.options.code_page.is_none() {
                        "; `ncsheet run --code-page N` names the code page of the Excel the macro is for \
                         (936 Simplified Chinese, 932 Japanese, 1251 Cyrillic …)"
                    } else {
                        ""
                    }
                ),
            )
        })?;
        self.charge(bytes.len() as u64, span)?;
        let mut files = self.files.borrow_mut();
        files.written[file].1.extend_from_slice(&bytes);
        let column = match text.rfind('\n') {
            Some(i) => text[i + 1..].chars().count(),
            None => self.column_of(&files, channel) + text.chars().count(),
        };
        if let Some(Channel { way: Way::Write { column: c, .. }, .. }) = files.channel_mut(channel) {
            *c = column;
        }
        Ok(())
    }

    fn column_of(&self, files: &Files, channel: Channels) -> usize {
        match files.channel(channel) {
            Some(Channel { way: Way::Write { column, .. }, .. }) => *column,
            _ => 0,
        }
    }

    /// The written file an open channel writes: (index, Unicode, name).
    fn writer(&self, channel: Channels, span: Span) -> Run<(usize, bool, String)> {
        let files = self.files.borrow();
        match files.channel(channel) {
            Some(Channel { name, way: Way::Write { file, unicode, .. } }) => Ok((*file, *unicode, name.clone())),
            Some(Channel { name, .. }) => {
                Err(self.file_error(span, BAD_MODE, format!("\"{name}\" is open for reading, not writing")))
            }
            None => Err(self.closed(channel, span)),
        }
    }

    fn closed(&self, channel: Channels, span: Span) -> Fault {
        match channel {
            Channels::Numbered(n) => self.file_error(span, BAD_NUMBER, format!("file #{n} is not open")),
            Channels::Stream(_) => self.file_error(span, BAD_NUMBER, "the TextStream is closed".to_string()),
        }
    }

    /// Reads with `take` (a line, a field) from an open file, or fails past its end.
    fn read_from(&self, channel: Channels, span: Span, take: impl Fn(&str, usize) -> (Value, usize)) -> Run<Value> {
        let mut files = self.files.borrow_mut();
        match files.channel_mut(channel) {
            Some(Channel { name, way: Way::Read { text, at, .. } }) => {
                if *at >= text.len() {
                    return Err(self.file_error(span, PAST_END, format!("\"{name}\"")));
                }
                let (value, next) = take(text, *at);
                *at = next;
                Ok(value)
            }
            Some(Channel { name, .. }) => {
                Err(self.file_error(span, BAD_MODE, format!("\"{name}\" is open for writing, not reading")))
            }
            None => Err(self.closed(channel, span)),
        }
    }

    /// Whether an open file is read to its end (`EOF`, `AtEndOfStream`).
    fn at_end(&self, channel: Channels, span: Span) -> Run<bool> {
        let files = self.files.borrow();
        match files.channel(channel) {
            Some(Channel { way: Way::Read { text, at, .. }, .. }) => Ok(*at >= text.len()),
            Some(Channel { name, .. }) => {
                Err(self.file_error(span, BAD_MODE, format!("\"{name}\" is open for writing, not reading")))
            }
            None => Err(self.closed(channel, span)),
        }
    }

    fn store_input(&self, target: &Target, value: Value, span: Span) -> Run<()> {
        match target {
            Target::Var(name) => self.set_var(name, Var::Value(value), span),
            Target::Element(name, index) => self.set_element(name, index, value, false, span),
            Target::Node(_) => Err(self.fault_at(span, "Input # and Line Input # read into a variable")),
        }
    }

    fn print_file(&self, number: &Expr, items: &[PrintPart], span: Span) -> Run<()> {
        let channel = Channels::Numbered(self.file_no(number)?);
        self.writer(channel, span)?;
        let mut open = false;
        for item in items {
            open = false;
            let column = self.column_of(&self.files.borrow(), channel);
            let text = match item {
                PrintPart::Value(e) => {
                    let v = self.eval(e)?;
                    if let Value::Array(_) = v {
                        return Err(self.fault_at(self.expr_span(e), "Print # prints values, not arrays"));
                    }
                    match self.as_date(e, &v) {
                        Some(date) => super::value::date_text(date),
                        None => print_form(&v),
                    }
                }
                PrintPart::Join => {
                    open = true;
                    continue;
                }
                // A zone or a Tab is where the next item goes: the line stays open after it.
                PrintPart::Zone | PrintPart::Tab(None) => {
                    open = true;
                    " ".repeat(ZONE - column % ZONE)
                }
                PrintPart::Spc(e) => self.repeated(" ", self.index(e, "Spc's count")?, "Spc", span)?,
                PrintPart::Tab(Some(e)) => {
                    open = true;
                    // Columns count from 1; a column already passed is on the next line.
                    let to = self.index(e, "Tab's column")?.max(1) as usize - 1;
                    if to >= column {
                        self.repeated(" ", (to - column) as i64, "Tab", span)?
                    } else {
                        format!("\r\n{}", self.repeated(" ", to as i64, "Tab", span)?)
                    }
                }
            };
            self.put_text(channel, &text, span)?;
        }
        if !open {
            self.put_text(channel, "\r\n", span)?;
        }
        Ok(())
    }

    fn write_file(&self, number: &Expr, items: &[Expr], open: bool, span: Span) -> Run<()> {
        let channel = Channels::Numbered(self.file_no(number)?);
        self.writer(channel, span)?;
        let mut line = String::new();
        for (i, e) in items.iter().enumerate() {
            let v = self.eval(e)?;
            if let Value::Array(_) = v {
                return Err(self.fault_at(self.expr_span(e), "Write # writes values, not arrays"));
            }
            if i > 0 {
                line.push(',');
            }
            match self.as_date(e, &v) {
                Some(date) => line.push_str(&super::value::universal_date_text(date)),
                None => line.push_str(&write_form(&v)),
            }
        }
        if open {
            line.push(',');
        } else {
            line.push_str("\r\n");
        }
        self.put_text(channel, &line, span)
    }

    // ---- expressions and objects ------------------------------------------------------

    /// `FreeFile`, `EOF(n)`, `LOF(n)`, `CreateObject("Scripting.FileSystemObject")`.
    pub(super) fn file_root(&self, ctx: &mut Ctx, link: &Link) -> Run<Obj> {
        if self.options.files.is_none() {
            return Err(self.without_files(link));
        }
        let args = self.values(ctx, link)?;
        let number = |what: &str| -> Run<i64> {
            let n = args.first().ok_or_else(|| self.fault_at(link.span, format!("{what} needs a file number")))?;
            let n = self.number_of(n, "the file number").map_err(|m| self.fault_at(link.span, m))?;
            Ok(n.round_ties_even() as i64)
        };
        let value = |v: Value| Ok(Obj::Value(v));
        match super::objects::lower(link).as_str() {
            "freefile" => {
                let high = match args.first() {
                    Some(v) => self.number_of(v, "FreeFile's range").map_err(|m| self.fault_at(link.span, m))? != 0.0,
                    None => false,
                };
                let range = if high { 256..=511 } else { 1..=255 };
                let files = self.files.borrow();
                let free =
                    range.into_iter().find(|n| !files.numbered.contains_key(n) && !files.records.contains_key(n));
                match free {
                    Some(n) => value(Value::Number(n as f64)),
                    None => Err(self.file_error(link.span, TOO_MANY, "FreeFile".to_string())),
                }
            }
            what @ ("eof" | "lof" | "loc" | "seek") if self.record_file_query(what, number(what)?).is_some() => {
                value(self.record_file_query(what, number(what)?).expect("a Binary or Random file"))
            }
            "loc" | "seek" => {
                let n = number(&link.name)?;
                Err(self.file_error(link.span, BAD_MODE, format!("{}(#{n}): not a Binary or Random file", link.name)))
            }
            "eof" => value(Value::Bool(self.at_end(Channels::Numbered(number("EOF")?), link.span)?)),
            "lof" => {
                let n = number("LOF")?;
                let files = self.files.borrow();
                let length = match files.numbered.get(&n).map(|c| &c.way) {
                    Some(Way::Read { bytes, .. }) => *bytes,
                    Some(Way::Write { file, .. }) => files.written[*file].1.len(),
                    None => return Err(self.closed(Channels::Numbered(n), link.span)),
                };
                value(Value::Number(length as f64))
            }
            "kill" => self.kill(&args, link.span).map(|()| Obj::Value(Value::Blank)),
            "dir" => self.dir(&args, link.span).map(|name| Obj::Value(Value::text(name))),
            "filelen" => {
                let name =
                    self.sandbox_name("FileLen", &args.first().map(print_text).unwrap_or_default(), link.span)?;
                match self.current_bytes("FileLen", &name, link.span)? {
                    Some(bytes) => value(Value::Number(bytes.len() as f64)),
                    None => Err(self.not_found("FileLen", &name, link.span)),
                }
            }
            "filedatetime" => {
                let name =
                    self.sandbox_name("FileDateTime", &args.first().map(print_text).unwrap_or_default(), link.span)?;
                let serial = self.file_date_time(&name, link.span)?;
                self.gave_date(true);
                value(Value::Number(serial))
            }
            "filecopy" => self.file_copy(&args, link.span).map(|()| Obj::Value(Value::Blank)),
            // Subfolders stay refused: every part of a path would have to be checked for a
            // symbolic link at the moment each file is written, which a link made between the
            // check and the write would get around; plain names in one folder have no such parts.
            "mkdir" | "rmdir" => Err(self.refused(
                link.span,
                format!(
                    "{}: refused: a macro's files are plain names inside the one --out-dir folder, which has no \
                     folders of its own (a folder part could lead out through a symbolic link); write the files \
                     into --out-dir itself",
                    link.name
                ),
            )),
            _ => Ok(Obj::Files(FileObj::System)),
        }
    }

    /// `FileDateTime(name)` ("FileDateTime function"): when the file was last modified, a
    /// Date in local time to the second. A file this run writes is written when the run
    /// ends, so its time is the run's clock now; a listed input (`--in-file`) has no time in
    /// the sandbox, which sees only its bytes.
    fn file_date_time(&self, name: &str, span: Span) -> Run<f64> {
        if self.files.borrow().written_index(name).is_some() {
            return Ok(crate::eval::evaluator::Env::now(self));
        }
        if self.files.borrow().is_removed(name) {
            return Err(self.not_found("FileDateTime", name, span));
        }
        let access = self.access();
        if access.inputs.iter().any(|(n, _)| n.eq_ignore_ascii_case(name)) {
            let why = format!(
                "FileDateTime \"{name}\": an --in-file file is read for its bytes only; its date is not part of \
                 the run (put the file in --out-dir to read its date)"
            );
            return Err(self.refused(span, why));
        }
        let modified = match access.out_dir {
            Some(_) => (access.modified_out_dir)(name)
                .map_err(|why| self.refused(span, format!("FileDateTime \"{name}\": refused: {why}")))?,
            None => None,
        };
        let modified = modified.ok_or_else(|| self.not_found("FileDateTime", name, span))?;
        Ok(local_serial(modified))
    }

    /// A file's bytes as they stand now: written this run, or listed, or in the folder.
    fn current_bytes(&self, what: &str, name: &str, span: Span) -> Run<Option<Vec<u8>>> {
        if let Some(i) = self.files.borrow().written_index(name) {
            return Ok(Some(self.files.borrow().written[i].1.clone()));
        }
        self.stored_bytes(what, name, span)
    }

    /// Refuses a file that is open (error 75, as VBA's Kill and FileCopy of an open file).
    fn not_open(&self, what: &str, name: &str, span: Span) -> Run<()> {
        let files = self.files.borrow();
        let open = |c: &Channel| c.name.eq_ignore_ascii_case(name);
        if files.numbered.values().any(open) || files.streams.iter().flatten().any(open) {
            return Err(self.file_error(span, ACCESS, format!("{what} \"{name}\": the file is open")));
        }
        Ok(())
    }

    /// The files a pattern names: the one name without wildcards (if it exists), else the
    /// output folder's files and those written this run that match it, in name order.
    fn matching(&self, what: &str, pattern: &str, span: Span) -> Run<Vec<String>> {
        if !pattern.contains(['*', '?']) {
            return Ok(if self.exists(pattern, span)? { vec![pattern.to_string()] } else { Vec::new() });
        }
        let listed = match self.access().out_dir {
            Some(_) => (self.access().list_out_dir)().map_err(|why| self.refused(span, format!("{what}: {why}")))?,
            None => Vec::new(),
        };
        let files = self.files.borrow();
        let mut names: Vec<String> = listed.into_iter().filter(|n| !files.is_removed(n)).collect();
        for (name, _) in files.live_written() {
            if !names.iter().any(|n| n.eq_ignore_ascii_case(name)) {
                names.push(name.clone());
            }
        }
        let pattern = pattern.to_lowercase();
        names.retain(|n| wildcard_matches(&pattern, &n.to_lowercase()));
        names.sort_by_key(|n| n.to_lowercase());
        Ok(names)
    }

    /// `Kill pathname` ("Kill statement"): deletes the files it names (wildcards allowed); none
    /// is error 53, an open one error 75. A file written this run is dropped; one of the
    /// folder is removed when the run succeeds (all or nothing, as the writes are); a listed
    /// input is never deleted.
    fn kill(&self, args: &[Value], span: Span) -> Run<()> {
        let path = args.first().map(print_text).unwrap_or_default();
        let pattern = self.sandbox_pattern("Kill", &path, true, span)?;
        let names = self.matching("Kill", &pattern, span)?;
        if names.is_empty() {
            return Err(self.not_found("Kill", &pattern, span));
        }
        for name in names {
            if self.access().inputs.iter().any(|(n, _)| n.eq_ignore_ascii_case(&name)) {
                return Err(self.refused(
                    span,
                    format!("Kill \"{name}\": refused: it is an input (--in-file), which a run never deletes"),
                ));
            }
            self.not_open("Kill", &name, span)?;
            let written = self.files.borrow().written_index(&name);
            if let Some(i) = written {
                self.files.borrow_mut().remove_written(i);
            }
            if self.access().out_dir.is_some() && self.stored_bytes("Kill", &name, span)?.is_some() {
                self.files.borrow_mut().removed.push(name);
            }
        }
        Ok(())
    }

    /// `Dir[(pathname[, attributes])]` ("Dir function"): the first file name the pattern
    /// matches ("" when none); `Dir` alone the next match of the last pattern, "" after the
    /// last, and error 5 once that "" was returned. The sandbox has files only, so the
    /// attributes find nothing more.
    fn dir(&self, args: &[Value], span: Span) -> Run<String> {
        let Some(path) = args.first() else {
            let mut files = self.files.borrow_mut();
            let Some(left) = files.dir_left.as_mut() else {
                let why = "Dir without a pattern, before any Dir(pattern) or after its last file";
                return Err(self.file_error(span, INVALID_CALL, why.to_string()));
            };
            let next = left.pop_front();
            if next.is_none() {
                files.dir_left = None;
            }
            return Ok(next.unwrap_or_default());
        };
        let path = match print_text(path) {
            p if p.is_empty() => "*".to_string(),
            p => p,
        };
        let pattern = self.sandbox_pattern("Dir", &path, true, span)?;
        let mut names: std::collections::VecDeque<String> = self.matching("Dir", &pattern, span)?.into();
        let first = names.pop_front();
        self.files.borrow_mut().dir_left = first.as_ref().map(|_| names);
        Ok(first.unwrap_or_default())
    }

    /// `FileCopy source, destination` ("FileCopy statement"): the destination, a file of the
    /// output folder, gets the source's bytes as they stand; an open file is error 75.
    fn file_copy(&self, args: &[Value], span: Span) -> Run<()> {
        let text = |i: usize| args.get(i).map(print_text).unwrap_or_default();
        let source = self.sandbox_name("FileCopy", &text(0), span)?;
        let destination = self.sandbox_name("FileCopy", &text(1), span)?;
        self.not_open("FileCopy", &source, span)?;
        self.not_open("FileCopy", &destination, span)?;
        let Some(bytes) = self.current_bytes("FileCopy", &source, span)? else {
            return Err(self.not_found("FileCopy", &source, span));
        };
        let file = self.open_for_writing("FileCopy", &destination, false, span)?;
        self.charge(bytes.len() as u64, span)?;
        self.files.borrow_mut().written[file].1 = bytes;
        Ok(())
    }

    /// A member of the FileSystemObject or of a TextStream.
    pub(super) fn file_member(&self, ctx: &mut Ctx, obj: FileObj, link: &Link) -> Run<Obj> {
        let name = super::objects::lower(link);
        let args = self.arranged_values(ctx, link, &name)?;
        let span = link.span;
        let text_arg = |i: usize| args.get(i).map(print_text).unwrap_or_default();
        let flag = |i: usize, default: bool| match args.get(i) {
            None | Some(Value::Blank) => Ok(default),
            Some(v) => crate::eval::coerce::to_bool(v).map_err(|e| self.fault_at(span, format!("{}: {e}", link.name))),
        };
        let blank = Ok(Obj::Value(Value::Blank));
        match (obj, name.as_str()) {
            (FileObj::System, "createtextfile") => {
                let name = self.sandbox_name("CreateTextFile", &text_arg(0), span)?;
                let (overwrite, unicode) = (flag(1, true)?, flag(2, false)?);
                if !overwrite && self.exists(&name, span)? {
                    return Err(self.file_error(span, EXISTS, format!("CreateTextFile \"{name}\"")));
                }
                let file = self.open_for_writing("CreateTextFile", &name, false, span)?;
                if unicode {
                    self.files.borrow_mut().written[file].1.extend_from_slice(&[0xFF, 0xFE]);
                }
                self.new_stream(name, Way::Write { file, column: 0, unicode }, span)
            }
            (FileObj::System, "opentextfile") => {
                let name = self.sandbox_name("OpenTextFile", &text_arg(0), span)?;
                let mode = match args.get(1) {
                    None | Some(Value::Blank) => 1.0,
                    Some(v) => self.number_of(v, "OpenTextFile's IOMode").map_err(|m| self.fault_at(span, m))?,
                };
                let create = flag(2, false)?;
                let unicode = matches!(args.get(3), Some(Value::Number(n)) if *n == -1.0);
                if mode != 1.0 && mode != 2.0 && mode != 8.0 {
                    let why = "IOMode is ForReading (1), ForWriting (2) or ForAppending (8)";
                    return Err(self.file_error(span, (5, errors::description(5)), format!("OpenTextFile: {why}")));
                }
                if !create && !self.exists(&name, span)? {
                    return Err(self.not_found("OpenTextFile", &name, span));
                }
                if mode == 1.0 {
                    let (text, bytes) = self.read_text("OpenTextFile", &name, span)?.unwrap_or(("".into(), 0));
                    return self.new_stream(name, Way::Read { text, at: 0, bytes }, span);
                }
                let file = self.open_for_writing("OpenTextFile", &name, mode == 8.0, span)?;
                let unicode = unicode || self.files.borrow().written[file].1.starts_with(&[0xFF, 0xFE]);
                self.new_stream(name, Way::Write { file, column: self.end_column(file), unicode }, span)
            }
            (
                FileObj::System,
                "getfilename" | "getbasename" | "getextensionname" | "getparentfoldername" | "getdrivename",
            ) => Ok(Obj::Value(Value::text(path_text(&name, &text_arg(0))))),
            (FileObj::System, "buildpath") => {
                Ok(Obj::Value(Value::text(super::path_names::build_path(&text_arg(0), &text_arg(1)))))
            }
            (FileObj::System, "folderexists") => Ok(Obj::Value(Value::Bool(self.folder_exists(&text_arg(0), span)?))),
            (FileObj::System, "fileexists") => {
                let name = self.sandbox_name("FileExists", &text_arg(0), span)?;
                Ok(Obj::Value(Value::Bool(self.exists(&name, span)?)))
            }
            (FileObj::Stream(id), "writeline") => {
                self.put_text(Channels::Stream(id), &format!("{}\r\n", text_arg(0)), span)?;
                blank
            }
            (FileObj::Stream(id), "write") => {
                self.put_text(Channels::Stream(id), &text_arg(0), span)?;
                blank
            }
            (FileObj::Stream(id), "writeblanklines") => {
                let n = args.first().map_or(Ok(1.0), |v| self.number_of(v, "WriteBlankLines' count"));
                let n = n.map_err(|m| self.fault_at(span, m))?.round_ties_even();
                let lines = self.repeated("\r\n", n.clamp(0.0, i64::MAX as f64) as i64, "WriteBlankLines", span)?;
                self.put_text(Channels::Stream(id), &lines, span)?;
                blank
            }
            (FileObj::Stream(id), "readline") => {
                let line = self.read_from(Channels::Stream(id), span, |text, at| {
                    let (line, next) = next_line(text, at, true);
                    (Value::text(line), next)
                })?;
                Ok(Obj::Value(line))
            }
            (FileObj::Stream(id), "skipline") => {
                self.read_from(Channels::Stream(id), span, |text, at| (Value::Blank, next_line(text, at, true).1))?;
                blank
            }
            (FileObj::Stream(id), "readall") => {
                if self.at_end(Channels::Stream(id), span)? {
                    return Err(self.file_error(span, PAST_END, "ReadAll".to_string()));
                }
                let all =
                    self.read_from(Channels::Stream(id), span, |text, at| (Value::text(&text[at..]), text.len()))?;
                Ok(Obj::Value(all))
            }
            (FileObj::Stream(id), "atendofstream") => {
                Ok(Obj::Value(Value::Bool(self.at_end(Channels::Stream(id), span)?)))
            }
            (FileObj::Stream(id), "close") => {
                if let Some(slot) = self.files.borrow_mut().streams.get_mut(id) {
                    *slot = None;
                }
                blank
            }
            (obj, _) => self.unmodelled(&Obj::Files(obj), link),
        }
    }

    /// `unit` `n` times (none for less than one), within the longest string a macro may make.
    fn repeated(&self, unit: &str, n: i64, what: &str, span: Span) -> Run<String> {
        let n = n.max(0) as usize;
        if n.saturating_mul(unit.len()) > self.options.max_string {
            let limit = self.options.max_string;
            let mut f = self.fault_at(
                span,
                format!(
                    "{what}: {n} times is past the longest string a macro may make ({limit}; {})",
                    self.options.raise_hint("raise it with --max-string")
                ),
            );
            f.kind = super::ErrorKind::Limit;
            return Err(f);
        }
        Ok(unit.repeat(n))
    }

    /// A new TextStream, its place counted in the memory budget (a loop opening streams
    /// without end is stopped like one filling an array).
    fn new_stream(&self, name: String, way: Way, span: Span) -> Run<Obj> {
        self.charge(STREAM_BYTES, span)?;
        let mut files = self.files.borrow_mut();
        files.streams.push(Some(Channel { name, way }));
        Ok(Obj::Files(FileObj::Stream(files.streams.len() - 1)))
    }

    /// A FileSystemObject or TextStream method's arguments in the order of its parameters:
    /// `fso.CreateTextFile(p, Overwrite:=True)` as `fso.CreateTextFile(p, True)`. A name the
    /// method does not have is VBA's error 448, "Named argument not found".
    fn arranged_values(&self, ctx: &mut Ctx, link: &Link, method: &str) -> Run<Vec<Value>> {
        let args = link.args.as_deref().unwrap_or(&[]);
        if args.iter().all(|a| a.name.is_none()) {
            return self.values(ctx, link);
        }
        let parameters = file_method_parameters(method);
        let mut out = vec![Value::Blank; args.len().max(parameters.len())];
        for (i, arg) in args.iter().enumerate() {
            let at = match &arg.name {
                None => i,
                Some(n) => parameters.iter().position(|p| p.eq_ignore_ascii_case(n)).ok_or_else(|| {
                    let mut f = self.fault_at(
                        link.span,
                        format!("Named argument not found (run-time error 448): {}:={n}", link.name),
                    );
                    f.code = 448;
                    f
                })?,
            };
            out[at] = ctx.eval(&arg.value).unwrap_single();
            self.take_pending()?;
        }
        while out.last().is_some_and(|v| matches!(v, Value::Blank)) {
            out.pop();
        }
        Ok(out)
    }

    /// `FolderExists(path)`: the output folder exists (as `ThisWorkbook.Path` spells it, or
    /// with a separator after it); the sandbox has no other folder, so a name inside it is
    /// False, and any other path is refused by name as a file's would be.
    fn folder_exists(&self, path: &str, span: Span) -> Run<bool> {
        let folder = self.access().out_dir.as_deref().map(folder_spelling);
        if folder.is_some_and(|f| path.trim_end_matches(['\\', '/']) == f.trim_end_matches(['\\', '/'])) {
            return Ok(true);
        }
        self.sandbox_name("FolderExists", path, span)?;
        Ok(false)
    }

    /// Whether a file of the sandbox exists: written this run, listed, or in the folder (and
    /// not deleted since).
    fn exists(&self, name: &str, span: Span) -> Run<bool> {
        if self.files.borrow().written_index(name).is_some() {
            return Ok(true);
        }
        Ok(self.stored_bytes("FileExists", name, span)?.is_some())
    }
}

/// A moment as a VBA Date in local time (days as the 1900 system counts them), to the
/// second as file times are shown.
fn local_serial(t: std::time::SystemTime) -> f64 {
    use chrono::{Datelike, Timelike};
    let local = chrono::DateTime::<chrono::Local>::from(t).naive_local();
    let day = crate::eval::dates::serial_from_ymd(
        crate::eval::dates::DateSystem::From1900,
        i64::from(local.year()),
        i64::from(local.month()),
        i64::from(local.day()),
    );
    day as f64 + f64::from(local.num_seconds_from_midnight()) / 86_400.0
}

/// An open file by its number or as a TextStream.
#[derive(Clone, Copy, Debug)]
enum Channels {
    Numbered(i64),
    Stream(usize),
}

impl Files {
    fn channel(&self, c: Channels) -> Option<&Channel> {
        match c {
            Channels::Numbered(n) => self.numbered.get(&n),
            Channels::Stream(id) => self.streams.get(id).and_then(Option::as_ref),
        }
    }

    fn channel_mut(&mut self, c: Channels) -> Option<&mut Channel> {
        match c {
            Channels::Numbered(n) => self.numbered.get_mut(&n),
            Channels::Stream(id) => self.streams.get_mut(id).and_then(Option::as_mut),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_names_pass_and_every_way_out_is_refused() {
        for ok in ["program.nc", "O1234", "part 2.nc", ".hidden", "a.b.c", "CONFIG.txt", "com10.txt"] {
            assert_eq!(checked_name(ok), None, "{ok}");
        }
        let refused = [
            ("", "a file needs a name"),
            ("../x.nc", "leaves the folder"),
            ("..", "leaves the folder"),
            ("sub/../../x", "leaves the folder"),
            ("/etc/passwd", "an absolute path"),
            ("\\x.nc", "an absolute path"),
            ("C:\\out.nc", "a drive letter"),
            ("c:out.nc", "a drive letter"),
            ("\\\\server\\share\\x.nc", "UNC"),
            ("//server/share/x.nc", "UNC"),
            ("\\\\?\\C:\\x", "an extended-length path"),
            ("\\\\?\\UNC\\server\\share\\x", "an extended-length path"),
            ("//?/C:/x", "an extended-length path"),
            ("\\\\.\\COM1", "a Windows device path"),
            ("sub\\x.nc", "a backslash"),
            ("sub/x.nc", "a folder part"),
            ("a.txt:stream", "alternate data stream"),
            ("CON", "device"),
            ("nul.txt", "device"),
            ("Com1.nc", "device"),
            ("LPT9", "device"),
            ("aux .txt", "device"),
            ("a?.nc", "forbids"),
            ("x.nc.", "trailing dot"),
            ("x.nc ", "trailing dot or space"),
            ("a\nb", "control character"),
        ];
        for (path, why) in refused {
            let got = checked_name(path).unwrap_or_else(|| panic!("{path:?} passed"));
            assert!(got.contains(why), "{path:?}: {got}");
        }
        assert!(checked_name(&"x".repeat(256)).is_some());
    }

    #[test]
    fn input_fields_read_as_write_wrote_them() {
        // "Write # statement": `"Hello World",234` then `#TRUE#`.
        let text = "\"Hello World\",234\r\n#TRUE#,  -1.5 ,plain text\r\n";
        let (a, at) = next_field(text, 0);
        let (b, at) = next_field(text, at);
        let (c, at) = next_field(text, at);
        let (d, at) = next_field(text, at);
        let (e, at) = next_field(text, at);
        assert_eq!(
            (a, b, c, d, e),
            (
                Value::text("Hello World"),
                Value::Number(234.0),
                Value::Bool(true),
                Value::Number(-1.5),
                Value::text("plain text")
            )
        );
        assert_eq!(at, text.len());
    }

    #[test]
    fn line_input_ends_lines_at_cr_and_crlf_readline_at_lf_too() {
        assert_eq!(next_line("a\r\nb", 0, false), ("a", 3));
        assert_eq!(next_line("a\rb", 0, false), ("a", 2));
        assert_eq!(next_line("a\nb", 0, false), ("a\nb", 3));
        assert_eq!(next_line("a\nb", 0, true), ("a", 2));
    }
}
