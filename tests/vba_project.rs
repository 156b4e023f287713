//! The VBA projects stored in Excel-saved .xlsm files, read by ncsheet and by olevba
//! (oletools, installed by `.ci/run`): every module's source must be the same text.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use ncsheet::vba::project::read_project;

/// olevba's reading of `file`: module stream path (`VBA/Module1`) → source. `None` where
/// oletools is not installed (an error on CI, where `.ci/run` installs it).
fn olevba(file: &Path) -> Option<BTreeMap<String, String>> {
    let script = r#"
import json, sys
from oletools.olevba import VBA_Parser
p = VBA_Parser(sys.argv[1])
out = {}
if p.detect_vba_macros():
    for (_, stream, _, code) in p.extract_macros():
        out[stream] = code
print(json.dumps(out))
"#;
    let run = Command::new("python3").arg("-c").arg(script).arg(file).output();
    let ok = run.as_ref().is_ok_and(|o| o.status.success());
    if !ok {
        let why = run.map(|o| String::from_utf8_lossy(&o.stderr).into_owned()).unwrap_or_else(|e| e.to_string());
        assert!(std::env::var_os("CI").is_none(), "olevba (pip oletools) is missing on CI: {why}");
        eprintln!("skipped: olevba (pip install oletools) does not run here: {why}");
        return None;
    }
    let text = String::from_utf8(run.unwrap().stdout).unwrap();
    let map: serde_json::Value = serde_json::from_str(&text).unwrap();
    Some(map.as_object().unwrap().iter().map(|(k, v)| (k.clone(), v.as_str().unwrap().to_string())).collect())
}

fn xlsm_files() -> Vec<PathBuf> {
    let mut files = Vec::new();
    common::workbooks(&common::corpus::path().join("../public"), &mut files);
    files.retain(|f| f.extension().is_some_and(|e| e == "xlsm"));
    files
}

#[test]
fn modules_read_as_olevba_reads_them() {
    let files = xlsm_files();
    let mut projects = 0;
    for file in &files {
        let opened = ncsheet::io::open(file).unwrap_or_else(|e| panic!("{e}"));
        let Some(bytes) = opened.layout.and_then(|l| l.vba_project) else {
            continue;
        };
        let Some(theirs) = olevba(file) else {
            return;
        };
        let project = read_project(&bytes).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let ours: BTreeMap<String, String> =
            project.modules.iter().map(|m| (format!("VBA/{}", m.stream), m.source.clone())).collect();
        assert_eq!(ours.keys().collect::<Vec<_>>(), theirs.keys().collect::<Vec<_>>(), "{}", file.display());
        for (stream, text) in &theirs {
            assert!(ours[stream] == *text, "{}: {stream} differs from olevba's", file.display());
        }
        projects += 1;
    }
    // The public corpus has ten Excel-saved workbooks with a VBA project.
    assert!(projects >= 10, "only {projects} VBA projects found in {} .xlsm files", files.len());
}

/// A project cut short or with a damaged stream is an error that names the stream.
#[test]
fn damaged_projects_are_errors_naming_the_stream() {
    let file = xlsm_files().into_iter().find(|f| f.to_string_lossy().contains("SimpleMacro")).unwrap();
    let bytes = ncsheet::io::open(&file).unwrap().layout.unwrap().vba_project.unwrap();
    let cut = read_project(&bytes[..bytes.len() / 2]).unwrap_err();
    assert!(!cut.stream.is_empty(), "{cut}");
    // Overwrite the compressed dir stream's signature byte wherever the stream starts: find
    // it by damaging each sector start in turn until the dir stream is the one named.
    let named_dir = (512..bytes.len()).step_by(64).any(|at| {
        let mut broken = bytes.clone();
        broken[at] ^= 0xFF;
        matches!(read_project(&broken), Err(e) if e.stream.ends_with("/dir"))
    });
    assert!(named_dir, "no damage to the dir stream was reported as the dir stream's");
}

/// The paper's chamfer macro put into the chamfer workbook: olevba reads the module back as
/// the .bas file's text (with CRLF line ends, as VBA stores them), and so does
/// ncsheet, beside a document module for the workbook and one for each sheet.
#[test]
fn an_imported_macro_reads_back_as_its_bas_file() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("chamfer.xlsm");
    let run = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .arg("macros")
        .arg(root.join("sheets/chamfer.xlsx"))
        .arg("--import")
        .arg(root.join("sheets/chamfer.bas"))
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let bas = std::fs::read_to_string(root.join("sheets/chamfer.bas")).unwrap();
    assert!(bas.starts_with("Attribute VB_Name = \"Chamfer\""), "the module names itself");
    let want = bas.replace("\r\n", "\n").replace('\n', "\r\n");
    let project = read_project(&ncsheet::io::open(&out).unwrap().layout.unwrap().vba_project.unwrap()).unwrap();
    let names: Vec<&str> = project.modules.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["ThisWorkbook", "Sheet1", "Sheet2", "Sheet3", "Sheet4", "Chamfer"]);
    assert!(project.modules[5].source == want, "ncsheet reads back another text");
    if let Some(theirs) = olevba(&out) {
        assert!(theirs["VBA/Chamfer"] == want, "olevba reads back another text");
        assert_eq!(theirs.len(), 6);
    }
}

/// The imported macro runs from the workbook itself: LinuxCNC's rs274 reads the program it
/// writes, and the chamfer cut goes from T1 to T2 of DOMAIN.md §1's table (outer, α = 45°).
#[test]
fn the_workbooks_own_chamfer_macro_runs_from_the_file() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("chamfer.xlsm");
    let (xlsx, bas) = (root.join("sheets/chamfer.xlsx"), root.join("sheets/chamfer.bas"));
    let made = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .arg("macros")
        .arg(&xlsx)
        .arg("--import")
        .arg(&bas)
        .arg("-o")
        .arg(&book)
        .output()
        .unwrap();
    assert!(made.status.success(), "{}", String::from_utf8_lossy(&made.stderr));
    let program = dir.path().join("chamfer.ngc");
    let ran = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .arg("run")
        .arg(&book)
        .args(["--sub", "Chamfer.Main", "--sheet", "Outer", "--dialect", "linuxcnc", "-o"])
        .arg(&program)
        .output()
        .unwrap();
    assert!(ran.status.success(), "{}", String::from_utf8_lossy(&ran.stderr));
    if !common::rs274::available() {
        return;
    }
    let moves = common::rs274::moves(&program).unwrap();
    let feeds: Vec<(f64, f64)> = moves
        .iter()
        .filter_map(|m| match m {
            common::rs274::Move::Feed { x, z, .. } => Some((*x, *z)),
            _ => None,
        })
        .collect();
    // rs274 reports X as a radius (the program is in diameter mode, G7): the cut feeds to T1,
    // then along the chamfer to T2.
    let near = |(x, z): (f64, f64), (dx, dz): (f64, f64)| (x - dx / 2.0).abs() < 0.001 && (z - dz).abs() < 0.001;
    let t1 = feeds.iter().position(|&p| near(p, (44.262742, -4.6)));
    let t2 = feeds.iter().position(|&p| near(p, (33.062742, 1.0)));
    assert!(matches!((t1, t2), (Some(a), Some(b)) if b == a + 1), "{feeds:?}");
}
