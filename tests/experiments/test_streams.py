"""Per-trial random streams from SeedSequence spawn keys."""

import numpy as np
import pytest

from vibrissa.experiments import runner
from vibrissa.experiments.streams import ORDER, SURFACES, TRIALS, stream
from vibrissa.whisker.surfaces import TEXTURES


def draws(seq: np.random.SeedSequence) -> np.ndarray:
    return np.random.default_rng(seq).random(4)


def test_same_key_same_stream_and_keys_are_independent():
    np.testing.assert_array_equal(draws(stream(3, TRIALS, 7)), draws(stream(3, TRIALS, 7)))
    others = [stream(3, TRIALS, 8), stream(4, TRIALS, 7), stream(3, ORDER), stream(3, SURFACES, 7)]
    for o in others:
        assert not np.array_equal(draws(stream(3, TRIALS, 7)), draws(o))


def test_streams_equal_those_of_seedsequence_spawn():
    """Addressable keys give exactly the children SeedSequence.spawn would."""
    root = np.random.SeedSequence(11)
    children = root.spawn(3)
    for i, child in enumerate(children):
        np.testing.assert_array_equal(draws(child), draws(stream(11, i)))


def test_every_texture_has_its_own_sheet():
    """The old scheme summed character codes: anagrams shared a sheet."""
    heights = {t: runner.session_surface(t, 0).heights_m.ravel()[:64].copy() for t in TEXTURES}
    names = list(heights)
    for i, a in enumerate(names):
        for b in names[i + 1 :]:
            assert not np.array_equal(heights[a], heights[b])


@pytest.mark.parametrize("bad", [(-1,), (0, -2)])
def test_negative_seed_or_key_is_refused(bad):
    with pytest.raises(ValueError, match="non-negative"):
        stream(bad[0], *bad[1:])
