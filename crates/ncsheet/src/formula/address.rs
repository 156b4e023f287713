//! A1-style addresses: column letters, cell and range text as a user types them.

use std::fmt;

/// Excel's sheet size.
pub const MAX_ROWS: u32 = 1_048_576;
pub const MAX_COLS: u32 = 16_384;

/// A cell position, 0-based.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Pos {
    pub row: u32,
    pub col: u32,
}

impl Pos {
    pub fn new(row: u32, col: u32) -> Pos {
        Pos { row, col }
    }
}

impl fmt::Display for Pos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}{}", column_name(self.col), self.row + 1)
    }
}

/// A rectangle of cells, corners inclusive and ordered (`first <= last`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Rect {
    pub first: Pos,
    pub last: Pos,
}

impl Rect {
    pub fn new(a: Pos, b: Pos) -> Rect {
        Rect { first: Pos::new(a.row.min(b.row), a.col.min(b.col)), last: Pos::new(a.row.max(b.row), a.col.max(b.col)) }
    }

    pub fn cell(p: Pos) -> Rect {
        Rect { first: p, last: p }
    }

    pub fn rows(&self) -> u32 {
        self.last.row - self.first.row + 1
    }

    pub fn cols(&self) -> u32 {
        self.last.col - self.first.col + 1
    }

    pub fn contains(&self, p: Pos) -> bool {
        (self.first.row..=self.last.row).contains(&p.row) && (self.first.col..=self.last.col).contains(&p.col)
    }

    pub fn is_cell(&self) -> bool {
        self.first == self.last
    }
}

impl fmt::Display for Rect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_cell() {
            write!(f, "{}", self.first)
        } else {
            write!(f, "{}:{}", self.first, self.last)
        }
    }
}

/// `0 -> "A"`, `25 -> "Z"`, `26 -> "AA"`.
pub fn column_name(col: u32) -> String {
    // Counted in u64: the bijective base-26 number is col + 1, which is past u32 for the
    // last u32 (a file's index is read as it stands, whatever it holds).
    let mut n = u64::from(col) + 1;
    let mut out = Vec::new();
    while n > 0 {
        let rem = (n - 1) % 26;
        out.push(b'A' + rem as u8);
        n = (n - 1) / 26;
    }
    out.reverse();
    String::from_utf8(out).expect("ASCII letters")
}

/// `"A" -> 0`, `"aa" -> 26`; `None` past column XFD or for non-letters.
pub fn column_index(letters: &str) -> Option<u32> {
    if letters.is_empty() || letters.len() > 3 {
        return None;
    }
    let mut n: u32 = 0;
    for b in letters.bytes() {
        if !b.is_ascii_alphabetic() {
            return None;
        }
        n = n * 26 + (b.to_ascii_uppercase() - b'A' + 1) as u32;
    }
    (n <= MAX_COLS).then(|| n - 1)
}

/// Parses `B3` or `$B$3` into a position on the sheet.
pub fn parse_cell(text: &str) -> Option<Pos> {
    let t = text.trim().replace('$', "");
    let split = t.find(|c: char| c.is_ascii_digit())?;
    let (letters, digits) = t.split_at(split);
    let col = column_index(letters)?;
    let row: u32 = digits.parse().ok()?;
    (1..=MAX_ROWS).contains(&row).then(|| Pos::new(row - 1, col))
}

/// Parses `A1:C10` or a single cell `B3` into a rectangle.
pub fn parse_rect(text: &str) -> Option<Rect> {
    match text.split_once(':') {
        Some((a, b)) => Some(Rect::new(parse_cell(a)?, parse_cell(b)?)),
        None => parse_cell(text).map(Rect::cell),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn column_names_round_trip_at_excel_boundaries() {
        for (i, s) in [(0, "A"), (25, "Z"), (26, "AA"), (701, "ZZ"), (702, "AAA"), (16383, "XFD")] {
            assert_eq!(column_name(i), s);
            assert_eq!(column_index(s), Some(i));
        }
        assert_eq!(column_index("XFE"), None);
    }

    #[test]
    fn column_names_are_total_up_to_the_last_u32() {
        // Bijective base 26 of 2^32, worked in Python apart from this code:
        // n = 2**32; s = ''; while n: n -= 1; s = chr(65 + n % 26) + s; n //= 26
        assert_eq!(column_name(u32::MAX), "MWLQKWV");
        assert_eq!(column_name(u32::MAX - 1), "MWLQKWU");
    }

    #[test]
    fn cells_parse_with_and_without_dollars() {
        assert_eq!(parse_cell("$B$3"), Some(Pos::new(2, 1)));
        assert_eq!(parse_cell("b3"), Some(Pos::new(2, 1)));
        assert_eq!(parse_cell("A0"), None);
        assert_eq!(parse_cell("A1048577"), None);
        assert_eq!(parse_rect("C10:A1").unwrap().to_string(), "A1:C10");
    }
}
