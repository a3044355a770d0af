//! Value parsers shared by every command's numeric flags: each rejects, at parse time, a value
//! the command could not use, with a message in the user's terms (clap prefixes it with the
//! flag: `invalid value '0' for '--epochs <EPOCHS>': must be at least 1`).
//!
//! Flags that use [`positive_f64`] or [`finite_f64`] also set `allow_negative_numbers = true`,
//! so that `--duration -1` reaches the parser instead of being taken for an unknown flag.

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

/// A positive whole number of microseconds, milliseconds, … (`--ba-window-us`).
pub fn positive_i64(s: &str) -> Result<i64, String> {
    match s.trim().parse::<i64>() {
        Ok(n) if n >= 1 => Ok(n),
        Ok(_) => Err("must be at least 1".into()),
        Err(_) => Err("not a whole number (expected 1, 2, 3, …)".into()),
    }
}

/// A positive whole number of milliseconds (`search dt --max-window-ms`).
pub fn positive_u32(s: &str) -> Result<u32, String> {
    let n = positive_count(s)?;
    u32::try_from(n).map_err(|_| "too large".to_owned())
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
}
