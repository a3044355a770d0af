//! The DAVIS240 driver above the raw USB calls: open checks, default configuration, register
//! reads and writes, and the registers that stop the camera (davis240.md §1.1–1.5). Starting it
//! ([`Davis::start`]) and streaming from it live in module `stream`.

use super::decode::DecoderConfig;
use super::protocol::*;
use super::transport::{DeviceInfo, Transport, TransportError};
use crate::error::DeviceError;
use std::sync::Arc;

/// What the device reports about itself at open (SYSINFO, DVS, APS and IMU registers; §1.4–1.5).
#[derive(Debug, Clone, PartialEq)]
pub struct DavisInfo {
    /// USB identity.
    pub usb: DeviceInfo,
    /// Logic version (18).
    pub logic_version: u32,
    /// Logic patch (≥ 1).
    pub logic_patch: u32,
    /// Chip identifier: 0, 1, 2 = DAVIS240A, B, C.
    pub chip: u32,
    /// The device is the timestamp master.
    pub is_master: bool,
    /// DVS columns, after the X/Y swap (240).
    pub dvs_size_x: u16,
    /// DVS rows, after the X/Y swap (180).
    pub dvs_size_y: u16,
    /// DVS invert-X/Y flag (orientation bit 2).
    pub dvs_invert_xy: bool,
    /// APS columns and rows.
    pub aps_size: (u16, u16),
    /// The APS has a global shutter.
    pub aps_global_shutter: bool,
    /// IMU type (0 none, 1 InvenSense 6050/6150, 2 InvenSense 9250).
    pub imu_type: u32,
    /// Actual logic clock (MHz): nominal × deviation / 1000.
    pub logic_clock_mhz: f64,
    /// Actual ADC clock (MHz).
    pub adc_clock_mhz: f64,
    /// Actual USB clock (MHz).
    pub usb_clock_mhz: f64,
    /// DVS filters present in the logic: pixel, background activity, ROI, skip, polarity.
    pub dvs_filters: [bool; 5],
}

impl DavisInfo {
    /// `DAVIS240A`, `DAVIS240B` or `DAVIS240C`.
    pub fn chip_name(&self) -> &'static str {
        match self.chip {
            0 => "DAVIS240A",
            1 => "DAVIS240B",
            _ => "DAVIS240C",
        }
    }

    /// The decoder geometry this device needs.
    pub fn decoder_config(&self) -> DecoderConfig {
        DecoderConfig {
            size_x: self.dvs_size_x,
            size_y: self.dvs_size_y,
            invert_xy: self.dvs_invert_xy,
        }
    }
}

/// Which parts of the camera run once started (step 4 of §1.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StartOptions {
    /// Run the APS (frames). Default `false`: a tactile sensor needs DVS events only.
    pub aps: bool,
    /// Run the IMU. Default `false`.
    pub imu: bool,
    /// Run the external-input detector. Default `false`.
    pub external_input: bool,
    /// Number of ring buffers. Default 256.
    pub ring_buffers: usize,
    /// Bytes per bulk read and ring buffer. Default 16 KiB (libcaer: 8 × 8 KiB in flight).
    pub buffer_bytes: usize,
}

impl Default for StartOptions {
    fn default() -> Self {
        Self {
            aps: false,
            imu: false,
            external_input: false,
            ring_buffers: 256,
            buffer_bytes: 16 << 10,
        }
    }
}

/// An opened DAVIS240, not yet streaming (davis240.md §1.5).
pub struct Davis<T: Transport> {
    pub(super) transport: Arc<T>,
    pub(super) info: DavisInfo,
}

/// Maps a transport error of `operation` to a [`DeviceError`] (an unplugged camera to
/// [`DeviceError::Disconnected`]).
pub(super) fn transport_error(operation: String) -> impl FnOnce(TransportError) -> DeviceError {
    move |e| match e {
        TransportError::Disconnected => DeviceError::Disconnected {
            bytes_received: 0,
            events_decoded: 0,
        },
        other => DeviceError::Usb {
            operation,
            message: other.to_string(),
        },
    }
}

/// Reads one register (request 0xBF IN, big-endian u32; §1.3).
fn read_register<T: Transport>(t: &T, module: u16, param: u16) -> Result<u32, DeviceError> {
    let mut buf = [0u8; 4];
    let what = || format!("register read (module {module}, param {param})");
    let n = t
        .control_in(VENDOR_REQUEST_FPGA_CONFIG, module, param, &mut buf)
        .map_err(transport_error(what()))?;
    if n != 4 {
        return Err(DeviceError::Usb {
            operation: what(),
            message: format!("{n} bytes returned, expected 4"),
        });
    }
    Ok(u32::from_be_bytes(buf))
}

/// Writes one register (request 0xBF OUT, big-endian u32; §1.3).
pub(super) fn write_register<T: Transport>(
    t: &T,
    module: u16,
    param: u16,
    value: u32,
) -> Result<(), DeviceError> {
    t.control_out(
        VENDOR_REQUEST_FPGA_CONFIG,
        module,
        param,
        &value.to_be_bytes(),
    )
    .map_err(transport_error(format!(
        "register write (module {module}, param {param})"
    )))?;
    Ok(())
}

/// Writes several registers in one request 0xC2 (wValue = count; 6 bytes each: u8 module,
/// u8 param, u32 big-endian value; §1.3).
fn write_registers<T: Transport>(t: &T, registers: &[Register]) -> Result<(), DeviceError> {
    for batch in registers.chunks(64) {
        let mut data = Vec::with_capacity(6 * batch.len());
        for &(module, param, value) in batch {
            data.push(module as u8);
            data.push(param as u8);
            data.extend_from_slice(&value.to_be_bytes());
        }
        t.control_out(
            VENDOR_REQUEST_FPGA_CONFIG_MULTIPLE,
            batch.len() as u16,
            0,
            &data,
        )
        .map_err(transport_error(format!(
            "multiple register write ({} registers)",
            batch.len()
        )))?;
    }
    Ok(())
}

impl<T: Transport> Davis<T> {
    /// Checks and reads the device as libcaer's open does (§1.5): firmware (bcdDevice) for the
    /// board, logic version 18 and patch ≥ 1, a DAVIS240 chip, sizes, orientation, clocks and the
    /// DVS filters present.
    pub fn open(transport: T, usb_info: DeviceInfo) -> Result<Self, DeviceError> {
        let required = if usb_info.product_id == PRODUCT_ID_FX3 {
            FIRMWARE_FX3
        } else {
            FIRMWARE_FX2
        };
        if usb_info.firmware != required {
            return Err(DeviceError::Firmware {
                found: usb_info.firmware,
                required,
            });
        }
        let t = &transport;
        let logic_version = read_register(t, SYSINFO, sysinfo::LOGIC_VERSION)?;
        if logic_version != LOGIC_VERSION {
            return Err(DeviceError::LogicVersion {
                found: logic_version,
                required: LOGIC_VERSION,
            });
        }
        let logic_patch = read_register(t, SYSINFO, sysinfo::LOGIC_PATCH)?;
        if logic_patch < LOGIC_PATCH_MIN {
            return Err(DeviceError::LogicPatch {
                found: logic_patch,
                minimum: LOGIC_PATCH_MIN,
            });
        }
        let chip = read_register(t, SYSINFO, sysinfo::CHIP_IDENTIFIER)?;
        if chip > 2 {
            return Err(DeviceError::UnsupportedChip { found: chip });
        }
        let size = |module, param| -> Result<u16, DeviceError> {
            let v = read_register(t, module, param)?;
            u16::try_from(v)
                .ok()
                .filter(|&s| (1..=4096).contains(&s))
                .ok_or(DeviceError::Register {
                    module,
                    param,
                    found: v,
                    expected: "a size of 1 to 4096 pixels",
                })
        };
        let (mut size_x, mut size_y) = (size(DVS, dvs::SIZE_COLUMNS)?, size(DVS, dvs::SIZE_ROWS)?);
        let invert_xy = read_register(t, DVS, dvs::ORIENTATION_INFO)? & 4 != 0;
        if invert_xy {
            std::mem::swap(&mut size_x, &mut size_y);
        }
        let (mut aps_x, mut aps_y) = (size(APS, aps::SIZE_COLUMNS)?, size(APS, aps::SIZE_ROWS)?);
        if read_register(t, APS, aps::ORIENTATION_INFO)? & 4 != 0 {
            std::mem::swap(&mut aps_x, &mut aps_y);
        }
        let deviation = f64::from(read_register(t, SYSINFO, sysinfo::CLOCK_DEVIATION)?) / 1000.0;
        let clock = |param| -> Result<f64, DeviceError> {
            Ok(f64::from(read_register(t, SYSINFO, param)?) * deviation)
        };
        let mut dvs_filters = [false; 5];
        for (flag, param) in dvs_filters.iter_mut().zip([
            dvs::HAS_PIXEL_FILTER,
            dvs::HAS_BACKGROUND_ACTIVITY_FILTER,
            dvs::HAS_ROI_FILTER,
            dvs::HAS_SKIP_FILTER,
            dvs::HAS_POLARITY_FILTER,
        ]) {
            *flag = read_register(t, DVS, param)? != 0;
        }
        let info = DavisInfo {
            usb: usb_info,
            logic_version,
            logic_patch,
            chip,
            is_master: read_register(t, SYSINFO, sysinfo::DEVICE_IS_MASTER)? != 0,
            dvs_size_x: size_x,
            dvs_size_y: size_y,
            dvs_invert_xy: invert_xy,
            aps_size: (aps_x, aps_y),
            aps_global_shutter: read_register(t, APS, aps::HAS_GLOBAL_SHUTTER)? != 0,
            imu_type: read_register(t, IMU, imu::TYPE)?,
            logic_clock_mhz: clock(sysinfo::LOGIC_CLOCK)?,
            adc_clock_mhz: clock(sysinfo::ADC_CLOCK)?,
            usb_clock_mhz: clock(sysinfo::USB_CLOCK)?,
            dvs_filters,
        };
        Ok(Self {
            transport: Arc::new(transport),
            info,
        })
    }

    /// What the device reported at open.
    pub fn info(&self) -> &DavisInfo {
        &self.info
    }

    /// The registers of libcaer's `caerDeviceSendDefaultConfig` for this device (§1.5): DAVIS240
    /// biases and chip configuration, then the FPGA defaults (FPGA background-activity filter on
    /// at 2 ms when present, as libcaer), then the USB early-packet delay of 1 ms.
    pub fn default_config(&self) -> Vec<Register> {
        let i = &self.info;
        let mut r: Vec<Register> = Vec::new();
        r.extend(
            DAVIS240_BIASES
                .iter()
                .enumerate()
                .map(|(p, &w)| (CHIP, p as u16, u32::from(w))),
        );
        // Chip configuration 128–141: MUX selects 0, RESETCALIBNEURON 1, TYPENCALIBNEURON 0,
        // RESETTESTPIXEL 1, SPECIALPIXELCONTROL 0 (240A/B only), AERNAROW 0, USEAOUT 0.
        for p in 128..=135 {
            r.push((CHIP, p, 0));
        }
        r.extend([(CHIP, 136, 1), (CHIP, 137, 0), (CHIP, 138, 1)]);
        if i.chip <= 1 {
            r.push((CHIP, 139, 0));
        }
        r.extend([(CHIP, 140, 0), (CHIP, 141, 0)]);
        if i.aps_global_shutter {
            r.push((CHIP, 142, 1));
        }
        r.extend([
            (MUX, mux::TIMESTAMP_RESET, 0),
            (MUX, mux::DROP_EXTINPUT_ON_TRANSFER_STALL, 1),
            (MUX, mux::DROP_DVS_ON_TRANSFER_STALL, 1),
            (DVS, dvs::WAIT_ON_TRANSFER_STALL, 0),
            (DVS, dvs::EXTERNAL_AER_CONTROL, 0),
        ]);
        let (sx, sy) = (u32::from(i.dvs_size_x), u32::from(i.dvs_size_y));
        let [pixel, ba, roi, skip, polarity] = i.dvs_filters;
        if pixel {
            for k in 0..8 {
                r.push((DVS, dvs::FILTER_PIXEL_0_ROW + 2 * k, sy));
                r.push((DVS, dvs::FILTER_PIXEL_0_ROW + 2 * k + 1, sx));
            }
        }
        if ba {
            r.extend([
                (DVS, dvs::FILTER_BACKGROUND_ACTIVITY, 1),
                (DVS, dvs::FILTER_BACKGROUND_ACTIVITY_TIME, 8),
                (DVS, dvs::FILTER_REFRACTORY_PERIOD, 0),
                (DVS, dvs::FILTER_REFRACTORY_PERIOD_TIME, 1),
            ]);
        }
        if roi {
            let s = dvs::FILTER_ROI_START_COLUMN;
            r.extend([
                (DVS, s, 0),
                (DVS, s + 1, 0),
                (DVS, s + 2, sx - 1),
                (DVS, s + 3, sy - 1),
            ]);
        }
        if skip {
            r.extend([
                (DVS, dvs::FILTER_SKIP_EVENTS, 0),
                (DVS, dvs::FILTER_SKIP_EVENTS_EVERY, 5),
            ]);
        }
        if polarity {
            let f = dvs::FILTER_POLARITY_FLATTEN;
            r.extend([(DVS, f, 0), (DVS, f + 1, 0), (DVS, f + 2, 0)]);
        }
        let (ax, ay) = (u32::from(i.aps_size.0), u32::from(i.aps_size.1));
        let adc_cycles = |us: f64| (us * i.adc_clock_mhz).round() as u32;
        let s = aps::START_COLUMN_0;
        r.extend([
            (APS, aps::WAIT_ON_TRANSFER_STALL, 1),
            (APS, aps::GLOBAL_SHUTTER, u32::from(i.aps_global_shutter)),
            (APS, s, 0),
            (APS, s + 1, 0),
            (APS, s + 2, ax - 1),
            (APS, s + 3, ay - 1),
            (APS, aps::EXPOSURE, adc_cycles(4000.0)),
            (APS, aps::FRAME_INTERVAL, adc_cycles(40_000.0)),
            (IMU, imu::SAMPLE_RATE_DIVIDER, 0),
            (IMU, imu::ACCEL_DLPF, 1),
            (IMU, imu::ACCEL_FULL_SCALE, 1),
            (IMU, imu::GYRO_DLPF, 1),
            (IMU, imu::GYRO_FULL_SCALE, 1),
            (EXTINPUT, extinput::DETECT_RISING_EDGES, 0),
            (EXTINPUT, extinput::DETECT_FALLING_EDGES, 0),
            (EXTINPUT, extinput::DETECT_PULSES, 1),
            (EXTINPUT, extinput::DETECT_PULSE_POLARITY, 1),
            (
                EXTINPUT,
                extinput::DETECT_PULSE_LENGTH,
                (10.0 * i.logic_clock_mhz).round() as u32,
            ),
            (
                USB,
                usb::EARLY_PACKET_DELAY,
                (8.0 * 125.0 * i.usb_clock_mhz).round() as u32,
            ),
        ]);
        r
    }

    /// Sends [`Davis::default_config`] (request 0xC2).
    pub fn send_default_config(&self) -> Result<(), DeviceError> {
        write_registers(&*self.transport, &self.default_config())
    }

    /// Asks the device to restart its timestamps at 0 (MUX TIMESTAMP_RESET 1 then 0 in one
    /// request); the stream then carries a timestamp-reset special event.
    pub fn reset_timestamps(&self) -> Result<(), DeviceError> {
        write_registers(
            &*self.transport,
            &[
                (MUX, mux::TIMESTAMP_RESET, 1),
                (MUX, mux::TIMESTAMP_RESET, 0),
            ],
        )
    }

    /// The registers that stop every part of the camera (step 1 of start, and stop; §1.5).
    pub(super) fn all_off(&self) -> [Register; 10] {
        [
            (DVS, dvs::RUN, 0),
            (APS, aps::RUN, 0),
            (IMU, imu::RUN_ACCELEROMETER, 0),
            (IMU, imu::RUN_GYROSCOPE, 0),
            (IMU, imu::RUN_TEMPERATURE, 0),
            (EXTINPUT, extinput::RUN_DETECTOR, 0),
            (MUX, mux::RUN, 0),
            (MUX, mux::TIMESTAMP_RUN, 0),
            (USB, usb::RUN, 0),
            (MUX, mux::RUN_CHIP, 0),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::super::decode::UsbDecoder;
    use super::super::transport::{ControlRecord, ReplayEnd, ReplayTransport};
    use super::*;
    use neurotac_core::EventBuffer;
    use std::time::{Duration, Instant};

    fn fx2() -> DeviceInfo {
        DeviceInfo {
            product_id: PRODUCT_ID_FX2,
            firmware: FIRMWARE_FX2,
            bus: 1,
            address: 4,
            serial: Some("00000123".into()),
        }
    }

    /// A synthetic stream: reset, then `n` events on a diagonal, one µs apart.
    fn words(n: u16) -> Vec<u8> {
        let mut w = vec![0x0001u16];
        for i in 0..n {
            w.extend([
                0x8000 | i,
                0x1000 | (i % 180),
                0x2000 | (i % 240) | ((i & 1) << 12),
            ]);
        }
        w.iter().flat_map(|w| w.to_le_bytes()).collect()
    }

    fn single_writes(records: &[ControlRecord]) -> Vec<Register> {
        records
            .iter()
            .filter(|r| r.request == VENDOR_REQUEST_FPGA_CONFIG)
            .map(|r| {
                (
                    r.value,
                    r.index,
                    u32::from_be_bytes(r.data[..4].try_into().unwrap()),
                )
            })
            .collect()
    }

    #[test]
    fn open_reads_the_device_and_checks_versions() {
        let davis = Davis::open(ReplayTransport::new(vec![], 64, ReplayEnd::Idle), fx2()).unwrap();
        let i = davis.info();
        assert_eq!(
            (i.chip_name(), i.dvs_size_x, i.dvs_size_y, i.dvs_invert_xy),
            ("DAVIS240C", 240, 180, false)
        );
        assert_eq!(
            (i.logic_version, i.logic_patch, i.usb_clock_mhz),
            (18, 1, 80.0)
        );
        let fx3 = DeviceInfo {
            product_id: PRODUCT_ID_FX3,
            ..fx2()
        };
        assert!(matches!(
            Davis::open(ReplayTransport::new(vec![], 64, ReplayEnd::Idle), fx3),
            Err(DeviceError::Firmware {
                found: 4,
                required: 6
            })
        ));
        for (param, value, check) in [
            (sysinfo::LOGIC_VERSION, 17, "logic"),
            (sysinfo::LOGIC_PATCH, 0, "patch"),
            (sysinfo::CHIP_IDENTIFIER, 4, "chip"),
        ] {
            let t = ReplayTransport::new(vec![], 64, ReplayEnd::Idle);
            t.set_register(SYSINFO, param, value);
            let err = Davis::open(t, fx2()).err().unwrap();
            let ok = match check {
                "logic" => matches!(
                    err,
                    DeviceError::LogicVersion {
                        found: 17,
                        required: 18
                    }
                ),
                "patch" => matches!(
                    err,
                    DeviceError::LogicPatch {
                        found: 0,
                        minimum: 1
                    }
                ),
                _ => matches!(err, DeviceError::UnsupportedChip { found: 4 }),
            };
            assert!(ok, "{check}: {err}");
        }
        let t = ReplayTransport::new(vec![], 64, ReplayEnd::Idle);
        t.set_register(DVS, dvs::SIZE_ROWS, 0);
        assert!(matches!(
            Davis::open(t, fx2()),
            Err(DeviceError::Register {
                module: 1,
                param: 1,
                ..
            })
        ));
        let t = ReplayTransport::new(vec![], 64, ReplayEnd::Idle);
        t.set_register(SYSINFO, sysinfo::CLOCK_DEVIATION, 1010);
        assert!((Davis::open(t, fx2()).unwrap().info().logic_clock_mhz - 80.8).abs() < 1e-9);
    }

    #[test]
    fn default_config_is_sent_big_endian_in_multiple_requests() {
        let davis = Davis::open(ReplayTransport::new(vec![], 64, ReplayEnd::Idle), fx2()).unwrap();
        let config = davis.default_config();
        assert_eq!(config[0], (CHIP, 0, 0x427F));
        assert_eq!(config[21], (CHIP, 21, 0x8410));
        assert!(config.contains(&(DVS, dvs::FILTER_BACKGROUND_ACTIVITY_TIME, 8)));
        assert!(config.contains(&(USB, usb::EARLY_PACKET_DELAY, 80_000)));
        assert!(config.contains(&(APS, aps::EXPOSURE, 120_000)));
        assert!(
            !config.iter().any(|&(m, p, _)| m == CHIP && p == 139),
            "240C has no special pixel control"
        );
        davis.send_default_config().unwrap();
        let writes = davis.transport.writes();
        assert!(
            writes
                .iter()
                .all(|w| w.request == VENDOR_REQUEST_FPGA_CONFIG_MULTIPLE)
        );
        let mut sent = Vec::new();
        for w in &writes {
            assert_eq!(
                w.data.len(),
                6 * usize::from(w.value),
                "wValue = number of entries"
            );
            for e in w.data.chunks_exact(6) {
                sent.push((
                    u16::from(e[0]),
                    u16::from(e[1]),
                    u32::from_be_bytes([e[2], e[3], e[4], e[5]]),
                ));
            }
        }
        assert_eq!(sent, config);
    }

    #[test]
    fn start_and_stop_follow_libcaers_order() {
        let davis = Davis::open(ReplayTransport::new(vec![], 64, ReplayEnd::Idle), fx2()).unwrap();
        let off = davis.all_off().to_vec();
        let mut stream = davis.start(StartOptions::default()).unwrap();
        stream.stop().unwrap();
        let t = &stream.davis.transport;
        assert_eq!(t.halts_cleared(), 1);
        let mut expected = off.clone();
        expected.extend([
            (MUX, mux::RUN_CHIP, 1),
            (USB, usb::RUN, 1),
            (MUX, mux::TIMESTAMP_RUN, 1),
            (MUX, mux::RUN, 1),
            (DVS, dvs::RUN, 1),
            (APS, aps::RUN, 0),
            (IMU, imu::RUN_ACCELEROMETER, 0),
            (IMU, imu::RUN_GYROSCOPE, 0),
            (IMU, imu::RUN_TEMPERATURE, 0),
            (EXTINPUT, extinput::RUN_DETECTOR, 0),
        ]);
        expected.extend(off);
        assert_eq!(single_writes(&t.writes()), expected);
        assert!(matches!(
            stream.next_events(&mut EventBuffer::new(), Duration::ZERO),
            Err(DeviceError::Stopped)
        ));
    }

    #[test]
    fn unplugging_keeps_every_decoded_event_and_ends_with_a_clear_error() {
        let bytes = words(5000);
        let mut whole = EventBuffer::new();
        UsbDecoder::davis240().decode(&bytes, &mut whole);
        // Odd-sized reads: words straddle the transfers.
        let davis = Davis::open(
            ReplayTransport::new(bytes.clone(), 777, ReplayEnd::Unplug),
            fx2(),
        )
        .unwrap();
        let mut stream = davis.start(StartOptions::default()).unwrap();
        let mut got = EventBuffer::new();
        let err = loop {
            match stream.next_events(&mut got, Duration::from_secs(5)) {
                Ok(_) => {}
                Err(e) => break e,
            }
        };
        assert_eq!(got, whole);
        assert!(
            matches!(
                err,
                DeviceError::Disconnected { bytes_received, events_decoded: 5000 } if bytes_received == bytes.len() as u64
            ),
            "{err}"
        );
        assert!(err.to_string().contains("disconnected"));
        assert_eq!(stream.dropped_packets(), 0);
        assert_eq!(stream.decode_stats().timestamp_resets, 1);
        let writes_before = stream.davis.transport.writes().len();
        stream.stop().unwrap();
        assert_eq!(
            stream.davis.transport.writes().len(),
            writes_before,
            "no writes to an unplugged camera"
        );
    }

    #[test]
    fn a_full_ring_drops_packets_and_never_blocks_the_reader() {
        let bytes = words(20_000);
        let transport = ReplayTransport::new(bytes.clone(), 1024, ReplayEnd::Idle);
        let davis = Davis::open(transport, fx2()).unwrap();
        let options = StartOptions {
            ring_buffers: 4,
            buffer_bytes: 1024,
            ..StartOptions::default()
        };
        let mut stream = davis.start(options).unwrap();
        // The consumer sleeps until the reader has read the whole stream.
        let deadline = Instant::now() + Duration::from_secs(10);
        while stream.davis.transport.bytes_played() < bytes.len() && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(5));
        }
        assert_eq!(
            stream.davis.transport.bytes_played(),
            bytes.len(),
            "the reader never waited"
        );
        let transfers = bytes.len().div_ceil(1024) as u64;
        assert_eq!(stream.dropped_packets(), transfers - 4);
        assert_eq!(stream.bytes_received(), bytes.len() as u64);
        let mut got = EventBuffer::new();
        stream
            .next_events(&mut got, Duration::from_millis(50))
            .unwrap();
        // Only the 4 buffered transfers (4 KiB ≈ 680 events) were kept.
        assert!(got.len() > 600 && got.len() < 700, "{}", got.len());
        assert_eq!(
            stream
                .next_events(&mut got, Duration::from_millis(20))
                .unwrap(),
            0
        );
        stream.stop().unwrap();
    }
}
