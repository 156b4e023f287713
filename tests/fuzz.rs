//! Fuzz targets, one per input ncsheet reads (issue 19): formula text, csv bytes, xlsx
//! packages mutated from a good one, macro source and surface formulas. Each runs a bounded
//! number of proptest cases inside `cargo test` and asserts that nothing panics (a panic is
//! a failed case; a stack overflow would abort the run). Inputs mix random characters with
//! the pieces hostile text is made of: deep brackets, long operator chains, huge numbers.

mod common;

use std::path::Path;

use proptest::prelude::*;

use ncsheet::eval::functions::Registry;
use ncsheet::eval::surface::FormulaSurface;
use ncsheet::eval::Ctx;
use ncsheet::formula::address::parse_cell;
use ncsheet::formula::parse::ParseContext;
use ncsheet::formula::Pos;
use ncsheet::io::xlsx;
use ncsheet::vba::{self, RunOptions};
use ncsheet::workbook::Workbook;

/// Pieces of formulas, hostile ones among them; a formula is a string of them.
fn formula_piece() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => "[-+*/^&%,;:(){}\"'!$#@<>= .0-9A-Za-z]{1,6}",
        1 => prop::sample::select(vec![
            "SUM(", "IF(", "LET(x,", "LAMBDA(x,", "TEXT(", "FIXED(", "MOD(", "REPT(\"ab\",", "SEQUENCE(",
            "OFFSET(A1,", "INDIRECT(\"", "1E+308", "-1E+308", "2^1024", "A1:XFD1048576", "A1#", "\"%%%%\"",
            "\"0.0E+0%\"", "Sheet2!", "1E-320", "#REF!", "{1,2;3,4}", "XFD1048576",
        ])
        .prop_map(str::to_string),
        1 => (1usize..600, prop::sample::select(vec!["(", "-", "ABS(", "+1", "&\"x\"", "*A1"]))
            .prop_map(|(n, s)| s.repeat(n)),
    ]
}

fn formula() -> impl Strategy<Value = String> {
    prop::collection::vec(formula_piece(), 0..12).prop_map(|pieces| format!("={}", pieces.concat()))
}

fn config(cases: u32) -> ProptestConfig {
    ProptestConfig { cases, failure_persistence: None, ..ProptestConfig::default() }
}

proptest! {
    #![proptest_config(config(200))]

    #[test]
    fn formula_text_never_panics(a in formula(), b in formula()) {
        let mut wb = Workbook::with_sheet();
        let _ = wb.set_input(0, parse_cell("B2").unwrap(), "3");
        let _ = wb.set_input(0, parse_cell("A1").unwrap(), &a);
        let _ = wb.set_input(0, parse_cell("C3").unwrap(), &b);
        let _ = wb.value(0, parse_cell("A1").unwrap());
        let _ = wb.formula(0, parse_cell("A1").unwrap());
        let _ = wb.problems();
    }

    #[test]
    fn surface_formulas_never_panic(text in formula()) {
        let ctx = ParseContext { at: Pos::new(0, 0), functions: &Registry, sheet: &|_| None };
        if let Ok(surface) = FormulaSurface::parse(&text, &ctx) {
            let wb = Workbook::with_sheet();
            let mut eval = Ctx::new(&wb, 0, Pos::new(0, 0));
            let mut bound = surface.bind(&mut eval);
            let _ = bound.height_at(0.5, -0.25);
            let _ = bound.sample_at(0.5, -0.25);
        }
    }

    #[test]
    fn csv_bytes_never_panic(bytes in prop::collection::vec(prop_oneof![
        4 => any::<u8>(),
        4 => prop::sample::select(b"=,\"\n\r;A1+(-)".to_vec()),
    ], 0..400)) {
        if let Ok(wb) = ncsheet::io::csv::read(&bytes) {
            let _ = wb.values(0);
            let _ = wb.problems();
        }
    }
}

/// Macro statements, hostile ones among them.
fn macro_line() -> impl Strategy<Value = String> {
    prop_oneof![
        2 => "[-+*/^&(),.:=<> \"'_0-9A-Za-z]{0,24}",
        2 => prop::sample::select(vec![
            "If x > 0 Then", "End If", "For i = 1 To 3", "Next", "Do While i < 5", "Loop", "x = x & x",
            "Debug.Print x", "ReDim a(1E+300)", "x = Space(1E+9)", "Select Case x", "Case 1", "End Select",
            "With Range(\"A1\")", "End With", "x = 1 + _", "GoTo 10", "10 x = 2", "x = Not Not x", "Dim a(3)",
            "a(5) = 1", "x = Replace(x, \"a\", x & x)", "Call Main", "On Error Resume Next", "x = 1 / 0",
        ])
        .prop_map(str::to_string),
    ]
}

proptest! {
    #![proptest_config(config(150))]

    #[test]
    fn macro_source_never_panics(lines in prop::collection::vec(macro_line(), 0..16)) {
        let src = format!("Sub Main()\n{}\nEnd Sub\n", lines.join("\n"));
        let mut wb = Workbook::with_sheet();
        let options = RunOptions { max_statements: 10_000, ..RunOptions::default() };
        let _ = vba::run(&mut wb, &src, "fuzz.bas", &options);
    }
}

/// A good package from our own writer, formulas and text in it.
fn good_package() -> Vec<u8> {
    let mut wb = Workbook::with_sheet();
    wb.add_sheet("Second").unwrap();
    for (cell, input) in
        [("A1", "2"), ("A2", "=A1*3"), ("B1", "text"), ("B2", "=CONCAT(B1,\"!\")"), ("C1", "=SEQUENCE(3)")]
    {
        let _ = wb.set_input(0, parse_cell(cell).unwrap(), input);
    }
    let _ = wb.set_input(1, parse_cell("C3").unwrap(), "=Sheet1!A2+1");
    xlsx::to_bytes(&wb, &xlsx::Layout::default()).unwrap()
}

/// The package with every part stored uncompressed, so that byte mutations reach the XML.
fn stored(package: &[u8]) -> Vec<u8> {
    let options = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
    common::rewrite_package(package, options, &mut |_, data| data).finish().unwrap().into_inner()
}

proptest! {
    #![proptest_config(config(150))]

    #[test]
    fn mutated_xlsx_packages_never_panic(
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8),
        compressed in any::<bool>(),
    ) {
        let good = good_package();
        let mut bytes = if compressed { good } else { stored(&good) };
        for (at, byte) in edits {
            let i = at.index(bytes.len());
            bytes[i] = byte;
        }
        if let Ok(imported) = xlsx::load_bytes(&bytes, Path::new("fuzz.xlsx")) {
            let _ = imported.workbook.problems();
        }
    }
}
