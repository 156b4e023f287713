//! The one function table. Every sheet function — Excel's and ncsheet's geometry built-ins —
//! is a row here: name, argument bounds, body, signature and a one-line summary.
//!
//! To add a function: write its body in the category module and add its row to that
//! module's `FUNCTIONS`; a new category module is listed once in [`REGISTRY`]. A function
//! whose result changes by itself (NOW) is marked [`FnSpec::volatile`].

use std::collections::HashMap;
use std::sync::LazyLock;

use crate::formula::ast::{Expr, FnId};
use crate::formula::parse::{FnInfo, FunctionTable};

use super::evaluator::{Ctx, Operand};
use super::value::{Value, XlResult};

pub mod args;
mod criteria;
mod date;
mod dispersion;
mod dynamic_ref;
mod geometry;
mod info;
mod logic;
mod lookup;
mod math;
mod order;
mod stats;
mod text;
mod text_format;
pub mod vba;

pub use geometry::{describe_gouge, formula_ball_path};
pub use logic::{as_lambda, Lambda};
pub use text_format::NumberFormat;

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
        FnSpec { name, min_args, max_args, kind: FnKind::Value(f), signature, summary, volatile: false }
    }

    pub const fn reference(
        name: &'static str,
        min_args: usize,
        max_args: usize,
        f: RefFn,
        signature: &'static str,
        summary: &'static str,
    ) -> FnSpec {
        FnSpec { name, min_args, max_args, kind: FnKind::Ref(f), signature, summary, volatile: false }
    }

    /// The same function, volatile.
    pub const fn volatile(self) -> FnSpec {
        FnSpec { volatile: true, ..self }
    }
}

/// Every function, in one list. Ids are indexes into it.
pub static REGISTRY: LazyLock<Vec<FnSpec>> = LazyLock::new(|| {
    [
        math::FUNCTIONS,
        stats::FUNCTIONS,
        dispersion::FUNCTIONS,
        order::FUNCTIONS,
        date::FUNCTIONS,
        logic::FUNCTIONS,
        lookup::FUNCTIONS,
        dynamic_ref::FUNCTIONS,
        text::FUNCTIONS,
        info::FUNCTIONS,
        geometry::FUNCTIONS,
        vba::FUNCTIONS,
    ]
    .concat()
});

static BY_NAME: LazyLock<HashMap<String, FnId>> = LazyLock::new(|| {
    let mut map = HashMap::new();
    for (i, f) in REGISTRY.iter().enumerate() {
        let previous = map.insert(f.name.to_ascii_uppercase(), i as FnId);
        assert!(previous.is_none(), "function {} is registered twice", f.name);
    }
    map
});

pub fn spec(id: FnId) -> &'static FnSpec {
    &REGISTRY[id as usize]
}

pub fn find(name: &str) -> Option<FnId> {
    BY_NAME.get(&name.to_ascii_uppercase()).copied()
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
