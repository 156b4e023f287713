//! The example macros in sheets/: chamfer.bas against docs/domain.md §1's table, and the cycles of
//! docs/domain.md §2 checked from the moves LinuxCNC's rs274 interpreter reads in their programs,
//! not from our own text.

mod common;

use common::rs274::{self, Move};
use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::nc::{dialect, Block, Program, ToolChange};
use ncsheet::vba::{self, RunOptions, RunOutput};
use ncsheet::workbook::Workbook;

const CHAMFER: &str = include_str!("../sheets/chamfer.bas");
const CYCLES: &str = include_str!("../sheets/cycles.bas");

/// The chamfer sheet as the paper lays it out: inputs in B2:B7, results in B9:B12, each
/// cell named (D, f, alpha, r, eA, eB, XA, ZA, XB, ZB) when `named`.
fn chamfer_workbook(inputs: [f64; 6], named: bool) -> Workbook {
    let mut wb = Workbook::new();
    let sheet = wb.add_sheet("Chamfer").unwrap();
    let names = ["D", "f", "alpha", "r", "eA", "eB"];
    for (i, (name, v)) in names.iter().zip(inputs).enumerate() {
        wb.set_input(sheet, parse_cell(&format!("A{}", i + 2)).unwrap(), name).unwrap();
        wb.set_input(sheet, parse_cell(&format!("B{}", i + 2)).unwrap(), &v.to_string()).unwrap();
        if named {
            wb.define_name(name, &format!("=Chamfer!$B${}", i + 2), None).unwrap();
        }
    }
    for (i, name) in ["XA", "ZA", "XB", "ZB"].iter().enumerate() {
        wb.set_input(sheet, parse_cell(&format!("A{}", i + 9)).unwrap(), name).unwrap();
        if named {
            wb.define_name(name, &format!("=Chamfer!$B${}", i + 9), None).unwrap();
        }
    }
    wb
}

fn run(wb: &mut Workbook, src: &str, options: &RunOptions) -> RunOutput {
    vba::run(wb, src, "macro.bas", options).unwrap_or_else(|e| panic!("{e}"))
}

fn results(wb: &Workbook) -> [f64; 4] {
    ["B9", "B10", "B11", "B12"].map(|c| match wb.value(0, parse_cell(c).unwrap()) {
        Value::Number(n) => n,
        other => panic!("{c} holds {other:?}"),
    })
}

fn assert_close(got: [f64; 4], want: [f64; 4], what: &str) {
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() < 5e-7, "{what}: got {got:?}, docs/domain.md says {want:?}");
    }
}

#[test]
fn chamfer_macro_writes_the_domain_values_into_the_named_cells() {
    // docs/domain.md §1, worked values (XA, ZA, XB, ZB) for the outer chamfer.
    let table = [
        ([40.0, 2.0, 45.0, 0.8, 1.0, 1.0], [44.262742, -4.6, 33.062742, 1.0]),
        ([40.0, 2.0, 30.0, 0.8, 1.0, 1.0], [42.325982, -4.6, 35.859659, 1.0]),
    ];
    for (inputs, want) in table {
        let mut wb = chamfer_workbook(inputs, true);
        let out = run(&mut wb, CHAMFER, &RunOptions::default());
        assert_close(results(&wb), want, &format!("outer {inputs:?}"));
        assert!(out.messages.is_empty(), "the macro's arithmetic and CHAMFER_* disagree: {:?}", out.messages);
        assert_eq!(out.printed.len(), 1);
    }
}

#[test]
fn chamfer_macro_does_inner_chamfers_through_the_sheet_functions() {
    let table = [
        ("pipe", [30.0, 2.0, 45.0, 0.8, 1.0, 1.0], [28.937258, -3.0, 36.937258, 1.0]),
        ("blind", [20.0, 2.0, 45.0, 0.8, 0.0, 1.0], [20.937258, -2.0, 26.937258, 1.0]),
    ];
    for (kind, inputs, want) in table {
        let mut wb = chamfer_workbook(inputs, true);
        let options = RunOptions { args: vec![("kind".into(), kind.into())], ..RunOptions::default() };
        let out = run(&mut wb, CHAMFER, &options);
        assert_close(results(&wb), want, kind);
        assert!(out.messages.is_empty(), "{:?}", out.messages);
    }
}

#[test]
fn chamfer_macro_uses_the_fixed_cells_without_names() {
    let mut wb = chamfer_workbook([40.0, 2.0, 45.0, 0.8, 1.0, 1.0], false);
    run(&mut wb, CHAMFER, &RunOptions::default());
    assert_close(results(&wb), [44.262742, -4.6, 33.062742, 1.0], "fixed layout");
}

#[test]
fn chamfer_macro_refuses_an_angle_with_no_geometry() {
    let mut wb = chamfer_workbook([40.0, 2.0, 90.0, 0.8, 1.0, 1.0], true);
    let out = run(&mut wb, CHAMFER, &RunOptions::default());
    assert_eq!(out.messages.len(), 1, "{:?}", out.messages);
    assert!(out.messages[0].contains("alpha=90"));
    assert!(!out.has_program());
}

fn moves(program: &Program) -> Option<Vec<Move>> {
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed");
        return None;
    }
    let text = dialect::by_name("linuxcnc").unwrap().render(program).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.ngc");
    std::fs::write(&path, &text).unwrap();
    Some(rs274::moves(&path).unwrap_or_else(|e| panic!("rs274 rejected the program:\n{e}\n{text}")))
}

/// (z, x as a radius) where a move ends.
fn end(m: &Move) -> (f64, f64) {
    match *m {
        Move::Traverse { x, z, .. } | Move::Feed { x, z, .. } => (z, x),
        Move::Arc { first_end, second_end, .. } => (first_end, second_end),
    }
}

#[test]
fn chamfer_program_read_by_rs274_cuts_from_t1_to_t2() {
    let mut wb = chamfer_workbook([40.0, 2.0, 45.0, 0.8, 1.0, 1.0], true);
    let out =
        run(&mut wb, CHAMFER, &RunOptions { dialect: Some(&ncsheet::nc::dialect::LINUXCNC), ..RunOptions::default() });
    let Some(moves) = moves(&out.program) else { return };
    // linuxcnc writes 3 decimals of a diameter: a radius is good to 0.0005.
    let near = |(z, x): (f64, f64), (wz, wx): (f64, f64)| (z - wz).abs() < 6e-4 && (x - wx).abs() < 6e-4;
    let feeds: Vec<usize> = (0..moves.len()).filter(|&i| matches!(moves[i], Move::Feed { .. })).collect();
    assert_eq!(feeds.len(), 2, "in to T1 and along the chamfer: {moves:?}");
    let cut = feeds[1];
    // T1: XA 44.262742 is radius 22.131371, ZA -4.6; T2: XB 33.062742, ZB 1 (docs/domain.md §1).
    assert!(matches!(moves[cut - 2], Move::Traverse { .. }), "approach by rapid: {moves:?}");
    assert!(near(end(&moves[cut - 1]), (-4.6, 22.131371)), "T1: {:?}", moves[cut - 1]);
    assert!(near(end(&moves[cut]), (1.0, 16.531371)), "T2: {:?}", moves[cut]);
    assert!(moves[cut + 1..].iter().all(|m| matches!(m, Move::Traverse { .. })), "retract by rapid: {moves:?}");
}

/// The finished part near a chamfer as segments ((z, r), (z, r)) with r a radius, drawn from
/// the inputs alone: the chamfer runs f along Z and f·tan α in radius (docs/domain.md §1's
/// corrected model); an outer chamfer joins the shaft and the face, a pipe chamfer the bore
/// and the face, a blind one the bore's flat bottom at Z −f and the face.
fn chamfer_contour(kind: &str, [d, f, alpha, ..]: [f64; 6]) -> Vec<((f64, f64), (f64, f64))> {
    let (r, h) = (d / 2.0, f * alpha.to_radians().tan());
    match kind {
        "outer" => vec![((-80.0, r), (-f, r)), ((-f, r), (0.0, r - h)), ((0.0, r - h), (0.0, 0.0))],
        "pipe" => vec![((-80.0, r), (-f, r)), ((-f, r), (0.0, r + h)), ((0.0, r + h), (0.0, r + 80.0))],
        _ => vec![((-f, 0.0), (-f, r)), ((-f, r), (0.0, r + h)), ((0.0, r + h), (0.0, r + 80.0))],
    }
}

fn distance_to_segment(p: (f64, f64), (a, b): ((f64, f64), (f64, f64))) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
}

/// How far the insert's nose is from the part when the theoretical tip is at (z, radius):
/// the nose centre is r above the tip in Z, and r outward (outer tool) or inward (boring
/// tool) in radius (docs/domain.md §1).
fn nose_clearance(kind: &str, inputs: [f64; 6], (z, x): (f64, f64)) -> f64 {
    let r = inputs[3];
    let centre = if kind == "outer" { (z + r, x + r) } else { (z + r, x - r) };
    chamfer_contour(kind, inputs).into_iter().map(|s| distance_to_segment(centre, s)).fold(f64::MAX, f64::min) - r
}

#[test]
fn chamfer_rapids_never_end_within_the_clearance_of_the_part() {
    // docs/domain.md §1's four worked cases and a few more angles and clearances; the macro's
    // default clearance is 1 mm.
    let cases = [
        ("outer", [40.0, 2.0, 45.0, 0.8, 1.0, 1.0]),
        ("outer", [40.0, 2.0, 30.0, 0.8, 1.0, 1.0]),
        ("outer", [40.0, 3.0, 60.0, 0.4, 0.2, 0.0]),
        ("pipe", [30.0, 2.0, 45.0, 0.8, 1.0, 1.0]),
        ("pipe", [30.0, 1.5, 45.0, 0.4, 0.2, 0.5]),
        ("blind", [20.0, 2.0, 45.0, 0.8, 0.0, 1.0]),
        ("blind", [24.0, 1.0, 45.0, 0.4, 0.0, 0.0]),
    ];
    let clear = 1.0;
    // 3 decimals of a diameter move the tip by up to 0.0005 in radius and Z.
    let slack = 1e-3;
    for (kind, inputs) in cases {
        let mut wb = chamfer_workbook(inputs, true);
        let options = RunOptions { args: vec![("kind".into(), kind.into())], ..RunOptions::default() };
        let out = run(&mut wb, CHAMFER, &options);
        assert!(out.messages.is_empty(), "{kind} {inputs:?}: {:?}", out.messages);
        let Some(moves) = moves(&out.program) else { return };
        let from = starts(&moves);
        let mut cuts = 0;
        for (m, s) in moves.iter().zip(&from) {
            match m {
                Move::Traverse { .. } => {
                    let gap = nose_clearance(kind, inputs, end(m));
                    assert!(gap >= clear - slack, "{kind} {inputs:?}: a rapid ends {gap:.4} mm off the part: {m:?}");
                    for p in samples(*s, m) {
                        let gap = nose_clearance(kind, inputs, p);
                        assert!(gap >= -slack, "{kind} {inputs:?}: a rapid cuts {:.4} mm deep at {p:?}", -gap);
                    }
                }
                _ => cuts += 1,
            }
        }
        assert_eq!(cuts, 2, "{kind}: in to T1 at feed, then the chamfer: {moves:?}");
        let path = dialect_text_path(&out.program);
        assert_eq!(rs274::feed_mode_at_first_cut(&path.1), Ok(Some(1)), "{kind}: G95 before the first cut");
    }
}

/// The program in the linuxcnc dialect in a temporary folder (kept alive by the first item).
fn dialect_text_path(program: &Program) -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.ngc");
    std::fs::write(&path, dialect::by_name("linuxcnc").unwrap().render(program).unwrap()).unwrap();
    (dir, path)
}

#[test]
fn every_cycle_program_feeds_per_revolution_from_its_first_cut() {
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed");
        return;
    }
    for sub in ["L16", "L17", "L13", "Main"] {
        let mut wb = Workbook::with_sheet();
        let out = run(&mut wb, CYCLES, &RunOptions { sub: Some(sub.into()), ..RunOptions::default() });
        let path = dialect_text_path(&out.program);
        assert_eq!(rs274::feed_mode_at_first_cut(&path.1), Ok(Some(1)), "{sub}");
        // Every rapid ends at least the cycles' Clear (1 mm) off the blank: diameter 44, face
        // at Z0 (the finished part lies inside it).
        for m in moves(&out.program).unwrap() {
            if let Move::Traverse { .. } = m {
                let (z, r) = end(&m);
                let gap = match (z > 0.0, r > 22.0) {
                    (true, true) => z.hypot(r - 22.0),
                    (true, false) => z,
                    (false, true) => r - 22.0,
                    (false, false) => -(r - 22.0).abs().min(z.abs()),
                };
                assert!(gap >= 1.0 - TOL, "{sub}: a rapid ends {gap} mm off the blank: {m:?}");
            }
        }
    }
}

#[test]
fn chamfer_program_renders_for_every_lathe_dialect() {
    let mut wb = chamfer_workbook([40.0, 2.0, 45.0, 0.8, 1.0, 1.0], true);
    let out = run(&mut wb, CHAMFER, &RunOptions::default());
    for name in ["iso", "linuxcnc", "sinumerik", "nc31"] {
        let text = dialect::by_name(name).unwrap().render(&out.program).unwrap_or_else(|e| panic!("{e}"));
        assert!(text.contains("X44.263") && text.contains("Z-4.6"), "{name}:\n{text}");
    }
}

// ---- the cycles ----------------------------------------------------------------------------

fn cycle(sub: &str, args: &[(&str, &str)]) -> (Program, Vec<Move>) {
    let mut wb = Workbook::with_sheet();
    let args = args.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect();
    let out = run(&mut wb, CYCLES, &RunOptions { sub: Some(sub.into()), args, ..RunOptions::default() });
    let moves = moves(&out.program).unwrap_or_default();
    (out.program, moves)
}

/// Where each move starts: the previous move's end (the first starts where it ends).
fn starts(moves: &[Move]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut at = moves.first().map(end).unwrap_or((0.0, 0.0));
    for m in moves {
        out.push(at);
        at = end(m);
    }
    out
}

/// Points along a move, arcs followed the way rs274 turns them.
fn samples(start: (f64, f64), m: &Move) -> Vec<(f64, f64)> {
    let n = 200;
    match *m {
        Move::Arc { first_end, second_end, first_centre, second_centre, rotation, .. } => {
            let (cz, cx) = (first_centre, second_centre);
            let radius = ((start.0 - cz).powi(2) + (start.1 - cx).powi(2)).sqrt();
            let a0 = (start.1 - cx).atan2(start.0 - cz);
            let a1 = (second_end - cx).atan2(first_end - cz);
            let mut sweep = a1 - a0;
            if rotation > 0 && sweep <= 0.0 {
                sweep += std::f64::consts::TAU;
            }
            if rotation < 0 && sweep >= 0.0 {
                sweep -= std::f64::consts::TAU;
            }
            (0..=n)
                .map(|i| {
                    let a = a0 + sweep * i as f64 / n as f64;
                    (cz + radius * a.cos(), cx + radius * a.sin())
                })
                .collect()
        }
        _ => {
            let e = end(m);
            (0..=n)
                .map(|i| {
                    let t = i as f64 / n as f64;
                    (start.0 + (e.0 - start.0) * t, start.1 + (e.1 - start.1) * t)
                })
                .collect()
        }
    }
}

const TOL: f64 = 6e-4;

#[test]
fn l16_zigzag_alternates_and_stops_at_the_allowance() {
    // L16 X W A P with X = 30, W = 40, A = 0.5, P = 2 from a 44 mm blank.
    let (program, moves) = cycle("L16", &[("X", "30"), ("W", "40"), ("A", "0.5"), ("P", "2"), ("Stock", "44")]);
    assert!(program.blocks.iter().any(|b| matches!(b, Block::Line { .. })));
    if moves.is_empty() {
        return;
    }
    let floor = (30.0 + 0.5) / 2.0;
    let from = starts(&moves);
    let mut cuts = Vec::new();
    for (m, s) in moves.iter().zip(&from) {
        let e = end(m);
        match m {
            Move::Feed { .. } => {
                assert!(e.1 >= floor - TOL, "cut below X + A: {m:?}");
                if (e.1 - s.1).abs() < 1e-9 && (e.0 - s.0).abs() > 1e-9 {
                    cuts.push((e.1, s.0, e.0));
                }
            }
            Move::Traverse { .. } => {
                // Between the face and the loop's end (a shoulder the tool may retract along).
                for p in samples(*s, m) {
                    let inside = p.0 < -TOL && p.0 > -40.0 + TOL;
                    assert!(!inside || p.1 >= 22.0 - TOL, "rapid through the blank at {p:?}");
                }
            }
            Move::Arc { .. } => panic!("L16 has no arcs"),
        }
    }
    // Each level cuts the whole length, the direction alternates, no level is skipped.
    assert!(cuts.len() >= 2, "{cuts:?}");
    for w in cuts.windows(2) {
        let (d0, d1) = (w[0].2 - w[0].1, w[1].2 - w[1].1);
        assert!(d0 * d1 < 0.0, "consecutive cuts go opposite ways: {cuts:?}");
        assert!(w[0].0 - w[1].0 <= 1.0 + TOL && w[1].0 < w[0].0, "steps of at most P (1 in radius): {cuts:?}");
    }
    for c in &cuts {
        let (lo, hi) = (c.1.min(c.2), c.1.max(c.2));
        assert!(lo <= -40.0 + TOL && hi >= -TOL, "a cut covers Z0 to Z-40: {c:?}");
    }
    assert!(cuts[0].0 >= 22.0 - 1.0 - TOL, "the first pass takes at most P off the blank: {cuts:?}");
    assert!((cuts.last().unwrap().0 - floor).abs() < TOL, "the last pass is at X + A: {cuts:?}");
}

/// The L17/L03 finish contour, as a radius at z (docs/domain.md §2's L03 for the example part).
fn contour(z: f64) -> f64 {
    if z >= -10.0 {
        10.0
    } else if z >= -15.0 {
        15.0 - (25.0 - (z + 10.0).powi(2)).max(0.0).sqrt()
    } else if z >= -25.0 {
        15.0
    } else {
        15.0 + (z + 25.0) * (20.0 - 15.0) / (-35.0 + 25.0)
    }
}

#[test]
fn l17_loop_follows_the_contour_at_shrinking_offsets_down_to_the_allowance() {
    let (_, moves) = cycle("L17", &[("A", "0.5"), ("P", "3"), ("Stock", "44")]);
    if moves.is_empty() {
        return;
    }
    let from = starts(&moves);
    let mut passes: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut in_pass = false;
    for (m, s) in moves.iter().zip(&from) {
        match m {
            Move::Traverse { .. } => {
                in_pass = false;
                for p in samples(*s, m) {
                    let inside = p.0 < -TOL && p.0 > -35.0 + TOL;
                    assert!(!inside || p.1 >= 22.0 - TOL, "rapid through the blank at {p:?}");
                }
            }
            _ => {
                if !in_pass {
                    passes.push(Vec::new());
                    in_pass = true;
                }
                passes.last_mut().unwrap().extend(samples(*s, m));
            }
        }
    }
    let mut offsets = Vec::new();
    for pass in &passes {
        // A pass runs from the face toward the chuck, never back (no zigzag in L17).
        for w in pass.windows(2) {
            assert!(w[1].0 <= w[0].0 + 1e-9, "a pass turns back at {:?}", w[1]);
        }
        let on_part: Vec<f64> =
            pass.iter().filter(|p| p.0 <= 0.0 && p.0 >= -35.0).map(|p| p.1 - contour(p.0)).collect();
        let (lo, hi) = on_part.iter().fold((f64::MAX, f64::MIN), |(a, b), d| (a.min(*d), b.max(*d)));
        assert!(hi - lo < 2.0 * TOL, "a pass keeps one offset from the contour: {lo}..{hi}");
        assert!(lo >= 0.25 - TOL, "cut below the contour plus A: offset {lo}");
        let z_span = pass.iter().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
        assert!(z_span.0 <= -35.0 + TOL && z_span.1 >= -TOL, "a pass covers the part: {z_span:?}");
        offsets.push(lo);
    }
    assert!(offsets.len() >= 2, "{offsets:?}");
    for w in offsets.windows(2) {
        assert!(w[1] < w[0] && w[0] - w[1] <= 1.5 + TOL, "offsets shrink by at most P (1.5 in radius): {offsets:?}");
    }
    // The blank is 22 in radius and the contour's lowest point 10: the first pass is at most P deep.
    assert!(offsets[0] >= 12.0 - 1.5 - TOL, "{offsets:?}");
    assert!((offsets.last().unwrap() - 0.25).abs() < TOL, "the last pass leaves A: {offsets:?}");
}

/// The L13 recess bottom as a radius at z: a taper, a flat, an arc bulging up, a flat, a taper.
fn recess(z: f64) -> f64 {
    let diameter = if z >= -14.0 {
        36.0 + (z + 10.0) * (30.0 - 36.0) / (-14.0 + 10.0)
    } else if z >= -18.0 {
        30.0
    } else if z >= -26.0 {
        2.0 * (12.0 + (25.0 - (z + 22.0).powi(2)).max(0.0).sqrt())
    } else {
        30.0 + (z + 26.0) * (36.0 - 30.0) / (-30.0 + 26.0)
    };
    diameter / 2.0
}

#[test]
fn l13_plunges_never_reach_below_the_bottom_and_cover_the_recess() {
    let (program, moves) = cycle("L13", &[("R0", "3"), ("R4", "2.5"), ("R5", "0.5")]);
    assert!(program.blocks.iter().any(|b| matches!(b, Block::Dwell(s) if *s == 0.5)), "a dwell after each plunge");
    if moves.is_empty() {
        return;
    }
    let from = starts(&moves);
    let mut covered = Vec::new();
    for (m, s) in moves.iter().zip(&from) {
        let e = end(m);
        match m {
            Move::Feed { .. } => {
                assert!((e.0 - s.0).abs() < 1e-9 && e.1 < s.1, "a plunge goes straight in: {m:?}");
                // The flat tool spans [z - R0, z]; the bottom under it must stay below its edge.
                let highest = (0..=3000).map(|i| recess(e.0 - 3.0 * i as f64 / 3000.0)).fold(f64::MIN, f64::max);
                assert!(e.1 >= highest - TOL, "plunge at Z{} to radius {} cuts the bottom ({highest})", e.0, e.1);
                assert!(e.1 <= highest + 2e-3, "plunge at Z{} stops short of the bottom: {} > {highest}", e.0, e.1);
                covered.push((e.0 - 3.0, e.0));
            }
            // Rapids end 1 mm (the cycles' Clear) above the blank's diameter 44.
            Move::Traverse { .. } => assert!(e.1 >= 23.0 - TOL, "rapids stay clear of the blank: {m:?}"),
            Move::Arc { .. } => panic!("L13 plunges straight"),
        }
    }
    covered.sort_by(|a, b| b.1.partial_cmp(&a.1).unwrap());
    let mut reach = -10.0;
    for (lo, hi) in &covered {
        assert!(*hi >= reach - TOL, "a gap along Z before {hi}: {covered:?}");
        reach = reach.min(*lo);
    }
    assert!(reach <= -30.0 + TOL, "the recess is covered to Z-30: {covered:?}");
}

#[test]
fn cycles_main_writes_one_program_for_every_dialect_that_has_arcs() {
    let mut wb = Workbook::with_sheet();
    let out = run(&mut wb, CYCLES, &RunOptions::default());
    for name in ["iso", "linuxcnc", "sinumerik"] {
        dialect::by_name(name).unwrap().render(&out.program).unwrap_or_else(|e| panic!("{name}: {e}"));
    }
    // NC31 has no circular interpolation: L17's fillet is written as lines (issue 32; the
    // chords are checked against the arc in tests/nc_trust.rs).
    let text = dialect::by_name("nc31").unwrap().render(&out.program).unwrap();
    assert!(!text.contains("G2") && !text.contains("G3"), "{text}");
}

// ---- the Nc object -------------------------------------------------------------------------

#[test]
fn nc_builds_blocks_from_positional_named_and_modal_arguments() {
    use ncsheet::nc::{ArcDirection, Machine, Target, Word};
    let src = "Sub Main()\n    Nc.Machine = \"mill\"\n    Nc.Name = \"POCKET\": Nc.Number = 7\n\
               \x20   Nc.Rapid 10, 0, 5\n    Nc.Feed = 100\n    Nc.Line Z:=-1\n    Nc.ArcCCW 0, 10, 0, 0\n\
               \x20   Nc.Line 0, 20, F:=200\n    Nc.Line 5, 20\n    Nc.Dwell 0.5\n    Nc.Comment \"done\", 1\n\
               \x20   Nc.Block \"M5\", \"S\", 0\n    Debug.Print Nc.Count & Nc.Machine & Nc.Feed\nEnd Sub\n";
    let mut wb = Workbook::with_sheet();
    let out = run(&mut wb, src, &RunOptions::default());
    let p = &out.program;
    assert_eq!((p.name.as_str(), p.number, p.machine), ("POCKET", Some(7), Machine::Mill));
    let z = |z: f64| Target { z: Some(z), ..Target::default() };
    assert_eq!(
        p.blocks,
        [
            Block::Rapid(Target::xyz(10.0, 0.0, 5.0)),
            Block::Line { to: z(-1.0), feed: Some(100.0) },
            Block::Arc {
                direction: ArcDirection::CounterClockwise,
                to: Target::xy(0.0, 10.0),
                centre: Target::xy(0.0, 0.0),
                feed: None
            },
            Block::Line { to: Target::xy(0.0, 20.0), feed: Some(200.0) },
            Block::Line { to: Target::xy(5.0, 20.0), feed: None },
            Block::Dwell(0.5),
            Block::Comment("done 1".into()),
            Block::Words(vec![Word::typed('M', 5.0, "5"), Word::new('S', 0.0)]),
        ]
    );
    assert_eq!(out.printed, ["8mill200"]);
    let Some(moves) = moves(p) else { return };
    // A quarter circle from (10, 0) around the origin to (0, 10), counter-clockwise.
    let arc = moves.iter().find(|m| matches!(m, Move::Arc { .. })).expect("an arc");
    assert!(
        matches!(*arc, Move::Arc { first_end, second_end, rotation: 1, .. }
        if first_end.abs() < 1e-9 && (second_end - 10.0).abs() < 1e-9),
        "{arc:?}"
    );
}

#[test]
fn nc_says_what_is_wrong_with_a_call() {
    let cases = [
        ("    Nc.Line 1, 2, 3, 4", "Nc.Line takes X, Z, F"),
        ("    Nc.Line 1, 2", "Nc.Line needs a feed: pass F:= or set Nc.Feed first"),
        ("    Nc.Rapid Q:=1", "Nc.Rapid has no argument Q (it takes X, Z)"),
        ("    Nc.Rapid", "Nc.Rapid needs a point to move to"),
        ("    Nc.ArcCW 1, 2, F:=0.1", "Nc.ArcCW needs the centre (CX and CZ)"),
        ("    Nc.Block \"G\"", "Nc.Block: G needs a number after it"),
        ("    Nc.Block 5", "Nc.Block: 5 has no address letter before it"),
        ("    Nc.Machine = \"robot\"", "Nc.Machine is \"lathe\" or \"mill\", not \"robot\""),
        ("    Nc.Fly", "Nc has no member Fly"),
    ];
    for (body, message) in cases {
        let mut wb = Workbook::with_sheet();
        let src = format!("Sub Main()\n{body}\nEnd Sub\n");
        let e = vba::run(&mut wb, &src, "nc.bas", &RunOptions::default()).unwrap_err();
        assert_eq!(e.message, message, "{body}");
        assert_eq!(e.span.unwrap().line, 2, "{body}");
    }
}

#[test]
fn nc_sets_feed_mode_spindle_tool_and_coolant() {
    use ncsheet::nc::{FeedMode, Spindle, SpindleDirection};
    let src = "Sub Main()\n    Nc.Tool 3\n    Nc.FeedPerRev 0.2\n    Nc.Spindle Vc:=180, Limit:=2500\n\
               \x20   Nc.Coolant True\n    Nc.Rapid 50, 2\n    Nc.Line 40, 0\n    Nc.FeedPerMin\n    Nc.Line 40, -5\n\
               \x20   Nc.Spindle 800, \"ccw\"\n    Nc.Spindle 0\nEnd Sub\n";
    let mut wb = Workbook::with_sheet();
    let out = run(&mut wb, src, &RunOptions::default());
    let cw = SpindleDirection::Clockwise;
    assert_eq!(
        out.program.blocks,
        [
            Block::Tool(ToolChange::new(3)),
            Block::FeedMode(FeedMode::PerRevolution),
            Block::Spindle(Spindle::SurfaceSpeed { metres_per_min: 180.0, max_rpm: 2500.0, direction: cw }),
            Block::Coolant(true),
            Block::Rapid(ncsheet::nc::Target::xz(50.0, 2.0)),
            Block::Line { to: ncsheet::nc::Target::xz(40.0, 0.0), feed: Some(0.2) },
            Block::FeedMode(FeedMode::PerMinute),
            // F means mm/min now: the next cut writes it again.
            Block::Line { to: ncsheet::nc::Target::xz(40.0, -5.0), feed: Some(0.2) },
            Block::Spindle(Spindle::Rpm { rpm: 800.0, direction: SpindleDirection::CounterClockwise }),
            Block::Spindle(Spindle::Stop),
        ]
    );
    let cases = [
        ("    Nc.Tool 0", "Nc.Tool takes a tool number from 1 to 99"),
        ("    Nc.FeedPerRev -1", "Nc.FeedPerRev takes the feed, above 0"),
        ("    Nc.Spindle 800, \"up\"", "Nc.Spindle: Dir is \"cw\" or \"ccw\", not \"up\""),
        ("    Nc.Coolant", "Nc.Coolant takes True or False"),
    ];
    for (body, message) in cases {
        let mut wb = Workbook::with_sheet();
        let e =
            vba::run(&mut wb, &format!("Sub Main()\n{body}\nEnd Sub\n"), "nc.bas", &RunOptions::default()).unwrap_err();
        assert_eq!(e.message, message, "{body}");
    }
}

#[test]
fn text_from_a_macro_stays_a_comment_in_every_dialect() {
    // The issue's injections: a line break in a comment, a comment closed inside a name.
    let src = "Sub Main()\n    Nc.Name = \"A) G0 Z-500 (\"\n    Nc.Comment \"hello\" & Chr(10) & \"G0 X0 Z-500\"\n\
               \x20   Nc.FeedPerRev 0.1\n    Nc.Spindle 500\n    Nc.Rapid 10, 1\nEnd Sub\n";
    let mut wb = Workbook::with_sheet();
    let out = run(&mut wb, src, &RunOptions::default());
    for name in ["iso", "linuxcnc", "sinumerik", "nc31"] {
        let text = dialect::by_name(name).unwrap().render(&out.program).unwrap();
        // Sinumerik's archive header holds the name as a file name (letters, digits, `_`).
        for line in text.lines().filter(|l| !l.starts_with("%_N_")) {
            let code = match name {
                "sinumerik" => line.split(';').next().unwrap(),
                _ => line.split('(').next().unwrap(),
            };
            assert!(!code.contains("500") || code.contains("S500"), "{name}: {line:?} runs as code in\n{text}");
        }
    }
}
