"""The KNN head on hand-computed cases, and the four codings."""

import numpy as np
import pytest

import neurotac
from neurotac import coding, van_rossum

# Five training samples on a line at 0, 1, 2, 10, 11 with classes 0, 0, 1, 1, 1.
POSITIONS = np.array([0.0, 1.0, 2.0, 10.0, 11.0])
LABELS = np.array([0, 0, 1, 1, 1])
SQUARE = np.abs(POSITIONS[:, None] - POSITIONS[None, :])


def test_predict_and_leave_one_out_by_hand():
    knn = neurotac.Knn(3).fit(LABELS)
    assert knn.k == 3 and "3" in repr(knn)
    # New samples at 0.4 (neighbours 0, 1, 2 → votes 0, 0, 1) and 9 (neighbours 10, 11, 2).
    new = np.abs(np.array([0.4, 9.0])[:, None] - POSITIONS[None, :])
    assert knn.predict(new).tolist() == [0, 1]
    # Leave-one-out: sample 0 → {1, 2, 10} = 0, 1, 1 → 1; sample 1 → {0, 2, 10} → 1 (0, 1, 1);
    # sample 2 → {1, 0, 10} = 0, 0, 1 → 0; samples 3, 4 → 1.
    assert neurotac.Knn(3).fit(LABELS).leave_one_out(SQUARE).tolist() == [1, 1, 0, 1, 1]


def test_tie_rules():
    # Vote tie 2–2 (k = 4): the smallest label wins, whichever is nearer.
    knn = neurotac.Knn(4).fit([5, 2, 5, 2])
    assert knn.predict([[0.1, 0.2, 0.3, 0.4]]).tolist() == [2]
    # Distance tie at the k-th neighbour: the lowest index wins.
    knn = neurotac.Knn(1).fit([7, 3, 9])
    assert knn.predict([[1.0, 1.0, 1.0]]).tolist() == [7]
    assert knn.predict([[2.0, 1.0, 1.0]]).tolist() == [3]


def test_knn_errors():
    with pytest.raises(neurotac.NeurotacValueError, match="k must be at least 1"):
        neurotac.Knn(0)
    with pytest.raises(neurotac.NeurotacValueError, match="not fitted"):
        neurotac.Knn(1).predict([[0.0]])
    with pytest.raises(neurotac.NeurotacValueError, match="k = 6 but the training set has only 5 samples"):
        neurotac.Knn(6).fit(LABELS)
    with pytest.raises(neurotac.NeurotacValueError, match="k = 5 but the training set has only 4 samples"):
        neurotac.Knn(5).fit(LABELS).leave_one_out(SQUARE)
    with pytest.raises(neurotac.NeurotacValueError, match="distance between samples 0 and 1 is -1"):
        neurotac.Knn(1).fit([0, 1]).predict([[1.0, -1.0]])
    with pytest.raises(neurotac.NeurotacValueError, match="distance matrix is 1×3 but there are 2 labels"):
        neurotac.Knn(1).fit([0, 1]).predict([[1.0, 2.0, 3.0]])


# Two samples of two units: a = {0.010, 0.0205}, {}; b = {0.001}, {0.004, 0.0309}.
TWO = neurotac.from_pymuvr([[[0.010, 0.0205], []], [[0.001], [0.004, 0.0309]]], labels=[0, 1])


def test_feature_codings_by_hand():
    assert coding.intensive(TWO).tolist() == [[1.0], [1.5]]
    assert coding.spatial(TWO).tolist() == [[2.0, 0.0], [1.0, 2.0]]
    # Δt = 10 ms over T = 31 ms (one ms past the latest spike): 22 windows [s, s + 10) ms of the
    # pooled counts divided by 2 units.
    features = coding.temporal(TWO, 0.010)
    assert features.shape == (2, 22)
    for row, spikes_ms in zip(features, ([10, 20], [1, 4, 30])):
        expected = [sum(s <= b < s + 10 for b in spikes_ms) / 2 for s in range(22)]
        assert row.tolist() == expected
    assert coding.temporal(TWO, 0.010, duration=0.040).shape == (2, 31)


def test_coding_distances():
    spatial = coding.distances(TWO, "spatial")
    assert spatial[0, 1] == pytest.approx(np.sqrt(5.0), rel=1e-15)
    assert coding.distances(TWO, "intensive")[1, 0] == 0.5
    temporal = coding.distances(TWO, "temporal", dt=0.010)
    features = coding.temporal(TWO, 0.010)
    assert temporal[0, 1] == pytest.approx(np.linalg.norm(features[0] - features[1]), rel=1e-12)
    vr = coding.spatiotemporal(TWO, tau=0.01, cos=0.5)
    assert np.array_equal(vr, van_rossum.square_distance_matrix(neurotac.to_pymuvr(TWO), 0.5, 0.01))
    assert np.array_equal(coding.distances(TWO, "spatiotemporal", tau=0.01, cos=0.5), vr)


def test_coding_errors_carry_the_library_message():
    with pytest.raises(neurotac.NeurotacValueError, match="temporal coding needs the window Δt"):
        coding.distances(TWO, "temporal")
    with pytest.raises(neurotac.NeurotacValueError, match="dt = 0.0105: a whole number of milliseconds"):
        coding.temporal(TWO, 0.0105)
    with pytest.raises(neurotac.NeurotacValueError, match=r"unknown coding 'rate' \(expected one of: intensive, spatial, temporal, spatiotemporal\)"):
        coding.distances(TWO, "rate")
    with pytest.raises(neurotac.NeurotacValueError, match="cos = 2: in \\[0, 1\\]"):
        coding.spatiotemporal(TWO, tau=0.01, cos=2.0)
