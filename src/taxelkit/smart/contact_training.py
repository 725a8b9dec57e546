"""Level 2 of the smart tactile sensor: learning the contact network by back-propagation.

Paper 001 (Section 3, Level 2) set the network's weights by hand and notes
that "having formulated this part of the recognition algorithm as a neural
network an increased number of inputs or more complicated decision regions
can be accommodated by training the neural network using back-propagation".
This module does that for the network of
:mod:`taxelkit.smart.contact_classes`, in plain NumPy: cross-entropy loss of
the softmax outputs, its exact gradient by back-propagation, mini-batch Adam
steps with a seeded generator, and a score of a network on labelled contacts.
Labelled contacts can come from recordings or from the simulator
(:mod:`taxelkit.motion.contact_samples`).

References
----------
Paper 001, Section 3, Level 2; D. E. Rumelhart, G. E. Hinton, R. J. Williams,
"Learning representations by back-propagating errors", Nature 323 (1986)
533-536; D. P. Kingma, J. Ba, "Adam: a method for stochastic optimization",
ICLR 2015.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.smart.contact_classes import (
    DEFAULT_CONFIDENCE,
    OUTPUT_CLASSES,
    ContactClass,
    ContactNetwork,
    _check_features,
    _forward,
    classify_features,
    network_inputs,
)

__all__ = [
    "ClassificationScore",
    "NetworkGradient",
    "loss_and_gradient",
    "score_network",
    "train_contact_network",
]

_N_OUT = len(OUTPUT_CLASSES)


@dataclass(frozen=True, eq=False)
class NetworkGradient:
    """Partial derivatives of the loss with respect to each weight array.

    Fields mirror :class:`ContactNetwork` (same shapes).
    """

    w_hidden: NDArray[np.float64]
    b_hidden: NDArray[np.float64]
    w_output: NDArray[np.float64]
    b_output: NDArray[np.float64]


def _labels_to_outputs(labels: ArrayLike, n: int) -> NDArray[np.intp]:
    lab = np.asarray(labels)
    if lab.shape != (n,):
        raise InputError(f"labels must have shape ({n},), got {lab.shape}")
    codes = np.asarray([int(c) for c in OUTPUT_CLASSES])
    match = lab[:, None] == codes[None, :]
    if not np.all(match.any(axis=1)):
        k = int(np.argmin(match.any(axis=1)))
        raise InputError(
            f"labels must be POINT, LINE or AREA codes {codes.tolist()}, got {lab[k]!r} at {k}"
        )
    return np.asarray(match.argmax(axis=1), dtype=np.intp)


def _loss_grad(
    net: ContactNetwork, x: NDArray[np.float64], y: NDArray[np.intp], weight_decay: float
) -> tuple[float, NetworkGradient]:
    """Mean cross-entropy (+ L2 on the weights) and its gradient by back-propagation."""
    n = x.shape[0]
    h, p = _forward(net, x)
    rows = np.arange(n)
    loss = float(-np.mean(np.log(np.maximum(p[rows, y], np.finfo(np.float64).tiny))))
    loss += 0.5 * weight_decay * float(np.sum(net.w_hidden**2) + np.sum(net.w_output**2))
    dz = p.copy()
    dz[rows, y] -= 1.0
    dz /= n  # d loss / d logits
    dh = (dz @ net.w_output.T) * (1.0 - h * h)  # through tanh
    grad = NetworkGradient(
        w_hidden=x.T @ dh + weight_decay * net.w_hidden,
        b_hidden=dh.sum(axis=0),
        w_output=h.T @ dz + weight_decay * net.w_output,
        b_output=dz.sum(axis=0),
    )
    return loss, grad


def loss_and_gradient(
    network: ContactNetwork,
    features: ArrayLike,
    labels: ArrayLike,
    *,
    weight_decay: float = 0.0,
) -> tuple[float, NetworkGradient]:
    """Cross-entropy loss of labelled contacts and its gradient (back-propagation).

    ``L = -mean(ln p[n, y_n]) + weight_decay / 2 (|w_hidden|^2 + |w_output|^2)``.

    Parameters
    ----------
    network : ContactNetwork
    features : (N, 2) float
        ``(area_mm2, elongation)`` of contacts (area > 0).
    labels : (N,) int
        POINT, LINE or AREA codes.
    weight_decay : float
        L2 coefficient (biases are not penalised).

    Returns
    -------
    loss : float
        Nats per sample.
    gradient : NetworkGradient
        ``dL / d(weights)``, same shapes as the network's arrays.

    Raises
    ------
    InputError
        On bad features, labels or weight decay.
    """
    x = network_inputs(features)
    y = _labels_to_outputs(labels, x.shape[0])
    wd = check_positive("weight_decay", weight_decay, allow_zero=True)
    return _loss_grad(network, x, y, wd)


def train_contact_network(
    features: ArrayLike,
    labels: ArrayLike,
    *,
    hidden_units: int = 6,
    epochs: int = 300,
    learning_rate: float = 0.03,
    batch_size: int | None = 256,
    weight_decay: float = 1e-4,
    initial: ContactNetwork | None = None,
    rng: int | np.random.Generator | None = None,
) -> ContactNetwork:
    """Learn the network's weights from labelled contacts by back-propagation.

    Mini-batch gradient descent with Adam steps (``beta1 = 0.9, beta2 =
    0.999``) on the cross-entropy of :func:`loss_and_gradient`. Inputs are
    standardised (mean 0, standard deviation 1 over the training set) while
    learning and the scaling is folded back into the first layer, so the
    returned network takes the same features as :data:`HAND_SET`.

    Parameters
    ----------
    features : (N, 2) float
        ``(area_mm2, elongation)`` of contacts (area > 0), for example
        ``contact_features(image_stats(...))`` or
        :func:`taxelkit.motion.contact_samples.pressed_contacts`.
    labels : (N,) int
        POINT, LINE or AREA codes.
    hidden_units : int
        ``H`` (ignored when ``initial`` is given).
    epochs : int
        Passes over the data.
    learning_rate : float
        Adam step size (in standardised-input units).
    batch_size : int or None
        Samples per step; ``None`` = full batch.
    weight_decay : float
        L2 coefficient on the (standardised) weights.
    initial : ContactNetwork, optional
        Start from these weights (for example :data:`HAND_SET`) instead of a
        random initialisation.
    rng : int, Generator or None
        Seed for the initial weights and the batch order; same seed, same
        network.

    Returns
    -------
    ContactNetwork
        A new network named ``"trained"``.

    Raises
    ------
    InputError
        On bad data or options.
    """
    x_raw = network_inputs(features)
    y = _labels_to_outputs(labels, x_raw.shape[0])
    n = x_raw.shape[0]
    if n < 2:
        raise InputError(f"features must hold at least 2 samples, got {n}")
    for name, value in (("hidden_units", hidden_units), ("epochs", epochs)):
        if not isinstance(value, int | np.integer) or value < 1:
            raise InputError(f"{name} must be an integer >= 1, got {value!r}")
    lr = check_positive("learning_rate", learning_rate)
    wd = check_positive("weight_decay", weight_decay, allow_zero=True)
    if batch_size is not None and (not isinstance(batch_size, int | np.integer) or batch_size < 1):
        raise InputError(f"batch_size must be an integer >= 1 or None, got {batch_size!r}")
    batch = n if batch_size is None else min(int(batch_size), n)
    gen = np.random.default_rng(rng)
    mean = x_raw.mean(axis=0)
    std = x_raw.std(axis=0)
    std = np.where(std > 0, std, 1.0)
    params = _initial_params(initial, int(hidden_units), mean, std, gen)
    x = (x_raw - mean) / std
    params = _adam_descent(params, x, y, epochs=int(epochs), batch=batch, lr=lr, wd=wd, gen=gen)
    w1 = params[0] / std[:, None]
    b1 = params[1] - (mean / std) @ params[0]
    return ContactNetwork(w1, b1, params[2], params[3], name="trained")


def _initial_params(
    initial: ContactNetwork | None,
    hidden_units: int,
    mean: NDArray[np.float64],
    std: NDArray[np.float64],
    gen: np.random.Generator,
) -> list[NDArray[np.float64]]:
    """First-layer and output weights and biases, for inputs standardised by ``mean``, ``std``."""
    if initial is None:
        h = hidden_units
        return [
            gen.normal(0.0, 1.0, size=(2, h)),
            gen.normal(0.0, 0.5, size=h),
            gen.normal(0.0, 1.0 / math.sqrt(h), size=(h, _N_OUT)),
            np.zeros(_N_OUT),
        ]
    return [  # the given weights expressed in standardised inputs
        initial.w_hidden * std[:, None],
        initial.b_hidden + mean @ initial.w_hidden,
        np.array(initial.w_output),
        np.array(initial.b_output),
    ]


def _adam_descent(
    params: list[NDArray[np.float64]],
    x: NDArray[np.float64],
    y: NDArray[np.intp],
    *,
    epochs: int,
    batch: int,
    lr: float,
    wd: float,
    gen: np.random.Generator,
) -> list[NDArray[np.float64]]:
    """Adam on mini-batches in a fresh random order each epoch; the final parameters.

    ``params`` (and the batches) in standardised inputs; ``y`` the output index of each sample.
    """
    params = list(params)
    n = x.shape[0]
    m1 = [np.zeros_like(q) for q in params]
    m2 = [np.zeros_like(q) for q in params]
    beta1, beta2, eps = 0.9, 0.999, 1e-8
    step = 0
    for _ in range(epochs):
        order = gen.permutation(n)
        for a in range(0, n, batch):
            idx = order[a : a + batch]
            net = ContactNetwork(params[0], params[1], params[2], params[3])
            _, g = _loss_grad(net, x[idx], y[idx], wd)
            step += 1
            grads = [g.w_hidden, g.b_hidden, g.w_output, g.b_output]
            for k, gk in enumerate(grads):
                m1[k] = beta1 * m1[k] + (1 - beta1) * gk
                m2[k] = beta2 * m2[k] + (1 - beta2) * gk * gk
                m_hat = m1[k] / (1 - beta1**step)
                v_hat = m2[k] / (1 - beta2**step)
                params[k] = params[k] - lr * m_hat / (np.sqrt(v_hat) + eps)
    return params


@dataclass(frozen=True, eq=False)
class ClassificationScore:
    """How well a network classifies labelled contacts.

    Parameters
    ----------
    accuracy : float
        Fraction classified as labelled at the given confidence
        (indeterminate counts as wrong).
    argmax_accuracy : float
        Fraction whose largest output is the label (no indeterminate).
    indeterminate_fraction : float
        Fraction classified indeterminate.
    confusion : (3, 5) int
        ``confusion[k, c]``: samples of output class ``k`` (point, line, area)
        assigned code ``c`` (:class:`ContactClass`).
    confidence : float
        The confidence used.
    """

    accuracy: float
    argmax_accuracy: float
    indeterminate_fraction: float
    confusion: NDArray[np.int64]
    confidence: float


def score_network(
    network: ContactNetwork,
    features: ArrayLike,
    labels: ArrayLike,
    *,
    confidence: float = DEFAULT_CONFIDENCE,
) -> ClassificationScore:
    """Accuracy and confusion of a network on labelled contacts.

    Parameters
    ----------
    network : ContactNetwork
    features : (N, 2) float
        ``(area_mm2, elongation)``, area > 0.
    labels : (N,) int
        POINT, LINE or AREA codes.
    confidence : float
        See :func:`classify_features`.

    Returns
    -------
    ClassificationScore
    """
    f = _check_features(features)
    y = _labels_to_outputs(labels, f.shape[0])
    codes = classify_features(f, network, confidence=confidence)
    argmax = classify_features(f, network, confidence=0.0)
    truth = np.asarray([int(c) for c in OUTPUT_CLASSES])[y]
    confusion = np.zeros((_N_OUT, len(ContactClass)), dtype=np.int64)
    np.add.at(confusion, (y, codes.astype(np.intp)), 1)
    n = max(1, f.shape[0])
    return ClassificationScore(
        accuracy=float(np.count_nonzero(codes == truth)) / n,
        argmax_accuracy=float(np.count_nonzero(argmax == truth)) / n,
        indeterminate_fraction=float(np.count_nonzero(codes == ContactClass.INDETERMINATE)) / n,
        confusion=confusion,
        confidence=float(confidence),
    )
