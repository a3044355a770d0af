//! The real DAVIS240C recording of `../shared/data/davis240/` in every format: every
//! reader decodes the same 118 558 events, event for event, and the USB word stream decodes to
//! the expected 64-bit timestamps across the 2^31 µs big wrap.

use ndarray::{Array1, Array2};
use ndarray_npy::read_npy;
use neurotac::core::EventBuffer;
use neurotac::sensor::DeviceError;
use neurotac::sensor::davis::{
    Davis, DeviceInfo, ReplayEnd, ReplayTransport, StartOptions, UsbDecoder, protocol,
};
use neurotac::sensor::format::{self, Format};
use std::path::{Path, PathBuf};

const EVENTS: usize = 118_558;
/// The shift of the USB stream's times relative to the files (README: 2^31 − 700 000 µs).
const USB_SHIFT_US: i64 = 2_146_783_648;

/// The data folder, or `None` (with the reason printed) when it is absent; fails under `CI`.
fn data_dir() -> Option<PathBuf> {
    neurotac::core::testing::shared_data("davis240")
}

/// The CSV as the reference: t µs from 0, top-left x/y, on.
fn reference(dir: &Path) -> EventBuffer {
    let (events, stats) = format::read_file(&dir.join("pick_events.csv")).unwrap();
    assert_eq!(stats.events as usize, EVENTS);
    events
}

fn assert_same(name: &str, got: &EventBuffer, want: &EventBuffer) {
    assert_eq!(got.len(), want.len(), "{name}: event count");
    for i in 0..want.len() {
        assert_eq!(got.get(i), want.get(i), "{name}: event {i}");
    }
}

#[test]
fn every_file_decodes_to_the_same_events() {
    let Some(dir) = data_dir() else { return };
    let want = reference(&dir);
    assert_eq!(want.polarity.iter().filter(|&&p| p).count(), 75_525);
    assert_eq!((want.t[0], want.t[EVENTS - 1]), (0, 1_390_419));
    for (file, format) in [
        ("pick.aedat", Format::Aedat2),
        (
            "pick_none.aedat4",
            Format::Aedat4(format::Compression::None),
        ),
        ("pick_lz4.aedat4", Format::Aedat4(format::Compression::None)),
        (
            "pick_zstd.aedat4",
            Format::Aedat4(format::Compression::None),
        ),
        ("pick_events.txt", Format::EcdText),
    ] {
        let path = dir.join(file);
        let head = std::fs::read(&path).unwrap();
        assert_eq!(Format::detect(&head[..64]), Ok(format), "{file}");
        let (got, stats) = format::read_file(&path).unwrap();
        assert_same(file, &got, &want);
        assert_eq!(
            (
                stats.skipped,
                stats.out_of_range,
                stats.timestamps_backwards
            ),
            (0, 0, 0),
            "{file}"
        );
    }
}

#[test]
fn aedat2_matches_the_raw_jaer_fields() {
    let Some(dir) = data_dir() else { return };
    let raw: Array2<i32> = read_npy(dir.join("pick_raw_jaer_fields.npy")).unwrap();
    let (got, _) = format::read_file(&dir.join("pick.aedat")).unwrap();
    assert_eq!(raw.dim(), (4, EVENTS));
    for i in 0..EVENTS {
        let (raw_x, raw_y, t, p) = (raw[[0, i]], raw[[1, i]], raw[[2, i]], raw[[3, i]]);
        assert_eq!(
            i64::from(got.x[i]),
            239 - i64::from(raw_x),
            "x of event {i}"
        );
        assert_eq!(
            i64::from(got.y[i]),
            179 - i64::from(raw_y),
            "y of event {i}"
        );
        assert_eq!(got.t[i], i64::from(t), "t of event {i}");
        assert_eq!(got.polarity[i], p == 1, "p of event {i}");
    }
}

#[test]
fn usb_words_decode_to_the_expected_64_bit_times_in_any_chunking() {
    let Some(dir) = data_dir() else { return };
    let bytes = std::fs::read(dir.join("pick_usb_words.bin")).unwrap();
    let expected: Array1<i64> = read_npy(dir.join("pick_usb_expected_t_us.npy")).unwrap();
    let want = reference(&dir);
    for chunk in [bytes.len(), 8192, 8191, 511] {
        let mut decoder = UsbDecoder::davis240();
        let mut got = EventBuffer::new();
        for piece in bytes.chunks(chunk) {
            decoder.decode(piece, &mut got);
        }
        assert_eq!(got.len(), EVENTS, "chunks of {chunk} bytes");
        assert_eq!(
            got.t.as_slice(),
            expected.as_slice().unwrap(),
            "chunks of {chunk} bytes"
        );
        assert_eq!(
            (got.x.clone(), got.y.clone(), got.polarity.clone()),
            (want.x.clone(), want.y.clone(), want.polarity.clone())
        );
        let before = got.t.iter().filter(|&&t| t < 1 << 31).count();
        assert_eq!((before, EVENTS - before), (45_791, 72_767));
        let stats = decoder.stats();
        assert_eq!(stats.words, 325_809);
        assert_eq!((stats.timestamp_resets, stats.big_wraps), (1, 1));
        assert_eq!(stats.timestamps_backwards + stats.dropped_x_out_of_range, 0);
        assert!(!decoder.has_pending_byte());
    }
    assert!(
        want.t
            .iter()
            .zip(expected.iter())
            .all(|(a, b)| a + USB_SHIFT_US == *b)
    );
}

#[test]
fn writers_round_trip_losslessly_and_reproduce_the_shared_files() {
    let Some(dir) = data_dir() else { return };
    let want = reference(&dir);
    let out = tempfile::tempdir().unwrap();
    for name in ["a.aedat", "a.aedat3", "a.aedat4", "a.txt", "a.csv"] {
        let path = out.path().join(name);
        format::write_file(&path, &want, format::DAVIS240_SIZE).unwrap();
        let (got, _) = format::read_file(&path).unwrap();
        assert_same(name, &got, &want);
    }
    // The text writers and the AEDAT 2.0 writer reproduce the shared files byte for byte.
    for (name, shared) in [
        ("a.aedat", "pick.aedat"),
        ("a.txt", "pick_events.txt"),
        ("a.csv", "pick_events.csv"),
    ] {
        let ours = std::fs::read(out.path().join(name)).unwrap();
        assert!(
            ours == std::fs::read(dir.join(shared)).unwrap(),
            "{name} differs from {shared}"
        );
    }
    // Every AEDAT 4.0 codec.
    for compression in [
        format::Compression::None,
        format::Compression::Lz4,
        format::Compression::Zstd,
    ] {
        let path = out.path().join(format!("{compression:?}.aedat4"));
        let mut writer = format::create_writer_as(
            &path,
            Format::Aedat4(compression),
            format::DAVIS240_SIZE,
            format::Replace::No,
        )
        .unwrap();
        writer.write(&want).unwrap();
        writer.finish().unwrap();
        let (got, _) = format::read_file(&path).unwrap();
        assert_same(&format!("{compression:?}"), &got, &want);
    }
}

#[test]
fn times_past_the_big_wrap_survive_every_format() {
    let Some(dir) = data_dir() else { return };
    let bytes = std::fs::read(dir.join("pick_usb_words.bin")).unwrap();
    let mut usb = EventBuffer::new();
    UsbDecoder::davis240().decode(&bytes, &mut usb);
    let out = tempfile::tempdir().unwrap();
    for name in ["a.aedat", "a.aedat3", "a.aedat4", "a.txt", "a.csv"] {
        let path = out.path().join(name);
        let mut writer =
            format::create_writer(&path, format::DAVIS240_SIZE, format::Replace::No).unwrap();
        for start in (0..usb.len()).step_by(50_000) {
            let end = (start + 50_000).min(usb.len());
            let chunk: EventBuffer = (start..end).map(|i| usb.get(i).unwrap()).collect();
            writer.write(&chunk).unwrap();
        }
        writer.finish().unwrap();
        let mut reader = format::open_reader(&path).unwrap();
        let mut got = EventBuffer::new();
        reader.read_to_end(&mut got).unwrap();
        assert_same(name, &got, &usb);
        assert_eq!(
            reader.stats().timestamp_wraps,
            u64::from(name == "a.aedat"),
            "{name}"
        );
    }
}

#[test]
fn the_background_activity_keep_masks_match_the_recording() {
    // The masks are the oracle of the noise filter; here: they load and fit the events.
    let Some(dir) = data_dir() else { return };
    for (file, kept) in [
        ("pick_ba_keep_2000us.npy", 70_563),
        ("pick_ba_keep_5000us.npy", 81_980),
    ] {
        let mask: Array1<bool> = read_npy(dir.join(file)).unwrap();
        assert_eq!(mask.len(), EVENTS, "{file}");
        assert_eq!(mask.iter().filter(|&&k| k).count(), kept, "{file}");
    }
}

#[test]
fn the_driver_streams_the_recorded_usb_bytes_and_keeps_them_all_when_unplugged() {
    // Everything above the raw USB calls (open checks, configuration, start order, reader thread,
    // ring, consumer-side decoding) runs on the recorded stream, in libcaer's 8 KiB transfers; the
    // "camera" is unplugged when the recording ends.
    let Some(dir) = data_dir() else { return };
    let bytes = std::fs::read(dir.join("pick_usb_words.bin")).unwrap();
    let expected: Array1<i64> = read_npy(dir.join("pick_usb_expected_t_us.npy")).unwrap();
    let usb = DeviceInfo {
        product_id: protocol::PRODUCT_ID_FX2,
        firmware: protocol::FIRMWARE_FX2,
        bus: 1,
        address: 2,
        serial: None,
    };
    let davis = Davis::open(
        ReplayTransport::new(bytes.clone(), 8192, ReplayEnd::Unplug),
        usb,
    )
    .unwrap();
    davis.send_default_config().unwrap();
    let options = StartOptions {
        buffer_bytes: 8192,
        ..StartOptions::default()
    };
    let mut stream = davis.start(options).unwrap();
    let mut events = EventBuffer::new();
    let err = loop {
        if let Err(e) = stream.next_events(&mut events, std::time::Duration::from_secs(5)) {
            break e;
        }
    };
    assert!(
        matches!(err, DeviceError::Disconnected { bytes_received, events_decoded }
            if bytes_received == bytes.len() as u64 && events_decoded == EVENTS as u64),
        "{err}"
    );
    assert_eq!(stream.dropped_packets(), 0);
    assert_eq!(events.t.as_slice(), expected.as_slice().unwrap());
    let want = reference(&dir);
    assert_eq!(
        (events.x, events.y, events.polarity),
        (want.x, want.y, want.polarity)
    );
}

#[test]
fn pick_aedat_cut_inside_its_header_is_truncated_at_the_cut() {
    let Some(dir) = data_dir() else { return };
    let bytes = std::fs::read(dir.join("pick.aedat")).unwrap();
    for cut in 12..248 {
        match format::reader_from_bytes(&bytes[..cut]) {
            Err(e @ neurotac::sensor::FormatError::TruncatedHeader { offset, .. }) => {
                assert_eq!(offset, cut as u64);
                let msg = e.to_string();
                assert!(
                    msg.contains(&format!("truncated inside the header at byte {cut}")),
                    "{msg}"
                );
            }
            Err(e) => panic!("cut {cut}: {e}"),
            Ok(_) => panic!("cut {cut}: read as a recording"),
        }
    }
    // The whole header: an empty recording.
    let mut reader = format::reader_from_bytes(&bytes[..248]).unwrap();
    assert_eq!(reader.read_chunk(&mut EventBuffer::new()).unwrap(), 0);
}
