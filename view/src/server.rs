//! The embedded HTTP/1.1 server of the page: one thread per connection, every asset compiled
//! into the binary, frames pushed as Server-Sent Events. A viewer that goes away ends only its
//! own thread; the others go on.
//!
//! | request | answer |
//! |---|---|
//! | `GET /` | the page (`page/index.html`, with `/page.js` and `/page.css`) |
//! | `GET /stream` | `text/event-stream`: one `data: <message>` per drawn frame, newest first when a viewer lags |
//! | `GET /frame.svg`, `GET /frame.json` | the newest drawn frame, its SVG or its message |
//! | `POST /control` | a [`Control`] as text (`pause`, `play`, `step`, `seek 1.2`, `speed 2`) with `Content-Type: application/x-neurotac-control` ([`CONTROL_CONTENT_TYPE`]); `204`, or `400` naming what it did not understand |
//!
//! # Security model
//! The page has no login: whoever can send it a request it accepts can watch the stream (its
//! `source` names the recording's path) and control the player. It is meant for this machine:
//! - it listens on `127.0.0.1` unless told otherwise (`neurotac view --host` warns when the
//!   address is not a loopback one: then anyone on the network can watch and control it);
//! - it answers only requests whose `Host` names it — `localhost`, `127.0.0.1`, `[::1]` or the
//!   address given, with its port ([`AllowedHosts`]) — so a web page whose DNS name is rebound
//!   to this machine reads nothing (`403`);
//! - it obeys `POST /control` only with its own content type ([`CONTROL_CONTENT_TYPE`], which a
//!   page of another site cannot send without a CORS preflight the server does not grant) and
//!   an `Origin`, when sent, that is the page's own (`403`), so a page of another site cannot
//!   pause or steer it, and browsers keep other sites from reading its answers;
//! - every request must arrive whole within a deadline, every write to a viewer finish
//!   within a timeout, and at most [`ServerLimits::max_connections`] are served at once
//!   (`503` beyond), so slow or stalled clients cannot hold it; malformed requests get `400`.
//!
//! Programs of other users on the same machine can still connect to the loopback address:
//! they can watch and control the view as the page can, and nothing more — nothing is served
//! from disk and no request reaches outside the player.

use crate::error::ViewError;
use crate::hub::{Control, Hub};
use crate::request::{AllowedHosts, Refusal, Request, read_request};
use std::io::Write;
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

const INDEX_HTML: &str = include_str!("page/index.html");
const PAGE_JS: &str = include_str!("page/page.js");
const PAGE_CSS: &str = include_str!("page/page.css");

/// The content type `POST /control` must carry: not one a page of another site may send
/// without asking first (a CORS preflight, which this server never grants).
pub const CONTROL_CONTENT_TYPE: &str = "application/x-neurotac-control";

/// How long the server waits for clients (see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServerLimits {
    /// Time for a whole request (head and body) to arrive, from the connection (default 10 s).
    pub request_deadline: Duration,
    /// Time for one write to a viewer to finish; a viewer that stops reading is dropped after
    /// it (default 10 s).
    pub write_timeout: Duration,
    /// Connections served at once, streams included; more are answered `503` (default 64).
    pub max_connections: usize,
}

impl Default for ServerLimits {
    fn default() -> Self {
        Self {
            request_deadline: Duration::from_secs(10),
            write_timeout: Duration::from_secs(10),
            max_connections: 64,
        }
    }
}

/// The page's server, listening.
pub struct Server {
    listener: TcpListener,
    hub: Arc<Hub>,
    hosts: AllowedHosts,
    limits: ServerLimits,
}

impl Server {
    /// Listens on `host:port` (`port` 0: any free port), with the default [`ServerLimits`].
    pub fn bind(host: &str, port: u16, hub: Arc<Hub>) -> Result<Self, ViewError> {
        let address = format!("{host}:{port}");
        let listener =
            TcpListener::bind(&address).map_err(|source| ViewError::Listen { address, source })?;
        let port = listener.local_addr().map_or(port, |a| a.port());
        Ok(Self {
            listener,
            hub,
            hosts: AllowedHosts::new(host, port),
            limits: ServerLimits::default(),
        })
    }

    /// The same server with other limits.
    pub fn with_limits(self, limits: ServerLimits) -> Self {
        Self { limits, ..self }
    }

    /// The address it listens on.
    pub fn local_addr(&self) -> SocketAddr {
        self.listener
            .local_addr()
            .expect("a bound listener has an address")
    }

    /// Serves on a thread of its own until the process ends.
    pub fn spawn(self) {
        std::thread::Builder::new()
            .name("view-server".into())
            .spawn(move || {
                let open = Arc::new(AtomicUsize::new(0));
                let served = Arc::new(Served {
                    hub: self.hub,
                    hosts: self.hosts,
                    limits: self.limits,
                });
                for stream in self.listener.incoming().flatten() {
                    let _ = stream.set_write_timeout(Some(served.limits.write_timeout));
                    let slot = Slot::take(&open, served.limits.max_connections);
                    let Some(slot) = slot else {
                        // Answered here: a short write into an empty socket does not block.
                        let _ = respond(
                            &mut &stream,
                            "503 Service Unavailable",
                            "text/plain; charset=utf-8",
                            "too many connections to neurotac view; try again",
                        );
                        continue;
                    };
                    let served = Arc::clone(&served);
                    // A failed spawn (out of threads) drops this connection only.
                    let _ = std::thread::Builder::new()
                        .name("view-viewer".into())
                        .spawn(move || {
                            let _slot = slot;
                            // A viewer that goes away is not an error of the view.
                            let _ = serve(&stream, &served);
                        });
                }
            })
            .expect("spawning the server thread");
    }
}

/// What every connection's thread shares.
struct Served {
    hub: Arc<Hub>,
    hosts: AllowedHosts,
    limits: ServerLimits,
}

/// One of the connections served at once, given back when dropped.
struct Slot(Arc<AtomicUsize>);

impl Slot {
    fn take(open: &Arc<AtomicUsize>, max: usize) -> Option<Slot> {
        open.fetch_update(Ordering::SeqCst, Ordering::SeqCst, |n| {
            (n < max).then_some(n + 1)
        })
        .ok()
        .map(|_| Slot(Arc::clone(open)))
    }
}

impl Drop for Slot {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

/// One request on `stream`.
fn serve(stream: &TcpStream, served: &Served) -> std::io::Result<()> {
    let text = "text/plain; charset=utf-8";
    let mut out = stream;
    let request = match read_request(stream, served.limits.request_deadline) {
        Ok(request) => request,
        Err(Refusal::Malformed(why)) => {
            return respond(
                &mut out,
                "400 Bad Request",
                text,
                &format!("bad request: {why}"),
            );
        }
        Err(Refusal::TooLarge) => {
            return respond(&mut out, "413 Content Too Large", text, "request too large");
        }
        Err(Refusal::TimedOut) => {
            return respond(&mut out, "408 Request Timeout", text, "request too slow");
        }
        Err(Refusal::Closed) => return Ok(()),
    };
    match request.header("host") {
        Some(host) if served.hosts.allows(host) => {}
        host => {
            let why = format!(
                "Host {:?} is not this server (it answers {} with its port)",
                host.unwrap_or(""),
                served.hosts.names()
            );
            let status = match host {
                None => "400 Bad Request",
                Some(_) => "403 Forbidden",
            };
            return respond(&mut out, status, text, &why);
        }
    }
    let hub = &served.hub;
    match (request.method.as_str(), request.path.as_str()) {
        ("GET", "/") => respond(&mut out, "200 OK", "text/html; charset=utf-8", INDEX_HTML),
        ("GET", "/page.js") => respond(&mut out, "200 OK", "text/javascript", PAGE_JS),
        ("GET", "/page.css") => respond(&mut out, "200 OK", "text/css", PAGE_CSS),
        ("GET", "/frame.svg") => respond(&mut out, "200 OK", "image/svg+xml", &hub.latest().svg),
        ("GET", "/frame.json") => respond(
            &mut out,
            "200 OK",
            "application/json",
            &hub.latest().message,
        ),
        ("GET", "/stream") => stream_frames(&mut out, hub),
        ("POST", "/control") => match control(&request, &served.hosts) {
            Ok(control) => {
                hub.control(control);
                respond(&mut out, "204 No Content", "text/plain", "")
            }
            Err((status, why)) => respond(&mut out, status, text, &why),
        },
        _ => respond(&mut out, "404 Not Found", "text/plain", "not found"),
    }
}

/// The control `request` asks for, or the status and reason it is refused with.
fn control(request: &Request, hosts: &AllowedHosts) -> Result<Control, (&'static str, String)> {
    if let Some(origin) = request.header("origin")
        && !hosts.allows_origin(origin)
    {
        return Err((
            "403 Forbidden",
            format!("a control from the page of another site ({origin:?}) is refused"),
        ));
    }
    let kind = request.header("content-type").unwrap_or("");
    if !kind.eq_ignore_ascii_case(CONTROL_CONTENT_TYPE) {
        return Err((
            "415 Unsupported Media Type",
            format!("a control is sent as Content-Type: {CONTROL_CONTENT_TYPE}, not {kind:?}"),
        ));
    }
    let body = String::from_utf8_lossy(&request.body);
    Control::parse(&body).ok_or_else(|| {
        (
            "400 Bad Request",
            format!(
                "not a control: {:?} ({})",
                body.chars().take(80).collect::<String>(),
                Control::syntax()
            ),
        )
    })
}

fn respond(out: &mut &TcpStream, status: &str, kind: &str, body: &str) -> std::io::Result<()> {
    write!(
        out,
        "HTTP/1.1 {status}\r\nContent-Type: {kind}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )?;
    out.flush()
}

/// Server-Sent Events: the newest drawn frame whenever there is a newer one than the last
/// sent, until the viewer goes away or the hub stops. A comment line every few seconds finds
/// a viewer that went away while nothing moved.
fn stream_frames(out: &mut &TcpStream, hub: &Hub) -> std::io::Result<()> {
    out.set_nodelay(true)?;
    write!(
        out,
        "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n"
    )?;
    let mut sent = 0;
    let latest = hub.latest();
    if latest.seq > 0 {
        send(out, &latest.message)?;
        sent = latest.seq;
    }
    while !hub.is_stopped() {
        match hub.next_after(sent, Duration::from_secs(5)) {
            Some(drawn) => {
                send(out, &drawn.message)?;
                sent = drawn.seq;
            }
            None => {
                out.write_all(b": still here\n\n")?;
                out.flush()?;
            }
        }
    }
    Ok(())
}

fn send(out: &mut &TcpStream, message: &str) -> std::io::Result<()> {
    // The message is one line of JSON (serde_json escapes newlines inside strings).
    out.write_all(b"data: ")?;
    out.write_all(message.as_bytes())?;
    out.write_all(b"\n\n")?;
    out.flush()
}
