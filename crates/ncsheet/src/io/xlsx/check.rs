//! Where ncsheet's results differ from the values Excel cached in the file
//! (`ncsheet eval --check FILE`).

use crate::eval::{Value, XlError};
use crate::formula::address::Pos;
use crate::formula::ast::SheetId;
use crate::workbook::Workbook;

use super::CachedValue;

/// Numbers agree when they differ by at most this fraction of the larger magnitude.
pub const REL_TOLERANCE: f64 = 1e-9;

/// A cell whose recomputed value is not the one Excel stored.
#[derive(Clone, Debug, PartialEq)]
pub struct Difference {
    pub sheet: SheetId,
    pub pos: Pos,
    /// The formula that computes the cell (its anchor's, for a value an array spilled into).
    pub formula: Option<String>,
    pub excel: Value,
    pub ncsheet: Value,
    /// The formula calls NOW, TODAY or a random function: a difference is expected.
    pub volatile: bool,
}

/// Every cached value the recomputed workbook disagrees with, in file order.
pub fn compare_cached(wb: &Workbook, cached: &[CachedValue]) -> Vec<Difference> {
    let mut out = Vec::new();
    for c in cached {
        let ours = wb.value(c.sheet, c.pos);
        if values_agree(&c.value, &ours) {
            continue;
        }
        let formula = wb.formula(c.sheet, c.anchor);
        let volatile = wb.calls_volatile(c.sheet, c.anchor);
        out.push(Difference { sheet: c.sheet, pos: c.pos, formula, excel: c.value.clone(), ncsheet: ours, volatile });
    }
    out
}

/// Whether a value Excel cached and one ncsheet computed are the same result: numbers within
/// [`REL_TOLERANCE`], everything else exactly. An error Excel cached as text (`t="str"`)
/// equals the error.
pub fn values_agree(excel: &Value, ours: &Value) -> bool {
    match (excel, ours) {
        (Value::Number(a), Value::Number(b)) => a == b || (a - b).abs() <= REL_TOLERANCE * a.abs().max(b.abs()),
        (Value::Text(t), Value::Error(e)) => t.parse::<XlError>() == Ok(*e),
        (a, b) => a == b,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_agree_to_a_relative_tolerance_other_values_exactly() {
        assert!(values_agree(&Value::Number(1.0), &Value::Number(1.0 + 1e-12)));
        assert!(!values_agree(&Value::Number(1.0), &Value::Number(1.0 + 1e-6)));
        assert!(values_agree(&Value::Number(0.0), &Value::Number(0.0)));
        assert!(!values_agree(&Value::Number(0.0), &Value::Number(1e-300)));
        assert!(values_agree(&Value::text("#N/A"), &Value::Error(XlError::NA)));
        assert!(!values_agree(&Value::text("1"), &Value::Number(1.0)));
        assert!(!values_agree(&Value::Bool(true), &Value::Number(1.0)));
    }
}
