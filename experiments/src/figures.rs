//! Paper-style figures of taxel spike trains (SVG): the raster of Fig. "spike trains", with
//! its spatial (spikes per taxel) and temporal (rolling-window) distributions.

use crate::svg::{Axis, Chart, Marker, PALETTE, Series, panels};
use neurotac_core::MultiSpikeTrain;

/// A raster: one row of ticks per taxel (y = taxel index, x = time in s).
pub fn raster_chart(trains: &MultiSpikeTrain, title: &str) -> Chart {
    let points = trains
        .channels()
        .enumerate()
        .flat_map(|(c, times)| times.iter().map(move |&t| (t, c as f64)))
        .collect();
    Chart {
        title: title.to_owned(),
        x: Axis::linear("time (s)"),
        y: Axis {
            label: "taxel".into(),
            log: false,
            range: Some((-1.0, trains.n_channels() as f64)),
        },
        series: vec![Series {
            label: format!("{} spikes", trains.total_spikes()),
            points,
            color: "#222".into(),
            marker: Marker::Tick,
            filled: true,
            line: false,
        }],
    }
}

/// Spikes per taxel (the spatial coding's view).
pub fn spatial_chart(trains: &MultiSpikeTrain, title: &str) -> Chart {
    let points = trains
        .counts()
        .iter()
        .enumerate()
        .map(|(c, &n)| (c as f64, n as f64))
        .collect();
    Chart {
        title: title.to_owned(),
        x: Axis {
            label: "taxel".into(),
            log: false,
            range: Some((-1.0, trains.n_channels() as f64)),
        },
        y: Axis::linear("spikes"),
        series: vec![Series {
            label: "spikes per taxel".into(),
            points,
            color: PALETTE[0].into(),
            marker: Marker::Square,
            filled: true,
            line: false,
        }],
    }
}

/// Spikes per taxel in a window of `window_s` rolled in 1 ms steps over `[0, end)` (the
/// temporal coding's view): value at `s` = spikes in `[s, s + window)` over all taxels / N.
pub fn temporal_chart(trains: &MultiSpikeTrain, window_s: f64, title: &str) -> Chart {
    let pooled = trains.pooled();
    let end = pooled.last().copied().unwrap_or(0.0).max(window_s);
    let n = trains.n_channels().max(1) as f64;
    let steps = ((end - window_s).max(0.0) / 1e-3).floor() as usize + 1;
    let points = (0..steps)
        .map(|k| {
            let s = k as f64 * 1e-3;
            let lo = pooled.partition_point(|&t| t < s);
            let hi = pooled.partition_point(|&t| t < s + window_s);
            (s, (hi - lo) as f64 / n)
        })
        .collect();
    Chart {
        title: title.to_owned(),
        x: Axis::linear("window start (s)"),
        y: Axis::linear(&format!("spikes per taxel in {:.0} ms", window_s * 1e3)),
        series: vec![Series {
            label: format!("Δt = {:.0} ms", window_s * 1e3),
            points,
            color: PALETTE[1].into(),
            marker: Marker::None,
            filled: false,
            line: true,
        }],
    }
}

/// The three views stacked (raster, spatial, temporal) as one SVG document.
pub fn spike_train_figure(trains: &MultiSpikeTrain, title: &str, window_s: f64) -> String {
    panels(
        &[
            raster_chart(trains, title),
            spatial_chart(trains, "spatial distribution"),
            temporal_chart(trains, window_s, "temporal distribution"),
        ],
        1,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_show_every_spike_and_the_rolling_mean() {
        let trains =
            MultiSpikeTrain::from_channels(vec![vec![0.01, 0.5], vec![], vec![0.2]]).unwrap();
        let raster = raster_chart(&trains, "t");
        assert_eq!(
            raster.series[0].points,
            vec![(0.01, 0.0), (0.5, 0.0), (0.2, 2.0)]
        );
        let temporal = temporal_chart(&trains, 0.1, "t");
        // Window [0.2, 0.3) holds one spike of three taxels.
        assert_eq!(temporal.series[0].points[200], (0.2, 1.0 / 3.0));
        let svg = spike_train_figure(&trains, "3 taxels", 0.1);
        assert!(svg.matches("<line x1").count() >= 3);
        assert!(svg.contains("spatial distribution") && svg.contains("temporal distribution"));
    }
}
