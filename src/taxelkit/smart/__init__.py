"""The smart tactile sensor of paper 001: image statistics (Level 1) and contact classes (Level 2).

The package sees frames, timestamps and the pitch only; labelled training
contacts are made on the simulator side (:mod:`taxelkit.motion.contact_samples`).
"""

from taxelkit.smart.area_moments import moments_central, moments_of_area
from taxelkit.smart.contact_classes import (
    AREA_MAX_ELONGATION,
    AREA_MIN_AREA_MM2,
    DEFAULT_CONFIDENCE,
    HAND_SET,
    LINE_MIN_AREA_MM2,
    LINE_MIN_ELONGATION,
    OUTPUT_CLASSES,
    POINT_MAX_AREA_MM2,
    ContactClass,
    ContactNetwork,
    classify_contacts,
    classify_features,
    contact_features,
    contact_probabilities,
    hand_set_network,
    network_inputs,
)
from taxelkit.smart.contact_training import (
    ClassificationScore,
    NetworkGradient,
    loss_and_gradient,
    score_network,
    train_contact_network,
)
from taxelkit.smart.moments import (
    CELL_SECOND_MOMENT,
    FrameStats,
    ImageStats,
    binary_images,
    frame_stats,
    image_stats,
)

__all__ = [
    "AREA_MAX_ELONGATION",
    "AREA_MIN_AREA_MM2",
    "CELL_SECOND_MOMENT",
    "DEFAULT_CONFIDENCE",
    "HAND_SET",
    "LINE_MIN_AREA_MM2",
    "LINE_MIN_ELONGATION",
    "OUTPUT_CLASSES",
    "POINT_MAX_AREA_MM2",
    "ClassificationScore",
    "ContactClass",
    "ContactNetwork",
    "FrameStats",
    "ImageStats",
    "NetworkGradient",
    "binary_images",
    "classify_contacts",
    "classify_features",
    "contact_features",
    "contact_probabilities",
    "frame_stats",
    "hand_set_network",
    "image_stats",
    "loss_and_gradient",
    "moments_central",
    "moments_of_area",
    "network_inputs",
    "score_network",
    "train_contact_network",
]
