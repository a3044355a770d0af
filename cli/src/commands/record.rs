//! `neurotac record --out FILE --duration T`: records the first DAVIS240 attached to an event file
//! (format from the extension; `.aedat4` writes AEDAT 4.0 with LZ4) that states the camera's
//! DVS size.
//!
//! The camera gets libcaer's default configuration and streams DVS events only. If it is
//! unplugged mid-recording, every event received before is written, the file is completed and
//! the command fails with the disconnection.

use super::options::{ForceOption, OutPathOption, help};
use super::outputs::{Output, check_outputs};
use crate::commands::args::{self, Time};
use anyhow::Context;
use clap::Args;
use neurotac_sensor::davis::{Davis, RusbTransport, StartOptions, record};
use neurotac_sensor::format;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

#[derive(Debug, Args)]
#[command(mut_args(help("out", "Output event file (.aedat4, .aedat, .aedat3, .txt or .csv)")))]
pub struct RecordArgs {
    #[command(flatten)]
    out: OutPathOption,
    #[command(flatten)]
    force: ForceOption,
    /// Recording duration (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_duration, allow_negative_numbers = true, long)]
    duration: Time,
    /// Add the host's Unix time at start (µs) to the device timestamps, as DV recordings hold
    /// (AEDAT 4.0 only: the 32-bit AEDAT 2.0 timestamps cannot hold it).
    #[arg(long)]
    unix_time: bool,
}

pub fn run(args: RecordArgs) -> anyhow::Result<()> {
    let out = &args.out.out;
    check_outputs([Output::file("--out", out)], args.force.force)?;
    let format = format::Format::from_extension(out)?;
    let (transport, usb) = RusbTransport::open_first()?;
    let davis = Davis::open(transport, usb).context("opening the DAVIS camera")?;
    println!(
        "recording {} ({}×{}) for {} to {}",
        davis.info().chip_name(),
        davis.info().dvs_size_x,
        davis.info().dvs_size_y,
        args.duration,
        out.display()
    );
    davis
        .send_default_config()
        .context("configuring the camera")?;
    let sensor = (davis.info().dvs_size_x, davis.info().dvs_size_y);
    let replace = format::Replace::when(args.force.force);
    let mut writer = format::create_writer_as(out, format, sensor, replace)?;
    let mut stream = davis.start(StartOptions::default())?;
    let offset_us = if args.unix_time {
        SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map(|d| d.as_micros() as i64)
            .unwrap_or(0)
    } else {
        0
    };
    let duration = Duration::from_secs_f64(args.duration.s());
    let rec = record(&mut stream, &mut *writer, duration, offset_us)
        .with_context(|| format!("writing {}", out.display()))?;
    println!(
        "{} events in {:.2} s; {} USB packets dropped (ring full); {} out-of-range addresses dropped",
        rec.events,
        rec.elapsed.as_secs_f64(),
        rec.dropped_packets,
        rec.decode.dropped_x_out_of_range + rec.decode.ignored_y_out_of_range
    );
    if let Some(e) = rec.ended_early {
        return Err(anyhow::Error::new(e).context(format!(
            "recording ended early; the {} events received were written to {}",
            rec.events,
            out.display()
        )));
    }
    Ok(())
}
