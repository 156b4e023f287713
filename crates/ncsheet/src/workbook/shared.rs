//! Shared formulas: a formula copied down a column is parsed once and every copy points at
//! the one tree, as Excel's shared formulas do.
//!
//! A cheap scan turns the formula text into a key in which each cell reference is written
//! as an offset from the formula's cell (R1C1 style). Texts with equal keys parse to equal
//! trees (references are stored as offsets), so the parse is skipped for every copy.
//!
//! Formulas that differ only in their numbers (`=$A$1*2+1`, `=$A$1*3+1`) share a "shape":
//! the key with each number literal left out. A formula whose shape is known shares that
//! tree too, with its own numbers beside it (the evaluator reads them in place of the
//! tree's literals), without parsing.

use std::rc::Rc;

use crate::eval::functions;
use crate::eval::functions::Searched;
use crate::formula::address::{Pos, MAX_COLS, MAX_ROWS};
use crate::formula::ast::{ArrayLit, Expr, ExprKind, Reference, SheetId, SheetRef, TableRef};
use crate::formula::parse::ParseError;

use super::graph::FxMap;

/// One parsed formula and what the dependency graph needs of it.
pub struct SharedFormula {
    pub expr: Rc<Expr>,
    /// The references in the tree with the part of each that is read whatever the cell
    /// computes, so edges are found without walking it again.
    pub refs: Rc<[(Reference, Part)]>,
    /// Uses a defined name (its references are looked up when edges are built), as seen from
    /// the given sheet (`None`: the formula's own).
    pub names: Rc<[(Rc<str>, Option<SheetId>)]>,
    /// The structured references in the tree (`Parts[Qty]`), whose cells are looked up in
    /// the workbook's tables when edges are built.
    pub tables: Rc<[Rc<TableRef>]>,
    /// This formula's numbers where they differ from the shared tree's: each number literal
    /// of `expr` (by address) with the value to read instead (see `Ctx::numbers`).
    pub numbers: Box<[(*const Expr, f64)]>,
    /// Calls a function recomputed at every edit (`FnSpec::every_edit`: NOW, INDIRECT).
    pub volatile: bool,
}

/// How much of a reference a formula cell reads whatever it computes: its graph edge.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Part {
    Whole,
    /// VLOOKUP's table: the column searched (the cell returned is linked at run time).
    FirstColumn,
    /// HLOOKUP's table: the row searched.
    FirstRow,
}

/// The reference nodes of `expr` read only in part, each with the part that is an edge
/// (`None`: no edge).
fn partly_read_refs(expr: &Expr) -> Vec<(*const Expr, Option<Part>)> {
    let mut out = Vec::new();
    expr.visit(&mut |e| {
        if let ExprKind::Call(id, args) = &e.kind {
            let spec = functions::spec(*id);
            let written_as_ref = |i: usize| args.get(i).filter(|a| matches!(a.kind, ExprKind::Ref(_)));
            // Read for where it is, not for what it holds (FnSpec::position_arg): an edge
            // from the whole reference made `B3 = INDEX(B:B,ROW()-1)+A3` a cycle through
            // every cell of column B, and `=ROW(A1:A3)` in A1 a reader of its own spill.
            if let Some(first) = written_as_ref(0).filter(|_| spec.position_arg) {
                out.push((first as *const Expr, None));
            }
            // Read where searched and where picked (FnSpec::picked_arg): an edge from the
            // whole return column made `C3 = XLOOKUP(A3-1,A:A,C:C)+B3` filled down a cycle.
            if let Some(picked) = spec.picked_arg {
                if let Some(arg) = written_as_ref(picked.arg as usize) {
                    let part = match picked.searched {
                        Searched::Nothing => None,
                        Searched::FirstColumn => Some(Part::FirstColumn),
                        Searched::FirstRow => Some(Part::FirstRow),
                    };
                    out.push((arg as *const Expr, part));
                }
            }
        }
    });
    out
}

impl SharedFormula {
    pub fn new(expr: Expr) -> SharedFormula {
        let mut refs = Vec::new();
        let mut names = Vec::new();
        let mut tables: Vec<Rc<TableRef>> = Vec::new();
        let mut volatile = false;
        let partly = partly_read_refs(&expr);
        let part_of = |e: &Expr| partly.iter().find(|(p, _)| std::ptr::eq(*p, e)).map_or(Some(Part::Whole), |p| p.1);
        expr.visit(&mut |e| match &e.kind {
            crate::formula::ast::ExprKind::Ref(r) => {
                // A reference read twice (`IF(C1>1,C1-1,C1+1)`) is one edge of the graph.
                if let Some(part) = part_of(e).filter(|&part| !refs.contains(&(r.clone(), part))) {
                    refs.push((r.clone(), part));
                }
            }
            crate::formula::ast::ExprKind::Name(n) => names.push((n.clone(), None)),
            // `bump(1, 2)`: a named LAMBDA, whose cells are read as a name's are.
            ExprKind::UnknownCall(n, _) => names.push((n.clone(), None)),
            // `Sheet2!Rate`: the name as Sheet2 sees it (a missing sheet reads nothing).
            ExprKind::SheetName(SheetRef::Id(sheet), n) => names.push((n.clone(), Some(*sheet))),
            ExprKind::Table(r) if !tables.contains(r) => tables.push(r.clone()),
            ExprKind::Call(id, _) => volatile |= functions::spec(*id).every_edit,
            _ => {}
        });
        let (refs, names, tables) = (refs.into(), names.into(), tables.into());
        SharedFormula { expr: Rc::new(expr), refs, names, tables, numbers: Box::new([]), volatile }
    }

    /// `pattern`'s formula with `literals` for its numbers, in the order [`Expr::visit`]
    /// meets them (the caller checked that the pattern has as many).
    pub fn with_literals(pattern: &SharedFormula, literals: &[f64]) -> SharedFormula {
        let mut nodes = Vec::with_capacity(literals.len());
        pattern.expr.visit(&mut |e| {
            if let ExprKind::Number(_) = e.kind {
                nodes.push(e as *const Expr);
            }
        });
        debug_assert_eq!(nodes.len(), literals.len());
        SharedFormula {
            expr: pattern.expr.clone(),
            refs: pattern.refs.clone(),
            names: pattern.names.clone(),
            tables: pattern.tables.clone(),
            numbers: nodes.into_iter().zip(literals.iter().copied()).collect(),
            volatile: pattern.volatile,
        }
    }

    /// The tree with this formula's own numbers in it (for printing).
    pub fn own_tree(&self) -> Expr {
        let mut numbers = self.numbers.iter().map(|&(_, v)| v);
        with_numbers(&self.expr, &mut numbers)
    }
}

/// Parsed formulas, deduplicated by their relative key.
#[derive(Default)]
pub struct FormulaStore {
    pub formulas: Vec<SharedFormula>,
    by_key: FxMap<Vec<u8>, u32>,
    /// Formulas by shape (see the module doc), for copying with other numbers.
    by_shape: FxMap<Vec<u8>, u32>,
    /// Keys whose text does not parse, with the error at its place in the key: 100,000 copies
    /// of one shared formula that fails would each be parsed again (a millisecond each).
    failed: FxMap<Vec<u8>, ParseError>,
}

impl FormulaStore {
    pub fn get(&self, id: u32) -> &SharedFormula {
        &self.formulas[id as usize]
    }

    /// The id of an already parsed formula with this key.
    pub fn find(&self, key: &[u8]) -> Option<u32> {
        self.by_key.get(key).copied()
    }

    pub fn add(&mut self, key: Option<Vec<u8>>, formula: SharedFormula) -> u32 {
        let id = self.formulas.len() as u32;
        self.formulas.push(formula);
        if let Some(k) = key {
            self.by_key.insert(k, id);
        }
        id
    }

    /// Puts each formula in its slot in place of the one there, which no cell runs any more,
    /// and forgets the keys and shapes that named the old ones: a shift that rewrites every
    /// copy of a formula alike reuses its slot, so the store does not grow with each edit.
    pub fn replace(&mut self, slots: Vec<(u32, SharedFormula)>) {
        if slots.is_empty() {
            return;
        }
        let mut ids: Vec<u32> = slots.iter().map(|&(id, _)| id).collect();
        ids.sort_unstable();
        for (id, formula) in slots {
            self.formulas[id as usize] = formula;
        }
        self.by_key.retain(|_, id| ids.binary_search(id).is_err());
        self.by_shape.retain(|_, id| ids.binary_search(id).is_err());
    }

    /// Why the text of this key does not parse, the offset a place in the key.
    pub fn failure(&self, key: &[u8]) -> Option<&ParseError> {
        self.failed.get(key)
    }

    /// Notes that the text of `key` does not parse (`error.offset` a place in the key).
    pub fn add_failure(&mut self, key: &[u8], error: ParseError) {
        self.failed.insert(key.to_vec(), error);
    }

    /// Forgets the keys (after a sheet is added, `Missing` sheet references may resolve now).
    pub fn forget_keys(&mut self) {
        if !self.failed.is_empty() {
            self.failed.clear();
        }
        // Clearing costs the maps' capacity even when empty: sheets added one after another
        // (100,000 of them in a file) must not pay it each time.
        if !self.by_key.is_empty() {
            self.by_key.clear();
        }
        if !self.by_shape.is_empty() {
            self.by_shape.clear();
        }
    }

    /// A formula with this shape, to copy with other numbers.
    pub fn find_shape(&self, shape: &[u8]) -> Option<u32> {
        self.by_shape.get(shape).copied()
    }

    /// Offers formula `id` as the pattern for its shape: taken when its tree's numbers, in
    /// order, are the literals of its text (then every text of that shape parses to the
    /// same tree but for those numbers), and when no function reads part of it as a tree.
    pub fn add_shape(&mut self, shape: &[u8], id: u32, literals: &[f64]) {
        let mut numbers = Vec::with_capacity(literals.len());
        let mut read_as_tree = false;
        self.formulas[id as usize].expr.visit(&mut |e| match e.kind {
            ExprKind::Number(n) => numbers.push(n),
            ExprKind::Call(f, _) if functions::spec(f).reads_trees => read_as_tree = true,
            _ => {}
        });
        let same =
            numbers.len() == literals.len() && numbers.iter().zip(literals).all(|(a, b)| a.to_bits() == b.to_bits());
        if same && !read_as_tree {
            self.by_shape.insert(shape.to_vec(), id);
        }
    }
}

/// The shape of a relative key and the values of its number literals, from the literal
/// spans [`relative_key_into`] recorded; `None` when a literal is not a plain finite number.
pub fn shape_of(key: &[u8], spans: &[(usize, usize)], shape: &mut Vec<u8>, literals: &mut Vec<f64>) -> bool {
    shape.clear();
    literals.clear();
    let mut last = 0;
    for &(start, end) in spans {
        match std::str::from_utf8(&key[start..end]).map(str::parse::<f64>) {
            Ok(Ok(v)) if v.is_finite() => literals.push(v),
            _ => return false,
        }
        shape.extend_from_slice(&key[last..start]);
        shape.push(2);
        last = end;
    }
    shape.extend_from_slice(&key[last..]);
    true
}

/// A copy of `e` with its numbers, in the order [`Expr::visit`] meets them, taken from `numbers`.
fn with_numbers(e: &Expr, numbers: &mut dyn Iterator<Item = f64>) -> Expr {
    let kind = match &e.kind {
        ExprKind::Number(n) => ExprKind::Number(numbers.next().unwrap_or(*n)),
        ExprKind::Paren(a) => ExprKind::Paren(Box::new(with_numbers(a, numbers))),
        ExprKind::Unary(op, a) => ExprKind::Unary(*op, Box::new(with_numbers(a, numbers))),
        ExprKind::Binary(op, a, b) => {
            let a = with_numbers(a, numbers);
            ExprKind::Binary(*op, Box::new(a), Box::new(with_numbers(b, numbers)))
        }
        ExprKind::Call(id, args) => ExprKind::Call(*id, args.iter().map(|a| with_numbers(a, numbers)).collect()),
        ExprKind::UnknownCall(name, args) => {
            ExprKind::UnknownCall(name.clone(), args.iter().map(|a| with_numbers(a, numbers)).collect())
        }
        ExprKind::Invoke(callee, args) => {
            let callee = Box::new(with_numbers(callee, numbers));
            ExprKind::Invoke(callee, args.iter().map(|a| with_numbers(a, numbers)).collect())
        }
        ExprKind::Array(lit) => ExprKind::Array(Rc::new(ArrayLit {
            rows: lit.rows,
            cols: lit.cols,
            items: lit.items.iter().map(|a| with_numbers(a, numbers)).collect(),
        })),
        other => other.clone(),
    };
    Expr::new(kind, e.span)
}

/// The relative key of a formula typed in cell `at`, or `None` when the text has a form the
/// scan does not understand (whole rows/columns, unusual tokens): such text is parsed each time.
#[cfg(test)]
pub fn relative_key(text: &str, at: Pos) -> Option<String> {
    let mut out = Vec::new();
    relative_key_into(text, at, &mut out, &mut Vec::new()).then(|| String::from_utf8(out).expect("a key is text"))
}

/// How the scan treats a byte of formula text.
#[derive(Clone, Copy, PartialEq)]
enum Class {
    /// Operators, parentheses, commas, spaces: copied as they are.
    Plain,
    /// `"` or `'`: a string or a quoted sheet name, copied to its closing quote.
    Quote,
    /// A digit or `.`: a number literal.
    Number,
    /// A letter, `$`, `_` or `\`: the start of a cell address, a function or a name.
    Word,
    /// `[`: a structured reference's items (`Parts[Qty]`), copied whole to the closing `]`.
    Bracket,
    /// Part of a character past ASCII: copied.
    Wide,
}

/// Each byte's class, looked up once per byte: this scan runs on every formula a file holds.
const CLASSES: [Class; 256] = {
    let mut table = [Class::Plain; 256];
    let mut c = 0;
    while c < 256 {
        let b = c as u8;
        table[c] = match b {
            b'"' | b'\'' => Class::Quote,
            b'[' => Class::Bracket,
            b'0'..=b'9' | b'.' => Class::Number,
            b'$' | b'A'..=b'Z' | b'a'..=b'z' | b'_' | b'\\' => Class::Word,
            0x80..=0xff => Class::Wide,
            _ => Class::Plain,
        };
        c += 1;
    }
    table
};

/// Whether a byte continues a word (an address, a function's or a name's text).
const IN_WORD: [bool; 256] = {
    let mut table = [false; 256];
    let mut c = 0;
    while c < 256 {
        let b = c as u8;
        table[c] = b.is_ascii_alphanumeric() || matches!(b, b'$' | b'_' | b'.' | b'\\');
        c += 1;
    }
    table
};

/// [`relative_key`] written into `out` (cleared first), so that a caller can reuse one buffer
/// for every cell of a workbook; `false` where `relative_key` gives `None`. `literals`
/// receives where in `out` each number literal is. The key is the text's bytes with each
/// cell address replaced, so it is UTF-8 whenever the text is.
pub fn relative_key_into(text: &str, at: Pos, out: &mut Vec<u8>, literals: &mut Vec<(usize, usize)>) -> bool {
    scan_key(text, at, out, literals, &mut |_, _| {})
}

/// One piece of a formula's text and what its relative key holds for it: a cell address is
/// rewritten, anything else copied byte for byte.
#[derive(Clone, Copy)]
struct Piece {
    text: (usize, usize),
    key: (usize, usize),
}

impl Piece {
    /// `offset` (inside `from`) moved to the same place of `to`: the same byte of a piece
    /// copied as it is, the start of a rewritten address.
    fn moved(offset: usize, from: (usize, usize), to: (usize, usize)) -> usize {
        let copied = from.1 - from.0 == to.1 - to.0;
        to.0 + if copied { offset - from.0 } else { 0 }
    }
}

/// The pieces of `text`'s relative key, in order; `None` when the text has no key.
fn pieces(text: &str, at: Pos) -> Option<Vec<Piece>> {
    let mut pieces = Vec::new();
    let mut last = (0, 0);
    let mut mark = |t: usize, k: usize| {
        if (t, k) != last {
            pieces.push(Piece { text: (last.0, t), key: (last.1, k) });
        }
        last = (t, k);
    };
    let mut out = Vec::new();
    if !scan_key(text, at, &mut out, &mut Vec::new(), &mut mark) {
        return None;
    }
    mark(text.len(), out.len());
    Some(pieces)
}

/// Where byte `offset` of `text` (typed at `at`) falls in its relative key: a parse error's
/// place kept with the key, so that every text of that key gets it at its own place.
pub fn key_offset(text: &str, at: Pos, offset: usize) -> usize {
    let pieces = pieces(text, at).unwrap_or_default();
    match pieces.iter().find(|p| offset < p.text.1) {
        Some(p) => Piece::moved(offset, p.text, p.key),
        None => pieces.last().map_or(offset, |p| p.key.1),
    }
}

/// The byte of `text` (typed at `at`) at `offset` of its relative key ([`key_offset`] back).
pub fn text_offset(text: &str, at: Pos, offset: usize) -> usize {
    let pieces = pieces(text, at).unwrap_or_default();
    match pieces.iter().find(|p| offset < p.key.1) {
        Some(p) => Piece::moved(offset, p.key, p.text),
        None => text.len(),
    }
}

/// The scan of [`relative_key_into`], telling `mark` where each piece of the text starts in
/// the text and in the key.
fn scan_key(
    text: &str,
    at: Pos,
    out: &mut Vec<u8>,
    literals: &mut Vec<(usize, usize)>,
    mark: &mut impl FnMut(usize, usize),
) -> bool {
    out.clear();
    literals.clear();
    // Offsets are seldom longer than the addresses they replace: one reserve serves the scan.
    out.reserve(text.len() + 16);
    let b = text.as_bytes();
    let mut i = 0;
    while i < b.len() {
        mark(i, out.len());
        let class = CLASSES[b[i] as usize];
        let end = match class {
            Class::Plain | Class::Wide => run_end(b, i, class),
            Class::Quote => match quoted_end(b, i) {
                Some(end) => end,
                None => return false,
            },
            Class::Number => {
                let end = number_end(b, i);
                if next_non_space(b, end) == Some(b':') {
                    return false;
                }
                literals.push((out.len(), out.len() + end - i));
                end
            }
            // `T[A1]` names column A1 of table T, not a cell. Without a table's name before it
            // (`[@Qty]`) the table is the one holding the formula's cell, which no key holds.
            Class::Bracket => match bracket_end(b, i) {
                Some(end) if out.last().is_some_and(|&c| IN_WORD[c as usize]) => end,
                _ => return false,
            },
            Class::Word => match push_word(b, i, at, out) {
                Some(end) => {
                    i = end;
                    continue;
                }
                None => return false,
            },
        };
        append(out, &b[i..end]);
        i = end;
    }
    true
}

/// Appends a piece of formula text byte by byte: the pieces are a few bytes long, for which
/// a `memcpy` call costs more than the copy.
fn append(out: &mut Vec<u8>, bytes: &[u8]) {
    for &c in bytes {
        out.push(c);
    }
}

/// The end of the run of bytes of `class` from `start`. A run of bytes past ASCII ends where
/// an ASCII byte starts, so it holds whole characters.
fn run_end(b: &[u8], start: usize, class: Class) -> usize {
    b[start..].iter().position(|&c| CLASSES[c as usize] != class).map_or(b.len(), |n| start + n)
}

/// Appends the word at `start` (a cell address as its offsets from `at`, anything else as
/// typed) and returns where it ends; `None` for a form the key cannot hold.
fn push_word(b: &[u8], start: usize, at: Pos, out: &mut Vec<u8>) -> Option<usize> {
    let end = b[start..].iter().position(|&c| !IN_WORD[c as usize]).map_or(b.len(), |n| start + n);
    let word = &b[start..end];
    let next = next_non_space(b, end);
    // A word right before `[` is a table's name, whatever it looks like.
    let table = b.get(end) == Some(&b'[');
    match cell_address(word) {
        Some(cell) if !matches!(next, Some(b'(') | Some(b'!')) && !table => {
            out.push(1);
            push_coord(out, cell.row_abs, cell.row, at.row);
            out.push(1);
            push_coord(out, cell.col_abs, cell.col, at.col);
            out.push(1);
        }
        // A whole column (`A:A`) or a row span with `$`: its meaning depends on the position
        // in a way the key does not model.
        _ if next == Some(b':') && !word.iter().any(u8::is_ascii_digit) => return None,
        _ if word.contains(&b'$') => return None,
        _ => append(out, word),
    }
    Some(end)
}

/// The end of the structured reference's items opening at `start` (past its closing `]`):
/// brackets nest, and `'` escapes the character after it (`[Col'[1']]`).
fn bracket_end(b: &[u8], start: usize) -> Option<usize> {
    let mut depth = 0;
    let mut i = start;
    while i < b.len() {
        match b[i] {
            b'\'' => i += 1,
            b'[' => depth += 1,
            b']' => {
                depth -= 1;
                if depth == 0 {
                    return Some(i + 1);
                }
            }
            _ => {}
        }
        i += 1;
    }
    None
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

fn next_non_space(b: &[u8], from: usize) -> Option<u8> {
    b[from..].iter().copied().find(|c| !c.is_ascii_whitespace())
}

/// A cell address as typed: 0-based indexes and which parts carry a `$`.
struct CellAddress {
    row: u32,
    col: u32,
    row_abs: bool,
    col_abs: bool,
}

/// `B3`, `$B$3`, `b3`: the address, or `None` for a word that is not one cell on the sheet.
fn cell_address(word: &[u8]) -> Option<CellAddress> {
    let col_abs = word.first() == Some(&b'$');
    let mut i = usize::from(col_abs);
    let mut col: u32 = 0;
    let letters_start = i;
    while i < word.len() && word[i].is_ascii_alphabetic() {
        if i - letters_start == 3 {
            return None;
        }
        col = col * 26 + (word[i].to_ascii_uppercase() - b'A' + 1) as u32;
        i += 1;
    }
    if i == letters_start || col > MAX_COLS {
        return None;
    }
    let row_abs = word.get(i) == Some(&b'$');
    i += usize::from(row_abs);
    let digits = &word[i..];
    if digits.is_empty() {
        return None;
    }
    let mut row: u64 = 0;
    for &d in digits {
        if !d.is_ascii_digit() {
            return None;
        }
        row = (row * 10 + (d - b'0') as u64).min(u64::from(u32::MAX) + 1);
    }
    if !(1..=MAX_ROWS as u64).contains(&row) {
        return None;
    }
    Some(CellAddress { row: row as u32 - 1, col: col - 1, row_abs, col_abs })
}

/// `B3` at C5 gives row offset "-2" and column offset "-1"; `$B$3` gives "$2" and "$1".
fn push_coord(out: &mut Vec<u8>, absolute: bool, v: u32, base: u32) {
    if absolute {
        out.push(b'$');
        push_int(out, v as i64);
    } else {
        push_int(out, v as i64 - base as i64);
    }
}

/// Appends `n` in decimal (`write!` costs more than the rest of the scan).
fn push_int(out: &mut Vec<u8>, n: i64) {
    if (0..10).contains(&n) {
        out.push(b'0' + n as u8);
        return;
    }
    if n < 0 {
        out.push(b'-');
    }
    let mut m = n.unsigned_abs();
    let mut buf = [0u8; 20];
    let mut i = buf.len();
    loop {
        i -= 1;
        buf[i] = b'0' + (m % 10) as u8;
        m /= 10;
        if m == 0 {
            break;
        }
    }
    append(out, &buf[i..]);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_place_in_one_copy_is_found_in_another_of_other_lengths() {
        // `=B9+1+)` typed in row 9 and `=B10+1+)` in row 10 share a key; the `)` is byte 6 of
        // the first text and byte 7 of the second; the `B` of the address byte 1 of both.
        let (a, b) = ("=B9+1+)", "=B10+1+)");
        let (at_a, at_b) = (Pos::new(8, 0), Pos::new(9, 0));
        assert_eq!(relative_key(a, at_a), relative_key(b, at_b));
        assert_eq!(text_offset(b, at_b, key_offset(a, at_a, 6)), 7);
        assert_eq!(text_offset(b, at_b, key_offset(a, at_a, 1)), 1);
        assert_eq!(text_offset(b, at_b, key_offset(a, at_a, a.len())), b.len());
        assert_eq!(text_offset(a, at_a, key_offset(b, at_b, 5)), 4);
    }

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
        // Not cells: too many letters, row 0, past the last row or column, stray characters.
        for word in ["ABCD1", "A0", "A1048577", "XFE1", "A1.5", "A_1", "$$A1", "A$$1", "$1", "A", "A99999999999"] {
            assert!(cell_address(word.as_bytes()).is_none(), "{word}");
        }
        let c = cell_address(b"$xfd$1048576").unwrap();
        assert_eq!((c.row, c.col, c.row_abs, c.col_abs), (MAX_ROWS - 1, MAX_COLS - 1, true, true));
        let c = cell_address(b"b0003").unwrap();
        assert_eq!((c.row, c.col, c.row_abs, c.col_abs), (2, 1, false, false));
        // Sheet names followed by ! are not cells.
        assert_ne!(relative_key("=AB1!A1", at), relative_key("=AB2!A2", below));
    }

    #[test]
    fn a_structured_reference_is_kept_whole_in_the_key() {
        let (at, below) = (Pos::new(0, 0), Pos::new(1, 0));
        // Columns named A1 and A2 of table T are two columns, not one cell moved along.
        assert_ne!(relative_key("=T[A1]", at), relative_key("=T[A2]", below));
        // A number in a column's name is no literal another copy may change.
        assert_eq!(relative_key("=T[[Col 2]]+1", at).as_deref(), Some("=T[[Col 2]]+1"));
        // `'` escapes a bracket in a name; a table's name like a cell's is a name.
        assert_eq!(relative_key("=T1[Col'[1']]", at).as_deref(), Some("=T1[Col'[1']]"));
        // Without its table's name the reference reads the table of its cell: no key.
        assert_eq!(relative_key("=[@Qty]*2", at), None);
        assert_eq!(relative_key("=SUM([Qty])", at), None);
    }
}
