//! Recording a camera stream to an event file: the loop behind `neurotac record`, over any
//! [`Transport`] so that it is tested with recorded byte streams.

use super::decode::DecodeStats;
use super::stream::DavisStream;
use super::transport::Transport;
use crate::error::{DeviceError, FormatError};
use crate::format::EventWriter;
use neurotac_core::EventBuffer;
use std::time::{Duration, Instant};

/// What a recording wrote and how it ended.
#[derive(Debug)]
pub struct Recording {
    /// Events written.
    pub events: u64,
    /// Wall-clock duration of the recording.
    pub elapsed: Duration,
    /// USB transfers dropped because the ring was full.
    pub dropped_packets: u64,
    /// The decoder's counters.
    pub decode: DecodeStats,
    /// `Some` when the camera stopped streaming early (unplugged, USB failure); every event
    /// received before was written.
    pub ended_early: Option<DeviceError>,
}

/// Writes the events of `stream` to `writer` for `duration` of wall-clock time, adding
/// `offset_us` to every timestamp (0, or the host's Unix time at start for DV-style absolute
/// times), then stops the camera and completes the file.
///
/// A disconnection ends the recording early: the events received before it are written, the
/// file is completed and [`Recording::ended_early`] holds the error. Only a failure to write the
/// file is an `Err`.
pub fn record<T: Transport>(
    stream: &mut DavisStream<T>,
    writer: &mut dyn EventWriter,
    duration: Duration,
    offset_us: i64,
) -> Result<Recording, FormatError> {
    let start = Instant::now();
    let mut chunk = EventBuffer::new();
    let mut events = 0u64;
    let mut ended_early = None;
    while start.elapsed() < duration {
        chunk.clear();
        let wait = duration
            .saturating_sub(start.elapsed())
            .min(Duration::from_millis(50));
        match stream.next_events(&mut chunk, wait) {
            Ok(0) => continue,
            Ok(_) => {}
            Err(e) => {
                ended_early = Some(e);
                break;
            }
        }
        if offset_us != 0 {
            chunk.t.iter_mut().for_each(|t| *t += offset_us);
        }
        writer.write(&chunk)?;
        events += chunk.len() as u64;
    }
    if let Err(e) = stream.stop() {
        ended_early.get_or_insert(e);
    }
    writer.finish()?;
    Ok(Recording {
        events,
        elapsed: start.elapsed(),
        dropped_packets: stream.dropped_packets(),
        decode: stream.decode_stats(),
        ended_early,
    })
}

#[cfg(test)]
mod tests {
    use super::super::protocol::{FIRMWARE_FX2, PRODUCT_ID_FX2};
    use super::super::transport::{DeviceInfo, ReplayEnd, ReplayTransport};
    use super::super::{Davis, StartOptions, UsbDecoder};
    use super::*;
    use crate::format::{
        Aedat4Reader, Aedat4Writer, Compression, CsvWriter, DAVIS240_SIZE, EventReader,
    };
    use std::io::Cursor;

    fn stream(end: ReplayEnd) -> (Vec<u8>, DavisStream<ReplayTransport>) {
        let mut words = vec![0x0001u16];
        for i in 0..30_000u16 {
            words.extend([
                0x8000 | (i & 0x7FFF),
                0x1000 | (i % 180),
                0x3000 | (i % 240),
            ]);
        }
        let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        let usb = DeviceInfo {
            product_id: PRODUCT_ID_FX2,
            firmware: FIRMWARE_FX2,
            bus: 1,
            address: 1,
            serial: None,
        };
        let davis = Davis::open(ReplayTransport::new(bytes.clone(), 4096, end), usb).unwrap();
        (bytes, davis.start(StartOptions::default()).unwrap())
    }

    fn read_back(file: &[u8]) -> EventBuffer {
        let mut out = EventBuffer::new();
        Aedat4Reader::new(file)
            .unwrap()
            .read_to_end(&mut out)
            .unwrap();
        out
    }

    #[test]
    fn an_unplugged_camera_leaves_a_complete_file_with_every_event() {
        let (bytes, mut s) = stream(ReplayEnd::Unplug);
        let mut file = Cursor::new(Vec::new());
        let mut writer = Aedat4Writer::new(&mut file, Compression::Lz4, DAVIS240_SIZE).unwrap();
        let rec = record(&mut s, &mut writer, Duration::from_secs(30), 0).unwrap();
        drop(writer);
        assert!(
            matches!(rec.ended_early, Some(DeviceError::Disconnected { .. })),
            "{rec:?}"
        );
        assert!(rec.elapsed < Duration::from_secs(30));
        let mut want = EventBuffer::new();
        UsbDecoder::davis240().decode(&bytes, &mut want);
        assert_eq!(rec.events, 30_000);
        assert_eq!(read_back(file.get_ref()), want);
    }

    /// What `neurotac record out.csv` writes: valid CSV of the `t,x,y,on` layout, every event.
    #[test]
    fn a_recording_written_as_csv_reads_back_strictly_with_every_event() {
        let (bytes, mut s) = stream(ReplayEnd::Unplug);
        let mut file = Vec::new();
        let mut writer = CsvWriter::new(&mut file, DAVIS240_SIZE).unwrap();
        record(&mut s, &mut writer, Duration::from_secs(30), 0).unwrap();
        drop(writer);
        let text = std::str::from_utf8(&file).unwrap();
        let (header, rows) = neurotac_core::io::csv::read_table(text).unwrap();
        assert_eq!(header, ["t", "x", "y", "on"]);
        let mut want = EventBuffer::new();
        UsbDecoder::davis240().decode(&bytes, &mut want);
        let want: Vec<[String; 4]> = (want.iter())
            .map(|e| {
                [e.t.0, i64::from(e.x), i64::from(e.y), i64::from(e.polarity)]
                    .map(|v| v.to_string())
            })
            .collect();
        assert_eq!(rows, want);
    }

    #[test]
    fn a_streaming_camera_is_recorded_for_the_duration_with_an_offset() {
        let (_, mut s) = stream(ReplayEnd::Idle);
        let mut file = Cursor::new(Vec::new());
        let mut writer = Aedat4Writer::new(&mut file, Compression::None, DAVIS240_SIZE).unwrap();
        let rec = record(&mut s, &mut writer, Duration::from_millis(300), 1_000_000).unwrap();
        drop(writer);
        assert!(rec.ended_early.is_none(), "{rec:?}");
        assert!(rec.elapsed >= Duration::from_millis(300));
        let got = read_back(file.get_ref());
        assert_eq!(got.len() as u64, rec.events);
        assert_eq!(
            got.len(),
            30_000,
            "the replay is read whole well within 300 ms"
        );
        assert_eq!(got.t[0], 1_000_000);
    }
}
