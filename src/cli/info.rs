//! `ncsheet info FILE`: what a workbook holds, before looking at any cell — its sheets with
//! their used ranges and formula counts, its defined names and tables, whether it carries
//! macros, and the file's calculation settings (with where ncsheet calculates otherwise).

use std::io::{self, BufWriter, Write};
use std::path::PathBuf;

use clap::Args;
use ncsheet::formula::address::{Pos, Rect};
use ncsheet::io::xlsx::{Calculation, Table};

use super::report::Result;

/// List a workbook's sheets (used range, formulas), defined names, tables, macros and its
/// calculation settings.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// The workbook (.csv, .xlsx, .xlsm)
    pub file: PathBuf,
    #[command(flatten)]
    pub timeout: super::limits::TimeoutArg,
    #[command(flatten)]
    pub reading: super::WorkbookOptions,
}

pub fn run(args: InfoArgs, delimiter: Option<u8>) -> Result<()> {
    let doc = super::open(&args.file, delimiter)?;
    let wb = doc.workbook();
    let mut out = BufWriter::new(io::stdout().lock());
    writeln!(out, "{}", args.file.display())?;
    writeln!(out, "sheets:")?;
    let names = wb.sheet_names();
    let width = names.iter().map(|n| n.chars().count()).max().unwrap_or(0);
    // In tab order, as Excel shows them (a macro may have moved a sheet).
    for &id in wb.tab_order() {
        let name = &names[id as usize];
        let used =
            wb.used_rect(id).map_or_else(|| "empty".to_string(), |r| Rect::new(Pos::new(0, 0), r.last).to_string());
        let cells = wb.values(id);
        let formulas = cells.iter().filter(|(p, _)| wb.is_formula(id, *p)).count();
        writeln!(out, "  {}  {used:<10} {} cells, {formulas} formulas", padded(name, width), cells.len())?;
    }
    let defined = wb.names();
    if defined.is_empty() {
        writeln!(out, "defined names: none")?;
    } else {
        writeln!(out, "defined names:")?;
        let width = defined.iter().map(|(n, _, _)| n.chars().count()).max().unwrap_or(0);
        for (name, formula, scope) in &defined {
            let scope = scope.map_or(String::new(), |s| format!("  (sheet {} only)", names[s as usize]));
            writeln!(out, "  {}  {formula}{scope}", padded(name, width))?;
        }
    }
    let macros = doc.layout().is_some_and(|l| l.vba_project.is_some());
    let macros = if macros {
        "a VBA project (kept when saved as .xlsm; `ncsheet macros FILE` lists its macros, `ncsheet run FILE --sub MODULE.SUB` runs one)"
    } else {
        "none"
    };
    writeln!(out, "macros: {macros}")?;
    let locale = super::locale::in_force();
    writeln!(
        out,
        "locale: {} ({}; from {}): decimal '{}', list separator '{}', dates {}",
        locale.locale,
        locale.locale.english_name,
        locale.source,
        locale.locale.decimal,
        locale.locale.list,
        locale.locale.short_date
    )?;
    match doc.layout() {
        Some(layout) => {
            write_tables(&mut out, &layout.tables, &names)?;
            write_calculation(&mut out, &layout.calculation)?;
        }
        None => writeln!(out, "tables: none (a csv file)\ncalculation: none stored (a csv file)")?,
    }
    out.flush()?;
    Ok(())
}

/// Names are aligned in a column no wider than this: a longer one (a name may be 65,535
/// characters and more) is written whole and pushes only its own line.
const MAX_NAME_COLUMN: usize = 40;

/// `name` followed by spaces up to `width` characters (at most [`MAX_NAME_COLUMN`]); padded
/// by hand because `format!`'s width is a u16 and panics past 65,535.
fn padded(name: &str, width: usize) -> String {
    let width = width.min(MAX_NAME_COLUMN);
    let len = name.chars().count();
    format!("{name}{}", " ".repeat(width.saturating_sub(len)))
}

/// Each table: its name, where it stands and its column names.
fn write_tables(out: &mut dyn Write, tables: &[Table], sheets: &[String]) -> io::Result<()> {
    if tables.is_empty() {
        return writeln!(out, "tables: none");
    }
    writeln!(out, "tables:")?;
    let width = tables.iter().map(|t| t.name.chars().count()).max().unwrap_or(0);
    for t in tables {
        let place = format!("{}!{}", sheets.get(t.sheet as usize).map_or("?", String::as_str), t.rect);
        writeln!(out, "  {}  {place}  columns: {}", padded(&t.name, width), t.columns.join(", "))?;
    }
    Ok(())
}

/// The file's calculation settings, and a word where ncsheet does otherwise.
fn write_calculation(out: &mut dyn Write, c: &Calculation) -> io::Result<()> {
    let on = |b: bool| if b { "on" } else { "off" };
    writeln!(out, "calculation (as the file asks):")?;
    writeln!(out, "  mode              {}", c.mode)?;
    writeln!(out, "  iterate           {}", on(c.iterate))?;
    if c.iterate {
        writeln!(out, "  iterations        at most {}, until no change exceeds {}", c.iterate_count, c.iterate_delta)?;
    }
    writeln!(out, "  full calc on load {}", on(c.full_calc_on_load))?;
    writeln!(out, "  date system       {}", if c.date_1904 { "1904" } else { "1900" })?;
    if c.mode == "manual" {
        writeln!(out, "  note: ncsheet recalculates every formula anyway; `eval --check` lists what differs")?;
    }
    if c.iterate {
        writeln!(out, "  note: ncsheet iterates circular references as the file asks (Excel's order may differ)")?;
    }
    Ok(())
}
