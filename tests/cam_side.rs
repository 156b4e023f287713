//! Issue 33, scope 1: the cam paper's design sheet as its shop uses it (docs/domain.md §5):
//! parabolic (constant-acceleration) pieces, angles in hundredths of a turn, the shipped sheet
//! complete with the paper's return rows, and arcs on the material side of the profile.
//!
//! The profile is computed here from the sheet's numbers with the closed forms of each kind;
//! the program is read from its text as the control reads it.

use std::process::{Command, Output};

use ncsheet::geometry::cam::{check_coverage, fit_piece_on_side, Piece, PieceKind, Side};
use ncsheet::nc::cam_sheet::parse_sheet;

fn ncsheet(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ncsheet")).args(args).output().unwrap()
}

fn sheet_path() -> String {
    format!("{}/sheets/cam-turret.csv", env!("CARGO_MANIFEST_DIR"))
}

/// Radius at the polar angle `phi` (degrees) of a piece given as the sheet gives it, from the
/// closed form of its kind.
fn closed_form(kind: &str, [r0, phi0, r1, phi1]: [f64; 4], phi: f64) -> f64 {
    let t = (phi - phi0) / (phi1 - phi0);
    match kind {
        "circle" => r0,
        "arch" => r0 + (r1 - r0) * t,
        // r = r0·e^(a(φ − φ0)), a = ln(r1/r0)/(φ1 − φ0) (docs/domain.md §5 [fix]).
        "log" => r0 * ((r1 / r0).ln() / (phi1 - phi0) * (phi - phi0)).exp(),
        // From rest to rest: s = 2h·t² up to the middle, h − 2h(1 − t)² after.
        "parab" if t <= 0.5 => r0 + 2.0 * (r1 - r0) * t * t,
        "parab" => r1 - 2.0 * (r1 - r0) * (1.0 - t) * (1.0 - t),
        _ => panic!("kind {kind}"),
    }
}

/// One disc's rows of the shipped sheet: kind and [r0, φ0, r1, φ1].
fn disc_rows(disc: &str) -> Vec<(String, [f64; 4])> {
    let text = std::fs::read_to_string(sheet_path()).unwrap();
    let mut rows = Vec::new();
    for line in text.lines().skip(1) {
        // The operation may hold a quoted comma; the last six fields are what counts.
        let f: Vec<&str> = line.rsplitn(7, ',').collect();
        let n = |s: &str| s.parse::<f64>().unwrap();
        if f[5] == disc {
            rows.push((f[4].to_string(), [n(f[1]), n(f[3]), n(f[0]), n(f[2])]));
        }
    }
    rows
}

/// The profile radius at `phi` degrees, from the rows covering it.
fn profile_radius(rows: &[(String, [f64; 4])], phi: f64) -> f64 {
    let phi = if phi == 360.0 { phi } else { phi.rem_euclid(360.0) };
    let (kind, piece) =
        rows.iter().find(|(_, p)| (p[1]..=p[3]).contains(&phi)).unwrap_or_else(|| panic!("no row covers {phi}°"));
    closed_form(kind, *piece, phi)
}

/// Signed distance from `q` to the profile: positive away from the cam centre. The profile
/// near q's polar angle is taken as a polyline of 0.0005° chords (their sag is below 1e-8 mm).
fn signed_distance(profile: &dyn Fn(f64) -> f64, q: (f64, f64)) -> f64 {
    let phi_q = q.1.atan2(q.0).to_degrees();
    let point = |phi: f64| {
        let r = profile(phi);
        (r * phi.to_radians().cos(), r * phi.to_radians().sin())
    };
    let steps = 1200;
    let line: Vec<(f64, f64)> = (0..=steps).map(|i| point(phi_q - 0.3 + 0.6 * i as f64 / steps as f64)).collect();
    let distance = line
        .windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let t = (((q.0 - a.0) * dx + (q.1 - a.1) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
            (q.0 - a.0 - t * dx).hypot(q.1 - a.1 - t * dy)
        })
        .fold(f64::MAX, f64::min);
    if q.0.hypot(q.1) >= profile(phi_q) {
        distance
    } else {
        -distance
    }
}

/// The arcs of an ISO program as a control reads them, sampled: the start is where the last
/// block ended as written, the centre the start plus I J as written, the radius going from the
/// start's to the end's.
fn written_arc_points(text: &str, per_arc: usize) -> Vec<Vec<(f64, f64)>> {
    let mut arcs = Vec::new();
    let (mut at, mut g) = ((f64::NAN, f64::NAN), 0);
    for line in text.lines().filter(|l| !l.starts_with('(')) {
        let words: Vec<&str> = line.split_whitespace().collect();
        let value = |letter: char| words.iter().find_map(|w| w.strip_prefix(letter)?.parse::<f64>().ok());
        for w in &words {
            if let Some(code) = w.strip_prefix('G').and_then(|c| c.parse::<u32>().ok()).filter(|c| *c <= 3) {
                g = code;
            }
        }
        if value('X').is_none() && value('Y').is_none() {
            continue;
        }
        let end = (value('X').unwrap_or(at.0), value('Y').unwrap_or(at.1));
        if g == 2 || g == 3 {
            let c = (at.0 + value('I').unwrap(), at.1 + value('J').unwrap());
            let polar = |p: (f64, f64)| ((p.0 - c.0).hypot(p.1 - c.1), (p.1 - c.1).atan2(p.0 - c.0));
            let ((r0, a0), (r1, a1)) = (polar(at), polar(end));
            let tau = std::f64::consts::TAU;
            let sweep = if g == 3 { (a1 - a0).rem_euclid(tau) } else { -(a0 - a1).rem_euclid(tau) };
            arcs.push(
                (0..=per_arc)
                    .map(|i| {
                        let u = i as f64 / per_arc as f64;
                        let (r, a) = (r0 + (r1 - r0) * u, a0 + sweep * u);
                        (c.0 + r * a.cos(), c.1 + r * a.sin())
                    })
                    .collect(),
            );
        }
        at = end;
    }
    arcs
}

/// The least and the greatest signed distance of the written arcs from the profile.
fn band_of(text: &str, profile: &dyn Fn(f64) -> f64) -> (f64, f64) {
    let arcs = written_arc_points(text, 40);
    assert!(!arcs.is_empty(), "no arcs in\n{text}");
    arcs.iter()
        .flatten()
        .map(|&q| signed_distance(profile, q))
        .fold((f64::MAX, f64::MIN), |(lo, hi), d| (lo.min(d), hi.max(d)))
}

/// An angle near 340°–360° as a number in that range (the dwell before and after extends it).
fn near_340_to_360(phi: f64) -> f64 {
    let phi = phi.rem_euclid(360.0);
    (if phi < 180.0 { phi + 360.0 } else { phi }).clamp(340.0, 360.0)
}

#[test]
fn a_parabolic_piece_rises_with_constant_acceleration_from_rest_to_rest() {
    let (r0, phi0, r1, phi1) = (70.0, 340.0, 114.0, 360.0);
    let piece = Piece::new(PieceKind::parse("parab").unwrap(), r0, phi0, r1, phi1).unwrap();
    assert_eq!(PieceKind::parse("Parabolic").unwrap(), PieceKind::Parabolic);
    for i in 0..=40 {
        let t = i as f64 / 40.0;
        let p = piece.point(t);
        let phi = phi0 + (phi1 - phi0) * t;
        let expected = closed_form("parab", [r0, phi0, r1, phi1], phi);
        assert!((p.coords.norm() - expected).abs() < 1e-9, "t = {t}: r = {} against {expected}", p.coords.norm());
        assert!((p.y.atan2(p.x).to_degrees().rem_euclid(360.0) - phi.rem_euclid(360.0)).abs() % 360.0 < 1e-9);
    }
    // At rest at both ends (no corner with the dwells either side) and half way at the middle.
    let tangent_is_circular = |t: f64| piece.tangent(t).dot(&piece.point(t).coords.normalize()).abs() < 1e-12;
    assert!(tangent_is_circular(0.0) && tangent_is_circular(1.0));
    assert!((piece.point(0.5).coords.norm() - 92.0).abs() < 1e-12);
    // Outside, within 0.01 mm, as the closed form says.
    let rows = vec![("parab".to_string(), [r0, phi0, r1, phi1])];
    let profile = |phi: f64| profile_radius(&rows, near_340_to_360(phi));
    for arc in fit_piece_on_side(&piece, 0.01, Side::Outside, 0.0).unwrap() {
        for k in 0..=40 {
            let q = arc.point_at(k as f64 / 40.0);
            let d = signed_distance(&profile, (q.x, q.y));
            assert!((-1e-9..=0.01 + 1e-9).contains(&d), "arc point {q} is {d} mm from the parabolic piece");
        }
    }
}

#[test]
fn a_parabolic_piece_in_a_program_lies_outside_within_the_tolerance() {
    let out = ncsheet(&[
        "arcfit", "--kind", "parab", "--r0", "70", "--phi0", "340", "--r1", "114", "--phi1", "360", "--tol", "0.01",
        "--format", "nc",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rows = vec![("parab".to_string(), [70.0, 340.0, 114.0, 360.0])];
    let profile = |phi: f64| profile_radius(&rows, near_340_to_360(phi));
    let (lo, hi) = band_of(&String::from_utf8(out.stdout).unwrap(), &profile);
    assert!(lo >= 0.0 && hi <= 0.01, "the written arcs lie {lo}..{hi} mm from the piece");
}

/// The paper's table 1 gives the turret slide's angles in hundredths of a turn (columns 11,
/// 12), its table 2 the same angles in degrees ("Beosztás"): a sheet in hundredths reads as
/// those degrees.
#[test]
fn a_sheet_in_hundredths_of_a_turn_reads_as_the_papers_degrees() {
    let hundredths = "row,type,from_hundredths,to_hundredths,r_start,r_end\n\
                      a,circle,0,1.5,114,114\n\
                      c,arch,3,7,110,116\n\
                      e,arch,10,44.5,79,102\n\
                      g,arch,47.5,57.5,100.5,109\n\
                      j,arch,60.5,64.5,70,88\n\
                      n,arch,65,97,68.15,80\n\
                      o,log,97,100,80,30\n";
    let degrees =
        [(0.0, 5.4), (10.8, 25.2), (36.0, 160.2), (171.0, 207.0), (217.8, 232.2), (234.0, 349.2), (349.2, 360.0)];
    let segments = parse_sheet(hundredths).unwrap();
    assert_eq!(segments.len(), degrees.len());
    for (s, (from, to)) in segments.iter().zip(degrees) {
        assert!((s.piece.phi0_deg - from).abs() < 1e-9 && (s.piece.phi1_deg - to).abs() < 1e-9, "{s:?}");
    }
    let both = "type,from_deg,to_deg,from_hundredths,to_hundredths,r_start,r_end\ncircle,0,5.4,0,1.5,114,114\n";
    let err = parse_sheet(both).unwrap_err().to_string();
    assert!(err.contains("line 1") && err.contains("twice"), "{err}");
    let half = "type,from_hundredths,to_deg,r_start,r_end\ncircle,0,5.4,114,114\n";
    let err = parse_sheet(half).unwrap_err().to_string();
    assert!(err.contains("line 1") && err.contains("but no"), "{err}");
}

/// Table 2 of the paper with its return and approach columns (docs/cam.md lists the two
/// corrections and the one derived row), both discs closed at 360°.
#[test]
fn the_shipped_sheet_goes_round_both_discs_with_the_papers_rows() {
    let turret = [
        ("circle", [114.0, 0.0, 114.0, 5.4]),
        ("log", [114.0, 5.4, 110.0, 8.0]),
        ("circle", [110.0, 8.0, 110.0, 10.8]),
        ("arch", [110.0, 10.8, 116.0, 25.2]),
        ("log", [116.0, 25.2, 79.0, 28.0]),
        ("circle", [79.0, 28.0, 79.0, 36.0]),
        ("arch", [79.0, 36.0, 102.0, 160.2]),
        ("log", [102.0, 160.2, 100.5, 163.0]),
        ("circle", [100.5, 163.0, 100.5, 171.0]),
        ("arch", [100.5, 171.0, 109.0, 207.0]),
        ("log", [109.0, 207.0, 70.0, 210.0]),
        ("circle", [70.0, 210.0, 70.0, 217.8]),
        ("arch", [70.0, 217.8, 88.0, 232.2]),
        ("circle", [88.0, 232.2, 88.0, 234.0]),
        ("log", [88.0, 234.0, 70.0, 237.6]),
        ("circle", [70.0, 237.6, 70.0, 340.0]),
        ("log", [70.0, 340.0, 114.0, 360.0]),
    ];
    let part_off = [
        ("circle", [30.0, 0.0, 30.0, 220.0]),
        ("log", [30.0, 220.0, 68.15, 234.0]),
        ("arch", [68.15, 234.0, 80.0, 349.2]),
        ("log", [80.0, 349.2, 30.0, 360.0]),
    ];
    for (disc, expected) in [("R", &turret[..]), ("III", &part_off[..])] {
        let rows = disc_rows(disc);
        let rows: Vec<(&str, [f64; 4])> = rows.iter().map(|(k, p)| (k.as_str(), *p)).collect();
        assert_eq!(rows, expected, "disc {disc}");
    }
    let segments = parse_sheet(&std::fs::read_to_string(sheet_path()).unwrap()).unwrap();
    for disc in ["R", "III"] {
        let one: Vec<_> = segments.iter().filter(|s| s.disc == disc).cloned().collect();
        assert_eq!(check_coverage(&one), vec![], "disc {disc}");
        let out = ncsheet(&["cam", &sheet_path(), "--disc", disc, "--tol", "0.05", "--format", "csv"]);
        assert!(out.status.success(), "disc {disc} without --partial: {}", String::from_utf8_lossy(&out.stderr));
        assert!(out.stderr.is_empty(), "disc {disc}: {}", String::from_utf8_lossy(&out.stderr));
    }
}

/// The acceptance check of the side: every arc as the program writes it (its decimals) lies
/// on the chosen side of the sheet's profile, within the tolerance; by default outside, as a
/// finished outer cam needs. `--side both` does cross the profile (the check can fail).
#[test]
fn cam_arcs_as_written_lie_on_the_chosen_side_within_the_tolerance() {
    for disc in ["R", "III"] {
        let rows = disc_rows(disc);
        let profile = |phi: f64| profile_radius(&rows, phi);
        for tol in ["0.01", "0.05"] {
            let tol_mm: f64 = tol.parse().unwrap();
            for side in [None, Some("outside"), Some("inside"), Some("both")] {
                let mut args = vec!["cam", "--disc", disc, "--tol", tol, "--format", "nc"];
                if let Some(side) = side {
                    args.extend(["--side", side]);
                }
                let sheet = sheet_path();
                args.insert(1, &sheet);
                let out = ncsheet(&args);
                assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
                let (lo, hi) = band_of(&String::from_utf8(out.stdout).unwrap(), &profile);
                let what =
                    format!("disc {disc}, tol {tol}, side {side:?}: the arcs lie {lo}..{hi} mm from the profile");
                match side {
                    None | Some("outside") => assert!(lo >= 0.0 && hi <= tol_mm, "{what}"),
                    Some("inside") => assert!(lo >= -tol_mm && hi <= 0.0, "{what}"),
                    _ => assert!(lo >= -tol_mm && hi <= tol_mm && lo < 0.0 && hi > 0.0, "{what}"),
                }
            }
        }
    }
}
