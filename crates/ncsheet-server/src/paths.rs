//! The curves and paths a cell computes, for the machining pane: the tangent arcs of an
//! ARCH_FIT call over the true cam curve with their deviation (`geometry::cam`), and the points
//! a BALLPATH call spills with its backplots in plan (coloured by depth) and in section
//! (`nc::backplot`). All from the library; the page only draws.

use serde_json::{json, Value as Json};

use super::workbench::{refused, Refused};
use ncsheet::document::Document;
use ncsheet::eval::{Ctx, Value};
use ncsheet::formula::address::Pos;
use ncsheet::formula::ast::{Expr, ExprKind, SheetId};
use ncsheet::geometry::cam::{deviation, fit_piece, CamOptions, Piece, PieceKind, Side, Turn};
use ncsheet::io::{encode_export_with, Content, Export, ExportOptions};
use ncsheet::nc::backplot::{self, Extras, Move, MoveKind, Plane, Toolpath};
use ncsheet::nc::cam::distance_to_arc;
use ncsheet::nc::cam_sheet::{fit_design_sheet, svg_drawing as cam_drawing, SvgOptions};
use ncsheet::nc::Machine;

/// Points of the true curve the page draws.
const CURVE_SAMPLES: usize = 400;

/// The arguments of the first call of `function` in a formula.
pub fn call_of<'a>(e: &'a Expr, function: &str) -> Option<&'a [Expr]> {
    match &e.kind {
        ExprKind::Call(id, args) => {
            if ncsheet::eval::functions::spec(*id).name.starts_with(function) {
                return Some(args);
            }
            args.iter().find_map(|a| call_of(a, function))
        }
        ExprKind::Paren(inner) | ExprKind::Unary(_, inner) => call_of(inner, function),
        ExprKind::Binary(_, a, b) => call_of(a, function).or_else(|| call_of(b, function)),
        ExprKind::UnknownCall(_, args) | ExprKind::Invoke(_, args) => args.iter().find_map(|a| call_of(a, function)),
        _ => None,
    }
}

/// The values of the arguments of `function` called in the cell's formula.
fn arguments(doc: &Document, sheet: SheetId, pos: Pos, function: &str) -> Result<Vec<Value>, Refused> {
    let wb = doc.workbook();
    let cell = wb.cell_name(sheet, pos);
    let tree = wb.formula_tree(sheet, pos).ok_or_else(|| refused(format!("{cell} holds no formula")))?;
    let args = call_of(&tree, function).ok_or_else(|| refused(format!("{cell} calls no {function}")))?;
    Ok(args.iter().map(|a| Ctx::new(wb, sheet, pos).eval(a)).collect())
}

fn number(cell: &str, function: &str, values: &[Value], i: usize) -> Result<f64, Refused> {
    match values.get(i) {
        Some(Value::Number(x)) => Ok(*x),
        Some(v) => Err(refused(format!("{cell}: argument {} of {function} is {v}, not a number", i + 1))),
        None => Err(refused(format!("{cell}: {function} lacks argument {}", i + 1))),
    }
}

/// An ARCH_FIT call's piece, its arcs and how far they stray: the curve sampled, each arc
/// with its ends, centre and sense, and at each sample the distance to the nearest arc (for
/// the page to draw magnified along the curve's normal).
pub fn arch_fit(doc: &Document, sheet: SheetId, pos: Pos) -> Result<Json, Refused> {
    let cell = doc.workbook().cell_name(sheet, pos);
    let values = arguments(doc, sheet, pos, "ARCH_FIT")?;
    let kind = PieceKind::parse(&values.first().map(Value::to_string).unwrap_or_default())
        .map_err(|e| refused(format!("{cell}: {e}")))?;
    let n: Vec<f64> = (1..6).map(|i| number(&cell, "ARCH_FIT", &values, i)).collect::<Result<_, _>>()?;
    let piece = Piece::new(kind, n[0], n[1], n[2], n[3]).map_err(|e| refused(format!("{cell}: {e}")))?;
    let arcs = fit_piece(&piece, n[4]).map_err(|e| refused(format!("{cell}: {e}")))?;
    let curve: Vec<Json> = (0..=CURVE_SAMPLES)
        .map(|i| {
            let t = i as f64 / CURVE_SAMPLES as f64;
            let p = piece.point(t);
            let normal = {
                let d = piece.tangent(t);
                let len = d.norm().max(f64::MIN_POSITIVE);
                [-d.y / len, d.x / len]
            };
            let off = arcs.iter().map(|a| distance_to_arc(a, p)).fold(f64::INFINITY, f64::min);
            json!({ "x": p.x, "y": p.y, "n": normal, "d": off })
        })
        .collect();
    let arcs_json: Vec<Json> = arcs
        .iter()
        .map(|a| {
            json!({
                "start": [a.start.x, a.start.y], "end": [a.end.x, a.end.y], "centre": [a.centre.x, a.centre.y],
                "radius": a.radius, "ccw": a.turn == Turn::Ccw,
            })
        })
        .collect();
    let check = deviation(&piece, &arcs, 200);
    Ok(json!({
        "cell": cell, "kind": kind.word(), "tolerance": n[4],
        "curve": curve, "arcs": arcs_json, "deviation": check.max(),
    }))
}

/// The most points of a ball path sent to the page whole; a longer path is sent thinned (the
/// backplots always draw every point, thinned only within their pixels).
const PAGE_POINTS: usize = 200_000;

/// The points a BALLPATH call spills (x, y, z rows under the cell), their backplots in plan
/// and in section with the stock, and the points for the page's 3D view.
pub fn ball_path(doc: &Document, sheet: SheetId, pos: Pos) -> Result<Json, Refused> {
    let wb = doc.workbook();
    let cell = wb.cell_name(sheet, pos);
    let values = arguments(doc, sheet, pos, "BALLPATH")?;
    let points = spilled_points(doc, sheet, pos);
    if points.len() < 2 {
        return Err(refused(format!("{cell}: the ball path has fewer than two points (see the cell's value)")));
    }
    let moves: Vec<Move> = points
        .windows(2)
        .enumerate()
        .map(|(i, w)| Move { block: i + 1, kind: MoveKind::Feed, from: w[0], to: w[1], arc: None })
        .collect();
    let path = Toolpath { machine: Machine::Mill, moves };
    let stock = stock_of(&cell, &values, &points)?;
    let extras = Extras { stock: Some(stock), ..Extras::default() };
    let title = format!("{cell}: ball path, {} points", points.len());
    let plan = backplot::svg_drawing_with(&path, Plane::Xy, &title, &extras).map_err(|e| refused(e.message))?;
    let section = backplot::svg_drawing_with(&path, Plane::Xz, &title, &extras).map_err(|e| refused(e.message))?;
    let every = points.len().div_ceil(PAGE_POINTS);
    let sent: Vec<f64> = points.iter().step_by(every).flat_map(|p| p.iter().copied()).collect();
    Ok(json!({
        "cell": cell, "count": points.len(), "points": sent, "plan": plan, "section": section,
        "first": points[0], "last": points[points.len() - 1], "stock": [stock.0, stock.1],
    }))
}

/// The rows of numbers x, y, z from the cell down, as far as they go.
fn spilled_points(doc: &Document, sheet: SheetId, pos: Pos) -> Vec<[f64; 3]> {
    let wb = doc.workbook();
    let mut points = Vec::new();
    for row in pos.row.. {
        let at = |c: u32| match wb.value(sheet, Pos::new(row, pos.col + c)) {
            Value::Number(n) => Some(n),
            _ => None,
        };
        let (Some(x), Some(y), Some(z)) = (at(0), at(1), at(2)) else { break };
        points.push([x, y, z]);
    }
    points
}

/// The stock a ball path cuts: the rectangle x0..x1, y0..y1 the call names, from the path's
/// lowest point to its highest.
fn stock_of(cell: &str, values: &[Value], points: &[[f64; 3]]) -> Result<([f64; 3], [f64; 3]), Refused> {
    let n = |i| number(cell, "BALLPATH", values, i);
    let (x0, x1, y0, y1) = (n(2)?, n(3)?, n(4)?, n(5)?);
    let (lo, hi) = points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p[2]), hi.max(p[2])));
    Ok(([x0.min(x1), y0.min(y1), lo], [x0.max(x1), y0.max(y1), hi]))
}

/// A cam design sheet (the sheet's values as `ncsheet cam` reads a csv: row, operation, disc,
/// type, angles and radii) fitted disc by disc with arcs on the outside of the curve within
/// `tolerance`: each disc's drawing (`nc::cam_sheet::svg_drawing`: the curve, the arcs, the
/// magnified deviation) and its count of arcs.
pub fn cam_sheet(doc: &Document, sheet: SheetId, tolerance: f64) -> Result<Json, Refused> {
    if !(tolerance > 0.0 && tolerance.is_finite()) {
        return Err(refused(format!("tolerance {tolerance}: a positive number of mm")));
    }
    let wb = doc.workbook();
    let what = Export { sheet, range: None, content: Content::Values };
    let options = ExportOptions { delimiter: Some(b','), layout: doc.layout(), raw: true };
    let encoded = encode_export_with(wb, std::path::Path::new("sheet.csv"), &what, &options)
        .map_err(|e| refused(e.to_string()))?;
    let text = String::from_utf8_lossy(encoded.bytes()).into_owned();
    let cam = CamOptions { tolerance, side: Side::Outside, reserve: 0.0, allow_partial: false, with_bounds: false };
    let sheet_name = wb.sheet_names().into_iter().nth(sheet as usize).unwrap_or_default();
    let fits = fit_design_sheet(&text, &cam).map_err(|e| refused(format!("{sheet_name} as a cam sheet: {e}")))?;
    let discs: Vec<Json> = fits
        .iter()
        .map(|fit| json!({ "disc": fit.disc, "arcs": fit.n_arcs(), "svg": cam_drawing(fit, &SvgOptions::default()) }))
        .collect();
    Ok(json!({ "sheet": sheet_name, "tolerance": tolerance, "discs": discs }))
}
