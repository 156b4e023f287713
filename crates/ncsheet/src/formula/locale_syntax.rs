//! Formulas as a spreadsheet whose locale writes decimal commas types them (and a `;`-separated
//! csv holds them): `;` between arguments, `,` as the decimal mark (`=ROUND(A1*0,5;2)`), and in an
//! array constant `.` between columns and `;` between rows (`{1,5.2;3.4}`). ncsheet holds
//! formulas in the Excel file syntax (`,`, `.`, `{1.5,2;3,4}`); these two functions swap
//! the separators outside text, quoted sheet names and structured references, and change
//! nothing else.

/// An Excel-syntax formula as a decimal-comma spreadsheet writes it.
pub fn to_semicolon_locale(formula: &str) -> String {
    swap(formula, ('.', ','), |c, in_array| match c {
        ',' if in_array => '.',
        ',' => ';',
        c => c,
    })
}

/// A formula typed in a decimal-comma spreadsheet, in the Excel syntax ncsheet reads.
pub fn from_semicolon_locale(formula: &str) -> String {
    swap(formula, (',', '.'), |c, in_array| match c {
        '.' if in_array => ',',
        ';' if !in_array => ',',
        c => c,
    })
}

/// Copies `formula`, mapping each separator outside a number through `separator` (given
/// whether it stands in an array constant) and the decimal mark in numbers `mark.0` to
/// `mark.1`.
fn swap(formula: &str, mark: (char, char), separator: impl Fn(char, bool) -> char) -> String {
    let chars: Vec<char> = formula.chars().collect();
    let mut out = String::with_capacity(formula.len() + 8);
    let (mut i, mut arrays) = (0, 0usize);
    while i < chars.len() {
        let c = chars[i];
        match c {
            '"' | '\'' => i = copy_quoted(&chars, i, &mut out),
            '[' => i = copy_bracketed(&chars, i, &mut out),
            '{' | '}' => {
                arrays = if c == '{' { arrays + 1 } else { arrays.saturating_sub(1) };
                out.push(c);
                i += 1;
            }
            _ if starts_number(&chars, i, mark.0) => i = copy_number(&chars, i, mark, &mut out),
            _ if separator(c, arrays > 0) != c => {
                out.push(separator(c, arrays > 0));
                i += 1;
            }
            _ if is_name_char(c) => {
                // A name or reference, copied whole: a `.` or digit in it is no number.
                while i < chars.len() && is_name_char(chars[i]) {
                    out.push(chars[i]);
                    i += 1;
                }
            }
            c => {
                out.push(separator(c, arrays > 0));
                i += 1;
            }
        }
    }
    out
}

fn is_name_char(c: char) -> bool {
    c.is_alphanumeric() || matches!(c, '_' | '.' | '\\' | '$' | '?')
}

/// Whether a number literal starts at `i`: a digit, or a decimal mark and a digit. (Names
/// and references are copied whole, so a digit in one never comes here.)
fn starts_number(chars: &[char], i: usize, mark: char) -> bool {
    let digit_at = |j: usize| chars.get(j).is_some_and(char::is_ascii_digit);
    digit_at(i) || (chars[i] == mark && digit_at(i + 1))
}

/// Copies the number literal at `i` with its decimal mark `mark.0` written as `mark.1`;
/// returns the index after it.
fn copy_number(chars: &[char], mut i: usize, mark: (char, char), out: &mut String) -> usize {
    let mut mark_seen = false;
    while i < chars.len() {
        let c = chars[i];
        let next_is_digit = chars.get(i + 1).is_some_and(char::is_ascii_digit);
        if c.is_ascii_digit() {
            out.push(c);
        } else if c == mark.0 && !mark_seen && next_is_digit {
            mark_seen = true;
            out.push(mark.1);
        } else if matches!(c, 'e' | 'E') && exponent_follows(chars, i + 1) {
            out.push(c);
            if matches!(chars[i + 1], '+' | '-') {
                i += 1;
                out.push(chars[i]);
            }
        } else {
            break;
        }
        i += 1;
    }
    i
}

fn exponent_follows(chars: &[char], i: usize) -> bool {
    let digits_from = if matches!(chars.get(i), Some('+' | '-')) { i + 1 } else { i };
    chars.get(digits_from).is_some_and(char::is_ascii_digit)
}

/// Copies a `"…"` text or `'…'` sheet name (its quote doubled inside) from `i`; returns the
/// index after it.
fn copy_quoted(chars: &[char], mut i: usize, out: &mut String) -> usize {
    let quote = chars[i];
    out.push(quote);
    i += 1;
    while i < chars.len() {
        out.push(chars[i]);
        if chars[i] == quote {
            if chars.get(i + 1) == Some(&quote) {
                out.push(quote);
                i += 2;
                continue;
            }
            return i + 1;
        }
        i += 1;
    }
    i
}

/// Copies a structured reference's `[…]` (nested, `'` escaping a bracket) from `i`.
fn copy_bracketed(chars: &[char], mut i: usize, out: &mut String) -> usize {
    let mut depth = 0usize;
    while i < chars.len() {
        let c = chars[i];
        out.push(c);
        i += 1;
        match c {
            '\'' if i < chars.len() => {
                out.push(chars[i]);
                i += 1;
            }
            '[' => depth += 1,
            ']' => {
                depth -= 1;
                if depth == 0 {
                    break;
                }
            }
            _ => {}
        }
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pairs of the Excel file syntax and the decimal-comma locale's, as Excel's and
    /// LibreOffice's German editions show the same formula.
    const PAIRS: &[(&str, &str)] = &[
        ("=ROUND(A1*0.5,2)", "=ROUND(A1*0,5;2)"),
        ("=SUM(Sheet1!A1:B2,1.25E-3,.5)", "=SUM(Sheet1!A1:B2;1,25E-3;,5)"),
        ("=IF(A1>1,\"a,b;c.d\",'my.sheet'!B2)", "=IF(A1>1;\"a,b;c.d\";'my.sheet'!B2)"),
        ("=SUM({1.5,2;3,4})", "=SUM({1,5.2;3.4})"),
        ("={1.5,2,2.5}", "={1,5.2.2,5}"),
        ("=SUM(Table1[[#This Row],[a.b]],x.1)", "=SUM(Table1[[#This Row],[a.b]];x.1)"),
        ("=LET(f,LAMBDA(n,n*2.5),f(1))", "=LET(f;LAMBDA(n;n*2,5);f(1))"),
        ("=$A$1+A$12", "=$A$1+A$12"),
        ("=SUM(1,2)+MAX(1.5,2.5)", "=SUM(1;2)+MAX(1,5;2,5)"),
    ];

    #[test]
    fn separators_and_decimal_marks_are_swapped_outside_texts_names_and_references() {
        for (excel, local) in PAIRS {
            assert_eq!(to_semicolon_locale(excel), *local);
            assert_eq!(from_semicolon_locale(local), *excel);
        }
    }
}
