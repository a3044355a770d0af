//! Speed ↔ accuracy trade-offs (`neurotac tradeoff`). [`study`] is the command without a
//! subcommand: classification accuracy of the four codings (Wilson interval, McNemar against
//! the reference setting) against cost, per swept family, with a recommended operating point.
//! The trades below measure one trade's numerical error alone (`tradeoff neurons|vr|simulator`):
//! each measures rows, marks their Pareto front ([`pareto`]) and writes `<stem>.csv`,
//! `<stem>.md` and `<stem>.svg` through the shared [`Table`] and [`write_trade`].
//!
//! | module | trade |
//! |---|---|
//! | [`neurons`] | model × integrator × dt × precision × spike stamping: updates/s against spike-time error |
//! | [`vr`] | exact vs synaptic-trace Van Rossum distance (trace dt × f32/f64): matrix time against LOO accuracy |
//! | [`simulator`] | pixel-model step tolerance: trials/s against event-timing error |
//!
//! To add a trade: a module with a config, a measuring function, its rows' `COLUMNS` and one
//! `cells(row)` building one [`Table`] for `to_csv`, `to_markdown` and `pareto_table` (a
//! [`Column`] or a [`Cell`] where the CSV and the Markdown table differ), `to_svg` built on
//! [`error_series`], and a `report` that measures and writes.

mod error;
pub mod neurons;
pub mod pareto;
pub mod simulator;
pub mod study;
mod table;
pub mod vr;

pub use error::TradeoffError;
pub use table::{
    Cell, Column, Table, error_series, mark_front, trade_files, write_files, write_trade,
};
