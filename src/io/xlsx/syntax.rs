//! Formula spelling in xlsx files versus the spelling a user types.
//!
//! Excel stores functions newer than Excel 2007 with a `_xlfn.` prefix (`_xlfn._xlws.` for
//! FILTER and SORT), LET and LAMBDA parameters with `_xlpm.`, the spill operator `A1#` as
//! `_xlfn.ANCHORARRAY(A1)` and the implicit intersection `@x` as `_xlfn.SINGLE(x)`. Our
//! parser drops the prefixes by itself; this module turns ANCHORARRAY and SINGLE back into
//! operators on import, and writes all of it back on export. Export prints through the one
//! printer of `formula::print`: `FileSpelling` only says how names and the two operators
//! are spelled, so parentheses and every other node are printed as for the formula typed.
//!
//! Both directions take a fast path: text that has none of these needs no parse.

use std::borrow::Cow;

use crate::eval::functions::{spec, Registry};
use crate::formula::address::Pos;
use crate::formula::ast::*;
use crate::formula::print::{print_spelled, AsTyped, OperatorSpelling, Spelling};
use crate::workbook::Workbook;

/// A formula as stored in a file (no leading `=`) → as typed (no leading `=`).
pub fn from_file<'t>(text: &'t str, wb: &Workbook, sheet: SheetId, pos: Pos) -> Cow<'t, str> {
    if !calls_any(text, &["ANCHORARRAY", "SINGLE"]) {
        return Cow::Borrowed(text);
    }
    let Ok(mut expr) = wb.parse_at(text, sheet, pos) else { return Cow::Borrowed(text) };
    operators_from_file(&mut expr);
    Cow::Owned(print(&expr, wb, pos, &AsTyped))
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

/// A cell's formula (`=…`, as [`Workbook::formula`] prints it) → as stored in a file.
pub fn to_file(formula: &str, wb: &Workbook, sheet: SheetId, pos: Pos, storage: Storage) -> String {
    let text = formula.strip_prefix('=').unwrap_or(formula);
    if !needs_file_spelling(text) {
        return text.to_string();
    }
    match wb.parse_at(text, sheet, pos) {
        Ok(expr) => print(&expr, wb, pos, &FileSpelling { storage }),
        // Text that does not parse (a table reference, an external link) goes back as it came.
        Err(_) => text.to_string(),
    }
}

/// Whether file-spelled formula text calls a function that makes rust_xlsxwriter (and
/// Excel) store the formula as a dynamic array.
pub fn calls_dynamic_function(file_text: &str) -> bool {
    const DYNAMIC: &[&str] = &[
        "ANCHORARRAY",
        "BYCOL",
        "BYROW",
        "CHOOSECOLS",
        "CHOOSEROWS",
        "DROP",
        "EXPAND",
        "FILTER",
        "HSTACK",
        "LAMBDA",
        "MAKEARRAY",
        "MAP",
        "PY",
        "QUERYSTRING",
        "RANDARRAY",
        "REDUCE",
        "SCAN",
        "SEQUENCE",
        "SINGLE",
        "SORT",
        "SORTBY",
        "SWITCH",
        "TAKE",
        "TEXTSPLIT",
        "TOCOL",
        "TOROW",
        "UNIQUE",
        "VSTACK",
        "WRAPCOLS",
        "WRAPROWS",
        "XLOOKUP",
    ];
    let mut found = false;
    for_each_call(file_text, &mut |name| {
        let name = name.rsplit('.').next().unwrap_or(name);
        found |= DYNAMIC.iter().any(|d| d.eq_ignore_ascii_case(name));
    });
    found
}

/// Calls `f` with each name directly followed by `(` outside string literals and quoted
/// sheet names.
fn for_each_call(text: &str, f: &mut dyn FnMut(&str)) {
    let b = text.as_bytes();
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            q @ (b'"' | b'\'') => {
                i += 1;
                while i < b.len() {
                    if b[i] == q {
                        if b.get(i + 1) == Some(&q) {
                            i += 1;
                        } else {
                            break;
                        }
                    }
                    i += 1;
                }
            }
            c if c.is_ascii_alphabetic() || c == b'_' => {
                let start = i;
                while i < b.len() && (b[i].is_ascii_alphanumeric() || matches!(b[i], b'_' | b'.')) {
                    i += 1;
                }
                if b.get(i) == Some(&b'(') {
                    f(&text[start..i]);
                }
                continue;
            }
            _ => {}
        }
        i += 1;
    }
}

/// Whether `text` has `NAME(` for one of `names`, in any case. Looks only before each `(`:
/// this runs on every formula of an import.
fn calls_any(text: &str, names: &[&str]) -> bool {
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
/// nothing changes. Which arguments take whole ranges or arrays comes from the small
/// tables below; the rule runs only on formulas that produced arrays, so a function
/// missing from them costs at most that one cell.
pub fn legacy_intersection(text: &str, wb: &Workbook, sheet: SheetId, pos: Pos) -> Option<String> {
    let mut expr = wb.parse_at(text, sheet, pos).ok()?;
    let mut changed = false;
    intersect(&mut expr, wb, sheet, &mut changed);
    if !changed {
        return None;
    }
    Some(print(&expr, wb, pos, &AsTyped))
}

/// Puts `@` on the ranges under `e` that Excel intersects, `e` being where one value is
/// expected. Nothing under an argument that takes arrays is intersected.
fn intersect(e: &mut Expr, wb: &Workbook, sheet: SheetId, changed: &mut bool) {
    match &mut e.kind {
        ExprKind::Ref(r) if !matches!(r.shape, RefShape::Cell(_)) => wrap_implicit(e, changed),
        ExprKind::Binary(BinOp::Range, ..) => wrap_implicit(e, changed),
        ExprKind::Name(n) if names_a_range(wb, n, sheet) => wrap_implicit(e, changed),
        ExprKind::Paren(x) => intersect(x, wb, sheet, changed),
        ExprKind::Unary(UnaryOp::Neg | UnaryOp::Plus | UnaryOp::Percent, x) => intersect(x, wb, sheet, changed),
        ExprKind::Binary(_, a, b) => {
            intersect(a, wb, sheet, changed);
            intersect(b, wb, sheet, changed);
        }
        ExprKind::Call(..) | ExprKind::UnknownCall(..) => {
            let name = match &e.kind {
                ExprKind::Call(id, _) => spec(*id).name.to_ascii_uppercase(),
                ExprKind::UnknownCall(name, _) => name.to_ascii_uppercase(),
                _ => unreachable!("matched a call"),
            };
            let (ExprKind::Call(_, args) | ExprKind::UnknownCall(_, args)) = &mut e.kind else { unreachable!() };
            for (i, arg) in args.iter_mut().enumerate() {
                if takes_array(&name, i) || (is_bare_range(arg) && takes_range(&name, i)) {
                    continue;
                }
                intersect(arg, wb, sheet, changed);
            }
        }
        _ => {}
    }
}

fn wrap_implicit(e: &mut Expr, changed: &mut bool) {
    let span = e.span;
    let inner = std::mem::replace(e, Expr::new(ExprKind::Missing, span));
    *e = Expr::new(ExprKind::Unary(UnaryOp::Implicit, Box::new(inner)), span);
    *changed = true;
}

fn is_bare_range(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Ref(_) | ExprKind::Name(_) | ExprKind::Binary(BinOp::Range, ..) => true,
        ExprKind::Paren(x) => is_bare_range(x),
        _ => false,
    }
}

fn names_a_range(wb: &Workbook, name: &str, sheet: SheetId) -> bool {
    use crate::eval::Env;
    Env::defined_name(wb, name, sheet).is_some_and(|(expr, _)| match &expr.kind {
        ExprKind::Ref(r) => !matches!(r.shape, RefShape::Cell(_)),
        ExprKind::Binary(BinOp::Range, ..) => true,
        _ => false,
    })
}

/// Arguments evaluated as arrays even in a pre-2019 formula.
fn takes_array(name: &str, i: usize) -> bool {
    match name {
        "SUMPRODUCT" | "MMULT" | "MDETERM" | "MINVERSE" | "TRANSPOSE" | "FREQUENCY" | "LINEST" | "LOGEST" | "TREND"
        | "GROWTH" | "SUMX2MY2" | "SUMX2PY2" | "SUMXMY2" => true,
        "INDEX" => i == 0,
        "MATCH" | "VLOOKUP" | "HLOOKUP" | "XMATCH" => i == 1,
        "LOOKUP" => i >= 1,
        _ => false,
    }
}

/// Arguments that take a whole range (an aggregate, a lookup table, a reference).
fn takes_range(name: &str, i: usize) -> bool {
    match name {
        "SUM" | "SUMSQ" | "AVERAGE" | "AVERAGEA" | "COUNT" | "COUNTA" | "COUNTBLANK" | "MAX" | "MAXA" | "MIN"
        | "MINA" | "PRODUCT" | "MEDIAN" | "MODE" | "MODE.SNGL" | "MODE.MULT" | "STDEV" | "STDEV.S" | "STDEV.P"
        | "STDEVA" | "STDEVP" | "STDEVPA" | "VAR" | "VAR.S" | "VAR.P" | "VARA" | "VARP" | "VARPA" | "AVEDEV"
        | "DEVSQ" | "GEOMEAN" | "HARMEAN" | "KURT" | "SKEW" | "SKEW.P" | "AND" | "OR" | "XOR" | "CONCAT" | "SUMIFS"
        | "COUNTIFS" | "AVERAGEIFS" | "MAXIFS" | "MINIFS" | "ROWS" | "COLUMNS" | "AREAS" | "NPV" | "CORREL"
        | "COVAR" | "COVARIANCE.P" | "COVARIANCE.S" | "PEARSON" | "RSQ" | "SLOPE" | "INTERCEPT" | "STEYX"
        | "FORECAST" | "FORECAST.LINEAR" | "PROB" | "IRR" | "MIRR" | "XNPV" | "XIRR" | "T.TEST" | "TTEST"
        | "F.TEST" | "FTEST" | "CHISQ.TEST" | "CHITEST" | "Z.TEST" | "ZTEST" | "DSUM" | "DCOUNT" | "DCOUNTA"
        | "DAVERAGE" | "DMAX" | "DMIN" | "DGET" | "DPRODUCT" | "DSTDEV" | "DSTDEVP" | "DVAR" | "DVARP" => true,
        "LARGE" | "SMALL" | "PERCENTILE" | "PERCENTILE.INC" | "PERCENTILE.EXC" | "QUARTILE" | "QUARTILE.INC"
        | "QUARTILE.EXC" | "PERCENTRANK" | "PERCENTRANK.INC" | "PERCENTRANK.EXC" | "TRIMMEAN" | "OFFSET" | "ROW"
        | "COLUMN" | "CELL" | "ISREF" | "ISFORMULA" | "FORMULATEXT" | "SHEET" | "COUNTIF" => i == 0,
        "RANK" | "RANK.EQ" | "RANK.AVG" | "SUBTOTAL" => i >= 1,
        "SUMIF" | "AVERAGEIF" => i != 1,
        "TEXTJOIN" | "AGGREGATE" => i >= 2,
        _ => false,
    }
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
        _ => {}
    }
    let name: &str = match &e.kind {
        ExprKind::Call(id, args) if args.len() == 1 => spec(*id).name,
        ExprKind::UnknownCall(name, args) if args.len() == 1 => name,
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
        ExprKind::Ref(_) | ExprKind::Name(_) | ExprKind::Call(..) | ExprKind::UnknownCall(..) | ExprKind::Paren(_) => {
            arg
        }
        _ => {
            let span = arg.span;
            Expr::new(ExprKind::Paren(Box::new(arg)), span)
        }
    };
    e.kind = ExprKind::Unary(op, Box::new(arg));
}

/// Whether typed text differs from its file spelling: it has `#` or `@` outside strings, or
/// calls a function Excel prefixes (LET and LAMBDA included, for their parameters).
fn needs_file_spelling(text: &str) -> bool {
    let mut quote = None;
    for c in text.bytes() {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None if c == b'"' || c == b'\'' => quote = Some(c),
            None if c == b'#' || c == b'@' => return true,
            None => {}
        }
    }
    let mut found = false;
    for_each_call(text, &mut |name| found |= future_prefix(name).is_some());
    found
}

/// The prefix Excel stores before a function name, if any.
pub fn future_prefix(name: &str) -> Option<&'static str> {
    if ["FILTER", "SORT", "PY"].iter().any(|f| f.eq_ignore_ascii_case(name)) {
        return Some("_xlfn._xlws.");
    }
    let upper = name.bytes().map(|b| b.to_ascii_uppercase());
    FUTURE_FUNCTIONS.binary_search_by(|f| f.bytes().cmp(upper.clone())).is_ok().then_some("_xlfn.")
}

/// Functions Excel stores with `_xlfn.` (added after Excel 2007), sorted: rust_xlsxwriter's
/// list and the newer ones the Excel corpus shows (REGEX…, TRIMRANGE). Not ISO.CEILING,
/// which Excel stores bare.
static FUTURE_FUNCTIONS: &[&str] = &[
    "ACOT",
    "ACOTH",
    "AGGREGATE",
    "ANCHORARRAY",
    "ARABIC",
    "ARRAYTOTEXT",
    "BASE",
    "BETA.DIST",
    "BETA.INV",
    "BINOM.DIST",
    "BINOM.DIST.RANGE",
    "BINOM.INV",
    "BITAND",
    "BITLSHIFT",
    "BITOR",
    "BITRSHIFT",
    "BITXOR",
    "BYCOL",
    "BYROW",
    "CEILING.MATH",
    "CEILING.PRECISE",
    "CHISQ.DIST",
    "CHISQ.DIST.RT",
    "CHISQ.INV",
    "CHISQ.INV.RT",
    "CHISQ.TEST",
    "CHOOSECOLS",
    "CHOOSEROWS",
    "COMBINA",
    "CONCAT",
    "CONFIDENCE.NORM",
    "CONFIDENCE.T",
    "COT",
    "COTH",
    "COVARIANCE.P",
    "COVARIANCE.S",
    "CSC",
    "CSCH",
    "DAYS",
    "DECIMAL",
    "DETECTLANGUAGE",
    "DROP",
    "ENCODEURL",
    "ERF.PRECISE",
    "ERFC.PRECISE",
    "EXPAND",
    "EXPON.DIST",
    "F.DIST",
    "F.DIST.RT",
    "F.INV",
    "F.INV.RT",
    "F.TEST",
    "FIELDVALUE",
    "FILTERXML",
    "FLOOR.MATH",
    "FLOOR.PRECISE",
    "FORECAST.ETS",
    "FORECAST.ETS.CONFINT",
    "FORECAST.ETS.SEASONALITY",
    "FORECAST.ETS.STAT",
    "FORECAST.LINEAR",
    "FORMULATEXT",
    "GAMMA",
    "GAMMA.DIST",
    "GAMMA.INV",
    "GAMMALN.PRECISE",
    "GAUSS",
    "GROUPBY",
    "HSTACK",
    "HYPGEOM.DIST",
    "IFNA",
    "IFS",
    "IMAGE",
    "IMCOSH",
    "IMCOT",
    "IMCSC",
    "IMCSCH",
    "IMSEC",
    "IMSECH",
    "IMSINH",
    "IMTAN",
    "ISFORMULA",
    "ISOMITTED",
    "ISOWEEKNUM",
    "LAMBDA",
    "LET",
    "LOGNORM.DIST",
    "LOGNORM.INV",
    "MAKEARRAY",
    "MAP",
    "MAXIFS",
    "MINIFS",
    "MODE.MULT",
    "MODE.SNGL",
    "MUNIT",
    "NEGBINOM.DIST",
    "NORM.DIST",
    "NORM.INV",
    "NORM.S.DIST",
    "NORM.S.INV",
    "NUMBERVALUE",
    "PDURATION",
    "PERCENTILE.EXC",
    "PERCENTILE.INC",
    "PERCENTOF",
    "PERCENTRANK.EXC",
    "PERCENTRANK.INC",
    "PERMUTATIONA",
    "PHI",
    "PIVOTBY",
    "POISSON.DIST",
    "PQSOURCE",
    "PYTHON_STR",
    "PYTHON_TYPE",
    "PYTHON_TYPENAME",
    "QUARTILE.EXC",
    "QUARTILE.INC",
    "QUERYSTRING",
    "RANDARRAY",
    "RANK.AVG",
    "RANK.EQ",
    "REDUCE",
    "REGEXEXTRACT",
    "REGEXREPLACE",
    "REGEXTEST",
    "RRI",
    "SCAN",
    "SEC",
    "SECH",
    "SEQUENCE",
    "SHEET",
    "SHEETS",
    "SINGLE",
    "SKEW.P",
    "SORTBY",
    "STDEV.P",
    "STDEV.S",
    "STOCKHISTORY",
    "SWITCH",
    "T.DIST",
    "T.DIST.2T",
    "T.DIST.RT",
    "T.INV",
    "T.INV.2T",
    "T.TEST",
    "TAKE",
    "TEXTAFTER",
    "TEXTBEFORE",
    "TEXTJOIN",
    "TEXTSPLIT",
    "TOCOL",
    "TOROW",
    "TRANSLATE",
    "TRIMRANGE",
    "UNICHAR",
    "UNICODE",
    "UNIQUE",
    "VALUETOTEXT",
    "VAR.P",
    "VAR.S",
    "VSTACK",
    "WEBSERVICE",
    "WEIBULL.DIST",
    "WRAPCOLS",
    "WRAPROWS",
    "XLOOKUP",
    "XMATCH",
    "XOR",
    "Z.TEST",
];

/// Excel's spelling of a formula in a file stored as `storage`.
struct FileSpelling {
    storage: Storage,
}

impl Spelling for FileSpelling {
    fn function_name(&self, name: &str, out: &mut String) {
        if let Some(prefix) = future_prefix(name) {
            out.push_str(prefix);
        }
        out.push_str(name);
    }

    fn parameter_name(&self, name: &str, out: &mut String) {
        out.push_str("_xlpm.");
        out.push_str(name);
    }

    fn implicit_intersection(&self, in_call: bool) -> OperatorSpelling {
        if self.storage == Storage::Legacy && !in_call {
            OperatorSpelling::Omitted
        } else {
            OperatorSpelling::Function("SINGLE")
        }
    }

    fn spill(&self) -> OperatorSpelling {
        OperatorSpelling::Function("ANCHORARRAY")
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

    fn book() -> Workbook {
        let mut wb = Workbook::with_sheet();
        wb.add_sheet("Data sheet").unwrap();
        wb
    }

    #[test]
    fn the_future_function_list_is_sorted() {
        assert!(FUTURE_FUNCTIONS.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn spill_and_implicit_intersection_come_back_as_operators() {
        let wb = book();
        let at = Pos::new(4, 2);
        assert_eq!(from_file("SUM(_xlfn.ANCHORARRAY(A1))", &wb, 0, at), "SUM(A1#)");
        assert_eq!(from_file("_xlfn.SINGLE(A1:A9)*2", &wb, 0, at), "@A1:A9*2");
        assert_eq!(from_file("_xlfn.SINGLE(A1+1)", &wb, 0, at), "@(A1+1)");
        assert_eq!(from_file("SUM('Data sheet'!A1:B2)", &wb, 0, at), "SUM('Data sheet'!A1:B2)");
    }

    #[test]
    fn newer_functions_parameters_and_operators_get_their_file_spelling() {
        let wb = book();
        let at = Pos::new(0, 0);
        let to_file = |text: &str, wb: &Workbook, sheet, at| to_file(text, wb, sheet, at, Storage::Dynamic);
        assert_eq!(to_file("=SUM(A1:A3)+SIN(1)", &wb, 0, at), "SUM(A1:A3)+SIN(1)");
        assert_eq!(to_file("=CONCAT(\"x#\",A1)", &wb, 0, at), "_xlfn.CONCAT(\"x#\",A1)");
        assert_eq!(to_file("=SUM(A1#)", &wb, 0, at), "SUM(_xlfn.ANCHORARRAY(A1))");
        assert_eq!(to_file("=@A1:A3", &wb, 0, at), "_xlfn.SINGLE(A1:A3)");
        assert_eq!(to_file("=FILTER(A1:A3,A1:A3>1)", &wb, 0, at), "_xlfn._xlws.FILTER(A1:A3,A1:A3>1)");
        assert_eq!(
            to_file("=LET(x,2,y,x+1,x*y)+x", &wb, 0, at),
            "_xlfn.LET(_xlpm.x,2,_xlpm.y,_xlpm.x+1,_xlpm.x*_xlpm.y)+x"
        );
        assert_eq!(to_file("='Data sheet'!B2#", &wb, 0, at), "_xlfn.ANCHORARRAY('Data sheet'!B2)");
        assert_eq!(to_file("=IF(A1=#N/A,1,2)", &wb, 0, at), "IF(A1=#N/A,1,2)");
        assert!(calls_dynamic_function("_xlfn._xlws.SORT(A1:A3)"));
        assert!(!calls_dynamic_function("SUM(A1:A3)&\"SORT(\""));
    }

    #[test]
    fn legacy_formulas_intersect_where_excel_did_and_are_written_back_without_at() {
        let wb = book();
        let at = Pos::new(17, 0);
        let legacy = |text| legacy_intersection(text, &wb, 0, at);
        assert_eq!(legacy("E15:E19").as_deref(), Some("@E15:E19"));
        assert_eq!(legacy("AM:AM*2").as_deref(), Some("@AM:AM*2"));
        assert_eq!(legacy("SUM(E15:E19)"), None);
        assert_eq!(legacy("SIN(E15:E19)").as_deref(), Some("SIN(@E15:E19)"));
        assert_eq!(legacy("SUM(E15:E19*2)").as_deref(), Some("SUM(@E15:E19*2)"));
        assert_eq!(legacy("SUMPRODUCT(E15:E19*F15:F19)"), None);
        assert_eq!(legacy("IF(A1,B1:B5,2)").as_deref(), Some("IF(A1,@B1:B5,2)"));
        let written = |text| to_file(text, &wb, 0, at, Storage::Legacy);
        assert_eq!(written("=@E15:E19*2"), "E15:E19*2");
        assert_eq!(written("=SIN(@E15:E19)"), "SIN(_xlfn.SINGLE(E15:E19))");
    }
}
