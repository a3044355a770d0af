//! Hot loops allocate nothing after warm-up: the USB decoder fed chunk by chunk, and
//! every file reader handing out chunk after chunk into a reused buffer. Counted by a global
//! allocator that tallies this thread's allocations.

use neurotac::core::EventBuffer;
use neurotac::core::testing::{CountingAllocator, allocations_on_this_thread};
use neurotac::sensor::davis::UsbDecoder;
use neurotac::sensor::format::{self, Format};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

fn allocations() -> u64 {
    allocations_on_this_thread()
}

/// A synthetic stream: 200 000 events, a wrap word every 30 000 µs.
fn usb_words() -> Vec<u8> {
    let mut words = vec![0x0001u16];
    for i in 0..200_000u32 {
        if i % 30_000 == 0 {
            words.push(0x7001);
        }
        words.extend([0x8000 | (i % 0x8000) as u16, 0x1000 | (i % 180) as u16]);
        words.push(0x2000 | (i % 240) as u16 | ((i & 1) << 12) as u16);
    }
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

#[test]
fn decoding_and_reading_allocate_nothing_after_warm_up() {
    // USB decoder: 8 KiB transfers into a buffer cleared after each.
    let bytes = usb_words();
    let mut decoder = UsbDecoder::davis240();
    let mut out = EventBuffer::with_capacity(1 << 16);
    decoder.decode(&bytes[..8192], &mut out); // warm-up: the decoder's scratch block
    let before = allocations();
    for chunk in bytes[8192..].chunks(8192) {
        out.clear();
        decoder.decode(chunk, &mut out);
    }
    assert_eq!(allocations() - before, 0, "USB decoder");

    // Every reader: the events written to memory, then read chunk by chunk.
    let mut events = EventBuffer::new();
    decoder.decode(&bytes, &mut events);
    for format in Format::ALL {
        let file = format::to_bytes(&events, format, format::DAVIS240_SIZE).unwrap();
        let mut reader = format::reader_from_bytes(&file).unwrap();
        let mut chunk = EventBuffer::with_capacity(1 << 18);
        reader.read_chunk(&mut chunk).unwrap(); // warm-up: payload and decompression buffers
        reader.read_chunk(&mut chunk).unwrap();
        let before = allocations();
        let mut n = 0;
        loop {
            chunk.clear();
            let k = reader.read_chunk(&mut chunk).unwrap();
            if k == 0 {
                break;
            }
            n += k;
        }
        assert!(n > 100_000, "{format:?}: {n}");
        assert_eq!(allocations() - before, 0, "{format:?}");
    }
}
