"""The ring-down test of a whisker model: deflect the tip, release it, measure the decay.

It is an identification measurement.

:func:`ring_down_test` is what ``vibrissa whisker ring`` runs, as a library function: the
released whisker's base signal, low-passed to its first mode, measured by
:func:`vibrissa.signal.ring_down` and set beside the model's own first mode.
"""

from __future__ import annotations

import math
from typing import Any

import scipy.signal

from vibrissa.signal import ring_down
from vibrissa.whisker.rod import RodModel
from vibrissa.whisker.simulate import free_vibration

__all__ = ["ring_down_test"]


def ring_down_test(
    model: RodModel,
    *,
    tip_deflection_mm: float,
    duration_s: float,
    dt_s: float,
    lowpass: bool = True,
) -> dict[str, Any]:
    """Deflect the tip of ``model`` statically, release it and measure the ring-down.

    The base signal is the magnet's tangent ``tan_x`` (with a rigid follicle, which holds
    the magnet still, the slope of the first shaft element instead). With ``lowpass`` it
    is low-passed (4th-order Butterworth, zero phase) at the geometric mean of the first
    two natural frequencies to isolate the first mode, whose decay the higher modes
    otherwise disturb (badly so at a clamped base). The damped frequency comes from the
    mean spacing of its zero crossings, the damping ratio from a least-squares fit of
    log|peak| against time over half-cycle peaks (:func:`vibrissa.signal.ring_down`).

    Parameters
    ----------
    model : RodModel
        The whisker.
    tip_deflection_mm : float
        Initial static tip deflection along x (mm).
    duration_s, dt_s : float
        Simulated time after release and the integration step (s).
    lowpass : bool, default=True
        Isolate the first mode before measuring.

    Returns
    -------
    dict
        ``frequency_hz`` and ``damping_ratio`` measured (``None`` with too few half
        cycles), ``model_frequency_hz`` (undamped) and ``model_damped_frequency_hz`` of
        the first mode, ``n_peaks_fitted``, ``signal`` (which base signal),
        ``lowpass_hz`` (``None``: unfiltered) and ``dt_s``.
    """
    res = free_vibration(
        model,
        tip_deflection_mm=tip_deflection_mm,
        duration_s=duration_s,
        dt_s=dt_s,
        record_every=1 if model.rigid_follicle else 0,
    )
    if model.rigid_follicle:
        e = res.states_m[:, 2] - res.states_m[:, 1]
        sig = e[:, 0] / e[:, 2]
        signal_name = "base slope of the shaft (rigid follicle)"
    else:
        sig = res.tan_xy[:, 0]
        signal_name = "magnet tan_x"
    f_nat = model.natural_frequencies_hz
    lowpass_hz: float | None = None
    if lowpass and f_nat.size > 1:
        fc = float(math.sqrt(f_nat[0] * f_nat[1]))
        if fc < 0.4 / res.dt_s:
            sos = scipy.signal.butter(4, fc, fs=1.0 / res.dt_s, output="sos")
            sig = scipy.signal.sosfiltfilt(sos, sig)
            lowpass_hz = fc
    meas = ring_down(sig, res.dt_s)
    alpha, beta_s, beta_f = model.damping
    _, fd = model.modal_damping(alpha, beta_s, beta_f, 1)
    return {
        "frequency_hz": meas["frequency_hz"],
        "damping_ratio": meas["damping_ratio"],
        "model_frequency_hz": float(model.natural_frequencies_hz[0]),
        "model_damped_frequency_hz": float(fd[0]),
        "n_peaks_fitted": meas["n_peaks"],
        "signal": signal_name,
        "lowpass_hz": lowpass_hz,
        "dt_s": res.dt_s,
    }
