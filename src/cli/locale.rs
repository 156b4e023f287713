//! `--locale`: the user's locale for every command, as LibreOffice picks its own (LC_ALL, then
//! LC_NUMERIC, then LANG; C, POSIX or nothing set is en-US). The choice is made once when the
//! command line is read and handed to every document opened (its `Settings`); `ncsheet info`
//! says which is in force and where it came from.

use std::sync::OnceLock;

use ncsheet::eval::locale::FromEnvironment;
use ncsheet::eval::Locale;

/// The locale chosen for this run, and where it came from.
#[derive(Clone, Debug)]
pub struct InForce {
    pub locale: Locale,
    /// `--locale`, or the environment variable and its value.
    pub source: String,
}

static IN_FORCE: OnceLock<InForce> = OnceLock::new();

/// `--locale`'s value: a tag ncsheet has data for.
pub fn parse_locale(text: &str) -> Result<Locale, String> {
    Locale::from_tag(text).ok_or_else(|| {
        let known: Vec<String> = Locale::all().map(|l| l.tag.to_string()).collect();
        format!("no locale '{text}' (ncsheet knows {})", known.join(", "))
    })
}

/// Decides the run's locale: `--locale`, else the environment's.
pub fn apply(option: Option<Locale>) {
    let in_force = match option {
        Some(locale) => InForce { locale, source: "--locale".into() },
        None => from_environment(Locale::from_environment(|name| std::env::var(name).ok())),
    };
    let _ = IN_FORCE.set(in_force);
}

fn from_environment(found: FromEnvironment) -> InForce {
    let source = match (&found.variable, found.unknown) {
        (Some((name, value)), false) => format!("{name}={value}"),
        (Some((name, value)), true) => {
            format!("{name}={value}, a locale ncsheet has no data for, so en-US; choose one with --locale")
        }
        (None, _) => "no LC_ALL, LC_NUMERIC or LANG names one".into(),
    };
    InForce { locale: found.locale, source }
}

/// The run's locale (en-US before [`apply`], as in the library's tests).
pub fn in_force() -> InForce {
    IN_FORCE.get().cloned().unwrap_or(InForce { locale: Locale::EN_US, source: "the default".into() })
}

/// The hint for a number option typed with the locale's decimal mark (`--tol 0,01`).
pub fn number_option_hint(value: &str) -> Option<String> {
    let meant = value.replace(',', ".");
    let is_decimal_comma = value.contains(',') && meant.parse::<f64>().is_ok();
    is_decimal_comma.then(|| format!("options take numbers with a decimal point, whatever the locale: {meant}"))
}

/// `run --arg NAME=VALUE`s with their values read as typed in the workbook's locale
/// (`r=0,8` in et-EE is the number 0.8); a number of another locale is refused.
pub fn typed_args(
    wb: &ncsheet::workbook::Workbook,
    args: &[(String, String)],
) -> super::report::Result<Vec<(String, String)>> {
    let typed = |(name, value): &(String, String)| match wb.typed_input(value) {
        Ok(value) => Ok((name.clone(), value.into_owned())),
        Err(why) => Err(super::report::Error::Usage(format!("--arg {name}: {why}"))),
    };
    args.iter().map(typed).collect()
}

/// What a csv read with a detected `,` was taken for in a decimal-comma locale, whose Excel
/// would expect `;` (the io layer says it of a `;` csv itself).
pub fn csv_reading(doc: &ncsheet::document::Document, given: Option<u8>) -> Option<String> {
    let ncsheet::io::Origin::Csv(original) = doc.origin() else { return None };
    let locale = doc.settings().locale;
    match (given, original.delimiter()) {
        (None, b',') if !locale.is_canonical() => Some(format!(
            "read as a ,-separated csv with decimal points, not as {locale}'s ;-separated csv (--delimiter ';' reads it so)"
        )),
        _ => None,
    }
}

/// Why cells are `#VALUE!` when what they read is text that is a number in another locale
/// (`0,8` under en-US, `0.8` under et-EE): one line per such cell, naming the input cell and
/// the spelling meant.
pub fn foreign_numbers(wb: &ncsheet::workbook::Workbook) -> Vec<String> {
    use ncsheet::eval::{Value, XlError};
    let locale = wb.settings().locale;
    let mut out = Vec::new();
    for (sheet, _) in wb.sheet_names().iter().enumerate() {
        let sheet = sheet as ncsheet::formula::ast::SheetId;
        for (pos, value) in wb.values(sheet) {
            let Value::Text(text) = &value else { continue };
            if wb.is_formula(sheet, pos) {
                continue;
            }
            let Some((other, meant)) = locale.number_elsewhere(text) else { continue };
            let failing: Vec<String> = wb
                .dependents(sheet, pos)
                .into_iter()
                .filter(|&(s, p)| matches!(wb.value(s, p), Value::Error(XlError::Value)))
                .map(|(s, p)| wb.cell_name(s, p))
                .collect();
            if failing.is_empty() {
                continue;
            }
            out.push(format!(
                "{} {} #VALUE!: {} holds the text '{text}', a number in {other} but only text in {locale}, the locale \
                 in force; type {meant} there, or choose the locale with --locale",
                cells_named(&failing),
                if failing.len() == 1 { "is" } else { "are" },
                wb.cell_name(sheet, pos)
            ));
        }
    }
    out
}

/// `A1, A2` or, for many cells (a text read by a whole column), the first few and a count:
/// one line naming 200,000 cells was megabytes.
fn cells_named(cells: &[String]) -> String {
    const NAMED: usize = ncsheet::io::notes::LISTED;
    match cells.len() {
        n if n <= NAMED => cells.join(", "),
        n => format!("{} and {} more cells", cells[..NAMED].join(", "), n - NAMED),
    }
}

/// For a `#VALUE!` cell, the cells it reads that hold text that is a number in another
/// locale (`show`'s notes), each with the spelling meant.
pub fn foreign_inputs_of(
    wb: &ncsheet::workbook::Workbook,
    sheet: ncsheet::formula::ast::SheetId,
    pos: ncsheet::formula::address::Pos,
) -> Vec<String> {
    use ncsheet::eval::{Value, XlError};
    /// Ranges read are looked into up to this many cells.
    const MAX_CELLS: u64 = 10_000;
    if !matches!(wb.value(sheet, pos), Value::Error(XlError::Value)) {
        return Vec::new();
    }
    let locale = wb.settings().locale;
    let mut out = Vec::new();
    for (s, rect) in wb.precedents(sheet, pos) {
        if rect.rows() as u64 * rect.cols() as u64 > MAX_CELLS {
            continue;
        }
        for (p, value) in wb.values(s) {
            let Value::Text(text) = &value else { continue };
            if !rect.contains(p) || wb.is_formula(s, p) {
                continue;
            }
            if let Some((other, meant)) = locale.number_elsewhere(text) {
                out.push(format!(
                    "reads {}, the text '{text}', a number in {other} but only text in {locale}: type {meant} there, \
                     or choose the locale with --locale",
                    wb.cell_name(s, p)
                ));
            }
        }
    }
    out
}
