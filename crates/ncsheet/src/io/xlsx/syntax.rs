//! Formula spelling in xlsx files versus the spelling a user types.
//!
//! Excel stores functions newer than Excel 2007 with a `_xlfn.` prefix (`_xlfn._xlws.` for
//! FILTER and SORT), LET and LAMBDA parameters with `_xlpm.`, the spill operator `A1#` as
//! `_xlfn.ANCHORARRAY(A1)` and the implicit intersection `@x` as `_xlfn.SINGLE(x)`. Our
//! parser drops the prefixes of the functions it knows (a function we lack keeps the prefix
//! it was read with); this module turns ANCHORARRAY and SINGLE back into operators on
//! import, and writes all of it back on export, each function's prefix as its registry row
//! says (`FnSpec::future`). Export prints through the one
//! printer of `formula::print`: `FileSpelling` only says how names and the two operators
//! are spelled, so parentheses and every other node are printed as for the formula typed.
//!
//! Export prints the workbook's trees (`Workbook::formula_tree`), never its text; import
//! takes a fast path: text without these operators needs no parse.

use crate::eval::functions::{find, spec, Registry};
use crate::formula::address::Pos;
use crate::formula::ast::*;
use crate::formula::parse::strip_future_prefix;
use crate::formula::print::{print_spelled, OperatorSpelling, Spelling};
use crate::workbook::Workbook;

/// A formula as stored in a file (no leading `=`) that writes the spill or the intersection
/// operator as a function: its tree with the operators back. `None` when the text has
/// neither (it is read as typed) or does not parse (it is stored as typed, as `#NAME?`).
pub fn tree_from_file(text: &str, wb: &Workbook, sheet: SheetId, pos: Pos) -> Option<Expr> {
    if !calls_any(text, &["ANCHORARRAY", "SINGLE"]) {
        return None;
    }
    let mut expr = wb.parse_at(text, sheet, pos).ok()?;
    operators_from_file(&mut expr);
    Some(expr)
}

/// How a formula is stored: which decides how `@` is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Storage {
    /// A plain `<f>`: Excel intersects by itself, so an `@x` outside any function call is
    /// written `x` (which LibreOffice reads too). Inside a call, whether Excel would
    /// intersect depends on the function, so `@` stays `_xlfn.SINGLE`.
    Legacy,
    /// A dynamic-array formula (`t="array"`, `cm="1"`): `@x` is `_xlfn.SINGLE(x)`.
    Dynamic,
}

/// A formula as a file stores it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileFormula {
    /// The text, without the leading `=`.
    pub text: String,
    /// It calls a function (or writes an operator, `_xlfn.ANCHORARRAY`, `_xlfn.SINGLE`)
    /// that makes Excel and rust_xlsxwriter store the formula as a dynamic array.
    pub dynamic: bool,
}

/// A formula tree held by the cell `pos` → as stored in a file.
pub fn to_file(tree: &Expr, wb: &Workbook, pos: Pos, storage: Storage) -> FileFormula {
    let spelling = FileSpelling { storage, dynamic: std::cell::Cell::new(false) };
    let text = print(tree, wb, pos, &spelling);
    FileFormula { text, dynamic: spelling.dynamic.get() }
}

/// A cell's formula as stored in a file, `None` for a constant. Text that did not parse
/// (a table reference, an external link) goes back as it came.
pub fn cell_to_file(wb: &Workbook, sheet: SheetId, pos: Pos, storage: Storage) -> Option<FileFormula> {
    match wb.formula_tree(sheet, pos) {
        Some(tree) => Some(to_file(&tree, wb, pos, storage)),
        None => wb
            .formula(sheet, pos)
            .map(|text| FileFormula { text: text.trim_start_matches('=').to_string(), dynamic: false }),
    }
}

/// A cell's formula as a file stores it: dynamic when it must be, legacy otherwise.
pub fn cell_to_file_as_needed(wb: &Workbook, sheet: SheetId, pos: Pos) -> Option<String> {
    let legacy = cell_to_file(wb, sheet, pos, Storage::Legacy)?;
    Some(match legacy.dynamic {
        true => cell_to_file(wb, sheet, pos, Storage::Dynamic)?.text,
        false => legacy.text,
    })
}

/// Whether `text` has `NAME(` for one of `names`, in any case. Looks only before each `(`:
/// this runs on every formula of an import.
pub(super) fn calls_any(text: &str, names: &[&str]) -> bool {
    let bytes = text.as_bytes();
    memchr::memchr_iter(b'(', bytes).any(|paren| {
        names
            .iter()
            .any(|name| paren >= name.len() && bytes[paren - name.len()..paren].eq_ignore_ascii_case(name.as_bytes()))
    })
}

/// Excel evaluates a formula that is not an array formula (`<f>` without `t="array"`) the
/// pre-2019 way: a range where one value is expected is cut to the cell in line with the
/// formula (implicit intersection); Excel 365 shows that as `@`. Given such a formula that
/// produced an array here, returns it with `@` where Excel intersected, or `None` when
/// nothing changes. Which arguments take whole ranges or arrays is the registry's
/// (`FnSpec::array_args`, `FnSpec::range_args`); the rule runs only on formulas that
/// produced arrays, so a function marked wrongly costs at most that one cell.
pub fn legacy_intersection(tree: &Expr, wb: &Workbook, sheet: SheetId) -> Option<Expr> {
    let mut expr = tree.clone();
    let mut changed = false;
    intersect(&mut expr, wb, sheet, &mut changed);
    changed.then_some(expr)
}

/// A legacy formula whose result is still an array, intersected as a whole (`@ROW(A3:A8)`,
/// `@(x+{1,2})`): as Excel shows such a result, a reference in line with the cell or an
/// array's first item. Written back to a file, the `@` is left out again.
pub fn whole_intersection(tree: &Expr) -> Option<Expr> {
    if matches!(tree.kind, ExprKind::Unary(UnaryOp::Implicit, _)) {
        return None;
    }
    let mut expr = tree.clone();
    if !matches!(
        expr.kind,
        ExprKind::Ref(_) | ExprKind::Table(_) | ExprKind::Name(_) | ExprKind::Call(..) | ExprKind::Paren(_)
    ) {
        let span = expr.span;
        expr = Expr::new(ExprKind::Paren(Box::new(expr)), span);
    }
    wrap_implicit(&mut expr, &mut false);
    Some(expr)
}

/// Whether a legacy formula with a single value for a result still has a range that Excel
/// intersects (`SUM(A1:A9*2)`, `MAX(IF(B1:B9>0,1))` outside an array formula): its value
/// differs from ours unless rewritten by [`legacy_intersection`]. A formula calling a
/// function newer than Excel 2010 or one we lack is left alone: which of their arguments
/// take arrays is less certain than the legacy ones'.
pub fn intersects_in_scalar_formula(expr: &Expr, wb: &Workbook, sheet: SheetId) -> bool {
    let mut newer = false;
    expr.visit(&mut |e| match &e.kind {
        ExprKind::Call(id, _) => newer |= spec(*id).file_prefix.as_str() != "",
        ExprKind::UnknownCall(..) => newer = true,
        _ => {}
    });
    if newer {
        return false;
    }
    let mut copy = expr.clone();
    let mut changed = false;
    intersect_operands(&mut copy, wb, sheet, false, &mut changed);
    changed
}

/// [`intersects_in_scalar_formula`]'s rewrite: `@` on the ranges that are operands of an
/// operator, or `None` when there are none.
pub fn legacy_operand_intersection(tree: &Expr, wb: &Workbook, sheet: SheetId) -> Option<Expr> {
    let mut expr = tree.clone();
    let mut changed = false;
    intersect_operands(&mut expr, wb, sheet, false, &mut changed);
    changed.then_some(expr)
}

/// Puts `@` on the ranges under `e` that are operands of an arithmetic, comparison or
/// text operator (`operand`: `e` is one), where Excel always intersects outside an array
/// formula; nothing under an argument that takes arrays. A range handed to a function as it
/// stands is left alone: whether the function takes it whole is the registry's.
fn intersect_operands(e: &mut Expr, wb: &Workbook, sheet: SheetId, operand: bool, changed: &mut bool) {
    match &mut e.kind {
        ExprKind::Ref(r) if operand && !matches!(r.shape, RefShape::Cell(_)) => wrap_implicit(e, changed),
        ExprKind::Table(r) if operand && !one_cell(r) => wrap_implicit(e, changed),
        ExprKind::Binary(op, ..) if operand && is_reference_op(*op) => wrap_implicit(e, changed),
        ExprKind::Name(n) if operand && names_a_range(wb, n, sheet) => wrap_implicit(e, changed),
        ExprKind::Paren(x) => intersect_operands(x, wb, sheet, operand, changed),
        ExprKind::Unary(UnaryOp::Neg | UnaryOp::Plus | UnaryOp::Percent, x) => {
            intersect_operands(x, wb, sheet, true, changed)
        }
        ExprKind::Binary(op, a, b) if !is_reference_op(*op) => {
            intersect_operands(a, wb, sheet, true, changed);
            intersect_operands(b, wb, sheet, true, changed);
        }
        ExprKind::Call(id, args) => {
            let f = spec(*id);
            for (i, arg) in args.iter_mut().enumerate() {
                if !f.array_args.contains(i) {
                    intersect_operands(arg, wb, sheet, false, changed);
                }
            }
        }
        ExprKind::UnknownCall(_, args) => {
            args.iter_mut().for_each(|arg| intersect_operands(arg, wb, sheet, false, changed))
        }
        _ => {}
    }
}

/// Puts `@` on the ranges under `e` that Excel intersects, `e` being where one value is
/// expected. Nothing under an argument that takes arrays is intersected.
fn intersect(e: &mut Expr, wb: &Workbook, sheet: SheetId, changed: &mut bool) {
    match &mut e.kind {
        ExprKind::Ref(r) if !matches!(r.shape, RefShape::Cell(_)) => wrap_implicit(e, changed),
        ExprKind::Table(r) if !one_cell(r) => wrap_implicit(e, changed),
        ExprKind::Binary(op, ..) if is_reference_op(*op) => wrap_implicit(e, changed),
        ExprKind::Name(n) if names_a_range(wb, n, sheet) => wrap_implicit(e, changed),
        ExprKind::Paren(x) => intersect(x, wb, sheet, changed),
        ExprKind::Unary(UnaryOp::Neg | UnaryOp::Plus | UnaryOp::Percent, x) => intersect(x, wb, sheet, changed),
        ExprKind::Binary(_, a, b) => {
            intersect(a, wb, sheet, changed);
            intersect(b, wb, sheet, changed);
        }
        ExprKind::Call(id, args) => {
            let f = spec(*id);
            for (i, arg) in args.iter_mut().enumerate() {
                if f.array_args.contains(i) || (is_bare_range(arg) && f.range_args.contains(i)) {
                    continue;
                }
                intersect(arg, wb, sheet, changed);
            }
        }
        // What a function we lack takes is unknown; it evaluates to #NAME? anyway.
        ExprKind::UnknownCall(_, args) => args.iter_mut().for_each(|arg| intersect(arg, wb, sheet, changed)),
        _ => {}
    }
}

/// A structured reference to one cell, its own row's in one column (`Parts[@Qty]`), which
/// Excel never intersects.
fn one_cell(r: &crate::formula::ast::TableRef) -> bool {
    r.rows.this_row && r.columns.as_ref().is_some_and(|(first, last)| first.eq_ignore_ascii_case(last))
}

fn wrap_implicit(e: &mut Expr, changed: &mut bool) {
    let span = e.span;
    let inner = std::mem::replace(e, Expr::new(ExprKind::Missing, span));
    *e = Expr::new(ExprKind::Unary(UnaryOp::Implicit, Box::new(inner)), span);
    *changed = true;
}

/// `:`, space and `,`: operators on references whose result is a reference.
fn is_reference_op(op: BinOp) -> bool {
    matches!(op, BinOp::Range | BinOp::Intersect | BinOp::Union)
}

fn is_bare_range(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Ref(_) | ExprKind::Name(_) | ExprKind::Table(_) => true,
        ExprKind::Binary(op, ..) if is_reference_op(*op) => true,
        ExprKind::Paren(x) => is_bare_range(x),
        _ => false,
    }
}

fn names_a_range(wb: &Workbook, name: &str, sheet: SheetId) -> bool {
    use crate::eval::Env;
    Env::defined_name(wb, name, sheet).is_some_and(|(expr, _)| match &expr.kind {
        ExprKind::Ref(r) => !matches!(r.shape, RefShape::Cell(_)),
        ExprKind::Binary(op, ..) => is_reference_op(*op),
        // A table's name alone is its data.
        ExprKind::Table(_) => true,
        _ => false,
    })
}

/// `ANCHORARRAY(x)` → `x#`, `SINGLE(x)` → `@x`, everywhere in the tree.
fn operators_from_file(e: &mut Expr) {
    match &mut e.kind {
        ExprKind::Unary(_, x) | ExprKind::Paren(x) => operators_from_file(x),
        ExprKind::Binary(_, a, b) => {
            operators_from_file(a);
            operators_from_file(b);
        }
        ExprKind::Call(_, args) | ExprKind::UnknownCall(_, args) => args.iter_mut().for_each(operators_from_file),
        ExprKind::Invoke(callee, args) => {
            operators_from_file(callee);
            args.iter_mut().for_each(operators_from_file);
        }
        _ => {}
    }
    let name: &str = match &e.kind {
        ExprKind::Call(id, args) if args.len() == 1 => spec(*id).name,
        ExprKind::UnknownCall(name, args) if args.len() == 1 => strip_future_prefix(name),
        _ => return,
    };
    let op = if name.eq_ignore_ascii_case("ANCHORARRAY") {
        UnaryOp::Spill
    } else if name.eq_ignore_ascii_case("SINGLE") {
        UnaryOp::Implicit
    } else {
        return;
    };
    let arg = match std::mem::replace(&mut e.kind, ExprKind::Missing) {
        ExprKind::Call(_, mut args) | ExprKind::UnknownCall(_, mut args) => args.pop().expect("one argument"),
        _ => unreachable!("matched a call above"),
    };
    let arg = match arg.kind {
        ExprKind::Ref(_)
        | ExprKind::Table(_)
        | ExprKind::Name(_)
        | ExprKind::Call(..)
        | ExprKind::UnknownCall(..)
        | ExprKind::Paren(_) => arg,
        _ => {
            let span = arg.span;
            Expr::new(ExprKind::Paren(Box::new(arg)), span)
        }
    };
    e.kind = ExprKind::Unary(op, Box::new(arg));
}

/// Excel's spelling of a formula in a file stored as `storage`.
struct FileSpelling {
    storage: Storage,
    /// Set when the text written makes the formula a dynamic-array formula.
    dynamic: std::cell::Cell<bool>,
}

impl Spelling for FileSpelling {
    /// A known function is spelled as its registry row says; an unknown one kept the
    /// prefix it was read with.
    fn function_name(&self, name: &str, out: &mut String) {
        if let Some(f) = find(name).map(spec) {
            out.push_str(f.file_prefix.as_str());
            self.dynamic.set(self.dynamic.get() || f.dynamic);
        }
        out.push_str(name);
    }

    fn parameter_name(&self, name: &str, out: &mut String) {
        out.push_str("_xlpm.");
        out.push_str(name);
    }

    fn optional_parameter(&self, name: &str, out: &mut String) {
        out.push_str("_xlop.");
        out.push_str(name);
    }

    fn implicit_intersection(&self, in_call: bool) -> OperatorSpelling {
        if self.storage == Storage::Legacy && !in_call {
            OperatorSpelling::Omitted
        } else {
            self.dynamic.set(true);
            OperatorSpelling::Function("_xlfn.SINGLE")
        }
    }

    fn this_row_as_at(&self) -> bool {
        false
    }

    fn spill(&self) -> OperatorSpelling {
        self.dynamic.set(true);
        OperatorSpelling::Function("_xlfn.ANCHORARRAY")
    }
}

/// Prints `expr`, held by the cell `pos`, in `spelling`, naming sheets as `wb` does.
fn print(expr: &Expr, wb: &Workbook, pos: Pos, spelling: &dyn Spelling) -> String {
    let names = wb.sheet_names();
    let sheet_name = |id: SheetId| names.get(id as usize).cloned().unwrap_or_else(|| "#REF".into());
    print_spelled(expr, pos, &Registry, &sheet_name, spelling)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formula::print::AsTyped;

    /// Typed formula text as a file stores it.
    fn file_text(text: &str, wb: &Workbook, sheet: SheetId, at: Pos, storage: Storage) -> String {
        to_file(&wb.parse_at(text, sheet, at).unwrap(), wb, at, storage).text
    }

    fn book() -> Workbook {
        let mut wb = Workbook::with_sheet();
        wb.add_sheet("Data sheet").unwrap();
        wb
    }

    #[test]
    fn spill_and_implicit_intersection_come_back_as_operators() {
        let wb = book();
        let at = Pos::new(4, 2);
        let typed = |text: &str| tree_from_file(text, &wb, 0, at).map(|e| print(&e, &wb, at, &AsTyped));
        assert_eq!(typed("SUM(_xlfn.ANCHORARRAY(A1))").as_deref(), Some("SUM(A1#)"));
        assert_eq!(typed("_xlfn.SINGLE(A1:A9)*2").as_deref(), Some("@A1:A9*2"));
        assert_eq!(typed("_xlfn.SINGLE(A1+1)").as_deref(), Some("@(A1+1)"));
        assert_eq!(typed("SUM('Data sheet'!A1:B2)"), None);
        let in_place = "_xlfn.LAMBDA(_xlpm.x,SUM(_xlpm.x))(_xlfn.ANCHORARRAY(A1))";
        assert_eq!(typed(in_place).as_deref(), Some("LAMBDA(x,SUM(x))(A1#)"));
    }

    #[test]
    fn newer_functions_parameters_and_operators_get_their_file_spelling() {
        let wb = book();
        let at = Pos::new(0, 0);
        let to_file = |text: &str, wb: &Workbook, sheet, at| file_text(text, wb, sheet, at, Storage::Dynamic);
        assert_eq!(to_file("=SUM(A1:A3)+SIN(1)", &wb, 0, at), "SUM(A1:A3)+SIN(1)");
        assert_eq!(to_file("=CONCAT(\"x#\",A1)", &wb, 0, at), "_xlfn.CONCAT(\"x#\",A1)");
        assert_eq!(to_file("=SUM(A1#)", &wb, 0, at), "SUM(_xlfn.ANCHORARRAY(A1))");
        assert_eq!(to_file("=@A1:A3", &wb, 0, at), "_xlfn.SINGLE(A1:A3)");
        let filter = "_xlfn._xlws.FILTER(A1:A3,A1:A3>1)";
        assert_eq!(to_file(&format!("={filter}"), &wb, 0, at), filter);
        assert_eq!(
            to_file("=LET(x,2,y,x+1,x*y)+x", &wb, 0, at),
            "_xlfn.LET(_xlpm.x,2,_xlpm.y,_xlpm.x+1,_xlpm.x*_xlpm.y)+x"
        );
        assert_eq!(to_file("='Data sheet'!B2#", &wb, 0, at), "_xlfn.ANCHORARRAY('Data sheet'!B2)");
        assert_eq!(to_file("=IF(A1=#N/A,1,2)", &wb, 0, at), "IF(A1=#N/A,1,2)");
        let dynamic = |text: &str| super::to_file(&wb.parse_at(text, 0, at).unwrap(), &wb, at, Storage::Legacy).dynamic;
        assert!(dynamic("=SEQUENCE(3)+1"));
        assert!(dynamic("=SUM(A1#)"));
        assert!(!dynamic("=SUM(A1:A3)&\"SEQUENCE(\""));
        assert!(!dynamic("=@A1:A3"));
        // Functions we lack keep the prefix they were read with, going back to a file.
        assert_eq!(to_file("=_xlfn.STOCKHISTORY(\"X\",1)+1", &wb, 0, at), "_xlfn.STOCKHISTORY(\"X\",1)+1");
        assert_eq!(to_file("=_xlfn._xlws.NOSUCH(A1)", &wb, 0, at), "_xlfn._xlws.NOSUCH(A1)");
        assert_eq!(to_file("=NOSUCH(A1)", &wb, 0, at), "NOSUCH(A1)");
        // calc_tests/INFORMATION/ISOMITTED.xlsx's A6 as Excel stored it: an optional
        // parameter (`[b]` as typed) and a LAMBDA called in place.
        let stored = "_xlfn.LAMBDA(_xlpm.a,_xlop.b,IF(_xlfn.ISOMITTED(_xlpm.b),_xlpm.a/2,_xlpm.a*_xlpm.b))(A5)";
        let typed = "LAMBDA(a,[b],IF(ISOMITTED(b),a/2,a*b))(A5)";
        assert_eq!(print(&wb.parse_at(stored, 0, at).unwrap(), &wb, at, &AsTyped), typed);
        assert_eq!(to_file(&format!("={typed}"), &wb, 0, at), stored);
        assert!(super::to_file(&wb.parse_at(typed, 0, at).unwrap(), &wb, at, Storage::Legacy).dynamic);
    }

    #[test]
    fn operators_spelled_as_functions_keep_their_operands_grouped() {
        let wb = book();
        let at = Pos::new(0, 0);
        let dynamic = |text| file_text(text, &wb, 0, at, Storage::Dynamic);
        assert_eq!(dynamic("=(A1#+1)*2"), "(_xlfn.ANCHORARRAY(A1)+1)*2");
        assert_eq!(dynamic("=@(A1:A3+1)*2"), "_xlfn.SINGLE(A1:A3+1)*2");
        assert_eq!(dynamic("=LAMBDA(temp,(5/9)*(temp-32))"), "_xlfn.LAMBDA(_xlpm.temp,(5/9)*(_xlpm.temp-32))");
        // A LAMBDA bound by LET is called by its parameter name.
        assert_eq!(
            dynamic("=LET(F,LAMBDA(t,t+1),F(2))"),
            "_xlfn.LET(_xlpm.F,_xlfn.LAMBDA(_xlpm.t,_xlpm.t+1),_xlpm.F(2))"
        );
        assert_eq!(file_text("=@A1:A3*2", &wb, 0, at, Storage::Legacy), "A1:A3*2");
    }

    #[test]
    fn legacy_formulas_intersect_where_excel_did_and_are_written_back_without_at() {
        let wb = book();
        let at = Pos::new(17, 0);
        let legacy = |text| {
            let tree = legacy_intersection(&wb.parse_at(text, 0, at).unwrap(), &wb, 0)?;
            Some(print(&tree, &wb, at, &AsTyped))
        };
        assert_eq!(legacy("E15:E19").as_deref(), Some("@E15:E19"));
        assert_eq!(legacy("AM:AM*2").as_deref(), Some("@AM:AM*2"));
        assert_eq!(legacy("SUM(E15:E19)"), None);
        assert_eq!(legacy("SIN(E15:E19)").as_deref(), Some("SIN(@E15:E19)"));
        assert_eq!(legacy("SUM(E15:E19*2)").as_deref(), Some("SUM(@E15:E19*2)"));
        assert_eq!(legacy("SUMPRODUCT(E15:E19*F15:F19)"), None);
        assert_eq!(legacy("IF(A1,B1:B5,2)").as_deref(), Some("IF(A1,@B1:B5,2)"));
        // Formulas with one value for a result: Excel intersects a range under an operator
        // whose result a function takes as one value.
        let parsed = |text| wb.parse_at(text, 0, at).unwrap();
        let scalar = |text| intersects_in_scalar_formula(&parsed(text), &wb, 0);
        assert!(scalar("SUM(E15:E19*2)"));
        assert!(scalar("MAX(IF(E15:E19>0,1,0))"));
        assert!(!scalar("SUM(E15:E19)+COUNTIF(E:E,\">1\")"));
        assert!(!scalar("SUM(CHOOSE(2,E1:E2,E1:E3))+WORKDAY(E1,6,F2:F5)"));
        let typed = |tree: Expr| print(&tree, &wb, at, &AsTyped);
        let operands = |text| legacy_operand_intersection(&parsed(text), &wb, 0).map(typed);
        assert_eq!(operands("SUM(E15:E19*2)").as_deref(), Some("SUM(@E15:E19*2)"));
        assert!(!scalar("SUMPRODUCT(E15:E19*F15:F19)+VLOOKUP(1,E1:F9,2,0)+INDEX(E1:E9*2,2)"));
        assert!(!scalar("_xlfn.XLOOKUP(1,E1:E9*2,F1:F9)"));
        // A result still an array is intersected whole; the file gets the formula back.
        let whole = |text| typed(whole_intersection(&parsed(text)).unwrap());
        assert_eq!(whole("ROW(A3:A8)"), "@ROW(A3:A8)");
        assert_eq!(whole("{1,2}+1"), "@({1,2}+1)");
        assert_eq!(whole("({1,2}+1)"), "@({1,2}+1)");
        assert!(whole_intersection(&parsed("@ROW(A3:A8)")).is_none());
        let written = |text| file_text(text, &wb, 0, at, Storage::Legacy);
        assert_eq!(written("=@ROW(A3:A8)"), "ROW(A3:A8)");
        assert_eq!(written("=@E15:E19*2"), "E15:E19*2");
        assert_eq!(written("=SIN(@E15:E19)"), "SIN(_xlfn.SINGLE(E15:E19))");
    }
}
