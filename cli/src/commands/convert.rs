//! `neurotac convert IN OUT`: converts an event file between AEDAT 2.0, AEDAT 3.1, AEDAT 4.0,
//! ECD text and CSV. The input format is detected from its first bytes, the output format from
//! the extension; the conversion streams chunk by chunk and prints its speed in events/s.
//!
//! The output states the input's sensor size (`neurotac_sensor::format::camera`). For an input
//! that states none (CSV or ECD text without a `# sensor` line, …) it is `--sensor`, by default
//! 240 × 180 — the size the input is then read with, so events outside it are skipped (and
//! counted in the warning). A `--sensor` other than the size the input states, or a size the
//! output format cannot state (AEDAT 2.0 and 3.1: the DAVIS240's and DAVIS346's only), is
//! refused before anything is written.

use super::args;
use super::options::ForceOption;
use super::outputs::{Output, check_outputs};
use anyhow::Context;
use clap::{Args, ValueEnum};
use neurotac_core::EventBuffer;
use neurotac_sensor::format::{self, Compression, DAVIS240_SIZE, Format};
use std::path::PathBuf;
use std::time::Instant;

#[derive(Debug, Clone, Copy, ValueEnum)]
enum Codec {
    None,
    Lz4,
    Zstd,
}

#[derive(Debug, Args)]
pub struct ConvertArgs {
    /// Input event file (.aedat, .aedat3, .aedat4, ECD .txt or .csv; detected from its content).
    input: PathBuf,
    /// Output event file; the extension picks the format (.aedat, .aedat3, .aedat4, .txt, .csv).
    output: PathBuf,
    #[command(flatten)]
    force: ForceOption,
    /// Packet compression when writing AEDAT 4.0.
    #[arg(long, value_enum, default_value = "lz4")]
    compression: Codec,
    /// Sensor size WIDTHxHEIGHT (e.g. 346x260) of an input that states none (CSV or ECD text
    /// without a `# sensor` line); default 240x180. Refused if the input states another.
    #[arg(long, value_parser = args::sensor_size, value_name = "WIDTHxHEIGHT")]
    sensor: Option<(u16, u16)>,
}

pub fn run(args: ConvertArgs) -> anyhow::Result<()> {
    neurotac_core::io::check_distinct(&args.input, &args.output)?;
    check_outputs([Output::file("OUTPUT", &args.output)], args.force.force)?;
    let out_format = match Format::from_extension(&args.output)? {
        Format::Aedat4(_) => Format::Aedat4(match args.compression {
            Codec::None => Compression::None,
            Codec::Lz4 => Compression::Lz4,
            Codec::Zstd => Compression::Zstd,
        }),
        other => other,
    };
    let start = Instant::now();
    let assumed = args.sensor.unwrap_or(DAVIS240_SIZE);
    let mut reader = format::open_reader_assuming(&args.input, assumed)?;
    let sensor = match (reader.sensor_size(), args.sensor) {
        (Some(stated), Some(given)) if stated != given => anyhow::bail!(
            "{} states a {} × {} sensor, not the --sensor {} × {}",
            args.input.display(),
            stated.0,
            stated.1,
            given.0,
            given.1
        ),
        (stated, _) => stated.unwrap_or(assumed),
    };
    let replace = format::Replace::when(args.force.force);
    let mut writer = format::create_writer_as(&args.output, out_format, sensor, replace)?;
    let mut chunk = EventBuffer::new();
    while reader.read_chunk(&mut chunk)? > 0 {
        writer.write(&chunk)?;
        chunk.clear();
    }
    writer
        .finish()
        .with_context(|| format!("completing {}", args.output.display()))?;
    let seconds = start.elapsed().as_secs_f64();
    let stats = reader.stats();
    println!(
        "{} → {} ({}, {} × {} sensor): {} events in {:.3} s = {:.1} M events/s",
        args.input.display(),
        args.output.display(),
        out_format.name(),
        sensor.0,
        sensor.1,
        stats.events,
        seconds,
        stats.events as f64 / seconds / 1e6
    );
    if stats.skipped > 0 {
        println!(
            "  skipped {} non-polarity records, packets or streams",
            stats.skipped
        );
    }
    if stats.timestamp_wraps > 0 {
        println!(
            "  unwrapped {} 32-bit timestamp wraps",
            stats.timestamp_wraps
        );
    }
    if let Some(warning) = stats.warning(&args.input) {
        eprintln!("{warning}");
    }
    if stats.out_of_range > 0 && reader.sensor_size().is_none() && args.sensor.is_none() {
        eprintln!(
            "  the input states no sensor size, so {} × {} was assumed: give its size with --sensor WIDTHxHEIGHT",
            sensor.0, sensor.1
        );
    }
    Ok(())
}
