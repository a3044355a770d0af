"""An independent NumPy reference of the multi-unit Van Rossum distance, from its definition.

Houghton & Sen with pymuvr's normalisation (shared/specs/van-rossum.md §1.2):

    D²(U, V) = Σ_ij C_ij (⟨u_i,u_j⟩ + ⟨v_i,v_j⟩ − ⟨u_i,v_j⟩ − ⟨v_i,u_j⟩),   C = (1 − c)·I + c·11ᵀ
    ⟨a, b⟩ = Σ_{s∈a} Σ_{t∈b} exp(−|s − t| / τ)

computed by brute force: every kernel value of every pair of spikes (O(n²)), summed per pair of
units with one-hot matrices. No markage, no decomposition, nothing shared with the Rust code.
"""

import numpy as np


def unit_gram(a, b, n_units, tau):
    """G[i, j] = ⟨a_i, b_j⟩ for two observations (lists of unit spike-time lists)."""
    ta = np.concatenate([np.asarray(u, dtype=float) for u in a] + [np.empty(0)])
    tb = np.concatenate([np.asarray(u, dtype=float) for u in b] + [np.empty(0)])
    la = np.repeat(np.arange(len(a)), [len(u) for u in a]).astype(int)
    lb = np.repeat(np.arange(len(b)), [len(u) for u in b]).astype(int)
    kernel = np.exp(-np.abs(ta[:, None] - tb[None, :]) / tau)
    one_a = np.zeros((len(ta), n_units))
    one_a[np.arange(len(ta)), la] = 1.0
    one_b = np.zeros((len(tb), n_units))
    one_b[np.arange(len(tb)), lb] = 1.0
    return one_a.T @ kernel @ one_b


def squared_distance(u, v, cos, tau):
    """(D², scale): D² clamped at 0, and Σ C ⊙ (G_uu + G_vv), the size of the terms that cancel
    (rounding errors are relative to it)."""
    n_units = len(u)
    c = (1.0 - cos) * np.eye(n_units) + cos * np.ones((n_units, n_units))
    uu, vv = unit_gram(u, u, n_units, tau), unit_gram(v, v, n_units, tau)
    uv, vu = unit_gram(u, v, n_units, tau), unit_gram(v, u, n_units, tau)
    d2 = np.sum(c * (uu + vv - uv - vu))
    return max(d2, 0.0), np.sum(c * (uu + vv))


def matrices(rows, columns, cos, tau):
    """(D², scale) matrices between every row observation and every column observation (each
    pair once when both are the same list: D² is symmetric by definition)."""
    d2 = np.zeros((len(rows), len(columns)))
    scale = np.zeros_like(d2)
    for i, u in enumerate(rows):
        for j, v in enumerate(columns):
            if rows is columns and j < i:
                d2[i, j], scale[i, j] = d2[j, i], scale[j, i]
            else:
                d2[i, j], scale[i, j] = squared_distance(u, v, cos, tau)
    return d2, scale


def assert_close(distances, rows, columns, cos, tau, rtol=1e-9):
    """Asserts that the distances D (a NumPy matrix) match the reference: |D² − D²_ref| at most
    `rtol`·D²_ref plus 1e-12 of the cancelling terms (van-rossum.md §3: D² cancels to about
    1e-15 of them for near-identical samples)."""
    d2_ref, scale = matrices(rows, columns, cos, tau)
    d2 = np.asarray(distances) ** 2
    assert d2.shape == d2_ref.shape
    error = np.abs(d2 - d2_ref)
    bound = rtol * d2_ref + 1e-12 * scale
    worst = np.unravel_index(np.argmax(error - bound), error.shape) if error.size else None
    assert np.all(error <= bound), (
        f"entry {worst}: D² {d2[worst]!r} vs reference {d2_ref[worst]!r} (scale {scale[worst]!r})"
    )
