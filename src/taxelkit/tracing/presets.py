"""Named tracer settings: the paper's reading and taxelkit's robust default.

:data:`ROBUST_DETECTOR` / :data:`ROBUST_TRACER` are the defaults of
:class:`~taxelkit.tracing.edge_estimate.EdgeDetectorConfig` and
:class:`~taxelkit.tracing.tracer.TracerConfig`:

* the dead zone adapts to the noise measured at each point
  (:mod:`taxelkit.neuron.dead_zone`): ``max(10 um, 4 sigma)`` above each
  scan's baseline (a tilt's slope is a baseline);
* where the noise raised the dead zone (a rough plate), an edge needs a line
  of at least :data:`~taxelkit.tracing.edge_estimate.ROBUST_MIN_EDGE_CROSSINGS`
  crossings, a line is kept only when
  :data:`~taxelkit.tracing.edge_estimate.ROBUST_MIN_VOTE_AGREEMENT` of its
  crossings agree on the raised side, and the first sighting of the edge is
  confirmed before tracing starts.

On a clean plate the dead zone stays at the paper's 10 um and none of the
extra tests applies, so the robust tracer gives the faithful tracer's traces
bit for bit (``fig7``, ``fig8``, ``fig9`` and ``recall-vs-s`` are unchanged;
``tests/tracing`` checks it).

:data:`FAITHFUL_DETECTOR` / :data:`FAITHFUL_TRACER` are the paper's reading:
Eq. 9 with the fixed dead zone
:data:`~taxelkit.tracing.edge_estimate.DEFAULT_EPSILON` (10 um), every line
with three crossings taken as an edge, the first sighting kept.

Loops are called closed only around a plausible contour in both
(:mod:`taxelkit.tracing.loop_closure`).
"""

from __future__ import annotations

from taxelkit.tracing.edge_estimate import EdgeDetectorConfig
from taxelkit.tracing.tracer import TracerConfig

__all__ = [
    "FAITHFUL_DETECTOR",
    "FAITHFUL_TRACER",
    "ROBUST_DETECTOR",
    "ROBUST_TRACER",
    "TRACER_PRESETS",
]

#: The paper's fixed dead zone, Eq. 9.
FAITHFUL_DETECTOR = EdgeDetectorConfig(dead_zone="fixed")
#: The tracer with :data:`FAITHFUL_DETECTOR` and unconfirmed first sightings.
FAITHFUL_TRACER = TracerConfig(detector=FAITHFUL_DETECTOR, confirm_edge=False)
#: Noise-adaptive dead zone and edge test (the default).
ROBUST_DETECTOR = EdgeDetectorConfig()
#: The default tracer.
ROBUST_TRACER = TracerConfig()
#: Presets by name.
TRACER_PRESETS: dict[str, TracerConfig] = {"faithful": FAITHFUL_TRACER, "robust": ROBUST_TRACER}
