//! The NC writers fed random comments, names and numbers (line breaks, comment delimiters,
//! `%`, 1e300, NaN, 0, negatives): every ISO and LinuxCNC program they write is read back by
//! LinuxCNC's rs274, and its moves must be exactly the model's moves (to the dialect's
//! resolution), or the writer must have refused. Programs whose numbers are all in range
//! must not be refused.

mod common;

use common::rs274::{self, Move};
use ncsheet::nc::dialect;
use ncsheet::nc::{Block, FeedMode, Machine, Program, Spindle, SpindleDirection, Target};
use proptest::prelude::*;

/// Text made of pieces that break comments and lines when written carelessly.
fn text() -> impl Strategy<Value = String> {
    let piece = prop_oneof![
        Just("\n".to_string()),
        Just("\r".to_string()),
        Just("(".to_string()),
        Just(")".to_string()),
        Just(";".to_string()),
        Just("%".to_string()),
        Just(",".to_string()),
        Just("MSG,".to_string()),
        Just("G0 X0 Z-500".to_string()),
        Just("M30".to_string()),
        "[a-zA-Z0-9 .:#*+-]{0,6}",
    ];
    prop::collection::vec(piece, 0..6).prop_map(|p| p.concat())
}

/// A number that is sometimes one no control should get.
fn number() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(1e300),
        Just(-1e300),
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(0.0),
        Just(-0.0),
        -2.0e6..2.0e6f64,
        -500.0..500.0f64,
        -500.0..500.0f64,
        -500.0..500.0f64,
    ]
}

fn feed() -> impl Strategy<Value = f64> {
    prop_oneof![Just(0.0), Just(-5.0), Just(f64::NAN), Just(1e300), 0.05..0.5f64, 10.0..2000.0f64]
}

/// The largest coordinate the dialect writes: 8 digits at 3 decimals (iso), 9 (linuxcnc).
fn largest(dialect: &str) -> f64 {
    if dialect == "iso" {
        99_999.999
    } else {
        999_999.999
    }
}

/// (rapid to `a`, feed to `b` at `f`) in a program with comments and a name from `texts`.
fn program(machine: Machine, texts: &[String; 3], a: [f64; 3], b: [f64; 3], f: f64) -> Program {
    let mut p = Program::new(&texts[0], machine);
    p.push(Block::Comment(texts[1].clone()));
    match machine {
        Machine::Lathe => {
            p.push(Block::FeedMode(FeedMode::PerRevolution));
            p.push(Block::Spindle(Spindle::Rpm { rpm: 800.0, direction: SpindleDirection::Clockwise }));
            p.push(Block::Rapid(Target::xz(a[0], a[2])));
            p.push(Block::Comment(texts[2].clone()));
            p.push(Block::Line { to: Target::xz(b[0], b[2]), feed: Some(f) });
        }
        Machine::Mill => {
            p.push(Block::FeedMode(FeedMode::PerMinute));
            p.push(Block::Rapid(Target::xyz(a[0], a[1], a[2])));
            p.push(Block::Comment(texts[2].clone()));
            p.push(Block::Line { to: Target::xyz(b[0], b[1], b[2]), feed: Some(f) });
        }
    }
    p
}

fn check(dialect: &str, machine: Machine, p: &Program, a: [f64; 3], b: [f64; 3], f: f64) -> Result<(), TestCaseError> {
    let in_range = |v: f64| v.is_finite() && v.abs() <= largest(dialect);
    // A lathe program has no Y: only the values it writes must be in range.
    let written = |v: [f64; 3]| if machine == Machine::Lathe { vec![v[0], v[2]] } else { v.to_vec() };
    let valid =
        written(a).into_iter().chain(written(b)).all(in_range) && f.is_finite() && f >= 0.001 && f <= largest(dialect);
    let text = match dialect::by_name(dialect).unwrap().render(p) {
        Ok(text) => text,
        Err(e) => {
            prop_assert!(!valid, "{dialect} refused a program it can write: {e}");
            return Ok(());
        }
    };
    prop_assert!(valid, "{dialect} wrote a program with a number out of range:\n{text}");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.ngc");
    std::fs::write(&path, &text).unwrap();
    let moves = rs274::moves(&path).map_err(|e| TestCaseError::fail(format!("rs274 rejected:\n{text}\n{e}")))?;
    // X on a lathe is a diameter in the program and a radius in rs274 (G7 on input).
    let scale = if machine == Machine::Lathe { 0.5 } else { 1.0 };
    let y = |v: [f64; 3]| if machine == Machine::Lathe { 0.0 } else { v[1] };
    let want = [Move::Traverse { x: a[0] * scale, y: y(a), z: a[2] }, Move::Feed { x: b[0] * scale, y: y(b), z: b[2] }];
    prop_assert_eq!(moves.len(), want.len(), "moves {:?} for\n{}", moves, text);
    for (got, want) in moves.iter().zip(&want) {
        let close = |p: f64, q: f64| (p - q).abs() <= 6e-4 * (1.0 + q.abs() * 1e-12);
        let same = match (got, want) {
            (Move::Traverse { x, y, z }, Move::Traverse { x: wx, y: wy, z: wz })
            | (Move::Feed { x, y, z }, Move::Feed { x: wx, y: wy, z: wz }) => {
                close(*x, *wx) && close(*y, *wy) && close(*z, *wz)
            }
            _ => false,
        };
        prop_assert!(same, "{:?} is not {:?} in\n{}", got, want, text);
    }
    Ok(())
}

proptest! {
    #![proptest_config(common::fuzz::config(96))]

    #[test]
    fn iso_and_linuxcnc_write_the_models_moves_or_refuse(
        texts in [text(), text(), text()],
        a in [number(), number(), number()],
        b in [number(), number(), number()],
        f in feed(),
        lathe in any::<bool>(),
        linuxcnc in any::<bool>(),
    ) {
        if !rs274::available() {
            return Ok(());
        }
        // rs274 reads ISO mill programs (G94, no O-number); ISO lathe programs say G99 for
        // feed per revolution (Fanuc G-code system A), which LinuxCNC does not.
        let dialect = if linuxcnc || lathe { "linuxcnc" } else { "iso" };
        let machine = if lathe { Machine::Lathe } else { Machine::Mill };
        let p = program(machine, &texts, a, b, f);
        check(dialect, machine, &p, a, b, f)?;
    }
}
