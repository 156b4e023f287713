//! Syntax tree back to formula text (Excel's canonical spelling: upper-case function names).
//!
//! One printer for every spelling of a formula: as a user types it, and as a file stores it.
//! Each node (and so every parenthesis and operator) is printed here once; a [`Spelling`] only
//! chooses the few words that differ, so a file format cannot drift from the language.

use std::fmt::Write;
use std::rc::Rc;

use super::address::{column_name, Pos, MAX_COLS, MAX_ROWS};
use super::ast::*;
use super::parse::FunctionTable;

/// Names the sheets of a workbook for printing sheet-qualified references.
pub type SheetNames<'a> = &'a dyn Fn(SheetId) -> String;

/// Prints `expr` as held by the cell `at`, without the leading `=`, as a user types it.
pub fn print_formula(expr: &Expr, at: Pos, functions: &dyn FunctionTable, sheets: SheetNames) -> String {
    print_spelled(expr, at, functions, sheets, &AsTyped)
}

/// Prints `expr` as held by the cell `at`, without the leading `=`, in `spelling`.
pub fn print_spelled(
    expr: &Expr,
    at: Pos,
    functions: &dyn FunctionTable,
    sheets: SheetNames,
    spelling: &dyn Spelling,
) -> String {
    let mut out = String::new();
    Printer { at, functions, sheets, spelling, out: &mut out, parameters: Vec::new(), call_depth: 0, found: None }
        .expr(expr);
    out
}

/// Told each node printed and the bytes of the text it became.
pub type Located<'a> = dyn FnMut(&Expr, Span) + 'a;

/// Prints `expr` as typed, calling `found` with each node and the bytes of the text it was
/// printed as: a message can then point into a formula the workbook holds only as a tree.
pub fn print_locating(
    expr: &Expr,
    at: Pos,
    functions: &dyn FunctionTable,
    sheets: SheetNames,
    found: &mut Located,
) -> String {
    let mut out = String::new();
    let spelling = &AsTyped;
    let parameters = Vec::new();
    Printer { at, functions, sheets, spelling, out: &mut out, parameters, call_depth: 0, found: Some(found) }
        .expr(expr);
    out
}

/// The words that differ between the spellings of one formula tree. Every hook defaults to
/// the spelling a user types; a file format (xlsx's `_xlfn.` prefixes …) overrides the few it
/// changes, so that this module need not know any file format.
pub trait Spelling {
    /// Writes the name of a function being called (a name bound by LET or LAMBDA goes to
    /// [`Spelling::parameter_name`] instead).
    fn function_name(&self, name: &str, out: &mut String) {
        out.push_str(name);
    }

    /// Writes a name bound by an enclosing LET or LAMBDA, where it is declared and where it
    /// is used (also when it is called, as a LAMBDA bound by LET).
    fn parameter_name(&self, name: &str, out: &mut String) {
        out.push_str(name);
    }

    /// Writes a LAMBDA parameter its callers may leave out, where it is declared.
    fn optional_parameter(&self, name: &str, out: &mut String) {
        out.push('[');
        out.push_str(name);
        out.push(']');
    }

    /// How the implicit intersection `@x` is written; `in_call` says whether it sits inside
    /// a function call's arguments.
    fn implicit_intersection(&self, _in_call: bool) -> OperatorSpelling {
        OperatorSpelling::Symbol
    }

    /// How the spill operator `x#` is written.
    fn spill(&self) -> OperatorSpelling {
        OperatorSpelling::Symbol
    }

    /// A structured reference's own row as `[@Qty]` (as typed) rather than
    /// `[[#This Row],[Qty]]` (as Excel's files store it).
    fn this_row_as_at(&self) -> bool {
        true
    }

    /// References in R1C1 style (`R[-1]C2`) instead of A1 style.
    fn r1c1(&self) -> bool {
        false
    }
}

/// The R1C1 spelling (VBA's `FormulaR1C1`), which `parse_formula_r1c1` reads.
pub struct R1C1;

impl Spelling for R1C1 {
    fn r1c1(&self) -> bool {
        true
    }
}

/// The spelling a user types, which the parser reads and the workbook shows.
pub struct AsTyped;

impl Spelling for AsTyped {}

/// How a prefix or postfix operator is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OperatorSpelling {
    /// Its own symbol: `@x`, `x#`.
    Symbol,
    /// A call of the function of that name (spelled by [`Spelling::function_name`]) on the
    /// operand, whose own parentheses the call's replace: `@(A1+1)` → `SINGLE(A1+1)`.
    Function(&'static str),
    /// Left out: the operand alone.
    Omitted,
}

/// Quotes a sheet name when Excel would (`'Chamfer data'!A1`).
pub fn quote_sheet_name(name: &str) -> String {
    let plain = name.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_')
        && name.chars().all(|c| c.is_alphanumeric() || c == '_' || c == '.')
        && super::address::parse_cell(name).is_none();
    if plain {
        name.to_string()
    } else {
        format!("'{}'", name.replace('\'', "''"))
    }
}

/// Shortest text that reads back as the same number: positional for everyday magnitudes,
/// `1.5E+20` style for very large and very small ones (as Excel writes them).
pub fn number_literal(v: f64) -> String {
    let magnitude = v.abs();
    if v == 0.0 || (1e-5..1e15).contains(&magnitude) {
        return format!("{v}");
    }
    let text = format!("{v:E}");
    match text.split_once('E') {
        Some((mantissa, exp)) if !exp.starts_with('-') => format!("{mantissa}E+{exp}"),
        _ => text,
    }
}

struct Printer<'a> {
    at: Pos,
    functions: &'a dyn FunctionTable,
    sheets: SheetNames<'a>,
    spelling: &'a dyn Spelling,
    out: &'a mut String,
    /// Names bound by the LET and LAMBDA calls around the current node.
    parameters: Vec<Rc<str>>,
    /// How many function calls enclose the current node.
    call_depth: u32,
    /// Told where each node was printed (see [`print_locating`]).
    found: Option<&'a mut Located<'a>>,
}

impl Printer<'_> {
    fn expr(&mut self, e: &Expr) {
        let start = self.out.len() as u32;
        self.node(e);
        if let Some(found) = self.found.as_mut() {
            found(e, Span { start, end: self.out.len() as u32 });
        }
    }

    fn node(&mut self, e: &Expr) {
        match &e.kind {
            ExprKind::Number(v) => self.out.push_str(&number_literal(*v)),
            ExprKind::Text(s) => {
                let _ = write!(self.out, "\"{}\"", s.replace('"', "\"\""));
            }
            ExprKind::Bool(b) => self.out.push_str(if *b { "TRUE" } else { "FALSE" }),
            ExprKind::Error(err) => self.out.push_str(err.as_str()),
            ExprKind::Missing => {}
            ExprKind::Ref(r) if self.spelling.r1c1() => write_reference_r1c1(self.out, r, self.sheets),
            ExprKind::Ref(r) => write_reference(self.out, r, self.at, self.sheets),
            ExprKind::Table(r) => r.write(self.out, self.spelling.this_row_as_at()),
            ExprKind::Name(n) => self.name(n),
            ExprKind::SheetName(sheet, n) => {
                write_sheet_prefix(self.out, sheet, self.sheets);
                self.out.push_str(n);
            }
            ExprKind::Array(lit) => self.array(lit),
            ExprKind::Paren(inner) => {
                self.out.push('(');
                self.expr(inner);
                self.out.push(')');
            }
            ExprKind::Unary(op, inner) => self.unary(*op, inner),
            ExprKind::Binary(op, a, b) => {
                self.expr(a);
                self.out.push_str(binary_symbol(*op));
                self.expr(b);
            }
            ExprKind::Call(id, args) => {
                let functions = self.functions;
                self.call(functions.name(*id), args)
            }
            ExprKind::UnknownCall(name, args) => self.call(name, args),
            ExprKind::Invoke(callee, args) => {
                self.expr(callee);
                self.arguments("", args);
            }
            ExprKind::OptionalParam(name) => self.spelling.optional_parameter(name, self.out),
            // Only macros hold host nodes, and macros are not printed back; say what it is.
            ExprKind::Host(id) => {
                let _ = write!(self.out, "MACRO_NODE({id})");
            }
        }
    }

    fn name(&mut self, name: &str) {
        if self.is_parameter(name) {
            self.spelling.parameter_name(name, self.out);
        } else {
            self.out.push_str(name);
        }
    }

    fn is_parameter(&self, name: &str) -> bool {
        self.parameters.iter().any(|p| p.eq_ignore_ascii_case(name))
    }

    fn unary(&mut self, op: UnaryOp, inner: &Expr) {
        let spelling = match op {
            UnaryOp::Implicit => self.spelling.implicit_intersection(self.call_depth > 0),
            UnaryOp::Spill => self.spelling.spill(),
            _ => OperatorSpelling::Symbol,
        };
        match spelling {
            OperatorSpelling::Symbol => self.operator_symbol(op, inner),
            OperatorSpelling::Function(name) => self.operator_as_function(name, inner),
            OperatorSpelling::Omitted => self.expr(inner),
        }
    }

    fn operator_symbol(&mut self, op: UnaryOp, inner: &Expr) {
        match op {
            UnaryOp::Neg => self.out.push('-'),
            UnaryOp::Plus => self.out.push('+'),
            UnaryOp::Implicit => self.out.push('@'),
            UnaryOp::Not => self.out.push_str("Not "),
            UnaryOp::Percent | UnaryOp::Spill => {}
        }
        self.expr(inner);
        match op {
            UnaryOp::Percent => self.out.push('%'),
            UnaryOp::Spill => self.out.push('#'),
            _ => {}
        }
    }

    /// `@(A1+1)` as `SINGLE(A1+1)`: the call's parentheses stand for the operand's. The
    /// operand does not count as a call argument: it is the operator's, not a function's.
    fn operator_as_function(&mut self, name: &str, inner: &Expr) {
        self.spelling.function_name(name, self.out);
        self.out.push('(');
        match &inner.kind {
            ExprKind::Paren(x) => self.expr(x),
            _ => self.expr(inner),
        }
        self.out.push(')');
    }

    fn call(&mut self, name: &str, args: &[Expr]) {
        if self.is_parameter(name) {
            self.spelling.parameter_name(name, self.out);
        } else {
            self.spelling.function_name(name, self.out);
        }
        self.arguments(name, args);
    }

    /// `(a,b,…)` after the function `name` (empty for an in-place call), with the names it
    /// declares in scope.
    fn arguments(&mut self, name: &str, args: &[Expr]) {
        self.out.push('(');
        let outer_parameters = self.parameters.len();
        self.parameters.extend(bound_names(name, args));
        self.call_depth += 1;
        for (i, a) in args.iter().enumerate() {
            if i > 0 {
                self.out.push(',');
            }
            self.expr(a);
        }
        self.call_depth -= 1;
        self.parameters.truncate(outer_parameters);
        self.out.push(')');
    }

    fn array(&mut self, lit: &ArrayLit) {
        self.out.push('{');
        for (i, item) in lit.items.iter().enumerate() {
            if i > 0 {
                self.out.push(if i % lit.cols.max(1) == 0 { ';' } else { ',' });
            }
            self.expr(item);
        }
        self.out.push('}');
    }
}

/// The names a call declares for its arguments, in scope in every one of them:
/// `LET(n1, v1, n2, v2, body)` and `LAMBDA(p1, p2, body)`.
fn bound_names(function: &str, args: &[Expr]) -> Vec<Rc<str>> {
    let is_let = function.eq_ignore_ascii_case("LET");
    let is_lambda = function.eq_ignore_ascii_case("LAMBDA");
    if !is_let && !is_lambda {
        return Vec::new();
    }
    let declares = |i: usize| i + 1 < args.len() && (is_lambda || i.is_multiple_of(2));
    let name = |e: &Expr| match &e.kind {
        ExprKind::Name(n) | ExprKind::OptionalParam(n) => Some(n.clone()),
        _ => None,
    };
    args.iter().enumerate().filter(|(i, _)| declares(*i)).filter_map(|(_, e)| name(e)).collect()
}

/// Writes a reference as held by the cell `at` (`Sheet2!$A$1:B3`; `#REF!` off the sheet):
/// the one spelling of references, for formulas as typed and as files store them.
pub fn write_reference(out: &mut String, r: &Reference, at: Pos, sheets: SheetNames) {
    write_sheet_prefix(out, &r.sheet, sheets);
    let cell = |out: &mut String, c: CellCoord| {
        write_col(out, c.col, at);
        write_row(out, c.row, at);
    };
    let line = |out: &mut String, rows: bool, a: Coord, b: Coord| {
        let part = if rows { write_row } else { write_col };
        part(out, a, at);
        out.push(':');
        part(out, b, at);
    };
    write_shape(out, r.shape, cell, line);
}

/// Writes a reference in R1C1 style: `R2C3`, `R[-1]C`, `R1C1:R[2]C[2]`, `R3:R5`, `C[1]`.
fn write_reference_r1c1(out: &mut String, r: &Reference, sheets: SheetNames) {
    write_sheet_prefix(out, &r.sheet, sheets);
    let part = |out: &mut String, letter: char, c: Coord| {
        out.push(letter);
        let _ = match (c.absolute, c.value) {
            (true, v) => write!(out, "{}", v + 1),
            (false, 0) => Ok(()),
            (false, v) => write!(out, "[{v}]"),
        };
    };
    let cell = |out: &mut String, c: CellCoord| {
        part(out, 'R', c.row);
        part(out, 'C', c.col);
    };
    let line = |out: &mut String, rows: bool, a: Coord, b: Coord| {
        let letter = if rows { 'R' } else { 'C' };
        part(out, letter, a);
        if a != b {
            out.push(':');
            part(out, letter, b);
        }
    };
    write_shape(out, r.shape, cell, line);
}

/// A reference's shape in either style: `cell` writes one cell, `line` whole columns or
/// (`true`) whole rows.
fn write_shape(
    out: &mut String,
    shape: RefShape,
    cell: impl Fn(&mut String, CellCoord),
    line: impl Fn(&mut String, bool, Coord, Coord),
) {
    match shape {
        RefShape::Cell(c) => cell(out, c),
        RefShape::Cells(a, b) => {
            cell(out, a);
            out.push(':');
            cell(out, b);
        }
        RefShape::Cols(a, b) => line(out, false, a, b),
        RefShape::Rows(a, b) => line(out, true, a, b),
    }
}

fn write_col(out: &mut String, c: Coord, at: Pos) {
    match c.resolve(at.col, MAX_COLS) {
        Some(i) => {
            let _ = write!(out, "{}{}", if c.absolute { "$" } else { "" }, column_name(i));
        }
        None => out.push_str("#REF!"),
    }
}

/// `Sheet2!` or `'Chamfer data'!` before a reference or name; nothing for the current sheet.
fn write_sheet_prefix(out: &mut String, sheet: &SheetRef, sheets: SheetNames) {
    match sheet {
        SheetRef::Current => {}
        SheetRef::Id(id) => {
            let _ = write!(out, "{}!", quote_sheet_name(&sheets(*id)));
        }
        SheetRef::Missing(name) => {
            let _ = write!(out, "{}!", quote_sheet_name(name));
        }
        // Excel quotes a 3-D reference's ends as one when either needs it: `'Jan 1:Mar'!`.
        SheetRef::Span(first, last) => {
            let (first, last) = (sheets(*first), sheets(*last));
            let pair = format!("{first}:{last}");
            if quote_sheet_name(&first) == first && quote_sheet_name(&last) == last {
                let _ = write!(out, "{pair}!");
            } else {
                let _ = write!(out, "'{}'!", pair.replace('\'', "''"));
            }
        }
    }
}

fn write_row(out: &mut String, c: Coord, at: Pos) {
    match c.resolve(at.row, MAX_ROWS) {
        Some(i) => {
            let _ = write!(out, "{}{}", if c.absolute { "$" } else { "" }, i + 1);
        }
        None => out.push_str("#REF!"),
    }
}

pub fn binary_symbol(op: BinOp) -> &'static str {
    match op {
        BinOp::Range => ":",
        BinOp::Intersect => " ",
        BinOp::Union => ",",
        BinOp::Pow => "^",
        BinOp::Mul => "*",
        BinOp::Div => "/",
        BinOp::Add => "+",
        BinOp::Sub => "-",
        BinOp::Concat => "&",
        BinOp::Eq => "=",
        BinOp::Ne => "<>",
        BinOp::Lt => "<",
        BinOp::Le => "<=",
        BinOp::Gt => ">",
        BinOp::Ge => ">=",
        BinOp::Mod => " Mod ",
        BinOp::IntDiv => "\\",
        BinOp::And => " And ",
        BinOp::Or => " Or ",
        BinOp::Xor => " Xor ",
        BinOp::Eqv => " Eqv ",
        BinOp::Imp => " Imp ",
        BinOp::Like => " Like ",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formula::parse::{parse_formula, FnInfo, ParseContext};

    /// A few functions known by id, so that calls print through [`FunctionTable::name`];
    /// the rest parse as unknown calls, printed by the name typed.
    struct Functions;

    const KNOWN: [&str; 5] = ["SUM", "SIN", "LET", "LAMBDA", "XLOOKUP"];

    impl FunctionTable for Functions {
        fn lookup(&self, name: &str) -> Option<FnInfo> {
            let id = KNOWN.iter().position(|f| f.eq_ignore_ascii_case(name))?;
            Some(FnInfo { id: id as FnId, min_args: 0, max_args: 255 })
        }

        fn name(&self, id: FnId) -> &str {
            KNOWN[id as usize]
        }
    }

    fn printed(text: &str, spelling: &dyn Spelling) -> String {
        let ctx = ParseContext { at: Pos::new(0, 0), functions: &Functions, sheet: &|_| None };
        let expr = parse_formula(text, &ctx).expect("parses");
        print_spelled(&expr, Pos::new(0, 0), &Functions, &|_| String::new(), spelling)
    }

    #[test]
    fn the_default_spelling_is_the_formula_as_typed() {
        for text in ["XLOOKUP(1,A:A,B:B)", "LET(x,1,x+1)", "A1#", "@A1:A3", "-(@A1:A3+B1#)%*2"] {
            assert_eq!(printed(text, &AsTyped), text);
        }
    }

    #[test]
    fn an_in_place_lambda_with_an_optional_parameter_prints_as_typed() {
        // A file's spelling (crates/ncsheet/src/io/xlsx/syntax.rs tests the way back) reads as typed.
        let file = "_xlfn.LAMBDA(_xlpm.a,_xlop.b,_xlpm.a*_xlpm.b)(A5)";
        let typed = "LAMBDA(a,[b],a*b)(A5)";
        assert_eq!(printed(file, &AsTyped), typed);
        assert_eq!(printed(typed, &AsTyped), typed);
        assert_eq!(printed("LAMBDA(x,x)(1)(2)+1", &AsTyped), "LAMBDA(x,x)(1)(2)+1");
    }
}
