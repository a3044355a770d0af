//! [`Player`]: moves a [`StreamSource`] through a [`StreamMonitor`] (and a
//! [`StreamObserver`], the recogniser) at the chosen speed, obeys the viewers' controls and
//! hands a frame to the [`Hub`] every [`FRAME_INTERVAL`].
//!
//! **Pacing.** At a paced speed `f` an event of stream time `t` is pushed when the wall clock
//! reaches `anchor_wall + (t − anchor_t)/f` (anchored again on play, seek and speed change),
//! and the open pooling window is closed as soon as its end has passed on that clock, so
//! spikes show without waiting for the next event. At `max` every event is pushed as soon as it
//! is read; frames still come every interval, each showing the stream as it is then (what
//! that leaves out is the frame's [`Decimation`](crate::Decimation)). A camera is pushed as it
//! arrives.
//!
//! **Latency.** Each frame carries the wall time at which the oldest event it shows for the
//! first time was due (paced: its time came; max or camera: it was read); the page subtracts
//! it from the time it painted the frame.

use crate::frame::{CodingDecisions, Frame, PlayState};
use crate::hub::{Control, Hub, Speed};
use crate::monitor::{MonitorConfig, StreamMonitor};
use crate::source::{SourceRead, StreamSource};
use neurotac_core::EventBuffer;
use neurotac_sensor::taxel::TaxelLayout;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

/// Wall time between frames (100 per second): an event waits at most this long for its
/// frame. At 1× in headless Chromium on a 2-core machine the oldest event of a frame reaches
/// the screen in ≈ 45 ms (median; README "Look at the sensor"), 20 ms-frames took ≈ 55 ms.
/// A tab that paints slower draws only the newest frame it has.
pub const FRAME_INTERVAL: Duration = Duration::from_millis(10);

/// How long the last picture of a simulated slide stays before the next slide starts.
const HOLD_BETWEEN_STREAMS: Duration = Duration::from_millis(1500);

/// What watches the stream besides the monitor: the online recogniser, one per coding.
pub trait StreamObserver {
    /// The next pixel events (as the monitor got them).
    fn push(&mut self, events: &EventBuffer);
    /// The stream ended: final decisions.
    fn finish(&mut self);
    /// A new stream starts (a rewind, the next slide): forget this one.
    fn restart(&mut self);
    /// Class names of the decisions.
    fn class_names(&self) -> Vec<String>;
    /// Each coding's decisions so far.
    fn decisions(&self) -> Vec<CodingDecisions>;
}

/// No recogniser.
pub struct NoObserver;

impl StreamObserver for NoObserver {
    fn push(&mut self, _: &EventBuffer) {}
    fn finish(&mut self) {}
    fn restart(&mut self) {}
    fn class_names(&self) -> Vec<String> {
        Vec::new()
    }
    fn decisions(&self) -> Vec<CodingDecisions> {
        Vec::new()
    }
}

/// How a player starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlayerOptions {
    /// Replay speed of a recording (ignored for a camera).
    pub speed: Speed,
    /// Start paused (at the first frame).
    pub paused: bool,
    /// What the monitor keeps.
    pub monitor: MonitorConfig,
}

/// How a player ended.
#[derive(Debug, Clone, PartialEq)]
pub struct PlayerEnd {
    /// Pixel events shown, over every stream (and again for a replayed stretch).
    pub events: u64,
    /// The source's failure, if it failed (already shown on the page).
    pub failure: Option<String>,
}

/// Plays a source to the hub (module docs).
pub struct Player<'s> {
    source: &'s mut dyn StreamSource,
    observer: &'s mut dyn StreamObserver,
    hub: &'s Hub,
    layout: TaxelLayout,
    options: PlayerOptions,
    monitor: StreamMonitor,
    state: PlayState,
    speed: Speed,
    label: String,
    notice: Option<String>,
    /// Read but not yet pushed: `pending[cursor..]`.
    pending: EventBuffer,
    cursor: usize,
    scratch: EventBuffer,
    /// Paced: (wall instant, stream µs) that are due together.
    anchor: Option<(Instant, i64)>,
    seq: u64,
    oldest_due: Option<f64>,
    last_frame_wall: Instant,
    /// Events pushed, over every stream and replay.
    pushed: u64,
    clock: WallClock,
}

impl<'s> Player<'s> {
    /// A player of `source` on `layout`, the decisions of `observer`, frames to `hub`.
    pub fn new(
        source: &'s mut dyn StreamSource,
        observer: &'s mut dyn StreamObserver,
        hub: &'s Hub,
        layout: &TaxelLayout,
        options: PlayerOptions,
    ) -> Result<Self, crate::ViewError> {
        let speed = options.speed;
        Ok(Self {
            label: source.label(),
            source,
            observer,
            hub,
            layout: layout.clone(),
            monitor: StreamMonitor::new(layout, options.monitor)?,
            options,
            state: match options.paused {
                true => PlayState::Paused,
                false => PlayState::Playing,
            },
            speed,
            notice: None,
            pending: EventBuffer::new(),
            cursor: 0,
            scratch: EventBuffer::new(),
            anchor: None,
            seq: 0,
            oldest_due: None,
            last_frame_wall: Instant::now(),
            pushed: 0,
            clock: WallClock::new(),
        })
    }

    /// Plays until the hub is stopped (Ctrl-C).
    pub fn run(mut self) -> PlayerEnd {
        let mut next_frame = Instant::now();
        while !self.hub.is_stopped() {
            for control in self.hub.take_controls() {
                self.obey(control);
            }
            let worked = match self.state {
                PlayState::Playing => self.play_some(next_frame),
                _ => false,
            };
            let now = Instant::now();
            if now >= next_frame {
                if self.state == PlayState::Playing || self.seq == 0 {
                    self.publish();
                }
                next_frame = now + FRAME_INTERVAL;
            } else if !worked {
                std::thread::sleep((next_frame - now).min(Duration::from_millis(5)));
            }
        }
        PlayerEnd {
            events: self.pushed,
            failure: self.notice.filter(|_| self.state == PlayState::Failed),
        }
    }

    fn is_live(&self) -> bool {
        self.source.is_live()
    }

    /// Pushes what is due before `until`; `false` when it only waited.
    fn play_some(&mut self, until: Instant) -> bool {
        if self.cursor == self.pending.len() && !self.refill() {
            return true;
        }
        let first = self.pending.t[self.cursor];
        let now = Instant::now();
        let (end, due) = match (self.is_live(), self.speed) {
            (false, Speed::Paced(f)) => {
                let (wall, stream) = *self.anchor.get_or_insert((now, first));
                // Saturating: a stream with far-apart times (or a slow speed) cannot overflow.
                let stream_now =
                    stream.saturating_add(((now - wall).as_secs_f64() * f * 1e6) as i64);
                let rest = &self.pending.t[self.cursor..];
                let end = self.cursor + rest.partition_point(|&t| t <= stream_now);
                if end == self.cursor {
                    // Quiet: let the clock close a pooling window, then wait for the next event.
                    self.monitor
                        .advance_to(stream_now.min(first.saturating_sub(1)));
                    let wait = wall_time(first.saturating_sub(stream_now), f);
                    std::thread::sleep(
                        wait.min(until.saturating_duration_since(now))
                            .min(Duration::from_millis(5)),
                    );
                    return false;
                }
                let after = wall_time(first.saturating_sub(stream).max(0), f);
                (end, wall.checked_add(after).unwrap_or(now))
            }
            _ => (self.pending.len(), now),
        };
        self.push_range(end, self.clock.unix_ms(due));
        true
    }

    /// Reads the next chunk into `pending`; `false` when there is none now (end, failure, a
    /// live source with nothing yet).
    fn refill(&mut self) -> bool {
        self.pending.clear();
        self.cursor = 0;
        match self.source.read(&mut self.pending) {
            Ok(SourceRead::Events) => !self.pending.is_empty(),
            Ok(SourceRead::End) => {
                self.end_of_stream();
                false
            }
            Err(e) => {
                self.fail_with(&*e);
                false
            }
        }
    }

    /// Pushes `pending[cursor..end]`, the oldest of them due at `due_unix_ms`.
    fn push_range(&mut self, end: usize, due_unix_ms: f64) {
        let events = if self.cursor == 0 && end == self.pending.len() {
            &self.pending
        } else {
            self.scratch.clear();
            for i in self.cursor..end {
                self.scratch.push(self.pending.get(i).expect("in range"));
            }
            &self.scratch
        };
        self.cursor = end;
        self.pushed += events.len() as u64;
        self.oldest_due.get_or_insert(due_unix_ms);
        let result = self.monitor.push(events);
        self.observer.push(events);
        if let Err(e) = result {
            self.fail_with(&e);
        }
    }

    fn end_of_stream(&mut self) {
        self.monitor.finish();
        self.observer.finish();
        self.publish_as(PlayState::Ended);
        match self.source.next_stream() {
            Ok(true) => {
                std::thread::sleep(HOLD_BETWEEN_STREAMS);
                self.label = self.source.label();
                self.restart();
            }
            Ok(false) => self.state = PlayState::Ended,
            Err(e) => self.fail_with(&*e),
        }
    }

    /// Fails with the source's error `e` and its causes (the OS reason of a file that went).
    fn fail_with(&mut self, e: &(dyn std::error::Error + 'static)) {
        let why = format!("{}: {}", self.label, neurotac_core::error_chain(e));
        self.fail(why);
    }

    fn fail(&mut self, why: String) {
        eprintln!("{why}");
        self.notice = Some(why);
        self.state = PlayState::Failed;
        self.publish();
    }

    /// A fresh monitor and observer for a new stream (or the same one from its start).
    fn restart(&mut self) {
        self.monitor = StreamMonitor::new(&self.layout, self.options.monitor)
            .expect("the configuration was validated when the player was made");
        self.observer.restart();
        self.pending.clear();
        self.cursor = 0;
        self.anchor = None;
    }

    fn obey(&mut self, control: Control) {
        match control {
            // A camera does not wait: it is watched live, never paused.
            Control::Pause if self.state == PlayState::Playing && !self.is_live() => {
                self.state = PlayState::Paused;
                self.publish();
            }
            Control::Play if self.state == PlayState::Paused => {
                self.state = PlayState::Playing;
                self.anchor = None;
                // The speed against real time counts from here, not from the pause.
                self.last_frame_wall = Instant::now();
            }
            // At the end of a recording: from its start again.
            Control::Play if self.state == PlayState::Ended && !self.is_live() => {
                self.obey(Control::Seek(0.0));
                self.obey(Control::Play);
            }
            Control::Step if self.state != PlayState::Failed && !self.is_live() => {
                let window = self.options.monitor.transduction.pool_window_us;
                let target =
                    (self.monitor.elapsed_us()).map_or(window, |t| t.saturating_add(window));
                self.state = PlayState::Paused;
                self.fast_forward(target);
                self.publish();
            }
            Control::Seek(t_s) if !self.is_live() => {
                let target = (t_s * 1e6).round() as i64;
                if self.monitor.elapsed_us().is_some_and(|now| target < now)
                    || self.state == PlayState::Ended
                {
                    if let Err(e) = self.source.rewind() {
                        return self.fail_with(&*e);
                    }
                    self.restart();
                }
                if self.state == PlayState::Ended {
                    self.state = PlayState::Paused;
                }
                self.fast_forward(target);
                self.anchor = None;
                self.publish();
            }
            Control::Speed(speed) => {
                self.speed = speed;
                self.anchor = None;
            }
            _ => {}
        }
    }

    /// Pushes, unpaced, every event up to stream time `target_us` (from the stream origin).
    fn fast_forward(&mut self, target_us: i64) {
        loop {
            if self.cursor == self.pending.len() && !self.refill() {
                return;
            }
            let origin = self.monitor_origin();
            let rest = &self.pending.t[self.cursor..];
            let end =
                self.cursor + rest.partition_point(|&t| t.saturating_sub(origin) <= target_us);
            let now = self.clock.unix_ms(Instant::now());
            if end > self.cursor {
                self.push_range(end, now);
            }
            if end < self.pending.len() || self.state == PlayState::Failed {
                let origin = self.monitor_origin();
                self.monitor.advance_to(origin.saturating_add(target_us));
                return;
            }
        }
    }

    /// The stream origin (its first event), the next pending event's time before any.
    fn monitor_origin(&self) -> i64 {
        match self.monitor.elapsed_us() {
            Some(_) => self
                .monitor
                .origin_us()
                .expect("known once an event arrived"),
            None => self.pending.t.get(self.cursor).copied().unwrap_or(0),
        }
    }

    fn publish(&mut self) {
        let state = self.state;
        self.publish_as(state);
    }

    fn publish_as(&mut self, state: PlayState) {
        self.seq += 1;
        let speed = match self.is_live() {
            true => "live".to_owned(),
            false => self.speed.label(),
        };
        let mut frame: Frame = self
            .monitor
            .frame(self.seq, &self.label, state, Some(&speed));
        let wall = self.last_frame_wall.elapsed().as_secs_f64() * 1e3;
        self.last_frame_wall = Instant::now();
        // Measured only over a stretch of playing (0: not measured).
        frame.decimation.speed_vs_realtime = match wall > 0.0 && self.state == PlayState::Playing {
            true => frame.decimation.stream_ms_since_last_frame / wall,
            false => 0.0,
        };
        frame.class_names = self.observer.class_names();
        frame.decisions = self.observer.decisions();
        frame.notice = self.notice.clone();
        frame.oldest_new_event_due_unix_ms = self.oldest_due.take();
        self.hub.publish(frame);
    }
}

/// The wall time `stream_us` of stream time takes at speed `factor` (> 0), as long as the
/// largest [`Duration`] at most (a slow speed and far-apart events cannot overflow it).
fn wall_time(stream_us: i64, factor: f64) -> Duration {
    Duration::try_from_secs_f64(stream_us as f64 / factor * 1e-6).unwrap_or(Duration::MAX)
}

/// Wall-clock milliseconds since the Unix epoch for [`Instant`]s (which the page's clock is
/// compared with).
struct WallClock {
    instant: Instant,
    unix_ms: f64,
}

impl WallClock {
    fn new() -> Self {
        let unix = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .unwrap_or_default();
        Self {
            instant: Instant::now(),
            unix_ms: unix.as_secs_f64() * 1e3,
        }
    }

    fn unix_ms(&self, at: Instant) -> f64 {
        match at.checked_duration_since(self.instant) {
            Some(d) => self.unix_ms + d.as_secs_f64() * 1e3,
            None => self.unix_ms - (self.instant - at).as_secs_f64() * 1e3,
        }
    }
}
