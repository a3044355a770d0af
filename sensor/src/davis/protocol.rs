//! DAVIS USB protocol constants and register values (davis240.md §1.1–1.5, libcaer 3.3).

/// USB vendor id of every iniVation DVS/DAVIS camera (§1.1).
pub const VENDOR_ID: u16 = 0x152A;
/// Product id of the DAVIS FX2 board (USB 2.0; the classic DAVIS240 A/B/C).
pub const PRODUCT_ID_FX2: u16 = 0x841B;
/// Product id of the DAVIS FX3 board (USB 3.0).
pub const PRODUCT_ID_FX3: u16 = 0x841A;
/// Firmware version required on FX2 (low byte of bcdDevice).
pub const FIRMWARE_FX2: u8 = 4;
/// Firmware version required on FX3.
pub const FIRMWARE_FX3: u8 = 6;
/// FPGA/CPLD logic version required (SYSINFO param 0).
pub const LOGIC_VERSION: u32 = 18;
/// Minimum logic patch (SYSINFO param 7).
pub const LOGIC_PATCH_MIN: u32 = 1;
/// Bulk IN endpoint of the event stream (§1.2).
pub const DATA_ENDPOINT: u8 = 0x82;
/// Vendor request: read or write one register, big-endian u32 data (§1.3).
pub const VENDOR_REQUEST_FPGA_CONFIG: u8 = 0xBF;
/// Vendor request: write several registers, 6 bytes each (u8 module, u8 param, u32 BE value).
pub const VENDOR_REQUEST_FPGA_CONFIG_MULTIPLE: u8 = 0xC2;

/// One register write: `(module, parameter, value)` (§1.3–1.4).
pub type Register = (u16, u16, u32);

/// Module MUX (§1.4).
pub const MUX: u16 = 0;
/// Module DVS.
pub const DVS: u16 = 1;
/// Module APS.
pub const APS: u16 = 2;
/// Module IMU.
pub const IMU: u16 = 3;
/// Module EXTINPUT.
pub const EXTINPUT: u16 = 4;
/// Module BIAS / CHIP (bias params 0–127, chip configuration 128+).
pub const CHIP: u16 = 5;
/// Module SYSINFO (read-only).
pub const SYSINFO: u16 = 6;
/// Module USB.
pub const USB: u16 = 9;

/// MUX parameters.
pub mod mux {
    /// Run the multiplexer.
    pub const RUN: u16 = 0;
    /// Run the timestamp counter.
    pub const TIMESTAMP_RUN: u16 = 1;
    /// Reset the timestamp counter (write 1 then 0).
    pub const TIMESTAMP_RESET: u16 = 2;
    /// Power the chip (biases).
    pub const RUN_CHIP: u16 = 3;
    /// Drop external-input events when USB stalls.
    pub const DROP_EXTINPUT_ON_TRANSFER_STALL: u16 = 4;
    /// Drop DVS events when USB stalls.
    pub const DROP_DVS_ON_TRANSFER_STALL: u16 = 5;
}

/// DVS parameters.
pub mod dvs {
    /// Columns (read-only).
    pub const SIZE_COLUMNS: u16 = 0;
    /// Rows (read-only).
    pub const SIZE_ROWS: u16 = 1;
    /// Orientation (read-only; bit 2 = invert X/Y).
    pub const ORIENTATION_INFO: u16 = 2;
    /// Run the DVS.
    pub const RUN: u16 = 3;
    /// Wait (instead of dropping) when USB stalls.
    pub const WAIT_ON_TRANSFER_STALL: u16 = 4;
    /// External AER control.
    pub const EXTERNAL_AER_CONTROL: u16 = 5;
    /// The logic has the pixel filter.
    pub const HAS_PIXEL_FILTER: u16 = 10;
    /// First pixel-filter row parameter (row k = 11 + 2k, column k = 12 + 2k, k = 0..7).
    pub const FILTER_PIXEL_0_ROW: u16 = 11;
    /// The logic has the background-activity filter.
    pub const HAS_BACKGROUND_ACTIVITY_FILTER: u16 = 30;
    /// Enable the background-activity filter.
    pub const FILTER_BACKGROUND_ACTIVITY: u16 = 31;
    /// Background-activity time (units of 250 µs).
    pub const FILTER_BACKGROUND_ACTIVITY_TIME: u16 = 32;
    /// Enable the refractory filter.
    pub const FILTER_REFRACTORY_PERIOD: u16 = 33;
    /// Refractory time (units of 250 µs).
    pub const FILTER_REFRACTORY_PERIOD_TIME: u16 = 34;
    /// The logic has the ROI filter.
    pub const HAS_ROI_FILTER: u16 = 40;
    /// ROI start column (then start row, end column, end row at 42, 43, 44).
    pub const FILTER_ROI_START_COLUMN: u16 = 41;
    /// The logic has the skip filter.
    pub const HAS_SKIP_FILTER: u16 = 50;
    /// Enable event skipping.
    pub const FILTER_SKIP_EVENTS: u16 = 51;
    /// Skip every N events.
    pub const FILTER_SKIP_EVENTS_EVERY: u16 = 52;
    /// The logic has the polarity filter.
    pub const HAS_POLARITY_FILTER: u16 = 60;
    /// Polarity flatten (then suppress, suppress type at 62, 63).
    pub const FILTER_POLARITY_FLATTEN: u16 = 61;
    /// The logic has statistics counters.
    pub const HAS_STATISTICS: u16 = 80;
}

/// APS parameters.
pub mod aps {
    /// Columns.
    pub const SIZE_COLUMNS: u16 = 0;
    /// Rows.
    pub const SIZE_ROWS: u16 = 1;
    /// Orientation (bit 2 invert X/Y, bit 1 flip X, bit 0 flip Y).
    pub const ORIENTATION_INFO: u16 = 2;
    /// Run the APS.
    pub const RUN: u16 = 4;
    /// Wait when USB stalls.
    pub const WAIT_ON_TRANSFER_STALL: u16 = 5;
    /// The chip has a global shutter.
    pub const HAS_GLOBAL_SHUTTER: u16 = 6;
    /// Use the global shutter.
    pub const GLOBAL_SHUTTER: u16 = 7;
    /// ROI 0 start column (then start row, end column, end row at 9, 10, 11).
    pub const START_COLUMN_0: u16 = 8;
    /// Exposure (ADC clock cycles).
    pub const EXPOSURE: u16 = 12;
    /// Frame interval (ADC clock cycles).
    pub const FRAME_INTERVAL: u16 = 13;
}

/// IMU parameters.
pub mod imu {
    /// IMU type (read-only).
    pub const TYPE: u16 = 0;
    /// Run the accelerometer.
    pub const RUN_ACCELEROMETER: u16 = 2;
    /// Run the gyroscope.
    pub const RUN_GYROSCOPE: u16 = 3;
    /// Run the temperature sensor.
    pub const RUN_TEMPERATURE: u16 = 4;
    /// Sample-rate divider.
    pub const SAMPLE_RATE_DIVIDER: u16 = 5;
    /// Accelerometer low-pass filter.
    pub const ACCEL_DLPF: u16 = 6;
    /// Accelerometer full scale.
    pub const ACCEL_FULL_SCALE: u16 = 7;
    /// Gyroscope low-pass filter.
    pub const GYRO_DLPF: u16 = 9;
    /// Gyroscope full scale.
    pub const GYRO_FULL_SCALE: u16 = 10;
}

/// External-input parameters.
pub mod extinput {
    /// Run the detector.
    pub const RUN_DETECTOR: u16 = 0;
    /// Detect rising edges.
    pub const DETECT_RISING_EDGES: u16 = 1;
    /// Detect falling edges.
    pub const DETECT_FALLING_EDGES: u16 = 2;
    /// Detect pulses.
    pub const DETECT_PULSES: u16 = 3;
    /// Pulse polarity.
    pub const DETECT_PULSE_POLARITY: u16 = 4;
    /// Pulse length (logic clock cycles).
    pub const DETECT_PULSE_LENGTH: u16 = 5;
}

/// SYSINFO parameters (read-only).
pub mod sysinfo {
    /// Logic version.
    pub const LOGIC_VERSION: u16 = 0;
    /// Chip identifier (0/1/2 = DAVIS240A/B/C).
    pub const CHIP_IDENTIFIER: u16 = 1;
    /// The device is the timestamp master.
    pub const DEVICE_IS_MASTER: u16 = 2;
    /// Logic clock (MHz).
    pub const LOGIC_CLOCK: u16 = 3;
    /// ADC clock (MHz).
    pub const ADC_CLOCK: u16 = 4;
    /// USB clock (MHz).
    pub const USB_CLOCK: u16 = 5;
    /// Clock deviation (actual = nominal × deviation / 1000).
    pub const CLOCK_DEVIATION: u16 = 6;
    /// Logic patch level.
    pub const LOGIC_PATCH: u16 = 7;
}

/// USB parameters.
pub mod usb {
    /// Run the USB data path.
    pub const RUN: u16 = 0;
    /// Early packet delay (FPGA cycles).
    pub const EARLY_PACKET_DELAY: u16 = 1;
}

/// Type of a coarse/fine bias transistor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BiasType {
    /// N-type, normal.
    N,
    /// P-type, normal.
    P,
    /// N-type, cascode.
    NCascode,
}

/// The 16-bit word of an enabled coarse/fine bias at normal current level (§1.4): bit 0 enabled,
/// bit 1 N-type, bit 2 normal (not cascode), bit 3 normal current level, bits 4–11 fine,
/// bits 12–14 coarse.
pub const fn coarse_fine_bias(kind: BiasType, coarse: u8, fine: u8) -> u16 {
    let sex_n = matches!(kind, BiasType::N | BiasType::NCascode) as u16;
    let normal = !matches!(kind, BiasType::NCascode) as u16;
    1 | sex_n << 1 | normal << 2 | 1 << 3 | (fine as u16) << 4 | ((coarse & 7) as u16) << 12
}

/// The 16-bit word of a shifted-source bias (§1.4): bits 0–1 operating mode, bits 2–3 voltage
/// level, bits 4–9 ref, bits 10–15 reg.
pub const fn shifted_source_bias(mode: u8, level: u8, reference: u8, regulator: u8) -> u16 {
    (mode & 3) as u16
        | ((level & 3) as u16) << 2
        | ((reference & 63) as u16) << 4
        | ((regulator & 63) as u16) << 10
}

/// libcaer's DAVIS240 default biases, params 0–21 of module [`CHIP`] (§1.4 table).
pub const DAVIS240_BIASES: [u16; 22] = [
    coarse_fine_bias(BiasType::N, 4, 39),         // 0 DIFFBN
    coarse_fine_bias(BiasType::N, 5, 255),        // 1 ONBN
    coarse_fine_bias(BiasType::N, 4, 0),          // 2 OFFBN
    coarse_fine_bias(BiasType::NCascode, 5, 185), // 3 APSCASEPC
    coarse_fine_bias(BiasType::NCascode, 5, 115), // 4 DIFFCASBNC
    coarse_fine_bias(BiasType::N, 6, 219),        // 5 APSROSFBN
    coarse_fine_bias(BiasType::N, 5, 164),        // 6 LOCALBUFBN
    coarse_fine_bias(BiasType::N, 6, 144),        // 7 PIXINVBN
    coarse_fine_bias(BiasType::P, 2, 58),         // 8 PRBP
    coarse_fine_bias(BiasType::P, 1, 16),         // 9 PRSFBP
    coarse_fine_bias(BiasType::P, 4, 25),         // 10 REFRBP
    coarse_fine_bias(BiasType::N, 6, 91),         // 11 AEPDBN
    coarse_fine_bias(BiasType::N, 5, 49),         // 12 LCOLTIMEOUTBN
    coarse_fine_bias(BiasType::P, 4, 80),         // 13 AEPUXBP
    coarse_fine_bias(BiasType::P, 7, 152),        // 14 AEPUYBP
    coarse_fine_bias(BiasType::N, 5, 255),        // 15 IFTHRBN
    coarse_fine_bias(BiasType::N, 5, 255),        // 16 IFREFRBN
    coarse_fine_bias(BiasType::N, 7, 215),        // 17 PADFOLLBN
    coarse_fine_bias(BiasType::N, 6, 253),        // 18 APSOVERFLOWLEVELBN
    coarse_fine_bias(BiasType::N, 5, 254),        // 19 BIASBUFFER
    shifted_source_bias(0, 0, 1, 33),             // 20 SSP
    shifted_source_bias(0, 0, 1, 33),             // 21 SSN
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_biases_match_the_libcaer_words() {
        let words = [
            0x427F, 0x5FFF, 0x400F, 0x5B9B, 0x573B, 0x6DBF, 0x5A4F, 0x690F, 0x23AD, 0x110D, 0x419D,
            0x65BF, 0x531F, 0x450D, 0x798D, 0x5FFF, 0x5FFF, 0x7D7F, 0x6FDF, 0x5FEF, 0x8410, 0x8410,
        ];
        assert_eq!(DAVIS240_BIASES, words);
    }
}
