//! One HTTP/1.1 request read from a viewer within a deadline, and the checks the server makes
//! of it before it answers: the `Host` it names ([`AllowedHosts`]), the `Origin` of a request
//! that changes something. A request that is not HTTP (not UTF-8, no request line, a header
//! without a colon, a bad `Content-Length`) is answered `400`; one longer than
//! [`MAX_REQUEST_BYTES`] `413`; one that takes longer than its deadline to arrive, whatever it
//! sends meanwhile, `408`.

use std::io::{BufRead, BufReader, Read};
use std::net::{IpAddr, TcpStream};
use std::time::{Duration, Instant};

/// Longest request head, or body, read (bytes): nothing the page sends is near it.
pub const MAX_REQUEST_BYTES: u64 = 16 * 1024;

/// A request as the server reads it.
#[derive(Debug)]
pub(crate) struct Request {
    pub method: String,
    /// The path without its query.
    pub path: String,
    /// Header names in lower case, values trimmed.
    pub headers: Vec<(String, String)>,
    pub body: Vec<u8>,
}

impl Request {
    /// The value of header `name` (lower case), if sent.
    pub fn header(&self, name: &str) -> Option<&str> {
        (self.headers.iter())
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }
}

/// Why a request gets no regular answer.
#[derive(Debug)]
pub(crate) enum Refusal {
    /// Not an HTTP request the server reads (answered 400, with the reason).
    Malformed(String),
    /// A head or body longer than [`MAX_REQUEST_BYTES`] (answered 413).
    TooLarge,
    /// The request did not arrive before its deadline (answered 408 if the socket takes it).
    TimedOut,
    /// The viewer went away.
    Closed,
}

impl From<std::io::Error> for Refusal {
    fn from(e: std::io::Error) -> Self {
        match e.kind() {
            std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut => Refusal::TimedOut,
            _ => Refusal::Closed,
        }
    }
}

/// Reads from a socket until a deadline: each read waits at most the time left.
struct DeadlineReader<'a> {
    stream: &'a TcpStream,
    deadline: Instant,
}

impl Read for DeadlineReader<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let left = self.deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err(std::io::ErrorKind::TimedOut.into());
        }
        self.stream.set_read_timeout(Some(left))?;
        self.stream.read(buf)
    }
}

/// One line of the head, as text without its line end.
fn line(reader: &mut impl BufRead, what: &str) -> Result<String, Refusal> {
    let mut bytes = Vec::new();
    reader.read_until(b'\n', &mut bytes)?;
    if bytes.last() != Some(&b'\n') {
        return Err(match bytes.len() as u64 >= MAX_REQUEST_BYTES {
            true => Refusal::TooLarge,
            false if bytes.is_empty() && what == "request line" => Refusal::Closed,
            false => Refusal::Malformed(format!("the {what} ends without a line end")),
        });
    }
    let text = String::from_utf8(bytes)
        .map_err(|_| Refusal::Malformed(format!("the {what} is not UTF-8")))?;
    Ok(text.trim_end_matches(['\r', '\n']).to_owned())
}

/// Reads one request from `stream`: head and body must both have arrived within `deadline`.
pub(crate) fn read_request(stream: &TcpStream, deadline: Duration) -> Result<Request, Refusal> {
    let timed = DeadlineReader {
        stream,
        deadline: Instant::now() + deadline,
    };
    // A head of at most MAX_REQUEST_BYTES, then a body of at most as many.
    let mut reader = BufReader::new(timed.take(2 * MAX_REQUEST_BYTES));
    let request_line = line(&mut reader, "request line")?;
    let mut head_bytes = request_line.len() as u64;
    let mut parts = request_line.split(' ');
    let (Some(method), Some(target), Some(version), None) =
        (parts.next(), parts.next(), parts.next(), parts.next())
    else {
        return Err(Refusal::Malformed(
            "the request line is not METHOD PATH HTTP/1.x".into(),
        ));
    };
    if !version.starts_with("HTTP/1.") || !target.starts_with('/') || method.is_empty() {
        return Err(Refusal::Malformed(
            "the request line is not METHOD PATH HTTP/1.x".into(),
        ));
    }
    let mut headers = Vec::new();
    loop {
        let header = line(&mut reader, "header")?;
        head_bytes += header.len() as u64 + 2;
        if head_bytes > MAX_REQUEST_BYTES {
            return Err(Refusal::TooLarge);
        }
        if header.is_empty() {
            break;
        }
        let Some((name, value)) = header.split_once(':') else {
            return Err(Refusal::Malformed(format!(
                "header line without a colon: {:?}",
                header.chars().take(60).collect::<String>()
            )));
        };
        headers.push((name.trim().to_ascii_lowercase(), value.trim().to_owned()));
    }
    let mut request = Request {
        method: method.to_owned(),
        path: target.split('?').next().unwrap_or("").to_owned(),
        headers,
        body: Vec::new(),
    };
    let length = match request.header("content-length") {
        None => 0,
        Some(text) => text
            .parse::<u64>()
            .map_err(|_| Refusal::Malformed(format!("Content-Length {text:?} is not a number")))?,
    };
    if length > MAX_REQUEST_BYTES {
        return Err(Refusal::TooLarge);
    }
    (&mut reader).take(length).read_to_end(&mut request.body)?;
    if request.body.len() as u64 != length {
        return Err(Refusal::Malformed(format!(
            "the body has {} of its {length} bytes",
            request.body.len()
        )));
    }
    Ok(request)
}

/// The `Host` values the server answers: `localhost`, `127.0.0.1`, `[::1]` and the address it
/// was told to listen on, each with its port. A page of another site that a DNS name was
/// rebound to this machine for names that site, and is refused.
#[derive(Debug, Clone)]
pub struct AllowedHosts {
    names: Vec<String>,
    port: u16,
}

impl AllowedHosts {
    /// The names of a server listening on `host` (as given to `--host`), port `port`.
    pub fn new(host: &str, port: u16) -> Self {
        let given = match host.parse::<IpAddr>() {
            Ok(IpAddr::V6(v6)) => format!("[{v6}]"),
            _ => host.trim().to_ascii_lowercase(),
        };
        let mut names: Vec<String> = ["localhost", "127.0.0.1", "[::1]"].map(String::from).into();
        if !names.contains(&given) {
            names.push(given);
        }
        Self { names, port }
    }

    /// The names, for an error message.
    pub fn names(&self) -> String {
        self.names.join(", ")
    }

    /// Whether `host` (a `Host` header, or an `Origin` without its scheme) names this server:
    /// one of the names with this port (port 80 may be left out).
    pub fn allows(&self, host: &str) -> bool {
        let host = host.to_ascii_lowercase();
        let (name, port) = match host.rsplit_once(':') {
            // "[::1]" alone has colons inside its brackets only.
            Some((name, port)) if !port.ends_with(']') => (name, port.parse::<u16>().ok()),
            _ => (host.as_str(), Some(80)),
        };
        port == Some(self.port) && self.names.iter().any(|n| n == name)
    }

    /// Whether `origin` (an `Origin` header) is a page of this server (`http://` + an allowed
    /// host).
    pub fn allows_origin(&self, origin: &str) -> bool {
        origin
            .strip_prefix("http://")
            .is_some_and(|host| self.allows(host))
    }
}

#[cfg(test)]
mod tests {
    use super::AllowedHosts;

    #[test]
    fn hosts_are_the_loopback_names_and_the_given_one_with_the_port() {
        let hosts = AllowedHosts::new("127.0.0.1", 8240);
        for good in ["127.0.0.1:8240", "LOCALHOST:8240", "[::1]:8240"] {
            assert!(hosts.allows(good), "{good}");
        }
        for bad in [
            "evil.example:8240",
            "127.0.0.1:8241",
            "127.0.0.1",
            "localhost.evil.example:8240",
            "",
            "[::1]",
        ] {
            assert!(!hosts.allows(bad), "{bad}");
        }
        let lan = AllowedHosts::new("192.168.1.5", 80);
        assert!(lan.allows("192.168.1.5") && lan.allows("192.168.1.5:80"));
        assert!(AllowedHosts::new("::", 9).allows("[::]:9"));
        assert!(hosts.allows_origin("http://localhost:8240"));
        assert!(!hosts.allows_origin("https://localhost:8240"));
        assert!(!hosts.allows_origin("http://evil.example:8240"));
        assert!(!hosts.allows_origin("null"));
    }
}
