//! How long a connection may hold the server without asking anything. Each connection takes
//! a file descriptor and a task, and hyper as axum serves it waits for a request's head (and
//! between keep-alive requests) without end: 1,100 connections that sent nothing, or a
//! request line a byte at a time, left a server under the usual 1,024 descriptors answering
//! no one until they closed. Here a connection that is not being answered must deliver its
//! whole request, head and body, within [`Options::request_deadline`](crate::Options) of
//! opening or of its last answer; past it the connection is closed. While a request is being
//! answered (a macro may run for its whole `--timeout`) the clock stops.
//!
//! At most [`MAX_CONNECTIONS`] are open at once; the next waits in the system's queue until
//! one closes. Each open connection holds its buffers (about 20 KB): 19,500 held at once
//! grew the server by 400 MB, which the allocator kept after they closed.

use std::future::Future;
use std::io;
use std::net::SocketAddr;
use std::pin::Pin;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::task::{Context, Poll};
use std::time::Duration;

use axum::extract::connect_info::{ConnectInfo, Connected};
use axum::extract::Request;
use axum::http::StatusCode;
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{OwnedSemaphorePermit, Semaphore};
use tokio::time::{Instant, Sleep};

/// The largest request body read (the page's largest is a cell's input or a file name).
const BODY_LIMIT: usize = 2 << 20;

/// The most connections the server holds open at once: a browser opens six to a server,
/// and the deadline frees a slot held by one that sends nothing within seconds.
pub const MAX_CONNECTIONS: usize = 256;

/// The server's listener: each connection it accepts keeps the deadline and one of the
/// `open` slots until it closes.
pub(crate) struct Deadlined {
    pub listener: TcpListener,
    pub deadline: Duration,
    pub open: Arc<Semaphore>,
}

impl Deadlined {
    pub fn new(listener: TcpListener, deadline: Duration) -> Deadlined {
        Deadlined { listener, deadline, open: Arc::new(Semaphore::new(MAX_CONNECTIONS)) }
    }
}

impl axum::serve::Listener for Deadlined {
    type Io = Connection;
    type Addr = SocketAddr;

    async fn accept(&mut self) -> (Connection, SocketAddr) {
        loop {
            // A slot first: past the limit the connection stays in the system's queue.
            let Ok(slot) = self.open.clone().acquire_owned().await else { continue };
            match self.listener.accept().await {
                Ok((stream, address)) => return (Connection::new(stream, self.deadline, slot), address),
                // Out of descriptors or memory: connections past their deadline free some soon.
                Err(e) if !connection_error(&e) => tokio::time::sleep(Duration::from_millis(100)).await,
                Err(_) => {}
            }
        }
    }

    fn local_addr(&self) -> io::Result<SocketAddr> {
        self.listener.local_addr()
    }
}

/// An error of the one connection being accepted (the next accept may succeed at once).
fn connection_error(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::ConnectionRefused | io::ErrorKind::ConnectionAborted | io::ErrorKind::ConnectionReset
    )
}

/// Whether a connection's request is being answered, and since when it has waited for one.
#[derive(Clone)]
pub(crate) struct Activity(Arc<State>);

struct State {
    answering: AtomicUsize,
    waiting_since: Mutex<Instant>,
}

impl Activity {
    fn new() -> Activity {
        Activity(Arc::new(State { answering: AtomicUsize::new(0), waiting_since: Mutex::new(Instant::now()) }))
    }

    fn answering(&self) -> bool {
        self.0.answering.load(Ordering::Acquire) > 0
    }

    fn waiting_since(&self) -> Instant {
        *self.0.waiting_since.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Stops the connection's clock until the guard is dropped, when it starts again.
    fn answer(&self) -> Answering {
        self.0.answering.fetch_add(1, Ordering::AcqRel);
        Answering(self.clone())
    }
}

struct Answering(Activity);

impl Drop for Answering {
    fn drop(&mut self) {
        *self.0 .0.waiting_since.lock().unwrap_or_else(|e| e.into_inner()) = Instant::now();
        self.0 .0.answering.fetch_sub(1, Ordering::AcqRel);
    }
}

impl Connected<axum::serve::IncomingStream<'_, Deadlined>> for Activity {
    fn connect_info(stream: axum::serve::IncomingStream<'_, Deadlined>) -> Activity {
        stream.io().activity.clone()
    }
}

/// A TCP connection whose reads fail once it has waited past its deadline for a request.
pub(crate) struct Connection {
    stream: TcpStream,
    activity: Activity,
    deadline: Duration,
    timer: Pin<Box<Sleep>>,
    /// Given back when the connection is dropped (closed).
    _slot: OwnedSemaphorePermit,
}

impl Connection {
    fn new(stream: TcpStream, deadline: Duration, slot: OwnedSemaphorePermit) -> Connection {
        let activity = Activity::new();
        let timer = Box::pin(tokio::time::sleep_until(activity.waiting_since() + deadline));
        Connection { stream, activity, deadline, timer, _slot: slot }
    }
}

impl AsyncRead for Connection {
    fn poll_read(self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &mut ReadBuf<'_>) -> Poll<io::Result<()>> {
        let this = self.get_mut();
        let read = Pin::new(&mut this.stream).poll_read(cx, buf);
        if read.is_ready() || this.activity.answering() {
            return read;
        }
        // Bytes arriving do not move the deadline: a request sent a byte at a time is late too.
        let due = this.activity.waiting_since() + this.deadline;
        if this.timer.deadline() != due {
            this.timer.as_mut().reset(due);
        }
        match this.timer.as_mut().poll(cx) {
            Poll::Ready(()) => Poll::Ready(Err(io::Error::new(io::ErrorKind::TimedOut, "no whole request in time"))),
            Poll::Pending => Poll::Pending,
        }
    }
}

impl AsyncWrite for Connection {
    fn poll_write(self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &[u8]) -> Poll<io::Result<usize>> {
        Pin::new(&mut self.get_mut().stream).poll_write(cx, buf)
    }

    fn poll_flush(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().stream).poll_flush(cx)
    }

    fn poll_shutdown(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().stream).poll_shutdown(cx)
    }

    fn poll_write_vectored(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bufs: &[io::IoSlice<'_>],
    ) -> Poll<io::Result<usize>> {
        Pin::new(&mut self.get_mut().stream).poll_write_vectored(cx, bufs)
    }

    fn is_write_vectored(&self) -> bool {
        self.stream.is_write_vectored()
    }
}

/// Reads a request's body whole while the connection's clock runs (a body sent slowly is
/// late as a head is), then stops the clock while the request is answered.
pub(crate) async fn answer_in_time(request: Request, next: Next) -> Response {
    let activity = request.extensions().get::<ConnectInfo<Activity>>().map(|c| c.0.clone());
    let (parts, body) = request.into_parts();
    let body = match axum::body::to_bytes(body, BODY_LIMIT).await {
        Ok(body) => body,
        Err(_) => {
            let message = "the request's body is larger than 2 MiB, or did not arrive whole in time";
            return (StatusCode::BAD_REQUEST, message).into_response();
        }
    };
    let _answering = activity.as_ref().map(Activity::answer);
    next.run(Request::from_parts(parts, axum::body::Body::from(body))).await
}

#[cfg(test)]
mod tests {
    use super::*;
    use axum::serve::Listener;

    /// Whether `future` is done at its first poll.
    fn ready_at_once<F: Future>(future: F) -> bool {
        let mut future = std::pin::pin!(future);
        let mut cx = Context::from_waker(std::task::Waker::noop());
        future.as_mut().poll(&mut cx).is_ready()
    }

    /// With two slots, two connections are accepted and a third waits for a slot, however
    /// long it has been queued; it is accepted as soon as one of the two closes.
    #[test]
    fn past_the_open_connections_allowed_the_next_waits_for_one_to_close() {
        let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
        runtime.block_on(async {
            let listener = TcpListener::bind("127.0.0.1:0").await.unwrap();
            let address = listener.local_addr().unwrap();
            let mut server =
                Deadlined { listener, deadline: Duration::from_secs(60), open: Arc::new(Semaphore::new(2)) };
            let _clients: Vec<_> = (0..3).map(|_| std::net::TcpStream::connect(address).unwrap()).collect();
            let first = server.accept().await.0;
            let _second = server.accept().await.0;
            assert_eq!(server.open.available_permits(), 0);
            assert!(!ready_at_once(server.accept()), "a third connection was accepted past the limit");
            drop(first);
            assert_eq!(server.open.available_permits(), 1, "a closed connection gives its slot back");
            let _third = server.accept().await.0;
            assert_eq!(server.open.available_permits(), 0);
        });
    }
}
