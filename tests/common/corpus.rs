//! Where the Excel oracle corpora are: vendored under `tests/data/excel-corpus` (README.md there
//! lists their sources and licences), or `NCSHEET_EXCEL_CORPUS`.

use std::path::PathBuf;

/// The corpus folder, or `None` (with a message) on a machine without it. On CI (`CI` set)
/// a missing corpus is a failure, so a green run always means the comparison ran.
pub fn root() -> Option<PathBuf> {
    let path = path();
    if path.is_dir() {
        return Some(path);
    }
    assert!(std::env::var_os("CI").is_none(), "Excel corpus not found at {}", path.display());
    eprintln!("skipped: Excel corpus not found at {}", path.display());
    None
}

/// Where the corpus should be, whether or not it is there.
pub fn path() -> PathBuf {
    std::env::var_os("NCSHEET_EXCEL_CORPUS")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/excel-corpus/ironcalc")))
}

/// The public corpus (Excel-saved workbooks from public projects' test data):
/// `tests/data/excel-corpus/public` (beside [`path`]'s folder), or `NCSHEET_EXCEL_PUBLIC_CORPUS`.
pub fn public_path() -> PathBuf {
    std::env::var_os("NCSHEET_EXCEL_PUBLIC_CORPUS").map(PathBuf::from).unwrap_or_else(|| {
        let ironcalc = path();
        ironcalc.parent().map_or_else(|| PathBuf::from("public"), |p| p.join("public"))
    })
}

/// [`public_path`] when the corpus is there; `None` (the caller skips) without it, a
/// failure under CI.
pub fn public_root() -> Option<PathBuf> {
    let root = public_path();
    if !root.is_dir() {
        assert!(std::env::var_os("CI").is_none(), "public Excel corpus not found at {}", root.display());
        eprintln!("skipped: public Excel corpus not found at {}", root.display());
        return None;
    }
    Some(root)
}

/// Files the corpus README lists as not produced by Excel (relative to [`root`]): their
/// cached values are no oracle.
pub const NOT_FROM_EXCEL: &[&str] = &[
    "calc_tests/LOOKUP_AND_REFERENCE/XMATCH_arrays.xlsx",
    "calc_tests/STATISTICAL/GEOMEAN.xlsx",
    "calc_tests/array_in_scalar_repro.xlsx",
    "docs/CHOOSE.xlsx",
    "libreoffice_888_example.xlsx",
    "missing_r_on_row.xlsx",
    "openpyxl_example.xlsx",
    "shared_formula_volatile.xlsx",
];

/// The Excel 97–2003 corpus (real .xls files Excel saved, with Excel's values in their FORMULA
/// records): `tests/data/excel-corpus/xls` (beside [`path`]'s folder), or `NCSHEET_EXCEL_XLS_CORPUS`.
pub fn xls_path() -> PathBuf {
    std::env::var_os("NCSHEET_EXCEL_XLS_CORPUS").map(PathBuf::from).unwrap_or_else(|| {
        let ironcalc = path();
        ironcalc.parent().map_or_else(|| PathBuf::from("xls"), |p| p.join("xls"))
    })
}
