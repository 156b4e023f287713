//! References made at run time: INDIRECT (from text) and OFFSET (moved from another
//! reference). Their cells are not in the formula's text, so the dependency graph cannot
//! know them in advance: each is reported through [`Ctx::note_dynamic_ref`], and the workbook
//! links the cell to it after evaluation (crates/ncsheet/src/workbook/recalc.rs). Excel recalculates both at
//! every edit (they are volatile); here OFFSET is recomputed only when what it reads changes
//! (`FnSpec::every_edit`). OFFSET's first argument is where to start, not what it reads
//! (`FnSpec::position_arg`): no graph edge comes from it, only from the cells it reaches, so
//! a running balance `B3 = OFFSET(B3,-1,0)+A3`, or `OFFSET(B:B,ROW()-2,0,1)` over its own
//! column, is no cycle.

use crate::eval::coerce::{to_bool, to_number, to_text};
use crate::eval::functions::api::{ArgSet, Ctx, FnSpec, Operand, Registry};
use crate::eval::value::{Value, XlError, XlResult};
use crate::formula::address::{Pos, Rect, MAX_COLS, MAX_ROWS};
use crate::formula::ast::{BinOp, Expr, ExprKind, SheetId};
use crate::formula::parse::{parse_formula, ParseContext};

pub const FUNCTIONS: &[FnSpec] = &[
    FnSpec::reference(
        "INDIRECT",
        1,
        2,
        indirect,
        "INDIRECT(ref_text, [a1])",
        "The reference named by text: A1 style (`B3`, `Sheet2!A1:C4`, a defined name), or R1C1 style when a1 is FALSE",
    )
    .biff(148)
    .volatile(),
    FnSpec::reference(
        "OFFSET",
        3,
        5,
        offset,
        "OFFSET(reference, rows, cols, [height], [width])",
        "The reference moved by rows and cols, with the given height and width (the original's by default)",
    )
    .biff(78)
    .range_args(ArgSet::only(0))
    .volatile()
    .reach_linked()
    .position_arg(),
];

fn indirect(ctx: &mut Ctx, args: &[Expr]) -> Operand {
    let made = indirect_ref(ctx, args);
    into_operand(ctx, made)
}

fn offset(ctx: &mut Ctx, args: &[Expr]) -> Operand {
    let made = offset_ref(ctx, args);
    into_operand(ctx, made)
}

/// A reference made here is reported to the workbook before it is used.
fn into_operand(ctx: &mut Ctx, made: XlResult<(SheetId, Rect)>) -> Operand {
    match made {
        Ok((sheet, rect)) => {
            ctx.note_dynamic_ref(sheet, rect);
            Operand::Ref(sheet, rect)
        }
        Err(e) => Operand::Value(Value::Error(e)),
    }
}

fn scalar(ctx: &mut Ctx, e: &Expr) -> XlResult<Value> {
    match ctx.eval(e) {
        Value::Array(_) => Err(XlError::Value),
        Value::Error(err) => Err(err),
        v => Ok(v),
    }
}

fn indirect_ref(ctx: &mut Ctx, args: &[Expr]) -> XlResult<(SheetId, Rect)> {
    let text = to_text(&scalar(ctx, &args[0])?)?;
    let a1 = match args.get(1).filter(|e| e.kind != ExprKind::Missing) {
        Some(e) => to_bool(&scalar(ctx, e)?)?,
        None => true,
    };
    let text = text.trim();
    if a1 {
        a1_reference(ctx, text)
    } else {
        r1c1_reference(ctx, text)
    }
}

/// `B3`, `$B$3:C4`, `Sheet2!A1`, `'My sheet'!A:A` or a defined name, read with the formula
/// parser. Anything else (a formula, a number) is `#REF!`, as in Excel.
fn a1_reference(ctx: &mut Ctx, text: &str) -> XlResult<(SheetId, Rect)> {
    if let Some(made) = plain_a1_reference(ctx, text) {
        return made;
    }
    // `Table1[Qty]`, `Table1[#Totals]` read as a formula's: the cells the table names now.
    let env = ctx.env;
    let sheet_named = |name: &str| sheet_id(env, name);
    let parse = ParseContext { at: ctx.at, functions: &Registry, sheet: &sheet_named };
    let expr = parse_formula(text, &parse).map_err(|_| XlError::Ref)?;
    if !is_reference(&expr) {
        return Err(XlError::Ref);
    }
    match ctx.operand(&expr) {
        Operand::Ref(sheet, rect) => Ok((sheet, rect)),
        // Text that reads as an unknown name names no cell.
        Operand::Value(Value::Error(XlError::Name)) => Err(XlError::Ref),
        Operand::Value(Value::Error(e)) => Err(e),
        Operand::Value(_) | Operand::Areas(_) => Err(XlError::Ref),
    }
}

/// The usual text, `B3`, `$B$3:C4` or `'Sheet 2'!A1`, read without the formula parser: a
/// column of INDIRECT cells is recomputed at every edit, and the parser was nearly all of
/// the cost. `None` for anything else (names, whole rows or columns, unquoted sheet names),
/// which the parser reads.
fn plain_a1_reference(ctx: &Ctx, text: &str) -> Option<XlResult<(SheetId, Rect)>> {
    let (sheet, cells) = match text.strip_prefix('\'') {
        Some(quoted) => {
            let (name, cells) = quoted.rsplit_once("'!")?;
            (name, cells)
        }
        None if text.contains('!') => return None,
        None => ("", text),
    };
    let rect = match cells.split_once(':') {
        Some((a, b)) => Rect::new(plain_a1_cell(a)?, plain_a1_cell(b)?),
        None => Rect::cell(plain_a1_cell(cells)?),
    };
    if sheet.is_empty() {
        return (!text.starts_with('\'')).then_some(Ok((ctx.sheet, rect)));
    }
    if sheet.replace("''", "").contains('\'') {
        return None;
    }
    Some(sheet_id(ctx.env, &sheet.replace("''", "'")).map(|id| (id, rect)).ok_or(XlError::Ref))
}

/// `B3` or `$B$3` (a column of one to three letters up to XFD, a row from 1 without leading
/// zeros up to the last), or `None`.
fn plain_a1_cell(text: &str) -> Option<Pos> {
    let text = text.strip_prefix('$').unwrap_or(text);
    let letters = text.bytes().take_while(u8::is_ascii_alphabetic).count();
    let (column, rest) = text.split_at(letters);
    let digits = rest.strip_prefix('$').unwrap_or(rest);
    if digits.is_empty() || digits.starts_with('0') || digits.len() > 7 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let col = crate::formula::address::column_index(column)?;
    let row: u32 = digits.parse().ok()?;
    (row <= MAX_ROWS).then(|| Pos::new(row - 1, col))
}

fn is_reference(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Ref(_) | ExprKind::Name(_) | ExprKind::SheetName(..) | ExprKind::Table(_) => true,
        ExprKind::Binary(BinOp::Range, a, b) => is_reference(a) && is_reference(b),
        _ => false,
    }
}

fn sheet_id(env: &dyn crate::eval::Env, name: &str) -> Option<SheetId> {
    env.sheet_id(name)
}

/// `R2C3`, `R[-1]C`, `R1C1:R4C2`, `Sheet2!R1C1`: rows and columns absolute, or in brackets
/// relative to the formula's cell; a letter alone is the formula's own row or column.
fn r1c1_reference(ctx: &Ctx, text: &str) -> XlResult<(SheetId, Rect)> {
    let (sheet, cells) = match text.rsplit_once('!') {
        Some((name, cells)) => {
            let name = name.strip_prefix('\'').and_then(|n| n.strip_suffix('\'')).unwrap_or(name);
            (sheet_id(ctx.env, &name.replace("''", "'")).ok_or(XlError::Ref)?, cells)
        }
        None => (ctx.sheet, text),
    };
    let (first, last) = match cells.split_once(':') {
        Some((a, b)) => (r1c1_cell(a, ctx.at)?, r1c1_cell(b, ctx.at)?),
        None => {
            let p = r1c1_cell(cells, ctx.at)?;
            (p, p)
        }
    };
    Ok((sheet, Rect::new(first, last)))
}

fn r1c1_cell(text: &str, at: Pos) -> XlResult<Pos> {
    let rest = text.strip_prefix(['R', 'r']).ok_or(XlError::Ref)?;
    let c = rest.find(['C', 'c']).ok_or(XlError::Ref)?;
    let row = r1c1_index(&rest[..c], at.row, MAX_ROWS)?;
    let col = r1c1_index(&rest[c + 1..], at.col, MAX_COLS)?;
    Ok(Pos::new(row, col))
}

/// One coordinate: empty (the formula's own), `n` (1-based) or `[k]` (an offset).
fn r1c1_index(text: &str, here: u32, count: u32) -> XlResult<u32> {
    let index = if text.is_empty() {
        i64::from(here)
    } else if let Some(offset) = text.strip_prefix('[').and_then(|t| t.strip_suffix(']')) {
        i64::from(here) + offset.parse::<i64>().map_err(|_| XlError::Ref)?
    } else {
        text.parse::<i64>().map_err(|_| XlError::Ref)? - 1
    };
    in_sheet(index, count)
}

fn in_sheet(index: i64, count: u32) -> XlResult<u32> {
    if (0..i64::from(count)).contains(&index) {
        Ok(index as u32)
    } else {
        Err(XlError::Ref)
    }
}

/// A height or width as given, the reference's own when left out.
fn whole_or(ctx: &mut Ctx, args: &[Expr], i: usize, default: u32) -> XlResult<f64> {
    let dates = ctx.dates();
    match args.get(i).filter(|e| e.kind != ExprKind::Missing) {
        Some(e) => to_number(&scalar(ctx, e)?, dates),
        None => Ok(f64::from(default)),
    }
}

/// Whole rows or columns of a height or width, truncated: 0 is `#REF!`, and a size between
/// 0 and 1 is one (Excel: `OFFSET(W39,2,2,3,0.9)` is one column wide).
fn size(n: f64) -> XlResult<i64> {
    if n == 0.0 {
        return Err(XlError::Ref);
    }
    let whole = n.trunc();
    Ok(if whole == 0.0 { n.signum() as i64 } else { whole as i64 })
}

fn offset_ref(ctx: &mut Ctx, args: &[Expr]) -> XlResult<(SheetId, Rect)> {
    let dates = ctx.dates();
    let (sheet, base) = match ctx.operand(&args[0]) {
        Operand::Ref(sheet, rect) => (sheet, rect),
        Operand::Value(Value::Error(e)) => return Err(e),
        Operand::Value(_) | Operand::Areas(_) => return Err(XlError::Value),
    };
    let mut whole = |i: usize, default: f64| -> XlResult<i64> {
        match args.get(i).filter(|e| e.kind != ExprKind::Missing) {
            Some(e) => Ok(to_number(&scalar(ctx, e)?, dates)?.trunc() as i64),
            None => Ok(default as i64),
        }
    };
    let rows = whole(1, 0.0)?;
    let cols = whole(2, 0.0)?;
    let height = size(whole_or(ctx, args, 3, base.rows())?)?;
    let width = size(whole_or(ctx, args, 4, base.cols())?)?;
    let corner = |start: u32, by: i64, size: i64, count: u32| -> XlResult<(u32, u32)> {
        // Saturating: a move or size of 1E+300 was cast to i64::MAX and overflowed here (a
        // panic in a debug build); any such count is off the sheet, `#REF!`.
        let from = i64::from(start).saturating_add(by);
        // A negative height or width reaches up or left from the moved corner, as in Excel.
        let (low, high) =
            if size > 0 { (from, from.saturating_add(size - 1)) } else { (from.saturating_add(size + 1), from) };
        Ok((in_sheet(low, count)?, in_sheet(high, count)?))
    };
    let (top, bottom) = corner(base.first.row, rows, height, MAX_ROWS)?;
    let (left, right) = corner(base.first.col, cols, width, MAX_COLS)?;
    Ok((sheet, Rect::new(Pos::new(top, left), Pos::new(bottom, right))))
}
