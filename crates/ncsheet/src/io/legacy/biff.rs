//! BIFF8 formulas (MS-XLS 2.5.198, `Rgce`): the tokens a `.xls` file stores, in reverse Polish
//! order, turned into formula text as an xlsx file spells it. Operators are written with the
//! parentheses their precedence needs (a file need not hold a `PtgParen` for each), references
//! keep their `$`, a reference over all 65,536 rows of BIFF8 is a whole column (as Excel opens
//! it) and one over all 256 columns a whole row.

use std::fmt::Write as _;

use super::quoted_sheet;

/// What a formula's references and names point at, from the workbook's globals.
pub struct Context<'a> {
    /// Every sheet of the workbook in file order (`BoundSheet8`), charts and macros included.
    pub sheets: &'a [String],
    /// `ExternSheet`'s entries: (index into `books`, first sheet, last sheet).
    pub xtis: &'a [(u16, i16, i16)],
    pub books: &'a [SupBook],
    /// Every `Lbl` (defined name) in file order: its name and the sheet index it belongs to.
    pub names: &'a [(String, Option<usize>)],
}

/// A `SupBook`: this workbook, the add-in functions, or another workbook, with its
/// `ExternName`s.
#[derive(Debug, Clone)]
pub enum SupBook {
    Own,
    AddIns(Vec<String>),
    Other(Vec<String>),
}

/// Why a formula could not be carried over: its cached value is kept instead.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Unreadable {
    /// `PtgTbl`: a cell of a what-if data table.
    DataTable,
    /// A reference or name in another workbook.
    OtherWorkbook,
    /// A token or function this reader does not know, or a damaged formula.
    Token(String),
}

impl std::fmt::Display for Unreadable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Unreadable::DataTable => f.write_str("cells of a what-if data table (TABLE)"),
            Unreadable::OtherWorkbook => f.write_str("formulas reading another workbook"),
            Unreadable::Token(what) => write!(f, "formulas with {what}"),
        }
    }
}

/// Precedence of what an item on the stack is (higher binds tighter); operands are atoms.
const COMPARE: u8 = 1;
const CONCAT: u8 = 2;
const ADD: u8 = 3;
const MULTIPLY: u8 = 4;
const POWER: u8 = 5;
const PERCENT: u8 = 6;
const UNARY: u8 = 7;
const INTERSECT: u8 = 9;
const RANGE: u8 = 10;
const ATOM: u8 = 11;

struct Item {
    text: String,
    precedence: u8,
}

fn atom(text: String) -> Item {
    Item { text, precedence: ATOM }
}

/// The last row and column BIFF8 has: a reference spanning all of them is a whole column
/// or row.
const LAST_ROW: u32 = 0xFFFF;
const LAST_COL: u32 = 0xFF;

/// A reader over the formula's bytes.
struct Bytes<'a> {
    data: &'a [u8],
    at: usize,
}

impl<'a> Bytes<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], Unreadable> {
        let slice = self.data.get(self.at..self.at + n).ok_or_else(damaged)?;
        self.at += n;
        Ok(slice)
    }
    fn u8(&mut self) -> Result<u8, Unreadable> {
        Ok(self.take(1)?[0])
    }
    fn u16(&mut self) -> Result<u16, Unreadable> {
        let b = self.take(2)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }
    fn u32(&mut self) -> Result<u32, Unreadable> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn f64(&mut self) -> Result<f64, Unreadable> {
        let b = self.take(8)?;
        Ok(f64::from_le_bytes(b.try_into().expect("8 bytes")))
    }
    fn done(&self) -> bool {
        self.at >= self.data.len()
    }
}

fn damaged() -> Unreadable {
    Unreadable::Token("a damaged formula".into())
}

/// A string of BIFF8 (`XLUnicodeStringNoCch`): `cch` characters after a flags byte, in UTF-16
/// or (compressed) Latin-1, with rich-text runs and phonetic data skipped.
pub fn unicode_string(bytes: &[u8], cch: usize) -> Option<(String, usize)> {
    let flags = *bytes.first()?;
    let mut at = 1;
    let runs = if flags & 0x08 != 0 {
        let r = u16::from_le_bytes([*bytes.get(at)?, *bytes.get(at + 1)?]) as usize;
        at += 2;
        r
    } else {
        0
    };
    let ext = if flags & 0x04 != 0 {
        let e = u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?) as usize;
        at += 4;
        e
    } else {
        0
    };
    let text = if flags & 0x01 != 0 {
        let raw = bytes.get(at..at + 2 * cch)?;
        at += 2 * cch;
        let units: Vec<u16> = raw.chunks_exact(2).map(|c| u16::from_le_bytes([c[0], c[1]])).collect();
        String::from_utf16_lossy(&units)
    } else {
        let raw = bytes.get(at..at + cch)?;
        at += cch;
        raw.iter().map(|&b| b as char).collect()
    };
    Some((text, at + 4 * runs + ext))
}

/// The formula of `rgce` (with `extra`, the `RgbExtra` after it) as an xlsx file spells it.
/// `cell` is the cell it computes in (0-based row, column), which the relative references of
/// a shared formula (`PtgRefN`, `PtgAreaN`) count from; `sheet` the index of its sheet.
pub fn decode(
    rgce: &[u8],
    extra: &[u8],
    ctx: &Context,
    cell: (u32, u32),
    sheet: Option<usize>,
) -> Result<String, Unreadable> {
    let mut bytes = Bytes { data: rgce, at: 0 };
    let mut extra = Bytes { data: extra, at: 0 };
    let mut stack: Vec<Item> = Vec::new();
    while !bytes.done() {
        let ptg = bytes.u8()?;
        // Operand and function tokens come in three classes (reference, value, array): the
        // same token with bit 5 or 6 set.
        let base = if ptg >= 0x20 { (ptg & 0x1F) | 0x20 } else { ptg };
        match base {
            0x01 => return Err(Unreadable::Token("a shared or array formula without its record".into())),
            0x02 => return Err(Unreadable::DataTable),
            0x03..=0x11 => binary(&mut stack, ptg)?,
            0x12 | 0x13 => {
                let operand = stack.pop().ok_or_else(damaged)?;
                let sign = if ptg == 0x12 { '+' } else { '-' };
                stack.push(Item { text: format!("{sign}{}", wrap(operand, UNARY)), precedence: UNARY });
            }
            0x14 => {
                let operand = stack.pop().ok_or_else(damaged)?;
                stack.push(Item { text: format!("{}%", wrap(operand, PERCENT)), precedence: PERCENT });
            }
            0x15 => {
                let inner = stack.pop().ok_or_else(damaged)?;
                stack.push(atom(format!("({})", inner.text)));
            }
            0x16 => stack.push(atom(String::new())),
            0x17 => {
                let cch = bytes.u8()? as usize;
                let (text, used) = unicode_string(&bytes.data[bytes.at..], cch).ok_or_else(damaged)?;
                bytes.at += used;
                stack.push(atom(format!("\"{}\"", text.replace('"', "\"\""))));
            }
            0x18 => return Err(Unreadable::Token(format!("the extended token 0x18{:02X}", bytes.u8().unwrap_or(0)))),
            0x19 => attribute(&mut bytes, &mut stack)?,
            0x1C => stack.push(atom(error_text(bytes.u8()?).to_string())),
            0x1D => stack.push(atom(if bytes.u8()? != 0 { "TRUE" } else { "FALSE" }.to_string())),
            0x1E => stack.push(atom(bytes.u16()?.to_string())),
            0x1F => stack.push(atom(number(bytes.f64()?))),
            0x20 => {
                bytes.take(7)?;
                stack.push(atom(array_constant(&mut extra)?));
            }
            0x21 => {
                let iftab = bytes.u16()?;
                let (name, argc) = function(iftab)?;
                let argc = argc.ok_or_else(|| Unreadable::Token(format!("{name} with a fixed count of arguments")))?;
                call(&mut stack, name, argc as usize)?;
            }
            0x22 => {
                let argc = (bytes.u8()? & 0x7F) as usize;
                let iftab = bytes.u16()? & 0x7FFF;
                if iftab == 0xFF {
                    user_call(&mut stack, argc)?;
                } else {
                    call(&mut stack, function(iftab)?.0, argc)?;
                }
            }
            0x23 => {
                let index = bytes.u32()? as usize;
                stack.push(atom(defined_name(ctx, index, sheet)?));
            }
            0x24 | 0x2C => {
                let (row, col) = (bytes.u16()?, bytes.u16()?);
                let shared = base == 0x2C;
                stack.push(atom(cell_ref(row, col, shared.then_some(cell))));
            }
            0x25 | 0x2D => {
                let (r1, r2, c1, c2) = (bytes.u16()?, bytes.u16()?, bytes.u16()?, bytes.u16()?);
                let shared = base == 0x2D;
                stack.push(atom(area_ref(r1, r2, c1, c2, shared.then_some(cell))));
            }
            0x26..=0x28 => {
                // A reference expression's precomputed area (or its failure): the tokens
                // that compute it follow, and its cached rectangles are in the extra data.
                bytes.take(6)?;
                if base == 0x26 {
                    let count = extra.u16()? as usize;
                    extra.take(8 * count)?;
                }
            }
            0x29 | 0x2E | 0x2F => {
                bytes.take(2)?;
            }
            0x2A => {
                bytes.take(4)?;
                stack.push(atom("#REF!".into()));
            }
            0x2B => {
                bytes.take(8)?;
                stack.push(atom("#REF!".into()));
            }
            0x39 => {
                let (ixti, index) = (bytes.u16()?, bytes.u16()? as usize);
                bytes.take(2)?;
                stack.push(atom(external_name(ctx, ixti, index)?));
            }
            0x3A | 0x3C => {
                let ixti = bytes.u16()?;
                let (row, col) = (bytes.u16()?, bytes.u16()?);
                let text = match sheet_prefix(ctx, ixti)? {
                    Some(prefix) if base == 0x3A => format!("{prefix}{}", cell_ref(row, col, None)),
                    _ => "#REF!".to_string(),
                };
                stack.push(atom(text));
            }
            0x3B | 0x3D => {
                let ixti = bytes.u16()?;
                let (r1, r2, c1, c2) = (bytes.u16()?, bytes.u16()?, bytes.u16()?, bytes.u16()?);
                let text = match sheet_prefix(ctx, ixti)? {
                    Some(prefix) if base == 0x3B => format!("{prefix}{}", area_ref(r1, r2, c1, c2, None)),
                    _ => "#REF!".to_string(),
                };
                stack.push(atom(text));
            }
            other => return Err(Unreadable::Token(format!("the token 0x{other:02X}"))),
        }
    }
    match (stack.pop(), stack.is_empty()) {
        (Some(item), true) => Ok(item.text),
        _ => Err(damaged()),
    }
}

/// A binary operator over the two items on top of the stack.
fn binary(stack: &mut Vec<Item>, ptg: u8) -> Result<(), Unreadable> {
    let (op, precedence) = match ptg {
        0x03 => ("+", ADD),
        0x04 => ("-", ADD),
        0x05 => ("*", MULTIPLY),
        0x06 => ("/", MULTIPLY),
        0x07 => ("^", POWER),
        0x08 => ("&", CONCAT),
        0x09 => ("<", COMPARE),
        0x0A => ("<=", COMPARE),
        0x0B => ("=", COMPARE),
        0x0C => (">=", COMPARE),
        0x0D => (">", COMPARE),
        0x0E => ("<>", COMPARE),
        0x0F => (" ", INTERSECT),
        0x10 => (",", 0),
        _ => (":", RANGE),
    };
    let right = stack.pop().ok_or_else(damaged)?;
    let left = stack.pop().ok_or_else(damaged)?;
    if op == "," {
        // A union is written in parentheses, so that it never reads as two arguments.
        stack.push(atom(format!("({},{})", left.text, right.text)));
        return Ok(());
    }
    let left = wrap(left, precedence);
    let right = wrap(right, precedence + 1);
    stack.push(Item { text: format!("{left}{op}{right}"), precedence });
    Ok(())
}

/// An item's text, in parentheses when it binds less tightly than `needed`.
fn wrap(item: Item, needed: u8) -> String {
    if item.precedence < needed {
        format!("({})", item.text)
    } else {
        item.text
    }
}

/// `PtgAttr`: control tokens with no effect on the text, and `SUM` of one argument.
fn attribute(bytes: &mut Bytes, stack: &mut Vec<Item>) -> Result<(), Unreadable> {
    let flags = bytes.u8()?;
    if flags & 0x04 != 0 {
        let offsets = bytes.u16()? as usize + 1;
        bytes.take(2 * offsets)?;
        return Ok(());
    }
    bytes.take(2)?;
    if flags & 0x10 != 0 {
        let argument = stack.pop().ok_or_else(damaged)?;
        stack.push(atom(format!("SUM({})", argument.text)));
    }
    Ok(())
}

/// A call of a built-in function over the top `argc` items.
fn call(stack: &mut Vec<Item>, name: &str, argc: usize) -> Result<(), Unreadable> {
    if stack.len() < argc {
        return Err(damaged());
    }
    let args: Vec<String> = stack.split_off(stack.len() - argc).into_iter().map(|i| i.text).collect();
    stack.push(atom(format!("{name}({})", args.join(","))));
    Ok(())
}

/// A call of an add-in or macro function: its name is the first of the `argc` items.
fn user_call(stack: &mut Vec<Item>, argc: usize) -> Result<(), Unreadable> {
    if argc == 0 || stack.len() < argc {
        return Err(damaged());
    }
    let mut args = stack.split_off(stack.len() - argc).into_iter().map(|i| i.text);
    let name = args.next().unwrap_or_default();
    let rest: Vec<String> = args.collect();
    stack.push(atom(format!("{name}({})", rest.join(","))));
    Ok(())
}

fn error_text(code: u8) -> &'static str {
    match code {
        0x00 => "#NULL!",
        0x07 => "#DIV/0!",
        0x0F => "#VALUE!",
        0x17 => "#REF!",
        0x1D => "#NAME?",
        0x24 => "#NUM!",
        0x2B => "#GETTING_DATA",
        _ => "#N/A",
    }
}

/// A number as a formula writes it.
fn number(n: f64) -> String {
    let text = format!("{n:?}");
    text.strip_suffix(".0").map(str::to_string).unwrap_or(text)
}

/// `PtgExtraArray`: an array constant's size and values, row by row, as `{1,2;3,4}`.
fn array_constant(extra: &mut Bytes) -> Result<String, Unreadable> {
    let cols = extra.u8()? as usize + 1;
    let rows = extra.u16()? as usize + 1;
    let mut text = String::from("{");
    for r in 0..rows {
        if r > 0 {
            text.push(';');
        }
        for c in 0..cols {
            if c > 0 {
                text.push(',');
            }
            match extra.u8()? {
                0x01 => text.push_str(&number(extra.f64()?)),
                0x02 => {
                    let cch = extra.u16()? as usize;
                    let (s, used) = unicode_string(&extra.data[extra.at..], cch).ok_or_else(damaged)?;
                    extra.at += used;
                    let _ = write!(text, "\"{}\"", s.replace('"', "\"\""));
                }
                0x04 => {
                    let b = extra.take(8)?[0];
                    text.push_str(if b != 0 { "TRUE" } else { "FALSE" });
                }
                0x10 => text.push_str(error_text(extra.take(8)?[0])),
                _ => {
                    extra.take(8)?;
                }
            }
        }
    }
    text.push('}');
    Ok(text)
}

/// A column or row number moved by a shared formula's offset: BIFF8 stores a relative row
/// as a signed 16-bit offset and a relative column as a signed 8-bit one.
fn relative(value: u16, origin: u32, is_column: bool) -> u32 {
    let offset = if is_column { (value & 0xFF) as u8 as i8 as i64 } else { value as i16 as i64 };
    let size = if is_column { LAST_COL as i64 + 1 } else { LAST_ROW as i64 + 1 };
    (origin as i64 + offset).rem_euclid(size) as u32
}

/// One end of a reference: its row and column (`ColRelU`: 14 bits of column, bit 14 the
/// column relative, bit 15 the row relative), moved by `origin` where relative.
fn location(row: u16, col: u16, origin: Option<(u32, u32)>) -> (u32, u32, bool, bool) {
    let col_relative = col & 0x4000 != 0;
    let row_relative = col & 0x8000 != 0;
    let mut r = row as u32;
    let mut c = (col & 0x3FFF) as u32;
    if let Some((orow, ocol)) = origin {
        if row_relative {
            r = relative(row, orow, false);
        }
        if col_relative {
            c = relative(col & 0x3FFF, ocol, true);
        }
    }
    (r, c, row_relative, col_relative)
}

fn cell_ref(row: u16, col: u16, origin: Option<(u32, u32)>) -> String {
    let (r, c, row_relative, col_relative) = location(row, col, origin);
    format!(
        "{}{}{}{}",
        if col_relative { "" } else { "$" },
        crate::formula::address::column_name(c),
        if row_relative { "" } else { "$" },
        r + 1
    )
}

fn area_ref(r1: u16, r2: u16, c1: u16, c2: u16, origin: Option<(u32, u32)>) -> String {
    let (top, left, top_rel, left_rel) = location(r1, c1, origin);
    let (bottom, right, bottom_rel, right_rel) = location(r2, c2, origin);
    let dollar = |relative: bool| if relative { "" } else { "$" };
    let col = crate::formula::address::column_name;
    if top == 0 && bottom == LAST_ROW && origin.is_none() {
        return format!("{}{}:{}{}", dollar(left_rel), col(left), dollar(right_rel), col(right));
    }
    if left == 0 && right == LAST_COL && origin.is_none() {
        return format!("{}{}:{}{}", dollar(top_rel), top + 1, dollar(bottom_rel), bottom + 1);
    }
    format!(
        "{}{}{}{}:{}{}{}{}",
        dollar(left_rel),
        col(left),
        dollar(top_rel),
        top + 1,
        dollar(right_rel),
        col(right),
        dollar(bottom_rel),
        bottom + 1
    )
}

/// The sheet part of a 3D reference (`Sheet1!`, `'Sheet 1:Sheet 3'!`).
/// `None` when the sheet was deleted (the reference is then `#REF!`).
fn sheet_prefix(ctx: &Context, ixti: u16) -> Result<Option<String>, Unreadable> {
    let &(book, first, last) = ctx.xtis.get(ixti as usize).ok_or_else(damaged)?;
    match ctx.books.get(book as usize) {
        Some(SupBook::Own) => {}
        Some(_) => return Err(Unreadable::OtherWorkbook),
        None => return Err(damaged()),
    }
    let name = |i: i16| usize::try_from(i).ok().and_then(|i| ctx.sheets.get(i));
    match (name(first), name(last)) {
        (Some(a), Some(b)) if a == b || first == last => Ok(Some(format!("{}!", quoted_sheet(a)))),
        (Some(a), Some(b)) => {
            let both = format!("{a}:{b}");
            let needs_quotes = quoted_sheet(a).starts_with('\'') || quoted_sheet(b).starts_with('\'');
            Ok(Some(if needs_quotes { format!("'{}'!", both.replace('\'', "''")) } else { format!("{both}!") }))
        }
        // A sheet since deleted.
        _ => Ok(None),
    }
}

/// A defined name as a formula in `sheet` reads it (1-based `index` into the names).
fn defined_name(ctx: &Context, index: usize, sheet: Option<usize>) -> Result<String, Unreadable> {
    let (name, scope) = ctx.names.get(index.wrapping_sub(1)).ok_or_else(damaged)?;
    match scope {
        Some(s) if Some(*s) != sheet => {
            let owner = ctx.sheets.get(*s).ok_or_else(damaged)?;
            Ok(format!("{}!{name}", quoted_sheet(owner)))
        }
        _ => Ok(name.clone()),
    }
}

/// `PtgNameX`: an add-in function's name, or a name of this workbook.
fn external_name(ctx: &Context, ixti: u16, index: usize) -> Result<String, Unreadable> {
    let &(book, ..) = ctx.xtis.get(ixti as usize).ok_or_else(damaged)?;
    match ctx.books.get(book as usize) {
        Some(SupBook::AddIns(names)) => names.get(index.wrapping_sub(1)).cloned().ok_or_else(damaged),
        Some(SupBook::Own) => defined_name(ctx, index, None),
        Some(SupBook::Other(_)) => Err(Unreadable::OtherWorkbook),
        None => Err(damaged()),
    }
}

/// A built-in function by its number (MS-XLS 2.5.198.17 `Ftab`), with its count of arguments
/// when that is fixed (a `PtgFunc` holds none).
fn function(iftab: u16) -> Result<(&'static str, Option<u8>), Unreadable> {
    FUNCTIONS
        .binary_search_by_key(&iftab, |&(n, ..)| n)
        .map(|i| (FUNCTIONS[i].1, FUNCTIONS[i].2))
        .map_err(|_| Unreadable::Token(format!("the function number {iftab}")))
}

/// The worksheet functions of `Ftab` by number, with their argument count where fixed
/// (`None`: a variable count, always stored as `PtgFuncVar`). Excel 4 macro-sheet functions
/// are left out: a worksheet cannot compute them.
const FUNCTIONS: &[(u16, &str, Option<u8>)] = &[
    (0, "COUNT", None),
    (1, "IF", None),
    (2, "ISNA", Some(1)),
    (3, "ISERROR", Some(1)),
    (4, "SUM", None),
    (5, "AVERAGE", None),
    (6, "MIN", None),
    (7, "MAX", None),
    (8, "ROW", None),
    (9, "COLUMN", None),
    (10, "NA", Some(0)),
    (11, "NPV", None),
    (12, "STDEV", None),
    (13, "DOLLAR", None),
    (14, "FIXED", None),
    (15, "SIN", Some(1)),
    (16, "COS", Some(1)),
    (17, "TAN", Some(1)),
    (18, "ATAN", Some(1)),
    (19, "PI", Some(0)),
    (20, "SQRT", Some(1)),
    (21, "EXP", Some(1)),
    (22, "LN", Some(1)),
    (23, "LOG10", Some(1)),
    (24, "ABS", Some(1)),
    (25, "INT", Some(1)),
    (26, "SIGN", Some(1)),
    (27, "ROUND", Some(2)),
    (28, "LOOKUP", None),
    (29, "INDEX", None),
    (30, "REPT", Some(2)),
    (31, "MID", Some(3)),
    (32, "LEN", Some(1)),
    (33, "VALUE", Some(1)),
    (34, "TRUE", Some(0)),
    (35, "FALSE", Some(0)),
    (36, "AND", None),
    (37, "OR", None),
    (38, "NOT", Some(1)),
    (39, "MOD", Some(2)),
    (40, "DCOUNT", Some(3)),
    (41, "DSUM", Some(3)),
    (42, "DAVERAGE", Some(3)),
    (43, "DMIN", Some(3)),
    (44, "DMAX", Some(3)),
    (45, "DSTDEV", Some(3)),
    (46, "VAR", None),
    (47, "DVAR", Some(3)),
    (48, "TEXT", Some(2)),
    (49, "LINEST", None),
    (50, "TREND", None),
    (51, "LOGEST", None),
    (52, "GROWTH", None),
    (56, "PV", None),
    (57, "FV", None),
    (58, "NPER", None),
    (59, "PMT", None),
    (60, "RATE", None),
    (61, "MIRR", Some(3)),
    (62, "IRR", None),
    (63, "RAND", Some(0)),
    (64, "MATCH", None),
    (65, "DATE", Some(3)),
    (66, "TIME", Some(3)),
    (67, "DAY", Some(1)),
    (68, "MONTH", Some(1)),
    (69, "YEAR", Some(1)),
    (70, "WEEKDAY", None),
    (71, "HOUR", Some(1)),
    (72, "MINUTE", Some(1)),
    (73, "SECOND", Some(1)),
    (74, "NOW", Some(0)),
    (75, "AREAS", Some(1)),
    (76, "ROWS", Some(1)),
    (77, "COLUMNS", Some(1)),
    (78, "OFFSET", None),
    (82, "SEARCH", None),
    (83, "TRANSPOSE", Some(1)),
    (86, "TYPE", Some(1)),
    (97, "ATAN2", Some(2)),
    (98, "ASIN", Some(1)),
    (99, "ACOS", Some(1)),
    (100, "CHOOSE", None),
    (101, "HLOOKUP", None),
    (102, "VLOOKUP", None),
    (105, "ISREF", Some(1)),
    (109, "LOG", None),
    (111, "CHAR", Some(1)),
    (112, "LOWER", Some(1)),
    (113, "UPPER", Some(1)),
    (114, "PROPER", Some(1)),
    (115, "LEFT", None),
    (116, "RIGHT", None),
    (117, "EXACT", Some(2)),
    (118, "TRIM", Some(1)),
    (119, "REPLACE", Some(4)),
    (120, "SUBSTITUTE", None),
    (121, "CODE", Some(1)),
    (124, "FIND", None),
    (125, "CELL", None),
    (126, "ISERR", Some(1)),
    (127, "ISTEXT", Some(1)),
    (128, "ISNUMBER", Some(1)),
    (129, "ISBLANK", Some(1)),
    (130, "T", Some(1)),
    (131, "N", Some(1)),
    (140, "DATEVALUE", Some(1)),
    (141, "TIMEVALUE", Some(1)),
    (142, "SLN", Some(3)),
    (143, "SYD", Some(4)),
    (144, "DDB", None),
    (148, "INDIRECT", None),
    (162, "CLEAN", Some(1)),
    (163, "MDETERM", Some(1)),
    (164, "MINVERSE", Some(1)),
    (165, "MMULT", Some(2)),
    (167, "IPMT", None),
    (168, "PPMT", None),
    (169, "COUNTA", None),
    (183, "PRODUCT", None),
    (184, "FACT", Some(1)),
    (189, "DPRODUCT", Some(3)),
    (190, "ISNONTEXT", Some(1)),
    (193, "STDEVP", None),
    (194, "VARP", None),
    (195, "DSTDEVP", Some(3)),
    (196, "DVARP", Some(3)),
    (197, "TRUNC", None),
    (198, "ISLOGICAL", Some(1)),
    (199, "DCOUNTA", Some(3)),
    (204, "USDOLLAR", None),
    (205, "FINDB", None),
    (206, "SEARCHB", None),
    (207, "REPLACEB", Some(4)),
    (208, "LEFTB", None),
    (209, "RIGHTB", None),
    (210, "MIDB", Some(3)),
    (211, "LENB", Some(1)),
    (212, "ROUNDUP", Some(2)),
    (213, "ROUNDDOWN", Some(2)),
    (214, "ASC", Some(1)),
    (215, "DBCS", Some(1)),
    (216, "RANK", None),
    (219, "ADDRESS", None),
    (220, "DAYS360", None),
    (221, "TODAY", Some(0)),
    (222, "VDB", None),
    (227, "MEDIAN", None),
    (228, "SUMPRODUCT", None),
    (229, "SINH", Some(1)),
    (230, "COSH", Some(1)),
    (231, "TANH", Some(1)),
    (232, "ASINH", Some(1)),
    (233, "ACOSH", Some(1)),
    (234, "ATANH", Some(1)),
    (235, "DGET", Some(3)),
    (244, "INFO", Some(1)),
    (247, "DB", None),
    (252, "FREQUENCY", Some(2)),
    (261, "ERROR.TYPE", Some(1)),
    (269, "AVEDEV", None),
    (270, "BETADIST", None),
    (271, "GAMMALN", Some(1)),
    (272, "BETAINV", None),
    (273, "BINOMDIST", Some(4)),
    (274, "CHIDIST", Some(2)),
    (275, "CHIINV", Some(2)),
    (276, "COMBIN", Some(2)),
    (277, "CONFIDENCE", Some(3)),
    (278, "CRITBINOM", Some(3)),
    (279, "EVEN", Some(1)),
    (280, "EXPONDIST", Some(3)),
    (281, "FDIST", Some(3)),
    (282, "FINV", Some(3)),
    (283, "FISHER", Some(1)),
    (284, "FISHERINV", Some(1)),
    (285, "FLOOR", Some(2)),
    (286, "GAMMADIST", Some(4)),
    (287, "GAMMAINV", Some(3)),
    (288, "CEILING", Some(2)),
    (289, "HYPGEOMDIST", Some(4)),
    (290, "LOGNORMDIST", Some(3)),
    (291, "LOGINV", Some(3)),
    (292, "NEGBINOMDIST", Some(3)),
    (293, "NORMDIST", Some(4)),
    (294, "NORMSDIST", Some(1)),
    (295, "NORMINV", Some(3)),
    (296, "NORMSINV", Some(1)),
    (297, "STANDARDIZE", Some(3)),
    (298, "ODD", Some(1)),
    (299, "PERMUT", Some(2)),
    (300, "POISSON", Some(3)),
    (301, "TDIST", Some(3)),
    (302, "WEIBULL", Some(4)),
    (303, "SUMXMY2", Some(2)),
    (304, "SUMX2MY2", Some(2)),
    (305, "SUMX2PY2", Some(2)),
    (306, "CHITEST", Some(2)),
    (307, "CORREL", Some(2)),
    (308, "COVAR", Some(2)),
    (309, "FORECAST", Some(3)),
    (310, "FTEST", Some(2)),
    (311, "INTERCEPT", Some(2)),
    (312, "PEARSON", Some(2)),
    (313, "RSQ", Some(2)),
    (314, "STEYX", Some(2)),
    (315, "SLOPE", Some(2)),
    (316, "TTEST", Some(4)),
    (317, "PROB", None),
    (318, "DEVSQ", None),
    (319, "GEOMEAN", None),
    (320, "HARMEAN", None),
    (321, "SUMSQ", None),
    (322, "KURT", None),
    (323, "SKEW", None),
    (324, "ZTEST", None),
    (325, "LARGE", Some(2)),
    (326, "SMALL", Some(2)),
    (327, "QUARTILE", Some(2)),
    (328, "PERCENTILE", Some(2)),
    (329, "PERCENTRANK", None),
    (330, "MODE", None),
    (331, "TRIMMEAN", Some(2)),
    (332, "TINV", Some(2)),
    (336, "CONCATENATE", None),
    (337, "POWER", Some(2)),
    (342, "RADIANS", Some(1)),
    (343, "DEGREES", Some(1)),
    (344, "SUBTOTAL", None),
    (345, "SUMIF", None),
    (346, "COUNTIF", Some(2)),
    (347, "COUNTBLANK", Some(1)),
    (350, "ISPMT", Some(4)),
    (351, "DATEDIF", Some(3)),
    (352, "DATESTRING", Some(1)),
    (353, "NUMBERSTRING", Some(2)),
    (354, "ROMAN", None),
    (358, "GETPIVOTDATA", None),
    (359, "HYPERLINK", None),
    (360, "PHONETIC", Some(1)),
    (361, "AVERAGEA", None),
    (362, "MAXA", None),
    (363, "MINA", None),
    (364, "STDEVPA", None),
    (365, "VARPA", None),
    (366, "STDEVA", None),
    (367, "VARA", None),
    (368, "BAHTTEXT", Some(1)),
    (379, "RTD", None),
];

#[cfg(test)]
mod tests {
    use super::*;

    type Parts = (Vec<String>, Vec<(u16, i16, i16)>, Vec<SupBook>, Vec<(String, Option<usize>)>);

    fn ctx() -> Parts {
        (vec!["Sheet1".into(), "My Data".into()], vec![(0, 1, 1), (0, 0, 1)], vec![SupBook::Own], vec![])
    }

    fn run(rgce: &[u8]) -> Result<String, Unreadable> {
        let (sheets, xtis, books, names) = ctx();
        let c = Context { sheets: &sheets, xtis: &xtis, books: &books, names: &names };
        decode(rgce, &[], &c, (4, 2), Some(0))
    }

    #[test]
    fn operators_get_the_parentheses_their_precedence_needs() {
        // (1+2)*3 stored without a PtgParen: 1 2 + 3 *
        assert_eq!(run(&[0x1E, 1, 0, 0x1E, 2, 0, 0x03, 0x1E, 3, 0, 0x05]).unwrap(), "(1+2)*3");
        // 1-(2-3): 1 2 3 - -
        assert_eq!(run(&[0x1E, 1, 0, 0x1E, 2, 0, 0x1E, 3, 0, 0x04, 0x04]).unwrap(), "1-(2-3)");
        // -2^2 is (-2)^2 in Excel: 2 neg 2 ^
        assert_eq!(run(&[0x1E, 2, 0, 0x13, 0x1E, 2, 0, 0x07]).unwrap(), "-2^2");
        // PtgGe is 0x0C, PtgGt 0x0D (MS-XLS 2.5.198.57, 2.5.198.60).
        assert_eq!(run(&[0x1E, 1, 0, 0x1E, 2, 0, 0x0C]).unwrap(), "1>=2");
        assert_eq!(run(&[0x1E, 1, 0, 0x1E, 2, 0, 0x0D]).unwrap(), "1>2");
    }

    #[test]
    fn references_keep_their_dollars_and_whole_columns_read_as_columns() {
        // PtgRef B3 with row and column relative (bits 15 and 14 set).
        assert_eq!(run(&[0x44, 2, 0, 1, 0xC0]).unwrap(), "B3");
        assert_eq!(run(&[0x44, 2, 0, 1, 0x00]).unwrap(), "$B$3");
        // PtgArea3d over all rows of columns A:B of 'My Data'.
        assert_eq!(run(&[0x3B, 0, 0, 0, 0, 0xFF, 0xFF, 0, 0xC0, 1, 0xC0]).unwrap(), "'My Data'!A:B");
        // PtgRef3d over two sheets.
        assert_eq!(run(&[0x3A, 1, 0, 0, 0, 0, 0]).unwrap(), "'Sheet1:My Data'!$A$1");
    }

    #[test]
    fn shared_formulas_count_relative_references_from_their_cell() {
        // PtgRefN row -1, column +1 relative, from C5: D4.
        assert_eq!(run(&[0x2C, 0xFF, 0xFF, 0x01, 0xC0]).unwrap(), "D4");
    }

    #[test]
    fn functions_take_their_arguments_from_the_stack() {
        // ROUND(1.5, 0) as PtgFunc; SUM(1,2) as PtgFuncVar.
        assert_eq!(run(&[0x1F, 0, 0, 0, 0, 0, 0, 0xF8, 0x3F, 0x1E, 0, 0, 0x41, 27, 0]).unwrap(), "ROUND(1.5,0)");
        assert_eq!(run(&[0x1E, 1, 0, 0x1E, 2, 0, 0x42, 2, 4, 0]).unwrap(), "SUM(1,2)");
        assert_eq!(run(&[0x02, 0, 0, 0, 0]), Err(Unreadable::DataTable));
    }

    #[test]
    fn the_function_table_is_sorted_and_every_name_is_a_worksheet_function() {
        const LACKING: &[&str] = &[
            "USDOLLAR",
            "FINDB",
            "SEARCHB",
            "REPLACEB",
            "LEFTB",
            "RIGHTB",
            "MIDB",
            "LENB",
            "ASC",
            "DBCS",
            "DATESTRING",
            "NUMBERSTRING",
            "GETPIVOTDATA",
            "PHONETIC",
            "BAHTTEXT",
            "RTD",
        ];
        assert!(FUNCTIONS.windows(2).all(|w| w[0].0 < w[1].0));
        // Functions of Excel 97 ncsheet does not compute (they read as #NAME?, as they would
        // typed); every other name must be one of the registry's.
        let missing: Vec<&str> =
            FUNCTIONS.iter().map(|f| f.1).filter(|name| crate::eval::functions::find(name).is_none()).collect();
        assert_eq!(missing, LACKING, "names the registry lacks");
    }
}
