//! A ball path's surface formula has a bounded cost (issue 30, runaway): its slopes are built
//! within `MAX_SLOPE_PARTS` parts, and its evaluations within `MAX_SURFACE_STEPS` formula
//! steps, charged up front for the path's points and counted as they are spent. Each test
//! bounds work (parts, steps), never time.

use std::process::Command;

use ncsheet::eval::functions::Registry;
use ncsheet::eval::surface::{FormulaSurface, SurfaceFault};
use ncsheet::eval::Ctx;
use ncsheet::formula::parse::ParseContext;
use ncsheet::formula::Pos;
use ncsheet::workbook::Workbook;

fn ballpath(surface: &str, grid: &str) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(["ballpath", "--surface", surface, "--radius", "1", "--x", grid, "--y", grid])
        .args(["--stepover", "0.01", "--step", "0.01", "--gouge", "off"])
        .output()
        .expect("ncsheet runs");
    (out.status.success(), String::from_utf8_lossy(&out.stderr).into_owned())
}

/// A product of 1,400 factors x has a slope of about a million parts (1,400²/2 products, each
/// a copy of the factors before it): it asked for 270 MB and ran past 30 s with the gouge
/// check. It is refused while the slope is built, by the limit's number.
#[test]
fn a_slope_past_its_part_limit_is_refused_while_it_is_built() {
    let product = vec!["x"; 1400].join("*");
    let (ok, stderr) = ballpath(&product, "0:1");
    assert!(!ok);
    assert!(stderr.contains("the surface's slope by x would have more than 1000000 parts"), "{stderr}");
    // 200 factors: about 20,000 parts, within the limit; the path is made (x^200 is 0 to
    // rounding below 0.01 and 1 at x = 1).
    let (ok, stderr) = ballpath(&vec!["x"; 200].join("*"), "0:1");
    assert!(ok, "{stderr}");
}

/// A 999-term sum SIN(x*k)*COS(y*k) over 201 × 201 points: about 35,000 steps a point with its
/// slopes, 1.4·10^9 for the points alone, past the 500,000,000 one path may spend. It ran past
/// 30 s (and took 2.1 GB sharing its parts); it is refused before any point is placed.
#[test]
fn a_long_surface_over_many_points_is_refused_up_front() {
    let sum: Vec<String> = (1..=999).map(|k| format!("SIN(x*{k})*COS(y*{k})")).collect();
    let (ok, stderr) = ballpath(&sum.join("+"), "0:2");
    assert!(!ok);
    assert!(stderr.contains("points alone would take more than the 500000000 steps one path may spend"), "{stderr}");
    assert!(stderr.contains("the path's 40401 points"), "{stderr}");
}

/// The steps are counted as they are spent: a surface bound with room for `n` samples gives
/// `n` and then stops, naming the limit and the steps a sample takes.
#[test]
fn the_surface_stops_when_its_steps_are_spent() {
    let parsing = ParseContext { at: Pos::new(0, 0), functions: &Registry, sheet: &|_| None };
    let surface = FormulaSurface::parse("0.3*EXP(-16*(x^2+y^2))", &parsing).unwrap();
    let per_sample = surface.steps().sample;
    assert!(per_sample > 0);
    let wb = Workbook::with_sheet();
    let mut eval = Ctx::new(&wb, 0, Pos::new(0, 0));
    let limit = 10 * per_sample + per_sample / 2;
    let mut bound = surface.bind_within(&mut eval, limit);
    for i in 0..10 {
        // The paper's bump and its slope by x (docs/domain.md §3 [fix]): -9.6·x·e^(−16x²−16y²).
        let x = 0.01 * f64::from(i);
        let [z, dzdx, _] = bound.sample_at(x, 0.0).unwrap();
        let e = (-16.0 * x * x).exp();
        assert!((z - 0.3 * e).abs() < 1e-15 && (dzdx + 9.6 * x * e).abs() < 1e-14, "sample {i}");
    }
    assert_eq!(bound.sample_at(0.5, 0.0), Err(SurfaceFault::OutOfSteps { limit, per_sample }));
}
