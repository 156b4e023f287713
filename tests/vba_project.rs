//! The VBA projects stored in Excel-saved .xlsm files, read by ncsheet and by olevba
//! (oletools, installed by `.ci/run`): every module's source must be the same text.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use common::vba::{olevba, with_stream, xlsm_with_project};

use ncsheet::vba::project::{read_project, ModuleKind};

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
/// writes, and the chamfer cut goes from T1 to T2 of docs/domain.md §1's table (outer, α = 45°).
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
    assert_cuts_the_first_chamfer(&program);
}

/// rs274 reads `program` as the cut of docs/domain.md §1's first row (outer, D 40, f 2, α 45°,
/// r 0.8, eA = eB = 1): a feed to T1, then along the chamfer to T2.
fn assert_cuts_the_first_chamfer(program: &Path) {
    if !common::rs274::available() {
        return;
    }
    let moves = common::rs274::moves(program).unwrap_or_else(|e| panic!("{}: {e}", program.display()));
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
    assert!(matches!((t1, t2), (Some(a), Some(b)) if b == a + 1), "{}: {feeds:?}", program.display());
}

fn chamfer_bas() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("sheets/chamfer.bas")
}

/// The .bas file's text as VBA stores it (CRLF line ends).
fn chamfer_text() -> String {
    std::fs::read_to_string(chamfer_bas()).unwrap().replace("\r\n", "\n").replace('\n', "\r\n")
}

/// The Excel-saved workbooks of the public corpus that have a VBA project.
fn xlsm_with_projects() -> Vec<PathBuf> {
    let files: Vec<PathBuf> = xlsm_files()
        .into_iter()
        .filter(|f| ncsheet::io::open(f).unwrap_or_else(|e| panic!("{e}")).layout.unwrap().vba_project.is_some())
        .collect();
    assert!(files.len() >= 10, "only {} .xlsm files with a VBA project", files.len());
    files
}

/// `ncsheet macros FILE --import chamfer.bas -o OUT`, which must succeed (--unprotect: one
/// of the projects has a password; tests/vba2.rs checks the refusal without it).
fn import_chamfer(file: &Path, out: &Path) {
    let run = common::cli::ncsheet(&[
        "macros",
        file.to_str().unwrap(),
        "--import",
        chamfer_bas().to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--unprotect",
    ]);
    assert_eq!(run.code, 0, "{}: {}", file.display(), run.stderr);
}

/// Every part of an xlsx package by name, decompressed.
fn parts(file: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut zip = zip::ZipArchive::new(std::fs::File::open(file).unwrap()).unwrap();
    (0..zip.len())
        .map(|i| {
            let mut entry = zip.by_index(i).unwrap();
            let mut data = Vec::new();
            std::io::Read::read_to_end(&mut entry, &mut data).unwrap();
            (entry.name().unwrap().to_string(), data)
        })
        .collect()
}

fn vba_project_of(file: &Path) -> ncsheet::vba::project::VbaProject {
    let bytes = ncsheet::io::open(file).unwrap().layout.unwrap().vba_project.unwrap();
    read_project(&bytes).unwrap_or_else(|e| panic!("{}: {e}", file.display()))
}

/// The chamfer macro imported into each Excel-saved project: olevba reads every old module
/// with the same text as in the original and the new one with the .bas file's; ncsheet reads
/// the same; every other part of the package is the original's; the original is untouched;
/// and the macro runs from the new file (its inputs typed into B2:B7 of the first sheet, the
/// fixed layout chamfer.bas reads) to the program rs274 reads as docs/domain.md §1's first cut.
#[test]
fn chamfer_imports_into_every_excel_project_keeping_its_modules() {
    let dir = tempfile::tempdir().unwrap();
    let want = chamfer_text();
    for (i, file) in xlsm_with_projects().iter().enumerate() {
        let before = std::fs::read(file).unwrap();
        let out = dir.path().join(format!("out{i}.xlsm"));
        import_chamfer(file, &out);
        assert!(std::fs::read(file).unwrap() == before, "{}: the input changed", file.display());

        let (old, new) = (vba_project_of(file), vba_project_of(&out));
        assert_eq!(new.modules.len(), old.modules.len() + 1, "{}", file.display());
        for (a, b) in old.modules.iter().zip(&new.modules) {
            assert_eq!((&a.name, a.kind), (&b.name, b.kind), "{}", file.display());
            assert!(a.source == b.source, "{}: {} reads back another text", file.display(), a.name);
        }
        let chamfer = new.modules.last().unwrap();
        assert_eq!((chamfer.name.as_str(), chamfer.kind), ("Chamfer", ModuleKind::Standard));
        assert!(chamfer.source == want, "{}: Chamfer reads back another text", file.display());

        let (mut old_parts, mut new_parts) = (parts(file), parts(&out));
        assert!(old_parts.remove("xl/vbaProject.bin").is_some() && new_parts.remove("xl/vbaProject.bin").is_some());
        assert!(old_parts == new_parts, "{}: other parts of the package changed", file.display());

        if let (Some(mut theirs), Some(original)) = (olevba(&out), olevba(file)) {
            assert!(
                theirs.remove("VBA/Chamfer").is_some_and(|t| t == want),
                "{}: olevba reads Chamfer",
                file.display()
            );
            assert!(theirs == original, "{}: olevba reads the old modules differently", file.display());
        }

        let ready = dir.path().join(format!("ready{i}.xlsm"));
        let typed = common::cli::ncsheet(&[
            "set",
            out.to_str().unwrap(),
            "B2=40",
            "B3=2",
            "B4=45",
            "B5=0.8",
            "B6=1",
            "B7=1",
            "-o",
            ready.to_str().unwrap(),
        ]);
        assert_eq!(typed.code, 0, "{}: {}", file.display(), typed.stderr);
        let program = dir.path().join(format!("chamfer{i}.ngc"));
        let ran = common::cli::ncsheet(&[
            "run",
            ready.to_str().unwrap(),
            "--sub",
            "Chamfer.Main",
            "--dialect",
            "linuxcnc",
            "-o",
            program.to_str().unwrap(),
        ]);
        assert_eq!(ran.code, 0, "{}: {}", file.display(), ran.stderr);
        // docs/domain.md §1's first row, as the macro prints it.
        assert!(ran.stderr.contains("XA=44.263 ZA=-4.600 XB=33.063 ZB=1.000"), "{}: {}", file.display(), ran.stderr);
        assert_cuts_the_first_chamfer(&program);
    }
}

/// LibreOffice opens each workbook with the imported macro and finds its modules: the old
/// ones with their kinds and the new one a normal module holding the macro's procedures (its
/// VBA import, kept as Basic modules in an .ods).
#[test]
fn libreoffice_lists_the_imported_module() {
    let Some(soffice) = common::soffice() else {
        eprintln!("skipped: LibreOffice (soffice) is not installed");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let files = xlsm_with_projects();
    let outs: Vec<PathBuf> = (0..files.len()).map(|i| dir.path().join(format!("out{i}.xlsm"))).collect();
    for (file, out) in files.iter().zip(&outs) {
        import_chamfer(file, out);
    }
    let converted = dir.path().join("ods");
    let profile = format!("-env:UserInstallation=file://{}", dir.path().join("profile").display());
    common::libreoffice_convert_to(&soffice, &profile, &outs, &converted, "ods");
    for (file, out) in files.iter().zip(&outs) {
        let ods = converted.join(out.file_name().unwrap()).with_extension("ods");
        assert!(ods.exists(), "LibreOffice did not open {} (from {})", out.display(), file.display());
        let basic: BTreeMap<String, Vec<u8>> =
            parts(&ods).into_iter().filter(|(name, _)| name.starts_with("Basic/VBAProject/")).collect();
        let module_type = |name: &str| -> Option<String> {
            let xml = String::from_utf8_lossy(basic.get(&format!("Basic/VBAProject/{name}.xml"))?).into_owned();
            let at = xml.find("script:moduleType=\"")? + "script:moduleType=\"".len();
            Some(xml[at..].split('"').next()?.to_string())
        };
        let listed = String::from_utf8_lossy(basic.get("Basic/VBAProject/script-lb.xml").map_or(&[][..], |b| b));
        let project = vba_project_of(file);
        for m in project.modules.iter().map(|m| (m.name.as_str(), m.kind)).chain([("Chamfer", ModuleKind::Standard)]) {
            let (name, kind) = m;
            assert!(
                listed.contains(&format!("library:name=\"{name}\"")),
                "{}: {name} not listed: {listed}",
                file.display()
            );
            let lo = module_type(name);
            let normal = lo.as_deref() == Some("normal");
            assert_eq!(normal, kind == ModuleKind::Standard, "{}: {name} is {lo:?} in LibreOffice", file.display());
        }
        let chamfer = String::from_utf8_lossy(&basic["Basic/VBAProject/Chamfer.xml"]).into_owned();
        assert!(chamfer.contains("Sub OuterChamfer(") && chamfer.contains("Function Place("), "{}", file.display());
    }
}

/// What a test does to a stream's bytes.
type Damage = dyn Fn(&[u8]) -> Vec<u8>;

/// Each stream that holds the project (dir, PROJECT, a module) cut to half its length or
/// overwritten: reading the project, listing its macros and importing into it are errors
/// that name the stream, and the import writes nothing.
#[test]
fn a_cut_or_damaged_stream_is_an_error_naming_it_for_reading_and_import() {
    let file = xlsm_files().into_iter().find(|f| f.to_string_lossy().contains("SimpleMacro")).unwrap();
    let bytes = ncsheet::io::open(&file).unwrap().layout.unwrap().vba_project.unwrap();
    let cut = |s: &[u8]| s[..s.len() / 2].to_vec();
    let garbage = |s: &[u8]| vec![0xFF; s.len()];
    let without_module_line = |s: &[u8]| String::from_utf8_lossy(s).replace("Module=Module1\r\n", "").into_bytes();
    let cases: [(&str, &Damage); 7] = [
        ("/VBA/dir", &cut),
        ("/VBA/dir", &garbage),
        ("/PROJECT", &cut),
        ("/PROJECT", &garbage),
        ("/PROJECT", &without_module_line),
        ("/VBA/Module1", &cut),
        ("/VBA/Module1", &garbage),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (n, (stream, change)) in cases.iter().enumerate() {
        let broken = with_stream(&bytes, stream, change);
        let e = read_project(&broken).unwrap_err();
        assert_eq!(e.stream, *stream, "case {n}: {e}");

        let book = dir.path().join(format!("broken{n}.xlsm"));
        xlsm_with_project(&file, &broken, &book);
        let listed = common::cli::ncsheet(&["macros", book.to_str().unwrap()]);
        assert!(listed.code != 0 && listed.stderr.contains(&format!("{stream}: ")), "case {n}: {}", listed.stderr);
        let out = dir.path().join(format!("out{n}.xlsm"));
        let import = common::cli::ncsheet(&[
            "macros",
            book.to_str().unwrap(),
            "--import",
            chamfer_bas().to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(import.code != 0 && import.stderr.contains(&format!("{stream}: ")), "case {n}: {}", import.stderr);
        assert!(!out.exists(), "case {n}: the import wrote {}", out.display());
    }
}

/// A module name the project has is refused, and replaced only with --replace; a document
/// module is never replaced by a .bas.
#[test]
fn an_existing_module_name_is_refused_unless_replaced() {
    let file = xlsm_files().into_iter().find(|f| f.to_string_lossy().contains("SimpleMacro")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let bas = dir.path().join("Module1.bas");
    std::fs::write(
        &bas,
        "Attribute VB_Name = \"Module1\"\r\nSub Hello()\r\n    Range(\"A1\").Value = 1\r\nEnd Sub\r\n",
    )
    .unwrap();
    let out = dir.path().join("out.xlsm");
    let args = ["macros", file.to_str().unwrap(), "--import", bas.to_str().unwrap(), "-o", out.to_str().unwrap()];
    let refused = common::cli::ncsheet(&args);
    assert!(refused.code != 0 && refused.stderr.contains("already has a module Module1"), "{}", refused.stderr);
    assert!(!out.exists());
    let replaced = common::cli::ncsheet(&[&args[..], &["--replace"]].concat());
    assert_eq!(replaced.code, 0, "{}", replaced.stderr);
    let (old, new) = (vba_project_of(&file), vba_project_of(&out));
    let names = |p: &ncsheet::vba::project::VbaProject| p.modules.iter().map(|m| m.name.clone()).collect::<Vec<_>>();
    assert_eq!(names(&old), names(&new));
    let module1 = new.modules.iter().find(|m| m.name == "Module1").unwrap();
    assert_eq!(module1.source, std::fs::read_to_string(&bas).unwrap());
    if let Some(theirs) = olevba(&out) {
        assert_eq!(theirs["VBA/Module1"], module1.source);
    }
    let document = dir.path().join("ThisWorkbook.bas");
    std::fs::write(&document, "Sub Hello()\r\nEnd Sub\r\n").unwrap();
    let doc_args = [
        "macros",
        file.to_str().unwrap(),
        "--import",
        document.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--replace",
        "--force",
    ];
    let refused = common::cli::ncsheet(&doc_args);
    assert!(refused.code != 0 && refused.stderr.contains("document or class"), "{}", refused.stderr);
}

/// The dir stream ([MS-OVBA] 2.3.4.2) may list any number of modules, each naming its stream
/// and where its compressed source starts (MODULEOFFSET). Each module's stream was read whole
/// again: 6,000 modules naming one 8 MiB stream copied 48 GB and ran for seconds, ten times
/// as many for minutes. A stream is read once, however many modules name it.
#[test]
fn many_modules_naming_one_large_stream_read_it_once() {
    const MODULE_OFFSET: u16 = 0x0031;
    let pad = 8u32 << 20;
    let xlsm = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/excel-corpus/public/poi/test-data_spreadsheet_SimpleMacro.xlsm");
    let good = vba_project_of_bytes(&xlsm);
    let mut cfb = cfb::CompoundFile::open(std::io::Cursor::new(good.clone())).unwrap();
    let mut packed = Vec::new();
    std::io::Read::read_to_end(&mut cfb.open_stream("/VBA/dir").unwrap(), &mut packed).unwrap();
    let dir = ncsheet::vba::ovba::decompress(&packed).unwrap();
    // The records of the dir stream: id, size, data (PROJECTVERSION's size says 4, 6 follow).
    let mut at = 0;
    let mut records = Vec::new();
    while at + 6 <= dir.len() {
        let id = u16::from_le_bytes([dir[at], dir[at + 1]]);
        let size = if id == 0x0009 { 6 } else { u32::from_le_bytes(dir[at + 2..at + 6].try_into().unwrap()) as usize };
        records.push((id, at, at + 6 + size));
        at += 6 + size;
    }
    let start = records.iter().find(|r| r.0 == 0x0019).unwrap().1;
    let end = records.iter().find(|r| r.0 == 0x002B).unwrap().2;
    let stream =
        String::from_utf8(records.iter().find(|r| r.0 == 0x001A).map(|r| dir[r.1 + 6..r.2].to_vec()).unwrap()).unwrap();
    let mut block = dir[start..end].to_vec();
    for (id, from, _) in records.iter().filter(|r| (start..end).contains(&r.1)) {
        if *id == MODULE_OFFSET {
            let at = from - start + 6;
            let offset = u32::from_le_bytes(block[at..at + 4].try_into().unwrap()) + pad;
            block[at..at + 4].copy_from_slice(&offset.to_le_bytes());
        }
    }
    let mut hostile = dir[..start].to_vec();
    (0..6_000).for_each(|_| hostile.extend_from_slice(&block));
    hostile.extend_from_slice(&dir[end..]);
    let packed = ncsheet::vba::ovba::compress(&hostile).unwrap();
    let project = with_stream(&good, "/VBA/dir", |_| packed.clone());
    let project =
        with_stream(&project, &format!("/VBA/{stream}"), |old| [vec![0; pad as usize], old.to_vec()].concat());
    // Counted, not timed (a clock fails on a busy machine and passes a slow reader on a fast
    // one): the hostile project reads the streams the good one reads, each once.
    let streams_read = |bytes: &[u8]| {
        let before = ncsheet::vba::project::streams_read_on_this_thread();
        let read = read_project(bytes);
        (read, ncsheet::vba::project::streams_read_on_this_thread() - before)
    };
    let (_, good_reads) = streams_read(&good);
    let (read, hostile_reads) = streams_read(&project);
    match read {
        Ok(read) => assert!(read.modules.len() > 1, "the modules are read"),
        Err(e) => assert!(e.to_string().starts_with("/VBA/") || e.to_string().starts_with("PROJECT"), "{e}"),
    }
    assert_eq!(hostile_reads, good_reads, "streams read for 6,000 modules naming one stream");
}

fn vba_project_of_bytes(xlsm: &Path) -> Vec<u8> {
    let mut zip = zip::ZipArchive::new(std::fs::File::open(xlsm).unwrap()).unwrap();
    let mut bytes = Vec::new();
    std::io::Read::read_to_end(&mut zip.by_name("xl/vbaProject.bin").unwrap(), &mut bytes).unwrap();
    bytes
}

/// A module file without an `Attribute VB_Name` line (a snippet saved from a forum, a module
/// typed in an editor) is named by its file name, and where that is no VBA module name ("gcode
/// writer.bas", "2d.bas": a module name starts with a letter and has no space) or is taken, as
/// the VBA editor names a module it makes: Module1, Module2 …, the first free. Before, such a
/// file was refused. olevba reads the names back from the project's dir stream.
#[test]
fn module_files_without_a_name_are_named_as_the_editor_names_new_modules() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        path.to_str().unwrap().to_string()
    };
    let spaced = write("gcode writer.bas", "Sub WriteIt()\r\n    Range(\"A1\").Value = 1\r\nEnd Sub\r\n");
    let digit = write("2d.bas", "Function Twice(x)\r\n    Twice = 2 * x\r\nEnd Function\r\n");
    let plain = write("Helpers.bas", "Function Half(x)\r\n    Half = x / 2\r\nEnd Function\r\n");
    let out = dir.path().join("named.xlsm");
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("sheets/chamfer.xlsx");
    let args = ["macros", source.to_str().unwrap(), "--import", &spaced, "--import", &digit, "--import", &plain];
    let run = common::cli::ncsheet(&[&args[..], &["-o", out.to_str().unwrap()]].concat());
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stderr.contains("gcode writer.bas: no Attribute VB_Name line") && run.stderr.contains("read as Module1")
    );
    let project = read_project(&ncsheet::io::open(&out).unwrap().layout.unwrap().vba_project.unwrap()).unwrap();
    let names: Vec<&str> = project.modules.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names[names.len() - 3..], ["Module1", "Module2", "Helpers"]);
    if let Some(theirs) = olevba(&out) {
        for name in ["VBA/Module1", "VBA/Module2", "VBA/Helpers"] {
            assert!(theirs.contains_key(name), "{name} not in {:?}", theirs.keys().collect::<Vec<_>>());
        }
    }
}
