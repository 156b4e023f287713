//! `ncsheet run` as a user runs it: the paper's chamfer macro on a workbook, its program read
//! back by LinuxCNC's rs274, and the refusals a macro meets.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::rs274::{self, Move};

fn ncsheet(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ncsheet")).args(args).output().unwrap()
}

/// The fixed layout of sheets/chamfer.bas: inputs in B2:B7, results in B9:B12.
const CHAMFER_SHEET: &str = "input,value\nD,40\nf,2\nalpha,45\nr,0.8\neA,1\neB,1\n\nXA,\nZA,\nXB,\nZB,\n";

fn macro_path(name: &str) -> String {
    format!("{}/sheets/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn chamfer_macro_cuts_from_t1_to_t2_as_domain_md_computes_them() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "chamfer.csv", CHAMFER_SHEET);
    let program = dir.path().join("chamfer.ngc");
    let saved = dir.path().join("out.csv");
    let out = ncsheet(&[
        "run",
        &book,
        &macro_path("chamfer.bas"),
        "--dialect",
        "linuxcnc",
        "-o",
        program.to_str().unwrap(),
        "--save",
        saved.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // The results were written into the workbook (docs/domain.md §1, outer, α = 45°).
    let wb = ncsheet(&["eval", saved.to_str().unwrap(), "B9:B12", "--format", "csv"]);
    let values: Vec<f64> = String::from_utf8(wb.stdout).unwrap().lines().map(|l| l.parse().unwrap()).collect();
    for (got, want) in values.iter().zip([44.262742, -4.6, 33.062742, 1.0]) {
        assert!((got - want).abs() < 1e-6, "{values:?}");
    }
    if !rs274::available() {
        eprintln!("skipped the rs274 part: rs274 is not installed");
        return;
    }
    let moves = rs274::moves(&program).unwrap();
    // rs274 reports X as a radius (G7 diameter mode on input).
    // In at feed to T1, along the chamfer to T2; the rapid before ends 1 mm (the macro's
    // clearance) off the chamfer line: 1/cos 45° further out in X than T1.
    let feed: Vec<&Move> = moves.iter().filter(|m| matches!(m, Move::Feed { .. })).collect();
    let Move::Feed { x, z, .. } = feed[0] else { unreachable!() };
    assert!((x - 44.262742 / 2.0).abs() < 0.001 && (z + 4.6).abs() < 0.001, "{feed:?}");
    let Move::Feed { x, z, .. } = feed[1] else { unreachable!() };
    assert!((x - 33.062742 / 2.0).abs() < 0.001 && (z - 1.0).abs() < 0.001, "{feed:?}");
    let first_cut = moves.iter().position(|m| matches!(m, Move::Feed { .. })).unwrap();
    let Move::Traverse { x, z, .. } = moves[first_cut - 1] else { panic!("expected a rapid before T1: {moves:?}") };
    let clear = 44.262742 / 2.0 + 1.0 / 45f64.to_radians().cos();
    assert!((x - clear).abs() < 0.001 && (z + 4.6).abs() < 0.001, "{moves:?}");
    // F0.1 is per revolution: G95 before the first cut.
    assert_eq!(rs274::feed_mode_at_first_cut(&program), Ok(Some(1)));
}

#[test]
fn debug_print_and_msgbox_go_to_stderr() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "b.csv", "1\n");
    let bas = write(dir.path(), "m.bas", "Sub Main()\n  Debug.Print \"x=\"; [A1] * 2\n  MsgBox \"done\"\nEnd Sub\n");
    let out = ncsheet(&["run", &book, &bas]);
    assert!(out.status.success());
    assert_eq!(String::from_utf8_lossy(&out.stdout), "");
    // What the macro printed, then that there is no program (issue 32: never silently empty).
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!("x= 2 \ndone\nncsheet: {bas}: note: no NC program: the macro emitted no NC block (no move)\n")
    );
}

#[test]
fn a_runaway_macro_stops_with_its_line_and_a_caret() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "b.csv", "1\n");
    let bas = write(dir.path(), "loop.bas", "Sub Main()\n  Dim i\n  Do\n    i = i + 1\n  Loop\nEnd Sub\n");
    let out = ncsheet(&["run", &book, &bas, "--max-statements", "1000"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("loop.bas:") && err.contains('^') && err.contains("--max-statements"), "{err}");
}

#[test]
fn a_macro_cannot_touch_files() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "b.csv", "1\n");
    let victim = write(dir.path(), "victim.txt", "keep me");
    let bas = write(dir.path(), "kill.bas", &format!("Sub Main()\n  Kill \"{victim}\"\nEnd Sub\n"));
    let out = ncsheet(&["run", &book, &bas]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep me");
    let bas = write(dir.path(), "shell.bas", "Sub Main()\n  Shell \"rm -rf /tmp/x\"\nEnd Sub\n");
    assert_eq!(ncsheet(&["run", &book, &bas]).status.code(), Some(1));
}

#[test]
fn saving_over_the_input_workbook_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "b.csv", "1\n");
    let bas = write(dir.path(), "m.bas", "Sub Main()\n  [A1] = 2\nEnd Sub\n");
    let out = ncsheet(&["run", &book, &bas, "--save", &book]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(std::fs::read_to_string(&book).unwrap(), "1\n");
}

// "Workbook.Save method": "Saves changes to the specified workbook". ncsheet never writes the
// file it opened (the test above), so `ThisWorkbook.Save` at the end of a real module (Kyostar1112's
// CsvOut.bas: `ActiveWorkbook.Save`) is not a refused file statement: the run goes on, the input
// stays as it was, and the changes are kept where --save says — or the user is told, with the
// line of the Save, that nothing was written.
#[test]
fn workbook_save_keeps_the_changes_only_where_save_says() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "b.csv", "1\n");
    let bas = write(dir.path(), "m.bas", "Sub Main()\n  [A1] = 2\n  ActiveWorkbook.Save\n  [A2] = 3\nEnd Sub\n");
    let out = ncsheet(&["run", &book, &bas]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(
        err.contains("m.bas:3: note: Workbook.Save: the workbook is not written") && err.contains("--save"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&book).unwrap(), "1\n");
    let saved = dir.path().join("out.csv");
    let out = ncsheet(&["run", &book, &bas, "--save", saved.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(!err.contains("Workbook.Save"), "{err}");
    assert_eq!(std::fs::read_to_string(&saved).unwrap().lines().collect::<Vec<_>>(), ["2", "3"]);
    assert_eq!(std::fs::read_to_string(&book).unwrap(), "1\n");
}

// A macro that writes to a fixed Windows folder runs unchanged once --map-dir maps that folder
// onto the output folder, matched as Windows matches paths (either case, / or \); "Print #
// statement": each line ends with CR LF. A path that goes on past the folder (.., a deeper
// folder) is still refused at its line, and a DIR other than --out-dir is a usage error.
// The name --input gives a save dialog is written there too.
#[test]
fn map_dir_runs_a_macro_that_writes_to_a_fixed_folder() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "b.csv", "1\n");
    let out_dir = dir.path().join("out");
    std::fs::create_dir(&out_dir).unwrap();
    let bas = write(
        dir.path(),
        "m.bas",
        "Sub Main()\n  Open \"C:\\Users\\me\\Desktop\\part.nc\" For Output As #1\n  Print #1, \"G0 X0\"\n  Close #1\n  \
         f = Application.GetSaveAsFilename()\n  Open \"c:/users/ME/desktop/\" & f For Output As #2\n  Print #2, \"M30\"\n  \
         Close #2\nEnd Sub\n",
    );
    let map = format!("C:\\Users\\me\\Desktop={}", out_dir.display());
    let out = ncsheet(&["run", &book, &bas, "--map-dir", &map, "--input", "end.nc"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert_eq!(std::fs::read_to_string(out_dir.join("part.nc")).unwrap(), "G0 X0\r\n");
    assert_eq!(std::fs::read_to_string(out_dir.join("end.nc")).unwrap(), "M30\r\n");
    for escape in ["..\\x.nc", "sub\\x.nc"] {
        let bas = write(
            dir.path(),
            "e.bas",
            &format!("Sub Main()\n  Open \"C:\\Users\\me\\Desktop\\{escape}\" For Output As #1\nEnd Sub\n"),
        );
        let out = ncsheet(&["run", &book, &bas, "--map-dir", &map]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_ne!(out.status.code(), Some(0), "{err}");
        assert!(err.contains("e.bas:2:") && err.contains("refused"), "{err}");
    }
    let other = format!("C:\\x={}", dir.path().display());
    let out = ncsheet(&["run", &book, &bas, "--out-dir", out_dir.to_str().unwrap(), "--map-dir", &other]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("is not the --out-dir folder"), "{err}");
}

/// Issue 32: the shipped chamfer sheet and macro work together as README says: the csv's
/// labelled rows are the macro's inputs, and the cut goes from T1 to T2 of DOMAIN.md §1
/// (outer, α = 45°: XA 44.262742, ZA −4.6, XB 33.062742, ZB 1), as rs274 reads it.
#[test]
fn the_shipped_chamfer_csv_runs_with_the_shipped_macro() {
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("chamfer.ngc");
    let out = ncsheet(&[
        "run",
        &macro_path("chamfer.csv"),
        &macro_path("chamfer.bas"),
        "--dialect",
        "linuxcnc",
        "-o",
        program.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    if !rs274::available() {
        eprintln!("skipped the rs274 part: rs274 is not installed");
        return;
    }
    let feeds: Vec<Move> =
        rs274::moves(&program).unwrap().into_iter().filter(|m| matches!(m, Move::Feed { .. })).collect();
    let at = |m: &Move| match *m {
        Move::Feed { x, z, .. } => (x, z),
        _ => unreachable!(),
    };
    let (x, z) = at(&feeds[0]);
    assert!((x - 44.262742 / 2.0).abs() < 0.001 && (z + 4.6).abs() < 0.001, "{feeds:?}");
    let (x, z) = at(&feeds[1]);
    assert!((x - 33.062742 / 2.0).abs() < 0.001 && (z - 1.0).abs() < 0.001, "{feeds:?}");
}

/// The finish contour L03 of cycles.bas (DOMAIN.md §2) as a radius at z: diameter 20 to
/// Z-10, a concave R5 fillet to diameter 30 at Z-15, a cylinder to Z-25, a taper to 40 at Z-35.
fn contour_radius(z: f64) -> f64 {
    if z >= -10.0 {
        10.0
    } else if z >= -15.0 {
        15.0 - (25.0 - (z + 10.0).powi(2)).max(0.0).sqrt()
    } else if z >= -25.0 {
        15.0
    } else {
        15.0 + (-25.0 - z) / 2.0
    }
}

/// Issue 32: cycles.bas's Main makes one part with the right tool for each cycle: the turning
/// tool (T1) for L16 and L17, the grooving tool (T2) for L13; L16's roughing stays outside the
/// contour L17 finishes (it does not remove the taper), and L17 cuts no deeper than it.
#[test]
fn the_cycles_main_makes_one_part_with_a_tool_per_cycle() {
    if !rs274::available() {
        eprintln!("skipped: rs274 is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("main.ngc");
    let out = ncsheet(&[
        "run",
        &macro_path("chamfer.csv"),
        &macro_path("cycles.bas"),
        "--dialect",
        "linuxcnc",
        "-o",
        program.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let canon = rs274::canon(&program).unwrap();
    let (mut cycle, mut tool) = (String::new(), 0);
    let mut last: Option<(f64, f64)> = None;
    let mut cycles_seen = Vec::new();
    for line in canon.lines() {
        if let Some((_, rest)) = line.split_once("COMMENT(\"") {
            if let Some(name) = ["L16", "L17", "L13"].iter().find(|n| rest.starts_with(&format!("{n} "))) {
                cycle = name.to_string();
                cycles_seen.push(cycle.clone());
            }
        }
        if let Some((_, rest)) = line.split_once("CHANGE_TOOL(") {
            tool = rest.trim_end_matches(')').trim().parse().unwrap();
        }
        for m in rs274::moves_of(line) {
            let (x, z) = match m {
                Move::Traverse { x, z, .. } | Move::Feed { x, z, .. } => (x, z),
                Move::Arc { first_end, second_end, .. } => (second_end, first_end),
            };
            if !matches!(m, Move::Traverse { .. }) {
                let want = if cycle == "L13" { 2 } else { 1 };
                assert_eq!(tool, want, "{cycle} cuts with T{tool}: {line}");
                if cycle == "L16" || cycle == "L17" {
                    let (x0, z0) = last.unwrap_or((x, z));
                    // The deepest the contour reaches over the move's span along Z.
                    let (lo, hi) = (z.min(z0), z.max(z0));
                    let highest =
                        (0..=100).map(|k| contour_radius(lo + (hi - lo) * k as f64 / 100.0)).fold(0.0, f64::max);
                    if cycle == "L16" {
                        assert!(x.min(x0) >= highest - 1e-6, "L16 cuts into the contour: {line}");
                    } else {
                        assert!(x >= contour_radius(z) - 1e-3, "L17 cuts below the contour: {line}");
                    }
                }
            }
            last = Some((x, z));
        }
    }
    assert_eq!(cycles_seen, ["L16", "L17", "L13"], "one program, three cycles");
}

// Microsoft's "Code Page Identifiers": 936 is GBK (Simplified Chinese). The VBA editor exports
// a module in the system's ANSI code page, so a .bas from a Chinese Excel holds GBK bytes;
// `--code-page 936` reads its text as written (in code page 1252 `个数据` was `¸öÊý¾Ý`).
#[test]
fn a_module_exported_in_a_chinese_code_page_reads_with_code_page() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "b.csv", "x\n");
    let bas = dir.path().join("m.bas");
    // `Range("A1").Value = "个数据"`, the text in GBK bytes (个 B8F6, 数 CAFD, 据 BEDD).
    let mut bytes = b"Sub Main()\r\n    Range(\"A1\").Value = \"".to_vec();
    bytes.extend_from_slice(&[0xB8, 0xF6, 0xCA, 0xFD, 0xBE, 0xDD]);
    bytes.extend_from_slice(b"\"\r\nEnd Sub\r\n");
    std::fs::write(&bas, &bytes).unwrap();
    let saved = dir.path().join("out.csv");
    let (bas, saved_path) = (bas.to_str().unwrap(), saved.to_str().unwrap());
    let out = ncsheet(&["run", &book, bas, "--code-page", "936", "--save", saved_path]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&saved).unwrap();
    assert!(text.trim_start_matches('\u{feff}').starts_with("个数据"), "{text}");
}
