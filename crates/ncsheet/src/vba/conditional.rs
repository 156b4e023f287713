//! What VBA does to a module's text before it parses statements, done here byte for byte in
//! place so that every offset, line and column stays where it was:
//!
//! - conditional compilation ([MS-VBAL] 3.4): `#Const`, `#If … Then`, `#ElseIf`, `#Else`,
//!   `#End If`. The directive lines and the lines of branches not taken become spaces. The
//!   compilation constants are those of Excel on 64-bit Windows ([MS-VBAL] 3.4.1.1 lists
//!   them): `VBA7`, `VBA6`, `Win64` and `Win32` are True, `Win16` and `Mac` False;
//! - a comment continued by ` _` at the end of its line ([MS-VBAL] 3.2.2: a line
//!   continuation inside a comment continues the comment): the lines it continues become spaces.

use std::borrow::Cow;
use std::collections::HashMap;

use crate::formula::parse::ParseError;

/// The deepest `#If` blocks nest, and parentheses in a directive's condition.
const MAX_NESTING: usize = 100;

/// The module's text with directives, branches not taken and continued comments blanked.
pub fn prepare(src: &str) -> Result<Cow<'_, str>, ParseError> {
    if !needs_preparing(src) {
        return Ok(Cow::Borrowed(src));
    }
    let mut out = src.as_bytes().to_vec();
    let mut constants: HashMap<String, i64> = [("vba7", -1), ("vba6", -1), ("win64", -1), ("win32", -1)]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect();
    constants.insert("win16".into(), 0);
    constants.insert("mac".into(), 0);
    // Each open #If: (this branch is taken, a branch was taken already, the #If's
    // surroundings are taken).
    let mut open: Vec<(bool, bool, bool)> = Vec::new();
    let mut comment_continues = false;
    let mut offset = 0;
    for line in src.split_inclusive('\n') {
        let start = offset;
        offset += line.len();
        let taking = open.last().is_none_or(|&(taken, _, _)| taken);
        let code = line.trim_end_matches(['\r', '\n']);
        if comment_continues {
            blank(&mut out[start..start + code.len()]);
            comment_continues = code.ends_with(" _");
            continue;
        }
        let trimmed = code.trim_start();
        if let Some(directive) = trimmed.strip_prefix('#').filter(|d| is_directive(d)) {
            let at = start + (code.len() - trimmed.len());
            directive_line(directive, taking, &mut open, &mut constants)
                .map_err(|m| ParseError { offset: at, message: m })?;
            blank(&mut out[start..start + code.len()]);
            continue;
        }
        if !taking {
            blank(&mut out[start..start + code.len()]);
            continue;
        }
        comment_continues = comment_start(code).is_some() && code.ends_with(" _");
    }
    if !open.is_empty() {
        return Err(ParseError { offset: src.len(), message: "#If without #End If".into() });
    }
    Ok(Cow::Owned(String::from_utf8(out).expect("only ASCII bytes replaced by spaces")))
}

/// Whether any line could be a directive or a continued comment (most modules: none).
fn needs_preparing(src: &str) -> bool {
    src.lines().any(|l| {
        let t = l.trim_start();
        t.starts_with('#') || (l.ends_with(" _") && comment_start(l).is_some())
    })
}

fn is_directive(text: &str) -> bool {
    let word: String = text.chars().take_while(|c| c.is_ascii_alphabetic()).collect::<String>().to_ascii_lowercase();
    matches!(word.as_str(), "if" | "elseif" | "else" | "end" | "const")
}

/// Every byte but the line's end a space (a character of several bytes, several spaces).
pub(super) fn blank(bytes: &mut [u8]) {
    bytes.iter_mut().for_each(|b| *b = b' ');
}

/// Where a line's comment starts: a `'` outside a string, or `Rem` as the line's statement.
fn comment_start(line: &str) -> Option<usize> {
    let trimmed = line.trim_start();
    let lead = line.len() - trimmed.len();
    let rem = trimmed.get(..3).is_some_and(|w| w.eq_ignore_ascii_case("rem"))
        && trimmed[3..].chars().next().is_none_or(|c| c == ' ' || c == '\t');
    if rem {
        return Some(lead);
    }
    let mut in_string = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => in_string = !in_string,
            '\'' if !in_string => return Some(i),
            _ => {}
        }
    }
    None
}

fn directive_line(
    text: &str,
    taking: bool,
    open: &mut Vec<(bool, bool, bool)>,
    constants: &mut HashMap<String, i64>,
) -> Result<(), String> {
    let text = text.split('\'').next().unwrap_or("").trim();
    let lower = text.to_ascii_lowercase();
    let word = lower.split(|c: char| !c.is_ascii_alphabetic()).next().unwrap_or("");
    let rest = &text[word.len()..];
    match word {
        "const" if taking => {
            let (name, value) = rest.split_once('=').ok_or("#Const needs a name = value")?;
            let name = name.trim().to_ascii_lowercase();
            if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                return Err(format!("#Const {name}: not a name"));
            }
            let value = condition(value, constants)?;
            constants.insert(name, value);
        }
        "const" => {}
        "if" => {
            if open.len() >= MAX_NESTING {
                return Err(format!("#If blocks nest more than {MAX_NESTING} deep"));
            }
            let holds = taking && condition(strip_then(rest)?, constants)? != 0;
            open.push((holds, holds, taking));
        }
        "elseif" => {
            let (_, done, outer) = *open.last().ok_or("#ElseIf without #If")?;
            let holds = outer && !done && condition(strip_then(rest)?, constants)? != 0;
            *open.last_mut().expect("checked") = (holds, done || holds, outer);
        }
        "else" => {
            let (_, done, outer) = *open.last().ok_or("#Else without #If")?;
            *open.last_mut().expect("checked") = (outer && !done, true, outer);
        }
        "end" if lower.split_whitespace().nth(1) == Some("if") || lower == "endif" => {
            open.pop().ok_or("#End If without #If")?;
        }
        _ => return Err(format!("#{text}: not a directive (#If, #ElseIf, #Else, #End If, #Const)")),
    }
    Ok(())
}

fn strip_then(rest: &str) -> Result<&str, String> {
    let trimmed = rest.trim_end();
    let cut = trimmed.len().checked_sub(4).filter(|&i| trimmed.is_char_boundary(i));
    match cut {
        Some(i) if trimmed[i..].eq_ignore_ascii_case("then") => Ok(&trimmed[..i]),
        _ => Err("#If and #ElseIf end with Then".into()),
    }
}

/// A directive's condition: numbers, True, False, compilation constants (an unknown one is
/// Empty, 0), `Not`, `And`, `Or`, `Xor`, comparisons, `+ -` and parentheses, as integers
/// where True is -1.
fn condition(text: &str, constants: &HashMap<String, i64>) -> Result<i64, String> {
    let tokens = tokens(text)?;
    let mut p = Cond { tokens: &tokens, at: 0, constants, depth: 0 };
    let v = p.logic()?;
    if p.at != tokens.len() {
        return Err(format!("#If {}: not a condition", text.trim()));
    }
    Ok(v)
}

fn tokens(text: &str) -> Result<Vec<String>, String> {
    let mut out = Vec::new();
    let chars: Vec<char> = text.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_alphanumeric() || c == '_' {
            let from = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push(chars[from..i].iter().collect::<String>().to_ascii_lowercase());
        } else if (c == '<' || c == '>') && matches!(chars.get(i + 1), Some('=' | '>')) {
            out.push(chars[i..i + 2].iter().collect());
            i += 2;
        } else if "()=<>+-".contains(c) {
            out.push(c.to_string());
            i += 1;
        } else {
            return Err(format!("#If: {c} has no meaning in a condition"));
        }
    }
    Ok(out)
}

struct Cond<'a> {
    tokens: &'a [String],
    at: usize,
    constants: &'a HashMap<String, i64>,
    depth: usize,
}

impl Cond<'_> {
    fn peek(&self) -> Option<&str> {
        self.tokens.get(self.at).map(String::as_str)
    }

    fn eat(&mut self, word: &str) -> bool {
        let found = self.peek() == Some(word);
        self.at += usize::from(found);
        found
    }

    fn logic(&mut self) -> Result<i64, String> {
        let mut v = self.not()?;
        loop {
            if self.eat("and") {
                v &= self.not()?;
            } else if self.eat("or") {
                v |= self.not()?;
            } else if self.eat("xor") {
                v ^= self.not()?;
            } else {
                return Ok(v);
            }
        }
    }

    fn not(&mut self) -> Result<i64, String> {
        if self.eat("not") {
            return Ok(!self.nested(Self::not)?);
        }
        self.comparison()
    }

    fn nested(&mut self, f: fn(&mut Self) -> Result<i64, String>) -> Result<i64, String> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(format!("#If: a condition nested more than {MAX_NESTING} deep"));
        }
        let v = f(self);
        self.depth -= 1;
        v
    }

    fn comparison(&mut self) -> Result<i64, String> {
        let a = self.sum()?;
        let op = match self.peek() {
            Some(op @ ("=" | "<>" | "<" | ">" | "<=" | ">=")) => op.to_string(),
            _ => return Ok(a),
        };
        self.at += 1;
        let b = self.sum()?;
        let holds = match op.as_str() {
            "=" => a == b,
            "<>" => a != b,
            "<" => a < b,
            ">" => a > b,
            "<=" => a <= b,
            _ => a >= b,
        };
        Ok(if holds { -1 } else { 0 })
    }

    fn sum(&mut self) -> Result<i64, String> {
        let mut v = self.atom()?;
        loop {
            if self.eat("+") {
                v = v.saturating_add(self.atom()?);
            } else if self.eat("-") {
                v = v.saturating_sub(self.atom()?);
            } else {
                return Ok(v);
            }
        }
    }

    fn atom(&mut self) -> Result<i64, String> {
        let token = self.peek().ok_or("#If: the condition ends too soon")?.to_string();
        self.at += 1;
        match token.as_str() {
            "(" => {
                let v = self.nested(Self::logic)?;
                if !self.eat(")") {
                    return Err("#If: a ( without its )".into());
                }
                Ok(v)
            }
            "-" => Ok(self.nested(Self::atom)?.saturating_neg()),
            "true" => Ok(-1),
            "false" => Ok(0),
            t if t.starts_with(|c: char| c.is_ascii_digit()) => {
                t.parse().map_err(|_| format!("#If: {t} is not a whole number"))
            }
            t if t.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') => {
                Ok(self.constants.get(t).copied().unwrap_or(0))
            }
            t => Err(format!("#If: expected a value, not {t}")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_branch_taken_is_the_one_excel_64_bit_windows_takes() {
        let src = "#If VBA7 And Win64 Then\nA\n#ElseIf Mac Then\nB\n#Else\nC\n#End If\nD\n";
        let out = prepare(src).unwrap();
        assert_eq!(out.len(), src.len());
        let kept: Vec<&str> = out.lines().map(str::trim).filter(|l| !l.is_empty()).collect();
        assert_eq!(kept, ["A", "D"]);
    }

    #[test]
    fn const_and_not_and_nesting() {
        let kept = |src: &str| -> Vec<String> {
            prepare(src).unwrap().lines().map(|l| l.trim().to_string()).filter(|l| !l.is_empty()).collect()
        };
        let src = "#Const DEBUG_ON = True\n#If Not DEBUG_ON Then\nA\n#Else\n#If Mac Or (VBA7 = 0) Then\nB\n#Else\nC\n#End If\n#End If\n";
        assert_eq!(kept(src), ["C"]);
        // VBA's Not is bitwise (MS-VBAL 5.6.9.8.1, the Not operator): Not 1 is -2, which is
        // true, so `#Const X = 1` … `#If Not X` takes the branch (a known VBA trap).
        assert_eq!(kept("#Const X = 1\n#If Not X Then\nA\n#Else\nB\n#End If\n"), ["A"]);
    }

    #[test]
    fn a_continued_comment_takes_the_next_lines() {
        let src = "x = 1 ' a comment _\n  still the comment _\n  and this\ny = \"' _\"\nz\n";
        let out = prepare(src).unwrap();
        let kept: Vec<&str> = out.lines().map(str::trim).collect();
        assert_eq!(kept, ["x = 1 ' a comment _", "", "", "y = \"' _\"", "z"]);
    }

    #[test]
    fn unbalanced_directives_are_errors_at_their_line() {
        assert!(prepare("#If VBA7 Then\nA\n").unwrap_err().message.contains("#End If"));
        assert_eq!(prepare("A\n#Else\n").unwrap_err().offset, 2);
        let deep = "#If ".to_string() + &"(".repeat(500) + "1" + &")".repeat(500) + " Then\n#End If\n";
        assert!(prepare(&deep).is_err());
    }
}
