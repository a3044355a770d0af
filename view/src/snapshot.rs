//! `neurotac view --snapshot`: the frame of a stream at a chosen time, made without a
//! browser by the same monitor (and drawn by the same [`draw_frame`](crate::draw_frame)) as the
//! live page.

use crate::error::ViewError;
use crate::frame::{Frame, PlayState};
use crate::monitor::{MonitorConfig, StreamMonitor};
use crate::player::StreamObserver;
use crate::source::{SourceRead, StreamSource};
use neurotac_core::EventBuffer;
use neurotac_sensor::taxel::TaxelLayout;

/// The frame of `source`'s stream at stream time `at_s` (s from its first event; `None`: its
/// end, the last pooling window closed as `neurotac transduce` closes it), with `observer`'s
/// decisions up to then. A read error names the file and offset; the time given is refused
/// when it is past the stream's end.
pub fn frame_at(
    source: &mut dyn StreamSource,
    observer: &mut dyn StreamObserver,
    layout: &TaxelLayout,
    config: MonitorConfig,
    at_s: Option<f64>,
) -> Result<Frame, ViewError> {
    let mut monitor = StreamMonitor::new(layout, config)?;
    let target_us = at_s.map(|t| (t * 1e6).round() as i64);
    let mut chunk = EventBuffer::new();
    let mut cut = EventBuffer::new();
    let ended = loop {
        chunk.clear();
        if source.read(&mut chunk).map_err(ViewError::Source)? == SourceRead::End {
            break true;
        }
        let (Some(&first), Some(target)) = (chunk.t.first(), target_us) else {
            push(&mut monitor, observer, &chunk)?;
            continue;
        };
        let origin = monitor.origin_us().unwrap_or(first);
        let keep = chunk.t.partition_point(|&t| t - origin <= target);
        if keep == chunk.len() {
            push(&mut monitor, observer, &chunk)?;
            continue;
        }
        cut.clear();
        chunk.iter().take(keep).for_each(|e| cut.push(e));
        push(&mut monitor, observer, &cut)?;
        monitor.advance_to(origin + target);
        break false;
    };
    if ended {
        if let (Some(at), Some(elapsed)) = (at_s, monitor.elapsed_us())
            && (at * 1e6).round() as i64 > elapsed
        {
            return Err(ViewError::PastTheEnd {
                at_s: at,
                end_s: elapsed as f64 * 1e-6,
            });
        }
        monitor.finish();
        observer.finish();
    }
    let state = match ended {
        true => PlayState::Ended,
        false => PlayState::Snapshot,
    };
    let mut frame = monitor.frame(1, &source.label(), state, None);
    frame.class_names = observer.class_names();
    frame.decisions = observer.decisions();
    Ok(frame)
}

fn push(
    monitor: &mut StreamMonitor,
    observer: &mut dyn StreamObserver,
    events: &EventBuffer,
) -> Result<(), ViewError> {
    monitor.push(events)?;
    observer.push(events);
    Ok(())
}
