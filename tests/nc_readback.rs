//! NC programs as a control runs them (issue 15): the DDA interpolator against the paper's
//! table T8.1.1 (docs/domain.md §4).

use std::process::Command;

use ncsheet::nc::dda;

/// Table T8.1.1 of Glavonjić's course notes *Upravljanje i programiranje mašina alatki*
/// (University of Belgrade; docs/domain.md §4), typed from the paper: n = 4, δx = 16, δy = 8;
/// per clock (X p, X q after, X pulse, Y p, Y q after, Y pulse).
const T8_1_1: [(u64, u64, u64, u64, u64, u64, u64); 16] = [
    (1, 16, 0, 1, 8, 8, 0),
    (2, 16, 0, 1, 8, 0, 1),
    (3, 16, 0, 1, 8, 8, 0),
    (4, 16, 0, 1, 8, 0, 1),
    (5, 16, 0, 1, 8, 8, 0),
    (6, 16, 0, 1, 8, 0, 1),
    (7, 16, 0, 1, 8, 8, 0),
    (8, 16, 0, 1, 8, 0, 1),
    (9, 16, 0, 1, 8, 8, 0),
    (10, 16, 0, 1, 8, 0, 1),
    (11, 16, 0, 1, 8, 8, 0),
    (12, 16, 0, 1, 8, 0, 1),
    (13, 16, 0, 1, 8, 8, 0),
    (14, 16, 0, 1, 8, 0, 1),
    (15, 16, 0, 1, 8, 8, 0),
    (16, 16, 0, 1, 8, 0, 1),
];

#[test]
fn dda_reproduces_table_t8_1_1_every_clock() {
    let run = dda::linear(4, &[16, 8]).unwrap();
    assert_eq!(run.clocks().count(), 16);
    for (clock, row) in run.clocks().zip(T8_1_1) {
        let (x, y) = (clock.axes[0], clock.axes[1]);
        let got = (clock.number, x.p, x.q, u64::from(x.pulse), y.p, y.q, u64::from(y.pulse));
        assert_eq!(got, row, "clock {}", row.0);
    }
    // The paper's sums: 16 pulses on X, 8 on Y, both arriving at K after the 16th clock.
    assert_eq!(run.pulses(), vec![16, 8]);
}

#[test]
fn nc_dda_prints_table_t8_1_1() {
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(["nc", "dda", "--bits", "4", "--dx", "16", "--dy", "8"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let rows: Vec<Vec<&str>> = text.lines().map(|l| l.split_whitespace().collect()).collect();
    // The paper writes an overflow as `16-16=0` and a sum below 2ⁿ as the sum kept in q.
    let q = |q_after: u64, pulse: u64, p: u64| {
        if pulse == 1 {
            format!("{}-16={q_after}", q_after + 16)
        } else {
            assert!(q_after < 16 && q_after >= p);
            q_after.to_string()
        }
    };
    for (clock, xp, xq, xd, yp, yq, yd) in T8_1_1 {
        let row = rows.iter().find(|r| r.first() == Some(&clock.to_string().as_str())).expect("clock row");
        let want = [
            clock.to_string(),
            xp.to_string(),
            q(xq, xd, xp),
            xd.to_string(),
            yp.to_string(),
            q(yq, yd, yp),
            yd.to_string(),
        ];
        assert_eq!(row.iter().map(|s| s.to_string()).collect::<Vec<_>>(), want, "clock {clock}");
    }
    assert_eq!(rows.last().unwrap(), &vec!["pulses", "16", "8"]);
}

#[test]
fn nc_dda_takes_millimetres_at_the_machine_increment() {
    let run = |args: &[&str]| Command::new(env!("CARGO_BIN_EXE_ncsheet")).args(args).output().unwrap();
    let mm = run(&["nc", "dda", "--increment", "0.001", "--dx", "0.016", "--dy", "0.008"]);
    let counts = run(&["nc", "dda", "--dx", "16", "--dy", "8"]);
    assert!(mm.status.success(), "{}", String::from_utf8_lossy(&mm.stderr));
    assert_eq!(mm.stdout, counts.stdout);
    let off_grid = run(&["nc", "dda", "--increment", "0.001", "--dx", "0.0165"]);
    assert_eq!(off_grid.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&off_grid.stderr).contains("--dx"));
}

/// A legal move of 16,000,000 increments (a 24-bit adder: 2^24 = 16,777,216 clocks) comes out
/// whole under a 1 GiB address-space cap: its table, about 1.2 GB, is written row by row (held
/// in memory it aborted at the cap; then it was refused past 2^20 clocks). Counted, not timed.
#[test]
fn nc_dda_writes_a_table_of_two_to_the_24_clocks_within_bounded_memory() {
    use std::io::Read;
    let mut child = Command::new("sh")
        .arg("-c")
        .arg("ulimit -v 1048576; exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_ncsheet"))
        .args(["nc", "dda", "--dx", "16000000", "--dy", "3"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdout = child.stdout.take().unwrap();
    let (mut lines, mut head, mut tail) = (0u64, Vec::new(), Vec::new());
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = stdout.read(&mut buf).unwrap();
        if n == 0 {
            break;
        }
        lines += buf[..n].iter().filter(|&&b| b == b'\n').count() as u64;
        if head.len() < 1000 {
            head.extend_from_slice(&buf[..n.min(1000)]);
        }
        tail.extend_from_slice(&buf[..n]);
        let keep = tail.len().saturating_sub(1000);
        tail.drain(..keep);
    }
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "{:?}: {}", out.status, String::from_utf8_lossy(&out.stderr));
    // The title, the column heads, the row of zeros, 2^24 clocks and the pulses.
    assert_eq!(lines, 3 + (1 << 24) + 1);
    let head = String::from_utf8_lossy(&head);
    let rows: Vec<Vec<&str>> = head.lines().map(|l| l.split_whitespace().collect()).collect();
    assert_eq!(rows[0].join(" "), "DDA: 24 bits, 2^24 = 16777216 clocks");
    // Clock 2: X's sum 16,000,000 + 16,000,000 passes 2^24 and leaves 15,222,784 with a
    // pulse; Y's q holds 3 + 3.
    assert_eq!(rows[4], ["2", "16000000", "32000000-16777216=15222784", "1", "3", "6", "0"]);
    let tail = String::from_utf8_lossy(&tail);
    assert_eq!(tail.lines().last().unwrap().split_whitespace().collect::<Vec<_>>(), ["pulses", "16000000", "3"]);
}

/// `nc dda -o OUT` writes through the one atomic write exactly what stdout shows.
#[test]
fn nc_dda_writes_its_table_to_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("t8.txt");
    let run = |args: &[&str]| Command::new(env!("CARGO_BIN_EXE_ncsheet")).args(args).output().unwrap();
    let shown = run(&["nc", "dda", "--bits", "4", "--dx", "16", "--dy", "8"]);
    let written = run(&["nc", "dda", "--bits", "4", "--dx", "16", "--dy", "8", "-o", file.to_str().unwrap()]);
    assert!(written.status.success(), "{}", String::from_utf8_lossy(&written.stderr));
    assert!(written.stdout.is_empty());
    assert_eq!(std::fs::read(&file).unwrap(), shown.stdout);
    let arc = ["nc", "dda", "--arc", "ccw", "--dx=-10", "--dy", "10", "--i=-10", "--j", "0"];
    let shown = run(&arc);
    let written = run(&[&arc[..], &["-o", file.to_str().unwrap()]].concat());
    assert!(written.status.success(), "{}", String::from_utf8_lossy(&written.stderr));
    assert_eq!(std::fs::read(&file).unwrap(), shown.stdout);
}

use ncsheet::nc::motion::{self, Rates};
use ncsheet::nc::{ArcDirection, Block, FeedMode, Machine, Program, Target};

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn a_long_block_is_the_closed_form_trapezoid() {
    // L = 250 mm at v = 3000 mm/min = 50 mm/s, a = 200 mm/s²: v²/a = 12.5 mm < L.
    let (l, v, a) = (250.0, 50.0, 200.0);
    let t = motion::trapezoid(l, v * 60.0, a).unwrap();
    let t_acc = v / a;
    let s_acc = 0.5 * a * t_acc * t_acc;
    let t_cruise = (l - 2.0 * s_acc) / v;
    assert!(close(t.peak, v, 1e-12));
    assert!(close(t.t_accel, t_acc, 1e-12));
    assert!(close(t.t_cruise, t_cruise, 1e-12));
    assert!(close(t.total, 2.0 * t_acc + t_cruise, 1e-12));
}

#[test]
fn a_short_block_is_a_triangle() {
    // L = 2 mm cannot reach 50 mm/s at 200 mm/s² (that takes 12.5 mm): half the block
    // accelerating, s = a·t²/2 = L/2.
    let (l, v, a) = (2.0, 50.0, 200.0);
    let t = motion::trapezoid(l, v * 60.0, a).unwrap();
    let t_half = (l / a).sqrt();
    assert!(close(t.t_cruise, 0.0, 0.0));
    assert!(close(t.total, 2.0 * t_half, 1e-12));
    assert!(close(t.peak, a * t_half, 1e-12));
    assert!(t.peak < v);
}

#[test]
fn axis_velocities_are_the_direction_cosines() {
    // δx = 16, δy = 8 (the paper's move): f_x = 16/√320, f_y = 8/√320.
    let v = motion::axis_velocities(&[16.0, 8.0], 50.0);
    assert!(close(v[0], 50.0 * 16.0 / 320f64.sqrt(), 1e-12));
    assert!(close(v[1], 50.0 * 8.0 / 320f64.sqrt(), 1e-12));
    assert!(close(v[0].hypot(v[1]), 50.0, 1e-12));
}

/// Time to run `length` mm from rest to rest, by stepping the motion: speed up at `a` until
/// the distance left is what braking from the current speed takes, never above `v`.
fn integrate(length: f64, v: f64, a: f64) -> f64 {
    let dt = 1e-6;
    let (mut s, mut speed, mut t) = (0.0, 0.0, 0.0);
    while s < length {
        let braking = speed * speed / (2.0 * a);
        if length - s <= braking {
            speed = (speed - a * dt).max(1e-9);
        } else {
            speed = (speed + a * dt).min(v);
        }
        s += speed * dt;
        t += dt;
    }
    t
}

#[test]
fn a_programs_time_matches_a_numerical_integration() {
    let mut p = Program::new("T", Machine::Mill);
    p.push(Block::FeedMode(FeedMode::PerMinute));
    p.push(Block::Rapid(Target::xyz(0.0, 0.0, 5.0)));
    p.push(Block::Line { to: Target::xyz(0.0, 0.0, -1.0), feed: Some(300.0) }); // 6 mm
    p.push(Block::Line { to: Target::xy(40.0, 30.0), feed: Some(1200.0) }); // 50 mm
                                                                            // A half circle of radius 20 around (40, 50): π·20 mm.
    let centre = Target::xy(40.0, 50.0);
    p.push(Block::Arc { direction: ArcDirection::CounterClockwise, to: Target::xy(40.0, 70.0), centre, feed: None });
    p.push(Block::Line { to: Target::xy(40.5, 70.0), feed: None }); // 0.5 mm: a triangle
    p.push(Block::Dwell(1.5));
    p.push(Block::Rapid(Target::xyz(40.5, 70.0, 25.0))); // 26 mm at the rapid rate
    let (a, rapid) = (500.0, 12000.0);
    let times = motion::program_times(&p, Rates { accel: a, rapid }).unwrap();
    let total: f64 = times.iter().map(|b| b.time).sum();
    let expected = integrate(6.0, 5.0, a)
        + integrate(50.0, 20.0, a)
        + integrate(std::f64::consts::PI * 20.0, 20.0, a)
        + integrate(0.5, 20.0, a)
        + 1.5
        + integrate(26.0, 200.0, a);
    assert!(close(total, expected, 1e-3), "{total} vs {expected}");
    let lengths: Vec<f64> = times.iter().map(|b| b.length).collect();
    assert!(close(lengths[3], std::f64::consts::PI * 20.0, 1e-9), "{lengths:?}");
}

use ncsheet::nc::dialect;
use ncsheet::nc::read::{self, Family};
use ncsheet::nc::{Compensation, Spindle, SpindleDirection, ToolChange, ToolOffset};

fn reread(text: &str, dialect_name: &str) -> String {
    let d = dialect::by_name(dialect_name).unwrap();
    let (program, _) = d.read(text, None).unwrap_or_else(|e| panic!("{dialect_name}: {e}\n{text}"));
    d.render(&program).unwrap_or_else(|e| panic!("{dialect_name}: {e}\n{text}"))
}

/// The programs written by hand from the controls' manuals (tests/nc/<dialect>, the writers'
/// oracle) read back and are written out again to the same text, in every dialect.
#[test]
fn hand_written_programs_read_back_to_the_same_text() {
    for d in dialect::all() {
        let mut read = 0;
        for entry in std::fs::read_dir(format!("tests/nc/{}", d.name())).unwrap() {
            let path = entry.unwrap().path();
            let text = std::fs::read_to_string(&path).unwrap();
            assert_eq!(reread(&text, d.name()), text, "{}", path.display());
            read += 1;
        }
        assert!(read > 0, "no programs in tests/nc/{}", d.name());
    }
}

fn mill_program() -> Program {
    let mut p = Program::new("PLATE", Machine::Mill);
    p.retract = Some(Target::xyz(0.0, 0.0, 50.0));
    p.push(Block::Comment("contour".into()));
    p.push(Block::FeedMode(FeedMode::PerMinute));
    p.push(Block::Tool(ToolChange::new(3)));
    p.push(Block::Spindle(Spindle::Rpm { rpm: 2400.0, direction: SpindleDirection::Clockwise }));
    p.push(Block::Coolant(true));
    p.push(Block::Rapid(Target::xyz(-5.0, 0.0, 2.0)));
    p.push(Block::Compensation(Compensation::Right));
    p.push(Block::Line { to: Target { z: Some(-2.5), ..Target::default() }, feed: Some(120.0) });
    p.push(Block::Line { to: Target::xy(30.0, 0.0), feed: Some(450.0) });
    let centre = Target::xy(30.0, 12.3456);
    p.push(Block::Arc {
        direction: ArcDirection::CounterClockwise,
        to: Target::xy(42.3456, 12.3456),
        centre,
        feed: None,
    });
    let centre = Target::xy(30.0, 12.3456);
    p.push(Block::Arc {
        direction: ArcDirection::Clockwise,
        to: Target::xy(17.6544, 12.3456),
        centre,
        feed: Some(300.0),
    });
    p.push(Block::Dwell(0.75));
    p.push(Block::Compensation(Compensation::Off));
    p
}

fn lathe_program() -> Program {
    let mut p = Program::new("SHAFT", Machine::Lathe);
    p.number = Some(42);
    p.retract = Some(Target::xz(80.0, 10.0));
    p.push(Block::Tool(ToolChange::new(2)));
    p.push(Block::FeedMode(FeedMode::PerRevolution));
    let direction = SpindleDirection::Clockwise;
    p.push(Block::Spindle(Spindle::SurfaceSpeed { metres_per_min: 200.0, max_rpm: 3000.0, direction }));
    p.push(Block::Rapid(Target::xz(30.0, 2.0)));
    p.push(Block::Line { to: Target::xz(30.0, -20.0), feed: Some(0.15) });
    let centre = Target::xz(40.0, -20.0);
    p.push(Block::Arc {
        direction: ArcDirection::CounterClockwise,
        to: Target::xz(40.0, -25.0),
        centre,
        feed: Some(0.1),
    });
    p.push(Block::Line { to: Target::xz(56.0, -25.0), feed: None });
    p
}

/// Programs our writers produce read back into the model and are written out again to the
/// same text, in every dialect that writes them (NC31 has neither arcs nor G96).
#[test]
fn generated_programs_read_back_to_the_same_text() {
    for d in dialect::all() {
        let name = d.name();
        for mut p in [mill_program(), lathe_program()] {
            if name == "linuxcnc" {
                p.number = None;
            }
            if !d.writes(p.machine) || matches!(name, "nc31" | "nc81") {
                continue;
            }
            let text = d.render(&p).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(reread(&text, name), text, "{name}");
        }
    }
}

#[test]
fn moves_read_as_the_control_means_them() {
    // Inches, incremental moves and an R-form arc: the quarter circle of radius 10 from (0, 0)
    // to (10, 10) turning clockwise has its centre at (10, 0): from there the start lies at
    // 180° and the end at 90°, a clockwise quarter (around (0, 10) it would be 270°).
    let text = "G20 G17 G90 G94\nG0 X0 Y0 Z0.1\nG91 G1 Z-0.2 F10\nG90\nG2 X0.3937007874 Y0.3937007874 R0.3937007874\n";
    let p = read::read(text, Family::LinuxCnc, None).unwrap();
    assert_eq!(p.machine, Machine::Mill);
    let Block::Line { to, feed } = &p.blocks[2] else { panic!("{:?}", p.blocks) };
    assert!(close(to.z.unwrap(), -0.1 * 25.4, 1e-9) && close(feed.unwrap(), 254.0, 1e-9));
    let Block::Arc { centre, to, direction, .. } = &p.blocks[3] else { panic!("{:?}", p.blocks) };
    assert_eq!(*direction, ArcDirection::Clockwise);
    assert!(close(centre.x.unwrap(), 10.0, 1e-6) && close(centre.y.unwrap(), 0.0, 1e-6), "{centre:?}");
    assert!(close(to.x.unwrap(), 10.0, 1e-6));
    // LinuxCNC's radius mode on a lathe (G8): X10 is a diameter of 20 in the model.
    let p = read::read("G18 G8 G90\nG0 X10 Z1\n", Family::LinuxCnc, None).unwrap();
    assert_eq!(p.machine, Machine::Lathe);
    assert_eq!(p.blocks[0], Block::Rapid(Target::xz(20.0, 1.0)));
}

#[test]
fn unknown_words_are_errors_naming_line_and_column() {
    let cases = [
        ("G21 G90\nG1 X1 Q5 F100\n", 2, 7),
        ("G21\nG0 X0 Y0\nG1 X1 F10\nG33 Z-5 K1\n", 4, 1),
        ("G0 X0 Y0\nG1 X1 $ F10\n", 2, 7),
        ("G0 X0 Y0\nG1 X1 F10 M47\n", 2, 11),
        ("G0 X0 Y0\nG1 X1 F\n", 2, 7),
        ("G0 X0 Y0\nG2 X10 Y10 R1\n", 2, 12),
        // A word that means nothing without its code is not dropped: P without G4.
        ("G0 X0 Y0\nG1 X1 P5 F10\n", 2, 7),
    ];
    for (text, line, column) in cases {
        let e = read::read(text, Family::Fanuc, Some(Machine::Mill)).unwrap_err();
        assert_eq!((e.line, e.column), (line, column), "{text:?}: {e}");
    }
}

mod common;

use common::rs274::{self as rs274, Move};

/// The moves our reader makes of a program, as rs274 reports them: absolute mm, X as a radius
/// on a lathe, axes never set at 0, arcs by their end and centre in the plane.
fn our_moves(p: &Program) -> Vec<Move> {
    let lathe = p.machine == Machine::Lathe;
    let x_true = |x: f64| if lathe { x / 2.0 } else { x };
    let mut at = [0.0f64; 3];
    let mut moves = Vec::new();
    for b in &p.blocks {
        let (Block::Rapid(t) | Block::Line { to: t, .. } | Block::Arc { to: t, .. }) = b else { continue };
        at = [t.x.map(x_true).unwrap_or(at[0]), t.y.unwrap_or(at[1]), t.z.unwrap_or(at[2])];
        moves.push(match b {
            Block::Rapid(_) => Move::Traverse { x: at[0], y: at[1], z: at[2] },
            Block::Line { .. } => Move::Feed { x: at[0], y: at[1], z: at[2] },
            Block::Arc { direction, centre, .. } => {
                let rotation = if *direction == ArcDirection::CounterClockwise { 1 } else { -1 };
                if lathe {
                    let (cz, cx) = (centre.z.unwrap(), x_true(centre.x.unwrap()));
                    Move::Arc {
                        first_end: at[2],
                        second_end: at[0],
                        first_centre: cz,
                        second_centre: cx,
                        rotation,
                        axis_end: at[1],
                    }
                } else {
                    let (cx, cy) = (centre.x.unwrap(), centre.y.unwrap());
                    Move::Arc {
                        first_end: at[0],
                        second_end: at[1],
                        first_centre: cx,
                        second_centre: cy,
                        rotation,
                        axis_end: at[2],
                    }
                }
            }
            _ => unreachable!(),
        });
    }
    moves
}

fn same_moves(a: &[Move], b: &[Move]) -> bool {
    let near = |x: &[f64], y: &[f64]| x.iter().zip(y).all(|(p, q)| (p - q).abs() < 1e-4);
    a.len() == b.len()
        && a.iter().zip(b).all(|pair| match pair {
            (Move::Traverse { x, y, z }, Move::Traverse { x: p, y: q, z: r })
            | (Move::Feed { x, y, z }, Move::Feed { x: p, y: q, z: r }) => near(&[*x, *y, *z], &[*p, *q, *r]),
            (
                Move::Arc { first_end, second_end, first_centre, second_centre, rotation, axis_end },
                Move::Arc {
                    first_end: a1,
                    second_end: a2,
                    first_centre: c1,
                    second_centre: c2,
                    rotation: r,
                    axis_end: e,
                },
            ) => {
                rotation == r
                    && near(
                        &[*first_end, *second_end, *first_centre, *second_centre, *axis_end],
                        &[*a1, *a2, *c1, *c2, *e],
                    )
            }
            _ => false,
        })
}

/// LinuxCNC's interpreter and our reader make the same moves of the same programs.
#[test]
fn rs274_moves_equal_our_readers_moves() {
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed (bash .ci/run installs linuxcnc-uspace)");
        return;
    }
    let hand = "%\n(HAND)\nG21 G17 G90 G94\nG0 X5 Y5 Z2\nG1 Z-1 F200\nG91 G1 X20 Y0\nG90 G3 X25 Y15 R-5\n\
                G2 X35 Y15 R5\nG1 X35 Y5\nG3 X30 Y0 I-5 J0\nG0 Z10\nM2\n%\n";
    let mut mill = mill_program();
    mill.blocks.retain(|b| !matches!(b, Block::Compensation(_)));
    let generated = [mill, lathe_program()].map(|mut p| {
        p.number = None;
        dialect::by_name("linuxcnc").unwrap().render(&p).unwrap()
    });
    let lathe_nc = std::fs::read_to_string("tests/nc/linuxcnc/lathe.nc").unwrap();
    let dir = tempfile::tempdir().unwrap();
    for (i, text) in [hand.to_string(), lathe_nc, generated[0].clone(), generated[1].clone()].iter().enumerate() {
        let path = dir.path().join(format!("p{i}.ngc"));
        std::fs::write(&path, text).unwrap();
        let theirs = rs274::moves(&path).unwrap_or_else(|e| panic!("rs274 rejected program {i}:\n{e}\n{text}"));
        let ours = our_moves(&read::read(text, Family::LinuxCnc, None).unwrap());
        assert!(same_moves(&ours, &theirs), "program {i}:\nours   {ours:?}\nrs274 {theirs:?}\n{text}");
    }
}

#[test]
fn nc_time_prints_the_cycle_time() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.ngc");
    std::fs::write(&path, "G21 G17 G90 G94\nG0 X0 Y0 Z0\nG1 X100 F3000\nG4 P0.5\nM2\n").unwrap();
    let run = |file: &std::path::Path| {
        Command::new(env!("CARGO_BIN_EXE_ncsheet"))
            .args(["nc", "time", "--accel", "200", "--rapid", "10000", "--dialect", "linuxcnc"])
            .arg(file)
            .output()
            .unwrap()
    };
    let out = run(&path);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    // 100 mm at 50 mm/s with 200 mm/s²: L/v + v/a = 2 + 0.25 s; the dwell 0.5 s.
    assert!(text.contains("cycle time 2.750 s"), "{text}");
    std::fs::write(&path, "G21 G17 G90 G94\nG0 X0 Y0 Z0\nG1 X100 E5 F3000\n").unwrap();
    let out = run(&path);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("line 3, column 9"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The cam programs of the shipped example (sheets/cam-turret.csv, fitted arcs by the
/// hundred) read back to the same text in both dialects, and rs274 moves as our reader does.
#[test]
fn cam_programs_of_the_example_read_back() {
    use ncsheet::geometry::cam::{by_disc, fit_cam, CamOptions};
    use ncsheet::nc::cam::{self as nc_cam, cam_program, CamNcOptions};
    use ncsheet::nc::cam_sheet::parse_sheet;
    let segments = parse_sheet(include_str!("../sheets/cam-turret.csv")).unwrap();
    let options = CamOptions::either_side(0.001, true);
    let dir = tempfile::tempdir().unwrap();
    let rs274_here = rs274::available();
    for (disc, s) in by_disc(&segments) {
        let cam = fit_cam(&disc, &s, &options).unwrap();
        for side in [nc_cam::Compensation::Off, nc_cam::Compensation::Right] {
            // A 2 mm cutter with a 1.5 mm lead: the default 10 mm one cannot plunge clear of
            // disc III's steep return next to its start.
            let options =
                CamNcOptions { compensation: side, cutter_diameter: 2.0, lead: 1.5, ..CamNcOptions::default() };
            let program = match cam_program(&cam, &options) {
                Ok(p) => p,
                Err(e) if side != nc_cam::Compensation::Off && e.contains("plunge point") => continue,
                Err(e) => panic!("disc {disc}: {e}"),
            };
            for name in ["iso", "linuxcnc"] {
                let mut p = program.clone();
                if name == "linuxcnc" {
                    p.number = None;
                }
                let text = dialect::by_name(name).unwrap().render(&p).unwrap();
                assert_eq!(reread(&text, name), text, "disc {disc}, {name}");
                if name == "linuxcnc" && side == nc_cam::Compensation::Off && rs274_here {
                    let path = dir.path().join("cam.ngc");
                    std::fs::write(&path, &text).unwrap();
                    let theirs = rs274::moves(&path).unwrap();
                    let ours = our_moves(&read::read(&text, Family::LinuxCnc, None).unwrap());
                    assert!(
                        same_moves(&ours, &theirs),
                        "disc {disc}: {} moves vs rs274's {}",
                        ours.len(),
                        theirs.len()
                    );
                }
            }
        }
    }
}

/// A hand-written Sinumerik lathe program: radius mode (DIAMOF), an arc by CR=, LIMS=, MSG,
/// `T1 D1`, the dwell `G4 F`, inches by G70.
#[test]
fn sinumerik_words_read_as_the_control_means_them() {
    let text = "%_N_SHAFT_MPF\n;$PATH=/_N_MPF_DIR\nN10 G18 DIAMOF G90 G71\nN20 T1 D1 ; roughing tool\n\
                N30 G95 LIMS=3000\nN40 G96 S200 M3\nN50 G0 X20 Z2\nN60 G1 Z-10 F0.2\n\
                N70 G2 X25 Z-15 CR=5 F0.1\nN80 MSG(\"check the shoulder\")\nN90 DIAMON\nN100 G1 X60\n\
                N110 G4 F1.5\nN120 G70 G1 Z-0.5\nN130 M5\nN140 M30\n";
    let (p, lines) = dialect::by_name("sinumerik").unwrap().read(text, None).unwrap();
    assert_eq!(p.name, "SHAFT");
    assert_eq!(p.machine, Machine::Lathe);
    let direction = SpindleDirection::Clockwise;
    // In radius mode X20 is a radius: the model's X is the diameter 40. The clockwise quarter
    // of radius 5 from (Z-10, R20) to (Z-15, R25) turns around (Z-10, R25): from there the
    // start lies straight below and the end straight left (around (Z-15, R20) it would turn
    // counter-clockwise).
    let want = vec![
        Block::Tool(ToolChange::new(1)),
        Block::Comment("roughing tool".into()),
        Block::FeedMode(FeedMode::PerRevolution),
        Block::Spindle(Spindle::SurfaceSpeed { metres_per_min: 200.0, max_rpm: 3000.0, direction }),
        Block::Rapid(Target::xz(40.0, 2.0)),
        Block::Line { to: Target { z: Some(-10.0), ..Target::default() }, feed: Some(0.2) },
        Block::Arc {
            direction: ArcDirection::Clockwise,
            to: Target::xz(50.0, -15.0),
            centre: Target::xz(50.0, -10.0),
            feed: Some(0.1),
        },
        Block::Comment("check the shoulder".into()),
        Block::Line { to: Target { x: Some(60.0), ..Target::default() }, feed: None },
        Block::Dwell(1.5),
        Block::Line { to: Target { z: Some(-12.7), ..Target::default() }, feed: None },
        Block::Spindle(Spindle::Stop),
    ];
    assert_eq!(p.blocks.len(), want.len(), "{:?}", p.blocks);
    for (got, want) in p.blocks.iter().zip(&want) {
        match (got, want) {
            (Block::Arc { centre: c, to: t, .. }, Block::Arc { centre: wc, to: wt, .. }) => {
                assert!(close(c.x.unwrap(), wc.x.unwrap(), 1e-9) && close(c.z.unwrap(), wc.z.unwrap(), 1e-9), "{c:?}");
                assert_eq!(t, wt);
            }
            (Block::Line { to: t, .. }, Block::Line { to: wt, .. }) if t.z.is_some() && wt.z.is_some() => {
                assert!(close(t.z.unwrap(), wt.z.unwrap(), 1e-9), "{t:?}");
            }
            _ => assert_eq!(got, want),
        }
    }
    assert_eq!(lines, vec![4, 4, 5, 6, 7, 8, 9, 10, 12, 13, 14, 15]);
}

/// Plain language with CT (tangent arc), CR (arc by radius), IX (incremental), the dwell
/// cycle and M functions riding on the moves.
#[test]
fn heidenhain_blocks_read_as_the_control_means_them() {
    let text = "0 BEGIN PGM CT MM\n1 TOOL CALL 2 Z S2000\n2 L X+0 Y+0 Z+2 R0 FMAX M3\n3 L Z-1 F100\n\
                4 L X+10 RL F300\n5 CT X+20 Y+10\n6 CR X+30 Y+0 R+10 DR-\n7 L IX+5 F200\n\
                8 CYCL DEF 9.0 DWELL TIME\n9 CYCL DEF 9.1 DWELL 2\n10 L Z+50 R0 FMAX M5\n11 END PGM CT MM\n";
    let (p, _) = dialect::by_name("heidenhain").unwrap().read(text, None).unwrap();
    let direction = SpindleDirection::Clockwise;
    let z = |z: f64| Target { z: Some(z), ..Target::default() };
    // CT leaves (10, 0) along +X (the line before) for (20, 10): the circle tangent to the
    // X axis at (10, 0) through (20, 10) has its centre at (10, 10), counter-clockwise. CR from
    // (20, 10) to (30, 0), R 10, clockwise, the shorter arc: around (20, 0).
    let want = vec![
        Block::Tool(ToolChange::new(2)),
        Block::Spindle(Spindle::Rpm { rpm: 2000.0, direction }),
        Block::Compensation(Compensation::Off),
        Block::Rapid(Target::xyz(0.0, 0.0, 2.0)),
        Block::FeedMode(FeedMode::PerMinute),
        Block::Line { to: z(-1.0), feed: Some(100.0) },
        Block::Compensation(Compensation::Left),
        Block::Line { to: Target { x: Some(10.0), ..Target::default() }, feed: Some(300.0) },
        Block::Arc {
            direction: ArcDirection::CounterClockwise,
            to: Target::xy(20.0, 10.0),
            centre: Target::xy(10.0, 10.0),
            feed: None,
        },
        Block::Arc {
            direction: ArcDirection::Clockwise,
            to: Target::xy(30.0, 0.0),
            centre: Target::xy(20.0, 0.0),
            feed: None,
        },
        Block::Line { to: Target { x: Some(35.0), ..Target::default() }, feed: Some(200.0) },
        Block::Dwell(2.0),
        Block::Spindle(Spindle::Stop),
        Block::Compensation(Compensation::Off),
        Block::Rapid(z(50.0)),
    ];
    assert_eq!(p.blocks.len(), want.len(), "{:#?}", p.blocks);
    for (got, want) in p.blocks.iter().zip(&want) {
        if let (Block::Arc { centre: c, direction: d, .. }, Block::Arc { centre: wc, direction: wd, .. }) = (got, want)
        {
            assert_eq!(d, wd);
            assert!(close(c.x.unwrap(), wc.x.unwrap(), 1e-9) && close(c.y.unwrap(), wc.y.unwrap(), 1e-9), "{c:?}");
        } else {
            assert_eq!(got, want);
        }
    }
}

#[test]
fn nc31_rapids_are_marked_e_and_every_other_move_cuts_per_revolution() {
    let text = "N001 T1\nN002 S800 M03\nN003 X50 Z2 E\nN004 X40 Z0 F0.1\nN005 Z-10\nN006 G4 D0.5\nN007 M02\n";
    let (p, _) = dialect::by_name("nc31").unwrap().read(text, None).unwrap();
    assert_eq!(p.machine, Machine::Lathe);
    let direction = SpindleDirection::Clockwise;
    assert_eq!(
        p.blocks,
        vec![
            Block::FeedMode(FeedMode::PerRevolution),
            Block::Tool(ToolChange::new(1)),
            Block::Spindle(Spindle::Rpm { rpm: 800.0, direction }),
            Block::Rapid(Target::xz(50.0, 2.0)),
            Block::Line { to: Target::xz(40.0, 0.0), feed: Some(0.1) },
            Block::Line { to: Target { z: Some(-10.0), ..Target::default() }, feed: None },
            Block::Dwell(0.5),
        ]
    );
}

#[test]
fn unknown_words_of_every_dialect_are_errors_naming_line_and_column() {
    let cases = [
        ("sinumerik", "N10 G17 G90\nN20 G0 X0 Y0\nN30 G1 X10 Y5 F100 SOFT\n", 3, 20),
        ("sinumerik", "N10 G17 G90\nN20 T=\"DRILL\"\n", 2, 5),
        ("sinumerik", "N10 G17 G90\nN20 G0 X0 Y0\nN30 G2 X10 Y10 CR=AC(5)\n", 3, 19),
        ("sinumerik", "N10 G17 G90\nN20 G0 X0 Y0\nN30 G2 X10 Y10 R5\n", 3, 16),
        ("sinumerik", "N10 G17 G90 (no comment)\n", 1, 13),
        ("heidenhain", "0 BEGIN PGM A MM\n1 L X+0 Y+0 FMAX\n2 L X+5 Q5 F100\n3 END PGM A MM\n", 3, 9),
        ("heidenhain", "0 BEGIN PGM A MM\n1 L X+0 Y+0 FMAX\n2 RND R2\n3 END PGM A MM\n", 3, 3),
        ("heidenhain", "0 BEGIN PGM A MM\n1 L X+0 Y+0 FMAX\n2 C X+5 Y+0 DR+\n3 END PGM A MM\n", 3, 3),
        ("heidenhain", "0 BEGIN PGM A MM\n1 L X+0 Y+0 FMAX\n", 2, 1),
        ("heidenhain", "1 L X+0 Y+0 FMAX\n", 1, 3),
        ("nc31", "N001 T1\nN002 S800 M03\nN003 X50 Z2 E\nN004 G1 X40 F0.1\n", 4, 6),
        ("nc31", "N001 X50 Z2 E\nN002 X40 Q5 F0.1\n", 2, 10),
    ];
    for (name, text, line, column) in cases {
        let e = dialect::by_name(name).unwrap().read(text, None).unwrap_err();
        assert_eq!((e.line, e.column), (line, column), "{name} {text:?}: {e}");
    }
}

/// `nc time --dialect` takes every dialect the writers know: a program written in each is
/// timed as the closed form says.
#[test]
fn nc_time_reads_every_dialect() {
    let dir = tempfile::tempdir().unwrap();
    for d in dialect::all() {
        let mill = d.writes(Machine::Mill);
        let mut p = Program::new("TIMED", if mill { Machine::Mill } else { Machine::Lathe });
        let direction = SpindleDirection::Clockwise;
        let expected = if mill {
            p.push(Block::FeedMode(FeedMode::PerMinute));
            p.push(Block::Spindle(Spindle::Rpm { rpm: 1000.0, direction }));
            p.push(Block::Rapid(Target::xyz(0.0, 0.0, 0.0)));
            p.push(Block::Line { to: Target::xy(100.0, 0.0), feed: Some(3000.0) });
            // 100 mm at 50 mm/s with 200 mm/s²: L/v + v/a.
            100.0 / 50.0 + 50.0 / 200.0
        } else {
            p.push(Block::FeedMode(FeedMode::PerRevolution));
            p.push(Block::Spindle(Spindle::Rpm { rpm: 500.0, direction }));
            p.push(Block::Rapid(Target::xz(40.0, 2.0)));
            p.push(Block::Line { to: Target::xz(40.0, -98.0), feed: Some(0.25) });
            // 0.25 mm/rev at 500 1/min: 125 mm/min over 100 mm.
            let v = 125.0 / 60.0;
            100.0 / v + v / 200.0
        };
        let path = dir.path().join(format!("{}.nc", d.name()));
        std::fs::write(&path, d.render(&p).unwrap()).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
            .args(["nc", "time", "--accel", "200", "--rapid", "10000", "--dialect", d.name()])
            .arg(&path)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}: {}", d.name(), String::from_utf8_lossy(&out.stderr));
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(text.contains(&format!("cycle time {expected:.3} s")), "{}: {text}", d.name());
    }
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(["nc", "time", "--accel", "200", "--rapid", "10000", "--dialect", "nope", "p.nc"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    for name in dialect::names() {
        assert!(err.contains(name), "{name} not offered: {err}");
    }
}

/// The time of a block at one speed v (mm/s) from rest to rest: the closed-form trapezoid,
/// or the triangle when the block is too short to reach v.
fn closed_form(length: f64, v: f64, a: f64) -> f64 {
    if length * a >= v * v {
        length / v + v / a
    } else {
        2.0 * (length / a).sqrt()
    }
}

/// Constant surface speed with feed per revolution: turning along Z at one diameter runs the
/// spindle at 1000·v/(π·D), capped by G50 S; the feed is F·rpm.
#[test]
fn g96_with_g95_times_a_cut_at_the_diameter_it_turns() {
    let text = "%\nO0001 (CSS)\nN10 G21 G18 G40\nN20 G99\nN30 G50 S2000\nN40 G96 S150 M3\n\
                N50 G0 X40. Z2.\nN60 G1 Z-98. F0.2\nN70 G0 X10. Z2.\nN80 G1 Z-48. F0.1\nN90 M30\n%\n";
    let (p, _) = read::read_dialect(text, &ncsheet::nc::dialect::ISO, None).unwrap();
    let a = 100.0;
    let times = motion::program_times(&p, Rates { accel: a, rapid: 10000.0 }).unwrap();
    let got: Vec<f64> = times.iter().map(|t| t.time).collect();
    // At ⌀40: 150 000/(π·40) = 1193.7 1/min, under the limit; at ⌀10 it would be 4774.6:
    // the spindle turns at its limit 2000.
    let rpm40 = 150_000.0 / (std::f64::consts::PI * 40.0);
    let rapid = 10000.0 / 60.0;
    let want = [
        0.0,
        closed_form(100.0, 0.2 * rpm40 / 60.0, a),
        closed_form(15f64.hypot(100.0), rapid, a),
        closed_form(50.0, 0.1 * 2000.0 / 60.0, a),
    ];
    assert_eq!(got.len(), want.len(), "{times:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(close(*g, w, 1e-9), "{got:?} vs {want:?}");
    }
}

/// Facing under constant surface speed: the spindle speeds up as the diameter shrinks, until
/// the limit (LIMS=). With an acceleration too large to matter, the time is the integral of
/// ds/(F·n(D)/60) over the radial path, ds = dD/2.
#[test]
fn g96_facing_speeds_up_to_the_limit_as_the_diameter_shrinks() {
    let text = "%_N_FACE_MPF\nN10 G18 DIAMON G90 G71\nN20 G95\nN30 LIMS=3000\nN40 G96 S200 M3\n\
                N50 G0 X80 Z0\nN60 G1 X20 F0.1\nN70 M30\n";
    let (p, _) = read::read_dialect(text, &ncsheet::nc::dialect::SINUMERIK, None).unwrap();
    let times = motion::program_times(&p, Rates { accel: 1e7, rapid: 10000.0 }).unwrap();
    let (v, f, max) = (200.0, 0.1, 3000.0);
    let pi = std::f64::consts::PI;
    // The diameter below which 1000·v/(π·D) exceeds the limit.
    let dc = 1000.0 * v / (pi * max);
    let uncapped = 60.0 * pi / (1000.0 * v * f) * (80.0 * 80.0 - dc * dc) / 4.0;
    let capped = (dc - 20.0) / 2.0 / (f * max / 60.0);
    let cut = times.last().unwrap();
    assert_eq!(cut.kind, "line");
    assert!(close(cut.length, 30.0, 1e-12));
    assert!(close(cut.time, uncapped + capped, 1e-4), "{} vs {}", cut.time, uncapped + capped);
}

/// `G1 F100` alone sets the feed for the cuts after it, and is written back as it was.
#[test]
fn a_lone_feed_block_sets_the_feed() {
    let text = "%\n(FEED)\nN10 G21 G17 G90 G40\nN20 G94\nN30 G0 X0 Y0 Z0\nN40 G1 F100\nN50 G1 X50\nN60 M2\n%\n";
    let (p, _) = read::read_dialect(text, &ncsheet::nc::dialect::LINUXCNC, None).unwrap();
    assert_eq!(reread(text, "linuxcnc"), text);
    let a = 50.0;
    let times = motion::program_times(&p, Rates { accel: a, rapid: 10000.0 }).unwrap();
    let total: f64 = times.iter().map(|t| t.time).sum();
    assert!(close(total, closed_form(50.0, 100.0 / 60.0, a), 1e-9), "{times:?}");
    let plain =
        "0 BEGIN PGM FEED MM\n1 L X+0.0000 Y+0.0000 Z+0.0000 FMAX\n2 L F100\n3 L X+50.0000\n4 END PGM FEED MM\n";
    assert_eq!(reread(plain, "heidenhain"), plain);
}

/// The nearest point on the grid to the circle of radius r around the origin at angle t.
fn on_grid(r: f64, t: f64) -> (i64, i64) {
    ((r * t.cos()).round() as i64, (r * t.sin()).round() as i64)
}

/// Circular DDA: every position after a pulse lies within one increment on each axis of the
/// true circle (the radius of the start), the path turns the programmed way, and the end is
/// reached exactly, for arcs of every size and sweep, full circles included.
#[test]
fn dda_circles_stay_near_the_circle_and_end_exactly() {
    let mut checked = 0;
    let mut worst = 0.0f64;
    let mut boxed_out = 0;
    let radii = (1..=64).map(|r| r as f64 * 1.37).chain([100.0, 257.0, 1000.0, 4095.0, 20000.0]);
    for r in radii {
        for (t0, t1) in [(0.0, 1.0), (0.3, 2.9), (1.2, 5.0), (-2.0, 0.7), (0.0, 0.0), (0.8, 0.8), (3.0, -3.0)] {
            for direction in [ArcDirection::CounterClockwise, ArcDirection::Clockwise] {
                let (start, end) = (on_grid(r, t0), on_grid(r, t1));
                let r_true = (start.0 as f64).hypot(start.1 as f64);
                if ((end.0 as f64).hypot(end.1 as f64) - r_true).abs() > 0.5 {
                    continue;
                }
                let bits = dda::bits_for_circle(start, end);
                let clocks = dda::circular(bits, start, end, direction)
                    .and_then(|run| run.clocks().collect::<Result<Vec<_>, _>>())
                    .unwrap_or_else(|e| panic!("r {r} {start:?}→{end:?} {direction:?}: {e}"));
                assert_eq!(clocks.last().map_or(start, |c| c.position), end, "r {r} {t0}→{t1} {direction:?}");
                let mut at = start;
                let mut turned = 0.0;
                for c in &clocks {
                    let (x, y) = c.position;
                    // Within one increment on each axis of a point of the circle: the box of
                    // ±1 around the position meets the circle.
                    let (ax, ay) = ((x as f64).abs(), (y as f64).abs());
                    let nearest = (ax - 1.0).max(0.0).hypot((ay - 1.0).max(0.0));
                    let farthest = (ax + 1.0).hypot(ay + 1.0);
                    if !(nearest <= r_true && r_true <= farthest) {
                        boxed_out += 1;
                    }
                    worst = worst.max(((x as f64).hypot(y as f64) - r_true).abs());
                    assert!(c.steps.iter().all(|s| s.abs() <= 1));
                    // The turn from the last position, as a cross product: its sign is the direction.
                    turned += (at.0 * y - at.1 * x) as f64;
                    at = (x, y);
                }
                let ccw = direction == ArcDirection::CounterClockwise;
                assert!(if ccw { turned > 0.0 } else { turned < 0.0 }, "r {r} {t0}→{t1} {direction:?} turned {turned}");
                checked += 1;
            }
        }
    }
    assert!(checked > 500, "{checked}");
    // Every position within one increment on each axis of the circle (330 of them strayed up
    // to 2.1 increments radially when the Y adder started again one clock late past X = 0);
    // radially that is at most √2, where both axes are off by a whole increment at once.
    assert_eq!(boxed_out, 0, "worst {worst}");
    assert!(worst < std::f64::consts::SQRT_2, "{worst}");
}

/// `nc dda --arc`: a quarter circle of radius 10 increments from (10, 0) counter-clockwise
/// around the origin ends at (0, 10) after 10 pulses on each axis.
#[test]
fn nc_dda_takes_an_arc() {
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(["nc", "dda", "--arc", "ccw", "--dx=-10", "--dy", "10", "--i=-10", "--j", "0"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let last_clock = text.lines().rev().nth(1).unwrap();
    let fields: Vec<&str> = last_clock.split_whitespace().collect();
    assert_eq!(&fields[fields.len() - 2..], ["0", "10"], "{text}");
    assert!(text.ends_with("pulses  X 10  Y 10\n"), "{text}");
}

/// The semicolon is each control's own: on a Fanuc it is the end of block (the manuals print
/// every block ending in `;`, the code LF shows as `;`; a Mazak/Fanuc-style lathe manual's
/// T function example: `T0101 ;` … `G01 X20. F0.3 ;` … `T0100 ; Cancels the tool offset
/// function`), so text after it is the next block, never a comment; LinuxCNC ("; comment to
/// the end of the line", G-code overview) and Sinumerik (`; comment`) take it as a comment.
#[test]
fn a_semicolon_is_read_as_each_control_reads_it() {
    let manual = "O0010 ;\nN1 G99 ;\nN2 T0101 ;\nN3 G97 S800 M03 ;\nN4 G00 X100. Z1. ;\nN5 G01 X20. F0.3 ;\n\
                  N6 G00 X200. Z180. ;\nN7 T0100 ;\nN8 M02 ;\n";
    let (p, lines) = read::read_with_lines(manual, Family::Fanuc, Some(Machine::Lathe)).unwrap();
    let direction = SpindleDirection::Clockwise;
    let want = vec![
        Block::FeedMode(FeedMode::PerRevolution),
        Block::Tool(ToolChange::new(1)),
        Block::Spindle(Spindle::Rpm { rpm: 800.0, direction }),
        Block::Rapid(Target::xz(100.0, 1.0)),
        Block::Line { to: Target { x: Some(20.0), ..Target::default() }, feed: Some(0.3) },
        Block::Rapid(Target::xz(200.0, 180.0)),
        Block::Tool(ToolChange { number: 1, offset: ToolOffset::Cancelled }),
    ];
    assert_eq!(p.number, Some(10));
    assert_eq!(p.blocks, want);
    assert_eq!(lines, [2, 3, 4, 5, 6, 7, 8]);
    // The same blocks punched as one line of tape, separated by their EOB only.
    let tape = manual.replace('\n', " ");
    let (q, lines) = read::read_with_lines(&tape, Family::Fanuc, Some(Machine::Lathe)).unwrap();
    assert_eq!(q.blocks, want);
    assert_eq!(lines, [1; 7]);
    // An error after an EOB names its own column in the line.
    let bad = tape.replace("F0.3", "F0.3 Q1");
    let e = read::read(&bad, Family::Fanuc, Some(Machine::Lathe)).unwrap_err();
    assert_eq!((e.line, e.column), (1, bad.find("Q1").unwrap() + 1), "{e}");
    // LinuxCNC and Sinumerik: the rest of the line is a comment, not a block.
    for (family, text) in [
        (Family::LinuxCnc, "G18 G7\nG0 X100 Z1 ; G1 X20 F0.3\n"),
        (Family::Sinumerik, "N10 G18\nN20 G0 X100 Z1 ; G1 X20 F0.3\n"),
    ] {
        let p = read::read(text, family, Some(Machine::Lathe)).unwrap();
        assert_eq!(
            p.blocks,
            [Block::Rapid(Target::xz(100.0, 1.0)), Block::Comment("G1 X20 F0.3".into())],
            "{family:?}"
        );
    }
}

/// A full circle takes about 2π·2ⁿ clocks (each clock turns an n-bit arc by at most a quarter
/// increment, docs/domain.md §4): with 24-bit adders 105 million rows, 6 GB of text and
/// minutes of writing for any radius. An arc's table ends where a straight move's does, at
/// 2^24 clocks, and one longer is refused before a row is written, saying what is enough; the
/// same circle with the bits its radius needs takes 4R pulses on each axis.
#[test]
fn nc_dda_refuses_an_arc_of_more_clocks_than_a_table_has_rows() {
    let circle = |bits| dda::circular(bits, (-1000, 0), (-1000, 0), ArcDirection::Clockwise).unwrap();
    assert_eq!(circle(dda::bits_for_circle((-1000, 0), (-1000, 0))).pulses().unwrap(), [4000, 4000]);
    let error = circle(24).pulses().unwrap_err().to_string();
    assert!(error.contains("the arc takes more than 16777216 clocks with 24-bit adders"), "{error}");
    assert!(error.contains("--bits 12 is enough for this radius"), "{error}");

    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("arc.txt");
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(["nc", "dda", "--arc", "cw", "--dx", "0", "--dy", "0", "--i", "8000000", "--j", "0"])
        .args(["-o", file.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("give a coarser --increment"));
    assert!(!file.exists(), "nothing is written");
}

/// LinuxCNC's parameters and expressions (`#1 = 10`, `X[#1*2]`, `Z-#<depth>`, functions in
/// degrees, a line's settings taking effect after the line): the moves our reader makes of
/// parametric programs are the moves rs274 makes of them.
#[test]
fn parametric_programs_move_as_rs274_moves_them() {
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed (bash .ci/run installs linuxcnc-uspace)");
        return;
    }
    let programs = [
        "G21 G90 G17\n#1 = 10\n#<depth> = 2\n#2 = 3 #1 = 4 (the settings of a line take effect after it)\nT1 M6\n\
         S1000 M3\nG0 X0 Y0 Z5\nG1 F100 X[#1] Z-[#<depth>]\nX[#1*2] Y#2\nX-#1\nX[2**3+1] Y[ATAN[1]/[1]] Z[SIN[30]]\n\
         X[5 MOD 3] Y[1+2*3] Z[-7 MOD 3]\nX[1 LT 2] Y[FIX[-2.5]] Z[FUP[-2.5]]\nX[ROUND[2.5]] Y[ROUND[-2.5]] Z[EXISTS[#<depth>]]\nM2\n",
        "G21 G90 G17\n#<r> = 12.5\n#<a> = 30\n#3 = 2\nG0 X[#<r>*COS[#<a>]] Y[#<r>*SIN[#<a>]] Z#3\n\
         G1 F[#3*50] Z-1\nG3 X[#<r>*COS[#<a>+90]] Y[#<r>*SIN[#<a>+90]] I[0-#<r>*COS[#<a>]] J[0-#<r>*SIN[#<a>]]\n\
         #<a> = [#<a> + 90]\nG2 X[#<r>*COS[#<a>-90]] Y[#<r>*SIN[#<a>-90]] R#<r>\n#[#3+2] = [SQRT[2]*#<r>]\nG1 X#4 Y[-#4]\n\
         G1 X[2--3] Y[2*-3] Z[- [1 + 1] ** 2]\nG0 X[1 GT 0 + 1] Y[2 OR 0 AND 0] Z[ACOS[0] + ASIN[1] + TAN[45] + ABS[-3]]\n\
         G0 X[EXP[1] + LN[10]] Y[3 XOR 0] Z[#< R > / #<r>]\nG0 X##3 Y[1 EQ 1.00005] Z[1 NE 1.00005]\nM2\n",
    ];
    let dir = tempfile::tempdir().unwrap();
    for (i, text) in programs.iter().enumerate() {
        let path = dir.path().join(format!("p{i}.ngc"));
        std::fs::write(&path, text).unwrap();
        let theirs = rs274::moves(&path).unwrap_or_else(|e| panic!("rs274 rejected program {i}:\n{e}\n{text}"));
        let ours = our_moves(&read::read(text, Family::LinuxCnc, None).unwrap_or_else(|e| panic!("program {i}: {e}")));
        assert!(same_moves(&ours, &theirs), "program {i}:\nours   {ours:?}\nrs274 {theirs:?}\n{text}");
    }
}

/// A random expression of LinuxCNC's operators and functions whose value stays small and
/// defined (no division, no logarithms): depth `depth`, from the generator `next`.
fn random_expression(next: &mut impl FnMut(u32) -> u32, depth: u32) -> String {
    let number = |next: &mut dyn FnMut(u32) -> u32| {
        let v = f64::from(next(2000)) / 100.0 - 10.0;
        if next(4) == 0 {
            format!("#{}", 1 + next(3))
        } else {
            format!("{v}")
        }
    };
    if depth == 0 || next(4) == 0 {
        return number(next);
    }
    if next(3) == 0 {
        let f = ["ABS", "SIN", "COS", "FIX", "FUP", "ROUND", "-"][next(7) as usize];
        let inner = random_expression(next, depth - 1);
        return if f == "-" { format!("-[{inner}]") } else { format!("{f}[{inner}]") };
    }
    let ops = ["+", "-", "*", "MOD 7", "EQ", "NE", "GT", "LT", "AND", "OR", "XOR", "** 2"];
    let mut text = random_expression(next, depth - 1);
    for _ in 0..=next(2) {
        let op = ops[next(ops.len() as u32) as usize];
        text = match op {
            "MOD 7" | "** 2" => format!("{text} {op}"),
            _ => format!("{text} {op} {}", random_expression(next, depth - 1)),
        };
        if next(2) == 0 {
            text = format!("[{text}]");
        }
    }
    format!("[{text}]")
}

/// Four hundred random expressions (operators bound as LinuxCNC binds them, signs, nested
/// brackets, parameters) have the values rs274 gives them, to its four printed decimals.
#[test]
fn random_expressions_have_rs274s_values() {
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed (bash .ci/run installs linuxcnc-uspace)");
        return;
    }
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move |n: u32| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % u64::from(n)) as u32
    };
    let expressions: Vec<String> = (0..400).map(|_| random_expression(&mut next, 3)).collect();
    let mut text = "G21 G90 G17\n#1 = 2.5\n#2 = -3.25\n#3 = 0\n".to_string();
    for e in &expressions {
        text += &format!("G0 X{e}\n");
    }
    text += "M2\n";
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("expressions.ngc");
    std::fs::write(&path, &text).unwrap();
    let theirs = rs274::moves(&path).unwrap_or_else(|e| panic!("rs274 rejected the expressions: {e}"));
    let ours = our_moves(&read::read(&text, Family::LinuxCnc, None).unwrap());
    assert_eq!(ours.len(), expressions.len());
    assert_eq!(theirs.len(), expressions.len());
    for ((e, a), b) in expressions.iter().zip(&ours).zip(&theirs) {
        let (Move::Traverse { x: a, .. }, Move::Traverse { x: b, .. }) = (a, b) else { panic!("{a:?} {b:?}") };
        // rs274 prints four decimals.
        assert!((a - b).abs() <= 0.00005 + 1e-9 * a.abs(), "X{e}: ours {a}, rs274 {b}");
    }
}

/// What LinuxCNC refuses in parameters and expressions is refused here too, at the line and
/// column of the cause, and never read as 0; nesting past the limit is refused, not a crash.
#[test]
fn expression_errors_name_line_and_column() {
    let cases = [
        ("G0 X[1/0]", 7, "divides by zero"),
        ("G0 X[SQRT[-1]]", 6, "square root of a negative"),
        ("G0 X[LN[0]]", 6, "logarithm"),
        ("G0 X[ACOS[2]]", 6, "from -1 to 1"),
        ("G0 X[[-8]**[1/3]]", 10, "not whole"),
        ("G0 X#1.5", 5, "must be whole"),
        ("G0 X#5602", 5, "not a parameter"),
        ("#0=1", 1, "not a parameter"),
        ("G0 X[1+]", 8, "a value is missing"),
        ("G0 X[1", 5, "not closed by `]`"),
        ("G0 X[FOO[1]]", 6, "not one of LinuxCNC's functions"),
        ("G0 X[ATAN[1]]", 13, "ATAN[y]/[x]"),
        ("G0 X#<nowhere>", 5, "read before the program sets it"),
        ("G0 X#5420", 5, "the control's state"),
        ("#5221=10", 1, "changes the control's state"),
        ("G0 X[1 MOD 0]", 8, "MOD 0"),
        ("G0 X#1#2", 9, "takes `=`"),
    ];
    for (line, column, message) in cases {
        let text = format!("G21\n{line}\nM2\n");
        let e = read::read(&text, Family::LinuxCnc, None).expect_err(line);
        assert_eq!((e.line, e.column), (2, column), "{line}: {e}");
        assert!(e.message.contains(message), "{line}: {e}");
        if !line.contains("#5") && rs274::available() {
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join("e.ngc");
            std::fs::write(&path, &text).unwrap();
            assert!(rs274::moves(&path).is_err(), "rs274 reads {line:?}, which we refuse");
        }
    }
    let deep = format!("G21\nG0 X{}1\nM2\n", "[".repeat(100_000));
    let e = read::read(&deep, Family::LinuxCnc, None).unwrap_err();
    assert!(e.message.contains("nested more than"), "{e}");
    let fanuc = read::read("G21\nG0 X#1\nM30\n", Family::Fanuc, Some(Machine::Mill)).unwrap_err();
    assert!(fanuc.message.contains("Fanuc Macro B"), "{fanuc}");
}

/// LinuxCNC's O-codes as the control runs them: subroutines of the same file with their own
/// #1–#30 and named parameters, values returned in #<_value>, while, do … while and repeat
/// loops with break and continue, if/elseif/else. The moves are rs274's.
#[test]
fn o_code_programs_move_as_rs274_moves_them() {
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed (bash .ci/run installs linuxcnc-uspace)");
        return;
    }
    let programs = [
        "G21 G90 G17\no<square> sub\n  G1 X[#1] Y[#2] F100\n  G1 X[#1 + #3]\n  G1 Y[#2 + #3]\n  G1 X#1\n  G1 Y#2\n\
         #<side> = #3\no<square> endsub\no200 sub\n  o200 return [#1 * 2]\no200 endsub\n#<_n> = 0\nG0 Z5\n\
         o100 while [#<_n> LT 3]\n  o<square> call [#<_n> * 10] [0] [5]\n  #<_n> = [#<_n> + 1]\no100 endwhile\n\
         o101 repeat [2]\n  G0 Z[10 + #<_n>]\n  #<_n> = [#<_n> + 1]\no101 endrepeat\no102 do\n  #<_n> = [#<_n> - 1]\n\
         o103 if [#<_n> EQ 3]\n    G0 Z15\n  o103 elseif [#<_n> LT 1]\n    o102 break\n  o103 else\n    G0 X[#<_n>] Y-1\n\
         o103 endif\no102 while [#<_n> GT -5]\no200 call [21]\nG0 X#<_value> Y[EXISTS[#<side>]]\nM2\n",
        "G21 G90 G17\n#1 = 7\no10 sub\n  #<depth> = [#1 + 1]\n  o11 if [#<depth> LT 4]\n    G1 X[#<depth> * 3] Z-#<depth> F50\n\
         o10 call [#<depth>]\n  o11 endif\n  G0 Y#<depth>\no10 endsub\no10 call [0]\nG0 X#1\n#2 = 0\n\
         o20 while [#2 LT 6]\n  #2 = [#2 + 1]\n  o21 if [[#2 MOD 2] EQ 0]\n    o20 continue\n  o21 endif\n  G0 X[#2 * 10]\n\
         o20 endwhile\no30 repeat [5]\n  #2 = [#2 - 1]\n  o31 if [#2 LT 3]\n    G0 Z1\n  o31 endif\n  o32 if [#2 EQ 5]\n\
         G0 Z2\n  o32 elseif [#2 GT 4]\n  G0 Z3\n  o32 endif\n  G0 Y[#2]\no30 endrepeat\no40 repeat [0]\n  G0 X999\no40 endrepeat\nM2\n",
    ];
    let dir = tempfile::tempdir().unwrap();
    for (i, text) in programs.iter().enumerate() {
        let path = dir.path().join(format!("o{i}.ngc"));
        std::fs::write(&path, text).unwrap();
        let theirs = rs274::moves(&path).unwrap_or_else(|e| panic!("rs274 rejected program {i}:\n{e}\n{text}"));
        let ours = our_moves(&read::read(text, Family::LinuxCnc, None).unwrap_or_else(|e| panic!("program {i}: {e}")));
        assert!(theirs.len() > 10, "program {i} moves too little to show anything: {theirs:?}");
        assert!(same_moves(&ours, &theirs), "program {i}:\nours   {ours:?}\nrs274 {theirs:?}\n{text}");
    }
}

/// O-codes the reader cannot run as the control would are refused at their line: a call of a
/// subroutine in another file, a loop that never ends, calls past the depth limit.
#[test]
fn o_codes_that_cannot_run_are_refused_at_their_line() {
    let cases = [
        ("G21\no<elsewhere> call [1]\nM2\n", 2, "not in this program"),
        ("G21\no1 while [1]\nG0 X1\no1 endwhile\nM2\n", 4, "never ends"),
        ("G21\no1 repeat [3]\no1 break\no1 endrepeat\nM2\n", 3, "only while and do loops"),
        ("G21\no1 sub\no1 call\no1 endsub\no1 call\nM2\n", 3, "more than 50 deep"),
        ("G21\no1 sub\no1 endsub\no1 sub\no1 endsub\nM2\n", 4, "defined twice"),
        ("G21\no1 if [1]\nG0 X1\nM2\n", 2, "o1 if has no o1 endif after it"),
        ("G21\no1 endif\nM2\n", 2, "o1 endif has no o1 if before it"),
        ("G21\no1 do\no1 continue\no1 while [0]\nM2\n", 3, "do … while"),
        ("G21\no1 sub\no1 endsub\no1 return\nM2\n", 4, "without a call"),
    ];
    for (text, line, message) in cases {
        let e = read::read(text, Family::LinuxCnc, None).expect_err(text);
        assert_eq!(e.line, line, "{text:?}: {e}");
        assert!(e.message.contains(message), "{text:?}: {e}");
    }
}

/// LinuxCNC's predefined named parameters (the manual's "Predefined Named Parameters":
/// `#<_x>`, `#<_feed>`, `#<_rpm>`, `#<_metric>`, `#<_absolute>`, `#<_coord_system>`,
/// `#<_motion_mode>`, `#<_line>`, `#<_call_level>` …) read the control's modal state: the
/// moves our reader makes of programs that compute with them are the moves rs274 makes (a
/// lathe's `#<_x>` is the radius in G7 too; `#<_x>` after G20 is in inches; EQ and NE within
/// 0.0001, GE and LE exact as in LinuxCNC 2.9.0).
#[test]
fn predefined_parameters_move_as_rs274_moves_them() {
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed (bash .ci/run installs linuxcnc-uspace)");
        return;
    }
    let programs = [
        "G21 G90 G17 G94\nG0 X[#<_motion_mode> / 100] Y[#<_plane> / 100] Z[#<_ccomp> / 100]\n\
         G0 X[#<_metric> + #<_absolute> * 2 + #<_imperial> * 4 + #<_incremental> * 8] Y[#<_coord_system> / 100] \
         Z[#<_units_per_minute> + #<_units_per_rev> * 2 + #<_inverse_time> * 4]\nS800 M3\n\
         G1 X[#<_x> + 10] Y[#<_y> - 1] Z[#<_feed> / 100] F120\nG1 X[#<_rpm> / 100] Y#<_spindle_on> Z[#<_spindle_cw> + #<_feed> / 100]\n\
         M4\nG0 X#<_spindle_cw> Y#<_line> Z#<_call_level>\nM8\nG0 X#<_flood> Y#<_mist> Z[#<_vmajor> + #<_vminor>]\n\
         G2 X[#<_x> + 2] Y#<_y> R1 F100\nG0 X#<_motion_mode> Y[EXISTS[#<_x>]] Z[#<_value> + #<_value_returned>]\n\
         G91\nG0 X#<_incremental> Y#<_absolute>\nG90 G20\n#<inch> = #<_x>\nG21\n\
         G0 X[#<inch> * 25.4 + 1] Y[#<_spindle_rpm_mode> + #<_spindle_css_mode> * 2] Z[#<_lathe_radius_mode> + #<_ijk_absolute_mode> * 2]\n\
         G0 X[1 EQ 1.0001] Y[100 EQ 100.0001] Z[[1 GE 1.00005] + [1.00005 LE 1] * 2 + [1 NE 0.9999] * 4]\n\
         G0 X[#<_retract_r_plane> + #<_retract_old_z> * 2] Y[#<_feed_override> + #<_speed_override> + #<_feed_hold> + #<_adaptive_feed>] Z#<_remap_level>\n\
         G94\nG1 X[#<_feed> + 5] Y[#<_units_per_minute>] F50\nG1 X[#<_feed> / 10]\no100 sub\n  G0 X#<_call_level> Y#<_line> Z[#<_x> + 0.5]\n\
         o100 endsub\no100 call\nM5 M9\nG0 X[#<_spindle_on> + #<_flood> * 2] Y3 Z3\nM2\n",
        "G21 G90 G18 G7\nG0 X20 Z5\nG0 X[#<_x> * 4] Z[#<_lathe_diameter_mode> + #<_plane> / 100]\nG8\n\
         G0 X#<_x> Z[#<_lathe_radius_mode> + #<_z>]\nG96 S150 D2000 M3\nG95\n\
         G1 X[#<_rpm> / 10] Z[#<_spindle_css_mode> + #<_units_per_rev> + #<_feed>] F0.1\nG97 S500\n\
         G1 X[#<_x> - 1] Z[#<_spindle_rpm_mode> - #<_rpm> / 100 + #<_feed>]\nM2\n",
    ];
    let dir = tempfile::tempdir().unwrap();
    for (i, text) in programs.iter().enumerate() {
        let path = dir.path().join(format!("predefined{i}.ngc"));
        std::fs::write(&path, text).unwrap();
        let theirs = rs274::moves(&path).unwrap_or_else(|e| panic!("rs274 rejected program {i}:\n{e}\n{text}"));
        let ours = our_moves(&read::read(text, Family::LinuxCnc, None).unwrap_or_else(|e| panic!("program {i}: {e}")));
        assert!(theirs.len() >= 5, "program {i} moves too little to show anything: {theirs:?}");
        assert!(same_moves(&ours, &theirs), "program {i}:\nours   {ours:?}\nrs274 {theirs:?}\n{text}");
    }
}

/// What the reader cannot know of the control's state is refused by name at its line and
/// column, never read as 0: where an axis is before the program moves it or after cutter
/// compensation moved it, the tool before the first change, machine coordinates (`#<_abs_x>`,
/// G53), the tool table, preview or machine (`#<_task>`). A predefined parameter is read-only
/// as on LinuxCNC, and a cut after a feed mode word without a new F is refused as rs274
/// refuses it (it sets the feed to 0 there), where the F before it was carried over.
#[test]
fn predefined_parameters_the_reader_cannot_know_are_refused_by_name() {
    let cases = [
        ("G0 X#<_x>", 5, "before the program moves X", false),
        ("G0 X1 Y1\nG0 Z[#<_z> + 1]", 6, "before the program moves Z", false),
        ("G0 X#<_current_tool>", 5, "first tool change", false),
        ("G0 X#<_abs_x>", 5, "machine coordinate", false),
        ("G0 X#<_tool_offset>", 5, "tool table", false),
        ("G0 X#<_current_pocket>", 5, "pocket", false),
        ("G0 X#<_task>", 5, "preview", false),
        ("G0 X#<_u>", 5, "does not move", false),
        ("G0 X#<_ini[axis_0]max_velocity>", 5, "INI file", false),
        ("G0 X0 Y0 Z0\n#<_x> = 5", 1, "read-only", true),
        ("#<_value> = 1", 1, "read-only", true),
        ("G0 X0 Y0 Z0\nG53 G0 Z0", 1, "machine coordinates", false),
        ("G0 X0 Y0 Z0\nG1 X1 F100\nG94\nG1 X2", 1, "a cut with no feed", true),
        ("G0 X0 Y0 Z0\nG1 X1 F100\nG95\nG2 X2 Y1 R1", 1, "a cut with no feed", true),
    ];
    let check_rs274 = rs274::available();
    for (body, column, message, rs274_refuses) in cases {
        let text = format!("G21 G90 G17\n{body}\nM2\n");
        let e = read::read(&text, Family::LinuxCnc, None).expect_err(body);
        let line = 1 + body.lines().count();
        assert_eq!((e.line, e.column), (line, column), "{body}: {e}");
        assert!(e.message.contains(message), "{body}: {e}");
        if rs274_refuses && check_rs274 {
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join("e.ngc");
            std::fs::write(&path, &text).unwrap();
            assert!(rs274::moves(&path).is_err(), "rs274 reads {body:?}, which we refuse");
        }
    }
    // After G40 an axis is known again once a move writes it; the one it does not write is not.
    let compensated =
        "G21 G90 G17\nT1 M6\nG0 X0 Y0 Z1\nG41 D1\nG1 X10 Y0 F100\nG40\nG1 X20\nG0 X[#<_x> + 1] Z#<_z>\nG0 Y#<_y>\nM2\n";
    let e = read::read(compensated, Family::LinuxCnc, None).unwrap_err();
    assert_eq!((e.line, e.column), (9, 5), "{e}");
    assert!(e.message.contains("cutter compensation"), "{e}");
}

/// A CAM post's set-up line (`G17 G21 G40 G49 G54 G80 G90 G94`, `G64 P0.01`, `G61`, `G61.1`,
/// `G91.1`) changes nothing the model holds and is read, so such programs are timed and moved
/// as rs274 moves them; G80 ends the motion mode (`#<_motion_mode>` 800) and the axis words
/// beside it are refused as rs274 refuses them. Codes that would move the path (another work
/// offset, absolute arc centres) are refused by name, though rs274 reads them against its own
/// offsets.
#[test]
fn cam_set_up_codes_move_as_rs274_moves_them() {
    let header = "%\n(CAM POST)\nG17 G21 G40 G49 G54 G80 G90 G94\nG64 P0.01 Q0.005\nG91.1\n\
                  T1 M6\nS8000 M3\nG0 X0 Y0 Z5\nG61\nG1 Z-1 F300\nG64 P0.02\nG1 X20\nG2 X30 Y10 I0 J10\n\
                  G61.1\nG1 Y20\nG80\nG0 X[#<_motion_mode> / 100] Z[#<_coord_system> / 100]\nG54 G0 Z10\nM5\nM2\n%\n";
    let ours = read::read(header, Family::LinuxCnc, None).unwrap_or_else(|e| panic!("{e}"));
    let refused = [
        ("G0 X1\nG80 X5", 2, 5, "with G80", true),
        ("G0 X1\nG80\nX5", 3, 1, "no motion code", true),
        ("G0 X1\nG55\nG0 X5", 2, 1, "another work offset", false),
        ("G59.3", 1, 1, "G59.3 selects another work offset", false),
        ("G90.1", 1, 1, "absolute", false),
        ("G61 P1", 1, 5, "P has no meaning", true),
    ];
    for (body, line, column, message, _) in refused {
        let e = read::read(&format!("{body}\nM2\n"), Family::LinuxCnc, None).expect_err(body);
        assert_eq!((e.line, e.column), (line, column), "{body}: {e}");
        assert!(e.message.contains(message), "{body}: {e}");
    }
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed (bash .ci/run installs linuxcnc-uspace)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("header.ngc");
    std::fs::write(&path, header).unwrap();
    let theirs = rs274::moves(&path).unwrap_or_else(|e| panic!("rs274 rejected the program:\n{e}"));
    assert_eq!(theirs.len(), 7, "{theirs:?}");
    assert!(same_moves(&our_moves(&ours), &theirs), "ours   {:?}\nrs274 {theirs:?}", our_moves(&ours));
    for (body, _, _, _, rs274_refuses) in refused {
        std::fs::write(&path, format!("{body}\nM2\n")).unwrap();
        assert_eq!(rs274::moves(&path).is_err(), rs274_refuses, "{body}");
    }
}
