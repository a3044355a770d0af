//! The raw USB calls the DAVIS driver makes, behind [`Transport`], with two implementations:
//! [`RusbTransport`] (a real camera through rusb and a vendored libusb) and [`ReplayTransport`]
//! (a recorded byte stream played back as if it came from a camera, with a DAVIS240C's
//! registers). Everything above these calls — register encoding, configuration, the start/stop
//! order, the reader thread, the ring, decoding — is the same code for both.

use super::protocol::{DATA_ENDPOINT, PRODUCT_ID_FX2, PRODUCT_ID_FX3, VENDOR_ID};
use crate::error::DeviceError;
use std::collections::HashMap;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

/// Timeout of control transfers (as neuromorphic-drivers: 1 s; davis240.md §1.3).
pub const CONTROL_TIMEOUT: Duration = Duration::from_secs(1);

/// Why a USB call failed, as far as the driver needs to know.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TransportError {
    /// Nothing arrived within the timeout (not an error for bulk reads).
    Timeout,
    /// The device is gone (unplugged).
    Disconnected,
    /// Any other failure, with the USB library's message.
    Other(String),
}

impl std::fmt::Display for TransportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Timeout => write!(f, "timed out"),
            Self::Disconnected => write!(f, "device disconnected"),
            Self::Other(m) => write!(f, "{m}"),
        }
    }
}

/// The raw USB operations of a DAVIS camera (davis240.md §1.2–1.3). Vendor control requests go
/// to the device (bmRequestType `0x40` out, `0xC0` in).
pub trait Transport: Send + Sync + 'static {
    /// A vendor IN control transfer; returns the bytes read into `buf`.
    fn control_in(
        &self,
        request: u8,
        value: u16,
        index: u16,
        buf: &mut [u8],
    ) -> Result<usize, TransportError>;

    /// A vendor OUT control transfer; returns the bytes written.
    fn control_out(
        &self,
        request: u8,
        value: u16,
        index: u16,
        data: &[u8],
    ) -> Result<usize, TransportError>;

    /// A bulk IN read from `endpoint`; returns the bytes read (0 or [`TransportError::Timeout`]
    /// when nothing came within `timeout`).
    fn bulk_in(
        &self,
        endpoint: u8,
        buf: &mut [u8],
        timeout: Duration,
    ) -> Result<usize, TransportError>;

    /// Clears a halt on `endpoint`.
    fn clear_halt(&self, endpoint: u8) -> Result<(), TransportError>;
}

/// One DAVIS camera seen on the bus (from its device descriptor; davis240.md §1.1).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeviceInfo {
    /// USB product id: [`PRODUCT_ID_FX2`] or [`PRODUCT_ID_FX3`].
    pub product_id: u16,
    /// Firmware version: the low byte of `bcdDevice`.
    pub firmware: u8,
    /// USB bus number.
    pub bus: u8,
    /// USB device address.
    pub address: u8,
    /// Serial number (ASCII, at most 8 characters), when it could be read.
    pub serial: Option<String>,
}

impl DeviceInfo {
    /// `"FX2"` or `"FX3"`.
    pub fn board(&self) -> &'static str {
        if self.product_id == PRODUCT_ID_FX3 {
            "FX3"
        } else {
            "FX2"
        }
    }
}

fn usb_error(operation: impl Into<String>, e: rusb::Error) -> DeviceError {
    DeviceError::Usb {
        operation: operation.into(),
        message: e.to_string(),
    }
}

fn transport_error(e: rusb::Error) -> TransportError {
    match e {
        rusb::Error::Timeout => TransportError::Timeout,
        rusb::Error::NoDevice => TransportError::Disconnected,
        other => TransportError::Other(other.to_string()),
    }
}

/// A libusb context of our own: unlike rusb's global context, whose initialisation failure is a
/// panic, a failure here is [`DeviceError::UsbUnavailable`].
fn context() -> Result<rusb::Context, DeviceError> {
    use rusb::UsbContext as _;
    let context = rusb::Context::new().map_err(|e| DeviceError::UsbUnavailable {
        message: e.to_string(),
    })?;
    // Touch the device list once so that an unusable USB stack fails here.
    context.devices().map_err(|e| DeviceError::UsbUnavailable {
        message: e.to_string(),
    })?;
    Ok(context)
}

/// The DAVIS cameras attached (VID 0x152A, PID 0x841B or 0x841A; davis240.md §1.1), FX2 boards
/// first. An empty list when none is attached; [`DeviceError::UsbUnavailable`] when this machine
/// has no usable USB stack (e.g. a container without `/dev/bus/usb`).
pub fn list_devices() -> Result<Vec<DeviceInfo>, DeviceError> {
    use rusb::UsbContext as _;
    let devices = context()?
        .devices()
        .map_err(|e| usb_error("listing devices", e))?;
    let mut found = Vec::new();
    for device in devices.iter() {
        let Ok(desc) = device.device_descriptor() else {
            continue;
        };
        let pid = desc.product_id();
        if desc.vendor_id() != VENDOR_ID || (pid != PRODUCT_ID_FX2 && pid != PRODUCT_ID_FX3) {
            continue;
        }
        let version = desc.device_version();
        let firmware = (version.minor() << 4) | version.sub_minor();
        let serial = device
            .open()
            .ok()
            .and_then(|h| h.read_serial_number_string_ascii(&desc).ok());
        found.push(DeviceInfo {
            product_id: pid,
            firmware,
            bus: device.bus_number(),
            address: device.address(),
            serial,
        });
    }
    found.sort_by_key(|d| (d.product_id != PRODUCT_ID_FX2, d.bus, d.address));
    Ok(found)
}

/// A DAVIS camera opened through rusb (libusb built from source by the `vendored` feature;
/// davis240.md §1.1–1.3, §7 pitfall 9).
pub struct RusbTransport {
    handle: rusb::DeviceHandle<rusb::Context>,
}

impl RusbTransport {
    /// Opens the first DAVIS camera ([`list_devices`] order), selects configuration 1 and claims
    /// interface 0 (davis240.md §1.1). [`DeviceError::NotFound`] when there is none.
    pub fn open_first() -> Result<(Self, DeviceInfo), DeviceError> {
        let info = list_devices()?
            .into_iter()
            .next()
            .ok_or(DeviceError::NotFound)?;
        Ok((Self::open(&info)?, info))
    }

    /// Opens the camera at `info`'s bus and address.
    pub fn open(info: &DeviceInfo) -> Result<Self, DeviceError> {
        use rusb::UsbContext as _;
        let devices = context()?
            .devices()
            .map_err(|e| usb_error("listing devices", e))?;
        let device = devices
            .iter()
            .find(|d| d.bus_number() == info.bus && d.address() == info.address)
            .ok_or(DeviceError::NotFound)?;
        let handle = device.open().map_err(|e| usb_error("open", e))?;
        if handle.active_configuration().ok() != Some(1) {
            handle
                .set_active_configuration(1)
                .map_err(|e| usb_error("set configuration 1", e))?;
        }
        handle
            .claim_interface(0)
            .map_err(|e| usb_error("claim interface 0", e))?;
        Ok(Self { handle })
    }
}

impl Transport for RusbTransport {
    fn control_in(
        &self,
        request: u8,
        value: u16,
        index: u16,
        buf: &mut [u8],
    ) -> Result<usize, TransportError> {
        self.handle
            .read_control(0xC0, request, value, index, buf, CONTROL_TIMEOUT)
            .map_err(transport_error)
    }

    fn control_out(
        &self,
        request: u8,
        value: u16,
        index: u16,
        data: &[u8],
    ) -> Result<usize, TransportError> {
        self.handle
            .write_control(0x40, request, value, index, data, CONTROL_TIMEOUT)
            .map_err(transport_error)
    }

    fn bulk_in(
        &self,
        endpoint: u8,
        buf: &mut [u8],
        timeout: Duration,
    ) -> Result<usize, TransportError> {
        self.handle
            .read_bulk(endpoint, buf, timeout)
            .map_err(transport_error)
    }

    fn clear_halt(&self, endpoint: u8) -> Result<(), TransportError> {
        self.handle.clear_halt(endpoint).map_err(transport_error)
    }
}

/// A control transfer a [`ReplayTransport`] received.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ControlRecord {
    /// bRequest.
    pub request: u8,
    /// wValue.
    pub value: u16,
    /// wIndex.
    pub index: u16,
    /// The data sent.
    pub data: Vec<u8>,
}

/// What a [`ReplayTransport`] does once its bytes are played.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReplayEnd {
    /// Report [`TransportError::Disconnected`], as an unplugged camera does.
    Unplug,
    /// Keep timing out, as an idle camera does.
    Idle,
}

/// A recorded DAVIS USB byte stream played back through the [`Transport`] calls.
///
/// Register reads answer from a register map (by default a DAVIS240C on FX2 with logic 18 patch
/// 1, see [`ReplayTransport::davis240c_registers`]); register writes are recorded
/// ([`ReplayTransport::writes`]); bulk reads on endpoint `0x82` hand out the recorded bytes in
/// pieces of at most `chunk` bytes, then end as [`ReplayEnd`] says.
pub struct ReplayTransport {
    bytes: Vec<u8>,
    chunk: usize,
    position: AtomicUsize,
    end: ReplayEnd,
    registers: Mutex<HashMap<(u16, u16), u32>>,
    writes: Mutex<Vec<ControlRecord>>,
    halts_cleared: AtomicUsize,
}

impl ReplayTransport {
    /// Plays `bytes` in reads of at most `chunk` bytes, then ends as `end` says.
    pub fn new(bytes: Vec<u8>, chunk: usize, end: ReplayEnd) -> Self {
        Self {
            bytes,
            chunk: chunk.max(1),
            position: AtomicUsize::new(0),
            end,
            registers: Mutex::new(Self::davis240c_registers()),
            writes: Mutex::new(Vec::new()),
            halts_cleared: AtomicUsize::new(0),
        }
    }

    /// The registers of a DAVIS240C (FX2, logic 18 patch 1, master, 240 × 180, logic 80 MHz, ADC
    /// 30 MHz, USB 80 MHz, clock deviation 1000, every DVS filter present, no IMU).
    pub fn davis240c_registers() -> HashMap<(u16, u16), u32> {
        use super::protocol::{APS, IMU};
        use super::protocol::{DVS, SYSINFO, aps, dvs, sysinfo};
        use crate::geometry::{DAVIS240_HEIGHT, DAVIS240_WIDTH};
        let (columns, rows) = (u32::from(DAVIS240_WIDTH), u32::from(DAVIS240_HEIGHT));
        HashMap::from([
            ((SYSINFO, sysinfo::LOGIC_VERSION), 18),
            ((SYSINFO, sysinfo::CHIP_IDENTIFIER), 2),
            ((SYSINFO, sysinfo::DEVICE_IS_MASTER), 1),
            ((SYSINFO, sysinfo::LOGIC_CLOCK), 80),
            ((SYSINFO, sysinfo::ADC_CLOCK), 30),
            ((SYSINFO, sysinfo::USB_CLOCK), 80),
            ((SYSINFO, sysinfo::CLOCK_DEVIATION), 1000),
            ((SYSINFO, sysinfo::LOGIC_PATCH), 1),
            ((DVS, dvs::SIZE_COLUMNS), columns),
            ((DVS, dvs::SIZE_ROWS), rows),
            ((DVS, dvs::ORIENTATION_INFO), 0),
            ((DVS, dvs::HAS_PIXEL_FILTER), 1),
            ((DVS, dvs::HAS_BACKGROUND_ACTIVITY_FILTER), 1),
            ((DVS, dvs::HAS_ROI_FILTER), 1),
            ((DVS, dvs::HAS_SKIP_FILTER), 1),
            ((DVS, dvs::HAS_POLARITY_FILTER), 1),
            ((DVS, dvs::HAS_STATISTICS), 1),
            ((APS, aps::SIZE_COLUMNS), columns),
            ((APS, aps::SIZE_ROWS), rows),
            ((APS, aps::ORIENTATION_INFO), 0),
            ((APS, aps::HAS_GLOBAL_SHUTTER), 1),
            ((IMU, 0), 0),
        ])
    }

    /// Sets one register (e.g. to simulate another firmware or chip).
    pub fn set_register(&self, module: u16, param: u16, value: u32) {
        self.registers
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .insert((module, param), value);
    }

    /// Every OUT control transfer received, in order.
    pub fn writes(&self) -> Vec<ControlRecord> {
        self.writes
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .clone()
    }

    /// How many times the data endpoint's halt was cleared.
    pub fn halts_cleared(&self) -> usize {
        self.halts_cleared.load(Ordering::Relaxed)
    }

    /// Bytes handed out so far.
    pub fn bytes_played(&self) -> usize {
        self.position.load(Ordering::Relaxed).min(self.bytes.len())
    }
}

impl Transport for ReplayTransport {
    fn control_in(
        &self,
        request: u8,
        value: u16,
        index: u16,
        buf: &mut [u8],
    ) -> Result<usize, TransportError> {
        if request != super::protocol::VENDOR_REQUEST_FPGA_CONFIG || buf.len() < 4 {
            return Err(TransportError::Other(format!(
                "unexpected IN request {request:#04x}"
            )));
        }
        let registers = self.registers.lock().unwrap_or_else(|p| p.into_inner());
        let v = registers.get(&(value, index)).copied().unwrap_or(0);
        buf[..4].copy_from_slice(&v.to_be_bytes());
        Ok(4)
    }

    fn control_out(
        &self,
        request: u8,
        value: u16,
        index: u16,
        data: &[u8],
    ) -> Result<usize, TransportError> {
        self.writes
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .push(ControlRecord {
                request,
                value,
                index,
                data: data.to_vec(),
            });
        Ok(data.len())
    }

    fn bulk_in(
        &self,
        endpoint: u8,
        buf: &mut [u8],
        timeout: Duration,
    ) -> Result<usize, TransportError> {
        if endpoint != DATA_ENDPOINT {
            return Err(TransportError::Other(format!(
                "unexpected endpoint {endpoint:#04x}"
            )));
        }
        let n = self.chunk.min(buf.len());
        let start = self.position.fetch_add(n, Ordering::Relaxed);
        if start >= self.bytes.len() {
            return match self.end {
                ReplayEnd::Unplug => Err(TransportError::Disconnected),
                ReplayEnd::Idle => {
                    std::thread::sleep(timeout.min(Duration::from_millis(5)));
                    Err(TransportError::Timeout)
                }
            };
        }
        let end = (start + n).min(self.bytes.len());
        buf[..end - start].copy_from_slice(&self.bytes[start..end]);
        Ok(end - start)
    }

    fn clear_halt(&self, endpoint: u8) -> Result<(), TransportError> {
        if endpoint == DATA_ENDPOINT {
            self.halts_cleared.fetch_add(1, Ordering::Relaxed);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn listing_without_a_camera_is_empty_or_usb_unavailable_never_a_panic() {
        // No DAVIS is attached to a build machine; containers often have no USB stack at all.
        match list_devices() {
            Ok(devices) => assert!(devices.is_empty(), "{devices:?}"),
            Err(e) => assert!(matches!(e, DeviceError::UsbUnavailable { .. }), "{e}"),
        }
        assert!(matches!(
            RusbTransport::open_first(),
            Err(DeviceError::NotFound | DeviceError::UsbUnavailable { .. })
        ));
    }
}
