//! 3D references (`Sheet2:Sheet5!A11`, `'Jan 24':'Dec 24'!B2:B9`): the same cells on every
//! sheet from the first to the last, in tab order. Excel accepts them only as arguments of
//! the functions that take any number of ranges (SUM, COUNT, AVERAGE, MAX …), where a 3D
//! reference means exactly the list of its sheets' references; the importer writes it so,
//! and the graph links each sheet's cells.

use std::borrow::Cow;

/// The formula text with each 3D reference spelled as the list of its sheets' references;
/// `sheets` are the workbook's sheet names in tab order. A span whose ends are not both
/// sheets stays as it is. `spanned(first, last)` is told the tabs of each span expanded.
pub fn expand_sheet_spans<'t>(text: &'t str, sheets: &[String], spanned: &mut dyn FnMut(usize, usize)) -> Cow<'t, str> {
    if sheets.len() < 2 || !text.contains(':') || !text.contains('!') {
        return Cow::Borrowed(text);
    }
    replace_tokens(text, |at| span_at(text, at, sheets, spanned))
}

/// The formula text with each token `replace` knows (given where it starts, outside text
/// and quoted names, not within a name or reference: `Some((end, replacement))`) replaced.
pub(super) fn replace_tokens(text: &str, mut replace: impl FnMut(usize) -> Option<(usize, String)>) -> Cow<'_, str> {
    let bytes = text.as_bytes();
    let mut out = String::new();
    let mut copied = 0;
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'"' {
            i = skip_delimited(bytes, i);
            continue;
        }
        let starts_token = i == 0 || !is_name_byte(bytes[i - 1]) && !matches!(bytes[i - 1], b'!' | b']' | b'\'');
        if starts_token {
            if let Some((end, replacement)) = replace(i) {
                out.push_str(&text[copied..i]);
                out.push_str(&replacement);
                copied = end;
                i = end;
                continue;
            }
        }
        i += if bytes[i] == b'\'' { skip_delimited(bytes, i) - i } else { 1 };
    }
    if copied == 0 {
        return Cow::Borrowed(text);
    }
    out.push_str(&text[copied..]);
    Cow::Owned(out)
}

/// The formula text with the sheet dropped from each `Sheet1!#REF!` (`'My data'!#REF!`,
/// `[1]Data!#REF!`): Excel writes a reference whose cells were deleted so, and it means
/// `#REF!`, in a cell as in a defined name.
pub fn ref_errors_without_sheet(text: &str) -> Cow<'_, str> {
    // The `!` first: one vectorised search, where the whole pattern costs a set-up per
    // formula of the file.
    if !text.contains('!') || !text.contains("!#REF!") {
        return Cow::Borrowed(text);
    }
    let bytes = text.as_bytes();
    let mut out = String::new();
    let mut copied = 0;
    let mut i = 0;
    while i < bytes.len() {
        let end = match bytes[i] {
            b'"' => {
                i = skip_delimited(bytes, i);
                continue;
            }
            b'\'' => skip_delimited(bytes, i),
            // `[1]Data`: a linked workbook's sheet.
            b'[' => {
                let digits = bytes[i + 1..].iter().take_while(|b| b.is_ascii_digit()).count();
                if digits == 0 || bytes.get(i + 1 + digits) != Some(&b']') {
                    i += 1;
                    continue;
                }
                let at = i + 2 + digits;
                at + bytes[at..].iter().take_while(|&&b| is_name_byte(b)).count()
            }
            b if is_name_byte(b) => {
                i + bytes[i..].iter().take_while(|&&b| is_name_byte(b) || b == b'[' || b == b']').count()
            }
            _ => {
                i += 1;
                continue;
            }
        };
        if text.get(end..).is_some_and(|rest| rest.starts_with("!#REF!")) {
            out.push_str(&text[copied..i]);
            copied = end + 1;
        }
        i = end.max(i + 1);
    }
    if copied == 0 {
        return Cow::Borrowed(text);
    }
    out.push_str(&text[copied..]);
    Cow::Owned(out)
}

/// `first:last!ref` starting at `at`: where it ends and its expansion.
fn span_at(text: &str, at: usize, sheets: &[String], spanned: &mut dyn FnMut(usize, usize)) -> Option<(usize, String)> {
    let (first, after_first) = sheet_name(text, at)?;
    let (first, last, after_last) = match first.split_once(':') {
        // Excel quotes the pair as one: `'Jan 1:Mar''s'!B2` (a sheet name has no `:`).
        Some((a, b)) => (a.to_string(), b.to_string(), after_first),
        None => {
            text.get(after_first..)?.strip_prefix(':')?;
            let (last, after_last) = sheet_name(text, after_first + 1)?;
            (first, last, after_last)
        }
    };
    let bang = text.get(after_last..)?.strip_prefix('!')?;
    let ref_len = bang.bytes().take_while(|&b| b.is_ascii_alphanumeric() || b == b'$' || b == b':').count();
    if ref_len == 0 {
        return None;
    }
    let reference = &bang[..ref_len];
    let index = |name: &str| sheets.iter().position(|s| s.eq_ignore_ascii_case(name));
    let (a, b) = (index(&first)?, index(&last)?);
    let (a, b) = (a.min(b), a.max(b));
    spanned(a, b);
    let list: Vec<String> = sheets[a..=b].iter().map(|s| format!("'{}'!{reference}", s.replace('\'', "''"))).collect();
    Some((after_last + 1 + ref_len, list.join(",")))
}

/// A sheet name at `at`, bare (`Sheet2`) or quoted (`'Jan 24'`): the name and where it ends.
fn sheet_name(text: &str, at: usize) -> Option<(String, usize)> {
    let bytes = text.as_bytes();
    if bytes.get(at) == Some(&b'\'') {
        let end = skip_delimited(bytes, at);
        if end > bytes.len() || bytes.get(end - 1) != Some(&b'\'') || end - at < 2 {
            return None;
        }
        return Some((text[at + 1..end - 1].replace("''", "'"), end));
    }
    let len = bytes[at..].iter().take_while(|&&b| is_name_byte(b)).count();
    (len > 0).then(|| (text[at..at + len].to_string(), at + len))
}

pub(super) fn is_name_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b == b'.' || b >= 0x80
}

/// One past the end of the `"string"` or `'quoted sheet name'` that starts at `i` (its
/// quote, doubled inside, is `bytes[i]`), or the end of the text when it is not closed.
pub(super) fn skip_delimited(bytes: &[u8], mut i: usize) -> usize {
    let quote = bytes[i];
    i += 1;
    while i < bytes.len() {
        if bytes[i] == quote {
            if bytes.get(i + 1) == Some(&quote) {
                i += 2;
                continue;
            }
            return i + 1;
        }
        i += 1;
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sheets() -> Vec<String> {
        ["Summary", "Jan", "Feb 24", "Mar", "Notes"].iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn a_sheet_span_is_the_list_of_its_sheets_references() {
        let s = sheets();
        assert_eq!(expand_sheet_spans("SUM(Jan:Mar!B2)", &s, &mut |_, _| {}), "SUM('Jan'!B2,'Feb 24'!B2,'Mar'!B2)");
        assert_eq!(
            expand_sheet_spans("COUNT('Feb 24':Mar!$A$1:$B$2)", &s, &mut |_, _| {}),
            "COUNT('Feb 24'!$A$1:$B$2,'Mar'!$A$1:$B$2)"
        );
        assert_eq!(expand_sheet_spans("SUM(Mar:Jan!C1)", &s, &mut |_, _| {}), "SUM('Jan'!C1,'Feb 24'!C1,'Mar'!C1)");
        assert_eq!(expand_sheet_spans("SUM('Jan:Feb 24'!C1)", &s, &mut |_, _| {}), "SUM('Jan'!C1,'Feb 24'!C1)");
        assert_eq!(expand_sheet_spans("SUM('Feb 24:Jan'!C1)", &s, &mut |_, _| {}), "SUM('Jan'!C1,'Feb 24'!C1)");
    }

    #[test]
    fn a_deleted_reference_is_ref_whatever_sheet_it_was_on() {
        assert_eq!(ref_errors_without_sheet("Sheet1!#REF!"), "#REF!");
        assert_eq!(ref_errors_without_sheet("SUM('My data'!#REF!,A1)*[1]Jan!#REF!"), "SUM(#REF!,A1)*#REF!");
        for text in ["#REF!*2", "\"Sheet1!#REF!\"&A1", "Sheet1!A1", "[@x]+#REF!"] {
            assert_eq!(ref_errors_without_sheet(text), text);
        }
    }

    #[test]
    fn ranges_text_and_unknown_sheets_stay() {
        let s = sheets();
        for text in ["SUM(Jan!A1:B2)", "Jan!A1:Mar!B2", "\"Jan:Mar!A1\"", "SUM(Jan:Dec!A1)", "[1]Jan:Mar!A1"] {
            assert_eq!(expand_sheet_spans(text, &s, &mut |_, _| {}), text);
        }
    }
}
