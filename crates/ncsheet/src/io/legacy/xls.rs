//! Excel 97–2003 workbooks (`.xls`, BIFF8, MS-XLS): the `Workbook` stream of the compound
//! file, read record by record. The globals give the sheets, shared strings, number formats,
//! defined names and what 3D references point at; each worksheet's records its cells, with
//! formulas as `FORMULA` records holding Excel's cached result, `SHRFMLA` (a formula shared
//! by a block of cells) and `ARRAY` (a Ctrl+Shift+Enter formula over an area).

use std::collections::HashMap;
use std::io::{Cursor, Read};
use std::rc::Rc;

use crate::eval::{Value, XlError};
use crate::formula::address::{Pos, Rect};
use crate::workbook::Visibility;

use super::biff::{self, Context, SupBook, Unreadable};
use crate::io::notes::{quoted, Grouped};

use super::{cells_named, Book, Cell, Name, Sheet, MAX_CELLS};

/// A NAME record: its name, the sheet it belongs to, formula bytes, extra bytes, and whether
/// it names a macro.
type NameRecord = (String, Option<usize>, Vec<u8>, Vec<u8>, bool);

/// A shared or array formula by its area: the area, its formula bytes and extra bytes.
type AreaFormula = (Rect, Vec<u8>, Vec<u8>);

/// One record, its `CONTINUE` records' data kept apart (the shared-string table needs to
/// know where each starts).
struct Record<'a> {
    kind: u16,
    parts: Vec<&'a [u8]>,
    /// Where its header starts in the Workbook stream (for errors).
    at: usize,
}

impl Record<'_> {
    fn data(&self) -> std::borrow::Cow<'_, [u8]> {
        if self.parts.len() == 1 {
            std::borrow::Cow::Borrowed(self.parts[0])
        } else {
            std::borrow::Cow::Owned(self.parts.concat())
        }
    }
}

const CONTINUE: u16 = 0x003C;
const EOF: u16 = 0x000A;
const BOF: u16 = 0x0809;

/// The records of a substream from `start`, up to its EOF, those of nested substreams
/// (a chart on a sheet) left out.
fn records(stream: &[u8], start: usize) -> Result<Vec<Record<'_>>, String> {
    Ok(substream(stream, start)?.0)
}

/// [`records`], and the offset where they end. A record whose length runs past the stream,
/// or a stream that ends before the substream's EOF, is refused: the records after the
/// break were dropped without a word (a file cut short, a damaged length).
fn substream(stream: &[u8], start: usize) -> Result<(Vec<Record<'_>>, usize), String> {
    let mut out: Vec<Record> = Vec::new();
    let mut at = start;
    let mut depth = 0usize;
    let mut first = true;
    loop {
        let Some(header) = stream.get(at..at + 4) else {
            return Err(format!(
                "the Workbook stream ends at byte {} inside the records that start at byte {start}, before their EOF \
                 record: a file cut short",
                stream.len()
            ));
        };
        let kind = u16::from_le_bytes([header[0], header[1]]);
        let len = u16::from_le_bytes([header[2], header[3]]) as usize;
        let Some(data) = stream.get(at + 4..at + 4 + len) else {
            return Err(format!(
                "record {} (0x{kind:04X}) at byte {at} of the Workbook stream says it holds {len} bytes, past the \
                 stream's end (byte {}): a damaged file",
                record_name(kind),
                stream.len()
            ));
        };
        let header = at;
        at += 4 + len;
        match kind {
            BOF if !first => depth += 1,
            EOF if depth > 0 => {
                depth -= 1;
                continue;
            }
            _ => {}
        }
        first = false;
        if depth > 0 {
            continue;
        }
        if kind == CONTINUE {
            if let Some(last) = out.last_mut() {
                last.parts.push(data);
            }
            continue;
        }
        if kind == EOF {
            return Ok((out, at));
        }
        out.push(Record { kind, parts: vec![data], at: header });
    }
}

/// MS-XLS's name of a record type the reader reads, for errors.
fn record_name(kind: u16) -> &'static str {
    match kind {
        0x0006 => "Formula",
        0x0017 => "ExternSheet",
        0x0018 => "Lbl",
        0x0023 => "ExternName",
        0x0085 => "BoundSheet8",
        0x00BD => "MulRk",
        0x00D6 => "RString",
        0x00E0 => "XF",
        0x00FC => "SST",
        0x00FD => "LabelSst",
        0x01AE => "SupBook",
        0x0203 => "Number",
        0x0204 => "Label",
        0x0205 => "BoolErr",
        0x0207 => "String",
        0x0221 => "Array",
        0x0236 => "Table",
        0x027E => "RK",
        0x041E => "Format",
        _ => "of an unknown type",
    }
}

/// The refusal of a damaged record of `whose` (the workbook's globals or a sheet): where it
/// is and what is wrong with it. A field read past a record's end was read as 0, silently.
fn damaged_record(whose: &str, r: &Record, what: &str) -> String {
    format!(
        "{whose}: record {} (0x{:04X}) at byte {} of the Workbook stream {what}: a damaged file",
        record_name(r.kind),
        r.kind,
        r.at
    )
}

/// Checks that a record holds the `need` bytes of the fields read from it.
fn holds(whose: &str, r: &Record, d: &[u8], need: usize) -> Result<(), String> {
    if d.len() < need {
        return Err(damaged_record(whose, r, &format!("is cut short ({} bytes where {need} are needed)", d.len())));
    }
    Ok(())
}

/// The formula bytes of a record whose `cce` (a u16) is at `start - 2`, and the extra bytes
/// after them; `None` when the record is shorter than `cce` says.
fn formula_bytes(d: &[u8], start: usize) -> Option<(Vec<u8>, Vec<u8>)> {
    let cce = u16_at(d, start.checked_sub(2)?) as usize;
    let rgce = d.get(start..start + cce)?.to_vec();
    Some((rgce, d[start + cce..].to_vec()))
}

fn u16_at(b: &[u8], at: usize) -> u16 {
    b.get(at..at + 2).map_or(0, |s| u16::from_le_bytes([s[0], s[1]]))
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    b.get(at..at + 4).map_or(0, |s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
}

fn f64_at(b: &[u8], at: usize) -> f64 {
    b.get(at..at + 8).map_or(0.0, |s| f64::from_le_bytes(s.try_into().expect("8 bytes")))
}

/// What the globals substream says.
#[derive(Default)]
struct Globals {
    /// (name, stream offset of its BOF, visibility, sheet type: 0 a worksheet).
    sheets: Vec<(String, usize, Visibility, u8)>,
    /// Shared among the cells that show them.
    strings: Vec<Rc<str>>,
    formats: HashMap<u16, String>,
    /// Each XF's number format index.
    xf_formats: Vec<u16>,
    books: Vec<SupBook>,
    xtis: Vec<(u16, i16, i16)>,
    /// (name, sheet index it belongs to, formula bytes, extra bytes, is a macro's name).
    names: Vec<NameRecord>,
    date_1904: bool,
    /// `Country`'s iCountryDef: the country code of the saving Excel's UI language.
    country: Option<u16>,
}

/// Reads an .xls file's bytes into a [`Book`].
pub fn read(bytes: &[u8]) -> Result<Book, String> {
    let stream = workbook_stream(bytes)?;
    let globals = read_globals(&stream)?;
    let sheet_names: Vec<String> = globals.sheets.iter().map(|s| s.0.clone()).collect();
    let name_refs: Vec<(String, Option<usize>)> = globals.names.iter().map(|n| (n.0.clone(), n.1)).collect();
    let ctx = Context { sheets: &sheet_names, xtis: &globals.xtis, books: &globals.books, names: &name_refs };
    let mut book = Book {
        date_1904: globals.date_1904,
        application: application(bytes),
        excel_language: globals.country.and_then(ui_language),
        ..Book::default()
    };
    // Worksheets keep their order; a sheet's index in the file → its index in the book.
    let mut index_in_book: Vec<Option<usize>> = Vec::new();
    // The bytes the sheets' records span together: in a sound file they do not overlap, so
    // never more than the stream; sheets pointing into each other would read it again and
    // again (quadratic time, the same cells many times over).
    let (mut spanned, mut cells) = (0usize, 0usize);
    for (name, offset, visibility, kind) in &globals.sheets {
        if *kind != 0 {
            let what = match kind {
                1 => "an Excel 4 macro sheet",
                2 => "a chart sheet",
                6 => "a VBA module",
                _ => "not a worksheet",
            };
            book.notes.push(format!("sheet '{name}' is {what} and was left out"));
            index_in_book.push(None);
            continue;
        }
        let sheet_index = index_in_book.len();
        index_in_book.push(Some(book.sheets.len()));
        let (records, end) = sheet_substream(&stream, *offset, name)?;
        spanned += end.saturating_sub(*offset);
        if spanned > stream.len() {
            return Err(format!(
                "the records of sheet '{name}' (from byte {offset} of the Workbook stream, its BoundSheet8) overlap \
                 another sheet's: a damaged file"
            ));
        }
        let sheet = read_sheet(records, name, *visibility, sheet_index, &ctx, &globals, &mut book.notes)?;
        cells += sheet.cells.len();
        if cells > MAX_CELLS {
            return Err(super::too_many_cells());
        }
        book.sheets.push(sheet);
    }

    let mut left_out = Grouped::default();
    for (name, scope, rgce, extra, is_macro) in &globals.names {
        if *is_macro || rgce.is_empty() {
            continue;
        }
        let sheet = match scope {
            None => None,
            Some(i) => match index_in_book.get(*i).copied().flatten() {
                Some(s) => Some(s),
                None => {
                    left_out.push(format!("name {} belongs to a sheet that was left out", quoted(name)));
                    continue;
                }
            },
        };
        match biff::decode(rgce, extra, &ctx, (0, 0), *scope) {
            Ok(formula) => book.names.push(Name { name: name.clone(), formula, sheet }),
            Err(why) => left_out.push(format!("name {} was left out: ncsheet does not read {why}", quoted(name))),
        }
    }
    left_out.finish("defined names were left out", &mut book.notes);
    Ok(book)
}

/// The `Workbook` stream of the compound file.
fn workbook_stream(bytes: &[u8]) -> Result<Vec<u8>, String> {
    let mut cfb = cfb::CompoundFile::open(Cursor::new(bytes)).map_err(|e| format!("not a compound file: {e}"))?;
    let name = if cfb.is_stream("/Workbook") {
        "/Workbook"
    } else if cfb.is_stream("/Book") {
        return Err("it is an Excel 5.0/95 (BIFF5) workbook; ncsheet reads Excel 97-2003 (BIFF8) .xls: \
                    save it as .xlsx in Excel or LibreOffice"
            .into());
    } else if cfb.is_stream("/EncryptedPackage") {
        return Err("it is an encrypted workbook; remove the password in Excel and save again".into());
    } else {
        return Err("the compound file has no Workbook stream".into());
    };
    let mut stream = Vec::new();
    cfb.open_stream(name)
        .and_then(|mut s| s.read_to_end(&mut stream))
        .map_err(|e| format!("the Workbook stream: {e}"))?;
    Ok(stream)
}

/// The program that saved the file: `SummaryInformation`'s application name ([MS-OLEPS]
/// 2.21 PropertySetStream, its first property set; PIDSI_APPNAME 0x12, a CodePageString in
/// the code page of property 1). Read here, not by calamine, which parses the whole
/// workbook on the way and panicked on a damaged one.
fn application(bytes: &[u8]) -> Option<String> {
    let mut cfb = cfb::CompoundFile::open(Cursor::new(bytes)).ok()?;
    let mut stream = Vec::new();
    cfb.open_stream("/\u{5}SummaryInformation").ok()?.take(1 << 20).read_to_end(&mut stream).ok()?;
    let set = stream.get(u32_at(&stream, 44) as usize..)?;
    let count = (u32_at(set, 4) as usize).min(set.len() / 8);
    let property = |id: u32| {
        (0..count).find(|i| u32_at(set, 8 + 8 * i) == id).and_then(|i| set.get(u32_at(set, 12 + 8 * i) as usize..))
    };
    const VT_I2: u16 = 0x02;
    const VT_LPSTR: u16 = 0x1E;
    let utf16 = property(1).is_some_and(|p| u16_at(p, 0) == VT_I2 && u16_at(p, 4) == 1200);
    let name = property(0x12).filter(|p| u16_at(p, 0) == VT_LPSTR)?;
    let text = name.get(8..8 + u32_at(name, 4) as usize)?;
    let text = if utf16 {
        String::from_utf16_lossy(&text.chunks_exact(2).map(|u| u16::from_le_bytes([u[0], u[1]])).collect::<Vec<_>>())
    } else {
        text.iter().map(|&b| char::from(b)).collect()
    };
    Some(text.trim_end_matches('\0').to_string()).filter(|t| !t.is_empty())
}

/// The records of the sheet whose BoundSheet8 gives `offset`: a worksheet's BOF must start
/// there ([MS-XLS] 2.4.28, lbPlyPos). An offset anywhere else read other records, or none,
/// as the sheet's: the sheet opened empty or with the workbook's own records as its cells.
fn sheet_substream<'s>(stream: &'s [u8], offset: usize, name: &str) -> Result<(Vec<Record<'s>>, usize), String> {
    const WORKSHEET: u16 = 0x0010;
    let bof = stream.get(offset..offset + 8).filter(|h| u16_at(h, 0) == BOF);
    if bof.is_none_or(|h| u16_at(h, 6) != WORKSHEET) {
        return Err(format!(
            "sheet '{name}': its BoundSheet8 record gives byte {offset} of the Workbook stream ({} bytes) as where \
             its records start, and no worksheet's BOF record starts there: a damaged file",
            stream.len()
        ));
    }
    substream(stream, offset).map_err(|e| format!("sheet '{name}': {e}"))
}

fn read_globals(stream: &[u8]) -> Result<Globals, String> {
    let mut g = Globals::default();
    let records = records(stream, 0)?;
    let Some(bof) = records.first().filter(|r| r.kind == BOF) else {
        return Err("the Workbook stream does not start with a BOF record".into());
    };
    if u16_at(&bof.data(), 0) != 0x0600 {
        return Err("it is not a BIFF8 (Excel 97-2003) workbook; save it as .xlsx in Excel or LibreOffice".into());
    }
    const WHOSE: &str = "the workbook's globals";
    for r in &records {
        let d = r.data();
        let cut_short = || damaged_record(WHOSE, r, "is cut short");
        match r.kind {
            0x002F => return Err("the workbook is encrypted; remove the password in Excel and save again".into()),
            0x0022 => {
                holds(WHOSE, r, &d, 2)?;
                g.date_1904 = u16_at(&d, 0) == 1;
            }
            0x008C if d.len() >= 2 => g.country = Some(u16_at(&d, 0)),
            0x0085 => {
                holds(WHOSE, r, &d, 8)?;
                let offset = u32_at(&d, 0) as usize;
                let visibility = match d.get(4).map(|v| v & 0x03) {
                    Some(1) => Visibility::Hidden,
                    Some(2) => Visibility::VeryHidden,
                    _ => Visibility::Visible,
                };
                let (kind, cch) = (d[5], d[6] as usize);
                let (name, _) = biff::unicode_string(&d[7..], cch).ok_or_else(cut_short)?;
                g.sheets.push((name, offset, visibility, kind));
            }
            0x00FC => {
                holds(WHOSE, r, &d, 8)?;
                g.strings = shared_strings(r);
            }
            0x041E => {
                holds(WHOSE, r, &d, 5)?;
                let cch = u16_at(&d, 2) as usize;
                let (code, _) = biff::unicode_string(&d[4..], cch).ok_or_else(cut_short)?;
                g.formats.insert(u16_at(&d, 0), code);
            }
            0x00E0 => {
                holds(WHOSE, r, &d, 4)?;
                g.xf_formats.push(u16_at(&d, 2));
            }
            0x01AE => {
                holds(WHOSE, r, &d, 4)?;
                g.books.push(supbook(&d));
            }
            0x0023 => {
                holds(WHOSE, r, &d, 8)?;
                external_name(&mut g.books, &d).ok_or_else(cut_short)?;
            }
            0x0017 => {
                let count = u16_at(&d, 0) as usize;
                holds(WHOSE, r, &d, 2 + 6 * count)?;
                for i in 0..count {
                    let at = 2 + 6 * i;
                    g.xtis.push((u16_at(&d, at), u16_at(&d, at + 2) as i16, u16_at(&d, at + 4) as i16));
                }
            }
            0x0018 => {
                holds(WHOSE, r, &d, 15)?;
                g.names.push(defined_name(&d).ok_or_else(cut_short)?);
            }
            _ => {}
        }
    }
    Ok(g)
}

/// The language of an Excel whose `Country` record (MS-XLS) names `country`, the
/// international calling code of the country of its UI language, when it is not English
/// and CELL's info types are translated into it; `None` for a country of several languages
/// (Belgium, Switzerland, Canada) or one whose translations ncsheet does not hold.
fn ui_language(country: u16) -> Option<&'static str> {
    Some(match country {
        31 => "nl",
        33 => "fr",
        34 | 52 => "es",
        36 => "hu",
        39 => "it",
        43 | 49 => "de",
        45 => "da",
        47 => "nb",
        48 => "pl",
        55 => "pt-BR",
        351 => "pt-PT",
        358 => "fi",
        420 => "cs",
        _ => return None,
    })
}

/// `SupBook`: this workbook (`ctab` sheets, `cch` 0x0401), the add-ins (0x3A01), or another.
fn supbook(d: &[u8]) -> SupBook {
    match u16_at(d, 2) {
        0x0401 => SupBook::Own,
        0x3A01 => SupBook::AddIns(Vec::new()),
        _ => SupBook::Other(Vec::new()),
    }
}

/// `ExternName`: a name of the last `SupBook` (an add-in function's, for one); `None` when
/// the record is cut short.
fn external_name(books: &mut [SupBook], d: &[u8]) -> Option<()> {
    let cch = *d.get(6)? as usize;
    let (name, _) = biff::unicode_string(d.get(7..)?, cch)?;
    if let Some(SupBook::AddIns(names) | SupBook::Other(names)) = books.last_mut() {
        names.push(name);
    }
    Some(())
}

/// `Lbl`: a defined name. Built-in names (`Print_Area`…) are stored as one character.
/// `None` when the record is cut short.
fn defined_name(d: &[u8]) -> Option<NameRecord> {
    let flags = u16_at(d, 0);
    let cch = *d.get(3)? as usize;
    let cce = u16_at(d, 4) as usize;
    let itab = u16_at(d, 8) as usize;
    let (mut name, used) = biff::unicode_string(d.get(14..)?, cch)?;
    if flags & 0x20 != 0 {
        let builtin = [
            "Consolidate_Area",
            "Auto_Open",
            "Auto_Close",
            "Extract",
            "Database",
            "Criteria",
            "Print_Area",
            "Print_Titles",
            "Recorder",
            "Data_Form",
            "Auto_Activate",
            "Auto_Deactivate",
            "Sheet_Title",
            "_FilterDatabase",
        ];
        let code = name.chars().next().map_or(0, |c| c as usize);
        name = format!("_xlnm.{}", builtin.get(code).copied().unwrap_or("Unknown"));
    }
    let start = 14 + used;
    let rgce = d.get(start..start + cce)?.to_vec();
    let extra = d[start + cce..].to_vec();
    let scope = (itab > 0).then(|| itab - 1);
    // fFunc or fOB: a macro's name, no formula of a worksheet.
    let is_macro = flags & 0x0A != 0;
    Some((name, scope, rgce, extra, is_macro))
}

/// The shared-string table (`SST` and its `CONTINUE`s). A string's characters may run on
/// into the next record, which then starts with a new flags byte saying their width.
fn shared_strings(r: &Record) -> Vec<Rc<str>> {
    let mut reader = PartReader { parts: &r.parts, part: 0, at: 8 };
    let count = u32_at(r.parts[0], 4) as usize;
    let mut out = Vec::with_capacity(count.min(1 << 20));
    for _ in 0..count {
        let Some(s) = reader.rich_string() else { break };
        out.push(s.into());
    }
    out
}

/// The `XLUnicodeString` at `at` of a record (a cell's text, a formula's text result), whose
/// characters may run on into `CONTINUE` records, each starting with a flags byte of its own
/// (MS-XLS: a string continued in the next record): that byte is not a character. `None`
/// when the records end before the string does.
fn continued_string(r: &Record, at: usize) -> Option<String> {
    PartReader { parts: &r.parts, part: 0, at }.rich_string()
}

struct PartReader<'a, 'b> {
    parts: &'b [&'a [u8]],
    part: usize,
    at: usize,
}

impl PartReader<'_, '_> {
    fn byte(&mut self) -> Option<u8> {
        while self.at >= self.parts.get(self.part)?.len() {
            self.part += 1;
            self.at = 0;
        }
        let b = self.parts[self.part][self.at];
        self.at += 1;
        Some(b)
    }
    fn u16(&mut self) -> Option<u16> {
        Some(u16::from_le_bytes([self.byte()?, self.byte()?]))
    }
    fn u32(&mut self) -> Option<u32> {
        Some(u32::from_le_bytes([self.byte()?, self.byte()?, self.byte()?, self.byte()?]))
    }
    fn skip(&mut self, n: usize) -> Option<()> {
        for _ in 0..n {
            self.byte()?;
        }
        Some(())
    }

    /// `XLUnicodeRichExtendedString`, its characters possibly split over records.
    fn rich_string(&mut self) -> Option<String> {
        let cch = self.u16()? as usize;
        let flags = self.byte()?;
        let runs = if flags & 0x08 != 0 { self.u16()? as usize } else { 0 };
        let ext = if flags & 0x04 != 0 { self.u32()? as usize } else { 0 };
        let mut wide = flags & 0x01 != 0;
        let mut units: Vec<u16> = Vec::with_capacity(cch);
        while units.len() < cch {
            if self.at >= self.parts.get(self.part)?.len() {
                self.part += 1;
                self.at = 0;
                wide = self.byte()? & 0x01 != 0;
                continue;
            }
            units.push(if wide { self.u16()? } else { self.byte()? as u16 });
        }
        self.skip(4 * runs + ext)?;
        Some(String::from_utf16_lossy(&units))
    }
}

/// A formula record as read, decoded once the sheet's shared and array formulas are known.
struct FormulaRecord {
    pos: (u32, u32),
    xf: u16,
    cached: Option<Value>,
    rgce: Vec<u8>,
    extra: Vec<u8>,
}

/// A sheet's records: cells, formulas and the shared and array formulas they point to.
#[allow(clippy::too_many_arguments)]
fn read_sheet(
    records: Vec<Record<'_>>,
    name: &str,
    visibility: Visibility,
    sheet_index: usize,
    ctx: &Context,
    globals: &Globals,
    notes: &mut Vec<String>,
) -> Result<Sheet, String> {
    let mut sheet = Sheet { name: name.to_string(), visibility, ..Sheet::default() };
    let whose = format!("sheet '{name}'");
    let mut formulas: Vec<FormulaRecord> = Vec::new();
    // By the first cell of their area: (area, formula bytes, extra bytes).
    let mut shared: HashMap<(u32, u32), AreaFormula> = HashMap::new();
    let mut arrays: HashMap<(u32, u32), AreaFormula> = HashMap::new();
    let mut tables: Vec<(u32, u32)> = Vec::new();
    let put = |sheet: &mut Sheet, d: &[u8], value: Value, xf: u16| {
        let pos = (u16_at(d, 0) as u32, u16_at(d, 2) as u32);
        sheet.cells.insert(pos, Cell { value: Some(value), format: format_of(globals, xf), ..Cell::default() });
    };
    for r in records {
        let d = r.data();
        holds(&whose, &r, &d, least_cell_record(r.kind))?;
        let cut_short = || damaged_record(&whose, &r, "is cut short");
        match r.kind {
            0x0203 => put(&mut sheet, &d, Value::Number(f64_at(&d, 6)), u16_at(&d, 4)),
            0x027E => put(&mut sheet, &d, Value::Number(rk(u32_at(&d, 6))), u16_at(&d, 4)),
            0x00BD => {
                let row = u16_at(&d, 0) as u32;
                let first = u16_at(&d, 2) as u32;
                let count = d.len().saturating_sub(6) / 6;
                for i in 0..count {
                    let at = 4 + 6 * i;
                    let cell = Cell {
                        value: Some(Value::Number(rk(u32_at(&d, at + 2)))),
                        format: format_of(globals, u16_at(&d, at)),
                        ..Cell::default()
                    };
                    sheet.cells.insert((row, first + i as u32), cell);
                }
            }
            0x00FD => {
                let index = u32_at(&d, 6) as usize;
                let Some(text) = globals.strings.get(index).cloned() else {
                    let what = format!(
                        "names shared string {index}, past the {} strings of the shared-string table",
                        globals.strings.len()
                    );
                    return Err(damaged_record(&whose, &r, &what));
                };
                put(&mut sheet, &d, Value::Text(text), u16_at(&d, 4));
            }
            0x0204 | 0x00D6 => {
                let text = continued_string(&r, 6).ok_or_else(cut_short)?;
                put(&mut sheet, &d, Value::Text(text.into()), u16_at(&d, 4));
            }
            0x0205 => {
                let (v, is_error) = (d[6], d[7]);
                let value = if is_error != 0 { Value::Error(error_of(v)) } else { Value::Bool(v != 0) };
                put(&mut sheet, &d, value, u16_at(&d, 4));
            }
            0x0006 => formulas.push(formula_record(&d).ok_or_else(cut_short)?),
            0x0207 => {
                let text = continued_string(&r, 0).ok_or_else(cut_short)?;
                if let Some(last) = formulas.last_mut() {
                    last.cached = Some(Value::Text(text.into()));
                }
            }
            0x04BC => {
                let area = ref_u(&d);
                let (rgce, extra) = formula_bytes(&d, 10).ok_or_else(cut_short)?;
                shared.insert((area.first.row, area.first.col), (area, rgce, extra));
            }
            0x0221 => {
                let area = ref_u(&d);
                let (rgce, extra) = formula_bytes(&d, 14).ok_or_else(cut_short)?;
                arrays.insert((area.first.row, area.first.col), (area, rgce, extra));
            }
            0x0236 => {
                let area = ref_u(&d);
                tables.push((area.first.row, area.first.col));
            }
            _ => {}
        }
    }
    let mut unread: Vec<(Unreadable, Vec<(u32, u32)>)> = Vec::new();
    let mut search_left = MAX_SHARED_SEARCH;
    for f in formulas {
        let format = format_of(globals, f.xf);
        let exp = (f.rgce.first() == Some(&0x01) && f.rgce.len() >= 5)
            .then(|| (u16_at(&f.rgce, 1) as u32, u16_at(&f.rgce, 3) as u32));
        let decoded = match exp {
            None => biff::decode(&f.rgce, &f.extra, ctx, f.pos, Some(sheet_index)).map(|t| (t, None)),
            Some(anchor) => match (
                shared_formula(&shared, anchor, f.pos, &mut search_left).map_err(|e| format!("{whose}: {e}"))?,
                arrays.get(&anchor),
            ) {
                (Some((_, rgce, extra)), _) => {
                    biff::decode(rgce, extra, ctx, f.pos, Some(sheet_index)).map(|t| (t, None))
                }
                (None, Some((area, rgce, extra))) if anchor == f.pos => {
                    biff::decode(rgce, extra, ctx, f.pos, Some(sheet_index)).map(|t| (t, Some(*area)))
                }
                (None, Some(_)) => {
                    // A cell the array formula fills: its value only.
                    let cell = Cell { value: f.cached, format, ..Cell::default() };
                    sheet.cells.insert(f.pos, cell);
                    continue;
                }
                (None, None) if tables.contains(&anchor) => Err(Unreadable::DataTable),
                (None, None) => Err(Unreadable::Token("a shared formula whose record is missing".into())),
            },
        };
        match decoded {
            Ok((text, array)) => {
                let cell = Cell { value: f.cached, formula: Some(text), array, format };
                sheet.cells.insert(f.pos, cell);
            }
            Err(why) => {
                sheet.cells.insert(f.pos, Cell { value: f.cached, format, ..Cell::default() });
                match unread.iter_mut().find(|(w, _)| *w == why) {
                    Some((_, cells)) => cells.push(f.pos),
                    None => unread.push((why, vec![f.pos])),
                }
            }
        }
    }
    for (why, cells) in unread {
        notes.push(format!(
            "{} formula cell{} of sheet '{name}' keep the value the file stored, as a constant: ncsheet does not \
             read {why} ({})",
            cells.len(),
            if cells.len() == 1 { "" } else { "s" },
            cells_named(name, &cells)
        ));
    }
    Ok(sheet)
}

/// The fewest bytes a cell record of a sheet holds (MS-XLS 2.4: the fields read from it,
/// its strings' and formulas' lengths checked apart); 0 for records the reader skips.
fn least_cell_record(kind: u16) -> usize {
    match kind {
        0x0203 => 14,          // Number: Cell, Xnum
        0x027E | 0x00FD => 10, // RK: Cell, RkNumber; LabelSst: Cell, isst
        0x00BD => 12,          // MulRk: row, first column, one RkRec, last column
        0x0204 | 0x00D6 => 9,  // Label, RString: Cell, cch, flags
        0x0205 | 0x0236 => 8,  // BoolErr: Cell, bBoolErr, fError; Table: RefU, flags
        0x0006 => 22,          // Formula: Cell, result, flags, chn, cce
        0x0207 => 3,           // String: cch, flags
        0x04BC => 10,          // ShrFmla: RefU, reserved, cUse, cce
        0x0221 => 14,          // Array: RefU, flags, chn, cce
        _ => 0,
    }
}

/// The area comparisons one sheet may spend looking for the shared formula of a cell whose
/// `PtgExp` names no area's first cell (each such cell looks through every area, about a
/// second at the limit): 100,000 such cells and as many areas, a 5 MB file, took minutes.
/// Past it the file is refused naming the sheet (docs/limits.md).
pub const MAX_SHARED_SEARCH: usize = 1 << 27;

/// The shared formula a cell's `PtgExp` points to: the one whose area starts at `anchor`,
/// as a rule, else one whose area holds the anchor or the cell (files written by other
/// programs point elsewhere in the area), that search counted against `search_left`.
fn shared_formula<'a>(
    shared: &'a HashMap<(u32, u32), AreaFormula>,
    anchor: (u32, u32),
    cell: (u32, u32),
    search_left: &mut usize,
) -> Result<Option<&'a AreaFormula>, String> {
    if let Some(found) = shared.get(&anchor) {
        return Ok(Some(found));
    }
    let mut holds = |p: (u32, u32)| -> Result<Option<&'a AreaFormula>, String> {
        *search_left = search_left.checked_sub(shared.len()).ok_or_else(|| {
            format!(
                "more than {MAX_SHARED_SEARCH} comparisons of shared formulas' areas finding the records of cells that \
                 point into them, ncsheet's limit for a sheet: a damaged or hostile file"
            )
        })?;
        Ok(shared.values().find(|(area, ..)| area.contains(Pos::new(p.0, p.1))))
    };
    match holds(anchor)? {
        Some(found) => Ok(Some(found)),
        None => holds(cell),
    }
}

/// A `FORMULA` record: its cell, style, cached result (a string one follows in a `STRING`
/// record) and formula bytes; `None` when it is shorter than its fields.
fn formula_record(d: &[u8]) -> Option<FormulaRecord> {
    let pos = (u16_at(d, 0) as u32, u16_at(d, 2) as u32);
    let result = d.get(6..14)?;
    let cached = if result[6] == 0xFF && result[7] == 0xFF {
        match result[0] {
            0x00 => None,
            0x01 => Some(Value::Bool(result[2] != 0)),
            0x02 => Some(Value::Error(error_of(result[2]))),
            _ => Some(Value::Text("".into())),
        }
    } else {
        Some(Value::Number(f64_at(d, 6)))
    };
    let (rgce, extra) = formula_bytes(d, 22)?;
    Some(FormulaRecord { pos, xf: u16_at(d, 4), cached, rgce, extra })
}

/// `RefU`: rows as 2 bytes, columns as 1.
fn ref_u(d: &[u8]) -> Rect {
    let first = Pos::new(u16_at(d, 0) as u32, d.get(4).copied().unwrap_or(0) as u32);
    let last = Pos::new(u16_at(d, 2) as u32, d.get(5).copied().unwrap_or(0) as u32);
    Rect::new(first, last)
}

/// `RkNumber`: a number in 30 bits, an integer or the top of a double, perhaps times 100.
pub(super) fn rk(v: u32) -> f64 {
    let n = if v & 0x02 != 0 { ((v as i32) >> 2) as f64 } else { f64::from_bits(((v & 0xFFFF_FFFC) as u64) << 32) };
    if v & 0x01 != 0 {
        n / 100.0
    } else {
        n
    }
}

/// A BErr (the error codes BIFF8 and [MS-XLSB] 2.5.98.2 share) as an error value.
pub(super) fn error_of(code: u8) -> XlError {
    match code {
        0x00 => XlError::Null,
        0x07 => XlError::Div0,
        0x0F => XlError::Value,
        0x17 => XlError::Ref,
        0x1D => XlError::Name,
        0x24 => XlError::Num,
        0x2B => XlError::GettingData,
        _ => XlError::NA,
    }
}

/// The number format code of an XF, `None` for General.
fn format_of(globals: &Globals, xf: u16) -> Option<String> {
    let id = *globals.xf_formats.get(xf as usize)?;
    if id == 0 {
        return None;
    }
    globals.formats.get(&id).cloned().or_else(|| builtin_format(id).map(str::to_string))
}

/// The built-in number formats a file names by number only (ECMA-376 §18.8.30, en-US).
fn builtin_format(id: u16) -> Option<&'static str> {
    Some(match id {
        1 => "0",
        2 => "0.00",
        3 => "#,##0",
        4 => "#,##0.00",
        9 => "0%",
        10 => "0.00%",
        11 => "0.00E+00",
        12 => "# ?/?",
        13 => "# ??/??",
        14 => "m/d/yyyy",
        15 => "d-mmm-yy",
        16 => "d-mmm",
        17 => "mmm-yy",
        18 => "h:mm AM/PM",
        19 => "h:mm:ss AM/PM",
        20 => "h:mm",
        21 => "h:mm:ss",
        22 => "m/d/yyyy h:mm",
        37 => "#,##0 ;(#,##0)",
        38 => "#,##0 ;[Red](#,##0)",
        39 => "#,##0.00;(#,##0.00)",
        40 => "#,##0.00;[Red](#,##0.00)",
        45 => "mm:ss",
        46 => "[h]:mm:ss",
        47 => "mmss.0",
        48 => "##0.0E+0",
        49 => "@",
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rk_numbers_are_integers_or_the_top_of_a_double_perhaps_in_hundredths() {
        assert_eq!(rk((5 << 2) | 0x02), 5.0);
        assert_eq!(rk((-7i32 << 2) as u32 | 0x02), -7.0);
        assert_eq!(rk((1234 << 2) | 0x03), 12.34);
        let top = (1.5f64.to_bits() >> 32) as u32;
        assert_eq!(rk(top), 1.5);
    }

    #[test]
    fn shared_strings_continue_across_records_with_a_new_width() {
        // Two strings: "ab" compressed; "cdé" starts compressed in the SST record and
        // continues in a CONTINUE record as UTF-16.
        let sst: &[u8] = &[2, 0, 0, 0, 2, 0, 0, 0, 2, 0, 0, b'a', b'b', 3, 0, 0, b'c'];
        let cont: &[u8] = &[1, b'd', 0, 0xE9, 0];
        let r = Record { kind: 0x00FC, parts: vec![sst, cont], at: 0 };
        assert_eq!(shared_strings(&r), ["ab".into(), "cdé".into()] as [Rc<str>; 2]);
    }
}
