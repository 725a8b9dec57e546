"""``SensorBank.forget_history``: bounded memory on endless streams, the same events."""

from __future__ import annotations

import numpy as np

from taxelkit.frames import TactileFrames
from taxelkit.smart.bank import SensorBank
from taxelkit.smart.recogniser import recognise

PITCH_MM = 1.7625


def bars(seed: int, n_frames: int) -> np.ndarray:
    """Bars and blobs that appear, move and lift, at random."""
    rng = np.random.default_rng(seed)
    frames = np.zeros((n_frames, 16, 16), bool)
    j = int(rng.integers(0, 15))
    while j < n_frames:
        length, width = int(rng.integers(20, 80)), int(rng.integers(1, 4))
        row, col, step = int(rng.integers(2, 12)), int(rng.integers(1, 6)), int(rng.integers(0, 2))
        for k in range(j, min(n_frames, j + length)):
            c = min(col + step * (k - j) // 6, 12)
            frames[k, row : row + width, c : c + 4] = True
        j += length + int(rng.integers(5, 30))
    return frames


def test_forgetting_the_history_keeps_the_events_and_bounds_what_is_kept() -> None:
    streams = np.stack([bars(s, 600) for s in range(3)])
    t_s = np.arange(600) / 20.0
    bank = SensorBank(3, (16, 16), pitch_mm=PITCH_MM)
    got: list[list[object]] = [[], [], []]
    for a in range(0, 600, 50):
        for k, e in bank.push_many(streams[:, a : a + 50], t_s[a : a + 50]):
            got[k].append(e)
        bank.forget_history(events_kept=4)
        assert all(len(bank.classes(k)) == 0 for k in range(3))
    for k, e in bank.flush():
        got[k].append(e)
    for k in range(3):
        want = list(recognise(TactileFrames(streams[k], t_s, pitch_mm=PITCH_MM)).events)
        assert got[k] == want and len(want) > 20
        kept = bank.result(k).events
        assert len(kept) < len(want) and list(kept) == want[len(want) - len(kept) :]
