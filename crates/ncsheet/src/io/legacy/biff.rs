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
pub(super) const PERCENT: u8 = 6;
pub(super) const UNARY: u8 = 7;
const INTERSECT: u8 = 9;
const RANGE: u8 = 10;
const ATOM: u8 = 11;

pub(super) struct Item {
    pub(super) text: String,
    pub(super) precedence: u8,
}

pub(super) fn atom(text: String) -> Item {
    Item { text, precedence: ATOM }
}

/// The last row and column BIFF8 has: a reference spanning all of them is a whole column
/// or row.
const LAST_ROW: u32 = 0xFFFF;
const LAST_COL: u32 = 0xFF;

/// A reader over the formula's bytes.
pub(super) struct Bytes<'a> {
    pub(super) data: &'a [u8],
    pub(super) at: usize,
}

impl<'a> Bytes<'a> {
    pub(super) fn take(&mut self, n: usize) -> Result<&'a [u8], Unreadable> {
        let slice = self.data.get(self.at..self.at + n).ok_or_else(damaged)?;
        self.at += n;
        Ok(slice)
    }
    pub(super) fn u8(&mut self) -> Result<u8, Unreadable> {
        Ok(self.take(1)?[0])
    }
    pub(super) fn u16(&mut self) -> Result<u16, Unreadable> {
        let b = self.take(2)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }
    pub(super) fn u32(&mut self) -> Result<u32, Unreadable> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    pub(super) fn f64(&mut self) -> Result<f64, Unreadable> {
        let b = self.take(8)?;
        Ok(f64::from_le_bytes(b.try_into().expect("8 bytes")))
    }
    pub(super) fn done(&self) -> bool {
        self.at >= self.data.len()
    }
}

pub(super) fn damaged() -> Unreadable {
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
pub(super) fn binary(stack: &mut Vec<Item>, ptg: u8) -> Result<(), Unreadable> {
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
pub(super) fn wrap(item: Item, needed: u8) -> String {
    if item.precedence < needed {
        format!("({})", item.text)
    } else {
        item.text
    }
}

/// `PtgAttr`: control tokens with no effect on the text, and `SUM` of one argument.
pub(super) fn attribute(bytes: &mut Bytes, stack: &mut Vec<Item>) -> Result<(), Unreadable> {
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
pub(super) fn call(stack: &mut Vec<Item>, name: &str, argc: usize) -> Result<(), Unreadable> {
    if stack.len() < argc {
        return Err(damaged());
    }
    let args: Vec<String> = stack.split_off(stack.len() - argc).into_iter().map(|i| i.text).collect();
    stack.push(atom(format!("{name}({})", args.join(","))));
    Ok(())
}

/// A call of an add-in or macro function: its name is the first of the `argc` items.
pub(super) fn user_call(stack: &mut Vec<Item>, argc: usize) -> Result<(), Unreadable> {
    if argc == 0 || stack.len() < argc {
        return Err(damaged());
    }
    let mut args = stack.split_off(stack.len() - argc).into_iter().map(|i| i.text);
    let name = args.next().unwrap_or_default();
    let rest: Vec<String> = args.collect();
    stack.push(atom(format!("{name}({})", rest.join(","))));
    Ok(())
}

pub(super) fn error_text(code: u8) -> &'static str {
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
pub(super) fn number(n: f64) -> String {
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
pub(super) fn sheet_prefix(ctx: &Context, ixti: u16) -> Result<Option<String>, Unreadable> {
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
pub(super) fn defined_name(ctx: &Context, index: usize, sheet: Option<usize>) -> Result<String, Unreadable> {
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
pub(super) fn external_name(ctx: &Context, ixti: u16, index: usize) -> Result<String, Unreadable> {
    let &(book, ..) = ctx.xtis.get(ixti as usize).ok_or_else(damaged)?;
    match ctx.books.get(book as usize) {
        Some(SupBook::AddIns(names)) => names.get(index.wrapping_sub(1)).cloned().ok_or_else(damaged),
        Some(SupBook::Own) => defined_name(ctx, index, None),
        Some(SupBook::Other(_)) => Err(Unreadable::OtherWorkbook),
        None => Err(damaged()),
    }
}

/// A built-in function by its number (MS-XLS 2.5.198.17 `Ftab`), with its count of arguments
/// when that is fixed (a `PtgFunc` holds none). The number is a fact on the function's row of
/// the function table (`FnSpec::biff`); the functions of Excel 97 ncsheet does not compute
/// are read by name, to show #NAME? as a typed call of them would.
pub(super) fn function(iftab: u16) -> Result<(&'static str, Option<u8>), Unreadable> {
    if let Some(id) = crate::eval::functions::find_biff(iftab) {
        let spec = crate::eval::functions::spec(id);
        return Ok((spec.name, spec.biff.and_then(|b| b.fixed_args)));
    }
    NOT_COMPUTED
        .iter()
        .find(|&&(n, ..)| n == iftab)
        .map(|&(_, name, argc)| (name, argc))
        .ok_or_else(|| Unreadable::Token(format!("the function number {iftab}")))
}

/// The worksheet functions of `Ftab` that ncsheet does not compute, by number, with their
/// argument count where fixed (`None`: a variable count, always stored as `PtgFuncVar`).
/// Excel 4 macro-sheet functions are left out: a worksheet cannot compute them.
const NOT_COMPUTED: &[(u16, &str, Option<u8>)] = &[
    (204, "USDOLLAR", None),
    (205, "FINDB", None),
    (206, "SEARCHB", None),
    (207, "REPLACEB", Some(4)),
    (208, "LEFTB", None),
    (209, "RIGHTB", None),
    (210, "MIDB", Some(3)),
    (211, "LENB", Some(1)),
    (214, "ASC", Some(1)),
    (215, "DBCS", Some(1)),
    (352, "DATESTRING", Some(1)),
    (353, "NUMBERSTRING", Some(2)),
    (360, "PHONETIC", Some(1)),
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
    fn functions_are_known_by_their_excel_97_numbers() {
        // MS-XLS 2.5.198.17 (Ftab): the number and, for PtgFunc, the fixed count of arguments.
        for (number, name, argc) in [
            (0, "COUNT", None),
            (1, "IF", None),
            (4, "SUM", None),
            (27, "ROUND", Some(2)),
            (31, "MID", Some(3)),
            (40, "DCOUNT", Some(3)),
            (65, "DATE", Some(3)),
            (102, "VLOOKUP", None),
            (148, "INDIRECT", None),
            (199, "DCOUNTA", Some(3)),
            (228, "SUMPRODUCT", None),
            (285, "FLOOR", Some(2)),
            (344, "SUBTOTAL", None),
            (346, "COUNTIF", Some(2)),
            (351, "DATEDIF", Some(3)),
            (368, "BAHTTEXT", Some(1)),
            (379, "RTD", None),
        ] {
            assert_eq!(function(number).unwrap(), (name, argc), "function number {number}");
        }
        assert!(function(380).is_err());
    }

    #[test]
    fn a_function_ncsheet_lacks_is_read_by_name_and_has_no_number_in_the_registry() {
        for &(number, name, _) in NOT_COMPUTED {
            assert!(
                crate::eval::functions::find(name).is_none(),
                "{name} is in the registry: give its row .biff({number})"
            );
            assert!(crate::eval::functions::find_biff(number).is_none(), "{number} is also a registry row's");
        }
    }
}
