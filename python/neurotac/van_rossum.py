"""The exact multi-unit Van Rossum distance with pymuvr's arguments and normalisation.

``square_distance_matrix(observations, cos, tau)`` and
``distance_matrix(observations1, observations2, cos, tau)`` take what pymuvr takes (a list of
observations, each a list of units, each a list of spike times) and return the same values as
pymuvr 1.3.3, as float64 NumPy matrices, computed in Rust without the GIL (keyword ``threads``:
worker threads, default all cores or ``RAYON_NUM_THREADS``). They are exact where pymuvr is not
(repeated spike times, unsorted trains, times far from 0) and accept NumPy arrays, tuples and
empty lists. ``square_distance_matrix_flat(times, units, offsets, n_units, cos, tau)`` takes a
dataset's flat arrays instead of lists.
"""

from ._native import distance_matrix, square_distance_matrix, square_distance_matrix_flat

__all__ = ["distance_matrix", "square_distance_matrix", "square_distance_matrix_flat"]
