//! What every event-file format implements and reports (davis240.md §2): the streaming
//! [`EventReader`] and [`EventWriter`], the reader's counters ([`ReadStats`], [`Backwards`]) and
//! the end-of-input rule all readers share (events decoded before an error first, then the
//! error, then nothing), plus the block size readers pull and the size assumed when a file
//! states none.

use crate::error::FormatError;
use crate::geometry::{DAVIS240_HEIGHT, DAVIS240_WIDTH};
use neurotac_core::EventBuffer;
use std::path::Path;

/// Pixel-array size assumed when a file does not state one: the DAVIS240's 240 × 180.
pub const DAVIS240_SIZE: (u16, u16) = (DAVIS240_WIDTH, DAVIS240_HEIGHT);

/// Byte size of the blocks readers pull from their input.
pub(crate) const READ_BLOCK: usize = 1 << 18;

/// A timestamp that went backwards, as first seen by a reader.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Backwards {
    /// Byte offset of the record (for text: of the line).
    pub offset: u64,
    /// Time of the event before (µs).
    pub previous_us: i64,
    /// Time of this event (µs).
    pub t_us: i64,
}

/// What a reader produced and what it skipped.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ReadStats {
    /// Polarity events delivered.
    pub events: u64,
    /// Events dropped because x or y lies outside the sensor (documented skip).
    pub out_of_range: u64,
    /// Records of other kinds skipped: APS/IMU/special records (AEDAT 2.0/3.1), invalid events
    /// (AEDAT 3.1 valid bit 0), packets of non-event streams and empty packets (AEDAT 4.0).
    pub skipped: u64,
    /// Events earlier than the event before them (kept in file order).
    pub timestamps_backwards: u64,
    /// The first such event.
    pub first_backwards: Option<Backwards>,
    /// 32-bit timestamp wraps unwrapped (AEDAT 2.0).
    pub timestamp_wraps: u64,
}

impl ReadStats {
    /// The one-line warning every command prints (on stderr) when a reader of `input` kept events
    /// going back in time (in file order) or skipped events outside the sensor; `None` when it
    /// did neither. The wording lives here alone so that `convert`, `filter` and `transduce`
    /// say the same thing.
    pub fn warning(&self, input: &Path) -> Option<String> {
        let mut parts = Vec::new();
        if self.out_of_range > 0 {
            parts.push(format!(
                "skipped {} events outside the sensor",
                self.out_of_range
            ));
        }
        if let Some(b) = self.first_backwards {
            parts.push(format!(
                "{} events go back in time (kept in file order; the first at byte {}: {} µs after {} µs)",
                self.timestamps_backwards, b.offset, b.t_us, b.previous_us
            ));
        }
        (!parts.is_empty()).then(|| format!("warning: {}: {}", input.display(), parts.join("; ")))
    }

    /// Records one event at `offset` with time `t` after an event at `previous`.
    #[inline]
    pub(crate) fn check_order(&mut self, offset: u64, previous: i64, t: i64) {
        if t < previous {
            self.timestamps_backwards += 1;
            if self.first_backwards.is_none() {
                self.first_backwards = Some(Backwards {
                    offset,
                    previous_us: previous,
                    t_us: t,
                });
            }
        }
    }
}

/// How every reader ends: events decoded before an error are delivered first, the error comes
/// from the next call, and after the end or an error every call returns 0.
#[derive(Debug, Default)]
pub(crate) struct ReaderEnd {
    pending: Option<FormatError>,
    done: bool,
}

impl ReaderEnd {
    /// Runs `fill`, which appends at least one event to `out` or reaches the end of the input.
    pub(crate) fn chunk<S>(
        state: &mut S,
        end: impl Fn(&mut S) -> &mut ReaderEnd,
        out: &mut EventBuffer,
        fill: impl FnOnce(&mut S, &mut EventBuffer) -> Result<(), FormatError>,
    ) -> Result<usize, FormatError> {
        let e = end(state);
        if let Some(error) = e.pending.take() {
            return Err(error);
        }
        if e.done {
            return Ok(0);
        }
        let before = out.len();
        let result = fill(state, out);
        let appended = out.len() - before;
        let e = end(state);
        match result {
            Ok(()) => {
                e.done = appended == 0;
                Ok(appended)
            }
            Err(error) => {
                e.done = true;
                if appended == 0 {
                    return Err(error);
                }
                e.pending = Some(error);
                Ok(appended)
            }
        }
    }
}

/// Maps an I/O error creating or writing the output at `path` into a [`FormatError::Io`].
pub(crate) fn write_error(path: &Path) -> impl Fn(std::io::Error) -> FormatError + '_ {
    io_error(path, neurotac_core::IoAction::Write)
}

/// Maps an I/O error opening or reading the input at `path` into a [`FormatError::Io`].
pub(crate) fn read_error(path: &Path) -> impl Fn(std::io::Error) -> FormatError + '_ {
    io_error(path, neurotac_core::IoAction::Read)
}

fn io_error(
    path: &Path,
    action: neurotac_core::IoAction,
) -> impl Fn(std::io::Error) -> FormatError + '_ {
    move |source| FormatError::Io {
        path: path.to_path_buf(),
        action,
        source,
    }
}

/// A streaming event-file reader (one per format of davis240.md §2).
pub trait EventReader {
    /// Appends the next chunk of events (at most a few hundred thousand) to `out` and returns how
    /// many were appended; `0` means the end of the input. Events decoded before an error are
    /// delivered first; the error comes from the following call.
    fn read_chunk(&mut self, out: &mut EventBuffer) -> Result<usize, FormatError>;

    /// What was read and skipped so far.
    fn stats(&self) -> ReadStats;

    /// The pixel-array size `(width, height)` the file states (module `camera`): the event
    /// stream's `sizeX`/`sizeY` (AEDAT 4.0), the camera of the `# AEChip:` line (AEDAT 2.0) or
    /// of the `#Source` line (AEDAT 3.1), the `# sensor WIDTHxHEIGHT` first line (ECD text,
    /// CSV); `None` when the file states none. Events outside the stated size, or outside the
    /// size assumed when none is stated (240 × 180 unless opened with
    /// [`open_reader_assuming`](super::open_reader_assuming)), are skipped and counted.
    fn sensor_size(&self) -> Option<(u16, u16)>;

    /// Reads every remaining event into `out`.
    fn read_to_end(&mut self, out: &mut EventBuffer) -> Result<u64, FormatError> {
        let mut n = 0u64;
        loop {
            let k = self.read_chunk(out)?;
            if k == 0 {
                return Ok(n);
            }
            n += k as u64;
        }
    }
}

impl<R: EventReader + ?Sized> EventReader for Box<R> {
    fn read_chunk(&mut self, out: &mut EventBuffer) -> Result<usize, FormatError> {
        (**self).read_chunk(out)
    }

    fn stats(&self) -> ReadStats {
        (**self).stats()
    }

    fn sensor_size(&self) -> Option<(u16, u16)> {
        (**self).sensor_size()
    }
}

/// The sensor size a reader bounds its events by: the one its file states, else the one
/// assumed by the caller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ReaderSensor {
    /// What the file states.
    pub stated: Option<(u16, u16)>,
    /// What the caller assumes when the file states nothing (default 240 × 180).
    pub assumed: (u16, u16),
}

impl ReaderSensor {
    /// A file that states `stated` (or nothing), with the default assumption.
    pub(crate) fn new(stated: Option<(u16, u16)>) -> Self {
        Self {
            stated,
            assumed: DAVIS240_SIZE,
        }
    }

    /// The size events must lie inside.
    #[inline]
    pub(crate) fn bounds(&self) -> (u16, u16) {
        self.stated.unwrap_or(self.assumed)
    }
}

/// The typed refusal of a sensor size `format` cannot state, for the output `path`.
pub(crate) fn unsupported_size(
    path: &Path,
    format: &'static str,
    size: (u16, u16),
    supported: &'static str,
) -> FormatError {
    FormatError::UnsupportedSensorSize {
        path: path.to_path_buf(),
        format,
        width: size.0,
        height: size.1,
        supported,
    }
}

/// Refuses event `index` at `(x, y)` when it lies outside the `size` a writer states: writers
/// never write an event their own file says cannot exist.
#[inline]
pub(crate) fn check_inside(
    path: &Path,
    index: u64,
    (x, y): (u16, u16),
    size: (u16, u16),
) -> Result<(), FormatError> {
    if x < size.0 && y < size.1 {
        return Ok(());
    }
    Err(FormatError::Unrepresentable {
        path: path.to_path_buf(),
        index,
        reason: format!(
            "pixel ({x}, {y}) is outside the {} × {} sensor the file states",
            size.0, size.1
        ),
    })
}

/// A streaming event-file writer (one per format of davis240.md §2). Every writer states the
/// sensor size it is created with in its format's own way (module `camera`) and refuses events
/// outside it ([`FormatError::Unrepresentable`]).
pub trait EventWriter {
    /// Writes the events of `events` (after those written before).
    fn write(&mut self, events: &EventBuffer) -> Result<(), FormatError>;

    /// Writes what is buffered and completes the file (trailing tables, header fields). Call it
    /// once, after the last [`EventWriter::write`].
    fn finish(&mut self) -> Result<(), FormatError>;
}
