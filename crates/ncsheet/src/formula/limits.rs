//! How deep a formula or a macro may nest: ncsheet's limits, checked before the recursive
//! parser runs, so that hostile text is refused with a caret instead of overflowing the
//! stack (docs/limits.md).
//!
//! Excel refuses a formula with more than 64 nested functions. ncsheet counts every bracket
//! (parentheses, function calls, array braces, `[…]`) and every prefix operator (`-`, `+`,
//! `@`, `Not`) still open at a place, and allows [`MAX_NESTING`]: twice Excel's 64 functions
//! with room for the parentheses around their arguments, so that every formula Excel
//! accepts loads. Operators chained at one level (`1+1+1+…`) nest the syntax tree too;
//! [`MAX_TREE_DEPTH`] bounds the tree the parser builds. Macro blocks (`If`, `For`, `Do`,
//! `While`, `Select Case`, `With`) nest at most [`MAX_NESTING`] deep.
//!
//! Both limits are well below what the smallest thread stack the engine runs on (2 MiB, the
//! test harness's) holds for parsing, evaluating, printing and dropping such a tree.

use super::parse::ParseError;

/// Brackets and prefix operators open at one place of a formula or macro line, and blocks
/// open at one line of a macro.
pub const MAX_NESTING: usize = 255;

/// Levels of the syntax tree of one formula or macro expression, chained operators included.
pub const MAX_TREE_DEPTH: u32 = 1_500;

/// The message of a formula nested past [`MAX_NESTING`].
fn nesting_error(offset: usize) -> ParseError {
    ParseError {
        offset,
        message: format!(
            "nested more than {MAX_NESTING} levels deep (brackets and signs; ncsheet's limit, Excel's is 64 nested functions)"
        ),
    }
}

/// The message of a tree deeper than [`MAX_TREE_DEPTH`], at the operator that passes it.
pub fn tree_depth_error(offset: usize) -> ParseError {
    ParseError {
        offset,
        message: format!(
            "more than {MAX_TREE_DEPTH} operators chained or nested (ncsheet's limit on a formula's depth)"
        ),
    }
}

/// Which language the text is in: it decides what `'` starts and whether a line ends a
/// statement.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Language {
    /// A cell formula: `'…'` quotes a sheet name.
    Formula,
    /// A macro module: `'` starts a comment, a line break ends a statement.
    Macro,
}

/// Refuses text whose brackets and prefix operators nest past [`MAX_NESTING`], naming the
/// byte where it happens. A lexical scan, linear in the text and free of recursion: it
/// skips strings, quoted sheet names and comments, and counts a prefix operator as open
/// until the next binary operator, separator or closing bracket of its level.
pub fn check_nesting(text: &str, language: Language) -> Result<(), ParseError> {
    let bytes = text.as_bytes();
    // Per open bracket level: the prefix operators still open there.
    let mut levels: Vec<usize> = vec![0];
    let mut after_operand = false;
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        match b {
            b'"' => {
                i = skip_past(bytes, i + 1, b'"');
                after_operand = true;
                continue;
            }
            b'\'' if language == Language::Macro => {
                // The comment runs to the line break, which ends the statement below.
                i = skip_past(bytes, i + 1, b'\n').saturating_sub(1).max(i + 1);
                continue;
            }
            b'\'' => {
                i = skip_past(bytes, i + 1, b'\'');
                after_operand = true;
                continue;
            }
            b'\n' if language == Language::Macro && !continued(bytes, i) => {
                levels.clear();
                levels.push(0);
                after_operand = false;
            }
            b'(' | b'{' | b'[' => {
                levels.push(0);
                if open_levels(&levels) > MAX_NESTING {
                    return Err(nesting_error(i));
                }
                after_operand = false;
            }
            b')' | b'}' | b']' => {
                if levels.len() > 1 {
                    levels.pop();
                }
                after_operand = true;
            }
            b'-' | b'+' | b'@' if !after_operand => {
                if let Some(run) = levels.last_mut() {
                    *run += 1;
                }
                if open_levels(&levels) > MAX_NESTING {
                    return Err(nesting_error(i));
                }
            }
            b',' | b';' | b'-' | b'+' | b'*' | b'/' | b'^' | b'&' | b'=' | b'<' | b'>' | b':' | b'\\' => {
                if let Some(run) = levels.last_mut() {
                    *run = 0;
                }
                after_operand = false;
            }
            _ if b.is_ascii_alphanumeric() || b == b'_' || b == b'.' || b == b'$' || b >= 0x80 => {
                let end = word_end(bytes, i);
                let word = &text[i..end];
                if language == Language::Macro && word.eq_ignore_ascii_case("not") && !after_operand {
                    if let Some(run) = levels.last_mut() {
                        *run += 1;
                    }
                    if open_levels(&levels) > MAX_NESTING {
                        return Err(nesting_error(i));
                    }
                } else if after_operand && b.is_ascii_alphabetic() {
                    // A word after an operand is an operator word (`And`, `Mod`, `Then`):
                    // it ends the prefix operators of its level.
                    if let Some(run) = levels.last_mut() {
                        *run = 0;
                    }
                    after_operand = false;
                } else {
                    after_operand = true;
                }
                i = end;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    Ok(())
}

/// Brackets open plus the prefix operators open inside each of them.
fn open_levels(levels: &[usize]) -> usize {
    levels.len() - 1 + levels.iter().sum::<usize>()
}

/// The index just past the next `end` byte from `from` (or the end of the text).
fn skip_past(bytes: &[u8], from: usize, end: u8) -> usize {
    memchr::memchr(end, &bytes[from.min(bytes.len())..]).map_or(bytes.len(), |k| from + k + 1)
}

fn word_end(bytes: &[u8], from: usize) -> usize {
    let mut j = from;
    while j < bytes.len()
        && (bytes[j].is_ascii_alphanumeric() || matches!(bytes[j], b'_' | b'.' | b'$') || bytes[j] >= 0x80)
    {
        j += 1;
    }
    j
}

/// Whether the line break at `i` follows a ` _` line continuation.
fn continued(bytes: &[u8], i: usize) -> bool {
    let before = bytes[..i].strip_suffix(b"\r").unwrap_or(&bytes[..i]);
    let trimmed = before.iter().rposition(|&b| b != b' ' && b != b'\t').map_or(&before[..0], |k| &before[..=k]);
    trimmed.ends_with(b" _") || trimmed.ends_with(b"\t_")
}

/// Refuses a macro whose blocks (`If … Then` on its own, `For`, `Do`, `While`, `Select`,
/// `With`) nest past [`MAX_NESTING`], naming the byte of the statement that opens one too
/// many. Statements are read one per line or `:`; a mistaken count only moves the place
/// where an absurdly deep macro is refused.
pub fn check_block_nesting(src: &str) -> Result<(), ParseError> {
    let mut depth = 0usize;
    let mut offset = 0;
    let mut thens = 0usize;
    for line in src.split_inclusive('\n') {
        let code = strip_comment(line);
        // One-line Ifs nest inside one another (`If a Then If b Then …`, over continued
        // lines too): the parser recurses into each, so they count as blocks of their line.
        for at in then_words(code) {
            thens += 1;
            if thens > MAX_NESTING {
                return Err(ParseError {
                    offset: offset + at,
                    message: format!("blocks nested more than {MAX_NESTING} levels deep (ncsheet's limit)"),
                });
            }
        }
        let trimmed = code.trim_end();
        if !(trimmed.ends_with(" _") || trimmed.ends_with("\t_")) {
            thens = 0;
        }
        let mut start = offset;
        for stmt in split_statements(code) {
            let lead = stmt.len() - stmt.trim_start().len();
            match block_effect(stmt.trim()) {
                1 => {
                    depth += 1;
                    if depth > MAX_NESTING {
                        return Err(ParseError {
                            offset: start + lead,
                            message: format!("blocks nested more than {MAX_NESTING} levels deep (ncsheet's limit)"),
                        });
                    }
                }
                -1 => depth = depth.saturating_sub(1),
                _ => {}
            }
            start += stmt.len() + 1;
        }
        offset += line.len();
    }
    Ok(())
}

/// The bytes where the `Then` words of a line (outside strings) begin.
fn then_words(code: &str) -> impl Iterator<Item = usize> + '_ {
    let bytes = code.as_bytes();
    let word_byte = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let mut in_string = false;
    (0..bytes.len()).filter(move |&k| {
        if bytes[k] == b'"' {
            in_string = !in_string;
        }
        !in_string
            && (k == 0 || !word_byte(bytes[k - 1]))
            && bytes[k..].get(..4).is_some_and(|w| w.eq_ignore_ascii_case(b"then"))
            && !bytes.get(k + 4).is_some_and(|&c| word_byte(c))
    })
}

/// The line without its `'` comment (a `'` inside a string is text).
fn strip_comment(line: &str) -> &str {
    let mut in_string = false;
    for (k, c) in line.char_indices() {
        match c {
            '"' => in_string = !in_string,
            '\'' if !in_string => return &line[..k],
            _ => {}
        }
    }
    line
}

/// The statements of a line, split at `:` outside strings.
fn split_statements(code: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut in_string = false;
    let mut from = 0;
    for (k, c) in code.char_indices() {
        match c {
            '"' => in_string = !in_string,
            ':' if !in_string => {
                out.push(&code[from..k]);
                from = k + 1;
            }
            _ => {}
        }
    }
    out.push(&code[from..]);
    out
}

/// +1 for a statement opening a block, -1 for one closing it, 0 otherwise.
fn block_effect(stmt: &str) -> i32 {
    let mut words = stmt.split_whitespace().map(str::to_ascii_lowercase);
    let first = words.next().unwrap_or_default();
    match first.as_str() {
        "if" => i32::from(stmt.to_ascii_lowercase().ends_with("then")),
        "for" | "do" | "while" | "with" => 1,
        "select" => 1,
        "next" | "loop" | "wend" => -1,
        "end" => match words.next().as_deref() {
            Some("if" | "select" | "with") => -1,
            _ => 0,
        },
        _ => 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn excel_nesting_passes_and_deeper_is_refused_at_the_bracket() {
        let ok = format!("={}1{}", "IF(TRUE,(".repeat(64), "))".repeat(64));
        assert!(check_nesting(&ok, Language::Formula).is_ok());
        let deep = format!("={}1{}", "(".repeat(5000), ")".repeat(5000));
        assert_eq!(check_nesting(&deep, Language::Formula).unwrap_err().offset, 1 + MAX_NESTING);
    }

    #[test]
    fn signs_count_until_the_next_operator_of_their_level() {
        let ok = format!("={}", "-1+".repeat(10_000) + "1");
        assert!(check_nesting(&ok, Language::Formula).is_ok());
        let deep = format!("={}1", "-".repeat(20_000));
        assert_eq!(check_nesting(&deep, Language::Formula).unwrap_err().offset, 1 + MAX_NESTING);
        let nots = format!("x = {}True\n", "Not ".repeat(1000));
        assert!(check_nesting(&nots, Language::Macro).is_err());
    }

    #[test]
    fn strings_sheet_names_and_comments_do_not_count() {
        let text = format!("=\"{}\"&'{}'!A1", "(".repeat(1000), "((".repeat(300));
        assert!(check_nesting(&text, Language::Formula).is_ok());
        let src = format!("' {}\nx = 1\n", "(".repeat(1000));
        assert!(check_nesting(&src, Language::Macro).is_ok());
    }

    #[test]
    fn macro_blocks_count_by_statement() {
        let flat = "Sub m()\nFor i = 1 To 3: x = 1: Next\nIf x Then y = 1\nEnd Sub\n".repeat(400);
        assert!(check_block_nesting(&flat).is_ok());
        let deep = format!("Sub m()\n{}{}End Sub\n", "If x Then\n".repeat(5000), "End If\n".repeat(5000));
        assert!(check_block_nesting(&deep).is_err());
        let one_line = format!("Sub m()\n{}x = 1\nEnd Sub\n", "If x Then ".repeat(5000));
        let err = check_block_nesting(&one_line).unwrap_err();
        assert_eq!(err.offset, "Sub m()\n".len() + MAX_NESTING * "If x Then ".len() + "If x ".len());
        let continued = format!("Sub m()\n{}x = 1\nEnd Sub\n", "If x Then _\n".repeat(5000));
        assert!(check_block_nesting(&continued).is_err());
        let fine = format!("Sub m()\n{}x = \"Then Then\"\nEnd Sub\n", "If Thenx Then ".repeat(MAX_NESTING));
        assert!(check_block_nesting(&fine).is_ok());
    }
}
