"""Live views in rerun of the smart sensor and the edge tracer.

Optional extra: ``pip install "taxelkit[viewer]"``.

The core of taxelkit never imports this package; rerun itself is imported
only when a :class:`RerunView` is created.
"""

from taxelkit.viewer.rerun_view import (
    ENTITY_PATHS,
    RerunView,
    ViewerConnectionError,
    ViewerDependencyError,
    check_viewer_available,
    view_recognition,
)
from taxelkit.viewer.trace_view import TRACE_ENTITY_PATHS, view_trace

__all__ = [
    "ENTITY_PATHS",
    "TRACE_ENTITY_PATHS",
    "RerunView",
    "ViewerConnectionError",
    "ViewerDependencyError",
    "check_viewer_available",
    "view_recognition",
    "view_trace",
]
