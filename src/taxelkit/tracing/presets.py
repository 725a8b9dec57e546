"""Named tracer settings: the paper's reading and taxelkit's robust tracer.

:data:`FAITHFUL_DETECTOR` / :data:`FAITHFUL_TRACER` are the defaults of
:class:`~taxelkit.tracing.edge_estimate.EdgeDetectorConfig` and
:class:`~taxelkit.tracing.tracer.TracerConfig`: Eq. 9 with the fixed dead zone
:data:`~taxelkit.tracing.edge_estimate.DEFAULT_EPSILON` (10 um), every line
with three crossings taken as an edge. They give the published ``fig7``,
``fig8``, ``fig9`` and ``recall-vs-s``.

:data:`ROBUST_DETECTOR` / :data:`ROBUST_TRACER` are for plates that are rough
or tilted (the ``trace-robustness`` experiment):

* the dead zone adapts to the noise measured at each point
  (:mod:`taxelkit.neuron.dead_zone`): ``max(10 um, 4 sigma)`` above each
  scan's baseline;
* an edge needs a line of at least :data:`ROBUST_MIN_EDGE_CROSSINGS`
  crossings (isolated pulses that survive the dead zone come in ones and
  twos; along the traces of the five specimens, clean or rough, the best line
  had 6 or more);
* a line is kept only when :data:`ROBUST_MIN_VOTE_AGREEMENT` of its crossings
  agree on the raised side (a bump is climbed and left at the same place:
  about half agree; along clean traces of the five specimens at least 0.7 did
  on all but a few second lines at star corners).

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
    "ROBUST_MIN_EDGE_CROSSINGS",
    "ROBUST_MIN_VOTE_AGREEMENT",
    "ROBUST_TRACER",
    "TRACER_PRESETS",
]

#: Crossings the best line needs in the robust tracer: one row or column of
#: the 6 x 6 active block of paper 000.
ROBUST_MIN_EDGE_CROSSINGS = 6
#: Fraction of a line's crossings that must agree on the raised side.
ROBUST_MIN_VOTE_AGREEMENT = 0.7

#: The paper's fixed dead zone (the library default).
FAITHFUL_DETECTOR = EdgeDetectorConfig()
#: The default tracer (faithful dead zone).
FAITHFUL_TRACER = TracerConfig()
#: Noise-adaptive dead zone and edge test.
ROBUST_DETECTOR = EdgeDetectorConfig(
    dead_zone="adaptive",
    min_vote_agreement=ROBUST_MIN_VOTE_AGREEMENT,
    min_edge_crossings=ROBUST_MIN_EDGE_CROSSINGS,
)
#: The tracer with :data:`ROBUST_DETECTOR`; :func:`~taxelkit.tracing.tracer.find_edge`
#: confirms a sighting before it starts.
ROBUST_TRACER = TracerConfig(detector=ROBUST_DETECTOR, confirm_edge=True)
#: Presets by name.
TRACER_PRESETS: dict[str, TracerConfig] = {"faithful": FAITHFUL_TRACER, "robust": ROBUST_TRACER}
