//! Excel tables (`xl/tables/tableN.xml`, named from a worksheet's relationships) and the
//! structured references that name their parts: `Table1[Qty]`, `Table1[[#Headers],[Qty]]`,
//! `Table1[[#This Row],[A]:[B]]`, `[@Price]` (in a cell of the table, the table is implied),
//! `Table1[]`, `#All`, `#Data`, `#Headers`, `#Totals`.
//!
//! On import a structured reference becomes the absolute range it names on the table's sheet
//! (`#This Row` the formula's row), so the graph, recalculation and cycle detection see an
//! ordinary reference.

use std::borrow::Cow;

use crate::formula::address::{column_name, parse_rect, Pos, Rect};
use crate::formula::ast::SheetId;

use super::sheet_span::skip_delimited;
use super::xml::{for_each_tag, unescape, TagKind};

/// A table: a named rectangle of a sheet with named columns — the workbook's own type, which
/// the macros' ListObjects read too.
pub use crate::workbook::TableShape as Table;

/// Reads a table part; `None` when it names no valid range.
pub fn parse_table(xml: &[u8], sheet: SheetId) -> Option<Table> {
    let mut table = None;
    let mut columns = Vec::new();
    let mut style = None;
    for_each_tag(xml, &mut |tag, _| match tag.name {
        b"table" => {
            let number = |key: &str, default: u32| tag.parsed(key).unwrap_or(default);
            let name = tag.attr("displayName").or_else(|| tag.attr("name")).map(unescape).unwrap_or_default();
            let rect = tag.attr("ref").and_then(|r| parse_rect(&unescape(r)));
            if let Some(rect) = rect {
                let (header_rows, totals_rows) = (number("headerRowCount", 1), number("totalsRowCount", 0));
                table = Some(Table {
                    name,
                    sheet,
                    rect,
                    header_rows,
                    totals_rows,
                    columns: Vec::new(),
                    style: None,
                    id: 0,
                });
            }
        }
        b"tableColumn" => columns.push(tag.attr("name").map(unescape).unwrap_or_default()),
        b"tableStyleInfo" => style = tag.attr("name").map(unescape),
        _ => {}
    });
    let mut table = table?;
    table.columns = columns;
    table.style = style;
    (!table.name.is_empty()).then_some(table)
}

/// The range of a table part's `<autoFilter>` when it filters on a column: the rows it hides are filtered rows, which every SUBTOTAL skips.
pub fn active_filter(xml: &[u8]) -> Option<Rect> {
    let (mut area, mut filtering) = (None, false);
    for_each_tag(xml, &mut |tag, _| match tag.name {
        b"autoFilter" if tag.kind != TagKind::End => area = tag.attr("ref").and_then(|r| parse_rect(&unescape(r))),
        b"filterColumn" => filtering = true,
        _ => {}
    });
    area.filter(|_| filtering)
}

/// The formula text with every structured reference replaced by the range it names (or
/// `#REF!` when it names nothing), for a formula in `pos` of `sheet`. `sheet_name` names
/// the sheets.
pub fn resolve_structured<'t>(
    text: &'t str,
    tables: &[Table],
    sheet: SheetId,
    pos: Pos,
    sheet_name: &dyn Fn(SheetId) -> String,
) -> Cow<'t, str> {
    let names_a_table = || {
        let upper = text.to_ascii_uppercase();
        tables.iter().any(|t| upper.contains(&t.name.to_ascii_uppercase()))
    };
    if tables.is_empty() || !text.contains('[') && !names_a_table() {
        return Cow::Borrowed(text);
    }
    let bytes = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut copied = 0;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'"' | b'\'' => i = skip_delimited(bytes, i),
            b'[' => {
                let name_start = table_name_start(bytes, i);
                let name = &text[name_start..i];
                let Some(end) = closing_bracket(bytes, i) else { break };
                let inner = &text[i + 1..end];
                let table = if name.is_empty() {
                    tables.iter().find(|t| t.sheet == sheet && t.rect.contains(pos))
                } else {
                    tables.iter().find(|t| t.name.eq_ignore_ascii_case(name))
                };
                // `[1]Sheet!A1` (another workbook) and brackets that name no table stay.
                let resolved = table.and_then(|t| {
                    let specifier = Specifier::parse(inner, t)?;
                    Some(specifier.render(t, pos, sheet_name))
                });
                if let Some(resolved) = resolved {
                    out.push_str(&text[copied..name_start]);
                    out.push_str(&resolved);
                    copied = end + 1;
                }
                i = end + 1;
            }
            c if is_name_char(c) => {
                let end = name_end(bytes, i);
                // A table's name alone (`ROWS(Parts)`, `VLOOKUP(x,Parts,2)`) is its data.
                let alone = !matches!(bytes.get(end), Some(b'[' | b'(' | b'!'))
                    && (i == 0 || !matches!(bytes[i - 1], b'!' | b'.' | b'\\'));
                let table = alone.then(|| tables.iter().find(|t| t.name.eq_ignore_ascii_case(&text[i..end]))).flatten();
                if let Some(table) = table {
                    let data = Specifier { rows: Rows { data: true, ..Rows::default() }, columns: None };
                    out.push_str(&text[copied..i]);
                    out.push_str(&data.render(table, pos, sheet_name));
                    copied = end;
                }
                i = end;
            }
            _ => i += 1,
        }
    }
    if copied == 0 {
        return Cow::Borrowed(text);
    }
    out.push_str(&text[copied..]);
    Cow::Owned(out)
}

/// The reader of structured references installed in a workbook read from xlsx, so that
/// INDIRECT reads the structured references of its text (`INDIRECT("Table1[Qty]")`) as a
/// formula read at load does, over the workbook's tables as they are then (a macro may have
/// added rows to one).
pub struct FileTables;

impl crate::workbook::StructuredReferences for FileTables {
    fn resolve(&self, wb: &crate::workbook::Workbook, text: &str, sheet: SheetId, pos: Pos) -> Option<String> {
        let name = |s: SheetId| crate::eval::Env::sheet_name(wb, s).unwrap_or_default();
        match resolve_structured(text, wb.table_list(), sheet, pos, &name) {
            Cow::Owned(resolved) => Some(resolved),
            Cow::Borrowed(_) => None,
        }
    }
}

/// A character of a name (a table's, a function's, a cell's).
fn is_name_char(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_' || c == b'.' || c == b'\\' || c >= 0x80
}

/// Where the name (or number, or cell address) starting at `at` ends.
fn name_end(bytes: &[u8], at: usize) -> usize {
    at + bytes[at..].iter().take_while(|&&c| is_name_char(c)).count()
}

/// Where the table name before the `[` at `at` starts (`at` itself when there is none).
fn table_name_start(bytes: &[u8], at: usize) -> usize {
    let mut start = at;
    while start > 0 && is_name_char(bytes[start - 1]) {
        start -= 1;
    }
    // A name starts with a letter, `_` or `\`; digits before `[` belong to something else.
    while start < at && (bytes[start].is_ascii_digit() || bytes[start] == b'.') {
        start += 1;
    }
    start
}

/// The `]` closing the `[` at `open`; `'` escapes the character after it.
fn closing_bracket(bytes: &[u8], open: usize) -> Option<usize> {
    let mut depth = 0;
    let mut i = open;
    while i < bytes.len() {
        match bytes[i] {
            b'\'' => i += 1,
            b'[' => depth += 1,
            b']' => {
                depth -= 1;
                if depth == 0 {
                    return Some(i);
                }
            }
            _ => {}
        }
        i += 1;
    }
    None
}

/// Which rows of a table a reference takes.
#[derive(Clone, Copy, Debug, Default)]
struct Rows {
    headers: bool,
    data: bool,
    totals: bool,
    this_row: bool,
}

/// The rows and columns a structured reference names.
struct Specifier {
    rows: Rows,
    /// First and last column index in the table; `None` for all.
    columns: Option<(usize, usize)>,
}

impl Specifier {
    fn parse(inner: &str, table: &Table) -> Option<Specifier> {
        let inner = inner.trim();
        let mut rows = Rows::default();
        let mut columns: Option<(usize, usize)> = None;
        if let Some(rest) = inner.strip_prefix('@') {
            rows.this_row = true;
            let rest = rest.trim();
            if !rest.is_empty() {
                let name = rest.strip_prefix('[').and_then(|r| r.strip_suffix(']')).unwrap_or(rest);
                let c = column_index(table, name)?;
                columns = Some((c, c));
            }
            return Some(Specifier { rows, columns });
        }
        if !inner.starts_with('[') {
            if inner.is_empty() {
                rows.data = true;
            } else if !special(inner, &mut rows) {
                let c = column_index(table, inner)?;
                columns = Some((c, c));
                rows.data = true;
            }
            return Some(Specifier { rows, columns });
        }
        // `[item],[item]` and `[col]:[col]`.
        let bytes = inner.as_bytes();
        let mut i = 0;
        let mut pending_range = false;
        while i < bytes.len() {
            match bytes[i] {
                b'[' => {
                    let end = closing_bracket(bytes, i)?;
                    let item = &inner[i + 1..end];
                    if !special(item, &mut rows) {
                        let c = column_index(table, item)?;
                        columns = match (columns, pending_range) {
                            (Some((a, _)), true) => Some((a.min(c), a.max(c))),
                            (None, _) | (_, false) => Some((c, c)),
                        };
                    }
                    pending_range = false;
                    i = end + 1;
                }
                b':' => {
                    pending_range = true;
                    i += 1;
                }
                b',' | b' ' => i += 1,
                _ => return None,
            }
        }
        if !(rows.headers || rows.data || rows.totals || rows.this_row) {
            rows.data = true;
        }
        Some(Specifier { rows, columns })
    }

    fn render(&self, table: &Table, pos: Pos, sheet_name: &dyn Fn(SheetId) -> String) -> String {
        let Some(rect) = self.rect(table, pos) else { return "#REF!".to_string() };
        let name = sheet_name(table.sheet).replace('\'', "''");
        let cell = |p: Pos| format!("${}${}", column_name(p.col), p.row + 1);
        if rect.is_cell() {
            format!("'{name}'!{}", cell(rect.first))
        } else {
            format!("'{name}'!{}:{}", cell(rect.first), cell(rect.last))
        }
    }

    fn rect(&self, t: &Table, pos: Pos) -> Option<Rect> {
        let top = t.rect.first.row;
        let bottom = t.rect.last.row;
        let data_top = top + t.header_rows;
        let data_bottom = bottom.checked_sub(t.totals_rows)?;
        let (first_row, last_row) = if self.rows.this_row {
            if pos.row < data_top || pos.row > data_bottom {
                return None;
            }
            (pos.row, pos.row)
        } else {
            let mut span: Option<(u32, u32)> = None;
            let mut take = |a: u32, b: u32| {
                if a <= b {
                    span = Some(span.map_or((a, b), |(x, y)| (x.min(a), y.max(b))));
                }
            };
            if self.rows.headers && t.header_rows > 0 {
                take(top, data_top - 1);
            }
            if self.rows.data {
                take(data_top, data_bottom);
            }
            if self.rows.totals && t.totals_rows > 0 {
                take(data_bottom + 1, bottom);
            }
            span?
        };
        let (first_col, last_col) = match self.columns {
            Some((a, b)) => (t.rect.first.col + a as u32, t.rect.first.col + b as u32),
            None => (t.rect.first.col, t.rect.last.col),
        };
        Some(Rect::new(Pos::new(first_row, first_col), Pos::new(last_row, last_col)))
    }
}

/// Reads `#All`, `#Data`, `#Headers`, `#Totals`, `#This Row` into `rows`; false for a column.
fn special(item: &str, rows: &mut Rows) -> bool {
    let item = item.trim();
    if !item.starts_with('#') {
        return false;
    }
    match item.to_ascii_lowercase().as_str() {
        "#all" => {
            rows.headers = true;
            rows.data = true;
            rows.totals = true;
        }
        "#data" => rows.data = true,
        "#headers" => rows.headers = true,
        "#totals" => rows.totals = true,
        "#this row" => rows.this_row = true,
        _ => return false,
    }
    true
}

/// The column named `escaped` (`'` escapes `[`, `]`, `#` and `'` in a column name).
fn column_index(table: &Table, escaped: &str) -> Option<usize> {
    let mut name = String::with_capacity(escaped.len());
    let mut chars = escaped.chars();
    while let Some(c) = chars.next() {
        if c == '\'' {
            name.extend(chars.next());
        } else {
            name.push(c);
        }
    }
    let exact = table.columns.iter().position(|c| c.eq_ignore_ascii_case(&name));
    exact.or_else(|| table.columns.iter().position(|c| c.trim().eq_ignore_ascii_case(name.trim())))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> Table {
        Table {
            name: "Sales".into(),
            sheet: 0,
            rect: parse_rect("B2:D6").expect("rect"),
            header_rows: 1,
            totals_rows: 1,
            columns: vec!["Item".into(), "Qty".into(), "Unit Price".into()],
            style: None,
            id: 0,
        }
    }

    fn resolve(text: &str, pos: &str) -> String {
        let pos = crate::formula::address::parse_cell(pos).expect("cell");
        resolve_structured(text, &[table()], 0, pos, &|_| "Data".to_string()).into_owned()
    }

    #[test]
    fn structured_references_name_the_parts_of_a_table() {
        // B2:D6 is the header row 2, data rows 3–5 and totals row 6.
        assert_eq!(resolve("SUM(Sales[Qty])", "A1"), "SUM('Data'!$C$3:$C$5)");
        assert_eq!(resolve("Sales[[#Headers],[Qty]]", "A1"), "'Data'!$C$2");
        assert_eq!(resolve("Sales[[#Totals],[Qty]]", "A1"), "'Data'!$C$6");
        assert_eq!(resolve("COUNTA(Sales[#All])", "A1"), "COUNTA('Data'!$B$2:$D$6)");
        assert_eq!(resolve("Sales[[#Headers],[#Data],[Item]:[Qty]]", "A1"), "'Data'!$B$2:$C$5");
        assert_eq!(resolve("Sales[]", "A1"), "'Data'!$B$3:$D$5");
        assert_eq!(resolve("[@Qty]*[@[Unit Price]]", "D4"), "'Data'!$C$4*'Data'!$D$4");
        assert_eq!(resolve("Sales[[#This Row],[Qty]]", "F5"), "'Data'!$C$5");
        assert_eq!(resolve("Sales[@Qty]", "F9"), "#REF!");
        assert_eq!(
            resolve("ROWS(Sales)+VLOOKUP(1,sales,2)", "A1"),
            "ROWS('Data'!$B$3:$D$5)+VLOOKUP(1,'Data'!$B$3:$D$5,2)"
        );
        assert_eq!(resolve("Sales!A1+SalesTax+\"Sales\"", "A1"), "Sales!A1+SalesTax+\"Sales\"");
    }

    #[test]
    fn text_other_workbooks_and_unknown_names_are_left_alone() {
        assert_eq!(resolve("\"Sales[Qty]\"&[1]Sheet1!A1", "A1"), "\"Sales[Qty]\"&[1]Sheet1!A1");
        assert_eq!(resolve("Other[Qty]", "A1"), "Other[Qty]");
        assert_eq!(resolve("Sales[Nope]", "A1"), "Sales[Nope]");
    }
}
