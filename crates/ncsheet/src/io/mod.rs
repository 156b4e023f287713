//! Files in and out. The file type is chosen by extension: `.csv` (one sheet) and `.xlsx` /
//! `.xlsm` (every sheet, formulas, names, Excel's cached values, number formats and column
//! widths).
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
use std::sync::Arc;

use crate::formula::address::Rect;
use crate::formula::ast::SheetId;
use crate::workbook::Workbook;

pub mod atomic;
pub mod csv;
pub(crate) mod csv_locale;
pub(crate) mod legacy;
pub mod limits;
pub mod notes;
pub mod xlsx;

/// The file types ncsheet knows, by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Csv,
    Xlsx,
    /// Excel 97-2003 (BIFF8), read only (`legacy/xls.rs`).
    Xls,
    /// Excel's binary workbook, read only (`legacy/xlsb.rs`).
    Xlsb,
    /// OpenDocument, read only (`legacy/ods.rs`).
    Ods,
}

impl Format {
    /// The format of a file from its extension (case-insensitive).
    pub fn of(path: &Path) -> Result<Format, Error> {
        let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("csv") => Ok(Format::Csv),
            Some("xlsx" | "xlsm") => Ok(Format::Xlsx),
            Some("xls") => Ok(Format::Xls),
            Some("xlsb") => Ok(Format::Xlsb),
            Some("ods") => Ok(Format::Ods),
            _ => Err(Error::new(path, ErrorKind::UnknownFormat)),
        }
    }

    /// The format of a file's bytes: a compound file holding a workbook stream is an .xls,
    /// a zip package an .xlsb (`xl/workbook.bin`), an .ods (its `mimetype`) or else an xlsx
    /// workbook, whatever the file is called; otherwise the name's extension says (a csv
    /// has no signature).
    pub fn detect(bytes: &[u8], name: &Path) -> Result<Format, Error> {
        if let Some(kind) = legacy::detect(bytes) {
            return Ok(kind.format());
        }
        if bytes.starts_with(b"PK\x03\x04") {
            return Ok(Format::Xlsx);
        }
        Format::of(name)
    }

    /// The read-only format this is, if it is one.
    fn legacy(self) -> Option<legacy::Kind> {
        match self {
            Format::Xls => Some(legacy::Kind::Xls),
            Format::Xlsb => Some(legacy::Kind::Xlsb),
            Format::Ods => Some(legacy::Kind::Ods),
            Format::Csv | Format::Xlsx => None,
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
    /// A csv file holds one sheet; the workbook has several.
    OneSheetOnly {
        sheets: usize,
    },
    /// An xlsx package that cannot be read or written; `part` names the piece of it.
    Xlsx {
        part: Option<String>,
        message: String,
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
            ErrorKind::Read(e) => write!(f, "cannot read: {}", plain(e)),
            ErrorKind::Write(e) => match missing_folder(&self.path, e) {
                Some(folder) => write!(f, "cannot write: the folder {} does not exist", folder.display()),
                None => write!(f, "cannot write: {}", plain(e)),
            },
            ErrorKind::Malformed { line, message } => write!(f, "line {line}: {message}"),
            ErrorKind::UnknownFormat => {
                write!(f, "unknown file type (ncsheet reads and writes .csv, .xlsx and .xlsm, and reads .xls, .xlsb and .ods)")?;
                f.write_str(conversion_advice(&self.path))
            }
            ErrorKind::Xlsx { part: Some(part), message } => write!(f, "{part}: {message}"),
            ErrorKind::Xlsx { part: None, message } => f.write_str(message),
            ErrorKind::OneSheetOnly { sheets } => {
                write!(f, "a csv file holds one sheet and the workbook has {sheets}; export one with --sheet")
            }
        }
    }
}

/// A system error in a user's words: what happened, without the errno Rust appends
/// ("No such file or directory (os error 2)" is "no such file or folder").
fn plain(e: &std::io::Error) -> String {
    use std::io::ErrorKind as K;
    match e.kind() {
        K::NotFound => "no such file or folder".into(),
        K::PermissionDenied => "permission denied".into(),
        K::IsADirectory => "it is a folder, not a file".into(),
        K::StorageFull => "the disk is full".into(),
        _ => {
            let text = e.to_string();
            match text.rfind(" (os error ") {
                Some(at) => text[..at].to_string(),
                None => text,
            }
        }
    }
}

/// The folder of `path` when a write failed because it does not exist.
fn missing_folder<'a>(path: &'a Path, e: &std::io::Error) -> Option<&'a Path> {
    let folder = path.parent().filter(|p| !p.as_os_str().is_empty())?;
    (e.kind() == std::io::ErrorKind::NotFound && !folder.is_dir()).then_some(folder)
}

/// What to do with a spreadsheet file of another program.
fn conversion_advice(path: &Path) -> &'static str {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("fods" | "numbers") => {
            "; save it as .xlsx from Excel or LibreOffice (File > Save As), or convert it: \
             soffice --headless --convert-to xlsx FILE"
        }
        _ => "",
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

/// A workbook as read from a file, with what the file held besides the cells' inputs.
pub struct Opened {
    pub workbook: Workbook,
    /// The values Excel stored for formula cells (empty for csv), for `eval --check`.
    pub cached: Vec<xlsx::CachedValue>,
    /// Number formats and column widths to write back (xlsx only).
    pub layout: Option<xlsx::Layout>,
    /// The program that last saved the file, whose results `cached` holds (xlsx only).
    pub written_by: Option<String>,
    /// What the import left out, one sentence each, for the user to hear.
    pub notes: Vec<String>,
    /// The file as read, for saving it back without losing what ncsheet does not model.
    pub origin: Origin,
}

/// Where a workbook came from. A save to a file of the same kind starts from the original:
/// a csv keeps every untouched field as typed, an xlsx package every part and cell that did
/// not change (see `xlsx/patch.rs`).
#[derive(Clone, Debug, Default)]
pub enum Origin {
    /// Made from nothing (or from a file kept no trace of).
    #[default]
    New,
    Csv(csv::Original),
    /// The xlsx package as read.
    Xlsx(Source),
    /// A file of a format ncsheet reads but does not write (.xls, .xlsb, .ods): a save is
    /// an xlsx written anew.
    Legacy(PathBuf, legacy::Kind),
}

/// The bytes of a file as read, which a save starts from, and the name its messages use.
#[derive(Clone, Debug)]
pub struct Source {
    pub file: PathBuf,
    pub bytes: Arc<[u8]>,
}

impl Source {
    /// Whether the package holds macros (.xlsm) by its name.
    fn holds_macros(&self) -> bool {
        is_xlsm(&self.file)
    }
}

/// A file ready to be written: its bytes computed, and what it cannot keep of the original.
pub struct Encoded {
    pub path: PathBuf,
    bytes: Vec<u8>,
    /// What the saved file loses, one sentence each: said before anything is written.
    pub losses: Vec<String>,
}

impl Encoded {
    /// Bytes computed elsewhere (an NC program, a drawing), to write with the others.
    pub fn new(path: &Path, bytes: Vec<u8>) -> Encoded {
        Encoded { path: path.to_path_buf(), bytes, losses: Vec::new() }
    }

    /// The file's bytes, as they would be written.
    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }

    /// The file's bytes, taken.
    pub fn into_bytes(self) -> Vec<u8> {
        self.bytes
    }

    /// Writes the file atomically (see [`atomic`]).
    pub fn write(&self, options: atomic::Options) -> Result<(), Error> {
        atomic::write_bytes(&self.path, options, &self.bytes).map_err(|e| Error::new(&self.path, ErrorKind::Write(e)))
    }
}

/// Reads a workbook and recalculates it, keeping what the file said besides the cells.
/// Cells that hold bad input (a formula that does not parse) are not an error here: they
/// load as error values, listed by `Workbook::problems`.
pub fn open(path: &Path) -> Result<Opened, Error> {
    open_with(path, None)
}

/// [`open`], a csv file read with the given delimiter (`None`: detected).
pub fn open_with(path: &Path, csv_delimiter: Option<u8>) -> Result<Opened, Error> {
    let bytes = read_file(path)?;
    let format = Format::detect(&bytes, path)?;
    open_bytes(bytes, path, format, csv_delimiter)
}

/// The bytes of a file, or an error naming it.
pub fn read_file(path: &Path) -> Result<Vec<u8>, Error> {
    std::fs::read(path).map_err(|e| Error::new(path, ErrorKind::Read(e)))
}

/// [`open`] of bytes in a known format; `path` names them in messages (and is not read).
pub fn open_bytes(bytes: Vec<u8>, path: &Path, format: Format, csv_delimiter: Option<u8>) -> Result<Opened, Error> {
    open_bytes_limited(bytes, path, format, csv_delimiter, limits::ReadLimits::default())
}

/// [`open_bytes`] held to the read limits `limits` (how far an xlsx part may inflate, how
/// long a csv field or line may be).
pub fn open_bytes_limited(
    bytes: Vec<u8>,
    path: &Path,
    format: Format,
    csv_delimiter: Option<u8>,
    limits: limits::ReadLimits,
) -> Result<Opened, Error> {
    match format {
        Format::Csv => {
            let (mut workbook, original) =
                csv::read_original_limited(&bytes, csv_delimiter, limits).map_err(|m| Error::new(path, m.into()))?;
            workbook.track_changes();
            let mut notes = Vec::new();
            if csv_delimiter.is_none() {
                notes.extend(csv::detection_note(&bytes));
            }
            let origin = Origin::Csv(original);
            Ok(Opened { workbook, cached: Vec::new(), layout: None, written_by: None, notes, origin })
        }
        Format::Xlsx => {
            let imported = xlsx::load_bytes_limited(&bytes, path, limits)?;
            Ok(Opened::imported(imported, Origin::Xlsx(Source { file: path.to_path_buf(), bytes: bytes.into() })))
        }
        Format::Xls | Format::Xlsb | Format::Ods => {
            let kind = format.legacy().expect("a read-only format");
            let imported = legacy::load(&bytes, path, kind, limits)?;
            Ok(Opened::imported(imported, Origin::Legacy(path.to_path_buf(), kind)))
        }
    }
}

impl Opened {
    /// A workbook an importer read, its edits tracked from here on for the save.
    fn imported(mut imported: xlsx::Imported, origin: Origin) -> Opened {
        imported.workbook.track_changes();
        imported.workbook.note_unsaved_values(&imported.uncached);
        Opened {
            workbook: imported.workbook,
            cached: imported.cached,
            layout: Some(imported.layout),
            written_by: imported.written_by,
            notes: notes::bounded(imported.notes),
            origin,
        }
    }
}

/// Reads a workbook and recalculates it (see [`open`]).
pub fn load(path: &Path) -> Result<Workbook, Error> {
    open(path).map(|o| o.workbook)
}

/// Saves a whole workbook so that [`load`] reads back the same inputs.
pub fn save(wb: &Workbook, path: &Path) -> Result<(), Error> {
    save_with_layout(wb, None, path)
}

/// [`save`], writing back an xlsx source's number formats and column widths.
pub fn save_with_layout(wb: &Workbook, layout: Option<&xlsx::Layout>, path: &Path) -> Result<(), Error> {
    encode_save(wb, layout, &Origin::New, path)?.write(atomic::Options::default())
}

/// What a save of `wb` to `path` writes, computed and not yet written. From an [`Origin`]
/// of the same kind as `path`, the original is kept (see [`Origin`]); otherwise the file is
/// written anew (an xlsx through rust_xlsxwriter with `layout`'s formats and widths), and
/// what an xlsx original held beyond that is named in [`Encoded::losses`].
pub fn encode_save(
    wb: &Workbook,
    layout: Option<&xlsx::Layout>,
    origin: &Origin,
    path: &Path,
) -> Result<Encoded, Error> {
    encode_save_with(wb, layout, origin, path, None)
}

/// [`encode_save`] with the delimiter of a csv written anew (`None`: `,`); a csv read from a
/// file keeps its own.
pub fn encode_save_with(
    wb: &Workbook,
    layout: Option<&xlsx::Layout>,
    origin: &Origin,
    path: &Path,
    delimiter: Option<u8>,
) -> Result<Encoded, Error> {
    let encoded = |bytes, losses| Ok(Encoded { path: path.to_path_buf(), bytes, losses });
    let kept: Result<Encoded, Error> = match (Format::of(path)?, origin) {
        (format @ (Format::Xls | Format::Xlsb | Format::Ods), _) => Err(read_only(path, format)),
        // Sheets deleted do not count: a macro may add a sheet and delete one.
        (Format::Csv, _) if wb.sheet_count() != 1 => {
            Err(Error::new(path, ErrorKind::OneSheetOnly { sheets: wb.sheet_count() }))
        }
        // The csv's own sheet left: its text kept, the cells edited on it written anew.
        (Format::Csv, Origin::Csv(original)) if wb.tab_order() == [0] => {
            let changes = wb.changes().unwrap_or_default();
            let mut edited: Vec<_> =
                changes.inputs.into_iter().filter(|&(sheet, _)| sheet == 0).map(|(_, p)| p).collect();
            if changes.shifted {
                // The places cells left when rows or columns moved, holding nothing now.
                let left = original.filled_places().filter(|&p| wb.input(0, p).is_none_or(|i| i.is_empty()));
                edited.extend(left.collect::<Vec<_>>());
                edited.sort_unstable_by_key(|p| (p.row, p.col));
                edited.dedup();
            }
            let mut bytes = Vec::new();
            let sheet_name = wb.sheet_names().into_iter().next().unwrap_or_default();
            let formats = layout.and_then(|l| l.sheets.get(&sheet_name)).map(|l| &l.look.number_formats);
            csv::write_edited(wb, original, &edited, formats, &mut bytes)
                .map_err(|e| Error::new(path, ErrorKind::Write(e)))?;
            encoded(bytes, Vec::new())
        }
        (Format::Csv, _) => {
            let whole = Export { sheet: wb.tab_order()[0], range: None, content: Content::Formulas };
            encode_export_with(wb, path, &whole, &ExportOptions { delimiter, ..ExportOptions::default() })
        }
        (Format::Xlsx, Origin::Xlsx(source)) if source.holds_macros() == is_xlsm(path) => {
            let changes = wb.changes().unwrap_or_default();
            match xlsx::patch(source, wb, &changes, layout)? {
                Ok(patched) => encoded(patched.bytes, patched.losses),
                Err(xlsx::Unpatchable(why)) => {
                    let default = xlsx::Layout::default();
                    let bytes = xlsx::to_bytes_for(wb, layout.unwrap_or(&default), path)?;
                    let losses = [Some(rewritten_loss(&source.file, &why)), links_loss(layout)];
                    encoded(bytes, losses.into_iter().flatten().collect())
                }
            }
        }
        (Format::Xlsx, origin) => {
            let default = xlsx::Layout::default();
            let bytes = xlsx::to_bytes_for(wb, layout.unwrap_or(&default), path)?;
            let losses = match origin {
                Origin::Xlsx(source) => {
                    [Some(rewritten_loss(&source.file, "it is saved under another extension")), links_loss(layout)]
                        .into_iter()
                        .flatten()
                        .collect()
                }
                Origin::Legacy(source, kind) => vec![legacy::conversion_loss(source, *kind)],
                _ => Vec::new(),
            };
            encoded(bytes, losses)
        }
    };
    let mut encoded = kept?;
    let replaced = wb.changes().unwrap_or_default().formulas_replaced;
    let names: Vec<String> = replaced.iter().map(|&(sheet, pos)| wb.cell_name(sheet, pos)).collect();
    encoded.losses.extend(formulas_replaced(&names));
    Ok(encoded)
}

/// The refusal to write a file of a format ncsheet only reads.
fn read_only(path: &Path, format: Format) -> Error {
    let kind = format.legacy().expect("a read-only format");
    let message = format!(
        "ncsheet reads {} but does not write that format (ncsheet writes .xlsx, .xlsm and .csv); \
         save the workbook elsewhere with -o FILE.xlsx",
        kind.describe()
    );
    Error::new(path, ErrorKind::Xlsx { part: None, message })
}

/// The .xlsm `source` to be saved as `path` with a new VBA project (`xl/vbaProject.bin`),
/// every other part as it was.
pub fn encode_with_vba_project(source: &Source, project: &[u8], path: &Path) -> Result<Encoded, Error> {
    let bytes = xlsx::replace_part(source, "xl/vbaProject.bin", project)?;
    Ok(Encoded::new(path, bytes))
}

/// Whether a package is named as one holding macros (.xlsm): a package is kept as it is only
/// under its own kind of name.
fn is_xlsm(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("xlsm"))
}

/// The loss of formulas that edits replaced by constants, naming the cells.
fn formulas_replaced(cells: &[String]) -> Option<String> {
    let shown = cells.iter().take(8).cloned().collect::<Vec<_>>().join(", ");
    let more = if cells.len() > 8 { format!(" and {} more", cells.len() - 8) } else { String::new() };
    (!cells.is_empty()).then(|| {
        format!(
            "formulas replaced by constants, so the saved file no longer computes these cells ({}): {shown}{more}",
            cells.len()
        )
    })
}

/// The loss of the links to other workbooks when a package is written anew without their
/// parts (one was missing): their references were read as the values Excel cached and are
/// written so, as constants.
fn links_loss(layout: Option<&xlsx::Layout>) -> Option<String> {
    let n = layout.filter(|l| l.links.parts.is_empty()).map_or(0, |l| l.external_links);
    (n > 0).then(|| {
        format!(
            "the links to {n} other workbook{} are written as the values Excel last cached for them: the \
             formulas that read them keep those values as constants, and the link parts are not kept",
            if n == 1 { "" } else { "s" }
        )
    })
}

fn rewritten_loss(source: &Path, why: &str) -> String {
    format!(
        "the workbook is written anew ({why}): of {} only cells, defined names, number formats, alignment, bold \
         and italic, fonts' sizes, colours and underlines, solid fills, column widths, row heights, hidden rows \
         and columns, hyperlinks, tables and the VBA project are kept; charts, drawings, comments, fonts' names, \
         borders, patterned fills, merged cells, validation, conditional formats, print areas, print titles \
         and Excel's other built-in names and the rest are lost",
        source.display()
    )
}

/// Writes one sheet (or a range of it) as values or as formulas. An xlsx export is a new
/// one-sheet workbook: the values as constants (a coordinate table to hand on), or, with
/// formulas, the whole workbook.
pub fn export(wb: &Workbook, path: &Path, what: &Export) -> Result<(), Error> {
    encode_export(wb, path, what)?.write(atomic::Options::default())
}

/// What [`export`] writes, computed and not yet written.
pub fn encode_export(wb: &Workbook, path: &Path, what: &Export) -> Result<Encoded, Error> {
    encode_export_with(wb, path, what, &ExportOptions::default())
}

/// How an export writes values besides [`Export`]'s choice of cells.
#[derive(Clone, Copy, Debug, Default)]
pub struct ExportOptions<'a> {
    /// The csv delimiter (`None`: `,`).
    pub delimiter: Option<u8>,
    /// The source's number formats: a csv shows values as their cells do, an xlsx keeps
    /// the formats on the values. `None`: General.
    pub layout: Option<&'a xlsx::Layout>,
    /// Numbers in full precision in a csv, whatever their format.
    pub raw: bool,
}

/// [`encode_export`] with [`ExportOptions`].
pub fn encode_export_with(
    wb: &Workbook,
    path: &Path,
    what: &Export,
    options: &ExportOptions,
) -> Result<Encoded, Error> {
    let sheet_name = wb.sheet_names().into_iter().nth(what.sheet as usize).unwrap_or_default();
    let sheet_layout = options.layout.and_then(|l| l.sheets.get(&sheet_name));
    let bytes = match Format::of(path)? {
        format @ (Format::Xls | Format::Xlsb | Format::Ods) => return Err(read_only(path, format)),
        Format::Csv => {
            let style = csv::Style {
                delimiter: options.delimiter.unwrap_or(b','),
                formats: sheet_layout.map(|l| &l.look.number_formats),
                raw: options.raw,
            };
            let mut bytes = Vec::new();
            csv::write_with(wb, what, &style, &mut bytes as &mut dyn Write)
                .map_err(|e| Error::new(path, ErrorKind::Write(e)))?;
            bytes
        }
        Format::Xlsx => match what.content {
            Content::Formulas => return encode_save(wb, options.layout, &Origin::New, path),
            Content::Values => {
                let layout = values_layout(wb, what, &sheet_name, sheet_layout);
                xlsx::to_bytes_for(&values_only(wb, what), &layout, path)?
            }
        },
    };
    Ok(Encoded { path: path.to_path_buf(), bytes, losses: Vec::new() })
}

/// The number formats of `what`'s cells moved as [`values_only`] moves the cells.
fn values_layout(wb: &Workbook, what: &Export, name: &str, source: Option<&xlsx::SheetLayout>) -> xlsx::Layout {
    let mut layout = xlsx::Layout::default();
    let (Some(source), Some(rect)) = (source, what.range.or_else(|| wb.used_rect(what.sheet))) else { return layout };
    let formats = source
        .look
        .number_formats
        .iter()
        .filter(|(pos, _)| rect.contains(**pos))
        .map(|(pos, code)| (crate::formula::Pos::new(pos.row - rect.first.row, pos.col - rect.first.col), code.clone()))
        .collect();
    let look = crate::workbook::SheetLook { number_formats: formats, ..Default::default() };
    let sheet = xlsx::SheetLayout { look, ..xlsx::SheetLayout::default() };
    layout.sheets.insert(name.to_string(), sheet);
    layout
}

/// A one-sheet workbook holding the values of `what`'s cells as constants, from A1.
fn values_only(wb: &Workbook, what: &Export) -> Workbook {
    let name = wb.sheet_names().into_iter().nth(what.sheet as usize).unwrap_or_else(|| "Sheet1".into());
    let mut out = Workbook::new();
    let sheet = out.add_sheet(&name).expect("a new workbook has no sheets");
    let Some(rect) = what.range.or_else(|| wb.used_rect(what.sheet)) else { return out };
    for (pos, value) in wb.values(what.sheet) {
        if rect.contains(pos) {
            let at = crate::formula::Pos::new(pos.row - rect.first.row, pos.col - rect.first.col);
            out.set_value_deferred(sheet, at, value);
        }
    }
    out
}

impl From<xlsx::XlsxError> for Error {
    fn from(e: xlsx::XlsxError) -> Error {
        Error { path: e.file, kind: ErrorKind::Xlsx { part: e.part, message: e.message } }
    }
}

impl From<csv::Malformed> for ErrorKind {
    fn from(m: csv::Malformed) -> ErrorKind {
        ErrorKind::Malformed { line: m.line, message: m.message }
    }
}
