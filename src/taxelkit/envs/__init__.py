"""gymnasium environments (optional extra: ``pip install "taxelkit[gym]"``).

Importing this package registers ``taxelkit/EdgeTrace-v0`` and
``taxelkit/ActiveTouch-v0`` with gymnasium::

    import gymnasium as gym
    import taxelkit.envs  # noqa: F401  (registers the ids)

    env = gym.make("taxelkit/EdgeTrace-v0")

(``gym.make("taxelkit.envs:taxelkit/EdgeTrace-v0")`` imports it for you.) The
core of taxelkit never imports this package.
"""

try:
    import gymnasium  # noqa: F401  (checked first, for a clear message)
except ImportError as _exc:  # pragma: no cover - depends on the install
    raise ImportError(
        'taxelkit.envs needs gymnasium, which is not installed: pip install "taxelkit[gym]"'
    ) from _exc

from taxelkit.envs.active_touch import ActiveTouchEnv
from taxelkit.envs.edge_trace import EdgeTraceEnv
from taxelkit.envs.registration import ENV_IDS, register_envs

__all__ = ["ENV_IDS", "ActiveTouchEnv", "EdgeTraceEnv", "register_envs"]

register_envs()
