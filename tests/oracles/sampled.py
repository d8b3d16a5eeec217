"""A car's footprints at its samples, from a result document's numbers alone (its type's
width, front and rear overhangs and the rear-axle poses), for tests that judge with
shapely what cars covered."""

from __future__ import annotations

import numpy as np
import shapely


def footprints(car: dict) -> np.ndarray:
    """The car's footprint polygons at its samples (a ``result.json`` vehicle)."""
    s, ty = car["samples"], car["type"]
    x, y, th = (np.asarray(s[k]) for k in ("x", "y", "theta"))
    u = np.stack([np.cos(th), np.sin(th)], axis=1)
    w = np.stack([-np.sin(th), np.cos(th)], axis=1)
    c = np.stack([x, y], axis=1)
    corners = [c + u * a + w * b for a, b in ((-ty["rear"], -ty["width"] / 2),
                                              (ty["front"], -ty["width"] / 2),
                                              (ty["front"], ty["width"] / 2),
                                              (-ty["rear"], ty["width"] / 2))]
    return shapely.polygons(np.stack(corners, axis=1))
