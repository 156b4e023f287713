//! Programs written in the `linuxcnc` dialect, read back by LinuxCNC's `rs274` interpreter.

mod common;

use common::rs274::{self, Move};
use ncsheet::nc::dialect;
use ncsheet::nc::{ArcDirection, Block, FeedMode, Machine, Program, Spindle, SpindleDirection, Target};

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-4
}

fn run(p: &Program) -> Option<Vec<Move>> {
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed (bash .ci/run installs linuxcnc-uspace)");
        return None;
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.ngc");
    std::fs::write(&path, dialect::by_name("linuxcnc").unwrap().render(p).unwrap()).unwrap();
    Some(rs274::moves(&path).unwrap_or_else(|e| panic!("rs274 rejected the program:\n{e}")))
}

#[test]
fn lathe_program_moves_in_diameter_mode() {
    let mut p = Program::new("LATHE", Machine::Lathe);
    p.push(Block::FeedMode(FeedMode::PerRevolution));
    p.push(Block::Spindle(Spindle::Rpm { rpm: 800.0, direction: SpindleDirection::Clockwise }));
    p.push(Block::Rapid(Target::xz(50.0, 2.0)));
    p.push(Block::Line { to: Target::xz(40.0, 0.0), feed: Some(0.1) });
    // Quarter circle of radius 3 from (X40, Z0) around (X46, Z0): I is a radius offset (3)
    // although X is a diameter.
    let centre = Target::xz(46.0, 0.0);
    p.push(Block::Arc { direction: ArcDirection::Clockwise, to: Target::xz(46.0, -3.0), centre, feed: Some(0.1) });
    let Some(moves) = run(&p) else { return };
    assert!(matches!(moves[0], Move::Traverse { x, z, .. } if close(x, 25.0) && close(z, 2.0)), "{moves:?}");
    assert!(matches!(moves[1], Move::Feed { x, z, .. } if close(x, 20.0) && close(z, 0.0)), "{moves:?}");
    match moves[2] {
        Move::Arc { first_end, second_end, first_centre, second_centre, rotation, .. } => {
            assert!(close(first_end, -3.0) && close(second_end, 23.0), "{moves:?}");
            assert!(close(first_centre, 0.0) && close(second_centre, 23.0), "{moves:?}");
            assert_eq!(rotation, -1);
        }
        ref m => panic!("expected an arc, got {m:?}"),
    }
}

#[test]
fn mill_program_arcs_in_the_xy_plane() {
    let mut p = Program::new("MILL", Machine::Mill);
    p.push(Block::Rapid(Target::xyz(10.0, 0.0, 5.0)));
    p.push(Block::Line { to: Target { z: Some(-1.0), ..Target::default() }, feed: Some(100.0) });
    let centre = Target::xy(0.0, 0.0);
    p.push(Block::Arc {
        direction: ArcDirection::CounterClockwise,
        to: Target::xy(0.0, 10.0),
        centre,
        feed: Some(100.0),
    });
    let Some(moves) = run(&p) else { return };
    match moves[2] {
        Move::Arc { first_end, second_end, first_centre, second_centre, rotation, axis_end } => {
            assert!(close(first_end, 0.0) && close(second_end, 10.0));
            assert!(close(first_centre, 0.0) && close(second_centre, 0.0));
            assert_eq!(rotation, 1);
            assert!(close(axis_end, -1.0));
        }
        ref m => panic!("expected an arc, got {m:?}"),
    }
}
