"""Transmit-chain errors: per-code phase-shifter error tables and Tx-to-Tx coupling.

A real 6-bit phase shifter does not produce exactly q x 5.625 deg at code q: each of its 64
settings has its own phase and gain error (the INL/DNL curve that TI's shifter calibration
measures), and neighbouring transmit channels couple. This module holds the pure kernels:

- drawing error tables from a documented distribution with a seed (`ShifterErrorSpec`),
- the shifter's complex factor for programmed codes (`shifter_factor`) and the Tx coupling
  (`coupling_matrix`, `apply_coupling`), which `radarsim.frontend` applies to every scheme's
  transmit weights,
- choosing codes from a calibration table (`select_codes`) and the residual phase error of the
  codes a config programs (`phase_residual_deg`),
- the analytic spur prediction: a transmit error periodic in the code period P puts lines at
  multiples of 1/P of the chirp rate whose complex amplitudes are the DFT of one period's
  complex weights (`code_period_lines`, `spur_levels_dbc`; design.md section 8).

Contract: to Tx k at a chirp whose programmed code is q the shifter applies the phase
-(q LSB + shifter_phase_error_deg[k, q]) and the amplitude gain
10^(shifter_gain_error_db[k, q] / 20), on top of the static per-Tx and random per-chirp errors.

References
----------
.. [1] TI, AWR2944 DDMA application note [TI-DDMA], section 4.1 (6-bit codes, table 4) and
   section 4.2 (shifter error > +/-10 deg uncalibrated, +/-2 deg calibrated; figures 7-8).
.. [2] A. V. Oppenheim, R. W. Schafer, Discrete-Time Signal Processing, 3rd ed., section 8.1
   (a periodic sequence has a line spectrum given by the DFT of one period).
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Callable, NamedTuple

import numpy as np

from core.errors import BadInput

__all__ = ["SHIFTER_ERROR_DISTRIBUTIONS", "ShifterErrorDistribution", "PHASE_QUANTIZATIONS",
           "PhaseQuantization", "ShifterErrorSpec", "MAX_SHIFTER_PHASE_ERROR_DEG",
           "MAX_SHIFTER_GAIN_ERROR_DB", "MAX_TX_COUPLING_DB", "shifter_factor",
           "coupling_matrix", "apply_coupling", "select_codes", "program_codes", "wrap_deg",
           "phase_residual_deg", "code_period_lines", "spur_levels_dbc", "resolve_table",
           "check_table", "vector_modulator_tables", "resolve_config_tables"]

#: Largest accepted |phase error| of one code, deg (beyond +/-180 deg the error is ambiguous).
MAX_SHIFTER_PHASE_ERROR_DEG = 180.0
#: Largest accepted |gain error| of one code, dB.
MAX_SHIFTER_GAIN_ERROR_DB = 10.0
#: Largest accepted Tx-to-Tx coupling level, dB: a passive neighbour cannot radiate more of a
#: channel's signal than the channel itself.
MAX_TX_COUPLING_DB = 0.0

class ShifterErrorDistribution(NamedTuple):
    """One way to draw a per-code error table: ``draw(g, (n_tx, n_codes), dnl_fraction)``
    returns the raw table, which `ShifterErrorSpec.draw` makes relative to code 0 and scales."""

    description: str
    draw: Callable[[np.random.Generator, tuple[int, int], float], np.ndarray]


def _inl_dnl(g: np.random.Generator, shape: tuple[int, int], dnl_fraction: float) -> np.ndarray:
    """INL curve sum_h cos(2 pi h q / n_codes + phi_h) / h, h = 1..3, plus white DNL noise
    carrying `dnl_fraction` of the variance (see `ShifterErrorSpec`)."""
    n_tx, n_codes = shape
    q = np.arange(n_codes)
    h = np.arange(1, 4)
    phi = g.uniform(0, 2 * np.pi, (n_tx, h.size))
    inl = np.sum(np.cos(2 * np.pi * h[None, :, None] * q[None, None, :] / n_codes
                        + phi[:, :, None]) / h[None, :, None], axis=1)
    inl = inl - inl[:, :1]
    dnl = g.standard_normal(shape)
    dnl = dnl - dnl[:, :1]
    return math.sqrt(1 - dnl_fraction) * inl / _rms(inl) + \
        math.sqrt(dnl_fraction) * dnl / _rms(dnl)


#: How `ShifterErrorSpec` draws a table (every row then scaled to the requested rms over codes,
#: relative to code 0).
SHIFTER_ERROR_DISTRIBUTIONS = {
    "uniform": ShifterErrorDistribution("independent per code, uniform",
                                        lambda g, shape, _: g.uniform(-1.0, 1.0, shape)),
    "gaussian": ShifterErrorDistribution("independent per code, Gaussian",
                                         lambda g, shape, _: g.standard_normal(shape)),
    "inl_dnl": ShifterErrorDistribution(
        "smooth INL curve (harmonics 1..3 of the code circle, random phases, amplitude 1/h) "
        "plus white DNL noise (a `dnl_fraction` share of the variance)", _inl_dnl),
}


class PhaseQuantization(NamedTuple):
    """One rule mapping a programmed phase onto shifter codes: ``code_of(phase / lsb)`` (before
    the modulo); `ideal`: the applied phase stays the wanted one (no code grid)."""

    description: str
    code_of: Callable[[np.ndarray], np.ndarray]
    ideal: bool = False


#: How a programmed phase is mapped onto the shifter's codes. A tiny tolerance keeps exact
#: multiples (e.g. 180 / 5.625 = 32) from flooring down.
PHASE_QUANTIZATIONS = {
    "floor": PhaseQuantization("code = floor(phase / lsb), as [TI-DDMA] table 4",
                               lambda p: np.floor(p + 1e-9)),
    "round": PhaseQuantization("code = round(phase / lsb), as TI's SDK", np.round),
    "none": PhaseQuantization("ideal shifter (no quantisation; codes rounded for look-ups)",
                              np.round, ideal=True),
}


def wrap_deg(x: np.ndarray) -> np.ndarray:
    """Wrap angles to [-180, 180) deg."""
    return np.mod(np.asarray(x, dtype=float) + 180.0, 360.0) - 180.0


@dataclass(frozen=True, kw_only=True, slots=True)
class ShifterErrorSpec:
    """A documented random error table: which distribution, how large, which seed.

    Parameters
    ----------
    distribution : {"uniform", "gaussian", "inl_dnl"}
        See `SHIFTER_ERROR_DISTRIBUTIONS`.
    rms : float
        Root-mean-square of each Tx's row over its codes (deg for phase tables, dB for gain
        tables), after making the row relative to code 0; >= 0.
    seed : int
        Seed of the generator (`numpy.random.default_rng(seed)`), >= 0.
    dnl_fraction : float
        `inl_dnl` only: share of the variance in the white per-code DNL part, 0..1 (default
        0.2).

    Notes
    -----
    Every row is made relative to code 0 (row[0] = 0: the channel's absolute phase and gain at
    code 0 are the array calibration, `tx_phase_error_deg` / `tx_gain_error_db`), then scaled
    so that sqrt(mean(row^2)) equals `rms` exactly. The `inl_dnl` curve of Tx k is
    sum_h a_h cos(2 pi h q / n_codes + phi_h), h = 1..3, a_h = 1/h, phi_h uniform: the first
    harmonic models LO feed-through, the second I/Q imbalance of a vector-modulator shifter.
    """

    distribution: str
    rms: float
    seed: int = 0
    dnl_fraction: float = 0.2

    def __post_init__(self) -> None:
        if self.distribution not in SHIFTER_ERROR_DISTRIBUTIONS:
            raise BadInput(f"distribution={self.distribution!r} is not one of "
                           f"{sorted(SHIFTER_ERROR_DISTRIBUTIONS)}")
        if not (isinstance(self.rms, (int, float)) and not isinstance(self.rms, bool)
                and math.isfinite(self.rms) and self.rms >= 0):
            raise BadInput(f"rms={self.rms!r} must be a finite number >= 0")
        if not isinstance(self.seed, (int, np.integer)) or isinstance(self.seed, bool) or \
                self.seed < 0:
            raise BadInput(f"seed={self.seed!r} must be an integer >= 0")
        if not (isinstance(self.dnl_fraction, (int, float)) and 0 <= self.dnl_fraction <= 1):
            raise BadInput(f"dnl_fraction={self.dnl_fraction!r} must be in 0..1")

    def draw(self, n_tx: int, n_codes: int) -> np.ndarray:
        """(n_tx, n_codes) float table, row k for Tx k+1, relative to code 0, rms `rms`."""
        shape = (n_tx, n_codes)
        t = SHIFTER_ERROR_DISTRIBUTIONS[self.distribution].draw(
            np.random.default_rng(self.seed), shape, self.dnl_fraction)
        t = t - t[:, :1]
        r = _rms(t)
        return np.zeros(shape) if self.rms == 0 else t * (self.rms / np.where(r > 0, r, 1.0))


def vector_modulator_tables(n_codes: int, quadrature_skew_deg: float,
                            iq_gain_imbalance_db: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Phase and gain error of an I/Q vector-modulator shifter with quadrature errors.

    Code q sets theta = 2 pi q / n_codes; the modulator outputs
    s = cos(theta) + a exp(j (pi/2 + phi)) sin(theta) with a = 10^(imbalance/20) and phi the
    quadrature skew, instead of exp(j theta). Phase error arg(s) - theta, gain 20 log10 |s|;
    both 0 at code 0. The skew gives a smooth INL with a strong second harmonic
    (0, phi, 0, phi at 0/90/180/270 deg): the pattern that puts a line at the mirror velocity
    of a 90-deg step.

    Returns
    -------
    phase_error_deg, gain_error_db : (n_codes,) float
    """
    theta = 2 * np.pi * np.arange(n_codes) / n_codes
    a = 10 ** (iq_gain_imbalance_db / 20)
    s = np.cos(theta) + a * np.exp(1j * (np.pi / 2 + np.radians(quadrature_skew_deg))) * \
        np.sin(theta)
    return wrap_deg(np.degrees(np.angle(s) - theta)), 20 * np.log10(np.abs(s))


def _rms(t: np.ndarray) -> np.ndarray:
    return np.sqrt(np.mean(np.square(t), axis=-1, keepdims=True))


def resolve_table(name: str, value: Any, n_tx: int, n_codes: int,
                  limit: float) -> tuple[tuple[float, ...], ...]:
    """A config table field as a tuple of n_tx rows of n_codes floats.

    `value` is None (all zeros), a nested sequence / array of shape (n_tx, n_codes), or a
    mapping with the keys of `ShifterErrorSpec` (drawn once, here). Raises ValueError naming
    `name` for a wrong shape, a non-finite value or |value| > `limit`.
    """
    if value is None:
        return ((0.0,) * n_codes,) * n_tx
    if isinstance(value, ShifterErrorSpec):
        arr = value.draw(n_tx, n_codes)
    elif isinstance(value, Mapping):
        try:
            spec = ShifterErrorSpec(**dict(value))
        except TypeError as exc:
            raise BadInput(f"{name}: bad error-table spec {dict(value)!r} ({exc}); keys: "
                           "distribution, rms, seed, dnl_fraction") from exc
        except ValueError as exc:
            raise BadInput(f"{name}: {exc}") from exc
        arr = spec.draw(n_tx, n_codes)
    else:
        arr = value
    arr = check_table(name, arr, (n_tx, n_codes), limit)
    return tuple(tuple(float(v) for v in row) for row in arr)


def check_table(name: str, value: Any, shape: tuple[int, int], limit: float,
                allow_neg_inf: bool = False) -> np.ndarray:
    """Validate a 2-D float table: shape, finite (or -inf when allowed), |value| <= limit."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise BadInput(f"{name} must be a numeric table of shape {shape}: {exc}") from exc
    if arr.shape != shape:
        raise BadInput(f"{name} has shape {arr.shape}, expected {shape} "
                       "(rows Tx1..Txn)")
    bad = ~np.isfinite(arr)
    if allow_neg_inf:
        bad &= ~np.isneginf(arr)
    if bad.any():
        k, q = np.argwhere(bad)[0]
        raise BadInput(f"{name}[{k}][{q}]={float(arr[k, q])!r} must be finite")
    fin = np.where(np.isfinite(arr), arr, 0.0)
    over = np.abs(fin) > limit
    if over.any():
        k, q = np.argwhere(over)[0]
        raise BadInput(f"{name}[{k}][{q}]={float(arr[k, q])!r} exceeds the limit +/-{limit:g}")
    return arr


def shifter_factor(phase_error_deg: np.ndarray, gain_error_db: np.ndarray,
                   codes: np.ndarray) -> np.ndarray:
    """Complex error factor of the shifter at the programmed codes.

    Parameters
    ----------
    phase_error_deg, gain_error_db : (n_tx, n_codes) float
        Per-Tx, per-code error tables.
    codes : (n_tx, n_chirps) int
        Programmed code of each Tx at each chirp.

    Returns
    -------
    (n_tx, n_chirps) complex128
        10^(g[k, q] / 20) exp(-j e[k, q]): the ideal applied phase -q LSB is not included.
    """
    rows = np.arange(codes.shape[0])[:, None]
    e = np.radians(np.asarray(phase_error_deg, dtype=float))[rows, codes]
    g = 10 ** (np.asarray(gain_error_db, dtype=float)[rows, codes] / 20)
    return g * np.exp(-1j * e)


def coupling_matrix(level_db: np.ndarray, phase_deg: np.ndarray) -> np.ndarray:
    """(n_tx, n_tx) complex coupling C[k, j] = 10^(level_db[k, j] / 20) exp(j phase_deg[k, j]):
    the share of channel j's signal radiated by element k (-inf dB: none)."""
    return 10 ** (np.asarray(level_db, dtype=float) / 20) * \
        np.exp(1j * np.radians(np.asarray(phase_deg, dtype=float)))


def apply_coupling(coupling: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Radiated weights C @ w: (n_tx, n_tx) @ (n_tx, n_chirps) -> (n_tx, n_chirps) complex.

    With the identity matrix (0 dB diagonal, -inf dB elsewhere) every product is an exact 1 or
    0, so the result is bit-identical to `weights`."""
    return coupling @ weights


def select_codes(wanted_deg: np.ndarray, measured_error_deg: np.ndarray,
                 lsb_deg: float) -> np.ndarray:
    """Codes whose measured phase is closest to the wanted phase (calibrated programming).

    Parameters
    ----------
    wanted_deg : (n_tx, P) float
        Phase each Tx should be programmed to, deg (the shifter then delays by it).
    measured_error_deg : (n_tx, n_codes) float
        Calibration table: measured phase of code q minus q LSB, deg, relative to code 0.
    lsb_deg : float
        Nominal step, deg.

    Returns
    -------
    (n_tx, P) int64
        argmin_q |wrap(q LSB + measured[k, q] - wanted[k, p])| (ties: the lowest code).
    """
    cal = np.asarray(measured_error_deg, dtype=float)
    measured = np.arange(cal.shape[1]) * lsb_deg + cal  # (T, Q)
    diff = wrap_deg(measured[:, None, :] - np.asarray(wanted_deg, dtype=float)[:, :, None])
    return np.argmin(np.abs(diff), axis=-1).astype(np.int64)


def program_codes(wanted_deg: np.ndarray, lsb_deg: float, n_codes: int, rule: str,
                  calibration_deg: np.ndarray | None = None) -> np.ndarray:
    """Shifter codes the chip programs for wanted phases.

    Parameters
    ----------
    wanted_deg : (n_tx, P) float
        Wanted (programmed, i.e. delay) phase of each Tx at each chirp of the period, deg.
    lsb_deg : float
        Nominal step, deg.
    n_codes : int
        2^bits.
    rule : str
        Key of `PHASE_QUANTIZATIONS`: the uncalibrated mapping ([TI-DDMA] table 4 floors, TI's
        SDK rounds; "none" rounds for the table look-up while the applied phase stays ideal).
    calibration_deg : (n_tx, n_codes) float, optional
        Measured per-code error table; when given, `select_codes` replaces the rule.

    Returns
    -------
    (n_tx, P) int64 codes in 0..n_codes-1
    """
    wanted = np.asarray(wanted_deg, dtype=float)
    if calibration_deg is not None:
        return select_codes(wanted, calibration_deg, lsb_deg)
    codes = PHASE_QUANTIZATIONS[rule].code_of(wanted / lsb_deg)
    return np.mod(codes, n_codes).astype(np.int64)


def phase_residual_deg(wanted_deg: np.ndarray, codes: np.ndarray,
                       phase_error_deg: np.ndarray, lsb_deg: float) -> np.ndarray:
    """Phase the shifter really programs minus the wanted phase, relative to code 0, deg.

    residual[k, p] = wrap(q LSB + e[k, q] - e[k, 0] - wanted[k, p]) with q = codes[k, p]: the
    code-grid rounding plus the table error of the chosen code (code 0 is the reference the
    array calibration absorbs).

    Returns
    -------
    (n_tx, P) float, deg in [-180, 180)
    """
    e = np.asarray(phase_error_deg, dtype=float)
    rows = np.arange(codes.shape[0])[:, None]
    return wrap_deg(codes * lsb_deg + e[rows, codes] - e[:, :1] - wanted_deg)


def code_period_lines(weights: np.ndarray) -> np.ndarray:
    """Spectral lines of a transmit sequence periodic in P chirps.

    A slow-time sequence w[c mod P] s[c] has, for each line m = 0..P-1 (a Doppler offset of
    m/P of the chirp rate, i.e. m x n_chirps / P bins), the complex amplitude
    W[m] = (1/P) sum_c w[c] exp(-2 pi j m c / P).

    Parameters
    ----------
    weights : (..., P) complex
        One code period of complex transmit weights (phase and gain per chirp).

    Returns
    -------
    (..., P) complex
    """
    w = np.asarray(weights)
    return np.fft.fft(w, axis=-1) / w.shape[-1]


def spur_levels_dbc(weights: np.ndarray) -> np.ndarray:
    """(..., P) power of each line of `code_period_lines` over the strongest line, dBc."""
    p = np.abs(code_period_lines(weights)) ** 2
    return 10 * np.log10(np.maximum(p, 1e-300) / p.max(axis=-1, keepdims=True))


def resolve_config_tables(cfg) -> dict[str, Any]:
    """The shifter and coupling fields of a `radarsim.RadarConfig`, resolved and checked.

    `shifter_phase_error_deg` / `shifter_gain_error_db` become (n_tx, 2^bits) tuples (a spec
    mapping is drawn once, `ShifterErrorSpec`; None: zeros), `tx_coupling_db` /
    `tx_coupling_deg` (n_tx, n_tx) tuples (None: identity, -inf dB off the diagonal) and
    `shifter_calibration_deg` a measured (n_tx, 2^bits) table or None. A calibration is a
    measurement (`radarsim.calibration.resolve_calibration`), never run here.

    Raises
    ------
    ValueError
        Wrong shapes, values beyond the limits, a coupling diagonal other than 0 dB / 0 deg, a
        calibration table with an ideal shifter, or a calibration request instead of a table.
    """
    n_tx, n_codes = cfg.n_tx, 2 ** cfg.phase_shifter_bits  # 1 code on a chip without shifters
    out = {"shifter_phase_error_deg": resolve_table(
               "shifter_phase_error_deg", cfg.shifter_phase_error_deg, n_tx, n_codes,
               MAX_SHIFTER_PHASE_ERROR_DEG),
           "shifter_gain_error_db": resolve_table(
               "shifter_gain_error_db", cfg.shifter_gain_error_db, n_tx, n_codes,
               MAX_SHIFTER_GAIN_ERROR_DB)}
    eye = np.eye(n_tx, dtype=bool)
    lvl = np.where(eye, 0.0, -np.inf) if cfg.tx_coupling_db is None else \
        check_table("tx_coupling_db", cfg.tx_coupling_db, (n_tx, n_tx), np.inf,
                    allow_neg_inf=True)
    ph = np.zeros((n_tx, n_tx)) if cfg.tx_coupling_deg is None else \
        check_table("tx_coupling_deg", cfg.tx_coupling_deg, (n_tx, n_tx), 360.0)
    if np.any(lvl[eye] != 0) or np.any(ph[eye] != 0):
        raise BadInput(f"tx_coupling_db / tx_coupling_deg diagonal must be 0 dB and "
                       f"0 deg (channel gains are tx_gain_error_db), got "
                       f"{lvl[eye].tolist()} dB, {ph[eye].tolist()} deg")
    if np.any(lvl[~eye] > MAX_TX_COUPLING_DB):
        raise BadInput(f"tx_coupling_db off-diagonal level {lvl[~eye].max():g} dB "
                       f"exceeds the limit {MAX_TX_COUPLING_DB:g} dB")
    out["tx_coupling_db"] = tuple(tuple(float(v) for v in r) for r in lvl)
    out["tx_coupling_deg"] = tuple(tuple(float(v) for v in r) for r in ph)
    cal = cfg.shifter_calibration_deg
    if cal is None:
        out["shifter_calibration_deg"] = None
        return out
    if PHASE_QUANTIZATIONS[cfg.phase_quantization].ideal:
        raise BadInput(f"shifter_calibration_deg is set but phase_quantization="
                       f"{cfg.phase_quantization!r}: "
                       "an ideal shifter has no codes to choose; use 'floor' or 'round'")
    if isinstance(cal, Mapping):
        raise BadInput(f"shifter_calibration_deg={dict(cal)!r} is a calibration request, not "
                       "a measured table: a config never runs a measurement; resolve it "
                       "with radarsim.calibration.resolve_calibration(cfg, request) (a "
                       "sweep's radar table does this per cell)")
    out["shifter_calibration_deg"] = resolve_table(
        "shifter_calibration_deg", cal, n_tx, n_codes, MAX_SHIFTER_PHASE_ERROR_DEG)
    return out
