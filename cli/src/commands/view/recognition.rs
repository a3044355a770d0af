//! The online recogniser as a [`StreamObserver`] of the view: one [`Recogniser`] per coding
//! on the same events as the page, started again with every stream (a rewind, the next slide).

use neurotac_core::EventBuffer;
use neurotac_experiments::online::{Decision, OnlineClassifier, Recogniser};
use neurotac_sensor::taxel::TransductionConfig;
use neurotac_view::{CodingDecisions, DecisionPoint, StreamObserver};

/// One recogniser per classifier (coding), as the page shows them.
pub struct Recognition<'a> {
    classifiers: &'a [OnlineClassifier<'a>],
    transduction: TransductionConfig,
    stable_windows: usize,
    live: Vec<Recogniser<'a>>,
    finals: Vec<Option<Decision>>,
}

impl<'a> Recognition<'a> {
    /// Recognisers of `classifiers`, transducing as `transduction` (the training set's, with
    /// the stream's own origin), stable after `stable_windows` windows.
    pub fn new(
        classifiers: &'a [OnlineClassifier<'a>],
        transduction: TransductionConfig,
        stable_windows: usize,
    ) -> anyhow::Result<Self> {
        Ok(Self {
            live: recognisers(classifiers, transduction, stable_windows)?,
            finals: vec![None; classifiers.len()],
            classifiers,
            transduction,
            stable_windows,
        })
    }
}

/// A fresh recogniser per classifier.
fn recognisers<'a>(
    classifiers: &'a [OnlineClassifier<'a>],
    transduction: TransductionConfig,
    stable_windows: usize,
) -> anyhow::Result<Vec<Recogniser<'a>>> {
    let made = (classifiers.iter()).map(|c| Recogniser::new(c, transduction, stable_windows));
    Ok(made.collect::<Result<_, _>>()?)
}

fn point(d: &Decision) -> DecisionPoint {
    DecisionPoint {
        t_s: d.t_s,
        class: d.class,
        vote_share: d.vote_share,
        tie: d.tie,
        stable: d.stable,
    }
}

impl StreamObserver for Recognition<'_> {
    fn push(&mut self, events: &EventBuffer) {
        for r in self.live.iter_mut().filter(|r| !r.is_done()) {
            // A bad event is the monitor's error too, which the page shows; the decisions
            // made before it stay.
            let _ = r.push(events);
        }
    }

    fn finish(&mut self) {
        for (r, last) in self.live.iter_mut().zip(&mut self.finals) {
            // No event at all: no decision to show.
            *last = r.finish().ok();
        }
    }

    fn restart(&mut self) {
        // The same settings made them before, so they are made again.
        if let Ok(live) = recognisers(self.classifiers, self.transduction, self.stable_windows) {
            self.live = live;
        }
        self.finals = vec![None; self.classifiers.len()];
    }

    fn class_names(&self) -> Vec<String> {
        self.classifiers
            .first()
            .map(|c| c.training().class_names().to_vec())
            .unwrap_or_default()
    }

    fn decisions(&self) -> Vec<CodingDecisions> {
        (self.classifiers.iter().zip(&self.live).zip(&self.finals))
            .map(|((c, r), last)| CodingDecisions {
                coding: c.coding().name.to_string(),
                history: r.decisions().iter().map(point).collect(),
                final_decision: last.as_ref().map(point),
            })
            .collect()
    }
}
