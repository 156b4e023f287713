//! `ncsheet show FILE CELL…`: what is inside a cell — its formula as typed, its value in
//! full and as its number format shows it, the cells it reads and the cells that read it.
//! The repl's `show CELL` prints the same.

use std::cell::RefCell;
use std::collections::HashMap;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use clap::Args;
use ncsheet::formula::address::{Pos, Rect};
use ncsheet::formula::ast::SheetId;
use ncsheet::workbook::Workbook;

use super::output::Shown;
use super::report::{printable, Result};
use super::target::{parse_target, Target};

/// Show cells inside: formula as typed, value, number format, the cells each reads and the
/// cells that read it.
#[derive(Debug, Args)]
pub struct ShowArgs {
    /// The workbook (.csv, .xlsx, .xlsm)
    pub file: PathBuf,
    /// Cells or defined names: B3, Outer!G6, XA (a range shows each of its cells)
    #[arg(value_name = "CELL", required = true, value_parser = parse_target)]
    pub cells: Vec<Target>,
    /// The sheet of cells named without one (default: the active one, where the file opens)
    #[arg(long, value_name = "NAME")]
    pub sheet: Option<String>,
    /// Follow what each cell reads this many steps back: 1 lists the cells it reads, 2 also
    /// what those read, and so on, each with its formula and value
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub depth: u32,
    #[command(flatten)]
    pub timeout: super::limits::TimeoutArg,
    #[command(flatten)]
    pub reading: super::WorkbookOptions,
}

pub fn run(args: ShowArgs, delimiter: Option<u8>) -> Result<()> {
    let doc = super::open(&args.file, delimiter)?;
    let wb = doc.workbook();
    let sheet = super::default_sheet(wb, &args.file, args.sheet.as_deref())?;
    let shown = Shown { layout: doc.layout(), ..Shown::default() };
    let located = args.cells.iter().map(|t| super::locate(wb, &args.file, t, sheet)).collect::<Result<Vec<_>>>()?;
    refuse_huge_descriptions(&located.iter().map(|s| s.rect).collect::<Vec<_>>())?;
    let named = NamedPlaces::default();
    let mut out = BufWriter::new(io::stdout().lock());
    for (i, s) in located.iter().enumerate() {
        if i > 0 {
            writeln!(out)?;
        }
        // Printed as the terminal should show it: a cell's text may hold escapes.
        let described = describe_rect(wb, &shown, &named, s.sheet, s.rect, s.label.as_deref());
        out.write_all(printable(&described).as_bytes())?;
        if args.depth > 1 && s.rect.is_cell() {
            let tree = precedent_tree(wb, &shown, &named, s.sheet, s.rect.first, args.depth);
            out.write_all(printable(&tree).as_bytes())?;
        }
    }
    out.flush()?;
    Ok(())
}

/// The most lines a precedent tree prints: a deep chain of a million cells is cut, saying so.
const MAX_TREE_LINES: usize = 10_000;

/// What a cell reads, followed `depth` steps back as an indented tree, each cell with its
/// formula (or input) and value; a cell met before is named again without its subtree.
fn precedent_tree(wb: &Workbook, shown: &Shown, named: &NamedPlaces, sheet: SheetId, pos: Pos, depth: u32) -> String {
    let mut text = format!("  precedents, {depth} steps back:\n");
    let mut seen = std::collections::HashSet::new();
    seen.insert((sheet, pos));
    let mut lines = 0;
    let mut stack: Vec<(SheetId, Pos, u32)> = children(wb, sheet, pos, 1);
    stack.reverse();
    while let Some((s, p, level)) = stack.pop() {
        if lines == MAX_TREE_LINES {
            text.push_str(&format!("    … cut at {MAX_TREE_LINES} lines\n"));
            break;
        }
        lines += 1;
        let indent = "  ".repeat(level as usize + 1);
        let what = wb.formula(s, p).or_else(|| wb.input(s, p)).unwrap_or_default();
        let first_visit = seen.insert((s, p));
        let again = if first_visit { "" } else { " (above)" };
        let value = shown.text(wb, s, p);
        text.push_str(&format!("{indent}{}  {what}  = {value}{again}\n", place(wb, named, sheet, s, Rect::cell(p))));
        if first_visit && level < depth {
            let mut next = children(wb, s, p, level + 1);
            next.reverse();
            stack.extend(next);
        }
    }
    text
}

/// The cells `pos` reads (ranges as their cells), at `level` in the tree.
fn children(wb: &Workbook, sheet: SheetId, pos: Pos, level: u32) -> Vec<(SheetId, Pos, u32)> {
    let mut cells = Vec::new();
    for (s, rect) in wb.precedents(sheet, pos) {
        let count = rect.rows() as u64 * rect.cols() as u64;
        if count > MAX_TREE_LINES as u64 {
            // A whole column read is one line, not a million.
            cells.push((s, rect.first, level));
            continue;
        }
        for row in rect.first.row..=rect.last.row {
            for col in rect.first.col..=rect.last.col {
                cells.push((s, Pos::new(row, col), level));
            }
        }
    }
    cells
}

/// Each cell of a rectangle, described; a blank line between cells.
pub fn describe_rect(
    wb: &Workbook,
    shown: &Shown,
    named: &NamedPlaces,
    sheet: SheetId,
    rect: Rect,
    label: Option<&str>,
) -> String {
    let mut parts = Vec::new();
    for row in rect.first.row..=rect.last.row {
        for col in rect.first.col..=rect.last.col {
            parts.push(describe(wb, shown, named, sheet, Pos::new(row, col), label.filter(|_| rect.is_cell())));
        }
    }
    parts.join("\n")
}

/// One cell as lines of `field  text`.
pub fn describe(
    wb: &Workbook,
    shown: &Shown,
    named: &NamedPlaces,
    sheet: SheetId,
    pos: Pos,
    label: Option<&str>,
) -> String {
    let mut lines: Vec<(&str, String)> = Vec::new();
    let title = wb.cell_name(sheet, pos);
    let names = named.at(wb, sheet, Rect::cell(pos));
    let title = match (label, names.is_empty()) {
        (Some(l), _) => format!("{title} ({l})"),
        (None, false) => format!("{title} ({})", names.join(", ")),
        (None, true) => title,
    };
    // Formulas and typed numbers as the user's locale spells them.
    let locale = wb.settings().locale;
    if let Some(f) = wb.formula(sheet, pos) {
        lines.push(("formula", locale.local_formula(&f)));
    } else if let Some(input) = wb.input(sheet, pos) {
        let number = matches!(wb.value(sheet, pos), ncsheet::eval::Value::Number(_));
        lines.push(("input", if number { locale.localize_shown(&input) } else { input }));
    }
    let value = wb.value(sheet, pos);
    let full =
        Shown { layout: shown.layout, raw: true, formulas: false, width: shown.width, parsed: Default::default() };
    lines.push(("value", if value.is_blank() { "(blank)".into() } else { full.text(wb, sheet, pos) }));
    if let Some(code) = shown.format_code(wb, sheet, pos) {
        lines.push(("format", code.to_string()));
        lines.push(("shown", shown.text(wb, sheet, pos)));
    }
    for note in wb.notes(sheet, pos) {
        lines.push(("note", note));
    }
    for note in super::locale::foreign_inputs_of(wb, sheet, pos) {
        lines.push(("note", note));
    }
    let reads = wb.precedents(sheet, pos);
    if !reads.is_empty() {
        lines.push(("reads", listed(reads.len(), reads.iter().map(|&(s, r)| place(wb, named, sheet, s, r)))));
    }
    let read_by = wb.dependents(sheet, pos);
    if !read_by.is_empty() {
        let places = read_by.iter().map(|&(s, p)| place(wb, named, sheet, s, Rect::cell(p)));
        lines.push(("read by", listed(read_by.len(), places)));
    }
    let mut text = format!("{title}\n");
    for (field, value) in lines {
        text.push_str(&format!("  {field:<8} {value}\n"));
    }
    text
}

/// The most places a `reads` or `read by` line names: a running total filled down
/// (`=SUM(A$1:A5)`) has every cell of the column read by all those below it, and described
/// whole a column of 100,000 such cells named 5 billion places.
const MAX_LISTED_PLACES: usize = 100;

/// The first [`MAX_LISTED_PLACES`] of `count` places, and how many more there are.
fn listed(count: usize, places: impl Iterator<Item = String>) -> String {
    let mut text = places.take(MAX_LISTED_PLACES).collect::<Vec<_>>().join(", ");
    if count > MAX_LISTED_PLACES {
        text.push_str(&format!(", … ({} more, {count} in all)", count - MAX_LISTED_PLACES));
    }
    text
}

/// `B3`, `Outer!B3 (D)`: the sheet when it is another one, and the names that point there.
fn place(wb: &Workbook, named: &NamedPlaces, from: SheetId, sheet: SheetId, rect: Rect) -> String {
    let mut text = if sheet == from {
        rect.to_string()
    } else {
        let cell = wb.cell_name(sheet, rect.first);
        let sheet_part = &cell[..cell.rfind('!').unwrap_or(0)];
        format!("{sheet_part}!{rect}")
    };
    let names = named.at(wb, sheet, rect);
    if !names.is_empty() {
        text.push_str(&format!(" ({})", names.join(", ")));
    }
    text
}

/// The defined names that point exactly at each place of a sheet, found once per sheet for
/// one `show`: reading every name again for each cell and each place it names took minutes
/// for one cell of a workbook of 20,000 names.
#[derive(Default)]
pub struct NamedPlaces {
    by_sheet: RefCell<HashMap<SheetId, HashMap<Rect, Vec<String>>>>,
}

impl NamedPlaces {
    /// The names that point exactly at `rect` of `sheet` (a name of another sheet's scope read
    /// from that sheet), in the workbook's order.
    fn at(&self, wb: &Workbook, sheet: SheetId, rect: Rect) -> Vec<String> {
        let mut by_sheet = self.by_sheet.borrow_mut();
        let places = by_sheet.entry(sheet).or_insert_with(|| {
            let mut places: HashMap<Rect, Vec<String>> = HashMap::new();
            for (name, _, scope) in wb.name_trees() {
                if let Some((s, r)) = wb.name_reference(&name, scope.unwrap_or(sheet)) {
                    if s == sheet {
                        places.entry(r).or_default().push(name);
                    }
                }
            }
            places
        });
        places.get(&rect).cloned().unwrap_or_default()
    }
}

/// For the repl: a file's cells described, as `show` does.
pub fn describe_target(wb: &Workbook, file: &Path, target: &Target, sheet: SheetId) -> Result<String> {
    let s = super::locate(wb, file, target, sheet)?;
    refuse_huge_descriptions(&[s.rect])?;
    Ok(describe_rect(wb, &Shown::default(), &NamedPlaces::default(), s.sheet, s.rect, s.label.as_deref()))
}

/// The most cells `show` describes at once: each is a few lines, blanks included, so
/// `A1:XFD1048576` (17 billion cells) aborted at the memory cap and `A1:J1000000` wrote
/// 349 MB of "(blank)".
pub const MAX_DESCRIBED_CELLS: u64 = 100_000;

/// Refuses ranges of more cells in all than [`MAX_DESCRIBED_CELLS`]: many ranges each under
/// it described as much as one over it (30 of 100,000 cells wrote 88 MB in 35 s).
fn refuse_huge_descriptions(rects: &[Rect]) -> Result<()> {
    let cells: u64 = rects.iter().map(|r| r.rows() as u64 * r.cols() as u64).sum();
    if cells <= MAX_DESCRIBED_CELLS {
        return Ok(());
    }
    let what = match rects {
        [one] => format!("{one} is {cells} cells"),
        _ => format!("the ranges are {cells} cells in all"),
    };
    Err(super::report::Error::User(format!(
        "{what}, more than the {MAX_DESCRIBED_CELLS} `show` describes at once; name a smaller range \
         (or print values with `eval FILE RANGE`)"
    )))
}
