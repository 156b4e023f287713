//! NC31 parameterised subprograms (issue 33, docs/domain.md §2): a cycle written once after
//! the main program's M02 as `Lnn` … `M17`, with R parameters, `IF … THEN … GOTO` and words
//! that take a parameter's value (`XR4`, `W-R1`), called per use. The reader runs it as the
//! control does, so `nc` tools see the real path: the points are checked against the zigzag
//! of the paper's L16 algorithm computed here, and against the flat (unrolled) program.
//! Calls with values (`L16 X30 W40 …`, the letters bound by the header `L16 XR5 WR1 …`) read
//! the same way; `run --dialect nc31 --subprograms` writes a macro's marked cycles so
//! (sheets/cycles.bas's L16), checked against the cycle's path worked out here, against the
//! unrolled program block for block, and with `nc time` and `nc check`.

mod common;

use common::cli::ncsheet;
use ncsheet::nc::dialect;
use ncsheet::nc::{Block, Program};

/// The paper's L16 ("zigzag") algorithm as an NC31 subprogram, with its formal parameters
/// (R1 the loop length W, R2 the allowance A, R3 the depth of cut P) and, for the current
/// and the final diameter X_T and X_K, R4 and R5. Block labels N1–N9 as the paper numbers
/// them; the comparison `X_T ≥ X_K + A` is on R6 = R5 + R2.
const L16: &str = "\
N1 R6=R5+R2
N2 IF R4<R6 THEN GOTO N10
N3 XR4
N4 W-R1
N5 R4=R4-R3
N6 IF R4<R6 THEN GOTO N10
N7 XR4
N8 WR1
N9 R4=R4-R3 GOTO N2
N10 M17
";

/// A turning job that calls L16 twice: a 44 mm blank down to 30 mm (allowance 0.5, depth 2)
/// over 40 mm, then a 30 mm step down to 20.4 mm (allowance 0.2, depth 1.5) over 12 mm.
fn with_subprograms() -> String {
    format!(
        "N001 T1\nN002 S700 M03 F0.5\nN003 X44 Z0 E\nN004 R1=40\nN005 R2=0.5\nN006 R3=2\nN007 R4=44\n\
         N008 R5=30\nN009 L16\nN010 X50 Z2 E\nN011 X30 Z-28 E\nN012 R1=12\nN013 R2=0.2\nN014 R3=1.5\n\
         N015 R4=30\nN016 R5=20.4\nN017 L16\nN018 X60 Z5 E\nN019 M05\nN020 M02\nN100 L16\n{L16}"
    )
}

/// Where the tool goes in one L16 call from (x0, z0), as the paper's algorithm says
/// (docs/domain.md §2): while X_T ≥ X_K + A feed in to X_T, cut W toward the chuck, step in by
/// P, and (if still above) feed in and cut back; as (x, z) after each move.
fn zigzag(x0: f64, z0: f64, w: f64, a: f64, p: f64, xk: f64) -> Vec<(f64, f64)> {
    let mut points = Vec::new();
    let (mut xt, mut z) = (x0, z0);
    let mut toward_chuck = true;
    while xt >= xk + a - 1e-9 {
        points.push((xt, z));
        z += if toward_chuck { -w } else { w };
        points.push((xt, z));
        xt -= p;
        toward_chuck = !toward_chuck;
    }
    points
}

/// The moves of the whole job: rapids and the two cycles' cuts, as (rapid, x, z).
fn expected() -> Vec<(bool, f64, f64)> {
    let mut moves = vec![(true, 44.0, 0.0)];
    moves.extend(zigzag(44.0, 0.0, 40.0, 0.5, 2.0, 30.0).into_iter().map(|(x, z)| (false, x, z)));
    moves.push((true, 50.0, 2.0));
    moves.push((true, 30.0, -28.0));
    moves.extend(zigzag(30.0, -28.0, 12.0, 0.2, 1.5, 20.4).into_iter().map(|(x, z)| (false, x, z)));
    moves.push((true, 60.0, 5.0));
    moves
}

/// The unrolled program: every move of [`expected`] as its own block.
fn flat() -> String {
    let mut text = String::from("N001 T1\nN002 S700 M03 F0.5\n");
    for (i, (rapid, x, z)) in expected().into_iter().enumerate() {
        text.push_str(&format!("N{:03} X{x} Z{z}{}\n", i + 3, if rapid { " E" } else { "" }));
    }
    text.push_str("N900 M05\nN901 M02\n");
    text
}

fn read(text: &str) -> Program {
    let nc31 = dialect::by_name("nc31").unwrap();
    nc31.read(text, None).unwrap_or_else(|e| panic!("{e}\n{text}")).0
}

/// The moves of a program read back, as (rapid, x, z) with every axis filled in.
fn moves(program: &Program) -> Vec<(bool, f64, f64)> {
    let (mut x, mut z) = (f64::NAN, f64::NAN);
    let mut out = Vec::new();
    for block in &program.blocks {
        let (rapid, to) = match block {
            Block::Rapid(t) => (true, t),
            Block::Line { to, .. } if to.x.is_some() || to.z.is_some() => (false, to),
            _ => continue,
        };
        x = to.x.unwrap_or(x);
        z = to.z.unwrap_or(z);
        out.push((rapid, x, z));
    }
    out
}

fn assert_same_path(got: &[(bool, f64, f64)], want: &[(bool, f64, f64)]) {
    assert_eq!(got.len(), want.len(), "moves:\n{got:?}\nwanted:\n{want:?}");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        let close = g.0 == w.0 && (g.1 - w.1).abs() < 5e-4 && (g.2 - w.2).abs() < 5e-4;
        assert!(close, "move {}: {g:?}, wanted {w:?}", i + 1);
    }
}

#[test]
fn a_cycle_written_as_a_subprogram_reads_back_as_the_papers_zigzag() {
    let want = expected();
    // 44 → 30.5: passes at 44, 42, …, 32 (seven); 30 → 20.6: at 30, 28.5, …, 21 (seven).
    assert_eq!(want.iter().filter(|m| !m.0).count(), 2 * 7 + 2 * 7);
    let got = moves(&read(&with_subprograms()));
    assert_same_path(&got, &want);
}

#[test]
fn the_subprogram_program_and_the_flat_one_read_back_the_same() {
    let (sub, flat) = (read(&with_subprograms()), read(&flat()));
    assert_same_path(&moves(&sub), &moves(&flat));
    // The blocks that are not moves (tool, spindle, feed mode) agree too.
    let others = |p: &Program| p.blocks.iter().filter(|b| !matches!(b, Block::Rapid(_) | Block::Line { .. })).count();
    assert_eq!(others(&sub), others(&flat));
}

#[test]
fn nc_time_and_check_see_the_expanded_path() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("sub.nc31");
    let flat_path = dir.path().join("flat.nc31");
    std::fs::write(&sub, with_subprograms()).unwrap();
    std::fs::write(&flat_path, flat()).unwrap();
    assert_time_and_check_agree(&sub, &flat_path);
}

/// `nc time` and `nc check` say the same of both programs: the cycle time, and the findings
/// (whose lines differ: the passes of one are in its subprogram).
fn assert_time_and_check_agree(sub: &std::path::Path, flat: &std::path::Path) {
    for command in ["time", "check"] {
        let run = |path: &std::path::Path| {
            let mut args = vec!["nc", command, path.to_str().unwrap(), "--dialect", "nc31"];
            if command == "time" {
                args.extend(["--accel", "200", "--rapid", "10000"]);
            }
            ncsheet(&args)
        };
        let (a, b) = (run(sub), run(flat));
        assert_eq!(a.code, b.code, "{command}: {}\n{}", a.stderr, b.stderr);
        let text = |s: &str| -> Vec<String> {
            let named = |p: &std::path::Path| p.file_name().unwrap().to_string_lossy().into_owned();
            s.replace(&named(sub), "P")
                .replace(&named(flat), "P")
                .lines()
                .filter(|l| command == "check" || l.contains("cycle time"))
                .map(|l| l.split_once(": ").map_or(l, |(_, m)| m).to_string())
                .collect()
        };
        assert_eq!(text(&a.stdout), text(&b.stdout), "{command}:\n{}\n{}", a.stdout, b.stdout);
        if command == "time" {
            assert_eq!(text(&a.stdout).len(), 1, "{}{}", a.stdout, a.stderr);
        }
    }
}

#[test]
fn what_the_control_would_not_run_is_refused_at_its_line() {
    let nc31 = dialect::by_name("nc31").unwrap();
    let refused = |text: &str| nc31.read(text, None).unwrap_err();
    // R5 is never set before L16 uses it.
    let unset = with_subprograms().replace("N008 R5=30\n", "");
    let e = refused(&unset);
    assert!(e.message.contains("R5 has no value"), "{e}");
    assert_eq!(e.line, 21, "{e}");
    // A call of a subprogram that is not written.
    let e = refused("N001 X40 Z0 E\nN002 L21\nN003 M02\n");
    assert_eq!((e.line, e.message.contains("L21")), (2, true), "{e}");
    // A loop that never ends (the depth of cut 0).
    let e = refused(&with_subprograms().replace("N006 R3=2", "N006 R3=0"));
    assert!(e.message.contains("never ends"), "{e}");
    // A subprogram without its M17.
    let e = refused("N001 L03\nN002 M02\nN003 L03\nN004 X40\n");
    assert_eq!(e.line, 3, "{e}");
}

// ---- calls with values, and programs written with subprograms (issue 33, scope 2) ---------

/// The paper's call form: the header binds the call's letters to R parameters and each call
/// gives them values, numbers or a parameter's (docs/domain.md §2, "Calls with values"): the
/// job of [`with_subprograms`], its values now in the two calls (X the final diameter, W the
/// loop, A the allowance, P the depth of cut as the paper's `L16 X W A P`, B the start).
#[test]
fn a_call_with_values_reads_back_as_the_papers_zigzag() {
    let text = format!(
        "N001 T1\nN002 S700 M03 F0.5\nN003 X44 Z0 E\nN004 L16 X30 W40 A0.5 P2 B44\nN005 X50 Z2 E\n\
         N006 X30 Z-28 E\nN007 R9=1.5\nN008 L16 X20.4 W12 A0.2 PR9 B30\nN009 X60 Z5 E\nN010 M05\nN011 M02\n\
         N100 L16 XR5 WR1 AR2 PR3 BR4\n{L16}"
    );
    assert_same_path(&moves(&read(&text)), &expected());
}

/// The repository's sheets/ file, by path (the binary runs in the test's folder).
fn sheet(name: &str) -> String {
    format!("{}/sheets/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// `ncsheet run sheets/chamfer.csv sheets/cycles.bas --dialect nc31 EXTRA…` into `out`: the text.
fn run_cycles(out: &std::path::Path, extra: &[&str]) -> String {
    let (book, bas) = (sheet("chamfer.csv"), sheet("cycles.bas"));
    let mut args = vec!["run", &book, &bas, "--dialect", "nc31", "-o", out.to_str().unwrap()];
    args.extend(extra);
    let run = ncsheet(&args);
    assert_eq!(run.code, 0, "{args:?}: {}", run.stderr);
    std::fs::read_to_string(out).unwrap()
}

/// cycles.bas's L16 as docs/domain.md §2 describes it (zigzag, cutting both ways, the first
/// pass at the blank's diameter B − P, the last exactly at X + A) with its approach and
/// return in rapid 1 mm off the blank (2 on the diameter), from and back to Z1: (rapid, x, z).
fn l16_moves(x: f64, w: f64, a: f64, p: f64, blank: f64) -> Vec<(bool, f64, f64)> {
    let safe = blank + 2.0;
    let mut moves = vec![(true, safe, 1.0), (true, safe, 0.0)];
    let (mut pass, mut z) = (blank, 0.0);
    loop {
        pass = (pass - p).max(x + a);
        moves.push((false, pass, z));
        z = if z == 0.0 { -w } else { 0.0 };
        moves.push((false, pass, z));
        if pass <= x + a {
            break;
        }
    }
    moves.extend([(true, safe, z), (true, safe, 1.0)]);
    moves
}

/// The feed in force at every cut.
fn feeds(program: &Program) -> Vec<f64> {
    let mut feed = f64::NAN;
    let mut out = Vec::new();
    for block in &program.blocks {
        if let Block::Line { to, feed: f } = block {
            feed = f.unwrap_or(feed);
            if to.x.is_some() || to.z.is_some() {
                out.push(feed);
            }
        }
    }
    out
}

#[test]
fn the_cycles_macro_with_subprograms_calls_l16_and_moves_as_the_unrolled_program() {
    let dir = tempfile::tempdir().unwrap();
    let job = ["--sub", "L16", "--arg", "X=30", "--arg", "W=40", "--arg", "P=2", "--arg", "A=0.5"];
    let flat = run_cycles(&dir.path().join("flat.nc31"), &job);
    let mut with = job.to_vec();
    with.push("--subprograms");
    let called = run_cycles(&dir.path().join("sub.nc31"), &with);
    // Written as the paper writes a cycle: one call with its values, the cycle once after
    // M02 under a header binding the call's letters, ended by M17.
    let (main, subprogram) = called.split_once("M02\n").expect("an M02");
    let calls: Vec<&str> = main.lines().filter(|l| l.contains(" L16")).collect();
    assert_eq!(calls.len(), 1, "{called}");
    assert!(calls[0].ends_with(" L16 X30 W40 A0.5 P2 B44 F0.2"), "{called}");
    assert!(!main.lines().any(|l| l.contains("Z-40")), "no pass is written in the main program:\n{called}");
    assert!(subprogram.lines().next().unwrap().ends_with(" L16 XR1 WR2 AR3 PR4 BR5 FR6"), "{called}");
    assert!(subprogram.trim_end().ends_with("M17"), "{called}");
    // Read back with the subprogram run: the path of the unrolled program, and both the
    // path of the cycle worked out here: 44 → 42, 40, …, 32, then 30.5 = X + A.
    let want = l16_moves(30.0, 40.0, 0.5, 2.0, 44.0);
    let passes: Vec<f64> = want.iter().filter(|m| !m.0).map(|m| m.1).step_by(2).collect();
    assert_eq!(passes, [42.0, 40.0, 38.0, 36.0, 34.0, 32.0, 30.5]);
    let (sub, unrolled) = (read(&called), read(&flat));
    assert_same_path(&moves(&sub), &want);
    assert_same_path(&moves(&unrolled), &want);
    // Block for block: the feed of every cut, and the blocks that are no moves.
    assert_eq!(feeds(&sub), feeds(&unrolled));
    assert_eq!(feeds(&sub), [0.2; 14]);
    let others = |p: &Program| -> Vec<Block> {
        p.blocks.iter().filter(|b| !matches!(b, Block::Rapid(_) | Block::Line { .. })).cloned().collect()
    };
    assert_eq!(others(&sub), others(&unrolled));
}

#[test]
fn the_whole_part_with_subprograms_times_and_checks_as_the_unrolled_one() {
    let dir = tempfile::tempdir().unwrap();
    let (flat_path, sub_path) = (dir.path().join("flat.nc31"), dir.path().join("sub.nc31"));
    let flat = run_cycles(&flat_path, &[]);
    let called = run_cycles(&sub_path, &["--subprograms"]);
    // Main's three cycles, each one call with its values (L13's recess shifted 30 along Z).
    let (main, _) = called.split_once("M02\n").expect("an M02");
    for call in
        [" L16 X40 W35 A0.5 P2 B44 F0.2", " L17 A0.5 P3 B44 F0.15", " L13 X44 Z-40 K-60 P3 W2.5 D0.5 A0 F0.05 Q-30"]
    {
        assert_eq!(main.lines().filter(|l| l.ends_with(call)).count(), 1, "{call}:\n{called}");
    }
    // After M02 each subprogram once, those the cycles call (L03, L14) included.
    let named: Vec<String> =
        subprogram_headers(&called).iter().map(|h| h.split(' ').next().unwrap().to_string()).collect();
    assert_eq!(named, ["L16", "L17", "L13", "L03", "L14"], "{called}");
    assert_same_path(&moves(&read(&called)), &moves(&read(&flat)));
    assert_eq!(feeds(&read(&called)), feeds(&read(&flat)));
    assert_time_and_check_agree(&sub_path, &flat_path);
}

/// A cycle of cycles.bas run alone, unrolled and with `--subprograms` (plus `extra`): both texts.
fn flat_and_called(dir: &std::path::Path, sub: &str, extra: &[&str]) -> (String, String) {
    let mut job = vec!["--sub", sub];
    job.extend(extra);
    let flat = run_cycles(&dir.join("flat.nc31"), &job);
    job.push("--subprograms");
    (flat, run_cycles(&dir.join("sub.nc31"), &job))
}

/// The lines of `text` after its M02 that head a subprogram (`N041 L13 XR6 …`), without the
/// label: the first, and each after a subprogram's M17.
fn subprogram_headers(text: &str) -> Vec<String> {
    let (_, after) = text.split_once("M02\n").expect("an M02");
    let mut heads = Vec::new();
    let mut next_is_head = true;
    for line in after.lines() {
        if next_is_head {
            heads.push(line.split_once(' ').map_or(line, |(_, c)| c).to_string());
        }
        next_is_head = line.ends_with("M17");
    }
    heads
}

/// cycles.bas's recess bottom (docs/domain.md §2, L13) as a diameter at z, in closed form: a
/// taper from 36 at Z-10 to 30 at Z-14, a flat, the arc of radius 5 about (Z-22, radius 12)
/// solved for X on its outer side, X = 2(12 + √(5² − (z + 22)²)), a flat, a taper back to 36.
fn recess_bottom(z: f64) -> f64 {
    match z {
        z if z >= -14.0 => 36.0 - 6.0 * (z + 10.0) / -4.0,
        z if z >= -18.0 => 30.0,
        z if z >= -26.0 => 2.0 * (12.0 + (25.0 - (z + 22.0).powi(2)).sqrt()),
        z if z >= -30.0 => 30.0 + 6.0 * (z + 26.0) / -4.0,
        _ => 36.0,
    }
}

#[test]
fn l13_with_subprograms_plunges_to_the_arc_bottom_as_the_unrolled_program() {
    let dir = tempfile::tempdir().unwrap();
    let (flat, called) = flat_and_called(dir.path(), "L13", &[]);
    let (main, _) = called.split_once("M02\n").unwrap();
    let calls: Vec<&str> = main.lines().filter(|l| l.contains(" L13 ")).collect();
    assert_eq!(calls.len(), 1, "{called}");
    assert!(calls[0].ends_with(" L13 X44 Z-10 K-30 P3 W2.5 D0.5 A0 F0.05 Q0"), "{called}");
    assert!(!main.contains("G4"), "no plunge is written in the main program:\n{called}");
    let headers = subprogram_headers(&called);
    assert_eq!(headers, ["L13 XR6 ZR7 KR8 PR0 WR4 DR5 AR9 FR10 QR11", "L14"], "{called}");
    // The plunges as the paper's algorithm places them: the tool's right corner at Z-10, then
    // 2.5 to the left each time, the last one (Z-27) taking what is left of the 20 mm recess
    // for the 3 mm tool; each to the higher bottom under its two corners, or the arc's top
    // (X34 at Z-22) when it lies between them.
    let rights = [-10.0, -12.5, -15.0, -17.5, -20.0, -22.5, -25.0, -27.0];
    let mut want = vec![(true, 46.0, 1.0)];
    for z in rights {
        let (left, right) = (z - 3.0, z);
        let mut x = recess_bottom(left).max(recess_bottom(right));
        if left <= -22.0 && right >= -22.0 {
            x = x.max(34.0);
        }
        want.extend([(true, 46.0, z), (false, x, z), (true, 46.0, z)]);
    }
    want.push((true, 46.0, 1.0));
    // Hand-worked: at Z-20 the corners are over the arc either side of its top.
    assert!(want.contains(&(false, 34.0, -20.0)), "{want:?}");
    // At Z-25 (corners at Z-28 and Z-25) the left one is on the taper: 30 + 6·2/4 = 33.
    assert!(want.contains(&(false, 33.0, -25.0)), "{want:?}");
    let (sub, unrolled) = (read(&called), read(&flat));
    let plunges = |p: &Program| -> Vec<(bool, f64, f64)> {
        let mut m = moves(p);
        m.dedup();
        m
    };
    assert_same_path(&plunges(&sub), &want);
    assert_same_path(&plunges(&unrolled), &want);
    // Block for block: every move, its feed, the dwells and the other blocks.
    assert_eq!(moves(&sub), moves(&unrolled));
    assert_eq!(feeds(&sub), feeds(&unrolled));
    let dwells = |p: &Program| p.blocks.iter().filter(|b| matches!(b, Block::Dwell(s) if *s == 0.5)).count();
    assert_eq!((dwells(&sub), dwells(&unrolled)), (8, 8));
}

/// cycles.bas's L17 passes: the contour L03 shifted out by 21, 18, …, 3, then 0.5 (the blank's
/// 44 less the contour's 20, less the depth of cut 3 each pass, the allowance 0.5 the last).
const L17_SHIFTS: [f64; 8] = [21.0, 18.0, 15.0, 12.0, 9.0, 6.0, 3.0, 0.5];

#[test]
fn l17_with_subprograms_cuts_the_fillet_as_lines_within_arc_tol_as_the_unrolled_program() {
    for tol in ["0.01", "0.002"] {
        let dir = tempfile::tempdir().unwrap();
        let (flat, called) = flat_and_called(dir.path(), "L17", &["--arc-tol", tol]);
        let tol: f64 = tol.parse().unwrap();
        let (main, _) = called.split_once("M02\n").unwrap();
        let calls: Vec<&str> = main.lines().filter(|l| l.contains(" L17")).collect();
        assert_eq!(calls.len(), 1, "{called}");
        assert!(calls[0].ends_with(" L17 A0.5 P3 B44 F0.15"), "{called}");
        assert_eq!(subprogram_headers(&called), ["L17 AR2 PR3 BR4 FR5", "L03"], "{called}");
        let (sub, unrolled) = (read(&called), read(&flat));
        assert_eq!(moves(&sub), moves(&unrolled), "tol {tol}");
        assert_eq!(feeds(&sub), feeds(&unrolled), "tol {tol}");
        assert_fillet_within(&moves(&sub), tol);
    }
}

/// Every pass of L17 as docs/domain.md §2 has it: the contour shifted out by each of
/// [`L17_SHIFTS`] in turn, its fillet (radius 5 about Z-10, diameter 30 + shift, from
/// diameter 20 + shift at Z-10 to 30 + shift at Z-15) cut as lines whose ends lie on the arc
/// (to the 0.001 of the words) and which stray from it by no more than `tol`.
fn assert_fillet_within(moves: &[(bool, f64, f64)], tol: f64) {
    let cuts: Vec<&(bool, f64, f64)> = moves.iter().filter(|m| !m.0).collect();
    let starts: Vec<f64> = cuts.iter().filter(|m| m.2 == 0.0).map(|m| m.1).collect();
    let want: Vec<f64> = L17_SHIFTS.iter().map(|s| 20.0 + s).collect();
    assert_eq!(starts, want, "each pass starts at the face on the shifted contour");
    for shift in L17_SHIFTS {
        let (cz, cr) = (-10.0, 15.0 + shift / 2.0);
        let on_arc: Vec<(f64, f64)> = cuts
            .iter()
            .map(|m| (m.2, m.1 / 2.0))
            .skip_while(|&(z, r)| !(z == -10.0 && (r - (10.0 + shift / 2.0)).abs() < 1e-9))
            .take_while(|&(z, _)| z >= -15.0)
            .collect();
        assert!(on_arc.len() >= 3, "shift {shift}: the fillet as lines: {on_arc:?}");
        assert_eq!(on_arc.last(), Some(&(-15.0, cr)), "shift {shift}");
        for pair in on_arc.windows(2) {
            let [(z0, r0), (z1, r1)] = [pair[0], pair[1]];
            for (z, r) in [(z0, r0), (z1, r1)] {
                assert!(((z - cz).hypot(r - cr) - 5.0).abs() <= 0.0006, "shift {shift}: ({z}, {r}) off the arc");
            }
            // The most a chord strays from its arc: the sagitta of its length on radius 5.
            let half = (z1 - z0).hypot(r1 - r0) / 2.0;
            let sagitta = 5.0 - (25.0 - half * half).sqrt();
            assert!(sagitta <= tol + 1e-9, "shift {shift}: a chord strays {sagitta} > {tol}");
        }
    }
}

/// `--arc-tol` is for a control without arcs. L17 on a control with arcs cuts each pass's
/// fillet as one arc at any tolerance, as before the NC31 subprograms (cycles.bas gives its
/// subprogram on every run, for Nc.Cycle, but the fillet's lines only where they are written);
/// the NC31, which gets the fillet as lines, still refuses a tolerance within its 0.001 step.
#[test]
fn l17_at_an_arc_tol_of_the_controls_step_refuses_only_the_control_without_arcs() {
    let dir = tempfile::tempdir().unwrap();
    let (book, bas) = (sheet("chamfer.csv"), sheet("cycles.bas"));
    for d in ["iso", "linuxcnc", "sinumerik"] {
        let out = dir.path().join(format!("l17.{d}"));
        let args =
            ["run", &book, &bas, "--sub", "L17", "--dialect", d, "--arc-tol", "0.001", "-o", out.to_str().unwrap()];
        let run = ncsheet(&args);
        assert_eq!(run.code, 0, "{args:?}: {}", run.stderr);
        let text = std::fs::read_to_string(&out).unwrap();
        let program = dialect::by_name(d).unwrap().read(&text, None).unwrap_or_else(|e| panic!("{e}\n{text}")).0;
        // Each pass's fillet: clockwise from diameter 20 + shift at Z-10 to 30 + shift at Z-15
        // about diameter 30 + shift, Z-10 (docs/domain.md §2).
        let arcs: Vec<(f64, f64, f64, f64)> = program
            .blocks
            .iter()
            .filter_map(|b| match b {
                Block::Arc { direction: ncsheet::nc::ArcDirection::Clockwise, to, centre, .. } => {
                    Some((to.x?, to.z?, centre.x?, centre.z?))
                }
                _ => None,
            })
            .collect();
        let want: Vec<(f64, f64, f64, f64)> = L17_SHIFTS.iter().map(|s| (30.0 + s, -15.0, 30.0 + s, -10.0)).collect();
        assert_eq!(arcs, want, "{d}:\n{text}");
    }
    for d in ["nc31", "nc81"] {
        let out = dir.path().join(format!("l17.{d}"));
        let run = ncsheet(&[
            "run",
            &book,
            &bas,
            "--sub",
            "L17",
            "--dialect",
            d,
            "--arc-tol",
            "0.001",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_ne!(run.code, 0, "{d}");
        assert!(run.stderr.contains("--arc-tol"), "{d}: {}", run.stderr);
        assert!(!out.exists(), "{d}: nothing written");
    }
}

#[test]
fn nc81_writes_the_words_of_nc31_per_the_paper() {
    // docs/domain.md §1: the chamfer paper's model serves "all NC31- and NC81-type controls";
    // no NC81 manual was available, so nc81 writes what the paper gives, NC31's words.
    let dir = tempfile::tempdir().unwrap();
    let (book, bas) = (sheet("chamfer.csv"), sheet("cycles.bas"));
    let mut texts = Vec::new();
    for (d, extra) in [("nc31", None), ("nc81", None), ("nc31", Some("--subprograms")), ("nc81", Some("--subprograms"))]
    {
        let out = dir.path().join(format!("{d}{}.txt", texts.len()));
        let mut args = vec!["run", &book, &bas, "--dialect", d, "-o", out.to_str().unwrap()];
        args.extend(extra);
        let run = ncsheet(&args);
        assert_eq!(run.code, 0, "{args:?}: {}", run.stderr);
        texts.push(std::fs::read_to_string(&out).unwrap());
    }
    assert_eq!(texts[0], texts[1]);
    assert_eq!(texts[2], texts[3]);
    assert!(texts[3].contains(" L13 X44 "), "{}", texts[3]);
    // Read as nc81 (named, or by the extension .nc81), its subprograms run.
    let program = dir.path().join("part.nc81");
    std::fs::write(&program, &texts[3]).unwrap();
    let p = program.to_str().unwrap();
    for args in [vec!["nc", "check", p], vec!["nc", "check", p, "--dialect", "nc81"]] {
        let run = ncsheet(&args);
        assert_eq!(run.code, 0, "{args:?}: {}{}", run.stdout, run.stderr);
    }
    let run = ncsheet(&["nc", "check", p]);
    assert!(run.stderr.contains("read as nc81 ("), "{}", run.stderr);
}

/// A grooving cycle of a macro's own: three grooves at Z-10, -15, -20, 4, 5 and 6 mm deep on
/// the diameter from X40, each marked as a use of L20 whose blocks are `body`.
fn grooves(body: &str) -> String {
    format!(
        "Sub Main()\n    Nc.Machine = \"lathe\"\n    Nc.Tool 2\n    Nc.FeedPerRev 0.05\n    Nc.Spindle 500\n\
         \x20   Nc.Subprogram \"L20 XR1 ZR2 DR3\", {body}\n    Dim i As Integer\n    For i = 0 To 2\n\
         \x20       Nc.Cycle \"L20\", 40, -10 - 5 * i, 4 + i\n        Nc.Rapid 40, -10 - 5 * i\n\
         \x20       Nc.Line 40 - (4 + i), , 0.05\n        Nc.Rapid 40\n        Nc.EndCycle\n    Next\n\
         \x20   Nc.Spindle 0\nEnd Sub\n"
    )
}

fn run_macro(src: &str) -> Result<Program, String> {
    let mut wb = ncsheet::workbook::Workbook::with_sheet();
    let options = ncsheet::vba::RunOptions::default();
    ncsheet::vba::run(&mut wb, src, "grooves.bas", &options).map(|o| o.program).map_err(|e| e.to_string())
}

fn grooves_program(body: &str) -> Program {
    run_macro(&grooves(body)).unwrap_or_else(|e| panic!("{e}"))
}

/// L20: in rapid to X Z, cut to X − D, out in rapid; one VBA string per block, and several
/// blocks in one string, a line each.
const GROOVE: &str = r#""N1 XR1 ZR2 E", "N2 R4=R1-R3" & vbLf & "N3 XR4 F0.05", "N4 XR1 E M17""#;

#[test]
fn a_macros_own_cycle_is_called_once_per_use_and_reads_back_as_its_grooves() {
    let program = grooves_program(GROOVE);
    let text = dialect::NC31.render_with_subprograms(&program).unwrap();
    let (main, _) = text.split_once("M02\n").expect("an M02");
    let calls: Vec<&str> = main.lines().filter(|l| l.contains(" L20 X")).collect();
    assert_eq!(calls.len(), 3, "{text}");
    assert!(calls[2].ends_with(" L20 X40 Z-20 D6"), "{text}");
    assert_eq!(text.matches("M17").count(), 1, "the subprogram is written once:\n{text}");
    // Each groove: in rapid to X40 at its Z, cut to 40 − depth, out in rapid.
    let mut want = Vec::new();
    for (z, depth) in [(-10.0, 4.0), (-15.0, 5.0), (-20.0, 6.0)] {
        want.extend([(true, 40.0, z), (false, 40.0 - depth, z), (true, 40.0, z)]);
    }
    let got = read(&text);
    assert_same_path(&moves(&got), &want);
    assert_eq!(feeds(&got), [0.05; 3]);
    // Without the option nothing changes: the blocks, as every writer writes them.
    let flat = dialect::by_name("nc31").unwrap().render(&program).unwrap();
    assert!(!flat.contains("L20") && !flat.contains("M17"), "{flat}");
    assert_same_path(&moves(&read(&flat)), &want);
}

#[test]
fn a_subprogram_that_does_not_do_what_its_blocks_do_is_refused() {
    // Deeper instead of shallower: the check says where, in the program with the calls.
    let wrong = GROOVE.replace("R4=R1-R3", "R4=R1+R3");
    let e = dialect::NC31.render_with_subprograms(&grooves_program(&wrong)).unwrap_err();
    assert!(e.message.contains("does not do what the blocks marked for them do"), "{e}");
    assert!(e.message.contains("cuts to X44 Z-10"), "{e}");
    // No feed in the subprogram: the first use's F0.05 is no longer in the main program.
    let no_feed = GROOVE.replace(" F0.05", "");
    let e = dialect::NC31.render_with_subprograms(&grooves_program(&no_feed)).unwrap_err();
    assert!(e.message.contains("cuts to X36 Z-10 at F?"), "{e}");
    // A use never closed; a use opened inside another.
    let mut open = grooves_program(GROOVE);
    open.calls[2].end = None;
    let e = dialect::NC31.render_with_subprograms(&open).unwrap_err();
    assert!(e.message.contains("not closed"), "{e}");
    let e = run_macro(&grooves(GROOVE).replace("        Nc.EndCycle\n", "")).unwrap_err();
    assert!(e.contains("close it with Nc.EndCycle first"), "{e}");
    // A value the call's words would round: the subprogram would cut elsewhere.
    let fine = grooves(GROOVE).replace("4 + i\n", "4.0004 + i\n").replace("40 - (4 + i)", "40 - (4.0004 + i)");
    let e = dialect::NC31.render_with_subprograms(&run_macro(&fine).unwrap()).unwrap_err();
    assert!(e.message.contains("L20's D is 4.0004, which the control's words write as D4"), "{e}");
    assert_eq!(e.block, Some(4), "the first use's first block (after T2, the feed mode, S500): {e}");
    // --subprograms for a control without them.
    let (book, bas) = (sheet("chamfer.csv"), sheet("cycles.bas"));
    let iso = ncsheet(&["run", &book, &bas, "--dialect", "iso", "--subprograms"]);
    assert_eq!(iso.code, 2, "{}", iso.stderr);
    assert!(iso.stderr.contains("--dialect nc31"), "{}", iso.stderr);
}

#[test]
fn nc_subprogram_refuses_what_the_reader_would_not_read() {
    let fails = |lines: &str| run_macro(&format!("Sub Main()\n{lines}\nEnd Sub\n")).unwrap_err();
    assert!(fails("Nc.Subprogram \"L20 X1\", \"N1 M17\"").contains("not to a value"));
    assert!(fails("Nc.Subprogram \"L20 XR1\", \"N1 X2 M17\", \"N2 X3\"").contains("before its last block"));
    assert!(fails("Nc.Subprogram \"L20 XR1\", \"N1 XR1\"").contains("no M17"));
    assert!(
        fails("Nc.Subprogram \"L20 XR1\", \"N1 M17\"\nNc.Subprogram \"L20 XR2\", \"N1 M17\"").contains("differently")
    );
    assert!(fails("Nc.Cycle \"L20\", 1").contains("no Nc.Subprogram before it"));
    assert!(fails("Nc.Subprogram \"L20 XR1\", \"N1 M17\"\nNc.Cycle \"L20\", 1, 2").contains("takes 1 values"));
    assert!(fails("Nc.EndCycle").contains("without an Nc.Cycle"));
}

#[test]
fn a_call_of_a_subprogram_not_written_and_chords_misgiven_are_refused() {
    // L20's body calls L21, which no Nc.Subprogram gives: the writer says so, not the control.
    let body = GROOVE.replace("\"N1 XR1 ZR2 E\"", "\"N1 XR1 ZR2 E\", \"N5 L21\"");
    let e = dialect::NC31.render_with_subprograms(&grooves_program(&body)).unwrap_err();
    assert!(e.message.contains("L20 calls L21, which is not written"), "{e}");
    // Nc.ChordsCW takes the arc's start, end and centre, and an arc of radius 0 has no lines.
    let fails = |call: &str| run_macro(&format!("Sub Main()\n    Dim c\n    c = {call}\nEnd Sub\n")).unwrap_err();
    let e = fails("Nc.ChordsCW(20, -10, 30, -15, 30)");
    assert!(e.contains("Nc.ChordsCW takes the start X, Z, the end X, Z and the centre X, Z"), "{e}");
    // A quarter circle of radius 5 at the default 0.01 mm: the fewest equal chords whose
    // sagitta 5(1 − cos(π/4n)) is within 0.01 less the 0.001 the written ends may move; each
    // end on the circle as the control's words write it, the last the arc's end.
    let src = "Sub Main()\n    Dim c, k\n    c = Nc.ChordsCW(20, -10, 30, -15, 30, -10)\n    \
               For k = LBound(c) To UBound(c)\n        Debug.Print c(k)\n    Next\nEnd Sub\n";
    let mut wb = ncsheet::workbook::Workbook::with_sheet();
    let out = ncsheet::vba::run(&mut wb, src, "chords.bas", &ncsheet::vba::RunOptions::default()).unwrap();
    let values: Vec<f64> = out.printed.iter().map(|l| l.trim().parse().unwrap()).collect();
    let sagitta = |n: u32| 5.0 * (1.0 - (std::f64::consts::FRAC_PI_4 / f64::from(n)).cos());
    let n = (1..).find(|&n| sagitta(n) <= 0.009).unwrap();
    assert_eq!(values.len(), 2 * n as usize, "{values:?}");
    for point in values.chunks(2) {
        let (x, z) = (point[0], point[1]);
        assert!(((z + 10.0).hypot(x / 2.0 - 15.0) - 5.0).abs() <= 0.0006, "({x}, {z}) off the arc");
        assert_eq!(x, (x * 1000.0).round() / 1000.0, "written to the 0.001");
    }
    assert_eq!(values[values.len() - 2..], [30.0, -15.0]);
}
