"""``compRangeBiasAndRxChanPhase``: the board calibration line of the mmWave SDK 3.x demos
(xWR16xx/18xx/68xx) and the MCU+ SDK AWR294x TDM demo, read into the processing settings
``range_bias_m`` and ``channel_comp`` (`pipeline.compensation` applies them).

Syntax (``MmwDemo_CLICompRangeBiasAndRxChanPhaseCfg``)::

    compRangeBiasAndRxChanPhase <rangeBias> <Re(0,0)> <Im(0,0)> ... <Re(T-1,R-1)> <Im(T-1,R-1)>

one (Re, Im) pair per Tx x Rx pair of the chip, Tx major in chip channel order, whatever
``channelCfg`` enables: the demo's CLI refuses any other count
(``argc != 1 + 1 + SYS_COMMON_NUM_TX_ANTENNAS * SYS_COMMON_NUM_RX_CHANNEL * 2``) and stores each
part as Q15 (``value * 32768`` saturated to int16). The radar's own virtual channels take their
pairs from that list (`pipeline.compensation.ti_pair_index`).

``antennaCalibParams``: the channel calibration of the MCU+ SDK DDM demo (AWR2944/AWR2x44P/
AWR2544, and the R79 demo), ``MmwDemo_CLIAntennaCalibParams``::

    antennaCalibParams <Im(0,0)> <Re(0,0)> <Im(0,1)> <Re(0,1)> ... <Im(T-1,R-1)> <Re(T-1,R-1)>

one (Im, Re) pair per virtual antenna of the chip's T x R array, in the order
``antGeometryCfg`` lists them (Tx0Rx0 .. Tx3Rx3: chip Tx major, the same order as
``compRangeBiasAndRxChanPhase``); the CLI refuses fewer than 2 T R values
(``argc < 1 + SYS_COMMON_NUM_TX_ANTENNAS * SYS_COMMON_NUM_RX_CHANNEL * 2``) and rearranges them
into the DPU's azimuth/elevation order. The Doppler DPU (``DPU_DopplerProcHWA``,
``antennaCalibParams`` "in Im/Re format") and the DSP angle estimation multiply each virtual
antenna's sample by its coefficient before the azimuth FFT: the same operation as
``compRangeBiasAndRxChanPhase`` without a range bias, so the line fills ``channel_comp``
(`antenna_calib_pairs`; applied by `pipeline.compensation`). The demo keeps the values as
floats (its HWA path quantises them; the format was not found in the sources read): here they
take the Q15 step of ``compRangeBiasAndRxChanPhase`` (< 3.1e-5 per part), and the identity line
``0 1 0 1 ...`` the demos ship is no correction at all (exact in floats).
"""
from __future__ import annotations

from ..config_rules import MAX_RANGE_BIAS_M
from .parse_state import ParseState
from .syntax import Line

__all__ = ["comp_range_bias_and_rx_chan_phase", "comp_value_count", "antenna_calib_params",
           "antenna_calib_pairs", "is_identity"]


def comp_value_count(chip) -> int:
    """Values after the command for a chip: rangeBias + Re/Im of n_tx x n_rx pairs."""
    return 1 + 2 * chip.n_tx * chip.n_rx


def comp_range_bias_and_rx_chan_phase(st: ParseState, ln: Line) -> None:
    want = comp_value_count(st.chip)
    if len(ln.args) != want:
        raise ln.fail(f"{len(ln.args)} values; the {st.chip.name} needs {want} (rangeBias, "
                      f"then Re, Im of each of its {st.chip.n_tx} Tx x {st.chip.n_rx} Rx "
                      "pairs, Tx major)")
    bias = float(ln.dec(0, "rangeBias"))
    if not abs(bias) <= MAX_RANGE_BIAS_M:
        raise ln.fail(f"rangeBias = {bias:g} m is outside +/-{MAX_RANGE_BIAS_M:g} m, the "
                      "largest range bias a board has")
    parts = _unit_values(ln, 1, ("Re", "Im"), st.chip.n_rx,
                         "the Q15 range [-1, 1] (the demo would saturate it)")
    _refuse_all_zero(ln, parts)
    st.processing.update(range_bias_m=bias, channel_comp=tuple(zip(parts[0::2], parts[1::2])))
    st.processing_origin.update(range_bias_m=ln.cmd, channel_comp=ln.cmd)
    st.processing_commands[ln.cmd] = ln


def _unit_values(ln: Line, first: int, names: tuple[str, str], n_rx: int,
                 limit: str) -> list[float]:
    """The line's values from index `first` on, each in [-1, 1], read as interleaved
    (names[0], names[1]) parts of the coefficients of (Tx, Rx) pairs, Tx major (the names
    and pair indices go into the message of a malformed value); `limit` says why out of range
    is refused."""
    vals = []
    for i in range(first, len(ln.args)):
        k = i - first
        v = float(ln.dec(i, f"{names[k % 2]}({k // 2 // n_rx},{k // 2 % n_rx})"))
        if not -1.0 <= v <= 1.0:
            raise ln.fail(f"value {i + 1} = {v:g} is outside {limit}")
        vals.append(v)
    return vals


def _refuse_all_zero(ln: Line, values: list[float]) -> None:
    """Every coefficient 0 + 0j erases every channel: refused (no correction is 1 + 0j)."""
    if not any(values):
        raise ln.fail("every coefficient is 0 + 0j: it would erase every channel (no "
                      "correction is 1 + 0j, i.e. Re 1, Im 0)")


def is_identity(pairs) -> bool:
    """Whether (re, im) coefficient pairs are all 1 + 0j (no correction)."""
    return all(re == 1.0 and im == 0.0 for re, im in pairs)


def antenna_calib_params(st: ParseState, ln: Line) -> None:
    """Record the ``antennaCalibParams`` line; its family decides whether it applies
    (`radarsim.ti.reader`, `antenna_calib_pairs`)."""
    st.antenna_calib = ln
    st.processing_commands[ln.cmd] = ln


def antenna_calib_pairs(ln: Line, chip) -> tuple[tuple[float, float], ...] | None:
    """(re, im) coefficient per chip (Tx, Rx) pair, Tx major, of an ``antennaCalibParams``
    line, or None for the identity line.

    Raises
    ------
    ValueError
        "line N (antennaCalibParams): ..." for a count other than 2 x n_tx x n_rx of the chip,
        a malformed value or one outside [-1, 1].
    """
    want = 2 * chip.n_tx * chip.n_rx
    if len(ln.args) != want:
        raise ln.fail(f"{len(ln.args)} values; the {chip.name} needs {want} (Im, Re of each of "
                      f"its {chip.n_tx} Tx x {chip.n_rx} Rx virtual antennas, Tx major)")
    vals = _unit_values(ln, 0, ("Im", "Re"), chip.n_rx,
                        "[-1, 1] (a calibration coefficient never amplifies; the "
                        "fixed-point path would saturate)")
    _refuse_all_zero(ln, vals)
    pairs = tuple(zip(vals[1::2], vals[0::2]))
    return None if is_identity(pairs) else pairs
