use super::*;
use crate::ranks::ThreadRanks;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `Σ_k Σ_l e^{−|u_k − v_l|/τ}` by brute force.
fn product(u: &[f64], v: &[f64], tau: f64) -> f64 {
    u.iter()
        .map(|a| v.iter().map(|b| (-(a - b).abs() / tau).exp()).sum::<f64>())
        .sum()
}

/// pymuvr's definition with every cross-unit term: `Σ_ij C_ij (⟨u_i,u_j⟩ + ⟨v_i,v_j⟩ − ⟨u_i,v_j⟩ − ⟨v_i,u_j⟩)`.
fn reference_d2(u: &MultiSpikeTrain, v: &MultiSpikeTrain, tau: f64, cos: f64) -> f64 {
    let p = u.n_channels();
    let mut d2 = 0.0;
    for i in 0..p {
        for j in 0..p {
            let c = if i == j { 1.0 } else { cos };
            let (ui, uj, vi, vj) = (u.channel(i), u.channel(j), v.channel(i), v.channel(j));
            d2 += c
                * (product(ui, uj, tau) + product(vi, vj, tau)
                    - product(ui, vj, tau)
                    - product(vi, uj, tau));
        }
    }
    d2.max(0.0)
}

fn trains(channels: Vec<Vec<f64>>) -> MultiSpikeTrain {
    MultiSpikeTrain::from_channels(channels).unwrap()
}

/// Random samples: `p` channels, up to `max_spikes` spikes each, 1-µs stamps in [0, span).
fn random_samples(
    n: usize,
    p: usize,
    max_spikes: usize,
    span: f64,
    seed: u64,
) -> Vec<MultiSpikeTrain> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            MultiSpikeTrain::from_unsorted_channels((0..p).map(|_| {
                let k = rng.random_range(0..=max_spikes);
                (0..k)
                    .map(|_| (rng.random::<f64>() * span * 1e6).floor() / 1e6)
                    .collect::<Vec<_>>()
            }))
            .unwrap()
        })
        .collect()
}

fn assert_rel(a: f64, b: f64, rel: f64, what: &str) {
    assert!(
        (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-300),
        "{what}: {a} vs {b} (relative {})",
        (a - b).abs() / a.abs().max(b.abs())
    );
}

#[test]
fn matches_the_full_cross_unit_definition_in_both_evaluations() {
    let samples = random_samples(6, 4, 12, 1.0, 1);
    for tau in [0.005, 0.05, 0.5, 5.0] {
        let vr = VanRossum::new(tau).unwrap();
        let centred = vr.prepare_with(&samples, true).unwrap();
        let decayed = vr.prepare_with(&samples, false).unwrap();
        assert!(centred.is_centred() && !decayed.is_centred());
        for i in 0..samples.len() {
            for j in 0..samples.len() {
                let (ll_c, sp_c) = centred.squared_parts(i, j);
                let (ll_d, sp_d) = decayed.squared_parts(i, j);
                for cos in [0.0, 0.25, 0.4, 1.0] {
                    let want = reference_d2(&samples[i], &samples[j], tau, cos);
                    let what = format!("τ={tau} c={cos} ({i},{j})");
                    assert_rel(combine_squared(ll_c, sp_c, cos), want, 1e-10, &what);
                    assert_rel(combine_squared(ll_d, sp_d, cos), want, 1e-10, &what);
                }
            }
        }
    }
}

#[test]
fn matrices_are_symmetric_with_zero_diagonal_and_agree_with_pairs() {
    let samples = random_samples(7, 3, 8, 0.5, 2);
    let vr = VanRossum::new(0.02).unwrap();
    let m = vr.matrices(&samples, &crate::OneProcess).unwrap();
    let d = m.distances(0.3).unwrap();
    for i in 0..7 {
        assert_eq!(d[[i, i]], 0.0);
        for j in 0..7 {
            assert_eq!(d[[i, j]], d[[j, i]]);
            let pair = vr.distance(&samples[i], &samples[j], 0.3).unwrap();
            // Identical samples cancel to ~1e-15 in D², ~3e-8 in D (the spec's tolerance: 1e-7 on D).
            assert!((d[[i, j]] - pair).abs() < 1e-7, "{i} {j}");
        }
    }
}

#[test]
fn squared_into_a_reused_matrix_of_any_shape_equals_squared() {
    let samples = random_samples(9, 3, 8, 0.5, 3);
    let m = VanRossum::new(0.02)
        .unwrap()
        .matrices(&samples, &crate::OneProcess)
        .unwrap();
    let mut out = Array2::from_elem((2, 5), f64::NAN);
    for cos in [0.0, 0.37, 1.0] {
        m.squared_into(cos, &mut out).unwrap();
        assert_eq!(out, m.squared(cos).unwrap(), "cos θ = {cos}");
    }
    // Matrices in another memory order combine the same.
    let transposed = VanRossumMatrices {
        tau_s: m.tau_s,
        ll2: m.ll2.t().as_standard_layout().into_owned().reversed_axes(),
        sp2: m.sp2.clone(),
    };
    assert!(!transposed.ll2.is_standard_layout());
    transposed.squared_into(0.37, &mut out).unwrap();
    assert_eq!(out, m.squared(0.37).unwrap());
    assert!(m.squared_into(1.5, &mut out).is_err());
}

#[test]
fn one_spike_against_an_empty_train_is_one() {
    let vr = VanRossum::new(0.076).unwrap();
    let one = trains(vec![vec![2.0], vec![]]);
    let empty = MultiSpikeTrain::empty(2);
    for cos in [0.0, 0.4, 1.0] {
        assert!((vr.distance(&one, &empty, cos).unwrap() - 1.0).abs() < 1e-12);
    }
    assert_eq!(vr.distance(&empty, &empty, 0.5).unwrap(), 0.0);
    // All-empty samples against each other, with no spike anywhere.
    let m = vr
        .matrices(&[empty.clone(), empty], &crate::OneProcess)
        .unwrap();
    assert_eq!(m.ll2.sum() + m.sp2.sum(), 0.0);
    // No samples at all.
    assert_eq!(
        vr.matrices(&[], &crate::OneProcess).unwrap().ll2.dim(),
        (0, 0)
    );
}

#[test]
fn coincident_spikes_are_counted_once_each_pair_even_when_repeated() {
    let vr = VanRossum::new(0.01).unwrap();
    // ⟨[0.1],[0.1,0.1]⟩ = 2, so d² = 1 + 4 − 4 = 1 (pymuvr gets 3 here); identical ⇒ 0.
    let a = trains(vec![vec![0.1]]);
    let b = trains(vec![vec![0.1, 0.1]]);
    assert!((vr.squared_distance(&a, &b, 0.0).unwrap() - 1.0).abs() < 1e-12);
    assert_eq!(vr.squared_distance(&b, &b.clone(), 0.0).unwrap(), 0.0);
    // Pooled trains: two channels spiking together form a within-train repeat of SP².
    let u = trains(vec![vec![0.1], vec![0.1]]);
    let v = trains(vec![vec![0.1], vec![]]);
    let m = vr
        .matrices(&[u.clone(), v.clone()], &crate::OneProcess)
        .unwrap();
    assert!((m.sp2[[0, 1]] - 1.0).abs() < 1e-12, "SP² = 4 + 1 − 2·2");
    assert!((m.ll2[[0, 1]] - 1.0).abs() < 1e-12);
    assert_eq!(
        vr.matrices(&[u.clone(), u], &crate::OneProcess)
            .unwrap()
            .sp2[[0, 1]],
        0.0
    );
}

#[test]
fn long_tau_gives_spike_count_distances() {
    let samples = random_samples(5, 4, 10, 4.5, 3);
    let vr = VanRossum::new(1e7).unwrap();
    let m = vr.matrices(&samples, &crate::OneProcess).unwrap();
    for i in 0..5 {
        for j in 0..5 {
            let dn: Vec<f64> = (0..4)
                .map(|c| samples[i].count(c) as f64 - samples[j].count(c) as f64)
                .collect();
            let ll = dn.iter().map(|x| x * x).sum::<f64>();
            let sp = dn.iter().sum::<f64>().powi(2);
            assert!(
                (m.ll2[[i, j]] - ll).abs() <= 1e-5 * ll.max(1.0),
                "LL² {i} {j}"
            );
            assert!(
                (m.sp2[[i, j]] - sp).abs() <= 1e-5 * sp.max(1.0),
                "SP² {i} {j}"
            );
        }
    }
}

#[test]
fn short_tau_counts_non_coincident_spikes() {
    // 1-µs stamps, τ = 1 ns: only exact coincidences survive (neighbours give e^{−1000}).
    let u = trains(vec![vec![0.001, 0.002, 0.002, 0.5], vec![0.3]]);
    let v = trains(vec![vec![0.002, 0.400], vec![0.3, 0.300001]]);
    for tau in [1e-9, 1e-12] {
        let vr = VanRossum::new(tau).unwrap();
        let m = vr
            .matrices(&[u.clone(), v.clone()], &crate::OneProcess)
            .unwrap();
        // Channel 0: ⟨u,u⟩ = 4 + 2 (the repeated 0.002), ⟨v,v⟩ = 2, ⟨u,v⟩ = 2 ⇒ 4.
        // Channel 1: 1 + 2 − 2·1 = 1.
        assert!(
            (m.ll2[[0, 1]] - 5.0).abs() < 1e-12,
            "τ={tau}: {}",
            m.ll2[[0, 1]]
        );
        // Pooled: u = {.001,.002,.002,.3,.5}, v = {.002,.3,.300001,.4}: 5+2 + 4 − 2·3 = 5.
        assert!(
            (m.sp2[[0, 1]] - 5.0).abs() < 1e-12,
            "τ={tau}: {}",
            m.sp2[[0, 1]]
        );
    }
    // 1 µs neighbours at τ = 1 µs still give e^{−1}.
    let vr = VanRossum::new(1e-6).unwrap();
    let d2 = vr
        .squared_distance(&trains(vec![vec![1.0]]), &trains(vec![vec![1.000001]]), 0.0)
        .unwrap();
    assert!((d2 - (2.0 - 2.0 * (-1.0f64).exp())).abs() < 1e-9, "{d2}");
}

#[test]
fn translation_and_scale_invariant_and_stable_far_from_zero() {
    let samples = random_samples(5, 3, 10, 4.5, 4);
    let shift = |by: f64, scale: f64| -> Vec<MultiSpikeTrain> {
        samples
            .iter()
            .map(|o| {
                MultiSpikeTrain::from_channels(
                    o.channels()
                        .map(|c| c.iter().map(|t| (t + by) * scale).collect::<Vec<_>>()),
                )
                .unwrap()
            })
            .collect()
    };
    for tau in [1e-6, 0.076, 1.0, 1e4] {
        let base = VanRossum::new(tau)
            .unwrap()
            .matrices(&samples, &crate::OneProcess)
            .unwrap();
        for (by, scale) in [(1e5, 1.0), (-1e5, 1.0), (0.0, 1e3), (0.0, 1e-3)] {
            let moved = VanRossum::new(tau * scale)
                .unwrap()
                .matrices(&shift(by, scale), &crate::OneProcess)
                .unwrap();
            for (a, b) in base
                .ll2
                .iter()
                .zip(&moved.ll2)
                .chain(base.sp2.iter().zip(&moved.sp2))
            {
                assert!(a.is_finite() && b.is_finite());
                // Shifting by 10⁵ s perturbs each stamp by up to 1.5e-11 s (the f64 spacing).
                let tol = 1e-8 * a.abs().max(1.0) + if by != 0.0 { 4.0e-11 / tau } else { 0.0 };
                assert!(
                    (a - b).abs() <= tol,
                    "τ={tau} shift={by} scale={scale}: {a} vs {b}"
                );
            }
        }
    }
}

#[test]
fn tiny_and_huge_tau_never_overflow() {
    let samples = random_samples(4, 2, 10, 4.5, 5);
    for tau in [1e-300, 1e-12, 1e-3, 1e3, 1e300] {
        let m = VanRossum::new(tau)
            .unwrap()
            .matrices(&samples, &crate::OneProcess)
            .unwrap();
        assert!(
            m.ll2
                .iter()
                .chain(m.sp2.iter())
                .all(|x| x.is_finite() && *x >= 0.0),
            "τ={tau}"
        );
    }
    // Times far beyond pymuvr's t/τ ≈ 11356 limit, positive and negative.
    let far = [
        trains(vec![vec![-1e9, 1e9]]),
        trains(vec![vec![-1e9 + 1e-3]]),
    ];
    let d2 = VanRossum::new(1e-3)
        .unwrap()
        .squared_distance(&far[0], &far[1], 0.0)
        .unwrap();
    // ⟨u,u⟩ = 2, ⟨v,v⟩ = 1, ⟨u,v⟩ = e^{−Δ/τ} with Δ the (exactly subtracted) gap.
    let gap = far[1].channel(0)[0] - far[0].channel(0)[0];
    let want = 3.0 - 2.0 * (-gap / 1e-3).exp();
    assert!((d2 - want).abs() < 1e-12, "{d2} vs {want}");
}

#[test]
fn exact_distance_equals_the_integral_of_the_filtered_trains() {
    // (2/τ)∫ Σ_ij C_ij δ_i δ_j dt by the midpoint rule on a τ/4000 grid.
    let samples = random_samples(2, 3, 5, 0.2, 6);
    let (u, v) = (&samples[0], &samples[1]);
    for (tau, cos) in [(0.02, 0.0), (0.02, 0.4), (0.05, 1.0)] {
        let h = tau / 4000.0;
        let end = 0.2 + 40.0 * tau;
        let f = |train: &[f64], t: f64| -> f64 {
            train
                .iter()
                .filter(|&&s| s <= t)
                .map(|s| (-(t - s) / tau).exp())
                .sum()
        };
        let steps = (end / h) as usize;
        let mut integral = 0.0;
        for k in 0..steps {
            let t = (k as f64 + 0.5) * h;
            let delta: Vec<f64> = (0..3)
                .map(|c| f(u.channel(c), t) - f(v.channel(c), t))
                .collect();
            let sum: f64 = delta.iter().sum();
            integral += (1.0 - cos) * delta.iter().map(|d| d * d).sum::<f64>() + cos * sum * sum;
        }
        let numeric = 2.0 / tau * integral * h;
        let exact = VanRossum::new(tau)
            .unwrap()
            .squared_distance(u, v, cos)
            .unwrap();
        assert!(
            (numeric - exact).abs() < 2e-3 * exact.max(1.0),
            "τ={tau} c={cos}: {numeric} vs {exact}"
        );
    }
}

#[test]
fn bad_parameters_and_shapes_are_typed_errors() {
    for tau in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            VanRossum::new(tau),
            Err(DistanceError::InvalidParameter { what: "tau_s", .. })
        ));
    }
    let vr = VanRossum::new(0.01).unwrap();
    let a = trains(vec![vec![0.1], vec![]]);
    for cos in [-0.1, 1.5, f64::NAN] {
        assert!(matches!(
            vr.squared_distance(&a, &a.clone(), cos),
            Err(DistanceError::InvalidParameter { what: "cos", .. })
        ));
    }
    let three = trains(vec![vec![], vec![], vec![0.2]]);
    assert!(matches!(
        vr.matrices(&[a.clone(), a, three], &crate::OneProcess)
            .unwrap_err(),
        DistanceError::ChannelCount {
            sample: 2,
            expected: 2,
            got: 3
        }
    ));
}

/// Random samples on a coarse time grid (many coincidences, crowded table cells), with varying
/// counts, an empty sample and a repeated one.
fn crowded_samples(seed: u64) -> Vec<MultiSpikeTrain> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut samples: Vec<MultiSpikeTrain> = (0..24)
        .map(|s| {
            MultiSpikeTrain::from_unsorted_channels((0..5).map(|_| {
                let k = rng.random_range(0..=(s % 6) * 8);
                (0..k)
                    .map(|_| rng.random_range(0..200u32) as f64 * 0.0025)
                    .collect::<Vec<_>>()
            }))
            .unwrap()
        })
        .collect();
    samples.push(MultiSpikeTrain::empty(5));
    samples.push(samples[7].clone());
    samples
}

#[test]
fn centred_tables_equal_the_decayed_merges_to_1e_12() {
    for (seed, tau) in [(7, 0.002), (8, 0.02), (9, 0.3), (10, 5.0)] {
        let samples = crowded_samples(seed);
        let vr = VanRossum::new(tau).unwrap();
        let centred = vr.prepare(&samples).unwrap();
        let decayed = vr.prepare_with(&samples, false).unwrap();
        assert!(centred.is_centred() && !decayed.is_centred());
        let (fast, reference) = (
            centred.matrices(&crate::OneProcess).unwrap(),
            decayed.matrices(&crate::OneProcess).unwrap(),
        );
        for (what, f, r) in [
            ("LL²", &fast.ll2, &reference.ll2),
            ("SP²", &fast.sp2, &reference.sp2),
        ] {
            for ((i, j), &a) in f.indexed_iter() {
                let b = r[[i, j]];
                // Relative to D² or, where D² cancels (nearly identical samples, long τ), to the
                // self products ⟨u,u⟩ + ⟨v,v⟩ it is the difference of (distances to the empty 24).
                let scale = a.abs().max(b.abs()).max(r[[i, 24]] + r[[j, 24]]);
                let tol = 1e-12 * scale;
                assert!((a - b).abs() <= tol, "τ={tau} {what} ({i},{j}): {a} vs {b}");
            }
        }
        // Pairs evaluated alone give exactly the matrix entries (same sums, same order).
        for (i, j) in [(0, 1), (5, 23), (24, 3), (25, 7), (11, 11)] {
            let (ll, sp) = centred.squared_parts(i, j);
            assert_eq!((ll, sp), (fast.ll2[[i, j]], fast.sp2[[i, j]]), "({i},{j})");
        }
        assert!(fast.ll2[[25, 7]] <= 1e-10 && fast.sp2[[25, 7]] <= 1e-10);
    }
}

#[test]
fn pairs_alone_in_either_order_equal_the_matrix_entries_bit_for_bit() {
    // Crowded cells (several spikes of one row in a cell), a last block of rows that is not
    // full, and rows split over ranks at arbitrary boundaries: each entry is still the sums of
    // its two samples alone, in their order, whichever of them is named first.
    let samples = crowded_samples(12);
    for (tau, allow_centred) in [(0.003, true), (0.04, true), (0.04, false)] {
        let vr = VanRossum::new(tau).unwrap();
        let prepared = vr.prepare_with(&samples, allow_centred).unwrap();
        assert_eq!(prepared.is_centred(), allow_centred);
        let one = prepared.matrices(&crate::OneProcess).unwrap();
        for i in 0..samples.len() {
            for j in 0..samples.len() {
                let entry = (one.ll2[[i, j]], one.sp2[[i, j]]);
                assert_eq!(prepared.squared_parts(i, j), entry, "τ={tau} ({i},{j})");
            }
        }
        for ranks in [2, 3, 5] {
            let split = ThreadRanks::run(ranks, |r| prepared.matrices(r).unwrap());
            assert!(split.iter().all(|m| *m == one), "τ={tau}, {ranks} ranks");
        }
    }
}

#[test]
fn matrices_are_identical_at_any_thread_count() {
    let samples = crowded_samples(11);
    let vr = VanRossum::new(0.01).unwrap();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| vr.matrices(&samples, &crate::OneProcess).unwrap())
    };
    let one = run(1);
    for threads in [2, 3, 5] {
        assert_eq!(run(threads), one, "{threads} threads");
    }
}

/// Asserts that `cross` (new × prepared) equals the entries `(n_prepared + i, j)` of the
/// `reference` matrices of the prepared samples, then the new ones, then an empty sample (at
/// `empty`), to 1e-12 of `D²` or, where `D²` cancels, of the self products `⟨u,u⟩ + ⟨v,v⟩`.
fn assert_cross_entries(
    cross: &VanRossumMatrices,
    reference: &VanRossumMatrices,
    n_prepared: usize,
    what: &str,
) {
    let empty = reference.ll2.nrows() - 1;
    assert_eq!(cross.ll2.dim(), (empty - n_prepared, n_prepared), "{what}");
    assert_eq!(cross.sp2.dim(), cross.ll2.dim(), "{what}");
    for (name, c, r) in [
        ("LL²", &cross.ll2, &reference.ll2),
        ("SP²", &cross.sp2, &reference.sp2),
    ] {
        for ((i, j), &a) in c.indexed_iter() {
            let row = n_prepared + i;
            let b = r[[row, j]];
            let scale = a.abs().max(b.abs()).max(r[[row, empty]] + r[[j, empty]]);
            assert!(
                (a - b).abs() <= 1e-12 * scale,
                "{what} {name} ({i},{j}): {a} vs {b}"
            );
        }
    }
}

/// The reference of [`assert_cross_entries`]: the square matrices of `prepared`, then `new`,
/// then an empty sample, each cut to its spikes `t < t_end_s`.
fn stacked_reference(
    vr: &VanRossum,
    prepared: &[MultiSpikeTrain],
    new: &[MultiSpikeTrain],
    t_end_s: f64,
) -> VanRossumMatrices {
    let channels = prepared[0].n_channels();
    let stacked: Vec<MultiSpikeTrain> = prepared
        .iter()
        .chain(new)
        .chain([&MultiSpikeTrain::empty(channels)])
        .map(|o| o.window(f64::NEG_INFINITY, t_end_s).unwrap())
        .collect();
    vr.matrices(&stacked, &crate::OneProcess).unwrap()
}

/// New samples for the cross tests: random ones, an empty one, one with empty channels, and
/// copies of prepared samples (identical samples).
fn new_samples(prepared: &[MultiSpikeTrain], seed: u64) -> Vec<MultiSpikeTrain> {
    let channels = prepared[0].n_channels();
    let mut new = random_samples(4, channels, 12, 0.5, seed);
    new.push(MultiSpikeTrain::empty(channels));
    let mut sparse = vec![Vec::new(); channels];
    sparse[channels - 1] = vec![0.25, 0.25, 0.3];
    new.push(trains(sparse));
    new.extend([prepared[3].clone(), prepared[prepared.len() - 1].clone()]);
    new
}

#[test]
fn cross_matrices_equal_the_stacked_square_matrices() {
    for (seed, tau) in [(21, 0.002), (22, 0.02), (23, 0.3), (24, 5.0)] {
        let prepared = crowded_samples(seed);
        let new = new_samples(&prepared, seed);
        let vr = VanRossum::new(tau).unwrap();
        let reference = stacked_reference(&vr, &prepared, &new, f64::INFINITY);
        for centred in [true, false] {
            let p = vr.prepare_with(&prepared, centred).unwrap();
            assert_eq!(p.is_centred(), centred);
            let cross = p.cross_matrices(&new).unwrap();
            assert_eq!(cross.tau_s, tau);
            let what = format!("τ={tau}, centred {centred}");
            assert_cross_entries(&cross, &reference, prepared.len(), &what);
            // Identical samples: D² ≈ 0 (rounding of ⟨u,u⟩ + ⟨v,v⟩ − 2⟨u,v⟩ only).
            let (n, last) = (new.len(), prepared.len() - 1);
            for (i, j) in [(n - 2, 3), (n - 1, last)] {
                let scale = reference.ll2[[j, prepared.len() + n]];
                assert!(cross.ll2[[i, j]] <= 1e-12 * scale.max(1.0), "{what}");
            }
            // The empty new sample: D² = ⟨b,b⟩ exactly as the reference's distance to ∅.
            for j in 0..prepared.len() {
                let (a, b) = (cross.sp2[[4, j]], reference.sp2[[j, prepared.len() + n]]);
                assert!((a - b).abs() <= 1e-12 * b, "{what}: {a} vs {b}");
            }
        }
    }
}

#[test]
fn cross_matrices_until_equal_preparing_the_prefixes_from_scratch() {
    let prepared = crowded_samples(31);
    let new = new_samples(&prepared, 31);
    // Cut before every spike, between spikes, exactly at a spike time (excluded), after all.
    let spike_time = prepared[5].channel(2)[0];
    for tau in [0.004, 0.05] {
        let vr = VanRossum::new(tau).unwrap();
        for centred in [true, false] {
            let p = vr.prepare_with(&prepared, centred).unwrap();
            for t_end_s in [f64::NEG_INFINITY, 0.0, 0.1013, spike_time, 0.3, 0.5, 10.0] {
                let reference = stacked_reference(&vr, &prepared, &new, t_end_s);
                let cross = p.cross_matrices_until(&new, t_end_s).unwrap();
                let what = format!("τ={tau}, centred {centred}, T={t_end_s}");
                assert_cross_entries(&cross, &reference, prepared.len(), &what);
            }
            // Up to T = +∞ is the whole comparison, bit for bit.
            assert_eq!(
                p.cross_matrices_until(&new, f64::INFINITY).unwrap(),
                p.cross_matrices(&new).unwrap()
            );
        }
    }
}

#[test]
fn cross_matrices_stay_exact_for_spike_times_far_apart() {
    // Prepared over [0, 1) s with τ = 1 ms: span/(2τ) = 500, so centred.
    let prepared = random_samples(8, 3, 10, 1.0, 41);
    let vr = VanRossum::new(1e-3).unwrap();
    let p = vr.prepare(&prepared).unwrap();
    assert!(p.is_centred());
    let shifted = |o: &MultiSpikeTrain, by: f64| {
        MultiSpikeTrain::from_channels(
            o.channels()
                .map(|c| c.iter().map(|t| t + by).collect::<Vec<_>>()),
        )
        .unwrap()
    };
    let new = vec![
        // Beyond the centred range on either side, and straddling it.
        shifted(&prepared[1], 1e5),
        shifted(&prepared[2], -1e9),
        trains(vec![vec![0.5, 3.0], vec![-2.0], vec![0.999]]),
        // Within it: the sweep, also before the first and after the last prepared spike.
        shifted(&prepared[3], 0.0004),
        trains(vec![vec![-0.15, 1.15], vec![], vec![1.1]]),
        prepared[4].clone(),
    ];
    for t_end_s in [f64::INFINITY, 0.6, 1e6] {
        let reference = stacked_reference(&vr, &prepared, &new, t_end_s);
        let cross = p.cross_matrices_until(&new, t_end_s).unwrap();
        assert!(
            cross
                .ll2
                .iter()
                .chain(&cross.sp2)
                .all(|x| x.is_finite() && *x >= 0.0)
        );
        assert_cross_entries(&cross, &reference, prepared.len(), &format!("T={t_end_s}"));
    }
}

#[test]
fn cross_matrices_check_channels_and_the_cut() {
    let prepared = random_samples(3, 2, 5, 1.0, 51);
    let p = VanRossum::new(0.01).unwrap().prepare(&prepared).unwrap();
    let two = MultiSpikeTrain::empty(2);
    let three = trains(vec![vec![0.1], vec![], vec![]]);
    assert!(matches!(
        p.cross_matrices(&[two.clone(), three.clone()]).unwrap_err(),
        DistanceError::ChannelCount {
            sample: 1,
            expected: 2,
            got: 3
        }
    ));
    assert!(matches!(
        p.cross_matrices_until(std::slice::from_ref(&two), f64::NAN),
        Err(DistanceError::InvalidParameter {
            what: "t_end_s",
            ..
        })
    ));
    // No new sample; nothing prepared (then any channel count).
    assert_eq!(p.cross_matrices(&[]).unwrap().ll2.dim(), (0, 3));
    let nothing = VanRossum::new(0.01).unwrap().prepare(&[]).unwrap();
    assert_eq!(
        nothing.cross_matrices(&[two, three]).unwrap().sp2.dim(),
        (2, 0)
    );
}

#[test]
fn cross_matrices_are_identical_at_any_thread_count() {
    let prepared = crowded_samples(61);
    let new = new_samples(&prepared, 61);
    let p = VanRossum::new(0.01).unwrap().prepare(&prepared).unwrap();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| p.cross_matrices_until(&new, 0.3).unwrap())
    };
    let one = run(1);
    for threads in [2, 3] {
        assert_eq!(run(threads), one, "{threads} threads");
    }
}

/// CPU time of the calling thread (s).
fn thread_cpu_s() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec through a valid pointer.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) };
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}

/// One live sample (49 channels × ~35 spikes) against 1100 prepared samples of the same size
/// over 4.5 s, τ = 76 ms, on one thread. Run by hand:
/// `cargo test --release -p neurotac-core cross_matrices_timing -- --ignored --nocapture`.
#[test]
#[ignore = "timing, run by hand"]
fn cross_matrices_timing() {
    let prepared = random_samples(1100, 49, 70, 4.5, 71);
    let live = random_samples(1, 49, 70, 4.5, 72);
    let spikes: usize = prepared.iter().map(MultiSpikeTrain::total_spikes).sum();
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    one_thread.install(|| {
        let cpu = thread_cpu_s();
        let p = VanRossum::new(0.076).unwrap().prepare(&prepared).unwrap();
        let prepared_cpu = thread_cpu_s();
        p.cross_matrices(&[]).unwrap(); // indexes the prepared samples
        eprintln!(
            "prepare {:.3} s, index {:.3} s CPU ({:.1} spikes per channel, centred: {})",
            prepared_cpu - cpu,
            thread_cpu_s() - prepared_cpu,
            spikes as f64 / (1100.0 * 49.0),
            p.is_centred()
        );
        for t_end_s in [f64::INFINITY, 2.25, f64::NEG_INFINITY] {
            let mut times: Vec<(f64, f64)> = (0..41)
                .map(|_| {
                    let (wall, cpu) = (std::time::Instant::now(), thread_cpu_s());
                    let m = p.cross_matrices_until(&live, t_end_s).unwrap();
                    std::hint::black_box(m);
                    let wall = wall.elapsed().as_secs_f64();
                    ((thread_cpu_s() - cpu) * 1e3, wall * 1e3)
                })
                .collect();
            times.sort_by(|a, b| a.0.total_cmp(&b.0));
            eprintln!(
                "1 × 1100 until T = {t_end_s} s: CPU min {:.2} ms, median {:.2} ms (wall {:.2} ms)",
                times[0].0, times[20].0, times[20].1
            );
        }
    });
}

#[test]
fn growing_live_sample_equals_the_prefix_cross_matrices_at_every_window() {
    // Training samples and a live one on a coarse time grid (many coincident spikes across
    // samples), the live one advanced in 20 ms windows, some empty.
    let train = random_samples(12, 5, 9, 1.0, 41);
    let live = random_samples(1, 5, 9, 1.0, 42).remove(0);
    for tau in [0.004, 0.05, 0.8] {
        let prepared = VanRossum::new(tau).unwrap().prepare(&train).unwrap();
        let growing = GrowingVanRossum::new(&train, tau).unwrap().unwrap();
        let mut state = growing.live();
        let mut previous = f64::NEG_INFINITY;
        for w in 1..=60 {
            let t_end = w as f64 * 0.02;
            let new: Vec<&[f64]> = live
                .channels()
                .map(|c| {
                    let from = c.partition_point(|&t| t < previous);
                    &c[from..c.partition_point(|&t| t < t_end)]
                })
                .collect();
            growing.advance(&mut state, &new, t_end).unwrap();
            previous = t_end;
            let m = prepared
                .cross_matrices_until(std::slice::from_ref(&live), t_end)
                .unwrap();
            for i in 0..train.len() {
                let (ll, sp) = growing.squared_parts(&state, i);
                let scale = 1.0 + m.ll2[[0, i]].max(m.sp2[[0, i]]);
                assert!(
                    (ll - m.ll2[[0, i]]).abs() <= 1e-9 * scale,
                    "τ {tau}, T {t_end}, {i}: LL² {ll} vs {}",
                    m.ll2[[0, i]]
                );
                assert!(
                    (sp - m.sp2[[0, i]]).abs() <= 1e-9 * scale,
                    "τ {tau}, T {t_end}, {i}: SP² {sp} vs {}",
                    m.sp2[[0, i]]
                );
            }
        }
    }
    // Going back in time, or a spike outside the window, changes nothing and is refused.
    let growing = GrowingVanRossum::new(&train, 0.05).unwrap().unwrap();
    let mut state = growing.live();
    let empty: Vec<&[f64]> = vec![&[]; 5];
    growing.advance(&mut state, &empty, 0.5).unwrap();
    assert!(growing.advance(&mut state, &empty, 0.4).is_err());
    let mut late: Vec<&[f64]> = vec![&[]; 5];
    late[2] = &[0.3];
    assert!(growing.advance(&mut state, &late, 0.6).is_err());
    // A span the centred exponentials cannot hold: None, use the prefix cross matrices.
    let far = vec![trains(vec![vec![0.0], vec![2000.0]])];
    assert!(GrowingVanRossum::new(&far, 1.0).unwrap().is_none());
}
