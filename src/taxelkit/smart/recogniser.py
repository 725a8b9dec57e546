"""The smart tactile sensor of paper 001: Levels 1-4, batch and streaming.

:func:`recognise` processes a whole recording (vectorised Levels 1-2, run-length
debounce, per-segment Level 3); :class:`~taxelkit.smart.streaming.SmartSensor`
(re-exported here) takes frames as they come and emits
:class:`~taxelkit.smart.elimination.Event` objects as they happen, and
:class:`~taxelkit.smart.bank.SensorBank` does so for many arrays at once.
All see only frames, timestamps and the pitch; for the same frames they
produce the same events.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive, check_threshold
from taxelkit.frames import DEFAULT_FRAME_INTERVAL_S, TactileFrames
from taxelkit.smart.cleaning import CleaningConfig, clean_images
from taxelkit.smart.contact_classes import (
    DEFAULT_CONFIDENCE,
    HAND_SET,
    ContactClass,
    ContactNetwork,
    classify_contacts,
)
from taxelkit.smart.contact_limits import ContactLimits, apply_limits
from taxelkit.smart.levels12 import (
    DEFAULT_CLEANING,
    DEFAULT_LIMITS,
    DEFAULT_THRESHOLD_MM,
    half_length,
)
from taxelkit.smart.levels34 import Levels34, Recognition, finish, track_segments
from taxelkit.smart.line_extents import line_extents
from taxelkit.smart.moments import binary_images, image_stats
from taxelkit.smart.streaming import SmartSensor
from taxelkit.smart.tactemes import (
    SegmentTrack,
    TactemeConfig,
    accepted_runs,
    debounce_counts,
)

_NONE = int(ContactClass.NONE)
#: Accepted runs whose Level 3 the batch recogniser computes together.
_RUNS_TOGETHER = 128

__all__ = ["DEFAULT_CLEANING", "DEFAULT_LIMITS", "Recognition", "SmartSensor", "recognise"]


def _levels34_for_runs(
    runs: list[tuple[int, int, NDArray[np.intp]]],
    track_of: Any,
    config: TactemeConfig,
    frame_interval_s: float | None = None,
) -> Levels34:
    """Levels 3-4 over the accepted runs of a whole recording (batch).

    The segments' Level 3 is computed :data:`_RUNS_TOGETHER` runs at a time
    (:func:`~taxelkit.smart.levels34.track_segments`), so that their tracks
    are not all held at once.
    """
    state = Levels34(config, frame_interval_s)
    for a in range(0, len(runs), _RUNS_TOGETHER):
        part = runs[a : a + _RUNS_TOGETHER]
        contact = [i for i, (cls, _, _) in enumerate(part) if cls != _NONE]
        items = [(part[i][0], track_of(part[i][2]), None) for i in contact]
        segs = dict(zip(contact, track_segments(items, config), strict=True))
        for i, (cls, accept, _) in enumerate(part):
            state.open_run(cls, accept, segs.get(i))
    return state


def recognise(
    recording: TactileFrames | ArrayLike,
    *,
    threshold: float | None = None,
    pitch_mm: float | None = None,
    network: ContactNetwork = HAND_SET,
    confidence: float = DEFAULT_CONFIDENCE,
    config: TactemeConfig | None = None,
    cleaning: CleaningConfig | None = DEFAULT_CLEANING,
    limits: ContactLimits | None = DEFAULT_LIMITS,
) -> Recognition:
    """Recognise the object(s) touching the sensor in a recording (batch).

    Parameters
    ----------
    recording : TactileFrames or (T, rows, cols) array
        Bool contact images or float deflections.
    threshold : float, optional
        Contact threshold for float frames (in the recording's units); default
        0.03 mm, the Bonneville preset's. Ignored for bool frames.
    pitch_mm : float, optional
        Overrides the recording's pitch (required for a bare array).
    network : ContactNetwork
        Level 2 network (hand-set by default).
    confidence : float
        Level 2 confidence.
    config : TactemeConfig, optional
        Level 3 thresholds.
    cleaning : CleaningConfig or None
        Image cleaning before Level 1 (:mod:`taxelkit.smart.cleaning`);
        None feeds the thresholded images to Level 1 as paper 001 does.
    limits : ContactLimits or None
        Level 2 limits in mm and taxels, with hysteresis
        (:mod:`taxelkit.smart.contact_limits`); None keeps the network's classes.

    Returns
    -------
    Recognition
    """
    cfg = TactemeConfig() if config is None else config
    if isinstance(recording, TactileFrames):
        frames = recording.frames
        t_s = np.asarray(recording.t_s, dtype=np.float64)
        pitch = recording.pitch_mm if pitch_mm is None else check_positive("pitch_mm", pitch_mm)
    else:
        frames = np.asarray(recording)
        t_s = np.arange(frames.shape[0], dtype=np.float64) * DEFAULT_FRAME_INTERVAL_S
        if pitch_mm is None:
            raise InputError("pitch_mm is required when recording is a bare array")
        pitch = check_positive("pitch_mm", pitch_mm)
    thr = DEFAULT_THRESHOLD_MM if threshold is None else check_threshold("threshold", threshold)
    images = binary_images(frames, None if frames.dtype == bool else thr)
    if cleaning is not None and images.ndim == 3:
        images = clean_images(images, t_s, config=cleaning)
    stats = image_stats(images, pitch_mm=pitch)
    classes = classify_contacts(stats, network, confidence=confidence)
    half = half_length(stats)
    if limits is not None:
        classes = apply_limits(
            classes,
            stats.n_taxels,
            2.0 * half,
            stats.elongation,
            limits,
            area_mm2=stats.area_mm2,
            t_s=t_s if images.ndim == 3 else None,
        ).astype(np.int8)

    extent = np.full((classes.size, 2), np.nan)
    lines = np.flatnonzero(classes == ContactClass.LINE)
    if lines.size:
        stack = images.reshape(-1, *images.shape[-2:])
        extent[lines] = line_extents(
            stack[lines], stats.centre_mm[lines], stats.orientation_deg[lines], pitch
        )

    def track_of(idx: NDArray[np.intp]) -> SegmentTrack:
        return SegmentTrack(
            idx,
            stats.centre_mm[idx],
            stats.orientation_deg[idx],
            stats.area_mm2[idx],
            stats.elongation[idx],
            half[idx],
            t_s[idx],
            extent[idx],
            float(pitch),
        )

    dt = float(t_s[1] - t_s[0]) if t_s.size > 1 else None
    k, k_none = debounce_counts(cfg, dt)
    runs = accepted_runs(classes, k, k_none=k_none)
    state = _levels34_for_runs(runs, track_of, cfg, dt)
    return finish(
        classes,
        state.events,
        list(state.slips.values()),
        objects=cfg.objects,
        unread_gap_s=state.unread_gap_s,
        blip_s=cfg.blip_s,
        frame_interval_s=dt,
        last_frame=int(classes.size) - 1,
    )
