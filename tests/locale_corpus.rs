//! LibreOffice set to de-DE, fr-FR and et-EE as the oracle on the public corpus (issue 28):
//! the workbooks of `tests/data/excel-corpus/public` under [`MAX_BYTES`] are exported sheet
//! by sheet as `;` csv (the shown text of every cell) by LibreOffice, recalculating in the
//! locale, and by ncsheet opened in the locale, as `ncsheet export --locale` writes them.
//!
//! Where ncsheet and LibreOffice show a cell differently already in en-US, LibreOffice
//! differs from Excel there (functions, formats, volatile values: the conformance tests and
//! docs/excel-conformance.md deal with those), not the locale. Every other cell must show the
//! same text in each locale as LibreOffice shows it, but for the differences listed in
//! [`KNOWN`] and [`known_kind`], each with its reason.
//!
//! The values are compared too: LibreOffice recalculates each workbook in the locale and
//! saves it as xlsx, whose cached formula results must be ncsheet's computed values under
//! that locale, but for the cells of [`KNOWN_VALUES`], each with its reason.
//!
//! The figures (session 15, LibreOffice 7.4, 72,462 shown cells and 2,079 formula values
//! that agree in en-US): shown text differs in 171 cells in de-DE, 169 in fr-FR and 31 in
//! et-EE, every one of [`KNOWN`] or of [`known_kind`]'s kinds; values differ in 24 cells in
//! de-DE and fr-FR (TEXT with English date letters, Excel's reading) and none in et-EE.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use ncsheet::document::{Document, OpenOptions};
use ncsheet::eval::{Locale, Settings, Value};
use ncsheet::io::{Content, Export, ExportOptions};

/// The workbooks compared: every one of the public corpus smaller than this, so that the
/// test stays within a few minutes with four LibreOffice passes.
const MAX_BYTES: u64 = 200 * 1024;

/// The locales compared with LibreOffice, after en-US (the baseline).
const LOCALES: [&str; 3] = ["de-DE", "fr-FR", "et-EE"];

/// Cells where ncsheet in a locale shows other text than LibreOffice while both agree in
/// en-US, and why (`file!sheet!cell`, a prefix of it).
const KNOWN: &[(&str, &str)] = &[
    (
        "poi__test-data_spreadsheet_50755_workday_formula_example.xlsx!Sheet1!",
        "Excel's built-in format 15 (d-mmm-yy): LibreOffice shows its locale's medium date (de-DE `01. Feb 11`)",
    ),
    ("xlcalculator__tests_resources_DAY.xlsx!Sheet1!A1", "built-in format 15, as above"),
];

/// Formula cells whose value ncsheet in a locale computes otherwise than LibreOffice while
/// both agree in en-US, and why (`file!sheet!cell`, a prefix of it). None now: the values
/// that differ are TEXT results of [`known_kind`]'s kinds (AM/PM designators, English date
/// letters), counted by reason in the test's output.
const KNOWN_VALUES: &[(&str, &str)] = &[];

/// Differences of LibreOffice's from Excel's that show in any cell of their kind: why, when
/// ncsheet's text `ours` and LibreOffice's `theirs` in `locale` are one of them.
fn known_kind(locale: &str, ours: &str, theirs: &str) -> Option<&'static str> {
    // LibreOffice shows Excel's built-in 0% and 0.00% (9, 10) in its locale's percent format;
    // Excel keeps the code's `25%`.
    if [" %", "\u{a0}%"].iter().any(|spaced| ours.replace('%', spaced) == theirs) {
        return Some("built-in percent format");
    }
    // A `* ` fill repeats to the column's width in LibreOffice, measured in the locale's font.
    if ours.ends_with(' ') && ours.trim_end() == theirs.trim_end() {
        return Some("fill to the column's width");
    }
    // LibreOffice shows AM/PM as its locale's designators (de-DE vorm./nachm., et-EE e.l/p.l).
    let designators = match locale {
        "de-DE" => Some(("vorm.", "nachm.")),
        "et-EE" => Some(("e.l", "p.l")),
        _ => None,
    };
    let ours = &designators.map_or(ours.to_string(), |(am, pm)| ours.replace("AM", am).replace("PM", pm));
    if ours == theirs {
        return Some("AM/PM designators");
    }
    // Excel reads TEXT's code with the date letters of the locale and shows any other letter
    // as it is: in de-DE and fr-FR, whose day and year letters are T/J and j/a, an en-US
    // workbook's `dd-mm-yyyy` shows `dd-03-yyyy` (see Locale::canonical_date_letters for the
    // source). LibreOffice guesses such a code is an en-US one and shows the day and year.
    let english_letters = ["de-DE", "fr-FR"].contains(&locale) && ours.contains(['d', 'D', 'y', 'Y']);
    (english_letters && letters_stand_for(ours, theirs)).then_some("English date letters in TEXT's code")
}

/// Whether `theirs` is `ours` with each run of the letters `d` and `y` (either case) in
/// `ours` standing for a run of letters or digits (a day, a year, a day's name).
fn letters_stand_for(ours: &str, theirs: &str) -> bool {
    let is_letter = |c: char| matches!(c, 'd' | 'D' | 'y' | 'Y');
    match ours.chars().next() {
        None => theirs.is_empty(),
        Some(c) if is_letter(c) => {
            let rest = ours.trim_start_matches(is_letter);
            let run: Vec<(usize, char)> = theirs.char_indices().take_while(|(_, c)| c.is_alphanumeric()).collect();
            run.iter().any(|&(i, c)| letters_stand_for(rest, &theirs[i + c.len_utf8()..]))
        }
        Some(c) => theirs.starts_with(c) && letters_stand_for(&ours[c.len_utf8()..], &theirs[c.len_utf8()..]),
    }
}

/// The corpus workbooks compared, by a name unique in one folder (`corpus_file`).
fn chosen_workbooks(root: &Path) -> Vec<(String, PathBuf)> {
    let mut found = Vec::new();
    let mut folders = vec![root.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
                continue;
            }
            let is_workbook = path.extension().is_some_and(|e| e == "xlsx" || e == "xlsm");
            if is_workbook && std::fs::metadata(&path).unwrap().len() < MAX_BYTES {
                let relative = path.strip_prefix(root).unwrap().to_string_lossy().replace('/', "__");
                found.push((relative, path));
            }
        }
    }
    found.sort();
    found
}

/// The filter options of LibreOffice's csv export: `separator`, `"` quotes, UTF-8, the shown
/// text of the cells (not their full values), every sheet to a file of its own.
fn csv_filter(separator: u8) -> String {
    format!("csv:Text - txt - csv (StarCalc):{separator},34,76,1,,0,false,true,true,false,false,-1")
}

/// LibreOffice's csv export of every sheet of `inputs` into `out`, in batches (one process
/// each), and once more for the workbooks a batch left without a csv (LibreOffice sometimes
/// dies under load); a process is stopped after ten minutes.
fn libreoffice_csv(soffice: &Path, profile: &str, inputs: &[PathBuf], out: &Path, separator: u8) {
    let run = |batch: &[PathBuf]| {
        let mut child = Command::new(soffice)
            .arg(profile)
            .args(["--headless", "--norestore", "--convert-to", &csv_filter(separator), "--outdir"])
            .arg(out)
            .args(batch)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start soffice");
        let start = Instant::now();
        while child.try_wait().expect("wait for soffice").is_none() {
            if start.elapsed() > Duration::from_secs(600) {
                let _ = child.kill();
                let _ = child.wait();
                return;
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    };
    inputs.chunks(40).for_each(run);
    let written: Vec<String> = std::fs::read_dir(out)
        .map(|entries| entries.map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect())
        .unwrap_or_default();
    let missing: Vec<PathBuf> = inputs
        .iter()
        .filter(|p| {
            let stem = format!("{}-", p.file_stem().unwrap().to_string_lossy());
            !written.iter().any(|w| w.starts_with(&stem))
        })
        .cloned()
        .collect();
    missing.chunks(10).for_each(run);
}

/// The separator of the locale's csv: `;` where the decimal mark is a comma.
fn separator(locale: &str) -> u8 {
    if locale == "en-US" {
        b','
    } else {
        b';'
    }
}

/// A csv text as rows of fields.
fn grid(text: &str, separator: u8) -> Vec<Vec<String>> {
    let mut reader =
        csv::ReaderBuilder::new().has_headers(false).flexible(true).delimiter(separator).from_reader(text.as_bytes());
    reader.records().map(|r| r.map(|r| r.iter().map(str::to_string).collect()).unwrap_or_default()).collect()
}

/// `file` as ncsheet opens it in `locale` (computing every formula there).
fn open_in(file: &Path, locale: &str) -> Option<Document> {
    let mut settings = Settings::default();
    settings.locale = Locale::from_tag(locale).unwrap();
    let options = OpenOptions { settings: Some(settings), ..OpenOptions::named(file) };
    Document::open_file(file, &options).ok()
}

/// Each sheet of `file` as ncsheet opened in `locale` exports it: (sheet name, csv text).
fn ncsheet_sheets(file: &Path, locale: &str) -> Vec<(String, String)> {
    let Some(doc) = open_in(file, locale) else { return Vec::new() };
    let wb = doc.workbook();
    let export = |(sheet, name): (usize, String)| {
        let what = Export { sheet: sheet as _, range: None, content: Content::Values };
        let options = ExportOptions { delimiter: Some(separator(locale)), layout: doc.layout(), raw: false };
        let encoded = ncsheet::io::encode_export_with(wb, Path::new("out.csv"), &what, &options).ok()?;
        Some((name, String::from_utf8(encoded.into_bytes()).unwrap()))
    };
    wb.sheet_names().into_iter().enumerate().filter_map(export).collect()
}

/// The shown text of every cell, by `file!sheet!cell`, as ncsheet and as LibreOffice write
/// it in one locale; a sheet LibreOffice wrote no csv for is left out.
type Shown = BTreeMap<String, (String, String)>;

fn shown_in(workbooks: &[(String, PathBuf)], lo_out: &Path, locale: &str) -> Shown {
    let mut shown = Shown::new();
    for (name, path) in workbooks {
        let stem = Path::new(name).file_stem().unwrap().to_string_lossy().into_owned();
        for (sheet, ours) in ncsheet_sheets(path, locale) {
            let Ok(theirs) = std::fs::read_to_string(lo_out.join(format!("{stem}-{sheet}.csv"))) else { continue };
            let (ours, theirs) = (grid(&ours, separator(locale)), grid(&theirs, separator(locale)));
            let rows = ours.len().max(theirs.len());
            for row in 0..rows {
                let field =
                    |g: &Vec<Vec<String>>, col: usize| g.get(row).and_then(|r| r.get(col)).cloned().unwrap_or_default();
                let cols = ours.get(row).map_or(0, Vec::len).max(theirs.get(row).map_or(0, Vec::len));
                for col in 0..cols {
                    let mine = field(&ours, col);
                    // ncsheet guards text a spreadsheet would read as something else with `'`.
                    let mine = mine.strip_prefix('\'').map_or(mine.clone(), str::to_string);
                    let cell = ncsheet::formula::address::Pos::new(row as u32, col as u32);
                    shown.insert(format!("{name}!{sheet}!{cell}"), (mine, field(&theirs, col)));
                }
            }
        }
    }
    shown
}

/// What `read(workbooks, out, locale)` finds in en-US and in each of [`LOCALES`] after
/// LibreOffice set to that locale (recalculating every formula on load) ran
/// `convert(soffice, profile, copies, out)` on copies of the chosen workbooks; `None`
/// without LibreOffice or the corpus (failing on CI).
fn per_locale<T>(
    convert: impl Fn(&Path, &str, &[PathBuf], &Path, &str),
    read: impl Fn(&[(String, PathBuf)], &Path, &str) -> T,
) -> Option<BTreeMap<&'static str, T>> {
    let soffice = common::soffice()?;
    let root = common::corpus::public_path();
    if !root.is_dir() {
        assert!(std::env::var_os("CI").is_none(), "public Excel corpus not found at {}", root.display());
        return None;
    }
    let workbooks = chosen_workbooks(&root);
    assert!(workbooks.len() > 100, "{} workbooks under {MAX_BYTES} bytes", workbooks.len());
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let inputs = d.join("in");
    std::fs::create_dir_all(&inputs).unwrap();
    let copies: Vec<PathBuf> = workbooks
        .iter()
        .map(|(name, path)| {
            let copy = inputs.join(name);
            std::fs::copy(path, &copy).unwrap();
            copy
        })
        .collect();
    let mut by_locale = BTreeMap::new();
    for locale in std::iter::once("en-US").chain(LOCALES) {
        let out = d.join(format!("lo-{locale}"));
        let profile = common::locale::libreoffice_profile(&d.join(format!("profile-{locale}")), locale);
        convert(&soffice, &profile, &copies, &out, locale);
        by_locale.insert(locale, read(&workbooks, &out, locale));
    }
    Some(by_locale)
}

#[test]
fn libreoffice_in_the_locale_is_the_oracle_on_the_public_corpus() {
    let csv = |soffice: &Path, profile: &str, copies: &[PathBuf], out: &Path, locale: &str| {
        libreoffice_csv(soffice, profile, copies, out, separator(locale))
    };
    let Some(by_locale) = per_locale(csv, shown_in) else { return };
    let baseline = &by_locale["en-US"];
    let agree_in_en_us: Vec<&String> = baseline.iter().filter(|(_, (a, b))| a == b).map(|(k, _)| k).collect();
    assert!(agree_in_en_us.len() > 10_000, "{} cells agree in en-US", agree_in_en_us.len());
    let mut found = Vec::new();
    for locale in LOCALES {
        let shown = &by_locale[locale];
        let mut disagree = 0;
        for cell in &agree_in_en_us {
            let Some((ours, theirs)) = shown.get(*cell) else { continue };
            if ours != theirs {
                disagree += 1;
                let listed = KNOWN.iter().any(|(prefix, _)| cell.starts_with(prefix));
                if !listed && known_kind(locale, ours, theirs).is_none() {
                    found.push(format!("{locale}: {cell}: ncsheet {ours:?}, LibreOffice {theirs:?}"));
                }
            }
        }
        println!("{locale}: {disagree} of the {} cells agreeing in en-US differ", agree_in_en_us.len());
    }
    assert!(found.is_empty(), "{} cells:\n{}", found.len(), found.join("\n"));
}

/// Every formula cell's value, by `file!sheet!cell`, as ncsheet computes it opened in
/// `locale` and as LibreOffice recalculated it there (the results it cached in the xlsx it
/// saved in `lo_out`); a workbook LibreOffice saved no xlsx of is left out.
type Computed = BTreeMap<String, (Value, Value)>;

fn computed_in(workbooks: &[(String, PathBuf)], lo_out: &Path, locale: &str) -> Computed {
    let mut computed = Computed::new();
    for (name, path) in workbooks {
        let saved = lo_out.join(name).with_extension("xlsx");
        let Ok(mut theirs) = calamine::open_workbook::<calamine::Xlsx<_>, _>(&saved) else { continue };
        let Some(doc) = open_in(path, locale) else { continue };
        let wb = doc.workbook();
        for (sheet, sheet_name) in wb.sheet_names().into_iter().enumerate() {
            let Some(recalculated) = common::excel_oracle::read_sheet(&mut theirs, &sheet_name) else { continue };
            for (&(row, col), value) in &recalculated.values {
                if !recalculated.formulas.contains_key(&(row, col)) {
                    continue;
                }
                let pos = ncsheet::formula::address::Pos::new(row, col);
                let ours = wb.value(sheet as _, pos);
                computed.insert(format!("{name}!{sheet_name}!{pos}"), (ours, value.clone()));
            }
        }
    }
    computed
}

/// Whether ncsheet's value is LibreOffice's: numbers to 1e-9 relative (LibreOffice saves
/// 15 to 17 significant digits, and sums in its own order), an empty text and an empty
/// cell alike.
fn same_value(ours: &Value, theirs: &Value) -> bool {
    let empty = |v: &Value| matches!(v, Value::Blank) || matches!(v, Value::Text(t) if t.is_empty());
    match (ours, theirs) {
        (Value::Number(a), Value::Number(b)) => a == b || (a - b).abs() <= 1e-9 * a.abs().max(b.abs()),
        (Value::Array(a), theirs) => a.data.first().is_some_and(|first| same_value(first, theirs)),
        (a, b) if empty(a) && empty(b) => true,
        (a, b) => a == b,
    }
}

#[test]
fn libreoffice_in_the_locale_computes_the_corpus_values_ncsheet_computes() {
    // LibreOffice saves what it recalculated as xlsx: the formulas' cached results.
    let xlsx = |soffice: &Path, profile: &str, copies: &[PathBuf], out: &Path, _: &str| {
        common::libreoffice_convert(soffice, profile, copies, out)
    };
    let Some(by_locale) = per_locale(xlsx, computed_in) else { return };
    let baseline = &by_locale["en-US"];
    let agree_in_en_us: Vec<&String> =
        baseline.iter().filter(|(_, (ours, theirs))| same_value(ours, theirs)).map(|(k, _)| k).collect();
    assert!(agree_in_en_us.len() > 1_000, "{} formula cells agree in en-US", agree_in_en_us.len());
    println!("{} of {} formula cells agree in en-US", agree_in_en_us.len(), baseline.len());
    let mut found = Vec::new();
    for locale in LOCALES {
        let computed = &by_locale[locale];
        let mut excused: BTreeMap<&str, usize> = BTreeMap::new();
        for cell in &agree_in_en_us {
            let Some((ours, theirs)) = computed.get(*cell) else { continue };
            if same_value(ours, theirs) {
                continue;
            }
            // A text result (TEXT's) differs as the shown text does, for the same reasons.
            let text_kind = match (ours, theirs) {
                (Value::Text(a), Value::Text(b)) => known_kind(locale, a, b),
                _ => None,
            };
            let listed = KNOWN_VALUES.iter().find(|(prefix, _)| cell.starts_with(prefix)).map(|(_, why)| *why);
            match text_kind.or(listed) {
                Some(why) => *excused.entry(why).or_default() += 1,
                None => found.push(format!("{locale}: {cell}: ncsheet {ours:?}, LibreOffice {theirs:?}")),
            }
        }
        println!("{locale}: formula cells agreeing in en-US that compute otherwise, by reason: {excused:?}");
    }
    assert!(found.is_empty(), "{} cells:\n{}", found.len(), found.join("\n"));
}

#[test]
fn english_date_letters_stand_for_the_day_and_year_libreoffice_shows() {
    assert!(letters_stand_for("yyyy-01-dd 00:00:00,4", "1904-01-02 00:00:00,4"));
    assert!(letters_stand_for("d days 14", "11 days 14"));
    assert!(letters_stand_for("dddd-Oktober-yyyy", "Samstag-Oktober-1952"));
    assert!(!letters_stand_for("dd-01-yyyy", "01-02-2025"));
    assert!(!letters_stand_for("dd", "12 "));
}
