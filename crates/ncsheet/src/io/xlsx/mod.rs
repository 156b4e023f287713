//! Excel workbooks (.xlsx, .xlsm): import with calamine, export with rust_xlsxwriter.
//!
//! **API Boundary.** This module is the only place that knows how Excel spells formulas in
//! its files: `_xlfn.`/`_xlws.` prefixes on newer functions, `_xlpm.` on LET/LAMBDA
//! parameters, `_xlfn.ANCHORARRAY(A1)` for the spill operator `A1#` and `_xlfn.SINGLE(x)` for
//! `@x` (see `syntax.rs`). The workbook only ever sees the spelling a user types.
//!
//! Import (`read.rs`) takes every worksheet: values, formulas (shared formulas expanded for
//! each cell), defined names with their scope, and keeps the values Excel cached for formula
//! cells, so [`compare_cached`] can list where ncsheet disagrees with Excel. A formula that
//! does not parse keeps its text and shows `#NAME?` (the workbook lists it in `problems`);
//! nothing is dropped silently: what is skipped (chart sheets, built-in `_xlnm.` names)
//! is said in [`Imported::notes`]. calamine opens the package and reads its styles; the
//! cells come from one streaming pass over each worksheet's XML (`sheet_xml.rs`, over the
//! small checked XML reader of `xml.rs`), which also finds what calamine does not expose:
//! array-formula areas and dynamic-array marks, column widths. The sheet list and the scope
//! of names come from `raw.rs`.
//!
//! Export (`write.rs`) writes all sheets, values, formulas with their computed results as
//! cached values (viewers that do not recalculate show numbers), defined names, and the
//! number formats and column widths the source file had ([`Layout`]): a workbook made new.
//! A workbook read from an xlsx is saved by [`patch`] (`patch.rs`): the original package with
//! only the changed cells rewritten. Both write through `io::atomic`.
//!
//! **Architecture Invariant:** every error names the file and, when known, the part of the
//! package (`parts.xlsx: xl/worksheets/sheet2.xml: …`); bad input never panics.

use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};

use crate::eval::Value;
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::SheetId;
use crate::workbook::{SheetLook, Workbook};

mod check;
mod external;
pub(crate) mod opc;
mod patch;
mod patch_styles;
mod patch_tables;
mod pivot;
mod raw;
mod read;
mod sheet_span;
mod sheet_xml;
mod syntax;
mod tables;
mod write;
mod write_tables;
pub(crate) mod xml;

pub use check::{compare_cached, values_agree, Difference, REL_TOLERANCE};
pub use patch::{patch, replace_part, Patched, Unpatchable};
pub(crate) use raw::{check_entry_names, Inflating};
pub use read::{load, load_bytes, load_bytes_limited};
pub use tables::Table;
pub use write::{save, save_with_layout, to_bytes, to_bytes_for};

/// A workbook read from an xlsx file, with what the file said besides the cells.
pub struct Imported {
    pub workbook: Workbook,
    /// The values the file stored for formula cells and for the cells their arrays spilled
    /// into (Excel's results, for comparison), in file order.
    pub cached: Vec<CachedValue>,
    /// Number formats and column widths, to write back on export.
    pub layout: Layout,
    /// What the import left out or could not take, one sentence each.
    pub notes: Vec<String>,
    /// The program that last saved the file, whose results `cached` holds (`docProps/app.xml`;
    /// [`WRITTEN_BY`] for a file ncsheet wrote).
    pub written_by: Option<String>,
    /// Formula cells the file stored no result for (`<v/>`, as a generator that does not
    /// calculate writes them): a save writes ncsheet's result there, as Excel would.
    pub uncached: Vec<(SheetId, Pos)>,
}

/// How ncsheet names itself as the last author (`docProps/core.xml`'s `lastModifiedBy`) of
/// a workbook it writes new; Excel and LibreOffice write their user's name when they save it
/// again.
pub const WRITTEN_BY: &str = "ncsheet";

/// The `Application` of a workbook ncsheet writes new (rust_xlsxwriter's): LibreOffice reads
/// the references of a package named otherwise in its own syntax.
pub const NEW_WORKBOOK_APPLICATION: &str = "Microsoft Excel";

/// A value Excel computed and stored in the file.
#[derive(Clone, Debug, PartialEq)]
pub struct CachedValue {
    pub sheet: SheetId,
    pub pos: Pos,
    pub value: Value,
    /// The formula cell that computed it: `pos` itself, or the anchor of the array formula
    /// whose result spilled into `pos`.
    pub anchor: Pos,
}

/// Presentation the engine does not model but a saved file should keep.
#[derive(Clone, Debug, Default)]
pub struct Layout {
    /// By sheet name (case as in the workbook).
    pub sheets: HashMap<String, SheetLayout>,
    /// The file's VBA project (`xl/vbaProject.bin`), written back when saving as .xlsm.
    pub vba_project: Option<Vec<u8>>,
    /// The workbook's VBA code name (`ThisWorkbook`), if the file gave one.
    pub workbook_code_name: Option<String>,
    /// How the file asks to be calculated (for `info`; ncsheet always recalculates).
    pub calculation: Calculation,
    /// The file's tables (`xl/tables/`), in sheet order (for `info`).
    pub tables: Vec<Table>,
    /// How many other workbooks the file links to (`xl/externalLinks/`): their references
    /// were read as the values Excel cached (`links` writes them back).
    pub external_links: usize,
    /// The link parts and the formulas that read them, to write back in a package made new.
    pub links: KeptLinks,
}

/// Links to other workbooks as the file had them: a package written anew keeps the parts,
/// and the formulas and names still as read keep their references to the linked workbooks.
#[derive(Clone, Debug, Default)]
pub struct KeptLinks {
    /// Each external-link part with its relationships part, in the file's numbering (`[1]`
    /// first); empty when a numbered part is missing (the numbering could not be kept).
    pub parts: Vec<(Vec<u8>, Option<Vec<u8>>)>,
    /// By cell: the formula as the file spelled it, and as ncsheet writes the formula it read.
    pub cells: HashMap<(SheetId, Pos), LinkedFormula>,
    /// By name (lowercase) and scope, likewise.
    pub names: HashMap<(String, Option<SheetId>), LinkedFormula>,
}

/// A formula that reads linked workbooks: written back as the file had it while ncsheet
/// would still write it as `resolved` (no one edited it).
#[derive(Clone, Debug, Default)]
pub struct LinkedFormula {
    pub original: String,
    pub resolved: String,
}

/// The file's calculation settings: `<calcPr>` and `date1904` of `<workbookPr>`, with
/// ECMA-376's defaults for what the file leaves out.
#[derive(Clone, Debug, PartialEq)]
pub struct Calculation {
    /// `auto`, `autoNoTable` (all but data tables) or `manual`.
    pub mode: String,
    /// Circular references iterate instead of being errors.
    pub iterate: bool,
    pub iterate_count: u32,
    /// Iteration stops when no value changes by more than this.
    pub iterate_delta: f64,
    /// Excel recomputes every formula when it opens the file.
    pub full_calc_on_load: bool,
    /// Date serials count from 1904-01-01.
    pub date_1904: bool,
}

impl Default for Calculation {
    fn default() -> Self {
        Calculation {
            mode: "auto".into(),
            iterate: false,
            iterate_count: 100,
            iterate_delta: 0.001,
            full_calc_on_load: false,
            date_1904: false,
        }
    }
}

#[derive(Clone, Debug, Default)]
pub struct SheetLayout {
    /// How the sheet looks: number formats, cell styles, widths, heights (a macro's run
    /// starts from it and leaves its changes in it).
    pub look: SheetLook,
    /// The look as the file had it, kept when a macro first changed `look`: a save over the
    /// file's own package writes what differs (new cell styles, widths, heights).
    pub file_look: Option<SheetLook>,
    /// The sheet's VBA code name (`Sheet1`), if the file gave one.
    pub code_name: Option<String>,
    /// The sheet's active cell as the file saved it (for a macro's `ActiveCell`).
    pub active_cell: Option<Pos>,
    /// The sheet's selection as the file saved it, area by area (for a macro's `Selection`).
    pub selection: Option<Vec<Rect>>,
    /// Array formulas of the file by anchor: written back over the same area when ncsheet
    /// does not spill them itself (it may lack a function, or the formula is a legacy
    /// Ctrl+Shift+Enter one filling its area with a scalar).
    pub array_formulas: HashMap<Pos, ArrayFormula>,
}

/// An array formula as the file stored it: `<f t="array" ref="A1:A5">` in its anchor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ArrayFormula {
    pub anchor: Pos,
    /// The cells it fills, anchor included.
    pub area: Rect,
    /// A dynamic array (`cm="1"`, Excel 365) rather than a legacy Ctrl+Shift+Enter formula.
    pub dynamic: bool,
}

/// An xlsx file that could not be read or written.
#[derive(Debug)]
pub struct XlsxError {
    pub file: PathBuf,
    /// The part of the package (`xl/worksheets/sheet2.xml`) or the sheet, when known.
    pub part: Option<String>,
    pub kind: ErrorKind,
    pub message: String,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// The file could not be opened, read or written.
    Io,
    /// Not a zip package at all, or a damaged one.
    NotXlsx,
    /// An Excel 97-2003 binary workbook.
    LegacyXls,
    /// Encrypted with a password.
    Encrypted,
    /// A part of the package holds XML or values that do not make sense.
    Damaged,
    /// More than this program will hold in memory.
    TooLarge,
    /// The workbook cannot be written as xlsx (a name or text Excel does not allow).
    Unwritable,
}

impl XlsxError {
    pub(crate) fn new(file: &Path, part: Option<&str>, kind: ErrorKind, message: impl Into<String>) -> XlsxError {
        XlsxError { file: file.to_path_buf(), part: part.map(str::to_string), kind, message: message.into() }
    }
}

impl fmt::Display for XlsxError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: ", self.file.display())?;
        if let Some(part) = &self.part {
            write!(f, "{part}: ")?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for XlsxError {}
