//! Shared by the xlsx tests: walking the Excel corpus and judging formula results against
//! reference values (Excel's cached ones, or LibreOffice's).

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use ncsheet::eval::functions::{as_lambda, bound_names};
use ncsheet::eval::functions::{find, spec, Outside};
use ncsheet::eval::{Env, Value};
use ncsheet::formula::address::{Pos, Rect};
use ncsheet::formula::ast::{Expr, ExprKind, Reference, SheetId, UnaryOp};
use ncsheet::formula::parse::strip_future_prefix;
use ncsheet::io::xlsx::{CachedValue, Imported};
use ncsheet::workbook::Workbook;

/// The corpus, which these tests always need (see `corpus::root` for the tests that may
/// skip without it).
pub fn corpus_root() -> PathBuf {
    super::corpus::path()
}

pub fn workbooks(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            workbooks(&p, out);
        } else if p.extension().is_some_and(|e| e == "xlsx" || e == "xlsm") {
            out.push(p);
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    Agree,
    Disagree,
    Upstream,
    Unsupported,
    Volatile,
    /// A formula ncsheet does not compute (it does not parse, or calls an add-in's
    /// function) whose cell keeps the value the file cached, as Excel shows it: neither
    /// computed nor compared. The cells reading it are judged as usual.
    Kept,
}

/// What a formula calls and reads.
pub struct FormulaInfo {
    /// Registered functions it calls (canonical names), or `(operators only)`.
    pub functions: Vec<String>,
    /// Unregistered functions it calls.
    pub unknown: Vec<String>,
    pub parses: bool,
    pub volatile: bool,
    pub reads: Vec<(SheetId, Rect)>,
    /// Uses the spill operator `A1#` (stored as `_xlfn.ANCHORARRAY`).
    pub spill_ref: bool,
    /// Uses `@` inside a function call (stored as `_xlfn.SINGLE`).
    pub at_in_call: bool,
}

/// Makes the public Functions of the workbook's VBA project callable from its cells, as the
/// command line does when it opens an .xlsm (`cli/macros.rs`).
pub fn install_workbook_functions(imported: &mut Imported) {
    let Some(bytes) = imported.layout.vba_project.as_ref() else { return };
    let project = ncsheet::vba::project::read_project(bytes).expect("the VBA project reads");
    ncsheet::vba::install_functions(&mut imported.workbook, &project, ncsheet::vba::RunOptions::default());
}

pub fn analyse(wb: &Workbook, sheet: SheetId, anchor: Pos) -> FormulaInfo {
    let mut info = FormulaInfo {
        functions: Vec::new(),
        unknown: Vec::new(),
        parses: false,
        volatile: false,
        reads: Vec::new(),
        spill_ref: false,
        at_in_call: false,
    };
    let Some(expr) = wb.formula_tree(sheet, anchor) else { return info };
    info.parses = true;
    let mut names = Vec::new();
    let mut called = Vec::new();
    expr.visit(&mut |e| match &e.kind {
        ExprKind::Call(id, _) => info.functions.push(spec(*id).name.to_string()),
        ExprKind::UnknownCall(name, _) => called.push(name.clone()),
        ExprKind::Ref(r) => info.reads.extend(resolve(r, sheet, anchor)),
        ExprKind::Name(n) => names.push(n.clone()),
        _ => {}
    });
    // A call of a LAMBDA the formula binds (LET) or a defined name holds is no unknown
    // function: the defined LAMBDA's body counts as part of the formula.
    let bound = bound_names(&expr);
    for name in called {
        if bound.iter().any(|b| b.eq_ignore_ascii_case(&name)) {
            continue;
        }
        if wb.has_user_function(&name) {
            // The workbook's own (VBA) function: it runs, so its value is compared, unless
            // it is volatile (`Application.Volatile`).
            info.volatile |= wb.calls_volatile(sheet, anchor);
            continue;
        }
        match Env::defined_name(wb, &name, sheet) {
            Some((body, _)) if as_lambda(&body).is_some() => body.visit(&mut |e| match &e.kind {
                ExprKind::Call(id, _) => info.functions.push(spec(*id).name.to_string()),
                ExprKind::UnknownCall(inner, _) if !bound_names(&body).contains(inner) => {
                    info.unknown.push(strip_future_prefix(inner).to_string())
                }
                ExprKind::Name(n) => names.push(n.clone()),
                _ => {}
            }),
            _ => info.unknown.push(strip_future_prefix(&name).to_string()),
        }
    }
    spill_reads(wb, &expr, sheet, anchor, &mut info.reads);
    expr.visit(&mut |e| match &e.kind {
        ExprKind::Unary(UnaryOp::Spill, _) => info.spill_ref = true,
        ExprKind::Call(_, args) | ExprKind::UnknownCall(_, args) => args
            .iter()
            .for_each(|a| a.visit(&mut |x| info.at_in_call |= matches!(x.kind, ExprKind::Unary(UnaryOp::Implicit, _)))),
        _ => {}
    });
    for n in names {
        if let Some((name_expr, name_sheet)) = Env::defined_name(wb, &n, sheet) {
            name_expr.visit_refs(&mut |r| info.reads.extend(resolve(r, name_sheet, Pos::new(0, 0))));
        }
    }
    // With the clock fixed (the workbook's settings), NOW and TODAY give the saved time again.
    let fixed_clock = wb.settings().clock.is_some();
    info.volatile = info.functions.iter().filter_map(|f| find(f)).any(|id| match spec(id).reads {
        Outside::Nothing => false,
        Outside::Clock => !fixed_clock,
        Outside::Chance | Outside::Host => true,
    });
    info.functions.sort();
    info.functions.dedup();
    if info.functions.is_empty() {
        info.functions.push("(operators only)".into());
    }
    info
}

/// `A1#` reads the whole area the anchor spilled into.
fn spill_reads(wb: &Workbook, expr: &Expr, sheet: SheetId, at: Pos, reads: &mut Vec<(SheetId, Rect)>) {
    expr.visit(&mut |e| {
        if let ExprKind::Unary(UnaryOp::Spill, inner) = &e.kind {
            if let Some((s, rect)) = match &inner.kind {
                ExprKind::Ref(r) => resolve(r, sheet, at),
                _ => None,
            } {
                reads.push((s, Env::spill_rect(wb, s, rect.first).unwrap_or(rect)));
            }
        }
    });
}

fn resolve(r: &Reference, sheet: SheetId, at: Pos) -> Option<(SheetId, Rect)> {
    r.resolve(sheet, at)
}

/// Cells by sheet, for "does this rectangle hold one of them".
#[derive(Default)]
struct CellSet {
    cells: HashSet<(SheetId, Pos)>,
    by_sheet: HashMap<SheetId, Vec<Pos>>,
}

impl CellSet {
    fn insert(&mut self, sheet: SheetId, pos: Pos) -> bool {
        let new = self.cells.insert((sheet, pos));
        if new {
            self.by_sheet.entry(sheet).or_default().push(pos);
        }
        new
    }

    fn hits(&self, sheet: SheetId, rect: Rect, except: (SheetId, Pos)) -> bool {
        let area = rect.rows() as u64 * rect.cols() as u64;
        let list = self.by_sheet.get(&sheet).map_or(&[][..], Vec::as_slice);
        if area <= list.len() as u64 {
            (rect.first.row..=rect.last.row).any(|r| {
                (rect.first.col..=rect.last.col)
                    .any(|c| (sheet, Pos::new(r, c)) != except && self.cells.contains(&(sheet, Pos::new(r, c))))
            })
        } else {
            list.iter().any(|&p| rect.contains(p) && (sheet, p) != except)
        }
    }
}

pub struct CellResult {
    pub sheet: SheetId,
    pub pos: Pos,
    pub anchor: Pos,
    pub verdict: Verdict,
    /// The reference value the cell was judged against.
    pub expected: Option<Value>,
}

/// Judges the formula results of one workbook against a reference: `expected` gives the
/// value a cell should have (`None`: nothing to compare); `excluded` says which formulas
/// count as unsupported besides those calling a function missing from our table; `agree`
/// compares the reference value with ours.
pub fn judge(
    imported: &Imported,
    expected: &dyn Fn(&CachedValue) -> Option<Value>,
    excluded: &dyn Fn(&FormulaInfo) -> bool,
    agree: &dyn Fn(&Value, &Value) -> bool,
) -> (Vec<CellResult>, HashMap<(SheetId, Pos), FormulaInfo>) {
    let wb = &imported.workbook;
    let mut infos: HashMap<(SheetId, Pos), FormulaInfo> = HashMap::new();
    for c in &imported.cached {
        infos.entry((c.sheet, c.anchor)).or_insert_with(|| analyse(wb, c.sheet, c.anchor));
    }
    // Unsupported and volatile cells, then everything that reads them.
    let mut tainted = CellSet::default();
    let mut volatile = HashSet::new();
    // An array formula's other cells are not kept (they show no value of the file's).
    let kept = |c: &CachedValue| c.pos == c.anchor && wb.keeps_file_value(c.sheet, c.pos);
    let expectations: Vec<Option<Value>> = imported.cached.iter().map(expected).collect();
    for (c, want) in imported.cached.iter().zip(&expectations) {
        let info = &infos[&(c.sheet, c.anchor)];
        if kept(c) {
            continue;
        }
        // A call of a name Excel did not know either (it cached #NAME? for it): no function
        // ncsheet lacks, and the cell is compared (its #NAME? is Excel's).
        let lacking = !info.unknown.is_empty() && *want != Some(Value::Error(ncsheet::eval::XlError::Name));
        if !info.parses || lacking || info.volatile || excluded(info) {
            tainted.insert(c.sheet, c.pos);
            if info.volatile {
                volatile.insert((c.sheet, c.pos));
            }
        }
    }
    loop {
        let mut grew = false;
        for c in &imported.cached {
            if tainted.cells.contains(&(c.sheet, c.pos)) {
                continue;
            }
            let info = &infos[&(c.sheet, c.anchor)];
            let reads_tainted = info.reads.iter().any(|&(s, r)| tainted.hits(s, r, (c.sheet, c.anchor)))
                || tainted.cells.contains(&(c.sheet, c.anchor));
            if reads_tainted {
                let from_volatile = info
                    .reads
                    .iter()
                    .any(|&(s, r)| volatile.iter().any(|&(vs, vp): &(SheetId, Pos)| vs == s && r.contains(vp)));
                if from_volatile {
                    volatile.insert((c.sheet, c.pos));
                }
                grew |= tainted.insert(c.sheet, c.pos);
            }
        }
        if !grew {
            break;
        }
    }
    let mut wrong = CellSet::default();
    for (c, want) in imported.cached.iter().zip(&expectations) {
        if want.as_ref().is_some_and(|w| !agree(w, &wb.value(c.sheet, c.pos))) {
            wrong.insert(c.sheet, c.pos);
        }
    }
    let results = imported
        .cached
        .iter()
        .zip(expectations)
        .filter(|(_, want)| want.is_some())
        .map(|(c, want)| {
            let key = (c.sheet, c.pos);
            let info = &infos[&(c.sheet, c.anchor)];
            let verdict = if kept(c) {
                Verdict::Kept
            } else if volatile.contains(&key) {
                Verdict::Volatile
            } else if tainted.cells.contains(&key) {
                Verdict::Unsupported
            } else if !wrong.cells.contains(&key) {
                Verdict::Agree
            } else if info.reads.iter().any(|&(s, r)| wrong.hits(s, r, (c.sheet, c.anchor)))
                || (c.anchor != c.pos && wrong.cells.contains(&(c.sheet, c.anchor)))
            {
                Verdict::Upstream
            } else {
                Verdict::Disagree
            };
            CellResult { sheet: c.sheet, pos: c.pos, anchor: c.anchor, verdict, expected: want }
        })
        .collect();
    (results, infos)
}

#[derive(Default, Clone, Copy)]
pub struct Tally {
    pub agree: usize,
    pub disagree: usize,
    pub upstream: usize,
    pub unsupported: usize,
    pub volatile: usize,
    pub kept: usize,
}

impl Tally {
    pub fn add(&mut self, v: Verdict) {
        match v {
            Verdict::Agree => self.agree += 1,
            Verdict::Disagree => self.disagree += 1,
            Verdict::Upstream => self.upstream += 1,
            Verdict::Unsupported => self.unsupported += 1,
            Verdict::Volatile => self.volatile += 1,
            Verdict::Kept => self.kept += 1,
        }
    }

    pub fn add_all(&mut self, other: &Tally) {
        self.agree += other.agree;
        self.disagree += other.disagree;
        self.upstream += other.upstream;
        self.unsupported += other.unsupported;
        self.volatile += other.volatile;
        self.kept += other.kept;
    }

    pub fn compared(&self) -> usize {
        self.agree + self.disagree + self.upstream
    }

    pub fn all(&self) -> usize {
        self.compared() + self.unsupported + self.volatile + self.kept
    }
}

pub fn percent(part: usize, whole: usize) -> String {
    if whole == 0 {
        "–".into()
    } else {
        format!("{:.1}%", 100.0 * part as f64 / whole as f64)
    }
}

/// LibreOffice's `soffice`, or `None` on a machine without it. On CI (`CI` set) it must be
/// there: `.ci/run` installs it, and a test that skipped there would pass with no oracle.
pub fn soffice() -> Option<PathBuf> {
    let candidates = [
        "/usr/bin/soffice",
        "/usr/local/bin/soffice",
        "/usr/lib/libreoffice/program/soffice",
        "/opt/libreoffice/program/soffice",
    ];
    let found = candidates.iter().map(PathBuf::from).find(|p| p.exists());
    assert!(found.is_some() || std::env::var_os("CI").is_none(), "LibreOffice (soffice) is missing on CI");
    found
}

/// A LibreOffice profile that recalculates every xlsx on load (by default it trusts the
/// cached values, which would make this test compare our numbers with themselves).
pub fn recalculating_profile(dir: &Path) -> String {
    let user = dir.join("user");
    std::fs::create_dir_all(&user).unwrap();
    let settings = r#"<?xml version="1.0" encoding="UTF-8"?>
<oor:items xmlns:oor="http://openoffice.org/2001/registry" xmlns:xs="http://www.w3.org/2001/XMLSchema" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
<item oor:path="/org.openoffice.Office.Calc/Formula/Load"><prop oor:name="OOXMLRecalcMode" oor:op="fuse"><value>0</value></prop></item>
<item oor:path="/org.openoffice.Office.Calc/Formula/Load"><prop oor:name="ODFRecalcMode" oor:op="fuse"><value>0</value></prop></item>
</oor:items>
"#;
    std::fs::write(user.join("registrymodifications.xcu"), settings).unwrap();
    format!("-env:UserInstallation=file://{}", dir.display())
}

/// `file` as LibreOffice saves it after opening and recalculating it (in `dir/lo`, a profile
/// in `dir/profile`); `None` on a machine without LibreOffice (never on CI: [`soffice`]).
pub fn libreoffice_recalculated(file: &Path, dir: &Path) -> Option<PathBuf> {
    let soffice = soffice()?;
    let profile = recalculating_profile(&dir.join("profile"));
    let out = dir.join("lo");
    libreoffice_convert(&soffice, &profile, &[file.to_path_buf()], &out);
    Some(out.join(file.file_name().expect("file name")).with_extension("xlsx"))
}

/// Converts `inputs` to xlsx in `out` with LibreOffice: in batches (one process each), and
/// once more for the files a batch left out (LibreOffice sometimes dies under load).
pub fn libreoffice_convert(soffice: &Path, profile: &str, inputs: &[PathBuf], out: &Path) {
    libreoffice_convert_to(soffice, profile, inputs, out, "xlsx");
}

/// [`libreoffice_convert`] to another format (`ods`: the VBA modules LibreOffice imported
/// are kept as Basic modules).
pub fn libreoffice_convert_to(soffice: &Path, profile: &str, inputs: &[PathBuf], out: &Path, format: &str) {
    for batch in inputs.chunks(40) {
        run_soffice(soffice, profile, batch, out, format);
    }
    let missing: Vec<PathBuf> = inputs
        .iter()
        .filter(|p| !out.join(p.file_name().expect("file name")).with_extension(format).exists())
        .cloned()
        .collect();
    for batch in missing.chunks(10) {
        run_soffice(soffice, profile, batch, out, format);
    }
}

fn run_soffice(soffice: &Path, profile: &str, inputs: &[PathBuf], out: &Path, format: &str) {
    let mut child = Command::new(soffice)
        .arg(profile)
        .args(["--headless", "--norestore", "--convert-to", format, "--outdir"])
        .arg(out)
        .args(inputs)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start soffice");
    let start = Instant::now();
    loop {
        if child.try_wait().expect("wait for soffice").is_some() {
            return;
        }
        if start.elapsed() > Duration::from_secs(600) {
            let _ = child.kill();
            let _ = child.wait();
            return;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// An xlsx package rewritten part by part: `change(name, bytes)` gives each part's new bytes,
/// stored with `options` (uncompressed, so that byte mutations reach the XML, or deflated).
/// The writer is returned open, for parts to add.
pub fn rewrite_package(
    package: &[u8],
    options: zip::write::SimpleFileOptions,
    change: &mut dyn FnMut(&str, Vec<u8>) -> Vec<u8>,
) -> zip::ZipWriter<std::io::Cursor<Vec<u8>>> {
    use std::io::{Read, Write};
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(package)).unwrap();
    let mut out = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    for i in 0..zip.len() {
        let mut entry = zip.by_index(i).unwrap();
        let name = entry.name().unwrap().to_string();
        let mut data = Vec::new();
        entry.read_to_end(&mut data).unwrap();
        out.start_file(name.as_str(), options).unwrap();
        out.write_all(&change(&name, data)).unwrap();
    }
    out
}

/// The corpus's per-file tolerance (its README): a number in `METADATA!A1`, for files whose
/// functions Excel computes by approximations (BESSEL.xlsx: 1e-5).
pub fn metadata_tolerance(wb: &Workbook) -> Option<f64> {
    let sheet = wb.sheet_names().iter().position(|n| n.eq_ignore_ascii_case("METADATA"))?;
    match wb.value(sheet as _, Pos::new(0, 0)) {
        Value::Number(eps) => Some(eps),
        _ => None,
    }
}

/// The corpus's `numbers_are_close(x, y, eps)`: |x−y| < eps, or relative to √(x²+y²).
pub fn close_within(excel: &Value, ours: &Value, eps: Option<f64>) -> bool {
    let (Some(eps), Value::Number(x), Value::Number(y)) = (eps, excel, ours) else { return false };
    let d = (x - y).abs();
    d < eps || d / x.hypot(*y) < eps
}
