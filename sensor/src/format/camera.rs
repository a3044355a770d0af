//! How each format states the sensor size (davis240.md §2), and the cameras that AEDAT 2.0 and
//! 3.1 name instead of a size.
//!
//! | format | states the size by | sizes it can state |
//! |---|---|---|
//! | AEDAT 2.0 | jAER's chip class, `# AEChip: eu.seebetter.ini.chips.davis.Davis346B` | the [`CAMERAS`] |
//! | AEDAT 3.1 | cAER's camera name, `#Source 1: DAVIS346` | the [`CAMERAS`] |
//! | AEDAT 4.0 | the event stream's `sizeX` / `sizeY` | 1 … 32767 each (16-bit signed coordinates) |
//! | ECD text, CSV | an optional first line `# sensor 346x260` ([`sensor_line`]) | 1 … 65535 each |
//!
//! A file that states no size is read with an assumed one (240 × 180 unless the caller says
//! otherwise), and a writer refuses a size its format cannot state
//! ([`FormatError::UnsupportedSensorSize`](crate::FormatError::UnsupportedSensorSize)).

use super::contract::DAVIS240_SIZE;

/// A camera that AEDAT 2.0 and 3.1 headers name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Camera {
    /// Pixel-array size `(width, height)`.
    pub size: (u16, u16),
    /// Lower-case start of every name that denotes it: jAER's chip classes (`DAVIS240C`,
    /// `Davis346B`, `Davis346red`, …) and cAER's camera names (`DAVIS240C`, `DAVIS346`,
    /// `DAVIS346B`, …).
    prefix: &'static str,
    /// The jAER chip class written on an AEDAT 2.0 `# AEChip:` line.
    pub jaer_class: &'static str,
    /// The camera name cAER writes on an AEDAT 3.1 `#Source` line (also the AEDAT 4.0 `source`).
    pub name: &'static str,
}

/// The cameras whose names AEDAT 2.0 and 3.1 files are read and written with. jAER records
/// every DAVIS through the same address layout (`DAViSFX3HardwareInterface`: raw x = width − 1 −
/// x, raw y = height − 1 − y), so one AEDAT 2.0 layout serves both.
pub const CAMERAS: [Camera; 2] = [
    Camera {
        size: DAVIS240_SIZE,
        prefix: "davis240",
        jaer_class: "eu.seebetter.ini.chips.davis.DAVIS240C",
        name: "DAVIS240C",
    },
    Camera {
        size: (346, 260),
        prefix: "davis346",
        jaer_class: "eu.seebetter.ini.chips.davis.Davis346B",
        name: "DAVIS346",
    },
];

/// The sizes of [`CAMERAS`], as errors name them.
pub(crate) const CAMERA_SIZES: &str = "240 × 180 (DAVIS240C) or 346 × 260 (DAVIS346)";

/// The camera a jAER chip class or cAER camera name denotes (the part after the last `.`,
/// case-insensitive), if it is one of [`CAMERAS`].
pub fn camera_named(name: &str) -> Option<&'static Camera> {
    let simple = name.trim().rsplit('.').next()?.to_ascii_lowercase();
    CAMERAS.iter().find(|c| simple.starts_with(c.prefix))
}

/// The camera of a sensor size, if it is one of [`CAMERAS`].
pub fn camera_of_size(size: (u16, u16)) -> Option<&'static Camera> {
    CAMERAS.iter().find(|c| c.size == size)
}

/// Parses a sensor size written `WIDTHxHEIGHT` (`346x260`; both at least 1).
pub fn parse_sensor_size(text: &str) -> Option<(u16, u16)> {
    let (w, h) = text.trim().split_once(['x', 'X'])?;
    let parse = |s: &str| {
        s.bytes()
            .all(|b| b.is_ascii_digit())
            .then(|| s.parse::<u16>().ok())
            .flatten()
            .filter(|&v| v > 0)
    };
    Some((parse(w)?, parse(h)?))
}

/// The first line by which ECD text and CSV files state their sensor size: `# sensor 346x260`
/// (LF-terminated). Tools that skip `#` comment lines (numpy's `loadtxt`, pandas with
/// `comment="#"`) read past it.
pub fn sensor_line(size: (u16, u16)) -> String {
    format!("# sensor {}x{}\n", size.0, size.1)
}

/// The size stated by a `# sensor WIDTHxHEIGHT` line (without its line end; blanks around the
/// words are allowed), or `None` if the line is not one.
pub(crate) fn parse_sensor_line(line: &[u8]) -> Option<(u16, u16)> {
    let text = std::str::from_utf8(line).ok()?;
    let rest = text
        .strip_prefix('#')?
        .trim_start()
        .strip_prefix("sensor")?;
    if !rest.starts_with([' ', '\t']) {
        return None;
    }
    parse_sensor_size(rest)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_denote_cameras_in_any_case_and_package() {
        for name in [
            "eu.seebetter.ini.chips.davis.DAVIS240C",
            "DAVIS240A",
            "davis240c",
        ] {
            assert_eq!(camera_named(name).unwrap().size, (240, 180), "{name}");
        }
        for name in [
            "eu.seebetter.ini.chips.davis.Davis346B",
            "eu.seebetter.ini.chips.davis.Davis346red",
            "DAVIS346",
            "DAVIS346bsi",
        ] {
            assert_eq!(camera_named(name).unwrap().size, (346, 260), "{name}");
        }
        for name in [
            "DVS128",
            "DAVI346",
            "ch.unizh.ini.jaer.chip.retina.DVXplorer",
            "",
        ] {
            assert_eq!(camera_named(name), None, "{name}");
        }
        assert_eq!(camera_of_size((320, 240)), None);
    }

    #[test]
    fn sensor_lines_parse_back_and_nothing_else_does() {
        for size in [(240, 180), (346, 260), (1, 65535)] {
            let line = sensor_line(size);
            assert_eq!(
                parse_sensor_line(line.trim_end().as_bytes()),
                Some(size),
                "{line}"
            );
        }
        assert_eq!(parse_sensor_line(b"#sensor\t320x240 "), Some((320, 240)));
        for bad in [
            &b"# sensor 0x10"[..],
            b"# sensor 346x",
            b"# sensor 346 x 260",
            b"# sensor 70000x1",
            b"# sensor +3x4",
            b"# sensors 3x4",
            b"# 346x260",
            b"t,x,y,on",
        ] {
            assert_eq!(
                parse_sensor_line(bad),
                None,
                "{}",
                String::from_utf8_lossy(bad)
            );
        }
    }
}
