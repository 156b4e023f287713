//! The example sheets a user runs first, computed by the real binary and checked against
//! docs/domain.md's tables.

use std::process::Command;

fn eval_json(sheet: &str) -> serde_json::Map<String, serde_json::Value> {
    let path = format!("{}/sheets/{sheet}", env!("CARGO_MANIFEST_DIR"));
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet")).args(["eval", &path, "--format", "json"]).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let problems = String::from_utf8_lossy(&out.stderr);
    assert!(problems.trim().is_empty(), "{sheet} reports problems:\n{problems}");
    match serde_json::from_slice(&out.stdout).unwrap() {
        serde_json::Value::Object(m) => m,
        other => panic!("not an object: {other}"),
    }
}

fn number(m: &serde_json::Map<String, serde_json::Value>, cell: &str) -> f64 {
    m.get(&format!("Sheet1!{cell}")).and_then(|v| v.as_f64()).unwrap_or_else(|| panic!("{cell} is not a number"))
}

/// Table T8.1.4 (docs/domain.md §4), printed to 3 decimals: rows φ = 0°, 45°, 90°.
#[test]
fn sphere_5axis_reproduces_table_t8_1_4() {
    let m = eval_json("sphere-5axis.csv");
    let rows = [
        (6, 0.0, [156.125, 0.0, 75.0, 0.0, 18.195]),
        (9, 45.0, [110.397, 110.397, 75.0, -12.756, 13.084]),
        (12, 90.0, [0.0, 156.125, 75.0, -18.195, 0.0]),
    ];
    for (row, phi, printed) in rows {
        assert_eq!(number(&m, &format!("A{row}")), phi);
        for (col, want) in ["H", "I", "J", "K", "L"].into_iter().zip(printed) {
            let got = number(&m, &format!("{col}{row}"));
            assert!((got - want).abs() <= 0.0005, "{col}{row} = {got}, printed {want}");
        }
    }
    // φ runs 0…360° in steps of 15°.
    assert_eq!(number(&m, "A30"), 360.0);
}

/// docs/domain.md §1's worked values, to 1e-6 mm.
#[test]
fn chamfer_builtin_reproduces_the_domain_table() {
    let m = eval_json("chamfer-builtin.csv");
    let table = [
        (2, [44.262742, -4.6, 33.062742, 1.0]),
        (3, [42.325982, -4.6, 35.859659, 1.0]),
        (4, [28.937258, -3.0, 36.937258, 1.0]),
        (5, [20.937258, -2.0, 26.937258, 1.0]),
    ];
    for (row, want) in table {
        for (col, w) in ["H", "I", "J", "K"].into_iter().zip(want) {
            let got = number(&m, &format!("{col}{row}"));
            assert!((got - w).abs() < 1e-6, "{col}{row} = {got}, want {w}");
        }
    }
}
