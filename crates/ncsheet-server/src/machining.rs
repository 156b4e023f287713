//! The machining pane's data, all from the library: a chamfer's construction for a cell
//! calling CHAMFER* (`geometry::chamfer`), and a macro's NC program written in a dialect with
//! its backplot (`vba::run`, `nc::dialect`, `nc::read`, `nc::backplot`). The page only draws.

use std::path::{Path, PathBuf};

use serde_json::{json, Value as Json};

use super::workbench::{refused, Refused, Workbench};
use ncsheet::document::Document;
use ncsheet::eval::{Ctx, Value};
use ncsheet::formula::address::Pos;
use ncsheet::formula::ast::SheetId;
use ncsheet::geometry::chamfer::{chamfer as chamfer_geometry, ChamferKind, ChamferSpec};
use ncsheet::nc::backplot::{self, Plane};
use ncsheet::nc::{dialect, read, Block, Machine};
use ncsheet::vba::project::{decode_module_file, procedures};
use ncsheet::vba::{self, ModuleKind, RunOptions};

/// The code page of a .bas file beside a workbook without a VBA project (the VBA editor's
/// export in Western Europe).
const BAS_CODE_PAGE: u16 = 1252;

/// A run from the page stops after this long: the page waits for it.
const RUN_SECONDS: f64 = 20.0;

/// The chamfer a cell's CHAMFER* call builds: the part's contour, the chamfer line A–B, the
/// nose circles at the start (T1) and end (T2) of the cut with their theoretical tips.
pub fn chamfer(doc: &Document, sheet: SheetId, pos: Pos) -> Result<Json, Refused> {
    let wb = doc.workbook();
    let cell = wb.cell_name(sheet, pos);
    let tree = wb.formula_tree(sheet, pos).ok_or_else(|| refused(format!("{cell} holds no formula")))?;
    let args =
        super::paths::call_of(&tree, "CHAMFER").ok_or_else(|| refused(format!("{cell} calls no CHAMFER function")))?;
    if args.len() != 7 {
        return Err(refused(format!("{cell}: CHAMFER takes 7 arguments")));
    }
    let values: Vec<Value> = args.iter().map(|a| Ctx::new(wb, sheet, pos).eval(a)).collect();
    let kind = ChamferKind::parse(&values[0].to_string()).map_err(|e| refused(format!("{cell}: {e}")))?;
    let mut n = [0.0; 6];
    for (i, v) in values[1..].iter().enumerate() {
        let Value::Number(x) = v else {
            return Err(refused(format!("{cell}: argument {} of CHAMFER is {v}, not a number", i + 2)));
        };
        n[i] = *x;
    }
    let spec = ChamferSpec::from_arguments(kind, n);
    let g = chamfer_geometry(&spec).map_err(|e| refused(format!("{cell}: {e}")))?;
    let point = |p: ncsheet::geometry::chamfer::ZxPoint| json!({ "z": p.x, "x": p.y });
    let points = g.points();
    Ok(json!({
        "cell": cell,
        "kind": values[0].to_string().to_ascii_lowercase(),
        "radius": spec.diameter / 2.0,
        "nose": spec.nose_radius,
        "a": point(g.a), "b": point(g.b),
        "centre1": point(g.centre1), "centre2": point(g.centre2),
        "tip1": point(g.tip1), "tip2": point(g.tip2),
        "xa": points.xa, "za": points.za, "xb": points.xb, "zb": points.zb,
    }))
}

/// The macros the page can run: the standard modules of the workbook's VBA project and the
/// .bas files found beside the workbook, each with its Subs; and the dialects.
pub fn macros(bench: &Workbench, bas_files: &[PathBuf]) -> Json {
    let mut sources = Vec::new();
    if let Some(Ok(project)) = bench.document().vba_project() {
        for m in project.modules.iter().filter(|m| m.kind == ModuleKind::Standard) {
            sources
                .push(json!({ "source": format!("module:{}", m.name), "label": m.name, "subs": sub_names(&m.source) }));
        }
    }
    for path in bas_files {
        let name = path.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
        let subs = read_bas(path).map(|s| sub_names(&s)).unwrap_or_default();
        sources.push(json!({ "source": format!("file:{name}"), "label": name, "subs": subs }));
    }
    json!({ "sources": sources, "dialects": dialects(), "machines": [machine_name(Machine::Lathe), machine_name(Machine::Mill)] })
}

/// Every dialect with the machines whose programs it writes, for the page's choice.
fn dialects() -> Vec<Json> {
    let machines = [Machine::Lathe, Machine::Mill];
    dialect::all()
        .into_iter()
        .map(|d| {
            let writes: Vec<&str> = machines.into_iter().filter(|&m| d.writes(m)).map(machine_name).collect();
            json!({ "name": d.name(), "machines": writes })
        })
        .collect()
}

/// The names of the Subs a module declares, which a run may start at.
fn sub_names(source: &str) -> Vec<String> {
    let name_of = |line: &String| {
        let mut words = line.split(|c: char| c.is_whitespace() || c == '(').filter(|w| !w.is_empty());
        let mut word = words.next()?;
        while ["public", "private", "friend", "static"].iter().any(|m| word.eq_ignore_ascii_case(m)) {
            word = words.next()?;
        }
        word.eq_ignore_ascii_case("sub").then(|| words.next().map(str::to_string)).flatten()
    };
    procedures(source).iter().filter_map(name_of).collect()
}

fn read_bas(path: &Path) -> Result<String, Refused> {
    let bytes = ncsheet::io::read_file(path).map_err(|e| refused(e.to_string()))?;
    decode_module_file(&bytes, BAS_CODE_PAGE)
        .map_err(|e| refused(format!("{}:{}:{}: {}", path.display(), e.line, e.column, e.message)))
}

/// Runs a macro on the workbook (its writes to cells stay, as in Excel) and answers with the
/// program in `dialect_name`, line by line, and its backplot drawn from the program as written.
/// What the page asks to run.
pub struct RunRequest {
    /// `module:NAME` or `file:NAME.bas`.
    pub source: String,
    /// The Sub to start at (empty: `Main`, or the first Sub without arguments).
    pub sub: String,
    pub dialect: String,
    /// The machine the program is for until the macro says `Nc.Machine`: `lathe` or `mill`.
    pub machine: String,
    /// The sheet `Range` and `Cells` mean before the macro activates another.
    pub sheet: SheetId,
}

pub fn run(bench: &mut Workbench, bas_files: &[PathBuf], request: &RunRequest) -> Result<Json, Refused> {
    let (source, sub, dialect_name) = (request.source.as_str(), request.sub.as_str(), request.dialect.as_str());
    let d = dialect::by_name(dialect_name)
        .ok_or_else(|| refused(format!("dialect {dialect_name}: one of {}", dialect::names().join(", "))))?;
    let chosen = machine_named(&request.machine)?;
    if !d.writes(chosen) {
        return Err(refused(format!("{} writes no {} programs", d.name(), request.machine)));
    }
    let (file, text) = macro_text(bench, bas_files, source)?;
    let mut options = run_options(bench.document(), sub, d, request.sheet);
    options.machine = chosen;
    let label = format!("macro {}", if sub.is_empty() { file.as_str() } else { sub });
    let out =
        bench.with_macro(&label, |wb| vba::run(wb, &text, &file, &options)).map_err(|e| refused(e.to_string()))?;
    let printed = out.printed.clone();
    if !out.program.blocks.iter().any(|b| !matches!(b, Block::Comment(_))) {
        return Ok(
            json!({ "lines": [], "printed": printed, "svg": "", "message": "the macro emitted no NC block (no move)" }),
        );
    }
    let program_text = d.render(&out.program).map_err(|e| refused(format!("{file}: {e}")))?;
    let machine = out.program.machine;
    let (read_back, line_of_block) = read::read_dialect(&program_text, d, Some(machine))
        .map_err(|e| refused(format!("the program as written does not read back: {e}")))?;
    let path = backplot::toolpath(&read_back).map_err(|e| refused(e.message))?;
    let title = format!("{file} ({})", d.name());
    let svg = backplot::svg_drawing(&path, Plane::for_machine(machine), &title).map_err(|e| refused(e.message))?;
    let moves: Vec<Json> = path
        .moves
        .iter()
        .map(|m| json!({ "block": m.block, "line": line_of_block.get(m.block.saturating_sub(1)), "from": m.from, "to": m.to, "rapid": m.kind == backplot::MoveKind::Rapid }))
        .collect();
    let lines: Vec<&str> = program_text.lines().collect();
    let download =
        format!("{}.{}", file.rsplit_once('.').map_or(file.as_str(), |(stem, _)| stem), program_extension(d.name()));
    Ok(json!({
        "lines": lines, "printed": printed, "svg": svg, "moves": moves, "machine": machine_name(machine),
        "program": program_text, "download": download,
    }))
}

/// The file extension a control's programs usually carry.
fn program_extension(dialect_name: &str) -> &'static str {
    match dialect_name {
        "linuxcnc" => "ngc",
        "sinumerik" => "mpf",
        "heidenhain" => "h",
        _ => "nc",
    }
}

fn machine_named(name: &str) -> Result<Machine, Refused> {
    match name {
        "lathe" => Ok(Machine::Lathe),
        "mill" => Ok(Machine::Mill),
        other => Err(refused(format!("machine {other}: lathe or mill"))),
    }
}

fn machine_name(machine: Machine) -> &'static str {
    match machine {
        Machine::Lathe => "lathe",
        Machine::Mill => "mill",
    }
}

/// The file name and text of `module:NAME` (the workbook's) or `file:NAME.bas` (beside it:
/// only the files the server was given, never a path from the request).
fn macro_text(bench: &Workbench, bas_files: &[PathBuf], source: &str) -> Result<(String, String), Refused> {
    if let Some(name) = source.strip_prefix("module:") {
        let project = bench.document().vba_project().ok_or_else(|| refused("the workbook holds no VBA project"))?;
        let project = project.map_err(|e| refused(e.to_string()))?;
        let module = project.modules.iter().find(|m| m.name == name && m.kind == ModuleKind::Standard);
        let module = module.ok_or_else(|| refused(format!("no standard module {name}")))?;
        return Ok((module.name.clone(), module.source.clone()));
    }
    if let Some(name) = source.strip_prefix("file:") {
        let path = bas_files.iter().find(|p| p.file_name().is_some_and(|f| f == name));
        let path = path.ok_or_else(|| refused(format!("{name} is no macro file beside the workbook")))?;
        return Ok((name.to_string(), read_bas(path)?));
    }
    Err(refused(format!("{source}: name a macro as module:NAME or file:NAME.bas")))
}

fn run_options(doc: &Document, sub: &str, dialect: &'static dyn dialect::Dialect, sheet: SheetId) -> RunOptions {
    let sheets = doc.layout().into_iter().flat_map(|l| &l.sheets);
    let code_names = sheets.clone().filter_map(|(name, s)| Some((s.code_name.clone()?, name.clone()))).collect();
    RunOptions {
        sub: (!sub.is_empty()).then(|| sub.to_string()),
        deadline: Some(vba::Deadline::after(RUN_SECONDS)),
        code_names,
        active_cells: sheets.filter_map(|(name, s)| Some((name.clone(), s.active_cell?))).collect(),
        sheet: doc.workbook().sheet_names().into_iter().nth(sheet as usize),
        dialect: Some(dialect),
        ..RunOptions::default()
    }
}
