"""Which sequences of a stand-in scene are for training and which for testing."""

from __future__ import annotations

import numpy as np

from .synth_config import SynthConfig


def split_sequences(scene: str, config: SynthConfig) -> tuple[list[int], list[int]]:
    """Sequence numbers (1-based) of the training and test splits, test ones interleaved."""
    n_train, n_test = config.sequence_counts[scene]
    total = n_train + n_test
    test = sorted({int(np.rint(x)) for x in np.linspace(1, total, n_test + 2)[1:-1]})
    while len(test) < n_test:  # tiny counts: fill from the end
        test.append(max(set(range(1, total + 1)) - set(test)))
    train = [s for s in range(1, total + 1) if s not in test]
    return train, sorted(test)
