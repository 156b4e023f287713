//! Hostile containers (issue 30), seventh round (session 20): the readers' classes the
//! earlier rounds did not reach. What each test expects comes from outside our code: XML 1.0
//! (W3C, fifth edition), ECMA-376 Part 2 (Open Packaging Conventions), RFC 3986.

mod common;

use std::path::Path;

use ncsheet::formula::address::parse_cell;
use ncsheet::io::xlsx::{self, ErrorKind, Layout, XlsxError};
use ncsheet::workbook::Workbook;

const FILE: &str = "hostile.xlsx";

/// A workbook of our writer's: Sheet1 with a number, a text (shared string) and a formula.
fn good_workbook() -> Vec<u8> {
    let mut wb = Workbook::with_sheet();
    for (cell, input) in [("A1", "2"), ("B1", "text"), ("C1", "=A1*3")] {
        wb.set_input(0, parse_cell(cell).unwrap(), input).unwrap();
    }
    xlsx::to_bytes(&wb, &Layout::default()).unwrap()
}

/// `package` with the first `from` of `part` replaced by `to`.
fn spoiled(package: &[u8], part: &str, from: &str, to: &str) -> Vec<u8> {
    let options = zip::write::SimpleFileOptions::default();
    let mut change = |name: &str, data: Vec<u8>| {
        if name != part {
            return data;
        }
        let text = String::from_utf8(data).unwrap();
        assert!(text.contains(from), "{part} holds no {from}: {text}");
        text.replacen(from, to, 1).into_bytes()
    };
    common::xlsx::rewrite_package(package, options, &mut change).finish().unwrap().into_inner()
}

fn part_text(package: &[u8], part: &str) -> String {
    use std::io::Read;
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(package)).unwrap();
    let mut text = String::new();
    zip.by_name(part).unwrap().read_to_string(&mut text).unwrap();
    text
}

fn load(bytes: &[u8]) -> Result<xlsx::Imported, XlsxError> {
    xlsx::load_bytes(bytes, Path::new(FILE))
}

const DECLARATION: &str = r#"<?xml version="1.0" encoding="UTF-8" standalone="yes"?>"#;
const SHEET: &str = "xl/worksheets/sheet1.xml";
const STRINGS: &str = "xl/sharedStrings.xml";

/// XML 1.0 allows a reference only to a character of its `Char` production (§2.2: tab, line
/// feed, carriage return, U+0020–U+D7FF, U+E000–U+FFFD, U+10000–U+10FFFF; §4.1, constraint
/// "Legal Character") and only to an entity it declares (§4.1, "Entity Declared": the five
/// predefined ones, as an Office Open XML part may have no DTD, ECMA-376 Part 2 §8.1.4
/// [M1.18], which also tells readers to treat a DTD as an error). Each of these was shown as
/// text in its cell (`x&foo;y`, `x\u{1}y`), `&#0;` dropped or read as a space, and a DTD's
/// entity expanded by calamine: now the part is refused, naming it and the cell or string.
#[test]
fn references_xml_does_not_allow_refuse_the_part_naming_the_cell() {
    let good = good_workbook();
    let inline = |text: &str| format!(r#"<c r="D1" t="inlineStr"><is><t>{text}</t></is></c></row>"#);
    let in_sheet = ["x&foo;y", "x&#1;y", "x&#0;y", "x&#xD800;y", "x&#99999999;y", "x&#xFFFE;y", "R&D"];
    for text in in_sheet {
        let bytes = spoiled(&good, SHEET, "</row>", &inline(text));
        let e = load(&bytes).err().unwrap_or_else(|| panic!("{text} was read"));
        assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(SHEET)), "{e}");
        assert!(e.message.starts_with("cell D1 holds XML that is not well-formed: "), "{text}: {e}");
    }
    // A formula's text and a shared string are character data too.
    let e = load(&spoiled(&good, SHEET, "<f>A1*3</f>", "<f>A1*3&amp;&#2;</f>")).err().unwrap();
    assert!(e.message.contains("cell C1 ") && e.message.contains("&#2;"), "{e}");
    let e = load(&spoiled(&good, STRINGS, "<t>text</t>", "<t>te&#x1F;xt</t>")).err().unwrap();
    assert_eq!(e.part.as_deref(), Some(STRINGS), "{e}");
    assert!(e.message.contains("&#x1F;"), "{e}");
    // The sheet's name in the workbook part (read by the forgiving reader of small parts).
    let e = load(&spoiled(&good, "xl/workbook.xml", r#"name="Sheet1""#, r#"name="Sheet&#0;""#)).err().unwrap();
    assert_eq!(e.part.as_deref(), Some("xl/workbook.xml"), "{e}");
    assert!(e.message.contains("&#0;"), "{e}");

    // A DTD in any part, declaring the entity the text uses or not.
    let dtd = format!("{DECLARATION}<!DOCTYPE x [<!ENTITY foo \"bar\">]>");
    let used = spoiled(&spoiled(&good, STRINGS, DECLARATION, &dtd), STRINGS, "<t>text</t>", "<t>&foo;</t>");
    for (part, bytes) in [
        (STRINGS, used),
        (SHEET, spoiled(&good, SHEET, DECLARATION, &dtd)),
        ("xl/styles.xml", spoiled(&good, "xl/styles.xml", DECLARATION, &dtd)),
        ("xl/workbook.xml", spoiled(&good, "xl/workbook.xml", DECLARATION, &dtd)),
    ] {
        let e = load(&bytes).err().unwrap_or_else(|| panic!("{part} with a DTD was read"));
        assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(part)), "{e}");
        assert!(e.message.contains("declares a DTD") && e.message.contains("[M1.18]"), "{e}");
    }

    // What XML allows still reads: the predefined entities, references to characters in
    // range (tab, é, an emoji past U+FFFF).
    let text = "a&amp;b&lt;&#9;&#xE9;&#x1F600;";
    let wb = load(&spoiled(&good, SHEET, "</row>", &inline(text))).unwrap().workbook;
    let shown = wb.value(0, parse_cell("D1").unwrap());
    assert_eq!(shown, ncsheet::eval::Value::Text("a&b<\té\u{1F600}".into()));
}

/// A relationship's target is a URI reference resolved against its source part's folder
/// (ECMA-376 Part 2, §9.3; RFC 3986 §5.2: `.` and `..` segments removed, `/` from the root)
/// whose percent-encoded octets stand for their characters (RFC 3986 §2.1). Each spelling
/// below names xl/worksheets/sheet1.xml; calamine joined the target to `xl/` as written and
/// said "Worksheet not found". A target that leaves the package is refused, naming the
/// relationship.
#[test]
fn relationship_targets_resolve_as_pack_uris_do() {
    let good = good_workbook();
    let rels = "xl/_rels/workbook.xml.rels";
    let written = r#"Target="worksheets/sheet1.xml""#;
    for target in [
        "../xl/worksheets/./sheet1.xml",
        "/xl/worksheets/sheet1.xml",
        "worksheets/../worksheets/sheet1.xml",
        "worksheets/sheet%31.xml",
        "./worksheets//sheet1.xml",
    ] {
        let bytes = spoiled(&good, rels, written, &format!(r#"Target="{target}""#));
        let wb = load(&bytes).unwrap_or_else(|e| panic!("{target}: {e}")).workbook;
        assert_eq!(wb.value(0, parse_cell("C1").unwrap()), ncsheet::eval::Value::Number(6.0), "{target}");
    }
    let main = spoiled(&good, "_rels/.rels", r#"Target="xl/workbook.xml""#, r#"Target="./xl/../xl/workbook.xml""#);
    assert!(load(&main).is_ok());

    for target in ["../../etc/passwd", "file:///etc/passwd", "//server/share/sheet1.xml", "sheet%2F1.xml"] {
        let bytes = spoiled(&good, rels, written, &format!(r#"Target="{target}""#));
        let e = load(&bytes).err().unwrap_or_else(|| panic!("{target} was read"));
        assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(rels)), "{e}");
        assert!(e.message.starts_with("relationship rId1: the target '"), "{target}: {e}");
    }
}

/// A `<sheet>` whose relationship names a part that is no sheet (the theme), or a kind
/// calamine does not read (an Excel 4 macro sheet): calamine refused the whole workbook with
/// "Unrecognized sheet:type: xl/theme/theme1.xml", naming no part of the package. Such a
/// sheet is left out with a note naming it and its kind, the other sheets read.
#[test]
fn a_sheet_whose_relationship_is_no_worksheet_is_left_out_with_a_note() {
    let good = good_workbook();
    let rels = part_text(&good, "xl/_rels/workbook.xml.rels");
    let theme = rels.split("<Relationship ").find(|r| r.contains("/theme\"")).unwrap();
    let id = theme.split("Id=\"").nth(1).unwrap().split('"').next().unwrap();
    let extra = format!(r#"<sheets><sheet name="Two" sheetId="2" r:id="{id}"/>"#);
    let imported = load(&spoiled(&good, "xl/workbook.xml", "<sheets>", &extra)).unwrap();
    assert!(
        imported.notes.iter().any(|n| n.contains("sheet 'Two' is a theme and was left out")),
        "{:?}",
        imported.notes
    );
    assert_eq!(imported.workbook.value(0, parse_cell("C1").unwrap()), ncsheet::eval::Value::Number(6.0));
}

/// `[Content_Types].xml` and the document properties (`docProps/app.xml`, `core.xml`) are
/// XML parts like any other: a DTD in one is an error a reader must report (ECMA-376 Part 2
/// §8.1.4, [M1.18]), as is an entity XML does not declare (XML 1.0 §4.1, "Entity Declared")
/// or an element left open (§3, "Element Type Match"). No reader of cells reads them, so each
/// was passed over in silence (the program that wrote the file read as unknown) and a save
/// copied it on; now the package is refused naming the part.
#[test]
fn package_metadata_parts_that_are_not_well_formed_are_refused_naming_the_part() {
    let good = good_workbook();
    let dtd = format!("{DECLARATION}<!DOCTYPE Types [<!ENTITY x \"y\">]>");
    let types = "[Content_Types].xml";
    let app = part_text(&good, "docProps/app.xml");
    let application = app.split("<Application>").nth(1).unwrap().split('<').next().unwrap().to_string();
    let cases = [
        (types, spoiled(&good, types, DECLARATION, &dtd), "declares a DTD"),
        ("docProps/app.xml", spoiled(&good, "docProps/app.xml", DECLARATION, &dtd), "declares a DTD"),
        (
            "docProps/app.xml",
            spoiled(&good, "docProps/app.xml", &application, &format!("{application}&bogus;")),
            "unknown entity &bogus;",
        ),
        ("docProps/core.xml", spoiled(&good, "docProps/core.xml", "</cp:coreProperties>", ""), "cut short"),
    ];
    for (part, bytes, why) in cases {
        let e = load(&bytes).err().unwrap_or_else(|| panic!("{part} ({why}) was read"));
        assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(part)), "{e}");
        assert!(e.message.contains(why), "{part}: {e}");
    }
    // The good parts still read, and say who wrote the file.
    assert!(load(&good).unwrap().written_by.is_some());
}

/// XML 1.0 allows no control character but tab, line feed and carriage return in a document
/// (§2.2, the `Char` production: U+0001–U+0008, U+000B, U+000C, U+000E–U+001F are outside
/// it), raw or as a reference (`&#1;`, refused before). Raw, each was read: into a cell's
/// text, a shared string, a sheet's name. Now the part is refused naming it and the
/// character; a raw tab, line feed and carriage return (read as a line feed, §2.11) still
/// read.
#[test]
fn raw_control_characters_xml_does_not_allow_refuse_the_part() {
    let good = good_workbook();
    let inline = |text: &str| format!(r#"<c r="D1" t="inlineStr"><is><t>{text}</t></is></c></row>"#);
    let cases = [
        (SHEET, spoiled(&good, SHEET, "</row>", &inline("x\u{1}y")), "U+0001"),
        (SHEET, spoiled(&good, SHEET, "</row>", &inline("x\u{8}y")), "U+0008"),
        (SHEET, spoiled(&good, SHEET, "</row>", &inline("x\u{B}y")), "U+000B"),
        (SHEET, spoiled(&good, SHEET, "</row>", &inline("x\u{C}y")), "U+000C"),
        (SHEET, spoiled(&good, SHEET, "<f>A1*3</f>", "<f>A1*3\u{E}</f>"), "U+000E"),
        (STRINGS, spoiled(&good, STRINGS, "<t>text</t>", "<t>te\u{1F}xt</t>"), "U+001F"),
        ("xl/workbook.xml", spoiled(&good, "xl/workbook.xml", r#"name="Sheet1""#, "name=\"Sheet\u{2}1\""), "U+0002"),
        (
            "docProps/core.xml",
            spoiled(&good, "docProps/core.xml", "</cp:coreProperties>", "\u{1B}</cp:coreProperties>"),
            "U+001B",
        ),
    ];
    for (part, bytes, character) in cases {
        let e = load(&bytes).err().unwrap_or_else(|| panic!("{part} with {character} was read"));
        assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(part)), "{e}");
        assert!(e.message.contains(character) && e.message.contains("XML 1.0"), "{part}: {e}");
    }
    let wb = load(&spoiled(&good, SHEET, "</row>", &inline("a\tb\nc\r\nd"))).unwrap().workbook;
    assert_eq!(wb.value(0, parse_cell("D1").unwrap()), ncsheet::eval::Value::Text("a\tb\nc\nd".into()));
}

/// A part in UTF-8 (XML 1.0 §4.3.3: without an encoding declaration, or declaring UTF-8)
/// holding bytes that are no UTF-8 is not well-formed; calamine refused the styles, the
/// shared strings and the relationships with "Xml error: cannot decode input using UTF-8",
/// naming no part. Now the message names it.
#[test]
fn bytes_that_are_not_utf8_refuse_the_part_naming_it() {
    let good = good_workbook();
    let with_bad_byte = |part: &str| {
        let options = zip::write::SimpleFileOptions::default();
        let mut change = |name: &str, mut data: Vec<u8>| {
            if name == part {
                // 0xFF begins no UTF-8 sequence: after the root's start tag, as text.
                let at = data.windows(2).position(|w| w == b"><").unwrap_or_else(|| panic!("{part}: no tag")) + 1;
                data.insert(at, 0xFF);
            }
            data
        };
        common::xlsx::rewrite_package(&good, options, &mut change).finish().unwrap().into_inner()
    };
    for part in ["xl/styles.xml", STRINGS, "_rels/.rels", "xl/_rels/workbook.xml.rels"] {
        let e = load(&with_bad_byte(part)).err().unwrap_or_else(|| panic!("{part} was read"));
        assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(part)), "{e}");
        assert!(e.message.contains("UTF-8"), "{part}: {e}");
    }
}

/// XML 1.0 §3.1, well-formedness constraint "Unique Att Spec": an attribute name appears at
/// most once in a tag. `<c r="A1" r="B1">` was read silently (the first `r` taken, a guess);
/// now every part our readers or calamine read is refused, naming the part and the element.
#[test]
fn an_attribute_given_twice_refuses_the_part_naming_it() {
    let good = good_workbook();
    let cases = [
        (SHEET, r#"<c r="A1""#, r#"<c r="A1" r="B1""#, "<c>"),
        ("xl/styles.xml", r#"<xf numFmtId="0""#, r#"<xf numFmtId="0" numFmtId="14""#, "<xf>"),
        (STRINGS, r#" uniqueCount=""#, r#" count="7" uniqueCount=""#, "<sst>"),
        ("xl/workbook.xml", r#"<sheet name="Sheet1""#, r#"<sheet name="Sheet1" name="Other""#, "<sheet>"),
        ("xl/theme/theme1.xml", r#"name="Office Theme""#, r#"name="A" name="Office Theme""#, "<theme>"),
        ("_rels/.rels", r#"Id="rId1""#, r#"Id="rId1" Id="rId9""#, "<Relationship>"),
        ("xl/_rels/workbook.xml.rels", r#"Id="rId1""#, r#"Id="rId1" Id="rId9""#, "<Relationship>"),
    ];
    for (part, from, to, element) in cases {
        let e = load(&spoiled(&good, part, from, to)).err().unwrap_or_else(|| panic!("{part} was read"));
        assert_eq!((e.kind, e.part.as_deref()), (ErrorKind::Damaged, Some(part)), "{e}");
        assert!(e.message.contains(&format!("{element} gives the attribute")), "{part}: {e}");
        assert!(e.message.contains("twice"), "{part}: {e}");
    }
}

/// A part beside the cells (a table, a pivot table and its cache, a link to another workbook
/// and its relationships) whose XML is not well-formed (here: an element after the end of
/// the document, XML 1.0 §2.1 production `document`) was dropped silently: the table, the
/// pivot table or the linked values were missing with no word of why (the records of a
/// pivot cache even read as none, so GETPIVOTDATA summarised nothing). Now a note names the
/// part, why, and what was left out; a save over the file keeps the part byte for byte.
#[test]
fn a_part_beside_the_cells_that_cannot_be_read_is_noted_and_kept() {
    let Some(public) = common::corpus::public_root() else { return };
    let poi = public.join("poi");
    let cases = [
        ("test-data_spreadsheet_63934.xlsx", "xl/tables/table1.xml", "the table was left out"),
        ("test-data_spreadsheet_63934.xlsx", "xl/externalLinks/externalLink1.xml", "linked workbook show #NAME?"),
        ("test-data_spreadsheet_63934.xlsx", "xl/externalLinks/_rels/externalLink1.xml.rels", "file name is unknown"),
        ("test-data_spreadsheet_54436.xlsx", "xl/pivotTables/pivotTable1.xml", "pivot table was left out"),
        ("test-data_spreadsheet_54436.xlsx", "xl/pivotCache/pivotCacheDefinition1.xml", "pivot table was left out"),
        ("test-data_spreadsheet_54436.xlsx", "xl/pivotCache/pivotCacheRecords1.xml", "pivot table was left out"),
    ];
    let dir = std::env::temp_dir().join(format!("ncsheet-unreadable-part-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (file, part, left_out) in cases {
        let good = std::fs::read(poi.join(file)).unwrap();
        let text = part_text(&good, part);
        let bad = spoiled(&good, part, text.trim_end(), &format!("{}<x/>", text.trim_end()));
        let imported = load(&bad).unwrap_or_else(|e| panic!("{part}: {e}"));
        let note = imported.notes.iter().find(|n| n.starts_with(&format!("{part}: the XML is not well-formed")));
        let note = note.unwrap_or_else(|| panic!("{part}: no note among {:?}", imported.notes));
        assert!(note.contains("<x> after the end of the document") && note.contains(left_out), "{note}");

        let (input, output) = (dir.join("in.xlsx"), dir.join("out.xlsx"));
        std::fs::write(&input, &bad).unwrap();
        let run = common::cli::ncsheet(&["set", input.to_str().unwrap(), "Z99=1", "-o", output.to_str().unwrap()]);
        assert_eq!(run.code, 0, "{part}: {}", run.stderr);
        assert!(run.stderr.contains(part), "{part}: the save said nothing of it: {}", run.stderr);
        let saved = std::fs::read(&output).unwrap();
        assert_eq!(part_text(&saved, part), part_text(&bad, part), "{part} changed on save");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Excel stores a formula made before dynamic arrays as a plain `<f>` and shows such a
/// formula's array result by implicit intersection: its first item (Microsoft, "Implicit
/// intersection operator: @", and "Dynamic array formulas in non-dynamic aware Excel").
/// Here A(k) = A(k+1)+ROW($B$1:$B$5) for 2,000 rows over A2001 = 0, so A(k) shows
/// 2001 − k. Each such formula was rewritten and recalculated on its own, recomputing every
/// formula reading it each time: 2·10^6 evaluations for the chain (a chain whose cells each
/// made 5,000 items ran for minutes). Counted, not timed: the load evaluates each a few times.
#[test]
fn a_chain_of_legacy_array_formulas_loads_in_linear_work() {
    let rows = 2_000u32;
    let mut cells: String =
        (1..=rows).map(|k| format!(r#"<row r="{k}"><c r="A{k}"><f>A{}+ROW($B$1:$B$5)</f></c></row>"#, k + 1)).collect();
    cells.push_str(&format!(r#"<row r="{0}"><c r="A{0}"><v>0</v></c></row>"#, rows + 1));
    let good = good_workbook();
    let sheet = part_text(&good, SHEET);
    let (start, end) = (sheet.find("<sheetData>").unwrap(), sheet.find("</sheetData>").unwrap());
    let bytes = spoiled(&good, SHEET, &sheet[start..end], &format!("<sheetData>{cells}"));
    let imported = load(&bytes).unwrap();
    let wb = &imported.workbook;
    for k in [1, 2, 1_000, rows] {
        assert_eq!(
            wb.value(0, parse_cell(&format!("A{k}")).unwrap()),
            common::sheet::n(f64::from(rows + 1 - k)),
            "A{k}"
        );
    }
    let evaluated = wb.formulas_evaluated();
    assert!(evaluated <= 8 * u64::from(rows), "{evaluated} evaluations to load {rows} legacy formulas");
}
