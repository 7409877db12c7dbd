"""Range-bias and virtual-channel compensation: TI's ``compRangeBiasAndRxChanPhase``.

A board's feed lines and channels give every echo a range bias and every virtual channel a
complex gain (`radarsim.RadarConfig.range_bias_m`, the per-Tx and per-Rx errors). TI's demos
correct both from one CLI line, and every chain here applies it as the demos do: each virtual
antenna's sample is multiplied by its coefficient before angle estimation (and before the
TDMA/BPM velocity hypotheses are scored, which read the same samples), and the range of each
point is the interpolated range minus ``rangeBias``.

The line, as the demos read it (``MmwDemo_CLICompRangeBiasAndRxChanPhaseCfg``, mmWave SDK 3.x
xwr16xx/18xx/68xx ``mmw_cli.c`` and the MCU+ SDK AWR294x TDM demo)::

    compRangeBiasAndRxChanPhase <rangeBias> <Re(0,0)> <Im(0,0)> <Re(0,1)> ... <Re(T-1,R-1)>
    <Im(T-1,R-1)>

holds one coefficient per (Tx, Rx) pair of the CHIP, T and R its channel counts whatever
``channelCfg`` enables (the CLI refuses any other count: ``argc != 1 + 1 +
SYS_COMMON_NUM_TX_ANTENNAS * SYS_COMMON_NUM_RX_CHANNEL * 2``), Tx major, in chip channel order;
each part becomes Q15 as ``(int32_t)(value * 32768.)`` saturated to int16. The DPC then takes the
enabled antennas' coefficients in the order the sub-frame transmits them
(``DPC_ObjDet_GetRxChPhaseComp``: ``rxChPhaseComp[txAntOrder[tx] * NUM_RX + rxAntOrder[rx]]``).
Here: `virtual_coefficients` maps the chip-ordered list onto `RadarConfig.virtual_positions_m`'s
order (`tx_order` x active Rx).

TI's AoA DPU clamps a range that the bias makes negative at 0; here the shift is exact (every
reported range moves by exactly ``rangeBias``), so a point is never moved onto the radar.

References
----------
.. [1] TI, mmWave SDK 3.x ``ti/datapath/dpc/objectdetection/objdethwa`` documentation,
       "Range bias and rx channel gain/phase measurement and compensation".
.. [2] TI, mmWave SDK 3.x / MCU+ SDK AWR294x demo ``mmw_cli.c``:
       ``MmwDemo_CLICompRangeBiasAndRxChanPhaseCfg``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from core.errors import BadInput
from radarsim.config import RadarConfig
from radarsim.config_rules import MAX_RANGE_BIAS_M

from .dc_range_signature import DcRangeSignature

__all__ = ["COMP_COMMAND", "Q15_SCALE", "q15", "n_chip_pairs", "ti_pair_index",
           "virtual_coefficients", "compensate", "apply_coefficients", "check_channel_comp",
           "comp_line", "chip_order_coefficients", "check_comp_values", "implied_board",
           "CalibrationConfig"]

#: The TI CLI command this module applies.
COMP_COMMAND = "compRangeBiasAndRxChanPhase"
#: Q15 scale of the demo's coefficients (``value * 32768``, saturated to int16).
Q15_SCALE = 32768


def q15(values) -> np.ndarray:
    """Coefficient parts as the demo stores them: trunc(v x 32768) saturated to
    [-32768, 32767], returned as that integer / 32768 (float64)."""
    q = np.trunc(np.asarray(values, dtype=float) * Q15_SCALE)
    return np.clip(q, -Q15_SCALE, Q15_SCALE - 1) / Q15_SCALE


def n_chip_pairs(cfg: RadarConfig) -> int:
    """Coefficients a ``compRangeBiasAndRxChanPhase`` line holds for `cfg`'s chip: every
    (Tx, Rx) pair of the chip (xWR16xx 2 x 4, xWR18xx/68xx 3 x 4, AWR294x 4 x 4)."""
    spec = cfg.chip_spec
    return spec.n_tx * spec.n_rx


def ti_pair_index(cfg: RadarConfig) -> np.ndarray:
    """(n_virtual,) int: position in the chip-ordered coefficient list of each virtual channel
    of `cfg.virtual_positions_m` (Tx in `tx_order`, then the active Rx):
    (chip Tx channel - 1) x chip n_rx + (chip Rx channel - 1)."""
    n_rx_chip = cfg.chip_spec.n_rx
    tx_ch = np.array([cfg.tx_channels[k - 1] for k in cfg.tx_order]) - 1
    rx_ch = np.array(cfg.rx_channels) - 1
    return (tx_ch[:, None] * n_rx_chip + rx_ch[None, :]).reshape(-1)


def check_comp_values(range_bias_m: float, channel_comp) -> tuple[tuple[float, float], ...] | None:
    """Validate the values of a compensation line; returns the coefficients as a tuple of
    (re, im) float pairs (or None). Raises BadInput naming the value and the limit: the range
    bias within +/- `radarsim.config_rules.MAX_RANGE_BIAS_M` (the bound a simulated board's
    bias has, so a profile a sweep refuses is refused here too), coefficients in the Q15 range
    and not all zero (that erases every channel)."""
    if not (isinstance(range_bias_m, (int, float, np.integer, np.floating))
            and not isinstance(range_bias_m, bool) and math.isfinite(range_bias_m)):
        raise BadInput(f"range_bias_m={range_bias_m!r} must be a finite number (m)")
    if abs(range_bias_m) > MAX_RANGE_BIAS_M:
        raise BadInput(f"range_bias_m={range_bias_m!r} is outside +/-{MAX_RANGE_BIAS_M:g} m, "
                       "the largest range bias a board has")
    if channel_comp is None:
        return None
    try:
        pairs = tuple((float(re), float(im)) for re, im in channel_comp)
    except (TypeError, ValueError):
        raise BadInput(f"channel_comp={channel_comp!r} must be a sequence of (re, im) pairs")\
            from None
    if not pairs or not all(math.isfinite(v) for p in pairs for v in p):
        raise BadInput(f"channel_comp must hold finite (re, im) pairs, got {channel_comp!r}")
    bad = [v for p in pairs for v in p if not -1.0 <= v <= 1.0]
    if bad:
        # 1.0 itself is the demos' "no correction" (1 0 1 0 ...): Q15 saturates it to
        # 32767 / 32768. Beyond +/-1 the demo would clip silently: refused here.
        raise BadInput(f"channel_comp value {bad[0]!r} is outside the Q15 range [-1, 1] of "
                       f"{COMP_COMMAND} (the demo would saturate it)")
    if not any(v for p in pairs for v in p):
        raise BadInput(f"channel_comp is all zero ({len(pairs)} coefficients 0 + 0j): it "
                       "would erase every channel (no correction is 1 + 0j)")
    return pairs


@dataclass(frozen=True, kw_only=True, slots=True)
class CalibrationConfig:
    """The board corrections the chains apply: TI's ``compRangeBiasAndRxChanPhase`` and
    ``calibDcRangeSig``.

    Parameters
    ----------
    range_bias_m : float
        ``rangeBias``, m: subtracted from every reported range (default 0).
    channel_comp : tuple of (re, im) or None
        The line's coefficients, one per (Tx, Rx) pair of the chip in TI's chip channel order
        (Tx major), each part in [-1, 1] (Q15 when applied); every chain multiplies its
        virtual-antenna samples by them before angle estimation (`compensate`). None: no
        correction (default).
    dc_range_signature : pipeline.dc_range_signature.DcRangeSignature or None
        TI's DC range signature, subtracted from the range-FFT output of every chain
        (`pipeline.chirp_level.range_stage`); measured over a capture's first frames by
        ``radar-harness process``. None: nothing subtracted (default).
    """

    range_bias_m: float = 0.0
    channel_comp: tuple[tuple[float, float], ...] | None = None
    dc_range_signature: DcRangeSignature | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "channel_comp",
                           check_comp_values(self.range_bias_m, self.channel_comp))
        if self.dc_range_signature is not None and \
                not isinstance(self.dc_range_signature, DcRangeSignature):
            raise BadInput(f"dc_range_signature must be a DcRangeSignature or None, got "
                           f"{type(self.dc_range_signature).__name__}")


def check_channel_comp(cfg: RadarConfig, channel_comp) -> None:
    """Raise if a coefficient list does not fit `cfg`'s chip (`n_chip_pairs`) or gives a
    virtual channel the radar uses a zero coefficient (that channel would be erased: SNR
    -inf, angles from the others' leakage)."""
    if channel_comp is None:
        return
    want = n_chip_pairs(cfg)
    spec = cfg.chip_spec
    if len(channel_comp) != want:
        raise BadInput(f"{COMP_COMMAND}: {len(channel_comp)} (re, im) coefficients "
                       f"({1 + 2 * len(channel_comp)} values), the {spec.name} needs "
                       f"{want} = {spec.n_tx} Tx x {spec.n_rx} Rx ({1 + 2 * want} values: "
                       "rangeBias, then Re/Im per chip Tx x Rx pair)")
    used = ti_pair_index(cfg)
    zero = [int(i) for i in used if not any(channel_comp[i])]
    if zero:
        i = zero[0]
        raise BadInput(f"{COMP_COMMAND}: the coefficient of chip Tx{i // spec.n_rx + 1} "
                       f"Rx{i % spec.n_rx + 1} is 0 + 0j ({len(zero)} of the radar's "
                       f"{len(used)} virtual channels): it would erase a channel the profile "
                       "enables (no correction is 1 + 0j)")


@lru_cache(maxsize=32)
def _virtual_coefficients(cfg: RadarConfig, channel_comp: tuple) -> np.ndarray:
    pairs = q15(np.array(channel_comp, dtype=float))
    coef = (pairs[:, 0] + 1j * pairs[:, 1])[ti_pair_index(cfg)].astype(np.complex64)
    coef.setflags(write=False)
    return coef


def virtual_coefficients(cfg: RadarConfig, channel_comp) -> np.ndarray | None:
    """(n_virtual,) complex64 Q15 coefficient of each virtual channel in
    `cfg.virtual_positions_m` order, or None when there is no compensation."""
    if channel_comp is None:
        return None
    check_channel_comp(cfg, channel_comp)
    return _virtual_coefficients(cfg, tuple(channel_comp))


def compensate(cfg: RadarConfig, proc, virt: np.ndarray,
               channels: np.ndarray | None = None) -> np.ndarray:
    """Virtual-antenna samples times their coefficients (``proc.calibration.channel_comp``).

    Parameters
    ----------
    cfg : RadarConfig
    proc : pipeline.ProcessingConfig
        Its ``calibration.channel_comp`` (None: `virt` is returned unchanged, same object).
    virt : (..., n_ch) complex
        Samples; the last axis holds virtual channels (all of them, or `channels`).
    channels : (n_ch,) int, optional
        Which virtual channels (indices into `cfg.virtual_positions_m`) the last axis holds.

    Returns
    -------
    (..., n_ch) complex64 (a new array) or `virt` itself.
    """
    return apply_coefficients(cfg, proc.calibration.channel_comp, virt, channels)


def apply_coefficients(cfg: RadarConfig, channel_comp, virt: np.ndarray,
                       channels: np.ndarray | None = None) -> np.ndarray:
    """`compensate` by the coefficients ``channel_comp`` itself (hashable: for products
    cached per configuration, e.g. a DFT with the coefficients folded into its columns)."""
    coef = virtual_coefficients(cfg, channel_comp)
    if coef is None:
        return virt
    if channels is not None:
        coef = coef[channels]
    return virt * coef


def chip_order_coefficients(cfg: RadarConfig, virtual: np.ndarray) -> np.ndarray:
    """(n_chip_pairs,) complex: coefficients of `cfg`'s virtual channels placed in the chip
    order of the CLI line; pairs of channels the profile does not enable get 1 (TI's
    measurement writes only enabled antennas; the demo default is 1 + 0j)."""
    out = np.ones(n_chip_pairs(cfg), dtype=complex)
    out[ti_pair_index(cfg)] = virtual
    return out


def comp_line(range_bias_m: float, coefficients: np.ndarray) -> str:
    """The ``compRangeBiasAndRxChanPhase`` line: range bias (m, 4 decimals) and the Re/Im of
    each chip-ordered coefficient (5 decimals: finer than a Q15 step, 3.1e-5)."""
    parts = [f"{range_bias_m:.4f}"]
    for c in np.asarray(coefficients, dtype=complex):
        # round first and add 0.0: -1e-17 would print as "-0.00000"
        parts += [f"{round(c.real, 5) + 0.0:.5f}", f"{round(c.imag, 5) + 0.0:.5f}"]
    return " ".join([COMP_COMMAND, *parts])


def implied_board(cfg: RadarConfig, channel_comp, range_bias_m: float = 0.0) -> dict:
    """The board a ``compRangeBiasAndRxChanPhase`` line calibrates, as `RadarConfig` fields.

    A line's coefficient c_i undoes virtual channel i's complex gain g_i (c_i g_i the same for
    every channel), so g_i is proportional to 1 / c_i; the front end models g = t_k r_r (one
    gain per Tx and per Rx), fitted here as the best rank-1 approximation of the (Tx, Rx)
    matrix of 1 / c (its leading singular pair), referred to the first Tx and Rx. The demos'
    "1 0 -1 0 ..." lines of antenna-on-package boards (two Rx fed in antiphase) are reproduced
    exactly; a measured line is approximated where it is not a Tx x Rx product. Phases and
    gains are rounded to 1e-6 deg / dB, so an identity line gives an ideal board bit for bit.

    Returns
    -------
    dict
        tx_phase_error_deg, tx_gain_error_db (per Tx in `tx_channels` order), rx_phase_error_deg,
        rx_gain_error_db, range_bias_m; empty when the line is absent.
    """
    if channel_comp is None and not range_bias_m:
        return {}
    out = {"range_bias_m": float(range_bias_m)}
    coef = virtual_coefficients(cfg, channel_comp)
    if coef is None:
        return out
    g = (1.0 / coef.astype(complex)).reshape(cfg.n_tx, cfg.n_rx)  # rows in tx_order
    u, s, vh = np.linalg.svd(g)
    t, r = u[:, 0] * np.sqrt(s[0]), vh[0] * np.sqrt(s[0])  # g = s u v^H
    t, r = t / t[0], r / r[0]
    t = t[np.argsort(np.array(cfg.tx_order))]  # tx_order rows -> Tx1..Txn

    def deg(x):
        return tuple(float(v) + 0.0 for v in np.round(np.degrees(np.angle(x)), 6))

    def db(x):
        return tuple(float(v) + 0.0 for v in np.round(20 * np.log10(np.abs(x)), 6))
    out.update(tx_phase_error_deg=deg(t), tx_gain_error_db=db(t), rx_phase_error_deg=deg(r),
               rx_gain_error_db=db(r))
    return out
