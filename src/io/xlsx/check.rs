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
        let volatile = formula.as_deref().is_some_and(calls_volatile);
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

/// Whether formula text calls a function whose result changes on every recalculation.
fn calls_volatile(formula: &str) -> bool {
    const VOLATILE: [&str; 5] = ["NOW", "TODAY", "RAND", "RANDBETWEEN", "RANDARRAY"];
    let b = formula.as_bytes();
    let mut i = 0;
    let mut in_string = false;
    while i < b.len() {
        let c = b[i];
        if c == b'"' {
            in_string = !in_string;
        } else if !in_string && (c.is_ascii_alphabetic() || c == b'_') && (i == 0 || !is_name_byte(b[i - 1])) {
            let start = i;
            while i < b.len() && is_name_byte(b[i]) {
                i += 1;
            }
            let name = &formula[start..i];
            let name = name.rsplit('.').next().unwrap_or(name);
            if b.get(i) == Some(&b'(') && VOLATILE.iter().any(|v| v.eq_ignore_ascii_case(name)) {
                return true;
            }
            continue;
        }
        i += 1;
    }
    false
}

fn is_name_byte(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_' || c == b'.'
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

    #[test]
    fn volatile_calls_are_recognized_outside_strings() {
        assert!(calls_volatile("=NOW()-A1"));
        assert!(calls_volatile("=INT(RAND()*6)"));
        assert!(calls_volatile("=_xlfn.RANDARRAY(3)"));
        assert!(!calls_volatile("=\"NOW()\"&A1"));
        assert!(!calls_volatile("=TODAYS(1)+MYRAND(2)"));
    }
}
