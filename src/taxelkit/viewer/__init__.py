"""A live view of the smart sensor in rerun (optional extra: ``pip install "taxelkit[viewer]"``).

The core of taxelkit never imports this package; rerun itself is imported
only when a :class:`RerunView` is created.
"""

from taxelkit.viewer.rerun_view import (
    ENTITY_PATHS,
    RerunView,
    ViewerDependencyError,
    check_viewer_available,
    view_recognition,
)

__all__ = [
    "ENTITY_PATHS",
    "RerunView",
    "ViewerDependencyError",
    "check_viewer_available",
    "view_recognition",
]
