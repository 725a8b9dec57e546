"""Experiment ``contact-classes``: Level 2 of the smart sensor, hand-set and trained.

Two data sets, both from the simulator side (:mod:`taxelkit.motion`):

* **pressed contacts** (:func:`~taxelkit.motion.contact_samples.pressed_contacts`):
  solids pressed in poses whose contact type is known by construction (point:
  sphere, vertex, apex; line: cylinder side, cube and tetrahedron edges; area:
  faces), half for training by back-propagation and half held out, as in
  paper 001 ("weights calculated by hand", trainable);
* **rolled contacts** (:func:`~taxelkit.motion.rolled_contacts.rolled_contacts`):
  the frames of whole rolls from every available motion engine (kinematic
  scripts, MuJoCo physics), seen through every sensor imperfection of the
  robustness experiment and cleaned as the robust recogniser cleans them,
  labelled by the ground-truth phase of each frame. A network is trained on
  the rolls of one set of seeds and scored, per engine and imperfection, on
  rolls of other seeds.

The hand-set network is scored on both; the figure shows every network's
decision regions with the samples it is judged on.
"""

from __future__ import annotations

import importlib.util
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.experiments.robustness import FAULTS
from taxelkit.motion.contact_samples import LabelledContacts, pressed_contacts
from taxelkit.motion.rolled_contacts import LabelledRoll, rolled_contacts
from taxelkit.smart.cleaning import clean_images
from taxelkit.smart.contact_classes import HAND_SET, ContactClass, ContactNetwork, contact_features
from taxelkit.smart.contact_training import (
    ClassificationScore,
    score_network,
    train_contact_network,
)
from taxelkit.smart.moments import image_stats
from taxelkit.smart.tacteme_table import OBJECTS

__all__ = ["ContactClassesResult", "RollSamples", "run_contact_classes"]

_CODE = {
    "point": int(ContactClass.POINT),
    "line": int(ContactClass.LINE),
    "area": int(ContactClass.AREA),
}
#: Imperfections the rolled contacts are seen through: the robustness experiment's.
ROLL_FAULTS: tuple[str, ...] = FAULTS


def features_of(samples: LabelledContacts) -> tuple[NDArray[np.float64], NDArray[np.int8]]:
    """``(area_mm2, elongation)`` and class codes of pressed contacts."""
    stats = image_stats(samples.images, pitch_mm=samples.pitch_mm)
    codes = np.array([_CODE[str(x)] for x in samples.labels], dtype=np.int8)
    return contact_features(stats), codes


@dataclass(frozen=True, eq=False)
class RollSamples:
    """Labelled frames of rolls, as the robust recogniser's Level 2 sees them.

    Attributes
    ----------
    features : (N, 2) float
    labels : (N,) int8
        Class codes.
    engine, fault : (N,) str
        Where each frame came from.
    """

    features: NDArray[np.float64]
    labels: NDArray[np.int8]
    engine: NDArray[np.str_]
    fault: NDArray[np.str_]


def roll_samples(rolls: list[LabelledRoll]) -> RollSamples:
    """Clean each roll, take the Level 1 features of its labelled, non-empty frames."""
    feats, labels, engines, faults = [], [], [], []
    for r in rolls:
        images = clean_images(r.recording.frames > r.threshold_mm, r.recording.t_s)
        stats = image_stats(images, pitch_mm=r.recording.pitch_mm)
        keep = (r.labels != "") & (stats.n_taxels > 0)
        feats.append(contact_features(stats)[keep])
        labels.append(np.array([_CODE[str(x)] for x in r.labels[keep]], dtype=np.int8))
        engines.append(np.full(int(keep.sum()), r.engine))
        faults.append(np.full(int(keep.sum()), r.fault))
    return RollSamples(
        np.concatenate(feats),
        np.concatenate(labels),
        np.concatenate(engines),
        np.concatenate(faults),
    )


@dataclass(frozen=True, eq=False)
class ContactClassesResult:
    """Samples, trained networks and held-out scores."""

    samples: LabelledContacts
    trained: ContactNetwork
    hand_set: ClassificationScore
    learnt: ClassificationScore
    n_train: int
    roll_test: RollSamples
    roll_trained: ContactNetwork
    roll_scores: dict[str, dict[str, dict[str, float]]]
    engines: tuple[str, ...]
    n_roll_train: int

    @property
    def features(self) -> NDArray[np.float64]:
        """Features of the pressed contacts."""
        return features_of(self.samples)[0]

    @property
    def labels(self) -> NDArray[np.int8]:
        """Class codes of the pressed contacts."""
        return features_of(self.samples)[1]

    def to_json(self) -> dict[str, Any]:
        """Held-out accuracies of the networks on pressed and on rolled contacts."""
        return {
            "experiment": "contact-classes",
            "samples": int(self.samples.labels.size),
            "trained_on": self.n_train,
            "hand_set": _row(self.hand_set),
            "trained": _row(self.learnt),
            "rolls": {
                "engines": list(self.engines),
                "faults": list(ROLL_FAULTS),
                "trained_on_frames": self.n_roll_train,
                "held_out_frames": int(self.roll_test.labels.size),
                "scores": self.roll_scores,
            },
        }


def _row(score: ClassificationScore) -> dict[str, float]:
    return {
        "accuracy": round(float(score.accuracy), 4),
        "argmax_accuracy": round(float(score.argmax_accuracy), 4),
        "indeterminate_fraction": round(float(score.indeterminate_fraction), 4),
    }


def _engines() -> tuple[str, ...]:
    return ("kinematic", "mujoco") if importlib.util.find_spec("mujoco") else ("kinematic",)


def run_contact_classes(
    *,
    seed: int = 0,
    n_per_class: int = 300,
    n_rolls: int = 2,
    progress: Callable[[int, int], None] | None = None,
) -> ContactClassesResult:
    """Train and score Level 2 networks on pressed and on rolled contacts.

    Parameters
    ----------
    seed : int
    n_per_class : int
        Pressed contacts per class.
    n_rolls : int
        Rolls per engine and object for training, and as many for testing.
    progress : callable, optional
    """
    rng = np.random.default_rng(seed)
    samples = pressed_contacts(n_per_class=n_per_class, rng=rng)
    feats, codes = features_of(samples)
    order = rng.permutation(codes.size)
    half = order.size // 2
    train, test = order[:half], order[half:]
    net = train_contact_network(feats[train], codes[train], rng=rng)
    hand = score_network(HAND_SET, feats[test], codes[test])
    learnt = score_network(net, feats[test], codes[test])
    if progress is not None:
        progress(1, 3)
    engines = _engines()
    train_rolls = roll_samples(
        rolled_contacts(engines, OBJECTS, ROLL_FAULTS, n_rolls=n_rolls, rng=rng)
    )
    test_rolls = roll_samples(
        rolled_contacts(engines, OBJECTS, ROLL_FAULTS, n_rolls=n_rolls, rng=rng)
    )
    if progress is not None:
        progress(2, 3)
    roll_net = train_contact_network(train_rolls.features, train_rolls.labels, rng=rng)
    scores: dict[str, dict[str, dict[str, float]]] = {}
    for name, network in (
        ("hand_set", HAND_SET),
        ("trained_on_pressed", net),
        ("trained_on_rolls", roll_net),
    ):
        scores[name] = {"all": _row(score_network(network, test_rolls.features, test_rolls.labels))}
        for engine in engines:
            for fault in ROLL_FAULTS:
                m = (test_rolls.engine == engine) & (test_rolls.fault == fault)
                scores[name][f"{engine}/{fault}"] = _row(
                    score_network(network, test_rolls.features[m], test_rolls.labels[m])
                )
    if progress is not None:
        progress(3, 3)
    return ContactClassesResult(
        samples,
        net,
        hand,
        learnt,
        int(half),
        test_rolls,
        roll_net,
        scores,
        engines,
        int(train_rolls.labels.size),
    )
