//! Value parsers shared by every command's numeric flags: each rejects, at parse time, a value
//! the command could not use, with a message in the user's terms (clap prefixes it with the
//! flag: `invalid value '0' for '--epochs <EPOCHS>': must be at least 1`).
//!
//! Flags that use [`positive_f64`], [`finite_f64`] or a time parser also set
//! `allow_negative_numbers = true`, so that `--duration -1` reaches the parser instead of being
//! taken for an unknown flag.
//!
//! Every time-valued flag of every command reads a [`Time`]: a number with a unit (`20ms`,
//! `0.02s`, `25us`, `25µs`) or a bare number of milliseconds (the paper's unit for Δt and τ).
//! Each quantity has one parser ([`time_step`], [`time_window`], [`time_tau`], [`time_tau_step`],
//! [`time_duration`], [`time_event_window`]) that refuses a value outside its sane range, so a
//! bare value written in seconds before bare numbers meant milliseconds (`--tau 0.076`) is
//! refused with a hint instead of being misread.

use neurotac_experiments::menu::Menu;

/// A count of at least 1 (`--epochs`, `--trials`, `--taxels`, `--n`, …).
pub fn positive_count(s: &str) -> Result<usize, String> {
    match s.trim().parse::<i128>() {
        Ok(n) if n >= 1 => usize::try_from(n).map_err(|_| "too large".to_owned()),
        Ok(_) => Err("must be at least 1".into()),
        Err(_) => Err("not a whole number (expected 1, 2, 3, …)".into()),
    }
}

/// A whole number of at least 0 (`--threads`, where 0 means one per core).
pub fn count(s: &str) -> Result<usize, String> {
    match s.trim().parse::<i128>() {
        Ok(n) if n >= 0 => usize::try_from(n).map_err(|_| "too large".to_owned()),
        Ok(_) => Err("must be 0 or more".into()),
        Err(_) => Err("not a whole number (expected 0, 1, 2, …)".into()),
    }
}

/// A sensor size `WIDTHxHEIGHT`, both at least 1 (`convert --sensor 346x260`).
pub fn sensor_size(s: &str) -> Result<(u16, u16), String> {
    neurotac_sensor::format::parse_sensor_size(s)
        .ok_or_else(|| "not a sensor size (expected WIDTHxHEIGHT, e.g. 346x260)".into())
}

/// A finite number (`neuron --current`).
pub fn finite_f64(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err("must be a finite number".into()),
        Err(_) => Err("not a number".into()),
    }
}

/// A finite number greater than 0 (durations, time steps, rates, τ, radii, …).
pub fn positive_f64(s: &str) -> Result<f64, String> {
    let x = finite_f64(s)?;
    match x > 0.0 {
        true => Ok(x),
        false => Err("must be greater than 0".into()),
    }
}

/// A number in [0, 1] (`--cos`).
pub fn unit_interval(s: &str) -> Result<f64, String> {
    let x = finite_f64(s)?;
    match (0.0..=1.0).contains(&x) {
        true => Ok(x),
        false => Err("must lie in [0, 1]".into()),
    }
}

/// A fraction strictly between 0 and 1 (`--test-fraction`).
pub fn open_fraction(s: &str) -> Result<f64, String> {
    let x = finite_f64(s)?;
    match x > 0.0 && x < 1.0 {
        true => Ok(x),
        false => Err("must lie strictly between 0 and 1".into()),
    }
}

/// A span of time from the command line, held in seconds (the library's unit for spike times).
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
pub struct Time(f64);

impl Time {
    /// The time in seconds.
    pub const fn s(self) -> f64 {
        self.0
    }

    /// The time in milliseconds.
    pub const fn ms(self) -> f64 {
        self.0 * 1e3
    }

    /// The time as a whole number of milliseconds (what the temporal coding's windows and
    /// sample durations are counted in), or an error naming `flag` and the value as given.
    pub fn whole_ms(self, flag: &str) -> anyhow::Result<u32> {
        let ms = self.ms();
        match (ms - ms.round()).abs() <= 1e-6 && ms.round() <= f64::from(u32::MAX) {
            true => Ok(ms.round() as u32),
            false => anyhow::bail!("{flag} {self} is not a whole number of milliseconds"),
        }
    }

    /// The time in whole microseconds (rounded), the unit of event timestamps.
    pub fn us(self) -> i64 {
        (self.0 * 1e6).round() as i64
    }
}

impl std::fmt::Display for Time {
    /// The largest unit in which the value is at least 1: `1.5s`, `20ms`, `25µs`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = self.0;
        let (value, unit) = match s.abs() {
            a if a >= 1.0 => (s, "s"),
            a if a >= 1e-3 => (s * 1e3, "ms"),
            _ => (s * 1e6, "µs"),
        };
        // Round away the binary noise of the unit change (0.1 ms is 0.09999… in seconds).
        write!(f, "{}{unit}", (value * 1e9).round() / 1e9)
    }
}

/// The unit suffixes a time accepts, and how many of each make a second (longest suffix
/// first, so `ms` is not read as `m` + `s`; a division by a power of ten rounds correctly, so
/// `25us` is exactly the double nearest 25 µs).
const TIME_UNITS: [(&str, f64); 5] = [
    ("ms", 1e3),
    ("us", 1e6),
    ("µs", 1e6),
    ("μs", 1e6),
    ("s", 1.0),
];

/// Parses a time in `[min, max]`: a number with a unit of [`TIME_UNITS`], or a bare number of
/// milliseconds. A bare value out of range whose reading in seconds would fit gets a hint, since
/// bare numbers meant seconds for some flags before they all meant milliseconds.
fn time_in(s: &str, min: Time, max: Time) -> Result<Time, String> {
    let s = s.trim();
    let (number, per_s) = TIME_UNITS
        .iter()
        .find_map(|(suffix, per_s)| s.strip_suffix(suffix).map(|n| (n.trim_end(), Some(*per_s))))
        .unwrap_or((s, None));
    let x = match number.parse::<f64>() {
        Ok(x) if x.is_finite() => x,
        Ok(_) => return Err("must be a finite time".into()),
        Err(_) => return Err("not a time (expected e.g. 20, 20ms, 0.02s or 25us)".into()),
    };
    let t = Time(x / per_s.unwrap_or(1e3));
    if t.0 <= 0.0 {
        return Err("must be greater than 0".into());
    }
    if min <= t && t <= max {
        return Ok(t);
    }
    let side = match t < min {
        true => format!("below the smallest, {min}"),
        false => format!("above the largest, {max}"),
    };
    let hint = match per_s.is_none() && (min..=max).contains(&Time(x)) {
        true => format!("; a bare number means milliseconds, write {number}s for seconds"),
        false => String::new(),
    };
    // The value as given: a huge one has no readable form in another unit.
    Err(format!("{} is {side}{hint}", given(s)))
}

/// `s` as it was typed (a bare number with its unit, ms, added), cut to 40 characters.
fn given(s: &str) -> String {
    let text: String = s.chars().take(40).collect();
    match TIME_UNITS.iter().any(|(suffix, _)| s.ends_with(suffix)) {
        true => text,
        false => format!("{text}ms"),
    }
}

/// A simulation time step (`neuron --dt`, `bench --dt`, `--trace-dt`): 1 µs … 100 ms.
pub fn time_step(s: &str) -> Result<Time, String> {
    time_in(s, Time(1e-6), Time(0.1))
}

/// A coding or pooling window Δt (`--dt` of the codings, `transduce --pool`): 1 ms … 10 s.
pub fn time_window(s: &str) -> Result<Time, String> {
    time_in(s, Time(1e-3), Time(10.0))
}

/// The τ range of touch codings (the paper's searches): outside it `--tau` warns.
const USUAL_TAU: (Time, Time) = (Time(1e-3), Time(10.0));

/// A Van Rossum kernel time constant τ (`--tau`, `--tau-min`, `--tau-max`): any finite time
/// above 0, as the library computes the distance exactly at every τ; outside 1 ms … 10 s it
/// warns ([`unusual_tau`]).
pub fn time_tau(s: &str) -> Result<Time, String> {
    let t = time_in(s, Time(f64::MIN_POSITIVE), Time(f64::MAX))?;
    if let Some(warning) = unusual_tau(s, t) {
        eprintln!("warning: {warning}");
    }
    Ok(t)
}

/// Why τ `t` (typed as `s`) is unusual, if it is outside 1 ms … 10 s; a bare number gets the
/// hint that it means milliseconds.
pub fn unusual_tau(s: &str, t: Time) -> Option<String> {
    let (min, max) = USUAL_TAU;
    if (min..=max).contains(&t) {
        return None;
    }
    let number = s.trim();
    let bare = !TIME_UNITS
        .iter()
        .any(|(suffix, _)| number.ends_with(suffix));
    let hint = match bare
        && number
            .parse()
            .is_ok_and(|x: f64| (min..=max).contains(&Time(x)))
    {
        true => format!("; a bare number means milliseconds, write {number}s for seconds"),
        false => String::new(),
    };
    Some(format!(
        "τ = {} is outside {min} … {max}, the range of touch codings{hint}",
        given(s)
    ))
}

/// The step of a τ grid (`--tau-step`): 0.1 ms … 1 s.
pub fn time_tau_step(s: &str) -> Result<Time, String> {
    time_in(s, Time(1e-4), Time(1.0))
}

/// A simulated, sampled or recorded duration (`--duration`, `layout --calibration`): 10 ms …
/// one day. Shorter runs would hold less than one τ of the paper's neurons.
pub fn time_duration(s: &str) -> Result<Time, String> {
    time_in(s, Time(1e-2), Time(86_400.0))
}

/// A per-event window of the sensor filters (`--ba-window`, `--refractory`): 1 µs … 100 ms.
pub fn time_event_window(s: &str) -> Result<Time, String> {
    time_in(s, Time(1e-6), Time(0.1))
}

/// The value parser of a library menu ([`Menu`]: codings, neuron models, precisions): its keys
/// are the possible values `--help` lists and clap suggests from, each parsed with the menu's
/// own `FromStr`, so the list is declared once, in the library.
pub fn menu<T: Menu + std::str::FromStr + Clone + Send + Sync>()
-> impl clap::builder::TypedValueParser<Value = T>
where
    <T as std::str::FromStr>::Err: std::error::Error + Send + Sync + 'static,
{
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(T::ALL.iter().map(|c| c.key()))
        .try_map(|key| key.parse::<T>())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_refuse_zero_negatives_and_words() {
        assert_eq!(positive_count("3"), Ok(3));
        assert!(positive_count("0").unwrap_err().contains("at least 1"));
        assert!(positive_count("-2").unwrap_err().contains("at least 1"));
        assert!(positive_count("two").unwrap_err().contains("whole number"));
        assert_eq!(count("0"), Ok(0));
        assert!(count("-1").is_err());
    }

    #[test]
    fn reals_refuse_nan_infinity_and_out_of_range() {
        assert_eq!(positive_f64("0.5"), Ok(0.5));
        assert!(positive_f64("-1").unwrap_err().contains("greater than 0"));
        assert!(positive_f64("0").is_err());
        assert!(positive_f64("nan").unwrap_err().contains("finite"));
        assert!(positive_f64("inf").is_err());
        assert_eq!(finite_f64("-1.5"), Ok(-1.5));
        assert!(unit_interval("1.2").is_err());
        assert_eq!(unit_interval("1"), Ok(1.0));
        assert!(open_fraction("1").is_err());
    }

    #[test]
    fn times_take_a_unit_and_bare_numbers_are_milliseconds() {
        let ms = |s| time_window(s).map(Time::ms);
        assert_eq!(ms("20"), Ok(20.0));
        assert_eq!(ms("20ms"), Ok(20.0));
        assert_eq!(ms("0.02s"), Ok(20.0));
        assert_eq!(ms(" 20 ms "), Ok(20.0));
        assert_eq!(time_step("25us").map(Time::s), Ok(25e-6));
        assert_eq!(time_step("25µs").map(Time::s), Ok(25e-6));
        assert_eq!(time_step("25μs").map(Time::s), Ok(25e-6));
        assert!(time_window("twenty").unwrap_err().contains("not a time"));
        assert!(time_window("20m").unwrap_err().contains("not a time"));
        assert!(time_window("-20ms").unwrap_err().contains("greater than 0"));
        assert!(time_window("nan").unwrap_err().contains("finite"));
    }

    #[test]
    fn a_window_in_whole_ms_is_refused_otherwise_with_the_value_as_given() {
        assert_eq!(
            time_window("0.159s").unwrap().whole_ms("--dt").unwrap(),
            159
        );
        let e = time_window("20.5").unwrap().whole_ms("--dt").unwrap_err();
        assert_eq!(
            e.to_string(),
            "--dt 20.5ms is not a whole number of milliseconds"
        );
    }

    #[test]
    fn an_out_of_range_time_is_echoed_as_given() {
        let e = time_duration("1e300s").unwrap_err();
        assert!(e.starts_with("1e300s is above the largest, 86400s"), "{e}");
        assert!(!e.contains("inf"), "{e}");
        let e = time_step("1e-300s").unwrap_err();
        assert!(e.starts_with("1e-300s is below the smallest, 1µs"), "{e}");
    }

    #[test]
    fn every_tau_the_library_computes_is_accepted_and_an_unusual_one_warned_about() {
        // The fixtures' τ = 1 µs, which the library (and pymuvr) compute exactly.
        assert_eq!(time_tau("1us").map(Time::s), Ok(1e-6));
        assert_eq!(time_tau("0.076").map(Time::s), Ok(76e-6));
        assert_eq!(time_tau("100s").map(Time::s), Ok(100.0));
        let warning = unusual_tau("0.076", Time(76e-6)).unwrap();
        assert!(
            warning.contains("0.076ms is outside 1ms … 10s"),
            "{warning}"
        );
        assert!(warning.contains("write 0.076s for seconds"), "{warning}");
        assert!(!unusual_tau("1us", Time(1e-6)).unwrap().contains("bare"));
        assert_eq!(unusual_tau("76ms", Time(0.076)), None);
        for bad in ["0", "-1ms", "nan", "inf", "1e999s"] {
            assert!(time_tau(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn a_bare_value_in_seconds_is_refused_with_a_hint() {
        let e = time_window("0.076").unwrap_err();
        assert!(e.contains("0.076ms is below the smallest, 1ms"), "{e}");
        assert!(e.contains("write 0.076s for seconds"), "{e}");
        assert_eq!(time_tau("0.076s").map(Time::ms), Ok(76.0));
        // With a unit the value is what the user meant: no hint.
        let e = time_window("20s").unwrap_err();
        assert!(
            e.contains("above the largest, 10s") && !e.contains("bare"),
            "{e}"
        );
        assert!(time_tau_step("0.005").unwrap_err().contains("write 0.005s"));
        assert!(time_duration("4.5").unwrap_err().contains("write 4.5s"));
    }
}
