//! Token-level passes over a file's formula text before it is parsed: `Sheet1!#REF!` read as
//! `#REF!`, and the scanning helpers the linked-workbook and table passes share (texts and
//! quoted sheet names skipped whole). A 3-D reference (`Sheet2:Sheet5!A11`) needs no pass:
//! the formula language reads it as one node, resolved by tab order when evaluated.

use std::borrow::Cow;

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

    #[test]
    fn a_deleted_reference_is_ref_whatever_sheet_it_was_on() {
        assert_eq!(ref_errors_without_sheet("Sheet1!#REF!"), "#REF!");
        assert_eq!(ref_errors_without_sheet("SUM('My data'!#REF!,A1)*[1]Jan!#REF!"), "SUM(#REF!,A1)*#REF!");
        for text in ["#REF!*2", "\"Sheet1!#REF!\"&A1", "Sheet1!A1", "[@x]+#REF!"] {
            assert_eq!(ref_errors_without_sheet(text), text);
        }
    }
}
