//! The workbench's HTTP surface: the page at `/` and the JSON API under `/api/`, behind the
//! guard. Every answer is a status the page can read: 403 for a stranger, 404 for a path that
//! is not served, 400 with the reason for a request the workbook refuses, never a crash.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::OnceLock;

use axum::body::{Body, Bytes};
use axum::extract::{Query, Request, State};
use axum::http::{header, HeaderValue, StatusCode};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use serde_json::{json, Value as Json_};

use super::guard::{Claims, Guard, TOKEN_HEADER};
use super::workbench::{refused, Refused, Window, Workbench};
use super::{machining, paths};
use super::{DocumentThread, Unanswered};
use ncsheet::document::SaveFormat;
use ncsheet::formula::address::Pos;

/// What every handler shares.
#[derive(Clone)]
pub struct App {
    pub guard: Guard,
    pub document: DocumentThread,
    /// The macro files (.bas) beside the workbook, the only ones a run may read.
    pub bas_files: std::sync::Arc<Vec<PathBuf>>,
}

pub fn router(app: App) -> Router {
    let guard = app.guard.clone();
    Router::new()
        .route("/", get(page))
        .route("/api/sheets", get(sheets))
        .route("/api/cells", get(cells))
        .route("/api/locate", get(locate))
        .route("/api/inspect", get(inspect))
        .route("/api/set", post(set))
        .route("/api/undo", post(undo))
        .route("/api/redo", post(redo))
        .route("/api/losses", get(losses))
        .route("/api/download", get(download))
        .route("/api/save", post(save))
        .route("/api/chamfer", get(chamfer))
        .route("/api/archfit", get(arch_fit))
        .route("/api/ballpath", get(ball_path))
        .route("/api/camsheet", get(cam_sheet))
        .route("/api/macros", get(macros))
        .route("/api/run", post(run_macro))
        .fallback(not_found)
        .with_state(app)
        // The outer layer runs first: a stranger is refused before its body is read.
        .layer(middleware::from_fn(super::connections::answer_in_time))
        .layer(middleware::from_fn_with_state(guard, admit))
}

/// Refuses strangers before any handler (or the 404) sees the request.
async fn admit(State(guard): State<Guard>, request: Request, next: Next) -> Response {
    match check(&guard, &request) {
        Ok(()) => next.run(request).await,
        Err(denied) => (StatusCode::FORBIDDEN, denied.message()).into_response(),
    }
}

fn check(guard: &Guard, request: &Request) -> Result<(), super::guard::Denied> {
    let headers = request.headers();
    let text = |name: header::HeaderName| headers.get(name).and_then(|v| v.to_str().ok());
    // The API takes the token from its header only (a link or a form cannot set one); the
    // page, opened from the printed URL, from its query too.
    let mut token = headers.get(TOKEN_HEADER).and_then(|v| v.to_str().ok());
    if token.is_none() && !request.uri().path().starts_with("/api/") {
        token = request.uri().query().and_then(|q| q.split('&').find_map(|kv| kv.strip_prefix("t=")));
    }
    guard.admit(&Claims { host: text(header::HOST), origin: text(header::ORIGIN), token })
}

async fn not_found() -> Response {
    (StatusCode::NOT_FOUND, "not found: the workbench serves its page and its API only").into_response()
}

/// The page with its style and script inlined, made once.
fn page_text() -> &'static str {
    static PAGE: OnceLock<String> = OnceLock::new();
    PAGE.get_or_init(|| {
        include_str!("assets/index.html")
            .replace("/*STYLE*/", include_str!("assets/app.css"))
            .replace("/*SCRIPT*/", include_str!("assets/app.js"))
    })
}

async fn page() -> Response {
    let mut response = page_text().into_response();
    let headers = response.headers_mut();
    headers.insert(header::CONTENT_TYPE, HeaderValue::from_static("text/html; charset=utf-8"));
    headers.insert(header::CACHE_CONTROL, HeaderValue::from_static("no-store"));
    // The token is in the page's URL: no other site may frame it or be told it.
    headers.insert(header::REFERRER_POLICY, HeaderValue::from_static("no-referrer"));
    headers.insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static(
            "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src data: blob:; connect-src 'self'; frame-ancestors 'none'",
        ),
    );
    response
}

/// A 400 (or 409) with the reason as text.
fn refusal(r: Refused) -> Response {
    let status = if r.conflict { StatusCode::CONFLICT } else { StatusCode::BAD_REQUEST };
    (status, Json(json!({ "error": r.message }))).into_response()
}

/// A request the workbook's thread did not answer: it stopped (500), or it is computing past
/// `--timeout` (503, with what became of the request, for the page to say).
fn unanswered(u: Unanswered) -> Response {
    let message = match u {
        Unanswered::Gone => {
            return (StatusCode::INTERNAL_SERVER_ERROR, "the workbook's thread stopped").into_response()
        }
        Unanswered::Late { seconds, started: true } => format!(
            "still computing after the --timeout of {seconds} s: a formula's recalculation cannot stop partway, so \
             this request finishes in the background and the workbook answers again when it is done"
        ),
        Unanswered::Late { seconds, started: false } => format!(
            "the workbook is still computing an earlier request after the --timeout of {seconds} s: this request \
             was not carried out"
        ),
    };
    (StatusCode::SERVICE_UNAVAILABLE, Json(json!({ "error": message }))).into_response()
}

/// Runs `f` on the workbook and answers with its JSON or its refusal.
async fn on_workbook(app: &App, f: impl FnOnce(&mut Workbench) -> Result<Json_, Refused> + Send + 'static) -> Response {
    match app.document.with(f).await {
        Ok(Ok(answer)) => Json(answer).into_response(),
        Ok(Err(r)) => refusal(r),
        Err(u) => unanswered(u),
    }
}

type Params = Query<HashMap<String, String>>;

/// A whole number from the query or a JSON body.
fn number(params: &HashMap<String, String>, key: &str) -> Result<u64, Refused> {
    let text = params.get(key).ok_or_else(|| refused(format!("missing {key}")))?;
    text.parse().map_err(|_| refused(format!("{key}={text}: not a whole number")))
}

fn json_number(body: &Json_, key: &str) -> Result<u64, Refused> {
    body.get(key).and_then(Json_::as_u64).ok_or_else(|| refused(format!("{key}: a whole number is needed")))
}

fn json_text<'a>(body: &'a Json_, key: &str) -> Result<&'a str, Refused> {
    body.get(key).and_then(Json_::as_str).ok_or_else(|| refused(format!("{key}: a text is needed")))
}

/// A request body as JSON (an object).
fn body_json(body: &Bytes) -> Result<Json_, Refused> {
    match serde_json::from_slice::<Json_>(body) {
        Ok(value @ Json_::Object(_)) => Ok(value),
        Ok(_) => Err(refused("the request body must be a JSON object")),
        Err(e) => Err(refused(format!("the request body is not JSON: {e}"))),
    }
}

/// The window a query or body names: `sheet`, `r0`, `r1`, `c0`, `c1`.
fn window_from(bench: &Workbench, get: impl Fn(&str) -> Result<u64, Refused>) -> Result<Window, Refused> {
    bench.window(get("sheet")?, (get("r0")?, get("r1")?), (get("c0")?, get("c1")?))
}

/// The cell a query or body names: `sheet`, `r`, `c`.
fn cell_from(bench: &Workbench, get: impl Fn(&str) -> Result<u64, Refused>) -> Result<(u16, Pos), Refused> {
    let window = bench.window(get("sheet")?, (get("r")?, get("r")?), (get("c")?, get("c")?))?;
    Ok((window.sheet, window.rect.first))
}

fn format_of(params: &HashMap<String, String>) -> Result<SaveFormat, Refused> {
    match params.get("format").map(String::as_str) {
        Some("xlsx") => Ok(SaveFormat::Xlsx),
        Some("xlsm") => Ok(SaveFormat::Xlsm),
        Some("csv") => Ok(SaveFormat::Csv),
        other => Err(refused(format!("format {}: xlsx, xlsm or csv", other.unwrap_or("(none)")))),
    }
}

async fn sheets(State(app): State<App>) -> Response {
    on_workbook(&app, |bench| Ok(bench.summary())).await
}

async fn cells(State(app): State<App>, Query(params): Params) -> Response {
    on_workbook(&app, move |bench| Ok(bench.cells(window_from(bench, |k| number(&params, k))?))).await
}

async fn locate(State(app): State<App>, Query(params): Params) -> Response {
    on_workbook(&app, move |bench| {
        let current = bench.sheet(number(&params, "sheet")?)?;
        let name = params.get("name").ok_or_else(|| refused("missing name"))?;
        let (sheet, pos) = bench.locate(name, current)?;
        Ok(json!({ "sheet": sheet, "r": pos.row, "c": pos.col }))
    })
    .await
}

async fn inspect(State(app): State<App>, Query(params): Params) -> Response {
    on_workbook(&app, move |bench| {
        let (sheet, pos) = cell_from(bench, |k| number(&params, k))?;
        Ok(bench.inspect(sheet, pos))
    })
    .await
}

async fn set(State(app): State<App>, body: Bytes) -> Response {
    on_workbook(&app, move |bench| {
        let body = body_json(&body)?;
        let (sheet, pos) = cell_from(bench, |k| json_number(&body, k))?;
        let input = json_text(&body, "input")?.to_string();
        let window = window_from(bench, |k| json_number(&body["window"], k))?;
        bench.set(sheet, pos, &input, window)
    })
    .await
}

async fn undo(State(app): State<App>, body: Bytes) -> Response {
    on_workbook(&app, move |bench| {
        let window = window_of_body(bench, &body)?;
        bench.undo(window)
    })
    .await
}

async fn redo(State(app): State<App>, body: Bytes) -> Response {
    on_workbook(&app, move |bench| {
        let window = window_of_body(bench, &body)?;
        bench.redo(window)
    })
    .await
}

/// The page's window, from a body `{"window": {...}}`.
fn window_of_body(bench: &Workbench, body: &Bytes) -> Result<Window, Refused> {
    let body = body_json(body)?;
    window_from(bench, |k| json_number(&body["window"], k))
}

async fn losses(State(app): State<App>, Query(params): Params) -> Response {
    on_workbook(&app, move |bench| bench.losses(format_of(&params)?, bench.sheet(number(&params, "sheet")?)?)).await
}

async fn download(State(app): State<App>, Query(params): Params) -> Response {
    let answer = app
        .document
        .with(move |bench| bench.download(format_of(&params)?, bench.sheet(number(&params, "sheet")?)?))
        .await;
    match answer {
        Ok(Ok((name, bytes))) => {
            let disposition = format!("attachment; filename=\"{}\"", name.replace(['"', '\\', '\r', '\n'], "_"));
            let mut response = Body::from(bytes).into_response();
            let headers = response.headers_mut();
            headers.insert(header::CONTENT_TYPE, HeaderValue::from_static("application/octet-stream"));
            if let Ok(value) = HeaderValue::from_str(&disposition) {
                headers.insert(header::CONTENT_DISPOSITION, value);
            }
            response
        }
        Ok(Err(r)) => refusal(r),
        Err(u) => unanswered(u),
    }
}

async fn save(State(app): State<App>, body: Bytes) -> Response {
    on_workbook(&app, move |bench| {
        let body = body_json(&body)?;
        let name = json_text(&body, "name")?.to_string();
        let over = body.get("over").and_then(Json_::as_bool).unwrap_or(false);
        let sheet = match body.get("sheet") {
            Some(_) => bench.sheet(json_number(&body, "sheet")?)?,
            None => 0,
        };
        bench.save(&name, over, sheet)
    })
    .await
}

/// What the machining pane shows for the cell a query names (`sheet`, `r`, `c`).
type CellView = fn(&ncsheet::document::Document, ncsheet::formula::ast::SheetId, Pos) -> Result<Json_, Refused>;

async fn cell_view(app: &App, params: HashMap<String, String>, view: CellView) -> Response {
    on_workbook(app, move |bench| {
        let (sheet, pos) = cell_from(bench, |k| number(&params, k))?;
        view(bench.document(), sheet, pos)
    })
    .await
}

async fn chamfer(State(app): State<App>, Query(params): Params) -> Response {
    cell_view(&app, params, machining::chamfer).await
}

async fn arch_fit(State(app): State<App>, Query(params): Params) -> Response {
    cell_view(&app, params, paths::arch_fit).await
}

async fn ball_path(State(app): State<App>, Query(params): Params) -> Response {
    cell_view(&app, params, paths::ball_path).await
}

async fn cam_sheet(State(app): State<App>, Query(params): Params) -> Response {
    on_workbook(&app, move |bench| {
        let sheet = bench.sheet(number(&params, "sheet")?)?;
        let text = params.get("tol").map_or("0.01", String::as_str);
        let tolerance = text.parse().map_err(|_| refused(format!("tol={text}: not a number")))?;
        paths::cam_sheet(bench.document(), sheet, tolerance)
    })
    .await
}

async fn macros(State(app): State<App>) -> Response {
    let files = app.bas_files.clone();
    on_workbook(&app, move |bench| Ok(machining::macros(bench, &files))).await
}

async fn run_macro(State(app): State<App>, body: Bytes) -> Response {
    let files = app.bas_files.clone();
    let timeout = app.document.timeout;
    on_workbook(&app, move |bench| {
        let body = body_json(&body)?;
        let request = machining::RunRequest {
            source: json_text(&body, "source")?.to_string(),
            sub: json_text(&body, "sub")?.to_string(),
            dialect: json_text(&body, "dialect")?.to_string(),
            machine: body.get("machine").and_then(Json_::as_str).unwrap_or("lathe").to_string(),
            sheet: bench.sheet(json_number(&body, "sheet")?)?,
            seconds: timeout.unwrap_or(machining::RUN_SECONDS),
        };
        let mut answer = machining::run(bench, &files, &request)?;
        answer["history"] = bench.history();
        Ok(answer)
    })
    .await
}
