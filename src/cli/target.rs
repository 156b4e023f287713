//! Cell arguments as a user types them: `B3`, `A1:D20`, `Sheet1!B3`, `'My sheet'!A1:B2`,
//! and `CELL=INPUT` assignments. Parsed by clap, so a malformed one is a usage error.

use ncsheet::formula::address::{parse_cell, parse_rect, Rect};

/// A cell or a rectangle, on a named sheet or on the command's sheet.
#[derive(Clone, Debug, PartialEq)]
pub struct Target {
    pub sheet: Option<String>,
    pub rect: Rect,
}

/// `CELL=INPUT`: what to type into a cell.
#[derive(Clone, Debug, PartialEq)]
pub struct Assignment {
    pub target: Target,
    pub input: String,
}

const EXPECTED: &str = "expected a cell like B3 or a range like A1:D20, optionally after a sheet name (Sheet1!B3)";

pub fn parse_target(text: &str) -> Result<Target, String> {
    let (sheet, address) = split_sheet(text.trim())?;
    let rect = parse_rect(address).ok_or_else(|| EXPECTED.to_string())?;
    Ok(Target { sheet, rect })
}

pub fn parse_cell_target(text: &str) -> Result<Target, String> {
    let (sheet, address) = split_sheet(text.trim())?;
    let pos = parse_cell(address).ok_or_else(|| format!("expected one cell like B3, not {address}"))?;
    Ok(Target { sheet, rect: Rect::cell(pos) })
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
    use ncsheet::formula::address::Pos;

    #[test]
    fn targets_with_and_without_sheets() {
        let t = parse_target("B3").unwrap();
        assert_eq!((t.sheet, t.rect), (None, Rect::cell(Pos::new(2, 1))));
        let t = parse_target("'It''s'!A1:b2").unwrap();
        assert_eq!((t.sheet.as_deref(), t.rect.to_string()), (Some("It's"), "A1:B2".to_string()));
        assert!(parse_target("B").is_err());
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
        assert!(parse_assignment("B3").is_err());
        assert!(parse_assignment("A1:B2=1").is_err());
    }
}
