//! `ncsheet serve`: the workbench, a local web server showing one workbook in a browser grid
//! with its toolpaths beside it. HTTP is axum's on a one-thread tokio runtime; the page is
//! plain HTML, CSS and JavaScript compiled into the binary (`assets/`).
//!
//! The [`Document`] is not `Send` (its formula trees are shared by `Rc`), so it lives on a
//! thread of its own: each request hands that thread a job and awaits its answer, which also
//! serialises the edits. The server prints nothing: [`Server::open`] returns the URL and the
//! caller says it.

mod connections;
mod guard;
mod machining;
mod paths;
mod routes;
mod workbench;

use std::fmt;
use std::net::{Ipv4Addr, SocketAddr, TcpListener};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Arc;
use std::time::Duration;

use tokio::sync::{mpsc, oneshot};

pub use guard::TOKEN_HEADER;
use guard::{random_token, Guard};
use ncsheet::document::{Document, OpenOptions};
use workbench::Workbench;

/// The stack of the document's thread: a macro run from the page recurses as deep as the
/// command line's `run` allows by default.
const DOCUMENT_STACK: usize = 256 << 20;

/// What `ncsheet serve` was asked for.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// The port on 127.0.0.1 (0: one the system picks).
    pub port: u16,
    /// Macro files (.bas) beside the workbook that the page may run: the caller lists the
    /// folder, the server reads only these.
    pub macro_files: Vec<PathBuf>,
    /// How to read the workbook: the command line's read limits, locale, csv delimiter and
    /// the limits of the workbook's own functions, as every other command reads it (the
    /// name is the served file's).
    pub open: OpenOptions,
    /// The command line's `--timeout`, in seconds, for each request as for a command: a
    /// macro run stops at its statement, the workbook's own functions stop with the edit's
    /// recalculation, and a request still computing then is answered with an error while the
    /// server goes on answering. `None`: no limit, but a macro run from the page stops after
    /// 20 s.
    pub timeout: Option<f64>,
    /// How long a connection not being answered may take to deliver a whole request, from
    /// opening or its last answer ([`REQUEST_DEADLINE`] when `None`); past it it is closed.
    pub request_deadline: Option<Duration>,
}

/// A connection's time to deliver a whole request, head and body (see `connections`): a
/// browser sends one at once, and opens a new connection when an idle one was closed.
pub const REQUEST_DEADLINE: Duration = Duration::from_secs(10);

/// Why the workbench did not start or stopped.
#[derive(Debug)]
pub enum Error {
    /// The workbook did not open (the message names the file and the place).
    Open(String),
    /// The port could not be taken.
    Bind { port: u16, error: std::io::Error },
    /// The server failed while running.
    Serve(std::io::Error),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Open(message) => f.write_str(message),
            Error::Bind { port, error } => write!(f, "cannot listen on 127.0.0.1:{port}: {error}"),
            Error::Serve(error) => write!(f, "the server stopped: {error}"),
        }
    }
}

impl std::error::Error for Error {}

/// The parts of [`OpenOptions`] that cross to the document's thread (a macro's output sink
/// cannot). The workbook's own functions keep the command line's limits but not its
/// deadline: a deadline set when the server starts would stop every function call after it
/// (each recalculation gets `--timeout` of its own instead, [`Options::timeout`]).
struct Reading {
    format: Option<ncsheet::io::Format>,
    csv_delimiter: Option<u8>,
    read_limits: ncsheet::io::limits::ReadLimits,
    settings: Option<ncsheet::eval::Settings>,
    limits: [u64; 6],
}

impl Reading {
    fn of(open: &OpenOptions) -> Reading {
        let f = &open.functions;
        Reading {
            format: open.format,
            csv_delimiter: open.csv_delimiter,
            read_limits: open.read_limits,
            settings: open.settings.clone(),
            limits: [
                f.max_statements,
                f.max_depth as u64,
                f.max_string as u64,
                f.max_array_items as u64,
                f.max_output,
                f.max_memory,
            ],
        }
    }

    fn options(&self, path: &Path) -> OpenOptions {
        let [max_statements, max_depth, max_string, max_array_items, max_output, max_memory] = self.limits;
        let functions = ncsheet::vba::RunOptions {
            max_statements,
            max_depth: max_depth as usize,
            max_string: max_string as usize,
            max_array_items: max_array_items as usize,
            max_output,
            max_memory,
            ..Default::default()
        };
        OpenOptions {
            name: path.to_path_buf(),
            format: self.format,
            csv_delimiter: self.csv_delimiter,
            read_limits: self.read_limits,
            settings: self.settings.clone(),
            functions,
        }
    }
}

/// A job for the document's thread.
type Job = Box<dyn FnOnce(&mut Workbench) + Send>;

/// The way to the document's thread, shared by every request.
#[derive(Clone)]
struct DocumentThread {
    jobs: mpsc::UnboundedSender<Job>,
    /// `--timeout`: how long a request waits for its answer.
    timeout: Option<f64>,
}

/// Why a request got no answer from the workbook's thread.
enum Unanswered {
    /// The thread stopped (a job panicked past its guard, or the server is ending).
    Gone,
    /// No answer within `--timeout` (and a moment's grace). `started`: the job was running
    /// and goes on to its end (a recalculation cannot stop partway); else it never will run.
    Late { seconds: f64, started: bool },
}

/// How long past `--timeout` a request waits, so that a macro that stops itself at the
/// deadline can say where (the command line's clock waits 100 ms; a request has its answer
/// to build too).
const GRACE: Duration = Duration::from_millis(500);

/// Where a job is: waiting in the queue, running, or given up by its request before it ran.
const WAITING: u8 = 0;
const RUNNING: u8 = 1;
const ABANDONED: u8 = 2;

impl DocumentThread {
    /// Opens the workbook on a new thread that then runs the jobs sent to it.
    fn start(path: &Path, open: &OpenOptions, timeout: Option<f64>) -> Result<DocumentThread, Error> {
        let (jobs, mut queue) = mpsc::unbounded_channel::<Job>();
        let (opened_tx, opened_rx) = std::sync::mpsc::channel::<Result<(), String>>();
        let path = path.to_path_buf();
        let reading = Reading::of(open);
        let thread = std::thread::Builder::new().name("workbook".into()).stack_size(DOCUMENT_STACK).spawn(move || {
            // Taken before the read: a change while it reads is a change a save over it sees.
            let read = ncsheet::io::atomic::ReadState::of(&path).ok();
            let mut bench = match Document::open_file(&path, &reading.options(&path)) {
                Ok(mut doc) => {
                    // Each edit's recalculation gets the time a command gets.
                    doc.workbook_mut().settings_mut().functions.seconds_per_recalculation = timeout;
                    Workbench::new(doc, path, read)
                }
                Err(e) => return drop(opened_tx.send(Err(e.to_string()))),
            };
            drop(opened_tx.send(Ok(())));
            while let Some(job) = queue.blocking_recv() {
                // A panic in one request must not take the workbook away from the others.
                let bench = &mut bench;
                let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(move || job(bench)));
            }
        });
        thread.map_err(|e| Error::Open(format!("cannot start the workbook's thread: {e}")))?;
        match opened_rx.recv() {
            Ok(Ok(())) => Ok(DocumentThread { jobs, timeout }),
            Ok(Err(message)) => Err(Error::Open(message)),
            Err(_) => Err(Error::Open("the workbook's thread stopped while opening it".into())),
        }
    }

    /// Runs `f` on the workbook and returns its answer, waiting at most `--timeout` (and
    /// [`GRACE`]): a job its request gave up on before it started is never run.
    async fn with<R: Send + 'static>(
        &self,
        f: impl FnOnce(&mut Workbench) -> R + Send + 'static,
    ) -> Result<R, Unanswered> {
        let (tx, mut rx) = oneshot::channel();
        let state = Arc::new(AtomicU8::new(WAITING));
        let job_state = state.clone();
        let job: Job = Box::new(move |bench| {
            if job_state.compare_exchange(WAITING, RUNNING, Ordering::SeqCst, Ordering::SeqCst).is_ok() {
                drop(tx.send(f(bench)));
            }
        });
        self.jobs.send(job).map_err(|_| Unanswered::Gone)?;
        let Some(seconds) = self.timeout else { return rx.await.map_err(|_| Unanswered::Gone) };
        let wait = Duration::try_from_secs_f64(seconds).unwrap_or(Duration::MAX).saturating_add(GRACE);
        match tokio::time::timeout(wait, &mut rx).await {
            Ok(answer) => answer.map_err(|_| Unanswered::Gone),
            // The answer may have come as the wait ended.
            Err(_) => rx.try_recv().map_err(|_| {
                let given_up = state.compare_exchange(WAITING, ABANDONED, Ordering::SeqCst, Ordering::SeqCst);
                Unanswered::Late { seconds, started: given_up.is_err() }
            }),
        }
    }
}

/// A workbench bound to its port, ready to run.
pub struct Server {
    listener: TcpListener,
    guard: Guard,
    document: DocumentThread,
    macro_files: Vec<PathBuf>,
    request_deadline: Duration,
}

impl Server {
    /// Opens the workbook at `path` and takes the port on 127.0.0.1 (never another address).
    pub fn open(path: &Path, options: &Options) -> Result<Server, Error> {
        let document = DocumentThread::start(path, &options.open, options.timeout)?;
        let address = SocketAddr::from((Ipv4Addr::LOCALHOST, options.port));
        let listener = TcpListener::bind(address).map_err(|error| Error::Bind { port: options.port, error })?;
        let port = listener.local_addr().map_err(|error| Error::Bind { port: options.port, error })?.port();
        let macro_files = options.macro_files.clone();
        let request_deadline = options.request_deadline.unwrap_or(REQUEST_DEADLINE);
        Ok(Server { listener, guard: Guard::new(port, random_token()), document, macro_files, request_deadline })
    }

    /// The address to open in a browser, with the token.
    pub fn url(&self) -> String {
        format!("http://127.0.0.1:{}/?t={}", self.port(), self.guard.token())
    }

    pub fn port(&self) -> u16 {
        self.listener.local_addr().map_or(0, |a| a.port())
    }

    /// The secret every request must carry.
    pub fn token(&self) -> &str {
        self.guard.token()
    }

    /// Serves until the process ends.
    pub fn run(self) -> Result<(), Error> {
        let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().map_err(Error::Serve)?;
        runtime.block_on(async move {
            self.listener.set_nonblocking(true).map_err(Error::Serve)?;
            let listener = tokio::net::TcpListener::from_std(self.listener).map_err(Error::Serve)?;
            let listener = connections::Deadlined::new(listener, self.request_deadline);
            let router = routes::router(routes::App {
                guard: self.guard,
                document: self.document,
                bas_files: std::sync::Arc::new(self.macro_files),
            });
            let service = router.into_make_service_with_connect_info::<connections::Activity>();
            axum::serve(listener, service).await.map_err(Error::Serve)
        })
    }
}
