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
    outcome_counts,
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
    with pytest.raises(ValueError, match="max_back_steps must be at least 1"):
        FsmSettings(max_back_steps=0)


def test_back_repeats_while_a_whisker_still_touches_up_to_its_limit() -> None:
    rng = np.random.default_rng(0)
    s = FsmSettings(max_back_steps=3)
    state = FsmState(BACK)
    names = []
    for _ in range(4):
        state, cmd = transition(state, _touch(1), rng, s)
        names.append(state.name)
    assert names[:3] == [BACK, BACK, TURN]  # the third BACK step is the last allowed
    # touching during the step but free at its end: clear, so TURN
    free_at_end = Observation(_touch(1).contact, _touch(1).strain, contact_at_end=(False,) * 4)
    assert transition(FsmState(BACK), free_at_end, rng, s)[0].name == TURN
    once = FsmSettings(back_until_clear=False)
    assert transition(FsmState(BACK), _touch(1), rng, once)[0].name == TURN


def test_an_over_strain_while_turning_aborts_if_the_turn_is_watched() -> None:
    rng = np.random.default_rng(0)
    strained = _touch(0, strain=1.5)
    watched = FsmSettings(monitor_turn=True)
    assert transition(FsmState(TURN), strained, rng, watched)[0].name == ABORT
    assert transition(FsmState(TURN), _touch(0), rng, watched)[0].name == FWD_1
    # the default reads the thesis: the strain is watched within the 0.5 s steps only
    assert transition(FsmState(TURN), strained, rng)[0].name == FWD_1


def test_outcome_counts_say_where_each_abort_came_from() -> None:
    states = [FWD_1, HIT_1, FWD_2, HIT_2, BACK, TURN, FWD_1, ABORT, BACK, BACK, TURN]
    states += [ABORT, BACK, TURN, FWD_1, HIT_1, FWD_2, FWD_2, ABORT, BACK]
    c = outcome_counts(states)
    assert (c["hit_1"], c["hit_2"], c["abort"], c["turn"]) == (2, 1, 3, 3)
    assert c["abort_after"] == {FWD_1: 1, FWD_2: 1, TURN: 1}
    assert c["fwd2_ends"] == {"hit_2": 1, "abort": 1}
    assert c["back_steps"] == 5
    with pytest.raises(ValueError, match="unknown FSM state"):
        outcome_counts([FWD_1, "JUMP"])


def test_two_whiskers_touching_in_fwd_2_are_a_second_contact() -> None:
    rng = np.random.default_rng(0)
    both = FsmState(FWD_2, frozenset({1, 2}))
    assert transition(both, _touch(1, 2), rng)[0].name == HIT_2
    strict = FsmSettings(two_in_contact=False)
    assert transition(both, _touch(1, 2), rng, strict)[0].name == FWD_2
    assert transition(both, _touch(2, 3), rng, strict)[0].name == HIT_2
