//! `ncsheet serve`, the workbench: its safety through a plain TCP client (no token, a foreign
//! Origin or Host, a path outside, a flood of malformed requests), its API on the chamfer
//! workbook (values from docs/domain.md §1 and the values Excel cached in the file), and its
//! page in a real browser (tests/workbench_browser.py through Selenium and chromium-driver).

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

use ncsheet_server::{Options, Server, TOKEN_HEADER};
use serde_json::Value;

/// A workbench serving a copy of `sheets/NAME` from a folder of its own.
struct Bench {
    port: u16,
    token: String,
    folder: tempfile::TempDir,
}

impl Bench {
    fn start(name: &str) -> Bench {
        Bench::with_macros(name, &[])
    }

    /// Serves `sheets/NAME` with the macro files `bas` copied beside it.
    fn with_macros(name: &str, bas: &[&str]) -> Bench {
        let folder = tempfile::tempdir().unwrap();
        let sheets = Path::new(env!("CARGO_MANIFEST_DIR")).join("sheets");
        let file = folder.path().join(name);
        std::fs::copy(sheets.join(name), &file).unwrap();
        let mut macro_files = Vec::new();
        for b in bas {
            macro_files.push(folder.path().join(b));
            std::fs::copy(sheets.join(b), folder.path().join(b)).unwrap();
        }
        let server = Server::open(&file, &Options { port: 0, macro_files, ..Options::default() }).unwrap();
        let (port, token) = (server.port(), server.token().to_string());
        std::thread::spawn(move || server.run());
        Bench { port, token, folder }
    }

    /// Serves a csv of `rows` rows: A holds the row's number, B doubles it by formula.
    fn big_sheet(rows: usize) -> Bench {
        let folder = tempfile::tempdir().unwrap();
        let file = folder.path().join("big.csv");
        let text: String = (1..=rows).map(|i| format!("{i},=A{i}*2\n")).collect();
        std::fs::write(&file, text).unwrap();
        let server = Server::open(&file, &Options::default()).unwrap();
        let (port, token) = (server.port(), server.token().to_string());
        std::thread::spawn(move || server.run());
        Bench { port, token, folder }
    }

    /// Serves `name` written with `text` in a folder of its own, with the macro files `bas`
    /// (name, text) beside it, opened with `open` (the command line's reading options).
    fn written(name: &str, text: &str, bas: &[(&str, &str)], open: ncsheet::document::OpenOptions) -> Bench {
        Bench::written_with(name, text, bas, Options { open, ..Options::default() })
    }

    /// As [`Bench::written`], served with `options` (its port and macro files aside).
    fn written_with(name: &str, text: impl AsRef<[u8]>, bas: &[(&str, &str)], options: Options) -> Bench {
        let folder = tempfile::tempdir().unwrap();
        let file = folder.path().join(name);
        std::fs::write(&file, text).unwrap();
        let mut macro_files = Vec::new();
        for (b, source) in bas {
            std::fs::write(folder.path().join(b), source).unwrap();
            macro_files.push(folder.path().join(b));
        }
        let server = Server::open(&file, &Options { port: 0, macro_files, ..options }).unwrap();
        let (port, token) = (server.port(), server.token().to_string());
        std::thread::spawn(move || server.run());
        Bench { port, token, folder }
    }

    fn file(&self, name: &str) -> PathBuf {
        self.folder.path().join(name)
    }

    /// Sends raw bytes and returns the status (0 when the server closed without one) and body.
    /// It waits for the server however long it takes: no test passes or fails by the clock
    /// (a server that never answers is a hang the test run's own limit ends).
    fn raw(&self, request: &[u8]) -> (u16, String) {
        let mut stream = TcpStream::connect(("127.0.0.1", self.port)).unwrap();
        stream.write_all(request).unwrap();
        let mut answer = Vec::new();
        let _ = stream.read_to_end(&mut answer);
        let text = String::from_utf8_lossy(&answer).into_owned();
        let status = text.split(' ').nth(1).and_then(|s| s.parse().ok()).unwrap_or(0);
        let body = text.split_once("\r\n\r\n").map_or(String::new(), |(_, b)| b.to_string());
        (status, body)
    }

    /// A request as a browser on this page sends it: own Host, the token header, no Origin.
    fn send(&self, method: &str, path: &str, extra: &str, body: &str) -> (u16, String) {
        let request = format!(
            "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1:{}\r\n{TOKEN_HEADER}: {}\r\n{extra}Content-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
            self.port,
            self.token,
            body.len()
        );
        self.raw(request.as_bytes())
    }

    fn get_json(&self, path: &str) -> Value {
        let (status, body) = self.send("GET", path, "", "");
        assert_eq!(status, 200, "GET {path}: {body}");
        serde_json::from_str(&body).unwrap()
    }

    fn post_json(&self, path: &str, body: &Value) -> (u16, Value) {
        let (status, text) = self.send("POST", path, "", &body.to_string());
        (status, serde_json::from_str(&text).unwrap_or(Value::Null))
    }
}

/// The changed cell at (row, col) of an edit's answer.
fn changed(answer: &Value, row: u64, col: u64) -> &Value {
    let cells = answer["changed"].as_array().unwrap();
    cells.iter().find(|c| c["r"] == row && c["c"] == col).unwrap_or_else(|| panic!("({row},{col}) not in {answer}"))
}

const OUTER: u64 = 1;
const WINDOW: &str = r#"{"sheet":1,"r0":0,"r1":40,"c0":0,"c1":10}"#;

#[test]
fn a_request_without_the_token_is_forbidden() {
    let bench = Bench::start("chamfer.xlsx");
    let host = format!("Host: 127.0.0.1:{}\r\n", bench.port);
    let (status, _) = bench.raw(format!("GET /api/sheets HTTP/1.1\r\n{host}Connection: close\r\n\r\n").as_bytes());
    assert_eq!(status, 403);
    let (status, _) = bench.raw(format!("GET / HTTP/1.1\r\n{host}Connection: close\r\n\r\n").as_bytes());
    assert_eq!(status, 403);
    let (status, _) = bench.raw(format!("GET /?t=0123 HTTP/1.1\r\n{host}Connection: close\r\n\r\n").as_bytes());
    assert_eq!(status, 403);
    // The API takes the token from its header only, not from a link's query.
    let path = format!("/api/sheets?t={}", bench.token);
    let (status, _) = bench.raw(format!("GET {path} HTTP/1.1\r\n{host}Connection: close\r\n\r\n").as_bytes());
    assert_eq!(status, 403);
    let page = format!("GET /?t={} HTTP/1.1\r\n{host}Connection: close\r\n\r\n", bench.token);
    let (status, body) = bench.raw(page.as_bytes());
    assert_eq!(status, 200);
    assert!(body.contains("<script>") && body.contains("/api/cells"), "{body}");
}

#[test]
fn a_foreign_origin_or_host_is_forbidden() {
    let bench = Bench::start("chamfer.xlsx");
    let (status, _) = bench.send("GET", "/api/sheets", "Origin: http://evil.example\r\n", "");
    assert_eq!(status, 403);
    let (status, _) = bench.send("POST", "/api/undo", "Origin: null\r\n", &format!(r#"{{"window":{WINDOW}}}"#));
    assert_eq!(status, 403);
    // DNS rebinding: the browser thinks it talks to evil.example, and says so in Host.
    let request = format!(
        "GET /api/sheets HTTP/1.1\r\nHost: evil.example:{}\r\n{TOKEN_HEADER}: {}\r\nConnection: close\r\n\r\n",
        bench.port, bench.token
    );
    assert_eq!(bench.raw(request.as_bytes()).0, 403);
    let (status, _) = bench.send("GET", "/api/sheets", &format!("Origin: http://localhost:{}\r\n", bench.port), "");
    assert_eq!(status, 200);
}

#[test]
fn a_path_outside_the_served_ones_is_not_found() {
    let bench = Bench::start("chamfer.xlsx");
    for path in
        ["/../Cargo.toml", "/etc/passwd", "/api/../../chamfer.xlsx", "/chamfer.xlsx", "/api/nothing", "/%2e%2e/x"]
    {
        let (status, body) = bench.send("GET", path, "", "");
        assert_eq!(status, 404, "{path}: {body}");
        assert!(!body.contains("PK"), "{path} served a file");
    }
}

#[test]
fn a_thousand_malformed_requests_leave_the_server_answering() {
    let bench = Bench::start("chamfer.xlsx");
    let host = format!("Host: 127.0.0.1:{}\r\n", bench.port);
    let token = format!("{TOKEN_HEADER}: {}\r\n", bench.token);
    let bodies = [
        "",
        "{",
        "[]",
        "null",
        "{\"sheet\":-1}",
        "{\"sheet\":99,\"r\":0,\"c\":0,\"input\":\"1\",\"window\":{}}",
        "{\"sheet\":1,\"r\":1e30,\"c\":0,\"input\":\"1\"}",
        "{\"sheet\":1,\"r\":0,\"c\":0,\"input\":7}",
        "{\"window\":{\"sheet\":1,\"r0\":5,\"r1\":1,\"c0\":0,\"c1\":0}}",
        "\u{0}\u{1}\u{2}",
        "{\"name\":\"../x.xlsx\"}",
        "{\"name\":\"/tmp/x.xlsx\",\"over\":true}",
        "{\"source\":\"file:/etc/passwd\",\"sub\":\"\",\"dialect\":\"iso\",\"sheet\":0}",
    ];
    let queries = [
        "/api/cells",
        "/api/cells?sheet=x",
        "/api/cells?sheet=1&r0=0&r1=99999999&c0=0&c1=1",
        "/api/cells?sheet=1&r0=9&r1=1&c0=0&c1=1",
        "/api/locate?sheet=1&name=%ZZ",
        "/api/inspect?sheet=7&r=0&c=0",
        "/api/download?format=exe&sheet=0",
        "/api/download?format=csv",
        "/api/losses?format=csv&sheet=9",
        "/api/chamfer?sheet=1&r=0&c=0",
        "/api/locate?sheet=1",
    ];
    let posts = ["/api/set", "/api/undo", "/api/redo", "/api/save", "/api/run"];
    for i in 0..1000 {
        let request: Vec<u8> = match i % 5 {
            0 => format!("GARBAGE{i} \u{7f}\r\n\r\n").into_bytes(),
            1 => format!("GET {} HTTP/1.1\r\n{host}{token}Connection: close\r\n\r\n", queries[i % queries.len()])
                .into_bytes(),
            2 => {
                let body = bodies[i % bodies.len()];
                let path = posts[i % posts.len()];
                format!(
                    "POST {path} HTTP/1.1\r\n{host}{token}Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
                    body.len()
                )
                .into_bytes()
            }
            3 => format!("GET / HTTP/1.1\r\n{host}Content-Length: -{i}\r\nConnection: close\r\n\r\n").into_bytes(),
            _ => {
                let mut bytes = format!("GET /api/sheets HTTP/1.1\r\n{host}X-Bad: ").into_bytes();
                bytes.extend([0xff, 0xfe, 0x00, b'\r', b'\n', b'\r', b'\n']);
                bytes
            }
        };
        let (status, body) = bench.raw(&request);
        assert!(status == 0 || (400..500).contains(&status), "request {i} answered {status}: {body}");
    }
    let summary = bench.get_json("/api/sheets");
    assert_eq!(summary["sheets"][OUTER as usize]["name"], "Outer");
}

#[test]
fn an_edit_answers_the_changed_cells_and_undo_brings_the_old_values_back() {
    let bench = Bench::start("chamfer.xlsx");
    let located = bench.get_json("/api/locate?sheet=0&name=Outer!B8");
    assert_eq!((located["sheet"].as_u64(), located["r"].as_u64(), located["c"].as_u64()), (Some(1), Some(7), Some(1)));
    // The sheet-level name alpha of Outer is B8 too.
    let alpha = bench.get_json("/api/locate?sheet=1&name=alpha");
    assert_eq!((alpha["r"].as_u64(), alpha["c"].as_u64()), (Some(7), Some(1)));

    let window: Value = serde_json::from_str(WINDOW).unwrap();
    let set = serde_json::json!({ "sheet": OUTER, "r": 7, "c": 1, "input": "30", "window": window });
    let (status, answer) = bench.post_json("/api/set", &set);
    assert_eq!(status, 200, "{answer}");
    assert_eq!((answer["history"]["undo"].as_u64(), answer["history"]["redo"].as_u64()), (Some(1), Some(0)));
    // docs/domain.md §1: outer chamfer D 40, f 2, α 30°, r 0.8, eA 1, eB 1.
    let (xa, xb) = (changed(&answer, 5, 6), changed(&answer, 7, 6));
    assert!((xa["num"].as_f64().unwrap() - 42.3259818304895).abs() < 1e-12, "{xa}");
    assert!((xb["num"].as_f64().unwrap() - 35.8596588155657).abs() < 1e-12, "{xb}");
    assert_eq!(xa["shown"], "42.325982", "the cell's format is 0.000000");
    assert_eq!(xb["shown"], "35.859659");
    // Only cells that changed: the labels and inputs of the sheet are not sent again.
    assert!(answer["changed"].as_array().unwrap().len() < 30, "{answer}");
    assert!(!answer["changed"].as_array().unwrap().iter().any(|c| c["r"] == 5 && c["c"] == 0));

    let (status, undone) = bench.post_json("/api/undo", &serde_json::json!({ "window": window }));
    assert_eq!(status, 200, "{undone}");
    // The values Excel cached in the file for α = 45°.
    assert!((changed(&undone, 5, 6)["num"].as_f64().unwrap() - 44.262741699796955).abs() < 1e-12);
    assert!((changed(&undone, 7, 6)["num"].as_f64().unwrap() - 33.06274169979695).abs() < 1e-12);
    assert_eq!(changed(&undone, 7, 1)["input"], "45");
    assert_eq!((undone["history"]["undo"].as_u64(), undone["history"]["redo"].as_u64()), (Some(0), Some(1)));
    let (status, redone) = bench.post_json("/api/redo", &serde_json::json!({ "window": window }));
    assert_eq!(status, 200);
    assert!((changed(&redone, 5, 6)["num"].as_f64().unwrap() - 42.3259818304895).abs() < 1e-12);
    let (status, nothing) = bench.post_json("/api/redo", &serde_json::json!({ "window": window }));
    assert_eq!(status, 400, "{nothing}");
}

#[test]
fn a_cell_shows_what_it_reads_and_what_reads_it() {
    let bench = Bench::start("chamfer.xlsx");
    // Outer!G6 is =C21; Summary!C5 is =Outer!G6.
    let g6 = bench.get_json("/api/inspect?sheet=1&r=5&c=6");
    let names = |list: &Value| {
        list.as_array().unwrap().iter().map(|m| m["name"].as_str().unwrap().to_string()).collect::<Vec<_>>()
    };
    assert_eq!(names(&g6["precedents"]), ["Outer!C21"]);
    assert_eq!(names(&g6["dependents"]), ["Summary!C5"]);
}

#[test]
fn a_formula_error_is_explained_where_it_is_shown() {
    let bench = Bench::start("chamfer.xlsx");
    let window: Value = serde_json::from_str(WINDOW).unwrap();
    let set = serde_json::json!({ "sheet": OUTER, "r": 30, "c": 9, "input": "=NOSUCH(1)", "window": window });
    let (status, answer) = bench.post_json("/api/set", &set);
    assert_eq!(status, 200);
    let cell = changed(&answer, 30, 9);
    assert_eq!(cell["shown"], "#NAME?");
    assert!(cell["explain"].as_str().unwrap().contains("unknown function NOSUCH"), "{cell}");
    let refused = serde_json::json!({ "sheet": OUTER, "r": 30, "c": 9, "input": "=1+*2", "window": window });
    let (status, answer) = bench.post_json("/api/set", &refused);
    assert_eq!(status, 400, "a formula that does not parse is refused: {answer}");
    assert!(answer["error"].as_str().unwrap().starts_with("Outer!J31"), "{answer}");
}

#[test]
fn saving_writes_beside_the_workbook_and_over_it_only_when_asked() {
    let bench = Bench::start("chamfer.xlsx");
    let original = std::fs::read(bench.file("chamfer.xlsx")).unwrap();
    let losses = bench.get_json("/api/losses?format=xlsx&sheet=1");
    assert!(losses["losses"].is_array(), "{losses}");
    let (status, answer) = bench.post_json("/api/save", &serde_json::json!({ "name": "../escape.xlsx" }));
    assert_eq!(status, 400, "{answer}");
    let (status, answer) = bench.post_json("/api/save", &serde_json::json!({ "name": "chamfer.xlsx" }));
    assert_eq!(status, 409, "{answer}");
    assert_eq!(std::fs::read(bench.file("chamfer.xlsx")).unwrap(), original);

    let window: Value = serde_json::from_str(WINDOW).unwrap();
    let set = serde_json::json!({ "sheet": OUTER, "r": 7, "c": 1, "input": "30", "window": window });
    assert_eq!(bench.post_json("/api/set", &set).0, 200);
    let (status, answer) = bench.post_json("/api/save", &serde_json::json!({ "name": "edited.xlsx" }));
    assert_eq!(status, 200, "{answer}");
    let saved = ncsheet::document::Document::open_file(&bench.file("edited.xlsx"), &Default::default()).unwrap();
    let (sheet, g6) = saved.cell("Outer!G6").unwrap();
    let ncsheet::eval::Value::Number(xa) = saved.workbook().value(sheet, g6) else { panic!("G6 is no number") };
    assert!((xa - 42.3259818304895).abs() < 1e-12);
    let (status, _) = bench.post_json("/api/save", &serde_json::json!({ "name": "edited.xlsx" }));
    assert_eq!(status, 409, "an existing file is not replaced by a save-as");
    let (status, answer) = bench.post_json("/api/save", &serde_json::json!({ "name": "chamfer.xlsx", "over": true }));
    assert_eq!(status, 200, "{answer}");
    assert_ne!(std::fs::read(bench.file("chamfer.xlsx")).unwrap(), original);
    // A csv holds one sheet: the shown one's values as its cells show them, the loss said.
    let losses = bench.get_json("/api/losses?format=csv&sheet=1");
    assert!(losses["losses"][0].as_str().unwrap().contains("other 3 sheet(s)"), "{losses}");
    let (status, answer) = bench.post_json("/api/save", &serde_json::json!({ "name": "outer.csv", "sheet": 1 }));
    assert_eq!(status, 200, "{answer}");
    let saved = std::fs::read_to_string(bench.file("outer.csv")).unwrap();
    assert!(saved.lines().nth(7).unwrap().starts_with("α,30,°,"), "{saved}");
    let (status, csv) = bench.send("GET", "/api/download?format=csv&sheet=1", "", "");
    assert_eq!(status, 200, "{csv}");
    let row8 = csv.lines().nth(7).unwrap();
    assert!(row8.starts_with("α,30,°,"), "{row8}");
    assert!(csv.lines().nth(5).unwrap().contains(",XA,42.325982,mm"), "{csv}");
}

/// docs/domain.md §1, the outer chamfer D 40, f 2, α 45°, r 0.8, eA 1, eB 1.
const XA_45: f64 = 44.2627416997970;
const ZA_45: f64 = -4.6;
const XB_45: f64 = 33.0627416997970;
const ZB_45: f64 = 1.0;

#[test]
fn a_cell_calling_chamfer_gives_its_construction() {
    let bench = Bench::start("chamfer-builtin.csv");
    // H2 is =CHAMFER(A2,B2,C2,D2,E2,F2,G2) over outer, 40, 2, 45, 0.8, 1, 1.
    let g = bench.get_json("/api/chamfer?sheet=0&r=1&c=7");
    let num = |k: &str| g[k].as_f64().unwrap_or_else(|| panic!("{k} in {g}"));
    for (got, want) in [(num("xa"), XA_45), (num("za"), ZA_45), (num("xb"), XB_45), (num("zb"), ZB_45)] {
        assert!((got - want).abs() < 1e-9, "{got} vs {want}: {g}");
    }
    // The chamfer line runs from A = (-f, D/2) to B = (0, D/2 - f·tan α).
    assert_eq!((g["a"]["z"].as_f64(), g["a"]["x"].as_f64()), (Some(-2.0), Some(20.0)));
    assert!((g["b"]["x"].as_f64().unwrap() - 18.0).abs() < 1e-12);
    assert_eq!(g["kind"], "outer");
    let (status, body) = bench.send("GET", "/api/chamfer?sheet=0&r=1&c=0", "", "");
    assert_eq!(status, 400, "a constant calls no CHAMFER: {body}");
}

#[test]
fn a_macro_beside_the_workbook_runs_into_a_program_and_its_backplot() {
    let bench = Bench::with_macros("chamfer.xlsx", &["chamfer.bas"]);
    let macros = bench.get_json("/api/macros");
    let source = &macros["sources"][0];
    assert_eq!(source["source"], "file:chamfer.bas", "{macros}");
    assert!(source["subs"].as_array().unwrap().iter().any(|s| s == "Main"), "{macros}");
    let run = serde_json::json!({ "source": "file:chamfer.bas", "sub": "Main", "dialect": "linuxcnc", "sheet": OUTER });
    let (status, out) = bench.post_json("/api/run", &run);
    assert_eq!(status, 200, "{out}");
    let lines: Vec<&str> = out["lines"].as_array().unwrap().iter().map(|l| l.as_str().unwrap()).collect();
    assert!(out["svg"].as_str().unwrap().starts_with("<svg"), "{out}");
    // The two feed moves end at T1 and T2 (X a radius in the backplot, a diameter in the
    // program), and the program's lines they come from say the same to the dialect's digits.
    let feeds: Vec<&Value> = out["moves"].as_array().unwrap().iter().filter(|m| m["rapid"] == false).collect();
    assert_eq!(feeds.len(), 2, "{out}");
    for (feed, (x, z)) in feeds.iter().zip([(XA_45, ZA_45), (XB_45, ZB_45)]) {
        let to = &feed["to"];
        assert!(
            (to[0].as_f64().unwrap() * 2.0 - x).abs() < 1e-3 && (to[2].as_f64().unwrap() - z).abs() < 1e-3,
            "{feed}"
        );
        let line = lines[feed["line"].as_u64().unwrap() as usize - 1];
        assert!(line.contains(&format!("X{:.3}", x)) && line.contains('Z'), "{line}");
    }
    let (status, refused) = bench.post_json(
        "/api/run",
        &serde_json::json!({ "source": "file:../x.bas", "sub": "", "dialect": "iso", "sheet": 0 }),
    );
    assert_eq!(status, 400, "{refused}");
}

#[test]
fn a_window_reaches_the_last_row_of_a_large_sheet() {
    let bench = Bench::big_sheet(100_000);
    let summary = bench.get_json("/api/sheets");
    assert_eq!(summary["sheets"][0]["rows"], 100_000);
    let window = bench.get_json("/api/cells?sheet=0&r0=99990&r1=99999&c0=0&c1=1");
    let last = window["cells"].as_array().unwrap().iter().find(|c| c["r"] == 99_999 && c["c"] == 1).unwrap();
    assert_eq!(last["num"], 200_000.0);
    assert_eq!(last["input"], "=A100000*2");
    let (status, _) = bench.send("GET", "/api/cells?sheet=0&r0=0&r1=5000&c0=0&c1=1", "", "");
    assert_eq!(status, 400, "a window is at most a screen, many times over");
}

#[test]
fn a_spilled_range_is_marked_for_the_grid() {
    let folder = tempfile::tempdir().unwrap();
    let file = folder.path().join("spill.csv");
    std::fs::write(&file, "=SEQUENCE(3)*10,5\n").unwrap();
    let server = Server::open(&file, &Options::default()).unwrap();
    let bench = Bench { port: server.port(), token: server.token().to_string(), folder };
    std::thread::spawn(move || server.run());
    let window = bench.get_json("/api/cells?sheet=0&r0=0&r1=4&c0=0&c1=1");
    let cells = window["cells"].as_array().unwrap();
    let at = |r: u64, c: u64| cells.iter().find(|x| x["r"] == r && x["c"] == c).unwrap_or_else(|| panic!("{window}"));
    assert_eq!((at(0, 0)["spill"].as_str(), at(0, 0)["shown"].as_str()), (Some("anchor"), Some("10")));
    assert_eq!((at(2, 0)["spill"].as_str(), at(2, 0)["shown"].as_str()), (Some("item"), Some("30")));
    assert_eq!(at(0, 1)["spill"], Value::Null, "a constant is no spill");
    assert_eq!(cells.len(), 4);
}

/// The largest window, 200,000 cells whose formulas do not parse (`=1+`), above 100,000
/// formulas that spill: it holds each of its cells once and no other, each with its own
/// explanation, and no spill mark of the anchors below it; a window one row or one column
/// larger is refused, so an answer is at most that many cells. (Each cell shown looked through
/// all the workbook's problems and all the sheet's spill anchors, minutes a window; the time of
/// one window is `ncsheet-bench-window`'s, benches/README.md.)
#[test]
fn a_window_shows_its_own_cells_whatever_the_sheet_holds_elsewhere() {
    let (rows, cols) = (1000u64, 200u64);
    let broken = vec!["=1+"; cols as usize].join(",");
    let mut text = format!("{broken}\n").repeat(rows as usize);
    text.push_str(&"\"=SEQUENCE(1,2)\"\n".repeat(100_000));
    let bench = Bench::written("many.csv", &text, &[], ncsheet::document::OpenOptions::default());
    let window = bench.get_json(&format!("/api/cells?sheet=0&r0=0&r1={}&c0=0&c1={}", rows - 1, cols - 1));
    let cells = window["cells"].as_array().unwrap();
    let places: std::collections::HashSet<(u64, u64)> =
        cells.iter().map(|c| (c["r"].as_u64().unwrap(), c["c"].as_u64().unwrap())).collect();
    assert_eq!((cells.len(), places.len()), (200_000, 200_000), "each cell of the window once");
    assert!(places.iter().all(|&(r, c)| r < rows && c < cols), "a cell outside the window");
    for cell in cells {
        assert_eq!(cell["spill"], Value::Null, "no anchor is inside the window: {cell}");
        // Each explanation is the `=1+` of its cell, with the caret under its column 4.
        let explain = cell["explain"].as_str().unwrap_or_else(|| panic!("{cell}"));
        assert!(explain.contains("=1+") && explain.contains("column 4"), "{cell}");
    }
    for past in [format!("r0=0&r1={rows}&c0=0&c1={}", cols - 1), format!("r0=0&r1={}&c0=0&c1={cols}", rows - 1)] {
        let (status, body) = bench.send("GET", &format!("/api/cells?sheet=0&{past}"), "", "");
        assert_eq!(status, 400, "{past}: {body}");
    }
    let below = bench.get_json("/api/cells?sheet=0&r0=1000&r1=1001&c0=0&c1=1");
    let at = |r: u64, c: u64| below["cells"].as_array().unwrap().iter().find(|x| x["r"] == r && x["c"] == c).cloned();
    assert_eq!(at(1000, 0).map(|x| x["spill"].clone()), Some(Value::from("anchor")), "{below}");
    assert_eq!(at(1000, 1).map(|x| x["spill"].clone()), Some(Value::from("item")), "{below}");
}

/// A process killed however the test that started it ends.
struct Killed(std::process::Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// `ncsheet serve` on a copy of sheets/chamfer.xlsx with `extra` arguments: the running
/// server, its port and the query of the URL it printed.
fn serve_command(folder: &Path, extra: &[&str]) -> (Killed, u16, String) {
    let file = folder.join("chamfer.xlsx");
    std::fs::copy(Path::new(env!("CARGO_MANIFEST_DIR")).join("sheets/chamfer.xlsx"), &file).unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(["serve", file.to_str().unwrap()])
        .args(extra)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut child = Killed(child);
    let mut line = String::new();
    BufReader::new(child.0.stdout.take().unwrap()).read_line(&mut line).unwrap();
    let url = line.trim().to_string();
    let rest = url.strip_prefix("http://127.0.0.1:").unwrap_or_else(|| panic!("{url}"));
    let (port, query) = rest.split_once('/').unwrap();
    (child, port.parse().unwrap(), query.to_string())
}

/// The page as a browser first asks for it, by the printed URL.
fn page_answer(port: u16, query: &str) -> String {
    let mut stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
    write!(stream, "GET /{query} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n\r\n").unwrap();
    let mut answer = String::new();
    stream.read_to_string(&mut answer).unwrap();
    answer
}

#[test]
fn the_command_prints_the_url_and_serves_the_page() {
    let folder = tempfile::tempdir().unwrap();
    let (_server, port, query) = serve_command(folder.path(), &[]);
    let answer = page_answer(port, &query);
    assert!(answer.starts_with("HTTP/1.1 200"), "{answer}");
    assert!(query.starts_with("?t=") && query.len() == 3 + 32, "{query}");
}

/// The page in Chromium: select Outer!B8, type 30, read XA and XB; undo; run chamfer.bas for a
/// lathe; a ball path drawn in 3D by WebGL (its pixels read back), orbited and zoomed;
/// screenshots of the grid, the pane and the 3D view into docs/. Skipped without chromium,
/// chromium-driver or selenium, except on CI.
#[test]
fn the_page_in_a_real_browser() {
    let missing = ["chromium", "chromedriver"]
        .into_iter()
        .find(|tool| Command::new("which").arg(tool).output().map_or(true, |o| !o.status.success()));
    let selenium = Command::new("python3").args(["-c", "import selenium"]).status().is_ok_and(|s| s.success());
    let why = match (missing, selenium) {
        (Some(tool), _) => Some(format!("{tool} is not installed (Debian chromium, chromium-driver)")),
        (None, false) => Some("python selenium is not installed (pip install selenium)".to_string()),
        (None, true) => None,
    };
    if let Some(why) = why {
        assert!(std::env::var_os("CI").is_none(), "the browser test cannot run on CI: {why}");
        eprintln!("skipped: {why}");
        return;
    }
    let bench = Bench::with_macros("chamfer.xlsx", &["chamfer.bas"]);
    let big = Bench::big_sheet(100_000);
    let ball = Bench::start("eqcam-bump.csv");
    let url = |b: &Bench| format!("http://127.0.0.1:{}/?t={}", b.port, b.token);
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let docs = root.join("docs");
    let out = Command::new("python3")
        .arg(root.join("tests/workbench_browser.py"))
        .args([url(&bench), url(&big)])
        .arg(&docs)
        .arg(bench.folder.path().join("chrome-profile"))
        .arg(url(&ball))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("ok"), "{stdout}");
    eprint!("{stdout}");
    for shot in ["workbench-grid.png", "workbench-machining.png", "workbench-ballpath-3d.png"] {
        assert!(std::fs::metadata(docs.join(shot)).unwrap().len() > 10_000, "{shot}");
    }
}

#[test]
fn the_workbook_is_read_with_the_command_lines_locale_and_limits() {
    // German Excel reads the text "0,5" as one half where a formula computes with it; read as
    // en-US it is no number.
    let text = "\"=\"\"0,5\"\"*2\"\n";
    let mut settings = ncsheet::eval::Settings::default();
    settings.locale = ncsheet::eval::Locale::from_tag("de-DE").unwrap();
    let open = ncsheet::document::OpenOptions { settings: Some(settings), ..Default::default() };
    let bench = Bench::written("half.csv", text, &[], open);
    let window = bench.get_json("/api/cells?sheet=0&r0=0&r1=0&c0=0&c1=0");
    assert_eq!(window["cells"][0]["num"].as_f64(), Some(1.0), "{window}");
    let english = Bench::written("half.csv", text, &[], Default::default());
    let window = english.get_json("/api/cells?sheet=0&r0=0&r1=0&c0=0&c1=0");
    assert_eq!(window["cells"][0]["shown"], "#VALUE!", "{window}");
    // The csv's separator is the one the options name: with ',' the line 1;2 is one field.
    let comma = ncsheet::document::OpenOptions { csv_delimiter: Some(b','), ..Default::default() };
    let bench = Bench::written("pair.csv", "1;2\n", &[], comma);
    let window = bench.get_json("/api/cells?sheet=0&r0=0&r1=0&c0=0&c1=1");
    let cells = window["cells"].as_array().unwrap();
    assert_eq!((cells.len(), cells[0]["shown"].as_str()), (1, Some("1;2")), "{window}");
    // A field longer than --max-csv-field allows is refused at opening, naming the file.
    let folder = tempfile::tempdir().unwrap();
    let file = folder.path().join("long.csv");
    std::fs::write(&file, "1,123456789012345678901234567890\n").unwrap();
    let mut open = ncsheet::document::OpenOptions::default();
    open.read_limits.csv_field_bytes = 8;
    let refused = Server::open(&file, &Options { open, ..Options::default() }).err().expect("a field over the limit");
    assert!(refused.to_string().contains("long.csv"), "{refused}");
}

/// A macro that types α = 30° into Outer!B8 and a note into C30.
const WRITING_MACRO: &str = "Attribute VB_Name = \"Alpha\"\r\nSub Main()\r\n    Range(\"B8\").Value = 30\r\n    Range(\"C30\").Value = \"written\"\r\nEnd Sub\r\n";

#[test]
fn a_macros_writes_are_one_step_of_undo() {
    let sheets = Path::new(env!("CARGO_MANIFEST_DIR")).join("sheets");
    let bytes = std::fs::read(sheets.join("chamfer.xlsx")).unwrap();
    let folder = tempfile::tempdir().unwrap();
    std::fs::write(folder.path().join("chamfer.xlsx"), bytes).unwrap();
    std::fs::write(folder.path().join("alpha.bas"), WRITING_MACRO).unwrap();
    let macro_files = vec![folder.path().join("alpha.bas")];
    let server =
        Server::open(&folder.path().join("chamfer.xlsx"), &Options { port: 0, macro_files, ..Options::default() })
            .unwrap();
    let bench = Bench { port: server.port(), token: server.token().to_string(), folder };
    std::thread::spawn(move || server.run());

    let run = serde_json::json!({ "source": "file:alpha.bas", "sub": "Main", "dialect": "linuxcnc", "machine": "lathe", "sheet": OUTER });
    let (status, out) = bench.post_json("/api/run", &run);
    assert_eq!(status, 200, "{out}");
    assert_eq!((out["history"]["undo"].as_u64(), out["history"]["redo"].as_u64()), (Some(1), Some(0)), "{out}");
    // docs/domain.md §1 for α = 30°.
    assert!((api_number(&bench, 5, 6) - 42.3259818304895).abs() < 1e-12);
    assert!((api_number(&bench, 7, 6) - 35.8596588155657).abs() < 1e-12);

    let window: Value = serde_json::from_str(WINDOW).unwrap();
    let (status, undone) = bench.post_json("/api/undo", &serde_json::json!({ "window": window }));
    assert_eq!(status, 200, "{undone}");
    // Both writes taken back at once: Excel's cached values for α = 45° and no note.
    assert_eq!(changed(&undone, 7, 1)["input"], "45");
    assert_eq!(changed(&undone, 29, 2)["input"], "");
    assert!((changed(&undone, 5, 6)["num"].as_f64().unwrap() - 44.262741699796955).abs() < 1e-12);
    assert!((changed(&undone, 7, 6)["num"].as_f64().unwrap() - 33.06274169979695).abs() < 1e-12);
    assert_eq!((undone["history"]["undo"].as_u64(), undone["history"]["redo"].as_u64()), (Some(0), Some(1)));
    let (status, redone) = bench.post_json("/api/redo", &serde_json::json!({ "window": window }));
    assert_eq!(status, 200, "{redone}");
    assert_eq!(changed(&redone, 29, 2)["input"], "written");
    assert!((changed(&redone, 5, 6)["num"].as_f64().unwrap() - 42.3259818304895).abs() < 1e-12);
}

/// A cell of `sheet` from the API: its input and the number it shows (`None`: not a number).
fn api_cell(bench: &Bench, sheet: u64, row: u64, col: u64) -> (String, Option<f64>) {
    let window = bench.get_json(&format!("/api/cells?sheet={sheet}&r0={row}&r1={row}&c0={col}&c1={col}"));
    let cell = &window["cells"][0];
    (cell["input"].as_str().unwrap_or_default().to_string(), cell["num"].as_f64())
}

// A macro deleting a sheet is one step of the history, as its writes are: undo brings the
// sheet back with its cells, and the formulas and names that pointed to it read it again;
// redo deletes it again. Values by hand: Gone!A2 = 5*2, Keep!A1 = 10+1, Keep!B1 = Total = 5.
#[test]
fn undo_brings_back_a_sheet_a_macro_deleted() {
    let folder = tempfile::tempdir().unwrap();
    let book = folder.path().join("two.xlsx");
    let mut wb = ncsheet::workbook::Workbook::new();
    wb.add_sheet("Keep").unwrap();
    wb.add_sheet("Gone").unwrap();
    let at = |cell: &str| ncsheet::formula::address::parse_cell(cell).unwrap();
    wb.define_name("Total", "=Gone!$A$1", None).unwrap();
    for (sheet, cell, input) in [(1, "A1", "5"), (1, "A2", "=A1*2"), (0, "A1", "=Gone!A2+1"), (0, "B1", "=Total")] {
        wb.set_input(sheet, at(cell), input).unwrap();
    }
    ncsheet::io::save(&wb, &book).unwrap();
    let bas = folder.path().join("gone.bas");
    std::fs::write(&bas, "Sub Main()\r\n    Worksheets(\"Gone\").Delete\r\nEnd Sub\r\n").unwrap();
    let server = Server::open(&book, &Options { port: 0, macro_files: vec![bas], ..Options::default() }).unwrap();
    let bench = Bench { port: server.port(), token: server.token().to_string(), folder };
    std::thread::spawn(move || server.run());

    let run = serde_json::json!({ "source": "file:gone.bas", "sub": "Main", "dialect": "linuxcnc", "machine": "lathe", "sheet": 0 });
    let (status, out) = bench.post_json("/api/run", &run);
    assert_eq!(status, 200, "{out}");
    assert_eq!(bench.get_json("/api/sheets")["order"], serde_json::json!([0]));
    assert_eq!(api_cell(&bench, 0, 0, 0).1, None, "Keep!A1 is #REF! once Gone is deleted");

    let window = serde_json::json!({ "sheet": 0, "r0": 0, "r1": 5, "c0": 0, "c1": 5 });
    let (status, undone) = bench.post_json("/api/undo", &serde_json::json!({ "window": window }));
    assert_eq!(status, 200, "{undone}");
    assert_eq!(bench.get_json("/api/sheets")["order"], serde_json::json!([0, 1]));
    assert_eq!(api_cell(&bench, 1, 1, 0), ("=A1*2".to_string(), Some(10.0)));
    assert_eq!(api_cell(&bench, 0, 0, 0), ("=Gone!A2+1".to_string(), Some(11.0)));
    assert_eq!(api_cell(&bench, 0, 0, 1), ("=Total".to_string(), Some(5.0)));

    let (status, redone) = bench.post_json("/api/redo", &serde_json::json!({ "window": window }));
    assert_eq!(status, 200, "{redone}");
    assert_eq!(bench.get_json("/api/sheets")["order"], serde_json::json!([0]));
    assert_eq!(api_cell(&bench, 0, 0, 0).1, None);
}

/// The number a cell of Outer holds, from the API.
fn api_number(bench: &Bench, row: u64, col: u64) -> f64 {
    let window = bench.get_json(&format!("/api/cells?sheet={OUTER}&r0={row}&r1={row}&c0={col}&c1={col}"));
    window["cells"][0]["num"].as_f64().unwrap_or_else(|| panic!("{window}"))
}

#[test]
fn the_runner_offers_each_dialect_for_its_machines_and_hands_the_program_over() {
    let bench = Bench::with_macros("chamfer.xlsx", &["chamfer.bas"]);
    let macros = bench.get_json("/api/macros");
    let dialects = macros["dialects"].as_array().unwrap();
    let names: Vec<&str> = dialects.iter().map(|d| d["name"].as_str().unwrap()).collect();
    let wanted: Vec<&str> = ncsheet::nc::dialect::all().iter().map(|d| d.name()).collect();
    assert_eq!(names, wanted);
    // Heidenhain's plain language is a milling control's (docs: TNC 640 manual).
    let heidenhain = dialects.iter().find(|d| d["name"] == "heidenhain").unwrap();
    assert_eq!(heidenhain["machines"], serde_json::json!(["mill"]));
    let refused = serde_json::json!({ "source": "file:chamfer.bas", "sub": "Main", "dialect": "heidenhain", "machine": "lathe", "sheet": OUTER });
    let (status, body) = bench.post_json("/api/run", &refused);
    assert_eq!(status, 400, "{body}");
    assert!(body["error"].as_str().unwrap().contains("heidenhain"), "{body}");

    let run = serde_json::json!({ "source": "file:chamfer.bas", "sub": "Main", "dialect": "iso", "machine": "lathe", "sheet": OUTER });
    let (status, out) = bench.post_json("/api/run", &run);
    assert_eq!(status, 200, "{out}");
    assert_eq!(out["download"], "chamfer.nc");
    // The program handed over, read by the library's NC reader: its feed moves end at T1
    // and T2 (docs/domain.md §1 via Excel's cached values), as the backplot's do.
    let text = out["program"].as_str().unwrap();
    let program =
        ncsheet::nc::read::read_dialect(text, &ncsheet::nc::dialect::ISO, Some(ncsheet::nc::Machine::Lathe)).unwrap().0;
    let path = ncsheet::nc::backplot::toolpath(&program).unwrap();
    let feeds: Vec<_> = path.moves.iter().filter(|m| m.kind == ncsheet::nc::backplot::MoveKind::Feed).collect();
    assert_eq!(feeds.len(), 2);
    for (feed, (x, z)) in feeds.iter().zip([(XA_45, ZA_45), (XB_45, ZB_45)]) {
        assert!((feed.to[0] * 2.0 - x).abs() < 1e-3 && (feed.to[2] - z).abs() < 1e-3, "{feed:?}");
    }
    let plotted = out["moves"].as_array().unwrap();
    let last = &plotted[plotted.len() - 1]["to"];
    let end = path.moves.last().unwrap().to;
    for i in 0..3 {
        assert!((last[i].as_f64().unwrap() - end[i]).abs() < 1e-9, "{last} vs {end:?}");
    }
}

#[test]
fn an_arch_fit_cell_shows_its_arcs_over_the_true_spiral() {
    // An Archimedean piece from r 40 at 0° to r 60 at 90°, to 0.01 mm.
    let bench = Bench::written("arch.csv", "\"=ARCH_FIT(\"\"arch\"\",40,0,60,90,0.01)\"\n", &[], Default::default());
    let g = bench.get_json("/api/archfit?sheet=0&r=0&c=0");
    let spiral_r = |phi_deg: f64| 40.0 + 20.0 * phi_deg / 90.0;
    // The curve the page draws is the spiral r(φ) = r0 + (r1 − r0)(φ − φ0)/(φ1 − φ0).
    for p in g["curve"].as_array().unwrap() {
        let (x, y) = (p["x"].as_f64().unwrap(), p["y"].as_f64().unwrap());
        let phi = y.atan2(x).to_degrees();
        assert!(((x * x + y * y).sqrt() - spiral_r(phi)).abs() < 1e-9, "{p}");
        assert!(p["d"].as_f64().unwrap() <= 0.01 + 1e-9, "{p}");
    }
    let arcs = g["arcs"].as_array().unwrap();
    assert!(arcs.len() >= 2, "{g}");
    // Each arc's ends lie on its circle, the first starts at (40, 0), the last ends at (0, 60),
    // and every joint is within the tolerance of the spiral.
    let at = |v: &Value| (v[0].as_f64().unwrap(), v[1].as_f64().unwrap());
    let first = at(&arcs[0]["start"]);
    let last = at(&arcs[arcs.len() - 1]["end"]);
    assert!((first.0 - 40.0).abs() < 1e-9 && first.1.abs() < 1e-9, "{first:?}");
    assert!(last.0.abs() < 1e-9 && (last.1 - 60.0).abs() < 1e-9, "{last:?}");
    for a in arcs {
        let (c, r) = (at(&a["centre"]), a["radius"].as_f64().unwrap());
        for end in [at(&a["start"]), at(&a["end"])] {
            assert!((((end.0 - c.0).powi(2) + (end.1 - c.1).powi(2)).sqrt() - r).abs() < 1e-6 * r, "{a}");
            let phi = end.1.atan2(end.0).to_degrees();
            assert!(((end.0 * end.0 + end.1 * end.1).sqrt() - spiral_r(phi)).abs() <= 0.01 + 1e-9, "{a}");
        }
    }
    assert!(g["deviation"].as_f64().unwrap() <= 0.01 + 1e-6, "{g}");
}

#[test]
fn a_ballpath_cell_shows_its_path_in_plan_section_and_points() {
    let bench = Bench::start("eqcam-bump.csv");
    // A13 spills the tip path over z = 15·exp(−16((x/50)² + (y/50)²)), x, y in −25..25 mm.
    let g = bench.get_json("/api/ballpath?sheet=0&r=12&c=0");
    let count = g["count"].as_u64().unwrap() as usize;
    let points = g["points"].as_array().unwrap();
    assert_eq!(points.len(), 3 * count);
    let surface = |x: f64, y: f64| 15.0 * (-16.0 * ((x / 50.0).powi(2) + (y / 50.0).powi(2))).exp();
    let mut apex = None;
    for p in points.chunks(3) {
        let (x, y, z) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap(), p[2].as_f64().unwrap());
        // The tip never dips into the part.
        assert!(z >= surface(x, y) - 1e-6, "({x}, {y}, {z})");
        if x.abs() < 1e-9 && y.abs() < 1e-9 {
            apex = Some(z);
        }
    }
    // Over the bump's top the ball touches at its tip: z = 15.
    assert!((apex.expect("a point over the apex") - 15.0).abs() < 1e-6);
    let plan = g["plan"].as_str().unwrap();
    let section = g["section"].as_str().unwrap();
    for part in ["id=\"grid\"", "id=\"graduations\"", "id=\"stock\""] {
        assert!(plan.contains(part) && section.contains(part), "{part}");
    }
    assert!(plan.contains("coloured by depth"), "the plan colours feeds by Z");
    assert!(section.contains("id=\"z0\""), "the section shows the Z0 face");
    assert_eq!(
        g["stock"],
        serde_json::json!([[-25.0, -25.0, points_min_z(points)], [25.0, 25.0, points_max_z(points)]])
    );
}

fn points_min_z(points: &[Value]) -> f64 {
    points.chunks(3).map(|p| p[2].as_f64().unwrap()).fold(f64::INFINITY, f64::min)
}

fn points_max_z(points: &[Value]) -> f64 {
    points.chunks(3).map(|p| p[2].as_f64().unwrap()).fold(f64::NEG_INFINITY, f64::max)
}

/// A raster of a million points: its backplot is thinned to what the drawing shows, in
/// paths small enough for rsvg-convert, which must open it when installed.
#[test]
fn a_million_point_backplot_stays_small_and_opens_in_rsvg() {
    use ncsheet::nc::backplot::{svg_drawing, Move, MoveKind, Plane, Toolpath};
    let (lines, per_line) = (1000, 1000);
    let mut points = Vec::with_capacity(lines * per_line);
    for j in 0..lines {
        for i in 0..per_line {
            let x = if j % 2 == 0 { i } else { per_line - 1 - i } as f64 * 0.05;
            let y = j as f64 * 0.05;
            points.push([x, y, -1.0 - (x / 10.0).sin() * (y / 10.0).cos()]);
        }
    }
    let moves: Vec<Move> = points
        .windows(2)
        .enumerate()
        .map(|(i, w)| Move { block: i + 1, kind: MoveKind::Feed, from: w[0], to: w[1], arc: None })
        .collect();
    let path = Toolpath { machine: ncsheet::nc::Machine::Mill, moves };
    let svg = svg_drawing(&path, Plane::Xy, "raster").unwrap();
    assert!(svg.len() < 8 << 20, "{} bytes", svg.len());
    let longest = svg.lines().filter(|l| l.starts_with("<path d=")).map(str::len).max().unwrap();
    assert!(longest < 200_000, "a path of {longest} bytes");
    let folder = tempfile::tempdir().unwrap();
    std::fs::write(folder.path().join("raster.svg"), &svg).unwrap();
    match Command::new("rsvg-convert")
        .arg(folder.path().join("raster.svg"))
        .arg("-o")
        .arg(folder.path().join("raster.png"))
        .output()
    {
        Ok(out) => assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr)),
        Err(_) => assert!(std::env::var_os("CI").is_none(), "rsvg-convert is not installed"),
    }
}

#[test]
fn a_cam_design_sheet_is_fitted_disc_by_disc() {
    let bench = Bench::start("cam-turret.csv");
    let fit = bench.get_json("/api/camsheet?sheet=0&tol=0.01");
    // The discs the sheet's disc column names, in order of first appearance.
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("sheets/cam-turret.csv")).unwrap();
    let mut named: Vec<String> = Vec::new();
    for line in text.lines().skip(1) {
        let fields: Vec<&str> = line.split(',').collect();
        // The operation may be quoted with a comma inside: the disc is third from the type.
        let Some(type_at) = fields.iter().position(|f| ["circle", "arch", "log", "parabola"].contains(f)) else {
            continue;
        };
        let disc = fields[type_at - 1].to_string();
        if !named.contains(&disc) {
            named.push(disc);
        }
    }
    let discs = fit["discs"].as_array().unwrap();
    let got: Vec<String> = discs.iter().map(|d| d["disc"].as_str().unwrap().to_string()).collect();
    assert_eq!(got, named, "{fit}");
    for d in discs {
        assert!(d["arcs"].as_u64().unwrap() > 0 && d["svg"].as_str().unwrap().starts_with("<svg"), "{}", d["disc"]);
    }
    let (status, body) = bench.send("GET", "/api/camsheet?sheet=0&tol=-1", "", "");
    assert_eq!(status, 400, "{body}");
}

/// A macro that never ends, each turn a statement costlier than a thousand plain ones: only
/// the clock stops it (the statement limit is hours away).
const ENDLESS_MACRO: &str = "Attribute VB_Name = \"Endless\"\r\nSub Main()\r\n    Dim x As Double\r\n    Do\r\n        x = x + Evaluate(\"SUM(SEQUENCE(20000))\")\r\n    Loop\r\nEnd Sub\r\n";

#[test]
fn serve_timeout_stops_a_macro_run_at_its_statement() {
    let options = Options { timeout: Some(0.5), ..Options::default() };
    let bench = Bench::written_with("book.csv", "1\n", &[("endless.bas", ENDLESS_MACRO)], options);
    let run = serde_json::json!({ "source": "file:endless.bas", "sub": "Main", "dialect": "iso", "machine": "lathe", "sheet": 0 });
    let (status, out) = bench.post_json("/api/run", &run);
    assert_eq!(status, 400, "the macro's own error, not the server's: {out}");
    let error = out["error"].as_str().unwrap();
    assert!(error.contains("--timeout of 0.5 s") && error.contains("endless.bas"), "{error}");
    let summary = bench.get_json("/api/sheets");
    assert_eq!(summary["file"], "book.csv");
}

/// A formula that computes for seconds in little memory: n sums of 1 + 2 + … + 1000, each
/// by a LAMBDA called 1000 times, n · 500500 in all. It must outlast two requests' --timeout
/// and grace (1.1 s) on a fast machine: 10,000 sums took 0.9 s in a test build, and the request
/// queued behind them ran.
const SLOW_SUMS: u64 = 50_000;

/// An edit whose recalculation outlasts `--timeout` (a formula cannot stop partway): its
/// request is answered with an error naming the limit while the workbook computes on; a
/// request queued behind it is refused and never carried out; the page is still served; and
/// the edit's value is there once the computation ends.
#[test]
fn serve_timeout_answers_a_long_recalculation_with_an_error() {
    let options = Options { timeout: Some(0.05), ..Options::default() };
    let bench = Bench::written_with("book.csv", "1\n", &[], options);
    let window = serde_json::json!({ "sheet": 0, "r0": 0, "r1": 5, "c0": 0, "c1": 3 });
    let slow = format!("=REDUCE(0,SEQUENCE({SLOW_SUMS}),LAMBDA(a,b,a+REDUCE(0,SEQUENCE(1000),LAMBDA(c,d,c+d))))");
    let edit =
        |c: u64, input: &str| serde_json::json!({ "sheet": 0, "r": 0, "c": c, "input": input, "window": window });
    let (status, answer) = bench.post_json("/api/set", &edit(1, &slow));
    assert_eq!(status, 503, "{answer}");
    let error = answer["error"].as_str().unwrap();
    assert!(error.contains("still computing after the --timeout of 0.05 s"), "{error}");
    let (status, answer) = bench.post_json("/api/set", &edit(2, "7"));
    assert_eq!(status, 503, "{answer}");
    assert!(answer["error"].as_str().unwrap().contains("was not carried out"), "{answer}");
    let page =
        format!("GET /?t={} HTTP/1.1\r\nHost: 127.0.0.1:{}\r\nConnection: close\r\n\r\n", bench.token, bench.port);
    assert_eq!(bench.raw(page.as_bytes()).0, 200, "the page is served while the workbook computes");
    // Each look waits at most --timeout and its grace.
    let cells = (0..600)
        .find_map(|_| {
            let (status, body) = bench.send("GET", "/api/cells?sheet=0&r0=0&r1=0&c0=0&c1=2", "", "");
            (status == 200).then(|| serde_json::from_str::<Value>(&body).unwrap())
        })
        .expect("the workbook answers again");
    let at = |c: u64| cells["cells"].as_array().unwrap().iter().find(|x| x["c"] == c).cloned();
    assert_eq!(at(1).unwrap()["num"].as_f64(), Some(SLOW_SUMS as f64 * 500_500.0), "{cells}");
    assert_eq!(at(2), None, "the refused edit was not made: {cells}");
    let summary = bench.get_json("/api/sheets");
    assert_eq!(summary["history"]["undo"], 1, "{summary}");
}

/// docs/domain.md §1's outer chamfer on Outer (D 40, f 2, α 45°): the chamfer runs from
/// A = (Z −f, X D/2) to B = (Z 0, X D/2 − f·tan α), X a radius in the backplot.
#[test]
fn a_macros_backplot_shows_the_workbooks_part_and_stock() {
    let bench = Bench::with_macros("chamfer.xlsx", &["chamfer.bas"]);
    let run = serde_json::json!({ "source": "file:chamfer.bas", "sub": "Main", "dialect": "linuxcnc", "machine": "lathe", "sheet": OUTER });
    let (status, out) = bench.post_json("/api/run", &run);
    assert_eq!(status, 200, "{out}");
    let part = &out["part"];
    let point = |v: &Value| [0, 1, 2].map(|i| v[i].as_f64().unwrap());
    let outline: Vec<[f64; 3]> = part["outline"].as_array().unwrap().iter().map(point).collect();
    let (radius, f, alpha) = (20.0, 2.0, 45f64.to_radians());
    let a = [radius, 0.0, -f];
    let b = [radius - f * alpha.tan(), 0.0, 0.0];
    let near = |p: [f64; 3], q: [f64; 3]| (0..3).all(|i| (p[i] - q[i]).abs() < 1e-9);
    let at_a = outline.iter().position(|&p| near(p, a)).unwrap_or_else(|| panic!("A not in {outline:?}"));
    assert!(near(outline[at_a + 1], b), "A then B: {outline:?}");
    // The part reaches past the tool's start (ZA = −4.6), down to the axis and out to D/2.
    let left = outline.iter().map(|p| p[2]).fold(f64::INFINITY, f64::min);
    assert!(left < ZA_45, "{outline:?}");
    assert!(outline.iter().all(|p| p[0] >= 0.0 && p[0] <= radius && p[2] <= 0.0), "{outline:?}");
    // The stock before the chamfer: the bar, D/2 in radius, up to the face.
    let stock = &part["stock"];
    assert!(near(point(&stock[0]), [0.0, 0.0, left]) && near(point(&stock[1]), [radius, 0.0, 0.0]), "{stock}");
    assert!(part["said"].as_str().unwrap().contains("outer chamfer of Outer's names"), "{part}");
    let svg = out["svg"].as_str().unwrap();
    assert!(svg.contains("id=\"part\"") && svg.contains("id=\"stock\""), "the backplot draws them");

    // sheets/chamfer.csv labels its inputs in rows, names none and calls no CHAMFER: the
    // program is drawn without a part, and the page is told why.
    let bench = Bench::with_macros("chamfer.csv", &["chamfer.bas"]);
    let run = serde_json::json!({ "source": "file:chamfer.bas", "sub": "Main", "dialect": "linuxcnc", "machine": "lathe", "sheet": 0 });
    let (status, out) = bench.post_json("/api/run", &run);
    assert_eq!(status, 200, "{out}");
    assert!(out["part"]["said"].as_str().unwrap().starts_with("no stock or part is known"), "{out}");
    assert!(!out["svg"].as_str().unwrap().contains("id=\"part\""), "{out}");
}

/// `serve --timeout` bounds each request, never the server's life (the command line's clock
/// would end the process once the timeout passed).
#[test]
fn serve_timeout_bounds_requests_not_the_server() {
    let folder = tempfile::tempdir().unwrap();
    let (mut server, port, query) = serve_command(folder.path(), &["--timeout", "0.2"]);
    // Well past the timeout, the server still serves.
    std::thread::sleep(Duration::from_secs(1));
    assert!(server.0.try_wait().unwrap().is_none(), "the server ended");
    let answer = page_answer(port, &query);
    assert!(answer.starts_with("HTTP/1.1 200"), "{answer}");
}

// "Sheets.Add method" (Excel VBA reference): Before is "the sheet before which the new sheet
// is added". A sheet a macro adds before the first is the first tab: the summary lists the
// sheets' numbers in tab order, the new sheet (number 1) first.
#[test]
fn a_sheet_a_macro_adds_before_the_first_is_the_first_tab() {
    let bas = "Sub Main()\n    Sheets.Add Before:=Sheets(1)\n    ActiveSheet.Name = \"Notes\"\nEnd Sub\n";
    let bench = Bench::written("book.csv", "1,2\n", &[("add.bas", bas)], Default::default());
    let run = serde_json::json!({ "source": "file:add.bas", "sub": "Main", "dialect": "linuxcnc", "sheet": 0 });
    let (status, out) = bench.post_json("/api/run", &run);
    assert_eq!(status, 200, "{out}");
    let summary = bench.get_json("/api/sheets");
    assert_eq!(summary["sheets"][1]["name"], "Notes", "{summary}");
    assert_eq!(summary["order"], serde_json::json!([1, 0]), "{summary}");
}

/// A save over the opened workbook is an edit in place (issue 30): another program that saved
/// the file after the workbench read it (here a command's `set --in-place`, as a person would
/// run beside the page) keeps its work, the save refused with a conflict and nothing written;
/// once the page's work is saved elsewhere, nothing is lost. A save over a file no one else
/// touched still goes through, and a second one after it too.
#[test]
fn saving_over_a_workbook_another_program_saved_meanwhile_is_refused() {
    let bench = Bench::written("book.csv", "1,=A1*2\n", &[], Default::default());
    let file = bench.file("book.csv");
    std::fs::write(&file, "7,=A1*2\n").unwrap();
    let (status, answer) = bench.post_json("/api/save", &serde_json::json!({ "name": "book.csv", "over": true }));
    assert_eq!(status, 409, "{answer}");
    assert!(answer["error"].as_str().unwrap().contains("changed since ncsheet read it"), "{answer}");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "7,=A1*2\n", "the other program's work is kept");

    let bench = Bench::written("book.csv", "1,=A1*2\n", &[], Default::default());
    for _ in 0..2 {
        let (status, answer) = bench.post_json("/api/save", &serde_json::json!({ "name": "book.csv", "over": true }));
        assert_eq!(status, 200, "{answer}");
    }
}

/// A connection that does not deliver a whole request within the deadline, from its opening
/// or its last answer, is closed: one that sends nothing, one that sends a request line and
/// stops, one that sends its head and part of its body, one idle after an answer. (They were
/// held without end: 1,100 such connections left a server with the usual 1,024 descriptors
/// answering no one.) A request being answered keeps its connection however long it takes:
/// a macro run outlasting the deadline is answered.
#[test]
fn connections_that_send_no_whole_request_in_time_are_closed() {
    let options =
        Options { timeout: Some(0.6), request_deadline: Some(Duration::from_millis(200)), ..Options::default() };
    let bench = Bench::written_with("book.csv", "1\n", &[("endless.bas", ENDLESS_MACRO)], options);
    let head =
        format!("POST /api/set HTTP/1.1\r\nHost: 127.0.0.1:{}\r\n{TOKEN_HEADER}: {}\r\n", bench.port, bench.token);
    let partial = [
        String::new(),
        "GET /api/sheets HTTP/1.1\r\n".to_string(),
        format!("{head}Content-Type: application/json\r\nContent-Length: 100\r\n\r\n{{\"sheet\":"),
    ];
    let mut held: Vec<TcpStream> = (0..30)
        .map(|i| {
            let mut stream = TcpStream::connect(("127.0.0.1", bench.port)).unwrap();
            stream.write_all(partial[i % partial.len()].as_bytes()).unwrap();
            stream
        })
        .collect();
    // A keep-alive request answered, then nothing more.
    let mut idle = TcpStream::connect(("127.0.0.1", bench.port)).unwrap();
    let get = format!(
        "GET /api/sheets HTTP/1.1\r\nHost: 127.0.0.1:{}\r\n{TOKEN_HEADER}: {}\r\n\r\n",
        bench.port, bench.token
    );
    idle.write_all(get.as_bytes()).unwrap();
    held.push(idle);
    for (i, stream) in held.iter_mut().enumerate() {
        let mut answer = Vec::new();
        // Ends when the server closes the connection (or resets it); never by a clock here.
        let _ = stream.read_to_end(&mut answer);
        let text = String::from_utf8_lossy(&answer);
        if i == 30 {
            assert!(text.starts_with("HTTP/1.1 200"), "{text}");
        } else {
            assert!(!text.contains(" 200 "), "connection {i} was answered: {text}");
        }
    }
    let run = serde_json::json!({ "source": "file:endless.bas", "sub": "Main", "dialect": "iso", "machine": "lathe", "sheet": 0 });
    let (status, out) = bench.post_json("/api/run", &run);
    assert_eq!(status, 400, "the macro's own error after 0.6 s: {out}");
    assert!(out["error"].as_str().unwrap().contains("--timeout of 0.6 s"), "{out}");
}

/// A header typed over in the workbench renames its table's column, as in Excel ("When a
/// header is changed, all formula references to that column are automatically adjusted",
/// Barresse and Jones, *Excel Tables*, ch. 2): LibreOffice's tables.xlsx, Use!A1 is
/// SUM(Parts[Qty]), 17 as LibreOffice cached it; typed over, B1 "Quantity" makes it
/// SUM(Parts[Quantity]), and B2 = 4 then gives 17 - 2 + 4 = 19. Undo names the column Qty again.
#[test]
fn a_header_typed_over_renames_the_tables_column_and_undo_names_it_back() {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/libreoffice/tables.xlsx");
    let bench = Bench::written_with("tables.xlsx", std::fs::read(source).unwrap(), &[], Options::default());
    let window = serde_json::json!({ "sheet": 0, "r0": 0, "r1": 10, "c0": 0, "c1": 8 });
    let set = |r: u64, c: u64, input: &str| {
        let body = serde_json::json!({ "sheet": 0, "r": r, "c": c, "input": input, "window": window });
        let (status, answer) = bench.post_json("/api/set", &body);
        assert_eq!(status, 200, "{answer}");
    };
    set(0, 1, "Quantity");
    set(1, 1, "4");
    let (status, answer) = bench.post_json("/api/save", &serde_json::json!({ "name": "renamed.xlsx" }));
    assert_eq!(status, 200, "{answer}");
    let saved = ncsheet::document::Document::open_file(&bench.file("renamed.xlsx"), &Default::default()).unwrap();
    let (sheet, a1) = saved.cell("Use!A1").unwrap();
    assert_eq!(saved.workbook().input(sheet, a1).as_deref(), Some("=SUM(Parts[Quantity])"));
    assert_eq!(saved.workbook().value(sheet, a1), ncsheet::eval::Value::Number(19.0));
    for _ in 0..2 {
        assert_eq!(bench.post_json("/api/undo", &serde_json::json!({ "window": window })).0, 200);
    }
    let (status, answer) = bench.post_json("/api/save", &serde_json::json!({ "name": "undone.xlsx" }));
    assert_eq!(status, 200, "{answer}");
    let saved = ncsheet::document::Document::open_file(&bench.file("undone.xlsx"), &Default::default()).unwrap();
    assert_eq!(saved.workbook().input(sheet, a1).as_deref(), Some("=SUM(Parts[Qty])"));
    assert_eq!(saved.workbook().value(sheet, a1), ncsheet::eval::Value::Number(17.0));
}
