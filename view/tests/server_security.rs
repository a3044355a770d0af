//! The page's server against clients that are not its page: a DNS-rebinding page (a foreign
//! `Host`), a page of another site posting controls, malformed and oversized requests, clients
//! that trickle or stop reading, too many connections, absurd control values; and a recording
//! deleted under a running view.

mod common;

use common::{Tab, latest, raw, recording, request, serving, serving_with};
use neurotac_view::{
    CONTROL_CONTENT_TYPE, Control, FileSource, Hub, MonitorConfig, NoObserver, Player,
    PlayerOptions, ServerLimits, Speed,
};
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A request with `headers` (one `Name: value` per line, without line ends) and `body`.
fn with_headers(address: SocketAddr, start: &str, headers: &[&str], body: &str) -> (u16, String) {
    let mut head = format!("{start} HTTP/1.1\r\n");
    for h in headers {
        head += &format!("{h}\r\n");
    }
    head += &format!("Content-Length: {}\r\n\r\n{body}", body.len());
    raw(address, head.as_bytes())
}

#[test]
fn only_requests_naming_this_server_are_answered() {
    let dir = tempfile::tempdir().unwrap();
    let path = recording(dir.path(), 1);
    let mut source = FileSource::open(&path).unwrap();
    serving(&mut source, Speed::Max, |address| {
        let port = address.port();
        for host in [
            format!("127.0.0.1:{port}"),
            format!("localhost:{port}"),
            format!("[::1]:{port}"),
        ] {
            let (status, _) =
                with_headers(address, "GET /frame.json", &[&format!("Host: {host}")], "");
            assert_eq!(status, 200, "{host}");
        }
        // A DNS-rebinding page names its own site: it reads nothing (the source's path least).
        for path in ["/frame.json", "/stream", "/", "/frame.svg"] {
            let (status, body) = with_headers(
                address,
                &format!("GET {path}"),
                &[&format!("Host: evil.example:{port}")],
                "",
            );
            assert_eq!(status, 403, "{path}: {body}");
            assert!(
                !body.contains("bursts.csv") && body.contains("evil.example"),
                "{body}"
            );
        }
        let other_port = format!("Host: 127.0.0.1:{}", port.wrapping_add(1));
        assert_eq!(with_headers(address, "GET /", &[&other_port], "").0, 403);
        assert_eq!(with_headers(address, "GET /", &[], "").0, 400, "no Host");
    });
}

#[test]
fn a_control_from_another_site_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = recording(dir.path(), 3);
    let mut source = FileSource::open(&path).unwrap();
    serving(&mut source, Speed::Paced(1.0), |address| {
        let mut tab = Tab::open(address);
        tab.until(|m| m["t_s"].as_f64().unwrap() > 0.05);
        let host = format!("Host: {address}");
        let kind = format!("Content-Type: {CONTROL_CONTENT_TYPE}");
        // What a page of another site can send without a preflight: a simple content type.
        for simple in [
            "text/plain",
            "application/x-www-form-urlencoded",
            "multipart/form-data",
        ] {
            let (status, why) = with_headers(
                address,
                "POST /control",
                &[
                    &host,
                    &format!("Content-Type: {simple}"),
                    "Origin: http://evil.example",
                ],
                "pause",
            );
            assert_eq!(status, 403, "{simple}: {why}");
            let (status, why) = with_headers(
                address,
                "POST /control",
                &[&host, &format!("Content-Type: {simple}")],
                "pause",
            );
            assert_eq!(status, 415, "{simple}: {why}");
            assert!(why.contains(CONTROL_CONTENT_TYPE), "{why}");
        }
        // The right content type from another origin.
        for origin in ["http://evil.example", "null", &format!("https://{address}")] {
            let origin = format!("Origin: {origin}");
            let (status, _) =
                with_headers(address, "POST /control", &[&host, &kind, &origin], "pause");
            assert_eq!(status, 403, "{origin}");
        }
        std::thread::sleep(Duration::from_millis(200));
        assert_eq!(
            latest(address)["state"],
            "playing",
            "a refused control paused it"
        );
        // The page's own origin, or none (a program such as curl), is obeyed.
        let own = format!("Origin: http://{address}");
        let (status, why) = with_headers(address, "POST /control", &[&host, &kind, &own], "pause");
        assert_eq!(status, 204, "{why}");
        tab.until(|m| m["state"] == "paused");
        let (status, _) = with_headers(address, "POST /control", &[&host, &kind], "play");
        assert_eq!(status, 204);
        tab.until(|m| m["state"] == "playing");
        // The page itself sends the content type.
        let (_, page_js) = request(address, "GET", "/page.js", "");
        assert!(page_js.contains(CONTROL_CONTENT_TYPE), "{page_js}");
    });
}

#[test]
fn malformed_and_oversized_requests_get_an_answer_naming_why() {
    let dir = tempfile::tempdir().unwrap();
    let path = recording(dir.path(), 1);
    let mut source = FileSource::open(&path).unwrap();
    serving(&mut source, Speed::Max, |address| {
        let host = format!("Host: {address}\r\n");
        let cases: [(Vec<u8>, u16, &str); 6] = [
            (b"GET /\xff\xfe HTTP/1.1\r\n\r\n".to_vec(), 400, "not UTF-8"),
            (
                b"GET / HTTP/1.1\r\nHost: \xc3\x28\r\n\r\n".to_vec(),
                400,
                "not UTF-8",
            ),
            (b"HELLO\r\n\r\n".to_vec(), 400, "request line"),
            (
                format!("GET / HTTP/1.1\r\n{host}no colon here\r\n\r\n").into_bytes(),
                400,
                "colon",
            ),
            (
                format!("POST /control HTTP/1.1\r\n{host}Content-Length: lots\r\n\r\n")
                    .into_bytes(),
                400,
                "Content-Length",
            ),
            (
                format!("POST /control HTTP/1.1\r\n{host}Content-Length: 99999999999\r\n\r\n")
                    .into_bytes(),
                413,
                "too large",
            ),
        ];
        for (bytes, expected, why) in cases {
            let (status, body) = raw(address, &bytes);
            assert_eq!(
                status,
                expected,
                "{:?}: {body}",
                String::from_utf8_lossy(&bytes)
            );
            assert!(body.contains(why), "{body}");
        }
        let long_header = format!("GET / HTTP/1.1\r\n{host}X: {}\r\n\r\n", "a".repeat(20_000));
        assert_eq!(raw(address, long_header.as_bytes()).0, 413);
        // Still serving.
        assert_eq!(request(address, "GET", "/", "").0, 200);
    });
}

#[test]
fn control_values_outside_their_ranges_are_refused_before_the_player() {
    let dir = tempfile::tempdir().unwrap();
    let path = recording(dir.path(), 1);
    let mut source = FileSource::open(&path).unwrap();
    let end = serving(&mut source, Speed::Paced(1.0), |address| {
        for bad in [
            "speed 1e-300",
            "speed 1e-7",
            "speed 1e7",
            "seek 1e300",
            "seek -0.5",
            "speed inf",
        ] {
            let (status, why) = request(address, "POST", "/control", bad);
            assert_eq!(status, 400, "{bad}: {why}");
            assert!(why.contains(bad) && why.contains("1e-6 to 1e6"), "{why}");
        }
        for good in [
            "speed 0.000001",
            "speed 1e6",
            "speed 1",
            "seek 9e12",
            "seek 0",
        ] {
            assert_eq!(request(address, "POST", "/control", good).0, 204, "{good}");
        }
        assert_eq!(request(address, "GET", "/", "").0, 200, "still serving");
    });
    assert_eq!(end.failure, None);
    assert_eq!(Control::parse("speed 1e-300"), None);
    assert_eq!(Control::parse("seek 1e300"), None);
}

#[test]
fn a_player_at_an_extreme_speed_over_far_apart_events_does_not_panic() {
    let dir = tempfile::tempdir().unwrap();
    // Events 2⁶² µs apart: no wait or due time between them fits a Duration at 1e-300×.
    let path = dir.path().join("far.csv");
    std::fs::write(&path, "t,x,y,on\n0,10,10,1\n4611686018427387904,11,10,0\n").unwrap();
    for speed in [Speed::Paced(1e-300), Speed::Paced(1e300), Speed::Paced(1.0)] {
        let mut source = FileSource::open(&path).unwrap();
        let hub = Hub::start();
        let options = PlayerOptions {
            speed,
            paused: false,
            monitor: MonitorConfig::default(),
        };
        let layout = neurotac_sensor::taxel::TaxelLayout::neurotac_default();
        let stopper = Arc::clone(&hub);
        let timer = std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(300));
            stopper.stop();
        });
        let mut observer = NoObserver;
        let end = Player::new(&mut source, &mut observer, &hub, &layout, options)
            .unwrap()
            .run();
        timer.join().unwrap();
        assert!(end.events >= 1, "{speed:?}");
    }
}

/// A connection that sends `GET / HTTP/1.1\r\n` one byte every `every`, for at most `for_at_most`;
/// how long the server let it go on (until it answered or closed).
fn trickle(address: SocketAddr, every: Duration, for_at_most: Duration) -> Duration {
    let mut s = TcpStream::connect(address).unwrap();
    s.set_read_timeout(Some(Duration::from_millis(1))).unwrap();
    let start = Instant::now();
    for &b in b"GET / HTTP/1.1\r\nX-Slow: "
        .iter()
        .chain(std::iter::repeat(&b'a'))
    {
        if s.write_all(&[b]).is_err() || start.elapsed() > for_at_most {
            break;
        }
        let mut byte = [0u8; 1];
        match s.read(&mut byte) {
            Ok(_) => break, // answered (408) or closed
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {}
            Err(_) => break,
        }
        std::thread::sleep(every);
    }
    start.elapsed()
}

#[test]
fn a_client_that_trickles_is_cut_off_at_its_deadline_and_connections_are_capped() {
    let dir = tempfile::tempdir().unwrap();
    let path = recording(dir.path(), 1);
    let mut source = FileSource::open(&path).unwrap();
    let limits = ServerLimits {
        request_deadline: Duration::from_millis(800),
        write_timeout: Duration::from_secs(10),
        max_connections: 3,
    };
    serving_with(limits, &mut source, Speed::Max, |address| {
        // One byte every 100 ms never lets a per-read timeout pass; the deadline does.
        let lasted = trickle(address, Duration::from_millis(100), Duration::from_secs(20));
        assert!(
            lasted < Duration::from_secs(10),
            "a trickling client lasted {lasted:?}"
        );
        // Three idle connections take every slot: a fourth is answered 503 at once.
        let idle: Vec<TcpStream> = (0..3)
            .map(|_| TcpStream::connect(address).unwrap())
            .collect();
        std::thread::sleep(Duration::from_millis(100));
        let (status, why) = request(address, "GET", "/", "");
        assert_eq!(status, 503, "{why}");
        // Past their deadline they are dropped, and the page is served again.
        std::thread::sleep(Duration::from_millis(1500));
        assert_eq!(request(address, "GET", "/", "").0, 200);
        drop(idle);
    });
}

#[test]
fn a_viewer_that_stops_reading_is_dropped_after_the_write_timeout() {
    let dir = tempfile::tempdir().unwrap();
    let path = recording(dir.path(), 60);
    let mut source = FileSource::open(&path).unwrap();
    let limits = ServerLimits {
        request_deadline: Duration::from_secs(10),
        write_timeout: Duration::from_millis(500),
        max_connections: 1,
    };
    serving_with(limits, &mut source, Speed::Paced(1.0), |address| {
        // A stream opened and never read: its socket fills, the write times out, its slot is
        // given back. Until then the only slot is taken.
        let mut stalled = TcpStream::connect(address).unwrap();
        write!(stalled, "GET /stream HTTP/1.1\r\nHost: {address}\r\n\r\n").unwrap();
        std::thread::sleep(Duration::from_millis(200));
        assert_eq!(request(address, "GET", "/", "").0, 503);
        let deadline = Instant::now() + Duration::from_secs(60);
        loop {
            std::thread::sleep(Duration::from_millis(250));
            if request(address, "GET", "/", "").0 == 200 {
                break;
            }
            assert!(
                Instant::now() < deadline,
                "the stalled viewer still holds its slot"
            );
        }
        drop(stalled);
    });
}

#[test]
fn a_recording_deleted_under_the_view_fails_with_the_systems_reason() {
    let dir = tempfile::tempdir().unwrap();
    let path = recording(dir.path(), 1);
    let mut source = FileSource::open(&path).unwrap();
    let end = serving(&mut source, Speed::Max, |address| {
        let mut tab = Tab::open(address);
        tab.until(|m| m["state"] == "ended");
        std::fs::remove_file(&path).unwrap();
        // Play at the end replays from the start: the file is opened again, and is gone.
        assert_eq!(request(address, "POST", "/control", "play").0, 204);
        let failed = tab.until(|m| m["state"] == "failed");
        let notice = failed["notice"].as_str().unwrap();
        assert!(notice.contains("bursts.csv"), "{notice}");
        let reason = std::io::Error::from(std::io::ErrorKind::NotFound).to_string();
        assert!(
            notice.contains("No such file")
                || notice.to_lowercase().contains(&reason.to_lowercase()),
            "the OS reason is kept: {notice}"
        );
    });
    assert!(end.failure.is_some());
}
