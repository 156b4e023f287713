//! Links to other workbooks (`xl/externalLinks/externalLinkN.xml`). Excel keeps, for each
//! linked workbook, its sheet names, its defined names and the values of the cells the
//! formulas read, as they were when last refreshed; a formula names the link by its number:
//! `[1]Data!$B$4`, `'[2]Thread data'!A1:C9`, `[1]!Thread_Data` (a name of that workbook),
//! `[1]Data!Local_Name` (a sheet's name); `[0]` is the workbook itself. ncsheet does not open other files: the importer
//! writes each such reference as the values Excel cached (a constant, or an array constant
//! for a range), so formulas and names compute what Excel showed.

use std::borrow::Cow;
use std::collections::HashMap;

use crate::eval::Value;
use crate::formula::address::{parse_cell, Pos, Rect};
use crate::formula::print::number_literal;

use super::sheet_span::{self, is_name_byte, skip_delimited};
use super::xml::{for_each_tag, unescape};

/// A linked range larger than this stays as written (and shows `#NAME?`): an array constant
/// of a whole column would be a million items.
const MAX_CELLS: u64 = 1 << 16;

/// What one external-link part holds about its workbook.
#[derive(Debug, Default)]
pub struct ExternalBook {
    sheets: Vec<String>,
    /// Name, what it refers to (`='Data'!$B$2`), the sheet it belongs to (index).
    names: Vec<(String, String, Option<usize>)>,
    /// Cached values per sheet (by index).
    cells: Vec<HashMap<Pos, Value>>,
}

/// Reads an external-link part; `None` when it links no workbook (DDE, OLE links).
pub fn parse_link(xml: &[u8]) -> Option<ExternalBook> {
    let mut book = ExternalBook::default();
    let mut linked = false;
    let (mut sheet, mut cell, mut kind): (Option<usize>, Option<Pos>, Vec<u8>) = (None, None, Vec::new());
    for_each_tag(xml, &mut |tag, content| match tag.name {
        b"externalBook" => linked = true,
        b"sheetName" => book.sheets.push(tag.attr("val").map(unescape).unwrap_or_default()),
        b"definedName" => {
            let name = tag.attr("name").map(unescape).unwrap_or_default();
            let refers_to = tag.attr("refersTo").map(unescape).unwrap_or_default();
            let scope = tag.attr("sheetId").and_then(|v| std::str::from_utf8(v).ok()?.parse().ok());
            book.names.push((name, refers_to, scope));
        }
        b"sheetData" => sheet = tag.attr("sheetId").and_then(|v| std::str::from_utf8(v).ok()?.parse().ok()),
        b"cell" => {
            cell = tag.attr("r").and_then(|r| parse_cell(&unescape(r)));
            kind = tag.attr("t").unwrap_or(b"n").to_vec();
        }
        b"v" => {
            let (Some(s), Some(pos)) = (sheet, cell.take()) else { return };
            let text = unescape(content);
            let value = match kind.as_slice() {
                b"str" | b"s" | b"inlineStr" => Value::text(text.as_str()),
                b"b" => Value::Bool(text.trim() == "1"),
                b"e" => text.trim().parse().map(Value::Error).unwrap_or(Value::Blank),
                _ => text.trim().parse().map(Value::Number).unwrap_or(Value::Blank),
            };
            if book.cells.len() <= s {
                book.cells.resize_with(s + 1, HashMap::new);
            }
            book.cells[s].insert(pos, value);
        }
        _ => {}
    });
    linked.then_some(book)
}

/// The formula text with each reference into a linked workbook (`books[n-1]` for `[n]`)
/// written as the values Excel cached for it. A reference that cannot be resolved stays.
pub fn resolve_links<'t>(text: &'t str, books: &[Option<ExternalBook>]) -> Cow<'t, str> {
    if !text.contains('[') {
        return Cow::Borrowed(text);
    }
    let bytes = text.as_bytes();
    sheet_span::replace_tokens(text, |at| matches!(bytes[at], b'[' | b'\'').then(|| link_at(text, at, books))?)
}

/// `[n]Sheet!ref`, `'[n]Sheet'!ref`, `[n]!Name` or `[n]Sheet!Name` at `at`: where it ends
/// and the cached values as formula text.
fn link_at(text: &str, at: usize, books: &[Option<ExternalBook>]) -> Option<(usize, String)> {
    let bytes = text.as_bytes();
    // The book number and sheet name, and where the `!` is.
    let (index, sheet, bang) = if bytes[at] == b'\'' {
        let end = skip_delimited(bytes, at);
        let inner = text.get(at + 1..end.checked_sub(1)?)?.replace("''", "'");
        let (index, sheet) = book_prefix(&inner)?;
        (index, Some(sheet.to_string()), end)
    } else {
        let close = at + text[at..].find(']')?;
        let index: usize = text[at + 1..close].parse().ok()?;
        let sheet_len = bytes[close + 1..].iter().take_while(|&&b| is_name_byte(b)).count();
        let sheet = (sheet_len > 0).then(|| text[close + 1..close + 1 + sheet_len].to_string());
        (index, sheet, close + 1 + sheet_len)
    };
    if bytes.get(bang) != Some(&b'!') {
        return None;
    }
    if index == 0 {
        // `[0]` is the workbook itself: `[0]!Name` is `Name`.
        let sheet = sheet.map_or(String::new(), |s| format!("'{}'!", s.replace('\'', "''")));
        return Some((bang + 1, sheet));
    }
    let book = books.get(index.checked_sub(1)?)?.as_ref()?;
    let rest = &text[bang + 1..];
    let len = rest.bytes().take_while(|&b| is_name_byte(b) || matches!(b, b'$' | b':')).count();
    let target = &rest[..len];
    let sheet_index = match &sheet {
        Some(name) => Some(book.sheets.iter().position(|s| s.eq_ignore_ascii_case(name))?),
        None => None,
    };
    let literal = match (sheet_index, reference(target)) {
        (Some(s), Some(rect)) => book.values(s, rect)?,
        _ => book.name_values(target, sheet_index)?,
    };
    Some((bang + 1 + len, literal))
}

/// `[n]Sheet name` → (n, sheet name).
fn book_prefix(inner: &str) -> Option<(usize, &str)> {
    let rest = inner.strip_prefix('[')?;
    let close = rest.find(']')?;
    let sheet = &rest[close + 1..];
    (!sheet.is_empty()).then_some(())?;
    Some((rest[..close].parse().ok()?, sheet))
}

/// `$A$1` or `$A$1:$C$9` (not a name).
fn reference(text: &str) -> Option<Rect> {
    let (a, b) = text.split_once(':').unwrap_or((text, text));
    Some(Rect::new(parse_cell(a)?, parse_cell(b)?))
}

impl ExternalBook {
    /// The cached values of `rect` on sheet `sheet` as formula text.
    fn values(&self, sheet: usize, rect: Rect) -> Option<String> {
        if rect.rows() as u64 * rect.cols() as u64 > MAX_CELLS {
            return None;
        }
        let cells = self.cells.get(sheet);
        let item = |pos: Pos| cells.and_then(|c| c.get(&pos)).map_or_else(|| "0".to_string(), literal);
        if rect.is_cell() {
            let text = item(rect.first);
            return Some(if text.starts_with('-') { format!("({text})") } else { text });
        }
        let rows: Vec<String> = (rect.first.row..=rect.last.row)
            .map(|r| {
                let row: Vec<String> = (rect.first.col..=rect.last.col).map(|c| item(Pos::new(r, c))).collect();
                row.join(",")
            })
            .collect();
        Some(format!("{{{}}}", rows.join(";")))
    }

    /// The cached values a name of the linked workbook refers to: the sheet's own name
    /// first, then the workbook's.
    fn name_values(&self, name: &str, sheet: Option<usize>) -> Option<String> {
        let found = |scope: Option<usize>| {
            self.names.iter().find(|(n, _, s)| *s == scope && n.eq_ignore_ascii_case(name)).map(|(_, r, _)| r)
        };
        let refers_to = sheet.and_then(|s| found(Some(s))).or_else(|| found(None))?;
        let refers_to = refers_to.strip_prefix('=').unwrap_or(refers_to);
        let (sheet_name, target) = refers_to.rsplit_once('!')?;
        let sheet_name = match sheet_name.strip_prefix('\'').and_then(|s| s.strip_suffix('\'')) {
            Some(quoted) => quoted.replace("''", "'"),
            None => sheet_name.to_string(),
        };
        let s = self.sheets.iter().position(|n| n.eq_ignore_ascii_case(&sheet_name))?;
        self.values(s, reference(target)?)
    }
}

/// A cached value as a formula constant.
fn literal(v: &Value) -> String {
    match v {
        Value::Number(n) => number_literal(*n),
        Value::Text(t) => format!("\"{}\"", t.replace('"', "\"\"")),
        Value::Bool(b) => if *b { "TRUE" } else { "FALSE" }.to_string(),
        Value::Error(e) => e.to_string(),
        _ => "0".to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn book() -> ExternalBook {
        let xml = br#"<externalLink><externalBook r:id="rId1"><sheetNames><sheetName val="Data"/><sheetName val="Thread data"/></sheetNames>
            <definedNames><definedName name="Pitch" refersTo="='Thread data'!$B$2"/><definedName name="Local" refersTo="=Data!$A$1:$A$2" sheetId="0"/></definedNames>
            <sheetDataSet><sheetData sheetId="0"><row r="1"><cell r="A1"><v>1.5</v></cell><cell r="B1" t="str"><v>M6 "fine"</v></cell></row>
            <row r="2"><cell r="A2"><v>-2</v></cell><cell r="B2" t="e"><v>#N/A</v></cell></row></sheetData>
            <sheetData sheetId="1"><row r="2"><cell r="B2" t="b"><v>1</v></cell></row></sheetData></sheetDataSet></externalBook></externalLink>"#;
        parse_link(xml).expect("a linked workbook")
    }

    #[test]
    fn references_into_a_linked_workbook_become_its_cached_values() {
        let books = [Some(book())];
        let resolve = |text| resolve_links(text, &books).into_owned();
        assert_eq!(resolve("[1]Data!$A$1*2"), "1.5*2");
        assert_eq!(resolve("SUM([1]Data!A1:B2)"), "SUM({1.5,\"M6 \"\"fine\"\"\";-2,#N/A})");
        assert_eq!(resolve("'[1]Thread data'!B2"), "TRUE");
        assert_eq!(resolve("[1]Data!A2+[1]Data!C9"), "(-2)+0");
        assert_eq!(resolve("[1]!Pitch"), "TRUE");
        assert_eq!(resolve("[1]Data!Local"), "{1.5;-2}");
        // `[0]` is the workbook itself.
        assert_eq!(resolve("IF(A1=1,[0]!Total,[0]Data!B2)"), "IF(A1=1,Total,'Data'!B2)");
    }

    #[test]
    fn what_is_not_a_known_link_stays() {
        let books = [Some(book())];
        for text in ["[2]Data!A1", "\"[1]Data!A1\"", "Table1[Qty]", "[1]Nosuch!A1", "[1]!Missing", "[1]!F(1)"] {
            assert_eq!(resolve_links(text, &books), text);
        }
    }
}
