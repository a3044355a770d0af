//! Reading the JSON form so that every error says where it is.
//!
//! serde_json parses the text directly (not through an intermediate `Value`, whose errors have
//! no position), so its errors keep their line and column. While it is inside `observations`
//! the reader keeps track of the observation, channel and spike it is at, and checks each spike
//! time as it is read (finite, not before the previous one in its channel); a parse that stops
//! there is reported at that observation, channel and spike:
//!
//! - an out-of-order time is a [`DatasetError::Spikes`] with [`SpikeError::Unsorted`];
//! - `NaN`, `Infinity` (which JSON does not have) and a number beyond `f64` (`1e999`) are a
//!   [`DatasetError::Spikes`] with [`SpikeError::NonFinite`];
//! - anything else (a string or `null` for a time, a channel that is not a list, broken syntax)
//!   is a [`DatasetError::Json`] with its [`SpikeLocation`] and serde_json's message.

use crate::error::{DatasetError, FilePosition, SpikeError, SpikeLocation};
use crate::spikes::{MultiSpikeTrain, check_spike};
use serde::de::{self, DeserializeSeed, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};
use std::cell::Cell;
use std::fmt;
use std::path::Path;

/// The fields of the JSON form, the optional ones defaulted.
pub(super) struct RawDataset {
    /// `labels`, or empty.
    pub(super) labels: Vec<usize>,
    /// `class_names`, or empty.
    pub(super) class_names: Vec<String>,
    /// `observations`, each checked.
    pub(super) observations: Vec<MultiSpikeTrain>,
    /// `meta`, or empty.
    pub(super) meta: serde_json::Map<String, serde_json::Value>,
}

/// Parses the JSON form; `path` only names the source in errors.
pub(super) fn parse(text: &str, path: &Path) -> Result<RawDataset, DatasetError> {
    let place = Place::default();
    let mut de = serde_json::Deserializer::from_str(text);
    let parsed = DatasetSeed(&place)
        .deserialize(&mut de)
        .and_then(|raw| de.end().map(|()| raw));
    parsed.map_err(|source| place.error(source, text, path))
}

/// Where the parser is inside `observations`, and the invalid spike time that stopped it.
#[derive(Default)]
struct Place {
    at: Cell<Option<SpikeLocation>>,
    invalid: Cell<Option<SpikeError>>,
}

impl Place {
    fn enter(&self, observation: usize, channel: Option<usize>, spike: Option<usize>) {
        self.at.set(Some(SpikeLocation {
            observation,
            channel,
            spike,
        }));
    }

    fn leave(&self) {
        self.at.set(None);
    }

    /// Keeps `error` for [`error`](Self::error) and stops the parser.
    fn invalid<E: de::Error>(&self, error: SpikeError) -> E {
        let e = E::custom(&error);
        self.invalid.set(Some(error));
        e
    }

    /// The dataset error for a parse that stopped with `source`.
    fn error(&self, source: serde_json::Error, text: &str, path: &Path) -> DatasetError {
        let position = Some(FilePosition::Text {
            line: source.line(),
            column: source.column(),
        });
        let at = self.at.get();
        if let (Some(at), Some(invalid)) = (at, self.invalid.take()) {
            return DatasetError::Spikes {
                observation: at.observation,
                position,
                source: invalid,
            };
        }
        if let Some(SpikeLocation {
            observation,
            channel: Some(channel),
            spike: Some(index),
        }) = at
            && source.classify() == serde_json::error::Category::Syntax
            && let Some(value) = non_finite_number_at(text, source.line(), source.column())
        {
            return DatasetError::Spikes {
                observation,
                position,
                source: SpikeError::NonFinite {
                    channel,
                    index,
                    value,
                },
            };
        }
        DatasetError::Json {
            path: path.to_owned(),
            at,
            source,
        }
    }
}

/// The number written at serde_json's `line` and `column` (1-based; the column counts bytes and
/// names the byte the parser stopped at), when it is one that JSON or `f64` cannot hold: `NaN`,
/// `Infinity`, `-Infinity`, `inf` or a number beyond `f64` such as `1e999`, read as Rust reads
/// it. `None` for anything else.
fn non_finite_number_at(text: &str, line: usize, column: usize) -> Option<f64> {
    let line_start = match line {
        0 | 1 => 0,
        _ => text.match_indices('\n').nth(line - 2)?.0 + 1,
    };
    let at = line_start.checked_add(column.checked_sub(1)?)?;
    let bytes = text.as_bytes();
    if at >= bytes.len() {
        return None;
    }
    let delimiter = |b: &u8| b.is_ascii_whitespace() || b",:[]{}\"".contains(b);
    let start = bytes[..at].iter().rposition(delimiter).map_or(0, |p| p + 1);
    let end = bytes[at..]
        .iter()
        .position(delimiter)
        .map_or(bytes.len(), |p| at + p);
    let token = text.get(start..end)?;
    token.parse::<f64>().ok().filter(|v| !v.is_finite())
}

/// The top-level object: `labels`, `class_names`, `observations` (required) and `meta`; other
/// keys are ignored.
struct DatasetSeed<'p>(&'p Place);

impl<'de> DeserializeSeed<'de> for DatasetSeed<'_> {
    type Value = RawDataset;
    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<RawDataset, D::Error> {
        deserializer.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for DatasetSeed<'_> {
    type Value = RawDataset;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a spike dataset (an object with `observations`)")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<RawDataset, A::Error> {
        let mut labels = None;
        let mut class_names = None;
        let mut observations = None;
        let mut meta = None;
        fn once<T, E: de::Error>(slot: &Option<T>, field: &'static str) -> Result<(), E> {
            match slot {
                Some(_) => Err(E::duplicate_field(field)),
                None => Ok(()),
            }
        }
        while let Some(key) = map.next_key::<String>()? {
            match key.as_str() {
                "labels" => {
                    once(&labels, "labels")?;
                    labels = Some(map.next_value()?);
                }
                "class_names" => {
                    once(&class_names, "class_names")?;
                    class_names = Some(map.next_value()?);
                }
                "observations" => {
                    once(&observations, "observations")?;
                    observations = Some(map.next_value_seed(ObservationsSeed(self.0))?);
                }
                "meta" => {
                    once(&meta, "meta")?;
                    meta = Some(map.next_value()?);
                }
                _ => {
                    map.next_value::<IgnoredAny>()?;
                }
            }
        }
        Ok(RawDataset {
            labels: labels.unwrap_or_default(),
            class_names: class_names.unwrap_or_default(),
            observations: observations.ok_or_else(|| de::Error::missing_field("observations"))?,
            meta: meta.unwrap_or_default(),
        })
    }
}

/// `observations`: a list of observations.
struct ObservationsSeed<'p>(&'p Place);

impl<'de> DeserializeSeed<'de> for ObservationsSeed<'_> {
    type Value = Vec<MultiSpikeTrain>;
    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Self::Value, D::Error> {
        deserializer.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for ObservationsSeed<'_> {
    type Value = Vec<MultiSpikeTrain>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a list of observations")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut observations = Vec::new();
        loop {
            let observation = observations.len();
            self.0.enter(observation, None, None);
            match seq.next_element_seed(ObservationSeed {
                place: self.0,
                observation,
            })? {
                Some(trains) => observations.push(trains),
                None => break,
            }
        }
        self.0.leave();
        Ok(observations)
    }
}

/// One observation: a list of channels.
struct ObservationSeed<'p> {
    place: &'p Place,
    observation: usize,
}

impl<'de> DeserializeSeed<'de> for ObservationSeed<'_> {
    type Value = MultiSpikeTrain;
    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Self::Value, D::Error> {
        deserializer.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for ObservationSeed<'_> {
    type Value = MultiSpikeTrain;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an observation (a list of channels)")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut times = Vec::new();
        let mut offsets = vec![0];
        loop {
            let channel = offsets.len() - 1;
            self.place.enter(self.observation, Some(channel), None);
            let seed = ChannelSeed {
                place: self.place,
                observation: self.observation,
                channel,
                times: &mut times,
            };
            match seq.next_element_seed(seed)? {
                Some(()) => offsets.push(times.len()),
                None => break,
            }
        }
        // Offsets from the channel ends, every time checked by `ChannelSeed`.
        Ok(MultiSpikeTrain::from_checked_parts(times, offsets))
    }
}

/// One channel: a list of spike times, appended to `times` as they are checked.
struct ChannelSeed<'p, 't> {
    place: &'p Place,
    observation: usize,
    channel: usize,
    times: &'t mut Vec<f64>,
}

impl<'de> DeserializeSeed<'de> for ChannelSeed<'_, '_> {
    type Value = ();
    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<(), D::Error> {
        deserializer.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for ChannelSeed<'_, '_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a channel (a list of spike times in seconds)")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let mut previous = f64::NEG_INFINITY;
        let mut index = 0;
        loop {
            self.place
                .enter(self.observation, Some(self.channel), Some(index));
            let Some(t) = seq.next_element_seed(TimeSeed)? else {
                return Ok(());
            };
            check_spike(self.channel, index, previous, t).map_err(|e| self.place.invalid(e))?;
            self.times.push(t);
            previous = t;
            index += 1;
        }
    }
}

/// One spike time: a JSON number, read as `f64`.
struct TimeSeed;

impl<'de> DeserializeSeed<'de> for TimeSeed {
    type Value = f64;
    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<f64, D::Error> {
        deserializer.deserialize_f64(self)
    }
}

impl Visitor<'_> for TimeSeed {
    type Value = f64;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a spike time (a number of seconds)")
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<f64, E> {
        Ok(v)
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<f64, E> {
        Ok(v as f64)
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<f64, E> {
        Ok(v as f64)
    }
}
