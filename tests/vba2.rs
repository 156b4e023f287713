//! VBA projects and macros nobody here wrote: protected projects ([MS-OVBA] 2.3.1.15-17),
//! modules exported by the VBA editor in its ANSI code page, class modules, and the errors of
//! Excel's object model. Oracles: [MS-OVBA] and [MS-VBAL], olevba's reading of the files.

mod common;

use std::path::{Path, PathBuf};

use common::vba::{olevba, with_stream, xlsm_with_project};

use ncsheet::vba::project::read_project;

fn corpus(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/excel-corpus/public").join(file)
}

const SIMPLE: &str = "poi/test-data_spreadsheet_SimpleMacro.xlsm";
/// Saved by Excel with a VBA project password (its DPB line holds a password hash).
const WITH_PASSWORD: &str = "poi/test-data_spreadsheet_mv-calculator-final-2-20-2013.xlsm";

fn chamfer_bas() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("sheets/chamfer.bas")
}

fn ncsheet(args: &[&str]) -> common::cli::Run {
    common::cli::ncsheet(args)
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn vba_bytes(file: &Path) -> Vec<u8> {
    ncsheet::io::open(file).unwrap().layout.unwrap().vba_project.unwrap()
}

fn stream_of(bytes: &[u8], path: &str) -> Vec<u8> {
    let mut cfb = cfb::CompoundFile::open(std::io::Cursor::new(bytes.to_vec())).unwrap();
    let mut data = Vec::new();
    std::io::Read::read_to_end(&mut cfb.open_stream(path).unwrap(), &mut data).unwrap();
    data
}

/// Data Encryption of [MS-OVBA] 2.4.3.2, written here from the specification: the seed,
/// the encrypted version (2) and project key (the sum of the bytes of the project's ID),
/// `(seed & 6) / 2` ignored bytes of value 7, the length (4 bytes) and the data.
fn spec_encrypt(data: &[u8], seed: u8, project_id: &str) -> String {
    let key = project_id.bytes().fold(0u8, |a, b| a.wrapping_add(b));
    let (version_enc, key_enc) = (seed ^ 2, seed ^ key);
    let mut out = vec![seed, version_enc, key_enc];
    let (mut unencrypted1, mut encrypted1, mut encrypted2) = (key, key_enc, version_enc);
    let ignored = std::iter::repeat_n(7u8, usize::from((seed & 6) / 2));
    let length = (data.len() as u32).to_le_bytes();
    for byte in ignored.chain(length).chain(data.iter().copied()) {
        let enc = byte ^ encrypted2.wrapping_add(unencrypted1);
        out.push(enc);
        (encrypted2, encrypted1, unencrypted1) = (encrypted1, enc, byte);
    }
    out.iter().map(|b| format!("{b:02X}")).collect()
}

/// Data Decryption of [MS-OVBA] 2.4.3.3, written here from the specification.
fn spec_decrypt(hex: &str) -> Vec<u8> {
    let bytes: Vec<u8> = (0..hex.len()).step_by(2).map(|i| u8::from_str_radix(&hex[i..i + 2], 16).unwrap()).collect();
    let (seed, version_enc, key_enc) = (bytes[0], bytes[1], bytes[2]);
    let (mut unencrypted1, mut encrypted1, mut encrypted2) = (seed ^ key_enc, key_enc, version_enc);
    let mut plain = Vec::new();
    for &enc in &bytes[3..] {
        let byte = enc ^ encrypted2.wrapping_add(unencrypted1);
        plain.push(byte);
        (encrypted2, encrypted1, unencrypted1) = (encrypted1, enc, byte);
    }
    let ignored = usize::from((seed & 6) / 2);
    let length = u32::from_le_bytes(plain[ignored..ignored + 4].try_into().unwrap()) as usize;
    assert_eq!(plain.len(), ignored + 4 + length, "{hex}");
    plain[ignored + 4..].to_vec()
}

/// The PROJECT stream's `key="value"` value.
fn project_value(text: &str, key: &str) -> String {
    let line = text.lines().find(|l| l.starts_with(&format!("{key}="))).unwrap();
    line[key.len() + 1..].trim_matches('"').to_string()
}

/// (CMG, DPB, GC) of a vbaProject.bin, decrypted.
fn protection_fields(bytes: &[u8]) -> (Vec<u8>, Vec<u8>, Vec<u8>) {
    let text = String::from_utf8_lossy(&stream_of(bytes, "/PROJECT")).into_owned();
    let field = |k| spec_decrypt(&project_value(&text, k));
    (field("CMG"), field("DPB"), field("GC"))
}

/// SimpleMacro's project locked for viewing with a password, as the VBA editor's "Lock project
/// for viewing" stores it: protected by the user (CMG bit fUserProtected), a password (a
/// 29-byte PasswordHash, 2.3.1.16, in DPB) and not visible (GC 0x00).
fn locked_simple_macro(out: &Path) {
    let file = corpus(SIMPLE);
    let bytes = with_stream(&vba_bytes(&file), "/PROJECT", |old| {
        let text = String::from_utf8_lossy(old).into_owned();
        let id = project_value(&text, "ID");
        let mut hash = vec![0xFF, 0x20, 0x00, 0x00];
        hash.extend((1..=24).map(|i| i * 7));
        hash.push(0);
        let fields = [
            ("CMG", spec_encrypt(&[1, 0, 0, 0], 0x31, &id)),
            ("DPB", spec_encrypt(&hash, 0x42, &id)),
            ("GC", spec_encrypt(&[0], 0x53, &id)),
        ];
        let mut new = String::new();
        for line in text.split_inclusive("\r\n") {
            match fields.iter().find(|(k, _)| line.starts_with(&format!("{k}="))) {
                Some((k, v)) => new += &format!("{k}=\"{v}\"\r\n"),
                None => new += line,
            }
        }
        new.into_bytes()
    });
    xlsm_with_project(&file, &bytes, out);
}

/// Importing a module into a project with a password, or one locked for viewing, is refused
/// naming the protection, and writes nothing; with --unprotect the project is written with
/// CMG 0, no password (DPB 0x00) and visible (GC 0xFF), its modules as olevba read them.
#[test]
fn importing_into_a_protected_project_is_refused_unless_unprotected() {
    let dir = tempfile::tempdir().unwrap();
    let locked = dir.path().join("locked.xlsm");
    locked_simple_macro(&locked);
    let bas = chamfer_bas();
    for (book, says) in [(corpus(WITH_PASSWORD), "has a password"), (locked.clone(), "is locked for viewing")] {
        let out = dir.path().join("out.xlsm");
        let args = ["macros", path(&book), "--import", path(&bas), "-o", path(&out)];
        let refused = ncsheet(&args);
        assert!(refused.code != 0, "{}", book.display());
        assert!(refused.stderr.contains(says) && refused.stderr.contains("PROJECT"), "{}", refused.stderr);
        assert!(refused.stderr.contains("--unprotect"), "{}", refused.stderr);
        assert!(!out.exists(), "{}: written", book.display());

        let done = ncsheet(&[&args[..], &["--unprotect"]].concat());
        assert_eq!(done.code, 0, "{}: {}", book.display(), done.stderr);
        let (cmg, dpb, gc) = protection_fields(&vba_bytes(&out));
        assert_eq!((cmg, dpb, gc), (vec![0, 0, 0, 0], vec![0], vec![0xFF]), "{}", book.display());
        if let (Some(mut after), Some(before)) = (olevba(&out), olevba(&book)) {
            assert!(after.remove("VBA/Chamfer").is_some(), "{}", book.display());
            assert!(after == before, "{}: olevba reads the old modules differently", book.display());
        }
        std::fs::remove_file(&out).unwrap();
    }
}

/// A locked project still stores its source: it is listed, exported as olevba reads it, and
/// its macro runs (SimpleMacro's TestMacro writes its text into the saved active cell, C4).
#[test]
fn a_locked_project_is_still_listed_exported_and_run() {
    let dir = tempfile::tempdir().unwrap();
    let locked = dir.path().join("locked.xlsm");
    locked_simple_macro(&locked);
    let (cmg, dpb, gc) = protection_fields(&vba_bytes(&locked));
    assert_eq!((cmg[0], dpb.len(), gc), (1, 29, vec![0]), "the test's project is locked");

    let listed = ncsheet(&["macros", path(&locked)]);
    assert_eq!(listed.code, 0, "{}", listed.stderr);
    assert!(listed.stdout.contains("Sub TestMacro()"), "{}", listed.stdout);
    assert!(listed.stderr.contains("locked for viewing"), "{}", listed.stderr);

    let export = dir.path().join("export");
    let exported = ncsheet(&["macros", path(&locked), "--export", path(&export)]);
    assert_eq!(exported.code, 0, "{}", exported.stderr);
    if let Some(theirs) = olevba(&locked) {
        let module1 = std::fs::read_to_string(export.join("Module1.bas")).unwrap();
        assert!(theirs["VBA/Module1"] == module1, "the export differs from olevba's reading");
    }

    let saved = dir.path().join("after.xlsx");
    let ran = ncsheet(&["run", path(&locked), "--sub", "Module1.TestMacro", "--save", path(&saved)]);
    assert_eq!(ran.code, 0, "{}", ran.stderr);
    let after = ncsheet::io::open(&saved).unwrap().workbook;
    let c4 = ncsheet::formula::address::parse_cell("C4").unwrap();
    assert_eq!(after.input(0, c4).as_deref(), Some("This is a macro workbook"));
    assert!(read_project(&vba_bytes(&locked)).unwrap().protection.unwrap().locked_for_viewing);
}

/// A module the VBA editor exported in Windows-1252: "Ø" 0xD8, "é" 0xE9, "–" 0x96, "°" 0xB0
/// (the code page's chart). The bytes are written here, not typed, so that no editor recodes them.
fn ansi_module(name: &str) -> Vec<u8> {
    let mut bas = format!("Attribute VB_Name = \"{name}\"\r\nSub Label()\r\n    ' Fase 45").into_bytes();
    bas.extend(b"\xB0 \x96 caf\xE9\r\n    Range(\"A1\").Value = \"\xD8 40 \x96 caf\xE9\"\r\nEnd Sub\r\n");
    bas
}

const ANSI_TEXT: &str =
    "Sub Label()\r\n    ' Fase 45° – café\r\n    Range(\"A1\").Value = \"Ø 40 – café\"\r\nEnd Sub\r\n";

/// An ANSI .bas is imported into an Excel project (code page 1252, which its CODEPAGE record
/// says) and into a new one (with --code-page 1252: the file does not say its code page), and
/// olevba reads the module back as the characters the bytes stand for; `run` reads the same
/// file and writes its text into A1.
#[test]
fn a_module_exported_in_the_ansi_code_page_is_imported_and_run() {
    let dir = tempfile::tempdir().unwrap();
    let bas = dir.path().join("Label.bas");
    std::fs::write(&bas, ansi_module("Label")).unwrap();
    let want = format!("Attribute VB_Name = \"Label\"\r\n{ANSI_TEXT}");
    let chamfer_xlsx = Path::new(env!("CARGO_MANIFEST_DIR")).join("sheets/chamfer.xlsx");
    for (n, book) in [corpus(SIMPLE), chamfer_xlsx].iter().enumerate() {
        let out = dir.path().join(format!("out{n}.xlsm"));
        let done = ncsheet(&["macros", path(book), "--import", path(&bas), "--code-page", "1252", "-o", path(&out)]);
        assert_eq!(done.code, 0, "{}: {}", book.display(), done.stderr);
        let project = read_project(&vba_bytes(&out)).unwrap();
        assert_eq!(project.code_page, 1252);
        let label = project.modules.iter().find(|m| m.name == "Label").unwrap();
        assert!(label.source == want, "{}: {:?}", book.display(), label.source);
        if let Some(theirs) = olevba(&out) {
            assert!(theirs["VBA/Label"] == want, "{}: olevba reads {:?}", book.display(), theirs["VBA/Label"]);
        }
    }
    let csv = dir.path().join("book.csv");
    std::fs::write(&csv, "x\n").unwrap();
    let saved = dir.path().join("after.csv");
    let ran =
        ncsheet(&["run", path(&csv), path(&bas), "--code-page", "1252", "--sub", "Label", "--save", path(&saved)]);
    assert_eq!(ran.code, 0, "{}", ran.stderr);
    assert_eq!(std::fs::read_to_string(&saved).unwrap().lines().next(), Some("Ø 40 – café"));
}

/// A .bas read in Windows-1252 (named: without it, the code page would be guessed, and a lone
/// 0x81 then starts a Shift_JIS character) with a byte 1252 leaves undefined (0x81), or a
/// UTF-8 file (byte-order mark, which wins over the code page) with a stray ANSI byte, is
/// refused at its line and column, by import and by run.
#[test]
fn undecodable_module_bytes_are_refused_at_their_place() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&[u8], &str); 2] = [
        (b"Sub A()\r\n    x = \"a\x81b\"\r\nEnd Sub\r\n", ":2:11: "),
        (b"\xEF\xBB\xBFSub A()\r\n' caf\xE9\r\nEnd Sub\r\n", ":2:6: "),
    ];
    for (n, (bytes, place)) in cases.iter().enumerate() {
        let bas = dir.path().join(format!("M{n}.bas"));
        std::fs::write(&bas, bytes).unwrap();
        let out = dir.path().join("out.xlsm");
        let import = ncsheet(&[
            "macros",
            path(&corpus(SIMPLE)),
            "--import",
            path(&bas),
            "--code-page",
            "1252",
            "-o",
            path(&out),
        ]);
        assert!(import.code != 0 && import.stderr.contains(&format!("M{n}.bas{place}")), "{}", import.stderr);
        assert!(!out.exists());
        let csv = dir.path().join("book.csv");
        std::fs::write(&csv, "x\n").unwrap();
        let ran = ncsheet(&["run", path(&csv), path(&bas), "--code-page", "1252"]);
        assert!(ran.code != 0 && ran.stderr.contains(&format!("M{n}.bas{place}")), "{}", ran.stderr);
    }
}

/// A class module as the VBA editor exports it (File > Export): the VERSION header and its
/// BEGIN … END block, then the Attribute lines the editor stores with the source.
const TOOL_CLS: &str = "VERSION 1.0 CLASS\r\nBEGIN\r\n  MultiUse = -1  'True\r\nEND\r\n";
const TOOL_SOURCE: &str = "Attribute VB_Name = \"Tool\"\r\nAttribute VB_GlobalNameSpace = False\r\n\
    Attribute VB_Creatable = False\r\nAttribute VB_PredeclaredId = False\r\nAttribute VB_Exposed = False\r\n\
    Private mD As Double\r\nPublic Property Get Diameter() As Double\r\n    Diameter = mD\r\nEnd Property\r\n\
    Public Property Let Diameter(v As Double)\r\n    mD = v\r\nEnd Property\r\n";

/// A .cls imports as a class module: the PROJECT stream lists it as `Class=Tool` ([MS-OVBA]
/// 2.3.1.6), olevba reads its source without the export header, and `macros` lists it as a
/// .cls. Code of the project makes objects of it ("Property Let statement": `t.Diameter = 40`
/// runs the Let, reading it the Get); a procedure of the class run on its own is refused by
/// name, as it needs an object.
#[test]
fn a_class_module_imports_and_the_project_uses_it() {
    let dir = tempfile::tempdir().unwrap();
    let cls = dir.path().join("Tool.cls");
    std::fs::write(&cls, format!("{TOOL_CLS}{TOOL_SOURCE}")).unwrap();
    let bas = dir.path().join("UseTool.bas");
    let use_tool = "Attribute VB_Name = \"UseTool\"\r\nSub Main()\r\n    Dim t As New Tool\r\n    t.Diameter = 40\r\n    Debug.Print t.Diameter * 2\r\nEnd Sub\r\n";
    std::fs::write(&bas, use_tool).unwrap();
    let out = dir.path().join("out.xlsm");
    let done =
        ncsheet(&["macros", path(&corpus(SIMPLE)), "--import", path(&cls), "--import", path(&bas), "-o", path(&out)]);
    assert_eq!(done.code, 0, "{}", done.stderr);

    let bytes = vba_bytes(&out);
    let project_text = String::from_utf8_lossy(&stream_of(&bytes, "/PROJECT")).into_owned();
    assert!(project_text.lines().any(|l| l == "Class=Tool"), "{project_text}");
    assert!(project_text.lines().any(|l| l == "Module=UseTool"), "{project_text}");
    let project = read_project(&bytes).unwrap();
    let tool = project.modules.iter().find(|m| m.name == "Tool").unwrap();
    assert_eq!(tool.kind, ncsheet::vba::project::ModuleKind::Class);
    assert!(tool.source == TOOL_SOURCE, "{:?}", tool.source);
    if let Some(theirs) = olevba(&out) {
        assert!(theirs["VBA/Tool"] == TOOL_SOURCE, "olevba reads {:?}", theirs["VBA/Tool"]);
        assert!(theirs["VBA/UseTool"] == use_tool);
    }
    let listed = ncsheet(&["macros", path(&out)]);
    assert!(listed.stdout.contains("Tool (cls)\n  Public Property Get Diameter() As Double"), "{}", listed.stdout);

    let ran = ncsheet(&["run", path(&out), "--sub", "UseTool.Main"]);
    assert_eq!(ran.code, 0, "{}", ran.stderr);
    assert!(ran.stderr.lines().any(|l| l == " 80 "), "{}", ran.stderr);
    // The same modules as files: the .bas run, the .cls given with --module.
    let ran = ncsheet(&["run", path(&corpus(SIMPLE)), path(&bas), "--module", path(&cls)]);
    assert_eq!(ran.code, 0, "{}", ran.stderr);
    assert!(ran.stderr.lines().any(|l| l == " 80 "), "{}", ran.stderr);
    let ran = ncsheet(&["run", path(&out), "--sub", "Tool.Diameter"]);
    assert!(ran.code != 0 && ran.stderr.contains("Tool is a class"), "{}", ran.stderr);
}

/// A UserForm (.frm) and a sheet's document module (.cls with VB_Base) are refused by name.
#[test]
fn forms_and_document_modules_are_not_imported() {
    let dir = tempfile::tempdir().unwrap();
    let frm = dir.path().join("UserForm1.frm");
    std::fs::write(&frm, "VERSION 5.00\r\nBegin {C62A69F0-16DC-11CE-9E98-00AA00574A4F} UserForm1\r\nEnd\r\n").unwrap();
    let sheet = dir.path().join("Sheet9.cls");
    std::fs::write(
        &sheet,
        format!("{TOOL_CLS}Attribute VB_Name = \"Sheet9\"\r\nAttribute VB_Base = \"0{{00020820-0000-0000-C000-000000000046}}\"\r\n"),
    )
    .unwrap();
    for (file, says) in [(frm, "UserForm"), (sheet, "document module")] {
        let out = dir.path().join("out.xlsm");
        let refused = ncsheet(&["macros", path(&corpus(SIMPLE)), "--import", path(&file), "-o", path(&out)]);
        assert!(refused.code != 0 && refused.stderr.contains(says), "{}", refused.stderr);
        assert!(!out.exists());
    }
}

/// Runs `source` (a .bas) on `book`, saving the workbook as `saved`.
fn run_bas(dir: &Path, book: &Path, source: &str, saved: &Path) -> common::cli::Run {
    let bas = dir.join("m.bas");
    std::fs::write(&bas, source).unwrap();
    ncsheet(&["run", path(book), path(&bas), "--save", path(saved)])
}

/// Excel's object-model errors, numbered as VBA numbers them ("Subscript out of range
/// (Error 9)" in the VBA reference; 1004 for a method that fails, as selecting on a hidden
/// sheet does): untrapped, an error at the module's line and column; trapped, `Err.Number`
/// and `Err.Description` as VBA gives them.
#[test]
fn excel_object_model_errors_carry_vbas_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let book = Path::new(env!("CARGO_MANIFEST_DIR")).join("sheets/chamfer.xlsx");
    let saved = dir.path().join("after.xlsx");
    let untrapped = [
        (
            "Sub Main()\r\n    Worksheets(\"NoSuch\").Range(\"A1\").Value = 1\r\nEnd Sub\r\n",
            "m.bas:2:5: ",
            "run-time error 9",
        ),
        ("Sub Main()\r\n    x = Worksheets(99).Name\r\nEnd Sub\r\n", "m.bas:2:9: ", "run-time error 9"),
        (
            "Sub Main()\r\n    Worksheets(2).Visible = False\r\n    Worksheets(2).Range(\"A1\").Select\r\nEnd Sub\r\n",
            "m.bas:3:31: ",
            "Select method of Range class failed (run-time error 1004)",
        ),
        (
            "Sub Main()\r\n    Worksheets(2).Visible = False\r\n    Worksheets(2).Select\r\nEnd Sub\r\n",
            "m.bas:3:19: ",
            "Select method of Worksheet class failed (run-time error 1004)",
        ),
    ];
    for (source, place, says) in untrapped {
        let ran = run_bas(dir.path(), &book, source, &saved);
        assert!(ran.code != 0 && ran.stderr.contains(place) && ran.stderr.contains(says), "{source}\n{}", ran.stderr);
    }
    let trapped = "Sub Main()\r\n    On Error Resume Next\r\n    Worksheets(\"NoSuch\").Range(\"A1\").Value = 1\r\n\
                   Worksheets(1).Range(\"H1\").Value = Err.Number\r\n    Worksheets(1).Range(\"H2\").Value = Err.Description\r\n\
                   Err.Clear\r\n    Worksheets(2).Visible = False\r\n    Worksheets(2).Range(\"A1\").Select\r\n\
                   Worksheets(1).Range(\"H3\").Value = Err.Number\r\nEnd Sub\r\n";
    let ran = run_bas(dir.path(), &book, trapped, &saved);
    assert_eq!(ran.code, 0, "{}", ran.stderr);
    let after = ncsheet::io::open(&saved).unwrap().workbook;
    let at = |a1| after.input(0, ncsheet::formula::address::parse_cell(a1).unwrap());
    assert_eq!(
        (at("H1"), at("H2"), at("H3")),
        (Some("9".into()), Some("Subscript out of range".into()), Some("1004".into()))
    );
}

/// `Columns("A:C").Copy Range("E1")` pastes whole columns as Excel does: every cell of E:G
/// becomes its source's (formulas moved by 4 columns, =A3+B3 becoming =E3+F3), so a cell of
/// G far below the data is blanked; `Rows("2:3").Copy Range("A6")` likewise for rows. Only
/// the used area is visited, not the three million cells of three whole columns.
#[test]
fn whole_columns_and_rows_copy_through_the_used_area() {
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("book.csv");
    let mut csv = String::from("a,b,c\n1,2,3\n4,5,=A3+B3\n");
    csv += &",\n".repeat(6);
    csv += ",,,,,,old\n";
    std::fs::write(&book, csv).unwrap();
    let saved = dir.path().join("after.csv");
    let source =
        "Sub Main()\r\n    Columns(\"A:C\").Copy Range(\"E1\")\r\n    Rows(\"2:3\").Copy Range(\"A12\")\r\nEnd Sub\r\n";
    let ran = run_bas(dir.path(), &book, source, &saved);
    assert_eq!(ran.code, 0, "{}", ran.stderr);
    let after = ncsheet::io::open(&saved).unwrap().workbook;
    let at = |a1| after.input(0, ncsheet::formula::address::parse_cell(a1).unwrap()).unwrap_or_default();
    assert_eq!([at("E1"), at("F2"), at("G3"), at("G10")], ["a", "2", "=E3+F3", ""]);
    assert_eq!([at("A12"), at("C13"), at("G13"), at("A14")], ["1", "=A13+B13", "=E13+F13", ""]);
}
