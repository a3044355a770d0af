"""The paper's four spike codings of a dataset dict.

``intensive(ds)``, ``spatial(ds)`` and ``temporal(ds, dt, duration=None)`` return feature
matrices (one row per sample); ``spatiotemporal(ds, tau, cos)`` the Van Rossum distance matrix;
``distances(ds, coding, dt=…, tau=…, cos=…)`` the N × N distance matrix of any of the four, as
``neurotac distances`` computes it (Euclidean on the features, Van Rossum for spatiotemporal).
"""

from ._native import distances, intensive, spatial, spatiotemporal, temporal

__all__ = ["distances", "intensive", "spatial", "spatiotemporal", "temporal"]
