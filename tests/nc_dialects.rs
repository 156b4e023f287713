//! Each dialect against programs written by hand from the control's documented syntax
//! (tests/nc/<dialect>/*.nc), plus a round-trip property of the number formatter.
//!
//! The property runs from the fixed seed of `common::fuzz`.

mod common;

use ncsheet::nc::dialect::{self, Dialect};
use ncsheet::nc::{
    ArcDirection, Block, Compensation, FeedMode, Machine, Program, Spindle, SpindleDirection, Target, ToolChange,
    ToolOffset, Word,
};
use proptest::prelude::*;

fn lathe_program(with_arc: bool) -> Program {
    let mut p = Program::new("CHAMFER", Machine::Lathe);
    p.number = Some(1);
    p.retract = Some(Target::xz(60.0, 5.0));
    p.push(Block::Comment("outer chamfer".into()));
    p.push(Block::Tool(ToolChange::new(1)));
    p.push(Block::FeedMode(FeedMode::PerRevolution));
    let direction = SpindleDirection::Clockwise;
    // NC31 has no constant surface speed: its program turns at a fixed speed.
    p.push(Block::Spindle(if with_arc {
        Spindle::SurfaceSpeed { metres_per_min: 180.0, max_rpm: 2500.0, direction }
    } else {
        Spindle::Rpm { rpm: 800.0, direction }
    }));
    p.push(Block::Coolant(true));
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
    p.retract = Some(Target { z: Some(50.0), ..Target::default() });
    p.blank = Some(([0.0, 0.0, -5.0], [10.0, 10.0, 0.0]));
    p.push(Block::Comment("square with a round corner".into()));
    p.push(Block::FeedMode(FeedMode::PerMinute));
    p.push(Block::Tool(ToolChange::new(1)));
    p.push(Block::Spindle(Spindle::Rpm { rpm: 3000.0, direction: SpindleDirection::Clockwise }));
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

/// NC81 writes NC31's words, per the chamfer paper (docs/domain.md §2, "NC81").
#[test]
fn nc81_lathe() {
    assert_eq!(render("nc81", &lathe_program(false)), golden("nc81", "lathe.nc"));
}

#[test]
fn what_a_control_cannot_read_is_an_error_naming_the_block() {
    let nc31 = dialect::by_name("nc31").unwrap();
    let mut with_arc = lathe_program(true);
    with_arc.blocks[3] = Block::Spindle(Spindle::Rpm { rpm: 800.0, direction: SpindleDirection::Clockwise });
    // NC31 has no circular interpolation: the arc (centre Z-2 at radius 20, R2) is written
    // as lines, every written end on its circle and every chord within the default 0.01 mm.
    let text = nc31.render(&with_arc).unwrap();
    let points: Vec<(f64, f64)> = text
        .lines()
        .filter(|l| !l.ends_with(" E"))
        .filter_map(|l| {
            let word = |a: char| l.split_whitespace().find_map(|w| w.strip_prefix(a)?.parse::<f64>().ok());
            Some((word('Z')?, word('X')? / 2.0))
        })
        .collect();
    let from = points.iter().position(|p| *p == (0.0, 20.0)).expect("the arc's start");
    let to = points.iter().position(|p| *p == (-2.0, 22.0)).expect("the arc's end");
    assert!(to > from + 2, "{text}");
    let off = |p: &(f64, f64)| (p.0 + 2.0).hypot(p.1 - 20.0) - 2.0;
    for p in &points[from..=to] {
        assert!(off(p).abs() < 0.001, "{p:?} is off the arc by {}: {text}", off(p));
    }
    for w in points[from..=to].windows(2) {
        let mid = ((w[0].0 + w[1].0) / 2.0, (w[0].1 + w[1].1) / 2.0);
        assert!(-off(&mid) <= 0.01, "a chord {} mm inside the arc: {text}", -off(&mid));
    }
    assert!(dialect::by_name("heidenhain").unwrap().render(&lathe_program(false)).is_err());
    assert!(nc31.render(&mill_program()).is_err());
    let mut p = lathe_program(false);
    p.push(Block::Words(vec![Word::new('Y', 1.0)]));
    let err = nc31.render(&p).unwrap_err();
    assert!(err.to_string().contains("address Y"), "{err}");
    let mut p = mill_program();
    p.push(Block::Rapid(Target::xy(f64::NAN, 0.0)));
    assert!(dialect::by_name("iso").unwrap().render(&p).is_err());
}

#[test]
fn a_lathe_cut_without_a_feed_mode_is_refused_naming_the_block() {
    let mut p = Program::new("NOMODE", Machine::Lathe);
    p.push(Block::Rapid(Target::xz(50.0, 2.0)));
    p.push(Block::Line { to: Target::xz(40.0, 0.0), feed: Some(0.1) });
    for d in dialect::all().into_iter().filter(|d| d.writes(Machine::Lathe)) {
        let err = d.render(&p).unwrap_err();
        assert_eq!(err.block, Some(2), "{}: {err}", d.name());
        assert!(err.message.contains("feed mode"), "{err}");
    }
}

/// A mill program (lathe for NC31) whose fourth block is `block`, in dialect `d`.
fn one(d: &dyn Dialect, block: Block) -> Result<String, dialect::NcError> {
    let machine = if d.writes(Machine::Mill) { Machine::Mill } else { Machine::Lathe };
    let mut p = Program::new("P", machine);
    p.push(Block::FeedMode(FeedMode::PerRevolution));
    p.push(Block::Spindle(Spindle::Rpm { rpm: 800.0, direction: SpindleDirection::Clockwise }));
    // A lathe has no Y (NC31 refuses one).
    p.push(Block::Rapid(if machine == Machine::Mill { Target::xyz(10.0, 0.0, 0.0) } else { Target::xz(10.0, 0.0) }));
    p.push(block);
    d.render(&p)
}

#[test]
fn numbers_no_control_should_get_are_refused() {
    let line = |x: f64, feed: f64| Block::Line { to: Target { x: Some(x), ..Target::default() }, feed: Some(feed) };
    for d in dialect::all() {
        for bad in [line(1e300, 1.0), line(f64::NAN, 1.0), line(f64::INFINITY, 1.0), line(1.0, 0.0), line(1.0, -5.0)] {
            let err = one(d, bad.clone()).unwrap_err();
            assert_eq!(err.block, Some(4), "{}: {bad:?}: {err}", d.name());
        }
        assert!(one(d, line(9_999.0, 1.0)).is_ok(), "{}", d.name());
        assert!(one(d, Block::Dwell(0.0)).is_err() && one(d, Block::Dwell(f64::NAN)).is_err());
        let spindle = |rpm: f64| Block::Spindle(Spindle::Rpm { rpm, direction: SpindleDirection::Clockwise });
        assert!(one(d, spindle(1e300)).is_err() && one(d, spindle(0.0)).is_err() && one(d, spindle(800.0)).is_ok());
        assert!(one(d, Block::Tool(ToolChange::new(0))).is_err());
    }
    // ±99999.999 fits Fanuc's 8 digits, 100000 does not.
    let iso = dialect::by_name("iso").unwrap();
    assert!(one(iso, line(99_999.0, 1.0)).is_ok());
    assert!(one(iso, line(100_000.0, 1.0)).is_err());
    // Fanuc stores programs O0001–O9999.
    let mut p = mill_program();
    p.number = Some(10_000);
    assert!(iso.render(&p).unwrap_err().message.contains("O0001"));
}

#[test]
fn arcs_off_their_circle_are_refused() {
    let arc =
        |to: Target, centre: Target| Block::Arc { direction: ArcDirection::Clockwise, to, centre, feed: Some(1.0) };
    for d in dialect::all().into_iter().filter(|d| d.writes(Machine::Mill)) {
        // Start (10, 0): radius 0, and a centre 7.6 from the start but 9.9 from the end.
        let err = one(d, arc(Target::xy(0.0, 10.0), Target::xy(10.0, 0.0))).unwrap_err();
        assert!(err.message.contains("radius 0"), "{}: {err}", d.name());
        let centre = Target::xy(2.4, 0.0);
        let to = Target::xy(2.4 + 9.9, 0.0);
        let err = one(d, arc(to, centre)).unwrap_err();
        assert_eq!(err.block, Some(4), "{err}");
        // A true quarter circle is written.
        assert!(one(d, arc(Target::xy(0.0, 10.0), Target::xy(0.0, 0.0))).is_ok(), "{}", d.name());
    }
}

#[test]
fn comments_and_names_stay_comments_in_every_dialect() {
    let evil = "A) G0 Z-500 (\nG0 X0 Z-500\r; %, (MSG, hi)";
    for d in dialect::all() {
        let machine = if d.writes(Machine::Mill) { Machine::Mill } else { Machine::Lathe };
        let mut p = Program::new(evil, machine);
        p.number = Some(1);
        p.push(Block::Comment(evil.into()));
        let text = d.render(&p).unwrap();
        for line in text.lines() {
            let code = match d.name() {
                "iso" | "linuxcnc" => {
                    // Everything outside one pair of parentheses is code.
                    let outside: String = line.split('(').next().unwrap().to_string()
                        + line.rsplit(')').next().filter(|_| line.contains(')')).unwrap_or("");
                    assert!(line.matches('(').count() <= 1 && line.matches(')').count() <= 1, "{line}");
                    outside
                }
                "sinumerik" | "heidenhain" => line.split(';').next().unwrap().to_string(),
                _ => line.to_string(),
            };
            assert!(!code.contains("Z-500"), "{}: code line {line:?} in\n{text}", d.name());
        }
        if d.name() == "iso" {
            assert!(!text.contains(',') && !text.chars().any(|c| c.is_ascii_lowercase()), "{text}");
        }
        if d.name() == "linuxcnc" {
            assert!(!text.contains(','), "(MSG, … is a command in LinuxCNC: {text}");
        }
    }
}

#[test]
fn block_numbers_wrap_past_the_controls_digits() {
    let mut p = Program::new("LONG", Machine::Lathe);
    p.push(Block::FeedMode(FeedMode::PerRevolution));
    for i in 0..12_000 {
        p.push(Block::Rapid(Target::xz(10.0 + (i % 7) as f64, 1.0)));
    }
    let text = render("iso", &p);
    let widest = text.lines().filter_map(|l| l.strip_prefix('N')?.split(' ').next()?.parse::<u64>().ok()).max();
    assert_eq!(widest, Some(99_990), "Fanuc reads N1–N99999");
    let text = render("nc31", &p);
    assert!(text.lines().all(|l| l.len() < 5 || !l.as_bytes()[4].is_ascii_digit()), "NC31 reads N001–N999");
}

#[test]
fn raw_words_keep_codes_whole() {
    let mut p = Program::new("RAW", Machine::Lathe);
    p.push(Block::Words(vec![Word::new('G', 1.0), Word::new('X', 12.5)]));
    p.push(Block::Words(vec![Word::new('M', 3.0), Word::new('S', 700.0)]));
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
    #![proptest_config(common::fuzz::with_regressions(256))]

    #[test]
    fn coordinates_round_trip_to_the_dialect_resolution(v in -5000.0f64..5000.0, which in 0usize..5) {
        let d: &dyn Dialect = dialect::all()[which];
        let machine = if d.writes(Machine::Lathe) { Machine::Lathe } else { Machine::Mill };
        let mut p = Program::new("P", machine);
        p.push(Block::Rapid(Target { x: Some(v), ..Target::default() }));
        let back = first_x(&d.render(&p).unwrap());
        prop_assert!((back - v).abs() <= d.resolution() / 2.0 + 1e-9, "{} wrote {} for {}", d.name(), back, v);
    }
}

/// NC31 (docs/domain.md §2: `N002 X34 Z-60 E`) moves X and Z only, and writes no cutter
/// compensation, constant surface speed, feed per minute or offset other than the tool's own:
/// each is refused naming the block, never written as words it does not read nor left out.
#[test]
fn nc31_refuses_what_it_cannot_carry_naming_the_block() {
    let nc31 = dialect::by_name("nc31").unwrap();
    let direction = SpindleDirection::Clockwise;
    let line = |t: Target| Block::Line { to: t, feed: Some(0.1) };
    let cases = [
        (line(Target { y: Some(5.0), ..Target::xz(40.0, -2.0) }), "Y axis"),
        (Block::Rapid(Target { c: Some(90.0), ..Target::xz(50.0, 2.0) }), "C axis"),
        (line(Target { a: Some(1.0), ..Target::default() }), "A axis"),
        (Block::Compensation(Compensation::Left), "compensation"),
        (Block::Spindle(Spindle::SurfaceSpeed { metres_per_min: 180.0, max_rpm: 2500.0, direction }), "surface speed"),
        (Block::FeedMode(FeedMode::PerMinute), "per revolution only"),
        (Block::Tool(ToolChange { number: 1, offset: ToolOffset::Number(2) }), "offset"),
    ];
    for (block, says) in cases {
        let mut p = lathe_program(false);
        p.blocks.insert(5, block.clone());
        let e = nc31.render(&p).unwrap_err();
        assert_eq!(e.block, Some(6), "{block:?}: {e}");
        assert!(e.message.contains(says), "{block:?}: {e}");
    }
    let mut p = lathe_program(false);
    p.retract = Some(Target { y: Some(0.0), ..Target::xz(60.0, 5.0) });
    let e = nc31.render(&p).unwrap_err();
    assert!(e.block.is_none() && e.message.contains("retract") && e.message.contains("Y axis"), "{e}");
}
