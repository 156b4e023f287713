//! Programs a machinist can trust end to end (issue 32): a run that emits no program fails and
//! leaves an earlier program file alone; every program any ncsheet command writes, in every
//! dialect it offers, is read back by `nc plot`, `nc check` and `nc time` with no `--dialect`
//! (the reader tells the dialect from the file and says so) and `nc check` finds nothing in it.

mod common;

use std::path::{Path, PathBuf};

use common::cli::{ncsheet, Run};

fn repo(rel: &str) -> String {
    format!("{}/{rel}", env!("CARGO_MANIFEST_DIR"))
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

/// The fixed layout of sheets/chamfer.bas (inputs B2:B7), with α = 95°: no chamfer has it,
/// and the macro's own check says so and ends (DOMAIN.md §1: 0 < α < 90°).
const NO_CHAMFER: &str = "input,value\nD,40\nf,2\nalpha,95\nr,0.8\neA,1\neB,1\n\nXA,\nZA,\nXB,\nZB,\n";

#[test]
fn a_run_that_emits_no_block_fails_and_leaves_the_old_program() {
    let dir = tempfile::tempdir().unwrap();
    let book = write(dir.path(), "bad.csv", NO_CHAMFER);
    let old = "%\n(AN EARLIER PROGRAM)\nG0 X50 Z2\nM30\n%\n";
    let program = write(dir.path(), "prog.ngc", old);
    let saved = dir.path().join("saved.csv");
    let run = ncsheet(&[
        "run",
        &book,
        &repo("sheets/chamfer.bas"),
        "--dialect",
        "linuxcnc",
        "-o",
        &program,
        "--save",
        saved.to_str().unwrap(),
    ]);
    assert_ne!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.contains("no chamfer has"), "the macro's own message: {}", run.stderr);
    assert!(run.stderr.contains("no NC block") && run.stderr.contains("left as it was"), "{}", run.stderr);
    assert_eq!(std::fs::read_to_string(&program).unwrap(), old);
    // All or nothing: the workbook is not saved either.
    assert!(!saved.exists());
    // Without an earlier file, none is made.
    let fresh = dir.path().join("fresh.ngc");
    let run = ncsheet(&["run", &book, &repo("sheets/chamfer.bas"), "-o", fresh.to_str().unwrap()]);
    assert_ne!(run.code, 0);
    assert!(!fresh.exists());
}

#[test]
fn a_successful_run_says_what_it_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("chamfer.ngc");
    let args = common::cli::outer_chamfer("linuxcnc", program.to_str().unwrap());
    let run = ncsheet(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(run.code, 0, "{}", run.stderr);
    let text = std::fs::read_to_string(&program).unwrap();
    let lines = text.lines().filter(|l| !l.trim().is_empty()).count();
    let said = run.stderr.lines().find(|l| l.starts_with("wrote ")).unwrap_or_else(|| panic!("{}", run.stderr));
    assert!(said.contains(program.to_str().unwrap()) && said.contains("linuxcnc"), "{said}");
    assert!(said.contains(&format!("{lines} lines")) && said.contains("tool T1"), "{said}");
    // The time, at the rates it names, is a whole program's: the feeds along the chamfer alone
    // (F0.1 mm/rev at 800 1/min = 80 mm/min over T1→T2 and the approach) take seconds.
    let seconds: f64 = said.split("about ").nth(1).and_then(|s| s.split(' ').next()).unwrap().parse().unwrap();
    let cut = ((44.262742f64 - 33.062742) / 2.0).hypot(-4.6 - 1.0) / 80.0 * 60.0;
    assert!(seconds > cut, "{said}: the cut T1→T2 alone takes {cut:.2} s");
}

/// Every generating command with every dialect it offers, as (name, arguments with `{d}` for
/// the dialect and `{o}` for the output): the dialects a command refuses by design (a lathe
/// macro in plain language, milling on NC31) are said by the command, not written.
fn generators(cl: &str) -> Vec<(&'static str, Vec<String>, Vec<&'static str>)> {
    let lathe = vec!["iso", "linuxcnc", "sinumerik", "nc31", "nc81"];
    let mill = vec!["iso", "linuxcnc", "sinumerik", "heidenhain"];
    let s = |v: &[&str]| v.iter().map(|a| a.to_string()).collect::<Vec<_>>();
    let chamfer = s(&["run", &repo("sheets/chamfer.xlsx"), &repo("sheets/chamfer.bas"), "--sheet", "Outer"]);
    let cycles = |sub: &str| s(&["run", &repo("sheets/chamfer.csv"), &repo("sheets/cycles.bas"), "--sub", sub]);
    let cam = s(&[
        "cam",
        &repo("sheets/cam-turret.csv"),
        "--tol",
        "0.01",
        "--partial",
        "--format",
        "nc",
        "--cutter",
        "right",
    ]);
    let arcfit = s(&[
        "arcfit", "--kind", "arch", "--r0", "79", "--phi0", "36", "--r1", "102", "--phi1", "160.2", "--tol", "0.01",
        "--format", "nc",
    ]);
    let ball = common::cli::bump_ballpath("5", "5", "lift");
    let post = s(&["post", cl, "--machine", "ab-head", "--pivot", "400"]);
    vec![
        ("chamfer", chamfer, lathe.clone()),
        ("l16", cycles("L16"), lathe.clone()),
        ("l13", cycles("L13"), lathe.clone()),
        ("l17", cycles("L17"), lathe.clone()),
        ("cam", cam, mill.clone()),
        ("arcfit", arcfit, mill.clone()),
        ("ballpath", ball, mill),
        ("post", post, vec!["iso", "linuxcnc", "sinumerik"]),
    ]
}

/// A 5-axis CL file: a tool change, a rapid and three cuts with a tilted axis.
const CL: &str = "PARTNO/SPHERE\nUNITS/MM\nLOADTL/1\nSPINDL/1000,CLW\nFEDRAT/200\nRAPID\nGOTO/10,0,50,0,0,1\n\
GOTO/10,0,40,0.1,0,0.99498744\nGOTO/0,10,40,0,0.1,0.99498744\nGOTO/-10,0,40,-0.1,0,0.99498744\n";

fn generate(dir: &Path, name: &str, args: &[String], dialect: &str) -> PathBuf {
    // A neutral extension: the dialect must be told from the text itself.
    let out = dir.join(format!("{name}-{dialect}.txt"));
    let mut argv: Vec<&str> = args.iter().map(String::as_str).collect();
    let flag = if name == "ballpath" { "--format" } else { "--dialect" };
    argv.extend([flag, dialect, "-o", out.to_str().unwrap()]);
    let run = ncsheet(&argv);
    assert_eq!(run.code, 0, "{name} --dialect {dialect}: {}", run.stderr);
    out
}

fn read_back(program: &Path, dialect: &str) {
    // NC81 writes NC31's words (docs/domain.md §1): its text alone reads as nc31, the same.
    let dialect = if dialect == "nc81" { "nc31" } else { dialect };
    let p = program.to_str().unwrap();
    let svg = program.with_extension("svg");
    let runs: [(&str, Run); 3] = [
        ("nc plot", ncsheet(&["nc", "plot", p, "-o", svg.to_str().unwrap()])),
        ("nc check", ncsheet(&["nc", "check", p])),
        ("nc time", ncsheet(&["nc", "time", p, "--accel", "500", "--rapid", "5000"])),
    ];
    for (what, run) in runs {
        assert_eq!(run.code, 0, "{what} {p}: {}{}", run.stdout, run.stderr);
        assert!(
            run.stderr.contains(&format!("read as {dialect} (")),
            "{what} {p} says what it assumed: {}",
            run.stderr
        );
    }
}

#[test]
fn every_program_every_command_writes_is_read_back_checked_and_timed_without_dialect() {
    let dir = tempfile::tempdir().unwrap();
    let cl = write(dir.path(), "sphere.cl", CL);
    for (name, args, dialects) in generators(&cl) {
        for d in dialects {
            let program = generate(dir.path(), name, &args, d);
            read_back(&program, d);
        }
    }
}

#[test]
fn a_read_error_another_dialect_accepts_names_it() {
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("prog.mpf");
    let args = common::cli::outer_chamfer("sinumerik", program.to_str().unwrap());
    let run = ncsheet(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(run.code, 0, "{}", run.stderr);
    let p = program.to_str().unwrap();
    let wrong = ncsheet(&["nc", "check", p, "--dialect", "iso"]);
    assert_ne!(wrong.code, 0);
    assert!(wrong.stderr.contains("--dialect sinumerik"), "{}", wrong.stderr);
    // By its extension and header, read as it is.
    let right = ncsheet(&["nc", "plot", p, "-o", dir.path().join("p.svg").to_str().unwrap()]);
    assert_eq!(right.code, 0, "{}", right.stderr);
    assert!(right.stderr.contains("read as sinumerik"), "{}", right.stderr);
}

#[test]
fn a_mill_cut_needs_no_g94_where_the_control_powers_on_in_it_but_a_lathe_cut_does() {
    // LinuxCNC's documented start-up modes include G94; a Fanuc mill's too (parameter 3402 at
    // its default). A lathe's feed mode depends on the machine's set-up: F0.1 is per minute or
    // per revolution as the program says.
    let dir = tempfile::tempdir().unwrap();
    let mill =
        write(dir.path(), "mill.ngc", "G21 G17 G90 G40\nT1 M6 G43\nS1000 M3\nG0 X0 Y0 Z5\nG1 Z-1 F100\nM5\nM2\n");
    let run = ncsheet(&["nc", "check", &mill]);
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    let lathe = write(dir.path(), "lathe.ngc", "G21 G18 G7 G90 G40\nT1 M6\nS800 M3\nG0 X20 Z2\nG1 Z-5 F0.1\nM5\nM2\n");
    let run = ncsheet(&["nc", "check", &lathe]);
    assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
    assert!(run.stdout.contains("no feed mode"), "{}", run.stdout);
}

#[test]
fn the_iso_lathe_program_writes_no_word_that_is_a_cycle_in_system_a() {
    // Fanuc lathe G-code system A: G90 is the OD/ID cutting cycle A, G92 the thread cycle,
    // G94 the facing cycle (absolute and incremental are X/Z and U/W, feed modes G98/G99).
    let dir = tempfile::tempdir().unwrap();
    for (book, bas, sub) in [
        ("sheets/chamfer.xlsx", "sheets/chamfer.bas", None),
        ("sheets/chamfer.csv", "sheets/cycles.bas", Some("L16")),
        ("sheets/chamfer.csv", "sheets/cycles.bas", Some("L17")),
        ("sheets/chamfer.csv", "sheets/cycles.bas", Some("L13")),
    ] {
        let out = dir.path().join("lathe.nc");
        let mut args = vec!["run", book, bas, "--dialect", "iso", "-o", out.to_str().unwrap(), "--force"];
        let (book, bas) = (repo(book), repo(bas));
        args[1] = &book;
        args[2] = &bas;
        if book.ends_with(".xlsx") {
            args.extend(["--sheet", "Outer"]);
        }
        if let Some(sub) = sub {
            args.extend(["--sub", sub]);
        }
        let run = ncsheet(&args);
        assert_eq!(run.code, 0, "{}", run.stderr);
        let text = std::fs::read_to_string(&out).unwrap();
        for line in text.lines().filter(|l| !l.starts_with('(')) {
            for word in line.split_whitespace() {
                assert!(!["G90", "G92", "G94"].contains(&word), "{word} in `{line}` is a cycle in system A:\n{text}");
            }
        }
    }
}

/// The fillet of cycles.bas's contour L03 (DOMAIN.md §2: R5 from diameter 20 + dx at Z-10 to
/// diameter 30 + dx at Z-15), as NC31 gets it without circular interpolation: lines whose
/// ends lie on the circle and whose chords stay within --arc-tol of it (sagitta, computed
/// here from the written numbers).
#[test]
fn nc31_gets_the_arcs_of_the_loop_cycle_as_lines_within_the_arc_tolerance() {
    let dir = tempfile::tempdir().unwrap();
    let help = ncsheet(&["run", "--help"]);
    assert!(help.stdout.contains("--arc-tol") && help.stdout.contains("default 0.01"), "{}", help.stdout);
    for (tol, given) in [(0.01, None), (0.002, Some("0.002")), (0.05, Some("0.05"))] {
        let out = dir.path().join("l17.nc31");
        let (book, bas) = (repo("sheets/chamfer.csv"), repo("sheets/cycles.bas"));
        let mut args =
            vec!["run", &book, &bas, "--sub", "L17", "--dialect", "nc31", "-o", out.to_str().unwrap(), "--force"];
        if let Some(t) = given {
            args.extend(["--arc-tol", t]);
        }
        let run = ncsheet(&args);
        assert_eq!(run.code, 0, "{}", run.stderr);
        let text = std::fs::read_to_string(&out).unwrap();
        let points: Vec<(f64, f64)> = text
            .lines()
            .filter(|l| !l.ends_with(" E"))
            .filter_map(|l| {
                let word = |a: char| l.split_whitespace().find_map(|w| w.strip_prefix(a)?.parse::<f64>().ok());
                Some((word('X')?, word('Z')?))
            })
            .collect();
        let mut fillets = 0;
        for (i, w) in points.windows(2).enumerate() {
            // The fillet starts where a cut reaches Z-10 and goes on below it.
            if !((w[0].1 + 10.0).abs() < 1e-9 && w[1].1 < -10.0) {
                continue;
            }
            fillets += 1;
            let centre = (-10.0, w[0].0 / 2.0 + 5.0);
            let arc: Vec<(f64, f64)> =
                points[i..].iter().take_while(|p| p.1 >= -15.0 - 1e-9).map(|p| (p.1, p.0 / 2.0)).collect();
            assert!((arc.last().unwrap().0 + 15.0).abs() < 1e-9, "the fillet ends at Z-15: {arc:?}");
            assert!(arc.len() > 2, "an arc as more than one line: {arc:?}");
            for p in &arc {
                let r = (p.0 - centre.0).hypot(p.1 - centre.1);
                assert!((r - 5.0).abs() < 0.001, "a point off the fillet by {}: {p:?}", r - 5.0);
            }
            for c in arc.windows(2) {
                let mid = ((c[0].0 + c[1].0) / 2.0, (c[0].1 + c[1].1) / 2.0);
                let sagitta = 5.0 - (mid.0 - centre.0).hypot(mid.1 - centre.1);
                assert!(sagitta <= tol, "--arc-tol {tol}: a chord {sagitta} mm off the arc: {c:?}");
            }
        }
        assert!(fillets >= 2, "every pass of L17 cuts the fillet:\n{text}");
    }
}

/// A command line's words (none with spaces of its own).
fn words(line: &str) -> Vec<&str> {
    line.split_whitespace().collect()
}

/// `nc time`'s machine: acceleration (mm/s²) and rapid rate (mm/min).
const RATES: [&str; 4] = ["--accel", "500", "--rapid", "10000"];

/// The numbers of the Heidenhain `BLK FORM 0.1`/`0.2` lines: the lowest and highest Z.
fn blank_z(program: &str) -> (f64, f64) {
    let z_of = |form: &str| -> f64 {
        let line = program.lines().find(|l| l.contains(form)).unwrap_or_else(|| panic!("no {form}:\n{program}"));
        let z = line.rsplit(' ').find(|w| w.starts_with('Z') && w.len() > 1).unwrap();
        z[1..].parse().unwrap()
    };
    (z_of("BLK FORM 0.1"), z_of("BLK FORM 0.2"))
}

/// The valley z = 0.5 + x²/2 has a curvature radius of 1 mm at its bottom: a 3 mm ball
/// touching one flank cuts the other, and `--gouge lift` raises it to where it rests on both.
/// The stock block is still the surface's: from z = 0.5 (x = 0) to 0.5 + 2²/2 = 2.5 (x = ±2).
#[test]
fn the_heidenhain_blank_is_the_surfaces_not_the_lifted_paths() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("valley.h");
    let out_s = out.to_str().unwrap();
    for gouge in ["lift", "off"] {
        let mut args = words("ballpath --surface 0.5+x^2/2 --radius 3 --x=-2:2 --y=0:0 --stepover 0.5 --step 0.5");
        args.extend(["--gouge", gouge, "--format", "heidenhain", "-o", out_s, "--force"]);
        let run = ncsheet(&args);
        assert_eq!(run.code, 0, "{}", run.stderr);
        if gouge == "lift" {
            assert!(run.stderr.contains("lifted"), "the valley is lifted: {}", run.stderr);
        }
        let (low, high) = blank_z(&std::fs::read_to_string(&out).unwrap());
        assert!((low - 0.5).abs() < 1e-9 && (high - 2.5).abs() < 1e-9, "--gouge {gouge}: Z{low} to Z{high}");
    }
}

/// In Fanuc lathe G-code system A, G90 is the OD/ID turning cycle A (and G94 the facing
/// cycle): a reader that takes it for "absolute" runs a cycle as one straight cut. It is
/// refused, naming its line and column.
#[test]
fn a_fanuc_lathes_g90_is_a_cycle_not_absolute_mode() {
    let dir = tempfile::tempdir().unwrap();
    for (code, what) in [("G90", "turning cycle"), ("G94", "end-face turning cycle")] {
        let text = format!(
            "%\nO0001\nN10 G21 G18 G40\nN20 T0101\nN30 G99\nN40 G97 S800 M3\nN50 G0 X42. Z2.\nN60 {code} X38. Z-30. \
             F0.2\nN70 M30\n%\n"
        );
        let program = write(dir.path(), "cycle.nc", &text);
        for command in ["plot", "check", "time"] {
            let mut args = vec!["nc", command, &program, "--dialect", "iso"];
            match command {
                "plot" => args.extend(["-o", "-"]),
                "time" => args.extend(RATES),
                _ => {}
            }
            let run = ncsheet(&args);
            assert_ne!(run.code, 0, "nc {command} {code}: {}{}", run.stdout, run.stderr);
            assert!(run.stderr.contains(what), "nc {command} {code}: {}", run.stderr);
            assert!(run.stderr.contains("line 8") && run.stderr.contains("column 5"), "{}", run.stderr);
        }
    }
}

/// An empty program takes no time: "0.000 s", not "-0.000 s" (an empty sum of f64 is −0).
#[test]
fn nc_time_of_an_empty_program_is_zero_not_negative_zero() {
    let dir = tempfile::tempdir().unwrap();
    let program = write(dir.path(), "empty.ngc", "G21 G17 G90\nM2\n");
    let run = ncsheet(&["nc", "time", &program, "--dialect", "linuxcnc", "--accel", "500", "--rapid", "10000"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains("cycle time 0.000 s"), "{}", run.stdout);
    assert!(!run.stdout.contains("-0.000"), "{}", run.stdout);
}

/// An arc of radius 0.001 mm (the control's resolution) is refused as rs274 refuses it, but
/// the message gives its radius, not "radius 0".
#[test]
fn a_tiny_arc_is_refused_with_its_radius() {
    let dir = tempfile::tempdir().unwrap();
    let program = write(dir.path(), "tiny.ngc", "G21 G17 G90\nG0 X0 Y0 Z1\nG2 X0.002 Y0 I0.001 J0 F100\nM2\n");
    let run = ncsheet(&["nc", "check", &program, "--dialect", "linuxcnc"]);
    assert_ne!(run.code, 0, "{}{}", run.stdout, run.stderr);
    assert!(run.stderr.contains("radius 0.001 mm"), "{}", run.stderr);
    assert!(!run.stderr.contains("radius 0:"), "{}", run.stderr);
}

/// `cam --offset N`: cutter compensation takes the radius from register N, apart from the
/// tool number (issue 32, scope 2). LinuxCNC's rs274 (its D names a tool-table entry) cuts the
/// program of tool 1 with `--offset 21` exactly as the program of tool 21 itself; ISO writes
/// `G42 D21` after `T1`, and our readers take it back; Sinumerik's D is the cutting edge and
/// Heidenhain's radius the called tool's, so both refuse a register apart from the tool.
#[test]
fn cam_offset_is_the_radius_register_apart_from_the_tool() {
    let dir = tempfile::tempdir().unwrap();
    let sheet = repo("sheets/cam-turret.csv");
    let cam = |dialect: &str, extra: &[&str], name: &str| {
        let out = dir.path().join(name);
        let mut args = vec!["cam", &sheet, "--dialect", dialect, "-o", out.to_str().unwrap()];
        args.extend(words("--disc R --tol 0.05 --format nc --cutter right --cutter-diameter 12.7"));
        args.extend(extra);
        (ncsheet(&args), out)
    };
    let (run, iso) = cam("iso", &["--tool", "1", "--offset", "21"], "iso.nc");
    assert_eq!(run.code, 0, "{}", run.stderr);
    let text = std::fs::read_to_string(&iso).unwrap();
    assert!(text.contains("T1 M6 G43 H1"), "{text}");
    let comp: Vec<&str> = text.lines().filter(|l| l.contains("G42")).collect();
    assert!(!comp.is_empty() && comp.iter().all(|l| l.contains("G42 D21")), "{comp:?}");
    for command in ["check", "time"] {
        let mut args = vec!["nc", command, iso.to_str().unwrap()];
        if command == "time" {
            args.extend(RATES);
        }
        let back = ncsheet(&args);
        assert_eq!(back.code, 0, "nc {command}: {}{}", back.stdout, back.stderr);
    }
    for dialect in ["sinumerik", "heidenhain"] {
        let (run, _) = cam(dialect, &["--offset", "21"], "refused.nc");
        assert_ne!(run.code, 0, "{dialect}");
        assert!(run.stderr.contains("D21"), "{dialect}: {}", run.stderr);
    }
    if !common::rs274::available() {
        eprintln!("rs274 not installed: the LinuxCNC half is skipped");
        return;
    }
    // The stand-alone rs274 reads a table's diameters in inches: T1 2.54 mm, T21 12.7 mm.
    let table = dir.path().join("tools.tbl");
    std::fs::write(&table, "T1 P1 Z0 D0.1 ;\nT21 P21 Z0 D0.5 ;\n").unwrap();
    let cut = |program: &Path| {
        let canon = common::rs274::canon_with_tools(program, Some(&table)).unwrap();
        let feeds: Vec<String> = canon
            .lines()
            .filter(|l| l.contains("_FEED(") && !l.contains("SET_FEED"))
            .map(|l| l.split_once("N..... ").map_or(l, |(_, m)| m).to_string())
            .collect();
        feeds
    };
    let (run, with_offset) = cam("linuxcnc", &["--tool", "1", "--offset", "21"], "offset.ngc");
    assert_eq!(run.code, 0, "{}", run.stderr);
    let (run, tool21) = cam("linuxcnc", &["--tool", "21"], "tool21.ngc");
    assert_eq!(run.code, 0, "{}", run.stderr);
    let (a, b) = (cut(&with_offset), cut(&tool21));
    assert!(a.len() > 3, "{a:?}");
    assert_eq!(a, b, "G42 D21 after T1 cuts as tool 21");
    let (run, own) = cam("linuxcnc", &["--tool", "1"], "tool1.ngc");
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_ne!(cut(&own), a, "tool 1's own radius is another cut: the test can tell them apart");
}
