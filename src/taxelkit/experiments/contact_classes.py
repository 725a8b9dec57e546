"""Experiment ``contact-classes``: Level 2 of the smart sensor, hand-set and trained.

Labelled contact images are simulated on the Bonneville array (point: sphere,
vertex, apex; line: cylinder side, cube and tetrahedron edges; area: faces),
half for training by back-propagation and half held out. Both the hand-set
network (paper 001: "weights calculated by hand") and the trained one are
scored on the held-out half.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from taxelkit.smart.contact_classes import HAND_SET, ContactNetwork
from taxelkit.smart.contact_training import (
    ClassificationScore,
    score_network,
    train_contact_network,
)
from taxelkit.smart.training_data import ContactSamples, contact_training_samples

__all__ = ["ContactClassesResult", "run_contact_classes"]


@dataclass(frozen=True, eq=False)
class ContactClassesResult:
    """Samples, the trained network and both networks' held-out scores."""

    samples: ContactSamples
    trained: ContactNetwork
    hand_set: ClassificationScore
    learnt: ClassificationScore
    n_train: int

    def to_json(self) -> dict[str, Any]:
        """Held-out accuracies and indeterminate fractions of both networks."""

        def row(score: ClassificationScore) -> dict[str, float]:
            return {
                "accuracy": float(score.accuracy),
                "argmax_accuracy": float(score.argmax_accuracy),
                "indeterminate_fraction": float(score.indeterminate_fraction),
            }

        return {
            "experiment": "contact-classes",
            "samples": int(self.samples.labels.size),
            "trained_on": self.n_train,
            "hand_set": row(self.hand_set),
            "trained": row(self.learnt),
        }


def run_contact_classes(
    *, seed: int = 0, n_per_class: int = 300, progress: Callable[[int, int], None] | None = None
) -> ContactClassesResult:
    """Simulate labelled contacts, train on half, score both networks on the other half."""
    rng = np.random.default_rng(seed)
    samples = contact_training_samples(n_per_class=n_per_class, rng=rng)
    if progress is not None:
        progress(1, 3)
    order = rng.permutation(samples.labels.size)
    half = order.size // 2
    train, test = order[:half], order[half:]
    net = train_contact_network(samples.features[train], samples.labels[train], rng=rng)
    if progress is not None:
        progress(2, 3)
    hand = score_network(HAND_SET, samples.features[test], samples.labels[test])
    learnt = score_network(net, samples.features[test], samples.labels[test])
    if progress is not None:
        progress(3, 3)
    return ContactClassesResult(samples, net, hand, learnt, int(half))
