"""Shape recognition of paper 000: chain-symbolizing (Eq. 13) and Associatron recall (Eq. 10-14).

Modules: :mod:`~taxelkit.memory.direction_histogram` (move directions and their
sector histogram), :mod:`~taxelkit.memory.chain_code` (Eq. 13),
:mod:`~taxelkit.memory.partial_code` (0 = unknown for partial traces),
:mod:`~taxelkit.memory.code_rotation` (cyclic shifts),
:mod:`~taxelkit.memory.recall_rules` (Hebbian and improved rules),
:mod:`~taxelkit.memory.dense_recall` (dense associative memory),
:mod:`~taxelkit.memory.recall` (all-shift recall, Eq. 12 and 14) and
:mod:`~taxelkit.memory.associatron` (the memory object).
:mod:`~taxelkit.memory.turning_signature` and
:mod:`~taxelkit.memory.signature_memory` hold the order-aware code (tangent
signature) and its memory.
``ternary`` is Phi of Eq. 9, shared with :mod:`taxelkit.neuron`.
"""

from taxelkit.memory.associatron import MEMORY_FORMAT_VERSION, AssociativeMemory, memorise
from taxelkit.memory.chain_code import (
    DEFAULT_CHAIN_CODE,
    DEFAULT_LEVELS,
    ChainCodeConfig,
    chain_code_from_directions,
    chain_code_from_histogram,
    chain_code_from_moves,
    rounding_thresholds,
)
from taxelkit.memory.code_rotation import all_cyclic_shifts, cyclic_shift_index
from taxelkit.memory.dense_recall import DenseRecall
from taxelkit.memory.direction_histogram import (
    DEFAULT_SECTORS,
    SECTOR_BOUNDARY_TOLERANCE,
    ZERO_MOVE_TOLERANCE_MM,
    directions_from_moves,
    histogram_from_directions,
    histogram_from_moves,
    relative_frequency,
)
from taxelkit.memory.partial_code import (
    partial_chain_code_from_histogram,
    partial_chain_code_from_moves,
)
from taxelkit.memory.recall import (
    RECALL_CHUNK_QUERIES,
    TIE_TOLERANCE,
    RecallResult,
    correlation,
    recall_with_operator,
    verdict_text,
)
from taxelkit.memory.recall_rules import (
    FAITHFUL_RULE,
    FIELD_TOLERANCE,
    MASKED_PROJECTION_RIDGE,
    RECALL_RULES,
    LinearRecall,
    MaskedProjectionRecall,
    RecallOperator,
    RecallRuleSpec,
    get_recall_rule,
    hebbian_matrix,
)
from taxelkit.memory.signature_memory import (
    SIGNATURE_RULES,
    SignatureMemory,
    SignatureRecall,
)
from taxelkit.memory.turning_signature import (
    SIGNATURE_STEP_MM,
    StoredSignatures,
    signature_overlaps,
    tangent_signature,
)
from taxelkit.neuron.quantisers import ternary

__all__ = [
    "DEFAULT_CHAIN_CODE",
    "DEFAULT_LEVELS",
    "DEFAULT_SECTORS",
    "FAITHFUL_RULE",
    "FIELD_TOLERANCE",
    "MASKED_PROJECTION_RIDGE",
    "MEMORY_FORMAT_VERSION",
    "RECALL_CHUNK_QUERIES",
    "RECALL_RULES",
    "SECTOR_BOUNDARY_TOLERANCE",
    "SIGNATURE_RULES",
    "SIGNATURE_STEP_MM",
    "TIE_TOLERANCE",
    "ZERO_MOVE_TOLERANCE_MM",
    "AssociativeMemory",
    "ChainCodeConfig",
    "DenseRecall",
    "LinearRecall",
    "MaskedProjectionRecall",
    "RecallOperator",
    "RecallResult",
    "RecallRuleSpec",
    "SignatureMemory",
    "SignatureRecall",
    "StoredSignatures",
    "all_cyclic_shifts",
    "chain_code_from_directions",
    "chain_code_from_histogram",
    "chain_code_from_moves",
    "correlation",
    "cyclic_shift_index",
    "directions_from_moves",
    "get_recall_rule",
    "hebbian_matrix",
    "histogram_from_directions",
    "histogram_from_moves",
    "memorise",
    "partial_chain_code_from_histogram",
    "partial_chain_code_from_moves",
    "recall_with_operator",
    "relative_frequency",
    "rounding_thresholds",
    "signature_overlaps",
    "tangent_signature",
    "ternary",
    "verdict_text",
]
