"""The look shared by every picture: ink, the body palette and the sizes of details."""
from __future__ import annotations

import numpy as np
from matplotlib.colors import to_rgb

BAR = 0.014          # bar half-width as a fraction of the frame's larger side
MARGIN = 0.05        # blank border around the motion, fraction of the larger side
PALETTE = (          # (fill, edge) per moving body, in body order: seed 001's pink, green, blue
    ("#ff9e9e", "#c0392b"), ("#8ddc8d", "#1e8449"), ("#a6a6ff", "#2e3fa8"),
    ("#ffd27f", "#b9770e"), ("#d9a8f0", "#7d3c98"), ("#8fe0e6", "#117a80"),
    ("#e2c395", "#7b5a2e"), ("#c8c8c8", "#4d4d4d"),
)
INK = "#222222"
GROUND = ("#d9d9d9", INK)   # (fill, edge) of the ground


def tints(color):
    """(fill, edge) for a body given one colour: the colour as edge, a paler fill."""
    rgb = np.array(to_rgb(color))
    fill = 1.0 - 0.45 * (1.0 - rgb)
    return tuple(fill), tuple(rgb)
