//! `neurotac view` as a user runs it: the address printed, a clean stop on Ctrl-C, snapshots
//! of a recording and of the simulator with the recogniser, and bad input in one line.

mod common;

use common::neurotac;
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn recording() -> Option<std::path::PathBuf> {
    Some(neurotac_core::testing::shared_data("davis240")?.join("pick.aedat"))
}

#[test]
fn the_server_prints_its_address_and_stops_cleanly_on_ctrl_c() {
    let Some(pick) = recording() else { return };
    let mut child = Command::new(env!("CARGO_BIN_EXE_neurotac"))
        .args(["view", pick.to_str().unwrap(), "--port", "0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    let mut line = String::new();
    stdout.read_line(&mut line).unwrap();
    assert!(
        line.starts_with("serving http://127.0.0.1:") && line.contains("Ctrl-C"),
        "{line}"
    );
    let address = line
        .split_whitespace()
        .nth(1)
        .unwrap()
        .trim_end_matches('/');
    let address = address.trim_start_matches("http://").to_owned();
    // The page answers, then Ctrl-C.
    let mut s = std::net::TcpStream::connect(&address).unwrap();
    use std::io::{Read, Write};
    write!(s, "GET / HTTP/1.1\r\nHost: {address}\r\n\r\n").unwrap();
    let mut page = String::new();
    s.read_to_string(&mut page).unwrap();
    assert!(page.starts_with("HTTP/1.1 200") && page.contains("neurotac view"));
    unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
    let deadline = Instant::now() + Duration::from_secs(10);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        assert!(Instant::now() < deadline, "still running 10 s after Ctrl-C");
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut rest = String::new();
    stdout.read_to_string(&mut rest).unwrap();
    assert!(status.success(), "{status}");
    assert!(rest.contains("stopped after"), "{rest}");
}

#[test]
fn a_taken_port_is_one_line_and_a_failure() {
    let Some(pick) = recording() else { return };
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port().to_string();
    let (ok, _, stderr) = neurotac(&["view", pick.to_str().unwrap(), "--port", &port]);
    assert!(!ok);
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(stderr.contains(&format!("127.0.0.1:{port}")), "{stderr}");
    assert!(stderr.contains("--port 0"), "{stderr}");
}

#[test]
fn a_snapshot_draws_a_recording_at_a_chosen_time_as_svg_or_png() {
    let Some(pick) = recording() else { return };
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("pick.svg");
    let pick_s = pick.to_str().unwrap();
    let (ok, stdout, stderr) = neurotac(&[
        "view",
        pick_s,
        "--snapshot",
        svg.to_str().unwrap(),
        "--at",
        "0.5s",
    ]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("t = 0.500 s"), "{stdout}");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") && text.contains("class=\"events\""));
    assert_eq!(text.matches("class=\"taxel\"").count(), 49);
    // At the end: every spike `neurotac transduce` finds is in the raster.
    let (ok, transduced, _) = neurotac(&[
        "transduce",
        pick_s,
        "--out",
        dir.path().join("pick.json").to_str().unwrap(),
    ]);
    assert!(ok);
    let spikes: usize = transduced
        .split(" taxel spikes")
        .next()
        .unwrap()
        .rsplit(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let png = dir.path().join("pick.png");
    let (ok, _, stderr) = neurotac(&["view", pick_s, "--snapshot", png.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    let end = dir.path().join("end.svg");
    neurotac(&["view", pick_s, "--snapshot", end.to_str().unwrap()]);
    let text = std::fs::read_to_string(&end).unwrap();
    assert_eq!(text.matches("class=\"spike\"").count(), spikes);
    // An existing output is kept without --force; a time past the end is refused.
    let (ok, _, stderr) = neurotac(&["view", pick_s, "--snapshot", png.to_str().unwrap()]);
    assert!(!ok && stderr.contains("--force"), "{stderr}");
    let late = dir.path().join("late.svg");
    let (ok, _, stderr) = neurotac(&[
        "view",
        pick_s,
        "--snapshot",
        late.to_str().unwrap(),
        "--at",
        "9s",
    ]);
    assert!(!ok && stderr.contains("after the stream's end"), "{stderr}");
    assert!(!late.exists());
}

#[test]
fn a_snapshot_of_the_simulator_shows_the_recogniser_of_every_coding() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sim.svg");
    let cache = dir.path().join("cache");
    let (ok, stdout, stderr) = neurotac(&[
        "view",
        "--simulate",
        "grid 5 mm",
        "--train",
        "artificial",
        "--trials",
        "3",
        "--cache",
        cache.to_str().unwrap(),
        "--snapshot",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("wrote"), "{stdout}");
    let text = std::fs::read_to_string(&out).unwrap();
    for coding in ["intensive", "spatial", "temporal", "spatiotemporal"] {
        assert!(text.contains(coding), "{coding} is shown");
    }
    assert!(text.contains("simulated grid 5.0 mm, slide 1"));
}

#[test]
fn bad_sources_are_one_line_each() {
    let dir = tempfile::tempdir().unwrap();
    let (ok, _, stderr) = neurotac(&["view", "--simulate", "velvet", "--snapshot", "x.svg"]);
    assert!(!ok && stderr.contains("velvet"), "{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    let missing = dir.path().join("missing.aedat");
    let (ok, _, stderr) = neurotac(&["view", missing.to_str().unwrap()]);
    assert!(!ok && stderr.contains("missing.aedat"), "{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    let (ok, _, stderr) = neurotac(&["view", "--device", "--snapshot", "x.png"]);
    assert!(!ok && stderr.contains("--snapshot"), "{stderr}");
}

/// A small CSV recording: a burst at the first taxels.
fn small_recording(dir: &std::path::Path) -> std::path::PathBuf {
    let mut text = String::from("t,x,y,on\n");
    for i in 0..400 {
        text += &format!("{},{},{},{}\n", i * 100, 60 + i % 7, 40 + i % 5, i % 2);
    }
    let path = dir.join("small.csv");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_snapshot_extension_is_read_in_any_case_and_another_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let input = small_recording(dir.path());
    let input = input.to_str().unwrap();
    for name in ["x.jpg", "x", "x.svg.txt"] {
        let out = dir.path().join(name);
        let (ok, _, stderr) = neurotac(&["view", input, "--snapshot", out.to_str().unwrap()]);
        assert!(!ok && stderr.contains(".svg or .png"), "{name}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
        assert!(!out.exists(), "{name} was written");
    }
    let png = dir.path().join("x.PNG");
    let (ok, _, stderr) = neurotac(&["view", input, "--snapshot", png.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    let svg = dir.path().join("x.Svg");
    let (ok, _, stderr) = neurotac(&["view", input, "--snapshot", svg.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
}

#[test]
fn absurd_speeds_and_times_are_refused_in_one_line_naming_the_value() {
    let dir = tempfile::tempdir().unwrap();
    let input = small_recording(dir.path());
    let input = input.to_str().unwrap();
    let (ok, _, stderr) = neurotac(&["view", input, "--speed", "1e-300", "--port", "0"]);
    assert!(!ok && stderr.contains("1e-300"), "{stderr}");
    let out = dir.path().join("late.svg");
    let (ok, _, stderr) = neurotac(&[
        "view",
        input,
        "--snapshot",
        out.to_str().unwrap(),
        "--at",
        "1e300s",
    ]);
    assert!(!ok && stderr.contains("1e300s is above"), "{stderr}");
    assert!(!stderr.contains("infs"), "{stderr}");
}

/// Starts `neurotac view ARGS`, kills it once it serves, and returns what it printed to stderr.
fn first_warning(args: &[&str]) -> String {
    let mut child = Command::new(env!("CARGO_BIN_EXE_neurotac"))
        .arg("view")
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    let mut line = String::new();
    stdout.read_line(&mut line).unwrap();
    assert!(line.starts_with("serving http://"), "{line}");
    let _ = child.kill();
    let _ = child.wait();
    let mut stderr = String::new();
    use std::io::Read;
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut stderr)
        .unwrap();
    stderr
}

#[test]
fn a_host_that_is_not_loopback_gets_one_warning_line() {
    let dir = tempfile::tempdir().unwrap();
    let input = small_recording(dir.path());
    let input = input.to_str().unwrap();
    let stderr = first_warning(&[input, "--port", "0", "--host", "0.0.0.0", "--paused"]);
    let warnings: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("warning"))
        .collect();
    assert_eq!(warnings.len(), 1, "{stderr}");
    assert!(warnings[0].contains("not a loopback address"), "{stderr}");
    for host in ["127.0.0.1", "localhost"] {
        let stderr = first_warning(&[input, "--port", "0", "--host", host, "--paused"]);
        assert!(!stderr.contains("warning"), "{host}: {stderr}");
    }
}
