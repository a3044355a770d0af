//! Pareto fronts of speed ↔ accuracy measurements: the points no other point beats on both
//! speed (higher is better) and error (lower is better). Every `neurotac tradeoff` report uses
//! [`pareto_front`].

/// For each point, `true` when it is a candidate (`Some((speed, error))`) and no other
/// candidate is at least as fast and at least as accurate while strictly better on one of the
/// two. `None` marks a point that takes no part (e.g. a wrong spike count); it is never on the
/// front. Equal points are both kept.
pub fn pareto_front(points: &[Option<(f64, f64)>]) -> Vec<bool> {
    points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let Some((speed, error)) = *p else {
                return false;
            };
            !points.iter().enumerate().any(|(j, q)| {
                q.is_some_and(|(s, e)| {
                    j != i && s >= speed && e <= error && (s > speed || e < error)
                })
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dominated_and_excluded_points_are_off_the_front() {
        let points = [
            Some((10.0, 1.0)), // fastest, least accurate: on the front
            Some((5.0, 0.1)),  // on the front
            Some((4.0, 0.2)),  // beaten by (5, 0.1) on both
            Some((5.0, 0.1)),  // equal to a front point: kept
            None,              // excluded
            Some((1.0, 0.01)), // slowest, most accurate: on the front
            Some((10.0, 2.0)), // as fast as (10, 1) but worse: off
        ];
        assert_eq!(
            pareto_front(&points),
            [true, true, false, true, false, true, false]
        );
        assert!(pareto_front(&[]).is_empty());
        assert_eq!(pareto_front(&[None, Some((1.0, 1.0))]), [false, true]);
    }
}
