//! Syntax tree back to formula text (Excel's canonical spelling: upper-case function names).

use std::fmt::Write;

use super::address::{column_name, Pos, MAX_COLS, MAX_ROWS};
use super::ast::*;
use super::parse::FunctionTable;

/// Names the sheets of a workbook for printing sheet-qualified references.
pub type SheetNames<'a> = &'a dyn Fn(SheetId) -> String;

/// Prints `expr` as held by the cell `at`, without the leading `=`.
pub fn print_formula(expr: &Expr, at: Pos, functions: &dyn FunctionTable, sheets: SheetNames) -> String {
    let mut out = String::new();
    Printer { at, functions, sheets, out: &mut out }.expr(expr);
    out
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
    out: &'a mut String,
}

impl Printer<'_> {
    fn expr(&mut self, e: &Expr) {
        match &e.kind {
            ExprKind::Number(v) => self.out.push_str(&number_literal(*v)),
            ExprKind::Text(s) => {
                let _ = write!(self.out, "\"{}\"", s.replace('"', "\"\""));
            }
            ExprKind::Bool(b) => self.out.push_str(if *b { "TRUE" } else { "FALSE" }),
            ExprKind::Error(err) => self.out.push_str(err.as_str()),
            ExprKind::Missing => {}
            ExprKind::Ref(r) => self.reference(r),
            ExprKind::Name(n) => self.out.push_str(n),
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
                let name = self.functions.name(*id).to_string();
                self.call(&name, args)
            }
            ExprKind::UnknownCall(name, args) => self.call(name, args),
            // Only macros hold host nodes, and macros are not printed back; say what it is.
            ExprKind::Host(id) => {
                let _ = write!(self.out, "MACRO_NODE({id})");
            }
        }
    }

    fn unary(&mut self, op: UnaryOp, inner: &Expr) {
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

    fn call(&mut self, name: &str, args: &[Expr]) {
        self.out.push_str(name);
        self.out.push('(');
        for (i, a) in args.iter().enumerate() {
            if i > 0 {
                self.out.push(',');
            }
            self.expr(a);
        }
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

    fn reference(&mut self, r: &Reference) {
        write_reference(self.out, r, self.at, self.sheets);
    }
}

/// Writes a reference as held by the cell `at` (`Sheet2!$A$1:B3`; `#REF!` off the sheet):
/// the one spelling of references, for formulas as typed and as files store them.
pub fn write_reference(out: &mut String, r: &Reference, at: Pos, sheets: SheetNames) {
    match &r.sheet {
        SheetRef::Current => {}
        SheetRef::Id(id) => {
            let _ = write!(out, "{}!", quote_sheet_name(&sheets(*id)));
        }
        SheetRef::Missing(name) => {
            let _ = write!(out, "{}!", quote_sheet_name(name));
        }
    }
    let cell = |out: &mut String, c: CellCoord| {
        write_col(out, c.col, at);
        write_row(out, c.row, at);
    };
    match r.shape {
        RefShape::Cell(c) => cell(out, c),
        RefShape::Cells(a, b) => {
            cell(out, a);
            out.push(':');
            cell(out, b);
        }
        RefShape::Cols(a, b) => {
            write_col(out, a, at);
            out.push(':');
            write_col(out, b, at);
        }
        RefShape::Rows(a, b) => {
            write_row(out, a, at);
            out.push(':');
            write_row(out, b, at);
        }
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
    }
}
