//! `ncsheet nc check` (issue 15) on hand-written programs with known faults, each at a known
//! line, and on the shipped examples, which are clean. Whether LinuxCNC refuses an arc whose
//! end is off its circle is asked of LinuxCNC's own interpreter, rs274.

mod common;

use std::path::Path;

use common::cli::{ncsheet, Invocation, Run};

fn check(dir: &Path, name: &str, program: &str, extra: &[&str]) -> Run {
    let path = dir.join(name);
    std::fs::write(&path, program).unwrap();
    let mut args = vec!["nc", "check", path.to_str().unwrap()];
    args.extend(extra);
    ncsheet(&args)
}

/// The findings as (line, message), from `PROGRAM:LINE: message` lines.
fn findings(run: &Run) -> Vec<(usize, String)> {
    run.stdout
        .lines()
        .map(|l| {
            let (_, rest) = l.split_once(".nc:").unwrap_or_else(|| panic!("not PROGRAM:LINE: {l}"));
            let (line, message) = rest.split_once(": ").unwrap();
            (line.parse().unwrap(), message.to_string())
        })
        .collect()
}

fn has(found: &[(usize, String)], line: usize, words: &str) -> bool {
    found.iter().any(|(l, m)| *l == line && m.contains(words))
}

/// A tool change with its length offset (G43): without it the coordinates are the spindle's.
const HEADER: &str = "G21 G17 G90 G40\nT1 M6 G43\nS1000 M3\nG94\n";

#[test]
fn a_clean_program_exits_0_and_says_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let program = format!("{HEADER}G0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nG3 X0 Y10 I-10 J0\nG0 Z5\nM5\nM30\n");
    let run = check(
        dir.path(),
        "clean.nc",
        &program,
        &["--min-z", "-1", "--stock", "-20,-20,-10,20,20,0", "--dialect", "iso"],
    );
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    assert!(run.stdout.is_empty() && run.stderr.is_empty(), "{}{}", run.stdout, run.stderr);
}

#[test]
fn a_cut_without_feed_mode_feed_spindle_or_tool_is_found_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    // Line 3 cuts with none of them set; line 7 cuts again after the spindle stopped (M5).
    // On a lathe: a mill powers on in G94 (issue 32), a lathe's feed mode is its set-up's.
    let program = "G21 G18 G90\nG0 X0 Y0 Z5\nG1 Z-1\nG1 X10 F100\nM5\nG0 Z5\nG1 Z-1\nM30\n";
    let run = check(dir.path(), "bare.nc", program, &["--dialect", "linuxcnc", "--machine", "lathe"]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    let found = findings(&run);
    assert!(has(&found, 3, "no feed mode"), "{found:?}");
    assert!(has(&found, 3, "no feed F"), "{found:?}");
    assert!(has(&found, 3, "no tool"), "{found:?}");
    assert!(has(&found, 3, "spindle not turning"), "{found:?}");
    assert!(has(&found, 7, "spindle not turning"), "{found:?}");
    assert_eq!(found.len(), 5, "each said once: {found:?}");
    assert!(run.stderr.contains("5 findings"), "{}", run.stderr);
}

#[test]
fn a_cut_from_an_unknown_position_is_found() {
    let dir = tempfile::tempdir().unwrap();
    let program = format!("{HEADER}G1 X10 Y0 F100\nG1 Z-1\nM30\n");
    let run = check(dir.path(), "unknown.nc", &program, &[]);
    assert_eq!(run.code, 1);
    let found = findings(&run);
    assert!(has(&found, 5, "unknown position"), "{found:?}");
}

/// Arc ends off their circles by 0.001, 0.01 and 0.05 mm (radius 10): the first within the
/// default 0.002 mm, the others found; LinuxCNC (rs274) takes the 0.01 mm one and refuses the
/// 0.05 mm one, and the finding says so.
#[test]
fn arc_ends_off_their_circles_are_found_with_what_linuxcnc_does() {
    let dir = tempfile::tempdir().unwrap();
    for (off, found_line) in [(0.001, None), (0.01, Some(7)), (0.05, Some(7))] {
        let end = 10.0 + off;
        let program = format!("{HEADER}G0 X10 Y0 Z5\nG1 Z-1 F100\nG3 X0 Y{end} I-10 J0\nG0 Z5\nM5\nM30\n");
        let run = check(dir.path(), "arc.nc", &program, &[]);
        let found = findings(&run);
        match found_line {
            None => assert_eq!(run.code, 0, "{off}: {found:?}"),
            Some(line) => {
                assert_eq!(run.code, 1, "{off}: {}", run.stderr);
                assert!(has(&found, line, &format!("{off} mm off the circle")), "{off}: {found:?}");
                if common::rs274::available() {
                    let path = dir.path().join("arc.nc");
                    let refused = common::rs274::canon(&path).is_err();
                    let said = if refused { "LinuxCNC refuses it" } else { "LinuxCNC accepts it" };
                    assert!(has(&found, line, said), "{off}: rs274 refused: {refused}; {found:?}");
                }
            }
        }
        // A wider tolerance accepts the 0.01 mm arc.
        let run = check(dir.path(), "arc.nc", &program, &["--tolerance", "0.02"]);
        assert_eq!(run.code, i32::from(off > 0.02), "{off}: {}", run.stdout);
    }
}

/// A lathe arc (G18, X a diameter) from Ø20 to Ø40 at Z0 around Ø30 Z0, clockwise in the
/// (Z, X) plane: it bulges to Z−5 (radius 5) although both ends are at Z0.
#[test]
fn moves_below_min_z_count_an_arcs_extreme_point() {
    let dir = tempfile::tempdir().unwrap();
    let lathe = "G21 G18 G40\nT0101\nG99\nG97 S800 M3\nG0 X20 Z2\nG1 Z0 F0.1\nG2 X40 Z0 I5 K0\nG0 X50 Z2\nM5\nM30\n";
    let run = check(dir.path(), "lathe.nc", lathe, &["--min-z", "-3"]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    let found = findings(&run);
    assert!(has(&found, 7, "down to Z-5"), "{found:?}");
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(check(dir.path(), "lathe.nc", lathe, &["--min-z", "-5"]).code, 0);
    // Counter-clockwise it bulges to Z+5 instead.
    let ccw = lathe.replace("G2 X40", "G3 X40");
    assert_eq!(check(dir.path(), "lathe.nc", &ccw, &["--min-z", "-3"]).code, 0);
}

#[test]
fn rapids_through_the_stock_and_cuts_below_it_are_found() {
    let dir = tempfile::tempdir().unwrap();
    // Stock 100 × 100 × 10 with its top at Z0. Line 6 rapids across above it (fine), line 7
    // rapids through it at Z−2, line 9 cuts down to Z−12, under its bottom.
    let program =
        format!("{HEADER}G0 X-10 Y50 Z5\nG0 X110 Y50 Z5\nG0 X-10 Y50 Z-2\nG0 X-10 Y-10 Z5\nG1 Z-12 F100\nG0 Z5\nM30\n");
    let run = check(dir.path(), "stock.nc", &program, &["--stock", "0,0,-10,100,100,0"]);
    assert_eq!(run.code, 1, "{}", run.stderr);
    let found = findings(&run);
    assert!(has(&found, 7, "rapid move through the stock"), "{found:?}");
    assert!(has(&found, 9, "below the stock's bottom Z-10"), "{found:?}");
    assert_eq!(found.len(), 2, "{found:?}");
}

#[test]
fn a_malformed_stock_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    let program = format!("{HEADER}G0 X0 Y0 Z5\nM30\n");
    for stock in ["1,2,3", "0,0,0,10,10,x", "0,0,0,10,-1,5"] {
        let run = check(dir.path(), "p.nc", &program, &["--stock", stock]);
        assert_eq!(run.code, 2, "{stock}: {}", run.stderr);
        assert!(run.stderr.contains("--stock"), "{}", run.stderr);
    }
}

fn sheet(name: &str) -> String {
    format!("{}/sheets/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn the_shipped_examples_are_clean() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let at = Invocation { dir: Some(d), ..Invocation::default() };
    let chamfer = |dialect: &str, out: &str| {
        let args = common::cli::outer_chamfer(dialect, out);
        let run = at.run(&args.iter().map(String::as_str).collect::<Vec<_>>());
        assert_eq!(run.code, 0, "{}", run.stderr);
    };
    chamfer("iso", "chamfer.nc");
    chamfer("linuxcnc", "chamfer.ngc");
    let run =
        at.run(&["cam", &sheet("cam-turret.csv"), "--tol", "0.01", "--partial", "--format", "nc", "-o", "cam.nc"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let mut args = common::cli::bump_ballpath("1", "1", "off");
    args.extend(["--format", "linuxcnc", "-o", "ball.ngc"].map(String::from));
    let run = at.run(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(run.code, 0, "{}", run.stderr);
    for (file, dialect, extra) in [
        // docs/domain.md §1's shaft: Ø40, its end face at Z0 (Y is not used on a lathe).
        ("chamfer.nc", "iso", vec!["--stock", "0,0,-60,40,1,0"]),
        ("chamfer.ngc", "linuxcnc", vec!["--stock", "0,0,-60,40,1,0"]),
        // The disc (radius up to 114 mm), 12 mm thick under Z0.
        ("cam.nc", "iso", vec!["--min-z", "-12", "--stock", "-115,-115,-12,115,115,0"]),
        ("ball.ngc", "linuxcnc", vec!["--min-z", "0"]),
    ] {
        let path = d.join(file);
        let mut args = vec!["nc", "check", path.to_str().unwrap(), "--dialect", dialect];
        args.extend(extra);
        let run = ncsheet(&args);
        assert_eq!(run.code, 0, "{file}: {}{}", run.stdout, run.stderr);
    }
    // The cam program cuts at Z−12: a stated floor above it is found.
    let path = d.join("cam.nc");
    let run = ncsheet(&["nc", "check", path.to_str().unwrap(), "--min-z", "-10"]);
    assert_eq!(run.code, 1, "{}", run.stdout);
}

/// `T1 M6` without G43 on LinuxCNC applies no length (rs274 with a tool table reports no
/// `USE_TOOL_LENGTH_OFFSET` until a G43: tests/nc_read_control.rs), so the cuts' Z is the
/// spindle's point, not the tip: said once at the first cut after each such change.
#[test]
fn cuts_with_no_length_offset_are_found() {
    let dir = tempfile::tempdir().unwrap();
    let program = "G21 G17 G90 G40\nT1 M6\nS1000 M3\nG94\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nG43\nG1 X0\nG49\n\
                   G1 X5\nM30\n";
    let run = check(dir.path(), "nolength.nc", program, &[]);
    let found = findings(&run);
    assert!(has(&found, 6, "no tool offset in force"), "{found:?}");
    assert!(has(&found, 11, "no tool offset in force"), "{found:?}");
    assert_eq!(found.len(), 2, "{found:?}");
}
