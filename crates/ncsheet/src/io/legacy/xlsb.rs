//! Excel binary workbooks (`.xlsb`, MS-XLSB), read here from the parts' records: the
//! sheets and names of the workbook part, the shared strings, and each sheet part's cells
//! with the values Excel stored and their formulas. (calamine 0.38 read the cells once: it
//! panicked on a damaged record, refused a whole file over a defined name whose tokens it did
//! not know, and built each sheet as one dense block, so that two cells at A1 and
//! XFD1048576 asked for 17 billion slots; its spelling of formulas was wrong besides: `>`
//! and `>=` swapped, relative flags swapped, a 3-D reference named by the wrong sheet.)
//!
//! A formula's tokens ([MS-XLSB] 2.5.98, `Rgce`) are BIFF8's with wider fields: rows of 4
//! bytes, a string's length of 2 and no flags byte, a name's index of 4. The operators,
//! functions and names are turned into text by `biff.rs`, which the `.xls` reader shares. A
//! shared formula's cells hold `PtgExp`, pointing at the `BrtShrFmla` that follows its first
//! cell (an array formula's at its `BrtArrFmla`); a future function (`_xlfn.`) is a call
//! through a hidden name (`fFutureFunction`).
//! A formula this reader cannot carry over keeps the value Excel stored, as a constant, and a
//! note names the cells. A record cut short, a cell past the sheet's edge, a string index
//! past the table or a sheet whose part is missing refuses the file, naming the part and the
//! record.

use std::collections::{BTreeMap, HashMap};
use std::io::{BufReader, Cursor, Read, Seek};
use std::rc::Rc;

use super::biff::{self, atom, Bytes, Context, Item, SupBook, Unreadable};
use crate::io::notes::{quoted, Grouped};

use super::{cells_named, too_many_cells, Book, Cell, Name, Sheet, MAX_CELLS};
use crate::eval::{Value, XlError};
use crate::formula::address::{column_name, Pos, Rect};
use crate::io::limits::ReadLimits;
use crate::io::xlsx::{check_entry_names, Inflating};
use crate::workbook::{Visibility, WorkbookError, MAX_SHEETS};

/// Reads an .xlsb file's bytes into a [`Book`].
pub fn read(bytes: &[u8], limits: ReadLimits) -> Result<Book, String> {
    let zip = zip::ZipArchive::new(Cursor::new(bytes)).map_err(|e| e.to_string())?;
    check_entry_names(&zip, bytes).map_err(|(entry, why)| format!("{entry}: {why}"))?;
    let mut zip = Parts { zip, limits };
    let globals = read_globals(&mut zip)?;
    let strings = read_shared_strings(&mut zip)?;
    let application = application(&mut zip);
    let mut book = Book { application, date_1904: globals.date_1904, ..Book::default() };
    let ctx =
        Context { sheets: &globals.sheets, xtis: &globals.xtis, books: &globals.books, names: &globals.name_refs };
    let mut cells_left = MAX_CELLS;
    for (file_index, bundle) in globals.bundles.iter().enumerate() {
        let part = match (&bundle.part, bundle.worksheet) {
            (Some(part), true) => part,
            (Some(_), false) => {
                book.notes.push(format!("sheet '{}' is not a worksheet and was left out", bundle.name));
                continue;
            }
            (None, _) => {
                book.notes.push(format!("sheet '{}' has no part in the file and was left out", bundle.name));
                continue;
            }
        };
        let part = read_sheet_part(&mut zip, part, &strings, &mut cells_left)?;
        let mut sheet = Sheet { name: bundle.name.clone(), visibility: bundle.visibility, ..Sheet::default() };
        for (pos, value) in part.values {
            sheet.cells.insert(pos, Cell { value: Some(value), ..Cell::default() });
        }
        let mut unread = Vec::new();
        for formula in &part.formulas {
            let cell = sheet.cells.entry(formula.pos).or_default();
            match formula_text(formula, &part.blocks, &ctx, Some(file_index)) {
                Ok(Some((text, array))) => {
                    cell.formula = Some(text);
                    cell.array = array;
                }
                Ok(None) => {}
                Err(_) => unread.push(formula.pos),
            }
        }
        if !unread.is_empty() {
            book.notes.push(format!(
                "{} formula cells of sheet '{}' keep the value Excel stored, as a constant: ncsheet does not read \
                 their formulas (tables, array constants, other workbooks) ({})",
                unread.len(),
                bundle.name,
                cells_named(&bundle.name, &unread)
            ));
        }
        book.sheets.push(sheet);
    }
    read_names(&globals, &ctx, &mut book);
    book.notes.push("number formats are not read from an .xlsb file: values show as General".into());
    Ok(book)
}

/// The package's parts, each read through the limits on how far it may inflate.
struct Parts<R> {
    zip: zip::ZipArchive<R>,
    limits: ReadLimits,
}

impl<R: Read + Seek> Parts<R> {
    /// The records of a part (`None` when the file has no such part), its name spelled as
    /// calamine and Excel find it: as written, else with other case or with `\\`.
    fn records(&mut self, part: &str) -> Result<Option<Records<impl Read + '_>>, String> {
        let name = if self.zip.index_for_name(part).is_some() {
            part.to_string()
        } else {
            let same = |n: &str| n.replace('\\', "/").eq_ignore_ascii_case(part);
            match self.zip.file_names().flatten().find(|n| same(n)) {
                Some(name) => name.into_owned(),
                None => return Ok(None),
            }
        };
        let entry = self.zip.by_name(&name).map_err(|e| format!("{part}: {e}"))?;
        Ok(Some(Records(BufReader::new(Inflating::new(entry, self.limits)), 0)))
    }
}

/// The program that saved the file: `docProps/app.xml`'s `Application`.
fn application<R: Read + Seek>(zip: &mut Parts<R>) -> Option<String> {
    let mut xml = String::new();
    zip.zip.by_name("docProps/app.xml").ok()?.take(1 << 20).read_to_string(&mut xml).ok()?;
    let start = xml.find("<Application>")? + "<Application>".len();
    let text = &xml[start..];
    Some(text[..text.find('<')?].trim().to_string()).filter(|t| !t.is_empty())
}

/// BrtName's flags ([MS-XLSB] 2.4.711) of a name that is no defined name of the sheets': a
/// macro's (fFunc, fProc) or a future function's (fFutureFunction).
const NAME_NOT_A_FORMULA: u32 = 0x2 | 0x8 | 0x20000;

/// The workbook's defined names into `book`, as formulas of the sheets they belong to.
fn read_names(globals: &Globals, ctx: &Context, book: &mut Book) {
    let mut left_out = Grouped::default();
    for name in &globals.names {
        if name.flags & NAME_NOT_A_FORMULA != 0 || name.name.starts_with("_xlnm.") {
            continue;
        }
        let sheet = match name.scope {
            None => None,
            // The name's sheet (an index into the workbook part's sheets) among the book's.
            Some(i) => match globals.sheets.get(i).and_then(|n| book.sheets.iter().position(|s| s.name == *n)) {
                Some(s) => Some(s),
                None => {
                    left_out.push(format!("name {} belongs to a sheet that was left out", quoted(&name.name)));
                    continue;
                }
            },
        };
        match decode(&name.rgce, &name.extra, ctx, None, name.scope) {
            Ok(formula) => book.names.push(Name { name: name.name.clone(), formula, sheet }),
            Err(why) => left_out.push(format!("name {} was left out: ncsheet does not read {why}", quoted(&name.name))),
        }
    }
    left_out.finish("defined names were left out", &mut book.notes);
}

/// What the workbook part says: the sheets in file order with their parts, the
/// ExternSheet's XTIs, the supporting books and the defined names.
#[derive(Default)]
struct Globals {
    /// Each sheet's name, in file order (the index formulas and names use).
    sheets: Vec<String>,
    /// Each sheet, as [`Globals::sheets`].
    bundles: Vec<Bundle>,
    date_1904: bool,
    xtis: Vec<(u16, i16, i16)>,
    books: Vec<SupBook>,
    names: Vec<NameRecord>,
    /// Each name and the sheet it belongs to, for [`Context`].
    name_refs: Vec<(String, Option<usize>)>,
}

/// A sheet of the workbook part (BrtBundleSh): its name, state and part, and whether the
/// part is a worksheet's.
struct Bundle {
    name: String,
    visibility: Visibility,
    part: Option<String>,
    worksheet: bool,
}

struct NameRecord {
    name: String,
    flags: u32,
    scope: Option<usize>,
    rgce: Vec<u8>,
    extra: Vec<u8>,
}

/// Records of xl/workbook.bin ([MS-XLSB] 2.4) this reader uses.
const BRT_NAME: u16 = 0x0027;
const BRT_WB_PROP: u16 = 0x0099;
const BRT_BUNDLE_SH: u16 = 0x009C;
const BRT_SUP_BOOK_SRC: u16 = 0x0163;
const BRT_SUP_SELF: u16 = 0x0165;
const BRT_SUP_SAME: u16 = 0x0166;
const BRT_SUP_ADDIN: u16 = 0x029B;
const BRT_EXTERN_SHEET: u16 = 0x016A;

/// The largest record read whole: a formula's record holds its tokens and values.
const RECORD_LIMIT: u64 = 1 << 24;

const WORKBOOK_PART: &str = "xl/workbook.bin";

fn read_globals<R: Read + Seek>(zip: &mut Parts<R>) -> Result<Globals, String> {
    let mut rels = String::new();
    if let Ok(entry) = zip.zip.by_name("xl/_rels/workbook.bin.rels") {
        entry.take(1 << 20).read_to_string(&mut rels).map_err(|e| format!("xl/_rels/workbook.bin.rels: {e}"))?;
    }
    let targets: HashMap<&str, &str> = rels
        .split("<Relationship ")
        .skip(1)
        .filter_map(|r| Some((attribute(r, "Id")?, attribute(r, "Target")?)))
        .collect();
    let mut records = zip.records(WORKBOOK_PART)?.ok_or_else(|| format!("{WORKBOOK_PART}: the part is missing"))?;
    let mut g = Globals::default();
    while let Some((kind, body)) = records.next_head(RECORD_LIMIT).map_err(|e| format!("{WORKBOOK_PART}: {e}"))? {
        match kind {
            BRT_WB_PROP => g.date_1904 = body.first().is_some_and(|flags| flags & 1 != 0),
            // Past the sheets a workbook holds, before any sheet is read (200,000 records naming
            // one sheet part read it each time: 29 s and 1.9 GB before the cell limit stopped it).
            BRT_BUNDLE_SH if g.bundles.len() == MAX_SHEETS => {
                return Err(format!(
                    "{WORKBOOK_PART}: sheet {} (record BrtBundleSh): {}",
                    MAX_SHEETS + 1,
                    WorkbookError::TooManySheets
                ));
            }
            BRT_BUNDLE_SH => {
                let bundle = bundle(&body, &targets).map_err(|why| {
                    format!("{WORKBOOK_PART}: sheet {} (record BrtBundleSh): {why}", g.sheets.len() + 1)
                })?;
                g.sheets.push(bundle.name.clone());
                g.bundles.push(bundle);
            }
            BRT_SUP_SELF | BRT_SUP_SAME => g.books.push(SupBook::Own),
            BRT_SUP_ADDIN => g.books.push(SupBook::AddIns(Vec::new())),
            BRT_SUP_BOOK_SRC => g.books.push(SupBook::Other(Vec::new())),
            BRT_EXTERN_SHEET => {
                // cXti, then each XTI: iSupBook, itabFirst, itabLast (4 bytes each).
                let count = body.get(..4).map(|_| u32_at(&body, 0) as usize);
                let xtis = body.get(4..).unwrap_or_default();
                if count.is_none_or(|count| count.saturating_mul(12) > xtis.len()) {
                    return Err(format!(
                        "{WORKBOOK_PART}: the list of sheets 3-D references name (record BrtExternSheet) is cut short"
                    ));
                }
                for xti in xtis.chunks_exact(12).take(count.unwrap_or(0)) {
                    g.xtis.push((u32_at(xti, 0) as u16, u32_at(xti, 4) as i16, u32_at(xti, 8) as i16));
                }
            }
            BRT_NAME => {
                if let Some(name) = name_record(&body) {
                    g.name_refs.push((name.name.clone(), name.scope));
                    g.names.push(name);
                }
            }
            _ => {}
        }
    }
    Ok(g)
}

/// BrtBundleSh: hsState, iTabID, strRelID (null: no part), strName; the relationship names
/// the sheet's part, whose folder says what sheet it is.
fn bundle(body: &[u8], targets: &HashMap<&str, &str>) -> Result<Bundle, String> {
    let cut_short = || "the record is cut short".to_string();
    let state = body.get(..4).map(|_| u32_at(body, 0)).ok_or_else(cut_short)?;
    let rest = body.get(8..).ok_or_else(cut_short)?;
    let null_rel = rest.get(..4) == Some(&[0xFF; 4][..]);
    let (rel, after) = if null_rel {
        (None, &rest[4..])
    } else {
        wide_string(rest).map(|(r, a)| (Some(r), a)).ok_or_else(cut_short)?
    };
    let (name, _) = wide_string(after).ok_or_else(cut_short)?;
    let visibility = match state {
        0 => Visibility::Visible,
        1 => Visibility::Hidden,
        2 => Visibility::VeryHidden,
        other => {
            return Err(format!(
                "'{name}' has the state {other}, which is none of visible (0), hidden (1) and very hidden (2)"
            ))
        }
    };
    let part = match rel {
        None => None,
        Some(rel) => {
            let target = targets.get(rel.as_str()).ok_or_else(|| {
                format!("'{name}' names the relationship '{rel}', which xl/_rels/workbook.bin.rels does not hold")
            })?;
            let part = crate::io::xlsx::opc::resolve_target("xl", target);
            Some(part.map_err(|why| format!("'{name}': relationship '{rel}' {why}"))?)
        }
    };
    let folder = part.as_deref().and_then(|p| p.rsplit('/').nth(1));
    let worksheet = match folder {
        None | Some("worksheets") => true,
        Some("chartsheets" | "dialogsheets" | "macrosheets") => false,
        Some(_) => {
            return Err(format!(
            "'{name}' has its part at {}, which is under none of worksheets, chartsheets, dialogsheets and macrosheets",
            part.unwrap_or_default()
        ))
        }
    };
    Ok(Bundle { name, visibility, part, worksheet })
}

/// BrtName: flags, chKey, itab (0xFFFFFFFF: the workbook's), name, then NameParsedFormula
/// (cce, rgce, cb, rgcb).
fn name_record(body: &[u8]) -> Option<NameRecord> {
    let flags = u32::from_le_bytes(body.get(..4)?.try_into().ok()?);
    let itab = u32::from_le_bytes(body.get(5..9)?.try_into().ok()?);
    let (name, rest) = wide_string(body.get(9..)?)?;
    let (rgce, extra) = parsed_formula(rest)?;
    let scope = (itab != u32::MAX).then_some(itab as usize);
    Some(NameRecord { name, flags, scope, rgce: rgce.to_vec(), extra: extra.to_vec() })
}

/// A formula's tokens and extra data: cce, rgce, cb, rgcb.
fn parsed_formula(bytes: &[u8]) -> Option<(&[u8], &[u8])> {
    let cce = u32::from_le_bytes(bytes.get(..4)?.try_into().ok()?) as usize;
    let rgce = bytes.get(4..4 + cce)?;
    let rest = bytes.get(4 + cce..)?;
    let cb = rest.get(..4).map_or(0, |b| u32::from_le_bytes(b.try_into().expect("4 bytes")) as usize);
    Some((rgce, rest.get(4..4 + cb).unwrap_or_default()))
}

/// One formula cell of a sheet part.
struct FormulaCell {
    pos: (u32, u32),
    rgce: Vec<u8>,
    extra: Vec<u8>,
}

/// A formula a block of cells shares (BrtShrFmla) or an array formula (BrtArrFmla): its
/// cells, tokens and extra data.
struct BlockFormula {
    area: Rect,
    rgce: Vec<u8>,
    extra: Vec<u8>,
    array: bool,
}

/// A sheet part's values, its formulas and its shared and array formulas, by the cell they
/// follow (the first of their cells).
#[derive(Default)]
struct SheetPart {
    values: BTreeMap<(u32, u32), Value>,
    formulas: Vec<FormulaCell>,
    blocks: BTreeMap<(u32, u32), BlockFormula>,
}

/// Records of a sheet part ([MS-XLSB] 2.4): a row's header, then its cells, each a Cell
/// (column, style) and its value; BrtCellBlank to BrtCellIsst constants, BrtFmlaString to
/// BrtFmlaError formulas with their last result.
const BRT_ROW_HDR: u16 = 0x0000;
const BRT_CELL_BLANK: u16 = 0x0001;
const BRT_CELL_RK: u16 = 0x0002;
const BRT_CELL_ERROR: u16 = 0x0003;
const BRT_CELL_BOOL: u16 = 0x0004;
const BRT_CELL_REAL: u16 = 0x0005;
const BRT_CELL_ST: u16 = 0x0006;
const BRT_CELL_ISST: u16 = 0x0007;
const BRT_FMLA_STRING: u16 = 0x0008;
const BRT_FMLA_NUM: u16 = 0x0009;
const BRT_FMLA_BOOL: u16 = 0x000A;
const BRT_FMLA_ERROR: u16 = 0x000B;
const BRT_ARR_FMLA: u16 = 0x01AA;
const BRT_SHR_FMLA: u16 = 0x01AB;
const BRT_END_SHEET_DATA: u16 = 0x0092;

/// A sheet part's cells; `cells_left` counts down the cells the file may still hold (read
/// as they inflate, before the book's cells are counted as a whole).
fn read_sheet_part<R: Read + Seek>(
    zip: &mut Parts<R>,
    part: &str,
    strings: &[Rc<str>],
    cells_left: &mut usize,
) -> Result<SheetPart, String> {
    let mut records = zip.records(part)?.ok_or_else(|| format!("{part}: the sheet's part is missing from the file"))?;
    let (mut row, mut sheet, mut ended) = (0u32, SheetPart::default(), false);
    while let Some((kind, body)) = records.next_head(RECORD_LIMIT).map_err(|e| format!("{part}: {e}"))? {
        match kind {
            BRT_END_SHEET_DATA => ended = true,
            BRT_ROW_HDR => {
                row = body.get(..4).map(|_| u32_at(&body, 0)).filter(|r| *r <= LAST_ROW).ok_or_else(|| {
                    format!("{part}: a row (record BrtRowHdr) is cut short or past the sheet's last row")
                })?;
            }
            BRT_CELL_BLANK..=BRT_FMLA_ERROR => {
                let (col, value) = cell_value(kind, &body, strings)
                    .map_err(|why| format!("{part}: a cell of row {} (record 0x{kind:04X}) {why}", row + 1))?;
                *cells_left = cells_left.checked_sub(1).ok_or_else(|| format!("{part}: {}", too_many_cells()))?;
                if let Some(value) = value {
                    sheet.values.insert((row, col), value);
                }
                if kind >= BRT_FMLA_STRING {
                    // GrbitFmla (2 bytes) after the value, then the formula.
                    let value_end = match kind {
                        BRT_FMLA_NUM => 16,
                        BRT_FMLA_STRING => 12 + 2 * u32_at(&body, 8) as usize,
                        _ => 9,
                    };
                    if let Some((rgce, extra)) = body.get(value_end + 2..).and_then(parsed_formula) {
                        sheet.formulas.push(FormulaCell {
                            pos: (row, col),
                            rgce: rgce.to_vec(),
                            extra: extra.to_vec(),
                        });
                    }
                }
            }
            BRT_SHR_FMLA | BRT_ARR_FMLA if body.len() >= 16 => {
                // RfX (its cells: first and last row, first and last column), for an
                // array formula a flags byte, then the formula; the record follows the
                // first cell's.
                let array = kind == BRT_ARR_FMLA;
                let start = if array { 17 } else { 16 };
                let (Some(first), Some((rgce, extra))) =
                    (sheet.formulas.last(), body.get(start..).and_then(parsed_formula))
                else {
                    continue;
                };
                let area = block_area(&body).ok_or_else(|| {
                    let name = if array { "BrtArrFmla" } else { "BrtShrFmla" };
                    format!(
                        "{part}: the area of a formula (record {name}) at row {}, column {} runs past the sheet's \
                         edge or backwards (rows {}-{}, columns {}-{}): a damaged file",
                        first.pos.0 + 1,
                        first.pos.1 + 1,
                        u64::from(u32_at(&body, 0)) + 1,
                        u64::from(u32_at(&body, 4)) + 1,
                        u64::from(u32_at(&body, 8)) + 1,
                        u64::from(u32_at(&body, 12)) + 1
                    )
                })?;
                let block = BlockFormula { area, rgce: rgce.to_vec(), extra: extra.to_vec(), array };
                sheet.blocks.insert(first.pos, block);
            }
            _ => {}
        }
    }
    if !ended {
        // Cut at a record's edge, the part read whole but its last cells were gone.
        return Err(format!("{part}: the part ends before its cells do (no record BrtEndSheetData): a file cut short"));
    }
    Ok(sheet)
}

/// The cells of a shared or array formula (its RfX: first and last row, first and last
/// column), `None` when they run past the sheet's edge or backwards: such an area was
/// written into the workbook as is (a column past u32 panicked naming it).
fn block_area(body: &[u8]) -> Option<Rect> {
    let (rows, cols) = ((u32_at(body, 0), u32_at(body, 4)), (u32_at(body, 8), u32_at(body, 12)));
    let within = rows.0 <= rows.1 && rows.1 <= LAST_ROW && cols.0 <= cols.1 && cols.1 <= LAST_COL;
    within.then(|| Rect::new(Pos::new(rows.0, cols.0), Pos::new(rows.1, cols.1)))
}

/// A cell record's column and value (`None`: blank), or why it cannot be read.
fn cell_value(kind: u16, body: &[u8], strings: &[Rc<str>]) -> Result<(u32, Option<Value>), String> {
    let field = |at: usize, len: usize| body.get(at..at + len).ok_or_else(|| "is cut short".to_string());
    let col = u32_at(field(0, 8)?, 0);
    if col > LAST_COL {
        return Err(format!("is in column {}, past the sheet's last column XFD", u64::from(col) + 1));
    }
    let value = match kind {
        BRT_CELL_BLANK => None,
        BRT_CELL_RK => Some(Value::Number(super::xls::rk(u32_at(field(8, 4)?, 0)))),
        BRT_CELL_ERROR | BRT_FMLA_ERROR => {
            let code = field(8, 1)?[0];
            Some(Value::Error(
                known_error(code)
                    .ok_or_else(|| format!("holds the error code 0x{code:02X}, which is no error of Excel's"))?,
            ))
        }
        BRT_CELL_BOOL | BRT_FMLA_BOOL => Some(Value::Bool(field(8, 1)?[0] != 0)),
        BRT_CELL_REAL | BRT_FMLA_NUM => {
            Some(Value::Number(f64::from_le_bytes(field(8, 8)?.try_into().expect("8 bytes"))))
        }
        BRT_CELL_ST | BRT_FMLA_STRING => {
            let (text, _) = wide_string(&body[8..]).ok_or_else(|| "has its text cut short".to_string())?;
            Some(Value::Text(text.into()))
        }
        BRT_CELL_ISST => {
            let index = u32_at(field(8, 4)?, 0) as usize;
            let text = strings.get(index).ok_or_else(|| {
                format!("names shared string {index}, past the {} of xl/sharedStrings.bin", strings.len())
            })?;
            Some(Value::Text(text.clone()))
        }
        _ => None,
    };
    Ok((col, value))
}

/// A BErr ([MS-XLSB] 2.5.98.2) as the error it stands for, `None` for a code Excel has not.
fn known_error(code: u8) -> Option<XlError> {
    matches!(code, 0x00 | 0x07 | 0x0F | 0x17 | 0x1D | 0x24 | 0x2A | 0x2B).then(|| super::xls::error_of(code))
}

/// The shared strings (xl/sharedStrings.bin, each BrtSSTItem a flags byte and the text;
/// runs and phonetic text after it are left), none without the part.
fn read_shared_strings<R: Read + Seek>(zip: &mut Parts<R>) -> Result<Vec<Rc<str>>, String> {
    const PART: &str = "xl/sharedStrings.bin";
    const BRT_SST_ITEM: u16 = 0x0013;
    let Some(mut records) = zip.records(PART)? else { return Ok(Vec::new()) };
    let mut strings = Vec::new();
    while let Some((kind, body)) = records.next_head(RECORD_LIMIT).map_err(|e| format!("{PART}: {e}"))? {
        if kind == BRT_SST_ITEM {
            let (text, _) = body
                .get(1..)
                .and_then(wide_string)
                .ok_or_else(|| format!("{PART}: string {} (record BrtSSTItem) is cut short", strings.len() + 1))?;
            if strings.len() == MAX_CELLS {
                return Err(format!("{PART}: more strings than {}", too_many_cells()));
            }
            strings.push(text.into());
        }
    }
    Ok(strings)
}

/// A formula cell as the book holds it: its formula's text and, for the first cell of an
/// array formula, the array's area; `None` for another cell of an array formula (its value
/// only). A cell of a shared or array formula holds `PtgExp`, naming the first cell's row
/// (its column is the PtgExtraCol of the extra data); a shared formula is read from the
/// cell itself.
fn formula_text(
    cell: &FormulaCell,
    blocks: &BTreeMap<(u32, u32), BlockFormula>,
    ctx: &Context,
    sheet: Option<usize>,
) -> Result<Option<(String, Option<Rect>)>, Unreadable> {
    if cell.rgce.first() != Some(&0x01) {
        return decode(&cell.rgce, &cell.extra, ctx, None, sheet).map(|text| Some((text, None)));
    }
    let row = cell.rgce.get(1..5).map(|r| u32_at(r, 0)).ok_or_else(biff::damaged)?;
    let named = cell.extra.get(..4).map(|c| (row, u32_at(c, 0)));
    // Without its PtgExtraCol, the block on that row holding the cell: the last to start at
    // or before its column (blocks do not overlap). Looking through every block for each
    // such cell was quadratic.
    let block = named.and_then(|first| blocks.get(&first)).or_else(|| {
        let here = Pos::new(cell.pos.0, cell.pos.1);
        let (_, nearest) = blocks.range((row, 0)..=(row, cell.pos.1)).next_back()?;
        nearest.area.contains(here).then_some(nearest)
    });
    let block = block.ok_or_else(|| Unreadable::Token("a shared or array formula without its record".into()))?;
    if !block.array {
        return decode(&block.rgce, &block.extra, ctx, Some(cell.pos), sheet).map(|text| Some((text, None)));
    }
    if Pos::new(cell.pos.0, cell.pos.1) != block.area.first {
        return Ok(None);
    }
    decode(&block.rgce, &block.extra, ctx, None, sheet).map(|text| Some((text, Some(block.area))))
}

/// The last row and column of a sheet: a reference over all of them is a whole column or
/// row.
const LAST_ROW: u32 = 0xF_FFFF;
const LAST_COL: u32 = 0x3FFF;

/// The formula of `rgce` (with `extra`, its `RgbExtra`) as an xlsx file spells it. `origin`
/// is the cell a shared formula computes in, which its relative references (`PtgRefN`,
/// `PtgAreaN`) count from; `sheet` the file index of the formula's sheet.
fn decode(
    rgce: &[u8],
    extra: &[u8],
    ctx: &Context,
    origin: Option<(u32, u32)>,
    sheet: Option<usize>,
) -> Result<String, Unreadable> {
    let mut bytes = Bytes { data: rgce, at: 0 };
    let mut extra = Bytes { data: extra, at: 0 };
    let mut stack: Vec<Item> = Vec::new();
    while !bytes.done() {
        let ptg = bytes.u8()?;
        // Operand and function tokens come in three classes (reference, value, array).
        let base = if ptg >= 0x20 { (ptg & 0x1F) | 0x20 } else { ptg };
        match base {
            0x01 => return Err(Unreadable::Token("a shared or array formula inside another".into())),
            0x02 => return Err(Unreadable::DataTable),
            0x03..=0x11 => biff::binary(&mut stack, ptg)?,
            0x12 | 0x13 => {
                let operand = stack.pop().ok_or_else(biff::damaged)?;
                let sign = if ptg == 0x12 { '+' } else { '-' };
                let text = format!("{sign}{}", biff::wrap(operand, biff::UNARY));
                stack.push(Item { text, precedence: biff::UNARY });
            }
            0x14 => {
                let operand = stack.pop().ok_or_else(biff::damaged)?;
                let text = format!("{}%", biff::wrap(operand, biff::PERCENT));
                stack.push(Item { text, precedence: biff::PERCENT });
            }
            0x15 => {
                let inner = stack.pop().ok_or_else(biff::damaged)?;
                stack.push(atom(format!("({})", inner.text)));
            }
            0x16 => stack.push(atom(String::new())),
            0x17 => {
                // PtgStr: a count of UTF-16 units, then the units (no flags byte).
                let cch = bytes.u16()? as usize;
                let units: Vec<u16> =
                    bytes.take(2 * cch)?.chunks_exact(2).map(|u| u16::from_le_bytes([u[0], u[1]])).collect();
                let text = String::from_utf16_lossy(&units);
                stack.push(atom(format!("\"{}\"", text.replace('"', "\"\""))));
            }
            0x18 => return Err(Unreadable::Token("a table reference".into())),
            0x19 => biff::attribute(&mut bytes, &mut stack)?,
            0x1C => stack.push(atom(biff::error_text(bytes.u8()?).to_string())),
            0x1D => stack.push(atom(if bytes.u8()? != 0 { "TRUE" } else { "FALSE" }.to_string())),
            0x1E => stack.push(atom(bytes.u16()?.to_string())),
            0x1F => stack.push(atom(biff::number(bytes.f64()?))),
            0x20 => return Err(Unreadable::Token("an array constant".into())),
            0x21 => {
                let (name, argc) = function(bytes.u16()?)?;
                let argc = argc.ok_or_else(|| Unreadable::Token(format!("{name} with a fixed count of arguments")))?;
                biff::call(&mut stack, name, argc as usize)?;
            }
            0x22 => {
                let argc = (bytes.u8()? & 0x7F) as usize;
                let iftab = bytes.u16()? & 0x7FFF;
                if iftab == 0xFF {
                    biff::user_call(&mut stack, argc)?;
                } else {
                    biff::call(&mut stack, function(iftab)?.0, argc)?;
                }
            }
            0x23 => {
                let index = bytes.u32()? as usize;
                stack.push(atom(biff::defined_name(ctx, index, sheet)?));
            }
            0x24 | 0x2C => {
                let (row, col) = (bytes.u32()?, bytes.u16()?);
                let at = if base == 0x2C { origin } else { None };
                stack.push(atom(cell_text(location(row, col, at))));
            }
            0x25 | 0x2D => {
                let (r1, r2, c1, c2) = (bytes.u32()?, bytes.u32()?, bytes.u16()?, bytes.u16()?);
                let at = if base == 0x2D { origin } else { None };
                stack.push(atom(area_text(location(r1, c1, at), location(r2, c2, at))));
            }
            0x26..=0x28 => {
                // A reference expression's precomputed area: the tokens that compute it
                // follow, and its cached rectangles (RFx, 16 bytes each) are in the extra data.
                bytes.take(6)?;
                if base == 0x26 {
                    let count = extra.u32()? as usize;
                    extra.take(count.checked_mul(16).ok_or_else(biff::damaged)?)?;
                }
            }
            0x29 | 0x2E | 0x2F => {
                bytes.take(2)?;
            }
            0x2A => {
                bytes.take(6)?;
                stack.push(atom("#REF!".into()));
            }
            0x2B => {
                bytes.take(12)?;
                stack.push(atom("#REF!".into()));
            }
            0x39 => {
                let (ixti, index) = (bytes.u16()?, bytes.u32()? as usize);
                stack.push(atom(biff::external_name(ctx, ixti, index)?));
            }
            0x3A | 0x3C => {
                let ixti = bytes.u16()?;
                let (row, col) = (bytes.u32()?, bytes.u16()?);
                let text = match biff::sheet_prefix(ctx, ixti)? {
                    Some(prefix) if base == 0x3A => format!("{prefix}{}", cell_text(location(row, col, None))),
                    _ => "#REF!".to_string(),
                };
                stack.push(atom(text));
            }
            0x3B | 0x3D => {
                let ixti = bytes.u16()?;
                let (r1, r2, c1, c2) = (bytes.u32()?, bytes.u32()?, bytes.u16()?, bytes.u16()?);
                let text = match biff::sheet_prefix(ctx, ixti)? {
                    Some(prefix) if base == 0x3B => {
                        format!("{prefix}{}", area_text(location(r1, c1, None), location(r2, c2, None)))
                    }
                    _ => "#REF!".to_string(),
                };
                stack.push(atom(text));
            }
            other => return Err(Unreadable::Token(format!("the token 0x{other:02X}"))),
        }
    }
    match (stack.pop(), stack.is_empty()) {
        (Some(item), true) => Ok(item.text),
        _ => Err(biff::damaged()),
    }
}

/// A built-in function by its number: BIFF8's table ([MS-XLS] 2.5.198.17), which MS-XLSB's
/// Ftab ([MS-XLSB] 2.5.98.10) continues with Excel 2007's functions (IFERROR is 480): the
/// registry holds both (`FnSpec::biff`).
fn function(iftab: u16) -> Result<(&'static str, Option<u8>), Unreadable> {
    biff::function(iftab)
}

/// One end of a reference: (row, column, row relative, column relative). The column field
/// (`ColRelShort`) holds 14 bits of column, bit 14 the column relative, bit 15 the row
/// relative; in a shared formula (`origin`) a relative part is a signed offset from it.
fn location(row: u32, col: u16, origin: Option<(u32, u32)>) -> (u32, u32, bool, bool) {
    let col_relative = col & 0x4000 != 0;
    let row_relative = col & 0x8000 != 0;
    let (mut r, mut c) = (row, u32::from(col & 0x3FFF));
    if let Some((orow, ocol)) = origin {
        if row_relative {
            r = (i64::from(orow) + i64::from(row as i32)).rem_euclid(i64::from(LAST_ROW) + 1) as u32;
        }
        if col_relative {
            // 14 bits, signed.
            let offset = ((c << 18) as i32 >> 18) as i64;
            c = (i64::from(ocol) + offset).rem_euclid(i64::from(LAST_COL) + 1) as u32;
        }
    }
    (r, c, row_relative, col_relative)
}

fn dollar(relative: bool) -> &'static str {
    if relative {
        ""
    } else {
        "$"
    }
}

fn cell_text((row, col, row_relative, col_relative): (u32, u32, bool, bool)) -> String {
    format!("{}{}{}{}", dollar(col_relative), column_name(col), dollar(row_relative), row + 1)
}

/// An area as a file spells it: all rows of columns is `A:B`, all columns of rows `1:2`.
fn area_text(first: (u32, u32, bool, bool), last: (u32, u32, bool, bool)) -> String {
    if first.0 == 0 && last.0 == LAST_ROW {
        return format!("{}{}:{}{}", dollar(first.3), column_name(first.1), dollar(last.3), column_name(last.1));
    }
    if first.1 == 0 && last.1 == LAST_COL {
        return format!("{}{}:{}{}", dollar(first.2), first.0 + 1, dollar(last.2), last.0 + 1);
    }
    format!("{}:{}", cell_text(first), cell_text(last))
}

/// The value of `name="…"` in an XML start tag's text.
fn attribute<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let start = tag.find(&format!(" {name}=\"")).or_else(|| tag.starts_with(&format!("{name}=\"")).then_some(0))?;
    let value = &tag[start..];
    let value = &value[value.find('"')? + 1..];
    Some(&value[..value.find('"')?])
}

/// An XLWideString (a count of UTF-16 units, then the units) and what follows it; `None`
/// for a null string or one past the record's end.
fn wide_string(bytes: &[u8]) -> Option<(String, &[u8])> {
    let count = usize::try_from(u32::from_le_bytes(bytes.get(..4)?.try_into().ok()?)).ok()?;
    let units: Vec<u16> =
        bytes.get(4..4 + count.checked_mul(2)?)?.chunks(2).map(|u| u16::from_le_bytes([u[0], u[1]])).collect();
    Some((String::from_utf16_lossy(&units), &bytes[4 + count * 2..]))
}

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
}

/// The records of a part ([MS-XLSB] 2.1.4), read as a stream, and the byte the next one
/// starts at (for errors).
struct Records<R: Read>(R, u64);

impl<R: Read> Records<R> {
    /// The next record's type and the first `keep` bytes of its body (the rest is skipped);
    /// `None` at the part's end. A record the part ends inside, or whose type or size goes on
    /// past its last byte, is an error naming its byte: it was read short, or as other records.
    fn next_head(&mut self, keep: u64) -> std::io::Result<Option<(u16, Vec<u8>)>> {
        let start = self.1;
        let Some(kind) = self.varint(2, "type")? else { return Ok(None) };
        let size = self.varint(4, "size")?.ok_or_else(|| cut_short(start, "its size"))?;
        let mut head = Vec::new();
        (&mut self.0).take(size.min(keep)).read_to_end(&mut head)?;
        let skipped = std::io::copy(&mut (&mut self.0).take(size.saturating_sub(keep)), &mut std::io::sink())?;
        if head.len() as u64 + skipped < size {
            let what = format!("the {size} bytes its size gives (record 0x{kind:04X})");
            return Err(cut_short(start, &what));
        }
        self.1 += size;
        Ok(Some((kind as u16, head)))
    }

    /// A little-endian number of at most `bytes` bytes, 7 bits each, the high bit saying
    /// another follows; `None` at the end of the stream.
    fn varint(&mut self, bytes: u32, what: &str) -> std::io::Result<Option<u64>> {
        let start = self.1;
        let mut value = 0u64;
        for i in 0..bytes {
            let mut byte = [0u8];
            if self.0.read(&mut byte)? == 0 {
                return if i == 0 { Ok(None) } else { Err(cut_short(start, &format!("its {what}"))) };
            }
            self.1 += 1;
            value |= u64::from(byte[0] & 0x7F) << (7 * i);
            if byte[0] & 0x80 == 0 {
                return Ok(Some(value));
            }
        }
        Err(std::io::Error::other(format!(
            "the record at byte {start} has a {what} of more than {bytes} bytes (the high bit of its last byte is set; \
             [MS-XLSB] 2.1.4 allows {bytes}): a damaged file"
        )))
    }
}

/// The error of a record at byte `start` that the part ends inside of, before `what`.
fn cut_short(start: u64, what: &str) -> std::io::Error {
    std::io::Error::other(format!("the record at byte {start} is cut short: the part ends before {what}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(rgce: &[u8], origin: Option<(u32, u32)>) -> Result<String, Unreadable> {
        let sheets = vec!["Sheet1".to_string(), "My Data".to_string()];
        let xtis = vec![(0, 1, 1)];
        let books = vec![SupBook::Own];
        let names = vec![("Rate".to_string(), None), ("_xlfn.XOR".to_string(), None)];
        let ctx = Context { sheets: &sheets, xtis: &xtis, books: &books, names: &names };
        decode(rgce, &[], &ctx, origin, Some(0))
    }

    #[test]
    fn a_quote_in_a_string_is_doubled() {
        // PtgStr of `a"b` (3 UTF-16 units, [MS-XLSB] 2.5.98.81).
        assert_eq!(run(&[0x17, 3, 0, b'a', 0, b'"', 0, b'b', 0], None).unwrap(), "\"a\"\"b\"");
    }

    #[test]
    fn references_keep_their_flags_rows_are_four_bytes() {
        // PtgRef B3, both relative (bits 15 and 14 of the column); $A1 (row relative only).
        assert_eq!(run(&[0x44, 2, 0, 0, 0, 1, 0xC0], None).unwrap(), "B3");
        assert_eq!(run(&[0x44, 0, 0, 0, 0, 0, 0x80], None).unwrap(), "$A1");
        // PtgGe is 0x0C, PtgGt 0x0D ([MS-XLSB] 2.5.98.16).
        assert_eq!(run(&[0x1E, 1, 0, 0x1E, 2, 0, 0x0C], None).unwrap(), "1>=2");
        assert_eq!(run(&[0x1E, 1, 0, 0x1E, 2, 0, 0x0D], None).unwrap(), "1>2");
    }

    #[test]
    fn a_3d_reference_names_its_sheet_through_the_extern_sheet() {
        // PtgArea3d, XTI 0 (sheet 1, 'My Data'), all rows of column A: a whole column.
        let rgce = [0x3B, 0, 0, 0, 0, 0, 0, 0xFF, 0xFF, 0x0F, 0, 0, 0x40, 0, 0x40];
        assert_eq!(run(&rgce, None).unwrap(), "'My Data'!A:A");
    }

    #[test]
    fn shared_formulas_count_from_their_cell_and_future_functions_are_named() {
        // PtgRefN row -1, column +1 (relative) from C5 (row 4, column 2): D4.
        assert_eq!(run(&[0x4C, 0xFF, 0xFF, 0xFF, 0xFF, 0x01, 0xC0], Some((4, 2))).unwrap(), "D4");
        // PtgName 2 (the hidden `_xlfn.XOR`), TRUE, PtgFuncVar of 2 through number 255.
        assert_eq!(run(&[0x23, 2, 0, 0, 0, 0x1D, 1, 0x42, 2, 0xFF, 0], None).unwrap(), "_xlfn.XOR(TRUE)");
        assert_eq!(run(&[0x43, 1, 0, 0, 0], None).unwrap(), "Rate");
    }
}
