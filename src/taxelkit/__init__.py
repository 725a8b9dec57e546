"""taxelkit: sense and recognise shapes by touch with array tactile sensors."""

from taxelkit._version import __version__
from taxelkit.errors import InputError, RecordingError, TaxelkitError
from taxelkit.frames import TactileFrames

__all__ = ["InputError", "RecordingError", "TactileFrames", "TaxelkitError", "__version__"]
