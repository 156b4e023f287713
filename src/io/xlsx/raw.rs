//! Just enough XML to read what calamine does not expose: the sheet list with each sheet's
//! part, defined names with their `localSheetId`, and from each worksheet the areas of
//! array formulas (`<f t="array" ref="A1:A5">`), the style of each cell and column widths.
//!
//! The worksheet scan streams the part through a small tag scanner (no text is kept), so it
//! costs little beside calamine's own pass. It is forgiving: malformed markup ends the scan
//! quietly and calamine's pass reports the error.

use std::io::{Cursor, Read};

use zip::result::ZipError;
use zip::ZipArchive;

use crate::formula::address::{Pos, Rect, MAX_COLS, MAX_ROWS};

use super::{ArrayFormula, ErrorKind};

/// The zip package with its workbook-level parts read.
pub struct Package<'a> {
    zip: ZipArchive<Cursor<&'a [u8]>>,
    pub sheets: Vec<SheetEntry>,
    pub names: Vec<NameEntry>,
    /// `<workbookPr codeName="…">`: the workbook's VBA name.
    pub code_name: Option<String>,
}

#[derive(Clone, Debug)]
pub struct SheetEntry {
    pub name: String,
    /// Path of the part in the package, e.g. `xl/worksheets/sheet1.xml`.
    pub part: String,
    /// Last segment of the relationship type: `worksheet`, `chartsheet`, `dialogsheet`, …
    pub kind: String,
}

#[derive(Clone, Debug)]
pub struct NameEntry {
    pub name: String,
    pub formula: String,
    /// Index into the workbook's `<sheets>` list for a sheet-scoped name.
    pub local_sheet: Option<usize>,
}

/// What the worksheet scan found.
#[derive(Default, Debug)]
pub struct SheetScan {
    /// Array formulas, in file order.
    pub arrays: Vec<ArrayFormula>,
    /// Cells with a style other than the default, with their style index.
    pub styled: Vec<(Pos, u32)>,
    /// `<col>` widths: first and last column (0-based) and the width.
    pub widths: Vec<(u32, u32, f64)>,
    /// `<sheetPr codeName="…">`: the sheet's VBA name.
    pub code_name: Option<String>,
    /// Per column, one past the last row holding a cell.
    pub column_rows: Vec<u32>,
}

impl SheetScan {
    /// The grid slots the sheet needs: columns are stored densely down to their last cell.
    pub fn grid_slots(&self) -> u64 {
        self.column_rows.iter().map(|&r| r as u64).sum()
    }
}

type Err = (Option<String>, ErrorKind, String);

fn zip_error(part: Option<&str>, e: ZipError) -> Err {
    let kind = match e {
        ZipError::Io(_) => ErrorKind::Io,
        _ => ErrorKind::Damaged,
    };
    (part.map(str::to_string), kind, format!("damaged zip entry: {e}"))
}

impl<'a> Package<'a> {
    pub fn open(bytes: &'a [u8]) -> Result<Package<'a>, Err> {
        let zip = ZipArchive::new(Cursor::new(bytes))
            .map_err(|e| (None, ErrorKind::NotXlsx, format!("not a readable xlsx (zip) package: {e}")))?;
        let mut package = Package { zip, sheets: Vec::new(), names: Vec::new(), code_name: None };
        let workbook = package.main_part()?;
        let rels = package.relationships(&workbook)?;
        let text = package.read_part(&workbook)?;
        package.read_workbook(&workbook, &text, &rels)?;
        Ok(package)
    }

    /// Reads a whole (small) part as text; a missing part is an error.
    pub fn read_part(&mut self, part: &str) -> Result<String, Err> {
        let mut entry = match self.zip.by_name(part) {
            Ok(e) => e,
            Err(ZipError::FileNotFound) => {
                return Err((Some(part.to_string()), ErrorKind::Damaged, "missing from the package".into()))
            }
            Err(e) => return Err(zip_error(Some(part), e)),
        };
        let mut bytes = Vec::new();
        entry.read_to_end(&mut bytes).map_err(|e| zip_error(Some(part), ZipError::Io(e)))?;
        String::from_utf8(bytes).map_err(|_| (Some(part.to_string()), ErrorKind::Damaged, "not UTF-8 text".into()))
    }

    /// A part's raw bytes if the package has it.
    pub fn read_optional(&mut self, part: &str) -> Result<Option<Vec<u8>>, Err> {
        let mut entry = match self.zip.by_name(part) {
            Ok(e) => e,
            Err(ZipError::FileNotFound) => return Ok(None),
            Err(e) => return Err(zip_error(Some(part), e)),
        };
        let mut bytes = Vec::new();
        entry.read_to_end(&mut bytes).map_err(|e| zip_error(Some(part), ZipError::Io(e)))?;
        Ok(Some(bytes))
    }

    /// The workbook part named by the package relationships (`xl/workbook.xml` as a rule).
    fn main_part(&mut self) -> Result<String, Err> {
        let rels = match self.read_optional("_rels/.rels")? {
            Some(bytes) => bytes,
            None => return Ok("xl/workbook.xml".to_string()),
        };
        let mut main = None;
        for_each_tag(&rels, &mut |tag, _| {
            if tag.name == b"Relationship"
                && tag.attr("Type").is_some_and(|t| t.ends_with(b"/officeDocument"))
                && main.is_none()
            {
                main = tag.attr("Target").map(|t| resolve("", &unescape(t)));
            }
        });
        Ok(main.unwrap_or_else(|| "xl/workbook.xml".to_string()))
    }

    /// The relationships of a part: id → (target part, type's last segment).
    fn relationships(&mut self, part: &str) -> Result<Vec<(String, String, String)>, Err> {
        let (dir, file) = part.rsplit_once('/').unwrap_or(("", part));
        let rels_part = if dir.is_empty() { format!("_rels/{file}.rels") } else { format!("{dir}/_rels/{file}.rels") };
        let Some(bytes) = self.read_optional(&rels_part)? else { return Ok(Vec::new()) };
        let mut out = Vec::new();
        for_each_tag(&bytes, &mut |tag, _| {
            if tag.name == b"Relationship" {
                let id = tag.attr("Id").map(unescape).unwrap_or_default();
                let target = tag.attr("Target").map(|v| resolve(dir, &unescape(v))).unwrap_or_default();
                let kind = tag.attr("Type").map(unescape).unwrap_or_default();
                let kind = kind.rsplit('/').next().unwrap_or("").to_string();
                out.push((id, target, kind));
            }
        });
        Ok(out)
    }

    fn read_workbook(&mut self, part: &str, text: &str, rels: &[(String, String, String)]) -> Result<(), Err> {
        let bytes = text.as_bytes();
        let mut sheets = Vec::new();
        let mut names = Vec::new();
        let mut problem = None;
        let mut code_name = None;
        for_each_tag(bytes, &mut |tag, content| match tag.name {
            b"workbookPr" => code_name = tag.attr("codeName").map(unescape),
            b"sheet" => {
                let name = tag.attr("name").map(unescape).unwrap_or_default();
                let id = tag.attr("id").map(unescape).unwrap_or_default();
                match rels.iter().find(|(rid, ..)| *rid == id) {
                    Some((_, target, kind)) => {
                        sheets.push(SheetEntry { name, part: target.clone(), kind: kind.clone() })
                    }
                    None => problem = Some(format!("sheet '{name}' has no relationship '{id}'")),
                }
            }
            b"definedName" => {
                let name = tag.attr("name").map(unescape).unwrap_or_default();
                let local_sheet = tag.attr("localSheetId").and_then(|v| std::str::from_utf8(v).ok()?.parse().ok());
                names.push(NameEntry { name, formula: unescape(content), local_sheet });
            }
            _ => {}
        });
        if let Some(message) = problem {
            return Err((Some(part.to_string()), ErrorKind::Damaged, message));
        }
        self.sheets = sheets;
        self.names = names;
        self.code_name = code_name;
        Ok(())
    }

    /// Streams a worksheet part and collects array areas, cell styles and column widths.
    pub fn scan_sheet(&mut self, part: &str) -> Result<SheetScan, Err> {
        let entry = match self.zip.by_name(part) {
            Ok(e) => e,
            Err(ZipError::FileNotFound) => {
                return Err((Some(part.to_string()), ErrorKind::Damaged, "missing from the package".into()))
            }
            Err(e) => return Err(zip_error(Some(part), e)),
        };
        let mut scanner = SheetScanner::default();
        stream_tags(entry, &mut |tag| scanner.tag(tag)).map_err(|e| zip_error(Some(part), ZipError::Io(e)))?;
        Ok(scanner.scan)
    }
}

/// Resolves a relationship target against the folder of its source part.
fn resolve(dir: &str, target: &str) -> String {
    if let Some(abs) = target.strip_prefix('/') {
        return abs.to_string();
    }
    let mut parts: Vec<&str> = dir.split('/').filter(|s| !s.is_empty()).collect();
    for seg in target.split('/') {
        match seg {
            ".." => {
                parts.pop();
            }
            "." | "" => {}
            s => parts.push(s),
        }
    }
    parts.join("/")
}

/// Follows rows and cells through a worksheet, as calamine does (a `<c>` without `r` is
/// the next column; a `<row>` without `r` is the next row).
#[derive(Default)]
struct SheetScanner {
    scan: SheetScan,
    row: u32,
    col: u32,
    cell: Option<Pos>,
    /// The current cell has `cm="…"`: cell metadata, which marks dynamic arrays.
    cell_metadata: bool,
}

impl SheetScanner {
    fn tag(&mut self, tag: &Tag) {
        match (tag.kind, tag.name) {
            (TagKind::Start | TagKind::Empty, b"row") => {
                if let Some(r) = tag.attr("r").and_then(parse_u32) {
                    self.row = r.saturating_sub(1);
                }
                self.col = 0;
                if tag.kind == TagKind::Empty {
                    self.row += 1;
                }
            }
            (TagKind::End, b"row") => {
                self.row += 1;
                self.col = 0;
            }
            (TagKind::Start | TagKind::Empty, b"c") => {
                let pos = match tag.attr("r") {
                    Some(r) => parse_pos(r),
                    None => Some(Pos::new(self.row, self.col)),
                };
                self.cell = pos;
                self.cell_metadata = tag.attr("cm").is_some();
                if let Some(p) = pos {
                    self.col = p.col + 1;
                    let rows = &mut self.scan.column_rows;
                    if rows.len() <= p.col as usize {
                        rows.resize(p.col as usize + 1, 0);
                    }
                    rows[p.col as usize] = rows[p.col as usize].max(p.row + 1);
                    if let Some(s) = tag.attr("s").and_then(parse_u32) {
                        if s != 0 {
                            self.scan.styled.push((p, s));
                        }
                    }
                }
                if tag.kind == TagKind::Empty {
                    self.cell = None;
                }
            }
            (TagKind::End, b"c") => self.cell = None,
            (TagKind::Start | TagKind::Empty, b"f") => {
                if let (Some(anchor), Some(b"array")) = (self.cell, tag.attr("t")) {
                    let area = tag.attr("ref").and_then(parse_rect).unwrap_or(Rect::cell(anchor));
                    self.scan.arrays.push(ArrayFormula { anchor, area, dynamic: self.cell_metadata });
                }
            }
            (TagKind::Start | TagKind::Empty, b"sheetPr") => self.scan.code_name = tag.attr("codeName").map(unescape),
            (TagKind::Start | TagKind::Empty, b"col") => {
                let min = tag.attr("min").and_then(parse_u32);
                let max = tag.attr("max").and_then(parse_u32);
                let width = tag.attr("width").and_then(|w| std::str::from_utf8(w).ok()?.parse::<f64>().ok());
                if let (Some(min), Some(max), Some(width)) = (min, max, width) {
                    if min >= 1 && min <= max && max <= MAX_COLS && width.is_finite() && width >= 0.0 {
                        self.scan.widths.push((min - 1, max - 1, width));
                    }
                }
            }
            _ => {}
        }
    }
}

fn parse_u32(v: &[u8]) -> Option<u32> {
    std::str::from_utf8(v).ok()?.trim().parse().ok()
}

/// `AB12` (no `$`) to a position on the sheet.
pub fn parse_pos(v: &[u8]) -> Option<Pos> {
    let letters = v.iter().take_while(|b| b.is_ascii_alphabetic()).count();
    if letters == 0 || letters > 3 || letters == v.len() {
        return None;
    }
    let mut col: u32 = 0;
    for &b in &v[..letters] {
        col = col * 26 + (b.to_ascii_uppercase() - b'A' + 1) as u32;
    }
    let row = parse_u32(&v[letters..])?;
    ((1..=MAX_ROWS).contains(&row) && (1..=MAX_COLS).contains(&col)).then(|| Pos::new(row - 1, col - 1))
}

fn parse_rect(v: &[u8]) -> Option<Rect> {
    match v.iter().position(|&b| b == b':') {
        Some(i) => Some(Rect::new(parse_pos(&v[..i])?, parse_pos(&v[i + 1..])?)),
        None => parse_pos(v).map(Rect::cell),
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TagKind {
    Start,
    End,
    /// `<x/>`
    Empty,
}

/// One tag: its local name (namespace prefix removed) and raw attribute text.
pub struct Tag<'a> {
    pub kind: TagKind,
    pub name: &'a [u8],
    attrs: &'a [u8],
}

impl<'a> Tag<'a> {
    /// The raw (still escaped) value of an attribute, matched by local name.
    pub fn attr(&self, key: &str) -> Option<&'a [u8]> {
        let key = key.as_bytes();
        let b = self.attrs;
        let mut i = 0;
        while i < b.len() {
            while i < b.len() && b[i].is_ascii_whitespace() {
                i += 1;
            }
            let name_start = i;
            while i < b.len() && b[i] != b'=' && !b[i].is_ascii_whitespace() {
                i += 1;
            }
            let name = &b[name_start..i];
            while i < b.len() && (b[i].is_ascii_whitespace() || b[i] == b'=') {
                i += 1;
            }
            let quote = *b.get(i)?;
            if quote != b'"' && quote != b'\'' {
                return None;
            }
            let value_start = i + 1;
            let value_end = value_start + b[value_start..].iter().position(|&c| c == quote)?;
            i = value_end + 1;
            if local_name(name) == key {
                return Some(&b[value_start..value_end]);
            }
        }
        None
    }
}

fn local_name(name: &[u8]) -> &[u8] {
    match name.iter().rposition(|&b| b == b':') {
        Some(i) => &name[i + 1..],
        None => name,
    }
}

/// Where the markup starting at `buf[lt] == b'<'` ends (index of its `>`), `None` when the
/// buffer ends first. Comments, CDATA and processing instructions end at their own closers.
fn markup_end(buf: &[u8], lt: usize) -> Option<usize> {
    let rest = &buf[lt..];
    let closer: &[u8] = if rest.starts_with(b"<!--") {
        b"-->"
    } else if rest.starts_with(b"<![CDATA[") {
        b"]]>"
    } else if rest.starts_with(b"<?") {
        b"?>"
    } else {
        let mut quote = 0u8;
        for (i, &c) in rest.iter().enumerate().skip(1) {
            match c {
                b'"' | b'\'' if quote == 0 => quote = c,
                c if c == quote => quote = 0,
                b'>' if quote == 0 => return Some(lt + i),
                _ => {}
            }
        }
        return None;
    };
    memchr::memmem::find(rest, closer).map(|i| lt + i + closer.len() - 1)
}

/// The tag in `buf[lt..=gt]`, or `None` for comments, declarations and the like.
fn parse_tag(markup: &[u8]) -> Option<Tag<'_>> {
    let inner = &markup[1..markup.len() - 1];
    let (kind, inner) = match inner.first()? {
        b'/' => (TagKind::End, &inner[1..]),
        b'!' | b'?' => return None,
        _ => match inner.strip_suffix(b"/") {
            Some(body) => (TagKind::Empty, body),
            None => (TagKind::Start, inner),
        },
    };
    let name_end = inner.iter().position(|c| c.is_ascii_whitespace()).unwrap_or(inner.len());
    Some(Tag { kind, name: local_name(&inner[..name_end]), attrs: &inner[name_end..] })
}

/// Calls `f` for each start or empty tag of a complete document, with the text that follows
/// it up to the next markup (the content of an element that holds only text).
pub fn for_each_tag(buf: &[u8], f: &mut dyn FnMut(&Tag, &[u8])) {
    let mut pos = 0;
    while let Some(lt) = memchr::memchr(b'<', &buf[pos..]).map(|i| pos + i) {
        let Some(gt) = markup_end(buf, lt) else { return };
        pos = gt + 1;
        if let Some(tag) = parse_tag(&buf[lt..=gt]) {
            if tag.kind != TagKind::End {
                let text_end = memchr::memchr(b'<', &buf[pos..]).map_or(buf.len(), |i| pos + i);
                f(&tag, &buf[pos..text_end]);
            }
        }
    }
}

/// Calls `f` for every tag of a document read from `reader`, holding only a small window.
fn stream_tags(mut reader: impl Read, f: &mut dyn FnMut(&Tag)) -> std::io::Result<()> {
    const CHUNK: usize = 1 << 16;
    let mut buf: Vec<u8> = Vec::with_capacity(2 * CHUNK);
    let mut pos = 0;
    let mut eof = false;
    loop {
        match memchr::memchr(b'<', &buf[pos..]).map(|i| pos + i) {
            Some(lt) => match markup_end(&buf, lt) {
                Some(gt) => {
                    if let Some(tag) = parse_tag(&buf[lt..=gt]) {
                        f(&tag);
                    }
                    pos = gt + 1;
                    continue;
                }
                None if eof => return Ok(()),
                None => pos = lt,
            },
            None if eof => return Ok(()),
            None => pos = buf.len(),
        }
        // Keep the unfinished markup, read more.
        buf.drain(..pos);
        pos = 0;
        let old = buf.len();
        buf.resize(old + CHUNK, 0);
        let n = read_some(&mut reader, &mut buf[old..])?;
        buf.truncate(old + n);
        eof = n == 0;
        if buf.len() > 64 * CHUNK {
            // One tag longer than 4 MiB is not a worksheet we understand.
            return Ok(());
        }
    }
}

fn read_some(reader: &mut impl Read, out: &mut [u8]) -> std::io::Result<usize> {
    loop {
        match reader.read(out) {
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            r => return r,
        }
    }
}

/// XML text with its entities replaced.
pub fn unescape(raw: &[u8]) -> String {
    let text = String::from_utf8_lossy(raw);
    if !text.contains('&') {
        return text.into_owned();
    }
    let mut out = String::with_capacity(text.len());
    let mut rest: &str = &text;
    while let Some(amp) = rest.find('&') {
        out.push_str(&rest[..amp]);
        rest = &rest[amp..];
        let Some(semi) = rest.find(';') else { break };
        let entity = &rest[1..semi];
        let ch = match entity {
            "amp" => Some('&'),
            "lt" => Some('<'),
            "gt" => Some('>'),
            "quot" => Some('"'),
            "apos" => Some('\''),
            _ => {
                let code = if let Some(hex) = entity.strip_prefix("#x").or_else(|| entity.strip_prefix("#X")) {
                    u32::from_str_radix(hex, 16).ok()
                } else {
                    entity.strip_prefix('#').and_then(|d| d.parse().ok())
                };
                code.and_then(char::from_u32)
            }
        };
        match ch {
            Some(c) => {
                out.push(c);
                rest = &rest[semi + 1..];
            }
            None => {
                out.push('&');
                rest = &rest[1..];
            }
        }
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tags_attributes_and_entities() {
        let xml = br#"<?xml version="1.0"?><!-- a > b --><x:sheet name="A &amp; B" r:id='rId1'/><definedName name="n" localSheetId="2">Sheet1!$A$1&lt;&#65;</definedName>"#;
        let mut seen = Vec::new();
        for_each_tag(xml, &mut |tag, text| {
            seen.push((
                String::from_utf8_lossy(tag.name).into_owned(),
                tag.attr("name").map(unescape),
                tag.attr("id").map(unescape),
                unescape(text),
            ));
        });
        assert_eq!(
            seen,
            vec![
                ("sheet".into(), Some("A & B".into()), Some("rId1".into()), "".into()),
                ("definedName".into(), Some("n".into()), None, "Sheet1!$A$1<A".into()),
            ]
        );
    }

    #[test]
    fn sheet_scan_finds_arrays_styles_and_widths_across_chunk_edges() {
        let mut xml =
            String::from(r#"<worksheet><cols><col min="2" max="3" width="12.5" customWidth="1"/></cols><sheetData>"#);
        for r in 1..=5000 {
            xml.push_str(&format!(
                r#"<row r="{r}"><c r="A{r}" s="3"><v>{r}</v></c><c><f>A{r}*2</f><v>0</v></c></row>"#
            ));
        }
        xml.push_str(r#"<row><c r="C5001" cm="1"><f t="array" ref="C5001:C5003">SEQUENCE(3)</f><v>1</v></c></row>"#);
        xml.push_str("</sheetData></worksheet>");
        let mut scanner = SheetScanner::default();
        stream_tags(xml.as_bytes(), &mut |tag| scanner.tag(tag)).unwrap();
        let scan = scanner.scan;
        assert_eq!(scan.widths, vec![(1, 2, 12.5)]);
        assert_eq!(scan.styled.len(), 5000);
        assert_eq!(scan.styled[4999], (Pos::new(4999, 0), 3));
        let area = Rect::new(Pos::new(5000, 2), Pos::new(5002, 2));
        assert_eq!(scan.arrays, vec![ArrayFormula { anchor: Pos::new(5000, 2), area, dynamic: true }]);
    }

    #[test]
    fn relationship_targets_resolve_against_their_folder() {
        assert_eq!(resolve("xl", "worksheets/sheet1.xml"), "xl/worksheets/sheet1.xml");
        assert_eq!(resolve("xl", "/xl/worksheets/sheet1.xml"), "xl/worksheets/sheet1.xml");
        assert_eq!(resolve("xl/worksheets", "../drawings/d.xml"), "xl/drawings/d.xml");
        assert_eq!(parse_pos(b"XFD1048576"), Some(Pos::new(MAX_ROWS - 1, MAX_COLS - 1)));
        assert_eq!(parse_pos(b"XFE1"), None);
        assert_eq!(parse_pos(b"A0"), None);
    }
}
