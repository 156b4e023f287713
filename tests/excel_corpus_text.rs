//! Excel itself as the oracle for the logical, lookup, text and information functions: every
//! formula cell of the workbooks below is evaluated on Excel's cached values and compared
//! with its own cached value (the harness is `common::excel_oracle`). Run with
//! `cargo test --test excel_corpus_text -- --nocapture` for the per-file and per-function
//! tables.

mod common;

use common::excel_oracle::{check, Allowed, Suite};

const SUITE: Suite = Suite {
    // The function tests, and the templates (real sheets, whose formulas count where they
    // use only what we implement).
    sources: &[
        "calc_tests/LOGICAL",
        "calc_tests/LOOKUP_AND_REFERENCE",
        "calc_tests/TEXT",
        "calc_tests/INFORMATION",
        "calc_tests/DATABASE",
        "calc_tests/logical.xlsx",
        "calc_tests/simple_functions.xlsx",
        "templates",
    ],
    allowed: ALLOWED,
    excused_texts: &[],
};

/// Cells where we knowingly differ from Excel.
const ALLOWED: &[Allowed] = &[
    // FIXME(functions/financial.rs): DOLLARDE/DOLLARFR of a boolean fraction: #VALUE! in Excel.
    Allowed {
        file: "calc_tests/TEXT/DOLLARs.xlsx",
        sheet: "Sheet1",
        cells: &["C11", "D11", "C12", "D12"],
        why: "boolean fraction is #VALUE! in Excel",
    },
    // The argument cells hold #CALC! and #SPILL!, which the file stores as #VALUE! plus
    // rich-value metadata that calamine does not read.
    Allowed {
        file: "calc_tests/INFORMATION/ERROR.TYPE.xlsx",
        sheet: "Sheet1",
        cells: &["B8", "B14"],
        why: "argument is #CALC!/#SPILL! stored as #VALUE!",
    },
    // XMATCH's match mode 3 (regular expressions) is not implemented: #VALUE!.
    Allowed {
        file: "calc_tests/LOOKUP_AND_REFERENCE/XMATCH.xlsx",
        sheet: "Sheet1",
        cells: &["D6", "D7", "B14"],
        why: "XMATCH regular-expression mode",
    },
    // Day-first dates (the workbook is en-GB, Excel Online): "10-12-1999" and "2/3/2023" are
    // read month first, as in the US.
    Allowed {
        file: "calc_tests/TEXT/T_VALUE_VALUETOTEXT.xlsx",
        sheet: "Sheet1",
        cells: &["I5", "C15"],
        why: "VALUE of day-first date text",
    },
    // An empty result is #CALC!, which the file stores as #VALUE! (as for ERROR.TYPE above).
    Allowed {
        file: "calc_tests/LOOKUP_AND_REFERENCE/DROP_TAKE.xlsx",
        sheet: "Sheet1",
        cells: &["C2", "E2", "F2", "I2", "L2"],
        why: "#CALC! (empty array) stored as #VALUE!",
    },
    Allowed {
        file: "calc_tests/LOOKUP_AND_REFERENCE/FILTER_ERRORS.xlsx",
        sheet: "Sheet1",
        cells: &["E1"],
        why: "#CALC! (nothing kept) stored as #VALUE!",
    },
];

#[test]
fn excel_cached_values_agree() {
    check(&SUITE);
}
