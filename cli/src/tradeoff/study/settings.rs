//! What a study sweeps: the families ([`Family`]) and their settings ([`Setting`]), the
//! reference first.

use super::TradeoffError;
use neurotac_core::SpikeDataset;
use neurotac_experiments::afferents::AfferentConfig;
use neurotac_experiments::menu::Menu;
use neurotac_experiments::neuron_setup::{NeuronKind, Precision};
use neurotac_experiments::readouts::{EncodedSet, VrFrom, encode_offline, encode_through_graph};
use neurotac_sensor::sim::paper_transduction;
use neurotac_sensor::sim::params::SolverParams;
use neurotac_sensor::taxel::TransductionConfig;

/// A swept family of settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// Where the spatiotemporal coding's Van Rossum distance comes from.
    VanRossum,
    /// The afferent layer of a model (`reproduce --afferents`).
    Afferents(NeuronKind),
    /// The transduction's pooling and background-activity windows (simulated sets only).
    Transduction,
    /// The simulator's numerical settings (simulated sets only).
    Simulator,
}

impl Family {
    /// File stem and folder name: `vr`, `afferents-lif`.
    pub fn stem(self) -> String {
        match self {
            Family::VanRossum => "vr".into(),
            Family::Afferents(kind) => format!("afferents-{}", kind.key()),
            Family::Transduction => "transduction".into(),
            Family::Simulator => "simulator".into(),
        }
    }

    /// Title in the report.
    pub fn title(self) -> String {
        match self {
            Family::VanRossum => "Van Rossum distance: exact vs synaptic traces".into(),
            Family::Afferents(kind) => format!("{} afferent layer", kind.label()),
            Family::Transduction => "Transduction: pooling and BA windows".into(),
            Family::Simulator => "Simulator: solver tolerances".into(),
        }
    }

    /// What the numerical-error columns measure.
    pub fn error_name(self) -> &'static str {
        match self {
            Family::VanRossum => "distance relative error",
            Family::Afferents(_) | Family::Transduction | Family::Simulator => {
                "spike-time error (ms)"
            }
        }
    }

    /// The settings swept, the reference (exact or finest) first; `quick` sweeps fewer.
    pub fn settings(self, quick: bool) -> Vec<Setting> {
        match self {
            Family::VanRossum => {
                let dts_ms: &[f64] = match quick {
                    true => &[0.1, 1.0, 5.0, 20.0],
                    false => &[0.1, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0],
                };
                let mut out = vec![Setting::vr(VrFrom::Exact)];
                for &dt_ms in dts_ms {
                    for precision in [Precision::F64, Precision::F32] {
                        out.push(Setting::vr(VrFrom::Traces {
                            trace_dt_s: dt_ms * 1e-3,
                            precision,
                        }));
                    }
                }
                out
            }
            Family::Afferents(kind) => {
                let reference = AfferentConfig::of(kind);
                let dts_ms: &[f64] = match quick {
                    true => &[0.1, 1.0],
                    false => &[0.1, 0.25, 0.5, 1.0, 2.0],
                };
                let mut out = Vec::new();
                for &integrator in kind.integrators() {
                    for &dt_ms in dts_ms {
                        // f32 at the reference step only: its error is the rounding's.
                        let precisions: &[Precision] = match dt_ms == 0.1 {
                            true => &[Precision::F64, Precision::F32],
                            false => &[Precision::F64],
                        };
                        for &precision in precisions {
                            out.push(Setting::afferents(AfferentConfig {
                                integrator,
                                dt_s: dt_ms * 1e-3,
                                precision,
                                ..reference
                            }));
                        }
                    }
                }
                // Clock-driven at every step, with the reference's integrator and precision.
                for &dt_ms in dts_ms {
                    out.push(Setting::afferents(AfferentConfig {
                        dt_s: dt_ms * 1e-3,
                        automatic_stepping: false,
                        ..reference
                    }));
                }
                out
            }
            Family::Transduction => {
                let paper = paper_transduction();
                let (pools_ms, bas_ms): (&[i64], &[Option<i64>]) = match quick {
                    true => (&[10, 40], &[None, Some(2), Some(10)]),
                    false => (&[5, 10, 40], &[None, Some(1), Some(2), Some(10), Some(20)]),
                };
                let mut out = vec![Setting::transduction(paper)];
                for &pool_ms in pools_ms {
                    out.push(Setting::transduction(TransductionConfig {
                        pool_window_us: pool_ms * 1000,
                        ..paper
                    }));
                }
                for &ba_ms in bas_ms {
                    out.push(Setting::transduction(TransductionConfig {
                        ba_window_us: ba_ms.map(|ms| ms * 1000),
                        ..paper
                    }));
                }
                out
            }
            Family::Simulator => {
                // The finest of every setting first, then the defaults, then each setting
                // coarsened alone from the finest.
                let finest = SolverParams {
                    step_tolerance: 0.02,
                    mechanics_dt_s: 0.25e-3,
                    shear_dt_s: 25e-6,
                    ..SolverParams::default()
                };
                let (tolerances, mechanics_ms, shear_us): (&[f64], &[f64], &[f64]) = match quick {
                    true => (&[0.3], &[2.0], &[200.0]),
                    false => (&[0.067, 0.3], &[1.0, 2.0], &[100.0, 200.0]),
                };
                let mut out = vec![
                    Setting::solver(finest),
                    Setting::solver(SolverParams::default()),
                ];
                out.extend(tolerances.iter().map(|&step_tolerance| {
                    Setting::solver(SolverParams {
                        step_tolerance,
                        ..finest
                    })
                }));
                out.extend(mechanics_ms.iter().map(|&ms| {
                    Setting::solver(SolverParams {
                        mechanics_dt_s: ms * 1e-3,
                        ..finest
                    })
                }));
                out.extend(shear_us.iter().map(|&us| {
                    Setting::solver(SolverParams {
                        shear_dt_s: us * 1e-6,
                        ..finest
                    })
                }));
                out
            }
        }
    }
}

/// One setting of a family: how the set is encoded before the codings read it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setting {
    /// The Van Rossum distance exact or from traces.
    pub vr_from: VrFrom,
    /// The afferent layer, if any.
    pub afferents: Option<AfferentConfig>,
    /// The transduction of a re-simulated set ([`resimulate`](super::resimulate)); `None`: the set as
    /// given.
    pub transduction: Option<TransductionConfig>,
    /// The simulator's numerical settings of a re-simulated set; `None`: the set as given.
    pub solver: Option<SolverParams>,
}

impl Setting {
    fn vr(vr_from: VrFrom) -> Self {
        Self {
            vr_from,
            afferents: None,
            transduction: None,
            solver: None,
        }
    }

    fn afferents(config: AfferentConfig) -> Self {
        Self {
            afferents: Some(config),
            ..Self::vr(VrFrom::Exact)
        }
    }

    fn transduction(config: TransductionConfig) -> Self {
        Self {
            transduction: Some(config),
            ..Self::vr(VrFrom::Exact)
        }
    }

    fn solver(solver: SolverParams) -> Self {
        Self {
            solver: Some(solver),
            ..Self::vr(VrFrom::Exact)
        }
    }

    /// The setting as a table names it: `exact`, `traces 1 ms f32`,
    /// `exact 0.1 ms f64 auto`, `pool 20 ms, BA 5 ms`,
    /// `tolerance 0.067, mechanics 0.5 ms, shear 50 µs`.
    pub fn label(&self) -> String {
        if let Some(p) = self.solver {
            return format!(
                "tolerance {}, mechanics {} ms, shear {} µs",
                p.step_tolerance,
                p.mechanics_dt_s * 1e3,
                (p.shear_dt_s * 1e6).round()
            );
        }
        if let Some(t) = self.transduction {
            let ba = t
                .ba_window_us
                .map_or_else(|| "off".to_owned(), |us| format!("{} ms", us as f64 / 1e3));
            return format!("pool {} ms, BA {ba}", t.pool_window_us as f64 / 1e3);
        }
        match (self.afferents, self.vr_from) {
            (Some(a), _) => format!(
                "{} {} ms {} {}",
                a.integrator,
                a.dt_s * 1e3,
                a.precision.name(),
                if a.automatic_stepping {
                    "auto"
                } else {
                    "clock"
                }
            ),
            (None, VrFrom::Exact) => "exact".into(),
            (
                None,
                VrFrom::Traces {
                    trace_dt_s,
                    precision,
                },
            ) => format!("traces {} ms {}", trace_dt_s * 1e3, precision.name()),
        }
    }

    /// Encodes `data` as this setting says: the offline encoders without afferents (what
    /// `reproduce`'s pipeline reads), the readout network with them.
    pub fn encode(&self, data: &SpikeDataset) -> Result<EncodedSet, TradeoffError> {
        Ok(match self.afferents {
            None => encode_offline(data, self.vr_from)?,
            Some(a) => encode_through_graph(data, Some(a), self.vr_from, &|| {})?,
        })
    }
}
