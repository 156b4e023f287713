//! Each dialect against programs written by hand from the control's documented syntax
//! (tests/nc/<dialect>/*.nc), plus a round-trip property of the number formatter.

use ncsheet::nc::dialect::{self, Dialect};
use ncsheet::nc::{ArcDirection, Block, Machine, Program, Target, Word};
use proptest::prelude::*;

fn lathe_program(with_arc: bool) -> Program {
    let mut p = Program::new("CHAMFER", Machine::Lathe);
    p.number = Some(1);
    p.push(Block::Comment("outer chamfer".into()));
    p.push(Block::Rapid(Target::xz(50.0, 2.0)));
    p.push(Block::Line { to: Target::xz(40.0, 0.0), feed: Some(0.1) });
    if with_arc {
        let centre = Target::xz(40.0, -2.0);
        p.push(Block::Arc { direction: ArcDirection::Clockwise, to: Target::xz(44.0, -2.0), centre, feed: Some(0.1) });
    } else {
        p.push(Block::Line { to: Target::xz(44.0, -2.0), feed: Some(0.1) });
    }
    p.push(Block::Line { to: Target::xz(44.0, -10.0), feed: Some(0.1) });
    p.push(Block::Dwell(0.5));
    p.push(Block::Rapid(Target::xz(50.0, 2.0)));
    p
}

fn mill_program() -> Program {
    let mut p = Program::new("POCKET", Machine::Mill);
    p.number = Some(1);
    p.push(Block::Comment("square with a round corner".into()));
    p.push(Block::Rapid(Target::xyz(0.0, 0.0, 5.0)));
    p.push(Block::Line { to: Target { z: Some(-1.0), ..Target::default() }, feed: Some(100.0) });
    p.push(Block::Line { to: Target::xy(10.0, 0.0), feed: Some(200.0) });
    let centre = Target::xy(10.0, 5.0);
    p.push(Block::Arc {
        direction: ArcDirection::CounterClockwise,
        to: Target::xy(10.0, 10.0),
        centre,
        feed: Some(200.0),
    });
    p.push(Block::Line { to: Target::xy(0.0, 10.0), feed: Some(200.0) });
    p.push(Block::Rapid(Target { z: Some(5.0), ..Target::default() }));
    p
}

fn golden(dialect: &str, file: &str) -> String {
    let path = format!("{}/tests/nc/{dialect}/{file}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn render(dialect: &str, p: &Program) -> String {
    dialect::by_name(dialect).unwrap().render(p).unwrap()
}

#[test]
fn iso_lathe_and_mill() {
    assert_eq!(render("iso", &lathe_program(true)), golden("iso", "lathe.nc"));
    assert_eq!(render("iso", &mill_program()), golden("iso", "mill.nc"));
}

#[test]
fn linuxcnc_lathe() {
    assert_eq!(render("linuxcnc", &lathe_program(true)), golden("linuxcnc", "lathe.nc"));
}

#[test]
fn sinumerik_lathe() {
    assert_eq!(render("sinumerik", &lathe_program(true)), golden("sinumerik", "lathe.nc"));
}

#[test]
fn heidenhain_mill() {
    assert_eq!(render("heidenhain", &mill_program()), golden("heidenhain", "mill.nc"));
}

#[test]
fn nc31_lathe() {
    assert_eq!(render("nc31", &lathe_program(false)), golden("nc31", "lathe.nc"));
}

#[test]
fn what_a_control_cannot_read_is_an_error_naming_the_block() {
    let nc31 = dialect::by_name("nc31").unwrap();
    let err = nc31.render(&lathe_program(true)).unwrap_err();
    assert_eq!(err.block, Some(4));
    assert!(err.to_string().contains("circular interpolation"), "{err}");
    assert!(dialect::by_name("heidenhain").unwrap().render(&lathe_program(false)).is_err());
    assert!(nc31.render(&mill_program()).is_err());
    let mut p = lathe_program(false);
    p.push(Block::Words(vec![Word { address: 'Y', value: 1.0 }]));
    let err = nc31.render(&p).unwrap_err();
    assert!(err.to_string().contains("address Y"), "{err}");
    let mut p = mill_program();
    p.push(Block::Rapid(Target::xy(f64::NAN, 0.0)));
    assert!(dialect::by_name("iso").unwrap().render(&p).is_err());
}

#[test]
fn raw_words_keep_codes_whole() {
    let mut p = Program::new("RAW", Machine::Lathe);
    p.push(Block::Words(vec![Word { address: 'G', value: 1.0 }, Word { address: 'X', value: 12.5 }]));
    p.push(Block::Words(vec![Word { address: 'M', value: 3.0 }, Word { address: 'S', value: 700.0 }]));
    let text = render("iso", &p);
    assert!(text.contains("N20 G1 X12.5\n"), "{text}");
    // Spindle speeds are whole numbers on Fanuc (S700), unlike coordinates (X12.5, X40.).
    assert!(text.contains("N30 M3 S700\n"), "{text}");
}

/// The number after `X` in the first block that has one.
fn first_x(text: &str) -> f64 {
    let at = text.lines().find_map(|l| l.split_whitespace().find_map(|w| w.strip_prefix('X'))).unwrap();
    at.trim_end_matches('.').parse().unwrap()
}

proptest! {
    #[test]
    fn coordinates_round_trip_to_the_dialect_resolution(v in -5000.0f64..5000.0, which in 0usize..5) {
        let d: &dyn Dialect = dialect::all()[which];
        let machine = if d.name() == "heidenhain" { Machine::Mill } else { Machine::Lathe };
        let mut p = Program::new("P", machine);
        p.push(Block::Rapid(Target { x: Some(v), ..Target::default() }));
        let back = first_x(&d.render(&p).unwrap());
        prop_assert!((back - v).abs() <= d.resolution() / 2.0 + 1e-9, "{} wrote {} for {}", d.name(), back, v);
    }
}
