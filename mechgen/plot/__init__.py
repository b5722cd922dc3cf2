"""Pictures of a mechanism with matplotlib: one instant drawn, a sweep animated, quantities
plotted against time or each other, assembly modes side by side.

Everything is computed from the generated module (``POINTS``, ``BODIES``, ``JOINTS``,
``BODY_POINTS`` and its compiled ``points``) and from solved coordinates: numpy and
matplotlib only, never sympy. Every function takes ``ax=None`` (a new figure when None)
and returns what it drew.

What a drawing shows, read off the constraints:

- every moving body as a bar (two points) or a rounded plate (more) through its points,
  in its own colour;
- revolute joints as pins; a pin on the ground gets a pivot triangle on a hatched base,
  and grey bars join the ground's pivots (a four-bar's fixed link);
- ``point_on_line``: a slot cut along the axis body (over the travel the point makes) and a
  block sliding in it; on the ground, a hatched guide;
- ``translate``: the sliding body as a box along its axis on a hatched guide (ground; the
  box on the side away from the ground's other points, the same in every picture) or a
  slot (another body);
- ``relative_distance``: a connecting rod between its two points;
- optionally the point labels P1, P2, ... and each body's local axes, as in seed 001's
  "DEFINICION GRAFICA" pages; labels are placed where they overlap no other label, line,
  hatching or pin, and a point several bodies share gets one label, "P2·P1" (P2 of the
  first body, P1 of the second, each number in its body's colour).

Custom artists per body (the seed's Disk, Bar, Edge) go in ``artists={"manivela":
Disk(1, 4.0)}``: shapes in the body's local frame, numbered like its points (0 the origin).

The modules, each importing only those above it (and mechgen.errors, mechgen.runtime):

=============  =====================================================================
style          ink, the body palette, the size of details
scene          the bodies, points and joints a generated module states; body poses
shapes         plane geometry (hull, rounded, hatch) and custom shapes (Disk, Bar, ...)
labels         point labels placed where they collide with nothing
glyphs         the Builder: a glyph for every joint and body, labels, axes, the frame
drawing        Drawing, draw, draw_modes, motion
animation      Animation, animate, check_movie_path (one period: no repeated frame)
timeplot       plot, unit (time T, no made-up units, twin y axes, paths at equal scale)
forceplots     effort (a driver's torque over a cycle, its mean and peak), polar (a pin
               force's polar diagram)
arrows         force_arrows: the forces of a solution on a drawing (draw(forces=...))
bands          band_plot: tolerance bands against time (mech.tolerance: worst case, RSS,
               the Monte Carlo envelope; or each less the nominal)
=============  =====================================================================
"""
from .animation import Animation, animate, check_movie_path
from .arrows import ForceArrows, force_arrows
from .bands import band_plot
from .drawing import Drawing, draw, draw_modes, motion
from .forceplots import EffortPlot, PolarPlot, effort, polar
from .glyphs.shapes import AUTO, Bar, Disk, Edge, Plate, Shape
from .timeplot import plot, unit

# the settings of the look, readable as plot.INK etc. (as before the split)
from .animation import MOVIES  # noqa: F401
from .drawing import MOTION_POINTS  # noqa: F401
from .style import BAR, INK, MARGIN, PALETTE  # noqa: F401

__all__ = ["draw", "draw_modes", "animate", "plot", "motion", "unit", "Drawing", "Animation",
           "Shape", "Disk", "Bar", "Edge", "Plate", "AUTO", "check_movie_path",
           "effort", "polar", "force_arrows", "EffortPlot", "PolarPlot", "ForceArrows",
           "band_plot"]
