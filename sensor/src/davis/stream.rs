//! A streaming DAVIS240: [`Davis::start`] in libcaer's order (davis240.md §1.5), the reader
//! thread and its bounded ring of buffers (§1.2), decoded on the consumer side (§1.6).
//!
//! ```text
//! reader thread: bulk IN 0x82 → free buffer → ring (filled)       overflow → freewheel buffer, counted as dropped
//! consumer:      ring (filled) → UsbDecoder → caller's EventBuffer → buffer back to the free list
//! ```
//!
//! The reader never waits for the consumer: when every buffer is full it keeps reading into a
//! spare buffer and counts each such transfer as a dropped packet ([`DavisStream::dropped_packets`]).
//! A disconnection ends the stream after every buffer received before it has been decoded, with
//! [`DeviceError::Disconnected`].

use super::decode::{DecodeStats, UsbDecoder};
use super::device::{Davis, DavisInfo, StartOptions, transport_error, write_register};
use super::protocol::{
    APS, DATA_ENDPOINT, DVS, EXTINPUT, IMU, MUX, Register, USB, aps, dvs, extinput, imu, mux, usb,
};
use super::transport::{Transport, TransportError};
use crate::error::DeviceError;
use neurotac_core::EventBuffer;
use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How the reader thread ended.
#[derive(Debug, Clone)]
enum ReaderEnd {
    Disconnected,
    Failed(String),
    Stopped,
}

#[derive(Debug)]
struct RingState {
    filled: VecDeque<(Vec<u8>, usize)>,
    free: Vec<Vec<u8>>,
    dropped_packets: u64,
    bytes_received: u64,
    end: Option<ReaderEnd>,
}

/// The bounded ring between the reader thread and the consumer: a fixed set of buffers
/// allocated once, moving between a free list and a queue of filled ones.
#[derive(Debug)]
struct Ring {
    state: Mutex<RingState>,
    ready: Condvar,
}

impl Ring {
    fn new(buffers: usize, bytes: usize) -> Self {
        Self {
            state: Mutex::new(RingState {
                filled: VecDeque::with_capacity(buffers),
                free: (0..buffers).map(|_| vec![0u8; bytes]).collect(),
                dropped_packets: 0,
                bytes_received: 0,
                end: None,
            }),
            ready: Condvar::new(),
        }
    }

    fn lock(&self) -> MutexGuard<'_, RingState> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }
}

/// Bulk reads into free ring buffers; when none is free, into `spare`, counted as dropped.
fn reader_loop<T: Transport>(t: &T, ring: &Ring, stop: &AtomicBool, mut spare: Vec<u8>) {
    let timeout = Duration::from_millis(100);
    let end = loop {
        if stop.load(Ordering::Acquire) {
            break ReaderEnd::Stopped;
        }
        let buffer = ring.lock().free.pop();
        let overflow = buffer.is_none();
        let mut buffer = buffer.unwrap_or_else(|| std::mem::take(&mut spare));
        let result = t.bulk_in(DATA_ENDPOINT, &mut buffer, timeout);
        let mut state = ring.lock();
        match result {
            Ok(n) if n > 0 => {
                state.bytes_received += n as u64;
                if overflow {
                    state.dropped_packets += 1;
                    spare = buffer;
                } else {
                    state.filled.push_back((buffer, n));
                    ring.ready.notify_one();
                }
                continue;
            }
            Ok(_) | Err(TransportError::Timeout) => {}
            Err(TransportError::Disconnected) => break ReaderEnd::Disconnected,
            Err(TransportError::Other(m)) => break ReaderEnd::Failed(m),
        }
        if overflow {
            spare = buffer;
        } else {
            state.free.push(buffer);
        }
    };
    ring.lock().end = Some(end);
    ring.ready.notify_all();
}

impl<T: Transport> Davis<T> {
    /// Starts streaming in libcaer's order (§1.5): everything off, 10 ms, clear the endpoint halt
    /// and start the reader thread; chip on, 200 ms for the biases; USB, timestamps and MUX on,
    /// 50 ms; then DVS (and APS/IMU/external input if asked) on.
    pub fn start(self, options: StartOptions) -> Result<DavisStream<T>, DeviceError> {
        let t = &*self.transport;
        for (m, p, v) in self.all_off() {
            write_register(t, m, p, v)?;
        }
        std::thread::sleep(Duration::from_millis(10));
        t.clear_halt(DATA_ENDPOINT)
            .map_err(transport_error("clear halt on endpoint 0x82".into()))?;
        let ring = Arc::new(Ring::new(
            options.ring_buffers.max(2),
            options.buffer_bytes.max(512),
        ));
        let stop = Arc::new(AtomicBool::new(false));
        let reader = {
            let (transport, ring, stop) = (
                Arc::clone(&self.transport),
                Arc::clone(&ring),
                Arc::clone(&stop),
            );
            let spare = vec![0u8; options.buffer_bytes.max(512)];
            std::thread::Builder::new()
                .name("davis-usb-reader".into())
                .spawn(move || reader_loop(&*transport, &ring, &stop, spare))
                .map_err(|e| DeviceError::Usb {
                    operation: "starting the reader thread".into(),
                    message: e.to_string(),
                })?
        };
        let decoder = UsbDecoder::new(self.info.decoder_config());
        let stream = DavisStream {
            davis: self,
            ring,
            stop,
            reader: Some(reader),
            decoder,
            events: 0,
            stopped: false,
        };
        let t = &*stream.davis.transport;
        let steps: [(&[Register], u64); 3] = [
            (&[(MUX, mux::RUN_CHIP, 1)], 200),
            (
                &[
                    (USB, usb::RUN, 1),
                    (MUX, mux::TIMESTAMP_RUN, 1),
                    (MUX, mux::RUN, 1),
                ],
                50,
            ),
            (
                &[
                    (DVS, dvs::RUN, 1),
                    (APS, aps::RUN, u32::from(options.aps)),
                    (IMU, imu::RUN_ACCELEROMETER, u32::from(options.imu)),
                    (IMU, imu::RUN_GYROSCOPE, u32::from(options.imu)),
                    (IMU, imu::RUN_TEMPERATURE, u32::from(options.imu)),
                    (
                        EXTINPUT,
                        extinput::RUN_DETECTOR,
                        u32::from(options.external_input),
                    ),
                ],
                0,
            ),
        ];
        for (registers, settle_ms) in steps {
            for &(m, p, v) in registers {
                write_register(t, m, p, v)?;
            }
            std::thread::sleep(Duration::from_millis(settle_ms));
        }
        Ok(stream)
    }
}

/// A streaming DAVIS240: decodes the ring's buffers on the consumer side (davis240.md §1.2, §1.6).
pub struct DavisStream<T: Transport> {
    pub(super) davis: Davis<T>,
    ring: Arc<Ring>,
    stop: Arc<AtomicBool>,
    reader: Option<JoinHandle<()>>,
    decoder: UsbDecoder,
    events: u64,
    stopped: bool,
}

impl<T: Transport> DavisStream<T> {
    /// What the device reported at open.
    pub fn info(&self) -> &DavisInfo {
        &self.davis.info
    }

    /// Waits up to `timeout` for data, decodes every buffer that is ready and appends the events
    /// to `out`; returns how many were appended (0 when nothing arrived in time).
    ///
    /// When the camera is unplugged, the buffers received before are decoded and returned
    /// first; the next call fails with [`DeviceError::Disconnected`].
    pub fn next_events(
        &mut self,
        out: &mut EventBuffer,
        timeout: Duration,
    ) -> Result<usize, DeviceError> {
        let before = out.len();
        let deadline = Instant::now() + timeout;
        let mut state = self.ring.lock();
        loop {
            if let Some((buffer, n)) = state.filled.pop_front() {
                drop(state);
                self.decoder.decode(&buffer[..n], out);
                state = self.ring.lock();
                state.free.push(buffer);
                continue;
            }
            if out.len() > before {
                break;
            }
            match &state.end {
                Some(ReaderEnd::Disconnected) => {
                    return Err(DeviceError::Disconnected {
                        bytes_received: state.bytes_received,
                        events_decoded: self.events,
                    });
                }
                Some(ReaderEnd::Failed(m)) => {
                    return Err(DeviceError::Usb {
                        operation: "bulk read on endpoint 0x82".into(),
                        message: m.clone(),
                    });
                }
                Some(ReaderEnd::Stopped) => return Err(DeviceError::Stopped),
                None => {}
            }
            let now = Instant::now();
            if now >= deadline {
                break;
            }
            state = self
                .ring
                .ready
                .wait_timeout(state, deadline - now)
                .unwrap_or_else(|p| p.into_inner())
                .0;
        }
        let n = out.len() - before;
        self.events += n as u64;
        Ok(n)
    }

    /// Bulk transfers dropped because the ring was full (the consumer fell behind).
    pub fn dropped_packets(&self) -> u64 {
        self.ring.lock().dropped_packets
    }

    /// Bytes received from the device.
    pub fn bytes_received(&self) -> u64 {
        self.ring.lock().bytes_received
    }

    /// The decoder's counters (events, specials, out-of-range addresses, …).
    pub fn decode_stats(&self) -> DecodeStats {
        self.decoder.stats()
    }

    /// Stops the camera in libcaer's order (DVS, APS, IMU, external input, MUX, timestamps, USB,
    /// chip off) and ends the reader thread. After an unplug the register writes fail quietly.
    pub fn stop(&mut self) -> Result<(), DeviceError> {
        if self.stopped {
            return Ok(());
        }
        self.stopped = true;
        let disconnected = matches!(self.ring.lock().end, Some(ReaderEnd::Disconnected));
        let mut result = Ok(());
        if !disconnected {
            for (m, p, v) in self.davis.all_off() {
                if let Err(e) = write_register(&*self.davis.transport, m, p, v) {
                    result = Err(e);
                    break;
                }
            }
        }
        self.stop.store(true, Ordering::Release);
        if let Some(reader) = self.reader.take() {
            let _ = reader.join();
        }
        result
    }
}

impl<T: Transport> Drop for DavisStream<T> {
    fn drop(&mut self) {
        let _ = self.stop();
    }
}
