//! The formula syntax tree. Plain data: nothing here evaluates or touches a workbook.
//!
//! References are stored relative to the cell that holds the formula (like Excel's R1C1
//! form), so a formula copied down a column parses to one tree that every copy shares.

use std::rc::Rc;

use super::address::{Pos, Rect, MAX_COLS, MAX_ROWS};

pub use super::error::XlError;
pub use super::table_ref::{TableRef, TableRows};

/// Index of a sheet in its workbook.
pub type SheetId = u16;

/// Byte range of a node in the formula text as typed (a leading `=` included).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct Span {
    pub start: u32,
    pub end: u32,
}

/// One coordinate of a reference: an absolute index (`$A`) or an offset from the
/// formula's own cell (`A`). Both are 0-based.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Coord {
    pub value: i32,
    pub absolute: bool,
}

impl Coord {
    pub fn absolute(value: u32) -> Coord {
        Coord { value: value as i32, absolute: true }
    }

    pub fn relative(offset: i32) -> Coord {
        Coord { value: offset, absolute: false }
    }

    /// The 0-based index this coordinate points at from `base`, if it lies on the sheet.
    #[inline]
    pub fn resolve(self, base: u32, limit: u32) -> Option<u32> {
        let v = if self.absolute { self.value as i64 } else { base as i64 + self.value as i64 };
        (0..limit as i64).contains(&v).then_some(v as u32)
    }

    /// [`Coord::resolve`] as a defined name's coordinate reads: a relative one that runs off
    /// the sheet wraps around to the other edge, as Excel's do.
    #[inline]
    pub fn resolve_wrapping(self, base: u32, limit: u32) -> Option<u32> {
        if self.absolute {
            return self.resolve(base, limit);
        }
        Some((base as i64 + self.value as i64).rem_euclid(limit as i64) as u32)
    }
}

/// A cell address inside a reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CellCoord {
    pub row: Coord,
    pub col: Coord,
}

/// What a reference covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RefShape {
    /// `A1`
    Cell(CellCoord),
    /// `A1:C10`
    Cells(CellCoord, CellCoord),
    /// `A:C` (whole columns)
    Cols(Coord, Coord),
    /// `3:5` (whole rows)
    Rows(Coord, Coord),
}

/// Which sheet a reference points at.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum SheetRef {
    /// The sheet holding the formula.
    Current,
    Id(SheetId),
    /// A sheet name the workbook does not have: evaluates to `#REF!`.
    Missing(Rc<str>),
    /// A 3-D reference's sheets (`Sheet1:Sheet3!A1`): its two end sheets as written. It
    /// means every sheet whose tab lies between them when it is read, so a sheet moved or
    /// added between the ends joins it (Excel's "Create a 3-D reference to the same cell
    /// range on multiple worksheets"); it is no one sheet, so [`Reference::resolve`] gives
    /// `None` and the evaluator reads it as the areas of each sheet.
    Span(SheetId, SheetId),
}

#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Reference {
    pub sheet: SheetRef,
    pub shape: RefShape,
}

impl Reference {
    /// The sheet and rectangle this reference points at from cell `at` of `sheet`; `None`
    /// when it names a missing sheet or lands off the sheet (Excel's `#REF!`).
    pub fn resolve(&self, sheet: SheetId, at: Pos) -> Option<(SheetId, Rect)> {
        self.resolve_with(sheet, at, Coord::resolve)
    }

    /// [`Reference::resolve`] as a defined name's reference reads: relative coordinates wrap
    /// at the sheet's edges ([`Coord::resolve_wrapping`]).
    pub fn resolve_wrapping(&self, sheet: SheetId, at: Pos) -> Option<(SheetId, Rect)> {
        self.resolve_with(sheet, at, Coord::resolve_wrapping)
    }

    #[inline]
    fn resolve_with(
        &self,
        sheet: SheetId,
        at: Pos,
        coord: fn(Coord, u32, u32) -> Option<u32>,
    ) -> Option<(SheetId, Rect)> {
        let sheet = match &self.sheet {
            SheetRef::Current => sheet,
            SheetRef::Id(id) => *id,
            SheetRef::Missing(_) | SheetRef::Span(..) => return None,
        };
        let row = |c: Coord| coord(c, at.row, MAX_ROWS);
        let col = |c: Coord| coord(c, at.col, MAX_COLS);
        let rect = match self.shape {
            RefShape::Cell(c) => Rect::cell(Pos::new(row(c.row)?, col(c.col)?)),
            RefShape::Cells(a, b) => Rect::new(Pos::new(row(a.row)?, col(a.col)?), Pos::new(row(b.row)?, col(b.col)?)),
            RefShape::Cols(a, b) => Rect::new(Pos::new(0, col(a)?), Pos::new(MAX_ROWS - 1, col(b)?)),
            RefShape::Rows(a, b) => Rect::new(Pos::new(row(a)?, 0), Pos::new(row(b)?, MAX_COLS - 1)),
        };
        Some((sheet, rect))
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinOp {
    Range,
    /// `A1:C3 B2:D4`: the cells both references cover (a space in the text).
    Intersect,
    /// `(A1:A3,C1)`: a reference of several areas (a comma, only inside parentheses).
    Union,
    Pow,
    Mul,
    Div,
    Add,
    Sub,
    Concat,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    // The macro language's operators (crates/ncsheet/src/vba); formula text never produces them.
    /// `a Mod b`: VBA's remainder of the operands rounded to integers, signed like `a`.
    Mod,
    /// `a \ b`: VBA's integer division.
    IntDiv,
    /// `And`, `Or`, `Xor`, `Eqv`, `Imp`: logical on booleans, bitwise on integers.
    And,
    Or,
    Xor,
    Eqv,
    Imp,
    /// `text Like pattern`: VBA's wildcard match (`?`, `*`, `#`, `[a-z]`, `[!…]`).
    Like,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UnaryOp {
    Neg,
    Plus,
    Percent,
    /// `@`: implicit intersection.
    Implicit,
    /// `A1#`: the spill range anchored at a cell.
    Spill,
    /// `Not x` (macros only): logical on a boolean, bitwise on an integer.
    Not,
}

/// Index of a function in the registry (`eval::functions::REGISTRY`).
pub type FnId = u16;

#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    Number(f64),
    Text(Rc<str>),
    Bool(bool),
    Error(XlError),
    /// An omitted argument, as in `IF(A1,,2)`.
    Missing,
    Ref(Reference),
    /// A structured reference (`Parts[Qty]`, `[@Qty]`), resolved through the workbook's
    /// tables when evaluated.
    Table(Rc<TableRef>),
    /// A defined name or a `LET`/`LAMBDA` variable.
    Name(Rc<str>),
    /// A defined name as seen from a given sheet (`Sheet2!Rate`: the name scoped to Sheet2,
    /// else the workbook's).
    SheetName(SheetRef, Rc<str>),
    Array(Rc<ArrayLit>),
    /// Parentheses as typed, kept so that a formula prints back as it was written.
    Paren(Box<Expr>),
    Unary(UnaryOp, Box<Expr>),
    Binary(BinOp, Box<Expr>, Box<Expr>),
    Call(FnId, Vec<Expr>),
    /// A function the registry does not know: evaluates to `#NAME?`.
    UnknownCall(Rc<str>, Vec<Expr>),
    /// A call of what the first expression gives, written right after it: `LAMBDA(x,x+1)(2)`.
    Invoke(Box<Expr>, Vec<Expr>),
    /// A LAMBDA parameter its callers may leave out: `[b]` as typed, `_xlop.b` in a file.
    /// Only a LAMBDA's parameter list holds one (the parser sees to it).
    OptionalParam(Rc<str>),
    /// A node of the macro language that only its interpreter can evaluate (`Range("B3").Value`,
    /// a call of the macro's own Function): an index into the macro's node table, evaluated
    /// through the evaluator's `Host`. Formula text never produces it.
    Host(u32),
}

/// An array constant `{1,2;3,4}`, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct ArrayLit {
    pub rows: usize,
    pub cols: usize,
    pub items: Vec<Expr>,
}

impl Expr {
    pub fn new(kind: ExprKind, span: Span) -> Expr {
        Expr { kind, span }
    }

    /// Calls `f` for every reference in the tree, in text order.
    pub fn visit_refs(&self, f: &mut dyn FnMut(&Reference)) {
        self.visit(&mut |e| {
            if let ExprKind::Ref(r) = &e.kind {
                f(r)
            }
        });
    }

    /// Calls `f` for every node of the tree, parents before children.
    pub fn visit(&self, f: &mut dyn FnMut(&Expr)) {
        f(self);
        match &self.kind {
            ExprKind::Unary(_, e) | ExprKind::Paren(e) => e.visit(f),
            ExprKind::Binary(_, a, b) => {
                a.visit(f);
                b.visit(f);
            }
            ExprKind::Call(_, args) | ExprKind::UnknownCall(_, args) => args.iter().for_each(|a| a.visit(f)),
            ExprKind::Invoke(callee, args) => {
                callee.visit(f);
                args.iter().for_each(|a| a.visit(f));
            }
            ExprKind::Array(lit) => lit.items.iter().for_each(|a| a.visit(f)),
            _ => {}
        }
    }

    /// Calls `f` for every node of the tree, parents before children, letting it rewrite
    /// them (a node `f` replaced is walked as replaced). An array constant's items are
    /// constants, never references, and are not walked.
    pub fn visit_mut(&mut self, f: &mut dyn FnMut(&mut Expr)) {
        f(self);
        match &mut self.kind {
            ExprKind::Unary(_, e) | ExprKind::Paren(e) => e.visit_mut(f),
            ExprKind::Binary(_, a, b) => {
                a.visit_mut(f);
                b.visit_mut(f);
            }
            ExprKind::Call(_, args) | ExprKind::UnknownCall(_, args) => args.iter_mut().for_each(|a| a.visit_mut(f)),
            ExprKind::Invoke(callee, args) => {
                callee.visit_mut(f);
                args.iter_mut().for_each(|a| a.visit_mut(f));
            }
            _ => {}
        }
    }
}
