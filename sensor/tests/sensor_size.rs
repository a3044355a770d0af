//! The sensor size travels with the events through every format that can state it (module
//! `format::camera`): a DAVIS346 (346 × 260) or DVXplorer Lite (320 × 240) stream keeps its
//! corner pixels and its size through each writer and reader, a size a format cannot state is
//! refused naming the format and the size, and a file that states none reads as before.

use neurotac_core::{Event, EventBuffer, Timestamp};
use neurotac_sensor::FormatError;
use neurotac_sensor::format::{
    Aedat2Reader, Aedat3Reader, CsvReader, DAVIS240_SIZE, EcdTextReader, EventReader, Format,
    open_reader, open_reader_assuming, reader_from_bytes, to_bytes, write_file,
};

/// Events at the four corners of a `size` sensor and its centre, 1 ms apart.
fn corners((w, h): (u16, u16)) -> EventBuffer {
    [
        (0, 0),
        (w - 1, h - 1),
        (w - 1, 0),
        (0, h - 1),
        (w / 2, h / 2),
    ]
    .into_iter()
    .enumerate()
    .map(|(i, (x, y))| Event {
        t: Timestamp(1_000 * i as i64),
        x,
        y,
        polarity: i % 2 == 0,
    })
    .collect()
}

/// Whether `format` can state a `size` sensor: AEDAT 2.0 and 3.1 only name the DAVIS240 and
/// the DAVIS346.
fn can_state(format: Format, size: (u16, u16)) -> bool {
    match format {
        Format::Aedat2 | Format::Aedat3 => [(240, 180), (346, 260)].contains(&size),
        _ => true,
    }
}

#[test]
fn every_format_that_can_state_a_sensor_keeps_its_size_and_corner_events() {
    for size in [(346, 260), (320, 240), DAVIS240_SIZE] {
        let events = corners(size);
        for format in Format::ALL {
            let what = format!("{} × {} → {}", size.0, size.1, format.name());
            let written = to_bytes(&events, format, size);
            if !can_state(format, size) {
                let err = written.unwrap_err();
                assert!(
                    matches!(err, FormatError::UnsupportedSensorSize { width, height, .. }
                        if (width, height) == size),
                    "{what}: {err}"
                );
                let message = err.to_string();
                assert!(
                    message.contains(&format!("{} × {}", size.0, size.1))
                        && message.contains(format.name()),
                    "{what}: {message}"
                );
                continue;
            }
            let bytes = written.unwrap_or_else(|e| panic!("{what}: {e}"));
            let mut reader = reader_from_bytes(&bytes).unwrap();
            let stated = match format {
                // The text formats state every size but the one a file without the line has.
                Format::EcdText | Format::Csv if size == DAVIS240_SIZE => None,
                _ => Some(size),
            };
            assert_eq!(reader.sensor_size(), stated, "{what}");
            let mut back = EventBuffer::new();
            reader.read_to_end(&mut back).unwrap();
            assert_eq!(back, events, "{what}: the events read back");
            assert_eq!(reader.stats().out_of_range, 0, "{what}");
        }
    }
}

#[test]
fn each_format_states_the_size_as_its_own_tools_do() {
    let events = corners((346, 260));
    let text = |format| {
        String::from_utf8_lossy(&to_bytes(&events, format, (346, 260)).unwrap()).into_owned()
    };
    // jAER's chip class, cAER's camera name, DV's sizeX / sizeY, the documented comment line.
    assert!(text(Format::Aedat2).contains("# AEChip: eu.seebetter.ini.chips.davis.Davis346B\r\n"));
    assert!(text(Format::Aedat3).contains("#Source 1: DAVIS346\r\n"));
    let aedat4 = text(Format::Aedat4(neurotac_sensor::format::Compression::None));
    assert!(aedat4.contains("<attr key=\"sizeX\" type=\"int\">346</attr>"));
    assert!(aedat4.contains("<attr key=\"sizeY\" type=\"int\">260</attr>"));
    assert!(text(Format::Csv).starts_with("# sensor 346x260\nt,x,y,on\n0,0,0,1\n"));
    assert!(text(Format::EcdText).starts_with("# sensor 346x260\n0.000000000 0 0 1\n"));
    // A DAVIS240 text file stays exactly the ECD / faery layout.
    let davis240 = to_bytes(&corners(DAVIS240_SIZE), Format::Csv, DAVIS240_SIZE).unwrap();
    assert!(davis240.starts_with(b"t,x,y,on\n0,0,0,1\n"));
}

#[test]
fn sizes_no_format_field_can_hold_are_refused() {
    let events = EventBuffer::new();
    for (format, size) in [
        (
            Format::Aedat4(neurotac_sensor::format::Compression::Lz4),
            (40_000, 10),
        ),
        (
            Format::Aedat4(neurotac_sensor::format::Compression::Lz4),
            (10, 0),
        ),
        (Format::Csv, (0, 10)),
        (Format::EcdText, (10, 0)),
        (Format::Aedat3, (640, 480)),
    ] {
        let err = to_bytes(&events, format, size).unwrap_err();
        assert!(
            matches!(err, FormatError::UnsupportedSensorSize { .. }),
            "{}: {err}",
            format.name()
        );
    }
}

#[test]
fn an_event_outside_the_stated_sensor_is_a_write_error_naming_it() {
    let mut events = corners((346, 260));
    events.push(Event {
        t: Timestamp(9_000),
        x: 346,
        y: 0,
        polarity: true,
    });
    for format in Format::ALL {
        let err = to_bytes(&events, format, (346, 260)).unwrap_err();
        assert!(
            matches!(&err, FormatError::Unrepresentable { index: 5, reason, .. }
                if reason.contains("(346, 0)") && reason.contains("346 × 260")),
            "{}: {err}",
            format.name()
        );
    }
}

#[test]
fn a_davis346_aedat2_file_reads_with_jaer_mirrored_addresses() {
    // jAER's DAVIS layout: raw x = 345 − x, raw y = 259 − y; here raw (0, 0) and (345, 259).
    let mut file = b"#!AER-DAT2.0\r\n# AEChip: eu.seebetter.ini.chips.davis.Davis346red\r\n# End Of ASCII Header\r\n".to_vec();
    for (raw_x, raw_y, t) in [(0u32, 0u32, 5i32), (345, 259, 6)] {
        file.extend_from_slice(&(raw_y << 22 | raw_x << 12 | 1 << 11).to_be_bytes());
        file.extend_from_slice(&t.to_be_bytes());
    }
    let mut reader = Aedat2Reader::new(&file[..]).unwrap();
    assert_eq!(reader.sensor_size(), Some((346, 260)));
    let mut events = EventBuffer::new();
    reader.read_to_end(&mut events).unwrap();
    assert_eq!((events.x, events.y), (vec![345, 0], vec![259, 0]));
    // aedat4to2's misspelt chip (whose x it also leaves unmirrored) is refused, naming it.
    let file = b"#!AER-DAT2.0\r\n# AEChip: DAVI346\r\n# End of ASCII Header\r\n";
    let err = Aedat2Reader::new(&file[..]).err().unwrap();
    assert!(
        matches!(&err, FormatError::Invalid { field: "AEChip", found, .. } if found == "`DAVI346`"),
        "{err}"
    );
}

#[test]
fn an_aedat3_source_line_states_the_size_of_the_camera_it_names() {
    let header = |source: &str| format!("#!AER-DAT3.1\r\n#Format: RAW\r\n{source}#!END-HEADER\r\n");
    for (source, stated) in [
        ("#Source 1: DAVIS346B\r\n", Some((346, 260))),
        ("#Source 2: DAVIS240C\r\n", Some((240, 180))),
        ("#Source 1: DVS128\r\n", None),
        ("", None),
    ] {
        let bytes = header(source);
        let reader = Aedat3Reader::new(bytes.as_bytes()).unwrap();
        assert_eq!(reader.sensor_size(), stated, "{source}");
    }
}

#[test]
fn a_text_file_without_a_sensor_line_reads_as_before_and_one_with_it_states_its_size() {
    let body = "t,x,y,on\n1,345,259,1\n2,3,4,0\n";
    // Without the line: no stated size, events outside 240 × 180 skipped and counted.
    let mut reader = CsvReader::new(body.as_bytes()).unwrap();
    assert_eq!(reader.sensor_size(), None);
    let mut events = EventBuffer::new();
    reader.read_to_end(&mut events).unwrap();
    assert_eq!((events.len(), reader.stats().out_of_range), (1, 1));
    // With it (CRLF too), the corner pixel is kept.
    let stated = format!("# sensor 346x260\r\n{body}");
    let mut reader = CsvReader::new(stated.as_bytes()).unwrap();
    assert_eq!(reader.sensor_size(), Some((346, 260)));
    let mut events = EventBuffer::new();
    reader.read_to_end(&mut events).unwrap();
    assert_eq!((events.x, reader.stats().out_of_range), (vec![345, 3], 0));
    // A file that states no size, read as the size the caller assumes.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("faery.csv");
    std::fs::write(&path, body).unwrap();
    let mut reader = open_reader_assuming(&path, (346, 260)).unwrap();
    let mut events = EventBuffer::new();
    reader.read_to_end(&mut events).unwrap();
    assert_eq!((events.len(), reader.sensor_size()), (2, None));
    // An ECD text file of no events still states its size.
    let path = dir.path().join("empty.txt");
    write_file(&path, &EventBuffer::new(), (320, 240)).unwrap();
    let reader = open_reader(&path).unwrap();
    assert_eq!(reader.sensor_size(), Some((320, 240)));
    // A first `#` line that is not a sensor line is an error naming line 1.
    for bad in [
        "# sensor 346 by 260\n0 1 2 1\n",
        "# recorded by me\n0 1 2 1\n",
    ] {
        let err = EcdTextReader::new(bad.as_bytes()).err().unwrap();
        assert!(
            matches!(
                err,
                FormatError::Text {
                    line: 1,
                    field: "sensor line",
                    ..
                }
            ),
            "{bad}: {err}"
        );
    }
}
