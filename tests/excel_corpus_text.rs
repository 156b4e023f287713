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
    // The first cut of the function library (issue 12) differs from Excel here.
    Allowed {
        file: "calc_tests/LOOKUP_AND_REFERENCE/SORT.xlsx",
        sheet: "Sheet1",
        cells: &["D1", "E1", "M1"],
        why: "FIXME(#12): SORT by several keys and where blanks sort",
    },
    Allowed {
        file: "calc_tests/TEXT/TEXTBEFORE_TEXTAFTER.xlsx",
        sheet: "Sheet1",
        cells: &["H18", "J18", "H19", "J19", "H20", "J20"],
        why: "FIXME(#12): no instance and a delimiter longer than the text is #N/A in Excel, #VALUE! here",
    },
    Allowed {
        file: "calc_tests/DATABASE/DCOUNT_DCOUNTA_DGET_DPRODUCT.xlsx",
        sheet: "DCOUNT_DCOUNTA",
        cells: &["B38", "C38", "B43", "C43", "B51", "C51", "B56", "C56", "B57", "C57", "B58", "C58", "B65", "C65", "B67", "B69", "C69"],
        why: "FIXME(#12): D-function criteria cases Excel reads otherwise (headers outside the database, a field as number text, boolean and number criteria)",
    },
    Allowed {
        file: "calc_tests/DATABASE/DCOUNT_DCOUNTA_DGET_DPRODUCT.xlsx",
        sheet: "DGET",
        cells: &["B38", "B50"],
        why: "FIXME(#12): D-function criteria cases Excel reads otherwise (headers outside the database, a field as number text, boolean and number criteria)",
    },
    Allowed {
        file: "calc_tests/DATABASE/DCOUNT_DCOUNTA_DGET_DPRODUCT.xlsx",
        sheet: "DPRODUCT",
        cells: &["B27", "B38", "B42", "B50", "B54", "B56", "B57", "B58", "B63"],
        why: "FIXME(#12): D-function criteria cases Excel reads otherwise (headers outside the database, a field as number text, boolean and number criteria)",
    },
    Allowed {
        file: "calc_tests/DATABASE/DMIN_DMAX_DAVERAGE_DSUM.xlsx",
        sheet: "DMIN_DMAX_DAVERAGE_DSUM",
        cells: &["B38", "C38", "D38", "E38", "B43", "C43", "D43", "E43", "B51", "C51", "D51", "E51", "B56", "C56", "D56", "E56", "B57", "D57", "E57", "B58", "C58", "D58", "E58", "B63", "C63", "D63", "E63"],
        why: "FIXME(#12): D-function criteria cases Excel reads otherwise (headers outside the database, a field as number text, boolean and number criteria)",
    },
    Allowed {
        file: "calc_tests/DATABASE/DVAR_DVARP_DSTDEV_DSTDEVP.xlsx",
        sheet: "DVAR_DVARP_DSTDEV_DSTDEVP",
        cells: &["B38", "C38", "D38", "E38", "B43", "C43", "D43", "E43", "B51", "C51", "D51", "E51", "B56", "C56", "D56", "E56", "B57", "C57", "D57", "E57", "B58", "C58", "D58", "E58", "B63", "C63", "D63", "E63"],
        why: "FIXME(#12): D-function criteria cases Excel reads otherwise (headers outside the database, a field as number text, boolean and number criteria)",
    },
];

#[test]
fn excel_cached_values_agree() {
    check(&SUITE);
}
