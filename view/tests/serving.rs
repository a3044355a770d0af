//! The page's server with a player behind it, over real HTTP on localhost: every tab gets the
//! stream, controls move it, and a failing source, a tab that leaves or a taken port each end
//! with a clear notice while the rest goes on.

mod common;

use common::{Tab, latest, recording, request, serving, strip};
use neurotac_view::{FileSource, Hub, Server, Speed, ViewError};
use serde_json::Value;
use std::sync::Arc;
use std::time::Duration;

#[test]
fn every_tab_sees_the_whole_recording_and_its_counts() {
    let dir = tempfile::tempdir().unwrap();
    let path = recording(dir.path(), 1);
    let mut source = FileSource::open(&path).unwrap();
    let end = serving(&mut source, Speed::Max, |address| {
        let (mut a, mut b) = (Tab::open(address), Tab::open(address));
        let ended = |m: &Value| m["state"] == "ended";
        let (from_a, from_b) = (a.until(ended), b.until(ended));
        assert_eq!(from_a["counts"], from_b["counts"]);
        assert_eq!(from_a["counts"]["events_in"], 2 * 49 * 33);
        let spikes = from_a["counts"]["taxel_spikes"].as_u64().unwrap();
        assert!(spikes > 1000, "{}", strip(&from_a));
        assert_eq!(from_a["raster_spikes"].as_u64().unwrap(), spikes);
        let svg = from_a["svg"].as_str().unwrap();
        assert!(svg.starts_with("<svg"));
        assert_eq!(svg.matches("class=\"spike\"").count() as u64, spikes);
        // The page and its assets come from the binary; the SVG alone too.
        let (status, page) = request(address, "GET", "/", "");
        assert_eq!(status, 200);
        for asset in ["/page.js", "/page.css"] {
            assert!(page.contains(asset));
            assert_eq!(request(address, "GET", asset, "").0, 200);
        }
        assert_eq!(request(address, "GET", "/frame.svg", "").1, svg);
        assert_eq!(request(address, "GET", "/nothing", "").0, 404);
        let (status, why) = request(address, "POST", "/control", "jump 3");
        assert_eq!(status, 400);
        assert!(why.contains("jump 3") && why.contains("seek"), "{why}");
        // Play at the end replays the recording from its start, to the same counts.
        request(address, "POST", "/control", "play");
        let seq = from_a["seq"].as_u64().unwrap();
        let again = a.until(|m| m["seq"].as_u64().unwrap() > seq && m["state"] == "ended");
        assert_eq!(again["counts"], from_a["counts"]);
    });
    // Played twice.
    assert_eq!(end.events, 2 * 2 * 49 * 33);
    assert_eq!(end.failure, None);
}

#[test]
fn pause_holds_step_moves_one_window_and_seek_goes_back() {
    let dir = tempfile::tempdir().unwrap();
    let path = recording(dir.path(), 3);
    let mut source = FileSource::open(&path).unwrap();
    serving(&mut source, Speed::Paced(1.0), |address| {
        let mut tab = Tab::open(address);
        tab.until(|m| m["t_s"].as_f64().unwrap() > 0.2);
        assert_eq!(request(address, "POST", "/control", "pause").0, 204);
        let paused = tab.until(|m| m["state"] == "paused");
        std::thread::sleep(Duration::from_millis(300));
        let held = latest(address);
        assert_eq!(held["seq"], paused["seq"], "no frame while paused");
        assert_eq!(held["counts"], paused["counts"]);
        // A step: one pooling window (20 ms) on, still paused.
        request(address, "POST", "/control", "step");
        let stepped = tab.next();
        let dt = stepped["t_s"].as_f64().unwrap() - paused["t_s"].as_f64().unwrap();
        assert!((dt - 0.02).abs() < 1e-9, "{dt}");
        assert_eq!(stepped["state"], "paused");
        // Back to 0.1 s: the counts of the first 0.1 s only.
        request(address, "POST", "/control", "seek 0.1");
        let back = tab.next();
        assert!((back["t_s"].as_f64().unwrap() - 0.1).abs() < 1e-9);
        let events = back["counts"]["events_in"].as_u64().unwrap();
        assert!(events > 0 && events < paused["counts"]["events_in"].as_u64().unwrap());
        // Play again at max: it runs to the end.
        request(address, "POST", "/control", "speed max");
        request(address, "POST", "/control", "play");
        let ended = tab.until(|m| m["state"] == "ended");
        assert_eq!(ended["counts"]["events_in"], 2 * 49 * 100);
        assert_eq!(ended["speed"], "max");
    });
}

#[test]
fn a_tab_that_leaves_does_not_stop_the_others() {
    let dir = tempfile::tempdir().unwrap();
    let path = recording(dir.path(), 2);
    let mut source = FileSource::open(&path).unwrap();
    serving(&mut source, Speed::Paced(1.0), |address| {
        let mut staying = Tab::open(address);
        let mut leaving = Tab::open(address);
        leaving.next();
        drop(leaving);
        let first = staying.next()["seq"].as_u64().unwrap();
        let later = staying.until(|m| m["seq"].as_u64().unwrap() > first + 10);
        assert_eq!(later["state"], "playing");
    });
}

#[test]
fn a_file_that_ends_early_fails_on_the_page_naming_the_file_and_the_server_stays() {
    let dir = tempfile::tempdir().unwrap();
    let path = recording(dir.path(), 1);
    let text = std::fs::read_to_string(&path).unwrap();
    // Cut inside a line, as a copy that stopped does.
    let cut = dir.path().join("cut.csv");
    std::fs::write(&cut, &text[..text.len() / 2 + 3]).unwrap();
    let mut source = FileSource::open(&cut).unwrap();
    let end = serving(&mut source, Speed::Max, |address| {
        let mut tab = Tab::open(address);
        let failed = tab.until(|m| m["state"] == "failed");
        let notice = failed["notice"].as_str().unwrap();
        assert!(notice.contains("cut.csv"), "{notice}");
        assert!(
            failed["counts"]["events_in"].as_u64().unwrap() > 0,
            "what came first is shown"
        );
        // Still serving: the page, the frame, another tab.
        assert_eq!(request(address, "GET", "/", "").0, 200);
        assert_eq!(Tab::open(address).next()["state"], "failed");
    });
    assert!(end.failure.unwrap().contains("cut.csv"));
}

#[test]
fn an_unplugged_camera_fails_on_the_page_after_showing_its_events() {
    use neurotac_sensor::davis::protocol::{FIRMWARE_FX2, PRODUCT_ID_FX2};
    use neurotac_sensor::davis::{Davis, DeviceInfo, ReplayEnd, ReplayTransport, StartOptions};
    let Some(dir) = neurotac_core::testing::shared_data("davis240") else {
        return;
    };
    let bytes = std::fs::read(dir.join("pick_usb_words.bin")).unwrap();
    let usb = DeviceInfo {
        product_id: PRODUCT_ID_FX2,
        firmware: FIRMWARE_FX2,
        bus: 1,
        address: 2,
        serial: None,
    };
    let cut = bytes.len() * 3 / 10 / 4 * 4;
    let transport = ReplayTransport::new(bytes[..cut].to_vec(), 8192, ReplayEnd::Unplug);
    let davis = Davis::open(transport, usb).unwrap();
    davis.send_default_config().unwrap();
    let stream = davis.start(StartOptions::default()).unwrap();
    let mut source = neurotac_view::CameraSource::new("DAVIS240 (replayed)".into(), stream);
    let end = serving(&mut source, Speed::Paced(1.0), |address| {
        let failed = Tab::open(address).until(|m| m["state"] == "failed");
        let notice = failed["notice"].as_str().unwrap();
        assert!(notice.contains("DAVIS240 (replayed)"), "{notice}");
        assert!(
            notice.to_lowercase().contains("unplugged") || notice.contains("isconnected"),
            "{notice}"
        );
        assert!(failed["counts"]["events_in"].as_u64().unwrap() > 10_000);
        assert_eq!(failed["speed"], "live");
    });
    assert!(end.failure.is_some());
}

#[test]
fn a_taken_port_is_an_error_naming_the_address() {
    let hub = Hub::start();
    let first = Server::bind("127.0.0.1", 0, Arc::clone(&hub)).unwrap();
    let port = first.local_addr().port();
    let Err(e) = Server::bind("127.0.0.1", port, hub) else {
        panic!("the port is taken");
    };
    assert!(matches!(e, ViewError::Listen { .. }));
    assert!(e.to_string().contains(&format!("127.0.0.1:{port}")), "{e}");
}

#[test]
fn controls_parse_as_the_page_sends_them() {
    use neurotac_view::Control;
    assert_eq!(Control::parse("pause"), Some(Control::Pause));
    assert_eq!(Control::parse("seek 1.25"), Some(Control::Seek(1.25)));
    assert_eq!(
        Control::parse("speed max"),
        Some(Control::Speed(Speed::Max))
    );
    assert_eq!(
        Control::parse("speed 2x"),
        Some(Control::Speed(Speed::Paced(2.0)))
    );
    assert_eq!(
        Control::parse("speed realtime"),
        Some(Control::Speed(Speed::Paced(1.0)))
    );
    for bad in [
        "",
        "seek",
        "seek -1",
        "seek nan",
        "speed 0",
        "speed fast",
        "pause now",
    ] {
        assert_eq!(Control::parse(bad), None, "{bad:?}");
    }
}
