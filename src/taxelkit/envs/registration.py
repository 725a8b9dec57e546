"""Registration of the taxelkit environments with gymnasium."""

from __future__ import annotations

from gymnasium.envs.registration import register, registry

__all__ = ["ACTIVE_TOUCH_ID", "EDGE_TRACE_ID", "ENV_IDS", "register_envs"]

EDGE_TRACE_ID = "taxelkit/EdgeTrace-v0"
ACTIVE_TOUCH_ID = "taxelkit/ActiveTouch-v0"
#: Every environment id and its entry point.
ENV_IDS = {
    EDGE_TRACE_ID: "taxelkit.envs.edge_trace:EdgeTraceEnv",
    ACTIVE_TOUCH_ID: "taxelkit.envs.active_touch:ActiveTouchEnv",
}


def register_envs() -> None:
    """Register every id of :data:`ENV_IDS` that gymnasium does not know yet."""
    for env_id, entry_point in ENV_IDS.items():
        if env_id not in registry:
            register(id=env_id, entry_point=entry_point)
