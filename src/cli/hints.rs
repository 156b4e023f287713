//! A word when typed input looks wrong: text a user probably meant as something else. A
//! spreadsheet stores `TAN(RADIANS(alpha))` (no `=`), `0,8` (a decimal comma) or `1;2;3` as
//! text without a sound; the command line says so on stderr, naming the cell.

use ncsheet::eval::Value;
use ncsheet::formula::address::Pos;
use ncsheet::formula::ast::SheetId;
use ncsheet::workbook::{Input, Workbook};

/// Why `input`, stored in a cell as text, was probably meant otherwise; `None` when it looks
/// like the text it is.
pub fn doubt_about(wb: &Workbook, sheet: SheetId, pos: Pos, input: &str) -> Option<String> {
    let text = input.trim();
    if !matches!(Input::parse(input, wb.date_system()), Input::Value(Value::Text(_))) || text.starts_with('\'') {
        return None;
    }
    if is_decimal_comma(text) {
        let number = text.replace(',', ".");
        return Some(format!("'{text}' is stored as text; the decimal mark is a point: {number}"));
    }
    if text.contains(';') && text.split(';').filter(|p| !p.trim().is_empty()).count() >= 2 {
        return Some(format!("'{text}' is stored as text: one cell holds one value (is this a ;-separated list?)"));
    }
    let operators = text.contains(['(', '+', '*', '/', '^']) || text.chars().skip(1).any(|c| c == '-');
    if operators && wb.parse_at(&format!("={text}"), sheet, pos).is_ok() {
        return Some(format!("'{text}' is stored as text; a formula starts with =: ={text}"));
    }
    None
}

/// `0,8`, `-12,5`: digits, one comma, one to two or four-plus digits (not `1,234`, which a
/// spreadsheet reads as a thousands separator).
fn is_decimal_comma(text: &str) -> bool {
    let body = text.strip_prefix(['-', '+']).unwrap_or(text);
    let Some((whole, fraction)) = body.split_once(',') else { return false };
    let digits = |s: &str| !s.is_empty() && s.chars().all(|c| c.is_ascii_digit());
    digits(whole) && digits(fraction) && fraction.len() != 3
}
