"""[TI-DDMA] figures 7-8: one Tx stepped by a fixed phase per chirp against a corner reflector.

On an AWR1843, Tx1 stepped by 90 deg per chirp shifts a static corner reflector at about 4.5 m
to half the unambiguous velocity; the shifter's code-dependent error puts a ghost at the mirror
velocity, and calibration lowers it by more than 20 dB ([TI-DDMA] section 4.2). Here the front
end simulates that frame (`radarsim.simulate_frame_weights`), a plain range FFT and a
rectangular Doppler FFT at the reflector's range measure the lines, and the analytic
prediction is the DFT of one code period's complex weights (`radarsim.shifter.spur_levels_dbc`):
the sequence is periodic in P = 360 / step chirps, so its spectrum has exactly P lines, at
m n_chirps / P bins, with no leakage.

References
----------
.. [1] TI, AWR2944 DDMA application note [TI-DDMA], section 4.2, figures 7-8.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import pandas as pd

import radarsim
from core.errors import BadInput
from core.fileio import atomic_write
from radarsim import shifter as sh

__all__ = ["PhaseStepResult", "phase_step_experiment", "line_spectrum", "format_lines",
           "plot_phase_step"]


class PhaseStepResult(NamedTuple):
    """One run of the phase-stepping experiment.

    codes : (P,) int
        Programmed codes of the stepped Tx over one period.
    residual_deg : (P,) float
        Programmed-minus-wanted phase of those codes relative to code 0 (table included), deg.
    velocity_over_vmax : (n_chirps,) float
        Doppler axis of the cut, v / Vmax (Vmax = lambda / (4 Tc)), ascending, design.md 3 sign
        convention (radial velocity = -f_D lambda / 2).
    cut_dbc : (n_chirps,) float
        Range-Doppler cut at the reflector's range bin (power summed over Rx), dB relative to
        the target line.
    lines : pandas.DataFrame
        One row per line m = 0..P-1: ``line``, ``velocity_over_vmax``, ``role`` ("target",
        "mirror ghost" or "spur"), ``predicted_dbc``, ``measured_dbc``.
    """

    codes: np.ndarray
    residual_deg: np.ndarray
    velocity_over_vmax: np.ndarray
    cut_dbc: np.ndarray
    lines: pd.DataFrame


def line_spectrum(adc: np.ndarray) -> tuple[int, np.ndarray]:
    """Reflector range bin and its Doppler power spectrum.

    Parameters
    ----------
    adc : (n_c, n_rx, n_samples) int16
        One frame.

    Returns
    -------
    range_bin : int
        Strongest bin of the Blackman-Harris windowed real range FFT (power summed over chirps
        and Rx). The 4-term window (-92 dB sidelobes) keeps the real ADC's negative-frequency
        image out: at 4.5 m the R79 beat sits 3.4 bins above DC, and the image (6.8 bins away,
        conjugate slow-time phase) would otherwise put a -57 dBc line (Hann) exactly on the
        mirror velocity.
    power : (n_c,) float
        |rectangular Doppler FFT|^2 at that bin, summed over Rx, natural FFT order.
    """
    x = adc.astype(np.float32)
    n_s = x.shape[-1]
    from scipy.signal.windows import blackmanharris
    win = blackmanharris(n_s, sym=False).astype(np.float32)
    rng_fft = np.fft.rfft(x * win, axis=-1)[..., :n_s // 2]
    r0 = int(np.argmax(np.sum(np.abs(rng_fft) ** 2, axis=(0, 1))))
    dop = np.fft.fft(rng_fft[:, :, r0].astype(np.complex128), axis=0)
    return r0, np.sum(np.abs(dop) ** 2, axis=1)


def check_phase_step(cfg: radarsim.RadarConfig, step_deg: float, tx: int,
                     n_chirps: int) -> int:
    """Raise unless `phase_step_experiment` can run these settings; returns the code period
    P = 360 / step_deg."""
    p_float = 360.0 / step_deg if step_deg > 0 else math.inf
    period = int(round(p_float))
    if not (math.isfinite(p_float) and abs(p_float - period) < 1e-9 and period >= 2):
        raise BadInput(f"step_deg={step_deg!r}: 360 / step_deg must be an integer >= 2")
    if not 1 <= tx <= cfg.n_tx:
        raise BadInput(f"tx={tx!r} must be in 1..{cfg.n_tx}")
    if not isinstance(n_chirps, int) or n_chirps < period or n_chirps % period:
        raise BadInput(f"n_chirps={n_chirps!r} must be a positive multiple of the code "
                       f"period {period}")
    return period


def phase_step_experiment(cfg: radarsim.RadarConfig, *, rng: np.random.Generator,
                          step_deg: float = 90.0, tx: int = 1, range_m: float = 4.5,
                          rcs_m2: float = 10.0, n_chirps: int = 256) -> PhaseStepResult:
    """Simulate and measure the [TI-DDMA] figure 7-8 frame.

    Parameters
    ----------
    cfg : RadarConfig
        The radar: shifter error tables, coupling, static / per-chirp errors, and
        `shifter_calibration_deg` when calibrated (codes then chosen by the measured table,
        otherwise by `phase_quantization`).
    rng : numpy.random.Generator
        Thermal noise (and per-chirp phase noise).
    step_deg : float
        Programmed phase step per chirp, deg; 360 / step_deg must be an integer P >= 2.
    tx : int
        The stepped transmitter (1-based); the others are off.
    range_m, rcs_m2 : float
        Static corner reflector at boresight.
    n_chirps : int
        Chirps of the frame, a multiple of P.

    Returns
    -------
    PhaseStepResult
    """
    period = check_phase_step(cfg, step_deg, tx, n_chirps)
    k = tx - 1
    wanted = np.mod(step_deg * np.arange(period), 360.0)[None, :]
    cal = cfg.shifter_calibration_deg
    codes = sh.program_codes(wanted, cfg.phase_lsb_deg, 2 ** cfg.phase_shifter_bits,
                             cfg.phase_quantization,
                             None if cal is None else np.asarray(cal)[k:k + 1])[0]
    e_tab = np.asarray(cfg.shifter_phase_error_deg)
    g_tab = np.asarray(cfg.shifter_gain_error_db)
    residual = sh.phase_residual_deg(wanted, codes[None, :], e_tab[k:k + 1],
                                     cfg.phase_lsb_deg)[0]
    # Prediction: one period of 10^(g/20) exp(-j(q LSB + e)).
    w_period = sh.shifter_factor(e_tab[k:k + 1], g_tab[k:k + 1], codes[None, :])[0] * \
        np.exp(-1j * np.radians(codes * cfg.phase_lsb_deg))
    predicted = sh.spur_levels_dbc(w_period)

    c = np.arange(n_chirps)
    all_codes = np.zeros((cfg.n_tx, n_chirps), dtype=np.int64)
    all_codes[k] = codes[c % period]
    active = np.zeros((cfg.n_tx, n_chirps), dtype=bool)
    active[k] = True
    weights = radarsim.frontend.code_weights(cfg, all_codes, active, rng)
    sc = radarsim.Scatterers(position_m=[[range_m, 0.0, 0.0]], velocity_mps=[[0.0, 0.0, 0.0]],
                             rcs_m2=[rcs_m2])
    adc = radarsim.simulate_frame_weights(cfg, sc, rng, weights)
    _, power = line_spectrum(adc)

    m = np.arange(period)
    line_bins = m * (n_chirps // period)
    target = int(np.argmax(predicted))
    ref = power[line_bins[target]]
    measured = 10 * np.log10(np.maximum(power[line_bins], 1e-300) / ref)
    signed = lambda b, n: (b + n // 2) % n - n // 2  # noqa: E731
    v_lines = -2.0 * signed(m, period) / period
    mirror = (-signed(target, period)) % period
    roles = np.where(m == target, "target", np.where(m == mirror, "mirror ghost", "spur"))
    lines = pd.DataFrame({"line": m, "velocity_over_vmax": v_lines, "role": roles,
                          "predicted_dbc": predicted, "measured_dbc": measured})
    v = -2.0 * signed(c, n_chirps) / n_chirps
    order = np.argsort(v, kind="stable")
    cut = 10 * np.log10(np.maximum(power, 1e-300) / ref)
    return PhaseStepResult(codes=codes, residual_deg=residual, velocity_over_vmax=v[order],
                           cut_dbc=cut[order], lines=lines)


def format_lines(res: PhaseStepResult, title: str) -> list[str]:
    """Printable table of the lines of one run: predicted vs measured, dBc. A line predicted
    less than 10 dB above the noise floor of the cut (its median bin) shows "floor"."""
    floor = float(np.median(res.cut_dbc))
    out = [f"{title}: codes {res.codes.tolist()}, residual rms "
           f"{np.sqrt(np.mean(res.residual_deg ** 2)):.2f} deg, max "
           f"{np.max(np.abs(res.residual_deg)):.2f} deg; noise floor {floor:.1f} dBc",
           "   line  v/Vmax  role           predicted dBc  measured dBc  diff dB"]
    for r in res.lines.itertuples():
        pred = f"{r.predicted_dbc:12.2f}" if r.predicted_dbc > -150 else f"{'< -150':>12s}"
        diff = f"{r.measured_dbc - r.predicted_dbc:+7.2f}" if r.predicted_dbc > floor + 10 \
            else f"{'floor':>7s}"
        out.append(f"   {r.line:4d}  {r.velocity_over_vmax:+6.2f}  {r.role:<13s}  "
                   f"{pred}  {r.measured_dbc:12.2f}  {diff}")
    return out


def plot_phase_step(before: PhaseStepResult, after: PhaseStepResult, path) -> None:
    """Range-Doppler cut at the reflector's range before / after calibration (figures 7-8)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 4))
    for res, lab, col in ((before, "uncalibrated", "tab:red"), (after, "calibrated", "tab:blue")):
        ax.plot(res.velocity_over_vmax, res.cut_dbc, color=col, lw=0.8, label=lab)
        ax.plot(res.lines["velocity_over_vmax"], res.lines["predicted_dbc"], "o", mfc="none",
                color=col, label=f"{lab}: predicted lines (DFT of code period)")
    ax.set_xlabel("radial velocity / Vmax (design.md 3 sign)")
    ax.set_ylabel("power at reflector range, dBc")
    ax.set_ylim(bottom=max(-120.0, min(before.cut_dbc.min(), after.cut_dbc.min())))
    ax.set_title("one Tx stepped 90 deg/chirp, corner reflector 4.5 m ([TI-DDMA] figs 7-8)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    try:
        atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=100, bbox_inches="tight"))
    finally:
        plt.close(fig)
