//! Excel's hyperlinks as a macro makes and reads them, and as the xlsx file keeps them.
//!
//! Expected values: Microsoft's Excel VBA reference, "Hyperlinks.Add method" (Anchor,
//! Address, SubAddress, ScreenTip, TextToDisplay; returns the new Hyperlink; TextToDisplay is
//! the text displayed), "Hyperlink object" (Address, SubAddress, ScreenTip, TextToDisplay,
//! Range, Delete), "Hyperlinks.Count/Item/Delete", "Range.Hyperlinks" and
//! "Range.ClearHyperlinks"; in the file, ECMA-376 Part 1, 18.3.1.47 `hyperlink` (`ref`,
//! `location` for a place in the workbook, `r:id` for a relationship whose target, with
//! TargetMode="External", is the address), read back by openpyxl.

mod common;

use common::corpus;
use common::openpyxl::{openpyxl_available, python};
use common::vba::{main_fails, run_main as run};
use ncsheet::document::{Document, OpenOptions};
use ncsheet::vba::RunOptions;
use ncsheet::workbook::Workbook;

/// `Add` with named arguments returns the link; the anchor shows TextToDisplay, an empty
/// anchor without it shows the address, and a filled one keeps its value. The collection
/// counts, indexes from 1 and goes through its links in the order they were made; a range's
/// collection holds the links on its cells.
#[test]
fn hyperlinks_add_returns_the_link_and_the_anchor_shows_its_text() {
    let printed = run(
        &mut Workbook::with_sheet(),
        "    Dim h As Object, x As Object\n    Range(\"C3\").Value = \"keep\"\n    \
         Set h = ActiveSheet.Hyperlinks.Add(Anchor:=Range(\"A1\"), Address:=\"\", SubAddress:=\"'Sheet1'!B5\", \
         ScreenTip:=\"tip\", TextToDisplay:=\"Go\")\n    \
         ActiveSheet.Hyperlinks.Add Range(\"A2\"), \"https://example.com/x\"\n    \
         ActiveSheet.Hyperlinks.Add Range(\"C3\"), \"mailto:a@example.com\"\n    \
         Debug.Print ActiveSheet.Hyperlinks.Count; Range(\"A1\").Value; \"|\"; Range(\"A2\").Value; \"|\"; Range(\"C3\").Value\n    \
         Debug.Print TypeName(h); \"|\"; h.Address; \"|\"; h.SubAddress; \"|\"; h.TextToDisplay; \"|\"; h.ScreenTip; \"|\"; h.Range.Address\n    \
         For Each x In ActiveSheet.Hyperlinks\n        Debug.Print x.Address; \"|\"; x.SubAddress\n    Next\n    \
         Debug.Print Range(\"A1:B9\").Hyperlinks.Count; ActiveSheet.Hyperlinks(3).Range.Address; ActiveSheet.Hyperlinks.Item(2).Address",
    );
    assert_eq!(
        printed,
        [
            " 3 Go|https://example.com/x|keep",
            "Hyperlink||'Sheet1'!B5|Go|tip|$A$1",
            "|'Sheet1'!B5",
            "https://example.com/x|",
            "mailto:a@example.com|",
            " 2 $C$3https://example.com/x",
        ]
    );
}

/// A link moves with its cells and goes with them; `Delete` of one, of a range's, and
/// `ClearHyperlinks` take links away and leave the cells' text; a Hyperlink object whose link
/// is gone is Excel's run-time error 424, Object required; past the last item, error 9.
#[test]
fn hyperlinks_follow_their_cells_and_are_deleted() {
    let mut wb = Workbook::with_sheet();
    let printed = run(
        &mut wb,
        "    Dim h As Object\n    Set h = ActiveSheet.Hyperlinks.Add(Range(\"B2\"), \"\", \"Sheet1!A1\", , \"one\")\n    \
         ActiveSheet.Hyperlinks.Add Range(\"B3\"), \"\", \"Sheet1!A2\", , \"two\"\n    \
         ActiveSheet.Hyperlinks.Add Range(\"B4\"), \"\", \"Sheet1!A3\", , \"three\"\n    \
         Rows(1).Insert\n    Debug.Print h.Range.Address; ActiveSheet.Hyperlinks(3).Range.Address\n    \
         Rows(4).Delete\n    Debug.Print ActiveSheet.Hyperlinks.Count; ActiveSheet.Hyperlinks(2).TextToDisplay\n    \
         ActiveSheet.Hyperlinks.Add Range(\"B6\"), \"\", \"Sheet1!A4\", , \"four\"\n    \
         ActiveSheet.Hyperlinks(3).Delete\n    Range(\"B4:B9\").ClearHyperlinks\n    \
         Debug.Print ActiveSheet.Hyperlinks.Count; Range(\"B4\").Value\n    h.Delete\n    \
         Debug.Print ActiveSheet.Hyperlinks.Count",
    );
    assert_eq!(printed, ["$B$3$B$5", " 2 three", " 1 three", " 0 "]);
    let gone = main_fails(
        &mut Workbook::with_sheet(),
        "    Dim h As Object\n    Set h = ActiveSheet.Hyperlinks.Add(Range(\"B2\"), \"https://example.com\")\n    \
         ActiveSheet.Hyperlinks.Delete\n    Debug.Print h.Address",
    );
    assert!(gone.contains("424"), "{gone}");
    let past = main_fails(&mut Workbook::with_sheet(), "    Debug.Print ActiveSheet.Hyperlinks(1).Address");
    assert!(past.contains("run-time error 9"), "{past}");
}

/// Excel lays pages out for a printer (paper, margins, scaling, breaks, the fonts'
/// metrics); ncsheet lays out none, so `PageSetup` is refused by its name, not guessed.
#[test]
fn page_setup_is_refused_by_name() {
    let e = main_fails(&mut Workbook::with_sheet(), "    Debug.Print ActiveSheet.PageSetup.Pages.Count");
    assert!(e.contains("PageSetup") && e.contains("pages"), "{e}");
}

/// Reads each linked cell of the first sheet: its value, and the link's target (the
/// relationship's), location, display and tooltip; and the relationships' TargetMode.
const READ_LINKS: &str = r#"
import sys, zipfile, re
from openpyxl import load_workbook
ws = load_workbook(sys.argv[1]).active
for row in ws.iter_rows():
    for c in row:
        h = c.hyperlink
        if h:
            print(c.coordinate, c.value, h.target, h.location, h.tooltip, sep="|")
rels = zipfile.ZipFile(sys.argv[1]).read("xl/worksheets/_rels/sheet1.xml.rels").decode()
print(sorted(set(re.findall(r'TargetMode="(\w+)"', rels))))
"#;

/// The macro's links reach a saved file: a place in the workbook as `location`, an address
/// outside it through a relationship with TargetMode="External".
#[test]
fn the_macros_hyperlinks_are_saved_as_excel_keeps_them() {
    if !openpyxl_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut doc = Document::open(b"x\n".to_vec(), &OpenOptions::named("plain.csv")).unwrap();
    let src = "Sub Main()\n    ActiveSheet.Hyperlinks.Add Range(\"B2\"), \"\", \"'plain'!A1\", \"back\", \"Top\"\n    \
               ActiveSheet.Hyperlinks.Add Range(\"B3\"), \"https://example.com/a?b=1\"\nEnd Sub\n";
    doc.run_macro(src, "links.bas", RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let saved = dir.path().join("saved.xlsx");
    std::fs::write(&saved, doc.encode(&saved).unwrap().bytes()).unwrap();
    let read = python(READ_LINKS, &[&saved]);
    assert_eq!(
        read.lines().collect::<Vec<_>>(),
        [
            "B2|Top|None|'plain'!A1|back",
            "B3|https://example.com/a?b=1|https://example.com/a?b=1|None|None",
            "['External']",
        ]
    );
}

/// A link Excel wrote (ironcalc's CHOOSE.xlsx, saved by Excel: B1 leads to Microsoft's
/// CHOOSE page through relationship rId1) reaches the macro; a save over the package that did
/// not touch the links keeps the sheet's `<hyperlinks>` and its relationships byte for byte.
#[test]
fn a_files_hyperlinks_reach_the_macro_and_a_save_keeps_them_as_they_were() {
    let Some(root) = corpus::root() else { return };
    let book = root.join("calc_tests/LOOKUP_AND_REFERENCE/CHOOSE.xlsx");
    let bytes = std::fs::read(&book).unwrap();
    let mut doc = Document::open(bytes.clone(), &OpenOptions::named("CHOOSE.xlsx")).unwrap();
    let src = "Sub Main()\n    With ActiveSheet.Hyperlinks(1)\n        Debug.Print ActiveSheet.Hyperlinks.Count; \
               .Range.Address; \" \"; .Address\n    End With\n    Range(\"H30\").Value = 5\nEnd Sub\n";
    let printed = doc.run_macro(src, "read.bas", RunOptions::default()).unwrap_or_else(|e| panic!("{e}")).printed;
    let page = "https://support.microsoft.com/en-us/office/choose-function-fc5c184f-cb62-4ec7-a46e-38653b98f5bc";
    assert_eq!(printed, [format!(" 1 $B$1 {page}")]);
    let encoded = doc.encode(std::path::Path::new("saved.xlsx")).unwrap();
    assert_eq!(encoded.losses, Vec::<String>::new());
    let part = |package: &[u8], name: &str| {
        let mut zip = zip::ZipArchive::new(std::io::Cursor::new(package.to_vec())).unwrap();
        let mut text = String::new();
        std::io::Read::read_to_string(&mut zip.by_name(name).unwrap(), &mut text).unwrap();
        text
    };
    let links = |xml: String| xml[xml.find("<hyperlinks>").unwrap()..xml.find("</hyperlinks>").unwrap()].to_string();
    let sheet = "xl/worksheets/sheet1.xml";
    assert_eq!(links(part(encoded.bytes(), sheet)), links(part(&bytes, sheet)));
    let rels = "xl/worksheets/_rels/sheet1.xml.rels";
    assert_eq!(part(encoded.bytes(), rels), part(&bytes, rels));
    assert!(part(encoded.bytes(), sheet).contains("<c r=\"H30\""), "the edit was saved");
}
