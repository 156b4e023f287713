//! `sheets/chamfer.xlsx`: the chamfer model of docs/domain.md §1 as its authors would have built
//! it in Excel. One sheet per chamfer kind with named inputs (sheet-scoped `D`, `f`,
//! `alpha`, `r_`, `eA`, `eB`: Excel reserves the name `r`), one cell per formula of the
//! paper with its number beside it, the results XA ZA XB ZB, and a summary sheet. Standard
//! Excel functions only.
//!
//! The builder here makes the workbook with ncsheet and writes it with our xlsx writer when
//! asked (`NCSHEET_WRITE_SHEETS=1`). The committed file is checked against the paper's
//! formulas and docs/domain.md's values, and by LibreOffice.

mod common;

use std::path::{Path, PathBuf};

use ncsheet::eval::Value;
use ncsheet::formula::address::{parse_cell, Pos};
use ncsheet::io::xlsx::{self, Layout, SheetLayout};
use ncsheet::workbook::Workbook;

/// (formula number, quantity, formula with `{quantity}` for earlier rows, as printed)
type Step = (&'static str, &'static str, &'static str, &'static str);

struct Kind {
    sheet: &'static str,
    title: &'static str,
    diameter: &'static str,
    d: f64,
    e_a: f64,
    note: &'static str,
    /// The formula rows, in runs shared between the kinds where the paper's formulas are.
    steps: &'static [&'static [Step]],
}

const TAN: Step = ("", "tan α", "=SIN(alpha*PI()/180)/COS(alpha*PI()/180)", "tan α, used by the formulas below");
const BETA: Step = ("1", "β", "=PI()/2-alpha*PI()/180", "β = π/2 − α·π/180");
/// The start of both inner chamfers' end A (formulas 16–18).
const INNER_A: [Step; 5] = [
    TAN,
    BETA,
    ("16", "A'D", "=r_/SIN({β})", "A'D = r / sin β"),
    ("17", "DC", "=r_*{tan α}", "DC = AC·tan α, AC = r"),
    ("18", "A'C", "={A'D}-{DC}", "A'C = A'D − DC"),
];
const F_PRIME: Step = ("12", "f'", "=f*{tan α}", "f' = f·tan α");
/// End B, outer and inner alike up to XB (formulas 8–11).
const END_B: [Step; 4] = [
    ("8", "BE", "=eB+r_", "BE = eB + r"),
    ("9", "EF", "={BE}*{tan α}", "EF = BE·tan α"),
    ("10", "B'F", "=r_/SIN({β})", "B'F = r / sin β"),
    ("11", "B'E", "={EF}-{B'F}", "B'E = EF − B'F"),
];
const ZB: Step = ("14", "ZB", "=eB", "ZB = eB");
const INNER_XB_ZB: [Step; 2] = [("15", "XB", "=D+({f'}+{B'E}+r_)*2", "XB = Ds + (f' + B'E + r)·2"), ZB];

const KINDS: [Kind; 3] = [
    Kind {
        sheet: "Outer",
        title: "Outer chamfer at a shaft end",
        diameter: "shaft diameter Dv",
        d: 40.0,
        e_a: 1.0,
        note: "Exact for every angle α.",
        steps: &[
            &[
                TAN,
                BETA,
                ("2", "A'C", "=r_/SIN({β})", "A'C = r / sin β"),
                ("3", "AD", "=eA+r_", "AD = eA + r"),
                ("4", "CD", "={AD}*{tan α}", "CD = AD·tan α"),
                ("5", "A'D", "={CD}+{A'C}", "A'D = CD + A'C"),
                ("6", "XA", "=D+({A'D}-r_)*2", "XA = Dv + (A'D − r)·2"),
                ("7", "ZA", "=-(f+{AD}+r_)", "ZA = −(f + AD + r)"),
            ],
            &END_B,
            &[F_PRIME, ("13", "XB", "=D-({f'}+{B'E}+r_)*2", "XB = Dv − (f' + B'E + r)·2"), ZB],
        ],
    },
    Kind {
        sheet: "Pipe",
        title: "Inner chamfer at the mouth of a through bore (pipe)",
        diameter: "bore diameter Ds",
        d: 30.0,
        e_a: 1.0,
        note: "The paper's inner-chamfer formulas hold at α = 45° (docs/domain.md §1).",
        steps: &[
            &INNER_A,
            &[
                ("21", "DF", "=(eA-r_)*{tan α}", "DF = (eA − r)·tan α"),
                ("22", "XA", "=(D-({DF}+{DC}+{A'C})*2)+2*r_", "XA = [Ds − (DF + DC + A'C)·2] + 2r"),
                F_PRIME,
                ("23", "ZA", "=-({f'}+eA)", "ZA = −(f' + eA)"),
            ],
            &END_B,
            &INNER_XB_ZB,
        ],
    },
    Kind {
        sheet: "Blind",
        title: "Inner chamfer down to the bottom of a blind bore",
        diameter: "bore diameter Ds",
        d: 20.0,
        e_a: 0.0,
        note: "The paper's inner-chamfer formulas hold at α = 45° (docs/domain.md §1); eA = 0 here.",
        steps: &[
            &INNER_A,
            &[("19", "XA", "=(D-2*{A'C})+2*r_", "XA = (Ds − 2·A'C) + 2r"), F_PRIME, ("20", "ZA", "=-{f'}", "ZA = −f'")],
            &END_B,
            &INNER_XB_ZB,
        ],
    },
];

/// docs/domain.md §1 worked values: (sheet, XA, ZA, XB, ZB).
const DOMAIN_TABLE: [(&str, f64, f64, f64, f64); 3] = [
    ("Outer", 44.262742, -4.6, 33.062742, 1.0),
    ("Pipe", 28.937258, -3.0, 36.937258, 1.0),
    ("Blind", 20.937258, -2.0, 26.937258, 1.0),
];

/// Results block: XA ZA XB ZB in G6:G9 of each kind's sheet.
const RESULTS: [(&str, &str); 4] = [("XA", "G6"), ("ZA", "G7"), ("XB", "G8"), ("ZB", "G9")];

fn at(cell: &str) -> Pos {
    parse_cell(cell).unwrap()
}

fn set(wb: &mut Workbook, sheet: u16, cell: &str, input: &str) {
    wb.set_input_deferred(sheet, at(cell), input).unwrap_or_else(|e| panic!("{cell}: {e}"));
}

fn chamfer_workbook() -> (Workbook, Layout) {
    let mut wb = Workbook::new();
    let mut layout = Layout::default();
    let summary = wb.add_sheet("Summary").unwrap();
    let widths = [(0u16, 8.0), (1, 12.0), (2, 14.0), (3, 46.0), (5, 10.0), (6, 14.0), (7, 8.0)];
    let six = "0.000000";
    for kind in &KINDS {
        let s = wb.add_sheet(kind.sheet).unwrap();
        let mut sheet_layout = SheetLayout::default();
        sheet_layout.look.column_widths = widths.to_vec();
        set(&mut wb, s, "A1", &format!("'{} — theoretical tool tip T at the chamfer ends", kind.title));
        set(&mut wb, s, "A2", &format!("'Tamul & Olt, NC lathe chamfers. {}", kind.note));
        set(&mut wb, s, "A4", "Inputs");
        for (cell, text) in [("A5", "Symbol"), ("B5", "Value"), ("C5", "Unit"), ("D5", "Meaning")] {
            set(&mut wb, s, cell, text);
        }
        let inputs = [
            ("D", "D", kind.d, "mm", kind.diameter),
            ("f", "f", 2.0, "mm", "chamfer length along Z"),
            ("α", "alpha", 45.0, "°", "chamfer angle to the Z axis"),
            ("r", "r_", 0.8, "mm", "insert nose radius (named r_: Excel reserves r)"),
            ("eA", "eA", kind.e_a, "mm", "clearance past chamfer end A"),
            ("eB", "eB", 1.0, "mm", "clearance past chamfer end B"),
        ];
        for (i, (symbol, name, value, unit, meaning)) in inputs.iter().enumerate() {
            let row = 6 + i;
            set(&mut wb, s, &format!("A{row}"), symbol);
            set(&mut wb, s, &format!("B{row}"), &value.to_string());
            set(&mut wb, s, &format!("C{row}"), unit);
            set(&mut wb, s, &format!("D{row}"), meaning);
            let target = format!("='{}'!$B${row}", kind.sheet);
            wb.define_name(name, &target, Some(s)).unwrap();
        }
        set(&mut wb, s, "A13", "Formulas, numbered as in the paper");
        for (cell, text) in [("A14", "No."), ("B14", "Quantity"), ("C14", "Value"), ("D14", "Formula as printed")] {
            set(&mut wb, s, cell, text);
        }
        let mut rows: Vec<(&str, usize)> = Vec::new();
        for (i, (no, quantity, formula, printed)) in kind.steps.iter().copied().flatten().enumerate() {
            let row = 15 + i;
            let mut text = formula.to_string();
            for (q, r) in &rows {
                text = text.replace(&format!("{{{q}}}"), &format!("C{r}"));
            }
            assert!(!text.contains('{'), "{}: {quantity} refers to a later row: {text}", kind.sheet);
            if !no.is_empty() {
                set(&mut wb, s, &format!("A{row}"), no);
            }
            set(&mut wb, s, &format!("B{row}"), &format!("'{quantity}"));
            set(&mut wb, s, &format!("C{row}"), &text);
            set(&mut wb, s, &format!("D{row}"), &format!("'{printed}"));
            sheet_layout.look.number_formats.insert(at(&format!("C{row}")), six.into());
            rows.push((quantity, row));
        }
        for (cell, text) in [("F5", "Result"), ("G5", "Value"), ("H5", "Unit")] {
            set(&mut wb, s, cell, text);
        }
        for (i, (quantity, cell)) in RESULTS.iter().enumerate() {
            let row = rows.iter().find(|(q, _)| q == quantity).expect("result row").1;
            set(&mut wb, s, &format!("F{}", 6 + i), quantity);
            set(&mut wb, s, cell, &format!("=C{row}"));
            set(&mut wb, s, &format!("H{}", 6 + i), "mm");
            sheet_layout.look.number_formats.insert(at(cell), six.into());
        }
        layout.sheets.insert(kind.sheet.into(), sheet_layout);
    }
    set(&mut wb, summary, "A1", "'Chamfer coordinates on NC lathes — tool tip T1 past end A, T2 past end B");
    set(&mut wb, summary, "A2", "'X as diameter, Z negative in the material; inputs on each kind's sheet");
    for (cell, text) in [("A4", "Kind"), ("B4", "D"), ("C4", "XA"), ("D4", "ZA"), ("E4", "XB"), ("F4", "ZB")] {
        set(&mut wb, summary, cell, text);
    }
    let mut summary_layout = SheetLayout::default();
    summary_layout.look.column_widths = vec![(0, 10.0)];
    for (i, kind) in KINDS.iter().enumerate() {
        let row = 5 + i;
        set(&mut wb, summary, &format!("A{row}"), kind.sheet);
        set(&mut wb, summary, &format!("B{row}"), &format!("={}!$B$6", kind.sheet));
        for (col, (_, cell)) in ["C", "D", "E", "F"].iter().zip(RESULTS) {
            let target = format!("{col}{row}");
            set(&mut wb, summary, &target, &format!("={}!{cell}", kind.sheet));
            summary_layout.look.number_formats.insert(at(&target), six.into());
        }
    }
    for col in 1..6 {
        summary_layout.look.column_widths.push((col, 12.0));
    }
    layout.sheets.insert("Summary".into(), summary_layout);
    wb.recalculate();
    (wb, layout)
}

fn committed_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("sheets/chamfer.xlsx")
}

fn number(v: &Value) -> f64 {
    match v {
        Value::Number(n) => *n,
        other => panic!("not a number: {other:?}"),
    }
}

/// Asserts the results of each kind's sheet, read by `value(sheet, cell)`, match docs/domain.md.
fn assert_domain_table(who: &str, value: &dyn Fn(&str, &str) -> Value) {
    for (sheet, xa, za, xb, zb) in DOMAIN_TABLE {
        for ((name, cell), want) in RESULTS.iter().zip([xa, za, xb, zb]) {
            let got = number(&value(sheet, cell));
            assert!((got - want).abs() < 5e-7, "{who}: {sheet} {name} is {got}, docs/domain.md says {want}");
        }
    }
}

#[test]
fn ncsheet_computes_the_domain_table() {
    let (wb, _) = chamfer_workbook();
    assert!(wb.problems().is_empty(), "{:?}", wb.problems());
    assert_domain_table("ncsheet", &|sheet, cell| wb.value(wb.sheet_id(sheet).unwrap(), at(cell)));
    // The summary reads the same results.
    assert_eq!(wb.value(0, at("C5")), wb.value(1, at("G6")));
}

/// The shipped file holds the paper's formulas (as the builder above spells them) and, both
/// cached in the file and recomputed from it, docs/domain.md's values. The file is written only
/// when asked (`NCSHEET_WRITE_SHEETS=1`): a missing file fails, it is never made to pass.
#[test]
fn the_committed_sheet_holds_the_papers_formulas_and_domain_values() {
    let (wb, layout) = chamfer_workbook();
    let path = committed_path();
    if std::env::var_os("NCSHEET_WRITE_SHEETS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        xlsx::save_with_layout(&wb, &layout, &path).unwrap();
    }
    assert!(path.exists(), "{} is missing: run with NCSHEET_WRITE_SHEETS=1 to build it", path.display());
    let committed = xlsx::load(&path).unwrap();
    let back = &committed.workbook;
    assert_eq!(back.sheet_names(), wb.sheet_names());
    let (mut names, mut want) = (back.names(), wb.names());
    names.sort();
    want.sort();
    assert_eq!(names, want, "names");
    for sheet in 0..wb.sheet_len() as u16 {
        for (pos, _) in wb.values(sheet) {
            let cell = wb.cell_name(sheet, pos);
            assert_eq!(back.formula(sheet, pos), wb.formula(sheet, pos), "{cell}: run with NCSHEET_WRITE_SHEETS=1");
        }
    }
    let cached = |sheet: &str, cell: &str| {
        let id = back.sheet_id(sheet).unwrap();
        let c = committed.cached.iter().find(|c| c.sheet == id && c.pos == at(cell));
        c.map(|c| c.value.clone()).unwrap_or_else(|| panic!("{sheet}!{cell} has no cached value"))
    };
    assert_domain_table("the file's cached values", &cached);
    assert_domain_table("ncsheet on the file", &|sheet, cell| back.value(back.sheet_id(sheet).unwrap(), at(cell)));
    assert_eq!(
        committed.layout.sheets["Outer"].look.number_formats.get(&at("G6")).map(String::as_str),
        Some("0.000000")
    );
}

#[test]
fn libreoffice_computes_the_domain_table_from_the_file() {
    let Some(soffice) = common::soffice() else {
        println!("skipped: LibreOffice (soffice) is not installed");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let profile = common::recalculating_profile(&dir.path().join("profile"));
    let (wb, layout) = chamfer_workbook();
    let ours = dir.path().join("chamfer.xlsx");
    xlsx::save_with_layout(&wb, &layout, &ours).unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    common::libreoffice_convert(&soffice, &profile, &[ours], &out);
    let theirs = xlsx::load(&out.join("chamfer.xlsx")).unwrap();
    let cached = |sheet: &str, cell: &str| {
        let id = theirs.workbook.sheet_id(sheet).unwrap();
        theirs.cached.iter().find(|c| c.sheet == id && c.pos == at(cell)).map(|c| c.value.clone()).unwrap()
    };
    assert_domain_table("LibreOffice", &cached);
    // Every formula result, not only the four: LibreOffice agrees with ncsheet.
    for c in &theirs.cached {
        let name = &theirs.workbook.sheet_names()[c.sheet as usize];
        let ours = wb.value(wb.sheet_id(name).unwrap(), c.pos);
        assert!(xlsx::values_agree(&c.value, &ours), "{name}!{}: LibreOffice {:?}, ncsheet {ours:?}", c.pos, c.value);
    }
}
