//! [`Hub`]: where the player hands its frames to the page and the page hands its controls to
//! the player. Frames are drawn on the hub's own thread (the player never waits for a
//! drawing); every viewer (browser tab) gets the newest drawn frame when it is ready for one,
//! so a slow tab skips frames without holding up the stream or the other tabs.

use crate::draw::draw_frame;
use crate::frame::Frame;
use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::time::Duration;

/// A viewer's command to the player (`POST /control`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Control {
    /// Stop the stream where it is.
    Pause,
    /// Go on.
    Play,
    /// Paused: move on by one pooling window.
    Step,
    /// Go to this stream time (s).
    Seek(f64),
    /// Replay at this speed.
    Speed(Speed),
}

/// How fast a recording is replayed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Speed {
    /// `factor` × real time (1 = as recorded).
    Paced(f64),
    /// As fast as the transduction goes.
    Max,
}

impl Speed {
    /// The slowest paced speed: a millionth of real time.
    pub const MIN_FACTOR: f64 = 1e-6;
    /// The fastest paced speed: a million times real time (faster is `max`).
    pub const MAX_FACTOR: f64 = 1e6;

    /// Parses `realtime`, `max`, `2`, `2x`, `0.5×`: a factor from [`MIN_FACTOR`](Self::MIN_FACTOR)
    /// to [`MAX_FACTOR`](Self::MAX_FACTOR).
    pub fn parse(text: &str) -> Option<Speed> {
        let t = text.trim();
        match t {
            "realtime" | "real-time" => return Some(Speed::Paced(1.0)),
            "max" => return Some(Speed::Max),
            _ => {}
        }
        let number = t.trim_end_matches(['x', '×']);
        let factor: f64 = number.parse().ok()?;
        (Self::MIN_FACTOR..=Self::MAX_FACTOR)
            .contains(&factor)
            .then_some(Speed::Paced(factor))
    }

    /// As the page shows it: `realtime`, `2×`, `max`.
    pub fn label(self) -> String {
        match self {
            Speed::Paced(1.0) => "realtime".into(),
            Speed::Paced(f) => format!("{f}×"),
            Speed::Max => "max".into(),
        }
    }
}

impl Control {
    /// The controls, as an error message lists them.
    pub fn syntax() -> String {
        format!(
            "pause, play, step, seek SECONDS (0 to {:e}), speed realtime|max|N (N from {:e} to {:e})",
            Self::MAX_SEEK_S,
            Speed::MIN_FACTOR,
            Speed::MAX_FACTOR
        )
    }

    /// The latest seek target (s): its time in µs still fits an `i64` (292 000 years).
    pub const MAX_SEEK_S: f64 = 9.2e12;

    /// Parses a `POST /control` body: `pause`, `play`, `step`, `seek <s>` (0 to
    /// [`MAX_SEEK_S`](Self::MAX_SEEK_S)), `speed <speed>` ([`Speed::parse`]).
    pub fn parse(body: &str) -> Option<Control> {
        let mut words = body.split_whitespace();
        let control = match (words.next()?, words.next()) {
            ("pause", None) => Control::Pause,
            ("play", None) => Control::Play,
            ("step", None) => Control::Step,
            ("seek", Some(t)) => {
                let t: f64 = t.parse().ok()?;
                (0.0..=Self::MAX_SEEK_S)
                    .contains(&t)
                    .then_some(Control::Seek(t))?
            }
            ("speed", Some(s)) => Control::Speed(Speed::parse(s)?),
            _ => return None,
        };
        words.next().is_none().then_some(control)
    }
}

/// A drawn frame as viewers receive it.
#[derive(Debug, Clone, Default)]
pub struct Drawn {
    /// The frame's number (0: none yet).
    pub seq: u64,
    /// The message a viewer receives (JSON, the SVG inside).
    pub message: Arc<str>,
    /// The frame's SVG.
    pub svg: Arc<str>,
}

#[derive(Default)]
struct Slots {
    /// The newest frame not yet drawn.
    pending: Option<Frame>,
    /// The newest drawn frame.
    drawn: Drawn,
    closed: bool,
}

/// The meeting point of player, drawing thread and viewers (module docs).
pub struct Hub {
    slots: Mutex<Slots>,
    /// Signalled when a frame is pending (drawing thread) or drawn (viewers), and on close.
    changed: Condvar,
    controls: Mutex<VecDeque<Control>>,
    stop: AtomicBool,
}

impl Hub {
    /// A hub with its drawing thread running.
    pub fn start() -> Arc<Hub> {
        let hub = Arc::new(Hub {
            slots: Mutex::default(),
            changed: Condvar::new(),
            controls: Mutex::default(),
            stop: AtomicBool::new(false),
        });
        let drawer = Arc::clone(&hub);
        std::thread::Builder::new()
            .name("view-draw".into())
            .spawn(move || drawer.draw_loop())
            .expect("spawning the drawing thread");
        hub
    }

    fn slots(&self) -> MutexGuard<'_, Slots> {
        self.slots.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Hands a frame over to be drawn (replacing one not drawn yet).
    pub fn publish(&self, frame: Frame) {
        self.slots().pending = Some(frame);
        self.changed.notify_all();
    }

    fn draw_loop(&self) {
        let mut slots = self.slots();
        loop {
            if slots.closed {
                return;
            }
            let Some(frame) = slots.pending.take() else {
                slots = self
                    .changed
                    .wait(slots)
                    .unwrap_or_else(PoisonError::into_inner);
                continue;
            };
            drop(slots);
            let drawn = draw(&frame);
            slots = self.slots();
            slots.drawn = drawn;
            self.changed.notify_all();
        }
    }

    /// The newest drawn frame.
    pub fn latest(&self) -> Drawn {
        self.slots().drawn.clone()
    }

    /// Waits up to `timeout` for a drawn frame newer than `seq`; `None` on time-out or close.
    pub fn next_after(&self, seq: u64, timeout: Duration) -> Option<Drawn> {
        let slots = self.slots();
        let (slots, _) = self
            .changed
            .wait_timeout_while(slots, timeout, |s| s.drawn.seq <= seq && !s.closed)
            .unwrap_or_else(PoisonError::into_inner);
        (slots.drawn.seq > seq && !slots.closed).then(|| slots.drawn.clone())
    }

    /// Queues a viewer's control for the player.
    pub fn control(&self, control: Control) {
        self.controls
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push_back(control);
    }

    /// The controls queued since the last call, oldest first.
    pub fn take_controls(&self) -> Vec<Control> {
        let mut c = self.controls.lock().unwrap_or_else(PoisonError::into_inner);
        c.drain(..).collect()
    }

    /// Asks everything to stop (Ctrl-C): the player returns, viewers' streams end.
    pub fn stop(&self) {
        self.stop.store(true, Ordering::SeqCst);
        self.slots().closed = true;
        self.changed.notify_all();
    }

    /// Whether [`stop`](Self::stop) was called.
    pub fn is_stopped(&self) -> bool {
        self.stop.load(Ordering::SeqCst)
    }
}

/// Draws `frame` and wraps it in the viewers' message (design in `page/page.js`).
fn draw(frame: &Frame) -> Drawn {
    let svg: Arc<str> = draw_frame(frame).into();
    let message = serde_json::json!({
        "seq": frame.seq,
        "t_s": frame.t_s,
        "state": frame.state,
        "speed": frame.speed,
        "source": frame.source,
        "counts": frame.counts,
        "raster_spikes": frame.raster.spikes.len(),
        "decimation": frame.decimation,
        "notice": frame.notice,
        "due_unix_ms": frame.oldest_new_event_due_unix_ms,
        "svg": &*svg,
    });
    Drawn {
        seq: frame.seq,
        message: message.to_string().into(),
        svg,
    }
}
