//! The DAVIS USB event-stream decoder (davis240.md §1.6–1.7, libcaer 3.3
//! `davisCommonEventTranslator` semantics).
//!
//! The device sends little-endian 16-bit words. Bit 15 set: a timestamp word (low 15 bits of the
//! µs clock). Otherwise `code = bits 14–12`, `data = bits 11–0`:
//!
//! | code | word | decoder action |
//! |---|---|---|
//! | 0 | special event, `data` = type | timestamp reset (type 1) restarts time at 0; external input, IMU and APS frame markers become [`SpecialEvent`]s |
//! | 1 | Y address | `last_y = data` if `data < size_y`, else ignored (counted) |
//! | 2, 3 | X address, polarity = `code & 1` | one event `(t, x = data, y = last_y)` if `data < size_x`, else dropped (counted) |
//! | 4 | APS ADC sample | skipped (counted) |
//! | 5, 6 | misc 8/10-bit (IMU bytes, APS ROI, exposure) | skipped (counted) |
//! | 7 | timestamp wrap, `data` = multiplier N | `wrap_add += N · 2¹⁵`; past 2³¹ − 1 a "big wrap" into the 64-bit time |
//!
//! Event time = `(wrap_overflow << 31) | current` µs since the last device timestamp reset. Every
//! piece of state (time, last row, an odd trailing byte) persists across chunks, so a stream may
//! be cut anywhere.

use crate::geometry::{DAVIS240_HEIGHT, DAVIS240_WIDTH};
use neurotac_core::EventBuffer;

/// Words decoded per inner block; events of a block go to fixed scratch arrays first.
const BLOCK: usize = 4096;

/// Geometry of the pixel array as the device reports it (DVS params 0, 1, 2; davis240.md §1.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DecoderConfig {
    /// Columns (DVS param 0): 240 on a DAVIS240.
    pub size_x: u16,
    /// Rows (DVS param 1): 180 on a DAVIS240.
    pub size_y: u16,
    /// DVS ORIENTATION_INFO bit 2: swap the X and Y addresses (0 on a DAVIS240).
    pub invert_xy: bool,
}

impl DecoderConfig {
    /// The DAVIS240 (A/B/C): 240 × 180, no X/Y swap.
    pub const DAVIS240: Self = Self {
        size_x: DAVIS240_WIDTH,
        size_y: DAVIS240_HEIGHT,
        invert_xy: false,
    };
}

impl Default for DecoderConfig {
    /// [`DecoderConfig::DAVIS240`].
    fn default() -> Self {
        Self::DAVIS240
    }
}

/// Kind of a special (non-pixel) event (davis240.md §1.6, special types of code 0, plus the
/// host-side big wrap of §1.7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SpecialKind {
    /// Special type 1: the device clock restarted at 0.
    TimestampReset,
    /// A wrap word carried the 31-bit time past 2³¹ − 1 (libcaer's TIMESTAMP_WRAP).
    TimestampBigWrap,
    /// Special type 2: external input, falling edge.
    ExternalInputFalling,
    /// Special type 3: external input, rising edge.
    ExternalInputRising,
    /// Special type 4: external input pulse.
    ExternalInputPulse,
    /// Special type 5: start of an IMU sample.
    ImuStart,
    /// Special type 7: end of an IMU sample.
    ImuEnd,
    /// Special type 8 (global shutter, `true`) or 9 (rolling shutter, `false`): APS frame start.
    ApsFrameStart {
        /// Global-shutter frame.
        global_shutter: bool,
    },
    /// Special type 10: APS frame end.
    ApsFrameEnd,
    /// Special type 11: APS reset-column start.
    ApsResetColumnStart,
    /// Special type 12: APS signal-column start.
    ApsSignalColumnStart,
    /// Special type 13: APS column end.
    ApsColumnEnd,
    /// Special type 14: APS exposure start.
    ApsExposureStart,
    /// Special type 15: APS exposure end.
    ApsExposureEnd,
    /// Special type 16: external generator, falling edge.
    ExternalGeneratorFalling,
    /// Special type 17: external generator, rising edge.
    ExternalGeneratorRising,
    /// Any other special type (0 = reserved, 6, 18+): ignored by libcaer.
    Unknown(u16),
}

impl SpecialKind {
    fn from_type(data: u16) -> Self {
        match data {
            1 => Self::TimestampReset,
            2 => Self::ExternalInputFalling,
            3 => Self::ExternalInputRising,
            4 => Self::ExternalInputPulse,
            5 => Self::ImuStart,
            7 => Self::ImuEnd,
            8 => Self::ApsFrameStart {
                global_shutter: true,
            },
            9 => Self::ApsFrameStart {
                global_shutter: false,
            },
            10 => Self::ApsFrameEnd,
            11 => Self::ApsResetColumnStart,
            12 => Self::ApsSignalColumnStart,
            13 => Self::ApsColumnEnd,
            14 => Self::ApsExposureStart,
            15 => Self::ApsExposureEnd,
            16 => Self::ExternalGeneratorFalling,
            17 => Self::ExternalGeneratorRising,
            other => Self::Unknown(other),
        }
    }
}

/// A special event with the device time it happened at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SpecialEvent {
    /// Time (µs, same clock as the pixel events; for a reset: 0).
    pub t: i64,
    /// What happened.
    pub kind: SpecialKind,
}

/// Counters of everything the decoder saw besides the events it produced.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DecodeStats {
    /// 16-bit words decoded.
    pub words: u64,
    /// Polarity events produced.
    pub events: u64,
    /// X words with `x ≥ size_x`: dropped (libcaer drops them too).
    pub dropped_x_out_of_range: u64,
    /// Y words with `y ≥ size_y`: ignored, the previous row stays current.
    pub ignored_y_out_of_range: u64,
    /// Events earlier than the event before them (libcaer only logs such timestamps); the
    /// events keep the stream's order. The drop at a timestamp reset is not counted.
    pub timestamps_backwards: u64,
    /// Timestamp-reset specials.
    pub timestamp_resets: u64,
    /// Big wraps past 2³¹ µs.
    pub big_wraps: u64,
    /// Special events other than timestamp resets (external input, IMU and APS markers, unknown).
    pub specials: u64,
    /// APS ADC samples (code 4), skipped.
    pub aps_samples: u64,
    /// Misc 8/10-bit words (code 5 and 6: IMU bytes, APS ROI, exposure), skipped.
    pub misc_words: u64,
}

/// Words per run checked at once for rare words.
const RUN: usize = 32;

/// Fixed scratch for one block (allocated once per decoder).
struct Scratch {
    /// The block's words.
    words: [u16; BLOCK],
    /// Event times.
    t: [i64; BLOCK],
    /// The X word of each event (`x` = low 12 bits, polarity = bit 12) and, in the high 16 bits,
    /// its row.
    xy: [u32; BLOCK],
}

/// `true` for the words of the rare path: special (code 0), APS ADC (4), misc (5, 6) and wrap
/// (7), i.e. `w < 0x1000` or `0x4000 ≤ w < 0x8000`. Y, X and timestamp words are not rare.
#[inline(always)]
fn is_rare(w: u16) -> bool {
    (w.wrapping_sub(0x1000) >= 0x3000) & (w < 0x8000)
}

/// 1 for the X-word kinds (`w >> 12` = 2 or 3).
const IS_X: [u8; 16] = [0, 0, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0];

/// The decoder state the hot loop keeps in registers.
struct StepState {
    now: i64,
    wrap_base: i64,
    last_y: u16,
    n: usize,
}

/// One timestamp, Y or X word (davis240.md §1.6–1.7), without data-dependent branches: the event
/// slot is always written and the count advances only for an X word.
#[inline(always)]
fn step<const CHECK_RANGE: bool>(
    w: u16,
    st: &mut StepState,
    t: &mut [i64; BLOCK],
    xy: &mut [u32; BLOCK],
    size: (u16, u16),
) {
    let kind = usize::from(w >> 12);
    let data = w & 0x0FFF;
    let candidate = st.wrap_base + i64::from(w & 0x7FFF);
    st.now = if (w as i16) < 0 { candidate } else { st.now };
    let is_y = kind == 1 && (!CHECK_RANGE || data < size.1);
    st.last_y = if is_y { data } else { st.last_y };
    let slot = st.n & (BLOCK - 1);
    t[slot] = st.now;
    xy[slot] = u32::from(w) | u32::from(st.last_y) << 16;
    let x_ok = !CHECK_RANGE || data < size.0;
    st.n += usize::from(IS_X[kind]) & usize::from(x_ok);
}

/// Decoder of the DAVIS USB word stream into events (davis240.md §1.6–1.7).
///
/// Feed byte chunks of any length with [`UsbDecoder::decode`]; events are appended to an
/// [`EventBuffer`] that the caller reuses. After warm-up (the first call allocates one fixed
/// scratch block) decoding allocates nothing but the growth of the output buffer.
///
/// ```
/// use neurotac_core::EventBuffer;
/// use neurotac_sensor::davis::UsbDecoder;
/// // reset, timestamp 5 µs, row 7, column 10 ON, column 11 OFF
/// let words: [u16; 5] = [0x0001, 0x8005, 0x1007, 0x300A, 0x200B];
/// let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
/// let (mut dec, mut out) = (UsbDecoder::davis240(), EventBuffer::new());
/// dec.decode(&bytes[..3], &mut out); // any split works
/// dec.decode(&bytes[3..], &mut out);
/// assert_eq!((out.t, out.x, out.y, out.polarity), (vec![5, 5], vec![10, 11], vec![7, 7], vec![true, false]));
/// ```
pub struct UsbDecoder {
    config: DecoderConfig,
    /// `wrap_overflow << 31`.
    base: i64,
    /// libcaer's `wrapAdd` (multiple of 2¹⁵, < 2³¹).
    wrap_add: i64,
    /// Full 64-bit time of the most recent timestamp/wrap word.
    now: i64,
    last_y: u16,
    /// Odd trailing byte of the previous chunk.
    pending: Option<u8>,
    stats: DecodeStats,
    scratch: Option<Box<Scratch>>,
    /// Time of the last event produced (`i64::MIN` before the first and after a reset).
    last_event_t: i64,
    /// Event indices (within the current block) at which a timestamp reset happened.
    resets: Vec<usize>,
}

impl UsbDecoder {
    /// A decoder for the given geometry, in the state of a freshly reset device (time 0, row 0).
    pub fn new(config: DecoderConfig) -> Self {
        Self {
            config,
            base: 0,
            wrap_add: 0,
            now: 0,
            last_y: 0,
            pending: None,
            stats: DecodeStats::default(),
            scratch: None,
            last_event_t: i64::MIN,
            resets: Vec::new(),
        }
    }

    /// A decoder for a DAVIS240 ([`DecoderConfig::DAVIS240`]).
    pub fn davis240() -> Self {
        Self::new(DecoderConfig::DAVIS240)
    }

    /// The geometry this decoder checks addresses against.
    pub fn config(&self) -> DecoderConfig {
        self.config
    }

    /// Counters since construction.
    pub fn stats(&self) -> DecodeStats {
        self.stats
    }

    /// `true` when an odd byte of the last chunk waits for its partner.
    pub fn has_pending_byte(&self) -> bool {
        self.pending.is_some()
    }

    /// The current 64-bit device time (µs).
    pub fn now_us(&self) -> i64 {
        self.now
    }

    /// Decodes `bytes` (any length, continuing the previous chunk) and appends the polarity events
    /// to `out`. Special events are counted in [`UsbDecoder::stats`] only.
    pub fn decode(&mut self, bytes: &[u8], out: &mut EventBuffer) {
        self.decode_inner(bytes, out, None);
    }

    /// As [`UsbDecoder::decode`], and also appends every special event to `specials`.
    pub fn decode_with_specials(
        &mut self,
        bytes: &[u8],
        out: &mut EventBuffer,
        specials: &mut Vec<SpecialEvent>,
    ) {
        self.decode_inner(bytes, out, Some(specials));
    }

    fn decode_inner(
        &mut self,
        mut bytes: &[u8],
        out: &mut EventBuffer,
        mut specials: Option<&mut Vec<SpecialEvent>>,
    ) {
        if let Some(lo) = self.pending.take() {
            match bytes.split_first() {
                Some((&hi, rest)) => {
                    self.decode_words(&[lo, hi], out, specials.as_deref_mut());
                    bytes = rest;
                }
                None => {
                    self.pending = Some(lo);
                    return;
                }
            }
        }
        let even = bytes.len() & !1;
        for block in bytes[..even].chunks(2 * BLOCK) {
            self.decode_words(block, out, specials.as_deref_mut());
        }
        if even < bytes.len() {
            self.pending = Some(bytes[even]);
        }
    }

    /// Decodes at most `BLOCK` whole words in three passes: words and out-of-range counts
    /// (vectorised), the sequential state machine, then backwards-time counts and the split of
    /// the events into columns (vectorised).
    fn decode_words(
        &mut self,
        bytes: &[u8],
        out: &mut EventBuffer,
        specials: Option<&mut Vec<SpecialEvent>>,
    ) {
        debug_assert!(bytes.len().is_multiple_of(2) && bytes.len() <= 2 * BLOCK);
        let mut s = self.scratch.take().unwrap_or_else(|| {
            Box::new(Scratch {
                words: [0; BLOCK],
                t: [0; BLOCK],
                xy: [0; BLOCK],
            })
        });
        let n_words = (bytes.len() / 2).min(BLOCK);
        for (w, pair) in s.words[..n_words].iter_mut().zip(bytes.chunks_exact(2)) {
            *w = u16::from_le_bytes([pair[0], pair[1]]);
        }
        let out_of_range = self.count_out_of_range(&s.words[..n_words]);
        self.resets.clear();
        let n = if out_of_range {
            self.decode_block::<true>(n_words, &mut s, specials)
        } else {
            self.decode_block::<false>(n_words, &mut s, specials)
        };
        self.count_backwards(&s.t[..n]);
        let xy = &s.xy[..n];
        let column = xy.iter().map(|a| (a & 0x0FFF) as u16);
        let row = xy.iter().map(|a| (a >> 16) as u16);
        out.t.extend_from_slice(&s.t[..n]);
        if self.config.invert_xy {
            out.x.extend(row);
            out.y.extend(column);
        } else {
            out.x.extend(column);
            out.y.extend(row);
        }
        out.polarity.extend(xy.iter().map(|a| a & 0x1000 != 0));
        self.stats.words += n_words as u64;
        self.stats.events += n as u64;
        self.scratch = Some(s);
    }

    /// Counts the X words dropped and Y words ignored for out-of-range addresses; `true` if any.
    fn count_out_of_range(&mut self, words: &[u16]) -> bool {
        let (size_x, size_y) = (self.config.size_x, self.config.size_y);
        let (mut dropped_x, mut ignored_y) = (0u32, 0u32);
        for &w in words {
            let (kind, data) = (w >> 12, w & 0x0FFF);
            dropped_x += u32::from((kind >> 1 == 1) & (data >= size_x));
            ignored_y += u32::from((kind == 1) & (data >= size_y));
        }
        self.stats.dropped_x_out_of_range += u64::from(dropped_x);
        self.stats.ignored_y_out_of_range += u64::from(ignored_y);
        dropped_x + ignored_y > 0
    }

    /// Counts events earlier than the one before them, except across a timestamp reset.
    fn count_backwards(&mut self, t: &[i64]) {
        fn drops(previous: i64, t: &[i64]) -> u64 {
            let first = t.first().map_or(0, |&f| u64::from(f < previous));
            first + t.windows(2).filter(|w| w[1] < w[0]).count() as u64
        }
        let (mut previous, mut start) = (self.last_event_t, 0);
        for &r in &self.resets {
            self.stats.timestamps_backwards += drops(previous, &t[start..r]);
            (previous, start) = (i64::MIN, r);
        }
        self.stats.timestamps_backwards += drops(previous, &t[start..]);
        self.last_event_t = if start < t.len() {
            t[t.len() - 1]
        } else {
            previous
        };
    }

    /// The state machine over `s.words[..n_words]`, in runs of [`RUN`] words. A run without
    /// special, APS, misc or wrap words (almost every run) goes through [`step`] with no
    /// data-dependent branch; a run holding one checks every word and hands those to
    /// [`UsbDecoder::rare_word`]. `CHECK_RANGE` is only needed when the block holds an
    /// out-of-range address.
    fn decode_block<const CHECK_RANGE: bool>(
        &mut self,
        n_words: usize,
        s: &mut Scratch,
        mut specials: Option<&mut Vec<SpecialEvent>>,
    ) -> usize {
        let size = (self.config.size_x, self.config.size_y);
        let mut st = StepState {
            now: self.now,
            wrap_base: self.base + self.wrap_add,
            last_y: self.last_y,
            n: 0,
        };
        let Scratch { words, t, xy } = s;
        for run in words[..n_words].chunks(RUN) {
            let has_rare = run.iter().fold(false, |a, &w| a | is_rare(w));
            if !has_rare {
                for &w in run {
                    step::<CHECK_RANGE>(w, &mut st, t, xy, size);
                }
                continue;
            }
            for &w in run {
                if is_rare(w) {
                    self.now = st.now;
                    self.rare_word(w >> 12, w & 0x0FFF, st.n, specials.as_deref_mut());
                    st.now = self.now;
                    st.wrap_base = self.base + self.wrap_add;
                } else {
                    step::<CHECK_RANGE>(w, &mut st, t, xy, size);
                }
            }
        }
        self.now = st.now;
        self.last_y = st.last_y;
        st.n
    }

    /// Codes 0 and 4–7 (davis240.md §1.6, §1.7).
    #[cold]
    fn rare_word(
        &mut self,
        code: u16,
        data: u16,
        event_index: usize,
        specials: Option<&mut Vec<SpecialEvent>>,
    ) {
        let special = match code {
            0 => {
                let kind = SpecialKind::from_type(data);
                if kind == SpecialKind::TimestampReset {
                    self.base = 0;
                    self.wrap_add = 0;
                    self.now = 0;
                    self.stats.timestamp_resets += 1;
                    self.resets.push(event_index);
                } else {
                    self.stats.specials += 1;
                }
                Some(kind)
            }
            4 => {
                self.stats.aps_samples += 1;
                None
            }
            5 | 6 => {
                self.stats.misc_words += 1;
                None
            }
            7 => {
                let s = self.wrap_add + i64::from(data) * 0x8000;
                if s > i64::from(i32::MAX) {
                    self.base += 1 << 31;
                    self.wrap_add = s - (1 << 31);
                    self.stats.big_wraps += 1;
                    self.now = self.base + self.wrap_add;
                    Some(SpecialKind::TimestampBigWrap)
                } else {
                    self.wrap_add = s;
                    self.now = self.base + self.wrap_add;
                    None
                }
            }
            _ => unreachable!("codes 1-3 are decoded in the hot loop"),
        };
        if let (Some(kind), Some(specials)) = (special, specials) {
            specials.push(SpecialEvent { t: self.now, kind });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bytes(words: &[u16]) -> Vec<u8> {
        words.iter().flat_map(|w| w.to_le_bytes()).collect()
    }

    fn decode_all(words: &[u16]) -> (EventBuffer, DecodeStats, Vec<SpecialEvent>) {
        let mut d = UsbDecoder::davis240();
        let mut out = EventBuffer::new();
        let mut sp = Vec::new();
        d.decode_with_specials(&bytes(words), &mut out, &mut sp);
        (out, d.stats(), sp)
    }

    #[test]
    fn y_then_several_x_words_share_the_row() {
        let (out, st, _) = decode_all(&[0x8003, 0x1010, 0x3001, 0x2002, 0x3003]);
        assert_eq!(out.t, vec![3, 3, 3]);
        assert_eq!(out.x, vec![1, 2, 3]);
        assert_eq!(out.y, vec![16; 3]);
        assert_eq!(out.polarity, vec![true, false, true]);
        assert_eq!(st.words, 5);
        assert_eq!(st.events, 3);
    }

    #[test]
    fn wrap_multiplier_and_big_wrap_follow_libcaer() {
        // Two wraps of N = 2 then a timestamp: 4 · 2^15 + 7.
        let (out, _, _) = decode_all(&[0x7002, 0x7002, 0x8007, 0x1000, 0x3000]);
        assert_eq!(out.t, vec![4 * 32768 + 7]);
        // 16 wraps of N = 4095 reach 16·4095·2^15 = 2^31 − 2^19 (< 2^31): no big wrap yet;
        // then N = 17 passes 2^31 − 1 → overflow 1, wrapAdd = s − 2^31.
        let mut w = vec![0x7FFFu16; 16];
        w.extend([0x7011, 0x8001, 0x1005, 0x2009]);
        let (out, st, sp) = decode_all(&w);
        let s = 16 * 4095 * 32768 + 17 * 32768_i64;
        assert_eq!(out.t, vec![(1i64 << 31) + (s - (1 << 31)) + 1]);
        assert_eq!(st.big_wraps, 1);
        assert_eq!(sp[0].kind, SpecialKind::TimestampBigWrap);
        assert_eq!((out.x[0], out.y[0], out.polarity[0]), (9, 5, false));
    }

    #[test]
    fn timestamp_reset_restarts_time_and_is_not_a_pixel() {
        let (out, st, sp) = decode_all(&[0x7003, 0x8010, 0x1001, 0x3002, 0x0001, 0x8004, 0x3003]);
        assert_eq!(out.t, vec![3 * 32768 + 16, 4]);
        assert_eq!(out.y, vec![1, 1]);
        assert_eq!(st.timestamp_resets, 1);
        assert_eq!(
            sp,
            vec![SpecialEvent {
                t: 0,
                kind: SpecialKind::TimestampReset
            }]
        );
    }

    #[test]
    fn out_of_range_addresses_are_dropped_or_ignored() {
        // Y 180 is ignored (row stays 4); X 240 is dropped; X 239 is kept.
        let (out, st, _) = decode_all(&[0x1004, 0x10B4, 0x30F0, 0x30EF]);
        assert_eq!((out.x.clone(), out.y.clone()), (vec![239], vec![4]));
        assert_eq!(st.ignored_y_out_of_range, 1);
        assert_eq!(st.dropped_x_out_of_range, 1);
    }

    #[test]
    fn special_aps_imu_and_misc_words_never_become_pixels() {
        let words = [
            0x8001, 0x1002, // t = 1, y = 2
            0x0003, // ext input rising
            0x0005, 0x5304, 0x5012, 0x0007, // IMU start, misc8 config, one data byte, IMU end
            0x0008, 0x4123, 0x4FFF, 0x000D,
            0x000A, // APS frame start (GS), 2 ADC, column end, frame end
            0x6001, // misc10 exposure
            0x0040, // unknown special type 64
            0x3005,
        ];
        let (out, st, sp) = decode_all(&words);
        assert_eq!((out.len(), out.x[0], out.y[0]), (1, 5, 2));
        assert_eq!(st.aps_samples, 2);
        assert_eq!(st.misc_words, 3);
        assert_eq!(st.specials, 7);
        let kinds: Vec<_> = sp.iter().map(|s| s.kind).collect();
        assert_eq!(
            kinds,
            vec![
                SpecialKind::ExternalInputRising,
                SpecialKind::ImuStart,
                SpecialKind::ImuEnd,
                SpecialKind::ApsFrameStart {
                    global_shutter: true
                },
                SpecialKind::ApsColumnEnd,
                SpecialKind::ApsFrameEnd,
                SpecialKind::Unknown(64),
            ]
        );
        assert!(sp.iter().all(|s| s.t == 1));
    }

    #[test]
    fn backwards_timestamps_are_counted_and_order_is_kept() {
        let (out, st, _) = decode_all(&[0x8010, 0x1000, 0x3001, 0x8008, 0x3002]);
        assert_eq!(out.t, vec![16, 8]);
        assert_eq!(st.timestamps_backwards, 1);
    }

    #[test]
    fn invert_xy_swaps_addresses() {
        let mut d = UsbDecoder::new(DecoderConfig {
            size_x: 240,
            size_y: 180,
            invert_xy: true,
        });
        let mut out = EventBuffer::new();
        d.decode(&bytes(&[0x1007, 0x3009]), &mut out);
        assert_eq!((out.x[0], out.y[0]), (7, 9));
    }

    #[test]
    fn every_split_point_and_odd_bytes_give_the_same_events() {
        let words: Vec<u16> = (0..3000u16)
            .flat_map(|i| {
                [
                    0x8000 | ((i * 7) & 0x7FFF),
                    0x1000 | (i % 200),
                    0x2000 | (i % 250) | ((i & 1) << 12),
                ]
            })
            .chain([0x7001, 0x8002, 0x3001])
            .collect();
        let b = bytes(&words);
        let (whole, st, _) = decode_all(&words);
        assert!(st.events > 0);
        for split in [1usize, 2, 3, 777, 8191, 8192, 8193, b.len() - 1] {
            let mut d = UsbDecoder::davis240();
            let mut out = EventBuffer::new();
            d.decode(&b[..split], &mut out);
            assert_eq!(d.has_pending_byte(), split % 2 == 1);
            d.decode(&b[split..], &mut out);
            assert_eq!(out, whole, "split at {split}");
            assert_eq!(d.stats(), st);
        }
        // One byte at a time.
        let mut d = UsbDecoder::davis240();
        let mut out = EventBuffer::new();
        for byte in &b {
            d.decode(std::slice::from_ref(byte), &mut out);
        }
        d.decode(&[], &mut out);
        assert_eq!(out, whole);
    }

    #[test]
    fn output_buffer_is_appended_and_reusable() {
        let mut d = UsbDecoder::davis240();
        let mut out = EventBuffer::with_capacity(16);
        d.decode(&bytes(&[0x8001, 0x1001, 0x3001]), &mut out);
        out.clear();
        d.decode(&bytes(&[0x3002]), &mut out);
        assert_eq!((out.t.clone(), out.x.clone()), (vec![1], vec![2]));
        assert!(out.t.capacity() >= 16);
    }

    /// libcaer's translator written word by word, the plainest way (the oracle for the runs).
    type Reference = (Vec<(i64, u16, u16, bool)>, [u64; 3]);

    fn reference(words: &[u16], config: DecoderConfig) -> Reference {
        let (mut overflow, mut wrap_add, mut current) = (0i64, 0i64, 0i64);
        let (mut last_y, mut previous) = (0u16, i64::MIN);
        let (mut events, mut resets, mut wraps, mut backwards) = (Vec::new(), 0, 0, 0);
        for &w in words {
            if w & 0x8000 != 0 {
                current = wrap_add + i64::from(w & 0x7FFF);
                continue;
            }
            let (code, data) = (w >> 12, w & 0x0FFF);
            match code {
                0 if data == 1 => {
                    (overflow, wrap_add, current, previous) = (0, 0, 0, i64::MIN);
                    resets += 1;
                }
                1 if data < config.size_y => last_y = data,
                2 | 3 if data < config.size_x => {
                    let t = (overflow << 31) | current;
                    let (x, y) = if config.invert_xy {
                        (last_y, data)
                    } else {
                        (data, last_y)
                    };
                    backwards += u64::from(t < previous);
                    previous = t;
                    events.push((t, x, y, code == 3));
                }
                7 => {
                    let s = wrap_add + i64::from(data) * 0x8000;
                    if s > i64::from(i32::MAX) {
                        overflow += 1;
                        wrap_add = s - (1 << 31);
                        wraps += 1;
                    } else {
                        wrap_add = s;
                    }
                    current = wrap_add;
                }
                _ => {}
            }
        }
        (events, [resets, wraps, backwards])
    }

    #[test]
    fn random_streams_in_random_chunks_match_the_word_by_word_reference() {
        let mut state = 0x9E37_79B9_7F4A_7C15u64; // xorshift64*, fixed seed
        let mut next = move || {
            state ^= state >> 12;
            state ^= state << 25;
            state ^= state >> 27;
            state.wrapping_mul(0x2545_F491_4F6C_DD1D)
        };
        for case in 0..40 {
            let config = DecoderConfig {
                size_x: 240,
                size_y: 180,
                invert_xy: case % 5 == 4,
            };
            let len = (next() % 20_000) as usize;
            let rare_every = [3u64, 50, 5000, u64::MAX][case % 4];
            let words: Vec<u16> = (0..len)
                .map(|_| {
                    let r = next();
                    if r % rare_every == 0 {
                        // special (often a reset), APS, misc or a wrap with any multiplier
                        [
                            0x0001,
                            0x0003,
                            0x4123,
                            0x5012,
                            0x6001,
                            0x7000 | (r >> 20) as u16 & 0x0FFF,
                        ][(r >> 8) as usize % 6]
                    } else {
                        match r % 3 {
                            0 => 0x8000 | (r >> 16) as u16,
                            1 => 0x1000 | ((r >> 16) % 200) as u16,
                            _ => 0x2000 | ((r >> 16) % 256) as u16 | ((r >> 40) as u16 & 1) << 12,
                        }
                    }
                })
                .collect();
            let (want, [resets, wraps, backwards]) = reference(&words, config);
            let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
            let mut decoder = UsbDecoder::new(config);
            let mut out = EventBuffer::new();
            let mut at = 0;
            while at < bytes.len() {
                let take = ((next() % 9000) as usize + 1).min(bytes.len() - at);
                decoder.decode(&bytes[at..at + take], &mut out);
                at += take;
            }
            let got: Vec<_> = out.iter().map(|e| (e.t.0, e.x, e.y, e.polarity)).collect();
            assert_eq!(got, want, "case {case}");
            let st = decoder.stats();
            assert_eq!(
                (
                    st.timestamp_resets,
                    st.big_wraps,
                    st.timestamps_backwards,
                    st.words
                ),
                (resets, wraps, backwards, len as u64),
                "case {case}"
            );
        }
    }
}
