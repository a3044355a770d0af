//! `neurotac devices`: lists the DAVIS cameras attached over USB (VID 0x152A, PID 0x841B FX2 or
//! 0x841A FX3) and what each reports about itself.

use clap::Args;
use neurotac_sensor::davis::{Davis, RusbTransport, list_devices};

#[derive(Debug, Args)]
pub struct DevicesArgs {
    /// Only list the USB identities; do not open the cameras to read chip, logic and size.
    #[arg(long)]
    no_open: bool,
}

pub fn run(args: DevicesArgs) -> anyhow::Result<()> {
    let devices = match list_devices() {
        Ok(d) => d,
        Err(e) => {
            println!("{e}");
            return Ok(());
        }
    };
    if devices.is_empty() {
        println!("no DAVIS camera found (USB VID 0x152A, PID 0x841B FX2 or 0x841A FX3)");
        return Ok(());
    }
    for d in devices {
        println!(
            "DAVIS {} at bus {} address {}: firmware {}, serial {}",
            d.board(),
            d.bus,
            d.address,
            d.firmware,
            d.serial.as_deref().unwrap_or("(unreadable)")
        );
        if args.no_open {
            continue;
        }
        match RusbTransport::open(&d).and_then(|t| Davis::open(t, d.clone())) {
            Ok(davis) => {
                let i = davis.info();
                println!(
                    "  {} {}×{}, logic {} patch {}, logic clock {:.1} MHz, {}",
                    i.chip_name(),
                    i.dvs_size_x,
                    i.dvs_size_y,
                    i.logic_version,
                    i.logic_patch,
                    i.logic_clock_mhz,
                    if i.is_master {
                        "timestamp master"
                    } else {
                        "timestamp slave"
                    }
                );
            }
            Err(e) => println!("  cannot be used: {e}"),
        }
    }
    Ok(())
}
