//! The one function table. Every sheet function — Excel's and ncsheet's geometry built-ins —
//! is a row here: name, argument bounds, body, signature and a one-line summary.
//!
//! The library is a folder per family (math, statistics, text …), each file a table of rows
//! (`FUNCTIONS`) beside their bodies, written against the small API of `api.rs`. To add a
//! function: write its body in its family's file and add its row to that file's
//! `FUNCTIONS`; a new file is listed once in its family's `TABLES`, a new family once in
//! [`REGISTRY`]. A function
//! whose result changes by itself (NOW) is marked [`FnSpec::volatile`]; the other facts
//! about a function (its `_xlfn.` spelling in files, whether it makes a dynamic-array
//! formula, which arguments take whole ranges, its number in .xls files) are builder methods
//! on its row too, so that
//! no list of names elsewhere repeats the registry.

use std::collections::HashMap;
use std::sync::LazyLock;

use crate::formula::ast::{Expr, FnId};
use crate::formula::parse::{FnInfo, FunctionTable};

use super::evaluator::{Ctx, Operand};
use super::value::{Value, XlResult};

pub(crate) mod api;
pub(crate) mod args;
mod arrays;
pub(crate) use arrays::reshape::sort_cmp;
mod criteria;
mod database;
mod date;
mod engineering;
mod financial;
mod geometry;
mod information;
mod lambda;
mod logic;
mod lookup;
mod math;
mod scalar;
mod statistics;
mod text;
pub(crate) mod vba;

pub use crate::eval::format::text_format::NumberFormat;
pub use geometry::{describe_gouge, formula_ball_path, standalone_ball_path, PathFailure};
pub use lambda::{as_lambda, bound_names, Lambda};

/// A function body that returns a value.
pub type ValueFn = fn(&mut Ctx, &[Expr]) -> XlResult<Value>;
/// A function body that may return a reference (INDEX, OFFSET, …).
pub type RefFn = fn(&mut Ctx, &[Expr]) -> Operand;

#[derive(Clone, Copy)]
pub enum FnKind {
    Value(ValueFn),
    Ref(RefFn),
}

/// Upper bound for "any number of arguments" (Excel allows 255).
pub const MANY: usize = 255;

/// See [`FnSpec::picked_arg`].
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct PickedArg {
    pub arg: u8,
    pub searched: Searched,
}

/// The part of a picked argument a lookup reads whatever it finds: a graph edge.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Searched {
    /// None of it (XLOOKUP's and LOOKUP's return arrays).
    Nothing,
    /// Its first column (VLOOKUP's table).
    FirstColumn,
    /// Its first row (HLOOKUP's table).
    FirstRow,
}

#[derive(Clone, Copy)]
pub struct FnSpec {
    pub name: &'static str,
    pub min_args: usize,
    pub max_args: usize,
    pub kind: FnKind,
    /// `ROUND(number, digits)`: shown by `ncsheet functions`.
    pub signature: &'static str,
    pub summary: &'static str,
    /// Its result changes with no change to its arguments (NOW, TODAY): a cell calling it is
    /// recalculated at every recalculation, not only when what it reads changes.
    pub volatile: bool,
    /// A cell calling it is recomputed at every edit, not only when what it reads changes.
    /// Every volatile function is, but one whose reach is linked in the graph after each
    /// evaluation (OFFSET: the reference it is given is a position, no edge; the one it makes
    /// is linked by `relink_dynamic`), so filling a column with it one edit at a time stays
    /// linear.
    /// INDIRECT's text may name a sheet or a name not there yet: it stays.
    pub every_edit: bool,
    /// How an xlsx file spells the name: functions newer than Excel 2007 carry `_xlfn.`.
    pub file_prefix: FilePrefix,
    /// A file stores a formula calling it as a dynamic-array formula (Excel 365's array
    /// functions, and rust_xlsxwriter's list of them).
    pub dynamic: bool,
    /// Reads its arguments as syntax trees, not only as values (LAMBDA's body is
    /// differentiated by the surface functions): a formula calling it is never shared.
    pub reads_trees: bool,
    /// Arguments evaluated as whole arrays even in a pre-2019 (legacy) formula, where Excel
    /// otherwise intersects a range with the formula's row or column.
    pub array_args: ArgSet,
    /// Arguments that take a whole range as it stands (an aggregate, a lookup table, a
    /// reference) in a legacy formula.
    pub range_args: ArgSet,
    /// What its result depends on besides its arguments and the cells it reads: a value
    /// Excel cached for it was computed at another moment, by chance, or on another machine.
    pub reads: Outside,
    /// Its first argument, written as a reference, is read for where it is, not for what it
    /// holds (ROW, ROWS, ISREF …; INDEX and OFFSET link the cells they return at run time): no
    /// graph edge.
    pub position_arg: bool,
    /// An argument, written as a reference, whose cells are read only where the result is
    /// picked (XLOOKUP's return array, VLOOKUP's columns past the first): the graph links the
    /// part it searches, the body links the cells it returns at run time, as INDEX does. A
    /// running balance `C3 = XLOOKUP(A3-1,A:A,C:C)+B3` reads one cell of C, not a cycle.
    pub picked_arg: Option<PickedArg>,
    /// Its place in the .xls format's function table (MS-XLS 2.5.198.17 `Ftab`), for the
    /// functions Excel 97 had: the .xls reader knows a function by it.
    pub biff: Option<Biff>,
    /// A VBA function's parameters as Microsoft's VBA reference names them, in order, an
    /// optional one in brackets (`[Start]`): a macro may give arguments by these names
    /// (`InStr(Start:=1, String1:=s, String2:="x")`). Empty where no call names them.
    pub vba_params: &'static [&'static str],
}

/// A function's place in the .xls format's function table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Biff {
    pub number: u16,
    /// The count of arguments of a call stored without one (`PtgFunc`); `None` where the
    /// count varies (such a call always stores it, `PtgFuncVar`).
    pub fixed_args: Option<u8>,
}

/// What a function's result may depend on besides its arguments and the cells it reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outside {
    /// Nothing: the same arguments give the same result anywhere, at any time.
    Nothing,
    /// The clock (NOW, TODAY).
    Clock,
    /// Chance (RAND, RANDBETWEEN, RANDARRAY).
    Chance,
    /// The host: the computer and program that compute it (INFO).
    Host,
}

/// The spelling of a function's name in an xlsx file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilePrefix {
    None,
    /// `_xlfn.`: added after Excel 2007.
    Future,
    /// `_xlfn._xlws.`: FILTER, SORT.
    Worksheet,
}

impl FilePrefix {
    pub const fn as_str(self) -> &'static str {
        match self {
            FilePrefix::None => "",
            FilePrefix::Future => "_xlfn.",
            FilePrefix::Worksheet => "_xlfn._xlws.",
        }
    }
}

/// A set of argument positions (0-based); the last bit stands for every position from 63 on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ArgSet(u64);

impl ArgSet {
    pub const NONE: ArgSet = ArgSet(0);
    pub const ALL: ArgSet = ArgSet(!0);

    /// Only argument `i`.
    pub const fn only(i: u32) -> ArgSet {
        ArgSet(1 << i)
    }

    /// Argument `i` and every one after it.
    pub const fn from(i: u32) -> ArgSet {
        ArgSet(!0 << i)
    }

    /// The arguments of either set.
    pub const fn and(self, other: ArgSet) -> ArgSet {
        ArgSet(self.0 | other.0)
    }

    /// Every argument but `i`.
    pub const fn except(i: u32) -> ArgSet {
        ArgSet(!(1 << i))
    }

    pub const fn contains(self, i: usize) -> bool {
        let bit = if i < 63 { i } else { 63 };
        self.0 >> bit & 1 == 1
    }
}

impl FnSpec {
    pub const fn value(
        name: &'static str,
        min_args: usize,
        max_args: usize,
        f: ValueFn,
        signature: &'static str,
        summary: &'static str,
    ) -> FnSpec {
        FnSpec::new(name, min_args, max_args, FnKind::Value(f), signature, summary)
    }

    pub const fn reference(
        name: &'static str,
        min_args: usize,
        max_args: usize,
        f: RefFn,
        signature: &'static str,
        summary: &'static str,
    ) -> FnSpec {
        FnSpec::new(name, min_args, max_args, FnKind::Ref(f), signature, summary)
    }

    const fn new(
        name: &'static str,
        min_args: usize,
        max_args: usize,
        kind: FnKind,
        signature: &'static str,
        summary: &'static str,
    ) -> FnSpec {
        FnSpec {
            name,
            min_args,
            max_args,
            kind,
            signature,
            summary,
            volatile: false,
            every_edit: false,
            file_prefix: FilePrefix::None,
            dynamic: false,
            reads_trees: false,
            array_args: ArgSet::NONE,
            range_args: ArgSet::NONE,
            reads: Outside::Nothing,
            position_arg: false,
            picked_arg: None,
            biff: None,
            vba_params: &[],
        }
    }

    /// The same function, volatile (and so recomputed at every edit).
    pub const fn volatile(self) -> FnSpec {
        FnSpec { volatile: true, every_edit: true, ..self }
    }

    /// The same function, recomputed only when what it reads changes although Excel makes it
    /// volatile: the reference it makes is linked in the graph (see [`FnSpec::every_edit`]).
    pub const fn reach_linked(self) -> FnSpec {
        FnSpec { every_edit: false, ..self }
    }

    /// The same function, reading `what` besides its arguments (see [`FnSpec::reads`]).
    pub const fn reads(self, what: Outside) -> FnSpec {
        FnSpec { reads: what, ..self }
    }

    /// The same function, spelled `_xlfn.NAME` in a file (added after Excel 2007).
    pub const fn future(self) -> FnSpec {
        FnSpec { file_prefix: FilePrefix::Future, ..self }
    }

    /// The same function, spelled `_xlfn._xlws.NAME` in a file (FILTER, SORT).
    pub const fn worksheet_future(self) -> FnSpec {
        FnSpec { file_prefix: FilePrefix::Worksheet, ..self }
    }

    /// The same function, making a file store the formula calling it as a dynamic array.
    pub const fn dynamic(self) -> FnSpec {
        FnSpec { dynamic: true, ..self }
    }

    /// The same function, reading its arguments as syntax trees (see [`FnSpec::reads_trees`]).
    pub const fn reads_trees(self) -> FnSpec {
        FnSpec { reads_trees: true, ..self }
    }

    /// The same function, evaluating `args` as whole arrays in a legacy formula.
    pub const fn array_args(self, args: ArgSet) -> FnSpec {
        FnSpec { array_args: args, ..self }
    }

    /// The same function, taking `args` as whole ranges in a legacy formula.
    pub const fn range_args(self, args: ArgSet) -> FnSpec {
        FnSpec { range_args: args, ..self }
    }

    /// The same function, reading its first argument for its position only (see
    /// [`FnSpec::position_arg`]).
    pub const fn position_arg(self) -> FnSpec {
        FnSpec { position_arg: true, ..self }
    }

    /// The same function, reading argument `arg` only where it searches (`searched`) and at
    /// the cells it returns (see [`FnSpec::picked_arg`]).
    pub const fn picks_from(self, arg: u8, searched: Searched) -> FnSpec {
        FnSpec { picked_arg: Some(PickedArg { arg, searched }), ..self }
    }

    /// The same function, number `number` of the .xls format's function table; a call stored
    /// without a count of arguments has the row's count when that is fixed.
    pub const fn biff(self, number: u16) -> FnSpec {
        let fixed_args = if self.min_args == self.max_args { Some(self.min_args as u8) } else { None };
        FnSpec { biff: Some(Biff { number, fixed_args }), ..self }
    }

    /// The same function, its parameters named as VBA's reference names them (see
    /// [`FnSpec::vba_params`]).
    pub const fn vba_params(self, names: &'static [&'static str]) -> FnSpec {
        FnSpec { vba_params: names, ..self }
    }

    /// [`FnSpec::biff`] for a function whose .xls calls always store `args` arguments although
    /// a formula may give it fewer (DCOUNT's field may be left out: `DCOUNT(A1:B9,,D1:D2)`).
    pub const fn biff_fixed(self, number: u16, args: u8) -> FnSpec {
        FnSpec { biff: Some(Biff { number, fixed_args: Some(args) }), ..self }
    }
}

/// Every function, in one list. Ids are indexes into it.
pub static REGISTRY: LazyLock<Vec<FnSpec>> = LazyLock::new(|| {
    let families: &[&[&[FnSpec]]] = &[
        math::TABLES,
        statistics::TABLES,
        &[date::FUNCTIONS],
        &[logic::FUNCTIONS],
        lambda::TABLES,
        lookup::TABLES,
        &[database::FUNCTIONS],
        arrays::TABLES,
        text::TABLES,
        engineering::TABLES,
        financial::TABLES,
        &[information::FUNCTIONS],
        &[geometry::FUNCTIONS],
        &[vba::FUNCTIONS],
    ];
    families.concat().concat()
});

static BY_NAME: LazyLock<HashMap<String, FnId>> = LazyLock::new(|| {
    let mut map = HashMap::new();
    for (i, f) in REGISTRY.iter().enumerate() {
        let previous = map.insert(f.name.to_ascii_uppercase(), i as FnId);
        assert!(previous.is_none(), "function {} is registered twice", f.name);
    }
    map
});

static BY_BIFF: LazyLock<HashMap<u16, FnId>> = LazyLock::new(|| {
    let mut map = HashMap::new();
    for (i, f) in REGISTRY.iter().enumerate() {
        if let Some(biff) = f.biff {
            let previous = map.insert(biff.number, i as FnId);
            assert!(previous.is_none(), ".xls function number {} is given twice", biff.number);
        }
    }
    map
});

/// The function numbered `number` in the .xls format's function table, if ncsheet has it.
pub fn find_biff(number: u16) -> Option<FnId> {
    BY_BIFF.get(&number).copied()
}

pub fn spec(id: FnId) -> &'static FnSpec {
    &REGISTRY[id as usize]
}

pub fn find(name: &str) -> Option<FnId> {
    BY_NAME.get(&name.to_ascii_uppercase()).copied()
}

/// Whether the function `id` is SUBTOTAL or AGGREGATE, whose cells those functions skip.
pub fn is_subtotal_call(id: FnId) -> bool {
    matches!(spec(id).name, "SUBTOTAL" | "AGGREGATE")
}

/// The registry seen by the parser.
pub struct Registry;

impl FunctionTable for Registry {
    fn lookup(&self, name: &str) -> Option<FnInfo> {
        let id = find(name)?;
        let f = spec(id);
        Some(FnInfo { id, min_args: f.min_args, max_args: f.max_args })
    }

    fn name(&self, id: FnId) -> &str {
        spec(id).name
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_function_has_a_unique_name_and_sane_bounds() {
        for f in REGISTRY.iter() {
            assert!(f.min_args <= f.max_args, "{}", f.name);
            assert!(f.signature.starts_with(f.name), "{} signature {}", f.name, f.signature);
        }
        assert_eq!(BY_NAME.len(), REGISTRY.len());
    }
}
