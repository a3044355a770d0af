//! A headless Chromium for the tests that open the live view's page in a real browser:
//! [`chromium`] finds one (or says why the test skips), [`Browser`] runs it and opens
//! [`Tab`]s, driven over the Chrome DevTools Protocol ([`cdp`]). Every wait has a deadline, so
//! a hung browser fails the test with a message instead of hanging it; the browser and its
//! children are killed when the [`Browser`] is dropped.

pub mod cdp;

use std::collections::VecDeque;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex, mpsc};
use std::time::{Duration, Instant};

use base64::Engine;
use cdp::Cdp;
use serde_json::{Value, json};

/// The longest any one wait on the browser (or the page) lasts before the test fails.
pub const DEADLINE: Duration = Duration::from_secs(30);

/// Environment variable naming the Chromium (or Chrome) executable to use.
pub const CHROMIUM_ENV: &str = "NEUROTAC_CHROMIUM";

/// Environment variable that turns a skip for want of a browser into a failure (CI sets it to
/// `1` when it has installed Chromium).
pub const REQUIRE_ENV: &str = "NEUROTAC_REQUIRE_BROWSER";

const NO_CHROMIUM: &str =
    "skipped: no Chromium (install Debian's chromium or set NEUROTAC_CHROMIUM)";

/// The browser to drive: `$NEUROTAC_CHROMIUM`, else `/usr/bin/chromium`,
/// `/usr/bin/chromium-browser`, or `google-chrome` on the PATH. `None` (after saying so) when
/// there is none; panics instead when `NEUROTAC_REQUIRE_BROWSER=1`, or when
/// `$NEUROTAC_CHROMIUM` names no file.
pub fn chromium() -> Option<PathBuf> {
    if let Some(named) = std::env::var_os(CHROMIUM_ENV).filter(|v| !v.is_empty()) {
        let named = PathBuf::from(named);
        assert!(
            named.is_file(),
            "{CHROMIUM_ENV}={} is not a file",
            named.display()
        );
        return Some(named);
    }
    let on_path = std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|dir| dir.join("google-chrome"))
            .find(|p| p.is_file())
    });
    let found = ["/usr/bin/chromium", "/usr/bin/chromium-browser"]
        .into_iter()
        .map(PathBuf::from)
        .find(|p| p.is_file())
        .or(on_path);
    if found.is_none() {
        if std::env::var(REQUIRE_ENV).is_ok_and(|v| v == "1") {
            panic!("{NO_CHROMIUM}, and {REQUIRE_ENV}=1 makes that a failure");
        }
        eprintln!("{NO_CHROMIUM}");
    }
    found
}

/// The last lines a child process wrote to a pipe, kept for failure messages.
#[derive(Clone, Default)]
pub struct Tail(Arc<Mutex<VecDeque<String>>>);

impl Tail {
    const LINES: usize = 40;

    fn push(&self, line: String) {
        let mut lines = self.0.lock().unwrap();
        if lines.len() == Self::LINES {
            lines.pop_front();
        }
        lines.push_back(line);
    }

    /// The kept lines, one per line.
    pub fn text(&self) -> String {
        let lines = self.0.lock().unwrap();
        lines.iter().map(|l| format!("  {l}\n")).collect()
    }
}

/// Reads `pipe` line by line on a thread until it closes, keeping the last lines in the
/// returned [`Tail`] and sending each line `pick` accepts (what it returns) on the returned
/// channel. Draining the pipe keeps the child from blocking on a full one.
pub fn follow_lines(
    pipe: impl Read + Send + 'static,
    pick: impl Fn(&str) -> Option<String> + Send + 'static,
) -> (Tail, mpsc::Receiver<String>) {
    let (tail, sent) = (Tail::default(), mpsc::channel());
    let (kept, tx) = (tail.clone(), sent.0);
    std::thread::spawn(move || {
        for line in BufReader::new(pipe).lines() {
            let Ok(line) = line else { break };
            if let Some(picked) = pick(&line) {
                let _ = tx.send(picked);
            }
            kept.push(line);
        }
    });
    (tail, sent.1)
}

/// A running headless Chromium with its own profile folder; killed (with every process it
/// started) when dropped.
pub struct Browser {
    child: Child,
    stderr: Tail,
    /// The DevTools HTTP port.
    port: u16,
    /// The browser-wide DevTools connection (targets: open and close tabs).
    cdp: Option<Cdp>,
    _profile: tempfile::TempDir,
}

impl Browser {
    /// Starts `program` headless on about:blank and connects to its DevTools endpoint.
    pub fn launch(program: &Path) -> Browser {
        let profile = tempfile::tempdir().unwrap();
        let mut command = Command::new(program);
        command
            .args([
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--disable-quic",
                "--no-first-run",
                "--disable-background-networking",
                "--disable-component-update",
                "--disable-sync",
                // Two tabs watch one stream at once: neither may be throttled as hidden.
                "--disable-background-timer-throttling",
                "--disable-renderer-backgrounding",
                "--disable-backgrounding-occluded-windows",
            ])
            .arg(format!("--user-data-dir={}", profile.path().display()))
            .args([
                "--remote-debugging-port=0",
                "--window-size=1300,900",
                "about:blank",
            ])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            // Its own process group, so that Drop kills the renderers and helpers too.
            .process_group(0);
        let mut child = command
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start {}: {e}", program.display()));
        let (stderr, endpoint) = follow_lines(child.stderr.take().unwrap(), |line| {
            line.strip_prefix("DevTools listening on ")
                .map(|url| url.trim().to_owned())
        });
        let mut browser = Browser {
            child,
            stderr,
            port: 0,
            cdp: None,
            _profile: profile,
        };
        let url = endpoint.recv_timeout(DEADLINE).unwrap_or_else(|_| {
            panic!(
                "{} did not say \"DevTools listening on ws://…\" within {} s; its stderr ends:\n{}",
                program.display(),
                DEADLINE.as_secs(),
                browser.stderr.text()
            )
        });
        browser.port = devtools_port(&url)
            .unwrap_or_else(|| panic!("no port in the DevTools address {url:?}"));
        browser.cdp = Some(Cdp::connect(&url));
        browser
    }

    /// The tab the browser opened with (about:blank), found in `GET /json/list`.
    pub fn first_tab(&mut self) -> Tab {
        let deadline = Instant::now() + DEADLINE;
        loop {
            let (status, body) = http_get(self.port, "/json/list");
            let targets: Value = serde_json::from_str(&body).unwrap_or(Value::Null);
            let page = targets.as_array().and_then(|targets| {
                targets
                    .iter()
                    .find(|t| t["type"] == "page" && t["webSocketDebuggerUrl"].is_string())
            });
            if let Some(page) = page {
                return Tab::connect(
                    page["id"].as_str().unwrap(),
                    page["webSocketDebuggerUrl"].as_str().unwrap(),
                );
            }
            assert!(
                Instant::now() < deadline,
                "no page target in /json/list within {} s (HTTP {status}): {body}",
                DEADLINE.as_secs()
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    /// A new tab in its own window (so that both tabs are visible and neither is throttled),
    /// on about:blank.
    pub fn new_tab(&mut self) -> Tab {
        let created = self.cdp().call(
            "Target.createTarget",
            json!({ "url": "about:blank", "newWindow": true }),
        );
        let id = created["targetId"]
            .as_str()
            .unwrap_or_else(|| panic!("Target.createTarget returned {created}"));
        Tab::connect(
            id,
            &format!("ws://127.0.0.1:{}/devtools/page/{id}", self.port),
        )
    }

    /// Closes `tab`.
    pub fn close_tab(&mut self, tab: Tab) {
        let closed = self
            .cdp()
            .call("Target.closeTarget", json!({ "targetId": tab.target_id }));
        drop(tab);
        assert_ne!(closed["success"], false, "Target.closeTarget: {closed}");
    }

    fn cdp(&mut self) -> &mut Cdp {
        self.cdp.as_mut().expect("connected at launch")
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        // The whole process group: the browser, its zygote, renderers and helpers.
        // SAFETY: kill(2) with a negative pid signals that process group; no memory involved.
        unsafe { libc::kill(-(self.child.id() as i32), libc::SIGKILL) };
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The port of a DevTools address `ws://HOST:PORT/devtools/…`.
pub fn devtools_port(url: &str) -> Option<u16> {
    let authority = url.strip_prefix("ws://")?.split('/').next()?;
    authority.rsplit_once(':')?.1.parse().ok()
}

/// One page of the browser.
pub struct Tab {
    /// The DevTools target id.
    pub target_id: String,
    cdp: Cdp,
}

impl Tab {
    fn connect(target_id: &str, url: &str) -> Tab {
        Tab {
            target_id: target_id.to_owned(),
            cdp: Cdp::connect(url),
        }
    }

    /// Opens `url` and waits until the document has loaded.
    pub fn navigate(&mut self, url: &str) {
        let navigated = self.cdp.call("Page.navigate", json!({ "url": url }));
        if let Some(why) = navigated.get("errorText") {
            panic!("Page.navigate to {url}: {why}");
        }
        self.wait_for(&format!("{url} to load"), |tab| {
            (tab.eval("document.readyState") == "complete").then_some(())
        });
    }

    /// The value of the JavaScript `expression` (promises awaited), as JSON; `null` for
    /// `undefined`. Panics when it throws.
    pub fn eval(&mut self, expression: &str) -> Value {
        let reply = self.cdp.call(
            "Runtime.evaluate",
            json!({ "expression": expression, "returnByValue": true, "awaitPromise": true }),
        );
        if let Some(thrown) = reply.get("exceptionDetails") {
            let what = thrown["exception"]["description"].as_str();
            panic!(
                "{expression} threw: {}",
                what.unwrap_or(&thrown.to_string())
            );
        }
        reply["result"].get("value").cloned().unwrap_or(Value::Null)
    }

    /// Calls `probe` (every 50 ms) until it returns something, at most [`DEADLINE`]; panics
    /// with "waited … for `what`" after that.
    pub fn wait_for<T>(&mut self, what: &str, mut probe: impl FnMut(&mut Tab) -> Option<T>) -> T {
        let deadline = Instant::now() + DEADLINE;
        loop {
            if let Some(found) = probe(self) {
                return found;
            }
            assert!(
                Instant::now() < deadline,
                "waited {} s for {what}",
                DEADLINE.as_secs()
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// A PNG screenshot of the element `#id` (all of it, also where it reaches past the window).
    pub fn screenshot_png(&mut self, id: &str) -> Vec<u8> {
        let rect = self.eval(&format!(
            "(() => {{
                const r = document.getElementById('{id}').getBoundingClientRect();
                return {{ x: r.x + scrollX, y: r.y + scrollY, width: r.width, height: r.height,
                          scale: 1 }};
            }})()"
        ));
        let shot = self.cdp.call(
            "Page.captureScreenshot",
            json!({ "format": "png", "clip": rect, "captureBeyondViewport": true }),
        );
        let data = shot["data"]
            .as_str()
            .unwrap_or_else(|| panic!("Page.captureScreenshot returned no data"));
        base64::engine::general_purpose::STANDARD
            .decode(data)
            .expect("the screenshot is base64")
    }
}

/// `(status, body)` of `GET path` on `127.0.0.1:port`, within [`DEADLINE`]. (HTTP/1.1:
/// Chromium's DevTools server answers nothing to HTTP/1.0; the body is `Content-Length` long,
/// or lasts until the server closes.)
pub fn http_get(port: u16, path: &str) -> (u16, String) {
    let mut stream = TcpStream::connect_timeout(&([127, 0, 0, 1], port).into(), DEADLINE)
        .unwrap_or_else(|e| panic!("cannot connect to 127.0.0.1:{port}: {e}"));
    stream.set_read_timeout(Some(DEADLINE)).unwrap();
    stream.set_write_timeout(Some(DEADLINE)).unwrap();
    write!(
        stream,
        "GET {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let failed = |e: std::io::Error| panic!("GET {path} on port {port}: {e}");
    let mut reader = BufReader::new(stream);
    let mut head = Vec::new();
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line).unwrap_or_else(failed) == 0 || line == "\r\n" {
            break;
        }
        head.push(line.trim_end().to_owned());
    }
    let status = head
        .first()
        .and_then(|line| line.split(' ').nth(1))
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("GET {path} on port {port}: not HTTP: {head:?}"));
    let length = head.iter().find_map(|line| {
        let (name, value) = line.split_once(':')?;
        name.eq_ignore_ascii_case("content-length")
            .then(|| value.trim().parse::<u64>().ok())?
    });
    let mut body = Vec::new();
    match length {
        Some(n) => reader.take(n).read_to_end(&mut body),
        None => reader.read_to_end(&mut body),
    }
    .unwrap_or_else(failed);
    (status, String::from_utf8_lossy(&body).into_owned())
}
