//! How cells look, between a file and a macro, through the one `Document` both front ends
//! run macros on: a macro sees the formatting a file was written with (alignment, bold,
//! italic, wrap, a solid fill, a row's height), and what a macro formats reaches the saved
//! file, read back by an outside reader.
//!
//! The books are written and read by openpyxl (`.ci/run` installs it), which spells the
//! styles as ECMA-376 lays them out (`styles.xml` `cellXfs`, `fonts`, `fills`, `numFmts`;
//! the sheet's `<col width>` and `<row ht customHeight>`). Expected values in the macro's
//! terms are Microsoft's Excel VBA reference: "XlHAlign enumeration" (xlCenter -4108,
//! xlRight -4152), "XlVAlign enumeration" (xlTop -4160), "Interior.Color property" (an RGB
//! value, red in the low byte: RGB(255, 0, 0) is 255), "Range.RowHeight property" (points).

mod common;

use std::process::Command;

use common::openpyxl::{openpyxl_available, python};
use ncsheet::document::{Document, OpenOptions};
use ncsheet::vba::RunOptions;

/// The book `script` writes, opened: its folder (kept while the test runs) and document.
fn book_by_openpyxl(script: &str) -> (tempfile::TempDir, Document) {
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("book.xlsx");
    python(script, &[&book]);
    let doc = Document::open_file(&book, &OpenOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    (dir, doc)
}

fn run(doc: &mut Document, body: &str) -> Vec<String> {
    let src = format!("Sub Main()\n{body}\nEnd Sub\n");
    doc.run_macro(&src, "looks.bas", RunOptions::default()).unwrap_or_else(|e| panic!("{e}")).printed
}

/// openpyxl's book: A1 bold, B1 italic and centred, C1 filled solid red, D1 top-aligned
/// and wrapped, E1 right-aligned; row 3 30 points high.
const WRITE_FORMATTED: &str = r#"
import sys
from openpyxl import Workbook
from openpyxl.styles import Alignment, Font, PatternFill
wb = Workbook()
ws = wb.active
for col, v in zip("ABCDE", [1, 2, 3, 4, 5]):
    ws[col + "1"] = v
ws["A1"].font = Font(bold=True)
ws["B1"].font = Font(italic=True)
ws["B1"].alignment = Alignment(horizontal="center")
ws["C1"].fill = PatternFill(fill_type="solid", fgColor="FFFF0000")
ws["D1"].alignment = Alignment(vertical="top", wrap_text=True)
ws["E1"].alignment = Alignment(horizontal="right")
ws["A3"] = "tall"
ws.row_dimensions[3].height = 30
wb.save(sys.argv[1])
"#;

#[test]
fn a_macro_reads_the_formatting_the_file_was_written_with() {
    if !openpyxl_available() {
        return;
    }
    let (_dir, mut doc) = book_by_openpyxl(WRITE_FORMATTED);
    let printed = run(
        &mut doc,
        "    Debug.Print Range(\"A1\").Font.Bold & \"|\" & Range(\"B1\").Font.Bold & \"|\" & Range(\"B1\").Font.Italic\n\
         \x20   Debug.Print Range(\"B1\").HorizontalAlignment & \"|\" & Range(\"E1\").HorizontalAlignment\n\
         \x20   Debug.Print Range(\"C1\").Interior.Color & \"|\" & Range(\"A1\").Interior.Color\n\
         \x20   Debug.Print Range(\"D1\").VerticalAlignment & \"|\" & Range(\"D1\").WrapText & \"|\" & Range(\"A1\").WrapText\n\
         \x20   Debug.Print Rows(3).RowHeight & \"|\" & Rows(2).RowHeight",
    );
    // A cell without fill answers white (16777215); an unsized row Excel's standard 15.
    assert_eq!(printed, ["True|False|True", "-4108|-4152", "255|16777215", "-4160|True|False", "30|15"]);
}

/// Reads back what the macro below formatted, one `name=value` a line.
const READ_FORMATTED: &str = r#"
import sys
from openpyxl import load_workbook
ws = load_workbook(sys.argv[1]).active
a1, b2 = ws["A1"], ws["B2"]
print("format=" + a1.number_format)
print("bold=" + str(bool(a1.font.b)))
print("fill=" + b2.fill.fill_type + ":" + str(b2.fill.fgColor.rgb))
print("width=%.2f" % ws.column_dimensions["C"].width)
print("height=%.2f" % ws.row_dimensions[4].height)
"#;

/// What the macro sets: A1 `0.000` and bold, B2 filled RGB(0, 128, 255), column C 20
/// characters wide, row 4 30 points high.
const FORMAT: &str = "    Range(\"A1\").Value = 1.5\n    Range(\"B2\").Value = 2\n\
     \x20   Range(\"A1\").NumberFormat = \"0.000\"\n    Range(\"A1\").Font.Bold = True\n\
     \x20   Range(\"B2\").Interior.Color = RGB(0, 128, 255)\n\
     \x20   Columns(\"C\").ColumnWidth = 20\n    Rows(4).RowHeight = 30";

/// RGB(0, 128, 255) as the file spells a colour: ARGB, red first.
const EXPECTED: &[&str] = &["format=0.000", "bold=True", "fill=solid:FF0080FF", "width=20.00", "height=30.00"];

#[test]
fn a_macro_run_on_the_document_formats_the_workbook_it_saves_anew() {
    if !openpyxl_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Document::open(b"x\n".to_vec(), &OpenOptions::named("plain.csv")).unwrap();
    run(&mut doc, FORMAT);
    let saved = dir.path().join("saved.xlsx");
    let encoded = doc.encode(&saved).unwrap();
    std::fs::write(&saved, encoded.bytes()).unwrap();
    let read = python(READ_FORMATTED, &[&saved]);
    assert_eq!(read.lines().collect::<Vec<_>>(), EXPECTED);
}

/// Reads back A1's bold, B1's italic and C1's fill of a rewritten book.
const READ_REWRITTEN: &str = r#"
import sys
from openpyxl import load_workbook
ws = load_workbook(sys.argv[1]).active
print("A1 bold=" + str(bool(ws["A1"].font.b)))
print("B1 italic=" + str(bool(ws["B1"].font.i)))
print("C1 fill=" + str(ws["C1"].fill.fgColor.rgb))
"#;

#[test]
fn a_package_written_anew_keeps_the_files_styles_and_the_macros_and_says_only_what_it_loses() {
    if !openpyxl_available() {
        return;
    }
    let (dir, mut doc) = book_by_openpyxl(WRITE_FORMATTED);
    // A deleted row makes the save write the package anew (the patch keeps rows in place).
    run(&mut doc, "    Range(\"B1\").Font.Italic = True\n    Rows(5).Delete");
    let saved = dir.path().join("saved.xlsx");
    let encoded = doc.encode(&saved).unwrap();
    let anew = encoded.losses.iter().find(|l| l.contains("written anew")).expect("a rewrite");
    assert!(!anew.contains("styles"), "{anew}");
    std::fs::write(&saved, encoded.bytes()).unwrap();
    let read = python(READ_REWRITTEN, &[&saved]);
    assert_eq!(read.lines().collect::<Vec<_>>(), ["A1 bold=True", "B1 italic=True", "C1 fill=FFFF0000"]);
}

/// A book with values, column B 12 characters wide and E5 italic: what the patched save
/// must keep besides the macro's looks.
const WRITE_PLAIN: &str = r#"
import sys
from openpyxl import Workbook
from openpyxl.styles import Font
wb = Workbook()
ws = wb.active
ws["A1"] = 1
ws["B2"] = 2
ws["E5"] = "keep"
ws["E5"].font = Font(italic=True)
ws.column_dimensions["B"].width = 12
wb.save(sys.argv[1])
"#;

/// What the patched save kept of the file's own look.
const READ_KEPT: &str = r#"
import sys
from openpyxl import load_workbook
ws = load_workbook(sys.argv[1]).active
print("E5 italic=" + str(bool(ws["E5"].font.i)) + " B width=%.2f" % ws.column_dimensions["B"].width)
"#;

#[test]
fn a_save_over_the_files_own_package_writes_the_macros_formats() {
    if !openpyxl_available() {
        return;
    }
    let (dir, mut doc) = book_by_openpyxl(WRITE_PLAIN);
    run(&mut doc, FORMAT);
    let saved = dir.path().join("saved.xlsx");
    let encoded = doc.encode(&saved).unwrap();
    // Patched, not written anew, and nothing of the macro's formatting lost.
    assert_eq!(encoded.losses, Vec::<String>::new());
    std::fs::write(&saved, encoded.bytes()).unwrap();
    let read = python(READ_FORMATTED, &[&saved]);
    assert_eq!(read.lines().collect::<Vec<_>>(), EXPECTED);
    assert_eq!(python(READ_KEPT, &[&saved]).trim(), "E5 italic=True B width=12.00");
}

/// Takes the `<fills>` list out of the book's `styles.xml` (ECMA-376 18.8.39 makes it
/// optional).
const DROP_FILLS: &str = r#"
import re, sys, zipfile
with zipfile.ZipFile(sys.argv[1]) as src, zipfile.ZipFile(sys.argv[2], "w") as dst:
    for item in src.infolist():
        data = src.read(item.filename)
        if item.filename == "xl/styles.xml":
            data, n = re.subn(rb"<fills[^>]*>.*?</fills>", b"", data, flags=re.S)
            assert n == 1
        dst.writestr(item, data)
"#;

/// WRITE_PLAIN's book without `<fills>`: the macro's styles cannot be added to its styles
/// part, so the package is written anew, where the save failed as a damaged file.
#[test]
fn a_style_sheet_without_fills_is_written_anew_with_the_macros_formats() {
    if !openpyxl_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (plain, book) = (dir.path().join("plain.xlsx"), dir.path().join("book.xlsx"));
    python(WRITE_PLAIN, &[&plain]);
    python(DROP_FILLS, &[&plain, &book]);
    let mut doc = Document::open_file(&book, &OpenOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    run(&mut doc, FORMAT);
    let saved = dir.path().join("saved.xlsx");
    let encoded = doc.encode(&saved).unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(&saved, encoded.bytes()).unwrap();
    let read = python(READ_FORMATTED, &[&saved]);
    assert_eq!(read.lines().collect::<Vec<_>>(), EXPECTED);
}

/// A date typed with `ncsheet set` into a book read from a file gets Excel's built-in short
/// date (14, which openpyxl names `mm-dd-yy`), as Excel gives a typed date, in the file's own
/// package saved again; it was saved as a serial under General.
#[test]
fn a_date_set_into_a_book_is_saved_as_a_date() {
    if !openpyxl_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("book.xlsx");
    python(WRITE_PLAIN, &[&book]);
    let out = dir.path().join("out.xlsx");
    let run = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .arg("set")
        .arg(&book)
        .arg("A1=3/12/2025")
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let read = python(
        "import sys\nfrom openpyxl import load_workbook\nws = load_workbook(sys.argv[1]).active\n\
         a1 = ws['A1']\nprint(a1.is_date, a1.number_format, a1.value.date())",
        &[&out],
    );
    assert_eq!(read.trim(), "True mm-dd-yy 2025-03-12");
}

/// openpyxl's book of fonts: A1 red (FFFF0000), B1 14 points, C1 double-underlined, D1
/// plain; E1 a green font (FF008000) a macro makes automatic again.
const WRITE_FONTS: &str = r#"
import sys
from openpyxl import Workbook
from openpyxl.styles import Font
wb = Workbook()
ws = wb.active
for col in "ABCDE":
    ws[col + "1"] = col
ws["A1"].font = Font(color="FFFF0000")
ws["B1"].font = Font(sz=14)
ws["C1"].font = Font(u="double")
ws["E1"].font = Font(color="FF008000")
wb.save(sys.argv[1])
"#;

/// What a macro gave the fonts of row 2 and E1, as openpyxl reads them back.
const READ_FONTS: &str = r#"
import sys
from openpyxl import load_workbook
ws = load_workbook(sys.argv[1]).active
def colour(c):
    # Automatic: `auto`, or the theme's dark text (theme 1) a new file's Normal font names.
    col = ws[c].font.color
    if col is None:
        return "none"
    return "auto" if col.type == "auto" or (col.type == "theme" and col.theme == 1) else str(col.rgb)
print("A2 " + colour("A2") + " B2 " + colour("B2") + " E1 " + colour("E1"))
print("C2 sz=%s u=%s" % (ws["C2"].font.sz, ws["C2"].font.u))
print("A1 " + colour("A1") + " B1 sz=%s C1 u=%s" % (ws["B1"].font.sz, ws["C1"].font.u))
"#;

/// The macro: A2 blue by RGB, B2 red by palette index 3, C2 16 points and single-underlined,
/// E1 back to the automatic colour.
const SET_FONTS: &str = "    Range(\"A2:C2\").Value = 1\n    Range(\"A2\").Font.Color = RGB(0, 0, 255)\n\
     \x20   Range(\"B2\").Font.ColorIndex = 3\n    Range(\"C2\").Font.Size = 16\n\
     \x20   Range(\"C2\").Font.Underline = xlUnderlineStyleSingle\n    Range(\"E1\").Font.ColorIndex = xlAutomatic";

/// A font's colour, size and underline go from a file to a macro and from a macro to the
/// saved file, patched over the file's own package or written anew. Expected values:
/// "Font.Color property" (RGB, red in the low byte: FFFF0000 is 255), "Font.ColorIndex
/// property" (palette index 3 is red), "Font.Size property" (points), "XlUnderlineStyle
/// enumeration" (double -4119, single 2); the file's spelling ECMA-376 18.8.22 (`<font>`'s
/// `color rgb`, `sz val`, `u val`), read by openpyxl.
#[test]
fn font_colour_size_and_underline_go_from_the_file_to_the_macro_and_back() {
    if !openpyxl_available() {
        return;
    }
    let (dir, mut doc) = book_by_openpyxl(WRITE_FONTS);
    let printed = run(
        &mut doc,
        "    Debug.Print Range(\"A1\").Font.Color & \"|\" & Range(\"A1\").Font.ColorIndex & \"|\" & Range(\"D1\").Font.ColorIndex\n\
         \x20   Debug.Print Range(\"B1\").Font.Size & \"|\" & Range(\"D1\").Font.Size & \"|\" & Range(\"C1\").Font.Underline & \"|\" & Range(\"D1\").Font.Underline",
    );
    assert_eq!(printed, ["255|3|-4105", "14|11|-4119|-4142"]);
    run(&mut doc, SET_FONTS);
    let expected = ["A2 FF0000FF B2 FFFF0000 E1 auto", "C2 sz=16.0 u=single", "A1 FFFF0000 B1 sz=14.0 C1 u=double"];
    let patched = dir.path().join("patched.xlsx");
    let encoded = doc.encode(&patched).unwrap();
    assert_eq!(encoded.losses, Vec::<String>::new());
    std::fs::write(&patched, encoded.bytes()).unwrap();
    assert_eq!(python(READ_FONTS, &[&patched]).lines().collect::<Vec<_>>(), expected);
    // A deleted row makes the save write the package anew (the patch keeps rows in place).
    run(&mut doc, "    Rows(5).Delete");
    let anew = dir.path().join("anew.xlsx");
    let encoded = doc.encode(&anew).unwrap();
    assert!(encoded.losses.iter().any(|l| l.contains("written anew")), "{:?}", encoded.losses);
    std::fs::write(&anew, encoded.bytes()).unwrap();
    assert_eq!(python(READ_FONTS, &[&anew]).lines().collect::<Vec<_>>(), expected);
}

/// openpyxl's book: A1 in 14-point red single-underlined Arial.
const WRITE_FONT: &str = r#"
import sys
from openpyxl import Workbook
from openpyxl.styles import Font
wb = Workbook()
ws = wb.active
ws["A1"] = 1
ws["A1"].font = Font(name="Arial", size=14, color="FFFF0000", underline="single")
wb.save(sys.argv[1])
"#;

/// Reads back A1's font size, colour and underline.
const READ_FONT: &str = r#"
import sys
from openpyxl import load_workbook
f = load_workbook(sys.argv[1]).active["A1"].font
print("size=%g color=%s underline=%s" % (f.sz, f.color.rgb, f.u))
"#;

#[test]
fn a_package_written_anew_says_it_keeps_the_fonts_sizes_and_colours_that_it_keeps() {
    if !openpyxl_available() {
        return;
    }
    let (dir, mut doc) = book_by_openpyxl(WRITE_FONT);
    run(&mut doc, "    Rows(5).Delete");
    let saved = dir.path().join("saved.xlsx");
    let encoded = doc.encode(&saved).unwrap();
    std::fs::write(&saved, encoded.bytes()).unwrap();
    // What openpyxl reads from the saved file is what the message must not call lost.
    assert_eq!(python(READ_FONT, &[&saved]).trim(), "size=14 color=FFFF0000 underline=single");
    let anew = encoded.losses.iter().find(|l| l.contains("written anew")).expect("a rewrite");
    let lost = anew.split_once("are kept;").map(|(_, lost)| lost).expect("what is lost");
    assert!(lost.contains("fonts' names") && !lost.contains("sizes") && !lost.contains("colours"), "{anew}");
}
