//! NC31 parameterised subprograms (issue 33, docs/domain.md §2): a cycle written once after
//! the main program's M02 as `Lnn` … `M17`, with R parameters, `IF … THEN … GOTO` and words
//! that take a parameter's value (`XR4`, `W-R1`), called per use. The reader runs it as the
//! control does, so `nc` tools see the real path: the points are checked against the zigzag
//! of the paper's L16 algorithm computed here, and against the flat (unrolled) program.

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
    for command in ["time", "check"] {
        let run = |path: &std::path::Path| {
            let mut args = vec!["nc", command, path.to_str().unwrap(), "--dialect", "nc31"];
            if command == "time" {
                args.extend(["--accel", "200", "--rapid", "10000"]);
            }
            ncsheet(&args)
        };
        let (a, b) = (run(&sub), run(&flat_path));
        assert_eq!(a.code, b.code, "{command}: {}\n{}", a.stderr, b.stderr);
        let strip = |s: &str| s.replace("sub.nc31", "P").replace("flat.nc31", "P");
        if command == "time" {
            let time = |s: &str| s.lines().find(|l| l.contains("cycle time")).map(str::to_string);
            assert!(time(&a.stdout).is_some(), "{}{}", a.stdout, a.stderr);
            assert_eq!(time(&a.stdout), time(&b.stdout));
        } else {
            // Findings name source lines, which differ; their messages must not.
            let messages = |s: &str| -> Vec<String> {
                strip(s).lines().map(|l| l.split_once(": ").map_or(l, |(_, m)| m).to_string()).collect()
            };
            assert_eq!(messages(&a.stdout), messages(&b.stdout));
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
