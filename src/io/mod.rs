//! Files in and out. The file type is chosen by extension: `.csv` now; `.xlsx` is recognised
//! and refused with a clear error until its reader and writer exist.
//!
//! To add a format: write `io/<format>.rs` with a reader (bytes → [`Workbook`]) and a writer
//! (workbook → bytes), add a [`Format`] variant and its arms in [`load`], [`save`] and
//! [`export`], and round-trip tests in `tests/`. Writing always goes through
//! [`atomic::write_file`], so a failed save never leaves a half-written file.
//!
//! Nothing here prints: every failure is an [`Error`] naming the file (and the line, for a
//! malformed csv), which the command line renders once.

use std::fmt;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::formula::address::Rect;
use crate::formula::ast::SheetId;
use crate::workbook::Workbook;

pub mod atomic;
pub mod cam;
pub mod csv;

/// The file types ncsheet knows, by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Csv,
    Xlsx,
}

impl Format {
    /// The format of a file from its extension (case-insensitive).
    pub fn of(path: &Path) -> Result<Format, Error> {
        let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("csv") => Ok(Format::Csv),
            Some("xlsx") => Ok(Format::Xlsx),
            _ => Err(Error::new(path, ErrorKind::UnknownFormat)),
        }
    }
}

/// What an export writes for each cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Content {
    /// Computed values, as the sheet shows them.
    Values,
    /// What was typed: formulas as `=…` text, constants as they read back.
    Formulas,
}

/// Which part of a workbook an export writes.
#[derive(Clone, Copy, Debug)]
pub struct Export {
    pub sheet: SheetId,
    /// `None`: from A1 to the last used row and column.
    pub range: Option<Rect>,
    pub content: Content,
}

/// A file that could not be read or written, and why.
#[derive(Debug)]
pub struct Error {
    pub path: PathBuf,
    pub kind: ErrorKind,
}

#[derive(Debug)]
pub enum ErrorKind {
    Read(std::io::Error),
    Write(std::io::Error),
    /// The text is not a valid csv file; `line` is 1-based.
    Malformed {
        line: u64,
        message: String,
    },
    UnknownFormat,
    /// A format ncsheet will read and write but does not yet.
    NotYetSupported(Format),
    /// A csv file holds one sheet; the workbook has several.
    OneSheetOnly {
        sheets: usize,
    },
}

impl Error {
    pub fn new(path: &Path, kind: ErrorKind) -> Error {
        Error { path: path.to_path_buf(), kind }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: ", self.path.display())?;
        match &self.kind {
            ErrorKind::Read(e) => write!(f, "cannot read: {e}"),
            ErrorKind::Write(e) => write!(f, "cannot write: {e}"),
            ErrorKind::Malformed { line, message } => write!(f, "line {line}: {message}"),
            ErrorKind::UnknownFormat => write!(f, "unknown file type (ncsheet reads and writes .csv files)"),
            ErrorKind::NotYetSupported(Format::Xlsx) => write!(f, "xlsx is not supported yet (use a .csv file)"),
            ErrorKind::NotYetSupported(Format::Csv) => write!(f, "csv is not supported"),
            ErrorKind::OneSheetOnly { sheets } => {
                write!(f, "a csv file holds one sheet and the workbook has {sheets}; export one with --sheet")
            }
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.kind {
            ErrorKind::Read(e) | ErrorKind::Write(e) => Some(e),
            _ => None,
        }
    }
}

/// Reads a workbook and recalculates it. Cells that hold bad input (a formula that does not
/// parse) are not an error here: they load as error values, listed by `Workbook::problems`.
pub fn load(path: &Path) -> Result<Workbook, Error> {
    match Format::of(path)? {
        Format::Csv => {
            let bytes = std::fs::read(path).map_err(|e| Error::new(path, ErrorKind::Read(e)))?;
            csv::read(&bytes).map_err(|m| Error::new(path, m.into()))
        }
        format @ Format::Xlsx => Err(Error::new(path, ErrorKind::NotYetSupported(format))),
    }
}

/// Saves a whole workbook so that [`load`] reads back the same inputs.
pub fn save(wb: &Workbook, path: &Path) -> Result<(), Error> {
    match Format::of(path)? {
        Format::Csv => {
            if wb.sheet_len() != 1 {
                return Err(Error::new(path, ErrorKind::OneSheetOnly { sheets: wb.sheet_len() }));
            }
            export(wb, path, &Export { sheet: 0, range: None, content: Content::Formulas })
        }
        format @ Format::Xlsx => Err(Error::new(path, ErrorKind::NotYetSupported(format))),
    }
}

/// Writes one sheet (or a range of it) as values or as formulas.
pub fn export(wb: &Workbook, path: &Path, what: &Export) -> Result<(), Error> {
    match Format::of(path)? {
        Format::Csv => atomic::write_file(path, |out: &mut dyn Write| csv::write(wb, what, out))
            .map_err(|e| Error::new(path, ErrorKind::Write(e))),
        format @ Format::Xlsx => Err(Error::new(path, ErrorKind::NotYetSupported(format))),
    }
}

impl From<csv::Malformed> for ErrorKind {
    fn from(m: csv::Malformed) -> ErrorKind {
        ErrorKind::Malformed { line: m.line, message: m.message }
    }
}
