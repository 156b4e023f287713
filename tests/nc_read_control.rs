//! What a hand-written program does on its control, as the readers take it: the tool length
//! offset in force at each move, and what the control (or the writers) refuse. LinuxCNC programs are asked of LinuxCNC's own interpreter, rs274, with a tool table
//! (tool 1: 50 mm, tool 2: 30 mm): it reports the offset it applies (`USE_TOOL_LENGTH_OFFSET`)
//! apart from the programmed positions. The other controls from their manuals: Fanuc mill
//! (G43 H / G49, as LinuxCNC), Sinumerik (Function Manual Tool offset: "D0 compensation
//! deselection", D1 the default edge after T), Heidenhain (TOOL CALL always applies the
//! table's length).

mod common;

use std::collections::HashMap;

use ncsheet::nc::program::{Block, Machine, Program, ToolChange, ToolOffset};
use ncsheet::nc::read::{self, Family};

/// The tool table of these tests: tool number → length (mm).
fn lengths() -> HashMap<u32, f64> {
    HashMap::from([(1, 50.0), (2, 30.0)])
}

/// rs274's table: lengths in inches (its default machine units, see `common::rs274`).
fn rs274_table(dir: &std::path::Path) -> std::path::PathBuf {
    let path = dir.join("tools.tbl");
    let rows: String = lengths().iter().map(|(t, l)| format!("T{t} P{t} Z{:.9} D0.25\n", l / 25.4)).collect();
    std::fs::write(&path, rows).unwrap();
    path
}

/// The length (mm) the model says is in force at each straight move with an axis, in order.
fn model_offsets(p: &Program) -> Vec<f64> {
    let table = lengths();
    let (mut tool, mut offset) = (None::<u32>, ToolOffset::Cancelled);
    let mut out = Vec::new();
    for b in &p.blocks {
        match b {
            Block::Tool(ToolChange { number, offset: o }) => (tool, offset) = (Some(*number), *o),
            Block::LengthOffset(o) => offset = *o,
            Block::Rapid(t) | Block::Line { to: t, .. } if t.axes().next().is_some() => out.push(match offset {
                ToolOffset::Cancelled => 0.0,
                ToolOffset::Own => table[&tool.unwrap()],
                ToolOffset::Number(n) => table[&n],
            }),
            _ => {}
        }
    }
    out
}

/// Hand-written LinuxCNC programs: `T1 M6` alone, G43 on a later line (after a move and
/// before one), G43 H of another tool, a tool change while G43 is in force, G49.
const PROGRAMS: &[&str] = &[
    // The usual hand-written order: the change, then G43 with the first Z.
    "G21 G17 G90 G40 G49\nT1 M6\nG0 G43 H1 Z50\nG0 X0 Y0\nG1 Z-1 F100\nG0 Z50\nM2\n",
    // No G43 at all: the coordinates stay the spindle's.
    "G21 G17 G90 G40\nT1 M6\nG0 X0 Y0 Z100\nG1 Z20 F100\nM2\n",
    // A move before G43, G43 without H (the loaded tool), G49, then a change with none.
    "G21 G17 G90\nT1 M6\nG0 X0 Y0 Z100\nG43\nG0 Z50\nG1 Z-1 F100\nG49\nG0 Z120\nT2 M6\nG0 Z110\nM2\n",
    // A change while G43 is in force keeps the first tool's length; G43 H2 then takes tool 2's.
    "G21 G17 G90\nT1 M6 G43\nG0 X0 Y0 Z50\nT2 M6\nG0 Z40\nG43 H2 Z30\nG1 Z-1 F100\nG49 G0 Z100\nM2\n",
    // Another tool's register with the change.
    "G21 G17 G90\nT2 M6 G43 H1\nG0 X0 Y0 Z50\nM2\n",
    // T2 while tool 1 cuts only selects the next tool: G43 still takes the loaded tool 1,
    // and M6 alone changes to tool 2.
    "G21 G17 G90\nT1 M6\nG43\nG0 X0 Y0 Z50\nT2\nG43\nG0 Z40\nG1 Z-1 F100\nM6\nG0 Z60\nG43\nG0 Z30\nM2\n",
];

#[test]
fn linuxcnc_length_offsets_are_what_rs274_applies() {
    if !common::rs274::available() {
        eprintln!("rs274 not installed: skipped");
        return;
    }
    for (k, text) in PROGRAMS.iter().enumerate() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.ngc");
        std::fs::write(&path, text).unwrap();
        let canon = common::rs274::canon_with_tools(&path, Some(&rs274_table(dir.path()))).unwrap();
        let theirs: Vec<f64> =
            common::rs274::moves_with_length_offset(&canon).into_iter().map(|(_, offset)| offset).collect();
        let p = read::read(text, Family::LinuxCnc, Some(Machine::Mill)).unwrap();
        let ours = model_offsets(&p);
        assert_eq!(ours.len(), theirs.len(), "program {k}: {p:?}\n{canon}");
        for (i, (a, b)) in ours.iter().zip(&theirs).enumerate() {
            assert!((a - b).abs() < 1e-3, "program {k}, move {i}: ours {a} mm, rs274 {b} mm\n{text}\n{canon}");
        }
    }
}

#[test]
fn a_tool_change_alone_applies_no_length_on_linuxcnc_and_a_fanuc_mill() {
    for family in [Family::LinuxCnc, Family::Fanuc] {
        let p = read::read("G21 G17 G90\nT1 M6\nG0 X0 Y0 Z100\nM30\n", family, Some(Machine::Mill)).unwrap();
        assert_eq!(p.blocks[0], Block::Tool(ToolChange { number: 1, offset: ToolOffset::Cancelled }), "{family:?}");
    }
    // Fanuc: G43 H1 on the line after the change, before any move, is that change's offset.
    let p = read::read("G21 G17 G90\nT1 M6\nG0 G43 H1 Z50.\nM30\n", Family::Fanuc, Some(Machine::Mill)).unwrap();
    assert_eq!(p.blocks[0], Block::Tool(ToolChange::new(1)));
    // After a move, G49 is a block of its own, and the written program says so again.
    let text = "G21 G17 G90\nT1 M6 G43 H1\nG0 X0 Y0 Z50.\nG49\nG0 Z100.\nM30\n";
    let p = read::read(text, Family::Fanuc, Some(Machine::Mill)).unwrap();
    assert_eq!(p.blocks[2], Block::LengthOffset(ToolOffset::Cancelled));
    let written = ncsheet::nc::by_name("iso").unwrap().render(&p).unwrap();
    assert!(written.lines().any(|l| l.ends_with(" G49")), "{written}");
    assert_eq!(read::read(&written, Family::Fanuc, Some(Machine::Mill)).unwrap().blocks, p.blocks);
}

#[test]
fn a_t_word_without_m6_selects_the_next_tool_on_linuxcnc_and_a_fanuc_mill() {
    let text = "G21 G17 G90\nT1 M6 G43 H1\nG0 X0 Y0 Z50\nT2\nG1 Z-1 F100\nG0 Z50\nM6\nG0 Z40\nM30\n";
    for family in [Family::LinuxCnc, Family::Fanuc] {
        let p = read::read(text, family, Some(Machine::Mill)).unwrap();
        let tools: Vec<u32> =
            p.blocks.iter().filter_map(|b| if let Block::Tool(t) = b { Some(t.number) } else { None }).collect();
        assert_eq!(tools, [1, 2], "{family:?}: {:?}", p.blocks);
        // The change comes after the cut, where M6 stands: after the move to Z50.
        let change = p.blocks.iter().rposition(|b| matches!(b, Block::Tool(_))).unwrap();
        assert!(matches!(p.blocks[change - 1], Block::Rapid(_)), "{family:?}: {:?}", p.blocks);
        // M6 with no tool selected names its place.
        let e = read::read("G21 G17 G90\nG0 X0 Y0 Z50\nM6\n", family, Some(Machine::Mill)).unwrap_err();
        assert_eq!((e.line, e.column), (3, 1), "{family:?}: {e}");
    }
    // Read with no machine given: a Fanuc program is a mill's until a G18 says otherwise, so
    // a T right after the change, before any move (CAM's usual preselect), only selects.
    let text = "G21 G17 G90\nT1 M6 G43 H1\nT2\nG0 X0 Y0 Z50\nG0 Z100\nM6\nM30\n";
    let p = read::read(text, Family::Fanuc, None).unwrap();
    let tools: Vec<u32> =
        p.blocks.iter().filter_map(|b| if let Block::Tool(t) = b { Some(t.number) } else { None }).collect();
    assert_eq!(tools, [1, 2], "{:?}", p.blocks);
    let change = p.blocks.iter().position(|b| matches!(b, Block::Tool(ToolChange { number: 2, .. }))).unwrap();
    assert_eq!(p.blocks[..change].iter().filter(|b| matches!(b, Block::Rapid(_))).count(), 2, "{:?}", p.blocks);
    let unknown_lathe = read::read("G21 G18\nT0101\nG0 X50 Z2\nM30\n", Family::Fanuc, None).unwrap();
    assert!(unknown_lathe.blocks.iter().any(|b| matches!(b, Block::Tool(ToolChange { number: 1, .. }))));
    // A lathe's turret and Sinumerik change with T itself.
    let lathe = read::read("G18 G21\nT0202\nG0 X50 Z2\nM30\n", Family::Fanuc, Some(Machine::Lathe)).unwrap();
    assert!(lathe.blocks.iter().any(|b| matches!(b, Block::Tool(ToolChange { number: 2, .. }))));
    let sinumerik = read::read("N10 T1 D1\nN20 G0 X0 Y0 Z5\n", Family::Sinumerik, Some(Machine::Mill)).unwrap();
    assert_eq!(sinumerik.blocks[0], Block::Tool(ToolChange::new(1)));
}

#[test]
fn sinumerik_takes_the_cutting_edge_d_and_d1_by_default() {
    let read = |t: &str| read::read(t, Family::Sinumerik, Some(Machine::Mill)).unwrap().blocks;
    assert_eq!(read("N10 T1 M6\nN20 G0 X0 Y0 Z5\n")[0], Block::Tool(ToolChange::new(1)));
    let b = read("N10 T1 M6 D2\nN20 G0 X0 Y0 Z5\nN30 D0\nN40 G0 Z50\n");
    assert_eq!(b[0], Block::Tool(ToolChange { number: 1, offset: ToolOffset::Number(2) }));
    assert_eq!(b[2], Block::LengthOffset(ToolOffset::Cancelled));
}

#[test]
fn heidenhain_tool_call_always_applies_the_table_length() {
    let text = "0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S1000\n2 L X+0 Y+0 Z+5 R0 FMAX M3\n3 END PGM T MM\n";
    let p = ncsheet::nc::by_name("heidenhain").unwrap().read(text, None).unwrap().0;
    assert_eq!(p.blocks.iter().find(|b| matches!(b, Block::Tool(_))), Some(&Block::Tool(ToolChange::new(1))));
}

#[test]
fn a_length_offset_without_a_tool_or_on_a_fanuc_lathe_is_refused_at_its_column() {
    let e = read::read("G21 G17\nG43 H1\n", Family::LinuxCnc, Some(Machine::Mill)).unwrap_err();
    assert_eq!((e.line, e.column), (2, 1), "{e}");
    let e = read::read("G21 G18\nT0101\nG43 H1\n", Family::Fanuc, Some(Machine::Lathe)).unwrap_err();
    assert_eq!((e.line, e.column), (3, 1), "{e}");
    // A Fanuc lathe's T word is tool and offset: T1 names no tool.
    let e = read::read("G21 G18\nG99\nT1\n", Family::Fanuc, Some(Machine::Lathe)).unwrap_err();
    assert_eq!((e.line, e.column), (3, 1), "{e}");
}

/// Sinumerik's D0 deselects length and radius (Function Manual Tool offset: "D0
/// compensation deselection"), so G41/G42 after it has no radius: the writer refuses it and
/// so does the reader, at the G41/G42 (and with no tool called at all).
#[test]
fn sinumerik_radius_compensation_after_d0_is_refused_at_its_column() {
    for (text, line, column) in [
        ("N10 T1 M6 D0\nN20 G0 X0 Y0 Z5\nN30 G41 G1 X10 F100\n", 3, 5),
        ("N10 T1 M6\nN20 G0 X0 Y0 Z5\nN30 D0\nN40 G1 G42 X10 F100\n", 4, 8),
        ("N10 T1 M6 D0 G41\nN20 G1 X10 F100\n", 1, 14),
        ("N10 G0 X0 Y0 Z5\nN20 G41 G1 X10 F100\n", 2, 5),
    ] {
        let e = read::read(text, Family::Sinumerik, Some(Machine::Mill)).unwrap_err();
        assert_eq!((e.line, e.column), (line, column), "{text}: {e}");
    }
    // With an edge (D1 by default, or D2 again after D0) it is read.
    let ok = "N10 T1 M6 D0\nN20 G0 X0 Y0 Z5\nN30 D2\nN40 G41 G1 X10 F100\nN50 G40 G0 Z50\n";
    let p = read::read(ok, Family::Sinumerik, Some(Machine::Mill)).unwrap();
    assert!(p.blocks.contains(&Block::LengthOffset(ToolOffset::Number(2))), "{:?}", p.blocks);
    // The writer's refusal of the same program, for the record.
    let mut bad = p.clone();
    let at = bad.blocks.iter().position(|b| *b == Block::LengthOffset(ToolOffset::Number(2))).unwrap();
    bad.blocks.remove(at);
    assert!(ncsheet::nc::by_name("sinumerik").unwrap().render(&bad).is_err());
}

/// Every refusal the writers make on one block's values, the readers make on a hand-written
/// program, at its line and word: rs274 refuses the first ones too (its messages quoted);
/// the rest are the model's and the writers' limits (tool 0, speeds, dwell 0, G96 on a mill,
/// the control's digits), refused so that what is read can be written again.
#[test]
fn what_the_writers_refuse_is_refused_when_read() {
    let head = "G21 G17 G90\nT1 M6 G43\nS1000 M3\nG94\nG0 X0 Y0 Z5\n";
    let rs274_refuses = [
        ("G1 X1 F0", 7, "zero feed rate"),
        ("G1 X1 F-5", 7, "Negative f word"),
        ("S-5 M3", 1, "Negative spindle speed"),
        ("G4 P-1", 4, "Dwell time"),
        ("G2 X0 Y0 I0 J0 F100", 1, "Zero-radius arc"),
    ];
    let check_rs274 = common::rs274::available();
    for (body, column, theirs) in rs274_refuses {
        let text = format!("{head}{body}\nM2\n");
        let e = read::read(&text, Family::LinuxCnc, Some(Machine::Mill)).unwrap_err();
        assert_eq!((e.line, e.column), (6, column), "{body}: {e}");
        if check_rs274 {
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join("p.ngc");
            std::fs::write(&path, &text).unwrap();
            let complaint = common::rs274::canon(&path).unwrap_err();
            assert!(complaint.contains(theirs), "{body}: {complaint}");
        }
    }
    for (body, column) in [
        ("S0 M3", 1),
        ("S200000 M3", 1),
        ("T0 M6", 1),
        ("T100 M6 G43", 1),
        ("G43 H100", 5),
        ("G4 P0", 4),
        ("G96 D2000 S100 M3", 11),
        ("G1 X1234567.5 F100", 4),
    ] {
        let text = format!("{head}{body}\nM2\n");
        let e = read::read(&text, Family::LinuxCnc, Some(Machine::Mill)).unwrap_err();
        assert_eq!((e.line, e.column), (6, column), "{body}: {e}");
    }
    // Plain language: the same refusals, at the line and word.
    let plain = |body: &str| {
        let text =
            format!("0 BEGIN PGM A MM\n1 TOOL CALL 1 Z S1000\n2 L X+0 Y+0 Z+5 R0 FMAX M3\n{body}\n9 END PGM A MM\n");
        ncsheet::nc::by_name("heidenhain").unwrap().read(&text, None).unwrap_err()
    };
    for (body, line, column) in [
        ("3 L X+5 F0", 4, 9),
        ("3 TOOL CALL 100 Z", 4, 13),
        ("3 L X+123456789 F100", 4, 3),
        ("3 CYCL DEF 9.0 DWELL TIME\n4 CYCL DEF 9.1 DWELL 0", 5, 22),
    ] {
        let e = plain(body);
        assert_eq!((e.line, e.column), (line, column), "{body}: {e}");
    }
    // NC31 has the axes X and Z only; a Fanuc program number is O0001–O9999.
    let e = read::read("N001 X10 Y5 Z1 E\nN002 M02\n", Family::Nc31, None).unwrap_err();
    assert_eq!((e.line, e.column), (1, 10), "{e}");
    let e = read::read("%\nO12345 (X)\nG21 G17 G90\nM30\n%\n", Family::Fanuc, None).unwrap_err();
    assert_eq!((e.line, e.column), (2, 1), "{e}");
}

/// Fanuc's and LinuxCNC's D with G41/G42 names the radius register (on LinuxCNC a tool
/// number of the table; without D the loaded tool's): the model holds one register for the
/// program (`cam --offset`, issue 32) or each tool's own, so `D2` after `T1` is read as the
/// program's register 2, and a program mixing it with the tool's own is refused at the D.
#[test]
fn a_radius_register_other_than_the_tools_is_the_programs_and_a_mixture_is_refused() {
    let head = "G21 G17 G90\nT1 M6 G43\nS1000 M3\nG94\nG0 X0 Y0 Z5\n";
    for family in [Family::LinuxCnc, Family::Fanuc] {
        let p = read::read(&format!("{head}G41 D2 G1 X5 F100\nG40\nM2\n"), family, Some(Machine::Mill)).unwrap();
        assert_eq!(p.radius_offset, Some(2), "{family:?}");
        let own = read::read(&format!("{head}G41 D1 G1 X5 F100\nM2\n"), family, Some(Machine::Mill)).unwrap();
        assert_eq!(own.radius_offset, None, "{family:?}");
        let mixed = format!("{head}G41 D2 G1 X5 F100\nG40 G1 X6\nG42 D1 G1 X10\nM2\n");
        let e = read::read(&mixed, family, Some(Machine::Mill)).unwrap_err();
        assert_eq!((e.line, e.column), (8, 5), "{e}");
        let e = read::read("G21 G17 G90\nG0 X0 Y0 Z5\nG42 G1 X5 F100\n", family, Some(Machine::Mill)).unwrap_err();
        assert_eq!((e.line, e.column), (3, 1), "{e}");
    }
}

/// `Nc.Tool N, Offset:=` gives the length offset register (0: none), written for LinuxCNC
/// and read by rs274 with the tool table: tool 1 with its own 50 mm, with tool 2's 30 mm,
/// with none.
#[test]
fn a_macro_tool_change_gives_its_length_offset() {
    use ncsheet::vba::{self, RunOptions};
    let cases = [("Nc.Tool 1", ToolOffset::Own, 50.0), ("Nc.Tool 1, 2", ToolOffset::Number(2), 30.0)];
    let cases = cases.into_iter().chain([("Nc.Tool 1, Offset:=0", ToolOffset::Cancelled, 0.0)]);
    for (call, offset, length) in cases {
        let src = format!(
            "Sub Main()\n    Nc.Machine = \"mill\"\n    {call}\n    Nc.FeedPerMin\n    Nc.Spindle 1000\n    Nc.Rapid 0, 0, 50\n    \
             Nc.Line 0, 0, -1, 100\nEnd Sub\n"
        );
        let mut wb = ncsheet::workbook::Workbook::with_sheet();
        let out = vba::run(&mut wb, &src, "tool.bas", &RunOptions::default()).unwrap();
        assert_eq!(out.program.blocks[0], Block::Tool(ToolChange { number: 1, offset }), "{call}");
        if !common::rs274::available() {
            continue;
        }
        let text = ncsheet::nc::by_name("linuxcnc").unwrap().render(&out.program).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.ngc");
        std::fs::write(&path, &text).unwrap();
        let canon = common::rs274::canon_with_tools(&path, Some(&rs274_table(dir.path()))).unwrap();
        let moves = common::rs274::moves_with_length_offset(&canon);
        assert!(!moves.is_empty() && moves.iter().all(|(_, o)| (o - length).abs() < 1e-3), "{call}: {text}\n{canon}");
    }
    let mut wb = ncsheet::workbook::Workbook::with_sheet();
    let e =
        vba::run(&mut wb, "Sub Main()\n    Nc.Tool 1, 100\nEnd Sub\n", "t.bas", &RunOptions::default()).unwrap_err();
    assert_eq!(e.message, "Nc.Tool: Offset is an offset number from 1 to 99, or 0 for none");
}

/// A Fanuc main program and the subprograms written after it in the same file, as the 0i-MC
/// manual (B-64124EN/01 §12.3, "Subprogram (M98, M99)") writes them: `M98 P1002 L3` and the
/// packed `M98 P21002` ("M98 P51002 … Call the subprogram (number 1002) five times"), a
/// subprogram calling another (two levels), and `M99 P30` returning to the caller's `N30`
/// instead of the block after the call.
const FANUC_CALLS: &str = "O0001 (CALLS)\nG21 G17 G90 G94\nT1 M6\nS1000 M3\nG0 X0 Y0 Z5\nM98 P1002 L3\n\
M98 P21002 ;G0 X50\nM98 P1003\nN20 G0 Z40\nN30 G0 Z50\nM30\n\
O1002\nG91 G1 Z-6 F100\nX10\nG0 Z6\nG90 M99\n\
O1003\nG1 X60 F200\nM98 P1002\nM99 P30\n";

/// The same program written out flat by hand: what the control runs.
const FANUC_FLAT: &str = "O0001 (CALLS)\nG21 G17 G90 G94\nT1 M6\nS1000 M3\nG0 X0 Y0 Z5\n\
G91 G1 Z-6 F100\nX10\nG0 Z6\nG90\nG91 G1 Z-6 F100\nX10\nG0 Z6\nG90\nG91 G1 Z-6 F100\nX10\nG0 Z6\nG90\n\
G91 G1 Z-6 F100\nX10\nG0 Z6\nG90\nG91 G1 Z-6 F100\nX10\nG0 Z6\nG90\nG0 X50\n\
G1 X60 F200\nG91 G1 Z-6 F100\nX10\nG0 Z6\nG90\nG0 Z50\nM30\n";

/// The same calls in LinuxCNC's O-codes (o-code.adoc: `sub`/`call`, `repeat`), for rs274.
const LINUXCNC_CALLS: &str = "o1002 sub\nG91 G1 Z-6 F100\nX10\nG0 Z6\nG90\no1002 endsub\n\
G21 G17 G90 G94\nT1 M6\nS1000 M3\nG0 X0 Y0 Z5\no100 repeat [5]\no1002 call\no100 endrepeat\nG90 G0 X50\n\
G1 X60 F200\no1002 call\nG90 G0 Z50\nM2\n";

/// Where each move of a program read back ends, every axis filled in.
fn end_points(p: &Program) -> Vec<[f64; 3]> {
    let mut at = [f64::NAN; 3];
    let mut out = Vec::new();
    for b in &p.blocks {
        if let Block::Rapid(t) | Block::Line { to: t, .. } = b {
            at = [t.x.unwrap_or(at[0]), t.y.unwrap_or(at[1]), t.z.unwrap_or(at[2])];
            out.push(at);
        }
    }
    out
}

#[test]
fn fanuc_subprogram_calls_and_repeats_read_as_the_flat_program_and_as_rs274_runs_them() {
    let called = read::read(FANUC_CALLS, Family::Fanuc, None).unwrap_or_else(|e| panic!("{e}"));
    let flat = read::read(FANUC_FLAT, Family::Fanuc, None).unwrap();
    assert_eq!(called.blocks, flat.blocks);
    assert_eq!(called.number, Some(1));
    let points = end_points(&called);
    // Five passes of three moves, each 10 mm further in X, then the moves after them.
    assert_eq!(points.len(), 1 + 5 * 3 + 1 + 1 + 3 + 1, "{points:?}");
    assert_eq!(points[15], [50.0, 0.0, 5.0]);
    if !common::rs274::available() {
        eprintln!("rs274 is not installed: the LinuxCNC reading of the same calls is not compared");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("calls.ngc");
    std::fs::write(&path, LINUXCNC_CALLS).unwrap();
    let theirs: Vec<[f64; 3]> = common::rs274::moves(&path)
        .unwrap()
        .into_iter()
        .map(|m| match m {
            common::rs274::Move::Traverse { x, y, z } | common::rs274::Move::Feed { x, y, z } => [x, y, z],
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(theirs.len(), points.len(), "{theirs:?}");
    for (ours, theirs) in points.iter().zip(&theirs) {
        assert!(ours.iter().zip(theirs).all(|(a, b)| (a - b).abs() < 1e-6), "{ours:?} vs rs274 {theirs:?}");
    }
}

/// The "cycle time" line `ncsheet nc time` prints for `text` saved as `name` (the extension
/// picks the dialect).
fn cycle_time(name: &str, text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    let run = common::cli::ncsheet(&["nc", "time", path.to_str().unwrap(), "--accel", "500", "--rapid", "8000"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    run.stdout.lines().find(|l| l.starts_with("cycle time")).unwrap().to_string()
}

#[test]
fn nc_time_of_fanuc_subprogram_calls_is_the_flat_programs() {
    assert_eq!(cycle_time("calls.nc", FANUC_CALLS), cycle_time("flat.nc", FANUC_FLAT));
}

/// A Fanuc control ends a block at EOB, which the manuals print as `;` (B-64124EN/01 §13.2,
/// "Notation in this manual"): the whole calling program and its subprograms written on one
/// line, `;` between the blocks, is the same program as the flat one; an error in the last of
/// 2,000 blocks on one line names its column on that line.
#[test]
fn fanuc_blocks_joined_by_eob_on_one_line_read_as_the_flat_program() {
    let one_line = FANUC_CALLS.replace('\n', " ;");
    let called = read::read(&one_line, Family::Fanuc, None).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(called.blocks, read::read(FANUC_FLAT, Family::Fanuc, None).unwrap().blocks);
    let long: String = (0..2000).map(|i| format!("G01 X{}. F500. ;", i % 100)).collect();
    let e = read::read(&format!("G21 G90 ;{long}G01 Q ;\nM30\n"), Family::Fanuc, None).unwrap_err();
    assert_eq!((e.line, e.column), (1, "G21 G90 ;".len() + long.len() + 5), "{e}");
    let e = read::read(&format!("G21 G90 ;{long}M98 P7 ;\nM30\n"), Family::Fanuc, None).unwrap_err();
    assert_eq!((e.line, e.column), (1, "G21 G90 ;".len() + long.len() + 5), "{e}");
    assert!(e.message.contains("alarm 078"), "{e}");
}

/// The tape marks and the program number as a Fanuc control reads them: the first `%` line is
/// the leader, skipped to the end of its line, the next `%` ends the program (FANUC 16i
/// operator's manual B-63524EN/01 §8: "data between the first % and the next LF is skipped",
/// "A file always ends with %"); `:1234` is the program number in ISO code, the colon standing
/// for the address O ("the capital letter O for EIA format, and the older colon [ : ] for ASCII
/// (ISO) format", en.cncforum.net, "CNC Program Name and Number Identification"). The same
/// program written with `O1234` and no marks is the oracle.
#[test]
fn fanuc_tape_marks_and_a_colon_program_number_read_as_the_plain_program() {
    let body = "G21 G17 G90 G94\nG0 X0 Y0 Z5\nG1 X10 F100 ;G1 Y10 ;\nM30 ;\n";
    let marked = read::read(&format!("% PART-1234 REV.B\n:1234 (PART A)\n{body}%\n"), Family::Fanuc, None)
        .unwrap_or_else(|e| panic!("{e}"));
    let plain = read::read(&format!("O1234 (PART A)\n{body}"), Family::Fanuc, None).unwrap();
    assert_eq!((marked.number, marked.name.as_str()), (Some(1234), "PART A"));
    assert_eq!(marked.blocks, plain.blocks);
    // A second main program (ending with M30, not M99) is never run by this one: a control runs
    // it only when an operator selects it, so it is refused at its O line, not left out without
    // a word; so is text after the tape's end.
    let cases = [
        (format!("%\nO1234\n{body}%\nO2000\nG1 X1\nM30\n%\n"), 8, 1, "ends the program at line 7"),
        (format!("O1234\n{body}O2000 (SECOND PART)\nG1 X1\nM30\n"), 6, 1, "O2000 ends with M30, not M99"),
    ];
    for (text, line, column, says) in cases {
        let e = read::read(&text, Family::Fanuc, None).unwrap_err();
        assert_eq!((e.line, e.column), (line, column), "{text}\n{e}");
        assert!(e.message.contains(says), "{text}\n{e}");
    }
}

/// A subprogram (an O program returning with M99) that the main program does not call is what
/// a control keeps in memory: "such a program can be stored as a subprogram in memory" (FANUC
/// 0i-MC, B-64124EN/01 §12.3), and it runs only when called. The file reads as its main program
/// alone (the oracle: the main program written without it), and the reader notes each stored one
/// by its O line, including one that only a stored program calls.
#[test]
fn fanuc_subprograms_no_call_runs_are_stored_and_noted_not_refused() {
    let main = "O1234\nG21 G17 G90 G94\nG0 X0 Y0 Z5\nG1 X10 F100\nM30\n";
    let library = "O2000\nG1 X99 Y99 F100\nM98 P3000\nM99\n:3000\nG1 Y50\nM99\n";
    let alone = read::read(main, Family::Fanuc, None).unwrap();
    let with_library = format!("{main}{library}");
    let stored = read::read(&with_library, Family::Fanuc, None).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(stored.blocks, alone.blocks);
    assert_eq!(
        read::read_noted(&with_library, Family::Fanuc, None).unwrap().2,
        [
            "line 6: O2000 stored, not called by the main program",
            "line 10: O3000 stored, not called by the main program"
        ]
    );
    assert!(read::read_noted(main, Family::Fanuc, None).unwrap().2.is_empty());
    // The command line says so on stderr, and times the main program alone.
    assert_eq!(cycle_time("library.nc", &with_library), cycle_time("main.nc", main));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("library.nc");
    std::fs::write(&path, &with_library).unwrap();
    let run = common::cli::ncsheet(&["nc", "time", path.to_str().unwrap(), "--accel", "500", "--rapid", "8000"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("library.nc: line 6: O2000 stored, not called by the main program"), "{}", run.stderr);
}

/// What the manual bounds (a count of 1–999, four levels of nesting) and what the file does
/// not hold (alarm 078) are refused at their line and column; so is what the manual leaves to
/// a control's set-up (M99 in the main program restarts it; `M99 P` out of a repeated call).
#[test]
fn fanuc_subprogram_calls_the_control_would_not_run_are_refused_at_their_line_and_column() {
    let sub = "O1002\nG91 G1 X1 F100\nG90 M99\n";
    let nested = "O0001\nG0 X0 Y0 Z5\nM98 P1001\nM30\nO1001\nM98 P1002\nM99\nO1002\nM98 P1003\nM99\nO1003\n\
                  M98 P1004\nM99\nO1004\nM98 P1005\nM99\nO1005\nG1 X1 F100 M99\n";
    let cases = [
        (format!("G0 X0 Y0 Z5\nM98 P1009\nM30\n{sub}"), 2, 5, "O1009, which this file does not hold"),
        (format!("G0 X0 Y0 Z5\nM98 P1002 L1000\nM30\n{sub}"), 2, 5, "1 to 999 times"),
        (format!("G0 X0 Y0 Z5\nM98 P51002 L2\nM30\n{sub}"), 2, 5, "a count in P and an L"),
        (format!("G0 X0 Y0 Z5\nM98 P1002 Q10\nM30\n{sub}"), 2, 11, "Q"),
        ("G0 X0 Y0 Z5\nG1 X1 F100\nM99\n".to_string(), 3, 1, "M99 in the main program"),
        ("G0 X0 Y0 Z5\nM98 P1002\nM30\nO1002\nG1 X1 F100\n".to_string(), 4, 1, "O1002 has no M99"),
        ("N10 G0 X0 Y0 Z5\nM98 P31002\nM30\nO1002\nG1 X1 F100 M99 P10\n".to_string(), 2, 5, "repeats it 3 times"),
        (nested.to_string(), 15, 5, "nest more than 4 levels"),
        (format!("G0 X0 Y0 Z5\nM98 P1002\nM30\n{sub}O1002\nM99\n"), 7, 1, "written twice"),
    ];
    for (text, line, column, says) in cases {
        let e = read::read(&text, Family::Fanuc, None).unwrap_err();
        assert_eq!((e.line, e.column), (line, column), "{text}\n{e}");
        assert!(e.message.contains(says), "{text}\n{e}");
    }
}

/// `M98 P…L999` four levels deep is 999^4 (about 10^12) passes: the reader stops at the
/// budget every unrolled program shares (docs/limits.md), at the block that passes it.
#[test]
fn fanuc_repeats_nested_four_deep_stop_at_the_block_budget() {
    let mut text = String::from("O0001\nG0 X0 Y0 Z5\nM98 P1001 L999\nM30\n");
    for n in 1001..=1003 {
        text.push_str(&format!("O{n}\nM98 P{} L999\nM99\n", n + 1));
    }
    text.push_str("O1004\nG91 G1 X1 F100\nG90 M99\n");
    let e = read::read(&text, Family::Fanuc, None).unwrap_err();
    assert!(e.message.contains("runs more than 1000000 blocks"), "{e}");
    assert_eq!(e.line, 15, "{e}");
}

/// A plain-language program with a program section repeat and a subprogram, laid out as the
/// TNC manuals lay them out (TNC 370 User's Manual §6, "Subprograms and Program Section
/// Repeats": the subprograms after the main program's M2 block, each `LBL n` … `LBL 0`;
/// `CALL LBL 1 REP 2` runs the section from `LBL 1` to the call 2 more times, so 3 in all).
const HEIDENHAIN_LABELS: &str = "0 BEGIN PGM REP MM\n1 TOOL CALL 1 Z S1000\n2 L X+0 Y+0 Z+5 R0 FMAX M3\n\
3 LBL 1\n4 L IX+10 R0 F100\n5 L IY+5\n6 CALL LBL 1 REP 2\n7 CALL LBL \"DRILL\"\n8 L Z+50 R0 FMAX M2\n\
9 LBL \"DRILL\"\n10 L IZ-10 R0 F50\n11 L IZ+10 R0 FMAX\n12 LBL 0\n13 END PGM REP MM\n";

/// The same program written out flat by hand.
const HEIDENHAIN_FLAT: &str = "0 BEGIN PGM REP MM\n1 TOOL CALL 1 Z S1000\n2 L X+0 Y+0 Z+5 R0 FMAX M3\n\
3 L IX+10 R0 F100\n4 L IY+5\n5 L IX+10 R0 F100\n6 L IY+5\n7 L IX+10 R0 F100\n8 L IY+5\n\
9 L IZ-10 R0 F50\n10 L IZ+10 R0 FMAX\n11 L Z+50 R0 FMAX M2\n12 END PGM REP MM\n";

#[test]
fn heidenhain_section_repeats_and_subprograms_read_as_the_flat_program() {
    let heidenhain = ncsheet::nc::by_name("heidenhain").unwrap();
    let (called, lines) = heidenhain.read(HEIDENHAIN_LABELS, None).unwrap_or_else(|e| panic!("{e}"));
    let flat = heidenhain.read(HEIDENHAIN_FLAT, None).unwrap().0;
    assert_eq!(called.blocks, flat.blocks);
    let points = end_points(&called);
    assert_eq!(points.len(), 1 + 3 * 2 + 2 + 1, "{points:?}");
    assert_eq!(points[6], [30.0, 15.0, 5.0]);
    // Each block keeps the line it was written on: `5 L IY+5` (line 6) runs in each pass.
    assert_eq!(lines.iter().filter(|&&l| l == 6).count(), 3, "{lines:?}");
    assert_eq!(cycle_time("labels.h", HEIDENHAIN_LABELS), cycle_time("flat.h", HEIDENHAIN_FLAT));
}

/// A call of a label the program lacks, subprograms nested past the manual's 8 levels (a
/// subprogram calling itself), a block after M2 outside any subprogram and section repeats
/// within section repeats past the block budget (1000 × 1000 × 1000 passes) are refused at
/// their line and column.
#[test]
fn heidenhain_labels_the_control_would_not_run_are_refused_at_their_line_and_column() {
    let head = "0 BEGIN PGM E MM\n1 TOOL CALL 1 Z S1000\n2 L X+0 Y+0 Z+5 R0 FMAX M3\n";
    let cases = [
        ("3 CALL LBL 5\n4 L Z+50 R0 FMAX M2\n5 END PGM E MM\n", 4, 12, "no LBL 5"),
        (
            "3 CALL LBL 1\n4 L Z+50 R0 FMAX M2\n5 LBL 1\n6 CALL LBL 1\n7 LBL 0\n8 END PGM E MM\n",
            7,
            12,
            "more than 8 levels",
        ),
        (
            "3 CALL LBL 1\n4 L Z+50 R0 FMAX M2\n5 L X+1 R0 F100\n6 LBL 1\n7 LBL 0\n8 END PGM E MM\n",
            6,
            1,
            "not in a subprogram",
        ),
        (
            "3 LBL 1\n4 LBL 2\n5 LBL 3\n6 L IX+0.001 R0 F100\n7 CALL LBL 3 REP 1000\n8 CALL LBL 2 REP 1000\n\
             9 CALL LBL 1 REP 1000\n10 L Z+50 R0 FMAX M2\n11 END PGM E MM\n",
            0,
            1,
            "runs more than 1000000 blocks",
        ),
    ];
    for (tail, line, column, says) in cases {
        let text = format!("{head}{tail}");
        let e = ncsheet::nc::by_name("heidenhain").unwrap().read(&text, None).unwrap_err();
        assert!(e.message.contains(says), "{text}\n{e}");
        if line > 0 {
            assert_eq!((e.line, e.column), (line, column), "{text}\n{e}");
        }
    }
}
