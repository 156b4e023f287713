//! Cell arguments as a user types them: `B3`, `A1:D20`, `Sheet1!B3`, `'My sheet'!A1:B2`,
//! and `CELL=INPUT` assignments. Parsed by clap, so a malformed one is a usage error.

use ncsheet::formula::address::{parse_cell, parse_rect, Pos, Rect};

/// A cell or a rectangle, on a named sheet or on the command's sheet; or a defined name
/// (`alpha`, `XA`), which the command resolves against the workbook (`rect` is then unused).
#[derive(Clone, Debug, PartialEq)]
pub struct Target {
    pub sheet: Option<String>,
    pub rect: Rect,
    pub name: Option<String>,
}

/// `CELL=INPUT`: what to type into a cell.
#[derive(Clone, Debug, PartialEq)]
pub struct Assignment {
    pub target: Target,
    pub input: String,
}

const EXPECTED: &str =
    "expected a cell like B3, a range like A1:D20 (optionally after a sheet name: Sheet1!B3) or a defined name";

pub fn parse_target(text: &str) -> Result<Target, String> {
    let (sheet, address) = split_sheet(text.trim())?;
    match parse_rect(address) {
        Some(rect) => Ok(Target { sheet, rect, name: None }),
        None if looks_like_name(address) => Ok(named(sheet, address)),
        None => Err(EXPECTED.to_string()),
    }
}

pub fn parse_cell_target(text: &str) -> Result<Target, String> {
    let (sheet, address) = split_sheet(text.trim())?;
    match parse_cell(address) {
        Some(pos) => Ok(Target { sheet, rect: Rect::cell(pos), name: None }),
        None if looks_like_name(address) => Ok(named(sheet, address)),
        None => Err(format!("expected one cell like B3 or a defined name, not {address}")),
    }
}

fn named(sheet: Option<String>, name: &str) -> Target {
    Target { sheet, rect: Rect::cell(Pos::new(0, 0)), name: Some(name.to_string()) }
}

/// Excel's defined names: a letter, `_` or `\` first, then letters, digits, `_`, `.`.
pub fn looks_like_name(text: &str) -> bool {
    text.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_' || c == '\\')
        && text.chars().all(|c| c.is_alphanumeric() || matches!(c, '_' | '.' | '\\'))
}

/// `B3=45`, `B3==A1*2`, `Sheet1!B3=text`; `B3=` empties the cell. Spaces around the cell and
/// the input are dropped.
pub fn parse_assignment(text: &str) -> Result<Assignment, String> {
    // The first `=` after the sheet name (which may itself hold `=` inside quotes).
    let after_sheet = if text.trim_start().starts_with('\'') { text.rfind("'!").unwrap_or(0) } else { 0 };
    let Some(eq) = text[after_sheet..].find('=').map(|i| i + after_sheet) else {
        return Err("expected CELL=INPUT, like B3=45 or B3==A1*2".to_string());
    };
    let target = parse_cell_target(&text[..eq])?;
    Ok(Assignment { target, input: text[eq + 1..].trim().to_string() })
}

/// Splits `Sheet1!B3` into the sheet name and the address; `'It''s'!A1` unquotes to `It's`.
fn split_sheet(text: &str) -> Result<(Option<String>, &str), String> {
    let Some((sheet, address)) = text.rsplit_once('!') else { return Ok((None, text)) };
    let name = match sheet.strip_prefix('\'') {
        Some(rest) => {
            rest.strip_suffix('\'').ok_or_else(|| format!("unclosed quote in sheet name {sheet}"))?.replace("''", "'")
        }
        None => sheet.to_string(),
    };
    if name.is_empty() {
        return Err(format!("empty sheet name before '!' in {text}"));
    }
    Ok((Some(name), address))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn targets_with_and_without_sheets() {
        let t = parse_target("B3").unwrap();
        assert_eq!((t.sheet, t.rect), (None, Rect::cell(Pos::new(2, 1))));
        let t = parse_target("'It''s'!A1:b2").unwrap();
        assert_eq!((t.sheet.as_deref(), t.rect.to_string()), (Some("It's"), "A1:B2".to_string()));
        assert_eq!(parse_target("alpha").unwrap().name.as_deref(), Some("alpha"));
        assert!(parse_target("B 3").is_err());
        assert!(parse_target("!A1").is_err());
    }

    #[test]
    fn assignments_split_at_the_first_equals_sign() {
        let a = parse_assignment("B3==A1*2").unwrap();
        assert_eq!((a.target.rect.to_string(), a.input.as_str()), ("B3".to_string(), "=A1*2"));
        let a = parse_assignment(" C1 = 45 ").unwrap();
        assert_eq!((a.target.rect.to_string(), a.input.as_str()), ("C1".to_string(), "45"));
        let a = parse_assignment("'a=b'!C1=x").unwrap();
        assert_eq!((a.target.sheet.as_deref(), a.input.as_str()), (Some("a=b"), "x"));
        assert_eq!(parse_assignment("B3=").unwrap().input, "");
        assert_eq!(parse_assignment("alpha=30").unwrap().target.name.as_deref(), Some("alpha"));
        assert!(parse_assignment("B3").is_err());
        assert!(parse_assignment("A1:B2=1").is_err());
    }
}
