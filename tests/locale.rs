//! The user's locale (issue 28): typed values and formulas, shown values and the conversions
//! between text and numbers as that locale's Excel does them. The oracles: the values Excel
//! cached in the shipped chamfer workbook, LibreOffice set to de-DE, fr-FR and et-EE (its
//! shown text, exported as csv), and Excel's documented rules where LibreOffice differs.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::cli::{ncsheet, Invocation, Run};
use common::locale::libreoffice_profile;

const CHAMFER: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/sheets/chamfer.xlsx");
const CHAMFER_BAS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/sheets/chamfer.bas");

fn in_dir(dir: &Path, args: &[&str]) -> Run {
    Invocation { dir: Some(dir), ..Invocation::default() }.run(args)
}

fn ok(run: Run) -> Run {
    assert_eq!(run.code, 0, "stdout: {}\nstderr: {}", run.stdout, run.stderr);
    run
}

/// The acceptance of issue 28: the chamfer workbook driven entirely in et-EE. Excel cached
/// XA = 44.262742 (Outer!G6, format 0.000000) for r = 0.8 and D = 40; an Estonian Excel
/// shows it as 44,262742.
#[test]
fn the_chamfer_workbook_driven_in_et_ee() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The nose radius with a decimal comma, and D as a formula typed with `;` and `,`.
    let set = ok(in_dir(
        d,
        &["set", CHAMFER, "--locale", "et-EE", "Outer!r_=0,8", "Outer!D==ROUND(39,6;0)", "-o", "m1.xlsx"],
    ));
    assert!(set.stderr.contains("Outer!B9 = 0,8"), "{}", set.stderr);
    assert!(!set.stderr.contains("warning"), "{}", set.stderr);
    let shown = ok(in_dir(d, &["eval", "m1.xlsx", "--locale", "et-EE", "--sheet", "Outer", "G6", "G7", "B9"]));
    assert_eq!(
        shown.stdout.split_whitespace().collect::<Vec<_>>(),
        ["G6", "44,262742", "G7", "-4,600000", "B9", "0,8"]
    );
    // The formula is shown as the Estonian user typed it, and the file keeps Excel's syntax.
    let local = ok(in_dir(d, &["eval", "m1.xlsx", "--locale", "et-EE", "--sheet", "Outer", "--formulas", "B6"]));
    assert!(local.stdout.contains("=ROUND(39,6;0)"), "{}", local.stdout);
    let canonical = ok(in_dir(d, &["eval", "m1.xlsx", "--locale", "en-US", "--sheet", "Outer", "--formulas", "B6"]));
    assert!(canonical.stdout.contains("=ROUND(39.6,0)"), "{}", canonical.stdout);
    let json = ok(in_dir(d, &["eval", "m1.xlsx", "--locale", "et-EE", "--format", "json", "Outer!G6", "Outer!B9"]));
    assert!(json.stdout.contains("\"Outer!G6\": 44.2627416") && json.stdout.contains(": 0.8}"), "{}", json.stdout);
    // The macro gives the NC program the en-US run gives on the shipped workbook.
    let run = |workbook: &str, locale: &str, out: &str| {
        ok(in_dir(
            d,
            &["run", workbook, CHAMFER_BAS, "--sheet", "Outer", "--dialect", "linuxcnc", "--locale", locale, "-o", out],
        ))
    };
    run("m1.xlsx", "et-EE", "et.ngc");
    run(CHAMFER, "en-US", "en.ngc");
    let (et, en) =
        (std::fs::read_to_string(d.join("et.ngc")).unwrap(), std::fs::read_to_string(d.join("en.ngc")).unwrap());
    assert_eq!(et, en);
    assert!(en.contains("X44.263"), "{en}");
}

/// `0.8` in et-EE and `0,8` in en-US are numbers only in the other locale: refused with the
/// spelling meant, nothing written (the old behaviour stored text and broke XA, ZA, XB).
#[test]
fn a_number_of_another_locale_is_refused_with_the_spelling_meant() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let et = in_dir(d, &["set", CHAMFER, "--locale", "et-EE", "Outer!r_=0.8", "-o", "m.xlsx"]);
    assert_eq!(et.code, 1, "{}", et.stderr);
    assert!(et.stderr.contains("Outer!B9") && et.stderr.contains("type 0,8"), "{}", et.stderr);
    let en = in_dir(d, &["set", CHAMFER, "--locale", "en-US", "Outer!r_=0,8", "-o", "m.xlsx"]);
    assert_eq!(en.code, 1, "{}", en.stderr);
    assert!(en.stderr.contains("type 0.8"), "{}", en.stderr);
    assert!(!d.join("m.xlsx").exists());
    // Forced text is still text.
    ok(in_dir(d, &["set", CHAMFER, "--locale", "et-EE", "Outer!r_='0.8", "-o", "t.xlsx"]));
    // A date typed with a separator the locale does not read (LibreOffice in de-DE keeps
    // `12/03/2025` as text): refused with the locale's own spelling.
    let de = in_dir(d, &["set", CHAMFER, "--locale", "de-DE", "Outer!r_=12/03/2025", "-o", "m.xlsx"]);
    assert_eq!(de.code, 1, "{}", de.stderr);
    assert!(de.stderr.contains("type 12.03.2025"), "{}", de.stderr);
    assert!(!d.join("m.xlsx").exists());
}

/// A cell that is #VALUE! because it reads text of another locale says so, naming the input.
#[test]
fn value_errors_from_text_of_another_locale_name_the_input_cell() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(in_dir(d, &["set", CHAMFER, "--locale", "en-US", "Outer!r_='0,8", "-o", "t.xlsx"]));
    let shown = ok(in_dir(d, &["eval", "t.xlsx", "--locale", "en-US", "Outer!G6"]));
    assert!(shown.stdout.contains("#VALUE!"), "{}", shown.stdout);
    assert!(
        shown.stderr.contains("Outer!B9 holds the text '0,8'") && shown.stderr.contains("type 0.8"),
        "{}",
        shown.stderr
    );
    let show = ok(in_dir(d, &["show", "t.xlsx", "--locale", "en-US", "Outer!C17"]));
    assert!(show.stdout.contains("reads Outer!B9, the text '0,8'"), "{}", show.stdout);
}

/// Without --locale the environment decides, as LibreOffice reads it: LC_ALL, then LC_NUMERIC,
/// then LANG; C and POSIX are en-US.
#[test]
fn the_locale_comes_from_the_environment_as_libreoffice_reads_it() {
    let info = |vars: &[(&str, &str)]| {
        let mut command = Command::new(env!("CARGO_BIN_EXE_ncsheet"));
        command.args(["info", CHAMFER]).env_remove("LC_ALL").env_remove("LC_NUMERIC").env_remove("LANG");
        for (k, v) in vars {
            command.env(k, v);
        }
        let out = command.output().unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        stdout.lines().find(|l| l.starts_with("locale:")).unwrap_or_default().to_string()
    };
    assert!(info(&[("LANG", "de_DE.UTF-8")]).starts_with("locale: de-DE"));
    assert!(info(&[("LANG", "de_DE.UTF-8"), ("LC_NUMERIC", "et_EE.UTF-8")]).starts_with("locale: et-EE"));
    assert!(info(&[("LANG", "de_DE.UTF-8"), ("LC_ALL", "C")]).starts_with("locale: en-US"));
    assert!(info(&[]).starts_with("locale: en-US"));
    let chosen = ok(ncsheet(&["info", CHAMFER, "--locale", "hu-HU"]));
    assert!(chosen.stdout.contains("locale: hu-HU"), "{}", chosen.stdout);
    let unknown = ncsheet(&["info", CHAMFER, "--locale", "xx-YY"]);
    assert_eq!(unknown.code, 2);
    assert!(unknown.stderr.contains("et-EE"), "{}", unknown.stderr);
}

/// A day and month typed without a year fall in the year of the workbook's clock when its
/// settings fix one (NOW's clock), not the system clock's: with the clock at 2031-06-01
/// (serial 48000), de-DE `12.03.` is 2031-03-12 (serial 47919, days since 1899-12-30), in a
/// formula, a csv field read in the locale and a typed value.
#[test]
fn a_date_without_a_year_takes_the_year_of_the_settings_clock() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("clock.csv");
    std::fs::write(&path, "\"=DATEVALUE(\"\"12.03.\"\")\";12.03.;\"=YEAR(\"\"12. März\"\")\"\n").unwrap();
    let mut settings = ncsheet::eval::Settings::default();
    settings.clock = Some(48000.5);
    settings.locale = ncsheet::eval::Locale::from_tag("de-DE").unwrap();
    let options =
        ncsheet::document::OpenOptions { settings: Some(settings), ..ncsheet::document::OpenOptions::named(&path) };
    let doc = ncsheet::document::Document::open_file(&path, &options).unwrap();
    let value = |doc: &ncsheet::document::Document, col: u32| {
        doc.workbook().value(0, ncsheet::formula::address::Pos::new(0, col))
    };
    use ncsheet::eval::Value;
    assert_eq!(
        [value(&doc, 0), value(&doc, 1), value(&doc, 2)],
        [Value::Number(47919.0), Value::Number(47919.0), Value::Number(2031.0)]
    );
    let typed = doc.workbook().typed_input("12.3.").unwrap().into_owned();
    assert_eq!(typed, "47919", "the typed value as the file stores it");
}

/// The probes: coercions, TEXT's codes, FIXED, dates, joining a number, in one row.
const PROBES: &[&str] = &[
    r#"=VALUE("0,8")"#,
    r#"="1,5"*2"#,
    r#"=--"1 234,5""#,
    r#"=TEXT(1234.5,"00,00")"#,
    r##"=TEXT(1234.5,"#.##0,00")"##,
    r#"=FIXED(1234.567,1)"#,
    r#"=VALUE("12.03.2025")"#,
    r#"=1.5&"""#,
    // Two numbers joined: each shown as the locale shows it (ncsheet gave `1.52.25`).
    r#"=1.5&2.25"#,
    r#"=VALUE("0.8")"#,
    r#"=-"0,5""#,
    r#"="-0,0171"*1000"#,
    r#"=DATEVALUE("12.03.2025")"#,
    r#"="3"+"0,25""#,
    r#"=ROUND("2,345",2)"#,
    r#"=TEXT(0.256,"0,0%")"#,
    r#"=TEXT(-1234.5,"0,000")"#,
    r#"=TEXT(45728,"mmmm")"#,
    r#"=TEXT(45728,"d. mmmm yyyy")"#,
    r#"=TEXT(45728,"dddd")"#,
];

/// Probes whose text Excel's rule gives where LibreOffice guesses otherwise: Excel reads
/// TEXT's code with the date letters of the user's locale and shows any other letter as it
/// is (de-DE spells day and year `T` and `J`, fr-FR `j` and `a`: `d` and `y` are no date
/// letters there; the source is at `Locale::canonical_date_letters`). LibreOffice takes such
/// a code for an en-US one. (locale, probe, what that Excel shows.)
const LITERAL_LETTERS: &[(&str, &str, &str)] = &[
    ("de-DE", r#"=TEXT(45728,"d. mmmm yyyy")"#, "d. März yyyy"),
    ("fr-FR", r#"=TEXT(45728,"d. mmmm yyyy")"#, "d. mars yyyy"),
    ("de-DE", r#"=TEXT(45728,"dddd")"#, "dddd"),
    ("fr-FR", r#"=TEXT(45728,"dddd")"#, "dddd"),
];

/// A csv row of the probes, quoted for a `,`-separated file.
fn probe_csv() -> String {
    let fields: Vec<String> = PROBES.iter().map(|p| format!("\"{}\"", p.replace('"', "\"\""))).collect();
    format!("{}\n", fields.join(","))
}

/// The first row of a `;`-separated csv, fields unquoted.
fn semicolon_fields(text: &str) -> Vec<String> {
    let mut reader = csv::ReaderBuilder::new().has_headers(false).delimiter(b';').from_reader(text.as_bytes());
    let record = reader.records().next().expect("a row").expect("a csv row");
    record.iter().map(str::to_string).collect()
}

/// LibreOffice set to `locale` (its profile in `d`) converts `input` to `format` in `out`,
/// with `options` (an import filter) before.
fn libreoffice_converts(
    soffice: &impl AsRef<std::ffi::OsStr>,
    d: &Path,
    locale: &str,
    options: &[&str],
    format: &str,
    out: &Path,
    input: &Path,
) {
    let profile = libreoffice_profile(&d.join(format!("profile-{locale}")), locale);
    let status = Command::new(soffice)
        .arg(&profile)
        .args(["--headless", "--norestore"])
        .args(options)
        .args(["--convert-to", format, "--outdir"])
        .arg(out)
        .arg(input)
        .output()
        .expect("soffice runs");
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
}

/// The first row of `STEM.xlsx` in `dir` as LibreOffice set to `locale` exports it (shown
/// text, `;` csv), and as `ncsheet export --locale` does: (ours, theirs).
fn ours_and_libreoffice(
    soffice: &impl AsRef<std::ffi::OsStr>,
    d: &Path,
    stem: &str,
    locale: &str,
) -> (Vec<String>, Vec<String>) {
    let out = d.join(format!("lo-{locale}"));
    let csv = "csv:Text - txt - csv (StarCalc):59,34,76,1,,0,false,true,true";
    libreoffice_converts(soffice, d, locale, &[], csv, &out, &d.join(format!("{stem}.xlsx")));
    let theirs = semicolon_fields(&std::fs::read_to_string(out.join(format!("{stem}.csv"))).unwrap());
    let ours_file = format!("ours-{locale}.csv");
    ok(in_dir(d, &["export", &format!("{stem}.xlsx"), "--locale", locale, "-o", &ours_file]));
    let ours = semicolon_fields(&std::fs::read_to_string(d.join(&ours_file)).unwrap());
    (ours, theirs)
}

/// LibreOffice's name for #VALUE! in a csv it writes from an invalid argument.
fn as_excel_error(text: &str) -> &str {
    match text {
        "Err:502" => "#VALUE!",
        other => other,
    }
}

/// LibreOffice set to de-DE, fr-FR and et-EE computes the probes and exports the shown text
/// as a `;` csv; `ncsheet export --locale` of the same workbook writes the same fields.
#[test]
fn libreoffice_in_the_locale_is_the_oracle_for_coercions_text_codes_and_dates() {
    let Some(soffice) = common::soffice() else { return };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("probe.csv"), probe_csv()).unwrap();
    ok(in_dir(d, &["set", "probe.csv", "--locale", "en-US", "A2=1", "-o", "probe.xlsx"]));
    for locale in ["de-DE", "fr-FR", "et-EE"] {
        let (ours, theirs) = ours_and_libreoffice(&soffice, d, "probe", locale);
        for (i, probe) in PROBES.iter().enumerate() {
            // ncsheet's export guards text a spreadsheet could run (`-1234,500`) with a `'`.
            let ours = ours[i].strip_prefix('\'').unwrap_or(&ours[i]);
            let excel = LITERAL_LETTERS.iter().find(|(l, p, _)| *l == locale && p == probe).map(|(_, _, shows)| *shows);
            assert_eq!(ours, excel.unwrap_or(as_excel_error(&theirs[i])), "{locale}: {probe}");
        }
    }
}

/// NUMBERVALUE's separators default to the locale's in Excel ("If the Decimal_separator and
/// Group_separator arguments are not specified, separators from the current locale are
/// used", Excel's NUMBERVALUE page); LibreOffice uses `.` and `,` there, so it is no oracle.
#[test]
fn numbervalue_defaults_to_the_locale_separators() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("n.csv"), "\"=NUMBERVALUE(\"\"1.234,5\"\")\",\"=NUMBERVALUE(\"\"1,234.5\"\")\"\n").unwrap();
    let de = ok(in_dir(d, &["eval", "n.csv", "--delimiter", ",", "--locale", "de-DE", "--format", "json"]));
    assert_eq!(de.stdout.trim(), r##"{"Sheet1!A1": 1234.5, "Sheet1!B1": "#VALUE!"}"##);
    let en = ok(in_dir(d, &["eval", "n.csv", "--delimiter", ",", "--locale", "en-US", "--format", "json"]));
    assert_eq!(en.stdout.trim(), r##"{"Sheet1!A1": "#VALUE!", "Sheet1!B1": 1234.5}"##);
}

/// A workbook whose formulas turn comma-decimal text into numbers (as a French Excel's
/// engineering workbooks do with TEXTSPLIT(…)*1000 and VALUE) computes as in the comma
/// locale under --locale fr-FR, and as in en-US without it: LibreOffice in fr-FR gives
/// -17,1 and -0,0171 for these (see the probes above), en-US Excel #VALUE!.
#[test]
fn comma_decimal_text_computes_as_in_the_comma_locale() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let csv = "\"'-0,0171\",\"=A1*1000\",\"=VALUE(A1)\",\"=SUM(--TEXTSPLIT(\"\"1,5 2,5\"\",\"\" \"\"))\"\n";
    std::fs::write(d.join("fr.csv"), csv).unwrap();
    ok(in_dir(d, &["set", "fr.csv", "--delimiter", ",", "--locale", "en-US", "E1=1", "-o", "fr.xlsx"]));
    let fr = ok(in_dir(d, &["eval", "fr.xlsx", "--locale", "fr-FR", "--format", "json", "A1:D1"]));
    assert_eq!(
        fr.stdout.trim(),
        r#"{"Sheet1!A1": "-0,0171", "Sheet1!B1": -17.1, "Sheet1!C1": -0.0171, "Sheet1!D1": 4}"#
    );
    let en = ok(in_dir(d, &["eval", "fr.xlsx", "--locale", "en-US", "--format", "json", "A1:D1"]));
    assert_eq!(
        en.stdout.trim(),
        r##"{"Sheet1!A1": "-0,0171", "Sheet1!B1": "#VALUE!", "Sheet1!C1": "#VALUE!", "Sheet1!D1": "#VALUE!"}"##
    );
    // Shown in the locale: a decimal comma and the no-break space French Excel groups with.
    let shown = ok(in_dir(d, &["eval", "fr.xlsx", "--locale", "fr-FR", "B1", "C1"]));
    assert!(shown.stdout.contains("-17,1") && shown.stdout.contains("-0,0171"), "{}", shown.stdout);
}

/// The repl reads and shows in the locale: `0,5` and `=ROUND(A1*3;1)` in de-DE.
#[test]
fn the_repl_reads_and_shows_in_the_locale() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("r.csv"), "1,2\n").unwrap();
    let run = Invocation { dir: Some(d), stdin: "A1=0,5\nB1==ROUND(A1*3,33;1)\n", ..Invocation::default() }.run(&[
        "repl",
        "r.csv",
        "--delimiter",
        ",",
        "--locale",
        "de-DE",
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(run.stdout.lines().collect::<Vec<_>>(), ["0,5", "1,7"], "{}", run.stderr);
}

/// A number option typed with a decimal comma gets the spelling it wants.
#[test]
fn a_number_option_with_a_decimal_comma_gets_a_hint() {
    let run = ncsheet(&["cam", "--tol", "0,01", "x.csv"]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("hint:") && run.stderr.contains("0.01"), "{}", run.stderr);
}

/// A `;` csv opened in de-DE reads as a German Excel opens it: `1.234,5` is 1234.5 and
/// `12.03.2025` the 12th of March (serial 45728, DATE(2025,3,12)); a field forced to text
/// with `'` stays text. Without the locale, the grouped number is text, as before.
#[test]
fn a_semicolon_csv_reads_in_the_locale() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("eu.csv"), "1,5;=A1*2\n\"1.234,5\";=SUM(A1:A2)\n12.03.2025;'1.234,5\n").unwrap();
    let de = ok(in_dir(d, &["eval", "eu.csv", "--locale", "de-DE", "--format", "json"]));
    assert_eq!(
        de.stdout.trim(),
        r#"{"Sheet1!A1": 1.5, "Sheet1!B1": 3, "Sheet1!A2": 1234.5, "Sheet1!B2": 1236, "Sheet1!A3": 45728, "Sheet1!B3": "1.234,5"}"#
    );
    assert!(de.stderr.contains(";-separated"), "{}", de.stderr);
    let en = ok(in_dir(d, &["eval", "eu.csv", "--locale", "en-US", "--format", "json", "A2"]));
    assert_eq!(en.stdout.trim(), r#"{"Sheet1!A2": "1.234,5"}"#);
}

/// `Range.FormulaLocal` is the formula "in the language of the user" (Excel's Range page):
/// in de-DE `;` between arguments and decimal commas, read and written; `.Formula` stays
/// the file's syntax. A constant typed through it is read in the locale too.
#[test]
fn formula_local_reads_and_writes_in_the_locale() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("t.csv"), "x\n").unwrap();
    ok(in_dir(d, &["set", "t.csv", "--locale", "en-US", "C1=1", "-o", "t.xlsx"]));
    let macro_text = "Sub Probe()\n    Range(\"B1\").FormulaLocal = \"2,5\"\n    \
                      Range(\"A1\").FormulaLocal = \"=ROUND(B1*0,5;3)+SUM(1;2)\"\n    MsgBox Range(\"A1\").Formula\n    \
                      MsgBox Range(\"A1\").FormulaLocal\n    MsgBox Range(\"A1\").Value * 4\n    \
                      MsgBox Range(\"B1\").FormulaLocal\nEnd Sub\n";
    std::fs::write(d.join("probe.bas"), macro_text).unwrap();
    let run = ok(in_dir(d, &["run", "t.xlsx", "probe.bas", "--sub", "Probe", "--locale", "de-DE"]));
    let said: Vec<&str> = run.stderr.lines().filter(|l| !l.starts_with("ncsheet:")).collect();
    // ROUND(2.5*0.5, 3) + 3 = 4.25; times 4 is 17.
    assert_eq!(said, ["=ROUND(B1*0.5,3)+SUM(1,2)", "=ROUND(B1*0,5;3)+SUM(1;2)", "17", "2,5"], "{}", run.stderr);
    // In en-US `2,5` is no number: refused with the spelling meant, naming the macro's line.
    let run = in_dir(d, &["run", "t.xlsx", "probe.bas", "--sub", "Probe", "--locale", "en-US"]);
    assert_ne!(run.code, 0);
    assert!(run.stderr.contains("probe.bas:2") && run.stderr.contains("type 2.5"), "{}", run.stderr);
}

/// A date typed in the locale is a date serial shown as the locale's short date: Excel
/// gives the cell its built-in date format (14), which each locale shows its own way.
/// 28 November 2026 is serial 46354 (days since 1899-12-30).
#[test]
fn a_date_typed_in_the_locale_shows_as_its_short_date() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("t.csv"), "x\n").unwrap();
    ok(in_dir(d, &["set", "t.csv", "--locale", "de-DE", "A1=28.11.2026", "B1==A1*1", "-o", "t.xlsx"]));
    let shown = |locale: &str| ok(in_dir(d, &["eval", "t.xlsx", "A1", "B1", "--locale", locale])).stdout;
    assert_eq!(shown("de-DE"), "A1  28.11.2026\nB1  46354\n");
    assert_eq!(shown("en-US"), "A1  11/28/2026\nB1  46354\n");
    assert_eq!(shown("hu-HU"), "A1  2026.11.28.\nB1  46354\n");
    // A number typed is no date: it keeps General.
    ok(in_dir(d, &["set", "t.xlsx", "--locale", "de-DE", "C1=28,5", "-o", "u.xlsx"]));
    assert_eq!(ok(in_dir(d, &["eval", "u.xlsx", "C1", "--locale", "de-DE"])).stdout, "28,5\n");
}

/// Date letters typed in a locale's format codes (de-DE `TT.MM.JJJJ`, fr-FR `JJ/MM/AAAA`),
/// the short month and day names (`mmm`, `ddd`) and DOLLAR's currency: LibreOffice set to
/// the locale is the oracle, on TEXT of 2025-03-12, of the first of every month and of seven
/// days in a row.
#[test]
fn libreoffice_in_the_locale_is_the_oracle_for_date_letters_and_short_names() {
    let Some(soffice) = common::soffice() else { return };
    let mut probes: Vec<(&str, String)> = vec![
        ("de-DE", r#"=TEXT(45728,"TT.MM.JJJJ")"#.into()),
        ("de-DE", r#"=TEXT(45728,"TTTT, T. MMMM JJ")"#.into()),
        ("fr-FR", r#"=TEXT(45728,"JJ/MM/AAAA")"#.into()),
        ("fr-FR", r#"=TEXT(45728,"jjjj j mmm aa")"#.into()),
    ];
    // The short day name in each locale's letters (de-DE `TTT`, fr-FR `jjj`).
    for (locale, short_day) in [("de-DE", "TTT"), ("fr-FR", "jjj"), ("et-EE", "ddd")] {
        probes.extend((1..=12).map(|m| (locale, format!(r#"=TEXT(DATE(2025,{m},1),"mmm")"#))));
        // 2025-06-01 is a Sunday.
        probes.extend((1..=7).map(|d| (locale, format!(r#"=TEXT(DATE(2025,6,{d}),"{short_day}")"#))));
        // The currency DOLLAR shows, and its sign.
        probes.push((locale, "=DOLLAR(1234.5)".into()));
        probes.push((locale, "=DOLLAR(-1234.5,1)".into()));
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let fields: Vec<String> = probes.iter().map(|(_, p)| format!("\"{}\"", p.replace('"', "\"\""))).collect();
    std::fs::write(d.join("names.csv"), format!("{}\n", fields.join(","))).unwrap();
    ok(in_dir(d, &["set", "names.csv", "--locale", "en-US", "A2=1", "-o", "names.xlsx"]));
    for locale in ["de-DE", "fr-FR", "et-EE"] {
        let (ours, theirs) = ours_and_libreoffice(&soffice, d, "names", locale);
        for (i, (probe_locale, probe)) in probes.iter().enumerate() {
            if *probe_locale == locale {
                // ncsheet's export guards text a spreadsheet would read as a date with a `'`.
                let ours = ours[i].strip_prefix('\'').unwrap_or(&ours[i]);
                assert_eq!(ours, theirs[i], "{locale}: {probe}");
            }
        }
    }
}

/// A csv export in a locale writes a date as that locale shows it (its short date, as `eval`
/// shows it), not in en-US form: LibreOffice set to the locale exports the same workbook's
/// shown text as the oracle. 28 November 2026 typed in de-DE is a date of the built-in format.
#[test]
fn a_date_exports_as_the_locale_shows_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("t.csv"), "x\n").unwrap();
    ok(in_dir(d, &["set", "t.csv", "--locale", "de-DE", "A1=28.11.2026", "B1=1234,5", "-o", "dates.xlsx"]));
    // As `eval` shows it (a_date_typed_in_the_locale_shows_as_its_short_date), not 11-28-26.
    ok(in_dir(d, &["export", "dates.xlsx", "--locale", "de-DE", "-o", "de.csv"]));
    assert_eq!(std::fs::read_to_string(d.join("de.csv")).unwrap(), "28.11.2026;1234,5\n");
    let Some(soffice) = common::soffice() else { return };
    for locale in ["de-DE", "fr-FR", "et-EE"] {
        let (ours, theirs) = ours_and_libreoffice(&soffice, d, "dates", locale);
        assert_eq!(ours, theirs, "{locale}");
    }
}

/// The kinds of values a csv carries, each in a number format whose shown text reads back as
/// the same value: booleans (constant and computed), grouped numbers, percents, a scientific
/// number, Excel's built-in date (14) and date and time (22), a time, plain numbers, text.
fn write_kinds(path: &Path) {
    use rust_xlsxwriter::{Format, Workbook};
    let mut book = Workbook::new();
    let sheet = book.add_worksheet();
    let code = |code: &str| Format::new().set_num_format(code);
    sheet.write_boolean(0, 0, true).unwrap();
    sheet.write_boolean(0, 1, false).unwrap();
    sheet.write_formula(0, 2, "=2>1").unwrap();
    sheet.write_formula(0, 3, "=2<1").unwrap();
    sheet.write_number_with_format(0, 4, 1234567.89, &code("#,##0.00")).unwrap();
    sheet.write_number_with_format(0, 5, -1234.5, &code("#,##0.0")).unwrap();
    sheet.write_number_with_format(0, 6, 0.125, &code("0.0%")).unwrap();
    // Not Excel's built-in 0% (9), which LibreOffice shows with its locale's own percent
    // format (`25 %` in de-DE and fr-FR) where Excel keeps `25%`.
    sheet.write_number_with_format(0, 7, 0.0375, &code("0.000%")).unwrap();
    sheet.write_number(0, 8, -0.0171).unwrap();
    sheet.write_number(0, 9, 0.8).unwrap();
    sheet.write_number_with_format(0, 10, 1250.0, &code("0.00E+00")).unwrap();
    // 28 November 2026 and 12 March 2025 14:30 (serials 46354 and 45728 + 14.5/24).
    sheet.write_number_with_format(0, 11, 46354.0, &Format::new().set_num_format_index(14)).unwrap();
    sheet.write_number_with_format(0, 12, 45728.0 + 14.5 / 24.0, &Format::new().set_num_format_index(22)).unwrap();
    sheet.write_number_with_format(0, 13, 14.5 / 24.0, &code("h:mm")).unwrap();
    sheet.write_number(0, 14, 1234567.5).unwrap();
    sheet.write_string(0, 15, "abc").unwrap();
    book.save(path).unwrap();
}

/// A csv export in the locale writes booleans in its words (Excel's names of TRUE and FALSE:
/// WAHR/FALSCH in German, VRAI/FAUX in French, TÕENE/VÄÄR in Estonian) and numbers with its
/// own group mark (fr-FR and et-EE a no-break space, de-DE `.`), as LibreOffice set to the
/// locale exports the same workbook (the oracle); en-US is unchanged.
#[test]
fn booleans_and_grouped_numbers_export_as_libreoffice_writes_them() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_kinds(&d.join("kinds.xlsx"));
    let ours = |locale: &str| {
        let out = format!("ours-{locale}.csv");
        ok(in_dir(d, &["export", "kinds.xlsx", "--locale", locale, "-o", &out]));
        std::fs::read_to_string(d.join(out)).unwrap()
    };
    let de = ours("de-DE");
    assert!(de.starts_with("WAHR;FALSCH;WAHR;FALSCH;1.234.567,89;-1.234,5;12,5%;3,750%;-0,0171;0,8;"), "{de}");
    assert!(ours("fr-FR").starts_with("VRAI;FAUX;VRAI;FAUX;1\u{A0}234\u{A0}567,89;-1\u{A0}234,5;"));
    assert!(ours("et-EE").starts_with("TÕENE;VÄÄR;TÕENE;VÄÄR;1\u{A0}234\u{A0}567,89;"));
    assert!(ours("en-US").starts_with("TRUE,FALSE,TRUE,FALSE,\"1,234,567.89\",\"-1,234.5\",12.5%,3.750%,-0.0171,0.8,"));
    let Some(soffice) = common::soffice() else { return };
    for locale in ["de-DE", "fr-FR", "et-EE"] {
        let (ours, theirs) = ours_and_libreoffice(&soffice, d, "kinds", locale);
        assert_eq!(ours, theirs, "{locale}");
    }
}

/// `ncsheet eval`'s values of the first sheet of `file` read in `locale`, by cell (sheet
/// names left out: LibreOffice names a csv's sheet after the file).
fn values_by_cell(d: &Path, file: &Path, locale: &str) -> std::collections::BTreeMap<String, serde_json::Value> {
    let file = file.to_str().unwrap();
    let run = ok(in_dir(d, &["eval", file, "--locale", locale, "--format", "json"]));
    let values: serde_json::Map<String, serde_json::Value> = serde_json::from_str(&run.stdout).unwrap();
    values.into_iter().map(|(k, v)| (k.rsplit('!').next().unwrap().to_string(), v)).collect()
}

/// Whether two cells' JSON values are the same value (numbers to 1e-12 relative: LibreOffice
/// stores 15 to 17 significant digits).
fn same_value(a: &serde_json::Value, b: &serde_json::Value) -> bool {
    match (a.as_f64(), b.as_f64()) {
        (Some(x), Some(y)) => (x - y).abs() <= 1e-12 * x.abs().max(1.0),
        _ => a == b,
    }
}

fn assert_same_values(
    expected: &std::collections::BTreeMap<String, serde_json::Value>,
    found: &std::collections::BTreeMap<String, serde_json::Value>,
    what: &str,
) {
    for (cell, value) in expected {
        let got = found.get(cell).unwrap_or(&serde_json::Value::Null);
        assert!(same_value(value, got), "{what}: {cell}: expected {value}, found {got}");
    }
    assert_eq!(expected.len(), found.len(), "{what}: {found:?}");
}

/// LibreOffice set to `locale` reads a `;` csv in that locale (detecting numbers, dates,
/// percents and booleans as its users' files hold them) and saves it as xlsx: its path.
fn libreoffice_reads_csv(soffice: &impl AsRef<std::ffi::OsStr>, d: &Path, csv: &Path, locale: &str) -> PathBuf {
    let out = d.join(format!("lo-read-{locale}"));
    let reading = "--infilter=Text - txt - csv (StarCalc):59,34,76,1,,0,false,true";
    libreoffice_converts(soffice, d, locale, &[reading], "xlsx", &out, csv);
    out.join(csv.with_extension("xlsx").file_name().unwrap())
}

/// csv round trips through LibreOffice in each locale: the `;` csv `ncsheet export --locale`
/// writes (decimal commas, grouped numbers, percents, dates, a date with a time, booleans)
/// is read by LibreOffice set to that locale to the workbook's values, and LibreOffice's own
/// csv export of the workbook is read by `ncsheet --locale` to the same values.
#[test]
fn csv_round_trips_through_libreoffice_in_the_locale() {
    let Some(soffice) = common::soffice() else { return };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_kinds(&d.join("kinds.xlsx"));
    let workbook = values_by_cell(d, Path::new("kinds.xlsx"), "en-US");
    for locale in ["de-DE", "fr-FR", "et-EE"] {
        // ours_and_libreoffice leaves both csv files: ours-LOCALE.csv and lo-LOCALE/kinds.csv.
        ours_and_libreoffice(&soffice, d, "kinds", locale);
        let read_by_libreoffice = libreoffice_reads_csv(&soffice, d, &d.join(format!("ours-{locale}.csv")), locale);
        let theirs = values_by_cell(d, &read_by_libreoffice, "en-US");
        assert_same_values(&workbook, &theirs, &format!("{locale}: LibreOffice reading ncsheet's csv"));
        let ours = values_by_cell(d, &d.join(format!("lo-{locale}/kinds.csv")), locale);
        assert_same_values(&workbook, &ours, &format!("{locale}: ncsheet reading LibreOffice's csv"));
    }
}

/// Text cells that look like numbers, dates or words of a spreadsheet (A to I), each forced
/// to text in en-US.
const TEXTS: &[&str] = &["2:30 PM", "0.8", "12/03/2025", "12", "1,5", "WAHR", "2:30 nachm.", "12.03.2025", "abc"];

/// ncsheet's `;` csv in `locale` of a workbook of [`TEXTS`] (`texts.xlsx` in `d`).
fn texts_exported(d: &Path, locale: &str) -> String {
    if !d.join("texts.xlsx").exists() {
        std::fs::write(d.join("t.csv"), "x\n").unwrap();
        let typed: Vec<String> =
            TEXTS.iter().enumerate().map(|(i, t)| format!("{}1='{t}", char::from(b'A' + i as u8))).collect();
        let mut args = vec!["set", "t.csv", "--locale", "en-US"];
        args.extend(typed.iter().map(String::as_str));
        args.extend(["-o", "texts.xlsx"]);
        ok(in_dir(d, &args));
    }
    let out = format!("texts-{locale}.csv");
    ok(in_dir(d, &["export", "texts.xlsx", "--locale", locale, "-o", &out]));
    std::fs::read_to_string(d.join(out)).unwrap()
}

/// A text cell is written to a `;` csv in the locale as LibreOffice set to the locale writes
/// it, bare (LibreOffice 7.4 writes every text cell bare: `2:30 PM;0.8;12/03/2025;12;1,5;…`):
/// text that is a number or date only in another locale's spelling (`2:30 PM` in de-DE and
/// et-EE, which refuse en-US's PM) reads back there as the same text, so it gets no `'` (it
/// got one: `'2:30 PM`). Text the locale reads as something else (`12`, `1,5`, de-DE `WAHR`)
/// keeps ncsheet's `'`, where LibreOffice's bare field reads back as a number. With soffice:
/// ncsheet's fields are LibreOffice's, but for those marks, and LibreOffice reads ncsheet's
/// file to text wherever it reads its own to text.
#[test]
fn text_cells_are_written_to_a_semicolon_csv_as_libreoffice_writes_them() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let recorded = [
        ("de-DE", "2:30 PM;0.8;12/03/2025;'12;'1,5;'WAHR;'2:30 nachm.;'12.03.2025;abc\n"),
        ("fr-FR", "'2:30 PM;0.8;'12/03/2025;'12;'1,5;WAHR;2:30 nachm.;'12.03.2025;abc\n"),
        ("et-EE", "2:30 PM;0.8;12/03/2025;'12;'1,5;WAHR;2:30 nachm.;'12.03.2025;abc\n"),
    ];
    for (locale, expected) in recorded {
        assert_eq!(texts_exported(d, locale), expected, "{locale}");
    }
    let Some(soffice) = common::soffice() else { return };
    for (locale, _) in recorded {
        let out = d.join(format!("lo-{locale}"));
        let csv = "csv:Text - txt - csv (StarCalc):59,34,76,1,,0,false,true,true";
        libreoffice_converts(&soffice, d, locale, &[], csv, &out, &d.join("texts.xlsx"));
        let theirs_file = out.join("texts.csv");
        let theirs = semicolon_fields(&std::fs::read_to_string(&theirs_file).unwrap());
        let ours = semicolon_fields(&texts_exported(d, locale));
        let read_theirs = values_by_cell(d, &libreoffice_reads_csv(&soffice, d, &theirs_file, locale), "en-US");
        let ours_file = d.join(format!("texts-{locale}.csv"));
        let read_ours = values_by_cell(d, &libreoffice_reads_csv(&soffice, d, &ours_file, locale), "en-US");
        for (i, text) in TEXTS.iter().enumerate() {
            let cell = format!("{}1", char::from(b'A' + i as u8));
            let text_there = read_theirs.get(&cell) == Some(&serde_json::Value::from(*text));
            assert_eq!(ours[i].strip_prefix('\'').is_some(), !text_there, "{locale}: {text}");
            assert_eq!(ours[i].strip_prefix('\'').unwrap_or(&ours[i]), theirs[i], "{locale}: {text}");
            if text_there {
                assert_eq!(read_ours.get(&cell), read_theirs.get(&cell), "{locale}: {text}");
            }
        }
    }
}

/// Text typed in a `;` csv in de-DE that en-US would read as a time (`2:30 PM`, refused as
/// one there and kept as text) is saved bare, as LibreOffice writes a text cell (it was saved
/// as `'2:30 PM`); the fields not edited stay as the file spelled them (`1.234,5`, which the
/// locale's reading had made an edit and saved as `1234,5`).
#[test]
fn text_typed_in_a_semicolon_csv_is_saved_as_the_locale_reads_it_back() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("h.csv"), "2:30 PM;1.234,5;x\n").unwrap();
    ok(in_dir(d, &["set", "h.csv", "--locale", "de-DE", "C1=2:30 PM", "-o", "i.csv"]));
    assert_eq!(std::fs::read_to_string(d.join("i.csv")).unwrap(), "2:30 PM;1.234,5;2:30 PM\n");
    let back = ok(in_dir(d, &["eval", "i.csv", "--locale", "de-DE", "--format", "json"]));
    assert_eq!(back.stdout.trim(), r#"{"Sheet1!A1": "2:30 PM", "Sheet1!B1": 1234.5, "Sheet1!C1": "2:30 PM"}"#);
}

/// Excel's delimiter directive, a first line `sep=;`, names the delimiter and is no data
/// (Excel opens such a file with `;` between fields and the line not shown); ncsheet read it
/// as a text row (`sep=` in A1). The detection message says where the delimiter came from;
/// a save writes the line back, and a line in an error is named as it stands in the file.
#[test]
fn an_excel_sep_line_names_the_delimiter_and_is_no_data() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.csv"), "sep=;\r\na;0,5;x\r\n1;2;=A2+B2\r\n").unwrap();
    let run = ok(in_dir(d, &["eval", "s.csv", "--locale", "en-US", "--format", "json"]));
    let values =
        r#"{"Sheet1!A1": "a", "Sheet1!B1": 0.5, "Sheet1!C1": "x", "Sheet1!A2": 1, "Sheet1!B2": 2, "Sheet1!C2": 3}"#;
    assert_eq!(run.stdout.trim(), values);
    assert!(
        run.stderr.contains("read as ;-separated values (decimal commas as numbers), as its first line sep=; says"),
        "{}",
        run.stderr
    );
    ok(in_dir(d, &["set", "s.csv", "--locale", "en-US", "B2=5", "-o", "t.csv"]));
    assert_eq!(std::fs::read_to_string(d.join("t.csv")).unwrap(), "sep=;\r\na;0,5;x\r\n1;5;=A2+B2\r\n");
    // A directive against the text's look: `,` between fields, the `;` in a field is text.
    std::fs::write(d.join("c.csv"), "sep=,\na;b,\"1,5\"\n").unwrap();
    let run = ok(in_dir(d, &["eval", "c.csv", "--locale", "en-US", "--format", "json"]));
    assert_eq!(run.stdout.trim(), r#"{"Sheet1!A1": "a;b", "Sheet1!B1": "1,5"}"#);
    assert!(run.stderr.contains("read as ,-separated values, as its first line sep=, says"), "{}", run.stderr);
    std::fs::write(d.join("bad.csv"), "sep=;\na;b\n\"x\n").unwrap();
    let bad = in_dir(d, &["eval", "bad.csv", "--locale", "en-US"]);
    assert!(bad.stderr.contains("bad.csv: line 3: unterminated quoted field"), "{}", bad.stderr);
}

/// A `;` csv with dates and times, read in the locale and written back, keeps their spelling:
/// each gets the format a date or time typed there gets (Excel's built-in date, 14, its date
/// and time, 22, and `h:mm`, as `set` gives them), so `export` writes `12.03.2025` where it
/// wrote the serial 45728. The reading says the delimiter and the decimal comma, and the
/// values are LibreOffice's reading of the same file in the locale (the oracle).
#[test]
fn dates_and_times_of_a_semicolon_csv_are_written_back_as_they_were_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let soffice = common::soffice();
    for (locale, date) in [("de-DE", "12.03.2025"), ("fr-FR", "12/03/2025"), ("et-EE", "12.03.2025")] {
        let text = format!("{date};14:30;{date} 14:30;0,8;28{}\n", &date[2..]);
        let csv = d.join(format!("eu-{locale}.csv"));
        std::fs::write(&csv, &text).unwrap();
        let back = format!("back-{locale}.csv");
        let run = ok(in_dir(d, &["export", csv.to_str().unwrap(), "--locale", locale, "-o", &back]));
        assert!(run.stderr.contains(";-separated values (decimal commas"), "{}", run.stderr);
        assert_eq!(std::fs::read_to_string(d.join(&back)).unwrap(), text, "{locale}");
        let Some(soffice) = &soffice else { continue };
        let theirs = values_by_cell(d, &libreoffice_reads_csv(soffice, d, &csv, locale), "en-US");
        assert_same_values(&theirs, &values_by_cell(d, &csv, locale), locale);
    }
}

/// A date and a time typed with `set` into a csv are saved as the cell shows them, as Excel
/// and LibreOffice write a date cell to csv; they were saved as their serials
/// (`0,6041666666666666;45728`), which every reader takes for plain numbers. The values are
/// LibreOffice's reading of the saved file in the locale (the oracle, when installed).
#[test]
fn a_date_and_a_time_typed_into_a_csv_are_saved_as_shown() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let soffice = common::soffice();
    for (locale, date) in [("de-DE", "12.03.2025"), ("fr-FR", "12/03/2025"), ("et-EE", "12.03.2025")] {
        std::fs::write(d.join("t.csv"), "a;1,5;x\n").unwrap();
        let out = format!("t-{locale}.csv");
        let (time, day) = ("A1=14:30".to_string(), format!("B1={date}"));
        ok(in_dir(d, &["set", "t.csv", "--locale", locale, &time, &day, "-o", &out]));
        assert_eq!(std::fs::read_to_string(d.join(&out)).unwrap(), format!("14:30;{date};x\n"), "{locale}");
        let Some(soffice) = &soffice else { continue };
        let theirs = values_by_cell(d, &libreoffice_reads_csv(soffice, d, &d.join(&out), locale), "en-US");
        assert_eq!(theirs.get("A1").and_then(|v| v.as_f64()).map(|t| (t * 1440.0).round()), Some(870.0), "{locale}");
        assert_eq!(theirs.get("B1").and_then(|v| v.as_f64()), Some(45728.0), "{locale}");
    }
    // A formula in a cell with a date's format is a formula: written as typed in the locale.
    ok(in_dir(d, &["set", "t.csv", "--locale", "de-DE", "A1=12.03.2025", "A1==B1+0,5", "-o", "f.csv"]));
    assert_eq!(std::fs::read_to_string(d.join("f.csv")).unwrap(), "=B1+0,5;1,5;x\n");
    std::fs::write(d.join("u.csv"), "a,1.5,x\n").unwrap();
    ok(in_dir(d, &["set", "u.csv", "--locale", "en-US", "B1=3/12/2025", "-o", "u2.csv"]));
    assert_eq!(std::fs::read_to_string(d.join("u2.csv")).unwrap(), "a,3/12/2025,x\n");
}

/// A time typed in en-US gets the format Excel en-US gives it, as a date does (Microsoft's
/// built-in formats: 20 `h:mm`, 22 `m/d/yyyy h:mm`, 18 `h:mm AM/PM`, 21 `h:mm:ss`, 46
/// `[h]:mm:ss` for a day or more), so it shows and is saved to a csv as typed; it showed,
/// and was saved as, its serial (0.604166666666667). The values are unchanged: 14:30 is 870
/// minutes, 2025-03-12 serial 45728, and LibreOffice set to en-US reads the saved csv to them.
#[test]
fn a_time_typed_in_en_us_shows_as_excel_shows_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("t.csv"), "a,1.5,x,y,z\n").unwrap();
    let typed = ["A1=14:30", "B1=3/12/2025 14:30", "C1=2:30 PM", "D1=14:30:15", "E1=25:30"];
    for out in ["u.csv", "u.xlsx"] {
        let mut args = vec!["set", "t.csv", "--locale", "en-US"];
        args.extend(typed);
        args.extend(["-o", out]);
        ok(in_dir(d, &args));
    }
    let saved = std::fs::read_to_string(d.join("u.csv")).unwrap();
    assert_eq!(saved, "14:30,3/12/2025 14:30,2:30 PM,14:30:15,25:30:00\n");
    let shown = ok(in_dir(d, &["eval", "u.xlsx", "A1", "B1", "C1", "D1", "E1", "--locale", "en-US"])).stdout;
    assert_eq!(shown, "A1  14:30\nB1  3/12/2025 14:30\nC1  2:30 PM\nD1  14:30:15\nE1  25:30:00\n");
    let minutes = [870.0, 45728.0 * 1440.0 + 870.0, 870.0, 870.25, 1530.0];
    let in_minutes = |values: &std::collections::BTreeMap<String, serde_json::Value>| -> Vec<f64> {
        let cells = ["A1", "B1", "C1", "D1", "E1"];
        cells.iter().map(|c| (values[*c].as_f64().expect(c) * 1440.0 * 4.0).round() / 4.0).collect()
    };
    assert_eq!(in_minutes(&values_by_cell(d, Path::new("u.xlsx"), "en-US")), minutes);
    assert_eq!(in_minutes(&values_by_cell(d, Path::new("u.csv"), "en-US")), minutes);
    let Some(soffice) = common::soffice() else { return };
    let out = d.join("lo-read-en-US");
    let reading = "--infilter=Text - txt - csv (StarCalc):44,34,76,1,,0,false,true";
    libreoffice_converts(&soffice, d, "en-US", &[reading], "xlsx", &out, &d.join("u.csv"));
    assert_eq!(in_minutes(&values_by_cell(d, &out.join("u.xlsx"), "en-US")), minutes);
}

/// Times typed with seconds, of a day or more, or with a fraction of a second are saved to a
/// csv in the formats Excel gives them (21 `h:mm:ss`, 46 `[h]:mm:ss`, 47 `mm:ss.0`), which
/// LibreOffice set to the locale reads back to the same values (the oracle, when installed):
/// 14:30:15 is 52215 seconds, 25:30 is 1.0625 days, 1:30,5 is 90.5 seconds. `25:30` was
/// saved as `1:30` (`h:mm` drops the day) and `1:30,5` as `00:01`.
#[test]
fn long_and_fine_times_typed_into_a_csv_read_back_as_typed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let soffice = common::soffice();
    // An afternoon time in the locale's words: de-DE's `nachm.` has a `.` that is no fraction
    // of a second (ncsheet wrote `30:00,0`).
    for (locale, afternoon) in [("de-DE", "2:30 nachm."), ("fr-FR", "2:30 PM"), ("et-EE", "2:30 p.l")] {
        std::fs::write(d.join("t.csv"), "a;1,5;x\n").unwrap();
        let out = format!("t-{locale}.csv");
        let d1 = format!("D1={afternoon}");
        ok(in_dir(d, &["set", "t.csv", "--locale", locale, "A1=14:30:15", "B1=25:30", "C1=1:30,5", &d1, "-o", &out]));
        let written = std::fs::read_to_string(d.join(&out)).unwrap();
        assert_eq!(written, format!("14:30:15;25:30:00;01:30,5;{afternoon}\n"), "{locale}");
        let Some(soffice) = &soffice else { continue };
        let theirs = values_by_cell(d, &libreoffice_reads_csv(soffice, d, &d.join(&out), locale), "en-US");
        let seconds =
            |cell: &str| theirs.get(cell).and_then(|v| v.as_f64()).map(|t| (t * 86400.0 * 10.0).round() / 10.0);
        assert_eq!(
            [seconds("A1"), seconds("B1"), seconds("C1"), seconds("D1")],
            [Some(52215.0), Some(91800.0), Some(90.5), Some(52200.0)],
            "{locale}"
        );
    }
}

/// Format codes with words in brackets, and what TEXT(1234.5, code) gives with each in en-US
/// (LibreOffice 7.4 set to en-US, recorded: Err:502 is #VALUE!), but for `[Brown]0`.
const BRACKET_WORDS: [(&str, &str); 14] = [
    ("[Foo]0", "#VALUE!"),
    ("0;[Foo]-0", "#VALUE!"),
    ("[Gray]0", "#VALUE!"),
    ("[Orange]0", "#VALUE!"),
    ("[Color0]0", "#VALUE!"),
    ("[Rot]0", "#VALUE!"),
    ("[Rouge]0", "#VALUE!"),
    ("[Brown]0", "#VALUE!"),
    ("[Red]0", "1235"),
    ("[black]0.0", "1234.5"),
    ("[Color10]0", "1235"),
    ("[Color 10]0", "1235"),
    ("[Blue][>1]0", "1235"),
    ("[DBNum1]0", "1235"),
];

/// A word in a format code's brackets that is no colour of the locale, condition, currency
/// or elapsed time (`[Foo]0`, `[Gray]0`, another locale's `[Rot]0`) makes no code: TEXT gives
/// #VALUE! in en-US, as LibreOffice set to en-US does (the oracle, run when installed) and as
/// Excel refuses such a code; ncsheet ignored the word (`1235`). `[Brown]`, which
/// LibreOffice reads, is refused as Excel refuses it: Microsoft's "Review guidelines for
/// customizing a number format" names eight colours, and Brown is none of them. A cell whose
/// format has such a word shows its number in General, as LibreOffice shows it (`-1234.5`,
/// where ncsheet showed `-1235`).
#[test]
fn an_unknown_word_in_a_format_code_makes_no_code() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let fields: Vec<String> =
        BRACKET_WORDS.iter().map(|(code, _)| format!("\"=TEXT(1234.5,\"\"{code}\"\")\"")).collect();
    std::fs::write(d.join("w.csv"), format!("{}\n", fields.join(","))).unwrap();
    ok(in_dir(d, &["set", "w.csv", "--delimiter", ",", "--locale", "en-US", "A2=1", "-o", "w.xlsx"]));
    let cells: Vec<String> = (0..BRACKET_WORDS.len()).map(|i| format!("{}1", char::from(b'A' + i as u8))).collect();
    let mut args = vec!["eval", "w.xlsx", "--locale", "en-US"];
    args.extend(cells.iter().map(String::as_str));
    let ours: Vec<String> = ok(in_dir(d, &args)).stdout.lines().map(|l| l[cells[0].len() + 2..].to_string()).collect();
    let expected: Vec<&str> = BRACKET_WORDS.iter().map(|(_, shown)| *shown).collect();
    assert_eq!(ours, expected);
    let shown_in = |code: &str| {
        let path = d.join("f.xlsx");
        let mut book = rust_xlsxwriter::Workbook::new();
        let format = rust_xlsxwriter::Format::new().set_num_format(code);
        book.add_worksheet().write_number_with_format(0, 0, -1234.5, &format).unwrap();
        book.save(&path).unwrap();
        ok(in_dir(d, &["eval", "f.xlsx", "A1", "--locale", "en-US"])).stdout
    };
    assert_eq!(shown_in("[Foo]0"), "-1234.5\n");
    assert_eq!(shown_in("0;[Foo]-0"), "-1234.5\n");
    assert_eq!(shown_in("[Red]0"), "-1235\n");
    let Some(soffice) = common::soffice() else { return };
    let out = d.join("lo-en-US");
    let csv = "csv:Text - txt - csv (StarCalc):44,34,76,1,,0,false,true,true";
    libreoffice_converts(&soffice, d, "en-US", &[], csv, &out, &d.join("w.xlsx"));
    let theirs = std::fs::read_to_string(out.join("w.csv")).unwrap();
    let theirs: Vec<&str> = theirs.lines().next().unwrap().split(',').map(as_excel_error).collect();
    for (i, (code, _)) in BRACKET_WORDS.iter().enumerate() {
        if *code != "[Brown]0" {
            assert_eq!(ours[i], theirs[i], "{code}");
        }
    }
}

/// Percents and scientific numbers of a `;` csv, read in the locale and written back, come
/// back as LibreOffice set to the locale writes them (the oracle, run here when soffice is
/// installed; its text recorded for de-DE, fr-FR and et-EE with LibreOffice 7.4): the
/// locale's percent with two decimals (a no-break space before `%` in de-DE, a space in
/// fr-FR, none in et-EE) and `0,00E+00`. ncsheet wrote the bare values (`0,125`, `1500`).
#[test]
fn percents_and_scientific_numbers_of_a_semicolon_csv_are_written_back_as_libreoffice_writes_them() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = "12,5%;1,5E+03;25%;-3,75%;1E-5;1,2345E+10;1234,5\n";
    std::fs::write(d.join("pct.csv"), text).unwrap();
    let soffice = common::soffice();
    for (locale, space) in [("de-DE", "\u{A0}"), ("fr-FR", " "), ("et-EE", "")] {
        let back = format!("back-{locale}.csv");
        ok(in_dir(d, &["export", "pct.csv", "--locale", locale, "-o", &back]));
        let ours = std::fs::read_to_string(d.join(&back)).unwrap();
        let expected = format!("12,50{space}%;1,50E+03;25,00{space}%;-3,75{space}%;1,00E-05;1,23E+10;1234,5\n");
        assert_eq!(ours, expected, "{locale}");
        let Some(soffice) = &soffice else { continue };
        let out = d.join(format!("lo-pct-{locale}"));
        let reading = "--infilter=Text - txt - csv (StarCalc):59,34,76,1,,0,false,true";
        let writing = "csv:Text - txt - csv (StarCalc):59,34,76,1,,0,false,true,true";
        libreoffice_converts(soffice, d, locale, &[reading], writing, &out, &d.join("pct.csv"));
        assert_eq!(ours, std::fs::read_to_string(out.join("pct.csv")).unwrap(), "{locale}");
    }
    // en-US keeps the values as they were read.
    std::fs::write(d.join("en.csv"), "12.5%,1.5E+03\n").unwrap();
    ok(in_dir(d, &["export", "en.csv", "--locale", "en-US", "-o", "back-en.csv"]));
    assert_eq!(std::fs::read_to_string(d.join("back-en.csv")).unwrap(), "0.125,1500\n");
}

/// A `;` csv's fields that are numbers only in the file syntax (`0.8`, `12/03/2025` and
/// `1.5` in de-DE) are text in the locale, and a day and month without a year (`12.03.`) the
/// current year's, as LibreOffice set to the locale reads the file (the oracle, run at the
/// same time). ncsheet kept the en-US reading of such fields (0.8, 3 December 2025).
#[test]
fn a_csv_field_that_is_a_number_only_in_the_file_syntax_is_text_in_the_locale() {
    let Some(soffice) = common::soffice() else { return };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let csv = d.join("mixed.csv");
    std::fs::write(&csv, "12/03/2025;0.8;12.03.;1.5;1,5;12.03\n").unwrap();
    for locale in ["de-DE", "fr-FR", "et-EE"] {
        let theirs = values_by_cell(d, &libreoffice_reads_csv(&soffice, d, &csv, locale), "en-US");
        let ours = values_by_cell(d, &csv, locale);
        assert_same_values(&theirs, &ours, locale);
    }
    // A `,` file is read with decimal points (the command says so): its numbers stay numbers.
    std::fs::write(d.join("points.csv"), "0.8,1.5\n").unwrap();
    let run = ok(in_dir(d, &["eval", "points.csv", "--locale", "de-DE", "--format", "json"]));
    assert_eq!(run.stdout.trim(), r#"{"Sheet1!A1": 0.8, "Sheet1!B1": 1.5}"#);
    assert!(run.stderr.contains("with decimal points"), "{}", run.stderr);
}

/// A date with a time typed in the locale (`12.03.2025 14:30`, fr-FR `12/03/2025 14:30`) is
/// the day's serial plus the time (2025-03-12 is serial 45728, 14:30 is 14.5/24 of a day)
/// in Excel's built-in date and time format (22), which shows the short date and the time;
/// `14:30` alone is a time in `h:mm` (20). LibreOffice set to the locale shows those formats
/// the same way (the oracle for the shown text). LibreOffice's own typing gives other codes
/// (`TT.MM.JJ HH:MM`, `HH:MM:SS`: `12.03.25 14:30`, `14:30:00`); Excel's are kept.
#[test]
fn a_date_with_a_time_typed_in_the_locale_is_a_date_time() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("t.csv"), "x\n").unwrap();
    let soffice = common::soffice();
    for (locale, typed) in [("de-DE", "12.03.2025 14:30"), ("fr-FR", "12/03/2025 14:30"), ("et-EE", "12.03.2025 14:30")]
    {
        let stem = format!("t-{locale}");
        let out = format!("{stem}.xlsx");
        let (a1, b1) = (format!("A1={typed}"), "B1=14:30");
        ok(in_dir(d, &["set", "t.csv", "--locale", locale, &a1, b1, "-o", &out]));
        let values = values_by_cell(d, Path::new(&out), locale);
        assert!(same_value(&values["A1"], &serde_json::json!(45728.0 + 14.5 / 24.0)), "{locale}: {values:?}");
        assert!(same_value(&values["B1"], &serde_json::json!(14.5 / 24.0)), "{locale}: {values:?}");
        let shown = ok(in_dir(d, &["eval", &out, "A1", "B1", "--locale", locale])).stdout;
        assert_eq!(shown, format!("A1  {typed}\nB1  14:30\n"), "{locale}");
        let Some(soffice) = &soffice else { continue };
        let (ours, theirs) = ours_and_libreoffice(soffice, d, &stem, locale);
        assert_eq!(ours[..2], theirs[..2], "{locale}");
    }
}

/// Slovak's and Hungarian's short month names (`mmm`) and day names (`ddd`) of every month
/// and weekday, as LibreOffice set to sk-SK and hu-HU shows them (its locale data, CLDR's
/// abbreviated names), and their words for TRUE and FALSE.
#[test]
fn libreoffice_in_sk_and_hu_is_the_oracle_for_short_names() {
    let Some(soffice) = common::soffice() else { return };
    let mut probes: Vec<String> = (1..=12).map(|m| format!(r#"=TEXT(DATE(2025,{m},1),"mmm")"#)).collect();
    // 2025-06-01 is a Sunday.
    probes.extend((1..=7).map(|d| format!(r#"=TEXT(DATE(2025,6,{d}),"ddd")"#)));
    probes.extend(["=1<2".to_string(), "=1>2".to_string()]);
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let fields: Vec<String> = probes.iter().map(|p| format!("\"{}\"", p.replace('"', "\"\""))).collect();
    std::fs::write(d.join("short.csv"), format!("{}\n", fields.join(","))).unwrap();
    ok(in_dir(d, &["set", "short.csv", "--locale", "en-US", "A2=1", "-o", "short.xlsx"]));
    for locale in ["sk-SK", "hu-HU"] {
        let (ours, theirs) = ours_and_libreoffice(&soffice, d, "short", locale);
        for (i, probe) in probes.iter().enumerate() {
            assert_eq!(ours[i].strip_prefix('\'').unwrap_or(&ours[i]), theirs[i], "{locale}: {probe}");
        }
    }
}

/// The probes of [`values_and_shown_text_of_probes_are_libreoffice_s`], each with the locales
/// it runs in: text read as numbers and dates (a fraction, a space before `%` and a currency,
/// a time's fraction of a second with the decimal comma, a month named in the locale's words,
/// date text given to YEAR and MONTH), NUMBERVALUE with its separators given, text that is
/// no number where a number is compared or tested, and TEXT's codes with a `.` or English
/// date letters where the locale spells them otherwise.
const VALUE_PROBES: &[(&[&str], &str)] = &[
    (ALL, r#"=VALUE("1 1/2")"#),
    (ALL, r#"=VALUE("-2 3/4")"#),
    (&["fr-FR", "et-EE"], r#"=VALUE("12,5 %")"#),
    (&["fr-FR", "et-EE"], r#"=VALUE("1 234,5 €")"#),
    (ALL, r#"=VALUE("1,5 €")"#),
    (ALL, r#"=VALUE("$1,5")"#),
    (ALL, r#"=VALUE("1,5-")"#),
    (ALL, r#"="1.234,5-"*1"#),
    (ALL, r#"=VALUE("14:30:15,5")"#),
    (ALL, r#"=VALUE("1.234,5")"#),
    (ALL, r#"=VALUE("1 234,5")"#),
    (&["de-DE"], r#"=DATEVALUE("12. März 2025")"#),
    (&["fr-FR"], r#"=DATEVALUE("12 mars 2025")"#),
    (&["et-EE"], r#"=DATEVALUE("12. märts 2025")"#),
    (&["de-DE", "et-EE"], r#"=VALUE("12. März 2025 14:30")"#),
    (&["de-DE", "et-EE"], r#"=YEAR("12.03.2025")"#),
    (&["de-DE", "et-EE"], r#"=DAY("12.03.2025"&"")"#),
    (&["fr-FR"], r#"=MONTH("12/03/2025")"#),
    (ALL, r#"=EDATE("12.03.2025",1)"#),
    (ALL, r#"=TIMEVALUE("12.03.2025 14:30")"#),
    (ALL, r#"=NUMBERVALUE("1.234,5",",",".")"#),
    (ALL, r#"=NUMBERVALUE("1 234,5",","," ")"#),
    (ALL, r#"="1,5"=1.5"#),
    (ALL, r#"=ISNUMBER("1,5")"#),
    (ALL, r#"=N("1,5")"#),
    (ALL, r#"=IF("1,5">1,1,0)"#),
    (ALL, r#"=ABS("-0,5")+INT("3,7")"#),
    (ALL, r#"=DATE(2025,3,12)+"0,5""#),
    (ALL, r#"=TEXT(1234.5,"00.00")"#),
    (&["fr-FR", "et-EE"], r##"=TEXT(1234.5,"#,##0.00")"##),
    (ALL, r#"=TEXT(45728,"dd\ mmm\ yyyy")"#),
    (ALL, r#"=SUM("1,5",2)"#),
    (ALL, r#"=MAX("1,5",1)"#),
    // A day and month without a year, in each locale's forms: the current year's (LibreOffice
    // runs at the same time as ncsheet, so both take the same year).
    (&["de-DE"], r#"=DATEVALUE("12.03.")"#),
    (&["et-EE"], r#"=DATEVALUE("12.03")"#),
    (&["fr-FR"], r#"=DATEVALUE("12/3")"#),
    (&["de-DE", "et-EE"], r#"="12.3."+0"#),
    (&["de-DE"], r#"=DATEVALUE("12. März")"#),
    (&["fr-FR"], r#"=DATEVALUE("12 mars")"#),
    (&["et-EE"], r#"=YEAR("12 märts")"#),
    (&["de-DE"], r#"=DATEDIF("01.01.2000","12.03.","y")"#),
    // A named month: after a day with or without the `.` (not in fr-FR, whose date separator
    // is `/`), a short name's own `.`, a year between dashes; the month and one number are
    // that year's first day of the month (`März 12` is 1 March 2012); a full name with a `.`
    // after it, a dash without a year and a comma are no date.
    (&["de-DE"], r#"=DATEVALUE("März 12")"#),
    (&["de-DE"], r#"="März 12"+0"#),
    (&["de-DE"], r#"=DATEVALUE("Mär.12")"#),
    (&["de-DE"], r#"=DATEVALUE("märz 12.")"#),
    (&["de-DE"], r#"=DATEVALUE("Sept. 12")"#),
    (&["de-DE"], r#"=DATEVALUE("Dez 30")"#),
    (&["de-DE"], r#"=DATEVALUE("Dez 29")"#),
    (&["de-DE"], r#"=DATEVALUE("12.März")"#),
    (&["de-DE"], r#"=DATEVALUE("12.März 2025")"#),
    (&["de-DE"], r#"=DATEVALUE("12-März-2025")"#),
    (&["de-DE"], r#"=DATEVALUE("12.Mär.2025")"#),
    (&["de-DE"], r#"=DATEVALUE("März 12 25")"#),
    (&["de-DE"], r#"=DATEVALUE("12. März.")"#),
    (&["de-DE"], r#"=DATEVALUE("12-März")"#),
    (&["de-DE"], r#"=DATEVALUE("12.März.2025")"#),
    (&["de-DE"], r#"=DATEVALUE("März 12, 2025")"#),
    (&["de-DE"], r#"=DATEVALUE("März.12")"#),
    (&["de-DE"], r#"=DATEVALUE("12 March")"#),
    (&["fr-FR"], r#"=DATEVALUE("12. mars")"#),
    (&["fr-FR"], r#"=DATEVALUE("12 mars.")"#),
    (&["fr-FR"], r#"=DATEVALUE("12 janv")"#),
    (&["fr-FR"], r#"=DATEVALUE("Sept 12")"#),
    (&["fr-FR"], r#"=DATEVALUE("12/mars/2025")"#),
    (&["fr-FR"], r#"=DATEVALUE("mars 12")"#),
    (&["fr-FR"], r#"=DATEVALUE("mars/12")"#),
    (&["fr-FR"], r#"=DATEVALUE("janv. 12")"#),
    (&["fr-FR"], r#"=DATEVALUE("12/mars")"#),
    (&["fr-FR"], r#"=DATEVALUE("12-sept.-2025")"#),
    (&["fr-FR"], r#"=DATEVALUE("12/mars 2025")"#),
    (&["et-EE"], r#"=DATEVALUE("märts 12")"#),
    (&["et-EE"], r#"=DATEVALUE("veebr.12")"#),
    (&["et-EE"], r#"=DATEVALUE("märts-12")"#),
    (&["et-EE"], r#"=DATEVALUE("12.veebr.2025")"#),
    (&["et-EE"], r#"=DATEVALUE("12 märts.")"#),
    (&["et-EE"], r#"=DATEVALUE("Sept 12")"#),
    (&["et-EE"], r#"=DATEVALUE("12. Sep.")"#),
    // Forms that are no date there: `12.03` in de-DE (its form ends with the `.`), `12.03.`
    // in fr-FR, and `/` or `-` between a date's parts in de-DE and et-EE.
    (&["de-DE", "fr-FR"], r#"=DATEVALUE("12.03")"#),
    (&["fr-FR"], r#"=DATEVALUE("12.03.")"#),
    (&["de-DE", "et-EE"], r#"=DATEVALUE("12/03/2025")"#),
    (&["de-DE", "et-EE"], r#"=VALUE("12-03-2025")"#),
    (ALL, r#"=DATEVALUE("2025/03/12")"#),
    (&["fr-FR"], r#"=DATEVALUE("12-03-2025")+DATEVALUE("12.3.25")"#),
    // Date text given to the functions that take dates, read as arithmetic reads it.
    (ALL, r#"=DATEDIF("12.03.2025","12.04.2026","ym")"#),
    (&["fr-FR"], r#"=DATEDIF("12/03/2025","12/04/2025","d")"#),
    (ALL, r#"=WORKDAY("12.03.2025","2")"#),
    (ALL, r#"=NETWORKDAYS("12.03.2025","19.03.2025")"#),
    (ALL, r#"=NETWORKDAYS.INTL("12.03.2025","19.03.2025",1)"#),
    (ALL, r#"=COUPNCD("12.03.2025","15.11.2030",2,1)"#),
    (ALL, r#"=COUPDAYS("12.03.2025","15.11.2030",2,1)"#),
    (ALL, r#"=ACCRINTM("12.03.2025","15.11.2030",0.05,1000)"#),
    (ALL, r#"=DISC("12.03.2025","15.11.2030",90,100)"#),
    // TEXT's codes with two sections and a `.`, and with escaped and quoted characters after
    // the number; a space after the last placeholder scales by 1000 where spaces group.
    (ALL, r#"=TEXT(-1234.5,"0.0;(0.0)")"#),
    (ALL, r##"=TEXT(-1234.5,"#.##0,00;(#.##0,00)")"##),
    (ALL, r##"=TEXT(-1234.5,"#,##0.00;-#,##0.00")"##),
    (&["de-DE"], r##"=TEXT(1234.5,"#,##0.000")"##),
    (&["de-DE"], r#"=TEXT(1234.5,"0,0.0")"#),
    (&["de-DE"], r#"=TEXT(1234.5,"0.00")"#),
    // (`&""`: the same code is compared with LibreOffice in fr-FR and et-EE above.)
    (&["de-DE"], r##"=TEXT(1234.5,"#,##0.00")&"""##),
    (&["de-DE"], r#"=TEXT(1234.5,"0.00E+00")"#),
    (ALL, r#"=TEXT(1234.5,"0,0 \€")"#),
    (ALL, r#"=TEXT(1234.5,"0,0\ \€")"#),
    (ALL, r#"=TEXT(1234.5,"0,00 ""€""")"#),
    (ALL, r#"=TEXT(1234.5,"0,0 \k\g")"#),
    (ALL, r#"=TEXT(1234567.5,"0,0  ")"#),
    // The locale's word for General, a fraction of a second after the decimal comma, AM/PM
    // in the locale's words, a fraction's space (no group mark), scientific codes, the
    // month names of a code tagged with a language, DOLLAR and FIXED rounding to tens.
    (&["de-DE", "fr-FR"], r#"=TEXT(1234.5,"Standard")"#),
    (&["de-DE", "fr-FR"], r#"=TEXT(1234.5,"STANDARD"" kg""")"#),
    (ALL, r#"=TEXT(0.6,"hh:mm:ss,00")"#),
    (ALL, r#"=TEXT(0.6,"[h]:mm:ss,0")"#),
    (ALL, r#"=TEXT(45728.3,"hh:mm AM/PM")"#),
    (ALL, r#"=TEXT(45728.6,"h am/pm")"#),
    (ALL, r##"=TEXT(1.75,"# ?/?")"##),
    (ALL, r##"=TEXT(1.75,"# ??/??")"##),
    (ALL, r#"=TEXT(1234.5,"0,00E+00")"#),
    (ALL, r#"=TEXT(0.5,"0,00%")"#),
    (&["fr-FR", "et-EE"], r##"=TEXT(1234567.891,"# ##0")"##),
    (&["fr-FR", "et-EE"], r##"=TEXT(1234.5,"#,##0")"##),
    (&["de-DE"], r##"=TEXT(1234567.891,"#.##0")"##),
    (ALL, r#"=TEXT(45728,"[$-407]mmmm")"#),
    (ALL, r#"=TEXT(45728,"[$-40C]mmmm")"#),
    (ALL, r#"=TEXT(45728,"[$-425]mmmm")"#),
    (ALL, r#"=DOLLAR(1234.567,-2)"#),
    (ALL, r#"=DOLLAR(-0.5,2)"#),
    (ALL, r#"=FIXED(-1234567.891,-2)"#),
    (ALL, r#"=FIXED(1234.5,2,TRUE)"#),
    // A space before a currency tag is text where spaces group digits (a plain `€` after
    // the space still scales by 1000); a weekday code tagged with another language;
    // `mmmmm`, the first letter of the month's name; colour words in the locale's words
    // (de-DE `[Rot]`, `[Farbe10]`; English elsewhere), another locale's refused; `A/P`.
    (ALL, r##"=TEXT(1234.5,"#.##0,00 [$€-407]")"##),
    (ALL, r##"=TEXT(1234.5,"#.##0,00 [$€]")"##),
    (ALL, r#"=TEXT(1234.5,"0,00 [$€-407]")"#),
    (ALL, r##"=TEXT(1234.5,"#.##0,00 €")"##),
    (ALL, r#"=TEXT(45728,"[$-40C]dddd")"#),
    (ALL, r#"=TEXT(45728,"[$-40C]mmmmm")"#),
    (&["de-DE", "fr-FR"], r#"=TEXT(45728,"mmmmm")"#),
    (&["et-EE"], r#"=TEXT(45728,"mmmmm yyyy")"#),
    (&["de-DE"], r#"=TEXT(-5,"0;[Red]-0")"#),
    (&["de-DE"], r#"=TEXT(-5,"[Blau]0;[Rot]-0;[Farbe10]0")"#),
    (&["fr-FR", "et-EE"], r#"=TEXT(-5,"0;[Rot]-0")"#),
    (&["fr-FR", "et-EE"], r#"=TEXT(-5,"[Blue]0;[RED]-0;[Color10]0")"#),
    (ALL, r#"=TEXT(45728.6,"h:mm A/P")"#),
    // A currency sign or a language tag beside the code (see CURRENCY_OR_TAG).
    (&["fr-FR", "et-EE"], r##"=TEXT(1234.5,"$#,##0.00")"##),
    (&["fr-FR", "et-EE"], r##"=TEXT(1234.5,"#,##0.00 [$€-407]")"##),
    (&["de-DE"], r##"=TEXT(1234.5,"[$-409]#,##0.00")"##),
    // Typed times with the locale's words for before and after noon and not en-US's where
    // it has its own (de-DE, et-EE), an hour alone, ISO 8601's `T`, a weekday's full name
    // before a date.
    (&["de-DE"], r#"=VALUE("2:30 nachm.")"#),
    (&["de-DE"], r#"=VALUE("12.03.2025 2:30 nachm.")"#),
    (&["de-DE"], r#"=VALUE("12.03.2025 2 nachm.")"#),
    (&["et-EE"], r#"=VALUE("2:30 p.l")"#),
    (&["de-DE", "et-EE"], r#"=VALUE("2:30 PM")"#),
    (&["de-DE", "et-EE"], r#"="2:30 am"+0"#),
    (&["fr-FR"], r#"=VALUE("2 pm")"#),
    (ALL, r#"=VALUE("2025-03-12T14:30")"#),
    (ALL, r#"="2025-03-12T14:30:15"+0"#),
    (&["de-DE"], r#"=VALUE("Montag, 12. März 2025")"#),
    (&["de-DE"], r#"=DATEVALUE("mittwoch 12.03.2025")"#),
    (&["fr-FR"], r#"=VALUE("mercredi 12 mars 2025")"#),
    (&["fr-FR"], r#"=VALUE("mercredi, 12 mars 2025")"#),
    (&["et-EE"], r#"=VALUE("kolmapäev, 12. märts 2025")"#),
    // The locale's boolean words and large numbers turned into text (see EXCEL_SHOWS).
    (&["de-DE"], r#"=--"WAHR""#),
    (&["fr-FR"], r#"=--"VRAI""#),
    (&["et-EE"], r#"=--"TÕENE""#),
    (ALL, r#"=1E20&"""#),
    (ALL, r#"=1234567890123456&"""#),
    (ALL, r#"=1.5E-10&"""#),
];

/// Probes where LibreOffice departs from Excel's documented value, with that value and the
/// reason (not compared with LibreOffice).
const EXCEL_VALUES: &[(&str, f64, &str)] = &[
    (
        r#"=SUM("1,5",2)"#,
        3.5,
        "text representations of numbers typed directly into the arguments are counted (Excel's SUM); \
         LibreOffice in the locale gives #VALUE!",
    ),
    (
        r#"=MAX("1,5",1)"#,
        1.5,
        "\"Logical values and text representations of numbers that you type directly into the list of \
         arguments are counted\" (Excel's MAX page); LibreOffice in the locale gives Err:504",
    ),
];

/// Probes where LibreOffice departs from Excel's documented rule and the value is text or an
/// error: Excel's value as ncsheet writes it, and the reason (not compared with LibreOffice).
const EXCEL_SHOWS: &[(&str, &str, &str)] = &[
    (r#"=--"WAHR""#, "#VALUE!", BOOLEAN_WORDS),
    (r#"=--"VRAI""#, "#VALUE!", BOOLEAN_WORDS),
    (r#"=--"TÕENE""#, "#VALUE!", BOOLEAN_WORDS),
    (r#"=TEXT(1234.5,"0.00")"#, "1.235", EN_US_BUILT_IN),
    (r##"=TEXT(1234.5,"#,##0.00")&"""##, "1.234,50000", EN_US_BUILT_IN),
    (r#"=TEXT(1234.5,"0.00E+00")"#, "001E+03", EN_US_BUILT_IN),
    (r#"=1E20&"""#, "1E+20", NUMBER_TEXT),
    (r#"=1234567890123456&"""#, "1,23456789012346E+15", NUMBER_TEXT),
    (r#"=TEXT(45728.6,"h:mm A/P")"#, "2:24 P", A_OR_P),
    (r#"=TEXT(45728,"mmmmm yyyy")"#, "m 2025", MONTH_LETTER),
    (r##"=TEXT(1234.5,"$#,##0.00")"##, "$1\u{a0}234,50", CURRENCY_OR_TAG),
    (r##"=TEXT(1234.5,"#,##0.00 [$€-407]")"##, "1\u{a0}234,50 €", CURRENCY_OR_TAG),
    (r##"=TEXT(1234.5,"[$-409]#,##0.00")"##, "1.234,50000", CURRENCY_OR_TAG),
];

/// Why fr-FR and et-EE `TEXT(1234.5,"$#,##0.00")` is `$1 234,50`, and de-DE
/// `[$-409]#,##0.00` is `1.234,50000`: a currency sign or a language tag beside a code does
/// not change how its digits are read, so each is what the bare code shows (`1 234,50`,
/// LibreOffice's own for fr-FR and et-EE `#,##0.00`, compared above; de-DE's `1.234,50000`,
/// see EN_US_BUILT_IN) with the sign or the currency added, as Microsoft's TEXT page shows
/// `$#,##0.00` as the `#,##0.00` amount after `$` (`$1,234.57`), and a tag like `[$-409]`
/// picks the language of dates' names ("Number format codes"), not the marks. LibreOffice is
/// inconsistent with itself there: the same digits read otherwise once a `$` or a tag
/// stands beside them (fr-FR and et-EE `$1234,500.00`, `1234,500.00 €`; de-DE `1,234,50000`,
/// where its `#,##0.00 [$€-407]` is `1.234,50000 €`, as ncsheet's).
const CURRENCY_OR_TAG: &str = "a sign or tag beside a code leaves its digits read as the bare code's";

/// Why `h:mm A/P` shows `2:24 P`: Excel's "Review guidelines for customizing a number
/// format" page, "If the format contains an AM or PM, the hour is based on the 12-hour
/// clock, where "AM" or "A" indicates times from midnight until noon and "PM" or "P"
/// indicates times from noon until midnight" (its table: `h:mm:ss A/P` shows `4:36:03 P`);
/// the code's case is kept. LibreOffice set to de-DE, fr-FR or et-EE shows `2:24 p`.
const A_OR_P: &str = "A/P shows A or P as the code writes it in Excel; LibreOffice shows it lowercase";

/// Why et-EE `mmmmm` is `m` for March (`märts`): the same Excel page, "mmmmm: Display the
/// month as the first letter of the month"; LibreOffice set to et-EE shows `III` (a Roman
/// numeral of its own), while it shows the name's first letter in de-DE (`M`) and fr-FR (`m`).
const MONTH_LETTER: &str = "mmmmm is the month name's first letter in Excel; LibreOffice in et-EE shows III";

/// Why `--"WAHR"` is #VALUE!: Excel's VALUE page, "Text can be in any of the constant number,
/// date, or time formats recognized by Microsoft Excel. If text is not in one of these
/// formats, VALUE returns the #VALUE! error value", and arithmetic on text converts it the
/// same way (en-US `--"TRUE"` is #VALUE!, docs/functions.md). LibreOffice reads its boolean
/// words as numbers in every locale (en-US `--"TRUE"` is 1 there).
const BOOLEAN_WORDS: &str = "a boolean word is no number format: #VALUE! in Excel, 1 in LibreOffice";

/// Why de-DE `TEXT(1234.5,"0.00")` is `1.235`: German Excel reads TEXT's code in its own
/// marks, where `.` groups thousands (poi's 61495-test.xlsm cached `0.067` for
/// `TEXT(67.1,"00.00")`, text_codes_compute_as_the_comma_locale_excel_that_saved_them);
/// LibreOffice reads a code that is exactly one of its en-US built-in formats (`0.00`,
/// `#,##0`, `#,##0.00`, `0.00%`, `0.00E+00`) as en-US (`1,235`, `1.234,50`, `1,23E+03`), and
/// any other code (`0.0`, `##0.00`, `$#,##0.00`) in the locale. ncsheet reads them all in
/// de-DE's marks, as the German Excel that saved 61495 did: `#,##0.00` is `#` and the decimal
/// comma, then `##0.00` grouped (`1.234,50000`, as LibreOffice in de-DE shows the same code
/// with a language tag, `#,##0.00 [$€-407]`), and `0.00E+00` three grouped integer places
/// (`001E+03`). No contrary evidence was found (session 15).
const EN_US_BUILT_IN: &str = "an en-US built-in code: read in the locale by Excel, as en-US by LibreOffice";

/// Why `1E20&""` is `1E+20`: a number joined to text is written as Excel's General format
/// writes it, with Excel's 15 digits of precision ("Excel specifications and limits") and a
/// two-digit exponent (the "Display numbers in scientific (exponential) notation" page shows
/// 12345678901 as 1.23E+10); LibreOffice writes up to 17 digits and a three-digit exponent
/// (`1E+020`, `1234567890123456`) in every locale, en-US too.
const NUMBER_TEXT: &str = "Excel writes 15 digits and a two-digit exponent; LibreOffice 17 and three";

const ALL: &[&str] = &["de-DE", "fr-FR", "et-EE"];

/// Probes whose shown text LibreOffice gives otherwise than Excel while the value is the
/// same (the values are still compared), and why.
const SHOWN_DIFFERS: &[(&str, &str)] = &[
    (
        r#"=TIMEVALUE("12.03.2025 14:30")"#,
        "LibreOffice subtracts the day and keeps 0.604166666664241; Excel's time is 14.5/24 (0.604166666666667)",
    ),
    (r#"=DATE(2025,3,12)+"0,5""#, "LibreOffice gives the sum a date format of its own; Excel keeps General"),
];

/// A value LibreOffice cached as ncsheet's [`Value`] compares: LibreOffice's own error codes
/// (`Err:502`, an invalid argument) are `#VALUE!` in Excel.
fn same_probe_value(ours: &ncsheet::eval::Value, theirs: &ncsheet::eval::Value) -> bool {
    use ncsheet::eval::Value;
    match (ours, theirs) {
        (Value::Number(a), Value::Number(b)) => (a - b).abs() <= 1e-9 * a.abs().max(b.abs()),
        (Value::Error(_), Value::Error(_)) => ours == theirs,
        (Value::Error(ncsheet::eval::XlError::Value), Value::Text(t)) => t.starts_with("Err:"),
        _ => ours == theirs,
    }
}

/// LibreOffice set to each locale recalculates the probes: the values it saves (an xlsx,
/// read back) and the text it shows (a `;` csv) are ncsheet's under `--locale`, but for the
/// shown text of [`SHOWN_DIFFERS`] and the Excel values of [`EXCEL_VALUES`].
#[test]
fn values_and_shown_text_of_probes_are_libreoffice_s() {
    let Some(soffice) = common::soffice() else { return };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for locale in ALL {
        let probes: Vec<&str> = VALUE_PROBES.iter().filter(|(at, _)| at.contains(locale)).map(|(_, p)| *p).collect();
        let stem = format!("values-{locale}");
        let fields: Vec<String> = probes.iter().map(|p| format!("\"{}\"", p.replace('"', "\"\""))).collect();
        std::fs::write(d.join(format!("{stem}.csv")), format!("{}\n", fields.join(","))).unwrap();
        let xlsx = format!("{stem}.xlsx");
        ok(in_dir(d, &["set", &format!("{stem}.csv"), "--delimiter", ",", "--locale", "en-US", "A2=1", "-o", &xlsx]));
        // LibreOffice's values: the workbook it recalculated in the locale and saved.
        let saved = d.join(format!("lo-xlsx-{locale}"));
        libreoffice_converts(&soffice, d, locale, &[], "xlsx", &saved, &d.join(&xlsx));
        let mut theirs = calamine::open_workbook::<calamine::Xlsx<_>, _>(saved.join(&xlsx)).unwrap();
        let theirs = common::excel_oracle::read_sheet(&mut theirs, "Sheet1").expect("LibreOffice's sheet");
        let mut settings = ncsheet::eval::Settings::default();
        settings.locale = ncsheet::eval::Locale::from_tag(locale).unwrap();
        let path = d.join(&xlsx);
        let options =
            ncsheet::document::OpenOptions { settings: Some(settings), ..ncsheet::document::OpenOptions::named(&path) };
        let doc = ncsheet::document::Document::open_file(&path, &options).unwrap();
        let (ours_shown, theirs_shown) = ours_and_libreoffice(&soffice, d, &stem, locale);
        for (i, probe) in probes.iter().enumerate() {
            let ours = doc.workbook().value(0, ncsheet::formula::address::Pos::new(0, i as u32));
            if let Some((_, excel, why)) = EXCEL_VALUES.iter().find(|(p, _, _)| p == probe) {
                assert_eq!(ours, ncsheet::eval::Value::Number(*excel), "{locale}: {probe}: {why}");
                continue;
            }
            if let Some((_, excel, why)) = EXCEL_SHOWS.iter().find(|(p, _, _)| p == probe) {
                assert_eq!(ours.to_string(), *excel, "{locale}: {probe}: {why}");
                continue;
            }
            let cached = theirs.values.get(&(0, i as u32)).cloned().unwrap_or(ncsheet::eval::Value::Blank);
            assert!(same_probe_value(&ours, &cached), "{locale}: {probe}: ncsheet {ours:?}, LibreOffice {cached:?}");
            if SHOWN_DIFFERS.iter().any(|(p, _)| p == probe) {
                continue;
            }
            let shown = ours_shown[i].strip_prefix('\'').unwrap_or(&ours_shown[i]);
            assert_eq!(shown, as_excel_error(&theirs_shown[i]), "{locale}: {probe} (shown)");
        }
    }
}

/// A workbook a decimal-comma Excel saved (poi's 61495-test.xlsm, whose grouping mark was
/// `.`): the TEXT results it cached are what ncsheet computes under de-DE, where `.` groups
/// and `,` is the decimal mark (`TEXT(67.1,"00.00")` is `0.067`, `TEXT(68.2,"00,00")` is
/// `68,20`); under en-US the second is `0,068` (docs/excel-conformance.md lists it).
#[test]
fn text_codes_compute_as_the_comma_locale_excel_that_saved_them() {
    let file = common::corpus::public_path().join("poi/test-data_spreadsheet_61495-test.xlsm");
    if !file.exists() {
        assert!(std::env::var_os("CI").is_none(), "{} not found", file.display());
        return;
    }
    let mut cached = calamine::open_workbook::<calamine::Xlsx<_>, _>(&file).unwrap();
    let cached = common::excel_oracle::read_sheet(&mut cached, "TEST").expect("sheet TEST");
    let excel: Vec<String> = [(0, 1), (1, 1)].iter().map(|at| cached.values[at].to_string()).collect();
    assert_eq!(excel, ["D 0.067", "D 68,20"]);
    let run =
        ok(ncsheet(&["eval", file.to_str().unwrap(), "--locale", "de-DE", "--format", "json", "TEST!B1", "TEST!B2"]));
    assert_eq!(run.stdout.trim(), format!(r#"{{"TEST!B1": "{}", "TEST!B2": "{}"}}"#, excel[0], excel[1]));
}
