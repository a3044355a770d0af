//! `neurotac convert IN OUT`: converts an event file between AEDAT 2.0, AEDAT 3.1, AEDAT 4.0,
//! ECD text and CSV. The input format is detected from its first bytes, the output format from
//! the extension; the conversion streams chunk by chunk and prints its speed in events/s.

use super::options::ForceOption;
use super::outputs::refuse_existing;
use anyhow::Context;
use clap::{Args, ValueEnum};
use neurotac_core::EventBuffer;
use neurotac_sensor::format::{self, Compression, Format};
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
}

pub fn run(args: ConvertArgs) -> anyhow::Result<()> {
    neurotac_core::io::check_distinct(&args.input, &args.output)?;
    refuse_existing([args.output.as_path()], args.force.force)?;
    let out_format = match Format::from_extension(&args.output)? {
        Format::Aedat4(_) => Format::Aedat4(match args.compression {
            Codec::None => Compression::None,
            Codec::Lz4 => Compression::Lz4,
            Codec::Zstd => Compression::Zstd,
        }),
        other => other,
    };
    let start = Instant::now();
    let mut reader = format::open_reader(&args.input)?;
    let replace = format::Replace::when(args.force.force);
    let mut writer = format::create_writer_as(&args.output, out_format, replace)?;
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
        "{} → {} ({}): {} events in {:.3} s = {:.1} M events/s",
        args.input.display(),
        args.output.display(),
        out_format.name(),
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
    Ok(())
}
