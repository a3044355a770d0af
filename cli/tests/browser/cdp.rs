//! A minimal Chrome DevTools Protocol connection: JSON calls over one WebSocket (plain `ws://`
//! to a local browser), each waiting at most [`DEADLINE`](super::DEADLINE) for its reply.

use std::io::ErrorKind;
use std::net::{TcpStream, ToSocketAddrs};
use std::time::{Duration, Instant};

use serde_json::{Value, json};
use tungstenite::{Message, WebSocket};

use super::DEADLINE;

/// How long one read of the socket blocks before the deadline is checked again.
const POLL: Duration = Duration::from_millis(100);

/// One DevTools WebSocket: the browser's (targets) or a page's (navigate, evaluate, screenshot).
pub struct Cdp {
    socket: WebSocket<TcpStream>,
    next_id: u64,
    url: String,
}

impl Cdp {
    /// Connects to a `webSocketDebuggerUrl` (`ws://127.0.0.1:PORT/devtools/…`).
    pub fn connect(url: &str) -> Cdp {
        let authority = url
            .strip_prefix("ws://")
            .and_then(|rest| rest.split('/').next())
            .unwrap_or_else(|| panic!("{url:?} is not a ws:// URL"));
        let addr = authority
            .to_socket_addrs()
            .ok()
            .and_then(|mut a| a.next())
            .unwrap_or_else(|| panic!("cannot resolve {authority:?} of {url}"));
        let stream = TcpStream::connect_timeout(&addr, DEADLINE)
            .unwrap_or_else(|e| panic!("cannot connect to {url}: {e}"));
        // The handshake blocks at most DEADLINE; afterwards reads return every POLL.
        stream.set_read_timeout(Some(DEADLINE)).unwrap();
        stream.set_write_timeout(Some(DEADLINE)).unwrap();
        let (socket, _) = tungstenite::client(url, stream)
            .unwrap_or_else(|e| panic!("WebSocket handshake with {url} failed: {e}"));
        socket.get_ref().set_read_timeout(Some(POLL)).unwrap();
        Cdp {
            socket,
            next_id: 1,
            url: url.to_owned(),
        }
    }

    /// Calls `method` with `params` and returns its `result`, skipping the events and other
    /// messages that arrive first. Panics on a protocol error, a closed connection or no reply
    /// within the deadline.
    pub fn call(&mut self, method: &str, params: Value) -> Value {
        let id = self.next_id;
        self.next_id += 1;
        let request = json!({ "id": id, "method": method, "params": params }).to_string();
        self.socket
            .send(Message::text(request))
            .unwrap_or_else(|e| panic!("{method}: cannot send to {}: {e}", self.url));
        let deadline = Instant::now() + DEADLINE;
        loop {
            match self.socket.read() {
                Ok(Message::Text(text)) => {
                    if let Some(reply) = reply_to(&text, id) {
                        return reply.unwrap_or_else(|e| panic!("{method}: {e}"));
                    }
                }
                Ok(_) => {} // pings (answered by tungstenite), pongs, binary
                Err(tungstenite::Error::Io(e))
                    if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {}
                Err(e) => panic!("{method}: the DevTools connection {} failed: {e}", self.url),
            }
            if Instant::now() >= deadline {
                panic!(
                    "{method}: no reply from {} within {} s",
                    self.url,
                    DEADLINE.as_secs()
                );
            }
        }
    }
}

/// What the DevTools message `text` says about call `id`: `None` for an event or another
/// call's reply; `Some(Ok(result))`; `Some(Err(why))` for a protocol error (or a message that
/// is not JSON).
pub fn reply_to(text: &str, id: u64) -> Option<Result<Value, String>> {
    let message: Value = match serde_json::from_str(text) {
        Ok(m) => m,
        Err(e) => return Some(Err(format!("the browser sent non-JSON {text:?}: {e}"))),
    };
    if message.get("id").and_then(Value::as_u64) != Some(id) {
        return None;
    }
    if let Some(error) = message.get("error") {
        return Some(Err(format!(
            "protocol error {}: {}",
            error["code"],
            error["message"].as_str().unwrap_or("(no message)")
        )));
    }
    Some(Ok(message.get("result").cloned().unwrap_or(Value::Null)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reply_is_found_by_its_id_among_events_and_other_replies() {
        let event = r#"{"method":"Page.frameNavigated","params":{"frame":{"id":"F"}}}"#;
        let other = r#"{"id":6,"result":{"frameId":"F"}}"#;
        let ours = r#"{"id":7,"result":{"result":{"type":"number","value":3}}}"#;
        assert_eq!(reply_to(event, 7), None);
        assert_eq!(reply_to(other, 7), None);
        assert_eq!(
            reply_to(ours, 7),
            Some(Ok(json!({"result": {"type": "number", "value": 3}})))
        );
    }

    #[test]
    fn a_protocol_error_reply_is_an_error_with_its_code_and_message() {
        let text = r#"{"id":3,"error":{"code":-32000,"message":"Cannot navigate to invalid URL"}}"#;
        assert_eq!(
            reply_to(text, 3),
            Some(Err(
                "protocol error -32000: Cannot navigate to invalid URL".to_owned()
            ))
        );
        assert!(matches!(reply_to("not json", 3), Some(Err(_))));
    }
}
