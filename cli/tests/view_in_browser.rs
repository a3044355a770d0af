//! `neurotac view` in a real browser: a headless Chromium opens the live page of the shared
//! DAVIS240 recording and reads what it shows (design: the page's DOM ids and SSE messages).
//! Skips with a reason when there is no Chromium (a failure when `NEUROTAC_REQUIRE_BROWSER=1`)
//! or no shared data.

mod browser;
mod common;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use browser::{Browser, DEADLINE, Tab, Tail, follow_lines};
use common::neurotac;

/// The shared recording (1.39 s of a pin array being picked up), or `None` with the reason.
fn pick_recording() -> Option<PathBuf> {
    neurotac_core::testing::shared_data("davis240").map(|dir| dir.join("pick.aedat"))
}

/// The four stage counts `neurotac transduce` prints first:
/// `N pixel events → N after filters → N in receptive fields → N taxel spikes …`.
fn transduce_counts(recording: &Path) -> [u64; 4] {
    let out = tempfile::tempdir().unwrap();
    let spikes = out.path().join("spikes.json");
    let (ok, stdout, stderr) = neurotac(&[
        "transduce",
        recording.to_str().unwrap(),
        "--out",
        spikes.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let first = stdout.lines().next().unwrap_or_default();
    let stages: Vec<&str> = first.split(" → ").collect();
    let labels = [
        "pixel events",
        "after filters",
        "in receptive fields",
        "taxel spikes",
    ];
    assert_eq!(stages.len(), labels.len(), "{first}");
    std::array::from_fn(|i| {
        let (n, label) = stages[i].split_once(' ').unwrap_or_default();
        assert!(label.starts_with(labels[i]), "{first}");
        n.parse().unwrap_or_else(|_| panic!("{n:?} in {first:?}"))
    })
}

/// A running `neurotac view …`, killed when dropped.
struct View {
    child: Child,
    /// `http://127.0.0.1:PORT/`, as it printed.
    url: String,
    stderr: Tail,
}

impl View {
    /// Starts `neurotac view ARGS` and waits (at most [`DEADLINE`]) for its
    /// `serving http://…/ (Ctrl-C stops)` line.
    fn start(args: &[&str]) -> View {
        let mut child = Command::new(env!("CARGO_BIN_EXE_neurotac"))
            .arg("view")
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let (_, serving) = follow_lines(child.stdout.take().unwrap(), |line| {
            let url = line.strip_prefix("serving ")?.split(' ').next()?;
            Some(url.to_owned())
        });
        let (stderr, _) = follow_lines(child.stderr.take().unwrap(), |_| None);
        let mut view = View {
            child,
            url: String::new(),
            stderr,
        };
        view.url = serving.recv_timeout(DEADLINE).unwrap_or_else(|_| {
            std::thread::sleep(Duration::from_millis(300)); // let stderr be read
            panic!(
                "`neurotac view {}` did not print \"serving http://…\" within {} s ({:?}); stderr:\n{}",
                args.join(" "),
                DEADLINE.as_secs(),
                view.child.try_wait(),
                view.stderr.text()
            )
        });
        view
    }
}

impl Drop for View {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The page's readouts at one moment (text of each element, trimmed), and the number of
/// raster spikes drawn in `#view`.
struct Shown {
    text: HashMap<String, String>,
    spikes_drawn: u64,
}

const READOUTS: [&str; 13] = [
    "state",
    "frame-seq",
    "stream-time",
    "events-in",
    "after-filters",
    "in-fields",
    "taxel-spikes",
    "raster-spikes",
    "frames-skipped",
    "latency-ms",
    "latency-max-ms",
    "notice",
    "decimation",
];

impl Shown {
    /// Reads every readout of `tab` in one evaluation (so all of one frame). Panics when the
    /// page lacks one of the ids.
    fn read(tab: &mut Tab) -> Shown {
        let ids = serde_json::to_string(&READOUTS).unwrap();
        let value = tab.eval(&format!(
            "(() => {{
                const shown = {{}};
                for (const id of {ids}) {{
                    const e = document.getElementById(id);
                    shown[id] = e === null ? null : e.textContent.trim();
                }}
                shown['spikes-drawn'] = document.querySelectorAll('#view .spike').length;
                return shown;
            }})()"
        ));
        let text = READOUTS
            .iter()
            .map(|&id| {
                let t = value[id]
                    .as_str()
                    .unwrap_or_else(|| panic!("the page has no element #{id}"));
                (id.to_owned(), t.to_owned())
            })
            .collect();
        let spikes_drawn = value["spikes-drawn"].as_u64().unwrap();
        Shown { text, spikes_drawn }
    }

    fn text(&self, id: &str) -> &str {
        &self.text[id]
    }

    /// `#id` as an integer; panics when it is not one.
    fn int(&self, id: &str) -> u64 {
        let t = self.text(id);
        t.parse()
            .unwrap_or_else(|_| panic!("#{id} reads {t:?}, not an integer"))
    }

    /// `#id` as a number, `None` when it is not one (no frame yet, no value).
    fn num(&self, id: &str) -> Option<f64> {
        self.text(id).parse().ok().filter(|x: &f64| x.is_finite())
    }

    fn counts(&self) -> [u64; 4] {
        ["events-in", "after-filters", "in-fields", "taxel-spikes"].map(|id| self.int(id))
    }
}

/// Waits until `#state` reads `state` and returns that moment's readouts; panics when it reads
/// `failed` (with `#notice`) or, unless `state` is `ended`, `ended` first.
fn wait_for_state(tab: &mut Tab, state: &str) -> Shown {
    tab.wait_for(&format!("#state to read {state}"), |tab| {
        let shown = Shown::read(tab);
        match shown.text("state") {
            s if s == state => Some(shown),
            "failed" => panic!("the page says failed: {}", shown.text("notice")),
            "ended" => panic!(
                "the recording ended before #state read {state} (stream time {})",
                shown.text("stream-time")
            ),
            _ => None,
        }
    })
}

/// Waits until `#frame-seq` has advanced past its value now (new frames arrive).
fn wait_for_new_frames(tab: &mut Tab, what: &str) -> Shown {
    let first = tab.wait_for("a first frame (#frame-seq)", |tab| {
        Shown::read(tab).num("frame-seq")
    });
    tab.wait_for(
        &format!("#frame-seq to advance past {first} ({what})"),
        |tab| {
            let shown = Shown::read(tab);
            (shown.num("frame-seq")? > first).then_some(shown)
        },
    )
}

fn click(tab: &mut Tab, id: &str) {
    tab.eval(&format!("document.getElementById('{id}').click()"));
}

/// `(distinct colours, share of pixels not of the most common colour)` of a PNG.
fn colourfulness(png_bytes: &[u8]) -> (usize, f64) {
    let decoder = png::Decoder::new(std::io::Cursor::new(png_bytes));
    let mut reader = decoder.read_info().expect("the screenshot is a PNG");
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    let channels = info.color_type.samples();
    let mut histogram: HashMap<&[u8], usize> = HashMap::new();
    for pixel in pixels[..info.buffer_size()].chunks_exact(channels) {
        *histogram.entry(pixel).or_default() += 1;
    }
    let total: usize = histogram.values().sum();
    let background = histogram.values().max().copied().unwrap_or(0);
    (histogram.len(), 1.0 - background as f64 / total as f64)
}

#[test]
fn the_page_shows_transduce_counts_and_every_spike_of_a_recording() {
    let Some(chromium) = browser::chromium() else {
        return;
    };
    let Some(pick) = pick_recording() else {
        return;
    };
    let expected = transduce_counts(&pick);
    let view = View::start(&[pick.to_str().unwrap(), "--port", "0", "--speed", "4"]);
    let mut browser = Browser::launch(&chromium);
    let mut tab = browser.first_tab();
    tab.navigate(&view.url);
    let end = wait_for_state(&mut tab, "ended");

    assert_eq!(
        end.counts(),
        expected,
        "events in, after filters, in fields, taxel spikes: the page against `neurotac transduce`"
    );
    // The 1.39 s recording fits in the raster's 2 s window: every spike is drawn.
    assert_eq!(end.spikes_drawn, end.int("raster-spikes"));
    assert_eq!(end.spikes_drawn, expected[3]);

    // The frame's picture as the browser painted it: not blank.
    let png = tab.screenshot_png("view");
    let (colours, drawn_share) = colourfulness(&png);
    assert!(
        colours >= 64 && drawn_share >= 0.2,
        "the picture in #view looks blank: {colours} colours, {:.1} % not background",
        100.0 * drawn_share
    );
    println!(
        "page at the end (speed 4): {} events in → {} after filters → {} in fields → {} taxel \
         spikes, as `neurotac transduce`; {} spikes drawn (#raster-spikes {}); #view \
         painted: {} bytes of PNG, {colours} colours, {:.0} % not background",
        expected[0],
        expected[1],
        expected[2],
        expected[3],
        end.spikes_drawn,
        end.int("raster-spikes"),
        png.len(),
        100.0 * drawn_share
    );
}

#[test]
fn pausing_stops_the_page_and_two_tabs_watch_one_stream() {
    let Some(chromium) = browser::chromium() else {
        return;
    };
    let Some(pick) = pick_recording() else {
        return;
    };
    // At a quarter of real time the 1.39 s recording plays for 5.6 s.
    let view = View::start(&[pick.to_str().unwrap(), "--port", "0", "--speed", "0.25"]);
    let mut browser = Browser::launch(&chromium);
    let mut tabs = [browser.first_tab(), browser.new_tab()];
    for tab in &mut tabs {
        tab.navigate(&view.url);
    }
    for tab in &mut tabs {
        wait_for_new_frames(tab, "the stream plays");
    }

    click(&mut tabs[0], "pause");
    let paused = tabs.each_mut().map(|tab| wait_for_state(tab, "paused"));
    let still = |shown: &Shown| {
        (
            shown.text("stream-time").to_owned(),
            shown.text("events-in").to_owned(),
        )
    };
    assert_eq!(
        still(&paused[0]),
        still(&paused[1]),
        "the two tabs show one stream: stream time and events in"
    );
    std::thread::sleep(Duration::from_millis(1200));
    for tab in &mut tabs {
        let later = Shown::read(tab);
        assert_eq!(later.text("state"), "paused");
        assert_eq!(still(&later), still(&paused[0]), "a paused page moved");
    }

    click(&mut tabs[0], "pause");
    let paused_s = paused[0].num("stream-time").unwrap();
    for tab in &mut tabs {
        tab.wait_for("the stream time to move again after play", |tab| {
            (Shown::read(tab).num("stream-time")? > paused_s).then_some(())
        });
    }

    let [first, mut second] = tabs;
    browser.close_tab(first);
    let moving = wait_for_new_frames(&mut second, "after the other tab closed");
    println!(
        "two tabs: both paused at stream time {} s with {} events in, both moved on after play; \
         with one tab closed the other went on (frame {}, {} s)",
        still(&paused[0]).0,
        still(&paused[0]).1,
        moving.text("frame-seq"),
        moving.text("stream-time")
    );
}

#[test]
fn the_page_reports_its_event_to_screen_latency_at_real_time() {
    let Some(chromium) = browser::chromium() else {
        return;
    };
    let Some(pick) = pick_recording() else {
        return;
    };
    // Paused until the page watches, so that it sees the whole recording play.
    let view = View::start(&[
        pick.to_str().unwrap(),
        "--port",
        "0",
        "--speed",
        "1",
        "--paused",
    ]);
    let mut browser = Browser::launch(&chromium);
    let mut tab = browser.first_tab();
    tab.navigate(&view.url);
    wait_for_state(&mut tab, "paused");
    // Every #frame-seq the page shows, and every #latency-ms it sets (after the frame is painted).
    tab.eval(
        "window.shown = { 'frame-seq': [], 'latency-ms': [] };
         for (const id in window.shown) {
             const e = document.getElementById(id);
             new MutationObserver(() => window.shown[id].push(e.textContent.trim()))
                 .observe(e, { childList: true, characterData: true, subtree: true });
         }",
    );
    click(&mut tab, "pause");
    wait_for_state(&mut tab, "ended");
    let shown = tab.eval("window.shown");
    // Read after the frames: the maximum and the skipped count cover all of them.
    let end = Shown::read(&mut tab);
    let numbers = |id: &str| -> Vec<f64> {
        let texts = shown[id]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|t| t.as_str());
        texts.filter_map(|t| t.parse().ok()).collect()
    };
    let seqs = numbers("frame-seq");
    let mut latencies = numbers("latency-ms");
    assert!(
        !latencies.is_empty(),
        "no #latency-ms over {} frames",
        seqs.len()
    );
    latencies.sort_by(f64::total_cmp);
    let (median, max) = (
        latencies[latencies.len() / 2],
        latencies[latencies.len() - 1],
    );
    assert!(
        latencies[0] >= 0.0,
        "a negative event-to-screen latency: {} ms",
        latencies[0]
    );
    let page_max = end
        .num("latency-max-ms")
        .expect("#latency-max-ms is a number");
    assert!(
        page_max >= max,
        "#latency-max-ms {page_max} is below a frame's #latency-ms {max}"
    );
    let skipped = end.int("frames-skipped");
    let gaps: f64 = seqs.windows(2).map(|w| (w[1] - w[0] - 1.0).max(0.0)).sum();
    assert!(
        skipped as f64 >= gaps,
        "#frames-skipped {skipped}, yet the page's #frame-seq jumped over {gaps} frames"
    );
    println!(
        "event-to-screen latency at 1×: median {median:.1} ms, max {max:.1} ms over {} frames \
         with new events (#latency-max-ms {page_max}); {} frames shown, {skipped} skipped",
        latencies.len(),
        seqs.len()
    );
}
