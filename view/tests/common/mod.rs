//! What the server tests share: a recording, requests over real HTTP, a tab's stream, and a
//! player serving a source while a test runs.
#![allow(dead_code)]

use neurotac_sensor::taxel::TaxelLayout;
use neurotac_view::{
    Hub, MonitorConfig, NoObserver, Player, PlayerOptions, Server, ServerLimits, Speed,
    StreamSource,
};
use serde_json::Value;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A CSV recording of bursts at every taxel, `seconds` long.
pub fn recording(dir: &Path, seconds: i64) -> std::path::PathBuf {
    let mut text = String::from("t,x,y,on\n");
    let layout = TaxelLayout::neurotac_default();
    for step in 0..seconds * 1000 / 30 {
        for (k, &(x, y)) in layout.centres().iter().enumerate() {
            let t = step * 30_000 + k as i64 * 300;
            text += &format!(
                "{t},{},{},{}\n",
                x as u16,
                y as u16,
                (k + step as usize) % 2
            );
            text += &format!("{},{},{},1\n", t + 40, x as u16 + 1, y as u16);
        }
    }
    let path = dir.join("bursts.csv");
    std::fs::write(&path, text).unwrap();
    path
}

/// One request as the page sends it (its own `Host`; a control with its content type); the
/// status code and body.
pub fn request(address: SocketAddr, method: &str, path: &str, body: &str) -> (u16, String) {
    let kind = match method {
        "POST" => format!("Content-Type: {}\r\n", neurotac_view::CONTROL_CONTENT_TYPE),
        _ => String::new(),
    };
    let head = format!(
        "{method} {path} HTTP/1.1\r\nHost: {address}\r\n{kind}Content-Length: {}\r\n\r\n",
        body.len()
    );
    raw(address, &[head.as_bytes(), body.as_bytes()].concat())
}

/// `bytes` sent as they are; the status code and body of the answer (status 0: none).
pub fn raw(address: SocketAddr, bytes: &[u8]) -> (u16, String) {
    let mut s = TcpStream::connect(address).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    s.write_all(bytes).unwrap();
    let mut response = String::new();
    let _ = s.read_to_string(&mut response);
    let status = response
        .get(9..12)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    let body = response
        .split_once("\r\n\r\n")
        .map_or("", |(_, b)| b)
        .to_owned();
    (status, body)
}

pub fn latest(address: SocketAddr) -> Value {
    let (status, body) = request(address, "GET", "/frame.json", "");
    assert_eq!(status, 200);
    serde_json::from_str(&body).unwrap_or(Value::Null)
}

/// A tab: the Server-Sent Events of `/stream`.
pub struct Tab(pub BufReader<TcpStream>);

impl Tab {
    pub fn open(address: SocketAddr) -> Tab {
        let mut s = TcpStream::connect(address).unwrap();
        s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
        write!(s, "GET /stream HTTP/1.1\r\nHost: {address}\r\n\r\n").unwrap();
        let mut tab = Tab(BufReader::new(s));
        let mut line = String::new();
        tab.0.read_line(&mut line).unwrap();
        assert!(line.starts_with("HTTP/1.1 200"), "{line}");
        tab
    }

    /// The next frame message.
    pub fn next(&mut self) -> Value {
        loop {
            let mut line = String::new();
            assert!(self.0.read_line(&mut line).unwrap() > 0, "the stream ended");
            if let Some(data) = line.strip_prefix("data: ") {
                return serde_json::from_str(data).unwrap();
            }
        }
    }

    /// Frames until one satisfies `done` (within 20 s).
    pub fn until(&mut self, done: impl Fn(&Value) -> bool) -> Value {
        let deadline = Instant::now() + Duration::from_secs(20);
        loop {
            let m = self.next();
            if done(&m) {
                return m;
            }
            assert!(
                Instant::now() < deadline,
                "no such frame; last: {}",
                strip(&m)
            );
        }
    }
}

/// A message without its SVG, for assertion messages.
pub fn strip(m: &Value) -> Value {
    let mut m = m.clone();
    m.as_object_mut().map(|o| o.remove("svg"));
    m
}

/// Serves `source` at `speed` while `test` runs with the address, then stops; the player's
/// end.
pub fn serving(
    source: &mut dyn StreamSource,
    speed: Speed,
    test: impl FnOnce(SocketAddr) + Send,
) -> neurotac_view::PlayerEnd {
    serving_with(ServerLimits::default(), source, speed, test)
}

/// [`serving`] with the server's `limits`.
pub fn serving_with(
    limits: ServerLimits,
    source: &mut dyn StreamSource,
    speed: Speed,
    test: impl FnOnce(SocketAddr) + Send,
) -> neurotac_view::PlayerEnd {
    let hub = Hub::start();
    let server = Server::bind("127.0.0.1", 0, Arc::clone(&hub))
        .unwrap()
        .with_limits(limits);
    let address = server.local_addr();
    server.spawn();
    let options = PlayerOptions {
        speed,
        paused: false,
        monitor: MonitorConfig::default(),
    };
    let layout = TaxelLayout::neurotac_default();
    std::thread::scope(|scope| {
        let tester = scope.spawn(|| test(address));
        let stopper = Arc::clone(&hub);
        scope.spawn(move || {
            // The player stops when the test is over, passed or not.
            while !tester.is_finished() {
                std::thread::sleep(Duration::from_millis(10));
            }
            stopper.stop();
            if let Err(panic) = tester.join() {
                std::panic::resume_unwind(panic);
            }
        });
        let mut observer = NoObserver;
        Player::new(source, &mut observer, &hub, &layout, options)
            .unwrap()
            .run()
    })
}
