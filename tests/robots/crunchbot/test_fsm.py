"""CrunchBot's finite state machine (thesis 6.5.3) on scripted contacts."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vibrissa.robots.crunchbot.fsm import (
    ABORT,
    BACK,
    FWD_1,
    FWD_2,
    HIT_1,
    HIT_2,
    TURN,
    FsmSettings,
    FsmState,
    Observation,
    draw_turn,
    transition,
)

NONE = Observation((False, False, False, False), (0.0,) * 4)


def _touch(*whiskers: int, strain: float = 0.2) -> Observation:
    return Observation(
        tuple(i in whiskers for i in range(4)),
        tuple(strain if i in whiskers else 0.0 for i in range(4)),
    )


def _run(script: list[Observation], seed: int = 0) -> list[tuple[str, object]]:
    rng = np.random.default_rng(seed)
    state = FsmState()
    out = []
    for obs in script:
        state, cmd = transition(state, obs, rng)
        out.append((state.name, cmd))
    return out


def test_two_contacts_run_the_whole_cycle_with_the_thesis_speeds() -> None:
    script = [NONE, _touch(1), NONE, _touch(1), _touch(1), _touch(1, 2), NONE, NONE, NONE]
    steps = _run(script)
    assert [s for s, _ in steps] == [FWD_1, HIT_1, FWD_2, FWD_2, FWD_2, HIT_2, BACK, TURN, FWD_1]
    cmds = dict(steps)
    assert (cmds[FWD_1].linear_m_s, cmds[FWD_1].duration_s) == (0.05, 0.5)
    assert (cmds[FWD_2].linear_m_s, cmds[FWD_2].duration_s) == (0.02, 0.5)
    assert (cmds[BACK].linear_m_s, cmds[BACK].duration_s) == (-0.05, 0.5)
    assert cmds[HIT_1].duration_s == 0 and cmds[HIT_2].duration_s == 0
    turn = cmds[TURN]
    assert turn.linear_m_s == 0 and abs(turn.angular_rad_s) == 0.3
    assert turn.duration_s > 0


def test_the_first_whisker_staying_in_contact_is_not_a_second_contact() -> None:
    steps = _run([_touch(0, 1), NONE, _touch(1), _touch(0)])
    assert [s for s, _ in steps] == [HIT_1, FWD_2, FWD_2, FWD_2]


def test_strain_over_the_limit_aborts_then_backs_off() -> None:
    steps = _run([_touch(2), NONE, _touch(2, strain=1.5), NONE, NONE])
    assert [s for s, _ in steps] == [HIT_1, FWD_2, ABORT, BACK, TURN]
    assert steps[2][1].duration_s == 0


def test_strain_over_the_limit_in_fwd_1_and_a_bump_abort() -> None:
    assert _run([_touch(3, strain=2.0)])[0][0] == ABORT
    bump = Observation((False,) * 4, (0.0,) * 4, bumped=True)
    assert _run([_touch(3), NONE, bump])[-1][0] == ABORT


def test_strain_limit_is_a_setting() -> None:
    rng = np.random.default_rng(0)
    s = FsmSettings(strain_limit=3.0)
    state, _ = transition(FsmState(FWD_2, frozenset({2})), _touch(2, strain=2.0), rng, s)
    assert state.name == FWD_2


def test_turn_angles_follow_the_two_gaussian_mixture() -> None:
    rng = np.random.default_rng(7)
    s = FsmSettings()
    a = np.array([draw_turn(s, rng) for _ in range(4000)])
    narrow = np.isclose(a, 0.14 * math.pi)
    assert narrow.mean() == pytest.approx(0.5, abs=0.03)
    wide = a[~narrow]
    assert wide.mean() == pytest.approx(0.3 * math.pi, abs=0.05)
    assert wide.var() == pytest.approx(0.25 * math.pi, rel=0.08)


def test_a_turn_lasts_its_angle_over_the_turn_rate_and_is_seeded() -> None:
    state = FsmState(BACK)
    a = transition(state, NONE, np.random.default_rng(3))[1]
    b = transition(state, NONE, np.random.default_rng(3))[1]
    assert a == b
    angle = draw_turn(FsmSettings(), np.random.default_rng(3))
    assert a.angular_rad_s * a.duration_s == pytest.approx(angle)


def test_bad_states_and_settings_are_refused() -> None:
    with pytest.raises(ValueError, match="unknown FSM state 'JUMP'"):
        FsmState("JUMP")
    with pytest.raises(ValueError, match="fwd2_speed_m_s must be positive"):
        FsmSettings(fwd2_speed_m_s=0.0)
    with pytest.raises(ValueError, match="variance must be non-negative"):
        FsmSettings(turn_components=((1.0, 0.5, -1.0),))
