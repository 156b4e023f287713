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
use ncsheet::geometry::chamfer::{chamfer as chamfer_geometry, ChamferGeometry, ChamferKind, ChamferSpec};
use ncsheet::nc::backplot::{self, Extras, Plane, Toolpath};
use ncsheet::nc::{dialect, read, Block, Machine, Program};
use ncsheet::vba::project::{decode_module_file, guessed_code_page, procedures};
use ncsheet::vba::{self, ModuleKind, RunOptions};

/// A run from the page stops after this long unless `--timeout` says otherwise: the page
/// waits for it.
pub const RUN_SECONDS: f64 = 20.0;

/// The chamfer a cell's CHAMFER* call builds: the part's contour, the chamfer line A–B, the
/// nose circles at the start (T1) and end (T2) of the cut with their theoretical tips.
pub fn chamfer(doc: &Document, sheet: SheetId, pos: Pos) -> Result<Json, Refused> {
    let wb = doc.workbook();
    let cell = wb.cell_name(sheet, pos);
    let (spec, values) = chamfer_call(doc, sheet, pos)?;
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

/// The chamfer a cell's CHAMFER* call asks for, with the values of its arguments.
fn chamfer_call(doc: &Document, sheet: SheetId, pos: Pos) -> Result<(ChamferSpec, Vec<Value>), Refused> {
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
    Ok((ChamferSpec::from_arguments(kind, n), values))
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
    // The file does not say which ANSI code page it is in: ASCII and UTF-8 read as they are,
    // other text in the code page its bytes are guessed to be in, else refused at its place
    // (`ncsheet run --code-page N` reads it).
    decode_module_file(&bytes, guessed_code_page(&bytes))
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
    /// How long the run may take: `--timeout`, else [`RUN_SECONDS`].
    pub seconds: f64,
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
    options.deadline = Some(vba::Deadline::after(request.seconds));
    options.machine = chosen;
    let label = format!("macro {}", if sub.is_empty() { file.as_str() } else { sub });
    let out =
        bench.with_macro(&label, |doc| doc.run_macro(&text, &file, options)).map_err(|e| refused(e.to_string()))?;
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
    let known = known_part(bench.document(), request.sheet, &read_back, &path);
    let svg = backplot::svg_drawing_with(&path, Plane::for_machine(machine), &title, &known.extras)
        .map_err(|e| refused(e.message))?;
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
        "program": program_text, "download": download, "part": known.json(),
    }))
}

/// The stock and part a program's backplot shows, and where they come from in words.
struct KnownPart {
    extras: Extras,
    /// Where the stock and part come from, or why none is known.
    said: String,
}

impl KnownPart {
    fn json(&self) -> Json {
        let point = |p: &[f64; 3]| json!([p[0], p[1], p[2]]);
        json!({
            "stock": self.extras.stock.map(|(a, b)| json!([point(&a), point(&b)])),
            "outline": self.extras.part.iter().map(point).collect::<Vec<_>>(),
            "said": self.said,
        })
    }
}

/// The stock and part of a program where they are known: the blank the program states
/// (Heidenhain's BLK FORM, read back from the program as written), and on a lathe the
/// chamfer the workbook computes on the sheet the macro ran on.
fn known_part(doc: &Document, sheet: SheetId, program: &Program, path: &Toolpath) -> KnownPart {
    if let Some(blank) = program.blank {
        let said = "stock: the program's blank (BLK FORM)".to_string();
        return KnownPart { extras: Extras { stock: Some(blank), part: Vec::new() }, said };
    }
    if program.machine != Machine::Lathe {
        let said = "no stock or part is known: the program states no blank (BLK FORM)".to_string();
        return KnownPart { extras: Extras::default(), said };
    }
    match sheet_chamfer(doc, sheet) {
        Ok((spec, source)) => match chamfer_geometry(&spec) {
            Ok(g) => {
                let extras = chamfer_part(&spec, &g, path);
                let kind = format!("{:?}", spec.kind).to_ascii_lowercase();
                let stock_said = if extras.stock.is_some() { "; stock: the part before the chamfer" } else { "" };
                let said = format!(
                    "part: the {kind} chamfer of {source} (D {}, f {}, α {}°){stock_said}",
                    spec.diameter, spec.length, spec.angle_deg
                );
                KnownPart { extras, said }
            }
            Err(e) => KnownPart { extras: Extras::default(), said: format!("no part drawn: {source}: {e}") },
        },
        Err(why) => KnownPart { extras: Extras::default(), said: format!("no stock or part is known: {why}") },
    }
}

/// The chamfer of docs/domain.md §1 a sheet computes: its inputs as the sheet's names D, f,
/// alpha, r_ (or r), eA, eB with the kind the sheet's name says (Outer, Pipe or Blind, as
/// the paper's Excel model lays it out), else the first cell of the sheet calling CHAMFER*.
/// With where it was found, or why none was.
fn sheet_chamfer(doc: &Document, sheet: SheetId) -> Result<(ChamferSpec, String), String> {
    let wb = doc.workbook();
    let sheet_name = wb.sheet_names().into_iter().nth(sheet as usize).unwrap_or_default();
    let named = |name: &str| {
        let (s, pos) = doc.cell(&format!("'{}'!{name}", sheet_name.replace('\'', "''")))?;
        match wb.value(s, pos) {
            Value::Number(n) => Some(n),
            _ => None,
        }
    };
    let r = named("r_").or_else(|| named("r"));
    let inputs = [named("D"), named("f"), named("alpha"), r, named("eA"), named("eB")];
    if let Some(numbers) = inputs.iter().copied().collect::<Option<Vec<f64>>>() {
        if let Ok(kind) = ChamferKind::parse(&sheet_name) {
            let n = [numbers[0], numbers[1], numbers[2], numbers[3], numbers[4], numbers[5]];
            return Ok((ChamferSpec::from_arguments(kind, n), format!("{sheet_name}'s names D, f, alpha, r_, eA, eB")));
        }
    }
    match first_chamfer_call(doc, sheet) {
        Some(pos) => {
            chamfer_call(doc, sheet, pos).map(|(spec, _)| (spec, wb.cell_name(sheet, pos))).map_err(|r| r.message)
        }
        None => Err(format!(
            "{sheet_name} calls no CHAMFER function and names no chamfer's inputs (D, f, alpha, r_, eA, eB on a sheet \
             named Outer, Pipe or Blind)"
        )),
    }
}

/// The most cells of a sheet searched for a CHAMFER* call.
const CELLS_SEARCHED: u64 = 100_000;

/// The first cell of the sheet, row by row, whose formula calls CHAMFER*.
fn first_chamfer_call(doc: &Document, sheet: SheetId) -> Option<Pos> {
    let wb = doc.workbook();
    let used = wb.used_rect(sheet)?;
    let cells =
        (used.first.row..=used.last.row).flat_map(|r| (used.first.col..=used.last.col).map(move |c| Pos::new(r, c)));
    cells
        .take(CELLS_SEARCHED as usize)
        .find(|&pos| wb.formula_tree(sheet, pos).is_some_and(|tree| super::paths::call_of(&tree, "CHAMFER").is_some()))
}

/// A chamfered part in the lathe's backplot (X a radius, Z along the axis, the face at
/// Z = 0): the outline of its half section, from far enough left to show the path, and the
/// stock before the chamfer where it is a box (none for a blind bore, whose blank has the
/// bore in it). An inner chamfer's part is drawn with a wall as thick as the chamfer is long
/// or high: the workbook does not say the outer diameter.
fn chamfer_part(spec: &ChamferSpec, g: &ChamferGeometry, path: &Toolpath) -> Extras {
    let at = |z: f64, radius: f64| [radius, 0.0, z];
    let lowest_z = path.bounds().map_or(g.a.x, |(lo, _)| lo[2]);
    let left = lowest_z.min(g.a.x) - spec.length;
    let (a, b) = (at(g.a.x, g.a.y), at(g.b.x, g.b.y));
    let radius = spec.diameter / 2.0;
    let wall = g.b.y.max(g.a.y) + spec.length.max((g.b.y - g.a.y).abs());
    match spec.kind {
        ChamferKind::Outer => {
            let outline = vec![at(left, 0.0), at(left, radius), a, b, at(0.0, 0.0)];
            Extras { stock: Some((at(left, 0.0), at(0.0, radius))), part: outline }
        }
        ChamferKind::Pipe => {
            let outline = vec![at(left, radius), a, b, at(0.0, wall), at(left, wall)];
            Extras { stock: Some((at(left, radius), at(0.0, wall))), part: outline }
        }
        ChamferKind::Blind => {
            let outline = vec![at(left, 0.0), at(g.a.x, 0.0), a, b, at(0.0, wall), at(left, wall)];
            Extras { stock: None, part: outline }
        }
    }
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
    RunOptions {
        sub: (!sub.is_empty()).then(|| sub.to_string()),
        sheet: doc.workbook().sheet_names().into_iter().nth(sheet as usize),
        dialect: Some(dialect),
        limits_from: vba::LimitsFrom::Workbench,
        ..RunOptions::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ncsheet::document::OpenOptions;

    fn path_of(program: &Program) -> Toolpath {
        backplot::toolpath(program).unwrap()
    }

    /// A Heidenhain program's BLK FORM is the stock its backplot shows (the corners as the
    /// program states them).
    #[test]
    fn a_programs_blk_form_is_its_stock() {
        let text = "0 BEGIN PGM T MM\n1 BLK FORM 0.1 Z X-25 Y-20 Z-5\n2 BLK FORM 0.2 X+25 Y+20 Z+15\n\
                    3 TOOL CALL 1 Z S3000\n4 L X+0 Y+0 Z+20 R0 FMAX\n5 L Z+5 F200\n6 END PGM T MM\n";
        let heidenhain = dialect::by_name("heidenhain").unwrap();
        let (program, _) = read::read_dialect(text, heidenhain, Some(Machine::Mill)).unwrap();
        let doc = Document::open(b"1\n".to_vec(), &OpenOptions::named("book.csv")).unwrap();
        let known = known_part(&doc, 0, &program, &path_of(&program));
        assert_eq!(known.extras.stock, Some(([-25.0, -20.0, -5.0], [25.0, 20.0, 15.0])));
        assert!(known.extras.part.is_empty());
        assert!(known.said.contains("BLK FORM"), "{}", known.said);
    }

    /// A lathe program on a sheet whose H2 is =CHAMFER(outer, 40, 2, 45, 0.8, 1, 1): the part
    /// is that chamfer, A = (Z −2, X 20) to B = (Z 0, X 20 − 2·tan 45° = 18), X a radius.
    #[test]
    fn a_sheets_chamfer_call_is_a_lathe_programs_part() {
        let csv = include_bytes!("../../../sheets/chamfer-builtin.csv").to_vec();
        let doc = Document::open(csv, &OpenOptions::named("chamfer-builtin.csv")).unwrap();
        let text = "G18 G21\nT0101\nG97 S800 M3\nG0 X50 Z5\nG1 X40 Z-4 F0.1\nG0 X50 Z5\nM30\n";
        let iso = dialect::by_name("iso").unwrap();
        let (program, _) = read::read_dialect(text, iso, Some(Machine::Lathe)).unwrap();
        let known = known_part(&doc, 0, &program, &path_of(&program));
        let outline = &known.extras.part;
        let near = |p: [f64; 3], q: [f64; 3]| (0..3).all(|i| (p[i] - q[i]).abs() < 1e-12);
        let a = outline.iter().position(|&p| near(p, [20.0, 0.0, -2.0])).expect("A in the outline");
        assert!(near(outline[a + 1], [18.0, 0.0, 0.0]), "{outline:?}");
        assert!(known.said.contains("outer chamfer of") && known.said.contains("H2"), "{}", known.said);
    }
}
