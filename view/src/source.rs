//! Where a view's events come from: the [`StreamSource`] contract, a recorded file
//! ([`FileSource`]) and a DAVIS camera ([`CameraSource`]). The simulator's slides are a source
//! of the `neurotac` command (they need the experiments' seeds).

use neurotac_core::EventBuffer;
use neurotac_sensor::davis::{DavisStream, Transport};
use neurotac_sensor::format::{EventReader, open_reader};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// A source's error, shown on the page and printed as one line.
pub type SourceError = Box<dyn std::error::Error + Send + Sync>;

/// What [`StreamSource::read`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SourceRead {
    /// Events were appended (possibly none yet, for a live source).
    Events,
    /// The stream (a recording, a simulated slide) is over.
    End,
}

/// A stream of time-ordered pixel events, read chunk by chunk.
pub trait StreamSource {
    /// What the page calls it (a file name, a camera, a texture and slide).
    fn label(&self) -> String;

    /// Appends the next events to `chunk`. A live source waits at most a few tens of ms.
    fn read(&mut self, chunk: &mut EventBuffer) -> Result<SourceRead, SourceError>;

    /// `true` for a camera: the stream cannot wait, rewind or go faster than it happens.
    fn is_live(&self) -> bool;

    /// Starts the current stream again from its first event (a seek backwards).
    fn rewind(&mut self) -> Result<(), SourceError>;

    /// After [`SourceRead::End`]: moves to the next stream (the simulator's next slide);
    /// `false` when there is none.
    fn next_stream(&mut self) -> Result<bool, SourceError> {
        Ok(false)
    }
}

/// A recorded event file in any format `neurotac` reads, opened again to rewind.
pub struct FileSource {
    path: PathBuf,
    reader: Box<dyn EventReader>,
}

impl FileSource {
    /// Opens `path` (format detected from its first bytes).
    pub fn open(path: &Path) -> Result<Self, SourceError> {
        Ok(Self {
            reader: open_reader(path)?,
            path: path.to_owned(),
        })
    }

    /// The pixel-array size the file states, if any.
    pub fn sensor_size(&self) -> Option<(u16, u16)> {
        self.reader.sensor_size()
    }
}

impl StreamSource for FileSource {
    fn label(&self) -> String {
        self.path.display().to_string()
    }

    fn read(&mut self, chunk: &mut EventBuffer) -> Result<SourceRead, SourceError> {
        match self.reader.read_chunk(chunk)? {
            0 => Ok(SourceRead::End),
            _ => Ok(SourceRead::Events),
        }
    }

    fn is_live(&self) -> bool {
        false
    }

    fn rewind(&mut self) -> Result<(), SourceError> {
        self.reader = open_reader(&self.path)?;
        Ok(())
    }
}

/// A DAVIS camera streaming over any [`Transport`] (USB: `RusbTransport`).
pub struct CameraSource<T: Transport> {
    label: String,
    stream: DavisStream<T>,
}

impl<T: Transport> CameraSource<T> {
    /// Views `stream`, called `label` on the page.
    pub fn new(label: String, stream: DavisStream<T>) -> Self {
        Self { label, stream }
    }
}

impl<T: Transport> StreamSource for CameraSource<T> {
    fn label(&self) -> String {
        self.label.clone()
    }

    fn read(&mut self, chunk: &mut EventBuffer) -> Result<SourceRead, SourceError> {
        self.stream.next_events(chunk, Duration::from_millis(10))?;
        Ok(SourceRead::Events)
    }

    fn is_live(&self) -> bool {
        true
    }

    fn rewind(&mut self) -> Result<(), SourceError> {
        Err("a live camera cannot seek".into())
    }
}
