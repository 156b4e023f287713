//! `ncsheet info FILE`: what a workbook holds, before looking at any cell — its sheets with
//! their used ranges and formula counts, its defined names, whether it carries macros, and
//! how ncsheet calculates it.

use std::io::{self, BufWriter, Write};
use std::path::PathBuf;

use clap::Args;
use ncsheet::formula::address::{Pos, Rect};

use super::report::Result;

/// List a workbook's sheets (used range, formulas), defined names, macros and calculation.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// The workbook (.csv, .xlsx, .xlsm)
    pub file: PathBuf,
}

pub fn run(args: InfoArgs) -> Result<()> {
    let opened = super::open(&args.file)?;
    let wb = &opened.workbook;
    let mut out = BufWriter::new(io::stdout().lock());
    writeln!(out, "{}", args.file.display())?;
    writeln!(out, "sheets:")?;
    let names = wb.sheet_names();
    let width = names.iter().map(|n| n.chars().count()).max().unwrap_or(0);
    for (id, name) in names.iter().enumerate() {
        let id = id as u16;
        let used =
            wb.used_rect(id).map_or_else(|| "empty".to_string(), |r| Rect::new(Pos::new(0, 0), r.last).to_string());
        let cells = wb.values(id);
        let formulas = cells.iter().filter(|(p, _)| wb.is_formula(id, *p)).count();
        writeln!(out, "  {name:<width$}  {used:<10} {} cells, {formulas} formulas", cells.len())?;
    }
    let defined = wb.names();
    if defined.is_empty() {
        writeln!(out, "defined names: none")?;
    } else {
        writeln!(out, "defined names:")?;
        let width = defined.iter().map(|(n, _, _)| n.chars().count()).max().unwrap_or(0);
        for (name, formula, scope) in &defined {
            let scope = scope.map_or(String::new(), |s| format!("  (sheet {} only)", names[s as usize]));
            writeln!(out, "  {name:<width$}  {formula}{scope}")?;
        }
    }
    let macros = opened.layout.as_ref().is_some_and(|l| l.vba_project.is_some());
    let macros = if macros {
        "a VBA project (kept when saved as .xlsm; ncsheet runs macros from .bas files: ncsheet run)"
    } else {
        "none"
    };
    writeln!(out, "macros: {macros}")?;
    writeln!(
        out,
        "calculation: automatic, all formulas recomputed on load; circular references are #CIRC! (no iteration)"
    )?;
    out.flush()?;
    Ok(())
}
