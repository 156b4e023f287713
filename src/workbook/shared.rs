//! Shared formulas: a formula copied down a column is parsed once and every copy points at
//! the one tree, as Excel's shared formulas do.
//!
//! A cheap scan turns the formula text into a key in which each cell reference is written
//! as an offset from the formula's cell (R1C1 style). Texts with equal keys parse to equal
//! trees (references are stored as offsets), so the parse is skipped for every copy.

use std::collections::HashMap;
use std::fmt::Write;
use std::rc::Rc;

use crate::formula::address::{column_index, Pos, MAX_ROWS};
use crate::formula::ast::{Expr, Reference};

/// One parsed formula and what the dependency graph needs of it.
pub struct SharedFormula {
    pub expr: Rc<Expr>,
    /// The references in the tree, so edges are found without walking it again.
    pub refs: Vec<Reference>,
    /// Uses a defined name (its references are looked up when edges are built).
    pub names: Vec<Rc<str>>,
}

impl SharedFormula {
    pub fn new(expr: Expr) -> SharedFormula {
        let mut refs = Vec::new();
        let mut names = Vec::new();
        expr.visit(&mut |e| match &e.kind {
            crate::formula::ast::ExprKind::Ref(r) => refs.push(r.clone()),
            crate::formula::ast::ExprKind::Name(n) => names.push(n.clone()),
            _ => {}
        });
        SharedFormula { expr: Rc::new(expr), refs, names }
    }
}

/// Parsed formulas, deduplicated by their relative key.
#[derive(Default)]
pub struct FormulaStore {
    pub formulas: Vec<SharedFormula>,
    by_key: HashMap<String, u32>,
}

impl FormulaStore {
    pub fn get(&self, id: u32) -> &SharedFormula {
        &self.formulas[id as usize]
    }

    /// The id of an already parsed formula with this key.
    pub fn find(&self, key: &str) -> Option<u32> {
        self.by_key.get(key).copied()
    }

    pub fn add(&mut self, key: Option<String>, formula: SharedFormula) -> u32 {
        let id = self.formulas.len() as u32;
        self.formulas.push(formula);
        if let Some(k) = key {
            self.by_key.insert(k, id);
        }
        id
    }

    /// Forgets the keys (after a sheet is added, `Missing` sheet references may resolve now).
    pub fn forget_keys(&mut self) {
        self.by_key.clear();
    }
}

/// The relative key of a formula typed in cell `at`, or `None` when the text has a form the
/// scan does not understand (whole rows/columns, unusual tokens): such text is parsed each time.
pub fn relative_key(text: &str, at: Pos) -> Option<String> {
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len() + 16);
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        match c {
            b'"' | b'\'' => {
                let end = quoted_end(b, i)?;
                out.push_str(&text[i..end]);
                i = end;
            }
            b'0'..=b'9' | b'.' => {
                let end = number_end(b, i);
                if next_non_space(b, end) == Some(b':') {
                    return None;
                }
                out.push_str(&text[i..end]);
                i = end;
            }
            b'$' | b'A'..=b'Z' | b'a'..=b'z' | b'_' | b'\\' => {
                let end = word_end(b, i);
                let word = &text[i..end];
                let next = next_non_space(b, end);
                match cell_offsets(word, at) {
                    Some((row, col)) if !matches!(next, Some(b'(') | Some(b'!')) => {
                        let _ = write!(out, "\u{1}{row}\u{1}{col}\u{1}");
                    }
                    _ if next == Some(b':') && !word.bytes().any(|c| c.is_ascii_digit()) => return None,
                    _ if word.contains('$') => return None,
                    _ => out.push_str(word),
                }
                i = end;
            }
            _ if c >= 0x80 => {
                let ch = text[i..].chars().next()?;
                out.push(ch);
                i += ch.len_utf8();
            }
            _ => {
                out.push(c as char);
                i += 1;
            }
        }
    }
    Some(out)
}

fn quoted_end(b: &[u8], start: usize) -> Option<usize> {
    let q = b[start];
    let mut i = start + 1;
    while i < b.len() {
        if b[i] == q {
            if b.get(i + 1) == Some(&q) {
                i += 2;
                continue;
            }
            return Some(i + 1);
        }
        i += 1;
    }
    None
}

fn number_end(b: &[u8], start: usize) -> usize {
    let mut i = start;
    while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
        i += 1;
    }
    if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
        let mut j = i + 1;
        if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
            j += 1;
        }
        if j < b.len() && b[j].is_ascii_digit() {
            while j < b.len() && b[j].is_ascii_digit() {
                j += 1;
            }
            return j;
        }
    }
    i
}

fn word_end(b: &[u8], start: usize) -> usize {
    let mut i = start;
    while i < b.len() && (b[i].is_ascii_alphanumeric() || matches!(b[i], b'$' | b'_' | b'.' | b'\\')) {
        i += 1;
    }
    i
}

fn next_non_space(b: &[u8], from: usize) -> Option<u8> {
    b[from..].iter().copied().find(|c| !c.is_ascii_whitespace())
}

/// `B3` at C5 gives row offset "-2" and column offset "-1"; `$B$3` gives "$2" and "$1".
fn cell_offsets(word: &str, at: Pos) -> Option<(String, String)> {
    let (col_abs, rest) = match word.strip_prefix('$') {
        Some(r) => (true, r),
        None => (false, word),
    };
    let letters_end = rest.find(|c: char| !c.is_ascii_alphabetic())?;
    let (letters, rest) = rest.split_at(letters_end);
    let (row_abs, digits) = match rest.strip_prefix('$') {
        Some(r) => (true, r),
        None => (false, rest),
    };
    if digits.is_empty() || !digits.bytes().all(|c| c.is_ascii_digit()) {
        return None;
    }
    let col = column_index(letters)?;
    let row: u32 = digits.parse().ok()?;
    if !(1..=MAX_ROWS).contains(&row) {
        return None;
    }
    let row = row - 1;
    let fmt = |abs: bool, v: u32, base: u32| if abs { format!("${v}") } else { format!("{}", v as i64 - base as i64) };
    Some((fmt(row_abs, row, at.row), fmt(col_abs, col, at.col)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn copies_down_a_column_share_a_key() {
        let a = relative_key("=SIN(A1*PI()/180)+COS(A1)", Pos::new(0, 1));
        let b = relative_key("=SIN(A2*PI()/180)+COS(A2)", Pos::new(1, 1));
        assert_eq!(a, b);
        assert!(a.is_some());
    }

    #[test]
    fn different_formulas_never_share_a_key() {
        let at = Pos::new(4, 4);
        let below = Pos::new(5, 4);
        // Function names that look like cells stay as typed.
        assert_ne!(relative_key("=LOG10(2)", at), relative_key("=LOG11(2)", below));
        // Absolute references do not move.
        assert_ne!(relative_key("=$A$1", at), relative_key("=$A$2", below));
        assert_eq!(relative_key("=$A$1", at), relative_key("=$A$1", below));
        // Strings are copied verbatim.
        assert_ne!(relative_key("=\"A1\"", at), relative_key("=\"A2\"", below));
        // Whole rows and columns are position-dependent in a way the scan does not model.
        assert_eq!(relative_key("=SUM(1:1)", at), None);
        assert_eq!(relative_key("=SUM(A:A)", at), None);
        assert_eq!(relative_key("=SUM($1:2)", at), None);
        // Sheet names followed by ! are not cells.
        assert_ne!(relative_key("=AB1!A1", at), relative_key("=AB2!A2", below));
    }
}
