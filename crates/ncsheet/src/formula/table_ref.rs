//! Structured references, the names of an Excel table's parts: `Parts[Qty]`,
//! `Parts[[#Totals],[Qty]]`, `Parts[[#This Row],[A]:[B]]`, `[@Price]` (in a cell of a table,
//! the table is implied), `Parts[]`, `#All`, `#Data`, `#Headers`, `#Totals`.
//!
//! A formula keeps them as written, by the table's and the columns' names: what they name
//! is looked up in the workbook's tables when the formula is evaluated, so a reference
//! follows its table as it grows, shrinks or moves, and is written back as it was spelled.
//!
//! The grammar (`structured` in grammar/formula.pest) delimits the reference; the items
//! inside its brackets are read here. In a column's name `'` escapes `[`, `]`, `#` and `'`
//! (Excel's rule), and a name holding a space or a sign is written in its own brackets.

use std::rc::Rc;

/// Which rows of a table a structured reference takes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct TableRows {
    pub headers: bool,
    pub data: bool,
    pub totals: bool,
    /// The data row of the formula's own cell (`@`, `#This Row`).
    pub this_row: bool,
}

/// A structured reference.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct TableRef {
    /// The table's name; `None` for one written without it (`[@Qty]`), which names the
    /// table holding the formula's cell.
    pub table: Option<Rc<str>>,
    pub rows: TableRows,
    /// The first and last column, by name (escapes removed); `None` for every column.
    pub columns: Option<(Rc<str>, Rc<str>)>,
}

/// Reads the bracketed part of a structured reference, `[...]` with its outer brackets;
/// `None` when its items are not a structured reference's.
pub fn parse_table_ref(table: Option<&str>, brackets: &str) -> Option<TableRef> {
    let inner = brackets.strip_prefix('[')?.strip_suffix(']')?.trim();
    let table = table.map(Rc::from);
    let mut rows = TableRows::default();
    if let Some(rest) = inner.strip_prefix('@') {
        rows.this_row = true;
        let rest = rest.trim();
        let columns = if rest.is_empty() { None } else { Some(column_span(rest)?) };
        return Some(TableRef { table, rows, columns });
    }
    if !inner.starts_with('[') {
        // `Parts[]` is the data rows, as the table's name alone is.
        let columns = if inner.is_empty() {
            rows.data = true;
            None
        } else if special(inner, &mut rows)? {
            None
        } else {
            rows.data = true;
            let name: Rc<str> = unescape(inner).into();
            Some((name.clone(), name))
        };
        return Some(TableRef { table, rows, columns });
    }
    let mut columns: Option<(Rc<str>, Rc<str>)> = None;
    for item in items(inner)? {
        match item {
            Item::Special(text) => {
                special(text, &mut rows)?;
            }
            Item::Columns(first, last) => {
                if columns.is_some() {
                    return None;
                }
                columns = Some((unescape(first).into(), unescape(last).into()));
            }
        }
    }
    if rows == TableRows::default() {
        rows.data = true;
    }
    Some(TableRef { table, rows, columns })
}

/// One item of a bracketed list: a special item (`#Totals`) or a column or column span.
enum Item<'a> {
    Special(&'a str),
    Columns(&'a str, &'a str),
}

/// The items of `[a],[b]:[c]`, each without its brackets.
fn items(inner: &str) -> Option<Vec<Item<'_>>> {
    let bytes = inner.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let mut pending_span = false;
    while i < bytes.len() {
        match bytes[i] {
            b'[' => {
                let end = closing_bracket(bytes, i)?;
                let text = &inner[i + 1..end];
                if pending_span {
                    let Some(Item::Columns(first, _)) = out.pop() else { return None };
                    out.push(Item::Columns(first, text));
                } else if text.trim_start().starts_with('#') {
                    out.push(Item::Special(text));
                } else {
                    out.push(Item::Columns(text, text));
                }
                pending_span = false;
                i = end + 1;
            }
            b':' => {
                pending_span = true;
                i += 1;
            }
            b',' | b' ' => i += 1,
            _ => return None,
        }
    }
    (!pending_span).then_some(out)
}

/// `@Qty`'s column or `@[Unit Price]`'s, or `@[A]:[B]`'s span.
fn column_span(text: &str) -> Option<(Rc<str>, Rc<str>)> {
    if !text.starts_with('[') {
        let name: Rc<str> = unescape(text).into();
        return Some((name.clone(), name));
    }
    match items(text)?.as_slice() {
        [Item::Columns(first, last)] => Some((unescape(first).into(), unescape(last).into())),
        _ => None,
    }
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

/// Reads `#All`, `#Data`, `#Headers`, `#Totals`, `#This Row` into `rows`: `Some(true)`;
/// `Some(false)` for a column's name; `None` for a `#` item Excel does not know.
fn special(item: &str, rows: &mut TableRows) -> Option<bool> {
    let item = item.trim();
    if !item.starts_with('#') {
        return Some(false);
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
        _ => return None,
    }
    Some(true)
}

/// A column's name as written, its escapes removed (`'#` is `#`).
fn unescape(escaped: &str) -> String {
    let mut name = String::with_capacity(escaped.len());
    let mut chars = escaped.chars();
    while let Some(c) = chars.next() {
        if c == '\'' {
            name.extend(chars.next());
        } else {
            name.push(c);
        }
    }
    name
}

/// A column's name as a structured reference writes it: `'` before `[`, `]`, `#` and `'`.
fn escape(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    for c in name.chars() {
        if matches!(c, '[' | ']' | '#' | '\'') {
            out.push('\'');
        }
        out.push(c);
    }
    out
}

/// Whether a column's name must stand in its own brackets (`Parts[[Total $]]`): it holds one
/// of the characters Excel lists (a space, a sign, a bracket …). A space alone needs none in
/// a plain column (`Parts[Unit Price]`), but does after `@` (`[@[Unit Price]]`), and at a
/// name's ends (`Table3[[the two ]]`, as Excel writes it), where a plain reference's are trimmed.
fn needs_brackets(name: &str, after_at: bool) -> bool {
    name.starts_with(char::is_whitespace)
        || name.ends_with(char::is_whitespace)
        || name.chars().any(|c| {
            (c == ' ' && after_at)
                || (c != ' ' && c.is_whitespace())
                || matches!(
                    c,
                    ',' | ':'
                        | '.'
                        | '['
                        | ']'
                        | '#'
                        | '\''
                        | '"'
                        | '{'
                        | '}'
                        | '$'
                        | '^'
                        | '&'
                        | '*'
                        | '+'
                        | '='
                        | '-'
                        | '>'
                        | '<'
                        | '/'
                        | '@'
                )
        })
}

impl TableRef {
    /// Writes the reference: `this_row_as_at` chooses `[@Qty]` (as typed) over
    /// `[[#This Row],[Qty]]` (as Excel's files store it).
    pub fn write(&self, out: &mut String, this_row_as_at: bool) {
        if let Some(table) = &self.table {
            out.push_str(table);
        }
        let columns = self.columns.as_ref().map(|(first, last)| {
            let one = |name: &str| format!("[{}]", escape(name));
            if first == last {
                one(first)
            } else {
                format!("{}:{}", one(first), one(last))
            }
        });
        let rows = self.rows;
        if rows.this_row && this_row_as_at {
            out.push_str("[@");
            match (&self.columns, &columns) {
                (Some((first, last)), _) if first == last && !needs_brackets(first, true) => {
                    out.push_str(&escape(first))
                }
                (_, Some(columns)) => out.push_str(columns),
                _ => {}
            }
            out.push(']');
            return;
        }
        let mut parts: Vec<String> = Vec::new();
        if rows.headers && rows.data && rows.totals {
            parts.push("[#All]".into());
        } else {
            let named = [
                (rows.headers, "[#Headers]"),
                (rows.data && rows != TableRows { data: true, ..TableRows::default() }, "[#Data]"),
                (rows.totals, "[#Totals]"),
                (rows.this_row, "[#This Row]"),
            ];
            parts.extend(named.iter().filter(|(on, _)| *on).map(|(_, text)| text.to_string()));
        }
        out.push('[');
        match (parts.is_empty(), &self.columns, columns) {
            (true, None, _) => {}
            (true, Some((first, last)), _) if first == last && !needs_brackets(first, false) => {
                out.push_str(&escape(first))
            }
            (true, _, columns) => out.push_str(&columns.unwrap_or_default()),
            (false, _, columns) => {
                if parts.len() == 1 && columns.is_none() {
                    out.push_str(&parts[0][1..parts[0].len() - 1]);
                } else {
                    out.push_str(&parts.join(","));
                    if let Some(columns) = columns {
                        out.push(',');
                        out.push_str(&columns);
                    }
                }
            }
        }
        out.push(']');
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip(table: Option<&str>, brackets: &str, as_at: bool) -> String {
        let r = parse_table_ref(table, brackets).expect("a structured reference");
        let mut out = String::new();
        r.write(&mut out, as_at);
        out
    }

    #[test]
    fn structured_references_read_back_as_excel_writes_them() {
        assert_eq!(round_trip(Some("Parts"), "[Qty]", true), "Parts[Qty]");
        assert_eq!(round_trip(Some("Parts"), "[[#Totals],[Qty]]", true), "Parts[[#Totals],[Qty]]");
        assert_eq!(round_trip(Some("Parts"), "[#All]", true), "Parts[#All]");
        assert_eq!(round_trip(Some("Parts"), "[]", true), "Parts[]");
        assert_eq!(round_trip(None, "[@Qty]", true), "[@Qty]");
        assert_eq!(round_trip(Some("T"), "[@Qty]", false), "T[[#This Row],[Qty]]");
        assert_eq!(round_trip(Some("T"), "[[#This Row],[Qty]]", true), "T[@Qty]");
        assert_eq!(round_trip(None, "[@[Unit Price]]", true), "[@[Unit Price]]");
        assert_eq!(round_trip(Some("T"), "[[Unit Price]]", true), "T[Unit Price]");
        assert_eq!(round_trip(Some("T"), "[[Total $]]", true), "T[[Total $]]");
        assert_eq!(round_trip(Some("T"), "[[#Headers],[#Data],[A]:[B]]", true), "T[[#Headers],[#Data],[A]:[B]]");
        assert_eq!(round_trip(Some("T"), "[[A]:[B]]", true), "T[[A]:[B]]");
        // A name with a space at an end keeps its own brackets, as IronCalc's tables.xlsx holds
        // `Table3[[the two ]]`; `Table1[]` is the data rows (Excel's SUM(Table1[]) there: 274).
        assert_eq!(round_trip(Some("T"), "[[the two ]]", true), "T[[the two ]]");
        assert!(parse_table_ref(Some("T"), "[]").is_some_and(|r| r.rows.data && r.columns.is_none()));
        // Excel's escapes: `'` before `'` and `#`; a name with a sign in its own brackets.
        assert_eq!(round_trip(Some("T"), "[[Col'''#]]", true), "T[[Col'''#]]");
        let r = parse_table_ref(Some("T"), "[[Col'''#]]").expect("reference");
        assert_eq!(r.columns.as_ref().map(|c| c.0.to_string()), Some("Col'#".to_string()));
    }

    #[test]
    fn what_is_not_a_structured_reference_is_refused() {
        assert!(parse_table_ref(Some("T"), "[#Nope]").is_none());
        assert!(parse_table_ref(Some("T"), "[[A]:]").is_none());
        assert!(parse_table_ref(Some("T"), "[[A] x]").is_none());
    }
}
