//! Event files that are bad in every way a file can be (davis240.md §2): truncated files and
//! packets, wrong magic, a header that never ends, packet sizes larger than the file, corrupt
//! compressed payloads, zero-length packets, timestamps going backwards, coordinates out of
//! range. Each gives a typed error or a documented, counted skip ([`ReadStats`]). Also: every
//! reader streams an endless input in bounded chunks. Only the public API is used.

use neurotac_core::{Event, EventBuffer, Timestamp};
use neurotac_sensor::FormatError;
use neurotac_sensor::format::{
    Aedat2Reader, Aedat2Writer, Aedat3Reader, Aedat3Writer, Aedat4Reader, Compression, CsvReader,
    DAVIS240_SIZE, EcdTextReader, EventReader, EventWriter, Format, ReadStats, aedat2, aedat4,
    reader_from_bytes, to_bytes,
};
use std::io::Read;
use std::path::Path;

/// The bound on a chunk that [`EventReader::read_chunk`] documents ("at most a few hundred
/// thousand" events): the readers' block size in bytes, 2¹⁸, since an event takes at least one
/// byte of input.
const CHUNK_BOUND: usize = 1 << 18;

/// Where the header of an encoding ends (the byte after its end line).
fn header_end(bytes: &[u8], end_line: &[u8]) -> usize {
    bytes
        .windows(end_line.len())
        .position(|w| w == end_line)
        .unwrap()
        + end_line.len()
}

fn events(n: usize) -> EventBuffer {
    (0..n)
        .map(|i| Event {
            t: Timestamp(10 * i as i64),
            x: (i % 240) as u16,
            y: (i % 180) as u16,
            polarity: i % 3 == 0,
        })
        .collect()
}

fn encode(format: Format, ev: &EventBuffer) -> Vec<u8> {
    to_bytes(ev, format, DAVIS240_SIZE).unwrap()
}

/// Reads everything; returns the events delivered, the stats and the error that ended it.
fn read(bytes: &[u8]) -> (EventBuffer, ReadStats, Option<FormatError>) {
    let mut out = EventBuffer::new();
    let mut reader = match reader_from_bytes(bytes) {
        Ok(r) => r,
        Err(e) => return (out, ReadStats::default(), Some(e)),
    };
    let err = reader.read_to_end(&mut out).err();
    (out, reader.stats(), err)
}

/// An endless reader: `prefix`, then `line` repeated forever.
struct Endless {
    prefix: Vec<u8>,
    line: &'static [u8],
    pos: usize,
}

impl Read for Endless {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        for b in buf.iter_mut() {
            *b = if self.pos < self.prefix.len() {
                self.prefix[self.pos]
            } else {
                self.line[(self.pos - self.prefix.len()) % self.line.len()]
            };
            self.pos += 1;
        }
        Ok(buf.len())
    }
}

#[test]
fn every_reader_streams_an_endless_input_in_bounded_chunks() {
    // An input that never ends (a 10 GB file, a pipe): the header and the first packet or
    // lines of a real encoding, then that packet (or those lines) repeated forever.
    let ev = events(PACKET_EVENTS_MAX);
    for format in Format::ALL {
        let bytes = encode(format, &ev);
        let data_start = match format {
            Format::Aedat2 => bytes.len() - 8 * ev.len(),
            Format::Aedat3 => header_end(&bytes, b"#!END-HEADER\r\n"),
            Format::Aedat4(_) => {
                18 + u32::from_le_bytes(bytes[14..18].try_into().unwrap()) as usize
            }
            Format::EcdText => 0,
            Format::Csv => 9,
        };
        let repeat = match format {
            Format::Aedat4(_) => {
                let size =
                    i32::from_le_bytes(bytes[data_start + 4..data_start + 8].try_into().unwrap());
                &bytes[data_start..data_start + 8 + size as usize]
            }
            Format::Aedat3 => &bytes[data_start..data_start + 28 + 4096 * 8],
            _ => &bytes[data_start..],
        };
        let mut prefix = bytes[..data_start].to_vec();
        if let Format::Aedat4(_) = format {
            prefix[54..62].copy_from_slice(&(-1i64).to_le_bytes()); // no data table to stop at
        }
        let endless = Endless {
            prefix,
            line: Vec::leak(repeat.to_vec()),
            pos: 0,
        };
        let mut reader: Box<dyn EventReader> = match format {
            Format::Aedat2 => Box::new(Aedat2Reader::new(endless).unwrap()),
            Format::Aedat3 => Box::new(Aedat3Reader::new(endless).unwrap()),
            Format::Aedat4(_) => Box::new(Aedat4Reader::new(endless).unwrap()),
            Format::EcdText => Box::new(EcdTextReader::new(endless).unwrap()),
            Format::Csv => Box::new(CsvReader::new(endless).unwrap()),
        };
        let mut chunk = EventBuffer::new();
        let mut total = 0;
        for _ in 0..12 {
            chunk.clear();
            let n = reader.read_chunk(&mut chunk).unwrap();
            assert!(n > 0 && n <= CHUNK_BOUND, "{format:?}: chunk of {n} events");
            total += n;
        }
        assert!(total >= 12, "{format:?}");
        assert!(
            chunk.t.capacity() <= 4 * CHUNK_BOUND,
            "{format:?}: the buffer stays bounded"
        );
    }
}

/// Events per packet of the largest packets written (AEDAT 4.0).
const PACKET_EVENTS_MAX: usize = aedat4::PACKET_EVENTS;

#[test]
fn every_format_round_trips_in_memory() {
    let ev = events(25_000);
    for format in Format::ALL {
        let (got, stats, err) = read(&encode(format, &ev));
        assert!(err.is_none(), "{format:?}: {err:?}");
        assert_eq!(got, ev, "{format:?}");
        assert_eq!(stats.events, 25_000);
    }
}

#[test]
fn truncated_files_deliver_what_precedes_and_then_a_typed_error() {
    let ev = events(25_000);
    for format in Format::ALL {
        let bytes = encode(format, &ev);
        // Cut in the middle of the data (for AEDAT 4.0, inside the second packet).
        let cut = match format {
            Format::Aedat4(_) => {
                let first = 18 + u32::from_le_bytes(bytes[14..18].try_into().unwrap()) as usize;
                let size = i32::from_le_bytes(bytes[first + 4..first + 8].try_into().unwrap());
                first + 8 + size as usize + 8 + 5
            }
            _ => bytes.len() / 2 + 3,
        };
        let (got, _, err) = read(&bytes[..cut]);
        assert!(got.len() < ev.len(), "{format:?}");
        assert_eq!(
            got.t[..],
            ev.t[..got.len()],
            "{format:?}: a prefix of the events"
        );
        match format {
            // Text: the cut leaves a partial last line, which either fails to parse or parses
            // as a shorter (different) event; both are fine as long as nothing panics.
            Format::EcdText | Format::Csv => {}
            Format::Aedat4(_) => {
                assert!(
                    matches!(
                        err,
                        Some(FormatError::Invalid {
                            field: "packet size",
                            ..
                        })
                    ),
                    "{format:?}: {err:?}"
                )
            }
            _ => assert!(
                matches!(err, Some(FormatError::Truncated { .. })),
                "{format:?}: {err:?}"
            ),
        }
    }
    // Truncated inside a header or a packet header.
    let aedat4 = encode(Format::Aedat4(Compression::Lz4), &ev);
    for cut in [10, 16, 100, 18 + 812 + 4] {
        let (_, _, err) = read(&aedat4[..cut.min(aedat4.len())]);
        assert!(
            matches!(
                err,
                Some(
                    FormatError::Truncated { .. }
                        | FormatError::TruncatedHeader { .. }
                        | FormatError::Invalid { .. }
                )
            ),
            "cut {cut}: {err:?}"
        );
    }
    let aedat3 = encode(Format::Aedat3, &ev);
    let data_start = header_end(&aedat3, b"#!END-HEADER\r\n");
    let (_, _, err) = read(&aedat3[..data_start + 20]);
    assert!(
        matches!(err, Some(FormatError::Truncated { expected, .. }) if expected.contains("packet header"))
    );
    let (_, _, err) = read(&aedat3[..data_start - 5]);
    assert!(
        matches!(err, Some(FormatError::TruncatedHeader { expected, .. }) if expected.contains("END-HEADER"))
    );
}

#[test]
fn truncated_aedat4_without_known_length_is_reported_as_truncated() {
    let bytes = encode(Format::Aedat4(Compression::Zstd), &events(15_000));
    let mut reader = Aedat4Reader::new(&bytes[..bytes.len() - 900]).unwrap();
    let mut out = EventBuffer::new();
    assert_eq!(reader.read_chunk(&mut out).unwrap(), 10_000);
    let err = reader.read_chunk(&mut out).unwrap_err();
    assert!(matches!(err, FormatError::Truncated { .. }), "{err}");
    assert_eq!(reader.read_chunk(&mut out).unwrap(), 0, "stays ended");
}

#[test]
fn wrong_magic_is_a_typed_error_for_each_reader() {
    let junk: &[u8] = b"#!AER-DAT9.9\r\nxxxxxxxxxxxxxxxxxxxxxxxx";
    assert!(matches!(
        Aedat2Reader::new(junk),
        Err(FormatError::Invalid {
            field: "version line",
            ..
        })
    ));
    assert!(matches!(
        Aedat3Reader::new(junk),
        Err(FormatError::Invalid {
            field: "version line",
            ..
        })
    ));
    assert!(matches!(
        Aedat4Reader::new(junk),
        Err(FormatError::Invalid { field: "magic", .. })
    ));
    let (_, _, err) = read(b"\x00\x01\x02binary");
    assert!(matches!(
        err,
        Some(FormatError::UnknownFormat { offset: 0, .. })
    ));
    // A CSV with a wrong header names the line.
    let (_, _, err) = read(b"t,x,y,on\n1,2,3,1\n");
    assert!(err.is_none());
    let mut r = CsvReader::new(&b"time,x,y,on\n1,2,3,1\n"[..]).unwrap();
    let err = r.read_chunk(&mut EventBuffer::new()).unwrap_err();
    assert!(
        matches!(
            err,
            FormatError::Text {
                line: 1,
                field: "header",
                ..
            }
        ),
        "{err}"
    );
    // AEDAT 4.0 with a wrong IOHeader identifier.
    let mut bytes = encode(Format::Aedat4(Compression::None), &events(3));
    bytes[22..26].copy_from_slice(b"XXXX");
    let (_, _, err) = read(&bytes);
    assert!(
        matches!(
            err,
            Some(FormatError::Invalid {
                field: "IOHeader identifier",
                offset: 18,
                ..
            })
        ),
        "{err:?}"
    );
}

#[test]
fn aedat2_of_another_chip_is_refused_by_name() {
    let file = b"#!AER-DAT2.0\r\n# AEChip: ch.unizh.ini.jaer.chip.retina.DVS128\r\n#End Of ASCII Header\r\n";
    let err = Aedat2Reader::new(&file[..]).err().unwrap();
    assert!(
        matches!(
            err,
            FormatError::Invalid {
                field: "AEChip",
                offset: 14,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("DVS128"), "{err}");
    // Without a sentinel the header ends at the first byte that does not start a `#` line.
    let ok =
        b"#!AER-DAT2.0\r\n# AEChip: eu.seebetter.ini.chips.davis.DAVIS240B\r\n\0\0\0\0\0\0\0\x05";
    let (got, _, err) = read(&ok[..]);
    assert!(err.is_none(), "{err:?}");
    assert_eq!((got.t[0], got.x[0], got.y[0]), (5, 239, 179));
}

#[test]
fn a_header_that_never_ends_stops_at_the_limit() {
    let endless = |prefix: &[u8]| Endless {
        prefix: prefix.to_vec(),
        line: b"# more header\r\n",
        pos: 0,
    };
    let err = Aedat2Reader::new(endless(b"#!AER-DAT2.0\r\n"))
        .err()
        .unwrap();
    assert!(
        matches!(err, FormatError::HeaderTooLong { limit, .. } if limit == aedat2::MAX_HEADER_BYTES),
        "{err}"
    );
    let err = Aedat3Reader::new(endless(b"#!AER-DAT3.1\r\n"))
        .err()
        .unwrap();
    assert!(matches!(err, FormatError::HeaderTooLong { .. }), "{err}");
    // One endless line without a line end.
    let line = Endless {
        prefix: b"#!AER-DAT3.1\r\n#".to_vec(),
        line: b"x",
        pos: 0,
    };
    assert!(matches!(
        Aedat3Reader::new(line),
        Err(FormatError::HeaderTooLong { .. })
    ));
    // An IOHeader size beyond the limit.
    let mut bytes = encode(Format::Aedat4(Compression::None), &events(3));
    bytes[14..18].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(matches!(
        read(&bytes).2,
        Some(FormatError::Invalid {
            field: "IOHeader size",
            offset: 14,
            ..
        })
    ));
    // A text line that never ends.
    let line = Endless {
        prefix: Vec::new(),
        line: b"1",
        pos: 0,
    };
    let err = EcdTextReader::new(line)
        .unwrap()
        .read_chunk(&mut EventBuffer::new())
        .unwrap_err();
    assert!(
        matches!(err, FormatError::Text { field: "line", .. }),
        "{err}"
    );
    let line = Endless {
        prefix: b"t,x,y,on\n".to_vec(),
        line: b"1",
        pos: 0,
    };
    let err = CsvReader::new(line)
        .unwrap()
        .read_chunk(&mut EventBuffer::new())
        .unwrap_err();
    assert!(
        matches!(
            err,
            FormatError::Text {
                field: "line",
                line: 2,
                offset: 9,
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn packet_sizes_larger_than_the_file_are_rejected_without_allocating_them() {
    let mut bytes = encode(Format::Aedat4(Compression::Lz4), &events(100));
    let first = 18 + 812 - 812 + u32::from_le_bytes(bytes[14..18].try_into().unwrap()) as usize;
    bytes[first + 4..first + 8].copy_from_slice(&i32::MAX.to_le_bytes());
    let (_, _, err) = read(&bytes);
    let msg = err.as_ref().unwrap().to_string();
    assert!(
        matches!(err, Some(FormatError::Invalid { field: "packet size", offset, .. }) if offset == first as u64 + 4),
        "{msg}"
    );
    assert!(msg.contains("bytes left before the data table"), "{msg}");
    // A data-table position inside the header: refused; past the end of the file: the events
    // are delivered, then the table's bytes read as a packet or the end of the file fail.
    let mut bad = encode(Format::Aedat4(Compression::None), &events(10));
    bad[54..62].copy_from_slice(&3i64.to_le_bytes());
    let err = read(&bad).2;
    assert!(
        matches!(
            err,
            Some(FormatError::Invalid {
                field: "dataTablePosition",
                ..
            })
        ),
        "{err:?}"
    );
    let past_end = bad.len() as i64 + 1;
    bad[54..62].copy_from_slice(&past_end.to_le_bytes());
    let (got, _, err) = read(&bad);
    assert_eq!(got.len(), 10, "the events come first");
    // The table's bytes are then read as a packet header: a typed error.
    assert!(
        matches!(
            err,
            Some(FormatError::Invalid {
                field: "packet size",
                ..
            })
        ),
        "{err:?}"
    );
    // A file cut before its data table: truncated.
    let mut cut = encode(Format::Aedat4(Compression::None), &events(10));
    let table_at = i64::from_le_bytes(cut[54..62].try_into().unwrap()) as usize;
    cut.truncate(table_at);
    cut[54..62].copy_from_slice(&(table_at as i64 + 100).to_le_bytes());
    let (got, _, err) = read(&cut);
    assert_eq!(got.len(), 10);
    assert!(
        matches!(err, Some(FormatError::Truncated { .. })),
        "{err:?}"
    );
    bytes[first + 4..first + 8].copy_from_slice(&(-5i32).to_le_bytes());
    assert!(matches!(
        read(&bytes).2,
        Some(FormatError::Invalid {
            field: "packet size",
            ..
        })
    ));
    // AEDAT 3.1: a capacity of 2^31 − 1 events in a small file is read block by block and ends
    // as truncated.
    let mut bytes = encode(Format::Aedat3, &events(100));
    let data_start = header_end(&bytes, b"#!END-HEADER\r\n");
    for field in [16, 20] {
        bytes[data_start + field..data_start + field + 4].copy_from_slice(&i32::MAX.to_le_bytes());
    }
    let (got, _, err) = read(&bytes);
    assert_eq!(got.len(), 100);
    assert!(
        matches!(err, Some(FormatError::Truncated { .. })),
        "{err:?}"
    );
    // eventNumber above eventCapacity, negative sizes.
    bytes[data_start + 16..data_start + 20].copy_from_slice(&5i32.to_le_bytes());
    assert!(matches!(
        read(&bytes).2,
        Some(FormatError::Invalid {
            field: "eventNumber",
            ..
        })
    ));
    bytes[data_start + 4..data_start + 8].copy_from_slice(&(-8i32).to_le_bytes());
    assert!(matches!(
        read(&bytes).2,
        Some(FormatError::Invalid {
            field: "eventSize",
            ..
        })
    ));
}

#[test]
fn corrupt_compressed_payloads_are_decompression_errors() {
    for compression in [Compression::Lz4, Compression::Zstd] {
        let bytes = encode(Format::Aedat4(compression), &events(100));
        let first = 18 + u32::from_le_bytes(bytes[14..18].try_into().unwrap()) as usize;
        let size = i32::from_le_bytes(bytes[first + 4..first + 8].try_into().unwrap()) as usize;
        for (at, value) in [(0, 0x00), (5, 0xFF), (size / 2, 0xAA), (size - 2, 0x7F)] {
            let mut bad = bytes.clone();
            bad[first + 8 + at] ^= value | 1;
            let (_, _, err) = read(&bad);
            // A flipped byte inside the data may still decompress (LZ4 has no checksum here);
            // what it must never do is panic. The frame-level corruptions must be caught.
            if at < 6 {
                assert!(
                    matches!(err, Some(FormatError::Decompress { offset, .. }) if offset == first as u64),
                    "{compression:?} byte {at}: {err:?}"
                );
            }
        }
        // A payload cut short inside the packet (size field shrunk accordingly).
        let mut bad = bytes.clone();
        bad[first + 4..first + 8].copy_from_slice(&((size / 2) as i32).to_le_bytes());
        bad.drain(first + 8 + size / 2..first + 8 + size);
        assert!(
            matches!(
                read(&bad).2,
                Some(FormatError::Decompress { .. } | FormatError::Invalid { .. })
            ),
            "{compression:?}"
        );
    }
}

#[test]
fn zero_length_packets_are_skipped_and_counted() {
    let ev = events(50);
    let bytes = encode(Format::Aedat4(Compression::Lz4), &ev);
    let first = 18 + u32::from_le_bytes(bytes[14..18].try_into().unwrap()) as usize;
    let mut with_empty = bytes[..first].to_vec();
    with_empty.extend_from_slice(&[0, 0, 0, 0, 0, 0, 0, 0]); // stream 0, size 0
    with_empty.extend_from_slice(&[7, 0, 0, 0, 3, 0, 0, 0, 1, 2, 3]); // another stream, skipped
    with_empty.extend_from_slice(&bytes[first..]);
    // The data-table position moved by the 19 inserted bytes.
    let table = i64::from_le_bytes(with_empty[54..62].try_into().unwrap()) + 19;
    with_empty[54..62].copy_from_slice(&table.to_le_bytes());
    let (got, stats, err) = read(&with_empty);
    assert!(err.is_none(), "{err:?}");
    assert_eq!(got, ev);
    assert_eq!(stats.skipped, 2);
    // AEDAT 3.1: an empty polarity packet and a non-polarity packet between the header and data.
    let bytes = encode(Format::Aedat3, &ev);
    let data_start = header_end(&bytes, b"#!END-HEADER\r\n");
    let mut with_empty = bytes[..data_start].to_vec();
    let mut empty = [0u8; 28];
    empty[0] = 1;
    empty[4] = 8;
    empty[8] = 4;
    with_empty.extend_from_slice(&empty);
    let mut special = [0u8; 28];
    special[4] = 8; // type 0 (special), size 8, capacity 1
    special[16] = 1;
    with_empty.extend_from_slice(&special);
    with_empty.extend_from_slice(&[0; 8]);
    with_empty.extend_from_slice(&bytes[data_start..]);
    let (got, stats, err) = read(&with_empty);
    assert!(err.is_none(), "{err:?}");
    assert_eq!(got, ev);
    assert_eq!(stats.skipped, 2);
}

#[test]
fn backwards_timestamps_are_reported_and_kept_in_order() {
    let mut ev = events(300);
    ev.t[200] = 5; // earlier than event 199 (t = 1990)
    for format in Format::ALL {
        let (got, stats, err) = read(&encode(format, &ev));
        assert!(err.is_none(), "{format:?}: {err:?}");
        assert_eq!(got, ev, "{format:?}: not reordered");
        assert_eq!(stats.timestamps_backwards, 1, "{format:?}");
        let b = stats.first_backwards.unwrap();
        assert_eq!((b.previous_us, b.t_us), (1990, 5), "{format:?}");
    }
    // AEDAT 2.0: the record's byte offset is exact.
    let bytes = encode(Format::Aedat2, &ev);
    let header = bytes
        .windows(22)
        .position(|w| w == b"# End of ASCII Header\r".as_slice())
        .unwrap()
        + 23;
    let (_, stats, _) = read(&bytes);
    assert_eq!(
        stats.first_backwards.unwrap().offset,
        (header + 200 * 8) as u64
    );
}

#[test]
fn out_of_range_coordinates_are_skipped_and_counted() {
    let ev = events(10);
    // AEDAT 2.0: raw x 300 (a 10-bit field) in record 3.
    let mut bytes = encode(Format::Aedat2, &ev);
    let data = bytes.len() - 10 * 8;
    let addr = (179u32 - 3) << 22 | 300 << 12;
    bytes[data + 24..data + 28].copy_from_slice(&addr.to_be_bytes());
    let (got, stats, _) = read(&bytes);
    assert_eq!((got.len(), stats.out_of_range), (9, 1));
    // AEDAT 3.1: x 240.
    let mut bytes = encode(Format::Aedat3, &ev);
    let data = bytes.len() - 10 * 8;
    bytes[data..data + 4].copy_from_slice(&(240u32 << 17 | 1).to_le_bytes());
    let (got, stats, _) = read(&bytes);
    assert_eq!((got.len(), stats.out_of_range), (9, 1));
    // AEDAT 4.0: x 240, then y −1.
    let first_event =
        |bytes: &[u8]| 18 + u32::from_le_bytes(bytes[14..18].try_into().unwrap()) as usize + 8 + 32;
    for (field, value) in [(8, 240i16), (10, -1)] {
        let mut bytes = encode(Format::Aedat4(Compression::None), &ev);
        let e5 = first_event(&bytes) + 5 * 16;
        bytes[e5 + field..e5 + field + 2].copy_from_slice(&value.to_le_bytes());
        let (got, stats, _) = read(&bytes);
        assert_eq!((got.len(), stats.out_of_range), (9, 1));
    }
    // Text: y 180.
    let (got, stats, _) = read(b"t,x,y,on\n1,2,180,1\n2,3,4,0\n");
    assert_eq!((got.len(), stats.out_of_range), (1, 1));
    // Writers refuse an event outside the sensor their file states, naming it.
    let mut ev4 = events(10);
    ev4.x[2] = 240;
    for format in Format::ALL {
        let err = to_bytes(&ev4, format, DAVIS240_SIZE).unwrap_err();
        assert!(
            matches!(&err, FormatError::Unrepresentable { index: 2, reason, .. }
                if reason.contains("(240, 2)") && reason.contains("240 × 180")),
            "{}: {err}",
            format.name()
        );
    }
    let mut w = Aedat2Writer::new(Vec::new(), DAVIS240_SIZE).unwrap();
    assert!(matches!(
        w.write(&ev4),
        Err(FormatError::Unrepresentable { index: 2, .. })
    ));
    let mut neg = events(2);
    neg.t[1] = -1;
    let mut w = Aedat3Writer::new(Vec::new(), DAVIS240_SIZE).unwrap();
    assert!(matches!(
        w.write(&neg),
        Err(FormatError::Unrepresentable { index: 1, .. })
    ));
}

#[test]
fn text_errors_name_line_field_and_offset() {
    let (got, _, err) = read(b"0.1 1 2 1\n0.2 1 2 1\n0.3 1 x 1\n");
    assert_eq!(got.len(), 2, "lines before the error are delivered");
    match err {
        Some(FormatError::Text {
            line,
            offset,
            field,
            ref found,
            ..
        }) => {
            assert_eq!((line, offset, field, found.as_str()), (3, 20, "y", "x"));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn aedat2_cut_inside_its_header_is_truncated_not_empty() {
    // The header the writer produces is the one of `pick.aedat` (248 bytes); every cut inside
    // it, including inside the AEChip line (byte 200), is a typed error at the cut.
    let bytes = encode(Format::Aedat2, &events(3));
    let end = header_end(&bytes, b"# End of ASCII Header\r\n");
    assert_eq!(end, 248);
    for cut in 1..end {
        let (got, _, err) = read(&bytes[..cut]);
        assert!(got.is_empty());
        match &err {
            Some(e @ FormatError::TruncatedHeader { offset, .. }) if *offset == cut as u64 => {
                let msg = e.to_string();
                let want = format!("truncated inside the header at byte {cut}");
                assert!(msg.contains(&want), "cut {cut}: {msg}");
            }
            other => panic!("cut {cut}: {other:?}"),
        }
        if cut >= 12 {
            let direct = Aedat2Reader::new(&bytes[..cut]).err();
            assert!(
                matches!(direct, Some(FormatError::TruncatedHeader { offset, .. }) if offset == cut as u64),
                "cut {cut}: {direct:?}"
            );
        }
    }
    // The whole header and no record: an empty recording.
    let (got, stats, err) = read(&bytes[..end]);
    assert!(
        err.is_none() && got.is_empty() && stats.events == 0,
        "{err:?}"
    );
}

#[test]
fn aedat3_and_aedat4_cut_inside_their_header_or_magic_are_truncated() {
    let bytes = encode(Format::Aedat3, &events(3));
    let end = header_end(&bytes, b"#!END-HEADER\r\n");
    for cut in 1..end {
        let (_, _, err) = read(&bytes[..cut]);
        assert!(
            matches!(err, Some(FormatError::TruncatedHeader { offset, .. }) if offset == cut as u64),
            "cut {cut}: {err:?}"
        );
    }
    let bytes = encode(Format::Aedat4(Compression::None), &events(3));
    for cut in 1..12 {
        let (_, _, err) = read(&bytes[..cut]);
        assert!(
            matches!(err, Some(FormatError::TruncatedHeader { offset, .. }) if offset == cut as u64),
            "cut {cut}: {err:?}"
        );
    }
    // A version that is not a prefix of a supported one stays unsupported.
    assert!(matches!(
        read(b"#!AER-DAT3").2,
        Some(FormatError::TruncatedHeader { offset: 10, .. })
    ));
    assert!(matches!(
        read(b"#!AER-DAT1").2,
        Some(FormatError::UnsupportedVersion { .. })
    ));
}

#[test]
fn unsupported_version_is_quoted_once() {
    for (bytes, version) in [
        (&b"#!AER-DAT3.0\r\n"[..], "`3.0`"),
        (b"#!AER-DAT1\r\n", "`1`"),
        (b"#!AER-DAT3.\x00\r\n", "`3.\\x00`"),
    ] {
        let err = read(bytes).2.unwrap();
        let msg = err.to_string();
        assert!(
            matches!(err, FormatError::UnsupportedVersion { .. }),
            "{msg}"
        );
        assert!(
            msg.contains(&format!("unsupported AEDAT version {version} (")),
            "{msg}"
        );
        assert!(!msg.contains("``"), "{msg}");
    }
}

#[test]
fn text_errors_escape_control_bytes() {
    let cases: [&[u8]; 3] = [
        b"t,x,y,on\n1,2\x003,1\n",
        b"0.1 1 2 1\n0.2 1 2\x1b[31m 1\n",
        b"t,x,y,on\n1,2,3,\x00\n",
    ];
    for bytes in cases {
        let err = read(bytes).2.unwrap();
        let msg = err.to_string();
        assert!(matches!(err, FormatError::Text { .. }), "{msg}");
        assert!(
            !msg.chars().any(|c| c.is_control()),
            "raw control character in {msg:?}"
        );
        assert!(msg.contains("\\x00") || msg.contains("\\x1b"), "{msg}");
    }
    // Printable non-ASCII text is shown as it is; invalid UTF-8 is escaped.
    let err = read(b"t,x,y,on\n1,2,3,\xc2\xb5\n").2.unwrap();
    assert!(err.to_string().contains("`µ`"), "{err}");
    let err = read(b"t,x,y,on\n1,2,3,\xff\n").2.unwrap();
    assert!(err.to_string().contains("`\\xff`"), "{err}");
}

#[test]
fn too_many_fields_quotes_the_line_bounded() {
    let err = read(b"t,x,y,on\n1,2,3,1,5\n").2.unwrap();
    assert!(
        matches!(&err, FormatError::Text { field: "line", found, line: 2, .. } if found == "1,2,3,1,5"),
        "{err}"
    );
    let err = read(b"0.1 2 3 1 5\n").2.unwrap();
    assert!(
        matches!(&err, FormatError::Text { field: "line", found, .. } if found == "0.1 2 3 1 5"),
        "{err}"
    );
    // A long line is quoted up to a bound, marked as cut.
    let long = format!("t,x,y,on\n1,2,3,1{}\n", ",7".repeat(1000));
    let err = read(long.as_bytes()).2.unwrap();
    match &err {
        FormatError::Text { found, .. } => {
            assert!(
                found.starts_with("1,2,3,1,7,7") && found.ends_with('…'),
                "{found}"
            );
            assert!(found.len() <= 64 + '…'.len_utf8(), "{found}");
        }
        other => panic!("{other}"),
    }
}

#[test]
fn one_warning_line_for_backwards_time_and_skipped_events() {
    let (_, stats, err) = read(b"t,x,y,on\n10,1,2,1\n5,1,2,0\n11,300,2,1\n");
    assert!(err.is_none());
    let line = stats.warning(Path::new("in.csv")).unwrap();
    assert_eq!(
        line,
        "warning: in.csv: skipped 1 events outside the sensor; 1 events go back in time (kept in file order; the first at byte 18: 5 µs after 10 µs)"
    );
    assert!(!line.contains('\n'));
    let (_, stats, _) = read(b"t,x,y,on\n10,1,2,1\n");
    assert_eq!(stats.warning(Path::new("in.csv")), None);
}

#[test]
fn aedat2_round_trips_steps_back_across_a_wrap() {
    // Every step is below 2^31 µs, so the writer accepts it; the last steps back over the
    // 32-bit wrap the one before crossed.
    let mut ev = events(4);
    ev.t = vec![0, 2_147_483_000, 4_294_966_000, 2_147_483_000];
    let (got, stats, err) = read(&encode(Format::Aedat2, &ev));
    assert!(err.is_none(), "{err:?}");
    assert_eq!(got.t, ev.t);
    assert_eq!((stats.timestamp_wraps, stats.timestamps_backwards), (1, 1));
    // A step of 2^31 µs or more, or a first time beyond ±2^31 µs, is refused by the writer.
    for t in [vec![0, 1 << 31], vec![-(1 << 31) - 1]] {
        let mut ev = events(t.len());
        ev.t = t;
        let err = to_bytes(&ev, Format::Aedat2, DAVIS240_SIZE).unwrap_err();
        assert!(matches!(err, FormatError::Unrepresentable { .. }), "{err}");
    }
}
