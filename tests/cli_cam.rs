//! `ncsheet arcfit` and `ncsheet cam` run as a user runs them; the NC program is read back by
//! LinuxCNC's rs274 and compared with the coordinate table of the same fit.

mod common;

use std::process::{Command, Output};

use common::rs274::{self, Move};

fn ncsheet(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ncsheet")).args(args).output().unwrap()
}

fn sheet() -> String {
    format!("{}/sheets/cam-turret.csv", env!("CARGO_MANIFEST_DIR"))
}

/// The rows of an arcs table as numbers (x0,y0,x1,y1,cx,cy,r) and the direction.
fn arcs(csv: &str) -> Vec<([f64; 7], String)> {
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("x0,y0,x1,y1,cx,cy,r,dir"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let mut n = [0.0; 7];
            for (i, v) in f[..7].iter().enumerate() {
                n[i] = v.parse().unwrap();
            }
            (n, f[7].to_string())
        })
        .collect()
}

#[test]
fn arcfit_starts_and_ends_on_the_spiral() {
    // Either side (--side both): knots on the spiral (one side starts off it, tests/cam_side.rs).
    let out = ncsheet(&[
        "arcfit", "--kind", "arch", "--r0", "79", "--phi0", "36", "--r1", "102", "--phi1", "160.2", "--tol", "0.01",
        "--side", "both",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let table = arcs(&String::from_utf8(out.stdout).unwrap());
    // r = 79 mm at 36°, 102 mm at 160.2° (printed to 6 decimals).
    let (first, last) = (&table[0].0, &table[table.len() - 1].0);
    let at = |r: f64, deg: f64| (r * deg.to_radians().cos(), r * deg.to_radians().sin());
    let (x0, y0) = at(79.0, 36.0);
    let (x1, y1) = at(102.0, 160.2);
    assert!((first[0] - x0).abs() < 1e-6 && (first[1] - y0).abs() < 1e-6);
    assert!((last[2] - x1).abs() < 1e-6 && (last[3] - y1).abs() < 1e-6);
    // Radius grows with the angle: every arc turns counter-clockwise.
    assert!(table.iter().all(|(_, dir)| dir == "ccw"));
    // The bound for this piece at 0.01 mm is 4 arcs; at most ⌈1.25 × 4⌉ = 5.
    assert!(table.len() <= 5, "{} arcs", table.len());
}

#[test]
fn arcfit_rejects_what_has_no_geometry() {
    for bad in [
        vec!["--kind", "log", "--r0", "0", "--phi0", "0", "--r1", "10", "--phi1", "20", "--tol", "0.01"],
        vec!["--kind", "arch", "--r0", "10", "--phi0", "20", "--r1", "12", "--phi1", "20", "--tol", "0.01"],
        vec!["--kind", "arch", "--r0", "10", "--phi0", "0", "--r1", "12", "--phi1", "20", "--tol", "0"],
        vec!["--kind", "cone", "--r0", "10", "--phi0", "0", "--r1", "12", "--phi1", "20", "--tol", "0.01"],
    ] {
        let out = ncsheet(&[&["arcfit"], bad.as_slice()].concat());
        assert_eq!(out.status.code(), Some(1), "{bad:?}");
        assert!(!String::from_utf8_lossy(&out.stderr).trim().is_empty());
    }
}

#[test]
fn cam_reports_the_gaps_of_the_printed_sheet_with_their_rows() {
    // docs/domain.md §5's table, without the return rows sheets/cam-turret.csv adds.
    let dir = tempfile::tempdir().unwrap();
    let printed = dir.path().join("printed.csv");
    let shipped = std::fs::read_to_string(sheet()).unwrap();
    let kept: Vec<&str> = shipped.lines().filter(|l| !l.contains(",160.2,163,") && !l.contains(",163,171,")).collect();
    let kept: Vec<&str> = kept.into_iter().filter(|l| !l.contains(",207,210,") && !l.contains(",210,217.8,")).collect();
    std::fs::write(&printed, kept.join("\n")).unwrap();
    let out = ncsheet(&["cam", printed.to_str().unwrap(), "--tol", "0.05"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("gap 160.2°–171°") && err.contains("row 5") && err.contains("row 7"), "{err}");
}

#[test]
fn cam_program_is_read_by_rs274_as_the_arcs_of_the_table() {
    if !rs274::available() {
        eprintln!("skipped: rs274 is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("cam.ngc");
    let common = ["cam", &sheet(), "--tol", "0.01", "--partial", "--disc", "R"];
    let table = ncsheet(&common);
    assert!(table.status.success());
    let table = arcs(&String::from_utf8(table.stdout).unwrap());
    let nc =
        ncsheet(&[&common[..], &["--format", "nc", "--dialect", "linuxcnc", "-o", program.to_str().unwrap()]].concat());
    assert!(nc.status.success(), "{}", String::from_utf8_lossy(&nc.stderr));
    let moves = rs274::moves(&program).unwrap();
    // A milling feed is per minute (G94) from the first cut.
    assert_eq!(rs274::feed_mode_at_first_cut(&program), Ok(Some(0)));
    let read: Vec<&Move> = moves.iter().filter(|m| matches!(m, Move::Arc { .. })).collect();
    assert_eq!(read.len(), table.len());
    for (m, (a, dir)) in read.iter().zip(&table) {
        let Move::Arc { first_end, second_end, first_centre, second_centre, rotation, .. } = m else { unreachable!() };
        // The program has 4 decimals, the table 6: they agree to the program's resolution.
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-4;
        assert!(close(*first_end, a[2]) && close(*second_end, a[3]), "{m:?} vs {a:?}");
        assert!(close(*first_centre, a[4]) && close(*second_centre, a[5]), "{m:?} vs {a:?}");
        assert_eq!(*rotation, if dir == "ccw" { 1 } else { -1 });
    }
}

/// One arc of a program as the control reads it: start, end, centre (absolute), turning
/// counter-clockwise or not.
#[derive(Debug)]
struct WrittenArc {
    start: (f64, f64),
    end: (f64, f64),
    centre: (f64, f64),
    ccw: bool,
}

/// The arcs of a word-address program (G2/G3 X Y I J, modal G, centre offsets from the start
/// as written) or of a plain-language one (L X Y, CC X Y, C X Y DR±), read from the text with
/// the decimals it has.
fn written_arcs(text: &str) -> Vec<WrittenArc> {
    let mut arcs = Vec::new();
    let (mut at, mut centre, mut g) = ((f64::NAN, f64::NAN), (f64::NAN, f64::NAN), 0);
    for line in text.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        if line.starts_with('(') || line.starts_with(';') || words.is_empty() {
            continue;
        }
        let value = |letter: &str| -> Option<f64> {
            words.iter().find_map(|w| w.strip_prefix(letter).and_then(|v| v.parse::<f64>().ok()))
        };
        let (x, y) = (value("X").unwrap_or(at.0), value("Y").unwrap_or(at.1));
        match words.get(1).copied() {
            // Plain language: block number, then the function.
            Some("L") if words[0].parse::<u32>().is_ok() => at = (x, y),
            Some("CC") if words[0].parse::<u32>().is_ok() => centre = (x, y),
            Some("C") if words[0].parse::<u32>().is_ok() => {
                arcs.push(WrittenArc { start: at, end: (x, y), centre, ccw: words.contains(&"DR+") });
                at = (x, y);
            }
            _ => {
                for w in &words {
                    if let Some(code) = w.strip_prefix('G').and_then(|c| c.parse::<u32>().ok()) {
                        if code <= 3 {
                            g = code;
                        }
                    }
                }
                if value("X").is_none() && value("Y").is_none() {
                    continue;
                }
                if g == 2 || g == 3 {
                    let c = (at.0 + value("I").unwrap(), at.1 + value("J").unwrap());
                    arcs.push(WrittenArc { start: at, end: (x, y), centre: c, ccw: g == 3 });
                }
                at = (x, y);
            }
        }
    }
    arcs
}

/// Points along a written arc as a control cuts it: the radius going from the start's to the
/// end's (they differ by the rounding), the angle the arc's way round.
fn arc_points(a: &WrittenArc, n: usize) -> Vec<(f64, f64)> {
    let polar =
        |p: (f64, f64)| ((p.0 - a.centre.0).hypot(p.1 - a.centre.1), (p.1 - a.centre.1).atan2(p.0 - a.centre.0));
    let ((r0, t0), (r1, t1)) = (polar(a.start), polar(a.end));
    let mut sweep = t1 - t0;
    if a.ccw && sweep <= 0.0 {
        sweep += std::f64::consts::TAU;
    }
    if !a.ccw && sweep >= 0.0 {
        sweep -= std::f64::consts::TAU;
    }
    (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64;
            let (r, angle) = (r0 + (r1 - r0) * t, t0 + sweep * t);
            (a.centre.0 + r * angle.cos(), a.centre.1 + r * angle.sin())
        })
        .collect()
}

/// The spiral piece exactly: radius at an angle in degrees.
fn spiral(kind: &str, [r0, phi0, r1, phi1]: [f64; 4]) -> impl Fn(f64) -> f64 {
    let log = kind == "log";
    move |phi: f64| {
        let t = (phi - phi0) / (phi1 - phi0);
        if log {
            r0 * (r1 / r0).powf(t)
        } else {
            r0 + (r1 - r0) * t
        }
    }
}

fn polyline_distance(p: (f64, f64), line: &[(f64, f64)]) -> f64 {
    line.windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
            (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
        })
        .fold(f64::MAX, f64::min)
}

#[test]
fn cam_programs_as_written_stay_within_the_tolerance_of_the_spiral() {
    let pieces = [("arch", [79.0, 36.0, 102.0, 160.2]), ("log", [116.0, 25.2, 79.0, 28.0])];
    for (kind, piece) in pieces {
        let r = spiral(kind, piece);
        // The exact curve, densely: chords of 0.05° on radii near 100 mm sag by < 1e-6 mm.
        let n = ((piece[3] - piece[1]) / 0.05).ceil() as usize;
        let curve: Vec<(f64, f64)> = (0..=n)
            .map(|i| {
                let phi = piece[1] + (piece[3] - piece[1]) * i as f64 / n as f64;
                (r(phi) * phi.to_radians().cos(), r(phi) * phi.to_radians().sin())
            })
            .collect();
        for tol in ["0.01", "0.001"] {
            let tol_mm: f64 = tol.parse().unwrap();
            for dialect in ["iso", "linuxcnc", "sinumerik", "heidenhain"] {
                let numbers = piece.map(|v| v.to_string());
                let out = ncsheet(&[
                    "arcfit",
                    "--kind",
                    kind,
                    "--r0",
                    &numbers[0],
                    "--phi0",
                    &numbers[1],
                    "--r1",
                    &numbers[2],
                    "--phi1",
                    &numbers[3],
                    "--tol",
                    tol,
                    "--format",
                    "nc",
                    "--dialect",
                    dialect,
                ]);
                assert!(out.status.success(), "{dialect}: {}", String::from_utf8_lossy(&out.stderr));
                let text = String::from_utf8(out.stdout).unwrap();
                let arcs = written_arcs(&text);
                assert!(!arcs.is_empty(), "{dialect}: no arcs in\n{text}");
                let path: Vec<(f64, f64)> = arcs.iter().flat_map(|a| arc_points(a, 400)).collect();
                let worst = path.iter().map(|p| polyline_distance(*p, &curve)).fold(0.0, f64::max);
                assert!(worst <= tol_mm, "{kind} {dialect} tol {tol}: the program is {worst} mm off the spiral");
                let worst = curve.iter().map(|p| polyline_distance(*p, &path)).fold(0.0, f64::max);
                assert!(worst <= tol_mm, "{kind} {dialect} tol {tol}: the spiral is {worst} mm off the program");
            }
        }
    }
}

#[test]
fn every_listed_dialect_writes_and_bad_feeds_are_refused() {
    let help = String::from_utf8(ncsheet(&["arcfit", "--help"]).stdout).unwrap();
    let piece = ["arcfit", "--kind", "arch", "--r0", "79", "--phi0", "36", "--r1", "102", "--phi1", "160.2"];
    // Every dialect the help offers for --dialect writes the program (nc31 has no arcs and
    // is not offered).
    let listed: Vec<&str> = ["iso", "linuxcnc", "sinumerik", "heidenhain", "nc31"]
        .into_iter()
        .filter(|d| help.lines().any(|l| l.contains("possible values") && l.contains(d)))
        .collect();
    assert_eq!(listed, ["iso", "linuxcnc", "sinumerik", "heidenhain"], "{help}");
    for d in listed {
        let out = ncsheet(&[&piece[..], &["--tol", "0.01", "--format", "nc", "--dialect", d]].concat());
        assert!(out.status.success(), "{d}: {}", String::from_utf8_lossy(&out.stderr));
    }
    for feed in ["--feed=0", "--feed=-5"] {
        let out = ncsheet(&[&piece[..], &["--tol", "0.01", "--format", "nc", feed]].concat());
        assert_eq!(out.status.code(), Some(1), "{feed}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("block") && err.contains("feed"), "{feed}: {err}");
    }
}

/// The design sheet's profile exactly (sheets/cam-turret.csv): for a polar angle in degrees,
/// the radius of the disc's segment covering it, or `None` in a gap of the partial sheet.
fn profile_radius(disc: &str, phi: f64) -> Option<f64> {
    static TEXT: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    let text = TEXT.get_or_init(|| std::fs::read_to_string(sheet()).unwrap());
    let phi = phi.rem_euclid(360.0);
    for line in text.lines().skip(1) {
        // The operation may hold a quoted comma; the last six fields are what counts.
        let f: Vec<&str> = line.rsplitn(7, ',').collect();
        let (r1, r0, to, from, kind, d) = (f[0], f[1], f[2], f[3], f[4], f[5]);
        let n = |s: &str| s.parse::<f64>().unwrap();
        if d == disc && (n(from)..=n(to)).contains(&phi) {
            let kind = if kind == "circle" { "arch" } else { kind };
            return Some(spiral(kind, [n(r0), n(from), n(r1), n(to)])(phi));
        }
    }
    None
}

/// Whether a cutter of `radius` centred at `c` reaches more than `tol` inside the profile:
/// points of its edge whose polar radius is below the profile's at their angle.
fn cutter_inside(disc: &str, c: (f64, f64), radius: f64, tol: f64) -> Option<f64> {
    (0..360).find_map(|k| {
        let a = (k as f64).to_radians();
        let p = (c.0 + radius * a.cos(), c.1 + radius * a.sin());
        let r = profile_radius(disc, p.1.atan2(p.0).to_degrees())?;
        let depth = r - p.0.hypot(p.1);
        (depth > tol).then_some(depth)
    })
}

/// Issue 32: with a tool table, LinuxCNC's rs274 accepts the cam program for cutters of 2 to
/// 25 mm, with a straight or an arc lead, on both discs of the shipped sheet, and the cutter
/// centre rs274 computes with compensation never reaches inside the sheet's own profile on
/// the way in: from the clearance height down, along the lead, onto the profile.
#[test]
fn rs274_with_a_tool_table_accepts_cam_programs_for_cutters_of_2_to_25_mm() {
    if !rs274::available() {
        eprintln!("skipped: rs274 is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // Disc R's profile has concave places that a cutter over 16 mm does not reach under
    // compensation (LinuxCNC: "Arc move in concave corner cannot be reached by the tool");
    // the program rounds them (see the next test), so every cutter is accepted.
    for disc in ["R", "III"] {
        for diameter in [2.0, 5.0, 10.0, 16.0, 25.0] {
            for lead in ["line", "arc"] {
                let program = dir.path().join(format!("cam-{disc}-{diameter}-{lead}.ngc"));
                let d = diameter.to_string();
                let out = linuxcnc_cam_program(disc, &d, lead, &program);
                assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
                // A stand-alone rs274 reads its tool table in inches.
                let table = dir.path().join(format!("tools-{diameter}.tbl"));
                std::fs::write(&table, format!("T1 P1 Z0 D{:.9}\n", diameter / 25.4)).unwrap();
                let canon = rs274::canon_with_tools(&program, Some(&table))
                    .unwrap_or_else(|e| panic!("rs274 refuses {disc} D{diameter} {lead}: {e}"));
                // The approach: every move until the first cut along the profile's first arc
                // (the lead arc, if any, is the first ARC_FEED; the profile's comes after).
                let moves = rs274::moves_of(&canon);
                let arcs_before_profile = if lead == "arc" { 1 } else { 0 };
                let mut arcs_seen = 0;
                let mut from: Option<(f64, f64)> = None;
                for m in &moves {
                    let (to, z) = match *m {
                        Move::Traverse { x, y, z } | Move::Feed { x, y, z } => ((x, y), z),
                        Move::Arc { first_end, second_end, axis_end, .. } => {
                            arcs_seen += 1;
                            ((first_end, second_end), axis_end)
                        }
                    };
                    if arcs_seen > arcs_before_profile {
                        break;
                    }
                    // Above the disc's top (Z0) the cutter touches nothing.
                    if z >= 0.0 {
                        from = Some(to);
                        continue;
                    }
                    // Straight moves sampled along their length (the lead arc at its end).
                    let start = from.unwrap_or(to);
                    for k in 0..=50 {
                        let t = k as f64 / 50.0;
                        let c = (start.0 + (to.0 - start.0) * t, start.1 + (to.1 - start.1) * t);
                        if let Some(depth) = cutter_inside(disc, c, diameter / 2.0, 0.02) {
                            panic!(
                                "disc {disc}, D{diameter} {lead}: the cutter at {c:?} is {depth} mm inside the profile"
                            );
                        }
                    }
                    from = Some(to);
                }
            }
        }
    }
}

/// `ncsheet cam` on the shipped sheet at 0.01 mm, for LinuxCNC with the cutter right of the
/// profile (G42): the program of `disc` for a cutter of `diameter` with a `lead` (line, arc).
fn linuxcnc_cam_program(disc: &str, diameter: &str, lead: &str, program: &std::path::Path) -> Output {
    ncsheet(&[
        "cam",
        &sheet(),
        "--disc",
        disc,
        "--tol",
        "0.01",
        "--partial",
        "--format",
        "nc",
        "--dialect",
        "linuxcnc",
        "--cutter",
        "right",
        "--cutter-diameter",
        diameter,
        "--lead-kind",
        lead,
        "-o",
        program.to_str().unwrap(),
    ])
}

/// Issue 32: a concave place of the profile that a 25 mm cutter cannot reach under the
/// control's compensation (disc R, which LinuxCNC refused with "Arc move in concave corner
/// cannot be reached by the tool without gouging") is rounded in the program and said on
/// stderr; the cutter's centre as rs274 compensates it never reaches inside the sheet's
/// profile anywhere along the cut.
#[test]
fn a_concave_place_beyond_a_large_cutter_is_rounded_and_said_and_never_gouged() {
    if !rs274::available() {
        eprintln!("skipped: rs274 is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("cam-R-25.ngc");
    let out = linuxcnc_cam_program("R", "25", "line", &program);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("beyond the reach of the D25 cutter"), "{stderr}");
    let table = dir.path().join("tools.tbl");
    std::fs::write(&table, format!("T1 P1 Z0 D{:.9}\n", 25.0 / 25.4)).unwrap();
    let canon = rs274::canon_with_tools(&program, Some(&table)).unwrap_or_else(|e| panic!("rs274 refuses: {e}"));
    let radius = 12.5;
    let mut from: Option<(f64, f64)> = None;
    let mut checked = 0;
    for m in rs274::moves_of(&canon) {
        let (to, z, centre) = match m {
            Move::Traverse { x, y, z } | Move::Feed { x, y, z } => ((x, y), z, None),
            Move::Arc { first_end, second_end, first_centre, second_centre, rotation, axis_end } => {
                ((first_end, second_end), axis_end, Some(((first_centre, second_centre), rotation)))
            }
        };
        let start = from.unwrap_or(to);
        from = Some(to);
        if z >= 0.0 {
            continue;
        }
        for k in 0..=20 {
            let t = k as f64 / 20.0;
            let c = match centre {
                None => (start.0 + (to.0 - start.0) * t, start.1 + (to.1 - start.1) * t),
                Some((o, rotation)) => {
                    let (a0, a1) = ((start.1 - o.1).atan2(start.0 - o.0), (to.1 - o.1).atan2(to.0 - o.0));
                    let sweep = if rotation > 0 {
                        (a1 - a0).rem_euclid(std::f64::consts::TAU)
                    } else {
                        -(a0 - a1).rem_euclid(std::f64::consts::TAU)
                    };
                    let r = (start.0 - o.0).hypot(start.1 - o.1);
                    let a = a0 + sweep * t;
                    (o.0 + r * a.cos(), o.1 + r * a.sin())
                }
            };
            if let Some(depth) = cutter_inside("R", c, radius, 0.02) {
                panic!("the cutter at {c:?} is {depth} mm inside disc R's profile");
            }
            checked += 1;
        }
    }
    assert!(checked > 500, "only {checked} cutter positions below the top");
}

/// Issue 32: `nc check --tool-table` refuses what LinuxCNC refuses, a compensation entry move
/// not longer than the tool radius, and passes what it accepts; the radius is the table's.
#[test]
fn nc_check_with_a_tool_table_checks_the_compensation_entry_move() {
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("entry.ngc");
    // The entry move (G42 then G1 X114) is 5 mm long.
    std::fs::write(
        &program,
        "G21 G17 G90 G40\nT1 M6 G43\nS1000 M3\nG0 Z5\nG0 X119 Y0\nG1 Z-12 F100\nG42 D1\nG1 X114 Y0 F200\n\
         G3 X-114 Y0 I-114 J0\nG40\nG1 X-119\nG0 Z5\nM5\nM2\n",
    )
    .unwrap();
    let p = program.to_str().unwrap();
    for (diameter, refused) in [(8.0, false), (12.0, true), (16.0, true)] {
        let table = dir.path().join("t.tbl");
        std::fs::write(&table, format!("T1 P1 Z0 D{:.9} ;{diameter} mm\n", diameter / 25.4)).unwrap();
        let run = ncsheet(&["nc", "check", p, "--tool-table", table.to_str().unwrap(), "--table-units", "inch"]);
        let stdout = String::from_utf8_lossy(&run.stdout);
        assert_eq!(!run.status.success(), refused, "D{diameter}: {stdout}{}", String::from_utf8_lossy(&run.stderr));
        assert_eq!(stdout.contains("entry move"), refused, "{stdout}");
        if rs274::available() {
            let said = rs274::canon_with_tools(&program, Some(&table));
            assert_eq!(said.is_err(), refused, "rs274 with D{diameter}: {said:?}");
        }
    }
}
