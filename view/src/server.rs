//! The embedded HTTP/1.1 server of the page: one thread per connection, every asset compiled
//! into the binary, frames pushed as Server-Sent Events. A viewer that goes away ends only its
//! own thread; the others go on.
//!
//! | request | answer |
//! |---|---|
//! | `GET /` | the page (`page/index.html`, with `/page.js` and `/page.css`) |
//! | `GET /stream` | `text/event-stream`: one `data: <message>` per drawn frame, newest first when a viewer lags |
//! | `GET /frame.svg`, `GET /frame.json` | the newest drawn frame, its SVG or its message |
//! | `POST /control` | a [`Control`] as text (`pause`, `play`, `step`, `seek 1.2`, `speed 2`); `204`, or `400` naming what it did not understand |

use crate::error::ViewError;
use crate::hub::{Control, Hub};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::Arc;
use std::time::Duration;

const INDEX_HTML: &str = include_str!("page/index.html");
const PAGE_JS: &str = include_str!("page/page.js");
const PAGE_CSS: &str = include_str!("page/page.css");

/// Longest request head or body read (bytes): nothing the page sends is near it.
const MAX_REQUEST: u64 = 16 * 1024;

/// The page's server, listening.
pub struct Server {
    listener: TcpListener,
    hub: Arc<Hub>,
}

impl Server {
    /// Listens on `host:port` (`port` 0: any free port).
    pub fn bind(host: &str, port: u16, hub: Arc<Hub>) -> Result<Self, ViewError> {
        let address = format!("{host}:{port}");
        let listener =
            TcpListener::bind(&address).map_err(|source| ViewError::Listen { address, source })?;
        Ok(Self { listener, hub })
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
                for stream in self.listener.incoming().flatten() {
                    let hub = Arc::clone(&self.hub);
                    // A failed spawn (out of threads) drops this connection only.
                    let _ = std::thread::Builder::new()
                        .name("view-viewer".into())
                        .spawn(move || {
                            // A viewer that goes away is not an error of the view.
                            let _ = serve(stream, &hub);
                        });
                }
            })
            .expect("spawning the server thread");
    }
}

/// One request on `stream`.
fn serve(stream: TcpStream, hub: &Hub) -> std::io::Result<()> {
    stream.set_read_timeout(Some(Duration::from_secs(10)))?;
    let mut reader = BufReader::new(stream.try_clone()?.take(MAX_REQUEST));
    let mut line = String::new();
    reader.read_line(&mut line)?;
    let mut parts = line.split_whitespace();
    let (method, path) = (parts.next().unwrap_or(""), parts.next().unwrap_or(""));
    let mut content_length = 0u64;
    loop {
        let mut header = String::new();
        if reader.read_line(&mut header)? == 0 || header.trim().is_empty() {
            break;
        }
        if let Some((name, value)) = header.split_once(':')
            && name.eq_ignore_ascii_case("content-length")
        {
            content_length = value.trim().parse().unwrap_or(0).min(MAX_REQUEST);
        }
    }
    let mut out = stream;
    let path = path.split('?').next().unwrap_or("");
    match (method, path) {
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
        ("POST", "/control") => {
            let mut body = String::new();
            reader.take(content_length).read_to_string(&mut body)?;
            match Control::parse(&body) {
                Some(control) => {
                    hub.control(control);
                    respond(&mut out, "204 No Content", "text/plain", "")
                }
                None => respond(
                    &mut out,
                    "400 Bad Request",
                    "text/plain; charset=utf-8",
                    &format!(
                        "not a control: {:?} (pause, play, step, seek SECONDS, speed realtime|max|N)",
                        body.chars().take(80).collect::<String>()
                    ),
                ),
            }
        }
        _ => respond(&mut out, "404 Not Found", "text/plain", "not found"),
    }
}

fn respond(out: &mut TcpStream, status: &str, kind: &str, body: &str) -> std::io::Result<()> {
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
fn stream_frames(out: &mut TcpStream, hub: &Hub) -> std::io::Result<()> {
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

fn send(out: &mut TcpStream, message: &str) -> std::io::Result<()> {
    // The message is one line of JSON (serde_json escapes newlines inside strings).
    out.write_all(b"data: ")?;
    out.write_all(message.as_bytes())?;
    out.write_all(b"\n\n")?;
    out.flush()
}
