//! Fuzz targets, one per input ncsheet reads (issues 19 and 30): formula text, csv bytes, xlsx
//! packages mutated from a good one, their styles' number formats and defined names, macro
//! source and declarations, VBA project streams, NC programs in every dialect and surface
//! formulas. Each runs a bounded number of proptest cases inside `cargo test` and asserts that
//! nothing panics (a panic is a failed case; a stack overflow would abort the run). Inputs mix
//! random characters with the pieces hostile text is made of: deep brackets, long operator
//! chains, huge numbers. The cases come from a fixed seed (`common::fuzz`): CI runs the same
//! ones every time, a failure prints the seed, and `PROPTEST_CASES` and `PROPTEST_RNG_SEED`
//! run more or other cases locally.

mod common;

use std::path::Path;

use proptest::prelude::*;

use common::fuzz::{config, mutated};

use ncsheet::eval::functions::Registry;
use ncsheet::eval::surface::FormulaSurface;
use ncsheet::eval::Ctx;
use ncsheet::formula::address::parse_cell;
use ncsheet::formula::parse::ParseContext;
use ncsheet::formula::Pos;
use ncsheet::io::xlsx;
use ncsheet::vba::{self, RunOptions};
use ncsheet::workbook::Workbook;

/// Pieces of formulas, hostile ones among them; a formula is a string of them.
fn formula_piece() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => "[-+*/^&%,;:(){}\"'!$#@<>= .0-9A-Za-z]{1,6}",
        1 => prop::sample::select(vec![
            "SUM(", "IF(", "LET(x,", "LAMBDA(x,", "TEXT(", "FIXED(", "MOD(", "REPT(\"ab\",", "SEQUENCE(",
            "OFFSET(A1,", "INDIRECT(\"", "1E+308", "-1E+308", "2^1024", "A1:XFD1048576", "A1#", "\"%%%%\"",
            "\"0.0E+0%\"", "Sheet2!", "1E-320", "#REF!", "{1,2;3,4}", "XFD1048576",
        ])
        .prop_map(str::to_string),
        1 => (1usize..600, prop::sample::select(vec!["(", "-", "ABS(", "+1", "&\"x\"", "*A1"]))
            .prop_map(|(n, s)| s.repeat(n)),
    ]
}

fn formula() -> impl Strategy<Value = String> {
    prop::collection::vec(formula_piece(), 0..12).prop_map(|pieces| format!("={}", pieces.concat()))
}

proptest! {
    #![proptest_config(config(200))]

    #[test]
    fn formula_text_never_panics(a in formula(), b in formula()) {
        let mut wb = Workbook::with_sheet();
        let _ = wb.set_input(0, parse_cell("B2").unwrap(), "3");
        let _ = wb.set_input(0, parse_cell("A1").unwrap(), &a);
        let _ = wb.set_input(0, parse_cell("C3").unwrap(), &b);
        let _ = wb.value(0, parse_cell("A1").unwrap());
        let _ = wb.formula(0, parse_cell("A1").unwrap());
        let _ = wb.problems();
    }

    #[test]
    fn surface_formulas_never_panic(text in formula()) {
        let ctx = ParseContext { at: Pos::new(0, 0), functions: &Registry, sheet: &|_| None };
        if let Ok(surface) = FormulaSurface::parse(&text, &ctx) {
            let wb = Workbook::with_sheet();
            let mut eval = Ctx::new(&wb, 0, Pos::new(0, 0));
            let mut bound = surface.bind(&mut eval);
            let _ = bound.height_at(0.5, -0.25);
            let _ = bound.sample_at(0.5, -0.25);
        }
    }

    #[test]
    fn csv_bytes_never_panic(bytes in prop::collection::vec(prop_oneof![
        4 => any::<u8>(),
        4 => prop::sample::select(b"=,\"\n\r;A1+(-)".to_vec()),
    ], 0..400)) {
        if let Ok(wb) = ncsheet::io::csv::read(&bytes) {
            let _ = wb.values(0);
            let _ = wb.problems();
        }
    }
}

/// Macro statements, hostile ones among them.
fn macro_line() -> impl Strategy<Value = String> {
    prop_oneof![
        2 => "[-+*/^&(),.:=<> \"'_0-9A-Za-z]{0,24}",
        2 => prop::sample::select(vec![
            "If x > 0 Then", "End If", "For i = 1 To 3", "Next", "Do While i < 5", "Loop", "x = x & x",
            "Debug.Print x", "ReDim a(1E+300)", "x = Space(1E+9)", "Select Case x", "Case 1", "End Select",
            "With Range(\"A1\")", "End With", "x = 1 + _", "GoTo 10", "10 x = 2", "x = Not Not x", "Dim a(3)",
            "a(5) = 1", "x = Replace(x, \"a\", x & x)", "Call Main", "On Error Resume Next", "x = 1 / 0",
        ])
        .prop_map(str::to_string),
    ]
}

proptest! {
    #![proptest_config(config(150))]

    #[test]
    fn macro_source_never_panics(lines in prop::collection::vec(macro_line(), 0..16)) {
        let src = format!("Sub Main()\n{}\nEnd Sub\n", lines.join("\n"));
        let mut wb = Workbook::with_sheet();
        let options = RunOptions { max_statements: 10_000, ..RunOptions::default() };
        let _ = vba::run(&mut wb, &src, "fuzz.bas", &options);
    }
}

/// A good package from our own writer, formulas and text in it.
fn good_package() -> Vec<u8> {
    let mut wb = Workbook::with_sheet();
    wb.add_sheet("Second").unwrap();
    for (cell, input) in
        [("A1", "2"), ("A2", "=A1*3"), ("B1", "text"), ("B2", "=CONCAT(B1,\"!\")"), ("C1", "=SEQUENCE(3)")]
    {
        let _ = wb.set_input(0, parse_cell(cell).unwrap(), input);
    }
    let _ = wb.set_input(1, parse_cell("C3").unwrap(), "=Sheet1!A2+1");
    xlsx::to_bytes(&wb, &xlsx::Layout::default()).unwrap()
}

/// The package with every part stored uncompressed, so that byte mutations reach the XML.
fn stored(package: &[u8]) -> Vec<u8> {
    let options = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
    common::rewrite_package(package, options, &mut |_, data| data).finish().unwrap().into_inner()
}

proptest! {
    #![proptest_config(config(150))]

    #[test]
    fn mutated_xlsx_packages_never_panic(
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8),
        compressed in any::<bool>(),
    ) {
        let good = good_package();
        let mut bytes = if compressed { good } else { stored(&good) };
        for (at, byte) in edits {
            let i = at.index(bytes.len());
            bytes[i] = byte;
        }
        if let Ok(imported) = xlsx::load_bytes(&bytes, Path::new("fuzz.xlsx")) {
            let _ = imported.workbook.problems();
        }
    }
}

// ---------------------------------------------------------------------------------------
// Issue 30: number format codes (cell styles, TEXT, Format), names, VBA streams, macro
// declarations and the NC readers.

/// Pieces of number format codes, hostile ones among them (65,536 exponent zeros, long
/// elapsed parts, unclosed brackets and quotes).
fn format_code() -> impl Strategy<Value = String> {
    let piece = prop_oneof![
        3 => "[-0#?.,;%E+/ \"\\\\@_*\\[\\]hmsdyAP:]{1,6}",
        1 => prop::sample::select(vec![
            "0E+", "[h]", "[mm]", "[ss]", "[>=100]", "[Red]", "[$-409]", "yyyy-mm-dd", "AM/PM", "0.0%",
            "\"text\"", "@", "#,##0", "?/?", "General",
        ])
        .prop_map(str::to_string),
        1 => (1usize..70_000, prop::sample::select(vec!["0", "s", "h", "#", "?", ","])).prop_map(|(n, s)| s.repeat(n)),
    ];
    prop::collection::vec(piece, 1..6).prop_map(|p| p.concat())
}

proptest! {
    #![proptest_config(config(120))]

    #[test]
    fn number_format_codes_never_panic(code in format_code(), n in prop_oneof![
        any::<f64>(), Just(1e308), Just(-1e-320), Just(0.5), Just(45_000.75), Just(-2.5e15),
    ]) {
        let _ = ncsheet::eval::format::number_format::shown(n, Some(&code), ncsheet::eval::dates::DateSystem::From1900);
        let mut wb = Workbook::with_sheet();
        let quoted = code.replace('"', "\"\"");
        let _ = wb.set_input(0, parse_cell("A1").unwrap(), &format!("=LEN(TEXT({n:e},\"{quoted}\"))"));
        let _ = wb.value(0, parse_cell("A1").unwrap());
        let src = format!("Sub Main()\n    Debug.Print Len(Format({n:e}, \"{quoted}\"))\nEnd Sub\n");
        let options = RunOptions { max_statements: 1_000, ..RunOptions::default() };
        let _ = vba::run(&mut wb, &src, "fuzz.bas", &options);
    }

    #[test]
    fn xlsx_styles_and_names_never_panic(
        code in format_code(),
        name in prop_oneof!["[A-Za-z_\\\\.0-9]{1,12}", (1usize..70_000).prop_map(|n| "n".repeat(n))],
        refers in "[-+*/A-Z0-9!$:(),\"# ]{0,16}",
    ) {
        let good = good_package();
        let escape = |s: &str| s.replace('&', "&amp;").replace('<', "&lt;").replace('"', "&quot;");
        let mut change = |part: &str, data: Vec<u8>| {
            let text = String::from_utf8_lossy(&data).into_owned();
            match part {
                "xl/styles.xml" => {
                    let fmt = format!(r#"<numFmts count="1"><numFmt numFmtId="200" formatCode="{}"/></numFmts>"#, escape(&code));
                    let text = text.replacen("<fonts", &format!("{fmt}<fonts"), 1);
                    text.replacen("<cellXfs count=\"1\">", "<cellXfs count=\"2\"><xf numFmtId=\"200\" applyNumberFormat=\"1\"/>", 1).into_bytes()
                }
                "xl/workbook.xml" => {
                    let defined = format!(r#"<definedNames><definedName name="{}">{}</definedName></definedNames>"#, escape(&name), escape(&refers));
                    text.replacen("</sheets>", &format!("</sheets>{defined}"), 1).into_bytes()
                }
                "xl/worksheets/sheet1.xml" => text.replacen("<c r=\"A1\"", "<c r=\"A1\" s=\"1\"", 1).into_bytes(),
                _ => data,
            }
        };
        let options = zip::write::SimpleFileOptions::default();
        let bytes = common::rewrite_package(&good, options, &mut change).finish().unwrap().into_inner();
        if let Ok(imported) = xlsx::load_bytes(&bytes, Path::new("fuzz.xlsx")) {
            let _ = imported.workbook.problems();
            let _ = imported.workbook.names();
        }
    }

    #[test]
    fn vba_streams_never_panic(bytes in prop::collection::vec(prop_oneof![
        4 => any::<u8>(),
        2 => prop::sample::select(vec![0x01u8, 0xB0, 0x3F, 0xFF, 0x00, 0x30]),
    ], 0..2_000)) {
        let mut container = vec![1u8];
        container.extend_from_slice(&bytes);
        if let Ok(out) = vba::ovba::decompress(&container) {
            prop_assert!(out.len() <= vba::ovba::MAX_DECOMPRESSED);
        }
        let _ = vba::ovba::decompress(&bytes);
        let _ = vba::read_project(&bytes);
        // What compresses decompresses to itself.
        let packed = vba::ovba::compress(&bytes).unwrap();
        prop_assert_eq!(vba::ovba::decompress(&packed).unwrap(), bytes);
    }
}

/// Module-level declarations and procedure heads, hostile ones among them.
fn declaration() -> impl Strategy<Value = String> {
    prop_oneof![
        2 => "[-+*/&(),.:=<> \"'_0-9A-Za-z]{0,24}",
        3 => prop::sample::select(vec![
            "Const A = 1", "Const A = A + 1", "Public Const B As Long = 2 ^ 40", "Dim x As Long", "Dim x, x",
            "Private y(1 To 3) As Double", "Public z As Variant", "Option Explicit", "Option Base 1",
            "Dim a(1E+300)", "Const C = \"x\" & C", "Static s", "Dim q As New Collection", "Global g",
            "Private Const D = 1: Dim e", "Dim f As String * 5", "Type T", "End Type", "Declare Sub Sleep Lib \"k\" ()",
            "Attribute VB_Name = \"M\"", "Enum E", "End Enum",
            // A Type holding a large array, an array of such records, a write into one record's
            // array (issue 30, fifth round: measured once per record, copies not charged).
            "x(1 To 100000) As Double", "Dim t(1 To 100000) As T", "t(2).x(3) = 4",
        ])
        .prop_map(str::to_string),
    ]
}

proptest! {
    #![proptest_config(config(120))]

    #[test]
    fn macro_declarations_never_panic(
        module in prop::collection::vec(declaration(), 0..24),
        local in prop::collection::vec(declaration(), 0..12),
    ) {
        let src = format!("{}\nSub Main()\n{}\nDebug.Print 1\nEnd Sub\n", module.join("\n"), local.join("\n"));
        let mut wb = Workbook::with_sheet();
        let options = RunOptions { max_statements: 10_000, ..RunOptions::default() };
        let _ = vba::run(&mut wb, &src, "fuzz.bas", &options);
        let _ = vba::parse(&src, "fuzz.bas", &wb);
    }
}

/// NC blocks, hostile ones among them: every dialect's words, huge and tiny numbers, arcs of
/// nearly no radius, unclosed comments.
fn nc_block() -> impl Strategy<Value = String> {
    prop_oneof![
        2 => "[GMXYZIJKRFSTPQDNLOH0-9. +\\-=();#%:\\[\\]]{0,20}",
        3 => prop::sample::select(vec![
            "G0 X0 Y0 Z5", "G1 X10 F100", "G2 X1 Y0 I0.0005 J0", "G3 X0 Y0 R0.001", "G2 X1E+300 I1",
            "M3 S1000", "M6 T1", "T2", "M30", "%", "(unclosed", "; comment", "G18", "G96 S200", "G95 F0.1",
            "N10 G4 P1", "CYCLE81(10,0,2,-5)", "L X+10 Y+0 R0 FMAX", "CC X0 Y0", "C X+10 Y+0 DR+",
            "BEGIN PGM 1 MM", "END PGM 1 MM", "TOOL CALL 1 Z S1000", "G1 X-1E-320", "G1 XNaN", "O0001",
        ])
        .prop_map(str::to_string),
    ]
}

proptest! {
    #![proptest_config(config(120))]

    #[test]
    fn nc_readers_never_panic(blocks in prop::collection::vec(nc_block(), 0..20)) {
        let text = blocks.join("\n");
        for dialect in ncsheet::nc::dialect::all() {
            if let Ok((program, _)) = ncsheet::nc::read::read_dialect(&text, dialect, None) {
                let rates = ncsheet::nc::motion::Rates { accel: 1000.0, rapid: 10_000.0 };
                let _ = ncsheet::nc::motion::program_times(&program, rates);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Issue 30, second pass: byte mutations that reach past the first check of each reader —
// the streams of a real vbaProject.bin (its dir stream and module sources are MS-OVBA
// compressed), the styles and workbook parts of a package holding defined names, and
// declarations joined on one line with `:`.

/// The vbaProject.bin of a vendored workbook with a macro (Apache POI's SimpleMacro.xlsm).
fn good_vba_project() -> &'static [u8] {
    static PROJECT: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
    PROJECT.get_or_init(|| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/excel-corpus/public/poi/test-data_spreadsheet_SimpleMacro.xlsm");
        let mut zip = zip::ZipArchive::new(std::fs::File::open(path).unwrap()).unwrap();
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut zip.by_name("xl/vbaProject.bin").unwrap(), &mut bytes).unwrap();
        bytes
    })
}

/// The paths of a compound file's streams (PROJECT, VBA/dir, the modules, …).
fn streams(bytes: &[u8]) -> Vec<String> {
    let cfb = cfb::CompoundFile::open(std::io::Cursor::new(bytes)).unwrap();
    cfb.walk().filter(|e| e.is_stream()).map(|e| e.path().to_string_lossy().into_owned()).collect()
}

/// A package like [`good_package`] with defined names and a number format of its own.
fn good_package_with_names() -> Vec<u8> {
    let mut wb = Workbook::with_sheet();
    let _ = wb.set_input(0, parse_cell("A1").unwrap(), "2");
    let _ = wb.set_input(0, parse_cell("A2").unwrap(), "=Rate*A1");
    wb.define_name("Rate", "=Sheet1!$A$1*2", None).unwrap();
    wb.define_name("Twice", "=LAMBDA(x, 2*x)", None).unwrap();
    let _ = wb.set_input(0, parse_cell("A3").unwrap(), "=Twice(A2)");
    xlsx::to_bytes(&wb, &xlsx::Layout::default()).unwrap()
}

proptest! {
    #![proptest_config(config(150))]

    #[test]
    fn mutated_vba_project_streams_never_panic(
        which in any::<prop::sample::Index>(),
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8),
        cut in prop::option::of(any::<prop::sample::Index>()),
    ) {
        let good = good_vba_project();
        let names = streams(good);
        let path = &names[which.index(names.len())];
        let bytes = common::vba::with_stream(good, path, |old| mutated(old.to_vec(), &edits, cut));
        if let Ok(project) = vba::read_project(&bytes) {
            let wb = Workbook::with_sheet();
            for m in &project.modules {
                let _ = vba::parse(&m.source, &m.name, &wb);
            }
        }
    }

    #[test]
    fn mutated_styles_and_workbook_parts_never_panic(
        styles in any::<bool>(),
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8),
        cut in prop::option::of(any::<prop::sample::Index>()),
    ) {
        let good = good_package_with_names();
        let target = if styles { "xl/styles.xml" } else { "xl/workbook.xml" };
        let mut change = |part: &str, data: Vec<u8>| if part == target { mutated(data, &edits, cut) } else { data };
        let options = zip::write::SimpleFileOptions::default();
        let bytes = common::rewrite_package(&good, options, &mut change).finish().unwrap().into_inner();
        if let Ok(imported) = xlsx::load_bytes(&bytes, Path::new("fuzz.xlsx")) {
            let _ = imported.workbook.problems();
            let _ = imported.workbook.names();
            let _ = imported.workbook.value(0, parse_cell("A3").unwrap());
        }
    }

    #[test]
    fn declarations_joined_with_colons_never_panic(
        module in prop::collection::vec(declaration(), 0..24),
        local in prop::collection::vec(prop_oneof![declaration(), macro_line()], 0..24),
    ) {
        let src = format!("{}\nSub Main()\n{}\nEnd Sub\n", module.join(": "), local.join(": "));
        let mut wb = Workbook::with_sheet();
        let options = RunOptions { max_statements: 10_000, ..RunOptions::default() };
        let _ = vba::run(&mut wb, &src, "fuzz.bas", &options);
    }
}

/// The fuzz targets reach past the first check: the good inputs they mutate are read whole.
#[test]
fn the_fuzzed_inputs_start_from_readable_ones() {
    let project = vba::read_project(good_vba_project()).unwrap();
    assert!(!project.modules.is_empty());
    assert!(streams(good_vba_project()).iter().any(|s| s.ends_with("dir")));
    let imported = xlsx::load_bytes(&good_package_with_names(), Path::new("good.xlsx")).unwrap();
    // Rate = A1 * 2 = 4, A2 = 8, Twice(A2) = 16.
    assert_eq!(imported.workbook.value(0, parse_cell("A3").unwrap()), ncsheet::eval::Value::Number(16.0));
}

// ---------------------------------------------------------------------------------------
// Issue 30, third pass: the compound file's own structures ([MS-CFB] 2.2–2.6). An .xls and a
// vbaProject.bin are both compound files; random bytes rarely land on the few fields that
// steer a reader (sector shift, FAT and DIFAT counts and starts, the directory's sibling
// and child ids, a stream's start and size, the mini-FAT), so these mutations aim at them.

const MAX_REGULAR_SECTOR: u32 = 0xFFFF_FFFA;

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap())
}

/// Where a good compound file keeps its structures, to aim the mutations at them: the byte
/// offsets of its FAT sectors, directory entries and mini-FAT sectors.
struct CfbLayout {
    fat: Vec<usize>,
    entries: Vec<usize>,
    minifat: Vec<usize>,
    sector_len: usize,
}

impl CfbLayout {
    /// The layout of a well-formed file (its FAT listed in the header's DIFAT alone).
    fn of(bytes: &[u8]) -> CfbLayout {
        let sector_len = 1usize << u16::from_le_bytes([bytes[30], bytes[31]]);
        let offset = |sector: u32| (sector as usize + 1) * sector_len;
        let fat: Vec<usize> = (0..u32_at(bytes, 44) as usize).map(|i| offset(u32_at(bytes, 76 + 4 * i))).collect();
        let per_sector = sector_len / 4;
        let next = |sector: u32| u32_at(bytes, fat[sector as usize / per_sector] + 4 * (sector as usize % per_sector));
        let chain = |mut sector: u32| {
            let mut out = Vec::new();
            while sector <= MAX_REGULAR_SECTOR {
                out.push(offset(sector));
                sector = next(sector);
            }
            out
        };
        let entries: Vec<usize> = chain(u32_at(bytes, 48))
            .into_iter()
            .flat_map(|at| (0..sector_len / 128).map(move |i| at + 128 * i))
            .collect();
        let minifat = chain(u32_at(bytes, 60));
        CfbLayout { fat, entries, minifat, sector_len }
    }
}

/// One field of a compound file given another value.
#[derive(Clone, Debug)]
enum CfbChange {
    /// A header field (offset, width): versions, shifts, counts, first sectors, the cutoff,
    /// the header's DIFAT.
    Header(prop::sample::Index, CfbValue),
    /// An entry of the FAT: a sector's next sector.
    Fat(prop::sample::Index, CfbValue),
    /// A directory entry's field: name length, type, color, siblings, child, start, size.
    Entry(prop::sample::Index, prop::sample::Index, CfbValue),
    /// An entry of the mini-FAT.
    MiniFat(prop::sample::Index, CfbValue),
}

/// A value for a field: one of the special sector ids and edges, the field's own index (a
/// chain or tree that loops onto itself), or any number.
#[derive(Clone, Debug)]
enum CfbValue {
    Special(u32),
    Itself,
    Before,
    Any(u32),
}

fn cfb_value() -> impl Strategy<Value = CfbValue> {
    let special = [0, 1, 2, 3, 6, 9, 12, 16, 0xFF, 0x1000, 0xFFFF, 0x1_0000, 0x7FFF_FFFF, MAX_REGULAR_SECTOR]
        .into_iter()
        .chain([0xFFFF_FFFB, 0xFFFF_FFFC, 0xFFFF_FFFD, 0xFFFF_FFFE, 0xFFFF_FFFF])
        .collect::<Vec<u32>>();
    prop_oneof![
        4 => prop::sample::select(special).prop_map(CfbValue::Special),
        2 => Just(CfbValue::Itself),
        1 => Just(CfbValue::Before),
        1 => any::<u32>().prop_map(CfbValue::Any),
    ]
}

fn cfb_change() -> impl Strategy<Value = CfbChange> {
    let index = any::<prop::sample::Index>;
    prop_oneof![
        3 => (index(), cfb_value()).prop_map(|(i, v)| CfbChange::Header(i, v)),
        2 => (index(), cfb_value()).prop_map(|(i, v)| CfbChange::Fat(i, v)),
        4 => (index(), index(), cfb_value()).prop_map(|(e, f, v)| CfbChange::Entry(e, f, v)),
        1 => (index(), cfb_value()).prop_map(|(i, v)| CfbChange::MiniFat(i, v)),
    ]
}

/// The header's fields as (offset, width) ([MS-CFB] 2.2), the DIFAT's first entries last.
const CFB_HEADER_FIELDS: [(usize, usize); 15] = [
    (26, 2),
    (30, 2),
    (32, 2),
    (40, 4),
    (44, 4),
    (48, 4),
    (56, 4),
    (60, 4),
    (64, 4),
    (68, 4),
    (72, 4),
    (76, 4),
    (80, 4),
    (84, 4),
    (28, 2),
];

/// A directory entry's fields as (offset, width) ([MS-CFB] 2.6.1).
const CFB_ENTRY_FIELDS: [(usize, usize); 11] =
    [(0, 2), (64, 2), (66, 1), (67, 1), (68, 4), (72, 4), (76, 4), (116, 4), (120, 4), (124, 4), (120, 8)];

/// `bytes` with the fields `changes` name set, each value written little-endian in its width.
fn cfb_mutated(mut bytes: Vec<u8>, changes: &[CfbChange]) -> Vec<u8> {
    let layout = CfbLayout::of(&bytes);
    let per_sector = layout.sector_len / 4;
    for change in changes {
        // (byte offset, width, the field's own index for Itself/Before)
        let (at, width, own, value) = match change {
            CfbChange::Header(i, v) => {
                let (at, width) = CFB_HEADER_FIELDS[i.index(CFB_HEADER_FIELDS.len())];
                (at, width, 0, v)
            }
            CfbChange::Fat(i, v) => {
                let n = i.index(layout.fat.len() * per_sector);
                (layout.fat[n / per_sector] + 4 * (n % per_sector), 4, n, v)
            }
            CfbChange::Entry(e, f, v) => {
                let n = e.index(layout.entries.len());
                let (at, width) = CFB_ENTRY_FIELDS[f.index(CFB_ENTRY_FIELDS.len())];
                (layout.entries[n] + at, width, n, v)
            }
            CfbChange::MiniFat(_, _) if layout.minifat.is_empty() => continue,
            CfbChange::MiniFat(i, v) => {
                let n = i.index(layout.minifat.len() * per_sector);
                (layout.minifat[n / per_sector] + 4 * (n % per_sector), 4, n, v)
            }
        };
        let value = match value {
            CfbValue::Special(v) | CfbValue::Any(v) => u64::from(*v),
            CfbValue::Itself => own as u64,
            CfbValue::Before => own.saturating_sub(1) as u64,
        };
        // An 8-byte size is made huge whole: past what any file holds.
        let value = if width == 8 { value << 32 | value } else { value };
        bytes[at..at + width].copy_from_slice(&value.to_le_bytes()[..width]);
    }
    bytes
}

fn good_xls() -> Vec<u8> {
    std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/excel-corpus/xls/testNames.xls")).unwrap()
}

proptest! {
    #![proptest_config(config(400))]

    #[test]
    fn vba_projects_with_mutated_compound_file_structures_never_panic(
        changes in prop::collection::vec(cfb_change(), 1..4),
    ) {
        let bytes = cfb_mutated(good_vba_project().to_vec(), &changes);
        match vba::read_project(&bytes) {
            Ok(project) => {
                let wb = Workbook::with_sheet();
                for m in &project.modules {
                    let _ = vba::parse(&m.source, &m.name, &wb);
                }
            }
            Err(e) => prop_assert!(!e.stream.is_empty() && !e.message.is_empty(), "{e:?}"),
        }
    }

    #[test]
    fn xls_files_with_mutated_compound_file_structures_never_panic(
        changes in prop::collection::vec(cfb_change(), 1..4),
    ) {
        let bytes = cfb_mutated(good_xls(), &changes);
        let _ = ncsheet::io::Format::detect(&bytes, Path::new("hostile.xls"));
        match ncsheet::io::open_bytes(bytes, Path::new("hostile.xls"), ncsheet::io::Format::Xls, None) {
            Ok(opened) => {
                let _ = opened.workbook.problems();
                let _ = opened.workbook.value(0, parse_cell("A1").unwrap());
            }
            Err(e) => prop_assert!(e.to_string().starts_with("hostile.xls"), "{e}"),
        }
    }
}

/// The compound-file mutations reach the structures they aim at in both good files.
#[test]
fn the_compound_files_mutated_have_each_structure() {
    for bytes in [good_vba_project().to_vec(), good_xls()] {
        let layout = CfbLayout::of(&bytes);
        assert_eq!(layout.sector_len, 512);
        assert!(!layout.fat.is_empty() && layout.entries.len() >= 4 && !layout.minifat.is_empty());
        // The root entry is the first, of type 5 ([MS-CFB] 2.6.1).
        assert_eq!(bytes[layout.entries[0] + 66], 5);
    }
}
