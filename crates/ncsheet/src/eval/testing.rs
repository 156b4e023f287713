//! A small in-memory [`Env`] for evaluating formulas without a workbook (unit tests,
//! examples). One sheet named `Sheet1`; cells hold constants only.

use std::collections::BTreeMap;
use std::rc::Rc;

use crate::formula::address::{parse_cell, Pos, Rect};
use crate::formula::ast::{Expr, SheetId};
use crate::formula::parse::{parse_formula, ParseContext, ParseError};

use super::evaluator::{Ctx, Env};
use super::functions::Registry;
use super::surface::EmptyEnv;
use super::value::Value;

/// A number value (shorthand for tests).
pub fn n(v: f64) -> Value {
    Value::Number(v)
}

/// An error value (shorthand for tests).
pub fn err(e: super::value::XlError) -> Value {
    Value::Error(e)
}

#[derive(Default)]
pub struct MapEnv {
    pub cells: BTreeMap<(u32, u32), Value>,
    /// The clock and random sequence (RAND's tests start from a fixed seed).
    pub settings: super::Settings,
}

impl MapEnv {
    /// `MapEnv::with(&[("A1", 1.0.into()), ("A2", "x".into())])`
    pub fn with(cells: &[(&str, Value)]) -> MapEnv {
        let mut env = MapEnv::default();
        for (addr, v) in cells {
            let p = parse_cell(addr).expect("cell address");
            env.cells.insert((p.row, p.col), v.clone());
        }
        env
    }

    /// Parses and evaluates `formula` as if it sat in cell `at` of Sheet1.
    pub fn eval_at(&self, formula: &str, at: &str) -> Result<Value, ParseError> {
        let at = parse_cell(at).expect("cell address");
        let expr = parse_formula(
            formula,
            &ParseContext { at, functions: &Registry, sheet: &|n| (n.eq_ignore_ascii_case("Sheet1")).then_some(0) },
        )?;
        Ok(crate::eval::evaluator::no_lambda(Ctx::new(self, 0, at).eval(&expr)).unwrap_single())
    }

    /// Evaluates `formula` in cell Z100 (away from the usual test data).
    pub fn eval(&self, formula: &str) -> Value {
        self.eval_at(formula, "Z100").unwrap_or_else(|e| panic!("{}", e.render(formula)))
    }
}

impl Env for MapEnv {
    fn now(&self) -> f64 {
        self.settings.now(self.date_system())
    }

    fn next_random(&self) -> f64 {
        self.settings.next_random()
    }

    /// The locale its settings give (en-US unless a test sets another).
    fn locale(&self) -> super::Locale {
        self.settings.locale
    }

    fn value(&self, _: SheetId, pos: Pos) -> Value {
        self.cells.get(&(pos.row, pos.col)).cloned().unwrap_or_default()
    }

    fn for_each_value(&self, _: SheetId, rect: Rect, f: &mut dyn FnMut(Pos, &Value)) {
        for (&(row, col), v) in self.cells.range((rect.first.row, 0)..=(rect.last.row, u32::MAX)) {
            if (rect.first.col..=rect.last.col).contains(&col) && !v.is_blank() {
                f(Pos::new(row, col), v);
            }
        }
    }

    fn used_rect(&self, _: SheetId) -> Option<Rect> {
        let last_row = self.cells.keys().map(|k| k.0).max()?;
        let last_col = self.cells.keys().map(|k| k.1).max()?;
        Some(Rect::new(Pos::new(0, 0), Pos::new(last_row, last_col)))
    }

    // Otherwise the one empty sheet of a surface typed on its own.
    fn defined_name(&self, name: &str, sheet: SheetId) -> Option<(Rc<Expr>, SheetId)> {
        EmptyEnv::default().defined_name(name, sheet)
    }

    fn spill_rect(&self, sheet: SheetId, pos: Pos) -> Option<Rect> {
        EmptyEnv::default().spill_rect(sheet, pos)
    }

    fn sheet_count(&self) -> usize {
        EmptyEnv::default().sheet_count()
    }

    fn sheet_name(&self, sheet: SheetId) -> Option<String> {
        EmptyEnv::default().sheet_name(sheet)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::XlError;

    #[test]
    fn excel_precedence_and_associativity() {
        let env = MapEnv::default();
        // Excel: negation binds tighter than ^, ^ is left-associative.
        assert_eq!(env.eval("=-2^2"), n(4.0));
        assert_eq!(env.eval("=2^3^2"), n(64.0));
        assert_eq!(env.eval("=2+3*4"), n(14.0));
        assert_eq!(env.eval("=1+2&3"), Value::text("33"));
        assert_eq!(env.eval("=1+2=3"), Value::Bool(true));
        assert_eq!(env.eval("=50%*2"), n(1.0));
        assert_eq!(env.eval("=2^-1"), n(0.5));
        assert_eq!(env.eval("=--2"), n(2.0));
    }

    #[test]
    fn coercions_and_errors() {
        let env = MapEnv::with(&[("A1", n(2.0)), ("A2", Value::text("x")), ("A3", Value::Bool(true))]);
        assert_eq!(env.eval("=\"2\"*3"), n(6.0));
        assert_eq!(env.eval("=TRUE+1"), n(2.0));
        assert_eq!(env.eval("=1&TRUE"), Value::text("1TRUE"));
        assert_eq!(env.eval("=TRUE>1"), Value::Bool(true));
        assert_eq!(env.eval("=1/0"), Value::Error(XlError::Div0));
        assert_eq!(env.eval("=A2+1"), Value::Error(XlError::Value));
        assert_eq!(env.eval("=SQRT(-1)"), Value::Error(XlError::Num));
        assert_eq!(env.eval("=ATAN2(0,0)"), Value::Error(XlError::Div0));
        assert_eq!(env.eval("=POWER(-8,1/3)"), Value::Error(XlError::Num));
        assert_eq!(env.eval("=SUM(A1:A3)"), n(2.0));
        assert_eq!(env.eval("=NOSUCH(1)"), Value::Error(XlError::Name));
        assert_eq!(env.eval("=B7"), Value::Blank);
        assert_eq!(env.eval("=B7=\"\""), Value::Bool(true));
    }

    const MOVED_TABS: [&str; 3] = ["First", "Middle", "Last"];

    /// Three sheets, First, Middle and Last by id, whose tabs were moved: Last's tab shows
    /// second, Middle's last. Each sheet's cells hold 10 to the power of its id, so a sum
    /// tells which sheets it took.
    struct MovedTabs;

    impl Env for MovedTabs {
        fn now(&self) -> f64 {
            EmptyEnv::default().now()
        }

        fn next_random(&self) -> f64 {
            EmptyEnv::default().next_random()
        }

        fn value(&self, sheet: SheetId, _: Pos) -> Value {
            n(10f64.powi(sheet.into()))
        }

        fn for_each_value(&self, sheet: SheetId, rect: Rect, f: &mut dyn FnMut(Pos, &Value)) {
            for row in rect.first.row..=rect.last.row {
                for col in rect.first.col..=rect.last.col {
                    f(Pos::new(row, col), &self.value(sheet, Pos::new(row, col)));
                }
            }
        }

        fn used_rect(&self, _: SheetId) -> Option<Rect> {
            Some(Rect::new(Pos::new(0, 0), Pos::new(0, 0)))
        }

        // No names, no spills: as a surface typed on its own.
        fn defined_name(&self, name: &str, sheet: SheetId) -> Option<(Rc<Expr>, SheetId)> {
            EmptyEnv::default().defined_name(name, sheet)
        }

        fn spill_rect(&self, sheet: SheetId, pos: Pos) -> Option<Rect> {
            EmptyEnv::default().spill_rect(sheet, pos)
        }

        fn sheet_count(&self) -> usize {
            MOVED_TABS.len()
        }

        fn sheet_name(&self, sheet: SheetId) -> Option<String> {
            MOVED_TABS.get(usize::from(sheet)).map(|s| s.to_string())
        }

        fn tab_position(&self, sheet: SheetId) -> usize {
            [0, 2, 1][usize::from(sheet)]
        }
    }

    /// Excel's 3-D references take the sheets whose tabs lie between the two named, as the
    /// tabs stand ("Create a 3-D reference to the same cell range on multiple worksheets":
    /// moving a sheet outside the end points removes it from the reference). The default
    /// span took ids in order, so an environment with its own tab order but no span of its
    /// own summed Middle, whose tab is outside First:Last.
    #[test]
    fn a_3d_reference_spans_the_sheets_between_its_tabs_in_tab_order() {
        assert_eq!(MovedTabs.sheets_spanned(0, 2), vec![0, 2]);
        assert_eq!(MovedTabs.sheets_spanned(1, 0), vec![0, 2, 1]);
        let sheet = |name: &str| MOVED_TABS.iter().position(|s| s.eq_ignore_ascii_case(name)).map(|i| i as SheetId);
        let at = Pos::new(9, 9);
        let sum =
            parse_formula("=SUM(First:Last!A1)", &ParseContext { at, functions: &Registry, sheet: &sheet }).unwrap();
        let value = crate::eval::evaluator::no_lambda(Ctx::new(&MovedTabs, 0, at).eval(&sum)).unwrap_single();
        assert_eq!(value, n(101.0));
    }
}
