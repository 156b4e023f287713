//! VBA projects in tests: olevba (PyPI oletools, installed by `.ci/run`), the independent
//! reader of VBA projects, and the surgery tests do on a project's streams and its .xlsm.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// olevba's reading of `file`: module stream path (`VBA/Module1`) → source. `None` where
/// oletools is not installed (an error on CI, where `.ci/run` installs it).
pub fn olevba(file: &Path) -> Option<BTreeMap<String, String>> {
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

/// `bytes` (a compound file) with the stream at `path` given new contents.
pub fn with_stream(bytes: &[u8], path: &str, change: impl Fn(&[u8]) -> Vec<u8>) -> Vec<u8> {
    let mut cfb = cfb::CompoundFile::open(std::io::Cursor::new(bytes.to_vec())).unwrap();
    let mut old = Vec::new();
    std::io::Read::read_to_end(&mut cfb.open_stream(path).unwrap(), &mut old).unwrap();
    let mut stream = cfb.create_stream(path).unwrap();
    std::io::Write::write_all(&mut stream, &change(&old)).unwrap();
    drop(stream);
    cfb.flush().unwrap();
    cfb.into_inner().into_inner()
}

/// `source` (an .xlsm) written to `out` with another `xl/vbaProject.bin`.
pub fn xlsm_with_project(source: &Path, project: &[u8], out: &Path) {
    let mut zip = zip::ZipArchive::new(std::fs::File::open(source).unwrap()).unwrap();
    let mut writer = zip::ZipWriter::new(std::fs::File::create(out).unwrap());
    for i in 0..zip.len() {
        let entry = zip.by_index(i).unwrap();
        if entry.name().unwrap() == "xl/vbaProject.bin" {
            drop(entry);
            writer.start_file("xl/vbaProject.bin", zip::write::SimpleFileOptions::default()).unwrap();
            std::io::Write::write_all(&mut writer, project).unwrap();
        } else {
            writer.raw_copy_file(entry).unwrap();
        }
    }
    writer.finish().unwrap();
}

/// What `Sub Main()` with `body` printed, run on `wb` under the default options; the test
/// fails naming the macro's error.
pub fn run_main(wb: &mut ncsheet::workbook::Workbook, body: &str) -> Vec<String> {
    let src = format!("Sub Main()\n{body}\nEnd Sub\n");
    ncsheet::vba::run(wb, &src, "main.bas", &ncsheet::vba::RunOptions::default())
        .unwrap_or_else(|e| panic!("{e}"))
        .printed
}

/// The message of the error that stops `Sub Main()` with `body`; the test fails when the
/// macro runs to its end.
pub fn main_fails(wb: &mut ncsheet::workbook::Workbook, body: &str) -> String {
    let src = format!("Sub Main()\n{body}\nEnd Sub\n");
    match ncsheet::vba::run(wb, &src, "main.bas", &ncsheet::vba::RunOptions::default()) {
        Ok(out) => panic!("the macro ran to its end, printing {:?}", out.printed),
        Err(e) => e.message,
    }
}

/// `src`, a whole module, run from its `Sub Main` on a new one-sheet workbook under the
/// default options.
pub fn run_module(src: &str) -> Result<ncsheet::vba::RunOutput, ncsheet::vba::MacroError> {
    ncsheet::vba::run(
        &mut ncsheet::workbook::Workbook::with_sheet(),
        src,
        "test.bas",
        &ncsheet::vba::RunOptions::default(),
    )
}

/// What `Sub Main()` with `body` printed after the module-level lines `module` (Types,
/// Functions, constants), on a new one-sheet workbook; the test fails naming the macro's error.
pub fn printed_after(module: &str, body: &str) -> Vec<String> {
    run_module(&format!("{module}\nSub Main()\n{body}\nEnd Sub\n")).unwrap_or_else(|e| panic!("{e}")).printed
}

/// A VBA project of one standard module, Module1, holding `source`.
pub fn module1(source: &str) -> ncsheet::vba::project::VbaProject {
    use ncsheet::vba::project::{ModuleKind, ProjectModule, VbaProject};
    VbaProject {
        code_page: 1252,
        modules: vec![ProjectModule {
            name: "Module1".into(),
            stream: "Module1".into(),
            kind: ModuleKind::Standard,
            source: source.into(),
        }],
        protection: None,
    }
}

/// A macro run on a one-sheet workbook with the project's class modules (name, source as the
/// VBA project stores it, `Attribute` lines included), failing or not.
pub fn run_with_classes(
    main: &str,
    classes: &[(&str, &str)],
) -> Result<ncsheet::vba::RunOutput, ncsheet::vba::MacroError> {
    let mut wb = ncsheet::workbook::Workbook::with_sheet();
    let classes = classes.iter().map(|(n, s)| (n.to_string(), s.to_string())).collect();
    let options = ncsheet::vba::RunOptions { classes, ..ncsheet::vba::RunOptions::default() };
    ncsheet::vba::run(&mut wb, main, "Module1.bas", &options)
}
